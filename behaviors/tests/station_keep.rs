//! BHV_StationKeep: speeds at the radii, course to the station, activation, hibernation.

mod support;

use behaviors::{KeepMode, ParamError, StationKeep, Value};
use support::{Bhv, decide, posted, posted_all, uuv_domain};

fn keep(params: &[(&str, &str)]) -> Bhv {
    Bhv::new("BHV_StationKeep", "skeep", uuv_domain()).config(params)
}

/// Course and speed the behaviour alone decides with ownship at (x, y).
fn decision(b: &mut Bhv, t: f64, x: f64, y: f64) -> Option<(f64, f64)> {
    b.nav(x, y, 0.0, 1.0, 0.0);
    let f = b.run(t).0?;
    let d = decide(&b.domain, &[("sk", f, 100.0)]);
    Some((d.get("course").unwrap(), d.get("speed").unwrap()))
}

#[test]
fn speeds_switch_at_the_inner_and_outer_radii() {
    let mut b = keep(&[
        ("station_pt", "0,0"),
        ("inner_radius", "4"),
        ("outer_radius", "14"),
        ("outer_speed", "1.2"),
        ("transit_speed", "2.5"),
    ]);
    // Inside the inner radius: stop.
    assert_eq!(decision(&mut b, 0.0, 0.0, -3.0).unwrap().1, 0.0);
    // Between the radii: linear from 0 to the outer speed, course toward the station.
    let (crs, spd) = decision(&mut b, 1.0, 0.0, -9.0).unwrap();
    assert_eq!(crs, 0.0);
    assert!((spd - 0.6).abs() < 1e-9, "{spd}");
    let (crs, spd) = decision(&mut b, 2.0, -13.0, 0.0).unwrap();
    assert_eq!(crs, 90.0);
    assert!((spd - 1.1).abs() < 1e-9, "{spd}");
    // At and beyond the outer radius: transit speed.
    let (crs, spd) = decision(&mut b, 3.0, 30.0, 30.0).unwrap();
    assert_eq!(crs, 225.0);
    assert_eq!(spd, 2.5);
    assert_eq!(decision(&mut b, 4.0, 0.0, 14.0).unwrap().1, 2.5);
    let (_, out) = b.run(5.0);
    assert_eq!(posted(&out, "DIST_TO_STATION"), Some(&Value::Double(14.0)));
    // MOOS-IvP a2a9b716: setting the station hibernates once even without a hibernation
    // radius; outside radius -1 the next iteration seeks (speeds as above).
    assert_eq!(
        posted(&out, "PSKEEP_MODE"),
        Some(&Value::String("SEEKING_STATION".into()))
    );
    let circles: Vec<String> = posted_all(&out, "VIEW_POLYGON")
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect();
    assert_eq!(circles.len(), 2, "outer and inner: {circles:?}");
    assert!(circles[0].starts_with("radial:: x=0.0,y=0.0,source=abe:skeep,pts=32"));
    assert!(circles[0].ends_with("label=abe:station-keep-out,radius=14.0"));
    assert!(circles[1].ends_with("label=abe:station-keep-in,radius=4.0"));
    // Stopping erases them.
    let out = b.stop(6.0);
    assert!(
        posted_all(&out, "VIEW_POLYGON")
            .iter()
            .all(|v| v.as_str().unwrap().ends_with("active=false"))
    );
}

