//! Several communities in one run (issue #16, point 4): a [`LoadedFleet`] run as `coug run`
//! runs one mission, each community with its own bus (MOOSDB), apps and alog, all sharing
//! one [`Shared`] set.
//!
//! Lockstep: one virtual clock. The run goes from instant to instant (the earliest next
//! event of any community); at each, every community processes its events of that instant,
//! in fleet order (the base first), or on a pool of [`FleetOptions::threads`] threads made
//! once per run, each taking the next community not yet stepped, that meet at the end of
//! each instant. pShare routes
//! between communities of the run go through the in-process [`crate::pshare::PShareHub`]
//! and arrive at the receiver's first iteration after they were sent; the simulated
//! acoustic channel ([`crate::acomms_apps::AcousticNet`]) only collects what the modems ask
//! during an instant and merges it in a fixed order (time, kind, modem id, each modem's
//! order) when the run moves on. So what one community hands another is never read within
//! the instant it was handed over, and two runs of a fleet, on any number of threads, write
//! the same bytes in every community's alog.
//!
//! Real time: each community has its own TCP MOOSDB (on its mission's `ServerPort` when the
//! file sets one other than 0, else on a port the system picks) and runs as a single
//! real-time mission does, on its own thread; pShare goes over UDP, and the communities'
//! uSimModems share one acoustic channel (the run's [`Shared`]), each reaching it at its own
//! clock's time (a call behind the channel's latest time is stamped at it and counted late).
//!
//! Targets: a `--poke`, `--button` or `--until` text may start with `NAME:` to address the
//! community `NAME`. Without one, a poke goes to every community, a button is pressed in
//! every community that has it, and a condition must hold in every vehicle. `--deploy`
//! deploys every community (its DEPLOY button, or `DEPLOY=true` and
//! `MOOS_MANUAL_OVERRIDE=false`). The lockstep run ends when every condition holds at one
//! instant; in real time each community stops when its own condition holds (those without
//! one stop with the last).

use std::fmt;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use mission::condition::{Condition, parse_condition};

use crate::antler::logger_config;
use crate::app::Value;
use crate::bus::Bus;
use crate::clock::VirtualClock;
use crate::fleet::{LoadedFleet, Member, Role};
use crate::logger::LateSink;
use crate::pshare::{HUB, PShareHub};
use crate::scheduler::{Outcome, RunError, Scheduler};
use crate::shared::Shared;

use super::realtime::realtime;
use super::run::*;
use super::*;

/// What a fleet run is asked to do (see the module docs for the `NAME:` targets).
#[derive(Debug, Clone)]
pub struct FleetOptions {
    /// Lockstep or real time (a real-time `port` is ignored: each community has its own).
    pub mode: Mode,
    /// `[NAME:]VAR=VALUE[@T]`: to one community, or to every one.
    pub pokes: Vec<String>,
    /// Deploy every community.
    pub deploy: bool,
    /// `[NAME:]LABEL`: a pMarineViewer button of one community, or of every one that has it.
    pub buttons: Vec<String>,
    /// `[NAME:]CONDITION`: in one community, or in every vehicle; the run ends when all hold.
    pub until: Vec<String>,
    /// Simulated seconds before the run ends anyway.
    pub max_time: f64,
    /// The folder of the communities' log folders (`DIR/NAME/`); default: each mission's
    /// own log path, with the community's name appended.
    pub log_dir: Option<PathBuf>,
    /// Seed of every random draw (each community mixes in its name).
    pub seed: u64,
    /// Lockstep: threads stepping the communities (0, the default: one per core; at most
    /// one per community). The communities are independent within an instant (see the
    /// module docs), so every count writes the same bytes, for fleets linked by pShare and
    /// fleets sharing a simulated acoustic channel alike.
    pub threads: usize,
}

impl Default for FleetOptions {
    fn default() -> Self {
        FleetOptions {
            mode: Mode::Lockstep,
            pokes: Vec::new(),
            deploy: false,
            buttons: Vec::new(),
            until: Vec::new(),
            max_time: 3600.0,
            log_dir: None,
            seed: 1,
            threads: 0,
        }
    }
}

