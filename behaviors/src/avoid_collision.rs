//! BHV_AvoidCollision (MOOS-IvP `BHV_AvoidCollision` with `AOF_AvoidCollision` at
//! a2a9b716): a constraint over course and speed that keeps the closest point of approach
//! to one contact wide.
//!
//! Each running iteration, with the range `r` to the contact:
//! - the behaviour completes once `r >= 1.1 · completed_dist` (or the contact fails a filter it
//!   exits on);
//! - its relevance is `((outer − r) / (outer − inner))^g` with `outer = pwt_outer_dist`,
//!   `inner = pwt_inner_dist`, `g` 1 (`linear`), 2 (`quadratic`) or 1.5 (`quasi`), and 0 (no
//!   function) at or beyond `outer`; inside `inner` the ratio exceeds 1 and so does the
//!   relevance, as in the C++ (the branch meant to cap it is overwritten);
//! - the objective at `(course, speed)` is, for the CPA distance `d` over `time_on_leg`
//!   seconds, 0 when `d < min`, 100 when `d > max`, else `25 + 75 · (d − min) / (max − min)`,
//!   with `min = min_util_cpa_dist` (or `r / 2` once `r <= min_util_cpa_dist`) and
//!   `max = max_util_cpa_dist`; sampled by the reflector in 3 × 3 pieces, normalised to
//!   0..100 and weighted by `relevance · pwt`.
//!
//! With `use_plat_model = true` the CPA of each course is the platform-model engine's
//! (MOOS `CPXEnginePM`, [`crate::colregs::plat_cpx::PlatCpx::eval_cpa`]): along the helm's
//! model's turn to that course (the holonomic model's ray from ownship, or the Dubins spokes
//! then the ray). The engine gets the iteration's model once the relevance is positive, after
//! the contact's update, whose contact state therefore reads the previous iteration's model
//! ([`crate::contact`]).
//!
//! # Conformance with BHV_AvoidCollision (MOOS-IvP a2a9b716)
//!
//! The contact parameters (`contact`, `decay`, filters, bearing lines, ...) are those of
//! [`crate::contact`]'s table.
//!
//! | parameter | default | validation (C++ rule) | coug |
//! |---|---|---|---|
//! | pwt_outer_dist | 200 | number >= 0; raises pwt_inner_dist's partner rule | done |
//! | pwt_inner_dist | 50 | number >= 0; pwt_outer_dist raised to it if lower | done |
//! | max_util_cpa_dist | 75 | number >= 0; min lowered to it if higher | done |
//! | min_util_cpa_dist | 10 | number >= 0; max raised to it if lower | done |
//! | completed_dist | 500 | number >= 0 | done |
//! | pwt_grade | quasi | linear, quadratic, quasi (any case) | done |
//! | roc_max_heighten | 2 | number >= 0 (dampen lowered to it) | done (read; unused by the C++ function) |
//! | roc_max_dampen | -2 | number >= 0 | done (read; unused) |
//! | time_on_leg | 120 | number >= 0 | done |
//! | contact_type_required | none | as `match_type` | done |
//! | no_alert_request | false | boolean | done |
//! | collision_depth | 0 | `atof` > 0 and a `depth` domain, else refused; at or below the depth domain's high end accepted and ignored | done: the objective becomes [`crate::aof_avoid_collision_depth`]'s over course, speed and depth |
//! | use_refinery | false | boolean (`setBooleanOnString`) | done: the plateau regions of [`crate::refinery_cpa`] (MOOS `RefineryCPA`, time on leg `time_on_leg`, the unhalved `min_util_cpa_dist`) cut out of the 3 × 3 pieces, each a piece at the AOF's known maximum (the utility of the present range) |
//! | check_plateaus | false | boolean | done: with `use_refinery`, every point of every plateau checked against that maximum (`OF_Reflector::checkPlateaus`) |
//! | check_validity | false | boolean | done: `VALID_CHECK_OK` (every grid point in exactly one piece, `PDMap::valid`), with or without the refinery |
//! | verbose | false | boolean | done: gates `PLATEAU_CHECK_OK` and `PLATEAU_LOGIC_CASE` (the C++ prints to the console as well; coug does not) |
//! | pcheck_thresh | 0.001 | number >= 0 | done: the check's threshold; outside `[0, 1]` the reflector keeps 0.001 and warns (`AVD_DEBUG`) |
//! | can_disable | false | boolean | done: `BHV_ABLE_FILTER` disables, enables or expunges it (`contact::ContactBase::apply_able_filter`); disabled, it erases its bearing line and completes as when idle |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | BCM_ALERT_REQUEST | helm start, for a spawning template with an `updates` variable, unless `no_alert_request` | `id=<name>, on_flag=<UPDATES>=name=$[VNAME] # contact=$[VNAME],alert_range=<outer>, cpa_range=<completed>` then the filters | done |
//! | AVD_DEBUG | each running iteration with a contact | `In getRelevance: <range, 5 decimals>` | done |
//! | AVD_DEBUG | `check_plateaus` with `pcheck_thresh` outside `[0, 1]` (the reflector's warnings) | `pcheck_thresh value must be in range [0,1]` | done |
//! | PLATEAU_CHECK_OK | `use_refinery`, `check_plateaus` and `verbose` | `true`/`false` (on change) | done |
//! | PLATEAU_LOGIC_CASE | as PLATEAU_CHECK_OK | `aft`, `fore_in_rgam`, `fore_out_rgam` (repeatable) | done |
//! | PLATEAU_WORST_FAIL | `use_refinery`, `check_plateaus`, a plateau point off the maximum by more than `pcheck_thresh` | the worst difference (repeatable) | done |
//! | VALID_CHECK_OK | `check_validity` | `true`/`false` (on change) | done |
//! | AVD_STATUS | each depth-aware function (`collision_depth`) | the reflector's warnings (empty) | done |
//! | RANGE_AVD_<contact>, CLSG_SPD_AVD_<contact> | `post_per_contact_info` | range (whole metres beyond 10 m), closing speed to 0.1 | done |
//! | VIEW_SEGLIST | bearing lines configured | see [`crate::contact`] | done |

