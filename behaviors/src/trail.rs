//! BHV_Trail (MOOS-IvP `BHV_Trail` at a2a9b716): keeps station at a point `trail_range`
//! metres from a contact, at `trail_angle` relative to its heading (or absolute).
//!
//! Each running iteration, with the trail point `P` and ownship's distance `d` to it:
//! - relevance 1 when `pwt_outer_dist` is 0 or the contact is nearer than it, else 0 (no
//!   function, `PURSUIT = 0`);
//! - `d > nm_radius`: the AOF_CutRangeCPA objective toward `P` moving with the contact
//!   (patience 100: the CPA metric alone), 3 × 2 pieces;
//! - `radius < d <= nm_radius`: a course ZAIC_PEAK (30, 150, summit delta 50) on the bearing
//!   to the point `nm_radius` ahead of `P` along the contact's heading, coupled with a speed
//!   ZAIC_PEAK (0.1, 2, summit delta 50) at `cnv · (1 − 0.5 · ahead / nm_radius)` (`ahead`:
//!   ownship's distance ahead of `P` along the contact's heading; 0 when negative or
//!   `extrapolate = false`);
//! - `d <= radius`: the same ZAICs on the contact's heading and speed;
//!
//! normalised 0..100 and weighted by `relevance · pwt`.
//!
//! # Conformance with BHV_Trail (MOOS-IvP a2a9b716)
//!
//! | parameter | default | validation (C++ rule) | coug |
//! |---|---|---|---|
//! | trail_range | 50 | number >= 0 | done |
//! | trail_angle | 180 | number, wrapped to (−180, 180] | done |
//! | trail_angle_type | relative | relative, absolute | done |
//! | radius | 5 | number >= 0 | done |
//! | nm_radius | 20 | number >= 0 | done |
//! | pwt_outer_dist | 0 (always) | number >= 0 | done |
//! | mod_trail_range | | adds to trail_range (at least 10) | done |
//! | mod_trail_range_pct | | > 0: scales trail_range (at least 10) | done |
//! | no_alert_request | true | boolean | done |
//! | post_trail_dist_on_idle | true | boolean | done |
//! | time_on_leg | 60 | number >= 0 | done |
//! | contact parameters | | see [`crate::contact`] | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | BCM_ALERT_REQUEST | helm start of a spawning template with `no_alert_request = false` | `..,alert_range=<outer>, cpa_range=<outer+5>` | done |
//! | VIEW_POINT | running | the trail point, label `<us>_trailpoint`, gray50, size 8 | done |
//! | TRAIL_RELEVANCE, TRAIL_CTR (1) | running (repeatable) | number | done |
//! | PURSUIT | running: 1, or 0 without relevance; running→idle: 0 | number | done |
//! | TRAIL_RANGE | running with `pwt_outer_dist` set | integer | done |
//! | TRAIL_DISTANCE | running; idle with `post_trail_dist_on_idle` | integer | done |
//! | REGION | running | `Outside nm_radius`, `Inside nm_radius`, `Inside radius` | done |
//! | TRAIL_HEADING, TRAIL_SPEED | inside `nm_radius` | integer; speed to 0.1 | done |

use ivp::{IvpFunction, Reflector, ZaicPeak, couple};

use crate::behavior::{Behavior, Ctx, Out, ParamError, PostKey, add_vars};
use crate::common::Common;
use crate::contact::ContactBase;
use crate::cpa::CpaEngine;
use crate::cut_range::CutRange;
use crate::param::{is_number, moos_boolean};

/// BHV_Trail.
#[derive(Debug, Clone)]
pub struct Trail {
    /// The contact and the shared contact parameters.
    pub base: ContactBase,
    /// `trail_range`, m.
    pub trail_range: f64,
    /// `trail_angle`, degrees.
    pub trail_angle: f64,
    /// Whether `trail_angle` is relative to the contact's heading.
    pub angle_relative: bool,
    /// `radius`, m.
    pub radius: f64,
    /// `nm_radius`, m.
    pub nm_radius: f64,
    /// `pwt_outer_dist`, m (0: always relevant).
    pub pwt_outer_dist: f64,
    /// `no_alert_request`.
    pub no_alert_request: bool,
    /// `post_trail_dist_on_idle`.
    pub post_trail_dist_on_idle: bool,
    trail_pt: (f64, f64),
    update_var: String,
    spawnable: bool,
}

impl Default for Trail {
    fn default() -> Self {
        Self::new()
    }
}

/// The minimum trail range the `mod_trail_range*` parameters leave.
const MIN_TRAIL_RANGE: f64 = 10.0;

