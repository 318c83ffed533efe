//! Behaviour types, parameters and variables coug knows, used by `coug check`.
//!
//! Sources: `ivp-helm.md` §4.1 (pHelmIvP's ProcessConfig), §5.5 (parameters every behaviour
//! accepts) and §6 (each behaviour), checked against every mission of the MOOS-IvP corpus.
//! Parameter names are compared as pHelmIvP does: lower case, leading `_` ignored.
//!
//! ```
//! let wpt = mission::catalog::behavior("bhv_waypoint").unwrap();
//! assert!(wpt.accepts("Capture_Radius"));
//! assert!(wpt.accepts("endflag"));      // common to every behaviour
//! assert!(!wpt.accepts("capture_radiuss"));
//! assert!(mission::catalog::helm_accepts("Behaviors"));
//! ```

use crate::bhv::param_name;

/// One behaviour type: its parameters and the variables it posts by default.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BehaviorType {
    /// The type name as written in `.bhv` files, e.g. `BHV_Waypoint`.
    pub name: &'static str,
    /// Parameters specific to this type (lower case).
    pub params: &'static [&'static str],
    /// MOOS variables the behaviour posts by default.
    pub posts: &'static [&'static str],
}

impl BehaviorType {
    /// Whether `key` is a parameter of this type or a common behaviour parameter.
    pub fn accepts(&self, key: &str) -> bool {
        let k = param_name(key);
        self.params.contains(&k.as_str()) || COMMON_PARAMS.contains(&k.as_str())
    }
}

/// Parameters every behaviour accepts (`IvPBehavior::setParam`, ivp-helm.md §5.5), plus
/// `name`/`descriptor`, `templating` and `max_spawnings` handled by the behaviour spec.
pub const COMMON_PARAMS: &[&str] = &[
    "name",
    "descriptor",
    "pwt",
    "priwt",
    "priority",
    "condition",
    "updates",
    "duration",
    "duration_status",
    "duration_reset",
    "duration_idle_decay",
    "perpetual",
    "runflag",
    "run_flag",
    "runxflag",
    "runx_flag",
    "activeflag",
    "active_flag",
    "inactiveflag",
    "inactive_flag",
    "idleflag",
    "idle_flag",
    "endflag",
    "end_flag",
    "spawnflag",
    "spawn_flag",
    "spawnxflag",
    "spawnx_flag",
    "configflag",
    "config_flag",
    "nostarve",
    "no_starve",
    "post_mapping",
    "comms_policy",
    "build_info",
    "precision",
    "templating",
    "max_spawnings",
];

/// The parameters of a contact behaviour: [`CONTACT_PARAMS`] (written once, here) followed by
/// the type's own.
macro_rules! contact_params {
    ($($own:literal),* $(,)?) => {
        &[
            "contact",
            "extrapolate",
            "post_per_contact_info",
            "match_name",
            "ignore_name",
            "match_group",
            "ignore_group",
            "match_type",
            "ignore_type",
            "match_region",
            "ignore_region",
            "strict_ignore",
            "exit_on_filter_vtype",
            "exit_on_filter_group",
            "exit_on_filter_region",
            "cnflag",
            "decay",
            "on_no_contact_ok",
            "decay_end",
            "time_on_leg",
            "bearing_line_label_show",
            "bearing_line_show",
            "bearing_lines",
            "bearing_line_config",
            $($own),*
        ]
    };
}

/// The parameters of every BHV_AvdColregs version (V17's set), then `$own`: the contact
/// behaviours' common ones included.
macro_rules! colregs_params {
    ($($own:literal),* $(,)?) => {
        contact_params!(
            "use_plat_model",
            "pwt_inner_dist",
            "pwt_outer_dist",
            "min_util_cpa_dist",
            "max_util_cpa_dist",
            "completed_dist",
            "turn_radius",
            "avoid_mode",
            "avoid_submode",
            "no_alert_request",
            "contact_type_required",
            "pwt_grade",
            $($own),*
        )
    };
}

/// `$own`, then the parameters of BHV_LegRun's leg (written once, here).
macro_rules! leg_params {
    ($($own:literal),* $(,)?) => {
        &[
            $($own,)*
            "p1",
            "vx1",
            "p2",
            "vx2",
            "leg",
            "leg_len",
            "leg_len_mod",
            "leg_ang",
            "leg_ang_mod",
            "shift_pt",
            "turn1_bias",
            "turn2_bias",
            "turn_bias",
            "turn1_bias_mod",
            "turn2_bias_mod",
            "turn_bias_mod",
            "turn1_ext",
            "turn2_ext",
            "turn_ext",
            "turn1_ext_mod",
            "turn2_ext_mod",
            "turn_ext_mod",
            "turn1_rad",
            "turn2_rad",
            "turn_rad",
            "turn_rad_min",
            "turn1_rad_mod",
            "turn2_rad_mod",
            "turn_rad_mod",
            "turn_pt_gap",
            "turn1_dir",
            "turn2_dir",
            "turn_dir",
            "id",
        ]
    };
}

