//! End to end over loopback (127.0.0.1, OS-picked ports): an embedded MOOSDB, the viewer
//! joined to it as `coug_view`, and a websocket test client. Every wait is bounded.

use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

use futures_util::{SinkExt, StreamExt};
use moosdb::{Client, ClientConfig, MailStream, Server, ServerConfig, Value};
use serde_json::{Value as Json, json};
use tokio::time::timeout;
use tokio_tungstenite::tungstenite::client::IntoClientRequest;
use tokio_tungstenite::tungstenite::{Error as WsError, Message};
use viewer::server::{JoinConfig, Viewer, ViewerConfig, feed, serve};

const WAIT: Duration = Duration::from_secs(15);

type Ws =
    tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>;

const MISSION: &str = "\
ServerHost = localhost
ServerPort = 9000
ProcessConfig = pMarineViewer
{
  button_one = DEPLOY # DEPLOY=true # MOOS_MANUAL_OVERRIDE=false
  button_two = RETURN # RETURN=true
}
";

fn buttons() -> Vec<mission::buttons::Button> {
    let src = mission::source::SourceMap::from_text("m.moos", MISSION);
    mission::buttons::buttons(&mission::moos::parse_moos(&src).value)
}

async fn db() -> Server {
    Server::bind(ServerConfig::with_addr(SocketAddr::from((
        [127, 0, 0, 1],
        0,
    ))))
    .await
    .expect("bind loopback")
}

async fn client(srv: &Server, name: &str) -> (Arc<Client>, MailStream) {
    let (c, m) = Client::start(ClientConfig::new(
        name,
        "127.0.0.1",
        srv.local_addr().port(),
    ));
    timeout(WAIT, c.wait_connected())
        .await
        .expect("connect in time")
        .expect("welcomed");
    (Arc::new(c), m)
}

