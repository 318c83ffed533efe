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
pub use geometry::Cpx;
pub use velocity_filter::VelocityFilter;

pub use crate::contact_state::{ContactState, Distances, reflect};
