//! Mail into the helm (pHelmIvP's `OnNewMail` and registrations): the queue, the skew
//! check, the manual override, `IVPHELM_STATE` from other helms, node reports into the
//! ledger, everything else into the info buffer; and the variables the helm subscribes to.

use super::*;

impl Helm {
    /// The variables the helm subscribes to (reference §4.3 registrations): its own, the mode
    /// conditions' variables, and every variable a behaviour reads (conditions, flag
    /// conditions, `updates`, `duration_reset`,
    /// `nostarve` and [`Behavior::info_vars`], e.g. `GPS_UPDATE_RECEIVED`). The list only
    /// grows: a run-time update that makes a behaviour read a new variable adds it (and the
    /// helm posts `IVPHELM_REGISTER = <var>` for it, as pHelmIvP registers new info vars).
    /// New variables are appended, so a caller that remembers how many it has registered
    /// finds the new ones past that length (an unchanged length: nothing new), without a copy.
    pub fn subscriptions(&self) -> &[String] {
        &self.registered
    }

    /// The variables the helm and its behaviours read now.
    pub(super) fn wanted_subscriptions(&self) -> Vec<String> {
        let mut v: Vec<String> = [
            "DB_CLIENTS",
            "MOOS_MANUAL_OVERIDE",
            "MOOS_MANUAL_OVERRIDE",
            "RESTART_HELM",
            "IVPHELM_REJOURNAL",
            "BHV_ABLE_FILTER",
            "NAV_X",
            "NAV_Y",
            "NAV_SPEED",
            "NAV_HEADING",
            "NAV_DEPTH",
            "HELM_MAP_CLEAR",
            "AIS_REPORT",
            "NODE_REPORT",
            "AIS_REPORT_LOCAL",
            "NODE_REPORT_LOCAL",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        if !self.config.other_override_var.is_empty() {
            v.push(self.config.other_override_var.clone());
        }
        let push = |v: &mut Vec<String>, s: &str| {
            if !s.is_empty() && !v.iter().any(|x| x == s) {
                v.push(s.to_string());
            }
        };
        let mut bhv_vars = Vec::new();
        // pHelmIvP also registers the variables of the mode declarations' conditions.
        for var in self.modes.condition_vars() {
            push(&mut v, var);
        }
        for s in &self.slots {
            for (_, c) in &s.common.conditions {
                for var in c.variables() {
                    push(&mut v, var);
                }
            }
            for k in FlagKind::ALL {
                for f in s.common.flags(k) {
                    if let Some(c) = &f.condition {
                        for var in c.variables() {
                            push(&mut v, var);
                        }
                    }
                }
            }
            if let Some((var, _)) = &s.common.duration_reset {
                push(&mut v, var);
            }
            push(&mut v, &s.common.update_var);
            for (var, _) in &s.common.starve {
                push(&mut v, var);
            }
            s.bhv.info_vars(&mut bhv_vars);
        }
        for var in &bhv_vars {
            push(&mut v, var);
        }
        // The templates' `updates` variables (spawning requests).
        for t in &self.templates {
            push(&mut v, &t.update_var);
        }
        for var in self.initializes.iter().filter(|i| i.2).map(|i| i.0.clone()) {
            push(&mut v, &var);
        }
        push(&mut v, "IVPHELM_STATE");
        v
    }

    /// Adds the variables behaviours read now but the helm has not registered yet (after a
    /// run-time update), posting `IVPHELM_REGISTER` for each.
    pub(super) fn refresh_subscriptions(&mut self) {
        for var in self.wanted_subscriptions() {
            if !self.registered.contains(&var) {
                self.registered.push(var.clone());
                self.notify_static("IVPHELM_REGISTER", Value::String(var.into()));
            }
        }
    }

    /// Queues mail for the next [`Helm::iterate`].
    pub fn on_mail<'a>(&mut self, mail: impl IntoIterator<Item = &'a Mail>) {
        let holding = self.held_apps.iter().any(|(_, seen)| !seen);
        for m in mail {
            // hold_on_apps: note each app named in DB_CLIENTS (pHelmIvP `checkHoldOnApps`).
            if holding
                && m.key == "DB_CLIENTS"
                && let Value::String(list) = &m.value
            {
                for (app, seen) in &mut self.held_apps {
                    *seen |= list.split(',').any(|c| c.trim() == app.as_str());
                }
            }
            self.pending.push(m.clone());
        }
    }

