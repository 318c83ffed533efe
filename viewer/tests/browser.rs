//! The page in headless Chromium: screenshots of known scenes, and assertions on their pixels
//! (the vehicle glyph's colour where the page's fit-to-scene transform puts a known
//! NODE_REPORT, polygon vertices where they should be). The transform is the page's
//! (`assets/viewer.js`): the box around every vehicle position, shape point and background
//! image corner, at least
//! 20 m a side, centred and scaled to leave 40 px each side of the map canvas (the window
//! minus the 320 px side panel).
//!
//! Chromium is Debian's `chromium` (installed by `.ci/run`). Without it the tests fail
//! under `CI=true`; elsewhere they say loudly that they did not run. With
//! `COUG_VIEWER_SCREENSHOTS=DIR` the screenshots are also copied to `DIR` (how
//! `docs/viewer/` was made).

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;

use moos_types::Value;
use serde_json::Value as Json;
use viewer::server::{Outbox, Viewer, ViewerConfig, serve};

mod support;
use support::chromium;

const W: u32 = 1200;
const H: u32 = 800;
const BACKGROUND: [u8; 3] = [0x0b, 0x1d, 0x2a];

struct NoPosts;

impl Outbox for NoPosts {
    fn post(&self, _: &str, _: Value) -> Result<(), String> {
        Err("test".into())
    }
    fn moos_time(&self) -> f64 {
        0.0
    }
}

/// Serves `viewer` on a loopback port from a runtime on its own thread; returns the port.
fn serve_on_thread(viewer: Arc<Viewer>) -> (u16, tokio::runtime::Runtime) {
    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .unwrap();
    let listener = rt
        .block_on(tokio::net::TcpListener::bind("127.0.0.1:0"))
        .unwrap();
    let port = listener.local_addr().unwrap().port();
    rt.spawn(serve(viewer, listener));
    (port, rt)
}

/// A screenshot of the page at `port`, as RGB rows.
fn screenshot(chromium: &Path, port: u16, name: &str) -> (Vec<u8>, PathBuf) {
    screenshot_at(chromium, port, "/", name)
}

/// The page's DOM once its script has run (`chromium --dump-dom`) at `path`.
fn dump_dom(chromium: &Path, port: u16, path: &str, name: &str) -> String {
    let dir = test_support::scratch_dir(&format!("viewer-browser-{name}-dom"));
    let out = Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--force-device-scale-factor=1",
            "--no-first-run",
            "--virtual-time-budget=4000",
            &format!("--user-data-dir={}", dir.join("profile").display()),
            &format!("--window-size={W},{H}"),
            "--dump-dom",
            &format!("http://127.0.0.1:{port}{path}"),
        ])
        .output()
        .expect("chromium runs");
    let dom = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        dom.contains("id=\"chart\""),
        "no DOM from chromium: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    dom
}

/// An attribute of the element with `id` in a dumped DOM.
fn attribute(dom: &str, id: &str, name: &str) -> String {
    let at = dom
        .find(&format!("id=\"{id}\""))
        .unwrap_or_else(|| panic!("no #{id}"));
    let tag_start = dom[..at].rfind('<').unwrap();
    let tag = &dom[tag_start..tag_start + dom[tag_start..].find('>').unwrap()];
    let key = format!(" {name}=\"");
    let v = tag
        .find(&key)
        .unwrap_or_else(|| panic!("#{id} has no {name}: {tag}"));
    let rest = &tag[v + key.len()..];
    rest[..rest.find('"').unwrap()].to_string()
}

