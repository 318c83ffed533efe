//! The vehicle crate's simulator (uSimMarineV22), marine PID (pMarinePIDV22) and node
//! reporter (pNodeReporter) as [`App`]s, each configured from its `ProcessConfig` block.

use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::ProcessConfig;
use mission::source::Span;
use thiserror::Error;
use vehicle::geodesy::LocalGrid;
use vehicle::node_report::{NodeReportConfig, NodeReporter};
use vehicle::pid::{MarinePid, PidConfig};
use vehicle::sim::{SimConfig, Simulator};
use vehicle::{ConfigError, Posting};

use crate::antler::BuiltInApp;
use crate::app::{App, Mail, Post, Subscription, Value};
use crate::appcasting::AppcastLayer;

/// A vehicle app's block that cannot be used, with where it is.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{file}:{line}: {error}")]
pub struct VehicleAppError {
    /// File of the offending line (or of the block).
    pub file: String,
    /// Line of the offending parameter (or of the `ProcessConfig` line).
    pub line: u32,
    /// What is wrong.
    pub error: ConfigError,
}

/// Where a configuration error points: the parameter's line, else the block's.
fn span_of<'a>(block: &'a ProcessConfig, error: &ConfigError) -> &'a Span {
    let key = match error {
        ConfigError::UnknownKey { key, .. } | ConfigError::BadValue { key, .. } => {
            Some(key.as_str())
        }
        ConfigError::Missing { .. } => None,
    };
    let param = key.and_then(|k| {
        block
            .entries
            .iter()
            .find(|p| p.key.trim().eq_ignore_ascii_case(k.trim()))
    });
    param.map_or(&block.span, |p| &p.span)
}

fn located(block: &ProcessConfig, error: ConfigError) -> VehicleAppError {
    let span = span_of(block, &error);
    VehicleAppError {
        file: span.file_name().to_string(),
        line: span.line,
        error,
    }
}

fn params(block: &ProcessConfig) -> impl Iterator<Item = (&str, &str)> {
    block
        .entries
        .iter()
        .map(|p| (p.key.as_str(), p.value.as_str()))
}

/// The configuration problems of an app's `block` as warnings, each at its parameter's line
/// (else the block's): the vehicle apps', the drivers', uSimSensors' and the CoUGARs apps'.
pub(crate) fn config_warnings(block: &ProcessConfig, problems: &[ConfigError]) -> Vec<Diagnostic> {
    problems
        .iter()
        .map(|e| {
            Diagnostic::line_warning(DiagnosticKind::AppSetting, span_of(block, e), e.to_string())
        })
        .collect()
}

enum Inner {
    Sim(Box<Simulator>),
    Pid(Box<MarinePid>),
    Reporter(Box<NodeReporter>),
}

/// One of the vehicle apps behind the [`App`] trait.
pub struct VehicleApp {
    name: String,
    block: ProcessConfig,
    /// The block's AppTick, read once.
    tick: f64,
    inner: Inner,
    subs: Vec<Subscription>,
    postings: Vec<Posting>,
    warnings: Vec<Diagnostic>,
    startup_failure: Option<String>,
    /// AppCastingMOOSApp around the app.
    appcast: AppcastLayer,
}

impl BuiltInApp for VehicleApp {
    /// Sets the mission's `Community` and `MOOSTimeWarp` for the app's appcasts (the node
    /// name, the real-time rate limit); the block's appcasting keys are read again with
    /// them.
    fn with_appcast_globals(mut self, community: Option<&str>, warp: f64) -> Self {
        self.appcast = AppcastLayer::with_config_warnings(
            &self.name,
            &self.block,
            community,
            warp,
            &self.warnings,
        );
        if let Inner::Reporter(r) = &mut self.inner {
            r.set_term_report_interval(self.appcast.term_report_interval());
        }
        self
    }

    /// Unknown or unusable parameters of the block (`file:line: warning: app: unknown
    /// parameter ...`), which the C++ apps also only warn about.
    fn warnings(&self) -> &[Diagnostic] {
        &self.warnings
    }
}

