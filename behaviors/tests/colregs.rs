//! BHV_AvdColregsV22 (and V17, V19, V26) against values worked out from MOOS-IvP's formulas
//! (a2a9b716: `BHV_AvdColregsV*`, `AOF_CPA`, `AOF_R13`, `AOF_R14`, `AOF_R16`, `AOF_R17`,
//! `CPXEngineOG`): the objective functions at chosen courses and speeds, the encounter
//! classification on hand-built geometries, the parameter rules, and what each version does
//! differently.

// The C++ bearing rate divides by its own 12-digit pi (`MPI`), written out below.
#![allow(clippy::approx_constant)]

use behaviors::colregs::{
    AofCpa, AofR13, AofR14, AofR16, AofR17, AvdColregs, Cpx, Distances, GiveWaySide, Version,
};
use behaviors::contact::ContactInfo;
use behaviors::cpa::CpaEngine;
use behaviors::testing::Probe;
use behaviors::{Behavior, Common, Ctx, Emit, MapInfo, Out, ParamError, PostKey, Value};
use ivp::Domain;

fn domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
}

/// Ownship at `os = (x, y, heading, speed)`, contact `cn` at `cn` at time `t`.
fn info(t: f64, os: (f64, f64, f64, f64), cn: (f64, f64, f64, f64)) -> MapInfo {
    MapInfo::new(t)
        .num("NAV_X", os.0)
        .num("NAV_Y", os.1)
        .num("NAV_HEADING", os.2)
        .num("NAV_SPEED", os.3)
        .with_contact(
            "cn",
            ContactInfo {
                x_m: cn.0,
                y_m: cn.1,
                heading_deg: cn.2,
                speed_mps: cn.3,
                utc: t,
                vtype: "kayak".into(),
                ..ContactInfo::default()
            },
        )
}

fn ctx<'a>(info: &'a MapInfo, d: &'a Domain) -> Ctx<'a> {
    Ctx {
        info,
        domain: d,
        ownship: "abe",
        name: "avd_cn",
        perpetual: false,
    }
}

fn set(b: &mut AvdColregs, k: &str, v: &str) -> Result<(), ParamError> {
    let d = domain();
    let info = MapInfo::new(0.0);
    b.set_param(k, v, &mut Common::new(b.kind()), &ctx(&info, &d))
}

fn colregs(version: Version, params: &[(&str, &str)]) -> AvdColregs {
    let mut b = AvdColregs::new(version);
    set(&mut b, "contact", "cn").unwrap();
    for (k, v) in params {
        set(&mut b, k, v).unwrap_or_else(|e| panic!("{k} = {v}: {e}"));
    }
    b
}

/// One running iteration at time `t`.
fn run(
    b: &mut AvdColregs,
    t: f64,
    os: (f64, f64, f64, f64),
    cn: (f64, f64, f64, f64),
) -> (Option<ivp::IvpFunction>, Out) {
    let d = domain();
    let inf = info(t, os, cn);
    let mut out = Out::default();
    let f = b.on_run(&ctx(&inf, &d), &mut out);
    (f, out)
}

fn posted<'a>(out: &'a Out, var: &str) -> Option<&'a Value> {
    out.emits.iter().rev().find_map(|e| match e {
        Emit::Post { var: v, value, .. } if v == var => Some(value),
        _ => None,
    })
}

fn text(out: &Out, var: &str) -> Option<String> {
    posted(out, var).and_then(|v| v.as_str().map(str::to_string))
}

fn num(out: &Out, var: &str) -> Option<f64> {
    posted(out, var).and_then(|v| v.as_f64())
}

/// The CPA distance of two straight tracks, worked out with vectors: relative position `p`
/// (contact minus ownship) and relative velocity `v` (contact minus ownship), over `tol` s.
fn cpa(p: (f64, f64), v: (f64, f64), tol: f64) -> f64 {
    let vv = v.0 * v.0 + v.1 * v.1;
    let t = if vv == 0.0 {
        0.0
    } else {
        (-(p.0 * v.0 + p.1 * v.1) / vv).clamp(0.0, tol)
    };
    (p.0 + v.0 * t).hypot(p.1 + v.1 * t)
}

fn vel(h: f64, v: f64) -> (f64, f64) {
    (h.to_radians().sin() * v, h.to_radians().cos() * v)
}

// ---------------------------------------------------------------------------------------
// The pair geometry (CPXEngineOG).

