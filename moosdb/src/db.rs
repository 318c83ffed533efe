//! The MOOSDB as a pure core: variables, registrations, wildcard filters, held mail and
//! per-client outboxes. No I/O and no clock: every call takes the time as [`DbTime`].
//!
//! The TCP server ([`crate::server`]) is a thin edge around a [`Database`]; an in-process
//! caller (for example a lock-step simulation) can drive it directly:
//!
//! ```
//! use moosdb::db::{Database, DbConfig, DbTime};
//! use moosdb::{Message, MsgType, DataType, Value};
//! use bytes::Bytes;
//!
//! let t = DbTime { moos: 100.0, mono: 0.0 };
//! let mut db = Database::new(DbConfig::default(), t);
//! let sub = db.connect(Bytes::from_static(b"sub"), true, 100.0, t).id().unwrap();
//! let publ = db.connect(Bytes::from_static(b"pub"), true, 100.0, t).id().unwrap();
//! let mut reg = Message::new(MsgType::Register, DataType::Double, "X");
//! reg.dval = 0.0;
//! db.handle(sub, vec![reg], t).unwrap();
//! let mut post = Message::notify("X", Value::Double(2.0), 100.0);
//! post.src = Bytes::from_static(b"pub");
//! let effects = db.handle(publ, vec![post], t).unwrap();
//! assert!(effects.ready.contains(&sub));
//! let mut packets = Vec::new();
//! db.drain_outbox(sub, &mut packets);
//! assert_eq!(packets.concat()[0].dval, 2.0);
//! ```
//!
//! # Fidelity to the C++ MOOSDB
//!
//! The core follows `CMOOSDB` and the threaded comm server message for message; the tests
//! replay every recorded capture and get the C++ DB's packets back. Kept on purpose:
//! a `'T'`-only packet's reply is the echo alone (held mail waits), DB variables and
//! `DB_EVENT` reach asynchronous clients only when some client posts a notify, writes within a
//! subscriber's interval are dropped, the first write locks a variable's type.
//! Deliberate differences: per-client queues are bounded (oldest mail dropped, counted and
//! logged) where the C++ DB's are not; a wildcard unregister also forgets the stored filter
//! (the C++ DB keeps matching new variables); `DB_QOS` averages the last five latencies;
//! `DB_VARSUMMARY` prints times of day in UTC; `--response` consolidation is not offered
//! (timing echoes carry 0); there is no 100 ms pause before a handshake.
//!
//! Told which variables a client drops unread ([`Database::set_unread`]: an in-process
//! pLogger's `WildCardOmitPattern`s), the DB does not deliver them to it. With
//! [`DbConfig::lazy_summaries`] (the in-process bus of lockstep runs) it also builds the
//! `DB_VARSUMMARY` and `DB_RWSUMMARY` texts only while some client reads them (their writes,
//! times and frequencies are kept all the same; a late reader gets the text built when it
//! asks, so this one is not for a TCP DB whose clients come and go).
//!
//! Every write is queued for its subscribers as one shared [`Delivery`] (an `Arc`: no copy
//! of the message per subscriber). An in-process client posts its notifies as the
//! [`moos_types::Mail`] they deliver ([`Incoming::Posted`], through [`Database::handle_into`]),
//! and reads them back with [`Database::poll_into`] and [`Database::drain_deliveries`]: its
//! mail is the poster's (cloned, or taken by the last reader), with no message made or
//! converted. The TCP edge drains plain messages ([`Database::drain_outbox`]): a posted
//! mail's message is made there, for the TCP clients only.

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fmt::Write as _;
use std::sync::Arc;

use bytes::Bytes;
use rustc_hash::FxHashMap;
use smallvec::SmallVec;
use thiserror::Error;
use tracing::{info, warn};

use crate::message::{ASYNCHRONOUS, DataType, MESSAGE_FIXED_LEN, Message, MsgType, NO_ID, Value};
use moos_types::{ByteString, Mail};

/// Seconds between refreshes of the DB's own variables (DB_TIME, DB_CLIENTS, ...).
pub const SUMMARY_PERIOD: f64 = 2.0;

/// Default silence after which a client is dropped (`ClientTimeout`), unwarped seconds.
pub const DEFAULT_CLIENT_TIMEOUT: f64 = 5.0;

/// Default per-client bound on queued messages (outbox and held mail each).
pub const DEFAULT_OUTBOX_LIMIT: usize = 8192;

/// Default per-client bound on queued outbox bytes (64 MiB).
pub const DEFAULT_OUTBOX_BYTE_LIMIT: usize = 64 * 1024 * 1024;

/// Settings of a [`Database`].
#[derive(Debug, Clone)]
pub struct DbConfig {
    /// Community name (`Community`, default `#1`); the DB's own name is `MOOSDB_<community>`.
    pub community: String,
    /// Host name announced in the Welcome (`hostname=<this>`).
    pub host_name: String,
    /// Silence (unwarped seconds) after which a client is removed.
    pub client_timeout: f64,
    /// Most messages queued per client; beyond it the oldest are dropped, counted and logged.
    pub outbox_limit: usize,
    /// Most bytes (encoded) queued per client in its outbox; same overflow rule.
    pub outbox_byte_limit: usize,
    /// Build `DB_VARSUMMARY`/`DB_RWSUMMARY` only while some client reads them (default
    /// false: always, as the C++ DB). A client that registers for one later, or a server
    /// request, then gets the text as it is built when asked, not as it was at its last
    /// refresh: meant for in-process runs whose readers register at the start.
    pub lazy_summaries: bool,
}

impl Default for DbConfig {
    fn default() -> Self {
        DbConfig {
            community: "#1".to_string(),
            host_name: "localhost".to_string(),
            client_timeout: DEFAULT_CLIENT_TIMEOUT,
            outbox_limit: DEFAULT_OUTBOX_LIMIT,
            outbox_byte_limit: DEFAULT_OUTBOX_BYTE_LIMIT,
            lazy_summaries: false,
        }
    }
}

/// The time of one DB call.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DbTime {
    /// The DB's MOOS time (warped; the DB has no skew).
    pub moos: f64,
    /// Unwarped monotonic seconds from any fixed origin; used only for client liveness.
    pub mono: f64,
}

/// A connected client's handle inside the core: its slot in the DB's table of clients (the
/// low 32 bits) and that slot's generation (the high 32 bits), so a look-up is an index and
/// the handle of a client that left never names the one that takes its slot.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct ClientId(pub u64);

impl ClientId {
    fn new(slot: usize, generation: u32) -> ClientId {
        ClientId((u64::from(generation) << 32) | slot as u64)
    }

    fn slot(self) -> usize {
        (self.0 & 0xffff_ffff) as usize
    }

    fn generation(self) -> u32 {
        (self.0 >> 32) as u32
    }
}

/// Misuse of the core's API.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
pub enum DbError {
    /// The client is not (or no longer) connected.
    #[error("unknown or disconnected client {0:?}")]
    UnknownClient(ClientId),
}

/// The outcome of a handshake: what to send the new connection.
#[derive(Debug, Clone, PartialEq)]
pub enum Handshake {
    /// Admitted as `id`; send `reply` (the Welcome).
    Welcome {
        /// The new client's id.
        id: ClientId,
        /// The Welcome message.
        reply: Message,
    },
    /// Refused; send `reply` (the Poison) and close.
    Poison {
        /// The Poison message (reason in `sval`).
        reply: Message,
    },
}

impl Handshake {
    /// The id when welcomed.
    pub fn id(&self) -> Option<ClientId> {
        match self {
            Handshake::Welcome { id, .. } => Some(*id),
            Handshake::Poison { .. } => None,
        }
    }

    /// The message to send either way.
    pub fn reply(&self) -> &Message {
        match self {
            Handshake::Welcome { reply, .. } | Handshake::Poison { reply } => reply,
        }
    }
}

/// What a call changed outside the core.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct Effects {
    /// Clients whose outbox received packets; the edge should drain and send them.
    pub ready: Vec<ClientId>,
}

/// A message as the DB queues it for its clients: one shared allocation per write, whatever
/// the number of clients it reaches (each held mail and outbox holds an [`Arc`] of it, so a
/// delivery copies no message). Its encoded size is counted once. A notify an in-process
/// client posted ([`Incoming::Posted`]) is kept as the [`Mail`] it delivers, made by the
/// poster from text that was UTF-8 already: in-process readers clone it (the last one takes
/// it), with no conversion, and the message a TCP client reads is made from it when its
/// outbox is drained ([`Database::drain_outbox`]).
#[derive(Debug)]
pub struct Delivery {
    body: Incoming,
    encoded_len: usize,
}

impl Delivery {
    /// A shared delivery of `message`.
    pub fn new(message: Message) -> Arc<Delivery> {
        Delivery::of(Incoming::Message(message))
    }

    fn of(body: Incoming) -> Arc<Delivery> {
        Arc::new(Delivery {
            encoded_len: body.encoded_len(),
            body,
        })
    }

    /// True for a notify (what an in-process reader takes as mail).
    pub fn is_notify(&self) -> bool {
        self.body.msg_type() == MsgType::Notify
    }

    /// The message (a posted mail's made from it: id −1, dval2 −1, as the bus posted it).
    pub fn to_message(&self) -> Message {
        self.body.to_message()
    }

    /// The mail the message delivers ([`Message::mail`]; `None` for data type `'~'`): the
    /// poster's, cloned, or else converted from the message.
    pub fn mail(&self) -> Option<Mail> {
        match &self.body {
            Incoming::Posted(mail) => Some(mail.clone()),
            Incoming::Message(m) => m.mail(),
        }
    }

    /// [`Delivery::mail`], taken without a copy when this was its last holder.
    pub fn into_mail(this: Arc<Delivery>) -> Option<Mail> {
        match Arc::try_unwrap(this) {
            Ok(Delivery {
                body: Incoming::Posted(mail),
                ..
            }) => Some(mail),
            Ok(d) => d.mail(),
            Err(d) => d.mail(),
        }
    }

    /// The message itself when this was its last holder, else a copy.
    pub fn into_message(this: Arc<Delivery>) -> Message {
        Arc::try_unwrap(this).map_or_else(|d| d.to_message(), |d| d.body.into_message())
    }

    /// Gives a message with no community the DB's (a delivery another holder has too is
    /// copied first).
    fn fill_community(this: &mut Arc<Delivery>, community: &Bytes) {
        if !this.body.community().is_empty() {
            return;
        }
        if let Some(d) = Arc::get_mut(this) {
            d.body.fill_community(community);
            d.encoded_len = d.body.encoded_len();
        } else {
            let mut body = this.body.clone();
            body.fill_community(community);
            *this = Delivery::of(body);
        }
    }
}

/// A message of a packet: as decoded or made ([`Message`]), or a notify an in-process client
/// posted as the [`Mail`] it delivers (made from text that was UTF-8 already, as an app's
/// [`moos_types::Post`]; a mail with no community gets the DB's, as a message would). The DB
/// stores and queues a posted mail as it is, and its in-process readers get it with no
/// conversion. Both convert with `into()`: [`Database::handle`] takes either.
#[derive(Debug, Clone)]
pub enum Incoming {
    /// A message (decoded from a packet, or made by the caller).
    Message(Message),
    /// A notify posted in process (its id and dval2 are −1, its type the value's).
    Posted(Mail),
}

