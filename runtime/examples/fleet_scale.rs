//! Scale benchmark (issue #16): a fleet of N surface vehicles (helm, uSimMarineV22,
//! pMarinePIDV22, pNodeReporter, pShare, pLogger each) and a shoreside hearing every
//! vehicle's node reports through pShare's in-process route, in one process, in lockstep,
//! through `runtime::session::run_fleet` as `coug run FLEET.fleet --lockstep` runs it. The
//! vehicles are missions/fleet_survey's template; each surveys its own lane.
//!
//! ```sh
//! cargo run --release -p runtime --example fleet_scale            # N = 10, 50, 100
//! cargo run --release -p runtime --example fleet_scale -- 100 120 # one N, simulated seconds
//! cargo run --release -p runtime --example fleet_scale -- 100 120 1 # ... on one thread
//! cargo run --release -p runtime --example fleet_scale -- --stack cougar 100 120 1
//! ```
//!
//! `--stack cougar` runs CougUVs instead: missions/fleet_acomms' vehicle template (uSimCougUV,
//! uSimSensors, pNavGraph, pCougControls, pSafety, the helm, pNodeReporter, uSimModem,
//! pAcomms, pLogger) N times with its base beacon, the vehicles 60 m apart and their modem
//! ids 1 to 14 in turn; they talk only through the simulated acoustic channel (the base
//! polls coug1 and coug2, as in the mission). The output has the same format (the
//! in-process pShare count is 0).
//!
//! The third argument is the number of threads stepping the communities
//! (`FleetOptions::threads`; 0, the default here, is one per core). The alogs are the same
//! bytes on any number (the run's only shared media, pShare's in-process route and the
//! simulated acoustic channel, merge what an instant's communities hand them in a fixed
//! order).
//!
//! Instructions per vehicle per simulated second, the figure that does not depend on the
//! machine's load: callgrind counting the fleet's loop alone, on a short run on one thread,
//!
//! ```sh
//! valgrind --tool=callgrind --toggle-collect=runtime::session::fleet::advance_all \
//!     target/release/examples/fleet_scale 10 30 1
//! ```
//!
//! gives the loop's total over 10 vehicles and 30 simulated seconds (divide by 300). The whole
//! run's counts of a 40 s and a 10 s run, subtracted, give more: the loop plus the reading of
//! the logs back for the report.
//!
//! With no argument it runs each N in a child process of its own (so the memory figures of
//! one do not include the others') and prints one line per fleet: simulated seconds, wall
//! seconds of the run's loop, speed-up over real time, the CPU seconds of the whole call
//! (loading, planning, running, reading the logs back) and the speed-up per CPU second of
//! the loop (what one free core gives; on a loaded shared machine the wall figure is lower),
//! and memory per vehicle (the growth of the
//! resident set from before loading to its peak, over N; the alogs go to a temporary folder
//! and are removed, or to `$FLEET_SCALE_KEEP_LOGS` and are kept).

/// The `coug` binary's allocator (see its `main.rs`), so the figures are those of `coug run`.
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use runtime::fleet::LoadedFleet;
use runtime::session::{self, Ended, FleetOptions, Mode};

/// A `/proc/self/status` field in KiB (Linux).
fn status_kib(field: &str) -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with(field))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// CPU seconds (user + system) this process has used: the run's cost whatever the load of
/// a shared machine (the wall time there also counts other processes' turns).
fn cpu_s() -> f64 {
    // SAFETY: getrusage writes one rusage into the zeroed struct we own.
    let mut u: libc::rusage = unsafe { std::mem::zeroed() };
    if unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut u) } != 0 {
        return f64::NAN;
    }
    let tv = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 * 1e-6;
    tv(u.ru_utime) + tv(u.ru_stime)
}

/// Reads the CPU time at every simulated second of the run (the loop only: loading,
/// planning and reading the logs back are outside the first and last steps).
#[derive(Default)]
struct CpuProbe {
    first: Option<(f64, f64)>,
    last: Option<(f64, f64)>,
}