use ivp::IvpFunction;

use crate::aof_avoid_collision_depth::AofAvoidCollisionDepth;
use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::colregs::geometry::Cpx;
use crate::common::Common;
use crate::contact::ContactBase;
use crate::contact_state::{Distances, reflect};
use crate::param::is_number;
use crate::refinery_cpa::{
    PairGeometry, Refined, RefineryCpa, RefinerySettings, covers_once, distances_cpa,
    post_avoid_checks, reflect_refined,
};

/// How the relevance grows as the contact closes (`pwt_grade`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PwtGrade {
    /// Proportional.
    Linear,
    /// Squared.
    Quadratic,
    /// To the power 1.5 (the default).
    Quasi,
}

/// BHV_AvoidCollision.
#[derive(Debug, Clone)]
pub struct AvoidCollision {
    /// The contact and the shared contact parameters.
    pub base: ContactBase,
    /// `pwt_outer_dist`, m.
    pub pwt_outer_dist: f64,
    /// `pwt_inner_dist`, m.
    pub pwt_inner_dist: f64,
    /// `min_util_cpa_dist`, m.
    pub min_util_cpa_dist: f64,
    /// `max_util_cpa_dist`, m.
    pub max_util_cpa_dist: f64,
    /// `completed_dist`, m.
    pub completed_dist: f64,
    /// `pwt_grade`.
    pub pwt_grade: PwtGrade,
    /// `roc_max_heighten`.
    pub roc_max_heighten: f64,
    /// `roc_max_dampen`.
    pub roc_max_dampen: f64,
    /// `no_alert_request`.
    pub no_alert_request: bool,
    /// `collision_depth`, m (0: none): the depth-aware objective
    /// ([`crate::aof_avoid_collision_depth`]) instead of the course-speed one.
    pub collision_depth: f64,
    update_var: String,
    spawnable: bool,
    flags: [bool; 6],
    pcheck_thresh: f64,
}

