//! BHV_MemoryTurnLimit: keeps the course near the average heading of the last seconds.
//!
//! # Conformance with BHV_MemoryTurnLimit (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | memory_time | | s | −1 (unset) | number ≥ 0 | yes | done |
//! | turn_range | | deg | −1 (unset) | number in [0, 180] | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | MEM_HDG_AVG | each running iteration with both parameters and NAV_HEADING, NAV_SPEED | the average heading rounded to an integer (`postIntMessage`) | done |
//! | BHV_WARNING | running without `memory_time` (then without `turn_range`) | `Variable memory_time not specified` / `Variable turn_range not specified` | done |
//! | BHV_ERROR | running without NAV_HEADING (then NAV_SPEED) | `No Ownship NAV_HEADING in info_buffer` / `No Ownship NAV_SPEED in info_buffer` | done |
//!
//! Each running iteration adds NAV_HEADING to a memory that forgets headings older than
//! `memory_time`; the average is the direction of the sum of the headings' unit vectors (the
//! C++ `getHeadingAvg2`). The objective function is a ZAIC_PEAK on course: summit the average,
//! summit delta 0.2, base width 0, wrapping, peak width `turn_range` scaled by speed
//! (`turn_range × max(speed, 0.3) / 1.5`, and `turn_range` itself from 1.5 m/s). The type is a
//! constraint.

use std::collections::VecDeque;

use ivp::{IvpFunction, ZaicPeak};

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::common::Common;
use crate::param::number;

/// Limits turns to `turn_range` about the heading averaged over `memory_time` seconds.
#[derive(Debug, Clone)]
pub struct MemoryTurnLimit {
    /// Seconds of heading history (−1 = unset).
    pub memory_time: f64,
    /// Allowed deviation from the average, degrees (−1 = unset).
    pub turn_range: f64,
    /// `(time, heading)` remembered.
    memory: VecDeque<(f64, f64)>,
}

impl Default for MemoryTurnLimit {
    fn default() -> Self {
        Self::new()
    }
}

impl MemoryTurnLimit {
    /// The MOOS defaults (both parameters unset).
    pub fn new() -> Self {
        MemoryTurnLimit {
            memory_time: -1.0,
            turn_range: -1.0,
            memory: VecDeque::new(),
        }
    }

    /// The average of the remembered headings, degrees in [0, 360).
    pub fn heading_avg(&self) -> f64 {
        let (mut s, mut c) = (0.0, 0.0);
        for (_, h) in &self.memory {
            let r = h.to_radians();
            s += r.sin();
            c += r.cos();
        }
        let avg = s.atan2(c).to_degrees();
        if avg < 0.0 { avg + 360.0 } else { avg }
    }

    fn remember(&mut self, heading: f64, now: f64) {
        self.memory.push_back((now, heading));
        let forget = self
            .memory
            .iter()
            .filter(|(t, _)| now - t > self.memory_time)
            .count();
        self.memory.drain(..forget);
    }
}

impl Behavior for MemoryTurnLimit {
    fn kind(&self) -> &'static str {
        "BHV_MemoryTurnLimit"
    }

    fn default_name(&self) -> &'static str {
        "mem_turn_limit"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course"]
    }

    fn is_constraint(&self) -> bool {
        true
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_HEADING", "NAV_SPEED"]);
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        match param {
            "memory_time" => {
                let v = number(param, value)?;
                if v < 0.0 {
                    return Err(ParamError::bad(param, value, "a number >= 0"));
                }
                self.memory_time = v;
            }
            "turn_range" => {
                let v = number(param, value)?;
                if !(0.0..=180.0).contains(&v) {
                    return Err(ParamError::bad(param, value, "a number in [0, 180]"));
                }
                self.turn_range = v;
            }
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        if self.memory_time < 0.0 {
            out.warning(ctx.name, "Variable memory_time not specified");
            return None;
        }
        if self.turn_range < 0.0 {
            out.warning(ctx.name, "Variable turn_range not specified");
            return None;
        }
        let Some(heading) = ctx.info.num("NAV_HEADING") else {
            out.error("No Ownship NAV_HEADING in info_buffer");
            return None;
        };
        let Some(speed) = ctx.info.num("NAV_SPEED") else {
            out.error("No Ownship NAV_SPEED in info_buffer");
            return None;
        };
        self.remember(heading, ctx.info.now());
        let avg = self.heading_avg();
        out.post_int("MEM_HDG_AVG", avg);
        const REF_SPEED: f64 = 1.5;
        const MIN_SPEED: f64 = 0.3;
        let peakwidth = self.turn_range * speed.clamp(MIN_SPEED, REF_SPEED) / REF_SPEED;
        let mut z = ZaicPeak::new(ctx.domain, "course").ok()?;
        z.set_value_wrap(true);
        z.set_params(avg, peakwidth, 0.0, 0.2, 0.0, 100.0).ok()?;
        z.extract().ok()
    }
}
