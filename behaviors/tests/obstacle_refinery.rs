//! BHV_AvoidObstacleV24 with `use_refinery = true` against the C++ refinery
//! (`RefineryObAvoidV24`, `ObShipModelV24::setBngMinMaxToRimPoly`/`...GutPoly`,
//! `buildBoxesSpdAll`, `makeRegionsApart`, `RT_UniformX`, `Regressor::setWeight1` at
//! a2a9b716).
//!
//! Ownship at the origin heading north; the obstacle the square x in [-5, 5], y in [20, 30];
//! `min_util_cpa_dist = 4`, `max_util_cpa_dist = 8`. With the holonomic platform model a
//! heading's ray hits a convex polygon (CPA 0) exactly when the heading lies within the
//! polygon's span of bearings from ownship. The square spans 345.96° (corner (-5, 20)) to
//! 14.04° (corner (5, 20)): headings 346..359 and 0..14 hit it, and the gut span is
//! `(345, 15)`, the headings just outside (the C++ takes the neighbours of the hit span).
//! The rim (the square grown by 8) spans the bearings of its extreme vertices: the clear
//! span is from the first whole degree above its greatest bearing east of north to the last
//! below its least bearing west of north.

use behaviors::testing::Probe;
use behaviors::{AvoidObstacleV24, Behavior, Common, Ctx, MapInfo, Out};
use ivp::Domain;

fn domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
}

fn behaviour(refinery: bool) -> AvoidObstacleV24 {
    let d = domain();
    let info = MapInfo::new(0.0);
    let ctx = Ctx {
        info: &info,
        domain: &d,
        ownship: "abe",
        name: "avd_ob_1",
        perpetual: false,
    };
    let mut b = AvoidObstacleV24::new();
    for (k, v) in [
        ("poly", "pts={-5,20:-5,30:5,30:5,20},label=ob_1"),
        ("id", "ob_1"),
        ("min_util_cpa_dist", "4"),
        ("max_util_cpa_dist", "8"),
        ("allowable_ttc", "5"),
        ("pwt_inner_dist", "10"),
        ("pwt_outer_dist", "30"),
        ("completed_dist", "40"),
        ("holonomic_ok", "true"),
        ("use_refinery", if refinery { "true" } else { "false" }),
    ] {
        b.set_param(k, v, &mut Common::new("BHV_AvoidObstacleV24"), &ctx)
            .unwrap();
    }
    b
}

fn run(b: &mut AvoidObstacleV24) -> ivp::IvpFunction {
    run_at(b, 0.0, 0.0)
}

/// One running iteration with ownship at `(x, y)` heading north at 2 m/s.
fn run_at(b: &mut AvoidObstacleV24, x: f64, y: f64) -> ivp::IvpFunction {
    let d = domain();
    let info = MapInfo::new(100.0)
        .num("NAV_X", x)
        .num("NAV_Y", y)
        .num("NAV_HEADING", 0.0)
        .num("NAV_SPEED", 2.0);
    let ctx = Ctx {
        info: &info,
        domain: &d,
        ownship: "abe",
        name: "avd_ob_1",
        perpetual: false,
    };
    let mut out = Out::default();
    b.on_run(&ctx, &mut out).expect("a function")
}

/// The whole-degree headings clearing the rim, from its vertices' bearings seen from
/// ownship (the rim spanning north).
fn rim_span(b: &AvoidObstacleV24) -> (u32, u32) {
    let (x, y, _, _) = b.model.pose.unwrap();
    let bngs: Vec<f64> = b
        .model
        .rim
        .vertices()
        .iter()
        .map(|p| geometry::relative_angle(x, y, p.x, p.y))
        .collect();
    let east = bngs
        .iter()
        .copied()
        .filter(|a| *a < 180.0)
        .fold(0.0, f64::max);
    let west = bngs
        .iter()
        .copied()
        .filter(|a| *a >= 180.0)
        .fold(360.0, f64::min);
    (east.floor() as u32 + 1, west.ceil() as u32 - 1)
}

fn boxes(f: &ivp::IvpFunction) -> Vec<(Vec<u32>, Vec<u32>)> {
    f.pieces().map(|p| (p.lo.to_vec(), p.hi.to_vec())).collect()
}

