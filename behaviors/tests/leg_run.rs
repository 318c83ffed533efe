//! BHV_LegRun as MOOS-IvP a2a9b716: its coupled objective function, the Williamson turn
//! geometry of its ends (values worked out from `TurnGenWilliamson`'s formulas), its mode
//! cycle and flags, and its parameter rules.

mod support;

use behaviors::testing::Probe;
use behaviors::{Emit, LegGeometry, ParamError, Value};
use geometry::Point;
use support::{Bhv, posted, posted_all, uuv_domain};

/// `VAR=value` of every flag emitted, in order.
fn flags(out: &behaviors::Out) -> Vec<String> {
    out.emits
        .iter()
        .filter_map(|e| match e {
            Emit::Flag { flag, .. } => Some(format!("{}={}", flag.var, flag.value)),
            Emit::EndFlags { .. } => Some("<endflags>".into()),
            _ => None,
        })
        .collect()
}

/// A LegRun configured as the helm would (perpetual, its constructor's default).
fn legrun(params: &[(&str, &str)]) -> Bhv {
    let mut all = vec![("perpetual", "true")];
    all.extend_from_slice(params);
    Bhv::new("BHV_LegRun", "legs", uuv_domain()).config(&all)
}

const LEG: [(&str, &str); 4] = [
    ("p1", "0,0"),
    ("p2", "0,100"),
    ("turn_rad", "20"),
    ("speed", "2"),
];

fn close(a: Point, x: f64, y: f64, tol: f64) -> bool {
    (a.x - x).abs() < tol && (a.y - y).abs() < tol
}

#[test]
fn defaults_and_the_invalid_leg_warning() {
    let b = behaviors::create("BHV_LegRun").unwrap();
    assert_eq!(b.default_name(), "legrun");
    assert_eq!(b.domain_vars(), ["course", "speed"]);
    assert_eq!(b.default_common_params(), [("perpetual", "true")]);
    assert!(!b.is_constraint());
    // Turn radii unset (-1): the leg is invalid, a warning at configuration, no function.
    let mut l = legrun(&[("p1", "0,0"), ("p2", "0,100")]);
    let w = posted(&l.configured, "BHV_WARNING").unwrap();
    assert_eq!(w.as_str(), Some("legs: Invalid or unset legrun"));
    l.nav(0.0, 50.0, 0.0, 0.0, 0.0);
    assert!(l.start(1.0).0.is_none());
    // Valid: the warning is retracted, the settings posted, the mode set to init.
    let l = legrun(&LEG);
    let s = posted(&l.configured, "BHV_SETTINGS").unwrap();
    assert_eq!(
        s.as_str(),
        Some(
            "type=BHV_LegRun,name=legs,speed=2,currix=0,capture_radius=3,slip_radius=15,patience=50"
        )
    );
    assert_eq!(
        posted(&l.configured, "LR_MODE").unwrap().as_str(),
        Some("init")
    );
    assert!(
        posted(&l.configured, "LR_MODE_REPORT")
            .unwrap()
            .as_str()
            .unwrap()
            .starts_with("vname=abe,mode=init,utc=0")
    );
}

