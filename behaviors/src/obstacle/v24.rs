//! BHV_AvoidObstacleV24 (MOOS-IvP `BHV_AvoidObstacleV24` with `ObShipModelV24` and
//! `AOF_AvoidObstacleV24` at a2a9b716): a constraint over course and speed that keeps
//! ownship's path clear of one convex obstacle, usually spawned per obstacle by
//! pObstacleMgr's alert (`name=<prefix><key>#poly=...#id=<key>`).
//!
//! Every iteration (idle or running, MOOS `onEveryState`): the obstacle manager's
//! resolution (`OBM_RESOLVED` naming our id) or a range beyond `completed_dist` makes the
//! completion pending; ownship's pose (the helm's holonomic platform model: `NAV_X`,
//! `NAV_Y`, `NAV_HEADING`, `NAV_SPEED`) updates the [`ShipModel`]: the range, the buffer
//! polygons (`mid` at `min_util_cpa_dist`, `rim` at `max_util_cpa_dist`, both shrunk to the
//! range less 1 m when ownship is closer); range flags and CPA flags are posted.
//!
//! A running iteration: no function when the obstacle lies wholly more than 20° abaft the
//! beam; the relevance is the [`ShipModel::range_relevance`] (the grade is linear: V24 has no
//! `pwt_grade`); above 0.6 the passing side locks (only headings keeping the obstacle's
//! centre on its present side count) until the relevance drops below 0.1. The objective at
//! `(course, speed)` is, for the closest approach `d` of the ray from ownship along `course`
//! to the obstacle (with the helm's Dubins platform model: of the model's turn to `course`
//! and the ray after it, [`super::turn`]), 0 for `d <= min_util_cpa_dist`, 100 for `d >= max_util_cpa_dist`,
//! linear between (speed plays no part); sampled by the reflector in 3 × 3 pieces,
//! normalised to 0..100 and weighted by `relevance · pwt`. Ownship inside the obstacle, or
//! `min_util_cpa_dist`, `max_util_cpa_dist` or `allowable_ttc` never set, leaves no function:
//! `BHV_ERROR` "Allstop: Obstacle Breached" (or a warning with `allstop_on_breach = false`),
//! as in the C++; a function that is 0 everywhere is "Allstop: obstacle unavoidable".
//!
//! # Conformance with BHV_AvoidObstacleV24 (MOOS-IvP a2a9b716)
//!
//! | parameter | default | validation (C++ rule) | coug |
//! |---|---|---|---|
//! | polygon, poly | none | a convex polygon (`obstacle is not convex`) | done |
//! | allowable_ttc | 20 | `atof` of the value >= 0 (text reads as 0) | done (read; required by the function; unused by the C++'s evaluation with either model) |
//! | min_util_cpa_dist | 8 | number >= 0; max raised to it, an error when max was set | done |
//! | max_util_cpa_dist | 16 | number >= 0; min lowered to it, an error when min was set | done |
//! | pwt_inner_dist | 10 | number >= 0; outer and completed raised to it (errors when set) | done |
//! | pwt_outer_dist | 50 | number >= 0; inner lowered, completed raised (errors when set) | done |
//! | completed_dist | 50 | number >= 0; inner and outer lowered to it (errors when set) | done |
//! | id, obid | none | no white space; once set, no other value | done |
//! | rng_flag | none | `[<RANGE ]VAR=value`, posted while the range is below RANGE (always without one) | done |
//! | cpa_flag | none | `VAR=value`, posted at the closest approach of each pass within `pwt_outer_dist` | done |
//! | visual_hints | see below | colours and sizes >= 0 | done |
//! | holonomic_ok | false | boolean; false warns every iteration with the holonomic model (not with `pmgen = alg=dubins`) | done |
//! | allstop_on_breach | true | boolean | done |
//! | use_refinery | false | boolean | done: plateau and basin regions ([`super::refinery`]) |
//! | draw_buff_min_poly, draw_buff_max_poly | true | boolean | done (read; unused by the C++) |
//! | can_disable | false | boolean | done: `BHV_ABLE_FILTER` with `obstacle_id` or `vsource` disables, enables or expunges it (`obstacle/able.rs`) |
//!
//! Hints (MOOS `initVisualHints`): `vertex_size=0`, `edge_size=1`, `vertex_color=gray50`,
//! `edge_color=gray50`, `fill_color=off`, `label_color=white` and the `obst_`, `buff_min_`,
//! `buff_max_` sets the C++ sets but never applies; the `gut`, `mid` and `rim` polygons take
//! `<prefix>_<hint>` before `<hint>`, their fill set each time: gut `pink` with a side lock,
//! else `gray60`; mid and rim `gray70`.
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | OBM_ALERT_REQUEST | helm start, for a spawning template with an `updates` variable | `name=<name>,update_var=<var>,alert_range=<pwt_outer_dist, 1 decimal>` | done |
//! | NOTED_RESOLVED | `OBM_RESOLVED` posted | its value | done (the last one of an iteration) |
//! | VIEW_POLYGON (keys gut, mid, rim) | with each function | the polygons, 5 decimals, hints applied; labels `<label>`, `<label>_mid_poly`, `<label>_rim_poly` | done |
//! | VIEW_POLYGON (erasing) | idle, complete | `pts={0,0:9,0:0,9},active=false,label=..` | done |
//! | BHV_SETTINGS | configuration, idle to running | `type=BHV_AvoidObstacleV24,name=..,allowable_ttc=..,min_util_cpa=..,max_util_cpa=..,pwt_outer_dist=..,pwt_inner_dist=..,completed_dist=..` (2 decimals) | done |
//! | BHV_WARNING | the C++ warnings (invalid model, bad expansion, holonomic model, AOF init) | `<name>: <text>` | done |
//! | BHV_ERROR | breach, unavoidable | `Allstop: ...` | done |
//!
//! Macros in flags: `$[RNG]`, `$[BNG]`, `$[CPA]` (3 decimals), `$[SIDE]`, `$[OID]`, `$[OIDX]`
//! (after the id's last `_`), `$[SLOCK]`, `$[MINU_CPA]`, `$[MAXU_CPA]`; `$[RBNG]` stays as
//! it is (the C++ expands `BNG` for it).