/// The parameters of BHV_LegRun's leg (MOOS `LegRun::setParam`): the behaviour tells a bad
/// value of one of these from an unknown parameter by this list.
pub const LEG_PARAMS: &[&str] = leg_params!();

/// The parameters BHV_AvoidObstacleV24, BHV_AvoidObstacleX and BHV_AvoidObstacleV21 share
/// (written once, here), then `$own`.
macro_rules! obstacle_params {
    ($($own:literal),* $(,)?) => {
        &[
            "polygon",
            "poly",
            "allowable_ttc",
            "min_util_cpa_dist",
            "max_util_cpa_dist",
            "pwt_inner_dist",
            "pwt_outer_dist",
            "completed_dist",
            $($own),*
        ]
    };
}

/// BHV_AvdColregsV22's parameters, which V26 takes as well.
const COLREGS_V22_PARAMS: &[&str] = colregs_params!(
    "giveway_bow_dist",
    "verbose",
    "use_refinery",
    "check_plateaus",
    "check_validity",
    "pcheck_thresh",
    "can_disable",
    "headon_only",
    "eval_tol",
    "velocity_filter",
    "post_status_info_on_idle",
    "pts_port_turns_ok",
);

/// The behaviour types whose parameters coug checks (ivp-helm.md §6).
pub const BEHAVIORS: &[BehaviorType] = &[
    BehaviorType {
        name: "BHV_Waypoint",
        params: &[
            "points",
            "polygon",
            "xpoints",
            "point",
            "newpt",
            "speed",
            "speed_alt",
            "use_alt_speed",
            "capture_radius",
            "radius",
            "slip_radius",
            "nm_radius",
            "capture_line",
            "lead",
            "lead_damper",
            "lead_to_start",
            "lead_condition",
            "order",
            "repeat",
            "currix",
            "greedy_tour",
            "shortest_tour",
            "draw_path_loop",
            "wpt_status",
            "wpt_status_var",
            "wpt_index",
            "wpt_index_var",
            "cycle_index_var",
            "wpt_dist_to_prev",
            "wpt_dist_to_next",
            "post_suffix",
            "cycleflag",
            "wptflag",
            "wptflag_on_start",
            "reset_on_idle",
            "eager_prev_index_flag",
            "ipf_type",
            "ipf-type",
            "crs_spd_zaic_ratio",
            "patience",
            "efficiency_measure",
            "end_spd",
            "visual_hints",
        ],
        posts: &["WPT_STAT", "WPT_INDEX", "CYCLE_INDEX", "WPT_ODO"],
    },
    BehaviorType {
        name: "BHV_Loiter",
        params: &[
            "polygon",
            "speed",
            "speed_alt",
            "use_alt_speed",
            "clockwise",
            "capture_radius",
            "radius",
            "slip_radius",
            "nm_radius",
            "acquire_dist",
            "acquire_distance",
            "patience",
            "center_assign",
            "xcenter_assign",
            "ycenter_assign",
            "center_activate",
            "mod_poly_rad",
            "spiral_factor",
            "slingshot",
            "ipf_type",
            "ipf-type",
            "post_suffix",
            "visual_hints",
        ],
        posts: &[
            "LOITER_REPORT",
            "LOITER_INDEX",
            "LOITER_MODE",
            "LOITER_ACQUIRE",
            "LOITER_DIST_TO_VERT",
            "LOITER_COMPLETE",
        ],
    },
    BehaviorType {
        name: "BHV_ConstantSpeed",
        params: &[
            "speed",
            "peakwidth",
            "basewidth",
            "summitdelta",
            "speed_mismatch_var",
        ],
        posts: &[],
    },
    BehaviorType {
        name: "BHV_ConstantHeading",
        params: &[
            "heading",
            "peakwidth",
            "basewidth",
            "summitdelta",
            "complete_thresh",
            "heading_mismatch_var",
        ],
        posts: &[],
    },
    BehaviorType {
        name: "BHV_ConstantDepth",
        params: &[
            "depth",
            "peakwidth",
            "basewidth",
            "summitdelta",
            "depth_mismatch_var",
        ],
        posts: &[],
    },
    BehaviorType {
        name: "BHV_GoToDepth",
        params: &[
            "depth",
            "repeat",
            "arrival_delta",
            "capture_delta",
            "arrival_flag",
            "capture_flag",
        ],
        posts: &["LEVEL_DEPTH"],
    },
    BehaviorType {
        name: "BHV_MaxDepth",
        params: &["max_depth", "basewidth", "tolerance", "depth_slack_var"],
        posts: &[],
    },
    BehaviorType {
        name: "BHV_PeriodicSurface",
        params: &[
            "period",
            "mark_variable",
            "acomms_mark_variable",
            "pending_status_var",
            "pending_status_variable",
            "atsurface_status_var",
            "atsurface_status_variable",
            "max_time_at_surface",
            "ascent_speed",
            "speed_to_surface",
            "zero_speed_depth",
            "ascent_grade",
        ],
        posts: &[
            "PERIODIC_ASCEND",
            "PENDING_SURFACE",
            "TIME_AT_SURFACE",
            "PSF_AT_SURFACE_TIMEOUT",
        ],
    },
    BehaviorType {
        name: "BHV_StationKeep",
        params: &[
            "station_pt",
            "point",
            "center_activate",
            "inner_radius",
            "outer_radius",
            "outer_speed",
            "extra_speed",
            "transit_speed",
            "swing_time",
            "hibernation_radius",
            "visual_hints",
        ],
        posts: &["DIST_TO_STATION", "PSKEEP_MODE"],
    },
    BehaviorType {
        name: "BHV_OpRegion",
        params: &[
            "polygon",
            "max_depth",
            "min_altitude",
            "max_time",
            "trigger_entry_time",
            "trigger_exit_time",
            "breached_poly_flag",
            "breached_time_flag",
            "breached_altitude_flag",
            "breached_depth_flag",
            "soft_poly_breach",
            "reset_var",
            "time_remaining_var",
            "opregion_poly_var",
            "visual_hints",
        ],
        posts: &[
            "OPREG_TRAJECTORY_PERIM_DIST",
            "OPREG_TRAJECTORY_PERIM_ETA",
            "OPREG_ABSOLUTE_PERIM_DIST",
            "OPREG_ABSOLUTE_PERIM_ETA",
            "OPREG_TIME_REMAINING",
            "SECS_IN_POLY",
        ],
    },
    BehaviorType {
        name: "BHV_OpRegionV24",
        params: &[
            "core_poly",
            "save_poly",
            "halt_poly",
            "save_dist",
            "halt_dist",
            "max_depth",
            "min_altitude",
            "max_time",
            "recover_spd",
            "recover_speed",
            "reset",
            "trigger_on_poly_entry",
            "trigger_entry_time",
            "trigger_exit_time",
            "breached_poly_flag",
            "breached_time_flag",
            "breached_altitude_flag",
            "breached_depth_flag",
            "save_flag",
            "savex_flag",
            "draw_save_status",
            "draw_halt_status",
            "visual_hints",
            "dynamic_region_var",
        ],
        posts: &["VIEW_POLYGON", "COMMITTED"],
    },
    BehaviorType {
        name: "BHV_Timer",
        params: &["var_status_idle", "var_status_running", "status_suffix"],
        posts: &["TIMER_IDLE", "TIMER_RUNNING"],
    },
    BehaviorType {
        name: "BHV_MaxSpeed",
        params: &["max_speed", "basewidth", "tolerance", "speed_slack_var"],
        posts: &[],
    },
    BehaviorType {
        name: "BHV_HSLine",
        params: &["time_on_leg"],
        posts: &["VIEW_SEGLIST"],
    },
    BehaviorType {
        name: "BHV_BearingLine",
        params: &["bearing_point", "line_pct", "show_pt"],
        posts: &["VIEW_SEGLIST", "VIEW_POINT"],
    },
    BehaviorType {
        name: "BHV_ZigZag",
        params: &[
            "speed",
            "mod_speed",
            "spd_on_active",
            "speed_on_active",
            "stem_hdg",
            "stem_on_active",
            "hdg_thresh",
            "fierce_zigging",
            "zig_angle",
            "zig_angle_fierce",
            "delta_heading",
            "zig_first",
            "max_zig_legs",
            "max_zig_zags",
            "max_stem_odo",
            "zigflag",
            "zagflag",
            "portflag",
            "starflag",
            "portflagx",
            "starflagx",
            "visual_hints",
        ],
        posts: &["VIEW_SEGLIST"],
    },
    BehaviorType {
        name: "BHV_TestFailure",
        params: &["failure_type"],
        posts: &[],
    },
    BehaviorType {
        name: "BHV_MemoryTurnLimit",
        params: &["memory_time", "turn_range"],
        posts: &["MEM_HDG_AVG"],
    },
    BehaviorType {
        name: "BHV_PeriodicSpeed",
        params: &[
            "period_busy",
            "period_lazy",
            "period_speed",
            "basewidth",
            "zaic_basewidth",
            "period_basewidth",
            "peakwidth",
            "period_peakwidth",
            "zaic_peakwidth",
            "summit_delta",
            "zaic_summit_delta",
            "reset_upon_running",
            "initially_busy",
        ],
        posts: &[
            "PS_BUSY_COUNT",
            "PS_PENDING_ACTIVE",
            "PS_PENDING_INACTIVE",
            "PERIODIC_SPEED",
        ],
    },
    BehaviorType {
        name: "BHV_FixedTurn",
        params: &[
            "fix_turn",
            "mod_hdg",
            "turn_dir",
            "speed",
            "timeout",
            "turn_delay",
            "turn_spec",
            "schedule_repeat",
            "stale_nav_thresh",
            "radius_rep_var",
            "visual_hints",
        ],
        posts: &["FT_REPORT", "VIEW_SEGLIST"],
    },
    BehaviorType {
        name: "BHV_AvoidCollision",
        params: contact_params!(
            "use_plat_model",
            "pwt_outer_dist",
            "pwt_inner_dist",
            "min_util_cpa_dist",
            "max_util_cpa_dist",
            "completed_dist",
            "pwt_grade",
            "roc_max_heighten",
            "roc_max_dampen",
            "contact_type_required",
            "collision_depth",
            "no_alert_request",
            "verbose",
            "use_refinery",
            "check_plateaus",
            "check_validity",
            "pcheck_thresh",
            "can_disable",
        ),
        posts: &["BCM_ALERT_REQUEST", "AVD_DEBUG"],
    },
    BehaviorType {
        name: "BHV_CutRange",
        params: contact_params!(
            "use_plat_model",
            "pwt_outer_dist",
            "pwt_inner_dist",
            "giveup_dist",
            "giveup_range",
            "pursueflag",
            "giveupflag",
            "patience",
            "max_patience",
        ),
        posts: &["BCM_ALERT_REQUEST"],
    },
    BehaviorType {
        name: "BHV_Convoy",
        params: contact_params!(
            "use_plat_model",
            "nm_radius",
            "radius",
            "max_mark_range",
            "inter_mark_range",
            "cruise_speed",
            "spd_max",
            "spd_slower",
            "spd_faster",
            "rng_estop",
            "range_estop",
            "rng_tgating",
            "range_tailgating",
            "rng_lagging",
            "range_lagging",
            "rng_safety",
        ),
        posts: &[
            "TLEN",
            "QLEN",
            "MXRNG",
            "AVG2",
            "AVG5",
            "WPTX",
            "WPTY",
            "VIEW_POINT",
        ],
    },
    BehaviorType {
        name: "BHV_Trail",
        params: contact_params!(
            "use_plat_model",
            "nm_radius",
            "no_alert_request",
            "post_trail_dist_on_idle",
            "pwt_outer_dist",
            "radius",
            "trail_range",
            "mod_trail_range",
            "mod_trail_range_pct",
            "trail_angle",
            "trail_angle_type",
        ),
        posts: &[
            "VIEW_POINT",
            "TRAIL_RELEVANCE",
            "TRAIL_CTR",
            "PURSUIT",
            "TRAIL_RANGE",
            "TRAIL_DISTANCE",
            "REGION",
            "TRAIL_HEADING",
            "TRAIL_SPEED",
        ],
    },
    BehaviorType {
        name: "BHV_Shadow",
        params: contact_params!(
            "use_plat_model",
            "pwt_outer_dist",
            "heading_peakwidth",
            "hdg_peakwidth",
            "heading_basewidth",
            "hdg_basewidth",
            "speed_peakwidth",
            "spd_peakwidth",
            "speed_basewidth",
            "spd_basewidth",
        ),
        posts: &[
            "SHADOW_CONTACT_X",
            "SHADOW_CONTACT_Y",
            "SHADOW_CONTACT_SPEED",
            "SHADOW_CONTACT_HEADING",
            "SHADOW_RELEVANCE",
        ],
    },
    BehaviorType {
        name: "BHV_LegRun",
        params: leg_params!(
            // BHV_LegRun's own and its waypoint engines', then the leg's.
            "capture_line",
            "init_leg_mode",
            "lead",
            "lead_damper",
            "leg_spds",
            "leg_spds_onturn",
            "leg_spds_repeat",
            "leg_endflag",
            "leg_end_flag",
            "leg1_endflag",
            "leg1_end_flag",
            "leg2_endflag",
            "leg2_end_flag",
            "midlegflag",
            "mid_leg_flag",
            "midturnflag",
            "mid_turn_flag",
            "mid_leg_pct",
            "mid_turn_pct",
            "patience",
            "radius",
            "capture_radius",
            "repeat",
            "slip_radius",
            "speed",
            "turn_endflag",
            "turn_end_flag",
            "turn1_endflag",
            "turn1_end_flag",
            "turn2_endflag",
            "turn2_end_flag",
            "visual_hints",
        ),
        posts: &[
            "LR_MODE",
            "LR_MODE_REPORT",
            "LR_NOW_SPD",
            "VIEW_SEGLIST",
            "VIEW_POINT",
        ],
    },
    BehaviorType {
        name: "BHV_PModelView",
        params: &["edge_color", "vertex_color", "vertex_size"],
        posts: &["VIEW_SEGLR"],
    },
    BehaviorType {
        name: "BHV_AvoidObstacleV24",
        params: obstacle_params!(
            "holonomic_ok",
            "draw_buff_min_poly",
            "draw_buff_max_poly",
            "can_disable",
            "rng_flag",
            "cpa_flag",
            "visual_hints",
            "use_refinery",
            "id",
            "obid",
            "allstop_on_breach",
        ),
        posts: &["OBM_ALERT_REQUEST", "NOTED_RESOLVED", "VIEW_POLYGON"],
    },
    BehaviorType {
        name: "BHV_AvoidObstacleX",
        params: obstacle_params!(
            "resolved",
            "visual_hints",
            "use_refinery",
            "id",
            "i_understand_this_behavior_is_deprecated",
        ),
        posts: &[
            "OBM_ALERT_REQUEST",
            "NOTED_RESOLVED",
            "OS_DIST_TO_POLY",
            "AVD_OB_SPAWN",
            "VIEW_POLYGON",
        ],
    },
    BehaviorType {
        name: "BHV_AvoidObstacleV21",
        params: obstacle_params!(
            "rng_flag",
            "cpa_flag",
            "visual_hints",
            "use_refinery",
            "id",
            "i_understand_this_behavior_is_deprecated",
        ),
        posts: &[
            "OBM_ALERT_REQUEST",
            "NOTED_RESOLVED",
            "OS_DIST_TO_POLY",
            "VIEW_POLYGON",
        ],
    },
    BehaviorType {
        name: "BHV_AvoidObstacle",
        params: &[
            "polygon",
            "points",
            "poly",
            "allowable_ttc",
            "buffer_dist",
            "obstacle_key",
            "pwt_outer_dist",
            "pwt_inner_dist",
            "completed_dist",
            "no_alert_request",
            "resolved",
            "i_understand_this_behavior_is_deprecated",
            "visual_hints",
        ],
        posts: &[
            "OBM_ALERT_REQUEST",
            "OS_DIST_TO_POLY",
            "OBSTACLE_RESOLVED",
            "AVD_OB_SPAWN",
            "VIEW_POLYGON",
        ],
    },
    BehaviorType {
        name: "BHV_AvdColregsV22",
        params: COLREGS_V22_PARAMS,
        posts: &["BCM_ALERT_REQUEST"],
    },
    BehaviorType {
        name: "BHV_AvdColregsV19",
        params: colregs_params!(
            "giveway_bow_dist",
            "verbose",
            "use_refinery",
            "check_plateaus",
            "check_validity",
            "pcheck_thresh",
            "can_disable",
        ),
        posts: &[
            "BCM_ALERT_REQUEST",
            "AVD_INFO",
            "COL19_RELEVANCE",
            "VIEW_SEGLIST",
        ],
    },
    BehaviorType {
        name: "BHV_AvdColregsV17",
        params: colregs_params!(),
        posts: &["BCM_ALERT_REQUEST", "COL17_RELEVANCE", "VIEW_SEGLIST"],
    },
    BehaviorType {
        name: "BHV_AvdColregsV26",
        params: COLREGS_V22_PARAMS,
        posts: &["BCM_ALERT_REQUEST"],
    },
];

