//! The open behaviour registry: which behaviour type a `Behavior = BHV_...` line builds.
//!
//! The helm builds every behaviour through a [`Registry`]: the stock types ([`STOCK`]) and
//! whatever a user's crate registers. A binary with extra behaviours builds its registry and
//! hands it to the `coug` library (`coug::main_with`), which installs it as the process's
//! registry ([`Registry::install`]) before running the command line:
//!
//! ```
//! use behaviors::{Behavior, Ctx, Out, Registry};
//! use ivp::IvpFunction;
//!
//! /// A behaviour with no parameters of its own and no opinion.
//! struct Quiet;
//! impl Behavior for Quiet {
//!     fn kind(&self) -> &'static str {
//!         "BHV_Quiet"
//!     }
//!     fn on_run(&mut self, _: &Ctx<'_>, _: &mut Out) -> Option<IvpFunction> {
//!         None
//!     }
//! }
//!
//! let reg = Registry::with_stock().register("BHV_Quiet", || Quiet);
//! assert_eq!(reg.create("bhv_quiet").unwrap().kind(), "BHV_Quiet");
//! assert!(reg.create("BHV_Waypoint").is_some());
//! assert!(Registry::with_stock().create("BHV_Quiet").is_none());
//! ```

use std::sync::{Arc, OnceLock};

use crate::behavior::Behavior;
use crate::{
    ConstantDepth, ConstantHeading, ConstantSpeed, GoToDepth, Loiter, MaxDepth, OpRegion,
    OpRegionV24, PeriodicSurface, StationKeep, Timer, Waypoint,
};

// The non-contact stock behaviours of issue #18.
use crate::{
    BearingLine, FixedTurn, HsLine, MaxSpeed, MemoryTurnLimit, PeriodicSpeed, TestFailure, ZigZag,
};

/// Builds a stock behaviour with its defaults.
pub type StockFactory = fn() -> Box<dyn Behavior>;

/// The stock behaviour types, in the order `coug` lists them: the one place a stock behaviour
/// is added.
pub const STOCK: &[(&str, StockFactory)] = &[
    ("BHV_Waypoint", || Box::new(Waypoint::new())),
    ("BHV_Loiter", || Box::new(Loiter::new())),
    ("BHV_ConstantSpeed", || Box::new(ConstantSpeed::new())),
    ("BHV_ConstantHeading", || Box::new(ConstantHeading::new())),
    ("BHV_Timer", || Box::new(Timer::new())),
    ("BHV_ConstantDepth", || Box::new(ConstantDepth::new())),
    ("BHV_MaxDepth", || Box::new(MaxDepth::new())),
    ("BHV_OpRegion", || Box::new(OpRegion::new())),
    ("BHV_OpRegionV24", || Box::new(OpRegionV24::new())),
    ("BHV_PeriodicSurface", || Box::new(PeriodicSurface::new())),
    ("BHV_GoToDepth", || Box::new(GoToDepth::new())),
    ("BHV_StationKeep", || Box::new(StationKeep::new())),
    ("BHV_MaxSpeed", || Box::new(MaxSpeed::new())),
    ("BHV_HSLine", || Box::new(HsLine::new())),
    ("BHV_BearingLine", || Box::new(BearingLine::new())),
    ("BHV_ZigZag", || Box::new(ZigZag::new())),
    ("BHV_TestFailure", || Box::new(TestFailure::new())),
    ("BHV_MemoryTurnLimit", || Box::new(MemoryTurnLimit::new())),
    ("BHV_PeriodicSpeed", || Box::new(PeriodicSpeed::new())),
    ("BHV_FixedTurn", || Box::new(FixedTurn::new())),
    ("BHV_AvoidCollision", || {
        Box::new(crate::AvoidCollision::new())
    }),
    ("BHV_CutRange", || Box::new(crate::CutRange::new())),
    ("BHV_Shadow", || Box::new(crate::Shadow::new())),
    ("BHV_Trail", || Box::new(crate::Trail::new())),
    ("BHV_Convoy", || Box::new(crate::Convoy::new())),
    ("BHV_LegRun", || Box::new(crate::LegRun::new())),
    ("BHV_PModelView", || Box::new(crate::PModelView::new())),
    ("BHV_AvoidObstacleV24", || {
        Box::new(crate::AvoidObstacleV24::new())
    }),
    (
        "BHV_AvoidObstacle",
        || Box::new(crate::AvoidObstacle::new()),
    ),
    ("BHV_AvoidObstacleX", || {
        Box::new(crate::AvoidObstacleX::new())
    }),
    ("BHV_AvoidObstacleV21", || {
        Box::new(crate::AvoidObstacleX::v21())
    }),
    ("BHV_AvdColregsV22", || {
        Box::new(crate::AvdColregs::new(crate::ColregsVersion::V22))
    }),
    ("BHV_AvdColregsV19", || {
        Box::new(crate::AvdColregs::new(crate::ColregsVersion::V19))
    }),
    ("BHV_AvdColregsV17", || {
        Box::new(crate::AvdColregs::new(crate::ColregsVersion::V17))
    }),
    ("BHV_AvdColregsV26", || {
        Box::new(crate::AvdColregs::new(crate::ColregsVersion::V26))
    }),
];