/// A screenshot of the page at `port` and `path` (`/`, `/?follow=NAME`), as RGB rows.
fn screenshot_at(chromium: &Path, port: u16, path: &str, name: &str) -> (Vec<u8>, PathBuf) {
    let dir = test_support::scratch_dir(&format!("viewer-browser-{name}"));
    let png = dir.join(format!("{name}.png"));
    let profile = dir.join("profile");
    let out = Command::new(chromium)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--force-device-scale-factor=1",
            "--no-first-run",
            "--virtual-time-budget=4000",
            &format!("--user-data-dir={}", profile.display()),
            &format!("--window-size={W},{H}"),
            &format!("--screenshot={}", png.display()),
            &format!("http://127.0.0.1:{port}{path}"),
        ])
        .output()
        .expect("chromium runs");
    assert!(
        png.is_file(),
        "no screenshot from chromium: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&png).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (W, H), "screenshot size");
    let channels = info.color_type.samples();
    let rgb: Vec<u8> = buf[..info.buffer_size()]
        .chunks(channels)
        .flat_map(|p| [p[0], p[1], p[2]])
        .collect();
    if let Ok(dest) = std::env::var("COUG_VIEWER_SCREENSHOTS") {
        std::fs::create_dir_all(&dest).unwrap();
        std::fs::copy(&png, Path::new(&dest).join(format!("{name}.png"))).unwrap();
    }
    (rgb, png)
}

fn pixel(rgb: &[u8], x: f64, y: f64) -> [u8; 3] {
    let (x, y) = (x.round() as usize, y.round() as usize);
    let i = (y * W as usize + x) * 3;
    [rgb[i], rgb[i + 1], rgb[i + 2]]
}

/// The page's fit-to-scene transform for the scene's snapshot: world (x, y) to pixels.
fn transform(snapshot: &Json) -> impl Fn(f64, f64) -> (f64, f64) {
    let (scale, cx, cy) = fit(snapshot);
    let (cw, ch) = (f64::from(W - 320), f64::from(H));
    move |x, y| (cw / 2.0 + (x - cx) * scale, ch / 2.0 - (y - cy) * scale)
}

/// The page's transform when it follows a vehicle at (fx, fy): the fit's scale, centred there.
fn transform_following(snapshot: &Json, fx: f64, fy: f64) -> impl Fn(f64, f64) -> (f64, f64) {
    let (scale, _, _) = fit(snapshot);
    let (cw, ch) = (f64::from(W - 320), f64::from(H));
    move |x, y| (cw / 2.0 + (x - fx) * scale, ch / 2.0 - (y - fy) * scale)
}

/// The page's fit to the scene: scale (px/m) and centre.
fn fit(snapshot: &Json) -> (f64, f64, f64) {
    let mut b: Option<[f64; 4]> = None;
    let mut add = |x: Option<f64>, y: Option<f64>| {
        if let (Some(x), Some(y)) = (x, y) {
            b = Some(match b {
                None => [x, y, x, y],
                Some(b) => [b[0].min(x), b[1].min(y), b[2].max(x), b[3].max(y)],
            });
        }
    };
    for v in snapshot["vehicles"].as_array().unwrap() {
        add(v["x"].as_f64(), v["y"].as_f64());
    }
    let bg = &snapshot["background"];
    add(bg["left"].as_f64(), bg["bottom"].as_f64());
    add(bg["right"].as_f64(), bg["top"].as_f64());
    for s in snapshot["shapes"].as_array().unwrap() {
        match s["pts"].as_array() {
            Some(pts) => {
                for p in pts {
                    add(p[0].as_f64(), p[1].as_f64());
                }
            }
            None => add(s["x"].as_f64(), s["y"].as_f64()),
        }
    }
    let b = b.expect("a scene with something in it");
    let (cw, ch) = (f64::from(W - 320), f64::from(H));
    let dx = (b[2] - b[0]).max(20.0);
    let dy = (b[3] - b[1]).max(20.0);
    let scale = ((cw - 80.0) / dx).min((ch - 80.0) / dy);
    (scale, (b[0] + b[2]) / 2.0, (b[1] + b[3]) / 2.0)
}

fn near(a: [u8; 3], b: [u8; 3]) -> bool {
    a.iter().zip(b).all(|(x, y)| x.abs_diff(y) <= 8)
}

