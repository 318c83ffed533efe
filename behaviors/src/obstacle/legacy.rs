//! The obstacle behaviours MOOS-IvP keeps in `lib_dep_behaviors` (a2a9b716), each a class of
//! its own there and a type of its own here, over the shared [`super`] code:
//!
//! - [`AvoidObstacleX`] (`BHV_AvoidObstacleX`, `AOF_AvoidObstacleX`, the older
//!   `ObShipModel`), and its successor `BHV_AvoidObstacleV21` as the same type built with
//!   [`AvoidObstacleX::v21`]: V21 adds range and CPA flags, judges the model every
//!   iteration (idle too), sets the id once, drops the `resolved` parameter and posts its
//!   polygons with 5 decimals instead of 3. Neither has a breach all-stop or a side lock.
//! - [`AvoidObstacle`] (`BHV_AvoidObstacle`, `AOF_AvoidObstacle`): a buffer polygon
//!   (`buffer_dist`) and an all-or-nothing objective.
//!
//! None is an alias of another or of V24: each objective differs (see the types). Their
//! deprecation warnings (`i_understand_this_behavior_is_deprecated`) are read; coug's helm
//! does not post them (open).
//!
//! # `AOF_AvoidObstacleX` (X and V21)
//!
//! The older model adds to [`ShipModel`] the bearings bounding the obstacle and its outer
//! buffer (`max_util_cpa` out, corners every 10°), and the "basin" between the bearing to the
//! obstacle's centre and `θ_b` (90° beyond it on the passing side, or ownship's reciprocal
//! heading when that is nearer). For `(course c, speed v)`: 20 when `c` is in that basin; 100
//! when `c` misses the outer buffer's bearings; 20 when `c` is between the obstacle's bearings
//! and `v` is above the farther bounding vertex's distance over `allowable_ttc`; 100 when `v`
//! is below the outer buffer's distance (as an open path) over `allowable_ttc`; else, with
//! the ray's closest approach `d`: 100 for `d > max_util_cpa_dist`, 100 when the outer
//! buffer is more than `allowable_ttc` away at `v`, 0 for `d <= min_util_cpa_dist`, linear
//! between. Reflected in pieces of 3 courses × 2 speeds, normalised, weighted by
//! `relevance · pwt` (relevance: the linear range relevance, no heading discount).
//!
//! # Conformance with BHV_AvoidObstacleX / BHV_AvoidObstacleV21 (MOOS-IvP a2a9b716)
//!
//! | parameter | default | validation (C++ rule) | coug |
//! |---|---|---|---|
//! | polygon, poly | none | a convex polygon | done |
//! | allowable_ttc, min_util_cpa_dist, max_util_cpa_dist, pwt_inner_dist, pwt_outer_dist, completed_dist | 20, 8, 16, 10, 50, 50 | as BHV_AvoidObstacleV24 | done |
//! | resolved (X only) | false | boolean | done |
//! | id | none | no white space (V21: set once) | done |
//! | visual_hints | obstacle white/white/gray60 0.7, buffer_min gray60/dodger_blue/gray70 0.25, buffer_max gray60/dodger_blue/gray70 0.1, vertex sizes 1 | `obstacle_*`, `buffer_min_*`, `buffer_max_*` (`edge_color`, `vertex_color`, `vertex_size`, `fill_color`, `fill_transparency`); the C++ stops after the first colour or size of a list | done |
//! | use_refinery | false | boolean | done: the plateau and basin regions of the older `RefineryObAvoid` ([`super::refinery::legacy_regions`]) |
//! | rng_flag, cpa_flag (V21 only) | none | as BHV_AvoidObstacleV24 | done |
//! | i_understand_this_behavior_is_deprecated | false | boolean | read |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | OBM_ALERT_REQUEST | helm start, spawning template with `updates` | as V24 | done |
//! | NOTED_RESOLVED | `OBM_RESOLVED` posted | its value | done |
//! | OS_DIST_TO_POLY | each running iteration (V21: every iteration) | range | done |
//! | AVD_OB_SPAWN (X only) | spawned | the behaviour's name | done |
//! | VIEW_POLYGON (keys one, two, three) | with a function; erased when idle or complete | obstacle, `<label>_buff_min`, `<label>_buff_max` | done |
//! | BHV_SETTINGS | configuration, idle to running | `type=BHV_AvoidObstacleXs` (sic) / `type=BHV_AvoidObstacleV21`, then as V24 | done |
//!
//! # `BHV_AvoidObstacle`
//!
//! No function unless `buffer_dist > 0`, ownship is outside the obstacle, and the obstacle
//! grown by `buffer_dist` (or by the range less 2 m, when closer than `buffer_dist + 1`;
//! corners every 10°) is convex and does not hold ownship. Relevance: 0 when the obstacle is
//! wholly 20° abaft the beam or ownship touches it, 1 within `pwt_inner_dist`, 0 beyond
//! `pwt_outer_dist`, linear between. For `(course c, speed v)`: 0 when `c`'s ray meets the
//! buffer polygon and the range to it over `v` is within `allowable_ttc`; 0 when `c` puts the
//! obstacle's centre on the other side than ownship's heading does; else 100. Reflected in
//! 3 × 3 pieces, normalised, weighted by `relevance · pwt`. Completes beyond
//! `completed_dist`, posting `OBSTACLE_RESOLVED = <obstacle_key>`.
//!
//! | parameter | default | validation (C++ rule) | coug |
//! |---|---|---|---|
//! | polygon, points, poly | none | a convex polygon | done |
//! | allowable_ttc | 20 | number >= 0 | done |
//! | buffer_dist | 0 | number >= 0 | done |
//! | obstacle_key | none | no white space | done |
//! | pwt_outer_dist | 30 | number >= 0; inner lowered (error when set); completed raised to outer + 1 (refused when set) | done |
//! | pwt_inner_dist | 20 | number >= 0; outer raised (refused when set) | done |
//! | completed_dist | 75 | number >= 0; must exceed outer: raised to outer + 1 (error when outer set) | done |
//! | no_alert_request, resolved, i_understand_this_behavior_is_deprecated | false | boolean | done |
//! | visual_hints | obstacle white/dodger_blue/gray60 0.7, buffer gray60/dodger_blue/gray70 0.1 | `obstacle_*`, `buffer_*` (`edge_color`, `vertex_color`, `fill_color`, `fill_transparency`) | done |
//!
//! It has no `id` parameter: pObstacleMgr's alerts (which end `#id=<key>`) fail to spawn it,
//! in MOOS-IvP at a2a9b716 as here.

