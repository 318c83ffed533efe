//! BHV_Waypoint against the C++ at MOOS-IvP a2a9b716: the conformance rows that were open
//! (newpt, shortest_tour, index variables, crs_spd_zaic_ratio, visual_hints, ipf_type,
//! draw_path_loop, eager_prev_index_flag, BHV_SETTINGS, WAYPT_UPIECE) and the parameter
//! reads the C++ does with `atof`/`atoi`/`setBooleanOnString`.

mod support;

use behaviors::{Emit, Out, ParamError, Value};
use ivp::{Domain, IvpFunction};
use support::{Bhv, decide, posted, posted_all};

fn domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
}

fn wpt(params: &[(&str, &str)]) -> Bhv {
    Bhv::new("BHV_Waypoint", "wpt", domain()).config(params)
}

/// A running iteration with ownship at (x, y), heading `h`, speed 1.
fn run_at(b: &mut Bhv, t: f64, x: f64, y: f64, h: f64) -> (Option<IvpFunction>, Out) {
    b.nav(x, y, h, 1.0, 0.0);
    b.run(t)
}

fn num(out: &Out, var: &str) -> Option<f64> {
    posted(out, var).and_then(Value::as_f64)
}

fn text<'a>(out: &'a Out, var: &str) -> Option<&'a str> {
    posted(out, var).and_then(Value::as_str)
}

fn macro_of(b: &Bhv, name: &str) -> String {
    let mut s = String::new();
    assert!(b.bhv.macro_value(name, &mut s), "{name}");
    s
}

/// The values of the flags emitted in `out` for `var`, as `VAR=value` texts.
fn flag_values(out: &Out, var: &str) -> Vec<String> {
    out.emits
        .iter()
        .filter_map(|e| match e {
            Emit::Flag { flag, .. } if flag.var == var => Some(flag.value.to_string()),
            _ => None,
        })
        .collect()
}

fn is_bad(r: Result<(), ParamError>) -> bool {
    matches!(r, Err(ParamError::BadValue { .. }))
}

#[test]
fn newpt_appends_in_normal_order_and_is_ignored_when_reversed() {
    let mut b = wpt(&[
        ("points", "0,10:0,20"),
        ("radius", "2"),
        ("slip_radius", "0"),
    ]);
    b.set("newpt", "0,30").unwrap();
    b.set("newpt", "x=5,y=30").unwrap();
    assert!(is_bad(b.set("newpt", "nowhere")));
    assert_eq!(macro_of(&b, "POINTS"), "pts={0,10:0,20:0,30:5,30}");
    // The appended points are followed after the others.
    run_at(&mut b, 0.0, 0.0, 9.0, 0.0);
    run_at(&mut b, 1.0, 0.0, 19.0, 0.0);
    let (_, out) = run_at(&mut b, 2.0, 0.0, 29.0, 0.0);
    assert_eq!(num(&out, "WPT_INDEX"), Some(3.0));
    assert!(
        posted_all(&out, "VIEW_POINT")[0]
            .as_str()
            .unwrap()
            .starts_with("x=5,y=30,active=true,")
    );

    // MOOS `addWaypoint` adds nothing while the order is reversed (the value is accepted).
    let mut b = wpt(&[("points", "0,10:0,20"), ("order", "reverse")]);
    b.set("newpt", "0,30").unwrap();
    assert_eq!(macro_of(&b, "POINTS"), "pts={0,20:0,10}");
    assert_eq!(macro_of(&b, "WPTS"), "2");
}

#[test]
fn shortest_tour_reorders_nearest_first_from_the_first_known_position() {
    let mut b = wpt(&[("points", "30,0:10,0:20,0"), ("shortest_tour", "true")]);
    // Applied on the first iteration with a position, idle or running.
    b.nav(0.0, 0.0, 90.0, 1.0, 0.0);
    b.idle(0.0);
    assert_eq!(macro_of(&b, "POINTS"), "pts={10,0:20,0:30,0}");
    let (_, out) = b.run(1.0);
    assert_eq!(
        text(&out, "VIEW_SEGLIST").unwrap(),
        "pts={10,0:20,0:30,0},label=abe_wpt,label_color=white,edge_color=white,\
         vertex_color=dodger_blue,vertex_size=3,edge_size=1"
    );

    // With the order reversed the tour is built on the reversed route, then set as the new
    // route, which the engine reverses again: the farthest point comes first.
    let mut b = wpt(&[
        ("points", "30,0:10,0:20,0"),
        ("order", "reverse"),
        ("greedy_tour", "true"),
    ]);
    run_at(&mut b, 0.0, 0.0, 0.0, 90.0);
    assert_eq!(macro_of(&b, "POINTS"), "pts={30,0:20,0:10,0}");

    // A value that is not a boolean is accepted and ignored (no tour).
    let mut b = wpt(&[("points", "30,0:10,0:20,0"), ("shortest_tour", "maybe")]);
    run_at(&mut b, 0.0, 0.0, 0.0, 90.0);
    assert_eq!(macro_of(&b, "POINTS"), "pts={30,0:10,0:20,0}");
}