#[test]
fn the_objective_function_couples_the_cpp_zaics_with_the_patience_weights() {
    // Leg 1 runs towards p1 (0,0); from (0,50) the track point (no lead) is p1: bearing 180.
    let mut l = legrun(&LEG);
    l.nav(0.0, 50.0, 180.0, 2.0, 0.0);
    let (f, out) = l.start(1.0);
    let f = f.unwrap();
    assert_eq!(posted(&out, "LR_MODE").unwrap().as_str(), Some("leg1"));
    assert_eq!(posted(&out, "LR_NOW_SPD"), Some(&Value::Double(2.0)));
    assert_eq!(f.argmax2("course", "speed"), (180.0, 2.0));
    // Course: ZAIC_PEAK summit 180, base width 180: 50 at 270, 0 at 0. Speed: ZAIC_SPD summit
    // 2 (100), 0.1 at 70, 2.4 at 20, linear between (2.2: 100 - 80 * 0.2 / 0.4 = 60).
    // Patience 50: weights 50/50, normalised to [0, 100].
    let v = |c: f64, s: f64| f.value_at(&[("course", c), ("speed", s)]).unwrap();
    assert!((v(180.0, 2.0) - 100.0).abs() < 1e-6);
    assert!((v(180.0, 2.2) - 80.0).abs() < 1e-6); // 50 + 0.5 * 60
    assert!((v(270.0, 2.0) - 75.0).abs() < 1e-6); // 0.5 * 50 + 50
    assert!((v(0.0, 2.4) - 10.0).abs() < 1e-6); // 0 + 0.5 * 20
    // Patience 80: course weight 80, speed 20.
    let mut l = legrun(&[LEG[0], LEG[1], LEG[2], LEG[3], ("patience", "80")]);
    l.nav(0.0, 50.0, 180.0, 2.0, 0.0);
    let f = l.start(1.0).0.unwrap();
    let v = |c: f64, s: f64| f.value_at(&[("course", c), ("speed", s)]).unwrap();
    assert!((v(270.0, 2.0) - 60.0).abs() < 1e-6); // 0.8 * 50 + 20
    assert!((v(180.0, 2.2) - 92.0).abs() < 1e-6); // 80 + 0.2 * 60
    // Patience is clipped to [1, 99].
    let mut l = legrun(&[LEG[0], LEG[1], LEG[2], LEG[3], ("patience", "150")]);
    l.nav(0.0, 50.0, 180.0, 2.0, 0.0);
    let f = l.start(1.0).0.unwrap();
    let v270 = f.value_at(&[("course", 270.0), ("speed", 2.0)]).unwrap();
    assert!((v270 - (0.99 * 50.0 + 1.0)).abs() < 1e-6);
}

#[test]
fn far_and_close_turn_choose_the_first_leg_by_distance() {
    for (mode, first) in [("far_turn", "leg1"), ("close_turn", "leg2")] {
        // (0,80) is nearer p2 (0,100): far_turn heads for p1, close_turn for p2.
        let mut l = legrun(&[LEG[0], LEG[1], LEG[2], LEG[3], ("init_leg_mode", mode)]);
        l.nav(0.0, 80.0, 0.0, 2.0, 0.0);
        let (f, out) = l.start(1.0);
        assert_eq!(
            posted(&out, "LR_MODE").unwrap().as_str(),
            Some(first),
            "{mode}"
        );
        let crs = f.unwrap().argmax2("course", "speed").0;
        assert_eq!(crs, if first == "leg1" { 180.0 } else { 0.0 }, "{mode}");
    }
    // `resume` is accepted, then refused when the legs start (as the C++).
    let mut l = legrun(&[LEG[0], LEG[1], LEG[2], LEG[3], ("init_leg_mode", "resume")]);
    l.nav(0.0, 80.0, 0.0, 2.0, 0.0);
    let out = l.start(1.0).1;
    assert_eq!(
        out.error.as_deref(),
        Some("Bad init leg direction, check init_leg_mode param.")
    );
}