use ivp::{IvpFunction, Reflector};

use super::{
    ObstacleBase, RangeFlags, ShipModel, erase_ship_polygons, geom, idle_tail, non_neg,
    ship_config_status, ship_param, spec_inactive,
};
use crate::behavior::{Behavior, Ctx, Out, ParamError, PostKey, add_vars};
use crate::common::Common;
use crate::param::{atof, is_number, moos_boolean};

/// The course and speed of the helm's domain.
fn course_speed(ctx: &Ctx<'_>) -> Option<ivp::Domain> {
    let mut d = ivp::Domain::new();
    d.add(ctx.domain.get("course")?.clone()).ok()?;
    d.add(ctx.domain.get("speed")?.clone()).ok()?;
    Some(d)
}

/// `x` in the arc from `lo` to `hi` (wrapping through north when `lo > hi`).
fn in_arc(lo: f64, hi: f64, x: f64) -> bool {
    if lo <= hi {
        x >= lo && x <= hi
    } else {
        x >= lo || x <= hi
    }
}

/// The older `ObShipModel`: [`ShipModel`] with corners every 10° and the bearings its
/// objective reads.
#[derive(Debug, Clone)]
pub struct LegacyModel {
    /// The shared model.
    pub m: ShipModel,
    /// Bearings bounding the obstacle and the distances to their vertices.
    pub bng: (f64, f64, f64, f64),
    /// Bearings bounding the outer buffer and the distances to their vertices.
    pub cpa_bng: (f64, f64, f64, f64),
    /// The basin's far bound.
    pub theta_b: f64,
}

impl Default for LegacyModel {
    fn default() -> Self {
        let m = ShipModel {
            obuff_rdegs: 10.0,
            expand_failure: "Failed Expand:",
            ..ShipModel::default()
        };
        LegacyModel {
            m,
            bng: (0.0, 0.0, 0.0, 0.0),
            cpa_bng: (0.0, 0.0, 0.0, 0.0),
            theta_b: -1.0,
        }
    }
}

impl LegacyModel {
    /// Sets ownship and recomputes (MOOS `setPose`, then `updateDynamic`); false when the
    /// obstacle or its buffers are not convex.
    pub fn set_pose(&mut self, x: f64, y: f64, h: f64) -> bool {
        self.m.pose = Some((x, y, geometry::angle_360(h), 0.0));
        self.m.fresh = false;
        self.m.update();
        if !self.m.gut.is_convex() || !self.m.mid.is_convex() || !self.m.rim.is_convex() {
            return false;
        }
        let (osx, osy, osh, _) = self.m.pose.unwrap_or_default();
        if let Some(b) = geom::bearing_min_max_x(osx, osy, &self.m.gut) {
            self.bng = b;
        }
        if let Some(b) = geom::bearing_min_max_x(osx, osy, &self.m.rim) {
            self.cpa_bng = b;
        }
        let osh180 = geometry::angle_360(osh + 180.0);
        let b = self.m.obcent_bng;
        self.theta_b = match self.m.passing_side {
            "port" | "star" => {
                let w = geometry::angle_360(if self.m.passing_side == "port" {
                    b - 90.0
                } else {
                    b + 90.0
                });
                if geometry::angle::contains_angle(b, w, osh180) {
                    w
                } else {
                    osh180
                }
            }
            _ => -1.0,
        };
        true
    }

