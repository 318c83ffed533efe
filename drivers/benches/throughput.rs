//! Driver throughput: device bytes through a whole protocol state machine (line splitting,
//! parsing, counters, the MOOS posts made), in lines (frames) per second. The buffer
//! (`devices::samples`) is fed in 4 KiB pieces, as the link thread hands it over.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use devices::samples;
use drivers::dvl::{Dvl, DvlConfig};
use drivers::gps::{Gps, Source};
use drivers::seatrac::{SeaTrac, SeaTracConfig};
use drivers::teensy::{Teensy, TeensyConfig};
use drivers::{Io, Protocol};

const LINES: usize = 1000;

fn run(p: &mut dyn Protocol, data: &[u8], io: &mut Io) -> usize {
    io.posts.clear();
    for piece in data.chunks(4096) {
        p.on_bytes(piece, 1.0, io);
    }
    io.posts.len()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("driver");
    g.throughput(Throughput::Elements(LINES as u64));
    let mut io = Io::default();
    let grid = vehicle::geodesy::LocalGrid::new(48.0, 11.0).ok();
    let cases: Vec<(&str, Box<dyn Protocol>, Vec<u8>)> = vec![
        (
            "igps_nmea",
            Box::new(Gps::new(Source::Nmea, grid.clone())),
            samples::repeat(&samples::nmea(), LINES),
        ),
        (
            "igps_gpsd",
            Box::new(Gps::new(Source::Gpsd, grid)),
            samples::repeat(&[samples::gpsd_tpv()], LINES),
        ),
        (
            "idvl",
            Box::new(Dvl::new(DvlConfig::default())),
            samples::repeat(&[samples::a50_velocity()], LINES),
        ),
        (
            "iseatrac_status",
            Box::new(SeaTrac::new(SeaTracConfig::default())),
            samples::repeat(&[samples::seatrac_status()], LINES),
        ),
        (
            "iteensy",
            Box::new(Teensy::new(TeensyConfig::default())),
            samples::repeat(&samples::teensy(), LINES),
        ),
    ];
    for (name, mut p, data) in cases {
        g.bench_function(name, |b| {
            b.iter(|| assert!(run(p.as_mut(), &data, &mut io) > 0))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
