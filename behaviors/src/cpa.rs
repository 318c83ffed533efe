//! The closest-point-of-approach engine the contact behaviours and the contact manager share
//! (MOOS-IvP `CPXEngineOG` / `CPAEngine` at a2a9b716, the parts coug uses).
//!
//! Ownship at `(osx, osy)` holding course `osh` (degrees, whole-degree resolution as the C++
//! caches) and speed `osv`; the contact at `(cnx, cny)` holding heading `cnh` and speed `cnv`.
//! The squared range after `t` seconds is `k2·t² + k1·t + k0`; the CPA distance within a time
//! on leg `tol` is the range at the vertex of that parabola, clipped to `[0, tol]`, with the
//! C++ shortcuts: when the vehicles are already opening (or, for a closing contact, when
//! ownship outruns the contact toward it) the CPA is the present range.

use geometry::{angle_360, relative_angle};

/// MOOS `degToRadians`: `(deg / 180) · π`.
fn rad(deg: f64) -> f64 {
    (deg / 180.0) * std::f64::consts::PI
}

/// Relative bearing of `(x1, y1)` seen from `(x0, y0)` heading `h0` (MOOS `relBearing`).
pub fn rel_bearing(x0: f64, y0: f64, h0: f64, x1: f64, y1: f64) -> f64 {
    angle_360(relative_angle(x0, y0, x1, y1) - h0)
}

/// A CPA engine for one contact and ownship position (MOOS `CPXEngineOG`).
///
/// ```
/// use behaviors::cpa::CpaEngine;
/// // Contact 100 m north heading south at 1 m/s; ownship at the origin.
/// let e = CpaEngine::new(0.0, 100.0, 180.0, 1.0, 0.0, 0.0);
/// assert_eq!(e.range(), 100.0);
/// assert!(e.eval_cpa(0.0, 1.0, 120.0) < 1e-6, "head-on: they meet");
/// assert!((e.eval_cpa(90.0, 1.0, 120.0) - 70.71).abs() < 0.01);
/// ```
#[derive(Debug, Clone)]
pub struct CpaEngine {
    range: f64,
    k0: f64,
    k1: f64,
    k2: f64,
    cn_to_os_spd: f64,
    closing: bool,
    k1_cache: Vec<f64>,
    k2_cache: Vec<f64>,
    vthresh: Vec<f64>,
    relbng_cos: Vec<f64>,
}

impl CpaEngine {
    /// The engine for a contact at `(cnx, cny)` heading `cnh` at `cnv` (negative speeds are
    /// 0) and ownship at `(osx, osy)`.
    pub fn new(cnx: f64, cny: f64, cnh: f64, cnv: f64, osx: f64, osy: f64) -> Self {
        let cnh = angle_360(cnh);
        let cnv = cnv.max(0.0);
        let rel_bng_cn_os = rel_bearing(cnx, cny, cnh, osx, osy);
        let cn_to_os_spd = if rel_bng_cn_os != 90.0 {
            cnv * rad(rel_bng_cn_os).cos()
        } else {
            0.0
        };
        let closing = cn_to_os_spd > 0.0;
        let range = (osx - cnx).hypot(osy - cny);
        let (sin_cnh, cos_cnh) = rad(cnh).sin_cos();
        let cos_x_spd = -2.0 * cos_cnh * cnv;
        let sin_x_spd = -2.0 * sin_cnh * cnv;
        let k2 = cnv * cnv;
        let mut k1 = -2.0 * osy * cos_cnh * cnv;
        k1 += -2.0 * osx * sin_cnh * cnv;
        k1 += 2.0 * cny * cos_cnh * cnv;
        k1 += 2.0 * cnx * sin_cnh * cnv;
        let mut k0 = osy * osy;
        k0 += osx * osx;
        k0 += -2.0 * osy * cny;
        k0 += -2.0 * osx * cnx;
        k0 += cny * cny;
        k0 += cnx * cnx;
        let mut k1_cache = Vec::with_capacity(360);
        let mut k2_cache = Vec::with_capacity(360);
        for i in 0..360 {
            let (s, c) = rad(f64::from(i)).sin_cos();
            let mut v = 2.0 * c * osy;
            v += 2.0 * s * osx;
            v += -2.0 * c * cny;
            v += -2.0 * s * cnx;
            k1_cache.push(v);
            k2_cache.push(c * cos_x_spd + s * sin_x_spd);
        }
        // Speeds at which ownship's own motion makes the present range the CPA.
        let mut vthresh = vec![999.0; 360];
        let (from, sign) = if closing {
            (relative_angle(cnx, cny, osx, osy), 1.0)
        } else {
            (relative_angle(osx, osy, cnx, cny), -1.0)
        };
        for (i, slot) in vthresh.iter_mut().enumerate() {
            let cos_delta = rad(i as f64 - from).cos();
            if cos_delta > 0.0001 {
                *slot = sign * cn_to_os_spd / cos_delta;
            }
        }
        let os_cn = relative_angle(osx, osy, cnx, cny);
        let relbng_cos = (0..360)
            .map(|i| {
                let mut b = os_cn - f64::from(i);
                if b < 0.0 {
                    b += 360.0;
                } else if b >= 360.0 {
                    b -= 360.0;
                }
                if b != 90.0 && b != 270.0 {
                    rad(b).cos()
                } else {
                    0.0
                }
            })
            .collect();
        CpaEngine {
            range,
            k0,
            k1,
            k2,
            cn_to_os_spd,
            closing,
            k1_cache,
            k2_cache,
            vthresh,
            relbng_cos,
        }
    }