    /// MOOS `ObShipModel::isValid`.
    pub fn valid(&self) -> bool {
        let m = &self.m;
        m.pwt_outer_dist >= m.pwt_inner_dist
            && m.completed_dist >= m.pwt_outer_dist
            && m.max_util_cpa >= m.min_util_cpa
            && m.gut.is_convex()
            && m.mid.is_convex()
            && m.rim.is_convex()
            && m.pose.is_some()
    }

    /// The linear range relevance (no heading discount).
    pub fn range_relevance(&self) -> f64 {
        let m = &self.m;
        if m.pwt_outer_dist < m.pwt_inner_dist || m.range >= m.pwt_outer_dist {
            return 0.0;
        }
        if m.range <= m.pwt_inner_dist {
            return 1.0;
        }
        let d = m.pwt_outer_dist - m.pwt_inner_dist;
        if d <= 0.0 {
            return 0.0;
        }
        (m.pwt_outer_dist - m.range) / d
    }

    /// `AOF_AvoidObstacleX`'s utility of `(hdg, spd)`; see the module docs.
    pub fn eval(&self, hdg: f64, spd: f64) -> f64 {
        let m = &self.m;
        let (osx, osy, _, _) = m.pose.unwrap_or_default();
        let h = geometry::angle_360(hdg);
        let basin_major = match m.passing_side {
            "port" => in_arc(self.theta_b, m.obcent_bng, h),
            "star" => in_arc(m.obcent_bng, self.theta_b, h),
            _ => false,
        };
        if basin_major {
            return 20.0;
        }
        let (cmin, cmax) = (self.cpa_bng.0, self.cpa_bng.1);
        let plat_major = if cmin <= cmax {
            h < cmin || h > cmax
        } else {
            h < cmin && h > cmax
        };
        if plat_major {
            return 100.0;
        }
        if m.allowable_ttc > 0.0 {
            let smin = self.bng.2.max(self.bng.3) / m.allowable_ttc;
            if spd > smin && in_arc(self.bng.0, self.bng.1, hdg) {
                return 20.0;
            }
        }
        let minspd = geom::dist_to_open_path(&m.rim, osx, osy) / m.allowable_ttc;
        // Below the minimum speed (or not comparable with it, as the C++ `osv >= minspd`
        // test fails then too): 100.
        if spd.partial_cmp(&minspd).is_none_or(|o| o.is_lt()) {
            return 100.0;
        }
        let cpa = geom::ray_cpa(osx, osy, hdg, &m.gut);
        if cpa > m.max_util_cpa {
            return 100.0;
        }
        if geom::dist_to_poly(&m.rim, osx, osy) / spd > m.allowable_ttc {
            return 100.0;
        }
        if cpa <= m.min_util_cpa {
            return 0.0;
        }
        let range = m.max_util_cpa - m.min_util_cpa;
        if range <= 0.0 {
            return 0.0;
        }
        ((cpa - m.min_util_cpa) / range).clamp(0.0, 1.0) * 100.0
    }
}

/// The X family's display hints (its own fields, not a `HintHolder`).
#[derive(Debug, Clone)]
struct XHints {
    /// Per polygon (obstacle, buffer min, buffer max): edge, vertex, vertex size, fill,
    /// transparency.
    polys: [(String, String, f64, String, f64); 3],
}

impl Default for XHints {
    fn default() -> Self {
        let p = |e: &str, v: &str, f: &str, t: f64| (e.into(), v.into(), 1.0, f.into(), t);
        XHints {
            polys: [
                p("white", "white", "gray60", 0.7),
                p("gray60", "dodger_blue", "gray70", 0.25),
                p("gray60", "dodger_blue", "gray70", 0.1),
            ],
        }
    }
}

impl XHints {
    /// MOOS `handleParamVisualHints`: the first colour or size hint of the list decides the
    /// result; transparencies go on (the `buffer_min` one sets the outer buffer's).
    fn set(&mut self, spec: &str) -> bool {
        for piece in moos_types::text::parse_string_q(spec, ',') {
            let (k, v) = piece.split_once('=').unwrap_or((piece, ""));
            let (k, v) = (k.trim().to_ascii_lowercase(), v.trim());
            let (i, field) = if let Some(f) = k.strip_prefix("obstacle_") {
                (0, f)
            } else if let Some(f) = k.strip_prefix("buffer_min_") {
                (1, f)
            } else if let Some(f) = k.strip_prefix("buffer_max_") {
                (2, f)
            } else {
                return false;
            };
            let color = geometry::color::is_color(v);
            let p = &mut self.polys[i];
            match field {
                "edge_color" | "vertex_color" | "fill_color" => {
                    if color {
                        let slot = match field {
                            "edge_color" => &mut p.0,
                            "vertex_color" => &mut p.1,
                            _ => &mut p.3,
                        };
                        *slot = v.to_string();
                    }
                    return color;
                }
                "vertex_size" => {
                    let d = atof(v);
                    let ok = is_number(v) && d >= 0.0;
                    if ok {
                        p.2 = d;
                    }
                    return ok;
                }
                "fill_transparency" if is_number(v) => {
                    let t = atof(v).clamp(0.0, 1.0);
                    self.polys[if i == 1 { 2 } else { i }].4 = t;
                }
                _ => return false,
            }
        }
        true
    }
}

