//! `coug run --view` in process: the viewer fed from a lockstep run of alpha. A page that
//! never reads (a stalled websocket) neither slows nor changes the run: its alog is the one
//! of the same run without a viewer, and a page that connects afterwards sees the vehicle.

use std::path::Path;
use std::time::Duration;

use futures_util::StreamExt;
use runtime::session::{self, Mode, Quiet, RunOptions};
use serde_json::Value as Json;
use tokio::time::timeout;
use tokio_tungstenite::tungstenite::Message;
use viewer::live::{LiveView, ViewObserver};
use viewer::server::ViewerConfig;

const WAIT: Duration = Duration::from_secs(20);

fn options(log_dir: &Path) -> RunOptions {
    RunOptions {
        mode: Mode::Lockstep,
        deploy: true,
        max_time: 240.0,
        log_dir: Some(log_dir.to_path_buf()),
        ..RunOptions::default()
    }
}

/// The alog's records (its `%%` header names the file, which differs run to run).
fn records(alog: &str) -> String {
    std::fs::read_to_string(alog)
        .expect("the alog")
        .lines()
        .filter(|l| !l.starts_with("%%"))
        .collect::<Vec<_>>()
        .join("\n")
}

fn loopback_any_port() -> ViewerConfig {
    ViewerConfig {
        bind: "127.0.0.1:0".parse().unwrap(),
        min_frame_interval: Duration::ZERO,
        ..ViewerConfig::default()
    }
}

