//! BHV_LegRun and BHV_PModelView in motion (issue #18, point 4): the lockstep test mission
//! `tests/missions/stockbhv` with `legrun.bhv` (one lap of a leg with Williamson turns) and
//! `pmodel_view.bhv`, and the corpus mission `x1_legs`, which pHelmIvP refuses as written
//! (two parameters its BHV_LegRun does not know) and which runs once those two lines are
//! left out.

mod common;

use std::path::PathBuf;

use alog::Alog;
use common::*;

fn texts(log: &Alog, var: &str) -> Vec<(f64, String)> {
    log.entries
        .iter()
        .filter(|e| e.var == var)
        .filter_map(|e| Some((e.time, e.value.as_str()?.to_string())))
        .collect()
}

#[test]
fn legrun_runs_a_lap_with_its_turns() {
    let mission = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/missions/stockbhv/stockbhv.moos"
    ));
    let (bytes, _) = run_lockstep(
        "stockbhv-legrun",
        &mission,
        &["BHV=legrun.bhv"],
        deploy_until("LAP_DONE = true", 600.0),
    );
    let log = parse(&bytes);
    let modes: Vec<String> = texts(&log, "LR_MODE").into_iter().map(|m| m.1).collect();
    assert_eq!(modes, ["init", "leg1", "turn1", "leg2", "turn2", "leg1"]);
    // Leg 1 north to p1 (0,150); the port turn there (start heading 0): a swing to starboard
    // around (20,150), the loop around (0, 150 + 34.6) of radius 20, back in around (-20,150),
    // so the track reaches about y = 204.6 and x = +-20 before heading south.
    let t = track(&log);
    let top = t.iter().map(|p| p.2).fold(f64::MIN, f64::max);
    assert!((190.0..215.0).contains(&top), "northmost {top}");
    let west = t.iter().map(|p| p.1).fold(f64::MAX, f64::min);
    let east = t.iter().map(|p| p.1).fold(f64::MIN, f64::max);
    assert!(west < -10.0 && east > 10.0, "x from {west} to {east}");
    // The second turn below p2 (0,30): the loop around (0, 30 - 34.6).
    let bottom = t.iter().map(|p| p.2).fold(f64::MAX, f64::min);
    assert!((-40.0..-15.0).contains(&bottom), "southmost {bottom}");
    // The flags, with their macros expanded.
    // (`$[LEG_ID]` alone posts a number: the legs finished before this one.)
    let legs: Vec<f64> = log
        .entries
        .iter()
        .filter(|e| e.var == "LEG_END")
        .filter_map(|e| e.value.as_f64())
        .collect();
    assert_eq!(legs, [0.0, 1.0]);
    let mid: Vec<String> = texts(&log, "MID_LEG").into_iter().map(|v| v.1).collect();
    assert_eq!(mid, ["leg1", "leg2"]);
    assert_eq!(texts(&log, "TURN1_DONE").len(), 1);
    // One leg cycle completes the legs engine (repeat = 0): the endflag, perpetual.
    assert!(log.entries.iter().any(|e| e.var == "LEGS_DONE"));
    // The turn and the leg points are drawn.
    assert!(
        texts(&log, "VIEW_SEGLIST")
            .iter()
            .any(|(_, s)| s.contains("label=abe_turn"))
    );
    assert!(
        texts(&log, "VIEW_POINT")
            .iter()
            .any(|(_, s)| s.contains("label=abe_p1"))
    );
}

