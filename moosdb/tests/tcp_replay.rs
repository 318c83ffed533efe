//! Recorded C++ clients' bytes sent over TCP to the embedded server: the answers carry the
//! same messages the real MOOSDB sent (the DB's own clock-driven variables and timing echoes
//! aside, which depend on when the replay runs).

mod common;

use std::net::SocketAddr;
use std::time::Duration;

use futures_util::StreamExt;
use moosdb::codec::MoosCodec;
use moosdb::{Message, MsgType, Server, ServerConfig};
use tokio::io::AsyncWriteExt;
use tokio::net::TcpStream;
use tokio::time::timeout;
use tokio_util::codec::FramedRead;

async fn server_for(scenario: &str) -> Server {
    let idx = common::index(scenario);
    let mission = idx["mission_file"].as_str().unwrap();
    let mut cfg = ServerConfig::with_addr(SocketAddr::from(([127, 0, 0, 1], 0)));
    cfg.db.community = common::mission_value(mission, "Community").unwrap();
    Server::bind(cfg).await.unwrap()
}

/// Messages a client receives that do not depend on the DB's clock.
fn steady(msgs: &[Message]) -> Vec<Message> {
    msgs.iter()
        .filter(|m| m.msg_type != MsgType::Timing && !m.src_str().starts_with("MOOSDB_"))
        .map(|m| {
            let mut m = m.clone();
            if m.msg_type == MsgType::Welcome {
                m.time = 0.0;
                m.dval = 0.0;
                m.src_aux = Default::default();
            }
            m
        })
        .collect()
}

/// Sends one recorded connection's packets with the recorded spacing; returns what came back.
async fn replay_conn(addr: SocketAddr, scenario: &str, conn: usize) -> Vec<Message> {
    let idx = common::index(scenario);
    let c = &idx["connections"][conn - 1];
    let bytes = common::bin(scenario, c["c2s_file"].as_str().unwrap());
    let packets = common::packets(c, "c2s_packets");
    let s = TcpStream::connect(addr).await.unwrap();
    let (rd, mut wr) = s.into_split();
    let reader = tokio::spawn(async move {
        let mut r = FramedRead::new(rd, MoosCodec::new(1 << 24));
        let mut got = Vec::new();
        while let Ok(Some(Ok(p))) = timeout(Duration::from_secs(10), r.next()).await {
            got.extend(p);
        }
        got
    });
    wr.write_all(&bytes[..32]).await.unwrap();
    let t0 = packets[0].t;
    let start = tokio::time::Instant::now();
    for p in &packets {
        tokio::time::sleep_until(start + Duration::from_secs_f64(p.t - t0)).await;
        wr.write_all(&bytes[p.off..p.off + p.len]).await.unwrap();
    }
    tokio::time::sleep(Duration::from_millis(300)).await;
    drop(wr);
    reader.await.unwrap()
}

fn recorded(scenario: &str, conn: usize) -> Vec<Message> {
    let idx = common::index(scenario);
    common::packets(&idx["connections"][conn - 1], "s2c_packets")
        .into_iter()
        .flat_map(|p| p.msgs)
        .collect()
}

#[tokio::test]
async fn poke_client_bytes_get_the_recorded_answers() {
    let srv = server_for("poke").await;
    let got = replay_conn(srv.local_addr(), "poke", 1).await;
    let want = recorded("poke", 1);
    assert_eq!(steady(&got), steady(&want));
    assert!(steady(&want).len() >= 5);
}

#[tokio::test]
async fn binary_subscriber_gets_the_recorded_binary_mail() {
    let srv = server_for("binary").await;
    let addr = srv.local_addr();
    let sub = tokio::spawn(async move { replay_conn(addr, "binary", 1).await });
    // Start the publisher when the recording did (2 s after the subscriber).
    tokio::time::sleep(Duration::from_secs(2)).await;
    let publ = replay_conn(addr, "binary", 2).await;
    let sub = sub.await.unwrap();
    assert_eq!(steady(&sub), steady(&recorded("binary", 1)));
    assert_eq!(steady(&publ), steady(&recorded("binary", 2)));
    let bin = sub
        .iter()
        .find(|m| m.key_str() == "BIN_DATA")
        .expect("binary mail");
    assert_eq!(bin.sval.len(), 64);
}

#[tokio::test]
async fn clash_second_client_gets_the_recorded_poison() {
    let srv = server_for("clash").await;
    let addr = srv.local_addr();
    let first = tokio::spawn(async move { replay_conn(addr, "clash", 1).await });
    tokio::time::sleep(Duration::from_millis(1000)).await;
    let second = replay_conn(addr, "clash", 2).await;
    assert_eq!(second.len(), 1);
    assert_eq!(
        second,
        recorded("clash", 2)
            .into_iter()
            .map(|mut m| {
                m.time = second[0].time;
                m
            })
            .collect::<Vec<_>>()
    );
    assert_eq!(second[0].msg_type, MsgType::Poison);
    let first = first.await.unwrap();
    assert_eq!(steady(&first), steady(&recorded("clash", 1)));
}
