//! Real-time runs: every app as its own MOOS client of a TCP MOOSDB (so real external MOOS
//! apps can join the same DB), paced by the wall clock times the warp, with pokes and an
//! `until` condition handled by a `uPokeDB` client of the run.
//!
//! This mirrors a pAntler launch (one process per app) inside one process: the semantics
//! are MOOS's own, over the network code of `moosdb`. Lockstep runs use the
//! [`crate::Scheduler`] instead.

use std::collections::HashMap;
use std::time::Duration;

use mission::condition::{self, Condition};
use moosdb::time::Warp;
use moosdb::{Client, ClientConfig, DataType};
use tokio::sync::watch;

use crate::app::{App, Value};
use crate::remote::{RemoteConfig, RemoteError, run};
use crate::scheduler::{Outcome, Poke, PokeAt};

/// What a real-time run does besides running its apps.
#[derive(Debug, Clone, Default)]
pub struct RunSpec {
    /// Values to post (by a client called `uPokeDB`).
    pub pokes: Vec<Poke>,
    /// The run ends when this holds (checked on every change of its variables), once
    /// every after-first-iterate poke has gone out.
    pub until: Option<Condition>,
    /// The run ends at this many MOOS seconds after the start.
    pub max_time: f64,
}

/// The MOOSDB of a community in a real-time run, as bound: its port (the system's pick
/// when the mission says 0 or `--port 0`) and the run's time warp (`--warp` or the
/// mission's). The run puts it in its launch's [`crate::shared::Shared`] set under
/// [`RunningDb::key`] before the apps are built, so an app that reports where its community
/// is (the uField brokers' host record) tells the truth. Lockstep runs have none.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunningDb {
    /// The TCP port the MOOSDB listens on.
    pub port: u16,
    /// The run's `MOOSTimeWarp`.
    pub warp: f64,
}

impl RunningDb {
    /// Its name in the shared set: one per community (a real-time fleet's communities
    /// share one set).
    pub fn key(community: &str) -> String {
        format!("moosdb:{community}")
    }
}

/// How a real-time run ended, with the last values of the `until` variables.
#[derive(Debug, Clone, PartialEq)]
pub struct RunEnd {
    /// Why it ended.
    pub outcome: Outcome,
    /// The `until` condition's variables and their last values.
    pub values: Vec<(String, Option<Value>)>,
}

fn to_value(m: &moosdb::Message) -> Option<Value> {
    match m.data_type {
        DataType::Double => Some(Value::Double(m.dval)),
        DataType::String => Some(Value::String(m.sval_str().into_owned().into())),
        _ => None,
    }
}

fn holds(cond: &Condition, vals: &HashMap<String, Value>) -> bool {
    let lookup = |n: &str| -> Option<condition::Value<'_>> {
        match vals.get(n)? {
            Value::Double(x) => Some(condition::Value::Double(*x)),
            Value::String(s) => Some(condition::Value::String(s)),
            Value::Binary(_) => None,
        }
    };
    cond.evaluate(&lookup)
}

async fn joined(t: tokio::task::JoinHandle<Result<(), RemoteError>>) -> Result<(), RemoteError> {
    match t.await {
        Ok(r) => r,
        Err(_) => Err(RemoteError::Client(moosdb::ClientError::Closed)),
    }
}

