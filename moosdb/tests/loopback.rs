//! Client and embedded server on 127.0.0.1 with OS-assigned ports. Every wait is bounded
//! and generous; nothing depends on precise wall-clock timing.

use std::net::SocketAddr;
use std::time::Duration;

use bytes::Bytes;
use futures_util::{SinkExt, StreamExt};
use moosdb::codec::{MoosCodec, PREAMBLE};
use moosdb::packet::encode_packet;
use moosdb::{
    Client, ClientConfig, ClientError, ConnectionState, DataType, MailStream, Message, MsgType,
    Server, ServerConfig, Value,
};
use tokio::io::AsyncWriteExt;
use tokio::net::TcpStream;
use tokio::time::timeout;
use tokio_util::codec::Framed;

const WAIT: Duration = Duration::from_secs(15);

async fn server_at(addr: SocketAddr) -> Server {
    let mut cfg = ServerConfig::with_addr(addr);
    cfg.db.community = "loop".into();
    Server::bind(cfg).await.expect("bind loopback")
}

async fn server() -> Server {
    server_at(SocketAddr::from(([127, 0, 0, 1], 0))).await
}

async fn client(srv: &Server, name: &str) -> (Client, MailStream) {
    let (c, m) = Client::start(ClientConfig::new(
        name,
        "127.0.0.1",
        srv.local_addr().port(),
    ));
    timeout(WAIT, c.wait_connected())
        .await
        .expect("connect in time")
        .expect("welcomed");
    (c, m)
}

