//! The MOOSDB's TCP edge: accepts V10 (asynchronous) and old synchronous clients on tokio and
//! feeds their packets to the pure [`Database`] core.
//!
//! Each connection is one task: it reads the preamble and the name packet (5 s limits), runs
//! the handshake through the core, then concurrently reads packets into the core and writes
//! the packets the core queued for it. Handshakes never run on the accept loop, so a client
//! that connects while another disconnects cannot stall accepting (the C++ DB's failure in
//! reference section 11). Every socket gets TCP_NODELAY. A client whose outbox overflows
//! loses its oldest mail (counted and logged by the core); it never delays other clients.

use std::collections::HashMap;
use std::net::SocketAddr;
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::{Duration, Instant};

use futures_util::{SinkExt, StreamExt};
use tokio::io::AsyncReadExt;
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{Notify, watch};
use tokio::task::JoinHandle;
use tokio_util::codec::{FramedRead, FramedWrite};
use tracing::{debug, info, warn};

use crate::codec::{MoosCodec, PREAMBLE_LEN, preamble_ok};
use crate::db::{ClientId, Database, DbConfig, DbTime, Handshake};
use crate::packet::DEFAULT_MAX_PACKET_LEN;
use crate::time::{Warp, unix_now};

/// Default MOOSDB port.
pub const DEFAULT_PORT: u16 = 9000;

/// Time allowed for the preamble and for the name packet (the C++ DB's 5 s).
pub const HANDSHAKE_TIMEOUT: Duration = Duration::from_secs(5);

/// Settings of a [`Server`].
#[derive(Debug, Clone)]
pub struct ServerConfig {
    /// Address to listen on (default 127.0.0.1:9000; port 0 lets the OS pick).
    pub addr: SocketAddr,
    /// The core's settings (community, client timeout, outbox limit, host name).
    pub db: DbConfig,
    /// Time warp (`MOOSTimeWarp`).
    pub warp: Warp,
    /// Largest accepted packet; a client announcing more is disconnected.
    pub max_packet_len: usize,
}

impl Default for ServerConfig {
    fn default() -> Self {
        ServerConfig {
            addr: SocketAddr::from(([127, 0, 0, 1], DEFAULT_PORT)),
            db: DbConfig {
                host_name: local_host_name(),
                ..DbConfig::default()
            },
            warp: Warp::default(),
            max_packet_len: DEFAULT_MAX_PACKET_LEN,
        }
    }
}

impl ServerConfig {
    /// Defaults, listening on `addr` (use port 0 for an OS-chosen port).
    ///
    /// ```
    /// let cfg = moosdb::ServerConfig::with_addr(([127, 0, 0, 1], 0).into());
    /// assert_eq!(cfg.addr.port(), 0);
    /// ```
    pub fn with_addr(addr: SocketAddr) -> ServerConfig {
        ServerConfig {
            addr,
            ..ServerConfig::default()
        }
    }
}

/// This machine's host name (from `/etc/hostname` or `$HOSTNAME`), else `localhost`.
pub fn local_host_name() -> String {
    std::fs::read_to_string("/etc/hostname")
        .ok()
        .map(|s| s.trim().to_string())
        .filter(|s| !s.is_empty())
        .or_else(|| std::env::var("HOSTNAME").ok())
        .unwrap_or_else(|| "localhost".to_string())
}

#[derive(Debug)]
struct Conn {
    wake: Notify,
}

#[derive(Debug)]
struct State {
    db: Database,
    conns: HashMap<ClientId, Arc<Conn>>,
}

#[derive(Debug)]
struct Shared {
    state: Mutex<State>,
    start: Instant,
    warp: Warp,
    max_packet_len: usize,
}

impl Shared {
    fn now(&self) -> DbTime {
        DbTime {
            moos: self.warp.local(unix_now()),
            mono: self.start.elapsed().as_secs_f64(),
        }
    }

    fn lock(&self) -> MutexGuard<'_, State> {
        // A panic while holding the lock cannot leave the core half-updated in a way that
        // matters more than stopping; keep serving with whatever state it has.
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }
}

/// A running MOOSDB. Dropping it (or [`Server::shutdown`]) stops accepting and closes every
/// connection.
#[derive(Debug)]
pub struct Server {
    local_addr: SocketAddr,
    shared: Arc<Shared>,
    stop: watch::Sender<bool>,
    tasks: Vec<JoinHandle<()>>,
}

impl Server {
    /// Binds and starts serving.
    pub async fn bind(config: ServerConfig) -> std::io::Result<Server> {
        let listener = TcpListener::bind(config.addr).await?;
        let local_addr = listener.local_addr()?;
        let start = Instant::now();
        let warp = config.warp;
        let now = DbTime {
            moos: warp.local(unix_now()),
            mono: 0.0,
        };
        let shared = Arc::new(Shared {
            state: Mutex::new(State {
                db: Database::new(config.db, now),
                conns: HashMap::new(),
            }),
            start,
            warp,
            max_packet_len: config.max_packet_len,
        });
        let (stop, stop_rx) = watch::channel(false);
        info!(%local_addr, "MOOSDB listening");
        let accept = tokio::spawn(accept_loop(listener, shared.clone(), stop_rx.clone()));
        let reaper = tokio::spawn(reap_loop(shared.clone(), stop_rx));
        Ok(Server {
            local_addr,
            shared,
            stop,
            tasks: vec![accept, reaper],
        })
    }

    /// The bound address (with the OS-chosen port when bound to port 0).
    pub fn local_addr(&self) -> SocketAddr {
        self.local_addr
    }

