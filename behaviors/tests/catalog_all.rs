//! One check of every stock behaviour against the parameters `coug check` lists for it
//! (`mission::catalog`, the one list): each listed parameter is known to the behaviour
//! (accepted, or refused for its value, never unknown), and a parameter the catalog lists for
//! some other type but not for this one is unknown to this one. The per-family tests
//! (`catalog`, `catalog_depth`, `colregs`, `obstacle_catalog`) check values and refusals.

mod support;

use std::collections::BTreeSet;

use behaviors::ParamError;
use support::{Bhv, uuv_domain};

/// Values that some parameters accept and others refuse: either way a known parameter is
/// not reported as unknown.
const VALUES: [&str; 6] = [
    "1",
    "true",
    "A=1",
    "x=1,y=2",
    "pts={0,0:0,9:9,9},label=a",
    "0,0:10,0:10,10",
];

/// Whether `kind` knows `param` (some value of [`VALUES`] is not refused as unknown).
fn knows(kind: &str, param: &str) -> bool {
    VALUES.iter().any(|v| {
        let mut b = Bhv::new(kind, "b", uuv_domain());
        !matches!(b.set(param, v), Err(ParamError::Unknown { .. }))
    })
}

#[test]
fn every_stock_behaviour_knows_exactly_the_parameters_the_catalog_lists() {
    let listed: BTreeSet<&str> = mission::catalog::BEHAVIORS
        .iter()
        .flat_map(|t| t.params.iter().copied())
        .collect();
    let mut wrong = Vec::new();
    for kind in behaviors::kinds() {
        let t = mission::catalog::behavior(kind).unwrap_or_else(|| panic!("{kind} not listed"));
        for p in t.params {
            if !knows(kind, p) {
                wrong.push(format!("{kind}: `{p}` is listed but unknown"));
            }
        }
        for p in listed.iter().filter(|p| !t.accepts(p)) {
            if knows(kind, p) {
                wrong.push(format!("{kind}: `{p}` is known but not listed"));
            }
        }
        assert!(!knows(kind, "no_such_param"), "{kind}");
        assert!(!t.accepts("no_such_param"), "{kind}");
    }
    assert!(wrong.is_empty(), "{wrong:#?}");
}