/// BHV_AvoidObstacleX, and BHV_AvoidObstacleV21 ([`AvoidObstacleX::v21`]).
#[derive(Debug, Clone)]
pub struct AvoidObstacleX {
    v21: bool,
    /// The obstacle, its id and resolution.
    pub base: ObstacleBase,
    /// Ownship and the obstacle.
    pub model: LegacyModel,
    use_refinery: bool,
    hide_deprecation: bool,
    hints: XHints,
    flags: RangeFlags,
    /// The relevance of the last running iteration.
    pub relevance: f64,
    valid: bool,
}

impl Default for AvoidObstacleX {
    fn default() -> Self {
        Self::new()
    }
}

impl AvoidObstacleX {
    /// BHV_AvoidObstacleX with MOOS-IvP's defaults.
    pub fn new() -> Self {
        AvoidObstacleX {
            v21: false,
            base: ObstacleBase::new(),
            model: LegacyModel::default(),
            use_refinery: false,
            hide_deprecation: false,
            hints: XHints::default(),
            flags: RangeFlags::default(),
            relevance: 0.0,
            valid: false,
        }
    }

    /// BHV_AvoidObstacleV21 with MOOS-IvP's defaults.
    pub fn v21() -> Self {
        AvoidObstacleX {
            v21: true,
            ..Self::new()
        }
    }

    /// MOOS `updatePlatformInfo`: ownship into the model, with the C++ warnings.
    fn update_platform(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        let i = ctx.info;
        let (x, y, h) = (i.num("NAV_X"), i.num("NAV_Y"), i.num("NAV_HEADING"));
        let ok = self
            .model
            .set_pose(x.unwrap_or(0.0), y.unwrap_or(0.0), h.unwrap_or(0.0));
        let problem = if !ok {
            Some("Problem updating obship_model pose")
        } else if x.is_none() || y.is_none() {
            Some("No Ownship NAV_X and/or NAV_Y in info_buffer")
        } else if h.is_none() {
            Some("No Ownship NAV_HEADING in info_buffer")
        } else {
            None
        };
        if let Some(p) = problem {
            out.warning(ctx.name, p);
        }
        problem.is_none()
    }

    /// MOOS `onEveryState`: X notes resolutions; V21 also judges the model, posts flags and
    /// the range, and makes completion pending beyond `completed_dist`.
    fn every_state(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.base.check_resolved(ctx, out);
        if !self.v21 {
            return;
        }
        self.valid = self.update_platform(ctx, out) && self.model.valid();
        if !self.valid {
            out.warning(ctx.name, "Invalid update of ownship/obship model");
        }
        if !self.model.m.failed_expand.is_empty() {
            let msg = std::mem::take(&mut self.model.m.failed_expand);
            out.warning(ctx.name, &msg);
        }
        if !self.valid {
            return;
        }
        let range = self.model.m.range;
        self.flags.update(range, self.model.m.pwt_outer_dist, out);
        out.post("OS_DIST_TO_POLY", range);
        if range > self.model.m.completed_dist {
            self.base.resolved_pending = true;
        }
    }

