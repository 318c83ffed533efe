//! The receiver's fuzz body (`acomms::fuzz::receive`) on stable: one valid frame of every
//! message as seeds, then a fixed number of deterministic mutants
//! (`test_support::fuzz::Campaign`). Random, truncated, spliced and bit-flipped payloads must
//! be refused and counted, never panic; whatever is accepted re-encodes to the same bytes.

use test_support::fuzz::Campaign;

/// Mutants run.
const ITERATIONS: usize = 60_000;

#[test]
fn fuzz_receiver() {
    let mut seeds = acomms::fuzz::seeds();
    let n = seeds.len();
    seeds.push(seeds.concat());
    let r = Campaign::new("acomms", seeds)
        .tokens(&[
            "\u{71}", "\u{75}", "\u{78}", "\u{7C}", "\u{7E}", "\u{11}", "\u{31}",
        ])
        .iterations(ITERATIONS)
        .max_len(64)
        .run(acomms::fuzz::receive);
    assert_eq!((r.seeds, r.mutants), (n + 1, ITERATIONS));
    assert!(r.changed > ITERATIONS / 2, "{r:?}");
}

#[test]
fn the_seeds_are_all_accepted() {
    let key = acomms::FleetKey::new(acomms::fuzz::KEY);
    let mut rx = acomms::Receiver::new(acomms::fuzz::ME, key);
    for s in acomms::fuzz::seeds() {
        assert!(rx.receive(&s).is_ok(), "{s:02X?}");
    }
    assert_eq!(rx.counters().accepted, acomms::SIZE_TABLE.len() as u64);
}
