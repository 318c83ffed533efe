//! A whole mission run as a library: what `coug run` does, callable in process.
//!
//! [`load`] preprocesses and parses a `.moos` file and each helm's behaviour files;
//! [`validate`] finds what the run would warn about or refuse; [`run`] plans the ANTLER
//! apps (every built-in from [`crate::antler::BUILT_INS`], the helm among them), opens the
//! pLogger session on disk and runs the apps in lockstep on the virtual clock or in real
//! time on a TCP MOOSDB, until the `until` condition holds, the time runs out, every app
//! finishes or the caller asks it to stop. It returns a [`RunReport`]: how the run ended,
//! the `until` values, the alog's path and its totals (counted while it was written: those
//! reading it back would give).
//!
//! Printing, Ctrl-C and exit codes are the caller's: an [`Observer`] is told the run's
//! warnings and notices, every `IVPHELM_SUMMARY` and, about once per simulated second (or
//! every 50 ms of wall time in real time), the DB's current values; its
//! [`Observer::stop_requested`] ends the run cleanly (log flushed and closed).

use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};

use chrono::NaiveDateTime;
use mission::Parsed;
use mission::bhv::BehaviorFile;
use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::{MissionFile, parse_moos};
use mission::nsplug::{Options, preprocess};
use mission::source::FsSource;
use thiserror::Error;

use crate::antler::{HelmFiles, LaunchError, LogTarget, Plan, logger_config, plan};
use crate::helm::load_behaviors;

mod fleet;
mod options;
mod realtime;
mod report;
mod run;
pub(crate) mod tally;

pub use fleet::{FleetOptions, FleetReport, fleet_port, run_fleet, validate_fleet};
pub use options::{Mode, Observer, Quiet, RunOptions};
pub use realtime::mission_for_externals;
pub use report::{Ended, LogTotals, RunReport};
pub use run::{SessionError, run};

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
        self.plan_shared(start, seed, log, crate::shared::Shared::new())
    }

    /// As [`LoadedMission::plan`], the apps sharing `shared` with the other communities of
    /// the run (a fleet).
    pub fn plan_shared(
        &self,
        start: f64,
        seed: u64,
        log: Option<LogTarget>,
        shared: crate::shared::Shared,
    ) -> Result<Plan, LaunchError> {
        let mut launch = crate::antler::Launch::new(start, seed)
            .with_helm_files(self.helm_files())
            .with_shared(shared);
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
