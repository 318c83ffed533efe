//! `coug plot`: the vehicle track of an alog (NAV_X and NAV_Y of one instant make one
//! point), with the waypoints, marked points and polygons the behaviours posted
//! (`VIEW_SEGLIST`, `VIEW_POINT`, `VIEW_POLYGON`), equal-aspect axes in metres, a legend
//! with an entry for each kind of thing drawn (track, start, end, waypoints, marked points,
//! polygons) placed where it hides nothing, the mission's name as title ([`mission_title`]),
//! the simulator's truth (`SIM_X/Y`) and dead reckoning (`DR_X/Y`) beside the track when the
//! log has them (the vehicle navigated on pNavGraph's estimate: the track is then labelled
//! `estimate`), and a depth-versus-time panel over the run's whole time span when the vehicle dived
//! (deeper than [`DIVE_THRESHOLD`]). Drawn with `plotters` as SVG text or PNG bytes, with
//! the DejaVu Sans font built in (the `dejavu` crate: no font files, no system font
//! libraries).
//!
//! ```
//! let log = alog::parse("%% LOGSTART 0\n0 NAV_X s 0\n0 NAV_Y s 0\n1 NAV_X s 10\n1 NAV_Y s 5\n").unwrap();
//! let data = runtime::plot::PlotData::from_alog(&log);
//! assert_eq!(data.track.len(), 2); // one point per instant
//! let svg = runtime::plot::to_svg(&data, &runtime::plot::PlotOptions::default()).unwrap();
//! assert!(svg.starts_with("<svg"));
//! ```

mod render;

use std::collections::BTreeMap;

use alog::{Alog, Value};
use thiserror::Error;

pub use render::{to_png, to_svg};

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
    /// `(time, x, y)` each time the position changed (once both are known): NAV_X and NAV_Y
    /// posted at the same time make one point.
    pub track: Vec<(f64, f64, f64)>,
    /// `(time, depth)` of every NAV_DEPTH record.
    pub depth: Vec<(f64, f64)>,
    /// VIEW_POINTs: the last active version of each label.
    pub points: Vec<Shape>,
    /// VIEW_SEGLISTs: the last active version of each label.
    pub seglists: Vec<Shape>,
    /// VIEW_POLYGONs: the last active version of each label.
    pub polygons: Vec<Shape>,
    /// The simulator's truth `(time, x, y)` (SIM_X, SIM_Y) when the log has it: the
    /// vehicle navigated on an estimate, drawn beside it.
    pub truth: Vec<(f64, f64, f64)>,
    /// Plain dead reckoning `(time, x, y)` (DR_X, DR_Y) when the log has it.
    pub dead_reckoning: Vec<(f64, f64, f64)>,
}

