//! The estimated state of one keyframe, its layout, and the frame helpers.
//!
//! Frame: the local grid of MOOS, x east and y north in metres, with depth (positive down) as
//! the third axis. Heading `psi` is the NED yaw: 0 north, clockwise positive, radians, kept
//! continuous (not wrapped) along the window so differences of states are plain differences.
//! A level-frame velocity `u = [forward, starboard, down]` (the body velocity rotated by pitch and
//! roll only) becomes a grid velocity through [`level_to_grid`].

use nalgebra::{SMatrix, SVector};

/// Size of one keyframe's state.
pub const DIM: usize = 7;
/// A keyframe state vector.
pub type V7 = SVector<f64, DIM>;
/// A 7x7 block (information, covariance, Jacobian products).
pub type M7 = SMatrix<f64, DIM, DIM>;

/// Index of x (east, m).
pub const X: usize = 0;
/// Index of y (north, m).
pub const Y: usize = 1;
/// Index of depth (m, positive down).
pub const Z: usize = 2;
/// Index of the heading (rad, NED yaw, continuous).
pub const PSI: usize = 3;
/// Index of the heading bias (rad): AHRS yaw = heading + bias.
pub const BIAS: usize = 4;
/// Index of the water current east (m/s).
pub const CX: usize = 5;
/// Index of the water current north (m/s).
pub const CY: usize = 6;

/// Wraps an angle to (-pi, pi].
pub fn wrap_pi(a: f64) -> f64 {
    // Most angles are already in range (and come back unchanged, not through a + 2 pi - 2 pi).
    if a > -std::f64::consts::PI && a <= std::f64::consts::PI {
        return a;
    }
    let tau = std::f64::consts::TAU;
    let mut w = a.rem_euclid(tau);
    if w > std::f64::consts::PI {
        w -= tau;
    }
    w
}

/// Rotates a level-frame vector `u = [forward, starboard, down]` by the heading `psi` onto the
/// grid: returns `[east, north, down]`.
pub fn level_to_grid(psi: f64, u: &[f64; 3]) -> [f64; 3] {
    let (s, c) = psi.sin_cos();
    [s * u[0] + c * u[1], c * u[0] - s * u[1], u[2]]
}

/// Derivative of [`level_to_grid`] with respect to `psi`.
pub fn level_to_grid_dpsi(psi: f64, u: &[f64; 3]) -> [f64; 3] {
    let (s, c) = psi.sin_cos();
    [c * u[0] - s * u[1], -s * u[0] - c * u[1], 0.0]
}

/// The inverse of [`level_to_grid`]: a grid vector `[east, north, down]` in the level frame.
pub fn grid_to_level(psi: f64, v: &[f64; 3]) -> [f64; 3] {
    let (s, c) = psi.sin_cos();
    [s * v[0] + c * v[1], c * v[0] - s * v[1], v[2]]
}

/// Rotates a body velocity (FRD) by pitch and roll (NED Euler, ZYX order) into the level frame.
pub fn body_to_level(v: &[f64; 3], pitch_rad: f64, roll_rad: f64) -> [f64; 3] {
    let (sr, cr) = roll_rad.sin_cos();
    let (sp, cp) = pitch_rad.sin_cos();
    // Roll about forward, then pitch about starboard.
    let a = [v[0], cr * v[1] - sr * v[2], sr * v[1] + cr * v[2]];
    [cp * a[0] + sp * a[2], a[1], -sp * a[0] + cp * a[2]]
}

/// The heading rate (rad/s) from body rates `[p, q, r]` at the given pitch and roll (ZYX Euler
/// kinematics).
pub fn yaw_rate(rates: &[f64; 3], pitch_rad: f64, roll_rad: f64) -> f64 {
    let (sr, cr) = roll_rad.sin_cos();
    let cp = pitch_rad.cos().max(0.05);
    (rates[1] * sr + rates[2] * cr) / cp
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames() {
        // Heading north, forward 1 m/s: north.
        let g = level_to_grid(0.0, &[1.0, 0.0, 0.0]);
        assert!((g[0]).abs() < 1e-12 && (g[1] - 1.0).abs() < 1e-12);
        // Heading east (90 deg compass): east.
        let g = level_to_grid(std::f64::consts::FRAC_PI_2, &[1.0, 0.0, 0.0]);
        assert!((g[0] - 1.0).abs() < 1e-12 && g[1].abs() < 1e-12);
        // Starboard while heading north: east.
        let g = level_to_grid(0.0, &[0.0, 1.0, 0.0]);
        assert!((g[0] - 1.0).abs() < 1e-12);
        let u = [0.3, -1.2, 0.1];
        let back = grid_to_level(0.7, &level_to_grid(0.7, &u));
        for k in 0..3 {
            assert!((back[k] - u[k]).abs() < 1e-12);
        }
        // Nose down 90 deg: forward becomes down.
        let l = body_to_level(&[1.0, 0.0, 0.0], -std::f64::consts::FRAC_PI_2, 0.0);
        assert!((l[2] - 1.0).abs() < 1e-12 && l[0].abs() < 1e-12);
        assert!((wrap_pi(3.0 * std::f64::consts::PI) - std::f64::consts::PI).abs() < 1e-12);
        assert!((wrap_pi(-0.1) + 0.1).abs() < 1e-15);
    }
}