impl Default for AvoidCollision {
    fn default() -> Self {
        Self::new()
    }
}

impl AvoidCollision {
    /// The C++ defaults.
    pub fn new() -> Self {
        AvoidCollision {
            base: ContactBase::new(120.0),
            pwt_outer_dist: 200.0,
            pwt_inner_dist: 50.0,
            min_util_cpa_dist: 10.0,
            max_util_cpa_dist: 75.0,
            completed_dist: 500.0,
            pwt_grade: PwtGrade::Quasi,
            roc_max_heighten: 2.0,
            roc_max_dampen: -2.0,
            no_alert_request: false,
            collision_depth: 0.0,
            update_var: String::new(),
            spawnable: false,
            flags: [false; 6],
            pcheck_thresh: 0.001,
        }
    }

    /// The relevance at range `r` (MOOS `getRelevance`).
    pub fn relevance_at(&self, r: f64) -> f64 {
        if r >= self.pwt_outer_dist {
            return 0.0;
        }
        let pct = (self.pwt_outer_dist - r) / (self.pwt_outer_dist - self.pwt_inner_dist);
        match self.pwt_grade {
            PwtGrade::Linear => pct,
            PwtGrade::Quadratic => pct * pct,
            PwtGrade::Quasi => pct.powf(1.5),
        }
    }

    /// The utility of a CPA distance `d` (MOOS `AOF_AvoidCollision::metric`).
    pub fn metric(d: f64, min: f64, max: f64) -> f64 {
        if d < min {
            0.0
        } else if d > max {
            100.0
        } else {
            25.0 + 75.0 * (d - min) / (max - min)
        }
    }

    /// The objective function for the present geometry (before the weight), or `None` if
    /// the reflector fails.
    pub fn objective(&self, ctx: &Ctx<'_>) -> Option<IvpFunction> {
        let mut d = Distances::for_contact(
            &self.base,
            self.base.time_on_leg,
            self.min_util_cpa_dist,
            self.max_util_cpa_dist,
        )?;
        // `use_plat_model`: the CPA along the model handed to the engine this iteration.
        d.pm = self.base.plat_cpx(self.base.engine_model.clone());
        let (min, max) = (d.collision_distance, d.all_clear_distance);
        reflect(ctx.domain, |crs, spd| {
            Self::metric(d.cpa(crs, spd), min, max)
        })
    }

    /// The refinery parameters (`use_refinery`, `check_plateaus`, `check_validity`,
    /// `pcheck_thresh`, `verbose`).
    pub fn refinery_settings(&self) -> RefinerySettings {
        RefinerySettings {
            use_refinery: self.flags[2],
            check_plateaus: self.flags[3],
            check_validity: self.flags[5],
            pcheck_thresh: self.pcheck_thresh,
            verbose: self.flags[1],
        }
    }

    /// The objective refined (MOOS `getAvoidIPF` with `use_refinery`: `RefineryCPA`'s plateau
    /// regions handed to the reflector, each a piece of the AOF's known maximum, the utility
    /// of the present range), with the plateau checks when `check_plateaus` is set, and what
    /// the refinery found; `None` as [`AvoidCollision::objective`].
    pub fn objective_refined(&self, ctx: &Ctx<'_>) -> Option<(IvpFunction, Refined)> {
        let mut d = Distances::for_contact(
            &self.base,
            self.base.time_on_leg,
            self.min_util_cpa_dist,
            self.max_util_cpa_dist,
        )?;
        // `use_plat_model`: the CPA along the model handed to the engine this iteration.
        d.pm = self.base.plat_cpx(self.base.engine_model.clone());
        let (min, max) = (d.collision_distance, d.all_clear_distance);
        let settings = self.refinery_settings();
        let known = (0.0, Self::metric(d.engine.range(), min, max));
        let (osx, osy, osh, osv) = self.base.os;
        let (cnx, cny, cnh, cnv) = self.base.cn;
        let geo = PairGeometry::of(&Cpx::new(cnx, cny, cnh, cnv, osx, osy, osh, osv));
        let refinery = |dom: &ivp::Domain| {
            RefineryCpa::new(
                dom,
                geo,
                self.base.time_on_leg,
                self.min_util_cpa_dist,
                self.max_util_cpa_dist,
                |h, s, t| distances_cpa(&d, h, s, t),
            )
        };
        reflect_refined(ctx.domain, refinery, &settings, Some(known), |crs, spd| {
            Self::metric(d.cpa(crs, spd), min, max)
        })
    }

