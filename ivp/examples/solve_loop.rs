//! Solves the benchmark problems a fixed number of times: a deterministic driver for
//! `valgrind --tool=callgrind` (instruction counts are repeatable where timings are not).
//!
//! `cargo build --release -p ivp --example solve_loop &&
//!  valgrind --tool=callgrind target/release/examples/solve_loop 200`

#[path = "../benches/common/mod.rs"]
mod problems;

use ivp::Solver;

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(100);
    let (a, b) = (problems::problem_a(), problems::problem_b());
    let mut solver = Solver::new();
    let mut nodes = 0;
    for _ in 0..n {
        for p in [&a, &b] {
            std::hint::black_box(solver.solve(p));
            nodes += solver.nodes_visited();
        }
    }
    println!("{n} rounds, {nodes} nodes");
}
