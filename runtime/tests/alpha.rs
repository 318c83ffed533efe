//! The real s1_alpha mission run in lockstep with every app in-process: the helm engine,
//! the simulator, the marine PID, the node reporter and pLogger, deployed as `--deploy`
//! would, until `MISSION = complete`.

mod support;

use runtime::Outcome;
use runtime::plot::PlotData;
use support::{START, run_corpus};

fn run() -> (Outcome, Vec<u8>) {
    run_corpus(
        "s1_alpha",
        "alpha",
        &["DEPLOY=true", "MOOS_MANUAL_OVERRIDE=false"],
        "MISSION = complete",
        1800.0,
    )
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