/// What a fleet run did: how it ended, and each community's own report (its alog, totals and
/// `until` values).
#[derive(Debug, Clone)]
pub struct FleetReport {
    /// The fleet file (or the first mission of a list).
    pub fleet: PathBuf,
    /// How the run ended.
    pub ended: Ended,
    /// MOOS time of the start.
    pub start: f64,
    /// Wall-clock seconds the run took.
    pub wall_s: f64,
    /// Every community's report, in fleet order.
    pub members: Vec<(String, RunReport)>,
    /// pShare datagrams handed between communities in process (lockstep).
    pub in_process: u64,
}

impl FleetReport {
    /// Simulated seconds from start to end.
    pub fn sim_s(&self) -> f64 {
        let end = match self.ended {
            Ended::Outcome(
                Outcome::ConditionMet { time }
                | Outcome::MaxTime { time }
                | Outcome::AllFinished { time },
            )
            | Ended::Interrupted { time } => time,
        };
        end - self.start
    }

    /// True when `until` conditions were given and did not all hold by the end.
    pub fn until_pending(&self) -> bool {
        self.members.iter().any(|(_, r)| r.until.is_some())
            && !matches!(self.ended, Ended::Outcome(Outcome::ConditionMet { .. }))
    }

    /// The report of community `name`.
    pub fn member(&self, name: &str) -> Option<&RunReport> {
        self.members.iter().find(|(n, _)| n == name).map(|(_, r)| r)
    }
}

impl fmt::Display for FleetReport {
    /// The closing summary of a fleet run: how it ended, then per community its distance,
    /// completed behaviours, helm state, `until` values and log.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "coug run: fleet {} ({} communities)",
            self.fleet.display(),
            self.members.len()
        )?;
        let how = match self.ended {
            Ended::Outcome(Outcome::ConditionMet { .. }) => "every until condition met".into(),
            Ended::Outcome(Outcome::MaxTime { .. }) => format!(
                "max time {} s reached",
                self.members.first().map_or(0.0, |(_, r)| r.max_time)
            ),
            Ended::Outcome(Outcome::AllFinished { .. }) => "every app finished".to_string(),
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
        if self.in_process > 0 {
            writeln!(f, "  pShare:      {} datagrams in process", self.in_process)?;
        }
        for (name, r) in &self.members {
            writeln!(f, "  [{name}]")?;
            if let Some(t) = &r.totals {
                if t.summary.distance > 0.0 {
                    writeln!(f, "    distance:  {:.1} m", t.summary.distance)?;
                }
                if !t.completed.is_empty() {
                    writeln!(f, "    completed: {}", t.completed.join(", "))?;
                }
                if let Some(h) = &t.summary.helm_state {
                    writeln!(f, "    helm:      {h}")?;
                }
                for why in &t.malconfig {
                    writeln!(f, "    malconfig: {why}")?;
                }
            }
            for line in r.until_text() {
                writeln!(f, "    {line}")?;
            }
            writeln!(f, "    log:       {}", r.alog)?;
        }
        Ok(())
    }
}

/// Splits `NAME:rest` when `NAME` is a community of the fleet; `Err` when the text starts
/// with what can only be a community name that the fleet does not have.
fn target<'a>(text: &'a str, fleet: &LoadedFleet) -> Result<(Option<&'a str>, &'a str), String> {
    let Some((pre, rest)) = text.split_once(':') else {
        return Ok((None, text));
    };
    let name = pre.trim();
    // `VAR:=VALUE` is a string poke, not a target.
    if rest.starts_with('=') || !crate::fleet::valid_name(name) {
        return Ok((None, text));
    }
    if fleet.member(name).is_some() {
        return Ok((Some(name), rest.trim_start()));
    }
    let names: Vec<&str> = fleet.members.iter().map(|m| m.name.as_str()).collect();
    Err(format!(
        "{text}: no community {name} in the fleet (it has {})",
        names.join(", ")
    ))
}

/// FNV-1a of a community's name, mixed into the run's seed.
fn name_seed(seed: u64, name: &str) -> u64 {
    use std::hash::Hasher as _;
    let mut h = fnv::FnvHasher::default();
    h.write(name.as_bytes());
    seed ^ h.finish()
}

