//! `coug plot` output checked by parsing it: the SVG is well-formed XML with the expected
//! elements, the PNG decodes to the expected size with the track drawn.

use runtime::plot::{PlotData, PlotError, PlotOptions, image_size, to_png, to_svg};

/// A synthetic dive: a square track at 2..8 m depth with a survey seglist, a loiter
/// polygon and a next-point marker.
fn synthetic(dive: bool) -> String {
    let mut s = String::from(
        "%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%\n%% LOGSTART           1700000000\n",
    );
    for k in 0..400 {
        let t = f64::from(k) * 0.5;
        let (x, y) = match k / 100 {
            0 => (f64::from(k), 0.0),
            1 => (100.0, -f64::from(k - 100)),
            2 => (100.0 - f64::from(k - 200), -100.0),
            _ => (0.0, -100.0 + f64::from(k - 300)),
        };
        s.push_str(&format!(
            "{t:.5} NAV_X uSimMarine {x:.5}\n{t:.5} NAV_Y uSimMarine {y:.5}\n"
        ));
        let z = if dive { 2.0 + 6.0 * (t / 200.0) } else { 0.0 };
        s.push_str(&format!("{t:.5} NAV_DEPTH uSimMarine {z:.5}\n"));
    }
    s.push_str("10.0 VIEW_SEGLIST pHelmIvP pts={0,0:100,0:100,-100:0,-100},label=survey,edge_color=white\n");
    s.push_str("10.0 VIEW_POLYGON pHelmIvP pts={40,-40:60,-40:60,-60:40,-60},label=loiter\n");
    s.push_str("10.0 VIEW_POINT pHelmIvP x=100,y=0,label=next\n");
    s
}

fn data(dive: bool) -> PlotData {
    PlotData::from_alog(&alog::parse(&synthetic(dive)).unwrap())
}

#[test]
fn svg_is_well_formed_with_track_overlays_and_depth_panel() {
    let d = data(true);
    let svg = to_svg(
        &d,
        &PlotOptions {
            width: 800,
            title: "Dive & Survey".into(),
        },
    )
    .unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("valid XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "svg");
    let (w, h) = image_size(
        &d,
        &PlotOptions {
            width: 800,
            title: String::new(),
        },
    );
    assert_eq!(root.attribute("width"), Some("800"));
    assert_eq!(root.attribute("height"), Some(h.to_string().as_str()));
    assert_eq!(w, 800);
    // Track and depth trace (400 points each), the survey seglist (4), the loiter polygon
    // closed (5): polylines.
    let mut lines: Vec<usize> = root
        .descendants()
        .filter(|n| n.has_tag_name("polyline"))
        .map(|n| n.attribute("points").unwrap().split_whitespace().count())
        .filter(|&n| n > 2)
        .collect();
    lines.sort_unstable();
    assert_eq!(lines, [4, 5, 400, 400], "{lines:?}");
    let texts: Vec<String> = root
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .map(|t| t.trim().to_string())
        .collect();
    // Axis labels whole, the title in its own case, and a legend of what is drawn.
    for label in [
        "x (m)",
        "y (m)",
        "time (s)",
        "depth (m)",
        "Dive & Survey",
        "track",
        "start",
        "end",
        "waypoints",
        "marked points",
        "polygons",
    ] {
        assert!(
            texts.iter().any(|t| t == label),
            "missing {label}: {texts:?}"
        );
    }
    // Every coordinate lies inside the image.
    for n in root.descendants().filter(|n| n.has_tag_name("polyline")) {
        for p in n.attribute("points").unwrap().split_whitespace() {
            let (x, y) = p.split_once(',').unwrap();
            let (x, y): (f64, f64) = (x.parse().unwrap(), y.parse().unwrap());
            assert!(
                (0.0..=f64::from(w)).contains(&x) && (0.0..=f64::from(h)).contains(&y),
                "{p}"
            );
        }
    }
}

#[test]
fn surface_track_has_no_depth_panel() {
    let d = data(false);
    let opts = PlotOptions::default();
    let (w, h) = image_size(&d, &opts);
    assert!(h < image_size(&data(true), &opts).1);
    assert_eq!(w, opts.width);
    let svg = to_svg(&d, &opts).unwrap();
    assert!(!svg.contains("depth (m)"));
}

#[test]
fn png_decodes_to_the_plot_size_with_the_track_drawn() {
    let d = data(true);
    let opts = PlotOptions {
        width: 600,
        title: "dive".into(),
    };
    let bytes = to_png(&d, &opts).unwrap();
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
    let mut reader = decoder.read_info().expect("PNG header");
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).expect("PNG data");
    assert_eq!((info.width, info.height), image_size(&d, &opts));
    assert_eq!(info.color_type, png::ColorType::Rgba);
    let px = &buf[..info.buffer_size()];
    let pixels: Vec<&[u8]> = px.chunks(4).collect();
    let white = pixels.iter().filter(|p| p[..3] == [255, 255, 255]).count();
    assert!(white > pixels.len() / 2, "mostly background");
    // The track colour (31,119,180) appears on many pixels.
    let track = pixels
        .iter()
        .filter(|p| {
            (i32::from(p[0]) - 31).abs() < 8
                && (i32::from(p[1]) - 119).abs() < 8
                && (i32::from(p[2]) - 180).abs() < 8
        })
        .count();
    assert!(track > 500, "track pixels: {track}");
    // Labels are drawn in black.
    assert!(pixels.iter().filter(|p| p[..3] == [0, 0, 0]).count() > 200);
}

