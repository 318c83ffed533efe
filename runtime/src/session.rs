//! A whole mission run as a library: what `coug run` does, callable in process.
//!
//! [`load`] preprocesses and parses a `.moos` file and each helm's behaviour files;
//! [`validate`] finds what the run would warn about or refuse; [`run`] plans the ANTLER
//! apps (every built-in from [`crate::antler::BUILT_INS`], the helm among them), opens the
//! pLogger session on disk and runs the apps in lockstep on the virtual clock or in real
//! time on a TCP MOOSDB, until the `until` condition holds, the time runs out, every app
//! finishes or the caller asks it to stop. It returns a [`RunReport`]: how the run ended,
//! the `until` values, the alog's path and the totals read back from it.
//!
//! Printing, Ctrl-C and exit codes are the caller's: an [`Observer`] is told the run's
//! warnings and notices, every `IVPHELM_SUMMARY` and, about once per simulated second (or
//! every 50 ms of wall time in real time), the DB's current values; its
//! [`Observer::stop_requested`] ends the run cleanly (log flushed and closed).

use std::collections::HashMap;
use std::fmt;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::time::{Duration, Instant};

use chrono::NaiveDateTime;
use mission::Parsed;
use mission::bhv::BehaviorFile;
use mission::buttons::{self, ButtonValue};
use mission::condition::{Condition, parse_condition};
use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::{AntlerRun, MissionFile, override_globals, parse_moos};
use mission::nsplug::{Options, preprocess};
use mission::source::FsSource;
use moosdb::time::Warp;
use moosdb::{Server, ServerConfig};
use thiserror::Error;

use crate::antler::{HelmFiles, LaunchError, LogTarget, MissionGlobals, Plan, logger_config, plan};
use crate::app::{AppError, Value};
use crate::bus::Bus;
use crate::bus::BusError;
use crate::clock::VirtualClock;
use crate::helm::load_behaviors;
use crate::logger::{LateSink, SideFiles};
use crate::realtime::{RunSpec, run_apps};
use crate::remote::{RemoteConfig, RemoteError};
use crate::scheduler::{Outcome, Poke, PokeAt, RunError, Scheduler};
use crate::summary::{RunSummary, behaviour_list};

/// MOOS time at which every lockstep run starts (so two runs log the same bytes).
pub const LOCKSTEP_START: f64 = 1_786_000_000.0;

/// The banner's `FILE OPENED ON` text (pLogger 2024 prints the Unix epoch there).
pub const OPENED_ON: &str = "Thu Jan  1 00:00:00 1970";

/// A mission loaded and checked: the expanded `.moos`, its text, and each helm's behaviours.
pub struct LoadedMission {
    /// The mission file as given.
    pub path: PathBuf,
    /// The expanded, parsed mission.
    pub mission: MissionFile,
    /// The expanded mission text (written for external apps when it differs).
    pub text: String,
    /// Each helm's behaviour file by the helm's MOOS name, or why it cannot be used (the
    /// helm then runs in MALCONFIG).
    pub behaviors: HashMap<String, Result<Parsed<BehaviorFile>, Vec<String>>>,
    /// True when macros changed the text (external apps then get an expanded copy).
    pub expanded: bool,
    /// The mission file's folder (relative paths in the mission are read from there).
    pub dir: PathBuf,
    /// The reader's and nsplug's warnings (an unexpanded `$(X)` is left to the apps).
    pub warnings: Vec<Diagnostic>,
    /// How the files were preprocessed (a helm's RESTART_HELM reads them again so).
    pub opts: Options,
}

/// Why a mission cannot be loaded.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum LoadError {
    /// Errors in the mission's files (`file:line: ...` each).
    #[error("{}", join_lines(.0))]
    Files(Vec<Diagnostic>),
    /// The file is not a MOOS mission.
    #[error(
        "{}: not a MOOS mission file (no ServerHost, ServerPort, Community or ProcessConfig)",
        .0.display()
    )]
    NotAMission(PathBuf),
}

impl LoadError {
    /// One message per finding.
    pub fn messages(&self) -> Vec<String> {
        match self {
            LoadError::Files(d) => d.iter().map(ToString::to_string).collect(),
            e => vec![e.to_string()],
        }
    }
}

fn join_lines<T: fmt::Display>(items: &[T]) -> String {
    items
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join("\n")
}

/// The program's base name (`/usr/bin/pHelmIvP` → `pHelmIvP`).
fn base(app: &str) -> &str {
    app.rsplit('/').next().unwrap_or(app)
}