impl From<Message> for Incoming {
    fn from(m: Message) -> Incoming {
        Incoming::Message(m)
    }
}

impl From<Mail> for Incoming {
    fn from(m: Mail) -> Incoming {
        Incoming::Posted(m)
    }
}

impl Incoming {
    fn msg_type(&self) -> MsgType {
        match self {
            Incoming::Message(m) => m.msg_type,
            Incoming::Posted(_) => MsgType::Notify,
        }
    }

    fn key(&self) -> &Bytes {
        match self {
            Incoming::Message(m) => &m.key,
            Incoming::Posted(p) => p.key.as_bytes(),
        }
    }

    fn src(&self) -> &Bytes {
        match self {
            Incoming::Message(m) => &m.src,
            Incoming::Posted(p) => p.source.as_bytes(),
        }
    }

    fn src_aux(&self) -> &Bytes {
        match self {
            Incoming::Message(m) => &m.src_aux,
            Incoming::Posted(p) => p.source_aux.as_bytes(),
        }
    }

    fn community(&self) -> &Bytes {
        match self {
            Incoming::Message(m) => &m.community,
            Incoming::Posted(p) => p.community.as_bytes(),
        }
    }

    fn time(&self) -> f64 {
        match self {
            Incoming::Message(m) => m.time,
            Incoming::Posted(p) => p.time,
        }
    }

    fn data_type(&self) -> DataType {
        match self {
            Incoming::Message(m) => m.data_type,
            Incoming::Posted(p) => match p.value {
                Value::Double(_) => DataType::Double,
                Value::String(_) => DataType::String,
                Value::Binary(_) => DataType::Binary,
            },
        }
    }

    fn dval(&self) -> f64 {
        match self {
            Incoming::Message(m) => m.dval,
            Incoming::Posted(p) => p.value.as_f64().unwrap_or(-1.0),
        }
    }

    /// The string or binary value (shared, or a copy of binary data).
    fn sval(&self) -> Bytes {
        match self {
            Incoming::Message(m) => m.sval.clone(),
            Incoming::Posted(p) => match &p.value {
                Value::Double(_) => Bytes::new(),
                Value::String(s) => s.as_bytes().clone(),
                Value::Binary(b) => Bytes::copy_from_slice(b),
            },
        }
    }

    fn encoded_len(&self) -> usize {
        match self {
            Incoming::Message(m) => m.encoded_len(),
            Incoming::Posted(p) => {
                let value = match &p.value {
                    Value::Double(_) => 0,
                    Value::String(s) => s.len(),
                    Value::Binary(b) => b.len(),
                };
                MESSAGE_FIXED_LEN
                    + p.source.len()
                    + p.source_aux.len()
                    + p.community.len()
                    + p.key.len()
                    + value
            }
        }
    }

    fn to_message(&self) -> Message {
        match self {
            Incoming::Message(m) => m.clone(),
            Incoming::Posted(p) => Message {
                id: NO_ID,
                msg_type: MsgType::Notify,
                data_type: self.data_type(),
                src: p.source.as_bytes().clone(),
                src_aux: p.source_aux.as_bytes().clone(),
                community: p.community.as_bytes().clone(),
                key: p.key.as_bytes().clone(),
                time: p.time,
                dval: self.dval(),
                dval2: -1.0,
                sval: self.sval(),
            },
        }
    }

    fn into_message(self) -> Message {
        match self {
            Incoming::Message(m) => m,
            posted => posted.to_message(),
        }
    }

    /// Gives a message with no community the DB's.
    fn fill_community(&mut self, community: &Bytes) {
        if !self.community().is_empty() {
            return;
        }
        match self {
            Incoming::Message(m) => m.community = community.clone(),
            Incoming::Posted(p) => p.community = moos_types::text_of(community),
        }
    }

    /// A posted mail whose key is a copy of its own (a fresh buffer, held nowhere else)
    /// takes the variable's `key` instead, so that its readers share one buffer.
    fn share_key(&mut self, key: &Bytes) {
        if let Incoming::Posted(p) = self
            && p.key.as_bytes().as_ptr() != key.as_ptr()
            && p.key.as_bytes().is_unique()
            && let Ok(k) = ByteString::try_from(key.clone())
        {
            p.key = k;
        }
    }
}

#[derive(Debug, Clone, Copy)]
struct Sub {
    /// The subscriber (its mail goes straight to it, no look-up by name).
    client: ClientId,
    period: f64,
    last_sent: f64,
    /// The client drops this variable's mail unread ([`Unread`]): nothing is delivered.
    unread: bool,
}

/// Variables a client drops unread although its registrations match them (pLogger's
/// `WildCardOmitPattern`s under wildcard logging without an exclusion log): the DB delivers
/// them no mail, and builds `DB_VARSUMMARY`/`DB_RWSUMMARY` only while some client reads them
/// (see [`Database::set_unread`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Unread {
    /// `MOOSWildCmp` patterns of the variables dropped.
    pub patterns: Vec<Bytes>,
    /// Variables read although a pattern matches them.
    pub except: Vec<Bytes>,
}

impl Unread {
    /// True when the client drops `key`'s mail unread.
    pub fn covers(&self, key: &[u8]) -> bool {
        self.patterns.iter().any(|p| wildcard_match(p, key))
            && !self.except.iter().any(|e| e[..] == *key)
    }
}

impl Sub {
    fn expired(&self, now: f64) -> bool {
        self.period == 0.0 || now - self.last_sent >= self.period
    }
}

/// A variable's subscribers by client name, in name order (the order they are served in):
/// one vector, so a write walks them without chasing tree nodes.
#[derive(Debug, Clone, Default)]
struct Subscribers(Vec<(Bytes, Sub)>);

impl Subscribers {
    fn find(&self, name: &[u8]) -> Result<usize, usize> {
        self.0.binary_search_by(|(n, _)| n[..].cmp(name))
    }

    fn get_mut(&mut self, name: &[u8]) -> Option<&mut Sub> {
        let i = self.find(name).ok()?;
        Some(&mut self.0[i].1)
    }

    fn contains_key(&self, name: &[u8]) -> bool {
        self.find(name).is_ok()
    }

    /// Adds `sub`, or replaces the one of `name`.
    fn insert(&mut self, name: &Bytes, sub: Sub) {
        match self.find(name) {
            Ok(i) => self.0[i].1 = sub,
            Err(i) => self.0.insert(i, (name.clone(), sub)),
        }
    }

    /// The subscription of `name`, added as `sub` if there is none.
    fn get_or_insert(&mut self, name: &Bytes, sub: Sub) -> &mut Sub {
        let i = match self.find(name) {
            Ok(i) => i,
            Err(i) => {
                self.0.insert(i, (name.clone(), sub));
                i
            }
        };
        &mut self.0[i].1
    }

    fn remove(&mut self, name: &[u8]) {
        if let Ok(i) = self.find(name) {
            self.0.remove(i);
        }
    }

    fn keys(&self) -> impl Iterator<Item = &Bytes> {
        self.0.iter().map(|(n, _)| n)
    }

    fn values(&self) -> impl Iterator<Item = &Sub> {
        self.0.iter().map(|(_, s)| s)
    }

    fn values_mut(&mut self) -> impl Iterator<Item = &mut Sub> {
        self.0.iter_mut().map(|(_, s)| s)
    }
}

#[derive(Debug, Clone)]
struct Var {
    /// The name (the buffer the first write or registration brought).
    key: Bytes,
    data_type: DataType,
    dval: f64,
    sval: Bytes,
    time: f64,
    written_time: f64,
    writer: Bytes,
    src_aux: Bytes,
    community: Bytes,
    written_to: u64,
    /// A DB summary whose text was not built at its last write: no client read it then.
    stale: bool,
    writers: BTreeSet<Bytes>,
    subscribers: Subscribers,
    freq: f64,
    stats_time: f64,
    stats_writes: u64,
}

impl Var {
    fn new(key: Bytes, data_type: DataType) -> Var {
        Var {
            key,
            data_type,
            dval: 0.0,
            sval: Bytes::new(),
            time: -1.0,
            written_time: -1.0,
            writer: Bytes::new(),
            src_aux: Bytes::new(),
            community: Bytes::new(),
            written_to: 0,
            stale: false,
            writers: BTreeSet::new(),
            subscribers: Subscribers::default(),
            freq: 0.0,
            stats_time: f64::NEG_INFINITY,
            stats_writes: 0,
        }
    }

    /// `Var2Msg`: the current value as a fresh notify (id -1).
    fn to_msg(&self, key: &Bytes) -> Message {
        let mut m = Message::new(MsgType::Notify, self.data_type, "");
        m.key = key.clone();
        m.time = self.time;
        m.src = self.writer.clone();
        m.src_aux = self.src_aux.clone();
        m.community = self.community.clone();
        match self.data_type {
            DataType::Double => m.dval = self.dval,
            DataType::String | DataType::Binary => m.sval = self.sval.clone(),
            DataType::NotSet => {}
        }
        m
    }

    fn reset(&mut self) {
        self.dval = 0.0;
        self.sval = Bytes::new();
        self.time = -1.0;
        self.written_time = -1.0;
        self.writer = Bytes::new();
        self.src_aux = Bytes::new();
        self.written_to = 0;
        self.stale = false;
        self.writers.clear();
        self.freq = 0.0;
        self.stats_time = f64::NEG_INFINITY;
        self.stats_writes = 0;
    }
}

/// A wildcard subscription (`MsgFilter`).
#[derive(Debug, Clone, PartialEq)]
struct Filter {
    app: Bytes,
    var: Bytes,
    period: f64,
}

impl Filter {
    fn matches(&self, src: &[u8], key: &[u8]) -> bool {
        wildcard_match(&self.app, src) && wildcard_match(&self.var, key)
    }
}

#[derive(Debug, Default, Clone)]
struct Timing {
    recent: VecDeque<f64>,
    last: f64,
    max: f64,
    min: f64,
}

impl Timing {
    fn add(&mut self, ms: f64) {
        if self.recent.is_empty() {
            self.max = ms;
            self.min = ms;
        }
        self.max = self.max.max(ms);
        self.min = self.min.min(ms);
        self.last = ms;
        if self.recent.len() == 5 {
            self.recent.pop_front();
        }
        self.recent.push_back(ms);
    }

    fn average(&self) -> f64 {
        self.recent.iter().sum::<f64>() / self.recent.len().max(1) as f64
    }
}

#[derive(Debug)]
struct ClientState {
    name: Bytes,
    asynchronous: bool,
    order: u64,
    last_heard: f64,
    held: VecDeque<Arc<Delivery>>,
    /// The queued packets' messages, one after the other (no buffer per packet).
    outbox: VecDeque<Arc<Delivery>>,
    /// Each queued packet's message count and encoded bytes, oldest first.
    packets: VecDeque<(usize, usize)>,
    outbox_msgs: usize,
    outbox_bytes: usize,
    dropped: u64,
    timing: Option<Timing>,
    unread: Unread,
    /// Listed in [`Database::waiting`] (it was given held mail since the last notify
    /// packet).
    listed: bool,
}

