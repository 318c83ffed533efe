//! CPU per driver at the devices' real rates: a fake device (a thread of this process) writes
//! each protocol's lines at its rate over a pseudo-terminal or a loopback TCP socket for
//! `SECONDS` of wall time, while the driver is stepped at its AppTick as the app would be.
//! The driver's CPU is the process's CPU time less the fake device thread's own. The lines
//! are `devices::samples`' (the GPS's are GGA and RMC on the mission's origin).
//!
//! `cargo run --release -p drivers --example real_rates [SECONDS]` (default 10). A measuring
//! tool, not a test: it reads the clock.

use std::io::{Read, Write};
use std::net::TcpListener;
use std::os::fd::FromRawFd;
use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use devices::samples;
use drivers::dvl::{Dvl, DvlConfig};
use drivers::gps::{Gps, Source};
use drivers::link::{Endpoint, LinkConfig};
use drivers::seatrac::{SeaTrac, SeaTracConfig};
use drivers::teensy::{Teensy, TeensyConfig};
use drivers::{Driver, Io, Protocol};

fn thread_cpu() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: a valid timespec.
    unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut t) };
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}

fn process_cpu() -> f64 {
    let mut t = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: a valid timespec.
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut t) };
    t.tv_sec as f64 + t.tv_nsec as f64 * 1e-9
}

/// A pty pair: the master as a file, the slave's path.
fn pty() -> (std::fs::File, PathBuf) {
    let (mut m, mut s) = (-1, -1);
    let mut name = [0 as libc::c_char; 128];
    // SAFETY: termios is plain data; valid pointers to locals.
    unsafe {
        let mut t: libc::termios = std::mem::zeroed();
        libc::cfmakeraw(&mut t);
        assert_eq!(
            libc::openpty(&mut m, &mut s, name.as_mut_ptr(), &t, std::ptr::null()),
            0
        );
        libc::close(s);
    }
    // SAFETY: NUL-terminated by openpty; `m` is ours.
    let path = unsafe { std::ffi::CStr::from_ptr(name.as_ptr()) }
        .to_string_lossy()
        .into_owned();
    (
        unsafe { std::fs::File::from_raw_fd(m) },
        PathBuf::from(path),
    )
}

/// Runs `device` (which writes one period's lines) at `rate_hz` on its own thread, and steps
/// the driver at `tick_hz`, for `secs`; returns (driver CPU %, lines posted per second).
fn measure<P: Protocol>(
    name: &str,
    mut d: Driver<P>,
    mut sink: Box<dyn Write + Send>,
    lines: Vec<u8>,
    rate_hz: f64,
    tick_hz: f64,
    secs: f64,
) {
    let stop = Arc::new(AtomicBool::new(false));
    let st = Arc::clone(&stop);
    let device = std::thread::spawn(move || {
        let t0 = thread_cpu();
        let start = Instant::now();
        let mut k = 0u64;
        while !st.load(Ordering::Relaxed) {
            let due = start + Duration::from_secs_f64(k as f64 / rate_hz);
            if let Some(w) = due.checked_duration_since(Instant::now()) {
                std::thread::sleep(w);
            }
            if sink.write_all(&lines).is_err() {
                break;
            }
            k += 1;
        }
        thread_cpu() - t0
    });
    d.start().unwrap();
    let cpu0 = process_cpu();
    let start = Instant::now();
    let mut posts = 0usize;
    let mut io = Io::default();
    let mut k = 0u64;
    while start.elapsed().as_secs_f64() < secs {
        let now = k as f64 / tick_hz;
        let due = start + Duration::from_secs_f64(now);
        if let Some(w) = due.checked_duration_since(Instant::now()) {
            std::thread::sleep(w);
        }
        d.step(now, &mut io);
        posts += io.posts.len();
        io.posts.clear();
        k += 1;
    }
    stop.store(true, Ordering::Relaxed);
    let cpu = process_cpu() - cpu0;
    let dev_cpu = device.join().unwrap();
    let wall = start.elapsed().as_secs_f64();
    d.stop();
    let st = d.protocol.stats();
    println!(
        "{name:<10} {:>6.0} lines/s in, {:>6.0} posts/s, driver CPU {:.3}% (device {:.3}%), lines {} errors {}",
        st.lines as f64 / wall,
        posts as f64 / wall,
        100.0 * (cpu - dev_cpu) / wall,
        100.0 * dev_cpu / wall,
        st.lines,
        st.parse_errors + st.bad_checksum
    );
}

