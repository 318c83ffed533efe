//! pShare: the UDP bridge between MOOS communities (issue #16, point 5), wire-compatible with
//! MOOS's C++ `pShare`: each shared message goes out as one datagram holding one serialised
//! `CMOOSMsg`, renamed to its route's destination name ([`pshare::datagram`]); what arrives
//! on an input route is posted into this community with its source, source aux, community
//! and time kept, as the C++ app posts it (`Post(msg, true)`, and the DB keeps a non-empty
//! originating community).
//!
//! The configuration, routing and datagram rules are the pure `pshare` crate; this module is
//! the app and its I/O edge: std UDP sockets in non-blocking mode, opened at start-up (never
//! while a mission is only checked), read until empty at each iteration (receiving never
//! blocks the iteration), written from the mail handler.
//!
//! # Conformance with MOOS's pShare
//!
//! | parameter / posting | coug |
//! |---|---|
//! | `output` long form (`src_name`, `dest_name`, `route` with `&`, `frequency`, `duration`, `max_shares`) | done |
//! | `output` short form (`X->[Y:]host:port[@Hz] & [Z:]multicast_N`) | done |
//! | `input = route = A & B`, `white_list = P & Q` | done (unicast) |
//! | wildcard shares `var_pattern[:app_pattern]`, prefix renaming, caret `^` | done |
//! | `multicast_N` routes, `multicast_address`, `multicast_base_port` | read and listed; open: coug opens no multicast socket (a warning says so) |
//! | `PSHARE_CMD` (`<NAME>_CMD`): `cmd=output,...` / `cmd=input,...`, older than start-up ignored | done |
//! | `duration = 0` restated: the latest value once (re-registration) | done |
//! | `PSHARE_OUTPUT_SUMMARY`, `PSHARE_INPUT_SUMMARY` once a second | done |
//! | loop guard: a received name pShare registers for is not posted | done |
//! | 48 KiB limit on sent messages | done |
//! | `listen_address` (coug only; default `0.0.0.0`, every interface, as pShare binds) | the address listeners and the sender bind to; tests use `127.0.0.1` |
//! | an input port of 0 (coug only) | the system picks the port; [`PShareApp::listening`] reads it back |
//! | command line `-o`/`-i` | open: the single-app mode reads the mission block only |
//! | `radio_max_depth` (coug only; default: none, no gate, as pShare) | the surface-only radio: see below |
//! | `radio_store`, `radio_store_max` (coug only; default `off`, 100) | store and forward on the surface-only radio: see below |
//!
//! # The surface-only radio
//!
//! Underwater a vehicle talks only through its acoustic modem (pAcomms); its radio or Wi-Fi
//! link works at the surface only. MOOS-IvP models no such thing: pShare shares whatever the
//! depth, and uFldNodeComms (the simulated inter-vehicle link) gates messages by range and
//! frequency, never by depth. In coug the bridge of a vehicle sets `radio_max_depth = M`
//! (metres) to gate itself on its own `NAV_DEPTH` ([`pshare::RadioGate`]): while the latest
//! `NAV_DEPTH` is deeper than `M`, nothing is sent (counted as `submerged` in
//! [`TxCounts`]) and every datagram that arrives, in process or over UDP, is read and dropped
//! (counted in [`pshare::RxCounts::submerged`]). By default a radio does not store and
//! forward: nothing of the dive is queued and replayed on surfacing. Before any `NAV_DEPTH`
//! the link is up. Without the parameter (the default, and the shoreside's case) the bridge
//! is always up, so every MOOS-IvP mission runs unchanged. The gate applies to the
//! in-process route of a fleet run and to UDP alike, in lockstep and in real time.
//!
//! ## Store and forward
//!
//! A vehicle's bridge may keep what it would have sent while submerged and send it when it
//! surfaces, as a vehicle whose software queues its reports for the next radio contact:
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `radio_store` | `off` | `off`: what the dive would have sent is dropped (counted `submerged`); `latest`: the latest value of each variable is kept (an older one is `superseded`); `all`: every message is kept, in order |
//! | `radio_store_max` | 100 | the most messages kept (`all`) or variables kept (`latest`); past it the oldest is dropped and counted (`overflow`) |
//!
//! On surfacing (the first `NAV_DEPTH` at most `radio_max_depth` after a deeper one), the
//! kept messages go out, oldest first, before any mail delivered after that `NAV_DEPTH`,
//! through the routes as they are then (so a route's `frequency` or `max_shares` still
//! applies, and a route added during the dive carries them too); each keeps its writer's
//! time, source and community, so the shoreside logs when it was written. Only the sending
//! side stores: what arrives while submerged is still dropped (the other side's radio has
//! nobody to talk to). The counts (`stored`, `forwarded`, `superseded`, `overflow` and
//! the number queued) are in the appcast and [`PShareApp::store_counts`]; `radio_store`
//! without `radio_max_depth` has no effect (a warning says so).
//!
//! # The in-process route (a fleet run)
//!
//! When `coug run` runs several communities in one process in lockstep, their pShares meet
//! through a [`PShareHub`] in the run's [`Shared`] (named [`HUB`]): every input route on a
//! UDP port is registered there when the app is built (no socket is opened for it), and an
//! output whose `host:port` is a registered input (the host a loopback name or address, or
//! the input's own host) is handed to that input's [`Inbox`] instead of a socket. The bytes
//! are the very datagram UDP would carry (same renaming, same 48 KiB limit), read back by the
//! same code (white list, loop guard, relayed posting); a datagram sent at MOOS time `t` is
//! read by the receiver's first iteration after `t`, so the delivery does not depend on the
//! order the communities are stepped in. Outputs to any other address go over UDP as usual.
//! A single mission has no hub, and every route is UDP.
//!
//! Bad lines are warnings (`mission::Diagnostic`, kind `AppSetting`, at their line) and the
//! rest of the block is kept; the C++ app prints an error and skips the block's later lines.
//! Datagrams that are not one notify message are counted per input and dropped.

use std::collections::{HashMap, VecDeque};
use std::fmt::Write as _;
use std::io::ErrorKind;
use std::net::{Ipv4Addr, SocketAddr, SocketAddrV4, ToSocketAddrs, UdpSocket};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, PoisonError};

use bytes::Bytes;
use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::ProcessConfig;
use moos_types::{ByteString, Relayed};
use moosdb::Message;
use pshare::config::{Command, Endpoint, InputSpec, OutputSpec, parse_command};
use pshare::datagram::{self, RECEIVE_BUFFER, RxCounts};
use pshare::{Added, Config, RadioGate, RouteTable};

