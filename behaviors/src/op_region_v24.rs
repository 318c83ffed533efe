//! BHV_OpRegionV24 (MOOS-IvP a2a9b716, `lib_behaviors-marine/BHV_OpRegionV24.cpp`): the
//! operating region with a *halt* polygon that stops the vehicle and a *save* polygon that
//! steers it back in.
//!
//! Every running iteration, in this order:
//! 1. **Halt checks**, each an error (`BHV_ERROR`, the helm all-stops) after posting its
//!    breach flags: `NAV_DEPTH > max_depth` (0 = off; no `NAV_DEPTH` is an error too),
//!    `NAV_ALTITUDE < min_altitude` (0 = off), seconds since the start `> max_time` (0 = off),
//!    and the halt polygon. The halt polygon counts as left only after `trigger_exit_time`
//!    seconds outside (default 0.5) and, with `trigger_on_poly_entry` (default true), only once
//!    the vehicle has been inside it for `trigger_entry_time` seconds (default 1). A halt
//!    breach also draws a red status circle (`draw_halt_status`).
//! 2. **Save polygon**: inside it nothing is asked (a grey circle is erased). Outside it,
//!    having once been inside, the `save_flag`s post once per excursion and the `savex_flag`s
//!    every iteration, a yellow status circle is drawn (`draw_save_status`), and the behaviour
//!    builds a course-speed function toward the polygon: course utility 100 for the heading
//!    that reaches the polygon soonest, 0 for the farthest and for headings that miss it
//!    (ZAIC_Vector over the domain's headings); when no heading reaches it, the turn is
//!    committed to one side (`COMMITTED = left|right`) until one does; speed peaks at
//!    `recover_spd` (0.8 m/s). The course/speed weights cycle with the helm iteration (95/5,
//!    80/20, 50/50, 20/80, 5/95).
//!
//! `save_dist` / `halt_dist` (>= 0) derive the save / halt polygon from `core_poly` grown by
//! that distance (corners rounded every 15 degrees); 0 copies the core polygon. With
//! `dynamic_region_var`, a posting of a polygon there replaces the core polygon.
//! `reset = true` (as an update) restarts the clock and the entry/exit bookkeeping.
//!
//! Macros in its flags: `CORE_POLY`, `SAVE_POLY`, `HALT_POLY` (specs), `SAVE_DIST`,
//! `HALT_DIST`, `SECS_IN_HALT_POLY`, `SECS_OUT_HALT_POLY`, `SECS_OUT_SAVE_POLY`, `TIME_LEFT`
//! (with `max_time`), `DEPTH_LEFT` (with `max_depth`), `ALT_LEFT` (with `min_altitude`),
//! `DIST_TO_CORE|SAVE|HALT`, `TRAJ_DIST_TO_CORE|SAVE|HALT`, `ETA_TO_…` and `TRAJ_ETA_TO_…`
//! (distance over the domain's top speed). As in the C++, `TRAJ_DIST_TO_CORE` gives the plain
//! distance to the core polygon.
//!
//! Differences from the C++, deliberate: the clock for `max_time` starts at the behaviour's
//! first iteration when the helm had no time at configuration (pHelmIvP: the helm's start,
//! which precedes it by the helm's first second); colour names in `visual_hints` are not
//! checked against MOOS's colour table; a grown polygon that is not convex is refused (the
//! C++ first tries to repair it).
//!
//! # Conformance with BHV_OpRegionV24 (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | core_poly | | polygon | none | convex (`setPolyOnString`), label `core<us>` | yes | done |
//! | save_poly | | polygon | none | convex, label `save<us>` | yes | done |
//! | halt_poly | | polygon | none | convex, label `halt<us>` | yes | done |
//! | save_dist | | m | −1 (off) | number >= 0 | yes | done |
//! | halt_dist | | m | −1 (off) | number >= 0 | yes | done |
//! | max_depth | | m | 0 (off) | number >= 0 | yes | done |
//! | min_altitude | | m | 0 (off) | number >= 0 | yes | done |
//! | max_time | | s | 0 (off) | number >= 0 | yes | done |
//! | recover_spd | recover_speed | m/s | 0.8 | number > 0 | yes | done |
//! | reset | | bool | | only `true` (any case) | yes | done |
//! | trigger_on_poly_entry | | bool | true | MOOS boolean | yes | done |
//! | trigger_entry_time | | s | 1 | number >= 0 | yes | done |
//! | trigger_exit_time | | s | 0.5 | number >= 0 | yes | done |
//! | breached_poly_flag | | flag | | `VAR=VALUE` | yes | done |
//! | breached_time_flag | | flag | | `VAR=VALUE` | yes | done |
//! | breached_altitude_flag | | flag | | `VAR=VALUE` | yes | done |
//! | breached_depth_flag | | flag | | `VAR=VALUE` | yes | done |
//! | save_flag | | flag | | `VAR=VALUE` | yes | done |
//! | savex_flag | | flag | | `VAR=VALUE` | yes | done |
//! | draw_save_status | | bool | true | MOOS boolean | yes | done |
//! | draw_halt_status | | bool | true | MOOS boolean | yes | done |
//! | visual_hints | | hints | see below | `key=value,...`; sizes numbers, colours names | yes | done |
//! | dynamic_region_var | | var | none | no white space; subscribed | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | VIEW_POLYGON | config, each save-recovery iteration: core (+ save, halt when grown) | `get_spec(3)` with hints | done |
//! | VIEW_POLYGON | run→idle | `pts={0,0:9,0:0,9},active=false,label=...` for each polygon | done |
//! | VIEW_POLYGON | inside the save polygon | status circle erased (`<us>_stat`) | done |
//! | VIEW_POLYGON | outside the save polygon | status circle r=4, 12 pts, duration 2, save_status hints | done |
//! | VIEW_POLYGON | halt breach | status circle r=4, 8 pts, halt_status hints | done |
//! | COMMITTED | each recovery iteration (repeatable) | `none`, `left` or `right` | done |
//! | BHV_ERROR | a halt breach | `OpRegion Depth failure`, `OpRegion Altitude failure`, `OpRegion timeout failure`, `OpRegion HaltPoly Failure`, `No ownship depth in info_buffer.`, `No ownship altitude in info_buffer.` | done |
//!
//! | macro | meaning | coug |
//! |---|---|---|
//! | CORE_POLY, SAVE_POLY, HALT_POLY | polygon specs | done |
//! | SAVE_DIST, HALT_DIST | configured distances | done |
//! | SECS_IN_HALT_POLY, SECS_OUT_HALT_POLY, SECS_OUT_SAVE_POLY | timers | done |
//! | TIME_LEFT, DEPTH_LEFT, ALT_LEFT | remaining margins (whole metres for depth/altitude) | done |
//! | DIST_TO_*, TRAJ_DIST_TO_*, ETA_TO_*, TRAJ_ETA_TO_* | distances and times to CORE/SAVE/HALT | done |