/// The connected clients: a slab indexed by [`ClientId::slot`] (no hash or tree walk per
/// subscriber a write reaches), each slot with the generation of the id it was last given.
#[derive(Debug, Default)]
struct Clients {
    slots: Vec<(u32, Option<ClientState>)>,
    free: Vec<usize>,
}

impl Clients {
    fn get(&self, id: ClientId) -> Option<&ClientState> {
        match self.slots.get(id.slot()) {
            Some((g, Some(c))) if *g == id.generation() => Some(c),
            _ => None,
        }
    }

    fn get_mut(&mut self, id: ClientId) -> Option<&mut ClientState> {
        match self.slots.get_mut(id.slot()) {
            Some((g, Some(c))) if *g == id.generation() => Some(c),
            _ => None,
        }
    }

    fn contains(&self, id: ClientId) -> bool {
        self.get(id).is_some()
    }

    /// Adds a client in a free slot (its generation moved on) or a new one.
    fn insert(&mut self, c: ClientState) -> ClientId {
        match self.free.pop() {
            Some(i) => {
                let slot = &mut self.slots[i];
                slot.0 = slot.0.wrapping_add(1).max(1);
                slot.1 = Some(c);
                ClientId::new(i, slot.0)
            }
            None => {
                self.slots.push((1, Some(c)));
                ClientId::new(self.slots.len() - 1, 1)
            }
        }
    }

    fn remove(&mut self, id: ClientId) -> Option<ClientState> {
        self.get(id)?;
        let c = self.slots[id.slot()].1.take();
        self.free.push(id.slot());
        c
    }

    /// The clients with their ids, in slot order.
    fn iter(&self) -> impl Iterator<Item = (ClientId, &ClientState)> {
        self.slots
            .iter()
            .enumerate()
            .filter_map(|(i, (g, c))| Some((ClientId::new(i, *g), c.as_ref()?)))
    }

    fn values(&self) -> impl Iterator<Item = &ClientState> {
        self.slots.iter().filter_map(|(_, c)| c.as_ref())
    }

    fn values_mut(&mut self) -> impl Iterator<Item = &mut ClientState> {
        self.slots.iter_mut().filter_map(|(_, c)| c.as_mut())
    }
}

impl ClientState {
    fn note_drop(&mut self, n: u64) {
        let before = self.dropped;
        self.dropped += n;
        if before == 0 || before / 1000 != self.dropped / 1000 {
            warn!(
                client = %String::from_utf8_lossy(&self.name),
                dropped_total = self.dropped,
                "client is not keeping up: oldest queued mail dropped"
            );
        }
    }

    fn hold(&mut self, msg: Arc<Delivery>, limit: usize) {
        if self.held.len() >= limit.max(1) {
            self.held.pop_front();
            self.note_drop(1);
        }
        self.held.push_back(msg);
    }

    /// Queues the messages as one packet (none: no packet); true if one was queued.
    fn queue(
        &mut self,
        packet: impl IntoIterator<Item = Arc<Delivery>>,
        limit: usize,
        byte_limit: usize,
    ) -> bool {
        let before = self.outbox.len();
        let mut bytes = 0;
        for m in packet {
            bytes += m.encoded_len;
            self.outbox.push_back(m);
        }
        let n = self.outbox.len() - before;
        if n == 0 {
            return false;
        }
        self.packets.push_back((n, bytes));
        self.outbox_msgs += n;
        self.outbox_bytes += bytes;
        while (self.outbox_msgs > limit || self.outbox_bytes > byte_limit) && self.packets.len() > 1
        {
            if let Some((n, bytes)) = self.packets.pop_front() {
                self.outbox.drain(..n);
                self.outbox_msgs -= n;
                self.outbox_bytes -= bytes;
                self.note_drop(n as u64);
            }
        }
        true
    }

    /// Queues the held mail as one packet (none held: no packet).
    fn queue_held(&mut self, limit: usize, byte_limit: usize) -> bool {
        let mut held = std::mem::take(&mut self.held);
        let queued = self.queue(held.drain(..), limit, byte_limit);
        // The held buffer is kept for the next mail.
        self.held = held;
        queued
    }
}

/// The MOOSDB core. See the module documentation.
#[derive(Debug)]
pub struct Database {
    config: DbConfig,
    db_name: Bytes,
    community: Bytes,
    start_time: f64,
    summary_time: f64,
    /// The variables by name (hashed: a write looks its variable up once; what lists
    /// them in order sorts, see [`Database::sorted_vars`]).
    vars: FxHashMap<VarName, Var>,
    clients: Clients,
    /// Clients given held mail since the last notify packet (each once, see
    /// [`ClientState::listed`]): the ones whose held mail a notify packet pushes.
    waiting: Vec<ClientId>,
    names: FxHashMap<Bytes, ClientId>,
    filters: BTreeMap<Bytes, Vec<Filter>>,
    /// The next client's connection order (`DB_CLIENTS` lists the newest first).
    next_order: u64,
    /// Variables whose every accepted write is kept for [`Database::take_taps`].
    tapped: Vec<Bytes>,
    taps: Vec<Message>,
}

/// Delivers `msg` into the held mail of client `id` (if connected), listing it in
/// `waiting`.
fn hold_for(
    clients: &mut Clients,
    waiting: &mut Vec<ClientId>,
    id: ClientId,
    msg: Arc<Delivery>,
    limit: usize,
) {
    if let Some(c) = clients.get_mut(id) {
        c.hold(msg, limit);
        if !c.listed {
            c.listed = true;
            waiting.push(id);
        }
    }
}

/// The id of the client called `name` and whether it drops `key`'s mail unread.
fn client_of(
    clients: &Clients,
    names: &FxHashMap<Bytes, ClientId>,
    name: &[u8],
    key: &[u8],
) -> Option<(ClientId, bool)> {
    let id = *names.get(name)?;
    Some((id, clients.get(id).is_some_and(|c| c.unread.covers(key))))
}

/// True when `a` and `b` hold the same bytes. The bus hands out one shared buffer per name,
/// so a name that repeats is mostly the very buffer kept: then nothing is compared.
fn same_text(a: &Bytes, b: &Bytes) -> bool {
    (a.as_ptr() == b.as_ptr() && a.len() == b.len()) || a == b
}

/// A variable's name as the DB's table keys it: held inline up to 24 bytes (most MOOS
/// names), so a write's look-up compares the name without reading another buffer.
type VarName = SmallVec<[u8; 24]>;

/// The DB's summaries, built only while some client reads them.
const LAZY_SUMMARIES: [&str; 2] = ["DB_VARSUMMARY", "DB_RWSUMMARY"];

impl Database {
    /// A DB started at `now`, holding its own (not yet written) variables.
    pub fn new(config: DbConfig, now: DbTime) -> Database {
        let community = Bytes::from(config.community.clone());
        let db_name = Bytes::from(format!("MOOSDB_{}", config.community));
        let mut vars = FxHashMap::default();
        for (key, dt) in [
            ("DB_TIME", DataType::Double),
            ("DB_UPTIME", DataType::Double),
            ("DB_CLIENTS", DataType::Double),
            ("DB_EVENT", DataType::String),
            ("DB_VARSUMMARY", DataType::String),
            ("DB_QOS", DataType::String),
            ("DB_RWSUMMARY", DataType::String),
        ] {
            let key = Bytes::from_static(key.as_bytes());
            let mut v = Var::new(key.clone(), dt);
            // The C++ DB names the writer of its not-yet-written variables with the name it
            // has before reading its community ("MOOSDB#1"); DB_VARSUMMARY shows it.
            v.writer = Bytes::from_static(b"MOOSDB#1");
            v.community = community.clone();
            v.written_time = now.moos;
            vars.insert(VarName::from_slice(&key), v);
        }
        Database {
            config,
            db_name,
            community,
            start_time: now.moos,
            summary_time: now.moos,
            vars,
            clients: Clients::default(),
            waiting: Vec::new(),
            names: FxHashMap::default(),
            filters: BTreeMap::new(),
            next_order: 1,
            tapped: Vec::new(),
            taps: Vec::new(),
        }
    }

    /// The DB's MOOS name, `MOOSDB_<community>`.
    pub fn name(&self) -> &str {
        std::str::from_utf8(&self.db_name).unwrap_or("MOOSDB")
    }

    /// The settings.
    pub fn config(&self) -> &DbConfig {
        &self.config
    }

    /// Handshake: admits a client called `name` or refuses a duplicate name.
    ///
    /// On success gives its id and the Welcome to send (`'W'`, data `'D'`, dval = skew =
    /// `now − client_time`, sval `asynchronous`, src_aux `hostname=..`, community) and posts
    /// `DB_EVENT = connected=NAME`. On a clash gives the Poison to send.
    pub fn connect(
        &mut self,
        name: Bytes,
        asynchronous: bool,
        client_time: f64,
        now: DbTime,
    ) -> Handshake {
        if self.names.contains_key(&name) {
            let mut p = Message::new(MsgType::Poison, DataType::String, "");
            p.time = now.moos;
            p.sval = Bytes::from(format!(
                "A client of this name (\"{}\") already exists",
                String::from_utf8_lossy(&name)
            ));
            return Handshake::Poison { reply: p };
        }
        let order = self.next_order;
        self.next_order += 1;
        let id = self.clients.insert(ClientState {
            name: name.clone(),
            asynchronous,
            order,
            last_heard: now.mono,
            held: VecDeque::new(),
            outbox: VecDeque::new(),
            packets: VecDeque::new(),
            outbox_msgs: 0,
            outbox_bytes: 0,
            dropped: 0,
            timing: None,
            unread: Unread::default(),
            listed: false,
        });
        self.names.insert(name.clone(), id);
        let mut w = Message::new(MsgType::Welcome, DataType::Double, "");
        w.time = now.moos;
        w.dval = now.moos - client_time;
        w.sval = Bytes::from_static(ASYNCHRONOUS.as_bytes());
        w.src_aux = Bytes::from(format!("hostname={}", self.config.host_name));
        w.community = self.community.clone();
        info!(client = %String::from_utf8_lossy(&name), asynchronous, "client connected");
        let event = format!("connected={}", String::from_utf8_lossy(&name));
        self.internal_notify("DB_EVENT", Value::String(event.into()), now);
        Handshake::Welcome { id, reply: w }
    }

    /// Handshake from the client's first message (`'i'`: sval = name, key `asynchronous` for
    /// V10 clients, compared case-insensitively). `None` (no readable name message) gives the
    /// Poison the C++ DB sends in that case.
    pub fn handshake(&mut self, first: Option<&Message>, now: DbTime) -> Handshake {
        match first {
            Some(m) => {
                let asynchronous = m.key.eq_ignore_ascii_case(ASYNCHRONOUS.as_bytes());
                self.connect(m.sval.clone(), asynchronous, m.time, now)
            }
            None => {
                let mut p = Message::new(MsgType::Poison, DataType::String, "");
                p.time = now.moos;
                p.sval = Bytes::from_static(b"Failed to read receive client's name");
                Handshake::Poison { reply: p }
            }
        }
    }

