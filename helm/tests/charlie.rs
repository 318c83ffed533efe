//! The s3_charlie mission end to end: a counter-clockwise BHV_Loiter around a radial polygon,
//! then a return waypoint and station keeping, with a kinematic stand-in for the vehicle.

mod common;

use common::{Rig, Vehicle, get, is_str};
use helm::{Helm, Mail};
use mission::source::SourceMap;
use test_support::mission_text;

use geometry::angle_180;

#[test]
fn charlie_loiters_counter_clockwise_then_returns() {
    let moos = mission::moos::parse_moos(&SourceMap::from_text(
        "charlie.moos",
        &mission_text("s3_charlie/charlie.moos"),
    ));
    let bhv = mission::bhv::parse_bhv(&SourceMap::from_text(
        "charlie.bhv",
        &mission_text("s3_charlie/charlie.bhv"),
    ));
    let helm = Helm::from_mission(&moos.value, &bhv);
    assert!(
        helm.config_errors().is_empty(),
        "{:?}",
        helm.config_errors()
    );
    let mut rig = Rig::new(helm, Vehicle::new(0.0, -10.0, 180.0));
    for _ in 0..6 {
        rig.step(&[]);
    }
    let t = rig.t;
    let posts = rig.step(&[
        Mail::new("MOOS_MANUAL_OVERRIDE", "false", t),
        Mail::new("DEPLOY", "true", t),
    ]);
    assert!(
        is_str(get(&posts, "IVPHELM_BHV_ACTIVE"), "loiter"),
        "{posts:?}"
    );
    assert!(is_str(get(&posts, "MODE"), "ACTIVE:LOITERING"));
    // speed 1.3 is between grid values (0.2 m/s steps): the lower of the tied neighbours.
    let spd = get(&posts, "DESIRED_SPEED").unwrap().as_f64().unwrap();
    assert!((spd - 1.2).abs() < 1e-9, "{spd}");
    let poly = get(&posts, "VIEW_POLYGON").unwrap().as_str().unwrap();
    assert!(poly.contains("label=LOITER_POLYGON"), "{poly}");

    // Loiter for 400 s: the bearing from the polygon centre (0,-75) to the vehicle must wind
    // counter-clockwise (decreasing compass bearing) for more than one full lap, and every
    // vertex index must come up.
    let mut winding = 0.0;
    let bearing = |x: f64, y: f64| x.atan2(y + 75.0).to_degrees();
    let mut last = bearing(rig.vehicle.x, rig.vehicle.y);
    let mut seen = [false; 6];
    let start = rig.t;
    let mut max_off = 0.0f64;
    while rig.t < start + 400.0 {
        let posts = rig.step(&[]);
        if let Some(v) = get(&posts, "LOITER_INDEX") {
            seen[v.as_f64().unwrap() as usize] = true;
        }
        let b = bearing(rig.vehicle.x, rig.vehicle.y);
        winding += angle_180(b - last);
        last = b;
        if rig.t > start + 120.0 {
            let r = rig.vehicle.x.hypot(rig.vehicle.y + 75.0);
            max_off = max_off.max((r - 37.0).abs());
        }
    }
    assert!(
        winding < -360.0,
        "winding {winding} degrees (counter-clockwise is negative)"
    );
    assert_eq!(seen, [true; 6], "every vertex sought");
    assert!(
        max_off < 15.0,
        "stays near the polygon once acquired: {max_off}"
    );

    // RETURN=true: MODE becomes ACTIVE:RETURNING and the return waypoint drives to (15,0).
    let t = rig.t;
    let posts = rig.step(&[Mail::new("RETURN", "true", t)]);
    assert!(is_str(get(&posts, "MODE"), "ACTIVE:RETURNING"), "{posts:?}");
    assert!(is_str(get(&posts, "IVPHELM_BHV_ACTIVE"), "waypt_return"));
    // The loiter, now idle, erases its viewer objects.
    assert!(
        posts.iter().any(|p| p.key == "VIEW_POLYGON"
            && p.value.as_str().is_some_and(|s| s.contains("active=false")))
    );
    rig.run_until(400.0, "STATION_KEEP=true", |p| {
        p.iter()
            .any(|x| x.key == "STATION_KEEP" && x.value.as_str() == Some("true"))
    });
    assert!((rig.vehicle.x - 15.0).hypot(rig.vehicle.y) < 16.0);
    let posts = rig.step(&[]);
    assert!(
        is_str(get(&posts, "MODE"), "ACTIVE:STATION-KEEPING"),
        "{posts:?}"
    );
}
