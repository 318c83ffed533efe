//! BHV_Orbit's objective function checked with `behaviors::testing`, and the example mission
//! run in lockstep, in process, with the example's registry: the helm knows BHV_Orbit (no
//! MALCONFIG), and the vehicle circles the centre at the radius and completes two laps.

use std::path::{Path, PathBuf};

use behaviors::testing::Probe;
use behaviors::{Behavior, Common, Ctx, MapInfo, Out, Registry};
use ivp::{Domain, IvpFunction};
use my_behaviour::Orbit;
use runtime::session::{self, Mode, RunOptions};

fn domain() -> Domain {
    Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
}

/// The objective of an orbit configured by `params` with the vehicle at `(x, y)`.
fn objective(params: &[(&str, &str)], x: f64, y: f64) -> IvpFunction {
    let d = domain();
    let info = MapInfo::new(0.0)
        .num("NAV_X", x)
        .num("NAV_Y", y)
        .num("NAV_HEADING", 0.0)
        .num("NAV_SPEED", 0.0);
    let ctx = Ctx {
        info: &info,
        domain: &d,
        ownship: "abe",
        name: "orbit",
        perpetual: false,
    };
    let mut orbit = Orbit::new();
    let mut common = Common::new("BHV_Orbit");
    for (k, v) in params {
        orbit.set_param(k, v, &mut common, &ctx).unwrap();
    }
    let mut out = Out::default();
    orbit.on_run(&ctx, &mut out).expect("an objective function")
}

const ORBIT: &[(&str, &str)] = &[("center", "0,-60"), ("radius", "40"), ("speed", "2")];

#[test]
fn on_the_circle_it_prefers_the_tangent_at_its_speed() {
    // 40 m south of the centre: bearing 180 from it, so the clockwise tangent is west.
    let f = objective(ORBIT, 0.0, -100.0);
    assert_eq!(f.argmax2("course", "speed"), (270.0, 2.0));
    assert_eq!(
        f.value_at(&[("course", 270.0), ("speed", 2.0)]),
        Some(100.0)
    );
    // Counter-clockwise: east.
    let ccw = [ORBIT, &[("clockwise", "false")]].concat();
    assert_eq!(
        objective(&ccw, 0.0, -100.0).argmax2("course", "speed"),
        (90.0, 2.0)
    );
}

#[test]
fn off_the_circle_it_turns_toward_it_in_proportion() {
    // Half a radius outside (20 m): 45° from the tangent toward the centre; half a radius
    // inside: 45° away from it; a radius or more outside: straight at the centre.
    assert_eq!(
        objective(ORBIT, 0.0, -120.0).argmax2("course", "speed").0,
        315.0
    );
    assert_eq!(
        objective(ORBIT, 0.0, -80.0).argmax2("course", "speed").0,
        225.0
    );
    assert_eq!(
        objective(ORBIT, 0.0, -200.0).argmax2("course", "speed").0,
        0.0
    );
}

#[test]
fn the_course_peak_is_ninety_degrees_wide_at_seven_eighths() {
    let f = objective(ORBIT, 0.0, -100.0);
    let course = f.profile("course", &[("speed", 2.0)]);
    assert_eq!(course.peak(), (270.0, 100.0));
    // Course utility falls linearly to 0 at 180° off: 75 at ±45°, coupled 50/50 with the
    // speed's 100 gives 87.5 (a hair less, in the pieces' arithmetic), 87.2 at ±46°.
    assert_eq!(course.width_above(87.4), 90.0);
    let speed = f.profile("speed", &[("course", 270.0)]);
    assert_eq!(speed.peak(), (2.0, 100.0));
    // The speed plateau 2 ± 0.1 loses 10 at its edges: 95 coupled.
    assert!((speed.width_above(95.0) - 0.2).abs() < 1e-9);
}

#[test]
fn renders_as_text_and_png_for_tuning() {
    let f = objective(ORBIT, 0.0, -100.0);
    let text = f.render_text("course", "speed", 72, 9);
    let rows: Vec<&str> = text.lines().collect();
    assert_eq!(rows.len(), 11, "{text}");
    // The top row is 4 m/s, the middle one 2 m/s: the best cells are in the middle row only,
    // around 270° (columns 53 and 54 of 72 over 0..359 are 268° and 273°).
    assert!(
        rows[0].ends_with("speed=4") && rows[4].ends_with("speed=2"),
        "{text}"
    );
    let best: Vec<usize> = rows[..9].iter().map(|r| r.matches('@').count()).collect();
    assert!(
        best[4] > 0 && best.iter().sum::<usize>() == best[4],
        "{text}"
    );
    assert_eq!(&rows[4][53..55], "@@", "{text}");
    let mut png = Vec::new();
    f.render_png("course", "speed", 2, &mut png).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
    if let Ok(dir) = std::env::var("ORBIT_PNG_DIR") {
        std::fs::write(Path::new(&dir).join("orbit.png"), &png).unwrap();
    }
}

