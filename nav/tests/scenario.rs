//! The synthetic closed-form scenario: a lawnmower at 1.5 m/s, 3-5 m deep, surfacing every 300 s
//! for GPS (1.5 m noise), a 3 degree heading bias, a 0.1 m/s current, DVL noise.

mod common;
use common::truth::{Event, Scenario, Sim, feed};
use nav::{DeadReckoner, NavConfig, Navigator, VelocityReference};

struct Outcome {
    /// (estimate error, dead-reckoning error) at each resurfacing, before the first fix.
    dives: Vec<(f64, f64)>,
    /// Worst bias error (deg) and current error (m/s) from 30 s after the first resurfacing.
    worst_bias_deg: f64,
    worst_current_mps: f64,
    /// Worst error at the surface 5 s or more after a resurfacing (from the first resurfacing).
    worst_surface_m: f64,
    /// Worst error anywhere from 30 s after the first resurfacing.
    worst_after_m: f64,
    reports: usize,
}

fn run(sc: Scenario, end_s: f64) -> Outcome {
    let (bias, current) = (sc.bias_rad, sc.current);
    let cycle = sc.surface_s + sc.dive_s;
    let mut sim = Sim::new(sc);
    let mut nav = Navigator::new(NavConfig::default());
    let mut dr = DeadReckoner::new();
    let mut out = Outcome {
        dives: Vec::new(),
        worst_bias_deg: 0.0,
        worst_current_mps: 0.0,
        worst_surface_m: 0.0,
        worst_after_m: 0.0,
        reports: 0,
    };
    let mut was_submerged = false;
    let mut surfaced_at = f64::NAN;
    let first_resurface = cycle;
    loop {
        let e = sim.next_event();
        let t = e.t_s();
        if t > end_s {
            break;
        }
        let tr = sim.truth();
        if let Event::Gps(_) = e {
            if was_submerged {
                let est = nav.estimate().unwrap();
                let d = dr.position_at(t).unwrap();
                out.dives.push((
                    (est.x_m - tr.x_m).hypot(est.y_m - tr.y_m),
                    (d[0] - tr.x_m).hypot(d[1] - tr.y_m),
                ));
                surfaced_at = t;
            }
            was_submerged = false;
        } else if tr.depth_m > 1.0 {
            was_submerged = true;
        }
        feed(&mut nav, &mut dr, &e);
        if nav.take_dive_report().is_some() {
            out.reports += 1;
        }
        let Some(est) = nav.estimate() else { continue };
        let err = (est.x_m - tr.x_m).hypot(est.y_m - tr.y_m);
        if t > first_resurface + 30.0 {
            out.worst_bias_deg = out
                .worst_bias_deg
                .max((est.heading_bias_rad - bias).to_degrees().abs());
            out.worst_current_mps = out
                .worst_current_mps
                .max((est.current_east_mps - current[0]).hypot(est.current_north_mps - current[1]));
            out.worst_after_m = out.worst_after_m.max(err);
        }
        if tr.depth_m < 0.2 && t - surfaced_at >= 5.0 {
            out.worst_surface_m = out.worst_surface_m.max(err);
        }
    }
    out
}

#[test]
fn water_track_bias_and_current_are_estimated_and_beat_dead_reckoning() {
    let sc = Scenario::default();
    assert!(((sc.current[0]).hypot(sc.current[1]) - 0.1).abs() < 1e-12);
    let o = run(sc, 1850.0);
    println!(
        "dives (est, dr) {:?}; bias {:.3} deg, current {:.4} m/s, surface {:.2} m, after {:.2} m",
        o.dives, o.worst_bias_deg, o.worst_current_mps, o.worst_surface_m, o.worst_after_m
    );
    assert_eq!(o.dives.len(), 5);
    assert_eq!(o.reports, 5);
    for (k, (est, dr)) in o.dives.iter().enumerate() {
        assert!(
            est < dr,
            "dive {}: estimate {est} m, dead reckoning {dr} m",
            k + 1
        );
    }
    assert!(
        o.worst_bias_deg < 0.5,
        "bias error {} deg",
        o.worst_bias_deg
    );
    assert!(
        o.worst_current_mps < 0.03,
        "current error {}",
        o.worst_current_mps
    );
    // Within two sigma of the GPS noise (1.5 m) once the fixes are in.
    assert!(
        o.worst_surface_m < 3.0,
        "surface error {}",
        o.worst_surface_m
    );
    assert!(
        o.worst_after_m < 3.0,
        "error after the first surfacing {}",
        o.worst_after_m
    );
}

#[test]
fn bottom_lock_bias_is_estimated() {
    // Over ground, the current does not move the vehicle's DVL track: only the bias matters.
    let sc = Scenario {
        reference: VelocityReference::Ground,
        seed: 3,
        ..Scenario::default()
    };
    let o = run(sc, 1130.0);
    println!(
        "bottom lock: dives {:?}; bias {:.3} deg",
        o.dives, o.worst_bias_deg
    );
    assert!(
        o.worst_bias_deg < 0.5,
        "bias error {} deg",
        o.worst_bias_deg
    );
    for (est, dr) in &o.dives {
        assert!(est < dr);
    }
    assert!(o.worst_surface_m < 3.0);
}
