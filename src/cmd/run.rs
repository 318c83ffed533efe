//! `coug run MISSION.moos [NAME=VALUE]... [--lockstep | --warp N] [--poke VAR=VALUE[@T]]...
//! [--deploy] [--until CONDITION] [--max-time SECONDS] [--log-dir DIR] [--port N]`:
//! one command runs a whole MOOS-IvP mission.
//!
//! The mission (and each helm's `behaviors =` file) is nsplug-expanded with the given
//! macros, the ANTLER block is resolved into coug's built-in apps (`runtime::antler`), and
//! the apps run either in lockstep on a virtual clock (deterministic, as fast as the CPU
//! allows) or in real time times the warp with the MOOSDB on TCP, so real MOOS apps can
//! join; ANTLER apps coug does not build in are then started from PATH as pAntler starts
//! them (`APP MISSION.moos [ALIAS]`).
//!
//! Exit codes: 0 when the `--until` condition held (or the run reached `--max-time`
//! without one), 2 when `--max-time` came first, 1 on errors in files or arguments.

use std::collections::HashMap;
use std::io::{BufWriter, IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use clap::Args;
use mission::Parsed;
use mission::bhv::BehaviorFile;
use mission::buttons::{self, ButtonValue};
use mission::condition::{Condition, parse_condition};
use mission::diagnostic::DiagnosticKind;
use mission::moos::{AntlerRun, MissionFile, parse_moos};
use mission::nsplug::{Options, preprocess};
use mission::source::FsSource;
use moosdb_client::time::Warp;
use moosdb_client::{Server, ServerConfig};
use runtime::antler::{LogTarget, MissionGlobals, Plan, logger_config, plan};
use runtime::chrono::{self, NaiveDateTime};
use runtime::helm::{HelmApp, load_behaviors};
use runtime::logger::{LateSink, SideFiles};
use runtime::realtime::{RunSpec, run_apps};
use runtime::remote::RemoteConfig;
use runtime::summary::{RunSummary, behaviour_list};
use runtime::{
    App, AppError, Bus, Outcome, Poke, PokeAt, RunError, Scheduler, Value, VirtualClock,
};

/// MOOS time at which every lockstep run starts (so two runs log the same bytes).
pub const LOCKSTEP_START: f64 = 1_786_000_000.0;

/// The banner's `FILE OPENED ON` text (pLogger 2024 prints the Unix epoch there).
pub const OPENED_ON: &str = "Thu Jan  1 00:00:00 1970";

/// Arguments of `coug run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The mission file.
    #[arg(value_name = "MISSION.moos")]
    pub mission: PathBuf,
    /// nsplug macro definitions for the mission and its behaviour files.
    #[arg(value_name = "NAME=VALUE")]
    pub macros: Vec<String>,
    /// Virtual clock: every app and the bus in one thread, deterministic, as fast as the
    /// CPU allows.
    #[arg(long, conflicts_with = "warp")]
    pub lockstep: bool,
    /// Real-time speed-up (default: the mission's MOOSTimeWarp).
    #[arg(long, value_name = "N")]
    pub warp: Option<f64>,
    /// Post a value once the helm is up (`VAR=VALUE`, `VAR:=VALUE` for a string), or at
    /// `T` seconds after the start (`VAR=VALUE@T`). Repeatable.
    #[arg(long = "poke", value_name = "VAR=VALUE[@T]")]
    pub pokes: Vec<String>,
    /// Press the mission's DEPLOY button (pMarineViewer's `button_* = DEPLOY # ...`), or, when
    /// it has none, post DEPLOY=true and MOOS_MANUAL_OVERRIDE=false.
    #[arg(long)]
    pub deploy: bool,
    /// Press the pMarineViewer button with this label (or key, `button_two`) after the helm's
    /// first iteration, as an operator would (repeatable, in order).
    #[arg(long = "button", value_name = "LABEL")]
    pub buttons: Vec<String>,
    /// End the run when this condition (.bhv syntax) holds, e.g. "MISSION = complete".
    #[arg(long, value_name = "CONDITION")]
    pub until: Option<String>,
    /// End the run after this many simulated seconds (exit 2 if `--until` is pending).
    #[arg(long, value_name = "SECONDS", default_value_t = 3600.0)]
    pub max_time: f64,
    /// The folder pLogger's session folder goes in (default: the mission's GlobalLogPath,
    /// else the pLogger block's PATH, else the current directory, as pLogger).
    #[arg(long, value_name = "DIR")]
    pub log_dir: Option<PathBuf>,
    /// MOOSDB port in real time (default: the mission's ServerPort; 0 picks a free one).
    #[arg(long, value_name = "N")]
    pub port: Option<u16>,
    /// Seed of every random draw (uTimerScript randomness).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Simulated seconds between progress lines when stderr is not a terminal.
    #[arg(long, value_name = "SECONDS", default_value_t = 10.0)]
    pub progress_every: f64,
    /// Extra directory searched for nsplug `#include` files (repeatable).
    #[arg(short = 'p', long = "path", value_name = "DIR")]
    pub include_paths: Vec<PathBuf>,
}