    fn aof_problem(&self) -> Option<&'static str> {
        self.model.m.aof_problem()
    }

    /// The objective function for the present model, before normalisation and weight.
    pub fn objective(&self, ctx: &Ctx<'_>) -> Option<IvpFunction> {
        let domain = course_speed(ctx)?;
        let model = &self.model;
        let r = Reflector::new(&domain, |v: &[f64]| model.eval(v[0], v[1]))
            .set_param("uniform_piece", "course:3,speed:2")
            .ok()?;
        let r = if self.use_refinery {
            let regions = super::refinery::legacy_regions(&domain, model);
            super::refinery::apply(r, regions)?
        } else {
            r
        };
        r.build().ok()
    }

    fn labels(&self) -> [String; 3] {
        let l = &self.model.m.label;
        [l.clone(), format!("{l}_buff_min"), format!("{l}_buff_max")]
    }

    fn post_polygons(&self, out: &mut Out) {
        let m = &self.model.m;
        let labels = self.labels();
        let polys = [&m.gut, &m.mid, &m.rim];
        for (i, key) in ["one", "two", "three"].into_iter().enumerate() {
            let mut v = match (i, &self.base.poly) {
                (0, Some(p)) => p.clone(),
                _ => {
                    let mut v = geometry::ViewPolygon::new(polys[i].clone());
                    v.attrs.label.clone_from(&labels[i]);
                    v
                }
            };
            v.precision = if self.v21 { 5 } else { 3 };
            v.attrs.active = true;
            let h = &self.hints.polys[i];
            v.attrs.edge_color = Some(h.0.clone());
            v.attrs.vertex_color = Some(h.1.clone());
            v.attrs.vertex_size = Some(h.2);
            if self.relevance > 0.0 {
                v.attrs.fill_color = Some(h.3.clone());
                v.attrs.fill_transparency = Some(h.4);
            }
            out.post_key("VIEW_POLYGON", v.to_spec(), PostKey::Tag(key));
        }
    }

    fn erase_polygons(&self, out: &mut Out) {
        let [_, min, max] = self.labels();
        erase_ship_polygons(&self.model.m, [&min, &max], ["one", "two", "three"], out);
    }
}

impl Behavior for AvoidObstacleX {
    fn kind(&self) -> &'static str {
        if self.v21 {
            "BHV_AvoidObstacleV21"
        } else {
            "BHV_AvoidObstacleX"
        }
    }

    super::obstacle_identity!("avoid_obstacle");

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        if let Some(r) = ship_param(&mut self.base, &mut self.model.m, param, value) {
            return r;
        }
        match param {
            "resolved" if !self.v21 => {
                self.base.resolved_pending =
                    moos_boolean(param, value, self.base.resolved_pending)?;
                Ok(())
            }
            "visual_hints" => {
                if self.hints.set(value) {
                    Ok(())
                } else {
                    Err(ParamError::bad(param, value, "the X family's hints"))
                }
            }
            "use_refinery" => {
                self.use_refinery = moos_boolean(param, value, self.use_refinery)?;
                Ok(())
            }
            "id" if self.v21 => self.base.set_id(param, value),
            "id" => {
                // X may change its id.
                if value.is_empty() || value.contains(char::is_whitespace) {
                    return Err(ParamError::bad(param, value, "a name without white space"));
                }
                self.base.obstacle_id = value.to_string();
                Ok(())
            }
            "i_understand_this_behavior_is_deprecated" => {
                self.hide_deprecation = moos_boolean(param, value, self.hide_deprecation)?;
                Ok(())
            }
            "rng_flag" if self.v21 => self.flags.set_rng_flag(param, value),
            "cpa_flag" if self.v21 => self.flags.set_cpa_flag(param, value),
            _ => Err(ParamError::unknown(param)),
        }
    }

    fn set_common(&mut self, common: &Common) {
        self.base.set_common(common);
    }

    fn on_helm_start(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.base
            .alert_request(ctx, self.model.m.pwt_outer_dist, out);
    }

    fn on_spawn(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        if !self.v21 {
            out.post("AVD_OB_SPAWN", ctx.name.to_string());
        }
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(
            out,
            [
                "NAV_X",
                "NAV_Y",
                "NAV_HEADING",
                self.base.resolved_var.as_str(),
            ],
        );
    }

    fn pwt_factor(&self) -> f64 {
        self.relevance
    }

    fn config_status(&self, name: &str) -> Option<String> {
        let kind = if self.v21 {
            "BHV_AvoidObstacleV21"
        } else {
            "BHV_AvoidObstacleXs"
        };
        Some(ship_config_status(kind, name, &self.model.m))
    }

    fn on_idle_to_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        crate::behavior::post_config_status(&*self, ctx, out);
    }

    fn on_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.every_state(ctx, out);
        idle_tail(&self.base, |o| self.erase_polygons(o), out);
    }

    fn on_complete(&mut self, _ctx: &Ctx<'_>, out: &mut Out) {
        self.erase_polygons(out);
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        self.relevance = 0.0;
        self.every_state(ctx, out);
        if self.base.resolved_pending {
            out.complete();
            return None;
        }
        if self.v21 {
            if !self.valid {
                return None;
            }
        } else {
            if !self.model.m.failed_expand.is_empty() {
                let msg = std::mem::take(&mut self.model.m.failed_expand);
                out.warning(ctx.name, &msg);
            }
            if !self.update_platform(ctx, out) || !self.model.valid() {
                return None;
            }
            let range = self.model.m.range;
            out.post("OS_DIST_TO_POLY", range);
            if range > self.model.m.completed_dist {
                out.complete();
                return None;
            }
        }
        let (osx, osy, osh, _) = self.model.m.pose.unwrap_or_default();
        if geom::poly_aft(osx, osy, osh, &self.model.m.gut, 20.0) {
            return None;
        }
        let relevance = self.model.range_relevance();
        if relevance <= 0.0 {
            return None;
        }
        self.relevance = relevance;
        if let Some(p) = self.aof_problem() {
            let kind = if self.v21 { "V21" } else { "X" };
            out.warning(
                ctx.name,
                &format!("Unable to init AOF_AvoidObstacle{kind}:{p}"),
            );
            self.relevance = 0.0;
            return None;
        }
        let mut f = self.objective(ctx)?;
        f.normalize(0.0, 100.0);
        self.post_polygons(out);
        Some(f)
    }

    fn macro_value(&self, name: &str, out: &mut String) -> bool {
        if !self.v21 {
            return false;
        }
        use moos_types::fmt::compact;
        let m = &self.model.m;
        match name {
            "CPA" => compact(out, self.flags.cpa_reported, 3),
            "RNG" => compact(out, m.range, 3),
            "BNG" => compact(out, m.obcent_bng, 3),
            "RBNG" => compact(out, m.obcent_relbng, 3),
            "SIDE" => out.push_str(m.passing_side),
            "OSV" | "SPD" => compact(out, 0.0, 3),
            "OID" => out.push_str(&m.label),
            _ => return false,
        }
        true
    }
}