use crate::antler::BuiltInApp;
use crate::app::{App, AppResult, Mail, Post, Subscription};
use crate::appcasting::{AppcastLayer, Note};
use crate::shared::Shared;

/// The MOOS name of the app.
pub const PROGRAM: &str = "pShare";

/// Most datagrams read from one input per iteration (the rest wait for the next one).
const MAX_READS_PER_ITERATION: usize = 4096;

/// Seconds between the summary postings.
const SUMMARY_PERIOD: f64 = 1.0;

/// The depth the surface-only radio follows.
const DEPTH_VAR: &str = "NAV_DEPTH";

/// The name of the in-process hub in a run's [`Shared`] set (see the module docs).
pub const HUB: &str = "pshare";

/// The datagrams waiting for one in-process input route, each with the MOOS time it was
/// sent at and its sender's number.
#[derive(Debug, Default)]
pub struct Inbox {
    queue: Mutex<VecDeque<(f64, u64, Bytes)>>,
}

impl Inbox {
    fn push(&self, sent: f64, sender: u64, datagram: Bytes) {
        self.queue
            .lock()
            .unwrap_or_else(PoisonError::into_inner)
            .push_back((sent, sender, datagram));
    }

    /// Moves the datagrams sent strictly before `now` into `out`, oldest first, and those
    /// of one instant by sender number (the order the senders were built in, so the order
    /// one thread stepping the communities in fleet order pushes them; several threads push
    /// an instant's datagrams in any order).
    fn take_before(&self, now: f64, out: &mut Vec<Bytes>) {
        let mut q = self.queue.lock().unwrap_or_else(PoisonError::into_inner);
        let n = q.iter().take_while(|(t, _, _)| *t < now).count();
        if n == 0 {
            return;
        }
        let taken = q.make_contiguous();
        taken[..n].sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        out.extend(q.drain(..n).map(|(_, _, d)| d));
    }
}

/// The in-process radio between the pShares of one run: their input routes by UDP port.
/// A fleet run puts one in its [`Shared`] set under [`HUB`] before building the apps.
#[derive(Debug, Default)]
pub struct PShareHub {
    inputs: Mutex<HashMap<u16, (String, Arc<Inbox>)>>,
    delivered: AtomicU64,
    /// The number the next pShare to join gets.
    senders: AtomicU64,
}

/// True for a host name that means this machine (`localhost`, `127.x.x.x`, `0.0.0.0`).
fn is_local(host: &str) -> bool {
    host.eq_ignore_ascii_case("localhost") || host.starts_with("127.") || host == "0.0.0.0"
}

impl PShareHub {
    /// An empty hub.
    pub fn new() -> PShareHub {
        PShareHub::default()
    }

    /// Registers an input route on `host:port`; `None` when another input already has the
    /// port (that one keeps it).
    fn listen(&self, host: &str, port: u16) -> Option<Arc<Inbox>> {
        let mut inputs = self.inputs.lock().unwrap_or_else(PoisonError::into_inner);
        if inputs.contains_key(&port) {
            return None;
        }
        let inbox = Arc::new(Inbox::default());
        inputs.insert(port, (host.to_string(), inbox.clone()));
        Some(inbox)
    }

    /// The inbox of the input an output to `host:port` reaches in process, if any.
    fn route(&self, host: &str, port: u16) -> Option<Arc<Inbox>> {
        let inputs = self.inputs.lock().unwrap_or_else(PoisonError::into_inner);
        let (h, inbox) = inputs.get(&port)?;
        (is_local(host) || h.eq_ignore_ascii_case(host)).then(|| inbox.clone())
    }

    /// The UDP ports registered as in-process inputs, in increasing order.
    pub fn ports(&self) -> Vec<u16> {
        let inputs = self.inputs.lock().unwrap_or_else(PoisonError::into_inner);
        let mut p: Vec<u16> = inputs.keys().copied().collect();
        p.sort_unstable();
        p
    }

    /// Datagrams handed over in process so far.
    pub fn delivered(&self) -> u64 {
        self.delivered.load(Ordering::Relaxed)
    }
}

/// One input route and what came in on it.
#[derive(Debug)]
struct Listener {
    endpoint: Endpoint,
    white_list: Vec<String>,
    socket: Option<UdpSocket>,
    /// The in-process route (a fleet run): no socket then.
    inbox: Option<Arc<Inbox>>,
    port: Option<u16>,
    counts: RxCounts,
}

/// What was sent, in all.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TxCounts {
    /// Datagrams sent (over UDP or in process).
    pub sent: u64,
    /// Of them, datagrams handed to another community of the run in process.
    pub in_process: u64,
    /// Messages over the 48 KiB limit, not sent.
    pub too_large: u64,
    /// Shares not sent: a multicast route, an address that did not resolve, a send error.
    pub failed: u64,
    /// Messages not shared because the radio was down (the vehicle submerged, see the
    /// module docs).
    pub submerged: u64,
}

/// What a submerged bridge does with what it would have sent (`radio_store`, see the
/// module docs).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum RadioStore {
    /// Dropped and counted (the default).
    #[default]
    Off,
    /// The latest value of each variable is kept.
    Latest,
    /// Every message is kept, in order.
    All,
}

impl RadioStore {
    /// The parameter's word.
    pub fn as_str(self) -> &'static str {
        match self {
            RadioStore::Off => "off",
            RadioStore::Latest => "latest",
            RadioStore::All => "all",
        }
    }
}

/// The default `radio_store_max`.
pub const DEFAULT_RADIO_STORE_MAX: usize = 100;

/// What the store of a submerged bridge did, in all.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct StoreCounts {
    /// Messages kept while submerged.
    pub stored: u64,
    /// Kept messages sent on surfacing (each through its routes as they were then).
    pub forwarded: u64,
    /// Kept messages replaced by a newer value of their variable (`latest`).
    pub superseded: u64,
    /// Kept messages dropped, the oldest first, because the store was full.
    pub overflow: u64,
}

/// The messages a submerged bridge keeps for its next surfacing.
#[derive(Debug, Default)]
struct Store {
    mode: RadioStore,
    max: usize,
    kept: VecDeque<Mail>,
    counts: StoreCounts,
}

impl Store {
    fn keep(&mut self, m: &Mail) {
        if self.mode == RadioStore::Off {
            return;
        }
        self.counts.stored += 1;
        if self.mode == RadioStore::Latest
            && let Some(i) = self.kept.iter().position(|k| k.key == m.key)
        {
            self.kept.remove(i);
            self.counts.superseded += 1;
        }
        self.kept.push_back(m.clone());
        while self.kept.len() > self.max {
            self.kept.pop_front();
            self.counts.overflow += 1;
        }
    }
}

