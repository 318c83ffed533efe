//! Loopback benchmark against the embedded MOOSDB: sustained messages/s and median/p99
//! latency, 1 publisher -> 1 subscriber and 1 publisher -> 10 subscribers, 100-byte strings.
//!
//! `cargo bench -p moosdb --bench loopback` (prints a table; no criterion).

use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use moosdb::{Client, ClientConfig, Server, ServerConfig, Value};

const PAYLOAD: usize = 100;

struct Figures {
    msgs_per_s: f64,
    deliveries_per_s: f64,
    median_us: f64,
    p99_us: f64,
}

async fn connect(port: u16, name: &str) -> (Client, moosdb::MailStream) {
    let (c, m) = Client::start(ClientConfig::new(name, "127.0.0.1", port));
    c.wait_connected().await.expect("connected");
    (c, m)
}

/// Runs `n` messages from one publisher to `subs` subscribers. With `rate = None` the
/// publisher goes as fast as a bounded in-flight window allows (throughput); with a rate it
/// paces itself (latency).
async fn run(
    server: &Server,
    port: u16,
    subs: usize,
    n: u64,
    rate: Option<f64>,
    tag: &str,
) -> Figures {
    let epoch = Instant::now();
    let var = format!("BENCH_{tag}");
    let received = Arc::new(AtomicU64::new(0));
    let mut tasks = Vec::new();
    let mut clients = Vec::new();
    for i in 0..subs {
        let (c, mut mail) = connect(port, &format!("sub_{tag}_{i}")).await;
        c.register(&var, 0.0);
        clients.push(c);
        let received = received.clone();
        let var = var.clone();
        tasks.push(tokio::spawn(async move {
            let mut lat = Vec::with_capacity(n as usize);
            let mut got = 0u64;
            while got < n {
                let m = mail.recv().await.expect("mail");
                if m.key_str() != var {
                    continue;
                }
                lat.push(epoch.elapsed().as_secs_f64() - m.time);
                got += 1;
                received.fetch_add(1, Ordering::Relaxed);
            }
            lat
        }));
    }
    let (publ, _pm) = connect(port, &format!("pub_{tag}")).await;
    while server.with_db(|db| db.subscribers(&var).len()) < subs {
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    let payload = "x".repeat(PAYLOAD);
    let start = Instant::now();
    let window = 2000 * subs as u64;
    for i in 0..n {
        match rate {
            Some(r) => {
                let due = start + Duration::from_secs_f64(i as f64 / r);
                tokio::time::sleep_until(due.into()).await;
            }
            None => {
                while i * subs as u64 - received.load(Ordering::Relaxed) > window {
                    tokio::task::yield_now().await;
                }
            }
        }
        let t = epoch.elapsed().as_secs_f64();
        publ.notify_with(&var, Value::String(payload.clone().into()), Some(t), "")
            .unwrap();
    }
    let mut all = Vec::new();
    for t in tasks {
        all.extend(t.await.unwrap());
    }
    let elapsed = start.elapsed().as_secs_f64();
    all.sort_by(f64::total_cmp);
    let pct = |p: f64| all[((all.len() - 1) as f64 * p) as usize] * 1e6;
    for c in clients {
        c.close().await;
    }
    publ.close().await;
    Figures {
        msgs_per_s: n as f64 / elapsed,
        deliveries_per_s: (n * subs as u64) as f64 / elapsed,
        median_us: pct(0.5),
        p99_us: pct(0.99),
    }
}

fn main() {
    // `cargo test --benches` passes `--bench`-less args; keep that run short.
    let quick = !std::env::args().any(|a| a == "--bench");
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .unwrap();
    rt.block_on(async {
        let cfg = ServerConfig::with_addr(SocketAddr::from(([127, 0, 0, 1], 0)));
        let server = Server::bind(cfg).await.unwrap();
        let port = server.local_addr().port();
        let (n_tp, n_lat) = if quick {
            (2_000, 200)
        } else {
            (200_000, 5_000)
        };
        println!("moosdb loopback benchmark ({PAYLOAD}-byte strings, 2 worker threads)");
        println!(
            "{:<34} {:>12} {:>14} {:>10} {:>10}",
            "case", "msgs/s", "deliveries/s", "median us", "p99 us"
        );
        for (subs, label) in [(1usize, "1 pub -> 1 sub"), (10, "1 pub -> 10 subs")] {
            let tp = run(
                &server,
                port,
                subs,
                n_tp / subs as u64,
                None,
                &format!("tp{subs}"),
            )
            .await;
            println!(
                "{:<34} {:>12.0} {:>14.0} {:>10.0} {:>10.0}",
                format!("{label}, max rate"),
                tp.msgs_per_s,
                tp.deliveries_per_s,
                tp.median_us,
                tp.p99_us
            );
            let lat = run(
                &server,
                port,
                subs,
                n_lat,
                Some(1000.0),
                &format!("lat{subs}"),
            )
            .await;
            println!(
                "{:<34} {:>12.0} {:>14.0} {:>10.0} {:>10.0}",
                format!("{label}, 1000 msg/s paced"),
                lat.msgs_per_s,
                lat.deliveries_per_s,
                lat.median_us,
                lat.p99_us
            );
        }
        drop(server);
    });
}