    /// The objective of a running iteration with the refinery's and the checks' postings
    /// (MOOS `getAvoidIPF`): with `use_refinery`, [`AvoidCollision::objective_refined`] and
    /// its checks ([`crate::refinery_cpa::post_avoid_checks`]), the reflector's warnings on
    /// `AVD_DEBUG`; with `check_validity`, `VALID_CHECK_OK` (every grid point in one piece).
    fn objective_checked(&self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let settings = self.refinery_settings();
        let f = if settings.use_refinery {
            let (f, info) = self.objective_refined(ctx)?;
            post_avoid_checks(&info, settings.verbose, out);
            if !info.warnings.is_empty() {
                out.post("AVD_DEBUG", info.warnings);
            }
            f
        } else {
            self.objective(ctx)?
        };
        if settings.check_validity {
            let ok = if covers_once(&f) { "true" } else { "false" };
            out.post("VALID_CHECK_OK", ok);
        }
        Some(f)
    }

    /// The depth-aware objective for the present geometry (MOOS `getAvoidDepthIPF`, see
    /// [`crate::aof_avoid_collision_depth`]), before the weight; `None` without a course,
    /// speed and depth domain.
    pub fn depth_objective(&self, ctx: &Ctx<'_>) -> Option<IvpFunction> {
        let (_, _, osh, osv) = self.base.os;
        AofAvoidCollisionDepth::new(
            ctx.domain,
            self.base.cpa_engine(),
            osh,
            osv,
            self.base.time_on_leg,
            self.min_util_cpa_dist,
            self.max_util_cpa_dist,
            self.collision_depth,
        )?
        .build(ctx.domain)
    }

    fn post_range(&self, out: &mut Out) {
        if !self.base.post_per_contact_info {
            return;
        }
        let c = &self.base.contact;
        let (_, _, osh, osv) = self.base.os;
        let roc = self.base.cpa_engine().eval_roc(osh, osv);
        out.post(format!("CLSG_SPD_AVD_{c}"), (roc / 0.1).round() * 0.1);
        if self.base.range <= 10.0 {
            out.post(format!("RANGE_AVD_{c}"), self.base.range);
        } else {
            out.post_int(format!("RANGE_AVD_{c}"), self.base.range);
        }
    }

    fn done(&self) -> bool {
        !self.base.filter_holds() || self.base.range >= self.completed_dist * 1.1
    }
}

/// `setMinPartOfPairOnString`: a number >= 0 for the low end, the high end raised to it.
fn set_low(lo: &mut f64, hi: &mut f64, param: &str, v: &str) -> Result<(), ParamError> {
    let d = nonneg(param, v)?;
    *lo = d;
    if *hi < *lo {
        *hi = *lo;
    }
    Ok(())
}

/// `setMaxPartOfPairOnString`: a number >= 0 for the high end, the low end lowered to it.
fn set_high(lo: &mut f64, hi: &mut f64, param: &str, v: &str) -> Result<(), ParamError> {
    let d = nonneg(param, v)?;
    *hi = d;
    if *lo > *hi {
        *lo = *hi;
    }
    Ok(())
}

