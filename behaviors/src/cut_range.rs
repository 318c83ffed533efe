//! BHV_CutRange (MOOS-IvP `BHV_CutRange` with `AOF_CutRangeCPA` at a2a9b716): closes the
//! range to a contact, trading the rate of closure against the CPA distance.
//!
//! Each running iteration, with the range `r` to the contact:
//! - pursuit: with `giveup_range > 0`, ownship is in pursuit while `r <= giveup_range + 1`
//!   (`pursueflag`s posted on entering, `giveupflag`s on leaving); with `giveup_range` 0 the
//!   C++ never enters pursuit, so the behaviour never produces a function (kept as is);
//! - relevance: 0 unless in pursuit; 1 at or beyond `pwt_outer_dist`; 0 inside
//!   `pwt_inner_dist`; else `(r − inner) / (outer − inner)`; 0 when the two are equal;
//! - objective at `(course, speed)`: `(1 − p)·nroc + p·m` with `p = patience / 100`,
//!   `nroc = 100 · (roc − min_roc) / (max_roc − min_roc)` (the rate of closure normalised
//!   over every heading at the domain's top speed) and `m = 100 · (1 − cpa / r)` (0 when the
//!   CPA over `time_on_leg` exceeds `r`); sampled in course 2 × speed 3 pieces, normalised
//!   0..100, weighted by `relevance · pwt`.
//!
//! # Conformance with BHV_CutRange (MOOS-IvP a2a9b716)
//!
//! | parameter | default | validation (C++ rule) | coug |
//! |---|---|---|---|
//! | pwt_outer_dist, pwt_inner_dist | 0, 0 | number >= 0, kept ordered | done |
//! | giveup_dist, giveup_range | 0 (never) | number >= 0 | done |
//! | pursueflag, giveupflag | none | `VAR=VALUE` | done |
//! | patience | 0 | 0..100 | done; lowered to `max_patience` |
//! | max_patience | 85 | 0..100 | done |
//! | time_on_leg | 15 | number >= 0 (the function needs >= 1) | done |
//! | contact parameters | | see [`crate::contact`] | done |
//! | use_refinery, check_plateaus, pcheck_thresh | not parameters | the C++ includes `RefineryCPA.h` but neither reads nor uses them: unknown, so MALCONFIG | done (refused) |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | BCM_ALERT_REQUEST | helm start of a spawning template | `id=<name>, on_flag=<UPDATES>=name=$[VNAME] # contact=$[VNAME],alert_range=<outer>, cpa_range=<outer+1>` then the filters | done |
//! | BHV_WARNING | the function cannot be built | `Error in initializing AOF_CutRangeCPA.` | done |

use ivp::{IvpFunction, Reflector};

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::common::{Common, Flag};
use crate::contact::ContactBase;
use crate::cpa::CpaEngine;
use crate::param::is_number;

/// BHV_CutRange.
#[derive(Debug, Clone)]
pub struct CutRange {
    /// The contact and the shared contact parameters.
    pub base: ContactBase,
    /// `pwt_outer_dist`, m.
    pub pwt_outer_dist: f64,
    /// `pwt_inner_dist`, m.
    pub pwt_inner_dist: f64,
    /// `giveup_range`, m (0: never give up).
    pub giveup_range: f64,
    /// `patience`, 0..100.
    pub patience: f64,
    /// `max_patience`, 0..100.
    pub max_patience: f64,
    /// `pursueflag`s.
    pub pursue_flags: Vec<Flag>,
    /// `giveupflag`s.
    pub giveup_flags: Vec<Flag>,
    in_pursuit: bool,
    update_var: String,
    spawnable: bool,
}

impl Default for CutRange {
    fn default() -> Self {
        Self::new()
    }
}

impl CutRange {
    /// The C++ defaults.
    pub fn new() -> Self {
        CutRange {
            base: ContactBase::new(15.0),
            pwt_outer_dist: 0.0,
            pwt_inner_dist: 0.0,
            giveup_range: 0.0,
            patience: 0.0,
            max_patience: 85.0,
            pursue_flags: Vec::new(),
            giveup_flags: Vec::new(),
            in_pursuit: false,
            update_var: String::new(),
            spawnable: false,
        }
    }

    /// The relevance at range `r` while in pursuit (MOOS `getRelevance`).
    pub fn relevance_at(&self, r: f64) -> f64 {
        let total = self.pwt_outer_dist - self.pwt_inner_dist;
        if total == 0.0 || !self.in_pursuit {
            return 0.0;
        }
        if r >= self.pwt_outer_dist {
            return 1.0;
        }
        if r < self.pwt_inner_dist {
            return 0.0;
        }
        (r - self.pwt_inner_dist) / total
    }

    /// Sets the pursuit state (for tests of the objective).
    pub fn set_in_pursuit(&mut self, b: bool) {
        self.in_pursuit = b;
    }

    /// The objective's value at `(course, speed)` (MOOS `AOF_CutRangeCPA::evalBox`), for
    /// the engine of the present geometry, the range `dist` to the contact, the rate of
    /// closure bounds and the horizon `tol`.
    pub fn aof(
        &self,
        engine: &CpaEngine,
        dist: f64,
        roc_bounds: (f64, f64),
        course: f64,
        speed: f64,
    ) -> f64 {
        let cpa = engine.eval_cpa(course, speed, self.base.time_on_leg);
        let roc = engine.eval_roc(course, speed);
        let metric = if cpa < 0.0 {
            100.0
        } else if cpa > dist {
            0.0
        } else {
            100.0 - cpa / dist * 100.0
        };
        let (min_roc, max_roc) = roc_bounds;
        let range = max_roc - min_roc;
        let nroc = if range > 0.0 {
            (roc - min_roc) / range * 100.0
        } else {
            0.0
        };
        let pct = self.patience / 100.0;
        (1.0 - pct) * nroc + pct * metric
    }