/// A mission loaded and checked: the expanded `.moos`, its text, and each helm's behaviours.
pub struct Loaded {
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
    pub warnings: Vec<String>,
    /// How the files were preprocessed (a helm's RESTART_HELM reads them again so).
    pub opts: Options,
}

fn base(app: &str) -> &str {
    app.rsplit('/').next().unwrap_or(app)
}

/// Preprocesses and parses the mission and its behaviour files; returns the error
/// messages (`file:line: ...`) when any file has an error. Warnings go to stderr.
pub fn load(
    path: &Path,
    macros: &[String],
    include_paths: &[PathBuf],
) -> Result<Loaded, Vec<String>> {
    let mut opts = Options::new();
    opts.include_paths = include_paths.to_vec();
    for m in macros {
        opts.define_arg(m);
    }
    let pre = preprocess(&FsSource, path, &opts).map_err(|d| vec![d.to_string()])?;
    let text = pre.source.text();
    let original = std::fs::read_to_string(path).unwrap_or_default();
    let parsed = parse_moos(&pre.source);
    let mut errors = Vec::new();
    let mut warnings = Vec::new();
    for d in pre.diagnostics.iter().chain(parsed.diagnostics.iter()) {
        if d.is_error() {
            errors.push(d.to_string());
        } else if d.kind != DiagnosticKind::UndefinedMacro {
            // `$(X)` left for the apps (uTimerScript's `$(COUNT)`, behaviour flags' `$(X)`)
            // is normal in a mission; `coug check` lists them.
            warnings.push(d.to_string());
        }
    }
    let mission = parsed.value;
    if !mission::is_mission(&mission) {
        return Err(vec![not_a_mission(path)]);
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
    if errors.is_empty() {
        let expanded = text.trim_end() != original.trim_end();
        Ok(Loaded {
            mission,
            text,
            behaviors,
            expanded,
            dir,
            warnings,
            opts,
        })
    } else {
        Err(errors)
    }
}

/// What `coug run` finds wrong with a loaded mission before running it, and `coug check`
/// reports: one path for both commands.
#[derive(Debug, Default)]
pub struct Validation {
    /// Findings that do not stop the run (file:line first where known).
    pub warnings: Vec<String>,
    /// Each helm that would run in MALCONFIG (never driving), with why.
    pub malconfig: Vec<(String, Vec<String>)>,
    /// Apps that would end at start-up (the run goes on without them), with why.
    pub failed: Vec<String>,
    /// Why the run cannot start at all.
    pub errors: Vec<String>,
}

/// Validates a loaded mission as `coug run` would start it: the reader's warnings, the apps'
/// configuration warnings, helms that would be in MALCONFIG, built-in apps without a
/// ProcessConfig block, and AppTick/CommsTick values MOOS cannot read.
pub fn validate(loaded: &Loaded) -> Validation {
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
                v.warnings.push(format!(
                    "{}:{}: {}: {} = {}: not a number; MOOS cannot read it and keeps its default",
                    p.span.file_name(),
                    p.span.line,
                    block.name,
                    p.key,
                    p.value
                ));
            }
        }
    }
    for run in m.antler_runs() {
        let name = run.moos_name();
        if runtime::antler::BUILT_IN.contains(&base(&run.app)) && m.process(name).is_none() {
            v.warnings.push(format!(
                "{}:{}: {} runs with no `ProcessConfig = {name}` block: every setting at its default",
                run.span.file_name(),
                run.span.line,
                run.app
            ));
        }
    }
    let mut malconfig = Vec::new();
    // Planned as the run plans it, with a log that goes nowhere (nothing touches the disk).
    let log = LogTarget {
        config: logger_config(m),
        writer: Box::new(std::io::sink()),
        opened: NaiveDateTime::default(),
        opened_on: OPENED_ON.into(),
        side: None,
    };
    let planned = plan(m, 0.0, 0, Some(log), &mut |run: &AntlerRun, _block| {
        if base(&run.app) != "pHelmIvP" {
            return None;
        }
        let h = helm_app(loaded, run.moos_name());
        if !h.config_errors().is_empty() {
            let reasons = h.config_errors().iter().map(ToString::to_string).collect();
            malconfig.push((run.moos_name().to_string(), reasons));
        }
        Some(Ok(Box::new(h) as Box<dyn App>))
    });
    match planned {
        Ok(p) => {
            v.warnings.extend(p.warnings);
            v.failed = p.failed;
        }
        // A file without an ANTLER block is not a mission `coug run` can start (it says so
        // when asked to), but it is a good MOOS file for apps started by hand.
        Err(runtime::antler::LaunchError::NoAntler) => {}
        Err(e) => v.errors.push(e.to_string()),
    }
    v.malconfig = malconfig;
    v
}

