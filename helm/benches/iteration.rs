//! One full helm iteration on the real alpha.bhv (course x speed domain) with the vehicle
//! mid-survey: mail in, modes, three behaviours, the waypoint's objective function, the solve,
//! and all postings.

use criterion::{Criterion, criterion_group, criterion_main};

mod common;
use common::{mid_survey, nav};

fn bench(c: &mut Criterion) {
    let (mut helm, mut t, (x, y, h, v)) = mid_survey();
    assert!(
        helm.iterate(t + 0.25)
            .iter()
            .any(|p| p.key == "DESIRED_HEADING"),
        "the survey must be running"
    );
    t += 0.25;
    c.bench_function("helm_iteration_alpha_mid_survey", |b| {
        b.iter(|| {
            t += 0.25;
            helm.on_mail(&nav(x, y, h, v, t));
            helm.iterate(t).len()
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