#[test]
fn center_activate_holds_where_it_was_activated() {
    let mut b = keep(&[("center_activate", "true"), ("swing_time", "2")]);
    b.nav(100.0, 50.0, 0.0, 1.0, 0.0);
    let (_, out) = b.start(10.0);
    assert!(
        matches!(posted(&out, "BHV_SETTINGS"), Some(Value::String(s)) if s.contains("center_activate=true"))
    );
    // During the swing time the station follows the vehicle.
    assert_eq!(decision(&mut b, 11.0, 101.0, 50.0).unwrap().1, 0.0);
    assert_eq!(decision(&mut b, 12.0, 102.0, 50.0).unwrap().1, 0.0);
    let sk_station = |b: &mut Bhv| {
        let (_, out) = b.run(12.5);
        posted(&out, "DIST_TO_STATION").unwrap().as_f64().unwrap()
    };
    // After it, the station stays at (102, 50).
    b.nav(122.0, 50.0, 0.0, 1.0, 0.0);
    assert_eq!(sk_station(&mut b), 20.0);
    let (crs, spd) = decision(&mut b, 13.0, 122.0, 50.0).unwrap();
    assert_eq!((crs, spd), (270.0, 2.5));
    // Deactivated and reactivated elsewhere: a new station.
    b.stop(14.0);
    b.nav(0.0, 0.0, 0.0, 1.0, 0.0);
    b.start(20.0);
    decision(&mut b, 22.5, 0.0, 0.0);
    assert_eq!(decision(&mut b, 30.0, 10.0, 0.0).unwrap().0, 270.0);
}

#[test]
fn hibernation_until_drifting_out_then_seek_the_inner_radius() {
    let mut b = keep(&[
        ("station_pt", "0,0"),
        ("hibernation_radius", "25"),
        ("inner_radius", "4"),
        ("outer_radius", "15"),
    ]);
    // Drifting inside the hibernation radius: no thrust even beyond the outer radius.
    assert_eq!(decision(&mut b, 0.0, 0.0, 20.0).unwrap().1, 0.0);
    let (_, out) = b.run(1.0);
    assert_eq!(
        posted(&out, "PSKEEP_MODE"),
        Some(&Value::String("HIBERNATING".into()))
    );
    assert_eq!(decision(&mut b, 2.0, 0.0, 24.0).unwrap().1, 0.0);
    // Out of it: seek the station at transit speed ...
    assert_eq!(decision(&mut b, 3.0, 0.0, 26.0).unwrap(), (180.0, 2.5));
    let (_, out) = b.run(3.5);
    assert_eq!(
        posted(&out, "PSKEEP_MODE"),
        Some(&Value::String("SEEKING_STATION".into()))
    );
    // ... and keep seeking inside the hibernation radius while closing in ...
    let mut t = 4.0;
    let mut y = 24.0;
    while y > 5.0 {
        let (_, spd) = decision(&mut b, t, 0.0, y).unwrap();
        assert!(spd > 0.0, "seeking at y={y}");
        t += 1.0;
        y -= 2.0;
    }
    // ... until inside the inner radius: hibernating again.
    assert_eq!(decision(&mut b, t, 0.0, 3.0).unwrap().1, 0.0);
    let (_, out) = b.run(t + 1.0);
    assert_eq!(
        posted(&out, "PSKEEP_MODE"),
        Some(&Value::String("HIBERNATING".into()))
    );
    // Drifting within the hibernation radius stays stopped.
    assert_eq!(decision(&mut b, t + 2.0, 0.0, 18.0).unwrap().1, 0.0);
}

#[test]
fn stalled_progress_inside_the_hibernation_radius_ends_the_seek() {
    let mut b = keep(&[("station_pt", "0,0"), ("hibernation_radius", "25")]);
    decision(&mut b, 0.0, 0.0, 20.0);
    decision(&mut b, 1.0, 0.0, 30.0);
    assert_eq!(
        posted(&b.run(1.5).1, "PSKEEP_MODE"),
        Some(&Value::String("SEEKING_STATION".into()))
    );
    // Closing in for more than 5 s inside the radius: progress noted ...
    let mut t = 2.0;
    for y in [24.0, 22.0, 20.0, 18.0, 16.0, 14.0, 12.0] {
        decision(&mut b, t, 0.0, y);
        t += 1.0;
    }
    // ... then pushed back (a current) for more than 5 s: progress ended, hibernate.
    for y in [12.5, 13.0, 13.5, 14.0, 14.5, 15.0, 15.5] {
        decision(&mut b, t, 0.0, y);
        t += 1.0;
    }
    assert_eq!(
        posted(&b.run(t).1, "PSKEEP_MODE"),
        Some(&Value::String("HIBERNATING".into()))
    );
}