    /// The lowest and highest rate of closure over the 360 whole-degree headings at `speed`
    /// (MOOS `minMaxROC`).
    pub fn roc_bounds(engine: &CpaEngine, speed: f64) -> (f64, f64) {
        let (mut lo, mut hi) = (0.0, 0.0);
        for h in 0..360 {
            let r = engine.eval_roc(f64::from(h), speed);
            if h == 0 || r > hi {
                hi = r;
            }
            if h == 0 || r < lo {
                lo = r;
            }
        }
        (lo, hi)
    }

    /// The objective function for the present geometry (before normalising and the weight).
    pub fn objective(&self, ctx: &Ctx<'_>) -> Option<IvpFunction> {
        if self.base.time_on_leg < 1.0 || self.base.range <= 0.0 {
            return None;
        }
        let mut domain = ivp::Domain::new();
        domain.add(ctx.domain.get("course")?.clone()).ok()?;
        let spd = ctx.domain.get("speed")?.clone();
        let top = spd.high();
        domain.add(spd).ok()?;
        let engine = self.base.cpa_engine();
        let bounds = Self::roc_bounds(&engine, top);
        let dist = self.base.range;
        Reflector::new(&domain, |v: &[f64]| {
            self.aof(&engine, dist, bounds, v[0], v[1])
        })
        .set_param("uniform_piece", "course:2,speed:3")
        .ok()?
        .build()
        .ok()
    }

    fn check_pursuit(&mut self, out: &mut Out) {
        if self.giveup_range <= 0.0 {
            return;
        }
        let in_pursuit = self.base.range <= self.giveup_range + 1.0;
        if in_pursuit && !self.in_pursuit {
            for f in &self.pursue_flags {
                out.flag(f, false);
            }
        }
        if !in_pursuit && self.in_pursuit {
            for f in &self.giveup_flags {
                out.flag(f, false);
            }
        }
        self.in_pursuit = in_pursuit;
    }
}

fn strict_range(param: &str, v: &str, lo: f64, hi: f64) -> Result<f64, ParamError> {
    let d = geometry::atof(v);
    if is_number(v) && (lo..=hi).contains(&d) {
        Ok(d)
    } else {
        Err(ParamError::bad(param, v, "a number from 0 to 100"))
    }
}

impl Behavior for CutRange {
    /// IvPContactBehavior's post mortem: the reason, range and bearing to the contact.
    fn post_mortem(&self, reason: &str) -> String {
        self.base.post_mortem(reason)
    }

    fn kind(&self) -> &'static str {
        "BHV_CutRange"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course", "speed"]
    }

    fn default_name(&self) -> &'static str {
        "bhv_cutrange"
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
        let nonneg = |v: &str| {
            if is_number(v) && geometry::atof(v) >= 0.0 {
                Ok(geometry::atof(v))
            } else {
                Err(ParamError::bad(param, v, "a number >= 0"))
            }
        };
        match param {
            "pwt_inner_dist" => {
                self.pwt_inner_dist = nonneg(value)?;
                if self.pwt_outer_dist < self.pwt_inner_dist {
                    self.pwt_outer_dist = self.pwt_inner_dist;
                }
            }
            "pwt_outer_dist" => {
                self.pwt_outer_dist = nonneg(value)?;
                if self.pwt_inner_dist > self.pwt_outer_dist {
                    self.pwt_inner_dist = self.pwt_outer_dist;
                }
            }
            "giveup_dist" | "giveup_range" => self.giveup_range = nonneg(value)?,
            "pursueflag" | "giveupflag" => {
                let f =
                    Flag::parse(value).ok_or_else(|| ParamError::bad(param, value, "VAR=VALUE"))?;
                if param == "pursueflag" {
                    self.pursue_flags.push(f);
                } else {
                    self.giveup_flags.push(f);
                }
            }
            "patience" => self.patience = strict_range(param, value, 0.0, 100.0)?,
            "max_patience" => self.max_patience = strict_range(param, value, 0.0, 100.0)?,
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn on_set_param_complete(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        if self.patience > self.max_patience {
            self.patience = self.max_patience;
        }
        crate::behavior::post_config_status(&*self, ctx, out);
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
        if self.update_var.is_empty() || !self.spawnable {
            return;
        }
        let mut req = format!(
            "id={}, on_flag={}=name=$[VNAME] # contact=$[VNAME],alert_range={}, cpa_range={}",
            ctx.name,
            self.update_var,
            moos_types::fmt::compact_string(self.pwt_outer_dist, 1),
            moos_types::fmt::compact_string(self.pwt_outer_dist + 1.0, 1),
        );
        let filters = self.base.filter.summary();
        if !filters.is_empty() {
            req.push(',');
            req.push_str(&filters);
        }
        out.post("BCM_ALERT_REQUEST", req);
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_X", "NAV_Y"]);
    }

    fn pwt_factor(&self) -> f64 {
        self.base.relevance
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        self.base.relevance = 0.0;
        if !self.base.update(ctx, out) {
            return None;
        }
        self.base.post_contact_flags(out);
        self.check_pursuit(out);
        let relevance = self.relevance_at(self.base.range);
        if relevance <= 0.0 {
            return None;
        }
        let Some(mut f) = self.objective(ctx) else {
            out.warning(ctx.name, "Error in initializing AOF_CutRangeCPA.");
            return None;
        };
        f.normalize(0.0, 100.0);
        self.base.relevance = relevance;
        Some(f)
    }
}
