//! Connection churn (the C++ MOOSDB's failure mode, reference section 11.4): 1000 rounds of
//! 3 connects, 3 abrupt closes and 1 connect that must be welcomed, with no pause, while a
//! subscriber receives a 50 Hz variable without missing a value.

use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use bytes::Bytes;
use futures_util::StreamExt;
use moosdb::codec::{MoosCodec, PREAMBLE};
use moosdb::packet::encode_packet;
use moosdb::{Client, ClientConfig, DataType, Message, MsgType, Server, ServerConfig, Value};
use tokio::io::AsyncWriteExt;
use tokio::net::TcpStream;
use tokio::time::timeout;
use tokio_util::codec::FramedRead;

const ROUNDS: usize = 1000;

fn hello(name: &str) -> Vec<u8> {
    let mut m = Message::new(MsgType::Data, DataType::String, "asynchronous");
    m.sval = Bytes::from(name.to_string());
    m.time = moosdb::time::unix_now();
    let mut buf = PREAMBLE.to_vec();
    encode_packet(&[m], &mut buf);
    buf
}

async fn one_round(addr: SocketAddr, round: usize) -> Result<(), String> {
    // Three connects, closed abruptly at different points of the handshake.
    let a = TcpStream::connect(addr).await.map_err(|e| e.to_string())?;
    let mut b = TcpStream::connect(addr).await.map_err(|e| e.to_string())?;
    let mut c = TcpStream::connect(addr).await.map_err(|e| e.to_string())?;
    let _ = b.write_all(&PREAMBLE[..20]).await;
    let _ = c.write_all(&hello(&format!("churn_gone_{round}"))).await;
    drop(a);
    drop(b);
    drop(c);
    // One connect that must be welcomed.
    let mut s = TcpStream::connect(addr).await.map_err(|e| e.to_string())?;
    s.set_nodelay(true).map_err(|e| e.to_string())?;
    s.write_all(&hello(&format!("churn_{round}")))
        .await
        .map_err(|e| e.to_string())?;
    let mut r = FramedRead::new(s, MoosCodec::new(1 << 20));
    let reply = timeout(Duration::from_secs(10), r.next())
        .await
        .map_err(|_| format!("round {round}: no Welcome within 10 s"))?
        .ok_or_else(|| format!("round {round}: closed without Welcome"))?
        .map_err(|e| format!("round {round}: {e}"))?;
    match reply.first() {
        Some(m) if m.msg_type == MsgType::Welcome => Ok(()),
        other => Err(format!("round {round}: expected Welcome, got {other:?}")),
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn churn_never_blocks_handshakes_or_mail() {
    let cfg = ServerConfig::with_addr(SocketAddr::from(([127, 0, 0, 1], 0)));
    let srv = Server::bind(cfg).await.unwrap();
    let addr = srv.local_addr();
    let port = addr.port();

    let (sub, mut mail) = Client::start(ClientConfig::new("churn_sub", "127.0.0.1", port));
    let (publ, _pm) = Client::start(ClientConfig::new("churn_pub", "127.0.0.1", port));
    timeout(Duration::from_secs(10), sub.wait_connected())
        .await
        .unwrap()
        .unwrap();
    timeout(Duration::from_secs(10), publ.wait_connected())
        .await
        .unwrap()
        .unwrap();
    sub.register("TICK", 0.0);
    timeout(Duration::from_secs(10), async {
        while !srv.with_db(|db| db.subscribers("TICK").contains(&"churn_sub".to_string())) {
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
    })
    .await
    .expect("subscription in place");

    let stop = Arc::new(AtomicBool::new(false));
    let publ = Arc::new(publ);
    let publisher = {
        let stop = stop.clone();
        let publ = publ.clone();
        tokio::spawn(async move {
            let mut tick = tokio::time::interval(Duration::from_millis(20));
            let mut n = 0u64;
            while !stop.load(Ordering::Relaxed) {
                tick.tick().await;
                publ.notify("TICK", Value::Double(n as f64))
                    .expect("publisher connected");
                n += 1;
            }
            n
        })
    };

    let started = std::time::Instant::now();
    for round in 0..ROUNDS {
        one_round(addr, round).await.unwrap();
    }
    let churn_time = started.elapsed();
    stop.store(true, Ordering::Relaxed);
    let sent = publisher.await.unwrap();
    assert!(sent > 0);

    let mut expected = 0u64;
    timeout(Duration::from_secs(20), async {
        while expected < sent {
            let m = mail.recv().await.expect("mail open");
            if m.key_str() != "TICK" {
                continue;
            }
            assert_eq!(m.dval as u64, expected, "subscriber missed a 50 Hz value");
            expected += 1;
        }
    })
    .await
    .unwrap_or_else(|_| panic!("subscriber got {expected} of {sent} values"));
    eprintln!("churn: {ROUNDS} rounds in {churn_time:?}, {sent} ticks at 50 Hz all received");
    assert!(matches!(
        sub.state(),
        moosdb::ConnectionState::Connected { .. }
    ));
}
