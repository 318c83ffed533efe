//! The reflector's plateau and basin checks (MOOS-IvP `OF_Reflector::checkPlateaus` and
//! `checkBasins` at a2a9b716), which a behaviour's `check_plateaus` runs on the regions its
//! refinery handed over, before the function is built.
//!
//! Every grid point of every region (as added, before they are made apart) is evaluated and
//! compared with the function's known maximum (MOOS `getKnownMax`); the result is the
//! largest difference beyond the threshold (MOOS `pcheck_thresh`, 0.001 by default), 0 when
//! every point is within it or there is no region, and 1 when there are regions but the
//! extremes are not known ([`Reflector::known_min_max`] not given: MOOS `minMaxKnown`
//! false). The basin check compares with the known *maximum* too, as the C++ does (it reads
//! `getKnownMax` where the minimum is meant).

use super::Reflector;
use super::refinery::RegionBox;

/// MOOS `OF_Reflector`'s default `pcheck_thresh`.
pub const DEFAULT_PCHECK_THRESH: f64 = 0.001;

impl<F: Fn(&[f64]) -> f64> Reflector<F> {
    /// MOOS `checkPlateaus`: the worst difference, beyond `thresh`, between the function at a
    /// point of a plateau region and its known maximum (0: all plateaus hold; 1: plateaus
    /// with unknown extremes).
    pub fn check_plateaus(&self, thresh: f64) -> f64 {
        self.check_regions(&self.plateaus, thresh)
    }

    /// MOOS `checkBasins`: as [`Reflector::check_plateaus`] over the basin regions, also
    /// against the known maximum (the C++ compares with `getKnownMax`).
    pub fn check_basins(&self, thresh: f64) -> f64 {
        self.check_regions(&self.basins, thresh)
    }

    fn check_regions(&self, regions: &[RegionBox], thresh: f64) -> f64 {
        if regions.is_empty() {
            return 0.0;
        }
        let Some((_, max)) = self.known else {
            return 1.0;
        };
        let vars = self.domain.vars();
        let mut x = vec![0.0; vars.len()];
        let mut ix: Vec<u32> = Vec::with_capacity(vars.len());
        let mut worst = 0.0;
        for r in regions {
            ix.clear();
            ix.extend_from_slice(&r.lo);
            loop {
                for (k, v) in vars.iter().enumerate() {
                    x[k] = v.value(ix[k]);
                }
                let delta = ((self.func)(&x) - max).abs();
                if delta > thresh && delta > worst {
                    worst = delta;
                }
                // Next point, the first variable fastest.
                let mut k = 0;
                loop {
                    if k == ix.len() {
                        break;
                    }
                    if ix[k] < r.hi[k] {
                        ix[k] += 1;
                        break;
                    }
                    ix[k] = r.lo[k];
                    k += 1;
                }
                if k == ix.len() {
                    break;
                }
            }
        }
        worst
    }
}

#[cfg(test)]
mod tests {
    use crate::{Domain, Reflector, RegionBox};

    fn rb(lo: [u32; 2], hi: [u32; 2]) -> RegionBox {
        RegionBox {
            lo: lo.to_vec(),
            hi: hi.to_vec(),
            plat: 0,
        }
    }

    #[test]
    fn plateau_points_are_compared_with_the_known_maximum() {
        let d = Domain::from_vars(&[("x", 0.0, 9.0, 10), ("y", 0.0, 4.0, 5)]).unwrap();
        // Flat at 100 for x <= 4, falling by 1 per step of x beyond.
        let f = |v: &[f64]| if v[0] <= 4.0 { 100.0 } else { 104.0 - v[0] };
        let r = || Reflector::new(&d, f);
        // No region: nothing to check.
        assert_eq!(r().known_min_max(0.0, 100.0).check_plateaus(0.001), 0.0);
        // Extremes unknown: the C++ answers 1.
        let unknown = r().plateau_region(rb([0, 0], [4, 4])).unwrap();
        assert_eq!(unknown.check_plateaus(0.001), 1.0);
        // A true plateau.
        let good = r()
            .plateau_region(rb([0, 0], [4, 4]))
            .unwrap()
            .known_min_max(0.0, 100.0);
        assert_eq!(good.check_plateaus(0.001), 0.0);
        // Reaching x = 7: 104 - 7 = 97, three below the maximum.
        let bad = r()
            .plateau_region(rb([2, 1], [7, 3]))
            .unwrap()
            .known_min_max(0.0, 100.0);
        assert_eq!(bad.check_plateaus(0.001), 3.0);
        // A threshold of 3 lets that through: only differences beyond it count.
        assert_eq!(bad.check_plateaus(3.0), 0.0);
        assert_eq!(bad.check_plateaus(2.5), 3.0);
        // No basin: 0.
        assert_eq!(bad.check_basins(0.001), 0.0);
        // A basin is compared with the maximum as well (the C++'s getKnownMax): x = 9 is 95.
        let basin = r()
            .basin_region(rb([9, 0], [9, 4]))
            .unwrap()
            .known_min_max(95.0, 100.0);
        assert_eq!(basin.check_basins(0.001), 5.0);
    }
}
