//! The page's operator gestures in headless Chromium, driven over its DevTools protocol on
//! loopback (`--remote-debugging-port=0`, the port read from the profile's
//! `DevToolsActivePort`): a button press asks for confirmation and posts only when it is
//! accepted; the wheel zooms and a drag pans the map. Every wait is bounded.
//!
//! Chromium is Debian's `chromium` (installed by `.ci/run`). Without it the test fails under
//! `CI=true`; elsewhere it says loudly that it did not run.

use std::collections::{HashMap, VecDeque};
use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::sync::{Arc, Mutex};
use std::time::Duration;

use futures_util::{SinkExt, StreamExt};
use moos_types::Value;
use serde_json::{Value as Json, json};
use tokio::time::timeout;
use tokio_tungstenite::tungstenite::Message;
use viewer::server::{Outbox, Viewer, ViewerConfig, serve};

mod support;
use support::chromium;

const WAIT: Duration = Duration::from_secs(30);

type Ws =
    tokio_tungstenite::WebSocketStream<tokio_tungstenite::MaybeTlsStream<tokio::net::TcpStream>>;

#[derive(Default)]
struct Recorder(Mutex<Vec<(String, Value)>>);

impl Outbox for Recorder {
    fn post(&self, var: &str, value: Value) -> Result<(), String> {
        self.0.lock().unwrap().push((var.to_string(), value));
        Ok(())
    }
    fn moos_time(&self) -> f64 {
        0.0
    }
}

/// The browser process, killed when the test ends however it ends.
struct Browser(Child);

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// A DevTools connection: commands by id, events kept until asked for.
struct Cdp {
    ws: Ws,
    next_id: u64,
    results: HashMap<u64, Json>,
    events: VecDeque<Json>,
    session: Option<String>,
}

impl Cdp {
    async fn read_one(&mut self) {
        let m = timeout(WAIT, self.ws.next())
            .await
            .expect("a DevTools frame in time")
            .expect("DevTools stream open")
            .expect("DevTools frame ok");
        if let Message::Text(t) = m {
            let j: Json = serde_json::from_str(t.as_str()).expect("DevTools JSON");
            match j.get("id").and_then(Json::as_u64) {
                Some(id) => {
                    self.results.insert(id, j);
                }
                None => self.events.push_back(j),
            }
        }
    }

    /// Sends `method` (to the attached page, once attached) and returns its result.
    async fn call(&mut self, method: &str, params: Json) -> Json {
        self.next_id += 1;
        let id = self.next_id;
        let mut msg = json!({ "id": id, "method": method, "params": params });
        if let Some(s) = &self.session {
            msg["sessionId"] = json!(s);
        }
        self.ws
            .send(Message::text(msg.to_string()))
            .await
            .expect("DevTools send");
        loop {
            if let Some(r) = self.results.remove(&id) {
                assert!(r.get("error").is_none(), "{method}: {r}");
                return r["result"].clone();
            }
            self.read_one().await;
        }
    }

    /// The next event named `method` (earlier ones of other names are kept).
    async fn event(&mut self, method: &str) -> Json {
        loop {
            if let Some(i) = self.events.iter().position(|e| e["method"] == method) {
                return self.events.remove(i).unwrap()["params"].clone();
            }
            self.read_one().await;
        }
    }

    /// The value of a JavaScript expression in the page.
    async fn eval(&mut self, expr: &str) -> Json {
        let r = self
            .call(
                "Runtime.evaluate",
                json!({ "expression": expr, "returnByValue": true }),
            )
            .await;
        assert!(r.get("exceptionDetails").is_none(), "{expr}: {r}");
        r["result"]["value"].clone()
    }

    /// Polls `expr` until it is true (bounded).
    async fn until(&mut self, what: &str, expr: &str) {
        timeout(WAIT, async {
            while self.eval(expr).await != json!(true) {
                tokio::time::sleep(Duration::from_millis(50)).await;
            }
        })
        .await
        .unwrap_or_else(|_| panic!("the page never showed {what}"));
    }
}