#[test]
fn wpt_index_var_posts_when_the_index_changes() {
    let mut b = wpt(&[
        ("points", "0,10:0,20:0,30"),
        ("radius", "2"),
        ("slip_radius", "0"),
        ("wpt_index_var", "MY_IX"),
    ]);
    let (_, out) = run_at(&mut b, 0.0, 0.0, 0.0, 0.0);
    assert_eq!(num(&out, "MY_IX"), Some(0.0));
    assert_eq!(posted(&out, "WPT_INDEX"), None);
    let (_, out) = run_at(&mut b, 1.0, 0.0, 1.0, 0.0);
    assert_eq!(posted(&out, "MY_IX"), None, "unchanged index");
    let (_, out) = run_at(&mut b, 2.0, 0.0, 9.0, 0.0);
    assert_eq!(num(&out, "MY_IX"), Some(1.0));
    assert_eq!(macro_of(&b, "PI"), "1");

    let mut b = wpt(&[("points", "0,10"), ("wpt_index", "silent")]);
    let (_, out) = run_at(&mut b, 0.0, 0.0, 0.0, 0.0);
    assert!(posted(&out, "WPT_INDEX").is_none() && posted(&out, "silent").is_none());
    for bad in ["A B", ""] {
        assert!(is_bad(b.set("wpt_index", bad)), "{bad:?}");
        assert!(is_bad(b.set("wpt_index_var", bad)), "{bad:?}");
        assert!(is_bad(b.set("cycle_index_var", bad)), "{bad:?}");
    }
}

#[test]
fn cycle_index_var_posts_each_new_cycle_count() {
    let mut b = wpt(&[
        ("points", "0,10:0,20"),
        ("radius", "2"),
        ("slip_radius", "0"),
        ("repeat", "2"),
        ("cycle_index_var", "LAPS"),
        ("post_suffix", "A"),
    ]);
    // Cycle count 0 is never posted.
    let (_, out) = run_at(&mut b, 0.0, 0.0, 0.0, 0.0);
    assert_eq!(posted(&out, "LAPS_A"), None);
    let (_, out) = run_at(&mut b, 1.0, 0.0, 9.0, 0.0);
    assert_eq!(posted(&out, "LAPS_A"), None);
    let (_, out) = run_at(&mut b, 2.0, 0.0, 19.0, 0.0);
    assert_eq!(num(&out, "LAPS_A"), Some(1.0));
    assert_eq!(
        posted_all(&out, "WPT_STAT_A")[0].as_str(),
        Some("behavior-name=wpt,cycled")
    );
    let (_, out) = run_at(&mut b, 3.0, 0.0, 18.0, 0.0);
    assert_eq!(posted(&out, "LAPS_A"), None);
    run_at(&mut b, 4.0, 0.0, 9.0, 0.0);
    let (_, out) = run_at(&mut b, 5.0, 0.0, 19.0, 0.0);
    assert_eq!(num(&out, "LAPS_A"), Some(2.0));
    // The third pass ends the repeats: completed, and the count still posts.
    run_at(&mut b, 6.0, 0.0, 9.0, 0.0);
    let (f, out) = run_at(&mut b, 7.0, 0.0, 19.0, 0.0);
    assert!(f.is_none() && out.completed);
    assert_eq!(num(&out, "LAPS_A"), Some(3.0));

    let mut b = wpt(&[("points", "0,10:0,20"), ("cycle_index_var", "SILENT")]);
    let (_, out) = run_at(&mut b, 0.0, 0.0, 9.0, 0.0);
    assert!(posted(&out, "silent").is_none());
}

/// The coupled function's value at course `c` (degrees) and speed index `s`.
fn value(f: &IvpFunction, c: u32, s: u32) -> f64 {
    f.eval(&[c, s]).unwrap()
}