/// One community's share of the options.
struct MemberPlan {
    opts: RunOptions,
    until: Option<Condition>,
    log_dir: PathBuf,
}

fn member_plans(fleet: &LoadedFleet, opts: &FleetOptions) -> Result<Vec<MemberPlan>, SessionError> {
    let invalid = SessionError::Invalid;
    let mut plans: Vec<MemberPlan> = Vec::new();
    for m in &fleet.members {
        let log_dir = match &opts.log_dir {
            Some(d) => d.join(&m.name),
            None => PathBuf::from(logger_config(&m.loaded.mission).path).join(&m.name),
        };
        plans.push(MemberPlan {
            opts: RunOptions {
                mode: opts.mode,
                pokes: Vec::new(),
                deploy: opts.deploy,
                buttons: Vec::new(),
                until: None,
                max_time: opts.max_time,
                log_dir: Some(log_dir.clone()),
                seed: name_seed(opts.seed, &m.name),
            },
            until: None,
            log_dir,
        });
    }
    let index = |name: &str| fleet.members.iter().position(|m| m.name == name);
    for p in &opts.pokes {
        match target(p, fleet).map_err(|e| invalid(format!("--poke {e}")))? {
            (Some(n), rest) => plans[index(n).unwrap_or(0)].opts.pokes.push(rest.into()),
            (None, all) => plans
                .iter_mut()
                .for_each(|mp| mp.opts.pokes.push(all.into())),
        }
    }
    for b in &opts.buttons {
        match target(b, fleet).map_err(|e| invalid(format!("--button {e}")))? {
            (Some(n), rest) => plans[index(n).unwrap_or(0)].opts.buttons.push(rest.into()),
            (None, label) => {
                let mut any = false;
                for (mp, m) in plans.iter_mut().zip(&fleet.members) {
                    let all = mission::buttons::buttons(&m.loaded.mission);
                    if mission::buttons::find(&all, label).is_some() {
                        mp.opts.buttons.push(label.into());
                        any = true;
                    }
                }
                if !any {
                    return Err(invalid(format!(
                        "--button {label}: no community of the fleet has that button"
                    )));
                }
            }
        }
    }
    // Each community's conditions, joined with `and`.
    let mut texts: Vec<Vec<String>> = vec![Vec::new(); plans.len()];
    for u in &opts.until {
        let (who, cond) = target(u, fleet).map_err(|e| invalid(format!("--until {e}")))?;
        parse_condition(cond).map_err(|e| invalid(format!("--until {u:?}: {e}")))?;
        match who {
            Some(n) => texts[index(n).unwrap_or(0)].push(cond.into()),
            None => {
                let vehicles: Vec<usize> = (0..plans.len())
                    .filter(|&i| fleet.members[i].role == Role::Vehicle)
                    .collect();
                if vehicles.is_empty() {
                    return Err(invalid(format!(
                        "--until {u:?}: the fleet has no vehicle; name a community (NAME: {cond})"
                    )));
                }
                vehicles
                    .into_iter()
                    .for_each(|i| texts[i].push(cond.into()));
            }
        }
    }
    for (mp, t) in plans.iter_mut().zip(texts) {
        if t.is_empty() {
            continue;
        }
        let joined = t
            .iter()
            .map(|c| format!("({c})"))
            .collect::<Vec<_>>()
            .join(" and ");
        let text = if t.len() == 1 { t[0].clone() } else { joined };
        let c = parse_condition(&text).map_err(|e| invalid(format!("--until {text:?}: {e}")))?;
        mp.until = Some(c);
        mp.opts.until = Some(text);
    }
    Ok(plans)
}

