//! A safety default in lockstep with the real coug vehicle: BHV_MaxDepth without a
//! `duration` line guards for the whole run (MOOS-IvP a2a9b716 gives it no time limit), so a
//! ConstantDepth of 30 m (pwt 120) against MaxDepth 12 m, tolerance 4 (pwt 300) keeps the
//! vehicle at or above 16 m, as the real pHelmIvP does.

mod support;

use runtime::Outcome;
use support::run_dir;

#[test]
fn max_depth_without_duration_keeps_the_vehicle_above_its_limit() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/data/max_depth_guard");
    let (outcome, bytes) = run_dir(
        dir,
        "guard",
        &["DEPLOY=true", "MOOS_MANUAL_OVERRIDE=false"],
        "DEPLOY = never",
        600.0,
    );
    assert!(matches!(outcome, Outcome::MaxTime { .. }), "{outcome:?}");
    let log = alog::parse(std::str::from_utf8(&bytes).unwrap()).unwrap();
    let depths: Vec<(f64, f64)> = log
        .entries
        .iter()
        .filter(|e| e.var == "NAV_DEPTH")
        .filter_map(|e| Some((e.time, e.value.as_f64()?)))
        .collect();
    assert!(depths.len() > 1000, "{} NAV_DEPTH entries", depths.len());
    let deepest = depths.iter().map(|d| d.1).fold(0.0, f64::max);
    // max_depth + tolerance is the hard bound; the guard should hold close to 12 m.
    assert!(
        deepest <= 16.0,
        "dived to {deepest} m through the 12 m limit"
    );
    // Not vacuous: the vehicle did dive toward the limit and stayed near it.
    assert!(deepest > 10.0, "never dived: deepest {deepest} m");
    let late: Vec<f64> = depths
        .iter()
        .filter(|(t, _)| *t > 400.0)
        .map(|d| d.1)
        .collect();
    assert!(
        late.iter().all(|d| (9.0..=16.0).contains(d)),
        "not held near 12 m after 400 s: {:?}",
        late.iter()
            .fold((f64::MAX, 0.0_f64), |(lo, hi), d| (lo.min(*d), hi.max(*d)))
    );
    // The guard never completed, and posted its slack.
    let completed = log.entries.iter().any(|e| {
        e.var == "IVPHELM_SUMMARY"
            && e.value
                .as_str()
                .and_then(|s| s.split(",completed_bhvs=").nth(1))
                .is_some_and(|c| c.split(',').next().unwrap_or_default().contains("guard"))
    });
    assert!(!completed, "the max-depth guard completed");
    assert!(
        log.entries.iter().any(|e| e.var == "DEPTH_SLACK"),
        "DEPTH_SLACK never posted"
    );
}
