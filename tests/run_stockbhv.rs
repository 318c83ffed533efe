//! The non-contact stock behaviours (issue #18, point 4) in motion: each drives the lockstep
//! test mission `tests/missions/stockbhv` (a surface vehicle at 0,0 heading north) with its
//! own behaviour file, and the alog shows what the behaviour does.

mod common;

use std::path::PathBuf;

use alog::Alog;
use common::*;

fn mission() -> PathBuf {
    let p = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/missions/stockbhv/stockbhv.moos"
    ));
    assert!(p.is_file(), "{} is missing", p.display());
    p
}

/// Runs the mission with behaviour file `bhv` until `until` (at most `max_time` s).
fn run(bhv: &str, until: &str, max_time: f64) -> Alog {
    let macro_ = format!("BHV={bhv}");
    let (bytes, _) = run_lockstep(
        &format!("stockbhv-{bhv}"),
        &mission(),
        &[&macro_],
        deploy_until(until, max_time),
    );
    parse(&bytes)
}

/// `(time, value)` of every numeric post of `var`.
fn nums(log: &Alog, var: &str) -> Vec<(f64, f64)> {
    log.entries
        .iter()
        .filter(|e| e.var == var)
        .filter_map(|e| Some((e.time, e.value.as_f64()?)))
        .collect()
}

/// Every string post of `var`, in order.
fn texts(log: &Alog, var: &str) -> Vec<(f64, String)> {
    log.entries
        .iter()
        .filter(|e| e.var == var)
        .filter_map(|e| Some((e.time, e.value.as_str()?.to_string())))
        .collect()
}

#[test]
fn max_speed_caps_the_speed_a_waypoint_asks_for() {
    let log = run("max_speed.bhv", "NAV_Y > 60", 200.0);
    let desired = nums(&log, "DESIRED_SPEED");
    assert!(!desired.is_empty());
    // The waypoint asks for 3 m/s; the cap (pwt 200, ramp 0.2 m/s) wins at 1.5 m/s.
    for (t, v) in &desired {
        assert!(*v <= 1.5 + 1e-9, "DESIRED_SPEED {v} at {t}");
    }
    assert!(desired.iter().any(|(_, v)| (*v - 1.5).abs() < 1e-9));
    let speeds = nums(&log, "NAV_SPEED");
    let top = speeds.iter().map(|p| p.1).fold(0.0, f64::max);
    assert!(top < 1.6 && top > 1.3, "top speed {top}");
    // The slack variable: max_speed - NAV_SPEED, settling near 0.
    let slack = nums(&log, "SPEED_SLACK");
    assert!(slack.last().unwrap().1.abs() < 0.1, "{slack:?}");
}

/// The `pts={x1,y1:x2,y2}` of a two-point seglist spec.
fn two_points(spec: &str) -> ((f64, f64), (f64, f64)) {
    let inner = spec
        .strip_prefix("pts={")
        .and_then(|s| s.split('}').next())
        .unwrap_or_else(|| panic!("no points in {spec}"));
    let pts: Vec<(f64, f64)> = inner
        .split(':')
        .map(|p| {
            let (x, y) = p.split_once(',').unwrap();
            (x.parse().unwrap(), y.parse().unwrap())
        })
        .collect();
    assert_eq!(pts.len(), 2, "{spec}");
    (pts[0], pts[1])
}

