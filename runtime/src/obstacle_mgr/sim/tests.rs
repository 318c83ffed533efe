use super::*;
use crate::antler::BuiltInApp;
use crate::app::Value;

const FILE: &str = "\
// two obstacles in a 50 m square
region    = pts={0,0:0,-50:50,-50:50,0}
min_range = 2
min_size  = 4
max_size  = 6
poly = pts={10,-10:14,-10:14,-14:10,-14},label=ob_0
poly = pts={30,-30:34,-30:34,-34:30,-34},label=ob_1,vsource=sim
";

fn sim(lines: &[&str], file: &str) -> (ObstacleSim, Vec<String>) {
    ObstacleSim::new(lines, Some(("ob.txt", file)), 11)
}

fn posts<'a>(out: &'a [Post], key: &str) -> Vec<&'a str> {
    out.iter()
        .filter(|p| p.key == key)
        .map(|p| p.value.as_str().unwrap_or(""))
        .collect()
}

fn report(name: &str, x: f64, y: f64) -> Value {
    Value::text(format!(
        "NAME={name},TYPE=kayak,X={x},Y={y},SPD=1,HDG=0,TIME=100,COLOR=yellow"
    ))
}

#[test]
fn the_corpus_obstacle_files_read_clean() {
    let root = test_support::mission_file("");
    for (rel, n, min_range) in [
        ("m2_berta_obstacles/obstacles.txt", 5, 2.0),
        ("m2_berta_otest/obstacles.txt", 5, 2.0),
        ("m2_berta_otest/obstacles_one.txt", 1, 2.0),
        ("m2_berta_tx/obstacles.txt", 5, 2.0),
        ("m34_bo_alpha/obstacles.txt", 5, 20.0),
    ] {
        let text = std::fs::read_to_string(root.join(rel)).unwrap();
        let f = ObstacleFile::parse(rel, &text);
        assert!(f.ok && f.problems.is_empty(), "{rel}: {:?}", f.problems);
        assert_eq!(f.obstacles.len(), n, "{rel}");
        assert_eq!(
            (f.min_range, f.min_size, f.max_size),
            (min_range, 6.0, 10.0)
        );
        let region = f.region.expect("a region");
        assert_eq!(region.attrs.label, "obs_region");
        assert_eq!(region.polygon.len(), 4);
        assert!(f.obstacles.iter().all(|o| o.polygon.is_convex()));
        assert_eq!(f.obstacles[0].polygon.len(), 8, "{rel}");
    }
}