/// The parameters every contact behaviour takes (MOOS `IvPContactBehavior::setParam`).
pub const CONTACT_PARAMS: &[&str] = contact_params!();

/// `$own`, then the lines every AppCasting MOOS app takes ([`APP_CASTING_PARAMS`], written
/// once, here).
macro_rules! app_casting_params {
    ($($own:literal),* $(,)?) => {
        &[
            $($own,)*
            "apptick",
            "commstick",
            "maxapptick",
            "app_logging",
            "term_report_interval",
            "max_appcast_events",
            "deprecated_ok",
        ]
    };
}

/// pHelmIvP's own ProcessConfig parameters (MOOS-IvP a2a9b716 `HelmIvP::OnStartUp`), plus
/// [`APP_CASTING_PARAMS`]. Any other line is an unhandled config line: a config warning,
/// which puts pHelmIvP in MALCONFIG.
pub const HELM_PARAMS: &[&str] = app_casting_params!(
    "behaviors",
    "domain",
    "ok_skew",
    "verbose",
    "start_engaged",
    "active_start",
    "start_indrive",
    "start_in_drive",
    "allow_park",
    "park_on_allstop",
    "standby",
    "helm_alias",
    "helm_prefix",
    "hold_on_app",
    "hold_on_apps",
    "nav_grace",
    "contact_max_age",
    "seed_random",
    "goals_mandatory",
    "node_skew",
    "ivp_behavior_dir",
    "ivp_behavior_dirs",
    "bhv_dir_not_found_ok",
    "bhv_dirs_not_found_ok",
    "pmgen",
    "other_override_var",
);