/// Preprocesses `path` with the nsplug `macros` (`NAME=VALUE`) and `include_paths`, parses
/// it and each helm's behaviour files.
pub fn load(
    path: &Path,
    macros: &[String],
    include_paths: &[PathBuf],
) -> Result<LoadedMission, LoadError> {
    let mut opts = Options::new();
    opts.include_paths = include_paths.to_vec();
    for m in macros {
        opts.define_arg(m);
    }
    let pre = preprocess(&FsSource, path, &opts).map_err(|d| LoadError::Files(vec![d]))?;
    let text = pre.source.text();
    let original = std::fs::read_to_string(path).unwrap_or_default();
    let parsed = parse_moos(&pre.source);
    let mut errors = Vec::new();
    let mut warnings = Vec::new();
    for d in pre.diagnostics.into_iter().chain(parsed.diagnostics) {
        if d.is_error() {
            errors.push(d);
        } else if d.kind != DiagnosticKind::UndefinedMacro {
            // `$(X)` left for the apps (uTimerScript's `$(COUNT)`, behaviour flags' `$(X)`)
            // is normal in a mission; `coug check` lists them.
            warnings.push(d);
        }
    }
    let mission = parsed.value;
    if !mission::is_mission(&mission) {
        return Err(LoadError::NotAMission(path.to_path_buf()));
    }
    if !errors.is_empty() {
        return Err(LoadError::Files(errors));
    }
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let mut behaviors = HashMap::new();
    for run in mission.antler_runs() {
        if base(&run.app) != "pHelmIvP" {
            continue;
        }
        let name = run.moos_name().to_string();
        let bhv = load_behaviors(&mission, &dir, &name, &opts, &FsSource);
        behaviors.insert(name, bhv);
    }
    let expanded = text.trim_end() != original.trim_end();
    Ok(LoadedMission {
        path: path.to_path_buf(),
        mission,
        text,
        behaviors,
        expanded,
        dir,
        warnings,
        opts,
    })
}

impl LoadedMission {
    /// Where the helms read their behaviours: the files already read, the mission's folder
    /// and the nsplug options.
    pub fn helm_files(&self) -> HelmFiles {
        HelmFiles {
            dir: self.dir.clone(),
            opts: self.opts.clone(),
            loaded: self.behaviors.clone(),
        }
    }

    /// The MOOS name of the first helm of the ANTLER block (`pHelmIvP` when there is none):
    /// the app whose first iteration releases the run's pokes.
    pub fn first_helm(&self) -> String {
        self.mission
            .antler_runs()
            .into_iter()
            .find(|r| base(&r.app) == "pHelmIvP")
            .map_or_else(|| "pHelmIvP".to_string(), |r| r.moos_name().to_string())
    }

    /// Plans the ANTLER apps starting at MOOS time `start` with `seed`, logging to `log`.
    pub fn plan(&self, start: f64, seed: u64, log: Option<LogTarget>) -> Result<Plan, LaunchError> {
        let mut launch = crate::antler::Launch::new(start, seed).with_helm_files(self.helm_files());
        launch.log = log;
        plan(&self.mission, launch, &mut |_, _| None)
    }
}

/// What a run finds wrong with a loaded mission before running it, and `coug check`
/// reports: one path for both.
#[derive(Debug, Default)]
pub struct Validation {
    /// Findings that do not stop the run, each at its line.
    pub warnings: Vec<Diagnostic>,
    /// Each helm that would run in MALCONFIG (never driving), with why.
    pub malconfig: Vec<(String, Vec<String>)>,
    /// Apps that would end at start-up (the run goes on without them), with why.
    pub failed: Vec<String>,
    /// Why the run cannot start at all.
    pub errors: Vec<String>,
}

/// Validates a loaded mission as [`run`] would start it: the reader's warnings, the apps'
/// configuration warnings, apps that would be in MALCONFIG, built-in apps without a
/// ProcessConfig block, and AppTick/CommsTick values MOOS cannot read.
pub fn validate(loaded: &LoadedMission) -> Validation {
    let mut v = Validation {
        warnings: loaded.warnings.clone(),
        ..Validation::default()
    };
    let m = &loaded.mission;
    for block in &m.processes {
        for key in ["AppTick", "CommsTick"] {
            if let Some(p) = block
                .entries
                .iter()
                .find(|p| p.key.eq_ignore_ascii_case(key))
                && p.value.trim().parse::<f64>().is_err()
            {
                v.warnings.push(Diagnostic::line_warning(
                    DiagnosticKind::AppSetting,
                    &p.span,
                    format!(
                        "{}: {} = {}: not a number; MOOS cannot read it and keeps its default",
                        block.name, p.key, p.value
                    ),
                ));
            }
        }
    }
    for run in m.antler_runs() {
        let name = run.moos_name();
        if crate::antler::built_in(&run.app).is_some_and(|b| b.reads_block)
            && m.process(name).is_none()
        {
            v.warnings.push(Diagnostic::line_warning(
                DiagnosticKind::NoConfigBlock,
                &run.span,
                format!(
                    "{} runs with no `ProcessConfig = {name}` block: every setting at its default",
                    run.app
                ),
            ));
        }
    }
    // Planned as the run plans it, with a log that goes nowhere (nothing touches the disk).
    let log = LogTarget {
        config: logger_config(m),
        writer: Box::new(std::io::sink()),
        opened: NaiveDateTime::default(),
        opened_on: OPENED_ON.into(),
        side: None,
    };
    match loaded.plan(0.0, 0, Some(log)) {
        Ok(p) => {
            v.warnings.extend(p.warnings);
            v.failed = p.failed;
            for app in &p.apps {
                let reasons = app.malconfig();
                if !reasons.is_empty() {
                    v.malconfig.push((app.name().to_string(), reasons));
                }
            }
        }
        // A file without an ANTLER block is not a mission a run can start (it says so when
        // asked to), but it is a good MOOS file for apps started by hand.
        Err(LaunchError::NoAntler) => {}
        Err(e) => v.errors.push(e.to_string()),
    }
    v
}