impl Trail {
    /// The C++ defaults.
    pub fn new() -> Self {
        Trail {
            base: ContactBase::new(60.0),
            trail_range: 50.0,
            trail_angle: 180.0,
            angle_relative: true,
            radius: 5.0,
            nm_radius: 20.0,
            pwt_outer_dist: 0.0,
            no_alert_request: true,
            post_trail_dist_on_idle: true,
            trail_pt: (0.0, 0.0),
            update_var: String::new(),
            spawnable: false,
        }
    }

    /// The trail point for the contact at `(cnx, cny)` heading `cnh` (MOOS
    /// `calculateTrailPoint`).
    pub fn trail_point(&self, cnx: f64, cny: f64, cnh: f64) -> (f64, f64) {
        let h = if self.angle_relative {
            geometry::angle_360(cnh + self.trail_angle)
        } else {
            self.trail_angle
        };
        let p = geometry::project_point(cnx, cny, h, self.trail_range);
        (p.x, p.y)
    }

    fn zaics(&self, ctx: &Ctx<'_>, hdg: f64, spd: f64) -> Option<IvpFunction> {
        let mut h = ZaicPeak::new(ctx.domain, "course").ok()?;
        h.set_params(hdg, 30.0, 150.0, 50.0, 0.0, 100.0).ok()?;
        h.set_value_wrap(true);
        let h = h.extract().ok()?;
        let mut s = ZaicPeak::new(ctx.domain, "speed").ok()?;
        s.set_params(spd, 0.1, 2.0, 50.0, 0.0, 100.0).ok()?;
        let s = s.extract().ok()?;
        couple(&h, &s).ok()
    }

    fn post_distance(&self, out: &mut Out) -> f64 {
        let (ox, oy, ..) = self.base.os;
        let d = (ox - self.trail_pt.0).hypot(oy - self.trail_pt.1);
        out.post_int("TRAIL_DISTANCE", d);
        d
    }
}

impl Behavior for Trail {
    /// IvPContactBehavior's post mortem: the reason, range and bearing to the contact.
    fn post_mortem(&self, reason: &str) -> String {
        self.base.post_mortem(reason)
    }

