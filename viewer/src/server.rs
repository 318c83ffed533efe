//! The viewer's edge: the axum router (the embedded page, the `/ws` websocket, button
//! presses), who may use it, and the MOOS client that feeds the scene.
//!
//! Access: the server binds 127.0.0.1 unless told otherwise; [`ViewerConfig::check`] refuses
//! a non-loopback bind without a token. With a token, every request (the page, its script,
//! the websocket) must carry `?token=<token>` or is answered 401. A websocket upgrade whose
//! `Origin` names another host than the request's `Host` is refused (403), so a web page from
//! elsewhere cannot drive a viewer on the user's machine.
//!
//! The websocket: the server sends a snapshot on connect, then deltas ([`crate::scene`]). The
//! feed ([`Viewer::apply`]) only updates the scene and bumps a `watch` version, never waiting
//! for a client; each client's task sends, when it is free again, what changed since the
//! version it last sent, so a slow client gets the newest state and skips intermediate
//! frames, and frames to one client are at least [`ViewerConfig::min_frame_interval`] apart.
//! The page sends `{"press":"DEPLOY"}` (optionally `"vname":"abe"` for a `_$[VNAME]`
//! variable): only a button of the mission's pMarineViewer block is pressed, and its
//! configured postings are all it posts; the answer is `{"type":"pressed",...}` or
//! `{"type":"refused","error":...}`.

use std::collections::HashMap;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use axum::Router;
use axum::extract::ws::{Message as WsMessage, WebSocket, WebSocketUpgrade};
use axum::extract::{Query, State};
use axum::http::{HeaderMap, StatusCode, header};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use futures_util::{SinkExt, StreamExt};
use mission::buttons::{Button, ButtonValue};
use moos_types::Value;
use serde_json::json;
use tokio::sync::watch;

use crate::scene::{Scene, SceneConfig, viewed_variables};

const INDEX_HTML: &str = include_str!("../assets/index.html");
const VIEWER_JS: &str = include_str!("../assets/viewer.js");

/// How a viewer serves.
#[derive(Debug, Clone)]
pub struct ViewerConfig {
    /// Address of the HTTP server (default 127.0.0.1:9080).
    pub bind: SocketAddr,
    /// The token the page must present (`?token=`); required for a non-loopback bind.
    pub token: Option<String>,
    /// The scene's limits.
    pub scene: SceneConfig,
    /// The mission's pMarineViewer buttons: all the page can press.
    pub buttons: Vec<Button>,
    /// The mission's pMarineViewer mouse context pokes: all a click can post.
    pub contexts: Vec<crate::context::ContextPoke>,
    /// Least time between two frames to one client.
    pub min_frame_interval: Duration,
    /// The mission's `LatOrigin`/`LongOrigin` (degrees): the local grid of `$(LAT)`/`$(LON)`
    /// and of the background image.
    pub origin: Option<(f64, f64)>,
    /// The map's background image (pMarineViewer's `tiff_file`), served as
    /// `/background.png`.
    pub background: Option<Arc<crate::background::Background>>,
}

impl Default for ViewerConfig {
    fn default() -> Self {
        ViewerConfig {
            bind: SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), 9080),
            token: None,
            scene: SceneConfig::default(),
            buttons: Vec::new(),
            contexts: Vec::new(),
            min_frame_interval: Duration::from_millis(50),
            origin: None,
            background: None,
        }
    }
}

/// The mission's `LatOrigin`/`LongOrigin` when both are numbers.
pub fn mission_origin(m: &mission::moos::MissionFile) -> Option<(f64, f64)> {
    let num = |k: &str| {
        m.global(k)
            .and_then(|v| v.trim().parse::<f64>().ok())
            .filter(|v| v.is_finite())
    };
    Some((num("LatOrigin")?, num("LongOrigin")?))
}

/// A configuration the viewer refuses.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ConfigError {
    /// Binding an address other machines can reach needs a token.
    NonLoopbackWithoutToken(SocketAddr),
    /// An empty token protects nothing.
    EmptyToken,
}

