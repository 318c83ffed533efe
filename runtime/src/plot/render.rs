//! Drawing a [`PlotData`] with `plotters`: SVG text or PNG bytes.

use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{PlotData, PlotError, PlotOptions, image_size};

const TRACK: RGBColor = RGBColor(31, 119, 180);
const SEGLIST: RGBColor = RGBColor(255, 127, 14);
const POLYGON: RGBColor = RGBColor(44, 160, 44);
const POINT: RGBColor = RGBColor(214, 39, 40);
const DEPTH: RGBColor = RGBColor(148, 103, 189);
const START: RGBColor = RGBColor(0, 150, 0);
/// The most points a line is drawn with (a long log is thinned evenly, ends kept).
const MAX_POINTS: usize = 4000;
/// The one font: DejaVu Sans, built into the binary.
const FONT: &str = "sans-serif";

/// Registers the built-in font with plotters once.
fn font() -> Result<(), PlotError> {
    static DONE: OnceLock<bool> = OnceLock::new();
    let ok = *DONE.get_or_init(|| {
        plotters::style::register_font(FONT, FontStyle::Normal, dejavu::sans::regular()).is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(PlotError::Encode("the built-in font cannot be read".into()))
    }
}

/// The plot as an SVG document.
pub fn to_svg(data: &PlotData, opts: &PlotOptions) -> Result<String, PlotError> {
    if data.track.is_empty() {
        return Err(PlotError::NoTrack);
    }
    font()?;
    let size = image_size(data, opts);
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, size).into_drawing_area();
        draw(&root, data, opts)?;
        root.present().map_err(err)?;
    }
    Ok(out)
}

/// The plot as PNG bytes (RGBA).
pub fn to_png(data: &PlotData, opts: &PlotOptions) -> Result<Vec<u8>, PlotError> {
    if data.track.is_empty() {
        return Err(PlotError::NoTrack);
    }
    font()?;
    let (w, h) = image_size(data, opts);
    if w < 200 || h < 200 || w > 8000 || h > 10_000 {
        return Err(PlotError::Size(w, h));
    }
    let mut rgb = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        draw(&root, data, opts)?;
        root.present().map_err(err)?;
    }
    let mut rgba = Vec::with_capacity(rgb.len() / 3 * 4);
    for p in rgb.chunks_exact(3) {
        rgba.extend_from_slice(&[p[0], p[1], p[2], 255]);
    }
    let mut bytes = Vec::new();
    let mut enc = png::Encoder::new(&mut bytes, w, h);
    enc.set_color(png::ColorType::Rgba);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc
        .write_header()
        .map_err(|e| PlotError::Encode(e.to_string()))?;
    writer
        .write_image_data(&rgba)
        .map_err(|e| PlotError::Encode(e.to_string()))?;
    writer
        .finish()
        .map_err(|e| PlotError::Encode(e.to_string()))?;
    Ok(bytes)
}

fn err<E: std::fmt::Display>(e: E) -> PlotError {
    PlotError::Encode(e.to_string())
}

/// Thins `pts` to at most `max` points, keeping the first and the last.
fn thin<T: Copy>(pts: &[T], max: usize) -> Vec<T> {
    if pts.len() <= max || max < 2 {
        return pts.to_vec();
    }
    let stride = pts.len().div_ceil(max - 1);
    let mut v: Vec<T> = pts.iter().step_by(stride).copied().collect();
    if let Some(last) = pts.last() {
        v.push(*last);
    }
    v
}

