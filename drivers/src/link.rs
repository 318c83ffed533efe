//! The one I/O edge of every driver: a serial port (any tty path, so a pseudo-terminal works
//! the same) or a TCP client, run on its own thread, exchanging bytes with the app through
//! bounded channels.
//!
//! The app side never blocks: [`Link::poll`] and [`Link::send`] only try the channels. When
//! the receive channel is full (the app is not keeping up) a chunk is dropped and counted;
//! when the send channel is full, or a write does not complete within the write timeout (a
//! stalled peer), the command is dropped and counted. A link that fails (the device unplugged,
//! the peer closing, a read or write error, or no byte for the stall timeout) is closed and
//! reopened with exponential backoff, forever, until the [`Link`] is dropped.
//!
//! The serial port is opened with `libc` (termios raw mode, 8N1, the given baud rate, no flow
//! control), not through a serial-port crate: it needs nothing from the system (no libudev)
//! and a pty path opens as a tty does.
//!
//! Every connection gets a generation number; the bytes read carry it, so the app can tell the
//! first bytes of a new connection (and restart its protocol's start-up sequence) from the
//! last bytes of an old one.

use std::io::{self, Read, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, SyncSender, TrySendError, sync_channel};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// Where a link connects.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Endpoint {
    /// A serial device (or pseudo-terminal) path and its baud rate.
    Serial {
        /// The device path (`/dev/ttyUSB0`, a udev link, a pty).
        path: PathBuf,
        /// Baud rate (a standard one: 9600, 19200, 38400, 57600, 115200, 230400, ...).
        baud: u32,
    },
    /// A TCP server.
    Tcp {
        /// Host name or address.
        host: String,
        /// Port.
        port: u16,
    },
}

impl std::fmt::Display for Endpoint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Endpoint::Serial { path, baud } => write!(f, "{}@{baud}", path.display()),
            Endpoint::Tcp { host, port } => write!(f, "tcp://{host}:{port}"),
        }
    }
}

/// How a link behaves.
#[derive(Debug, Clone, PartialEq)]
pub struct LinkConfig {
    /// Where it connects.
    pub endpoint: Endpoint,
    /// First delay before reopening a failed link (doubles up to `backoff_max`).
    pub backoff_min: Duration,
    /// Longest delay between attempts.
    pub backoff_max: Duration,
    /// Chunks of received bytes the channel to the app holds.
    pub rx_capacity: usize,
    /// Commands the channel from the app holds.
    pub tx_capacity: usize,
    /// How long one wait for bytes lasts before the thread looks at its stop flag and stall
    /// timer (bytes queued by the app wake it at once).
    pub poll_interval: Duration,
    /// How long a write may take before the command is dropped (a stalled peer).
    pub write_timeout: Duration,
    /// Reconnect when no byte arrived for this long (`None`: never).
    pub stall_timeout: Option<Duration>,
}

impl LinkConfig {
    /// The defaults for `endpoint`: backoff 0.2 s doubling to 5 s, 256 received chunks, 64
    /// commands, 100 ms waits, 0.5 s writes, no stall timeout.
    pub fn new(endpoint: Endpoint) -> Self {
        LinkConfig {
            endpoint,
            backoff_min: Duration::from_millis(200),
            backoff_max: Duration::from_secs(5),
            rx_capacity: 256,
            tx_capacity: 64,
            poll_interval: Duration::from_millis(100),
            write_timeout: Duration::from_millis(500),
            stall_timeout: None,
        }
    }
}

/// Counters of a link, shared between its thread and the app.
#[derive(Debug, Default)]
struct Shared {
    connected: AtomicBool,
    generation: AtomicU64,
    connects: AtomicU64,
    disconnects: AtomicU64,
    open_failures: AtomicU64,
    rx_bytes: AtomicU64,
    tx_bytes: AtomicU64,
    rx_dropped_bytes: AtomicU64,
    tx_dropped: AtomicU64,
    write_timeouts: AtomicU64,
    stalls: AtomicU64,
    stop: AtomicBool,
    last_error: Mutex<String>,
    /// An eventfd the app writes to when it queues bytes, so the thread wakes at once.
    wake: Option<OwnedFd>,
}

