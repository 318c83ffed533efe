//! The interval-programming (IvP) core: decision domains, piecewise-linear objective
//! functions, the ZAIC builders, the reflector and coupler, and the exact solver.
//!
//! Everything is in the integer index space of a [`Domain`]: a function's pieces are boxes of
//! grid indices with a linear interior function. Behaviours build functions with the ZAIC
//! builders or the [`Reflector`], the helm adds them to a [`Problem`] under the behaviours'
//! names, and the [`Solver`] returns the [`Decision`] that maximizes their weighted sum.
//!
//! ```
//! use ivp::{couple, Domain, Problem, ZaicHdg, ZaicSpd};
//! let d = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
//! let hdg = ZaicHdg::new(&d, "course", 90.0, 10.0, 10.0, 50.0, 50.0, 0.0, 100.0).unwrap();
//! let spd = ZaicSpd::new(&d, "speed", 2.0, 1.5, 2.5, 70.0, 70.0).unwrap();
//! let waypoint = couple(&hdg.extract().unwrap(), &spd.extract().unwrap()).unwrap();
//! let mut problem = Problem::new(d);
//! problem.add("waypoint", waypoint.with_pwt(100.0)).unwrap();
//! let decision = problem.solve().unwrap();
//! assert_eq!(decision.get("course"), Some(90.0));
//! assert_eq!(decision.get("speed"), Some(2.0));
//! ```

#![warn(missing_docs)]
// Numeric kernels index several parallel arrays with one loop variable; iterator zips
// would hide which dimension is which.
#![allow(clippy::needless_range_loop)]

mod coupler;
mod domain;
pub mod encode;
mod error;
mod function;
mod reflector;
mod solver;
mod zaic;

pub use coupler::{couple, couple_weighted};
pub use domain::{Domain, DomainVar, Snap};
pub use error::{DomainError, IvpError};
pub use function::{DEFAULT_PWT, IvpFunction, Piece};
pub use reflector::{
    DEFAULT_PCHECK_THRESH, Reflector, RegionBox, boxes_all_speeds, make_regions_apart,
};
pub use solver::{Decision, DecisionVar, Problem, Solver};
pub use zaic::{
    BREAK_TIES, Combine, PeakComponent, SEGMENT_TOLERANCE, ZaicHdg, ZaicHeq, ZaicLeq, ZaicPeak,
    ZaicSpd, ZaicVector, join_knots, segment,
};
