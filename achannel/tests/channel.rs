//! The channel on hand-built geometries: delay, half-duplex, collisions, range; the loss
//! statistics over 10,000 seeded packets against the configured curve; determinism.

use achannel::{Channel, Config, LossCurve, NodeId, Position, Reception, TxError, UsblNoise};
use proptest::prelude::*;

const TICK: f64 = 0.1;

fn lossless() -> Config {
    Config {
        loss: LossCurve::Table {
            points: vec![(0.0, 1.0)],
            size_sigma_bytes: f64::INFINITY,
        },
        ..Config::default()
    }
}

fn at(x: f64, y: f64, depth: f64) -> Position {
    Position::new(x, y, depth)
}

/// Steps at `TICK` from `from` to `to` and collects the receptions with the tick they came at.
fn run_ticks(ch: &mut Channel, from: f64, to: f64) -> Vec<(f64, Reception)> {
    let mut out = Vec::new();
    let mut k = (from / TICK).round() as i64;
    while k as f64 * TICK <= to + 1e-9 {
        let t = k as f64 * TICK;
        out.extend(ch.step(t).into_iter().map(|r| (t, r)));
        k += 1;
    }
    out
}

#[test]
fn delay_is_range_over_sound_speed_plus_airtime_within_a_tick() {
    let mut ch = Channel::new(lossless());
    let a = ch.add_node(at(0.0, 0.0, 2.0));
    let ranges = [100.0, 750.0, 1500.0, 2999.0];
    let rx: Vec<NodeId> = ranges
        .iter()
        .enumerate()
        .map(|(i, r)| {
            // Spread around the sender, one at depth 2 like the sender.
            let th = i as f64 * 1.3;
            ch.add_node(at(r * th.sin(), r * th.cos(), 2.0))
        })
        .collect();
    let payload = [0xA5u8; 20]; // 160 bits at 100 bit/s: 1.6 s
    let end = ch.transmit(a, &payload, 0.35).unwrap();
    assert!((end - (0.35 + 1.6)).abs() < 1e-12);
    let got = run_ticks(&mut ch, 0.0, 5.0);
    assert_eq!(got.len(), ranges.len());
    for (node, r) in rx.iter().zip(ranges) {
        let (tick, rec) = got.iter().find(|(_, rec)| rec.to == *node).unwrap();
        let expected = 0.35 + r / 1500.0 + 1.6;
        assert!(
            (rec.arrival_s - expected).abs() < 1e-9,
            "{r}: {}",
            rec.arrival_s
        );
        assert!((rec.true_range_m - r).abs() < 1e-9);
        assert!(
            *tick >= expected && *tick < expected + TICK,
            "{r}: tick {tick}"
        );
        assert_eq!(
            (rec.from, rec.sent_s, &rec.payload[..]),
            (a, 0.35, &payload[..])
        );
    }
    assert_eq!(ch.in_flight(), 0);
}

#[test]
fn a_node_cannot_hear_while_it_transmits() {
    let mut ch = Channel::new(lossless());
    let a = ch.add_node(at(0.0, 0.0, 0.0));
    let b = ch.add_node(at(1500.0, 0.0, 0.0));
    // a's packet is at b from 1.0 to 1.8; b talks from 1.2 to 2.0 and loses it.
    ch.transmit(a, &[1; 10], 0.0).unwrap();
    assert!(ch.step(1.2).is_empty());
    ch.transmit(b, &[2; 10], 1.2).unwrap();
    // b is busy: a second transmission before 2.0 is refused.
    assert_eq!(
        ch.transmit(b, &[3], 1.5),
        Err(TxError::Busy { until_s: 2.0 })
    );
    let got = run_ticks(&mut ch, 1.3, 4.0);
    // b's packet reaches a at 2.2..3.0, when a is quiet.
    assert_eq!(got.len(), 1);
    assert_eq!((got[0].1.to, got[0].1.from), (a, b));
    let s = ch.stats();
    assert_eq!(
        (s.half_duplex, s.delivered, s.collisions, s.arrivals),
        (1, 1, 0, 2)
    );
}

#[test]
fn a_transmission_that_starts_after_the_arrival_ends_does_not_cut_it() {
    let mut ch = Channel::new(lossless());
    let a = ch.add_node(at(0.0, 0.0, 0.0));
    let b = ch.add_node(at(1500.0, 0.0, 0.0));
    ch.transmit(a, &[1; 10], 0.0).unwrap(); // at b 1.0..1.8
    let first = ch.step(1.8);
    assert_eq!(first.len(), 1);
    ch.transmit(b, &[2; 10], 1.8).unwrap(); // touching, not overlapping
    assert_eq!(run_ticks(&mut ch, 1.9, 4.0).len(), 1);
    assert_eq!(ch.stats().half_duplex, 0);
}