/// How the apps run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mode {
    /// Every app and the bus in one thread on a virtual clock: deterministic, as fast as the
    /// CPU allows, starting at [`LOCKSTEP_START`].
    Lockstep,
    /// Real time times a warp, the MOOSDB on TCP so real MOOS apps can join; ANTLER apps
    /// coug does not build in are started from PATH.
    RealTime {
        /// The speed-up (default: the mission's MOOSTimeWarp).
        warp: Option<f64>,
        /// The MOOSDB port (default: the mission's ServerPort; 0 picks a free one).
        port: Option<u16>,
    },
}

/// What a run does besides running the mission's apps.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Lockstep or real time.
    pub mode: Mode,
    /// Values to post (`VAR=VALUE`, `VAR:=VALUE`, `VAR=VALUE@T`), after the first helm's
    /// first iteration unless timed.
    pub pokes: Vec<String>,
    /// Press the mission's DEPLOY button, or post DEPLOY=true and
    /// MOOS_MANUAL_OVERRIDE=false when it has none.
    pub deploy: bool,
    /// pMarineViewer buttons to press (by label or key), in order.
    pub buttons: Vec<String>,
    /// End the run when this condition (.bhv syntax) holds.
    pub until: Option<String>,
    /// End the run after this many simulated seconds.
    pub max_time: f64,
    /// The folder pLogger's session folder goes in (default: the mission's GlobalLogPath,
    /// else the pLogger block's PATH, else the current directory, as pLogger).
    pub log_dir: Option<PathBuf>,
    /// Seed of every random draw.
    pub seed: u64,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            mode: Mode::Lockstep,
            pokes: Vec::new(),
            deploy: false,
            buttons: Vec::new(),
            until: None,
            max_time: 3600.0,
            log_dir: None,
            seed: 1,
        }
    }
}

/// What the caller is told during a run (all methods do nothing by default).
pub trait Observer {
    /// A finding that does not stop the run (the caller prints it).
    fn warning(&mut self, _text: &str) {}

    /// Something the run did (the MOOSDB listening, an external app started).
    fn notice(&mut self, _text: &str) {}

    /// One `IVPHELM_SUMMARY` posting.
    fn helm_summary(&mut self, _summary: &str) {}

    /// The run is at `sim_s` simulated seconds; `current` reads the DB's current values.
    fn step(&mut self, _sim_s: f64, _current: &dyn Fn(&str) -> Option<Value>) {}

    /// True to end the run now (Ctrl-C): the log is flushed and closed.
    fn stop_requested(&self) -> bool {
        false
    }
}

/// An observer that ignores everything (tests, batch runs).
#[derive(Debug, Default, Clone, Copy)]
pub struct Quiet;

impl Observer for Quiet {}

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Ended {
    /// The scheduler's outcome (condition met, max time, every app finished).
    Outcome(Outcome),
    /// The caller asked it to stop ([`Observer::stop_requested`]) at MOOS time `time`.
    Interrupted {
        /// MOOS time of the stop.
        time: f64,
    },
}

/// Totals read back from a run's alog.
#[derive(Debug, Clone, PartialEq)]
pub struct LogTotals {
    /// Distance, position and the helm's last state (see [`RunSummary`]).
    pub summary: RunSummary,
    /// Every behaviour that completed during the run, in order of completion.
    pub completed: Vec<String>,
    /// Each `IVPHELM_CONFIG_WARNING` posted (why a helm was in MALCONFIG).
    pub malconfig: Vec<String>,
}

