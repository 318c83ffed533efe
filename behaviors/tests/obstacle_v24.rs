//! BHV_AvoidObstacleV24 against values worked out from MOOS-IvP's formulas
//! (`ObShipModelV24::evalHdgSpd`, `getRangeRelevance`, `polyRayCPA`, `bearingMinMaxToPoly`,
//! `BHV_AvoidObstacleV24::onRunState`/`getRelevance`, a2a9b716), its parameter rules and its
//! postings.
//!
//! The obstacle is the square x in [-5, 5], y in [20, 30] (`ob_1`); with
//! `min_util_cpa_dist = 4`, `max_util_cpa_dist = 8`, `pwt_inner_dist = 10`,
//! `pwt_outer_dist = 30`, `completed_dist = 40`. From the origin a heading `θ` east of the
//! square's corner (5, 20) passes that corner at `20 sin θ − 5 cos θ`.

use behaviors::testing::Probe;
use behaviors::{AvoidObstacleV24, Behavior, Common, Ctx, Emit, MapInfo, Out, ParamError};
use ivp::Domain;

const SQUARE: &str = "pts={-5,20:-5,30:5,30:5,20},label=ob_1";

fn domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
}

fn at(x: f64, y: f64, h: f64) -> MapInfo {
    MapInfo::new(100.0)
        .num("NAV_X", x)
        .num("NAV_Y", y)
        .num("NAV_HEADING", h)
        .num("NAV_SPEED", 2.0)
}

fn ctx<'a>(info: &'a MapInfo, d: &'a Domain) -> Ctx<'a> {
    Ctx {
        info,
        domain: d,
        ownship: "abe",
        name: "avd_ob_1",
        perpetual: false,
    }
}

fn set(b: &mut AvoidObstacleV24, k: &str, v: &str) -> Result<(), ParamError> {
    let d = domain();
    let info = MapInfo::new(0.0);
    b.set_param(
        k,
        v,
        &mut Common::new("BHV_AvoidObstacleV24"),
        &ctx(&info, &d),
    )
}

fn configured() -> AvoidObstacleV24 {
    let mut b = AvoidObstacleV24::new();
    for (k, v) in [
        ("poly", SQUARE),
        ("id", "ob_1"),
        ("min_util_cpa_dist", "4"),
        ("max_util_cpa_dist", "8"),
        ("allowable_ttc", "5"),
        ("pwt_inner_dist", "10"),
        ("pwt_outer_dist", "30"),
        ("completed_dist", "40"),
        ("holonomic_ok", "true"),
    ] {
        set(&mut b, k, v).unwrap();
    }
    b
}

fn run(b: &mut AvoidObstacleV24, info: &MapInfo) -> (Option<ivp::IvpFunction>, Out) {
    let d = domain();
    let mut out = Out::default();
    let f = b.on_run(&ctx(info, &d), &mut out);
    (f, out)
}

fn posts(out: &Out, var: &str) -> Vec<String> {
    out.emits
        .iter()
        .filter_map(|e| match e {
            Emit::Post { var: v, value, .. } if v == var => {
                Some(value.as_str().unwrap_or_default().to_string())
            }
            _ => None,
        })
        .collect()
}