#[test]
fn no_station_and_bad_values() {
    let mut b = keep(&[]);
    b.nav(0.0, 0.0, 0.0, 0.0, 0.0);
    let (f, out) = b.run(0.0);
    assert!(f.is_none());
    assert!(
        matches!(posted(&out, "BHV_WARNING"), Some(Value::String(s)) if s.contains("STATION_POINT_NOT_SET"))
    );
    for (p, v) in [
        ("station_pt", "here"),
        ("inner_radius", "0"),
        ("outer_radius", "-3"),
        ("outer_speed", "fast"),
        ("transit_speed", "0"),
        ("hibernation_radius", "-5"),
        ("center_activate", "yes"),
        ("swing_time", "long"),
    ] {
        assert!(
            matches!(b.set(p, v), Err(ParamError::BadValue { .. })),
            "{p} = {v}"
        );
    }
    // outer_speed raises the transit speed if needed; swing_time clips to 60 s.
    b.set("transit_speed", "1").unwrap();
    b.set("outer_speed", "1.5").unwrap();
    b.set("point", "x=5,y=5").unwrap();
    assert_eq!(b.run(1.0).1.error, None);
    let d = StationKeep::new();
    assert_eq!(
        (
            d.inner_radius,
            d.outer_radius,
            d.outer_speed,
            d.transit_speed
        ),
        (4.0, 15.0, 1.2, 2.5)
    );
    assert_eq!(d.mode(), KeepMode::Disabled);
    assert_eq!(decision(&mut b, 2.0, 5.0, 100.0).unwrap().1, 1.5);
}

#[test]
fn station_set_iteration_as_the_cpp_state_machine() {
    let mut b = keep(&[("station_pt", "x=12,y=-121"), ("inner_radius", "4")]);
    // First running iteration: the station is set; distance not yet measured (-1), mode
    // HIBERNATING, speed 0 whatever the distance.
    b.nav(12.0, -61.0, 0.0, 1.0, 0.0);
    let (f, out) = b.run(0.0);
    assert_eq!(posted(&out, "DIST_TO_STATION"), Some(&Value::Double(-1.0)));
    assert_eq!(
        posted(&out, "PSKEEP_MODE"),
        Some(&Value::String("HIBERNATING".into()))
    );
    let d = decide(&b.domain, &[("sk", f.unwrap(), 100.0)]);
    assert_eq!(d.get("speed"), Some(0.0));
    // Then 60 m away: seek at the transit speed.
    let (crs, spd) = decision(&mut b, 1.0, 12.0, -61.0).unwrap();
    assert_eq!((crs, spd), (180.0, 2.5));
    // Inside the inner radius the seek ends (HIBERNATING), and with no hibernation radius the
    // next iteration seeks again: the C++ toggles between the two while on station.
    let modes: Vec<String> = (0..3)
        .map(|k| {
            b.nav(12.0, -119.0, 0.0, 1.0, 0.0);
            let (_, out) = b.run(2.0 + k as f64);
            posted(&out, "PSKEEP_MODE")
                .unwrap()
                .as_str()
                .unwrap()
                .to_string()
        })
        .collect();
    assert_eq!(modes, ["HIBERNATING", "SEEKING_STATION", "HIBERNATING"]);
}