#[test]
fn overlapping_arrivals_at_a_receiver_are_both_lost() {
    let mut ch = Channel::new(lossless());
    let a = ch.add_node(at(-1000.0, 0.0, 5.0));
    let b = ch.add_node(at(0.0, 0.0, 5.0));
    let c = ch.add_node(at(1000.0, 0.0, 5.0));
    let d = ch.add_node(at(2000.0, 0.0, 5.0));
    // a and c at once: at b both arrive 0.667..1.467 and collide. At d, c's packet comes at
    // 0.667..1.467 and a's at 2.0..2.8: no overlap, both heard. a and c hear each other
    // after their own transmissions end (at 1.333).
    ch.transmit(a, &[0xAA; 10], 0.0).unwrap();
    ch.transmit(c, &[0xCC; 10], 0.0).unwrap();
    let got = run_ticks(&mut ch, 0.0, 5.0);
    let heard = |n: NodeId| -> Vec<NodeId> {
        got.iter()
            .filter(|(_, r)| r.to == n)
            .map(|(_, r)| r.from)
            .collect()
    };
    assert_eq!(heard(b), vec![]);
    assert_eq!(heard(d), vec![c, a]);
    assert_eq!(heard(a), vec![c]);
    assert_eq!(heard(c), vec![a]);
    assert_eq!(ch.stats().collisions, 2);

    // Spaced out, the same two packets both reach b.
    let mut ch = Channel::new(lossless());
    let a = ch.add_node(at(-1000.0, 0.0, 5.0));
    let b = ch.add_node(at(0.0, 0.0, 5.0));
    let c = ch.add_node(at(1000.0, 0.0, 5.0));
    ch.transmit(a, &[0xAA; 10], 0.0).unwrap();
    ch.step(0.8);
    ch.transmit(c, &[0xCC; 10], 0.8).unwrap(); // at b from 1.467, a's ended at 1.467
    let got = run_ticks(&mut ch, 0.9, 5.0);
    let at_b: Vec<NodeId> = got
        .iter()
        .filter(|(_, r)| r.to == b)
        .map(|(_, r)| r.from)
        .collect();
    assert_eq!(at_b, vec![a, c]);
    assert_eq!(ch.stats().collisions, 0);
}

#[test]
fn three_overlapping_arrivals_are_all_lost() {
    let mut ch = Channel::new(lossless());
    let hub = ch.add_node(at(0.0, 0.0, 0.0));
    let others: Vec<NodeId> = (0..3)
        .map(|i| ch.add_node(at(500.0 + 100.0 * f64::from(i), 0.0, 0.0)))
        .collect();
    for (i, n) in others.iter().enumerate() {
        ch.transmit(*n, &[7; 10], 0.2 * i as f64).unwrap();
    }
    let got = run_ticks(&mut ch, 0.0, 5.0);
    assert!(got.iter().all(|(_, r)| r.to != hub));
}

#[test]
fn nothing_is_heard_past_the_maximum_range() {
    let mut ch = Channel::new(Config {
        max_range_m: 1000.0,
        ..lossless()
    });
    let a = ch.add_node(at(0.0, 0.0, 0.0));
    let near = ch.add_node(at(0.0, 1000.0, 0.0));
    let far = ch.add_node(at(0.0, -1000.5, 0.0));
    // A packet beyond range does not occupy the far node either: it hears `near` meanwhile.
    ch.transmit(a, &[1; 5], 0.0).unwrap();
    ch.transmit(near, &[2; 5], 0.0).unwrap();
    let got = run_ticks(&mut ch, 0.0, 5.0);
    let pairs: Vec<(NodeId, NodeId)> = got.iter().map(|(_, r)| (r.from, r.to)).collect();
    assert!(!pairs.contains(&(a, far)));
    assert!(
        !pairs.contains(&(near, far)),
        "2000.5 m is out of range too"
    );
    let s = ch.stats();
    // a->far, near->far, far is not transmitting; a<->near hear each other? Both were
    // transmitting at 0..0.4 and the packets arrive at 0.667..1.067: yes.
    assert_eq!(pairs, vec![(near, a), (a, near)]);
    assert_eq!((s.out_of_range, s.arrivals, s.delivered), (2, 2, 2));
}

