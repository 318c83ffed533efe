//! Launching a mission in-process: the ANTLER block's `Run` lines resolved against coug's
//! built-in apps (what pAntler does with processes, done with [`App`]s on one bus).
//!
//! Built in here: `MOOSDB` (the bus itself), `pLogger`, `uTimerScript`, `uSimMarine`,
//! `uSimMarineV22`, `pMarinePID`, `pMarinePIDV22`, `pNodeReporter`. Other apps (the helm
//! until its engine lands, viewers, ...) go to the caller's `custom` factory first; what
//! nobody builds is listed in [`Plan::external`] for the caller to start from PATH (real
//! time) or skip with a warning (lockstep). Each app reads the `ProcessConfig` block of
//! its MOOS name (the alias after `~`, as MOOS apps do).

use std::io::Write;

use chrono::NaiveDateTime;
use mission::moos::{AntlerRun, MissionFile, ProcessConfig};
use thiserror::Error;
use vehicle::geodesy::LocalGrid;

use crate::app::App;
use crate::logger::{Logger, LoggerConfig};
use crate::timer_script::{TimerScript, TimerScriptError};
use crate::vehicle::{VehicleApp, VehicleAppError};

/// A mission's top-level settings, with MOOS defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct MissionGlobals {
    /// `Community` (default `#1`).
    pub community: String,
    /// `MOOSTimeWarp` (default 1).
    pub time_warp: f64,
    /// `ServerHost` (default `localhost`).
    pub server_host: String,
    /// `ServerPort` (default 9000).
    pub server_port: u16,
    /// `LatOrigin` and `LongOrigin`, when both are numbers.
    pub origin: Option<(f64, f64)>,
    /// `GlobalLogPath`, if set.
    pub global_log_path: Option<String>,
}

impl MissionGlobals {
    /// Reads the globals; values that are not usable are reported and replaced by the
    /// default (as the MOOS apps do).
    pub fn from_mission(m: &MissionFile) -> (MissionGlobals, Vec<String>) {
        let mut warnings = Vec::new();
        let mut num = |key: &str| -> Option<f64> {
            let v = m.global(key)?;
            match v.trim().parse::<f64>() {
                Ok(x) if x.is_finite() => Some(x),
                _ => {
                    warnings.push(format!("{key} = {v}: not a number, ignored"));
                    None
                }
            }
        };
        let warp = num("MOOSTimeWarp").filter(|w| *w > 0.0).unwrap_or(1.0);
        let port = num("ServerPort");
        let lat = num("LatOrigin");
        let lon = num("LongOrigin");
        let server_port = match port {
            Some(p) if (1.0..=65535.0).contains(&p) && p.fract() == 0.0 => p as u16,
            Some(p) => {
                warnings.push(format!("ServerPort = {p}: not a port, using 9000"));
                9000
            }
            None => 9000,
        };
        let g = MissionGlobals {
            community: m.global("Community").unwrap_or("#1").trim().to_string(),
            time_warp: warp,
            server_host: m
                .global("ServerHost")
                .unwrap_or("localhost")
                .trim()
                .to_string(),
            server_port,
            origin: lat.zip(lon),
            global_log_path: m.global("GlobalLogPath").map(|s| s.trim().to_string()),
        };
        (g, warnings)
    }

    /// The local grid of the origin, if one is set and valid.
    pub fn grid(&self) -> Option<LocalGrid> {
        let (lat, lon) = self.origin?;
        LocalGrid::new(lat, lon).ok()
    }
}

/// Where the built-in pLogger writes.
pub struct LogTarget {
    /// The logger's settings (from [`logger_config`], possibly with a new path).
    pub config: LoggerConfig,
    /// The alog file (opened by the caller at `config.alog_path(&opened)`).
    pub writer: Box<dyn Write>,
    /// The session's date-time (names the files).
    pub opened: NaiveDateTime,
    /// The banner's `FILE OPENED ON` text.
    pub opened_on: String,
    /// The mission copy and requested copies beside the alog (none: the alog only).
    pub side: Option<crate::logger::SideFiles>,
}