/// The helm called `name` of a loaded mission (MALCONFIG when its configuration is bad).
fn helm_app(loaded: &Loaded, name: &str) -> HelmApp {
    let m = &loaded.mission;
    let app = match loaded.behaviors.get(name) {
        Some(bhv) => HelmApp::from_behaviors(name, m, bhv.as_ref().map_err(Vec::as_slice)),
        None => HelmApp::from_behaviors(name, m, Err(&[])),
    };
    app.with_reload(m, &loaded.dir, &loaded.opts)
}

/// Says on stderr why a helm is in MALCONFIG (it runs anyway, as pHelmIvP does: it posts
/// `IVPHELM_STATE = MALCONFIG` and never drives).
pub fn report_malconfig<E: std::fmt::Display>(name: &str, errors: &[E]) {
    if errors.is_empty() {
        return;
    }
    errln!(
        "{name}: MALCONFIG: the helm will not drive ({} configuration error{}):",
        errors.len(),
        if errors.len() == 1 { "" } else { "s" }
    );
    for e in errors {
        errln!("{name}:   {e}");
    }
}

/// The pokes of the command line: `--deploy`, the `--button` presses, then the `--poke`s,
/// each after the first helm's first iteration unless timed. `start` is the run's MOOS start
/// time (a button's `$[UTC]`).
fn pokes(args: &RunArgs, m: &MissionFile, helm: &str, start: f64) -> Result<Vec<Poke>, String> {
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
    if args.deploy {
        match buttons::find(&all, "DEPLOY") {
            Some(b) => press(b, &mut out),
            None => {
                for t in ["DEPLOY=true", "MOOS_MANUAL_OVERRIDE=false"] {
                    out.push(Poke::parse(t, helm).map_err(|e| e.to_string())?);
                }
            }
        }
    }
    for name in &args.buttons {
        let Some(b) = buttons::find(&all, name) else {
            let labels: Vec<&str> = all.iter().map(|b| b.label.as_str()).collect();
            return Err(if labels.is_empty() {
                format!("--button {name}: the mission has no pMarineViewer buttons")
            } else {
                format!(
                    "--button {name}: no such button; the mission's buttons: {}",
                    labels.join(", ")
                )
            });
        };
        press(b, &mut out);
    }
    for t in &args.pokes {
        out.push(Poke::parse(t, helm).map_err(|e| format!("--poke {t}: {e}"))?);
    }
    Ok(out)
}

/// The logger's target for a session under `dir` whose contents are dated `opened`. The
/// writer is a [`LateSink`]: nothing is created on disk until [`open_log`].
fn log_target(loaded: &Loaded, dir: &Path, opened: NaiveDateTime) -> (LogTarget, LateSink) {
    let m = &loaded.mission;
    let mut config = logger_config(m);
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
    loaded: &Loaded,
    dir: &Path,
    named: NaiveDateTime,
    sink: &LateSink,
) -> Result<String, String> {
    let (target, _) = log_target(loaded, dir, named);
    let (at, file) = target
        .config
        .claim_session(&named)
        .map_err(|e| e.to_string())?;
    let folder = PathBuf::from(target.config.directory(&at));
    sink.attach(Box::new(BufWriter::with_capacity(1 << 16, file)), folder);
    Ok(target.config.alog_path(&at))
}

/// Resolves the ANTLER block with coug's helm for every `pHelmIvP` line.
fn make_plan(
    loaded: &Loaded,
    start: f64,
    seed: u64,
    log: Option<LogTarget>,
) -> Result<Plan, String> {
    let m = &loaded.mission;
    plan(m, start, seed, log, &mut |run: &AntlerRun, _block| {
        if base(&run.app) != "pHelmIvP" {
            return None;
        }
        let h = helm_app(loaded, run.moos_name());
        Some(Ok(Box::new(h) as Box<dyn App>))
    })
    .map_err(|e| e.to_string())
}

