//! BHV_OpRegion: breaches by polygon, depth, altitude and time, the breach flags, soft
//! breaches, resets and the status postings.

mod support;

use behaviors::{Emit, ParamError, Value};
use support::{Bhv, flags, posted, posted_all, uuv_domain};

const SQUARE: &str = "pts={-50,-50:50,-50:50,50:-50,50}";

fn region(params: &[(&str, &str)]) -> Bhv {
    let mut p = vec![("polygon", SQUARE)];
    p.extend_from_slice(params);
    Bhv::new("BHV_OpRegion", "opreg", uuv_domain()).config(&p)
}

#[test]
fn inside_the_region_no_breach_and_perimeter_status() {
    let mut b = region(&[("max_depth", "30"), ("max_time", "60")]);
    b.nav(0.0, 0.0, 0.0, 2.0, 10.0);
    let (f, out) = b.run(10.0);
    assert!(f.is_none(), "never an objective function");
    assert!(out.error.is_none());
    // Heading north from the centre: 50 m to the edge, 25 s at 2 m/s; top speed 4 m/s.
    assert_eq!(
        posted(&out, "OPREG_TRAJECTORY_PERIM_DIST"),
        Some(&Value::Double(50.0))
    );
    assert_eq!(
        posted(&out, "OPREG_TRAJECTORY_PERIM_ETA"),
        Some(&Value::Double(25.0))
    );
    assert_eq!(
        posted(&out, "OPREG_ABSOLUTE_PERIM_DIST"),
        Some(&Value::Double(50.0))
    );
    assert_eq!(
        posted(&out, "OPREG_ABSOLUTE_PERIM_ETA"),
        Some(&Value::Double(13.0))
    );
    assert_eq!(
        posted(&out, "OPREG_TIME_REMAINING"),
        Some(&Value::Double(60.0))
    );
    let Some(Value::String(view)) = posted(&out, "VIEW_POLYGON") else {
        panic!("no VIEW_POLYGON")
    };
    assert!(
        view.starts_with("pts={-50,-50:50,-50:50,50:-50,50}"),
        "{view}"
    );
    assert!(view.contains("label=abe:opreg:opreg"), "{view}");
    assert!(view.contains("vertex_color=brown"), "{view}");
    // Idle: the polygon is erased.
    let out = b.idle(11.0);
    let Some(Value::String(view)) = posted(&out, "VIEW_POLYGON") else {
        panic!("no erase")
    };
    assert!(view.contains("active=false"), "{view}");
}

#[test]
fn polygon_breach_after_the_exit_time_is_an_error_with_flags_once() {
    let mut b = region(&[
        ("breached_poly_flag", "OPREG_POLY_BREACH = true"),
        ("breached_poly_flag", "WHO = $[OWNSHIP]"),
    ]);
    b.nav(0.0, 0.0, 90.0, 2.0, 1.0);
    assert!(b.run(0.0).1.error.is_none());
    // Out of the square: the default trigger_exit_time is 0.5 s.
    b.nav(51.0, 0.0, 90.0, 2.0, 1.0);
    let out = b.run(0.25).1;
    assert!(out.error.is_none(), "0 s outside");
    let out = b.run(0.5).1;
    assert!(out.error.is_none(), "0.25 s outside");
    let out = b.run(0.75).1;
    let err = out.error.as_deref().expect("breach after 0.5 s outside");
    assert!(err.contains("Polygon containment failure"), "{err}");
    assert!(err.contains("x=51.0 y=0.0"), "{err}");
    assert_eq!(flags(&out), ["OPREG_POLY_BREACH", "WHO"]);
    // The flags are repeatable (never filtered) and come before the error.
    assert!(out.emits.iter().all(|e| !matches!(
        e,
        Emit::Flag {
            repeatable: false,
            ..
        }
    )));
    // Posted once per breach.
    let out = b.run(1.0).1;
    assert!(out.error.is_some());
    assert!(flags(&out).is_empty());
}

#[test]
fn zero_exit_time_breaches_at_once_and_returning_inside_clears() {
    let mut b = region(&[("trigger_exit_time", "0")]);
    b.nav(60.0, 0.0, 90.0, 2.0, 1.0);
    assert!(b.run(0.0).1.error.is_some(), "first iteration outside");
    let mut b = region(&[("trigger_exit_time", "1")]);
    b.nav(60.0, 0.0, 90.0, 2.0, 1.0);
    assert!(b.run(0.0).1.error.is_none());
    b.nav(0.0, 0.0, 90.0, 2.0, 1.0);
    assert!(b.run(0.8).1.error.is_none());
    b.nav(60.0, 0.0, 90.0, 2.0, 1.0);
    assert!(b.run(1.6).1.error.is_none(), "the outside clock restarted");
    assert!(b.run(2.6).1.error.is_some());
}

