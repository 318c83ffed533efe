//! Hardware in the loop without hardware (issue #15, points 2 and 5): the CougUV's hardware
//! mission run by `coug run` against the four device emulators, which measure the
//! simulator's truth, while the real drivers, navigator and controls run unchanged.
//!
//! Two parts meet through a registry of benches in the process:
//!
//! - [`Bench`]: the four emulators ([`emulate`]) on their usual transports, opened before
//!   the mission is expanded: the GPS as gpsd (JSON on a loopback TCP port the OS picks), the
//!   DVL A50 (loopback TCP, OS-picked port), the SeaTrac X150 and the Teensy (each on a new
//!   pseudo-terminal). [`Bench::macros`] hands their endpoints to the mission as nsplug
//!   macros (`GPS_HOST`, `GPS_PORT`, `DVL_HOST`, `DVL_PORT`, `SEATRAC_DEVICE`,
//!   `TEENSY_DEVICE`), with `EMULATE=true` and the bench's name (`EMULATE_BENCH`), so the
//!   drivers' blocks differ from the vehicle's only in those values, and no port or path is
//!   fixed. The emulators run on their own thread, on a clock warped as the community's
//!   ([`emulate::warp`]), so their rates and timeouts are in the community's seconds.
//!   [`prepare`] reads the bench's settings from the mission (the `uSimDevices` block and the
//!   origin) and starts it.
//! - `uSimDevices` ([`SimDevicesApp`]), an app of the mission's emulated form: it flies the
//!   CougUV model ([`vehicle::couguv`], uSimCougUV's parameters) on what the emulated Teensy
//!   drives (its servo angles and thruster pulse, turned back into fin deflections and
//!   thrust through the vehicle's kinematics), posts the truth as uSimCougUV does
//!   (`SIM_*`), and feeds that truth to the bench's emulators (their
//!   [`emulate::truth::SharedTruth`]). pCougControls' fins thus reach the model only through
//!   iTeensy's `$CONTR` lines and the Teensy's firmware rules (whole degrees, ESC arming,
//!   the command-loss failsafe), and the navigator sees the model only through the drivers.
//!
//! # uSimDevices parameters
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `bench` | none | the bench's name (`$(EMULATE_BENCH)`); without a running bench of that name the model runs and nothing is measured (an appcast warning) |
//! | `vehicle`, `fin_0_direction` .. `fin_2_direction`, `top_fin_offset`, `right_fin_offset`, `left_fin_offset`, `trim_ratio`, `demo_mode` | the mission's pCougControls block's | the fin kinematics the servo angles are undone with ([`vehicle::cougars::KINEMATICS_KEYS`], read by pCougControls' own parser): by default those of the mission's pCougControls (its ANTLER run's block), so one block rules both; set here only for a mission without pCougControls (then any of these lines replaces its kinematics) |
//! | uSimCougUV's (`prefix`, `start_pos`, `buoyancy_rate`, `default_water_depth`, ...) | uSimCougUV's | the model and the truth's prefix, see [`vehicle::couguv`] |
//! | `declination` | 0 | deg east: the X150 writes the magnetic yaw (true heading less it); iSeaTrac's `declination` must match |
//! | `atmospheric_pressure` | 101325 | Pa: the air pressure the Teensy's and the X150's pressure sensors see at the surface |
//! | `gps_max_depth` | the GPS model's | m: the antenna is above water (fixes) while the hull is shallower |
//! | `gps_fault`, `dvl_fault`, `seatrac_fault`, `teensy_fault` | none | repeatable: a fault of that emulator, [`emulate::fault`]'s syntax (`leak@120`, `dropout@60+10`), in mission time: the community's MOOS seconds since the mission's start (the DB's, the `Launch` start; the log's times count from pLogger's start, a fraction of a second later), as the user reads them in the mission and its log. The bench starts the emulators earlier, with their fault plans pending ([`emulate::fault::FaultClock`]); uSimDevices sets the plans' origin at its start-up from the mission's start, the bench's Unix epoch and its warp, so no fault fires in a bench without uSimDevices |
//!
//! The DVL's bottom is the model's `default_water_depth` (30 m unless set).

use std::collections::HashMap;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Mutex, OnceLock, PoisonError};

use emulate::build::{self, Kind, Options, Running, Settings};
use emulate::fault::{FaultClock, FaultPlan};
use emulate::teensy::{TeensyInputs, TeensyPort};
use emulate::transport::{EdgeStats, Endpoint, Transport};
use emulate::truth::SharedTruth;
use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::{MissionFile, ProcessConfig};
use vehicle::ConfigError;
use vehicle::cougars::{ControlsConfig, KINEMATICS_KEYS, Kinematics, vars};
use vehicle::couguv::{CougUvSim, CougUvSimConfig};
use vehicle::geodesy::LocalGrid;
use vehicle::sensors::{TruthField, TruthTracker};

use crate::app::{Mail, Post, Subscription, Value};
use crate::appcasting::Note;
use crate::hosted::{AppCore, Hosted};

/// The app's program name.
pub const PROGRAM: &str = "uSimDevices";

