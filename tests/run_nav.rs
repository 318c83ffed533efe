//! The navigation loop closed, in lockstep: the dive and cougUV_survey missions run with the
//! helm and the PID on pNavGraph's estimate (the simulator's truth under `SIM_*`), complete,
//! and navigate better than dead reckoning. The figures are printed (`--nocapture`) for the
//! closing notes; `coug nav` replays the survey's log to the same figures.

mod common;

use common::*;
use runtime::navreplay::{Figures, Navigation, Point, errors, live, truth};

/// Every `var` value of the log, with its time.
fn series(log: &alog::Alog, var: &str) -> Vec<(f64, f64)> {
    log.entries
        .iter()
        .filter(|e| e.var == var)
        .filter_map(|e| Some((e.time, e.value.as_f64()?)))
        .collect()
}

/// Runs `mission`, checks the helm ran on the navigator and returns the log, the figures of
/// the live navigation, printed.
fn run_on_estimate(name: &str, mission: &str, max_time: f64) -> (Vec<u8>, alog::Alog, Figures) {
    let mission = project_mission(mission);
    let (bytes, stdout) = run_lockstep(
        name,
        &mission,
        &[],
        deploy_until("MISSION = complete", max_time),
    );
    assert!(stdout.contains("MISSION = \"complete\""), "{stdout}");
    let log = parse(&bytes);
    // NAV_* is the navigator's alone; the truth is the simulator's.
    for e in log.entries.iter().filter(|e| e.var == "NAV_X") {
        assert_eq!(e.source, "pNavGraph", "NAV_X at {}", e.time);
    }
    assert!(
        log.entries
            .iter()
            .any(|e| e.var == "SIM_X" && e.source == "uSimMarineV22")
    );
    let first_nav = log
        .entries
        .iter()
        .find(|e| e.var.starts_with("NAV_") && e.var != "NAV_STATUS");
    let first_fix = log
        .entries
        .iter()
        .find(|e| e.var == "GPS_FIX" && e.value.as_f64() == Some(1.0))
        .expect("a GPS fix");
    assert!(
        first_nav.expect("the navigator posts").time >= first_fix.time,
        "NAV_* before the first fix"
    );
    // The status is in the log (the missions omit only the apps' own P*/U*_STATUS): it
    // says why before the first estimate, then `ok`.
    let status: Vec<(f64, String)> = log
        .entries
        .iter()
        .filter(|e| e.var == "NAV_STATUS")
        .map(|e| (e.time, e.value.to_string()))
        .collect();
    assert!(
        status
            .first()
            .is_some_and(|s| s.1.starts_with("initialising: ")),
        "{status:?}"
    );
    let first_ok = status
        .iter()
        .find(|s| s.1 == "ok")
        .expect("NAV_STATUS = ok");
    assert!(first_ok.0 <= first_nav.unwrap().time + 1.0, "{status:?}");
    check_pitch_loop(name, &log);
    let truth = truth(&log);
    let figures = Figures::of(&live(&log, "DR"), &truth);
    eprintln!("{name} (live, helm on the estimate):\n{}", figures.report());
    (bytes, log, figures)
}

/// The depth loop on the estimate holds its pitch: no limit cycle between full elevators
/// (with a derivative on the lagged NAV_PITCH the pitch swung by 7 to 19 degrees), measured
/// as the pitch's spread while the vehicle holds its depth (under 1.5 m/s of speed change,
/// deeper than 2 m, desired depth steady).
fn check_pitch_loop(name: &str, log: &alog::Alog) {
    let pitch = series(log, "SIM_PITCH");
    let depth = series(log, "SIM_DEPTH");
    let desired = series(log, "DESIRED_DEPTH");
    let at = |s: &[(f64, f64)], t: f64| -> Option<f64> {
        let i = s.partition_point(|p| p.0 <= t);
        (i > 0).then(|| s[i - 1].1)
    };
    let held: Vec<f64> = pitch
        .iter()
        .filter(|(t, _)| {
            let (Some(d), Some(want)) = (at(&depth, *t), at(&desired, *t)) else {
                return false;
            };
            want > 2.0 && (d - want).abs() < 0.5 && at(&desired, t - 10.0) == Some(want)
        })
        .map(|p| p.1.to_degrees())
        .collect();
    assert!(held.len() > 200, "{name}: {} samples at depth", held.len());
    let mean = held.iter().sum::<f64>() / held.len() as f64;
    let sd = (held.iter().map(|p| (p - mean).powi(2)).sum::<f64>() / held.len() as f64).sqrt();
    eprintln!(
        "{name}: pitch at depth: mean {mean:.2} deg, sd {sd:.2} deg ({} samples)",
        held.len()
    );
    assert!(sd < 2.0, "{name}: pitch limit cycle, sd {sd} deg");
}

