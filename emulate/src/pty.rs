//! Pseudo-terminals (Unix `openpty`): the emulator holds the master side, a serial driver
//! opens the slave path (`/dev/pts/N`, or a symbolic link to it) as it would open
//! `/dev/ttyUSB0`.
//!
//! The emulator also keeps the slave open itself, so reading the master never fails while
//! no driver has the port open; what the device writes while nobody reads is dropped once
//! more than [`STALE_BYTES`] wait in the terminal's queue (a real serial port with nobody
//! listening loses its bytes too). Both sides are put in raw mode (no echo, no line
//! editing, no newline translation), as a serial driver sets its port.

use std::ffi::CStr;
use std::io;
use std::os::fd::{AsRawFd, FromRawFd, OwnedFd, RawFd};
use std::path::{Path, PathBuf};

use tokio::io::unix::AsyncFd;

/// Bytes allowed to wait unread in the slave's queue before they are flushed.
pub const STALE_BYTES: usize = 1024;

fn cvt(r: libc::c_int) -> io::Result<libc::c_int> {
    if r < 0 {
        Err(io::Error::last_os_error())
    } else {
        Ok(r)
    }
}

/// Puts a terminal in raw mode (`cfmakeraw`), 115200 baud.
pub fn set_raw(fd: RawFd) -> io::Result<()> {
    // SAFETY: `t` is a plain C struct filled by tcgetattr before use; `fd` is open.
    unsafe {
        let mut t: libc::termios = std::mem::zeroed();
        cvt(libc::tcgetattr(fd, &mut t))?;
        libc::cfmakeraw(&mut t);
        libc::cfsetispeed(&mut t, libc::B115200);
        libc::cfsetospeed(&mut t, libc::B115200);
        cvt(libc::tcsetattr(fd, libc::TCSANOW, &t))?;
    }
    Ok(())
}

fn set_nonblocking(fd: RawFd) -> io::Result<()> {
    // SAFETY: fcntl on an open descriptor with integer arguments.
    unsafe {
        let flags = cvt(libc::fcntl(fd, libc::F_GETFL))?;
        cvt(libc::fcntl(fd, libc::F_SETFL, flags | libc::O_NONBLOCK))?;
        cvt(libc::fcntl(fd, libc::F_SETFD, libc::FD_CLOEXEC))?;
    }
    Ok(())
}

/// Reads what is available from a non-blocking descriptor.
fn read_fd(fd: RawFd, buf: &mut [u8]) -> io::Result<usize> {
    // SAFETY: `buf` is valid for `buf.len()` bytes.
    let n = unsafe { libc::read(fd, buf.as_mut_ptr().cast(), buf.len()) };
    if n < 0 {
        Err(io::Error::last_os_error())
    } else {
        Ok(n as usize)
    }
}

/// Writes what fits into a non-blocking descriptor.
fn write_fd(fd: RawFd, buf: &[u8]) -> io::Result<usize> {
    // SAFETY: `buf` is valid for `buf.len()` bytes.
    let n = unsafe { libc::write(fd, buf.as_ptr().cast(), buf.len()) };
    if n < 0 {
        Err(io::Error::last_os_error())
    } else {
        Ok(n as usize)
    }
}

/// An open pseudo-terminal, master side async.
#[derive(Debug)]
pub struct Pty {
    master: AsyncFd<OwnedFd>,
    slave: OwnedFd,
    path: PathBuf,
    link: Option<PathBuf>,
}

impl Pty {
    /// Opens a new pseudo-terminal (in a tokio runtime); with `link`, a symbolic link at that
    /// path is made (or moved) to point at its slave.
    pub fn open(link: Option<&Path>) -> io::Result<Pty> {
        let (mut m, mut s): (libc::c_int, libc::c_int) = (-1, -1);
        // SAFETY: openpty writes two descriptors; the name, termios and winsize are optional.
        cvt(unsafe {
            libc::openpty(
                &mut m,
                &mut s,
                std::ptr::null_mut(),
                std::ptr::null(),
                std::ptr::null(),
            )
        })?;
        // SAFETY: both descriptors were just opened and are owned here only.
        let (master, slave) = unsafe { (OwnedFd::from_raw_fd(m), OwnedFd::from_raw_fd(s)) };
        let mut name = [0 as libc::c_char; 128];
        // SAFETY: `name` is writable for its length.
        let r = unsafe { libc::ttyname_r(slave.as_raw_fd(), name.as_mut_ptr(), name.len()) };
        if r != 0 {
            return Err(io::Error::from_raw_os_error(r));
        }
        // SAFETY: ttyname_r wrote a NUL-terminated string.
        let path = PathBuf::from(
            unsafe { CStr::from_ptr(name.as_ptr()) }
                .to_string_lossy()
                .into_owned(),
        );
        set_raw(slave.as_raw_fd())?;
        set_nonblocking(master.as_raw_fd())?;
        set_nonblocking(slave.as_raw_fd())?;
        let pty = Pty {
            // SAFETY: the OwnedFd stays open, and is the same descriptor, while registered.
            master: unsafe { AsyncFd::register(master) }?,
            slave,
            path,
            link: link.map(Path::to_path_buf),
        };
        if let Some(l) = &pty.link {
            relink(&pty.path, l)?;
        }
        Ok(pty)
    }

