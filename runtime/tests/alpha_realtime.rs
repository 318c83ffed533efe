//! The real s1_alpha mission in real time at a warp: every app (helm, simulator, PID, node
//! reporter) a separate client of a TCP MOOSDB, deployed by pokes, until
//! `MISSION = complete`. Bounded by a generous wall-clock timeout.

use std::time::Duration;

use mission::source::SourceMap;
use moosdb::time::Warp;
use moosdb::{Server, ServerConfig};
use runtime::antler::{Launch, plan};
use runtime::helm::HelmApp;
use runtime::realtime::{RunSpec, run_apps};
use runtime::remote::RemoteConfig;
use runtime::{App, Outcome, Poke, Value};

#[tokio::test(flavor = "current_thread")]
async fn alpha_completes_in_real_time_at_warp_40() {
    let read = |n: &str| test_support::mission_text(&format!("s1_alpha/{n}"));
    let m =
        mission::moos::parse_moos(&SourceMap::from_text("alpha.moos", &read("alpha.moos"))).value;
    let bhv = mission::bhv::parse_bhv(&SourceMap::from_text("alpha.bhv", &read("alpha.bhv")));
    let warp = 40.0;
    let mut sc = ServerConfig::with_addr(([127, 0, 0, 1], 0).into());
    sc.warp = Warp::new(warp).unwrap();
    let server = Server::bind(sc).await.unwrap();
    let cfg = RemoteConfig {
        host: "127.0.0.1".into(),
        port: server.local_addr().port(),
        warp,
    };
    let start = moosdb::time::unix_now() * warp;
    // No log target: pLogger is skipped (with a warning) here.
    let p = plan(&m, Launch::new(start, 1), &mut |run, block| {
        (run.app == "pHelmIvP").then(|| {
            Ok(Box::new(HelmApp::new(run.moos_name(), block.cloned(), &m, &bhv)) as Box<dyn App>)
        })
    })
    .unwrap();
    let names: Vec<&str> = p.apps.iter().map(|a| a.name()).collect();
    assert_eq!(
        names,
        vec![
            "uSimMarineV22",
            "pMarinePIDV22",
            "pHelmIvP",
            "pNodeReporter"
        ]
    );
    let spec = RunSpec {
        pokes: vec![
            Poke::parse("DEPLOY=true", "pHelmIvP").unwrap(),
            Poke::parse("MOOS_MANUAL_OVERRIDE=false", "pHelmIvP").unwrap(),
        ],
        until: Some(mission::condition::parse_condition("MISSION = complete").unwrap()),
        max_time: 2000.0,
    };
    let local = tokio::task::LocalSet::new();
    let end = tokio::time::timeout(
        Duration::from_secs(240),
        local.run_until(run_apps(p.apps, &cfg, spec)),
    )
    .await
    .expect("alpha ends within 240 wall seconds at warp 40")
    .unwrap();
    assert!(
        matches!(end.outcome, Outcome::ConditionMet { .. }),
        "{:?}, {:?}",
        end.outcome,
        end.values
    );
    assert_eq!(
        end.values,
        vec![("MISSION".to_string(), Some(Value::text("complete")))]
    );
    let x = server.with_db(|db| db.current("NAV_X")).unwrap();
    let y = server.with_db(|db| db.current("NAV_Y")).unwrap();
    // Back near the return point 0,-20.
    assert!(
        x.dval.hypot(y.dval + 20.0) < 10.0,
        "ended at {},{}",
        x.dval,
        y.dval
    );
    server.shutdown();
}