use ivp::{IvpFunction, Reflector};

use super::{
    Hints, ObstacleBase, RangeFlags, ShipModel, erase_ship_polygons, idle_tail, plat_pose,
    ship_config_status, ship_param,
};
use crate::behavior::{Behavior, Ctx, Out, ParamError, PostKey, add_vars};
use crate::common::Common;
use crate::param::moos_boolean;

/// BHV_AvoidObstacleV24.
#[derive(Debug, Clone)]
pub struct AvoidObstacleV24 {
    /// The obstacle, its id and resolution.
    pub base: ObstacleBase,
    /// Ownship and the obstacle.
    pub model: ShipModel,
    use_refinery: bool,
    flags: RangeFlags,
    draw_buff_min_poly: bool,
    draw_buff_max_poly: bool,
    holonomic_ok: bool,
    allstop_on_breach: bool,
    hints: Hints,
    /// The relevance of the last running iteration.
    pub relevance: f64,
    valid: bool,
    /// `port`, `star` or empty: the passing side held.
    pub side_lock: String,
}

impl Default for AvoidObstacleV24 {
    fn default() -> Self {
        Self::new()
    }
}

/// MOOS `initVisualHints` of the V24 behaviour.
fn default_hints() -> Hints {
    let mut h = Hints::default();
    h.measure("vertex_size", 0.0);
    h.measure("edge_size", 1.0);
    for (k, v) in [
        ("vertex_color", "gray50"),
        ("edge_color", "gray50"),
        ("fill_color", "off"),
        ("label_color", "white"),
        ("obst_edge_color", "white"),
        ("obst_vertex_color", "white"),
        ("obst_fill_color", "gray60"),
        ("buff_min_edge_color", "gray60"),
        ("buff_min_vertex_color", "dodger_blue"),
        ("buff_min_fill_color", "gray70"),
        ("buff_min_label_color", "off"),
        ("buff_max_edge_color", "gray60"),
        ("buff_max_vertex_color", "dodger_blue"),
        ("buff_max_fill_color", "gray70"),
        ("buff_max_label_color", "off"),
    ] {
        h.color(k, v);
    }
    for (k, v) in [
        ("obst_vertex_size", 1.0),
        ("obst_fill_transparency", 0.7),
        ("buff_min_vertex_size", 1.0),
        ("buff_min_fill_transparency", 0.25),
        ("buff_max_vertex_size", 1.0),
        ("buff_max_fill_transparency", 0.1),
    ] {
        h.measure(k, v);
    }
    h
}

impl AvoidObstacleV24 {
    /// A behaviour with MOOS-IvP's defaults.
    pub fn new() -> Self {
        AvoidObstacleV24 {
            base: ObstacleBase::new(),
            model: ShipModel::default(),
            use_refinery: false,
            flags: RangeFlags::default(),
            draw_buff_min_poly: true,
            draw_buff_max_poly: true,
            holonomic_ok: false,
            allstop_on_breach: true,
            hints: default_hints(),
            relevance: 0.0,
            valid: false,
            side_lock: String::new(),
        }
    }

