//! The I/O edge: runs an [`Emulator`] on a TCP listener or a pseudo-terminal, on tokio's
//! clock (emulator time is the seconds since the edge started; paused in tests).
//!
//! - TCP: listens on the given address (127.0.0.1, port 0 by default: the OS picks one);
//!   one host at a time, a newer connection replaces the older one (a driver that
//!   reconnects after a stall is served at once). A disconnection fault closes the socket;
//!   connections made while the device is off are closed at once.
//! - Pseudo-terminal: the slave path (and the optional link) are the endpoint; a
//!   disconnection fault closes the terminal (the driver's reads fail) and, once the device
//!   is back, opens a new one and moves the link to it: [`Handle::endpoints`] announces it.
//!
//! Every tick, the emulator's reports are written; a TCP peer that does not take them
//! within [`WRITE_TIMEOUT`] is dropped; a terminal that is full drops them.

use std::fmt;
use std::io;
use std::net::SocketAddr;
use std::path::PathBuf;
use std::time::Duration;

use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::{TcpListener, TcpStream};
use tokio::sync::{oneshot, watch};
use tokio::task::JoinHandle;
use tokio::time::{Instant, MissedTickBehavior};

use crate::device::Emulator;
use crate::pty::Pty;

/// How long a TCP write may wait for the peer before the connection is dropped.
pub const WRITE_TIMEOUT: Duration = Duration::from_secs(2);

/// Where to serve.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Transport {
    /// A TCP listener at this address.
    Tcp(SocketAddr),
    /// A pseudo-terminal, with an optional symbolic link to its slave.
    Pty {
        /// The link to make (e.g. `/tmp/gps0`).
        link: Option<PathBuf>,
    },
}

impl Transport {
    /// TCP on 127.0.0.1 at `port` (0: the OS picks).
    pub fn loopback(port: u16) -> Self {
        Transport::Tcp(SocketAddr::from(([127, 0, 0, 1], port)))
    }
}

/// Where a driver finds the emulator.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Endpoint {
    /// The TCP address listened on.
    Tcp(SocketAddr),
    /// A pseudo-terminal.
    Pty {
        /// The slave's path.
        path: PathBuf,
        /// The link to it, if any.
        link: Option<PathBuf>,
    },
    /// Off (between a disconnection and the new pseudo-terminal), or stopped.
    Down,
}

impl Endpoint {
    /// The path a serial driver opens: the link if there is one, else the slave.
    pub fn serial_path(&self) -> Option<&std::path::Path> {
        match self {
            Endpoint::Pty { path, link } => Some(link.as_deref().unwrap_or(path)),
            _ => None,
        }
    }

    /// The TCP address.
    pub fn tcp(&self) -> Option<SocketAddr> {
        match self {
            Endpoint::Tcp(a) => Some(*a),
            _ => None,
        }
    }
}

impl fmt::Display for Endpoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Endpoint::Tcp(a) => write!(f, "tcp {a}"),
            Endpoint::Pty { path, link: None } => write!(f, "pty {}", path.display()),
            Endpoint::Pty {
                path,
                link: Some(l),
            } => write!(f, "pty {} (link {})", path.display(), l.display()),
            Endpoint::Down => write!(f, "down"),
        }
    }
}

/// What the edge did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct EdgeStats {
    /// Connections accepted (TCP) or terminals opened (pseudo-terminal).
    pub connections: u64,
    /// Connections closed by a disconnection fault.
    pub disconnects: u64,
    /// Bytes written.
    pub bytes_out: u64,
    /// Bytes received.
    pub bytes_in: u64,
    /// Bytes dropped (a full terminal, a peer gone or stalled).
    pub dropped: u64,
    /// Bytes written earlier but flushed unread from a terminal (its reader stalled; see
    /// [`crate::pty::STALE_BYTES`]).
    pub flushed: u64,
    /// How many times a terminal was flushed so: each can cut one frame, whose tail the
    /// reader then gets as garbage.
    pub flushes: u64,
}

