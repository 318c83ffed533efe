//! The real s4_delta mission in lockstep with every app in-process (helm, legacy
//! uSimMarine, pMarinePID, pNodeReporter, its GPS uTimerScript, pLogger), deployed, with
//! `SURVEY=true` at 300 s and `RETURN=true` at 1200 s, until `DEPLOY = false`.

mod support;

use runtime::Outcome;
use runtime::summary::RunSummary;
use support::{START, run_corpus};

#[test]
fn delta_loiters_surveys_and_returns() {
    let (outcome, bytes) = run_corpus(
        "s4_delta",
        "delta",
        &[
            "DEPLOY=true",
            "MOOS_MANUAL_OVERRIDE=false",
            "SURVEY=true@300",
            "RETURN=true@1200",
        ],
        "DEPLOY = false",
        3600.0,
    );
    let Outcome::ConditionMet { time } = outcome else {
        panic!("delta did not end: {outcome:?}");
    };
    assert!(
        time - START > 1200.0,
        "ended before the return was asked: {}",
        time - START
    );
    let log = alog::parse(std::str::from_utf8(&bytes).unwrap()).unwrap();
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