#[test]
fn crossing_geometry_gamma_epsilon_and_bow_crossing_distance() {
    // The contact at (100, 50) heading west at 2 m/s; ownship at the origin heading north
    // at 2 m/s. Ownship is 50 m from the contact's bow-stern line (y = 50) and 100 m from its
    // beam line (x = 100), ahead of it and on its port side.
    let g = Cpx::new(100.0, 50.0, 270.0, 2.0, 0.0, 0.0, 0.0, 2.0);
    assert!((g.range_gam - 50.0).abs() < 1e-9 && (g.range_eps - 100.0).abs() < 1e-9);
    assert!(g.fore && !g.aft && g.port && !g.star);
    // Holding north it reaches y = 50 after 25 s, when the contact is at x = 50: it crosses
    // the bow 50 m ahead of the contact.
    assert!(g.crosses_bow(0.0, 2.0) && !g.crosses_stern(0.0, 2.0));
    assert!((g.crosses_bow_dist(0.0, 2.0) - 50.0).abs() < 1e-9);
    // Heading south it never reaches the line.
    assert!(!g.crosses_bow_or_stern(180.0, 2.0));
    assert_eq!(g.crosses_bow_dist(180.0, 2.0), -1.0);
    // Bearing rate at course 90 (east, straight at the contact's track): the contact's
    // bearing is 63.43°, the tangent 153.43°; ownship's speed along it 2·cos(63.43°) = 0.894
    // (negated), the contact's 2·cos(116.57°) = −0.894: −1.789 m/s · 360 / (2π · 111.8 m).
    let r = 100f64.hypot(50.0);
    let expected =
        -2.0 * 2.0 * (63.434948822922f64).to_radians().cos() * 360.0 / (2.0 * r * 3.14159265359);
    // Course 90 is cached at its whole degree: exact here.
    assert!((g.bearing_rate(90.0, 2.0) - expected).abs() < 1e-9);
}

#[test]
fn passing_sides_when_overtaking() {
    // The contact 50 m ahead (5 m to the right) heading north at 1 m/s; ownship behind it,
    // on its port side, at 2 m/s.
    let g = Cpx::new(5.0, 50.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0);
    assert!(g.aft && !g.fore && g.port && !g.star);
    assert!((g.range_gam - 5.0).abs() < 1e-9 && (g.range_eps - 50.0).abs() < 1e-9);
    // Faster along its heading: it passes; veering left passes the contact's port side.
    assert!(g.passes(350.0, 2.0) && g.passes_port(350.0, 2.0) && !g.passes_star(350.0, 2.0));
    assert!(g.passes_star(10.0, 2.0) && !g.passes_port(10.0, 2.0));
    // Slower: never passes.
    assert!(!g.passes(0.0, 0.5) && !g.passes_port(350.0, 0.5));
    // Port passing distance at course 350: the beam line is reached after 50 / (2 cos 10° − 1)
    // s, ownship then 5 + 2 sin 10° · t to the left of the bow-stern line.
    let t = 50.0 / (2.0 * 10f64.to_radians().cos() - 1.0);
    let side = 5.0 + 2.0 * 10f64.to_radians().sin() * t;
    assert!((g.passes_port_dist(350.0, 2.0) - side).abs() < 1e-6);
    assert_eq!(g.passes_star_dist(350.0, 2.0), -1.0);
    // Dead astern ownship is on both sides of the contact, and the C++ gives the same
    // distance for both.
    let g = Cpx::new(0.0, 50.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0);
    assert!(g.port && g.star && g.range_gam == 0.0);
    let side = 2.0 * 10f64.to_radians().sin() * t;
    assert!((g.passes_port_dist(350.0, 2.0) - side).abs() < 1e-6);
    assert!((g.passes_star_dist(350.0, 2.0) - side).abs() < 1e-6);
}

// ---------------------------------------------------------------------------------------
// The objective functions.

fn distances(cn: (f64, f64, f64, f64), tol: f64, coll: f64, clear: f64) -> Distances {
    let e = CpaEngine::new(cn.0, cn.1, cn.2, cn.3, 0.0, 0.0);
    Distances::new(e, tol, coll, clear).unwrap()
}

#[test]
fn aof_cpa_metric_and_values() {
    // Head-on contact 100 m north heading south at 2 m/s.
    let aof = AofCpa {
        d: distances((0.0, 100.0, 180.0, 2.0), 120.0, 10.0, 75.0),
    };
    assert_eq!(aof.metric(5.0), 0.0);
    assert_eq!(aof.metric(10.0), 25.0);
    assert_eq!(aof.metric(42.5), 62.5);
    assert_eq!(aof.metric(80.0), 100.0);
    // Straight at it: they meet.
    assert_eq!(aof.eval(0.0, 2.0), 0.0);
    // Due east at 2: CPA 50·√2 = 70.71 m, 25 + 75 · 60.71 / 65 = 95.05.
    let d = cpa((0.0, 100.0), (-2.0, -2.0), 120.0);
    assert!((aof.eval(90.0, 2.0) - (25.0 + 75.0 * (d - 10.0) / 65.0)).abs() < 1e-9);
    assert!((aof.eval(90.0, 2.0) - 95.05).abs() < 0.01);
    assert!(
        Distances::new(
            CpaEngine::new(0.0, 1.0, 0.0, 0.0, 0.0, 0.0),
            60.0,
            20.0,
            10.0
        )
        .is_none()
    );
}

