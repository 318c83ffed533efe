//! Pattern generators checked vertex-by-vertex against numbers worked out by hand from each
//! format's definition (reference `moos-apps-extra.md` §2 and the notes in `pattern.rs`).

use geometry::pattern::{
    Bowtie, Ellipse, Lawnmower, Oval, Pylon, Radial, RangeWedge, Rows, Wedge, ZigZag,
};
use geometry::spec::{parse_polygon, parse_seglist};
use geometry::{ParseError, Point};

fn assert_pts(got: &[Point], want: &[(f64, f64)], tol: f64) {
    assert_eq!(got.len(), want.len(), "vertex count: got {got:?}");
    for (i, (g, w)) in got.iter().zip(want).enumerate() {
        assert!(
            (g.x - w.0).abs() <= tol && (g.y - w.1).abs() <= tol,
            "vertex {i}: got ({}, {}), want ({}, {})",
            g.x,
            g.y,
            w.0,
            w.1
        );
    }
}

#[test]
fn lawnmower_reference_example_ew() {
    // format=lawnmower, x=0, y=0, width=100, height=60, swath=20 (rows ew, start 0,0):
    // bw=60, bl=100, angle=90, lanes at y=30,10,-10,-30; all four outer ends are equidistant
    // from the start so the first (lane 0, east end) wins.
    let v = parse_seglist("format=lawnmower, x=0, y=0, width=100, height=60, swath=20").unwrap();
    let want = [
        (50.0, 30.0),
        (-50.0, 30.0),
        (-50.0, 10.0),
        (50.0, 10.0),
        (50.0, -10.0),
        (-50.0, -10.0),
        (-50.0, -30.0),
        (50.0, -30.0),
    ];
    assert_pts(v.seglist.points(), &want, 1e-9);
    // Snap 0.00001 is always applied; with precision 1 the spec is the plain integers.
    assert_eq!(
        v.to_spec(),
        "pts={50,30:-50,30:-50,10:50,10:50,-10:-50,-10:-50,-30:50,-30}"
    );
}

#[test]
fn lawnmower_ns_entry_on_last_lane_reverses_lanes() {
    // rows=ns, width 40 => bw=40, bl=100, angle 0; lanes x=-20, 0, 20 (lane 0 on bearing 270).
    // Start (100,-100): nearest outer end is (20,-50), the last lane's south end.
    let v = parse_seglist(
        "format=lawnmower,x=0,y=0,width=40,height=100,lane_width=20,rows=ns,startx=100,starty=-100",
    )
    .unwrap();
    let want = [
        (20.0, -50.0),
        (20.0, 50.0),
        (0.0, 50.0),
        (0.0, -50.0),
        (-20.0, -50.0),
        (-20.0, 50.0),
    ];
    assert_pts(v.seglist.points(), &want, 1e-9);
}

#[test]
fn lawnmower_ew_equals_ns_rotated_90() {
    let ew = Lawnmower::new(0.0, 0.0, 40.0, 20.0, 10.0)
        .vertices()
        .unwrap();
    let mut ns = Lawnmower::new(0.0, 0.0, 20.0, 40.0, 10.0);
    ns.rows = Rows::NorthSouth;
    ns.degs = 90.0;
    let ns = ns.vertices().unwrap();
    // Hand-worked: lanes at y=10,0,-10 running x=+20 -> -20, alternating.
    let want = [
        (20.0, 10.0),
        (-20.0, 10.0),
        (-20.0, 0.0),
        (20.0, 0.0),
        (20.0, -10.0),
        (-20.0, -10.0),
    ];
    assert_pts(&ew, &want, 1e-9);
    assert_pts(&ns, &want, 1e-9);
}

#[test]
fn lawnmower_ignores_angle_below_one_like_moos() {
    // XYPatternBlock::setParam ignores angle < 1: rows=ns, degs=-30 behaves like degs=0.
    let a = parse_seglist("format=lawnmower,x=5,y=5,width=30,height=50,swath=10,rows=ns,degs=-30")
        .unwrap();
    let b = parse_seglist("format=lawnmower,x=5,y=5,width=30,height=50,swath=10,rows=ns").unwrap();
    assert_eq!(a.seglist, b.seglist);
    let c = parse_seglist("format=lawnmower,x=5,y=5,width=30,height=50,swath=10,rows=ns,degs=0.5")
        .unwrap();
    assert_eq!(a.seglist, c.seglist);
}

