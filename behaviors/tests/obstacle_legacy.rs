//! BHV_AvoidObstacle, BHV_AvoidObstacleX and BHV_AvoidObstacleV21 against values worked out
//! from MOOS-IvP's formulas (`AOF_AvoidObstacle::evalBox`, `AOF_AvoidObstacleX::evalBox`, the
//! older `ObShipModel`, a2a9b716): one objective test per type pinning what makes it differ
//! from BHV_AvoidObstacleV24, and their parameter rules.
//!
//! The obstacle is the square x in [-5, 5], y in [20, 30] (`ob_1`).

use behaviors::{
    AvoidObstacle, AvoidObstacleV24, AvoidObstacleX, Behavior, Common, Ctx, Emit, MapInfo, Out,
    ParamError,
};
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

fn set<B: Behavior>(b: &mut B, k: &str, v: &str) -> Result<(), ParamError> {
    let d = domain();
    let info = MapInfo::new(0.0);
    b.set_param(k, v, &mut Common::new(b.kind()), &ctx(&info, &d))
}

fn configure<B: Behavior>(b: &mut B, params: &[(&str, &str)]) {
    for (k, v) in params {
        set(b, k, v).unwrap_or_else(|e| panic!("{k}={v}: {e}"));
    }
}

const MODEL: [(&str, &str); 7] = [
    ("poly", SQUARE),
    ("min_util_cpa_dist", "4"),
    ("max_util_cpa_dist", "8"),
    ("allowable_ttc", "5"),
    ("pwt_inner_dist", "10"),
    ("pwt_outer_dist", "30"),
    ("completed_dist", "40"),
];

fn run<B: Behavior>(b: &mut B, info: &MapInfo) -> (Option<ivp::IvpFunction>, Out) {
    let d = domain();
    let mut out = Out::default();
    let f = b.on_run(&ctx(info, &d), &mut out);
    (f, out)
}

fn posted(out: &Out, var: &str) -> Vec<String> {
    out.emits
        .iter()
        .filter_map(|e| match e {
            Emit::Post { var: v, value, .. } if v == var => Some(match value.as_str() {
                Some(s) => s.to_string(),
                None => format!("{}", value.as_ref().as_f64().unwrap_or(f64::NAN)),
            }),
            _ => None,
        })
        .collect()
}

#[test]
fn x_penalises_the_basin_toward_the_obstacle_side_and_lets_slow_speeds_through() {
    // From (-1, 0) heading north the square's centre (0, 25) is 2.29° to starboard: the
    // basin runs from that bearing round to θ_b = ownship's reciprocal heading (180°),
    // since 92.29° (the centre's bearing + 90°) leaves 180° outside the arc.
    let mut x = AvoidObstacleX::new();
    configure(&mut x, &MODEL);
    let (f, out) = run(&mut x, &at(-1.0, 0.0, 0.0));
    assert!(f.is_some(), "{out:?}");
    assert_eq!(x.model.m.passing_side, "star");
    assert_eq!(x.model.theta_b, 180.0);
    // Heading 90 clears the square by far, yet it is in the basin: 20 (V24 gives 100).
    assert_eq!(x.model.eval(90.0, 2.0), 20.0);
    let mut v24 = AvoidObstacleV24::new();
    configure(&mut v24, &MODEL);
    run(&mut v24, &at(-1.0, 0.0, 0.0));
    assert_eq!(v24.model.eval_heading(90.0), 100.0);
    // Heading 300 misses the outer buffer's bearings: 100.
    assert_eq!(x.model.eval(300.0, 2.0), 100.0);
    // Heading 350 meets the square (at y = 20, x = -1 − 20·tan 10° = -4.53). At 2 m/s
    // ownship is slower than the outer buffer's range (about 12 m) over allowable_ttc
    // (5 s): 100; at 3 m/s the ray's closest approach 0 is within min_util_cpa_dist: 0.
    // V24 gives 0 at any speed.
    assert_eq!(x.model.eval(350.0, 2.0), 100.0);
    assert_eq!(x.model.eval(350.0, 3.0), 0.0);
    assert_eq!(v24.model.eval_heading(350.0), 0.0);
    // Relevance: linear, no heading discount: (30 − 20)/20.
    assert_eq!(x.relevance, 0.5);
    assert_eq!(posted(&out, "OS_DIST_TO_POLY"), ["20"]);
}