#[test]
fn a_heading_is_worth_its_rays_closest_approach_between_the_utility_distances() {
    let mut b = configured();
    let (f, out) = run(&mut b, &at(0.0, 0.0, 0.0));
    assert!(out.error.is_none(), "{:?}", out);
    let f = f.expect("a function");
    let m = &b.model;
    assert_eq!(m.range, 20.0);
    // Dead ahead the ray meets the square.
    assert_eq!(m.eval_heading(0.0), 0.0);
    // 30°: 20·0.5 − 5·cos 30° = 5.6699 m: (5.6699 − 4) / (8 − 4) · 100 = 41.75.
    let e30 = (20.0 * 0.5 - 5.0 * 30f64.to_radians().cos() - 4.0) / 4.0 * 100.0;
    assert!((m.eval_heading(30.0) - e30).abs() < 1e-9);
    assert!((m.eval_heading(30.0) - 41.7468).abs() < 1e-3);
    // 25°: 3.920 m, inside min_util_cpa_dist: 0. 40°: 9.026 m, beyond max: 100.
    assert_eq!(m.eval_heading(25.0), 0.0);
    assert_eq!(m.eval_heading(40.0), 100.0);
    // Symmetric to the west.
    assert!((m.eval_heading(330.0) - e30).abs() < 1e-9);
    // East the closest approach is the bottom edge's 20 m.
    assert_eq!(m.eval_heading(90.0), 100.0);
    // The reflected function: near 0 over the blocked headings (the planes fitted to the
    // 3 x 3 pieces dip below 0 where a piece spans the edge of the blocked sector, and the
    // normalisation lifts them back to 0), 100 over the open ones, speed playing no part.
    let blocked = f.value_at(&[("course", 0.0), ("speed", 2.0)]).unwrap();
    assert!((0.0..1.0).contains(&blocked), "{blocked}");
    let open = f.value_at(&[("course", 90.0), ("speed", 0.0)]).unwrap();
    assert!(open > 99.0, "{open}");
    assert_eq!(f.value_at(&[("course", 180.0), ("speed", 4.0)]), Some(open));
    assert_eq!(f.max_val(), 100.0);
    assert!(blocked < open);
    // Relevance: 20 m between 10 and 30 is (30 − 20) / 20 = 0.5; the bearings bounding the
    // square wrap through north (345.96° to 14.04°): no heading discount.
    assert_eq!(b.relevance, 0.5);
    assert_eq!(b.pwt_factor(), 0.5);
    assert!(b.side_lock.is_empty());
}

#[test]
fn relevance_is_discounted_by_the_angle_to_the_nearer_bounding_bearing() {
    // From (20, 0) heading north: range to (5, 20) is 25 m, pct (30 − 25)/20 = 0.25; the
    // bearings run from 308.66° to 333.43° (= 360° − atan(15/30)), 26.57° off the heading:
    // 0.25 · cos 26.57° = 0.25 · 2/√5.
    let mut b = configured();
    let (f, _) = run(&mut b, &at(20.0, 0.0, 0.0));
    assert!(f.is_some());
    assert!(
        (b.relevance - 0.5 / 5f64.sqrt()).abs() < 1e-12,
        "{}",
        b.relevance
    );
}

#[test]
fn close_in_the_passing_side_locks() {
    // From (-1, 8): 12 m from the bottom edge, pct (30 − 12)/20 = 0.9 > 0.6; the square's
    // centre (0, 25) is 3.37° to starboard: the lock keeps it there.
    let mut b = configured();
    let (f, _) = run(&mut b, &at(-1.0, 8.0, 0.0));
    assert!(f.is_some());
    assert!((b.relevance - 0.9).abs() < 1e-12);
    assert_eq!(b.side_lock, "port");
    assert_eq!(b.model.passing_side, "star");
    // Heading 60° would put the centre to port: 0 with the lock. Without it the ray passes
    // (5, 20) at |6·cos 60° − 12·sin 60°| = 7.392 m: (7.392 − 4)/4 · 100 = 84.81.
    assert_eq!(b.model.eval_heading(60.0), 0.0);
    let mut m = b.model.clone();
    m.side_lock = false;
    let want = ((12.0 * 60f64.to_radians().sin() - 3.0) - 4.0) / 4.0 * 100.0;
    assert!((m.eval_heading(60.0) - want).abs() < 1e-9);
    // Turning west keeps the centre to starboard: allowed, far from the square.
    assert_eq!(b.model.eval_heading(270.0), 100.0);
}