/// The `pShare` app.
pub struct PShareApp {
    name: String,
    block: ProcessConfig,
    config: Config,
    warnings: Vec<Diagnostic>,
    appcast: AppcastLayer,
    listen_address: Ipv4Addr,
    cmd_key: String,
    radio: RadioGate,
    store: Store,
    table: RouteTable,
    listeners: Vec<Listener>,
    hub: Option<Arc<PShareHub>>,
    /// This pShare's number in the hub (the order of its datagrams within an instant).
    sender_no: u64,
    ready: Vec<Bytes>,
    sender: Option<UdpSocket>,
    resolved: HashMap<Endpoint, Option<SocketAddr>>,
    opened: bool,
    new_subs: Vec<Subscription>,
    start: f64,
    last_summary: Option<f64>,
    tx: TxCounts,
    buf: Vec<u8>,
    out_buf: Vec<u8>,
}

impl BuiltInApp for PShareApp {
    /// Sets the mission's `Community` and `MOOSTimeWarp` for the app's appcasts.
    fn with_appcast_globals(mut self, community: Option<&str>, warp: f64) -> Self {
        self.appcast = AppcastLayer::with_config_warnings(
            &self.name,
            &self.block,
            community,
            warp,
            &self.warnings,
        );
        self
    }

    /// Bad lines of the block and the multicast routes that will not be opened.
    fn warnings(&self) -> &[Diagnostic] {
        &self.warnings
    }
}

impl PShareApp {
    /// The app `name` from its `block`; bad lines are [`PShareApp::warnings`].
    pub fn new(name: &str, block: ProcessConfig) -> Self {
        let (config, bad) = Config::from_params(
            block
                .entries
                .iter()
                .map(|p| (p.span.line as usize, p.key.as_str(), p.value.as_str())),
        );
        let span_of = |line: usize| {
            block
                .entries
                .iter()
                .find(|p| p.span.line as usize == line)
                .map_or(&block.span, |p| &p.span)
        };
        let mut warnings: Vec<Diagnostic> = bad
            .iter()
            .map(|b| {
                Diagnostic::line_warning(
                    DiagnosticKind::AppSetting,
                    span_of(b.line),
                    format!("{PROGRAM}: {} = {}: {}", b.key, b.value, b.error),
                )
            })
            .collect();
        let multicast = config
            .outputs
            .iter()
            .map(|o| &o.endpoint)
            .chain(config.inputs.iter().flat_map(|i| &i.endpoints))
            .any(Endpoint::is_multicast);
        if multicast {
            warnings.push(Diagnostic::line_warning(
                DiagnosticKind::AppSetting,
                &block.span,
                format!(
                    "{PROGRAM}: multicast routes are read but coug opens no multicast socket: \
                     they send and receive nothing"
                ),
            ));
        }
        let mut listen_address = Ipv4Addr::UNSPECIFIED;
        if let Some(p) = block
            .entries
            .iter()
            .find(|p| p.key.trim().eq_ignore_ascii_case("listen_address"))
        {
            match p.value.trim().parse() {
                Ok(a) => listen_address = a,
                Err(_) => warnings.push(Diagnostic::line_warning(
                    DiagnosticKind::AppSetting,
                    &p.span,
                    format!(
                        "{PROGRAM}: listen_address = {}: not an IPv4 address",
                        p.value.trim()
                    ),
                )),
            }
        }
        let store = radio_store(&block, config.radio_max_depth.is_some(), &mut warnings);
        let mut table = RouteTable::default();
        for o in &config.outputs {
            table.add(o, 0.0);
        }
        let listeners = config.inputs.iter().flat_map(listeners_of).collect();
        PShareApp {
            cmd_key: format!("{}_CMD", name.to_ascii_uppercase()),
            radio: RadioGate::new(config.radio_max_depth),
            store,
            appcast: AppcastLayer::with_config_warnings(name, &block, None, 1.0, &warnings),
            name: name.to_string(),
            block,
            config,
            warnings,
            listen_address,
            table,
            listeners,
            hub: None,
            sender_no: 0,
            ready: Vec::new(),
            sender: None,
            resolved: HashMap::new(),
            opened: false,
            new_subs: Vec::new(),
            start: 0.0,
            last_summary: None,
            tx: TxCounts::default(),
            buf: vec![0; RECEIVE_BUFFER],
            out_buf: Vec::new(),
        }
    }

    /// Joins the run's in-process radio when `shared` holds a [`PShareHub`] (a fleet run):
    /// the input routes register there and open no socket (see the module docs). Without a
    /// hub nothing changes.
    pub fn with_shared(mut self, shared: &Shared) -> Self {
        self.hub = shared.get::<PShareHub>(HUB);
        if let Some(hub) = &self.hub {
            self.sender_no = hub.senders.fetch_add(1, Ordering::Relaxed);
        }
        for i in 0..self.listeners.len() {
            self.attach_inbox(i);
        }
        self
    }

    fn attach_inbox(&mut self, i: usize) {
        let Some(hub) = &self.hub else {
            return;
        };
        let l = &mut self.listeners[i];
        let Endpoint::Udp { host, port } = &l.endpoint else {
            return;
        };
        if *port == 0 {
            return;
        }
        l.inbox = hub.listen(host, *port);
        if l.inbox.is_none() {
            let w = format!(
                "another pShare of the run listens on port {port}: {} goes over UDP",
                l.endpoint
            );
            self.appcast.note(Note::Warning(w), self.start);
        }
    }

    /// The configuration read.
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// Opens the sockets (the listeners and the sender); done at start-up, or earlier by a
    /// caller that needs the ports the system picked. Failures are run warnings.
    pub fn open(&mut self) {
        if self.opened {
            return;
        }
        self.opened = true;
        for i in 0..self.listeners.len() {
            self.open_listener(i);
        }
        match UdpSocket::bind(SocketAddrV4::new(self.listen_address, 0))
            .and_then(|s| s.set_nonblocking(true).map(|()| s))
        {
            Ok(s) => self.sender = Some(s),
            Err(e) => self
                .appcast
                .note(Note::Warning(format!("no socket to send from: {e}")), 0.0),
        }
        let endpoints: Vec<Endpoint> = self
            .table
            .named()
            .flat_map(|(_, r)| r.iter().map(|r| r.endpoint.clone()))
            .chain(
                self.table
                    .wildcards()
                    .flat_map(|(_, _, r)| r.iter().map(|r| r.endpoint.clone())),
            )
            .collect();
        for e in endpoints {
            self.resolve(&e);
        }
    }