/// pContactMgrV20's ProcessConfig parameters (MOOS-IvP a2a9b716 `ContactMgrV20::OnStartUp`
/// and its `handleConfigDeprecations`: the deprecated names are accepted with a warning; its
/// own `alert_range` and `alert_cpa_range` are warned and refused), lower case, plus
/// [`APP_CASTING_PARAMS`]. `runtime::contact_mgr` reads each of them.
pub const CONTACT_MGR_V20_PARAMS: &[&str] = &[
    "alert",
    "ignore_name",
    "match_name",
    "ignore_group",
    "match_group",
    "ignore_type",
    "match_type",
    "match_region",
    "ignore_region",
    "strict_ignore",
    "max_contacts",
    "decay",
    "range_report_timeout",
    "range_report_maxsize",
    "display_radii",
    "display_radii_id",
    "post_closest_range",
    "post_closest_relbng",
    "post_all_ranges",
    "max_retired_history",
    "contact_local_coords",
    "recap_interval",
    "contacts_recap_interval",
    "reject_range",
    "alert_verbose",
    "contact_max_age",
    "alert_range_color",
    "default_alert_range_color",
    "cpa_range_color",
    "default_cpa_range_color",
    "hold_alerts_for_helm",
    "ownship_group",
    "ownship_type",
    "disable_var",
    "enable_var",
    "expunge_var",
    "able_flag",
    "disable_flag",
    "enable_flag",
    "early_warning_flag",
    "cease_warning_flag",
    "retire_flag",
    "early_warning_time",
    "early_warning_radii",
    "ewarn_radii_color",
    "apptick",
    "commstick",
    "maxapptick",
    "app_logging",
    "term_report_interval",
    "max_appcast_events",
    "deprecated_ok",
];