#[test]
fn entry_trigger_waits_for_the_vehicle_to_enter() {
    // Launched outside (from a dock): not enforced until it has been inside 2 s.
    let mut b = region(&[("trigger_entry_time", "2"), ("trigger_exit_time", "0")]);
    b.nav(-80.0, 0.0, 90.0, 2.0, 0.0);
    for t in 0..5 {
        assert!(
            b.run(f64::from(t)).1.error.is_none(),
            "outside before entry"
        );
    }
    // In for 1 s only, then out again: still no entry.
    b.nav(-40.0, 0.0, 90.0, 2.0, 0.0);
    b.run(5.0);
    b.run(6.0);
    b.nav(-80.0, 0.0, 270.0, 2.0, 0.0);
    assert!(b.run(6.5).1.error.is_none(), "1 s inside is not an entry");
    // In for 2.5 s: entered; leaving now is a breach.
    b.nav(-40.0, 0.0, 90.0, 2.0, 0.0);
    for t in [7.0, 8.0, 9.5] {
        assert!(b.run(t).1.error.is_none());
    }
    b.nav(-80.0, 0.0, 270.0, 2.0, 0.0);
    assert!(b.run(10.0).1.error.is_some(), "enforced after entry");
}

#[test]
fn depth_altitude_and_time_breaches_post_their_flags() {
    let mut b = region(&[
        ("max_depth", "30"),
        ("min_altitude", "5"),
        ("max_time", "50"),
        ("breached_depth_flag", "OPREG_DEPTH_BREACH=true"),
        ("breached_altitude_flag", "OPREG_ALT_BREACH=true"),
        ("breached_time_flag", "OPREG_TIME_BREACH=true"),
        ("time_remaining_var", "OPREG_LEFT"),
    ]);
    b.nav(0.0, 0.0, 0.0, 2.0, 10.0).num("NAV_ALTITUDE", 20.0);
    let out = b.run(100.0).1;
    assert!(out.error.is_none());
    assert_eq!(posted(&out, "OPREG_LEFT"), Some(&Value::Double(50.0)));

    // Depth alone.
    b.num("NAV_DEPTH", 30.5);
    let out = b.run(101.0).1;
    let err = out.error.as_deref().unwrap();
    assert!(err.starts_with("OpRegion Depth failure: max:30.00000 detected:30.50000"));
    assert_eq!(flags(&out), ["OPREG_DEPTH_BREACH"]);

    // Altitude.
    let mut b = region(&[
        ("min_altitude", "5"),
        ("breached_altitude_flag", "OPREG_ALT_BREACH=true"),
    ]);
    b.nav(0.0, 0.0, 0.0, 2.0, 10.0).num("NAV_ALTITUDE", 4.0);
    let out = b.run(0.0).1;
    assert!(out.error.as_deref().unwrap().contains("Altitude failure"));
    assert_eq!(flags(&out), ["OPREG_ALT_BREACH"]);
    // Missing altitude with a limit set is an error too.
    let mut b = region(&[("min_altitude", "5")]);
    b.nav(0.0, 0.0, 0.0, 2.0, 10.0);
    assert!(b.run(0.0).1.error.unwrap().contains("altitude"));

    // Time: counted from the first running iteration.
    let mut b = region(&[
        ("max_time", "50"),
        ("breached_time_flag", "OPREG_TIME_BREACH=true"),
        ("time_remaining_var", "OPREG_LEFT"),
    ]);
    b.nav(0.0, 0.0, 0.0, 2.0, 10.0);
    b.run(100.0);
    let out = b.run(145.0).1;
    assert!(out.error.is_none());
    assert_eq!(posted(&out, "OPREG_LEFT"), Some(&Value::Double(5.0)));
    assert!(
        b.run(150.0).1.error.is_none(),
        "exactly max_time is allowed"
    );
    let out = b.run(150.5).1;
    assert!(out.error.as_deref().unwrap().contains("timeout failure"));
    assert_eq!(flags(&out), ["OPREG_TIME_BREACH"]);
    assert_eq!(
        posted(&out, "OPREG_TIME_REMAINING"),
        Some(&Value::Double(0.0))
    );
}