type Factory = Arc<dyn Fn() -> Box<dyn Behavior> + Send + Sync>;

/// One registered type.
#[derive(Clone)]
struct Entry {
    kind: String,
    lower: String,
    make: Factory,
}

/// Behaviour types by name (compared without case, as pHelmIvP's factory does), each with a
/// function that builds one with its defaults. Cheap to clone (the factories are shared).
#[derive(Clone, Default)]
pub struct Registry {
    entries: Vec<Entry>,
}

impl std::fmt::Debug for Registry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.kinds()).finish()
    }
}

/// The registry [`Registry::install`] made the process's, if any.
static INSTALLED: OnceLock<Registry> = OnceLock::new();
/// The stock registry, built on first use when none is installed.
static STOCK_REGISTRY: OnceLock<Registry> = OnceLock::new();

impl Registry {
    /// A registry with no types.
    pub fn empty() -> Self {
        Registry::default()
    }

    /// A registry with the stock types ([`STOCK`]).
    pub fn with_stock() -> Self {
        let mut r = Registry::empty();
        for (kind, make) in STOCK {
            r.insert(kind, Arc::new(*make));
        }
        r
    }

    /// Adds (or replaces, compared without case) the type `kind`, built by `make`: e.g.
    /// `.register("BHV_Orbit", Orbit::new)`. The name is what `.bhv` files write after
    /// `Behavior =`; the behaviour's [`Behavior::kind`] should return the same.
    pub fn register<B, F>(mut self, kind: &str, make: F) -> Self
    where
        B: Behavior + 'static,
        F: Fn() -> B + Send + Sync + 'static,
    {
        self.insert(
            kind,
            Arc::new(move || Box::new(make()) as Box<dyn Behavior>),
        );
        self
    }

    fn insert(&mut self, kind: &str, make: Factory) {
        let lower = kind.trim().to_ascii_lowercase();
        let entry = Entry {
            kind: kind.trim().to_string(),
            lower,
            make,
        };
        match self.entries.iter_mut().find(|e| e.lower == entry.lower) {
            Some(e) => *e = entry,
            None => self.entries.push(entry),
        }
    }

    /// A behaviour of type `kind` (case-insensitive, blank ends ignored) with its defaults;
    /// `None` for a type this registry does not have.
    pub fn create(&self, kind: &str) -> Option<Box<dyn Behavior>> {
        let k = kind.trim().to_ascii_lowercase();
        self.entries
            .iter()
            .find(|e| e.lower == k)
            .map(|e| (e.make)())
    }

    /// Whether `kind` is registered (case-insensitive).
    pub fn contains(&self, kind: &str) -> bool {
        let k = kind.trim().to_ascii_lowercase();
        self.entries.iter().any(|e| e.lower == k)
    }

    /// The registered type names, in registration order.
    pub fn kinds(&self) -> impl Iterator<Item = &str> + '_ {
        self.entries.iter().map(|e| e.kind.as_str())
    }

    /// Makes this the process's registry, the one [`Registry::global`] returns and every helm
    /// built without an explicit registry uses. Only the first install takes effect: returns
    /// false (and drops `self`) when a registry was installed already.
    pub fn install(self) -> bool {
        INSTALLED.set(self).is_ok()
    }

    /// The process's registry: the installed one, else the stock one.
    pub fn global() -> &'static Registry {
        INSTALLED
            .get()
            .unwrap_or_else(|| STOCK_REGISTRY.get_or_init(Registry::with_stock))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stock_types_resolve_without_case_and_report_their_kind() {
        let r = Registry::with_stock();
        for (kind, _) in STOCK {
            let b = r.create(&kind.to_ascii_uppercase()).unwrap();
            assert_eq!(b.kind(), *kind);
        }
        assert_eq!(r.kinds().count(), STOCK.len());
        assert!(r.create(" bhv_loiter ").is_some());
        assert!(r.create("BHV_Nonsense").is_none());
    }

    #[test]
    fn a_registered_type_replaces_one_of_the_same_name() {
        let r = Registry::with_stock().register("bhv_timer", Timer::new);
        assert_eq!(r.kinds().count(), STOCK.len());
        assert_eq!(r.kinds().filter(|k| *k == "bhv_timer").count(), 1);
        let r = Registry::empty().register("BHV_Timer", Timer::new);
        assert!(r.contains("BHV_TIMER"));
        assert!(!r.contains("BHV_Waypoint"));
    }
}