/// What the progress line shows: the helm state and position from the DB's current values,
/// the active behaviours from every IVPHELM_SUMMARY posting (the helm writes `active_bhvs`
/// only when it changes, so the latest value alone does not say it), in lockstep and real
/// time alike.
#[derive(Default)]
struct Progress {
    active: Vec<String>,
    last_line: Option<Instant>,
    next_sim: f64,
    printed_inline: bool,
}

fn num(v: Option<Value>) -> Option<f64> {
    v.and_then(|v| v.as_f64())
}

fn text(v: Option<Value>) -> Option<String> {
    v.and_then(|v| v.as_str().map(String::from))
}

impl Progress {
    /// Takes one IVPHELM_SUMMARY posting.
    fn observe_summary(&mut self, summary: &str) {
        if let Some(a) = behaviour_list(summary, "active_bhvs") {
            self.active = a;
        }
    }

    fn line(
        &mut self,
        sim: f64,
        wall: f64,
        get: &dyn Fn(&str) -> Option<Value>,
        terminal: bool,
    ) -> String {
        let state = text(get("IVPHELM_STATE")).unwrap_or_else(|| "-".into());
        let active = if self.active.is_empty() {
            "none".to_string()
        } else {
            self.active.join(",")
        };
        let f = |k: &str| num(get(k)).map_or("-".into(), |x| format!("{x:.1}"));
        let line = format!(
            "t={sim:7.1}s  {:6.0}x  helm={state}  active={active}  x={} y={} depth={}",
            sim / wall.max(1e-9),
            f("NAV_X"),
            f("NAV_Y"),
            f("NAV_DEPTH")
        );
        if terminal {
            format!("\r\x1b[2K{line}")
        } else {
            format!("{line}\n")
        }
    }

    /// Prints a progress line if one is due.
    fn tick(
        &mut self,
        sim: f64,
        wall: &Instant,
        get: &dyn Fn(&str) -> Option<Value>,
        terminal: bool,
        every: f64,
    ) {
        let due = if terminal {
            self.last_line
                .is_none_or(|t| t.elapsed() >= Duration::from_millis(200))
        } else {
            sim >= self.next_sim
        };
        if !due {
            return;
        }
        self.last_line = Some(Instant::now());
        while self.next_sim <= sim {
            self.next_sim += every.max(0.1);
        }
        let l = self.line(sim, wall.elapsed().as_secs_f64(), get, terminal);
        let mut err = std::io::stderr().lock();
        let _ = err.write_all(l.as_bytes());
        let _ = err.flush();
        self.printed_inline = terminal;
    }

    fn finish(&mut self) {
        if self.printed_inline {
            errln!();
            self.printed_inline = false;
        }
    }
}

/// How a run ended, for the summary and the exit code.
struct Ended {
    outcome: Outcome,
    start: f64,
    wall: f64,
    until_values: Vec<(String, Option<Value>)>,
}

fn fmt_value(v: &Option<Value>) -> String {
    match v {
        None => "(never posted)".into(),
        Some(Value::Double(x)) => format!("{x}"),
        Some(Value::String(s)) => format!("\"{s}\""),
        Some(Value::Binary(b)) => format!("({} bytes)", b.len()),
    }
}

