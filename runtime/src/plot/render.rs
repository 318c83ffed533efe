//! Drawing a [`PlotData`] with `plotters`: SVG text or PNG bytes.

use std::sync::OnceLock;

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::{PlotData, PlotError, PlotOptions, image_size};

const TRACK: RGBColor = RGBColor(31, 119, 180);
const SEGLIST: RGBColor = RGBColor(255, 127, 14);
const POLYGON: RGBColor = RGBColor(44, 160, 44);
const POINT: RGBColor = RGBColor(214, 39, 40);
const DEPTH: RGBColor = RGBColor(148, 103, 189);
const START: RGBColor = RGBColor(0, 150, 0);
const TRUTH: RGBColor = RGBColor(0, 0, 0);
const DEAD_RECKONING: RGBColor = RGBColor(150, 150, 150);
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

/// How many tick labels an axis asks plotters for (its default).
const TICKS: usize = 11;
/// The depth axis's (a shorter panel).
const DEPTH_TICKS: usize = 6;

/// Decimals for the tick labels of an axis over `range` with at most `n` labels: the
/// fewest that write every tick plotters puts there exactly ("40", not "40.0"; "2.5"
/// where ticks are half metres), the same for every label of the axis.
fn decimals(range: (f64, f64), n: usize) -> usize {
    let ticks = RangedCoordf64::from(range.0..range.1).key_points(n);
    let exact = |v: f64, d: usize| {
        let s = format!("{v:.d$}");
        s.parse::<f64>()
            .is_ok_and(|p| (p - v).abs() <= 1e-9 * v.abs().max(1.0))
    };
    (0..=6)
        .find(|&d| ticks.iter().all(|&v| exact(v, d)))
        .unwrap_or(6)
}

