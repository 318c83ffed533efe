//! Helpers of the end-to-end tests: pseudo-terminal pairs standing in for serial devices, a
//! stepping loop with a bounded wait, and post lookups.

#![allow(dead_code)]

use std::fs::File;
use std::io::{Read, Write};
use std::os::fd::{AsRawFd, FromRawFd};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use drivers::{Driver, Io, Protocol};
use moos_types::Post;

/// The longest a test waits for anything (a bound, never an assertion on timing).
pub const BOUND: Duration = Duration::from_secs(20);

/// A pseudo-terminal: the test holds the master (the fake device), the driver opens the
/// slave by its path (through a symlink the test can point at a new pty: a device that
/// disappears and returns, as a udev link does).
pub struct Pty {
    /// The master side.
    pub master: File,
    /// The slave's path.
    pub slave: PathBuf,
}

impl Pty {
    /// A new pair, the slave in raw mode (no echo, no line editing) from the start.
    pub fn new() -> Pty {
        let mut m: libc::c_int = -1;
        let mut s: libc::c_int = -1;
        let mut name = [0 as libc::c_char; 128];
        // SAFETY: termios is plain data; cfmakeraw fills it.
        let mut t: libc::termios = unsafe { std::mem::zeroed() };
        // SAFETY: valid pointers to locals; `name` is large enough for a pts path.
        unsafe {
            libc::cfmakeraw(&mut t);
            let r = libc::openpty(&mut m, &mut s, name.as_mut_ptr(), &t, std::ptr::null());
            assert_eq!(r, 0, "openpty: {}", std::io::Error::last_os_error());
        }
        // SAFETY: NUL-terminated by openpty.
        let slave = unsafe { std::ffi::CStr::from_ptr(name.as_ptr()) }
            .to_string_lossy()
            .into_owned();
        // SAFETY: `s` is ours to close (the driver opens the path itself).
        unsafe { libc::close(s) };
        // SAFETY: `m` is a fresh fd we own.
        let master = unsafe { File::from_raw_fd(m) };
        Pty {
            master,
            slave: PathBuf::from(slave),
        }
    }

    /// Writes all of `data` to the device side.
    pub fn write(&mut self, data: &[u8]) {
        self.master.write_all(data).unwrap();
    }

    /// Reads what the driver wrote, waiting until `done` says the bytes so far are enough or
    /// the bound passes (then it panics with what it has).
    pub fn read_until(&mut self, mut done: impl FnMut(&[u8]) -> bool) -> Vec<u8> {
        let end = Instant::now() + BOUND;
        let mut got = Vec::new();
        let mut buf = [0u8; 4096];
        while !done(&got) {
            assert!(
                Instant::now() < end,
                "the driver did not write what was expected: {:?}",
                String::from_utf8_lossy(&got)
            );
            let mut p = libc::pollfd {
                fd: self.master.as_raw_fd(),
                events: libc::POLLIN,
                revents: 0,
            };
            // SAFETY: one valid pollfd.
            let r = unsafe { libc::poll(&mut p, 1, 50) };
            if r > 0 {
                match self.master.read(&mut buf) {
                    Ok(n) => got.extend_from_slice(&buf[..n]),
                    Err(e) if e.raw_os_error() == Some(libc::EIO) => {
                        std::thread::sleep(Duration::from_millis(10))
                    }
                    Err(e) => panic!("read: {e}"),
                }
            }
        }
        got
    }
}

/// Points the symlink `link` at `target` (replacing it).
pub fn point(link: &Path, target: &Path) {
    let _ = std::fs::remove_file(link);
    std::os::unix::fs::symlink(target, link).unwrap();
}

/// A link to `endpoint` that reconnects quickly (20 ms, backing off to 100 ms), as a test
/// wants.
pub fn fast_link(endpoint: drivers::link::Endpoint) -> drivers::link::LinkConfig {
    let mut l = drivers::link::LinkConfig::new(endpoint);
    l.backoff_min = Duration::from_millis(20);
    l.backoff_max = Duration::from_millis(100);
    l
}

/// [`fast_link`] to the serial port (or pseudo-terminal) at `path`, 115200 baud.
pub fn serial(path: &Path) -> drivers::link::LinkConfig {
    fast_link(drivers::link::Endpoint::Serial {
        path: path.to_path_buf(),
        baud: 115_200,
    })
}