/// BHV_AvoidObstacle; see the module docs.
#[derive(Debug, Clone)]
pub struct AvoidObstacle {
    /// The obstacle.
    pub base: ObstacleBase,
    /// The obstacle grown by the present buffer distance, once built.
    pub buff: Option<geometry::Polygon>,
    /// `allowable_ttc` (20).
    pub allowable_ttc: f64,
    /// `buffer_dist` (0).
    pub buffer_dist: f64,
    /// `pwt_outer_dist` (30).
    pub pwt_outer_dist: f64,
    /// `pwt_inner_dist` (20).
    pub pwt_inner_dist: f64,
    /// `completed_dist` (75).
    pub completed_dist: f64,
    set: [bool; 3],
    obstacle_key: String,
    no_alert_request: bool,
    hide_deprecation: bool,
    /// Obstacle and buffer hints: edge, vertex, fill, transparency.
    hints: [(String, String, String, f64); 2],
    /// The relevance of the last running iteration.
    pub relevance: f64,
    pose: (f64, f64, f64),
}

impl Default for AvoidObstacle {
    fn default() -> Self {
        Self::new()
    }
}

impl AvoidObstacle {
    /// A behaviour with MOOS-IvP's defaults.
    pub fn new() -> Self {
        AvoidObstacle {
            base: ObstacleBase::new(),
            buff: None,
            allowable_ttc: 20.0,
            buffer_dist: 0.0,
            pwt_outer_dist: 30.0,
            pwt_inner_dist: 20.0,
            completed_dist: 75.0,
            set: [false; 3],
            obstacle_key: String::new(),
            no_alert_request: false,
            hide_deprecation: false,
            hints: [
                ("white".into(), "dodger_blue".into(), "gray60".into(), 0.7),
                ("gray60".into(), "dodger_blue".into(), "gray70".into(), 0.1),
            ],
            relevance: 0.0,
            pose: (0.0, 0.0, 0.0),
        }
    }

    fn gut(&self) -> &geometry::Polygon {
        self.base.gut()
    }

    /// MOOS `applyBuffer`: the buffer polygon for the present range, or why there is none.
    fn apply_buffer(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        self.buff = None;
        let (x, y, _) = self.pose;
        if self.buffer_dist <= 0.0 || self.gut().contains(x, y) {
            return false;
        }
        let range = geom::dist_to_poly(self.gut(), x, y);
        let mut d = self.buffer_dist;
        if range < self.buffer_dist + 1.0 {
            d = (range - 2.0).max(0.0);
        }
        match geom::buffer(self.gut(), d, 10.0) {
            Some(b) if !b.contains(x, y) => {
                self.buff = Some(b);
                true
            }
            Some(_) => {
                out.warning(ctx.name, "Buffer obstacle contains OS position");
                false
            }
            None => {
                out.warning(ctx.name, "Buffer obstacle not convex");
                false
            }
        }
    }

    /// The relevance (MOOS `getRelevance`).
    pub fn relevance_now(&self) -> f64 {
        let (x, y, h) = self.pose;
        if self.pwt_outer_dist < self.pwt_inner_dist || geom::poly_aft(x, y, h, self.gut(), 20.0) {
            return 0.0;
        }
        let r = geom::dist_to_poly(self.gut(), x, y);
        if r == 0.0 || r >= self.pwt_outer_dist {
            return 0.0;
        }
        if r <= self.pwt_inner_dist {
            return 1.0;
        }
        let d = self.pwt_outer_dist - self.pwt_inner_dist;
        if d <= 0.0 {
            0.0
        } else {
            (self.pwt_outer_dist - r) / d
        }
    }