/// Prints the closing summary and returns the exit code.
fn finish(args: &RunArgs, ended: &Ended, alog_path: Option<&str>) -> i32 {
    let (time, code) = match ended.outcome {
        Outcome::ConditionMet { time } => (time, 0),
        Outcome::MaxTime { time } => (time, if args.until.is_some() { 2 } else { 0 }),
        Outcome::AllFinished { time } => (time, if args.until.is_some() { 2 } else { 0 }),
    };
    let sim = time - ended.start;
    let mut out = String::new();
    use std::fmt::Write as _;
    let _ = writeln!(out, "coug run: {}", args.mission.display());
    let how = match ended.outcome {
        Outcome::ConditionMet { .. } => format!(
            "until condition met ({})",
            args.until.as_deref().unwrap_or("")
        ),
        Outcome::MaxTime { .. } => format!("max time {} s reached", args.max_time),
        Outcome::AllFinished { .. } => "every app finished".into(),
    };
    let _ = writeln!(out, "  ended:       {how}");
    let _ = writeln!(
        out,
        "  simulated:   {sim:.1} s   wall: {:.3} s   speed-up: {:.0}x",
        ended.wall,
        sim / ended.wall.max(1e-9)
    );
    if let Some(path) = alog_path {
        match std::fs::read_to_string(path)
            .ok()
            .and_then(|t| alog::parse(&t).ok())
        {
            Some(log) => {
                let s = RunSummary::from_alog(&log);
                let _ = writeln!(out, "  distance:    {:.1} m", s.distance);
                if s.max_depth > 0.0 {
                    let _ = writeln!(out, "  max depth:   {:.2} m", s.max_depth);
                }
                if let Some((x, y)) = s.final_position {
                    let _ = writeln!(out, "  final x,y:   {x:.1}, {y:.1}");
                }
                // Every behaviour that completed during the run (the helm's later reports
                // may drop it, e.g. once the mission is no longer active).
                let mut completed: Vec<String> = Vec::new();
                for e in log.entries.iter().filter(|e| e.var == "IVPHELM_SUMMARY") {
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
                let done = if completed.is_empty() {
                    "none".to_string()
                } else {
                    completed.join(", ")
                };
                let _ = writeln!(out, "  completed:   {done}");
                if let Some(h) = &s.helm_state {
                    let _ = writeln!(out, "  helm state:  {h}");
                }
                for e in log
                    .entries
                    .iter()
                    .filter(|e| e.var == "IVPHELM_CONFIG_WARNING")
                {
                    if let Some(why) = e.value.as_str() {
                        let _ = writeln!(out, "  malconfig:   {why}");
                    }
                }
            }
            None => {
                let _ = writeln!(out, "  (the log could not be read back for totals)");
            }
        }
    }
    for (k, v) in &ended.until_values {
        let _ = writeln!(out, "  {k} = {}", fmt_value(v));
    }
    match alog_path {
        Some(p) => {
            let _ = writeln!(out, "  log:         {p}");
        }
        None => {
            let _ = writeln!(out, "  log:         (none)");
        }
    }
    out!("{out}");
    if code == 2 {
        let pending: Vec<String> = ended
            .until_values
            .iter()
            .map(|(k, v)| format!("{k} = {}", fmt_value(v)))
            .collect();
        errln!(
            "coug run: still pending after {sim:.1} simulated s: {} (now {})",
            args.until.as_deref().unwrap_or(""),
            pending.join(", ")
        );
    }
    code
}

/// Runs `coug run`; returns the process exit code.
pub fn run(args: &RunArgs) -> i32 {
    match run_inner(args) {
        Ok(code) => code,
        Err(messages) => {
            for m in messages {
                errln!("coug run: error: {m}");
            }
            1
        }
    }
}

fn run_inner(args: &RunArgs) -> Result<i32, Vec<String>> {
    if !(args.max_time.is_finite() && args.max_time > 0.0) {
        return Err(vec![format!(
            "--max-time {}: expected a positive number of seconds",
            args.max_time
        )]);
    }
    let loaded = load(&args.mission, &args.macros, &args.include_paths)?;
    let checked = validate(&loaded);
    if !checked.errors.is_empty() {
        return Err(checked.errors);
    }
    for w in &checked.warnings {
        errln!("coug run: warning: {w}");
    }
    for (name, reasons) in &checked.malconfig {
        report_malconfig(name, reasons);
    }
    for f in &checked.failed {
        errln!("coug run: error: {f}; the run goes on without it");
    }
    let until = match &args.until {
        Some(u) => Some(parse_condition(u).map_err(|e| vec![format!("--until {u:?}: {e}")])?),
        None => None,
    };
    let helm = loaded
        .mission
        .antler_runs()
        .into_iter()
        .find(|r| base(&r.app) == "pHelmIvP")
        .map_or_else(|| "pHelmIvP".to_string(), |r| r.moos_name().to_string());
    // A button's `$[UTC]`: the run's start (lockstep's virtual one, or now).
    let start = if args.lockstep {
        LOCKSTEP_START
    } else {
        moosdb_client::time::unix_now() * args.warp.unwrap_or(1.0)
    };
    let pokes = pokes(args, &loaded.mission, &helm, start).map_err(|e| vec![e])?;
    if let Some(c) = &until {
        let bhvs: Vec<&BehaviorFile> = loaded
            .behaviors
            .values()
            .filter_map(|b| b.as_ref().ok().map(|p| &p.value))
            .collect();
        let poked: Vec<&str> = pokes.iter().map(|p| p.key.as_str()).collect();
        for v in mission::until::unknown_vars(c, &loaded.text, &bhvs, &poked) {
            errln!(
                "coug run: warning: --until: nothing in the mission posts, initialises or names {v}; the run may go on to --max-time ({} s)",
                args.max_time
            );
        }
    }
    // As pLogger: GlobalLogPath, else the pLogger block's PATH, else `./`; --log-dir wins.
    let log_dir = args
        .log_dir
        .clone()
        .unwrap_or_else(|| PathBuf::from(logger_config(&loaded.mission).path));
    if args.lockstep {
        lockstep(args, &loaded, pokes, until, &log_dir)
    } else {
        realtime(args, &loaded, pokes, until, &log_dir)
    }
}

/// An app's failure as the run's error. The only files the built-in apps write are the
/// log session's (pLogger), so a write failure names the alog by its file on disk (the path
/// in a lockstep log's banner carries the virtual date instead).
fn app_failed(e: &AppError, alog_path: &str) -> Vec<String> {
    match e {
        AppError::Io { app, source, .. } => {
            vec![format!(
                "{app}: the log {alog_path} could not be written: {source}"
            )]
        }
    }
}

/// Flushes and closes the alog: any write error of the session fails the run.
fn close_log(sink: &LateSink, alog_path: &str) -> Result<(), Vec<String>> {
    sink.close()
        .map_err(|e| vec![format!("the log {alog_path} could not be written: {e}")])
}

/// Why a file is refused as a mission (see [`mission::is_mission`]).
pub fn not_a_mission(path: &Path) -> String {
    format!(
        "{}: not a MOOS mission file (no ServerHost, ServerPort, Community or ProcessConfig)",
        path.display()
    )
}

/// The local wall-clock time, to the second (log names).
fn wall_now() -> NaiveDateTime {
    chrono::Local::now().naive_local()
}

/// A flag set on Ctrl-C (watched by a helper thread), so a lockstep run can stop
/// between steps with its log flushed.
fn interrupt_flag() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let f = flag.clone();
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build();
    if let Ok(rt) = rt {
        std::thread::spawn(move || {
            rt.block_on(async {
                super::signal::shutdown().await;
                f.store(true, Ordering::Relaxed);
            });
        });
    }
    flag
}