#[test]
fn the_turn_is_the_williamson_turn_of_the_cpp() {
    // p1 (0,0), p2 (0,100): the turn at p1 starts at p1 heading 180 and ends at p1 heading 0.
    // Lane gap d = 0, radius r = 20: v = (r + d/2) / 2r = 0.5, theta = 60 deg, the loop's
    // opening w = (90 - 60) * 2 = 60, b = sin(60) * 2r = 34.641. Port turn: the first arc
    // around c1 = p1 + 20 to starboard (-20,0) from 90 deg over theta; the loop around
    // c3 = p1 + b astern (0,-34.641) from 330 deg back over 360 - w = 300; the last arc
    // around c2 (20,0) from 270 - 60 = 210 over 60. With 20 deg between points: 4 + 16 + 4.
    let mut leg = LegGeometry::default();
    for (p, v) in [("p1", "0,0"), ("p2", "0,100"), ("turn_rad", "20")] {
        assert!(leg.set_param(p, v), "{p}");
    }
    let t = leg.turn_points(1);
    assert_eq!(t.len(), 24);
    assert!(close(t[0], 0.0, 0.0, 1e-9));
    // 110 deg around (-20,0): (-20 + 20 sin 110, 20 cos 110).
    assert!(close(
        t[1],
        -1.206_147_584_281_83,
        -6.840_402_866_513_374,
        1e-9
    ));
    assert!(close(
        t[4],
        -10.0,
        -34.641_016_151_377_55 + 17.320_508_075_688_77,
        1e-9
    ));
    for p in &t[4..20] {
        let r = (p.x - 0.0).hypot(p.y + 34.641_016_151_377_55);
        assert!((r - 20.0).abs() < 1e-9, "{p:?}");
    }
    assert!(close(t[23], 0.0, 0.0, 1e-9));
    // The turn at p2 mirrors it (its loop beyond p2, heading 0 there, then 180).
    let t2 = leg.turn_points(2);
    assert_eq!(t2.len(), 24);
    assert!(close(
        t2[4],
        10.0,
        100.0 + 34.641_016_151_377_55 - 17.320_508_075_688_77,
        1e-9
    ));
    // Starboard: the mirror image of the port turn.
    assert!(leg.set_param("turn1_dir", "star"));
    let s = leg.turn_points(1);
    assert_eq!(s.len(), 24);
    for (a, b) in s.iter().zip(&t) {
        assert!(close(*a, -b.x, b.y, 1e-9));
    }
    // Bias 100 %: at most r - 0.1/2 = 19.95 sideways. k1 = r - bias = 0.05 needs an extent of
    // at least sqrt(4r^2 - k1^2) = 39.99997, so the loop's centre is pushed to 1 m beyond it:
    // c3 = (-19.95, -(39.99997 + 1)) for a port turn. Then be > b: theta1 = atan(be/k1) -
    // acos(r/h1) = 77.2497 and theta2 = atan(be/k2) - acos(r/h2) = 0.0699 (h = sqrt(be^2 +
    // k^2) / 2), w = 180 - (theta1 + theta2) = 102.68: 4 + 13 + 1 points.
    assert!(leg.set_param("turn1_dir", "port"));
    assert!(leg.set_param("turn1_bias", "100"));
    let b = leg.turn_points(1);
    let be = (1600.0_f64 - 0.05 * 0.05).sqrt() + 1.0;
    let loop_pts: Vec<&Point> = b
        .iter()
        .filter(|p| ((p.x + 19.95).hypot(p.y + be) - 20.0).abs() < 1e-9)
        .collect();
    assert_eq!(loop_pts.len(), 13);
    assert_eq!(b.len(), 18);
    // The last arc is one point, at 270 - theta2 around c2 (20,0): just short of p1.
    let k2 = 20.0 + 19.95;
    let h2 = (be * be + k2 * k2).sqrt() / 2.0;
    let theta2 = (be / k2).atan().to_degrees() - (20.0 / h2).acos().to_degrees();
    let a = (270.0 - theta2).to_radians();
    assert!(close(
        *b.last().unwrap(),
        20.0 + 20.0 * a.sin(),
        20.0 * a.cos(),
        1e-9
    ));
    // An extension: the turn starts `turn1_ext` beyond p1 and ends back at p1.
    assert!(leg.set_param("turn1_bias", "0"));
    assert!(leg.set_param("turn1_ext", "10"));
    let e = leg.turn_points(1);
    assert!(close(e[0], 0.0, 0.0, 1e-9));
    assert!(close(e[1], 0.0, -10.0, 1e-9));
    assert!(close(*e.last().unwrap(), 0.0, 0.0, 1e-9));
    // The leg by its centre: x=0,y=50,ang=0,len=100 is the same leg.
    let mut by_ctr = LegGeometry::default();
    assert!(by_ctr.set_param("leg", "x=0,y=50,ang=0,len=100"));
    assert!(close(by_ctr.p1.unwrap(), 0.0, 0.0, 1e-9));
    assert!(close(by_ctr.p2.unwrap(), 0.0, 100.0, 1e-9));
    assert!(by_ctr.set_param("shift_pt", "10,50"));
    assert!(close(by_ctr.p1.unwrap(), 10.0, 0.0, 1e-9));
    assert!(by_ctr.set_param("leg_len_mod", "-20"));
    assert!(close(by_ctr.p2.unwrap(), 10.0, 90.0, 1e-9));
}

