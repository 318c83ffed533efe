//! BHV_FixedTurn as MOOS-IvP a2a9b716: the turn counting, the report and its drawings, the
//! schedule, the coupled function and the value rules.

mod support;

use behaviors::{Emit, ParamError, Value};
use support::{Bhv, posted, posted_all, uuv_domain};

fn turn(params: &[(&str, &str)]) -> Bhv {
    Bhv::new("BHV_FixedTurn", "ft", uuv_domain()).config(params)
}

/// `VAR=value` of every flag emitted, in order.
fn flags(out: &behaviors::Out) -> Vec<String> {
    out.emits
        .iter()
        .filter_map(|e| match e {
            Emit::Flag { flag, .. } => Some(format!("{}={}", flag.var, flag.value)),
            _ => None,
        })
        .collect()
}

#[test]
fn defaults() {
    let b = behaviors::create("BHV_FixedTurn").unwrap();
    assert_eq!(b.default_name(), "fixturn");
    assert_eq!(b.domain_vars(), ["course", "speed"]);
}

#[test]
fn the_function_steers_the_offset_from_the_current_heading() {
    let mut b = turn(&[("fix_turn", "90"), ("mod_hdg", "30"), ("speed", "1.5")]);
    b.nav(0.0, 0.0, 100.0, 1.0, 0.0);
    let (f, out) = b.start(0.0);
    assert!(!out.completed);
    let f = f.unwrap();
    // Port (the default): course summit 100 - 30 = 70, base width 180; speed summit 1.5,
    // 1.9 at 20. Coupled 50/50, normalised: (70, 1.5) 100; (160, 1.5) 25 + 50 = 75;
    // (70, 1.9) 50 + 10 = 60.
    assert!((f.eval(&[70, 15]).unwrap() - 100.0).abs() < 1e-6);
    assert!((f.eval(&[160, 15]).unwrap() - 75.0).abs() < 1e-6);
    assert!((f.eval(&[70, 19]).unwrap() - 60.0).abs() < 1e-6);
    // The summit follows the heading: at 80, the summit is 50.
    b.nav(1.0, 1.0, 80.0, 1.0, 0.0);
    let f = b.run(1.0).0.unwrap();
    assert!((f.eval(&[50, 15]).unwrap() - 100.0).abs() < 1e-6);
    // 100 -> 80 -> 10: 90 degrees to port: done, no function.
    b.nav(2.0, 2.0, 10.0, 1.0, 0.0);
    let (f, out) = b.run(2.0);
    assert!(f.is_none() && out.completed);
    // Turning the wrong way counts against the turn.
    let mut b = turn(&[("fix_turn", "30"), ("turn_dir", "star")]);
    b.nav(0.0, 0.0, 100.0, 1.0, 0.0);
    b.start(0.0);
    b.nav(0.0, 0.0, 90.0, 1.0, 0.0);
    assert!(!b.run(1.0).1.completed);
    b.nav(0.0, 0.0, 125.0, 1.0, 0.0);
    // -10 + 35 = 25 < 30.
    assert!(!b.run(2.0).1.completed);
    b.nav(0.0, 0.0, 130.0, 1.0, 0.0);
    assert!(b.run(3.0).1.completed);
}

