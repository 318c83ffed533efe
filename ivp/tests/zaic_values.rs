//! Builder values checked against numbers worked out by hand from the ZAIC formulas
//! (reference: ivp-helm.md section 2 and the MOOS-IvP builders).

use ivp::{
    BREAK_TIES, Combine, Domain, IvpError, IvpFunction, PeakComponent, ZaicHdg, ZaicHeq, ZaicLeq,
    ZaicPeak, ZaicSpd,
};

fn course() -> Domain {
    Domain::parse_specs(["course:0:359:360"]).unwrap()
}
fn speed() -> Domain {
    Domain::parse_specs(["speed:0:4:41"]).unwrap()
}
fn depth() -> Domain {
    Domain::parse_specs(["depth:0:100:101"]).unwrap()
}
fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}
/// The function value, which may differ from the formula by the 0.001 segmentation tolerance.
fn fval(f: &IvpFunction, ix: u32) -> f64 {
    f.eval(&[ix]).expect("point covered")
}

#[test]
fn peak_summit_edges_and_base() {
    // summit 50, peakwidth 10, basewidth 20, summitdelta 20, min 0, max 100 over depth.
    let d = depth();
    let mut z = ZaicPeak::new(&d, "depth").unwrap();
    z.set_params(50.0, 10.0, 20.0, 20.0, 0.0, 100.0).unwrap();
    // summit: maxutil
    assert!(close(z.eval_point(50), 100.0));
    // inside the peak: 100 - (20/10)*dist -> dist 5: 90
    assert!(close(z.eval_point(55), 90.0));
    assert!(close(z.eval_point(45), 90.0));
    // edge of the peak (dist 10): 100 - 20 = 80
    assert!(close(z.eval_point(60), 80.0));
    // inside the base: 80 - (80-0)/20 * (dist-10) -> dist 15: 60
    assert!(close(z.eval_point(65), 60.0));
    // edge of the base (dist 30): 0; beyond: minutil
    assert!(close(z.eval_point(80), 0.0));
    assert!(close(z.eval_point(81), 0.0));
    assert!(close(z.eval_point(0), 0.0));
    let f = z.extract().unwrap();
    for ix in [0, 20, 40, 45, 50, 55, 60, 65, 80, 100] {
        assert!(
            (fval(&f, ix) - z.eval_point(ix)).abs() <= 0.001 + 1e-9,
            "ix {ix}"
        );
    }
    // the piecewise function keeps the exact summit
    assert!(close(f.max_val(), 100.0));
    assert_eq!(f.max_pt(), Some(vec![50]));
}

#[test]
fn peak_wraps_across_the_course_seam() {
    let d = course();
    let mut z = ZaicPeak::new(&d, "course").unwrap();
    z.set_params(355.0, 0.0, 20.0, 0.0, 0.0, 100.0).unwrap();
    z.set_value_wrap(true);
    // 359: direct distance 4 -> 100 - 100/20*4 = 80
    assert!(close(z.eval_point(359), 80.0));
    // 0: around the seam: (0-0) + (359-355) + delta 1 = 5 -> 75
    assert!(close(z.eval_point(0), 75.0));
    // 10: 10 + 4 + 1 = 15 -> 25
    assert!(close(z.eval_point(10), 25.0));
    // 14: distance 19 -> 5; 15: distance 20 -> 0 (edge of base)
    assert!(close(z.eval_point(14), 5.0));
    assert!(close(z.eval_point(15), 0.0));
    // without wrap, 0 is 355 away: minutil
    let mut nz = ZaicPeak::new(&d, "course").unwrap();
    nz.set_params(355.0, 0.0, 20.0, 0.0, 0.0, 100.0).unwrap();
    assert!(close(nz.eval_point(0), 0.0));
    let f = z.extract().unwrap();
    assert!((fval(&f, 0) - 75.0).abs() <= 0.001);
    assert!((fval(&f, 10) - 25.0).abs() <= 0.001);
    assert!((fval(&f, 355) - 100.0).abs() <= 1e-9);
}

#[test]
fn peak_clips_to_min_and_max_utility() {
    let d = depth();
    let mut z = ZaicPeak::new(&d, "depth").unwrap();
    // summitdelta larger than the utility range clips to the range (20..60 -> 40)
    z.set_params(30.0, 10.0, 10.0, 90.0, 20.0, 60.0).unwrap();
    assert_eq!(z.components()[0].summitdelta, 40.0);
    assert!(close(z.eval_point(30), 60.0));
    // peak edge: 60 - 40 = 20 = minutil; base stays at minutil
    assert!(close(z.eval_point(40), 20.0));
    assert!(close(z.eval_point(45), 20.0));
    assert!(close(z.eval_point(90), 20.0));
    // negative widths clip to 0
    z.set_params(30.0, -5.0, -5.0, 0.0, 0.0, 100.0).unwrap();
    assert_eq!(z.components()[0].peakwidth, 0.0);
    assert!(close(z.eval_point(30), 100.0));
    assert!(close(z.eval_point(31), 0.0));
}

