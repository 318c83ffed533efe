//! The scene from MOOS mail: vehicles, staleness, VIEW_* objects, appcasts, deltas.

use mission::buttons::buttons;
use serde_json::Value;
use viewer::scene::{Rejected, Scene, SceneConfig, ShapeKind};

fn scene() -> Scene {
    Scene::new(SceneConfig::default(), Vec::new())
}

const ABE: &str = "NAME=abe,X=10.5,Y=-20.25,SPD=1.5,HDG=90,DEP=3,LAT=43.8,LON=-70.3,TYPE=UUV,\
                   COLOR=yellow,MODE=MODE@ACTIVE:SURVEYING,ALLSTOP=clear,TIME=1000";

#[test]
fn node_report_makes_a_vehicle() {
    let mut s = scene();
    s.apply("NODE_REPORT_LOCAL", ABE, 100.0).unwrap();
    let v = &s.vehicles()["abe"];
    assert_eq!(v.report.x_m, Some(10.5));
    assert_eq!(v.report.y_m, Some(-20.25));
    assert_eq!(v.report.heading_deg, Some(90.0));
    assert_eq!(v.report.speed_mps, Some(1.5));
    assert_eq!(v.report.depth_m, Some(3.0));
    assert_eq!(v.report.mode, "MODE@ACTIVE:SURVEYING");
    assert_eq!(v.helm_state(), "DRIVE");
    assert!(!v.stale);
    let snap = s.snapshot();
    let j = &snap["vehicles"][0];
    assert_eq!(j["name"], "abe");
    assert_eq!(j["x"], 10.5);
    assert_eq!(j["helm"], "DRIVE");
    assert_eq!(j["trail"], serde_json::json!([[10.5, -20.25]]));
    assert_eq!(
        s.apply("NODE_REPORT", "X=1,Y=2", 101.0),
        Err(Rejected::NoName)
    );
}

#[test]
fn helm_state_from_mode() {
    let mut s = scene();
    for (mode, state) in [
        ("NOHELM-EVER", "NOHELM"),
        ("NOHELM-12", "NOHELM"),
        ("PARK", "PARK"),
        ("MALCONFIG", "MALCONFIG"),
        ("DRIVE", "DRIVE"),
    ] {
        s.apply("NODE_REPORT", &format!("NAME=b,X=0,Y=0,MODE={mode}"), 1.0)
            .unwrap();
        assert_eq!(s.vehicles()["b"].helm_state(), state, "{mode}");
    }
}

#[test]
fn trail_is_bounded() {
    let mut s = Scene::new(
        SceneConfig {
            trail_max: 3,
            ..SceneConfig::default()
        },
        Vec::new(),
    );
    for i in 0..5 {
        s.apply("NODE_REPORT", &format!("NAME=abe,X={i},Y=0"), i as f64)
            .unwrap();
    }
    let trail: Vec<(f64, f64)> = s.vehicles()["abe"].trail().collect();
    assert_eq!(trail, vec![(2.0, 0.0), (3.0, 0.0), (4.0, 0.0)]);
}

#[test]
fn stale_vehicles_are_greyed_then_removed() {
    let mut s = scene();
    s.apply("NODE_REPORT", ABE, 100.0).unwrap();
    s.tick(160.0);
    assert!(!s.vehicles()["abe"].stale, "60 s is not yet stale");
    let v = s.version();
    s.tick(160.5);
    assert!(s.vehicles()["abe"].stale);
    let d = s.delta_since(v).unwrap();
    assert_eq!(d["type"], "delta");
    assert_eq!(d["vehicles"][0]["stale"], true);
    assert_eq!(d["vehicles"][0]["trail_add"], serde_json::json!([]));
    // A new report makes it fresh again.
    s.apply("NODE_REPORT", ABE, 170.0).unwrap();
    assert!(!s.vehicles()["abe"].stale);
    s.tick(170.0 + 240.0);
    assert!(s.vehicles()["abe"].stale);
    let v = s.version();
    s.tick(170.0 + 240.5);
    assert!(s.vehicles().is_empty());
    assert_eq!(
        s.delta_since(v).unwrap()["removed_vehicles"],
        serde_json::json!(["abe"])
    );
}