#[test]
fn every_bad_line_is_refused_at_its_file_and_line() {
    let bad = |text: &str| ObstacleFile::parse("ob.txt", text);
    // A region or an obstacle that is not convex stops the reading there; what came before
    // is kept.
    let f = bad("min_size = 4\nmax_size = 6\nmin_range = 2\n\
         poly = pts={0,0:4,0:4,4},label=a\nregion = pts={0,0:10,10:10,0:0,10}\n\
         poly = pts={20,0:24,0:24,4},label=b\n");
    assert!(!f.ok);
    assert_eq!(f.obstacles.len(), 1);
    assert_eq!(
        f.problems[0].to_string(),
        "ob.txt:5: Poorly specified region: pts={0,0:10,10:10,0:0,10}"
    );
    let f = bad("min_size = 4\npoly = pts={0,0:4,4:4,0:0,4},label=a\nmax_size = 6\n");
    assert_eq!(
        f.problems[0].to_string(),
        "ob.txt:2: Poorly specified obstacle: pts={0,0:4,4:4,0:0,4},label=a"
    );
    assert_eq!((f.ok, f.max_size), (false, 0.0), "the rest is not read");
    let f = bad("poly = nonsense\n");
    assert_eq!(
        f.problems[0].to_string(),
        "ob.txt:1: Poorly specified obstacle: nonsense"
    );
    // Bad numbers are warned and the reading goes on.
    let f = bad(
        "min_range = -2\nmin_size = x\nmax_size = 6m\nmin_size = 4\nmax_size = 6\n\
         min_range = 3\nrange = 4\n",
    );
    let got: Vec<String> = f.problems.iter().map(ToString::to_string).collect();
    assert_eq!(
        got,
        [
            "ob.txt:1: Poorly specified min_range: -2",
            "ob.txt:2: Poorly specified min_size: x",
            "ob.txt:3: Poorly specified max_size: 6m",
            "ob.txt:7: not an obstacle file line (ignored, as uFldObstacleSim ignores it): range = 4",
        ]
    );
    assert!(f.ok);
    assert_eq!(f.min_range_posts, [0.0, 3.0]);
    // The checks after the file, in the C++'s order.
    for (text, why) in [
        (
            "max_size = 6\nmin_range = 2\n",
            "Unset or non-positive min_poly_size",
        ),
        ("min_size = 6\nmin_range = 2\n", "Unset max_poly_size"),
        (
            "min_size = 6\nmax_size = 8\n",
            "Unset or non-positive min_range",
        ),
        (
            "min_size = 9\nmax_size = 8\nmin_range = 2\n",
            "min_poly_size greater than max_poly_size",
        ),
    ] {
        let f = bad(text);
        assert!(!f.ok, "{text}");
        assert_eq!(f.problems.len(), 1);
        assert_eq!(f.problems[0].to_string(), format!("ob.txt: {why}"));
    }
    assert_eq!(
        bad("min_size = 9\nmax_size = 8\nmin_range = 2\n").min_size,
        8.0
    );
    // `#` lines are comments (gen_obstacles writes one), `//` too.
    assert!(bad("# gen_obstacles --amt=5\n// x = y\n\n").problems.len() == 1);
}

#[test]
fn block_lines_read_as_the_cpp_reads_them() {
    // Every parameter the catalog lists is taken with a good value.
    let good = |p: &str| match p {
        "obstacle_file" => "ob.txt",
        p if p.contains("color") => "red",
        "draw_region" | "post_points" | "reuse_ids" | "post_visuals" => "false",
        _ => "3",
    };
    for p in mission::catalog::OBSTACLE_SIM_PARAMS {
        let line = format!("{p} = {}", good(p));
        let (_, w) = ObstacleSim::new(&[line.as_str()], None, 1);
        assert!(w.is_empty(), "{line}: {w:?}");
    }
    let (s, w) = ObstacleSim::new(
        &[
            "poly_vert_color = bluish",
            "poly_vert_size = -1",
            "post_points = maybe",
            "min_duration = soon",
            "sensor_rng = 20",
            "AppTick = 4",
        ],
        None,
        1,
    );
    assert_eq!(
        w,
        [
            "Unhandled config line: poly_vert_color=bluish",
            "Unhandled config line: poly_vert_size=-1",
            "Unhandled config line: post_points=maybe",
            "Unhandled config line: min_duration=soon",
            "Unhandled config line: sensor_rng=20",
        ]
    );
    assert_eq!(s.s.poly_vert_color, "gray50");
    // min_duration and max_duration keep min <= max; a negative min goes to 0 with a max.
    let (s, _) = ObstacleSim::new(&["max_duration = 5", "min_duration = 8"], None, 1);
    assert_eq!((s.s.min_duration, s.s.max_duration), (8.0, 8.0));
    let (s, _) = ObstacleSim::new(&["min_duration = 8", "max_duration = 5"], None, 1);
    assert_eq!((s.s.min_duration, s.s.max_duration), (5.0, 5.0));
    let (s, _) = ObstacleSim::new(&["max_duration = 5"], None, 1);
    assert_eq!((s.s.min_duration, s.s.max_duration), (0.0, 5.0));
    // A file's problems follow the block's, and a failed file is an unhandled line.
    let (s, w) = sim(
        &["poly_fill_color = green"],
        "poly = pts={0,0:1,0:1,1:0,1},label=z\n",
    );
    assert_eq!(
        w,
        [
            "ob.txt: Unset or non-positive min_poly_size",
            "Unhandled config line: obstacle_file=ob.txt"
        ]
    );
    assert_eq!(s.obstacles().len(), 1, "the obstacle is kept");
    assert_eq!(s.obstacles()[0].attrs.fill_color.as_deref(), Some("green"));
    let (_, w) = ObstacleSim::new(&[], Some(("none.txt", "")), 1);
    assert_eq!(
        w,
        [
            "Error reading: none.txt",
            "Unhandled config line: obstacle_file=none.txt"
        ]
    );
}

