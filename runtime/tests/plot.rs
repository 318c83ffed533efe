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
