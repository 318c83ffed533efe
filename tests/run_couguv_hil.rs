//! Hardware in the loop without hardware: `missions/cougUV` in its hardware form (`HW=true`)
//! run in real time at a time warp against the four device emulators (what `coug run
//! --emulate` does, in process): the real drivers iGPS (gpsd JSON over loopback TCP), iDVL
//! (the A50's JSON over loopback TCP), iSeaTrac (X150 frames on a pseudo-terminal) and iTeensy
//! (ASCII lines on a pseudo-terminal), pNavGraph on what they post, pCougControls' fins and
//! thrust through iTeensy's `$CONTR` to the emulated Teensy, whose servo angles and thruster
//! pulse fly the CougUV model in uSimDevices, whose truth the emulators measure.
//!
//! The warp is 4: the survey takes about 370 simulated seconds, so about 92 s of wall time;
//! the run is bounded by `--max-time` 640 simulated seconds (160 s of wall time at warp 4).
//! At warp 8 a loaded machine (load 6 and more on 2 cores) starved the run: pCougControls'
//! 2 s staleness limits are a quarter of a second of wall time there.
//! Nothing is asserted about wall time: every wait is bounded by the run's own limit.
//!
//! The figures (completion time, navigation error at each resurfacing, each driver's
//! throughput from its counters, CPU per thread from `/proc/self/task`) are printed for the
//! closing note (`cargo test --test run_couguv_hil -- --nocapture`).

mod common;

use std::collections::HashMap;
use std::sync::Mutex;
use std::time::Instant;

use common::*;
use runtime::Value;
use runtime::navreplay;
use runtime::session::{self, Mode, Observer, RunOptions};

/// The warp of the run.
const WARP: f64 = 4.0;

/// One thread's CPU time from `/proc/self/task/<tid>/stat`: its name and utime + stime, in
/// clock ticks.
fn thread_cpu() -> Vec<(u32, String, u64)> {
    let mut out = Vec::new();
    let Ok(dir) = std::fs::read_dir("/proc/self/task") else {
        return out;
    };
    for e in dir.flatten() {
        let Ok(tid) = e.file_name().to_string_lossy().parse::<u32>() else {
            continue;
        };
        let Ok(stat) = std::fs::read_to_string(e.path().join("stat")) else {
            continue;
        };
        // `pid (comm) state ppid ...`: comm may hold spaces; the fields after its `)`.
        let (Some(open), Some(close)) = (stat.find('('), stat.rfind(')')) else {
            continue;
        };
        let comm = stat[open + 1..close].to_string();
        let f: Vec<&str> = stat[close + 2..].split(' ').collect();
        // After the comm: state is field 3, utime 14 and stime 15 (1-based in proc(5)).
        let ticks = |i: usize| {
            f.get(i - 3)
                .and_then(|v| v.parse::<u64>().ok())
                .unwrap_or(0)
        };
        out.push((tid, comm, ticks(14) + ticks(15)));
    }
    out
}

/// Keeps the latest driver statuses and samples the threads' CPU during the run.
#[derive(Default)]
struct Watch {
    status: HashMap<String, String>,
    cpu: HashMap<u32, (String, u64)>,
    sim_s: f64,
}

const STATUS_VARS: [&str; 4] = [
    "GPS_DRIVER_STATUS",
    "DVL_DRIVER_STATUS",
    "SEATRAC_DRIVER_STATUS",
    "TEENSY_DRIVER_STATUS",
];

impl Observer for Watch {
    fn step(&mut self, sim_s: f64, current: &dyn Fn(&str) -> Option<Value>) {
        self.sim_s = sim_s;
        for v in STATUS_VARS {
            if let Some(s) = current(v).and_then(|v| v.as_str().map(String::from)) {
                self.status.insert(v.to_string(), s);
            }
        }
        for (tid, comm, ticks) in thread_cpu() {
            self.cpu.insert(tid, (comm, ticks));
        }
    }
}

