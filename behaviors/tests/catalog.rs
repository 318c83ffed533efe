//! The parameters `coug check` lists (mission::catalog) against the behaviours of issue #4.

use behaviors::{Common, Ctx, MapInfo, ParamError, create};

/// The behaviour types of issue #4 (others are checked by their own tests).
const MINE: [&str; 5] = [
    "BHV_Waypoint",
    "BHV_Loiter",
    "BHV_ConstantSpeed",
    "BHV_ConstantHeading",
    "BHV_Timer",
];

/// Every parameter `coug check` lists for these types is either accepted or rejected
/// explicitly as unsupported, never reported as unknown.
#[test]
fn catalog_parameters_are_known() {
    let domain = ivp::Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
    let info = MapInfo::new(0.0)
        .num("NAV_X", 0.0)
        .num("NAV_Y", 0.0)
        .num("NAV_HEADING", 0.0)
        .num("NAV_SPEED", 0.0);
    let ctx = Ctx {
        info: &info,
        domain: &domain,
        ownship: "a",
        name: "b",
        perpetual: false,
    };
    let sample = |p: &str| -> &str {
        match p {
            "points" | "polygon" | "xpoints" => "0,0:10,0:10,10:0,10",
            "point" | "newpt" => "5,5",
            "order" => "normal",
            "repeat" => "1",
            "currix" => "0",
            "ipf_type" | "ipf-type" => "zaic",
            "efficiency_measure" => "off",
            "visual_hints" => "vertex_size=3",
            "cycleflag" | "wptflag" | "lead_condition" => "A = 1",
            "end_spd" => "slow_dist=10,stop_dist=1",
            "greedy_tour"
            | "shortest_tour"
            | "reset_on_idle"
            | "draw_path_loop"
            | "eager_prev_index_flag" => "true",
            "clockwise" => "true",
            "center_assign" => "5,5",
            p if p.starts_with("use_")
                || p.ends_with("_start")
                || p == "capture_line"
                || p == "center_activate" =>
            {
                "true"
            }
            p if p.ends_with("_var")
                || p.starts_with("var_")
                || p.starts_with("wpt_")
                || p.ends_with("_suffix")
                || p == "cycle_index_var" =>
            {
                "SOME_VAR"
            }
            _ => "2",
        }
    };
    let mut unsupported = Vec::new();
    for kind in MINE {
        let t = mission::catalog::BEHAVIORS
            .iter()
            .find(|b| b.name == kind)
            .unwrap();
        for p in t.params {
            let mut b = create(kind).unwrap();
            let mut c = Common::new(kind);
            if *p == "xpoints" {
                // xpoints replaces a route of the same length.
                b.set_param("points", sample(p), &mut c, &ctx).unwrap();
            }
            match b.set_param(p, sample(p), &mut c, &ctx) {
                Ok(()) => {}
                Err(ParamError::Unknown { .. }) => {
                    panic!("{kind}: catalog parameter {p} unknown")
                }
                Err(ParamError::BadValue { expected, .. }) => {
                    assert!(expected.contains("not support"), "{kind} {p}: {expected}");
                    unsupported.push(format!("{kind}.{p}"));
                }
            }
        }
    }
    // Both spellings of the function type, as MOOS-IvP accepts, are listed.
    for kind in ["BHV_Waypoint", "BHV_Loiter"] {
        let t = mission::catalog::behavior(kind).unwrap();
        assert!(t.accepts("ipf_type") && t.accepts("ipf-type"), "{kind}");
    }
    assert!(unsupported.is_empty(), "{unsupported:?}");
    for p in mission::catalog::COMMON_PARAMS {
        let mut c = Common::new("BHV_Timer");
        let v = match *p {
            "condition" => "A = 1",
            "updates" | "duration_status" | "name" | "descriptor" => "X",
            "duration_reset" => "X=1",
            "post_mapping" => "A,B",
            "nostarve" | "no_starve" => "A,5",
            "comms_policy" => "open",
            "templating" => "disallow",
            "duration_idle_decay" | "perpetual" => "true",
            p if p.contains("flag") => "A = 1",
            _ => "2",
        };
        assert_eq!(c.set_param(p, v), Ok(true), "common {p}");
    }
}
