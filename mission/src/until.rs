//! Whether a run's stop condition (`coug run --until`) can ever hold: a variable nothing in the
//! mission posts, initialises or even names would keep the run going to `--max-time`.

use std::collections::HashSet;

use crate::bhv::BehaviorFile;
use crate::catalog::WELL_KNOWN_VARS;
use crate::condition::Condition;

/// Prefixes of variables the standard apps post without the mission naming them (the helm's
/// and the DB's reports, navigation, the PID's and simulator's outputs, node reports, the
/// stock behaviours' status variables).
const APP_PREFIXES: &[&str] = &[
    "IVPHELM_",
    "DB_",
    "NAV_",
    "DESIRED_",
    "PID_",
    "USM_",
    "NODE_",
    "PNR_",
    "BHV_",
    "LOITER_",
    "WPT_",
    "CYCLE_",
    "OPREG_",
    "PSKEEP_",
    "PSURFACE_",
    "VIEW_",
    "LOGGER_",
    "APPCAST",
];

/// The variables of `until` that nothing in the mission posts, initialises or names: not in
/// the mission text (which holds every app's configuration and any uTimerScript event), not
/// in a behaviour file (initialize lines, modes, parameters and flags), not poked by the
/// command (`poked`), and not a variable the standard apps post on their own.
///
/// ```
/// use mission::condition::parse_condition;
/// let c = parse_condition("MISSION = complete and DONE = true").unwrap();
/// let left = mission::until::unknown_vars(&c, "// posts MISSION via a flag", &[], &[]);
/// assert_eq!(left, ["DONE"]);
/// ```
pub fn unknown_vars(
    until: &Condition,
    mission_text: &str,
    behaviors: &[&BehaviorFile],
    poked: &[&str],
) -> Vec<String> {
    let mut named: HashSet<&str> = words(mission_text).collect();
    for b in behaviors {
        named.extend(b.initializes.iter().map(|i| i.var.as_str()));
        for m in &b.modes {
            named.insert(m.var.as_str());
        }
        for spec in &b.behaviors {
            for p in &spec.params {
                named.extend(words(&p.value));
            }
        }
    }
    let mut out: Vec<String> = Vec::new();
    for v in until.variables() {
        let known = named.contains(v)
            || poked.contains(&v)
            || WELL_KNOWN_VARS.contains(&v)
            || APP_PREFIXES.iter().any(|p| v.starts_with(p))
            || v.ends_with("_STATUS");
        if !known && !out.iter().any(|o| o == v) {
            out.push(v.to_string());
        }
    }
    out
}

/// The identifier-like words of a text.
fn words(text: &str) -> impl Iterator<Item = &str> {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| !w.is_empty())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::condition::parse_condition;
    use crate::source::SourceMap;

    #[test]
    fn names_from_behaviours_pokes_and_apps_count() {
        let bhv = crate::bhv::parse_bhv(&SourceMap::from_text(
            "m.bhv",
            "initialize READY = false\nBehavior = BHV_Waypoint\n{\n  endflag = RETURNED = true\n}\n",
        ))
        .value;
        let c = parse_condition(
            "READY = true and RETURNED = true and GO = 1 and NAV_X > 3 and IVPHELM_ITER > 2 and TYPO = 1",
        )
        .unwrap();
        assert_eq!(unknown_vars(&c, "", &[&bhv], &["GO"]), ["TYPO"]);
    }
}
