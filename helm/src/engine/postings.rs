//! What the helm posts for its behaviours (pHelmIvP's `postBehaviorMessages`, reference
//! §4.5): the queued messages through `post_mapping` and the duplicate filter, flags with
//! their `[if]` conditions, destinations and macros, `BHV_IPF` parts, the state-space
//! variables, completed behaviours leaving the set; and the all-stop.

use super::*;

/// A behaviour message waiting to be posted: var, value and how the duplicate filter keys it
/// (the key string `<behaviour><var><tag>` is only assembled when the message is posted).
pub(super) struct Message {
    /// The variable's shared name ([`super::outbox::Names`]), looked up once when queued.
    pub(super) var: ByteString,
    pub(super) value: Value,
    pub(super) key: PostKey,
}

/// A behaviour's latest posting of a variable.
#[derive(Debug, Clone)]
pub(super) struct Outgoing {
    pub(super) value: Value,
    pub(super) time: f64,
    pub(super) bhv: String,
    pub(super) iter: u64,
}

/// Decimals of numeric macro values (MOOS `macroExpand(str, macro, double)`, 3 by default;
/// trailing zeros dropped).
pub(super) const MACRO_DIGITS: usize = 3;

pub(super) fn geometry_angle(h: f64) -> f64 {
    let a = h % 360.0;
    if a < 0.0 { a + 360.0 } else { a }
}

impl Helm {
    pub(super) fn notify(&mut self, var: &str, value: Value, aux: &str) {
        self.out.push(var, value, aux);
    }

    /// [`Helm::notify`] under a name known at compile time, with an empty aux (no lookup).
    pub(super) fn notify_static(&mut self, var: &'static str, value: Value) {
        self.out.push_static(var, value);
    }

    pub(super) fn post_allstop(&mut self, msg: &str) {
        if !self.state.enabled() {
            return;
        }
        match self.allstop.update(msg) {
            AllStopAction::None => {}
            AllStopAction::Announce(m) => {
                self.notify_static("IVPHELM_ALLSTOP", Value::String(m.into()))
            }
            AllStopAction::AnnounceAndZero(m) => {
                self.notify_static("IVPHELM_ALLSTOP", Value::String(m.into()));
                for i in 0..self.config.domain.len() {
                    let name = self.config.domain.vars()[i].name().to_ascii_uppercase();
                    let var = if name == "COURSE" {
                        "DESIRED_HEADING".to_string()
                    } else {
                        format!("DESIRED_{name}")
                    };
                    self.notify(&var, Value::Double(0.0), "");
                }
            }
        }
    }