/// [`fast_link`] to a TCP server at `host:port`.
pub fn tcp(host: &str, port: u16) -> drivers::link::LinkConfig {
    fast_link(drivers::link::Endpoint::Tcp {
        host: host.to_string(),
        port,
    })
}

/// A fresh scratch folder `name` under cargo's temporary folder for integration tests
/// (`target/tmp`), emptied by the next run.
pub fn scratch(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("drivers-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Steps `driver` (virtual time advancing 0.05 s a step, a short sleep between steps so the
/// link thread can run) until `done` holds for everything posted so far; panics after the
/// bound. Returns the posts and the virtual time reached.
pub struct Stepper {
    /// Virtual MOOS time.
    pub now: f64,
    /// Every post so far, with the step time it came out at.
    pub posts: Vec<(f64, Post)>,
    /// Every appcast warning so far.
    pub warnings: Vec<String>,
}

impl Stepper {
    /// From time `now`.
    pub fn new(now: f64) -> Stepper {
        Stepper {
            now,
            posts: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// One step.
    pub fn step<P: Protocol>(&mut self, d: &mut Driver<P>) {
        self.now += 0.05;
        let mut io = Io::default();
        d.step(self.now, &mut io);
        self.take(io);
    }

    /// Hands a mail to the driver at the current time.
    pub fn mail<P: Protocol>(&mut self, d: &mut Driver<P>, key: &str, v: moos_types::Value) {
        let mut io = Io::default();
        d.on_mail(key, &v, self.now, &mut io);
        self.take(io);
    }

    fn take(&mut self, io: Io) {
        let now = self.now;
        self.posts.extend(io.posts.into_iter().map(|p| (now, p)));
        self.warnings.extend(io.warnings);
    }

    /// Steps until `done(self)` or the bound (a panic naming `what`).
    pub fn until<P: Protocol>(
        &mut self,
        d: &mut Driver<P>,
        what: &str,
        mut done: impl FnMut(&Stepper, &Driver<P>) -> bool,
    ) {
        let end = Instant::now() + BOUND;
        while !done(self, d) {
            assert!(
                Instant::now() < end,
                "{what}: not within the bound; status {}",
                d.status()
            );
            self.step(d);
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    /// The double values posted to `key`, in order.
    pub fn doubles(&self, key: &str) -> Vec<f64> {
        self.posts
            .iter()
            .filter(|(_, p)| &*p.key == key)
            .filter_map(|(_, p)| p.value.as_f64())
            .collect()
    }

    /// The string values posted to `key`, in order.
    pub fn texts(&self, key: &str) -> Vec<String> {
        self.posts
            .iter()
            .filter(|(_, p)| &*p.key == key)
            .filter_map(|(_, p)| p.value.as_str().map(str::to_string))
            .collect()
    }

    /// The number of posts so far: a mark for the `*_since` lookups.
    pub fn mark(&self) -> usize {
        self.posts.len()
    }

    /// The double values posted to `key` from the post numbered `mark` on.
    pub fn doubles_since(&self, mark: usize, key: &str) -> Vec<f64> {
        self.posts[mark.min(self.posts.len())..]
            .iter()
            .filter(|(_, p)| &*p.key == key)
            .filter_map(|(_, p)| p.value.as_f64())
            .collect()
    }

    /// The string values posted to `key` from the post numbered `mark` on.
    pub fn texts_since(&self, mark: usize, key: &str) -> Vec<String> {
        self.posts[mark.min(self.posts.len())..]
            .iter()
            .filter(|(_, p)| &*p.key == key)
            .filter_map(|(_, p)| p.value.as_str().map(str::to_string))
            .collect()
    }

    /// Where the first post of `key` with the string value `value` is (its number).
    pub fn find_text(&self, key: &str, value: &str) -> Option<usize> {
        self.posts
            .iter()
            .position(|(_, p)| &*p.key == key && p.value.as_str() == Some(value))
    }

    /// Steps `n` times.
    pub fn steps<P: Protocol>(&mut self, d: &mut Driver<P>, n: usize) {
        for _ in 0..n {
            self.step(d);
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    /// The latest status text of the driver (`<DEV>_DRIVER_STATUS`), empty if none yet.
    pub fn status(&self, var: &str) -> String {
        self.texts(var).pop().unwrap_or_default()
    }

    /// How many posts of `key`.
    pub fn count(&self, key: &str) -> usize {
        self.posts.iter().filter(|(_, p)| &*p.key == key).count()
    }
}