fn nonneg(param: &str, v: &str) -> Result<f64, ParamError> {
    if is_number(v) && geometry::atof(v) >= 0.0 {
        Ok(geometry::atof(v))
    } else {
        Err(ParamError::bad(param, v, "a number >= 0"))
    }
}

impl Behavior for AvoidCollision {
    /// IvPContactBehavior's post mortem: the reason, range and bearing to the contact.
    fn post_mortem(&self, reason: &str) -> String {
        self.base.post_mortem(reason)
    }

    fn kind(&self) -> &'static str {
        "BHV_AvoidCollision"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        if self.collision_depth > 0.0 {
            &["course", "speed", "depth"]
        } else {
            &["course", "speed"]
        }
    }

    fn default_name(&self) -> &'static str {
        "avoid_collision"
    }

    fn is_constraint(&self) -> bool {
        true
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        if let Some(r) = self.base.set_param(param, value) {
            return r;
        }
        match param {
            "pwt_inner_dist" => set_low(
                &mut self.pwt_inner_dist,
                &mut self.pwt_outer_dist,
                param,
                value,
            ),
            "pwt_outer_dist" => set_high(
                &mut self.pwt_inner_dist,
                &mut self.pwt_outer_dist,
                param,
                value,
            ),
            "min_util_cpa_dist" => set_low(
                &mut self.min_util_cpa_dist,
                &mut self.max_util_cpa_dist,
                param,
                value,
            ),
            "max_util_cpa_dist" => set_high(
                &mut self.min_util_cpa_dist,
                &mut self.max_util_cpa_dist,
                param,
                value,
            ),
            "completed_dist" => {
                self.completed_dist = nonneg(param, value)?;
                Ok(())
            }
            "contact_type_required" if !value.is_empty() => {
                self.base.set_param("match_type", value).unwrap_or(Ok(()))
            }
            "collision_depth" => {
                // MOOS: > 0 with a depth domain; at or below the domain's deepest it is
                // accepted and changes nothing.
                let d = geometry::atof(value);
                match ctx.domain.get("depth").map(|v| v.high()) {
                    Some(h) if d > 0.0 => {
                        if d < h {
                            self.collision_depth = d;
                        }
                        Ok(())
                    }
                    _ => Err(ParamError::bad(
                        param,
                        value,
                        "a depth > 0 with a depth decision variable",
                    )),
                }
            }
            "pwt_grade" => {
                self.pwt_grade = match value.to_ascii_lowercase().as_str() {
                    "linear" => PwtGrade::Linear,
                    "quadratic" => PwtGrade::Quadratic,
                    "quasi" => PwtGrade::Quasi,
                    _ => return Err(ParamError::bad(param, value, "linear, quadratic or quasi")),
                };
                Ok(())
            }
            "roc_max_heighten" => {
                self.roc_max_heighten = nonneg(param, value)?;
                if self.roc_max_dampen > self.roc_max_heighten {
                    self.roc_max_dampen = self.roc_max_heighten;
                }
                Ok(())
            }
            "roc_max_dampen" => {
                // The C++ compares heighten with itself here, so nothing else changes.
                self.roc_max_dampen = nonneg(param, value)?;
                Ok(())
            }
            "pcheck_thresh" => {
                self.pcheck_thresh = nonneg(param, value)?;
                Ok(())
            }
            "no_alert_request" | "verbose" | "use_refinery" | "check_plateaus"
            | "check_validity" | "can_disable" => {
                let i = [
                    "no_alert_request",
                    "verbose",
                    "use_refinery",
                    "check_plateaus",
                    "can_disable",
                    "check_validity",
                ]
                .iter()
                .position(|p| *p == param)
                .unwrap_or(0);
                let b = crate::param::moos_boolean(param, value, self.flags[i])?;
                self.flags[i] = b;
                if param == "can_disable" {
                    self.base.can_disable = b;
                }
                if param == "no_alert_request" {
                    self.no_alert_request = b;
                }
                Ok(())
            }
            _ => Err(ParamError::unknown(param)),
        }
    }

    fn set_common(&mut self, common: &Common) {
        self.update_var.clone_from(&common.update_var);
        self.spawnable = common.templating.spawns();
    }

    fn contact_name(&self) -> Option<&str> {
        self.base.contact_name()
    }

    fn on_helm_start(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        if self.no_alert_request || self.update_var.is_empty() || !self.spawnable {
            return;
        }
        let ranges = (self.pwt_outer_dist, self.completed_dist);
        post_alert_request(ctx.name, &self.update_var, ranges, &self.base, out);
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(
            out,
            ["NAV_X", "NAV_Y", "NAV_SPEED", "NAV_HEADING", "AVOIDING"],
        );
    }

    fn macro_value(&self, name: &str, out: &mut String) -> bool {
        self.base.macro_value(name, out)
    }

    fn pwt_factor(&self) -> f64 {
        self.base.relevance
    }

    fn on_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        if !self.base.update(ctx, out) {
            return;
        }
        self.post_range(out);
        if self.done() {
            out.complete();
        }
    }

    fn apply_able_filter(&mut self, msg: &str, out: &mut Out) -> bool {
        let kind = self.kind();
        crate::contact::able_filter_hook(&mut self.base, msg, kind, out)
    }

    fn is_disabled(&self) -> bool {
        self.base.disabled
    }

    /// MOOS `onDisabledState`: the bearing line erased, completion as when idle (on the
    /// range of the last update).
    fn on_disabled(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.base.update(ctx, out);
        self.base.post_bearing_line(ctx, out, false);
        if self.done() {
            out.complete();
        }
    }

    fn on_run_to_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.base.post_bearing_line(ctx, out, false);
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        self.base.relevance = 0.0;
        if !self.base.update(ctx, out) {
            self.post_range(out);
            return None;
        }
        self.base.post_contact_flags(out);
        self.post_range(out);
        if self.done() {
            out.complete();
            return None;
        }
        let r = self.base.range;
        let mut dbg = String::from("In getRelevance: ");
        moos_types::fmt::fixed(&mut dbg, r, 5);
        out.post("AVD_DEBUG", dbg);
        let relevance = self.relevance_at(r);
        if relevance <= 0.0 {
            return None;
        }
        self.base.relevance = relevance;
        // The platform-model engine gets this iteration's model (after the update, so the
        // contact state read the previous one, as the C++).
        self.base.hand_model(ctx);
        let f = if self.collision_depth > 0.0 {
            let f = self.depth_objective(ctx);
            if f.is_some() {
                // MOOS posts the reflector's warnings each time (none from coug's).
                out.post("AVD_STATUS", "");
            }
            f
        } else {
            self.objective_checked(ctx, out)
        };
        let Some(mut f) = f else {
            out.error("Unable to init AOF_AvoidCollision.");
            return None;
        };
        f.normalize(0.0, 100.0);
        self.base.post_bearing_line(ctx, out, true);
        Some(f)
    }
}

/// Posts a spawning contact template's `BCM_ALERT_REQUEST` at helm start (BHV_AvoidCollision
/// and the AvdColregs family): its name as the alert's id, a flag on its `updates` variable
/// naming the contact, `(alert_range, cpa_range)` as given, then the contact filters of
/// `base`.
pub(crate) fn post_alert_request(
    name: &str,
    update_var: &str,
    (alert_range, cpa_range): (f64, f64),
    base: &ContactBase,
    out: &mut Out,
) {
    let mut req = format!(
        "id={name}, on_flag={update_var}=name=$[VNAME] # contact=$[VNAME],alert_range={}, cpa_range={}",
        moos_types::fmt::compact_string(alert_range, 1),
        moos_types::fmt::compact_string(cpa_range, 1),
    );
    let filters = base.filter.summary();
    if !filters.is_empty() {
        req.push(',');
        req.push_str(&filters);
    }
    out.post("BCM_ALERT_REQUEST", req);
}