impl session::Observer for CpuProbe {
    fn step(&mut self, sim_s: f64, _current: &dyn Fn(&str) -> Option<runtime::Value>) {
        let now = (sim_s, cpu_s());
        self.first.get_or_insert(now);
        self.last = Some(now);
    }
}

/// Which vehicles the fleet is made of.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Stack {
    /// missions/fleet_survey: surface vehicles (helm, uSimMarineV22, pMarinePIDV22,
    /// pNodeReporter, pShare, pLogger) and a shoreside.
    Surface,
    /// missions/fleet_acomms: CougUVs (uSimCougUV, uSimSensors, pNavGraph, pCougControls,
    /// pSafety, helm, pNodeReporter, uSimModem, pAcomms, pLogger) and the base beacon.
    Cougar,
}

impl Stack {
    fn name(self) -> &'static str {
        match self {
            Stack::Surface => "surface",
            Stack::Cougar => "cougar",
        }
    }
}

/// Writes a fleet file of `n` vehicles into `dir`, from the stack's template.
fn write_fleet(dir: &Path, n: usize, stack: Stack) -> PathBuf {
    match stack {
        Stack::Surface => write_surface_fleet(dir, n),
        Stack::Cougar => write_cougar_fleet(dir, n),
    }
}

/// Writes a fleet file of `n` CougUVs from the fleet_acomms template into `dir`: the base
/// beacon (polling coug1 and coug2, as in the mission), and vehicles `coug1..cougN` 60 m
/// apart (each starts at `X1 = 60 (i - 1)`, 0 and runs its lane down `X1` and up
/// `X1 + 20`), modem ids 1 to 14 in turn (`1 + (i - 1) mod 14`: the channel has 15 ids and
/// the base is 15).
fn write_cougar_fleet(dir: &Path, n: usize) -> PathBuf {
    let missions = Path::new(env!("CARGO_MANIFEST_DIR")).join("../missions/fleet_acomms");
    let mut text = format!(
        "macro = ACOMMS_KEY=cougars-fleet-acomms-example-key\n\
         base = base {}/base.moos PORT=9000\n\
         template = {}/vehicle.moos\n",
        missions.display(),
        missions.display()
    );
    for i in 1..=n {
        let x1 = (i - 1) as f64 * 60.0;
        text.push_str(&format!(
            "vehicle = coug{i} PORT={} MODEM_ID={} X1={x1} X2={} COLOR=yellow\n",
            9000 + i,
            1 + (i - 1) % 14,
            x1 + 20.0,
        ));
    }
    let path = dir.join(format!("fleet_{n}.fleet"));
    std::fs::write(&path, text).expect("fleet file written");
    path
}

/// Writes a fleet file of `n` vehicles from the fleet_survey template into `dir`.
fn write_surface_fleet(dir: &Path, n: usize) -> PathBuf {
    let missions = Path::new(env!("CARGO_MANIFEST_DIR")).join("../missions/fleet_survey");
    let mut text = format!(
        "macro = SHORE_LISTEN=9300\nbase = shoreside {}/shoreside.moos SHORE_PORT=9000\n\
         template = {}/vehicle.moos\n",
        missions.display(),
        missions.display()
    );
    for i in 1..=n {
        let x0 = (i - 1) as f64 * 60.0;
        let (x1, x2) = (x0 + 20.0, x0 + 40.0);
        text.push_str(&format!(
            "vehicle = v{i} VPORT={} LISTEN={} MODEM_ID={i} START_X={x0} COLOR=yellow \
             POINTS={x1},-20:{x1},-100:{x2},-100:{x2},-20\n",
            10_000 + i,
            9300 + i,
        ));
    }
    let path = dir.join(format!("fleet_{n}.fleet"));
    std::fs::write(&path, text).expect("fleet file written");
    path
}