impl Shared {
    fn wake(&self) {
        if let Some(w) = &self.wake {
            let one: u64 = 1;
            // SAFETY: writing 8 bytes from a local to an eventfd we own.
            unsafe {
                libc::write(w.as_raw_fd(), (&raw const one).cast(), 8);
            }
        }
    }

    fn drain_wake(&self) {
        if let Some(w) = &self.wake {
            let mut v: u64 = 0;
            // SAFETY: reading 8 bytes into a local from a non-blocking eventfd we own.
            unsafe {
                libc::read(w.as_raw_fd(), (&raw mut v).cast(), 8);
            }
        }
    }
}

/// A non-blocking eventfd, or none (the thread then notices sends at its poll interval).
fn eventfd() -> Option<OwnedFd> {
    // SAFETY: plain flags; a negative result is handled.
    let fd = unsafe { libc::eventfd(0, libc::EFD_NONBLOCK | libc::EFD_CLOEXEC) };
    // SAFETY: a fresh fd we own.
    (fd >= 0).then(|| unsafe { OwnedFd::from_raw_fd(fd) })
}

/// A snapshot of a link's counters.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct LinkCounters {
    /// The link is open now.
    pub connected: bool,
    /// The current (or last) connection's number, from 1; 0 before the first.
    pub generation: u64,
    /// Connections made.
    pub connects: u64,
    /// Connections lost (closed by the peer, an error, a stall).
    pub disconnects: u64,
    /// Attempts to open that failed.
    pub open_failures: u64,
    /// Bytes read from the device.
    pub rx_bytes: u64,
    /// Bytes written to the device.
    pub tx_bytes: u64,
    /// Bytes read but dropped because the app's channel was full.
    pub rx_dropped_bytes: u64,
    /// Commands dropped: the send channel full, the link down, or a write timed out.
    pub tx_dropped: u64,
    /// Writes that did not complete within the write timeout (a peer not reading; also
    /// counted in `tx_dropped`).
    pub write_timeouts: u64,
    /// Connections closed because nothing arrived for the stall timeout.
    pub stalls: u64,
    /// The last error seen (open, read or write), empty if none.
    pub last_error: String,
}

/// What the app receives from a link.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Chunk {
    /// The connection the bytes came on.
    pub generation: u64,
    /// The bytes.
    pub bytes: Vec<u8>,
}

/// A running link: its thread, its channels and its counters. Dropping it stops the thread
/// (within one poll interval or one connection attempt).
pub struct Link {
    rx: Receiver<Chunk>,
    pending: Option<Chunk>,
    tx: SyncSender<Vec<u8>>,
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
    endpoint: Endpoint,
}

impl Link {
    /// Starts the link's thread; it connects at once and keeps reconnecting.
    pub fn open(cfg: LinkConfig) -> io::Result<Link> {
        let (rx_tx, rx) = sync_channel(cfg.rx_capacity.max(1));
        let (tx, tx_rx) = sync_channel(cfg.tx_capacity.max(1));
        let shared = Arc::new(Shared {
            wake: eventfd(),
            ..Shared::default()
        });
        let endpoint = cfg.endpoint.clone();
        let s = Arc::clone(&shared);
        let thread = std::thread::Builder::new()
            .name(format!("link {endpoint}"))
            .spawn(move || run(&cfg, &s, &rx_tx, &tx_rx))?;
        Ok(Link {
            rx,
            pending: None,
            tx,
            shared,
            thread: Some(thread),
            endpoint,
        })
    }

    /// Where the link connects.
    pub fn endpoint(&self) -> &Endpoint {
        &self.endpoint
    }

    /// The next chunk received, if one is waiting (never blocks).
    pub fn poll(&mut self) -> Option<Chunk> {
        self.pending.take().or_else(|| self.rx.try_recv().ok())
    }

    /// True when no received chunk is waiting (the last bytes of a closed connection are
    /// taken before its close is acted on).
    pub fn poll_is_empty(&mut self) -> bool {
        if self.pending.is_none() {
            self.pending = self.rx.try_recv().ok();
        }
        self.pending.is_none()
    }

