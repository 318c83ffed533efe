//! The baseline: plain DVL + AHRS integration (no heading bias, no current), with the same
//! inputs as the navigator, for comparison. It starts at the first GPS fix and never uses GPS
//! again; when the DVL is silent it holds the last velocity.

use crate::measurements::{Attitude, Depth, DvlVelocity, GpsFix};
use crate::state::{body_to_level, level_to_grid};

/// A DVL + AHRS dead reckoner.
#[derive(Debug, Clone, Default)]
pub struct DeadReckoner {
    pos: Option<[f64; 2]>,
    depth_m: f64,
    t_s: f64,
    att: Option<Attitude>,
    u: [f64; 3],
}

impl DeadReckoner {
    /// A reckoner waiting for its first fix.
    pub fn new() -> DeadReckoner {
        DeadReckoner::default()
    }

    fn advance(&mut self, t_s: f64) {
        let (Some(p), Some(a)) = (self.pos.as_mut(), self.att) else {
            return;
        };
        let dt = t_s - self.t_s;
        if dt > 0.0 && dt.is_finite() {
            let v = level_to_grid(a.yaw_rad, &self.u);
            p[0] += v[0] * dt;
            p[1] += v[1] * dt;
            self.t_s = t_s;
        }
    }

    /// A DVL report (invalid or non-finite ones are ignored: the last velocity is held).
    pub fn dvl(&mut self, m: &DvlVelocity) {
        if !m.valid || !m.t_s.is_finite() || !m.vel_body_mps.iter().all(|v| v.is_finite()) {
            return;
        }
        self.advance(m.t_s);
        let (p, r) = self.att.map_or((0.0, 0.0), |a| (a.pitch_rad, a.roll_rad));
        self.u = body_to_level(&m.vel_body_mps, p, r);
    }

    /// An attitude (the measured yaw is used as the heading).
    pub fn attitude(&mut self, m: &Attitude) {
        if m.check().is_err() {
            return;
        }
        self.advance(m.t_s);
        self.att = Some(*m);
    }

    /// A depth.
    pub fn depth(&mut self, m: &Depth) {
        if m.check().is_ok() {
            self.depth_m = m.depth_m;
        }
    }

    /// A GPS fix: only the first one is used, as the start.
    pub fn gps(&mut self, m: &GpsFix) {
        if self.pos.is_none() && m.check(0, f64::INFINITY).is_ok() {
            self.pos = Some([m.x_m, m.y_m]);
            self.t_s = m.t_s;
        }
    }

    /// The position (east, north, depth) at time `t_s`, holding the last velocity.
    pub fn position_at(&self, t_s: f64) -> Option<[f64; 3]> {
        let p = self.pos?;
        let mut me = self.clone();
        me.advance(t_s);
        let q = me.pos.unwrap_or(p);
        Some([q[0], q[1], self.depth_m])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::measurements::VelocityReference;

    #[test]
    fn integrates_heading_and_velocity() {
        let mut d = DeadReckoner::new();
        d.attitude(&Attitude {
            t_s: 0.0,
            yaw_rad: std::f64::consts::FRAC_PI_2,
            pitch_rad: 0.0,
            roll_rad: 0.0,
        });
        d.gps(&GpsFix {
            t_s: 0.0,
            x_m: 10.0,
            y_m: 5.0,
            hdop: 1.0,
            sats: 8,
        });
        d.dvl(&DvlVelocity {
            t_s: 0.0,
            vel_body_mps: [2.0, 0.0, 0.0],
            valid: true,
            fom_mps: 0.01,
            reference: VelocityReference::Ground,
        });
        let p = d.position_at(3.0).unwrap();
        assert!((p[0] - 16.0).abs() < 1e-9 && (p[1] - 5.0).abs() < 1e-9);
    }
}
