//! BHV_GoToDepth: levels in order, hold times, crossing, repeat and completion.

mod support;

use behaviors::{Emit, GoToDepth, ParamError, Value};
use support::{Bhv, at_depth, decide, posted, uuv_domain};

fn target(b: &mut Bhv, t: f64, depth: f64) -> Option<f64> {
    b.num("NAV_DEPTH", depth);
    let f = b.run(t).0?;
    Some(
        decide(&b.domain, &[("gtd", f, 100.0)])
            .get("depth")
            .unwrap(),
    )
}

#[test]
fn levels_in_order_with_hold_times_then_complete() {
    let mut b = Bhv::new("BHV_GoToDepth", "gtd", uuv_domain())
        .config(&[("depth", "10,5:20,0:5,2"), ("capture_flag", "DEPTH")]);
    b.num("NAV_X", 0.0);
    // Seeks 10 m from the surface.
    assert_eq!(target(&mut b, 0.0, 0.0), Some(10.0));
    let f = b.run(0.5).0.unwrap();
    // Peak width 0, base width 5.
    assert_eq!(at_depth(&f, 10), 100.0);
    assert!((at_depth(&f, 8) - 60.0).abs() < 1e-6);
    assert_eq!(at_depth(&f, 15), 0.0);
    // Within 1 m: arrived (GTD_DEPTH = 1), held 5 s.
    b.num("NAV_DEPTH", 9.2);
    let (f, out) = b.run(1.0);
    assert!(f.is_some());
    assert_eq!(posted(&out, "GTD_DEPTH"), Some(&Value::Double(1.0)));
    assert_eq!(target(&mut b, 5.5, 10.0), Some(10.0), "still holding");
    // After 5 s: the next level, announced in LEVEL_DEPTH.
    b.num("NAV_DEPTH", 10.0);
    let (f, out) = b.run(6.0);
    assert_eq!(posted(&out, "LEVEL_DEPTH"), Some(&Value::Double(20.0)));
    assert_eq!(
        decide(&b.domain, &[("g", f.unwrap(), 100.0)]).get("depth"),
        Some(20.0)
    );
    // Crossing 20 m between iterations (14 → 23) counts as arrival; hold 0.
    assert_eq!(target(&mut b, 7.0, 14.0), Some(20.0));
    b.num("NAV_DEPTH", 23.0);
    let (_, out) = b.run(8.0);
    assert_eq!(posted(&out, "GTD_DEPTH"), Some(&Value::Double(2.0)));
    let (f, out) = b.run(8.5);
    assert_eq!(posted(&out, "LEVEL_DEPTH"), Some(&Value::Double(5.0)));
    assert!(f.is_some());
    // Up to 5 m, held 2 s, then done: complete, no function.
    assert_eq!(target(&mut b, 9.0, 5.5), Some(5.0));
    assert_eq!(target(&mut b, 10.0, 5.0), Some(5.0));
    b.num("NAV_DEPTH", 5.0);
    let (f, out) = b.run(11.5);
    assert!(f.is_none());
    assert!(out.completed);
    assert!(out.emits.contains(&Emit::Complete));
}

#[test]
fn repeat_cycles_the_levels() {
    let mut b = Bhv::new("BHV_GoToDepth", "gtd", uuv_domain()).config(&[
        ("depth", "10:20"),
        ("repeat", "1"),
        ("capture_delta", "0.5"),
    ]);
    let mut seen = Vec::new();
    let mut depth = 0.0;
    for k in 0..40 {
        b.num("NAV_DEPTH", depth);
        let (f, out) = b.run(f64::from(k));
        if out.completed {
            break;
        }
        let d = decide(&b.domain, &[("g", f.unwrap(), 100.0)])
            .get("depth")
            .unwrap();
        if seen.last() != Some(&d) {
            seen.push(d);
        }
        depth = d; // the vehicle gets there by the next iteration
    }
    assert_eq!(seen, [10.0, 20.0, 10.0, 20.0]);
}

#[test]
fn perpetual_starts_over_after_completing() {
    let mut b = Bhv::new("BHV_GoToDepth", "gtd", uuv_domain())
        .config(&[("depth", "3"), ("perpetual", "true")]);
    assert_eq!(target(&mut b, 0.0, 3.0), Some(3.0));
    let (f, out) = b.run(1.0);
    assert!(f.is_none() && out.completed);
    assert_eq!(target(&mut b, 2.0, 0.0), Some(3.0), "seeking again");
}

#[test]
fn bad_levels_and_missing_depth() {
    let mut b = Bhv::new("BHV_GoToDepth", "gtd", uuv_domain());
    for (p, v) in [
        ("depth", "ten"),
        ("depth", "10,5,3"),
        ("depth", "-10,5"),
        ("depth", "10,-5"),
        ("depth", "10:x"),
        ("repeat", "-1"),
        ("repeat", "twice"),
        ("capture_delta", "-1"),
    ] {
        assert!(
            matches!(b.set(p, v), Err(ParamError::BadValue { .. })),
            "{p} = {v}"
        );
    }
    // A rejected line adds nothing.
    b.set("depth", "7").unwrap();
    let g = GoToDepth::new();
    assert!(g.levels().is_empty());
    let (f, out) = b.run(0.0);
    assert!(f.is_none());
    assert!(out.error.as_deref().unwrap().contains("Depth"));
    b.num("NAV_DEPTH", 0.0);
    assert_eq!(target(&mut b, 1.0, 0.0), Some(7.0));
}