    /// Runs `f` on the core under its lock (inspection, tests, in-process posting).
    pub fn with_db<R>(&self, f: impl FnOnce(&mut Database) -> R) -> R {
        f(&mut self.shared.lock().db)
    }

    /// Stops accepting and closes every connection.
    pub fn shutdown(self) {
        drop(self);
    }
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.stop.send(true);
        for t in &self.tasks {
            t.abort();
        }
    }
}

async fn accept_loop(listener: TcpListener, shared: Arc<Shared>, stop: watch::Receiver<bool>) {
    loop {
        match listener.accept().await {
            Ok((sock, peer)) => {
                if let Err(e) = sock.set_nodelay(true) {
                    debug!(%peer, "set_nodelay failed: {e}");
                }
                let shared = shared.clone();
                let mut stop = stop.clone();
                tokio::spawn(async move {
                    tokio::select! {
                        _ = serve(sock, peer, shared) => {}
                        _ = stop.wait_for(|s| *s) => {}
                    }
                });
            }
            Err(e) => {
                // Out of descriptors and similar: back off briefly, keep accepting.
                warn!("accept failed: {e}");
                tokio::time::sleep(Duration::from_millis(20)).await;
            }
        }
    }
}

async fn reap_loop(shared: Arc<Shared>, mut stop: watch::Receiver<bool>) {
    let mut tick = tokio::time::interval(Duration::from_millis(250));
    loop {
        tokio::select! {
            _ = tick.tick() => {}
            _ = stop.wait_for(|s| *s) => return,
        }
        let now = shared.now();
        let mut st = shared.lock();
        for (id, _) in st.db.reap_silent(now) {
            if let Some(c) = st.conns.get(&id) {
                c.wake.notify_one();
            }
        }
    }
}

async fn serve(sock: TcpStream, peer: SocketAddr, shared: Arc<Shared>) {
    let (mut rd, wr) = sock.into_split();
    let mut pre = [0u8; PREAMBLE_LEN];
    match tokio::time::timeout(HANDSHAKE_TIMEOUT, rd.read_exact(&mut pre)).await {
        Ok(Ok(_)) => {}
        Ok(Err(e)) => {
            debug!(%peer, "connection closed before the protocol string: {e}");
            return;
        }
        Err(_) => {
            warn!(%peer, "no protocol string within 5 s; closing");
            return;
        }
    }
    if !preamble_ok(&pre) {
        warn!(%peer, "wrong protocol string; closing");
        return;
    }
    // The preamble is raw bytes; everything after it is packets.
    let mut reader = FramedRead::new(rd, MoosCodec::new(shared.max_packet_len));
    let mut wr = FramedWrite::new(wr, MoosCodec::default());
    // Each wake writes everything the core queued in one go (the outbox limits bound it), as
    // one buffer, instead of flushing every 8 KiB while queueing.
    wr.set_backpressure_boundary(usize::MAX);
    let first = match tokio::time::timeout(HANDSHAKE_TIMEOUT, reader.next()).await {
        Ok(Some(Ok(msgs))) => msgs.into_iter().next(),
        Ok(None) => {
            debug!(%peer, "closed before sending its name");
            return;
        }
        Ok(Some(Err(e))) => {
            warn!(%peer, "bad handshake packet: {e}");
            None
        }
        Err(_) => {
            warn!(%peer, "no name packet within 5 s");
            None
        }
    };
    let conn = Arc::new(Conn {
        wake: Notify::new(),
    });
    let handshake = {
        let now = shared.now();
        let mut st = shared.lock();
        let h = st.db.handshake(first.as_ref(), now);
        if let Some(id) = h.id() {
            st.conns.insert(id, conn.clone());
        }
        h
    };
    let id = match handshake {
        Handshake::Welcome { id, reply } => {
            if let Err(e) = wr.send(&[reply][..]).await {
                debug!(%peer, "could not send Welcome: {e}");
                drop_client(&shared, id);
                return;
            }
            id
        }
        Handshake::Poison { reply } => {
            warn!(%peer, reason = %reply.sval_str(), "handshake refused");
            let _ = wr.send(&[reply][..]).await;
            let _ = wr.close().await;
            return;
        }
    };
    let name = first.map(|m| m.sval_str().into_owned()).unwrap_or_default();

    let read_side = async {
        loop {
            match reader.next().await {
                Some(Ok(msgs)) => {
                    let now = shared.now();
                    let mut st = shared.lock();
                    match st.db.handle(id, msgs, now) {
                        Ok(effects) => {
                            for r in effects.ready {
                                if let Some(c) = st.conns.get(&r) {
                                    c.wake.notify_one();
                                }
                            }
                        }
                        Err(_) => return,
                    }
                }
                None => {
                    debug!(client = %name, "closed by the client");
                    return;
                }
                Some(Err(e)) => {
                    warn!(client = %name, %peer, "closing connection: {e}");
                    return;
                }
            }
        }
    };
    let write_side = async {
        let mut packets = Vec::new();
        loop {
            conn.wake.notified().await;
            let alive = shared.lock().db.drain_outbox(id, &mut packets);
            if !alive {
                return;
            }
            if packets.is_empty() {
                continue;
            }
            // Queue every packet, then write them together.
            for p in packets.drain(..) {
                if wr.feed(&p[..]).await.is_err() {
                    return;
                }
            }
            if wr.flush().await.is_err() {
                return;
            }
        }
    };
    tokio::select! {
        _ = read_side => {}
        _ = write_side => {}
    }
    drop_client(&shared, id);
}

fn drop_client(shared: &Shared, id: ClientId) {
    let now = shared.now();
    let mut st = shared.lock();
    st.conns.remove(&id);
    st.db.disconnect(id, now);
}