/// The counter `name` of a driver status line (`...,lines=120,...`).
fn counter(status: &str, name: &str) -> Option<f64> {
    status.split(',').find_map(|kv| {
        let (k, v) = kv.split_once('=')?;
        (k == name).then(|| v.parse().ok())?
    })
}

/// How many times the emulator behind driver status variable `var` flushed its terminal
/// unread (a stalled driver; see [`emulate::transport::EdgeStats::flushes`]).
fn edge_flushes(
    edges: &[(
        emulate::build::Kind,
        std::io::Result<emulate::transport::EdgeStats>,
    )],
    var: &str,
) -> u64 {
    edges
        .iter()
        .filter(|(kind, _)| var.starts_with(&kind.name().to_ascii_uppercase()))
        .filter_map(|(_, stats)| stats.as_ref().ok())
        .map(|stats| stats.flushes)
        .sum()
}

/// The two runs share two cores with the rest of the machine: one at a time.
static SERIAL: Mutex<()> = Mutex::new(());

/// What a run against the bench gives back.
struct Hil {
    report: session::RunReport,
    watch: Watch,
    wall_s: f64,
    before: Vec<(u32, String, u64)>,
    teensy: emulate::teensy::TeensyInputs,
    edges: Vec<(
        emulate::build::Kind,
        std::io::Result<emulate::transport::EdgeStats>,
    )>,
}

/// The hardware form with `macros` against a new bench at [`WARP`], deployed, until `until`
/// or `max_time` simulated seconds, logging in a fresh folder `name`; the validation must be
/// clean.
fn run_hil(name: &str, macros: &[&str], until: &str, max_time: f64) -> Hil {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mission = project_mission("cougUV/cougUV.moos");
    let dir = fresh_dir(name);
    let mut given = vec!["HW=true".to_string()];
    given.extend(macros.iter().map(|m| m.to_string()));
    let prepared = runtime::hil::prepare(&mission, &given, &[], Some(WARP), 1)
        .unwrap_or_else(|e| panic!("the bench does not start: {e}"));
    let macros = &prepared.macros;
    for want in [
        "EMULATE=true",
        "GPS_PORT=",
        "DVL_PORT=",
        "SEATRAC_DEVICE=/dev/",
        "TEENSY_DEVICE=/dev/",
    ] {
        assert!(
            macros.iter().any(|m| m.starts_with(want)),
            "{want}: {macros:?}"
        );
    }
    let loaded = session::load(&mission, macros, &[]).expect("the hardware form loads");
    let checked = session::validate(&loaded);
    assert!(
        checked.errors.is_empty() && checked.failed.is_empty() && checked.malconfig.is_empty(),
        "{checked:?}"
    );
    let warnings: Vec<String> = checked.warnings.iter().map(ToString::to_string).collect();
    assert!(warnings.is_empty(), "{warnings:#?}");
    let opts = RunOptions {
        mode: Mode::RealTime {
            warp: Some(WARP),
            port: Some(0),
        },
        deploy: true,
        until: Some(until.into()),
        max_time,
        log_dir: Some(dir.join("logs")),
        ..RunOptions::default()
    };
    let mut watch = Watch::default();
    let wall = Instant::now();
    let before = thread_cpu();
    let report = session::run(&loaded, &opts, &mut watch).expect("the run starts and ends");
    let wall_s = wall.elapsed().as_secs_f64();
    let teensy = prepared.bench.teensy();
    let edges = prepared.bench.stop();
    Hil {
        report,
        watch,
        wall_s,
        before,
        teensy,
        edges,
    }
}

