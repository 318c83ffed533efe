//! Apps run as MOOS processes over TCP against the project's MOOSDB (loopback, OS-chosen
//! port), watched by an independent client. Waits are bounded and generous; nothing
//! depends on how fast the machine is.

use std::time::Duration;

use moosdb::{Client, ClientConfig, Server, ServerConfig};
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
    fn on_startup(&mut self, _now: f64, out: &mut Vec<Post>) -> runtime::AppResult {
        out.push(Post::text("COUNTER_UP", "true"));
        Ok(())
    }
    fn iterate(&mut self, _now: f64, out: &mut Vec<Post>) -> runtime::AppResult {
        out.push(Post::double("COUNT", f64::from(self.n)));
        self.n += 1;
        Ok(())
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
    fn on_mail(&mut self, mail: &[Mail], _now: f64, _out: &mut Vec<Post>) -> runtime::AppResult {
        assert!(
            mail.windows(2).all(|w| w[0].time <= w[1].time),
            "mail sorted by time"
        );
        if let Some(m) = mail.last() {
            assert_eq!(m.source, "counter");
            self.last = m.value.as_f64();
        }
        Ok(())
    }
    fn iterate(&mut self, _now: f64, out: &mut Vec<Post>) -> runtime::AppResult {
        if let Some(v) = self.last {
            out.push(Post::double("DOUBLE", 2.0 * v).with_aux("doubled"));
        }
        Ok(())
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
    let r = run(&mut Counter { n: 0 }, &bad, std::future::pending()).await;
    assert!(matches!(r, Err(RemoteError::Warp(w)) if w == 0.0), "{r:?}");
    first.close().await;
}

/// Heading 90° at 2 m/s, as a helm would post.
struct ScriptedHelm;

impl App for ScriptedHelm {
    fn name(&self) -> &str {
        "pHelmIvP"
    }
    fn app_tick(&self) -> f64 {
        4.0
    }
    fn iterate(&mut self, _now: f64, out: &mut Vec<Post>) -> runtime::AppResult {
        out.push(Post::text("IVPHELM_STATE", "DRIVE"));
        out.push(Post::double("DESIRED_HEADING", 90.0));
        out.push(Post::double("DESIRED_SPEED", 2.0));
        out.push(Post::double("DESIRED_DEPTH", 0.0));
        Ok(())
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn vehicle_apps_swap_in_as_separate_moos_clients_with_warp() {
    use mission::source::SourceMap;
    use runtime::vehicle::VehicleApp;
    let text = test_support::mission_text("s1_alpha/alpha.moos");
    let m = mission::moos::parse_moos(&SourceMap::from_text("alpha.moos", &text)).value;
    let block = |n: &str| m.process(n).unwrap().clone();
    let warp = 10.0;
    let mut sc = ServerConfig::with_addr(([127, 0, 0, 1], 0).into());
    sc.warp = moosdb::time::Warp::new(warp).unwrap();
    let server = Server::bind(sc).await.unwrap();
    let port = server.local_addr().port();
    let cfg = RemoteConfig {
        host: "127.0.0.1".into(),
        port,
        warp,
    };
    let mut occ = ClientConfig::new("observer", "127.0.0.1", port);
    occ.warp = moosdb::time::Warp::new(warp).unwrap();
    let (observer, mut inbox) = Client::start(occ);
    observer.wait_connected().await.unwrap();
    observer.register("NODE_REPORT_LOCAL", 0.0);
    let start = observer.moos_time();
    let mut sim =
        VehicleApp::simulator("uSimMarineV22", block("uSimMarineV22"), None, start, false).unwrap();
    let mut pid = VehicleApp::marine_pid("pMarinePIDV22", block("pMarinePIDV22"), false).unwrap();
    let mut rep = VehicleApp::node_reporter(
        "pNodeReporter",
        block("pNodeReporter"),
        "alpha",
        start,
        None,
        0,
    )
    .unwrap();
    let mut helm = ScriptedHelm;
    let (stop_tx, stop_rx) = watch::channel(false);
    let watch = async {
        let mut first_x = None;
        let mut last_x = None;
        let moved = tokio::time::timeout(Duration::from_secs(60), async {
            loop {
                // The PID acts only once the override is lifted (as `--deploy` does).
                let _ = observer.notify("MOOS_MANUAL_OVERRIDE", moosdb::Value::from("false"));
                let Ok(Some(m)) =
                    tokio::time::timeout(Duration::from_millis(500), inbox.recv()).await
                else {
                    continue;
                };
                let r = m.sval_str().into_owned();
                let x: f64 = r
                    .split(',')
                    .find_map(|kv| kv.strip_prefix("X="))
                    .and_then(|v| v.parse().ok())
                    .unwrap_or_else(|| panic!("no X= in {r}"));
                first_x.get_or_insert(x);
                last_x = Some(x);
                if x - first_x.unwrap_or(x) > 20.0 {
                    return;
                }
            }
        })
        .await;
        let _ = stop_tx.send(true);
        assert!(
            moved.is_ok(),
            "the vehicle did not move east: {first_x:?} -> {last_x:?}"
        );
    };
    let (a, b, c, d, ()) = tokio::join!(
        run(&mut sim, &cfg, stopped(stop_rx.clone())),
        run(&mut pid, &cfg, stopped(stop_rx.clone())),
        run(&mut rep, &cfg, stopped(stop_rx.clone())),
        run(&mut helm, &cfg, stopped(stop_rx.clone())),
        watch
    );
    for r in [a, b, c, d] {
        r.unwrap();
    }
    observer.close().await;
    server.shutdown();
}
