//! `coug view LOG.alog` over the websocket, without a browser: the page's time slider (seek),
//! play/pause and speed drive a scene rebuilt from the log.

use std::sync::Arc;
use std::time::Duration;

use alog::{AlogWriter, Header, LogValue};
use futures_util::{SinkExt, StreamExt};
use serde_json::Value as Json;
use tokio::time::timeout;
use tokio_tungstenite::tungstenite::Message;
use viewer::replay::{Replay, drive};
use viewer::server::{Outbox, Viewer, ViewerConfig, serve};

const WAIT: Duration = Duration::from_secs(20);
const START: f64 = 1000.0;

struct Refuse;

impl Outbox for Refuse {
    fn post(&self, _: &str, _: moos_types::Value) -> Result<(), String> {
        Err("replay".into())
    }
    fn moos_time(&self) -> f64 {
        0.0
    }
}

/// A log of 100 s: abe at x = t every second, a polygon at t = 30, removed at t = 60.
fn log() -> alog::Alog {
    let header = Header {
        path: "./LOG/LOG.alog",
        opened_on: "Thu Jan  1 00:00:00 1970",
        log_start: START,
        mark_data_type: false,
    };
    let mut w = AlogWriter::new(Vec::new(), &header).unwrap();
    for k in 0..=100 {
        let t = START + f64::from(k);
        let report = format!("NAME=abe,TYPE=kayak,X={k},Y=-5,SPD=1,HDG=90,DEP=0,TIME={t}");
        w.record(
            t,
            "NODE_REPORT_LOCAL",
            "pNodeReporter",
            LogValue::String(&report),
        )
        .unwrap();
        w.record(t, "NAV_X", "uSimMarine", LogValue::Double(f64::from(k)))
            .unwrap();
        if k == 30 {
            w.record(
                t,
                "VIEW_POLYGON",
                "pHelmIvP",
                LogValue::String("pts={0,0:10,0:10,10},label=box"),
            )
            .unwrap();
        }
        if k == 60 {
            w.record(
                t,
                "VIEW_POLYGON",
                "pHelmIvP",
                LogValue::String("pts={0,0:10,0:10,10},label=box,active=false"),
            )
            .unwrap();
        }
    }
    alog::parse(&String::from_utf8(w.into_inner()).unwrap()).unwrap()
}

type Ws =
    tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>;

async fn until(ws: &mut Ws, what: &str, found: impl Fn(&Json) -> bool) -> Json {
    timeout(WAIT, async {
        loop {
            let m = ws.next().await.expect("open").expect("frame");
            if let Message::Text(t) = m {
                let j: Json = serde_json::from_str(t.as_str()).unwrap();
                if found(&j) {
                    return j;
                }
            }
        }
    })
    .await
    .unwrap_or_else(|_| panic!("no frame with {what}"))
}

fn abe_x(j: &Json) -> Option<f64> {
    j["vehicles"]
        .as_array()?
        .iter()
        .find(|v| v["name"] == "abe")?["x"]
        .as_f64()
}

