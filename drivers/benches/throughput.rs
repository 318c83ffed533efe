//! Driver throughput: device bytes through a whole protocol state machine (line splitting,
//! parsing, counters, the MOOS posts made), in lines (frames) per second. The buffer is fed
//! in 4 KiB pieces, as the link thread hands it over.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use devices::seatrac::{self, Response};
use devices::teensy::Telemetry;
use drivers::dvl::{Dvl, DvlConfig};
use drivers::gps::{Gps, Source};
use drivers::seatrac::{SeaTrac, SeaTracConfig};
use drivers::teensy::{Teensy, TeensyConfig};
use drivers::{Io, Protocol};

const LINES: usize = 1000;

fn repeat(lines: &[Vec<u8>]) -> Vec<u8> {
    let mut v = Vec::new();
    for k in 0..LINES {
        v.extend_from_slice(&lines[k % lines.len()]);
    }
    v
}

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
    let nmea = repeat(&[
        b"$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n".to_vec(),
        b"$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A\r\n".to_vec(),
        b"$GPVTG,054.7,T,034.4,M,005.5,N,010.2,K*48\r\n".to_vec(),
    ]);
    let mut gps = Gps::new(Source::Nmea, grid.clone());
    g.bench_function("igps_nmea", |b| {
        b.iter(|| assert!(run(&mut gps, &nmea, &mut io) > 0))
    });

    let tpv = repeat(&[
        b"{\"class\":\"TPV\",\"device\":\"/dev/ttyUSB0\",\"mode\":3,\"time\":\"2026-11-26T12:00:00.000Z\",\"lat\":48.1173,\"lon\":11.5167,\"altMSL\":545.4,\"track\":84.4,\"speed\":11.5,\"eph\":2.1}\n".to_vec(),
    ]);
    let mut gpsd = Gps::new(Source::Gpsd, grid);
    g.bench_function("igps_gpsd", |b| {
        b.iter(|| assert!(run(&mut gpsd, &tpv, &mut io) > 0))
    });

    let vel = devices::a50::VelocityReport {
        time_ms: 106.39,
        time_of_validity_us: Some(1_638_191_471_563_017),
        time_of_transmission_us: Some(1_638_191_471_752_336),
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
    }
    .encode();
    let a50 = repeat(&[vel.into_bytes()]);
    let mut dvl = Dvl::new(DvlConfig::default());
    g.bench_function("idvl", |b| {
        b.iter(|| assert!(run(&mut dvl, &a50, &mut io) > 0))
    });

    let status = Response::Status(seatrac::Status {
        timestamp_ms: 123_456,
        environment: Some(seatrac::Environment {
            supply_mv: 15_600,
            temp_ddegc: 215,
            pressure_mbar: 1100,
            depth_dm: 12,
            vos_dmps: 14_820,
        }),
        attitude: Some(seatrac::Attitude {
            yaw_ddeg: 3550,
            pitch_ddeg: -25,
            roll_ddeg: 10,
        }),
        mag_cal: None,
        acc_cal: None,
        ahrs_raw: None,
        ahrs_comp: Some(seatrac::AhrsComp {
            acc: [0.01, -0.02, 0.99],
            mag: [20.0, -3.0, 40.0],
            gyro: [0.1, -0.2, 1.5],
        }),
    })
    .encode();
    let frames = repeat(&[status.into_bytes()]);
    let mut st = SeaTrac::new(SeaTracConfig::default());
    g.bench_function("iseatrac_status", |b| {
        b.iter(|| assert!(run(&mut st, &frames, &mut io) > 0))
    });

    let teensy = repeat(&[
        Telemetry::Depth {
            pressure_pa: 101_325.0,
            temp_degc: 21.3,
        }
        .encode()
        .into_bytes(),
        Telemetry::Battery {
            voltage_v: 15.9,
            current_a: 2.1,
        }
        .encode()
        .into_bytes(),
        Telemetry::Leak { leak: false }.encode().into_bytes(),
    ]);
    let mut t = Teensy::new(TeensyConfig::default());
    g.bench_function("iteensy", |b| {
        b.iter(|| assert!(run(&mut t, &teensy, &mut io) > 0))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