#[test]
fn aof_r13_passes_on_the_asked_side() {
    // Overtaking: the contact 50 m ahead, 5 m to the right, heading north at 1 m/s, ownship
    // at 2 m/s.
    let cn = (5.0, 50.0, 0.0, 1.0);
    let d = distances(cn, 120.0, 10.0, 75.0);
    let geo = Cpx::new(cn.0, cn.1, cn.2, cn.3, 0.0, 0.0, 0.0, 2.0);
    let port = AofR13 {
        d: d.clone(),
        geo: geo.clone(),
        pass_to_port: true,
    };
    // The metric: 15 + 85 · (d − 10) / 65 below 75, 100 above.
    assert_eq!(port.metric_cpa(42.5), 57.5);
    assert_eq!(port.metric_cpa(76.0), 100.0);
    // Course 350 at 2 passes the contact's port side: CPA of the two tracks.
    let (ox, oy) = vel(350.0, 2.0);
    let dist = cpa((5.0, 50.0), (-ox, 1.0 - oy), 120.0);
    assert!(dist > 10.0 && dist < 75.0, "{dist}");
    let expected = 15.0 + 85.0 * (dist - 10.0) / 65.0;
    assert!((port.eval(350.0, 2.0) - expected).abs() < 1e-6);
    // Course 30 passes its starboard side: refused when port was asked...
    assert!(geo.passes_star(30.0, 2.0));
    assert_eq!(port.eval(30.0, 2.0), 0.0);
    // ... and kept when starboard was.
    let star = AofR13 {
        d,
        geo,
        pass_to_port: false,
    };
    let (ox, oy) = vel(30.0, 2.0);
    let dist = cpa((5.0, 50.0), (-ox, 1.0 - oy), 120.0);
    let expected = if dist > 75.0 {
        100.0
    } else {
        15.0 + 85.0 * (dist - 10.0) / 65.0
    };
    assert!((star.eval(30.0, 2.0) - expected).abs() < 1e-6);
    assert_eq!(star.eval(350.0, 2.0), 0.0);
    // Stopped: no passing, the CPA alone (the contact pulls away: the present range).
    let r = 5f64.hypot(50.0);
    assert!((star.eval(0.0, 0.0) - (15.0 + 85.0 * (r - 10.0) / 65.0)).abs() < 1e-9);
}

#[test]
fn aof_r14_rewards_the_starboard_turn_by_bearing_rate() {
    // Head-on: the contact 100 m north heading south at 2 m/s.
    let cn = (0.0, 100.0, 180.0, 2.0);
    let geo = Cpx::new(cn.0, cn.1, cn.2, cn.3, 0.0, 0.0, 0.0, 2.0);
    let aof = AofR14::new(distances(cn, 120.0, 10.0, 75.0), geo);
    // Both turned 90° right of the line between them (ownship east, the contact west) at the
    // contact's speed: the tangent speeds add to −4 m/s, times 360 / (2π · 100).
    let k = 360.0 / (2.0 * 100.0 * 3.14159265359);
    assert!((aof.initial_bng_rate - (-4.0 * k)).abs() < 1e-9);
    // Course 90 at 2: bearing rate −2 · k, half the initial: the term is 50; the CPA 70.71 m
    // gives 95.05; together 145.05.
    assert!((aof.metric3(90.0, 2.0) - 50.0).abs() < 1e-9);
    let d = cpa((0.0, 100.0), (-2.0, -2.0), 120.0);
    let expected = 25.0 + 75.0 * (d - 10.0) / 65.0 + 50.0;
    assert!((aof.eval(90.0, 2.0) - expected).abs() < 1e-9);
    // Turning to port passes starboard to starboard: 0.
    assert_eq!(aof.eval(270.0, 2.0), 0.0);
    assert_eq!(aof.eval(300.0, 2.0), 0.0);
    // Holding course: they meet: the CPA term is 0, the bearing rate 0.
    assert_eq!(aof.eval(0.0, 2.0), 0.0);
}

#[test]
fn aof_r16_stern_and_bow_passing() {
    // The contact at (100, 50) heading west at 2 m/s crosses ahead of ownship heading north.
    let cn = (100.0, 50.0, 270.0, 2.0);
    let geo = Cpx::new(cn.0, cn.1, cn.2, cn.3, 0.0, 0.0, 0.0, 2.0);
    let stern = AofR16 {
        d: distances(cn, 120.0, 10.0, 75.0),
        geo: geo.clone(),
        side: GiveWaySide::Stern,
        ok_cn_bow_cross_dist: 0.0,
        pts_port_turns_ok: true,
    };
    // Holding north crosses its bow: refused.
    assert_eq!(stern.eval(0.0, 2.0), 0.0);
    // A port turn that does not cross its stern: refused.
    assert_eq!(stern.eval(300.0, 2.0), 0.0);
    // East at 2 (a starboard turn): tracks 50 m apart, closing at 4 m/s: CPA 50 m after
    // 25 s: 25 + 75 · 40 / 65 = 71.15.
    assert!((stern.eval(90.0, 2.0) - (25.0 + 75.0 * 40.0 / 65.0)).abs() < 1e-9);
    assert_eq!(stern.metric_cpa(5.0), 0.0);
    // Without port turns: a starboard turn must cross the stern too.
    let strict = AofR16 {
        pts_port_turns_ok: false,
        ..stern.clone()
    };
    // East never reaches the contact's track; ENE reaches it after 50 s, 87 m east, long
    // after the contact passed: astern.
    assert!(!geo.crosses_stern(90.0, 2.0));
    assert_eq!(strict.eval(90.0, 2.0), 0.0);
    assert!(geo.crosses_stern(60.0, 2.0));
    assert!(strict.eval(60.0, 2.0) > 0.0);
    // Bow passing: a starboard turn must still cross the bow, by more than
    // ok_cn_bow_cross_dist when set (holding north crosses 50 m ahead).
    let bow = AofR16 {
        side: GiveWaySide::Bow,
        ok_cn_bow_cross_dist: 60.0,
        ..stern
    };
    assert_eq!(bow.eval(90.0, 2.0), 0.0, "east crosses its stern");
    assert!(bow.eval(0.0, 2.0) > 0.0, "north is no turn");
    assert!(geo.crosses_bow(5.0, 2.0));
    assert!(geo.crosses_bow_dist(5.0, 2.0) < 60.0);
    assert_eq!(bow.eval(5.0, 2.0), 0.0, "crosses the bow by less than 60 m");
}

