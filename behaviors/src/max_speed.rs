//! BHV_MaxSpeed: a ZAIC_LEQ constraint on `speed`.
//!
//! # Conformance with BHV_MaxSpeed (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | max_speed | | m/s | 1 | number (MOOS `isNumber`); negative clipped to 0 | yes | done |
//! | basewidth | tolerance | m/s | 0.5 | number; negative clipped to 0 | yes | done |
//! | speed_slack_var | | var | none | no white space | yes | done |
//! | duration (common) | | s | −1: no time limit | | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | `speed_slack_var` | every iteration, idle or running, with NAV_SPEED (filtered on change) | `max_speed − NAV_SPEED` | done |
//! | BHV_WARNING | idle or running without NAV_SPEED | `No ownship SPEED info in info_buffer.` | done |
//! | BHV_ERROR | no `speed` in the helm domain | `Null IvPDomain given to Behavior` (the helm's check) | done |
//!
//! The type is a constraint (MOOS `isConstraint`): with `goals_mandatory`, a helm with only
//! BHV_MaxSpeed active has no goal behaviour.

use ivp::{IvpFunction, ZaicLeq};

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::common::Common;
use crate::constant_depth::var_name;
use crate::param::number;

/// Caps the speed: ZAIC_LEQ(summit `max_speed`, base width `basewidth`). Speeds at or below
/// `max_speed` get the full utility (rising by a tie-breaking slope toward it), utility falls
/// linearly to 0 over `basewidth` above it.
#[derive(Debug, Clone)]
pub struct MaxSpeed {
    /// The highest allowed speed, m/s.
    pub max_speed: f64,
    /// Width of the ramp above `max_speed`, m/s.
    pub basewidth: f64,
    /// Variable receiving `max_speed − NAV_SPEED` ("" = none).
    pub slack_var: String,
}

impl Default for MaxSpeed {
    fn default() -> Self {
        Self::new()
    }
}

impl MaxSpeed {
    /// The MOOS defaults (`max_speed` 1, `basewidth` 0.5).
    pub fn new() -> Self {
        MaxSpeed {
            max_speed: 1.0,
            basewidth: 0.5,
            slack_var: String::new(),
        }
    }

    /// Posts the slack, or warns without NAV_SPEED (MOOS `updateInfoIn`, idle and running).
    fn update_info_in(&self, ctx: &Ctx<'_>, out: &mut Out) {
        match ctx.info.num("NAV_SPEED") {
            Some(v) if !self.slack_var.is_empty() => {
                out.post(self.slack_var.clone(), self.max_speed - v);
            }
            Some(_) => {}
            None => out.warning(ctx.name, "No ownship SPEED info in info_buffer."),
        }
    }
}

impl Behavior for MaxSpeed {
    fn kind(&self) -> &'static str {
        "BHV_MaxSpeed"
    }

    fn default_name(&self) -> &'static str {
        "maxspd"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["speed"]
    }

    fn is_constraint(&self) -> bool {
        true
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_SPEED"]);
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        match param {
            "max_speed" => self.max_speed = number(param, value)?.max(0.0),
            "basewidth" | "tolerance" => self.basewidth = number(param, value)?.max(0.0),
            "speed_slack_var" => self.slack_var = var_name(param, value)?,
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn on_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.update_info_in(ctx, out);
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        self.update_info_in(ctx, out);
        let mut z = ZaicLeq::new(ctx.domain, "speed").ok()?;
        let built = z
            .set_summit(self.max_speed)
            .and_then(|_| z.set_basewidth(self.basewidth))
            .and_then(|_| z.extract());
        match built {
            Ok(f) => Some(f),
            Err(_) => {
                out.error("Unable to generate max-speed IvP function");
                None
            }
        }
    }
}
