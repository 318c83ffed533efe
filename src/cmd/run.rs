//! `coug run MISSION.moos [NAME=VALUE]... [--lockstep | --warp N] [--poke VAR=VALUE[@T]]...
//! [--deploy] [--until CONDITION] [--max-time SECONDS] [--log-dir DIR] [--port N] [--emulate]`:
//! one command runs a whole MOOS-IvP mission. With `--emulate` (real time) the CougUV's four
//! device emulators are started first and the mission's drivers pointed at them
//! (`runtime::hil`: hardware in the loop without hardware).
//!
//! The mission (and each helm's `behaviors =` file) is nsplug-expanded with the given
//! macros, the ANTLER block is resolved into coug's built-in apps, and the apps run either
//! in lockstep on a virtual clock (deterministic, as fast as the CPU allows) or in real time
//! times the warp with the MOOSDB on TCP, so real MOOS apps can join; ANTLER apps coug does
//! not build in are then started from PATH as pAntler starts them (`APP MISSION.moos
//! [ALIAS]`). All of that is `runtime::session`; this command parses the arguments, prints
//! warnings, progress and the summary, turns Ctrl-C into a clean stop, and picks the exit
//! code.
//!
//! Several communities in one run: `coug run FLEET.fleet ...` (a base and vehicles from a
//! template with per-vehicle macros, see `runtime::fleet`) or `coug run a.moos b.moos ...`
//! (each community named by its `Community`). `--poke`, `--button` and `--until` then take
//! an optional `NAME:` prefix (`--poke henry:DEPLOY=true@0`, `--until "henry: MISSION =
//! complete"`); without it a poke goes to every community, a button to every community that
//! has it, a condition to every vehicle; `--deploy` deploys every community. Each community
//! logs in its own folder (`LOG_DIR/NAME/`). That is `runtime::session::run_fleet`. A fleet
//! prints its progress every `--progress-every` simulated seconds (terminal or not), one line
//! per community (`FleetProgress`), in lockstep and in real time alike.
//!
//! Exit codes: 0 when the `--until` condition held (or the run reached `--max-time`
//! without one), 2 when `--max-time` came first, 1 on errors in files or arguments.

use std::io::{IsTerminal, Write};
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use clap::Args;
use runtime::session::{self, Ended, Mode, Observer, RunOptions, SessionError};
use runtime::summary::behaviour_list;
use runtime::{Outcome, Value};

/// Arguments of `coug run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// The mission file (or a `.fleet` file: several communities).
    #[arg(value_name = "MISSION.moos")]
    pub mission: PathBuf,
    /// nsplug macro definitions for the mission and its behaviour files; an argument
    /// without `=` is one more mission file (a fleet of them).
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
    /// End the run when this condition (.bhv syntax) holds, e.g. "MISSION = complete". In a
    /// fleet: `[NAME:]CONDITION`, repeatable, the run ends when all hold.
    #[arg(long, value_name = "CONDITION")]
    pub until: Vec<String>,
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
    /// Simulated seconds between progress lines when stderr is not a terminal (a fleet's
    /// lines, one per community, always).
    #[arg(long, value_name = "SECONDS", default_value_t = 10.0)]
    pub progress_every: f64,
    /// Extra directory searched for nsplug `#include` files (repeatable).
    #[arg(short = 'p', long = "path", value_name = "DIR")]
    pub include_paths: Vec<PathBuf>,
    /// Serve the web viewer on the run (as `coug view`); it stays up after the run until
    /// Ctrl-C.
    #[arg(long)]
    pub view: bool,
    /// Port of the viewer's page (with --view; 0 picks a free one).
    #[arg(long, value_name = "P", default_value_t = 9080, requires = "view")]
    pub http_port: u16,
    /// Address the viewer binds (with --view); anything but loopback needs --token.
    #[arg(
        long,
        value_name = "ADDR",
        default_value = "127.0.0.1",
        requires = "view"
    )]
    pub bind: std::net::IpAddr,
    /// A token the page must present (`?token=T`); required for a non-loopback --bind.
    #[arg(long, requires = "view")]
    pub token: Option<String>,
    /// Lockstep with --view: hold the run to this many times real time so a person can
    /// watch (default: as fast as it goes, the viewer dropping frames).
    #[arg(long, value_name = "X", requires = "view", requires = "lockstep")]
    pub pace: Option<f64>,
    /// Hardware in the loop without hardware (real time only): start the CougUV's four
    /// device emulators, point the mission's drivers at them (macros `EMULATE=true`,
    /// `EMULATE_BENCH`, `GPS_HOST`, `GPS_PORT`, `DVL_HOST`, `DVL_PORT`, `SEATRAC_DEVICE`,
    /// `TEENSY_DEVICE`) and let its `uSimDevices` feed them the simulator's truth.
    #[arg(long, conflicts_with = "lockstep")]
    pub emulate: bool,
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

