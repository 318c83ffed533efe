//! The navigation loop closed, in lockstep: the dive and cougUV_survey missions run with the
//! helm and the PID on pNavGraph's estimate (the simulator's truth under `SIM_*`), complete,
//! and navigate better than dead reckoning. The figures are printed (`--nocapture`) for the
//! closing notes; `coug nav` replays the survey's log to the same figures.

mod common;

use common::*;
use runtime::navreplay::{Figures, live, truth};

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
    let truth = truth(&log);
    let figures = Figures::of(&live(&log, "DR"), &truth);
    eprintln!("{name} (live, helm on the estimate):\n{}", figures.report());
    (bytes, log, figures)
}

/// The navigator beats dead reckoning at every resurfacing, and after the first dive's fix
/// it stays within two sigma of the GPS noise.
fn check_figures(name: &str, f: &Figures, min_dives: usize, gps_noise: f64) {
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
        after.max_m < 2.0 * gps_noise,
        "{name}: after the first fix, max error {} m (GPS noise {gps_noise} m)",
        after.max_m
    );
}

#[test]
fn dive_navigates_on_the_estimate() {
    let (_, _, f) = run_on_estimate("run-nav-dive", "dive/dive.moos", 1200.0);
    check_figures("dive", &f, 2, 1.5);
}

#[test]
fn couguv_survey_estimates_the_compass_bias_and_beats_dead_reckoning() {
    let (bytes, log, f) =
        run_on_estimate("run-nav-cougUV", "cougUV_survey/cougUV_survey.moos", 2400.0);
    check_figures("cougUV_survey", &f, 5, 1.5);
    let end = log.entries.last().unwrap().time;
    assert!((1500.0..2400.0).contains(&end), "about 30 minutes: {end} s");
    let d = series(&log, "SIM_DEPTH");
    let deep: Vec<f64> = d.iter().filter(|p| p.1 > 2.0).map(|p| p.1).collect();
    let mean = deep.iter().sum::<f64>() / deep.len() as f64;
    assert!((3.0..=5.0).contains(&mean), "mean survey depth {mean} m");

    // The 3 degree compass bias, after the first surfacing's fixes.
    let first_fix = f.dives[0].fix_t_s;
    let bias = series(&log, "NAV_HEADING_BIAS");
    let after: Vec<f64> = bias
        .iter()
        .filter(|p| p.0 > first_fix)
        .map(|p| p.1)
        .collect();
    let worst = after.iter().map(|b| (b - 3.0).abs()).fold(0.0, f64::max);
    let cx = series(&log, "NAV_CURRENT_X");
    let cy = series(&log, "NAV_CURRENT_Y");
    eprintln!(
        "cougUV_survey: heading bias after the first fix {:.3}..{:.3} deg (worst error {worst:.3}); \
         current at the end ({:.4}, {:.4}) m/s (truth 0.1 east)",
        after.iter().copied().fold(f64::INFINITY, f64::min),
        after.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        cx.last().unwrap().1,
        cy.last().unwrap().1
    );
    assert!(
        !after.is_empty() && worst < 0.5,
        "heading bias off by {worst} deg"
    );

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
    check_figures("cougUV_survey replay", &rf, 5, 1.5);
}