/// The navigator beats dead reckoning at every resurfacing; after the first dive's fix its
/// RMSE is within two sigma of the GPS noise, and so is its largest error (`max_after`
/// false: only its error at the resurfacings from the third dive on, see the survey's test).
fn check_figures(name: &str, f: &Figures, min_dives: usize, gps_noise: f64, max_after: bool) {
    assert!(
        f.dives.len() >= min_dives,
        "{name}: {} dives",
        f.dives.len()
    );
    for d in &f.dives {
        let (e, r) = (
            d.estimate_error_m.unwrap(),
            d.dead_reckoning_error_m.unwrap(),
        );
        assert!(
            e < r,
            "{name}: dive {}: estimate {e} m, dead reckoning {r} m",
            d.report.dive
        );
    }
    assert!(f.estimate.rmse_m < f.dead_reckoning.rmse_m, "{name}");
    let after = &f.estimate_after_first_fix;
    assert!(after.n > 100, "{name}: {after:?}");
    assert!(
        after.rmse_m < 2.0 * gps_noise,
        "{name}: after the first fix, RMSE {} m (GPS noise {gps_noise} m)",
        after.rmse_m
    );
    if max_after {
        assert!(
            after.max_m < 2.0 * gps_noise,
            "{name}: after the first fix, max error {} m (GPS noise {gps_noise} m)",
            after.max_m
        );
    } else {
        for d in f.dives.iter().skip(1) {
            let e = d.estimate_error_m.unwrap();
            assert!(e < 2.0 * gps_noise, "{name}: dive {}: {e} m", d.report.dive);
        }
    }
}

/// The largest error of the estimate from a second after the first resurfacing's fix on
/// (underwater included): once a dive's track has been corrected by GPS, within two sigma
/// of the GPS.
fn check_after_first_surfacing(
    name: &str,
    nav: &Navigation,
    truth: &[Point],
    f: &Figures,
    gps_noise: f64,
) {
    let from = f.dives[0].fix_t_s + 1.0;
    let e = errors(&nav.estimate, truth, from);
    eprintln!("{name}: from a second after the first resurfacing's fix ({from:.1} s): {e:?}");
    assert!(e.n > 100, "{name}: {e:?}");
    assert!(
        e.max_m < 2.0 * gps_noise,
        "{name}: after the first resurfacing, max error {} m (GPS noise {gps_noise} m)",
        e.max_m
    );
}

#[test]
fn dive_navigates_on_the_estimate() {
    let (_, _, f) = run_on_estimate("run-nav-dive", "dive/dive.moos", 1200.0);
    check_figures("dive", &f, 2, 1.5, true);
}

