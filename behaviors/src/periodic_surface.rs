//! BHV_PeriodicSurface (reference §6.7): comes to the surface every `period` seconds and waits
//! there for a fix.
//!
//! # Conformance with BHV_PeriodicSurface (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | period | | s | 300 | number > 0 | yes | done |
//! | mark_variable | | var | GPS_UPDATE_RECEIVED | non-empty; subscribed | yes | done |
//! | acomms_mark_variable | | `VAR,interval,max_time` | none | VAR without white space, 0 < interval <= max_time; subscribed | yes | done |
//! | pending_status_var | pending_status_variable | var | PENDING_SURFACE | non-empty | yes | done |
//! | atsurface_status_var | atsurface_status_variable | var | TIME_AT_SURFACE | non-empty | yes | done |
//! | ascent_speed | speed_to_surface | m/s | −1 (`current`: the speed at ascent start) | number >= 0 or `current` | yes | done |
//! | zero_speed_depth | | m | 0 | number >= 0 | yes | done |
//! | max_time_at_surface | | s | 300 | number >= 0 | yes | done |
//! | ascent_grade | | enum | linear | linear, quadratic, quasi, fullspeed | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | `pending_status_var` | while waiting | whole seconds to the next ascent | done |
//! | `atsurface_status_var` | while waiting (0) and at the surface | whole seconds at the surface | done |
//! | PERIODIC_ASCEND | ascent start / at the surface | `true` / `false` | done |
//! | PSF_AT_SURFACE_TIMEOUT | `max_time_at_surface` passed without a mark | `Timestamp=<t>` | done |

use ivp::{IvpFunction, ZaicPeak, couple};

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::common::Common;
use crate::fmt::fixed;
use crate::param::{is_number, number};

/// How the ascent speed tapers between the depth where the ascent began and
/// `zero_speed_depth` (`ascent_grade`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AscentGrade {
    /// Speed proportional to the fraction of the ascent left (default).
    Linear,
    /// Proportional to its square.
    Quadratic,
    /// Proportional to its power 1.5.
    Quasi,
    /// The full ascent speed until `zero_speed_depth`.
    FullSpeed,
}

/// The cycle's phase.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Submerged, counting down the period (no objective function).
    Waiting,
    /// Coming up: depth 0 at the ascent speed.
    Ascending,
    /// At or above `zero_speed_depth`: depth 0 at speed 0, until a mark arrives or
    /// `max_time_at_surface` passes.
    AtSurface,
}

/// The periodic-surface behaviour, as MOOS-IvP's: while the period has not run out since the
/// last *mark* (a change of `mark_variable`, default `GPS_UPDATE_RECEIVED`) it produces nothing
/// and the vehicle does its other work (`PENDING_SURFACE` counts down, `TIME_AT_SURFACE` = 0).
/// Then it ascends (`PERIODIC_ASCEND = true`): depth 0 at `ascent_speed` (or, with
/// `current`, the speed when the ascent began), tapered by `ascent_grade`. At
/// `zero_speed_depth` it is at the surface (`PERIODIC_ASCEND = false`) and asks for speed 0
/// and depth 0, posting the whole seconds spent there in `TIME_AT_SURFACE`. A mark (any new
/// value of the mark variable; the same value posted again is none, as MOOS compares values,
/// not posting times) ends the cycle and restarts the period; so does
/// `max_time_at_surface` (posting `PSF_AT_SURFACE_TIMEOUT = Timestamp=<t>`).
///
/// The objective function couples speed ZAIC_PEAK(desired, base 0.5, or 0 when desired is 0)
/// with depth ZAIC_PEAK(0, base 0), 50/50. Missing `NAV_DEPTH`/`NAV_SPEED` is an error
/// (`BHV_ERROR`), as in MOOS-IvP. `acomms_mark_variable = VAR,interval,max_time`: each new
/// value of VAR extends the period by `interval`, up to `max_time` in all.
#[derive(Debug, Clone)]
pub struct PeriodicSurface {
    /// Seconds between surfacings.
    pub period: f64,
    /// Variable whose every change is a mark.
    pub mark_variable: String,
    acomms_var: String,
    acomms_interval: f64,
    acomms_max: f64,
    /// Countdown variable (`PENDING_SURFACE`).
    pub pending_status_var: String,
    /// Time-at-surface variable (`TIME_AT_SURFACE`).
    pub atsurface_status_var: String,
    /// Longest wait at the surface, s.
    pub max_time_at_surface: f64,
    /// Ascent speed, m/s (−1 = the speed at the start of the ascent).
    pub ascent_speed: f64,
    /// Depth at or above which the vehicle counts as surfaced, m.
    pub zero_speed_depth: f64,
    /// Ascent speed profile.
    pub ascent_grade: AscentGrade,
    phase: Phase,
    first_iteration: bool,
    mark_time: Option<f64>,
    surface_mark_time: f64,
    depth_at_ascent: f64,
    speed_at_ascent: f64,
    last_mark_num: Option<f64>,
    last_mark_str: Option<String>,
    last_amark: String,
    amark_extension: f64,
}