    /// Removes a client: its subscriptions, filters, held mail and outbox; posts
    /// `DB_EVENT = disconnected=NAME`. Returns its name, or `None` if it was not connected.
    pub fn disconnect(&mut self, id: ClientId, now: DbTime) -> Option<String> {
        let c = self.clients.remove(id)?;
        self.names.remove(&c.name);
        self.waiting.retain(|w| *w != id);
        for v in self.vars.values_mut() {
            v.subscribers.remove(&c.name);
        }
        self.filters.remove(&c.name);
        let name = String::from_utf8_lossy(&c.name).into_owned();
        if c.dropped > 0 {
            warn!(client = %name, dropped_total = c.dropped, "client left; it had mail dropped");
        }
        info!(client = %name, "client disconnected");
        let event = format!("disconnected={name}");
        self.internal_notify("DB_EVENT", Value::String(event.into()), now);
        Some(name)
    }

    /// Removes every client silent for longer than the client timeout (unwarped
    /// `now.mono`); returns their ids and names.
    pub fn reap_silent(&mut self, now: DbTime) -> Vec<(ClientId, String)> {
        let timeout = self.config.client_timeout;
        // In connection order, as their DB_EVENTs come.
        let mut silent: Vec<(u64, ClientId)> = self
            .clients
            .iter()
            .filter(|(_, c)| now.mono - c.last_heard > timeout)
            .map(|(id, c)| (c.order, id))
            .collect();
        silent.sort_unstable();
        let silent = silent.into_iter().map(|(_, id)| id);
        let mut out = Vec::new();
        for id in silent {
            if let Some(name) = self.disconnect(id, now) {
                warn!(client = %name, "disconnecting after {timeout} seconds of silence");
                out.push((id, name));
            }
        }
        out
    }

    /// Processes one packet from a client (`OnRxPkt` plus the threaded server's rules).
    ///
    /// A leading `'T'` is echoed first with dval = DB time and dval2 = 0. Then every message
    /// is processed in order, the DB variables are refreshed if more than 2 s passed, and the
    /// reply is queued: for an asynchronous client `[T echo] + held mail + request replies`
    /// if non-empty (held mail only if something besides the T came); for a synchronous
    /// client always `[NULL(dval = DB time)] + held mail + replies`. If the packet carried a
    /// notify, every asynchronous client's held mail is then pushed as its own packet.
    ///
    /// The packet is any sequence of messages (a decoded `Vec`, or an in-process caller's
    /// iterator, which needs no buffer of its own), each a [`Message`] or a posted [`Mail`]
    /// ([`Incoming`]).
    pub fn handle(
        &mut self,
        id: ClientId,
        msgs: impl IntoIterator<Item = impl Into<Incoming>>,
        now: DbTime,
    ) -> Result<Effects, DbError> {
        let mut effects = Effects::default();
        self.handle_into(id, msgs, now, &mut effects)?;
        Ok(effects)
    }

    /// [`Database::handle`] with the effects written into `effects` (cleared first), so an
    /// in-process caller reuses one buffer. An in-process client posts its notifies as the
    /// mail they deliver ([`Incoming::Posted`]): the DB stores and queues them as they are,
    /// and its in-process readers get that mail with no conversion.
    pub fn handle_into(
        &mut self,
        id: ClientId,
        msgs: impl IntoIterator<Item = impl Into<Incoming>>,
        now: DbTime,
        effects: &mut Effects,
    ) -> Result<(), DbError> {
        effects.ready.clear();
        // Each message is shared at once: the DB moves a pointer from here on.
        let msgs = msgs.into_iter().map(|m| Delivery::of(m.into()));
        self.packet(id, msgs, false, now, &mut effects.ready)
    }

    /// What [`Database::handle_into`] does with a packet of one `'.'` (a poll: the client's
    /// held mail is queued), without building the message.
    pub fn poll_into(
        &mut self,
        id: ClientId,
        now: DbTime,
        effects: &mut Effects,
    ) -> Result<(), DbError> {
        effects.ready.clear();
        self.packet(id, std::iter::empty(), true, now, &mut effects.ready)
    }

    /// A packet's processing; `polled`: it held a message that needs no processing (a
    /// `'.'`) besides `msgs`.
    fn packet(
        &mut self,
        id: ClientId,
        msgs: impl IntoIterator<Item = Arc<Delivery>>,
        polled: bool,
        now: DbTime,
        ready: &mut Vec<ClientId>,
    ) -> Result<(), DbError> {
        let c = self.clients.get_mut(id).ok_or(DbError::UnknownClient(id))?;
        c.last_heard = now.mono;
        let asynchronous = c.asynchronous;
        let mut echo = None;
        let mut msgs = msgs.into_iter().peekable();
        if let Some(t) = msgs.next_if(|m| m.body.msg_type() == MsgType::Timing) {
            let mut t = Delivery::into_message(t);
            c.timing
                .get_or_insert_with(Timing::default)
                .add((now.moos - t.time) * 1000.0);
            t.dval = now.moos;
            t.dval2 = 0.0;
            echo = Some(t);
        }
        let mut had_notify = false;
        let mut had_any = polled;
        let mut replies = VecDeque::new();
        // The client's name, taken when a message other than a notify needs it.
        let mut name: Option<Bytes> = None;
        for m in msgs {
            had_any = true;
            if m.is_notify() {
                had_notify = true;
                self.on_notify(m, now);
            } else {
                let name = match &name {
                    Some(n) => n.clone(),
                    None => {
                        let n = self.clients.get(id).map(|c| c.name.clone());
                        name.get_or_insert(n.unwrap_or_default()).clone()
                    }
                };
                self.process(&name, Delivery::into_message(m), now, &mut replies);
            }
        }
        if now.moos - self.summary_time > SUMMARY_PERIOD {
            self.summary_time = now.moos;
            self.publish_summaries(now);
        }
        let limit = self.config.outbox_limit;
        let byte_limit = self.config.outbox_byte_limit;
        if let Some(c) = self.clients.get_mut(id) {
            let take_held = had_any || !asynchronous;
            let head = if asynchronous {
                echo
            } else {
                let mut null = Message::new(MsgType::Null, DataType::Double, "");
                null.time = now.moos;
                null.dval = now.moos;
                Some(null)
            };
            let mut held = std::mem::take(&mut c.held);
            let held_part = held.drain(..if take_held { held.len() } else { 0 });
            let queued = c.queue(
                head.into_iter()
                    .map(Delivery::new)
                    .chain(held_part)
                    .chain(replies.into_iter().map(Delivery::new)),
                limit,
                byte_limit,
            );
            c.held = held;
            if queued {
                ready.push(id);
            }
        }
        if had_notify {
            // Only the clients given held mail since the last notify packet can have any.
            let first = ready.len();
            for cid in self.waiting.drain(..) {
                let Some(c) = self.clients.get_mut(cid) else {
                    continue;
                };
                c.listed = false;
                if c.asynchronous && !c.held.is_empty() {
                    c.queue_held(limit, byte_limit);
                    if !ready.contains(&cid) {
                        ready.push(cid);
                    }
                }
            }
            // In id order, as they would be found in the table.
            ready[first..].sort_unstable();
        }
        Ok(())
    }

    /// Moves the client's queued packets into `out`; `false` if the client is gone (the edge
    /// should then close its connection).
    pub fn drain_outbox(&mut self, id: ClientId, out: &mut Vec<Vec<Message>>) -> bool {
        match self.clients.get_mut(id) {
            Some(c) => {
                for (n, _) in c.packets.drain(..) {
                    out.push(c.outbox.drain(..n).map(Delivery::into_message).collect());
                }
                c.outbox_msgs = 0;
                c.outbox_bytes = 0;
                true
            }
            None => false,
        }
    }

    /// Moves the messages of the client's queued packets into `out`, one after the other
    /// (an in-process client needs no packet boundaries, and no buffer per packet);
    /// `false` if the client is gone.
    pub fn drain_messages(&mut self, id: ClientId, out: &mut Vec<Message>) -> bool {
        match self.clients.get_mut(id) {
            Some(c) => {
                out.extend(c.outbox.drain(..).map(Delivery::into_message));
                c.packets.clear();
                c.outbox_msgs = 0;
                c.outbox_bytes = 0;
                true
            }
            None => false,
        }
    }

    /// [`Database::drain_messages`] without copies: the shared deliveries themselves (an
    /// in-process reader takes each one's [`Delivery::mail`]).
    pub fn drain_deliveries(&mut self, id: ClientId, out: &mut Vec<Arc<Delivery>>) -> bool {
        match self.clients.get_mut(id) {
            Some(c) => {
                out.extend(c.outbox.drain(..));
                c.packets.clear();
                c.outbox_msgs = 0;
                c.outbox_bytes = 0;
                true
            }
            None => false,
        }
    }

    /// Tells the DB which variables client `id` drops unread although its registrations
    /// match them (an in-process pLogger's omitted variables): they are no longer delivered
    /// to it. With [`DbConfig::lazy_summaries`], `DB_VARSUMMARY`/`DB_RWSUMMARY` are then
    /// built at their 2 s refresh only while some client does read them or a tap keeps them
    /// (otherwise their write is recorded, time, writer and frequency, without the text; a
    /// client that registers later, or [`Database::current`], gets the text built when it
    /// asks). Applies to the client's existing registrations too. `false` if the client is
    /// not connected.
    pub fn set_unread(&mut self, id: ClientId, unread: Unread) -> bool {
        let Some(c) = self.clients.get_mut(id) else {
            return false;
        };
        let name = c.name.clone();
        for (k, v) in self.vars.iter_mut() {
            if let Some(sub) = v.subscribers.get_mut(&name) {
                sub.unread = unread.covers(k);
            }
        }
        c.unread = unread;
        true
    }

    /// True when some client reads `key`'s mail (a registration not marked unread) or a
    /// tap keeps its writes.
    fn is_read(&self, key: &str) -> bool {
        self.tapped.iter().any(|t| t[..] == *key.as_bytes())
            || self
                .vars
                .get(key.as_bytes())
                .is_some_and(|v| v.subscribers.values().any(|s| !s.unread))
    }

    /// The text of a lazily built DB summary as it would be built now (empty for any
    /// other variable).
    fn summary_text(&self, key: &[u8]) -> String {
        match key {
            b"DB_VARSUMMARY" => self.var_summary(),
            b"DB_RWSUMMARY" => self.rw_summary(&self.ordered_clients()),
            _ => String::new(),
        }
    }

    /// Records a write of a DB summary nobody reads: everything but its text.
    fn skip_summary(&mut self, key: &'static str, now: DbTime) {
        self.internal_notify(key, Value::String(String::new().into()), now);
        if let Some(v) = self.vars.get_mut(key.as_bytes()) {
            v.stale = true;
        }
    }

    /// Messages dropped so far for a client because it did not keep up.
    pub fn dropped(&self, id: ClientId) -> Option<u64> {
        self.clients.get(id).map(|c| c.dropped)
    }

    /// The id of the connected client called `name`.
    pub fn client_id(&self, name: &str) -> Option<ClientId> {
        self.names.get(name.as_bytes()).copied()
    }

    /// True if `id` is connected.
    pub fn is_connected(&self, id: ClientId) -> bool {
        self.clients.contains(id)
    }

    /// Names of the connected clients, newest first (the order of `DB_CLIENTS`).
    pub fn client_names(&self) -> Vec<String> {
        self.ordered_clients()
            .into_iter()
            .map(|n| String::from_utf8_lossy(&n).into_owned())
            .collect()
    }

