//! Apps run as MOOS processes over TCP against the project's MOOSDB (loopback, OS-chosen
//! port), watched by an independent client. Waits are bounded and generous; nothing
//! depends on how fast the machine is.

use std::time::Duration;

use moosdb_client::{Client, ClientConfig, Server, ServerConfig};
use runtime::remote::{RemoteConfig, RemoteError, run};
use runtime::{App, Mail, Post, Subscription};
use tokio::sync::watch;

struct Counter {
    n: u32,
}

impl App for Counter {
    fn name(&self) -> &str {
        "counter"
    }
    fn app_tick(&self) -> f64 {
        20.0
    }
    fn on_startup(&mut self, _now: f64, out: &mut Vec<Post>) {
        out.push(Post::text("COUNTER_UP", "true"));
    }
    fn iterate(&mut self, _now: f64, out: &mut Vec<Post>) {
        out.push(Post::double("COUNT", f64::from(self.n)));
        self.n += 1;
    }
}

struct Doubler {
    last: Option<f64>,
}

impl App for Doubler {
    fn name(&self) -> &str {
        "doubler"
    }
    fn app_tick(&self) -> f64 {
        10.0
    }
    fn subscriptions(&self) -> Vec<Subscription> {
        vec![Subscription::var("COUNT")]
    }
    fn on_mail(&mut self, mail: &[Mail], _now: f64, _out: &mut Vec<Post>) {
        assert!(
            mail.windows(2).all(|w| w[0].time <= w[1].time),
            "mail sorted by time"
        );
        if let Some(m) = mail.last() {
            assert_eq!(m.source, "counter");
            self.last = m.value.as_f64();
        }
    }
    fn iterate(&mut self, _now: f64, out: &mut Vec<Post>) {
        if let Some(v) = self.last {
            out.push(Post::double("DOUBLE", 2.0 * v).with_aux("doubled"));
        }
    }
}

async fn stopped(mut rx: watch::Receiver<bool>) {
    let _ = rx.wait_for(|s| *s).await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn two_apps_talk_through_a_tcp_moosdb() {
    let server = Server::bind(ServerConfig::with_addr(([127, 0, 0, 1], 0).into()))
        .await
        .unwrap();
    let port = server.local_addr().port();
    let cfg = RemoteConfig {
        host: "127.0.0.1".into(),
        port,
        warp: 1.0,
    };
    let (observer, mut inbox) = Client::start(ClientConfig::new("observer", "127.0.0.1", port));
    observer.wait_connected().await.unwrap();
    for v in ["COUNT", "DOUBLE", "COUNTER_UP", "DOUBLER_STATUS"] {
        observer.register(v, 0.0);
    }
    let (stop_tx, stop_rx) = watch::channel(false);
    let mut counter = Counter { n: 0 };
    let mut doubler = Doubler { last: None };
    let watch = async {
        let mut counts = Vec::new();
        let mut doubled = None;
        let mut up = false;
        let mut status = None;
        let seen = tokio::time::timeout(Duration::from_secs(60), async {
            while let Some(m) = inbox.recv().await {
                match m.key_str().as_ref() {
                    "COUNT" => counts.push(m.dval),
                    "DOUBLE" => {
                        assert_eq!(m.src_str(), "doubler");
                        assert_eq!(&m.src_aux[..], b"doubled");
                        assert_eq!(m.dval % 2.0, 0.0);
                        if m.dval >= 10.0 {
                            doubled = Some(m.dval);
                        }
                    }
                    "COUNTER_UP" => up = true,
                    "DOUBLER_STATUS" => status = Some(m.sval_str().into_owned()),
                    _ => {}
                }
                if doubled.is_some() && up && status.is_some() && counts.len() >= 10 {
                    return;
                }
            }
        })
        .await;
        let _ = stop_tx.send(true);
        assert!(
            seen.is_ok(),
            "timed out: counts {counts:?}, doubled {doubled:?}"
        );
        // Every COUNT arrives, in order (from whichever value was current when the
        // observer's registration reached the DB).
        assert!(counts.windows(2).all(|w| w[1] == w[0] + 1.0), "{counts:?}");
        let status = status.unwrap();
        assert!(status.contains("MOOSName=doubler"), "{status}");
        assert!(status.ends_with("Subscribing=\"COUNT,\""), "{status}");
    };
    let (a, b, ()) = tokio::join!(
        run(&mut counter, &cfg, stopped(stop_rx.clone())),
        run(&mut doubler, &cfg, stopped(stop_rx.clone())),
        watch
    );
    a.unwrap();
    b.unwrap();
    assert!(counter.n >= 10);
    observer.close().await;
    server.shutdown();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_taken_name_is_refused() {
    let server = Server::bind(ServerConfig::with_addr(([127, 0, 0, 1], 0).into()))
        .await
        .unwrap();
    let port = server.local_addr().port();
    let (first, _mail) = Client::start(ClientConfig::new("counter", "127.0.0.1", port));
    first.wait_connected().await.unwrap();
    let cfg = RemoteConfig {
        host: "127.0.0.1".into(),
        port,
        warp: 1.0,
    };
    let r = tokio::time::timeout(
        Duration::from_secs(30),
        run(&mut Counter { n: 0 }, &cfg, std::future::pending()),
    )
    .await
    .expect("refusal within 30 s");
    assert!(matches!(r, Err(RemoteError::Client(_))), "{r:?}");
    let bad = RemoteConfig {
        warp: 0.0,
        ..cfg.clone()
    };
    assert_eq!(
        run(&mut Counter { n: 0 }, &bad, std::future::pending()).await,
        Err(RemoteError::Warp(0.0))
    );
    first.close().await;
}