/// uFldNodeComms's ProcessConfig parameters (MOOS-IvP a2a9b716 `FldNodeComms::OnStartUp`),
/// lower case, plus [`APP_CASTING_PARAMS`]. `runtime::node_comms` reads each of them.
pub const NODE_COMMS_PARAMS: &[&str] = &[
    "comms_range",
    "critical_range",
    "stale_time",
    "min_msg_interval",
    "min_rpt_interval",
    "max_msg_length",
    "stealth",
    "earange",
    "groups",
    "msg_groups",
    "view_node_rpt_pulses",
    "drop_percentage",
    "pulse_duration",
    "shared_node_reports",
    "msg_color",
    "msg_repeat_color",
    "apptick",
    "commstick",
    "maxapptick",
    "app_logging",
    "term_report_interval",
    "max_appcast_events",
    "deprecated_ok",
];

/// The lines an AppCasting MOOS app's unhandled-line check lets through without a warning
/// (MOOS-IvP a2a9b716 `AppCastingMOOSApp::reportUnhandledConfigWarning`), lower case.
pub const APP_CASTING_PARAMS: &[&str] = app_casting_params!();

/// Whether pHelmIvP accepts `key` in its ProcessConfig block (case-insensitive).
pub fn helm_accepts(key: &str) -> bool {
    let k = key.to_ascii_lowercase();
    HELM_PARAMS.contains(&k.as_str())
}

