//! A deterministic driver for profiling: the alpha helm driven to mid-survey (as the
//! `iteration` bench does), then `N` more iterations (first argument, default 2000) at a fixed
//! pose. Prints the number of postings so the work cannot be optimised away.
//!
//! ```text
//! cargo build --release -p helm --example iterate_loop
//! valgrind --tool=callgrind target/release/examples/iterate_loop 2000
//! ```

#[path = "../benches/common/mod.rs"]
mod common;
use common::{mid_survey, nav};

fn main() {
    let n: usize = std::env::args()
        .nth(1)
        .map(|a| a.parse().expect("iteration count"))
        .unwrap_or(2000);
    let (mut helm, mut t, (x, y, h, v)) = mid_survey();
    // The measured part: the bench's loop.
    let mut posts = 0usize;
    for _ in 0..n {
        t += 0.25;
        helm.on_mail(&nav(x, y, h, v, t));
        posts += helm.iterate(t).len();
    }
    println!("{n} iterations, {posts} postings");
}
