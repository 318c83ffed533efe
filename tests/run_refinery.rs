//! BHV_AvoidCollision with `use_refinery = true` in lockstep encounters (issue #18): the
//! head-on and crossing fleets of `missions/encounters` with `REFINERY=on` (the behaviour's
//! plateau refinery, `check_plateaus`, `check_validity` and `verbose`). Every closest
//! approach stays above `min_util_cpa_dist` (10 m), and the alogs hold the checks'
//! postings: `PLATEAU_CHECK_OK`, `PLATEAU_LOGIC_CASE` and `VALID_CHECK_OK`.

mod common;

use std::collections::BTreeMap;

use common::*;
use runtime::fleet::LoadedFleet;
use runtime::session::{self, FleetOptions, Mode};

/// Runs `fleet` with `REFINERY=on`, deployed, until every transit is complete; returns each
/// community's parsed alog by name.
fn run(fleet: &str) -> BTreeMap<String, alog::Alog> {
    let path = project_mission(&format!("encounters/{fleet}"));
    let macros = vec!["REFINERY=on".to_string()];
    let loaded = LoadedFleet::from_file(&path, &macros, &[])
        .unwrap_or_else(|e| panic!("{fleet} does not load: {e}"));
    let checked = session::validate_fleet(&loaded);
    assert!(checked.errors.is_empty(), "{:?}", checked.errors);
    assert!(checked.malconfig.is_empty(), "{:?}", checked.malconfig);
    let dir = fresh_dir(&format!("refinery-{}", fleet.trim_end_matches(".fleet")));
    let opts = FleetOptions {
        mode: Mode::Lockstep,
        deploy: true,
        until: vec!["MISSION = complete".into()],
        max_time: 600.0,
        log_dir: Some(dir.join("logs")),
        ..FleetOptions::default()
    };
    let report = session::run_fleet(&loaded, &opts, &mut session::Quiet)
        .unwrap_or_else(|e| panic!("{fleet} failed: {e}"));
    assert!(
        matches!(
            report.ended,
            session::Ended::Outcome(runtime::Outcome::ConditionMet { .. })
        ),
        "{fleet}: {report}"
    );
    report
        .members
        .iter()
        .map(|(m, _)| {
            let alog = find_alog(&dir.join("logs").join(m));
            (m.clone(), parse(&std::fs::read(&alog).unwrap()))
        })
        .collect()
}

/// The closest approach of two tracks (each position of `a` against `b`'s latest).
fn closest(a: &[(f64, f64, f64)], b: &[(f64, f64, f64)]) -> f64 {
    let mut best = f64::INFINITY;
    let mut j = 0;
    for &(t, x, y) in a {
        while j + 1 < b.len() && b[j + 1].0 <= t {
            j += 1;
        }
        if b.is_empty() || b[j].0 > t {
            continue;
        }
        best = best.min((x - b[j].1).hypot(y - b[j].2));
    }
    best
}

fn values(log: &alog::Alog, var: &str) -> Vec<String> {
    log.entries
        .iter()
        .filter(|e| e.var == var)
        .map(|e| e.value.to_string())
        .collect()
}

fn encounter(fleet: &str) {
    let logs = run(fleet);
    let names: Vec<&String> = logs.keys().collect();
    assert_eq!(names.len(), 2);
    let d = closest(&track(&logs[names[0]]), &track(&logs[names[1]]));
    eprintln!("{fleet} with use_refinery: closest approach {d:.2} m");
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
