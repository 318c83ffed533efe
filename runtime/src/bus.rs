//! The bus: an in-process MOOSDB. In-process apps are ordinary clients of a
//! [`moosdb::Database`] core, so they get MOOSDB semantics (current value on
//! register, intervals, wildcard registrations, `DB_*` variables) and the same database
//! can also serve TCP clients in real-time mode.

use std::sync::Arc;

use bytes::Bytes;
use moos_types::ByteString;
use moosdb::db::{ClientId, Database, DbConfig, DbError, DbTime, Delivery, Effects};
use moosdb::{DataType, Message, MsgType};
use rustc_hash::FxHashSet;
use thiserror::Error;

use crate::app::{Mail, Post, Subscription};

/// Misuse of the bus.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum BusError {
    /// Another client already has this MOOS name.
    #[error("a client called {0:?} is already connected")]
    NameTaken(String),
    /// The handle does not belong to a connected client.
    #[error("client {0:?} is not connected")]
    NotConnected(ClientId),
}

/// Where the bus's [`Database`] lives: owned in-process ([`LocalDb`], lockstep), or shared
/// with other code (an implementation that locks a shared core, stamps its own clock and
/// tells a network edge which clients to serve in [`DbHost::wake`]). Real-time runs use
/// TCP clients instead ([`crate::realtime`]).
pub trait DbHost {
    /// Runs `f` on the database at MOOS time `now`.
    fn with_mut<R>(&mut self, now: f64, f: impl FnOnce(&mut Database, DbTime) -> R) -> R;

    /// Runs `f` on the database for reading.
    fn with_ref<R>(&self, f: impl FnOnce(&Database) -> R) -> R;

    /// Told which clients have packets waiting after a call (TCP edges send them).
    fn wake(&mut self, _effects: &Effects) {}
}

/// A database owned by the bus; liveness time is MOOS time since the start.
#[derive(Debug)]
pub struct LocalDb {
    db: Database,
    start: f64,
}

impl LocalDb {
    /// A database of community `community` started at MOOS time `start`.
    pub fn new(community: &str, start: f64) -> LocalDb {
        // Its clients are the run's apps, registered at their start: the DB summaries are
        // built only while one of them reads them.
        let config = DbConfig {
            community: community.to_string(),
            lazy_summaries: true,
            ..DbConfig::default()
        };
        let t = DbTime {
            moos: start,
            mono: 0.0,
        };
        LocalDb {
            db: Database::new(config, t),
            start,
        }
    }

    /// The database.
    pub fn database(&mut self) -> &mut Database {
        &mut self.db
    }
}

impl DbHost for LocalDb {
    fn with_mut<R>(&mut self, now: f64, f: impl FnOnce(&mut Database, DbTime) -> R) -> R {
        let t = DbTime {
            moos: now,
            mono: now - self.start,
        };
        f(&mut self.db, t)
    }

    fn with_ref<R>(&self, f: impl FnOnce(&Database) -> R) -> R {
        f(&self.db)
    }
}

/// An in-process MOOSDB with in-process clients. Every call takes the MOOS time.
///
/// Mail is handed out without copies of its names (see [`moos_types::Mail`]): a post becomes
/// the mail it delivers, its names and value moved in (a fresh copy of a variable name is
/// swapped for the DB's buffer of it), the bus keeps one shared buffer per source name, and
/// the DB hands the mail to its in-process readers as it is, so a post reaches the DB and
/// its subscribers without copying text.
#[derive(Debug)]
pub struct Bus<H: DbHost = LocalDb> {
    host: H,
    /// The fetched deliveries (reused: a fetch allocates no buffer of its own).
    fetched: Vec<Arc<Delivery>>,
    /// The last call's effects (reused likewise).
    effects: Effects,
    names: Names,
    /// The DB's community, the one of the mail of the posts that name none.
    community: ByteString,
}

/// Most names [`Names`] keeps before it starts afresh (it only saves copies: a name seen
/// again after that is copied once more).
const NAMES_LIMIT: usize = 4096;

/// Shared buffers of the source names posts carry (an app's name, mostly), so that
/// publishing hands the DB reference-counted buffers instead of fresh copies (the DB keeps
/// them as writers, and every subscriber's mail shares them).
#[derive(Debug, Default)]
struct Names {
    set: FxHashSet<ByteString>,
}

impl Names {
    /// The shared buffer holding `s` (empty text needs none).
    fn get(&mut self, s: &str) -> ByteString {
        if s.is_empty() {
            return ByteString::new();
        }
        if let Some(b) = self.set.get(s) {
            return b.clone();
        }
        if self.set.len() >= NAMES_LIMIT {
            self.set.clear();
        }
        let b = ByteString::from(s);
        // The first clone turns the buffer into a shared one (one allocation); every later
        // clone of either handle only counts a reference.
        let shared = b.clone();
        self.set.insert(b);
        shared
    }
}

