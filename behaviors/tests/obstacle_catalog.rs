//! The parameters `coug check` lists (mission::catalog) for the obstacle behaviours are
//! exactly the ones the behaviours take: each listed one is known to the behaviour (accepted
//! or refused for its value, never unknown), and a name not listed is unknown to both.

mod support;

use behaviors::ParamError;
use support::{Bhv, uuv_domain};

const KINDS: [&str; 4] = [
    "BHV_AvoidObstacleV24",
    "BHV_AvoidObstacle",
    "BHV_AvoidObstacleX",
    "BHV_AvoidObstacleV21",
];

#[test]
fn every_listed_parameter_is_known_and_no_other() {
    for kind in KINDS {
        let t = mission::catalog::behavior(kind).unwrap_or_else(|| panic!("{kind} not listed"));
        for p in t.params {
            for v in ["1", "true", "A=1", "pts={0,0:0,9:9,9},label=a"] {
                let mut b = Bhv::new(kind, "b", uuv_domain());
                let r = b.set(p, v);
                assert!(
                    !matches!(r, Err(ParamError::Unknown { .. })),
                    "{kind}: `{p}` is listed but unknown"
                );
            }
        }
        let mut b = Bhv::new(kind, "b", uuv_domain());
        let unknown: &[&str] = match kind {
            "BHV_AvoidObstacle" => &["no_such_param", "id", "min_util_cpa_dist"],
            "BHV_AvoidObstacleX" => &["no_such_param", "rng_flag", "buffer_dist"],
            "BHV_AvoidObstacleV21" => &["no_such_param", "resolved", "buffer_dist"],
            _ => &["no_such_param", "buffer_dist", "pwt_grade"],
        };
        for p in unknown {
            assert!(
                matches!(b.set(p, "1"), Err(ParamError::Unknown { .. })),
                "{kind}: {p}"
            );
            assert!(!t.accepts(p), "{kind}: {p}");
        }
        assert!(behaviors::kinds().any(|k| k == kind), "{kind} in STOCK");
    }
}