impl std::fmt::Display for ConfigError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ConfigError::NonLoopbackWithoutToken(a) => write!(
                f,
                "binding {a} (not loopback) needs a token (--token) the page must present"
            ),
            ConfigError::EmptyToken => write!(f, "the token is empty"),
        }
    }
}

impl std::error::Error for ConfigError {}

impl ViewerConfig {
    /// The default configuration with what the mission gives: its pMarineViewer buttons and
    /// context pokes, and its origin.
    pub fn for_mission(m: &mission::moos::MissionFile) -> ViewerConfig {
        ViewerConfig {
            buttons: mission::buttons::buttons(m),
            contexts: crate::context::context_pokes(m),
            origin: mission_origin(m),
            ..ViewerConfig::default()
        }
    }

    /// [`ViewerConfig::for_mission`] plus the background image its pMarineViewer block
    /// names (`tiff_file`), looked for beside the mission file `path` first; a background
    /// that cannot be shown is left out and its reason returned, for a warning.
    pub fn for_mission_file(
        m: &mission::moos::MissionFile,
        path: &std::path::Path,
    ) -> (ViewerConfig, Option<String>) {
        let mut config = ViewerConfig::for_mission(m);
        let dir = path.parent().filter(|d| !d.as_os_str().is_empty());
        let warning = match crate::background::Background::for_mission(m, dir) {
            Some(Ok(b)) => {
                config.background = Some(Arc::new(b));
                None
            }
            Some(Err(e)) => Some(format!("{}: {e}; no background image", path.display())),
            None => None,
        };
        (config, warning)
    }

    /// Refuses a non-loopback bind without a token, and an empty token.
    pub fn check(&self) -> Result<(), ConfigError> {
        match &self.token {
            Some(t) if t.is_empty() => Err(ConfigError::EmptyToken),
            None if !self.bind.ip().is_loopback() => {
                Err(ConfigError::NonLoopbackWithoutToken(self.bind))
            }
            _ => Ok(()),
        }
    }
}

/// Where button presses are posted: the MOOS client in `coug view`.
pub trait Outbox: Send + Sync + 'static {
    /// Posts `var = value`.
    fn post(&self, var: &str, value: Value) -> Result<(), String>;
    /// MOOS time now (for `$[UTC]`).
    fn moos_time(&self) -> f64;
}

impl Outbox for moosdb::Client {
    fn post(&self, var: &str, value: Value) -> Result<(), String> {
        self.notify(var, value).map_err(|e| e.to_string())
    }
    fn moos_time(&self) -> f64 {
        moosdb::Client::moos_time(self)
    }
}

/// Why a press was refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PressError {
    /// No configured button has this label or key.
    UnknownButton(String),
    /// A `_$[VNAME]` variable and no vehicle named in the press.
    NoVehicle(String),
    /// The post failed (the MOOS client is gone or its outbox full).
    Post(String),
    /// A context poke uses `$(LAT)`/`$(LON)` and the mission has no (valid) origin.
    NoOrigin,
}

impl std::fmt::Display for PressError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PressError::UnknownButton(b) => write!(f, "no button {b:?} in the mission"),
            PressError::NoVehicle(v) => write!(f, "{v} needs a vehicle (\"vname\")"),
            PressError::Post(e) => write!(f, "post failed: {e}"),
            PressError::NoOrigin => {
                write!(f, "$(LAT)/$(LON) need the mission's LatOrigin/LongOrigin")
            }
        }
    }
}

/// The viewer's shared state: the scene, its version, the buttons and where presses go.
pub struct Viewer {
    scene: Mutex<Scene>,
    scene_config: SceneConfig,
    /// Bumped when the scene is rebuilt (a replay's seek): pages then get a new snapshot.
    epoch: AtomicU64,
    /// A replay's state (`{"t":..,"start":..,"end":..,"playing":..,"speed":..}`), sent with
    /// every frame.
    status: Mutex<Option<serde_json::Value>>,
    /// Where a replay's controls go (`coug view LOG.alog`).
    replay: std::sync::OnceLock<tokio::sync::mpsc::UnboundedSender<ReplayControl>>,
    version: watch::Sender<u64>,
    buttons: Vec<Button>,
    contexts: Vec<crate::context::ContextPoke>,
    /// Clicks per side (`$(IX)`), left then right.
    clicks: [AtomicU64; 2],
    token: Option<String>,
    outbox: Arc<dyn Outbox>,
    presses: AtomicU64,
    /// Pages connected now.
    pages: AtomicU64,
    min_frame_interval: Duration,
    /// The mission's local grid, when it has an origin.
    grid: Option<vehicle::geodesy::LocalGrid>,
    background: Option<Arc<crate::background::Background>>,
}