    /// The slave's path (`/dev/pts/N`).
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The symbolic link to the slave, if one was asked for.
    pub fn link(&self) -> Option<&Path> {
        self.link.as_deref()
    }

    /// Waits for bytes from the driver and reads them.
    pub async fn read(&self, buf: &mut [u8]) -> io::Result<usize> {
        loop {
            let mut guard = self.master.readable().await?;
            match guard.try_io(|fd| read_fd(fd.as_raw_fd(), buf)) {
                Ok(r) => return r,
                Err(_would_block) => continue,
            }
        }
    }

    /// Writes what the terminal takes now. Old bytes nobody read are flushed first (see
    /// [`STALE_BYTES`]); the outcome counts them apart from the bytes of `data` dropped
    /// because the queue was full.
    pub fn write(&self, data: &[u8]) -> io::Result<Written> {
        let slave = self.slave.as_raw_fd();
        let mut queued: libc::c_int = 0;
        let mut flushed = 0;
        // SAFETY: FIONREAD writes one int.
        if unsafe { libc::ioctl(slave, libc::FIONREAD, &mut queued) } == 0
            && queued as usize > STALE_BYTES
        {
            // SAFETY: tcflush on an open terminal.
            if unsafe { libc::tcflush(slave, libc::TCIFLUSH) } == 0 {
                flushed = queued as usize;
            }
        }
        let mut at = 0;
        while at < data.len() {
            match write_fd(self.master.get_ref().as_raw_fd(), &data[at..]) {
                Ok(0) => break,
                Ok(n) => at += n,
                Err(e) if e.kind() == io::ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
                Err(e) => return Err(e),
            }
        }
        Ok(Written {
            dropped: data.len() - at,
            flushed,
        })
    }
}

/// What [`Pty::write`] did besides writing.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Written {
    /// Bytes of the data not written (the terminal's queue was full).
    pub dropped: usize,
    /// Older bytes flushed unread from the driver's side first (more than [`STALE_BYTES`]
    /// waited): the driver may then see the tail of a cut frame.
    pub flushed: usize,
}

impl Drop for Pty {
    fn drop(&mut self) {
        // The link would point at a terminal that is gone (or, later, someone else's).
        if let Some(l) = &self.link
            && std::fs::read_link(l).is_ok_and(|p| p == self.path)
        {
            let _ = std::fs::remove_file(l);
        }
    }
}

/// Points the symbolic link `link` at `target`, replacing whatever link was there
/// (atomically: a new link renamed over the old one).
pub fn relink(target: &Path, link: &Path) -> io::Result<()> {
    let mut tmp = link.as_os_str().to_owned();
    tmp.push(format!(".{}.tmp", std::process::id()));
    let tmp = PathBuf::from(tmp);
    let _ = std::fs::remove_file(&tmp);
    std::os::unix::fs::symlink(target, &tmp)?;
    std::fs::rename(&tmp, link)
}

/// The other end, for tests and tools: a serial port opened by path (raw, non-blocking),
/// read and written asynchronously.
#[derive(Debug)]
pub struct SerialClient {
    fd: AsyncFd<OwnedFd>,
}

impl SerialClient {
    /// Opens `path` (a pseudo-terminal's slave or a link to it) in a tokio runtime.
    pub fn open(path: &Path) -> io::Result<SerialClient> {
        use std::os::unix::ffi::OsStrExt;
        let c = std::ffi::CString::new(path.as_os_str().as_bytes())
            .map_err(|_| io::Error::from(io::ErrorKind::InvalidInput))?;
        // SAFETY: a NUL-terminated path and integer flags.
        let fd = cvt(unsafe {
            libc::open(
                c.as_ptr(),
                libc::O_RDWR | libc::O_NOCTTY | libc::O_NONBLOCK | libc::O_CLOEXEC,
            )
        })?;
        // SAFETY: just opened, owned here only.
        let fd = unsafe { OwnedFd::from_raw_fd(fd) };
        set_raw(fd.as_raw_fd())?;
        Ok(SerialClient {
            // SAFETY: the OwnedFd stays open, and is the same descriptor, while registered.
            fd: unsafe { AsyncFd::register(fd) }?,
        })
    }

    /// Reads some bytes; `Ok(0)` or an error when the terminal was closed (EIO on Linux).
    pub async fn read(&self, buf: &mut [u8]) -> io::Result<usize> {
        loop {
            let mut guard = self.fd.readable().await?;
            match guard.try_io(|fd| read_fd(fd.as_raw_fd(), buf)) {
                Ok(r) => return r,
                Err(_would_block) => continue,
            }
        }
    }

    /// Writes all of `data`.
    pub async fn write_all(&self, mut data: &[u8]) -> io::Result<()> {
        while !data.is_empty() {
            let mut guard = self.fd.writable().await?;
            match guard.try_io(|fd| write_fd(fd.as_raw_fd(), data)) {
                Ok(Ok(n)) => data = &data[n..],
                Ok(Err(e)) => return Err(e),
                Err(_would_block) => continue,
            }
        }
        Ok(())
    }
}