#[test]
fn polygon_added_replaced_and_removed() {
    let mut s = scene();
    s.apply(
        "VIEW_POLYGON",
        "pts={0,0:10,0:10,10},label=ops,edge_color=red",
        1.0,
    )
    .unwrap();
    let p = s.shape(ShapeKind::Polygon, "ops").unwrap();
    assert_eq!(
        p.fields["pts"],
        serde_json::json!([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]])
    );
    assert_eq!(p.fields["edge_color"], "#ff0000");
    let v = s.version();
    s.apply("VIEW_POLYGON", "pts={0,0:20,0:20,20:0,20},label=ops", 2.0)
        .unwrap();
    assert_eq!(s.shape_count(), 1, "same label replaces");
    let p = s.shape(ShapeKind::Polygon, "ops").unwrap();
    assert_eq!(p.fields["pts"].as_array().unwrap().len(), 4);
    let d = s.delta_since(v).unwrap();
    assert_eq!(d["shapes"][0]["key"], "ops");
    assert_eq!(d["shapes"][0]["kind"], "polygon");
    // Another kind with the same label is another object.
    s.apply("VIEW_SEGLIST", "pts={0,0:5,5},label=ops", 3.0)
        .unwrap();
    assert_eq!(s.shape_count(), 2);
    let v = s.version();
    s.apply("VIEW_POLYGON", "label=ops,active=false", 4.0)
        .unwrap();
    assert!(s.shape(ShapeKind::Polygon, "ops").is_none());
    assert!(s.shape(ShapeKind::SegList, "ops").is_some());
    let d = s.delta_since(v).unwrap();
    assert_eq!(d["removed_shapes"], serde_json::json!([["polygon", "ops"]]));
    assert!(matches!(
        s.apply("VIEW_POLYGON", "pts={0,0:oops},label=x", 5.0),
        Err(Rejected::BadShape(_))
    ));
}

#[test]
fn other_view_kinds_keep_their_fields_and_expire() {
    let mut s = scene();
    s.apply(
        "VIEW_CIRCLE",
        "x=5,y=6,radius=20,label=c,edge_color=white",
        1.0,
    )
    .unwrap();
    s.apply("VIEW_MARKER", "type=diamond,x=1,y=2,label=m,width=4", 1.0)
        .unwrap();
    s.apply("MARKER", "type=circle,x=3,y=4,label=m2", 1.0)
        .unwrap();
    s.apply("VIEW_VECTOR", "x=1,y=2,mag=3,ang=45,label=v", 1.0)
        .unwrap();
    s.apply("VIEW_ARROW", "cx=1,cy=2,angle=10,label=a", 1.0)
        .unwrap();
    s.apply(
        "VIEW_COMMS_PULSE",
        "sx=0,sy=0,tx=10,ty=10,beam=0.1,duration=5,label=cp",
        1.0,
    )
    .unwrap();
    s.apply(
        "VIEW_RANGE_PULSE",
        "x=0,y=0,radius=40,duration=10,label=rp",
        1.0,
    )
    .unwrap();
    s.apply("VIEW_POINT", "x=7,y=8,label=p,vertex_size=4", 1.0)
        .unwrap();
    let c = s.shape(ShapeKind::Circle, "c").unwrap();
    assert_eq!(c.fields["radius"], 20.0);
    assert_eq!(c.fields["edge_color"], "#ffffff");
    assert_eq!(
        s.shape(ShapeKind::Marker, "m").unwrap().fields["type"],
        "diamond"
    );
    assert!(s.shape(ShapeKind::Marker, "m2").is_some());
    assert_eq!(s.shape(ShapeKind::Vector, "v").unwrap().fields["ang"], 45.0);
    assert_eq!(s.shape(ShapeKind::Point, "p").unwrap().fields["x"], 7.0);
    assert_eq!(s.shape_count(), 8);
    s.tick(6.5);
    assert!(
        s.shape(ShapeKind::CommsPulse, "cp").is_none(),
        "duration 5 ended"
    );
    assert!(s.shape(ShapeKind::RangePulse, "rp").is_some());
    s.tick(11.5);
    assert!(s.shape(ShapeKind::RangePulse, "rp").is_none());
    assert_eq!(s.shape_count(), 6);
}

#[test]
fn unlabelled_objects_are_bounded() {
    let mut s = Scene::new(
        SceneConfig {
            max_unlabeled: 4,
            ..SceneConfig::default()
        },
        Vec::new(),
    );
    for i in 0..10 {
        s.apply("VIEW_POINT", &format!("x={i},y=0"), 1.0).unwrap();
    }
    assert_eq!(s.shape_count(), 4);
}