    fn open_listener(&mut self, i: usize) {
        let l = &mut self.listeners[i];
        let Endpoint::Udp { port, .. } = l.endpoint else {
            return;
        };
        if l.inbox.is_some() {
            l.port = Some(port);
            return;
        }
        let bound = UdpSocket::bind(SocketAddrV4::new(self.listen_address, port))
            .and_then(|s| s.set_nonblocking(true).map(|()| s))
            .and_then(|s| s.local_addr().map(|a| (s, a.port())));
        match bound {
            Ok((s, p)) => {
                l.socket = Some(s);
                l.port = Some(p);
            }
            Err(e) => {
                let w = format!("cannot listen on {}: {e}", l.endpoint);
                self.appcast.note(Note::Warning(w), 0.0);
            }
        }
    }

    fn resolve(&mut self, e: &Endpoint) -> Option<SocketAddr> {
        if let Some(a) = self.resolved.get(e) {
            return *a;
        }
        let addr = match e {
            Endpoint::Udp { host, port } => (host.as_str(), *port)
                .to_socket_addrs()
                .ok()
                .and_then(|mut a| a.find(SocketAddr::is_ipv4)),
            Endpoint::Multicast(_) => None,
        };
        if addr.is_none() && !e.is_multicast() {
            self.appcast
                .note(Note::Warning(format!("cannot resolve {e}")), self.start);
        }
        self.resolved.insert(e.clone(), addr);
        addr
    }

    /// Every input route with the port it listens on (`None`: not open: a multicast
    /// channel, a failed bind, or before [`PShareApp::open`]; an in-process route is open
    /// on its configured port).
    pub fn listening(&self) -> Vec<(Endpoint, Option<u16>)> {
        self.listeners
            .iter()
            .map(|l| (l.endpoint.clone(), l.port))
            .collect()
    }

    /// What came in on each input route.
    pub fn received(&self) -> Vec<(Endpoint, RxCounts)> {
        self.listeners
            .iter()
            .map(|l| (l.endpoint.clone(), l.counts))
            .collect()
    }

    /// What was sent.
    pub fn sent(&self) -> TxCounts {
        self.tx
    }

    /// The store and forward setting (`radio_store`) and its bound (`radio_store_max`).
    pub fn radio_store(&self) -> (RadioStore, usize) {
        (self.store.mode, self.store.max)
    }

    /// What the store did, and how many messages it holds now.
    pub fn store_counts(&self) -> (StoreCounts, usize) {
        (self.store.counts, self.store.kept.len())
    }

    /// The routing table in force.
    pub fn routes(&self) -> &RouteTable {
        &self.table
    }

    fn add_output(&mut self, spec: &OutputSpec, now: f64) {
        match self.table.add(spec, now) {
            Added::Named(v) | Added::Wildcard(v) | Added::ResendLatest(v) => {
                self.new_subs.push(Subscription::var(v));
            }
            Added::Refreshed => {}
        }
        if self.opened {
            self.resolve(&spec.endpoint);
        }
    }

    fn add_input(&mut self, spec: &InputSpec) {
        for l in listeners_of(spec) {
            if self.listeners.iter().any(|o| o.endpoint == l.endpoint) {
                let w = format!("already listening on {}", l.endpoint);
                self.appcast.note(Note::Warning(w), self.start);
                continue;
            }
            self.listeners.push(l);
            self.attach_inbox(self.listeners.len() - 1);
            if self.opened {
                self.open_listener(self.listeners.len() - 1);
            }
        }
    }

    fn on_command(&mut self, m: &Mail, now: f64) {
        // Commands written before this pShare started are stale (`IsYoungerThan`).
        if m.time < self.start {
            return;
        }
        let Some(text) = m.value.as_str() else {
            return;
        };
        match parse_command(text) {
            Ok(Command::Output(specs)) => {
                for s in &specs {
                    self.add_output(s, now);
                }
            }
            Ok(Command::Input(spec)) => self.add_input(&spec),
            Err(e) => self.appcast.note(
                Note::Warning(format!("{} = {text}: {e}", self.cmd_key)),
                now,
            ),
        }
    }

    fn share(&mut self, m: &Mail, now: f64) {
        if !self.radio.up() {
            if self.would_route(m) {
                self.tx.submerged += 1;
                self.store.keep(m);
            }
            return;
        }
        let sends = self.table.route(&m.key, &m.source, now);
        if sends.is_empty() {
            return;
        }
        let mut msg = Message::notify(&m.key, m.value.clone(), m.time);
        msg.src = m.source.as_bytes().clone();
        msg.src_aux = m.source_aux.as_bytes().clone();
        msg.community = m.community.as_bytes().clone();
        for s in sends {
            let mut out = std::mem::take(&mut self.out_buf);
            if datagram::encode(&msg, &s.dest_name, &mut out).is_err() {
                self.tx.too_large += 1;
                let w = format!(
                    "{} is over {} bytes: not shared",
                    m.key,
                    pshare::MAX_UDP_SIZE
                );
                self.appcast.note(Note::Warning(w), now);
            } else if let Some(inbox) = self.in_process(&s.endpoint) {
                inbox.push(now, self.sender_no, Bytes::copy_from_slice(&out));
                self.tx.sent += 1;
                self.tx.in_process += 1;
            } else {
                let to = self.resolve(&s.endpoint);
                match (to, &self.sender) {
                    (Some(to), Some(sock)) if sock.send_to(&out, to).is_ok() => self.tx.sent += 1,
                    _ => self.tx.failed += 1,
                }
            }
            self.out_buf = out;
        }
    }

    /// True when `m` has routes: a named share, or a wildcard share matching its name and
    /// its writer.
    fn would_route(&self, m: &Mail) -> bool {
        use moos_types::text::wildcard_match;
        self.table.registered_for(&m.key)
            || self.table.wildcards().any(|(var, app, _)| {
                wildcard_match(var.as_bytes(), m.key.as_bytes())
                    && wildcard_match(app.as_bytes(), m.source.as_bytes())
            })
    }

    /// Surfaced: what the store kept goes out, oldest first.
    fn forward_stored(&mut self, now: f64) {
        let kept = std::mem::take(&mut self.store.kept);
        for m in &kept {
            self.store.counts.forwarded += 1;
            self.share(m, now);
        }
    }

    /// The in-process inbox an output to `e` reaches, if the run has one.
    fn in_process(&self, e: &Endpoint) -> Option<Arc<Inbox>> {
        let hub = self.hub.as_ref()?;
        let Endpoint::Udp { host, port } = e else {
            return None;
        };
        let inbox = hub.route(host, *port)?;
        hub.delivered.fetch_add(1, Ordering::Relaxed);
        Some(inbox)
    }