/// A running emulator: its endpoint, and the way to stop it.
#[derive(Debug)]
pub struct Handle {
    endpoints: watch::Receiver<Endpoint>,
    stop: Option<oneshot::Sender<()>>,
    task: JoinHandle<io::Result<EdgeStats>>,
}

impl Handle {
    /// The current endpoint.
    pub fn endpoint(&self) -> Endpoint {
        self.endpoints.borrow().clone()
    }

    /// The endpoint as it changes (a new pseudo-terminal after a disconnection).
    pub fn endpoints(&self) -> watch::Receiver<Endpoint> {
        self.endpoints.clone()
    }

    /// Stops the emulator (closing its socket or terminal) and returns what it did.
    pub async fn stop(mut self) -> io::Result<EdgeStats> {
        if let Some(s) = self.stop.take() {
            let _ = s.send(());
        }
        self.task
            .await
            .map_err(|e| io::Error::other(e.to_string()))?
    }

    /// Waits until the emulator ends by itself (an I/O error), without stopping it.
    pub async fn join(mut self) -> io::Result<EdgeStats> {
        let _keep = self.stop.take();
        self.task
            .await
            .map_err(|e| io::Error::other(e.to_string()))?
    }
}

/// Starts `emulator` on `transport` in the current tokio runtime: the listener or terminal
/// is open when this returns (errors are returned here), its endpoint in the handle.
pub async fn spawn(emulator: Emulator, transport: Transport) -> io::Result<Handle> {
    let (stop_tx, stop_rx) = oneshot::channel();
    let (endpoints, task) = match transport {
        Transport::Tcp(addr) => {
            let listener = TcpListener::bind(addr).await?;
            let (tx, rx) = watch::channel(Endpoint::Tcp(listener.local_addr()?));
            (rx, tokio::spawn(run_tcp(emulator, listener, stop_rx, tx)))
        }
        Transport::Pty { link } => {
            let pty = Pty::open(link.as_deref())?;
            let (tx, rx) = watch::channel(Endpoint::Pty {
                path: pty.path().to_path_buf(),
                link: link.clone(),
            });
            (rx, tokio::spawn(run_pty(emulator, pty, link, stop_rx, tx)))
        }
    };
    Ok(Handle {
        endpoints,
        stop: Some(stop_tx),
        task,
    })
}

fn ticker(period: f64) -> tokio::time::Interval {
    let p = Duration::from_secs_f64(period.clamp(0.001, 10.0));
    let mut i = tokio::time::interval(p);
    i.set_missed_tick_behavior(MissedTickBehavior::Skip);
    i
}

async fn read_opt(conn: &mut Option<TcpStream>, buf: &mut [u8]) -> io::Result<usize> {
    match conn {
        Some(c) => c.read(buf).await,
        None => std::future::pending().await,
    }
}

/// Writes to the connection, dropping it when the peer is gone or stalls.
async fn send(conn: &mut Option<TcpStream>, data: &[u8], stats: &mut EdgeStats) {
    if data.is_empty() {
        return;
    }
    let Some(c) = conn else {
        stats.dropped += data.len() as u64;
        return;
    };
    match tokio::time::timeout(WRITE_TIMEOUT, c.write_all(data)).await {
        Ok(Ok(())) => stats.bytes_out += data.len() as u64,
        _ => {
            stats.dropped += data.len() as u64;
            *conn = None;
        }
    }
}

