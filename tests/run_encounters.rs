//! Encounters with BHV_AvoidCollision as fleet runs (issue #18, "What must be shown"):
//! the two- and three-vehicle lockstep fleets of `missions/encounters` (head-on, crossing,
//! overtaking, a three-way meeting), each vehicle a community with its own helm, simulator,
//! pNodeReporter and pBasicContactMgr, their NODE_REPORTs shared by pShare. With the
//! behaviour every closest approach (from the alogs' NAV_X/NAV_Y) stays above its
//! `min_util_cpa_dist` (10 m); with it off (`AVOID=off`) the same encounters collide.

mod common;
mod encounters;

use std::collections::BTreeMap;

use common::*;
use encounters::{closest, run_fleet};

/// The behaviour's `min_util_cpa_dist` in `missions/encounters/vehicle.bhv`.
const MIN_UTIL_CPA: f64 = 10.0;

/// Runs `fleet` (a file of `missions/encounters`) with the command-line `macros`; returns
/// each community's alog by name.
fn run_logs(name: &str, fleet: &str, macros: &[&str]) -> BTreeMap<String, alog::Alog> {
    run_fleet("encounters", name, fleet, macros)
}

/// Every pair's closest approach in the run of `fleet`, `("a-b", distance, time)`.
fn approaches(name: &str, fleet: &str, macros: &[&str]) -> Vec<(String, f64, f64)> {
    closest(&run_logs(name, fleet, macros))
        .into_iter()
        .map(|((a, b), (d, t))| (format!("{a}-{b}"), d, t))
        .collect()
}

/// Runs `fleet` with and without the behaviour and checks both outcomes.
fn encounter(fleet: &str, vehicles: usize) {
    let stem = fleet.trim_end_matches(".fleet");
    let with = approaches(&format!("enc-{stem}"), fleet, &[]);
    let without = approaches(&format!("enc-{stem}-off"), fleet, &["AVOID=off"]);
    assert_eq!(with.len(), vehicles * (vehicles - 1) / 2);
    for ((pair, d, t), (_, d0, t0)) in with.iter().zip(&without) {
        eprintln!(
            "{fleet} {pair}: closest approach {d:.2} m at t={t:.2} with BHV_AvoidCollision, \
             {d0:.2} m at t={t0:.2} without"
        );
        assert!(
            *d > MIN_UTIL_CPA,
            "{fleet} {pair}: {d:.2} m at t={t:.2} is within min_util_cpa_dist"
        );
    }
    // Without the behaviour at least one pair collides (in a three-way meeting every pair
    // meets at the same point).
    for (pair, d0, t0) in &without {
        assert!(
            *d0 < 3.0,
            "{fleet} {pair}: without the behaviour {d0:.2} m at t={t0:.2}, no collision"
        );
    }
}

#[test]
fn head_on() {
    encounter("head_on.fleet", 2);
}

#[test]
fn crossing() {
    encounter("crossing.fleet", 2);
}

#[test]
fn overtaking() {
    encounter("overtaking.fleet", 2);
}

#[test]
fn three_way() {
    encounter("three_way.fleet", 3);
}

/// BHV_AvoidCollision with `use_plat_model = true` on the helm's Dubins platform model
/// (`pmgen`, 10 m turns): its CPA follows the model's turn to each course, and the head-on and
/// crossing encounter keeps every closest approach above `min_util_cpa_dist`; the turns change
/// the encounter (the closest approach differs from the default engine's: 29.27 m against
/// 30.17 m when measured; head-on, 31.05 m against 30.01 m).
#[test]
fn use_plat_model_on_the_dubins_model_keeps_clear() {
    let pm = [
        "PLAT_MODEL=true",
        "PMGEN=alg=dubins#radius=10#spoke_degs=10",
    ];
    for fleet in ["crossing.fleet"] {
        let stem = fleet.trim_end_matches(".fleet");
        let on = approaches(&format!("enc-{stem}-pm"), fleet, &pm);
        let og = approaches(&format!("enc-{stem}-og"), fleet, &[pm[1]]);
        for ((pair, d, t), (_, d0, _)) in on.iter().zip(&og) {
            eprintln!(
                "{fleet} {pair}: closest approach {d:.2} m at t={t:.2} with use_plat_model, \
                 {d0:.2} m without"
            );
            assert!(
                *d > MIN_UTIL_CPA,
                "{fleet} {pair}: {d:.2} m at t={t:.2} is within min_util_cpa_dist"
            );
        }
        assert_ne!(on, og, "{fleet}: use_plat_model changed nothing");
    }
}

/// BHV_AvoidCollision with `collision_depth` (`head_on_depth.fleet`: abe with a depth domain
/// and `collision_depth = 4`, ben at the surface without avoidance): abe keeps close to its
/// line and passes under ben, below the collision depth when they are closest, then
/// returns to the surface.
#[test]
fn collision_depth_passes_under_a_surface_contact() {
    let logs = run_logs("enc-head_on_depth", "head_on_depth.fleet", &[]);
    let (_, (d, t)) = closest(&logs)[0];
    let abe_depth = depths(&logs["abe"]);
    let at = |t: f64| {
        abe_depth
            .iter()
            .take_while(|s| s.0 <= t)
            .last()
            .map_or(0.0, |s| s.1)
    };
    let deepest = abe_depth.iter().map(|s| s.1).fold(0.0, f64::max);
    eprintln!(
        "head_on_depth: closest {d:.2} m at t={t:.2}, abe at {:.2} m then (deepest {deepest:.2} m)",
        at(t)
    );
    assert!(
        at(t) >= 4.0,
        "abe at {:.2} m when closest ({d:.2} m at t={t:.2})",
        at(t)
    );
    let last = abe_depth.last().expect("NAV_DEPTH logged").1;
    assert!(last < 1.0, "back near the surface at the end: {last:.2} m");
}
