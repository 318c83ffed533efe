//! Load driver for the live viewer (a measurement, not a test): an embedded MOOSDB on
//! loopback, a publisher posting 100 vehicles' NODE_REPORTs at 4 Hz each with a VIEW_POINT
//! and a VIEW_SEGLIST per report, the viewer joined to the DB as `coug_view`, and a plain
//! MOOS client (`watcher`) timing the DB's delivery of every NODE_REPORT. Each part runs on
//! its own named threads (`moosdb`, `publisher`, `viewer`, `pages`, `watcher`), so the CPU
//! each used is read per thread from `/proc/self/task/*/stat` (utime + stime).
//!
//! Three phases of equal length:
//! 1. no page open (the viewer only keeps its scene);
//! 2. one page reading every frame and one page that never reads (stalled: its socket
//!    buffers fill and stay full);
//! 3. both pages gone: the reading one closed properly, the stalled one dropped mid-frame.
//!
//! For each phase it prints the mail posted per second, the watcher's delivery (mail per
//! second, mean and worst delay from the post's time to its arrival), the frames per second
//! and their size on the reading page, and the CPU of each part as a share of one core; a
//! slow or closed page should change nothing but the viewer's own share.
//!
//! `cargo run --release -p viewer --example live_load [SECONDS_PER_PHASE]` (default 10).

use std::collections::BTreeMap;
use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use futures_util::{SinkExt, StreamExt};
use moosdb::{Client, ClientConfig, Server, ServerConfig, Value};
use viewer::server::{JoinConfig, Viewer, ViewerConfig, feed, serve};

const PARTS: [&str; 5] = ["moosdb", "publisher", "viewer", "pages", "watcher"];

/// CPU seconds (utime + stime) of this process's threads, by thread name.
fn cpu_by_thread() -> BTreeMap<String, f64> {
    let mut out = BTreeMap::new();
    let Ok(tasks) = std::fs::read_dir("/proc/self/task") else {
        return out;
    };
    for t in tasks.flatten() {
        let p = t.path();
        let name = std::fs::read_to_string(p.join("comm")).unwrap_or_default();
        let stat = std::fs::read_to_string(p.join("stat")).unwrap_or_default();
        let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
        let f: Vec<&str> = rest.split_whitespace().collect();
        // stat's fields 14 and 15 (utime, stime), 11 and 12 after the state field; 100 ticks/s.
        let tick = |i: usize| f.get(i).and_then(|s| s.parse::<f64>().ok()).unwrap_or(0.0);
        *out.entry(name.trim().to_string()).or_insert(0.0) += (tick(11) + tick(12)) / 100.0;
    }
    out
}

fn runtime(name: &str) -> tokio::runtime::Runtime {
    tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .max_blocking_threads(1)
        .thread_name(name)
        .enable_all()
        .build()
        .expect("a runtime")
}

/// The watcher's delivery figures since the last reset.
#[derive(Default)]
struct Delivery {
    count: u64,
    delay_sum: f64,
    delay_max: f64,
}

#[derive(Default)]
struct Phase {
    posted: u64,
    wall: f64,
    frames: u64,
    frame_bytes: u64,
    delivery: Delivery,
    cpu: BTreeMap<String, f64>,
}