impl LogTotals {
    /// The totals of a parsed alog.
    pub fn from_alog(log: &alog::Alog) -> LogTotals {
        // Every behaviour that completed during the run (the helm's later reports may drop
        // it, e.g. once the mission is no longer active).
        let mut completed: Vec<String> = Vec::new();
        let mut malconfig = Vec::new();
        for e in &log.entries {
            match e.var.as_str() {
                "IVPHELM_SUMMARY" => {
                    let list = e
                        .value
                        .as_str()
                        .and_then(|v| behaviour_list(v, "completed_bhvs"));
                    for b in list.unwrap_or_default() {
                        if !completed.contains(&b) {
                            completed.push(b);
                        }
                    }
                }
                "IVPHELM_CONFIG_WARNING" => {
                    if let Some(why) = e.value.as_str() {
                        malconfig.push(why.to_string());
                    }
                }
                _ => {}
            }
        }
        LogTotals {
            summary: RunSummary::from_alog(log),
            completed,
            malconfig,
        }
    }
}

/// What a run did: how it ended, its times, the `until` values and its log.
#[derive(Debug, Clone)]
pub struct RunReport {
    /// The mission file.
    pub mission: PathBuf,
    /// How it ended.
    pub ended: Ended,
    /// The `until` condition as given.
    pub until: Option<String>,
    /// The max time as given (simulated seconds).
    pub max_time: f64,
    /// MOOS time of the start.
    pub start: f64,
    /// Wall-clock seconds the run took.
    pub wall_s: f64,
    /// The `until` condition's variables and their last values.
    pub until_values: Vec<(String, Option<Value>)>,
    /// The alog written.
    pub alog: String,
    /// The alog's totals (`None` when it could not be read back).
    pub totals: Option<LogTotals>,
}

impl RunReport {
    /// MOOS time at the end.
    pub fn end_time(&self) -> f64 {
        match self.ended {
            Ended::Outcome(
                Outcome::ConditionMet { time }
                | Outcome::MaxTime { time }
                | Outcome::AllFinished { time },
            )
            | Ended::Interrupted { time } => time,
        }
    }

    /// Simulated seconds from start to end.
    pub fn sim_s(&self) -> f64 {
        self.end_time() - self.start
    }

    /// True when an `until` condition was given and did not hold by the end.
    pub fn until_pending(&self) -> bool {
        self.until.is_some() && !matches!(self.ended, Ended::Outcome(Outcome::ConditionMet { .. }))
    }

    /// `VAR = value` of each `until` variable, as the closing lines show them.
    pub fn until_text(&self) -> Vec<String> {
        self.until_values
            .iter()
            .map(|(k, v)| format!("{k} = {}", fmt_value(v)))
            .collect()
    }
}

fn fmt_value(v: &Option<Value>) -> String {
    match v {
        None => "(never posted)".into(),
        Some(Value::Double(x)) => format!("{x}"),
        Some(Value::String(s)) => format!("\"{s}\""),
        Some(Value::Binary(b)) => format!("({} bytes)", b.len()),
    }
}

impl fmt::Display for RunReport {
    /// The closing summary `coug run` prints: how it ended, times, distance, depth,
    /// completed behaviours, helm state, the `until` values and the log.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "coug run: {}", self.mission.display())?;
        let how = match self.ended {
            Ended::Outcome(Outcome::ConditionMet { .. }) => format!(
                "until condition met ({})",
                self.until.as_deref().unwrap_or("")
            ),
            Ended::Outcome(Outcome::MaxTime { .. }) => {
                format!("max time {} s reached", self.max_time)
            }
            Ended::Outcome(Outcome::AllFinished { .. }) => "every app finished".into(),
            Ended::Interrupted { .. } => "interrupted".into(),
        };
        writeln!(f, "  ended:       {how}")?;
        let sim = self.sim_s();
        writeln!(
            f,
            "  simulated:   {sim:.1} s   wall: {:.3} s   speed-up: {:.0}x",
            self.wall_s,
            sim / self.wall_s.max(1e-9)
        )?;
        match &self.totals {
            Some(t) => {
                let s = &t.summary;
                writeln!(f, "  distance:    {:.1} m", s.distance)?;
                if s.max_depth > 0.0 {
                    writeln!(f, "  max depth:   {:.2} m", s.max_depth)?;
                }
                if let Some((x, y)) = s.final_position {
                    writeln!(f, "  final x,y:   {x:.1}, {y:.1}")?;
                }
                let done = if t.completed.is_empty() {
                    "none".to_string()
                } else {
                    t.completed.join(", ")
                };
                writeln!(f, "  completed:   {done}")?;
                if let Some(h) = &s.helm_state {
                    writeln!(f, "  helm state:  {h}")?;
                }
                for why in &t.malconfig {
                    writeln!(f, "  malconfig:   {why}")?;
                }
            }
            None => writeln!(f, "  (the log could not be read back for totals)")?,
        }
        for line in self.until_text() {
            writeln!(f, "  {line}")?;
        }
        writeln!(f, "  log:         {}", self.alog)
    }
}