impl Bus<LocalDb> {
    /// A bus whose own DB (community `community`) starts at MOOS time `start`.
    pub fn new(community: &str, start: f64) -> Bus<LocalDb> {
        Bus::with_host(LocalDb::new(community, start))
    }
}

impl<H: DbHost> Bus<H> {
    /// A bus over any database host.
    pub fn with_host(host: H) -> Bus<H> {
        let community = host.with_ref(|db| ByteString::from(db.config().community.as_str()));
        Bus {
            host,
            fetched: Vec::new(),
            effects: Effects::default(),
            names: Names::default(),
            community,
        }
    }

    /// The database host.
    pub fn host(&mut self) -> &mut H {
        &mut self.host
    }

    /// Connects a client called `name` (an asynchronous client, as every V10 app is).
    pub fn connect(&mut self, name: &str, now: f64) -> Result<ClientId, BusError> {
        let key = self.names.get(name).into_bytes();
        self.host
            .with_mut(now, |db, t| db.connect(key, true, now, t).id())
            .ok_or_else(|| BusError::NameTaken(name.to_string()))
    }

    /// Tells the DB which variables client `id` drops unread ([`App::unread`](crate::app::App::unread)).
    pub fn set_unread(
        &mut self,
        id: ClientId,
        unread: moosdb::db::Unread,
        now: f64,
    ) -> Result<(), BusError> {
        if self.host.with_mut(now, |db, _| db.set_unread(id, unread)) {
            Ok(())
        } else {
            Err(BusError::NotConnected(id))
        }
    }

    /// Removes a client.
    pub fn disconnect(&mut self, id: ClientId, now: f64) {
        self.host.with_mut(now, |db, t| db.disconnect(id, t));
    }

    /// Registers for a variable or (with `*`/`?`) a variable-name pattern from any app.
    pub fn subscribe(
        &mut self,
        id: ClientId,
        sub: &Subscription,
        now: f64,
    ) -> Result<(), BusError> {
        let msg = if sub.is_wildcard() {
            let mut m = Message::new(MsgType::WildcardRegister, DataType::String, "");
            m.sval = Bytes::from(format!(
                "AppPattern=*,VarPattern={},Interval={}",
                sub.pattern, sub.interval
            ));
            m.time = now;
            m
        } else {
            let mut m = Message::new(MsgType::Register, DataType::Double, &sub.pattern);
            m.dval = sub.interval;
            m.time = now;
            m
        };
        Self::send(&mut self.host, &mut self.effects, id, [msg], now)
    }

    /// Publishes posts made at `now` by the client `id` (taken: their names and values
    /// become the mail, with no copy); a post with an empty source gets `default_source`.
    pub fn publish(
        &mut self,
        id: ClientId,
        posts: impl IntoIterator<Item = Post>,
        default_source: &str,
        now: f64,
    ) -> Result<(), BusError> {
        let mut posts = posts.into_iter().peekable();
        if posts.peek().is_none() {
            return Ok(());
        }
        let default_src = self.names.get(default_source);
        let names = &mut self.names;
        let own_community = &self.community;
        // Each post goes as the mail it delivers, made here from its text (UTF-8 already):
        // the DB hands it to the readers as it is, and makes a message of it only for a
        // TCP client. A fresh copy of a variable name is swapped for the DB's buffer there.
        let mails = posts.map(|p| {
            // A relayed message keeps its time and community (the DB keeps a non-empty one);
            // the others get the DB's, as the DB would give them.
            let (time, community) = match p.relayed {
                Some(r) if !r.community.is_empty() => (r.time, r.community),
                Some(r) => (r.time, own_community.clone()),
                None => (now, own_community.clone()),
            };
            let source = if p.source.is_empty() {
                default_src.clone()
            } else {
                names.get(&p.source)
            };
            Mail {
                key: p.key,
                value: p.value,
                time,
                source,
                // Aux fields vary (the helm's `<iteration>:<behaviour>`): the post's own
                // buffer, as the app made it.
                source_aux: p.aux,
                community,
            }
        });
        let effects = &mut self.effects;
        self.host
            .with_mut(now, |db, t| db.handle_into(id, mails, t, effects))
            .map_err(|_| BusError::NotConnected(id))?;
        if !self.effects.ready.is_empty() {
            self.host.wake(&self.effects);
        }
        Ok(())
    }

    fn send(
        host: &mut H,
        effects: &mut Effects,
        id: ClientId,
        msgs: impl IntoIterator<Item = Message>,
        now: f64,
    ) -> Result<(), BusError> {
        host.with_mut(now, |db, t| db.handle_into(id, msgs, t, effects))
            .map_err(|_| BusError::NotConnected(id))?;
        if !effects.ready.is_empty() {
            host.wake(effects);
        }
        Ok(())
    }