#[test]
fn a_refresh_posts_the_obstacles_and_region_as_the_cpp_writes_them() {
    let (mut s, w) = sim(&["max_duration = 300", "min_duration = 200"], FILE);
    assert!(w.is_empty(), "{w:?}");
    let mut out = Vec::new();
    s.on_startup(5.0, &mut out);
    assert_eq!(posts(&out, "PLOGGER_CMD"), ["COPY_FILE_REQUEST = ob.txt"]);
    assert_eq!(
        out.iter()
            .filter(|p| p.key == "UFOS_MIN_RNG")
            .map(|p| p.value.as_f64())
            .collect::<Vec<_>>(),
        [Some(2.0)]
    );
    out.clear();
    // Nothing until a vehicle or a viewer asks.
    s.iterate(6.0, &mut out);
    assert!(out.is_empty(), "{out:?}");
    s.on_mail("NODE_REPORT", &report("abe", -100.0, 0.0), 6.5, &mut out);
    s.iterate(7.0, &mut out);
    assert_eq!(
        posts(&out, "VIEW_POLYGON"),
        [
            "pts={10,-10:14,-10:14,-14:10,-14},label=ob_0,label_color=invisible,\
             edge_color=gray50,vertex_color=gray50,fill_color=white,vertex_size=1,\
             edge_size=1,fill_transparency=0.15",
            "pts={30,-30:34,-30:34,-34:30,-34},label=ob_1,vsource=sim,label_color=invisible,\
             edge_color=gray50,vertex_color=gray50,fill_color=white,vertex_size=1,\
             edge_size=1,fill_transparency=0.15",
            "pts={0,0:0,-50:50,-50:50,0},label=obs_region,edge_color=gray50,vertex_color=white",
        ]
    );
    let known = posts(&out, "KNOWN_OBSTACLE");
    assert_eq!(known, posts(&out, "GIVEN_OBSTACLE"));
    assert_eq!(known.len(), 2);
    for (k, (spec, d)) in known.iter().zip(s.durations()).enumerate() {
        assert!((200.0..=300.0).contains(d), "{d}");
        let head = if k == 0 {
            "pts={10,-10:14,-10:14,-14:10,-14},label=ob_0,duration="
        } else {
            "pts={30,-30:34,-30:34,-34:30,-34},label=ob_1,vsource=sim,duration="
        };
        assert_eq!(*spec, format!("{head}{}", compact_string(*d, 5)));
    }
    // Once only; again on PMV_CONNECT; and every refresh_interval.
    out.clear();
    s.on_mail("NODE_REPORT", &report("abe", -90.0, 0.0), 7.5, &mut out);
    s.iterate(8.0, &mut out);
    assert!(out.is_empty());
    s.on_mail("PMV_CONNECT", &Value::text("true"), 8.5, &mut out);
    s.iterate(9.0, &mut out);
    assert_eq!(posts(&out, "KNOWN_OBSTACLE").len(), 2);
    let (mut s, _) = sim(&["refresh_interval = 10", "draw_region = false"], FILE);
    let mut n = Vec::new();
    for t in 0..25 {
        let mut out = Vec::new();
        s.iterate(f64::from(t), &mut out);
        if !out.is_empty() {
            n.push(t);
            assert_eq!(posts(&out, "VIEW_POLYGON").len(), 2, "no region");
        }
    }
    // The first refresh when more than the interval has passed since -1 (the C++'s start).
    assert_eq!(n, [10, 21]);
}

