//! Solver benchmarks on the helm-like problems of `common/mod.rs`.
//!
//! Run with `cargo bench -p ivp --bench solver`; piece counts are printed once.

use criterion::{Criterion, criterion_group, criterion_main};
use ivp::Solver;

mod common;
use common::{problem_a, problem_b};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    for (name, p) in [
        ("a_course_speed", problem_a()),
        ("b_course_speed_depth", problem_b()),
    ] {
        let counts: Vec<String> = p
            .functions()
            .map(|(o, f)| format!("{o}={}", f.piece_count()))
            .collect();
        let mut solver = Solver::new();
        let dec = solver.solve(&p).unwrap();
        eprintln!(
            "{name}: pieces [{}], nodes {}, decision {:?}",
            counts.join(", "),
            solver.nodes_visited(),
            dec.vars
                .iter()
                .map(|v| (v.name.as_str(), v.value))
                .collect::<Vec<_>>()
        );
        c.bench_function(name, |b| b.iter(|| black_box(solver.solve(black_box(&p)))));
        let mut plain = Solver::new().with_seeding(false);
        plain.solve(&p);
        eprintln!(
            "{name}: nodes without the seed threshold {}",
            plain.nodes_visited()
        );
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
