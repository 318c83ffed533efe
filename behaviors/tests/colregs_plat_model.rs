//! BHV_AvdColregsV26 on the helm's Dubins platform model against values worked out from
//! MOOS-IvP's formulas (a2a9b716: `CPXEnginePM`, `CPXEngineThin`, `PlatModel::getTurnSeglr`,
//! `AOF_CPA`), and V22 (and V26 on the holonomic model) unchanged by it.

use std::sync::Arc;

use behaviors::colregs::plat_cpx::PlatCpx;
use behaviors::colregs::{AofCpa, AvdColregs, Distances, Version};
use behaviors::contact::ContactInfo;
use behaviors::cpa::CpaEngine;
use behaviors::plat_model::PlatModel;
use behaviors::testing::Probe;
use behaviors::{Behavior, Common, Ctx, MapInfo, Out};
use ivp::Domain;

/// Ownship at the origin heading north at 2 m/s; a Dubins model of radius 20 with a spoke
/// every 90°: the starboard circle's centre is (20, 0) and its one spoke is (20, 20), the
/// port one's (−20, 20). The turn to 90 (1.5 spokes, rounded down to 1) is (0,0) → (20,20),
/// heading 45 for 28.28 m, then the ray east.
fn dubins() -> PlatModel {
    PlatModel::dubins(0.0, 0.0, 0.0, 2.0, 20.0, 90.0)
}

/// The CPA of two straight tracks: relative position `p` (contact minus ownship), relative
/// velocity `v` (contact minus ownship); `(distance, time)`, time clipped to `[0, tol]`.
fn cpa(p: (f64, f64), v: (f64, f64), tol: f64) -> (f64, f64) {
    let vv = v.0 * v.0 + v.1 * v.1;
    let t = (-(p.0 * v.0 + p.1 * v.1) / vv).clamp(0.0, tol);
    ((p.0 + v.0 * t).hypot(p.1 + v.1 * t), t)
}

#[test]
fn the_cpa_follows_the_turn_segment_by_segment() {
    let m = Arc::new(dubins());
    let path = m.turn(90.0);
    assert_eq!(path.len(), 2);
    let leg = 20f64.hypot(20.0);
    let s45 = 2f64.sqrt();
    // A contact at (60, 25) heading west at 1 m/s.
    let pm = PlatCpx::new(m.clone(), (60.0, 25.0, 270.0, 1.0));
    // Segment 0, heading 45 at 2 m/s: relative velocity (−1 − √2, −√2); its CPA comes after
    // the 14.14 s the segment lasts, so it does not count.
    let (_, t0) = cpa((60.0, 25.0), (-1.0 - s45, -s45), 120.0);
    assert!(t0 > leg / 2.0, "{t0}");
    // At (20, 20) after 14.14 s the contact has gone 14.14 m west, to (45.86, 25); heading
    // east at 2 its relative velocity is (−3, 0): closest 5 m after 8.62 s more.
    let (d1, t1) = cpa((60.0 - leg / 2.0 - 20.0, 5.0), (-3.0, 0.0), 120.0);
    assert!((d1 - 5.0).abs() < 1e-9 && (t1 - (40.0 - leg / 2.0) / 3.0).abs() < 1e-9);
    assert!((pm.eval_cpa(90.0, 2.0, 120.0) - d1).abs() < 1e-6);
    // The holonomic ray east from the origin passes it at 25 m.
    let og = CpaEngine::new(60.0, 25.0, 270.0, 1.0, 0.0, 0.0);
    let (d_holo, _) = cpa((60.0, 25.0), (-3.0, 0.0), 120.0);
    assert!((og.eval_cpa(90.0, 2.0, 120.0) - d_holo).abs() < 1e-9);
    assert!((d_holo - 25.0).abs() < 1e-9);
    // Dead ahead the path is the ray: the same CPA as the OG engine.
    assert!((pm.eval_cpa(0.0, 2.0, 120.0) - og.eval_cpa(0.0, 2.0, 120.0)).abs() < 1e-9);
    // A stationary contact at (40, 30): the ray east passes 30 m off, the turn 10 m.
    let pm = PlatCpx::new(m, (40.0, 30.0, 0.0, 0.0));
    assert!((pm.eval_cpa(90.0, 2.0, 120.0) - 10.0).abs() < 1e-9);
    let og = CpaEngine::new(40.0, 30.0, 0.0, 0.0, 0.0, 0.0);
    assert!((og.eval_cpa(90.0, 2.0, 120.0) - 30.0).abs() < 1e-9);
    // At speed 0 ownship stays put: the present range.
    assert!((pm.eval_cpa(90.0, 0.0, 120.0) - 50.0).abs() < 1e-9);
}

