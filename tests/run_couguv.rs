//! `coug run` end to end on missions/cougUV in its simulation form, in lockstep: the helm on
//! pNavGraph's estimate, pCougControls' cascade and fin mixing, and uSimCougUV's CougUV
//! model closing the loop through uSimSensors.

mod common;

use common::*;

/// The time of the first post of `var` with value `val`.
fn first_post(log: &alog::Alog, var: &str, val: &str) -> f64 {
    log.entries
        .iter()
        .find(|e| e.var == var && e.value.as_str() == Some(val))
        .map(|e| e.time)
        .unwrap_or_else(|| panic!("{var} = {val} never posted"))
}

/// `(time, value)` of every numeric record of `var`.
fn series(log: &alog::Alog, var: &str) -> Vec<(f64, f64)> {
    log.entries
        .iter()
        .filter(|e| e.var == var)
        .filter_map(|e| Some((e.time, e.value.as_f64()?)))
        .collect()
}

/// The last value of a series at or before `t`.
fn at(s: &[(f64, f64)], t: f64) -> Option<f64> {
    let i = s.partition_point(|p| p.0 <= t);
    (i > 0).then(|| s[i - 1].1)
}

fn angle180(a: f64) -> f64 {
    (a + 180.0).rem_euclid(360.0) - 180.0
}

fn rms(v: &[f64]) -> f64 {
    (v.iter().map(|x| x * x).sum::<f64>() / v.len() as f64).sqrt()
}

