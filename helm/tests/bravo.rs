//! The s2_bravo mission end to end: hierarchical modes (ACTIVE:SURVEYING / ACTIVE:RETURNING /
//! INACTIVE) driving two waypoint behaviours, with a kinematic stand-in for the vehicle.

mod common;

use common::{Rig, Vehicle, get, is_str};
use helm::{Helm, Mail, Value};
use mission::source::SourceMap;
use test_support::mission_text;

#[test]
fn bravo_modes_survey_return_and_stop() {
    let moos = mission::moos::parse_moos(&SourceMap::from_text(
        "bravo.moos",
        &mission_text("s2_bravo/bravo.moos"),
    ));
    let bhv = mission::bhv::parse_bhv(&SourceMap::from_text(
        "bravo.bhv",
        &mission_text("s2_bravo/bravo.bhv"),
    ));
    let helm = Helm::from_mission(&moos.value, &bhv);
    assert!(
        helm.config_errors().is_empty(),
        "{:?}",
        helm.config_errors()
    );
    let mut rig = Rig::new(helm, Vehicle::new(0.0, -10.0, 180.0));

    let posts = rig.step(&[]);
    assert!(is_str(
        get(&posts, "IVPHELM_MODESET"),
        "MODE#---,ACTIVE#---,INACTIVE#ACTIVE,SURVEYING#ACTIVE,RETURNING"
    ));
    assert!(is_str(
        get(&posts, "IVPHELM_DOMAIN"),
        "speed,0,4,21:course,0,359,360"
    ));
    for _ in 0..5 {
        rig.step(&[]);
    }
    let t = rig.t;
    let posts = rig.step(&[Mail::new("MOOS_MANUAL_OVERRIDE", "false", t)]);
    let mode = posts.iter().find(|p| p.key == "MODE").unwrap();
    assert_eq!(
        (mode.value.as_str(), &*mode.aux),
        (Some("INACTIVE"), "HELM_MODE")
    );
    assert!(is_str(get(&posts, "IVPHELM_ALLSTOP"), "NothingToDo"));

    let t = rig.t;
    let posts = rig.step(&[Mail::new("DEPLOY", "true", t)]);
    assert!(is_str(get(&posts, "MODE"), "ACTIVE:SURVEYING"));
    assert!(is_str(get(&posts, "IVPHELM_BHV_ACTIVE"), "waypt_survey"));
    let summary = get(&posts, "IVPHELM_SUMMARY").unwrap().as_str().unwrap();
    assert!(
        summary.contains(",modes=MODE@ACTIVE:SURVEYING,"),
        "{summary}"
    );
    assert_eq!(get(&posts, "DESIRED_SPEED"), Some(&Value::Double(2.0)));

    // The survey ends with RETURN=true; the mode switches on the next iteration.
    rig.run_until(900.0, "RETURN=true", |p| {
        p.iter()
            .any(|x| x.key == "RETURN" && x.value.as_str() == Some("true"))
    });
    let indices: Vec<f64> = rig
        .log
        .iter()
        .filter(|(_, p)| p.key == "WPT_INDEX")
        .map(|(_, p)| p.value.as_f64().unwrap())
        .collect();
    assert_eq!(indices, [0.0, 1.0, 2.0, 3.0, 4.0]);
    let posts = rig.step(&[]);
    assert!(is_str(get(&posts, "MODE"), "ACTIVE:RETURNING"), "{posts:?}");
    assert!(is_str(get(&posts, "IVPHELM_BHV_ACTIVE"), "waypt_return"));

    // Back at (0,0): endflags RETURN=false and DEPLOY=false, then INACTIVE and all-stop.
    let posts = rig.run_until(600.0, "DEPLOY=false", |p| {
        p.iter()
            .any(|x| x.key == "DEPLOY" && x.value.as_str() == Some("false"))
    });
    assert!(is_str(get(&posts, "RETURN"), "false"));
    assert!(rig.vehicle.x.hypot(rig.vehicle.y) < 8.0);
    let posts = rig.step(&[]);
    assert!(is_str(get(&posts, "MODE"), "INACTIVE"), "{posts:?}");
    assert_eq!(get(&posts, "DESIRED_SPEED"), Some(&Value::Double(0.0)));
}
