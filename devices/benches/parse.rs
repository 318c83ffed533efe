//! Parsing throughput per protocol: a buffer of device lines pushed through the protocol's
//! line splitter and parsed, in lines (frames) per second.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use devices::line::LineSplitter;
use devices::{a50, nmea, seatrac, teensy};

const LINES: usize = 1000;

fn repeat(lines: &[&[u8]]) -> Vec<u8> {
    let mut v = Vec::new();
    for k in 0..LINES {
        v.extend_from_slice(lines[k % lines.len()]);
    }
    v
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("parse");
    g.throughput(Throughput::Elements(LINES as u64));

    let gps = repeat(&[
        b"$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n",
        b"$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A\r\n",
        b"$GPVTG,054.7,T,034.4,M,005.5,N,010.2,K*48\r\n",
    ]);
    g.bench_function("nmea", |b| {
        b.iter(|| {
            let mut s = LineSplitter::new(nmea::MAX_LINE).with_starts(b"$");
            let mut ok = 0;
            s.push(&gps, |l| ok += usize::from(nmea::parse(l).is_ok()));
            assert_eq!(ok, LINES);
        })
    });

    let vel = devices::a50::Message::Velocity(devices::a50::VelocityReport {
        time_ms: 106.39,
        time_of_validity_us: Some(1638191471563017),
        time_of_transmission_us: Some(1638191471752336),
        vel_body_mps: [0.512, -0.0213, 0.0041],
        fom_mps: 0.0016,
        covariance: Some([[2.4e-8, -3.3e-9, -1.6e-10]; 3]),
        altitude_m: 4.95,
        transducers: (0..4)
            .map(|id| devices::a50::Transducer {
                id,
                velocity_mps: 0.25,
                distance_m: 5.5,
                rssi_dbm: -30.4,
                nsd_dbm: -88.7,
                beam_valid: true,
            })
            .collect(),
        velocity_valid: true,
        status: 0,
        format: Some("json_v3.1".into()),
    })
    .encode();
    let dr = br#"{"ts": 49056.809, "x": 12.43, "y": 64.61, "z": 1.76, "std": 0.10, "roll": -0.54, "pitch": 1.61, "yaw": 2.02, "type": "position_local", "status": 0, "format": "json_v3.1"}
"#;
    let dvl = repeat(&[vel.as_bytes(), dr]);
    g.bench_function("a50", |b| {
        b.iter(|| {
            let mut s = LineSplitter::new(a50::MAX_LINE);
            let mut ok = 0;
            s.push(&dvl, |l| ok += usize::from(a50::parse(l).is_ok()));
            assert_eq!(ok, LINES);
        })
    });

    let modem = repeat(&[
        b"$100340E2010000000000762FD700810400000F000000E4398403E7FF0C00C13B\r\n",
        b"$61000303050807000000001400E43944FDE803000068890900CF010444FD3AFD3FFD42FDC201D4FE0C00000361626378BC\r\n",
    ]);
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

    let mcu = repeat(&[
        b"$DEPTH,101919.6,14.2\r\n",
        b"$BATTE,16.4,2.3\r\n",
        b"$LEAK,0\r\n",
    ]);
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