/// Runs `apps` (each as its own client of the DB at `config`) until the spec's condition
/// holds, `max_time` passes, or every app finishes. Must be called inside a tokio
/// [`tokio::task::LocalSet`] (apps need not be `Send`). A refused app name ends the run
/// with the error.
pub async fn run_apps(
    apps: Vec<Box<dyn App>>,
    config: &RemoteConfig,
    spec: RunSpec,
) -> Result<RunEnd, RemoteError> {
    let warp = Warp::new(config.warp).map_err(|_| RemoteError::Warp(config.warp))?;
    let mut cc = ClientConfig::new("uPokeDB", &config.host, config.port);
    cc.warp = warp;
    let (poker, mut inbox) = Client::start(cc);
    poker.wait_connected().await?;
    let start = poker.moos_time();
    let mut waiting: Vec<(String, Poke)> = Vec::new();
    let mut timed: Vec<(f64, Poke)> = Vec::new();
    for p in spec.pokes {
        match &p.at {
            PokeAt::Time(t) => timed.push((start + t, p)),
            PokeAt::AfterFirstIterate(app) => {
                let status = format!("{}_STATUS", app.to_ascii_uppercase());
                poker.register(&status, 0.0);
                waiting.push((status, p));
            }
        }
    }
    timed.sort_by(|a, b| a.0.total_cmp(&b.0));
    let names: Vec<String> = apps
        .iter()
        .map(|a| format!("{}_STATUS", a.name().to_ascii_uppercase()))
        .collect();
    // Pokes for apps that do not run go out now.
    let (orphans, kept): (Vec<_>, Vec<_>) =
        waiting.into_iter().partition(|(s, _)| !names.contains(s));
    waiting = kept;
    for (_, p) in orphans {
        poker.notify(&p.key, p.value.clone())?;
    }
    let vars: Vec<String> = spec
        .until
        .as_ref()
        .map(|c| c.variables().into_iter().map(String::from).collect())
        .unwrap_or_default();
    for v in &vars {
        poker.register(v, 0.0);
    }
    let slowest_period = apps.iter().map(|a| 1.0 / a.app_tick()).fold(0.0, f64::max);
    let (stop_tx, stop_rx) = watch::channel(false);
    let mut tasks = Vec::new();
    for mut app in apps {
        let cfg = config.clone();
        let mut rx = stop_rx.clone();
        tasks.push(tokio::task::spawn_local(async move {
            let stop = async move {
                let _ = rx.wait_for(|s| *s).await;
            };
            run(&mut *app, &cfg, stop).await
        }));
    }
    let mut vals: HashMap<String, Value> = HashMap::new();
    let end = start + spec.max_time;
    let mut tick = tokio::time::interval(Duration::from_millis(20));
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let outcome = loop {
        tokio::select! {
            m = inbox.recv() => {
                let Some(m) = m else { break Outcome::AllFinished { time: poker.moos_time() } };
                let key = m.key_str().into_owned();
                if let Some(i) = waiting.iter().position(|(s, _)| *s == key) {
                    let (_, p) = waiting.remove(i);
                    poker.notify(&p.key, p.value.clone())?;
                }
                if vars.contains(&key) && let Some(v) = to_value(&m) {
                    vals.insert(key, v);
                }
            }
            _ = tick.tick() => {}
        }
        let now = poker.moos_time();
        while timed.first().is_some_and(|(t, _)| *t <= now) {
            let (_, p) = timed.remove(0);
            poker.notify(&p.key, p.value.clone())?;
        }
        if waiting.is_empty()
            && let Some(c) = &spec.until
            && holds(c, &vals)
        {
            break Outcome::ConditionMet { time: now };
        }
        if now >= end {
            break Outcome::MaxTime { time: now };
        }
        if let Some(i) = tasks.iter().position(|t| t.is_finished()) {
            if let Err(e) = joined(tasks.remove(i)).await {
                let _ = stop_tx.send(true);
                for t in tasks {
                    let _ = joined(t).await;
                }
                return Err(e);
            }
            if tasks.is_empty() {
                break Outcome::AllFinished { time: now };
            }
        }
    };
    // Let the apps (pLogger above all) take in the posts of the last moment, as MOOS apps
    // still running after a mission ends would, before they are stopped: one period of
    // the slowest app, in warped time, at most one wall second.
    if !tasks.is_empty() {
        let wall = (slowest_period / config.warp).min(1.0);
        tokio::time::sleep(Duration::from_secs_f64(wall)).await;
    }
    let _ = stop_tx.send(true);
    for t in tasks {
        joined(t).await?;
    }
    poker.close().await;
    let mut seen = Vec::new();
    let values = vars
        .into_iter()
        .filter(|v| {
            let fresh = !seen.contains(v);
            seen.push(v.clone());
            fresh
        })
        .map(|v| {
            let val = vals.get(&v).cloned();
            (v, val)
        })
        .collect();
    Ok(RunEnd { outcome, values })
}