#[test]
fn aof_r17_holds_course_and_speed_or_avoids_in_extremis() {
    let cn = (-60.0, 40.0, 90.0, 2.0);
    let geo = Cpx::new(cn.0, cn.1, cn.2, cn.3, 0.0, 0.0, 0.0, 2.0);
    let mut aof = AofR17 {
        d: distances(cn, 120.0, 10.0, 75.0),
        geo,
        original_course: 90.0,
        original_speed: 2.0,
        inextremis: false,
    };
    assert_eq!(aof.eval(90.0, 2.0), 100.0);
    // 10° and 0.5 m/s off: (2 · 0.5 + 2/3) / 3 · 100 = 55.56.
    assert!((aof.eval(100.0, 2.5) - (2.0 * 0.5 + 1.0 / 1.5) / 3.0 * 100.0).abs() < 1e-9);
    assert_eq!(aof.eval(120.0, 4.0), 0.0);
    // In extremis with the contact on ownship's port side: port turns refused, the CPA
    // metric otherwise.
    aof.inextremis = true;
    assert_eq!(aof.eval(300.0, 2.0), 0.0);
    let d = cpa((-60.0, 40.0), (2.0 - 2.0, -0.0), 120.0);
    assert!(
        (aof.eval(90.0, 2.0) - (25.0 + 75.0 * (d.min(75.0) - 10.0) / 65.0).min(100.0)).abs() < 1e-9
    );
}

// ---------------------------------------------------------------------------------------
// Encounter classification.

const OS: (f64, f64, f64, f64) = (0.0, 0.0, 0.0, 2.0);

#[test]
fn head_on_is_rule_14_and_turns_to_starboard() {
    let mut b = colregs(Version::V22, &[]);
    let (f, out) = run(&mut b, 10.0, OS, (0.0, 80.0, 180.0, 2.0));
    assert_eq!((b.mode, b.submode), ("headon", "none"));
    assert_eq!(b.mode_ix, 10);
    // Within pwt_inner_dist (90): full relevance.
    assert_eq!(b.pwt_factor(), 1.0);
    assert_eq!(b.actual_pwt, 100.0);
    let f = f.expect("a function");
    let (c, _) = f.argmax2("course", "speed");
    assert!(c > 20.0 && c < 180.0, "turns to starboard: {c}");
    assert!(f.value_at(&[("course", 300.0), ("speed", 2.0)]).unwrap() < 20.0);
    assert!(out.error.is_none());
    // Without per-contact info: no mode postings.
    assert!(posted(&out, "COL22_AVOID_MODE_CN").is_none());
}

#[test]
fn contact_crossing_from_starboard_makes_ownship_give_way() {
    let mut b = colregs(
        Version::V22,
        &[("pwt_outer_dist", "200"), ("completed_dist", "250")],
    );
    // The contact at (90, 60) heading west at 1.5: ownship would cross its bow 45 m ahead
    // (less than (2·75 + 10)/3 = 53.3) and the contact's track is 60 m away: stern.
    let (f, _) = run(&mut b, 10.0, OS, (90.0, 60.0, 270.0, 1.5));
    assert_eq!((b.mode, b.submode), ("giveway", "stern"));
    assert_eq!(b.mode_ix, 20);
    assert!((b.state.os_crosses_cn_bow_dist - 45.0).abs() < 1e-9);
    let f = f.expect("a function");
    // Holding course crosses the bow: at the bottom (0 before the function is normalised
    // over its pieces); the best course turns right, behind the contact.
    assert!(f.value_at(&[("course", 0.0), ("speed", 2.0)]).unwrap() < 25.0);
    let (c, s) = f.argmax2("course", "speed");
    let geo = Cpx::new(90.0, 60.0, 270.0, 1.5, 0.0, 0.0, 0.0, 2.0);
    assert!(!geo.crosses_bow(c, s), "{c} {s}");
    let v = |c: f64| f.value_at(&[("course", c), ("speed", 2.0)]).unwrap();
    // ENE passes 31 m astern of it: 25 + 75 · 21 / 65 = 49 before normalising.
    assert!(v(60.0) > v(0.0) + 25.0, "astern of it beats ahead of it");
    // Closer track (40 m < 53.3): ownship could not turn behind it: bow.
    let mut b = colregs(Version::V22, &[]);
    run(&mut b, 10.0, OS, (60.0, 40.0, 270.0, 2.0));
    assert_eq!((b.mode, b.submode), ("giveway", "bow"));
    assert_eq!(b.mode_ix, 22);
}

