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

//!
//! # Conformance with RefineryObAvoid (the X family's, MOOS-IvP a2a9b716)
//!
//! BHV_AvoidObstacleX and BHV_AvoidObstacleV21 use the older `RefineryObAvoid` over the older
//! `ObShipModel` ([`legacy_regions`], [`super::legacy::LegacyModel`]): different regions,
//! the same reflector stage.
//!
//! | step | C++ | coug |
//! |---|---|---|
//! | major plateau | `buildBoxesSpdAll` from the outer buffer's greatest bearing (snapped up) round to its least (snapped down), value 4 | done |
//! | major basin | passing `port`: `theta_b` (snapped down) to the obstacle centre's bearing (snapped up); `star`: centre (up) to `theta_b` (down); none otherwise; value −5 | done |
//! | minor plateau | with `allowable_ttc` > 0: every course at speeds from the domain's lowest to the speed reaching the outer buffer in `allowable_ttc` (its vertices as an open path, `dist_to_point`; snapped down), `buildBoxHdgAll`, value 2 | done |
//! | minor basin | with `allowable_ttc` > 0: the obstacle's bearing span (each end snapped by `getHdgSnappedProx`, which rounds up) at speeds from the one covering the farther of its two vertices in `allowable_ttc` (snapped up) to the top, `buildBoxesHdgSpd`, value −4 | done |
//! | overlaps, reflector | as V24's | done |

use ivp::{Domain, Reflector, RegionBox, Snap, boxes_all_speeds, make_regions_apart};

use super::ShipModel;
use super::geom::ray_cpa;
use super::legacy::LegacyModel;

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
    apart(all)
}

/// `regions` with plateau value `plat`.
fn with(mut v: Vec<RegionBox>, plat: i32) -> Vec<RegionBox> {
    for r in &mut v {
        r.plat = plat;
    }
    v
}

/// The regions made disjoint, then split into plateaus and basins.
fn apart(all: Vec<RegionBox>) -> (Vec<RegionBox>, Vec<RegionBox>) {
    make_regions_apart(all)
        .into_iter()
        .partition(|r| r.plat >= 0)
}

/// Hands the regions to the reflector as plateaus and basins, the AOF's known extremes (0
/// and 100) their values; the other pieces are fitted within their samples: the C++
/// `Regressor`'s `strict_range`, on by default (the reflector's default too; set here all the
/// same).
pub fn apply<F: Fn(&[f64]) -> f64>(
    mut r: Reflector<F>,
    (plateaus, basins): (Vec<RegionBox>, Vec<RegionBox>),
) -> Option<Reflector<F>> {
    for p in plateaus {
        r = r.plateau_region(p).ok()?;
    }
    for b in basins {
        r = r.basin_region(b).ok()?;
    }
    let r = r.set_param("strict_range", "true").ok()?;
    Some(r.known_min_max(0.0, 100.0))
}

/// A value of `var` snapped onto its grid (MOOS `getDiscreteVal` then `getVal`).
fn snapped(var: &ivp::DomainVar, v: f64, snap: Snap) -> f64 {
    var.value(var.index(v, snap))
}

/// A heading in `[0, 360)` for the snaps below.
fn hdg360(h: f64) -> f64 {
    if (0.0..360.0).contains(&h) {
        h
    } else {
        geometry::angle_360(h)
    }
}

/// MOOS `RefineryObAvoid::getHdgSnappedHigh`: 0 past the domain's last course.
fn hdg_snapped_high(crs: &ivp::DomainVar, h: f64) -> f64 {
    let h = hdg360(h);
    if h > crs.high() {
        return 0.0;
    }
    snapped(crs, h, Snap::Ceil)
}

/// MOOS `getHdgSnappedProx`: past the last course, that course within half a step, else
/// 0; otherwise rounded up (as the C++ does, despite the name).
fn hdg_snapped_prox(crs: &ivp::DomainVar, h: f64) -> f64 {
    let h = hdg360(h);
    if h > crs.high() {
        return if h - crs.high() > crs.delta() / 2.0 {
            0.0
        } else {
            crs.high()
        };
    }
    snapped(crs, h, Snap::Ceil)
}

/// MOOS `buildBoxHdgAll`: every course at speeds `smin..smax` (snapped inward; the nearest to
/// their mean when that leaves none); `None` when `smin > smax`.
fn boxes_all_courses(domain: &Domain, smin: f64, smax: f64) -> Option<RegionBox> {
    if smin > smax {
        return None;
    }
    let b = RegionBox {
        lo: vec![0; domain.len()],
        hi: domain.vars().iter().map(|v| v.points() - 1).collect(),
        plat: 0,
    };
    Some(with_speeds(domain, b, smin, smax))
}

/// The speed span of a region set to `smin..smax`, snapped inward (the nearest to their mean
/// when that leaves none), as `buildBoxHdgAll` and `buildBoxesHdgSpd` do.
fn with_speeds(domain: &Domain, mut b: RegionBox, smin: f64, smax: f64) -> RegionBox {
    let Some(si) = domain.index_of("speed") else {
        return b;
    };
    let spd = &domain.vars()[si];
    let (mut lo, mut hi) = (spd.index(smin, Snap::Ceil), spd.index(smax, Snap::Floor));
    if lo > hi {
        lo = spd.index((smin + smax) / 2.0, Snap::Nearest);
        hi = lo;
    }
    b.lo[si] = lo;
    b.hi[si] = hi;
    b
}

/// The plateau and basin regions of BHV_AvoidObstacleX / V21 (MOOS
/// `RefineryObAvoid::setRefineRegions`) over the course and speed of `domain`.
pub fn legacy_regions(domain: &Domain, model: &LegacyModel) -> (Vec<RegionBox>, Vec<RegionBox>) {
    let (Some(crs), Some(spd)) = (domain.get("course"), domain.get("speed")) else {
        return (Vec::new(), Vec::new());
    };
    let m = &model.m;
    let low = |h| snapped(crs, hdg360(h), Snap::Floor);
    let high = |h| hdg_snapped_high(crs, h);
    let mut plats = with(
        boxes_all_speeds(domain, high(model.cpa_bng.1), low(model.cpa_bng.0)),
        4,
    );
    let mut basins = Vec::new();
    let (theta_b, cent) = (model.theta_b, m.obcent_bng);
    let major_basin = match m.passing_side {
        "port" => Some((low(theta_b), high(cent))),
        "star" => Some((high(cent), low(theta_b))),
        _ => None,
    };
    if let Some((bmin, bmax)) = major_basin {
        basins.extend(with(boxes_all_speeds(domain, bmin, bmax), -5));
    }
    let ttc = m.allowable_ttc;
    if ttc > 0.0 {
        let (osx, osy, _, _) = m.pose.unwrap_or_default();
        let minspd = super::geom::dist_to_open_path(&m.rim, osx, osy) / ttc;
        let smax = snapped(spd, minspd, Snap::Floor);
        if let Some(mut b) = boxes_all_courses(domain, spd.low(), smax) {
            b.plat = 2;
            plats.push(b);
        }
        let (hmin, hmax) = (
            hdg_snapped_prox(crs, model.bng.0),
            hdg_snapped_prox(crs, model.bng.1),
        );
        let smin = snapped(spd, model.bng.2.max(model.bng.3) / ttc, Snap::Ceil);
        let hdg_spd = boxes_all_speeds(domain, hmin, hmax)
            .into_iter()
            .map(|b| with_speeds(domain, b, smin, spd.high()));
        basins.extend(with(hdg_spd.collect(), -4));
    }
    plats.append(&mut basins);
    apart(plats)
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