#[test]
fn couguv_hardware_form_completes_its_survey_against_the_emulators() {
    let Hil {
        report,
        watch,
        wall_s,
        before,
        teensy,
        edges,
    } = run_hil("run-couguv-hil", &[], "MISSION = complete", 640.0);
    let summary = report.to_string();
    assert!(
        !report.until_pending(),
        "the survey did not complete within 640 s:\n{summary}"
    );
    assert!(
        summary.contains("completed:   gps_wait, leg1, up1, leg2, home"),
        "{summary}"
    );

    let log = parse(&std::fs::read(&report.alog).expect("the alog"));
    // The loop closes through the drivers: the navigator's inputs come from them, the truth
    // from uSimDevices, and no simulated sensor runs.
    let source = |var: &str| {
        log.entries
            .iter()
            .find(|e| e.var == var)
            .map(|e| e.source.clone())
            .unwrap_or_else(|| panic!("{var} never posted"))
    };
    for (var, app) in [
        ("GPS_X", "iGPS"),
        ("DVL_VEL_X", "iDVL"),
        ("AHRS_HEADING", "iSeaTrac"),
        ("PRESSURE", "iTeensy"),
        ("BATTERY_VOLTAGE", "iTeensy"),
        ("SIM_DEPTH", "uSimDevices"),
        ("NAV_DEPTH", "pNavGraph"),
        ("FIN_TOP_DEG", "pCougControls"),
    ] {
        assert_eq!(source(var), app, "{var}");
    }
    // pSafety watched the whole run and never acted.
    let safety: Vec<&str> = log
        .entries
        .iter()
        .filter(|e| e.var == "SAFETY_MODE")
        .filter_map(|e| e.value.as_str())
        .collect();
    assert_eq!(safety, ["OK"], "pSafety: {safety:?}");
    // The dives reached the survey depth and never the guard's.
    let max_depth = depths(&log).iter().fold(0.0f64, |m, p| m.max(p.1));
    assert!((2.5..5.0).contains(&max_depth), "max depth {max_depth}");
    // The navigator's uncertainty stays physical however the run was starved: a stall used to
    // leave dead-reckoning keyframes with free headings (NAV_POS_STD 1e5-1e7 m, see
    // nav/tests/stall_burst.rs). Its prior is 10 m; a dive of ~2 minutes adds a few metres.
    let (mut postings, mut max_pos_std) = (0usize, 0.0f64);
    for e in log.entries.iter().filter(|e| e.var == "NAV_POS_STD") {
        let v = e.value.as_f64().unwrap_or(f64::NAN);
        assert!(
            v.is_finite() && v < 100.0,
            "NAV_POS_STD {v} m at {}",
            e.time
        );
        postings += 1;
        max_pos_std = max_pos_std.max(v);
    }
    assert!(postings > 0, "NAV_POS_STD never posted");
    let solver_failures = log
        .entries
        .iter()
        .filter(|e| e.var == "NAV_STATUS" && e.value.as_str() == Some("degraded: solver failure"))
        .count();
    assert_eq!(solver_failures, 0, "pNavGraph's solver failed");

    // Navigation at each resurfacing: the estimate just before the first GPS fix after the
    // dive, against the truth. Bound: 2 m + 5 % of the distance dived. Dead reckoning on the
    // A50 model (0.5 % scale error, 2 cm/s noise) and the X150's AHRS (1° heading noise,
    // integrated) drifts by about 1-2 % of the distance; the estimate at the dive's start
    // carries the surface fixes' error (σ 1.5 m each, a few fixes at 1 Hz); 5 % leaves room
    // for the heading errors of the turns, which the gyro-less emulated AHRS does not smooth.
    let nav = navreplay::live(&log, "DR");
    let truth = navreplay::truth(&log);
    let figures = navreplay::Figures::of(&nav, &truth);
    assert_eq!(figures.dives.len(), 2, "two dives:\n{}", figures.report());
    for d in &figures.dives {
        let err = d.estimate_error_m.expect("an estimate before the fix");
        let bound = 2.0 + 0.05 * d.report.distance_m;
        assert!(
            err < bound,
            "dive {}: error {err:.2} m at resurfacing over {:.1} m (bound {bound:.1} m)\n{}",
            d.report.dive,
            d.report.distance_m,
            figures.report()
        );
    }

    // Each driver parsed its device's data with no error, and the Teensy took the commands.
    let sim_s = report.sim_s();
    let mut throughput = Vec::new();
    for v in STATUS_VARS {
        let s = watch
            .status
            .get(v)
            .unwrap_or_else(|| panic!("{v} never posted"));
        let n = |k: &str| counter(s, k).unwrap_or_else(|| panic!("{v}: no {k}: {s}"));
        assert!(s.starts_with("link=up"), "{v}: {s}");
        assert_eq!(n("connects"), 1.0, "{v}: {s}");
        // A serial device whose reader stalls loses its oldest bytes (the emulator flushes
        // its terminal past `STALE_BYTES`, as a real UART overruns): each flush may cut one
        // frame, whose tail the driver then counts as garbage or one bad frame. Without a
        // flush nothing may be wrong.
        let flushes = edge_flushes(&edges, v) as f64;
        let bad_frames = n("bad_checksum") + n("parse_errors") + n("oversize");
        assert!(bad_frames <= flushes, "{v} ({flushes} flushes): {s}");
        assert!(
            n("garbage_bytes") <= flushes * emulate::pty::STALE_BYTES as f64,
            "{v} ({flushes} flushes): {s}"
        );
        // At least one line per simulated second over the run (each device reports at 1 Hz
        // or faster).
        let lines = n("lines");
        assert!(lines > sim_s * 0.8, "{v}: {lines} lines in {sim_s} s: {s}");
        throughput.push((v, lines, n("rx_bytes")));
    }
    assert!(
        teensy.accepted as f64 > sim_s * 5.0 && teensy.refused == 0,
        "the Teensy's commands: {teensy:?}"
    );

    // The figures.
    println!("{summary}");
    println!("wall time of the run: {wall_s:.1} s (warp {WARP}), simulated {sim_s:.1} s");
    println!("NAV_POS_STD: largest {max_pos_std:.2} m over {postings} postings");
    print!("{}", figures.report());
    for (v, lines, bytes) in &throughput {
        println!(
            "{v}: {lines} lines ({:.1}/simulated s, {:.1}/wall s), {bytes} bytes",
            lines / sim_s,
            lines / wall_s
        );
    }
    println!(
        "Teensy: {} $CONTR accepted ({:.1}/simulated s), {} refused",
        teensy.accepted,
        teensy.accepted as f64 / sim_s,
        teensy.refused
    );
    for (kind, stats) in &edges {
        println!("emulated {}: {:?}", kind.name(), stats);
    }
    // CPU per thread over the run (clock ticks of 10 ms), for the threads that lived in it.
    let hz = 100.0;
    let base: HashMap<u32, u64> = before.iter().map(|(t, _, c)| (*t, *c)).collect();
    let mut threads: Vec<(String, f64)> = watch
        .cpu
        .iter()
        .map(|(tid, (comm, ticks))| {
            let used = ticks - base.get(tid).copied().unwrap_or(0).min(*ticks);
            (comm.clone(), used as f64 / hz)
        })
        .filter(|(_, s)| *s > 0.0)
        .collect();
    threads.sort_by(|a, b| b.1.total_cmp(&a.1));
    for (comm, s) in threads {
        println!(
            "thread {comm:<16} {s:>6.2} s CPU = {:>5.2} % of one core over {wall_s:.0} s of wall time",
            100.0 * s / wall_s
        );
    }
}

