//! Dive reports, as LSTS DUNE's NavError monitor makes them: at each resurfacing, the distance
//! travelled underwater, the correction the first good GPS fix implies, and their ratio.

/// One dive's report.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiveReport {
    /// Dive number, from 1.
    pub dive: u32,
    /// When the dive started (depth first below `dive_depth_m`), s.
    pub start_t_s: f64,
    /// When the vehicle was back at the surface, s.
    pub surface_t_s: f64,
    /// Time of the first good fix after it, s.
    pub fix_t_s: f64,
    /// Horizontal distance travelled underwater along the estimate, m.
    pub distance_m: f64,
    /// Distance between the first good fix and the estimate at its time, m.
    pub correction_m: f64,
    /// `100 * correction / distance` (0 when the distance is 0).
    pub ratio_pct: f64,
}

/// Follows the estimate through dives (pure: the navigator feeds it).
#[derive(Debug, Clone)]
pub struct DiveTracker {
    /// Depth below which a dive starts, m.
    pub dive_depth_m: f64,
    /// Depth above which the vehicle is back at the surface, m.
    pub surface_depth_m: f64,
    submerged: bool,
    awaiting_fix: bool,
    distance_m: f64,
    last_xy: Option<[f64; 2]>,
    start_t_s: f64,
    surface_t_s: f64,
    dives: u32,
}

impl Default for DiveTracker {
    fn default() -> Self {
        DiveTracker::new(1.0, 0.5)
    }
}

impl DiveTracker {
    /// A tracker with its dive and surface depths (m, the second smaller than the first).
    pub fn new(dive_depth_m: f64, surface_depth_m: f64) -> DiveTracker {
        DiveTracker {
            dive_depth_m,
            surface_depth_m,
            submerged: false,
            awaiting_fix: false,
            distance_m: 0.0,
            last_xy: None,
            start_t_s: 0.0,
            surface_t_s: 0.0,
            dives: 0,
        }
    }

    /// Whether a dive is under way.
    pub fn submerged(&self) -> bool {
        self.submerged
    }

    /// Feeds one estimate (position east/north and depth, m).
    pub fn update(&mut self, t_s: f64, x_m: f64, y_m: f64, depth_m: f64) {
        if !self.submerged {
            if depth_m > self.dive_depth_m {
                self.submerged = true;
                self.awaiting_fix = false;
                self.distance_m = 0.0;
                self.start_t_s = t_s;
                self.last_xy = Some([x_m, y_m]);
            }
            return;
        }
        if let Some([lx, ly]) = self.last_xy {
            self.distance_m += (x_m - lx).hypot(y_m - ly);
        }
        self.last_xy = Some([x_m, y_m]);
        if depth_m < self.surface_depth_m {
            self.submerged = false;
            self.awaiting_fix = true;
            self.surface_t_s = t_s;
        }
    }

    /// Feeds an accepted GPS fix and the estimate at its time (before the fix is used); returns
    /// the report when it is the first fix after a dive.
    pub fn gps_fix(&mut self, t_s: f64, fix: [f64; 2], estimate: [f64; 2]) -> Option<DiveReport> {
        if !self.awaiting_fix {
            return None;
        }
        self.awaiting_fix = false;
        self.dives += 1;
        let correction_m = (fix[0] - estimate[0]).hypot(fix[1] - estimate[1]);
        let ratio_pct = if self.distance_m > 0.0 {
            100.0 * correction_m / self.distance_m
        } else {
            0.0
        };
        Some(DiveReport {
            dive: self.dives,
            start_t_s: self.start_t_s,
            surface_t_s: self.surface_t_s,
            fix_t_s: t_s,
            distance_m: self.distance_m,
            correction_m,
            ratio_pct,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_dive_report() {
        let mut d = DiveTracker::default();
        assert!(d.gps_fix(0.0, [0.0, 0.0], [0.0, 0.0]).is_none());
        d.update(0.0, 0.0, 0.0, 0.0);
        d.update(1.0, 0.0, 0.0, 2.0); // dive starts at (0, 0)
        d.update(2.0, 30.0, 0.0, 3.0);
        d.update(3.0, 30.0, 40.0, 3.0);
        d.update(4.0, 30.0, 40.0, 0.2); // surfaced: 70 m travelled
        assert!(!d.submerged());
        let r = d.gps_fix(5.0, [33.0, 44.0], [30.0, 40.0]).unwrap();
        assert_eq!(r.dive, 1);
        assert!((r.distance_m - 70.0).abs() < 1e-12);
        assert!((r.correction_m - 5.0).abs() < 1e-12);
        assert!((r.ratio_pct - 100.0 * 5.0 / 70.0).abs() < 1e-12);
        assert_eq!((r.start_t_s, r.surface_t_s, r.fix_t_s), (1.0, 4.0, 5.0));
        // Only the first fix after a dive reports.
        assert!(d.gps_fix(6.0, [0.0, 0.0], [0.0, 0.0]).is_none());
    }
}
