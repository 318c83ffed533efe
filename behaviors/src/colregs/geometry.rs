//! The relative geometry the COLREGS behaviours classify encounters with (MOOS-IvP
//! `CPXEngine`/`CPXEngineOG` passing and crossing predicates and IvPContactBehavior's
//! contact state at a2a9b716), written beside [`crate::cpa`] so its engine stays as it is.
//!
//! A [`Cpx`] holds one vehicle pair seen from "ownship" (`os`) with "the contact" (`cn`):
//! where ownship is relative to the contact's bow-stern line and beam, and, for any course and
//! speed of ownship, whether it passes the contact to port or starboard (crosses the
//! contact's beam line) or crosses its bow or stern (crosses its bow-stern line), and by how
//! much. The distances along the contact's heading are `eps` (to the beam line) and across it
//! `gam` (to the bow-stern line). Course-dependent terms are taken at the whole degree below
//! the course, as the C++ caches them.
//!
//! [`crate::contact_state::ContactState`] is what IvPContactBehavior keeps each iteration
//! from a pair (its `m_cnos`): the pair seen both ways (ownship to contact and contact to
//! ownship).

use geometry::{angle_180, angle_360, relative_angle};

use crate::cpa::rel_bearing;

/// The value of pi the C++ engines' bearing rate uses (their `MPI`, 12 digits).
#[allow(clippy::approx_constant)]
pub const MOOS_PI: f64 = 3.14159265359;

/// MOOS `degToRadians`.
fn rad(deg: f64) -> f64 {
    (deg / 180.0) * std::f64::consts::PI
}

/// The cosine of the angle between a heading (whole degree `i`) and `theta`, 0 at exactly
/// 90° (the C++ caches' special case).
fn cos_between(i: usize, theta: f64) -> f64 {
    let mut d = i as f64 - theta;
    if d > 180.0 {
        d -= 360.0;
    } else if d < -180.0 {
        d += 360.0;
    }
    let d = d.abs();
    if d == 90.0 { 0.0 } else { rad(d).cos() }
}

/// The whole degree of a course, after wrapping into `[0, 360)`.
fn ix(osh: f64) -> usize {
    (angle_360(osh) as usize).min(359)
}

/// Relative position of a point seen from a vehicle at `(x, y)` heading `h` (MOOS
/// `ptForeOfOwnship`, `ptAftOfOwnship`, `ptPortOfOwnship`, `ptStarOfOwnship`): fore, aft,
/// port, starboard; all false when the point is the vehicle's position. Abeam is both fore
/// and aft, dead ahead or astern both port and starboard.
pub fn sides(x: f64, y: f64, h: f64, px: f64, py: f64) -> (bool, bool, bool, bool) {
    if x == px && y == py {
        return (false, false, false, false);
    }
    let rb = rel_bearing(x, y, h, px, py);
    (
        rb <= 90.0 || rb >= 270.0,
        (90.0..=270.0).contains(&rb),
        (180.0..=360.0).contains(&rb),
        (0.0..=180.0).contains(&rb),
    )
}

/// The speed of a vehicle heading `osh` at `osv` along `heading` (MOOS `speedInHeading`).
pub fn speed_in_heading(osh: f64, osv: f64, heading: f64) -> f64 {
    if osv == 0.0 {
        return 0.0;
    }
    let delta = angle_180(osh - heading).abs();
    if delta == 0.0 {
        osv
    } else if delta == 180.0 {
        -osv
    } else if delta == 90.0 {
        0.0
    } else {
        rad(delta).cos() * osv
    }
}

/// Whether turning from `osh` to `new_hdg` is a turn to port (MOOS `portTurn`: a clockwise
/// change of more than 180°).
pub fn port_turn(osh: f64, new_hdg: f64) -> bool {
    angle_360(new_hdg - osh) > 180.0
}

/// Whether turning from `osh` to `new_hdg` is a turn to starboard (MOOS `starTurn`: a
/// clockwise change strictly between 0 and 180°).
pub fn star_turn(osh: f64, new_hdg: f64) -> bool {
    let d = angle_360(new_hdg - osh);
    d > 0.0 && d < 180.0
}