#[test]
fn crs_spd_zaic_ratio_splits_the_function_between_course_and_speed() {
    // Ownship heads for the point (course 90 is the top of the course function); the speed
    // function's lowest value is at speed 0 (and 4). OF_Coupler scales the course function
    // to [0, ratio] and the speed function to [0, 100 - ratio]: at course 90 and speed 0 the
    // value is the ratio itself.
    for (param, ratio) in [
        ("crs_spd_zaic_ratio", 80.0),
        ("patience", 30.0),
        ("patience", 50.0),
    ] {
        let r = ratio.to_string();
        let mut b = wpt(&[("points", "100,0"), ("speed", "2"), (param, r.as_str())]);
        let (f, _) = run_at(&mut b, 0.0, 0.0, 0.0, 90.0);
        let f = f.unwrap();
        assert!((value(&f, 90, 20) - 100.0).abs() < 1e-6);
        assert!((value(&f, 90, 0) - ratio).abs() < 1e-6, "{param} {ratio}");
        assert!((value(&f, 270, 20) - (100.0 - ratio)).abs() < 1e-6);
    }
    // A speed-only competitor at weight 40 asking for speed 0: with 80% on course the
    // waypoint's speed share (20) loses; with 20% on course (speed share 80) it wins.
    for (ratio, want) in [("80", 0.0), ("20", 2.0)] {
        let mut b = wpt(&[
            ("points", "100,0"),
            ("speed", "2"),
            ("crs_spd_zaic_ratio", ratio),
        ]);
        let (f, _) = run_at(&mut b, 0.0, 0.0, 0.0, 90.0);
        let mut stop = ivp::ZaicPeak::new(&b.domain, "speed").unwrap();
        stop.set_params(0.0, 0.0, 2.0, 0.0, 0.0, 100.0).unwrap();
        let d = decide(
            &b.domain,
            &[
                ("wpt", f.unwrap(), 100.0),
                ("stop", stop.extract().unwrap(), 40.0),
            ],
        );
        assert_eq!(d.get("speed"), Some(want), "ratio {ratio}");
        assert_eq!(d.get("course"), Some(90.0));
    }
    let mut b = wpt(&[("points", "100,0"), ("speed", "2")]);
    for bad in ["0.5", "99.5", "abc", "-3"] {
        assert!(is_bad(b.set("crs_spd_zaic_ratio", bad)), "{bad}");
    }
    // atof: the numeric prefix is read.
    b.set("patience", "70pct").unwrap();
    let (f, _) = run_at(&mut b, 0.0, 0.0, 0.0, 90.0);
    assert!((value(&f.unwrap(), 90, 0) - 70.0).abs() < 1e-6);
}

#[test]
fn ipf_type_zaic_spd_shapes_the_speed_function() {
    // ZAIC_SPD(med 2, low 0.1, high 2.4, low util 70, high util 20), 0 at the domain ends:
    // with half the function on speed, at course 90 the value is 50 + speed utility / 2.
    let mut b = wpt(&[
        ("points", "100,0"),
        ("speed", "2"),
        ("ipf-type", "ZAIC_SPD"),
    ]);
    assert_eq!(macro_of(&b, "IPF_TYPE"), "zaic_spd");
    let (f, _) = run_at(&mut b, 0.0, 0.0, 0.0, 90.0);
    let f = f.unwrap();
    for (s, want) in [(20, 100.0), (1, 85.0), (24, 60.0), (0, 50.0), (40, 50.0)] {
        assert!((value(&f, 90, s) - want).abs() < 1e-6, "speed index {s}");
    }
    let d = decide(&b.domain, &[("wpt", f, 100.0)]);
    assert_eq!((d.get("course"), d.get("speed")), (Some(90.0), Some(2.0)));

    // The default ZAIC_PEAK: speed 0 is the speed function's lowest point.
    b.set("ipf_type", "zaic").unwrap();
    let (f, _) = run_at(&mut b, 1.0, 0.0, 0.0, 90.0);
    assert!((value(&f.unwrap(), 90, 0) - 50.0).abs() < 1e-6);

    // Any other value is accepted and ignored, as the C++ does.
    b.set("ipf_type", "gaussian").unwrap();
    assert_eq!(macro_of(&b, "IPF_TYPE"), "zaic");
    b.set("ipf_type", "ROC").unwrap();
    assert_eq!(macro_of(&b, "IPF_TYPE"), "roc");
    b.set("ipf_type", "Rate_Of_Closure").unwrap();
    assert_eq!(macro_of(&b, "IPF_TYPE"), "rate_of_closure");
}