/// Adds a point to an `(x, y)` pair series: `var` is one of the pair; a point is made (or
/// the instant's point updated) once both are known.
fn pair_point(
    out: &mut Vec<(f64, f64, f64)>,
    xy: &mut (Option<f64>, Option<f64>),
    is_x: bool,
    v: f64,
    t: f64,
) {
    if is_x {
        xy.0 = Some(v);
    } else {
        xy.1 = Some(v);
    }
    if let (Some(x), Some(y)) = *xy {
        match out.last_mut() {
            Some(last) if last.0 == t => (last.1, last.2) = (x, y),
            Some(&mut (_, lx, ly)) if lx == x && ly == y => {}
            _ => out.push((t, x, y)),
        }
    }
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
        let (mut truth, mut dr) = ((None, None), (None, None));
        for e in &log.entries {
            match (e.var.as_str(), &e.value) {
                ("SIM_X" | "SIM_Y", Value::Double(v)) => {
                    pair_point(&mut d.truth, &mut truth, e.var == "SIM_X", *v, e.time);
                }
                ("DR_X" | "DR_Y", Value::Double(v)) => {
                    pair_point(&mut d.dead_reckoning, &mut dr, e.var == "DR_X", *v, e.time);
                }
                ("NAV_X", Value::Double(v)) | ("NAV_Y", Value::Double(v)) => {
                    if e.var == "NAV_X" {
                        x = Some(*v);
                    } else {
                        y = Some(*v);
                    }
                    if let (Some(x), Some(y)) = (x, y) {
                        match d.track.last_mut() {
                            // NAV_X and NAV_Y of one instant are one point, not a step.
                            Some(last) if last.0 == e.time => (last.1, last.2) = (x, y),
                            Some(&mut (_, lx, ly)) if lx == x && ly == y => {}
                            _ => d.track.push((e.time, x, y)),
                        }
                    }
                }
                ("NAV_DEPTH", Value::Double(v)) => d.depth.push((e.time, *v)),
                ("VIEW_POINT", Value::String(s)) => {
                    if let Ok(p) = geometry::spec::parse_point(s) {
                        let pts = vec![(p.point.x, p.point.y)];
                        keep(&mut points, p.attrs.active, &p.attrs.label, pts);
                    }
                }
                ("VIEW_SEGLIST", Value::String(s)) => {
                    if let Ok(p) = geometry::spec::parse_seglist(s) {
                        let pts = p.seglist.points().iter().map(|q| (q.x, q.y)).collect();
                        keep(&mut segls, p.attrs.active, &p.attrs.label, pts);
                    }
                }
                ("VIEW_POLYGON", Value::String(s)) => {
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

    /// True when the vehicle dived: some NAV_DEPTH deeper than [`DIVE_THRESHOLD`] (a
    /// surface vehicle's few centimetres of noise draw no depth panel).
    pub fn dived(&self) -> bool {
        self.depth.iter().any(|&(_, z)| z > DIVE_THRESHOLD)
    }

    /// The run's time span `(first, last)` in log seconds: the track's and the depth
    /// records' times together, widened to at least one second. The depth panel's time
    /// axis covers it, so it shows the whole run the track panel shows.
    pub fn time_span(&self) -> (f64, f64) {
        let times = self
            .track
            .iter()
            .map(|p| p.0)
            .chain(self.depth.iter().map(|p| p.0));
        let (mut lo, mut hi) = times.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), t| {
            (a.min(t), b.max(t))
        });
        if !lo.is_finite() {
            (lo, hi) = (0.0, 0.0);
        }
        if hi - lo < 1.0 {
            hi = lo + 1.0;
        }
        (lo, hi)
    }
}

/// The depth in metres below which the vehicle counts as at the surface: a log whose
/// NAV_DEPTH never exceeds it gets no depth panel.
pub const DIVE_THRESHOLD: f64 = 0.1;

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

/// The mission's name from a log file's name: the stem, less pLogger's time stamp
/// (`_D_M_YYYY_____HH_MM_SS`) when it has one.
///
/// ```
/// use runtime::plot::mission_name;
/// assert_eq!(mission_name("DIVE_24_11_2026_____20_27_49.alog"), "DIVE");
/// assert_eq!(mission_name("LOG_HENRY_5_8_2026_____18_22_55.alog"), "LOG_HENRY");
/// assert_eq!(mission_name("dive.alog"), "dive");
/// ```
pub fn mission_name(file_name: &str) -> String {
    let stem = file_name.strip_suffix(".alog").unwrap_or(file_name);
    if let Some((date, time)) = stem.split_once("_____") {
        let time_ok = time.split('_').count() == 3
            && time
                .split('_')
                .all(|p| p.len() == 2 && p.bytes().all(|b| b.is_ascii_digit()));
        let parts: Vec<&str> = date.rsplitn(4, '_').collect();
        if time_ok
            && parts.len() == 4
            && parts[..3]
                .iter()
                .all(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()))
        {
            return parts[3].to_string();
        }
    }
    stem.to_string()
}

