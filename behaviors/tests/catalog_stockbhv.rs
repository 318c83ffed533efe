//! The parameters `coug check` lists (mission::catalog) for the non-contact stock behaviours
//! of issue #18 are exactly the ones the behaviours take: each listed one is known to the
//! behaviour (accepted or refused for its value, never unknown), and a name not listed is
//! unknown to both.

mod support;

use behaviors::ParamError;
use support::{Bhv, uuv_domain};

const KINDS: [&str; 8] = [
    "BHV_MaxSpeed",
    "BHV_HSLine",
    "BHV_BearingLine",
    "BHV_ZigZag",
    "BHV_TestFailure",
    "BHV_MemoryTurnLimit",
    "BHV_PeriodicSpeed",
    "BHV_FixedTurn",
];

#[test]
fn every_listed_parameter_is_known_and_no_other() {
    for kind in KINDS {
        let t = mission::catalog::behavior(kind).unwrap_or_else(|| panic!("{kind} not listed"));
        assert!(!t.params.is_empty(), "{kind}");
        for p in t.params {
            let mut b = Bhv::new(kind, "b", uuv_domain());
            // A value that is valid for some parameters and refused by others: either way
            // the parameter must be the behaviour's own.
            for v in ["1", "true", "A=1", "x=1,y=2"] {
                let r = b.set(p, v);
                assert!(
                    !matches!(r, Err(ParamError::Unknown { .. })),
                    "{kind}: `{p}` is listed but unknown"
                );
            }
        }
        let mut b = Bhv::new(kind, "b", uuv_domain());
        assert!(matches!(
            b.set("no_such_param", "1"),
            Err(ParamError::Unknown { .. })
        ));
        assert!(!t.accepts("no_such_param"));
        assert!(behaviors::kinds().any(|k| k == kind), "{kind} in STOCK");
    }
}