#[test]
fn ipf_type_roc_reflects_the_rate_of_closure_function() {
    let mut b = wpt(&[("points", "100,0"), ("speed", "2"), ("ipf_type", "roc")]);
    let (f, _) = run_at(&mut b, 0.0, 0.0, 0.0, 0.0);
    let f = f.unwrap();
    // 600 uniform pieces at most (genUnifBox over 360 x 41), then 500 cut by smart
    // refinement; normalised to 0..100.
    assert!(
        f.piece_count() > 1000 && f.piece_count() <= 1100,
        "{}",
        f.piece_count()
    );
    assert!((f.max_val() - 100.0).abs() < 1e-9 && f.min_val().abs() < 1e-9);
    // AOF_Waypoint: 100 toward the point (course 90) at 2 m/s; 20 straight away at 4 m/s;
    // the normalisation maps [20, 100] to [0, 100] (20 is the lowest value: away at top
    // speed). The pieces are planes through samples, so a few units of slack.
    let near = |c: u32, s: u32, want: f64, tol: f64| {
        let v = value(&f, c, s);
        assert!(
            (v - want).abs() <= tol,
            "course {c} speed {s}: {v} vs {want}"
        );
    };
    near(90, 20, 100.0, 2.0);
    near(270, 40, 0.0, 2.0);
    // Standing still: 80 -> 75 after normalisation.
    near(0, 0, 75.0, 3.0);
    let d = decide(&b.domain, &[("wpt", f.clone(), 100.0)]);
    let (crs, spd) = (d.get("course").unwrap(), d.get("speed").unwrap());
    assert!(
        (crs - 90.0).abs() <= 2.0 && (spd - 2.0).abs() <= 0.15,
        "{crs} {spd}"
    );

    // The desired speed is the alternate one when in use; crs_spd_zaic_ratio does not apply.
    b.set("speed_alt", "1").unwrap();
    b.set("use_alt_speed", "true").unwrap();
    b.set("crs_spd_zaic_ratio", "90").unwrap();
    let (g, _) = run_at(&mut b, 1.0, 0.0, 0.0, 0.0);
    let d = decide(&b.domain, &[("wpt", g.unwrap(), 100.0)]);
    let (crs, spd) = (d.get("course").unwrap(), d.get("speed").unwrap());
    assert!(
        (crs - 90.0).abs() <= 2.0 && (spd - 1.0).abs() <= 0.15,
        "{crs} {spd}"
    );
    // Two builds give the same pieces (the queue's generator has a fixed seed).
    let (h, _) = run_at(&mut b, 2.0, 0.0, 0.0, 0.0);
    let (k, _) = run_at(&mut b, 3.0, 0.0, 0.0, 0.0);
    let boxes = |f: &IvpFunction| {
        f.pieces()
            .map(|p| (p.lo.to_vec(), p.hi.to_vec()))
            .collect::<Vec<_>>()
    };
    assert_eq!(boxes(&h.unwrap()), boxes(&k.unwrap()));
}

