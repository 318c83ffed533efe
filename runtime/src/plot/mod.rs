//! `coug plot`: the vehicle track of an alog, with the waypoints, seglists and polygons the
//! behaviours posted (`VIEW_POINT`, `VIEW_SEGLIST`, `VIEW_POLYGON`), equal-aspect axes in
//! metres, and a depth-versus-time panel when the vehicle dived. Output as SVG text or PNG
//! bytes (drawn with tiny-skia and a built-in bitmap font, so no font files are needed).
//!
//! ```
//! let log = alog::parse("%% LOGSTART 0\n0 NAV_X s 0\n0 NAV_Y s 0\n1 NAV_X s 10\n1 NAV_Y s 5\n").unwrap();
//! let data = runtime::plot::PlotData::from_alog(&log);
//! assert_eq!(data.track.len(), 3); // a point each time x or y changes
//! let svg = runtime::plot::to_svg(&data, &runtime::plot::PlotOptions::default()).unwrap();
//! assert!(svg.starts_with("<svg"));
//! ```

mod font;
mod png;
mod svg;

use std::collections::BTreeMap;

use alog::{Alog, EntryValue};
use thiserror::Error;

pub use png::to_png;
pub use svg::to_svg;

/// Why a plot cannot be drawn.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum PlotError {
    /// The log has no NAV_X/NAV_Y pair.
    #[error("the log has no vehicle track (no NAV_X and NAV_Y records)")]
    NoTrack,
    /// The image is too large or too small to draw.
    #[error("cannot draw a {0}x{1} image")]
    Size(u32, u32),
    /// PNG encoding failed.
    #[error("PNG encoding failed: {0}")]
    Encode(String),
}

/// A labelled overlay shape in local metres.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    /// The label the behaviour gave it.
    pub label: String,
    /// Vertices (one for a point).
    pub points: Vec<(f64, f64)>,
}

/// What a plot shows, gathered from an alog.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PlotData {
    /// `(time, x, y)` each time NAV_X or NAV_Y changed (once both are known).
    pub track: Vec<(f64, f64, f64)>,
    /// `(time, depth)` of every NAV_DEPTH record.
    pub depth: Vec<(f64, f64)>,
    /// VIEW_POINTs: the last active version of each label.
    pub points: Vec<Shape>,
    /// VIEW_SEGLISTs: the last active version of each label.
    pub seglists: Vec<Shape>,
    /// VIEW_POLYGONs: the last active version of each label.
    pub polygons: Vec<Shape>,
}

fn keep(map: &mut BTreeMap<String, Shape>, active: bool, label: &str, pts: Vec<(f64, f64)>) {
    // Erasures (active=false) are ignored: the plot shows every shape that was shown.
    if active && !pts.is_empty() {
        map.insert(
            label.to_string(),
            Shape {
                label: label.to_string(),
                points: pts,
            },
        );
    }
}

impl PlotData {
    /// Collects the track, depth and overlays from a parsed alog. Unreadable `VIEW_*`
    /// values are skipped.
    pub fn from_alog(log: &Alog) -> PlotData {
        let mut d = PlotData::default();
        let (mut x, mut y) = (None, None);
        let mut points = BTreeMap::new();
        let mut segls = BTreeMap::new();
        let mut polys = BTreeMap::new();
        for e in &log.entries {
            match (e.var.as_str(), &e.value) {
                ("NAV_X", EntryValue::Double(v)) | ("NAV_Y", EntryValue::Double(v)) => {
                    if e.var == "NAV_X" {
                        x = Some(*v);
                    } else {
                        y = Some(*v);
                    }
                    if let (Some(x), Some(y)) = (x, y)
                        && d.track.last().is_none_or(|&(_, lx, ly)| lx != x || ly != y)
                    {
                        d.track.push((e.time, x, y));
                    }
                }
                ("NAV_DEPTH", EntryValue::Double(v)) => d.depth.push((e.time, *v)),
                ("VIEW_POINT", EntryValue::String(s)) => {
                    if let Ok(p) = geometry::spec::parse_point(s) {
                        let pts = vec![(p.point.x, p.point.y)];
                        keep(&mut points, p.attrs.active, &p.attrs.label, pts);
                    }
                }
                ("VIEW_SEGLIST", EntryValue::String(s)) => {
                    if let Ok(p) = geometry::spec::parse_seglist(s) {
                        let pts = p.seglist.points().iter().map(|q| (q.x, q.y)).collect();
                        keep(&mut segls, p.attrs.active, &p.attrs.label, pts);
                    }
                }
                ("VIEW_POLYGON", EntryValue::String(s)) => {
                    if let Ok(p) = geometry::spec::parse_polygon(s) {
                        let pts = p.polygon.vertices().iter().map(|q| (q.x, q.y)).collect();
                        keep(&mut polys, p.attrs.active, &p.attrs.label, pts);
                    }
                }
                _ => {}
            }
        }
        d.points = points.into_values().collect();
        d.seglists = segls.into_values().collect();
        d.polygons = polys.into_values().collect();
        d
    }