    /// Queues `bytes` for the device (never blocks): false, and counted, when the queue is
    /// full or the link thread is gone.
    pub fn send(&self, bytes: Vec<u8>) -> bool {
        match self.tx.try_send(bytes) {
            Ok(()) => {
                self.shared.wake();
                true
            }
            Err(TrySendError::Full(_) | TrySendError::Disconnected(_)) => {
                self.shared.tx_dropped.fetch_add(1, Ordering::Relaxed);
                false
            }
        }
    }

    /// Counts a command the app dropped itself (the link was down).
    pub fn send_dropped(&self) {
        self.shared.tx_dropped.fetch_add(1, Ordering::Relaxed);
    }

    /// The link is open now.
    pub fn connected(&self) -> bool {
        self.shared.connected.load(Ordering::Acquire)
    }

    /// The current connection's number (0 before the first).
    pub fn generation(&self) -> u64 {
        self.shared.generation.load(Ordering::Acquire)
    }

    /// A snapshot of the counters.
    pub fn counters(&self) -> LinkCounters {
        let s = &self.shared;
        let l = |a: &AtomicU64| a.load(Ordering::Relaxed);
        LinkCounters {
            connected: s.connected.load(Ordering::Acquire),
            generation: s.generation.load(Ordering::Acquire),
            connects: l(&s.connects),
            disconnects: l(&s.disconnects),
            open_failures: l(&s.open_failures),
            rx_bytes: l(&s.rx_bytes),
            tx_bytes: l(&s.tx_bytes),
            rx_dropped_bytes: l(&s.rx_dropped_bytes),
            tx_dropped: l(&s.tx_dropped),
            write_timeouts: l(&s.write_timeouts),
            stalls: l(&s.stalls),
            last_error: s.last_error.lock().map(|e| e.clone()).unwrap_or_default(),
        }
    }
}

impl Drop for Link {
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Release);
        self.shared.wake();
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

/// An open connection.
enum Conn {
    Tcp(TcpStream),
    Serial(std::fs::File),
}

fn set_error(s: &Shared, e: impl std::fmt::Display) {
    if let Ok(mut l) = s.last_error.lock() {
        *l = e.to_string();
    }
}

/// Sleeps `d` in slices, returning early (true) when told to stop.
fn sleep_or_stop(s: &Shared, d: Duration) -> bool {
    let end = Instant::now() + d;
    loop {
        if s.stop.load(Ordering::Acquire) {
            return true;
        }
        let now = Instant::now();
        if now >= end {
            return false;
        }
        std::thread::sleep((end - now).min(Duration::from_millis(20)));
    }
}

fn run(cfg: &LinkConfig, s: &Shared, rx_tx: &SyncSender<Chunk>, tx_rx: &Receiver<Vec<u8>>) {
    let mut backoff = cfg.backoff_min;
    while !s.stop.load(Ordering::Acquire) {
        let conn = match open(cfg) {
            Ok(c) => c,
            Err(e) => {
                s.open_failures.fetch_add(1, Ordering::Relaxed);
                set_error(s, format!("open {}: {e}", cfg.endpoint));
                // Commands for a device that is not there are stale by the time it is.
                while tx_rx.try_recv().is_ok() {
                    s.tx_dropped.fetch_add(1, Ordering::Relaxed);
                }
                if sleep_or_stop(s, backoff) {
                    return;
                }
                backoff = (backoff * 2).min(cfg.backoff_max);
                continue;
            }
        };
        backoff = cfg.backoff_min;
        let generation = s.generation.fetch_add(1, Ordering::AcqRel) + 1;
        s.connects.fetch_add(1, Ordering::Relaxed);
        s.connected.store(true, Ordering::Release);
        let why = serve(cfg, s, conn, generation, rx_tx, tx_rx);
        s.connected.store(false, Ordering::Release);
        if let Some(why) = why {
            s.disconnects.fetch_add(1, Ordering::Relaxed);
            set_error(s, why);
            if sleep_or_stop(s, backoff) {
                return;
            }
            backoff = (backoff * 2).min(cfg.backoff_max);
        }
    }
}