impl std::fmt::Debug for Viewer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Viewer")
            .field("buttons", &self.buttons.len())
            .field("token", &self.token.is_some())
            .finish()
    }
}

fn lock(m: &Mutex<Scene>) -> MutexGuard<'_, Scene> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

impl Viewer {
    /// A viewer posting presses to `outbox`; fails on a configuration [`ViewerConfig::check`]
    /// refuses.
    pub fn new(config: &ViewerConfig, outbox: Arc<dyn Outbox>) -> Result<Arc<Viewer>, ConfigError> {
        config.check()?;
        Ok(Arc::new(Viewer {
            scene: Mutex::new(Scene::new(config.scene.clone(), config.buttons.clone())),
            scene_config: config.scene.clone(),
            epoch: AtomicU64::new(0),
            status: Mutex::new(None),
            replay: std::sync::OnceLock::new(),
            version: watch::Sender::new(0),
            buttons: config.buttons.clone(),
            contexts: config.contexts.clone(),
            clicks: [AtomicU64::new(0), AtomicU64::new(0)],
            token: config.token.clone(),
            outbox,
            presses: AtomicU64::new(0),
            pages: AtomicU64::new(0),
            min_frame_interval: config.min_frame_interval,
            grid: config
                .origin
                .and_then(|(lat, lon)| vehicle::geodesy::LocalGrid::new(lat, lon).ok()),
            background: config.background.clone(),
        }))
    }

    /// How many pages are connected: each page's task counts itself from its upgrade to its
    /// end (the page closed, its connection broke, or a send failed).
    pub fn pages(&self) -> u64 {
        self.pages.load(Ordering::SeqCst)
    }

    /// Runs `f` on the scene (read it; changes made here are not announced to clients).
    pub fn with_scene<R>(&self, f: impl FnOnce(&Scene) -> R) -> R {
        f(&lock(&self.scene))
    }

    /// Takes one piece of mail into the scene and wakes the clients; never waits for them.
    /// Mail the scene does not take is dropped (logged at debug level).
    pub fn apply(&self, var: &str, value: &str, now: f64) {
        let version = {
            let mut s = lock(&self.scene);
            if let Err(e) = s.apply(var, value, now) {
                tracing::debug!(var, ?e, "mail not shown");
            }
            s.version()
        };
        self.announce(version);
    }

    /// Advances the scene's time (stale vehicles, expired objects) and wakes the clients.
    pub fn tick(&self, now: f64) {
        let version = {
            let mut s = lock(&self.scene);
            s.tick(now);
            s.version()
        };
        self.announce(version);
    }

    /// Changes the scene with `f` and wakes the pages (a replay's playhead moving).
    pub fn update(&self, f: impl FnOnce(&mut Scene)) {
        let version = {
            let mut s = lock(&self.scene);
            f(&mut s);
            s.version()
        };
        self.announce(version);
    }

    /// Replaces the scene by an empty one that `fill` builds up (a replay's seek), and
    /// sends every page a new snapshot.
    pub fn rebuild(&self, fill: impl FnOnce(&mut Scene)) {
        {
            let mut s = lock(&self.scene);
            let mut fresh = Scene::new(self.scene_config.clone(), self.buttons.clone());
            fill(&mut fresh);
            *s = fresh;
            self.epoch.fetch_add(1, Ordering::SeqCst);
        }
        self.version.send_modify(|v| *v = v.wrapping_add(1));
    }

    /// Sets the replay state sent with every frame, and wakes the pages.
    pub fn set_status(&self, status: serde_json::Value) {
        *self.status.lock().unwrap_or_else(|p| p.into_inner()) = Some(status);
        self.version.send_modify(|v| *v = v.wrapping_add(1));
    }