/// Starts Chromium with DevTools on a loopback port of its choosing and attaches to a new
/// page at `url`.
async fn open(chromium: &PathBuf, url: &str) -> (Browser, Cdp) {
    let dir = test_support::scratch_dir("viewer-interactive");
    let profile = dir.join("profile");
    let child = Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--remote-debugging-address=127.0.0.1",
            "--remote-debugging-port=0",
            "--window-size=1200,800",
            &format!("--user-data-dir={}", profile.display()),
            "about:blank",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("chromium starts");
    let browser = Browser(child);
    let active = profile.join("DevToolsActivePort");
    let text = timeout(WAIT, async {
        loop {
            if let Ok(t) = std::fs::read_to_string(&active)
                && t.lines().count() >= 2
            {
                return t;
            }
            tokio::time::sleep(Duration::from_millis(50)).await;
        }
    })
    .await
    .expect("chromium wrote its DevTools port");
    let mut lines = text.lines();
    let port: u16 = lines.next().unwrap().trim().parse().expect("a port");
    let path = lines.next().unwrap().trim().to_string();
    let (ws, _) = timeout(
        WAIT,
        tokio_tungstenite::connect_async(format!("ws://127.0.0.1:{port}{path}")),
    )
    .await
    .expect("DevTools handshake in time")
    .expect("DevTools accepted");
    let mut cdp = Cdp {
        ws,
        next_id: 0,
        results: HashMap::new(),
        events: VecDeque::new(),
        session: None,
    };
    let target = cdp.call("Target.createTarget", json!({ "url": url })).await;
    let attached = cdp
        .call(
            "Target.attachToTarget",
            json!({ "targetId": target["targetId"], "flatten": true }),
        )
        .await;
    cdp.session = Some(attached["sessionId"].as_str().unwrap().to_string());
    cdp.call("Page.enable", json!({})).await;
    cdp.call("Runtime.enable", json!({})).await;
    (browser, cdp)
}