#[test]
fn contact_crossing_from_port_makes_ownship_stand_on() {
    let mut b = colregs(Version::V22, &[]);
    // The contact at (-60, 75) heading east at 2: it reaches ownship's track after 30 s, at
    // y = 75, ownship then at y = 60: it crosses ownship's bow 15 m ahead.
    let cn = (-60.0, 75.0, 90.0, 2.0);
    let (f, _) = run(&mut b, 10.0, OS, cn);
    assert_eq!(b.mode, "standon");
    assert!((b.state.cn_crosses_os_bow_dist - 15.0).abs() < 1e-9);
    // Relative bearing 321.3° (in (315, 350]), crossing ahead by at least min_util_cpa_dist
    // (10) but less than (75 + 10) / 2, no turn rate yet: unsure_bow.
    assert_eq!(b.submode, "unsure_bow");
    assert_eq!(b.mode_ix, 36);
    // Stand-on holds the course and speed it had: peak at (0, 2).
    let f = f.expect("a function");
    assert_eq!(f.argmax2("course", "speed"), (0.0, 2.0));
    // The contact turning to port at 1°/s for 4 s (a rate below 0.1): bow.
    for (i, t) in [11.0, 12.0, 13.0, 14.0].into_iter().enumerate() {
        run(&mut b, t, OS, (cn.0, cn.1, 89.0 - i as f64, cn.3));
    }
    assert_eq!((b.mode, b.submode), ("standon", "bow"));
    assert_eq!(b.heading_rate(4.0), Some(-1.0));
    assert_eq!(b.mode_ix, 32);
    // Astern: the contact at (-60, 40) crosses ownship's track at y = 40 when ownship is at
    // y = 60: stern.
    let mut b = colregs(Version::V22, &[]);
    run(&mut b, 10.0, OS, (-60.0, 40.0, 90.0, 2.0));
    assert_eq!(b.state.cn_crosses_os_bow_dist, -1.0);
    assert_eq!((b.mode, b.submode), ("standon", "stern"));
    // Closer in: CPA 14 m now; once the CPA is within min_util_cpa_dist (10) and the range
    // within max_util_cpa_dist (75): in extremis, the CPA function.
    let mut b = colregs(Version::V22, &[("min_util_cpa_dist", "20")]);
    let (f, _) = run(&mut b, 10.0, OS, (-60.0, 40.0, 90.0, 2.0));
    assert_eq!((b.mode, b.submode), ("standon", "inextremis"));
    assert_eq!(b.mode_ix, 31);
    let (c, _) = f.unwrap().argmax2("course", "speed");
    assert!(c != 0.0);
}

#[test]
fn overtaking_is_rule_13_passing_on_the_side_away_from_the_contact() {
    let mut b = colregs(Version::V22, &[]);
    // The contact 60 m ahead, a little to starboard, heading north at 1; ownship at 3.
    let (f, _) = run(&mut b, 10.0, (0.0, 0.0, 0.0, 3.0), (5.0, 60.0, 0.0, 1.0));
    assert_eq!((b.mode, b.submode), ("overtaking", "port"));
    assert_eq!(b.mode_ix, 43);
    let f = f.expect("a function");
    let (c, s) = f.argmax2("course", "speed");
    let geo = Cpx::new(5.0, 60.0, 0.0, 1.0, 0.0, 0.0, 0.0, 3.0);
    assert!(
        !geo.passes_star(c, s),
        "never past the contact's starboard side: {c} {s}"
    );
    // Courses that overtake to starboard are at the bottom.
    assert!(geo.passes_star(30.0, 3.0));
    assert!(f.value_at(&[("course", 30.0), ("speed", 3.0)]).unwrap() < 20.0);
}

#[test]
fn being_overtaken_is_rule_17_stand_on() {
    let mut b = colregs(Version::V22, &[]);
    // The contact 60 m astern, 15 m to starboard, heading north at 3; ownship at 1.
    let (f, _) = run(&mut b, 10.0, (0.0, 0.0, 0.0, 1.0), (15.0, -60.0, 0.0, 3.0));
    assert_eq!((b.mode, b.submode), ("standon_ot", "starboard"));
    assert_eq!(f.unwrap().argmax2("course", "speed"), (0.0, 1.0));
    // Straight astern: its CPA (0) is within min_util_cpa_dist: in extremis.
    let mut b = colregs(Version::V22, &[]);
    run(&mut b, 10.0, (0.0, 0.0, 0.0, 1.0), (0.0, -60.0, 0.0, 3.0));
    assert_eq!((b.mode, b.submode), ("standon_ot", "inextremis"));
}