    /// The replay state, if this viewer replays a log.
    pub fn status(&self) -> Option<serde_json::Value> {
        self.status
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .clone()
    }

    /// Sends the page's replay controls to `tx` (set once, by the replay driver).
    pub fn set_replay_control(&self, tx: tokio::sync::mpsc::UnboundedSender<ReplayControl>) {
        let _ = self.replay.set(tx);
    }

    fn announce(&self, version: u64) {
        self.version.send_if_modified(|v| {
            let changed = *v != version;
            *v = version;
            changed
        });
    }

    /// Presses the configured button `name` (label or key): posts its postings, in order,
    /// and returns them. Nothing is posted for a name that is not a configured button.
    pub fn press(
        &self,
        name: &str,
        vname: Option<&str>,
    ) -> Result<Vec<(String, Value)>, PressError> {
        let button = mission::buttons::find(&self.buttons, name)
            .ok_or_else(|| PressError::UnknownButton(name.to_string()))?;
        let bix = self.presses.load(Ordering::Relaxed);
        let mut posts = Vec::with_capacity(button.postings.len());
        for (var, value) in &button.postings {
            let var = if var.contains("$[VNAME]") {
                let v = vname
                    .filter(|v| !v.is_empty())
                    .ok_or_else(|| PressError::NoVehicle(var.clone()))?;
                var.replace("$[VNAME]", &v.to_ascii_uppercase())
            } else {
                var.clone()
            };
            let value = match value {
                ButtonValue::Double(d) => Value::Double(*d),
                ButtonValue::Text(t) => Value::text(t.as_str()),
                ButtonValue::Utc => Value::Double(self.outbox.moos_time()),
                ButtonValue::PressCount => Value::Double(bix as f64),
            };
            posts.push((var, value));
        }
        // Only a press that posts counts for `$[BIX]`.
        self.presses.fetch_add(1, Ordering::Relaxed);
        for (var, value) in &posts {
            self.outbox
                .post(var, value.clone())
                .map_err(PressError::Post)?;
        }
        Ok(posts)
    }

    /// A click's context pokes: posts every configured poke of `side` with menu key `key`
    /// (and the side's `any_*` pokes), macros expanded for the click at (`x`, `y`) with
    /// `vname` the active vehicle. Nothing is posted when no configured poke has that key.
    pub fn click(
        &self,
        side: crate::context::Side,
        key: &str,
        x: f64,
        y: f64,
        vname: &str,
    ) -> Result<Vec<(String, Value)>, PressError> {
        if !self.contexts.iter().any(|c| c.side == side && c.key == key) {
            return Err(PressError::UnknownButton(format!(
                "{}_context[{key}]",
                side.as_str()
            )));
        }
        let (x, y) = ((x * 10.0).round() / 10.0, (y * 10.0).round() / 10.0);
        let (vpos, closest) = self.with_scene(|s| {
            let vpos = s
                .vehicles()
                .get(vname)
                .and_then(|v| Some((v.report.x_m?, v.report.y_m?)));
            let closest = s
                .vehicles()
                .iter()
                .filter_map(|(n, v)| {
                    let d = (v.report.x_m? - x).hypot(v.report.y_m? - y);
                    Some((d, n))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, n)| n.clone())
                .unwrap_or_default();
            (vpos, closest)
        });
        let lat_lon = self.grid.as_ref().and_then(|g| g.to_latlon(x, y).ok());
        if lat_lon.is_none()
            && self
                .contexts
                .iter()
                .any(|c| c.matches(side, key) && c.needs_lat_lon())
        {
            return Err(PressError::NoOrigin);
        }
        let i = match side {
            crate::context::Side::Left => 0,
            crate::context::Side::Right => 1,
        };
        // pMarineViewer snaps a click to 0.1 m (above).
        let click = crate::context::Click {
            x,
            y,
            vname: vname.to_string(),
            vpos,
            ix: self.clicks[i].fetch_add(1, Ordering::Relaxed),
            bix: self.presses.fetch_add(1, Ordering::Relaxed),
            utc: self.outbox.moos_time(),
            lat_lon,
            closest,
        };
        let posts: Vec<(String, Value)> = self
            .contexts
            .iter()
            .filter(|c| c.matches(side, key))
            .map(|c| c.expand(&click))
            .collect();
        for (var, value) in &posts {
            self.outbox
                .post(var, value.clone())
                .map_err(PressError::Post)?;
        }
        Ok(posts)
    }