/// Clicks the page's button `label` on the page's next turn (so the call returns before the
/// confirmation blocks the page).
fn click_button(label: &str) -> String {
    format!(
        "setTimeout(() => [...document.querySelectorAll('#buttons button')]\
         .find(b => b.textContent === '{label}').click(), 0); true"
    )
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_press_posts_only_when_confirmed_and_the_map_zooms_and_pans() {
    let Some(chromium) = chromium() else { return };
    let src = mission::source::SourceMap::from_text(
        "m.moos",
        "ProcessConfig = pMarineViewer\n{\n  button_one = DEPLOY # DEPLOY=true # MOOS_MANUAL_OVERRIDE=false\n  button_two = RETURN # RETURN=true\n  right_context[station] = STATION_POINT = x=$(XPOS),y=$(YPOS)\n}\n",
    );
    let config = ViewerConfig::for_mission(&mission::moos::parse_moos(&src).value);
    let rec = Arc::new(Recorder::default());
    let viewer = Viewer::new(&config, rec.clone()).unwrap();
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let port = listener.local_addr().unwrap().port();
    tokio::spawn(serve(viewer, listener));

    let (_browser, mut cdp) = open(&chromium, &format!("http://127.0.0.1:{port}/")).await;
    cdp.until(
        "its two buttons",
        "document.querySelectorAll('#buttons button').length === 2",
    )
    .await;

    // Dismissed: the prompt names the button and what it posts; nothing is posted.
    cdp.eval(&click_button("DEPLOY")).await;
    let dialog = cdp.event("Page.javascriptDialogOpening").await;
    assert_eq!(dialog["type"], "confirm", "{dialog}");
    let message = dialog["message"].as_str().unwrap();
    assert!(
        message.contains("Press DEPLOY") && message.contains("DEPLOY=true"),
        "{message}"
    );
    cdp.call("Page.handleJavaScriptDialog", json!({ "accept": false }))
        .await;

    // Accepted: RETURN is posted. The page sends presses in order on one websocket, so once
    // RETURN has arrived a dismissed DEPLOY would have arrived before it.
    cdp.eval(&click_button("RETURN")).await;
    let dialog = cdp.event("Page.javascriptDialogOpening").await;
    assert!(
        dialog["message"].as_str().unwrap().contains("RETURN=true"),
        "{dialog}"
    );
    cdp.call("Page.handleJavaScriptDialog", json!({ "accept": true }))
        .await;
    timeout(WAIT, async {
        while rec.0.lock().unwrap().is_empty() {
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
    })
    .await
    .expect("the accepted press was posted");
    assert_eq!(
        rec.0.lock().unwrap().clone(),
        vec![("RETURN".to_string(), Value::text("true"))],
        "only the confirmed press posts"
    );

    // The wheel zooms in by 1.2 and stops the automatic fit; a drag pans by the pointer's
    // travel in metres (right is east, down is south on the screen's y).
    let scale0 = cdp.eval("view.scale").await.as_f64().unwrap();
    cdp.eval(
        "canvas.dispatchEvent(new WheelEvent('wheel', { deltaY: -100, cancelable: true })); true",
    )
    .await;
    let scale1 = cdp.eval("view.scale").await.as_f64().unwrap();
    assert!((scale1 / scale0 - 1.2).abs() < 1e-9, "{scale0} -> {scale1}");
    assert_eq!(cdp.eval("view.auto").await, json!(false));
    let (cx0, cy0) = (
        cdp.eval("view.cx").await.as_f64().unwrap(),
        cdp.eval("view.cy").await.as_f64().unwrap(),
    );
    cdp.eval(
        "canvas.dispatchEvent(new MouseEvent('mousedown', { button: 0, clientX: 400, clientY: 300 }));\
         window.dispatchEvent(new MouseEvent('mousemove', { clientX: 460, clientY: 330 }));\
         window.dispatchEvent(new MouseEvent('mouseup', {})); true",
    )
    .await;
    let (cx1, cy1) = (
        cdp.eval("view.cx").await.as_f64().unwrap(),
        cdp.eval("view.cy").await.as_f64().unwrap(),
    );
    assert!((cx0 - cx1 - 60.0 / scale1).abs() < 1e-9, "{cx0} -> {cx1}");
    assert!((cy1 - cy0 - 30.0 / scale1).abs() < 1e-9, "{cy0} -> {cy1}");

    // A right-click offers the mission's context pokes; each is confirmed, with the spot.
    let right_click = "canvas.dispatchEvent(new MouseEvent('contextmenu', \
         { button: 2, clientX: 500, clientY: 400, cancelable: true })); \
         setTimeout(() => document.querySelector('#menu div').click(), 0); true";
    cdp.eval(right_click).await;
    let dialog = cdp.event("Page.javascriptDialogOpening").await;
    let message = dialog["message"].as_str().unwrap().to_string();
    assert!(
        message.starts_with("Post at x=") && message.contains("STATION_POINT"),
        "{message}"
    );
    cdp.call("Page.handleJavaScriptDialog", json!({ "accept": false }))
        .await;
    cdp.eval(right_click).await;
    cdp.event("Page.javascriptDialogOpening").await;
    cdp.call("Page.handleJavaScriptDialog", json!({ "accept": true }))
        .await;
    timeout(WAIT, async {
        while rec.0.lock().unwrap().len() < 2 {
            tokio::time::sleep(Duration::from_millis(20)).await;
        }
    })
    .await
    .expect("the accepted context poke was posted");
    let posted = rec.0.lock().unwrap().clone();
    assert_eq!(posted.len(), 2, "one post per confirmed poke: {posted:?}");
    assert_eq!(posted[1].0, "STATION_POINT");
    // The posted spot is the one the prompt showed (x=.., y=.. to 0.1 m).
    let shown: Vec<f64> = message["Post at ".len()..]
        .split('?')
        .next()
        .unwrap()
        .split(", ")
        .map(|kv| kv[2..].parse().unwrap())
        .collect();
    let value = posted[1].1.as_str().expect("a string poke");
    let got: Vec<f64> = value
        .split(',')
        .map(|kv| kv[2..].parse().unwrap())
        .collect();
    assert_eq!(got.len(), 2, "{value}");
    assert!(
        (got[0] - shown[0]).abs() <= 0.051 && (got[1] - shown[1]).abs() <= 0.051,
        "{value} vs {message}"
    );
}