/// The mission's name for a plot's title: from the log's own banner (`%% LOG FILE:`, the
/// path pLogger gave the log, named after the mission's `File` prefix), so that it
/// survives copying or renaming the file; else from `file_name`. pLogger's time stamp is
/// dropped either way (see [`mission_name`]).
///
/// ```
/// let log = alog::parse("%% LOG FILE: ./logs/DIVE_24_11_2026_____20_27_49/DIVE_24_11_2026_____20_27_49.alog\n%% LOGSTART 0\n").unwrap();
/// assert_eq!(runtime::plot::mission_title(&log, "run3.alog"), "DIVE");
/// let headless = alog::parse("0.5 NAV_X s 1\n").unwrap();
/// assert_eq!(runtime::plot::mission_title(&headless, "Run3.alog"), "Run3");
/// ```
pub fn mission_title(log: &Alog, file_name: &str) -> String {
    let from_banner = log
        .log_file
        .as_deref()
        .map(|p| p.trim().rsplit(['/', '\\']).next().unwrap_or(""))
        .map(mission_name)
        .unwrap_or_default();
    if from_banner.trim().is_empty() {
        mission_name(file_name)
    } else {
        from_banner
    }
}

/// Height of the depth panel, pixels.
pub(crate) const DEPTH_PANEL_H: u32 = 240;

/// The image size (width, height) in pixels of a plot: the width asked for; the height
/// holds a square track panel and, when the vehicle dived, the depth panel.
pub fn image_size(data: &PlotData, opts: &PlotOptions) -> (u32, u32) {
    let h = opts.width + if data.dived() { DEPTH_PANEL_H } else { 0 };
    (opts.width, h)
}

