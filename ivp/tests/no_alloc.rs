//! A warmed-up `Solver` allocates nothing during a solve except the returned `Decision`
//! (its vector and one name per decided variable).

#[path = "../benches/common/mod.rs"]
mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    static ALLOCS: Cell<usize> = const { Cell::new(0) };
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCS.with(|c| c.set(c.get() + 1));
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCS.with(|c| c.set(c.get() + 1));
        // SAFETY: forwarded unchanged to the system allocator.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations_during(f: impl FnOnce()) -> usize {
    let before = ALLOCS.with(Cell::get);
    f();
    ALLOCS.with(Cell::get) - before
}

#[test]
fn steady_state_solves_allocate_only_the_decision() {
    let problems = [common::problem_a(), common::problem_b()];
    let mut solver = ivp::Solver::new();
    // warm up on both problems so every buffer reaches its working size
    for p in &problems {
        solver.solve(p);
    }
    for p in &problems {
        let mut decided = 0;
        let n = allocations_during(|| {
            let d = solver.solve(p).expect("a decision");
            decided = d.vars.len();
            drop(d);
        });
        assert_eq!(n, 1 + decided, "allocations in a warmed-up solve");
    }
}
