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
/// obstacle behaviours but what MOOS-IvP would refuse too: s1_alpha_obsavoid and
/// s1_alpha_obstaclemgr (its uTimerScript's gaussian `rand_var`s included) are clean;
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
    let (code, text) = check(&[
        "check",
        "s1_alpha_obstaclemgr/alpha.moos",
        "s1_alpha_obstaclemgr/alpha.bhv",
    ]);
    assert_eq!(code, Some(0), "{text}");
    assert!(!text.contains("error"), "{text}");
    assert!(
        !text.contains("pObstacleMgr")
            && !text.contains("AvoidObstacle")
            && !text.contains("uTimerScript"),
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

/// The vertices of a `pts={x,y:x,y:...}` spec.
fn pts_of(spec: &str) -> Vec<(f64, f64)> {
    let Some(start) = spec.find("pts={") else {
        return Vec::new();
    };
    let body = &spec[start + 5..];
    let body = &body[..body.find('}').unwrap_or(body.len())];
    body.split(':')
        .filter_map(|p| {
            let mut it = p.split(',');
            Some((it.next()?.parse().ok()?, it.next()?.parse().ok()?))
        })
        .collect()
}

/// The signed distance from `(x, y)` to a convex polygon's boundary: negative inside.
fn poly_dist(x: f64, y: f64, poly: &[(f64, f64)]) -> f64 {
    let n = poly.len();
    let mut d = f64::INFINITY;
    let mut inside = n >= 3;
    let mut sign = 0.0;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len2 = dx * dx + dy * dy;
        let t = if len2 > 0.0 {
            (((x - a.0) * dx + (y - a.1) * dy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        d = d.min((x - a.0 - t * dx).hypot(y - a.1 - t * dy));
        let cross = dx * (y - a.1) - dy * (x - a.0);
        if cross != 0.0 {
            if sign == 0.0 {
                sign = cross.signum();
            } else if cross.signum() != sign {
                inside = false;
            }
        }
    }
    if inside { -d } else { d }
}

/// The corpus's s1_alpha_obstaclemgr in lockstep: uTimerScript's gaussian `rand_var`s
/// scatter `TRACKED_FEATURE` points around five spots beside the survey, pObstacleMgr lassos
/// each cluster into an obstacle polygon (`VIEW_POLYGON` `obmgr_<key>`) and alerts the helm
/// as each comes within 19 m. The mission's template is the old BHV_AvoidObstacle, which has
/// no `id` parameter: pObstacleMgr's alerts end `#id=<key>`, so every spawn is aborted, in
/// MOOS-IvP at a2a9b716 (`BehaviorSet::handlePossibleSpawnings`, `setParam("id")` false) as
/// here, and the survey runs through the two obstacles on its first leg (`c` and `e`) as
/// MOOS-IvP's would. The same survey with BHV_AvoidObstacleV24 keeps clear of its obstacles:
/// `sensed_obstacles_*` below.
#[test]
fn corpus_s1_alpha_obstaclemgr_senses_its_obstacles_and_aborts_the_old_behaviours_spawns() {
    let mission = test_support::mission_file("s1_alpha_obstaclemgr/alpha.moos");
    let (bytes, summary) = run_lockstep(
        "obstacles-obstaclemgr",
        &mission,
        &[],
        deploy_until("WPT_INDEX = 4", 600.0),
    );
    let log = parse(&bytes);
    let closest = closest_to_posted_polygons(&log, "obmgr_");
    eprintln!("{summary}\ns1_alpha_obstaclemgr: closest approach per sensed obstacle: {closest:?}");
    // The survey progressed: four of its five points reached, 350 m and more run.
    let t = track(&log);
    let run: f64 = t
        .windows(2)
        .map(|w| (w[1].1 - w[0].1).hypot(w[1].2 - w[0].2))
        .sum();
    assert!(run > 350.0, "{run}");
    // The gaussian points became obstacles (the five spots, all within their min/max).
    for key in ["b", "c", "d", "e"] {
        assert!(closest.contains_key(key), "obstacle {key}: {closest:?}");
    }
    assert!(has(&log, "TRACKED_FEATURE", "label=c,color=3,size=2"));
    // The manager alerted the helm; the old behaviour refuses `id`, so no spawn took.
    assert!(has(
        &log,
        "OBSTACLE_ALERT",
        "name=avoid_obstacle_c#poly=pts={"
    ));
    assert!(has(
        &log,
        "IVPHELM_LIFE_EVENT",
        "bname=avoid_obstacle_c, btype=BHV_AvoidObstacle, event=abort"
    ));
    assert!(!has(
        &log,
        "IVPHELM_LIFE_EVENT",
        "btype=BHV_AvoidObstacle, event=spawn"
    ));
    // So nothing steers round the obstacles on the first leg (x = 60): the track enters one.
    assert!(closest["c"].min(closest["e"]) < 0.0, "{closest:?}");
}

/// For each obstacle whose `VIEW_POLYGON` label starts with `prefix`, the closest the track
/// came to the polygon it had at that moment (negative: that far inside).
fn closest_to_posted_polygons(
    log: &alog::Alog,
    prefix: &str,
) -> std::collections::BTreeMap<String, f64> {
    let mut polys: std::collections::BTreeMap<String, Vec<(f64, f64)>> = Default::default();
    let (mut x, mut y) = (None, None);
    let mut closest: std::collections::BTreeMap<String, f64> = Default::default();
    for e in &log.entries {
        match e.var.as_str() {
            "VIEW_POLYGON" => {
                let s = e.value.as_str().unwrap_or("");
                let label = s
                    .split(',')
                    .find_map(|kv| kv.strip_prefix("label="))
                    .and_then(|l| l.strip_prefix(prefix));
                if let Some(l) = label {
                    if s.contains("active=false") {
                        polys.remove(l);
                    } else {
                        polys.insert(l.to_string(), pts_of(s));
                    }
                }
                continue;
            }
            "NAV_X" => x = e.value.as_f64(),
            "NAV_Y" => y = e.value.as_f64(),
            _ => continue,
        }
        if let (Some(x), Some(y)) = (x, y) {
            for (k, p) in &polys {
                let d = poly_dist(x, y, p);
                let c = closest.entry(k.clone()).or_insert(f64::INFINITY);
                *c = c.min(d);
            }
        }
    }
    closest
}

/// The true obstacles of `missions/obstacles/sensed.txt` (label, vertices).
fn sensed_obstacles() -> Vec<(String, Vec<(f64, f64)>)> {
    let text = std::fs::read_to_string(project_mission("obstacles/sensed.txt")).unwrap();
    text.lines()
        .filter_map(|l| l.trim().strip_prefix("poly = "))
        .map(|spec| {
            let label = spec.split(',').find_map(|kv| kv.strip_prefix("label="));
            (label.unwrap().to_string(), pts_of(spec))
        })
        .collect()
}

/// For each true obstacle, the closest the track came to it (negative: inside).
fn closest_to_truth(log: &alog::Alog) -> Vec<(String, f64)> {
    let t = track(log);
    assert!(t.len() > 100, "a track");
    sensed_obstacles()
        .into_iter()
        .map(|(k, p)| {
            let d = t
                .iter()
                .map(|&(_, x, y)| poly_dist(x, y, &p))
                .fold(f64::INFINITY, f64::min);
            (k, d)
        })
        .collect()
}

/// s1_alpha_obstaclemgr's survey with simulated obstacles (`missions/obstacles/sensed.moos`):
/// uFldObstacleSim reads the obstacle file and posts the points the vehicle's 40 m sensor
/// sees of each obstacle (`TRACKED_FEATURE_ALPHA`, from its `NODE_REPORT`), pObstacleMgr
/// hulls them into obstacles and alerts the helm, and the BHV_AvoidObstacleV24 spawned for
/// each keeps the vehicle more than its `min_util_cpa_dist` (5 m) from every true obstacle
/// polygon while the survey completes. The viewer gets the true obstacles, the sensed hulls,
/// the behaviours' buffers and the points.
#[test]
fn sensed_obstacles_from_the_simulator_are_avoided_by_their_spawned_behaviours() {
    let mission = project_mission("obstacles/sensed.moos");
    let (bytes, summary) = run_lockstep(
        "obstacles-sensed",
        &mission,
        &[],
        deploy_until("MISSION = complete", 600.0),
    );
    let log = parse(&bytes);
    let near = closest_to_truth(&log);
    eprintln!("{summary}\nsensed: closest approach per obstacle: {near:?}");
    for (k, d) in &near {
        assert!(*d > 5.0, "{k}: {d:.2} m, min_util_cpa_dist is 5");
    }
    for k in ["ob_0", "ob_1", "ob_2"] {
        assert!(
            has(
                &log,
                "IVPHELM_LIFE_EVENT",
                &format!("bname=avd_obs_{k}, btype=BHV_AvoidObstacleV24, event=spawn")
            ),
            "{k} spawned"
        );
        // The simulator's true obstacle, the manager's hull, the behaviour's buffer.
        assert!(has(
            &log,
            "VIEW_POLYGON",
            &format!(
                "label={k},label_color=invisible,edge_color=white,vertex_color=green,fill_color=invisible"
            )
        ));
        assert!(has(&log, "VIEW_POLYGON", &format!("label=obmgr_{k},")));
        assert!(has(&log, "TRACKED_FEATURE_ALPHA", &format!(",key={k}")));
    }
    assert!(has(
        &log,
        "VIEW_POLYGON",
        "label=obs_region,edge_color=gray50,vertex_color=white"
    ));
    assert!(has(&log, "VIEW_POINT", "label=alpha:ob_0:"));
    assert!(has(
        &log,
        "KNOWN_OBSTACLE",
        "pts={56,-76:64,-76:64,-84:56,-84},label=ob_0"
    ));
    assert!(
        !has(&log, "GIVEN_OBSTACLE", ""),
        "points, not given obstacles"
    );
    assert!(!has(&log, "BHV_ERROR", ""), "no allstop");
}

/// The same survey with `POINTS=false`: the simulator gives the obstacles whole
/// (`GIVEN_OBSTACLE`, no duration: the manager's `given_max_duration` is off), pObstacleMgr
/// takes them as given and alerts the helm. Each obstacle straddles a leg of the survey
/// (x = 60, y = -160): the straight track would cross all three.
#[test]
fn given_obstacles_from_the_simulator_are_avoided_too() {
    let mission = project_mission("obstacles/sensed.moos");
    let (bytes, _) = run_lockstep(
        "obstacles-given",
        &mission,
        &["POINTS=false"],
        deploy_until("MISSION = complete", 600.0),
    );
    let log = parse(&bytes);
    let near = closest_to_truth(&log);
    eprintln!("given: closest approach per obstacle: {near:?}");
    for (k, d) in &near {
        assert!(*d > 5.0, "{k}: {d:.2} m");
    }
    assert!(has(
        &log,
        "GIVEN_OBSTACLE",
        "pts={56,-76:64,-76:64,-84:56,-84},label=ob_0"
    ));
    assert!(!has(&log, "TRACKED_FEATURE_ALPHA", ""));
    assert!(has(
        &log,
        "OBSTACLE_ALERT",
        "name=avd_obs_ob_0#poly=pts={56,-76:64,-76:64,-84:56,-84},label=ob_0#id=ob_0"
    ));
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