#[test]
fn lawnmower_corpus_rotated_survey() {
    // s4_delta: x=80, y=-80, width=70, height=30, lane_width=8, rows=north-south, degs=30.
    // bw=70, bl=30, angle 30; lanes = trunc(70/8 + 1 + 0.99999) = 10.
    // Lane 0 centre: 35 m on bearing 300 from (80,-80) = (49.6891, -62.5);
    // its ends 15 m along 30 / 210: (57.1891, -49.5096) and (42.1891, -75.4904).
    // Lane 1 centre: 27 m on 300 = (56.6173, -66.5); second vertex is its 210 end.
    let v = parse_seglist("format=lawnmower, label=dudley_survey, x=80, y=-80, width=70, height=30, lane_width=8, rows=north-south, degs=30").unwrap();
    assert_eq!(v.seglist.len(), 20);
    assert_eq!(v.attrs.label, "dudley_survey");
    let p = v.seglist.points();
    assert_pts(
        &p[..4],
        &[
            (57.1891, -49.5096),
            (42.1891, -75.4904),
            (49.1173, -79.4904),
            (64.1173, -53.5096),
        ],
        1e-4,
    );
}

#[test]
fn lawnmower_errors() {
    assert_eq!(
        parse_seglist("format=lawnmower, x=0, y=0, width=100, swath=20").unwrap_err(),
        ParseError::Missing {
            key: "height",
            format: "lawnmower"
        }
    );
    assert!(matches!(
        parse_seglist("format=lawnmower, x=$(X), y=0, width=100, height=5, swath=20").unwrap_err(),
        ParseError::BadNumber { .. }
    ));
    assert!(matches!(
        parse_seglist("format=lawnmower, x=0, y=0, width=100, height=5, swath=0").unwrap_err(),
        ParseError::InvalidValue { .. }
    ));
    assert!(matches!(
        parse_seglist("format=lawnmower, x=0, y=0, width=1e9, height=5, swath=0.001").unwrap_err(),
        ParseError::BadNumber { .. }
    ));
    assert!(matches!(
        parse_seglist("format=lawnmower, x=0, y=0, width=5, height=10000000, swath=0.001")
            .unwrap_err(),
        ParseError::TooManyVertices(_)
    ));
}

#[test]
fn bowtie_reference_example_and_cases() {
    let v = parse_seglist(
        "format=bowtie, label=dudley_bowtie, x=80, y=-80, wid1=10, wid2=25, wid3=30, height=20",
    )
    .unwrap();
    assert_eq!(
        v.to_spec(),
        "pts={70,-90:55,-90:50,-80:55,-70:70,-70:90,-90:105,-90:110,-80:105,-70:90,-70},label=dudley_bowtie"
    );
    // Start at bearing 135 from the centre: case se, order 2,1,5,7,8,3,4,6,10,9.
    let b = Bowtie {
        x: 80.0,
        y: -80.0,
        height: 20.0,
        wid1: 10.0,
        wid2: 25.0,
        wid3: 30.0,
        start: Some(Point::new(90.0, -90.0)),
    };
    let want = [
        (70.0, -70.0),
        (55.0, -70.0),
        (50.0, -80.0),
        (55.0, -90.0),
        (70.0, -90.0),
        (90.0, -70.0),
        (105.0, -70.0),
        (110.0, -80.0),
        (105.0, -90.0),
        (90.0, -90.0),
    ];
    assert_pts(&b.vertices(), &want, 0.0);
    // Bearing 225: sw, order 3,4,6,10,9,2,1,5,7,8.
    let b = Bowtie {
        start: Some(Point::new(70.0, -90.0)),
        ..b
    };
    assert_eq!(b.vertices()[0], Point::new(90.0, -70.0));
    assert_eq!(b.vertices()[9], Point::new(70.0, -90.0));
    // Bearing 315: nw, order 9,10,6,4,3,8,7,5,1,2.
    let b = Bowtie {
        start: Some(Point::new(70.0, -70.0)),
        ..b
    };
    assert_eq!(b.vertices()[0], Point::new(90.0, -90.0));
    assert_eq!(b.vertices()[2], Point::new(110.0, -80.0));
    // Only startx given: both are needed, so the case stays ne.
    let only_x = parse_seglist(
        "format=bowtie, x=80, y=-80, wid1=10, wid2=25, wid3=30, height=20, startx=70",
    )
    .unwrap();
    assert_eq!(only_x.seglist, v.seglist);
}

#[test]
fn zigzag_positional() {
    // Axis east (90), period 40: axis distances 10, 30, 50, 70, 90; first side is angle-90 = north.
    let v = parse_seglist("zigzag: 0,0,90,100,40,10").unwrap();
    let want = [
        (0.0, 0.0),
        (10.0, 10.0),
        (30.0, -10.0),
        (50.0, 10.0),
        (70.0, -10.0),
        (90.0, 10.0),
    ];
    assert_pts(v.seglist.points(), &want, 1e-9);
    let z = ZigZag {
        startx: 0.0,
        starty: 0.0,
        angle: 0.0,
        length: 20.0,
        period: 20.0,
        amplitude: 3.0,
        snap: 1.0,
    };
    // Axis north: distances 5, 15; sides west then east.
    assert_pts(
        &z.vertices().unwrap(),
        &[(0.0, 0.0), (-3.0, 5.0), (3.0, 15.0)],
        0.0,
    );
    assert_eq!(
        parse_seglist("zigzag: 0,0,90,100,40").unwrap_err(),
        ParseError::FieldCount {
            format: "zigzag",
            expected: "6 or 7",
            found: 5
        }
    );
    assert!(matches!(
        parse_seglist("format=zigzag, startx=0").unwrap_err(),
        ParseError::Unsupported(_)
    ));
}