/// Drives the behaviour like a vehicle that turns instantly to the function's course and
/// moves `step` metres per iteration; returns the modes posted and the flags, in order.
fn drive(l: &mut Bhv, iterations: usize, step: f64) -> (Vec<String>, Vec<String>) {
    let (mut x, mut y) = (0.0, 50.0);
    let mut modes = Vec::new();
    let mut all_flags = Vec::new();
    let mut hdg = 180.0;
    for k in 0..iterations {
        l.nav(x, y, hdg, 2.0, 0.0);
        let t = 1.0 + k as f64 * 0.25;
        let (f, out) = if k == 0 { l.start(t) } else { l.run(t) };
        for m in posted_all(&out, "LR_MODE") {
            modes.push(m.as_str().unwrap().to_string());
        }
        all_flags.extend(flags(&out));
        let f = f.expect("a function every iteration");
        hdg = f.profile("course", &[("speed", 2.0)]).peak().0;
        let p = geometry::project_point(x, y, hdg, step);
        (x, y) = (p.x, p.y);
    }
    (modes, all_flags)
}

#[test]
fn the_modes_cycle_with_their_flags() {
    let mut l = legrun(&[
        LEG[0],
        LEG[1],
        LEG[2],
        LEG[3],
        ("leg_endflag", "LEG_END=$[LEG_ID]"),
        ("leg1_endflag", "LEG1_END=true"),
        ("turn_endflag", "TURN_END=$[MODE]"),
        ("turn2_endflag", "TURN2_END=true"),
        ("mid_leg_flag", "MID_LEG=true"),
        ("mid_turn_flag", "MID_TURN=true"),
    ]);
    let (modes, flags) = drive(&mut l, 1000, 1.0);
    assert_eq!(
        &modes[..5],
        ["leg1", "turn1", "leg2", "turn2", "leg1"],
        "{modes:?}"
    );
    // Leg ends, then leg 1's own; the behaviour's macros are expanded when the flag is
    // posted (LEG_ID: legs finished before this one; MODE: the turn ending).
    let first: Vec<&str> = flags.iter().map(String::as_str).take(5).collect();
    assert_eq!(first[0], "MID_LEG=true");
    assert_eq!(first[1], "LEG_END=0");
    assert_eq!(first[2], "LEG1_END=true");
    assert_eq!(first[3], "MID_TURN=true");
    assert_eq!(first[4], "TURN_END=turn1");
    assert!(flags.iter().any(|f| f == "TURN2_END=true"));
}

#[test]
fn the_legs_engine_posts_the_endflags_after_its_repeats() {
    // repeat = 0: the legs complete when leg 2 reaches p2; the common endflags go out and,
    // perpetual, the legs start over.
    let mut l = legrun(&[LEG[0], LEG[1], LEG[2], LEG[3]]);
    let (modes, flags) = drive(&mut l, 1000, 1.0);
    let ends = flags.iter().filter(|f| *f == "<endflags>").count();
    assert!(ends >= 1, "{flags:?}");
    assert!(modes.iter().filter(|m| *m == "turn2").count() >= 1);
}

#[test]
fn leg_speeds_follow_the_schedule_from_the_first_mode_switch() {
    let mut l = legrun(&[LEG[0], LEG[1], LEG[2], LEG[3], ("leg_spds", "1.5, 2:3")]);
    let (mut x, mut y, mut hdg) = (0.0, 50.0, 180.0);
    let mut seen = Vec::new();
    for k in 0..1500 {
        l.nav(x, y, hdg, 2.0, 0.0);
        let t = 1.0 + k as f64 * 0.25;
        let (f, out) = if k == 0 { l.start(t) } else { l.run(t) };
        let spd = posted(&out, "LR_NOW_SPD").and_then(Value::as_f64).unwrap();
        if seen.last() != Some(&spd) {
            seen.push(spd);
        }
        hdg = f.unwrap().profile("course", &[("speed", spd)]).peak().0;
        let p = geometry::project_point(x, y, hdg, 1.0);
        (x, y) = (p.x, p.y);
    }
    // The first leg at cruise speed (the schedule starts at a switch into a leg), turns at
    // cruise speed (leg_spds_onturn false), then 1.5, 3, 3, then cruise again (exhausted).
    assert_eq!(&seen[..7], [2.0, 1.5, 2.0, 3.0, 2.0, 3.0, 2.0], "{seen:?}");
}

