//! BHV_Waypoint's `ipf_type = roc` (or `rate_of_closure`): MOOS `AOF_Waypoint` reflected
//! into pieces (BHV_Waypoint `buildOF` at a2a9b716).
//!
//! The objective of a (course, speed) is 80 % a rate-of-closure score and 20 % a
//! rate-of-detour score. With `a` the course's angle off the bearing to the track point
//! (0..360), the rate of closure is `cos(a) * speed`; its shortfall from the desired speed
//! (an excess counts half) is capped at twice the domain's top speed `m` and scored
//! `100 * (1 - shortfall / 2m)`. The rate of detour is `|angle180(a)| * speed` (a negative
//! speed counts 0), scored `100 * (1 - detour / 180m)`. The reflector builds it over the
//! behaviour's course and speed as the C++ `create(600, 500)` does: 600 uniform pieces
//! (MOOS `genUnifBox`), then 500 more cut from the worst-fitted ones (smart refinement), the
//! regressor's `strict_range` on (its C++ default), normalised to 0..100. The desired speed
//! is the one the ZAIC types use (the cruise or alternate speed, slowed by `end_spd`);
//! `crs_spd_zaic_ratio` does not apply.

use ivp::{Domain, IvpFunction, Reflector};

/// MOOS `AOF_Waypoint` once initialised: the bearing to the track point, the desired speed
/// and the domain's top speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AofWaypoint {
    /// Bearing from ownship to the track point, degrees (MOOS `relAng`).
    pub angle_to_wpt: f64,
    /// The speed the behaviour wants to close at, m/s.
    pub desired_speed: f64,
    /// The speed domain's highest value, m/s.
    pub max_speed: f64,
}

impl AofWaypoint {
    /// The function for ownship at `(osx, osy)` going to `(ptx, pty)`.
    pub fn new(osx: f64, osy: f64, ptx: f64, pty: f64, desired_speed: f64, max_speed: f64) -> Self {
        Self {
            angle_to_wpt: geometry::relative_angle(osx, osy, ptx, pty),
            desired_speed,
            max_speed,
        }
    }

    /// The utility of `course` (degrees) and `speed` (m/s) (MOOS `evalBox`).
    pub fn eval(&self, course: f64, speed: f64) -> f64 {
        let angle_diff = geometry::angle_360(course - self.angle_to_wpt);
        let rate_of_closure = (angle_diff / 180.0 * std::f64::consts::PI).cos() * speed;
        let roc_range = 2.0 * self.max_speed;
        let mut roc_diff = self.desired_speed - rate_of_closure;
        if roc_diff < 0.0 {
            roc_diff *= -0.5;
        }
        if roc_diff > roc_range {
            roc_diff = roc_range;
        }
        let score_roc = (1.0 - roc_diff / roc_range) * 100.0;
        let off = geometry::angle_180(angle_diff).abs();
        let rate_of_detour = off * speed.max(0.0);
        let score_rod = (1.0 - rate_of_detour / (self.max_speed * 180.0)) * 100.0;
        0.8 * score_roc + 0.2 * score_rod
    }
}

/// The reflected objective over `domain`'s course and speed (`None` without both, as the
/// C++ AOF's `initialize` fails).
pub fn objective(
    domain: &Domain,
    os: (f64, f64),
    trackpt: (f64, f64),
    desired_speed: f64,
) -> Option<IvpFunction> {
    let mut sub = Domain::new();
    sub.add(domain.get("course")?.clone()).ok()?;
    let spd = domain.get("speed")?.clone();
    let max_speed = spd.high();
    sub.add(spd).ok()?;
    let aof = AofWaypoint::new(os.0, os.1, trackpt.0, trackpt.1, desired_speed, max_speed);
    Reflector::new(&sub, |v: &[f64]| aof.eval(v[0], v[1]))
        .set_params(
            "uniform_amount = 600 # smart_amount = 500 # strict_range = true # normalize = true",
        )
        .ok()?
        .build()
        .ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_scores_follow_the_cpp_formulas() {
        // Waypoint due east: bearing 90. Desired 2 m/s, top speed 4 m/s.
        let aof = AofWaypoint::new(0.0, 0.0, 100.0, 0.0, 2.0, 4.0);
        assert_eq!(aof.angle_to_wpt, 90.0);
        // Straight at it at the desired speed: roc 100, rod 100.
        assert!((aof.eval(90.0, 2.0) - 100.0).abs() < 1e-12);
        // Straight at it at 4 m/s: overshoot 2 counts half (1 of 8): roc 87.5, rod 100:
        // 0.8 * 87.5 + 0.2 * 100 = 90.
        assert!((aof.eval(90.0, 4.0) - 90.0).abs() < 1e-12);
        // Standing still: shortfall 2 of 8: roc 75, rod 100: 80.
        assert!((aof.eval(0.0, 0.0) - 80.0).abs() < 1e-12);
        // 60 degrees off at 2 m/s: closure 1, shortfall 1 (87.5); detour 60 * 2 = 120 of
        // 720 (83.33): 70 + 16.667.
        let want = 0.8 * 87.5 + 0.2 * (1.0 - 120.0 / 720.0) * 100.0;
        assert!((aof.eval(150.0, 2.0) - want).abs() < 1e-9);
        assert!((aof.eval(30.0, 2.0) - want).abs() < 1e-9, "either side");
        // Straight away at 4 m/s: closure -4, shortfall 6 (25); detour 720 of 720 (0): 20.
        assert!((aof.eval(270.0, 4.0) - 20.0).abs() < 1e-12);
        // Away at 3 m/s with desired 4 of top 2: the shortfall 7 is capped at 4: roc 0,
        // detour 180 * 3 = 540 of 360: rod -50: -10.
        let capped = AofWaypoint::new(0.0, 0.0, 100.0, 0.0, 4.0, 2.0);
        assert!((capped.eval(270.0, 3.0) + 10.0).abs() < 1e-12);
    }

    #[test]
    fn the_reflected_function_peaks_toward_the_point_at_the_desired_speed() {
        let d =
            Domain::parse_specs(["course:0:359:360", "speed:0:4:41", "depth:0:100:101"]).unwrap();
        let f = objective(&d, (0.0, 0.0), (100.0, 100.0), 2.0).unwrap();
        assert_eq!(f.dim(), 2, "course and speed only");
        // 600 uniform pieces at most, then 500 more.
        let sizes_count = 1100;
        assert!(f.piece_count() <= sizes_count && f.piece_count() > 1000);
        assert!((f.max_val() - 100.0).abs() < 1e-9, "normalised");
        let best = f.max_pt().unwrap();
        let (crs, spd) = (f64::from(best[0]), f64::from(best[1]) / 10.0);
        assert!((crs - 45.0).abs() <= 3.0, "course {crs}");
        assert!((spd - 2.0).abs() <= 0.2, "speed {spd}");
        let no_speed = Domain::parse_specs(["course:0:359:360"]).unwrap();
        assert!(objective(&no_speed, (0.0, 0.0), (1.0, 1.0), 2.0).is_none());
    }
}