#[test]
fn peak_summit_insist_and_components() {
    let d = speed();
    let mut z = ZaicPeak::new(&d, "speed").unwrap();
    // summit 1.23 between grid points with no width: every point is minutil, so the
    // nearest point (1.2, index 12) is forced to max utility.
    z.set_params(1.23, 0.0, 0.0, 0.0, 0.0, 100.0).unwrap();
    let f = z.extract().unwrap();
    assert!(close(fval(&f, 12), 100.0));
    assert!(close(fval(&f, 13), 0.0));
    assert_eq!(f.max_pt(), Some(vec![12]));
    // summit above the domain: the last point
    z.set_params(9.0, 0.0, 0.0, 0.0, 0.0, 100.0).unwrap();
    assert_eq!(z.extract().unwrap().max_pt(), Some(vec![40]));
    // two components: max vs sum
    let mut m = ZaicPeak::new(&d, "speed").unwrap();
    m.set_params(1.0, 0.0, 1.0, 0.0, 0.0, 100.0).unwrap();
    m.add_component(PeakComponent {
        summit: 1.5,
        basewidth: 1.0,
        ..Default::default()
    })
    .unwrap();
    // at 1.2: comp0 = 100 - 100*0.2 = 80; comp1 = 100 - 100*0.3 = 70
    assert!((m.eval_point(12) - 80.0).abs() < 1e-9);
    m.set_combine(Combine::Sum);
    assert!((m.eval_point(12) - 150.0).abs() < 1e-9);
}

#[test]
fn peak_rejects_bad_utilities() {
    let mut z = ZaicPeak::new(&depth(), "depth").unwrap();
    assert!(matches!(
        z.set_params(10.0, 1.0, 1.0, 0.0, 100.0, 100.0),
        Err(IvpError::BadParam {
            param: "minutil",
            ..
        })
    ));
    assert!(z.set_params(10.0, f64::NAN, 1.0, 0.0, 0.0, 100.0).is_err());
    assert!(
        z.add_component(PeakComponent {
            minutil: 50.0,
            maxutil: 10.0,
            ..Default::default()
        })
        .is_err()
    );
    assert!(ZaicPeak::new(&depth(), "course").is_err());
}

#[test]
fn leq_pieces_and_tie_break_slopes() {
    // depth domain, summit 20, basewidth 10: LEQ prefers <= 20.
    let d = depth();
    let mut z = ZaicLeq::new(&d, "depth").unwrap();
    z.set_summit(20.0).unwrap();
    z.set_basewidth(10.0).unwrap();
    let f = z.extract().unwrap();
    assert_eq!(f.piece_count(), 3);
    // [0,20]: 100 + 0.00001*ix: rising gently so the point nearest the summit wins ties
    let p0 = f.piece(0);
    assert_eq!((p0.lo[0], p0.hi[0]), (0, 20));
    assert_eq!(p0.wts[0], BREAK_TIES);
    assert!(close(fval(&f, 0), 100.0));
    assert!(close(fval(&f, 20), 100.0 + 20.0 * BREAK_TIES));
    // ramp [21,30]: 100 - 10*(ix-20)
    assert!(close(fval(&f, 21), 90.0));
    assert!(close(fval(&f, 25), 50.0));
    assert!(close(fval(&f, 30), 0.0));
    // [31,100]: 0 - 0.00001*ix
    let p2 = f.piece(2);
    assert_eq!(p2.wts[0], -BREAK_TIES);
    assert!(close(fval(&f, 31), -31.0 * BREAK_TIES));
    assert!(close(fval(&f, 100), -100.0 * BREAK_TIES));
    // the maximum is at the summit itself
    assert_eq!(f.max_pt(), Some(vec![20]));
}

