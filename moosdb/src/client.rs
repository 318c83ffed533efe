//! The asynchronous (MOOS V10) client.
//!
//! [`Client::start`] spawns one task that connects (retrying every second of warped time
//! while no DB listens), handshakes, and then runs a writer (batches everything posted since
//! its last write into one packet, heads it with the `'T'` timing message at most once per
//! unwarped second, and sends the timing message alone when idle) next to a reader (updates
//! the clock skew from timing echoes and forwards mail to the [`MailStream`]). When the
//! connection drops it reconnects and re-applies every registration. A Poison (name clash)
//! is final.
//!
//! ```no_run
//! # async fn demo() -> Result<(), moosdb::ClientError> {
//! use moosdb::{Client, ClientConfig, Value};
//! let (client, mut mail) = Client::start(ClientConfig::new("pExample", "127.0.0.1", 9000));
//! client.wait_connected().await?;
//! client.register("NAV_X", 0.0);
//! client.notify("DEPLOY", Value::from("true"))?;
//! while let Some(m) = mail.recv().await {
//!     println!("{} = {}", m.key_str(), m.dval);
//! }
//! # Ok(()) }
//! ```

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use bytes::Bytes;
use futures_util::{SinkExt, StreamExt};
use thiserror::Error;
use tokio::net::TcpStream;
use tokio::net::tcp::{OwnedReadHalf, OwnedWriteHalf};
use tokio::sync::{mpsc, watch};
use tokio::task::JoinHandle;
use tokio_util::codec::{FramedRead, FramedWrite};
use tracing::{error, info, warn};

use crate::codec::{MoosCodec, PREAMBLE};
use crate::db::fmt_g6;
use crate::message::{
    ASYNC_TIMING_KEY, ASYNCHRONOUS, DataType, Message, MsgType, NO_ID, SERVER_REQUEST_ID, Value,
};
use crate::packet::DEFAULT_MAX_PACKET_LEN;
use crate::time::{Warp, unix_now, update_skew};

/// Unwarped period of the timing message (`TIMING_MESSAGE_PERIOD`).
pub const TIMING_PERIOD: Duration = Duration::from_secs(1);

/// Longest the writer sleeps without checking whether a timing message is due.
const WRITER_WAKE: Duration = Duration::from_millis(333);

/// Settings of a [`Client`].
#[derive(Debug, Clone)]
pub struct ClientConfig {
    /// DB host (`ServerHost`).
    pub host: String,
    /// DB port (`ServerPort`).
    pub port: u16,
    /// This client's MOOS name (must be unique in the community).
    pub name: String,
    /// Time warp (`MOOSTimeWarp`); must match the DB's.
    pub warp: Warp,
    /// Apply the DB's clock skew to [`Client::moos_time`] (MOOS default: on).
    pub skew_correction: bool,
    /// Mail held for the application before the reader stops reading (back-pressure).
    pub mail_capacity: usize,
    /// Posts queued for the writer; beyond it posting fails with
    /// [`ClientError::OutboxFull`] instead of growing without bound.
    pub outbox_capacity: usize,
    /// Largest packet accepted from the DB.
    pub max_packet_len: usize,
    /// Longest wait for the Welcome after sending the name.
    pub handshake_timeout: Duration,
}

impl ClientConfig {
    /// Defaults for `name` talking to `host:port`.
    pub fn new(name: &str, host: &str, port: u16) -> ClientConfig {
        ClientConfig {
            host: host.to_string(),
            port,
            name: name.to_string(),
            warp: Warp::default(),
            skew_correction: true,
            mail_capacity: 4096,
            outbox_capacity: 16384,
            max_packet_len: DEFAULT_MAX_PACKET_LEN,
            handshake_timeout: Duration::from_secs(10),
        }
    }
}

/// Where the client is in its life.
#[derive(Debug, Clone, PartialEq)]
pub enum ConnectionState {
    /// Trying to reach or handshake with the DB.
    Connecting,
    /// Welcomed by the DB.
    Connected {
        /// The DB's community.
        community: String,
        /// The DB's host name as the DB sees it.
        db_host: String,
    },
    /// Refused by the DB (name clash); final.
    Poisoned(String),
    /// Closed by the application; final.
    Closed,
}

