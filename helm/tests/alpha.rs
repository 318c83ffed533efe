//! The s1_alpha mission end to end: the real alpha.bhv and alpha.moos, a kinematic stand-in for
//! the vehicle, and the posted sequence checked against pHelmIvP's behaviour.

mod common;

use common::{Rig, Vehicle, all, get, is_str};
use helm::{Helm, HelmState, Mail, Value};
use mission::source::SourceMap;
use test_support::mission_text;

fn alpha_helm() -> Helm {
    let moos = mission::moos::parse_moos(&SourceMap::from_text(
        "alpha.moos",
        &mission_text("s1_alpha/alpha.moos"),
    ));
    assert!(!moos.has_errors(), "alpha.moos: {:?}", moos.diagnostics);
    let bhv = mission::bhv::parse_bhv(&SourceMap::from_text(
        "alpha.bhv",
        &mission_text("s1_alpha/alpha.bhv"),
    ));
    let helm = Helm::from_mission(&moos.value, &bhv);
    assert!(
        helm.config_errors().is_empty(),
        "{:?}",
        helm.config_errors()
    );
    helm
}

#[test]
fn alpha_mission_posts_the_phelmivp_sequence() {
    let helm = alpha_helm();
    // uSimMarineV22 start_pos in alpha.moos: x=0, y=-20, heading=180.
    let mut rig = Rig::new(helm, Vehicle::new(0.0, -20.0, 180.0));

    // --- Start-up: initialize lines, domain in pHelmIvP's (reversed) order, PARK.
    let posts = rig.step(&[]);
    let deploy = posts.iter().find(|p| p.key == "DEPLOY").unwrap();
    assert_eq!(
        (deploy.value.as_str(), &*deploy.aux),
        (Some("false"), "HELM_VAR_INIT")
    );
    assert!(is_str(get(&posts, "RETURN"), "false"));
    assert!(is_str(
        get(&posts, "IVPHELM_DOMAIN"),
        "speed,0,4,41:course,0,359,360"
    ));
    assert!(is_str(get(&posts, "IVPHELM_STATE"), "PARK"));
    assert!(is_str(
        get(&posts, "PLOGGER_CMD"),
        "COPY_FILE_REQUEST = alpha.bhv"
    ));

    // --- PARK until MOOS_MANUAL_OVERRIDE=false: all-stop ManualOverride, zero decisions once.
    let mut parked = posts.clone();
    for _ in 0..12 {
        parked.extend(rig.step(&[]));
    }
    assert!(
        parked
            .iter()
            .filter(|p| p.key == "IVPHELM_STATE")
            .all(|p| is_str(Some(&p.value), "PARK"))
    );
    assert_eq!(
        all(&parked, "IVPHELM_ALLSTOP")
            .iter()
            .map(|v| v.as_str().unwrap())
            .collect::<Vec<_>>(),
        ["ManualOverride"]
    );
    assert_eq!(all(&parked, "DESIRED_SPEED"), [&Value::Double(0.0)]);
    assert!(
        get(&parked, "IVPHELM_SUMMARY").is_none(),
        "no decisions while parked"
    );

    let t = rig.t;
    let posts = rig.step(&[Mail::new("MOOS_MANUAL_OVERRIDE", "false", t).from("uPokeDB")]);
    assert!(is_str(get(&posts, "IVPHELM_STATE"), "DRIVE"));
    assert_eq!(rig.helm.state(), HelmState::Drive);
    // First decision iteration: configflag CRUISE_SPD = $[SPEED], a lone numeric macro, is a
    // double; the survey waits for DEPLOY (its failed condition in BHV_STATUS).
    assert_eq!(get(&posts, "CRUISE_SPD"), Some(&Value::Double(3.0)));
    assert!(
        all(&posts, "BHV_STATUS").iter().any(
            |v| v.as_str() == Some("name=waypt_survey,pc=DEPLOY = true,state=idle,updates=0/0")
        )
    );

    // --- DEPLOY=false: nothing to do. First iteration is the grace one, zeros on the second.
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "NothingToDo"));
    assert!(get(&posts, "DESIRED_HEADING").is_none());
    let posts = rig.step(&[]);
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "NothingToDo"));
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(0.0)));
    let summary = get(&posts, "IVPHELM_SUMMARY")
        .unwrap()
        .as_str()
        .unwrap()
        .to_string();
    assert!(summary.starts_with("iter="), "{summary}");
    let posts = rig.step(&[]);
    assert!(
        get(&posts, "IVPHELM_ALLSTOP").is_none(),
        "all-stop only on change"
    );

    // --- DEPLOY=true: the survey runs; decisions every iteration.
    let t = rig.t;
    let posts = rig.step(&[Mail::new("DEPLOY", "true", t).from("uPokeDB")]);
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "clear"));
    assert!(is_str(get(&posts, "IVPHELM_BHV_ACTIVE"), "waypt_survey"));
    assert!(get(&posts, "CRUISE_SPD").is_none(), "configflags once");
    assert_eq!(all(&posts, "INFO").len(), 3, "three activeflags");
    assert!(is_str(get(&posts, "INFO"), "alpha"));
    let hdg = get(&posts, "DESIRED_HEADING").unwrap().as_f64().unwrap();
    let spd = get(&posts, "DESIRED_SPEED").unwrap().as_f64().unwrap();
    // First point (60,-40) lies east-south-east of (0,-20): bearing ~108 degrees.
    assert!((95.0..=125.0).contains(&hdg), "first course {hdg}");
    // use_alt_speed = true with speed_alt = 1.2.
    assert!((spd - 1.2).abs() < 1e-9, "survey speed {spd}");
    // wptflag_on_start: the flags are posted when the behaviour starts.
    assert!(
        is_str(get(&posts, "NEXT"), "60,-40"),
        "{:?}",
        get(&posts, "NEXT")
    );
    assert!(get(&posts, "OSPOS").is_some());

    // --- Survey the five points in order until the endflag RETURN=true.
    let mut indices: Vec<f64> = Vec::new();
    let posts = rig.run_until(900.0, "RETURN=true", |p| {
        p.iter()
            .any(|x| x.key == "RETURN" && x.value.as_str() == Some("true"))
    });
    for (_, p) in &rig.log {
        if p.key == "WPT_INDEX" {
            indices.push(p.value.as_f64().unwrap());
        }
    }
    assert_eq!(indices, [0.0, 1.0, 2.0, 3.0, 4.0], "waypoints in order");
    assert!(
        all(&posts, "WPT_STAT")
            .iter()
            .any(|v| v.as_str() == Some("behavior-name=waypt_survey,completed")),
        "{posts:?}"
    );
    let summary = get(&posts, "SUMMARY").unwrap().as_str().unwrap();
    assert!(summary.starts_with("speed=3,time="), "{summary}");
    // The completing iteration has no objective function: the grace all-stop, no zeros.
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "NothingToDo"));
    assert!(get(&posts, "DESIRED_HEADING").is_none());
    let survey_end = rig.t;
    // The vehicle really went round: it ended near the last point (150,-40).
    assert!(
        (rig.vehicle.x - 150.0).hypot(rig.vehicle.y + 40.0) < 16.0,
        "vehicle at {:.1},{:.1}",
        rig.vehicle.x,
        rig.vehicle.y
    );

    // --- Return leg: the next iteration the return behaviour drives at 2 m/s to (0,-20).
    let posts = rig.step(&[]);
    assert!(
        is_str(get(&posts, "IVPHELM_BHV_ACTIVE"), "waypt_return"),
        "{posts:?}"
    );
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "clear"));
    let spd = get(&posts, "DESIRED_SPEED").unwrap().as_f64().unwrap();
    assert!((spd - 2.0).abs() < 1e-9, "return speed {spd}");
    let posts = rig.run_until(600.0, "MISSION=complete", |p| {
        p.iter()
            .any(|x| x.key == "MISSION" && x.value.as_str() == Some("complete"))
    });
    assert!(is_str(get(&posts, "DEPLOY"), "false"));
    assert!(
        posts.iter().position(|p| p.key == "RETURN").unwrap()
            < posts.iter().position(|p| p.key == "MISSION").unwrap(),
        "endflags in file order"
    );
    assert!((rig.vehicle.x).hypot(rig.vehicle.y + 20.0) < 9.0);
    assert!(rig.t > survey_end);
    assert!(
        is_str(get(&posts, "IVPHELM_BHV_ACTIVE"), ""),
        "no behaviour active any more"
    );
    assert!(is_str(get(&posts, "IVPHELM_BHV_RUNNING"), "waypt_return"));

    // --- Then nothing to do: the completing iteration is the grace one, zeros follow.
    assert!(
        is_str(get(&posts, "IVPHELM_ALLSTOP"), "NothingToDo"),
        "{posts:?}"
    );
    assert!(get(&posts, "DESIRED_SPEED").is_none());
    let posts = rig.step(&[]);
    assert!(
        is_str(get(&posts, "IVPHELM_ALLSTOP"), "NothingToDo"),
        "{posts:?}"
    );
    assert_eq!(get(&posts, "DESIRED_SPEED"), Some(&Value::Double(0.0)));
    assert_eq!(get(&posts, "DESIRED_HEADING"), Some(&Value::Double(0.0)));
    // DEPLOY=false (an endflag) now makes every behaviour idle.
    assert!(is_str(get(&posts, "IVPHELM_BHV_RUNNING"), ""));
    assert!(is_str(
        get(&posts, "IVPHELM_BHV_IDLE"),
        "waypt_survey,waypt_return,const_speed"
    ));
    let posts = rig.step(&[]);
    assert!(get(&posts, "DESIRED_SPEED").is_none(), "zeros posted once");
    assert_eq!(rig.helm.info().text("MISSION"), Some("complete"));
}

use behaviors::Info as _;