/// A fleet's progress: every `every` simulated seconds, one line per community with its
/// helm state, active behaviours (from its own IVPHELM_SUMMARY postings) and position, read
/// through the fleet's `NAME:VAR` values.
struct FleetProgress {
    members: Vec<String>,
    active: Vec<Vec<String>>,
    next_sim: f64,
}

impl FleetProgress {
    fn new(members: Vec<String>) -> Self {
        FleetProgress {
            active: vec![Vec::new(); members.len()],
            members,
            next_sim: 0.0,
        }
    }

    /// Takes one IVPHELM_SUMMARY posting of community `member`.
    fn observe_summary(&mut self, member: &str, summary: &str) {
        if let Some(i) = self.members.iter().position(|m| m == member)
            && let Some(a) = behaviour_list(summary, "active_bhvs")
        {
            self.active[i] = a;
        }
    }

    /// The lines due at `sim` simulated seconds (`wall` seconds into the run), if any.
    fn lines(
        &mut self,
        sim: f64,
        wall: f64,
        get: &dyn Fn(&str) -> Option<Value>,
        every: f64,
    ) -> Option<String> {
        if sim < self.next_sim {
            return None;
        }
        while self.next_sim <= sim {
            self.next_sim += every.max(0.1);
        }
        let width = self.members.iter().map(String::len).max().unwrap_or(0);
        let mut out = String::new();
        for (name, active) in self.members.iter().zip(&self.active) {
            let var = |k: &str| get(&format!("{name}:{k}"));
            let state = text(var("IVPHELM_STATE")).unwrap_or_else(|| "-".into());
            let active = if active.is_empty() {
                "none".to_string()
            } else {
                active.join(",")
            };
            let f = |k: &str| num(var(k)).map_or("-".into(), |x| format!("{x:.1}"));
            out.push_str(&format!(
                "t={sim:7.1}s  {:6.0}x  {name:<width$}  helm={state}  active={active}  x={} y={} depth={}\n",
                sim / wall.max(1e-9),
                f("NAV_X"),
                f("NAV_Y"),
                f("NAV_DEPTH")
            ));
        }
        Some(out)
    }
}

/// The command line's observer: warnings to stderr, the progress line, Ctrl-C.
struct Cli {
    progress: Progress,
    /// A fleet run's progress (instead of `progress`'s single line).
    fleet: Option<FleetProgress>,
    wall: Instant,
    terminal: bool,
    every: f64,
    interrupted: Arc<AtomicBool>,
}

impl Observer for Cli {
    fn warning(&mut self, text: &str) {
        errln!("coug run: warning: {text}");
    }

    fn notice(&mut self, text: &str) {
        errln!("coug run: {text}");
    }

    fn helm_summary(&mut self, summary: &str) {
        self.progress.observe_summary(summary);
    }

    fn member_helm_summary(&mut self, member: &str, summary: &str) {
        if let Some(f) = &mut self.fleet {
            f.observe_summary(member, summary);
        }
    }

    fn step(&mut self, sim_s: f64, current: &dyn Fn(&str) -> Option<Value>) {
        if let Some(f) = &mut self.fleet {
            let wall = self.wall.elapsed().as_secs_f64();
            if let Some(text) = f.lines(sim_s, wall, current, self.every) {
                let mut err = std::io::stderr().lock();
                let _ = err.write_all(text.as_bytes());
                let _ = err.flush();
            }
            return;
        }
        self.progress
            .tick(sim_s, &self.wall, current, self.terminal, self.every);
    }