    fn receive(&mut self, now: f64, out: &mut Vec<Post>) {
        let up = self.radio.up();
        for l in &mut self.listeners {
            if let Some(inbox) = &l.inbox {
                self.ready.clear();
                inbox.take_before(now, &mut self.ready);
                if !up {
                    l.counts.submerged += self.ready.len() as u64;
                    self.ready.clear();
                }
                for d in self.ready.drain(..) {
                    accept(
                        &mut l.counts,
                        &l.white_list,
                        &self.table,
                        &self.cmd_key,
                        d,
                        out,
                    );
                }
                continue;
            }
            let Some(sock) = &l.socket else {
                continue;
            };
            for _ in 0..MAX_READS_PER_ITERATION {
                let n = match sock.recv_from(&mut self.buf) {
                    Ok((n, _)) => n,
                    Err(e) if e.kind() == ErrorKind::WouldBlock => break,
                    // An ICMP error of an earlier send, an interrupted call: read on.
                    Err(_) => continue,
                };
                if !up {
                    l.counts.submerged += 1;
                    continue;
                }
                let d = Bytes::copy_from_slice(&self.buf[..n]);
                accept(
                    &mut l.counts,
                    &l.white_list,
                    &self.table,
                    &self.cmd_key,
                    d,
                    out,
                );
            }
        }
    }

    fn summaries(&mut self, now: f64, out: &mut Vec<Post>) {
        let last = *self.last_summary.get_or_insert(now);
        if now - last < SUMMARY_PERIOD {
            return;
        }
        self.last_summary = Some(now);
        let group = &self.config.multicast_address;
        let base = self.config.multicast_base_port;
        out.push(Post::text(
            "PSHARE_OUTPUT_SUMMARY",
            self.table.output_summary(group, base),
        ));
        let inputs: Vec<String> = self
            .listeners
            .iter()
            .map(|l| match &l.endpoint {
                Endpoint::Udp { host, port } => format!("{host}:{}", l.port.unwrap_or(*port)),
                e @ Endpoint::Multicast(n) => format!(
                    "{}:multicast_{n}",
                    pshare::route::endpoint_address(e, group, base)
                ),
            })
            .collect();
        out.push(Post::text(
            "PSHARE_INPUT_SUMMARY",
            ByteString::from(inputs.join(",")),
        ));
    }
}

/// One datagram that came in on an input with `white_list`, counted in `counts`: decoded,
/// checked against the white list and the loop guard, and posted as a relayed post (UDP and
/// the in-process route alike).
fn accept(
    counts: &mut RxCounts,
    white_list: &[String],
    table: &RouteTable,
    cmd_key: &str,
    d: Bytes,
    out: &mut Vec<Post>,
) {
    let msg = match datagram::decode(d) {
        Ok(msg) => msg,
        Err(_) => {
            counts.garbage += 1;
            return;
        }
    };
    if !datagram::wanted(white_list, &msg.key) {
        counts.filtered += 1;
        return;
    }
    let Some(mail) = msg.mail() else {
        counts.garbage += 1;
        return;
    };
    if table.registered_for(&mail.key) || *mail.key == *cmd_key {
        counts.looped += 1;
        return;
    }
    counts.posted += 1;
    out.push(Post {
        key: mail.key,
        value: mail.value,
        source: mail.source,
        aux: mail.source_aux,
        relayed: Some(Box::new(Relayed {
            time: mail.time,
            community: mail.community,
        })),
    });
}

/// Reads `radio_store` and `radio_store_max` (coug only); bad values and a store without
/// `radio_max_depth` are warnings.
fn radio_store(block: &ProcessConfig, gated: bool, warnings: &mut Vec<Diagnostic>) -> Store {
    let mut store = Store {
        max: DEFAULT_RADIO_STORE_MAX,
        ..Store::default()
    };
    let mut warn = |p: &mission::Param, why: &str| {
        warnings.push(Diagnostic::line_warning(
            DiagnosticKind::AppSetting,
            &p.span,
            format!("{PROGRAM}: {} = {}: {why}", p.key.trim(), p.value.trim()),
        ))
    };
    for p in &block.entries {
        let v = p.value.trim();
        match p.key.trim().to_ascii_lowercase().as_str() {
            "radio_store" => match v.to_ascii_lowercase().as_str() {
                "off" => store.mode = RadioStore::Off,
                "latest" => store.mode = RadioStore::Latest,
                "all" => store.mode = RadioStore::All,
                _ => warn(p, "expected off, latest or all"),
            },
            "radio_store_max" => match v.parse::<usize>() {
                Ok(n) if n >= 1 => store.max = n,
                _ => warn(p, "expected a count of 1 or more"),
            },
            _ => {}
        }
    }
    if store.mode != RadioStore::Off
        && !gated
        && let Some(p) = block
            .entries
            .iter()
            .find(|p| p.key.trim().eq_ignore_ascii_case("radio_store"))
    {
        warn(
            p,
            "no effect without radio_max_depth (the radio is always up)",
        );
    }
    store
}

fn listeners_of(spec: &InputSpec) -> Vec<Listener> {
    spec.endpoints
        .iter()
        .map(|e| Listener {
            endpoint: e.clone(),
            white_list: spec.white_list.clone(),
            socket: None,
            inbox: None,
            port: None,
            counts: RxCounts::default(),
        })
        .collect()
}

/// The appcast body: the output routes with their share counts, the inputs with what came in.
fn appcast_body(
    table: &RouteTable,
    listeners: &[Listener],
    tx: TxCounts,
    (radio, store): (RadioGate, &Store),
    out: &mut String,
) {
    if radio.enabled() {
        let state = if radio.up() { "up" } else { "down (submerged)" };
        let _ = writeln!(out, "Radio: {state}");
        if store.mode != RadioStore::Off {
            let c = store.counts;
            let _ = writeln!(
                out,
                "Store: {} (at most {})  queued={} stored={} forwarded={} superseded={} overflow={}",
                store.mode.as_str(),
                store.max,
                store.kept.len(),
                c.stored,
                c.forwarded,
                c.superseded,
                c.overflow
            );
        }
        let _ = writeln!(out);
    }
    let _ = writeln!(out, "Output routes:");
    let mut any = false;
    for (var, routes) in table.named() {
        for r in routes {
            any = true;
            let _ = writeln!(
                out,
                "  {var} -> {} @ {}  shares={}",
                r.dest_name, r.endpoint, r.shares
            );
        }
    }
    for (var, who, routes) in table.wildcards() {
        for r in routes {
            any = true;
            let _ = writeln!(
                out,
                "  {var} (from {who}) -> {}<name> @ {}",
                r.dest_name, r.endpoint
            );
        }
    }
    if !any {
        let _ = writeln!(out, "  none");
    }
    let t = tx;
    let _ = writeln!(
        out,
        "  sent={} too_large={} failed={} submerged={}",
        t.sent, t.too_large, t.failed, t.submerged
    );
    let _ = writeln!(out, "\nInput routes:");
    if listeners.is_empty() {
        let _ = writeln!(out, "  none");
    }
    for l in listeners {
        let port = l
            .port
            .map_or_else(|| "closed".to_string(), |p| p.to_string());
        let c = l.counts;
        let _ = writeln!(
            out,
            "  {} (port {port})  posted={} filtered={} looped={} garbage={} submerged={}",
            l.endpoint, c.posted, c.filtered, c.looped, c.garbage, c.submerged
        );
    }
}

