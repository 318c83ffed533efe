//! One adapter for the apps made of a pure core: [`Hosted`] holds what every such app repeats
//! around its core (the MOOS name, the `ProcessConfig` block, the configuration warnings, the
//! AppTick and the [`AppcastLayer`]) and is the [`App`]; the core implements [`AppCore`]: its
//! registrations, its mail, its iteration, its appcast body. Adding an app is its core plus
//! its registry entry in [`crate::antler::BUILT_INS`], whose `make` builds it with
//! [`Hosted::host`] and hands it over with [`crate::antler::BuildCx::launched`].
//!
//! The adapter calls the layer at the points AppCastingMOOSApp does and keeps each app's
//! order of postings: `OnStartUp` ([`AppcastLayer::on_startup`], then the core's);
//! `OnNewMail` (the layer takes `APPCAST_REQ` and its kin, the core every other mail in
//! order, then [`AppCore::mail_done`]); `Iterate` ([`AppcastLayer::begin`], the core's
//! iteration, then [`AppcastLayer::end`] with the core's [`AppCore::report`]). What the core
//! tells the appcast (run warnings, retractions, events) it pushes as [`Note`]s, which reach
//! the layer at the end of the callback, at its time, before the cast is built.
//!
//! pCougControls, uSimCougUV, pNavGraph, uSimSensors, pSafety, the drivers iGPS, iDVL,
//! iSeaTrac and iTeensy, uSimDevices, the contact managers pBasicContactMgr and
//! pContactMgrV20, uFldNodeComms, pAcomms, uSimModem, pObstacleMgr and uFldObstacleSim are
//! hosted this way (the cores: `CougControls`, `CougUvSimCore`, `NavCore`, `SensorsCore`,
//! `SafetyCore`, `DriverCore`, `SimDevicesCore`, `ContactMgr`, `NodeComms`, `AcommsCore`,
//! `SimModemCore`, `ObstacleMgr`, `ObstacleSim`).

use mission::diagnostic::Diagnostic;
use mission::moos::ProcessConfig;

use crate::antler::BuiltInApp;
use crate::app::{App, AppResult, Mail, Post, Subscription, app_tick_of};
use crate::appcasting::{AppcastLayer, Note};

/// The pure part of a hosted app: no appcast state, no name or block bookkeeping.
pub trait AppCore: Send {
    /// The registrations besides the appcast layer's (which come first).
    fn subscriptions(&self) -> Vec<Subscription>;

    /// OnStartUp at MOOS time `now`, after the layer's.
    fn on_startup(&mut self, _now: f64, _out: &mut Vec<Post>, _notes: &mut Vec<Note>) {}

    /// One mail the appcast layer did not take, in delivery order.
    fn on_mail(&mut self, mail: &Mail, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>);

    /// After the last mail of one delivery (e.g. to hand on what the mail produced).
    fn mail_done(&mut self, _now: f64, _out: &mut Vec<Post>, _notes: &mut Vec<Note>) {}

    /// One iteration at MOOS time `now`, between the layer's `begin` and `end`.
    fn iterate(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>);

    /// The appcast body at MOOS time `now` (written only when a cast is due).
    fn report(&self, now: f64, body: &mut String);

    /// The run is over.
    fn stop(&mut self, _now: f64) -> AppResult {
        Ok(())
    }

    /// Why the app refuses to act on its configuration ([`App::malconfig`]).
    fn malconfig(&self) -> Vec<String> {
        Vec::new()
    }

    /// The process id, in single-app mode ([`App::set_process_id`]).
    fn set_process_id(&mut self, _pid: u32) {}
}

/// An app: a core with its name, block, warnings, AppTick and appcast layer.
pub struct Hosted<C> {
    name: String,
    block: ProcessConfig,
    warnings: Vec<Diagnostic>,
    tick: f64,
    appcast: AppcastLayer,
    notes: Vec<Note>,
    core: C,
}

impl<C: AppCore + 'static> BuiltInApp for Hosted<C> {
    /// Sets the mission's `Community` and `MOOSTimeWarp` for the app's appcasts.
    fn with_appcast_globals(mut self, community: Option<&str>, warp: f64) -> Self {
        self.appcast = AppcastLayer::with_config_warnings(
            &self.name,
            &self.block,
            community,
            warp,
            &self.warnings,
        );
        self
    }

    /// The configuration problems of the block, at their lines.
    fn warnings(&self) -> &[Diagnostic] {
        &self.warnings
    }
}

impl<C: AppCore> Hosted<C> {
    /// The app `name` made of `core`, configured from `block` with `warnings` (its
    /// configuration problems, each posted as an appcast config warning as `file:line:
    /// message`); it ticks at the block's `AppTick`. The appcasts name no community and no
    /// warp until [`BuiltInApp::with_appcast_globals`].
    pub fn host(name: &str, block: ProcessConfig, warnings: Vec<Diagnostic>, core: C) -> Self {
        Hosted {
            appcast: AppcastLayer::with_config_warnings(name, &block, None, 1.0, &warnings),
            name: name.to_string(),
            tick: app_tick_of(Some(&block)),
            block,
            warnings,
            notes: Vec::new(),
            core,
        }
    }

    /// The same app ticking at `hz` instead of the block's `AppTick`.
    pub fn with_tick(mut self, hz: f64) -> Self {
        self.tick = hz;
        self
    }