    fn stop_requested(&self) -> bool {
        self.interrupted.load(Ordering::Relaxed)
    }
}

/// A flag set on Ctrl-C (watched by a helper thread), so a run can stop between steps with
/// its log flushed.
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

fn error_lines(e: SessionError) -> Vec<String> {
    match e {
        SessionError::Load(l) => l.messages(),
        e => vec![e.to_string()],
    }
}

fn run_inner(args: &RunArgs) -> Result<i32, Vec<String>> {
    if !(args.max_time.is_finite() && args.max_time > 0.0) {
        return Err(vec![format!(
            "--max-time {}: expected a positive number of seconds",
            args.max_time
        )]);
    }
    let extra: Vec<PathBuf> = args
        .macros
        .iter()
        .filter(|m| !m.contains('='))
        .map(PathBuf::from)
        .collect();
    if !extra.is_empty() || args.mission.extension().is_some_and(|e| e == "fleet") {
        if args.emulate {
            return Err(vec![
                "--emulate runs one vehicle's mission, not a fleet".into(),
            ]);
        }
        return run_fleet(args, extra);
    }
    if args.until.len() > 1 {
        return Err(vec![
            "one --until for a single mission (join conditions with `and`)".into(),
        ]);
    }
    // The emulators first: their ports and terminals are the drivers' macros.
    let bench = if args.emulate {
        let p = runtime::hil::prepare(
            &args.mission,
            &args.macros,
            &args.include_paths,
            args.warp,
            args.seed,
        )
        .map_err(|e| vec![e])?;
        for (kind, at) in p.bench.endpoints() {
            errln!("coug run: emulated {}: {at}", kind.name());
        }
        Some(p)
    } else {
        None
    };
    let macros = bench.as_ref().map_or(&args.macros, |p| &p.macros);
    let loaded =
        session::load(&args.mission, macros, &args.include_paths).map_err(|e| e.messages())?;
    let checked = session::validate(&loaded);
    if !checked.errors.is_empty() {
        return Err(checked.errors);
    }
    for w in &checked.warnings {
        errln!("coug run: {w}");
    }
    for (name, reasons) in &checked.malconfig {
        report_malconfig(name, reasons);
    }
    for f in &checked.failed {
        errln!("coug run: error: {f}; the run goes on without it");
    }
    let opts = RunOptions {
        mode: if args.lockstep {
            Mode::Lockstep
        } else {
            Mode::RealTime {
                warp: args.warp,
                port: args.port,
            }
        },
        pokes: args.pokes.clone(),
        deploy: args.deploy,
        buttons: args.buttons.clone(),
        until: args.until.first().cloned(),
        max_time: args.max_time,
        log_dir: args.log_dir.clone(),
        seed: args.seed,
    };
    let terminal = std::io::stderr().is_terminal();
    let mut cli = Cli {
        progress: Progress::default(),
        fleet: None,
        wall: Instant::now(),
        terminal,
        every: args.progress_every,
        interrupted: interrupt_flag(),
    };
    let live = if args.view {
        let (from_mission, warning) =
            viewer::server::ViewerConfig::for_mission_file(&loaded.mission, &loaded.path);
        if let Some(w) = warning {
            errln!("coug run: warning: {w}");
        }
        let config = viewer::server::ViewerConfig {
            bind: std::net::SocketAddr::new(args.bind, args.http_port),
            token: args.token.clone(),
            ..from_mission
        };
        let live = viewer::live::LiveView::start(&config).map_err(|e| vec![e.to_string()])?;
        match &args.token {
            Some(t) => errln!("coug run: viewer at http://{}/?token={t}", live.addr()),
            None => errln!("coug run: viewer at http://{}/", live.addr()),
        }
        Some(live)
    } else {
        None
    };
    if let Some(p) = args.pace
        && !(p.is_finite() && p > 0.0)
    {
        return Err(vec![format!("--pace {p}: expected a positive speed-up")]);
    }
    let report = match &live {
        Some(live) => {
            let interrupted = cli.interrupted.clone();
            let r = session::run(
                &loaded,
                &opts,
                &mut viewer::live::ViewObserver::new(
                    &mut cli,
                    live,
                    session::LOCKSTEP_START,
                    args.pace,
                ),
            );
            cli.progress.finish();
            if r.is_ok() {
                errln!("coug run: the run ended; the viewer stays up until Ctrl-C");
            }
            while r.is_ok() && !interrupted.load(Ordering::Relaxed) {
                std::thread::sleep(Duration::from_millis(100));
            }
            r
        }
        None => {
            let r = session::run(&loaded, &opts, &mut cli);
            cli.progress.finish();
            r
        }
    };
    let report = report.map_err(error_lines)?;
    if let Some(p) = bench {
        for (kind, stats) in p.bench.stop() {
            if let Ok(st) = stats {
                errln!(
                    "coug run: emulated {}: {} bytes out, {} in, {} connection(s), {} dropped, {} flushed unread",
                    kind.name(),
                    st.bytes_out,
                    st.bytes_in,
                    st.connections,
                    st.dropped,
                    st.flushed
                );
            }
        }
    }
    if let Ended::Interrupted { .. } = report.ended {
        if args.lockstep {
            errln!(
                "coug run: interrupted at {:.1} simulated s; log: {}",
                report.sim_s(),
                report.alog
            );
        } else {
            errln!(
                "coug run: interrupted after {:.1} wall s; log: {}",
                report.wall_s,
                report.alog
            );
        }
        return Ok(130);
    }
    out!("{report}");
    let code = match report.ended {
        Ended::Outcome(Outcome::ConditionMet { .. }) => 0,
        _ if report.until_pending() => 2,
        _ => 0,
    };
    if code == 2 {
        errln!(
            "coug run: still pending after {:.1} simulated s: {} (now {})",
            report.sim_s(),
            args.until.first().map_or("", String::as_str),
            report.until_text().join(", ")
        );
    }
    Ok(code)
}

