//! Behaviour spawning (pHelmIvP's `BehaviorSet::handlePossibleSpawnings`, reference §5.4): a
//! `.bhv` entry with `templating = spawn` is a template, built once at configuration to
//! validate it (a bad line is MALCONFIG, as for any behaviour) and then kept only as its
//! lines. At the start of each decision iteration every posting of a template's `updates`
//! variable that contains `name` is a spawning request: when neither `<prefix><name>` nor
//! `<name>` is a behaviour of the set, a new instance is built from the template's lines and
//! then the request's `param=value # ...` pairs (its `name=` extends the prefix, the
//! template's own `name`), runs `on_set_param_complete` and `on_spawn`, posts its
//! `spawnflag`s and joins the set; an `IVPHELM_LIFE_EVENT` records the spawn (or `abort` for
//! a request with a bad parameter, which also warns `Failed to spawn ...`). A request whose
//! name is taken is an ordinary update of that instance (its own `updates` check sees it).
//! `max_spawnings` > 0 caps the instances a template makes. `templating = clone` spawns the
//! same way and keeps the entry as an ordinary behaviour too.
//!
//! Instances leave the set as every behaviour does, when they complete (`duration` expiry
//! included), with an `IVPHELM_LIFE_EVENT` death event.

use behaviors::{Common, FlagKind};
use mission::bhv::param_name;
use moos_types::text::{parse_string, parse_string_q};

use super::{Helm, Slot, apply_param};

/// A `templating = spawn` (or `clone`) entry of the `.bhv` file.
pub(super) struct Template {
    /// The behaviour type as written.
    pub kind: String,
    /// The entry's lines (key, value) in file order, `templating` and `max_spawnings` left
    /// out (the C++ spec keeps them for itself).
    pub lines: Vec<(String, String)>,
    /// The entry's `name` (the prefix of every instance's name; empty without one).
    pub prefix: String,
    /// The entry's `updates` variable (requests arrive there); empty: it never spawns.
    pub update_var: String,
    /// `max_spawnings` (0 = no limit).
    pub max: u32,
    /// Instances made.
    pub made: u32,
    /// Spawn attempts (made or aborted).
    pub tried: u32,
}

impl Template {
    /// From a `.bhv` entry whose built behaviour is `common`.
    pub fn new(spec: &mission::bhv::BehaviorSpec, common: &Common) -> Template {
        let mut prefix = String::new();
        let mut update_var = String::new();
        let mut lines = Vec::new();
        for p in &spec.params {
            let key = param_name(&p.key);
            // As the C++ spec reads them: the last `name` line, an `updates` line without
            // white space.
            match key.as_str() {
                "name" => prefix = p.value.trim().to_string(),
                "updates" if !p.value.contains(char::is_whitespace) => {
                    update_var = p.value.trim().to_string()
                }
                _ => {}
            }
            if key != "templating" && key != "max_spawnings" {
                lines.push((key, p.value.clone()));
            }
        }
        Template {
            kind: spec.kind.clone(),
            lines,
            prefix,
            update_var,
            max: common.max_spawnings,
            made: 0,
            tried: 0,
        }
    }

    /// The appcast's line for it (`KIND::prefix (Spawned:made/tried)`).
    pub fn summary(&self) -> String {
        format!(
            "{}::{} (Spawned:{}/{})",
            self.kind, self.prefix, self.made, self.tried
        )
    }
}

/// `tokStringParse(s, key, '#', '=')`: the value of the first `key=value` piece, empty when
/// there is none or a piece before it is not one `left=right` pair.
pub(super) fn field<'a>(s: &'a str, key: &str) -> &'a str {
    for piece in parse_string_q(s, '#') {
        let parts = parse_string(piece, '=');
        if parts.len() != 2 {
            return "";
        }
        if parts[0].trim() == key {
            return parts[1].trim();
        }
    }
    ""
}

/// Whether `s` is a behaviour name MOOS accepts (`isAlphaNum(s, "_-[]()#@+")`).
fn good_name(s: &str) -> bool {
    !s.is_empty()
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "_-[]()#@+".contains(c))
}