#[test]
fn modes_hold_until_their_release_conditions() {
    let mut b = colregs(Version::V22, &[]);
    run(&mut b, 10.0, OS, (0.0, 80.0, 180.0, 2.0));
    assert_eq!(b.mode, "headon");
    // Bearings now 14° off each other's bow (beyond the 12° entry threshold) but still
    // closing and ahead: head-on holds (release criteria are not the entry's).
    run(&mut b, 11.0, OS, (15.0, 60.0, 180.0, 2.0));
    assert_eq!(b.mode, "headon");
    // Past each other (ownship aft of the contact): released to the catch-all.
    run(&mut b, 12.0, OS, (15.0, -10.0, 180.0, 2.0));
    assert_eq!(b.mode, "cpa");
    let (t0, _) = b.mode_times(12.0);
    assert_eq!(t0, 0.0);
    // Beyond pwt_outer_dist: no mode, no function.
    let (f, _) = run(&mut b, 13.0, OS, (15.0, -101.0, 180.0, 2.0));
    assert_eq!(b.mode, "none");
    assert!(f.is_none());
}

#[test]
fn relevance_is_graded_between_the_pwt_distances_and_completes_past_1_1_completed() {
    let mut b = colregs(
        Version::V22,
        &[
            ("pwt_outer_dist", "200"),
            ("pwt_inner_dist", "50"),
            ("completed_dist", "300"),
            ("pwt_grade", "quadratic"),
        ],
    );
    run(&mut b, 10.0, OS, (0.0, 125.0, 180.0, 2.0));
    // (200 - 125) / 150 = 0.5, squared.
    assert_eq!(b.pwt_factor(), 0.25);
    assert_eq!(b.relevance(), 0.25);
    // 1.1 · 300 = 330.
    let (_, out) = run(&mut b, 11.0, OS, (0.0, 329.0, 180.0, 2.0));
    assert!(!out.completed);
    let (_, out) = run(&mut b, 12.0, OS, (0.0, 330.0, 180.0, 2.0));
    assert!(out.completed);
}

// ---------------------------------------------------------------------------------------
// Postings and macros.

#[test]
fn per_contact_postings_and_macros() {
    let mut b = colregs(Version::V22, &[("post_per_contact_info", "true")]);
    let (_, out) = run(&mut b, 10.0, OS, (0.0, 80.0, 180.0, 2.0));
    assert_eq!(text(&out, "COL22_AVOID_MODE_CN").as_deref(), Some("headon"));
    assert_eq!(num(&out, "COL22_RELEVANCE_CN"), Some(1.0));
    assert_eq!(
        text(&out, "COLREGS_AVOID_MODE_CN").as_deref(),
        Some("headon")
    );
    assert_eq!(
        text(&out, "COLREGS_SUMMARY_CN").as_deref(),
        Some("mode=headon:none")
    );
    assert_eq!(num(&out, "AVDCOL_RANGE_CN"), Some(80.0));
    // The C++'s double underscore.
    assert_eq!(num(&out, "CN_PORT_OF_OS__CN"), Some(0.0));
    assert_eq!(num(&out, "CN_FORE_OF_OS_CN"), Some(1.0));
    assert!(out.emits.contains(&Emit::Post {
        var: "COLREGS_AVOID_IX_CN".into(),
        value: Value::Double(10.0),
        key: PostKey::Repeatable,
    }));
    assert_eq!(
        text(&out, "HEADON_DEBUG_ABE").as_deref(),
        Some("contact=cn,entered head-on mode")
    );
    let m = |name: &str| {
        let mut s = String::new();
        assert!(b.macro_value(name, &mut s), "{name}");
        s
    };
    assert_eq!(m("FULL_MODE"), "headon:none");
    assert_eq!(m("MODE_ID"), "10");
    assert_eq!(m("APWT"), "100");
    assert_eq!(m("OS_CN_REL_BNG"), "0");
    assert_eq!(m("CN_OS_REL_BNG"), "0");
    assert_eq!(m("OS_FORE_OF_CN"), "true");
    assert_eq!(m("CN_NAME"), "cn");
}

// ---------------------------------------------------------------------------------------
// Parameters.

