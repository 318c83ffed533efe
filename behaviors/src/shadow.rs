//! BHV_Shadow (MOOS-IvP `BHV_Shadow` at a2a9b716): matches a contact's heading and speed.
//!
//! Each running iteration: relevance 1 when `pwt_outer_dist` is 0 or the contact is nearer
//! than it, else 0 (no function); the objective couples (50/50, normalised to 0..100) a
//! ZAIC_PEAK over course (summit the contact's heading, wrapping, `heading_peakwidth` 20,
//! `heading_basewidth` 160, summit delta 50, utilities 0..100) and one over speed (summit the
//! contact's speed, `speed_peakwidth` 0.1, `speed_basewidth` 2, summit delta 10), weighted by
//! `relevance · pwt`. (The C++ `AOF_Shadow` is not used by the behaviour.)
//!
//! # Conformance with BHV_Shadow (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | default | validation (C++ rule) | coug |
//! |---|---|---|---|---|
//! | pwt_outer_dist | | 0 (always relevant) | number >= 0 | done |
//! | heading_peakwidth | hdg_peakwidth | 20 | number >= 0 | done |
//! | heading_basewidth | hdg_basewidth | 160 | number >= 0 | done |
//! | speed_peakwidth | spd_peakwidth | 0.1 | number >= 0 | done |
//! | speed_basewidth | spd_basewidth | 2 | number >= 0 | done |
//! | contact parameters | | | see [`crate::contact`] | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | SHADOW_CONTACT_X, SHADOW_CONTACT_Y, SHADOW_CONTACT_SPEED, SHADOW_CONTACT_HEADING, SHADOW_RELEVANCE | each running iteration with a contact | rounded to integers | done |

use ivp::{IvpFunction, ZaicPeak, couple};

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::common::Common;
use crate::contact::ContactBase;
use crate::param::is_number;

/// BHV_Shadow.
#[derive(Debug, Clone)]
pub struct Shadow {
    /// The contact and the shared contact parameters.
    pub base: ContactBase,
    /// `pwt_outer_dist`, m (0: always relevant).
    pub pwt_outer_dist: f64,
    /// `heading_peakwidth`, degrees.
    pub hdg_peakwidth: f64,
    /// `heading_basewidth`, degrees.
    pub hdg_basewidth: f64,
    /// `speed_peakwidth`, m/s.
    pub spd_peakwidth: f64,
    /// `speed_basewidth`, m/s.
    pub spd_basewidth: f64,
}

impl Default for Shadow {
    fn default() -> Self {
        Self::new()
    }
}

impl Shadow {
    /// The C++ defaults.
    pub fn new() -> Self {
        Shadow {
            base: ContactBase::new(60.0),
            pwt_outer_dist: 0.0,
            hdg_peakwidth: 20.0,
            hdg_basewidth: 160.0,
            spd_peakwidth: 0.1,
            spd_basewidth: 2.0,
        }
    }

    /// The relevance at range `r` (MOOS `getRelevance`).
    pub fn relevance_at(&self, r: f64) -> f64 {
        if self.pwt_outer_dist == 0.0 || r < self.pwt_outer_dist {
            1.0
        } else {
            0.0
        }
    }

    /// The objective for a contact heading `cnh` at `cnv` (normalised, before the weight).
    pub fn objective(&self, ctx: &Ctx<'_>, cnh: f64, cnv: f64) -> Result<IvpFunction, String> {
        let mut hdg = ZaicPeak::new(ctx.domain, "course").map_err(|e| e.to_string())?;
        hdg.set_value_wrap(true);
        hdg.set_params(
            cnh,
            self.hdg_peakwidth,
            self.hdg_basewidth,
            50.0,
            0.0,
            100.0,
        )
        .map_err(|e| format!("Unable to generate hdg component of IvP function: {e}"))?;
        let hdg = hdg
            .extract()
            .map_err(|e| format!("Unable to generate hdg component of IvP function: {e}"))?;
        let mut spd = ZaicPeak::new(ctx.domain, "speed").map_err(|e| e.to_string())?;
        spd.set_params(
            cnv,
            self.spd_peakwidth,
            self.spd_basewidth,
            10.0,
            0.0,
            100.0,
        )
        .map_err(|e| format!("Unable to generate spd component of IvP function: {e}"))?;
        let spd = spd
            .extract()
            .map_err(|e| format!("Unable to generate spd component of IvP function: {e}"))?;
        let mut f = couple(&hdg, &spd)
            .map_err(|e| format!("Unable to generate coupled IvP function: {e}"))?;
        f.normalize(0.0, 100.0);
        Ok(f)
    }
}

impl Behavior for Shadow {
    /// IvPContactBehavior's post mortem: the reason, range and bearing to the contact.
    fn post_mortem(&self, reason: &str) -> String {
        self.base.post_mortem(reason)
    }

    fn kind(&self) -> &'static str {
        "BHV_Shadow"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course", "speed"]
    }

    fn default_name(&self) -> &'static str {
        "bhv_shadow"
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
        let slot = match param {
            "pwt_outer_dist" => &mut self.pwt_outer_dist,
            "heading_peakwidth" | "hdg_peakwidth" => &mut self.hdg_peakwidth,
            "heading_basewidth" | "hdg_basewidth" => &mut self.hdg_basewidth,
            "speed_peakwidth" | "spd_peakwidth" => &mut self.spd_peakwidth,
            "speed_basewidth" | "spd_basewidth" => &mut self.spd_basewidth,
            _ => return Err(ParamError::unknown(param)),
        };
        if is_number(value) && geometry::atof(value) >= 0.0 {
            *slot = geometry::atof(value);
            Ok(())
        } else {
            Err(ParamError::bad(param, value, "a number >= 0"))
        }
    }

    fn contact_name(&self) -> Option<&str> {
        self.base.contact_name()
    }

    fn macro_value(&self, name: &str, out: &mut String) -> bool {
        self.base.macro_value(name, out)
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_X", "NAV_Y", "NAV_SPEED", "NAV_HEADING"]);
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
        let relevance = self.relevance_at(self.base.range);
        let (cnx, cny, cnh, cnv) = self.base.cn;
        out.post_int("SHADOW_CONTACT_X", cnx);
        out.post_int("SHADOW_CONTACT_Y", cny);
        out.post_int("SHADOW_CONTACT_SPEED", cnv);
        out.post_int("SHADOW_CONTACT_HEADING", cnh);
        out.post_int("SHADOW_RELEVANCE", relevance);
        if relevance <= 0.0 {
            return None;
        }
        match self.objective(ctx, cnh, cnv) {
            Ok(f) => {
                self.base.relevance = relevance;
                Some(f)
            }
            Err(e) => {
                out.error(e);
                None
            }
        }
    }
}
