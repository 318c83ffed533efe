//! The obstacle refinery of BHV_AvoidObstacleV24 with `use_refinery = true` (MOOS-IvP
//! `RefineryObAvoidV24` and `ObShipModelV24::updateBngExtremes` at a2a9b716): the courses
//! whose ray (the holonomic platform model's turn) clears the buffered obstacle (`rim`)
//! are a plateau, those whose ray hits the obstacle itself (`gut`) a basin, and with a side
//! lock the courses of the other side a basin too; the reflector then cuts these regions out
//! of the uniform pieces and makes each one piece of the function's known maximum (100) or
//! minimum (0) ([`ivp::Reflector::plateau_region`]).
//!
//! # Conformance with RefineryObAvoidV24 (MOOS-IvP a2a9b716)
//!
//! | step | C++ | coug |
//! |---|---|---|
//! | bearing extremes | each whole-degree heading's seglr CPA to the rim and gut polygons; the span of headings clearing the rim (`setBngMinMaxToRimPoly`), the span hitting the gut (`setBngMinMaxToGutPoly`), with their wrap rules and quirks (a clear span running to 359 without wrapping ends at 0) | done ([`BngExtremes`]) |
//! | plateaus | `buildBoxesSpdAll(rim_min, rim_max)`, plateau value 4, when both are set and some heading clears the rim | done |
//! | basins | `buildBoxesSpdAll(gut_min, gut_max)`, value −2, when both are set and the rim's *unhit* count (the C++ reads that count here) is not 0 | done |
//! | side lock | `star`: courses `osh+165 .. osh+350`; `port`: `osh+10 .. osh+195`; basins of value −3 | done |
//! | overlaps | `makeRegionsApart` over all of them, then split by sign | done ([`ivp::make_regions_apart`]) |
//! | in the reflector | each region added as `plateau_region` / `basin_region` (their values reset to 1 / −1), pieces of the AOF's known 100 / 0 | done |

use ivp::{Domain, RegionBox, boxes_all_speeds, make_regions_apart};

use super::ShipModel;
use super::geom::ray_cpa;

/// The heading spans the refinery reads from the ship model (MOOS
/// `ObShipModelV24::updateBngExtremes`): −1 when a span is not found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BngExtremes {
    /// First heading of the span that clears the rim polygon, degrees.
    pub rim_min: f64,
    /// Last heading of that span.
    pub rim_max: f64,
    /// Headings (of 360) whose ray misses the rim polygon.
    pub rim_unhit: u32,
    /// The heading before the span that hits the obstacle.
    pub gut_min: f64,
    /// The heading after it.
    pub gut_max: f64,
}

/// The rim span from each heading's CPA (`setBngMinMaxToRimPoly`).
fn rim_span(cpa: &[f64]) -> (f64, f64) {
    let hits = cpa.iter().filter(|d| **d <= 0.0).count();
    if hits == 0 || hits == cpa.len() {
        return (-1.0, -1.0);
    }
    let (mut bmin, mut bmax) = (0usize, 0usize);
    if cpa[0] > 0.0 && cpa[359] > 0.0 {
        if let Some(ix) = (1..359).map(|i| 359 - i).find(|&ix| cpa[ix] <= 0.0) {
            bmin = ix + 1;
        }
        if let Some(i) = (1..359).find(|&i| cpa[i] <= 0.0) {
            bmax = i - 1;
        }
    } else {
        let mut found = false;
        for (i, &d) in cpa.iter().enumerate().take(359) {
            if d > 0.0 && !found {
                bmin = i;
                found = true;
            }
            if found && d <= 0.0 {
                bmax = i - 1;
                break;
            }
        }
    }
    (bmin as f64, bmax as f64)
}

/// The gut span from each heading's CPA (`setBngMinMaxToGutPoly`).
fn gut_span(cpa: &[f64]) -> (f64, f64) {
    let hits = cpa.iter().filter(|d| **d <= 0.0).count();
    if hits == 0 || hits == cpa.len() {
        return (-1.0, -1.0);
    }
    let (mut bmin, mut bmax) = (0usize, 0usize);
    if cpa[0] <= 0.0 && cpa[359] <= 0.0 {
        if let Some(ix) = (1..359).map(|i| 359 - i).find(|&ix| cpa[ix] > 0.0) {
            bmin = ix;
        }
        if let Some(i) = (1..359).find(|&i| cpa[i] > 0.0) {
            bmax = i;
        }
    } else {
        let mut found = false;
        for (i, &d) in cpa.iter().enumerate().take(359) {
            if d <= 0.0 && !found {
                bmin = if i == 0 { 359 } else { i - 1 };
                found = true;
            }
            if found && d > 0.0 {
                bmax = i;
                break;
            }
        }
    }
    (bmin as f64, bmax as f64)
}

