//! BHV_AvoidCollision with `use_refinery = true` in lockstep encounters (issue #18): the
//! head-on and crossing fleets of `missions/encounters` with `REFINERY=on` (the behaviour's
//! plateau refinery, `check_plateaus`, `check_validity` and `verbose`). Every closest
//! approach stays above `min_util_cpa_dist` (10 m), and the alogs hold the checks'
//! postings: `PLATEAU_CHECK_OK`, `PLATEAU_LOGIC_CASE` and `VALID_CHECK_OK`.

mod common;
mod encounters;

use encounters::{closest, run_fleet, values};

/// Runs `fleet` with `REFINERY=on`: the closest approach stays above `min_util_cpa_dist`,
/// and each vehicle's alog holds the checks' postings.
fn encounter(fleet: &str) {
    let name = format!("refinery-{}", fleet.trim_end_matches(".fleet"));
    let logs = run_fleet("encounters", &name, fleet, &["REFINERY=on"]);
    let pairs = closest(&logs);
    assert_eq!(pairs.len(), 1);
    let (_, (d, t)) = pairs[0];
    eprintln!("{fleet} with use_refinery: closest approach {d:.2} m at t={t:.2}");
    assert!(d > 10.0, "{fleet}: {d:.2} m is within min_util_cpa_dist");
    for (name, log) in &logs {
        let ok = values(log, "PLATEAU_CHECK_OK");
        let cases = values(log, "PLATEAU_LOGIC_CASE");
        let valid = values(log, "VALID_CHECK_OK");
        eprintln!(
            "{fleet} {name}: PLATEAU_CHECK_OK {ok:?}, {} PLATEAU_LOGIC_CASE, VALID_CHECK_OK {valid:?}, PLATEAU_WORST_FAIL {:?}",
            cases.len(),
            values(log, "PLATEAU_WORST_FAIL")
        );
        assert!(!ok.is_empty(), "{fleet} {name}: no PLATEAU_CHECK_OK");
        assert!(!cases.is_empty(), "{fleet} {name}: no PLATEAU_LOGIC_CASE");
        for c in &cases {
            assert!(
                ["aft", "fore_in_rgam", "fore_out_rgam"].contains(&c.as_str()),
                "{fleet} {name}: case {c}"
            );
        }
        // Every function's pieces cover the domain once.
        assert_eq!(valid, ["true"], "{fleet} {name}");
    }
}

#[test]
fn head_on_with_the_refinery() {
    encounter("head_on.fleet");
}

#[test]
fn crossing_with_the_refinery() {
    encounter("crossing.fleet");
}