/// Runs every community of `fleet` together, as `opts` says (see the module docs).
pub fn run_fleet(
    fleet: &LoadedFleet,
    opts: &FleetOptions,
    observer: &mut dyn Observer,
) -> Result<FleetReport, SessionError> {
    if !(opts.max_time.is_finite() && opts.max_time > 0.0) {
        return Err(SessionError::Invalid(format!(
            "--max-time {}: expected a positive number of seconds",
            opts.max_time
        )));
    }
    if fleet.members.is_empty() {
        return Err(SessionError::Invalid("the fleet has no community".into()));
    }
    let plans = member_plans(fleet, opts)?;
    match opts.mode {
        Mode::Lockstep => fleet_lockstep(fleet, plans, opts, observer),
        Mode::RealTime { warp, .. } => fleet_realtime(fleet, plans, warp, opts, observer),
    }
}

/// One community being run in lockstep.
struct Running<'a> {
    member: &'a Member,
    plan: MemberPlan,
    sched: Scheduler,
    sink: LateSink,
    alog: super::tally::OpenLog,
    finished: bool,
}

/// The write buffer of each community's alog in a lockstep fleet run: a quarter of a single
/// mission's (a vehicle of missions/fleet_survey logs ~13 kB per simulated second, so it is
/// still written in pieces of ~1 simulated second): 48 KiB less heap per vehicle of a large
/// fleet (heaptrack; the resident set hardly moves, the larger buffer's pages were not all
/// touched).
const FLEET_LOG_BUFFER: usize = 1 << 14;

fn fleet_lockstep(
    fleet: &LoadedFleet,
    plans: Vec<MemberPlan>,
    opts: &FleetOptions,
    observer: &mut dyn Observer,
) -> Result<FleetReport, SessionError> {
    let start = LOCKSTEP_START;
    let opened = chrono::DateTime::from_timestamp(start as i64, 0)
        .map(|d| d.naive_utc())
        .unwrap_or_default();
    let shared = Shared::new();
    let hub = shared.get_or_insert_with(HUB, PShareHub::new);
    let mut running: Vec<Running<'_>> = Vec::new();
    for (member, plan) in fleet.members.iter().zip(plans) {
        let loaded = &member.loaded;
        let name = &member.name;
        let helm = loaded.first_helm();
        let pokes = pokes(&plan.opts, &loaded.mission, &helm, start)
            .map_err(|e| SessionError::Invalid(format!("{name}: {e}")))?;
        let (target, sink) = log_target(loaded, &plan.log_dir, opened);
        let p = loaded
            .plan_shared(start, plan.opts.seed, Some(target), shared.clone())
            .map_err(|e| SessionError::Invalid(format!("{name}: {e}")))?;
        let alog = open_log(loaded, &plan.log_dir, wall_now(), &sink, FLEET_LOG_BUFFER)?;
        for ext in &p.external {
            observer.warning(&format!(
                "{name}: {}:{}: {} is not built into coug; skipped in lockstep",
                ext.span.file_name(),
                ext.span.line,
                ext.app
            ));
        }
        let mut sched = Scheduler::new(Bus::new(&p.globals.community, start), VirtualClock, start);
        for app in p.apps {
            sched.add_app(app).map_err(|e| run_error(e, &alog))?;
        }
        for poke in pokes {
            sched.add_poke(poke)?;
        }
        if let Some(c) = &plan.until {
            sched.watch_until(c.clone());
        }
        sched.tap("IVPHELM_SUMMARY");
        running.push(Running {
            member,
            plan,
            sched,
            sink,
            alog,
            finished: false,
        });
    }
    let threads = match opts.threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        n => n,
    }
    .min(running.len())
    .max(1);
    // One pool for the run: its threads live from instant to instant (spawning them at every
    // instant cost more than some instants' work) and take communities as they finish the
    // last, so one slow community does not idle the other threads.
    let pool = if threads > 1 {
        match rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("coug-fleet-{i}"))
            .build()
        {
            Ok(pool) => Some(pool),
            Err(e) => {
                observer.warning(&format!(
                    "no worker threads ({e}): the communities are stepped on one thread"
                ));
                None
            }
        }
    } else {
        None
    };
    let wall = Instant::now();
    let end = start + opts.max_time;
    let conditioned = running.iter().any(|r| r.plan.until.is_some());
    let mut next_step = start + 1.0;
    let ended = loop {
        if observer.stop_requested() {
            let t = running.iter().map(|r| r.sched.now()).fold(start, f64::max);
            break Ended::Interrupted { time: t };
        }
        let next = running
            .iter()
            .filter(|r| !r.finished)
            .filter_map(|r| r.sched.next_event_time())
            .min_by(f64::total_cmp);
        let Some(t) = next else {
            let t = running.iter().map(|r| r.sched.now()).fold(start, f64::max);
            break Ended::Outcome(Outcome::AllFinished { time: t });
        };
        if t > end {
            break Ended::Outcome(Outcome::MaxTime { time: end });
        }
        advance_all(&mut running, t, pool.as_ref())?;
        for r in running.iter_mut() {
            for p in r.sched.take_taps() {
                if let Some(v) = p.value.as_str() {
                    observer.member_helm_summary(&r.member.name, v);
                }
            }
        }
        if conditioned
            && running
                .iter_mut()
                .filter(|r| r.plan.until.is_some())
                .all(|r| r.sched.until_holds())
        {
            break Ended::Outcome(Outcome::ConditionMet { time: t });
        }
        if t >= next_step {
            while next_step <= t {
                next_step += 1.0;
            }
            let first = running
                .iter()
                .position(|r| r.member.role == Role::Vehicle)
                .unwrap_or(0);
            let current = |k: &str| -> Option<Value> {
                match k.split_once(':') {
                    Some((n, var)) => running
                        .iter()
                        .find(|r| r.member.name == n)
                        .and_then(|r| r.sched.current(var)),
                    None => running[first].sched.current(k),
                }
            };
            observer.step(t - start, &current);
        }
    };
    if matches!(ended, Ended::Outcome(_)) {
        for r in &mut running {
            r.sched
                .deliver_pending()
                .map_err(|e| run_error(e, &r.alog))?;
        }
    }
    let wall_s = wall.elapsed().as_secs_f64();
    let mut first_err = None;
    let mut members = Vec::new();
    for mut r in running {
        let until_values = r.sched.until_values();
        if let Err(e) = r.sched.stop()
            && first_err.is_none()
        {
            first_err = Some(app_failed(e, &r.alog));
        }
        drop(r.sched);
        let end = Ending(ended.clone(), start, wall_s, until_values);
        match close_and_report(&r.member.loaded, &r.plan.opts, &r.sink, r.alog, end) {
            Ok(report) => members.push((r.member.name.clone(), report)),
            Err(e) => {
                first_err.get_or_insert(e);
            }
        }
    }
    if let Some(e) = first_err {
        return Err(e);
    }
    Ok(FleetReport {
        fleet: fleet.path.clone(),
        ended,
        start,
        wall_s,
        members,
        in_process: hub.delivered(),
    })
}

