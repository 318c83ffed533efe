//! BHV_OpRegion (reference §6.11): the operating-region safety monitor.
//!
//! # Conformance with BHV_OpRegion (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | polygon | | polygon | none | convex; each line adds one | yes | done |
//! | max_depth | | m | 0 (off) | number >= 0 | yes | done |
//! | min_altitude | | m | 0 (off) | number >= 0 | yes | done |
//! | max_time | | s | 0 (off) | number >= 0 | yes | done |
//! | trigger_entry_time | | s | 1 | number >= 0 | yes | done |
//! | trigger_exit_time | | s | 0.5 | number >= 0 | yes | done |
//! | breached_poly_flag, breached_time_flag, breached_altitude_flag, breached_depth_flag | | flag | none | `VAR=value` | yes | done |
//! | soft_poly_breach | | bool | false | MOOS boolean | yes | done |
//! | reset_var | | var | none | no white space; `true`, `poly`, `time`, `altitude` (re-arms the altitude and the depth flags, as the C++); `depth` does nothing | yes | done |
//! | time_remaining_var | | var | none | no white space | yes | done |
//! | opregion_poly_var | | var | none | no white space | yes | done |
//! | visual_hints | | hints | vertex brown, edge aqua, label aqua, sizes 3 and 1 | MOOS colours (`isColor`), sizes numbers >= 0; a bad hint is ignored | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | OPREG_TRAJECTORY_PERIM_DIST, _ETA, OPREG_ABSOLUTE_PERIM_DIST, _ETA | each running iteration | integers above the C++ thresholds, else decimals | done |
//! | OPREG_TIME_REMAINING, `time_remaining_var` | with max_time | seconds | done |
//! | SECS_IN_POLY | each running iteration | seconds inside the polygon | done |
//! | `opregion_poly_var` | configuration and updates | `pts={...}` | done |
//! | VIEW_POLYGON | running (drawn), idle (`active=false`) | polygon spec | done |
//! | MOOS_MANUAL_OVERRIDE | soft polygon breach (repeatable) | `true` | done |
//! | BHV_ERROR | a breach | `BHV_OpRegion Polygon containment failure: ...`, `OpRegion Depth failure: ...`, `OpRegion Altitude failure: ...`, `OpRegion timeout failure: ...` | done |

use geometry::spec::parse_polygon;
use geometry::{Polygon, ViewPolygon};
use ivp::IvpFunction;

use crate::behavior::{Behavior, Ctx, Out, ParamError, PostKey, add_flag_vars, add_vars};
use crate::common::{Common, Flag};
use crate::fmt::fixed;
use crate::param::{boolean, number};

/// Which limit a breach concerns (indexes the breach flag lists).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Breach {
    /// Outside the polygon(s) for longer than `trigger_exit_time`.
    Poly,
    /// Running longer than `max_time`.
    Time,
    /// Below `min_altitude`.
    Altitude,
    /// Deeper than `max_depth`.
    Depth,
}

impl Breach {
    fn index(self) -> usize {
        match self {
            Breach::Poly => 0,
            Breach::Time => 1,
            Breach::Altitude => 2,
            Breach::Depth => 3,
        }
    }
}