/// The behaviour type named `kind` (case-insensitive), if coug knows it.
pub fn behavior(kind: &str) -> Option<&'static BehaviorType> {
    BEHAVIORS.iter().find(|b| b.name.eq_ignore_ascii_case(kind))
}

/// Variables that the standard MOOS-IvP processes of a mission post (navigation, helm,
/// MOOSDB, manual override), which behaviour conditions may test without any initialize.
pub const WELL_KNOWN_VARS: &[&str] = &[
    "NAV_X",
    "NAV_Y",
    "NAV_LAT",
    "NAV_LONG",
    "NAV_HEADING",
    "NAV_YAW",
    "NAV_SPEED",
    "NAV_DEPTH",
    "NAV_ALTITUDE",
    "NAV_PITCH",
    "NAV_ROLL",
    "MOOS_MANUAL_OVERRIDE",
    "MOOS_MANUAL_OVERIDE",
    "IVPHELM_STATE",
    "IVPHELM_ALLSTOP",
    "IVPHELM_MODESET",
    "DESIRED_HEADING",
    "DESIRED_SPEED",
    "DESIRED_DEPTH",
    "DB_TIME",
    "DB_UPTIME",
    "DB_CLIENTS",
    "GPS_UPDATE_RECEIVED",
];

/// Behaviour parameters whose value names a variable the behaviour posts (besides every
/// `*_var` parameter other than `reset_var`, which is read).
pub const OUTPUT_VAR_PARAMS: &[&str] = &[
    "duration_status",
    "wpt_status",
    "wpt_index",
    "wpt_dist_to_prev",
    "wpt_dist_to_next",
    "var_status_idle",
    "var_status_running",
];

