//! `coug run` end to end on the project's own surface mission (missions/surface_survey),
//! in lockstep: it completes, visits every survey point in order at the survey speed,
//! returns home, logs byte-identical alogs twice, and `coug plot` draws the track.

mod common;

use common::*;

#[test]
fn surface_survey_completes_and_is_repeatable() {
    let mission = project_mission("surface_survey/survey.moos");
    let opts = deploy_until("MISSION = complete", 900.0);
    let (a, stdout) = run_lockstep("run-survey-1", &mission, &[], opts.clone());
    let (b, _) = run_lockstep("run-survey-1", &mission, &[], opts);
    assert!(
        a == b,
        "two lockstep runs of the survey wrote different alogs"
    );
    assert!(stdout.contains("completed:   survey, return"), "{stdout}");

    let log = parse(&a);
    let t = track(&log);
    // survey.bhv: the survey points (slip radius 10), then home 0,0 (slip radius 8).
    let points = [
        (20.0, -20.0),
        (20.0, -100.0),
        (60.0, -100.0),
        (60.0, -20.0),
        (100.0, -20.0),
        (100.0, -100.0),
    ];
    let after = visits_in_order(&t, &points, 10.0, 0);
    visits_in_order(&t, &[(0.0, 0.0)], 8.0, after);
    assert_eq!(last_str(&log, "MISSION").as_deref(), Some("complete"));
    // Constant speed: once under way, the speed stays near 2 m/s.
    let speeds: Vec<f64> = log
        .entries
        .iter()
        .filter(|e| e.var == "NAV_SPEED" && e.time > 30.0)
        .filter_map(|e| e.value.as_f64())
        .collect();
    let mean = speeds.iter().sum::<f64>() / speeds.len() as f64;
    assert!((1.7..=2.3).contains(&mean), "mean speed {mean}");
    // The surface mission never dives: no depth panel.
    check_plots(&a, "run-survey", false);
    check_committed_png("surface_survey");
}

#[test]
fn macros_reach_the_behaviour_file() {
    let mission = project_mission("surface_survey/survey.moos");
    let (a, _) = run_lockstep(
        "run-survey-slow",
        &mission,
        &["SPEED=1.5"],
        deploy_until("MISSION = complete", 900.0),
    );
    let log = parse(&a);
    let speeds: Vec<f64> = log
        .entries
        .iter()
        .filter(|e| e.var == "NAV_SPEED" && e.time > 30.0)
        .filter_map(|e| e.value.as_f64())
        .collect();
    let mean = speeds.iter().sum::<f64>() / speeds.len() as f64;
    assert!(
        (1.3..=1.7).contains(&mean),
        "mean speed {mean} with SPEED=1.5"
    );
}