use geometry::pattern::Radial;
use geometry::spec::parse_polygon;
use geometry::{Polygon, ViewPolygon};
use ivp::{IvpFunction, ZaicPeak, ZaicVector, couple_weighted};

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_flag_vars, add_vars};
use crate::color::Hints;
use crate::common::{Common, Flag};
use crate::fmt::compact;
use crate::param::{moos_boolean, number};

/// The drawing defaults of the C++ constructor (MOOS `HintHolder`): general keys, and
/// per-polygon prefixes (`core_edge_color`) that take precedence.
fn default_hints() -> Hints {
    let mut h = Hints::default();
    h.set_measure("vertex_size", "0");
    h.set_measure("edge_size", "1");
    for (k, v) in [
        ("vertex_color", "gray50"),
        ("edge_color", "gray50"),
        ("label_color", "off"),
        ("core_edge_color", "gray30"),
        ("save_edge_color", "gray50"),
        ("halt_edge_color", "pink"),
        ("save_status_edge_color", "yellow"),
        ("halt_status_edge_color", "red"),
    ] {
        h.set_color(k, v);
    }
    h
}

/// Applies the hints under `prefix` to a polygon (MOOS `applyHints` for an `XYPolygon`).
fn apply_hints(h: &Hints, v: &mut ViewPolygon, prefix: &str) {
    h.apply(&mut v.attrs, prefix, true, true);
}