#[test]
fn radial_reference_example() {
    let v = parse_polygon("radial:: x=20, y=-80, radius=20, pts=8, snap=1").unwrap();
    assert_eq!(
        v.to_spec(),
        "pts={28,-62:38,-72:38,-88:28,-98:12,-98:2,-88:2,-72:12,-62}"
    );
    // Raw vertices before snapping, from the reference.
    let raw = Radial {
        x: 20.0,
        y: -80.0,
        z: 0.0,
        radius: 20.0,
        pts: 8,
        snap: 1.0,
    }
    .vertices()
    .unwrap();
    let want = [
        (27.654, -61.522),
        (38.478, -72.346),
        (38.478, -87.654),
        (27.654, -98.478),
        (12.346, -98.478),
        (1.522, -87.654),
        (1.522, -72.346),
        (12.346, -61.522),
    ];
    assert_pts(&raw, &want, 1e-3);
    // Same shape from the positional and format= forms.
    let p = parse_polygon("radial: 20,-80,20,8,1,L").unwrap();
    assert_eq!(p.polygon, v.polygon);
    assert_eq!(p.attrs.label, "L");
    let f = parse_polygon("format=radial, x=20, y=-80, radius=20, pts=8, snap=1").unwrap();
    assert_eq!(f.polygon, v.polygon);
}

#[test]
fn radial_square_shift_and_clockwise() {
    // pts=4: bearings 45, 135, 225, 315 at radius 10 round (5,0) (x=0 shifted by 5).
    let v = parse_polygon("format=radial, x=0, y=0, shiftx=5, radius=10, pts=4").unwrap();
    let r = 50f64.sqrt();
    assert_pts(
        v.polygon.vertices(),
        &[(5.0 + r, r), (5.0 + r, -r), (5.0 - r, -r), (5.0 - r, r)],
        1e-9,
    );
    assert!(v.polygon.is_clockwise());
    assert_eq!(
        parse_polygon("format=radial, x=0, y=0, radius=10, pts=2").unwrap_err(),
        ParseError::InvalidValue {
            key: "pts".into(),
            found: "2".into(),
            expected: "an integer >= 3"
        }
    );
    assert_eq!(
        parse_polygon("format=radial, x=0, y=0, radius=10, pts=6, colour=red").unwrap_err(),
        ParseError::UnknownKey {
            key: "colour".into(),
            format: "radial"
        }
    );
    assert_eq!(
        parse_polygon("format=radial, x=0, radius=10, pts=6").unwrap_err(),
        ParseError::Missing {
            key: "y",
            format: "radial"
        }
    );
}

#[test]
fn ellipse_axes_and_rotation() {
    // r=0: a = -pi, -pi/2, 0, pi/2 -> west, south, east, north (counter-clockwise).
    let e = Ellipse {
        x: 0.0,
        y: 0.0,
        z: 0.0,
        major: 20.0,
        minor: 10.0,
        rads: 0.0,
        pts: 4,
        snap: 0.0,
    };
    assert_pts(
        &e.vertices().unwrap(),
        &[(-10.0, 0.0), (0.0, -5.0), (10.0, 0.0), (0.0, 5.0)],
        1e-12,
    );
    // degs=90: the major axis turns to north-south; the -major end is south.
    let v = parse_polygon("format=ellipse, x=1, y=2, major=20, minor=10, pts=4, degs=90").unwrap();
    assert_pts(
        v.polygon.vertices(),
        &[(1.0, -8.0), (6.0, 2.0), (1.0, 12.0), (-4.0, 2.0)],
        1e-12,
    );
    assert!(!v.polygon.is_clockwise());
    // rads wins over degs.
    let r = parse_polygon("format=ellipse, x=1, y=2, major=20, minor=10, pts=4, degs=90, rads=0")
        .unwrap();
    assert!((r.polygon.vertices()[0].x - -9.0).abs() < 1e-12);
    assert_eq!(
        parse_polygon("format=ellipse, x=0, y=0, major=20, minor=10, pts=8").unwrap_err(),
        ParseError::Missing {
            key: "rads or degs",
            format: "ellipse"
        }
    );
}