    /// Everything delivered to `id` so far, sorted by message time (stable), appended to
    /// `out`. Like a sync client's poll, this also collects held mail.
    pub fn fetch(&mut self, id: ClientId, now: f64, out: &mut Vec<Mail>) -> Result<(), BusError> {
        // A poll (a `'.'`), then the queued deliveries, in one call on the DB.
        self.fetched.clear();
        let fetched = &mut self.fetched;
        let effects = &mut self.effects;
        let drained = self.host.with_mut(now, |db, t| -> Result<bool, DbError> {
            db.poll_into(id, t, effects)?;
            Ok(db.drain_deliveries(id, fetched))
        });
        if !matches!(drained, Ok(true)) {
            return Err(BusError::NotConnected(id));
        }
        if !self.effects.ready.is_empty() {
            self.host.wake(&self.effects);
        }
        let first = out.len();
        out.reserve(self.fetched.len());
        for d in self.fetched.drain(..) {
            if !d.is_notify() {
                continue;
            }
            // A post's mail as the poster made it (taken by its last reader, else cloned):
            // no conversion.
            if let Some(mail) = Delivery::into_mail(d) {
                out.push(mail);
            }
        }
        // Mostly in time order already: a sort only when not.
        if !out[first..].is_sorted_by(|a, b| a.time.total_cmp(&b.time).is_le()) {
            out[first..].sort_by(|a, b| a.time.total_cmp(&b.time));
        }
        Ok(())
    }

    /// The current value of a variable as the DB would replay it, if it was ever written
    /// (its buffers are the DB's: nothing is copied).
    pub fn current_message(&self, key: &str) -> Option<Message> {
        self.host.with_ref(|db| db.current(key))
    }

