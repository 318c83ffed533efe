//! BHV_AvoidObstacleV24 on a turning platform model (MOOS-IvP `ObShipModelV24::seglrCPA` and
//! `evalHdgSpd`, `GeomUtils`' `distSeglrToPoly`, `distSeglToPoly`, `distSegToPoly`,
//! `distSegToSeg` at a2a9b716; facts only, coug's own code).
//!
//! With the helm's Dubins model ([`crate::plat_model`]) a heading's closest approach to the
//! obstacle is taken along the model's turn to it: the least of the distances from the
//! turn's segments (spoke to spoke) to the polygon and of the ray's closest approach from the
//! last spoke ([`seglr_cpa`]). The utility of that approach is the holonomic one's
//! ([`ShipModel::eval_heading`]): the side lock first (on ownship's position and the
//! heading), then `min_util` within `min_util_cpa`, `max_util` beyond `max_util_cpa`,
//! linear between. With the holonomic model the path is the ray alone and nothing changes.
//!
//! `allowable_ttc` plays no part: the C++ keeps it (`AOF_AvoidObstacleV24` refuses to start
//! without it) but its evaluation has the time to collision as a "ToDo", with either model.

use geometry::Polygon;
use geometry::segment::{dist_point_to_segment, segments_cross};

use super::{ShipModel, geom};
use crate::plat_model::{PlatModel, TurnPath};

/// The distance between two segments: 0 when they cross, else the least of their end
/// points' distances to the other (MOOS `distSegToSeg`).
fn seg_to_seg(a: (f64, f64, f64, f64), b: (f64, f64, f64, f64)) -> f64 {
    let (x1, y1, x2, y2) = a;
    let (x3, y3, x4, y4) = b;
    if segments_cross(x1, y1, x2, y2, x3, y3, x4, y4) {
        return 0.0;
    }
    dist_point_to_segment(x1, y1, x2, y2, x3, y3)
        .min(dist_point_to_segment(x1, y1, x2, y2, x4, y4))
        .min(dist_point_to_segment(x3, y3, x4, y4, x1, y1))
        .min(dist_point_to_segment(x3, y3, x4, y4, x2, y2))
}

/// The distance from a segment to a convex polygon: 0 when it starts inside, else the least
/// distance to an edge (MOOS `distSegToPoly`).
fn seg_to_poly(s: (f64, f64, f64, f64), poly: &Polygon) -> f64 {
    if poly.contains(s.0, s.1) {
        return 0.0;
    }
    poly.edges()
        .map(|e| seg_to_seg(s, (e.a.x, e.a.y, e.b.x, e.b.y)))
        .fold(f64::INFINITY, f64::min)
}

/// The closest approach of a turn's path to a convex polygon (MOOS `distSeglrToPoly`): the
/// least of its segments' distances (the start's distance when it has no segment) and the
/// ray's closest approach; 0 for a polygon that is not convex, as the C++.
pub fn seglr_cpa(path: &TurnPath<'_>, poly: &Polygon) -> f64 {
    if !poly.is_convex() {
        return 0.0;
    }
    let segl = if path.len() == 1 {
        geom::dist_to_poly(poly, path.start.x, path.start.y)
    } else {
        (0..path.len() - 1)
            .map(|i| {
                let (a, b) = (path.vertex(i), path.vertex(i + 1));
                seg_to_poly((a.x, a.y, b.x, b.y), poly)
            })
            .fold(f64::INFINITY, f64::min)
    };
    let base = path.ray_base();
    let ray = geom::ray_cpa(base.x, base.y, path.ray, poly);
    if segl <= ray { segl } else { ray }
}

/// The utility of heading `hdg` with ownship turning as `pm` says (MOOS `evalHdgSpd` with a
/// Dubins `PlatModel`; see the module docs).
pub fn eval_heading(model: &ShipModel, pm: &PlatModel, hdg: f64) -> f64 {
    let (osx, osy, _, _) = model.pose.unwrap_or_default();
    if model.side_lock {
        let rel = geom::rel_bearing(osx, osy, hdg, model.center.0, model.center.1);
        let side = if rel > 0.0 && rel < 180.0 {
            "star"
        } else {
            "port"
        };
        if side != model.passing_side {
            return 0.0;
        }
    }
    let cpa = seglr_cpa(&pm.turn(hdg), &model.gut);
    if cpa >= model.max_util_cpa {
        return model.max_util;
    }
    if cpa <= model.min_util_cpa {
        return model.min_util;
    }
    let range = model.max_util_cpa - model.min_util_cpa;
    if range <= 0.0 {
        return model.min_util;
    }
    let pct = ((cpa - model.min_util_cpa) / range).clamp(0.0, 1.0);
    pct * (model.max_util - model.min_util)
}