#[test]
fn parameters_are_refused_as_moos_ivp_refuses_them() {
    let mut b = AvdColregs::v22();
    for (k, v) in [
        ("pwt_outer_dist", "-1"),
        ("pwt_inner_dist", "abc"),
        ("min_util_cpa_dist", "-3"),
        ("completed_dist", "-5"),
        ("giveway_bow_dist", "-1"),
        ("turn_radius", "x"),
        ("eval_tol", "4"),
        ("eval_tol", "301"),
        ("velocity_filter", "min_spd=3,max_spd=1"),
        ("velocity_filter", "min_spd=1,max_spd=3,pct=120"),
        ("avoid_mode", "bogus"),
        ("avoid_mode", "standon_ot"),
        ("pwt_grade", "cubic"),
        ("headon_only", "maybe"),
        ("pcheck_thresh", "-0.1"),
        ("contact_type_required", ""),
        ("use_plat_model", "yes"),
    ] {
        assert!(
            matches!(set(&mut b, k, v), Err(ParamError::BadValue { .. })),
            "{k} = {v}"
        );
    }
    assert!(matches!(
        set(&mut b, "overtaking_bng_range", "40"),
        Err(ParamError::Unknown { .. })
    ));
    // Pairs keep their order; completed_dist lowers the pwt distances; giveway_bow_dist is
    // clipped to [min_util, 2 · max_util].
    set(&mut b, "max_util_cpa_dist", "5").unwrap();
    assert_eq!((b.min_util_cpa_dist, b.max_util_cpa_dist), (5.0, 5.0));
    set(&mut b, "max_util_cpa_dist", "40").unwrap();
    set(&mut b, "min_util_cpa_dist", "12").unwrap();
    set(&mut b, "giveway_bow_dist", "500").unwrap();
    assert_eq!(b.giveway_bow_dist, 80.0);
    set(&mut b, "giveway_bow_dist", "2").unwrap();
    assert_eq!(b.giveway_bow_dist, 12.0);
    set(&mut b, "completed_dist", "50").unwrap();
    assert_eq!(
        (b.pwt_outer_dist, b.pwt_inner_dist, b.completed_dist),
        (50.0, 50.0, 50.0)
    );
    set(&mut b, "pwt_outer_dist", "80").unwrap();
    assert_eq!(
        b.completed_dist, 50.0,
        "only the three C++ branches raise it"
    );
    set(&mut b, "turn_radius", "10").unwrap();
    assert_eq!(b.completed_dist, 80.0, "raised to pwt_outer_dist");
    set(&mut b, "eval_tol", "300").unwrap();
    assert_eq!(b.base.time_on_leg, 300.0);
    set(&mut b, "avoid_mode", "giveway").unwrap();
    assert!(set(&mut b, "avoid_submode", "port").is_err());
    set(&mut b, "avoid_submode", "stern").unwrap();
    assert_eq!((b.mode, b.submode), ("giveway", "stern"));
    set(&mut b, "velocity_filter", "min_spd=0.5,max_spd=2,pct=40").unwrap();
    assert!(b.velocity_filter.is_some());
    set(&mut b, "pwt_grade", "QUASI").unwrap();
}