    /// MOOS `onEveryState`.
    fn every_state(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.base.check_resolved(ctx, out);
        self.model.set_pose(plat_pose(ctx));
        self.model.update();
        self.valid = self.model.invalid().is_none();
        if !self.valid {
            out.warning(ctx.name, "Invalid update of ownship/obship model");
        }
        if !self.model.failed_expand.is_empty() {
            let msg = std::mem::take(&mut self.model.failed_expand);
            out.warning(ctx.name, &msg);
        }
        if !self.valid {
            return;
        }
        let range = self.model.range;
        self.flags.update(range, self.model.pwt_outer_dist, out);
        if range > self.model.completed_dist {
            self.base.resolved_pending = true;
        }
        if !self.holonomic_ok && ctx.info.plat_model().is_none_or(|m| m.is_holonomic()) {
            out.warning(
                ctx.name,
                "holo plat_model not best. Set holonomic_ok=true to silence",
            );
        }
    }

    /// MOOS `getRelevance`: the range relevance, the side lock.
    pub fn relevance_now(&mut self) -> f64 {
        let r = self.model.range_relevance();
        if r <= 0.0 {
            return 0.0;
        }
        if r > 0.6 {
            if self.side_lock.is_empty() {
                self.side_lock = match self.model.passing_side {
                    "star" => "port".into(),
                    "port" => "star".into(),
                    _ => String::new(),
                };
            }
        } else if r < 0.1 {
            self.side_lock.clear();
        }
        self.model.side_lock = !self.side_lock.is_empty();
        r
    }

    /// Why the objective function cannot be built (MOOS `AOF_AvoidObstacleV24::initialize`).
    fn aof_problem(&self) -> Option<&'static str> {
        if self.model.pose.is_none() {
            Some("osx is not set")
        } else {
            self.model.aof_problem()
        }
    }

    /// The objective function over the helm's course and speed for the present model, before
    /// normalisation and weight; `None` when the reflector fails.
    pub fn objective(&self, ctx: &Ctx<'_>) -> Option<IvpFunction> {
        let mut domain = ivp::Domain::new();
        domain.add(ctx.domain.get("course")?.clone()).ok()?;
        domain.add(ctx.domain.get("speed")?.clone()).ok()?;
        let model = &self.model;
        let turning = ctx.info.plat_model().filter(|m| !m.is_holonomic());
        let r = Reflector::new(&domain, |v: &[f64]| match turning {
            Some(pm) => super::turn::eval_heading(model, pm, v[0]),
            None => model.eval_heading(v[0]),
        })
        .set_param("uniform_piece", "course:3,speed:3")
        .ok()?;
        let r = if self.use_refinery {
            let regions = super::refinery::regions(&domain, &self.model, &self.side_lock);
            super::refinery::apply(r, regions)?
        } else {
            r
        };
        r.build().ok()
    }

    /// The `gut`, `mid` and `rim` polygons as posted with a function.
    fn post_polygons(&mut self, out: &mut Out) {
        let relevant = self.relevance > 0.0;
        fn fill(relevant: bool, c: &'static str) -> &'static str {
            if relevant { c } else { "off" }
        }
        let gut_fill = if self.side_lock.is_empty() {
            "gray60"
        } else {
            "pink"
        };
        self.hints.color("gut_fill_color", fill(relevant, gut_fill));
        self.hints.color("mid_fill_color", fill(relevant, "gray70"));
        self.hints.color("rim_fill_color", fill(relevant, "gray70"));
        let label = self.model.label.clone();
        let mut gut = self
            .base
            .poly
            .clone()
            .unwrap_or_else(|| geometry::ViewPolygon::new(self.model.gut.clone()));
        gut.attrs.active = true;
        for (prefix, mut v) in [
            ("gut", gut),
            (
                "mid",
                self.view(&self.model.mid, &format!("{label}_mid_poly")),
            ),
            (
                "rim",
                self.view(&self.model.rim, &format!("{label}_rim_poly")),
            ),
        ] {
            v.precision = 5;
            self.hints.apply(prefix, &mut v.attrs);
            let key = match prefix {
                "gut" => "gut",
                "mid" => "mid",
                _ => "rim",
            };
            out.post_key("VIEW_POLYGON", v.to_spec(), PostKey::Tag(key));
        }
    }

    fn view(&self, p: &geometry::Polygon, label: &str) -> geometry::ViewPolygon {
        let mut v = geometry::ViewPolygon::new(p.clone());
        v.attrs.label = label.to_string();
        v
    }

    /// The erasing polygons (MOOS `postErasablePolygons`).
    fn erase_polygons(&self, out: &mut Out) {
        let label = &self.model.label;
        erase_ship_polygons(
            &self.model,
            [&format!("{label}_mid_poly"), &format!("{label}_rim_poly")],
            ["gut", "mid", "rim"],
            out,
        );
    }
}