/// The gap between the line through `(px1, py1)`-`(px2, py2)` and the circle of radius
/// `radius` ownship would draw turning hard to starboard (`right`) or port from `(osx, osy)`
/// heading `osh` (MOOS `turnGap`): 0 when they meet.
#[allow(clippy::too_many_arguments)]
pub fn turn_gap(
    osx: f64,
    osy: f64,
    osh: f64,
    radius: f64,
    (px1, py1): (f64, f64),
    (px2, py2): (f64, f64),
    right: bool,
) -> f64 {
    let a = if right {
        angle_360(osh + 90.0)
    } else {
        angle_360(osh - 90.0)
    };
    let (s, c) = rad(a).sin_cos();
    let (cx, cy) = (osx + s * radius, osy + c * radius);
    let (dx, dy) = (px2 - px1, py2 - py1);
    let len2 = dx * dx + dy * dy;
    let (ix, iy) = if len2 == 0.0 {
        (px1, py1)
    } else {
        let t = ((cx - px1) * dx + (cy - py1) * dy) / len2;
        (px1 + t * dx, py1 + t * dy)
    };
    let dist = (cx - ix).hypot(cy - iy);
    if dist > radius { dist - radius } else { 0.0 }
}

/// Point `dist` metres from `(x, y)` along `heading` (MOOS `projectPoint`).
pub fn project_point(heading: f64, dist: f64, x: f64, y: f64) -> (f64, f64) {
    let (s, c) = rad(heading).sin_cos();
    (x + s * dist, y + c * dist)
}

/// One vehicle pair, seen from ownship (MOOS `CPXEngineOG` without its CPA part, which is
/// [`CpaEngine`]'s).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Cpx {
    /// Ownship x, y, heading (in `[0, 360)`), speed (>= 0).
    pub os: (f64, f64, f64, f64),
    /// The contact's x, y, heading (in `[0, 360)`), speed (>= 0).
    pub cn: (f64, f64, f64, f64),
    /// Range, m.
    pub range: f64,
    /// Relative bearing of ownship seen from the contact (its "contact angle"), degrees.
    pub rel_bng_cn_os: f64,
    /// Relative bearing of the contact seen from ownship, degrees.
    pub rel_bng_os_cn: f64,
    /// Absolute bearing from ownship to the contact, degrees.
    pub abs_bng_os_cn: f64,
    /// Ownship is on the contact's position.
    pub on_contact: bool,
    /// Ownship is exactly on the contact's bow line.
    pub on_bowline: bool,
    /// Ownship is exactly on the contact's stern line.
    pub on_sternline: bool,
    /// On the contact, its bow line or its stern line.
    pub on_bowsternline: bool,
    /// Exactly abeam of the contact (or on it).
    pub on_beam: bool,
    /// Ownship is fore of the contact's beam.
    pub fore: bool,
    /// Ownship is aft of the contact's beam.
    pub aft: bool,
    /// Ownship is on the contact's port side.
    pub port: bool,
    /// Ownship is on the contact's starboard side.
    pub star: bool,
    /// The contact's speed toward ownship, m/s.
    pub cn_to_os_spd: f64,
    /// Distance from ownship to the contact's bow-stern line, m.
    pub range_gam: f64,
    /// Distance from ownship to the contact's beam line, m.
    pub range_eps: f64,
    theta_tn: f64,
    theta_os_gam: f64,
    spd_cn_at_tangent: f64,
    tn_constant: f64,
    /// V26 with a Dubins platform model: the course-dependent passing and crossing
    /// predicates follow the model's turn ([`super::plat_cpx`]); `None`: a ray.
    pub pm: Option<std::sync::Arc<super::plat_cpx::PlatCpx>>,
}

