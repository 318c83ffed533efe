//! BHV_ConstantHeading (reference §6.4): a wrapping ZAIC_PEAK preference on `course`.
//!
//! # Conformance with BHV_ConstantHeading (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | heading | | degrees | 0 | number; wrapped to [0, 360) and snapped to the domain | yes | done |
//! | peakwidth | | degrees | 10 | number; negative clipped to 0 | yes | done |
//! | basewidth | | degrees | 170 | number; negative clipped to 0 | yes | done |
//! | summitdelta | | 0..100 | 25 | number, clipped to [0, 100] | yes | done |
//! | complete_thresh | | degrees | −1 (off) | number; completes when \|heading error\| is below it | yes | done |
//! | heading_mismatch_var | | var | none | no white space | yes | done |
//! | duration (common) | | s | 0 (the constructor's) | | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | `heading_mismatch_var` | each running iteration with NAV_HEADING | \|angle180(NAV_HEADING − heading)\| | done |
//! | BHV_WARNING | running without NAV_HEADING | `No ownship HEADING info in info_buffer.` | done |
//! | BHV_ERROR | no `course` in the domain | `Null IvPDomain given to Behavior` (the helm's check, before the behaviour runs, as in the C++) | done |
//! | BHV_WARNING | ZAIC warnings | the ZAIC's text | done: none can arise (widths clipped at 0, summit delta to [0, 100] = the utility range); tested |

use ivp::IvpFunction;

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::common::Common;
use crate::memo::{FnMemo, PeakError};
use crate::param::number;

/// Prefers one heading: ZAIC_PEAK with value wrap (summit `heading`, `peakwidth` 10,
/// `basewidth` 170, `summitdelta` 25). Default `duration` 0, as in MOOS (reference §5.5): it
/// completes on its first run unless `duration` is set. With `complete_thresh` >= 0 it
/// completes once |heading error| < thresh.
#[derive(Debug, Clone)]
pub struct ConstantHeading {
    /// Desired heading, degrees.
    pub heading: f64,
    /// Plateau half-width.
    pub peakwidth: f64,
    /// Ramp width.
    pub basewidth: f64,
    /// Utility drop across the plateau.
    pub summitdelta: f64,
    /// Completion threshold, degrees (−1 = off).
    pub complete_thresh: f64,
    /// Variable receiving the heading mismatch ("" = none).
    pub mismatch_var: String,
    /// The last function built, reused while its inputs are the same.
    memo: FnMemo<4>,
}

impl Default for ConstantHeading {
    fn default() -> Self {
        Self::new()
    }
}

impl ConstantHeading {
    /// The MOOS defaults.
    pub fn new() -> Self {
        ConstantHeading {
            heading: 0.0,
            peakwidth: 10.0,
            basewidth: 170.0,
            summitdelta: 25.0,
            complete_thresh: -1.0,
            mismatch_var: String::new(),
            memo: FnMemo::default(),
        }
    }
}

impl Behavior for ConstantHeading {
    fn kind(&self) -> &'static str {
        "BHV_ConstantHeading"
    }

    fn default_name(&self) -> &'static str {
        "bhv_constantHeading"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course"]
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_HEADING"]);
    }
    fn default_duration(&self) -> f64 {
        0.0
    }
    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        match param {
            "heading" => {
                let h = geometry::angle_360(number(param, value)?);
                // Snapped to the nearest course value of the domain.
                self.heading = match ctx.domain.get("course") {
                    Some(d) if d.delta() > 0.0 => {
                        d.value(d.index(h, ivp::Snap::Nearest)).min(d.high())
                    }
                    _ => h,
                };
            }
            // As in MOOS, negative widths clip to 0.
            "peakwidth" => self.peakwidth = number(param, value)?.max(0.0),
            "basewidth" => self.basewidth = number(param, value)?.max(0.0),
            "summitdelta" => self.summitdelta = number(param, value)?.clamp(0.0, 100.0),
            "complete_thresh" => self.complete_thresh = number(param, value)?,
            "heading_mismatch_var" => {
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
        if ctx.info.num("NAV_HEADING").is_none() {
            out.warning(ctx.name, "No ownship HEADING info in info_buffer.");
        }
        if let Some(h) = ctx.info.num("NAV_HEADING") {
            let err = geometry::angle_180(h - self.heading).abs();
            if !self.mismatch_var.is_empty() {
                out.post(self.mismatch_var.clone(), err);
            }
            if self.complete_thresh >= 0.0 && err < self.complete_thresh {
                out.complete();
                return None;
            }
        }
        let params = [
            self.heading,
            self.peakwidth,
            self.basewidth,
            self.summitdelta,
        ];
        // A refused ZAIC gives no function, silently, as the C++ does.
        match self.memo.peak(ctx.domain, "course", true, params) {
            Ok(f) => Some(f),
            Err(PeakError::NoVariable) => {
                out.error("No 'heading/course' variable in the helm domain");
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
    use ivp::Domain;

    fn ctx_run(heading: &str, nav_hdg: f64, thresh: Option<&str>) -> (Option<IvpFunction>, Out) {
        let d = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
        let info = MapInfo::new(0.0).num("NAV_HEADING", nav_hdg);
        let ctx = Ctx {
            info: &info,
            domain: &d,
            ownship: "abe",
            name: "ch",
            perpetual: false,
        };
        let mut b = ConstantHeading::new();
        let mut c = Common::new("BHV_ConstantHeading");
        b.set_param("heading", heading, &mut c, &ctx).unwrap();
        if let Some(t) = thresh {
            b.set_param("complete_thresh", t, &mut c, &ctx).unwrap();
        }
        let mut out = Out::default();
        (b.on_run(&ctx, &mut out), out)
    }

    #[test]
    fn peak_wraps_around_north_with_default_widths() {
        let (f, _) = ctx_run("355", 0.0, None);
        let f = f.unwrap();
        assert_eq!(f.eval(&[355]), Some(100.0));
        // Inside the 10-degree plateau the utility drops by summitdelta 25 linearly.
        assert!((f.eval(&[5]).unwrap() - 75.0).abs() < 1e-6);
        // 180 degrees away (10 + 170) it reaches 0.
        assert!(f.eval(&[175]).unwrap() < 1.0);
    }

    #[test]
    fn completes_within_threshold() {
        let (f, out) = ctx_run("90", 88.0, Some("5"));
        assert!(f.is_none() && out.completed);
        let (f, out) = ctx_run("90", 60.0, Some("5"));
        assert!(f.is_some() && !out.completed);
    }
}