#[test]
fn three_vehicles_and_a_polygon_are_drawn_where_their_reports_put_them() {
    let Some(chromium) = chromium() else { return };
    let config = ViewerConfig {
        bind: "127.0.0.1:0".parse().unwrap(),
        ..ViewerConfig::default()
    };
    let viewer = Viewer::new(&config, Arc::new(NoPosts)).unwrap();
    let t = 100.0;
    viewer.apply(
        "NODE_REPORT",
        "NAME=abe,TYPE=kayak,X=0,Y=0,HDG=0,SPD=1.2,DEP=0,TIME=100",
        t,
    );
    viewer.apply(
        "NODE_REPORT",
        "NAME=ben,TYPE=auv,X=150,Y=60,HDG=90,SPD=1.5,DEP=4,TIME=100",
        t,
    );
    viewer.apply(
        "NODE_REPORT",
        "NAME=cal,TYPE=uuv,X=-80,Y=110,HDG=200,SPD=1,DEP=2,COLOR=cyan,TIME=100",
        t,
    );
    viewer.apply(
        "VIEW_POLYGON",
        "pts={-60,-40:120,-40:120,90:-60,90},label=ops,edge_color=white,vertex_color=magenta",
        t,
    );
    let snapshot = viewer.with_scene(|s| s.snapshot());
    let to_px = transform(&snapshot);
    let (port, _rt) = serve_on_thread(viewer);
    let (rgb, png) = screenshot(&chromium, port, "three_vehicles");
    // Each glyph, filled with the vehicle's colour: the palette by name order, or COLOR.
    for (name, x, y, color) in [
        ("abe", 0.0, 0.0, [0xff, 0xd7, 0x00]),
        ("ben", 150.0, 60.0, [0xff, 0x4f, 0xa0]),
        ("cal", -80.0, 110.0, [0x00, 0xff, 0xff]),
    ] {
        let (px, py) = to_px(x, y);
        let got = pixel(&rgb, px, py);
        assert!(
            near(got, color),
            "{name} at ({px:.0}, {py:.0}) is {got:?}, expected {color:?} ({})",
            png.display()
        );
    }
    // The polygon's vertices (magenta squares) where the transform puts them, and the map
    // around them background.
    for (x, y) in [(-60.0, -40.0), (120.0, -40.0), (120.0, 90.0), (-60.0, 90.0)] {
        let (px, py) = to_px(x, y);
        let got = pixel(&rgb, px, py);
        assert!(
            near(got, [0xff, 0x00, 0xff]),
            "vertex ({x}, {y}) at ({px:.0}, {py:.0}) is {got:?}"
        );
        assert!(near(pixel(&rgb, px - 25.0, py + 17.0), BACKGROUND) || x > 0.0 || y > 0.0);
    }
    // The side panel lists the three vehicles: not the map's background there.
    assert!(!near(pixel(&rgb, f64::from(W) - 100.0, 5.0), BACKGROUND));
}