/// The last value of `var` at or before `t` in the log.
fn value_at(log: &alog::Alog, var: &str, t: f64) -> Option<f64> {
    log.entries
        .iter()
        .filter(|e| e.var == var && e.time <= t)
        .filter_map(|e| e.value.as_f64())
        .next_back()
}

/// A leak mid-dive, through the whole hardware path: the emulated Teensy's leak sensor reads
/// wet (`TEENSY_FAULT=leak@120`: 120 s of mission time, the community's MOOS seconds since
/// the mission started, however long before it the emulators started: during the first leg
/// at depth), iTeensy posts `LEAK`,
/// pSafety triggers surface-then-disarm: pCougControls swims up fins-up, and once the vehicle
/// has stayed at the surface pSafety's `DEPLOY=false` disarms it, so iTeensy sends a zero
/// thrust with the fins centred (coug1's servo frame: the top fin's -10° offset) and the
/// Teensy drives its thruster neutral. Bound: the truth at the surface
/// (within 0.3 m) within 60 simulated seconds of the trigger; from the survey's 3 m that is
/// a climb of 5 cm/s, what the slightly buoyant hull does on its own with the thruster off,
/// so fins-up under thrust must do better.
#[test]
fn a_leak_mid_dive_surfaces_and_disarms_the_couguv_through_the_emulated_teensy() {
    let Hil { report, teensy, .. } = run_hil(
        "run-couguv-hil-leak",
        &["TEENSY_FAULT=leak@120"],
        "SAFETY_MODE = DISARMED",
        400.0,
    );
    let summary = report.to_string();
    assert!(!report.until_pending(), "never disarmed:\n{summary}");
    let log = parse(&std::fs::read(&report.alog).expect("the alog"));
    let leak = log
        .entries
        .iter()
        .find(|e| e.var == "LEAK" && e.value.as_f64() == Some(1.0))
        .expect("iTeensy posts the leak");
    assert_eq!(leak.source, "iTeensy");
    // The fault's time is the mission's: the log counts from pLogger's start, a fraction of a
    // second (a few at warp 4) after the mission's; the leak is posted within an iteration.
    let leak_at = leak.time;
    assert!(
        (117.5..121.0).contains(&leak_at),
        "the leak at {leak_at:.2} s of the log, not 120 s of mission time"
    );
    let trigger = log
        .entries
        .iter()
        .find(|e| {
            e.var == "SAFETY_EVENT"
                && e.value
                    .as_str()
                    .is_some_and(|v| v.starts_with("trigger=leak,action=surface_disarm"))
        })
        .expect("pSafety triggers on the leak");
    let t0 = trigger.time;
    assert!(
        t0 >= leak.time && t0 - leak.time < 1.0,
        "{} {}",
        leak.time,
        t0
    );
    let depth0 = value_at(&log, "SIM_DEPTH", t0).expect("a depth");
    assert!(depth0 > 1.5, "the leak came at {depth0} m, not mid-dive");
    // Nothing but the leak acted.
    let triggers: Vec<&str> = log
        .entries
        .iter()
        .filter(|e| e.var == "SAFETY_EVENT")
        .filter_map(|e| e.value.as_str())
        .filter(|v| v.starts_with("trigger="))
        .collect();
    assert_eq!(triggers.len(), 1, "{triggers:?}");
    let modes: Vec<&str> = log
        .entries
        .iter()
        .filter(|e| e.var == "SAFETY_MODE")
        .filter_map(|e| e.value.as_str())
        .collect();
    assert_eq!(modes, ["OK", "SURFACE", "DISARMED"], "{modes:?}");
    // Fins up while surfacing, and at the surface within the bound.
    assert!(
        log.entries
            .iter()
            .any(|e| e.var == "COUG_SURFACE" && e.time >= t0 && e.source == "pSafety"),
        "no fins-up command"
    );
    let surfaced = log
        .entries
        .iter()
        .find(|e| e.var == "SIM_DEPTH" && e.time > t0 && e.value.as_f64().is_some_and(|d| d < 0.3))
        .map(|e| e.time)
        .expect("the vehicle surfaces");
    assert!(
        surfaced - t0 < 60.0,
        "{:.1} s from {depth0:.2} m to the surface",
        surfaced - t0
    );
    // Disarmed at the surface: pCougControls' all-stop, sent as $CONTR, drives the thruster
    // neutral.
    let disarmed = log
        .entries
        .iter()
        .find(|e| e.var == "SAFETY_MODE" && e.value.as_str() == Some("DISARMED"))
        .map(|e| e.time)
        .unwrap();
    assert!(value_at(&log, "SIM_DEPTH", disarmed).unwrap() < 0.3);
    assert!(
        log.entries.iter().any(|e| e.var == "COUG_CONTROLS_STATE"
            && e.time >= disarmed
            && e.value.as_str() == Some("disarmed")),
        "pCougControls never disarmed"
    );
    assert_eq!(value_at(&log, "THRUST_PCT", f64::INFINITY), Some(0.0));
    let last = teensy.last.expect("the Teensy heard commands").1;
    assert_eq!(last.thrust_pct, 0, "{teensy:?}");
    assert_eq!(teensy.thruster_us, 1500, "{teensy:?}");
    // Disarmed, the fins are centred (zero deflection), not left up: coug1's servo frame is
    // the top fin's -10° offset and the elevators' 0, servos 80°, 90°, 90° (until the run's
    // end silences iTeensy and the firmware's failsafe centres them at 90°).
    assert_eq!(last.fins_deg, [-10.0, 0.0, 0.0], "{teensy:?}");
    assert_eq!(last.servo_angles_deg(), [80, 90, 90], "{teensy:?}");
    for (var, want) in [
        ("FIN_DEFLECT_TOP_DEG", 0.0),
        ("FIN_DEFLECT_STBD_DEG", 0.0),
        ("FIN_DEFLECT_PORT_DEG", 0.0),
    ] {
        assert_eq!(value_at(&log, var, f64::INFINITY), Some(want), "{var}");
    }
    println!(
        "leak posted at {leak_at:.2} s of the log; trigger at {:.1} s ({depth0:.2} m): surfaced {:.1} s later, disarmed {:.1} s after the trigger",
        t0 - log.entries[0].time,
        surfaced - t0,
        disarmed - t0
    );
}

