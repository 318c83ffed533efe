//! Property tests: parsers never panic on random input, parse(spec(x)) == x round trips, and
//! angle / distance identities.

use geometry::angle::{angle_at_vertex, angle_diff};
use geometry::pattern::Lawnmower;
use geometry::spec::{parse_point, parse_polygon, parse_seglist, parse_waypoints};
use geometry::{
    Attributes, Point, Polygon, SegList, Segment, ViewPoint, ViewPolygon, ViewSegList, angle_180,
    angle_360, project_point, relative_angle,
};
use proptest::prelude::*;

fn hundredths() -> impl Strategy<Value = f64> {
    (-10_000_000i64..10_000_000).prop_map(|n| n as f64 / 100.0)
}

fn word() -> impl Strategy<Value = String> {
    "[A-Za-z_][A-Za-z0-9_' ]{0,10}[A-Za-z0-9_]"
}

fn attributes() -> impl Strategy<Value = Attributes> {
    (
        (
            any::<bool>(),
            proptest::option::of(word()),
            proptest::option::of(word()),
            proptest::option::of(word()),
        ),
        (
            proptest::option::of("[a-z_]{1,12}"),
            proptest::option::of("[a-z_]{1,12}"),
            proptest::option::of("[a-z_]{1,12}"),
        ),
        (
            proptest::option::of(hundredths()),
            proptest::option::of(prop_oneof![
                Just(-1.0),
                (0i64..100_000).prop_map(|n| n as f64 / 100.0)
            ]),
            proptest::option::of((0i64..1000).prop_map(|n| n as f64 / 10.0)),
            proptest::option::of((0i64..1000).prop_map(|n| n as f64 / 10.0)),
            proptest::option::of((0i64..=100).prop_map(|n| n as f64 / 100.0)),
        ),
    )
        .prop_map(
            |(
                (active, label, msg, source),
                (lc, ec, vc),
                (time, duration, vsize, esize, trans),
            )| Attributes {
                active,
                label: label.unwrap_or_default(),
                msg: msg.unwrap_or_default(),
                source: source.unwrap_or_default(),
                label_color: lc,
                edge_color: ec,
                vertex_color: vc,
                time,
                duration,
                vertex_size: vsize,
                edge_size: esize,
                fill_transparency: trans,
                ..Attributes::default()
            },
        )
}

