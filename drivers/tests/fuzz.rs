//! The drivers' fuzz body (`drivers::fuzz::protocols`) on stable: seeds of every device's
//! traffic (`devices::samples`, and the framings mixed), then a fixed number of deterministic
//! mutants (`test_support::fuzz::Campaign`).

use devices::samples;
use test_support::fuzz::Campaign;

/// Mutants (each runs five protocols).
const ITERATIONS: usize = 4_000;

#[test]
fn fuzz_the_protocol_state_machines() {
    let mut seeds = vec![
        samples::repeat(&samples::nmea(), 3),
        samples::gpsd_tpv(),
        samples::a50_velocity(),
        samples::a50_dead_reckoning(),
        b"{\"response_to\":\"set_config\",\"success\":true,\"error_message\":\"\",\"result\":null,\"type\":\"response\"}\n".to_vec(),
        samples::seatrac_status(),
        devices::seatrac::Response::SysAlive { seconds: 5 }
            .encode()
            .into_bytes(),
        samples::repeat(&samples::teensy(), 3),
    ];
    seeds.push(seeds.concat());
    let r = Campaign::new("drivers", seeds)
        .tokens(&[
            "$GPGGA,",
            "$DEPTH,",
            "$LEAK,",
            "\r\n",
            "\n",
            "{\"type\":",
            "\"velocity\"",
            "$10",
            "$42",
            "*",
            ",",
        ])
        .iterations(ITERATIONS)
        .run(drivers::fuzz::protocols);
    assert_eq!((r.seeds, r.mutants), (9, ITERATIONS));
    assert!(r.changed > ITERATIONS / 2, "{r:?}");
}
