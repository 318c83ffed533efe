//! BHV_PeriodicSpeed: alternates a lazy period (no opinion) and a busy period (a speed).
//!
//! # Conformance with BHV_PeriodicSpeed (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | period_busy | | s | 0 | number > 0 | yes | done |
//! | period_lazy | | s | 0 | number > 0 | yes | done |
//! | period_speed | | m/s | 0 | number ≥ 0 | yes | done |
//! | basewidth | zaic_basewidth, period_basewidth | m/s | 0 | number ≥ 0 | yes | done |
//! | peakwidth | zaic_peakwidth, period_peakwidth | m/s | 0 | number ≥ 0 | yes | done |
//! | summit_delta | zaic_summit_delta | | 25 | number ≥ 0 | yes | done |
//! | reset_upon_running | | bool | true | MOOS boolean | yes | done |
//! | initially_busy | | bool | false | `true` or `false` (any case); restarts the period at the next iteration | yes | done |
//! | activeflag, inactiveflag (common) | | flag | `PERIODIC_SPEED=1`, `PERIODIC_SPEED=0` (set by the C++ constructor) | | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | PS_BUSY_COUNT | after configuration and each update (0), at the start of each busy period (the count) | number | done |
//! | PS_PENDING_INACTIVE | every iteration (idle or running) | seconds to the end of the busy period: as is at or below 1, rounded to an integer above | done |
//! | PS_PENDING_ACTIVE | every iteration (idle or running) | seconds to the next busy period, likewise | done |
//!
//! The C++ leaves the two countdowns uninitialised until first computed; coug starts them at
//! 0. The busy objective function is a ZAIC_PEAK on speed (summit `period_speed`, the widths
//! and summit delta configured), normalised to [0, 100].

use ivp::{IvpFunction, ZaicPeak};

use crate::behavior::{Behavior, Ctx, Out, ParamError};
use crate::common::Common;
use crate::param::{moos_boolean, number};

/// Prefers `period_speed` for `period_busy` seconds after each `period_lazy` seconds without
/// an opinion.
#[derive(Debug, Clone)]
pub struct PeriodicSpeed {
    /// Busy period, s.
    pub period_busy: f64,
    /// Lazy period, s.
    pub period_lazy: f64,
    /// The speed while busy, m/s.
    pub period_speed: f64,
    /// ZAIC base width.
    pub basewidth: f64,
    /// ZAIC peak width.
    pub peakwidth: f64,
    /// ZAIC summit delta.
    pub summit_delta: f64,
    /// Restart with a lazy period each time the behaviour starts running.
    pub reset_upon_running: bool,
    busy: bool,
    mark_needed: bool,
    mark_time: f64,
    busy_count: u32,
    time_to_busy: f64,
    time_to_lazy: f64,
}

impl Default for PeriodicSpeed {
    fn default() -> Self {
        Self::new()
    }
}

const BUSY_COUNT: &str = "PS_BUSY_COUNT";
const PENDING_BUSY: &str = "PS_PENDING_ACTIVE";
const PENDING_LAZY: &str = "PS_PENDING_INACTIVE";

impl PeriodicSpeed {
    /// The MOOS defaults.
    pub fn new() -> Self {
        PeriodicSpeed {
            period_busy: 0.0,
            period_lazy: 0.0,
            period_speed: 0.0,
            basewidth: 0.0,
            peakwidth: 0.0,
            summit_delta: 25.0,
            reset_upon_running: true,
            busy: false,
            mark_needed: true,
            mark_time: 0.0,
            busy_count: 0,
            time_to_busy: 0.0,
            time_to_lazy: 0.0,
        }
    }

    /// Whether the behaviour is in a busy period.
    pub fn is_busy(&self) -> bool {
        self.busy
    }

