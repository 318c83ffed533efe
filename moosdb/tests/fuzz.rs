//! The packet fuzz target (`moos_wire::fuzz::moos_packet`, run by cargo-fuzz on nightly
//! from `fuzz/`) runs on stable: over every packet the real C++ MOOSDB and clients exchanged
//! (the shared corpus's captures) and a few runs of consecutive packets, then over a fixed
//! number of deterministic mutants of them (`test_support::fuzz`), so every `cargo test`
//! fuzzes the codec for a short, bounded time and a failure reproduces exactly.

mod common;

use test_support::fuzz::Campaign;

/// Mutants: about three seconds in a debug build.
const ITERATIONS: usize = 250_000;

#[test]
fn fuzz_moos_packet_on_the_captures_and_their_mutants() {
    let mut seeds = Vec::new();
    let mut runs = 0;
    for scenario in common::scenarios() {
        let idx = common::index(&scenario);
        for conn in idx["connections"].as_array().expect("connections") {
            for dir in ["c2s", "s2c"] {
                let file = conn[format!("{dir}_file")].as_str().expect("file name");
                let bytes = common::bin(&scenario, file);
                let packets = common::packets(conn, &format!("{dir}_packets"));
                for p in &packets {
                    seeds.push(bytes[p.off..p.off + p.len].to_vec());
                }
                // Up to four consecutive packets: the stream decoder's several frames.
                let run = &packets[..packets.len().min(4)];
                if let (Some(first), Some(last)) = (run.first(), run.last()) {
                    seeds.push(bytes[first.off..last.off + last.len].to_vec());
                    runs += 1;
                }
            }
        }
    }
    let packets = seeds.len() - runs;
    assert_eq!(packets, 2638, "the captures README counts 2638 packets");
    let r = Campaign::new("moos_packet", seeds)
        .iterations(ITERATIONS)
        .run(moos_wire::fuzz::moos_packet);
    assert_eq!((r.seeds, r.mutants), (packets + runs, ITERATIONS), "{r:?}");
    assert!(r.changed > ITERATIONS * 9 / 10, "{r:?}");
}