#[test]
fn couguv_sim_completes_its_survey_with_the_cascade_in_the_loop() {
    let mission = project_mission("cougUV/cougUV.moos");
    let opts = deploy_until("MISSION = complete", 900.0);
    let (a, stdout) = run_lockstep("run-couguv-1", &mission, &[], opts.clone());
    let (b, _) = run_lockstep("run-couguv-1", &mission, &[], opts);
    assert!(a == b, "two lockstep runs of cougUV wrote different alogs");
    assert!(
        stdout.contains("completed:   gps_wait, leg1, up1, leg2, home"),
        "{stdout}"
    );
    let log = parse(&a);

    // Who posts what: the loop is closed through the CoUGARs controls and the CougUV model,
    // not the marine PID and uSimMarine.
    let source = |var: &str| {
        log.entries
            .iter()
            .find(|e| e.var == var)
            .map(|e| e.source.clone())
            .unwrap_or_else(|| panic!("{var} never posted"))
    };
    for v in [
        "FIN_TOP_DEG",
        "FIN_STBD_DEG",
        "FIN_PORT_DEG",
        "THRUST_PCT",
        "FIN_DEFLECT_PORT_DEG",
    ] {
        assert_eq!(source(v), "pCougControls", "{v}");
    }
    assert_eq!(source("SIM_DEPTH"), "uSimCougUV");
    assert_eq!(source("NAV_DEPTH"), "pNavGraph");
    assert_eq!(source("DESIRED_DEPTH"), "pHelmIvP");
    assert!(!log.entries.iter().any(|e| e.var == "DESIRED_RUDDER"));
    // Not armed before the deploy; active once the helm and the navigator are up.
    let states: Vec<&str> = log
        .entries
        .iter()
        .filter(|e| e.var == "COUG_CONTROLS_STATE")
        .filter_map(|e| e.value.as_str())
        .collect();
    assert_eq!(states.first(), Some(&"disarmed"), "{states:?}");
    assert!(states.contains(&"active"), "{states:?}");

    let depth = series(&log, "SIM_DEPTH");
    let desired_depth = series(&log, "DESIRED_DEPTH");
    let heading = series(&log, "SIM_HEADING");
    let desired_heading = series(&log, "DESIRED_HEADING");
    let fix = series(&log, "GPS_X");
    let legs = [
        (
            first_post(&log, "GPS_WAIT_DONE", "true"),
            first_post(&log, "LEG1_DONE", "true"),
        ),
        (
            first_post(&log, "UP1_DONE", "true"),
            first_post(&log, "LEG2_DONE", "true"),
        ),
    ];
    let up = (legs[0].1, legs[1].0);

    // Depth tracking at depth (3 m), after 60 s of each leg for the dive: RMS and worst.
    let mut depth_err = Vec::new();
    for &(t0, t1) in &legs {
        for &(t, d) in depth.iter().filter(|p| p.0 > t0 + 60.0 && p.0 < t1) {
            let want = at(&desired_depth, t).expect("a desired depth");
            assert_eq!(want, 3.0);
            depth_err.push(d - want);
        }
    }
    assert!(depth_err.len() > 500, "{} samples", depth_err.len());
    let depth_rms = rms(&depth_err);
    let depth_max = depth_err.iter().fold(0.0f64, |m, e| m.max(e.abs()));
    assert!(depth_rms < 0.2, "depth RMS {depth_rms}");
    assert!(depth_max < 0.4, "depth error up to {depth_max}");
    let max_depth = depth.iter().fold(0.0f64, |m, p| m.max(p.1));
    assert!(max_depth < 4.0, "dived to {max_depth} m");

    // Heading tracking on the straight parts once under way: the desired heading steady
    // (within 3°) over the last 15 s. Against the truth, and against the navigator's
    // heading (what the controller sees: the rest is the navigation's error).
    let nav_heading = series(&log, "NAV_HEADING");
    let mut heading_err = Vec::new();
    let mut control_err = Vec::new();
    for &(t, h) in heading.iter().filter(|p| p.0 > legs[0].0 + 15.0) {
        let (Some(now), Some(before)) = (at(&desired_heading, t), at(&desired_heading, t - 15.0))
        else {
            continue;
        };
        let steady = desired_heading
            .iter()
            .filter(|p| p.0 > t - 15.0 && p.0 <= t)
            .all(|p| angle180(p.1 - before).abs() <= 3.0);
        if steady {
            heading_err.push(angle180(h - now));
            control_err.push(angle180(at(&nav_heading, t).expect("NAV_HEADING") - now));
        }
    }
    assert!(heading_err.len() > 500, "{} samples", heading_err.len());
    let heading_rms = rms(&heading_err);
    let control_rms = rms(&control_err);
    assert!(heading_rms < 2.0, "heading RMS {heading_rms}");
    assert!(
        control_rms < 1.0,
        "heading RMS against NAV_HEADING {control_rms}"
    );

    // Up for GPS between the legs: at the surface, with fixes; none at depth.
    let up_depth = depth
        .iter()
        .filter(|p| p.0 > up.0 && p.0 < up.1)
        .fold(f64::MAX, |m, p| m.min(p.1));
    assert!(up_depth < 0.1, "surfaced only to {up_depth} m");
    assert!(
        fix.iter().any(|p| p.0 > up.0 && p.0 < up.1),
        "no GPS fix up"
    );
    assert!(
        !fix.iter()
            .any(|p| p.0 > legs[1].0 + 60.0 && p.0 < legs[1].1),
        "a fix at depth"
    );

    // The points in order (the truth within the slip radius), and home on the surface.
    let x = series(&log, "SIM_X");
    let y = series(&log, "SIM_Y");
    let track: Vec<(f64, f64, f64)> = x.iter().zip(&y).map(|(a, b)| (a.0, a.1, b.1)).collect();
    let points = [
        (0.0, -50.0),
        (40.0, -50.0),
        (40.0, -100.0),
        (80.0, -100.0),
        (80.0, -40.0),
        (40.0, 0.0),
    ];
    visits_in_order(&track, &points, 8.0, 0);
    assert!(depth.last().unwrap().1 < 0.2);
    eprintln!(
        "cougUV: {:.0} s; depth error at 3 m (after 60 s of each leg): RMS {depth_rms:.3} m, \
         max {depth_max:.3} m; heading error on straight legs: RMS {heading_rms:.2}° (against NAV_HEADING \
         {control_rms:.2}°); \
         max depth {max_depth:.2} m",
        log.entries.last().map_or(0.0, |e| e.time)
    );
    check_plots(&a, "run-couguv", true);
    check_committed_png("cougUV");
}