/// The operating-region guard. It never produces an objective function; on every running
/// iteration it checks, in MOOS-IvP's order:
///
/// 1. the polygon: ownship must be inside every configured `polygon` (each `polygon` line adds
///    one; the last one is drawn). Leaving counts only after `trigger_exit_time` seconds
///    (default 0.5) outside; with `trigger_entry_time` set > 0 the polygon is enforced only once
///    the vehicle has been inside that long;
/// 2. the depth: `NAV_DEPTH > max_depth` (0 = off);
/// 3. the altitude: `NAV_ALTITUDE < min_altitude` (0 = off);
/// 4. the time: seconds since the behaviour first ran `> max_time` (0 = off).
///
/// A breach posts that limit's `breached_*_flag`s (once, until reset) and then reports an
/// error ([`Out::error`]), which the helm posts as `BHV_ERROR` and answers with the all-stop
/// `BehaviorError` in the same iteration. With `soft_poly_breach = true` a polygon breach
/// instead posts `MOOS_MANUAL_OVERRIDE = true` and a `BHV_WARNING`.
///
/// It also posts `OPREG_TRAJECTORY_PERIM_DIST/ETA`, `OPREG_ABSOLUTE_PERIM_DIST/ETA`,
/// `OPREG_TIME_REMAINING` (with `max_time`), the `time_remaining_var`, the
/// `opregion_poly_var` (as `pts={...}`, at configuration and after updates) and `VIEW_POLYGON` (label
/// `<ownship>:<name>:opreg` unless the polygon has one; `active=false` while idle).
///
/// `reset_var` acts when it is posted during the iteration (any new posting, even of the same
/// value, as MOOS tests the variable's age): `true` resets everything, `poly` or `time` one
/// limit, `altitude` both the altitude and the depth flags (as the C++ does; `depth` resets
/// nothing).
///
/// Without `max_time` the `time_remaining_var` gets −1 and then 0 each iteration, as the C++
/// (which falls through after posting −1).
#[derive(Debug, Clone)]
pub struct OpRegion {
    polygons: Vec<Polygon>,
    view: Option<ViewPolygon>,
    /// Deepest allowed depth, m (0 = off).
    pub max_depth: f64,
    /// Lowest allowed altitude, m (0 = off).
    pub min_altitude: f64,
    /// Longest allowed running time, s (0 = off).
    pub max_time: f64,
    /// Seconds inside before the polygon is enforced (only when set > 0).
    pub trigger_entry_time: f64,
    /// Seconds outside before a polygon breach is declared.
    pub trigger_exit_time: f64,
    trigger_on_entry: bool,
    /// A polygon breach parks the helm (manual override) instead of an error.
    pub soft_poly_breach: bool,
    flags: [Vec<Flag>; 4],
    flags_posted: [bool; 4],
    reset_var: String,
    time_remaining_var: String,
    poly_var: String,
    hint_vertex_color: String,
    hint_edge_color: String,
    hint_label_color: String,
    hint_vertex_size: f64,
    hint_edge_size: f64,
    first_time: bool,
    prev_time: f64,
    start_time: f64,
    delta_time: f64,
    elapsed: f64,
    secs_in: f64,
    secs_out: f64,
    prev_in: bool,
    entry_made: bool,
    hints_applied: bool,
    buf: String,
}

impl Default for OpRegion {
    fn default() -> Self {
        Self::new()
    }
}

impl OpRegion {
    /// The MOOS defaults: no polygon, all limits off.
    pub fn new() -> Self {
        OpRegion {
            polygons: Vec::new(),
            view: None,
            max_depth: 0.0,
            min_altitude: 0.0,
            max_time: 0.0,
            trigger_entry_time: 1.0,
            trigger_exit_time: 0.5,
            trigger_on_entry: false,
            soft_poly_breach: false,
            flags: Default::default(),
            flags_posted: [false; 4],
            reset_var: String::new(),
            time_remaining_var: String::new(),
            poly_var: String::new(),
            hint_vertex_color: "brown".into(),
            hint_edge_color: "aqua".into(),
            hint_label_color: "aqua".into(),
            hint_vertex_size: 3.0,
            hint_edge_size: 1.0,
            first_time: true,
            prev_time: 0.0,
            start_time: 0.0,
            delta_time: 0.0,
            elapsed: 0.0,
            secs_in: 0.0,
            secs_out: 0.0,
            prev_in: false,
            entry_made: false,
            hints_applied: false,
            buf: String::new(),
        }
    }

    /// Seconds since the first running iteration (or the last `time` reset).
    pub fn elapsed(&self) -> f64 {
        self.elapsed
    }

    /// Whether the vehicle has been inside the polygon long enough for it to be enforced
    /// (relevant with `trigger_entry_time`).
    pub fn entry_made(&self) -> bool {
        self.entry_made
    }

    fn nonneg(param: &str, value: &str) -> Result<f64, ParamError> {
        let v = number(param, value)?;
        if v < 0.0 {
            return Err(ParamError::bad(param, value, "a number >= 0"));
        }
        Ok(v)
    }

    fn post_breach_flags(&mut self, which: Breach, out: &mut Out) {
        let i = which.index();
        if self.flags_posted[i] {
            return;
        }
        self.flags_posted[i] = true;
        for f in &self.flags[i] {
            out.flag(f, true);
        }
    }