#[test]
fn inner_beyond_outer_raises_the_outer_radius_and_hint_sizes_are_compact() {
    let mut b = keep(&[
        ("station_pt", "0,0"),
        ("inner_radius", "20"),
        ("outer_radius", "10"),
        ("visual_hints", "edge_size=2.5, vertex_size=3"),
    ]);
    b.nav(0.0, -50.0, 0.0, 1.0, 0.0);
    b.run(0.0);
    let (_, out) = b.run(1.0);
    let circles: Vec<&str> = posted_all(&out, "VIEW_POLYGON")
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    // Outer radius raised to 20; the collapsed inner circle is not drawn.
    assert_eq!(
        circles,
        [
            "radial:: x=0.0,y=0.0,source=abe:skeep,pts=32,edge_size=2.5,vertex_size=3,\
          edge_color=light_blue,label_color=white,vertex_color=red,\
          label=abe:station-keep-out,radius=20.0"
        ]
    );
}

#[test]
fn without_a_station_the_circles_are_erased_at_the_origin() {
    let mut b = keep(&[]);
    b.nav(5.0, 5.0, 0.0, 1.0, 0.0);
    let (f, out) = b.run(0.0);
    assert!(f.is_none());
    // MOOS measures to its unset station (0,0) all the same.
    assert_eq!(
        posted(&out, "DIST_TO_STATION"),
        Some(&Value::Double(50f64.sqrt()))
    );
    let circles: Vec<&str> = posted_all(&out, "VIEW_POLYGON")
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert_eq!(circles.len(), 3, "{circles:?}");
    assert!(
        circles
            .iter()
            .all(|c| c.starts_with("radial:: x=0.0,y=0.0,") && c.ends_with(",active=false"))
    );
    assert!(circles[2].contains("label=abe:station-keep-hiber,radius=-1.0"));
}

#[test]
fn during_the_swing_time_the_course_is_ownship_heading() {
    let mut b = keep(&[("center_activate", "true"), ("swing_time", "5")]);
    b.nav(0.0, 0.0, 135.0, 1.0, 0.0);
    b.run(0.0);
    b.nav(3.0, -3.0, 135.0, 1.0, 0.0);
    let (f, _) = b.run(1.0);
    let d = decide(&b.domain, &[("sk", f.unwrap(), 100.0)]);
    assert_eq!(d.get("course"), Some(135.0));
}

#[test]
fn settings_are_posted_on_each_start_in_the_cpp_format() {
    let mut b = keep(&[
        ("point", "x=12,y=-121"),
        ("hibernation_radius", "30"),
        ("outer_speed", "1.25"),
    ]);
    b.nav(0.0, 0.0, 0.0, 1.0, 0.0);
    let (_, out) = b.start(0.0);
    assert_eq!(
        posted(&out, "BHV_SETTINGS"),
        Some(&Value::String(
            "type=BHV_StationKeep,name=skeep,x=12.00,y=-121.00,inner_radius=4.0,\
             outer_radius=15.0,hibernation_radius=30.0,outer_speed=1.2,center_activate=false"
                .into()
        ))
    );
}

#[test]
fn visual_hints_with_unknown_colours_or_bad_sizes_are_ignored() {
    let mut b = keep(&[
        ("station_pt", "0,0"),
        ("inner_radius", "5"),
        ("outer_radius", "10"),
        (
            "visual_hints",
            "edge_color=reddish, vertex_color=hex:00,label_color=yellow, edge_size=-1, vertex_size=two",
        ),
    ]);
    b.nav(0.0, -50.0, 0.0, 1.0, 0.0);
    b.run(0.0);
    let (_, out) = b.run(1.0);
    let outer = posted_all(&out, "VIEW_POLYGON")
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .find(|s| s.contains("station-keep-out"))
        .unwrap();
    // `hex:00` is cut at its comma (MOOS splits the list first) and is not a colour; a
    // negative edge size is a number, so it applies (StationKeep does not check the sign) and
    // leaves the circle's edge size unset, so it is not written.
    assert_eq!(
        outer,
        "radial:: x=0.0,y=0.0,source=abe:skeep,pts=32,vertex_size=1,\
         edge_color=light_blue,label_color=yellow,vertex_color=red,\
         label=abe:station-keep-out,radius=10.0"
    );
}
