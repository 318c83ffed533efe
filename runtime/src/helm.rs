//! pHelmIvP: the `helm` crate's engine behind the [`App`] trait.

use ::helm::config::Globals;
use ::helm::{Helm, HelmState};
use mission::Parsed;
use mission::bhv::BehaviorFile;
use mission::moos::{MissionFile, ProcessConfig};

use crate::app::{App, Mail, Post, Subscription, Value};

/// The helm app: mail in, IvP decisions and behaviour postings out.
pub struct HelmApp {
    name: String,
    block: Option<ProcessConfig>,
    helm: Helm,
    mail: Vec<::helm::Mail>,
    registered: Vec<String>,
}

impl HelmApp {
    /// A helm called `name` configured from `block` (the `ProcessConfig` of its MOOS name;
    /// `None` puts the helm in MALCONFIG, as pHelmIvP without a block), the mission's
    /// globals and the parsed (nsplug-expanded) `.bhv` file. Problems do not fail here:
    /// the helm reports them ([`HelmApp::config_errors`]) and never drives.
    pub fn new(
        name: &str,
        block: Option<ProcessConfig>,
        mission: &MissionFile,
        bhv: &Parsed<BehaviorFile>,
    ) -> HelmApp {
        let helm = match &block {
            Some(b) => {
                let params: Vec<(&str, &str)> = b
                    .entries
                    .iter()
                    .map(|p| (p.key.as_str(), p.value.as_str()))
                    .collect();
                Helm::from_parsed(&params, &Globals::from_mission(mission), bhv)
            }
            None => Helm::from_mission(&MissionFile::default(), bhv),
        };
        let mut registered = helm.subscriptions();
        // pHelmIvP also registers the variables of the mode declarations' conditions
        // (e.g. DEPLOY in `set MODE = ACTIVE { DEPLOY = true }`).
        for m in &bhv.value.modes {
            for c in &m.conditions {
                for v in c.condition.variables() {
                    if !registered.iter().any(|r| r == v) {
                        registered.push(v.to_string());
                    }
                }
            }
        }
        HelmApp {
            name: name.to_string(),
            block,
            helm,
            mail: Vec::new(),
            registered,
        }
    }

    /// The helm's configuration problems (empty when it can drive).
    pub fn config_errors(&self) -> Vec<String> {
        self.helm
            .config_errors()
            .iter()
            .map(|e| e.to_string())
            .collect()
    }

    /// The helm state (PARK, DRIVE, MALCONFIG, DISABLED).
    pub fn state(&self) -> HelmState {
        self.helm.state()
    }
}

impl App for HelmApp {
    fn name(&self) -> &str {
        &self.name
    }

    fn process_config(&self) -> Option<&ProcessConfig> {
        self.block.as_ref()
    }

    fn subscriptions(&self) -> Vec<Subscription> {
        self.registered
            .iter()
            .map(|v| Subscription::var(v.clone()))
            .collect()
    }

    fn new_subscriptions(&mut self) -> Vec<Subscription> {
        let mut fresh = Vec::new();
        for v in self.helm.subscriptions() {
            if !self.registered.contains(&v) {
                fresh.push(Subscription::var(v.clone()));
                self.registered.push(v);
            }
        }
        fresh
    }

    fn on_mail(&mut self, mail: &[Mail], _now: f64, _out: &mut Vec<Post>) {
        self.mail.clear();
        self.mail.extend(mail.iter().filter_map(|m| {
            let value = match &m.value {
                Value::Double(x) => ::helm::Value::Num(*x),
                Value::String(s) => ::helm::Value::Str(s.clone()),
                Value::Binary(_) => return None,
            };
            Some(::helm::Mail {
                var: m.key.clone(),
                value,
                source: m.source.clone(),
                source_aux: m.source_aux.clone(),
                time: m.time,
            })
        }));
        self.helm.on_mail(&self.mail);
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) {
        for p in self.helm.iterate(now) {
            let value = match &p.value {
                ::helm::Value::Num(x) => Value::Double(*x),
                ::helm::Value::Str(s) => Value::String(s.clone()),
            };
            out.push(Post::new(p.var.clone(), value).with_aux(p.aux.clone()));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mission::source::SourceMap;

    #[test]
    fn registers_the_variables_of_mode_conditions() {
        let moos = "Community = c\nLatOrigin = 43.8\nLongOrigin = -70.3\nProcessConfig = pHelmIvP\n{\n  domain = course:0:359:360\n  domain = speed:0:4:41\n}\n";
        let m = mission::moos::parse_moos(&SourceMap::from_text("m.moos", moos)).value;
        let bhv = "initialize DEPLOY = false\nset MODE = ACTIVE {\n  DEPLOY = true\n  (QUIT != yes)\n} INACTIVE\n\
                   Behavior = BHV_ConstantSpeed\n{\n  name = cs\n  condition = MODE == ACTIVE\n  speed = 1\n}\n";
        let b = mission::bhv::parse_bhv(&SourceMap::from_text("m.bhv", bhv));
        let h = HelmApp::new("pHelmIvP", m.process("pHelmIvP").cloned(), &m, &b);
        assert!(h.config_errors().is_empty(), "{:?}", h.config_errors());
        let subs: Vec<String> = h.subscriptions().into_iter().map(|s| s.pattern).collect();
        for v in ["DEPLOY", "QUIT", "MODE", "NAV_X"] {
            assert!(subs.iter().any(|s| s == v), "{v} not in {subs:?}");
        }
        let n = subs.len();
        let mut dedup = subs.clone();
        dedup.sort();
        dedup.dedup();
        assert_eq!(dedup.len(), n, "no duplicate registrations");
    }
}