    /// Makes this freshly built helm the restart of `old` (pHelmIvP `RESTART_HELM`): it keeps
    /// `old`'s control (manual override), its pending mail and, for `type1` (`keep_info`),
    /// its info buffer without posting the initializes again (`type2` starts a fresh
    /// buffer and posts them). It starts over (registrations, domain, mode set) at its next
    /// iteration and posts `IVPHELM_RESTARTED = true` once it decides again.
    pub fn restart_from(&mut self, old: Helm, keep_info: bool) {
        self.has_control = old.has_control && self.errors.is_empty();
        self.pending = old.pending;
        self.held_apps = old.held_apps;
        if keep_info {
            self.info = old.info;
            self.skip_initialize = true;
        }
        self.restart_post_pending = true;
    }

    /// True while an app of `hold_on_apps` has not yet appeared in DB_CLIENTS: the
    /// behaviours' configuration-time postings (MOOS's helm start messages) wait.
    pub fn holding(&self) -> bool {
        self.held_apps.iter().any(|(_, seen)| !seen)
    }

    pub(super) fn handle_mail(&mut self, now: f64) {
        let mail = std::mem::take(&mut self.pending);
        for m in &mail {
            if self.state == HelmState::Disabled {
                break;
            }
            if let Some(ok) = self.config.ok_skew {
                let skew = (now - m.time).abs().min(now - self.start_time);
                if skew > ok && m.source != self.app_name && m.key != "HELM_MAP_CLEAR" {
                    let mut msg = format!(
                        "Helm ignores MOOS msg due to skew: {} Source={} Skew=",
                        m.key, m.source
                    );
                    fixed(&mut msg, skew, 2);
                    self.notes.push(AppcastNote::Warning(msg.clone()));
                    msg.push_str(" curr_time: ");
                    fixed(&mut msg, now, 3);
                    self.notify_static("IVPHELM_SKEW", Value::String(msg.into()));
                    continue;
                }
            }
            let is_override = m.key == "MOOS_MANUAL_OVERRIDE"
                || m.key == "MOOS_MANUAL_OVERIDE"
                || (!self.config.other_override_var.is_empty()
                    && m.key == self.config.other_override_var);
            if is_override {
                if let Value::String(s) = &m.value {
                    if s.trim().eq_ignore_ascii_case("false") {
                        self.has_control = self.state != HelmState::Malconfig;
                    } else if s.trim().eq_ignore_ascii_case("true") && self.config.allow_park {
                        self.has_control = false;
                    }
                    self.status_update();
                }
                self.info.set(&m.key, m.value.clone(), &m.source, m.time);
            } else if m.key == "IVPHELM_STATE" {
                self.init_vars_ready = true;
                let other = m.source != self.app_name;
                if other && self.config.standby.is_some() {
                    if self.state == HelmState::Standby {
                        // The primary is alive: the take-over clock starts again.
                        self.standby_last_heartbeat = now;
                    } else {
                        // Taken over already: a tardy primary; everything is published
                        // again.
                        self.refresh_pending = true;
                        self.rejournal = true;
                    }
                } else if other && m.value.as_str() != Some("STANDBY") && self.state.enabled() {
                    self.post_allstop("DisabledByStandbyHelm");
                    self.state = HelmState::Disabled;
                }
            } else if m.key == "IVPHELM_REJOURNAL" {
                self.rejournal = true;
            } else if m.key == "BHV_ABLE_FILTER" {
                // BehaviorSet: every behaviour sees the filter (`able.rs`), then the helm's
                // spawn blacklist.
                if let Value::String(s) = &m.value {
                    self.able_filter_mail(s);
                }
            } else if m.key == "NODE_REPORT_LOCAL" {
                self.node_report_local(&m.value, now);
            } else if matches!(&*m.key, "AIS_REPORT" | "NODE_REPORT" | "AIS_REPORT_LOCAL") {
                self.node_report(&m.value, now);
                self.info.set(&m.key, m.value.clone(), &m.source, m.time);
            } else if m.key == "HELM_MAP_CLEAR" {
                self.refresh_pending = true;
            } else if m.source_aux != "HELM_VAR_INIT" {
                self.info.set(&m.key, m.value.clone(), &m.source, m.time);
            }
        }
        // A standby helm takes over once the primary has been silent for its threshold
        // (checked when mail comes, as pHelmIvP checks at the end of its mail handler).
        if !mail.is_empty()
            && self.state == HelmState::Standby
            && self.standby_last_heartbeat > 0.0
            && let Some(threshold) = self.config.standby
            && now - self.standby_last_heartbeat > threshold
        {
            self.state = HelmState::Park;
            self.status_update();
        }
        self.pending = mail;
        self.pending.clear();
    }

