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
        let registered = helm.subscriptions();
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
        let now = self.helm.subscriptions();
        let fresh: Vec<Subscription> = now
            .iter()
            .filter(|v| !self.registered.contains(v))
            .map(|v| Subscription::var(v.clone()))
            .collect();
        if !fresh.is_empty() {
            self.registered = now;
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