    /// The context pokes as the page shows them.
    fn contexts_json(&self) -> serde_json::Value {
        serde_json::Value::Array(self.contexts.iter().map(|c| c.to_json()).collect())
    }

    /// Checks the token (when one is set) and, for a websocket, the origin.
    fn authorize(
        &self,
        query: &HashMap<String, String>,
        headers: &HeaderMap,
        ws: bool,
    ) -> Result<(), (StatusCode, &'static str)> {
        if let Some(token) = &self.token {
            let given = query.get("token").map(String::as_str).unwrap_or("");
            if !same(given.as_bytes(), token.as_bytes()) {
                return Err((StatusCode::UNAUTHORIZED, "token required\n"));
            }
        }
        if ws && let Some(origin) = headers.get(header::ORIGIN) {
            let host = headers.get(header::HOST).and_then(|h| h.to_str().ok());
            let origin_host = origin
                .to_str()
                .ok()
                .and_then(|o| o.split_once("://"))
                .map(|(_, rest)| rest.trim_end_matches('/'));
            if origin_host.is_none() || origin_host != host {
                return Err((StatusCode::FORBIDDEN, "cross-origin websocket refused\n"));
            }
        }
        Ok(())
    }

    /// The background's placement as the page gets it in every snapshot, `null` if none.
    fn background_json(&self) -> serde_json::Value {
        self.background
            .as_ref()
            .map_or(serde_json::Value::Null, |b| b.to_json())
    }

    /// The router: `/` (the page), `/viewer.js`, `/background.png`, `/ws`.
    pub fn router(self: &Arc<Self>) -> Router {
        Router::new()
            .route("/", get(page))
            .route("/index.html", get(page))
            .route("/viewer.js", get(script))
            .route("/background.png", get(background))
            .route("/ws", get(ws_upgrade))
            .with_state(self.clone())
    }

    fn handle_text(&self, text: &str) -> serde_json::Value {
        let Ok(msg) = serde_json::from_str::<serde_json::Value>(text) else {
            return json!({"type": "refused", "error": "not JSON"});
        };
        if let Some(cmd) = msg.get("replay").and_then(|p| p.as_str()) {
            let Some(tx) = self.replay.get() else {
                return json!({"type": "refused", "error": "not a replay"});
            };
            let num = |k: &str| {
                msg.get(k)
                    .and_then(|x| x.as_f64())
                    .filter(|x| x.is_finite())
            };
            let control = match (cmd, num("t"), num("speed")) {
                ("play", _, _) => ReplayControl::Play,
                ("pause", _, _) => ReplayControl::Pause,
                ("seek", Some(t), _) => ReplayControl::Seek(t),
                ("speed", _, Some(x)) if x > 0.0 => ReplayControl::Speed(x),
                _ => return json!({"type": "refused", "error": "bad replay control"}),
            };
            let _ = tx.send(control);
            return json!({"type": "replay_ok", "replay": cmd});
        }
        if let Some(key) = msg.get("context").and_then(|p| p.as_str()) {
            let side = match msg.get("side").and_then(|p| p.as_str()) {
                Some("left") => crate::context::Side::Left,
                _ => crate::context::Side::Right,
            };
            let num = |k: &str| {
                msg.get(k)
                    .and_then(|x| x.as_f64())
                    .filter(|x| x.is_finite())
            };
            let (Some(x), Some(y)) = (num("x"), num("y")) else {
                return json!({"type": "refused", "context": key, "error": "no x, y"});
            };
            let vname = msg.get("vname").and_then(|v| v.as_str()).unwrap_or("");
            return match self.click(side, key, x, y, vname) {
                Ok(posts) => json!({
                    "type": "pressed",
                    "context": key,
                    "posted": posts.iter().map(|(k, v)| json!([k, v.to_string()])).collect::<Vec<_>>(),
                }),
                Err(e) => {
                    tracing::warn!(context = key, "click refused: {e}");
                    json!({"type": "refused", "context": key, "error": e.to_string()})
                }
            };
        }
        let Some(name) = msg.get("press").and_then(|p| p.as_str()) else {
            return json!({"type": "refused", "error": "unknown request"});
        };
        let vname = msg.get("vname").and_then(|v| v.as_str());
        match self.press(name, vname) {
            Ok(posts) => json!({
                "type": "pressed",
                "button": name,
                "posted": posts.iter().map(|(k, v)| json!([k, v.to_string()])).collect::<Vec<_>>(),
            }),
            Err(e) => {
                tracing::warn!(button = name, "press refused: {e}");
                json!({"type": "refused", "button": name, "error": e.to_string()})
            }
        }
    }
}

