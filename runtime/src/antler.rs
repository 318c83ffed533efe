//! Launching a mission in-process: the ANTLER block's `Run` lines resolved against coug's
//! built-in apps (what pAntler does with processes, done with [`App`]s on one bus).
//!
//! The apps coug builds in are one registry, [`BUILT_INS`]: `MOOSDB` (the bus itself),
//! `pHelmIvP`, `uSimMarine(V22)`, `pMarinePID(V22)`, `pNodeReporter`, `pLogger`,
//! `uTimerScript`, `uSimSensors`, `pNavGraph`, `pSafety`, `pCougControls`, `uSimCougUV`,
//! `pShare`, the device drivers `iGPS`, `iDVL`, `iSeaTrac`, `iTeensy`, `uSimDevices` (the
//! CougUV behind the device emulators), and `pAcomms` and `uSimModem` (the acoustic network
//! and its simulated modem). A caller's `custom`
//! factory is asked first for every `Run` line (tests with in-memory behaviours, user apps);
//! what nobody builds is listed in [`Plan::external`] for the caller to start from PATH (real
//! time) or skip with a warning
//! (lockstep). Each app reads the `ProcessConfig` block of its MOOS name (the alias after
//! `~`, as MOOS apps do).

use std::collections::HashMap;
use std::io::Write;
use std::path::PathBuf;

use chrono::NaiveDateTime;
use mission::Parsed;
use mission::bhv::BehaviorFile;
use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::{AntlerRun, MissionFile, ProcessConfig};
use mission::nsplug::Options;
use mission::source::{FsSource, Span};
use thiserror::Error;
use vehicle::geodesy::LocalGrid;