#[test]
fn soft_poly_breach_parks_the_helm_instead_of_an_error() {
    let mut b = region(&[
        ("soft_poly_breach", "true"),
        ("trigger_exit_time", "0"),
        ("breached_poly_flag", "OPREG_POLY_BREACH=true"),
    ]);
    b.nav(80.0, 0.0, 270.0, 2.0, 10.0);
    let out = b.run(20.0).1;
    assert!(out.error.is_none());
    assert_eq!(
        posted(&out, "MOOS_MANUAL_OVERRIDE"),
        Some(&Value::String("true".into()))
    );
    assert_eq!(flags(&out), ["OPREG_POLY_BREACH"]);
    assert!(
        matches!(posted(&out, "BHV_WARNING"), Some(Value::String(w)) if w.contains("Soft polygon")),
        "{out:?}"
    );
}

#[test]
fn reset_var_rearms_the_flags_and_restarts_the_clock() {
    let mut b = region(&[
        ("max_time", "10"),
        ("reset_var", "OPREG_RESET"),
        ("breached_time_flag", "T_BREACH=1"),
    ]);
    b.nav(0.0, 0.0, 0.0, 1.0, 0.0);
    b.run(0.0);
    let out = b.run(11.0).1;
    assert!(out.error.is_some());
    assert_eq!(flags(&out), ["T_BREACH"]);
    b.post(12.0, "OPREG_RESET", "time");
    let out = b.run(12.0).1;
    assert!(out.error.is_none(), "clock restarted");
    let out = b.run(23.0).1;
    assert!(out.error.is_some());
    assert_eq!(flags(&out), ["T_BREACH"], "flags re-armed");
}

#[test]
fn reset_var_acts_on_fresh_postings_only_even_of_the_same_value() {
    let mut b = region(&[
        ("max_time", "10"),
        ("reset_var", "OPREG_RESET"),
        ("breached_time_flag", "T_BREACH=1"),
    ]);
    b.nav(0.0, 0.0, 0.0, 1.0, 0.0);
    b.run(0.0);
    b.post(5.0, "OPREG_RESET", "time");
    assert!(b.run(5.0).1.error.is_none());
    // The stale value in the buffer does not keep resetting: the clock runs from 5 s.
    assert!(
        b.run(15.0).1.error.is_none(),
        "exactly 10 s since the reset"
    );
    let out = b.run(15.5).1;
    assert!(out.error.as_deref().unwrap().contains("timeout failure"));
    assert_eq!(flags(&out), ["T_BREACH"]);
    // The same value posted again is a new reset.
    b.post(16.0, "OPREG_RESET", "time");
    let out = b.run(16.0).1;
    assert!(
        out.error.is_none(),
        "reset again by a fresh posting: {out:?}"
    );
    assert!(b.run(26.0).1.error.is_none());
    let out = b.run(26.5).1;
    assert!(out.error.is_some());
    assert_eq!(flags(&out), ["T_BREACH"], "flags re-armed again");
}

#[test]
fn several_polygons_must_all_contain_the_vehicle_and_poly_var() {
    let mut b = region(&[
        ("polygon", "pts={0,-50:100,-50:100,50:0,50}"),
        ("trigger_exit_time", "0"),
        ("opregion_poly_var", "OPREG_POLY"),
    ]);
    // Posted at configuration (MOOS onSetParamComplete), not by the iterations.
    assert_eq!(
        posted(&b.configured, "OPREG_POLY"),
        Some(&Value::String("pts={0,-50:100,-50:100,50:0,50}".into()))
    );
    b.nav(25.0, 0.0, 0.0, 1.0, 0.0);
    let out = b.run(0.0).1;
    assert!(out.error.is_none());
    assert!(posted(&out, "OPREG_POLY").is_none());
    assert!(posted(&b.run(1.0).1, "OPREG_POLY").is_none());
    b.nav(-25.0, 0.0, 0.0, 1.0, 0.0);
    assert!(
        b.run(2.0).1.error.is_some(),
        "inside the first, not the second"
    );
}