/// `coug run` with several communities: a `.fleet` file, or several `.moos` files.
fn run_fleet(args: &RunArgs, extra: Vec<PathBuf>) -> Result<i32, Vec<String>> {
    use runtime::fleet::LoadedFleet;
    if args.view {
        return Err(vec!["--view runs on one mission, not on a fleet".into()]);
    }
    if args.port.is_some() {
        return Err(vec![
            "--port: in a fleet each community's MOOSDB is on its mission's ServerPort (0 or none: a free port)"
                .into(),
        ]);
    }
    let macros: Vec<String> = args
        .macros
        .iter()
        .filter(|m| m.contains('='))
        .cloned()
        .collect();
    let fleet = if extra.is_empty() {
        LoadedFleet::from_file(&args.mission, &macros, &args.include_paths)
    } else {
        let mut paths = vec![args.mission.clone()];
        paths.extend(extra);
        LoadedFleet::from_missions(&paths, &macros, &args.include_paths)
    }
    .map_err(|e| e.messages())?;
    let checked = session::validate_fleet(&fleet);
    if !checked.errors.is_empty() {
        return Err(checked.errors);
    }
    for w in &checked.warnings {
        errln!("coug run: {w}");
    }
    for (name, reasons) in &checked.malconfig {
        report_malconfig(name, reasons);
    }
    for f in &checked.failed {
        errln!("coug run: error: {f}; the run goes on without it");
    }
    let opts = session::FleetOptions {
        mode: if args.lockstep {
            Mode::Lockstep
        } else {
            Mode::RealTime {
                warp: args.warp,
                port: None,
            }
        },
        pokes: args.pokes.clone(),
        deploy: args.deploy,
        buttons: args.buttons.clone(),
        until: args.until.clone(),
        max_time: args.max_time,
        log_dir: args.log_dir.clone(),
        seed: args.seed,
        threads: 0,
    };
    let mut cli = Cli {
        progress: Progress::default(),
        fleet: Some(FleetProgress::new(
            fleet.members.iter().map(|m| m.name.clone()).collect(),
        )),
        wall: Instant::now(),
        terminal: std::io::stderr().is_terminal(),
        every: args.progress_every,
        interrupted: interrupt_flag(),
    };
    let report = session::run_fleet(&fleet, &opts, &mut cli);
    cli.progress.finish();
    let report = report.map_err(error_lines)?;
    if let Ended::Interrupted { .. } = report.ended {
        errln!("coug run: interrupted at {:.1} simulated s", report.sim_s());
        return Ok(130);
    }
    out!("{report}");
    let code = match report.ended {
        Ended::Outcome(Outcome::ConditionMet { .. }) => 0,
        _ if report.until_pending() => 2,
        _ => 0,
    };
    if code == 2 {
        for (name, r) in &report.members {
            if r.until.is_some() {
                errln!(
                    "coug run: {name}: still pending after {:.1} simulated s: {} (now {})",
                    report.sim_s(),
                    r.until.as_deref().unwrap_or(""),
                    r.until_text().join(", ")
                );
            }
        }
    }
    Ok(code)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fleet_prints_one_progress_line_per_community_every_period() {
        let mut p = FleetProgress::new(vec!["shoreside".into(), "henry".into(), "ike".into()]);
        p.observe_summary(
            "henry",
            "iter=12,utc_time=1786000003.00,ofnum=1,var=speed:2,var=course:180,\
             active_bhvs=survey$1786000003.00$100.00000$9$0.01000$1/1$1,idle_bhvs=return$0.00$n/a",
        );
        p.observe_summary("nobody", "active_bhvs=x$1$1$1$1$1/1$1");
        let get = |k: &str| -> Option<Value> {
            match k {
                "henry:IVPHELM_STATE" => Some(Value::text("DRIVE")),
                "henry:NAV_X" => Some(Value::Double(12.34)),
                "henry:NAV_Y" => Some(Value::Double(-5.0)),
                "henry:NAV_DEPTH" => Some(Value::Double(0.0)),
                "ike:IVPHELM_STATE" => Some(Value::text("PARK")),
                "ike:NAV_X" => Some(Value::Double(60.0)),
                _ => None,
            }
        };
        let text = p.lines(0.0, 1.0, &get, 10.0).expect("due at the start");
        assert_eq!(
            text,
            "t=    0.0s       0x  shoreside  helm=-  active=none  x=- y=- depth=-\n\
             t=    0.0s       0x  henry      helm=DRIVE  active=survey  x=12.3 y=-5.0 depth=0.0\n\
             t=    0.0s       0x  ike        helm=PARK  active=none  x=60.0 y=- depth=-\n"
        );
        // Not again before the period; then once, with the speed-up over the wall.
        assert!(p.lines(9.9, 2.0, &get, 10.0).is_none());
        let text = p.lines(25.0, 2.5, &get, 10.0).expect("due");
        assert!(text.starts_with("t=   25.0s      10x  shoreside"), "{text}");
        assert_eq!(text.lines().count(), 3);
        assert!(p.lines(29.0, 3.0, &get, 10.0).is_none(), "next at 30 s");
        assert!(p.lines(30.0, 3.0, &get, 10.0).is_some());
    }

    fn write(name: &str, text: &str) -> PathBuf {
        let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/target/tmp/run-load"));
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
        let loaded = session::load(&ok, &[], &[]).unwrap_or_else(|e| panic!("{e:?}"));
        assert_eq!(loaded.mission.antler_runs().len(), 1);
        assert_eq!(loaded.mission.global("ServerPort"), Some("9000"));
        // A block without its `{`: the app would run without its configuration.
        let bad = write(
            "nobrace.moos",
            "ServerPort = 9000\nProcessConfig = ANTLER\n  Run = MOOSDB\n}\n",
        );
        let errors = session::load(&bad, &[], &[])
            .err()
            .expect("refused")
            .messages();
        assert!(
            errors[0].contains("is not followed by its block"),
            "{errors:?}"
        );
    }
}
