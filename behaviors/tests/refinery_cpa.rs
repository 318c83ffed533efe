//! `use_refinery`, `check_plateaus`, `check_validity`, `pcheck_thresh` and `verbose` on
//! BHV_AvoidCollision and BHV_AvdColregsV19/V22/V26 (MOOS-IvP a2a9b716: `getAvoidIPF`,
//! `buildCPA_IPF`, `RefineryCPA`, `OF_Reflector::checkPlateaus`/`checkBasins`): the refined
//! function against the uniform one, its pieces against the refinery's regions, and the
//! postings with their repeat rules.

use behaviors::colregs::{AvdColregs, Version};
use behaviors::contact::ContactInfo;
use behaviors::refinery_cpa::covers_once;
use behaviors::testing::Probe;
use behaviors::{AvoidCollision, Behavior, Common, Ctx, Emit, MapInfo, Out, PostKey, Value};
use ivp::{Domain, IvpFunction, RegionBox};

fn domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
}

/// Ownship at `os = (x, y, heading, speed)`, the contact `cn` at `cn`.
fn info(os: (f64, f64, f64, f64), cn: (f64, f64, f64, f64)) -> MapInfo {
    MapInfo::new(100.0)
        .num("NAV_X", os.0)
        .num("NAV_Y", os.1)
        .num("NAV_HEADING", os.2)
        .num("NAV_SPEED", os.3)
        .with_contact(
            "cn",
            ContactInfo {
                x_m: cn.0,
                y_m: cn.1,
                heading_deg: cn.2,
                speed_mps: cn.3,
                utc: 100.0,
                vtype: "kayak".into(),
                ..ContactInfo::default()
            },
        )
}

fn ctx<'a>(info: &'a MapInfo, d: &'a Domain) -> Ctx<'a> {
    Ctx {
        info,
        domain: d,
        ownship: "abe",
        name: "avd_cn",
        perpetual: false,
    }
}

fn configure<B: Behavior>(b: &mut B, params: &[(&str, &str)]) {
    let d = domain();
    let inf = MapInfo::new(0.0);
    let mut common = Common::new(b.kind());
    b.set_param("contact", "cn", &mut common, &ctx(&inf, &d))
        .unwrap();
    for (k, v) in params {
        b.set_param(k, v, &mut common, &ctx(&inf, &d))
            .unwrap_or_else(|e| panic!("{k} = {v}: {e}"));
    }
}

/// The avoidance settings of the refinery's unit tests: time on leg 60 s, 10 m, 30 m.
const AVOID: &[(&str, &str)] = &[
    ("time_on_leg", "60"),
    ("min_util_cpa_dist", "10"),
    ("max_util_cpa_dist", "30"),
    ("pwt_outer_dist", "300"),
];

fn avoid(extra: &[(&str, &str)]) -> AvoidCollision {
    let mut b = AvoidCollision::new();
    configure(&mut b, AVOID);
    configure(&mut b, extra);
    b
}

fn run<B: Behavior>(
    b: &mut B,
    os: (f64, f64, f64, f64),
    cn: (f64, f64, f64, f64),
) -> (Option<IvpFunction>, Out) {
    let d = domain();
    let inf = info(os, cn);
    let mut out = Out::default();
    let f = b.on_run(&ctx(&inf, &d), &mut out);
    (f, out)
}

/// Every posting of `var`: its value and key.
fn posts(out: &Out, var: &str) -> Vec<(Value, PostKey)> {
    out.emits
        .iter()
        .filter_map(|e| match e {
            Emit::Post { var: v, value, key } if v == var => Some((value.clone(), key.clone())),
            _ => None,
        })
        .collect()
}

fn text(v: &str) -> Value {
    Value::String(v.into())
}

/// A vehicle's x, y, heading and speed.
type Pose = (f64, f64, f64, f64);

