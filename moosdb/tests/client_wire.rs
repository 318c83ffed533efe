//! What the client puts on the wire, seen by a scripted fake DB on loopback: the preamble and
//! name packet, the timing message heading the first packet and then at most once per
//! second, message ids and sources, re-registration after a reconnect with ids continuing,
//! skew from the Welcome, and a Poison ending the client for good.

use std::time::{Duration, Instant};

use bytes::Bytes;
use futures_util::{SinkExt, StreamExt};
use moosdb::codec::{MoosCodec, PREAMBLE};
use moosdb::{Client, ClientConfig, ConnectionState, DataType, Message, MsgType, Value};
use tokio::io::AsyncReadExt;
use tokio::net::{TcpListener, TcpStream};
use tokio::time::timeout;
use tokio_util::codec::Framed;

const WAIT: Duration = Duration::from_secs(15);

async fn accept_handshake(l: &TcpListener) -> (Framed<TcpStream, MoosCodec>, Message) {
    let (mut s, _) = timeout(WAIT, l.accept())
        .await
        .expect("client connects")
        .unwrap();
    let mut pre = [0u8; 32];
    s.read_exact(&mut pre).await.unwrap();
    assert_eq!(pre, PREAMBLE);
    let mut r = Framed::new(s, MoosCodec::new(1 << 20));
    let hello = r.next().await.unwrap().unwrap();
    assert_eq!(hello.len(), 1);
    (r, hello.into_iter().next().unwrap())
}

fn welcome(skew: f64) -> Message {
    let mut w = Message::new(MsgType::Welcome, DataType::Double, "");
    w.dval = skew;
    w.sval = Bytes::from_static(b"asynchronous");
    w.src_aux = Bytes::from_static(b"hostname=fakehost");
    w.community = Bytes::from_static(b"fake");
    w
}

/// Reads packets for `dur`, with the arrival instant of each.
async fn collect(
    r: &mut Framed<TcpStream, MoosCodec>,
    dur: Duration,
) -> Vec<(Instant, Vec<Message>)> {
    let mut out = Vec::new();
    let end = tokio::time::Instant::now() + dur;
    while let Ok(p) = tokio::time::timeout_at(end, r.next()).await {
        out.push((
            Instant::now(),
            p.expect("client keeps the connection").unwrap(),
        ));
    }
    out
}

#[tokio::test]
async fn handshake_timing_ids_and_reconnect() {
    let l = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let port = l.local_addr().unwrap().port();
    let (c, _mail) = Client::start(ClientConfig::new("pWire", "127.0.0.1", port));
    let (mut r, hello) = accept_handshake(&l).await;
    assert_eq!(
        (hello.msg_type, hello.data_type, hello.id),
        (MsgType::Data, DataType::String, -1)
    );
    assert_eq!(
        (hello.key_str().as_ref(), hello.sval_str().as_ref()),
        ("asynchronous", "pWire")
    );
    assert_eq!((hello.dval, hello.dval2), (-1.0, -1.0));
    assert!(hello.src.is_empty() && hello.community.is_empty());

    r.send(&[welcome(100.0)][..]).await.unwrap();
    timeout(WAIT, c.wait_connected()).await.unwrap().unwrap();
    assert_eq!(
        c.state(),
        ConnectionState::Connected {
            community: "fake".into(),
            db_host: "fakehost".into()
        }
    );
    assert!((c.skew() - 100.0).abs() < 1e-9, "skew from the Welcome");
    c.register("A", 0.5);
    c.notify("N", Value::Double(2.0)).unwrap();
    c.notify("S", Value::from("s")).unwrap();
    let packets = collect(&mut r, Duration::from_millis(3500)).await;
    let first = &packets[0].1;
    assert_eq!(
        first[0].msg_type,
        MsgType::Timing,
        "first packet starts with T"
    );
    assert_eq!(
        (first[0].key_str().as_ref(), first[0].id, first[0].dval),
        ("_async_timing", -1, 0.0)
    );
    let all: Vec<&Message> = packets.iter().flat_map(|(_, p)| p).collect();
    let posted: Vec<(MsgType, i32, String)> = all
        .iter()
        .filter(|m| m.msg_type != MsgType::Timing)
        .map(|m| (m.msg_type, m.id, m.key_str().into_owned()))
        .collect();
    assert_eq!(
        posted,
        vec![
            (MsgType::Register, 0, "A".into()),
            (MsgType::Notify, 1, "N".into()),
            (MsgType::Notify, 2, "S".into())
        ]
    );
    for m in all.iter().filter(|m| m.msg_type != MsgType::Timing) {
        assert_eq!(m.src_str(), "pWire");
        assert!(m.community.is_empty());
    }
    let reg = all
        .iter()
        .find(|m| m.msg_type == MsgType::Register)
        .unwrap();
    assert_eq!(reg.dval, 0.5);
    // T at most once per (unwarped) second, always first in its packet, sent even when idle.
    let t_times: Vec<Instant> = packets
        .iter()
        .filter(|(_, p)| p[0].msg_type == MsgType::Timing)
        .map(|(t, _)| *t)
        .collect();
    assert!(
        t_times.len() >= 2,
        "heartbeats while idle: {}",
        t_times.len()
    );
    for w in t_times.windows(2) {
        assert!(
            w[1] - w[0] >= Duration::from_millis(900),
            "T too often: {:?}",
            w[1] - w[0]
        );
    }
    for (_, p) in &packets {
        assert!(p.iter().skip(1).all(|m| m.msg_type != MsgType::Timing));
    }

    // The DB goes away: the client reconnects, re-registers, and ids continue.
    drop(r);
    let (mut r2, hello2) = accept_handshake(&l).await;
    assert_eq!(hello2.sval_str(), "pWire");
    r2.send(&[welcome(0.0)][..]).await.unwrap();
    let again = collect(&mut r2, Duration::from_millis(1200)).await;
    let regs: Vec<(i32, String)> = again
        .iter()
        .flat_map(|(_, p)| p)
        .filter(|m| m.msg_type == MsgType::Register)
        .map(|m| (m.id, m.key_str().into_owned()))
        .collect();
    assert_eq!(regs, vec![(3, "A".to_string())]);
    c.close().await;
}

#[tokio::test]
async fn poison_is_final() {
    let l = TcpListener::bind("127.0.0.1:0").await.unwrap();
    let port = l.local_addr().unwrap().port();
    let (c, _mail) = Client::start(ClientConfig::new("dup", "127.0.0.1", port));
    let (mut r, _) = accept_handshake(&l).await;
    let mut k = Message::new(MsgType::Poison, DataType::String, "");
    k.sval = Bytes::from_static(b"A client of this name (\"dup\") already exists");
    r.send(&[k][..]).await.unwrap();
    let err = timeout(WAIT, c.wait_connected())
        .await
        .unwrap()
        .unwrap_err();
    assert_eq!(
        err,
        moosdb::ClientError::Poisoned("A client of this name (\"dup\") already exists".into())
    );
    // No second attempt within 2.5 s (a retry would come after 1 s).
    assert!(
        timeout(Duration::from_millis(2500), l.accept())
            .await
            .is_err()
    );
    assert_eq!(
        c.notify("X", Value::Double(1.0)),
        Err(moosdb::ClientError::NotConnected)
    );
}