fn lockstep(
    args: &RunArgs,
    loaded: &Loaded,
    pokes: Vec<Poke>,
    until: Option<Condition>,
    log_dir: &Path,
) -> Result<i32, Vec<String>> {
    let start = LOCKSTEP_START;
    let opened = chrono::DateTime::from_timestamp(start as i64, 0)
        .map(|d| d.naive_utc())
        .unwrap_or_default();
    let (target, sink) = log_target(loaded, log_dir, opened);
    let p = make_plan(loaded, start, args.seed, Some(target)).map_err(|e| vec![e])?;
    // The files are named from the wall-clock start (two runs never share a name); their
    // contents keep the virtual date, so a lockstep log is byte-identical run to run.
    let alog_path = open_log(loaded, log_dir, wall_now(), &sink).map_err(|e| vec![e])?;
    // (The plan's warnings were printed by `validate`.)
    for ext in &p.external {
        errln!(
            "coug run: warning: {}:{}: {} is not built into coug; skipped in lockstep",
            ext.span.file_name(),
            ext.span.line,
            ext.app
        );
    }
    let mut s = Scheduler::new(Bus::new(&p.globals.community, start), VirtualClock, start);
    for app in p.apps {
        s.add_app(app).map_err(|e| vec![e.to_string()])?;
    }
    for poke in pokes {
        s.add_poke(poke).map_err(|e| vec![e.to_string()])?;
    }
    if let Some(c) = until {
        s.set_until(c);
    }
    s.tap("IVPHELM_SUMMARY");
    let terminal = std::io::stderr().is_terminal();
    let mut progress = Progress {
        next_sim: 0.0,
        ..Progress::default()
    };
    let interrupted = interrupt_flag();
    let wall = Instant::now();
    let end = start + args.max_time;
    // One-second steps: the progress line samples the helm's summary at each.
    let step = 1.0;
    let mut t = start;
    let outcome = loop {
        if interrupted.load(Ordering::Relaxed) {
            progress.finish();
            s.stop().map_err(|e| app_failed(&e, &alog_path))?;
            drop(s);
            close_log(&sink, &alog_path)?;
            errln!(
                "coug run: interrupted at {:.1} simulated s; log: {alog_path}",
                t - start
            );
            return Ok(130);
        }
        t = (t + step).min(end);
        match s.advance(t).map_err(|e| match e {
            RunError::App(e) => app_failed(&e, &alog_path),
            e => vec![e.to_string()],
        })? {
            Some(o) => break o,
            None if t >= end => break Outcome::MaxTime { time: end },
            None => {}
        }
        for p in s.take_taps() {
            if let Some(v) = p.value.as_str() {
                progress.observe_summary(v);
            }
        }
        let get = |k: &str| s.current(k);
        progress.tick(t - start, &wall, &get, terminal, args.progress_every);
    };
    s.deliver_pending().map_err(|e| match e {
        RunError::App(e) => app_failed(&e, &alog_path),
        e => vec![e.to_string()],
    })?;
    let wall = wall.elapsed().as_secs_f64();
    progress.finish();
    let ended = Ended {
        outcome,
        start,
        wall,
        until_values: s.until_values(),
    };
    s.stop().map_err(|e| app_failed(&e, &alog_path))?;
    drop(s);
    close_log(&sink, &alog_path)?;
    Ok(finish(args, &ended, Some(&alog_path)))
}

