//! The DB core, fed every recorded client's packets at their recorded times, answers each
//! connection with the same packets the real C++ MOOSDB sent: same message types, data types,
//! ids, keys, sources, communities and values, in the same packets and order. Fields that
//! depend on the DB's own clock (DB time/uptime, skew, timing echoes' DB time, the text of
//! DB_VARSUMMARY/DB_QOS) and its host name are left aside.

mod common;

use std::collections::HashMap;

use bytes::Bytes;
use moosdb::db::{ClientId, Database, DbConfig, DbTime};
use moosdb::{Message, MsgType};

#[derive(Debug)]
enum Ev {
    /// The (re)started DB begins listening: a fresh database.
    Listen {
        start: f64,
    },
    Packet {
        conn: u64,
        idx: usize,
    },
    Eof {
        conn: u64,
    },
}

/// A message with the clock-dependent fields blanked.
fn comparable(m: &Message, db_name: &[u8]) -> Message {
    let mut m = m.clone();
    let from_db = &m.src[..] == db_name;
    match m.msg_type {
        MsgType::Welcome | MsgType::Poison => {
            m.time = 0.0;
            m.dval = 0.0;
            m.src_aux = Bytes::new();
        }
        MsgType::Timing => m.dval = 0.0,
        _ => {}
    }
    if from_db {
        m.time = 0.0;
        let key = &m.key[..];
        if key == b"DB_TIME" || key == b"DB_UPTIME" {
            m.dval = 0.0;
        }
        if key == b"DB_VARSUMMARY" {
            m.sval = Bytes::from(varsummary_shape(&m.sval_str()));
        }
        if key == b"DB_QOS" {
            m.sval = Bytes::from(qos_shape(&m.sval_str()));
        }
    }
    m
}

/// DB_VARSUMMARY without its clock-dependent parts: for each row the variable, writer, data
/// type and value (values of rows that hold times are dropped); written time and write
/// frequency left out. Also checks each row's fixed-width layout.
fn varsummary_shape(text: &str) -> String {
    let mut out = String::new();
    for line in text.lines() {
        let line = line.replacen("(write pending)", "(write_pending)", 1);
        let toks: Vec<&str> = line.split(' ').filter(|t| !t.is_empty()).collect();
        assert!(toks.len() >= 5, "short DB_VARSUMMARY row {line:?}");
        let (name, time, who, hz) = (toks[0], toks[1], toks[2], toks[4]);
        assert_eq!(time.len(), 12, "time column {time:?} in {line:?}");
        assert_eq!(&time[2..3], ":");
        assert_eq!(hz, "Hz", "{line:?}");
        let dtype = toks.get(5).copied().unwrap_or("");
        // The value is everything after the type column (the row is fixed-width up to it).
        let value = match line.find(" Hz ") {
            Some(i) => line[i + 4..].get(3..).unwrap_or(""),
            None => "",
        };
        let timey = matches!(name, "DB_TIME" | "DB_UPTIME" | "DB_QOS" | "DB_VARSUMMARY");
        out.push_str(&format!(
            "{name}|{who}|{dtype}|{}\n",
            if timey { "" } else { value }
        ));
    }
    out
}

/// DB_QOS without latencies: the client names in order, and the field count of each.
fn qos_shape(text: &str) -> String {
    text.split(',')
        .filter(|e| !e.is_empty())
        .map(|e| {
            let (name, nums) = e.split_once('=').expect("name=numbers");
            format!("{name}:{}", nums.split(':').count())
        })
        .collect::<Vec<_>>()
        .join(",")
}

