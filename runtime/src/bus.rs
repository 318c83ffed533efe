//! The bus: an in-process MOOSDB. In-process apps are ordinary clients of a
//! [`moosdb_client::Database`] core, so they get MOOSDB semantics (current value on
//! register, intervals, wildcard registrations, `DB_*` variables) and the same database
//! can also serve TCP clients in real-time mode.

use bytes::Bytes;
use moosdb_client::db::{ClientId, Database, DbConfig, DbTime};
use moosdb_client::{DataType, Message, MsgType};
use thiserror::Error;

use crate::app::{Mail, Post, Subscription, Value};

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

/// An in-process MOOSDB with in-process clients. Every call takes the MOOS time.
#[derive(Debug)]
pub struct Bus {
    db: Database,
    start: f64,
    packets: Vec<Vec<Message>>,
}

impl Bus {
    /// A bus whose DB (community `community`) starts at MOOS time `start`.
    pub fn new(community: &str, start: f64) -> Bus {
        let config = DbConfig {
            community: community.to_string(),
            ..DbConfig::default()
        };
        Bus {
            db: Database::new(config, Bus::db_time(start, start)),
            start,
            packets: Vec::new(),
        }
    }

    fn db_time(now: f64, start: f64) -> DbTime {
        DbTime {
            moos: now,
            mono: now - start,
        }
    }

    fn t(&self, now: f64) -> DbTime {
        Bus::db_time(now, self.start)
    }

    /// The DB core (for a TCP edge sharing it, or inspection).
    pub fn database(&mut self) -> &mut Database {
        &mut self.db
    }

    /// Connects a client called `name` (an asynchronous client, as every V10 app is).
    pub fn connect(&mut self, name: &str, now: f64) -> Result<ClientId, BusError> {
        let t = self.t(now);
        self.db
            .connect(Bytes::copy_from_slice(name.as_bytes()), true, now, t)
            .id()
            .ok_or_else(|| BusError::NameTaken(name.to_string()))
    }

    /// Removes a client.
    pub fn disconnect(&mut self, id: ClientId, now: f64) {
        let t = self.t(now);
        self.db.disconnect(id, t);
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
        self.send(id, vec![msg], now)
    }

    /// Publishes posts made at `now` by the client `id`; a post with an empty source gets
    /// `default_source`.
    pub fn publish(
        &mut self,
        id: ClientId,
        posts: &[Post],
        default_source: &str,
        now: f64,
    ) -> Result<(), BusError> {
        if posts.is_empty() {
            return Ok(());
        }
        let default_src = Bytes::copy_from_slice(default_source.as_bytes());
        let msgs = posts
            .iter()
            .map(|p| {
                let mut m = Message::new(MsgType::Notify, DataType::Double, "");
                m.key = Bytes::copy_from_slice(p.key.as_bytes());
                m.time = now;
                match &p.value {
                    Value::Double(x) => m.dval = *x,
                    Value::String(s) => {
                        m.data_type = DataType::String;
                        m.sval = Bytes::copy_from_slice(s.as_bytes());
                    }
                    Value::Binary(b) => {
                        m.data_type = DataType::Binary;
                        m.sval = Bytes::copy_from_slice(b);
                    }
                }
                m.src = if p.source.is_empty() {
                    default_src.clone()
                } else {
                    Bytes::copy_from_slice(p.source.as_bytes())
                };
                m
            })
            .collect();
        self.send(id, msgs, now)
    }

    fn send(&mut self, id: ClientId, msgs: Vec<Message>, now: f64) -> Result<(), BusError> {
        let t = self.t(now);
        self.db
            .handle(id, msgs, t)
            .map(|_| ())
            .map_err(|_| BusError::NotConnected(id))
    }

    /// Everything delivered to `id` so far, sorted by message time (stable), appended to
    /// `out`. Like a sync client's poll, this also collects held mail.
    pub fn fetch(&mut self, id: ClientId, now: f64, out: &mut Vec<Mail>) -> Result<(), BusError> {
        let poll = Message::new(MsgType::Null, DataType::Double, "");
        self.send(id, vec![poll], now)?;
        self.packets.clear();
        if !self.db.drain_outbox(id, &mut self.packets) {
            return Err(BusError::NotConnected(id));
        }
        let first = out.len();
        for m in self.packets.drain(..).flatten() {
            if m.msg_type != MsgType::Notify {
                continue;
            }
            if let Some(mail) = to_mail(&m) {
                out.push(mail);
            }
        }
        out[first..].sort_by(|a, b| a.time.total_cmp(&b.time));
        Ok(())
    }

    /// The current value of a variable, if it was ever written.
    pub fn current(&self, key: &str) -> Option<Mail> {
        self.db.current(key).as_ref().and_then(to_mail)
    }
}

fn text(b: &Bytes) -> String {
    String::from_utf8_lossy(b).into_owned()
}

fn to_mail(m: &Message) -> Option<Mail> {
    let value = match m.data_type {
        DataType::Double => Value::Double(m.dval),
        DataType::String => Value::String(text(&m.sval)),
        DataType::Binary => Value::Binary(m.sval.to_vec()),
        DataType::NotSet => return None,
    };
    Some(Mail {
        key: text(&m.key),
        value,
        time: m.time,
        source: text(&m.src),
        source_aux: text(&m.src_aux),
        community: text(&m.community),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn in_process_clients_get_moosdb_semantics() {
        let mut bus = Bus::new("test", 100.0);
        let a = bus.connect("a", 100.0).unwrap();
        let b = bus.connect("b", 100.0).unwrap();
        assert_eq!(
            bus.connect("a", 100.0),
            Err(BusError::NameTaken("a".into()))
        );
        bus.publish(a, &[Post::double("X", 1.0)], "a", 100.0)
            .unwrap();
        // Registering after the write replays the current value.
        bus.subscribe(b, &Subscription::var("X"), 100.5).unwrap();
        bus.subscribe(b, &Subscription::var("S_*"), 100.5).unwrap();
        bus.publish(
            a,
            &[Post::text("S_ONE", "hi"), Post::double("Y", 3.0)],
            "a",
            101.0,
        )
        .unwrap();
        bus.publish(a, &[Post::double("X", 2.0)], "a", 101.5)
            .unwrap();
        let mut mail = Vec::new();
        bus.fetch(b, 102.0, &mut mail).unwrap();
        let got: Vec<(String, Value, f64)> = mail
            .iter()
            .map(|m| (m.key.clone(), m.value.clone(), m.time))
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
        assert_eq!(mail[0].community, "test");
        assert_eq!(bus.current("Y").unwrap().value, Value::Double(3.0));
        assert!(bus.current("NOPE").is_none());
        mail.clear();
        bus.fetch(b, 102.5, &mut mail).unwrap();
        assert!(mail.is_empty());
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
            bus.publish(a, &[Post::double("X", t)], "a", t).unwrap();
        }
        let mut mail = Vec::new();
        bus.fetch(b, 3.0, &mut mail).unwrap();
        let times: Vec<f64> = mail.iter().map(|m| m.time).collect();
        assert_eq!(times, vec![0.0, 1.0, 2.0]);
    }
}