#[test]
fn leq_summit_delta_singleton_and_edges() {
    let d = speed();
    let mut z = ZaicLeq::new(&d, "speed").unwrap();
    z.set_summit(1.0).unwrap();
    z.set_basewidth(0.5).unwrap();
    z.set_summit_delta(5.0).unwrap();
    z.set_min_max_util(10.0, 90.0).unwrap();
    let f = z.extract().unwrap();
    // [0,9] at 90 (+ties), singleton 10 at 95, ramp [11,15] from 90 to 10 over 5 steps, rest 10
    assert_eq!(f.piece_count(), 4);
    assert!(close(fval(&f, 10), 95.0));
    assert!(close(fval(&f, 9), 90.0 + 9.0 * BREAK_TIES));
    assert!(close(fval(&f, 11), 74.0));
    assert!(close(fval(&f, 15), 10.0));
    assert!(close(fval(&f, 16), 10.0 - 16.0 * BREAK_TIES));
    // summit at the domain's low end: as in MOOS-IvP index 0 is left uncovered
    let mut z0 = ZaicLeq::new(&d, "speed").unwrap();
    z0.set_summit(0.0).unwrap();
    z0.set_basewidth(1.0).unwrap();
    let f0 = z0.extract().unwrap();
    assert_eq!(f0.eval(&[0]), None);
    // with ipt_one == 0 the ramp is anchored at its far end: 0 at index 10
    assert!(close(fval(&f0, 10), 0.0));
    assert!(close(fval(&f0, 5), 50.0));
}

#[test]
fn heq_pieces_and_tie_break_slopes() {
    let d = speed();
    let mut z = ZaicHeq::new(&d, "speed").unwrap();
    z.set_summit(2.0).unwrap();
    z.set_basewidth(1.0).unwrap();
    let f = z.extract().unwrap();
    assert_eq!(f.piece_count(), 3);
    // [20,40]: 100 - 0.00001*ix (prefers the low end, nearest the summit)
    let p0 = f.piece(0);
    assert_eq!((p0.lo[0], p0.hi[0]), (20, 40));
    assert_eq!(p0.wts[0], -BREAK_TIES);
    assert!(close(fval(&f, 20), 100.0 - 20.0 * BREAK_TIES));
    // ramp [10,19]: 0 at 10 rising 10 per step
    assert!(close(fval(&f, 10), 0.0));
    assert!(close(fval(&f, 15), 50.0));
    assert!(close(fval(&f, 19), 90.0));
    // [0,9]: 0 + 0.00001*ix
    assert!(close(fval(&f, 9), 9.0 * BREAK_TIES));
    assert_eq!(f.max_pt(), Some(vec![20]));
    // summit delta: singleton at the summit
    z.set_summit_delta(3.0).unwrap();
    let g = z.extract().unwrap();
    assert!(close(fval(&g, 20), 103.0));
    assert!(close(fval(&g, 21), 100.0 - 21.0 * BREAK_TIES));
}

#[test]
fn hleq_bad_parameters() {
    let mut z = ZaicLeq::new(&speed(), "speed").unwrap();
    assert!(matches!(
        z.set_basewidth(-1.0),
        Err(IvpError::BadParam {
            param: "basewidth",
            ..
        })
    ));
    assert!(z.set_min_max_util(5.0, 5.0).is_err());
    assert!(z.set_summit(f64::INFINITY).is_err());
    let one = Domain::from_vars(&[("x", 3.0, 3.0, 1)]).unwrap();
    assert!(matches!(
        ZaicHeq::new(&one, "x"),
        Err(IvpError::BadDomain { .. })
    ));
}

#[test]
fn spd_knots_and_values() {
    let d = speed();
    // med 2.0, low 1.5 (util 70), high 2.5 (util 60), ends 0 util
    let z = ZaicSpd::new(&d, "speed", 2.0, 1.5, 2.5, 70.0, 60.0).unwrap();
    assert_eq!(
        z.knots(),
        vec![(0, 0.0), (15, 70.0), (20, 100.0), (25, 60.0), (40, 0.0)]
    );
    let f = z.extract().unwrap();
    assert_eq!(f.piece_count(), 4);
    assert!(close(fval(&f, 0), 0.0));
    assert!(close(fval(&f, 15), 70.0));
    assert!(close(fval(&f, 10), 70.0 * 10.0 / 15.0));
    assert!(close(fval(&f, 18), 70.0 + 30.0 * 3.0 / 5.0));
    assert!(close(fval(&f, 20), 100.0));
    assert!(close(fval(&f, 23), 100.0 - 40.0 * 3.0 / 5.0));
    assert!(close(fval(&f, 40), 0.0));
    // pieces do not overlap: every index in exactly one piece
    for ix in 0..41u32 {
        assert_eq!(f.pieces().filter(|p| p.contains(&[ix])).count(), 1);
    }
    // speeds clip into the domain; low at the domain's low end takes min_spd_util
    let mut z = ZaicSpd::new(&d, "speed", 9.0, -1.0, 12.0, 70.0, 60.0).unwrap();
    z.set_min_max_util(10.0, 20.0, 100.0).unwrap();
    assert_eq!(z.knots(), vec![(0, 10.0), (40, 100.0)]);
    assert!(z.set_min_max_util(-1.0, 0.0, 100.0).is_err());
    assert!(z.set_min_max_util(0.0, 0.0, 0.0).is_err());
    assert!(ZaicSpd::new(&d, "speed", 1.0, 0.5, 1.5, -3.0, 0.0).is_err());
}