#[test]
fn a_full_starboard_circle_reports_its_radius() {
    let mut b = turn(&[
        ("fix_turn", "360"),
        ("turn_dir", "starboard"),
        ("speed", "1.5"),
        ("mod_hdg", "30"),
    ]);
    b.num("DESIRED_RUDDER", 20.0);
    // Circling clockwise around 50,50 at radius 10: at heading h the vehicle is at
    // 50,50 + 10 * (sin(h - 90), cos(h - 90)).
    let at = |h: f64| {
        let r = (h - 90.0).to_radians();
        (50.0 + 10.0 * r.sin(), 50.0 + 10.0 * r.cos())
    };
    // From 100 s (MOOS's odometer takes a start time of 0 for "not started").
    let (x, y) = at(0.0);
    b.info.set_now(100.0);
    b.nav(x, y, 0.0, 1.5, 0.0);
    b.start(100.0);
    let mut last = None;
    for k in 1..=36 {
        let h = f64::from(k * 10 % 360);
        let (x, y) = at(h);
        b.nav(x, y, h, 1.5, 0.0);
        let (f, out) = b.run(100.0 + f64::from(k));
        if out.completed {
            assert_eq!(k, 36, "360 degrees after 36 steps of 10");
            assert!(f.is_none());
            last = Some(out);
        }
    }
    let out = last.expect("completed");
    // Marks at turned angles 10..350 and 0 (360): 18 pairs 180 degrees apart, each a
    // diameter of 20 m, radius 10.
    assert_eq!(
        posted(&out, "FT_REPORT").and_then(Value::as_str),
        Some("spd=1.5,mod_hdg=30,rudder_avg=20,avg_rad=10,min_rad=10,max_rad=10")
    );
    let segls: Vec<&str> = posted_all(&out, "VIEW_SEGLIST")
        .into_iter()
        .filter_map(Value::as_str)
        .collect();
    assert_eq!(segls.len(), 18);
    // The first diameter: the marks of 0 (the 360 step: heading 0, at 40,50) and 180 (60,50).
    assert_eq!(
        segls[0],
        "pts={40,50:60,50},label=abeft0,label_color=invisible,edge_color=gray70,\
         vertex_color=light_green,duration=60,vertex_size=5"
    );
    let mut s = String::new();
    assert!(b.bhv.macro_value("TURN_TIME", &mut s));
    assert_eq!(s, "36");
    // Not perpetual: the next run (were it to come) would start a new turn by erasing the
    // diameters, in label order (abeft0, abeft1, abeft10, ...).
    b.info.set_now(140.0);
    b.nav(50.0, 60.0, 0.0, 1.5, 0.0);
    let (_, out) = b.run(140.0);
    let erased: Vec<&str> = posted_all(&out, "VIEW_SEGLIST")
        .into_iter()
        .filter_map(Value::as_str)
        .collect();
    assert_eq!(erased.len(), 18);
    assert_eq!(erased[0], "pts={0,0:9,0:0,9},active=false,label=abeft0");
    assert_eq!(erased[2], "pts={0,0:9,0:0,9},active=false,label=abeft10");
}

#[test]
fn timeout_delay_and_schedule() {
    // A timeout of 5 s ends a turn that never gets there.
    let mut b = turn(&[("fix_turn", "90"), ("timeout", "5")]);
    let fresh = |b: &mut Bhv, t: f64| {
        b.info.set_now(t);
        b.nav(0.0, 0.0, 100.0, 1.0, 0.0);
    };
    fresh(&mut b, 10.0);
    b.start(10.0);
    fresh(&mut b, 15.0);
    assert!(!b.run(15.0).1.completed);
    fresh(&mut b, 15.5);
    assert!(b.run(15.5).1.completed);
    // A delay of 3 s: straight on (offset 0) until then.
    let mut b = turn(&[("fix_turn", "90"), ("turn_delay", "3")]);
    b.nav(0.0, 0.0, 100.0, 1.0, 0.0);
    let f = b.start(0.0).0.unwrap();
    assert!((f.eval(&[100, 10]).unwrap() - 100.0).abs() < 1e-6);
    let f = b.run(3.0).0.unwrap();
    assert!((f.eval(&[80, 10]).unwrap() - 100.0).abs() < 1e-6);
    // A schedule: 30 degrees to starboard at 2 m/s then the behaviour's own turn; the
    // scheduled flag expands the turn's macros when posted.
    let mut b = turn(&[
        ("fix_turn", "60"),
        (
            "turn_spec",
            "fix=30, tdir=star, spd=2, mhdg=45, flag=T1=$[TURN_TIME]",
        ),
    ]);
    b.info.set_now(100.0);
    b.nav(0.0, 0.0, 100.0, 1.0, 0.0);
    let f = b.start(100.0).0.unwrap();
    assert!((f.eval(&[145, 20]).unwrap() - 100.0).abs() < 1e-6);
    b.nav(0.0, 0.0, 131.0, 1.0, 0.0);
    let (_, out) = b.run(104.0);
    assert!(out.completed);
    assert_eq!(flags(&out), ["T1=4"]);
    // Past the schedule: the behaviour's own settings (port, 20 off, 1 m/s).
    b.nav(0.0, 0.0, 131.0, 1.0, 0.0);
    let f = b.start(105.0).0.unwrap();
    assert!((f.eval(&[111, 10]).unwrap() - 100.0).abs() < 1e-6);
}