#[test]
fn aof_cpa_values_on_the_dubins_model() {
    // AOF_CPA with collision 10 and all clear 30 over 120 s.
    let cn = (60.0, 25.0, 270.0, 1.0);
    let e = CpaEngine::new(cn.0, cn.1, cn.2, cn.3, 0.0, 0.0);
    let holo = AofCpa {
        d: Distances::new(e.clone(), 120.0, 10.0, 30.0).unwrap(),
    };
    let turn = AofCpa {
        d: Distances::new(e, 120.0, 10.0, 30.0)
            .unwrap()
            .with_plat_model(Arc::new(dubins()), cn),
    };
    // East: the ray passes 25 m off, 25 + 75 · 15 / 20 = 81.25; the turn 5 m: 0.
    assert!((holo.eval(90.0, 2.0) - 81.25).abs() < 1e-9);
    assert_eq!(turn.eval(90.0, 2.0), 0.0);
    // North (no turn): the same value on both, the ray from the origin: relative velocity
    // (−1, −2) from (60, 25) closes to 42.5 m, beyond all clear: 100.
    let (d, _) = cpa((60.0, 25.0), (-1.0, -2.0), 120.0);
    assert!(d > 30.0);
    assert_eq!(holo.eval(0.0, 2.0), 100.0);
    assert_eq!(turn.eval(0.0, 2.0), 100.0);
}

fn domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
}

fn info(model: Option<PlatModel>) -> MapInfo {
    let i = MapInfo::new(10.0)
        .num("NAV_X", 0.0)
        .num("NAV_Y", 0.0)
        .num("NAV_HEADING", 0.0)
        .num("NAV_SPEED", 2.0)
        .with_contact(
            "cn",
            ContactInfo {
                x_m: 5.0,
                y_m: 70.0,
                heading_deg: 180.0,
                speed_mps: 2.0,
                utc: 10.0,
                vtype: "kayak".into(),
                ..ContactInfo::default()
            },
        );
    match model {
        Some(m) => i.with_plat_model(m),
        None => i,
    }
}

/// One running iteration of `version` against a contact nearly head-on, with `model`.
fn run(version: Version, model: Option<PlatModel>) -> (&'static str, ivp::IvpFunction) {
    let d = domain();
    let inf = info(model);
    let ctx = Ctx {
        info: &inf,
        domain: &d,
        ownship: "abe",
        name: "avd_cn",
        perpetual: false,
    };
    let mut b = AvdColregs::new(version);
    b.set_param("contact", "cn", &mut Common::new(b.kind()), &ctx)
        .unwrap();
    let mut out = Out::default();
    let f = b.on_run(&ctx, &mut out).expect("a function");
    (b.mode, f)
}

fn values(f: &ivp::IvpFunction) -> Vec<f64> {
    let mut v = Vec::new();
    for c in (0..360).step_by(5) {
        for s in [0.0, 1.0, 2.0, 3.5] {
            v.push(f.value_at(&[("course", c as f64), ("speed", s)]).unwrap());
        }
    }
    v
}

#[test]
fn v26_follows_the_dubins_model_and_v22_does_not() {
    let holo = PlatModel::holonomic(0.0, 0.0, 0.0, 2.0);
    let turn = PlatModel::dubins(0.0, 0.0, 0.0, 2.0, 30.0, 10.0);
    let (mode, v22) = run(Version::V22, None);
    assert_eq!(mode, "headon");
    let v22 = values(&v22);
    // V22 reads no model; V26 on the holonomic model (or none) is V22 (same time on leg).
    assert_eq!(values(&run(Version::V22, Some(turn.clone())).1), v22);
    assert_eq!(values(&run(Version::V26, None).1), v22);
    assert_eq!(values(&run(Version::V26, Some(holo)).1), v22);
    // On the Dubins model V26's head-on function changes.
    let (mode, v26) = run(Version::V26, Some(turn));
    assert_eq!(mode, "headon");
    assert_ne!(values(&v26), v22);
}