#[test]
fn a_log_without_a_track_is_an_error() {
    let d = PlotData::from_alog(&alog::parse("%% LOGSTART 0\n1.0 DEPLOY x true\n").unwrap());
    assert_eq!(to_svg(&d, &PlotOptions::default()), Err(PlotError::NoTrack));
    assert_eq!(to_png(&d, &PlotOptions::default()), Err(PlotError::NoTrack));
}

/// The `<text>` elements of an SVG, trimmed, with their `x` and font size.
fn texts(svg: &str) -> Vec<(String, f64, f64)> {
    let doc = roxmltree::Document::parse(svg).expect("valid XML");
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| {
            let x = n.attribute("x")?.parse().ok()?;
            let size = n.attribute("font-size")?.parse().ok()?;
            Some((n.text()?.trim().to_string(), x, size))
        })
        .collect()
}

/// The points of the SVG's polylines of more than two points (not a legend's sample
/// stroke) drawn in `stroke` (e.g. `"#1F77B4"`).
fn polyline_points(svg: &str, stroke: &str) -> Vec<(f64, f64)> {
    let doc = roxmltree::Document::parse(svg).expect("valid XML");
    doc.descendants()
        .filter(|n| n.has_tag_name("polyline") && n.attribute("stroke") == Some(stroke))
        .filter(|n| n.attribute("points").unwrap().split_whitespace().count() > 2)
        .flat_map(|n| {
            n.attribute("points")
                .unwrap()
                .split_whitespace()
                .map(|p| {
                    let (x, y) = p.split_once(',').unwrap();
                    (x.parse().unwrap(), y.parse().unwrap())
                })
                .collect::<Vec<(f64, f64)>>()
        })
        .collect()
}

const TRACK_STROKE: &str = "#1F77B4";
const DEPTH_STROKE: &str = "#9467BD";

fn svg_of(text: &str, title: &str) -> String {
    let d = PlotData::from_alog(&alog::parse(text).unwrap());
    to_svg(
        &d,
        &PlotOptions {
            width: 800,
            title: title.into(),
        },
    )
    .unwrap()
}

#[test]
fn the_legend_lists_only_what_is_drawn() {
    // A bare track: no waypoints, marked points or polygons in the legend.
    let mut log = String::from("%% LOGSTART 0\n");
    for k in 0..50 {
        log.push_str(&format!("{k}.0 NAV_X s {k}\n{k}.0 NAV_Y s {}\n", k / 2));
    }
    let svg = svg_of(&log, "Bare Track");
    let t: Vec<String> = texts(&svg).into_iter().map(|t| t.0).collect();
    for present in ["Bare Track", "track", "start", "end", "x (m)", "y (m)"] {
        assert!(t.iter().any(|x| x == present), "missing {present}: {t:?}");
    }
    for absent in [
        "waypoints",
        "marked points",
        "polygons",
        "depth (m)",
        "time (s)",
    ] {
        assert!(!t.iter().any(|x| x == absent), "unexpected {absent}: {t:?}");
    }
}

#[test]
fn the_legend_box_hides_none_of_the_track() {
    // The synthetic square track fills the panel's corners: the legend gets its own band.
    let svg = svg_of(&synthetic(true), "dive");
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let legend = doc
        .descendants()
        .find(|n| {
            n.has_tag_name("rect")
                && n.attribute("stroke") == Some("#000000")
                && n.attribute("fill") == Some("none")
        })
        .expect("a legend box");
    let f = |a: &str| legend.attribute(a).unwrap().parse::<f64>().unwrap();
    let (x, y, w, h) = (f("x"), f("y"), f("width"), f("height"));
    let track = polyline_points(&svg, TRACK_STROKE);
    assert!(track.len() >= 400, "{}", track.len());
    for &(px, py) in &track {
        assert!(
            !(x..=x + w).contains(&px) || !(y..=y + h).contains(&py),
            "track point {px},{py} under the legend {x},{y} {w}x{h}"
        );
    }
}