    fn check_reset(&mut self, ctx: &Ctx<'_>) {
        if self.reset_var.is_empty() {
            return;
        }
        // As MOOS: only a posting made this iteration counts, whatever its value.
        if !ctx.info.is_fresh(&self.reset_var) {
            return;
        }
        let Some(v) = ctx.info.text(&self.reset_var) else {
            return;
        };
        let v = v.trim().to_ascii_lowercase();
        let all = v == "true";
        if all || v == "poly" {
            self.flags_posted[Breach::Poly.index()] = false;
            self.secs_in = 0.0;
            self.prev_in = false;
            self.entry_made = false;
        }
        if all || v == "time" {
            self.first_time = true;
            self.flags_posted[Breach::Time.index()] = false;
        }
        if all || v == "altitude" {
            self.flags_posted[Breach::Altitude.index()] = false;
        }
        // As the C++ at a2a9b716: the depth flags are re-armed by `altitude` (and `true`);
        // a `depth` reset re-arms nothing.
        if all || v == "altitude" {
            self.flags_posted[Breach::Depth.index()] = false;
        }
    }

    fn set_time_stamps(&mut self, now: f64) {
        if self.first_time {
            self.start_time = now;
            self.delta_time = 0.0;
            self.first_time = false;
        } else {
            self.delta_time = now - self.prev_time;
        }
        self.prev_time = now;
        self.elapsed = now - self.start_time;
    }

    /// Updates the in/out timers; true if the polygon counts as breached now.
    fn polygon_breached(&mut self, x: f64, y: f64) -> bool {
        let contained = self.polygons.iter().all(|p| p.contains(x, y));
        if contained {
            self.secs_out = 0.0;
            self.secs_in = if self.prev_in {
                self.secs_in + self.delta_time
            } else {
                0.0
            };
            self.prev_in = true;
            if self.secs_in >= self.trigger_entry_time {
                self.entry_made = true;
            }
            return false;
        }
        self.secs_in = 0.0;
        self.secs_out = if self.prev_in {
            0.0
        } else {
            self.secs_out + self.delta_time
        };
        self.prev_in = false;
        if self.trigger_on_entry && !self.entry_made {
            return false;
        }
        self.secs_out >= self.trigger_exit_time
    }

    fn error(out: &mut Out, msg: String) {
        if out.error.is_none() {
            out.error(msg);
        }
    }

    fn post_time_remaining(&mut self, out: &mut Out) {
        if self.time_remaining_var.is_empty() {
            return;
        }
        // As the C++: without a max_time, −1 and then (falling through) 0 are both posted.
        if self.max_time <= 0.0 {
            out.post(self.time_remaining_var.clone(), -1.0);
        }
        let rem = (self.max_time - self.elapsed).max(0.0);
        if rem > 10.0 {
            out.post_int(self.time_remaining_var.clone(), rem);
        } else {
            out.post(self.time_remaining_var.clone(), rem);
        }
    }

    fn post_poly_var(&self, out: &mut Out) {
        if self.poly_var.is_empty() {
            return;
        }
        if let Some(p) = self.polygons.last() {
            let mut v = ViewPolygon::new(p.clone());
            v.precision = 2;
            out.post(self.poly_var.clone(), v.to_spec());
        }
    }

    /// Posts the polygon: drawn with the hints while running, `active=false` while idle.
    /// The label defaults to `<ownship>:<name>:opreg`.
    fn post_view(&mut self, ctx: &Ctx<'_>, out: &mut Out, active: bool) {
        let Some(v) = self.view.as_mut() else {
            return;
        };
        if v.attrs.label.is_empty() {
            v.attrs.label = format!("{}:{}:opreg", ctx.ownship, ctx.name);
        }
        if !self.hints_applied {
            self.hints_applied = true;
            v.attrs.vertex_color = Some(self.hint_vertex_color.clone());
            v.attrs.edge_color = Some(self.hint_edge_color.clone());
            v.attrs.label_color = Some(self.hint_label_color.clone());
            v.attrs.vertex_size = Some(self.hint_vertex_size);
            v.attrs.edge_size = Some(self.hint_edge_size);
        }
        v.attrs.active = active;
        self.buf.clear();
        v.spec(&mut self.buf);
        out.post("VIEW_POLYGON", self.buf.as_str());
    }