/// The devices of a bench, in the order of [`Bench::stats`].
pub const KINDS: [Kind; 4] = [Kind::Gps, Kind::Dvl, Kind::Seatrac, Kind::Teensy];

/// What the app reaches of a running bench.
#[derive(Clone)]
struct Feeds {
    truths: Vec<SharedTruth>,
    teensy: TeensyPort,
    /// The four emulators' fault plans count from this clock's origin (pending until the
    /// mission's uSimDevices starts it at the mission's start).
    faults: FaultClock,
    /// The Unix time of the emulators' time 0 (wall seconds).
    epoch_unix_s: f64,
    /// The emulators' warp.
    warp: f64,
}

impl Feeds {
    /// Starts the fault plans at the mission's start, `start` in the community's MOOS
    /// seconds (Unix time times the warp): plan time 0 is then the emulators' wall time
    /// `start / warp − epoch`.
    fn start_faults(&self, start: f64) {
        self.faults.start_at(start / self.warp - self.epoch_unix_s);
    }
}

fn registry() -> &'static Mutex<HashMap<String, Feeds>> {
    static BENCHES: OnceLock<Mutex<HashMap<String, Feeds>>> = OnceLock::new();
    BENCHES.get_or_init(|| Mutex::new(HashMap::new()))
}

fn lookup(name: &str) -> Option<Feeds> {
    registry()
        .lock()
        .unwrap_or_else(PoisonError::into_inner)
        .get(name)
        .cloned()
}

/// The emulators' settings, from the mission (see [`BenchConfig::from_mission`]).
#[derive(Debug, Clone, PartialEq)]
pub struct BenchConfig {
    /// The community's time warp (the emulators' clock runs this much faster than the wall).
    pub warp: f64,
    /// Seeds every draw of the emulators.
    pub seed: u64,
    /// The local grid's origin, degrees (the mission's `LatOrigin`, `LongOrigin`).
    pub origin: Option<(f64, f64)>,
    /// Magnetic declination, degrees east.
    pub declination_deg: f64,
    /// Air pressure at the surface, Pa.
    pub atmospheric_pa: f64,
    /// The flat bottom's depth, m.
    pub water_depth_m: f64,
    /// The GPS antenna's largest hull depth for a fix, m (`None`: the model's).
    pub gps_max_depth_m: Option<f64>,
    /// Fault specs per device, in [`KINDS`] order.
    pub faults: [Vec<String>; 4],
}

impl Default for BenchConfig {
    fn default() -> Self {
        BenchConfig {
            warp: 1.0,
            seed: 1,
            origin: None,
            declination_deg: 0.0,
            atmospheric_pa: 101_325.0,
            water_depth_m: 30.0,
            gps_max_depth_m: None,
            faults: Default::default(),
        }
    }
}

/// The keys of a uSimDevices block that are the bench's (read by [`BenchConfig`]).
const BENCH_KEYS: [&str; 8] = [
    "declination",
    "atmospheric_pressure",
    "gps_max_depth",
    "gps_fault",
    "dvl_fault",
    "seatrac_fault",
    "teensy_fault",
    "default_water_depth",
];

/// The app's own keys (besides the fin kinematics' [`KINEMATICS_KEYS`]).
const APP_KEYS: [&str; 1] = ["bench"];

fn key_is(p: &str, k: &str) -> bool {
    p.trim().eq_ignore_ascii_case(k)
}

impl BenchConfig {
    /// The settings of `block` (a uSimDevices block) in a mission with `origin`, at `warp`;
    /// a value that is not usable is an error naming its line.
    pub fn from_block(
        block: Option<&ProcessConfig>,
        origin: Option<(f64, f64)>,
        warp: f64,
        seed: u64,
    ) -> Result<BenchConfig, String> {
        let mut c = BenchConfig {
            warp,
            seed,
            origin,
            ..BenchConfig::default()
        };
        let Some(block) = block else {
            return Ok(c);
        };
        for p in &block.entries {
            let num = || {
                p.value
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        format!(
                            "{}:{}: {PROGRAM}: {} = {}: not a number",
                            p.span.file_name(),
                            p.span.line,
                            p.key.trim(),
                            p.value.trim()
                        )
                    })
            };
            let k = p.key.trim().to_ascii_lowercase();
            match k.as_str() {
                "declination" => c.declination_deg = num()?,
                "atmospheric_pressure" => c.atmospheric_pa = num()?,
                "default_water_depth" => c.water_depth_m = num()?,
                "gps_max_depth" => c.gps_max_depth_m = Some(num()?),
                _ => {
                    if let Some(i) = ["gps_fault", "dvl_fault", "seatrac_fault", "teensy_fault"]
                        .iter()
                        .position(|f| *f == k)
                    {
                        let spec = p.value.trim().to_string();
                        FaultPlan::parse(std::slice::from_ref(&spec)).map_err(|e| {
                            format!(
                                "{}:{}: {PROGRAM}: {} = {spec}: {e}",
                                p.span.file_name(),
                                p.span.line,
                                p.key.trim()
                            )
                        })?;
                        c.faults[i].push(spec);
                    }
                }
            }
        }
        Ok(c)
    }

    /// The settings of the mission's first `uSimDevices` (its ANTLER `Run` line, the block
    /// of its MOOS name), its origin, and `warp` (the mission's `MOOSTimeWarp` when `None`).
    pub fn from_mission(
        m: &MissionFile,
        warp: Option<f64>,
        seed: u64,
    ) -> Result<BenchConfig, String> {
        let (globals, _) = crate::antler::MissionGlobals::from_mission(m);
        let name = m
            .antler_runs()
            .into_iter()
            .find(|r| r.app.rsplit('/').next() == Some(PROGRAM))
            .map_or_else(|| PROGRAM.to_string(), |r| r.moos_name().to_string());
        BenchConfig::from_block(
            m.process(&name),
            globals.origin,
            warp.unwrap_or(globals.time_warp),
            seed,
        )
    }

    fn settings(&self) -> Settings {
        let mut s = Settings::default();
        if let Some(o) = self.origin {
            s.gps.origin_lat_lon = o;
        }
        if let Some(d) = self.gps_max_depth_m {
            s.gps.model.max_depth_m = d;
        }
        s.dvl.water_depth_m = self.water_depth_m;
        s.seatrac.declination_deg = self.declination_deg;
        s.seatrac.atmospheric_pa = self.atmospheric_pa;
        s.teensy.pressure.atmospheric_pa = self.atmospheric_pa;
        s
    }
}