/// The alog's records without the appcast traffic (`APPCAST_REQ*`, `APPCAST`).
fn without_appcasts(records: &str) -> String {
    records
        .lines()
        .filter(|l| {
            let var = l.split_whitespace().nth(1).unwrap_or("");
            !var.starts_with("APPCAST")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

fn first_difference(a: &str, b: &str) -> Option<String> {
    a.lines()
        .zip(b.lines())
        .find(|(x, y)| x != y)
        .map(|(x, y)| format!("without: {x}\n   with: {y}"))
}

#[test]
fn a_stalled_page_changes_nothing_in_a_lockstep_run() {
    let alpha = test_support::mission_file("s1_alpha/alpha.moos");
    let loaded = session::load(&alpha, &[], &[]).expect("alpha loads");
    let dir = test_support::scratch_dir("viewer-live");
    // One folder: the paths the logger posts are then the same (the session folders
    // themselves are named from the wall clock, never shared).
    let log_dir = test_support::fresh_dir(dir.join("logs"));

    let plain = session::run(&loaded, &options(&log_dir), &mut Quiet).expect("plain run");

    // The viewer with no page at all.
    let unviewed = {
        let live = LiveView::start(&loopback_any_port()).expect("viewer starts");
        let mut quiet = Quiet;
        let mut view = ViewObserver::new(&mut quiet, &live, session::LOCKSTEP_START, None);
        session::run(&loaded, &options(&log_dir), &mut view).expect("run without a page")
    };

    let live = LiveView::start(&loopback_any_port()).expect("viewer starts");
    let addr = live.addr();
    let client_rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .unwrap();
    // A page that connects and then never reads a frame.
    let stalled = client_rt
        .block_on(async {
            timeout(
                WAIT,
                tokio_tungstenite::connect_async(format!("ws://{addr}/ws")),
            )
            .await
        })
        .expect("handshake in time")
        .expect("websocket accepted");
    let mut quiet = Quiet;
    let mut view = ViewObserver::new(&mut quiet, &live, session::LOCKSTEP_START, None);
    let viewed = session::run(&loaded, &options(&log_dir), &mut view).expect("viewed run");

    assert_eq!(plain.sim_s(), viewed.sim_s());
    let (a, b) = (records(&unviewed.alog), records(&viewed.alog));
    assert!(a.len() > 100_000, "{} bytes of records", a.len());
    if a != b {
        panic!(
            "a stalled page changed the log; first difference:\n{:?}",
            first_difference(&a, &b)
        );
    }
    // The viewer's appcast requests are all it adds: the rest of the log is the plain run's.
    let plain_records = records(&plain.alog);
    assert!(!plain_records.contains("APPCAST_REQ"));
    assert_eq!(
        b.lines()
            .filter(|l| l.split_whitespace().nth(1) == Some("APPCAST_REQ"))
            .count(),
        120,
        "one request every 2 simulated s of the 240"
    );
    let (p, v) = (without_appcasts(&plain_records), without_appcasts(&b));
    if p != v {
        panic!(
            "the viewer changed more than the appcasts; first difference:\n{:?}",
            first_difference(&p, &v)
        );
    }
    // Asked all along the run, the apps kept appcasting: the pane shows the helm's cast of
    // its last iterations (at start-up, unasked, it casts iteration 0 or 1), the PID's and
    // the simulator's too.
    live.viewer().with_scene(|s| {
        let helm = s.appcast("alpha", "pHelmIvP").expect("the helm's appcast");
        assert!(
            helm.iteration() > 500,
            "helm iteration {}",
            helm.iteration()
        );
        for app in ["pMarinePIDV22", "uSimMarineV22", "pNodeReporter"] {
            let cast = s
                .appcast("alpha", app)
                .unwrap_or_else(|| panic!("{app}'s appcast"));
            assert!(cast.iteration() > 100, "{app}: {}", cast.iteration());
        }
    });

    // The scene holds what the run posted.
    let (x, y) = live.viewer().with_scene(|s| {
        let v = s.vehicles().get("alpha").expect("alpha in the scene");
        (v.report.x_m.unwrap(), v.report.y_m.unwrap())
    });
    assert!(x.is_finite() && y.is_finite());
    // A page that connects now gets it in its snapshot.
    let snapshot: Json = client_rt.block_on(async {
        let (mut ws, _) = tokio_tungstenite::connect_async(format!("ws://{addr}/ws"))
            .await
            .expect("second page");
        loop {
            let m = timeout(WAIT, ws.next())
                .await
                .expect("a frame in time")
                .expect("open")
                .expect("frame");
            if let Message::Text(t) = m {
                break serde_json::from_str(t.as_str()).unwrap();
            }
        }
    });
    assert_eq!(snapshot["type"], "snapshot");
    let names: Vec<&str> = snapshot["vehicles"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(|v| v["name"].as_str())
        .collect();
    assert_eq!(names, ["alpha"]);
    assert!(
        snapshot["shapes"].as_array().is_some_and(|s| !s.is_empty()),
        "the waypoints' VIEW_* shapes"
    );
    drop(stalled);
}

/// An observer that stops the run when told.
struct Stopper(std::sync::Arc<std::sync::atomic::AtomicBool>);

impl runtime::session::Observer for Stopper {
    fn stop_requested(&self) -> bool {
        self.0.load(std::sync::atomic::Ordering::Relaxed)
    }
}

type Ws =
    tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>;

/// Reads frames until the helm's appcast report satisfies `found`; returns that report.
async fn helm_report(ws: &mut Ws, found: impl Fn(&str) -> bool) -> String {
    timeout(Duration::from_secs(60), async {
        loop {
            let m = ws.next().await.expect("open").expect("frame");
            let Message::Text(t) = m else { continue };
            let j: Json = serde_json::from_str(t.as_str()).unwrap();
            for a in j["appcasts"].as_array().into_iter().flatten() {
                if a["app"] == "pHelmIvP"
                    && let Some(r) = a["report"].as_str()
                    && found(r)
                {
                    return r.to_string();
                }
            }
        }
    })
    .await
    .expect("the helm's appcast in time")
}

fn mode_line(report: &str) -> String {
    report
        .lines()
        .find(|l| l.trim_start().starts_with("Mode(s):"))
        .unwrap_or("")
        .to_string()
}

#[test]
fn a_page_sees_the_helm_appcast_follow_its_mode_in_a_real_time_run() {
    use futures_util::SinkExt;
    let delta = test_support::mission_file("s4_delta/delta.moos");
    let loaded = session::load(&delta, &[], &[]).expect("delta loads");
    let dir = test_support::scratch_dir("viewer-live-rt");
    let config = ViewerConfig {
        buttons: mission::buttons::buttons(&loaded.mission),
        ..loopback_any_port()
    };
    let live = LiveView::start(&config).expect("viewer starts");
    let addr = live.addr();
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let opts = RunOptions {
        mode: Mode::RealTime {
            warp: Some(4.0),
            port: Some(0),
        },
        max_time: 400.0,
        log_dir: Some(test_support::fresh_dir(dir.join("logs"))),
        ..RunOptions::default()
    };
    std::thread::scope(|scope| {
        let run = scope.spawn(|| {
            let mut stopper = Stopper(stop.clone());
            let mut view = ViewObserver::new(&mut stopper, &live, 0.0, None);
            session::run(&loaded, &opts, &mut view)
        });
        // However the page side ends (a panic included), the run is told to stop.
        struct StopOnDrop<'a>(&'a std::sync::atomic::AtomicBool);
        impl Drop for StopOnDrop<'_> {
            fn drop(&mut self) {
                self.0.store(true, std::sync::atomic::Ordering::Relaxed);
            }
        }
        let guard = StopOnDrop(&stop);
        let rt = tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .unwrap();
        let modes = rt.block_on(async {
            let (mut ws, _) = timeout(
                WAIT,
                tokio_tungstenite::connect_async(format!("ws://{addr}/ws")),
            )
            .await
            .expect("in time")
            .expect("accepted");
            // Not deployed: no mode yet (DEPLOY unknown; the viewer's requests, every 2 s,
            // keep the helm appcasting); each press changes it.
            let before = helm_report(&mut ws, |r| r.contains("Mode(s):")).await;
            ws.send(Message::text(r#"{"press":"DEPLOY"}"#))
                .await
                .unwrap();
            let deployed = helm_report(&mut ws, |r| mode_line(r).contains("LOITERING")).await;
            ws.send(Message::text(r#"{"press":"RETURN"}"#))
                .await
                .unwrap();
            // RETURNING, and at once INACTIVE again: delta's vehicle is still at its
            // return point, so the return ends at once and its end flag undeploys.
            let returning = helm_report(&mut ws, |r| {
                let m = mode_line(r);
                m.contains("MODE@") && !m.contains("LOITERING")
            })
            .await;
            [before, deployed, returning].map(|r| mode_line(&r))
        });
        drop(guard);
        run.join()
            .expect("run thread")
            .expect("the run ends cleanly");
        assert!(!modes[0].contains("ACTIVE:"), "{modes:?}");
        assert!(modes[1].contains("ACTIVE:LOITERING"), "{modes:?}");
        assert_ne!(modes[1], modes[2]);
    });
}

/// `--pace X` holds a lockstep run to X times real time in steps of about a tenth of a wall
/// second (X / 10 simulated seconds, kept within 0.05 and 1), so the page gets about ten
/// frames a wall second; without a pace the session's own step stands (1 s). The holding
/// itself is the wall clock and is not tested here.
#[test]
fn a_pace_gives_the_run_steps_of_a_tenth_of_a_wall_second() {
    use runtime::session::Observer;
    let live = LiveView::start(&loopback_any_port()).unwrap();
    let mut quiet = Quiet;
    for (pace, step) in [
        (None, 1.0),
        (Some(4.0), 0.4),
        (Some(1.0), 0.1),
        (Some(0.2), 0.05),
        (Some(50.0), 1.0),
        (Some(-3.0), 1.0),
    ] {
        let view = ViewObserver::new(&mut quiet, &live, session::LOCKSTEP_START, pace);
        assert!(
            (view.step_seconds() - step).abs() < 1e-12,
            "pace {pace:?}: {}",
            view.step_seconds()
        );
    }
}