/// Compares without stopping at the first difference.
fn same(a: &[u8], b: &[u8]) -> bool {
    a.len() == b.len() && a.iter().zip(b).fold(0u8, |acc, (x, y)| acc | (x ^ y)) == 0
}

async fn page(
    State(v): State<Arc<Viewer>>,
    Query(q): Query<HashMap<String, String>>,
    headers: HeaderMap,
) -> Response {
    match v.authorize(&q, &headers, false) {
        Ok(()) => (
            [(header::CONTENT_TYPE, "text/html; charset=utf-8")],
            INDEX_HTML,
        )
            .into_response(),
        Err(r) => r.into_response(),
    }
}

async fn script(
    State(v): State<Arc<Viewer>>,
    Query(q): Query<HashMap<String, String>>,
    headers: HeaderMap,
) -> Response {
    match v.authorize(&q, &headers, false) {
        Ok(()) => (
            [(header::CONTENT_TYPE, "text/javascript; charset=utf-8")],
            VIEWER_JS,
        )
            .into_response(),
        Err(r) => r.into_response(),
    }
}

async fn background(
    State(v): State<Arc<Viewer>>,
    Query(q): Query<HashMap<String, String>>,
    headers: HeaderMap,
) -> Response {
    if let Err(r) = v.authorize(&q, &headers, false) {
        return r.into_response();
    }
    match &v.background {
        Some(b) => ([(header::CONTENT_TYPE, "image/png")], b.png.clone()).into_response(),
        None => (StatusCode::NOT_FOUND, "no background image\n").into_response(),
    }
}

async fn ws_upgrade(
    State(v): State<Arc<Viewer>>,
    Query(q): Query<HashMap<String, String>>,
    headers: HeaderMap,
    ws: WebSocketUpgrade,
) -> Response {
    match v.authorize(&q, &headers, true) {
        Ok(()) => ws.on_upgrade(move |socket| client(v, socket)),
        Err(r) => r.into_response(),
    }
}

/// One page: a snapshot, then deltas whenever the scene changed and the client is free (a
/// new snapshot after the scene was rebuilt); a replay's state rides on every frame.
async fn client(v: Arc<Viewer>, socket: WebSocket) {
    /// Counts the page while its task lives, however it ends.
    struct Counted(Arc<Viewer>);
    impl Drop for Counted {
        fn drop(&mut self) {
            self.0.pages.fetch_sub(1, Ordering::SeqCst);
        }
    }
    v.pages.fetch_add(1, Ordering::SeqCst);
    let _counted = Counted(v.clone());
    let (mut tx, mut rx) = socket.split();
    let mut wake = v.version.subscribe();
    let (mut epoch, mut seen) = (u64::MAX, 0);
    let mut last_status = None;
    let mut first = true;
    loop {
        if !first {
            tokio::select! {
                changed = wake.changed() => {
                    if changed.is_err() {
                        break;
                    }
                }
                incoming = rx.next() => {
                    match incoming {
                        Some(Ok(WsMessage::Text(t))) => {
                            let reply = v.handle_text(t.as_str()).to_string();
                            if tx.send(WsMessage::Text(reply.into())).await.is_err() {
                                break;
                            }
                        }
                        Some(Ok(WsMessage::Close(_))) | None | Some(Err(_)) => break,
                        Some(Ok(_)) => {}
                    }
                    continue;
                }
            }
        }
        first = false;
        wake.mark_unchanged();
        let status = v.status();
        let frame = {
            let s = lock(&v.scene);
            let now_epoch = v.epoch.load(Ordering::SeqCst);
            if now_epoch != epoch {
                epoch = now_epoch;
                let mut snap = s.snapshot();
                snap["contexts"] = v.contexts_json();
                snap["background"] = v.background_json();
                Some((snap, s.version()))
            } else {
                s.delta_since(seen).map(|d| (d, s.version()))
            }
        };
        let frame = match frame {
            Some((mut j, version)) => {
                seen = version;
                if let Some(st) = &status {
                    j["replay"] = st.clone();
                }
                Some(j)
            }
            None if status.is_some() && status != last_status => {
                Some(json!({"type": "status", "replay": status.clone()}))
            }
            None => None,
        };
        last_status = status;
        if let Some(j) = frame {
            if tx
                .send(WsMessage::Text(j.to_string().into()))
                .await
                .is_err()
            {
                break;
            }
            if !v.min_frame_interval.is_zero() {
                tokio::time::sleep(v.min_frame_interval).await;
            }
        }
    }
}