    /// Keeps every accepted write of `key` from now on, for [`Database::take_taps`]: an
    /// in-process observer sees each posting, not only the latest value (as a MOOS client
    /// with a zero-period subscription would, without being one).
    pub fn tap(&mut self, key: &str) {
        let k = Bytes::copy_from_slice(key.as_bytes());
        if !self.tapped.contains(&k) {
            self.tapped.push(k);
        }
    }

    /// The tapped writes since the last call, in the order they were made.
    pub fn take_taps(&mut self) -> Vec<Message> {
        std::mem::take(&mut self.taps)
    }

    /// The current value of a variable as the DB would replay it, if it was ever written.
    pub fn current(&self, key: &str) -> Option<Message> {
        let v = self.vars.get(key.as_bytes())?;
        let mut m = (v.written_to > 0).then(|| v.to_msg(&v.key))?;
        if v.stale {
            m.sval = self.summary_text(&v.key).into();
        }
        Some(m)
    }

    /// Names of the clients subscribed to `key`, sorted.
    pub fn subscribers(&self, key: &str) -> Vec<String> {
        self.vars
            .get(key.as_bytes())
            .map(|v| {
                v.subscribers
                    .keys()
                    .map(|k| String::from_utf8_lossy(k).into_owned())
                    .collect()
            })
            .unwrap_or_default()
    }

    /// Names of all variables (written or only registered), sorted.
    pub fn var_names(&self) -> Vec<String> {
        self.sorted_vars()
            .into_iter()
            .map(|(k, _)| String::from_utf8_lossy(k).into_owned())
            .collect()
    }

    /// The variables in name order (the order of every list the DB makes of them).
    fn sorted_vars(&self) -> Vec<(&Bytes, &Var)> {
        let mut v: Vec<(&Bytes, &Var)> = self.vars.values().map(|v| (&v.key, v)).collect();
        v.sort_unstable_by(|a, b| a.0.cmp(b.0));
        v
    }

    fn ordered_clients(&self) -> Vec<Bytes> {
        let mut v: Vec<(u64, Bytes)> = self
            .clients
            .values()
            .map(|c| (c.order, c.name.clone()))
            .collect();
        v.sort_by_key(|c| std::cmp::Reverse(c.0));
        v.into_iter().map(|(_, n)| n).collect()
    }

    fn process(&mut self, name: &Bytes, m: Message, now: DbTime, replies: &mut VecDeque<Message>) {
        match m.msg_type {
            MsgType::Notify => self.on_notify(Delivery::new(m), now),
            MsgType::Register => self.on_register(name, &m.key, m.dval, now),
            MsgType::Unregister => {
                if let Some(v) = self.vars.get_mut(&m.key[..]) {
                    v.subscribers.remove(name);
                }
            }
            MsgType::WildcardRegister => {
                let spec = &m.sval;
                let app = val_from_string(spec, b"AppPattern").unwrap_or_default();
                let var = val_from_string(spec, b"VarPattern").unwrap_or_default();
                let period = val_from_string(spec, b"Interval")
                    .and_then(|p| std::str::from_utf8(&p).ok()?.parse::<f64>().ok())
                    .unwrap_or(0.0);
                let f = Filter {
                    app: Bytes::from(app),
                    var: Bytes::from(var),
                    period,
                };
                let list = self.filters.entry(name.clone()).or_default();
                if !list.contains(&f) {
                    list.push(f.clone());
                }
                let keys: Vec<Bytes> = self
                    .sorted_vars()
                    .into_iter()
                    .filter(|(k, v)| f.matches(&v.writer, k))
                    .map(|(k, _)| k.clone())
                    .collect();
                for k in keys {
                    self.on_register(name, &k, period, now);
                }
            }
            MsgType::WildcardUnregister => {
                let app = val_from_string(&m.sval, b"AppPattern").unwrap_or_default();
                let var = val_from_string(&m.sval, b"VarPattern").unwrap_or_default();
                if let Some(list) = self.filters.get_mut(name) {
                    list.retain(|f| f.app != app[..] || f.var != var[..]);
                }
                let f = Filter {
                    app: Bytes::from(app),
                    var: Bytes::from(var),
                    period: 0.0,
                };
                for (k, v) in self.vars.iter_mut() {
                    if f.matches(&v.writer, k) {
                        v.subscribers.remove(name);
                    }
                }
            }
            MsgType::ServerRequest => self.server_request(&m, now, replies),
            _ => {}
        }
    }

    fn on_register(&mut self, name: &Bytes, key: &Bytes, period: f64, now: DbTime) {
        if name.is_empty() {
            return;
        }
        let limit = self.config.outbox_limit;
        let Some((id, unread)) = client_of(&self.clients, &self.names, name, key) else {
            return;
        };
        let already = self.vars.contains_key(&key[..]);
        let var = self
            .vars
            .entry(VarName::from_slice(key))
            .or_insert_with(|| Var::new(key.clone(), DataType::NotSet));
        let written = var.written_to != 0;
        let stale = var.stale;
        let reply = (already && written && !unread).then(|| var.to_msg(key));
        let sub = var.subscribers.get_or_insert(
            name,
            Sub {
                client: id,
                period,
                last_sent: f64::NEG_INFINITY,
                unread,
            },
        );
        sub.period = period;
        if let Some(mut reply) = reply {
            sub.last_sent = now.moos;
            if stale {
                reply.sval = self.summary_text(key).into();
            }
            hold_for(
                &mut self.clients,
                &mut self.waiting,
                id,
                Delivery::new(reply),
                limit,
            );
        }
    }

    /// `OnNotify`: type lock, first-write wildcard matching, value store and fan-out.
    fn on_notify(&mut self, mut d: Arc<Delivery>, now: DbTime) {
        let limit = self.config.outbox_limit;
        Delivery::fill_community(&mut d, &self.community);
        // A write to a known variable looks it up once and clones no name.
        let var = match self.vars.get_mut(&d.body.key()[..]) {
            Some(var) => var,
            None => {
                let key = d.body.key();
                self.vars
                    .entry(VarName::from_slice(key))
                    .or_insert_with(|| Var::new(key.clone(), d.body.data_type()))
            }
        };
        if let Some(d) = Arc::get_mut(&mut d) {
            d.body.share_key(&var.key);
        }
        let incoming = &d.body;
        let (key, src) = (incoming.key(), incoming.src());
        let data_type = incoming.data_type();
        if var.written_to == 0 {
            var.data_type = data_type;
            for (client, filters) in &self.filters {
                for f in filters {
                    if f.matches(src, key)
                        && let Some((id, unread)) =
                            client_of(&self.clients, &self.names, client, key)
                    {
                        var.subscribers.insert(
                            client,
                            Sub {
                                client: id,
                                period: f.period,
                                last_sent: f64::NEG_INFINITY,
                                unread,
                            },
                        );
                    }
                }
            }
        }
        if var.data_type != data_type {
            warn!(
                var = %String::from_utf8_lossy(key),
                var_type = %(var.data_type.code() as char),
                msg_type = %(data_type.code() as char),
                src = %String::from_utf8_lossy(src),
                "write rejected: variable type is locked by its first write"
            );
            return;
        }
        let t = now.moos;
        var.written_time = t;
        var.time = incoming.time();
        // The writer, its aux field and community mostly repeat: a name is replaced (and the
        // writers looked up) only when it changed.
        if var.written_to == 0 || !same_text(&var.writer, src) {
            if !var.writers.contains(src) {
                var.writers.insert(src.clone());
            }
            var.writer = src.clone();
        }
        let aux = incoming.src_aux();
        if !same_text(&var.src_aux, aux) {
            var.src_aux = aux.clone();
        }
        let community = incoming.community();
        if !same_text(&var.community, community) {
            var.community = community.clone();
        }
        match var.data_type {
            DataType::Double => var.dval = incoming.dval(),
            _ => var.sval = incoming.sval(),
        }
        var.written_to += 1;
        let dt = t - var.stats_time;
        if dt > 0.5 {
            if dt > 10.0 {
                var.freq = 0.0;
            } else {
                let writes = (var.written_to - var.stats_writes).max(1) as f64;
                var.freq = 0.5 * var.freq + 0.5 / (dt / writes);
            }
            var.stats_writes = var.written_to;
            var.stats_time = t;
        }
        if !self.tapped.is_empty() && self.tapped.contains(incoming.key()) {
            self.taps.push(incoming.to_message());
        }
        // One shared delivery for every subscriber it reaches.
        for sub in var.subscribers.values_mut() {
            if !sub.unread && sub.expired(t) {
                sub.last_sent = t;
                hold_for(
                    &mut self.clients,
                    &mut self.waiting,
                    sub.client,
                    Arc::clone(&d),
                    limit,
                );
            }
        }
    }

    fn internal_notify(&mut self, key: &'static str, value: Value, now: DbTime) {
        let mut m = Message::notify("", value, now.moos);
        m.key = Bytes::from_static(key.as_bytes());
        m.src = self.db_name.clone();
        m.community = self.community.clone();
        self.on_notify(Delivery::new(m), now);
    }

    fn server_request(&mut self, m: &Message, now: DbTime, replies: &mut VecDeque<Message>) {
        let key = &m.key[..];
        let contains = |needle: &[u8]| key.windows(needle.len()).any(|w| w == needle);
        if key == b"ALL" {
            for (k, v) in self.sorted_vars() {
                let mut r = v.to_msg(k);
                r.id = m.id;
                r.dval = v.dval;
                r.sval = if v.stale {
                    self.summary_text(k).into()
                } else {
                    v.sval.clone()
                };
                r.dval2 = v.freq;
                r.time = v.written_time - self.start_time;
                if r.time < 0.0 {
                    r.time = -1.0;
                }
                replies.push_front(r);
            }
        } else if contains(b"PROC_SUMMARY") {
            for who in self.ordered_clients() {
                let mut subs = String::from("SUBSCRIBED=");
                let mut pubs = String::from("PUBLISHED=");
                for (k, v) in self.sorted_vars() {
                    let k = String::from_utf8_lossy(k);
                    if v.writers.contains(&who) {
                        pubs.push(',');
                        pubs.push_str(&k);
                    }
                    if v.subscribers.contains_key(&who) {
                        subs.push(',');
                        subs.push_str(&k);
                    }
                }
                let mut r = Message::new(MsgType::Notify, DataType::String, "PROC_SUMMARY");
                r.id = m.id;
                r.time = now.moos - self.start_time;
                r.src = self.db_name.clone();
                r.sval = Bytes::from(format!("{}:{subs},{pubs}", String::from_utf8_lossy(&who)));
                replies.push_front(r);
            }
        } else if contains(b"VAR_SUMMARY") {
            let mut all = Vec::new();
            for (i, (k, _)) in self.sorted_vars().into_iter().enumerate() {
                if i > 0 {
                    all.push(b',');
                }
                all.extend_from_slice(k);
            }
            let mut r = Message::new(MsgType::Notify, DataType::String, "VAR_SUMMARY");
            r.id = m.id;
            r.time = now.moos;
            r.src = self.db_name.clone();
            r.sval = Bytes::from(all);
            replies.push_front(r);
        } else if contains(b"DB_CLEAR") {
            info!(
                "DB_CLEAR requested: resetting {} variables",
                self.vars.len()
            );
            for v in self.vars.values_mut() {
                v.reset();
            }
            for c in self.clients.values_mut() {
                c.held.clear();
            }
            self.start_time = now.moos;
        }
    }

