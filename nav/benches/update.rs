//! One keyframe update (a DVL report: new keyframe, Gauss-Newton on the default window of 20,
//! marginalisation of the oldest) in the lawnmower scenario, mid-dive and at the surface.
//!
//! Run with `cargo bench -p nav --bench update`.

#[path = "../tests/common/truth.rs"]
mod truth;

use criterion::{Criterion, criterion_group, criterion_main};
use nav::{NavConfig, Navigator};
use std::time::{Duration, Instant};
use truth::{Event, Scenario, Sim};

/// Feeds events until the next DVL report, which is returned untimed-fed.
fn until_dvl(sim: &mut Sim, nav: &mut Navigator) -> nav::DvlVelocity {
    loop {
        match sim.next_event() {
            Event::Dvl(m) => return m,
            Event::Att(m) => drop(nav.attitude(&m)),
            Event::Gyro(m) => drop(nav.gyro(&m)),
            Event::Depth(m) => drop(nav.depth(&m)),
            Event::Gps(m) => drop(nav.gps(&m)),
        }
    }
}

fn bench(c: &mut Criterion) {
    let mut sim = Sim::new(Scenario::default());
    let mut nav = Navigator::new(NavConfig::default());
    // Warm up through the first dive and surfacing.
    while sim.truth().t_s < 450.0 {
        let m = until_dvl(&mut sim, &mut nav);
        let _ = nav.dvl(&m);
    }
    c.bench_function("keyframe_update_window20", |b| {
        b.iter_custom(|iters| {
            let mut total = Duration::ZERO;
            for _ in 0..iters {
                let m = until_dvl(&mut sim, &mut nav);
                let s = Instant::now();
                let _ = std::hint::black_box(nav.dvl(&m));
                total += s.elapsed();
            }
            total
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