/// Waits (bounded) until `client` is (or is no longer) subscribed to `key` in the DB.
async fn subscribed(srv: &Server, client: &str, key: &str, yes: bool) {
    timeout(WAIT, async {
        while srv.with_db(|db| db.subscribers(key).iter().any(|c| c == client)) != yes {
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
    })
    .await
    .unwrap_or_else(|_| panic!("{client} subscription to {key} never became {yes}"));
}

/// The next mail for `key`, skipping other variables.
async fn next_for(mail: &mut MailStream, key: &str) -> Message {
    timeout(WAIT, async {
        loop {
            let m = mail.recv().await.expect("mail stream open");
            if m.key_str() == key {
                return m;
            }
        }
    })
    .await
    .unwrap_or_else(|_| panic!("no mail for {key} within {WAIT:?}"))
}

#[tokio::test]
async fn register_notify_wildcard_unregister() {
    let srv = server().await;
    let (sub, mut mail) = client(&srv, "sub").await;
    let (publ, _pm) = client(&srv, "pub").await;
    sub.register("X", 0.0);
    sub.register("S", 0.0);
    sub.register("B", 0.0);
    sub.register("DONE", 0.0);
    for k in ["X", "S", "B", "DONE"] {
        subscribed(&srv, "sub", k, true).await;
    }

    publ.notify("X", Value::Double(1.5)).unwrap();
    publ.notify_with("S", Value::from("hello"), Some(123.0), "aux:1")
        .unwrap();
    publ.notify("B", Value::Binary(vec![0, 255, 7])).unwrap();
    let x = next_for(&mut mail, "X").await;
    assert_eq!(
        (x.dval, x.data_type, x.src_str().as_ref()),
        (1.5, DataType::Double, "pub")
    );
    assert_eq!(x.community, Bytes::from_static(b"loop"));
    let s = next_for(&mut mail, "S").await;
    assert_eq!(s.sval_str(), "hello");
    assert_eq!((s.time, s.src_aux.as_ref()), (123.0, &b"aux:1"[..]));
    let b = next_for(&mut mail, "B").await;
    assert_eq!(
        (b.data_type, b.sval.as_ref()),
        (DataType::Binary, &[0u8, 255, 7][..])
    );

    // Wildcard: existing NAV_OLD replayed at once, future NAV_NEW delivered, OTHER not.
    publ.notify("NAV_OLD", Value::Double(1.0)).unwrap();
    timeout(WAIT, async {
        while srv.with_db(|db| db.current("NAV_OLD").is_none()) {
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
    })
    .await
    .unwrap();
    sub.register_pattern("NAV_*", "p*", 0.0);
    let old = next_for(&mut mail, "NAV_OLD").await;
    assert_eq!(old.dval, 1.0);
    publ.notify("OTHER", Value::Double(9.0)).unwrap();
    publ.notify("NAV_NEW", Value::Double(2.0)).unwrap();
    let new = next_for(&mut mail, "NAV_NEW").await;
    assert_eq!(new.dval, 2.0);

    // Unregister: later writes of X no longer arrive (DONE marks the end).
    sub.unregister("X");
    subscribed(&srv, "sub", "X", false).await;
    publ.notify("X", Value::Double(7.0)).unwrap();
    publ.notify("DONE", Value::Double(1.0)).unwrap();
    let mut seen = Vec::new();
    timeout(WAIT, async {
        loop {
            let m = mail.recv().await.unwrap();
            if m.key_str() == "DONE" {
                break;
            }
            seen.push(m.key_str().into_owned());
        }
    })
    .await
    .unwrap();
    assert!(
        !seen.contains(&"X".to_string()),
        "X after unregister: {seen:?}"
    );
    assert!(
        !seen.contains(&"OTHER".to_string()),
        "pattern leak: {seen:?}"
    );
    sub.close().await;
    publ.close().await;
}

#[tokio::test]
async fn name_clash_gets_poison_and_does_not_retry() {
    let srv = server().await;
    let (_first, _m) = client(&srv, "twin").await;
    let (second, _m2) = Client::start(ClientConfig::new(
        "twin",
        "127.0.0.1",
        srv.local_addr().port(),
    ));
    let r = timeout(WAIT, second.wait_connected()).await.unwrap();
    match r {
        Err(ClientError::Poisoned(reason)) => {
            assert_eq!(reason, "A client of this name (\"twin\") already exists")
        }
        other => panic!("expected Poison, got {other:?}"),
    }
    tokio::time::sleep(Duration::from_millis(1500)).await;
    assert!(matches!(second.state(), ConnectionState::Poisoned(_)));
    assert_eq!(
        srv.with_db(|db| db.client_names()),
        vec!["twin".to_string()]
    );
}

/// Handshakes by hand: returns the stream and the DB's reply.
async fn raw_handshake(addr: SocketAddr, name: &str) -> (Framed<TcpStream, MoosCodec>, Message) {
    let mut s = TcpStream::connect(addr).await.expect("connect");
    s.set_nodelay(true).unwrap();
    let mut hello = Message::new(MsgType::Data, DataType::String, "asynchronous");
    hello.sval = Bytes::from(name.to_string());
    hello.time = moosdb::time::unix_now();
    let mut buf = PREAMBLE.to_vec();
    encode_packet(&[hello], &mut buf);
    s.write_all(&buf).await.unwrap();
    let mut r = Framed::new(s, MoosCodec::new(1 << 20));
    let reply = timeout(WAIT, r.next())
        .await
        .expect("reply in time")
        .expect("a packet")
        .expect("readable");
    (r, reply.into_iter().next().expect("one message"))
}

#[tokio::test]
async fn killed_client_leaves_db_clients_within_6s() {
    let srv = server().await;
    let (watcher, mut mail) = client(&srv, "watcher").await;
    watcher.register("DB_CLIENTS", 0.0);
    // Like every MOOS app the watcher posts a status now and then: in MOOS (and here) the
    // DB's own variables reach idle asynchronous clients only when some client posts.
    let watcher = std::sync::Arc::new(watcher);
    let w2 = watcher.clone();
    let status = tokio::spawn(async move {
        loop {
            let _ = w2.notify("WATCHER_STATUS", Value::from("AppErrorFlag=false"));
            tokio::time::sleep(Duration::from_millis(500)).await;
        }
    });
    let (victim, _vm) = client(&srv, "victim").await;
    // Wait until DB_CLIENTS lists the victim.
    timeout(WAIT, async {
        loop {
            let m = next_for(&mut mail, "DB_CLIENTS").await;
            if m.sval_str().contains("victim,") {
                break;
            }
        }
    })
    .await
    .unwrap();
    victim.abort();
    let killed = tokio::time::Instant::now();
    timeout(Duration::from_secs(6), async {
        loop {
            let m = next_for(&mut mail, "DB_CLIENTS").await;
            if !m.sval_str().contains("victim") {
                break;
            }
        }
    })
    .await
    .expect("victim still listed in DB_CLIENTS 6 s after it was killed");
    assert!(killed.elapsed() <= Duration::from_secs(6));

    // A client that hangs (socket open, silent) is removed after the 5 s client timeout.
    let (_hung, reply) = raw_handshake(srv.local_addr(), "hung").await;
    assert_eq!(reply.msg_type, MsgType::Welcome);
    assert!(srv.with_db(|db| db.client_id("hung").is_some()));
    let t0 = tokio::time::Instant::now();
    timeout(Duration::from_secs(12), async {
        while srv.with_db(|db| db.client_id("hung").is_some()) {
            tokio::time::sleep(Duration::from_millis(100)).await;
        }
    })
    .await
    .expect("silent client never removed");
    assert!(
        t0.elapsed() >= Duration::from_secs(4),
        "removed too early: {:?}",
        t0.elapsed()
    );
    status.abort();
}

#[tokio::test]
async fn db_restart_client_reconnects_and_resubscribes() {
    let srv = server().await;
    let addr = srv.local_addr();
    let (sub, mut mail) = client(&srv, "resub").await;
    sub.register("R", 0.0);
    sub.register_pattern("W_*", "*", 0.0);
    subscribed(&srv, "resub", "R", true).await;
    srv.shutdown();
    tokio::time::sleep(Duration::from_millis(300)).await;
    let srv2 = server_at(addr).await;
    timeout(WAIT, async {
        while srv2.with_db(|db| db.client_id("resub").is_none()) {
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    })
    .await
    .expect("client reconnected to the restarted DB");
    timeout(WAIT, sub.wait_connected()).await.unwrap().unwrap();
    let (publ, _pm) = client(&srv2, "pub2").await;
    // The re-applied registration (and the pattern, sent in the same packet) is in place
    // before anything is posted.
    subscribed(&srv2, "resub", "R", true).await;
    publ.notify("R", Value::Double(42.0)).unwrap();
    publ.notify("W_1", Value::from("w")).unwrap();
    assert_eq!(next_for(&mut mail, "R").await.dval, 42.0);
    assert_eq!(next_for(&mut mail, "W_1").await.sval_str(), "w");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn stuck_client_does_not_stall_a_fast_subscriber() {
    let srv = server().await;
    let (fast, mut mail) = client(&srv, "fast").await;
    fast.register("SEQ", 0.0);
    // The stuck client registers and then never reads again (it keeps the socket open and
    // sends heartbeats so it is not dropped for silence).
    let (mut stuck, reply) = raw_handshake(srv.local_addr(), "stuck").await;
    assert_eq!(reply.msg_type, MsgType::Welcome);
    let mut reg = Message::new(MsgType::Register, DataType::Double, "SEQ");
    reg.src = Bytes::from_static(b"stuck");
    reg.dval = 0.0;
    let mut buf = Vec::new();
    encode_packet(&[reg], &mut buf);
    stuck.get_mut().write_all(&buf).await.unwrap();
    let (stuck_tx, mut stuck_rx) = tokio::sync::mpsc::channel::<Vec<u8>>(4);
    let heartbeat = tokio::spawn(async move {
        let mut t = Message::new(MsgType::Timing, DataType::Double, "_async_timing");
        t.dval = 0.0;
        let mut hb = Vec::new();
        encode_packet(&[t], &mut hb);
        loop {
            let bytes = tokio::select! {
                _ = tokio::time::sleep(Duration::from_millis(500)) => hb.clone(),
                b = stuck_rx.recv() => match b { Some(b) => b, None => return },
            };
            if stuck.get_mut().write_all(&bytes).await.is_err() {
                return;
            }
        }
    });
    // The stuck client also takes big blobs: far more than socket buffers hold, so its
    // outbox must overflow while the fast subscriber is served.
    let mut reg = Message::new(MsgType::Register, DataType::Double, "BLOB");
    reg.src = Bytes::from_static(b"stuck");
    reg.dval = 0.0;
    let mut buf = Vec::new();
    encode_packet(&[reg], &mut buf);
    stuck_tx.send(buf).await.unwrap();
    let (publ, _pm) = client(&srv, "firehose").await;
    subscribed(&srv, "fast", "SEQ", true).await;
    subscribed(&srv, "stuck", "SEQ", true).await;
    subscribed(&srv, "stuck", "BLOB", true).await;
    let blob = vec![7u8; 256 * 1024];
    for _ in 0..200 {
        publ.notify("BLOB", Value::Binary(blob.clone())).unwrap();
    }
    const N: usize = 30_000;
    // The publisher keeps at most WINDOW messages in flight towards the fast subscriber (as a
    // real app's pace would), so only the stuck client can fall behind, however loaded the
    // machine is.
    const WINDOW: usize = 1000;
    let payload = "x".repeat(100);
    let received = std::sync::atomic::AtomicUsize::new(0);
    let sender = async {
        for i in 0..N {
            while i - received.load(std::sync::atomic::Ordering::Relaxed) >= WINDOW {
                tokio::time::sleep(Duration::from_millis(1)).await;
            }
            publ.notify("SEQ", Value::String(format!("{i:08}{payload}").into()))
                .unwrap();
        }
    };
    let receiver = async {
        let mut next = 0usize;
        while next < N {
            let m = next_for(&mut mail, "SEQ").await;
            let seq: usize = m.sval_str()[..8].parse().unwrap();
            if seq != next {
                let fast_dropped = srv.with_db(|db| db.dropped(db.client_id("fast").unwrap()));
                panic!("fast subscriber got {seq}, expected {next} (its drops: {fast_dropped:?})");
            }
            next += 1;
            received.store(next, std::sync::atomic::Ordering::Relaxed);
        }
    };
    timeout(Duration::from_secs(120), async {
        tokio::join!(sender, receiver)
    })
    .await
    .expect("fast subscriber kept up");
    let stuck_id = srv
        .with_db(|db| db.client_id("stuck"))
        .expect("stuck still connected");
    let dropped = srv.with_db(|db| db.dropped(stuck_id)).unwrap();
    assert!(dropped > 0, "the stuck client's overflow must be counted");
    assert_eq!(
        srv.with_db(|db| db.dropped(db.client_id("fast").unwrap())),
        Some(0)
    );
    heartbeat.abort();
}

#[tokio::test]
async fn client_retries_until_the_db_appears() {
    // Find a free port, release it, start the client first.
    let probe = server().await;
    let addr = probe.local_addr();
    probe.shutdown();
    tokio::time::sleep(Duration::from_millis(200)).await;
    let (c, _m) = Client::start(ClientConfig::new("early", "127.0.0.1", addr.port()));
    tokio::time::sleep(Duration::from_millis(1500)).await;
    assert_eq!(c.state(), ConnectionState::Connecting);
    let srv = server_at(addr).await;
    timeout(WAIT, c.wait_connected()).await.unwrap().unwrap();
    match c.state() {
        ConnectionState::Connected { community, .. } => assert_eq!(community, "loop"),
        other => panic!("{other:?}"),
    }
    assert!(srv.with_db(|db| db.client_id("early").is_some()));
}

#[tokio::test]
async fn warped_client_and_db_agree_on_moos_time() {
    let mut cfg = ServerConfig::with_addr(SocketAddr::from(([127, 0, 0, 1], 0)));
    cfg.warp = moosdb::time::Warp::new(10.0).unwrap();
    let srv = Server::bind(cfg).await.unwrap();
    let port = srv.local_addr().port();
    let mut ccfg = ClientConfig::new("warped", "127.0.0.1", port);
    ccfg.warp = moosdb::time::Warp::new(10.0).unwrap();
    let (c, mut mail) = Client::start(ccfg);
    timeout(WAIT, c.wait_connected()).await.unwrap().unwrap();
    c.register("W", 0.0);
    subscribed(&srv, "warped", "W", true).await;
    c.notify("W", Value::Double(1.0)).unwrap();
    let m = next_for(&mut mail, "W").await;
    let warped_now = 10.0 * moosdb::time::unix_now();
    // MOOS time is the absolute Unix time times the warp (about 1.8e10 here, not 1.8e9);
    // on one host the skew is only the (warped) handshake delay. Bounds allow 10 s of
    // real delay on a loaded machine.
    assert!(
        (m.time - warped_now).abs() < 100.0,
        "{} vs {warped_now}",
        m.time
    );
    assert!(c.skew().abs() < 100.0, "skew {}", c.skew());
    assert!((c.moos_time() - warped_now).abs() < 100.0);
}

/// Sends one message as a packet and reads the reply packet (bounded wait).
async fn exchange(r: &mut Framed<TcpStream, MoosCodec>, m: Message) -> Vec<Message> {
    r.send(&[m][..]).await.unwrap();
    timeout(WAIT, r.next())
        .await
        .expect("reply in time")
        .expect("a packet")
        .expect("readable")
}

#[tokio::test]
async fn old_synchronous_client_is_served() {
    let srv = server().await;
    let addr = srv.local_addr();
    let mut s = TcpStream::connect(addr).await.unwrap();
    let mut hello = Message::new(MsgType::Data, DataType::String, "");
    hello.sval = Bytes::from_static(b"oldie");
    let mut buf = PREAMBLE.to_vec();
    encode_packet(&[hello], &mut buf);
    s.write_all(&buf).await.unwrap();
    let mut r = Framed::new(s, MoosCodec::new(1 << 20));
    let w = r.next().await.unwrap().unwrap();
    assert_eq!(w[0].msg_type, MsgType::Welcome);
    let mut reg = Message::new(MsgType::Register, DataType::Double, "OLD");
    reg.src = Bytes::from_static(b"oldie");
    reg.dval = 0.0;
    let reply = exchange(&mut r, reg).await;
    assert_eq!(
        reply[0].msg_type,
        MsgType::Null,
        "sync replies start with NULL"
    );
    let (publ, _pm) = client(&srv, "newbie").await;
    publ.notify("OLD", Value::Double(3.0)).unwrap();
    // No push to a polling client: its mail waits for its next call.
    assert!(timeout(Duration::from_millis(700), r.next()).await.is_err());
    let mut null = Message::new(MsgType::Null, DataType::Double, "");
    null.src = Bytes::from_static(b"oldie");
    let reply = exchange(&mut r, null).await;
    assert_eq!(reply[0].msg_type, MsgType::Null);
    let old = reply
        .iter()
        .find(|m| m.key_str() == "OLD")
        .expect("held mail delivered");
    assert_eq!((old.dval, old.src_str().as_ref()), (3.0, "newbie"));
}