    /// The current value of a variable, if it was ever written.
    pub fn current(&self, key: &str) -> Option<Mail> {
        self.host
            .with_ref(|db| db.current(key))
            .as_ref()
            .and_then(Message::mail)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::Value;

    #[test]
    fn in_process_clients_get_moosdb_semantics() {
        let mut bus = Bus::new("test", 100.0);
        let a = bus.connect("a", 100.0).unwrap();
        let b = bus.connect("b", 100.0).unwrap();
        assert_eq!(
            bus.connect("a", 100.0),
            Err(BusError::NameTaken("a".into()))
        );
        bus.publish(
            a,
            [Post::double("X", 1.0).with_aux("HELM_VAR_INIT")],
            "a",
            100.0,
        )
        .unwrap();
        // Registering after the write replays the current value.
        bus.subscribe(b, &Subscription::var("X"), 100.5).unwrap();
        bus.subscribe(b, &Subscription::var("S_*"), 100.5).unwrap();
        bus.publish(
            a,
            [Post::text("S_ONE", "hi"), Post::double("Y", 3.0)],
            "a",
            101.0,
        )
        .unwrap();
        bus.publish(a, [Post::double("X", 2.0)], "a", 101.5)
            .unwrap();
        let mut mail = Vec::new();
        bus.fetch(b, 102.0, &mut mail).unwrap();
        let got: Vec<(String, Value, f64)> = mail
            .iter()
            .map(|m| (m.key.to_string(), m.value.clone(), m.time))
            .collect();
        assert_eq!(
            got,
            vec![
                ("X".into(), Value::Double(1.0), 100.0),
                ("S_ONE".into(), Value::text("hi"), 101.0),
                ("X".into(), Value::Double(2.0), 101.5),
            ]
        );
        assert_eq!(mail[0].source, "a");
        assert_eq!(mail[0].source_aux, "HELM_VAR_INIT");
        assert_eq!(mail[1].source_aux, "");
        assert_eq!(mail[0].community, "test");
        assert_eq!(bus.current("Y").unwrap().value, Value::Double(3.0));
        assert!(bus.current("NOPE").is_none());
        mail.clear();
        bus.fetch(b, 102.5, &mut mail).unwrap();
        assert!(mail.is_empty());
    }

    /// A host that records which clients it was told to wake.
    struct Recording {
        inner: LocalDb,
        woken: Vec<ClientId>,
    }

    impl DbHost for Recording {
        fn with_mut<R>(&mut self, now: f64, f: impl FnOnce(&mut Database, DbTime) -> R) -> R {
            self.inner.with_mut(now, f)
        }
        fn with_ref<R>(&self, f: impl FnOnce(&Database) -> R) -> R {
            self.inner.with_ref(f)
        }
        fn wake(&mut self, effects: &Effects) {
            self.woken.extend(&effects.ready);
        }
    }

    /// A client of the bus's DB that is not in-process (think: a TCP client), connected as
    /// `tcp` at time 0 and registered with `reg`.
    fn outside_client<H: DbHost>(bus: &mut Bus<H>, reg: Message) -> ClientId {
        let tcp = bus
            .host()
            .with_mut(0.0, |db, t| {
                db.connect(Bytes::from_static(b"tcp"), true, 0.0, t).id()
            })
            .unwrap();
        bus.host()
            .with_mut(0.0, |db, t| db.handle(tcp, vec![reg], t))
            .unwrap();
        tcp
    }

    #[test]
    fn a_shared_host_is_told_whom_to_wake() {
        let mut bus = Bus::with_host(Recording {
            inner: LocalDb::new("c", 0.0),
            woken: Vec::new(),
        });
        let a = bus.connect("a", 0.0).unwrap();
        // A client that is not in-process (think: a TCP client) subscribes directly.
        let mut reg = Message::new(MsgType::Register, DataType::Double, "X");
        reg.dval = 0.0;
        let tcp = outside_client(&mut bus, reg);
        bus.host().woken.clear();
        bus.publish(a, [Post::double("X", 4.0)], "a", 1.0).unwrap();
        assert_eq!(bus.host().woken, vec![tcp]);
        let mut out = Vec::new();
        bus.host()
            .with_mut(1.0, |db, _| db.drain_outbox(tcp, &mut out));
        assert_eq!(out.concat()[0].dval, 4.0);
    }

    #[test]
    fn posted_mail_is_the_mail_the_message_delivers() {
        use moos_types::Relayed;
        let mut bus = Bus::new("home", 0.0);
        let a = bus.connect("a", 0.0).unwrap();
        let b = bus.connect("b", 0.0).unwrap();
        bus.subscribe(b, &Subscription::var("*"), 0.0).unwrap();
        // A client outside the bus reads the same posts as messages.
        let mut reg = Message::new(MsgType::WildcardRegister, DataType::String, "");
        reg.sval = Bytes::from_static(b"AppPattern=*,VarPattern=*,Interval=0");
        let tcp = outside_client(&mut bus, reg);
        let mut relayed = Post::double("R", 5.0);
        relayed.source = "far".into();
        relayed.relayed = Some(Box::new(Relayed {
            time: 0.25,
            community: "away".into(),
        }));
        let mut relayed_here = Post::text("RH", "x");
        relayed_here.relayed = Some(Box::new(Relayed {
            time: 0.5,
            community: "".into(),
        }));
        let posts = [
            Post::double("D", 1.5).with_aux("7:cruise"),
            Post::text("S", "héllo"),
            Post::new("B", Value::Binary(vec![0, 0xff, 7])),
            relayed,
            relayed_here,
        ];
        bus.publish(a, posts, "a", 1.0).unwrap();
        let mut mail = Vec::new();
        bus.fetch(b, 1.0, &mut mail).unwrap();
        mail.retain(|m| !m.key.starts_with("DB_"));
        let mut packets = Vec::new();
        bus.host()
            .with_mut(1.0, |db, _| db.drain_outbox(tcp, &mut packets));
        let mut read: Vec<Mail> = packets
            .concat()
            .iter()
            .filter(|m| m.msg_type == MsgType::Notify && !m.key.starts_with(b"DB_"))
            .filter_map(Message::mail)
            .collect();
        read.sort_by(|x, y| x.time.total_cmp(&y.time));
        assert_eq!(mail, read);
        assert_eq!(mail.len(), 5);
        let r = mail.iter().find(|m| m.key == "R").unwrap();
        assert_eq!((&*r.source, &*r.community, r.time), ("far", "away", 0.25));
        let rh = mail.iter().find(|m| m.key == "RH").unwrap();
        assert_eq!(&*rh.community, "home");
        let d = mail.iter().find(|m| m.key == "D").unwrap();
        assert_eq!((&*d.source_aux, &*d.community), ("7:cruise", "home"));
    }

    #[test]
    fn interval_limits_delivery() {
        let mut bus = Bus::new("c", 0.0);
        let a = bus.connect("a", 0.0).unwrap();
        let b = bus.connect("b", 0.0).unwrap();
        bus.subscribe(b, &Subscription::every("X", 1.0), 0.0)
            .unwrap();
        for i in 0..10 {
            let t = f64::from(i) * 0.25;
            bus.publish(a, [Post::double("X", t)], "a", t).unwrap();
        }
        let mut mail = Vec::new();
        bus.fetch(b, 3.0, &mut mail).unwrap();
        let times: Vec<f64> = mail.iter().map(|m| m.time).collect();
        assert_eq!(times, vec![0.0, 1.0, 2.0]);
    }
}
