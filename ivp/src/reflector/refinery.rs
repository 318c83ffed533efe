//! Plateau and basin regions of the reflector (MOOS-IvP `OF_Reflector`'s `plateau_region` /
//! `basin_region`, `RT_UniformX`, and the `BuildUtils` box helpers `subtractBox`,
//! `makeRegionsApart`, `buildBoxesSpdAll` at a2a9b716).
//!
//! A refinery (a behaviour's knowledge of where its function is flat) hands the reflector
//! regions known to hold the function's maximum (plateaus) or minimum (basins). The uniform
//! pieces are built as usual, then each region is cut out of them (the pieces it overlaps
//! are replaced by what lies outside it, appended after the untouched pieces, as `BoxSet`
//! merges them), and the regions themselves become pieces, plateaus then basins. When the
//! function's extremes are known ([`Reflector::known_min_max`], MOOS `AOF::minMaxKnown`), a
//! linear plateau piece is the constant maximum and a linear basin piece the constant minimum
//! (the regressor's rule); otherwise they are fitted like any piece. Overlapping regions are first made disjoint
//! ([`make_regions_apart`]): the one of larger plateau magnitude keeps the overlap.

use super::{IxBox, Reflector, partition, refine_box};
use crate::domain::{Domain, Snap};
use crate::error::IvpError;
use crate::function::IvpFunction;

/// A region of the decision space in grid indices (inclusive bounds per variable, in the
/// domain's order) with its plateau value (MOOS `IvPBox::m_plat`): positive for a plateau,
/// negative for a basin; its magnitude ranks overlapping regions.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct RegionBox {
    /// Low index per variable.
    pub lo: Vec<u32>,
    /// High index per variable.
    pub hi: Vec<u32>,
    /// Plateau value: > 0 plateau, < 0 basin.
    pub plat: i32,
}

impl RegionBox {
    fn intersects(&self, b: &IxBox) -> bool {
        (0..self.lo.len()).all(|k| self.lo[k] <= b.hi[k] && b.lo[k] <= self.hi[k])
    }

    fn contains(&self, b: &IxBox) -> bool {
        (0..self.lo.len()).all(|k| self.lo[k] <= b.lo[k] && b.hi[k] <= self.hi[k])
    }

    fn ix(&self) -> IxBox {
        IxBox {
            lo: self.lo.clone(),
            hi: self.hi.clone(),
        }
    }

    /// Grid points in the region.
    pub fn size(&self) -> u64 {
        (0..self.lo.len())
            .map(|k| u64::from(self.hi[k] - self.lo[k] + 1))
            .product()
    }
}

/// MOOS `subtractBox`: the parts of `orig` outside `sub`, per dimension the part above `sub`
/// then the part below, each cut off the rest before the next; `[orig]` when they do not
/// meet, nothing when `sub` contains `orig`.
fn subtract_box(orig: &IxBox, sub: &IxBox) -> Vec<IxBox> {
    let d = orig.lo.len();
    let meets = (0..d).all(|k| orig.lo[k] <= sub.hi[k] && sub.lo[k] <= orig.hi[k]);
    if !meets {
        return vec![orig.clone()];
    }
    if (0..d).all(|k| sub.lo[k] <= orig.lo[k] && orig.hi[k] <= sub.hi[k]) {
        return Vec::new();
    }
    let mut out = Vec::new();
    let mut src = orig.clone();
    for k in 0..d {
        if sub.hi[k] < src.hi[k] {
            let mut above = src.clone();
            above.lo[k] = sub.hi[k] + 1;
            src.hi[k] = sub.hi[k];
            out.push(above);
        }
        if sub.lo[k] > src.lo[k] {
            let mut below = src.clone();
            below.hi[k] = sub.lo[k] - 1;
            src.lo[k] = sub.lo[k];
            out.push(below);
        }
    }
    out
}

