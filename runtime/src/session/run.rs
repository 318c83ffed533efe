//! Starting a run: its errors, pokes and log session, and the lockstep loop.

use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::time::Instant;

use chrono::NaiveDateTime;
use mission::bhv::BehaviorFile;
use mission::buttons::{self, ButtonValue};
use mission::condition::{Condition, parse_condition};
use mission::moos::MissionFile;
use thiserror::Error;

use crate::antler::{LogTarget, logger_config};
use crate::app::{AppError, Value};
use crate::bus::Bus;
use crate::bus::BusError;
use crate::clock::VirtualClock;
use crate::logger::{LateSink, SideFiles};
use crate::remote::RemoteError;
use crate::scheduler::{Outcome, Poke, PokeAt, RunError, Scheduler};

use super::realtime::*;
use super::tally::OpenLog;
use super::*;
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

pub(super) fn app_failed(e: AppError, alog: &str) -> SessionError {
    match e {
        AppError::Io { app, source, .. } => SessionError::LogWrite {
            app: Some(app),
            alog: alog.to_string(),
            source,
        },
    }
}

/// Flushes and closes the alog: any write error of the session fails the run.
pub(super) fn close_log(sink: &LateSink, alog: &str) -> Result<(), SessionError> {
    sink.close().map_err(|source| SessionError::LogWrite {
        app: None,
        alog: alog.to_string(),
        source,
    })
}

/// The pokes of the options: the DEPLOY press, the button presses, then the pokes, each
/// after the first helm's first iteration unless timed. `start` is the run's MOOS start
/// time (a button's `$[UTC]`).
pub(super) fn pokes(
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
pub(super) fn log_target(
    loaded: &LoadedMission,
    dir: &Path,
    opened: NaiveDateTime,
) -> (LogTarget, LateSink) {
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

/// The alog's write buffer of a single mission.
pub(super) const LOG_BUFFER: usize = 1 << 16;

/// Creates the session's folder and alog, named from `named` (the wall-clock start), never
/// over an existing log, attaches the file to `sink` behind a write buffer of `buffer`
/// bytes, and returns the alog's path and the sink's tally (pLogger counts the report's
/// totals into it as it writes).
pub(super) fn open_log(
    loaded: &LoadedMission,
    dir: &Path,
    named: NaiveDateTime,
    sink: &LateSink,
    buffer: usize,
) -> Result<OpenLog, SessionError> {
    let (target, _) = log_target(loaded, dir, named);
    let (at, file) = target
        .config
        .claim_session(&named)
        .map_err(|e| SessionError::LogOpen(e.to_string()))?;
    let folder = PathBuf::from(target.config.directory(&at));
    sink.attach(Box::new(BufWriter::with_capacity(buffer, file)), folder);
    Ok(OpenLog {
        path: target.config.alog_path(&at),
        tally: sink.tally(),
    })
}

/// The local wall-clock time, to the second (log names).
pub(super) fn wall_now() -> NaiveDateTime {
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
        Mode::RealTime { warp, port } => realtime(
            loaded,
            opts,
            (warp, port),
            pokes,
            until,
            &log_dir,
            crate::shared::Shared::new(),
            observer,
        ),
    }
}

pub(super) fn lockstep(
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
    let alog = open_log(loaded, log_dir, wall_now(), &sink, LOG_BUFFER)?;
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
    let watched = observer.watched();
    for v in &watched {
        s.tap(v);
    }
    let wall = Instant::now();
    let end = start + opts.max_time;
    // Steps of one second unless the observer asks for finer: it samples the DB at each.
    let step = observer.step_seconds();
    let step = if step.is_finite() && step > 0.0 {
        step
    } else {
        1.0
    };
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
            if watched.iter().any(|w| *w == *p.key) {
                observer.posting(&p.key, &p.value, t);
            }
            if &*p.key == "IVPHELM_SUMMARY"
                && let Some(v) = p.value.as_str()
            {
                observer.helm_summary(v);
            }
        }
        for (key, value) in observer.take_posts() {
            s.add_poke(Poke {
                key,
                value,
                at: PokeAt::Time(t - start),
            })?;
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
pub(super) struct Ending(
    pub(super) Ended,
    pub(super) f64,
    pub(super) f64,
    pub(super) Vec<(String, Option<Value>)>,
);

/// Closes the log (a write error fails the run) and reports the run, with the totals of its
/// alog (those reading it back would give, counted while it was written).
pub(super) fn close_and_report(
    loaded: &LoadedMission,
    opts: &RunOptions,
    sink: &LateSink,
    alog: OpenLog,
    end: Ending,
) -> Result<RunReport, SessionError> {
    close_log(sink, &alog)?;
    // What reading the closed alog back would give, counted while it was written.
    let totals = alog.tally.totals();
    let alog = alog.path;
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