impl Helm {
    fn has_behavior(&self, name: &str) -> bool {
        self.slots.iter().any(|s| s.common.name == name)
    }

    /// Spawns the instances requested since the last iteration (before the mode evaluation,
    /// as pHelmIvP's `part1_PreliminaryBehaviorSetHandling`).
    pub(super) fn handle_spawnings(&mut self, now: f64) {
        for t in 0..self.templates.len() {
            let var = self.templates[t].update_var.clone();
            if var.is_empty() {
                continue;
            }
            let requests: Vec<String> = self
                .info
                .deltas(&var)
                .iter()
                .filter(|u| u.contains("name"))
                .map(|u| u.to_string())
                .collect();
            for request in requests {
                let name = field(&request, "name").to_string();
                let full = format!("{}{name}", self.templates[t].prefix);
                let taken = |h: &Helm| h.has_behavior(&full) || h.has_behavior(&name);
                if !taken(self) {
                    let tpl = &self.templates[t];
                    if tpl.max > 0 && tpl.made >= tpl.max {
                        continue;
                    }
                    self.templates[t].tried += 1;
                    self.spawn(t, &request, now);
                }
                if !taken(self) {
                    self.bhvset_warnings.push(format!(
                        "Behavior named [{name}] or [{full}] not found or spawned."
                    ));
                }
            }
        }
    }

    /// One spawning attempt from template `t` with `request`.
    fn spawn(&mut self, t: usize, request: &str, now: f64) {
        let tpl = &self.templates[t];
        let Some(b) = self.registry.create(&tpl.kind) else {
            return;
        };
        let mut slot = Slot::new(b);
        let mut ok = true;
        for (key, value) in &tpl.lines {
            let r = apply_param(
                &mut slot,
                key,
                value,
                &self.info,
                &self.config,
                &self.ownship,
            );
            ok &= r.is_ok();
        }
        slot.common.us = None;
        for pair in parse_string_q(request, '#') {
            let (left, right) = pair.split_once('=').unwrap_or((pair, ""));
            let key = left.trim().to_ascii_lowercase();
            let value = right.trim();
            let good = if key == "name" || key == "descriptor" {
                // MOOS `augBehaviorName`: a name that already starts with the prefix is
                // taken whole.
                let good = good_name(value);
                if good {
                    if value.starts_with(&slot.common.name) {
                        slot.common.name = value.to_string();
                    } else {
                        slot.common.name.push_str(value);
                    }
                }
                good
            } else {
                apply_param(
                    &mut slot,
                    &key,
                    value,
                    &self.info,
                    &self.config,
                    &self.ownship,
                )
                .is_ok()
            };
            if !good {
                self.bhvset_warnings.push(format!(
                    "Failed to spawn {}. Bad config: {pair}",
                    slot.common.name
                ));
            }
            ok &= good;
        }
        let event = if ok { "spawn" } else { "abort" };
        let (name, kind) = (slot.common.name.clone(), slot.common.kind.clone());
        self.life_event(&name, &kind, event, request, "", now);
        if !ok {
            return;
        }
        slot.spawn_base = Some(self.templates[t].prefix.clone());
        self.templates[t].made += 1;
        self.bhv_total_ever += 1;
        self.slots.push(slot);
        let i = self.slots.len() - 1;
        // onSetParamComplete and onSpawn post with this iteration's messages, before the
        // spawnflags (repeatable); the configflags follow on its first iteration.
        self.call(i, |b, ctx, out| {
            b.on_set_param_complete(ctx, out);
            b.on_spawn(ctx, out);
            None
        });
        self.post_flags(i, FlagKind::Spawn);
        self.disable_if_blacklisted(i, request);
        self.subs_dirty = true;
        self.state_vars_dirty = true;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_name_field_reads_as_tok_string_parse() {
        assert_eq!(field("name=ben # contact=ben", "name"), "ben");
        assert_eq!(field(" name = ben#x=1", "name"), "ben");
        assert_eq!(field("x=1 # name=ben", "name"), "ben");
        assert_eq!(field("x # name=ben", "name"), "");
        assert_eq!(field("speed=2", "name"), "");
    }
}
