//! BHV_PModelView as MOOS-IvP a2a9b716: the platform model's turn towards the desired
//! heading drawn as a VIEW_SEGLR (the holonomic model: a ray from ownship), its erasure, and
//! its parameter rules.

mod support;

use behaviors::{ParamError, Value};
use support::{Bhv, posted, uuv_domain};

#[test]
fn defaults() {
    let b = behaviors::create("BHV_PModelView").unwrap();
    assert_eq!(b.default_name(), "pview");
    assert_eq!(b.domain_vars(), ["course", "speed"]);
    let mut vars = Vec::new();
    b.info_vars(&mut vars);
    assert!(vars.iter().any(|v| v == "DESIRED_HEADING"));
    assert!(vars.iter().any(|v| v == "DESIRED_SPEED"));
    // onSetParamComplete is empty in the C++: no BHV_SETTINGS.
    let p = Bhv::new("BHV_PModelView", "pv", uuv_domain()).config(&[("vertex_size", "4")]);
    assert!(p.configured.emits.is_empty());
    assert!(mission::catalog::behavior("BHV_PModelView").is_some());
}

#[test]
fn draws_the_ray_towards_the_desired_heading_and_erases_it() {
    let mut p = Bhv::new("BHV_PModelView", "pv", uuv_domain())
        .config(&[("edge_color", "red"), ("vertex_color", "blue")]);
    p.nav(12.34, -5.06, 10.0, 1.5, 0.0);
    // Not moving (DESIRED_SPEED 0): nothing drawn, no function.
    p.num("DESIRED_HEADING", 45.0).num("DESIRED_SPEED", 0.0);
    let (f, out) = p.start(1.0);
    assert!(f.is_none());
    assert!(posted(&out, "VIEW_SEGLR").is_none());
    // Moving: one vertex at ownship (one decimal), the ray along the desired heading, the
    // C++'s fixed look (its colour and size parameters are not used for it).
    p.num("DESIRED_SPEED", 2.0).num("DESIRED_HEADING", 92.25);
    let (f, out) = p.run(1.25);
    assert!(f.is_none());
    assert_eq!(
        posted(&out, "VIEW_SEGLR"),
        Some(&Value::text(
            "pts={12.3,-5.1},ray=92.2,label=abe_seglr,vertex_color=lime_green,vertex_size=2,\
             ray_len=20,head_size=1"
        ))
    );
    let out = p.stop(1.5);
    assert_eq!(
        posted(&out, "VIEW_SEGLR"),
        Some(&Value::text(
            "pts={12.3,-5.1},ray=92.2,active=false,label=abe_seglr,ray_len=5,head_size=3"
        ))
    );
}

#[test]
fn missing_navigation_is_an_error() {
    let mut p = Bhv::new("BHV_PModelView", "pv", uuv_domain()).config(&[]);
    p.num("NAV_Y", 1.0).num("NAV_HEADING", 0.0);
    let out = p.start(1.0).1;
    assert_eq!(
        out.error.as_deref(),
        Some("No ownship X/Y info in info_buffer.")
    );
}

#[test]
fn bad_values_are_refused() {
    let mut b = Bhv::new("BHV_PModelView", "pv", uuv_domain());
    for (p, v) in [
        ("edge_color", "bluish"),
        ("vertex_color", "12"),
        ("vertex_size", "-1"),
        ("vertex_size", "big"),
    ] {
        assert!(
            matches!(b.set(p, v), Err(ParamError::BadValue { .. })),
            "{p} = {v}"
        );
    }
    assert!(matches!(
        b.set("speed", "1"),
        Err(ParamError::Unknown { .. })
    ));
    for p in mission::catalog::behavior("BHV_PModelView").unwrap().params {
        assert!(
            !matches!(b.set(p, "1"), Err(ParamError::Unknown { .. })),
            "{p}"
        );
    }
}
