//! BHV_ConstantSpeed (reference §6.5): a ZAIC_PEAK preference on `speed`.
//!
//! # Conformance with BHV_ConstantSpeed (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | speed | | m/s | 0 | number; negative clipped to 0 | yes | done |
//! | peakwidth | | m/s | 0 | number; negative clipped to 0 | yes | done |
//! | basewidth | | m/s | 0.2 | number; negative clipped to 0 | yes | done |
//! | summitdelta | | 0..100 | 0 | number, clipped to [0, 100] | yes | done |
//! | speed_mismatch_var | | var | none | no white space | yes | done |
//! | duration (common) | | s | 0 (the constructor's) | | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | `speed_mismatch_var` | each running iteration with NAV_SPEED | \|NAV_SPEED − speed\| | done |
//! | BHV_WARNING | running without NAV_SPEED | `No ownship SPEED info in info_buffer.` | done |
//! | BHV_ERROR | no `speed` in the domain | `Null IvPDomain given to Behavior` (the helm's check, before the behaviour runs, as in the C++) | done |
//! | BHV_WARNING | ZAIC warnings | the ZAIC's text | done: none can arise (widths clipped at 0, summit delta to [0, 100] = the utility range); tested |

use ivp::IvpFunction;

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::common::Common;
use crate::memo::{FnMemo, PeakError};
use crate::param::number;

/// Prefers one speed: ZAIC_PEAK(summit `speed`, `peakwidth` 0, `basewidth` 0.2,
/// `summitdelta` 0). Its default `duration` is 0 (reference §5.5), so without a `duration` it
/// completes on its first run.
#[derive(Debug, Clone)]
pub struct ConstantSpeed {
    /// Desired speed, m/s.
    pub speed: f64,
    /// Plateau half-width.
    pub peakwidth: f64,
    /// Ramp width.
    pub basewidth: f64,
    /// Utility drop across the plateau.
    pub summitdelta: f64,
    /// Variable receiving |NAV_SPEED − speed| ("" = none).
    pub mismatch_var: String,
    /// The last function built, reused while its inputs are the same.
    memo: FnMemo<4>,
}

impl Default for ConstantSpeed {
    fn default() -> Self {
        Self::new()
    }
}

impl ConstantSpeed {
    /// The MOOS defaults.
    pub fn new() -> Self {
        ConstantSpeed {
            speed: 0.0,
            peakwidth: 0.0,
            basewidth: 0.2,
            summitdelta: 0.0,
            mismatch_var: String::new(),
            memo: FnMemo::default(),
        }
    }
}

impl Behavior for ConstantSpeed {
    fn kind(&self) -> &'static str {
        "BHV_ConstantSpeed"
    }

    fn default_name(&self) -> &'static str {
        "bhv_constant_speed"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["speed"]
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_SPEED"]);
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
            // As in MOOS, a negative speed clips to 0.
            "speed" => self.speed = number(param, value)?.max(0.0),
            // As in MOOS, negative widths clip to 0.
            "peakwidth" => self.peakwidth = number(param, value)?.max(0.0),
            "basewidth" => self.basewidth = number(param, value)?.max(0.0),
            "summitdelta" => self.summitdelta = number(param, value)?.clamp(0.0, 100.0),
            "speed_mismatch_var" => {
                if value.trim().contains(char::is_whitespace) {
                    return Err(ParamError::bad(param, value, "a variable name"));
                }
                self.mismatch_var = value.trim().to_string();
            }
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        match ctx.info.num("NAV_SPEED") {
            Some(v) if !self.mismatch_var.is_empty() => {
                out.post(self.mismatch_var.clone(), (v - self.speed).abs());
            }
            Some(_) => {}
            None => out.warning(ctx.name, "No ownship SPEED info in info_buffer."),
        }
        let params = [self.speed, self.peakwidth, self.basewidth, self.summitdelta];
        // A refused ZAIC gives no function, silently, as the C++ does.
        match self.memo.peak(ctx.domain, "speed", false, params) {
            Ok(f) => Some(f),
            Err(PeakError::NoVariable) => {
                out.error("No 'speed' variable in the helm domain");
                None
            }
            Err(PeakError::Refused(_)) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::behavior::MapInfo;
    use ivp::{Domain, Problem};

    #[test]
    fn peaks_at_configured_speed_with_configured_width() {
        let d = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
        let info = MapInfo::new(0.0).num("NAV_SPEED", 1.0);
        let ctx = Ctx {
            info: &info,
            domain: &d,
            ownship: "abe",
            name: "cs",
            perpetual: false,
        };
        let mut b = ConstantSpeed::new();
        let mut c = Common::new("BHV_ConstantSpeed");
        b.set_param("speed", "1.5", &mut c, &ctx).unwrap();
        b.set_param("basewidth", "0.5", &mut c, &ctx).unwrap();
        b.set_param("speed_mismatch_var", "SPD_MISS", &mut c, &ctx)
            .unwrap();
        assert!(
            b.set_param("speed_mismatch_var", "A B", &mut c, &ctx)
                .is_err()
        );
        assert!(b.set_param("speed", "fast", &mut c, &ctx).is_err());
        let mut neg = ConstantSpeed::new();
        neg.set_param("speed", "-1", &mut c, &ctx).unwrap();
        assert_eq!(neg.speed, 0.0, "negative speeds clip to 0 as in MOOS");
        let mut out = Out::default();
        let f = b.on_run(&ctx, &mut out).unwrap();
        // Index 15 = 1.5 m/s is the summit; 0.5 m/s away utility reaches 0.
        assert_eq!(f.eval(&[15]), Some(100.0));
        assert!((f.eval(&[13]).unwrap() - 60.0).abs() < 1e-6);
        assert_eq!(f.eval(&[20]), Some(0.0));
        let mut p = Problem::new(d.clone());
        p.add("cs", f).unwrap();
        assert_eq!(p.solve().unwrap().get("speed"), Some(1.5));
        assert!(matches!(&out.emits[0], crate::Emit::Post { var, value, .. }
            if var == "SPD_MISS" && value.as_f64() == Some(0.5)));
        assert_eq!(b.default_duration(), 0.0);
    }
}
