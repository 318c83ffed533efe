//! BHV_Orbit, a behaviour written outside coug: circle a point at a radius, clockwise or
//! not, for a number of laps. It shows what a user's behaviour implements (its type name,
//! its parameters, its objective function) and what it leaves to the helm (conditions,
//! flags, `duration`, `updates`, `templating = spawn`, priority weights).
//!
//! Parameters: `center = x,y` (0,0), `radius` (m, > 0, 50), `speed` (m/s, >= 0, 1.5),
//! `clockwise` (true), `laps` (>= 0, 0 = orbit for ever; at the count it completes and the
//! helm posts its `endflag`s).
//!
//! The objective: a course peak at the tangent to the circle, turned toward the circle in
//! proportion to the distance off it (a full quarter turn at one radius off), and a speed
//! peak, coupled 50/50.

use behaviors::param::{moos_boolean, number, number_min};
use behaviors::{Behavior, Common, Ctx, Out, ParamError};
use ivp::{IvpFunction, ZaicPeak, couple};

/// The orbit behaviour. See the crate docs.
#[derive(Debug, Clone)]
pub struct Orbit {
    /// Centre of the circle, local x/y metres.
    pub center: (f64, f64),
    /// Radius, metres.
    pub radius: f64,
    /// Speed, m/s.
    pub speed: f64,
    /// Clockwise as seen from above (compass headings increase along the orbit).
    pub clockwise: bool,
    /// Laps before completing (0 = never).
    pub laps: f64,
    /// Degrees swept around the centre so far, in the orbit's direction.
    swept: f64,
    /// The bearing from the centre at the previous running iteration.
    prev_bearing: Option<f64>,
}

impl Default for Orbit {
    fn default() -> Self {
        Self::new()
    }
}

impl Orbit {
    /// The defaults.
    pub fn new() -> Self {
        Orbit {
            center: (0.0, 0.0),
            radius: 50.0,
            speed: 1.5,
            clockwise: true,
            laps: 0.0,
            swept: 0.0,
            prev_bearing: None,
        }
    }

    /// The course the behaviour prefers at `(x, y)`: the tangent, turned toward the circle
    /// by 90° × (distance off the circle / radius), at most 90°.
    pub fn desired_course(&self, x: f64, y: f64) -> f64 {
        let bearing = bearing(self.center, (x, y));
        let range = (x - self.center.0).hypot(y - self.center.1);
        let off = ((range - self.radius) / self.radius).clamp(-1.0, 1.0) * 90.0;
        let course = if self.clockwise {
            bearing + 90.0 + off
        } else {
            bearing - 90.0 - off
        };
        course.rem_euclid(360.0)
    }

    /// Laps swept so far.
    pub fn laps_done(&self) -> f64 {
        self.swept / 360.0
    }
}

/// Compass bearing (degrees, 0 = north = +y, 90 = east = +x) from `from` to `to`.
fn bearing(from: (f64, f64), to: (f64, f64)) -> f64 {
    (to.0 - from.0)
        .atan2(to.1 - from.1)
        .to_degrees()
        .rem_euclid(360.0)
}

impl Behavior for Orbit {
    fn kind(&self) -> &'static str {
        "BHV_Orbit"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course", "speed"]
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        match param {
            "center" => {
                let bad = || ParamError::bad(param, value, "x,y");
                let (x, y) = value.split_once(',').ok_or_else(bad)?;
                self.center = (number(param, x).map_err(|_| bad())?, {
                    number(param, y).map_err(|_| bad())?
                });
            }
            "radius" => {
                let r = number(param, value)?;
                if r <= 0.0 {
                    return Err(ParamError::bad(param, value, "a radius > 0"));
                }
                self.radius = r;
            }
            "speed" => self.speed = number_min(param, value, 0.0)?,
            "clockwise" => self.clockwise = moos_boolean(param, value, self.clockwise)?,
            "laps" => self.laps = number_min(param, value, 0.0)?,
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn on_idle(&mut self, _ctx: &Ctx<'_>, _out: &mut Out) {
        // Laps count while running, from where the vehicle is when it starts again.
        self.prev_bearing = None;
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let Some((x, y, _, _)) = behaviors::nav(ctx.info) else {
            out.warning(ctx.name, "No ownship position in the info buffer");
            return None;
        };
        let b = bearing(self.center, (x, y));
        if let Some(prev) = self.prev_bearing {
            let step = (b - prev + 540.0).rem_euclid(360.0) - 180.0;
            self.swept += if self.clockwise { step } else { -step };
        }
        self.prev_bearing = Some(b);
        if self.laps > 0.0 && self.laps_done() >= self.laps {
            out.complete();
            return None;
        }
        let mut course = ZaicPeak::new(ctx.domain, "course").ok()?;
        course
            .set_params(self.desired_course(x, y), 0.0, 180.0, 0.0, 0.0, 100.0)
            .ok()?;
        course.set_value_wrap(true);
        let mut speed = ZaicPeak::new(ctx.domain, "speed").ok()?;
        speed
            .set_params(self.speed, 0.1, 1.0, 10.0, 0.0, 100.0)
            .ok()?;
        couple(&course.extract().ok()?, &speed.extract().ok()?).ok()
    }
}