/// Why a run could not start or did not complete.
#[derive(Debug, Error)]
pub enum SessionError {
    /// The mission's files cannot be used.
    #[error(transparent)]
    Load(#[from] LoadError),
    /// The run's options cannot be used (`--until`, `--poke`, `--button`, `--warp`,
    /// `--max-time`), or the mission cannot start (the plan's errors).
    #[error("{0}")]
    Invalid(String),
    /// The log session could not be created.
    #[error("{0}")]
    LogOpen(String),
    /// The log could not be written (a full or read-only disk): the run failed.
    #[error("{}the log {alog} could not be written: {source}", app.as_deref().map(|a| format!("{a}: ")).unwrap_or_default())]
    LogWrite {
        /// The app that was writing (pLogger's MOOS name), when known.
        app: Option<String>,
        /// The alog's path on disk.
        alog: String,
        /// The write error.
        source: std::io::Error,
    },
    /// The in-process bus refused a client or a registration (lockstep).
    #[error(transparent)]
    Bus(#[from] BusError),
    /// A client of the TCP MOOSDB failed (real time).
    #[error(transparent)]
    Remote(RemoteError),
    /// The MOOSDB could not listen, its host could not be resolved, or the async runtime
    /// could not start (real time).
    #[error("{0}")]
    Net(String),
}

fn app_failed(e: AppError, alog: &str) -> SessionError {
    match e {
        AppError::Io { app, source, .. } => SessionError::LogWrite {
            app: Some(app),
            alog: alog.to_string(),
            source,
        },
    }
}

/// Flushes and closes the alog: any write error of the session fails the run.
fn close_log(sink: &LateSink, alog: &str) -> Result<(), SessionError> {
    sink.close().map_err(|source| SessionError::LogWrite {
        app: None,
        alog: alog.to_string(),
        source,
    })
}

/// The pokes of the options: the DEPLOY press, the button presses, then the pokes, each
/// after the first helm's first iteration unless timed. `start` is the run's MOOS start
/// time (a button's `$[UTC]`).
fn pokes(
    opts: &RunOptions,
    m: &MissionFile,
    helm: &str,
    start: f64,
) -> Result<Vec<Poke>, SessionError> {
    let all = buttons::buttons(m);
    let mut out = Vec::new();
    let mut presses = 0u32;
    let mut press = |b: &buttons::Button, out: &mut Vec<Poke>| {
        for (var, v) in &b.postings {
            let value = match v {
                ButtonValue::Double(x) => Value::Double(*x),
                ButtonValue::Text(t) => Value::text(t.clone()),
                ButtonValue::Utc => Value::Double(start),
                ButtonValue::PressCount => Value::Double(f64::from(presses)),
            };
            out.push(Poke {
                key: var.clone(),
                value,
                at: PokeAt::AfterFirstIterate(helm.to_string()),
            });
        }
        presses += 1;
    };
    if opts.deploy {
        match buttons::find(&all, "DEPLOY") {
            Some(b) => press(b, &mut out),
            None => {
                for t in ["DEPLOY=true", "MOOS_MANUAL_OVERRIDE=false"] {
                    out.push(
                        Poke::parse(t, helm).map_err(|e| SessionError::Invalid(e.to_string()))?,
                    );
                }
            }
        }
    }
    for name in &opts.buttons {
        let Some(b) = buttons::find(&all, name) else {
            let labels: Vec<&str> = all.iter().map(|b| b.label.as_str()).collect();
            return Err(SessionError::Invalid(if labels.is_empty() {
                format!("--button {name}: the mission has no pMarineViewer buttons")
            } else {
                format!(
                    "--button {name}: no such button; the mission's buttons: {}",
                    labels.join(", ")
                )
            }));
        };
        press(b, &mut out);
    }
    for t in &opts.pokes {
        out.push(
            Poke::parse(t, helm).map_err(|e| SessionError::Invalid(format!("--poke {t}: {e}")))?,
        );
    }
    Ok(out)
}

/// The logger's target for a session under `dir` whose contents are dated `opened`. The
/// writer is a [`LateSink`]: nothing is created on disk until [`open_log`].
fn log_target(loaded: &LoadedMission, dir: &Path, opened: NaiveDateTime) -> (LogTarget, LateSink) {
    let mut config = logger_config(&loaded.mission);
    config.path = dir.to_string_lossy().trim_end_matches('/').to_string();
    if config.path.is_empty() {
        config.path = ".".into();
    }
    let sink = LateSink::new();
    let target = LogTarget {
        config,
        writer: Box::new(sink.clone()),
        opened,
        opened_on: OPENED_ON.into(),
        side: Some(SideFiles {
            mission_text: loaded.text.clone(),
            folder: sink.clone(),
            base_dir: loaded.dir.clone(),
        }),
    };
    (target, sink)
}

/// Creates the session's folder and alog, named from `named` (the wall-clock start), never
/// over an existing log, attaches the file to `sink`, and returns the alog's path.
fn open_log(
    loaded: &LoadedMission,
    dir: &Path,
    named: NaiveDateTime,
    sink: &LateSink,
) -> Result<String, SessionError> {
    let (target, _) = log_target(loaded, dir, named);
    let (at, file) = target
        .config
        .claim_session(&named)
        .map_err(|e| SessionError::LogOpen(e.to_string()))?;
    let folder = PathBuf::from(target.config.directory(&at));
    sink.attach(Box::new(BufWriter::with_capacity(1 << 16, file)), folder);
    Ok(target.config.alog_path(&at))
}

/// The local wall-clock time, to the second (log names).
fn wall_now() -> NaiveDateTime {
    chrono::Local::now().naive_local()
}

/// Runs a loaded mission as `opts` says, telling `observer` what happens. Validation's
/// warnings are the caller's to print (see [`validate`]); errors in it stop the run here.
pub fn run(
    loaded: &LoadedMission,
    opts: &RunOptions,
    observer: &mut dyn Observer,
) -> Result<RunReport, SessionError> {
    if !(opts.max_time.is_finite() && opts.max_time > 0.0) {
        return Err(SessionError::Invalid(format!(
            "--max-time {}: expected a positive number of seconds",
            opts.max_time
        )));
    }
    let until = match &opts.until {
        Some(u) => Some(
            parse_condition(u).map_err(|e| SessionError::Invalid(format!("--until {u:?}: {e}")))?,
        ),
        None => None,
    };
    let helm = loaded.first_helm();
    // A button's `$[UTC]`: the run's start (lockstep's virtual one, or now).
    let start = match opts.mode {
        Mode::Lockstep => LOCKSTEP_START,
        Mode::RealTime { warp, .. } => moosdb::time::unix_now() * warp.unwrap_or(1.0),
    };
    let pokes = pokes(opts, &loaded.mission, &helm, start)?;
    if let Some(c) = &until {
        let bhvs: Vec<&BehaviorFile> = loaded
            .behaviors
            .values()
            .filter_map(|b| b.as_ref().ok().map(|p| &p.value))
            .collect();
        let poked: Vec<&str> = pokes.iter().map(|p| p.key.as_str()).collect();
        for v in mission::until::unknown_vars(c, &loaded.text, &bhvs, &poked) {
            observer.warning(&format!(
                "--until: nothing in the mission posts, initialises or names {v}; the run may go on to --max-time ({} s)",
                opts.max_time
            ));
        }
    }
    // As pLogger: GlobalLogPath, else the pLogger block's PATH, else `./`; the option wins.
    let log_dir = opts
        .log_dir
        .clone()
        .unwrap_or_else(|| PathBuf::from(logger_config(&loaded.mission).path));
    match opts.mode {
        Mode::Lockstep => lockstep(loaded, opts, pokes, until, &log_dir, observer),
        Mode::RealTime { warp, port } => {
            realtime(loaded, opts, (warp, port), pokes, until, &log_dir, observer)
        }
    }
}

fn lockstep(
    loaded: &LoadedMission,
    opts: &RunOptions,
    pokes: Vec<Poke>,
    until: Option<Condition>,
    log_dir: &Path,
    observer: &mut dyn Observer,
) -> Result<RunReport, SessionError> {
    let start = LOCKSTEP_START;
    let opened = chrono::DateTime::from_timestamp(start as i64, 0)
        .map(|d| d.naive_utc())
        .unwrap_or_default();
    let (target, sink) = log_target(loaded, log_dir, opened);
    let p = loaded
        .plan(start, opts.seed, Some(target))
        .map_err(|e| SessionError::Invalid(e.to_string()))?;
    // The files are named from the wall-clock start (two runs never share a name); their
    // contents keep the virtual date, so a lockstep log is byte-identical run to run.
    let alog = open_log(loaded, log_dir, wall_now(), &sink)?;
    for ext in &p.external {
        observer.warning(&format!(
            "{}:{}: {} is not built into coug; skipped in lockstep",
            ext.span.file_name(),
            ext.span.line,
            ext.app
        ));
    }
    let run_err = |e: RunError| match e {
        RunError::App(e) => app_failed(e, &alog),
        RunError::Bus(e) => SessionError::Bus(e),
    };
    let mut s = Scheduler::new(Bus::new(&p.globals.community, start), VirtualClock, start);
    for app in p.apps {
        s.add_app(app).map_err(run_err)?;
    }
    for poke in pokes {
        s.add_poke(poke)?;
    }
    if let Some(c) = until {
        s.set_until(c);
    }
    s.tap("IVPHELM_SUMMARY");
    let wall = Instant::now();
    let end = start + opts.max_time;
    // One-second steps: the observer samples the DB at each.
    let step = 1.0;
    let mut t = start;
    let ended = loop {
        if observer.stop_requested() {
            break Ended::Interrupted { time: t };
        }
        t = (t + step).min(end);
        match s.advance(t).map_err(run_err)? {
            Some(o) => break Ended::Outcome(o),
            None if t >= end => break Ended::Outcome(Outcome::MaxTime { time: end }),
            None => {}
        }
        for p in s.take_taps() {
            if let Some(v) = p.value.as_str() {
                observer.helm_summary(v);
            }
        }
        let current = |k: &str| s.current(k);
        observer.step(t - start, &current);
    };
    if matches!(ended, Ended::Outcome(_)) {
        s.deliver_pending().map_err(run_err)?;
    }
    let wall_s = wall.elapsed().as_secs_f64();
    let until_values = s.until_values();
    s.stop().map_err(|e| app_failed(e, &alog))?;
    drop(s);
    let end = Ending(ended, start, wall_s, until_values);
    close_and_report(loaded, opts, &sink, alog, end)
}

/// How a run ended, before its log is closed and read back: the end, the MOOS start time,
/// the wall seconds taken, and the `until` values.
struct Ending(Ended, f64, f64, Vec<(String, Option<Value>)>);

/// Closes the log (a write error fails the run) and reports the run, with the totals of its
/// alog read back.
fn close_and_report(
    loaded: &LoadedMission,
    opts: &RunOptions,
    sink: &LateSink,
    alog: String,
    end: Ending,
) -> Result<RunReport, SessionError> {
    close_log(sink, &alog)?;
    let totals = std::fs::read_to_string(&alog)
        .ok()
        .and_then(|t| alog::parse(&t).ok())
        .map(|log| LogTotals::from_alog(&log));
    Ok(RunReport {
        mission: loaded.path.clone(),
        ended: end.0,
        until: opts.until.clone(),
        max_time: opts.max_time,
        start: end.1,
        wall_s: end.2,
        until_values: end.3,
        alog,
        totals,
    })
}

/// The mission as the external apps must read it, or `None` when the original file
/// describes this run: macros expanded, and the run's settings written over the file's, as
/// pAntler does with its `--NAME=VALUE` overloads: the DB's actual `ServerPort`, and the
/// run's `MOOSTimeWarp` when the option changed it.
pub fn mission_for_externals(
    loaded: &LoadedMission,
    globals: &MissionGlobals,
    port: u16,
    warp: f64,
) -> Option<String> {
    let mut overrides: Vec<(&str, String)> = Vec::new();
    if port != globals.server_port {
        overrides.push(("ServerPort", port.to_string()));
    }
    if warp != globals.time_warp {
        overrides.push(("MOOSTimeWarp", moos_types::fmt::g_string(warp, 6)));
    }
    if !loaded.expanded && overrides.is_empty() {
        return None;
    }
    let edits: Vec<(&str, &str)> = overrides.iter().map(|(k, v)| (*k, v.as_str())).collect();
    Some(override_globals(&loaded.text, &edits))
}

/// Writes the externals' mission (see [`mission_for_externals`]) into `log_dir` as
/// `expanded_<name>`, or returns the original path.
fn write_mission_for_externals(
    loaded: &LoadedMission,
    globals: &MissionGlobals,
    port: u16,
    warp: f64,
    log_dir: &Path,
) -> Result<PathBuf, SessionError> {
    let Some(text) = mission_for_externals(loaded, globals, port, warp) else {
        return Ok(loaded.path.clone());
    };
    std::fs::create_dir_all(log_dir)
        .map_err(|e| SessionError::LogOpen(format!("cannot create {}: {e}", log_dir.display())))?;
    let name = loaded.path.file_name().map_or_else(
        || "mission.moos".into(),
        |n| n.to_string_lossy().into_owned(),
    );
    let path = log_dir.join(format!("expanded_{name}"));
    std::fs::write(&path, text)
        .map_err(|e| SessionError::LogOpen(format!("cannot write {}: {e}", path.display())))?;
    Ok(path)
}

/// Starts the ANTLER apps coug does not build in, from PATH, as pAntler does.
fn start_externals(
    externals: &[AntlerRun],
    mission: &Path,
    observer: &mut dyn Observer,
) -> Vec<Child> {
    let mut children = Vec::new();
    for ext in externals {
        // pAntler's argv: `app mission_file moos_name`.
        let mut cmd = Command::new(&ext.app);
        cmd.arg(mission).arg(ext.moos_name());
        cmd.stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::null());
        match cmd.spawn() {
            Ok(c) => {
                observer.notice(&format!("started {} (pid {})", ext.app, c.id()));
                children.push(c);
            }
            Err(e) => observer.warning(&format!(
                "{}:{}: cannot start {}: {e}; running without it",
                ext.span.file_name(),
                ext.span.line,
                ext.app
            )),
        }
    }
    children
}

/// The children of a real-time run, killed when the run ends however it ends.
struct Children(Vec<Child>);

impl Drop for Children {
    fn drop(&mut self) {
        for c in &mut self.0 {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

fn realtime(
    loaded: &LoadedMission,
    opts: &RunOptions,
    (warp, port): (Option<f64>, Option<u16>),
    pokes: Vec<Poke>,
    until: Option<Condition>,
    log_dir: &Path,
    observer: &mut dyn Observer,
) -> Result<RunReport, SessionError> {
    let (globals, _) = MissionGlobals::from_mission(&loaded.mission);
    let warp_f = warp.unwrap_or(globals.time_warp);
    let warp =
        Warp::new(warp_f).map_err(|e| SessionError::Invalid(format!("--warp {warp_f}: {e}")))?;
    let port = port.unwrap_or(globals.server_port);
    let host = if globals.server_host.eq_ignore_ascii_case("localhost") {
        "127.0.0.1".to_string()
    } else {
        globals.server_host.clone()
    };
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .map_err(|e| SessionError::Net(e.to_string()))?;
    let local = tokio::task::LocalSet::new();
    local.block_on(&rt, async {
        let addr: std::net::SocketAddr = format!("{host}:{port}")
            .parse()
            .or_else(|_| {
                use std::net::ToSocketAddrs;
                (host.as_str(), port)
                    .to_socket_addrs()
                    .ok()
                    .and_then(|mut a| a.next())
                    .ok_or(())
            })
            .map_err(|_| SessionError::Net(format!("cannot resolve ServerHost {host}")))?;
        let mut sc = ServerConfig::with_addr(addr);
        sc.warp = warp;
        sc.db.community = globals.community.clone();
        let server = Server::bind(sc)
            .await
            .map_err(|e| SessionError::Net(format!("cannot listen on {addr}: {e}")))?;
        let port = server.local_addr().port();
        observer.notice(&format!(
            "MOOSDB_{} listening on {} (warp {warp_f})",
            globals.community,
            server.local_addr()
        ));
        let start = moosdb::time::unix_now() * warp_f;
        let opened = wall_now();
        let (target, sink) = log_target(loaded, log_dir, opened);
        let p = loaded
            .plan(start, opts.seed, Some(target))
            .map_err(|e| SessionError::Invalid(e.to_string()))?;
        let alog = open_log(loaded, log_dir, opened, &sink)?;
        let mut children = Children(Vec::new());
        if !p.external.is_empty() {
            let path = write_mission_for_externals(loaded, &globals, port, warp_f, log_dir)?;
            children.0 = start_externals(&p.external, &path, observer);
        }
        let cfg = RemoteConfig {
            host: addr.ip().to_string(),
            port,
            warp: warp_f,
        };
        let spec = RunSpec {
            pokes,
            until,
            max_time: opts.max_time,
        };
        let wall = Instant::now();
        let db = &server;
        db.with_db(|d| d.tap("IVPHELM_SUMMARY"));
        let watch = async {
            let mut tick = tokio::time::interval(Duration::from_millis(50));
            loop {
                tick.tick().await;
                if observer.stop_requested() {
                    return moosdb::time::unix_now() * warp_f;
                }
                let now = moosdb::time::unix_now() * warp_f;
                let current = |k: &str| -> Option<Value> {
                    db.with_db(|d| d.current(k))
                        .and_then(|m| match m.data_type {
                            moosdb::DataType::Double => Some(Value::Double(m.dval)),
                            moosdb::DataType::String => {
                                Some(Value::String(m.sval_str().into_owned().into()))
                            }
                            _ => None,
                        })
                };
                for m in db.with_db(|d| d.take_taps()) {
                    observer.helm_summary(&m.sval_str());
                }
                observer.step(now - start, &current);
            }
        };
        let result = tokio::select! {
            r = run_apps(p.apps, &cfg, spec) => Ok(r),
            t = watch => Err(t),
        };
        let wall_s = wall.elapsed().as_secs_f64();
        drop(children);
        server.shutdown();
        let (ended, until_values) = match result {
            Err(time) => (Ended::Interrupted { time }, Vec::new()),
            // An app's failure (a log that could not be written) fails the run.
            Ok(r) => {
                let end = r.map_err(|e| match e {
                    RemoteError::App(e) => app_failed(e, &alog),
                    e => SessionError::Remote(e),
                })?;
                (Ended::Outcome(end.outcome), end.values)
            }
        };
        let end = Ending(ended, start, wall_s, until_values);
        close_and_report(loaded, opts, &sink, alog, end)
    })
}