fn serial(path: PathBuf) -> LinkConfig {
    LinkConfig::new(Endpoint::Serial {
        path,
        baud: 115_200,
    })
}

fn main() {
    let secs: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(10.0);

    // iTeensy: $DEPTH, $BATTE, $LEAK at 20 Hz; AppTick 20.
    let (m, p) = pty();
    let lines = samples::teensy().concat();
    let d = Driver::new(Teensy::new(TeensyConfig::default()), serial(p), 1.0);
    // The master's reads are drained so the driver's $CONTR never fills the pty.
    let mut rd = m.try_clone().unwrap();
    std::thread::spawn(move || {
        let mut b = [0u8; 256];
        while rd.read(&mut b).is_ok_and(|n| n > 0) {}
    });
    measure("iTeensy", d, Box::new(m), lines, 20.0, 20.0, secs);

    // iSeaTrac: STATUS (environment, attitude, AHRS_COMP) at 10 Hz; AppTick 10. Start-up
    // is not answered: the driver stays in its alive step and still reads every STATUS.
    let (m, p) = pty();
    let status = samples::seatrac_status();
    let mut rd = m.try_clone().unwrap();
    std::thread::spawn(move || {
        let mut b = [0u8; 256];
        while rd.read(&mut b).is_ok_and(|n| n > 0) {}
    });
    let d = Driver::new(SeaTrac::new(SeaTracConfig::default()), serial(p), 1.0);
    measure("iSeaTrac", d, Box::new(m), status, 10.0, 10.0, secs);

    // iGPS over NMEA: GGA + RMC at 5 Hz; AppTick 5.
    let (m, p) = pty();
    let nmea = [
        devices::nmea::with_checksum(
            "GPGGA,171530.00,4004.3079,N,11136.0123,W,1,08,0.9,1367.0,M,0.0,M,,",
        ),
        devices::nmea::with_checksum(
            "GPRMC,171530.00,A,4004.3079,N,11136.0123,W,1.0,90.0,261126,,,A",
        ),
    ]
    .map(|l| l + "\r\n")
    .concat()
    .into_bytes();
    let grid = vehicle::geodesy::LocalGrid::new(40.0717976, -111.6002054).ok();
    let d = Driver::new(Gps::new(Source::Nmea, grid), serial(p), 1.0);
    measure("iGPS", d, Box::new(m), nmea, 5.0, 5.0, secs);

    // iDVL: a velocity report (four beams) and a dead-reckoning report at 15 Hz (its highest
    // rate, near the bottom); AppTick 15.
    let l = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = l.local_addr().unwrap().port();
    let reports = [samples::a50_velocity(), samples::a50_dead_reckoning()].concat();
    let d = Driver::new(
        Dvl::new(DvlConfig::default()),
        LinkConfig::new(Endpoint::Tcp {
            host: "127.0.0.1".into(),
            port,
        }),
        1.0,
    );
    let accept = std::thread::spawn(move || l.accept().unwrap().0);
    let mut dd = d;
    dd.start().unwrap();
    let s = accept.join().unwrap();
    let mut rd = s.try_clone().unwrap();
    std::thread::spawn(move || {
        let mut b = [0u8; 256];
        while rd.read(&mut b).is_ok_and(|n| n > 0) {}
    });
    measure("iDVL", dd, Box::new(s), reports, 15.0, 15.0, secs);
}
