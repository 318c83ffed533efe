//! AOF_R17 (MOOS-IvP `AOF_R17` at a2a9b716): COLREGS Rule 17, the stand-on vessel holding
//! course and speed, or acting alone in extremis. The C++ behaviours of every version build
//! their stand-on function from ZAICs instead ([`super::AvdColregs`]); this objective is kept
//! for users' behaviours, as MOOS-IvP keeps it in its library.
//!
//! Holding (`passing_side` other than `inextremis`): with `dc = |angle180(crs − original
//! course)|` and `dv = |spd − original speed|`, `fc = (20 − dc) / 20` when `dc < 20` else 0,
//! `fv = (1.5 − dv) / 1.5` when `dv < 1.5` else 0, utility `100 · (2·fc + fv) / 3`.
//! In extremis: 0 for a turn to port while the contact is on ownship's port side (relative
//! bearing > 180), else the CPA metric (0, `25 + 75·…`, 100; 0 when the distances are equal).

use super::geometry::port_turn;
use super::{Cpx, Distances};

/// AOF_R17 over one contact.
#[derive(Debug, Clone)]
pub struct AofR17 {
    /// The CPA engine, time on leg and the two distances.
    pub d: Distances,
    /// The pair's geometry.
    pub geo: Cpx,
    /// The course ownship held when it became the stand-on vessel, degrees.
    pub original_course: f64,
    /// The speed it held then, m/s.
    pub original_speed: f64,
    /// Act in extremis (`passing_side = inextremis`) rather than hold.
    pub inextremis: bool,
}

/// The passing sides AOF_R17 accepts (its `passing_side` parameter).
pub const R17_SIDES: [&str; 7] = [
    "stern",
    "bow",
    "unsure",
    "unsure_bow",
    "unsure_stern",
    "neither",
    "inextremis",
];

impl AofR17 {
    /// The hold-course-and-speed utility (MOOS `utilityHold`).
    pub fn utility_hold(&self, crs: f64, spd: f64) -> f64 {
        let dc = geometry::angle_180(crs - self.original_course).abs();
        let fc = if dc < 20.0 { (20.0 - dc) / 20.0 } else { 0.0 };
        let dv = (spd - self.original_speed).abs();
        let fv = if dv < 1.5 { (1.5 - dv) / 1.5 } else { 0.0 };
        (2.0 * fc + fv) / 3.0 * 100.0
    }

    /// The in-extremis utility (MOOS `utilityAvoid`).
    pub fn utility_avoid(&self, crs: f64, spd: f64) -> f64 {
        if self.geo.rel_bng_os_cn > 180.0 && port_turn(self.geo.os.2, crs) {
            return 0.0;
        }
        let dist = self.d.cpa(crs, spd);
        let (min, max) = (self.d.collision_distance, self.d.all_clear_distance);
        if dist < min {
            0.0
        } else if dist > max {
            100.0
        } else if max - min == 0.0 {
            0.0
        } else {
            25.0 + 75.0 * (dist - min) / (max - min)
        }
    }

    /// The utility of ownship course `crs` at speed `spd`.
    pub fn eval(&self, crs: f64, spd: f64) -> f64 {
        if self.inextremis {
            self.utility_avoid(crs, spd)
        } else {
            self.utility_hold(crs, spd)
        }
    }
}