#[test]
fn v21_is_x_s_objective_judged_every_iteration_with_flags_and_five_decimals() {
    let mut x = AvoidObstacleX::new();
    configure(&mut x, &MODEL);
    let mut v21 = AvoidObstacleX::v21();
    assert_eq!(v21.kind(), "BHV_AvoidObstacleV21");
    configure(&mut v21, &MODEL);
    set(&mut v21, "rng_flag", "<25 NEAR = $[RNG]").unwrap();
    let info = at(-1.0, 0.0, 0.0);
    let (fx, outx) = run(&mut x, &info);
    let (fv, outv) = run(&mut v21, &info);
    // The same objective function.
    let (fx, fv) = (fx.unwrap(), fv.unwrap());
    assert_eq!(fx.piece_count(), fv.piece_count());
    for c in [0.0, 45.0, 90.0, 300.0, 350.0] {
        for s in [1.0, 3.0] {
            assert_eq!(
                x.model.eval(c, s),
                v21.model.eval(c, s),
                "course {c} speed {s}"
            );
        }
    }
    // V21 posts its polygons with 5 decimals, X with 3.
    let vx = posted(&outx, "VIEW_POLYGON");
    let vv = posted(&outv, "VIEW_POLYGON");
    assert!(vx[1].contains("label=ob_1_buff_min") && vv[1].contains("label=ob_1_buff_min"));
    let decimals = |s: &str| {
        s.split(['{', ',', ':', '}'])
            .filter_map(|t| t.split_once('.').map(|(_, d)| d.len()))
            .max()
            .unwrap_or(0)
    };
    assert_eq!(decimals(&vx[1]), 3, "{}", vx[1]);
    assert_eq!(decimals(&vv[1]), 5, "{}", vv[1]);
    // Idle, V21 still judges the model: the range and its flag (X posts neither).
    let d = domain();
    let (mut ox, mut ov) = (Out::default(), Out::default());
    x.on_idle(&ctx(&info, &d), &mut ox);
    v21.on_idle(&ctx(&info, &d), &mut ov);
    assert!(posted(&ox, "OS_DIST_TO_POLY").is_empty());
    assert_eq!(posted(&ov, "OS_DIST_TO_POLY"), ["20"]);
    assert!(
        ov.emits
            .iter()
            .any(|e| matches!(e, Emit::Flag { flag, .. } if flag.var == "NEAR"))
    );
    // Config status names: the C++ X writes `BHV_AvoidObstacleXs`.
    assert!(
        x.config_status("a")
            .unwrap()
            .starts_with("type=BHV_AvoidObstacleXs,name=a,")
    );
    assert!(
        v21.config_status("a")
            .unwrap()
            .starts_with("type=BHV_AvoidObstacleV21,name=a,")
    );
}

