//! VIEW_POINT / VIEW_SEGLIST / VIEW_POLYGON strings, character for character against the
//! reference examples (`ivp-helm.md` §6 and §8, `moos-apps-extra.md` §2), and the parsers'
//! typed errors.

use geometry::spec::{parse_point, parse_polygon, parse_seglist};
use geometry::{
    Attributes, ParseError, Point, Polygon, SegList, ViewPoint, ViewPolygon, ViewSegList,
};

#[test]
fn view_point_reference_example() {
    let s = "x=10,y=-20.5,label=abe's nextpt,vertex_color=yellow,vertex_size=5";
    let vp = parse_point(s).unwrap();
    assert_eq!(vp.point, Point::new(10.0, -20.5));
    assert_eq!(vp.attrs.label, "abe's nextpt");
    assert_eq!(vp.attrs.vertex_color.as_deref(), Some("yellow"));
    assert_eq!(vp.attrs.vertex_size, Some(5.0));
    assert_eq!(vp.to_spec(), s);
    // Keys in any order parse to the same point.
    let reordered =
        parse_point("label=abe's nextpt, vertex_size=5, y=-20.5, vertex_color=yellow, x=10")
            .unwrap();
    assert_eq!(reordered, vp);
}

#[test]
fn view_point_formatting_rules() {
    let mut vp = ViewPoint::new(Point::new_3d(1.23456, -0.004, 2.5));
    // 2 decimals by default; -0.004 rounds to -0.00 which is written 0; z only when non-zero.
    assert_eq!(vp.to_spec(), "x=1.23,y=0,z=2.5");
    vp.precision = 4;
    vp.trans = 0.25;
    assert_eq!(vp.to_spec(), "x=1.2346,y=-0.004,z=2.5,trans=0.25");
    vp.point.z = 0.0;
    vp.trans = 0.0;
    vp.attrs.active = false;
    vp.attrs.label = "t".into();
    assert_eq!(vp.to_spec(), "x=1.2346,y=-0.004,active=false,label=t");
    let mut buf = String::from("prefix:");
    ViewPoint::erase_spec("abe's trackpt", &mut buf);
    assert_eq!(buf, "prefix:x=0,y=0,active=false,label=abe's trackpt");
    let erased = parse_point("x=0,y=0,active=false,label=abe's trackpt").unwrap();
    assert!(!erased.attrs.active);
}

#[test]
fn attributes_are_written_in_moos_order() {
    let attrs = Attributes {
        active: false,
        label: "L".into(),
        msg: "m".into(),
        source: "abe:wpt".into(),
        vsource: "abe".into(),
        id: "7".into(),
        label_color: Some("white".into()),
        edge_color: Some("gray50".into()),
        vertex_color: Some("dodger_blue".into()),
        fill_color: Some("pink".into()),
        time: Some(1234.5),
        duration: Some(10.0),
        vertex_size: Some(3.25),
        edge_size: Some(1.0),
        fill_transparency: Some(0.3),
    };
    let v = ViewSegList {
        seglist: SegList::from_points(vec![Point::new(1.0, 2.0)]),
        attrs,
        precision: 1,
    };
    let s = v.to_spec();
    // vertex_size has 1 decimal: 3.25 -> "3.2" (printf rounds the binary value half-even).
    assert_eq!(
        s,
        "pts={1,2},active=false,label=L,msg=m,source=abe:wpt,vsource=abe,id=7,label_color=white,\
         edge_color=gray50,vertex_color=dodger_blue,fill_color=pink,time=1234.5,duration=10,\
         vertex_size=3.2,edge_size=1,fill_transparency=0.3"
    );
    let back = parse_seglist(&s).unwrap();
    assert_eq!(back.attrs.source, "abe:wpt");
    assert_eq!(back.attrs.vertex_size, Some(3.2));
    assert!(!back.attrs.active);
}

#[test]
fn view_seglist_waypoint_style() {
    // BHV_Waypoint posts its path with 3-decimal points and label <us>_<bhvname>.
    let sl = SegList::from_points(vec![
        Point::new(60.0, -40.0),
        Point::new(60.1234, -160.5),
        Point::new(150.0, -160.0),
    ]);
    let mut v = ViewSegList::new(sl);
    v.precision = 3;
    v.attrs = Attributes::labeled("abe_waypt_survey");
    v.attrs.vertex_color = Some("dodger_blue".into());
    v.attrs.edge_color = Some("white".into());
    v.attrs.vertex_size = Some(3.0);
    v.attrs.edge_size = Some(1.0);
    assert_eq!(
        v.to_spec(),
        "pts={60,-40:60.123,-160.5:150,-160},label=abe_waypt_survey,edge_color=white,vertex_color=dodger_blue,vertex_size=3,edge_size=1"
    );
    // Erase form.
    assert_eq!(
        ViewSegList::erase("abe_waypt_survey").to_spec(),
        "active=false,label=abe_waypt_survey"
    );
    let e = parse_seglist("active=false,label=abe_waypt_survey").unwrap();
    assert!(e.seglist.is_empty() && !e.attrs.active);
}