#[test]
fn couguv_survey_estimates_the_compass_bias_and_beats_dead_reckoning() {
    let (bytes, log, f) =
        run_on_estimate("run-nav-cougUV", "cougUV_survey/cougUV_survey.moos", 2400.0);
    // With bottom lock (dive) the error stays within two sigma of the GPS all along; here
    // the DVL tracks the water and the first dive runs on the unknown bias and current (its
    // lanes, out and back, let the first fixes tell the two apart): the bound holds from the
    // first resurfacing on, underwater included.
    check_figures("cougUV_survey", &f, 5, 1.5, false);
    check_after_first_surfacing("cougUV_survey", &live(&log, "DR"), &truth(&log), &f, 1.5);
    let end = log.entries.last().unwrap().time;
    assert!((1500.0..2400.0).contains(&end), "about 30 minutes: {end} s");
    let d = series(&log, "SIM_DEPTH");
    let deep: Vec<f64> = d.iter().filter(|p| p.1 > 2.0).map(|p| p.1).collect();
    let mean = deep.iter().sum::<f64>() / deep.len() as f64;
    assert!((3.0..=5.0).contains(&mean), "mean survey depth {mean} m");

    // The 3 degree compass bias and the 0.1 m/s current east, after the first surfacing
    // (from the next dive on: the estimates move while the surfacing's fixes come in).
    let first_fix = f.dives[0].fix_t_s;
    let next_dive = d
        .iter()
        .find(|p| p.0 > first_fix && p.1 > 1.0)
        .expect("dives again")
        .0;
    let after = |var: &str| -> Vec<f64> {
        series(&log, var)
            .iter()
            .filter(|p| p.0 >= next_dive)
            .map(|p| p.1)
            .collect()
    };
    let worst = |v: &[f64], truth: f64| v.iter().map(|b| (b - truth).abs()).fold(0.0, f64::max);
    let (bias, cx, cy) = (
        after("NAV_HEADING_BIAS"),
        after("NAV_CURRENT_X"),
        after("NAV_CURRENT_Y"),
    );
    let (wb, wx, wy) = (worst(&bias, 3.0), worst(&cx, 0.1), worst(&cy, 0.0));
    eprintln!(
        "cougUV_survey from {next_dive:.1} s (the dive after the first surfacing): heading bias \
         worst error {wb:.3} deg (final {:.3}), current worst error ({wx:.4}, {wy:.4}) m/s \
         (final {:.4}, {:.4}; truth 0.1 east)",
        bias.last().unwrap(),
        cx.last().unwrap(),
        cy.last().unwrap()
    );
    assert!(bias.len() > 1000, "{}", bias.len());
    assert!(wb < 0.5, "heading bias off by {wb} deg");
    assert!(wx < 0.03 && wy < 0.03, "current off by ({wx}, {wy}) m/s");

    // `coug nav` replays the sensors through the same feed: the same navigation.
    let dir = fresh_dir("run-nav-cougUV-replay");
    std::fs::write(dir.join("run.alog"), &bytes).unwrap();
    let o = coug(&dir, &["nav", "run.alog", "-o", "nav.csv"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success(),
        "{text}{}",
        String::from_utf8_lossy(&o.stderr)
    );
    eprintln!("coug nav (replay):\n{text}");
    let csv = std::fs::read_to_string(dir.join("nav.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some(
            "time,x,y,depth,heading,sigma,status,heading_bias,current_x,current_y,dr_x,dr_y,dr_depth"
        )
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert!(rows.len() > 1000 && rows.iter().all(|r| r.len() == 13));
    assert!(
        text.contains(&format!("keyframes: {}", rows.len())),
        "{text}"
    );
    let replay = runtime::navreplay::replay(&log, nav::FeedConfig::default());
    let rf = Figures::of(&replay, &truth(&log));
    assert_eq!(
        rf.report(),
        text.split_once('\n').unwrap().1.split_once('\n').unwrap().1
    );
    assert_eq!(rf.dives.len(), f.dives.len());
    assert!(
        (rf.estimate_after_first_fix.rmse_m - f.estimate_after_first_fix.rmse_m).abs() < 0.1,
        "replay {:?} vs live {:?}",
        rf.estimate_after_first_fix,
        f.estimate_after_first_fix
    );
    check_figures("cougUV_survey replay", &rf, 5, 1.5, false);
    check_after_first_surfacing("cougUV_survey replay", &replay, &truth(&log), &rf, 1.5);
    check_plots(&bytes, "run-nav-cougUV", true);
    check_committed_png("cougUV_survey");
}