    /// True when the vehicle went below the surface.
    pub fn dived(&self) -> bool {
        self.depth.iter().any(|&(_, z)| z > 0.0)
    }
}

/// Plot settings.
#[derive(Debug, Clone, PartialEq)]
pub struct PlotOptions {
    /// Image width in pixels (the height follows from the panels).
    pub width: u32,
    /// Title text (empty: none).
    pub title: String,
}

impl Default for PlotOptions {
    fn default() -> Self {
        PlotOptions {
            width: 900,
            title: String::new(),
        }
    }
}

/// An RGB colour with alpha.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Rgba(pub u8, pub u8, pub u8, pub f32);

pub(crate) const BLACK: Rgba = Rgba(0, 0, 0, 1.0);
const GRID: Rgba = Rgba(220, 220, 220, 1.0);
const TRACK: Rgba = Rgba(31, 119, 180, 1.0);
const SEGLIST: Rgba = Rgba(255, 127, 14, 1.0);
const POLYGON: Rgba = Rgba(44, 160, 44, 1.0);
const POLYGON_FILL: Rgba = Rgba(44, 160, 44, 0.12);
const POINT: Rgba = Rgba(214, 39, 40, 1.0);
const DEPTH: Rgba = Rgba(148, 103, 189, 1.0);

/// Where text sits relative to its x.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Anchor {
    Start,
    Middle,
    End,
}

/// The drawing operations both back ends implement (pixel coordinates, y down).
pub(crate) trait Canvas {
    fn polyline(&mut self, pts: &[(f64, f64)], color: Rgba, width: f64);
    fn polygon(&mut self, pts: &[(f64, f64)], stroke: Rgba, fill: Rgba, width: f64);
    fn circle(&mut self, x: f64, y: f64, r: f64, fill: Rgba);
    fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, stroke: Rgba);
    /// `y` is the text baseline; `size` the cap height in pixels.
    fn text(&mut self, x: f64, y: f64, text: &str, size: f64, anchor: Anchor);
}

/// A data-to-pixel mapping of one panel.
#[derive(Debug, Clone, Copy)]
struct Frame {
    px: f64,
    py: f64,
    pw: f64,
    ph: f64,
    x0: f64,
    x1: f64,
    y0: f64,
    y1: f64,
    /// y grows downward in data (depth) when true.
    y_down: bool,
}

impl Frame {
    fn map(&self, x: f64, y: f64) -> (f64, f64) {
        let u = self.px + (x - self.x0) / (self.x1 - self.x0) * self.pw;
        let f = (y - self.y0) / (self.y1 - self.y0);
        let v = if self.y_down {
            self.py + f * self.ph
        } else {
            self.py + self.ph - f * self.ph
        };
        (u, v)
    }
}

/// A "nice" tick step (1, 2 or 5 × 10^k) giving about `n` intervals over `span`.
fn nice_step(span: f64, n: f64) -> f64 {
    let raw = (span / n).max(1e-9);
    let mag = 10f64.powf(raw.log10().floor());
    let f = raw / mag;
    let nice = if f < 1.5 {
        1.0
    } else if f < 3.5 {
        2.0
    } else if f < 7.5 {
        5.0
    } else {
        10.0
    };
    nice * mag
}

fn ticks(lo: f64, hi: f64, n: f64) -> (f64, Vec<f64>) {
    let step = nice_step(hi - lo, n);
    let mut v = Vec::new();
    let mut t = (lo / step).ceil() * step;
    while t <= hi + step * 1e-9 && v.len() < 100 {
        v.push(if t.abs() < step * 1e-9 { 0.0 } else { t });
        t += step;
    }
    (step, v)
}

fn tick_label(v: f64, step: f64) -> String {
    let decimals = if step >= 1.0 {
        0
    } else {
        (-step.log10().floor()) as usize
    };
    format!("{v:.decimals$}")
}