/// Serves one connection until it fails (the reason) or the link stops (`None`).
fn serve(
    cfg: &LinkConfig,
    s: &Shared,
    mut conn: Conn,
    generation: u64,
    rx_tx: &SyncSender<Chunk>,
    tx_rx: &Receiver<Vec<u8>>,
) -> Option<String> {
    let mut buf = vec![0u8; 4096];
    let mut last_rx = Instant::now();
    loop {
        if s.stop.load(Ordering::Acquire) {
            return None;
        }
        while let Ok(cmd) = tx_rx.try_recv() {
            match write_all(&mut conn, &cmd, cfg.write_timeout) {
                Ok(()) => {
                    s.tx_bytes.fetch_add(cmd.len() as u64, Ordering::Relaxed);
                }
                Err(e) if e.kind() == io::ErrorKind::TimedOut => {
                    s.tx_dropped.fetch_add(1, Ordering::Relaxed);
                    s.write_timeouts.fetch_add(1, Ordering::Relaxed);
                    set_error(s, "write timed out (the peer is not reading)");
                }
                Err(e) => return Some(format!("write: {e}")),
            }
        }
        match read(&mut conn, &mut buf, cfg.poll_interval, s) {
            Ok(0) => return Some("closed by the peer".into()),
            Ok(n) => {
                last_rx = Instant::now();
                s.rx_bytes.fetch_add(n as u64, Ordering::Relaxed);
                let chunk = Chunk {
                    generation,
                    bytes: buf[..n].to_vec(),
                };
                if rx_tx.try_send(chunk).is_err() {
                    s.rx_dropped_bytes.fetch_add(n as u64, Ordering::Relaxed);
                }
            }
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::WouldBlock | io::ErrorKind::TimedOut
                ) =>
            {
                if let Some(t) = cfg.stall_timeout
                    && last_rx.elapsed() >= t
                {
                    s.stalls.fetch_add(1, Ordering::Relaxed);
                    return Some(format!("nothing received for {:.1} s", t.as_secs_f64()));
                }
            }
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Some(format!("read: {e}")),
        }
    }
}

fn open(cfg: &LinkConfig) -> io::Result<Conn> {
    match &cfg.endpoint {
        Endpoint::Tcp { host, port } => {
            let mut last = io::Error::new(io::ErrorKind::NotFound, "no address");
            for addr in (host.as_str(), *port).to_socket_addrs()? {
                match TcpStream::connect_timeout(&addr, Duration::from_secs(2)) {
                    Ok(t) => {
                        t.set_nodelay(true)?;
                        t.set_nonblocking(true)?;
                        return Ok(Conn::Tcp(t));
                    }
                    Err(e) => last = e,
                }
            }
            Err(last)
        }
        Endpoint::Serial { path, baud } => open_serial(path, *baud).map(Conn::Serial),
    }
}

/// The termios speed constant of a baud rate.
fn speed(baud: u32) -> io::Result<libc::speed_t> {
    Ok(match baud {
        1200 => libc::B1200,
        2400 => libc::B2400,
        4800 => libc::B4800,
        9600 => libc::B9600,
        19200 => libc::B19200,
        38400 => libc::B38400,
        57600 => libc::B57600,
        115_200 => libc::B115200,
        230_400 => libc::B230400,
        460_800 => libc::B460800,
        921_600 => libc::B921600,
        _ => {
            return Err(io::Error::new(
                io::ErrorKind::InvalidInput,
                format!("unsupported baud rate {baud}"),
            ));
        }
    })
}

/// True when `baud` is a rate the serial link can set.
pub fn baud_supported(baud: u32) -> bool {
    speed(baud).is_ok()
}

fn cvt(r: libc::c_int) -> io::Result<libc::c_int> {
    if r < 0 {
        Err(io::Error::last_os_error())
    } else {
        Ok(r)
    }
}

