//! The CougUV's device drivers (issue #15, point 1): `iGPS`, `iDVL`, `iSeaTrac` and `iTeensy`.
//!
//! Each driver is two parts:
//!
//! - a pure protocol state machine ([`Protocol`]: [`gps::Gps`], [`dvl::Dvl`],
//!   [`seatrac::SeaTrac`], [`teensy::Teensy`]) over the codecs of the `devices` crate: bytes in
//!   give MOOS posts out, MOOS mail in gives bytes out, the start-up sequence is a state,
//!   timeouts and retries run on the `now` it is given (it never reads a clock), and every
//!   piece of garbage, bad checksum, oversize line and parse error is counted
//!   ([`devices::line::LinkStats`]);
//! - the one I/O edge all four share ([`link::Link`]): a serial port (or pseudo-terminal) or a
//!   TCP client on its own thread, reconnecting with backoff, exchanging bytes with the app
//!   through bounded channels, so a stalled device or a full channel drops and counts and never
//!   blocks the MOOS side.
//!
//! [`fuzz`] is the state machines' fuzz body (any bytes at any times: no panic, the counters
//! add up), for `tests/fuzz.rs` on stable and the cargo-fuzz target `drivers`.
//!
//! The commands' retry rule (an answer awaited for a time, so many tries, a busy answer
//! holding a command back) is one helper, [`retry::Tries`], for iDVL and iSeaTrac.
//!
//! [`Driver`] joins the two: the runtime's app (`runtime::driver_apps`, registered in
//! `runtime::antler::BUILT_INS`) calls [`Driver::step`] once per iteration.
//!
//! The drivers post the variables of the sensor models (`runtime::sensors`, uSimSensors),
//! with the same names, units and frames, so the navigator cannot tell hardware from
//! simulation. Each module's docs have its table of variables and parameters.
//!
//! # Variables every driver posts
//!
//! | variable | type | meaning |
//! |---|---|---|
//! | `<DEV>_DRIVER_STATUS` | string | every `status_period` (1 s) and at each connect/disconnect: `link=up\|down,state=...,connects=..,disconnects=..,open_failures=..,stalls=..,rx_bytes=..,tx_bytes=..,rx_dropped_bytes=..,tx_dropped=..,lines=..,garbage_bytes=..,oversize=..,bad_checksum=..,parse_errors=..` and the driver's own counters (`<DEV>` is `GPS`, `DVL`, `SEATRAC`, `TEENSY`: `<APP>_STATUS` is CMOOSApp's) |
//!
//! # Parameters every driver reads
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `device` | (driver's) | serial device path (a udev link or a pty works) |
//! | `baud` | (driver's) | serial baud rate |
//! | `host`, `port` | (driver's) | the TCP server (iDVL; iGPS through gpsd) |
//! | `reconnect_min`, `reconnect_max` | 0.2, 5 | s, the backoff between attempts to reopen the link (doubling) |
//! | `stall_timeout` | 0 (iDVL: 5) | s, reopen the link when nothing arrived for so long; 0: never |
//! | `status_period` | 1 | s, between `<DEV>_DRIVER_STATUS` posts |

#![warn(missing_docs)]

pub mod dvl;
pub mod fuzz;
pub mod gps;
pub mod link;
pub mod params;
pub mod retry;
pub mod seatrac;
pub mod teensy;

use std::fmt::Write as _;

use devices::line::LinkStats;
use moos_types::{Post, Value};

use link::{Link, LinkConfig, LinkCounters};

/// What a protocol step produced: posts for the MOOSDB, bytes for the device, and notes for
/// the appcast.
#[derive(Debug, Default)]
pub struct Io {
    /// Posts, in order; all at the step's `now`.
    pub posts: Vec<Post>,
    /// Byte strings for the device, in order.
    pub tx: Vec<Vec<u8>>,
    /// Appcast events (a command answered, a start-up step done).
    pub events: Vec<String>,
    /// Appcast run warnings (a command refused, a calibration failed).
    pub warnings: Vec<String>,
}

impl Io {
    /// A double post.
    pub fn double(&mut self, key: &'static str, v: f64) {
        self.posts.push(Post::double(key, v));
    }

    /// A string post.
    pub fn text(&mut self, key: &'static str, v: impl Into<String>) {
        self.posts.push(Post::text(key, v.into()));
    }

    /// Bytes for the device.
    pub fn send(&mut self, bytes: impl Into<Vec<u8>>) {
        self.tx.push(bytes.into());
    }

    /// The numbers posted to `key`, in order.
    pub fn doubles(&self, key: &str) -> Vec<f64> {
        self.posts
            .iter()
            .filter(|p| &*p.key == key)
            .filter_map(|p| p.value.as_f64())
            .collect()
    }

    /// The strings posted to `key`, in order.
    pub fn texts(&self, key: &str) -> Vec<String> {
        self.posts
            .iter()
            .filter(|p| &*p.key == key)
            .filter_map(|p| p.value.as_str().map(str::to_string))
            .collect()
    }
}

/// A device protocol as a pure state machine: it reads no clock and does no I/O.
pub trait Protocol: Send {
    /// The MOOS program name (`iGPS`).
    fn program(&self) -> &'static str;

    /// The status variable (`GPS_DRIVER_STATUS`).
    fn status_var(&self) -> &'static str;

    /// The MOOS variables the driver reads.
    fn subscriptions(&self) -> Vec<String> {
        Vec::new()
    }

    /// A new connection to the device: drop any partial line, start the start-up sequence.
    fn on_connect(&mut self, now: f64, io: &mut Io);

    /// The connection was lost.
    fn on_disconnect(&mut self, _now: f64, _io: &mut Io) {}

    /// Bytes from the device.
    fn on_bytes(&mut self, data: &[u8], now: f64, io: &mut Io);

    /// A MOOS mail.
    fn on_mail(&mut self, _key: &str, _value: &Value, _now: f64, _io: &mut Io) {}

    /// Once per iteration, after the bytes and mail: timeouts, retries, periodic commands.
    fn tick(&mut self, _now: f64, _io: &mut Io) {}

    /// The protocol's counters.
    fn stats(&self) -> LinkStats;

    /// The start-up state (`running` once started).
    fn state(&self) -> &'static str;

    /// Driver-specific `key=value` pairs for the status post (each preceded by a comma).
    fn status_extra(&self, _out: &mut String) {}

    /// Lines for the appcast body (the latest values).
    fn report(&self, out: &mut String);
}

/// A protocol and its link: what a driver app steps once per iteration.
pub struct Driver<P> {
    /// The protocol.
    pub protocol: P,
    link_cfg: LinkConfig,
    link: Option<Link>,
    generation: u64,
    connected: bool,
    status_period: f64,
    last_status: Option<f64>,
    max_chunks: usize,
}

impl<P: Protocol> Driver<P> {
    /// A driver for `protocol` over the link `link_cfg` (not opened yet), posting its status
    /// every `status_period` seconds.
    pub fn new(protocol: P, link_cfg: LinkConfig, status_period: f64) -> Self {
        Driver {
            protocol,
            link_cfg,
            link: None,
            generation: 0,
            connected: false,
            status_period,
            last_status: None,
            max_chunks: 4096,
        }
    }

    /// Opens the link (starts its thread); the app's start-up.
    pub fn start(&mut self) -> std::io::Result<()> {
        if self.link.is_none() {
            self.link = Some(Link::open(self.link_cfg.clone())?);
        }
        Ok(())
    }

    /// Closes the link (joins its thread); the app's end.
    pub fn stop(&mut self) {
        self.link = None;
        self.connected = false;
    }

    /// The link's settings.
    pub fn link_config(&self) -> &LinkConfig {
        &self.link_cfg
    }

    /// The link's counters (zero before [`Driver::start`]).
    pub fn counters(&self) -> LinkCounters {
        self.link.as_ref().map(Link::counters).unwrap_or_default()
    }

    /// Hands a mail to the protocol; its bytes go to the device.
    pub fn on_mail(&mut self, key: &str, value: &Value, now: f64, io: &mut Io) {
        self.protocol.on_mail(key, value, now, io);
        self.flush(io);
    }

    /// One iteration at `now`: takes the bytes that arrived (never waits), tells the protocol
    /// of a new or lost connection, ticks it, sends its bytes and posts the status when due.
    pub fn step(&mut self, now: f64, io: &mut Io) {
        let mut changed = false;
        if let Some(mut link) = self.link.take() {
            // Bytes come in the order the thread read them: a newer connection's first bytes
            // say it is up; a closed connection's last bytes are still read before its close.
            for _ in 0..self.max_chunks {
                let Some(c) = link.poll() else { break };
                if c.generation < self.generation {
                    continue;
                }
                if c.generation > self.generation {
                    changed |= self.connect(c.generation, now, io);
                }
                self.protocol.on_bytes(&c.bytes, now, io);
            }
            let up = link.connected();
            let generation = link.generation();
            if up && generation > self.generation {
                changed |= self.connect(generation, now, io);
            } else if !up && self.connected && link.poll_is_empty() {
                self.connected = false;
                self.protocol.on_disconnect(now, io);
                changed = true;
            }
            self.link = Some(link);
        }
        self.protocol.tick(now, io);
        self.flush(io);
        let due = self
            .last_status
            .is_none_or(|t| now - t >= self.status_period - 1e-9);
        if changed || due {
            self.last_status = Some(now);
            let s = self.status();
            io.posts.push(Post::text(self.protocol.status_var(), s));
        }
    }

    /// The connection `generation` is up: the previous one (if the protocol still had it) is
    /// closed first. Returns true (a change).
    fn connect(&mut self, generation: u64, now: f64, io: &mut Io) -> bool {
        if self.connected {
            self.protocol.on_disconnect(now, io);
        }
        self.generation = generation;
        self.connected = true;
        self.protocol.on_connect(now, io);
        true
    }

    fn flush(&mut self, io: &mut Io) {
        match &self.link {
            Some(link) if self.connected => {
                for b in io.tx.drain(..) {
                    link.send(b);
                }
            }
            // Bytes for a device that is not there are dropped (the start-up sequence runs
            // again at the next connection); the link counts them.
            Some(link) => {
                for _ in io.tx.drain(..) {
                    link.send_dropped();
                }
            }
            None => io.tx.clear(),
        }
    }

    /// The status text (`<DEV>_DRIVER_STATUS`).
    pub fn status(&self) -> String {
        let c = self.counters();
        let st = self.protocol.stats();
        let mut s = format!(
            "link={},state={}",
            if self.connected { "up" } else { "down" },
            self.protocol.state()
        );
        let _ = write!(
            s,
            ",connects={},disconnects={},open_failures={},stalls={},rx_bytes={},tx_bytes={},\
             rx_dropped_bytes={},tx_dropped={},lines={},garbage_bytes={},oversize={},\
             bad_checksum={},parse_errors={}",
            c.connects,
            c.disconnects,
            c.open_failures,
            c.stalls,
            c.rx_bytes,
            c.tx_bytes,
            c.rx_dropped_bytes,
            c.tx_dropped,
            st.lines,
            st.garbage_bytes,
            st.oversize,
            st.bad_checksum,
            st.parse_errors
        );
        self.protocol.status_extra(&mut s);
        s
    }

    /// The appcast body: the link, the counters and the protocol's report.
    pub fn report(&self, out: &mut String) {
        let c = self.counters();
        let st = self.protocol.stats();
        let _ = writeln!(
            out,
            "Link: {} ({})   state: {}",
            self.link_cfg.endpoint,
            if self.connected { "up" } else { "down" },
            self.protocol.state()
        );
        if !c.last_error.is_empty() {
            let _ = writeln!(out, "Last error: {}", c.last_error);
        }
        let _ = writeln!(out);
        let _ = writeln!(
            out,
            "Connects  Disconnects  OpenFail  Stalls  RxBytes  TxBytes  RxDropped  TxDropped"
        );
        let _ = writeln!(
            out,
            "--------  -----------  --------  ------  -------  -------  ---------  ---------"
        );
        let _ = writeln!(
            out,
            "{:<8}  {:<11}  {:<8}  {:<6}  {:<7}  {:<7}  {:<9}  {}",
            c.connects,
            c.disconnects,
            c.open_failures,
            c.stalls,
            c.rx_bytes,
            c.tx_bytes,
            c.rx_dropped_bytes,
            c.tx_dropped
        );
        let _ = writeln!(out);
        let _ = writeln!(out, "Lines  Garbage  Oversize  BadChecksum  ParseErrors");
        let _ = writeln!(out, "-----  -------  --------  -----------  -----------");
        let _ = writeln!(
            out,
            "{:<5}  {:<7}  {:<8}  {:<11}  {}",
            st.lines, st.garbage_bytes, st.oversize, st.bad_checksum, st.parse_errors
        );
        let _ = writeln!(out);
        self.protocol.report(out);
    }
}

/// Formats a float for a status pair: up to 6 significant digits, as MOOS's `%g`.
pub(crate) fn g(v: f64) -> String {
    let mut s = String::new();
    moos_types::fmt::g(&mut s, v, 6);
    s
}
