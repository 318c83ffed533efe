//! BHV_ConstantDepth (reference §6.3): a ZAIC_PEAK preference on `depth`.
//!
//! # Conformance with BHV_ConstantDepth (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | depth | | m | 0 | number; negative clipped to 0 | yes | done |
//! | peakwidth | | m | 3 | number; negative clipped to 0 | yes | done |
//! | basewidth | | m | 100 | number; negative clipped to 0 | yes | done |
//! | summitdelta | | 0..100 | 50 | number, clipped to [0, 100] | yes | done |
//! | depth_mismatch_var | | var | none | no white space (empty turns it off) | yes | done |
//! | duration (common) | | s | 0 (the constructor's) | | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | `depth_mismatch_var` | each running iteration with NAV_DEPTH | \|NAV_DEPTH − depth\| | done |
//! | BHV_WARNING | running without NAV_DEPTH | `No ownship DEPTH info in info_buffer.` | done |
//! | BHV_ERROR | no `depth` in the domain | `Null IvPDomain given to Behavior` (the helm's check, before the behaviour runs, as in the C++) | done |
//! | BHV_WARNING | ZAIC warnings | the ZAIC's text | done: none can arise (widths clipped at 0, summit delta to [0, 100] = the utility range); tested |

use ivp::IvpFunction;

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::common::Common;
use crate::memo::{FnMemo, PeakError};
use crate::param::number;

/// Prefers one depth: ZAIC_PEAK(summit `depth`, `peakwidth` 3, `basewidth` 100,
/// `summitdelta` 50).
///
/// As in MOOS-IvP:
/// - the default `duration` is 0, so without a `duration` (missions write
///   `duration = no-time-limit`) it completes on its first run (reference §5.5);
/// - negative `depth`, `peakwidth` and `basewidth` are clipped to 0 and `summitdelta` to
///   `[0, 100]`; a value that is not a number is rejected;
/// - a missing `NAV_DEPTH` only raises a `BHV_WARNING`; the function is still produced.
///
/// Without a `depth` variable in the helm domain it produces nothing (pHelmIvP keeps such a
/// behaviour idle because its sub-domain is empty).
#[derive(Debug, Clone)]
pub struct ConstantDepth {
    /// Desired depth, m.
    pub depth: f64,
    /// Plateau half-width, m.
    pub peakwidth: f64,
    /// Ramp width, m.
    pub basewidth: f64,
    /// Utility drop across the plateau.
    pub summitdelta: f64,
    /// Variable receiving |NAV_DEPTH − depth| ("" = none).
    pub mismatch_var: String,
    /// The last function built, reused while its inputs are the same.
    memo: FnMemo<4>,
}

impl Default for ConstantDepth {
    fn default() -> Self {
        Self::new()
    }
}

impl ConstantDepth {
    /// The MOOS defaults.
    pub fn new() -> Self {
        ConstantDepth {
            depth: 0.0,
            peakwidth: 3.0,
            basewidth: 100.0,
            summitdelta: 50.0,
            mismatch_var: String::new(),
            memo: FnMemo::default(),
        }
    }
}

/// A variable name as MOOS accepts one for a status variable: no white space.
pub(crate) fn var_name(param: &str, value: &str) -> Result<String, ParamError> {
    let v = value.trim();
    if v.contains(char::is_whitespace) {
        return Err(ParamError::bad(
            param,
            value,
            "a variable name without spaces",
        ));
    }
    Ok(v.to_string())
}

impl Behavior for ConstantDepth {
    fn kind(&self) -> &'static str {
        "BHV_ConstantDepth"
    }

    fn default_name(&self) -> &'static str {
        "bhv_constantdepth"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["depth"]
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_DEPTH"]);
    }
    fn default_duration(&self) -> f64 {
        0.0
    }
    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        match param {
            "depth" => self.depth = number(param, value)?.max(0.0),
            "peakwidth" => self.peakwidth = number(param, value)?.max(0.0),
            "basewidth" => self.basewidth = number(param, value)?.max(0.0),
            "summitdelta" => self.summitdelta = number(param, value)?.clamp(0.0, 100.0),
            "depth_mismatch_var" => self.mismatch_var = var_name(param, value)?,
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        match ctx.info.num("NAV_DEPTH") {
            Some(d) if !self.mismatch_var.is_empty() => {
                out.post(self.mismatch_var.clone(), (d - self.depth).abs());
            }
            Some(_) => {}
            None => out.warning(ctx.name, "No ownship DEPTH info in info_buffer."),
        }
        let params = [self.depth, self.peakwidth, self.basewidth, self.summitdelta];
        // No depth variable: no function, silently, as the C++ does.
        match self.memo.peak(ctx.domain, "depth", false, params) {
            Ok(f) => Some(f),
            Err(PeakError::Refused(e)) => {
                out.error(format!(
                    "Unable to generate constant-depth IvP function: {e}"
                ));
                None
            }
            Err(PeakError::NoVariable) => None,
        }
    }
}