/// The four emulators of the CougUV, running on their own thread, registered by name for
/// the mission's `uSimDevices`. Dropping it stops them.
pub struct Bench {
    name: String,
    rt: Option<tokio::runtime::Runtime>,
    running: Vec<(Kind, Running)>,
}

impl std::fmt::Debug for Bench {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Bench")
            .field("name", &self.name)
            .field("endpoints", &self.endpoints())
            .finish()
    }
}

impl Bench {
    /// Starts the four emulators as `config` says: the GPS (gpsd) and the DVL on loopback
    /// TCP ports the OS picks, the X150 and the Teensy on new pseudo-terminals.
    pub fn start(config: &BenchConfig) -> io::Result<Bench> {
        static NEXT: AtomicU64 = AtomicU64::new(1);
        let name = format!(
            "bench-{}-{}",
            std::process::id(),
            NEXT.fetch_add(1, Ordering::Relaxed)
        );
        let rt = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(1)
            .thread_name("coug-emulators")
            .enable_all()
            .build()?;
        let epoch = moosdb::time::unix_now();
        let clock = FaultClock::pending();
        let mut running = Vec::new();
        for (i, kind) in KINDS.into_iter().enumerate() {
            let faults = FaultPlan::parse(&config.faults[i])
                .map_err(|e| io::Error::new(io::ErrorKind::InvalidInput, e.to_string()))?;
            let options = Options {
                seed: config.seed ^ (0x9e37_79b9 * (i as u64 + 1)),
                faults,
                epoch_unix_s: epoch,
            };
            let transport = match kind {
                Kind::Gps | Kind::Dvl => Transport::loopback(0),
                Kind::Seatrac | Kind::Teensy => Transport::Pty { link: None },
            };
            let r = rt.block_on(build::spawn_warped_with_clock(
                kind,
                config.settings(),
                transport,
                options,
                config.warp,
                clock.clone(),
            ))?;
            running.push((kind, r));
        }
        let feeds = Feeds {
            truths: running.iter().map(|(_, r)| r.truth.clone()).collect(),
            teensy: running
                .iter()
                .find_map(|(_, r)| r.teensy.clone())
                .unwrap_or_default(),
            faults: clock,
            epoch_unix_s: epoch,
            warp: emulate::warp::usable_warp(config.warp),
        };
        registry()
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .insert(name.clone(), feeds);
        Ok(Bench {
            name,
            rt: Some(rt),
            running,
        })
    }

    /// The bench's name (the `bench` parameter of uSimDevices).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Each device's current endpoint, in [`KINDS`] order.
    pub fn endpoints(&self) -> Vec<(Kind, Endpoint)> {
        self.running
            .iter()
            .map(|(k, r)| (*k, r.handle.endpoint()))
            .collect()
    }

    fn endpoint(&self, kind: Kind) -> Endpoint {
        self.running
            .iter()
            .find(|(k, _)| *k == kind)
            .map_or(Endpoint::Down, |(_, r)| r.handle.endpoint())
    }

    /// The nsplug macros that point the mission's drivers at the emulators: `EMULATE=true`,
    /// `EMULATE_BENCH`, `GPS_HOST`, `GPS_PORT`, `DVL_HOST`, `DVL_PORT`, `SEATRAC_DEVICE`,
    /// `TEENSY_DEVICE`.
    pub fn macros(&self) -> Vec<String> {
        let mut m = vec![
            "EMULATE=true".to_string(),
            format!("EMULATE_BENCH={}", self.name),
        ];
        for (kind, var) in [(Kind::Gps, "GPS"), (Kind::Dvl, "DVL")] {
            if let Some(a) = self.endpoint(kind).tcp() {
                m.push(format!("{var}_HOST={}", a.ip()));
                m.push(format!("{var}_PORT={}", a.port()));
            }
        }
        for (kind, var) in [(Kind::Seatrac, "SEATRAC"), (Kind::Teensy, "TEENSY")] {
            if let Some(p) = self.endpoint(kind).serial_path() {
                m.push(format!("{var}_DEVICE={}", p.display()));
            }
        }
        m
    }