    /// The present range, m.
    pub fn range(&self) -> f64 {
        self.range
    }

    /// The contact's speed toward ownship, m/s (negative when it moves away).
    pub fn cn_speed_toward_os(&self) -> f64 {
        self.cn_to_os_spd
    }

    fn ix(osh: f64) -> usize {
        let h = if !(0.0..360.0).contains(&osh) {
            angle_360(osh)
        } else {
            osh
        };
        (h as usize).min(359)
    }

    /// The closest point of approach, m, if ownship holds course `osh` at `osv` for `tol`
    /// seconds (MOOS `evalCPA`).
    pub fn eval_cpa(&self, osh: f64, osv: f64, tol: f64) -> f64 {
        let i = Self::ix(osh);
        if self.closing {
            if osv > self.cn_to_os_spd && osv >= self.vthresh[i] {
                return self.range;
            }
        } else if osv <= self.vthresh[i] {
            return self.range;
        }
        let k2 = self.k2 + (self.k2_cache[i] + osv) * osv;
        if k2 < 0.0 {
            return self.range;
        }
        let k1 = self.k1 + self.k1_cache[i] * osv;
        let mut min_t = 0.0;
        if k2 != 0.0 {
            min_t = k1 / (-2.0 * k2);
        }
        if min_t <= 0.0 {
            return self.range;
        }
        if min_t >= tol {
            min_t = tol;
        }
        let d2 = min_t * ((k2 * min_t) + k1) + self.k0;
        if d2 > 0.0 { d2.sqrt() } else { 0.0 }
    }

    /// The rate of closure, m/s, at course `osh` and speed `osv` (MOOS `evalROC`).
    pub fn eval_roc(&self, osh: f64, osv: f64) -> f64 {
        self.relbng_cos[Self::ix(osh)] * osv + self.cn_to_os_spd
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_cpa_is_the_vertex_of_the_range_parabola() {
        // Contact at (100, 0) heading west at 2 m/s, ownship at the origin heading north at
        // 2 m/s: relative motion (-2, -2)·t from (100, 0): closest at t = 25 s, at
        // (50, -50): 70.71 m.
        let e = CpaEngine::new(100.0, 0.0, 270.0, 2.0, 0.0, 0.0);
        assert!((e.eval_cpa(0.0, 2.0, 120.0) - 50.0 * 2f64.sqrt()).abs() < 1e-9);
        // With a 10 s leg the CPA is the range at 10 s: (80, -20).
        assert!((e.eval_cpa(0.0, 2.0, 10.0) - 80f64.hypot(20.0)).abs() < 1e-9);
        // Heading west, away faster than the contact comes: present range.
        assert_eq!(e.eval_cpa(270.0, 3.0, 120.0), 100.0);
        // Stopped: the contact passes through the origin.
        assert!(e.eval_cpa(0.0, 0.0, 120.0) < 1e-6);
        // Rate of closure heading at it at 1 m/s: 1 + 2.
        assert!((e.eval_roc(90.0, 1.0) - 3.0).abs() < 1e-12);
    }

    #[test]
    fn an_opening_contact_gives_the_present_range_unless_ownship_chases() {
        // Contact at (0, 50) heading north (away) at 1 m/s.
        let e = CpaEngine::new(0.0, 50.0, 0.0, 1.0, 0.0, 0.0);
        assert!(e.cn_speed_toward_os() < 0.0);
        assert_eq!(e.eval_cpa(0.0, 1.0, 60.0), 50.0);
        // Chasing at 2 m/s for 60 s closes 60 m: they meet at t = 50.
        assert!(e.eval_cpa(0.0, 2.0, 60.0) < 1e-6);
        // For 30 s: 20 m.
        assert!((e.eval_cpa(0.0, 2.0, 30.0) - 20.0).abs() < 1e-9);
    }
}
