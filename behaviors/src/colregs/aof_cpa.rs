//! AOF_CPA (MOOS-IvP `lib_behaviors-colregs/AOF_CPA` at a2a9b716): the catch-all COLREGS
//! objective, utility of the closest point of approach alone.
//!
//! For the CPA distance `d` over the time on leg: 0 when `d < collision_distance`, 100 when
//! `d > all_clear_distance`, else `25 + 75 · (d − collision) / (all_clear − collision)`.

use super::Distances;

/// AOF_CPA over one contact.
#[derive(Debug, Clone)]
pub struct AofCpa {
    /// The CPA engine, time on leg and the two distances.
    pub d: Distances,
}

impl AofCpa {
    /// The function's metric of a CPA distance (MOOS `AOF_CPA::metric`).
    pub fn metric(&self, dist: f64) -> f64 {
        self.d.metric25(dist)
    }

    /// The utility of ownship course `crs` at speed `spd` (MOOS `evalBox`).
    pub fn eval(&self, crs: f64, spd: f64) -> f64 {
        self.metric(self.d.cpa(crs, spd))
    }
}
