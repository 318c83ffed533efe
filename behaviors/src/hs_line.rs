//! BHV_HSLine: draws the helm's decision as a line ahead of the vehicle; no objective function.
//!
//! # Conformance with BHV_HSLine (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | time_on_leg | | s | 60 | number (MOOS `isNumber`) > 0 | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | VIEW_SEGLIST | every running iteration | `pts={x,y:x2,y2},active=true,label=<ownship>_<name>` (1 decimal, compact) | done |
//! | VIEW_SEGLIST | idle and completed iterations, once a line was drawn | the last line with `active=false` | done |
//! | BHV_WARNING | running without DESIRED_HEADING, DESIRED_SPEED, NAV_X or NAV_Y | `No <VAR> info in the info_buffer` (the missing value read as 0) | done |
//!
//! The line starts at the vehicle and runs along DESIRED_HEADING for `time_on_leg` seconds at
//! DESIRED_SPEED scaled by its ratio to the highest DESIRED_SPEED seen (so the length is
//! `spd² / max_spd × time_on_leg`, as the C++ computes it).

use geometry::Point;
use ivp::IvpFunction;

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::common::Common;
use crate::param::number;

/// The helm's heading and speed as a line (a visual aid; never an objective function).
#[derive(Debug, Clone)]
pub struct HsLine {
    /// Seconds of travel the line stands for.
    pub time_on_leg: f64,
    /// The highest DESIRED_SPEED seen (−1 before the first run).
    max_des_speed: f64,
    /// The last line drawn (empty before the first run).
    line: Vec<Point>,
    /// Its label.
    label: String,
}

impl Default for HsLine {
    fn default() -> Self {
        Self::new()
    }
}

impl HsLine {
    /// The MOOS defaults (`time_on_leg` 60 s).
    pub fn new() -> Self {
        HsLine {
            time_on_leg: 60.0,
            max_des_speed: -1.0,
            line: Vec::new(),
            label: String::new(),
        }
    }

    /// The seglist spec with an explicit `active=` (MOOS `get_spec("active=..")`).
    fn spec(&self, active: bool) -> String {
        let mut s = String::new();
        geometry::spec::write_points(&mut s, &self.line, 1);
        s.push_str(if active {
            ",active=true"
        } else {
            ",active=false"
        });
        if !self.label.is_empty() {
            s.push_str(",label=");
            s.push_str(&self.label);
        }
        s
    }

    fn erase(&self, out: &mut Out) {
        if !self.line.is_empty() {
            out.post("VIEW_SEGLIST", self.spec(false));
        }
    }
}

/// A number from the info buffer, or 0 with a warning (MOOS `getBufferDoubleVal`).
pub(crate) fn num_or_warn(ctx: &Ctx<'_>, out: &mut Out, var: &str) -> f64 {
    match ctx.info.num(var) {
        Some(v) => v,
        None => {
            out.warning(ctx.name, &format!("No {var} info in the info_buffer"));
            0.0
        }
    }
}

impl Behavior for HsLine {
    fn kind(&self) -> &'static str {
        "BHV_HSLine"
    }

    fn default_name(&self) -> &'static str {
        "bhv_hsline"
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_X", "NAV_Y", "DESIRED_HEADING", "DESIRED_SPEED"]);
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        match param {
            "time_on_leg" => {
                let v = number(param, value)?;
                if v <= 0.0 {
                    return Err(ParamError::bad(param, value, "a number > 0"));
                }
                self.time_on_leg = v;
            }
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn on_idle(&mut self, _ctx: &Ctx<'_>, out: &mut Out) {
        self.erase(out);
    }

    fn on_complete(&mut self, _ctx: &Ctx<'_>, out: &mut Out) {
        self.erase(out);
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let hdg = num_or_warn(ctx, out, "DESIRED_HEADING");
        let mut spd = num_or_warn(ctx, out, "DESIRED_SPEED");
        let x = num_or_warn(ctx, out, "NAV_X");
        let y = num_or_warn(ctx, out, "NAV_Y");
        if spd > self.max_des_speed {
            self.max_des_speed = spd;
        }
        let pct = if self.max_des_speed > 0.0 {
            spd / self.max_des_speed
        } else {
            1.0
        };
        spd *= pct;
        let end = geometry::project_point(x, y, hdg, spd * self.time_on_leg);
        self.line.clear();
        self.line.push(Point::new(x, y));
        self.line.push(end);
        self.label.clear();
        self.label.push_str(ctx.ownship);
        self.label.push('_');
        self.label.push_str(ctx.name);
        out.post("VIEW_SEGLIST", self.spec(true));
        None
    }
}