#[test]
fn tick_labels_are_plain_numbers() {
    // "40", not "40.0"; and no "-0".
    let svg = svg_of(&synthetic(false), "survey");
    let t: Vec<String> = texts(&svg).into_iter().map(|t| t.0).collect();
    assert!(t.iter().any(|x| x == "0"), "{t:?}");
    assert!(t.iter().any(|x| x == "-100"), "{t:?}");
    assert!(!t.iter().any(|x| x.ends_with(".0") || x == "-0"), "{t:?}");
}

#[test]
fn long_tick_labels_leave_the_y_axis_name_whole() {
    // Coordinates in the tens of kilometres (a local grid far from its origin): the tick
    // labels are wider than usual and must not run into the rotated "y (m)".
    let mut log = String::from("%% LOGSTART 0\n");
    for k in 0..100 {
        let (x, y) = (
            -23_456.5 + f64::from(k) * 3.0,
            -54_321.25 - f64::from(k) * 2.0,
        );
        log.push_str(&format!(
            "{k}.0 NAV_X s {x}\n{k}.0 NAV_Y s {y}\n{k}.0 NAV_DEPTH s 120.5\n"
        ));
    }
    let svg = svg_of(&log, "far");
    let t = texts(&svg);
    let (_, name_x, name_size) = t.iter().find(|t| t.0 == "y (m)").expect("y (m)").clone();
    assert!(name_x >= 0.0);
    // The rotated name takes x in [name_x - size/2, name_x + size]; each y tick label
    // (right-aligned left of the plot) must start to the right of it. DejaVu Sans digits
    // are 0.636 em wide, '-' 0.338 em, '.' 0.32 em.
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let mut checked = 0;
    for n in doc
        .descendants()
        .filter(|n| n.has_tag_name("text") && n.attribute("text-anchor") == Some("end"))
    {
        let label = n.text().unwrap().trim();
        let x: f64 = n.attribute("x").unwrap().parse().unwrap();
        let size: f64 = n.attribute("font-size").unwrap().parse().unwrap();
        let width: f64 = label
            .chars()
            .map(|c| match c {
                '-' => 0.338,
                '.' => 0.32,
                _ => 0.636,
            })
            .sum::<f64>()
            * size;
        assert!(
            x - width > name_x + name_size,
            "tick {label:?} (from {}) runs into the y axis name (to {})",
            x - width,
            name_x + name_size
        );
        checked += 1;
    }
    assert!(checked >= 8, "{checked} y tick labels");
}

#[test]
fn surface_noise_draws_no_depth_panel() {
    // A surface vehicle whose depth sensor reads a few centimetres.
    let mut log = String::from("%% LOGSTART 0\n");
    for k in 0..50 {
        let z = if k % 2 == 0 { 0.04 } else { 0.0 };
        log.push_str(&format!(
            "{k}.0 NAV_X s {k}\n{k}.0 NAV_Y s 0\n{k}.0 NAV_DEPTH s {z}\n"
        ));
    }
    let svg = svg_of(&log, "surface");
    assert!(!svg.contains("depth (m)"));
    assert!(polyline_points(&svg, DEPTH_STROKE).is_empty());
}

#[test]
fn the_depth_panel_time_axis_covers_the_whole_run() {
    // The track runs 0..199.5 s; depth is logged only from 100 s on: its trace starts
    // half way along the time axis, not at its left end.
    let mut log = String::from("%% LOGSTART 0\n");
    for k in 0..400 {
        let t = f64::from(k) * 0.5;
        log.push_str(&format!("{t} NAV_X s {k}\n{t} NAV_Y s 0\n"));
        if t >= 100.0 {
            log.push_str(&format!("{t} NAV_DEPTH s 3\n"));
        }
    }
    let svg = svg_of(&log, "late depth");
    assert!(svg.contains("depth (m)") && svg.contains("time (s)"));
    let depth = polyline_points(&svg, DEPTH_STROKE);
    assert!(!depth.is_empty());
    let (lo, hi) = depth.iter().fold((f64::INFINITY, 0.0_f64), |(a, b), p| {
        (a.min(p.0), b.max(p.0))
    });
    // The plot spans about 85..790 px of the 800; half way is about 435.
    assert!(lo > 380.0 && lo < 480.0, "depth trace starts at x={lo}");
    assert!(hi > 760.0, "depth trace ends at x={hi}");
}

#[test]
fn png_text_keeps_its_case() {
    // Lower-case letters are their own glyphs: "survey" and "SURVEY" draw differently
    // (and both differ from no title).
    let d = data(false);
    let png_of = |title: &str| {
        let bytes = to_png(
            &d,
            &PlotOptions {
                width: 400,
                title: title.into(),
            },
        )
        .unwrap();
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
            .read_info()
            .unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        buf.truncate(info.buffer_size());
        buf
    };
    let (lower, upper, none) = (png_of("survey"), png_of("SURVEY"), png_of(""));
    assert!(
        lower != upper,
        "\"survey\" drew the same pixels as \"SURVEY\""
    );
    assert!(lower != none, "the title drew nothing");
}
