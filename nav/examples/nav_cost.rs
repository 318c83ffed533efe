//! The navigator's cost per simulated second, for callgrind and allocation counts: the
//! lawnmower scenario of the tests (DVL 5 Hz, AHRS and gyro 10 Hz, depth 20 Hz, GPS 5 Hz at the
//! surface; a 60 s surface stay every 300 s) is generated first, then fed to one [`Navigator`]
//! with the default settings (window 20, 3 iterations) in [`drive`], the only function to
//! measure:
//!
//! ```sh
//! cargo build --release -p nav --example nav_cost
//! valgrind --tool=callgrind --toggle-collect='*nav_cost*drive*' \
//!     target/release/examples/nav_cost 600
//! ```
//!
//! It prints the keyframes, the heap allocations made while driving (a counting allocator) per
//! simulated second, and a hash of every estimate's bits after each keyframe and of the final
//! status: an optimisation that leaves the navigator's outputs unchanged leaves the hash
//! unchanged. It also prints the estimate's accuracy against the scenario's truth at every
//! keyframe (horizontal position and heading error, RMS and largest, over the whole run and
//! from 30 s after the first resurfacing), for changes that may move the outputs' last bits.

#[path = "../tests/common/truth.rs"]
mod truth;

use nav::{Estimate, NavConfig, Navigator, Status};
use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicU64, Ordering};
use truth::{Event, Scenario, Sim, Truth};

struct Counting;
static ALLOCS: AtomicU64 = AtomicU64::new(0);

// SAFETY: forwards to the system allocator and only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: same layout, as the caller promised.
        unsafe { System.alloc(l) }
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: p came from alloc with layout l, as the caller promised.
        unsafe { System.realloc(p, l, new) }
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        // SAFETY: p came from alloc with this layout.
        unsafe { System.dealloc(p, l) }
    }
}

#[global_allocator]
static A: Counting = Counting;

/// FNV-1a over 64-bit words.
fn mix(h: &mut u64, v: u64) {
    for b in v.to_le_bytes() {
        *h ^= u64::from(b);
        *h = h.wrapping_mul(0x0100_0000_01b3);
    }
}

/// Feeds every event to `nav`; returns the hash of the outputs. Each keyframe's estimate is
/// kept in `kept` (with its event's index) for the accuracy figures.
#[inline(never)]
fn drive(nav: &mut Navigator, events: &[Event], kept: &mut Vec<(usize, Estimate)>) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325;
    for (i, e) in events.iter().enumerate() {
        let k = nav.keyframes();
        let r = match e {
            Event::Dvl(m) => nav.dvl(m),
            Event::Att(m) => nav.attitude(m),
            Event::Gyro(m) => nav.gyro(m),
            Event::Depth(m) => nav.depth(m),
            Event::Gps(m) => nav.gps(m),
        };
        mix(&mut h, u64::from(r.is_ok()));
        if nav.keyframes() > k
            && let Some(est) = nav.estimate()
        {
            kept.push((i, est));
            for v in [
                est.t_s,
                est.x_m,
                est.y_m,
                est.depth_m,
                est.heading_rad,
                est.speed_mps,
                est.heading_bias_rad,
                est.current_east_mps,
                est.current_north_mps,
                est.pos_sigma_m,
                est.heading_bias_sigma_rad,
                est.current_sigma_mps,
            ] {
                mix(&mut h, v.to_bits());
            }
            mix(
                &mut h,
                match nav.status() {
                    Status::Initialising(_) => 1,
                    Status::Ok => 2,
                    Status::DeadReckoning(_) => 3,
                    Status::Degraded(_) => 4,
                },
            );
        }
    }
    h
}

fn main() {
    let seconds: f64 = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(600.0);
    let mut sim = Sim::new(Scenario::default());
    let first_resurface = sim.sc.surface_s + sim.sc.dive_s;
    let mut events = Vec::with_capacity((seconds * 50.0) as usize + 16);
    let mut truths: Vec<Truth> = Vec::with_capacity(events.capacity());
    loop {
        let e = sim.next_event();
        if e.t_s() > seconds {
            break;
        }
        events.push(e);
        truths.push(sim.truth());
    }
    let mut nav = Navigator::new(NavConfig::default());
    let mut kept = Vec::with_capacity((seconds * 6.0) as usize + 16);
    let a0 = ALLOCS.load(Ordering::Relaxed);
    let hash = drive(&mut nav, &events, &mut kept);
    let allocs = ALLOCS.load(Ordering::Relaxed) - a0;
    let est = nav.estimate();
    println!(
        "{seconds} simulated s, {} events, {} keyframes, {allocs} allocations ({:.2} per \
         simulated s), output hash {hash:016x}, status {}, final x {:?}",
        events.len(),
        nav.keyframes(),
        allocs as f64 / seconds,
        nav.status().describe(),
        est.map(|e| (e.x_m, e.y_m)),
    );
    for (what, from) in [
        ("all keyframes", f64::NEG_INFINITY),
        (
            "from 30 s after the first resurfacing",
            first_resurface + 30.0,
        ),
    ] {
        let a = Accuracy::of(kept.iter().filter_map(|(i, e)| {
            let tr = &truths[*i];
            (tr.t_s >= from).then_some((e, tr))
        }));
        println!(
            "accuracy, {what} ({} keyframes): position RMS {:.6} m, max {:.6} m; heading RMS \
             {:.6} deg, max {:.6} deg",
            a.n, a.pos_rms_m, a.pos_max_m, a.hdg_rms_deg, a.hdg_max_deg
        );
    }
}

/// Horizontal position and heading errors against the truth.
struct Accuracy {
    n: usize,
    pos_rms_m: f64,
    pos_max_m: f64,
    hdg_rms_deg: f64,
    hdg_max_deg: f64,
}

impl Accuracy {
    fn of<'a>(pairs: impl Iterator<Item = (&'a Estimate, &'a Truth)>) -> Accuracy {
        let (mut n, mut sp, mut mp, mut sh, mut mh) = (0usize, 0.0, 0.0f64, 0.0, 0.0f64);
        for (e, tr) in pairs {
            let p = (e.x_m - tr.x_m).hypot(e.y_m - tr.y_m);
            let tau = std::f64::consts::TAU;
            let mut d = (e.heading_rad - tr.heading_rad).rem_euclid(tau);
            if d > std::f64::consts::PI {
                d -= tau;
            }
            let h = d.to_degrees().abs();
            n += 1;
            sp += p * p;
            sh += h * h;
            mp = mp.max(p);
            mh = mh.max(h);
        }
        let m = n.max(1) as f64;
        Accuracy {
            n,
            pos_rms_m: (sp / m).sqrt(),
            pos_max_m: mp,
            hdg_rms_deg: (sh / m).sqrt(),
            hdg_max_deg: mh,
        }
    }
}
