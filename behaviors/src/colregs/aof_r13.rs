//! AOF_R13 (MOOS-IvP `AOF_R13` at a2a9b716): COLREGS Rule 13, ownship overtaking the contact
//! and passing it on a chosen side.
//!
//! For the CPA distance `d`: 0 when `d < collision_distance`; else the CPA metric, 100 beyond
//! `all_clear_distance`, otherwise `15 + 85 · (d − collision) / (all_clear − collision)`
//! (0 when the two distances are equal). Then, at a non-zero speed, when passing to port was
//! asked and the course passes the contact to starboard, the utility is 0 unless the course's
//! port passing distance reaches `collision_distance` (it never does when the course passes
//! to starboard: the C++ asks for the other side's distance, which is then −1); the same
//! mirrored for starboard.

use super::{Cpx, Distances};

/// AOF_R13 over one contact.
#[derive(Debug, Clone)]
pub struct AofR13 {
    /// The CPA engine, time on leg and the two distances.
    pub d: Distances,
    /// The pair's geometry.
    pub geo: Cpx,
    /// Pass the contact on its port side (`passing_side = port`), else starboard.
    pub pass_to_port: bool,
}

impl AofR13 {
    /// The CPA metric (MOOS `AOF_R13::metricCPA`).
    pub fn metric_cpa(&self, dist: f64) -> f64 {
        let (min, max) = (self.d.collision_distance, self.d.all_clear_distance);
        if dist > max {
            return 100.0;
        }
        if max - min == 0.0 {
            return 0.0;
        }
        15.0 + 85.0 * (dist - min) / (max - min)
    }

    fn passes_side(&self, utility: f64, hdg: f64, spd: f64) -> f64 {
        if spd == 0.0 {
            return utility;
        }
        let coll = self.d.collision_distance;
        if self.pass_to_port {
            if self.geo.passes_star(hdg, spd) && self.geo.passes_port_dist(hdg, spd) < coll {
                return 0.0;
            }
        } else if self.geo.passes_port(hdg, spd) && self.geo.passes_star_dist(hdg, spd) < coll {
            return 0.0;
        }
        utility
    }

    /// The utility of ownship course `crs` at speed `spd`.
    pub fn eval(&self, crs: f64, spd: f64) -> f64 {
        let dist = self.d.cpa(crs, spd);
        if dist < self.d.collision_distance {
            return 0.0;
        }
        let u = self.metric_cpa(dist);
        if u > 0.0 {
            self.passes_side(u, crs, spd)
        } else {
            u
        }
    }
}
