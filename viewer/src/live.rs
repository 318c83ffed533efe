//! The viewer on an in-process run (`coug run --view`): a [`LiveView`] serves the page from
//! its own threads, and a [`ViewObserver`] (a `runtime::session::Observer` around the run's
//! own observer) feeds it.
//!
//! - Lockstep: the session taps the viewed variables ([`Observer::watched`]) and hands each
//!   posting to [`Viewer::apply`]; applying only updates the scene under its mutex, and each
//!   page is sent the newest state when it is free, so a slow or stalled page drops frames
//!   and never slows the run (the log is the same with a page or without, whether it reads
//!   or not). As pMarineViewer and `coug view` do, the viewer asks for appcasts: every
//!   [`APPCAST_REQ_INTERVAL_S`] simulated seconds (from the first step on) it posts
//!   `APPCAST_REQ` (every node and app, 3 s, any threshold, key `coug_view`) as a poke at the
//!   next step, so the apps appcast all along the run and the appcast pane follows them as
//!   in real time. These requests, and the appcasts they bring, are in the run's alog:
//!   a lockstep log with `--view` differs from one without (it stays the same run to run,
//!   with or without pages, for one `--pace`). A button press is queued and posted at the
//!   next step, as a `--poke` is. With a pace (`--pace X`) the observer holds the run to X
//!   times real time.
//! - Real time: the viewer joins the run's MOOSDB as the client `coug_view`, as `coug view`
//!   does (appcast requests, presses posted as that client).

use std::net::SocketAddr;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use moos_types::Value;
use runtime::session::Observer;

use crate::server::{
    ConfigError, JoinConfig, Outbox, Viewer, ViewerConfig, appcast_request, feed, serve,
};

/// Simulated seconds between two `APPCAST_REQ` of the viewer in a lockstep run
/// (pMarineViewer asks every 2 s).
pub const APPCAST_REQ_INTERVAL_S: f64 = 2.0;

/// Where presses go during a run: queued for the lockstep session, or posted by the MOOS
/// client once a real-time run's DB is joined.
#[derive(Default)]
pub struct RunOutbox {
    client: Mutex<Option<Arc<moosdb::Client>>>,
    queue: Mutex<Vec<(String, Value)>>,
    now: Mutex<f64>,
}

impl RunOutbox {
    fn take(&self) -> Vec<(String, Value)> {
        std::mem::take(&mut *self.queue.lock().unwrap_or_else(|p| p.into_inner()))
    }
}

impl Outbox for RunOutbox {
    fn post(&self, var: &str, value: Value) -> Result<(), String> {
        let client = self
            .client
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .clone();
        match client {
            Some(c) => c.notify(var, value).map_err(|e| e.to_string()),
            None => {
                self.queue
                    .lock()
                    .unwrap_or_else(|p| p.into_inner())
                    .push((var.to_string(), value));
                Ok(())
            }
        }
    }

    fn moos_time(&self) -> f64 {
        let client = self
            .client
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .clone();
        match client {
            Some(c) => c.moos_time(),
            None => *self.now.lock().unwrap_or_else(|p| p.into_inner()),
        }
    }
}

/// A viewer serving from its own tokio runtime (two worker threads), beside a run.
pub struct LiveView {
    viewer: Arc<Viewer>,
    outbox: Arc<RunOutbox>,
    addr: SocketAddr,
    rt: tokio::runtime::Runtime,
}

impl std::fmt::Debug for LiveView {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("LiveView")
            .field("addr", &self.addr)
            .finish()
    }
}

/// Why a live view did not start.
#[derive(Debug)]
pub enum StartError {
    /// The configuration is refused.
    Config(ConfigError),
    /// The runtime or the listening socket failed.
    Io(std::io::Error),
}

impl std::fmt::Display for StartError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            StartError::Config(e) => e.fmt(f),
            StartError::Io(e) => write!(f, "cannot serve the viewer: {e}"),
        }
    }
}

impl std::error::Error for StartError {}

impl LiveView {
    /// Binds `config.bind` (port 0 picks one) and serves the page until dropped.
    pub fn start(config: &ViewerConfig) -> Result<LiveView, StartError> {
        config.check().map_err(StartError::Config)?;
        let rt = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .thread_name("coug-view")
            .enable_all()
            .build()
            .map_err(StartError::Io)?;
        let outbox = Arc::new(RunOutbox::default());
        let viewer = Viewer::new(config, outbox.clone()).map_err(StartError::Config)?;
        let listener = rt
            .block_on(tokio::net::TcpListener::bind(config.bind))
            .map_err(StartError::Io)?;
        let addr = listener.local_addr().map_err(StartError::Io)?;
        rt.spawn(serve(viewer.clone(), listener));
        Ok(LiveView {
            viewer,
            outbox,
            addr,
            rt,
        })
    }

    /// The address the page is served at.
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// The viewer (its scene).
    pub fn viewer(&self) -> &Arc<Viewer> {
        &self.viewer
    }