#[test]
fn turn_specs_and_values_are_refused_as_the_cpp() {
    let mut b = Bhv::new("BHV_FixedTurn", "ft", uuv_domain());
    for (p, v) in [
        ("fix_turn", "0"),
        ("mod_hdg", "-10"),
        ("turn_dir", "Toggle"),
        ("speed", "auto"),
        ("speed", "0"),
        ("timeout", "-1"),
        ("turn_delay", "2"),
        ("stale_nav_thresh", "0.5"),
        ("radius_rep_var", "FT_RAD"),
        ("schedule_repeat", "true"),
        ("visual_hints", "edge_color=red"),
        (
            "turn_spec",
            "key=a, fix=90, spd=auto, tdir=rand, timeout=20, flag=A=1",
        ),
        ("turn_spec", "key=a, mhdg=15"),
        ("turn_spec", "clear"),
        ("turn_spec", "clearall, fix=45"),
    ] {
        b.set(p, v).unwrap_or_else(|e| panic!("{p} = {v}: {e}"));
    }
    for (p, v) in [
        ("fix_turn", "-1"),
        ("mod_hdg", "wide"),
        ("turn_dir", "left"),
        ("speed", "Auto"),
        ("speed", "-1"),
        ("timeout", "soon"),
        ("stale_nav_thresh", "0"),
        ("radius_rep_var", "A B"),
        ("radius_rep_var", ""),
        ("schedule_repeat", "maybe"),
        ("visual_hints", "edge_color=nocolor"),
        ("turn_spec", "fix=ninety"),
        ("turn_spec", "tdir=left"),
        ("turn_spec", "size=3"),
        ("turn_spec", "flag=novalue"),
    ] {
        assert!(
            matches!(b.set(p, v), Err(ParamError::BadValue { .. })),
            "{p} = {v}"
        );
    }
}

#[test]
fn stale_navigation_is_an_error() {
    let mut b = turn(&[("fix_turn", "90"), ("stale_nav_thresh", "2")]);
    b.nav(0.0, 0.0, 100.0, 1.0, 0.0);
    assert!(b.start(0.0).0.is_some());
    let (f, out) = b.run(2.5);
    assert!(f.is_none());
    assert_eq!(
        out.error.as_deref(),
        Some("ownship NAV_X/Y not found or stale.")
    );
}

#[test]
fn a_perpetual_turn_starts_afresh_and_its_endflags_see_the_finished_turn() {
    let mut b = turn(&[("fix_turn", "20"), ("perpetual", "true")]);
    b.info.set_now(100.0);
    b.nav(0.0, 0.0, 100.0, 1.0, 0.0);
    b.start(100.0);
    // (The odometer restarts with the turn: the first move after it is not counted, as in
    // the C++, whose reset odometer takes the next position as its first.)
    b.nav(3.0, 4.0, 90.0, 1.0, 0.0);
    assert!(!b.run(101.0).1.completed);
    b.nav(6.0, 8.0, 79.0, 1.0, 0.0);
    let (_, out) = b.run(102.0);
    assert!(out.completed);
    // The endflags are expanded after the call (by the helm): they see the finished turn,
    // 5 m in 2 s, as the C++ endflags (posted before its reset) do.
    let m = |b: &Bhv, name: &str| {
        let mut s = String::new();
        b.bhv.macro_value(name, &mut s);
        s
    };
    assert_eq!(
        (m(&b, "TURN_DIST"), m(&b, "TURN_TIME")),
        ("5".into(), "2".into())
    );
    // The next run starts a new turn from the current heading.
    b.nav(6.0, 8.0, 79.0, 1.0, 0.0);
    let (f, out) = b.run(103.0);
    assert!(!out.completed);
    assert!((f.unwrap().eval(&[59, 10]).unwrap() - 100.0).abs() < 1e-6);
    assert_eq!(m(&b, "TURN_DIST"), "0");
}
