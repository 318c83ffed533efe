//! BHV_OpRegionV24 (MOOS-IvP a2a9b716): halt checks, the save-polygon recovery, triggers,
//! reset, dynamic region, postings and macros. Expected values are worked out from the C++.

mod support;

use behaviors::{ParamError, Value};
use support::{Bhv, decide, flags, posted, posted_all, uuv_domain};

/// A 100 m square core region centred on the origin.
const CORE: &str = "-50,-50 : -50,50 : 50,50 : 50,-50";

fn opreg(params: &[(&str, &str)]) -> Bhv {
    Bhv::new("BHV_OpRegionV24", "opr", uuv_domain()).config(params)
}

fn err(out: &behaviors::Out) -> Option<&str> {
    out.error.as_deref()
}

#[test]
fn defaults_and_bad_values() {
    let b = behaviors::create("BHV_OpRegionV24").unwrap();
    assert_eq!(b.default_name(), "opregx");
    assert_eq!(
        b.default_duration(),
        -1.0,
        "a guard never times out by default"
    );
    assert_eq!(b.domain_vars(), ["course", "speed"]);
    let mut b = opreg(&[]);
    for (p, v) in [
        ("save_dist", "-1"),
        ("halt_dist", "far"),
        ("max_depth", "-3"),
        ("min_altitude", "x"),
        ("max_time", "-1"),
        ("recover_spd", "0"),
        ("recover_speed", "-1"),
        ("reset", "false"),
        ("trigger_on_poly_entry", "maybe"),
        ("trigger_entry_time", "-1"),
        ("trigger_exit_time", "soon"),
        ("breached_poly_flag", "NOEQUALS"),
        ("draw_save_status", "perhaps"),
        ("visual_hints", "edge_size=wide"),
        ("visual_hints", "core_edge_color=greenish"),
        ("dynamic_region_var", "TWO WORDS"),
        ("core_poly", "0,0 : 10,10 : 10,0 : 0,10"),
    ] {
        assert!(
            matches!(b.set(p, v), Err(ParamError::BadValue { .. })),
            "{p} = {v} accepted"
        );
    }
    assert!(matches!(
        b.set("polygon", CORE),
        Err(ParamError::Unknown { .. })
    ));
    for (p, v) in [
        ("recover_speed", "1.5"),
        ("reset", "TRUE"),
        ("trigger_on_poly_entry", "no"),
        ("draw_halt_status", "toggle"),
        ("visual_hints", "edge_color=green, vertex_size=2"),
    ] {
        b.set(p, v).unwrap_or_else(|e| panic!("{p} = {v}: {e}"));
    }
}

#[test]
fn halt_poly_counts_only_after_entry_and_the_exit_time() {
    let mut b = opreg(&[
        ("halt_poly", CORE),
        ("breached_poly_flag", "OPREG_BREACH = halt"),
    ]);
    // Launched outside: no breach until the vehicle has been inside for 1 s (default).
    b.nav(80.0, 0.0, 270.0, 1.0, 0.0);
    for t in [10.0, 20.0, 30.0] {
        assert_eq!(err(&b.run(t).1), None, "t={t}");
    }
    b.nav(40.0, 0.0, 270.0, 1.0, 0.0);
    b.run(31.0);
    b.run(31.5); // 0.5 s inside: not yet an entry
    b.nav(60.0, 0.0, 90.0, 1.0, 0.0);
    assert_eq!(err(&b.run(32.0).1), None);
    assert_eq!(err(&b.run(35.0).1), None, "no entry was made, so no breach");
    b.nav(40.0, 0.0, 270.0, 1.0, 0.0);
    b.run(36.0);
    b.run(37.0); // 1 s inside: entry made
    b.nav(60.0, 0.0, 90.0, 1.0, 0.0);
    assert_eq!(err(&b.run(37.2).1), None, "0 s outside");
    assert_eq!(err(&b.run(37.6).1), None, "0.4 s outside");
    let (f, out) = b.run(37.7);
    assert!(f.is_none());
    assert_eq!(err(&out), Some("OpRegion HaltPoly Failure"));
    assert_eq!(flags(&out), ["OPREG_BREACH"]);
    // The red status circle about ownship: radius 4, 8 points.
    let stat = posted(&out, "VIEW_POLYGON").unwrap().as_str().unwrap();
    assert!(
        stat.contains("label=abe_stat") && stat.contains("edge_color=red"),
        "{stat}"
    );
    assert_eq!(stat.matches(':').count(), 7, "8 vertices: {stat}");
}

#[test]
fn without_trigger_on_entry_the_halt_poly_binds_from_the_start() {
    let mut b = opreg(&[
        ("halt_poly", CORE),
        ("trigger_on_poly_entry", "false"),
        ("trigger_exit_time", "2"),
    ]);
    b.nav(80.0, 0.0, 270.0, 1.0, 0.0);
    assert_eq!(err(&b.run(10.0).1), None);
    assert_eq!(err(&b.run(11.9).1), None);
    assert_eq!(err(&b.run(12.0).1), Some("OpRegion HaltPoly Failure"));
}