#[test]
fn transmit_errors() {
    let mut ch = Channel::new(lossless());
    let a = ch.add_node(at(0.0, 0.0, 0.0));
    assert_eq!(
        ch.transmit(a, &[0; 32], 0.0),
        Err(TxError::TooLong { bytes: 32, max: 31 })
    );
    assert_eq!(
        ch.transmit(NodeId(9), &[0], 0.0),
        Err(TxError::UnknownNode(NodeId(9)))
    );
    ch.step(10.0);
    assert_eq!(
        ch.transmit(a, &[0], 9.0),
        Err(TxError::TimeWentBack { t: 9.0, now: 10.0 })
    );
    assert!(ch.transmit(a, &[0], 10.0).is_ok());
    assert_eq!(ch.stats().transmitted, 1);
}

/// The four-sigma binomial band around `p` for `n` trials.
fn band(p: f64, n: f64) -> f64 {
    4.0 * (p * (1.0 - p) / n).sqrt() + 1.0 / n
}

/// 10,000 packets from one sender to receivers at `ranges`; the delivered fraction at each.
fn delivered_fractions(config: Config, ranges: &[f64], bytes: usize) -> Vec<f64> {
    const N: usize = 10_000;
    let mut ch = Channel::new(config);
    let tx = ch.add_node(at(0.0, 0.0, 0.0));
    let rx: Vec<NodeId> = ranges
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let th = i as f64 * 0.9;
            ch.add_node(at(r * th.cos(), r * th.sin(), 0.0))
        })
        .collect();
    let period = ch.config().airtime_s(bytes) + 0.01;
    let mut counts = vec![0usize; rx.len()];
    let payload = vec![0x5A; bytes];
    for k in 0..N {
        let t = k as f64 * period;
        for r in ch.step(t) {
            counts[r.to.0 - 1] += 1;
        }
        ch.transmit(tx, &payload, t).unwrap();
    }
    for r in ch.step(N as f64 * period + 10.0) {
        counts[r.to.0 - 1] += 1;
    }
    let s = ch.stats();
    assert_eq!((s.collisions, s.half_duplex), (0, 0));
    assert_eq!(s.arrivals, (N * rx.len()) as u64);
    counts.iter().map(|c| *c as f64 / N as f64).collect()
}

#[test]
fn loss_statistics_match_the_gaussian_curve() {
    let curve = LossCurve::dune();
    let ranges = [100.0, 500.0, 900.0, 1400.0, 2200.0];
    let config = Config {
        seed: 0xC0FFEE,
        loss: curve.clone(),
        ..Config::default()
    };
    let got = delivered_fractions(config, &ranges, 30);
    for (r, f) in ranges.iter().zip(&got) {
        let p = curve.success(*r, 30);
        assert!((f - p).abs() <= band(p, 1e4), "{r} m: {f} against {p}");
    }
    // The curve does fall with range.
    assert!(got.windows(2).all(|w| w[0] > w[1]), "{got:?}");
}

#[test]
fn loss_statistics_match_a_table_curve_and_fall_with_size() {
    let curve = LossCurve::Table {
        points: vec![(0.0, 0.98), (400.0, 0.9), (800.0, 0.5), (1200.0, 0.1)],
        size_sigma_bytes: 40.0,
    };
    assert!((curve.success(600.0, 0) - 0.7).abs() < 1e-12);
    assert_eq!(curve.success(5000.0, 0), 0.1);
    let ranges = [200.0, 600.0, 1000.0];
    for (bytes, seed) in [(2usize, 1u64), (31, 2)] {
        let config = Config {
            seed,
            loss: curve.clone(),
            ..Config::default()
        };
        let got = delivered_fractions(config, &ranges, bytes);
        for (r, f) in ranges.iter().zip(&got) {
            let p = curve.success(*r, bytes);
            assert!(
                (f - p).abs() <= band(p, 1e4),
                "{r} m, {bytes} B: {f} against {p}"
            );
        }
    }
    assert!(curve.success(600.0, 31) < curve.success(600.0, 2));
}