impl VehicleApp {
    fn new(
        name: &str,
        block: ProcessConfig,
        inner: Inner,
        subs: Vec<&str>,
        warnings: Vec<Diagnostic>,
    ) -> Self {
        let appcast = AppcastLayer::with_config_warnings(name, &block, None, 1.0, &warnings);
        VehicleApp {
            name: name.to_string(),
            tick: crate::app::app_tick_of(Some(&block)),
            block,
            inner,
            subs: AppcastLayer::subscriptions()
                .chain(subs.into_iter().map(Subscription::var))
                .collect(),
            postings: Vec::with_capacity(32),
            warnings,
            startup_failure: None,
            appcast,
        }
    }

    /// uSimMarineV22 (`legacy` false) or the older uSimMarine (`legacy` true) from its
    /// block; `grid` from the mission's LatOrigin/LongOrigin adds NAV_LAT/NAV_LONG;
    /// `start` is the MOOS start time.
    pub fn simulator(
        name: &str,
        block: ProcessConfig,
        grid: Option<LocalGrid>,
        start: f64,
        legacy: bool,
    ) -> Result<Self, VehicleAppError> {
        let (mut cfg, unknown) =
            SimConfig::from_params_lenient(params(&block)).map_err(|e| located(&block, e))?;
        cfg.legacy = legacy;
        let w = config_warnings(&block, &unknown);
        let sim = Simulator::new(cfg, grid, start);
        let subs = sim.subscriptions();
        Ok(VehicleApp::new(
            name,
            block,
            Inner::Sim(Box::new(sim)),
            subs,
            w,
        ))
    }

    /// pMarinePIDV22 (`legacy` false) or the older pMarinePID (`legacy` true) from its block.
    /// Configuration problems are warnings ([`VehicleApp::warnings`]); the app runs, as the
    /// C++ apps do.
    pub fn marine_pid(
        name: &str,
        block: ProcessConfig,
        legacy: bool,
    ) -> Result<Self, VehicleAppError> {
        let (mut cfg, unknown) =
            PidConfig::from_params_lenient(params(&block)).map_err(|e| located(&block, e))?;
        cfg.legacy = legacy;
        // The older pMarinePID ends at start-up ("Improper PID Settings") when a required
        // gain or limit is missing; pMarinePIDV22 only reports it and runs on.
        let missing: Vec<&str> = unknown
            .iter()
            .filter_map(|e| match e {
                ConfigError::Missing { key, .. } => Some(*key),
                _ => None,
            })
            .collect();
        let failure = (legacy && !missing.is_empty()).then(|| {
            format!(
                "Improper PID Settings ({} missing): pMarinePID ends at start-up",
                missing.join(", ")
            )
        });
        let w = config_warnings(&block, &unknown);
        let pid = MarinePid::new(cfg);
        let subs = pid.subscriptions();
        let mut app = VehicleApp::new(name, block, Inner::Pid(Box::new(pid)), subs, w);
        app.startup_failure = failure;
        Ok(app)
    }

    /// pNodeReporter from its block, reporting as vehicle `community`; `grid` (the mission's
    /// origin) serves the cross-fill policies; `seed` seeds the blackout draws.
    pub fn node_reporter(
        name: &str,
        block: ProcessConfig,
        community: &str,
        start: f64,
        grid: Option<LocalGrid>,
        seed: u64,
    ) -> Result<Self, VehicleAppError> {
        let (cfg, unknown) = NodeReportConfig::from_params_lenient(params(&block))
            .map_err(|e| located(&block, e))?;
        let w = config_warnings(&block, &unknown);
        let rep = NodeReporter::new(cfg, community, start)
            .with_grid(grid)
            .with_seed(seed);
        let extra = rep.extra_subscriptions();
        let mut subs = NodeReporter::subscriptions().to_vec();
        subs.extend(extra.iter().map(String::as_str));
        Ok(VehicleApp::new(
            name,
            block,
            Inner::Reporter(Box::new(rep)),
            subs,
            w,
        ))
    }

    fn flush(&mut self, out: &mut Vec<Post>) {
        out.append(&mut self.postings);
    }
}