use crate::app::App;
use crate::helm::HelmApp;
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
    pub fn from_mission(m: &MissionFile) -> (MissionGlobals, Vec<Diagnostic>) {
        let mut warnings = Vec::new();
        let mut num = |key: &str| -> Option<f64> {
            let p = m.globals.iter().find(|p| p.is(key))?;
            let v = &p.value;
            match v.trim().parse::<f64>() {
                Ok(x) if x.is_finite() => Some(x),
                _ => {
                    warnings.push(Diagnostic::line_warning(
                        DiagnosticKind::BadGlobal,
                        &p.span,
                        format!("{key} = {v}: not a number, ignored"),
                    ));
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
                let at = m.globals.iter().find(|g| g.is("ServerPort"));
                warnings.push(Diagnostic::line_warning(
                    DiagnosticKind::BadGlobal,
                    &at.map_or_else(|| Span::new("mission", 0, 0), |g| g.span.clone()),
                    format!("ServerPort = {p}: not a port, using 9000"),
                ));
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
    pub writer: Box<dyn Write + Send>,
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
    /// Non-fatal findings, each at its line.
    pub warnings: Vec<Diagnostic>,
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

/// A factory for apps the caller builds itself (a test's in-memory helm, a user's app):
/// `Some` to take the `Run` line (an app, or an error message), `None` to leave it to the
/// built-ins.
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

/// Where each helm reads its behaviour files: the mission's folder (relative `behaviors =`
/// paths), the nsplug options they are expanded with, and the files already read (by the
/// helm's MOOS name) so a run and its check read them once.
#[derive(Debug, Clone, Default)]
pub struct HelmFiles {
    /// The mission file's folder.
    pub dir: PathBuf,
    /// How the behaviour files are preprocessed (RESTART_HELM reads them again so).
    pub opts: Options,
    /// Behaviour files already read, by helm MOOS name (see [`crate::helm::load_behaviors`]); a helm not
    /// in here reads its files when it is built.
    pub loaded: HashMap<String, Result<Parsed<BehaviorFile>, Vec<String>>>,
}

/// Everything building a mission's apps needs besides the mission itself.
pub struct Launch {
    /// The MOOS time the run starts at.
    pub start: f64,
    /// Seeds every random draw (each app that draws mixes in its MOOS name).
    pub seed: u64,
    /// Where pLogger writes (taken by the first pLogger; none: pLogger is not run).
    pub log: Option<LogTarget>,
    /// Where the helms read their behaviour files.
    pub helm_files: HelmFiles,
    /// Objects shared with the other communities of the run (a fleet run gives every
    /// community's launch the same set; a single mission its own).
    pub shared: crate::shared::Shared,
}

impl Launch {
    /// A launch at MOOS time `start` with `seed`, no log target and behaviour files read
    /// relative to the current directory.
    pub fn new(start: f64, seed: u64) -> Launch {
        Launch {
            start,
            seed,
            log: None,
            helm_files: HelmFiles::default(),
            shared: crate::shared::Shared::new(),
        }
    }

    /// The same launch writing its log to `log`.
    pub fn with_log(mut self, log: LogTarget) -> Launch {
        self.log = Some(log);
        self
    }

    /// The same launch sharing `shared` with other communities of the run.
    pub fn with_shared(mut self, shared: crate::shared::Shared) -> Launch {
        self.shared = shared;
        self
    }

    /// The same launch reading behaviour files as `files` says.
    pub fn with_helm_files(mut self, files: HelmFiles) -> Launch {
        self.helm_files = files;
        self
    }
}

/// One app being built: its program and MOOS name, its block, the mission and the launch.
pub struct BuildCx<'a> {
    /// The program's base name (`uSimMarineV22`).
    pub program: &'a str,
    /// The MOOS name it runs under.
    pub moos_name: &'a str,
    /// Its `ProcessConfig` block, if the mission has one.
    pub block: Option<ProcessConfig>,
    /// The mission.
    pub mission: &'a MissionFile,
    /// The mission's globals.
    pub globals: &'a MissionGlobals,
    /// The launch settings.
    pub launch: &'a mut Launch,
    /// Where non-fatal findings go.
    pub warnings: &'a mut Vec<Diagnostic>,
}

impl BuildCx<'_> {
    /// The block, or an empty one named after the MOOS name (every setting at its default).
    fn block_or_empty(&mut self) -> ProcessConfig {
        self.block.take().unwrap_or_else(|| ProcessConfig {
            name: self.moos_name.to_string(),
            span: mission::source::Span::new(
                &format!("(no ProcessConfig = {})", self.moos_name),
                0,
                0,
            ),
            entries: Vec::new(),
        })
    }

    /// Hands `app` to the launch: with the mission's appcast globals, its configuration
    /// findings added to the launch's warnings (less those it gives as MALCONFIG reasons,
    /// which are reported as such), boxed.
    pub fn launched<A: BuiltInApp>(&mut self, app: A) -> Result<Built, LaunchError> {
        self.launched_then(app, |app, _| app)
    }

    /// [`BuildCx::launched`], with `then` applied to the app once it has its globals.
    pub fn launched_then<A: BuiltInApp>(
        &mut self,
        app: A,
        then: impl FnOnce(A, &Launch) -> A,
    ) -> Result<Built, LaunchError> {
        let app =
            app.with_appcast_globals(self.mission.global("Community"), self.globals.time_warp);
        let app = then(app, self.launch);
        let malconfig = app.malconfig();
        self.warnings.extend(
            app.warnings()
                .iter()
                .filter(|w| !malconfig.contains(&w.located()))
                .cloned(),
        );
        Ok(Built::App(Box::new(app)))
    }
}

/// What every built-in app hands its launch: the configuration findings of its block, and a
/// way to take the mission's `Community` and `MOOSTimeWarp` for its appcasts.
/// [`BuildCx::launched`] applies both, so a `make` function builds the app and hands it over.
pub trait BuiltInApp: App + Sized + 'static {
    /// The block's configuration findings, each at its line (`coug check` and `coug run`
    /// report them; one that is also a [`App::malconfig`] reason is reported there only).
    fn warnings(&self) -> &[Diagnostic];

    /// The same app with the mission's `Community` and `MOOSTimeWarp` for its appcasts (the
    /// node name, the real-time rate limit); the block's appcasting keys are read again with
    /// them.
    fn with_appcast_globals(self, community: Option<&str>, warp: f64) -> Self;
}

/// One app coug builds in: the program name pAntler runs, what it does, and how it is made.
/// [`BUILT_INS`] is the one list: the planner, the single-app mode, `coug install-aliases`
/// and the checks all read it, so adding an app is adding an entry.
pub struct BuiltIn {
    /// The program name (a `Run` line's base name, and the alias name).
    pub program: &'static str,
    /// What the app does, for its usage text.
    pub what: &'static str,
    /// True when the app reads a `ProcessConfig` block of its MOOS name (the MOOSDB reads
    /// only the globals).
    pub reads_block: bool,
    make: fn(&mut BuildCx<'_>) -> Result<Built, LaunchError>,
}

/// Every app coug builds in, MOOSDB first.
pub const BUILT_INS: &[BuiltIn] = &[
    BuiltIn {
        program: "MOOSDB",
        what: "the MOOS database",
        reads_block: false,
        make: |_| Ok(Built::Db),
    },
    BuiltIn {
        program: "pHelmIvP",
        what: "the IvP helm",
        reads_block: true,
        make: make_helm,
    },
    BuiltIn {
        program: "uSimMarine",
        what: "the marine vehicle simulator",
        reads_block: true,
        make: make_simulator,
    },
    BuiltIn {
        program: "uSimMarineV22",
        what: "the marine vehicle simulator",
        reads_block: true,
        make: make_simulator,
    },
    BuiltIn {
        program: "pMarinePID",
        what: "the heading, speed and depth PID controller",
        reads_block: true,
        make: make_pid,
    },
    BuiltIn {
        program: "pMarinePIDV22",
        what: "the heading, speed and depth PID controller",
        reads_block: true,
        make: make_pid,
    },
    BuiltIn {
        program: "pNodeReporter",
        what: "node reports (NODE_REPORT_LOCAL)",
        reads_block: true,
        make: make_node_reporter,
    },
    BuiltIn {
        program: "pLogger",
        what: "the logger (alog, ._moos and requested copies)",
        reads_block: true,
        make: make_logger,
    },
    BuiltIn {
        program: "uTimerScript",
        what: "timed postings from a script",
        reads_block: true,
        make: make_timer_script,
    },
    BuiltIn {
        program: "uSimSensors",
        what: "simulated DVL, AHRS, pressure and GPS from the simulator's truth",
        reads_block: true,
        make: make_sensors,
    },
    BuiltIn {
        program: "pNavGraph",
        what: "the factor-graph navigator (NAV_* from the DVL, AHRS, pressure and GPS)",
        reads_block: true,
        make: make_navigator,
    },
    BuiltIn {
        program: "pSafety",
        what: "the safety supervisor (rules: leak, battery, depth, stale sensors, navigation, comms, silent apps)",
        reads_block: true,
        make: make_safety,
    },
    BuiltIn {
        program: "pCougControls",
        what: "the CoUGARs heading and depth-pitch cascade with fin mixing (fins and thrust for the Teensy)",
        reads_block: true,
        make: make_coug_controls,
    },
    BuiltIn {
        program: "uSimCougUV",
        what: "the CougUV simulator (three fins and a thruster; truth as uSimMarine posts it)",
        reads_block: true,
        make: make_couguv_sim,
    },
    BuiltIn {
        program: "pShare",
        what: "the UDP bridge between MOOS communities (wire-compatible with MOOS's pShare)",
        reads_block: true,
        make: make_pshare,
    },
    BuiltIn {
        program: "iGPS",
        what: "the GPS driver (NMEA 0183 on a serial port, or gpsd over TCP)",
        reads_block: true,
        make: make_gps,
    },
    BuiltIn {
        program: "iDVL",
        what: "the Water Linked DVL A50 driver (JSON over TCP)",
        reads_block: true,
        make: make_dvl,
    },
    BuiltIn {
        program: "iSeaTrac",
        what: "the SeaTrac X150 USBL modem and AHRS driver (serial)",
        reads_block: true,
        make: make_seatrac,
    },
    BuiltIn {
        program: "iTeensy",
        what: "the Teensy driver: fins and thruster out, pressure, battery and leak in (serial)",
        reads_block: true,
        make: make_teensy,
    },
    BuiltIn {
        program: "uSimDevices",
        what: "the CougUV model behind the device emulators (hardware in the loop: coug run --emulate)",
        reads_block: true,
        make: make_sim_devices,
    },
    BuiltIn {
        program: "pAcomms",
        what: "the polled acoustic network: polls, authenticated commands, contact reports from USBL fixes",
        reads_block: true,
        make: make_acomms,
    },
    BuiltIn {
        program: "uSimModem",
        what: "the simulated acoustic modem on a channel shared by the run's communities",
        reads_block: true,
        make: make_sim_modem,
    },
    BuiltIn {
        program: "pBasicContactMgr",
        what: "the contact manager: contacts from NODE_REPORTs, alerts that spawn the helm's contact behaviours",
        reads_block: true,
        make: make_contact_mgr,
    },
    BuiltIn {
        program: "uFldNodeBroker",
        what: "a vehicle's side of the fleet handshake: pings its shore hosts, bridges its variables once acknowledged",
        reads_block: true,
        make: make_node_broker,
    },
    BuiltIn {
        program: "uFldShoreBroker",
        what: "the shoreside's side of the fleet handshake: acknowledges vehicles, bridges commands to each",
        reads_block: true,
        make: make_shore_broker,
    },
    BuiltIn {
        program: "pObstacleMgr",
        what: "the obstacle manager: obstacle polygons from sensed points or given shapes, alerts that spawn the helm's obstacle behaviours",
        reads_block: true,
        make: make_obstacle_mgr,
    },
    BuiltIn {
        program: "pContactMgrV20",
        what: "the V20 contact manager: contacts from NODE_REPORTs (filtered, x/y from lat/lon), alerts that spawn the helm's contact behaviours",
        reads_block: true,
        make: make_contact_mgr_v20,
    },
    BuiltIn {
        program: "uFldNodeComms",
        what: "the shoreside's node-report relay: each vehicle's NODE_REPORT to the others within comms range, NODE_MESSAGE routing",
        reads_block: true,
        make: make_node_comms,
    },
    BuiltIn {
        program: "uFldObstacleSim",
        what: "the obstacle simulator: obstacles from a file as given obstacles or sensed points, random lifetimes, regenerated fields",
        reads_block: true,
        make: make_obstacle_sim,
    },
];

/// The built-in app run by `program` (a path or base name), if coug builds it in.
pub fn built_in(program: &str) -> Option<&'static BuiltIn> {
    let b = base(program);
    BUILT_INS.iter().find(|a| a.program == b)
}

fn make_helm(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let files = &cx.launch.helm_files;
    let name = cx.moos_name;
    // A bad configuration never stops the helm: it runs in MALCONFIG and says why.
    let app = match files.loaded.get(name) {
        Some(b) => HelmApp::from_behaviors(name, cx.mission, b.as_ref().map_err(Vec::as_slice))
            .with_reload(cx.mission, &files.dir, &files.opts),
        None => HelmApp::from_mission_files(name, cx.mission, &files.dir, &files.opts, &FsSource),
    };
    Ok(Built::App(Box::new(app)))
}

fn make_simulator(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let legacy = cx.program == "uSimMarine";
    let b = cx.block_or_empty();
    let v = VehicleApp::simulator(cx.moos_name, b, cx.globals.grid(), cx.launch.start, legacy)?;
    cx.launched(v)
}

fn make_pid(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let legacy = cx.program == "pMarinePID";
    let b = cx.block_or_empty();
    let v = VehicleApp::marine_pid(cx.moos_name, b, legacy)?;
    cx.launched(v)
}

fn make_node_reporter(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    let v = VehicleApp::node_reporter(
        cx.moos_name,
        b,
        &cx.globals.community,
        cx.launch.start,
        cx.globals.grid(),
        cx.launch.seed ^ fnv(cx.moos_name),
    )?;
    cx.launched(v)
}

fn make_logger(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    // Its warnings are the block's, said whether or not it runs.
    if let Some(b) = &cx.block {
        cx.warnings.extend(LoggerConfig::warnings(b));
    }
    let Some(t) = cx.launch.log.take() else {
        return Ok(Built::NoLogTarget);
    };
    let app = Logger::new(
        cx.moos_name,
        cx.block.take(),
        t.config,
        t.writer,
        &t.opened,
        &t.opened_on,
    )
    .with_side_files(t.side)
    .with_community(&cx.globals.community);
    cx.launched(app)
}

fn make_timer_script(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    let seed = cx.launch.seed ^ fnv(cx.moos_name);
    let ts = TimerScript::new(cx.moos_name, b, &cx.globals.community, seed)?;
    cx.launched(ts)
}

fn make_sensors(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    let seed = cx.launch.seed ^ fnv(cx.moos_name);
    cx.launched(crate::sensors::SensorsApp::new(
        cx.moos_name,
        b,
        cx.globals.grid(),
        seed,
    ))
}

fn make_navigator(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    cx.launched(crate::navigator::NavApp::new(
        cx.moos_name,
        b,
        cx.globals.grid(),
    ))
}

fn make_safety(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    cx.launched(crate::safety::SafetyApp::new(cx.moos_name, b))
}

fn make_coug_controls(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    cx.launched(crate::cougars::CougControlsApp::new(cx.moos_name, b))
}

fn make_couguv_sim(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    cx.launched(crate::cougars::CougUvSimApp::new(
        cx.moos_name,
        b,
        cx.globals.grid(),
    ))
}

fn make_contact_mgr(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    let community = &cx.globals.community;
    cx.launched(crate::contact_mgr::ContactMgrApp::new(
        cx.moos_name,
        b,
        community,
        cx.globals.grid(),
    ))
}

fn make_contact_mgr_v20(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    let app = crate::contact_mgr::ContactMgrApp::new_v20(
        cx.moos_name,
        b,
        &cx.globals.community,
        cx.globals.grid(),
    );
    cx.launched(app)
}

fn make_node_comms(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    let seed = cx.launch.seed ^ fnv(cx.moos_name);
    let app = crate::node_comms::NodeCommsApp::new(cx.moos_name, b, cx.globals.grid(), seed)
        .with_globals(cx.mission.global("Community"), cx.globals.time_warp);
    cx.launched(app)
}

fn make_obstacle_mgr(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    cx.launched(crate::obstacle_mgr::ObstacleMgrApp::new(cx.moos_name, b))
}

fn make_obstacle_sim(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    let app = crate::obstacle_mgr::sim::ObstacleSimApp::new(
        cx.moos_name,
        b,
        &cx.launch.helm_files.dir,
        cx.launch.seed ^ fnv(cx.moos_name),
        cx.globals.grid(),
    );
    cx.launched(app)
}

fn make_pshare(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    let app = crate::pshare::PShareApp::new(cx.moos_name, b);
    // After the globals: joining the run's radio may note a warning on the new appcast.
    cx.launched_then(app, |app, launch| app.with_shared(&launch.shared))
}

fn make_node_broker(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    let g = cx.globals;
    let app = crate::brokers::NodeBrokerApp::new(
        cx.moos_name,
        b,
        &g.community,
        g.server_port,
        g.time_warp,
    )
    .with_shared(&cx.launch.shared);
    cx.launched(app)
}

fn make_shore_broker(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    let g = cx.globals;
    let app = crate::brokers::ShoreBrokerApp::new(
        cx.moos_name,
        b,
        &g.community,
        g.server_port,
        g.time_warp,
    )
    .with_shared(&cx.launch.shared);
    cx.launched(app)
}

fn make_gps(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    cx.launched(crate::driver_apps::gps(cx.moos_name, b, cx.globals.grid()))
}

fn make_dvl(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    cx.launched(crate::driver_apps::dvl(cx.moos_name, b))
}

fn make_seatrac(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    cx.launched(crate::driver_apps::seatrac(cx.moos_name, b))
}

fn make_teensy(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    cx.launched(crate::driver_apps::teensy(cx.moos_name, b))
}

fn make_sim_devices(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    // The fin kinematics are pCougControls': its block, found by its ANTLER run.
    let controls = cx
        .mission
        .antler_runs()
        .into_iter()
        .find(|r| base(&r.app) == "pCougControls")
        .and_then(|r| cx.mission.process(r.moos_name()));
    let app = crate::hil::SimDevicesApp::new(
        cx.moos_name,
        b,
        cx.globals.grid(),
        controls,
        cx.launch.start,
    );
    cx.launched(app)
}

fn make_acomms(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    cx.launched(crate::acomms_apps::AcommsApp::new(cx.moos_name, b))
}

fn make_sim_modem(cx: &mut BuildCx<'_>) -> Result<Built, LaunchError> {
    let b = cx.block_or_empty();
    let l = &cx.launch;
    let app = crate::acomms_apps::SimModemApp::new(cx.moos_name, b, &l.shared, l.seed);
    cx.launched(app)
}

/// Builds the built-in app `program` (a path or base name such as `uSimMarineV22`) running
/// as MOOS name `moos_name`, from the mission's block of that name (defaults without one).
/// Used for every `Run` line by [`plan`], and alone by the single-app mode. Non-fatal
/// findings are appended to `warnings`.
pub fn build(
    program: &str,
    moos_name: &str,
    m: &MissionFile,
    globals: &MissionGlobals,
    launch: &mut Launch,
    warnings: &mut Vec<Diagnostic>,
) -> Result<Built, LaunchError> {
    let Some(app) = built_in(program) else {
        return Ok(Built::Unknown);
    };
    let mut cx = BuildCx {
        program: app.program,
        moos_name,
        block: m.process(moos_name).cloned(),
        mission: m,
        globals,
        launch,
        warnings,
    };
    (app.make)(&mut cx)
}

/// Resolves the ANTLER block. `launch` gives the MOOS start time, the seed of every random
/// draw, where pLogger writes (a pLogger is added first when the block runs none; without a
/// target pLogger is skipped with a warning) and where the helms read their behaviours.
/// `custom` is consulted first for every `Run` line.
pub fn plan(
    m: &MissionFile,
    mut launch: Launch,
    custom: &mut CustomFactory<'_>,
) -> Result<Plan, LaunchError> {
    let runs = m.antler_runs();
    if runs.is_empty() {
        return Err(LaunchError::NoAntler);
    }
    let (globals, mut warnings) = MissionGlobals::from_mission(m);
    if globals.origin.is_some()
        && globals.grid().is_none()
        && let Some(lat) = m.globals.iter().find(|p| p.is("LatOrigin"))
    {
        warnings.push(Diagnostic::line_warning(
            DiagnosticKind::BadGlobal,
            &lat.span,
            "LatOrigin/LongOrigin: not a valid origin; no NAV_LAT/NAV_LONG",
        ));
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
    if !has_logger && let Some(t) = launch.log.take() {
        plan.apps.push(Box::new(
            Logger::new("pLogger", None, t.config, t.writer, &t.opened, &t.opened_on)
                .with_side_files(t.side)
                .with_appcast_globals(m.global("Community"), plan.globals.time_warp),
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
            &mut launch,
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
            Built::NoLogTarget => warnings.push(Diagnostic::line_warning(
                DiagnosticKind::AppNotRun,
                &run.span,
                format!("{name}: no log target given; not logging"),
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

    fn corpus_dir(rel: &str) -> PathBuf {
        PathBuf::from(format!(
            "{}/../../shared/corpus/moos-ivp-missions/{rel}",
            env!("CARGO_MANIFEST_DIR")
        ))
    }

    fn corpus(rel: &str) -> MissionFile {
        let text = test_support::mission_text(rel);
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
        let files = HelmFiles {
            dir: corpus_dir("s1_alpha"),
            ..HelmFiles::default()
        };
        let launch = Launch::new(0.0, 1)
            .with_log(target())
            .with_helm_files(files);
        let p = plan(&m, launch, &mut |_, _| None).unwrap();
        assert_eq!(
            names(&p),
            vec![
                "pLogger",
                "uSimMarineV22",
                "pMarinePIDV22",
                "pHelmIvP",
                "pNodeReporter"
            ]
        );
        // The helm is built in and read its behaviours beside the mission.
        let helm = p.apps.iter().find(|a| a.name() == "pHelmIvP").unwrap();
        assert_eq!(helm.malconfig(), Vec::<String>::new());
        let ext: Vec<&str> = p.external.iter().map(|r| r.app.as_str()).collect();
        assert_eq!(ext, vec!["pMarineViewer", "uProcessWatch", "pRealm"]);
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
        let p = plan(&m, Launch::new(0.0, 1), &mut |run, block| {
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
        let p = plan(&m, Launch::new(0.0, 1), &mut |_, _| None).unwrap();
        assert_eq!(
            names(&p),
            vec![
                "uSimMarine",
                "pNodeReporter",
                "pMarinePID",
                "pHelmIvP",
                "uTimerScript"
            ]
        );
        assert!(
            p.warnings
                .iter()
                .any(|w| w.kind == DiagnosticKind::AppNotRun && w.message.contains("not logging")),
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
        let mut log = Launch::new(0.0, 1);
        let b = build("uSimMarineV22", "uSimMarineV22", &m, &g, &mut log, &mut w).unwrap();
        let Built::App(sim) = b else {
            panic!("no simulator")
        };
        assert_eq!((sim.name(), sim.app_tick()), ("uSimMarineV22", 4.0));
        // An alias without its own block runs with defaults, or says what it lacks.
        let b = build("/usr/bin/pNodeReporter", "rep2", &m, &g, &mut log, &mut w).unwrap();
        let Built::App(rep) = b else {
            panic!("no reporter")
        };
        assert_eq!((rep.name(), rep.app_tick()), ("rep2", 5.0));
        // A PID without its gains runs (with zero gains), as pMarinePIDV22 does, and says
        // what it lacks.
        w.clear();
        let b = build("pMarinePIDV22", "pid2", &m, &g, &mut log, &mut w).unwrap();
        assert!(matches!(b, Built::App(_)));
        assert!(
            w.iter().any(
                |x| x.to_string().starts_with("(no ProcessConfig = pid2):0: ")
                    && x.message.contains("yaw_pid_kp")
            ),
            "{w:?}"
        );
        assert!(matches!(
            build("MOOSDB", "MOOSDB", &m, &g, &mut log, &mut w),
            Ok(Built::Db)
        ));
        assert!(matches!(
            build("pLogger", "pLogger", &m, &g, &mut log, &mut w),
            Ok(Built::NoLogTarget)
        ));
        // The helm is built in; without its behaviour file (read from the current folder
        // here) it runs in MALCONFIG and says why, as pHelmIvP does.
        let Ok(Built::App(helm)) = build("pHelmIvP", "pHelmIvP", &m, &g, &mut log, &mut w) else {
            panic!("no helm")
        };
        assert!(
            helm.malconfig().iter().any(|e| e.contains("alpha.bhv")),
            "{:?}",
            helm.malconfig()
        );
        assert!(matches!(
            build("pMarineViewer", "pMarineViewer", &m, &g, &mut log, &mut w),
            Ok(Built::Unknown)
        ));
    }

    #[test]
    fn each_config_finding_is_reported_once_as_a_warning_or_as_malconfig() {
        // pSafety's findings make it MALCONFIG (reported as such), pCougControls' only warn.
        let text = "ProcessConfig = ANTLER\n{\n  Run = pSafety\n  Run = pCougControls\n}\n\
                    ProcessConfig = pSafety\n{\n  bogus_key = 1\n}\n\
                    ProcessConfig = pCougControls\n{\n  other_key = 2\n}\n";
        let m = mission::moos::parse_moos(&SourceMap::from_text("s.moos", text)).value;
        let p = plan(&m, Launch::new(0.0, 1), &mut |_, _| None).unwrap();
        let safety = p.apps.iter().find(|a| a.name() == "pSafety").unwrap();
        assert_eq!(
            safety.malconfig(),
            ["s.moos:8: pSafety: unknown parameter `bogus_key`"]
        );
        let w: Vec<String> = p.warnings.iter().map(Diagnostic::located).collect();
        assert!(!w.iter().any(|w| w.contains("bogus_key")), "{w:?}");
        assert_eq!(
            w.iter().filter(|w| w.starts_with("s.moos:12: ")).count(),
            1,
            "{w:?}"
        );
        assert!(w.iter().any(|w| w.contains("other_key")), "{w:?}");
    }

    #[test]
    fn aliases_pick_their_own_block_and_a_logger_is_added() {
        let text = "Community = c\nProcessConfig = ANTLER\n{\n  Run = MOOSDB @ NewConsole = false\n  \
                    Run = uTimerScript @ NewConsole = false ~ uTS_2\n}\n\
                    ProcessConfig = uTS_2\n{\n  AppTick = 2\n  event = var=X, val=1, time=1\n}\n";
        let m = mission::moos::parse_moos(&SourceMap::from_text("a.moos", text)).value;
        let p = plan(&m, Launch::new(0.0, 1).with_log(target()), &mut |_, _| None).unwrap();
        assert_eq!(names(&p), vec!["pLogger", "uTS_2"]);
        assert_eq!(p.apps[1].app_tick(), 2.0);
        let bad = "ProcessConfig = ANTLER\n{\n  Run = uTimerScript\n}\nProcessConfig = uTimerScript\n{\n  event = var=X, time=abc\n}\n";
        let m = mission::moos::parse_moos(&SourceMap::from_text("b.moos", bad)).value;
        let e = plan(&m, Launch::new(0.0, 1), &mut |_, _| None)
            .err()
            .unwrap();
        assert!(e.to_string().starts_with("b.moos:7: uTimerScript:"), "{e}");
        let none =
            mission::moos::parse_moos(&SourceMap::from_text("c.moos", "Community = x\n")).value;
        assert_eq!(
            plan(&none, Launch::new(0.0, 1), &mut |_, _| None).err(),
            Some(LaunchError::NoAntler)
        );
    }
}