/// The geometries of the refinery's unit tests, ownship heading north at 2 m/s.
const CROSSING: (Pose, Pose) = ((0.0, 0.0, 0.0, 2.0), (100.0, 100.0, 270.0, 1.0));
const HEAD_ON: (Pose, Pose) = ((0.0, 0.0, 0.0, 2.0), (0.0, 100.0, 180.0, 1.0));
const OVERTAKING: (Pose, Pose) = ((0.0, 0.0, 0.0, 2.0), (0.0, 100.0, 0.0, 1.0));

/// The grid point `(course, speed)` of the function's maximum.
fn argmax_ix(f: &IvpFunction) -> (i64, i64) {
    let (c, s) = f.argmax2("course", "speed");
    (c.round() as i64, (s * 10.0).round() as i64)
}

fn points_of(r: &RegionBox) -> impl Iterator<Item = [u32; 2]> + '_ {
    (r.lo[0]..=r.hi[0]).flat_map(move |c| (r.lo[1]..=r.hi[1]).map(move |s| [c, s]))
}

#[test]
fn the_refined_function_keeps_the_argmax_and_its_plateau_pieces_are_the_regions() {
    let d = domain();
    for (name, (os, cn)) in [
        ("crossing", CROSSING),
        ("head-on", HEAD_ON),
        ("overtaking", OVERTAKING),
    ] {
        let plain = run(&mut avoid(&[]), os, cn).0.unwrap();
        let mut b = avoid(&[("use_refinery", "true")]);
        let refined = run(&mut b, os, cn).0.unwrap();
        // The maximum's grid point stays a maximum: the refined function is at its maximum
        // there too (the plateau pieces tie with it at 100, so the refined argmax itself
        // may be any of their points).
        let a = argmax_ix(&plain);
        let at_a = refined.eval(&[a.0 as u32, a.1 as u32]).unwrap();
        assert!(
            (refined.max_val() - at_a).abs() < 1e-9 && (plain.max_val() - at_a).abs() < 1e-9,
            "{name}: {a:?} is {at_a}, the maximum {} ({})",
            refined.max_val(),
            plain.max_val()
        );
        assert!(covers_once(&refined), "{name}");
        // The pieces made of the regions: at the function's maximum (100 after the
        // normalisation: the AOF's known maximum, the utility of the present range), flat,
        // and exactly the regions' points.
        let inf = info(os, cn);
        let (raw, found) = b.objective_refined(&ctx(&inf, &d)).unwrap();
        assert!(!found.regions.is_empty(), "{name}");
        let mut in_regions = std::collections::BTreeSet::new();
        for r in &found.regions {
            in_regions.extend(points_of(r));
        }
        let mut in_flat_pieces = std::collections::BTreeSet::new();
        for p in raw.pieces() {
            let flat = p.wts[..2].iter().all(|w| *w == 0.0) && p.intercept() == 100.0;
            let r = RegionBox {
                lo: p.lo.to_vec(),
                hi: p.hi.to_vec(),
                plat: 0,
            };
            let inside = points_of(&r).filter(|pt| in_regions.contains(pt)).count();
            if inside > 0 {
                // A piece meeting a region lies wholly inside the regions and is a plateau.
                assert_eq!(inside as u64, r.size(), "{name}: piece {r:?}");
                assert!(flat, "{name}: piece {r:?} not flat at 100");
                in_flat_pieces.extend(points_of(&r));
            }
        }
        assert_eq!(in_flat_pieces, in_regions, "{name}");
        // And the plain function agrees on the plateaus: 100 wherever every corner of its
        // 3 x 3 piece is clear, never more.
        for pt in &in_regions {
            let v = plain.eval(pt).unwrap();
            assert!(v <= 100.0 + 1e-9, "{name} {pt:?}: {v}");
        }
    }
}

