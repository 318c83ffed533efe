//! BHV_HSLine and BHV_BearingLine as MOOS-IvP a2a9b716: no objective function, the VIEW_*
//! strings the C++ posts, their value rules.

mod support;

use behaviors::{ParamError, Value};
use support::{Bhv, posted, posted_all, uuv_domain};

fn text(v: Option<&Value>) -> &str {
    v.and_then(Value::as_str).expect("a string posting")
}

#[test]
fn hsline_draws_the_desired_heading_and_scaled_speed() {
    let mut b = Bhv::new("BHV_HSLine", "hsl", uuv_domain()).config(&[("time_on_leg", "10")]);
    assert_eq!(b.bhv.default_name(), "bhv_hsline");
    // Before any run nothing is erased.
    assert!(posted(&b.idle(0.0), "VIEW_SEGLIST").is_none());
    b.num("NAV_X", 10.0)
        .num("NAV_Y", 20.0)
        .num("DESIRED_HEADING", 90.0)
        .num("DESIRED_SPEED", 2.0);
    let (f, out) = b.run(1.0);
    assert!(f.is_none(), "HSLine never returns a function");
    // First run: max speed seen 2, pct 2/2 = 1, length 2 * 10 = 20 m east of 10,20.
    assert_eq!(
        text(posted(&out, "VIEW_SEGLIST")),
        "pts={10,20:30,20},active=true,label=abe_hsl"
    );
    // Speed 1 after 2: pct 1/2, speed 0.5, length 5 m; heading 45: sin = cos = 0.70711,
    // end 10 + 3.536, 20 + 3.536, written with one decimal.
    b.num("DESIRED_SPEED", 1.0).num("DESIRED_HEADING", 45.0);
    let (_, out) = b.run(2.0);
    assert_eq!(
        text(posted(&out, "VIEW_SEGLIST")),
        "pts={10,20:13.5,23.5},active=true,label=abe_hsl"
    );
    // Idle: the last line, erased.
    assert_eq!(
        text(posted(&b.idle(3.0), "VIEW_SEGLIST")),
        "pts={10,20:13.5,23.5},active=false,label=abe_hsl"
    );
}

#[test]
fn hsline_warns_for_each_missing_variable_and_reads_zero() {
    let mut b = Bhv::new("BHV_HSLine", "hsl", uuv_domain()).config(&[]);
    let (_, out) = b.run(0.0);
    let w: Vec<&str> = posted_all(&out, "BHV_WARNING")
        .into_iter()
        .filter_map(Value::as_str)
        .collect();
    assert_eq!(
        w,
        [
            "hsl: No DESIRED_HEADING info in the info_buffer",
            "hsl: No DESIRED_SPEED info in the info_buffer",
            "hsl: No NAV_X info in the info_buffer",
            "hsl: No NAV_Y info in the info_buffer",
        ]
    );
    assert_eq!(
        text(posted(&out, "VIEW_SEGLIST")),
        "pts={0,0:0,0},active=true,label=abe_hsl"
    );
}

#[test]
fn hsline_time_on_leg_must_be_a_positive_number() {
    let mut b = Bhv::new("BHV_HSLine", "hsl", uuv_domain());
    b.set("time_on_leg", "0.5").unwrap();
    for v in ["0", "-5", "ten", "1e2", ""] {
        assert!(
            matches!(b.set("time_on_leg", v), Err(ParamError::BadValue { .. })),
            "time_on_leg = {v}"
        );
    }
}

#[test]
fn bearing_line_points_part_way_to_the_bearing_point() {
    let mut b = Bhv::new("BHV_BearingLine", "bng", uuv_domain())
        .config(&[("bearing_point", "100.4,-49.6"), ("line_pct", "25")]);
    assert_eq!(b.bhv.default_name(), "bhv_bngline");
    b.num("NAV_X", 0.0).num("NAV_Y", 0.0);
    let (f, out) = b.run(0.0);
    assert!(f.is_none());
    // Distance hypot(100.4, 49.6) = 111.98; a quarter of it, 27.996 m, toward the point
    // (bearing 116.29 deg): end 27.996 * (100.4 / 111.98), 27.996 * (-49.6 / 111.98)
    // = 25.1, -12.4.
    assert_eq!(
        text(posted(&out, "VIEW_SEGLIST")),
        "pts={0,0:25.1,-12.4},label=abe_bng"
    );
    // The point keeps its two decimals; its label is x,y rounded to integers.
    assert_eq!(
        text(posted(&out, "VIEW_POINT")),
        "x=100.4,y=-49.6,label=100,-50"
    );
    // Idle: both erased.
    let out = b.idle(1.0);
    assert_eq!(
        text(posted(&out, "VIEW_SEGLIST")),
        "pts={0,0:25.1,-12.4},active=false,label=abe_bng"
    );
    assert_eq!(
        text(posted(&out, "VIEW_POINT")),
        "x=100.4,y=-49.6,active=false,label=100,-50"
    );
}

#[test]
fn bearing_line_hidden_point_and_missing_nav() {
    let mut b = Bhv::new("BHV_BearingLine", "bng", uuv_domain())
        .config(&[("bearing_point", "0,40"), ("show_pt", "false")]);
    // Before any run the line erase has no points: `active=false` alone.
    assert_eq!(text(posted(&b.idle(0.0), "VIEW_SEGLIST")), "active=false");
    let (_, out) = b.run(1.0);
    assert_eq!(posted_all(&out, "BHV_WARNING").len(), 2);
    // NAV read as 0,0: half of the 40 m north.
    assert_eq!(
        text(posted(&out, "VIEW_SEGLIST")),
        "pts={0,0:0,20},label=abe_bng"
    );
    assert_eq!(
        text(posted(&out, "VIEW_POINT")),
        "x=0,y=40,active=false,label=0,40"
    );
}

#[test]
fn bearing_line_values_are_clipped_or_refused_as_the_cpp() {
    let mut b = Bhv::new("BHV_BearingLine", "bng", uuv_domain());
    b.set("line_pct", "150").unwrap();
    b.set("line_pct", "-1").unwrap();
    b.set("show_pt", "toggle").unwrap();
    b.set("bearing_point", "x=5,y=6,vertex_color=red").unwrap();
    for (p, v) in [
        ("line_pct", "half"),
        ("show_pt", "maybe"),
        ("bearing_point", "nowhere"),
        ("bearing_point", ""),
    ] {
        assert!(
            matches!(b.set(p, v), Err(ParamError::BadValue { .. })),
            "{p} = {v}"
        );
    }
}