    /// What the emulated Teensy has been told and drives now.
    pub fn teensy(&self) -> TeensyInputs {
        lookup(&self.name)
            .map(|f| f.teensy.get())
            .unwrap_or_default()
    }

    /// Stops the emulators and returns what each edge did (bytes out and in, connections),
    /// in [`KINDS`] order.
    pub fn stop(mut self) -> Vec<(Kind, io::Result<EdgeStats>)> {
        let running = std::mem::take(&mut self.running);
        let Some(rt) = self.rt.as_ref() else {
            return Vec::new();
        };
        running
            .into_iter()
            .map(|(k, r)| (k, rt.block_on(r.handle.stop())))
            .collect()
    }
}

impl Drop for Bench {
    fn drop(&mut self) {
        registry()
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .remove(&self.name);
        if let Some(rt) = self.rt.take() {
            rt.shutdown_background();
        }
    }
}

/// A mission ready to run against a bench: the bench and the macros to load it with.
#[derive(Debug)]
pub struct Prepared {
    /// The running emulators.
    pub bench: Bench,
    /// The caller's macros followed by the bench's ([`Bench::macros`]).
    pub macros: Vec<String>,
}

/// Reads `path` with `macros` and `EMULATE=true` for its `uSimDevices` block and origin,
/// starts the bench at `warp` (the mission's `MOOSTimeWarp` when `None`), and returns it with
/// the macros the mission must be loaded with so its drivers find the emulators.
pub fn prepare(
    path: &Path,
    macros: &[String],
    include_paths: &[PathBuf],
    warp: Option<f64>,
    seed: u64,
) -> Result<Prepared, String> {
    let mut first = macros.to_vec();
    first.push("EMULATE=true".into());
    let loaded = crate::session::load(path, &first, include_paths).map_err(|e| e.to_string())?;
    let config = BenchConfig::from_mission(&loaded.mission, warp, seed)?;
    let bench = Bench::start(&config).map_err(|e| format!("cannot start the emulators: {e}"))?;
    let mut all = macros.to_vec();
    all.extend(bench.macros());
    Ok(Prepared { bench, macros: all })
}

/// Servo angle (0-180°, 90 centred) and thruster pulse back to what the model flies: the
/// physical fin deflections (top, starboard, port) through the inverse of `kin`
/// ([`Kinematics::deflections`]), and the thrust in percent (the firmware's map of -100..100 %
/// onto 1100..1900 µs, inverted).
pub fn actuators_to_command(t: &TeensyInputs, kin: &Kinematics) -> ([f64; 3], f64) {
    let thrust = if t.thruster_us == 0 {
        0.0
    } else {
        (f64::from(t.thruster_us) - 1500.0) / 4.0
    };
    let servo = t.servo_deg.map(|a| f64::from(a) - 90.0);
    (kin.deflections(servo, thrust), thrust)
}

/// The fin kinematics uSimDevices undoes the servo angles with, and the warnings of its own
/// lines: its own block's [`KINEMATICS_KEYS`] when it has any, else the mission's
/// pCougControls block's (`controls`), read by pCougControls' own parser
/// ([`ControlsConfig::from_params_lenient`]: the `vehicle` preset, then the keys overriding
/// it), else pCougControls' defaults (no preset: directions 1, no offsets).
fn kinematics_of(
    block: &ProcessConfig,
    controls: Option<&ProcessConfig>,
) -> (Kinematics, Vec<Diagnostic>) {
    let is_kin = |p: &&mission::Param| KINEMATICS_KEYS.iter().any(|k| key_is(&p.key, k));
    let own: Vec<&mission::Param> = block.entries.iter().filter(is_kin).collect();
    let (source, mine) = if own.is_empty() {
        let theirs: Vec<&mission::Param> = controls
            .map(|c| c.entries.iter().filter(is_kin).collect())
            .unwrap_or_default();
        (theirs, false)
    } else {
        (own, true)
    };
    let pairs = source.iter().map(|p| (p.key.as_str(), p.value.as_str()));
    let (cfg, problems) = ControlsConfig::from_params_lenient(pairs)
        .unwrap_or_else(|e| (ControlsConfig::default(), vec![e]));
    // pCougControls reports its own block's problems; only ours are warnings here.
    let warnings = if mine {
        problems
            .iter()
            .map(|e| {
                let key = match e {
                    ConfigError::UnknownKey { key, .. } | ConfigError::BadValue { key, .. } => {
                        Some(key)
                    }
                    ConfigError::Missing { .. } => None,
                };
                let span = key
                    .and_then(|k| source.iter().find(|p| key_is(&p.key, k)))
                    .map_or(&block.span, |p| &p.span);
                // The parser names pCougControls: these are uSimDevices' lines.
                let text = e.to_string();
                let what = text.split_once(": ").map_or(text.as_str(), |(_, w)| w);
                Diagnostic::line_warning(
                    DiagnosticKind::AppSetting,
                    span,
                    format!("{PROGRAM}: {what}"),
                )
            })
            .collect()
    } else {
        Vec::new()
    };
    (cfg.cougars.kinematics, warnings)
}