#[test]
fn depth_altitude_and_time_limits() {
    let mut b = opreg(&[
        ("max_depth", "10"),
        ("min_altitude", "3"),
        ("max_time", "100"),
        ("breached_depth_flag", "WHY = depth"),
        ("breached_altitude_flag", "WHY = altitude"),
        ("breached_time_flag", "WHY = time"),
    ]);
    // No altitude known: an error naming it.
    b.nav(0.0, 0.0, 0.0, 1.0, 5.0);
    assert_eq!(
        err(&b.run(1000.0).1),
        Some("No ownship altitude in info_buffer.")
    );
    b.num("NAV_ALTITUDE", 20.0);
    assert_eq!(err(&b.run(1001.0).1), None);
    b.num("NAV_DEPTH", 10.5);
    let out = b.run(1002.0).1;
    assert_eq!(err(&out), Some("OpRegion Depth failure"));
    assert_eq!(flags(&out), ["WHY"]);
    b.num("NAV_DEPTH", 5.0).num("NAV_ALTITUDE", 2.0);
    assert_eq!(err(&b.run(1003.0).1), Some("OpRegion Altitude failure"));
    b.num("NAV_ALTITUDE", 20.0);
    // The clock started at the first iteration (t=1000): 100 s allowed.
    assert_eq!(err(&b.run(1100.0).1), None);
    let out = b.run(1100.5).1;
    assert_eq!(err(&out), Some("OpRegion timeout failure"));
    // A reset (as an update) restarts the clock at the update.
    b.set("reset", "true").unwrap();
    b.info.set_now(1200.0);
    let ctx_out = {
        let mut o = behaviors::Out::default();
        let ctx = behaviors::Ctx {
            info: &b.info,
            domain: &b.domain,
            ownship: "abe",
            name: "opr",
            perpetual: false,
        };
        b.bhv.on_set_param_complete(&ctx, &mut o);
        o
    };
    assert!(ctx_out.error.is_none());
    assert_eq!(err(&b.run(1300.0).1), None);
    assert_eq!(err(&b.run(1300.1).1), Some("OpRegion timeout failure"));
    // Missing depth with max_depth set is an error too.
    let mut b = opreg(&[("max_depth", "10")]);
    b.num("NAV_X", 0.0)
        .num("NAV_Y", 0.0)
        .num("NAV_HEADING", 0.0);
    assert_eq!(err(&b.run(1.0).1), Some("No ownship depth in info_buffer."));
}

#[test]
fn save_poly_grown_from_core_steers_back_in() {
    let mut b = opreg(&[
        ("core_poly", CORE),
        ("save_dist", "10"),
        ("halt_dist", "40"),
        ("save_flag", "SAVING = true"),
        ("savex_flag", "SAVE_SECS = $[SECS_OUT_SAVE_POLY]"),
    ]);
    // Configuration draws core, save and halt polygons, with their hint colours.
    let views: Vec<&str> = posted_all(&b.configured, "VIEW_POLYGON")
        .into_iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert_eq!(views.len(), 3, "{views:?}");
    assert!(views[0].contains("label=coreabe") && views[0].contains("edge_color=gray30"));
    assert!(views[1].contains("label=opreg_save_abe") && views[1].contains("edge_color=gray50"));
    assert!(views[2].contains("label=opreg_halt_abe") && views[2].contains("edge_color=pink"));
    // Inside the save polygon (55 m east: beyond the core, inside the 10 m buffer).
    b.nav(55.0, 0.0, 90.0, 1.0, 0.0);
    let (f, out) = b.run(1.0);
    assert!(f.is_none() && err(&out).is_none());
    assert_eq!(
        posted(&out, "VIEW_POLYGON"),
        Some(&Value::String(
            "pts={0,0:9,0:0,9},active=false,label=abe_stat".into()
        ))
    );
    // Out of it, heading away (east): save flags once, savex every iteration, a committed
    // turn and a course-speed function toward the polygon.
    b.nav(65.0, 0.0, 90.0, 1.0, 0.0);
    let (f, out) = b.run(2.0);
    assert_eq!(flags(&out), ["SAVING", "SAVE_SECS"]);
    let committed = posted(&out, "COMMITTED")
        .unwrap()
        .as_str()
        .unwrap()
        .to_string();
    assert!(committed == "left" || committed == "right", "{committed}");
    let d = decide(&b.domain, &[("opr", f.unwrap(), 100.0)]);
    let crs = d.get("course").unwrap();
    // West-ish: a heading that reaches the save polygon from (65, 0).
    assert!((200.0..=340.0).contains(&crs), "course {crs}");
    let stat = posted_all(&out, "VIEW_POLYGON")[0].as_str().unwrap();
    assert!(
        stat.contains("edge_color=yellow") && stat.contains("duration=2"),
        "{stat}"
    );
    let (_, out) = b.run(3.0);
    assert_eq!(flags(&out), ["SAVE_SECS"], "save flags once per excursion");
    let mut secs = String::new();
    assert!(b.bhv.macro_value("SECS_OUT_SAVE_POLY", &mut secs));
    assert_eq!(secs, "1");
    // Back inside: the next excursion posts the save flags again.
    b.nav(55.0, 0.0, 270.0, 1.0, 0.0);
    b.run(4.0);
    b.nav(65.0, 0.0, 90.0, 1.0, 0.0);
    assert_eq!(flags(&b.run(5.0).1), ["SAVING", "SAVE_SECS"]);
}

