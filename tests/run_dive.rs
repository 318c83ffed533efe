//! `coug run` end to end on diving missions, in lockstep: the project's CougUV dive
//! mission (missions/dive) and the real s4_delta mission.

mod common;

use common::*;

/// The first record at or after `t` seconds.
fn index_at(track: &[(f64, f64, f64)], t: f64) -> usize {
    track.iter().position(|p| p.0 >= t).unwrap_or(track.len())
}

/// The time of the first post of `var` with value `val`.
fn first_post(log: &alog::Alog, var: &str, val: &str) -> Option<f64> {
    log.entries
        .iter()
        .find(|e| e.var == var && e.value.as_str() == Some(val))
        .map(|e| e.time)
}

#[test]
fn dive_mission_dives_surveys_surfaces_for_gps_and_loiters() {
    let mission = project_mission("dive/dive.moos");
    let opts = deploy_until("MISSION = complete", 1200.0);
    let (a, stdout) = run_lockstep("run-dive-1", &mission, &[], opts.clone());
    let (b, _) = run_lockstep("run-dive-1", &mission, &[], opts);
    assert!(
        a == b,
        "two lockstep runs of the dive mission wrote different alogs"
    );
    assert!(stdout.contains("completed:   survey, loiter"), "{stdout}");

    let log = parse(&a);
    let t = track(&log);
    let d = depths(&log);
    let done = first_post(&log, "SURVEY_DONE", "true").expect("the survey ends");

    // Dives to near the survey depth (4 m) and never beyond max_depth 6 + tolerance 1.
    let max = d.iter().map(|p| p.1).fold(0.0, f64::max);
    assert!(max >= 3.0, "dived only to {max} m");
    assert!(max <= 7.0, "exceeded the max depth: {max} m");
    let first_deep = d.iter().find(|p| p.1 >= 3.0).expect("reaches depth").0;
    assert!(first_deep < 60.0, "took {first_deep} s to dive");

    // Periodic surfacing during the survey: up (< 0.5 m), a GPS fix, then down again.
    let up = d
        .iter()
        .find(|p| p.0 > first_deep && p.0 < done && p.1 < 0.5)
        .expect("surfaces during the survey")
        .0;
    let gps = log
        .entries
        .iter()
        .find(|e| e.var == "GPS_UPDATE_RECEIVED" && e.time > up)
        .expect("uTimerScript fakes a GPS fix at the surface");
    assert_eq!(gps.source, "uTimerScript_GPS");
    let gps_depth = d.iter().rev().find(|p| p.0 <= gps.time).unwrap().1;
    assert!(gps_depth < 0.5, "GPS fix at {gps_depth} m");
    assert!(
        d.iter().any(|p| p.0 > gps.time && p.0 < done && p.1 >= 3.0),
        "dives again after the fix"
    );

    // The survey points in order (slip radius 10), inside the operating region.
    let points = [(30.0, -20.0), (30.0, -120.0), (70.0, -120.0), (70.0, -20.0)];
    let after = visits_in_order(&t, &points, 10.0, 0);
    assert!(t[after].0 <= done + 1.0);
    assert!(
        t.iter()
            .all(|&(_, x, y)| (-40.0..=140.0).contains(&x) && (-160.0..=40.0).contains(&y)),
        "left the operating region"
    );

    // Then the loiter at the surface around 15,-25 (radius 20) until it completes.
    let loiter = &t[index_at(&t, done + 60.0)..];
    assert!(!loiter.is_empty());
    assert!(
        loiter
            .iter()
            .all(|&(_, x, y)| (x - 15.0).hypot(y + 25.0) < 40.0),
        "strayed from the loiter"
    );
    let final_depth = d.last().unwrap().1;
    assert!(final_depth < 0.5, "ends at {final_depth} m");
    assert_eq!(last_str(&log, "MISSION").as_deref(), Some("complete"));
    check_plots(&a, "run-dive", true);
    check_committed_png("dive");
}

/// The real s4_delta mission as the issue runs it (its GPS uTimerScript, legacy
/// uSimMarine and pMarinePID with depth control), surveying from 300 s and returning at
/// 1200 s.
#[test]
fn delta_dives_loiters_with_periodic_surfacing_surveys_and_returns() {
    let mission = test_support::mission_file("s4_delta/delta.moos");
    let opts = RunOptions {
        pokes: vec!["SURVEY=true@300".into(), "RETURN=true@1200".into()],
        ..deploy_until("DEPLOY = false", 3000.0)
    };
    let (a, _) = run_lockstep("run-delta-1", &mission, &[], opts.clone());
    let (b, _) = run_lockstep("run-delta-1", &mission, &[], opts);
    assert!(a == b, "two lockstep runs of delta wrote different alogs");
    let log = parse(&a);
    let t = track(&log);
    let d = depths(&log);
    let survey = first_post(&log, "MODE", "ACTIVE:SURVEYING").expect("surveys");
    let ret = first_post(&log, "MODE", "ACTIVE:RETURNING").expect("returns");
    assert!((300.0..301.0).contains(&survey) && (1200.0..1201.0).contains(&ret));

    // Dives, and never deeper than max_depth 7 + tolerance 1.
    let max = d.iter().map(|p| p.1).fold(0.0, f64::max);
    assert!(max > 3.0, "dived only to {max} m");
    assert!(max <= 8.0, "exceeded delta's max depth 7 (+1): {max} m");

    // Loiters (before the survey) with periodic surfacing: down, then up for a fix.
    let deep = d
        .iter()
        .find(|p| p.0 < survey && p.1 >= 2.0)
        .expect("dives while loitering")
        .0;
    assert!(
        d.iter().any(|p| p.0 > deep && p.0 < survey && p.1 < 0.5),
        "no periodic surfacing while loitering"
    );
    // The loiter polygon: radial around 20,-80, radius 20.
    let loiter = &t[index_at(&t, 150.0)..index_at(&t, survey)];
    assert!(
        loiter
            .iter()
            .all(|&(_, x, y)| (x - 20.0).hypot(y + 80.0) < 45.0)
    );

    // Surveys: the bowtie's points (VIEW_SEGLIST of waypt_survey) within radius 8, in order.
    let seg = log
        .entries
        .iter()
        .find(|e| e.var == "VIEW_SEGLIST" && e.value.as_str().is_some_and(|v| v.contains("pts=")))
        .and_then(|e| e.value.as_str())
        .expect("the survey posts its seglist")
        .to_string();
    let pts: Vec<(f64, f64)> = seg
        .split("pts={")
        .nth(1)
        .and_then(|r| r.split('}').next())
        .unwrap()
        .split(':')
        .map(|p| {
            let (x, y) = p.split_once(',').unwrap();
            (x.parse().unwrap(), y.parse().unwrap())
        })
        .collect();
    assert!(pts.len() >= 6, "{seg}");
    let after = visits_in_order(&t, &pts, 8.0, index_at(&t, survey));
    assert!(t[after].0 < ret);

    // Returns to 0,0.
    visits_in_order(&t, &[(0.0, 0.0)], 8.0, index_at(&t, ret));
    assert_eq!(last_str(&log, "DEPLOY").as_deref(), Some("false"));
    check_plots(&a, "run-delta", true);
}