#[test]
fn points_lie_on_the_seen_side_of_each_obstacle_in_sensor_range() {
    let square = geometry::spec::parse_polygon("pts={10,-10:14,-10:14,-14:10,-14}")
        .unwrap()
        .polygon;
    let mut rng = fastrand::Rng::with_seed(3);
    let (vx, vy) = (0.0, 0.0);
    let (bmin, bmax) = behaviors::obstacle::geom::bearing_min_max(vx, vy, &square).unwrap();
    let mut bearings = std::collections::BTreeSet::new();
    let mut missed = 0;
    for _ in 0..2000 {
        // A ray along a bounding bearing grazes a vertex and may miss, as in the C++.
        let Some(p) = rand_point_on_poly(vx, vy, &square, &mut rng) else {
            missed += 1;
            continue;
        };
        // On the boundary...
        assert!(square.dist_to_boundary(p.x, p.y).unwrap() < 1e-9, "{p:?}");
        // ... on the side facing the viewer: nothing of the obstacle between.
        let near = Point::new(p.x * 0.999, p.y * 0.999);
        assert!(!square.contains(near.x, near.y), "{p:?}");
        let b = geometry::angle::relative_angle(vx, vy, p.x, p.y);
        assert!(
            b >= bmin - 1e-9 && b <= bmax + 1e-9,
            "{b} in {bmin}..{bmax}"
        );
        bearings.insert(b.round() as i64);
    }
    // Whole degrees across the obstacle's span (125.5 to 144.5 degrees).
    assert!(bearings.len() >= 17, "{bearings:?}");
    eprintln!("{missed} of 2000 draws missed");
    assert!(missed < 200, "{missed}");
    assert!(rand_point_on_poly(12.0, -12.0, &square, &mut rng).is_none());

    // The app: 3 points a vehicle a iteration for each obstacle within sensor_range only.
    let (mut s, w) = sim(
        &["post_points = true", "rate_points = 3", "sensor_range = 20"],
        FILE,
    );
    assert!(w.is_empty(), "{w:?}");
    let mut out = Vec::new();
    s.on_mail("NODE_REPORT", &report("abe", 0.0, 0.0), 1.0, &mut out);
    s.iterate(1.0, &mut out);
    let pts = posts(&out, "TRACKED_FEATURE_ABE");
    assert_eq!(pts.len(), 3, "ob_1 is 42 m off: {pts:?}");
    assert!(
        posts(&out, "GIVEN_OBSTACLE").is_empty(),
        "sensing, not giving"
    );
    assert_eq!(posts(&out, "KNOWN_OBSTACLE").len(), 2);
    let views = posts(&out, "VIEW_POINT");
    assert_eq!(views.len(), 3);
    for (k, (p, v)) in pts.iter().zip(&views).enumerate() {
        let f = |key: &str| {
            p.split(',')
                .find_map(|kv| kv.strip_prefix(key))
                .and_then(|t| t.parse::<f64>().ok())
                .unwrap()
        };
        let (x, y) = (f("x="), f("y="));
        assert!(p.ends_with(",key=ob_0"), "{p}");
        // Two decimals at most, on the square's boundary.
        assert_eq!(compact_string(x, 2), format!("{x}"));
        assert!(square.dist_to_boundary(x, y).unwrap() < 0.006, "{p}");
        assert_eq!(
            *v,
            format!(
                "x={x},y={y},label=abe:ob_0:{},label_color=invisible,vertex_color=yellow,\
                 duration=10,vertex_size=2",
                k + 1
            )
        );
    }
    // A second vehicle near ob_1 sees it, under its own name.
    let mut out = Vec::new();
    s.on_mail("NODE_REPORT", &report("Ben", 45.0, -45.0), 2.0, &mut out);
    s.iterate(2.0, &mut out);
    assert_eq!(posts(&out, "TRACKED_FEATURE_ABE").len(), 3);
    let ben = posts(&out, "TRACKED_FEATURE_BEN");
    assert_eq!(ben.len(), 3);
    assert!(
        ben.iter().all(|p| p.ends_with(",key=ob_1,vsource=sim")),
        "{ben:?}"
    );
    // UFOS_POINT_SIZE changes the drawn size.
    s.on_mail("UFOS_POINT_SIZE", &Value::text("bigger"), 3.0, &mut out);
    let mut out = Vec::new();
    s.iterate(3.0, &mut out);
    assert!(posts(&out, "VIEW_POINT")[0].ends_with(",vertex_size=3"));
}