    /// `AOF_AvoidObstacle`'s utility of `(hdg, spd)` with the buffer polygon `buff`.
    pub fn eval(&self, buff: &geometry::Polygon, hdg: f64, spd: f64) -> f64 {
        let (x, y, h) = self.pose;
        if buff.ray_distance(x, y, hdg).is_some() && spd != 0.0 {
            let ttc = geom::dist_to_poly(buff, x, y) / spd;
            if ttc <= self.allowable_ttc {
                return 0.0;
            }
        }
        let c = self.gut().center();
        let port_now = geom::rel_bearing(x, y, h, c.x, c.y) > 180.0;
        let port_eval = geom::rel_bearing(x, y, hdg, c.x, c.y) > 180.0;
        if port_now != port_eval { 0.0 } else { 100.0 }
    }

    fn erase_polygons(&self, out: &mut Out) {
        if self.gut().is_convex() {
            let label = self.base.label().to_string();
            out.post_key("VIEW_POLYGON", spec_inactive(&label), PostKey::Tag("orig"));
            if self.buffer_dist > 0.0 {
                let l = format!("{label}_buff");
                out.post_key("VIEW_POLYGON", spec_inactive(&l), PostKey::Tag("buff"));
            }
        }
    }

    fn post_polygons(&self, out: &mut Out) {
        if let Some(p) = &self.base.poly {
            let mut v = p.clone();
            v.attrs.active = true;
            v.precision = 3;
            let h = &self.hints[0];
            v.attrs.edge_color = Some(h.0.clone());
            v.attrs.vertex_color = Some("pink".into());
            if self.relevance > 0.0 {
                v.attrs.fill_color = Some(h.2.clone());
                v.attrs.fill_transparency = Some(h.3);
            }
            out.post_key("VIEW_POLYGON", v.to_spec(), PostKey::Tag("orig"));
        }
        if let Some(b) = &self.buff {
            let mut v = geometry::ViewPolygon::new(b.clone());
            v.precision = 3;
            v.attrs.label = format!("{}_buff", self.base.label());
            let h = &self.hints[1];
            v.attrs.edge_color = Some(h.0.clone());
            v.attrs.vertex_color = Some(h.1.clone());
            if self.relevance > 0.0 {
                v.attrs.fill_color = Some(h.2.clone());
                v.attrs.fill_transparency = Some(h.3);
            }
            out.post_key("VIEW_POLYGON", v.to_spec(), PostKey::Tag("buff"));
        }
    }
}