    fn post_poly_status(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        let i = ctx.info;
        let missing = [
            ("NAV_X", i.num("NAV_X")),
            ("NAV_Y", i.num("NAV_Y")),
            ("NAV_SPEED", i.num("NAV_SPEED")),
            ("NAV_HEADING", i.num("NAV_HEADING")),
        ]
        .into_iter()
        .find(|(_, v)| v.is_none());
        if let Some((var, _)) = missing {
            Self::error(
                out,
                format!("No ownship {var} ({}) in info_buffer", ctx.ownship),
            );
            return;
        }
        let (x, y) = (i.num("NAV_X").unwrap_or(0.0), i.num("NAV_Y").unwrap_or(0.0));
        let spd = i.num("NAV_SPEED").unwrap_or(0.0);
        let hdg = i.num("NAV_HEADING").unwrap_or(0.0);
        let Some(top) = ctx.domain.get("speed").map(|d| d.high()) else {
            Self::error(out, "No Top-Speed info found in the decision domain".into());
            return;
        };
        if let Some(poly) = self.polygons.last() {
            let traj = poly.ray_distance(x, y, hdg).unwrap_or(-1.0);
            let traj_eta = if spd > 0.0 { traj / spd } else { 0.0 };
            if traj <= 1.0 {
                out.post("OPREG_TRAJECTORY_PERIM_DIST", traj);
            } else {
                out.post_int("OPREG_TRAJECTORY_PERIM_DIST", traj);
            }
            out.post_int("OPREG_TRAJECTORY_PERIM_ETA", traj_eta);
            let abs = poly.dist_to_boundary(x, y).unwrap_or(-1.0);
            let abs_eta = if top > 0.0 { abs / top } else { 0.0 };
            if abs <= 1.0 {
                out.post("OPREG_ABSOLUTE_PERIM_DIST", abs);
            } else {
                out.post_int("OPREG_ABSOLUTE_PERIM_DIST", abs);
            }
            out.post_int("OPREG_ABSOLUTE_PERIM_ETA", abs_eta);
        }
        if self.max_time > 0.0 {
            out.post(
                "OPREG_TIME_REMAINING",
                (self.max_time - self.elapsed).max(0.0),
            );
        }
    }
}