/// The breach and save flag lists.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Flags {
    Poly,
    Time,
    Altitude,
    Depth,
    Save,
    Savex,
}

/// BHV_OpRegionV24; see the module docs.
#[derive(Debug, Clone)]
pub struct OpRegionV24 {
    max_depth: f64,
    min_alt: f64,
    max_time: f64,
    core: ViewPolygon,
    save: ViewPolygon,
    halt: ViewPolygon,
    save_dist: f64,
    halt_dist: f64,
    draw_save_status: bool,
    draw_halt_status: bool,
    trigger_entry_time: f64,
    trigger_exit_time: f64,
    trigger_on_poly_entry: bool,
    dynamic_region_var: String,
    recover_spd: f64,
    flags: [Vec<Flag>; 6],
    save_flags_posted: bool,
    halt_entry_made: bool,
    secs_in_halt: f64,
    secs_out_halt: f64,
    time_entered_halt: f64,
    time_exited_halt: f64,
    save_entry_made: bool,
    secs_out_save: f64,
    time_exited_save: f64,
    start_time: f64,
    hints: Hints,
    committed_turn: &'static str,
    helm_iter: u64,
    // Ownship and time as of the last running iteration (for the macros).
    now: f64,
    osx: f64,
    osy: f64,
    osh: f64,
    depth: f64,
    altitude: f64,
    max_osv: f64,
}

impl Default for OpRegionV24 {
    fn default() -> Self {
        Self::new()
    }
}

fn empty_poly() -> ViewPolygon {
    ViewPolygon::new(Polygon::default())
}

impl OpRegionV24 {
    /// The C++ defaults (every limit off, no polygons).
    pub fn new() -> Self {
        OpRegionV24 {
            max_depth: 0.0,
            min_alt: 0.0,
            max_time: 0.0,
            core: empty_poly(),
            save: empty_poly(),
            halt: empty_poly(),
            save_dist: -1.0,
            halt_dist: -1.0,
            draw_save_status: true,
            draw_halt_status: true,
            trigger_entry_time: 1.0,
            trigger_exit_time: 0.5,
            trigger_on_poly_entry: true,
            dynamic_region_var: String::new(),
            recover_spd: 0.8,
            flags: Default::default(),
            save_flags_posted: false,
            halt_entry_made: false,
            secs_in_halt: 0.0,
            secs_out_halt: 0.0,
            time_entered_halt: 0.0,
            time_exited_halt: 0.0,
            save_entry_made: false,
            secs_out_save: 0.0,
            time_exited_save: 0.0,
            start_time: 0.0,
            hints: default_hints(),
            committed_turn: "none",
            helm_iter: 0,
            now: 0.0,
            osx: 0.0,
            osy: 0.0,
            osh: 0.0,
            depth: 0.0,
            altitude: 0.0,
            max_osv: 0.0,
        }
    }

    /// The save polygon in force (after `save_dist` is applied).
    pub fn save_polygon(&self) -> &Polygon {
        &self.save.polygon
    }

    /// The halt polygon in force (after `halt_dist` is applied).
    pub fn halt_polygon(&self) -> &Polygon {
        &self.halt.polygon
    }