async fn subscribed(srv: &Server, client: &str, key: &str) {
    timeout(WAIT, async {
        while !srv.with_db(|db| db.subscribers(key).iter().any(|c| c == client)) {
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
    })
    .await
    .unwrap_or_else(|_| panic!("{client} never subscribed to {key}"));
}

/// A viewer serving on 127.0.0.1:0, fed by a `coug_view` client of `srv`.
async fn start_viewer(srv: &Server, config: ViewerConfig) -> SocketAddr {
    let (c, mail) = client(srv, "coug_view").await;
    let viewer = Viewer::new(&config, c.clone()).expect("config accepted");
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    tokio::spawn(serve(viewer.clone(), listener));
    tokio::spawn(feed(viewer, c, mail, JoinConfig::default()));
    subscribed(srv, "coug_view", "NODE_REPORT").await;
    subscribed(srv, "coug_view", "VIEW_POLYGON").await;
    subscribed(srv, "coug_view", "APPCAST").await;
    addr
}

async fn connect(addr: SocketAddr, query: &str) -> Ws {
    let (ws, _) = timeout(
        WAIT,
        tokio_tungstenite::connect_async(format!("ws://{addr}/ws{query}")),
    )
    .await
    .expect("handshake in time")
    .expect("websocket accepted");
    ws
}

async fn next_json(ws: &mut Ws) -> Json {
    loop {
        let m = timeout(WAIT, ws.next())
            .await
            .expect("a frame in time")
            .expect("stream open")
            .expect("frame ok");
        if let Message::Text(t) = m {
            return serde_json::from_str(t.as_str()).expect("JSON frame");
        }
    }
}

/// Reads frames until one satisfies `found` (bounded by WAIT overall).
async fn until(ws: &mut Ws, what: &str, found: impl Fn(&Json) -> bool) -> Json {
    timeout(WAIT, async {
        loop {
            let m = next_json(ws).await;
            if found(&m) {
                return m;
            }
        }
    })
    .await
    .unwrap_or_else(|_| panic!("{what} never reached the websocket client"))
}

fn has(m: &Json, list: &str, pred: impl Fn(&Json) -> bool) -> bool {
    m[list].as_array().is_some_and(|a| a.iter().any(pred))
}

#[tokio::test]
async fn mail_reaches_the_page_and_buttons_post() {
    let srv = db().await;
    let config = ViewerConfig {
        buttons: buttons(),
        ..ViewerConfig::default()
    };
    let addr = start_viewer(&srv, config).await;
    let mut ws = connect(addr, "").await;
    let snap = next_json(&mut ws).await;
    assert_eq!(snap["type"], "snapshot");
    assert_eq!(snap["buttons"][0]["label"], "DEPLOY");

    let (poster, _m) = client(&srv, "poster").await;
    poster
        .notify(
            "NODE_REPORT",
            Value::text("NAME=abe,X=12.5,Y=-40,SPD=1.2,HDG=45,DEP=2,MODE=PARK,TIME=1"),
        )
        .unwrap();
    let m = until(&mut ws, "NODE_REPORT", |m| {
        has(m, "vehicles", |v| v["name"] == "abe")
    })
    .await;
    let v = &m["vehicles"][0];
    assert_eq!(
        (v["x"].clone(), v["y"].clone()),
        (json!(12.5), json!(-40.0))
    );
    assert_eq!(v["helm"], "PARK");

    poster
        .notify(
            "VIEW_POLYGON",
            Value::text("pts={0,0:100,0:100,-100:0,-100},label=opregion,edge_color=gray"),
        )
        .unwrap();
    let m = until(&mut ws, "VIEW_POLYGON", |m| {
        has(m, "shapes", |s| s["label"] == "opregion")
    })
    .await;
    let s = m["shapes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["label"] == "opregion")
        .unwrap();
    assert_eq!(s["pts"].as_array().unwrap().len(), 4);
    assert_eq!(s["edge_color"], "#808080", "MOOS gray, as CSS");

    let mut cast = appcast::AppCast::new();
    cast.set_node_name("abe");
    cast.set_proc_name("pHelmIvP");
    cast.set_iteration(3);
    cast.set_messages("Helm State: PARK");
    poster
        .notify("APPCAST", Value::text(cast.to_moos_string()))
        .unwrap();
    let m = until(&mut ws, "APPCAST", |m| {
        has(m, "appcasts", |a| {
            a["node"] == "abe" && a["app"] == "pHelmIvP"
        })
    })
    .await;
    assert!(
        m["appcasts"][0]["report"]
            .as_str()
            .unwrap()
            .contains("Helm State: PARK")
    );

    // A press of a button the mission does not have is refused and posts nothing ...
    let (watcher, mut wmail) = client(&srv, "watcher").await;
    watcher.register("DEPLOY", 0.0);
    watcher.register("MOOS_MANUAL_OVERRIDE", 0.0);
    subscribed(&srv, "watcher", "MOOS_MANUAL_OVERRIDE").await;
    ws.send(Message::text(r#"{"press":"SELF_DESTRUCT"}"#))
        .await
        .unwrap();
    let r = until(&mut ws, "refusal", |m| m["type"] == "refused").await;
    assert!(r["error"].as_str().unwrap().contains("SELF_DESTRUCT"));
    ws.send(Message::text(r#"{"poke":"DEPLOY=true"}"#))
        .await
        .unwrap();
    until(&mut ws, "refusal", |m| m["type"] == "refused").await;

    // ... and a configured one posts its variables.
    ws.send(Message::text(r#"{"press":"DEPLOY"}"#))
        .await
        .unwrap();
    let r = until(&mut ws, "press answer", |m| m["type"] == "pressed").await;
    assert_eq!(
        r["posted"],
        json!([["DEPLOY", "true"], ["MOOS_MANUAL_OVERRIDE", "false"]])
    );
    let mut got = Vec::new();
    timeout(WAIT, async {
        while got.len() < 2 {
            let m = wmail.recv().await.expect("watcher mail");
            if m.key_str() == "DEPLOY" || m.key_str() == "MOOS_MANUAL_OVERRIDE" {
                got.push((
                    m.key_str().to_string(),
                    m.sval_str().to_string(),
                    m.src_str().to_string(),
                ));
            }
        }
    })
    .await
    .expect("the press reached the DB");
    got.sort();
    assert_eq!(
        got,
        vec![
            ("DEPLOY".into(), "true".into(), "coug_view".into()),
            (
                "MOOS_MANUAL_OVERRIDE".into(),
                "false".into(),
                "coug_view".into()
            ),
        ]
    );
    // Everything the viewer ever posted: appcast requests and the pressed button's variables.
    let posted: Vec<String> = srv.with_db(|db| {
        db.var_names()
            .into_iter()
            .filter(|k| db.current(k).is_some_and(|m| m.src_str() == "coug_view"))
            .collect()
    });
    for k in &posted {
        assert!(
            k.starts_with("APPCAST_REQ") || k == "DEPLOY" || k == "MOOS_MANUAL_OVERRIDE",
            "viewer posted {k}"
        );
    }
    assert!(!posted.iter().any(|k| k == "RETURN"));
}

fn refused_with(e: WsError, code: u16) {
    match e {
        WsError::Http(r) => assert_eq!(r.status().as_u16(), code),
        other => panic!("expected HTTP {code}, got {other:?}"),
    }
}

#[tokio::test]
async fn non_loopback_bind_needs_the_token() {
    let no_token = ViewerConfig {
        bind: "0.0.0.0:9080".parse().unwrap(),
        ..ViewerConfig::default()
    };
    assert!(
        no_token.check().is_err(),
        "a non-loopback bind without a token is refused"
    );
    let empty = ViewerConfig {
        token: Some(String::new()),
        ..no_token.clone()
    };
    assert!(empty.check().is_err());

    let srv = db().await;
    // Configured for every interface with a token; served here on loopback for the test.
    let addr = start_viewer(
        &srv,
        ViewerConfig {
            token: Some("s3cret".into()),
            buttons: buttons(),
            ..no_token
        },
    )
    .await;
    for query in ["", "?token=wrong", "?token=s3cre", "?tok=s3cret"] {
        let e = tokio_tungstenite::connect_async(format!("ws://{addr}/ws{query}"))
            .await
            .expect_err("refused without the right token");
        refused_with(e, 401);
    }
    let mut ws = connect(addr, "?token=s3cret").await;
    assert_eq!(next_json(&mut ws).await["type"], "snapshot");

    // The page itself needs the token too (plain HTTP/1.1 GET over loopback).
    let page = |path: &'static str| async move {
        use tokio::io::{AsyncReadExt, AsyncWriteExt};
        let mut s = tokio::net::TcpStream::connect(addr).await.unwrap();
        let req = format!("GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n");
        s.write_all(req.as_bytes()).await.unwrap();
        let mut out = String::new();
        timeout(WAIT, s.read_to_string(&mut out))
            .await
            .unwrap()
            .unwrap();
        out
    };
    assert!(page("/").await.starts_with("HTTP/1.1 401"));
    let ok = page("/?token=s3cret").await;
    assert!(ok.starts_with("HTTP/1.1 200"), "{ok}");
    assert!(ok.contains("viewer.js"));
    assert!(
        page("/viewer.js?token=s3cret")
            .await
            .contains("new WebSocket")
    );
}

#[tokio::test]
async fn cross_origin_websocket_is_refused() {
    let srv = db().await;
    let addr = start_viewer(&srv, ViewerConfig::default()).await;
    let mut req = format!("ws://{addr}/ws").into_client_request().unwrap();
    req.headers_mut()
        .insert("Origin", "http://evil.example".parse().unwrap());
    refused_with(
        tokio_tungstenite::connect_async(req).await.unwrap_err(),
        403,
    );
    let mut req = format!("ws://{addr}/ws").into_client_request().unwrap();
    req.headers_mut()
        .insert("Origin", format!("http://{addr}").parse().unwrap());
    let (mut ws, _) = tokio_tungstenite::connect_async(req)
        .await
        .expect("same origin accepted");
    assert_eq!(next_json(&mut ws).await["type"], "snapshot");
}

/// Presses go nowhere (the slow-client test needs no DB).
struct NoOutbox;

impl viewer::server::Outbox for NoOutbox {
    fn post(&self, _var: &str, _value: Value) -> Result<(), String> {
        Err("no DB".into())
    }
    fn moos_time(&self) -> f64 {
        0.0
    }
}

/// The feed never waits for a client: 5000 reports go in while a client reads nothing (on
/// this single-threaded runtime its task cannot run meanwhile), and the client then gets
/// one delta with the newest state and the trail bounded, not 5000 frames.
#[tokio::test]
async fn a_slow_client_gets_only_the_newest_state() {
    let viewer = Viewer::new(&ViewerConfig::default(), Arc::new(NoOutbox)).unwrap();
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    tokio::spawn(serve(viewer.clone(), listener));
    let mut ws = connect(addr, "").await;
    assert_eq!(next_json(&mut ws).await["type"], "snapshot");
    let n = 5000;
    for i in 1..=n {
        viewer.apply(
            "NODE_REPORT",
            &format!("NAME=abe,X={i},Y=0,HDG=90"),
            i as f64,
        );
    }
    let m = next_json(&mut ws).await;
    assert_eq!(m["type"], "delta");
    assert_eq!(m["vehicles"][0]["x"], json!(n as f64));
    let trail = m["vehicles"][0]["trail_add"].as_array().unwrap();
    assert_eq!(trail.len(), viewer::scene::SceneConfig::default().trail_max);
    assert_eq!(trail.last().unwrap(), &json!([n as f64, 0.0]));
    // No buttons configured: every press is refused.
    ws.send(Message::text(r#"{"press":"DEPLOY"}"#))
        .await
        .unwrap();
    let r = until(&mut ws, "refusal", |m| m["type"] == "refused").await;
    assert!(r["error"].as_str().unwrap().contains("no button"));
}

/// Records what a press posts.
#[derive(Default)]
struct Recorder(std::sync::Mutex<Vec<(String, Value)>>);

impl viewer::server::Outbox for Recorder {
    fn post(&self, var: &str, value: Value) -> Result<(), String> {
        self.0.lock().unwrap().push((var.to_string(), value));
        Ok(())
    }
    fn moos_time(&self) -> f64 {
        1234.5
    }
}

#[test]
fn press_types_values_as_pmarineviewer() {
    let src = mission::source::SourceMap::from_text(
        "m.moos",
        "ProcessConfig = pMarineViewer\n{\n  button_one = GO # DEPLOY_$[VNAME]=true # SPEED=1.5 # NOTE=\"42\" # T=$[UTC] # N=$[BIX]\n}\n",
    );
    let config = ViewerConfig {
        buttons: mission::buttons::buttons(&mission::moos::parse_moos(&src).value),
        ..ViewerConfig::default()
    };
    let rec = Arc::new(Recorder::default());
    let viewer = Viewer::new(&config, rec.clone()).unwrap();
    assert!(matches!(
        viewer.press("GO", None),
        Err(viewer::server::PressError::NoVehicle(_))
    ));
    assert!(
        rec.0.lock().unwrap().is_empty(),
        "a refused press posts nothing"
    );
    viewer.press("go", Some("abe")).unwrap();
    viewer.press("button_1", Some("ben")).unwrap();
    let posted = rec.0.lock().unwrap().clone();
    assert_eq!(
        posted,
        vec![
            ("DEPLOY_ABE".into(), Value::text("true")),
            ("SPEED".into(), Value::Double(1.5)),
            ("NOTE".into(), Value::text("42")),
            ("T".into(), Value::Double(1234.5)),
            ("N".into(), Value::Double(0.0)),
            ("DEPLOY_BEN".into(), Value::text("true")),
            ("SPEED".into(), Value::Double(1.5)),
            ("NOTE".into(), Value::text("42")),
            ("T".into(), Value::Double(1234.5)),
            ("N".into(), Value::Double(1.0)),
        ]
    );
}

/// A page that goes away (one closed properly, one whose connection is simply dropped) ends
/// its own task and nothing else: the feed goes on, the page left open gets the newest
/// state, and a page opening afterwards gets a snapshot of it.
#[tokio::test]
async fn closed_pages_end_their_tasks_and_the_others_go_on() {
    let viewer = Viewer::new(&ViewerConfig::default(), Arc::new(NoOutbox)).unwrap();
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    tokio::spawn(serve(viewer.clone(), listener));
    let mut open = connect(addr, "").await;
    let mut closing = connect(addr, "").await;
    let dropped = connect(addr, "").await;
    assert_eq!(next_json(&mut open).await["type"], "snapshot");
    assert_eq!(next_json(&mut closing).await["type"], "snapshot");
    let pages = |n: u64| {
        let v = viewer.clone();
        async move {
            timeout(WAIT, async {
                while v.pages() != n {
                    tokio::time::sleep(Duration::from_millis(10)).await;
                }
            })
            .await
            .unwrap_or_else(|_| panic!("{} pages, expected {n}", v.pages()));
        }
    };
    pages(3).await;
    closing.close(None).await.unwrap();
    drop(dropped);
    for i in 1..=1000 {
        viewer.apply("NODE_REPORT", &format!("NAME=abe,X={i},Y=0"), f64::from(i));
    }
    pages(1).await;
    let m = until(&mut open, "the newest report", |m| {
        has(m, "vehicles", |v| v["x"] == json!(1000.0))
    })
    .await;
    assert_eq!(m["type"], "delta");
    let mut late = connect(addr, "").await;
    let snap = next_json(&mut late).await;
    assert_eq!(snap["type"], "snapshot");
    assert_eq!(snap["vehicles"][0]["x"], json!(1000.0));
    pages(2).await;
}