impl Behavior for OpRegion {
    fn kind(&self) -> &'static str {
        "BHV_OpRegion"
    }

    fn default_name(&self) -> &'static str {
        "bhv_opregion"
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(
            out,
            [
                "NAV_X",
                "NAV_Y",
                "NAV_HEADING",
                "NAV_SPEED",
                "NAV_DEPTH",
                "NAV_ALTITUDE",
            ],
        );
        add_vars(out, [self.reset_var.as_str()]);
        for flags in &self.flags {
            add_flag_vars(out, flags);
        }
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        let v = value.trim();
        let no_white = |v: &str| {
            if v.contains(char::is_whitespace) {
                Err(ParamError::bad(
                    param,
                    value,
                    "a variable name without spaces",
                ))
            } else {
                Ok(v.to_string())
            }
        };
        match param {
            "polygon" => {
                let vp = parse_polygon(v)
                    .map_err(|_| ParamError::bad(param, value, "a convex polygon"))?;
                if vp.polygon.len() < 3 || !vp.polygon.is_convex() {
                    return Err(ParamError::bad(param, value, "a convex polygon"));
                }
                self.polygons.push(vp.polygon.clone());
                self.view = Some(vp);
                self.hints_applied = false;
            }
            "max_depth" => self.max_depth = Self::nonneg(param, v)?,
            "min_altitude" => self.min_altitude = Self::nonneg(param, v)?,
            "max_time" => self.max_time = Self::nonneg(param, v)?,
            "trigger_entry_time" => {
                self.trigger_entry_time = Self::nonneg(param, v)?;
                if self.trigger_entry_time > 0.0 {
                    self.trigger_on_entry = true;
                }
            }
            "trigger_exit_time" => self.trigger_exit_time = Self::nonneg(param, v)?,
            "breached_poly_flag"
            | "breached_time_flag"
            | "breached_altitude_flag"
            | "breached_depth_flag" => {
                let which = match param {
                    "breached_poly_flag" => Breach::Poly,
                    "breached_time_flag" => Breach::Time,
                    "breached_altitude_flag" => Breach::Altitude,
                    _ => Breach::Depth,
                };
                let f = Flag::parse(v).ok_or_else(|| ParamError::bad(param, value, "VAR=value"))?;
                self.flags[which.index()].push(f);
            }
            "soft_poly_breach" => self.soft_poly_breach = boolean(param, v)?,
            "reset_var" => self.reset_var = no_white(v)?,
            "time_remaining_var" => self.time_remaining_var = no_white(v)?,
            "opregion_poly_var" => {
                self.poly_var = no_white(v)?;
            }
            "visual_hints" => {
                use crate::hints::{color, pairs, size};
                self.hints_applied = false;
                for (k, val) in pairs(v) {
                    let size = size(val).filter(|d| *d >= 0.0);
                    match (k.as_str(), color(val), size) {
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

    // As MOOS: the polygon goes to `opregion_poly_var` once configured (the helm posts it
    // on its first iteration) and after each update (filtered when unchanged).
    fn on_set_param_complete(&mut self, _ctx: &Ctx<'_>, out: &mut Out) {
        self.post_poly_var(out);
    }

    fn on_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.check_reset(ctx);
        self.post_time_remaining(out);
        self.post_view(ctx, out, false);
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        self.check_reset(ctx);
        self.set_time_stamps(ctx.info.now());

        // 1. Polygon containment.
        if !self.polygons.is_empty() {
            match (ctx.info.num("NAV_X"), ctx.info.num("NAV_Y")) {
                (Some(x), Some(y)) => {
                    if self.polygon_breached(x, y) {
                        self.post_breach_flags(Breach::Poly, out);
                        let mut msg = String::from("BHV_OpRegion Polygon containment failure:  x=");
                        fixed(&mut msg, x, 1);
                        msg.push_str(" y=");
                        fixed(&mut msg, y, 1);
                        if self.soft_poly_breach {
                            out.post_key("MOOS_MANUAL_OVERRIDE", "true", PostKey::Repeatable);
                            out.warning(ctx.name, &format!("Soft polygon breach: {msg}"));
                        } else {
                            Self::error(out, msg);
                        }
                    }
                }
                _ => Self::error(out, "No ownship info in info_buffer".into()),
            }
        }
        self.post_poly_status(ctx, out);

        // 2. Depth.
        if self.max_depth > 0.0 {
            match ctx.info.num("NAV_DEPTH") {
                None => Self::error(out, "No ownship depth in info_buffer.".into()),
                Some(d) if d > self.max_depth => {
                    self.post_breach_flags(Breach::Depth, out);
                    let mut msg = String::from("OpRegion Depth failure: max:");
                    fixed(&mut msg, self.max_depth, 5);
                    msg.push_str(" detected:");
                    fixed(&mut msg, d, 5);
                    Self::error(out, msg);
                }
                Some(_) => {}
            }
        }

        // 3. Altitude.
        if self.min_altitude > 0.0 {
            match ctx.info.num("NAV_ALTITUDE") {
                None => Self::error(out, "No ownship altitude in info_buffer.".into()),
                Some(a) if a < self.min_altitude => {
                    self.post_breach_flags(Breach::Altitude, out);
                    let mut msg = String::from("OpRegion Altitude failure: Min-Altitude:");
                    fixed(&mut msg, self.min_altitude, 5);
                    msg.push_str("  Detected Altitude: ");
                    fixed(&mut msg, a, 5);
                    Self::error(out, msg);
                }
                Some(_) => {}
            }
        }

        // 4. Time.
        if self.max_time > 0.0 && self.elapsed > self.max_time {
            self.post_breach_flags(Breach::Time, out);
            let mut msg = String::from("OpRegion timeout failure: MaxTime:");
            fixed(&mut msg, self.max_time, 5);
            msg.push_str("  Elapsed Time: ");
            fixed(&mut msg, self.elapsed, 5);
            Self::error(out, msg);
        }

        self.post_time_remaining(out);
        out.post("SECS_IN_POLY", self.secs_in);
        self.post_view(ctx, out, true);
        None
    }
}