/// A replay control from the page (`{"replay":"play"}`, `"pause"`, `{"replay":"seek","t":T}`
/// with `T` seconds from the log's start, `{"replay":"speed","speed":X}`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ReplayControl {
    /// Play from the playhead.
    Play,
    /// Stop at the playhead.
    Pause,
    /// Move the playhead (seconds since the log's start); the scene is rebuilt there.
    Seek(f64),
    /// Playback speed (times real time).
    Speed(f64),
}

/// Serves the viewer on `listener` until the task is dropped.
pub async fn serve(viewer: Arc<Viewer>, listener: tokio::net::TcpListener) -> std::io::Result<()> {
    axum::serve(listener, viewer.router()).await
}

/// How the viewer's MOOS client behaves.
#[derive(Debug, Clone)]
pub struct JoinConfig {
    /// Seconds between `APPCAST_REQ` posts (pMarineViewer: 2 s).
    pub appcast_interval: Duration,
    /// Seconds between scene ticks (staleness, expiry).
    pub tick_interval: Duration,
    /// The `key=` of the appcast requests.
    pub appcast_key: String,
}

impl Default for JoinConfig {
    fn default() -> Self {
        JoinConfig {
            appcast_interval: Duration::from_secs(2),
            tick_interval: Duration::from_secs(1),
            appcast_key: "coug_view".to_string(),
        }
    }
}

/// The appcast request a viewer posts (`APPCAST_REQ`, and `APPCAST_REQ_<NODE>` per node
/// seen): every app of every node, for 3 s, any threshold.
pub fn appcast_request(key: &str) -> String {
    format!("node=all,app=all,duration=3.0,key={key},thresh=any")
}

/// Feeds the viewer from a MOOS client until its mail ends: registers the variables the scene
/// reads, hands every mail to [`Viewer::apply`] (at the client's MOOS time), posts appcast
/// requests and ticks the scene periodically.
pub async fn feed(
    viewer: Arc<Viewer>,
    client: Arc<moosdb::Client>,
    mut mail: moosdb::MailStream,
    config: JoinConfig,
) {
    for var in viewed_variables() {
        client.register(var, 0.0);
    }
    let mut appcast = tokio::time::interval(config.appcast_interval);
    let mut tick = tokio::time::interval(config.tick_interval);
    let request = appcast_request(&config.appcast_key);
    loop {
        tokio::select! {
            m = mail.recv() => {
                let Some(m) = m else { break };
                if m.is_double() {
                    continue;
                }
                viewer.apply(&m.key_str(), &m.sval_str(), client.moos_time());
            }
            _ = appcast.tick() => {
                if matches!(client.state(), moosdb::ConnectionState::Connected { .. }) {
                    let _ = client.notify(appcast::casting::APPCAST_REQ_VAR, Value::text(request.as_str()));
                    for node in viewer.with_scene(|s| s.nodes()) {
                        let _ = client.notify(
                            &appcast::casting::node_request_var(&node),
                            Value::text(request.as_str()),
                        );
                    }
                }
            }
            _ = tick.tick() => viewer.tick(client.moos_time()),
        }
    }
}