async fn run_tcp(
    mut emu: Emulator,
    listener: TcpListener,
    mut stop: oneshot::Receiver<()>,
    _endpoint: watch::Sender<Endpoint>,
) -> io::Result<EdgeStats> {
    let start = Instant::now();
    let now = || start.elapsed().as_secs_f64();
    let mut tick = ticker(emu.period());
    let mut conn: Option<TcpStream> = None;
    let mut stats = EdgeStats::default();
    let mut buf = vec![0u8; 4096];
    loop {
        tokio::select! {
            biased;
            _ = &mut stop => break,
            _ = tick.tick() => {
                let out = emu.tick(now());
                if out.disconnect && conn.take().is_some() {
                    stats.disconnects += 1;
                }
                send(&mut conn, &out.bytes, &mut stats).await;
            }
            acc = listener.accept() => {
                let (s, _) = acc?;
                let t = now();
                if emu.offline(t) {
                    drop(s);
                    continue;
                }
                let _ = s.set_nodelay(true);
                conn = Some(s);
                stats.connections += 1;
                let hello = emu.connect(t);
                send(&mut conn, &hello, &mut stats).await;
            }
            r = read_opt(&mut conn, &mut buf) => {
                match r {
                    Ok(n) if n > 0 => {
                        stats.bytes_in += n as u64;
                        let answer = emu.receive(now(), &buf[..n]);
                        send(&mut conn, &answer, &mut stats).await;
                    }
                    _ => conn = None,
                }
            }
        }
    }
    Ok(stats)
}

async fn read_pty(pty: &Option<Pty>, buf: &mut [u8]) -> io::Result<usize> {
    match pty {
        Some(p) => p.read(buf).await,
        None => std::future::pending().await,
    }
}

fn write_pty(pty: &Option<Pty>, data: &[u8], stats: &mut EdgeStats) -> io::Result<()> {
    if data.is_empty() {
        return Ok(());
    }
    match pty {
        Some(p) => {
            let w = p.write(data)?;
            stats.dropped += w.dropped as u64;
            stats.bytes_out += (data.len() - w.dropped) as u64;
            if w.flushed > 0 {
                stats.flushed += w.flushed as u64;
                stats.flushes += 1;
            }
        }
        None => stats.dropped += data.len() as u64,
    }
    Ok(())
}

async fn run_pty(
    mut emu: Emulator,
    pty: Pty,
    link: Option<PathBuf>,
    mut stop: oneshot::Receiver<()>,
    endpoint: watch::Sender<Endpoint>,
) -> io::Result<EdgeStats> {
    let start = Instant::now();
    let now = || start.elapsed().as_secs_f64();
    let mut tick = ticker(emu.period());
    let mut stats = EdgeStats {
        connections: 1,
        ..EdgeStats::default()
    };
    let hello = emu.connect(0.0);
    let mut pty = Some(pty);
    write_pty(&pty, &hello, &mut stats)?;
    let mut buf = vec![0u8; 4096];
    loop {
        tokio::select! {
            biased;
            _ = &mut stop => break,
            _ = tick.tick() => {
                let t = now();
                let out = emu.tick(t);
                if out.disconnect && pty.take().is_some() {
                    stats.disconnects += 1;
                    endpoint.send_replace(Endpoint::Down);
                }
                if pty.is_none() && !emu.offline(t) {
                    let p = Pty::open(link.as_deref())?;
                    endpoint.send_replace(Endpoint::Pty { path: p.path().to_path_buf(), link: link.clone() });
                    pty = Some(p);
                    stats.connections += 1;
                    let hello = emu.connect(t);
                    write_pty(&pty, &hello, &mut stats)?;
                }
                write_pty(&pty, &out.bytes, &mut stats)?;
            }
            r = read_pty(&pty, &mut buf) => {
                match r {
                    Ok(n) if n > 0 => {
                        stats.bytes_in += n as u64;
                        let answer = emu.receive(now(), &buf[..n]);
                        write_pty(&pty, &answer, &mut stats)?;
                    }
                    Ok(_) => {}
                    Err(e) if e.raw_os_error() == Some(libc::EIO) => {}
                    Err(e) => return Err(e),
                }
            }
        }
    }
    endpoint.send_replace(Endpoint::Down);
    Ok(stats)
}