    fn publish_summaries(&mut self, now: DbTime) {
        let t = now.moos;
        self.internal_notify("DB_TIME", Value::Double(t), now);
        self.internal_notify("DB_UPTIME", Value::Double(t - self.start_time), now);
        let clients = self.ordered_clients();
        let mut list = Vec::new();
        for c in &clients {
            list.extend_from_slice(c);
            list.push(b',');
        }
        // Client names are UTF-8 in practice; others are read lossily.
        let list = String::from_utf8(list)
            .unwrap_or_else(|e| String::from_utf8_lossy(e.as_bytes()).into_owned());
        self.internal_notify("DB_CLIENTS", Value::String(list.into()), now);
        // DB_VARSUMMARY shows DB_RWSUMMARY's text: both are built while the first is read.
        let lazy = self.config.lazy_summaries;
        let read_var = !lazy || self.is_read(LAZY_SUMMARIES[0]);
        let read_rw = read_var || self.is_read(LAZY_SUMMARIES[1]);
        if read_var {
            let summary = self.var_summary();
            self.internal_notify("DB_VARSUMMARY", Value::String(summary.into()), now);
            if let Some(v) = self.vars.get_mut(&b"DB_VARSUMMARY"[..]) {
                v.stale = false;
            }
        } else {
            self.skip_summary("DB_VARSUMMARY", now);
        }
        let mut qos = String::new();
        let mut by_name: Vec<&ClientState> = self.clients.values().collect();
        by_name.sort_by(|a, b| a.name.cmp(&b.name));
        for c in by_name {
            if let Some(tm) = &c.timing {
                let _ = write!(
                    qos,
                    "{}={}:{}:{}:{},",
                    String::from_utf8_lossy(&c.name),
                    fmt_g6(tm.last),
                    fmt_g6(tm.max),
                    fmt_g6(tm.min),
                    fmt_g6(tm.average())
                );
            }
        }
        self.internal_notify("DB_QOS", Value::String(qos.into()), now);
        if read_rw {
            let rw = self.rw_summary(&clients);
            self.internal_notify("DB_RWSUMMARY", Value::String(rw.into()), now);
            if let Some(v) = self.vars.get_mut(&b"DB_RWSUMMARY"[..]) {
                v.stale = false;
            }
        } else {
            self.skip_summary("DB_RWSUMMARY", now);
        }
    }

    fn var_summary(&self) -> String {
        let mut s = String::new();
        for (k, v) in self.sorted_vars() {
            let who = if v.writer.is_empty() {
                "(write pending)".into()
            } else {
                String::from_utf8_lossy(&v.writer)
            };
            let _ = write!(
                s,
                "{:<20} {:<20} {:<20} {:<4.1}Hz {:<2} ",
                String::from_utf8_lossy(k),
                TimeOfDay(v.written_time),
                who,
                v.freq,
                v.data_type.code() as char
            );
            match v.data_type {
                DataType::Double => {
                    let _ = write!(s, "{:.1}", v.dval);
                }
                DataType::String => {
                    if v.sval.len() > 25 {
                        s.push_str(&String::from_utf8_lossy(&v.sval[..22]));
                        s.push_str("...");
                    } else {
                        s.push_str(&String::from_utf8_lossy(&v.sval));
                    }
                }
                DataType::Binary => {
                    let n = v.sval.len();
                    if n < 1024 {
                        let _ = write!(s, "*binary* {n:<4} B");
                    } else if n < 1024 * 1024 {
                        let _ = write!(s, "*binary* {:.3} KB", n as f64 / 1024.0);
                    } else {
                        let _ = write!(s, "*binary* {:.3} MB", n as f64 / (1024.0 * 1024.0));
                    }
                }
                DataType::NotSet => {}
            }
            s.push('\n');
        }
        s
    }

    fn rw_summary(&self, clients: &[Bytes]) -> String {
        let vars = self.sorted_vars();
        let mut out = String::new();
        for (i, who) in clients.iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            out.push_str(&String::from_utf8_lossy(who));
            out.push('=');
            let subs = vars.iter().filter(|(_, v)| v.subscribers.contains_key(who));
            push_joined(&mut out, subs.map(|(k, _)| *k), ':');
            out.push('&');
            let pubs = vars.iter().filter(|(_, v)| v.writers.contains(who));
            push_joined(&mut out, pubs.map(|(k, _)| *k), ':');
        }
        out
    }
}

/// Appends the names read lossily as text, separated by `sep`.
fn push_joined<'a>(out: &mut String, names: impl Iterator<Item = &'a Bytes>, sep: char) {
    for (i, n) in names.enumerate() {
        if i > 0 {
            out.push(sep);
        }
        out.push_str(&String::from_utf8_lossy(n));
    }
}

/// `MOOSValFromString`: the value of `token` (case-insensitive) in a `tok=val,tok=val`
/// string, trimmed.
///
/// ```
/// use moosdb::db::val_from_string;
/// let s = b"AppPattern=*,VarPattern=NAV_*,Interval=0";
/// assert_eq!(val_from_string(s, b"varpattern").as_deref(), Some(&b"NAV_*"[..]));
/// ```
pub fn val_from_string(s: &[u8], token: &[u8]) -> Option<Vec<u8>> {
    for part in s.split(|&b| b == b',') {
        let Some(eq) = part.iter().position(|&b| b == b'=') else {
            continue;
        };
        if part[..eq].trim_ascii().eq_ignore_ascii_case(token) {
            return Some(part[eq + 1..].trim_ascii().to_vec());
        }
    }
    None
}

/// `MOOSWildCmp`: the workspace's one definition ([`moos_types::text::wildcard_match`]).
pub use moos_types::text::wildcard_match;

/// `HH:MM:SS.mmm` of a Unix time, in UTC (the C++ DB prints local time).
pub fn time_of_day(t: f64) -> String {
    TimeOfDay(t).to_string()
}

/// [`time_of_day`] as a `Display` (a width pads on the right, as `{:<20}` in
/// `DB_VARSUMMARY`), without a temporary string.
struct TimeOfDay(f64);

impl std::fmt::Display for TimeOfDay {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let t = self.0;
        let secs = t.floor();
        let ms = ((t - secs) * 1000.0).floor() as i64;
        let day = (secs as i64).rem_euclid(86_400);
        write!(
            f,
            "{:02}:{:02}:{:02}.{:03}",
            day / 3600,
            (day / 60) % 60,
            day % 60,
            ms.clamp(0, 999)
        )?;
        // Every field is in range, so the text is always 12 characters; a width pads it on
        // the right (the left alignment `DB_VARSUMMARY` asks for).
        for _ in 12..f.width().unwrap_or(0) {
            f.write_char(f.fill())?;
        }
        Ok(())
    }
}

/// A double as C++ `ostream <<` prints it by default (`%g`, 6 significant digits).
///
/// ```
/// use moosdb::db::fmt_g6;
/// assert_eq!(fmt_g6(0.406981234), "0.406981");
/// assert_eq!(fmt_g6(0.0), "0");
/// assert_eq!(fmt_g6(1795217436.0), "1.79522e+09");
/// ```
pub fn fmt_g6(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return if x.is_nan() {
            "nan".into()
        } else if x.is_infinite() {
            if x > 0.0 { "inf".into() } else { "-inf".into() }
        } else {
            "0".into()
        };
    }
    let sci = format!("{x:.5e}");
    let (mant, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    if !(-4..6).contains(&exp) {
        let mant = trim_zeros(mant);
        let sign = if exp < 0 { '-' } else { '+' };
        format!("{mant}e{sign}{:02}", exp.abs())
    } else {
        let decimals = (5 - exp).max(0) as usize;
        trim_zeros(&format!("{x:.decimals$}")).to_string()
    }
}