#[test]
fn outside_a_save_poly_never_entered_asks_nothing() {
    let mut b = opreg(&[("save_poly", CORE), ("save_flag", "SAVING = true")]);
    b.nav(80.0, 0.0, 90.0, 1.0, 0.0);
    let (f, out) = b.run(1.0);
    assert!(f.is_none() && flags(&out).is_empty() && err(&out).is_none());
}

#[test]
fn course_speed_weights_cycle_with_the_helm_iteration() {
    let mut b = opreg(&[("save_poly", CORE), ("recover_spd", "1.2")]);
    b.nav(0.0, 0.0, 90.0, 1.0, 0.0);
    b.run(1.0);
    b.nav(70.0, 0.0, 270.0, 1.0, 0.0); // heading back toward the square
    // Iteration 2: 50/50; the speed still peaks at the recovery speed.
    b.bhv.set_helm_iteration(2);
    let (f, out) = b.run(2.0);
    assert_eq!(
        posted(&out, "COMMITTED"),
        Some(&Value::String("none".into()))
    );
    let d = decide(&b.domain, &[("opr", f.unwrap(), 100.0)]);
    assert!((d.get("speed").unwrap() - 1.2).abs() < 1e-9, "{d:?}");
    assert_eq!(d.get("course"), Some(270.0), "straight at the nearest edge");
}

#[test]
fn idle_erases_every_polygon_and_running_redraws() {
    let mut b = opreg(&[("core_poly", CORE), ("save_dist", "0"), ("halt_dist", "0")]);
    let out = b.stop(1.0);
    let erased: Vec<&str> = posted_all(&out, "VIEW_POLYGON")
        .into_iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    // save_dist/halt_dist 0 copy the core polygon, label and all.
    assert_eq!(erased, ["pts={0,0:9,0:0,9},active=false,label=coreabe"; 3]);
    assert_eq!(b.bhv.kind(), "BHV_OpRegionV24");
}

#[test]
fn dynamic_region_replaces_the_core_polygon() {
    let mut b = opreg(&[("core_poly", CORE), ("dynamic_region_var", "NEW_REGION")]);
    let mut vars = Vec::new();
    b.bhv.info_vars(&mut vars);
    assert!(vars.iter().any(|v| v == "NEW_REGION"));
    b.nav(0.0, 0.0, 0.0, 1.0, 0.0);
    b.post(5.0, "NEW_REGION", "0,0 : 0,20 : 20,20 : 20,0");
    let (_, out) = b.run(5.0);
    let core = posted(&out, "VIEW_POLYGON").unwrap().as_str().unwrap();
    assert!(
        core.starts_with("pts={0,0:0,20:20,20:20,0}") && core.contains("label=coreabe"),
        "{core}"
    );
    let mut spec = String::new();
    assert!(b.bhv.macro_value("CORE_POLY", &mut spec));
    assert!(spec.starts_with("pts={0,0:0,20:20,20:20,0}"), "{spec}");
}

#[test]
fn distance_and_margin_macros() {
    let mut b = opreg(&[("core_poly", CORE), ("max_depth", "20"), ("max_time", "60")]);
    b.nav(70.0, 0.0, 270.0, 1.0, 7.5);
    b.run(10.0);
    b.run(25.0);
    let m = |b: &Bhv, name: &str| {
        let mut s = String::new();
        assert!(b.bhv.macro_value(name, &mut s), "{name}");
        s
    };
    assert_eq!(m(&b, "DIST_TO_CORE"), "20");
    assert_eq!(
        m(&b, "TRAJ_DIST_TO_CORE"),
        "20",
        "the C++ gives the plain distance"
    );
    assert_eq!(
        m(&b, "ETA_TO_CORE"),
        "5",
        "20 m at the domain's top speed, 4 m/s"
    );
    assert_eq!(m(&b, "DEPTH_LEFT"), "12", "whole metres");
    assert_eq!(m(&b, "TIME_LEFT"), "45");
    assert_eq!(m(&b, "SAVE_DIST"), "-1");
    let mut s = String::new();
    assert!(
        !b.bhv.macro_value("ALT_LEFT", &mut s),
        "no min_altitude: not expanded"
    );
}