/// Writes the mission for the external apps when the original file does not describe this
/// run: macros expanded, and the run's settings written over the file's, as pAntler does
/// with its `--NAME=VALUE` overloads (a `MISSION.moos++` copy): the DB's actual
/// `ServerPort`, and the run's `MOOSTimeWarp` when `--warp` changed it.
fn mission_for_externals(
    args: &RunArgs,
    loaded: &Loaded,
    globals: &MissionGlobals,
    port: u16,
    warp: f64,
    log_dir: &Path,
) -> Result<PathBuf, String> {
    let mut overrides: Vec<(&str, String)> = Vec::new();
    if port != globals.server_port {
        overrides.push(("ServerPort", port.to_string()));
    }
    if warp != globals.time_warp {
        overrides.push(("MOOSTimeWarp", moosdb_client::db::fmt_g6(warp)));
    }
    if !loaded.expanded && overrides.is_empty() {
        return Ok(args.mission.clone());
    }
    let mut out = String::new();
    let mut depth = 0usize;
    let mut written = vec![false; overrides.len()];
    for line in loaded.text.lines() {
        let t = line.trim_start();
        if t.starts_with('{') {
            depth += 1;
        } else if t.starts_with('}') {
            depth = depth.saturating_sub(1);
        }
        let key = t.split('=').next().map(str::trim).unwrap_or("");
        let hit = (depth == 0 && t.contains('='))
            .then(|| {
                overrides
                    .iter()
                    .position(|(k, _)| key.eq_ignore_ascii_case(k))
            })
            .flatten();
        match hit {
            Some(i) => {
                out.push_str(&format!("{} = {}\n", overrides[i].0, overrides[i].1));
                written[i] = true;
            }
            None => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    for (i, (k, v)) in overrides.iter().enumerate().rev() {
        if !written[i] {
            out.insert_str(0, &format!("{k} = {v}\n"));
        }
    }
    std::fs::create_dir_all(log_dir)
        .map_err(|e| format!("cannot create {}: {e}", log_dir.display()))?;
    let name = args.mission.file_name().map_or_else(
        || "mission.moos".into(),
        |n| n.to_string_lossy().into_owned(),
    );
    let path = log_dir.join(format!("expanded_{name}"));
    std::fs::write(&path, out).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(path)
}

/// Starts the ANTLER apps coug does not build in, from PATH, as pAntler does.
fn start_externals(externals: &[AntlerRun], mission: &Path) -> Vec<Child> {
    let mut children = Vec::new();
    for ext in externals {
        // pAntler's argv: `app mission_file moos_name`.
        let mut cmd = Command::new(&ext.app);
        cmd.arg(mission).arg(ext.moos_name());
        cmd.stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::null());
        match cmd.spawn() {
            Ok(c) => {
                errln!("coug run: started {} (pid {})", ext.app, c.id());
                children.push(c);
            }
            Err(e) => errln!(
                "coug run: warning: {}:{}: cannot start {}: {e}; running without it",
                ext.span.file_name(),
                ext.span.line,
                ext.app
            ),
        }
    }
    children
}

fn realtime(
    args: &RunArgs,
    loaded: &Loaded,
    pokes: Vec<Poke>,
    until: Option<Condition>,
    log_dir: &Path,
) -> Result<i32, Vec<String>> {
    let (globals, _) = MissionGlobals::from_mission(&loaded.mission);
    let warp_f = args.warp.unwrap_or(globals.time_warp);
    let warp = Warp::new(warp_f).map_err(|e| vec![format!("--warp {warp_f}: {e}")])?;
    let port = args.port.unwrap_or(globals.server_port);
    let host = if globals.server_host.eq_ignore_ascii_case("localhost") {
        "127.0.0.1".to_string()
    } else {
        globals.server_host.clone()
    };
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .map_err(|e| vec![e.to_string()])?;
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
            .map_err(|_| vec![format!("cannot resolve ServerHost {host}")])?;
        let mut sc = ServerConfig::with_addr(addr);
        sc.warp = warp;
        sc.db.community = globals.community.clone();
        let server = Server::bind(sc)
            .await
            .map_err(|e| vec![format!("cannot listen on {addr}: {e}")])?;
        let port = server.local_addr().port();
        errln!(
            "coug run: MOOSDB_{} listening on {} (warp {warp_f})",
            globals.community,
            server.local_addr()
        );
        let start = moosdb_client::time::unix_now() * warp_f;
        let opened = wall_now();
        let (target, sink) = log_target(loaded, log_dir, opened);
        let p = make_plan(loaded, start, args.seed, Some(target)).map_err(|e| vec![e])?;
        let alog_path = open_log(loaded, log_dir, opened, &sink).map_err(|e| vec![e])?;
        let mut children = Vec::new();
        if !p.external.is_empty() {
            let path = mission_for_externals(args, loaded, &globals, port, warp_f, log_dir)
                .map_err(|e| vec![e])?;
            children = start_externals(&p.external, &path);
        }
        let cfg = RemoteConfig {
            host: addr.ip().to_string(),
            port,
            warp: warp_f,
        };
        let spec = RunSpec {
            pokes,
            until,
            max_time: args.max_time,
        };
        let terminal = std::io::stderr().is_terminal();
        let wall = Instant::now();
        let db = &server;
        let every = args.progress_every;
        db.with_db(|d| d.tap("IVPHELM_SUMMARY"));
        let progress_task = async move {
            let mut progress = Progress::default();
            let mut tick =
                tokio::time::interval(Duration::from_millis(if terminal { 200 } else { 50 }));
            loop {
                tick.tick().await;
                let now = moosdb_client::time::unix_now() * warp_f;
                let get = |k: &str| -> Option<Value> {
                    db.with_db(|d| d.current(k))
                        .and_then(|m| match m.data_type {
                            moosdb_client::DataType::Double => Some(Value::Double(m.dval)),
                            moosdb_client::DataType::String => {
                                Some(Value::String(m.sval_str().into_owned().into()))
                            }
                            _ => None,
                        })
                };
                for m in db.with_db(|d| d.take_taps()) {
                    progress.observe_summary(&m.sval_str());
                }
                progress.tick(now - start, &wall, &get, terminal, every);
            }
        };
        let result = tokio::select! {
            r = run_apps(p.apps, &cfg, spec) => Some(r),
            _ = super::signal::shutdown() => None,
            _ = progress_task => unreachable!("the progress loop never ends"),
        };
        let wall = wall.elapsed().as_secs_f64();
        if terminal {
            errln!();
        }
        for mut c in children {
            let _ = c.kill();
            let _ = c.wait();
        }
        server.shutdown();
        let Some(result) = result else {
            close_log(&sink, &alog_path)?;
            errln!("coug run: interrupted after {wall:.1} wall s; log: {alog_path}");
            return Ok(130);
        };
        // An app's failure (a log that could not be written) fails the run.
        let end = result.map_err(|e| match e {
            runtime::remote::RemoteError::App(e) => app_failed(&e, &alog_path),
            e => vec![e.to_string()],
        })?;
        close_log(&sink, &alog_path)?;
        let ended = Ended {
            outcome: end.outcome,
            start,
            wall,
            until_values: end.values,
        };
        Ok(finish(args, &ended, Some(&alog_path)))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, text: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("coug-run-load-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let path = dir.join(name);
        std::fs::write(&path, text).expect("write mission");
        path
    }

    #[test]
    fn lines_moos_skips_are_skipped_but_blocks_moos_cannot_find_stop_the_run() {
        // Free text, a banner and a `#` line: MOOS ignores them, and so does the run.
        let ok = write(
            "skips.moos",
            "ServerPort = 9000\nMIT Sailing Pavilion (use this one)\n=====\n\
             ProcessConfig = ANTLER\n{\n  # Linux:\n  Run = MOOSDB @ NewConsole = false\n}\n",
        );
        let loaded = load(&ok, &[], &[]).unwrap_or_else(|e| panic!("{e:?}"));
        assert_eq!(loaded.mission.antler_runs().len(), 1);
        assert_eq!(loaded.mission.global("ServerPort"), Some("9000"));
        // A block without its `{`: the app would run without its configuration.
        let bad = write(
            "nobrace.moos",
            "ServerPort = 9000\nProcessConfig = ANTLER\n  Run = MOOSDB\n}\n",
        );
        let errors = load(&bad, &[], &[]).err().expect("refused");
        assert!(
            errors[0].contains("is not followed by its block"),
            "{errors:?}"
        );
    }
}