#[test]
fn visual_hints_draw_the_route_and_points() {
    let mut b = wpt(&[
        ("points", "0,0:0,100"),
        ("radius", "2"),
        ("lead", "10"),
        (
            "visual_hints",
            "nextpt_color=red, nextpt_lcolor=green, nextpt_vertex_size=8, vertex_color=orange",
        ),
        (
            "visual_hints",
            "edge_size=2,vertex_size=-1,label_color=gray50,foo=3",
        ),
    ]);
    run_at(&mut b, 0.0, 0.0, 0.0, 0.0);
    // 50 m along the leg with lead 10: the track point is 10 m ahead of the next point's
    // perpendicular foot, more than 5 m from the next point, so it is drawn.
    let (_, out) = run_at(&mut b, 1.0, 3.0, 50.0, 0.0);
    assert_eq!(
        text(&out, "VIEW_SEGLIST").unwrap(),
        "pts={0,0:0,100},label=abe_wpt,label_color=gray50,edge_color=white,\
         vertex_color=orange,vertex_size=3,edge_size=2"
    );
    let pts = posted_all(&out, "VIEW_POINT");
    assert_eq!(
        pts[0].as_str().unwrap(),
        "x=0,y=100,active=true,label=abe's nextpt,label_color=green,vertex_color=red,vertex_size=8"
    );
    assert_eq!(
        pts[1].as_str().unwrap(),
        "x=0,y=60,label=abe's trackpt,label_color=red,vertex_color=red,vertex_size=4"
    );
    // Stopping erases the points and the route (its points, inactive, 1 decimal).
    let out = b.stop(2.0);
    let pts = posted_all(&out, "VIEW_POINT");
    assert_eq!(
        pts[0].as_str().unwrap(),
        "x=0,y=0,active=false,label=abe's trackpt"
    );
    assert_eq!(
        pts[1].as_str().unwrap(),
        "x=0,y=0,active=false,label=abe's nextpt"
    );
    assert_eq!(
        text(&out, "VIEW_SEGLIST").unwrap(),
        "pts={0,0:0,100},active=false,label=abe_wpt"
    );

    // An edge colour `off` posts the erase form instead of the route.
    let mut b = wpt(&[("points", "0,0:0,100"), ("visual_hints", "edge_color=off")]);
    let (_, out) = run_at(&mut b, 0.0, 0.0, 50.0, 0.0);
    assert_eq!(
        text(&out, "VIEW_SEGLIST").unwrap(),
        "pts={0,0:9,0:0,9},active=false,label=abe_wpt"
    );

    // A bad hint is refused; the hints before it stay set.
    let mut b = wpt(&[("points", "0,0:0,100")]);
    assert!(is_bad(b.set("visual_hints", "edge_size=4,edge_color=bleu")));
    assert!(is_bad(b.set("visual_hints", "vertex_size=big")));
    assert!(is_bad(b.set("visual_hints", "edge_color=inactive")));
    b.bhv.on_set_param_complete(
        &behaviors::Ctx {
            info: &b.info,
            domain: &b.domain,
            ownship: "abe",
            name: "wpt",
            perpetual: false,
        },
        &mut Out::default(),
    );
    let (_, out) = run_at(&mut b, 0.0, 0.0, 50.0, 0.0);
    assert!(
        text(&out, "VIEW_SEGLIST")
            .unwrap()
            .ends_with(",edge_size=4")
    );
}

#[test]
fn draw_path_loop_draws_a_convex_route_as_a_polygon() {
    let mut b = wpt(&[
        ("points", "0,0:0,10:10,10:10,0"),
        ("draw_path_loop", "TRUE"),
    ]);
    let (_, out) = run_at(&mut b, 0.0, 5.0, -20.0, 0.0);
    assert_eq!(
        text(&out, "VIEW_POLYGON").unwrap(),
        "pts={0,0:0,10:10,10:10,0},label_color=white,edge_color=white,\
         vertex_color=dodger_blue,vertex_size=3,edge_size=1"
    );
    // Posted just before the route.
    let order: Vec<&str> = out
        .emits
        .iter()
        .filter_map(|e| match e {
            Emit::Post { var, .. } if var.starts_with("VIEW_") => Some(var.as_str()),
            _ => None,
        })
        .collect();
    assert_eq!(
        order,
        ["VIEW_POLYGON", "VIEW_SEGLIST", "VIEW_POINT", "VIEW_POINT"]
    );

    // A route that is not a convex polygon is not drawn as one; nor without the flag.
    let mut b = wpt(&[("points", "0,0:10,10:0,10:10,0"), ("draw_path_loop", "yes")]);
    let (_, out) = run_at(&mut b, 0.0, 5.0, -20.0, 0.0);
    assert_eq!(posted(&out, "VIEW_POLYGON"), None);
    b.set("draw_path_loop", "toggle").unwrap();
    b.set("points", "0,0:0,10:10,10:10,0").unwrap();
    let (_, out) = run_at(&mut b, 1.0, 5.0, -20.0, 0.0);
    assert_eq!(posted(&out, "VIEW_POLYGON"), None);
    assert!(is_bad(b.set("draw_path_loop", "sometimes")));
}