#[test]
fn alpha_mid_survey_draws_the_vehicle_on_its_reported_spot_and_its_waypoints() {
    use runtime::session::{self, Mode, Quiet, RunOptions};
    use viewer::live::{LiveView, ViewObserver};
    let Some(chromium) = chromium() else { return };
    let alpha = test_support::mission_file("s1_alpha/alpha.moos");
    let loaded = session::load(&alpha, &[], &[]).expect("alpha loads");
    let dir = test_support::scratch_dir("viewer-browser-alpha-logs");
    let live = LiveView::start(&ViewerConfig {
        bind: "127.0.0.1:0".parse().unwrap(),
        buttons: mission::buttons::buttons(&loaded.mission),
        ..ViewerConfig::default()
    })
    .unwrap();
    let opts = RunOptions {
        mode: Mode::Lockstep,
        deploy: true,
        max_time: 150.0,
        log_dir: Some(dir),
        ..RunOptions::default()
    };
    let mut quiet = Quiet;
    let mut view = ViewObserver::new(&mut quiet, &live, session::LOCKSTEP_START, None);
    session::run(&loaded, &opts, &mut view).expect("alpha runs");
    let snapshot = live.viewer().with_scene(|s| s.snapshot());
    let v = &snapshot["vehicles"][0];
    assert_eq!(v["name"], "alpha");
    let (x, y) = (v["x"].as_f64().unwrap(), v["y"].as_f64().unwrap());
    let to_px = transform(&snapshot);
    let (rgb, png) = screenshot(&chromium, live.addr().port(), "alpha_mid_survey");
    let (px, py) = to_px(x, y);
    let expected = match v["color"].as_str() {
        Some("") | None => [0xff, 0xd7, 0x00],
        // alpha's pNodeReporter reports COLOR=yellow (MOOS yellow, handed over as CSS).
        Some("#ffff00") => [0xff, 0xff, 0x00],
        Some(c) => panic!("alpha reports COLOR={c}; the test knows none and yellow"),
    };
    let got = pixel(&rgb, px, py);
    assert!(
        near(got, expected),
        "alpha at ({x:.1}, {y:.1}) -> ({px:.0}, {py:.0}) is {got:?} ({})",
        png.display()
    );
    // The appcast pane lists alpha's apps and shows the first one's report.
    let dom = dump_dom(&chromium, live.addr().port(), "/", "alpha_mid_survey");
    for app in [
        "alpha/pHelmIvP",
        "alpha/pMarinePIDV22",
        "alpha/uSimMarineV22",
        "alpha/pNodeReporter",
    ] {
        assert!(
            dom.contains(&format!("<option value=\"{app}\"")),
            "{app} in {dom}"
        );
    }
    let report = &dom[dom.find("<pre id=\"report\">").expect("the report pane")..];
    assert!(
        report.len() > 200 && !report.starts_with("<pre id=\"report\"></pre>"),
        "{report}"
    );
    // Every waypoint of the survey's seglist is drawn (a vertex square, not background).
    let seglist = snapshot["shapes"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["kind"] == "seglist")
        .expect("the waypoint behaviour's VIEW_SEGLIST");
    let pts = seglist["pts"].as_array().unwrap();
    assert!(pts.len() >= 3, "{seglist}");
    for p in pts {
        let (vx, vy) = to_px(p[0].as_f64().unwrap(), p[1].as_f64().unwrap());
        let got = pixel(&rgb, vx, vy);
        assert!(
            !near(got, BACKGROUND),
            "waypoint {p} at ({vx:.0}, {vy:.0}) not drawn ({})",
            png.display()
        );
    }
}

#[test]
fn the_background_image_is_drawn_where_its_info_puts_it() {
    use viewer::background::{Background, Placement};
    let Some(chromium) = chromium() else { return };
    // A 40 x 20 px image in four colours, on the box x -100..300, y -200..100.
    let (w, h) = (40u32, 20u32);
    let quadrants: [[u8; 3]; 4] = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]];
    let mut rgba = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let q = usize::from(y >= h / 2) * 2 + usize::from(x >= w / 2);
            rgba.extend_from_slice(&quadrants[q]);
            rgba.push(255);
        }
    }
    let img = viewer::background::Rgba {
        width: w,
        height: h,
        data: rgba,
    };
    let bg = Background {
        file: "map.tif".into(),
        png: viewer::background::encode_png(&img),
        width: w,
        height: h,
        placement: Placement {
            left: -100.0,
            right: 300.0,
            bottom: -200.0,
            top: 100.0,
        },
    };
    let config = ViewerConfig {
        bind: "127.0.0.1:0".parse().unwrap(),
        background: Some(Arc::new(bg)),
        ..ViewerConfig::default()
    };
    let viewer = Viewer::new(&config, Arc::new(NoPosts)).unwrap();
    let mut snapshot = viewer.with_scene(|s| s.snapshot());
    snapshot["background"] = serde_json::json!({
        "left": -100.0, "right": 300.0, "bottom": -200.0, "top": 100.0
    });
    let to_px = transform(&snapshot);
    let (port, _rt) = serve_on_thread(viewer);
    let (rgb, png) = screenshot(&chromium, port, "background");
    // The middle of each quadrant, away from the 100 m grid lines.
    for ((x, y), color) in [
        (-37.0, 37.0),
        (163.0, 37.0),
        (-37.0, -137.0),
        (163.0, -137.0),
    ]
    .into_iter()
    .zip(quadrants)
    {
        let (px, py) = to_px(x, y);
        let got = pixel(&rgb, px, py);
        assert!(
            near(got, color),
            "({x}, {y}) at ({px:.0}, {py:.0}) is {got:?}, expected {color:?} ({})",
            png.display()
        );
    }
    // Outside the image: the map's own background.
    let (px, py) = to_px(-100.0, 100.0);
    assert!(near(pixel(&rgb, px - 10.0, py - 10.0), BACKGROUND));
}