/// The `uSimDevices` app (see the module docs).
pub type SimDevicesApp = Hosted<SimDevicesCore>;

/// The model behind the emulators: the core of the `uSimDevices` app.
pub struct SimDevicesCore {
    bench: Option<String>,
    feeds: Option<Feeds>,
    kin: Kinematics,
    sim: CougUvSim,
    tracker: TruthTracker,
    truth_vars: Vec<(String, TruthField)>,
    postings: Vec<Post>,
    fed: u64,
    last_inputs: TeensyInputs,
    start: f64,
}

impl Hosted<SimDevicesCore> {
    /// The app `name` from its `block` in a mission whose pCougControls block is
    /// `controls` (the fin kinematics, unless the app's own block sets them) and which starts
    /// at MOOS time `start` (the emulators' faults count from it); `grid` (the mission's
    /// origin) adds the truth's latitude and longitude.
    pub fn new(
        name: &str,
        block: ProcessConfig,
        grid: Option<LocalGrid>,
        controls: Option<&ProcessConfig>,
        start: f64,
    ) -> Self {
        let mut warnings = Vec::new();
        let warn = |warnings: &mut Vec<Diagnostic>, p: &mission::Param, text: String| {
            warnings.push(Diagnostic::line_warning(
                DiagnosticKind::AppSetting,
                &p.span,
                text,
            ));
        };
        let mut bench = None;
        let (kin, kin_warnings) = kinematics_of(&block, controls);
        warnings.extend(kin_warnings);
        for p in &block.entries {
            if key_is(&p.key, "bench") {
                let v = p.value.trim();
                if v.is_empty() || v.contains("$(") {
                    warn(
                        &mut warnings,
                        p,
                        format!(
                            "{PROGRAM}: bench = {v}: no bench named (run with `coug run --emulate`)"
                        ),
                    );
                } else {
                    bench = Some(v.to_string());
                }
            }
        }
        if let Err(e) = BenchConfig::from_block(Some(&block), None, 1.0, 0) {
            warnings.push(Diagnostic::line_warning(
                DiagnosticKind::AppSetting,
                &block.span,
                e,
            ));
        }
        // The model's keys are uSimCougUV's; the bench's and the app's own are not unknown.
        let model_params = block
            .entries
            .iter()
            .filter(|p| {
                let k = p.key.trim();
                !APP_KEYS.iter().any(|a| k.eq_ignore_ascii_case(a))
                    && !KINEMATICS_KEYS.iter().any(|a| k.eq_ignore_ascii_case(a))
                    && (k.eq_ignore_ascii_case("default_water_depth")
                        || !BENCH_KEYS.iter().any(|b| k.eq_ignore_ascii_case(b)))
            })
            .map(|p| (p.key.as_str(), p.value.as_str()));
        let (cfg, problems) = CougUvSimConfig::from_params_lenient(model_params)
            .unwrap_or_else(|e| (CougUvSimConfig::default(), vec![e]));
        for e in &problems {
            let (key, text) = match e {
                ConfigError::UnknownKey { key, .. } => {
                    (Some(key), format!("{PROGRAM}: unknown parameter `{key}`"))
                }
                ConfigError::BadValue { key, .. } => (Some(key), format!("{PROGRAM}: {e}")),
                ConfigError::Missing { .. } => (None, format!("{PROGRAM}: {e}")),
            };
            let span = key
                .and_then(|k| block.entries.iter().find(|p| key_is(&p.key, k)))
                .map_or(&block.span, |p| &p.span);
            warnings.push(Diagnostic::line_warning(
                DiagnosticKind::AppSetting,
                span,
                text,
            ));
        }
        let truth_vars = TruthField::ALL
            .iter()
            .map(|(f, suffix)| (format!("{}_{suffix}", cfg.prefix), *f))
            .collect();
        let core = SimDevicesCore {
            bench,
            feeds: None,
            kin,
            sim: CougUvSim::new(cfg, grid),
            tracker: TruthTracker::new(),
            truth_vars,
            postings: Vec::with_capacity(16),
            fed: 0,
            last_inputs: TeensyInputs::default(),
            start,
        };
        Hosted::host(name, block, warnings, core)
    }

    /// The fin kinematics in force (see [`SimDevicesApp::new`]).
    pub fn kinematics(&self) -> &Kinematics {
        &self.core().kin
    }

    /// The model.
    pub fn sim(&self) -> &CougUvSim {
        &self.core().sim
    }
}

/// The MOOS time from which the Teensy's actuators hold what they drive now: the time it took
/// its last `$CONTR` (emulator time `t`, warped, is MOOS time `epoch × warp + t`), within the
/// model's step (`after`, the model's last advance, to `now`); `now` before any `$CONTR` (the
/// firmware's power-up neutral holds all along).
pub fn command_time(
    inputs: &TeensyInputs,
    epoch_unix_s: f64,
    warp: f64,
    after: Option<f64>,
    now: f64,
) -> f64 {
    let Some((t, _)) = inputs.last else {
        return now;
    };
    let given = epoch_unix_s * warp + t;
    let given = if given.is_finite() {
        given.min(now)
    } else {
        now
    };
    after.map_or(given, |a| given.max(a))
}