/// Whether the value of behaviour parameter `key` names a variable the behaviour posts.
///
/// ```
/// assert!(mission::catalog::names_output_var("WPT_STATUS_VAR"));
/// assert!(mission::catalog::names_output_var("wpt_dist_to_next"));
/// assert!(!mission::catalog::names_output_var("reset_var"));
/// assert!(!mission::catalog::names_output_var("mark_variable"));
/// ```
pub fn names_output_var(key: &str) -> bool {
    let k = param_name(key);
    (k.ends_with("_var") && k != "reset_var") || OUTPUT_VAR_PARAMS.contains(&k.as_str())
}

/// The programs whose `ProcessConfig` block coug reads line by line as MOOS `key = value`
/// lines: the MOOS core and essentials, every app of MOOS-IvP's `ivp/src` (a2a9b716) and its
/// deprecated apps. A block of any other program is kept (its `key = value` lines are
/// entries) but its other lines are not reported: such programs may read their block
/// themselves in another syntax (Goby's apps read protobuf text, `modem_id: 2`).
pub const MOOS_CONFIG_APPS: &[&str] = &[
    // MOOS core and essentials.
    "ANTLER",
    "MOOSDB",
    "pAntler",
    "pLogger",
    "pMOOSBridge",
    "pScheduler",
    "pShare",
    "iRemote",
    "iRemoteLite",
    "uMS",
    "uPoke",
    "uPlayBack",
    // MOOS-IvP.
    "iBlinkStick",
    "iSay",
    "pAutoPoke",
    "pBasicContactMgr",
    "pContactMgrV20",
    "pDeadManPost",
    "pEchoVar",
    "pHelmIvP",
    "pHostInfo",
    "pMapMarkers",
    "pMarinePID",
    "pMarinePIDV22",
    "pMarineViewer",
    "pMissionEval",
    "pMissionHash",
    "pNodeReporter",
    "pObstacleMgr",
    "pRealm",
    "pSearchGrid",
    "pSpoofNode",
    "pXRelay",
    "uCommand",
    "uFldBeaconRangeSensor",
    "uFldCollObDetect",
    "uFldCollisionDetect",
    "uFldContactRangeSensor",
    "uFldDelve",
    "uFldGenericSensor",
    "uFldMessageHandler",
    "uFldNodeBroker",
    "uFldNodeComms",
    "uFldObstacleSim",
    "uFldPathCheck",
    "uFldScope",
    "uFldShoreBroker",
    "uFunctionVis",
    "uHelmScope",
    "uLoadWatch",
    "uMAC",
    "uMACView",
    "uMayFinish",
    "uMemWatch",
    "uPlotViewer",
    "uPokeDB",
    "uProcessWatch",
    "uQueryDB",
    "uSimMarine",
    "uSimMarineV22",
    "uSimMarineV23",
    "uTermCommand",
    "uTimerScript",
    "uXMS",
];