#[test]
fn avoid_obstacle_is_all_or_nothing_on_time_to_its_buffer_and_the_passing_side() {
    let mut b = AvoidObstacle::new();
    configure(
        &mut b,
        &[
            ("poly", SQUARE),
            ("allowable_ttc", "5"),
            ("pwt_inner_dist", "10"),
            ("pwt_outer_dist", "30"),
            ("completed_dist", "40"),
        ],
    );
    // No buffer: no function at all.
    let (f, _) = run(&mut b, &at(0.0, 0.0, 0.0));
    assert!(f.is_none());
    set(&mut b, "buffer_dist", "5").unwrap();
    let (f, out) = run(&mut b, &at(0.0, 0.0, 0.0));
    assert!(f.is_some(), "{out:?}");
    assert_eq!(b.relevance, 0.5);
    let buff = b.buff.clone().unwrap();
    // The buffer's near edge is 15 m off: at 4 m/s 3.75 s (within 5 s) along a heading that
    // meets it: 0; at 2 m/s 7.5 s: 100. V24 gives 0 dead ahead at any speed.
    assert_eq!(b.eval(&buff, 0.0, 4.0), 0.0);
    assert_eq!(b.eval(&buff, 0.0, 2.0), 100.0);
    // Heading 90 puts the centre (dead ahead now) to port: 0 though it misses.
    assert_eq!(b.eval(&buff, 90.0, 4.0), 0.0);
    // Heading 270 keeps it to starboard and misses: 100.
    assert_eq!(b.eval(&buff, 270.0, 4.0), 100.0);
    let views = posted(&out, "VIEW_POLYGON");
    assert!(views[0].starts_with("pts={-5,20:-5,30:5,30:5,20},label=ob_1,edge_color=white,vertex_color=pink,fill_color=gray60"));
    assert!(views[1].contains("label=ob_1_buff"));
    // Beyond completed_dist: complete, posting OBSTACLE_RESOLVED on completion.
    let (f, out) = run(&mut b, &at(0.0, -30.0, 0.0));
    assert!(f.is_none() && out.completed);
}

#[test]
fn the_old_types_refuse_parameters_as_the_cpp_does() {
    let mut b = AvoidObstacle::new();
    assert!(matches!(
        set(&mut b, "id", "ob_1"),
        Err(ParamError::Unknown { .. })
    ));
    assert!(set(&mut b, "buffer_dist", "-1").is_err());
    set(&mut b, "pwt_outer_dist", "30").unwrap();
    // completed_dist must exceed pwt_outer_dist once that is set.
    assert!(set(&mut b, "completed_dist", "30").is_err());
    assert_eq!(b.completed_dist, 31.0);
    assert!(
        set(
            &mut b,
            "visual_hints",
            "obstacle_edge_color=red, buffer_fill_transparency=0.3"
        )
        .is_ok()
    );
    assert!(set(&mut b, "visual_hints", "edge_color=red").is_err());
    let mut x = AvoidObstacleX::new();
    assert!(set(&mut x, "resolved", "true").is_ok());
    assert!(matches!(
        set(&mut x, "rng_flag", "A=1"),
        Err(ParamError::Unknown { .. })
    ));
    set(&mut x, "id", "a").unwrap();
    assert!(set(&mut x, "id", "b").is_ok(), "X may change its id");
    // The C++ stops at the first colour of a list: the second hint is never read.
    assert!(
        set(
            &mut x,
            "visual_hints",
            "obstacle_edge_color=red, nonsense=1"
        )
        .is_ok()
    );
    let mut v21 = AvoidObstacleX::v21();
    assert!(matches!(
        set(&mut v21, "resolved", "true"),
        Err(ParamError::Unknown { .. })
    ));
    set(&mut v21, "id", "a").unwrap();
    assert!(set(&mut v21, "id", "b").is_err(), "V21 sets its id once");
    assert!(set(&mut v21, "rng_flag", "<x A=1").is_err());
}

/// The distance from `(x, y)` to the polygon's vertices as an open path (MOOS
/// `XYSegList::dist_to_point`, which `XYPolygon` inherits).
fn open_path_dist(p: &geometry::Polygon, x: f64, y: f64) -> f64 {
    p.vertices()
        .windows(2)
        .map(|w| geometry::segment::dist_point_to_segment(w[0].x, w[0].y, w[1].x, w[1].y, x, y))
        .fold(f64::INFINITY, f64::min)
}

fn region_of<'a>(f: &'a ivp::IvpFunction, lo: [u32; 2], hi: [u32; 2]) -> Option<ivp::Piece<'a>> {
    f.pieces().find(|p| p.lo == lo && p.hi == hi)
}