/// Runs one fleet of `n` vehicles for `seconds` simulated seconds; prints one line.
fn one(n: usize, seconds: f64, threads: usize, stack: Stack) {
    let dir = std::env::temp_dir().join(format!(
        "coug-fleet-scale-{}-{}-{n}",
        std::process::id(),
        stack.name()
    ));
    std::fs::create_dir_all(&dir).expect("scratch folder");
    // FLEET_SCALE_KEEP_LOGS=DIR writes the alogs there and keeps them (to compare the
    // output of two builds).
    let keep = std::env::var_os("FLEET_SCALE_KEEP_LOGS").map(PathBuf::from);
    let rss0 = status_kib("VmRSS:").unwrap_or(0);
    let path = write_fleet(&dir, n, stack);
    let t0 = Instant::now();
    let fleet = LoadedFleet::from_file(&path, &[], &[]).expect("the fleet loads");
    let load_s = t0.elapsed().as_secs_f64();
    let opts = FleetOptions {
        mode: Mode::Lockstep,
        deploy: true,
        max_time: seconds,
        log_dir: Some(keep.clone().unwrap_or_else(|| dir.join("logs"))),
        threads,
        ..FleetOptions::default()
    };
    let cpu0 = cpu_s();
    let mut probe = CpuProbe::default();
    let report = session::run_fleet(&fleet, &opts, &mut probe).expect("the fleet runs");
    let cpu = cpu_s() - cpu0;
    let loop_speed = match (probe.first, probe.last) {
        (Some((s0, c0)), Some((s1, c1))) if c1 > c0 => (s1 - s0) / (c1 - c0),
        _ => f64::NAN,
    };
    let peak = status_kib("VmHWM:").unwrap_or(0);
    assert!(matches!(report.ended, Ended::Outcome(_)));
    let moving = report
        .members
        .iter()
        .filter(|(_, r)| r.totals.as_ref().is_some_and(|t| t.summary.distance > 50.0))
        .count();
    let log_bytes: u64 = report
        .members
        .iter()
        .filter_map(|(_, r)| std::fs::metadata(&r.alog).ok())
        .map(|m| m.len())
        .sum();
    println!(
        "N={n:4}  simulated {:6.1} s  wall {:7.3} s (+{load_s:.2} s loading)  speed-up {:7.1}x  \
         cpu {cpu:7.3} s (all of run_fleet)  speed-up per CPU second of the loop {loop_speed:7.1}x  memory {:6.0} KiB/vehicle (RSS {} -> peak {} KiB)  in-process pShare {}  \
         vehicles under way {moving}/{n}  logs {:.1} MB",
        report.sim_s(),
        report.wall_s,
        report.sim_s() / report.wall_s.max(1e-9),
        (peak.saturating_sub(rss0)) as f64 / n as f64,
        rss0,
        peak,
        report.in_process,
        log_bytes as f64 / 1e6,
    );
    let _ = std::fs::remove_dir_all(&dir);
}

fn main() {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let mut stack = Stack::Surface;
    if let Some(at) = args.iter().position(|a| a == "--stack") {
        stack = match args.get(at + 1).map(String::as_str) {
            Some("surface") => Stack::Surface,
            Some("cougar") => Stack::Cougar,
            other => panic!("--stack surface|cougar, not {other:?}"),
        };
        args.drain(at..at + 2);
    }
    let seconds = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(120.0);
    // Threads stepping the communities (0: one per core).
    let threads = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(0);
    if let Some(n) = args.first().and_then(|s| s.parse().ok()) {
        one(n, seconds, threads, stack);
        return;
    }
    let me = std::env::current_exe().expect("own path");
    for n in [10, 50, 100] {
        let status = Command::new(&me)
            .args(["--stack", stack.name()])
            .arg(n.to_string())
            .arg(seconds.to_string())
            .arg(threads.to_string())
            .status()
            .expect("child runs");
        assert!(status.success(), "N={n} failed");
    }
}