    pub(super) fn post_behavior_messages(&mut self, iter: u64, now: f64) {
        // The behaviour set's warnings of this iteration (spawning), numbered from 0.
        for (k, w) in std::mem::take(&mut self.bhvset_warnings)
            .into_iter()
            .enumerate()
        {
            self.notes.push(AppcastNote::Warning(w.clone()));
            let mut v = String::new();
            uint(&mut v, k as u64);
            v.push(':');
            v.push_str(&w);
            self.notify_static("IVPHELM_BHVSET_WARNING", Value::String(v.into()));
        }
        let n = self.slots.len();
        if self.bhv_count != Some(n) {
            self.bhv_count = Some(n);
            self.notify_static("IVPHELM_BHV_CNT", Value::Double(n as f64));
        }
        let ever = self.bhv_total_ever;
        if self.bhv_count_ever != Some(ever) {
            self.bhv_count_ever = Some(ever);
            self.notify_static("IVPHELM_BHV_CNT_EVER", Value::Double(ever as f64));
        }
        self.notify_static("IVPHELM_ITER", Value::Double(iter as f64));
        let mut messages = std::mem::take(&mut self.messages);
        for (i, m) in messages.drain(..) {
            if m.var == "BHV_IPF" {
                // Muxed into parts of 2000 characters, id `<bhv>^<iteration>`, each posted
                // with the behaviour's name as its source aux; not kept in the info buffer.
                if let Value::String(text) = &m.value {
                    let name = &self.slots[i].common.name;
                    let mut id = String::with_capacity(name.len() + 12);
                    id.push_str(name);
                    id.push('^');
                    uint(&mut id, iter);
                    let mut parts = std::mem::take(&mut self.ipf_parts);
                    ivp::encode::mux(text, &id, 2000, &mut parts);
                    for part in parts.drain(..) {
                        let aux = self.out.names.get(name);
                        let p = self.out.next_key(m.var.clone());
                        p.aux = aux;
                        p.value = Value::String(part.into());
                    }
                    self.ipf_parts = parts;
                }
                continue;
            }
            self.info.set_ref(&m.var, &m.value, APP_NAME, now);
            if m.var == "BHV_WARNING" || m.var == "BHV_ERROR" {
                self.warnings += 1;
                // pHelmIvP shows them in its appcast; a warning whose key ends in
                // `retract` withdraws the same text.
                let text = match &m.value {
                    Value::String(t) => t.clone(),
                    v => v.to_string().into(),
                };
                let w = format!("{}: {text}", m.var);
                let retract = m.var == "BHV_WARNING"
                    && matches!(&m.key, PostKey::Tag(t) if t.ends_with("retract"));
                self.notes.push(if retract {
                    AppcastNote::Retract(w)
                } else {
                    AppcastNote::Warning(w)
                });
            }
            let name = &self.slots[i].common.name;
            let tag = match m.key {
                PostKey::Repeatable => None,
                PostKey::Var => Some(""),
                PostKey::Tag(t) => Some(t),
            };
            let post = match tag {
                None => true,
                Some(t) => {
                    let key = &mut self.key_buf;
                    key.clear();
                    key.push_str(name);
                    key.push_str(&m.var);
                    key.push_str(t);
                    self.filter.changed(key, &m.value)
                }
            };
            if post {
                match self.outgoing.get_mut(&*m.var) {
                    Some(o) => {
                        o.value.clone_from(&m.value);
                        o.time = now;
                        o.bhv.clone_from(name);
                        o.iter = iter;
                    }
                    None => {
                        self.outgoing.insert(
                            m.var.to_string(),
                            Outgoing {
                                value: m.value.clone(),
                                time: now,
                                bhv: name.clone(),
                                iter,
                            },
                        );
                    }
                }
                if m.var == "BHV_EVENT"
                    && let Value::String(e) = &m.value
                {
                    self.notes.push(AppcastNote::Event(e.to_string()));
                }
                // `<iteration>:<behaviour>` differs every iteration: made once per
                // iteration and behaviour, shared by its postings.
                let aux = self.slots[i].post_aux(iter);
                let p = self.out.next_key(m.var);
                p.value = m.value;
                p.aux = aux;
            }
        }
        self.messages = messages;
        // Condition and flag variables change only with the behaviour set or an update.
        if self.state_vars_dirty {
            self.state_vars_dirty = false;
            let vars = self.state_space_vars();
            if vars != self.state_vars {
                self.notify_static("IVPHELM_STATEVARS", Value::String(vars.clone().into()));
                self.state_vars = vars;
            }
        }
        let pending = self.slots.iter().any(|s| s.state == RunState::Completed);
        if self.completed_pending != Some(pending) {
            self.completed_pending = Some(pending);
            let v = if pending { "true" } else { "false" };
            self.notify_static("IVPHELM_COMPLETED_PENDING", Value::String(v.into()));
        }
        // This iteration's spawns, then the deaths: completed behaviours leave the set
        // (reference §4.4).
        for ev in std::mem::take(&mut self.life_events) {
            self.notify_static("IVPHELM_LIFE_EVENT", Value::String(ev.into()));
        }
        let mut removed = 0;
        let mut k = 0;
        while k < self.slots.len() {
            if self.slots[k].state == RunState::Completed {
                let s = self.slots.remove(k);
                let pm = &s.post_mortem;
                self.life_event(&s.common.name, &s.common.kind, "death", "", pm, now);
                for ev in std::mem::take(&mut self.life_events) {
                    self.notify_static("IVPHELM_LIFE_EVENT", Value::String(ev.into()));
                }
                removed += 1;
                self.state_vars_dirty = true;
            } else {
                k += 1;
            }
        }
        if self.completed_count != Some(removed) {
            self.completed_count = Some(removed);
            self.notify_static("IVPHELM_COMPLETED_COUNT", Value::Double(removed as f64));
        }
    }

    /// The variables of the behaviours' state space (MOOS `getStateSpaceVars`): condition
    /// variables and the variables of run, runx, idle, end, active and inactive flags,
    /// comma-separated, each once, in behaviour order.
    pub(super) fn state_space_vars(&self) -> String {
        let mut out: Vec<&str> = Vec::new();
        for s in &self.slots {
            for (_, c) in &s.common.conditions {
                for v in c.variables() {
                    if !out.contains(&v) {
                        out.push(v);
                    }
                }
            }
            for kind in [
                FlagKind::Run,
                FlagKind::Runx,
                FlagKind::Idle,
                FlagKind::End,
                FlagKind::Active,
                FlagKind::Inactive,
            ] {
                for f in s.common.flags(kind) {
                    if !out.contains(&f.var.as_str()) {
                        out.push(&f.var);
                    }
                }
            }
        }
        out.join(",")
    }

