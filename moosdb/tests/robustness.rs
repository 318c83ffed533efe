//! Random and mutated bytes against the decoder and against a live server: no panic, typed
//! errors, the offending connection is closed and everyone else keeps being served.

use std::net::SocketAddr;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use bytes::Bytes;
use futures_util::StreamExt;
use moosdb::codec::{MoosCodec, PREAMBLE};
use moosdb::packet::{StreamDecoder, decode_packet, encode_packet};
use moosdb::{
    Client, ClientConfig, DataType, MailStream, Message, MsgType, Server, ServerConfig, Value,
};
use proptest::prelude::*;
use tokio::io::AsyncWriteExt;
use tokio::net::TcpStream;
use tokio::runtime::Runtime;
use tokio::time::timeout;
use tokio_util::codec::FramedRead;

fn arb_msg() -> impl Strategy<Value = Message> {
    (
        any::<i32>(),
        prop::sample::select(MsgType::ALL.to_vec()),
        prop::sample::select(vec![
            DataType::Double,
            DataType::String,
            DataType::Binary,
            DataType::NotSet,
        ]),
        prop::collection::vec(any::<u8>(), 0..12),
        prop::collection::vec(any::<u8>(), 0..40),
        any::<f64>(),
        any::<f64>(),
    )
        .prop_map(|(id, t, d, key, sval, time, dval)| Message {
            id,
            msg_type: t,
            data_type: d,
            src: Bytes::from_static(b"fuzz"),
            src_aux: Bytes::new(),
            community: Bytes::new(),
            key: Bytes::from(key),
            time,
            dval,
            dval2: -1.0,
            sval: Bytes::from(sval),
        })
}

fn arb_packet() -> impl Strategy<Value = Vec<u8>> {
    prop::collection::vec(arb_msg(), 0..5).prop_map(|msgs| {
        let mut out = Vec::new();
        encode_packet(&msgs, &mut out);
        out
    })
}

/// A valid packet with a few bytes overwritten, some inserted, and maybe truncated.
fn arb_mutated() -> impl Strategy<Value = Vec<u8>> {
    (
        arb_packet(),
        prop::collection::vec((any::<usize>(), any::<u8>()), 0..6),
        prop::collection::vec((any::<usize>(), any::<u8>()), 0..3),
        any::<Option<usize>>(),
    )
        .prop_map(|(mut p, sets, inserts, cut)| {
            for (i, b) in sets {
                let n = p.len();
                p[i % n] = b;
            }
            for (i, b) in inserts {
                let n = p.len();
                p.insert(i % (n + 1), b);
            }
            if let Some(c) = cut {
                let n = p.len();
                p.truncate(c % (n + 1));
            }
            p
        })
}

/// Whole-packet decoding gives an error or messages that re-encode to the same bytes (apart
/// from the ignored compression flag); stream decoding in uneven 7-byte chunks never panics
/// and stops at the first error (the packet fuzz target's body).
fn check_decoder(bytes: &[u8]) {
    moos_wire::fuzz::moos_packet_in_chunks(bytes, 7);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn random_bytes_never_panic(bytes in prop::collection::vec(any::<u8>(), 0..300)) {
        check_decoder(&bytes);
    }

    #[test]
    fn mutated_packets_never_panic(bytes in arb_mutated()) {
        check_decoder(&bytes);
    }

    #[test]
    fn valid_packets_round_trip(bytes in arb_packet()) {
        let msgs = decode_packet(Bytes::from(bytes.clone())).unwrap();
        let mut again = Vec::new();
        encode_packet(&msgs, &mut again);
        prop_assert_eq!(again, bytes);
    }
}

struct Live {
    rt: Runtime,
    addr: SocketAddr,
    _server: Server,
    publ: Client,
    sub: Client,
    mail: tokio::sync::Mutex<MailStream>,
}

fn live() -> &'static Live {
    static LIVE: OnceLock<Live> = OnceLock::new();
    LIVE.get_or_init(|| {
        let rt = tokio::runtime::Builder::new_multi_thread()
            .worker_threads(2)
            .enable_all()
            .build()
            .unwrap();
        let (server, publ, sub, mail) = rt.block_on(async {
            let mut cfg = ServerConfig::with_addr(SocketAddr::from(([127, 0, 0, 1], 0)));
            cfg.max_packet_len = 1 << 20;
            let server = Server::bind(cfg).await.unwrap();
            let port = server.local_addr().port();
            let (publ, _) = Client::start(ClientConfig::new("good_pub", "127.0.0.1", port));
            let (sub, mail) = Client::start(ClientConfig::new("good_sub", "127.0.0.1", port));
            publ.wait_connected().await.unwrap();
            sub.wait_connected().await.unwrap();
            sub.register("ALIVE", 0.0);
            while !server.with_db(|db| db.subscribers("ALIVE").contains(&"good_sub".to_string())) {
                tokio::time::sleep(Duration::from_millis(10)).await;
            }
            (server, publ, sub, mail)
        });
        let addr = server.local_addr();
        Live {
            rt,
            addr,
            _server: server,
            publ,
            sub,
            mail: tokio::sync::Mutex::new(mail),
        }
    })
}

static CASE: AtomicUsize = AtomicUsize::new(0);

async fn attack(addr: SocketAddr, garbage: &[u8], after_handshake: bool) {
    let case = CASE.fetch_add(1, Ordering::Relaxed);
    let mut s = TcpStream::connect(addr).await.unwrap();
    let mut head = Vec::new();
    if after_handshake {
        let mut hello = Message::new(MsgType::Data, DataType::String, "asynchronous");
        hello.sval = Bytes::from(format!("attacker_{case}"));
        head = PREAMBLE.to_vec();
        encode_packet(&[hello], &mut head);
    }
    s.write_all(&head).await.unwrap();
    let _ = s.write_all(garbage).await;
    // Does our own decoder reject this stream? Then the server must hang up.
    let mut d = StreamDecoder::new(1 << 20);
    d.extend(garbage);
    let rejected = loop {
        match d.next_packet() {
            Ok(Some(_)) => continue,
            Ok(None) => break false,
            Err(_) => break true,
        }
    };
    if after_handshake && rejected {
        let mut r = FramedRead::new(s, MoosCodec::new(1 << 24));
        let closed = timeout(Duration::from_secs(10), async {
            loop {
                match r.next().await {
                    Some(Ok(_)) => continue,
                    None | Some(Err(_)) => return,
                }
            }
        })
        .await;
        assert!(
            closed.is_ok(),
            "server kept a connection that sent undecodable bytes"
        );
    }
}

async fn still_serving(l: &Live, n: f64) {
    l.publ.notify("ALIVE", Value::Double(n)).unwrap();
    let mut mail = l.mail.lock().await;
    timeout(Duration::from_secs(10), async {
        loop {
            let m = mail.recv().await.unwrap();
            if m.key_str() == "ALIVE" && m.dval == n {
                return;
            }
        }
    })
    .await
    .expect("good clients no longer served");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn live_server_survives_garbage(
        garbage in prop_oneof![prop::collection::vec(any::<u8>(), 1..200), arb_mutated()],
        after_handshake in any::<bool>(),
    ) {
        let l = live();
        let n = CASE.load(Ordering::Relaxed) as f64;
        l.rt.block_on(async {
            attack(l.addr, &garbage, after_handshake).await;
            still_serving(l, n).await;
        });
        assert!(matches!(l.sub.state(), moosdb::ConnectionState::Connected { .. }));
    }
}