    /// The turn the recovery is committed to: `none`, `left` or `right`.
    pub fn committed_turn(&self) -> &'static str {
        self.committed_turn
    }

    fn flag_list(&mut self, which: Flags) -> &mut Vec<Flag> {
        &mut self.flags[which as usize]
    }

    fn post_flags(&self, which: Flags, out: &mut Out) {
        for f in &self.flags[which as usize] {
            out.flag(f, false);
        }
    }

    /// MOOS `updateRegionPolys`: derive the save and halt polygons from the core one.
    fn update_region_polys(&mut self, ownship: &str) {
        if (self.save_dist >= 0.0 || self.halt_dist >= 0.0) && !self.core.polygon.is_convex() {
            return;
        }
        let grow = |core: &ViewPolygon, dist: f64, label: String| -> Option<ViewPolygon> {
            if dist == 0.0 {
                return Some(core.clone());
            }
            let p = core.polygon.buffered(dist, 15.0)?;
            let mut v = ViewPolygon::new(p);
            v.attrs.label = label;
            Some(v)
        };
        if self.save_dist >= 0.0
            && let Some(v) = grow(&self.core, self.save_dist, format!("opreg_save_{ownship}"))
        {
            self.save = v;
        }
        if self.halt_dist >= 0.0
            && let Some(v) = grow(&self.core, self.halt_dist, format!("opreg_halt_{ownship}"))
        {
            self.halt = v;
        }
    }

    fn post_viewable(&self, out: &mut Out) {
        let mut post = |v: &ViewPolygon, prefix: &str| {
            let mut v = v.clone();
            apply_hints(&self.hints, &mut v, prefix);
            v.precision = 3;
            out.post("VIEW_POLYGON", v.to_spec());
        };
        post(&self.core, "core");
        if self.save_dist > 0.0 {
            post(&self.save, "save");
        }
        if self.halt_dist > 0.0 {
            post(&self.halt, "halt");
        }
    }

    fn post_erasable(&self, out: &mut Out) {
        for v in [&self.core, &self.save, &self.halt] {
            out.post("VIEW_POLYGON", inactive_spec(&v.attrs.label));
        }
    }

    /// The small circle drawn about ownship to show a status.
    fn status_circle(&self, ctx: &Ctx<'_>, pts: u32) -> ViewPolygon {
        let r = Radial {
            x: self.osx,
            y: self.osy,
            z: 0.0,
            radius: 4.0,
            pts,
            snap: 0.0,
        };
        let mut v = ViewPolygon::new(Polygon::new(r.vertices().unwrap_or_default()));
        v.attrs.label = format!("{}_stat", ctx.ownship);
        v
    }

    /// MOOS `haltPolyVerify`: true when the vehicle counts as inside.
    fn halt_poly_ok(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        let now = self.now;
        let contained = self.halt.polygon.contains(self.osx, self.osy);
        if contained {
            if self.time_entered_halt == 0.0 {
                self.time_entered_halt = now;
            }
            self.secs_in_halt = now - self.time_entered_halt;
            if self.secs_in_halt >= self.trigger_entry_time {
                self.halt_entry_made = true;
            }
            self.time_exited_halt = 0.0;
            self.secs_out_halt = 0.0;
            return true;
        }
        if self.time_exited_halt == 0.0 {
            self.time_exited_halt = now;
        }
        self.secs_out_halt = now - self.time_exited_halt;
        self.time_entered_halt = 0.0;
        self.secs_in_halt = 0.0;
        let grace = self.secs_out_halt < self.trigger_exit_time;
        if !self.trigger_on_poly_entry && grace {
            return true;
        }
        if self.trigger_on_poly_entry && (!self.halt_entry_made || grace) {
            return true;
        }
        if self.draw_halt_status {
            let mut v = self.status_circle(ctx, 8);
            apply_hints(&self.hints, &mut v, "halt_status");
            out.post("VIEW_POLYGON", v.to_spec());
        }
        self.post_flags(Flags::Poly, out);
        out.error("OpRegion HaltPoly Failure");
        false
    }

    /// MOOS `updateRangeCache` + `determineInitialTurn` + the function of `buildOF`.
    fn recovery_function(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let var = ["course", "heading"]
            .into_iter()
            .find(|v| ctx.domain.get(v).is_some())?;
        let dv = ctx.domain.get(var)?;
        let headings: Vec<f64> = (0..dv.points()).map(|i| dv.value(i)).collect();
        let ranges: Vec<f64> = headings
            .iter()
            .map(|h| {
                self.save
                    .polygon
                    .ray_distance(self.osx, self.osy, *h)
                    .unwrap_or(-1.0)
            })
            .collect();
        let reaching = ranges.iter().filter(|r| **r != -1.0);
        let closest = reaching.clone().fold(f64::INFINITY, |a, b| a.min(*b));
        let farthest = reaching.fold(f64::NEG_INFINITY, |a, b| a.max(*b));
        let mut norm = vec![0.0; headings.len()];
        if closest.is_finite() && closest < farthest {
            for (n, r) in norm.iter_mut().zip(&ranges) {
                if *r != -1.0 {
                    *n = 100.0 * (farthest - r) / (farthest - closest);
                }
            }
        }
        // Heading toward the polygon now: no committed turn; otherwise keep (or pick) one.
        if self
            .save
            .polygon
            .ray_distance(self.osx, self.osy, self.osh)
            .is_some()
        {
            self.committed_turn = "none";
        } else if self.committed_turn == "none" {
            self.committed_turn = self.initial_turn(&headings, &ranges);
        }
        out.post_key(
            "COMMITTED",
            self.committed_turn,
            crate::behavior::PostKey::Repeatable,
        );
        let port = |h: f64| geometry::angle_360(h - self.osh) > 180.0;
        let utils: Vec<f64> = match self.committed_turn {
            "left" => headings
                .iter()
                .zip(&norm)
                .map(|(h, n)| if port(*h) { *n } else { 0.0 })
                .collect(),
            "right" => headings
                .iter()
                .zip(&norm)
                .map(|(h, n)| if port(*h) { 0.0 } else { *n })
                .collect(),
            _ => norm,
        };
        let hdg = ZaicVector::new(ctx.domain, var, &headings, &utils)
            .and_then(|z| z.extract())
            .ok()?;
        let mut spd = ZaicPeak::new(ctx.domain, "speed").ok()?;
        spd.set_params(
            self.recover_spd,
            self.recover_spd / 2.0,
            0.2,
            20.0,
            0.0,
            100.0,
        )
        .ok()?;
        let spd = spd.extract().ok()?;
        let (wc, ws) = match self.helm_iter % 5 {
            0 => (95.0, 5.0),
            1 => (80.0, 20.0),
            2 => (50.0, 50.0),
            3 => (20.0, 80.0),
            _ => (5.0, 95.0),
        };
        match couple_weighted(&hdg, &spd, wc, ws, true) {
            Ok(f) => Some(f),
            Err(_) => {
                out.warning(ctx.name, "Failure on the CRS_SPD COUPLER");
                None
            }
        }
    }

    /// Of the headings that reach the polygon, the one nearest ownship's heading: a right or
    /// a left turn toward it.
    fn initial_turn(&self, headings: &[f64], ranges: &[f64]) -> &'static str {
        let mut best: Option<(f64, f64)> = None;
        for (h, r) in headings.iter().zip(ranges) {
            if *r == -1.0 {
                continue;
            }
            let d = geometry::angle::angle_diff(self.osh, *h);
            if best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, *h));
            }
        }
        let hdg = best.map_or(0.0, |b| b.1);
        let osh = self.osh;
        if osh < hdg {
            if hdg - osh < 180.0 { "right" } else { "left" }
        } else if osh - hdg < 180.0 {
            "left"
        } else {
            "right"
        }
    }

    fn reset(&mut self) {
        self.start_time = 0.0;
        self.secs_in_halt = 0.0;
        self.secs_out_halt = 0.0;
        self.time_entered_halt = 0.0;
        self.time_exited_halt = 0.0;
        self.secs_out_save = 0.0;
        self.time_exited_save = 0.0;
        self.halt_entry_made = false;
        self.save_entry_made = false;
    }

    fn note_time(&mut self, now: f64) {
        self.now = now;
        if self.start_time == 0.0 {
            self.start_time = now;
        }
    }
}

