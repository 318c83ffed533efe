//! IvPContactBehavior's `use_plat_model` (its platform-model engines, `CPXEnginePM` over
//! `CPXEngineThin`, MOOS-IvP a2a9b716) on BHV_AvoidCollision, CutRange and the AvdColregs
//! family, and V26's contact state read with the previous iteration's model, against values
//! worked out by hand from the C++ formulas.

use std::sync::Arc;

use behaviors::colregs::plat_cpx::{PlatCpx, contact_state, empty_model};
use behaviors::colregs::{AvdColregs, Version};
use behaviors::contact::ContactInfo;
use behaviors::plat_model::PlatModel;
use behaviors::testing::Probe;
use behaviors::{AvoidCollision, Behavior, Common, Ctx, CutRange, MapInfo, Out};
use ivp::Domain;

fn domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
}

/// Ownship at `(x, y)` heading north at 1 m/s with `model`; contact `cn` at rest at
/// `(cnx, cny)`.
fn info(os: (f64, f64), cn: (f64, f64), model: Option<PlatModel>) -> MapInfo {
    let i = MapInfo::new(10.0)
        .num("NAV_X", os.0)
        .num("NAV_Y", os.1)
        .num("NAV_HEADING", 0.0)
        .num("NAV_SPEED", 1.0)
        .with_contact(
            "cn",
            ContactInfo {
                x_m: cn.0,
                y_m: cn.1,
                heading_deg: 0.0,
                speed_mps: 0.0,
                utc: 10.0,
                ..ContactInfo::default()
            },
        );
    match model {
        Some(m) => i.with_plat_model(m),
        None => i,
    }
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

fn configure<B: Behavior>(b: &mut B, params: &[(&str, &str)], ctx: &Ctx<'_>) {
    let mut common = Common::new(b.kind());
    b.set_param("contact", "cn", &mut common, ctx).unwrap();
    for (k, v) in params {
        b.set_param(k, v, &mut common, ctx).unwrap();
    }
}

/// Ownship at (100, 0) heading north, a Dubins model of radius 10 with a spoke every 90°:
/// the starboard circle's centre is (110, 0), its one spoke (110, 10). The turn to 90
/// (90/90 + 0.5 = 1.5 spokes, rounded down to 1) is (100,0) → (110,10), heading 45 for
/// 14.142 m, then the ray east from (110, 10).
fn dubins() -> PlatModel {
    PlatModel::dubins(100.0, 0.0, 0.0, 1.0, 10.0, 90.0)
}

/// The contact at rest at (130, 20).
const CN: (f64, f64) = (130.0, 20.0);

#[test]
fn the_cpa_follows_the_turn_hand_worked() {
    let pm = PlatCpx::new(Arc::new(dubins()), (CN.0, CN.1, 0.0, 0.0));
    // Course 90 at 1 m/s. Vertex 0, (100,0) heading 45: the contact (30, 20) away projects
    // 50/√2 = 35.36 m along the segment, 35.36 s, beyond the segment's 14.14 s: no answer.
    // Vertex 1, (110,10) heading 90 after 14.14 s: the contact 20 m ahead and 10 m to port,
    // CPA 10 m after 20 s more.
    assert!((pm.eval_cpa(90.0, 1.0, 120.0) - 10.0).abs() < 1e-9);
    // Holding north (no turn): the ray from (100, 0) passes the contact 30 m abeam.
    assert!((pm.eval_cpa(0.0, 1.0, 120.0) - 30.0).abs() < 1e-9);
    // The holonomic model: the ray east from (100, 0) passes it 20 m to port.
    let holo = PlatCpx::new(
        Arc::new(PlatModel::holonomic(100.0, 0.0, 0.0, 1.0)),
        (CN.0, CN.1, 0.0, 0.0),
    );
    assert!((holo.eval_cpa(90.0, 1.0, 120.0) - 20.0).abs() < 1e-9);
    // The empty model: rays from the origin. East along y = 0 the closest point (130, 0)
    // lies beyond the 120 s leg: at (120, 0) the contact is √(10² + 20²) = 22.36 m away.
    // North along x = 0: 130 m.
    let empty = PlatCpx::new(empty_model(), (CN.0, CN.1, 0.0, 0.0));
    assert!((empty.eval_cpa(90.0, 1.0, 120.0) - 500f64.sqrt()).abs() < 1e-9);
    assert!((empty.eval_cpa(0.0, 1.0, 120.0) - 130.0).abs() < 1e-9);
}

#[test]
fn avoid_collision_objective_on_the_turn_and_its_state_on_the_last_model() {
    let d = domain();
    let inf = info((100.0, 0.0), CN, Some(dubins()));
    let c = ctx(&inf, &d);
    let params = [("min_util_cpa_dist", "5"), ("max_util_cpa_dist", "75")];
    let mut og = AvoidCollision::new();
    configure(&mut og, &params, &c);
    let mut pm = AvoidCollision::new();
    configure(&mut pm, &params, &c);
    pm.set_param("use_plat_model", "true", &mut Common::new(pm.kind()), &c)
        .unwrap();
    let mut out = Out::default();
    assert!(og.on_run(&c, &mut out).is_some());
    assert!(pm.on_run(&c, &mut out).is_some());
    // The first update: the engine holds no model yet, so the contact state follows a ray
    // from the origin (north along x = 0: 130 m); the OG engine's from ownship (30 m).
    assert!((pm.base.states.now().os_curr_cpa_dist - 130.0).abs() < 1e-9);
    assert!((og.base.states.now().os_curr_cpa_dist - 30.0).abs() < 1e-9);
    // The second update reads the model handed on the first: the ray north from (100, 0).
    assert!(pm.on_run(&c, &mut out).is_some());
    assert!((pm.base.states.now().os_curr_cpa_dist - 30.0).abs() < 1e-9);
    // The objective (before normalising), metric 25 + 75 · (d − 5) / 70: east at 1 m/s the
    // turn's CPA 10 m gives 30.357, the ray's 20 m 41.071. Sampled in 3 × 3 pieces: near.
    let f_pm = pm.objective(&c).unwrap();
    let f_og = og.objective(&c).unwrap();
    let at = |f: &ivp::IvpFunction| f.value_at(&[("course", 90.0), ("speed", 1.0)]).unwrap();
    let (want_pm, want_og) = (25.0 + 75.0 * 5.0 / 70.0, 25.0 + 75.0 * 15.0 / 70.0);
    assert!((at(&f_pm) - want_pm).abs() < 1.5, "pm {}", at(&f_pm));
    assert!((at(&f_og) - want_og).abs() < 1.5, "og {}", at(&f_og));
    // Holding north both see 30 m: 25 + 75 · 25 / 70 = 51.786.
    let north = |f: &ivp::IvpFunction| f.value_at(&[("course", 1.0), ("speed", 1.0)]).unwrap();
    assert!((north(&f_pm) - north(&f_og)).abs() < 1.5);
}

#[test]
fn contact_state_of_the_engines_hand_worked() {
    // Ownship (100, 0) north at 1 m/s, the contact at rest at (130, 20).
    let os = (100.0, 0.0, 0.0, 1.0);
    let cn = (CN.0, CN.1, 0.0, 0.0);
    let s = contact_state(os, cn, Some(Arc::new(dubins())));
    // Rate of closure: ownship's speed toward the contact (bearing 56.31°, cosine 20/36.056),
    // 0.5547 m/s.
    let range = 1300f64.sqrt();
    assert!((s.rate_of_closure - 20.0 / range).abs() < 1e-9);
    // Bearing rate: the tangent 90° to port of the bearing 56.31° is 326.31°; ownship's speed
    // along it cos(33.69°) · −1 = −30/36.056; × −360 / (2π · 36.056): +1.3223 °/s.
    // The C++'s 12-digit pi (MPI).
    #[allow(clippy::approx_constant)]
    let mpi = 3.14159265359;
    let want = -(30.0 / range) * (-360.0 / (2.0 * range * mpi));
    assert!((s.bearing_rate - want).abs() < 1e-9, "{}", s.bearing_rate);
    assert!((s.os_curr_cpa_dist - 30.0).abs() < 1e-9);
    // Ownship heading north passes the contact's beam line (y = 20) to its port side.
    assert!(s.os_passes_cn);
    // The reverse engine has the empty model: the contact as ownship on a ray from the
    // origin; at rest it passes nothing and crosses nothing.
    assert!(!s.cn_passes_os && !s.cn_crosses_os);
}

#[test]
fn cut_range_and_v22_take_use_plat_model_with_the_empty_model() {
    let d = domain();
    let inf = info((100.0, 0.0), CN, Some(dubins()));
    let c = ctx(&inf, &d);
    let mut cr = CutRange::new();
    configure(&mut cr, &[("use_plat_model", "true")], &c);
    let mut out = Out::default();
    let _ = cr.on_run(&c, &mut out);
    let _ = cr.on_run(&c, &mut out);
    // CutRange never hands its engine a model: every update is on the rays from the origin.
    assert!((cr.base.states.now().os_curr_cpa_dist - 130.0).abs() < 1e-9);
    let mut v22 = AvdColregs::new(Version::V22);
    configure(
        &mut v22,
        &[("use_plat_model", "true"), ("completed_dist", "500")],
        &c,
    );
    let _ = v22.on_run(&c, &mut out);
    let _ = v22.on_run(&c, &mut out);
    assert!((v22.base.states.now().os_curr_cpa_dist - 130.0).abs() < 1e-9);
}

#[test]
fn v26_reads_the_previous_iterations_model() {
    let d = domain();
    let mut v26 = AvdColregs::new(Version::V26);
    let first = info(
        (50.0, 0.0),
        (0.0, 100.0),
        Some(PlatModel::holonomic(50.0, 0.0, 0.0, 1.0)),
    );
    let c = ctx(&first, &d);
    configure(&mut v26, &[("completed_dist", "500")], &c);
    assert!(
        v26.base.use_plat_model,
        "V26 starts on the platform-model engines"
    );
    let mut out = Out::default();
    let _ = v26.on_run(&c, &mut out);
    // No model handed yet: north from the origin straight through the contact at (0, 100).
    assert!(v26.base.states.now().os_curr_cpa_dist.abs() < 1e-9);
    // Next iteration ownship is at (40, 10) with its own model; the state reads the model of
    // the first iteration, the ray north from (50, 0): 50 m (the present pose would give 40).
    let second = info(
        (40.0, 10.0),
        (0.0, 100.0),
        Some(PlatModel::holonomic(40.0, 10.0, 0.0, 1.0)),
    );
    let c = ctx(&second, &d);
    let _ = v26.on_run(&c, &mut out);
    assert!((v26.base.states.now().os_curr_cpa_dist - 50.0).abs() < 1e-9);
    let _ = v26.on_run(&c, &mut out);
    assert!((v26.base.states.now().os_curr_cpa_dist - 40.0).abs() < 1e-9);
    // use_plat_model = false puts V26 on the OG engine: the present pose at once.
    let mut og = AvdColregs::new(Version::V26);
    configure(
        &mut og,
        &[("completed_dist", "500"), ("use_plat_model", "false")],
        &c,
    );
    let _ = og.on_run(&c, &mut out);
    assert!((og.base.states.now().os_curr_cpa_dist - 40.0).abs() < 1e-9);
}