#[test]
fn no_function_aft_and_completion_beyond_the_completed_distance_or_on_resolution() {
    // From (0, 40) heading north the square lies at relative bearings 153°..207°: aft.
    let mut b = configured();
    let (f, out) = run(&mut b, &at(0.0, 40.0, 0.0));
    assert!(f.is_none() && !out.completed);
    // From (0, -30): 50 m > 40: complete.
    let (f, out) = run(&mut b, &at(0.0, -30.0, 0.0));
    assert!(f.is_none() && out.completed);
    // The manager resolving our id completes it; another id does not.
    let mut b = configured();
    let (_, out) = run(&mut b, &at(0.0, 0.0, 0.0).text("OBM_RESOLVED", "ob_2"));
    assert!(!out.completed);
    assert_eq!(posts(&out, "NOTED_RESOLVED"), ["ob_2"]);
    let (_, out) = run(&mut b, &at(0.0, 0.0, 0.0).text("OBM_RESOLVED", "ob_1"));
    assert!(out.completed);
}

#[test]
fn a_breach_or_a_missing_utility_distance_is_an_allstop() {
    let mut b = configured();
    let (f, out) = run(&mut b, &at(0.0, 25.0, 0.0));
    assert!(f.is_none());
    assert_eq!(out.error.as_deref(), Some("Allstop: Obstacle Breached"));
    assert!(posts(&out, "BHV_WARNING").contains(
        &"avd_ob_1: Unable to init AOF_AvoidObstacleV24:m_obstacle contains osx,osy".to_string()
    ));
    // min_util_cpa_dist never set: the C++ AOF refuses to initialise.
    let mut b = AvoidObstacleV24::new();
    for (k, v) in [
        ("poly", SQUARE),
        ("max_util_cpa_dist", "8"),
        ("allowable_ttc", "5"),
    ] {
        set(&mut b, k, v).unwrap();
    }
    let (f, out) = run(&mut b, &at(0.0, 0.0, 0.0));
    assert!(f.is_none());
    assert_eq!(out.error.as_deref(), Some("Allstop: Obstacle Breached"));
    // And with allstop_on_breach = false a warning only.
    set(&mut b, "allstop_on_breach", "false").unwrap();
    let (_, out) = run(&mut b, &at(0.0, 0.0, 0.0));
    assert!(out.error.is_none());
    assert!(posts(&out, "BHV_WARNING").contains(&"avd_ob_1: Obstacle Breached".to_string()));
    // The holonomic model is warned about unless holonomic_ok.
    assert!(
        posts(&out, "BHV_WARNING")
            .iter()
            .any(|w| w.contains("holo plat_model not best"))
    );
}

#[test]
fn parameters_are_refused_as_the_cpp_refuses_them() {
    let mut b = AvoidObstacleV24::new();
    assert!(set(&mut b, "poly", "pts={0,0:10,10:10,0:0,10},label=bowtie").is_err());
    assert!(set(&mut b, "min_util_cpa_dist", "-1").is_err());
    assert!(set(&mut b, "max_util_cpa_dist", "far").is_err());
    assert!(set(&mut b, "allowable_ttc", "-2").is_err());
    // `atof` of text is 0: accepted.
    assert!(set(&mut b, "allowable_ttc", "soon").is_ok());
    assert_eq!(b.model.allowable_ttc, 0.0);
    assert!(matches!(
        set(&mut b, "pwt_grade", "linear"),
        Err(ParamError::Unknown { .. })
    ));
    assert!(matches!(
        set(&mut b, "buffer_dist", "3"),
        Err(ParamError::Unknown { .. })
    ));
    // The distances' order: an error only when the partner was set explicitly.
    let mut b = AvoidObstacleV24::new();
    set(&mut b, "completed_dist", "5").unwrap();
    assert_eq!((b.model.pwt_inner_dist, b.model.pwt_outer_dist), (5.0, 5.0));
    assert_eq!(
        set(&mut b, "pwt_outer_dist", "10"),
        Err(ParamError::bad(
            "pwt_outer_dist",
            "10",
            "pwt_outer_dist must be <= completed_dist"
        ))
    );
    let mut b = AvoidObstacleV24::new();
    set(&mut b, "max_util_cpa_dist", "5").unwrap();
    assert!(set(&mut b, "min_util_cpa_dist", "6").is_err());
    assert_eq!(b.model.max_util_cpa, 6.0);
    // The id is set once.
    set(&mut b, "id", "ob_1").unwrap();
    assert!(set(&mut b, "id", "ob_1").is_ok());
    assert!(set(&mut b, "obid", "ob_2").is_err());
    assert!(set(&mut AvoidObstacleV24::new(), "id", "a b").is_err());
    // Range flags: a bad threshold is refused, a bad flag after a good one ignored.
    assert!(set(&mut b, "rng_flag", "<near CLOSE=1").is_err());
    assert!(set(&mut b, "rng_flag", "<10 junk").is_ok());
    assert!(set(&mut b, "rng_flag", "").is_err());
    assert!(set(&mut b, "cpa_flag", "junk").is_err());
    assert!(set(&mut b, "visual_hints", "edge_color=bluish").is_err());
    assert!(set(&mut b, "holonomic_ok", "maybe").is_err());
}

