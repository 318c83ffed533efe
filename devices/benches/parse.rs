//! Parsing throughput per protocol: a buffer of device lines pushed through the protocol's
//! line splitter and parsed, in lines (frames) per second (the lines of `devices::samples`).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use devices::line::LineSplitter;
use devices::samples::{self, repeat};
use devices::{a50, nmea, seatrac, teensy};

const LINES: usize = 1000;

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("parse");
    g.throughput(Throughput::Elements(LINES as u64));

    let gps = repeat(&samples::nmea(), LINES);
    g.bench_function("nmea", |b| {
        b.iter(|| {
            let mut s = LineSplitter::new(nmea::MAX_LINE).with_starts(b"$");
            let mut ok = 0;
            s.push(&gps, |l| ok += usize::from(nmea::parse(l).is_ok()));
            assert_eq!(ok, LINES);
        })
    });

    let dvl = repeat(
        &[samples::a50_velocity(), samples::a50_dead_reckoning()],
        LINES,
    );
    g.bench_function("a50", |b| {
        b.iter(|| {
            let mut s = LineSplitter::new(a50::MAX_LINE);
            let mut ok = 0;
            s.push(&dvl, |l| ok += usize::from(a50::parse(l).is_ok()));
            assert_eq!(ok, LINES);
        })
    });

    let modem = repeat(
        &[
            &b"$100340E2010000000000762FD700810400000F000000E4398403E7FF0C00C13B\r\n"[..],
            b"$61000303050807000000001400E43944FDE803000068890900CF010444FD3AFD3FFD42FDC201D4FE0C00000361626378BC\r\n",
        ],
        LINES,
    );
    g.bench_function("seatrac", |b| {
        b.iter(|| {
            let mut s = LineSplitter::new(seatrac::MAX_FRAME).with_starts(b"#$");
            let mut ok = 0;
            s.push(&modem, |l| {
                ok += usize::from(seatrac::Response::decode(l).is_ok())
            });
            assert_eq!(ok, LINES);
        })
    });

    let mcu = repeat(&samples::teensy(), LINES);
    g.bench_function("teensy", |b| {
        b.iter(|| {
            let mut s = LineSplitter::new(teensy::MAX_LINE).with_starts(b"$");
            let mut ok = 0;
            s.push(&mcu, |l| {
                ok += usize::from(teensy::Telemetry::parse(l).is_ok())
            });
            assert_eq!(ok, LINES);
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