#[test]
fn x1_legs_is_refused_as_phelmivp_refuses_it_and_runs_without_its_two_unknown_lines() {
    // As written: BHV_LegRun at a2a9b716 knows neither `legflag` nor `mid_pct`, so pHelmIvP's
    // populator refuses the file (MALCONFIG); coug names exactly those two lines, and no
    // unknown behaviour type.
    let moos = test_support::mission_file("x1_legs/alpha.moos");
    let loaded = runtime::session::load(&moos, &[], &[]).expect("x1_legs loads");
    let checked = runtime::session::validate(&loaded);
    let reasons: Vec<&String> = checked.malconfig.iter().flat_map(|(_, r)| r).collect();
    assert_eq!(reasons.len(), 2, "{reasons:?}");
    assert!(reasons[0].contains("Line 43: legflag"), "{}", reasons[0]);
    assert!(reasons[1].contains("Line 52: mid_pct"), "{}", reasons[1]);
    assert!(!reasons.iter().any(|r| r.contains("type")), "{reasons:?}");
    // Without those two lines the mission runs: the legs, the turns, then (repeat = 1, two
    // cycles) the endflag RETURN = true and the return waypoint.
    let dir = fresh_dir("x1_legs-copy");
    let src = moos.parent().unwrap();
    std::fs::copy(src.join("alpha.moos"), dir.join("alpha.moos")).unwrap();
    let bhv = std::fs::read_to_string(src.join("alpha.bhv")).unwrap();
    let kept: Vec<&str> = bhv
        .lines()
        .filter(|l| {
            let t = l.trim_start();
            !t.starts_with("legflag") && !t.starts_with("mid_pct")
        })
        .collect();
    assert_eq!(kept.len() + 2, bhv.lines().count());
    std::fs::write(dir.join("alpha.bhv"), kept.join("\n")).unwrap();
    let (bytes, _) = run_lockstep(
        "x1_legs-run",
        &dir.join("alpha.moos"),
        &[],
        deploy_until("RETURN = true", 900.0),
    );
    let log = parse(&bytes);
    let modes: Vec<String> = texts(&log, "LR_MODE").into_iter().map(|m| m.1).collect();
    assert_eq!(
        &modes[..6],
        ["init", "leg1", "turn1", "leg2", "turn2", "leg1"],
        "{modes:?}"
    );
    // Two cycles of the leg (repeat = 1) before the endflags.
    assert_eq!(
        modes.iter().filter(|m| *m == "turn2").count(),
        2,
        "{modes:?}"
    );
    // The endflag's counter macro: `$[CTR2]` counts its own expansions.
    assert_eq!(
        texts(&log, "EFLAG").last().map(|v| v.1.as_str()),
        Some("endings=1")
    );
    // The vehicle reaches both ends of the leg, vx1 (70,-35) and vx2 (-35,-85).
    let t = track(&log);
    visits_in_order(&t, &[(70.0, -35.0), (-35.0, -85.0), (70.0, -35.0)], 6.0, 0);
}

#[test]
fn pmodel_view_draws_the_desired_heading_while_running() {
    let mission = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/missions/stockbhv/stockbhv.moos"
    ));
    // Ten seconds past the arrival, so the erasure is in the log.
    let mut opts = deploy_until("CHECK_END = true", 200.0);
    opts.pokes = vec!["CHECK_END=true@60".into()];
    let (bytes, _) = run_lockstep(
        "stockbhv-pmodel-view",
        &mission,
        &["BHV=pmodel_view.bhv"],
        opts,
    );
    assert!(texts(&parse(&bytes), "ARRIVED").iter().any(|a| a.0 < 55.0));
    let log = parse(&bytes);
    let seglrs = texts(&log, "VIEW_SEGLR");
    // Drawn while the waypoint drives (the helm's DESIRED_SPEED 2, heading 0), from the
    // vehicle's position; erased when its condition fails on arrival.
    let active: Vec<&String> = seglrs
        .iter()
        .map(|s| &s.1)
        .filter(|s| !s.contains("active=false"))
        .collect();
    assert!(active.len() > 20, "{}", active.len());
    assert!(
        active
            .iter()
            .all(|s| s.contains(",ray=0.0,label=abe_seglr,")),
        "{active:?}"
    );
    assert!(
        seglrs
            .last()
            .unwrap()
            .1
            .contains("active=false,label=abe_seglr")
    );
}