fn replay(scenario: &str) -> (usize, usize) {
    let idx = common::index(scenario);
    let mission = idx["mission_file"].as_str().unwrap();
    let community = common::mission_value(mission, "Community").expect("Community");
    let db_name = format!("MOOSDB_{community}").into_bytes();
    let conns = idx["connections"].as_array().unwrap();

    let mut c2s: HashMap<u64, Vec<common::RecPacket>> = HashMap::new();
    let mut s2c: HashMap<u64, Vec<common::RecPacket>> = HashMap::new();
    let mut events: Vec<(f64, Ev)> = Vec::new();
    // Every `listen` of the proxy follows a (re)start of the real DB.
    let listens: Vec<f64> = idx["proxy_events"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["event"] == "listen")
        .map(|e| e["t"].as_f64().unwrap())
        .collect();
    let mut starts = listens.clone();
    for conn in conns {
        let n = conn["conn"].as_u64().unwrap();
        let up = common::packets(conn, "c2s_packets");
        let down = common::packets(conn, "s2c_packets");
        for (i, p) in up.iter().enumerate() {
            events.push((p.t, Ev::Packet { conn: n, idx: i }));
        }
        for ev in conn["lifecycle"].as_array().unwrap() {
            if ev["event"] == "eof" && ev["dir"] == "c2s" {
                events.push((ev["t"].as_f64().unwrap(), Ev::Eof { conn: n }));
            }
        }
        // Each DB instance's start time follows from the uptimes it reported.
        for p in &down {
            let inst = listens.iter().rposition(|&l| l <= p.t).unwrap_or(0);
            for m in &p.msgs {
                if m.key_str() == "DB_UPTIME" && m.src_str().starts_with("MOOSDB_") {
                    starts[inst] = starts[inst].min(m.time - m.dval);
                }
            }
        }
        c2s.insert(n, up);
        s2c.insert(n, down);
    }
    for (l, s) in listens.iter().zip(&starts) {
        events.push((*l, Ev::Listen { start: *s }));
    }
    events.sort_by(|a, b| a.0.total_cmp(&b.0));

    let at = |t: f64| DbTime { moos: t, mono: t };
    let cfg = DbConfig {
        community: community.clone(),
        host_name: "replay".into(),
        ..DbConfig::default()
    };
    let mut db = Database::new(cfg.clone(), at(starts[0]));
    let mut ids: HashMap<u64, ClientId> = HashMap::new();
    let mut conn_of: HashMap<ClientId, u64> = HashMap::new();
    let mut sent: HashMap<u64, Vec<Vec<Message>>> = HashMap::new();
    let mut drained = Vec::new();
    for (t, ev) in events {
        match ev {
            Ev::Listen { start } => {
                // A killed DB forgets everything; its clients' connections died with it.
                db = Database::new(cfg.clone(), at(start));
                ids.clear();
            }
            Ev::Packet { conn, idx: 0 } => {
                let first = c2s[&conn][0].msgs.first().cloned();
                let h = db.handshake(first.as_ref(), at(t));
                if let Some(id) = h.id() {
                    ids.insert(conn, id);
                    conn_of.insert(id, conn);
                }
                sent.entry(conn).or_default().push(vec![h.reply().clone()]);
            }
            Ev::Packet { conn, idx } => {
                let Some(id) = ids.get(&conn) else { continue };
                let msgs = c2s[&conn][idx].msgs.clone();
                let effects = db.handle(*id, msgs, at(t)).expect("connected");
                for r in effects.ready {
                    drained.clear();
                    db.drain_outbox(r, &mut drained);
                    sent.entry(conn_of[&r]).or_default().append(&mut drained);
                }
            }
            Ev::Eof { conn } => {
                if let Some(id) = ids.remove(&conn) {
                    db.disconnect(id, at(t));
                }
            }
        }
    }

    let mut packets = 0;
    let mut messages = 0;
    for conn in conns {
        let n = conn["conn"].as_u64().unwrap();
        let ours = sent.remove(&n).unwrap_or_default();
        let theirs = &s2c[&n];
        for (i, rec) in theirs.iter().enumerate() {
            let Some(mine) = ours.get(i) else {
                panic!(
                    "{scenario} conn {n}: the C++ DB sent {} packets, we sent {}; first missing: {:#?}",
                    theirs.len(),
                    ours.len(),
                    rec.msgs
                );
            };
            let a: Vec<Message> = mine.iter().map(|m| comparable(m, &db_name)).collect();
            let b: Vec<Message> = rec.msgs.iter().map(|m| comparable(m, &db_name)).collect();
            assert_eq!(
                a, b,
                "{scenario} conn {n}: packet {i} (recorded at s2c offset {}) differs",
                rec.off
            );
            packets += 1;
            messages += b.len();
        }
        assert_eq!(
            ours.len(),
            theirs.len(),
            "{scenario} conn {n}: we sent extra packets: {:#?}",
            &ours[theirs.len().min(ours.len())..]
        );
    }
    (packets, messages)
}

#[test]
fn replay_poke() {
    assert_eq!(replay("poke"), (11, 31));
}

#[test]
fn replay_clash() {
    let (p, _) = replay("clash");
    assert!(p > 0);
}

#[test]
fn replay_binary() {
    let (p, _) = replay("binary");
    assert!(p > 0);
}

#[test]
fn replay_scope() {
    let (p, _) = replay("scope");
    assert!(p > 0);
}

#[test]
fn replay_logger() {
    let (p, _) = replay("logger");
    assert!(p > 0);
}

#[test]
fn replay_reconnect() {
    let (p, _) = replay("reconnect");
    assert!(p > 0);
}

#[test]
fn replay_helm() {
    let (p, _) = replay("helm");
    assert!(p > 0);
}
