//! Helm behaviours for the coug helm (reference `ivp-helm.md` §5.5 and §6).
//!
//! Each behaviour is a plain struct implementing [`Behavior`]: it takes parameters
//! ([`Behavior::set_param`], typed [`ParamError`]s for bad values), builds an IvP objective
//! function on a running iteration ([`Behavior::on_run`]), posts messages and flags through an
//! [`Out`] buffer, and reports completion ([`Out::complete`]). The parameters every behaviour
//! shares (`pwt`, `condition`, `duration`, flags, ...) live in [`Common`]; the helm engine
//! (crate `helm`) owns run states, durations, the duplicate filter and macro expansion.
//!
//! Behaviours are pure: the helm passes the time and the variables they read through a
//! [`Ctx`]; nothing here reads a clock.
//!
//! ```
//! use behaviors::{create, Common, Ctx, Out, MapInfo};
//! use ivp::Domain;
//! let domain = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
//! let mut common = Common::new("BHV_Waypoint");
//! let mut wpt = create("BHV_Waypoint").unwrap();
//! let info = MapInfo::new(0.0).num("NAV_X", 0.0).num("NAV_Y", 0.0).num("NAV_HEADING", 0.0).num("NAV_SPEED", 0.0);
//! let ctx = Ctx { info: &info, domain: &domain, ownship: "abe", name: "wpt", perpetual: false };
//! wpt.set_param("points", "100,0", &mut common, &ctx).unwrap();
//! wpt.set_param("speed", "2", &mut common, &ctx).unwrap();
//! let mut out = Out::default();
//! let f = wpt.on_run(&ctx, &mut out).unwrap();
//! let mut p = ivp::Problem::new(domain.clone());
//! p.add("wpt", f.with_pwt(100.0)).unwrap();
//! let d = p.solve().unwrap();
//! assert_eq!(d.get("course"), Some(90.0));
//! assert_eq!(d.get("speed"), Some(2.0));
//! ```
//!
//! # Adding a behaviour
//! A behaviour implements [`Behavior`]: `kind` and `on_run` are required; `set_param`
//! (returning [`ParamError::Unknown`] for names it does not know, typed parsing with the
//! [`param`] helpers) and the other hooks have defaults. The common parameters (conditions,
//! flags, `duration`, `updates`, `templating = spawn`, ...) are the helm's business.
//!
//! - A stock behaviour: `src/<name>.rs`, `mod <name>;` plus a `pub use`, one line in
//!   [`STOCK`], and its parameters in `mission::catalog`.
//! - A user's behaviour, in the user's own crate: register it,
//!   `Registry::with_stock().register("BHV_Mine", Mine::new)`, and hand the registry to
//!   `coug::main_with` (see `examples/my-behaviour` in the workspace). [`testing`] has the
//!   helpers to check its objective function (argmax, values, peaks and widths, text and PNG
//!   renderings).

#![warn(missing_docs)]

pub mod aof_avoid_collision_depth;
mod avoid_collision;
mod bearing_line;
mod behavior;
pub mod color;
pub mod colregs;
mod common;
mod constant_depth;
mod constant_heading;
mod constant_speed;
pub mod contact;
pub mod contact_state;
mod convoy;
pub mod cpa;
mod cut_range;
/// MOOS number formatting (the workspace's one set of helpers).
pub use moos_types::fmt;
mod fixed_turn;
mod go_to_depth;
pub mod hints;
mod hs_line;
mod leg_run;
mod loiter;
mod max_depth;
mod max_speed;
mod memo;
mod memory_turn_limit;
pub mod obstacle;
mod op_region;
mod op_region_v24;
pub mod param;
mod periodic_speed;
mod periodic_surface;
pub mod plat_model;
mod pmodel_view;
pub mod refinery_cpa;
pub mod registry;
mod shadow;
mod station_keep;
mod test_failure;
pub mod testing;
mod timer;
mod trail;
mod waypoint;
mod zigzag;

pub use avoid_collision::{AvoidCollision, PwtGrade};
pub use bearing_line::BearingLine;
pub use behavior::Fault;
pub use behavior::{
    Behavior, Ctx, Emit, Info, MapInfo, Out, ParamError, PostKey, Value, nav, post_config_status,
};
pub use colregs::{AvdColregs, Version as ColregsVersion};
pub use common::{Common, Flag, FlagKind, FlagValue, Templating};
pub use constant_depth::ConstantDepth;
pub use constant_heading::ConstantHeading;
pub use constant_speed::ConstantSpeed;
pub use convoy::Convoy;
pub use cut_range::CutRange;
pub use fixed_turn::{FixedTurn, ScheduledTurn};
pub use go_to_depth::GoToDepth;
pub use hs_line::HsLine;
pub use leg_run::{LEG_PARAMS, LegGeometry, LegMode, LegRun, WilliamsonTurn};
pub use loiter::Loiter;
pub use max_depth::MaxDepth;
pub use max_speed::MaxSpeed;
pub use memory_turn_limit::MemoryTurnLimit;
pub use obstacle::legacy::{AvoidObstacle, AvoidObstacleX};
pub use obstacle::v24::AvoidObstacleV24;
pub use op_region::{Breach, OpRegion};
pub use op_region_v24::OpRegionV24;
pub use periodic_speed::PeriodicSpeed;
pub use periodic_surface::{AscentGrade, PeriodicSurface, Phase};
pub use pmodel_view::PModelView;
pub use registry::{Registry, STOCK};
pub use shadow::Shadow;
pub use station_keep::{KeepMode, StationKeep};
pub use test_failure::TestFailure;
pub use timer::Timer;
pub use trail::Trail;
pub use waypoint::Waypoint;
pub use zigzag::{Leg, ZigZag};

/// Creates a behaviour of type `kind` (as written after `Behavior =`, case-insensitive),
/// with its defaults, from the process's registry ([`Registry::global`]: the stock types
/// unless a binary installed its own); `None` for a type it does not have.
///
/// ```
/// assert_eq!(behaviors::create("bhv_waypoint").unwrap().kind(), "BHV_Waypoint");
/// assert!(behaviors::create("BHV_Nonsense").is_none());
/// ```
pub fn create(kind: &str) -> Option<Box<dyn Behavior>> {
    Registry::global().create(kind)
}

/// The stock behaviour types ([`STOCK`]'s names), in order.
///
/// ```
/// assert!(behaviors::kinds().any(|k| k == "BHV_Loiter"));
/// ```
pub fn kinds() -> impl Iterator<Item = &'static str> {
    STOCK.iter().map(|(k, _)| *k)
}