#[test]
fn eager_prev_index_flag_ties_pi_to_the_point_just_reached() {
    let flags = [
        ("points", "0,10:0,20:0,30"),
        ("radius", "2"),
        ("slip_radius", "0"),
        ("wptflag", "PREV = $[PI]"),
        ("wptflag", "PREV_XY = $[PX],$[PY]"),
        ("wptflag_on_start", "true"),
    ];
    // Default: PI is the index reported by the last status, -1 before any.
    let mut b = wpt(&flags);
    let (_, out) = run_at(&mut b, 0.0, 0.0, 0.0, 0.0);
    assert_eq!(flag_values(&out, "PREV"), ["-1"]);
    // On start the previous point is the point about to be sought.
    assert_eq!(flag_values(&out, "PREV_XY"), ["0,10"]);
    assert_eq!(macro_of(&b, "PI"), "0");
    let (_, out) = run_at(&mut b, 1.0, 0.0, 9.0, 0.0);
    assert_eq!(flag_values(&out, "PREV"), ["0"]);
    assert_eq!(macro_of(&b, "PI"), "1");
    let (_, out) = run_at(&mut b, 2.0, 0.0, 12.0, 0.0);
    assert_eq!(posted(&out, "WPT_INDEX"), None);

    // Eager: PI is set with PX/PY when a point is reached (or on start).
    let mut eager = flags.to_vec();
    eager.push(("eager_prev_index_flag", "true"));
    let mut b = wpt(&eager);
    let (_, out) = run_at(&mut b, 0.0, 0.0, 0.0, 0.0);
    assert_eq!(flag_values(&out, "PREV"), ["0"]);
    // PI is already 0 when the status is reported: no index posting.
    assert_eq!(posted(&out, "WPT_INDEX"), None);
    let (_, out) = run_at(&mut b, 1.0, 0.0, 9.0, 0.0);
    assert_eq!(flag_values(&out, "PREV"), ["0"]);
    assert_eq!(flag_values(&out, "PREV_XY"), ["0,10"]);
    assert_eq!(macro_of(&b, "PI"), "0");
    // The index differs from PI between arrivals, so it is reported every iteration.
    let (_, out) = run_at(&mut b, 2.0, 0.0, 12.0, 0.0);
    assert_eq!(num(&out, "WPT_INDEX"), Some(1.0));
    assert!(is_bad(b.set("eager_prev_index_flag", "2")));
}

#[test]
fn bhv_settings_after_configuration_and_updates() {
    let b = wpt(&[
        ("points", "0,0:10,5.26"),
        ("speed", "1.5"),
        ("capture_line", "absolute"),
        ("repeat", "forever"),
        ("patience", "66.666"),
    ]);
    let settings = posted_all(&b.configured, "BHV_SETTINGS");
    assert_eq!(settings.len(), 1);
    assert_eq!(
        settings[0].as_str().unwrap(),
        "type=BHV_Waypoint,name=wpt,points=pts={0,0:10,5.3},speed=1.5,speed_alt=-1,currix=0,\
         greedy_tour=false,use_alt_speed=false,wpt_status=WPT_STAT,wpt_dist_to_prev=,\
         wpt_dist_to_next=,wpt_index=WPT_INDEX,cycle_index_var=CYCLE_INDEX,post_suffix=,\
         post_suffix=,ipf_type=zaic,lead=-1,lead_damper=-1,lead_to_start=false,order=normal,\
         repeats=forever,efficiency_measure=off,capture_radius=0,slip_radius=0,\
         capture_line=absolute,crs_spd_zaic_ratio=66.67"
    );
    // Repeatable: never filtered.
    assert!(b.configured.emits.iter().any(|e| matches!(e,
        Emit::Post { var, key: behaviors::PostKey::Repeatable, .. } if var == "BHV_SETTINGS")));
    // The route is given: the "no points" warning is retracted (a filtered posting).
    assert_eq!(
        text(&b.configured, "BHV_WARNING"),
        Some("wpt: No waypts given. Set val to empty if intentional")
    );
    assert!(b.configured.emits.iter().any(|e| matches!(e,
        Emit::Post { var, key: behaviors::PostKey::Tag("retract"), .. } if var == "BHV_WARNING")));

    // After an update the C++ posts it twice: the helm once (checkUpdates), then
    // onSetParamComplete once (the helm-level count is in helm/tests/engine.rs).
    let mut b = wpt(&[("points", "5,5"), ("order", "reverse"), ("repeat", "3")]);
    let s = posted_all(&b.configured, "BHV_SETTINGS")[0]
        .as_str()
        .unwrap();
    assert!(
        s.contains(",order=reverse,repeats=3,")
            && s.ends_with(",slip_radius=15,crs_spd_zaic_ratio=50")
    );
    assert_eq!(
        posted_all(&b.configured, "BHV_WARNING")[0].as_str(),
        Some("wpt: cycles/repeats not supported with single waypt")
    );
    b.set("speed", "2").unwrap();
    let mut out = Out::default();
    let ctx = behaviors::Ctx {
        info: &b.info,
        domain: &b.domain,
        ownship: "abe",
        name: "wpt",
        perpetual: true,
    };
    b.bhv.on_set_param_complete(&ctx, &mut out);
    let after = posted_all(&out, "BHV_SETTINGS");
    assert_eq!(after.len(), 1);
    assert!(after[0].as_str().unwrap().contains(",speed=2,"));

    // No points, and not said to be intentional: a warning.
    let b = wpt(&[("speed", "1")]);
    assert_eq!(
        text(&b.configured, "BHV_WARNING"),
        Some("wpt: No waypts given. Set val to empty if intentional")
    );
    let b = wpt(&[("points", "empty")]);
    assert_eq!(posted(&b.configured, "BHV_WARNING"), None);
}