#[test]
fn x_and_v21_refinery_makes_the_older_plateaus_and_basins() {
    // RefineryObAvoid from (-1, 0) heading north (passing the square to starboard, as in
    // the first test): the major basin runs from the centre's bearing 2.29° (snapped up:
    // 3) to θ_b = 180 (snapped down), value -5, every speed; the major plateau from the
    // outer buffer's greatest bearing (up) round to its least (down), value 4; the minor
    // plateau every course below the speed reaching the outer buffer in allowable_ttc
    // (snapped down), value 2; the minor basin the square's bearings 348.69° (to (-5, 20))
    // to 16.70° (to (5, 20)), each rounded up (349, 17), at speeds from the farther
    // vertex's 20.88 m / 5 s = 4.18 m/s (up: past the top, so 4.0) to the top, value -4.
    // makeRegionsApart keeps the larger magnitude's overlaps.
    for v21 in [false, true] {
        let mut x = if v21 {
            AvoidObstacleX::v21()
        } else {
            AvoidObstacleX::new()
        };
        configure(&mut x, &MODEL);
        set(&mut x, "use_refinery", "true").unwrap();
        let (f, out) = run(&mut x, &at(-1.0, 0.0, 0.0));
        let f = f.unwrap_or_else(|| panic!("{out:?}"));
        assert_eq!((x.model.m.passing_side, x.model.theta_b), ("star", 180.0));
        let (cmin, cmax) = (x.model.cpa_bng.0, x.model.cpa_bng.1);
        assert!(cmax < 90.0 && cmin > 270.0, "{cmin} {cmax}");
        let (p_lo, p_hi) = (cmax.ceil() as u32, cmin.floor() as u32);
        let spd_top = (open_path_dist(&x.model.m.rim, -1.0, 0.0) / 5.0 * 10.0).floor() as u32;
        assert!((20..=26).contains(&spd_top), "{spd_top}");
        let constant = |lo: [u32; 2], hi: [u32; 2], want: f64| {
            let p = region_of(&f, lo, hi).unwrap_or_else(|| panic!("{lo:?} {hi:?}"));
            assert_eq!(p.wts, [0.0, 0.0, want], "{lo:?} {hi:?}");
        };
        // The major basin, whole; the plateau beyond it.
        constant([3, 0], [180, 40], 0.0);
        constant([181, 0], [p_hi, 40], 100.0);
        assert!(
            (3..=180).contains(&p_lo),
            "the plateau begins in the basin: {p_lo}"
        );
        // The minor basin at the top speed: its west part whole, its east part outside
        // the major basin.
        constant([349, 40], [359, 40], 0.0);
        constant([0, 40], [2, 40], 0.0);
        // The minor plateau: every course below spd_top outside the regions above: courses
        // 0-2 and those between the plateau and the minor basin.
        let slow = f
            .pieces()
            .filter(|p| p.wts == [0.0, 0.0, 100.0] && p.hi[1] == spd_top && p.lo[1] == 0)
            .count();
        assert!(slow >= 2, "minor plateau pieces");
        for c in [0u32, 1, 2, p_hi + 1, 340] {
            assert_eq!(f.eval(&[c, spd_top]).unwrap(), 100.0, "course {c}");
            assert_eq!(x.model.eval(f64::from(c), f64::from(spd_top) / 10.0), 100.0);
        }
        // The regions hold where the AOF is flat: 100 on the plateaus; the basins take
        // the AOF's known minimum 0, where AOF_AvoidObstacleX gives 20 in the major basin
        // (the C++ does too) and 0 in the minor one (4 m/s is below the 4.18 that the
        // AOF's own 20 needs; the ray meets the square: CPA 0).
        for (c, s, aof) in [
            (90u32, 20u32, 20.0),
            (180, 0, 20.0),
            (0, 40, 0.0),
            (355, 40, 0.0),
        ] {
            assert_eq!(x.model.eval(f64::from(c), f64::from(s) / 10.0), aof);
            assert_eq!(f.eval(&[c, s]).unwrap(), 0.0);
        }
        for (c, s) in [(200u32, 40u32), (p_hi, 10)] {
            assert_eq!(x.model.eval(f64::from(c), f64::from(s) / 10.0), 100.0);
        }
        for c in 0..360u32 {
            for s in 0..41u32 {
                assert_eq!(f.pieces().filter(|p| p.contains(&[c, s])).count(), 1);
            }
        }
    }
}