fn trim_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(moos: f64) -> DbTime {
        DbTime { moos, mono: moos }
    }

    fn reg(key: &str, period: f64) -> Message {
        let mut m = Message::new(MsgType::Register, DataType::Double, key);
        m.dval = period;
        m
    }

    fn post(src: &str, key: &str, v: Value, time: f64) -> Message {
        let mut m = Message::notify(key, v, time);
        m.src = Bytes::from(src.to_string());
        m
    }

    fn drain(db: &mut Database, id: ClientId) -> Vec<Message> {
        let mut p = Vec::new();
        assert!(db.drain_outbox(id, &mut p));
        p.concat()
    }

    fn new_db() -> Database {
        let cfg = DbConfig {
            community: "test".into(),
            ..DbConfig::default()
        };
        Database::new(cfg, t(1000.0))
    }

    fn lazy_db() -> Database {
        let cfg = DbConfig {
            community: "test".into(),
            lazy_summaries: true,
            ..DbConfig::default()
        };
        Database::new(cfg, t(1000.0))
    }

    fn join(db: &mut Database, name: &str, now: f64) -> ClientId {
        db.connect(Bytes::from(name.to_string()), true, now, t(now))
            .id()
            .unwrap()
    }

    #[test]
    fn a_client_that_reconnects_under_its_name_gets_a_new_id() {
        let mut db = new_db();
        let a = join(&mut db, "a", 1000.0);
        let s = join(&mut db, "s", 1000.0);
        db.handle(s, vec![reg("X", 0.0)], t(1000.0)).unwrap();
        assert_eq!(db.disconnect(s, t(1000.1)).as_deref(), Some("s"));
        // The slot is taken again, under a new id: the old one names nobody.
        let s2 = join(&mut db, "s", 1000.2);
        assert_ne!(s, s2);
        assert!(!db.is_connected(s) && db.is_connected(s2));
        assert_eq!(db.client_id("s"), Some(s2));
        assert_eq!(
            db.poll_into(s, t(1000.3), &mut Effects::default()),
            Err(DbError::UnknownClient(s))
        );
        // The registration left with the old client; the new one makes its own.
        assert!(db.subscribers("X").is_empty());
        db.handle(s2, vec![reg("X", 0.0)], t(1000.3)).unwrap();
        let fx = db
            .handle(
                a,
                vec![post("a", "X", Value::Double(1.0), 1000.4)],
                t(1000.4),
            )
            .unwrap();
        assert_eq!(fx.ready, vec![s2]);
        let got = drain(&mut db, s2);
        assert_eq!(keys(&got), ["X"]);
        assert!(!db.drain_outbox(s, &mut Vec::new()));
        // DB_CLIENTS lists the newest first.
        assert_eq!(db.client_names(), ["s", "a"]);
    }

    #[test]
    fn register_interval_filters_fan_out() {
        let mut db = new_db();
        let s = join(&mut db, "s", 1000.0);
        let p = join(&mut db, "p", 1000.0);
        db.handle(s, vec![reg("X", 1.0)], t(1000.0)).unwrap();
        for (i, now) in [1000.0, 1000.5, 1001.0, 1001.2, 1002.1].iter().enumerate() {
            db.handle(
                p,
                vec![post("p", "X", Value::Double(i as f64), *now)],
                t(*now),
            )
            .unwrap();
        }
        let got: Vec<f64> = drain(&mut db, s)
            .iter()
            .filter(|m| m.key_str() == "X")
            .map(|m| m.dval)
            .collect();
        assert_eq!(got, vec![0.0, 2.0, 4.0]);
    }

    #[test]
    fn type_is_locked_by_first_write() {
        let mut db = new_db();
        let p = join(&mut db, "p", 1000.0);
        db.handle(p, vec![post("p", "X", Value::Double(1.0), 1.0)], t(1000.0))
            .unwrap();
        db.handle(p, vec![post("p", "X", Value::from("no"), 1.0)], t(1000.1))
            .unwrap();
        let cur = db.current("X").unwrap();
        assert_eq!(cur.data_type, DataType::Double);
        assert_eq!(cur.dval, 1.0);
    }

    #[test]
    fn silent_client_removed_after_timeout_not_before() {
        let mut db = new_db();
        let a = join(&mut db, "a", 0.0);
        let b = join(&mut db, "b", 0.0);
        let at = |mono: f64| DbTime {
            moos: 1000.0 + mono,
            mono,
        };
        db.handle(b, Vec::<Message>::new(), at(4.0)).unwrap();
        assert!(db.reap_silent(at(5.0)).is_empty());
        let gone = db.reap_silent(at(5.01));
        assert_eq!(gone, vec![(a, "a".to_string())]);
        assert!(!db.is_connected(a) && db.is_connected(b));
        assert_eq!(db.reap_silent(at(9.5)), vec![(b, "b".to_string())]);
    }

    #[test]
    fn summary_refreshes_only_after_two_seconds() {
        let mut db = new_db();
        let c = join(&mut db, "c", 1000.0);
        db.handle(c, vec![reg("DB_CLIENTS", 0.0)], t(1001.0))
            .unwrap();
        assert!(db.current("DB_CLIENTS").is_none());
        db.handle(c, Vec::<Message>::new(), t(1002.0)).unwrap();
        assert!(db.current("DB_TIME").is_none());
        db.handle(c, Vec::<Message>::new(), t(1002.01)).unwrap();
        assert_eq!(db.current("DB_TIME").unwrap().dval, 1002.01);
        assert_eq!(db.current("DB_UPTIME").unwrap().dval, 1002.01 - 1000.0);
        assert_eq!(db.current("DB_CLIENTS").unwrap().sval_str(), "c,");
    }

    fn wildcard_all() -> Message {
        let mut wr = Message::new(MsgType::WildcardRegister, DataType::String, "");
        wr.sval = Bytes::from_static(b"AppPattern=*,VarPattern=*,Interval=0");
        wr
    }

    fn keys(msgs: &[Message]) -> Vec<String> {
        msgs.iter().map(|m| m.key_str().into_owned()).collect()
    }

    #[test]
    fn summaries_nobody_reads_are_not_built_nor_delivered() {
        // Without lazy summaries the texts are built all the same; unread mail is not sent.
        let mut eager = new_db();
        let logger = join(&mut eager, "logger", 1000.0);
        let omit = Unread {
            patterns: vec![Bytes::from_static(b"DB_*SUMMARY")],
            except: Vec::new(),
        };
        assert!(eager.set_unread(logger, omit));
        eager
            .handle(logger, vec![wildcard_all()], t(1000.0))
            .unwrap();
        eager
            .handle(
                logger,
                vec![post("logger", "X", Value::Double(1.0), 1.0)],
                t(1002.5),
            )
            .unwrap();
        let var = eager.vars.get(&b"DB_VARSUMMARY"[..]).unwrap();
        assert!(!var.stale && var.sval.len() > 100);
        assert!(
            !keys(&drain(&mut eager, logger))
                .iter()
                .any(|k| k.ends_with("SUMMARY"))
        );

        let mut db = lazy_db();
        let logger = join(&mut db, "logger", 1000.0);
        let omit = Unread {
            patterns: vec![
                Bytes::from_static(b"DB_*SUMMARY"),
                Bytes::from_static(b"Y*"),
            ],
            except: vec![Bytes::from_static(b"Y2")],
        };
        assert!(db.set_unread(logger, omit));
        db.handle(logger, vec![wildcard_all()], t(1000.0)).unwrap();
        for (k, now) in [("X", 1001.0), ("Y", 1001.5), ("Y2", 1002.5), ("X", 1004.6)] {
            db.handle(
                logger,
                vec![post("logger", k, Value::Double(now), now)],
                t(now),
            )
            .unwrap();
        }
        let got = keys(&drain(&mut db, logger));
        // Nothing the logger drops reaches it; the other DB variables still do.
        assert!(
            !got.iter().any(|k| k.ends_with("SUMMARY") || k == "Y"),
            "{got:?}"
        );
        assert!(got.iter().any(|k| k == "DB_TIME") && got.iter().any(|k| k == "Y2"));
        let var = db.vars.get(&b"DB_VARSUMMARY"[..]).unwrap();
        assert!(var.stale && var.sval.is_empty() && var.written_to == 2);
        // Read later, the text is built when asked, as it would be built now.
        let now_text = db.var_summary();
        assert!(now_text.contains("DB_QOS") && now_text.contains("MOOSDB_test"));
        assert_eq!(db.current("DB_VARSUMMARY").unwrap().sval_str(), now_text);
        let rw = db.current("DB_RWSUMMARY").unwrap();
        assert!(rw.sval_str().starts_with("logger="), "{}", rw.sval_str());
        // A reader that registers gets the text at once, then every refresh builds it.
        let reader = join(&mut db, "reader", 1005.0);
        db.handle(reader, vec![reg("DB_VARSUMMARY", 0.0)], t(1005.0))
            .unwrap();
        let first = drain(&mut db, reader);
        let vs: Vec<&Message> = first
            .iter()
            .filter(|m| m.key_str() == "DB_VARSUMMARY")
            .collect();
        assert!(vs.len() == 1 && vs[0].sval_str().contains("DB_UPTIME"));
        db.handle(
            logger,
            vec![post("logger", "X", Value::Double(7.0), 7.0)],
            t(1007.0),
        )
        .unwrap();
        let built = db.vars.get(&b"DB_VARSUMMARY"[..]).unwrap();
        assert!(!built.stale && built.sval.len() > 100);
        let text = String::from_utf8_lossy(&built.sval).into_owned();
        // DB_RWSUMMARY is built with it (the summary shows its beginning).
        assert!(!db.vars.get(&b"DB_RWSUMMARY"[..]).unwrap().stale);
        assert!(text.contains("DB_RWSUMMARY"));
        let again = drain(&mut db, reader);
        assert_eq!(
            again
                .iter()
                .filter(|m| m.key_str() == "DB_VARSUMMARY")
                .map(|m| m.sval_str().into_owned())
                .collect::<Vec<_>>(),
            vec![text]
        );
        assert!(
            !keys(&drain(&mut db, logger))
                .iter()
                .any(|k| k.ends_with("SUMMARY"))
        );
    }

    #[test]
    fn slow_client_outbox_is_bounded_and_counted() {
        let cfg = DbConfig {
            outbox_limit: 10,
            ..DbConfig::default()
        };
        let mut db = Database::new(cfg, t(0.0));
        let s = join(&mut db, "s", 0.0);
        let p = join(&mut db, "p", 0.0);
        db.handle(s, vec![reg("X", 0.0)], t(0.0)).unwrap();
        for i in 0..25 {
            db.handle(
                p,
                vec![post("p", "X", Value::Double(i as f64), 0.0)],
                t(0.0),
            )
            .unwrap();
        }
        let got = drain(&mut db, s);
        assert_eq!(got.len(), 10);
        assert_eq!(got.last().unwrap().dval, 24.0);
        assert_eq!(db.dropped(s), Some(15));
    }

    #[test]
    fn wildcard_matches_existing_and_future_variables() {
        let mut db = new_db();
        let p = join(&mut db, "pNav", 1000.0);
        let w = join(&mut db, "w", 1000.0);
        db.handle(
            p,
            vec![post("pNav", "NAV_X", Value::Double(1.0), 1.0)],
            t(1000.0),
        )
        .unwrap();
        let mut wr = Message::new(MsgType::WildcardRegister, DataType::String, "w");
        wr.sval = Bytes::from_static(b"AppPattern=pNav,VarPattern=NAV_*,Interval=0");
        db.handle(w, vec![wr], t(1000.0)).unwrap();
        db.handle(
            p,
            vec![
                post("pNav", "NAV_Y", Value::Double(2.0), 1.0),
                post("pNav", "OTHER", Value::Double(3.0), 1.0),
            ],
            t(1000.1),
        )
        .unwrap();
        let keys: Vec<String> = drain(&mut db, w)
            .iter()
            .map(|m| m.key_str().into_owned())
            .collect();
        assert_eq!(keys, vec!["NAV_X", "NAV_Y"]);
    }

    fn request(key: &str) -> Message {
        let mut q = Message::new(MsgType::ServerRequest, DataType::String, key);
        q.id = crate::message::SERVER_REQUEST_ID;
        q
    }

    #[test]
    fn server_requests_all_proc_summary_and_clear() {
        let mut db = new_db();
        let a = join(&mut db, "a", 1000.0);
        db.handle(a, vec![reg("IN", 0.0)], t(1000.0)).unwrap();
        db.handle(
            a,
            vec![post("a", "OUT", Value::Double(4.0), 1000.0)],
            t(1001.0),
        )
        .unwrap();
        drain(&mut db, a);
        db.handle(a, vec![request("ALL")], t(1001.5)).unwrap();
        let all = drain(&mut db, a);
        // One message per variable, in reverse name order, id -2.
        let keys: Vec<String> = all.iter().map(|m| m.key_str().into_owned()).collect();
        let mut sorted = db.var_names();
        sorted.reverse();
        assert_eq!(keys, sorted);
        let out = all.iter().find(|m| m.key_str() == "OUT").unwrap();
        assert_eq!((out.id, out.dval, out.time), (-2, 4.0, 1.0));
        let inn = all.iter().find(|m| m.key_str() == "IN").unwrap();
        assert_eq!((inn.data_type, inn.time), (DataType::NotSet, -1.0));

        db.handle(a, vec![request("PROC_SUMMARY")], t(1001.6))
            .unwrap();
        let ps = drain(&mut db, a);
        assert_eq!(ps.len(), 1);
        assert_eq!(ps[0].sval_str(), "a:SUBSCRIBED=,IN,PUBLISHED=,OUT");

        db.handle(a, vec![request("DB_CLEAR")], t(1002.0)).unwrap();
        assert!(db.current("OUT").is_none());
        db.handle(a, vec![request("VAR_SUMMARY")], t(1002.1))
            .unwrap();
        let vs = drain(&mut db, a);
        assert_eq!(vs[0].key_str(), "VAR_SUMMARY");
        assert!(vs[0].sval_str().contains("IN,OUT"), "{}", vs[0].sval_str());
    }

    #[test]
    fn one_shared_delivery_per_write_and_a_posted_mail_handed_on() {
        let mut db = new_db();
        let a = join(&mut db, "a", 1000.0);
        let b = join(&mut db, "b", 1000.0);
        let p = join(&mut db, "p", 1000.0);
        for c in [a, b] {
            db.handle(c, vec![reg("S", 0.0)], t(1000.0)).unwrap();
        }
        db.handle(
            p,
            vec![post("p", "S", Value::from("hi"), 1000.5)],
            t(1000.5),
        )
        .unwrap();
        let (mut da, mut dbb) = (Vec::new(), Vec::new());
        assert!(db.drain_deliveries(a, &mut da));
        assert!(db.drain_deliveries(b, &mut dbb));
        assert_eq!((da.len(), dbb.len()), (1, 1));
        assert!(
            Arc::ptr_eq(&da[0], &dbb[0]),
            "both subscribers hold one delivery"
        );
        let ma = da[0].mail().unwrap();
        assert_eq!((&*ma.key, &*ma.source, &*ma.community), ("S", "p", "test"));
        assert_eq!(ma.value.as_str(), Some("hi"));
        assert_eq!(Some(ma), dbb[0].mail());
        // A posted mail is handed on as it was made.
        let mut made = post("p", "S", Value::from("hé"), 1000.6);
        made.community = Bytes::from_static(b"test");
        let mail = made.mail().unwrap();
        db.handle_into(p, [mail.clone()], t(1000.6), &mut Effects::default())
            .unwrap();
        assert!(db.drain_deliveries(a, &mut da));
        assert_eq!(da.len(), 2);
        assert!(
            Arc::ptr_eq(&da[0], &dbb[0]),
            "the first write, still shared"
        );
        assert_eq!(da[1].mail(), Some(mail));
        // One made without a community gets the DB's, in its message and its mail.
        let bare = post("p", "S", Value::from("x"), 1000.7);
        let mut mail = bare.mail().unwrap();
        db.handle_into(p, [mail.clone()], t(1000.7), &mut Effects::default())
            .unwrap();
        mail.community = "test".into();
        let mut fresh = Vec::new();
        assert!(db.drain_deliveries(b, &mut fresh));
        let last = fresh.last().unwrap();
        // The message a TCP client would read is the one the mail delivers.
        let mut expected = bare.clone();
        expected.community = Bytes::from_static(b"test");
        assert_eq!(last.to_message(), expected);
        assert_eq!(last.mail(), Some(mail.clone()));
        assert_eq!(
            db.current("S").unwrap().community,
            Bytes::from_static(b"test")
        );
        // The last holder takes the mail itself; a shared one is cloned.
        let last = fresh.pop().unwrap();
        let held = Arc::clone(&last);
        assert_eq!(Delivery::into_mail(last), Some(mail.clone()));
        assert_eq!(Delivery::into_mail(held), Some(mail));
        let mut da = vec![da.remove(0)];
        // The last holder takes the message itself; a shared one is copied.
        let first = Delivery::into_message(da.pop().unwrap());
        assert_eq!(first.sval_str(), "hi");
        assert_eq!(Delivery::into_message(dbb.pop().unwrap()), first);
        assert!(!db.drain_deliveries(ClientId(99), &mut da));
    }

    #[test]
    fn poll_and_handle_into_match_handle() {
        // Two DBs fed alike: one polled with a '.' through `handle`, one with `poll_into`.
        let mut dbs = [new_db(), new_db()];
        let mut got = Vec::new();
        for (i, db) in dbs.iter_mut().enumerate() {
            let s = join(db, "s", 1000.0);
            let p = join(db, "p", 1000.0);
            let mut fx = Effects {
                ready: vec![ClientId(42)],
            };
            db.handle_into(s, vec![reg("X", 0.0)], t(1000.0), &mut fx)
                .unwrap();
            assert!(!fx.ready.contains(&ClientId(42)), "cleared first");
            db.handle_into(
                p,
                vec![post("p", "X", Value::Double(1.0), 1000.1)],
                t(1000.1),
                &mut fx,
            )
            .unwrap();
            assert_eq!(fx.ready, vec![s]);
            // A registration's replay waits in the held mail until a poll.
            let q = join(db, "q", 1000.2);
            db.handle(q, vec![reg("X", 0.0)], t(1000.2)).unwrap();
            drain(db, q);
            db.handle(p, vec![reg("X", 0.0)], t(1000.3)).unwrap();
            if i == 0 {
                let null = Message::new(MsgType::Null, DataType::Double, "");
                fx = db.handle(p, vec![null], t(1000.4)).unwrap();
            } else {
                db.poll_into(p, t(1000.4), &mut fx).unwrap();
            }
            got.push((fx.ready.clone(), drain(db, p), drain(db, s)));
            assert_eq!(
                db.poll_into(ClientId(99), t(1000.5), &mut fx),
                Err(DbError::UnknownClient(ClientId(99)))
            );
        }
        assert_eq!(got[0], got[1]);
        assert_eq!(got[0].1.len(), 1, "p's replay of X");
    }

    #[test]
    fn writers_are_recorded_when_the_writer_changes_back_and_forth() {
        let mut db = new_db();
        let a = join(&mut db, "a", 1000.0);
        let b = join(&mut db, "b", 1000.0);
        for (who, src, now) in [(a, "a", 1000.1), (b, "b", 1000.2), (a, "a", 1000.3)] {
            db.handle(who, vec![post(src, "V", Value::Double(now), now)], t(now))
                .unwrap();
        }
        assert_eq!(db.current("V").unwrap().src_str(), "a");
        // The PROC_SUMMARY replies `a` gets at `now`.
        let summaries = |db: &mut Database, now: f64| -> Vec<String> {
            db.handle(a, vec![request("PROC_SUMMARY")], t(now)).unwrap();
            drain(db, a)
                .iter()
                .map(|m| m.sval_str().into_owned())
                .collect()
        };
        let ps = summaries(&mut db, 1000.4);
        assert!(
            ps.contains(&"a:SUBSCRIBED=,PUBLISHED=,V".to_string()),
            "{ps:?}"
        );
        assert!(
            ps.contains(&"b:SUBSCRIBED=,PUBLISHED=,V".to_string()),
            "{ps:?}"
        );
        // After a DB_CLEAR the first write records its writer again.
        db.handle(a, vec![request("DB_CLEAR")], t(1000.5)).unwrap();
        db.handle(
            a,
            vec![post("a", "V", Value::Double(1.0), 1000.6)],
            t(1000.6),
        )
        .unwrap();
        let ps = summaries(&mut db, 1000.7);
        assert!(
            ps.contains(&"a:SUBSCRIBED=,PUBLISHED=,V".to_string()),
            "{ps:?}"
        );
        assert!(
            ps.contains(&"b:SUBSCRIBED=,PUBLISHED=".to_string()),
            "{ps:?}"
        );
    }

    #[test]
    fn synchronous_clients_get_a_null_first_and_no_pushes() {
        let mut db = new_db();
        let s = db
            .connect(Bytes::from_static(b"old"), false, 1000.0, t(1000.0))
            .id()
            .unwrap();
        let p = join(&mut db, "p", 1000.0);
        let mut null = Message::new(MsgType::Null, DataType::Double, "");
        null.src = Bytes::from_static(b"old");
        db.handle(s, vec![reg("X", 0.0)], t(1000.1)).unwrap();
        let r = drain(&mut db, s);
        assert_eq!(r.len(), 1);
        assert_eq!((r[0].msg_type, r[0].dval), (MsgType::Null, 1000.1));
        let eff = db
            .handle(p, vec![post("p", "X", Value::Double(5.0), 1.0)], t(1000.2))
            .unwrap();
        assert!(!eff.ready.contains(&s), "sync clients are not pushed to");
        db.handle(s, vec![null], t(1000.3)).unwrap();
        let r = drain(&mut db, s);
        assert_eq!(r.len(), 2);
        assert_eq!((r[1].key_str().as_ref(), r[1].dval), ("X", 5.0));
    }

    #[test]
    fn timing_only_packet_gets_only_the_echo() {
        let mut db = new_db();
        let c = join(&mut db, "c", 1000.0);
        let p = join(&mut db, "p", 1000.0);
        db.handle(c, vec![reg("X", 0.0)], t(1000.0)).unwrap();
        // Registering for a variable written earlier replays its value at once.
        db.handle(p, vec![post("p", "Y", Value::Double(1.0), 1.0)], t(1000.0))
            .unwrap();
        drain(&mut db, c);
        db.handle(c, vec![reg("Y", 0.0)], t(1000.1)).unwrap();
        let replay = drain(&mut db, c);
        assert_eq!(replay[0].key_str(), "Y");
        assert_eq!(replay[0].id, -1, "register replay is a fresh message");
        let mut tm = Message::new(MsgType::Timing, DataType::Double, "_async_timing");
        tm.time = 999.0;
        tm.dval = 0.0;
        // Summary refresh happens (> 2 s) but the reply is the echo alone.
        db.handle(c, vec![reg("DB_TIME", 0.0)], t(1001.0)).unwrap();
        drain(&mut db, c);
        db.handle(c, vec![tm], t(1002.5)).unwrap();
        let r = drain(&mut db, c);
        assert_eq!(r.len(), 1);
        assert_eq!(
            (r[0].msg_type, r[0].time, r[0].dval, r[0].dval2),
            (MsgType::Timing, 999.0, 1002.5, 0.0)
        );
        assert!(db.current("DB_TIME").is_some());
    }

    #[test]
    fn wildcard_unregister_stops_existing_and_future_matches() {
        let mut db = new_db();
        let p = join(&mut db, "p", 1000.0);
        let w = join(&mut db, "w", 1000.0);
        let mut wr = Message::new(MsgType::WildcardRegister, DataType::String, "w");
        wr.sval = Bytes::from_static(b"AppPattern=*,VarPattern=A_*,Interval=0");
        db.handle(w, vec![wr.clone()], t(1000.0)).unwrap();
        db.handle(
            p,
            vec![post("p", "A_1", Value::Double(1.0), 1.0)],
            t(1000.1),
        )
        .unwrap();
        assert_eq!(drain(&mut db, w).len(), 1);
        let mut un = wr;
        un.msg_type = MsgType::WildcardUnregister;
        un.sval = Bytes::from_static(b"AppPattern=*,VarPattern=A_*,Interval=0");
        db.handle(w, vec![un], t(1000.2)).unwrap();
        db.handle(
            p,
            vec![
                post("p", "A_1", Value::Double(2.0), 1.0),
                post("p", "A_2", Value::Double(3.0), 1.0),
            ],
            t(1000.3),
        )
        .unwrap();
        assert!(drain(&mut db, w).is_empty());
        assert!(db.subscribers("A_2").is_empty());
    }

    #[test]
    fn glob_and_formatting_helpers() {
        assert!(wildcard_match(b"a?c*", b"abcdef"));
        assert!(!wildcard_match(b"a?c", b"ac"));
        assert!(wildcard_match(b"*_ITER_GAP", b"PHELM_ITER_GAP"));
        assert_eq!(time_of_day(-1.0), "23:59:59.000");
        assert_eq!(time_of_day(1795217434.275), "23:30:34.275");
        assert_eq!(format!("{:<14}|", TimeOfDay(-1.0)), "23:59:59.000  |");
        assert_eq!(fmt_g6(0.481129), "0.481129");
        assert_eq!(fmt_g6(12.5), "12.5");
        assert_eq!(fmt_g6(0.0000123), "1.23e-05");
    }
}