/// Client failures.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ClientError {
    /// Posting needs a live connection.
    #[error("not connected to a MOOSDB")]
    NotConnected,
    /// The client was closed.
    #[error("client is closed")]
    Closed,
    /// The DB refused the client.
    #[error("refused by the MOOSDB: {0}")]
    Poisoned(String),
    /// Too many posts are waiting to be written (the DB or the network is not keeping up).
    #[error("outbox full: the MOOSDB is not keeping up")]
    OutboxFull,
}

#[derive(Debug)]
enum Cmd {
    Post(Message),
    Close,
}

#[derive(Debug, Default)]
struct Subscriptions {
    vars: BTreeMap<String, f64>,
    patterns: Vec<(String, String, f64)>,
}

#[derive(Debug)]
struct Inner {
    name: Bytes,
    warp: Warp,
    skew_correction: bool,
    next_id: AtomicI32,
    skew: Mutex<f64>,
    subs: Mutex<Subscriptions>,
}

impl Inner {
    fn next_id(&self) -> i32 {
        self.next_id.fetch_add(1, Ordering::Relaxed)
    }

    fn skew(&self) -> f64 {
        *self.skew.lock().unwrap_or_else(|p| p.into_inner())
    }

    fn set_skew(&self, s: f64) {
        *self.skew.lock().unwrap_or_else(|p| p.into_inner()) = s;
    }

    fn local_time(&self) -> f64 {
        self.warp.local(unix_now())
    }

    fn moos_time(&self) -> f64 {
        self.local_time() + self.skew()
    }

    fn msg(&self, t: MsgType, d: DataType, key: &str) -> Message {
        let mut m = Message::new(t, d, key);
        m.id = self.next_id();
        m.src = self.name.clone();
        m.time = self.moos_time();
        m
    }

    fn register_msg(&self, var: &str, interval: f64) -> Message {
        let mut m = self.msg(MsgType::Register, DataType::Double, var);
        m.dval = interval;
        m
    }

    fn pattern_msg(&self, t: MsgType, var_pat: &str, app_pat: &str, interval: f64) -> Message {
        let mut m = Message::new(t, DataType::String, "");
        m.id = self.next_id();
        m.src = self.name.clone();
        m.key = self.name.clone();
        m.time = self.moos_time();
        m.sval = Bytes::from(format!(
            "AppPattern={app_pat},VarPattern={var_pat},Interval={}",
            fmt_g6(interval)
        ));
        m
    }
}

/// Mail delivered by the DB, in arrival order.
#[derive(Debug)]
pub struct MailStream {
    rx: mpsc::Receiver<Message>,
}

impl MailStream {
    /// The next message; `None` once the client has stopped for good.
    pub async fn recv(&mut self) -> Option<Message> {
        self.rx.recv().await
    }

    /// A message if one is waiting.
    pub fn try_recv(&mut self) -> Option<Message> {
        self.rx.try_recv().ok()
    }
}

/// A handle to a running client; see the module documentation.
#[derive(Debug)]
pub struct Client {
    inner: Arc<Inner>,
    cmd: mpsc::Sender<Cmd>,
    state: watch::Receiver<ConnectionState>,
    task: JoinHandle<()>,
}

impl Client {
    /// Starts the client task (needs a tokio runtime) and returns the handle and its mail.
    pub fn start(config: ClientConfig) -> (Client, MailStream) {
        let inner = Arc::new(Inner {
            name: Bytes::from(config.name.clone()),
            warp: config.warp,
            skew_correction: config.skew_correction,
            next_id: AtomicI32::new(0),
            skew: Mutex::new(0.0),
            subs: Mutex::new(Subscriptions::default()),
        });
        let (cmd, cmd_rx) = mpsc::channel(config.outbox_capacity.max(1));
        let (state_tx, state) = watch::channel(ConnectionState::Connecting);
        let (mail_tx, rx) = mpsc::channel(config.mail_capacity.max(1));
        let task = tokio::spawn(run(inner.clone(), config, cmd_rx, state_tx, mail_tx));
        (
            Client {
                inner,
                cmd,
                state,
                task,
            },
            MailStream { rx },
        )
    }

    /// This client's MOOS name.
    pub fn name(&self) -> &str {
        std::str::from_utf8(&self.inner.name).unwrap_or("")
    }