impl App for PShareApp {
    fn name(&self) -> &str {
        &self.name
    }

    fn process_config(&self) -> Option<&ProcessConfig> {
        Some(&self.block)
    }

    fn subscriptions(&self) -> Vec<Subscription> {
        AppcastLayer::subscriptions()
            .chain(std::iter::once(Subscription::var(&self.cmd_key)))
            .chain(self.radio.enabled().then(|| Subscription::var(DEPTH_VAR)))
            .chain(self.table.registrations().map(Subscription::var))
            .collect()
    }

    fn new_subscriptions(&mut self) -> Vec<Subscription> {
        std::mem::take(&mut self.new_subs)
    }

    fn on_startup(&mut self, now: f64, _out: &mut Vec<Post>) -> AppResult {
        self.appcast.on_startup(now);
        self.start = now;
        // The configured shares start (their `duration` counts) when the app does.
        self.table = RouteTable::default();
        for o in &self.config.outputs {
            self.table.add(o, now);
        }
        self.open();
        Ok(())
    }

    fn on_mail(&mut self, mail: &[Mail], now: f64, _out: &mut Vec<Post>) -> AppResult {
        for m in mail {
            if !self.appcast.take_mail(m) {
                continue;
            }
            if *m.key == *self.cmd_key {
                self.on_command(m, now);
                continue;
            }
            if self.radio.enabled()
                && *m.key == *DEPTH_VAR
                && let Some(d) = m.value.as_f64()
            {
                let was_up = self.radio.up();
                self.radio.depth(d);
                if !was_up && self.radio.up() {
                    self.forward_stored(now);
                }
            }
            self.share(m, now);
        }
        Ok(())
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> AppResult {
        let tick = self.app_tick();
        self.appcast.begin(now, tick, out);
        self.receive(now, out);
        self.summaries(now, out);
        let (table, listeners, tx) = (&self.table, &self.listeners, self.tx);
        let radio = (self.radio, &self.store);
        self.appcast.end(now, tick, out, |b| {
            appcast_body(table, listeners, tx, radio, b)
        });
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::Value;
    use crate::testing::{block, mail};

    fn posted<'a>(out: &'a [Post], key: &str) -> Vec<&'a Post> {
        out.iter().filter(|p| &*p.key == key).collect()
    }

    #[test]
    fn communities_of_one_run_share_in_process_at_the_next_iteration() {
        let shared = Shared::new();
        let hub = shared.get_or_insert_with(HUB, PShareHub::new);
        let mut rx = PShareApp::new(
            "pShare",
            block(
                "b.moos",
                "ProcessConfig = pShare\n{\n  input = route = localhost:9421, white_list = REMOTE_*\n}\n",
            ),
        )
        .with_shared(&shared);
        // Another pShare of the run cannot take the same port: it stays a UDP listener.
        let other = PShareApp::new(
            "pShare2",
            block(
                "c.moos",
                "ProcessConfig = pShare2\n{\n  input = route = localhost:9421\n}\n",
            ),
        )
        .with_shared(&shared);
        assert!(other.listeners[0].inbox.is_none());
        assert_eq!(hub.ports(), vec![9421]);
        let mut tx = PShareApp::new(
            "pShare",
            block(
                "a.moos",
                "ProcessConfig = pShare\n{\n  output = NAV_X->REMOTE_NAV_X:127.0.0.1:9421\n  \
                 output = SECRET->localhost:9421\n  output = NAV_Y->REMOTE_NAV_Y:127.0.0.1:9422\n}\n",
            ),
        )
        .with_shared(&shared);
        let mut out = Vec::new();
        rx.on_startup(10.0, &mut out).unwrap();
        tx.on_startup(10.0, &mut out).unwrap();
        // The receiver's input is in process: open on its port with no socket.
        assert_eq!(
            rx.listening(),
            vec![(
                Endpoint::Udp {
                    host: "localhost".into(),
                    port: 9421
                },
                Some(9421)
            )]
        );
        assert!(rx.listeners[0].socket.is_none());
        let sent = [
            mail("NAV_X", Value::Double(5.0), 11.0, "uSimMarine"),
            mail("SECRET", Value::Double(7.0), 11.0, "uSimMarine"),
            mail("NAV_Y", Value::Double(6.0), 11.0, "uSimMarine"),
        ];
        tx.on_mail(&sent, 11.0, &mut out).unwrap();
        // Two datagrams in process; NAV_Y's port has no input of the run: UDP.
        let t = tx.sent();
        assert_eq!((t.sent, t.in_process, t.failed), (3, 2, 0));
        assert_eq!(hub.delivered(), 2);
        // Not at the instant it was sent, whatever the order the communities run in.
        let mut got = Vec::new();
        rx.iterate(11.0, &mut got).unwrap();
        assert!(posted(&got, "REMOTE_NAV_X").is_empty());
        got.clear();
        rx.iterate(11.25, &mut got).unwrap();
        let x = posted(&got, "REMOTE_NAV_X");
        assert_eq!(x.len(), 1);
        assert_eq!(x[0].value, Value::Double(5.0));
        assert_eq!(&*x[0].source, "uSimMarine");
        let relayed = x[0].relayed.as_deref().expect("a relayed post");
        assert_eq!((relayed.time, &*relayed.community), (11.0, "abe"));
        // SECRET kept its name and the white list refused it, as over UDP.
        assert!(posted(&got, "SECRET").is_empty());
        let c = rx.received()[0].1;
        assert_eq!((c.posted, c.filtered, c.garbage), (1, 1, 0));
        got.clear();
        rx.iterate(11.5, &mut got).unwrap();
        assert!(posted(&got, "REMOTE_NAV_X").is_empty(), "delivered once");
    }

