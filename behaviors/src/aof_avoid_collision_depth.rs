//! BHV_AvoidCollision's depth-aware objective (MOOS-IvP `AOF_AvoidCollisionDepth` and
//! `BHV_AvoidCollision::getAvoidDepthIPF` at a2a9b716; facts only, coug's own code), built
//! when the behaviour has a `collision_depth`.
//!
//! Over course, speed and depth, with the deepest decision depth `D` (the depth domain's
//! high end) and the collision depth `c`:
//! - at depths `z >= c` (below the contact's reach) every course and speed is safe:
//!   `90 + dive(z)`;
//! - above it, `metric(cpa) + dive(z)`, the CPA over the time on leg at that course and speed
//!   (the CPA engine of the pair, from ownship's present position);
//!
//! with `dive(z) = 10 · (D − z) / D` (the depth clipped into `[0, D]`; 0 when `D <= 0`), and
//! `metric(d)` 0 below the collision distance `min` (`min_util_cpa_dist`, not halved when
//! the contact is close, unlike the course-speed objective), 100 above the all-clear
//! distance `max` (`max_util_cpa_dist`), `100 · (d − min) / (max − min)` between; when the
//! rate of closure `roc` at ownship's present heading and speed is negative (opening), `max`
//! is lowered by it, and `max` is raised to `min + 10` whenever they are closer than 10 m.
//!
//! The reflector samples it as the C++ sets it up: one uniform piece, then the depths
//! shallower than the collision depth's grid point (`c` snapped up) refined into pieces of
//! 10 courses × 5 speeds × 100 depths, and the depths from that point down as one piece.

use ivp::{Domain, IvpFunction, Reflector, Snap};

use crate::cpa::CpaEngine;

/// `AOF_AvoidCollisionDepth`: the pair's CPA engine and the objective's settings.
#[derive(Debug, Clone)]
pub struct AofAvoidCollisionDepth {
    /// The CPA engine (contact and ownship positions, the contact's motion).
    pub engine: CpaEngine,
    /// Time on leg, s.
    pub tol: f64,
    /// `collision_distance` (`min_util_cpa_dist`), m.
    pub collision_distance: f64,
    /// `all_clear_distance` (`max_util_cpa_dist`), m.
    pub all_clear_distance: f64,
    /// `collision_depth`, m.
    pub collision_depth: f64,
    /// The deepest decision depth (the depth domain's high end), m.
    pub max_decision_depth: f64,
    /// The rate of closure at ownship's present heading and speed, m/s.
    pub rate_of_closure: f64,
}

impl AofAvoidCollisionDepth {
    /// The objective for the pair of `engine` with ownship heading `osh` at `osv` (MOOS
    /// `initialize`: the rate of closure at the present heading and speed); `None` when the
    /// domain lacks course, speed or depth.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        domain: &Domain,
        engine: CpaEngine,
        osh: f64,
        osv: f64,
        tol: f64,
        collision_distance: f64,
        all_clear_distance: f64,
        collision_depth: f64,
    ) -> Option<Self> {
        domain.get("course")?;
        domain.get("speed")?;
        let depth = domain.get("depth")?;
        let rate_of_closure = engine.eval_roc(osh, osv);
        Some(AofAvoidCollisionDepth {
            engine,
            tol,
            collision_distance,
            all_clear_distance,
            collision_depth: collision_depth.max(0.0),
            max_decision_depth: depth.high(),
            rate_of_closure,
        })
    }

    /// The CPA metric (see the module docs).
    pub fn metric(&self, dist: f64) -> f64 {
        let min = self.collision_distance;
        let mut max = self.all_clear_distance;
        if self.rate_of_closure < 0.0 {
            max += self.rate_of_closure;
        }
        if max - min < 10.0 {
            max = min + 10.0;
        }
        if dist < min {
            0.0
        } else if dist > max {
            100.0
        } else {
            (dist - min) / (max - min) * 100.0
        }
    }

    /// The preference for shallower depths, 10 at the surface to 0 at the deepest (MOOS
    /// `evalDiveDepth` with a maximum utility of 10).
    pub fn dive(&self, depth: f64) -> f64 {
        let top = self.max_decision_depth;
        if top <= 0.0 {
            return 0.0;
        }
        let z = depth.clamp(0.0, top);
        (top - z) / top * 10.0
    }

    /// The objective at course `crs`, speed `spd` and depth `dep` (MOOS `evalBox`).
    pub fn eval(&self, crs: f64, spd: f64, dep: f64) -> f64 {
        if dep >= self.collision_depth {
            90.0 + self.dive(dep)
        } else {
            self.metric(self.engine.eval_cpa(crs, spd, self.tol)) + self.dive(dep)
        }
    }

    /// The function over the course, speed and depth variables of `domain` (in its order),
    /// sampled as `getAvoidDepthIPF` sets up the reflector (see the module docs); `None`
    /// when the domain lacks one of them.
    pub fn build(&self, domain: &Domain) -> Option<IvpFunction> {
        let mut d = Domain::new();
        for v in domain.vars() {
            if matches!(v.name(), "course" | "speed" | "depth") {
                d.add(v.clone()).ok()?;
            }
        }
        let (ci, si, zi) = (
            d.index_of("course")?,
            d.index_of("speed")?,
            d.index_of("depth")?,
        );
        let depth = &d.vars()[zi];
        // The collision depth's grid point, snapped up (MOOS `getDiscreteVal(.., 1)`).
        let disc = depth.index(self.collision_depth, Snap::Ceil);
        let half = depth.delta() / 2.0;
        let whole: Vec<String> = d
            .vars()
            .iter()
            .map(|v| format!("{}:{}", v.name(), v.points()))
            .collect();
        let mut r = Reflector::new(&d, |v: &[f64]| self.eval(v[ci], v[si], v[zi]))
            .set_param("uniform_amount", "1")
            .ok()?;
        // Regions in domain values, half a step inside the grid points they end on.
        if disc > 0 {
            let top = format!("depth:{}:{}", depth.low(), depth.value(disc - 1) + half);
            r = r
                .set_param("refine_region", &top)
                .ok()?
                .set_param("refine_piece", "course:10,speed:5,depth:100")
                .ok()?;
        }
        let bottom = format!("depth:{}:{}", depth.value(disc) - half, depth.high());
        r = r
            .set_param("refine_region", &bottom)
            .ok()?
            .set_param("refine_piece", &whole.join(","))
            .ok()?;
        r.build().ok()
    }
}
