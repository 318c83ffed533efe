//! The channel with 100 nodes scattered over a 2 km square (all within range of each other),
//! each sending a 15-byte status (1.2 s of airtime) in turn. One iteration is one 0.1 s tick
//! (the transmission of the tick, reaching the 99 others, and the step that resolves the
//! arrivals due), in steady state:
//! - `step_100_nodes/polled`: one sender per 3.5 s slot (airtime plus the largest delay
//!   across the square), as a polled MAC would: nearly every packet heard;
//! - `step_100_nodes/aloha`: a new sender every tick: everything collides, the most
//!   arrivals in flight.

use achannel::{Channel, Config, NodeId, Position};
use criterion::{Criterion, criterion_group, criterion_main};

const NODES: usize = 100;
const TICK: f64 = 0.1;

struct Fleet {
    ch: Channel,
    slot_ticks: usize,
    tick: usize,
    delivered: usize,
}

impl Fleet {
    fn new(slot_ticks: usize) -> Self {
        let mut ch = Channel::new(Config {
            seed: 1,
            ..Config::default()
        });
        let mut s = 12345u64;
        let mut coord = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64 * 2000.0
        };
        for _ in 0..NODES {
            let (x, y) = (coord(), coord());
            ch.add_node(Position::new(x, y, 10.0));
        }
        Self {
            ch,
            slot_ticks,
            tick: 0,
            delivered: 0,
        }
    }

    fn tick(&mut self) {
        let t = self.tick as f64 * TICK;
        if self.tick.is_multiple_of(self.slot_ticks) {
            let n = (self.tick / self.slot_ticks) % NODES;
            let _ = self.ch.transmit(NodeId(n), &[0x71; 15], t);
        }
        self.delivered += self.ch.step(t).len();
        self.tick += 1;
    }
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("step_100_nodes");
    for (name, slot) in [("polled", 35), ("aloha", 1)] {
        let mut fleet = Fleet::new(slot);
        for _ in 0..1000 {
            fleet.tick();
        }
        g.bench_function(name, |b| b.iter(|| fleet.tick()));
        println!(
            "{name}: after {} ticks: {:?}, {} in flight",
            fleet.tick,
            fleet.ch.stats(),
            fleet.ch.in_flight()
        );
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