#[test]
fn hsline_and_bearing_line_draw_what_the_vehicle_does() {
    let log = run("lines.bhv", "ARRIVED = true", 300.0);
    let hsl: Vec<(f64, String)> = texts(&log, "VIEW_SEGLIST")
        .into_iter()
        .filter(|(_, s)| s.ends_with("label=abe_hsl"))
        .collect();
    let bng: Vec<(f64, String)> = texts(&log, "VIEW_SEGLIST")
        .into_iter()
        .filter(|(_, s)| s.ends_with("label=abe_bng"))
        .collect();
    assert!(
        hsl.len() > 20 && bng.len() > 20,
        "{} {}",
        hsl.len(),
        bng.len()
    );
    // Each HSLine segment starts at the vehicle and runs along the helm's previous
    // DESIRED_HEADING: mid-run east (first leg) and north (second leg) both appear.
    let mut east = 0;
    let mut north = 0;
    for (_, s) in &hsl {
        assert!(s.contains(",active=true,"), "{s}");
        let ((x1, y1), (x2, y2)) = two_points(s);
        let (dx, dy) = (x2 - x1, y2 - y1);
        if dx > 5.0 && dy.abs() < 0.3 * dx {
            east += 1;
        }
        if dy > 5.0 && dx.abs() < 0.3 * dy {
            north += 1;
        }
        // Never longer than 10 s at the highest desired speed, 2 m/s.
        assert!(dx.hypot(dy) <= 20.0 + 0.15, "{s}");
    }
    assert!(east > 5 && north > 5, "east {east}, north {north}");
    // Each BearingLine segment ends half way from the vehicle to 100,100 (1 decimal).
    for (_, s) in &bng {
        let ((x1, y1), (x2, y2)) = two_points(s);
        assert!((x2 - (x1 + 100.0) / 2.0).abs() < 0.11, "{s}");
        assert!((y2 - (y1 + 100.0) / 2.0).abs() < 0.11, "{s}");
    }
    let pts = texts(&log, "VIEW_POINT");
    assert!(
        pts.iter().any(|(_, s)| s == "x=100,y=100,label=100,100"),
        "{pts:?}"
    );
}

