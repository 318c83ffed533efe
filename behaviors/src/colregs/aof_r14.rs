//! AOF_R14 (MOOS-IvP `AOF_R14` at a2a9b716): COLREGS Rule 14, head-on, both vessels turning
//! to starboard and passing port to port.
//!
//! 0 for a course that passes the contact to its starboard (starboard to starboard), and,
//! when ownship is on the contact's port side, for one that crosses its bow. Otherwise the
//! CPA metric (`AOF_CPA`'s: 0, `25 + 75·…`, 100) plus a bearing-rate term: the initial rate
//! `b0` is the bearing rate if both vessels turned 90° to starboard of the line between them
//! at the contact's speed; when `b0 < 0` and the course's bearing rate `b < 0`, the term is
//! `100 · min(1, b / b0)`, else 0. The sum ranges 0..200.

use super::{Cpx, Distances};

/// AOF_R14 over one contact.
#[derive(Debug, Clone)]
pub struct AofR14 {
    /// The CPA engine, time on leg and the two distances.
    pub d: Distances,
    /// The pair's geometry.
    pub geo: Cpx,
    /// The initial bearing rate (MOOS `calculateInitialMaxBngRate`).
    pub initial_bng_rate: f64,
}

impl AofR14 {
    /// The function for the pair `geo` (its initial bearing rate worked out).
    pub fn new(d: Distances, geo: Cpx) -> Self {
        let (osx, osy, _, _) = geo.os;
        let (cnx, cny, _, cnv) = geo.cn;
        let os_right = geometry::angle_360(geometry::relative_angle(osx, osy, cnx, cny) + 90.0);
        let cn_right = geometry::angle_360(geometry::relative_angle(cnx, cny, osx, osy) + 90.0);
        let turned = Cpx::new(cnx, cny, cn_right, cnv, osx, osy, 0.0, 0.0);
        let initial_bng_rate = turned.bearing_rate(os_right, cnv);
        AofR14 {
            d,
            geo,
            initial_bng_rate,
        }
    }

    /// The bearing-rate term (MOOS `metric3`).
    pub fn metric3(&self, osh: f64, osv: f64) -> f64 {
        if self.initial_bng_rate >= 0.0 {
            return 0.0;
        }
        let br = self.geo.bearing_rate(osh, osv);
        if br >= 0.0 {
            return 0.0;
        }
        if br <= self.initial_bng_rate {
            return 100.0;
        }
        -br / -self.initial_bng_rate * 100.0
    }

    /// The utility of ownship course `crs` at speed `spd`.
    pub fn eval(&self, crs: f64, spd: f64) -> f64 {
        if self.geo.on_contact {
            return 0.0;
        }
        if self.geo.port && self.geo.crosses_bow(crs, spd) {
            return 0.0;
        }
        if self.geo.passes_star(crs, spd) {
            return 0.0;
        }
        self.d.metric25(self.d.cpa(crs, spd)) + self.metric3(crs, spd)
    }
}