    /// Joins a real-time run's MOOSDB at `addr` as `coug_view` and feeds the viewer from it.
    pub fn join(&self, addr: SocketAddr, warp: f64) {
        let mut cfg = moosdb::ClientConfig::new("coug_view", &addr.ip().to_string(), addr.port());
        match moosdb::time::Warp::new(warp) {
            Ok(w) => cfg.warp = w,
            Err(e) => {
                tracing::warn!("viewer: warp {warp}: {e}");
                return;
            }
        }
        let viewer = self.viewer.clone();
        let outbox = self.outbox.clone();
        self.rt.spawn(async move {
            let (client, mail) = moosdb::Client::start(cfg);
            let client = Arc::new(client);
            if client.wait_connected().await.is_err() {
                tracing::warn!("viewer: cannot join the run's MOOSDB at {addr}");
                return;
            }
            *outbox.client.lock().unwrap_or_else(|p| p.into_inner()) = Some(client.clone());
            feed(viewer, client, mail, JoinConfig::default()).await;
        });
    }
}

/// The run's observer with the viewer fed beside it: every call also goes to `inner`.
pub struct ViewObserver<'a> {
    inner: &'a mut dyn Observer,
    live: &'a LiveView,
    pace: Option<f64>,
    start: f64,
    wall: Option<Instant>,
    /// A real-time run: the viewer's own MOOS client feeds and ticks the scene.
    joined: bool,
    /// Simulated seconds of the next lockstep appcast request.
    next_appcast_req: f64,
}

impl<'a> ViewObserver<'a> {
    /// Feeds `live` during a run whose lockstep MOOS start time is `start`; with `pace`, a
    /// lockstep run is held to `pace` times real time (none: as fast as it goes).
    pub fn new(
        inner: &'a mut dyn Observer,
        live: &'a LiveView,
        start: f64,
        pace: Option<f64>,
    ) -> Self {
        ViewObserver {
            inner,
            live,
            pace: pace.filter(|p| p.is_finite() && *p > 0.0),
            start,
            wall: None,
            joined: false,
            next_appcast_req: 0.0,
        }
    }
}

impl Observer for ViewObserver<'_> {
    fn warning(&mut self, text: &str) {
        self.inner.warning(text);
    }

    fn notice(&mut self, text: &str) {
        self.inner.notice(text);
    }

    fn helm_summary(&mut self, summary: &str) {
        self.inner.helm_summary(summary);
    }

    fn step(&mut self, sim_s: f64, current: &dyn Fn(&str) -> Option<Value>) {
        if !self.joined {
            let now = self.start + sim_s;
            *self
                .live
                .outbox
                .now
                .lock()
                .unwrap_or_else(|p| p.into_inner()) = now;
            self.live.viewer.tick(now);
            if sim_s >= self.next_appcast_req {
                // Queued now, posted at the next step (as a press).
                self.live
                    .outbox
                    .queue
                    .lock()
                    .unwrap_or_else(|p| p.into_inner())
                    .push((
                        appcast::casting::APPCAST_REQ_VAR.to_string(),
                        Value::text(appcast_request(&JoinConfig::default().appcast_key)),
                    ));
                while self.next_appcast_req <= sim_s {
                    self.next_appcast_req += APPCAST_REQ_INTERVAL_S;
                }
            }
        }
        if let Some(pace) = self.pace {
            let wall = *self.wall.get_or_insert_with(Instant::now);
            let due = Duration::from_secs_f64(sim_s / pace);
            let spent = wall.elapsed();
            if due > spent {
                std::thread::sleep(due - spent);
            }
        }
        self.inner.step(sim_s, current);
    }

    fn stop_requested(&self) -> bool {
        self.inner.stop_requested()
    }

    fn watched(&self) -> Vec<String> {
        let mut v: Vec<String> = self.inner.watched();
        for var in crate::scene::viewed_variables() {
            if !v.iter().any(|w| w == var) {
                v.push(var.to_string());
            }
        }
        v
    }

    fn posting(&mut self, key: &str, value: &Value, time: f64) {
        if let Some(s) = value.as_str() {
            self.live.viewer.apply(key, s, time);
        }
        self.inner.posting(key, value, time);
    }

    fn take_posts(&mut self) -> Vec<(String, Value)> {
        let mut v = self.inner.take_posts();
        v.extend(self.live.outbox.take());
        v
    }

    fn step_seconds(&self) -> f64 {
        // About ten frames per wall second when paced; one per simulated second otherwise.
        match self.pace {
            Some(p) => (p / 10.0).clamp(0.05, 1.0),
            None => self.inner.step_seconds(),
        }
    }

    fn db_listening(&mut self, addr: SocketAddr, warp: f64) {
        self.joined = true;
        self.live.join(addr, warp);
        self.inner.db_listening(addr, warp);
    }
}