impl App for VehicleApp {
    fn name(&self) -> &str {
        &self.name
    }

    fn startup_failure(&self) -> Option<String> {
        self.startup_failure.clone()
    }

    fn set_process_id(&mut self, pid: u32) {
        if let Inner::Reporter(r) = &mut self.inner {
            r.set_pid(pid);
        }
    }

    fn process_config(&self) -> Option<&ProcessConfig> {
        Some(&self.block)
    }

    fn app_tick(&self) -> f64 {
        self.tick
    }

    fn on_startup(&mut self, now: f64, out: &mut Vec<Post>) -> crate::app::AppResult {
        self.appcast.on_startup(now);
        if let Inner::Pid(p) = &mut self.inner {
            p.set_start_time(now);
        }
        // pNodeReporter posts PNODEREPORTER_PID in OnStartUp (single-app mode only).
        if let Inner::Reporter(r) = &mut self.inner {
            r.on_startup(&mut self.postings);
        }
        self.flush(out);
        Ok(())
    }

    fn subscriptions(&self) -> Vec<Subscription> {
        self.subs.clone()
    }

    fn on_mail(&mut self, mail: &[Mail], now: f64, out: &mut Vec<Post>) -> crate::app::AppResult {
        for m in mail {
            // AppCastingMOOSApp takes its own mail first.
            if !self.appcast.take_mail(m) {
                continue;
            }
            // The vehicle apps read no binary data.
            if matches!(m.value, Value::Binary(_)) {
                continue;
            }
            let v = m.value.as_ref();
            match &mut self.inner {
                // The simulator handles mail at the app's time (MOOSTime() in the C++), and
                // needs the writer to tell drift sources apart.
                Inner::Sim(s) => {
                    if let Some(p) = s.on_mail_from(&m.key, v, now, &m.source) {
                        self.postings.push(p);
                    }
                }
                Inner::Pid(p) => p.on_mail(&m.key, v, m.time),
                // pNodeReporter too stamps mail with its own time (m_curr_time, set to
                // MOOSTime() in OnNewMail), not the poster's.
                Inner::Reporter(r) => r.on_mail(&m.key, v, now),
            }
        }
        self.flush(out);
        Ok(())
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> crate::app::AppResult {
        let tick = self.app_tick();
        self.appcast.begin(now, tick, out);
        match &mut self.inner {
            Inner::Sim(s) => s.iterate(now, &mut self.postings),
            Inner::Pid(p) => p.iterate(now, &mut self.postings),
            Inner::Reporter(r) => {
                r.set_term_report_interval(self.appcast.term_report_interval());
                r.iterate(now, &mut self.postings);
                for note in r.take_appcast_notes() {
                    self.appcast.note(note, now);
                }
            }
        }
        self.flush(out);
        // PostReport: each app's report body, as its C++ buildReport writes it.
        let inner = &self.inner;
        self.appcast.end(now, tick, out, |body| match inner {
            Inner::Sim(s) => s.appcast_body(now, body),
            Inner::Pid(p) => p.appcast_body(now, body),
            Inner::Reporter(r) => r.appcast_body(now, body),
        });
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn block(text: &str) -> ProcessConfig {
        crate::testing::block("v.moos", text)
    }

    fn mail(key: &str, value: Value, time: f64) -> Mail {
        crate::testing::mail(key, value, time, "uMAC")
    }

    fn appcast_of(out: &[Post]) -> Option<appcast::AppCast> {
        out.iter()
            .find(|p| p.key == "APPCAST")
            .map(|p| appcast::AppCast::parse(p.value.as_str().unwrap()))
    }

    #[test]
    fn vehicle_apps_appcast_their_reports_on_request() {
        let b = block(
            "ProcessConfig = pMarinePIDV22\n{\n  AppTick = 4\n  yaw_pid_kp = 1.2\n  \
             yaw_pid_kd = 0\n  yaw_pid_ki = 0\n  yaw_pid_integral_limit = 0\n  \
             speed_pid_kp = 1\n  speed_pid_kd = 0\n  speed_pid_ki = 0\n  \
             speed_pid_integral_limit = 0\n  maxrudder = 100\n  maxthrust = 100\n  \
             term_report_interval = 0.4\n}\n",
        );
        let mut app = VehicleApp::marine_pid("pMarinePIDV22", b, false)
            .unwrap()
            .with_appcast_globals(Some("abe"), 1.0);
        assert!(
            app.subscriptions()
                .iter()
                .any(|s| s.pattern == "APPCAST_REQ")
        );
        let mut out = Vec::new();
        app.on_startup(0.0, &mut out).unwrap();
        // The first iteration always reports.
        app.iterate(0.25, &mut out).unwrap();
        let first = appcast_of(&out).expect("an appcast at iteration 1");
        assert_eq!(first.proc_name(), "pMarinePIDV22");
        assert_eq!(first.node_name(), "abe");
        out.clear();
        app.iterate(0.5, &mut out).unwrap();
        assert!(appcast_of(&out).is_none(), "nobody asked");
        let req = "node=abe,app=all,duration=3,key=uMAC_7,thresh=any";
        app.on_mail(&[mail("APPCAST_REQ", Value::text(req), 0.6)], 0.6, &mut out)
            .unwrap();
        app.iterate(0.75, &mut out).unwrap();
        let cast = appcast_of(&out).expect("an appcast on request");
        assert_eq!(cast.iteration(), 3);
        assert!(
            cast.messages().contains("PID has_control: false"),
            "{}",
            cast.messages()
        );
        // The request was the layer's: the PID never saw it.
        assert!(!out.iter().any(|p| p.key == "APPCAST_REQ"));
    }

    #[test]
    fn the_simulator_appcasts_on_request() {
        let b =
            block("ProcessConfig = uSimMarineV22\n{\n  AppTick = 4\n  start_pos = x=10,y=-5\n}\n");
        let mut app = VehicleApp::simulator("uSimMarineV22", b, None, 0.0, false)
            .unwrap()
            .with_appcast_globals(Some("abe"), 1.0);
        let mut out = Vec::new();
        app.on_startup(0.0, &mut out).unwrap();
        for k in 1..=3 {
            app.iterate(f64::from(k) * 0.25, &mut out).unwrap();
        }
        out.clear();
        let req = "node=all,app=uSimMarineV22,duration=3,key=uMAC_7,thresh=any";
        app.on_mail(&[mail("APPCAST_REQ", Value::text(req), 0.8)], 0.8, &mut out)
            .unwrap();
        app.iterate(1.0, &mut out).unwrap();
        let cast = appcast_of(&out).expect("an appcast on request");
        assert_eq!(cast.proc_name(), "uSimMarineV22");
        assert_eq!(cast.node_name(), "abe");
        assert!(!cast.messages().is_empty());
    }

    #[test]
    fn a_node_reporter_without_navigation_warns_in_its_appcast() {
        let b = block(
            "ProcessConfig = pNodeReporter\n{\n  AppTick = 4\n  platform_type = kayak\n  nav_grace_period = 5\n}\n",
        );
        let mut app = VehicleApp::node_reporter("pNodeReporter", b, "abe", 0.0, None, 1)
            .unwrap()
            .with_appcast_globals(Some("abe"), 1.0);
        let mut out = Vec::new();
        app.on_startup(0.0, &mut out).unwrap();
        let req = "node=abe,app=pNodeReporter,duration=30,key=k,thresh=any";
        app.on_mail(&[mail("APPCAST_REQ", Value::text(req), 0.0)], 0.0, &mut out)
            .unwrap();
        let mut warned = None;
        for k in 1..=40 {
            out.clear();
            app.iterate(f64::from(k) * 0.25, &mut out).unwrap();
            if let Some(c) = appcast_of(&out)
                && c.run_warning_total() > 0
            {
                warned = Some(c);
                break;
            }
        }
        let c = warned.expect("a run warning once the nav grace period is over");
        assert!(
            c.run_warnings()
                .keys()
                .any(|w| w.contains("Waiting for NAV_X/Y")),
            "{:?}",
            c.run_warnings()
        );
    }
}