impl Cpx {
    /// The pair: the contact at `(cnx, cny)` heading `cnh` at `cnv`, ownship at `(osx, osy)`
    /// heading `osh` at `osv` (negative speeds are 0).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        cnx: f64,
        cny: f64,
        cnh: f64,
        cnv: f64,
        osx: f64,
        osy: f64,
        osh: f64,
        osv: f64,
    ) -> Self {
        let cnh = angle_360(cnh);
        let osh = angle_360(osh);
        let cnv = cnv.max(0.0);
        let osv = osv.max(0.0);
        let rel_bng_cn_os = rel_bearing(cnx, cny, cnh, osx, osy);
        let rel_bng_os_cn = rel_bearing(osx, osy, osh, cnx, cny);
        let abs_bng_os_cn = relative_angle(osx, osy, cnx, cny);
        let on_contact = osx == cnx && osy == cny;
        let ang_cn_os = relative_angle(cnx, cny, osx, osy);
        let on_bowline = ang_cn_os == cnh;
        let on_sternline = !on_bowline && ang_cn_os == angle_360(cnh - 180.0);
        let (fore, aft, port, star) = sides(cnx, cny, cnh, osx, osy);
        let on_beam = on_contact || (fore && aft);
        let cn_to_os_spd = if rel_bng_cn_os != 90.0 {
            cnv * rad(rel_bng_cn_os).cos()
        } else {
            0.0
        };
        let range = (osx - cnx).hypot(osy - cny);
        // The OG engine's gamma/epsilon (its gamma cache's initialisation wins over the root's).
        let mut rb180 = rel_bng_cn_os;
        if rb180 > 180.0 {
            rb180 -= 360.0;
        } else if rb180 < -180.0 {
            rb180 += 360.0;
        }
        let rb180 = rb180.abs();
        let (range_gam, range_eps) = if rb180 == 0.0 || rb180 == 180.0 {
            (0.0, range)
        } else {
            let gam = range * rad(90.0 - rb180).cos();
            (gam, (range * range - gam * gam).max(0.0).sqrt())
        };
        let theta_tn = angle_360(abs_bng_os_cn + 90.0);
        let d = angle_180(cnh - theta_tn).abs();
        let spd_cn_at_tangent = if d != 90.0 { rad(d).cos() * cnv } else { 0.0 };
        let tn_constant = 360.0 / (2.0 * range * MOOS_PI);
        let theta_os_gam = if port {
            angle_360(cnh + 90.0)
        } else {
            angle_360(cnh - 90.0)
        };
        Cpx {
            os: (osx, osy, osh, osv),
            cn: (cnx, cny, cnh, cnv),
            range,
            rel_bng_cn_os,
            rel_bng_os_cn,
            abs_bng_os_cn,
            on_contact,
            on_bowline,
            on_sternline,
            on_bowsternline: on_contact || on_bowline || on_sternline,
            on_beam,
            fore,
            aft,
            port,
            star,
            cn_to_os_spd,
            range_gam,
            range_eps,
            theta_tn,
            theta_os_gam,
            spd_cn_at_tangent,
            tn_constant,
            pm: None,
        }
    }

    /// The pair with ownship's platform model: its course-dependent passing and crossing
    /// predicates are the platform-model engine's ([`super::plat_cpx::PlatCpx`]).
    pub fn with_plat_model(mut self, model: std::sync::Arc<crate::plat_model::PlatModel>) -> Self {
        let pm = super::plat_cpx::PlatCpx::new(model, self.cn);
        self.pm = Some(std::sync::Arc::new(pm));
        self
    }

    /// The pair seen from the contact: the contact as ownship, ownship as the contact.
    pub fn reversed(&self) -> Cpx {
        let (ox, oy, oh, ov) = self.os;
        let (cx, cy, ch, cv) = self.cn;
        Cpx::new(ox, oy, oh, ov, cx, cy, ch, cv)
    }

    /// Ownship's speed along the contact's heading at course `osh` and speed `osv`.
    fn v_os_cnh(&self, osh: f64, osv: f64) -> f64 {
        cos_between(ix(osh), self.cn.2) * osv
    }

    /// Ownship's speed toward the contact's bow-stern line.
    fn v_os_gam(&self, osh: f64, osv: f64) -> f64 {
        cos_between(ix(osh), self.theta_os_gam) * osv
    }

    /// Ownship's closing speed on the contact's beam line.
    fn v_os_eps(&self, osh: f64, osv: f64) -> f64 {
        let v = self.v_os_cnh(osh, osv);
        if self.aft {
            v - self.cn.3
        } else {
            self.cn.3 - v
        }
    }

    /// The rate, degrees per second, at which the contact's bearing from ownship changes at
    /// ownship course `osh` and speed `osv` (MOOS `bearingRate`; positive clockwise).
    pub fn bearing_rate(&self, osh: f64, osv: f64) -> f64 {
        let os_at_tangent = cos_between(ix(osh), self.theta_tn) * -osv;
        (os_at_tangent + self.spd_cn_at_tangent) * self.tn_constant
    }

    /// Whether ownship will cross the contact's beam line (pass it on one side) (MOOS
    /// `passesPortOrStar`).
    pub fn passes(&self, osh: f64, osv: f64) -> bool {
        if let Some(pm) = &self.pm {
            return pm.passes(osh, osv);
        }
        self.on_beam || self.v_os_eps(osh, osv) > 0.0
    }

    /// Whether ownship will pass the contact on the contact's port side (MOOS `passesPort`).
    pub fn passes_port(&self, osh: f64, osv: f64) -> bool {
        if let Some(pm) = &self.pm {
            return pm.passes_port(osh, osv);
        }
        if self.on_contact || !self.passes(osh, osv) {
            return false;
        }
        if self.aft && self.fore {
            return self.port;
        }
        if self.aft {
            self.bearing_rate(osh, osv) > 0.0
        } else {
            self.bearing_rate(osh, osv) < 0.0
        }
    }

    /// Whether ownship will pass the contact on its starboard side (MOOS `passesStar`).
    pub fn passes_star(&self, osh: f64, osv: f64) -> bool {
        if let Some(pm) = &self.pm {
            return pm.passes_star(osh, osv);
        }
        !self.on_contact && self.passes(osh, osv) && !self.passes_port(osh, osv)
    }

    /// The side distance at which ownship passes the contact's beam line, or −1 (MOOS
    /// `passesPortDist` with `port`, `passesStarDist` without).
    fn passes_dist(&self, osh: f64, osv: f64, port: bool) -> f64 {
        if let Some(pm) = &self.pm {
            return if port {
                pm.passes_port_dist(osh, osv)
            } else {
                pm.passes_star_dist(osh, osv)
            };
        }
        let (same, other) = if port {
            (self.port, self.star)
        } else {
            (self.star, self.port)
        };
        if self.on_contact || (self.on_beam && other) {
            return -1.0;
        }
        if self.on_beam && same {
            return self.range;
        }
        let v_eps = self.v_os_eps(osh, osv);
        if v_eps <= 0.0 {
            return -1.0;
        }
        let t = self.range_eps / v_eps;
        let gam_dist = t * self.v_os_gam(osh, osv);
        let mut x = -1.0;
        if same && gam_dist <= self.range_gam {
            x = self.range_gam - gam_dist;
        }
        if other && gam_dist > self.range_gam {
            x = gam_dist - self.range_gam;
        }
        if x < 0.0 { -1.0 } else { x }
    }

    /// How far to the contact's port ownship passes its beam line, or −1 (MOOS
    /// `passesPortDist`).
    pub fn passes_port_dist(&self, osh: f64, osv: f64) -> f64 {
        self.passes_dist(osh, osv, true)
    }

    /// How far to the contact's starboard ownship passes its beam line, or −1 (MOOS
    /// `passesStarDist`).
    pub fn passes_star_dist(&self, osh: f64, osv: f64) -> f64 {
        self.passes_dist(osh, osv, false)
    }

    /// Whether ownship will cross the contact's stern (MOOS `crossesStern`).
    pub fn crosses_stern(&self, osh: f64, osv: f64) -> bool {
        if let Some(pm) = &self.pm {
            return pm.crosses_stern(osh, osv);
        }
        if self.on_sternline {
            return true;
        }
        if osv <= 0.0 || cos_between(ix(osh), self.theta_os_gam) <= 0.0 {
            return false;
        }
        let br = self.bearing_rate(osh, osv);
        if self.port { br <= 0.0 } else { br >= 0.0 }
    }

    /// Whether ownship will cross the contact's bow (MOOS `crossesBow`; on the stern line it
    /// answers true, as the C++ does).
    pub fn crosses_bow(&self, osh: f64, osv: f64) -> bool {
        if let Some(pm) = &self.pm {
            return pm.crosses_bow(osh, osv);
        }
        if self.on_sternline {
            return true;
        }
        if osv <= 0.0 || cos_between(ix(osh), self.theta_os_gam) <= 0.0 {
            return false;
        }
        let br = self.bearing_rate(osh, osv);
        if self.port { br >= 0.0 } else { br <= 0.0 }
    }

    /// How far ahead of the contact ownship crosses its bow-stern line, or −1 when it crosses
    /// astern or not at all (MOOS `crossesBowDist`).
    pub fn crosses_bow_dist(&self, osh: f64, osv: f64) -> f64 {
        if let Some(pm) = &self.pm {
            return pm.crosses_bow_dist(osh, osv);
        }
        if self.on_bowline {
            return self.range;
        }
        if self.on_sternline || self.on_contact {
            return -1.0;
        }
        let v_gam = self.v_os_gam(osh, osv);
        if v_gam <= 0.0 {
            return -1.0;
        }
        let t = self.range_gam / v_gam;
        let mut x = t * self.v_os_cnh(osh, osv) - t * self.cn.3;
        if self.fore {
            x += self.range_eps;
        } else {
            x -= self.range_eps;
        }
        if x < 0.0 { -1.0 } else { x }
    }

    /// Whether ownship will cross the contact's bow-stern line at all (MOOS
    /// `crossesBowOrStern`).
    pub fn crosses_bow_or_stern(&self, osh: f64, osv: f64) -> bool {
        if let Some(pm) = &self.pm {
            return pm.crosses_bow_or_stern(osh, osv);
        }
        if self.on_bowsternline {
            return true;
        }
        osv > 0.0 && cos_between(ix(osh), self.theta_os_gam) > 0.00001
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sides_and_turns() {
        // A vehicle at the origin heading north; a point due east is fore, aft and starboard.
        assert_eq!(sides(0.0, 0.0, 0.0, 10.0, 0.0), (true, true, false, true));
        assert_eq!(
            sides(0.0, 0.0, 0.0, -10.0, 10.0),
            (true, false, true, false)
        );
        assert_eq!(sides(0.0, 0.0, 0.0, 0.0, 0.0), (false, false, false, false));
        assert!(port_turn(10.0, 300.0) && !port_turn(10.0, 100.0));
        assert!(star_turn(350.0, 20.0) && !star_turn(20.0, 20.0));
        assert_eq!(speed_in_heading(0.0, 2.0, 180.0), -2.0);
        assert!((speed_in_heading(0.0, 2.0, 60.0) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn turn_gap_is_the_distance_from_the_turning_circle_to_the_line() {
        // Ownship at the origin heading north, radius 10: the circle's centre is (10, 0).
        // The line x = 50 is 40 m from the centre: gap 30.
        let g = turn_gap(0.0, 0.0, 0.0, 10.0, (50.0, 0.0), (50.0, 100.0), true);
        assert!((g - 30.0).abs() < 1e-9);
        // Turning to port the centre is (-10, 0): 60 - 10.
        let g = turn_gap(0.0, 0.0, 0.0, 10.0, (50.0, 0.0), (50.0, 100.0), false);
        assert!((g - 50.0).abs() < 1e-9);
    }
}
