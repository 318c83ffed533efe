//! BHV_StationKeep (reference §6.10): holds position near a station point.
//!
//! # Conformance with BHV_StationKeep (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | station_pt | point | point | none | `x,y`, `x=..,y=..` (any `string2Point` form) | yes | done |
//! | center_activate | | bool | false | `true`/`false` | yes | done |
//! | inner_radius | | m | 4 | number > 0 | yes | done |
//! | outer_radius | | m | 15 | number > 0 (raised to the inner radius when smaller) | yes | done |
//! | outer_speed | | m/s | 1.2 | number > 0; raises transit_speed to it | yes | done |
//! | transit_speed | extra_speed | m/s | 2.5 | number > 0 | yes | done |
//! | swing_time | | s | 0 | number, clipped to [0, 60] | yes | done |
//! | hibernation_radius | | m | −1 (off) | number > 0, or `off`/`-1` | yes | done |
//! | visual_hints | | hints | vertex red, edge light_blue, label white, sizes 1 | MOOS colours (`isColor`), sizes numbers; a bad hint is ignored | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | DIST_TO_STATION | every running iteration (before it is remeasured on a station set; −1 before the first) | metres | done |
//! | PSKEEP_MODE | every running iteration with a station | `HIBERNATING`, `SEEKING_STATION` (`DISABLED` before a station is ever set) | done |
//! | BHV_SETTINGS | each idle→running transition (repeatable) | `type=BHV_StationKeep,name=..,x=..,y=..,inner_radius=..,outer_radius=..,hibernation_radius=..,outer_speed=..,center_activate=..` | done |
//! | VIEW_POLYGON | running (drawn), running→idle and no station (erased) | `radial:: x=..,y=..,source=<us>:<name>,pts=32,...,label=<us>:station-keep-out\|in\|hiber,radius=..` | done |
//! | BHV_WARNING | running without a station | `STATION_POINT_NOT_SET` | done |
//! | BHV_ERROR | no NAV_X/NAV_Y, no NAV_HEADING | `No ownship X/Y info in info_buffer.`, `No ownship heading info in info_buffer.` | done |

use std::collections::VecDeque;

use geometry::Point;
use geometry::spec::parse_point;
use ivp::{IvpFunction, ZaicPeak, couple};

use crate::behavior::{Behavior, Ctx, Out, ParamError, PostKey, add_vars};
use crate::common::Common;
use crate::fmt::{compact, fixed};
use crate::param::{boolean, number};

/// Hibernation state (`PSKEEP_MODE`), used with `hibernation_radius`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum KeepMode {
    /// No hibernation radius: plain station keeping.
    Disabled,
    /// Within the hibernation radius: no thrust (speed 0), e.g. a UUV floating at the surface.
    Hibernating,
    /// Drifted outside the hibernation radius: seeking the station until inside the inner
    /// radius, or until progress toward it stalls inside the hibernation radius.
    SeekingStation,
}