/// Opens a tty non-blocking in raw 8N1 at `baud`.
fn open_serial(path: &std::path::Path, baud: u32) -> io::Result<std::fs::File> {
    use std::os::unix::ffi::OsStrExt;
    let sp = speed(baud)?;
    let c = std::ffi::CString::new(path.as_os_str().as_bytes())
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "NUL in the path"))?;
    // SAFETY: `c` is a valid NUL-terminated path; the flags are plain constants.
    let fd = cvt(unsafe {
        libc::open(
            c.as_ptr(),
            libc::O_RDWR | libc::O_NOCTTY | libc::O_NONBLOCK | libc::O_CLOEXEC,
        )
    })?;
    // SAFETY: `fd` was just opened and is owned by nobody else.
    let owned = unsafe { OwnedFd::from_raw_fd(fd) };
    // SAFETY: termios is plain data; tcgetattr fills it for an open fd.
    let mut t: libc::termios = unsafe { std::mem::zeroed() };
    // SAFETY: `fd` is open; `t` is a valid termios to fill or read.
    unsafe {
        cvt(libc::tcgetattr(fd, &mut t))?;
        libc::cfmakeraw(&mut t);
        t.c_cflag |= libc::CLOCAL | libc::CREAD;
        t.c_cflag &= !(libc::CSTOPB | libc::PARENB | libc::CRTSCTS);
        t.c_iflag &= !(libc::IXON | libc::IXOFF | libc::IXANY);
        cvt(libc::cfsetispeed(&mut t, sp))?;
        cvt(libc::cfsetospeed(&mut t, sp))?;
        cvt(libc::tcsetattr(fd, libc::TCSANOW, &t))?;
    }
    Ok(std::fs::File::from(owned))
}

/// Waits up to `timeout` for `events` on `fd`: true when ready (or hung up: the next write
/// reports it).
fn wait_fd(fd: libc::c_int, events: libc::c_short, timeout: Duration) -> io::Result<bool> {
    let mut p = libc::pollfd {
        fd,
        events,
        revents: 0,
    };
    let ms = timeout.as_millis().min(i32::MAX as u128) as libc::c_int;
    // SAFETY: one valid pollfd.
    let r = unsafe { libc::poll(&mut p, 1, ms) };
    if r < 0 {
        let e = io::Error::last_os_error();
        return if e.kind() == io::ErrorKind::Interrupted {
            Ok(false)
        } else {
            Err(e)
        };
    }
    Ok(r > 0)
}

impl Conn {
    fn fd(&self) -> libc::c_int {
        match self {
            Conn::Tcp(t) => t.as_raw_fd(),
            Conn::Serial(f) => f.as_raw_fd(),
        }
    }
}

/// Waits up to `timeout` for bytes on the connection or a wake-up from the app; reads what
/// is there (`WouldBlock` when nothing is).
fn read(conn: &mut Conn, buf: &mut [u8], timeout: Duration, s: &Shared) -> io::Result<usize> {
    let mut fds = [
        libc::pollfd {
            fd: conn.fd(),
            events: libc::POLLIN,
            revents: 0,
        },
        libc::pollfd {
            fd: s.wake.as_ref().map_or(-1, AsRawFd::as_raw_fd),
            events: libc::POLLIN,
            revents: 0,
        },
    ];
    let ms = timeout.as_millis().min(i32::MAX as u128) as libc::c_int;
    // SAFETY: two valid pollfds (a negative fd is ignored by poll).
    let r = unsafe { libc::poll(fds.as_mut_ptr(), 2, ms) };
    if r < 0 {
        return Err(io::Error::last_os_error());
    }
    if fds[1].revents != 0 {
        s.drain_wake();
    }
    if fds[0].revents == 0 {
        return Err(io::ErrorKind::WouldBlock.into());
    }
    let r = match conn {
        Conn::Tcp(t) => t.read(buf),
        Conn::Serial(f) => f.read(buf),
    };
    match r {
        // A pty whose other side closed reads EIO: the device is gone.
        Err(e) if e.raw_os_error() == Some(libc::EIO) => Ok(0),
        r => r,
    }
}

fn write_all(conn: &mut Conn, mut data: &[u8], timeout: Duration) -> io::Result<()> {
    let end = Instant::now() + timeout;
    while !data.is_empty() {
        let left = end.saturating_duration_since(Instant::now());
        if !wait_fd(conn.fd(), libc::POLLOUT, left)? {
            return Err(io::ErrorKind::TimedOut.into());
        }
        let r = match conn {
            Conn::Tcp(t) => t.write(data),
            Conn::Serial(f) => f.write(data),
        };
        match r {
            Ok(0) => return Err(io::ErrorKind::WriteZero.into()),
            Ok(n) => data = &data[n..],
            Err(e)
                if matches!(
                    e.kind(),
                    io::ErrorKind::WouldBlock | io::ErrorKind::Interrupted
                ) => {}
            Err(e) => return Err(e),
        }
    }
    Ok(())
}
