//! The parameters `coug check` lists (mission::catalog) against the behaviours of issue #5,
//! both ways.

mod support;

use behaviors::ParamError;
use support::{Bhv, uuv_domain};

/// Each type with every parameter it accepts and a good sample value.
const ACCEPTED: &[(&str, &[(&str, &str)])] = &[
    (
        "BHV_ConstantDepth",
        &[
            ("depth", "5"),
            ("peakwidth", "2"),
            ("basewidth", "10"),
            ("summitdelta", "20"),
            ("depth_mismatch_var", "MISS"),
        ],
    ),
    (
        "BHV_GoToDepth",
        &[
            ("depth", "5,10:20"),
            ("repeat", "2"),
            ("arrival_delta", "1"),
            ("capture_delta", "1"),
            ("arrival_flag", "A"),
            ("capture_flag", "B"),
        ],
    ),
    (
        "BHV_MaxDepth",
        &[
            ("max_depth", "7"),
            ("basewidth", "1"),
            ("tolerance", "1"),
            ("depth_slack_var", "SLACK"),
        ],
    ),
    (
        "BHV_PeriodicSurface",
        &[
            ("period", "120"),
            ("mark_variable", "GPS_UPDATE_RECEIVED"),
            ("acomms_mark_variable", "ACOMMS,30,60"),
            ("pending_status_var", "PENDING"),
            ("pending_status_variable", "PENDING"),
            ("atsurface_status_var", "AT_SURFACE"),
            ("atsurface_status_variable", "AT_SURFACE"),
            ("max_time_at_surface", "60"),
            ("ascent_speed", "1"),
            ("speed_to_surface", "current"),
            ("zero_speed_depth", "0.5"),
            ("ascent_grade", "quasi"),
        ],
    ),
    (
        "BHV_StationKeep",
        &[
            ("station_pt", "5,5"),
            ("point", "5,5"),
            ("center_activate", "true"),
            ("inner_radius", "4"),
            ("outer_radius", "15"),
            ("outer_speed", "1.2"),
            ("extra_speed", "2.5"),
            ("transit_speed", "2.5"),
            ("swing_time", "5"),
            ("hibernation_radius", "25"),
            ("visual_hints", "vertex_size=2, edge_color=blue"),
        ],
    ),
    (
        "BHV_OpRegion",
        &[
            ("polygon", "pts={0,0:10,0:10,10:0,10}"),
            ("max_depth", "10"),
            ("min_altitude", "2"),
            ("max_time", "600"),
            ("trigger_entry_time", "1"),
            ("trigger_exit_time", "0.5"),
            ("breached_poly_flag", "A = 1"),
            ("breached_time_flag", "B = x"),
            ("breached_altitude_flag", "C = $[OWNSHIP]"),
            ("breached_depth_flag", "D = true"),
            ("soft_poly_breach", "false"),
            ("reset_var", "OPREG_RESET"),
            ("time_remaining_var", "TIME_LEFT"),
            ("opregion_poly_var", "OPREG_POLY"),
            ("visual_hints", "edge_color=yellow,vertex_size=2"),
        ],
    ),
];

#[test]
fn every_catalog_parameter_is_accepted_and_every_accepted_one_is_listed() {
    for (kind, params) in ACCEPTED {
        let cat = mission::catalog::BEHAVIORS
            .iter()
            .find(|b| b.name == *kind)
            .unwrap_or_else(|| panic!("{kind} missing from the catalog"));
        for (p, v) in *params {
            let mut b = Bhv::new(kind, "b", uuv_domain());
            b.set(p, v)
                .unwrap_or_else(|e| panic!("{kind}: {p} = {v} rejected: {e}"));
            assert!(
                cat.params.contains(p),
                "{kind}: {p} accepted but not in the catalog"
            );
        }
        for p in cat.params {
            assert!(
                params.iter().any(|(q, _)| q == p),
                "{kind}: catalog parameter {p} has no sample here"
            );
        }
        // And an unknown name is reported as unknown, not as a bad value.
        let mut b = Bhv::new(kind, "b", uuv_domain());
        assert!(matches!(
            b.set("no_such_param", "1"),
            Err(ParamError::Unknown { .. })
        ));
    }
}

#[test]
fn every_type_has_the_default_duration_of_its_cpp_constructor() {
    // MOOS-IvP a2a9b716: only the BHV_ConstantSpeed/Heading/Depth constructors set
    // m_duration = 0; every other behaviour keeps IvPBehavior's -1 (no time limit). A guard
    // such as BHV_MaxDepth with 0 would complete on its first iteration and guard nothing.
    for kind in behaviors::kinds() {
        let b = behaviors::create(&kind.to_ascii_lowercase()).unwrap();
        assert_eq!(b.kind(), kind);
        let want = match kind {
            "BHV_ConstantSpeed" | "BHV_ConstantHeading" | "BHV_ConstantDepth" => 0.0,
            _ => -1.0,
        };
        assert_eq!(b.default_duration(), want, "{kind}");
    }
    for kind in [
        "BHV_MaxDepth",
        "BHV_GoToDepth",
        "BHV_PeriodicSurface",
        "BHV_StationKeep",
        "BHV_OpRegion",
    ] {
        assert!(behaviors::kinds().any(|k| k == kind), "{kind}");
    }
}
