//! One [`App`] as a real MOOS process: connected to a MOOSDB over TCP (the single-app
//! "swap-in" mode, where pAntler starts coug in place of a C++ app), paced by the wall
//! clock at its AppTick (warped, as `MOOSPause` is), with CMOOSApp's life cycle:
//! connect, register, OnStartUp, then per tick: mail sorted by time, `<APP>_STATUS`
//! every 2 s, Iterate, posts.
//!
//! Also the MOOS command-line conventions of such an app ([`AppArgs`]).

use std::collections::BTreeSet;
use std::future::Future;
use std::time::Duration;

use moosdb::time::Warp;
use moosdb::{Client, ClientConfig, ClientError, Message, MsgType};
use thiserror::Error;

use crate::app::{App, Mail, Post, STATUS_PERIOD, status_text};

/// Why a remote app stopped with an error.
#[derive(Debug, Error)]
pub enum RemoteError {
    /// The DB refused the app (its name is taken) or the client closed.
    #[error("{0}")]
    Client(#[from] ClientError),
    /// `MOOSTimeWarp` outside MOOS's range.
    #[error("time warp {0} is outside (0, 400]")]
    Warp(f64),
    /// The app failed (a log it could not write): the run ends.
    #[error(transparent)]
    App(#[from] crate::app::AppError),
}

/// Where a remote app connects.
#[derive(Debug, Clone, PartialEq)]
pub struct RemoteConfig {
    /// `ServerHost`.
    pub host: String,
    /// `ServerPort`.
    pub port: u16,
    /// `MOOSTimeWarp`.
    pub warp: f64,
}

/// MOOS command-line conventions of an app: `APP MISSION.moos [ALIAS]` (as pAntler
/// launches it) or `--alias=NAME`, and `--moos_name=NAME`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AppArgs {
    /// The mission file (the first argument ending in `.moos` or `.moos++`).
    pub mission: Option<String>,
    /// The MOOS name to run under, if given.
    pub alias: Option<String>,
}

impl AppArgs {
    /// Reads the arguments after the program name.
    ///
    /// ```
    /// use runtime::remote::AppArgs;
    /// let a = AppArgs::parse(["alpha.moos", "pHelmIvP_2"]);
    /// assert_eq!((a.mission.as_deref(), a.alias.as_deref()), (Some("alpha.moos"), Some("pHelmIvP_2")));
    /// let b = AppArgs::parse(["--alias=sim2", "m.moos"]);
    /// assert_eq!(b.alias.as_deref(), Some("sim2"));
    /// ```
    pub fn parse<I, S>(args: I) -> AppArgs
    where
        I: IntoIterator<Item = S>,
        S: AsRef<str>,
    {
        let mut out = AppArgs {
            mission: None,
            alias: None,
        };
        let mut positional_alias = None;
        for a in args {
            let a = a.as_ref();
            if let Some(v) = a
                .strip_prefix("--alias=")
                .or_else(|| a.strip_prefix("--moos_name="))
            {
                out.alias = Some(v.to_string());
            } else if a.starts_with('-') {
                continue;
            } else if out.mission.is_none() && (a.ends_with(".moos") || a.ends_with(".moos++")) {
                out.mission = Some(a.to_string());
            } else if out.mission.is_some() && positional_alias.is_none() {
                positional_alias = Some(a.to_string());
            }
        }
        if out.alias.is_none() {
            out.alias = positional_alias;
        }
        out
    }
}

fn send(client: &Client, posts: &mut Vec<Post>, published: &mut BTreeSet<String>) {
    for p in posts.drain(..) {
        let value = p.value;
        // A post while reconnecting is lost, as CMOOSApp's Notify fails while offline.
        let sent = match p.relayed {
            Some(r) => {
                let mut m = Message::notify(&p.key, value, r.time);
                m.src = p.source.as_bytes().clone();
                m.src_aux = p.aux.as_bytes().clone();
                m.community = r.community.as_bytes().clone();
                client.relay(m)
            }
            None => client.notify_with(&p.key, value, None, &p.aux),
        };
        if sent.is_ok() && !published.contains(&*p.key) {
            published.insert(p.key.to_string());
        }
    }
}

/// Runs `app` against the MOOSDB at `config` until `stop` completes or the app finishes.
/// Returns an error if the DB refuses the app's name.
pub async fn run<A: App + ?Sized>(
    app: &mut A,
    config: &RemoteConfig,
    stop: impl Future<Output = ()>,
) -> Result<(), RemoteError> {
    let warp = Warp::new(config.warp).map_err(|_| RemoteError::Warp(config.warp))?;
    let mut cc = ClientConfig::new(app.name(), &config.host, config.port);
    cc.warp = warp;
    let (client, mut inbox) = Client::start(cc);
    tokio::pin!(stop);
    tokio::select! {
        r = client.wait_connected() => r?,
        _ = &mut stop => {
            client.close().await;
            return Ok(());
        }
    }
    let mut subscribed = BTreeSet::new();
    for s in app.subscriptions() {
        if s.is_wildcard() {
            client.register_pattern(&s.pattern, "*", s.interval);
        } else {
            client.register(&s.pattern, s.interval);
        }
        subscribed.insert(s.pattern);
    }
    let started = client.moos_time();
    app.set_process_id(std::process::id());
    let mut procinfo = crate::procinfo::ProcInfo::new();
    let mut load = procinfo.sample();
    app.set_process_load(load);
    let mut posts = Vec::new();
    let mut published = BTreeSet::new();
    app.on_startup(started, &mut posts)?;
    send(&client, &mut posts, &mut published);
    let period = warp.pause(Duration::from_secs_f64(1.0 / app.app_tick()));
    let mut tick = tokio::time::interval(period);
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let status_var = format!("{}_STATUS", app.name().to_ascii_uppercase());
    let mut last_status: Option<f64> = None;
    let mut mail = Vec::new();
    loop {
        let stopping = tokio::select! {
            _ = tick.tick() => false,
            _ = &mut stop => true,
        };
        let now = client.moos_time();
        mail.clear();
        while let Some(m) = inbox.try_recv() {
            if m.msg_type == MsgType::Notify
                && let Some(x) = Message::mail(&m)
            {
                mail.push(x);
            }
        }
        mail.sort_by(|a: &Mail, b: &Mail| a.time.total_cmp(&b.time));
        if !mail.is_empty()
            && let Err(e) = app.on_mail(&mail, now, &mut posts)
        {
            client.close().await;
            return Err(e.into());
        }
        // Asked to stop: the mail already received is handled (a logger logs it), nothing
        // more is posted.
        if stopping {
            break;
        }
        // `<APP>_STATUS` goes out before the iteration's postings, as CMOOSApp posts it,
        // except the first: a run's pokes "after the first iterate" wait for it, so it must
        // reach the DB after what the first iteration posted (the helm's `initialize`
        // values: a `DEPLOY = true` poke that overtook the helm's `DEPLOY = false` left the
        // vehicle parked).
        let first = last_status.is_none();
        let mut status = None;
        if last_status.is_none_or(|t| now - t >= STATUS_PERIOD) {
            last_status = Some(now);
            load = procinfo.sample();
            app.set_process_load(load);
            status = Some(Post::text(
                status_var.clone(),
                status_text(
                    app.name(),
                    now - started,
                    Some(load),
                    &published,
                    &subscribed,
                ),
            ));
        }
        if !first {
            posts.extend(status.take());
        }
        if let Err(e) = app.iterate(now, &mut posts) {
            client.close().await;
            return Err(e.into());
        }
        posts.extend(status);
        for s in app.new_subscriptions() {
            if s.is_wildcard() {
                client.register_pattern(&s.pattern, "*", s.interval);
            } else {
                client.register(&s.pattern, s.interval);
            }
            subscribed.insert(s.pattern);
        }
        send(&client, &mut posts, &mut published);
        if app.finished() {
            break;
        }
    }
    // The run is over: the app flushes and closes what it writes.
    let stopped = app.stop(client.moos_time());
    client.close().await;
    Ok(stopped?)
}