/// Two vehicles seen for 100 s, one silent since the start (stale), the page opened after:
/// `?follow=ben` centres ben and lists him as followed; abe is drawn grey and listed stale;
/// the strip chart shows ben's depth and speed over the whole 100 s (the history comes with
/// the page's first snapshot).
#[test]
fn the_page_follows_a_vehicle_greys_a_stale_one_and_charts_the_history() {
    let Some(chromium) = chromium() else { return };
    let config = ViewerConfig {
        bind: "127.0.0.1:0".parse().unwrap(),
        ..ViewerConfig::default()
    };
    let viewer = Viewer::new(&config, Arc::new(NoPosts)).unwrap();
    viewer.apply("NODE_REPORT", "NAME=abe,X=0,Y=0,HDG=0,SPD=1,DEP=0", 0.0);
    for k in 0..=10 {
        let t = f64::from(k) * 10.0;
        viewer.apply(
            "NODE_REPORT",
            &format!("NAME=ben,X={t},Y=50,HDG=90,SPD=1.5,DEP=5"),
            t,
        );
    }
    // A marker far out, so the fit leaves room around ben for abe once ben is centred.
    viewer.apply("VIEW_POINT", "x=300,y=150,label=far", 100.0);
    viewer.tick(100.0);
    let snapshot = viewer.with_scene(|s| s.snapshot());
    assert_eq!(snapshot["vehicles"][0]["stale"], true, "abe is stale");
    // Following moves the view off the fit (the fit's centre is 150, 75).
    let fitted = transform(&snapshot);
    assert!(fitted(100.0, 50.0).0 < f64::from(W - 320) / 2.0 - 100.0);
    assert_eq!(
        snapshot["vehicles"][1]["history"].as_array().unwrap().len(),
        11
    );
    let to_px = transform_following(&snapshot, 100.0, 50.0);
    let (port, _rt) = serve_on_thread(viewer);
    let (rgb, png) = screenshot_at(&chromium, port, "/?follow=ben", "follow_stale_chart");
    let dom = dump_dom(&chromium, port, "/?follow=ben", "follow_stale_chart");

    // ben (the palette's second colour) at the map's centre; abe grey where the fit's
    // scale puts him from there.
    let (cw, ch) = (f64::from(W - 320), f64::from(H));
    assert_eq!(to_px(100.0, 50.0), (cw / 2.0, ch / 2.0));
    for (name, (px, py), color) in [
        ("ben", to_px(100.0, 50.0), [0xff, 0x4f, 0xa0]),
        ("abe", to_px(0.0, 0.0), [0x77, 0x77, 0x77]),
    ] {
        let got = pixel(&rgb, px, py);
        assert!(
            near(got, color),
            "{name} at ({px:.0}, {py:.0}) is {got:?}, expected {color:?} ({})",
            png.display()
        );
    }
    // The list: ben followed, abe stale.
    assert!(dom.contains("ben  hdg 90  spd 1.5  dep 5.0"), "{dom}");
    assert!(dom.contains("[following]"), "{dom}");
    assert!(dom.contains("abe  hdg 0  spd 1.0  dep 0.0"), "{dom}");
    assert!(dom.contains(" (stale)"), "{dom}");

    // The chart charts ben (followed, not the first name) with all 11 points: over its 300 s
    // window ending at t = 100, t = 10 and t = 90 lie at x = 210 and 290; depth 5 (the
    // maximum) at the bottom (y = 130), speed 1.5 (the maximum) at the top (y = 10).
    assert_eq!(attribute(&dom, "chart", "data-vehicle"), "ben");
    assert_eq!(attribute(&dom, "chart", "data-points"), "11");
    let left: f64 = attribute(&dom, "chart", "data-left").parse().unwrap();
    let top: f64 = attribute(&dom, "chart", "data-top").parse().unwrap();
    let line_near = |x: f64, y: f64, color: [u8; 3]| {
        (-1..=1).any(|dy| {
            let got = pixel(&rgb, left + x, top + y + f64::from(dy));
            // Half a line's colour at least over the chart's background.
            got.iter()
                .zip(color)
                .zip(BACKGROUND)
                .all(|((g, c), b)| g.abs_diff(b) * 2 + 8 >= c.abs_diff(b))
        })
    };
    for x in [210.0, 250.0, 290.0] {
        assert!(
            line_near(x, 130.0, [0x4f, 0xc3, 0xff]),
            "no depth line at ({x}, 130) of the chart ({})",
            png.display()
        );
        assert!(
            line_near(x, 10.0, [0x4f, 0xe3, 0x4f]),
            "no speed line at ({x}, 10) of the chart ({})",
            png.display()
        );
    }
    // Nothing charted before the history starts (t = 0 is x = 200; t = -10 is x = 190).
    assert!(!line_near(190.0, 130.0, [0x4f, 0xc3, 0xff]));
}

