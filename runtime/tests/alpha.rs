//! The real s1_alpha mission run in lockstep with every app in-process: the helm engine,
//! the simulator, the marine PID, the node reporter and pLogger, deployed as `--deploy`
//! would, until `MISSION = complete`.

use chrono::NaiveDate;
use mission::source::SourceMap;
use runtime::antler::{LogTarget, logger_config, plan};
use runtime::helm::HelmApp;
use runtime::logger::SharedBuffer;
use runtime::plot::PlotData;
use runtime::{App, Bus, Outcome, Poke, Scheduler, VirtualClock};

const START: f64 = 1_786_000_000.0;
const DIR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../shared/corpus/moos-ivp-missions/s1_alpha"
);

fn read(name: &str) -> String {
    let path = format!("{DIR}/{name}");
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("corpus file {path} is required: {e}"))
}

fn run() -> (Outcome, Vec<u8>) {
    let m = mission::moos::parse_moos(&SourceMap::from_text("alpha.moos", &read("alpha.moos")));
    assert!(!m.has_errors());
    let m = m.value;
    let bhv = mission::bhv::parse_bhv(&SourceMap::from_text("alpha.bhv", &read("alpha.bhv")));
    let buf = SharedBuffer::default();
    let target = LogTarget {
        config: logger_config(&m),
        writer: Box::new(buf.clone()),
        opened: NaiveDate::from_ymd_opt(2026, 8, 5)
            .unwrap()
            .and_hms_opt(18, 22, 55)
            .unwrap(),
        opened_on: "Thu Jan  1 00:00:00 1970".into(),
    };
    let p = plan(&m, START, 1, Some(target), &mut |run, block| {
        (run.app == "pHelmIvP").then(|| {
            let h = HelmApp::new(run.moos_name(), block.cloned(), &m, &bhv);
            let errors = h.config_errors();
            if errors.is_empty() {
                Ok(Box::new(h) as Box<dyn App>)
            } else {
                Err(errors.join("; "))
            }
        })
    })
    .unwrap();
    let mut s = Scheduler::new(Bus::new(&p.globals.community, START), VirtualClock, START);
    for app in p.apps {
        s.add_app(app).unwrap();
    }
    for poke in ["DEPLOY=true", "MOOS_MANUAL_OVERRIDE=false"] {
        s.add_poke(Poke::parse(poke, "pHelmIvP").unwrap()).unwrap();
    }
    s.set_until(mission::condition::parse_condition("MISSION = complete").unwrap());
    let outcome = s.run(1800.0).unwrap();
    s.deliver_pending().unwrap();
    (outcome, buf.contents())
}

#[test]
fn alpha_completes_visiting_every_vertex_in_order_then_returns() {
    let (outcome, bytes) = run();
    let Outcome::ConditionMet { time } = outcome else {
        panic!("alpha did not complete: {outcome:?}");
    };
    assert!(time - START > 200.0, "finished too early: {}", time - START);
    let log = alog::parse(std::str::from_utf8(&bytes).unwrap()).unwrap();
    let track = PlotData::from_alog(&log).track;
    // alpha.bhv: survey polygon in order (slip radius 15), then the return point
    // 0,-20 (slip radius 8).
    let survey = [
        (60.0, -40.0),
        (60.0, -160.0),
        (150.0, -160.0),
        (180.0, -100.0),
        (150.0, -40.0),
    ];
    let mut from = 0;
    let mut passed = Vec::new();
    for &(vx, vy) in &survey {
        let hit = track[from..]
            .iter()
            .position(|&(_, x, y)| (x - vx).hypot(y - vy) <= 15.0)
            .unwrap_or_else(|| panic!("vertex {vx},{vy} not reached after record {from}"));
        from += hit;
        passed.push(track[from].0);
    }
    let back = track[from..]
        .iter()
        .position(|&(_, x, y)| x.hypot(y + 20.0) <= 8.0)
        .expect("return point reached after the survey");
    assert!(passed.windows(2).all(|w| w[0] < w[1]), "{passed:?}");
    assert!(track[from + back].0 > passed[4]);
    // The helm drove, and its completion flags came out.
    let last = |var: &str| {
        log.entries
            .iter()
            .rev()
            .find(|e| e.var == var)
            .and_then(|e| e.value.as_str().map(String::from))
    };
    assert_eq!(last("MISSION").as_deref(), Some("complete"));
    assert_eq!(last("DEPLOY").as_deref(), Some("false"));
    assert!(
        log.entries
            .iter()
            .any(|e| e.var == "IVPHELM_STATE" && e.value.as_str() == Some("DRIVE"))
    );
    // pLogger with LogAuxSrc: the helm's initialisation posts carry their aux source.
    assert!(
        log.entries
            .iter()
            .any(|e| e.var == "RETURN" && e.source == "pHelmIvP:HELM_VAR_INIT"),
        "no RETURN from pHelmIvP:HELM_VAR_INIT"
    );
}

#[test]
fn alpha_lockstep_logs_are_byte_identical() {
    let (o1, a) = run();
    let (o2, b) = run();
    assert_eq!(o1, o2);
    assert!(a.len() > 1_000_000, "{} bytes", a.len());
    assert!(a == b, "two lockstep runs of alpha differ");
}