/// A tick label with `dec` decimals (no "-0").
fn tick(v: f64, dec: usize) -> String {
    let s = format!("{v:.dec$}");
    if s.starts_with('-') && s[1..].bytes().all(|b| b == b'0' || b == b'.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// Where the legend goes: the corner of the track panel with the fewest drawn points
/// (upper right when tied), and how many points that corner holds. `(fx, fy)` is the
/// legend box's share of the panel's width and height.
fn legend_corner(
    pts: &[(f64, f64)],
    x: (f64, f64),
    y: (f64, f64),
    (fx, fy): (f64, f64),
) -> (SeriesLabelPosition, usize) {
    let xl = x.0 + (x.1 - x.0) * fx;
    let xr = x.1 - (x.1 - x.0) * fx;
    let yb = y.0 + (y.1 - y.0) * fy;
    let yt = y.1 - (y.1 - y.0) * fy;
    let corners = [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ];
    let count = |right: bool, upper: bool| {
        pts.iter()
            .filter(|&&(px, py)| {
                (if right { px >= xr } else { px <= xl })
                    && (if upper { py >= yt } else { py <= yb })
            })
            .count()
    };
    corners
        .into_iter()
        .map(|(pos, r, u)| (pos, count(r, u)))
        .min_by_key(|c| c.1)
        .unwrap_or((SeriesLabelPosition::UpperRight, 0))
}

/// The points of a polyline, with extra points along each segment at most `step` apart
/// (for finding where the drawing is, not for drawing).
fn densify(pts: &[(f64, f64)], step: f64, out: &mut Vec<(f64, f64)>) {
    out.extend(pts.first());
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        let n = ((b.0 - a.0).hypot(b.1 - a.1) / step)
            .ceil()
            .clamp(1.0, 1000.0) as usize;
        out.extend((1..=n).map(|k| {
            let f = k as f64 / n as f64;
            (a.0 + (b.0 - a.0) * f, a.1 + (b.1 - a.1) * f)
        }));
    }
}

/// The track's legend: `track`, or `estimate (NAV_*)` when the truth is drawn beside it.
fn track_label(data: &PlotData) -> &'static str {
    if data.truth.is_empty() {
        "track"
    } else {
        "estimate (NAV_*)"
    }
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    data: &PlotData,
    opts: &PlotOptions,
) -> Result<(), PlotError> {
    root.fill(&WHITE).map_err(err)?;
    let (w, h) = root.dim_in_pixel();
    let dived = data.dived();
    let (top, bottom) = if dived {
        root.split_vertically(h - super::DEPTH_PANEL_H)
    } else {
        root.split_vertically(h)
    };
    // Equal aspect: both axes get the larger span (the panel is square).
    let track: Vec<(f64, f64)> = thin(&data.track, MAX_POINTS)
        .iter()
        .map(|p| (p.1, p.2))
        .collect();
    let xy = |v: &[(f64, f64, f64)]| -> Vec<(f64, f64)> {
        thin(v, MAX_POINTS).iter().map(|p| (p.1, p.2)).collect()
    };
    let truth = xy(&data.truth);
    let dr = xy(&data.dead_reckoning);
    let all: Vec<(f64, f64)> = track
        .iter()
        .chain(&truth)
        .chain(&dr)
        .chain(
            data.points
                .iter()
                .chain(&data.seglists)
                .chain(&data.polygons)
                .flat_map(|s| &s.points),
        )
        .copied()
        .collect();
    let (x0, x1) = span(all.iter().map(|p| p.0), 10.0);
    let (y0, y1) = span(all.iter().map(|p| p.1), 10.0);
    let side = (x1 - x0).max(y1 - y0) * 1.08;
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let mut xr = ((cx - side / 2.0), (cx + side / 2.0));
    let mut yr = ((cy - side / 2.0), (cy + side / 2.0));

    let label_font: TextStyle = (FONT, 14).into();
    let desc_font: TextStyle = (FONT, 16).into();
    let (_, desc_h) = root.estimate_text_size("y (m)", &desc_font).map_err(err)?;
    // The y label area fits the widest tick label and the rotated axis name, the same for
    // both panels so that their plot areas line up.
    let (t0, t1) = data.time_span();
    let (_, dmax) = span(data.depth.iter().map(|p| p.1).chain([0.0]), 1.0);
    let dmax = dmax * 1.05;
    let d_dec = decimals((0.0, dmax), DEPTH_TICKS);
    let y_area = |xr: (f64, f64), yr: (f64, f64)| -> Result<u32, PlotError> {
        let dec = decimals(xr, TICKS).max(decimals(yr, TICKS));
        let mut labels = vec![tick(yr.0, dec), tick(yr.1, dec)];
        if dived {
            labels.push(tick(dmax, d_dec));
        }
        let mut widest = 0;
        for l in &labels {
            let (tw, _) = root.estimate_text_size(l, &label_font).map_err(err)?;
            widest = widest.max(tw);
        }
        Ok(widest + desc_h + 24)
    };

    // The legend, in reading order, with an entry only for what is drawn; it goes in the
    // emptiest corner, and when no corner is empty the panel grows a band at the top for it.
    let entries: Vec<&str> = [
        (true, track_label(data)),
        (!truth.is_empty(), "truth (SIM_*)"),
        (!dr.is_empty(), "dead reckoning (DR_*)"),
        (true, "start"),
        (true, "end"),
        (!data.seglists.is_empty(), "waypoints"),
        (!data.points.is_empty(), "marked points"),
        (!data.polygons.is_empty(), "polygons"),
    ]
    .into_iter()
    .filter_map(|(on, l)| on.then_some(l))
    .collect();
    let title_size = (f64::from(w) / 40.0).clamp(14.0, 28.0);
    let share = {
        let (mut lw, mut lh) = (0, 0);
        for l in &entries {
            let (tw, th) = root.estimate_text_size(l, &label_font).map_err(err)?;
            (lw, lh) = (lw.max(tw), lh.max(th));
        }
        let (tw, th) = top.dim_in_pixel();
        let pw = f64::from(tw) - 24.0 - f64::from(y_area(xr, yr)?);
        let ph = f64::from(th)
            - 24.0
            - 45.0
            - if opts.title.is_empty() {
                0.0
            } else {
                title_size * 1.5
            };
        let box_w = f64::from(lw + 55);
        let box_h = f64::from((lh + 6) * entries.len() as u32 + 25);
        (
            (box_w / pw.max(1.0)).min(0.6),
            (box_h / ph.max(1.0)).min(0.6),
        )
    };
    let mut occupied = Vec::new();
    let step = side / 200.0;
    densify(&track, step, &mut occupied);
    densify(&truth, step, &mut occupied);
    densify(&dr, step, &mut occupied);
    for s in data.seglists.iter().chain(&data.points) {
        densify(&s.points, step, &mut occupied);
    }
    for p in &data.polygons {
        let mut closed = p.points.clone();
        closed.extend(p.points.first());
        densify(&closed, step, &mut occupied);
    }
    let (mut legend_pos, crowded) = legend_corner(&occupied, xr, yr, share);
    if crowded > 0 {
        // A band above everything, as tall as the legend (the x range grows as much, to
        // keep metres square).
        let grow = side * share.1 / (1.0 - share.1);
        yr.1 += grow;
        xr = (xr.0 - grow / 2.0, xr.1 + grow / 2.0);
        legend_pos = SeriesLabelPosition::UpperRight;
    }
    let xy_dec = decimals(xr, TICKS).max(decimals(yr, TICKS));
    let t_dec = decimals((t0, t1), TICKS);
    let y_area = y_area(xr, yr)?;

    let mut chart = ChartBuilder::on(&top)
        .caption(&opts.title, (FONT, title_size))
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(y_area)
        .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)
        .map_err(err)?;
    let xy_fmt = |v: &f64| tick(*v, xy_dec);
    chart
        .configure_mesh()
        .x_desc("x (m)")
        .y_desc("y (m)")
        .x_labels(TICKS)
        .y_labels(TICKS)
        .x_label_formatter(&xy_fmt)
        .y_label_formatter(&xy_fmt)
        .label_style(label_font.clone())
        .axis_desc_style(desc_font.clone())
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(err)?;
    for p in &data.polygons {
        let mut pts = p.points.clone();
        if let Some(&first) = pts.first() {
            pts.push(first);
        }
        chart
            .draw_series(LineSeries::new(pts, POLYGON.stroke_width(2)))
            .map_err(err)?;
    }
    for p in &data.seglists {
        chart
            .draw_series(LineSeries::new(p.points.clone(), SEGLIST.stroke_width(1)).point_size(3))
            .map_err(err)?;
    }
    for p in &data.points {
        chart
            .draw_series(p.points.iter().map(|&q| Circle::new(q, 4, POINT.filled())))
            .map_err(err)?;
    }
    if !dr.is_empty() {
        chart
            .draw_series(LineSeries::new(dr.clone(), DEAD_RECKONING.stroke_width(1)))
            .map_err(err)?;
    }
    if !truth.is_empty() {
        chart
            .draw_series(LineSeries::new(truth.clone(), TRUTH.stroke_width(1)))
            .map_err(err)?;
    }
    chart
        .draw_series(LineSeries::new(track.clone(), TRACK.stroke_width(2)))
        .map_err(err)?;
    let (first, last) = (track[0], track[track.len() - 1]);
    chart
        .draw_series(std::iter::once(Circle::new(first, 6, START.filled())))
        .map_err(err)?;
    chart
        .draw_series(std::iter::once(TriangleMarker::new(
            last,
            8,
            BLACK.filled(),
        )))
        .map_err(err)?;

    // Legend entries are attached to empty series so that the drawing order above stays
    // free.
    let none = std::iter::empty::<EmptyElement<(f64, f64), DB>>;
    chart
        .draw_series(none())
        .map_err(err)?
        .label(track_label(data))
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], TRACK.stroke_width(2)));
    if !truth.is_empty() {
        chart
            .draw_series(none())
            .map_err(err)?
            .label("truth (SIM_*)")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], TRUTH.stroke_width(1)));
    }
    if !dr.is_empty() {
        chart
            .draw_series(none())
            .map_err(err)?
            .label("dead reckoning (DR_*)")
            .legend(|(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], DEAD_RECKONING.stroke_width(1))
            });
    }
    chart
        .draw_series(none())
        .map_err(err)?
        .label("start")
        .legend(|(x, y)| Circle::new((x + 10, y), 5, START.filled()));
    chart
        .draw_series(none())
        .map_err(err)?
        .label("end")
        .legend(|(x, y)| TriangleMarker::new((x + 10, y), 6, BLACK.filled()));
    if !data.seglists.is_empty() {
        chart
            .draw_series(none())
            .map_err(err)?
            .label("waypoints")
            .legend(|(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (20, 0)], SEGLIST.stroke_width(1))
                    + Circle::new((10, 0), 3, SEGLIST.stroke_width(1))
            });
    }
    if !data.points.is_empty() {
        chart
            .draw_series(none())
            .map_err(err)?
            .label("marked points")
            .legend(|(x, y)| Circle::new((x + 10, y), 4, POINT.filled()));
    }
    if !data.polygons.is_empty() {
        chart
            .draw_series(none())
            .map_err(err)?
            .label("polygons")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], POLYGON.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .position(legend_pos)
        .label_font(label_font.clone())
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;

    if dived {
        // The run's time span, depth growing downward.
        let mut depth = ChartBuilder::on(&bottom)
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(y_area)
            .build_cartesian_2d(t0..t1, dmax..0.0)
            .map_err(err)?;
        let t_fmt = |v: &f64| tick(*v, t_dec);
        let d_fmt = |v: &f64| tick(*v, d_dec);
        depth
            .configure_mesh()
            .x_desc("time (s)")
            .y_desc("depth (m)")
            .x_label_formatter(&t_fmt)
            .y_label_formatter(&d_fmt)
            .x_labels(TICKS)
            .y_labels(DEPTH_TICKS)
            .label_style(label_font)
            .axis_desc_style(desc_font)
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
