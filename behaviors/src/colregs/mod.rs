//! The COLREGS collision-avoidance behaviours (MOOS-IvP `lib_behaviors-colregs` at
//! a2a9b716): BHV_AvdColregsV22 and its siblings V17, V19 and V26, one engine
//! ([`AvdColregs`]) with a [`Version`], and the objective functions they build, one module
//! each: [`aof_cpa`] (catch-all), [`aof_r13`] (overtaking), [`aof_r14`] (head-on),
//! [`aof_r16`] (give-way), [`aof_r17`] (stand-on), over the pair geometry of [`geometry`].
//!
//! Every objective is a plain function of ownship course and speed (`eval`), sampled into an
//! [`IvpFunction`] by the reflector ([`reflect`]: uniform pieces of 3 courses × 3 speeds, as
//! the behaviours' `build_info` asks; coug fits planes to the pieces where the C++ marks
//! them `discrete`).

pub mod aof_cpa;
pub mod aof_r13;
pub mod aof_r14;
pub mod aof_r16;
pub mod aof_r17;
mod avd_colregs;
pub mod geometry;
pub mod plat_cpx;
pub mod velocity_filter;

pub use aof_cpa::AofCpa;
pub use aof_r13::AofR13;
pub use aof_r14::AofR14;
pub use aof_r16::{AofR16, GiveWaySide};
pub use aof_r17::AofR17;
pub use avd_colregs::{AvdColregs, Version};
pub use geometry::{ContactState, Cpx};
pub use velocity_filter::VelocityFilter;

use ivp::{Domain, IvpFunction, Reflector};

use crate::cpa::CpaEngine;

/// What every COLREGS objective shares (MOOS `AOF_ContactX`): the CPA engine of the pair,
/// the time on leg its CPA is evaluated over, and the distances below which a CPA is a
/// collision and above which it is all clear.
#[derive(Debug, Clone)]
pub struct Distances {
    /// The CPA engine (contact and ownship positions, the contact's motion).
    pub engine: CpaEngine,
    /// Time on leg, s (`tol`).
    pub tol: f64,
    /// `collision_distance`, m.
    pub collision_distance: f64,
    /// `all_clear_distance`, m.
    pub all_clear_distance: f64,
    /// V26 with a Dubins platform model: the CPA along the model's turn
    /// ([`plat_cpx::PlatCpx::eval_cpa`]) instead of the engine's ray.
    pub pm: Option<plat_cpx::PlatCpx>,
}

impl Distances {
    /// The distances, or `None` when `collision > all_clear` (MOOS `AOF_ContactX::initialize`
    /// fails: "collision_dist > all_clear_dist").
    pub fn new(engine: CpaEngine, tol: f64, collision: f64, all_clear: f64) -> Option<Self> {
        (collision <= all_clear).then_some(Distances {
            engine,
            tol,
            collision_distance: collision,
            all_clear_distance: all_clear,
            pm: None,
        })
    }

    /// The distances with the CPA taken along ownship's platform model's turns to each
    /// course, for the contact `cn` (`x, y, heading, speed`).
    pub fn with_plat_model(
        mut self,
        model: std::sync::Arc<crate::plat_model::PlatModel>,
        cn: (f64, f64, f64, f64),
    ) -> Self {
        self.pm = Some(plat_cpx::PlatCpx::new(model, cn));
        self
    }

    /// The CPA distance at ownship course `crs` and speed `spd` over the time on leg.
    pub fn cpa(&self, crs: f64, spd: f64) -> f64 {
        if let Some(pm) = &self.pm {
            return pm.eval_cpa(crs, spd, self.tol);
        }
        self.engine.eval_cpa(crs, spd, self.tol)
    }

    /// The CPA metric most of the objectives use: 0 below `collision_distance`, 100 above
    /// `all_clear_distance`, `25 + 75 · (d − collision) / (all_clear − collision)` between.
    pub fn metric25(&self, dist: f64) -> f64 {
        let (min, max) = (self.collision_distance, self.all_clear_distance);
        if dist < min {
            0.0
        } else if dist > max {
            100.0
        } else {
            25.0 + 75.0 * (dist - min) / (max - min)
        }
    }
}

/// Samples `f(course, speed)` over the course and speed variables of `domain` in uniform
/// pieces of 3 courses × 3 speeds; `None` when the domain lacks either variable.
pub fn reflect(domain: &Domain, f: impl Fn(f64, f64) -> f64) -> Option<IvpFunction> {
    let mut d = Domain::new();
    d.add(domain.get("course")?.clone()).ok()?;
    d.add(domain.get("speed")?.clone()).ok()?;
    Reflector::new(&d, |v: &[f64]| f(v[0], v[1]))
        .set_param("uniform_piece", "course:3,speed:3")
        .ok()?
        .build()
        .ok()
}