    /// [`Helm::queue`] for a variable name the caller owns (kept unless `post_mapping`
    /// renames it).
    pub(super) fn queue_owned(&mut self, i: usize, var: String, value: Value, key: &PostKey) {
        let renamed = match self.slots[i].common.mapped(&var) {
            None => return,
            Some(m) if m == var => None,
            Some(m) => Some(m.to_string()),
        };
        let var = match renamed {
            Some(m) => self.out.names.get(&m),
            None => self.out.names.get(&var),
        };
        let key = key.clone();
        self.messages.push((i, Message { var, value, key }));
    }

    /// Queues a behaviour message with the duplicate-filter key of `key`.
    pub(super) fn queue(&mut self, i: usize, var: &str, value: Value, key: &PostKey) {
        let common = &self.slots[i].common;
        let Some(var) = common.mapped(var) else {
            return;
        };
        let var = self.out.names.get(var);
        let key = key.clone();
        self.messages.push((i, Message { var, value, key }));
    }

    pub(super) fn post_flags(&mut self, i: usize, kind: FlagKind) {
        let flags = self.slots[i].common.flags(kind).to_vec();
        for f in &flags {
            self.post_flag(i, f, true);
        }
    }

    /// Posts one flag (reference §4.5, MOOS `postFlag`): the `[if]` condition is checked now,
    /// macros are expanded, a lone numeric macro posts a double; `#all`/`#group` destinations
    /// go off-board as `NODE_MESSAGE_LOCAL` (the `+` forms are also posted locally).
    pub(super) fn post_flag(&mut self, i: usize, f: &behaviors::Flag, repeatable: bool) {
        if let Some(c) = &f.condition {
            let info = &self.info;
            if !c.evaluate(&|n: &str| info.condition_value(n)) {
                return;
            }
        }
        let value = match &f.value {
            FlagValue::Double(x) => Value::Double(*x),
            FlagValue::String(s) => {
                let mut out = std::mem::take(&mut self.scratch);
                out.clear();
                self.expand_macros(i, s, &mut out);
                let v = if f.solo_macro
                    && mission::condition::is_numeric(out.trim())
                    && let Ok(x) = out.trim().parse::<f64>()
                {
                    Value::Double(x)
                } else {
                    Value::String(out.clone().into())
                };
                self.scratch = out;
                v
            }
            // A flag's value is parsed from text: never binary.
            FlagValue::Binary(b) => Value::Binary(b.clone()),
        };
        let key = if repeatable {
            PostKey::Repeatable
        } else {
            PostKey::Var
        };
        let dest = f.dest.as_str();
        if matches!(dest, "" | "all+" | "group+") {
            self.queue(i, &f.var, value.clone(), &key);
        }
        if matches!(dest, "all" | "all+" | "group" | "group+") {
            let group = if dest.starts_with("group") {
                let var = format!("{}_NAV_GROUP", self.us(i).to_ascii_uppercase());
                Some(self.info.text(&var).unwrap_or("").to_string())
            } else {
                None
            };
            let spec = self.node_message(i, &f.var, &value, group.as_deref());
            let key = match key {
                PostKey::Repeatable => PostKey::Repeatable,
                _ => PostKey::Tag(""),
            };
            self.queue(i, "NODE_MESSAGE_LOCAL", Value::String(spec.into()), &key);
        }
    }

    /// The vehicle name behaviour `i` goes by (its `us`, else the helm's community).
    pub(super) fn us(&self, i: usize) -> &str {
        self.slots[i].common.us.as_deref().unwrap_or(&self.ownship)
    }

    /// A `NODE_MESSAGE` spec (MOOS `NodeMessage::getSpec`) from this helm's behaviour `i`.
    pub(super) fn node_message(
        &self,
        i: usize,
        var: &str,
        value: &Value,
        group: Option<&str>,
    ) -> String {
        let mut s = format!("src_node={},dest_node=all", self.us(i));
        if let Some(g) = group.filter(|g| !g.is_empty()) {
            s.push_str(",dest_group=");
            s.push_str(g);
        }
        s.push_str(&format!(
            ",src_app={},src_bhv={},var_name={var}",
            self.app_name, self.slots[i].common.name
        ));
        match value {
            Value::Double(x) => {
                s.push_str(",double_val=");
                compact(&mut s, *x, 6);
            }
            Value::String(v) if v.contains(',') && !(v.starts_with('"') && v.ends_with('"')) => {
                s.push_str(&format!(",string_val=\"{v}\""));
            }
            Value::String(v) => {
                s.push_str(",string_val=");
                s.push_str(v);
            }
            // Behaviours post no binary data.
            Value::Binary(_) => {}
        }
        s
    }