impl Default for PeriodicSurface {
    fn default() -> Self {
        Self::new()
    }
}

impl PeriodicSurface {
    /// The MOOS defaults: period 300 s, `GPS_UPDATE_RECEIVED`, 300 s at the surface, ascent
    /// at the current speed, linear grade.
    pub fn new() -> Self {
        PeriodicSurface {
            period: 300.0,
            mark_variable: "GPS_UPDATE_RECEIVED".into(),
            acomms_var: String::new(),
            acomms_interval: 0.0,
            acomms_max: 0.0,
            pending_status_var: "PENDING_SURFACE".into(),
            atsurface_status_var: "TIME_AT_SURFACE".into(),
            max_time_at_surface: 300.0,
            ascent_speed: -1.0,
            zero_speed_depth: 0.0,
            ascent_grade: AscentGrade::Linear,
            phase: Phase::Waiting,
            first_iteration: true,
            mark_time: None,
            surface_mark_time: 0.0,
            depth_at_ascent: 0.0,
            speed_at_ascent: 0.0,
            last_mark_num: None,
            last_mark_str: None,
            last_amark: String::new(),
            amark_extension: 0.0,
        }
    }

    /// The current phase.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    fn remaining(&self, now: f64) -> f64 {
        let since = now - self.mark_time.unwrap_or(now);
        self.period - since + self.amark_extension
    }

    fn post_pending(&self, now: f64, out: &mut Out) {
        if !self.pending_status_var.is_empty() {
            out.post_int(self.pending_status_var.clone(), self.remaining(now));
        }
    }

    /// A mark: the first running iteration, or a new value of the mark variable.
    fn check_for_marking(&mut self, ctx: &Ctx<'_>, now: f64) -> bool {
        let mut noted = false;
        if self.first_iteration {
            self.first_iteration = false;
            noted = true;
        } else if let Some(s) = ctx.info.text(&self.mark_variable) {
            if self.last_mark_str.as_deref() != Some(s) {
                self.last_mark_str = Some(s.to_string());
                noted = true;
            }
        } else if let Some(v) = ctx.info.num(&self.mark_variable)
            && self.last_mark_num != Some(v)
        {
            self.last_mark_num = Some(v);
            noted = true;
        }
        if noted {
            self.mark_time = Some(now);
            self.amark_extension = 0.0;
        }
        noted
    }

    fn check_for_acomms_marking(&mut self, ctx: &Ctx<'_>) {
        if self.acomms_var.is_empty() || self.amark_extension >= self.acomms_max {
            return;
        }
        if let Some(s) = ctx.info.text(&self.acomms_var)
            && s != self.last_amark
        {
            self.last_amark = s.to_string();
            self.amark_extension =
                (self.amark_extension + self.acomms_interval).min(self.acomms_max);
        }
    }

    fn desired_speed(&self, depth: f64) -> f64 {
        let zsd = self.zero_speed_depth;
        if self.depth_at_ascent <= zsd || depth <= zsd {
            return 0.0;
        }
        if depth > self.depth_at_ascent {
            return self.speed_at_ascent;
        }
        let pct = (depth - zsd) / (self.depth_at_ascent - zsd);
        self.speed_at_ascent
            * match self.ascent_grade {
                AscentGrade::Linear => pct,
                AscentGrade::Quadratic => pct * pct,
                AscentGrade::Quasi => pct.powf(1.5),
                AscentGrade::FullSpeed => 1.0,
            }
    }
}