/// The app's appcast body: the bench (its name, whether it runs, truths fed), the Teensy's
/// inputs and the model.
fn appcast_body(
    bench: (Option<&str>, bool, u64),
    t: &TeensyInputs,
    sim: &CougUvSim,
    now: f64,
    body: &mut String,
) {
    use std::fmt::Write as _;
    let _ = writeln!(
        body,
        "Bench: {}   truths fed: {}",
        match bench {
            (Some(b), true, _) => b,
            (Some(_), false, _) => "not running",
            (None, _, _) => "none",
        },
        bench.2
    );
    let _ = writeln!(
        body,
        "Teensy: $CONTR accepted {}  refused {}  servos {:?}  thruster {} us{}",
        t.accepted,
        t.refused,
        t.servo_deg,
        t.thruster_us,
        if t.failsafe { "  (failsafe)" } else { "" }
    );
    body.push('\n');
    sim.appcast_body(now, body);
}

impl AppCore for SimDevicesCore {
    fn subscriptions(&self) -> Vec<Subscription> {
        Vec::new()
    }

    fn on_startup(&mut self, _now: f64, _out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        if let Some(b) = &self.bench {
            self.feeds = lookup(b);
            if let Some(f) = &self.feeds {
                // From now on `leak@120` means 120 s after the mission's start.
                f.start_faults(self.start);
            } else {
                notes.push(Note::Warning(format!(
                    "no bench {b} in this process: the devices measure nothing"
                )));
            }
        }
    }