#[tokio::test]
async fn the_slider_play_pause_and_speed_drive_the_replayed_scene() {
    let replay = Replay::from_alog(&log());
    assert_eq!(
        replay.len(),
        103,
        "101 reports and 2 polygons; NAV_X is not viewed"
    );
    assert_eq!(replay.duration(), 100.0);
    let config = ViewerConfig {
        bind: "127.0.0.1:0".parse().unwrap(),
        min_frame_interval: Duration::ZERO,
        ..ViewerConfig::default()
    };
    let viewer = Viewer::new(&config, Arc::new(Refuse)).unwrap();
    let listener = tokio::net::TcpListener::bind(config.bind).await.unwrap();
    let addr = listener.local_addr().unwrap();
    tokio::spawn(serve(viewer.clone(), listener));
    tokio::spawn(drive(
        viewer.clone(),
        Arc::new(replay),
        false,
        1.0,
        Duration::from_millis(20),
    ));
    let (mut ws, _) = tokio_tungstenite::connect_async(format!("ws://{addr}/ws"))
        .await
        .unwrap();
    // Paused at the start: abe's first report, no polygon yet.
    let first = until(&mut ws, "the first snapshot", |j| {
        j["type"] == "snapshot" && j["replay"]["t"] == 0.0
    })
    .await;
    assert_eq!(first["replay"]["playing"], false);
    assert_eq!(first["replay"]["end"], 100.0);
    assert_eq!(abe_x(&first), Some(0.0));

    // The slider to 45 s: a fresh snapshot of the scene at 45 s.
    ws.send(Message::text(r#"{"replay":"seek","t":45}"#))
        .await
        .unwrap();
    let at45 = until(&mut ws, "the scene at 45 s", |j| {
        j["type"] == "snapshot" && j["replay"]["t"] == 45.0
    })
    .await;
    assert_eq!(abe_x(&at45), Some(45.0));
    let shapes = at45["shapes"].as_array().unwrap();
    assert_eq!(shapes.len(), 1, "the polygon posted at 30 s");
    // Back to 20 s: rebuilt, so the polygon is not there yet and the trail is shorter.
    ws.send(Message::text(r#"{"replay":"seek","t":20.5}"#))
        .await
        .unwrap();
    let at20 = until(&mut ws, "the scene at 20.5 s", |j| {
        j["type"] == "snapshot" && j["replay"]["t"] == 20.5
    })
    .await;
    assert_eq!(abe_x(&at20), Some(20.0));
    assert!(at20["shapes"].as_array().unwrap().is_empty());
    // To 70 s: the polygon came and went.
    ws.send(Message::text(r#"{"replay":"seek","t":70}"#))
        .await
        .unwrap();
    let at70 = until(&mut ws, "the scene at 70 s", |j| {
        j["type"] == "snapshot" && j["replay"]["t"] == 70.0
    })
    .await;
    assert!(at70["shapes"].as_array().unwrap().is_empty());

    // Play fast: deltas move abe on; then pause and the playhead stays.
    ws.send(Message::text(r#"{"replay":"speed","speed":50}"#))
        .await
        .unwrap();
    ws.send(Message::text(r#"{"replay":"play"}"#))
        .await
        .unwrap();
    let moved = until(&mut ws, "abe moved on by playing", |j| {
        j["type"] == "delta" && abe_x(j).is_some_and(|x| x > 75.0)
    })
    .await;
    assert_eq!(moved["replay"]["speed"], 50.0);
    assert_eq!(moved["replay"]["playing"], true);
    ws.send(Message::text(r#"{"replay":"pause"}"#))
        .await
        .unwrap();
    let paused = until(&mut ws, "paused", |j| j["replay"]["playing"] == false).await;
    let t = paused["replay"]["t"].as_f64().unwrap();
    assert!((70.0..=100.0).contains(&t), "{t}");
    // Played to the end it stops there.
    ws.send(Message::text(r#"{"replay":"play"}"#))
        .await
        .unwrap();
    let end = until(&mut ws, "the end", |j| {
        j["replay"]["t"] == 100.0 && j["replay"]["playing"] == false
    })
    .await;
    assert_eq!(end["replay"]["end"], 100.0);
    assert_eq!(
        viewer.with_scene(|s| s.vehicles()["abe"].report.x_m),
        Some(100.0)
    );
    // A replay posts nothing: a press is refused, a bad control too.
    ws.send(Message::text(r#"{"press":"DEPLOY"}"#))
        .await
        .unwrap();
    until(&mut ws, "a refused press", |j| j["type"] == "refused").await;
    ws.send(Message::text(r#"{"replay":"seek"}"#))
        .await
        .unwrap();
    until(&mut ws, "a refused control", |j| {
        j["type"] == "refused" && j["error"] == "bad replay control"
    })
    .await;
}