#[test]
fn the_refinery_counts_its_queries_and_names_its_case() {
    let d = domain();
    let (os, cn) = HEAD_ON;
    let inf = info(os, cn);
    let mut b = avoid(&[("use_refinery", "true")]);
    run(&mut b, os, cn).0.unwrap();
    let (_, found) = b.objective_refined(&ctx(&inf, &d)).unwrap();
    // The refinery's head-on unit case: 41 + 41 + 1 + 44 + 44 queries, one wedge.
    assert_eq!(found.logic_case, "fore_in_rgam");
    assert_eq!(found.cpa_queries, 171);
    assert_eq!(found.regions.len(), 1);
    assert_eq!(
        (found.regions[0].lo.clone(), found.regions[0].hi.clone()),
        (vec![43, 8], vec![317, 40])
    );
}

#[test]
fn avoid_collision_posts_its_checks_as_the_cpp() {
    let (os, cn) = CROSSING;
    // check_plateaus without verbose: the plateaus hold, nothing is posted.
    let mut b = avoid(&[("use_refinery", "true"), ("check_plateaus", "true")]);
    let (_, out) = run(&mut b, os, cn);
    for var in [
        "PLATEAU_CHECK_OK",
        "PLATEAU_LOGIC_CASE",
        "PLATEAU_WORST_FAIL",
        "BASIN_CHECK_OK",
        "VALID_CHECK_OK",
    ] {
        assert!(posts(&out, var).is_empty(), "{var}");
    }
    // With verbose: PLATEAU_CHECK_OK (on change) and the logic case (repeatable); AvoidCollision
    // checks no basins.
    let mut b = avoid(&[
        ("use_refinery", "true"),
        ("check_plateaus", "true"),
        ("verbose", "true"),
        ("check_validity", "true"),
    ]);
    let (_, out) = run(&mut b, os, cn);
    assert_eq!(
        posts(&out, "PLATEAU_CHECK_OK"),
        [(text("true"), PostKey::Var)]
    );
    assert_eq!(
        posts(&out, "PLATEAU_LOGIC_CASE"),
        [(text("fore_out_rgam"), PostKey::Repeatable)]
    );
    assert!(posts(&out, "PLATEAU_WORST_FAIL").is_empty());
    assert!(posts(&out, "BASIN_CHECK_OK").is_empty());
    assert_eq!(
        posts(&out, "VALID_CHECK_OK"),
        [(text("true"), PostKey::Var)]
    );
    // pcheck_thresh beyond 1: the reflector's warning on AVD_DEBUG after the relevance one,
    // the check run with its default threshold.
    let mut b = avoid(&[
        ("use_refinery", "true"),
        ("check_plateaus", "true"),
        ("pcheck_thresh", "2"),
    ]);
    let (_, out) = run(&mut b, os, cn);
    let dbg = posts(&out, "AVD_DEBUG");
    assert_eq!(dbg.len(), 2);
    assert_eq!(dbg[1].0, text("pcheck_thresh value must be in range [0,1]"));
    // check_validity alone (no refinery): the uniform pieces cover the domain once.
    let mut b = avoid(&[("check_validity", "true")]);
    let (_, out) = run(&mut b, os, cn);
    assert_eq!(
        posts(&out, "VALID_CHECK_OK"),
        [(text("true"), PostKey::Var)]
    );
    // Refused values, as setBooleanOnString / setNonNegDoubleOnString refuse them.
    let mut b = AvoidCollision::new();
    let d = domain();
    let inf = MapInfo::new(0.0);
    let mut common = Common::new("BHV_AvoidCollision");
    for (k, v) in [
        ("use_refinery", "maybe"),
        ("check_plateaus", "1"),
        ("pcheck_thresh", "-0.5"),
        ("pcheck_thresh", "abc"),
    ] {
        assert!(
            b.set_param(k, v, &mut common, &ctx(&inf, &d)).is_err(),
            "{k} = {v}"
        );
    }
}