/// Thins `pts` to at most `max` points (keeping the first and last).
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

const MARGIN_L: f64 = 80.0;
const MARGIN_R: f64 = 25.0;
const MARGIN_T: f64 = 40.0;
const AXIS_GAP: f64 = 55.0;
const DEPTH_H: f64 = 200.0;
const MAX_POINTS: usize = 4000;

/// The image size (width, height) in pixels of a plot: the width asked for; the height
/// holds a square track panel and, when the vehicle dived, the depth panel.
pub fn image_size(data: &PlotData, opts: &PlotOptions) -> (u32, u32) {
    let w = f64::from(opts.width);
    let track_h = (w - MARGIN_L - MARGIN_R).max(100.0);
    let mut h = MARGIN_T + track_h + AXIS_GAP;
    if data.dived() {
        h += DEPTH_H + AXIS_GAP;
    }
    (opts.width, h.round() as u32)
}

/// Draws the whole plot on `c`.
pub(crate) fn draw(
    data: &PlotData,
    opts: &PlotOptions,
    c: &mut dyn Canvas,
) -> Result<(), PlotError> {
    if data.track.is_empty() {
        return Err(PlotError::NoTrack);
    }
    let (w, _) = image_size(data, opts);
    let w = f64::from(w);
    let pw = (w - MARGIN_L - MARGIN_R).max(100.0);
    let ph = pw;
    // Data bounds: track and overlays.
    let mut xs: Vec<f64> = data.track.iter().map(|p| p.1).collect();
    let mut ys: Vec<f64> = data.track.iter().map(|p| p.2).collect();
    for s in data
        .points
        .iter()
        .chain(&data.seglists)
        .chain(&data.polygons)
    {
        for &(x, y) in &s.points {
            xs.push(x);
            ys.push(y);
        }
    }
    let (mut x0, mut x1) = min_max(&xs);
    let (mut y0, mut y1) = min_max(&ys);
    // Equal aspect: widen the smaller span, then pad 5 %.
    let span = (x1 - x0).max(y1 - y0).max(10.0) * 1.1;
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    x0 = cx - span / 2.0;
    x1 = cx + span / 2.0;
    y0 = cy - span / 2.0;
    y1 = cy + span / 2.0;
    let f = Frame {
        px: MARGIN_L,
        py: MARGIN_T,
        pw,
        ph,
        x0,
        x1,
        y0,
        y1,
        y_down: false,
    };
    if !opts.title.is_empty() {
        c.text(w / 2.0, MARGIN_T - 14.0, &opts.title, 14.0, Anchor::Middle);
    }
    axes(c, &f, "x (m)", "y (m)");
    for s in &data.polygons {
        let pts: Vec<(f64, f64)> = s.points.iter().map(|&(x, y)| f.map(x, y)).collect();
        c.polygon(&pts, POLYGON, POLYGON_FILL, 1.5);
    }
    for s in &data.seglists {
        let pts: Vec<(f64, f64)> = s.points.iter().map(|&(x, y)| f.map(x, y)).collect();
        c.polyline(&pts, SEGLIST, 1.5);
        for &(u, v) in &pts {
            c.circle(u, v, 3.0, SEGLIST);
        }
    }
    let track: Vec<(f64, f64)> = thin(&data.track, MAX_POINTS)
        .iter()
        .map(|&(_, x, y)| f.map(x, y))
        .collect();
    c.polyline(&track, TRACK, 2.0);
    for s in &data.points {
        let (u, v) = f.map(s.points[0].0, s.points[0].1);
        c.circle(u, v, 4.0, POINT);
    }
    if let (Some(first), Some(last)) = (track.first(), track.last()) {
        c.circle(first.0, first.1, 5.0, BLACK);
        c.circle(last.0, last.1, 5.0, TRACK);
    }
    if data.dived() {
        let (t0, t1) = min_max(&data.depth.iter().map(|p| p.0).collect::<Vec<_>>());
        let (_, zmax) = min_max(&data.depth.iter().map(|p| p.1).collect::<Vec<_>>());
        let g = Frame {
            px: MARGIN_L,
            py: MARGIN_T + ph + AXIS_GAP,
            pw,
            ph: DEPTH_H,
            x0: t0,
            x1: if t1 > t0 { t1 } else { t0 + 1.0 },
            y0: 0.0,
            y1: (zmax * 1.1).max(1.0),
            y_down: true,
        };
        axes(c, &g, "time (s)", "depth (m)");
        let pts: Vec<(f64, f64)> = thin(&data.depth, MAX_POINTS)
            .iter()
            .map(|&(t, z)| g.map(t, z))
            .collect();
        c.polyline(&pts, DEPTH, 1.5);
    }
    Ok(())
}

