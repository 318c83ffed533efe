//! Real-time runs over a TCP MOOSDB (loopback, OS-chosen port) at a warp, with pokes and an
//! `until` condition. Waits are bounded and generous.

use std::time::Duration;

use mission::condition::parse_condition;
use moosdb::client::MailStream;
use moosdb::time::Warp;
use moosdb::{Client, ClientConfig, Server, ServerConfig};
use runtime::realtime::{RunEnd, RunSpec, run_apps};
use runtime::remote::{RemoteConfig, RemoteError};
use runtime::{App, Mail, Outcome, Poke, Post, Subscription, Value};

struct Counter;

impl App for Counter {
    fn name(&self) -> &str {
        "counter"
    }
    fn app_tick(&self) -> f64 {
        10.0
    }
    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> runtime::AppResult {
        out.push(Post::double("COUNTER_TIME", now));
        Ok(())
    }
}

/// Posts GO_SEEN = the GO value it was poked with.
struct Listener {
    go: Option<String>,
}

impl App for Listener {
    fn name(&self) -> &str {
        "listener"
    }
    fn subscriptions(&self) -> Vec<Subscription> {
        vec![Subscription::var("GO")]
    }
    fn on_mail(&mut self, mail: &[Mail], _now: f64, _out: &mut Vec<Post>) -> runtime::AppResult {
        for m in mail {
            self.go = m.value.as_str().map(String::from);
        }
        Ok(())
    }
    fn iterate(&mut self, _now: f64, out: &mut Vec<Post>) -> runtime::AppResult {
        if let Some(g) = &self.go {
            out.push(Post::text("GO_SEEN", g.clone()));
        }
        Ok(())
    }
}

async fn server(warp: f64) -> Server {
    let mut sc = ServerConfig::with_addr(([127, 0, 0, 1], 0).into());
    sc.warp = Warp::new(warp).unwrap();
    Server::bind(sc).await.unwrap()
}

fn cfg(s: &Server, warp: f64) -> RemoteConfig {
    RemoteConfig {
        host: "127.0.0.1".into(),
        port: s.local_addr().port(),
        warp,
    }
}

/// A client of the run's DB from outside it, registered for `vars`.
async fn outsider(c: &RemoteConfig, vars: &[&str]) -> (Client, MailStream) {
    let mut occ = ClientConfig::new("outsider", "127.0.0.1", c.port);
    occ.warp = Warp::new(c.warp).unwrap();
    let (client, inbox) = Client::start(occ);
    client.wait_connected().await.unwrap();
    for v in vars {
        client.register(v, 0.0);
    }
    (client, inbox)
}

/// Runs `apps` to their end, which must come within 60 s of wall time.
async fn run_to_end(apps: Vec<Box<dyn App>>, c: &RemoteConfig, spec: RunSpec) -> RunEnd {
    let local = tokio::task::LocalSet::new();
    tokio::time::timeout(
        Duration::from_secs(60),
        local.run_until(run_apps(apps, c, spec)),
    )
    .await
    .expect("ends within 60 s")
    .unwrap()
}

#[tokio::test(flavor = "current_thread")]
async fn pokes_reach_apps_and_until_ends_the_run() {
    let s = server(10.0).await;
    let c = cfg(&s, 10.0);
    let spec = RunSpec {
        pokes: vec![
            Poke::parse("MODE_POKE=ready", "listener").unwrap(),
            Poke::parse("GO=yes@2", "listener").unwrap(),
        ],
        until: Some(parse_condition("GO_SEEN = yes").unwrap()),
        max_time: 600.0,
    };
    let apps: Vec<Box<dyn App>> = vec![Box::new(Counter), Box::new(Listener { go: None })];
    let end = run_to_end(apps, &c, spec).await;
    let Outcome::ConditionMet { time } = end.outcome else {
        panic!("{:?}", end.outcome)
    };
    assert!(time > 0.0);
    assert_eq!(
        end.values,
        vec![("GO_SEEN".to_string(), Some(Value::text("yes")))]
    );
    // The after-first-iterate poke went out too (read back from the DB).
    let m = s
        .with_db(|db| db.current("MODE_POKE"))
        .expect("MODE_POKE posted");
    assert_eq!(m.sval_str(), "ready");
    assert_eq!(m.src_str(), "uPokeDB");
    s.shutdown();
}