impl KeepMode {
    fn as_str(self) -> &'static str {
        match self {
            KeepMode::Disabled => "DISABLED",
            KeepMode::Hibernating => "HIBERNATING",
            KeepMode::SeekingStation => "SEEKING_STATION",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Transit {
    Idle,
    PendingProgressStart,
    NotedProgressStart,
    NotedProgressEnd,
}

/// Station keeping: desired speed 0 inside `inner_radius` (default 4 m), rising linearly to
/// `outer_speed` (1.2 m/s) at `outer_radius` (15 m), and `transit_speed` (`extra_speed`,
/// 2.5 m/s) beyond; course toward the station. The function couples speed ZAIC_PEAK(desired,
/// base 0.4, utility 0..25) with course ZAIC_PEAK(bearing to station, base 180, wrap) 50/50.
///
/// The station is `station_pt`/`point`, or with `center_activate = true` ownship's position
/// when the behaviour starts running (re-taken every iteration for `swing_time` seconds,
/// 0..60, to let the vehicle settle). With `hibernation_radius` the vehicle hibernates (speed
/// 0) until it drifts outside that radius, then seeks the station until it is inside the
/// inner radius, or its distance stops shrinking (over 10 s of history) inside the
/// hibernation radius.
///
/// Posts `DIST_TO_STATION`, `PSKEEP_MODE`, `BHV_SETTINGS` on each start and the
/// `VIEW_POLYGON` circles `<us>:station-keep-out|in|hiber` (erased when it stops running).
///
/// As MOOS-IvP at a2a9b716, case for case: whenever the station is (re)set the mode becomes
/// `HIBERNATING` for that iteration, even without a hibernation radius (then the next
/// iteration, being outside radius −1, turns it to `SEEKING_STATION`, and reaching the inner
/// radius turns it back); `DIST_TO_STATION` is posted before it is recomputed on an iteration
/// that (re)sets the station (−1 before the first measurement); while the centre still follows
/// ownship (`center_activate` within `swing_time`) the course peak is ownship's heading; an
/// inner radius larger than the outer one raises the outer radius to it.
#[derive(Debug, Clone)]
pub struct StationKeep {
    static_station: Option<Point>,
    station: Option<Point>,
    /// Inner radius, m.
    pub inner_radius: f64,
    /// Outer radius, m.
    pub outer_radius: f64,
    /// Speed at the outer radius, m/s.
    pub outer_speed: f64,
    /// Speed beyond the outer radius, m/s.
    pub transit_speed: f64,
    /// Re-centre on ownship when the behaviour starts running.
    pub center_activate: bool,
    /// Seconds the centre follows ownship after activation (0..60).
    pub swing_time: f64,
    /// Hibernation radius, m (−1 = off).
    pub hibernation_radius: f64,
    hint_vertex_color: String,
    hint_edge_color: String,
    hint_label_color: String,
    hint_vertex_size: f64,
    hint_edge_size: f64,
    center_pending: bool,
    mode: KeepMode,
    transit: Transit,
    mark_time: Option<f64>,
    dist: f64,
    history: VecDeque<(f64, f64)>,
}

impl Default for StationKeep {
    fn default() -> Self {
        Self::new()
    }
}

impl StationKeep {
    /// The MOOS defaults.
    pub fn new() -> Self {
        StationKeep {
            static_station: None,
            station: None,
            inner_radius: 4.0,
            outer_radius: 15.0,
            outer_speed: 1.2,
            transit_speed: 2.5,
            center_activate: false,
            swing_time: 0.0,
            hibernation_radius: -1.0,
            hint_vertex_color: "red".into(),
            hint_edge_color: "light_blue".into(),
            hint_label_color: "white".into(),
            hint_vertex_size: 1.0,
            hint_edge_size: 1.0,
            center_pending: false,
            mode: KeepMode::Disabled,
            transit: Transit::Idle,
            mark_time: None,
            dist: -1.0,
            history: VecDeque::new(),
        }
    }

    /// The station point, once set.
    pub fn station(&self) -> Option<Point> {
        self.station
    }

    /// The hibernation mode.
    pub fn mode(&self) -> KeepMode {
        self.mode
    }

    /// The desired speed at distance `dist` from the station.
    pub fn desired_speed(&self, dist: f64) -> f64 {
        let outer = self.outer_radius;
        if self.mode == KeepMode::Hibernating || dist <= self.inner_radius {
            0.0
        } else if dist < outer {
            (dist - self.inner_radius) / (outer - self.inner_radius) * self.outer_speed
        } else {
            self.transit_speed
        }
    }

    /// Distance trend over the last 10 s: `Some(rate)` once more than 5 s are covered.
    fn trend(&self) -> Option<f64> {
        let (t_new, d_new) = *self.history.front()?;
        let (t_old, d_old) = *self.history.back()?;
        let dt = t_new - t_old;
        (dt > 5.0).then(|| (d_new - d_old) / dt)
    }

    fn update_hibernation(&mut self) {
        if self.mode == KeepMode::Disabled {
            return;
        }
        let (d, hib) = (self.dist, self.hibernation_radius);
        match self.transit {
            Transit::PendingProgressStart if d <= hib && self.trend().is_some_and(|r| r <= 0.0) => {
                self.history.clear();
                self.transit = Transit::NotedProgressStart;
            }
            Transit::NotedProgressStart if self.trend().is_some_and(|r| r >= 0.0) => {
                self.transit = Transit::NotedProgressEnd;
            }
            _ => {}
        }
        match self.mode {
            KeepMode::Hibernating if d > hib => {
                self.mode = KeepMode::SeekingStation;
                self.history.clear();
                self.transit = Transit::PendingProgressStart;
            }
            KeepMode::SeekingStation
                if d <= self.inner_radius
                    || (self.transit == Transit::NotedProgressEnd && d <= hib) =>
            {
                self.mode = KeepMode::Hibernating;
                self.transit = Transit::Idle;
                self.history.clear();
            }
            _ => {}
        }
    }

    fn post_circles(&self, ctx: &Ctx<'_>, out: &mut Out, active: bool) {
        // MOOS draws (or erases) at the current station, the origin before one is set.
        let st = self.station.unwrap_or_default();
        let mut base = String::from("radial:: x=");
        fixed(&mut base, st.x, 1);
        base.push_str(",y=");
        fixed(&mut base, st.y, 1);
        base.push_str(&format!(",source={}:{},pts=32", ctx.ownship, ctx.name));
        if self.hint_edge_size >= 0.0 {
            base.push_str(",edge_size=");
            compact(&mut base, self.hint_edge_size, 5);
        }
        if self.hint_vertex_size >= 0.0 {
            base.push_str(",vertex_size=");
            compact(&mut base, self.hint_vertex_size, 5);
        }
        for (k, v) in [
            ("edge_color", &self.hint_edge_color),
            ("label_color", &self.hint_label_color),
            ("vertex_color", &self.hint_vertex_color),
        ] {
            if !v.is_empty() {
                base.push_str(&format!(",{k}={v}"));
            }
        }
        let circles = [
            ("outer", "out", self.outer_radius, true),
            (
                "inner",
                "in",
                self.inner_radius,
                self.inner_radius < self.outer_radius,
            ),
            (
                "hiber",
                "hiber",
                self.hibernation_radius,
                self.hibernation_radius > self.outer_radius,
            ),
        ];
        for (tag, which, radius, wanted) in circles {
            if active && !wanted {
                continue;
            }
            let mut s = base.clone();
            s.push_str(&format!(
                ",label={}:station-keep-{which},radius=",
                ctx.ownship
            ));
            fixed(&mut s, radius, 1);
            if !active {
                s.push_str(",active=false");
            }
            out.post_key("VIEW_POLYGON", s, PostKey::Tag(tag));
        }
    }
}

impl Behavior for StationKeep {
    fn kind(&self) -> &'static str {
        "BHV_StationKeep"
    }

    fn default_name(&self) -> &'static str {
        "station_keep"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course", "speed"]
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_X", "NAV_Y"]);
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        let v = value.trim();
        let positive = |v: &str| -> Result<f64, ParamError> {
            let d = number(param, v)?;
            if d <= 0.0 {
                return Err(ParamError::bad(param, value, "a positive number"));
            }
            Ok(d)
        };
        match param {
            "station_pt" | "point" => {
                let p = parse_point(v).map_err(|_| ParamError::bad(param, value, "x,y"))?;
                self.static_station = Some(p.point);
                self.center_pending = true;
            }
            "hibernation_radius" => {
                if v.eq_ignore_ascii_case("off") || v == "-1" {
                    self.mode = KeepMode::Disabled;
                    self.hibernation_radius = -1.0;
                } else {
                    self.hibernation_radius = positive(v)?;
                    if self.mode == KeepMode::Disabled {
                        self.mode = KeepMode::Hibernating;
                    }
                }
            }
            "center_activate" => {
                self.center_activate = boolean(param, v)?;
                self.center_pending = true;
            }
            "outer_radius" => self.outer_radius = positive(v)?,
            "inner_radius" => self.inner_radius = positive(v)?,
            "outer_speed" => {
                self.outer_speed = positive(v)?;
                self.transit_speed = self.transit_speed.max(self.outer_speed);
            }
            "extra_speed" | "transit_speed" => self.transit_speed = positive(v)?,
            "swing_time" => self.swing_time = number(param, v)?.clamp(0.0, 60.0),
            "visual_hints" => {
                use crate::hints::{color, pairs, size};
                for (k, val) in pairs(v) {
                    match (k.as_str(), color(val), size(val)) {
                        ("vertex_color", Some(c), _) => self.hint_vertex_color = c.into(),
                        ("edge_color", Some(c), _) => self.hint_edge_color = c.into(),
                        ("label_color", Some(c), _) => self.hint_label_color = c.into(),
                        ("vertex_size", _, Some(d)) => self.hint_vertex_size = d,
                        ("edge_size", _, Some(d)) => self.hint_edge_size = d,
                        // MOOS ignores unknown hints and bad values.
                        _ => {}
                    }
                }
            }
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn config_status(&self, name: &str) -> Option<String> {
        let st = self.static_station.unwrap_or_default();
        let mut s = format!("type=BHV_StationKeep,name={name},x=");
        fixed(&mut s, st.x, 2);
        s.push_str(",y=");
        fixed(&mut s, st.y, 2);
        for (k, v) in [
            ("inner_radius", self.inner_radius),
            ("outer_radius", self.outer_radius),
            ("hibernation_radius", self.hibernation_radius),
            ("outer_speed", self.outer_speed),
        ] {
            s.push_str(&format!(",{k}="));
            fixed(&mut s, v, 1);
        }
        s.push_str(&format!(",center_activate={}", self.center_activate));
        Some(s)
    }

    fn on_idle_to_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        crate::behavior::post_config_status(&*self, ctx, out);
    }

    fn on_run_to_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.history.clear();
        self.post_circles(ctx, out, false);
        if self.center_activate {
            self.center_pending = true;
        }
        self.mark_time = None;
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let now = ctx.info.now();
        let (Some(x), Some(y)) = (ctx.info.num("NAV_X"), ctx.info.num("NAV_Y")) else {
            out.error("No ownship X/Y info in info_buffer.");
            return None;
        };
        let Some(heading) = ctx.info.num("NAV_HEADING").map(geometry::angle_360) else {
            out.error("No ownship heading info in info_buffer.");
            return None;
        };
        let mark = *self.mark_time.get_or_insert(now);
        let mut ctr_changed = false;
        if self.center_pending {
            if self.center_activate {
                self.station = Some(Point::new(x, y));
                ctr_changed = true;
                if now >= mark + self.swing_time {
                    self.center_pending = false;
                }
            } else if let Some(p) = self.static_station {
                self.station = Some(p);
                self.center_pending = false;
                ctr_changed = true;
            }
        }
        if ctr_changed {
            // A new station: hibernate this iteration; the distance is measured next time.
            self.mode = KeepMode::Hibernating;
            self.transit = Transit::Idle;
        } else {
            let st = self.station.unwrap_or_default();
            self.dist = (x - st.x).hypot(y - st.y);
            self.history.push_front((now, self.dist));
            while self.history.back().is_some_and(|(t, _)| now - t > 10.0) {
                self.history.pop_back();
            }
        }
        out.post("DIST_TO_STATION", self.dist);
        let Some(st) = self.station else {
            out.warning(ctx.name, "STATION_POINT_NOT_SET");
            self.post_circles(ctx, out, false);
            return None;
        };
        if self.inner_radius > self.outer_radius {
            self.outer_radius = self.inner_radius;
        }
        self.update_hibernation();
        out.post("PSKEEP_MODE", self.mode.as_str());
        self.post_circles(ctx, out, true);

        let desired = self.desired_speed(self.dist);
        let bearing = if self.center_pending {
            heading
        } else {
            geometry::relative_angle(x, y, st.x, st.y)
        };
        let mut spd = ZaicPeak::new(ctx.domain, "speed").ok()?;
        let mut crs = ZaicPeak::new(ctx.domain, "course").ok()?;
        crs.set_value_wrap(true);
        let built = spd
            .set_params(desired, 0.0, 0.4, 0.0, 0.0, 25.0)
            .and_then(|_| crs.set_params(bearing, 0.0, 180.0, 0.0, 0.0, 100.0))
            .and_then(|_| couple(&crs.extract()?, &spd.extract()?));
        match built {
            Ok(f) => Some(f),
            Err(e) => {
                out.error(format!("Unable to build the station-keep function: {e}"));
                None
            }
        }
    }
}