fn min_max(v: &[f64]) -> (f64, f64) {
    v.iter()
        .filter(|x| x.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        })
}

fn axes(c: &mut dyn Canvas, f: &Frame, xlabel: &str, ylabel: &str) {
    let (xstep, xt) = ticks(f.x0, f.x1, 8.0);
    let (ystep, yt) = ticks(f.y0, f.y1, if f.y_down { 4.0 } else { 8.0 });
    for &x in &xt {
        let (u, _) = f.map(x, f.y0);
        c.polyline(&[(u, f.py), (u, f.py + f.ph)], GRID, 1.0);
        c.text(
            u,
            f.py + f.ph + 16.0,
            &tick_label(x, xstep),
            9.0,
            Anchor::Middle,
        );
    }
    for &y in &yt {
        let (_, v) = f.map(f.x0, y);
        c.polyline(&[(f.px, v), (f.px + f.pw, v)], GRID, 1.0);
        c.text(f.px - 6.0, v + 4.5, &tick_label(y, ystep), 9.0, Anchor::End);
    }
    c.rect(f.px, f.py, f.pw, f.ph, BLACK);
    c.text(
        f.px + f.pw / 2.0,
        f.py + f.ph + 38.0,
        xlabel,
        11.0,
        Anchor::Middle,
    );
    c.text(4.0, f.py - 8.0, ylabel, 11.0, Anchor::Start);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_ticks() {
        assert_eq!(nice_step(100.0, 8.0), 10.0);
        assert_eq!(nice_step(300.0, 8.0), 50.0);
        assert_eq!(nice_step(7.0, 8.0), 1.0);
        assert_eq!(nice_step(2.0, 8.0), 0.2);
        let (s, t) = ticks(-23.0, 41.0, 8.0);
        assert_eq!(s, 10.0);
        assert_eq!(t, vec![-20.0, -10.0, 0.0, 10.0, 20.0, 30.0, 40.0]);
        assert_eq!(tick_label(0.4, 0.2), "0.4");
        assert_eq!(tick_label(-20.0, 10.0), "-20");
    }

    #[test]
    fn thinning_keeps_ends() {
        let v: Vec<u32> = (0..10_000).collect();
        let t = thin(&v, 100);
        assert!(t.len() <= 101);
        assert_eq!((t[0], *t.last().unwrap()), (0, 9_999));
        assert_eq!(thin(&v[..5], 100), v[..5].to_vec());
    }

    #[test]
    fn gathers_track_depth_and_overlays() {
        let text = "%% LOGSTART 100\n\
            0.0 NAV_X uSimMarine 0\n0.0 NAV_Y uSimMarine 0\n\
            1.0 NAV_X uSimMarine 3\n1.0 NAV_Y uSimMarine 4\n\
            1.5 NAV_X uSimMarine 3\n\
            1.0 NAV_DEPTH uSimMarine 2.5\n\
            2.0 VIEW_SEGLIST pHelmIvP pts={0,0:10,0:10,-10},label=survey\n\
            3.0 VIEW_SEGLIST pHelmIvP pts={0,0:20,0},label=survey\n\
            3.0 VIEW_SEGLIST pHelmIvP active=false,label=survey\n\
            3.0 VIEW_POINT pHelmIvP x=5,y=6,label=next\n\
            3.0 VIEW_POLYGON pHelmIvP pts={0,0:10,0:10,10},label=region\n\
            3.0 VIEW_POLYGON pHelmIvP garbage\n";
        let d = PlotData::from_alog(&alog::parse(text).unwrap());
        assert_eq!(
            d.track,
            vec![(0.0, 0.0, 0.0), (1.0, 3.0, 0.0), (1.0, 3.0, 4.0)]
        );
        assert_eq!(d.depth, vec![(1.0, 2.5)]);
        assert!(d.dived());
        assert_eq!(d.seglists.len(), 1);
        assert_eq!(d.seglists[0].points, vec![(0.0, 0.0), (20.0, 0.0)]);
        assert_eq!(d.points[0].points, vec![(5.0, 6.0)]);
        assert_eq!(d.polygons[0].label, "region");
        assert_eq!(d.polygons[0].points.len(), 3);
    }
}