    pub(super) fn expand_macros(&mut self, i: usize, text: &str, out: &mut String) {
        let now = self.info.now_time();
        let info = &self.info;
        let slot = &mut self.slots[i];
        // Each counter macro present (in its `$[..]` form) counts once per expansion, and all
        // its occurrences get the same value (MOOS `expandCtrMacro`).
        for (k, m) in [
            "$[CTR]", "$[CTR1]", "$[CTR2]", "$[CTR3]", "$[CTR4]", "$[CTR5]",
        ]
        .iter()
        .enumerate()
        {
            if text.contains(m) {
                slot.ctr[k] += 1;
            }
        }
        let mut rng = slot.hash_state();
        let ownship = slot.common.us.as_deref().unwrap_or(&self.ownship);
        let nav = |v: &str| info.num(v).unwrap_or(0.0);
        // One value per `HASH` macro and expansion, shared by its occurrences (MOOS
        // `macroHashExpand`): `HASH` and `HASH6` six characters, `HASHn` n (2 to 9).
        let mut hashes: [Option<String>; 10] = Default::default();
        expand(text, out, |name, o| {
            if slot.bhv.macro_value(name, o) {
                return true;
            }
            if let Some(n) = name.strip_prefix("HASH") {
                // `HASH` (slot 0) and `HASH6` are separate macros of six characters.
                let (k, len) = match n {
                    "" => (0, 6),
                    "2" | "3" | "4" | "5" | "6" | "7" | "8" | "9" => {
                        let l = n.parse().unwrap_or(6);
                        (l, l)
                    }
                    _ => return false,
                };
                let h = hashes[k].get_or_insert_with(|| {
                    let mut h = String::with_capacity(len);
                    behavior_set::push_hash(&mut rng, len, &mut h);
                    h
                });
                o.push_str(h);
                return true;
            }
            match name {
                "OWNSHIP" => o.push_str(ownship),
                "BHVNAME" => o.push_str(&slot.common.name),
                "BHVTYPE" => o.push_str(&slot.common.kind),
                "PWT" => compact(o, slot.common.pwt, MACRO_DIGITS),
                "CONTACT" => {}
                "UTC" => compact(o, now, MACRO_DIGITS),
                "OSX" => compact(o, nav("NAV_X"), MACRO_DIGITS),
                "OSY" => compact(o, nav("NAV_Y"), MACRO_DIGITS),
                "OSH" => compact(o, geometry_angle(nav("NAV_HEADING")), MACRO_DIGITS),
                "OSV" => compact(o, nav("NAV_SPEED"), MACRO_DIGITS),
                "DUR_RUN_TIME" => compact(o, slot.clock.running_time, MACRO_DIGITS),
                "DUR_IDLE_TIME" => compact(o, slot.clock.idle_time, MACRO_DIGITS),
                "NOW" => {
                    let t0 = *slot.now_start.get_or_insert(now);
                    compact(o, now - t0, MACRO_DIGITS)
                }
                "CTR" | "CTR1" | "CTR2" | "CTR3" | "CTR4" | "CTR5" => {
                    let k = name[3..].parse::<usize>().unwrap_or(0);
                    o.push_str(&slot.ctr[k].to_string());
                }
                _ => return false,
            }
            true
        });
        self.slots[i].hash_rng = rng;
    }

    /// Records an `IVPHELM_LIFE_EVENT` (`event` spawn, abort or death; `seed`: the spawning
    /// request, `helm_startup` for the behaviours of the file; `post_mortem`: why a behaviour
    /// died, if it says), posted with this iteration's behaviour messages.
    ///
    /// The text is pHelmIvP's: the event's own iteration (never set by the helm, so always
    /// 0), the time since the helm started when positive, the names, the seed and post
    /// mortem when not empty, then the helm's iteration:
    /// `iter=0,time=191.25, bname=survey, btype=BHV_Waypoint, event=death,iter=762`.
    pub(super) fn life_event(
        &mut self,
        name: &str,
        kind: &str,
        event: &str,
        seed: &str,
        post_mortem: &str,
        now: f64,
    ) {
        let mut ev = String::from("iter=0");
        let since_start = now - self.start_time;
        if since_start > 0.0 {
            ev.push_str(",time=");
            fixed(&mut ev, since_start, 2);
        }
        for (key, value) in [("bname", name), ("btype", kind), ("event", event)] {
            ev.push_str(", ");
            ev.push_str(key);
            ev.push('=');
            ev.push_str(value);
        }
        for (key, value) in [("seed", seed), ("post_mortem", post_mortem)] {
            if !value.is_empty() {
                ev.push_str(", ");
                ev.push_str(key);
                ev.push('=');
                ev.push_str(value);
            }
        }
        ev.push_str(",iter=");
        uint(&mut ev, self.iteration);
        self.life_events.push(ev);
    }
}