#[test]
fn every_catalog_parameter_is_known_to_its_version_and_no_other() {
    for v in [Version::V17, Version::V19, Version::V22, Version::V26] {
        let t = mission::catalog::behavior(v.kind()).unwrap_or_else(|| panic!("{v:?}"));
        assert!(behaviors::kinds().any(|k| k == v.kind()), "{v:?} in STOCK");
        assert_eq!(behaviors::create(v.kind()).unwrap().kind(), v.kind());
        for p in t.params {
            let mut b = AvdColregs::new(v);
            for val in ["1", "true", "x=1", "min_spd=1,max_spd=2"] {
                assert!(
                    !matches!(set(&mut b, p, val), Err(ParamError::Unknown { .. })),
                    "{v:?}: `{p}` listed but unknown"
                );
            }
        }
        for p in Version::V22.params() {
            if !t.params.contains(&p) {
                let mut b = AvdColregs::new(v);
                assert!(
                    matches!(set(&mut b, p, "1"), Err(ParamError::Unknown { .. })),
                    "{v:?}: `{p}` not listed but known"
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// What each version does differently.

#[test]
fn v17_cannot_build_its_give_way_function() {
    // V17 hands AOF_R16 an `osh` parameter it does not have: initialisation fails, the
    // behaviour posts an error (the helm halts).
    let mut b = colregs(Version::V17, &[]);
    let (f, out) = run(&mut b, 10.0, OS, (60.0, 40.0, 270.0, 2.0));
    assert_eq!(b.mode, "giveway");
    assert!(f.is_none());
    assert_eq!(
        out.error.as_deref(),
        Some("Unable to init AOF_R16:bad param[osh], value[0]")
    );
    let mut b = colregs(Version::V22, &[]);
    let (f, out) = run(&mut b, 10.0, OS, (60.0, 40.0, 270.0, 2.0));
    assert!(f.is_some() && out.error.is_none());
}

#[test]
fn v17_completes_at_completed_dist_v22_at_1_1_times() {
    let mut v17 = colregs(Version::V17, &[]);
    let mut v22 = colregs(Version::V22, &[]);
    let far = (0.0, 105.0, 180.0, 2.0);
    assert!(run(&mut v17, 10.0, OS, far).1.completed);
    assert!(!run(&mut v22, 10.0, OS, far).1.completed);
    // V17 refuses V19's parameters.
    assert!(matches!(
        set(&mut v17, "giveway_bow_dist", "20"),
        Err(ParamError::Unknown { .. })
    ));
    assert!(matches!(
        set(&mut v17, "use_refinery", "true"),
        Err(ParamError::Unknown { .. })
    ));
}

#[test]
fn v19_posts_its_mode_line_and_info_and_refuses_v22_parameters() {
    let mut b = colregs(Version::V19, &[]);
    let (_, out) = run(&mut b, 10.0, OS, (0.0, 80.0, 180.0, 2.0));
    assert_eq!(b.mode, "headon");
    assert_eq!(num(&out, "COL19_RELEVANCE"), Some(1.0));
    assert_eq!(
        text(&out, "AVD_INFO").as_deref(),
        Some("V19 CN:cn  Mode:headon:none")
    );
    // The mode line, label `<us><name>`, precision 1, the mode as its message.
    assert_eq!(
        text(&out, "VIEW_SEGLIST").as_deref(),
        Some("pts={0,0:0,80},label=abeavd_cn,msg=headon")
    );
    // Head-on debugging goes out without per-contact info.
    assert!(text(&out, "HEADON_DEBUG_ABE").is_some());
    // V22's parameters are not V19's; the give-way bow distance clips to max_util (75).
    for p in [
        "headon_only",
        "eval_tol",
        "velocity_filter",
        "post_status_info_on_idle",
        "pts_port_turns_ok",
    ] {
        assert!(
            matches!(set(&mut b, p, "true"), Err(ParamError::Unknown { .. })),
            "{p}"
        );
    }
    set(&mut b, "giveway_bow_dist", "500").unwrap();
    assert_eq!(b.giveway_bow_dist, 75.0);
    // No V22 macros.
    assert!(!b.macro_value("FULL_MODE", &mut String::new()));
}

#[test]
fn v26_evaluates_the_give_way_function_over_time_on_leg() {
    // A 10 s time on leg: V22's give-way function still looks 120 s ahead, V26's 10 s.
    let cn = (100.0, 50.0, 270.0, 2.0);
    let params = [
        ("time_on_leg", "10"),
        ("pwt_outer_dist", "150"),
        ("completed_dist", "200"),
        ("giveway_bow_dist", "20"),
    ];
    let mut v22 = colregs(Version::V22, &params);
    let mut v26 = colregs(Version::V26, &params);
    let (f22, _) = run(&mut v22, 10.0, OS, cn);
    let (f26, _) = run(&mut v26, 10.0, OS, cn);
    assert_eq!((v22.mode, v22.submode), ("giveway", "bow"));
    assert_eq!((v26.mode, v26.submode), ("giveway", "bow"));
    // Holding north: over 120 s the tracks meet 50 m ahead of the contact (CPA 44.7 m:
    // 25 + 75 · 34.7 / 65 = 65.1 before normalising); over 10 s the range only falls to
    // 95 m (> 75: 100). The two functions are normalised, so their difference shows.
    let at = |f: &ivp::IvpFunction| f.value_at(&[("course", 0.0), ("speed", 2.0)]).unwrap();
    let (a22, a26) = (at(&f22.unwrap()), at(&f26.unwrap()));
    // (Both normalised to 0..100 over their whole functions.)
    assert!(a26 - a22 > 15.0, "{a26} {a22}");
}

#[test]
fn v22_headon_only_turns_other_modes_into_cpa() {
    let mut b = colregs(Version::V22, &[("headon_only", "true")]);
    run(&mut b, 10.0, OS, (60.0, 40.0, 270.0, 2.0));
    assert_eq!((b.mode, b.submode), ("cpa", "none"));
    assert_eq!(b.mode_ix, 50);
}

#[test]
fn the_velocity_filter_scales_the_utility_distances() {
    // Both at 2 m/s with max_spd 1: the C++ factor is 100 (not 1): the distances are
    // multiplied by 100 for the function, then restored.
    let mut b = colregs(
        Version::V22,
        &[("velocity_filter", "min_spd=0.5,max_spd=1,pct=50")],
    );
    let (f, _) = run(&mut b, 10.0, OS, (0.0, 80.0, 180.0, 2.0));
    assert_eq!((b.min_util_cpa_dist, b.max_util_cpa_dist), (10.0, 75.0));
    // The distances become 1000 and 7500 m, and since the range (80 m) is within the
    // scaled min_util_cpa_dist the collision distance is half the range, 40 m: along course
    // 90 the CPA part is 25 + 75 · (d − 40) / 7460 (0 stopped, when the contact runs over
    // ownship), the bearing-rate part 0, 50, 100 at 0, 2, 4 m/s. Without the filter the CPA
    // part is 25 + 75 · (d − 10) / 65. Normalising keeps the ratio of the rises.
    let at = |f: &ivp::IvpFunction, s: f64| f.value_at(&[("course", 90.0), ("speed", s)]).unwrap();
    let (d2, d4) = (
        cpa((0.0, 80.0), (-2.0, -2.0), 120.0),
        cpa((0.0, 80.0), (-4.0, -2.0), 120.0),
    );
    let ratio = |v0: f64, v2: f64, v4: f64| (v4 - v2) / (v2 - v0);
    let m = |d: f64, lo: f64, hi: f64| 25.0 + 75.0 * (d - lo) / (hi - lo);
    let expected = ratio(0.0, m(d2, 40.0, 7500.0) + 50.0, m(d4, 40.0, 7500.0) + 100.0);
    let f = f.unwrap();
    let got = ratio(at(&f, 0.0), at(&f, 2.0), at(&f, 4.0));
    assert!((got - expected).abs() < 0.05, "{got} {expected}");
    let mut plain = colregs(Version::V22, &[]);
    let f = run(&mut plain, 10.0, OS, (0.0, 80.0, 180.0, 2.0))
        .0
        .unwrap();
    let expected = ratio(0.0, m(d2, 10.0, 75.0) + 50.0, m(d4, 10.0, 75.0) + 100.0);
    let got = ratio(at(&f, 0.0), at(&f, 2.0), at(&f, 4.0));
    assert!((got - expected).abs() < 0.05, "{got} {expected}");
}