#[test]
fn postings_alert_request_views_settings_and_flags() {
    let d = domain();
    let info = MapInfo::new(0.0);
    let c = Ctx {
        info: &info,
        domain: &d,
        ownship: "abe",
        name: "avd_obstacles_",
        perpetual: false,
    };
    let mut common = Common::new("BHV_AvoidObstacleV24");
    common.set_param("templating", "spawn").unwrap();
    common.set_param("updates", "OBSTACLE_ALERT").unwrap();
    let mut b = configured();
    b.set_common(&common);
    let mut out = Out::default();
    b.on_helm_start(&c, &mut out);
    assert_eq!(
        posts(&out, "OBM_ALERT_REQUEST"),
        ["name=avd_obstacles_,update_var=OBSTACLE_ALERT,alert_range=30"]
    );
    assert_eq!(
        b.config_status("avd").unwrap(),
        "type=BHV_AvoidObstacleV24,name=avd,allowable_ttc=5.00,min_util_cpa=4.00,\
         max_util_cpa=8.00,pwt_outer_dist=30.00,pwt_inner_dist=10.00,completed_dist=40.00"
    );
    set(&mut b, "rng_flag", "<25 NEAR = $[RNG]").unwrap();
    set(&mut b, "rng_flag", "<15 VERY_NEAR = $[OIDX]").unwrap();
    let (_, out) = run(&mut b, &at(0.0, 0.0, 0.0));
    let flags: Vec<&str> = out
        .emits
        .iter()
        .filter_map(|e| match e {
            Emit::Flag { flag, .. } => Some(flag.var.as_str()),
            _ => None,
        })
        .collect();
    assert_eq!(flags, ["NEAR"]);
    let mut s = String::new();
    assert!(b.macro_value("RNG", &mut s) && s == "20");
    s.clear();
    assert!(b.macro_value("OIDX", &mut s) && s == "1");
    let views = posts(&out, "VIEW_POLYGON");
    assert_eq!(
        views[0],
        "pts={-5,20:-5,30:5,30:5,20},label=ob_1,label_color=white,edge_color=gray50,\
         vertex_color=gray50,fill_color=gray60,vertex_size=0,edge_size=1"
    );
    assert!(views[1].contains("label=ob_1_mid_poly,") && views[1].contains("fill_color=gray70"));
    assert!(views[2].contains("label=ob_1_rim_poly,"));
    // Idle: erased.
    let mut out = Out::default();
    b.on_idle(&ctx(&at(0.0, 0.0, 0.0), &d), &mut out);
    assert_eq!(
        posts(&out, "VIEW_POLYGON"),
        [
            "pts={0,0:9,0:0,9},active=false,label=ob_1",
            "pts={0,0:9,0:0,9},active=false,label=ob_1_mid_poly",
            "pts={0,0:9,0:0,9},active=false,label=ob_1_rim_poly",
        ]
    );
}
