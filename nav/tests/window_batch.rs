//! The window solver against a dense batch Gauss-Newton, and marginalisation against the full
//! batch on a linear problem.

mod common;
use common::truth::{Scenario, Sim, feed};
use nav::{DeadReckoner, NavConfig, Navigator, solve_batch};

fn converging(window: usize) -> NavConfig {
    NavConfig {
        window_size: window,
        max_iterations: 50,
        step_tolerance: 1e-12,
        ..NavConfig::default()
    }
}

fn fed(cfg: NavConfig, sc: Scenario, until_s: f64) -> Navigator {
    let mut sim = Sim::new(sc);
    let mut nav = Navigator::new(cfg);
    let mut dr = DeadReckoner::new();
    loop {
        let e = sim.next_event();
        if e.t_s() > until_s {
            return nav;
        }
        feed(&mut nav, &mut dr, &e);
    }
}

/// Starts the window and the batch from the same perturbed point and compares the optima.
fn window_equals_batch(mut nav: Navigator) {
    let (states, prior, factors) = nav.problem();
    assert!(states.len() > 10);
    let mut start = states.clone();
    for (k, x) in start.iter_mut().enumerate() {
        x[0] += 0.5 * (k as f64).sin();
        x[1] -= 0.3;
        x[3] += 0.02;
        x[4] -= 0.01;
        x[5] += 0.05;
    }
    let mut batch = start.clone();
    let iters = solve_batch(&mut batch, &prior, &factors, 100, 1e-12).unwrap();
    assert!(iters > 1 && iters < 100, "batch took {iters} iterations");
    nav.resolve_from(&start);
    let window = nav.window_states();
    assert_eq!(window.len(), batch.len());
    for ((_, w), b) in window.iter().zip(&batch) {
        for k in 0..7 {
            assert!((w[k] - b[k]).abs() < 1e-6, "{} vs {}", w[k], b[k]);
        }
    }
}

#[test]
fn window_solve_equals_batch_before_marginalising() {
    // 8 s at the surface: GPS, AHRS, DVL, depth, gyro; 40 keyframes, none marginalised.
    let nav = fed(converging(200), Scenario::default(), 8.0);
    assert_eq!(nav.window_len() as u64, nav.keyframes());
    window_equals_batch(nav);
}

#[test]
fn window_solve_equals_batch_with_a_marginal_prior() {
    // Through a dive and back: the window (20) carries the prior of ~1900 marginalised keyframes.
    let nav = fed(converging(20), Scenario::default(), 380.0);
    assert_eq!(nav.window_len(), 20);
    assert!(nav.keyframes() > 1000);
    window_equals_batch(nav);
}

#[test]
fn marginalisation_is_exact_on_a_linear_problem() {
    // A vehicle that does not move through the water (zero DVL velocity, no tilt) drifts with the
    // current: every factor is then linear (the heading never multiplies a velocity) and the
    // Huber kernel and gate are opened, so the fixed-lag answer must equal the full batch.
    let sc = Scenario {
        speed_mps: 0.0,
        dvl_sigma_mps: 0.0,
        tilt_sigma_rad: 0.0,
        current: [0.1, -0.05],
        ..Scenario::default()
    };
    let linear = |window| NavConfig {
        gps_huber_k: 1e12,
        gps_gate_chi2: 1e30,
        ..converging(window)
    };
    let small = fed(linear(6), sc.clone(), 50.0);
    let full = fed(linear(100_000), sc, 50.0);
    assert_eq!(small.keyframes(), full.keyframes());
    assert!(full.window_len() > 200 && small.window_len() == 6);
    let (ws, wf) = (small.window_states(), full.window_states());
    // Every keyframe still in the small window equals the batch's smoothed keyframe.
    let offset = wf.len() - ws.len();
    for (k, (t, x)) in ws.iter().enumerate() {
        let (tf, xf) = wf[offset + k];
        assert_eq!(*t, tf);
        for c in 0..7 {
            assert!(
                (x[c] - xf[c]).abs() < 1e-6,
                "keyframe {k} state {c}: {} vs {}",
                x[c],
                xf[c]
            );
        }
    }
    let (a, b) = (small.estimate().unwrap(), full.estimate().unwrap());
    assert!((a.pos_sigma_m - b.pos_sigma_m).abs() < 1e-6);
    assert!((a.current_east_mps - b.current_east_mps).abs() < 1e-6);
    assert!((a.current_east_mps - 0.1).abs() < 0.05);
    // And the full window itself is the dense batch optimum.
    window_equals_batch(full);
}
