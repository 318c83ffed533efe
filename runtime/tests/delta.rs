//! The real s4_delta mission in lockstep with every app in-process (helm, legacy
//! uSimMarine, pMarinePID, pNodeReporter, its GPS uTimerScript, pLogger), deployed, with
//! `SURVEY=true` at 300 s and `RETURN=true` at 1200 s, until `DEPLOY = false`.

use chrono::NaiveDate;
use mission::source::SourceMap;
use runtime::antler::{LogTarget, logger_config, plan};
use runtime::helm::HelmApp;
use runtime::logger::SharedBuffer;
use runtime::summary::RunSummary;
use runtime::{App, Bus, Outcome, Poke, Scheduler, VirtualClock};

const START: f64 = 1_786_000_000.0;
const DIR: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../shared/corpus/moos-ivp-missions/s4_delta"
);

#[test]
fn delta_loiters_surveys_and_returns() {
    let read = |n: &str| {
        std::fs::read_to_string(format!("{DIR}/{n}"))
            .unwrap_or_else(|e| panic!("corpus file {DIR}/{n} is required: {e}"))
    };
    let m =
        mission::moos::parse_moos(&SourceMap::from_text("delta.moos", &read("delta.moos"))).value;
    let bhv = mission::bhv::parse_bhv(&SourceMap::from_text("delta.bhv", &read("delta.bhv")));
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
            let e = h.config_errors();
            if e.is_empty() {
                Ok(Box::new(h) as Box<dyn App>)
            } else {
                Err(e.join("; "))
            }
        })
    })
    .unwrap();
    let mut s = Scheduler::new(Bus::new(&p.globals.community, START), VirtualClock, START);
    for app in p.apps {
        s.add_app(app).unwrap();
    }
    for poke in [
        "DEPLOY=true",
        "MOOS_MANUAL_OVERRIDE=false",
        "SURVEY=true@300",
        "RETURN=true@1200",
    ] {
        s.add_poke(Poke::parse(poke, "pHelmIvP").unwrap()).unwrap();
    }
    s.set_until(mission::condition::parse_condition("DEPLOY = false").unwrap());
    let outcome = s.run(3600.0).unwrap();
    s.deliver_pending().unwrap();
    let Outcome::ConditionMet { time } = outcome else {
        panic!("delta did not end: {outcome:?}");
    };
    assert!(
        time - START > 1200.0,
        "ended before the return was asked: {}",
        time - START
    );
    let log = alog::parse(std::str::from_utf8(&buf.contents()).unwrap()).unwrap();
    // Hierarchical modes in the expected order, each entered after its poke.
    let modes: Vec<(f64, &str)> = log
        .entries
        .iter()
        .filter(|e| e.var == "MODE")
        .filter_map(|e| Some((e.time, e.value.as_str()?)))
        .collect();
    let first = |name: &str| {
        modes
            .iter()
            .find(|(_, m)| *m == name)
            .unwrap_or_else(|| panic!("mode {name} never entered: {modes:?}"))
            .0
    };
    let (loiter, survey, ret) = (
        first("ACTIVE:LOITERING"),
        first("ACTIVE:SURVEYING"),
        first("ACTIVE:RETURNING"),
    );
    assert!(loiter < 300.0 && (300.0..301.0).contains(&survey) && (1200.0..1201.0).contains(&ret));
    let sum = RunSummary::from_alog(&log);
    // It dives under the survey and loiter depth behaviours, and ends near the start.
    assert!(sum.max_depth > 5.0, "max depth {}", sum.max_depth);
    let (x, y) = sum.final_position.unwrap();
    assert!(x.hypot(y) < 10.0, "ended at {x},{y}");
    assert!(sum.distance > 1000.0, "travelled {}", sum.distance);
    let last_deploy = log
        .entries
        .iter()
        .rev()
        .find(|e| e.var == "DEPLOY")
        .unwrap();
    assert_eq!(last_deploy.value.as_str(), Some("false"));
}