    fn kind(&self) -> &'static str {
        "BHV_Trail"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course", "speed"]
    }

    fn default_name(&self) -> &'static str {
        "(d)trail"
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        if let Some(r) = self.base.set_param(param, value) {
            return r;
        }
        let d = geometry::atof(value);
        let nonneg = || {
            if is_number(value) && d >= 0.0 {
                Ok(d)
            } else {
                Err(ParamError::bad(param, value, "a number >= 0"))
            }
        };
        match param {
            "nm_radius" => self.nm_radius = nonneg()?,
            "radius" => self.radius = nonneg()?,
            "trail_range" => self.trail_range = nonneg()?,
            "pwt_outer_dist" => self.pwt_outer_dist = nonneg()?,
            "no_alert_request" => {
                self.no_alert_request = moos_boolean(param, value, self.no_alert_request)?
            }
            "post_trail_dist_on_idle" => {
                self.post_trail_dist_on_idle =
                    moos_boolean(param, value, self.post_trail_dist_on_idle)?
            }
            "mod_trail_range" => {
                self.trail_range = (self.trail_range + d).max(MIN_TRAIL_RANGE);
            }
            "mod_trail_range_pct" => {
                if d <= 0.0 {
                    return Err(ParamError::bad(param, value, "a percentage > 0"));
                }
                self.trail_range = (self.trail_range * d / 100.0).max(MIN_TRAIL_RANGE);
            }
            "trail_angle" => {
                if !is_number(value) {
                    return Err(ParamError::bad(param, value, "a number"));
                }
                self.trail_angle = geometry::angle_180(d);
            }
            "trail_angle_type" => match value.to_ascii_lowercase().as_str() {
                "absolute" => self.angle_relative = false,
                "relative" => self.angle_relative = true,
                _ => return Err(ParamError::bad(param, value, "absolute or relative")),
            },
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn set_common(&mut self, common: &Common) {
        self.update_var.clone_from(&common.update_var);
        self.spawnable = common.templating.spawns();
    }

    fn contact_name(&self) -> Option<&str> {
        self.base.contact_name()
    }

    fn macro_value(&self, name: &str, out: &mut String) -> bool {
        self.base.macro_value(name, out)
    }

    fn on_helm_start(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        if self.no_alert_request || self.update_var.is_empty() || !self.spawnable {
            return;
        }
        let mut req = format!(
            "id={}, on_flag={}=name=$[VNAME] # contact=$[VNAME],alert_range={}, cpa_range={}",
            ctx.name,
            self.update_var,
            moos_types::fmt::compact_string(self.pwt_outer_dist, 1),
            moos_types::fmt::compact_string(self.pwt_outer_dist + 5.0, 1),
        );
        let filters = self.base.filter.summary();
        if !filters.is_empty() {
            req.push(',');
            req.push_str(&filters);
        }
        out.post("BCM_ALERT_REQUEST", req);
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_X", "NAV_Y", "NAV_SPEED", "NAV_HEADING"]);
    }

    fn pwt_factor(&self) -> f64 {
        self.base.relevance
    }

    fn on_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        if !self.base.update(ctx, out) {
            return;
        }
        let (cnx, cny, cnh, _) = self.base.cn;
        self.trail_pt = self.trail_point(cnx, cny, cnh);
        if self.post_trail_dist_on_idle {
            self.post_distance(out);
        }
    }

    fn on_run_to_idle(&mut self, _ctx: &Ctx<'_>, out: &mut Out) {
        out.post("PURSUIT", 0.0);
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        self.base.relevance = 0.0;
        if !self.base.update(ctx, out) {
            return None;
        }
        self.base.post_contact_flags(out);
        let (cnx, cny, cnh, cnv) = self.base.cn;
        let cnh = geometry::angle_360(cnh);
        self.trail_pt = self.trail_point(cnx, cny, cnh);
        let (tx, ty) = self.trail_pt;
        let mut vp = geometry::ViewPoint::new(geometry::Point::new(tx, ty));
        vp.attrs.label = format!("{}_trailpoint", ctx.ownship);
        vp.attrs.vertex_size = Some(8.0);
        vp.attrs.vertex_color = Some("gray50".into());
        vp.attrs.time = Some(ctx.info.now());
        out.post("VIEW_POINT", vp.to_spec());
        let relevance = if self.pwt_outer_dist == 0.0 {
            1.0
        } else {
            out.post_int("TRAIL_RANGE", self.base.range);
            if self.base.range < self.pwt_outer_dist {
                1.0
            } else {
                0.0
            }
        };
        out.post_key("TRAIL_RELEVANCE", relevance, PostKey::Repeatable);
        out.post_key("TRAIL_CTR", 1.0, PostKey::Repeatable);
        if relevance <= 0.0 {
            out.post("PURSUIT", 0.0);
            return None;
        }
        out.post("PURSUIT", 1.0);
        let (head_x, head_y) = (cnh.to_radians().sin(), cnh.to_radians().cos());
        let d = self.post_distance(out);
        let (ox, oy, ..) = self.base.os;
        let f = if d > self.radius {
            if d > self.nm_radius {
                out.post("REGION", "Outside nm_radius");
                // AOF_CutRangeCPA toward the moving trail point, patience 100.
                let mut cut = CutRange::new();
                cut.max_patience = 100.0;
                cut.patience = 100.0;
                cut.base.time_on_leg = self.base.time_on_leg;
                let engine = CpaEngine::new(tx, ty, cnh, cnv, ox, oy);
                if self.base.time_on_leg < 1.0 || d <= 0.0 {
                    out.warning(ctx.name, "Error in initializing AOF_CutRangeCPA.");
                    return None;
                }
                let mut domain = ivp::Domain::new();
                domain.add(ctx.domain.get("course")?.clone()).ok()?;
                let spd = ctx.domain.get("speed")?.clone();
                let bounds = CutRange::roc_bounds(&engine, spd.high());
                domain.add(spd).ok()?;
                Reflector::new(&domain, |v: &[f64]| cut.aof(&engine, d, bounds, v[0], v[1]))
                    .set_param("uniform_piece", "course:3,speed:2")
                    .ok()?
                    .build()
                    .ok()
            } else {
                out.post("REGION", "Inside nm_radius");
                let ahead = head_x * (ox - tx) + head_y * (oy - ty);
                let ppx = head_x * self.nm_radius + tx;
                let ppy = head_y * self.nm_radius + ty;
                let modh = geometry::relative_angle(ox, oy, ppx, ppy);
                out.post_int("TRAIL_HEADING", modh);
                let mut modv = cnv * (1.0 - 0.5 * ahead / self.nm_radius);
                if modv < 0.0 || !self.base.extrapolate {
                    modv = 0.0;
                }
                out.post("TRAIL_SPEED", (modv / 0.1).round() * 0.1);
                self.zaics(ctx, modh, modv)
            }
        } else {
            out.post("REGION", "Inside radius");
            let modv = if cnv < 0.0 || !self.base.extrapolate {
                0.0
            } else {
                cnv
            };
            out.post("TRAIL_SPEED", modv);
            self.zaics(ctx, cnh, modv)
        };
        let mut f = f?;
        f.normalize(0.0, 100.0);
        self.base.relevance = relevance;
        Some(f)
    }
}