/// The settings of a mission's pLogger block (wildcard logging when there is none).
pub fn logger_config(m: &MissionFile) -> LoggerConfig {
    LoggerConfig::from_config(m.process("pLogger"), m.global("GlobalLogPath"))
}

/// A mission resolved into apps.
pub struct Plan {
    /// The apps to schedule, in ANTLER order.
    pub apps: Vec<Box<dyn App>>,
    /// `Run` lines no built-in or custom app handles.
    pub external: Vec<AntlerRun>,
    /// True when the ANTLER block runs MOOSDB.
    pub has_db: bool,
    /// Non-fatal findings, as `file:line: text` where known.
    pub warnings: Vec<String>,
    /// Apps left out because the C++ app would end at start-up with their configuration
    /// ([`App::startup_failure`]), as `file:line: name: why`.
    pub failed: Vec<String>,
    /// The mission's globals.
    pub globals: MissionGlobals,
}

/// A block that cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum LaunchError {
    /// A uTimerScript block.
    #[error(transparent)]
    TimerScript(#[from] TimerScriptError),
    /// A simulator, PID or node-reporter block.
    #[error(transparent)]
    Vehicle(#[from] VehicleAppError),
    /// An app built by the caller's factory refused its block.
    #[error("{file}:{line}: {app}: {message}")]
    Custom {
        /// File of the `Run` line.
        file: String,
        /// Line of the `Run` line.
        line: u32,
        /// The app.
        app: String,
        /// The factory's message.
        message: String,
    },
    /// The mission has no ANTLER block, or it runs nothing.
    #[error("the mission has no ANTLER block with Run lines")]
    NoAntler,
}

/// A factory for apps coug builds outside this crate (e.g. the helm): `Some` to take the
/// `Run` line (an app, or an error message), `None` to leave it.
pub type CustomFactory<'a> =
    dyn FnMut(&AntlerRun, Option<&ProcessConfig>) -> Option<Result<Box<dyn App>, String>> + 'a;

/// FNV-1a (64-bit) of the name's bytes: a per-app seed that does not change between runs.
fn fnv(s: &str) -> u64 {
    use std::hash::Hasher as _;
    let mut h = fnv::FnvHasher::default();
    h.write(s.as_bytes());
    h.finish()
}

/// What [`build`] made of one `Run` line.
pub enum Built {
    /// A built-in app.
    App(Box<dyn App>),
    /// `MOOSDB`: the bus itself.
    Db,
    /// pLogger without a log target: not run.
    NoLogTarget,
    /// Not an app coug builds.
    Unknown,
}

/// The programs [`build`] makes (a `Run` line of one of these uses its ProcessConfig block);
/// the MOOSDB is the run's own.
pub const BUILT_IN: &[&str] = &[
    "pHelmIvP",
    "uSimMarine",
    "uSimMarineV22",
    "pMarinePID",
    "pMarinePIDV22",
    "pNodeReporter",
    "pLogger",
    "uTimerScript",
];

/// Builds the built-in app `program` (a base name such as `uSimMarineV22`) running as
/// MOOS name `moos_name`, from the mission's block of that name (defaults without one).
/// Used for every `Run` line by [`plan`], and alone by the single-app mode. Non-fatal
/// findings are appended to `warnings`.
#[allow(clippy::too_many_arguments)]
pub fn build(
    program: &str,
    moos_name: &str,
    m: &MissionFile,
    globals: &MissionGlobals,
    start: f64,
    seed: u64,
    log: &mut Option<LogTarget>,
    warnings: &mut Vec<String>,
) -> Result<Built, LaunchError> {
    let block = m.process(moos_name).cloned();
    let empty = || ProcessConfig {
        name: moos_name.to_string(),
        span: mission::source::Span::new(&format!("(no ProcessConfig = {moos_name})"), 0, 0),
        entries: Vec::new(),
    };
    if base(program) == "pLogger"
        && let Some(b) = &block
    {
        warnings.extend(LoggerConfig::warnings(b));
    }
    let app: Box<dyn App> = match base(program) {
        "MOOSDB" => return Ok(Built::Db),
        "pLogger" => match log.take() {
            Some(t) => Box::new(
                Logger::new(
                    moos_name,
                    block,
                    t.config,
                    t.writer,
                    &t.opened,
                    &t.opened_on,
                )
                .with_side_files(t.side),
            ),
            None => return Ok(Built::NoLogTarget),
        },
        "uTimerScript" => {
            let b = block.unwrap_or_else(empty);
            let ts = TimerScript::new(moos_name, b, &globals.community, seed ^ fnv(moos_name))?;
            warnings.extend(ts.warnings().iter().cloned());
            Box::new(ts)
        }
        app @ ("uSimMarine" | "uSimMarineV22") => {
            let b = block.unwrap_or_else(empty);
            let legacy = app == "uSimMarine";
            let v = VehicleApp::simulator(moos_name, b, globals.grid(), start, legacy)?
                .with_appcast_globals(m.global("Community"), globals.time_warp);
            warnings.extend(v.warnings().iter().cloned());
            Box::new(v)
        }
        app @ ("pMarinePID" | "pMarinePIDV22") => {
            let legacy = app == "pMarinePID";
            let v = VehicleApp::marine_pid(moos_name, block.unwrap_or_else(empty), legacy)?
                .with_appcast_globals(m.global("Community"), globals.time_warp);
            warnings.extend(v.warnings().iter().cloned());
            Box::new(v)
        }
        "pNodeReporter" => {
            let v = VehicleApp::node_reporter(
                moos_name,
                block.unwrap_or_else(empty),
                &globals.community,
                start,
                globals.grid(),
                seed ^ fnv(moos_name),
            )?
            .with_appcast_globals(m.global("Community"), globals.time_warp);
            warnings.extend(v.warnings().iter().cloned());
            Box::new(v)
        }
        _ => return Ok(Built::Unknown),
    };
    Ok(Built::App(app))
}

/// Resolves the ANTLER block. `start` is the MOOS start time, `seed` seeds every random
/// draw (each uTimerScript gets `seed` mixed with its name), `log` is where pLogger writes
/// (a pLogger is added first when the block runs none; without a target pLogger is
/// skipped with a warning). `custom` is consulted first for every `Run` line.
pub fn plan(
    m: &MissionFile,
    start: f64,
    seed: u64,
    mut log: Option<LogTarget>,
    custom: &mut CustomFactory<'_>,
) -> Result<Plan, LaunchError> {
    let runs = m.antler_runs();
    if runs.is_empty() {
        return Err(LaunchError::NoAntler);
    }
    let (globals, mut warnings) = MissionGlobals::from_mission(m);
    if globals.origin.is_some() && globals.grid().is_none() {
        warnings.push("LatOrigin/LongOrigin: not a valid origin; no NAV_LAT/NAV_LONG".into());
    }
    let mut plan = Plan {
        apps: Vec::new(),
        external: Vec::new(),
        has_db: false,
        warnings: Vec::new(),
        failed: Vec::new(),
        globals,
    };
    let has_logger = runs.iter().any(|r| base(&r.app) == "pLogger");
    if !has_logger && let Some(t) = log.take() {
        plan.apps.push(Box::new(
            Logger::new("pLogger", None, t.config, t.writer, &t.opened, &t.opened_on)
                .with_side_files(t.side),
        ));
    }
    for run in runs {
        let name = run.moos_name().to_string();
        let block = m.process(&name).cloned();
        if let Some(made) = custom(&run, block.as_ref()) {
            match made {
                Ok(app) => plan.apps.push(app),
                Err(message) => {
                    return Err(LaunchError::Custom {
                        file: run.span.file_name().to_string(),
                        line: run.span.line,
                        app: name,
                        message,
                    });
                }
            }
            continue;
        }
        let built = build(
            &run.app,
            &name,
            m,
            &plan.globals,
            start,
            seed,
            &mut log,
            &mut warnings,
        )?;
        match built {
            Built::App(app) => match app.startup_failure() {
                // As pAntler with an app that ends at once: the run goes on without it.
                Some(why) => plan.failed.push(format!(
                    "{}:{}: {name}: {why}",
                    run.span.file_name(),
                    run.span.line
                )),
                None => plan.apps.push(app),
            },
            Built::Db => plan.has_db = true,
            Built::NoLogTarget => warnings.push(format!(
                "{}:{}: {name}: no log target given; not logging",
                run.span.file_name(),
                run.span.line
            )),
            Built::Unknown => plan.external.push(run),
        }
    }
    plan.warnings = warnings;
    Ok(plan)
}

/// The program's base name (`/usr/bin/pLogger` → `pLogger`).
fn base(app: &str) -> &str {
    app.rsplit('/').next().unwrap_or(app)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::logger::SharedBuffer;
    use mission::source::SourceMap;

    fn corpus(rel: &str) -> MissionFile {
        let path = format!(
            "{}/../../shared/corpus/moos-ivp-missions/{rel}",
            env!("CARGO_MANIFEST_DIR")
        );
        let text = std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("corpus file {path} is required: {e}"));
        mission::moos::parse_moos(&SourceMap::from_text(rel, &text)).value
    }

    fn target() -> LogTarget {
        LogTarget {
            config: LoggerConfig::default(),
            writer: Box::new(SharedBuffer::default()),
            opened: chrono::NaiveDate::from_ymd_opt(2026, 1, 2)
                .unwrap()
                .and_hms_opt(3, 4, 5)
                .unwrap(),
            opened_on: "Thu Jan  1 00:00:00 1970".into(),
            side: None,
        }
    }

    fn names(p: &Plan) -> Vec<&str> {
        p.apps.iter().map(|a| a.name()).collect()
    }

    #[test]
    fn alpha_resolves_to_built_ins_and_externals() {
        let m = corpus("s1_alpha/alpha.moos");
        let p = plan(&m, 0.0, 1, Some(target()), &mut |_, _| None).unwrap();
        assert_eq!(
            names(&p),
            vec!["pLogger", "uSimMarineV22", "pMarinePIDV22", "pNodeReporter"]
        );
        let ext: Vec<&str> = p.external.iter().map(|r| r.app.as_str()).collect();
        assert_eq!(
            ext,
            vec!["pHelmIvP", "pMarineViewer", "uProcessWatch", "pRealm"]
        );
        assert!(p.has_db);
        assert_eq!(p.globals.community, "alpha");
        assert_eq!(p.globals.server_port, 9000);
        assert!(p.globals.grid().is_some());
        assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    }

    #[test]
    fn delta_with_a_custom_helm() {
        let m = corpus("s4_delta/delta.moos");
        let mut asked = Vec::new();
        let p = plan(&m, 0.0, 1, None, &mut |run, block| {
            asked.push(run.app.clone());
            (run.app == "pHelmIvP").then(|| {
                assert!(block.is_some_and(|b| b.get("behaviors").is_some()));
                Err::<Box<dyn App>, String>("no helm yet".into())
            })
        })
        .err()
        .unwrap();
        assert_eq!(
            p.to_string(),
            "s4_delta/delta.moos:25: pHelmIvP: no helm yet"
        );
        assert_eq!(asked.last().map(String::as_str), Some("pHelmIvP"));
        let p = plan(&m, 0.0, 1, None, &mut |_, _| None).unwrap();
        assert_eq!(
            names(&p),
            vec!["uSimMarine", "pNodeReporter", "pMarinePID", "uTimerScript"]
        );
        assert!(
            p.warnings.iter().any(|w| w.contains("not logging")),
            "{:?}",
            p.warnings
        );
        assert_eq!(p.globals.community, "henry");
    }

    #[test]
    fn single_apps_are_built_by_program_and_moos_name() {
        let m = corpus("s1_alpha/alpha.moos");
        let (g, _) = MissionGlobals::from_mission(&m);
        let mut w = Vec::new();
        let mut log = None;
        let b = build(
            "uSimMarineV22",
            "uSimMarineV22",
            &m,
            &g,
            0.0,
            1,
            &mut log,
            &mut w,
        )
        .unwrap();
        let Built::App(sim) = b else {
            panic!("no simulator")
        };
        assert_eq!((sim.name(), sim.app_tick()), ("uSimMarineV22", 4.0));
        // An alias without its own block runs with defaults, or says what it lacks.
        let b = build(
            "/usr/bin/pNodeReporter",
            "rep2",
            &m,
            &g,
            0.0,
            1,
            &mut log,
            &mut w,
        )
        .unwrap();
        let Built::App(rep) = b else {
            panic!("no reporter")
        };
        assert_eq!((rep.name(), rep.app_tick()), ("rep2", 5.0));
        // A PID without its gains runs (with zero gains), as pMarinePIDV22 does, and says
        // what it lacks.
        w.clear();
        let b = build("pMarinePIDV22", "pid2", &m, &g, 0.0, 1, &mut log, &mut w).unwrap();
        assert!(matches!(b, Built::App(_)));
        assert!(
            w.iter().any(|x| x.starts_with("(no ProcessConfig = pid2):0: ")
                && x.contains("yaw_pid_kp")),
            "{w:?}"
        );
        assert!(matches!(
            build("MOOSDB", "MOOSDB", &m, &g, 0.0, 1, &mut log, &mut w),
            Ok(Built::Db)
        ));
        assert!(matches!(
            build("pLogger", "pLogger", &m, &g, 0.0, 1, &mut log, &mut w),
            Ok(Built::NoLogTarget)
        ));
        assert!(matches!(
            build("pHelmIvP", "pHelmIvP", &m, &g, 0.0, 1, &mut log, &mut w),
            Ok(Built::Unknown)
        ));
    }

    #[test]
    fn aliases_pick_their_own_block_and_a_logger_is_added() {
        let text = "Community = c\nProcessConfig = ANTLER\n{\n  Run = MOOSDB @ NewConsole = false\n  \
                    Run = uTimerScript @ NewConsole = false ~ uTS_2\n}\n\
                    ProcessConfig = uTS_2\n{\n  AppTick = 2\n  event = var=X, val=1, time=1\n}\n";
        let m = mission::moos::parse_moos(&SourceMap::from_text("a.moos", text)).value;
        let p = plan(&m, 0.0, 1, Some(target()), &mut |_, _| None).unwrap();
        assert_eq!(names(&p), vec!["pLogger", "uTS_2"]);
        assert_eq!(p.apps[1].app_tick(), 2.0);
        let bad = "ProcessConfig = ANTLER\n{\n  Run = uTimerScript\n}\nProcessConfig = uTimerScript\n{\n  event = var=X, time=abc\n}\n";
        let m = mission::moos::parse_moos(&SourceMap::from_text("b.moos", bad)).value;
        let e = plan(&m, 0.0, 1, None, &mut |_, _| None).err().unwrap();
        assert!(e.to_string().starts_with("b.moos:7: uTimerScript:"), "{e}");
        let none =
            mission::moos::parse_moos(&SourceMap::from_text("c.moos", "Community = x\n")).value;
        assert_eq!(
            plan(&none, 0.0, 1, None, &mut |_, _| None).err(),
            Some(LaunchError::NoAntler)
        );
    }
}