#[cfg(test)]
mod tests {
    use super::*;

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
        // NAV_X and NAV_Y of one instant: one point (no staircase); 1.5 s changed nothing.
        assert_eq!(d.track, vec![(0.0, 0.0, 0.0), (1.0, 3.0, 4.0)]);
        assert_eq!(d.depth, vec![(1.0, 2.5)]);
        assert!(d.dived());
        assert_eq!(d.seglists.len(), 1);
        assert_eq!(d.seglists[0].points, vec![(0.0, 0.0), (20.0, 0.0)]);
        assert_eq!(d.points[0].points, vec![(5.0, 6.0)]);
        assert_eq!(d.polygons[0].label, "region");
        assert_eq!(d.polygons[0].points.len(), 3);
    }

    #[test]
    fn truth_and_dead_reckoning_beside_the_estimate() {
        let text = "%% LOGSTART 0\n\
            0.1 SIM_X uSimMarineV22 0\n0.1 SIM_Y uSimMarineV22 1\n\
            0.2 NAV_X pNavGraph 0.5\n0.2 NAV_Y pNavGraph 1.5\n\
            0.2 DR_X pNavGraph 0.7\n0.2 DR_Y pNavGraph 1.7\n\
            0.3 SIM_Y uSimMarineV22 2\n0.3 SIM_X uSimMarineV22 1\n";
        let d = PlotData::from_alog(&alog::parse(text).unwrap());
        assert_eq!(d.track, vec![(0.2, 0.5, 1.5)]);
        assert_eq!(d.truth, vec![(0.1, 0.0, 1.0), (0.3, 1.0, 2.0)]);
        assert_eq!(d.dead_reckoning, vec![(0.2, 0.7, 1.7)]);
        let svg = to_svg(&d, &PlotOptions::default()).unwrap();
        assert!(svg.contains("truth (SIM_*)") && svg.contains("dead reckoning (DR_*)"));
        assert!(svg.contains("estimate (NAV_*)"));
        let plain = PlotData {
            truth: Vec::new(),
            dead_reckoning: Vec::new(),
            ..d
        };
        let svg = to_svg(&plain, &PlotOptions::default()).unwrap();
        assert!(!svg.contains("truth") && !svg.contains("estimate"));
    }

    fn track_of(text: &str) -> Vec<(f64, f64, f64)> {
        PlotData::from_alog(&alog::parse(text).unwrap()).track
    }

    #[test]
    fn nav_x_and_nav_y_of_one_instant_are_one_track_point() {
        // pLogger order within an instant varies (X then Y, Y then X, other variables in
        // between); each instant is one point, never an L-shaped step.
        let text = "%% LOGSTART 0\n\
            0.1 NAV_X uSimMarine 0\n0.1 NAV_Y uSimMarine 0\n\
            0.2 NAV_X uSimMarine 1\n0.2 NAV_Y uSimMarine 1\n\
            0.3 NAV_Y uSimMarine 2\n0.3 NAV_DEPTH uSimMarine 0\n0.3 NAV_X uSimMarine 2\n\
            0.4 NAV_X uSimMarine 3\n0.4 NAV_SPEED uSimMarine 1\n0.4 NAV_Y uSimMarine 3\n";
        assert_eq!(
            track_of(text),
            vec![
                (0.1, 0.0, 0.0),
                (0.2, 1.0, 1.0),
                (0.3, 2.0, 2.0),
                (0.4, 3.0, 3.0)
            ]
        );
    }

    #[test]
    fn a_lone_coordinate_update_keeps_the_other_coordinate() {
        // NAV_X alone at 2.0 moves along x at the last y; NAV_Y alone at 3.0 moves along y.
        // An update to the same position adds nothing.
        let text = "%% LOGSTART 0\n\
            1.0 NAV_X s 0\n1.0 NAV_Y s 5\n\
            2.0 NAV_X s 4\n\
            3.0 NAV_Y s 7\n\
            4.0 NAV_Y s 7\n";
        assert_eq!(
            track_of(text),
            vec![(1.0, 0.0, 5.0), (2.0, 4.0, 5.0), (3.0, 4.0, 7.0)]
        );
        // Before both are known there is no point: the first is where both are.
        let text = "%% LOGSTART 0\n0.5 NAV_X s 9\n1.0 NAV_X s 1\n1.0 NAV_Y s 2\n";
        assert_eq!(track_of(text), vec![(1.0, 1.0, 2.0)]);
    }

    #[test]
    fn surface_noise_is_no_dive() {
        let log = |z: f64| format!("%% LOGSTART 0\n0 NAV_X s 0\n0 NAV_Y s 0\n1 NAV_DEPTH s {z}\n");
        let at = |z: f64| PlotData::from_alog(&alog::parse(&log(z)).unwrap());
        assert!(!at(0.0).dived());
        assert!(!at(0.05).dived(), "5 cm is surface noise");
        assert!(at(0.5).dived());
    }

    #[test]
    fn the_time_span_covers_track_and_depth() {
        let text = "%% LOGSTART 0\n\
            2.0 NAV_X s 0\n2.0 NAV_Y s 0\n50.0 NAV_X s 9\n\
            10.0 NAV_DEPTH s 3\n60.0 NAV_DEPTH s 1\n";
        let d = PlotData::from_alog(&alog::parse(text).unwrap());
        assert_eq!(d.time_span(), (2.0, 60.0));
        assert_eq!(PlotData::default().time_span(), (0.0, 1.0));
    }

    #[test]
    fn the_title_is_the_mission_name_from_the_banner_else_the_file() {
        let banner = "%%%%%%%%\n%% LOG FILE:       ./logs/DIVE_6_8_2026_____07_06_40/DIVE_6_8_2026_____07_06_40.alog\n%% LOGSTART 0\n";
        let log = alog::parse(banner).unwrap();
        assert_eq!(mission_title(&log, "copy.alog"), "DIVE");
        let log = alog::parse("%% LOGSTART 0\n").unwrap();
        assert_eq!(
            mission_title(&log, "Henry_Survey_5_8_2026_____18_22_55.alog"),
            "Henry_Survey"
        );
        let log = alog::parse("%% LOG FILE:\n%% LOGSTART 0\n").unwrap();
        assert_eq!(mission_title(&log, "Mixed Case.alog"), "Mixed Case");
    }
}