#[test]
fn bad_parameters_are_refused_with_typed_errors() {
    let d = domain();
    let info = MapInfo::new(0.0);
    let ctx = Ctx {
        info: &info,
        domain: &d,
        ownship: "abe",
        name: "orbit",
        perpetual: false,
    };
    let mut o = Orbit::new();
    let mut c = Common::new("BHV_Orbit");
    for (k, v) in [
        ("radius", "0"),
        ("center", "5"),
        ("speed", "-1"),
        ("laps", "x"),
    ] {
        assert!(
            matches!(
                o.set_param(k, v, &mut c, &ctx),
                Err(behaviors::ParamError::BadValue { .. })
            ),
            "{k} = {v}"
        );
    }
    assert!(matches!(
        o.set_param("orbit_radius", "5", &mut c, &ctx),
        Err(behaviors::ParamError::Unknown { .. })
    ));
}

fn mission() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("mission/orbit.moos")
}

#[test]
fn a_helm_without_the_registry_is_malconfig() {
    let loaded = session::load(&mission(), &[], &[]).unwrap();
    let bhv = loaded.mission.process("pHelmIvP").unwrap();
    assert!(bhv.entries.iter().any(|e| e.value == "orbit.bhv"));
    let text = std::fs::read_to_string(mission().with_file_name("orbit.bhv")).unwrap();
    let parsed =
        mission::bhv::parse_bhv(&mission::source::SourceMap::from_text("orbit.bhv", &text));
    let params = [("domain", "course:0:359:360"), ("domain", "speed:0:4:41")];
    let g = helm::config::Globals {
        lat_origin: Some("0".into()),
        long_origin: Some("0".into()),
        community: Some("orbiter".into()),
    };
    let stock = helm::Helm::from_parsed_in(&Registry::with_stock(), &params, &g, &parsed);
    assert_eq!(stock.state(), helm::HelmState::Malconfig);
    let mine = Registry::with_stock().register("BHV_Orbit", Orbit::new);
    let ours = helm::Helm::from_parsed_in(&mine, &params, &g, &parsed);
    assert!(
        ours.config_errors().is_empty(),
        "{:?}",
        ours.config_errors()
    );
    assert_eq!(ours.behavior_names(), ["orbit"]);
}

#[test]
fn the_mission_runs_in_lockstep_with_the_orbit_driving() {
    Registry::with_stock()
        .register("BHV_Orbit", Orbit::new)
        .install();
    let loaded = session::load(&mission(), &[], &[]).unwrap();
    let checked = session::validate(&loaded);
    assert!(checked.errors.is_empty(), "{:?}", checked.errors);
    assert!(checked.malconfig.is_empty(), "{:?}", checked.malconfig);
    let dir = std::env::temp_dir().join(format!("my-behaviour-orbit-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let opts = RunOptions {
        mode: Mode::Lockstep,
        deploy: true,
        until: Some("MISSION = complete".into()),
        max_time: 900.0,
        log_dir: Some(dir.clone()),
        ..RunOptions::default()
    };
    let report = session::run(&loaded, &opts, &mut session::Quiet).unwrap();
    assert!(!report.until_pending(), "{report}");
    let log = alog::parse(&std::fs::read_to_string(&report.alog).unwrap()).unwrap();
    let texts = |var: &str| -> Vec<String> {
        log.entries
            .iter()
            .filter(|e| e.var == var)
            .filter_map(|e| e.value.as_str().map(str::to_string))
            .collect()
    };
    assert!(texts("IVPHELM_STATE").iter().any(|s| s == "DRIVE"));
    assert!(!texts("IVPHELM_STATE").iter().any(|s| s == "MALCONFIG"));
    // BHV_STATUS is not logged (`*_STATUS` omitted): the active list names it.
    assert!(texts("IVPHELM_BHV_ACTIVE").iter().any(|s| s == "orbit"));
    // Once on the circle (after the first half lap), the vehicle stays near it.
    let nums = |var: &str| -> Vec<(f64, f64)> {
        log.entries
            .iter()
            .filter(|e| e.var == var)
            .filter_map(|e| e.value.as_f64().map(|v| (e.time, v)))
            .collect()
    };
    let (xs, ys) = (nums("NAV_X"), nums("NAV_Y"));
    let end = xs.last().unwrap().0;
    let ranges: Vec<f64> = xs
        .iter()
        .zip(&ys)
        .filter(|((t, _), _)| *t > end / 2.0)
        .map(|((_, x), (_, y))| x.hypot(y + 60.0))
        .collect();
    assert!(ranges.len() > 100);
    for r in &ranges {
        assert!((30.0..50.0).contains(r), "range {r} from the centre");
    }
    // Two laps of 2π·40 m at 2 m/s take about 250 s.
    assert!((200.0..600.0).contains(&end), "ended at {end}");
    let _ = std::fs::remove_dir_all(&dir);
}