#[test]
fn appcast_stored_per_node_and_app() {
    let mut cast = appcast::AppCast::new();
    cast.set_node_name("abe");
    cast.set_proc_name("pHelmIvP");
    cast.set_iteration(7);
    cast.set_messages("helm is driving");
    let mut s = scene();
    s.apply("APPCAST", &cast.to_moos_string(), 1.0).unwrap();
    cast.set_proc_name("uSimMarine");
    cast.set_messages("sim report");
    s.apply("APPCAST", &cast.to_moos_string(), 1.0).unwrap();
    cast.set_node_name("ben");
    s.apply("APPCAST", &cast.to_moos_string(), 1.0).unwrap();
    assert_eq!(
        s.appcast("abe", "pHelmIvP").unwrap().messages().trim_end(),
        "helm is driving"
    );
    assert_eq!(
        s.appcast("abe", "uSimMarine")
            .unwrap()
            .messages()
            .trim_end(),
        "sim report"
    );
    assert!(s.appcast("ben", "uSimMarine").is_some());
    assert!(s.appcast("ben", "pHelmIvP").is_none());
    // The newest replaces the older one of the same node and app.
    cast.set_messages("newer");
    cast.set_iteration(8);
    let v = s.version();
    s.apply("APPCAST", &cast.to_moos_string(), 2.0).unwrap();
    assert_eq!(
        s.appcast("ben", "uSimMarine")
            .unwrap()
            .messages()
            .trim_end(),
        "newer"
    );
    let d = s.delta_since(v).unwrap();
    assert_eq!(d["appcasts"].as_array().unwrap().len(), 1);
    assert_eq!(d["appcasts"][0]["node"], "ben");
    assert_eq!(d["appcasts"][0]["iteration"], 8);
    assert!(
        d["appcasts"][0]["report"]
            .as_str()
            .unwrap()
            .contains("newer")
    );
    assert_eq!(s.nodes(), vec!["abe", "ben"]);
}

#[test]
fn deltas_carry_only_the_newest_state() {
    let mut s = scene();
    s.apply("NODE_REPORT", "NAME=abe,X=0,Y=0", 1.0).unwrap();
    let v = s.version();
    assert_eq!(s.delta_since(v), None, "nothing changed");
    for i in 1..=5 {
        s.apply(
            "NODE_REPORT",
            &format!("NAME=abe,X={i},Y=0"),
            1.0 + i as f64,
        )
        .unwrap();
    }
    let d = s.delta_since(v).unwrap();
    let vs = d["vehicles"].as_array().unwrap();
    assert_eq!(vs.len(), 1, "one vehicle, its newest state");
    assert_eq!(vs[0]["x"], 5.0);
    let added: Vec<f64> = vs[0]["trail_add"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p[0].as_f64().unwrap())
        .collect();
    assert_eq!(added, vec![1.0, 2.0, 3.0, 4.0, 5.0]);
    assert_eq!(d["version"], s.version());
}

#[test]
fn a_client_older_than_the_tombstones_gets_a_snapshot() {
    let mut s = Scene::new(
        SceneConfig {
            max_tombstones: 2,
            ..SceneConfig::default()
        },
        Vec::new(),
    );
    for i in 0..4 {
        s.apply("VIEW_POINT", &format!("x=0,y=0,label=p{i}"), 1.0)
            .unwrap();
    }
    let v = s.version();
    for i in 0..4 {
        s.apply(
            "VIEW_POINT",
            &format!("x=0,y=0,label=p{i},active=false"),
            1.0,
        )
        .unwrap();
    }
    let d: Value = s.delta_since(v).unwrap();
    assert_eq!(d["type"], "snapshot");
    assert_eq!(d["shapes"], serde_json::json!([]));
}

#[test]
fn snapshot_lists_the_buttons() {
    let src = mission::source::SourceMap::from_text(
        "m.moos",
        "ProcessConfig = pMarineViewer\n{\n  button_one = DEPLOY # DEPLOY=true # MOOS_MANUAL_OVERRIDE=false\n  button_two = RETURN # RETURN=true # SPEED=1.5\n}\n",
    );
    let m = mission::moos::parse_moos(&src).value;
    let s = Scene::new(SceneConfig::default(), buttons(&m));
    let snap = s.snapshot();
    assert_eq!(snap["buttons"][0]["label"], "DEPLOY");
    assert_eq!(
        snap["buttons"][0]["postings"],
        serde_json::json!([["DEPLOY", "true"], ["MOOS_MANUAL_OVERRIDE", "false"]])
    );
    assert_eq!(
        snap["buttons"][1]["postings"][1],
        serde_json::json!(["SPEED", "1.5"])
    );
}