/// `coug run --emulate` itself: the endpoints it announces are OS-picked ports and new
/// pseudo-terminals, the drivers connect to them (each emulator sent bytes and heard the
/// start-up commands it answers), and lockstep is refused (the emulators need real time).
/// Bounded by `--max-time 24` simulated seconds (3 s of wall time at warp 8).
#[test]
fn coug_run_emulate_announces_the_emulators_and_the_drivers_reach_them() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mission = project_mission("cougUV/cougUV.moos");
    let dir = fresh_dir("run-couguv-hil-cli");
    let m = mission.to_str().unwrap();
    let out = coug(
        &dir,
        &[
            "run",
            m,
            "HW=true",
            "--emulate",
            "--warp",
            "8",
            "--port",
            "0",
            "--max-time",
            "24",
            "--log-dir",
            "logs",
        ],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{err}");
    for (dev, kind) in [
        ("gps", "tcp 127.0.0.1:"),
        ("dvl", "tcp 127.0.0.1:"),
        ("seatrac", "pty /dev/"),
        ("teensy", "pty /dev/"),
    ] {
        let announced = format!("coug run: emulated {dev}: {kind}");
        assert!(err.contains(&announced), "{announced}: {err}");
        let stats = err
            .lines()
            .filter_map(|l| l.strip_prefix(&format!("coug run: emulated {dev}: ")))
            .find(|l| l.contains("bytes out"))
            .unwrap_or_else(|| panic!("{dev}: no byte counts: {err}"));
        let n = |what: &str| -> u64 {
            stats
                .split(", ")
                .find_map(|f| f.strip_suffix(what))
                .and_then(|v| v.split_whitespace().next_back()?.parse().ok())
                .unwrap_or_else(|| panic!("{dev}: {what}: {stats}"))
        };
        assert!(
            n(" bytes out") > 0 && n(" connection(s)") == 1,
            "{dev}: {stats}"
        );
        // Every driver talks to its device at start (gpsd's WATCH, the A50's set_config,
        // the X150's start-up sequence) except iTeensy, which sends $CONTR once armed.
        if dev != "teensy" {
            assert!(n(" in") > 0, "{dev}: {stats}");
        }
    }
    let refused = coug(&dir, &["run", m, "HW=true", "--emulate", "--lockstep"]);
    assert_eq!(
        refused.status.code(),
        Some(2),
        "clap refuses --emulate with --lockstep"
    );
}
