//! `pSafety`: the safety supervisor ([`safety`]) as a MOOS app.
//!
//! Its rules, actions, postings, health word and configuration are documented in the
//! [`safety`] crate. The app feeds every mail it registered for to [`safety::Supervisor`]
//! (with the mail's source, so `silent(APP)` hears any post of that app), judges the rules at
//! each iteration, and reports triggers and releases as appcast events, warn rules as run
//! warnings, and configuration errors as config warnings. A block with errors makes the app
//! MALCONFIG ([`crate::app::App::malconfig`]: `coug check` and `coug run` report it), and the supervisor
//! then keeps the vehicle from deploying.

use mission::diagnostic::Diagnostic;
use mission::moos::ProcessConfig;
use safety::{Notice, SafetyConfig, Supervisor};

use crate::antler::BuiltInApp;
use crate::app::{Mail, Post, Subscription};
use crate::appcasting::Note;
use crate::hosted::{AppCore, Hosted};

/// The MOOS name of the app.
pub const PROGRAM: &str = safety::PROGRAM;

/// The supervisor: the core of the `pSafety` app.
pub struct SafetyCore {
    supervisor: Supervisor,
    notices: Vec<Notice>,
}

/// The `pSafety` app.
pub type SafetyApp = Hosted<SafetyCore>;

impl Hosted<SafetyCore> {
    /// The app `name` from its `block`; its configuration errors are [`SafetyApp::errors`].
    pub fn new(name: &str, block: ProcessConfig) -> Self {
        let (cfg, errors) = SafetyConfig::from_block(&block);
        let located = errors.iter().map(Diagnostic::located).collect();
        let mut supervisor = Supervisor::new(cfg, located);
        supervisor.set_period(1.0 / crate::app::app_tick_of(Some(&block)));
        let core = SafetyCore {
            supervisor,
            notices: Vec::new(),
        };
        Hosted::host(name, block, errors, core)
    }

    /// The block's errors (each makes the app MALCONFIG), at their lines.
    pub fn errors(&self) -> &[Diagnostic] {
        self.warnings()
    }

    /// The supervisor.
    pub fn supervisor(&self) -> &Supervisor {
        &self.core().supervisor
    }
}

impl SafetyCore {
    fn flush(&mut self, notes: &mut Vec<Note>) {
        notes.extend(self.notices.drain(..).map(|n| match n {
            Notice::Event(e) => Note::Event(e),
            Notice::Warning(w) => Note::Warning(w),
        }));
    }
}

impl AppCore for SafetyCore {
    fn subscriptions(&self) -> Vec<Subscription> {
        self.supervisor
            .subscriptions()
            .into_iter()
            .map(Subscription::var)
            .collect()
    }

    fn on_startup(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        self.supervisor.start(now, out, &mut self.notices);
        self.flush(notes);
    }

    fn on_mail(&mut self, m: &Mail, _now: f64, _out: &mut Vec<Post>, _notes: &mut Vec<Note>) {
        self.supervisor.on_mail(&m.key, &m.value, &m.source, m.time);
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        self.supervisor.evaluate(now, out, &mut self.notices);
        self.flush(notes);
    }

    fn report(&self, _now: f64, body: &mut String) {
        self.supervisor.report(body);
    }

    fn malconfig(&self) -> Vec<String> {
        self.supervisor.errors().to_vec()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::{App, Value};

    fn block(text: &str) -> ProcessConfig {
        crate::testing::block("s.moos", text)
    }

    #[test]
    fn a_leak_is_an_event_and_the_helm_is_overridden() {
        let b = block(
            "ProcessConfig = pSafety\n{\n  AppTick = 4\n  rule = leak: LEAK == true -> surface_disarm\n}\n",
        );
        let mut app = SafetyApp::new("pSafety", b);
        assert!(app.errors().is_empty() && app.malconfig().is_empty());
        let subs: Vec<String> = app.subscriptions().into_iter().map(|s| s.pattern).collect();
        for v in [
            "APPCAST_REQ",
            "LEAK",
            "NAV_DEPTH",
            "MOOS_MANUAL_OVERRIDE",
            "SAFETY_RESET",
        ] {
            assert!(subs.contains(&v.to_string()), "{v}: {subs:?}");
        }
        let mut out = Vec::new();
        app.on_startup(0.0, &mut out).unwrap();
        let m = crate::testing::mail("LEAK", Value::text("true"), 1.0, "iTeensy");
        app.on_mail(&[m], 1.0, &mut out).unwrap();
        out.clear();
        app.iterate(1.0, &mut out).unwrap();
        let get = |k: &str| {
            out.iter()
                .rev()
                .find(|p| p.key == k)
                .map(|p| p.value.clone())
        };
        assert_eq!(get("MOOS_MANUAL_OVERRIDE"), Some(Value::text("true")));
        assert_eq!(get("SAFETY_MODE"), Some(Value::text("SURFACE")));
        let cast = get("APPCAST")
            .and_then(|v| v.as_str().map(String::from))
            .unwrap();
        assert!(cast.contains("trigger=leak"), "{cast}");
        assert!(cast.contains("LATCHED"), "{cast}");
    }

    #[test]
    fn bad_rules_are_config_warnings_and_malconfig() {
        let b = block(
            "ProcessConfig = pSafety\n{\n  rule = leak: LEAK = true -> surface_disarm\n  \
             rule = low: BATT < 14 -> allstop\n}\n",
        );
        let mut app = SafetyApp::new("pSafety", b);
        assert_eq!(app.errors().len(), 1);
        let why = app.malconfig();
        assert_eq!(why.len(), 1);
        assert!(why[0].starts_with("s.moos:3: pSafety: rule"), "{why:?}");
        let mut out = Vec::new();
        app.on_startup(0.0, &mut out).unwrap();
        assert!(
            out.iter()
                .any(|p| p.key == "MOOS_MANUAL_OVERRIDE" && p.value.as_str() == Some("true"))
        );
        out.clear();
        app.iterate(0.25, &mut out).unwrap();
        let cast = out.iter().find(|p| p.key == "APPCAST").unwrap();
        let cast = cast.value.as_str().unwrap();
        assert!(cast.contains("s.moos:3: pSafety: rule"), "{cast}");
    }
}