#[test]
fn macros_expand_in_the_flags() {
    let b = legrun(&LEG);
    let mut s = String::new();
    assert!(b.bhv.macro_value("MODE", &mut s));
    assert_eq!(s, "init");
    s.clear();
    assert!(b.bhv.macro_value("SPEED", &mut s));
    assert_eq!(s, "2");
    // The C++ expands " NY" (with a space): `$[NY]` is not one of its macros.
    assert!(!b.bhv.macro_value("NY", &mut String::new()));
    for m in [
        "NI", "NX", "CYCLES", "CYCREM", "WPTS_HIT", "DIST_NP", "DIST_PP", "PCT_NP", "LEG_ODO",
        "LEG_ID", "WRAPS",
    ] {
        assert!(b.bhv.macro_value(m, &mut String::new()), "{m}");
    }
}

#[test]
fn bad_values_are_refused_as_the_cpp_refuses_them() {
    let mut b = Bhv::new("BHV_LegRun", "legs", uuv_domain());
    let bad = [
        ("speed", "-1"),
        ("speed", "5"), // above the speed domain's 4 (clipped, and refused)
        ("speed", "fast"),
        ("patience", "x"),
        ("init_leg_mode", "Fixed"),
        ("mid_leg_pct", "101"),
        ("mid_turn_pct", "-1"),
        ("leg_spds", "5"),
        ("leg_spds", "0:2"),
        ("leg_spds", "x"),
        ("leg_spds_repeat", "maybe"),
        ("leg_endflag", "novalue"),
        ("capture_line", "sometimes"),
        ("lead", "-1"),
        ("lead_damper", "x"),
        ("capture_radius", "-2"),
        ("slip_radius", "-1"),
        ("repeat", "-1"),
        ("p1", "nowhere"),
        ("leg", "1:2:3"),
        ("leg", "x=1,y=2,ang=3,len=0"),
        ("leg_len", "0"),
        ("shift_pt", "1,2"), // needs p1 and p2
        ("turn_rad", "0"),
        ("turn_rad_min", "-1"),
        ("turn_ext", "-1"),
        ("turn1_dir", "left"),
        ("visual_hints", "edge_color=bluish"),
    ];
    for (p, v) in bad {
        assert!(
            matches!(b.set(p, v), Err(ParamError::BadValue { .. })),
            "{p} = {v} accepted"
        );
    }
    // Unknown to BHV_LegRun and to LegRun: the corpus x1_legs's `legflag` and `mid_pct`.
    for p in ["legflag", "mid_pct"] {
        assert!(
            matches!(b.set(p, "1"), Err(ParamError::Unknown { .. })),
            "{p}"
        );
    }
    // Accepted with the C++'s leniency: `repeat` text, a `radius` read by atof, clipped
    // patience and bias, a turn radius raised to the minimum.
    for (p, v) in [
        ("repeat", "often"),
        ("repeat", "forever"),
        ("radius", "abc"),
        ("patience", "0"),
        ("turn_bias", "300"),
        ("turn_rad", "1"),
        ("turn_pt_gap", "0"),
        ("turn_dir", "toggle"),
        ("leg_spds", "replace, 1, 2:1.5"),
        ("leg_spds", "clear"),
        ("vx1", "70, -35"),
        ("vx2", "-35, -85"),
        (
            "visual_hints",
            "nextpt_lcolor=gray70, turn_vertext_color=green",
        ),
    ] {
        b.set(p, v).unwrap_or_else(|e| panic!("{p} = {v}: {e}"));
    }
}