#[test]
fn waypt_upiece_is_never_posted() {
    // The C++ WAYPT_UPIECE posting is commented out (roc branch); nothing posts it.
    let mut b = wpt(&[
        ("points", "0,10:0,20"),
        ("radius", "2"),
        ("efficiency_measure", "all"),
    ]);
    for (t, y) in [(0.0, 0.0), (1.0, 9.0), (2.0, 19.0)] {
        let (_, out) = run_at(&mut b, t, 0.0, y, 0.0);
        assert_eq!(posted(&out, "WAYPT_UPIECE"), None);
    }
    assert!(
        b.configured
            .emits
            .iter()
            .all(|e| !matches!(e, Emit::Post { var, .. } if var == "WAYPT_UPIECE"))
    );
}

#[test]
fn points_start_and_empty_record_the_intent_only() {
    // `points = empty` keeps the route (the C++ only notes the intent).
    let mut b = wpt(&[("points", "0,10:0,20")]);
    b.set("points", "empty").unwrap();
    assert_eq!(macro_of(&b, "WPTS"), "2");
    // `point = start` with no route: the first known position, to 3 decimals.
    let mut b = wpt(&[("point", "start")]);
    assert_eq!(posted(&b.configured, "BHV_WARNING"), None);
    assert_eq!(macro_of(&b, "WPTS"), "0");
    b.nav(12.34567, -8.0, 0.0, 1.0, 0.0);
    b.idle(0.0);
    assert_eq!(macro_of(&b, "POINTS"), "pts={12.3,-8}");
    assert_eq!(macro_of(&b, "WPTS"), "1");
    // Seek it from 10 m away.
    let (_, out) = run_at(&mut b, 1.0, 22.346, -8.0, 0.0);
    assert_eq!(
        posted_all(&out, "VIEW_POINT")[0].as_str().map(|s| &s[..17]),
        Some("x=12.35,y=-8,acti")
    );
}

#[test]
fn moos_number_and_boolean_reads() {
    let mut b = wpt(&[("points", "0,10:0,20:0,30")]);
    // atoi: "2.5" repeats twice; atof: "4m" is 4; "abc" is 0 for the slip radius.
    b.set("repeat", "2.5").unwrap();
    assert_eq!(macro_of(&b, "CYCREM"), "2");
    assert!(is_bad(b.set("repeat", "two")));
    b.set("capture_radius", "4m").unwrap();
    b.set("slip_radius", "abc").unwrap();
    b.set("currix", "2").unwrap();
    assert_eq!(macro_of(&b, "NI"), "2");
    b.set("currix", "7").unwrap();
    assert_eq!(macro_of(&b, "NI"), "2", "past the route: ignored");
    assert!(is_bad(b.set("currix", "-1")));
    assert!(is_bad(b.set("speed_alt", "-1")));
    assert!(is_bad(b.set("lead_damper", "0")));
    assert!(is_bad(b.set("order", "Reverse")));
    b.set("reset_on_idle", "ON").unwrap();
    b.set("lead_to_start", "yes").unwrap();
    assert_eq!(macro_of(&b, "LEAD_TO_START"), "1");
    // use_alt_speed ignores a bad value.
    b.set("use_alt_speed", "perhaps").unwrap();
    assert_eq!(macro_of(&b, "USE_SPEED_ALT"), "0");
    // end_spd needs both distances, stop <= slow.
    b.set("end_spd", "slow_dist=10,stop_dist=10").unwrap();
    for bad in [
        "slow_dist=10",
        "slow_dist=0,stop_dist=0",
        "stop_dist=5,slow_dist=4",
        "SLOW_DIST=10,stop_dist=1",
    ] {
        assert!(is_bad(b.set("end_spd", bad)), "{bad}");
    }
}