    /// A vehicle's bridge with the surface-only radio and a shoreside's, in process.
    fn vehicle_and_shore(shared: &Shared) -> (PShareApp, PShareApp) {
        let vehicle = PShareApp::new(
            "pShare",
            block(
                "v.moos",
                "ProcessConfig = pShare\n{\n  radio_max_depth = 0.5\n  \
                 input = route = localhost:9441\n  \
                 output = NODE_REPORT_LOCAL->NODE_REPORT:localhost:9440\n}\n",
            ),
        )
        .with_shared(shared);
        let shore = PShareApp::new(
            "pShare",
            block(
                "s.moos",
                "ProcessConfig = pShare\n{\n  input = route = localhost:9440\n  \
                 output = RETURN_ALL->RETURN:localhost:9441\n}\n",
            ),
        )
        .with_shared(shared);
        (vehicle, shore)
    }

    fn depth(d: f64, t: f64) -> Mail {
        mail("NAV_DEPTH", Value::Double(d), t, "uSimMarine")
    }

    fn report(n: f64, t: f64) -> Mail {
        mail("NODE_REPORT_LOCAL", Value::Double(n), t, "pNodeReporter")
    }

    fn body(app: &PShareApp) -> String {
        let mut b = String::new();
        appcast_body(
            &app.table,
            &app.listeners,
            app.tx,
            (app.radio, &app.store),
            &mut b,
        );
        b
    }

    fn values(out: &[Post], key: &str) -> Vec<Value> {
        posted(out, key).iter().map(|p| p.value.clone()).collect()
    }

    #[test]
    fn a_diving_vehicle_stops_reaching_the_shore_and_nothing_of_the_dive_is_replayed() {
        let shared = Shared::new();
        shared.get_or_insert_with(HUB, PShareHub::new);
        let (mut v, mut shore) = vehicle_and_shore(&shared);
        let subs: Vec<String> = v.subscriptions().into_iter().map(|s| s.pattern).collect();
        assert!(subs.contains(&"NAV_DEPTH".to_string()));
        let subs: Vec<String> = shore
            .subscriptions()
            .into_iter()
            .map(|s| s.pattern)
            .collect();
        assert!(
            !subs.contains(&"NAV_DEPTH".to_string()),
            "no gate by default"
        );
        let mut out = Vec::new();
        v.on_startup(0.0, &mut out).unwrap();
        shore.on_startup(0.0, &mut out).unwrap();
        let mut heard = Vec::new();
        // One report a second; the vehicle dives at 3 s and surfaces at 6 s.
        for k in 1..=9 {
            let t = f64::from(k);
            let d = if (3..6).contains(&k) { 2.0 } else { 0.2 };
            v.on_mail(&[depth(d, t), report(t, t)], t, &mut out)
                .unwrap();
            shore.iterate(t + 0.5, &mut heard).unwrap();
        }
        let got = values(&heard, "NODE_REPORT");
        let want: Vec<Value> = [1.0, 2.0, 6.0, 7.0, 8.0, 9.0]
            .into_iter()
            .map(Value::Double)
            .collect();
        assert_eq!(
            got, want,
            "nothing sent from 3 s to 5 s, nothing replayed after"
        );
        let t = v.sent();
        assert_eq!((t.sent, t.in_process, t.submerged), (6, 6, 3));
        assert!(body(&v).starts_with("Radio: up\n"));
    }

    #[test]
    fn a_submerged_vehicle_drops_what_arrives_and_hears_again_at_the_surface() {
        let shared = Shared::new();
        shared.get_or_insert_with(HUB, PShareHub::new);
        let (mut v, mut shore) = vehicle_and_shore(&shared);
        let mut out = Vec::new();
        v.on_startup(0.0, &mut out).unwrap();
        shore.on_startup(0.0, &mut out).unwrap();
        let mut heard = Vec::new();
        for k in 1..=8 {
            let t = f64::from(k);
            // The shoreside has no gate: it sends every second whatever the vehicle's depth.
            shore
                .on_mail(
                    &[mail("RETURN_ALL", Value::Double(t), t, "uPokeDB")],
                    t,
                    &mut out,
                )
                .unwrap();
            let d = if (3..6).contains(&k) { 2.0 } else { 0.0 };
            v.on_mail(&[depth(d, t + 0.5)], t + 0.5, &mut out).unwrap();
            v.iterate(t + 0.5, &mut heard).unwrap();
        }
        let got = values(&heard, "RETURN");
        let want: Vec<Value> = [1.0, 2.0, 6.0, 7.0, 8.0]
            .into_iter()
            .map(Value::Double)
            .collect();
        assert_eq!(got, want);
        let c = v.received()[0].1;
        assert_eq!((c.posted, c.submerged), (5, 3));
        assert_eq!(shore.sent().submerged, 0);
        assert!(body(&v).contains("posted=5 filtered=0 looped=0 garbage=0 submerged=3"));
    }

    #[test]
    fn the_store_settings_are_read_and_bad_ones_are_warnings() {
        let app = |lines: &str| {
            PShareApp::new(
                "pShare",
                block(
                    "v.moos",
                    &format!("ProcessConfig = pShare\n{{\n{lines}}}\n"),
                ),
            )
        };
        let a = app("  radio_max_depth = 1\n  radio_store = Latest\n  radio_store_max = 7\n");
        assert!(a.warnings().is_empty(), "{:?}", a.warnings());
        assert_eq!(a.radio_store(), (RadioStore::Latest, 7));
        let d = app("  radio_max_depth = 1\n");
        assert_eq!(d.radio_store(), (RadioStore::Off, DEFAULT_RADIO_STORE_MAX));
        let b = app("  radio_max_depth = 1\n  radio_store = some\n  radio_store_max = 0\n");
        let w: Vec<String> = b.warnings().iter().map(Diagnostic::located).collect();
        assert_eq!(
            w,
            [
                "v.moos:4: pShare: radio_store = some: expected off, latest or all",
                "v.moos:5: pShare: radio_store_max = 0: expected a count of 1 or more",
            ]
        );
        assert_eq!(b.radio_store(), (RadioStore::Off, DEFAULT_RADIO_STORE_MAX));
        let c = app("  radio_store = all\n");
        let w: Vec<String> = c.warnings().iter().map(Diagnostic::located).collect();
        assert_eq!(
            w,
            [
                "v.moos:3: pShare: radio_store = all: no effect without radio_max_depth (the radio is always up)"
            ]
        );
    }