/// A range pulse and a comms pulse posted at t = 100, the scene at t = 105 (half their
/// 10 s): the range pulse is a disc of half its radius at half its fill, the comms pulse a
/// triangle from its source to a beam across its target, at half its fill.
#[test]
fn range_and_comms_pulses_grow_and_fade_as_pmarineviewer_draws_them() {
    let Some(chromium) = chromium() else { return };
    let config = ViewerConfig {
        bind: "127.0.0.1:0".parse().unwrap(),
        ..ViewerConfig::default()
    };
    let viewer = Viewer::new(&config, Arc::new(NoPosts)).unwrap();
    viewer.apply("NODE_REPORT", "NAME=abe,X=0,Y=0,HDG=0", 100.0);
    viewer.apply(
        "VIEW_RANGE_PULSE",
        "x=50,y=50,radius=40,duration=10,fill=1,fill_color=red,edge_color=red,label=ping",
        100.0,
    );
    viewer.apply(
        "VIEW_COMMS_PULSE",
        "sx=120,sy=20,tx=180,ty=80,beam_width=30,duration=10,fill=1,fill_color=blue,label=msg",
        100.0,
    );
    viewer.apply("NODE_REPORT", "NAME=ben,X=200,Y=100,HDG=0", 105.0);
    let snapshot = viewer.with_scene(|s| s.snapshot());
    let to_px = transform(&snapshot);
    let (port, _rt) = serve_on_thread(viewer);
    let (rgb, png) = screenshot(&chromium, port, "pulses");
    // Half red over the map's background, half blue.
    let half =
        |c: [u8; 3]| [0, 1, 2].map(|i| ((u16::from(c[i]) + u16::from(BACKGROUND[i])) / 2) as u8);
    for ((x, y), want, what) in [
        (
            (60.0, 50.0),
            half([255, 0, 0]),
            "inside the range pulse's 20 m",
        ),
        (
            (50.0, 38.0),
            half([255, 0, 0]),
            "inside the range pulse's 20 m",
        ),
        (
            (80.0, 50.0),
            BACKGROUND,
            "outside 20 m (the full radius is 40)",
        ),
        ((50.0, 82.0), BACKGROUND, "outside 20 m"),
        (
            (170.0, 70.0),
            half([0, 0, 255]),
            "inside the comms beam near the target",
        ),
        (
            (130.0, 30.0),
            half([0, 0, 255]),
            "inside the comms beam near the source",
        ),
        ((140.0, 80.0), BACKGROUND, "beside the comms beam"),
        ((183.0, 60.0), BACKGROUND, "beside the comms beam's target"),
    ] {
        let (px, py) = to_px(x, y);
        let got = pixel(&rgb, px, py);
        assert!(
            got.iter().zip(want).all(|(g, w)| g.abs_diff(w) <= 12),
            "({x}, {y}), {what}: ({px:.0}, {py:.0}) is {got:?}, expected {want:?} ({})",
            png.display()
        );
    }
}