#[test]
fn bad_values_are_rejected() {
    let mut b = Bhv::new("BHV_OpRegion", "o", uuv_domain());
    for (p, v) in [
        ("polygon", "bad"),
        ("polygon", "pts={0,0:10,10:0,20:5,10}"),
        ("max_depth", "-1"),
        ("max_time", "soon"),
        ("trigger_exit_time", "-0.5"),
        ("breached_poly_flag", "NOVALUE"),
        ("breached_depth_flag", "A B = 1"),
        ("soft_poly_breach", "maybe"),
        ("reset_var", "A B"),
    ] {
        assert!(
            matches!(b.set(p, v), Err(ParamError::BadValue { .. })),
            "{p} = {v}"
        );
    }
    assert!(matches!(
        b.set("max_depthh", "1"),
        Err(ParamError::Unknown { .. })
    ));
    // Without a polygon there is nothing to breach by position, and no view.
    b.nav(1e6, 1e6, 0.0, 1.0, 0.0);
    let out = b.run(0.0).1;
    assert!(out.error.is_none());
    assert!(posted_all(&out, "VIEW_POLYGON").is_empty());
}

#[test]
fn seconds_inside_the_polygon_are_posted_every_iteration() {
    let mut b = region(&[]);
    b.nav(0.0, 0.0, 0.0, 2.0, 0.0);
    let (_, out) = b.run(10.0);
    assert_eq!(posted(&out, "SECS_IN_POLY"), Some(&Value::Double(0.0)));
    b.run(11.0);
    let (_, out) = b.run(12.5);
    assert_eq!(posted(&out, "SECS_IN_POLY"), Some(&Value::Double(2.5)));
}

#[test]
fn visual_hints_keep_only_moos_colours_and_non_negative_sizes() {
    // Defaults (C++ constructor): vertex brown, edge aqua, label aqua, vertex 3, edge 1.
    let mut b = region(&[]);
    b.nav(0.0, 0.0, 0.0, 2.0, 0.0);
    let (_, out) = b.run(1.0);
    let view = posted(&out, "VIEW_POLYGON").unwrap().as_str().unwrap();
    for attr in [
        "label_color=aqua",
        "edge_color=aqua",
        "vertex_color=brown",
        "vertex_size=3",
        "edge_size=1",
    ] {
        assert!(view.contains(attr), "{attr} missing in {view}");
    }
    // A name MOOS does not know, a negative size and a non-number are ignored; the rest apply.
    let mut b = region(&[(
        "visual_hints",
        "edge_color=bluish, label_color=Dark_Green, vertex_size=-2, edge_size=2x, vertex_color=gray40",
    )]);
    b.nav(0.0, 0.0, 0.0, 2.0, 0.0);
    let (_, out) = b.run(1.0);
    let view = posted(&out, "VIEW_POLYGON").unwrap().as_str().unwrap();
    for attr in [
        "label_color=Dark_Green",
        "edge_color=aqua",
        "vertex_color=gray40",
        "vertex_size=3",
        "edge_size=1",
    ] {
        assert!(view.contains(attr), "{attr} missing in {view}");
    }
}

#[test]
fn depth_flags_are_rearmed_by_an_altitude_reset_not_a_depth_reset() {
    // The C++ at a2a9b716 re-arms the depth breach flags on `altitude` (and `true`) only.
    let mut b = region(&[
        ("max_depth", "30"),
        ("reset_var", "OPREG_RESET"),
        ("breached_depth_flag", "D_BREACH=1"),
    ]);
    b.nav(0.0, 0.0, 0.0, 1.0, 31.0);
    assert_eq!(flags(&b.run(0.0).1), ["D_BREACH"]);
    assert!(flags(&b.run(1.0).1).is_empty(), "posted once");
    b.post(2.0, "OPREG_RESET", "depth");
    let out = b.run(2.0).1;
    assert!(out.error.is_some(), "still breached");
    assert!(flags(&out).is_empty(), "a depth reset re-arms nothing");
    b.post(3.0, "OPREG_RESET", "altitude");
    assert_eq!(flags(&b.run(3.0).1), ["D_BREACH"], "re-armed by altitude");
    b.post(4.0, "OPREG_RESET", "true");
    assert_eq!(flags(&b.run(4.0).1), ["D_BREACH"], "re-armed by true");
}

#[test]
fn time_remaining_var_without_max_time_posts_minus_one_then_zero() {
    let mut b = region(&[("time_remaining_var", "LEFT")]);
    b.nav(0.0, 0.0, 0.0, 1.0, 0.0);
    let out = b.run(0.0).1;
    assert_eq!(
        posted_all(&out, "LEFT"),
        [&Value::Double(-1.0), &Value::Double(0.0)]
    );
}
