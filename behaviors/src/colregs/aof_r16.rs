//! AOF_R16 (MOOS-IvP `AOF_R16` at a2a9b716): COLREGS Rule 16, the give-way vessel crossing
//! the contact's stern or, when it is well clear, its bow.
//!
//! Passing to the stern (the default, `pts_port_turns_ok`): 0 for a course that crosses the
//! contact's bow, and for a course that is not a turn to starboard and does not cross its
//! stern; without `pts_port_turns_ok`, 0 unless the course crosses the stern and is not a
//! turn to port. Passing to the bow: a turn to starboard must cross the bow (and, with
//! `ok_cn_bow_cross_dist > 0`, by more than that). What is left gets the CPA metric (0 below
//! `collision_distance`, `25 + 75·…`, 100 beyond `all_clear_distance`, 0 when they are equal).

use super::geometry::{port_turn, star_turn};
use super::{Cpx, Distances};

/// Which side of the contact the give-way vessel aims for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GiveWaySide {
    /// Cross astern of the contact.
    Stern,
    /// Cross ahead of the contact.
    Bow,
}

/// AOF_R16 over one contact.
#[derive(Debug, Clone)]
pub struct AofR16 {
    /// The CPA engine, time on leg and the two distances.
    pub d: Distances,
    /// The pair's geometry.
    pub geo: Cpx,
    /// `passing_side`.
    pub side: GiveWaySide,
    /// `ok_cn_bow_cross_dist` (0: any bow crossing).
    pub ok_cn_bow_cross_dist: f64,
    /// `pts_port_turns_ok` (true by default).
    pub pts_port_turns_ok: bool,
}

impl AofR16 {
    /// The CPA metric (MOOS `AOF_R16::metricCPA`).
    pub fn metric_cpa(&self, dist: f64) -> f64 {
        let (min, max) = (self.d.collision_distance, self.d.all_clear_distance);
        if dist < min {
            return 0.0;
        }
        if dist > max {
            return 100.0;
        }
        if max - min == 0.0 {
            return 0.0;
        }
        25.0 + 75.0 * (dist - min) / (max - min)
    }

    /// The utility of ownship course `crs` at speed `spd`.
    pub fn eval(&self, crs: f64, spd: f64) -> f64 {
        let osh = self.geo.os.2;
        match self.side {
            GiveWaySide::Stern => {
                if self.pts_port_turns_ok {
                    if self.geo.crosses_bow(crs, spd) {
                        return 0.0;
                    }
                    if !star_turn(osh, crs) && !self.geo.crosses_stern(crs, spd) {
                        return 0.0;
                    }
                } else if !self.geo.crosses_stern(crs, spd) || port_turn(osh, crs) {
                    return 0.0;
                }
            }
            GiveWaySide::Bow => {
                if star_turn(osh, crs) {
                    if !self.geo.crosses_bow(crs, spd) {
                        return 0.0;
                    }
                    if self.ok_cn_bow_cross_dist > 0.0
                        && self.geo.crosses_bow_dist(crs, spd) <= self.ok_cn_bow_cross_dist
                    {
                        return 0.0;
                    }
                }
            }
        }
        self.metric_cpa(self.d.cpa(crs, spd))
    }
}
