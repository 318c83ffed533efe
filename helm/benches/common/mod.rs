//! The alpha helm driven to mid-survey: the fixture shared by the `iteration` bench and the
//! `iterate_loop` callgrind driver.

use helm::{Helm, Mail, Value};
use mission::source::SourceMap;

/// The four navigation variables at time `t`.
pub fn nav(x: f64, y: f64, h: f64, v: f64, t: f64) -> [Mail; 4] {
    [
        Mail::new("NAV_X", x, t),
        Mail::new("NAV_Y", y, t),
        Mail::new("NAV_HEADING", h, t),
        Mail::new("NAV_SPEED", v, t),
    ]
}

/// The alpha helm driven to mid-survey by a point-mass vehicle; returns it with the time.
pub fn mid_survey() -> (Helm, f64, (f64, f64, f64, f64)) {
    let moos = mission::moos::parse_moos(&SourceMap::from_text(
        "alpha.moos",
        &test_support::mission_text("s1_alpha/alpha.moos"),
    ));
    let bhv = mission::bhv::parse_bhv(&SourceMap::from_text(
        "alpha.bhv",
        &test_support::mission_text("s1_alpha/alpha.bhv"),
    ));
    let mut helm = Helm::from_mission(&moos.value, &bhv);
    assert!(helm.config_errors().is_empty());
    let (t, state) = fly_to_mid_survey(&mut helm);
    (helm, t, state)
}

/// Flies `helm` (alpha's, possibly with more behaviours) for 120 s with a point-mass vehicle,
/// the override lifted at 1 s and DEPLOY at 2 s; returns the time and the vehicle's
/// `(x, y, heading, speed)`.
pub fn fly_to_mid_survey(helm: &mut Helm) -> (f64, (f64, f64, f64, f64)) {
    let (mut x, mut y, mut h, mut v) = (0.0f64, -20.0f64, 180.0f64, 0.0f64);
    let (mut dh, mut dv) = (h, 0.0);
    let dt = 0.25;
    let mut t = 0.0;
    while t < 120.0 {
        t += dt;
        let err = (dh - h + 540.0).rem_euclid(360.0) - 180.0;
        h = (h + err.clamp(-10.0, 10.0)).rem_euclid(360.0);
        v += (dv - v).clamp(-0.125, 0.125);
        x += h.to_radians().sin() * v * dt;
        y += h.to_radians().cos() * v * dt;
        helm.on_mail(&nav(x, y, h, v, t));
        if (t - 1.0).abs() < 1e-9 {
            helm.on_mail(&[Mail::new("MOOS_MANUAL_OVERRIDE", "false", t)]);
        }
        if (t - 2.0).abs() < 1e-9 {
            helm.on_mail(&[Mail::new("DEPLOY", "true", t)]);
        }
        for p in helm.iterate(t) {
            match (&*p.key, &p.value) {
                ("DESIRED_HEADING", Value::Double(d)) => dh = *d,
                ("DESIRED_SPEED", Value::Double(d)) => dv = *d,
                _ => {}
            }
        }
    }
    (t, (x, y, h, v))
}
