//! Obstacles in lockstep (issue #18, point 4): `missions/obstacles`, a vehicle heading north
//! through three given obstacles (two on its track). pObstacleMgr alerts the helm as each
//! comes within `pwt_outer_dist`, the helm spawns a BHV_AvoidObstacleV24 per obstacle, and
//! the vehicle passes them without entering any; with `AVOID=false` the same transit runs
//! through the first one.

mod common;

use common::*;

/// The obstacles as `missions/obstacles/obstacles.moos` gives them to pObstacleMgr (all
/// axis-aligned rectangles: key, spec, x range, y range).
type Rect = (&'static str, &'static str, (f64, f64), (f64, f64));
const OBSTACLES: [Rect; 3] = [
    (
        "ob_a",
        "pts={-8,52:-8,68:8,68:8,52}, label=ob_a",
        (-8.0, 8.0),
        (52.0, 68.0),
    ),
    (
        "ob_b",
        "pts={-4,130:-4,146:12,146:12,130}, label=ob_b",
        (-4.0, 12.0),
        (130.0, 146.0),
    ),
    (
        "ob_c",
        "pts={40,90:40,100:50,100:50,90}, label=ob_c",
        (40.0, 50.0),
        (90.0, 100.0),
    ),
];

/// The signed distance from `(x, y)` to a rectangle's boundary: negative inside.
fn signed_dist(x: f64, y: f64, (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> f64 {
    let dx = (x0 - x).max(x - x1);
    let dy = (y0 - y).max(y - y1);
    if dx <= 0.0 && dy <= 0.0 {
        dx.max(dy)
    } else {
        dx.max(0.0).hypot(dy.max(0.0))
    }
}

fn obstacles() -> Vec<Rect> {
    let moos = std::fs::read_to_string(project_mission("obstacles/obstacles.moos")).unwrap();
    for (key, spec, _, _) in OBSTACLES {
        assert!(moos.contains(spec), "the mission gives {key} as {spec}");
    }
    OBSTACLES.to_vec()
}

/// For each obstacle, the closest the track came to it (negative: that far inside).
fn closest(log: &alog::Alog) -> Vec<(&'static str, f64)> {
    let t = track(log);
    assert!(t.len() > 100, "a track");
    obstacles()
        .into_iter()
        .map(|(key, _, xs, ys)| {
            let d = t
                .iter()
                .map(|&(_, x, y)| signed_dist(x, y, xs, ys))
                .fold(f64::INFINITY, f64::min);
            (key, d)
        })
        .collect()
}

fn run(name: &str, macros: &[&str]) -> alog::Alog {
    let mission = project_mission("obstacles/obstacles.moos");
    let (bytes, _) = run_lockstep(
        name,
        &mission,
        macros,
        deploy_until("MISSION = complete", 400.0),
    );
    parse(&bytes)
}

fn has(log: &alog::Alog, var: &str, needle: &str) -> bool {
    log.entries
        .iter()
        .any(|e| e.var == var && e.value.as_str().is_some_and(|s| s.contains(needle)))
}

#[test]
fn avoid_obstacle_v24_passes_every_obstacle_without_entering_it() {
    let log = run("obstacles-avoid", &[]);
    let near = closest(&log);
    eprintln!("with BHV_AvoidObstacleV24, closest approach per obstacle: {near:?}");
    for (key, d) in &near {
        assert!(*d > 0.0, "{key}: the track entered it ({d:.2} m)");
    }
    // The two on the track were passed at least min_util_cpa_dist (5 m) off.
    assert!(near[0].1 > 5.0 && near[1].1 > 5.0, "{near:?}");
    // The manager was asked for alerts, alerted the helm, which spawned a behaviour per
    // obstacle on the track; the behaviours completed once past.
    assert!(has(
        &log,
        "OBM_ALERT_REQUEST",
        "name=avd_obs_,update_var=OBSTACLE_ALERT,alert_range=30"
    ));
    assert!(has(
        &log,
        "OBSTACLE_ALERT",
        "name=avd_obs_ob_a#poly=pts={-8,52:-8,68:8,68:8,52},label=ob_a#id=ob_a"
    ));
    for b in ["avd_obs_ob_a", "avd_obs_ob_b"] {
        assert!(
            has(
                &log,
                "IVPHELM_LIFE_EVENT",
                &format!("bname={b}, btype=BHV_AvoidObstacleV24, event=spawn")
            ),
            "{b} spawned"
        );
        assert!(has(&log, "BHV_IPF", b), "{b} built functions");
    }
    assert!(!has(&log, "BHV_ERROR", ""), "no allstop");
    assert!(has(&log, "OBM_DIST_TO_OBJ", "OB_A,"));
}

#[test]
fn without_the_behaviour_the_transit_runs_through_an_obstacle() {
    let log = run("obstacles-none", &["AVOID=false"]);
    let near = closest(&log);
    eprintln!("without: closest approach per obstacle: {near:?}");
    assert!(near[0].1 < 0.0, "the track should cross ob_a: {near:?}");
    assert!(!has(&log, "OBM_ALERT_REQUEST", ""));
}

/// The corpus's s1_alpha_obsavoid in lockstep: BHV_AvoidObstacleV21 spawned from
/// pObstacleMgr's alert for its one given obstacle (x 50..80, y -100..-120, on the first
/// survey leg at x = 60) takes the vehicle round it.
#[test]
fn corpus_s1_alpha_obsavoid_passes_its_obstacle_with_v21() {
    let mission = test_support::mission_file("s1_alpha_obsavoid/alpha.moos");
    let (bytes, _) = run_lockstep(
        "obstacles-obsavoid",
        &mission,
        &[],
        deploy_until("NAV_Y < -140", 200.0),
    );
    let log = parse(&bytes);
    let d = track(&log)
        .iter()
        .map(|&(_, x, y)| signed_dist(x, y, (50.0, 80.0), (-120.0, -100.0)))
        .fold(f64::INFINITY, f64::min);
    eprintln!("s1_alpha_obsavoid: closest approach to its obstacle {d:.2} m");
    // max_util_cpa_dist is 20 there, min_util_cpa_dist 10.
    assert!(d > 10.0, "{d}");
    assert!(has(
        &log,
        "IVPHELM_LIFE_EVENT",
        "bname=avd_obsone, btype=BHV_AvoidObstacleV21, event=spawn"
    ));
    assert!(has(
        &log,
        "OBSTACLE_ALERT",
        "name=avd_obsone#poly=pts={50,-100:50,-120:80,-120:80,-100},label=one#id=one"
    ));
}

/// `coug check` on the corpus's obstacle missions reports nothing about pObstacleMgr or the
/// obstacle behaviours but what MOOS-IvP would refuse too: s1_alpha_obsavoid is clean;
/// s1_alpha_obstaclemgr's one error is its uTimerScript's gaussian `rand_var`;
/// m2_berta_obstacles (checked with the macros its launch script gives) gives
/// BHV_AvoidObstacleV24 a `buffer_dist`, which V24 does not take (the C++ `setParam` returns
/// false for it too), and its helm names the `targ_` file the launch script writes.
#[test]
fn corpus_obstacle_missions_check_as_moos_ivp_would() {
    let corpus = test_support::corpus("moos-ivp-missions");
    let check = |args: &[&str]| {
        let out = coug(&corpus, args);
        let text = format!(
            "{}{}",
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        (out.status.code(), text)
    };
    let (code, text) = check(&[
        "check",
        "s1_alpha_obsavoid/alpha.moos",
        "s1_alpha_obsavoid/alpha.bhv",
    ]);
    assert_eq!(code, Some(0), "{text}");
    assert!(!text.contains("error"), "{text}");
    assert!(!text.contains("pObstacleMgr"), "{text}");
    let (_, text) = check(&[
        "check",
        "s1_alpha_obstaclemgr/alpha.moos",
        "s1_alpha_obstaclemgr/alpha.bhv",
    ]);
    let errors: Vec<&str> = text.lines().filter(|l| l.contains("error")).collect();
    assert_eq!(errors.len(), 1, "{text}");
    assert!(
        errors[0].contains("uTimerScript: rand_var type \"gaussian\""),
        "{text}"
    );
    assert!(
        !text.contains("pObstacleMgr") && !text.contains("AvoidObstacle"),
        "{text}"
    );
    let (code, text) = check(&[
        "check",
        "m2_berta_obstacles/meta_vehicle.moos",
        "m2_berta_obstacles/meta_vehicle.bhv",
        "VNAME=abe",
        "START_POS=0,0",
        "LOITER_POS=x=0,y=-75",
        "BOT_MOOSDB=9001",
        "BOT_PSHARE=9201",
        "SHORE_PSHARE=9200",
        "WARP=1",
    ]);
    assert_eq!(code, Some(1), "{text}");
    let bhv_errors: Vec<&str> = text
        .lines()
        .filter(|l| l.contains("meta_vehicle.bhv") && l.contains("error"))
        .collect();
    assert_eq!(bhv_errors.len(), 1, "{text}");
    assert!(
        bhv_errors[0].contains("unknown parameter `buffer_dist` for BHV_AvoidObstacleV24"),
        "{text}"
    );
    assert!(!text.contains("pObstacleMgr"), "{text}");
}

/// BHV_AvoidObstacleV24 on the helm's Dubins platform model (`pmgen`, 10 m turns): each
/// heading judged by the closest approach of the model's turn to it; the transit still
/// passes the obstacles on its track at least `min_util_cpa_dist` (5 m) off.
#[test]
fn avoid_obstacle_v24_on_the_dubins_platform_model() {
    let log = run(
        "obstacles-avoid-dubins",
        &["PMGEN=alg=dubins#radius=10#spoke_degs=10"],
    );
    let near = closest(&log);
    eprintln!("with BHV_AvoidObstacleV24 on Dubins turns, closest approach per obstacle: {near:?}");
    for (key, d) in &near {
        assert!(*d > 0.0, "{key}: the track entered it ({d:.2} m)");
    }
    assert!(near[0].1 > 5.0 && near[1].1 > 5.0, "{near:?}");
    assert!(has(&log, "BHV_IPF", "avd_obs_ob_a"));
    assert!(!has(&log, "BHV_ERROR", ""), "no allstop");
}