#[test]
fn vertex_z_and_properties() {
    let v = parse_seglist("pts={1,2,3:4,5,0,foo:6,7,bar:x=8,y=9}").unwrap();
    let p = v.seglist.points();
    assert_eq!(p[0], Point::new_3d(1.0, 2.0, 3.0));
    assert_eq!((v.seglist.prop(1), v.seglist.prop(2)), ("foo", "bar"));
    assert_eq!(p[3], Point::new(8.0, 9.0));
    // z written when non-zero or when there is a property.
    assert_eq!(v.to_spec(), "pts={1,2,3:4,5,0,foo:6,7,0,bar:8,9}");
}

#[test]
fn edge_tags_are_skipped() {
    let v = parse_seglist("pts={0,0:10,0:10,10},tags={0,1,lane#1:2:lane},label=mow").unwrap();
    assert_eq!(v.seglist.len(), 3);
    assert_eq!(v.attrs.label, "mow");
}

#[test]
fn view_polygon_specs() {
    let v = parse_polygon("radial:: x=20, y=-80, radius=20, pts=8, snap=1, label=DUDLEY_LOITER")
        .unwrap();
    assert_eq!(
        v.to_spec(),
        "pts={28,-62:38,-72:38,-88:28,-98:12,-98:2,-88:2,-72:12,-62},label=DUDLEY_LOITER"
    );
    // Standard form round trip, label and colours.
    let s =
        "pts={60,-40:60,-160:150,-160:180,-100:150,-40},label=abe:opreg:opreg,edge_color=yellow";
    let p = parse_polygon(s).unwrap();
    assert_eq!(p.polygon.len(), 5);
    assert_eq!(p.to_spec(), s);
    // Erase.
    assert_eq!(
        ViewPolygon::erase("abe:opreg").to_spec(),
        "active=false,label=abe:opreg"
    );
    let e = parse_polygon("label=abe:opreg,active=false").unwrap();
    assert!(e.polygon.is_empty() && !e.attrs.active && e.attrs.label == "abe:opreg");
    // The StationKeep circle spec.
    let sk = parse_polygon("radial:: x=12.5,y=-40,source=abe:station,pts=32,edge_color=gray50,label=abe:station-keep-out,radius=15").unwrap();
    assert_eq!(sk.polygon.len(), 32);
    assert_eq!(sk.attrs.source, "abe:station");
    assert_eq!(sk.attrs.label, "abe:station-keep-out");
    assert!(
        sk.polygon.contains(12.5, -40.0)
            && sk.polygon.contains(12.5, -25.5)
            && !sk.polygon.contains(12.5, -24.9)
    );
}

#[test]
fn abbreviated_forms() {
    let v = parse_seglist("label,transit:190,25:155,-20:45,-85:-40,-100").unwrap();
    assert_eq!(v.attrs.label, "transit");
    assert_eq!(v.seglist.len(), 4);
    let v = parse_seglist("60,-40 : 60,-160 : 150,-160 : 180,-100 : 150,-40").unwrap();
    assert_eq!(v.seglist.get(3), Some(Point::new(180.0, -100.0)));
    let v = parse_seglist("points: 0,0 : 1,2,3").unwrap();
    assert_eq!(v.seglist.get(1), Some(Point::new_3d(1.0, 2.0, 3.0)));
    // Polygons from the abbreviated form are not gated on convexity (as in MOOS)...
    let bow = parse_polygon("0,0 : 10,10 : 10,0 : 0,10").unwrap();
    assert!(!bow.polygon.is_convex());
    // ...but the standard form is.
    assert_eq!(
        parse_polygon("pts={0,0:10,10:10,0:0,10}").unwrap_err(),
        ParseError::NotConvex
    );
    let a = parse_polygon(
        "label,A : 40,-270:60,-290:100,-290:120,-270:120,-180:100,-160:60,-160:40,-180",
    )
    .unwrap();
    assert_eq!(a.attrs.label, "A");
    assert!(a.polygon.is_convex());
}

