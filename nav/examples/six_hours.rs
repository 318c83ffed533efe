//! A deterministic six-hour driver for profiling (callgrind, heaptrack): the lawnmower scenario
//! of the tests (1.5 m/s, 3-5 m deep, surfacing every 300 s), one keyframe per DVL report at
//! 5 Hz. Prints the mean, p99 and max cost of a keyframe update per hour and the heap in use
//! (a counting allocator): the heap and the cost must stay flat.
//!
//! Run with `cargo run --release -p nav --example six_hours [hours]`.

#[path = "../tests/common/truth.rs"]
mod truth;

use nav::{NavConfig, Navigator};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;
use truth::{Event, Scenario, Sim};

struct Counting;
static BYTES: AtomicU64 = AtomicU64::new(0);
static ALLOCS: AtomicU64 = AtomicU64::new(0);

// SAFETY: forwards to the system allocator and only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        BYTES.fetch_add(l.size() as u64, Ordering::Relaxed);
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: same layout, as the caller promised.
        unsafe { System.alloc(l) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        BYTES.fetch_sub(l.size() as u64, Ordering::Relaxed);
        // SAFETY: p came from alloc with this layout.
        unsafe { System.dealloc(p, l) }
    }
}

#[global_allocator]
static A: Counting = Counting;

fn main() {
    let hours: f64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(6.0);
    let mut sim = Sim::new(Scenario::default());
    let mut cfg = NavConfig::default();
    if let Some(it) = std::env::args().nth(2).and_then(|a| a.parse().ok()) {
        cfg.max_iterations = it;
    }
    let mut nav = Navigator::new(cfg);
    let mut costs: Vec<f64> = Vec::with_capacity(20_000);
    let mut all: Vec<f64> = Vec::with_capacity((hours * 3600.0 * 5.0) as usize + 10);
    let mut hour = 1.0;
    let mut worst_err: f64 = 0.0;
    println!(
        "hour  updates  mean_us  p99_us  max_us  heap_bytes  allocs_this_hour  err_m  sigma_m"
    );
    let mut allocs0 = ALLOCS.load(Ordering::Relaxed);
    loop {
        let e = sim.next_event();
        let t = e.t_s();
        if t > hours * 3600.0 + 1.0 {
            break;
        }
        match e {
            Event::Dvl(m) => {
                let k = nav.keyframes();
                let s = Instant::now();
                let _ = nav.dvl(&m);
                let us = s.elapsed().as_secs_f64() * 1e6;
                if nav.keyframes() > k {
                    costs.push(us);
                }
            }
            Event::Att(m) => drop(nav.attitude(&m)),
            Event::Gyro(m) => drop(nav.gyro(&m)),
            Event::Depth(m) => drop(nav.depth(&m)),
            Event::Gps(m) => drop(nav.gps(&m)),
        }
        if let Some(est) = nav.estimate() {
            let tr = sim.truth();
            if t > 400.0 {
                worst_err = worst_err.max((est.x_m - tr.x_m).hypot(est.y_m - tr.y_m));
            }
        }
        if t >= hour * 3600.0 {
            costs.sort_by(f64::total_cmp);
            let n = costs.len();
            let mean = costs.iter().sum::<f64>() / n as f64;
            let est = nav.estimate().unwrap();
            let tr = sim.truth();
            let allocs = ALLOCS.load(Ordering::Relaxed);
            println!(
                "{:4.0}  {:7}  {:7.1}  {:6.1}  {:6.1}  {:10}  {:16}  {:5.2}  {:7.2}",
                hour,
                n,
                mean,
                costs[(n * 99) / 100],
                costs[n - 1],
                BYTES.load(Ordering::Relaxed),
                allocs - allocs0,
                (est.x_m - tr.x_m).hypot(est.y_m - tr.y_m),
                est.pos_sigma_m
            );
            allocs0 = allocs;
            all.extend_from_slice(&costs);
            costs.clear();
            hour += 1.0;
        }
    }
    all.sort_by(f64::total_cmp);
    let n = all.len().max(1);
    println!(
        "all: {} updates, mean {:.1} us, p99 {:.1} us; worst error after 400 s {:.2} m; rejections {}",
        all.len(),
        all.iter().sum::<f64>() / n as f64,
        all.get((n * 99) / 100).copied().unwrap_or(0.0),
        worst_err,
        nav.rejections().total()
    );
}