#[test]
fn mail_that_is_not_the_apps_is_a_bad_mail_warning() {
    let (mut s, _) = sim(&[], FILE);
    let mut out = Vec::new();
    s.on_mail("VEHICLE_CONNECT", &Value::text("true"), 1.0, &mut out);
    s.on_mail("NODE_REPORT", &Value::text("X=1,Y=2"), 1.0, &mut out);
    s.on_mail(
        "NODE_REPORT",
        &Value::text("NAME=al,X=1,Y=2,TIME=3,TYPE=auv"),
        1.0,
        &mut out,
    );
    s.on_mail("UFOS_POINT_SIZE", &Value::text("0.5"), 1.0, &mut out);
    let w: Vec<String> = s
        .take_notes()
        .into_iter()
        .map(|n| match n {
            Note::Warning(w) => w,
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(
        w,
        [
            "Bad Mail: VEHICLE_CONNECT",
            "Bad Mail: NODE_REPORT Missing vname.Missing timestamp.",
            "Bad Mail: NODE_REPORT underwater vehicle type with no depth reported",
            "Bad Mail: UFOS_POINT_SIZE",
        ]
    );
    assert!(out.is_empty());
}

/// The obstacles regenerated in the region: 8-vertex obstacles wholly inside it, sized
/// between min_size and max_size, `min_range` apart; with `reuse_ids = false` the old ones
/// erased and the new ones numbered on.
#[test]
fn the_field_is_regenerated_once_the_vehicle_has_left_the_region() {
    let (mut s, _) = sim(
        &[
            "reset_interval = 5",
            "reset_range = 10",
            "reuse_ids = false",
        ],
        FILE,
    );
    let mut out = Vec::new();
    s.on_startup(0.0, &mut out);
    let mut t = 0.0;
    let mut step = |s: &mut ObstacleSim, x: f64, y: f64| {
        t += 1.0;
        let mut out = Vec::new();
        s.on_mail("NODE_REPORT", &report("abe", x, y), t, &mut out);
        s.iterate(t, &mut out);
        out
    };
    // Outside, never in: no reset.
    for _ in 0..10 {
        assert!(posts(&step(&mut s, -30.0, 0.0), "KNOWN_OBSTACLE_CLEAR").is_empty());
    }
    // In, then out beyond reset_range: one regeneration.
    step(&mut s, 25.0, -25.0);
    assert!(posts(&step(&mut s, -5.0, 0.0), "KNOWN_OBSTACLE_CLEAR").is_empty());
    let out = step(&mut s, -20.0, 0.0);
    assert_eq!(posts(&out, "KNOWN_OBSTACLE_CLEAR"), ["all"]);
    let erased = posts(&out, "GIVEN_OBSTACLE");
    assert_eq!(
        &erased[..2],
        [
            "pts={0,0:9,0:0,9},active=false,label=ob_0,duration=0",
            "pts={0,0:9,0:0,9},active=false,label=ob_1,duration=0"
        ]
    );
    let region = geometry::spec::parse_polygon("pts={0,0:0,-50:50,-50:50,0}")
        .unwrap()
        .polygon;
    let obs = s.obstacles().to_vec();
    assert_eq!(
        obs.iter()
            .map(|o| o.attrs.label.as_str())
            .collect::<Vec<_>>(),
        ["ob_2", "ob_3"]
    );
    for o in &obs {
        let p = &o.polygon;
        assert_eq!(p.len(), 8);
        assert!(p.vertices().iter().all(|v| region.contains(v.x, v.y)));
        let c = p.center();
        let r = p
            .vertices()
            .iter()
            .map(|v| (v.x - c.x).hypot(v.y - c.y))
            .fold(0.0, f64::max);
        assert!((1.9..=3.1).contains(&r), "radius {r}");
        assert_eq!(o.attrs.edge_color.as_deref(), Some("gray50"));
    }
    assert!(poly_poly_dist(&obs[0].polygon, &obs[1].polygon) >= 2.0);
    assert!(posts(&out, "GIVEN_OBSTACLE")[2].contains("label=ob_2"));
    // Not again until the vehicle goes in and out anew; UFOS_RESET asks at once.
    assert!(posts(&step(&mut s, -20.0, 0.0), "KNOWN_OBSTACLE_CLEAR").is_empty());
    s.on_mail("UFOS_RESET", &Value::text("true"), 30.0, &mut Vec::new());
    assert_eq!(
        posts(&step(&mut s, -20.0, 0.0), "KNOWN_OBSTACLE_CLEAR"),
        ["all"]
    );
    // The same seed makes the same field.
    let (mut a, _) = sim(&[], FILE);
    let (mut b, _) = sim(&[], FILE);
    for x in [&mut a, &mut b] {
        x.on_mail("UFOS_RESET", &Value::text("x"), 1.0, &mut Vec::new());
        x.on_mail(
            "NODE_REPORT",
            &report("abe", -20.0, 0.0),
            1.0,
            &mut Vec::new(),
        );
        x.iterate(1.0, &mut Vec::new());
    }
    assert_eq!(a.obstacles(), b.obstacles());
    assert_eq!(a.obstacles()[0].attrs.label, "ob_0", "ids reused");
}

#[test]
fn the_app_reads_its_obstacle_file_beside_the_mission() {
    let dir = test_support::fresh_dir(
        std::env::temp_dir().join(format!("obstsim-app-{}", std::process::id())),
    );
    std::fs::write(dir.join("ob.txt"), FILE).unwrap();
    let block = crate::testing::block(
        "m.moos",
        "ProcessConfig = uFldObstacleSim\n{\n  AppTick = 2\n  obstacle_file = ob.txt\n  \
         poly_vert_color = fuzzy\n}\n",
    );
    let grid = vehicle::geodesy::LocalGrid::new(42.358456, -71.087589).ok();
    let app = ObstacleSimApp::new("uFldObstacleSim", block.clone(), &dir, 1, grid);
    let w: Vec<String> = app.warnings().iter().map(|d| d.located()).collect();
    assert_eq!(
        w,
        ["m.moos:5: uFldObstacleSim: Unhandled config line: poly_vert_color=fuzzy"]
    );
    let bare = ObstacleSimApp::new("uFldObstacleSim", block.clone(), &dir, 1, None);
    assert!(
        bare.warnings()[1]
            .located()
            .ends_with("uFldObstacleSim: Lat or Lon Origin not set in *.moos file."),
        "{:?}",
        bare.warnings()
    );
    assert_eq!(app.core().obstacles().len(), 2);
    use crate::app::App;
    assert_eq!(app.app_tick(), 2.0);
    let subs: Vec<String> = app.subscriptions().into_iter().map(|s| s.pattern).collect();
    assert!(subs.contains(&"NODE_REPORT".to_string()) && subs.contains(&"UFOS_RESET".into()));
    let _ = std::fs::remove_dir_all(&dir);
}