    /// A node report from another vehicle (pHelmIvP `processNodeReport`): into the ledger,
    /// and its group and type into the info buffer as `<VNAME>_NAV_GROUP` / `_NAV_TYPE`
    /// (for a rejected report the C++ sets `_NAV_GROUP` and `_NAV_TYPE`, empty, too).
    pub(super) fn node_report(&mut self, value: &Value, now: f64) {
        let text = match value {
            Value::String(s) => &s[..],
            _ => "",
        };
        let report = crate::ledger::NodeReport::parse(text);
        let name = match self.ledger.process(&report, now) {
            Ok(name) => name,
            Err(why) => {
                self.notes
                    .push(AppcastNote::Warning(format!("Bad NodeReport: {text}")));
                self.notes
                    .push(AppcastNote::Warning(format!("The issue: {why}")));
                String::new()
            }
        };
        let (group, vtype) = match self.ledger.get(&name) {
            Some(c) => (c.group.clone(), c.vtype.clone()),
            None => (String::new(), String::new()),
        };
        self.set_nav_field(&name, "GROUP", Value::String(group.into()), now);
        self.set_nav_field(&name, "TYPE", Value::String(vtype.into()), now);
    }

    /// Sets `<NAME>_NAV_<suffix>` (the name upper-cased) in the info buffer, the variable's
    /// name written into a reused buffer.
    fn set_nav_field(&mut self, name: &str, suffix: &str, value: Value, now: f64) {
        let mut key = std::mem::take(&mut self.key_buf);
        key.clear();
        key.extend(name.chars().map(|c| c.to_ascii_uppercase()));
        key.push_str("_NAV_");
        key.push_str(suffix);
        self.info.set(&key, value, APP_NAME, now);
        self.key_buf = key;
    }

    /// The vehicle's own report (pHelmIvP `processNodeReportLocal`): only its group, type,
    /// color and length reach the info buffer, as `<VNAME>_NAV_*`; the report itself does
    /// not.
    pub(super) fn node_report_local(&mut self, value: &Value, now: f64) {
        let text = match value {
            Value::String(s) => &s[..],
            _ => "",
        };
        let r = crate::ledger::NodeReport::parse(text);
        if r.name.is_empty() {
            self.notes
                .push(AppcastNote::Warning("Unhandled NODE_REPORT_LOCAL".into()));
            return;
        }
        for (suffix, v) in [("GROUP", r.group), ("TYPE", r.vtype), ("COLOR", r.color)] {
            if !v.is_empty() {
                self.set_nav_field(&r.name, suffix, Value::String(v.into()), now);
            }
        }
        if let Some(len) = r.length_m.filter(|&l| l != 0.0) {
            self.set_nav_field(&r.name, "LENGTH", Value::Double(len), now);
        }
    }
}
