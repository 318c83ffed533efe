//! Load driver for the live viewer (not a timed test): an embedded MOOSDB on loopback, a
//! publisher posting 100 vehicles' NODE_REPORTs at 4 Hz each with a VIEW_POINT and a
//! VIEW_SEGLIST per report, the viewer joined to the DB as `coug_view`, one page reading
//! every frame and one page that never reads (stalled). Prints the frames per second the
//! reading page got, their size, the mail the viewer took, and the process's CPU time
//! (everything above shares the process: DB, publisher, viewer, pages).
//!
//! `cargo run --release -p viewer --example live_load [SECONDS]` (default 20).

use std::net::SocketAddr;
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use futures_util::StreamExt;
use moosdb::{Client, ClientConfig, Server, ServerConfig, Value};
use viewer::server::{JoinConfig, Viewer, ViewerConfig, feed, serve};

/// User + system CPU seconds of this process (Linux `/proc/self/stat`, 100 ticks a second).
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let rest = stat.rsplit_once(')').map_or("", |(_, r)| r);
    let f: Vec<&str> = rest.split_whitespace().collect();
    let tick = |i: usize| f.get(i).and_then(|s| s.parse::<f64>().ok()).unwrap_or(0.0);
    // Fields 14 and 15 of stat (utime, stime) are 11 and 12 after the state field.
    (tick(11) + tick(12)) / 100.0
}

#[tokio::main(flavor = "multi_thread", worker_threads = 2)]
async fn main() {
    let seconds: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(20.0);
    let (vehicles, hz) = (100usize, 4.0);
    let srv = Server::bind(ServerConfig::with_addr(SocketAddr::from((
        [127, 0, 0, 1],
        0,
    ))))
    .await
    .expect("bind");
    let port = srv.local_addr().port();
    let connect = |name: &str| {
        let (c, m) = Client::start(ClientConfig::new(name, "127.0.0.1", port));
        (Arc::new(c), m)
    };
    let (viewer_client, mail) = connect("coug_view");
    viewer_client.wait_connected().await.expect("viewer joins");
    let config = ViewerConfig {
        bind: "127.0.0.1:0".parse().unwrap(),
        ..ViewerConfig::default()
    };
    let viewer = Viewer::new(&config, viewer_client.clone()).unwrap();
    let listener = tokio::net::TcpListener::bind(config.bind).await.unwrap();
    let http = listener.local_addr().unwrap();
    tokio::spawn(serve(viewer.clone(), listener));
    tokio::spawn(feed(
        viewer.clone(),
        viewer_client,
        mail,
        JoinConfig::default(),
    ));
    tokio::time::sleep(Duration::from_millis(500)).await;

    // The pages: one reads every frame, one never reads.
    let (stalled, _) = tokio_tungstenite::connect_async(format!("ws://{http}/ws"))
        .await
        .unwrap();
    let (mut page, _) = tokio_tungstenite::connect_async(format!("ws://{http}/ws"))
        .await
        .unwrap();
    let frames = Arc::new(AtomicU64::new(0));
    let bytes = Arc::new(AtomicU64::new(0));
    let (f2, b2) = (frames.clone(), bytes.clone());
    tokio::spawn(async move {
        while let Some(Ok(m)) = page.next().await {
            f2.fetch_add(1, Ordering::Relaxed);
            b2.fetch_add(m.len() as u64, Ordering::Relaxed);
        }
    });

    let (publisher, _pm) = connect("uFldFleet");
    publisher.wait_connected().await.expect("publisher joins");
    let cpu0 = cpu_seconds();
    let wall0 = Instant::now();
    let mut tick = tokio::time::interval(Duration::from_secs_f64(1.0 / hz));
    let mut posted = 0u64;
    let mut k = 0u64;
    while wall0.elapsed().as_secs_f64() < seconds {
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
                    posted += 1;
                }
            }
        }
        k += 1;
    }
    let wall = wall0.elapsed().as_secs_f64();
    let cpu = cpu_seconds() - cpu0;
    tokio::time::sleep(Duration::from_millis(500)).await;
    let n = frames.load(Ordering::Relaxed);
    let (vs, shapes) = viewer.with_scene(|s| (s.vehicles().len(), s.shape_count()));
    println!(
        "live viewer load: {vehicles} vehicles at {hz} Hz + VIEW_POINT + VIEW_SEGLIST each, {wall:.1} s"
    );
    println!(
        "  posted:            {posted} mail ({:.0}/s)",
        posted as f64 / wall
    );
    println!("  scene:             {vs} vehicles, {shapes} shapes");
    println!(
        "  reading page:      {n} frames, {:.1} frames/s, {:.1} kB/frame",
        n as f64 / wall,
        bytes.load(Ordering::Relaxed) as f64 / n.max(1) as f64 / 1000.0
    );
    println!(
        "  process CPU:       {cpu:.2} s over {wall:.1} s = {:.0}% of one core (DB, publisher, viewer, pages)",
        100.0 * cpu / wall
    );
    drop(stalled);
}