impl Behavior for AvoidObstacleV24 {
    super::obstacle_identity!("BHV_AvoidObstacleV24", "avdobs");

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        if let Some(r) = ship_param(&mut self.base, &mut self.model, param, value) {
            return r;
        }
        match param {
            "holonomic_ok" => {
                self.holonomic_ok = moos_boolean(param, value, self.holonomic_ok)?;
                Ok(())
            }
            "draw_buff_min_poly" => {
                self.draw_buff_min_poly = moos_boolean(param, value, self.draw_buff_min_poly)?;
                Ok(())
            }
            "draw_buff_max_poly" => {
                self.draw_buff_max_poly = moos_boolean(param, value, self.draw_buff_max_poly)?;
                Ok(())
            }
            "can_disable" => {
                self.base.can_disable = moos_boolean(param, value, self.base.can_disable)?;
                Ok(())
            }
            "use_refinery" => {
                self.use_refinery = moos_boolean(param, value, self.use_refinery)?;
                Ok(())
            }
            "allstop_on_breach" => {
                self.allstop_on_breach = moos_boolean(param, value, self.allstop_on_breach)?;
                Ok(())
            }
            "rng_flag" => self.flags.set_rng_flag(param, value),
            "cpa_flag" => self.flags.set_cpa_flag(param, value),
            "visual_hints" => {
                if self.hints.set(value) {
                    Ok(())
                } else {
                    Err(ParamError::bad(param, value, "colours and sizes >= 0"))
                }
            }
            "id" | "obid" => self.base.set_id(param, value),
            _ => Err(ParamError::unknown(param)),
        }
    }

    fn set_common(&mut self, common: &Common) {
        self.base.set_common(common);
    }

    fn on_helm_start(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.base.alert_request(ctx, self.model.pwt_outer_dist, out);
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(
            out,
            [
                "NAV_X",
                "NAV_Y",
                "NAV_HEADING",
                "NAV_SPEED",
                self.base.resolved_var.as_str(),
            ],
        );
        for (_, f) in &self.flags.rng_flags {
            crate::behavior::add_flag_vars(out, std::slice::from_ref(f));
        }
        crate::behavior::add_flag_vars(out, &self.flags.cpa_flags);
    }

    fn pwt_factor(&self) -> f64 {
        self.relevance
    }

    fn config_status(&self, name: &str) -> Option<String> {
        Some(ship_config_status(self.kind(), name, &self.model))
    }

    fn on_idle_to_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        crate::behavior::post_config_status(&*self, ctx, out);
    }

    fn on_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.every_state(ctx, out);
        idle_tail(&self.base, |o| self.erase_polygons(o), out);
    }

    fn apply_able_filter(&mut self, msg: &str, out: &mut Out) -> bool {
        match self.base.apply_able_filter(msg) {
            Ok(Some(crate::contact::AbleAction::Expunge)) => {
                out.complete();
                true
            }
            Ok(_) => true,
            Err(_) => false,
        }
    }

    fn is_disabled(&self) -> bool {
        self.base.disabled
    }

    /// Disabled: only the every-state work (MOOS `onEveryState`; V24 has no
    /// `onDisabledState`).
    fn on_disabled(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.every_state(ctx, out);
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
        if !self.valid {
            return None;
        }
        self.model.update();
        if self.model.obstacle_aft(20.0) {
            return None;
        }
        let relevance = self.relevance_now();
        if relevance <= 0.0 {
            return None;
        }
        self.relevance = relevance;
        let f = match self.aof_problem() {
            Some(p) => {
                out.warning(
                    ctx.name,
                    &format!("Unable to init AOF_AvoidObstacleV24:{p}"),
                );
                None
            }
            None => self.objective(ctx),
        };
        let Some(mut f) = f else {
            if self.allstop_on_breach {
                out.error("Allstop: Obstacle Breached");
            } else {
                out.warning(ctx.name, "Obstacle Breached");
            }
            self.relevance = 0.0;
            return None;
        };
        f.normalize(0.0, 100.0);
        self.post_polygons(out);
        if f.max_val() == 0.0 {
            out.error("Allstop: obstacle unavoidable");
            self.relevance = 0.0;
            return None;
        }
        Some(f)
    }

    fn macro_value(&self, name: &str, out: &mut String) -> bool {
        use moos_types::fmt::compact;
        let m = &self.model;
        match name {
            "RNG" => compact(out, m.range, 3),
            "BNG" => compact(out, m.obcent_bng, 3),
            "SIDE" => out.push_str(m.passing_side),
            "OID" => out.push_str(&m.label),
            "CPA" => compact(out, self.flags.cpa_reported, 3),
            "SLOCK" => out.push_str(&self.side_lock),
            "OIDX" => {
                if let Some((_, idx)) = m.label.rsplit_once('_') {
                    out.push_str(idx);
                }
            }
            "MINU_CPA" => compact(out, m.min_util_cpa, 3),
            "MAXU_CPA" => compact(out, m.max_util_cpa, 3),
            _ => return false,
        }
        true
    }
}