#[test]
fn typed_errors() {
    assert_eq!(parse_seglist("   ").unwrap_err(), ParseError::Empty);
    assert_eq!(
        parse_seglist("1,2:3").unwrap_err(),
        ParseError::BadVertex("3".into())
    );
    assert_eq!(
        parse_seglist("1,2:3,four").unwrap_err(),
        ParseError::BadVertex("3,four".into())
    );
    assert_eq!(
        parse_seglist("pts=1,2:3,4").unwrap_err(),
        ParseError::BadPointGroup("1,2:3,4".into())
    );
    assert_eq!(
        parse_seglist("pts={1,2:3,4}x").unwrap_err(),
        ParseError::BadPointGroup("x".into())
    );
    assert_eq!(
        parse_seglist("pts={}").unwrap_err(),
        ParseError::BadVertex("".into())
    );
    assert_eq!(
        parse_seglist("label=foo").unwrap_err(),
        ParseError::NoVertices("label=foo".into())
    );
    assert!(matches!(
        parse_seglist("format=radial, x=1").unwrap_err(),
        ParseError::UnknownFormat {
            kind: "seglist",
            ..
        }
    ));
    assert!(matches!(
        parse_seglist("pts={1,2},vertex_size=big").unwrap_err(),
        ParseError::BadNumber { .. }
    ));
    assert!(matches!(
        parse_seglist("pts={1,2},active=maybe").unwrap_err(),
        ParseError::InvalidValue { .. }
    ));
    assert_eq!(
        parse_point("1,2,3,4").unwrap_err(),
        ParseError::BadVertex("1,2,3,4".into())
    );
    assert_eq!(
        parse_point("label,foo").unwrap_err(),
        ParseError::NoVertices("label,foo".into())
    );
    assert_eq!(
        parse_point("x=1").unwrap_err(),
        ParseError::Missing {
            key: "y",
            format: "point"
        }
    );
    assert_eq!(
        parse_polygon("radial: 1,2,3").unwrap_err(),
        ParseError::FieldCount {
            format: "radial:",
            expected: "4 to 6",
            found: 3
        }
    );
    assert!(matches!(
        parse_polygon("radial: 0,0,10,1e3").unwrap_err(),
        ParseError::BadNumber { .. }
    ));
    assert!(matches!(
        parse_polygon("format=hexagon").unwrap_err(),
        ParseError::UnknownFormat {
            kind: "polygon",
            ..
        }
    ));
    assert!(matches!(
        parse_polygon("format=radial, x=0, y=0, radius=5, pts=99999999").unwrap_err(),
        ParseError::TooManyVertices(_)
    ));
    // Errors describe what was expected.
    let msg = parse_seglist("1,2:3").unwrap_err().to_string();
    assert!(msg.contains("expected x,y"), "{msg}");
}

#[test]
fn huge_generated_polygons_finish_quickly() {
    let t = std::time::Instant::now();
    // Either convex or rejected; what matters is that the O(n) convexity path is used.
    let r = parse_polygon("format=radial, x=0, y=0, radius=1000, pts=100000");
    if let Ok(v) = &r {
        assert_eq!(v.polygon.len(), 100_000);
    }
    assert!(t.elapsed().as_secs() < 30, "took {:?}", t.elapsed());
}

#[test]
fn from_str_impls() {
    let s: SegList = "0,0:10,0".parse().unwrap();
    assert_eq!(s.length(), 10.0);
    let p: Polygon = "format=radial, x=0, y=0, radius=10, pts=6".parse().unwrap();
    assert!(p.is_convex());
    let v: ViewPoint = "3,4".parse().unwrap();
    assert_eq!(v.point, Point::new(3.0, 4.0));
    let v: ViewPoint = "4,5,-2:label,foo:source,bravo".parse().unwrap();
    assert_eq!(
        (v.point, v.attrs.label.as_str(), v.attrs.source.as_str()),
        (Point::new_3d(4.0, 5.0, -2.0), "foo", "bravo")
    );
    let v: ViewPoint = "x=1,y=2,z=3,shiftx=10,hdg=45".parse().unwrap();
    assert_eq!(v.point, Point::new_3d(11.0, 2.0, 3.0));
}

#[test]
fn spec_writes_into_caller_buffer() {
    let v = ViewPolygon::new(Polygon::new(vec![
        Point::new(0.0, 0.0),
        Point::new(0.0, 1.5),
        Point::new(2.0, 0.0),
    ]));
    let mut buf = String::with_capacity(64);
    v.spec(&mut buf);
    let cap = buf.capacity();
    let first = buf.clone();
    for _ in 0..100 {
        buf.clear();
        v.spec(&mut buf);
    }
    assert_eq!(buf, first);
    assert_eq!(buf, "pts={0,0:0,1.5:2,0}");
    assert_eq!(
        buf.capacity(),
        cap,
        "reusing the buffer must not reallocate"
    );
}