    fn update_info_in(&mut self, now: f64, out: &mut Out) {
        if self.mark_needed {
            self.mark_needed = false;
            self.mark_time = now;
        }
        let since = now - self.mark_time;
        if self.busy {
            self.time_to_lazy = self.period_busy - since;
            if self.time_to_lazy <= 0.0 {
                self.busy = false;
                self.mark_time = now;
                self.time_to_lazy = 0.0;
            }
        } else {
            self.time_to_busy = self.period_lazy - since;
            if self.time_to_busy <= 0.0 {
                self.busy = true;
                self.mark_time = now;
                self.time_to_busy = 0.0;
                self.busy_count += 1;
                out.post(BUSY_COUNT, f64::from(self.busy_count));
            }
        }
    }

    fn post_status(&self, out: &mut Out) {
        for (var, v) in [
            (PENDING_LAZY, self.time_to_lazy),
            (PENDING_BUSY, self.time_to_busy),
        ] {
            if v <= 1.0 {
                out.post(var, v);
            } else {
                out.post_int(var, v);
            }
        }
    }
}

/// A number ≥ 0 (`min_excl`: > 0).
fn bounded(param: &str, value: &str, min_excl: bool) -> Result<f64, ParamError> {
    let v = number(param, value)?;
    if v < 0.0 || (min_excl && v == 0.0) {
        return Err(ParamError::bad(
            param,
            value,
            if min_excl {
                "a number > 0"
            } else {
                "a number >= 0"
            },
        ));
    }
    Ok(v)
}

impl Behavior for PeriodicSpeed {
    fn kind(&self) -> &'static str {
        "BHV_PeriodicSpeed"
    }

    fn default_name(&self) -> &'static str {
        "periodic_speed"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["speed"]
    }

    fn default_common_params(&self) -> &'static [(&'static str, &'static str)] {
        &[
            ("activeflag", "PERIODIC_SPEED=1"),
            ("inactiveflag", "PERIODIC_SPEED=0"),
        ]
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        match param {
            "period_busy" => self.period_busy = bounded(param, value, true)?,
            "period_lazy" => self.period_lazy = bounded(param, value, true)?,
            "period_speed" => self.period_speed = bounded(param, value, false)?,
            "basewidth" | "zaic_basewidth" | "period_basewidth" => {
                self.basewidth = bounded(param, value, false)?
            }
            "peakwidth" | "period_peakwidth" | "zaic_peakwidth" => {
                self.peakwidth = bounded(param, value, false)?
            }
            "summit_delta" | "zaic_summit_delta" => {
                self.summit_delta = bounded(param, value, false)?
            }
            "reset_upon_running" => {
                self.reset_upon_running = moos_boolean(param, value, self.reset_upon_running)?
            }
            "initially_busy" => {
                match value.trim().to_ascii_lowercase().as_str() {
                    "true" => self.busy = true,
                    "false" => self.busy = false,
                    _ => return Err(ParamError::bad(param, value, "true or false")),
                }
                self.mark_needed = true;
            }
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    /// The C++ override posts the busy count (0), not the settings.
    fn on_set_param_complete(&mut self, _ctx: &Ctx<'_>, out: &mut Out) {
        out.post(BUSY_COUNT, 0.0);
    }

    fn on_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        if self.reset_upon_running {
            self.time_to_busy = self.period_lazy;
            self.time_to_lazy = 0.0;
        } else {
            self.update_info_in(ctx.info.now(), out);
        }
        self.post_status(out);
    }

    fn on_idle_to_run(&mut self, ctx: &Ctx<'_>, _out: &mut Out) {
        if self.reset_upon_running {
            self.mark_time = ctx.info.now();
            self.busy = false;
        }
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        self.update_info_in(ctx.info.now(), out);
        self.post_status(out);
        if !self.busy {
            return None;
        }
        let mut z = ZaicPeak::new(ctx.domain, "speed").ok()?;
        z.set_params(
            self.period_speed,
            self.peakwidth,
            self.basewidth,
            self.summit_delta,
            0.0,
            100.0,
        )
        .ok()?;
        let mut f = z.extract().ok()?;
        f.normalize(0.0, 100.0);
        Some(f)
    }
}