    /// The core.
    pub fn core(&self) -> &C {
        &self.core
    }

    /// The core, to change.
    pub fn core_mut(&mut self) -> &mut C {
        &mut self.core
    }

    fn flush_notes(&mut self, now: f64) {
        for n in self.notes.drain(..) {
            self.appcast.note(n, now);
        }
    }
}

impl<C: AppCore> App for Hosted<C> {
    fn name(&self) -> &str {
        &self.name
    }

    fn process_config(&self) -> Option<&ProcessConfig> {
        Some(&self.block)
    }

    fn app_tick(&self) -> f64 {
        self.tick
    }

    fn subscriptions(&self) -> Vec<Subscription> {
        AppcastLayer::subscriptions()
            .chain(self.core.subscriptions())
            .collect()
    }

    fn on_startup(&mut self, now: f64, out: &mut Vec<Post>) -> AppResult {
        self.appcast.on_startup(now);
        self.core.on_startup(now, out, &mut self.notes);
        self.flush_notes(now);
        Ok(())
    }

    fn on_mail(&mut self, mail: &[Mail], now: f64, out: &mut Vec<Post>) -> AppResult {
        for m in mail {
            if self.appcast.take_mail(m) {
                self.core.on_mail(m, now, out, &mut self.notes);
            }
        }
        self.core.mail_done(now, out, &mut self.notes);
        self.flush_notes(now);
        Ok(())
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> AppResult {
        let tick = self.tick;
        self.appcast.begin(now, tick, out);
        self.core.iterate(now, out, &mut self.notes);
        self.flush_notes(now);
        let core = &self.core;
        self.appcast
            .end(now, tick, out, |body| core.report(now, body));
        Ok(())
    }

    fn stop(&mut self, now: f64) -> AppResult {
        self.core.stop(now)
    }

    fn malconfig(&self) -> Vec<String> {
        self.core.malconfig()
    }

    fn set_process_id(&mut self, pid: u32) {
        self.core.set_process_id(pid);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::Value;

    /// Counts its mail and iterations, notes an event at each, reports both.
    #[derive(Default)]
    struct Counter {
        mail: u32,
        iterations: u32,
    }

    impl AppCore for Counter {
        fn subscriptions(&self) -> Vec<Subscription> {
            vec![Subscription::var("X")]
        }
        fn on_mail(&mut self, m: &Mail, _: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
            self.mail += 1;
            out.push(Post::double("SEEN", m.value.as_f64().unwrap_or(-1.0)));
            notes.push(Note::Event(format!("mail {}", self.mail)));
        }
        fn iterate(&mut self, _: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
            self.iterations += 1;
            out.push(Post::double("ITER", f64::from(self.iterations)));
            notes.push(Note::Warning("counting".into()));
        }
        fn report(&self, now: f64, body: &mut String) {
            body.push_str(&format!(
                "mail={} iter={} at {now}\n",
                self.mail, self.iterations
            ));
        }
    }

    #[test]
    fn the_layer_takes_its_mail_and_the_core_writes_the_cast() {
        let block =
            crate::testing::block("h.moos", "ProcessConfig = pCount\n{\n  AppTick = 4\n}\n");
        let warn = Diagnostic::line_warning(
            mission::diagnostic::DiagnosticKind::AppSetting,
            &block.span,
            "pCount: a warning".to_string(),
        );
        let app = Hosted::host("pCount", block, vec![warn], Counter::default())
            .with_appcast_globals(Some("abe"), 2.0);
        assert_eq!(app.warnings().len(), 1);
        assert_eq!(app.app_tick(), 4.0);
        assert_eq!(app.with_tick(12.5).app_tick(), 12.5);
        let block =
            crate::testing::block("h.moos", "ProcessConfig = pCount\n{\n  AppTick = 4\n}\n");
        let mut app = Hosted::host("pCount", block, Vec::new(), Counter::default());
        let subs: Vec<String> = app.subscriptions().into_iter().map(|s| s.pattern).collect();
        assert_eq!(subs.first().map(String::as_str), Some("APPCAST_REQ"));
        assert_eq!(subs.last().map(String::as_str), Some("X"));
        let mut out = Vec::new();
        app.on_startup(0.0, &mut out).unwrap();
        let req = crate::testing::mail(
            "APPCAST_REQ",
            Value::text("node=abe,app=all,duration=3,key=k,thresh=any"),
            1.0,
            "uMAC",
        );
        let x = crate::testing::mail("X", Value::Double(7.0), 1.0, "pOther");
        app.on_mail(&[req, x], 1.0, &mut out).unwrap();
        assert_eq!(app.core().mail, 1, "the request is the layer's");
        app.iterate(1.25, &mut out).unwrap();
        let keys: Vec<&str> = out.iter().map(|p| &*p.key).collect();
        assert_eq!(keys, ["SEEN", "ITER", "APPCAST"]);
        let cast = appcast::AppCast::parse(out[2].value.as_str().unwrap());
        assert!(
            cast.messages().contains("mail=1 iter=1 at 1.25"),
            "{}",
            cast.messages()
        );
        assert!(cast.run_warnings().keys().any(|w| w.contains("counting")));
        assert!(cast.events().any(|e| e.contains("mail 1")));
        app.core_mut().mail = 5;
        assert_eq!(app.core().mail, 5);
    }
}