impl Behavior for PeriodicSurface {
    fn kind(&self) -> &'static str {
        "BHV_PeriodicSurface"
    }

    fn default_name(&self) -> &'static str {
        "periodic_surface"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["speed", "depth"]
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        // MOOS always declares GPS_UPDATE_RECEIVED, plus the configured mark variables.
        add_vars(out, ["NAV_DEPTH", "NAV_SPEED", "GPS_UPDATE_RECEIVED"]);
        add_vars(out, [self.mark_variable.as_str(), self.acomms_var.as_str()]);
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        let v = value.trim();
        let nonneg = |v: &str| -> Result<f64, ParamError> {
            let d = number(param, v)?;
            if d < 0.0 {
                return Err(ParamError::bad(param, value, "a number >= 0"));
            }
            Ok(d)
        };
        let var = |v: &str| -> Result<String, ParamError> {
            if v.is_empty() || v.contains(char::is_whitespace) {
                return Err(ParamError::bad(param, value, "a variable name"));
            }
            Ok(v.to_string())
        };
        match param {
            "period" => {
                let d = number(param, v)?;
                if d <= 0.0 {
                    return Err(ParamError::bad(
                        param,
                        value,
                        "a positive number of seconds",
                    ));
                }
                self.period = d;
            }
            "mark_variable" => self.mark_variable = var(v)?,
            "acomms_mark_variable" => {
                let parts: Vec<&str> = v.split(',').map(str::trim).collect();
                let expected = "VAR,interval,max_time with 0 < interval <= max_time";
                let [name, interval, max] = parts[..] else {
                    return Err(ParamError::bad(param, value, expected));
                };
                if name.is_empty()
                    || name.contains(char::is_whitespace)
                    || !is_number(interval)
                    || !is_number(max)
                {
                    return Err(ParamError::bad(param, value, expected));
                }
                let (i, m) = (number(param, interval)?, number(param, max)?);
                if i <= 0.0 || m < i {
                    return Err(ParamError::bad(param, value, expected));
                }
                self.acomms_var = name.to_string();
                self.acomms_interval = i;
                self.acomms_max = m;
                self.amark_extension = 0.0;
            }
            "pending_status_var" | "pending_status_variable" => self.pending_status_var = var(v)?,
            "atsurface_status_var" | "atsurface_status_variable" => {
                self.atsurface_status_var = var(v)?
            }
            "ascent_speed" | "speed_to_surface" => {
                self.ascent_speed = if v == "current" {
                    -1.0
                } else {
                    nonneg(v).map_err(|_| ParamError::bad(param, value, "speed >= 0 or current"))?
                };
            }
            "zero_speed_depth" => self.zero_speed_depth = nonneg(v)?,
            "max_time_at_surface" => self.max_time_at_surface = nonneg(v)?,
            "ascent_grade" => {
                self.ascent_grade = match v.to_ascii_lowercase().as_str() {
                    "linear" => AscentGrade::Linear,
                    "quadratic" => AscentGrade::Quadratic,
                    "quasi" => AscentGrade::Quasi,
                    "fullspeed" => AscentGrade::FullSpeed,
                    _ => {
                        return Err(ParamError::bad(
                            param,
                            value,
                            "linear, quadratic, quasi or fullspeed",
                        ));
                    }
                }
            }
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn on_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        let now = ctx.info.now();
        let depth = ctx.info.num("NAV_DEPTH");
        if depth.is_none() || ctx.info.num("NAV_SPEED").is_none() {
            out.error("No ownship NAV_DEPTH or NAV_SPEED in info_buffer");
        }
        // A behaviour idle from the start begins its first period once submerged.
        if self.first_iteration && depth.unwrap_or(0.0) >= self.zero_speed_depth {
            self.first_iteration = false;
            self.mark_time = Some(now);
        }
        self.post_pending(now, out);
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let now = ctx.info.now();
        let (Some(depth), Some(speed)) = (ctx.info.num("NAV_DEPTH"), ctx.info.num("NAV_SPEED"))
        else {
            out.error("No ownship NAV_DEPTH or NAV_SPEED in info_buffer");
            out.post(self.pending_status_var.clone(), "ERROR");
            return None;
        };
        self.post_pending(now, out);
        if self.check_for_marking(ctx, now) {
            return None;
        }
        self.check_for_acomms_marking(ctx);
        if self.remaining(now) > 0.0 {
            self.phase = Phase::Waiting;
            out.post(self.atsurface_status_var.clone(), 0.0);
            return None;
        }
        if self.phase == Phase::Waiting {
            self.phase = Phase::Ascending;
            out.post("PERIODIC_ASCEND", "true");
            self.depth_at_ascent = depth;
            self.speed_at_ascent = if self.ascent_speed != -1.0 {
                self.ascent_speed
            } else {
                speed
            };
        }
        if self.phase == Phase::Ascending && depth <= self.zero_speed_depth {
            out.post("PERIODIC_ASCEND", "false");
            self.phase = Phase::AtSurface;
            self.surface_mark_time = now;
        }
        if self.phase == Phase::AtSurface {
            let at_surface = now - self.surface_mark_time;
            out.post_int(self.atsurface_status_var.clone(), at_surface);
            if at_surface >= self.max_time_at_surface {
                self.mark_time = Some(now);
                self.phase = Phase::Waiting;
                let mut s = String::from("Timestamp=");
                fixed(&mut s, now, 2);
                out.post("PSF_AT_SURFACE_TIMEOUT", s);
                return None;
            }
        } else {
            out.post(self.atsurface_status_var.clone(), 0.0);
        }
        let desired = if self.phase == Phase::Ascending {
            self.desired_speed(depth)
        } else {
            0.0
        };
        let mut spd = ZaicPeak::new(ctx.domain, "speed").ok()?;
        let base = if desired == 0.0 { 0.0 } else { 0.5 };
        let mut dep = ZaicPeak::new(ctx.domain, "depth").ok()?;
        let built = spd
            .set_params(desired, 0.0, base, 0.0, 0.0, 100.0)
            .and_then(|_| dep.set_params(0.0, 0.0, 0.0, 0.0, 0.0, 100.0))
            .and_then(|_| couple(&spd.extract()?, &dep.extract()?));
        match built {
            Ok(f) => Some(f),
            Err(e) => {
                out.error(format!(
                    "Unable to build the periodic-surface function: {e}"
                ));
                None
            }
        }
    }
}