    /// MOOS time: warped local time plus the skew learnt from the DB.
    pub fn moos_time(&self) -> f64 {
        self.inner.moos_time()
    }

    /// The skew currently applied.
    pub fn skew(&self) -> f64 {
        self.inner.skew()
    }

    /// The connection state now.
    pub fn state(&self) -> ConnectionState {
        self.state.borrow().clone()
    }

    /// A watch on the connection state.
    pub fn state_watch(&self) -> watch::Receiver<ConnectionState> {
        self.state.clone()
    }

    /// Waits until connected; fails if poisoned or closed first.
    pub async fn wait_connected(&self) -> Result<(), ClientError> {
        let mut w = self.state.clone();
        let s = w
            .wait_for(|s| !matches!(s, ConnectionState::Connecting))
            .await
            .map_err(|_| ClientError::Closed)?
            .clone();
        match s {
            ConnectionState::Connected { .. } => Ok(()),
            ConnectionState::Poisoned(r) => Err(ClientError::Poisoned(r)),
            _ => Err(ClientError::Closed),
        }
    }

    fn is_connected(&self) -> bool {
        matches!(*self.state.borrow(), ConnectionState::Connected { .. })
    }

    fn post(&self, m: Message) -> Result<(), ClientError> {
        self.cmd.try_send(Cmd::Post(m)).map_err(|e| match e {
            mpsc::error::TrySendError::Full(_) => {
                warn!("outbox full: post dropped");
                ClientError::OutboxFull
            }
            mpsc::error::TrySendError::Closed(_) => ClientError::Closed,
        })
    }

    /// Subscribes to `var`, delivering at most once per `interval` seconds (0 = every
    /// write). Kept and re-applied after every reconnect.
    pub fn register(&self, var: &str, interval: f64) {
        lock(&self.inner.subs)
            .vars
            .insert(var.to_string(), interval);
        if self.is_connected() {
            let _ = self.post(self.inner.register_msg(var, interval));
        }
    }

    /// Subscribes to every variable matching `var_pattern` written by an app matching
    /// `app_pattern` (`*` and `?` globs), now and in future. Re-applied after reconnects.
    pub fn register_pattern(&self, var_pattern: &str, app_pattern: &str, interval: f64) {
        {
            let mut s = lock(&self.inner.subs);
            let entry = (var_pattern.to_string(), app_pattern.to_string(), interval);
            s.patterns
                .retain(|(v, a, _)| v != var_pattern || a != app_pattern);
            s.patterns.push(entry);
        }
        if self.is_connected() {
            let m = self.inner.pattern_msg(
                MsgType::WildcardRegister,
                var_pattern,
                app_pattern,
                interval,
            );
            let _ = self.post(m);
        }
    }

    /// Cancels a subscription made with [`Client::register`].
    pub fn unregister(&self, var: &str) {
        lock(&self.inner.subs).vars.remove(var);
        if self.is_connected() {
            let mut m = self.inner.msg(MsgType::Unregister, DataType::Double, var);
            m.dval = 0.0;
            let _ = self.post(m);
        }
    }

    /// Cancels a pattern subscription made with [`Client::register_pattern`].
    pub fn unregister_pattern(&self, var_pattern: &str, app_pattern: &str) {
        lock(&self.inner.subs)
            .patterns
            .retain(|(v, a, _)| v != var_pattern || a != app_pattern);
        if self.is_connected() {
            let m =
                self.inner
                    .pattern_msg(MsgType::WildcardUnregister, var_pattern, app_pattern, 0.0);
            let _ = self.post(m);
        }
    }

    /// Publishes `value` to `var` now, with src = this client's name.
    pub fn notify(&self, var: &str, value: Value) -> Result<(), ClientError> {
        self.notify_with(var, value, None, "")
    }

    /// Publishes with an explicit time (MOOS time; `None` = now) and auxiliary source.
    pub fn notify_with(
        &self,
        var: &str,
        value: Value,
        time: Option<f64>,
        src_aux: &str,
    ) -> Result<(), ClientError> {
        if !self.is_connected() {
            return Err(ClientError::NotConnected);
        }
        let mut m = Message::notify(var, value, time.unwrap_or_else(|| self.inner.moos_time()));
        m.id = self.inner.next_id();
        m.src = self.inner.name.clone();
        m.src_aux = Bytes::copy_from_slice(src_aux.as_bytes());
        self.post(m)
    }