fn main() {
    let phase_s: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(10.0);
    let (vehicles, hz) = (100usize, 4.0);
    let rts: BTreeMap<&str, tokio::runtime::Runtime> =
        PARTS.iter().map(|p| (*p, runtime(p))).collect();

    // The DB.
    let srv = rts["moosdb"]
        .block_on(Server::bind(ServerConfig::with_addr(SocketAddr::from((
            [127, 0, 0, 1],
            0,
        )))))
        .expect("bind");
    let port = srv.local_addr().port();
    let connect = |part: &str, name: &str| {
        let rt = &rts[part];
        let _in = rt.enter();
        let (c, m) = Client::start(ClientConfig::new(name, "127.0.0.1", port));
        let c = Arc::new(c);
        rt.block_on(c.wait_connected()).expect("joins the DB");
        (c, m)
    };

    // The viewer, as `coug view` runs it: its client, its feed and its web server.
    let (viewer_client, mail) = connect("viewer", "coug_view");
    let config = ViewerConfig {
        bind: "127.0.0.1:0".parse().unwrap(),
        ..ViewerConfig::default()
    };
    let viewer = Viewer::new(&config, viewer_client.clone()).unwrap();
    let http = rts["viewer"].block_on(async {
        let listener = tokio::net::TcpListener::bind(config.bind).await.unwrap();
        let http = listener.local_addr().unwrap();
        tokio::spawn(serve(viewer.clone(), listener));
        tokio::spawn(feed(
            viewer.clone(),
            viewer_client,
            mail,
            JoinConfig::default(),
        ));
        http
    });

    // The watcher: every NODE_REPORT's delay from its post to its arrival.
    let (watcher, mut wmail) = connect("watcher", "watcher");
    watcher.register("NODE_REPORT", 0.0);
    let delivery = Arc::new(Mutex::new(Delivery::default()));
    {
        let (d, w) = (delivery.clone(), watcher.clone());
        rts["watcher"].spawn(async move {
            while let Some(m) = wmail.recv().await {
                let delay = w.moos_time() - m.time;
                let mut d = d.lock().unwrap();
                d.count += 1;
                d.delay_sum += delay;
                d.delay_max = d.delay_max.max(delay);
            }
        });
    }

    // The publisher, on its own threads, until told to stop.
    let (publisher, _pm) = connect("publisher", "uFldFleet");
    let posted = Arc::new(AtomicU64::new(0));
    let stop = Arc::new(AtomicBool::new(false));
    {
        let (posted, stop) = (posted.clone(), stop.clone());
        rts["publisher"].spawn(async move {
            let mut tick = tokio::time::interval(Duration::from_secs_f64(1.0 / hz));
            let mut k = 0u64;
            while !stop.load(Ordering::Relaxed) {
                tick.tick().await;
                let t = k as f64 / hz;
                for v in 0..vehicles {
                    let (x, y) = (v as f64 * 10.0 + t, (t * 0.3 + v as f64).sin() * 50.0);
                    let report = format!(
                        "NAME=v{v},TYPE=auv,X={x:.2},Y={y:.2},SPD=1.5,HDG=90,DEP=2,MODE=DRIVE,TIME={t}"
                    );
                    let point = format!("x={x:.2},y={y:.2},label=v{v}_pt,vertex_size=3");
                    let seglist = format!(
                        "pts={{{x:.1},{y:.1}:{:.1},{:.1}:{:.1},{:.1}}},label=v{v}_wpt",
                        x + 20.0,
                        y,
                        x + 20.0,
                        y + 20.0
                    );
                    for (var, val) in [
                        ("NODE_REPORT", report),
                        ("VIEW_POINT", point),
                        ("VIEW_SEGLIST", seglist),
                    ] {
                        if publisher.notify(var, Value::String(val.into())).is_ok() {
                            posted.fetch_add(1, Ordering::Relaxed);
                        }
                    }
                }
                k += 1;
            }
        });
    }

    let frames = Arc::new(AtomicU64::new(0));
    let frame_bytes = Arc::new(AtomicU64::new(0));
    let measure = |run: Box<dyn FnOnce() + '_>| -> Phase {
        std::thread::sleep(Duration::from_millis(500));
        let cpu0 = cpu_by_thread();
        let p0 = posted.load(Ordering::Relaxed);
        let (f0, b0) = (
            frames.load(Ordering::Relaxed),
            frame_bytes.load(Ordering::Relaxed),
        );
        *delivery.lock().unwrap() = Delivery::default();
        let t0 = Instant::now();
        run();
        let wall = t0.elapsed().as_secs_f64();
        let cpu1 = cpu_by_thread();
        Phase {
            posted: posted.load(Ordering::Relaxed) - p0,
            wall,
            frames: frames.load(Ordering::Relaxed) - f0,
            frame_bytes: frame_bytes.load(Ordering::Relaxed) - b0,
            delivery: std::mem::take(&mut *delivery.lock().unwrap()),
            cpu: cpu1
                .iter()
                .map(|(k, v)| (k.clone(), v - cpu0.get(k).copied().unwrap_or(0.0)))
                .collect(),
        }
    };
    let sleep = || std::thread::sleep(Duration::from_secs_f64(phase_s));

    // Phase 1: no page.
    let no_page = measure(Box::new(sleep));

    // Phase 2: a reading page and a stalled one.
    let pages = &rts["pages"];
    let (stalled, _) = pages
        .block_on(tokio_tungstenite::connect_async(format!("ws://{http}/ws")))
        .unwrap();
    let (page, _) = pages
        .block_on(tokio_tungstenite::connect_async(format!("ws://{http}/ws")))
        .unwrap();
    let (mut page_tx, mut page_rx) = page.split();
    let reader = {
        let (f, b) = (frames.clone(), frame_bytes.clone());
        pages.spawn(async move {
            while let Some(Ok(m)) = page_rx.next().await {
                f.fetch_add(1, Ordering::Relaxed);
                b.fetch_add(m.len() as u64, Ordering::Relaxed);
            }
        })
    };
    let with_pages = measure(Box::new(sleep));

    // Phase 3: the reading page closes, the stalled one is dropped.
    let closed = measure(Box::new(|| {
        pages.block_on(async {
            let _ = page_tx.close().await;
        });
        reader.abort();
        drop(stalled);
        sleep();
    }));
    stop.store(true, Ordering::Relaxed);

    let (vs, shapes) = viewer.with_scene(|s| (s.vehicles().len(), s.shape_count()));
    println!(
        "live viewer load: {vehicles} vehicles at {hz} Hz, each report with a VIEW_POINT and a VIEW_SEGLIST; \
         {phase_s} s per phase; scene {vs} vehicles, {shapes} shapes"
    );
    for (name, p) in [
        ("no page", &no_page),
        ("reading + stalled page", &with_pages),
        ("pages closed", &closed),
    ] {
        let d = &p.delivery;
        println!("  {name}:");
        println!(
            "    posted {:.0} mail/s; watcher got {:.0} NODE_REPORT/s, delay mean {:.2} ms, worst {:.1} ms",
            p.posted as f64 / p.wall,
            d.count as f64 / p.wall,
            1e3 * d.delay_sum / d.count.max(1) as f64,
            1e3 * d.delay_max
        );
        if p.frames > 0 {
            println!(
                "    reading page: {:.1} frames/s, {:.1} kB/frame",
                p.frames as f64 / p.wall,
                p.frame_bytes as f64 / p.frames as f64 / 1e3
            );
        }
        let shares: Vec<String> = PARTS
            .iter()
            .map(|part| {
                let cpu: f64 = p
                    .cpu
                    .iter()
                    .filter(|(k, _)| k.starts_with(part))
                    .map(|(_, v)| v)
                    .sum();
                format!("{part} {:.1}%", 100.0 * cpu / p.wall)
            })
            .collect();
        let total: f64 = p.cpu.values().sum();
        println!(
            "    CPU (share of one core): {}; whole process {:.1}%",
            shares.join(", "),
            100.0 * total / p.wall
        );
    }
}