#[test]
fn hdg_sides_seam_and_clipping() {
    let d = course();
    // summit 10, port side: 20 deg to 40 util; starboard 30 deg to 60 util
    let z = ZaicHdg::new(&d, "course", 10.0, 20.0, 30.0, 40.0, 60.0, 0.0, 100.0).unwrap();
    assert!(close(z.eval_point(10), 100.0));
    // starboard: 100 - (40/30)*15 = 80 at 25; 60 at 40; then to 0 at 190
    assert!(close(z.eval_point(25), 80.0));
    assert!(close(z.eval_point(40), 60.0));
    assert!(close(z.eval_point(115), 60.0 - 60.0 / 150.0 * 75.0));
    // port across the seam: 355 is 15 deg to port: 100 - (60/20)*15 = 55
    assert!(close(z.eval_point(355), 55.0));
    assert!(close(z.eval_point(350), 40.0));
    // 280 is 90 to port: 40 - 40/160*70 = 22.5
    assert!(close(z.eval_point(280), 22.5));
    // 190 is the far side (180 from the summit, starboard branch): 0
    assert!(close(z.eval_point(190), 0.0));
    let f = z.extract().unwrap();
    for ix in [10, 25, 40, 115, 190, 280, 350, 355] {
        assert!(
            (fval(&f, ix) - z.eval_point(ix)).abs() <= 0.001 + 1e-9,
            "ix {ix}"
        );
    }
    assert_eq!(f.max_pt(), Some(vec![10]));
    // deltas clip to 180; delta utils clip into [min, max]
    let c = ZaicHdg::new(&d, "course", 0.0, 500.0, -4.0, 150.0, -10.0, 0.0, 100.0).unwrap();
    // With hdelta 0 the summit sits exactly at the starboard break point, so (as in
    // MOOS-IvP) it takes hdelta_util, here clipped from -10 to 0.
    assert!(close(c.eval_point(0), 0.0));
    assert!(close(c.eval_point(1), 0.0));
    // port side: ldelta clipped to 180 and ldelta_util to 100, so 90 to port is still 100
    assert!(close(c.eval_point(270), 100.0));
    assert!(ZaicHdg::new(&d, "course", 400.0, 10.0, 10.0, 50.0, 50.0, 0.0, 100.0).is_err());
    assert!(ZaicHdg::new(&d, "course", 40.0, 10.0, 10.0, 50.0, 50.0, 80.0, 20.0).is_err());
}

#[test]
fn hdg_replaces_a_bad_course_domain() {
    let d = Domain::from_vars(&[("course", 0.0, 720.0, 721)]).unwrap();
    let z = ZaicHdg::new(&d, "course", 90.0, 10.0, 10.0, 50.0, 50.0, 0.0, 100.0).unwrap();
    let f = z.extract().unwrap();
    assert_eq!(f.domain().vars()[0].points(), 360);
}

mod peak_values {
    use super::*;
    use proptest::prelude::*;

    fn component() -> impl Strategy<Value = PeakComponent> {
        (
            0.0f64..359.0,
            0.0f64..60.0,
            0.0f64..200.0,
            0.0f64..50.0,
            0.0f64..40.0,
            50.0f64..150.0,
        )
            .prop_map(
                |(summit, peakwidth, basewidth, summitdelta, minutil, maxutil)| PeakComponent {
                    summit,
                    peakwidth,
                    basewidth,
                    summitdelta,
                    minutil,
                    maxutil,
                },
            )
    }

    proptest! {
        /// The fast per-index values agree exactly with the point formula.
        #[test]
        fn values_match_eval_point(
            comps in prop::collection::vec(component(), 1..4),
            wrap in any::<bool>(),
            sum in any::<bool>(),
        ) {
            let d = course();
            let mut z = ZaicPeak::new(&d, "course").unwrap();
            let c0 = comps[0];
            z.set_params(c0.summit, c0.peakwidth, c0.basewidth, c0.summitdelta, c0.minutil, c0.maxutil)
                .unwrap();
            for c in &comps[1..] {
                z.add_component(*c).unwrap();
            }
            z.set_value_wrap(wrap);
            z.set_combine(if sum { Combine::Sum } else { Combine::Max });
            let mut vals = Vec::new();
            z.values(&mut vals);
            prop_assert_eq!(vals.len(), 360);
            for (ix, v) in vals.iter().enumerate() {
                prop_assert_eq!(v.to_bits(), z.eval_point(ix as u32).to_bits(), "ix {}", ix);
            }
        }
    }
}