#[test]
fn the_colregs_versions_refine_their_cpa_function_and_post_both_checks() {
    // The crossing geometry with ownship heading south: the contact on its port quarter,
    // passing north of it, fits no rule: the catch-all CPA mode.
    let (_, cn) = CROSSING;
    let os = (0.0, 0.0, 180.0, 2.0);
    for version in [Version::V19, Version::V22, Version::V26] {
        // The time on leg at its default, 120 s, the AOF_CPA's fixed one in V19 and V22 (with
        // another, their refinery's regions are found for a function they do not build).
        let params = [
            ("min_util_cpa_dist", "10"),
            ("max_util_cpa_dist", "30"),
            ("pwt_outer_dist", "300"),
            ("completed_dist", "300"),
            ("avoid_mode", "cpa"),
        ];
        let mut plain = AvdColregs::new(version);
        configure(&mut plain, &params);
        let (pf, pout) = run(&mut plain, os, cn);
        let pf = pf.expect("a CPA function");
        assert_eq!(plain.mode, "cpa", "{version:?}");
        assert!(posts(&pout, "PLATEAU_CHECK_OK").is_empty());
        let mut b = AvdColregs::new(version);
        configure(&mut b, &params);
        configure(
            &mut b,
            &[("use_refinery", "true"), ("check_plateaus", "true")],
        );
        let (f, out) = run(&mut b, os, cn);
        let f = f.expect("a refined CPA function");
        assert!(covers_once(&f));
        // More pieces than the 120 x 14 uniform ones: the regions cut them.
        assert_ne!(f.piece_count(), pf.piece_count(), "{version:?}");
        let (a, z) = (argmax_ix(&pf), argmax_ix(&f));
        let dc = (a.0 - z.0).rem_euclid(360).min((z.0 - a.0).rem_euclid(360));
        assert!(
            dc <= 1 && (a.1 - z.1).abs() <= 1,
            "{version:?}: {a:?} vs {z:?}"
        );
        // AOF_CPA does not know its extremes: the plateau check answers 1 (fails) whenever
        // there is a region, the basin check 0 (no basin); verbose or not.
        assert_eq!(
            posts(&out, "PLATEAU_CHECK_OK"),
            [(text("false"), PostKey::Var)]
        );
        assert_eq!(
            posts(&out, "BASIN_CHECK_OK"),
            [(text("true"), PostKey::Var)]
        );
        assert_eq!(
            posts(&out, "PLATEAU_LOGIC_CASE"),
            [(text("fore_out_rgam"), PostKey::Repeatable)]
        );
        assert_eq!(
            posts(&out, "PLATEAU_WORST_FAIL"),
            [(Value::Double(1.0), PostKey::Repeatable)]
        );
        // Without check_plateaus nothing is posted.
        let mut quiet = AvdColregs::new(version);
        configure(&mut quiet, &params);
        configure(&mut quiet, &[("use_refinery", "true")]);
        let (_, out) = run(&mut quiet, os, cn);
        assert!(posts(&out, "PLATEAU_LOGIC_CASE").is_empty());
    }
    // V17 refuses the parameters.
    let mut v17 = AvdColregs::new(Version::V17);
    let d = domain();
    let inf = MapInfo::new(0.0);
    let mut common = Common::new(v17.kind());
    assert!(
        v17.set_param("use_refinery", "true", &mut common, &ctx(&inf, &d))
            .is_err()
    );
}

#[test]
fn cut_range_has_no_refinery_parameter() {
    // BHV_CutRange includes RefineryCPA.h at a2a9b716 but neither reads nor uses it.
    let mut b = behaviors::create("BHV_CutRange").unwrap();
    let d = domain();
    let inf = MapInfo::new(0.0);
    let mut common = Common::new("BHV_CutRange");
    for k in ["use_refinery", "check_plateaus", "pcheck_thresh"] {
        assert!(
            b.set_param(k, "true", &mut common, &ctx(&inf, &d)).is_err(),
            "{k}"
        );
    }
}
