//! What the encounter tests share (`tests/run_encounters.rs`, `tests/run_refinery.rs`,
//! `tests/run_colregs.rs`): a lockstep run of a fleet of `missions/encounters` or
//! `missions/encounters_colregs` until every vehicle's transit is complete, and what is read
//! from the vehicles' alogs (closest approaches, postings).
#![allow(dead_code)]

use std::collections::BTreeMap;
use std::path::Path;

use runtime::fleet::LoadedFleet;
use runtime::session::{self, Ended, FleetOptions, Mode};

use crate::common::{find_alog, fresh_dir, parse, project_mission, track};

/// Runs the fleet `fleet` of `missions/<mission>` with the command-line `macros` in a fresh
/// folder `name`: checked first (no error, no MALCONFIG), then in lockstep, deployed, until
/// `MISSION = complete` (at most 600 s), which must end it. Returns every community's
/// parsed alog by name.
pub fn run_fleet(
    mission: &str,
    name: &str,
    fleet: &str,
    macros: &[&str],
) -> BTreeMap<String, alog::Alog> {
    let path = project_mission(&format!("{mission}/{fleet}"));
    let macros: Vec<String> = macros.iter().map(|m| m.to_string()).collect();
    let loaded = LoadedFleet::from_file(&path, &macros, &[])
        .unwrap_or_else(|e| panic!("{} does not load: {e}", path.display()));
    let checked = session::validate_fleet(&loaded);
    assert!(checked.errors.is_empty(), "{:?}", checked.errors);
    assert!(checked.malconfig.is_empty(), "{:?}", checked.malconfig);
    let dir = fresh_dir(name);
    let opts = FleetOptions {
        mode: Mode::Lockstep,
        deploy: true,
        until: vec!["MISSION = complete".into()],
        max_time: 600.0,
        log_dir: Some(dir.join("logs")),
        ..FleetOptions::default()
    };
    let report = session::run_fleet(&loaded, &opts, &mut session::Quiet)
        .unwrap_or_else(|e| panic!("{fleet} failed: {e}"));
    assert!(
        matches!(
            report.ended,
            Ended::Outcome(runtime::Outcome::ConditionMet { .. })
        ),
        "{fleet}: {report}"
    );
    report
        .members
        .iter()
        .map(|(m, r)| {
            let alog = find_alog(&dir.join("logs").join(m));
            assert_eq!(Path::new(&r.alog), alog);
            (m.clone(), parse(&std::fs::read(&alog).expect("alog")))
        })
        .collect()
}

/// The closest approach of every pair of vehicles over the run, `((a, b), (range, time))`
/// in name order, from their logged positions at the same lockstep instants.
pub fn closest(logs: &BTreeMap<String, alog::Alog>) -> Vec<((String, String), (f64, f64))> {
    let key = |t: f64| (t * 100.0).round() as i64;
    let tracks: BTreeMap<&String, BTreeMap<i64, (f64, f64)>> = logs
        .iter()
        .map(|(n, l)| {
            let tr = track(l).into_iter().map(|(t, x, y)| (key(t), (x, y)));
            (n, tr.collect())
        })
        .collect();
    let names: Vec<&String> = tracks.keys().copied().collect();
    let mut out = Vec::new();
    for (i, a) in names.iter().enumerate() {
        for b in &names[i + 1..] {
            let mut best = (f64::INFINITY, 0.0);
            for (t, (x, y)) in &tracks[a] {
                if let Some((u, v)) = tracks[b].get(t) {
                    let r = (x - u).hypot(y - v);
                    if r < best.0 {
                        best = (r, *t as f64 / 100.0);
                    }
                }
            }
            assert!(best.0.is_finite(), "{a} and {b} share no instant");
            out.push((((*a).clone(), (*b).clone()), best));
        }
    }
    out
}

/// Whether `log` has `var` with a string value containing `needle`.
pub fn has(log: &alog::Alog, var: &str, needle: &str) -> bool {
    log.entries
        .iter()
        .any(|e| e.var == var && e.value.as_str().is_some_and(|s| s.contains(needle)))
}

/// Every value `log` holds for `var`, in order, as text.
pub fn values(log: &alog::Alog, var: &str) -> Vec<String> {
    log.entries
        .iter()
        .filter(|e| e.var == var)
        .map(|e| e.value.to_string())
        .collect()
}