#[test]
fn end_spd_tapers_along_the_rest_of_the_route() {
    // Route 0,0 -> 0,20 -> 20,20 seeking point 1 from (0,10): 10 m to it plus the 20 m leg:
    // 30 m to go. slow_dist 40, stop_dist 10: 2 * (30 - 10) / 30 = 1.33 m/s.
    let mut b = wpt(&[
        ("points", "0,0:0,20:20,20"),
        ("speed", "2"),
        ("radius", "1"),
        ("end_spd", "slow_dist=40,stop_dist=10"),
    ]);
    run_at(&mut b, 0.0, 0.0, 0.0, 0.0);
    let (f, _) = run_at(&mut b, 1.0, 0.0, 10.0, 0.0);
    let d = decide(&b.domain, &[("wpt", f.unwrap(), 100.0)]);
    assert_eq!(d.get("course"), Some(0.0));
    assert!(
        (d.get("speed").unwrap() - 1.3).abs() < 1e-9,
        "{:?}",
        d.get("speed")
    );
    assert_eq!(macro_of(&b, "ALL_DIST_TOGO"), "30");
}

#[test]
fn aliases_toggles_and_clipping() {
    // speed clips to the domain (0..4).
    let mut b = wpt(&[("points", "0,10:0,20"), ("speed", "9")]);
    assert_eq!(macro_of(&b, "SPEED"), "4");
    // order toggle flips and restarts at index 0.
    b.set("currix", "1").unwrap();
    b.set("order", "toggle").unwrap();
    assert_eq!(
        (macro_of(&b, "ORDER"), macro_of(&b, "NI")),
        ("reverse".into(), "0".into())
    );
    assert_eq!(macro_of(&b, "POINTS"), "pts={0,20:0,10}");
    b.set("order", "toggle").unwrap();
    assert_eq!(macro_of(&b, "ORDER"), "normal");

    // wpt_status_var is wpt_status; silent turns the report off.
    let mut b = wpt(&[("points", "0,10"), ("wpt_status_var", "MY_STAT")]);
    let (_, out) = run_at(&mut b, 0.0, 0.0, 0.0, 0.0);
    assert_eq!(
        text(&out, "MY_STAT"),
        Some("vname=abe,behavior-name=wpt,index=0,hits=0/0,cycles=0,dist=10,eta=10")
    );
    b.set("wpt_status", "Silent").unwrap();
    let (_, out) = run_at(&mut b, 1.0, 0.0, 1.0, 0.0);
    assert!(posted(&out, "MY_STAT").is_none() && posted(&out, "WPT_STAT").is_none());

    // nm_radius is slip_radius: leaving a point passed 10 m away counts as arrival.
    let mut b = wpt(&[("points", "0,100:0,200"), ("nm_radius", "12")]);
    run_at(&mut b, 0.0, 10.0, 90.0, 0.0);
    run_at(&mut b, 1.0, 10.0, 100.0, 0.0);
    run_at(&mut b, 2.0, 10.0, 102.0, 0.0);
    assert_eq!(macro_of(&b, "NI"), "1");
    let mut b = wpt(&[("points", "0,100:0,200"), ("nm_radius", "8")]);
    run_at(&mut b, 0.0, 10.0, 90.0, 0.0);
    run_at(&mut b, 1.0, 10.0, 100.0, 0.0);
    run_at(&mut b, 2.0, 10.0, 102.0, 0.0);
    assert_eq!(macro_of(&b, "NI"), "0");

    // Several lead conditions must all hold.
    let mut b = wpt(&[
        ("points", "0,0:0,100"),
        ("radius", "2"),
        ("lead", "10"),
        ("lead_condition", "A = 1"),
        ("lead_condition", "B = 1"),
    ]);
    run_at(&mut b, 0.0, 0.0, 0.0, 0.0);
    b.num("A", 1.0).num("B", 0.0);
    let (_, out) = run_at(&mut b, 1.0, 3.0, 50.0, 0.0);
    assert!(
        posted_all(&out, "VIEW_POINT")[1]
            .as_str()
            .unwrap()
            .contains("active=false")
    );
    b.num("B", 1.0);
    let (_, out) = run_at(&mut b, 2.0, 3.0, 50.0, 0.0);
    assert!(
        posted_all(&out, "VIEW_POINT")[1]
            .as_str()
            .unwrap()
            .starts_with("x=0,y=60,")
    );
}