#[test]
fn the_refinery_makes_the_clear_courses_one_plateau_and_the_blocked_ones_basins() {
    let mut b = behaviour(true);
    let f = run(&mut b);
    let (rmin, rmax) = rim_span(&b);
    assert!(
        (36..=38).contains(&rmin) && (322..=324).contains(&rmax),
        "{rmin} {rmax}"
    );
    // The last three pieces: the plateau (largest), then the basins by size: courses 0-15
    // (16 courses) before 345-359 (15), every speed (the C++ ranks regions of equal
    // magnitude by size; `plateau_region`/`basin_region` reset the magnitudes to 1).
    let all = boxes(&f);
    let n = all.len();
    assert_eq!(
        all[n - 3..],
        [
            (vec![rmin, 0], vec![rmax, 40]),
            (vec![0, 0], vec![15, 40]),
            (vec![345, 0], vec![359, 40]),
        ]
    );
    // Their values: the AOF's known maximum and minimum, constant (after normalisation to
    // 0..100 over a function whose extremes they are).
    let plateau = f.pieces().nth(n - 3).unwrap();
    assert_eq!(
        (plateau.wts[0], plateau.wts[1], plateau.wts[2]),
        (0.0, 0.0, 100.0)
    );
    for basin in f.pieces().skip(n - 2) {
        assert_eq!((basin.wts[0], basin.wts[1], basin.wts[2]), (0.0, 0.0, 0.0));
    }
    // Every other piece is a uniform 3 x 3 piece, or part of one the regions cut: none
    // overlaps a region, and together they cover the domain once.
    for (lo, hi) in &all[..n - 3] {
        assert!(hi[0] - lo[0] < 3 && hi[1] - lo[1] < 3, "{lo:?} {hi:?}");
        assert!(lo[0] > 15 && hi[0] < 345 && (hi[0] < rmin || lo[0] > rmax));
    }
    for c in 0..360u32 {
        for s in 0..41u32 {
            assert_eq!(f.pieces().filter(|p| p.contains(&[c, s])).count(), 1);
        }
    }
    // The plateau and basin pieces hold where the function is flat: the AOF (the C++
    // `evalHdgSpd` with the holonomic model) is 0 on the blocked courses and 100 well inside
    // the clear ones (near the span's ends the rim's chords let a ray pass a little closer
    // than 8 m: the C++'s approximation, kept).
    for c in [0, 5, 14, 15, 345, 350] {
        assert_eq!(b.model.eval_heading(f64::from(c)), 0.0, "course {c}");
    }
    for c in [rmin + 3, 90, 180, 270, rmax - 3] {
        assert_eq!(b.model.eval_heading(f64::from(c)), 100.0, "course {c}");
    }
}

#[test]
fn the_refined_argmax_is_the_unrefined_one_within_a_grid_step() {
    let f = run(&mut behaviour(true));
    let g = run(&mut behaviour(false));
    let a = f.argmax();
    let b = g.argmax();
    assert!((a[0] - b[0]).abs() <= 1.0, "course {a:?} vs {b:?}");
    assert!((a[1] - b[1]).abs() <= 0.1 + 1e-9, "speed {a:?} vs {b:?}");
    assert!(
        (f.eval(&[a[0] as u32, (a[1] * 10.0).round() as u32])
            .unwrap()
            - 100.0)
            .abs()
            < 1e-9
    );
}

#[test]
fn a_side_lock_makes_the_other_side_a_basin() {
    // Ownship at (8, 5): 15.3 m from the square's corner (5, 20), relevance
    // (30 - 15.3) / 20 > 0.6, and the square's centre (0, 25) on its port bow: the side
    // locks (`star`, as the C++ names it from the passing side `port`). The lock's basin
    // covers courses 165..350 (magnitude 3); the clear courses' plateau (magnitude 4) keeps
    // its overlap with it; the lock's basin keeps its overlap with the obstacle's (2).
    let mut b = behaviour(true);
    let f = run_at(&mut b, 8.0, 5.0);
    assert_eq!(b.side_lock, "star");
    let (rmin, rmax) = rim_span(&b);
    assert!(rmin < 165 && rmax > 165 && rmax < 350, "{rmin} {rmax}");
    let all = boxes(&f);
    let n = all.len();
    assert_eq!(all[n - 3], (vec![rmin, 0], vec![rmax, 40]), "the plateau");
    let lock = f
        .pieces()
        .find(|p| p.lo == [rmax + 1, 0] && p.hi == [350, 40])
        .expect("the lock's basin beyond the plateau");
    assert_eq!(lock.wts, [0.0, 0.0, 0.0]);
    for c in [200, rmax] {
        assert_eq!(f.eval(&[c, 20]).unwrap(), 100.0, "course {c}");
    }
    for c in [rmax + 1, 340, 350] {
        assert_eq!(f.eval(&[c, 20]).unwrap(), 0.0, "course {c}");
    }
}
