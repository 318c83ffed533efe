//! The vehicle crate's simulator (uSimMarineV22), marine PID (pMarinePIDV22) and node
//! reporter (pNodeReporter) as [`App`]s, each configured from its `ProcessConfig` block.

use mission::moos::ProcessConfig;
use thiserror::Error;
use vehicle::geodesy::LocalGrid;
use vehicle::node_report::{NodeReportConfig, NodeReporter};
use vehicle::pid::{MarinePid, PidConfig};
use vehicle::sim::{SimConfig, Simulator};
use vehicle::{ConfigError, MailValue, Posting};

use crate::app::{App, Mail, Post, Subscription, Value};

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

fn located(block: &ProcessConfig, error: ConfigError) -> VehicleAppError {
    let key = match &error {
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
    let span = param.map_or(&block.span, |p| &p.span);
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

fn warnings(block: &ProcessConfig, unknown: Vec<ConfigError>) -> Vec<String> {
    unknown
        .into_iter()
        .map(|e| located(block, e).to_string())
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
    inner: Inner,
    subs: Vec<Subscription>,
    postings: Vec<Posting>,
    warnings: Vec<String>,
    startup_failure: Option<String>,
}

impl VehicleApp {
    fn new(
        name: &str,
        block: ProcessConfig,
        inner: Inner,
        subs: Vec<&str>,
        warnings: Vec<String>,
    ) -> Self {
        VehicleApp {
            name: name.to_string(),
            block,
            inner,
            subs: subs.into_iter().map(Subscription::var).collect(),
            postings: Vec::with_capacity(32),
            warnings,
            startup_failure: None,
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
        let w = warnings(&block, unknown);
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
        let w = warnings(&block, unknown);
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
        let w = warnings(&block, unknown);
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

    /// Unknown parameters of the block (`file:line: app: unknown parameter ...`), which
    /// the C++ apps also only warn about.
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    fn flush(&mut self, out: &mut Vec<Post>) {
        out.extend(self.postings.drain(..).map(|p| {
            let value = match p.value {
                vehicle::Value::Double(x) => Value::Double(x),
                vehicle::Value::Str(s) => Value::String(s),
            };
            Post::new(p.var.as_ref(), value)
        }));
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

    fn on_startup(&mut self, _now: f64, out: &mut Vec<Post>) {
        // pNodeReporter posts PNODEREPORTER_PID in OnStartUp (single-app mode only).
        if let Inner::Reporter(r) = &mut self.inner {
            r.on_startup(&mut self.postings);
        }
        self.flush(out);
    }

    fn subscriptions(&self) -> Vec<Subscription> {
        self.subs.clone()
    }

    fn on_mail(&mut self, mail: &[Mail], now: f64, out: &mut Vec<Post>) {
        for m in mail {
            let v = match &m.value {
                Value::Double(x) => MailValue::Double(*x),
                Value::String(s) => MailValue::Str(s),
                Value::Binary(_) => continue,
            };
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
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) {
        match &mut self.inner {
            Inner::Sim(s) => s.iterate(now, &mut self.postings),
            Inner::Pid(p) => p.iterate(now, &mut self.postings),
            Inner::Reporter(r) => r.iterate(now, &mut self.postings),
        }
        self.flush(out);
    }
}