    /// Publishes a notify relayed from another community (pShare's posting with the source
    /// kept): its source, aux, community and time are sent as they are; an empty source
    /// becomes this client's name. The id is this client's.
    pub fn relay(&self, mut m: Message) -> Result<(), ClientError> {
        if !self.is_connected() {
            return Err(ClientError::NotConnected);
        }
        m.msg_type = MsgType::Notify;
        m.id = self.inner.next_id();
        if m.src.is_empty() {
            m.src = self.inner.name.clone();
        }
        self.post(m)
    }

    /// Sends a server request (`ALL`, `VAR_SUMMARY`, `PROC_SUMMARY`, `DB_CLEAR`); replies
    /// arrive as mail with id -2.
    pub fn server_request(&self, what: &str) -> Result<(), ClientError> {
        if !self.is_connected() {
            return Err(ClientError::NotConnected);
        }
        let mut m = Message::new(MsgType::ServerRequest, DataType::String, what);
        m.id = SERVER_REQUEST_ID;
        m.src = self.inner.name.clone();
        m.time = self.inner.moos_time();
        self.post(m)
    }

    /// Flushes what was posted, closes the connection and waits for the task to end.
    pub async fn close(self) {
        let _ = self.cmd.send(Cmd::Close).await;
        let _ = self.task.await;
    }

    /// Stops the task at once without flushing (like a killed process).
    pub fn abort(self) {
        self.task.abort();
    }
}

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}

enum SessionEnd {
    Lost,
    Closed,
}

async fn run(
    inner: Arc<Inner>,
    config: ClientConfig,
    mut cmd_rx: mpsc::Receiver<Cmd>,
    state: watch::Sender<ConnectionState>,
    mail: mpsc::Sender<Message>,
) {
    let mut attempt: u64 = 0;
    loop {
        let _ = state.send(ConnectionState::Connecting);
        let stream = loop {
            match TcpStream::connect((config.host.as_str(), config.port)).await {
                Ok(s) => break s,
                Err(e) => {
                    attempt += 1;
                    if attempt == 1 || attempt.is_multiple_of(10) {
                        info!(
                            "contacting a MOOS server {}:{} - try {attempt}: {e}",
                            config.host, config.port
                        );
                    }
                    let pause = config.warp.pause(Duration::from_secs(1));
                    if !idle_wait(&mut cmd_rx, pause).await {
                        let _ = state.send(ConnectionState::Closed);
                        return;
                    }
                }
            }
        };
        let _ = stream.set_nodelay(true);
        let (rd, wr) = stream.into_split();
        let mut reader = FramedRead::new(rd, MoosCodec::new(config.max_packet_len));
        let mut wr = FramedWrite::new(wr, MoosCodec::default());
        inner.set_skew(0.0);
        let mut hello = Message::new(MsgType::Data, DataType::String, ASYNCHRONOUS);
        hello.time = inner.local_time();
        hello.sval = inner.name.clone();
        // The raw preamble goes ahead of the name packet, in the same write.
        wr.write_buffer_mut().extend_from_slice(&PREAMBLE);
        let reply = async {
            wr.send(&[hello][..]).await.ok()?;
            reader.next().await?.ok()
        };
        let reply = tokio::time::timeout(config.handshake_timeout, reply)
            .await
            .ok()
            .flatten();
        let Some(first) = reply.and_then(|p| p.into_iter().next()) else {
            warn!(
                "no handshake reply from {}:{}; retrying",
                config.host, config.port
            );
            if !idle_wait(&mut cmd_rx, config.warp.pause(Duration::from_secs(1))).await {
                let _ = state.send(ConnectionState::Closed);
                return;
            }
            continue;
        };
        if first.msg_type == MsgType::Poison {
            let reason = first.sval_str().into_owned();
            error!("MOOSDB refused this client: {reason}");
            let _ = state.send(ConnectionState::Poisoned(reason));
            return;
        }
        if inner.skew_correction {
            inner.set_skew(first.dval);
        }
        let aux = String::from_utf8_lossy(&first.src_aux).into_owned();
        let db_host = aux
            .split(',')
            .find_map(|kv| kv.trim().strip_prefix("hostname="))
            .unwrap_or("")
            .to_string();
        let community = String::from_utf8_lossy(&first.community).into_owned();
        info!(%community, %db_host, "connected to MOOSDB");
        let _ = state.send(ConnectionState::Connected { community, db_host });
        attempt = 0;

        let read_side = read_loop(&inner, &mut reader, &mail);
        let write_side = write_loop(&inner, &mut wr, &mut cmd_rx);
        let end = tokio::select! {
            _ = read_side => SessionEnd::Lost,
            e = write_side => e,
        };
        match end {
            SessionEnd::Closed => {
                let _ = wr.close().await;
                let _ = state.send(ConnectionState::Closed);
                return;
            }
            SessionEnd::Lost => {
                warn!("connection to the MOOSDB lost; reconnecting");
            }
        }
    }
}