/// Random strings built from the tokens the parsers care about, to reach deep branches.
fn geometry_soup() -> impl Strategy<Value = String> {
    let token = prop_oneof![
        Just("pts={".to_string()),
        Just("}".to_string()),
        Just("format=".to_string()),
        Just("radial".to_string()),
        Just("radial::".to_string()),
        Just("radial:".to_string()),
        Just("lawnmower".to_string()),
        Just("bowtie".to_string()),
        Just("ellipse".to_string()),
        Just("wedge:".to_string()),
        Just("rangewedge".to_string()),
        Just("oval:".to_string()),
        Just("pylon".to_string()),
        Just("zigzag:".to_string()),
        Just("label".to_string()),
        Just("active=false".to_string()),
        Just("x=".to_string()),
        Just("y=".to_string()),
        Just("pts=".to_string()),
        Just("radius=".to_string()),
        Just("width=".to_string()),
        Just("height=".to_string()),
        Just("swath=".to_string()),
        Just("lang=".to_string()),
        Just("rang=".to_string()),
        Just("range=".to_string()),
        Just("major=".to_string()),
        Just("minor=".to_string()),
        Just("degs=".to_string()),
        Just(",".to_string()),
        Just(":".to_string()),
        Just("=".to_string()),
        Just(" ".to_string()),
        Just("\"".to_string()),
        (-1000i32..1000).prop_map(|n| n.to_string()),
        (-100i32..100).prop_map(|n| format!("{}.5", n)),
        "[a-z{}$()]{1,3}",
    ];
    proptest::collection::vec(token, 0..24).prop_map(|v| v.concat())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn parsers_never_panic_on_arbitrary_text(s in ".{0,80}") {
        let _ = parse_point(&s);
        let _ = parse_seglist(&s);
        let _ = parse_polygon(&s);
        let _ = parse_waypoints(&s, 0.0, 0.0);
    }

    #[test]
    fn parsers_never_panic_on_token_soup(s in geometry_soup()) {
        let _ = parse_point(&s);
        let _ = parse_seglist(&s);
        let _ = parse_polygon(&s);
        let _ = parse_waypoints(&s, 1.0, -1.0);
    }

    #[test]
    fn view_point_round_trip(x in hundredths(), y in hundredths(), z in hundredths(),
                             trans in (0i64..=100).prop_map(|n| n as f64 / 100.0), attrs in attributes()) {
        let vp = ViewPoint { point: Point::new_3d(x, y, z), trans, attrs, precision: 2 };
        let s = vp.to_spec();
        prop_assert_eq!(parse_point(&s).unwrap(), vp, "{}", s);
    }

    #[test]
    fn view_seglist_round_trip(pts in proptest::collection::vec((hundredths(), hundredths(), hundredths(), proptest::option::of("[a-z][a-z0-9_]{0,6}")), 1..12),
                               attrs in attributes()) {
        let mut sl = SegList::new();
        for (x, y, z, prop) in pts {
            sl.push_with_prop(Point::new_3d(x, y, z), prop.unwrap_or_default());
        }
        let v = ViewSegList { seglist: sl, attrs, precision: 2 };
        let s = v.to_spec();
        // Precision is an output setting, not part of the text: parsed specs get the default.
        let mut back = parse_seglist(&s).unwrap();
        prop_assert_eq!(back.precision, 1);
        back.precision = 2;
        prop_assert_eq!(back, v, "{}", s);
    }

    #[test]
    fn view_polygon_round_trip(cx in hundredths(), cy in hundredths(), r in 1i64..100_000, n in 3u32..40,
                               rot in 0.0f64..360.0, attrs in attributes()) {
        let r = r as f64 / 100.0;
        let pts: Vec<Point> = (0..n)
            .map(|i| project_point(cx, cy, rot + 360.0 * f64::from(i) / f64::from(n), r).snapped(0.01))
            .collect();
        let poly = Polygon::new(pts);
        prop_assume!(poly.is_convex());
        let v = ViewPolygon { polygon: poly, attrs, precision: 2 };
        let s = v.to_spec();
        let mut back = parse_polygon(&s).unwrap();
        back.precision = 2;
        prop_assert_eq!(back.to_spec(), s.clone());
        prop_assert_eq!(back.polygon.len(), v.polygon.len());
        for (a, b) in back.polygon.vertices().iter().zip(v.polygon.vertices()) {
            prop_assert!((a.x - b.x).abs() < 1e-6 && (a.y - b.y).abs() < 1e-6, "{}", s);
        }
        prop_assert_eq!(back.attrs, v.attrs);
    }

    #[test]
    fn angle_normalisation_ranges(a in -1.0e6f64..1.0e6) {
        let a360 = angle_360(a);
        prop_assert!((0.0..360.0).contains(&a360));
        let a180 = angle_180(a);
        prop_assert!(a180 > -180.0 && a180 <= 180.0);
        // Same direction: differ by a multiple of 360 (up to rounding).
        prop_assert!(angle_diff(a360, a) < 1e-6);
        prop_assert!(angle_diff(a180, a360) < 1e-9);
        prop_assert!(angle_diff(a360 + 360.0, a360) < 1e-9);
    }

    #[test]
    fn project_then_bearing_recovers_heading(x in -1e4f64..1e4, y in -1e4f64..1e4, h in -720.0f64..720.0, d in 0.01f64..1e4) {
        let p = project_point(x, y, h, d);
        let b = relative_angle(x, y, p.x, p.y);
        prop_assert!((0.0..360.0).contains(&b));
        prop_assert!(angle_diff(b, h) < 1e-6, "h={} b={}", h, b);
        prop_assert!((Point::new(x, y).dist(&p) - d).abs() < 1e-6 * d.max(1.0));
    }

    #[test]
    fn angle_diff_symmetric_and_bounded(a in -1e4f64..1e4, b in -1e4f64..1e4) {
        let d = angle_diff(a, b);
        prop_assert!((0.0..=180.0).contains(&d));
        prop_assert_eq!(d, angle_diff(b, a));
    }

    #[test]
    fn segment_distance_and_intersection(x1 in -100.0f64..100.0, y1 in -100.0f64..100.0, x2 in -100.0f64..100.0, y2 in -100.0f64..100.0,
                                          x3 in -100.0f64..100.0, y3 in -100.0f64..100.0, x4 in -100.0f64..100.0, y4 in -100.0f64..100.0) {
        let s = Segment::from_xy(x1, y1, x2, y2);
        let t = Segment::from_xy(x3, y3, x4, y4);
        let d = s.dist_to_point(x3, y3);
        prop_assert!(d <= s.a.dist(&Point::new(x3, y3)) + 1e-9);
        prop_assert!(d <= s.b.dist(&Point::new(x3, y3)) + 1e-9);
        let c = s.closest_point(x3, y3);
        prop_assert!(s.dist_to_point(c.x, c.y) < 1e-9);
        prop_assert_eq!(s.crosses(&t), t.crosses(&s));
        if let Some(p) = s.intersection(&t) {
            prop_assert!(s.dist_to_point(p.x, p.y) < 1e-6 && t.dist_to_point(p.x, p.y) < 1e-6);
            prop_assert_eq!(s.dist_to_segment(&t), 0.0);
        } else {
            prop_assert!(s.dist_to_segment(&t) > 0.0);
        }
        // The capture-line test and the vertex angle agree.
        let passed = s.passed_end(x3, y3);
        let ang = angle_at_vertex(x1, y1, x2, y2, x3, y3);
        if ang > 90.0 + 1e-6 { prop_assert!(passed); }
        if ang < 90.0 - 1e-6 && ang > 0.0 { prop_assert!(!passed); }
    }

    #[test]
    fn regular_polygons_contain_centre_and_not_far_points(cx in -1e3f64..1e3, cy in -1e3f64..1e3, r in 1.0f64..500.0, n in 3u32..64) {
        let pts: Vec<Point> = (0..n).map(|i| project_point(cx, cy, 360.0 * f64::from(i) / f64::from(n), r)).collect();
        let p = Polygon::new(pts);
        prop_assert!(p.is_convex());
        prop_assert!(p.contains(cx, cy));
        prop_assert!(!p.contains(cx + 2.0 * r, cy));
        let sd = p.signed_distance(cx, cy).unwrap();
        // Inside, by the apothem r*cos(180/n).
        let apothem = r * (std::f64::consts::PI / f64::from(n)).cos();
        prop_assert!((sd + apothem).abs() < 1e-6 * r, "sd={} apothem={}", sd, apothem);
        let c = p.centroid();
        prop_assert!((c.x - cx).abs() < 1e-6 * r && (c.y - cy).abs() < 1e-6 * r);
        for v in p.vertices() {
            prop_assert!(p.contains(v.x, v.y));
        }
    }

    #[test]
    fn lawnmower_lanes_have_block_length(width in 1.0f64..300.0, height in 1.0f64..300.0, swath in 1.0f64..50.0, degs in -180.0f64..180.0) {
        let mut m = Lawnmower::new(0.0, 0.0, width, height, swath);
        m.degs = degs;
        m.snap = 0.0;
        let v = m.vertices().unwrap();
        let lanes = ((height / swath) + 1.0 + 0.99999).trunc() as usize;
        prop_assert_eq!(v.len(), 2 * lanes);
        for pair in v.chunks(2) {
            prop_assert!((pair[0].dist(&pair[1]) - width).abs() < 1e-6);
        }
    }
}