#[test]
fn wedges() {
    let w = parse_polygon("format=wedge, x=0, y=0, lang=0, rang=90, range=10, pts=2").unwrap();
    let r = 50f64.sqrt();
    assert_pts(
        w.polygon.vertices(),
        &[(0.0, 0.0), (0.0, 10.0), (r, r), (10.0, 0.0)],
        1e-12,
    );
    let tri = Wedge {
        x: 0.0,
        y: 0.0,
        lang: 0.0,
        rang: 90.0,
        range: 10.0,
        pts: 0,
        snap: 0.0,
    };
    assert_pts(
        &tri.vertices().unwrap(),
        &[(0.0, 0.0), (0.0, 10.0), (10.0, 0.0)],
        0.0,
    );
    // Across north: lang 350 -> rang 370 in 10-degree steps.
    let wrap = parse_polygon("wedge: x=0, y=0, lang=350, rang=10, range=10, pts=2").unwrap();
    let p = wrap.polygon.vertices();
    assert_eq!(p.len(), 4);
    assert!((p[2].x).abs() < 1e-12 && (p[2].y - 10.0).abs() < 1e-12);
    let rw = parse_polygon(
        "format=rangewedge, x=0, y=0, lang=0, rang=90, range_min=5, range_max=10, pts=1",
    )
    .unwrap();
    assert_pts(
        rw.polygon.vertices(),
        &[(0.0, 10.0), (10.0, 0.0), (5.0, 0.0), (0.0, 5.0)],
        0.0,
    );
    let collapsed = RangeWedge {
        x: 0.0,
        y: 0.0,
        lang: 0.0,
        rang: 90.0,
        range_min: 0.0,
        range_max: 10.0,
        pts: 2,
        snap: 0.0,
    };
    assert_eq!(collapsed.polygon().unwrap_err(), ParseError::NotConvex);
}

#[test]
fn pylon_and_oval() {
    let p = parse_polygon("format=pylon, x1=0, y1=0, x2=0, y2=10, axis_pad=2, perp_pad=3").unwrap();
    assert_pts(
        p.polygon.vertices(),
        &[(-3.0, -2.0), (3.0, -2.0), (3.0, 12.0), (-3.0, 12.0)],
        1e-12,
    );
    let direct = Pylon {
        x1: 0.0,
        y1: 0.0,
        x2: 0.0,
        y2: 10.0,
        z: 0.0,
        axis_pad: 2.0,
        perp_pad: 3.0,
        snap: 0.0,
    };
    assert_eq!(direct.polygon().unwrap(), p.polygon);
    assert_eq!(
        parse_polygon("pylon: x1=0, y1=0, x2=0, y2=10, axis_pad=2").unwrap_err(),
        ParseError::Missing {
            key: "perp_pad",
            format: "pylon"
        }
    );
    // il = (30 - 10)/2 = 10: c1 = (0,10), c2 = (0,-10).
    let o = parse_polygon("oval: x=0, y=0, rad=5, len=30, ang=0, label=o").unwrap();
    let v = o.polygon.vertices();
    assert_eq!(v.len(), 26);
    assert_pts(
        &[v[0], v[6], v[12], v[13], v[19], v[25]],
        &[
            (-5.0, 10.0),
            (0.0, 15.0),
            (5.0, 10.0),
            (5.0, -10.0),
            (0.0, -15.0),
            (-5.0, -10.0),
        ],
        1e-12,
    );
    assert!(o.polygon.is_clockwise());
    // Unknown keys are ignored by MOOS's stringToOval, unlike the other generators.
    let o2 = parse_polygon("format=oval, x=0, y=0, rad=5, len=30, ang=0, draw_degs=15, foo=bar")
        .unwrap();
    assert_eq!(o2.polygon, o.polygon);
    assert!(matches!(
        Oval {
            x: 0.0,
            y: 0.0,
            rad: 5.0,
            len: 10.0,
            ang: 0.0
        }
        .vertices()
        .unwrap_err(),
        ParseError::InvalidValue { .. }
    ));
}

#[test]
fn waypoint_polygon_values_export_from_nearest_vertex() {
    // A waypoint `points` that is a polygon keeps the polygon's order but starts at the
    // vertex nearest the vehicle.
    let v = geometry::spec::parse_waypoints("format=radial, x=0, y=0, radius=10, pts=4", -9.0, 9.0)
        .unwrap();
    let r = 50f64.sqrt();
    assert_pts(
        v.seglist.points(),
        &[(-r, r), (r, r), (r, -r), (-r, -r)],
        1e-9,
    );
    // Unknown everywhere: the polygon parser's error is reported.
    assert!(matches!(
        geometry::spec::parse_waypoints("format=spiral, x=0", 0.0, 0.0).unwrap_err(),
        ParseError::UnknownFormat {
            kind: "polygon",
            ..
        }
    ));
}