    #[test]
    fn a_latest_store_keeps_one_value_per_variable_and_forwards_it_on_surfacing() {
        let shared = Shared::new();
        shared.get_or_insert_with(HUB, PShareHub::new);
        let v = PShareApp::new(
            "pShare",
            block(
                "v.moos",
                "ProcessConfig = pShare\n{\n  radio_max_depth = 0.5\n  radio_store = latest\n  \
                 radio_store_max = 1\n  input = route = localhost:9451\n  \
                 output = NODE_REPORT_LOCAL->NODE_REPORT:localhost:9450\n  output = X->localhost:9450\n}\n",
            ),
        );
        let mut v = v.with_shared(&shared);
        let mut shore = PShareApp::new(
            "pShare",
            block(
                "s.moos",
                "ProcessConfig = pShare\n{\n  input = route = localhost:9450\n}\n",
            ),
        )
        .with_shared(&shared);
        let mut out = Vec::new();
        v.on_startup(0.0, &mut out).unwrap();
        shore.on_startup(0.0, &mut out).unwrap();
        // Under: two reports and one X; with room for one variable, the report goes.
        v.on_mail(
            &[depth(2.0, 1.0), report(1.0, 1.0), report(2.0, 2.0)],
            2.0,
            &mut out,
        )
        .unwrap();
        v.on_mail(&[mail("X", Value::Double(9.0), 3.0, "a")], 3.0, &mut out)
            .unwrap();
        assert_eq!(v.store_counts().1, 1);
        let mut heard = Vec::new();
        shore.iterate(3.5, &mut heard).unwrap();
        assert!(
            heard
                .iter()
                .all(|p| &*p.key != "X" && &*p.key != "NODE_REPORT")
        );
        // Surfacing: X goes out before the report that came with the surfacing depth.
        v.on_mail(&[depth(0.2, 4.0), report(4.0, 4.0)], 4.0, &mut out)
            .unwrap();
        shore.iterate(4.5, &mut heard).unwrap();
        let keys: Vec<&str> = heard
            .iter()
            .filter(|p| &*p.key == "X" || &*p.key == "NODE_REPORT")
            .map(|p| &*p.key)
            .collect();
        assert_eq!(keys, ["X", "NODE_REPORT"]);
        let (c, queued) = v.store_counts();
        assert_eq!(
            (c.stored, c.forwarded, c.superseded, c.overflow, queued),
            (3, 1, 1, 1, 0)
        );
        assert_eq!(v.sent().submerged, 3);
        assert!(body(&v).contains(
            "Store: latest (at most 1)  queued=0 stored=3 forwarded=1 superseded=1 overflow=1"
        ));
    }

    #[test]
    fn an_all_store_keeps_wildcard_shares_in_order() {
        let shared = Shared::new();
        shared.get_or_insert_with(HUB, PShareHub::new);
        let mut v = PShareApp::new(
            "pShare",
            block(
                "v.moos",
                "ProcessConfig = pShare\n{\n  radio_max_depth = 0.5\n  radio_store = all\n  \
                 output = src_name=SENSOR_*, route=localhost:9471\n}\n",
            ),
        )
        .with_shared(&shared);
        let mut shore = PShareApp::new(
            "pShare",
            block(
                "s.moos",
                "ProcessConfig = pShare\n{\n  input = route = localhost:9471\n}\n",
            ),
        )
        .with_shared(&shared);
        let mut out = Vec::new();
        v.on_startup(0.0, &mut out).unwrap();
        shore.on_startup(0.0, &mut out).unwrap();
        let sensor = |k: &str, x: f64, t: f64| mail(k, Value::Double(x), t, "iSensor");
        v.on_mail(
            &[depth(3.0, 1.0), sensor("SENSOR_A", 1.0, 1.0)],
            1.0,
            &mut out,
        )
        .unwrap();
        v.on_mail(
            &[sensor("SENSOR_B", 2.0, 2.0), sensor("SENSOR_A", 3.0, 2.0)],
            2.0,
            &mut out,
        )
        .unwrap();
        v.on_mail(&[depth(0.0, 3.0)], 3.0, &mut out).unwrap();
        let mut heard = Vec::new();
        shore.iterate(3.5, &mut heard).unwrap();
        let got: Vec<(&str, Value)> = heard
            .iter()
            .filter(|p| p.key.starts_with("SENSOR_"))
            .map(|p| (&*p.key, p.value.clone()))
            .collect();
        assert_eq!(
            got,
            [
                ("SENSOR_A", Value::Double(1.0)),
                ("SENSOR_B", Value::Double(2.0)),
                ("SENSOR_A", Value::Double(3.0)),
            ]
        );
        let (c, queued) = v.store_counts();
        assert_eq!((c.stored, c.forwarded, queued), (3, 3, 0));
        assert_eq!(v.sent().submerged, 3);
    }

    #[test]
    fn without_a_hub_every_route_is_udp() {
        let shared = Shared::new();
        let app = PShareApp::new(
            "pShare",
            block(
                "a.moos",
                "ProcessConfig = pShare\n{\n  input = route = localhost:9431\n}\n",
            ),
        )
        .with_shared(&shared);
        assert!(app.hub.is_none() && app.listeners[0].inbox.is_none());
        assert!(shared.is_empty());
    }

    #[test]
    fn bad_lines_and_multicast_routes_are_warnings_at_their_line() {
        let app = PShareApp::new(
            "pShare",
            block(
                "s.moos",
                "ProcessConfig = pShare\n{\n  output = X>10.0.0.1:9000\n  \
                 input = route = multicast_9\n  listen_address = here\n  \
                 output = src_name = Y, route = 127.0.0.1:9300\n}\n",
            ),
        );
        let w: Vec<String> = app.warnings().iter().map(Diagnostic::located).collect();
        assert_eq!(
            w,
            vec![
                "s.moos:3: pShare: output = X>10.0.0.1:9000: short form \"X>10.0.0.1:9000\" \
                 has no \"->\" between the variable and its routes",
                "s.moos:1: pShare: multicast routes are read but coug opens no multicast \
                 socket: they send and receive nothing",
                "s.moos:5: pShare: listen_address = here: not an IPv4 address",
            ]
        );
        assert_eq!(app.config().outputs.len(), 1);
        // Nothing is opened before start-up (a checked mission binds no port).
        assert_eq!(app.listening(), vec![(Endpoint::Multicast(9), None)]);
        let subs: Vec<String> = app.subscriptions().into_iter().map(|s| s.pattern).collect();
        assert!(subs.contains(&"PSHARE_CMD".to_string()));
        assert!(subs.contains(&"Y".to_string()));
    }
}