/// The MOOS `get_spec_inactive` of a polygon: a placeholder triangle, inactive, same label.
fn inactive_spec(label: &str) -> String {
    let mut s = String::from("pts={0,0:9,0:0,9},active=false");
    if !label.is_empty() {
        s.push_str(",label=");
        s.push_str(label);
    }
    s
}

fn nonneg(param: &str, value: &str) -> Result<f64, ParamError> {
    let d = number(param, value)?;
    if d < 0.0 {
        return Err(ParamError::bad(param, value, "a number >= 0"));
    }
    Ok(d)
}

impl Behavior for OpRegionV24 {
    fn kind(&self) -> &'static str {
        "BHV_OpRegionV24"
    }

    fn default_name(&self) -> &'static str {
        "opregx"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course", "speed"]
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
                self.dynamic_region_var.as_str(),
            ],
        );
        for f in &self.flags {
            add_flag_vars(out, f);
        }
    }

    fn set_helm_iteration(&mut self, iteration: u64) {
        self.helm_iter = iteration;
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        let v = value.trim();
        let poly = |kind: &str| -> Result<ViewPolygon, ParamError> {
            let p =
                parse_polygon(v).map_err(|_| ParamError::bad(param, value, "a convex polygon"))?;
            if !p.polygon.is_convex() {
                return Err(ParamError::bad(param, value, "a convex polygon"));
            }
            let mut out = ViewPolygon::new(p.polygon);
            out.attrs.label = format!("{kind}{}", ctx.ownship);
            Ok(out)
        };
        let flag =
            |v: &str| Flag::parse(v).ok_or_else(|| ParamError::bad(param, value, "VAR=value"));
        match param {
            "core_poly" => self.core = poly("core")?,
            "save_poly" => self.save = poly("save")?,
            "halt_poly" => self.halt = poly("halt")?,
            "save_dist" => self.save_dist = nonneg(param, v)?,
            "halt_dist" => self.halt_dist = nonneg(param, v)?,
            "max_depth" => self.max_depth = nonneg(param, v)?,
            "min_altitude" => self.min_alt = nonneg(param, v)?,
            "max_time" => self.max_time = nonneg(param, v)?,
            "recover_spd" | "recover_speed" => {
                let d = number(param, v)?;
                if d <= 0.0 {
                    return Err(ParamError::bad(param, value, "a number > 0"));
                }
                self.recover_spd = d;
            }
            "reset" => {
                if !v.eq_ignore_ascii_case("true") {
                    return Err(ParamError::bad(param, value, "true"));
                }
                self.reset();
            }
            "trigger_on_poly_entry" => {
                self.trigger_on_poly_entry = moos_boolean(param, v, self.trigger_on_poly_entry)?
            }
            "trigger_entry_time" => self.trigger_entry_time = nonneg(param, v)?,
            "trigger_exit_time" => self.trigger_exit_time = nonneg(param, v)?,
            "breached_poly_flag" => self.flag_list(Flags::Poly).push(flag(v)?),
            "breached_time_flag" => self.flag_list(Flags::Time).push(flag(v)?),
            "breached_altitude_flag" => self.flag_list(Flags::Altitude).push(flag(v)?),
            "breached_depth_flag" => self.flag_list(Flags::Depth).push(flag(v)?),
            "save_flag" => self.flag_list(Flags::Save).push(flag(v)?),
            "savex_flag" => self.flag_list(Flags::Savex).push(flag(v)?),
            "draw_save_status" => {
                self.draw_save_status = moos_boolean(param, v, self.draw_save_status)?
            }
            "draw_halt_status" => {
                self.draw_halt_status = moos_boolean(param, v, self.draw_halt_status)?
            }
            "visual_hints" => {
                if !self.hints.set_hints(v) {
                    return Err(ParamError::bad(param, value, "key=value hints"));
                }
            }
            "dynamic_region_var" => {
                if v.is_empty() || v.contains(char::is_whitespace) {
                    return Err(ParamError::bad(param, value, "a variable name"));
                }
                self.dynamic_region_var = v.to_string();
            }
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn on_set_param_complete(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.update_region_polys(ctx.ownship);
        let now = ctx.info.now();
        if self.start_time == 0.0 {
            self.start_time = now;
        }
        self.post_viewable(out);
    }

    fn on_run_to_idle(&mut self, _ctx: &Ctx<'_>, out: &mut Out) {
        self.post_erasable(out);
    }

    fn on_idle_to_run(&mut self, _ctx: &Ctx<'_>, out: &mut Out) {
        self.post_viewable(out);
    }

    fn on_idle(&mut self, ctx: &Ctx<'_>, _out: &mut Out) {
        self.note_time(ctx.info.now());
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let info = ctx.info;
        self.note_time(info.now());
        let (Some(x), Some(y)) = (info.num("NAV_X"), info.num("NAV_Y")) else {
            out.error("No ownship X/Y info in info_buffer.");
            return None;
        };
        let Some(h) = info.num("NAV_HEADING") else {
            out.error("No ownship heading info in info_buffer.");
            return None;
        };
        (self.osx, self.osy, self.osh) = (x, y, geometry::angle_360(h));
        self.max_osv = ctx.domain.get("speed").map_or(0.0, |d| d.high());
        // A new core polygon posted to the dynamic region variable.
        if !self.dynamic_region_var.is_empty() && info.is_fresh(&self.dynamic_region_var) {
            let text = info
                .text(&self.dynamic_region_var)
                .unwrap_or_default()
                .to_string();
            let parsed = parse_polygon(&text).ok().filter(|p| p.polygon.is_convex());
            if let Some(p) = &parsed {
                let mut v = ViewPolygon::new(p.polygon.clone());
                v.attrs.label = format!("core{}", ctx.ownship);
                self.core = v;
            }
            self.on_set_param_complete(ctx, out);
            // A bad polygon: this iteration asks nothing (as the C++).
            parsed.as_ref()?;
        }
        // Part 1: halt checks (each posts its error; the helm all-stops).
        let ok_dep = if self.max_depth <= 0.0 {
            true
        } else {
            match info.num("NAV_DEPTH") {
                None => {
                    out.error("No ownship depth in info_buffer.");
                    false
                }
                Some(d) => {
                    self.depth = d;
                    if d > self.max_depth {
                        self.post_flags(Flags::Depth, out);
                        out.error("OpRegion Depth failure");
                        false
                    } else {
                        true
                    }
                }
            }
        };
        let ok_alt = if self.min_alt <= 0.0 {
            true
        } else {
            match info.num("NAV_ALTITUDE") {
                None => {
                    out.error("No ownship altitude in info_buffer.");
                    false
                }
                Some(a) => {
                    self.altitude = a;
                    if a < self.min_alt {
                        self.post_flags(Flags::Altitude, out);
                        out.error("OpRegion Altitude failure");
                        false
                    } else {
                        true
                    }
                }
            }
        };
        let ok_time = if self.max_time <= 0.0 || self.now - self.start_time <= self.max_time {
            true
        } else {
            self.post_flags(Flags::Time, out);
            out.error("OpRegion timeout failure");
            false
        };
        let ok_poly = self.halt_poly_ok(ctx, out);
        if !(ok_dep && ok_alt && ok_time && ok_poly) {
            return None;
        }
        // Part 2: inside the save polygon, nothing to do.
        if self.save.polygon.contains(x, y) {
            self.committed_turn = "none";
            self.save_flags_posted = false;
            self.secs_out_save = 0.0;
            self.save_entry_made = true;
            out.post(
                "VIEW_POLYGON",
                inactive_spec(&format!("{}_stat", ctx.ownship)),
            );
            return None;
        }
        if !self.save_entry_made {
            return None;
        }
        // Part 3: outside, having been inside: steer back in.
        if !self.save_flags_posted {
            self.save_flags_posted = true;
            self.time_exited_save = self.now;
            self.post_flags(Flags::Save, out);
        }
        self.secs_out_save = self.now - self.time_exited_save;
        self.post_flags(Flags::Savex, out);
        if self.draw_save_status {
            let mut v = self.status_circle(ctx, 12);
            v.attrs.duration = Some(2.0);
            apply_hints(&self.hints, &mut v, "save_status");
            out.post("VIEW_POLYGON", v.to_spec());
        }
        let f = self.recovery_function(ctx, out);
        self.post_viewable(out);
        f
    }

    fn macro_value(&self, name: &str, out: &mut String) -> bool {
        let num = |out: &mut String, v: f64| compact(out, v, 3);
        let dist = |p: &Polygon| p.dist_to_boundary(self.osx, self.osy).unwrap_or(-1.0);
        let traj = |p: &Polygon| p.ray_distance(self.osx, self.osy, self.osh).unwrap_or(-1.0);
        let poly = |v: &ViewPolygon| v.to_spec();
        match name {
            "CORE_POLY" => out.push_str(&poly(&self.core)),
            "SAVE_POLY" => out.push_str(&poly(&self.save)),
            "HALT_POLY" => out.push_str(&poly(&self.halt)),
            "SAVE_DIST" => num(out, self.save_dist),
            "HALT_DIST" => num(out, self.halt_dist),
            "SECS_IN_HALT_POLY" => num(out, self.secs_in_halt),
            "SECS_OUT_HALT_POLY" => num(out, self.secs_out_halt),
            "SECS_OUT_SAVE_POLY" => num(out, self.secs_out_save),
            "TIME_LEFT" if self.max_time > 0.0 => {
                num(out, (self.max_time - (self.now - self.start_time)).max(0.0))
            }
            "DEPTH_LEFT" if self.max_depth > 0.0 => {
                num(out, (self.max_depth - self.depth).max(0.0).trunc())
            }
            "ALT_LEFT" if self.min_alt > 0.0 => {
                num(out, (self.altitude - self.min_alt).max(0.0).trunc())
            }
            "DIST_TO_CORE" | "TRAJ_DIST_TO_CORE" => num(out, dist(&self.core.polygon)),
            "DIST_TO_SAVE" => num(out, dist(&self.save.polygon)),
            "DIST_TO_HALT" => num(out, dist(&self.halt.polygon)),
            "TRAJ_DIST_TO_SAVE" => num(out, traj(&self.save.polygon)),
            "TRAJ_DIST_TO_HALT" => num(out, traj(&self.halt.polygon)),
            "ETA_TO_CORE" if self.max_osv > 0.0 => {
                num(out, dist(&self.core.polygon) / self.max_osv)
            }
            "ETA_TO_SAVE" if self.max_osv > 0.0 => {
                num(out, dist(&self.save.polygon) / self.max_osv)
            }
            "ETA_TO_HALT" if self.max_osv > 0.0 => {
                num(out, dist(&self.halt.polygon) / self.max_osv)
            }
            "TRAJ_ETA_TO_CORE" if self.max_osv > 0.0 => {
                num(out, traj(&self.core.polygon) / self.max_osv)
            }
            "TRAJ_ETA_TO_SAVE" if self.max_osv > 0.0 => {
                num(out, traj(&self.save.polygon) / self.max_osv)
            }
            "TRAJ_ETA_TO_HALT" if self.max_osv > 0.0 => {
                num(out, traj(&self.halt.polygon) / self.max_osv)
            }
            _ => return false,
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inactive_spec_is_the_moos_placeholder() {
        assert_eq!(
            inactive_spec("coreabe"),
            "pts={0,0:9,0:0,9},active=false,label=coreabe"
        );
    }

    #[test]
    fn hints_fall_back_from_prefix_to_general() {
        let mut h = default_hints();
        assert!(h.set_hints("edge_size=2, lcolor=white"));
        assert!(!h.set_hints("vertex_size=big"));
        let mut v = empty_poly();
        apply_hints(&h, &mut v, "core");
        assert_eq!(v.attrs.edge_color.as_deref(), Some("gray30"));
        assert_eq!(v.attrs.label_color.as_deref(), Some("white"));
        assert_eq!(v.attrs.edge_size, Some(2.0));
        assert_eq!(v.attrs.vertex_size, Some(0.0));
        let mut v = empty_poly();
        apply_hints(&h, &mut v, "halt_status");
        assert_eq!(v.attrs.edge_color.as_deref(), Some("red"));
    }

    #[test]
    fn initial_turn_toward_the_nearest_reaching_heading() {
        let mut b = OpRegionV24::new();
        b.osh = 350.0;
        // Only 20 reaches: a right turn through north.
        assert_eq!(b.initial_turn(&[20.0, 200.0], &[5.0, -1.0]), "right");
        b.osh = 90.0;
        assert_eq!(b.initial_turn(&[20.0, 200.0], &[5.0, -1.0]), "left");
    }
}