/// Steps every unfinished community through instant `t`: on the calling thread alone, or
/// on `pool`'s threads, each taking the next community not yet stepped (the communities of
/// an instant are independent: what one sends another reads at a later instant only). The
/// first error in fleet order is the run's. Never inlined: profilers (callgrind's
/// `--toggle-collect=runtime::session::fleet::advance_all`) count the fleet's loop by
/// this name.
#[inline(never)]
fn advance_all(
    running: &mut [Running<'_>],
    t: f64,
    pool: Option<&rayon::ThreadPool>,
) -> Result<(), SessionError> {
    use rayon::prelude::*;
    fn step(r: &mut Running<'_>, t: f64) -> Result<(), SessionError> {
        if r.finished {
            return Ok(());
        }
        if let Some(Outcome::AllFinished { .. }) =
            r.sched.advance(t).map_err(|e| run_error(e, &r.alog))?
        {
            r.finished = true;
        }
        Ok(())
    }
    let Some(pool) = pool else {
        return running.iter_mut().try_for_each(|r| step(r, t));
    };
    let first_err = pool.install(|| {
        running
            .par_iter_mut()
            .with_max_len(1)
            .enumerate()
            .filter_map(|(i, r)| step(r, t).err().map(|e| (i, e)))
            .min_by_key(|(i, _)| *i)
    });
    match first_err {
        Some((_, e)) => Err(e),
        None => Ok(()),
    }
}

fn run_error(e: RunError, alog: &str) -> SessionError {
    match e {
        RunError::App(e) => app_failed(e, alog),
        RunError::Bus(e) => SessionError::Bus(e),
    }
}

/// The variables a real-time community's thread reports for the fleet's progress (read by
/// the fleet's [`Observer::step`] as `NAME:VAR`).
pub const PROGRESS_VARS: [&str; 4] = ["IVPHELM_STATE", "NAV_X", "NAV_Y", "NAV_DEPTH"];

/// What a community's thread tells the fleet's observer.
enum Said {
    Warning(String),
    Notice(String),
    /// The community `.0`'s helm summary.
    Summary(usize, String),
    /// The community `.0` at `.1` simulated seconds, with its [`PROGRESS_VARS`].
    Step(usize, f64, Vec<(&'static str, Value)>),
}

/// A real-time community's observer: forwards to the fleet's observer (on the caller's
/// thread) and stops when the fleet does.
struct Relay {
    name: String,
    index: usize,
    tx: mpsc::Sender<Said>,
    stop: Arc<AtomicBool>,
}

impl Observer for Relay {
    fn warning(&mut self, text: &str) {
        let _ = self
            .tx
            .send(Said::Warning(format!("{}: {text}", self.name)));
    }

    fn notice(&mut self, text: &str) {
        let _ = self.tx.send(Said::Notice(format!("{}: {text}", self.name)));
    }

    fn helm_summary(&mut self, summary: &str) {
        let _ = self.tx.send(Said::Summary(self.index, summary.to_string()));
    }

    fn step(&mut self, sim_s: f64, current: &dyn Fn(&str) -> Option<Value>) {
        let values = PROGRESS_VARS
            .iter()
            .filter_map(|k| current(k).map(|v| (*k, v)))
            .collect();
        let _ = self.tx.send(Said::Step(self.index, sim_s, values));
    }

    fn stop_requested(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }
}

/// The MOOSDB port of a community in a real-time fleet: its mission's `ServerPort` when the
/// file sets one other than 0, else 0 (the system picks).
pub fn fleet_port(loaded: &LoadedMission) -> u16 {
    loaded
        .mission
        .global("ServerPort")
        .and_then(|p| p.trim().parse::<u16>().ok())
        .unwrap_or(0)
}

fn fleet_realtime(
    fleet: &LoadedFleet,
    plans: Vec<MemberPlan>,
    warp: Option<f64>,
    opts: &FleetOptions,
    observer: &mut dyn Observer,
) -> Result<FleetReport, SessionError> {
    let stop = Arc::new(AtomicBool::new(false));
    let (tx, rx) = mpsc::channel::<Said>();
    let wall = Instant::now();
    let start = moosdb::time::unix_now() * warp.unwrap_or(1.0);
    let conditioned: Vec<bool> = plans.iter().map(|p| p.until.is_some()).collect();
    // The communities' media (uSimModem's channel) are shared as in lockstep; no pShare hub:
    // pShare goes over UDP.
    let shared = Shared::new();
    let results: Vec<Result<RunReport, SessionError>> = std::thread::scope(|scope| {
        let mut handles = Vec::new();
        for (index, (member, plan)) in fleet.members.iter().zip(plans).enumerate() {
            let mut relay = Relay {
                name: member.name.clone(),
                index,
                tx: tx.clone(),
                stop: stop.clone(),
            };
            let shared = shared.clone();
            handles.push(scope.spawn(move || {
                let loaded = &member.loaded;
                let port = fleet_port(loaded);
                let helm = loaded.first_helm();
                let at = moosdb::time::unix_now() * warp.unwrap_or(1.0);
                let pokes = pokes(&plan.opts, &loaded.mission, &helm, at)?;
                realtime(
                    loaded,
                    &plan.opts,
                    (warp, Some(port)),
                    pokes,
                    plan.until,
                    &plan.log_dir,
                    shared,
                    &mut relay,
                )
            }));
        }
        drop(tx);
        // Each community's latest progress values, and the simulated time of the latest.
        let mut latest: Vec<Vec<(&'static str, Value)>> = vec![Vec::new(); fleet.members.len()];
        let mut sim = 0.0f64;
        let first = fleet
            .members
            .iter()
            .position(|m| m.role == Role::Vehicle)
            .unwrap_or(0);
        // Forward what the communities say; stop the ones without a condition once every
        // one with a condition has ended (or all, on the caller's request).
        loop {
            match rx.recv_timeout(Duration::from_millis(50)) {
                Ok(Said::Warning(w)) => observer.warning(&w),
                Ok(Said::Notice(n)) => observer.notice(&n),
                Ok(Said::Summary(i, s)) => observer.member_helm_summary(&fleet.members[i].name, &s),
                Ok(Said::Step(i, t, values)) => {
                    latest[i] = values;
                    sim = sim.max(t);
                    let lookup = |i: usize, var: &str| {
                        latest[i]
                            .iter()
                            .find(|(k, _)| *k == var)
                            .map(|(_, v)| v.clone())
                    };
                    let current = |k: &str| -> Option<Value> {
                        match k.split_once(':') {
                            Some((n, var)) => fleet
                                .members
                                .iter()
                                .position(|m| m.name == n)
                                .and_then(|i| lookup(i, var)),
                            None => lookup(first, k),
                        }
                    };
                    observer.step(sim, &current);
                }
                Err(mpsc::RecvTimeoutError::Timeout) => {}
                Err(mpsc::RecvTimeoutError::Disconnected) => break,
            }
            if observer.stop_requested() {
                stop.store(true, Ordering::Relaxed);
            }
            let waiting = handles
                .iter()
                .zip(&conditioned)
                .any(|(h, c)| *c && !h.is_finished());
            if conditioned.iter().any(|c| *c) && !waiting {
                stop.store(true, Ordering::Relaxed);
            }
        }
        handles
            .into_iter()
            .map(|h| {
                h.join().unwrap_or_else(|_| {
                    Err(SessionError::Net("a community's thread panicked".into()))
                })
            })
            .collect()
    });
    let wall_s = wall.elapsed().as_secs_f64();
    let mut members = Vec::new();
    for (m, r) in fleet.members.iter().zip(results) {
        members.push((m.name.clone(), r.map_err(|e| prefix(&m.name, e))?));
    }
    let met = members
        .iter()
        .zip(&conditioned)
        .filter(|(_, c)| **c)
        .all(|((_, r), _)| matches!(r.ended, Ended::Outcome(Outcome::ConditionMet { .. })));
    let end_time = members
        .iter()
        .map(|(_, r)| r.end_time())
        .fold(start, f64::max);
    let ended = if observer.stop_requested() {
        Ended::Interrupted { time: end_time }
    } else if conditioned.iter().any(|c| *c) && met {
        Ended::Outcome(Outcome::ConditionMet { time: end_time })
    } else if end_time >= start + opts.max_time {
        Ended::Outcome(Outcome::MaxTime { time: end_time })
    } else {
        Ended::Outcome(Outcome::AllFinished { time: end_time })
    };
    Ok(FleetReport {
        fleet: fleet.path.clone(),
        ended,
        start,
        wall_s,
        members,
        in_process: 0,
    })
}

fn prefix(name: &str, e: SessionError) -> SessionError {
    match e {
        SessionError::Invalid(m) => SessionError::Invalid(format!("{name}: {m}")),
        SessionError::Net(m) => SessionError::Net(format!("{name}: {m}")),
        SessionError::LogOpen(m) => SessionError::LogOpen(format!("{name}: {m}")),
        e => e,
    }
}

/// Validates every community as [`validate`] does one mission; findings are prefixed with
/// the community's name.
pub fn validate_fleet(fleet: &LoadedFleet) -> Validation {
    let mut all = Validation::default();
    for m in &fleet.members {
        let v = validate(&m.loaded);
        all.warnings.extend(v.warnings);
        all.malconfig.extend(
            v.malconfig
                .into_iter()
                .map(|(app, why)| (format!("{}: {app}", m.name), why)),
        );
        all.failed
            .extend(v.failed.into_iter().map(|f| format!("{}: {f}", m.name)));
        all.errors
            .extend(v.errors.into_iter().map(|e| format!("{}: {e}", m.name)));
    }
    all
}