/// MOOS `makeRegionsApart`: regions made disjoint. They are ranked by plateau magnitude,
/// then size (larger first; a stable sort keeps the given order among equals, where the C++
/// `std::sort` leaves it unspecified); each in turn is kept whole when it meets none of those
/// kept before it, else it is replaced by its parts outside the first kept one it meets,
/// which are examined next (last part first, as the C++ pushes them to the front).
pub fn make_regions_apart(mut boxes: Vec<RegionBox>) -> Vec<RegionBox> {
    if boxes.len() < 2 {
        return boxes;
    }
    boxes.sort_by(|a, b| {
        b.plat
            .unsigned_abs()
            .cmp(&a.plat.unsigned_abs())
            .then(b.size().cmp(&a.size()))
    });
    let mut minors: std::collections::VecDeque<RegionBox> = boxes.drain(1..).collect();
    let mut majors = boxes;
    while let Some(minor) = minors.pop_front() {
        let hit = majors.iter().find(|m| m.intersects(&minor.ix()));
        match hit {
            None => majors.push(minor),
            Some(major) => {
                for part in subtract_box(&minor.ix(), &major.ix()) {
                    minors.push_front(RegionBox {
                        lo: part.lo,
                        hi: part.hi,
                        plat: minor.plat,
                    });
                }
            }
        }
    }
    majors
}

/// MOOS `buildBoxesSpdAll`: the region of every speed and the courses from `hmin` to `hmax`
/// (degrees, clockwise; `hmin > hmax` wraps through north and gives two boxes, the low
/// courses first). Courses snap inward (`hmin` up, `hmax` down); when that leaves no course,
/// the one nearest their mean. Empty without `course` and `speed` variables. The boxes'
/// plateau value is 0 (the caller sets it).
pub fn boxes_all_speeds(domain: &Domain, hmin: f64, hmax: f64) -> Vec<RegionBox> {
    let (Some(ci), Some(si)) = (domain.index_of("course"), domain.index_of("speed")) else {
        return Vec::new();
    };
    let crs = &domain.vars()[ci];
    let spd_top = domain.vars()[si].points() - 1;
    let crs_top = crs.points() - 1;
    let mut low = crs.index(hmin, Snap::Ceil);
    let mut high = crs.index(hmax, Snap::Floor);
    let make = |c0: u32, c1: u32| {
        let mut lo = vec![0; domain.len()];
        let mut hi: Vec<u32> = domain.vars().iter().map(|v| v.points() - 1).collect();
        lo[ci] = c0;
        hi[ci] = c1;
        lo[si] = 0;
        hi[si] = spd_top;
        RegionBox { lo, hi, plat: 0 }
    };
    if hmin <= hmax {
        if low > high {
            low = crs.index((hmin + hmax) / 2.0, Snap::Nearest);
            high = low;
        }
        return vec![make(low, high)];
    }
    if high > low {
        low = crs.index((hmin + hmax) / 2.0, Snap::Nearest);
        high = low;
    }
    vec![make(0, high), make(low, crs_top)]
}

impl<F: Fn(&[f64]) -> f64> Reflector<F> {
    /// Adds a plateau region (`plateau_region`: its plateau value is set to 1, as the C++
    /// reflector does).
    pub fn plateau_region(mut self, mut region: RegionBox) -> Result<Self, IvpError> {
        self.check_region(&region)?;
        region.plat = 1;
        self.plateaus.push(region);
        Ok(self)
    }

    /// Adds a basin region (`basin_region`: its plateau value is set to −1).
    pub fn basin_region(mut self, mut region: RegionBox) -> Result<Self, IvpError> {
        self.check_region(&region)?;
        region.plat = -1;
        self.basins.push(region);
        Ok(self)
    }

    /// The function's known minimum and maximum (MOOS `AOF::minMaxKnown`, `getKnownMin`,
    /// `getKnownMax`): plateau pieces take the maximum, basin pieces the minimum.
    pub fn known_min_max(mut self, min: f64, max: f64) -> Self {
        self.known = Some((min, max));
        self
    }