    fn on_mail(&mut self, _m: &Mail, _now: f64, _out: &mut Vec<Post>, _notes: &mut Vec<Note>) {}

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        if let Some(f) = &self.feeds {
            // The Teensy's outputs are the model's command from the time the Teensy took its
            // last $CONTR: after a stall the model flies the old command up to the new one,
            // and no command longer than the failsafe's timeout after it was sent.
            let inputs = f.teensy.get();
            let given = command_time(&inputs, f.epoch_unix_s, f.warp, self.sim.last_time(), now);
            if inputs.accepted != self.last_inputs.accepted {
                self.sim.advance_to(given);
            }
            self.last_inputs = inputs;
            let (fins, thrust) = actuators_to_command(&self.last_inputs, &self.kin);
            let names = [
                vars::FIN_DEFLECT_TOP_DEG,
                vars::FIN_DEFLECT_STBD_DEG,
                vars::FIN_DEFLECT_PORT_DEG,
            ];
            for (n, v) in names.iter().zip(fins) {
                self.sim.on_mail(n, Value::Double(v).as_ref(), given);
            }
            self.sim
                .on_mail(vars::THRUST_PCT, Value::Double(thrust).as_ref(), given);
        }
        self.sim.iterate(now, &mut self.postings);
        notes.extend(self.sim.take_warnings().into_iter().map(Note::Warning));
        for p in &self.postings {
            let Some(v) = p.value.as_f64() else { continue };
            if let Some((_, f)) = self.truth_vars.iter().find(|(n, _)| *n == *p.key) {
                self.tracker.update(*f, v, now);
            }
        }
        if let (Some(f), Some(truth)) = (&self.feeds, self.tracker.truth(now)) {
            for s in &f.truths {
                s.feed(truth);
            }
            self.fed += 1;
        }
        out.append(&mut self.postings);
    }

    fn report(&self, now: f64, body: &mut String) {
        let bench = (self.bench.as_deref(), self.feeds.is_some(), self.fed);
        appcast_body(bench, &self.last_inputs, &self.sim, now, body);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::antler::BuiltInApp;
    use vehicle::cougars::CougarsConfig;

    fn block(text: &str) -> ProcessConfig {
        crate::testing::block("h.moos", text)
    }

    /// The model takes the Teensy's command from the time the Teensy took it (MOOS time
    /// `epoch × warp + emulator time`), within the model's step: after a stall of 40 simulated
    /// seconds the new command starts when it came, not at the stall's start, and a command
    /// taken before the step counts from the step's start.
    #[test]
    fn the_teensys_command_counts_from_when_the_teensy_took_it() {
        let c = devices::teensy::Contr {
            fins_deg: [0.0; 3],
            thrust_pct: 40,
        };
        let at = |t: f64| TeensyInputs {
            last: Some((t, c)),
            ..TeensyInputs::default()
        };
        let (epoch, warp) = (1.0e9, 8.0);
        let moos = epoch * warp;
        // Before any $CONTR: the power-up neutral, now.
        let none = TeensyInputs::default();
        assert_eq!(
            command_time(&none, epoch, warp, Some(moos), moos + 40.0),
            moos + 40.0
        );
        // Taken 39 s into a 40 s step: from then.
        assert_eq!(
            command_time(&at(139.0), epoch, warp, Some(moos + 100.0), moos + 140.0),
            moos + 139.0
        );
        // Taken before the step: from the step's start; never after now.
        assert_eq!(
            command_time(&at(50.0), epoch, warp, Some(moos + 100.0), moos + 140.0),
            moos + 100.0
        );
        assert_eq!(
            command_time(&at(150.0), epoch, warp, Some(moos + 100.0), moos + 140.0),
            moos + 140.0
        );
        assert_eq!(
            command_time(&at(50.0), epoch, warp, None, moos + 140.0),
            moos + 50.0
        );
    }

    /// uSimDevices' model over a stall: the old command flies until the failsafe's timeout,
    /// the new one from when the Teensy took it, as the split of [`command_time`] and
    /// `advance_to` gives; the same vehicle as short steps, finite.
    #[test]
    fn a_stalled_step_flies_the_old_command_to_the_failsafe_and_the_new_one_from_its_time() {
        use vehicle::couguv::{CougUvSim, CougUvSimConfig};
        let cfg = CougUvSimConfig::from_params([
            ("start_pos", "x=0, y=0, heading=0, speed=1, depth=2"),
            ("command_timeout", "5"),
        ])
        .unwrap();
        let set = |s: &mut CougUvSim, thrust: f64, t: f64| {
            s.on_mail(vars::THRUST_PCT, Value::Double(thrust).as_ref(), t);
        };
        // One step: 100 % at 0, nothing until 39 s, then 20 %, the step ending at 40 s.
        let mut once = CougUvSim::new(cfg.clone(), None);
        let mut out = Vec::new();
        set(&mut once, 100.0, 0.0);
        once.iterate(0.0, &mut out);
        once.advance_to(39.0);
        set(&mut once, 20.0, 39.0);
        once.iterate(40.0, &mut out);
        // Short steps: 100 % given at 0 (stopped by the failsafe after 5 s), 20 % at 39 s.
        let mut fine = CougUvSim::new(cfg, None);
        set(&mut fine, 100.0, 0.0);
        for k in 0..=800 {
            let t = f64::from(k) * 0.05;
            if k == 780 {
                set(&mut fine, 20.0, t);
            }
            fine.iterate(t, &mut out);
        }
        let (a, b) = (once.truth(), fine.truth());
        assert!(a.is_finite());
        // (The short steps fly the 20 % over the whole 50 ms step it arrived in.)
        assert!(
            (a.y - b.y).abs() < 1e-2 && (a.body.surge - b.body.surge).abs() < 5e-3,
            "{a:?}\n{b:?}"
        );
        assert_eq!(once.command().thruster, 20.0);
    }

    #[test]
    fn servo_angles_and_pulses_are_undone_through_the_kinematics() {
        let coug1 = CougarsConfig::coug1().kinematics;
        // coug1: top = fin - 10, starboard and port reversed.
        let t = TeensyInputs {
            servo_deg: [85, 93, 87],
            thruster_us: 1700,
            ..TeensyInputs::default()
        };
        let (fins, thrust) = actuators_to_command(&t, &coug1);
        assert_eq!(fins, [5.0, -3.0, 3.0]);
        assert_eq!(thrust, 50.0);
        // The firmware at power-up: all neutral (servos centred, 1500 µs).
        let neutral = TeensyInputs {
            servo_deg: [90; 3],
            thruster_us: 1500,
            ..TeensyInputs::default()
        };
        let (fins, thrust) = actuators_to_command(&neutral, &Kinematics::default());
        assert_eq!((fins, thrust), ([0.0; 3], 0.0));
        // A mix and its undoing agree to the servo's whole degree.
        let cmd = vehicle::cougars::UCommand {
            fin: [4.0, -7.0, 7.0],
            thruster: 30.0,
        };
        let mixed = coug1.mix(&cmd, true, false);
        let c = devices::teensy::Contr {
            fins_deg: mixed.fin,
            thrust_pct: mixed.thruster as i32,
        };
        let t = TeensyInputs {
            servo_deg: c.servo_angles_deg(),
            thruster_us: c.thruster_pulse_us(),
            ..TeensyInputs::default()
        };
        let (fins, thrust) = actuators_to_command(&t, &coug1);
        assert_eq!((fins, thrust), (cmd.fin, 30.0));
    }

    /// A third fin configuration (neither coug1 nor coug2: every direction and offset its
    /// own) in the mission's pCougControls block: uSimDevices reads it there, with
    /// pCougControls' parser, and undoes pCougControls' servo angles back to the physical
    /// deflections it commanded, to the servo's whole degree.
    #[test]
    fn the_fin_kinematics_are_pcougcontrols_own_even_a_third_vehicles() {
        let controls = block(
            "ProcessConfig = pCougControls\n{\n  vehicle = none\n  fin_0_direction = -1\n  \
             fin_1_direction = 1\n  fin_2_direction = -1\n  top_fin_offset = 6\n  \
             right_fin_offset = -12\n  left_fin_offset = 17\n  trim_ratio = 0.1\n  \
             pitch_kp = 0.3\n}\n",
        );
        let third = vehicle::cougars::ControlsConfig::from_params(
            controls
                .entries
                .iter()
                .map(|p| (p.key.as_str(), p.value.as_str())),
        )
        .unwrap()
        .cougars
        .kinematics;
        assert_ne!(third, CougarsConfig::coug1().kinematics);
        assert_ne!(third, CougarsConfig::coug2().kinematics);
        let app = SimDevicesApp::new(
            PROGRAM,
            block("ProcessConfig = uSimDevices\n{\n  prefix = SIM\n}\n"),
            None,
            Some(&controls),
            0.0,
        );
        assert!(app.warnings().is_empty(), "{:?}", app.warnings());
        assert_eq!(app.kinematics(), &third);
        // pCougControls' command through the Teensy's servos and back.
        for (fin, thrust) in [([4.0, -7.0, 7.0], 30.0), ([-20.0, 15.0, -15.0], 60.0)] {
            let cmd = vehicle::cougars::UCommand {
                fin,
                thruster: thrust,
            };
            let mixed = third.mix(&cmd, true, false);
            let c = devices::teensy::Contr {
                fins_deg: mixed.fin,
                thrust_pct: mixed.thruster as i32,
            };
            let t = TeensyInputs {
                servo_deg: c.servo_angles_deg(),
                thruster_us: c.thruster_pulse_us(),
                ..TeensyInputs::default()
            };
            let (back, th) = actuators_to_command(&t, app.kinematics());
            assert_eq!(th, thrust);
            for i in 0..3 {
                // The servo takes whole degrees: within one of the command.
                assert!((back[i] - fin[i]).abs() < 1.0, "{back:?} vs {fin:?}");
            }
        }
        // The old coug1 undoing would have read another command from the same servos.
        let mixed = third.mix(
            &vehicle::cougars::UCommand {
                fin: [4.0, -7.0, 7.0],
                thruster: 30.0,
            },
            true,
            false,
        );
        let t = TeensyInputs {
            servo_deg: devices::teensy::Contr {
                fins_deg: mixed.fin,
                thrust_pct: 30,
            }
            .servo_angles_deg(),
            thruster_us: 1620,
            ..TeensyInputs::default()
        };
        let (wrong, _) = actuators_to_command(&t, &CougarsConfig::coug1().kinematics);
        assert!((wrong[0] - 4.0).abs() > 5.0, "{wrong:?}");
        // The app's own lines win over pCougControls' (a mission without pCougControls), and
        // a bad one is the app's warning at its line.
        let own = SimDevicesApp::new(
            PROGRAM,
            block("ProcessConfig = uSimDevices\n{\n  vehicle = coug2\n  fin_0_direction = 2\n}\n"),
            None,
            Some(&controls),
            0.0,
        );
        assert_eq!(own.kinematics(), &CougarsConfig::coug2().kinematics);
        let w: Vec<String> = own.warnings().iter().map(Diagnostic::located).collect();
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].contains("h.moos:4")
                && w[0].contains("uSimDevices: parameter `fin_0_direction = 2`"),
            "{w:?}"
        );
        // Neither: pCougControls' defaults, as pCougControls itself would run.
        let none = SimDevicesApp::new(
            PROGRAM,
            block("ProcessConfig = uSimDevices\n{\n}\n"),
            None,
            None,
            0.0,
        );
        assert_eq!(none.kinematics(), &Kinematics::default());
    }

    #[test]
    fn the_block_mixes_model_bench_and_app_keys_and_flags_the_rest() {
        let app = SimDevicesApp::new(
            PROGRAM,
            block(
                "ProcessConfig = uSimDevices\n{\n  bench = $(EMULATE_BENCH)\n  vehicle = coug2\n  \
                 prefix = SIM\n  buoyancy_rate = 0.05\n  declination = 10.7\n  \
                 atmospheric_pressure = 84246\n  teensy_fault = leak@30\n  colour = red\n}\n",
            ),
            None,
            None,
            0.0,
        );
        let w: Vec<String> = app.warnings().iter().map(Diagnostic::located).collect();
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(
            w[0].contains("h.moos:3") && w[0].contains("no bench named"),
            "{w:?}"
        );
        assert!(
            w[1].contains("h.moos:10") && w[1].contains("unknown parameter `colour`"),
            "{w:?}"
        );
        assert_eq!(app.kinematics(), &CougarsConfig::coug2().kinematics);
        let c = BenchConfig::from_block(
            crate::app::App::process_config(&app),
            Some((40.0, -111.0)),
            4.0,
            9,
        )
        .unwrap();
        assert_eq!(
            (c.declination_deg, c.atmospheric_pa, c.warp, c.origin),
            (10.7, 84246.0, 4.0, Some((40.0, -111.0)))
        );
        assert_eq!(c.faults[3], vec!["leak@30".to_string()]);
        let bad = block("ProcessConfig = uSimDevices\n{\n  dvl_fault = sometimes\n}\n");
        let e = BenchConfig::from_block(Some(&bad), None, 1.0, 0).unwrap_err();
        assert!(
            e.starts_with("h.moos:3: uSimDevices: dvl_fault = sometimes"),
            "{e}"
        );
    }
}