/// Pulses carry their start and a duration (pMarineViewer's defaults when not given: range
/// 15 s, comms 3 s), start at their `time=` when given, and leave after `duration` (plus a
/// range pulse's `linger`).
#[test]
fn pulses_start_at_their_time_and_end_after_their_duration() {
    let mut s = scene();
    s.apply("VIEW_RANGE_PULSE", "x=1,y=2,label=r", 10.0)
        .unwrap();
    s.apply("VIEW_COMMS_PULSE", "sx=0,sy=0,tx=5,ty=5,label=c", 10.0)
        .unwrap();
    s.apply(
        "VIEW_RANGE_PULSE",
        "x=1,y=2,radius=50,duration=4,linger=2,time=8,label=late",
        10.0,
    )
    .unwrap();
    let r = s.shape(ShapeKind::RangePulse, "r").unwrap();
    assert_eq!(
        (r.fields["t0"].as_f64(), r.fields["duration"].as_f64()),
        (Some(10.0), Some(15.0))
    );
    let c = s.shape(ShapeKind::CommsPulse, "c").unwrap();
    assert_eq!(
        (c.fields["t0"].as_f64(), c.fields["duration"].as_f64()),
        (Some(10.0), Some(3.0))
    );
    let late = s.shape(ShapeKind::RangePulse, "late").unwrap();
    assert_eq!(
        (late.fields["t0"].as_f64(), late.fields["duration"].as_f64()),
        (Some(8.0), Some(4.0))
    );
    s.tick(13.5);
    assert!(
        s.shape(ShapeKind::CommsPulse, "c").is_none(),
        "3 s after 10"
    );
    assert!(
        s.shape(ShapeKind::RangePulse, "late").is_some(),
        "lingers to 14"
    );
    s.tick(14.5);
    assert!(
        s.shape(ShapeKind::RangePulse, "late").is_none(),
        "8 + 4 + 2"
    );
    s.tick(24.5);
    assert!(s.shape(ShapeKind::RangePulse, "r").is_some());
    s.tick(25.5);
    assert!(
        s.shape(ShapeKind::RangePulse, "r").is_none(),
        "15 s after 10"
    );
}

/// Each vehicle's depth and speed are kept for the strip chart: points a second apart and
/// the newest, over the last `history_s` seconds, and the whole of it in a snapshot only.
#[test]
fn depth_and_speed_history_is_kept_for_the_chart() {
    let mut s = Scene::new(
        SceneConfig {
            history_s: 10.0,
            ..SceneConfig::default()
        },
        Vec::new(),
    );
    for k in 0..=40 {
        let t = f64::from(k) * 0.5;
        s.apply(
            "NODE_REPORT",
            &format!("NAME=abe,X=0,Y=0,SPD={},DEP={}", t / 10.0, t),
            t,
        )
        .unwrap();
    }
    // No depth nor speed: nothing charted.
    s.apply("NODE_REPORT", "NAME=ben,X=0,Y=0", 20.0).unwrap();
    let h: Vec<[f64; 3]> = s.vehicles()["abe"].history().collect();
    // Points at 10, 11, ..., 19 and the newest, 20 (19.5 gave way to it): 11 points.
    assert_eq!(h.len(), 11, "{h:?}");
    assert_eq!(h[0], [10.0, 10.0, 1.0]);
    assert_eq!(h[10], [20.0, 20.0, 2.0]);
    assert!(h.windows(2).all(|w| w[1][0] - w[0][0] >= 1.0 - 1e-9));
    assert_eq!(s.vehicles()["ben"].history().count(), 0);
    let snap = s.snapshot();
    assert_eq!(snap["vehicles"][0]["history"].as_array().unwrap().len(), 11);
    assert_eq!(
        snap["vehicles"][0]["history"][10],
        serde_json::json!([20.0, 20.0, 2.0])
    );
    let delta = s.delta_since(s.version() - 1).unwrap();
    assert!(delta["vehicles"][0].get("history").is_none());
}

/// MOOS colours reach the page as CSS: names with underscores, `greyNN` and fractions as
/// `#rrggbb`, `off` as transparent, a report's COLOR too.
#[test]
fn moos_colours_are_handed_to_the_page_as_css() {
    let mut s = scene();
    s.apply(
        "VIEW_POLYGON",
        "pts={0,0:1,0:1,1},label=p,edge_color=Light_Blue,vertex_color=1:0.5:0,fill_color=grey50,label_color=off",
        1.0,
    )
    .unwrap();
    s.apply(
        "VIEW_MARKER",
        "x=1,y=2,label=m,color=0:0:1,primary_color=dark_green",
        1.0,
    )
    .unwrap();
    s.apply("NODE_REPORT", "NAME=abe,X=0,Y=0,COLOR=dodger_blue", 1.0)
        .unwrap();
    s.apply("NODE_REPORT", "NAME=ben,X=0,Y=0", 1.0).unwrap();
    let p = &s.shape(ShapeKind::Polygon, "p").unwrap().fields;
    assert_eq!(p["edge_color"], "#add8e6");
    assert_eq!(p["vertex_color"], "#ff8000");
    assert_eq!(p["fill_color"], "#808080");
    assert_eq!(p["label_color"], "transparent");
    let m = &s.shape(ShapeKind::Marker, "m").unwrap().fields;
    assert_eq!(m["color"], "#0000ff");
    assert_eq!(m["primary_color"], "#006400");
    let snap = s.snapshot();
    assert_eq!(snap["vehicles"][0]["color"], "#1e90ff");
    assert_eq!(
        snap["vehicles"][1]["color"], "",
        "no COLOR: the page's palette"
    );
}