    fn check_region(&self, r: &RegionBox) -> Result<(), IvpError> {
        let d = self.domain.len();
        let ok = r.lo.len() == d
            && r.hi.len() == d
            && (0..d).all(|k| r.lo[k] <= r.hi[k] && r.hi[k] < self.domain.vars()[k].points());
        if ok {
            Ok(())
        } else {
            Err(IvpError::Reflector(format!(
                "region {:?}..{:?} is not a box of the domain",
                r.lo, r.hi
            )))
        }
    }

    /// [`Reflector::build`]'s stages 1 and 2 with plateau or basin regions
    /// (`RT_UniformX::create`, then the directed refinement and the fit of every piece); the
    /// function and each piece's plateau value.
    pub(super) fn build_with_regions(
        &self,
        sizes: &[u32],
    ) -> Result<(IvpFunction, Vec<i32>), IvpError> {
        let (mut plateaus, mut basins) = (self.plateaus.clone(), self.basins.clone());
        if plateaus.len() + basins.len() >= 2 {
            let mut all = std::mem::take(&mut plateaus);
            all.append(&mut basins);
            for r in make_regions_apart(all) {
                if r.plat < 0 {
                    basins.push(r);
                } else {
                    plateaus.push(r);
                }
            }
        }
        let mut boxes = Vec::new();
        partition(&self.universe(), sizes, &mut boxes);
        for region in plateaus.iter().chain(&basins) {
            let mut kept = Vec::with_capacity(boxes.len());
            let mut rest = Vec::new();
            for b in boxes {
                if !region.intersects(&b) {
                    kept.push(b);
                } else if !region.contains(&b) {
                    rest.extend(subtract_box(&b, &region.ix()));
                }
            }
            kept.append(&mut rest);
            boxes = kept;
        }
        // Each piece with its plateau value (0 for an ordinary piece).
        let mut pieces: Vec<(IxBox, i32)> = boxes.into_iter().map(|b| (b, 0)).collect();
        pieces.extend(plateaus.iter().map(|r| (r.ix(), 1)));
        pieces.extend(basins.iter().map(|r| (r.ix(), -1)));
        for (region, piece) in &self.refine {
            let piece = piece.clone().unwrap_or_else(|| vec![1; self.domain.len()]);
            let mut next = Vec::with_capacity(pieces.len());
            for (b, plat) in pieces {
                let mut parts = Vec::new();
                refine_box(b, region, &piece, &mut parts);
                next.extend(parts.into_iter().map(|p| (p, plat)));
            }
            pieces = next;
        }
        let mut f = IvpFunction::new(self.domain.clone());
        let mut reg = self.regressor();
        let d = self.domain.len();
        for (b, plat) in &pieces {
            reg.fit(&b.lo, &b.hi, *plat, &self.domain, &self.func)?;
            f.push_piece(&b.lo, &b.hi, &reg.wts()[..d], reg.wts()[d])?;
        }
        Ok((f, pieces.into_iter().map(|(_, plat)| plat).collect()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rb(lo: [u32; 2], hi: [u32; 2], plat: i32) -> RegionBox {
        RegionBox {
            lo: lo.to_vec(),
            hi: hi.to_vec(),
            plat,
        }
    }

    #[test]
    fn subtracting_a_box_leaves_the_parts_outside_it_above_then_below() {
        let orig = IxBox {
            lo: vec![0, 0],
            hi: vec![9, 9],
        };
        let sub = IxBox {
            lo: vec![3, 4],
            hi: vec![5, 6],
        };
        let parts = subtract_box(&orig, &sub);
        let got: Vec<_> = parts.iter().map(|b| (b.lo.clone(), b.hi.clone())).collect();
        assert_eq!(
            got,
            [
                (vec![6, 0], vec![9, 9]),
                (vec![0, 0], vec![2, 9]),
                (vec![3, 7], vec![5, 9]),
                (vec![3, 0], vec![5, 3]),
            ]
        );
        assert!(subtract_box(&sub, &orig).is_empty());
    }

    #[test]
    fn regions_are_made_apart_the_larger_magnitude_keeping_the_overlap() {
        let a = rb([0, 0], [9, 4], 1);
        let b = rb([5, 2], [14, 4], -3);
        let apart = make_regions_apart(vec![a, b.clone()]);
        assert_eq!(apart[0], b, "magnitude 3 ranks first and stays whole");
        // a's parts outside b, the last part first.
        assert_eq!(apart[1..], [rb([5, 0], [9, 1], 1), rb([0, 0], [4, 4], 1)]);
        for (i, x) in apart.iter().enumerate() {
            for y in &apart[i + 1..] {
                assert!(!x.intersects(&y.ix()));
            }
        }
    }

    #[test]
    fn plateau_and_basin_regions_become_pieces_of_their_own() {
        let d = Domain::from_vars(&[("x", 0.0, 9.0, 10), ("y", 0.0, 4.0, 5)]).unwrap();
        let f = |v: &[f64]| 10.0 * v[0] + v[1];
        let r = || {
            Reflector::new(&d, f)
                .set_param("uniform_piece", "x:5,y:5")
                .unwrap()
        };
        let regions = |r: Reflector<_>| {
            r.plateau_region(rb([2, 0], [6, 4], 4))
                .unwrap()
                .basin_region(rb([9, 0], [9, 1], -2))
                .unwrap()
        };
        let g = regions(r()).known_min_max(-5.0, 500.0).build().unwrap();
        let boxes: Vec<_> = g.pieces().map(|p| (p.lo.to_vec(), p.hi.to_vec())).collect();
        // The uniform pieces x 0-4 and 5-9 lose x 2-6 (what is left of each follows the
        // untouched ones), then the basin x 9, y 0-1 (x 7-9 leaves x 7-8 below it and x 9,
        // y 2-4 above it); then the plateau and the basin themselves.
        let want: Vec<(Vec<u32>, Vec<u32>)> = vec![
            (vec![0, 0], vec![1, 4]),
            (vec![7, 0], vec![8, 4]),
            (vec![9, 2], vec![9, 4]),
            (vec![2, 0], vec![6, 4]),
            (vec![9, 0], vec![9, 1]),
        ];
        assert_eq!(boxes, want);
        assert_eq!(
            g.eval(&[4, 3]).unwrap(),
            500.0,
            "plateau: the known maximum"
        );
        assert_eq!(g.eval(&[9, 1]).unwrap(), -5.0, "basin: the known minimum");
        assert!(
            (g.eval(&[0, 3]).unwrap() - 3.0).abs() < 1e-9,
            "fitted elsewhere"
        );
        for x in 0..10u32 {
            for y in 0..5u32 {
                assert_eq!(g.pieces().filter(|p| p.contains(&[x, y])).count(), 1);
            }
        }
        // Extremes unknown: the regions are fitted as any piece.
        let h = regions(r()).build().unwrap();
        assert!((h.eval(&[4, 3]).unwrap() - 43.0).abs() < 1e-9);
    }

    #[test]
    fn boxes_of_all_speeds_snap_inward_and_wrap() {
        let d = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
        assert_eq!(boxes_all_speeds(&d, 10.5, 20.5), [rb([11, 0], [20, 40], 0)]);
        assert_eq!(
            boxes_all_speeds(&d, 350.2, 5.0),
            [rb([0, 0], [5, 40], 0), rb([351, 0], [359, 40], 0)]
        );
        // Both ends between the same two courses: the one nearest the mean.
        assert_eq!(boxes_all_speeds(&d, 10.2, 10.4), [rb([10, 0], [10, 40], 0)]);
    }
}