/// Waits `pause` while disconnected, discarding posts; `false` if the client was closed.
async fn idle_wait(cmd_rx: &mut mpsc::Receiver<Cmd>, pause: Duration) -> bool {
    let deadline = tokio::time::Instant::now() + pause;
    loop {
        tokio::select! {
            _ = tokio::time::sleep_until(deadline) => return true,
            c = cmd_rx.recv() => match c {
                None | Some(Cmd::Close) => return false,
                Some(Cmd::Post(_)) => {}
            },
        }
    }
}

async fn read_loop(
    inner: &Inner,
    reader: &mut FramedRead<OwnedReadHalf, MoosCodec>,
    mail: &mpsc::Sender<Message>,
) {
    let mut packets: u64 = 0;
    loop {
        let msgs = match reader.next().await {
            Some(Ok(m)) => m,
            None => return,
            Some(Err(e)) => {
                warn!("bad data from the MOOSDB: {e}");
                return;
            }
        };
        packets += 1;
        for (i, m) in msgs.into_iter().enumerate() {
            match m.msg_type {
                MsgType::Timing if i == 0 => {
                    if packets > 1 && inner.skew_correction {
                        let rx = inner.local_time();
                        inner.set_skew(update_skew(inner.skew(), m.time, m.dval, rx));
                    }
                }
                MsgType::Null | MsgType::Welcome | MsgType::Timing => {}
                _ => {
                    // A dropped MailStream is not an error: the client keeps serving posts.
                    let _ = mail.send(m).await;
                }
            }
        }
    }
}

async fn write_loop(
    inner: &Inner,
    wr: &mut FramedWrite<OwnedWriteHalf, MoosCodec>,
    cmd_rx: &mut mpsc::Receiver<Cmd>,
) -> SessionEnd {
    let mut batch: Vec<Message> = Vec::new();
    let mut last_timing: Option<Instant> = None;
    {
        let subs = lock(&inner.subs);
        for (var, interval) in &subs.vars {
            batch.push(inner.register_msg(var, *interval));
        }
        for (v, a, i) in &subs.patterns {
            batch.push(inner.pattern_msg(MsgType::WildcardRegister, v, a, *i));
        }
    }
    let mut closing = false;
    loop {
        if last_timing.is_none_or(|t| t.elapsed() >= TIMING_PERIOD) {
            let mut t = Message::new(MsgType::Timing, DataType::Double, ASYNC_TIMING_KEY);
            t.id = NO_ID;
            t.time = inner.local_time();
            t.dval = 0.0;
            batch.insert(0, t);
            last_timing = Some(Instant::now());
        }
        if !batch.is_empty() {
            let sent = wr.send(&batch[..]).await;
            batch.clear();
            if sent.is_err() {
                return SessionEnd::Lost;
            }
        }
        if closing {
            return SessionEnd::Closed;
        }
        let wait = tokio::time::sleep(WRITER_WAKE);
        tokio::select! {
            _ = wait => {}
            c = cmd_rx.recv() => {
                match c {
                    None | Some(Cmd::Close) => closing = true,
                    Some(Cmd::Post(m)) => batch.push(m),
                }
                while !closing {
                    match cmd_rx.try_recv() {
                        Ok(Cmd::Post(m)) => batch.push(m),
                        Ok(Cmd::Close) => closing = true,
                        Err(mpsc::error::TryRecvError::Disconnected) => closing = true,
                        Err(mpsc::error::TryRecvError::Empty) => break,
                    }
                }
            }
        }
    }
}