/// Every parameter of uFldObstacleSim's block (MOOS-IvP a2a9b716 `ObstacleSim::OnStartUp`),
/// besides the AppCastingMOOSApp ones.
pub const OBSTACLE_SIM_PARAMS: &[&str] = &[
    "obstacle_file",
    "poly_vert_color",
    "poly_fill_color",
    "poly_edge_color",
    "poly_label_color",
    "poly_vert_size",
    "poly_edge_size",
    "poly_transparency",
    "draw_region",
    "region_edge_color",
    "region_vert_color",
    "post_points",
    "rate_points",
    "point_size",
    "sensor_range",
    "min_duration",
    "max_duration",
    "refresh_interval",
    "reset_interval",
    "reset_range",
    "reuse_ids",
    "post_visuals",
];

/// Whether coug reads the block of program `app` (a base name, case-insensitive) line by
/// line; see [`MOOS_CONFIG_APPS`].
///
/// ```
/// assert!(mission::catalog::reads_moos_config("uTimerScript"));
/// assert!(mission::catalog::reads_moos_config("phelmivp"));
/// assert!(!mission::catalog::reads_moos_config("pAcommsHandler"));
/// ```
pub fn reads_moos_config(app: &str) -> bool {
    MOOS_CONFIG_APPS.iter().any(|a| a.eq_ignore_ascii_case(app))
}

/// The `$(NAME)` macros uTimerScript expands itself in its event values (MOOS-IvP a2a9b716
/// `TS_MOOSApp`), besides `$(1)`..`$(20)` and the names of its `rand_var`/`rand_pair`s.
pub const TIMER_SCRIPT_MACROS: &[&str] = &[
    "DBTIME", "UTCTIME", "UTC", "COUNT", "TCOUNT", "NAV_X", "NAV_Y", "IDX",
];

/// The `$(NAME)` macros pMarineViewer expands itself when a mouse click posts a
/// `left_context`/`right_context` pair (MOOS-IvP a2a9b716 `PMV_Viewer`).
pub const VIEWER_CLICK_MACROS: &[&str] = &[
    "XPOS",
    "X",
    "YPOS",
    "Y",
    "IX",
    "BIX",
    "UTC",
    "LAT",
    "LON",
    "HDG",
    "VNAME",
    "UP_VNAME",
    "VNAME_CLOSEST",
    "UP_VNAME_CLOSEST",
];

/// The `$(NAME)` macros pMarineViewer expands itself in a button or action posting.
pub const VIEWER_BUTTON_MACROS: &[&str] = &["UTC", "BIX"];

/// Whether `$(name)` in the value of parameter `key` of a block of program `app` is a macro
/// the app expands at run time (not an nsplug macro). `block_vars` are the names the block
/// itself declares as random variables (uTimerScript's `rand_var = varname=ANG, ...`).
///
/// ```
/// use mission::catalog::is_runtime_macro;
/// assert!(is_runtime_macro("uTimerScript", "event", "COUNT", &[]));
/// assert!(is_runtime_macro("uTimerScript", "event", "7", &[]));
/// assert!(is_runtime_macro("uTimerScript", "event", "ANG", &["ANG".into()]));
/// assert!(is_runtime_macro("pMarineViewer", "left_context[pt]", "XPOS", &[]));
/// assert!(!is_runtime_macro("pMarineViewer", "button_one", "XPOS", &[]));
/// assert!(!is_runtime_macro("pNodeReporter", "platform_type", "COUNT", &[]));
/// ```
pub fn is_runtime_macro(app: &str, key: &str, name: &str, block_vars: &[String]) -> bool {
    let k = key.to_ascii_lowercase();
    if app.eq_ignore_ascii_case("uTimerScript") {
        TIMER_SCRIPT_MACROS.contains(&name)
            || name.parse::<u32>().is_ok_and(|n| (1..=20).contains(&n))
            || block_vars.iter().any(|v| v == name)
    } else if app.eq_ignore_ascii_case("pMarineViewer") {
        if k.starts_with("left_context") || k.starts_with("right_context") {
            VIEWER_CLICK_MACROS.contains(&name)
        } else {
            (k.starts_with("button") || k.starts_with("action"))
                && VIEWER_BUTTON_MACROS.contains(&name)
        }
    } else {
        false
    }
}