#[test]
fn usbl_noise_has_the_configured_spread() {
    let mut ch = Channel::new(Config {
        seed: 42,
        usbl: UsblNoise {
            azimuth_sigma_deg: 2.0,
            elevation_sigma_deg: 1.0,
            range_sigma_m: 0.5,
        },
        ..lossless()
    });
    // The sender is 300 m east and 400 m north of the receiver, 100 m shallower.
    let rx = ch.add_node(at(0.0, 0.0, 110.0));
    let tx = ch.add_node(at(300.0, 400.0, 10.0));
    let true_az = 300f64.atan2(400.0).to_degrees();
    let true_el = 100f64.atan2(500.0).to_degrees();
    let true_r = (500f64 * 500.0 + 100.0 * 100.0).sqrt();
    let (mut az, mut el, mut r) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..4000 {
        let t = f64::from(k);
        for rec in ch.step(t) {
            assert_eq!(rec.to, rx);
            az.push(rec.usbl.azimuth_deg - true_az);
            el.push(rec.usbl.elevation_deg - true_el);
            r.push(rec.usbl.range_m - true_r);
        }
        ch.transmit(tx, &[0; 4], t).unwrap();
    }
    let stats = |v: &[f64]| {
        let m = v.iter().sum::<f64>() / v.len() as f64;
        let s = (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / v.len() as f64).sqrt();
        (m, s)
    };
    for (v, sigma) in [(&az, 2.0), (&el, 1.0), (&r, 0.5)] {
        let (m, s) = stats(v);
        assert!(m.abs() < 4.0 * sigma / (v.len() as f64).sqrt(), "mean {m}");
        assert!((s / sigma - 1.0).abs() < 0.06, "sd {s} for {sigma}");
    }
}

#[test]
fn azimuth_wraps_into_0_360() {
    let mut ch = Channel::new(Config {
        seed: 3,
        ..lossless()
    });
    // Due north: noise puts half the fixes just below 360 and half just above 0.
    let rx = ch.add_node(at(0.0, 0.0, 0.0));
    let tx = ch.add_node(at(0.0, 100.0, 0.0));
    let mut low = 0;
    for k in 0..200 {
        let t = f64::from(k);
        for rec in ch.step(t) {
            assert_eq!(rec.to, rx);
            assert!((0.0..360.0).contains(&rec.usbl.azimuth_deg));
            low += usize::from(rec.usbl.azimuth_deg < 180.0);
        }
        ch.transmit(tx, &[0; 4], t).unwrap();
    }
    assert!(low > 50 && low < 150, "{low}");
}

/// Node positions (x, y) and transmissions (node, time, bytes).
type Schedule = (Vec<(f64, f64)>, Vec<(usize, f64, usize)>);

/// A random schedule of transmissions among 2 to 7 nodes.
fn schedule() -> impl Strategy<Value = Schedule> {
    (2usize..8).prop_flat_map(|n| {
        (
            proptest::collection::vec((-2000.0f64..2000.0, -2000.0f64..2000.0), n),
            proptest::collection::vec((0..n, 0.0f64..30.0, 0usize..=31), 0..60),
        )
    })
}

fn play(seed: u64, nodes: &[(f64, f64)], txs: &[(usize, f64, usize)], dt: f64) -> Vec<Reception> {
    let mut ch = Channel::new(Config {
        seed,
        ..Config::default()
    });
    for (x, y) in nodes {
        ch.add_node(at(*x, *y, 10.0));
    }
    let mut txs = txs.to_vec();
    txs.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut out = Vec::new();
    let mut next = 0;
    for k in 0..=(40.0 / dt).round() as usize {
        let t = k as f64 * dt;
        // Each packet goes at its own time, which is after the last step.
        while next < txs.len() && txs[next].1 <= t {
            let (n, at_s, bytes) = txs[next];
            let _ = ch.transmit(NodeId(n), &vec![n as u8; bytes], at_s);
            next += 1;
        }
        out.extend(ch.step(t));
    }
    out.extend(ch.step(100.0));
    let s = ch.stats();
    let senders = s.transmitted * (nodes.len() as u64 - 1);
    assert_eq!(s.out_of_range + s.arrivals, senders);
    assert_eq!(
        s.arrivals,
        s.delivered + s.half_duplex + s.collisions + s.lost
    );
    assert_eq!(s.delivered, out.len() as u64);
    assert_eq!(ch.in_flight(), 0);
    out
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn counts_add_up_and_the_step_size_does_not_matter(
        (nodes, txs) in schedule(), seed in any::<u64>()
    ) {
        let fine = play(seed, &nodes, &txs, 0.05);
        let coarse = play(seed, &nodes, &txs, 0.5);
        prop_assert_eq!(fine, coarse);
    }
}
