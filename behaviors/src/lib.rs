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
//! 1. Write `src/<name>.rs` with a struct implementing [`Behavior`] (`kind`, `set_param`
//!    returning [`ParamError::Unknown`] for names it does not know, `on_run`, and the optional
//!    hooks). Use [`param`] helpers for typed parsing.
//! 2. Add `mod <name>;` plus a `pub use`, and one line in [`create`]'s match.
//! 3. Keep the accepted parameters in step with `mission::catalog`.

#![warn(missing_docs)]

mod behavior;
pub mod color;
mod common;
mod constant_depth;
mod constant_heading;
mod constant_speed;
/// MOOS number formatting (the workspace's one set of helpers).
pub use moos_types::fmt;
mod go_to_depth;
pub mod hints;
mod loiter;
mod max_depth;
mod op_region;
mod op_region_v24;
pub mod param;
mod periodic_surface;
mod station_keep;
mod timer;
mod waypoint;

pub use behavior::{
    Behavior, Ctx, Emit, Info, MapInfo, Out, ParamError, PostKey, Value, nav, post_config_status,
};
pub use common::{Common, Flag, FlagKind, FlagValue};
pub use constant_depth::ConstantDepth;
pub use constant_heading::ConstantHeading;
pub use constant_speed::ConstantSpeed;
pub use go_to_depth::GoToDepth;
pub use loiter::Loiter;
pub use max_depth::MaxDepth;
pub use op_region::{Breach, OpRegion};
pub use op_region_v24::OpRegionV24;
pub use periodic_surface::{AscentGrade, PeriodicSurface, Phase};
pub use station_keep::{KeepMode, StationKeep};
pub use timer::Timer;
pub use waypoint::Waypoint;

/// Creates a behaviour of type `kind` (as written after `Behavior =`, case-insensitive),
/// with its defaults; `None` for a type coug does not implement.
///
/// ```
/// assert_eq!(behaviors::create("bhv_waypoint").unwrap().kind(), "BHV_Waypoint");
/// assert!(behaviors::create("BHV_Nonsense").is_none());
/// ```
pub fn create(kind: &str) -> Option<Box<dyn Behavior>> {
    let k = kind.trim().to_ascii_lowercase();
    Some(match k.as_str() {
        "bhv_waypoint" => Box::new(Waypoint::new()),
        "bhv_loiter" => Box::new(Loiter::new()),
        "bhv_constantspeed" => Box::new(ConstantSpeed::new()),
        "bhv_constantheading" => Box::new(ConstantHeading::new()),
        "bhv_timer" => Box::new(Timer::new()),
        "bhv_constantdepth" => Box::new(ConstantDepth::new()),
        "bhv_maxdepth" => Box::new(MaxDepth::new()),
        "bhv_opregion" => Box::new(OpRegion::new()),
        "bhv_opregionv24" => Box::new(OpRegionV24::new()),
        "bhv_periodicsurface" => Box::new(PeriodicSurface::new()),
        "bhv_gotodepth" => Box::new(GoToDepth::new()),
        "bhv_stationkeep" => Box::new(StationKeep::new()),
        _ => return None,
    })
}

/// The behaviour types [`create`] knows.
pub const KINDS: &[&str] = &[
    "BHV_Waypoint",
    "BHV_Loiter",
    "BHV_ConstantSpeed",
    "BHV_ConstantHeading",
    "BHV_Timer",
    "BHV_ConstantDepth",
    "BHV_MaxDepth",
    "BHV_OpRegion",
    "BHV_OpRegionV24",
    "BHV_PeriodicSurface",
    "BHV_GoToDepth",
    "BHV_StationKeep",
];