/// The smallest and largest of `v`, widened to at least `min_span`.
fn span(v: impl Iterator<Item = f64>, min_span: f64) -> (f64, f64) {
    let (mut lo, mut hi) = v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    if !lo.is_finite() {
        (lo, hi) = (0.0, 0.0);
    }
    if hi - lo < min_span {
        let mid = (lo + hi) / 2.0;
        (lo, hi) = (mid - min_span / 2.0, mid + min_span / 2.0);
    }
    (lo, hi)
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    data: &PlotData,
    opts: &PlotOptions,
) -> Result<(), PlotError> {
    root.fill(&WHITE).map_err(err)?;
    let (w, h) = root.dim_in_pixel();
    let (top, bottom) = if data.dived() {
        root.split_vertically(h - super::DEPTH_PANEL_H)
    } else {
        root.split_vertically(h)
    };
    // Equal aspect: both axes get the larger span (the panel is square).
    let xs = data.track.iter().map(|p| p.1);
    let ys = data.track.iter().map(|p| p.2);
    let shapes = data
        .points
        .iter()
        .chain(&data.seglists)
        .chain(&data.polygons);
    let (sx, sy): (Vec<f64>, Vec<f64>) = shapes.flat_map(|s| s.points.iter().copied()).unzip();
    let (x0, x1) = span(xs.chain(sx), 10.0);
    let (y0, y1) = span(ys.chain(sy), 10.0);
    let side = (x1 - x0).max(y1 - y0) * 1.08;
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let title_size = (f64::from(w) / 40.0).clamp(14.0, 28.0);
    let mut chart = ChartBuilder::on(&top)
        .caption(&opts.title, (FONT, title_size))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(65)
        .build_cartesian_2d(
            (cx - side / 2.0)..(cx + side / 2.0),
            (cy - side / 2.0)..(cy + side / 2.0),
        )
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("x (m)")
        .y_desc("y (m)")
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(err)?;
    for (i, p) in data.polygons.iter().enumerate() {
        let mut pts = p.points.clone();
        if let Some(&first) = pts.first() {
            pts.push(first);
        }
        let s = chart
            .draw_series(LineSeries::new(pts, POLYGON.stroke_width(2)))
            .map_err(err)?;
        if i == 0 {
            s.label("polygons").legend(|(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], POLYGON.stroke_width(2))
            });
        }
    }
    let mut waypoints_labelled = false;
    for p in &data.seglists {
        let s = chart
            .draw_series(LineSeries::new(p.points.clone(), SEGLIST.stroke_width(1)).point_size(3))
            .map_err(err)?;
        if !waypoints_labelled {
            waypoints_labelled = true;
            s.label("waypoints")
                .legend(|(x, y)| Circle::new((x + 10, y), 3, SEGLIST.filled()));
        }
    }
    for p in &data.points {
        let s = chart
            .draw_series(p.points.iter().map(|&q| Circle::new(q, 4, POINT.filled())))
            .map_err(err)?;
        if !waypoints_labelled {
            waypoints_labelled = true;
            s.label("waypoints")
                .legend(|(x, y)| Circle::new((x + 10, y), 4, POINT.filled()));
        }
    }
    let track: Vec<(f64, f64)> = thin(&data.track, MAX_POINTS)
        .iter()
        .map(|p| (p.1, p.2))
        .collect();
    chart
        .draw_series(LineSeries::new(track.clone(), TRACK.stroke_width(2)))
        .map_err(err)?
        .label("track")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], TRACK.stroke_width(2)));
    if let (Some(&first), Some(&last)) = (track.first(), track.last()) {
        chart
            .draw_series(std::iter::once(Circle::new(first, 6, START.filled())))
            .map_err(err)?
            .label("start")
            .legend(|(x, y)| Circle::new((x + 10, y), 5, START.filled()));
        chart
            .draw_series(std::iter::once(TriangleMarker::new(
                last,
                8,
                BLACK.filled(),
            )))
            .map_err(err)?
            .label("end")
            .legend(|(x, y)| TriangleMarker::new((x + 10, y), 6, BLACK.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font((FONT, 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    if data.dived() {
        // The run's time span (the track's), depth growing downward.
        let (t0, t1) = span(
            data.track
                .iter()
                .map(|p| p.0)
                .chain(data.depth.iter().map(|p| p.0)),
            1.0,
        );
        let (_, dmax) = span(data.depth.iter().map(|p| p.1).chain([0.0]), 1.0);
        let mut depth = ChartBuilder::on(&bottom)
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(65)
            .build_cartesian_2d(t0..t1, (dmax * 1.05)..0.0)
            .map_err(err)?;
        depth
            .configure_mesh()
            .x_desc("time (s)")
            .y_desc("depth (m)")
            .label_style((FONT, 14))
            .axis_desc_style((FONT, 16))
            .light_line_style(RGBColor(235, 235, 235))
            .draw()
            .map_err(err)?;
        depth
            .draw_series(LineSeries::new(
                thin(&data.depth, MAX_POINTS),
                DEPTH.stroke_width(2),
            ))
            .map_err(err)?;
    }
    Ok(())
}