impl Behavior for AvoidObstacle {
    super::obstacle_identity!("BHV_AvoidObstacle", "avoid_obstacles");

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        let bool_param = |cur: bool| moos_boolean(param, value, cur);
        match param {
            "polygon" | "points" | "poly" => self
                .base
                .set_poly(value)
                .map_err(|e| ParamError::bad(param, value, e)),
            "allowable_ttc" => {
                self.allowable_ttc = non_neg(param, value)?;
                Ok(())
            }
            "buffer_dist" => {
                self.buffer_dist = non_neg(param, value)?;
                Ok(())
            }
            "obstacle_key" => {
                if value.is_empty() || value.contains(char::is_whitespace) {
                    return Err(ParamError::bad(param, value, "a name without white space"));
                }
                self.obstacle_key = value.to_string();
                Ok(())
            }
            "pwt_outer_dist" => {
                let d = non_neg(param, value)?;
                self.pwt_outer_dist = d;
                self.set[0] = true;
                if self.pwt_inner_dist > d {
                    self.pwt_inner_dist = d;
                    if self.set[1] {
                        return Err(ParamError::bad(
                            param,
                            value,
                            "pwt_outer_dist must be > pwt_inner_dist",
                        ));
                    }
                }
                if self.completed_dist <= d {
                    self.completed_dist = d + 1.0;
                    if self.set[2] {
                        return Err(ParamError::bad(param, value, "below completed_dist"));
                    }
                }
                Ok(())
            }
            "pwt_inner_dist" => {
                let d = non_neg(param, value)?;
                self.pwt_inner_dist = d;
                self.set[1] = true;
                if self.pwt_outer_dist < d {
                    self.pwt_outer_dist = d;
                    if self.set[0] {
                        return Err(ParamError::bad(param, value, "at most pwt_outer_dist"));
                    }
                }
                Ok(())
            }
            "completed_dist" => {
                let d = non_neg(param, value)?;
                self.completed_dist = d;
                self.set[2] = true;
                if d <= self.pwt_outer_dist {
                    self.completed_dist = self.pwt_outer_dist + 1.0;
                    if self.set[0] {
                        return Err(ParamError::bad(
                            param,
                            value,
                            "completed_dist must be > pwt_outer_dist",
                        ));
                    }
                }
                Ok(())
            }
            "no_alert_request" => {
                self.no_alert_request = bool_param(self.no_alert_request)?;
                Ok(())
            }
            "resolved" => {
                self.base.resolved_pending = bool_param(self.base.resolved_pending)?;
                Ok(())
            }
            "i_understand_this_behavior_is_deprecated" => {
                self.hide_deprecation = bool_param(self.hide_deprecation)?;
                Ok(())
            }
            "visual_hints" => {
                for piece in moos_types::text::parse_string_q(value, ',') {
                    let (k, v) = piece.split_once('=').unwrap_or((piece, ""));
                    let (k, v) = (k.trim().to_ascii_lowercase(), v.trim());
                    let (i, field) = match (k.strip_prefix("obstacle_"), k.strip_prefix("buffer_"))
                    {
                        (Some(f), _) => (0, f),
                        (_, Some(f)) => (1, f),
                        _ => return Err(ParamError::bad(param, value, "obstacle_/buffer_ hints")),
                    };
                    let h = &mut self.hints[i];
                    let color = geometry::color::is_color(v);
                    match field {
                        "edge_color" if color => h.0 = v.to_string(),
                        "vertex_color" if color => h.1 = v.to_string(),
                        "fill_color" if color => h.2 = v.to_string(),
                        "fill_transparency" if is_number(v) => h.3 = atof(v).clamp(0.0, 1.0),
                        _ => return Err(ParamError::bad(param, value, "obstacle_/buffer_ hints")),
                    }
                }
                Ok(())
            }
            _ => Err(ParamError::unknown(param)),
        }
    }

    fn set_common(&mut self, common: &Common) {
        self.base.update_var.clone_from(&common.update_var);
    }

    fn on_helm_start(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        // No spawning check here, unlike the newer types.
        if self.no_alert_request || self.base.update_var.is_empty() {
            return;
        }
        let mut b = self.base.clone();
        b.spawnable = true;
        b.alert_request(ctx, self.pwt_outer_dist, out);
    }

    fn on_spawn(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        out.post("AVD_OB_SPAWN", ctx.name.to_string());
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_X", "NAV_Y", "NAV_HEADING"]);
    }

    fn pwt_factor(&self) -> f64 {
        self.relevance
    }

    fn config_status(&self, name: &str) -> Option<String> {
        let mut s = format!("type=BHV_AvoidObstacles,name={name}");
        for (k, v) in [
            ("allowable_ttc", self.allowable_ttc),
            ("buffer_dist", self.buffer_dist),
            ("pwt_outer_dist", self.pwt_outer_dist),
            ("pwt_inner_dist", self.pwt_inner_dist),
            ("completed_dist", self.completed_dist),
        ] {
            s.push(',');
            s.push_str(k);
            s.push('=');
            moos_types::fmt::fixed(&mut s, v, 2);
        }
        s.push_str(",obstacle_key=");
        s.push_str(&self.obstacle_key);
        Some(s)
    }

    fn on_idle_to_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        crate::behavior::post_config_status(&*self, ctx, out);
    }

    fn on_idle(&mut self, _ctx: &Ctx<'_>, out: &mut Out) {
        self.erase_polygons(out);
    }

    fn on_complete(&mut self, _ctx: &Ctx<'_>, out: &mut Out) {
        self.erase_polygons(out);
        out.post_key(
            "OBSTACLE_RESOLVED",
            self.obstacle_key.clone(),
            PostKey::Repeatable,
        );
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        self.relevance = 0.0;
        if self.base.resolved_pending {
            out.complete();
            return None;
        }
        let i = ctx.info;
        let (Some(x), Some(y)) = (i.num("NAV_X"), i.num("NAV_Y")) else {
            out.warning(ctx.name, "No Ownship NAV_X and/or NAV_Y in info_buffer");
            return None;
        };
        let Some(h) = i.num("NAV_HEADING") else {
            out.warning(ctx.name, "No Ownship NAV_HEADING in info_buffer");
            return None;
        };
        self.pose = (x, y, h);
        if !self.gut().is_convex() || !self.apply_buffer(ctx, out) {
            return None;
        }
        let range = geom::dist_to_poly(self.gut(), x, y);
        out.post("OS_DIST_TO_POLY", range);
        if range > self.completed_dist {
            out.complete();
            return None;
        }
        let relevance = self.relevance_now();
        if relevance <= 0.0 {
            return None;
        }
        self.relevance = relevance;
        let buff = self.buff.clone()?;
        let domain = course_speed(ctx)?;
        let me = &*self;
        let mut f = Reflector::new(&domain, |v: &[f64]| me.eval(&buff, v[0], v[1]))
            .set_param("uniform_piece", "course:3,speed:3")
            .ok()?
            .build()
            .ok()?;
        f.normalize(0.0, 100.0);
        self.post_polygons(out);
        Some(f)
    }
}