#[test]
fn zigzag_alternates_its_heading_about_the_stem() {
    let log = run("zigzag.bhv", "ZZ_DONE = true", 400.0);
    // Legs end at 1, 2, ... 7 (more than max_zig_legs = 2 x 3 completes it).
    let legs: Vec<f64> = nums(&log, "ZIG_LEGS").into_iter().map(|p| p.1).collect();
    assert_eq!(legs, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
    // Sides: port first, then alternating; the seventh leg's side flag is not posted.
    let sides: Vec<String> = texts(&log, "ZIG_SIDE").into_iter().map(|p| p.1).collect();
    assert_eq!(
        sides,
        ["port", "star", "port", "star", "port", "star", "port"]
    );
    // The helm asks for 330 on port legs and 30 on starboard legs, nothing else.
    let desired: Vec<f64> = nums(&log, "DESIRED_HEADING")
        .into_iter()
        .map(|p| p.1)
        .collect();
    assert!(
        desired.iter().all(|h| *h == 330.0 || *h == 30.0),
        "{desired:?}"
    );
    // The heading reaches within 3 degrees of each in turn, and never swings much past them.
    let headings = nums(&log, "NAV_HEADING");
    let mut reached = Vec::new();
    for (_, h) in &headings {
        let off = if *h > 180.0 { h - 360.0 } else { *h };
        assert!(off.abs() < 45.0, "heading {h}");
        let side = if off <= -27.0 {
            "port"
        } else if off >= 27.0 {
            "star"
        } else {
            continue;
        };
        if reached.last() != Some(&side) {
            reached.push(side);
        }
    }
    assert_eq!(reached.len(), 7, "{reached:?}");
    // Progress along the stem: north, within a few metres of x = 0.
    let tr = track(&log);
    let (_, x_end, y_end) = *tr.last().unwrap();
    assert!(y_end > 30.0 && x_end.abs() < 15.0, "{x_end},{y_end}");
}

/// Runs the mission with `bhv` until `CHECK_END = true`, poked at `end` s.
fn run_to(bhv: &str, end: f64) -> Alog {
    let macro_ = format!("BHV={bhv}");
    let mut opts = deploy_until("CHECK_END = true", end + 30.0);
    opts.pokes = vec![format!("CHECK_END=true@{end}")];
    let (bytes, _) = run_lockstep(&format!("stockbhv-{bhv}"), &mission(), &[&macro_], opts);
    parse(&bytes)
}

/// Times of the helm's postings of `var`.
fn helm_times(log: &Alog, var: &str) -> Vec<f64> {
    log.entries
        .iter()
        .filter(|e| e.var == var && e.source.starts_with("pHelmIvP"))
        .map(|e| e.time)
        .collect()
}

#[test]
fn test_failure_crash_ends_the_helm_when_the_behaviour_completes() {
    let log = run_to("test_crash.bhv", 60.0);
    let iters = helm_times(&log, "IVPHELM_ITER");
    let deployed = helm_times(&log, "DESIRED_SPEED")
        .into_iter()
        .find(|_| true)
        .expect("the helm drives before the failure");
    let last = *iters.last().unwrap();
    // The behaviour runs 10 s from deployment, then the helm aborts: the iteration that
    // completed it publishes nothing (no endflag), and nothing comes after it.
    assert!(
        last > deployed + 9.0 && last < deployed + 11.0,
        "last helm iteration at {last}, deployed at {deployed}"
    );
    assert!(helm_times(&log, "FAILURE_DONE").is_empty());
    assert!(
        log.entries
            .iter()
            .all(|e| !e.source.starts_with("pHelmIvP") || e.time <= last),
        "the helm posted after its crash"
    );
    // The rest of the community goes on: the simulator still posts at 50 s.
    assert!(nums(&log, "NAV_Y").iter().any(|(t, _)| *t > 50.0));
}

#[test]
fn test_failure_burn_hangs_the_helm_three_seconds() {
    let log = run_to("test_burn.bhv", 40.0);
    let iters = helm_times(&log, "IVPHELM_ITER");
    let done = helm_times(&log, "FAILURE_DONE");
    assert_eq!(done.len(), 1, "the endflag comes out once, late");
    let done = done[0];
    // The helm iterates at its AppTick (4 Hz) but once: the iteration that completed the
    // behaviour hangs 3 s, and its postings (the endflag among them) come out when the hang
    // is over. The completed behaviour is then removed, so it never hangs again.
    let gaps: Vec<(f64, f64)> = iters
        .windows(2)
        .filter(|w| w[1] - w[0] > 0.3)
        .map(|w| (w[0], w[1]))
        .collect();
    assert_eq!(gaps.len(), 1, "{gaps:?}");
    let (hung_at, resumed) = gaps[0];
    assert!((resumed - hung_at - 3.25).abs() < 1e-9, "{gaps:?}");
    assert_eq!(done, resumed);
    assert!(iters.last().unwrap() > &35.0);
}

#[test]
fn memory_turn_limit_widens_a_u_turn() {
    let log = run("memory_turn_limit.bhv", "ARRIVED = true", 400.0);
    // Each iteration the helm's course is within the turn range (20 degrees, narrower
    // below 1.5 m/s) of the average heading it posted in the same iteration.
    let avg = nums(&log, "MEM_HDG_AVG");
    let desired = nums(&log, "DESIRED_HEADING");
    assert!(avg.len() > 40, "{}", avg.len());
    let mut checked = 0;
    for (t, a) in &avg {
        if let Some((_, d)) = desired.iter().find(|(td, _)| td == t) {
            let diff = (d - a + 540.0).rem_euclid(360.0) - 180.0;
            // The average is posted rounded to an integer: half a degree of slack.
            assert!(diff.abs() <= 20.5, "at {t}: desired {d}, average {a}");
            checked += 1;
        }
    }
    assert!(checked > 40, "{checked}");
    // The U-turn is wide: the vehicle swings further east or west of its start line than
    // the same waypoint turning freely.
    let widest = |log: &Alog| track(log).iter().map(|p| p.1.abs()).fold(0.0, f64::max);
    let limited = widest(&log);
    let free = widest(&run("u_turn.bhv", "ARRIVED = true", 400.0));
    assert!(limited > 2.0 * free, "limited {limited}, free {free}");
}

#[test]
fn periodic_speed_bursts_every_lazy_period() {
    let log = run_to("periodic_speed.bhv", 95.0);
    let desired = nums(&log, "DESIRED_SPEED");
    let deployed = desired[0].0;
    // 20 s lazy (the waypoint's 1 m/s), 10 s busy (2.5 m/s), from deployment on.
    for (t, v) in &desired {
        let phase = (t - deployed).rem_euclid(30.0);
        // Skip the iterations at the switches.
        if (phase - 20.0).abs() < 0.3 || !(0.3..=29.7).contains(&phase) {
            continue;
        }
        let want = if phase < 20.0 { 1.0 } else { 2.5 };
        assert!((v - want).abs() < 1e-9, "at {t} (phase {phase}): {v}");
    }
    // The busy count and the constructor's active/inactive flags (the inactive flag only
    // when an active period ends).
    let counts: Vec<f64> = nums(&log, "PS_BUSY_COUNT")
        .into_iter()
        .map(|p| p.1)
        .collect();
    assert_eq!(counts, [0.0, 1.0, 2.0, 3.0]);
    let flags: Vec<f64> = nums(&log, "PERIODIC_SPEED")
        .into_iter()
        .map(|p| p.1)
        .collect();
    assert_eq!(flags, [1.0, 0.0, 1.0, 0.0, 1.0, 0.0]);
}

#[test]
fn fixed_turn_flies_a_full_circle_and_reports_its_radius() {
    let log = run("fixed_turn.bhv", "TURNED > 0", 300.0);
    let report = texts(&log, "FT_REPORT");
    assert_eq!(report.len(), 1, "{report:?}");
    let (t_done, report) = &report[0];
    let field = |k: &str| -> f64 {
        report
            .split(',')
            .find_map(|kv| kv.strip_prefix(k)?.strip_prefix('='))
            .unwrap_or_else(|| panic!("{k} in {report}"))
            .parse()
            .unwrap()
    };
    assert_eq!(field("spd"), 1.5);
    assert_eq!(field("mod_hdg"), 30.0);
    let (avg, min, max) = (field("avg_rad"), field("min_rad"), field("max_rad"));
    assert!(min <= avg && avg <= max && min > 1.0, "{report}");
    // The endflag carries the turn's duration.
    let turned = nums(&log, "TURNED");
    assert_eq!(turned.len(), 1);
    let diam = texts(&log, "VIEW_SEGLIST")
        .into_iter()
        .filter(|(_, s)| s.contains("label=abeft"))
        .count();
    assert!(diam > 10, "{diam} diameters drawn");
    // The heading went all the way round, clockwise.
    let hdg = nums(&log, "NAV_HEADING");
    let mut turned_deg = 0.0;
    for w in hdg.windows(2).filter(|w| w[1].0 <= *t_done) {
        let d = (w[1].1 - w[0].1 + 540.0).rem_euclid(360.0) - 180.0;
        turned_deg += d;
    }
    assert!(turned_deg >= 355.0, "turned {turned_deg}");
}

#[test]
fn waypoint_with_ipf_type_roc_reaches_its_points() {
    let log = run("waypoint_roc.bhv", "ARRIVED = true", 400.0);
    let xs = nums(&log, "NAV_X");
    let ys = nums(&log, "NAV_Y");
    assert!(xs.len() > 100 && xs.len() == ys.len());
    // Each point is passed within the capture radius (5 m), or the slip radius (10 m) and
    // moving away, as the waypoint engine counts it: the closest approach to each.
    for (px, py) in [(0.0, 80.0), (60.0, 140.0), (0.0, 200.0)] {
        let closest = xs
            .iter()
            .zip(&ys)
            .map(|(x, y)| (x.1 - px).hypot(y.1 - py))
            .fold(f64::INFINITY, f64::min);
        assert!(closest <= 10.0, "closest to {px},{py}: {closest:.1} m");
    }
    let hits: Vec<f64> = nums(&log, "WPT_INDEX").into_iter().map(|p| p.1).collect();
    assert_eq!(hits, [0.0, 1.0, 2.0], "the index moves through the points");
    assert_eq!(texts(&log, "ARRIVED").len(), 1);
    // The rate-of-closure function's best speed is the desired 2 m/s once under way.
    let speeds = nums(&log, "DESIRED_SPEED");
    let late: Vec<f64> = speeds.iter().filter(|p| p.0 > 20.0).map(|p| p.1).collect();
    let mean = late.iter().sum::<f64>() / late.len() as f64;
    assert!((mean - 2.0).abs() < 0.25, "mean desired speed {mean}");
}