#[tokio::test(flavor = "current_thread")]
async fn max_time_ends_the_run_and_an_outside_client_sees_the_apps() {
    let s = server(20.0).await;
    let c = cfg(&s, 20.0);
    let (outsider, mut inbox) = outsider(&c, &["COUNTER_TIME"]).await;
    let spec = RunSpec {
        pokes: Vec::new(),
        until: Some(parse_condition("NEVER = 1").unwrap()),
        max_time: 4.0,
    };
    let apps: Vec<Box<dyn App>> = vec![Box::new(Counter)];
    let end = run_to_end(apps, &c, spec).await;
    assert!(
        matches!(end.outcome, Outcome::MaxTime { .. }),
        "{:?}",
        end.outcome
    );
    assert_eq!(end.values, vec![("NEVER".to_string(), None)]);
    let mut got = 0;
    while let Ok(Some(_)) = tokio::time::timeout(Duration::from_millis(200), inbox.recv()).await {
        got += 1;
    }
    assert!(got > 0, "the outside client saw no COUNTER_TIME");
    outsider.close().await;
    s.shutdown();
}

#[tokio::test(flavor = "current_thread")]
async fn a_refused_app_ends_the_run_with_its_error() {
    let s = server(1.0).await;
    let c = cfg(&s, 1.0);
    let (squatter, _m) = Client::start(ClientConfig::new("counter", "127.0.0.1", c.port));
    squatter.wait_connected().await.unwrap();
    let local = tokio::task::LocalSet::new();
    let spec = RunSpec {
        pokes: Vec::new(),
        until: None,
        max_time: 3600.0,
    };
    let apps: Vec<Box<dyn App>> = vec![Box::new(Counter), Box::new(Listener { go: None })];
    let r = tokio::time::timeout(
        Duration::from_secs(60),
        local.run_until(run_apps(apps, &c, spec)),
    )
    .await
    .expect("ends within 60 s");
    assert!(matches!(r, Err(RemoteError::Client(_))), "{r:?}");
    squatter.close().await;
    s.shutdown();
}

/// Posts `DEPLOY = false` at its first iteration, as the helm posts its `initialize` values.
struct Initializer {
    started: bool,
}

impl App for Initializer {
    fn name(&self) -> &str {
        "initializer"
    }
    fn app_tick(&self) -> f64 {
        10.0
    }
    fn iterate(&mut self, _now: f64, out: &mut Vec<Post>) -> runtime::AppResult {
        if !self.started {
            self.started = true;
            out.push(Post::text("DEPLOY", "false"));
        }
        Ok(())
    }
}

/// A poke "after the first iterate" waits for the app's first `<APP>_STATUS`, so that status
/// must reach the DB after what the first iteration posted: a `DEPLOY = true` poke that
/// overtook the helm's initial `DEPLOY = false` left a vehicle parked (seen under load in the
/// HIL survey).
#[tokio::test(flavor = "current_thread")]
async fn the_first_status_follows_the_first_iterations_postings() {
    let s = server(10.0).await;
    let c = cfg(&s, 10.0);
    let (outsider, mut inbox) = outsider(&c, &["DEPLOY", "INITIALIZER_STATUS"]).await;
    let spec = RunSpec {
        pokes: vec![Poke::parse("DEPLOY=true", "initializer").unwrap()],
        until: Some(parse_condition("DEPLOY = true").unwrap()),
        max_time: 600.0,
    };
    let apps: Vec<Box<dyn App>> = vec![Box::new(Initializer { started: false })];
    let end = run_to_end(apps, &c, spec).await;
    assert!(
        matches!(end.outcome, Outcome::ConditionMet { .. }),
        "{:?}",
        end.outcome
    );
    let mut seen = Vec::new();
    while let Ok(Some(m)) = tokio::time::timeout(Duration::from_millis(300), inbox.recv()).await {
        let key = m.key_str().into_owned();
        if key == "DEPLOY" || key == "INITIALIZER_STATUS" {
            let v = if key == "DEPLOY" {
                m.sval_str().into_owned()
            } else {
                String::new()
            };
            seen.push(format!("{key}{}{v}", if v.is_empty() { "" } else { "=" }));
        }
    }
    let first_status = seen
        .iter()
        .position(|k| k == "INITIALIZER_STATUS")
        .unwrap_or_else(|| panic!("no status: {seen:?}"));
    assert_eq!(
        seen[..first_status],
        ["DEPLOY=false".to_string()],
        "the initial value, then the status: {seen:?}"
    );
    assert_eq!(
        seen.iter().rfind(|k| k.starts_with("DEPLOY=")),
        Some(&"DEPLOY=true".to_string()),
        "{seen:?}"
    );
    let m = s.with_db(|db| db.current("DEPLOY")).expect("DEPLOY posted");
    assert_eq!(
        (m.sval_str().as_ref(), m.src_str().as_ref()),
        ("true", "uPokeDB")
    );
    outsider.close().await;
    s.shutdown();
}