impl BngExtremes {
    /// The spans for the model's ownship pose (the holonomic model: each heading's ray from
    /// ownship's position).
    pub fn of(model: &ShipModel) -> BngExtremes {
        let (osx, osy, _, _) = model.pose.unwrap_or_default();
        let rays = |poly| -> Vec<f64> {
            (0..360)
                .map(|h| ray_cpa(osx, osy, f64::from(h), poly))
                .collect()
        };
        let rim = rays(&model.rim);
        let gut = rays(&model.gut);
        let (rim_min, rim_max) = rim_span(&rim);
        let (gut_min, gut_max) = gut_span(&gut);
        BngExtremes {
            rim_min,
            rim_max,
            rim_unhit: rim.iter().filter(|d| **d > 0.0).count() as u32,
            gut_min,
            gut_max,
        }
    }
}

/// The plateau and basin regions over the course and speed variables of `domain` (MOOS
/// `RefineryObAvoidV24::setRefineRegions`) for the model and the behaviour's `side_lock`
/// (`star`, `port` or empty).
pub fn regions(
    domain: &Domain,
    model: &ShipModel,
    side_lock: &str,
) -> (Vec<RegionBox>, Vec<RegionBox>) {
    let ext = BngExtremes::of(model);
    let with = |mut v: Vec<RegionBox>, plat: i32| {
        for r in &mut v {
            r.plat = plat;
        }
        v
    };
    let mut all = Vec::new();
    if ext.rim_min >= 0.0 && ext.rim_max >= 0.0 && ext.rim_unhit > 0 {
        all.extend(with(boxes_all_speeds(domain, ext.rim_min, ext.rim_max), 4));
    }
    if ext.gut_min >= 0.0 && ext.gut_max >= 0.0 && ext.rim_unhit > 0 {
        all.extend(with(boxes_all_speeds(domain, ext.gut_min, ext.gut_max), -2));
    }
    if !side_lock.is_empty() {
        let osh = model.pose.map_or(0.0, |p| p.2);
        let (a, b) = if side_lock == "port" {
            (10.0, 195.0)
        } else {
            (165.0, 350.0)
        };
        let (hmin, hmax) = (geometry::angle_360(osh + a), geometry::angle_360(osh + b));
        all.extend(with(boxes_all_speeds(domain, hmin, hmax), -3));
    }
    let apart = make_regions_apart(all);
    apart.into_iter().partition(|r| r.plat >= 0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spans_follow_the_cpp_wrap_rules() {
        // Headings 40-60 hit; no wrap.
        let cpa: Vec<f64> = (0..360)
            .map(|h| if (40..=60).contains(&h) { 0.0 } else { 5.0 })
            .collect();
        assert_eq!(gut_span(&cpa), (39.0, 61.0));
        // The clear span starts at 0 and ends before 40 (no wrap: 359 is clear but 0 too,
        // so it wraps): from 61 round to 39.
        assert_eq!(rim_span(&cpa), (61.0, 39.0));
        // Headings 350-10 hit: wraps for the gut.
        let cpa: Vec<f64> = (0..360)
            .map(|h| if !(11..350).contains(&h) { 0.0 } else { 5.0 })
            .collect();
        assert_eq!(gut_span(&cpa), (349.0, 11.0));
        assert_eq!(rim_span(&cpa), (11.0, 349.0));
        // A clear span running to 359 without wrapping ends at 0 (the C++ loop stops at 358).
        let cpa: Vec<f64> = (0..360).map(|h| if h < 100 { 0.0 } else { 5.0 }).collect();
        assert_eq!(rim_span(&cpa), (100.0, 0.0));
        assert_eq!(rim_span(&[1.0; 360]), (-1.0, -1.0));
        assert_eq!(gut_span(&[0.0; 360]), (-1.0, -1.0));
    }
}