/// `coug view LOG.alog`'s page, paused at 45 s of a 100 s log: abe where his report at 45 s
/// puts him, the polygon the log drew at 30 s (removed at 60 s), the replay bar's clock.
#[test]
fn a_replayed_log_is_drawn_at_the_playhead_with_its_time_bar() {
    use alog::{AlogWriter, Header, LogValue};
    use viewer::replay::Replay;
    let Some(chromium) = chromium() else { return };
    let header = Header {
        path: "./LOG/LOG.alog",
        opened_on: "Thu Jan  1 00:00:00 1970",
        log_start: 1000.0,
        mark_data_type: false,
    };
    let mut w = AlogWriter::new(Vec::new(), &header).unwrap();
    for k in 0..=100 {
        let t = 1000.0 + f64::from(k);
        let report = format!(
            "NAME=abe,X={k},Y=-5,SPD=1,HDG=90,DEP={}",
            f64::from(k) / 10.0
        );
        w.record(
            t,
            "NODE_REPORT_LOCAL",
            "pNodeReporter",
            LogValue::String(&report),
        )
        .unwrap();
        let polygon = match k {
            30 => "pts={0,0:60,0:60,40:0,40},label=box,vertex_color=magenta",
            60 => "pts={0,0:60,0:60,40:0,40},label=box,active=false",
            _ => continue,
        };
        w.record(t, "VIEW_POLYGON", "pHelmIvP", LogValue::String(polygon))
            .unwrap();
    }
    let log = alog::parse(&String::from_utf8(w.into_inner()).unwrap()).unwrap();
    let replay = Replay::from_alog(&log);
    let viewer = Viewer::new(
        &ViewerConfig {
            bind: "127.0.0.1:0".parse().unwrap(),
            ..ViewerConfig::default()
        },
        Arc::new(NoPosts),
    )
    .unwrap();
    // What the replay driver does on a seek while paused.
    viewer.rebuild(|s| replay.scene_at(s, 45.0));
    viewer.set_status(serde_json::json!({
        "t": 45.0, "start": 1000.0, "end": replay.duration(), "playing": false, "speed": 1.0
    }));
    let snapshot = viewer.with_scene(|s| s.snapshot());
    assert_eq!(snapshot["vehicles"][0]["x"], 45.0);
    let to_px = transform(&snapshot);
    let (port, _rt) = serve_on_thread(viewer);
    let (rgb, png) = screenshot(&chromium, port, "replay");
    let dom = dump_dom(&chromium, port, "/", "replay");
    let (px, py) = to_px(45.0, -5.0);
    assert!(
        near(pixel(&rgb, px, py), [0xff, 0xd7, 0x00]),
        "abe at ({px:.0}, {py:.0}) ({})",
        png.display()
    );
    for (x, y) in [(0.0, 0.0), (60.0, 0.0), (60.0, 40.0), (0.0, 40.0)] {
        let (vx, vy) = to_px(x, y);
        assert!(
            near(pixel(&rgb, vx, vy), [0xff, 0x00, 0xff]),
            "vertex ({x}, {y}) at ({vx:.0}, {vy:.0}) ({})",
            png.display()
        );
    }
    assert!(dom.contains(">45.0 / 100.0 s<"), "{dom}");
    assert!(dom.contains("<button id=\"play\">play</button>"), "{dom}");
    // The bar is shown (bottom left), not the map's background there.
    assert!(!near(pixel(&rgb, 12.0, f64::from(H) - 14.0), BACKGROUND));
}
