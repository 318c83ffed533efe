//! BHV_MaxDepth (reference §6.8): a ZAIC_LEQ constraint on `depth`.

use ivp::{IvpFunction, ZaicLeq};

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::common::Common;
use crate::constant_depth::var_name;
use crate::memo::FnMemo;
use crate::param::number;

/// Keeps the vehicle shallower than `max_depth`: ZAIC_LEQ(summit `max_depth`, base width
/// `tolerance`/`basewidth`, default 100). Every depth at or above `max_depth` gets the full
/// utility (with a tiny tie-breaking rise toward `max_depth`), utility falls linearly to 0
/// over the tolerance below it, and deeper depths get 0.
///
/// As in MOOS-IvP at a2a9b716: there is no default `duration` (the behaviour never times out
/// unless a `duration` line says so; `BHV_MaxDepth`'s constructor leaves `IvPBehavior`'s −1
/// alone, unlike the constant-* behaviours); negative numbers are clipped to 0; a missing
/// `NAV_DEPTH` only raises a `BHV_WARNING`. `depth_slack_var` receives `max_depth −
/// NAV_DEPTH` every running iteration.
///
/// # Conformance with BHV_MaxDepth (MOOS-IvP a2a9b716)
///
/// | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
/// |---|---|---|---|---|---|---|
/// | max_depth | | m | 0 | number; negative clipped to 0 | yes | done |
/// | basewidth | tolerance | m | 100 | number; negative clipped to 0 | yes | done |
/// | depth_slack_var | | var | none | no white space | yes | done |
/// | duration (common) | | s | −1: no time limit | | yes | done |
///
/// | variable | when | format | coug |
/// |---|---|---|---|
/// | `depth_slack_var` | every running iteration with NAV_DEPTH (filtered on change) | `max_depth − NAV_DEPTH` | done |
/// | BHV_WARNING | running without NAV_DEPTH | `No ownship DEPTH info in info_buffer.` | done |
/// | BHV_ERROR | the function cannot be built | `Unable to generate constant-depth IvP function` | done |
/// | BHV_ERROR | no `depth` in the helm domain | `Null IvPDomain given to Behavior` (the helm's check, before the behaviour runs, as in the C++) | done |
#[derive(Debug, Clone)]
pub struct MaxDepth {
    /// The deepest allowed depth, m.
    pub max_depth: f64,
    /// Width of the ramp below `max_depth`, m.
    pub basewidth: f64,
    /// Variable receiving the depth slack ("" = none).
    pub slack_var: String,
    /// The last function built, reused while its inputs are the same.
    memo: FnMemo<2>,
}

impl Default for MaxDepth {
    fn default() -> Self {
        Self::new()
    }
}

impl MaxDepth {
    /// The MOOS defaults (`max_depth` 0, `basewidth` 100).
    pub fn new() -> Self {
        MaxDepth {
            max_depth: 0.0,
            basewidth: 100.0,
            slack_var: String::new(),
            memo: FnMemo::default(),
        }
    }
}

impl Behavior for MaxDepth {
    fn kind(&self) -> &'static str {
        "BHV_MaxDepth"
    }

    fn default_name(&self) -> &'static str {
        "maxdepth"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["depth"]
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_DEPTH"]);
    }
    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        match param {
            "max_depth" => self.max_depth = number(param, value)?.max(0.0),
            "basewidth" | "tolerance" => self.basewidth = number(param, value)?.max(0.0),
            "depth_slack_var" => self.slack_var = var_name(param, value)?,
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        match ctx.info.num("NAV_DEPTH") {
            Some(d) if !self.slack_var.is_empty() => {
                out.post(self.slack_var.clone(), self.max_depth - d);
            }
            Some(_) => {}
            None => out.warning(ctx.name, "No ownship DEPTH info in info_buffer."),
        }
        let params = [self.max_depth, self.basewidth];
        // Err(false): no depth variable, silently; Err(true): the ZAIC failed (reported).
        let built = self.memo.get_or(ctx.domain, params, || {
            let mut z = ZaicLeq::new(ctx.domain, "depth").map_err(|_| false)?;
            z.set_summit(params[0])
                .and_then(|_| z.set_basewidth(params[1]))
                .and_then(|_| z.extract())
                .map_err(|_| true)
        });
        match built {
            Ok(f) => Some(f),
            // The C++ message says "constant-depth" (copied from BHV_ConstantDepth).
            Err(true) => {
                out.error("Unable to generate constant-depth IvP function");
                None
            }
            Err(false) => None,
        }
    }
}
