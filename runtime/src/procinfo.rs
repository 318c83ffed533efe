//! The process's own load, as MOOS's `ProcInfo` measures it for `<APP>_STATUS` (`cpuload`,
//! `memory_kb`, `memory_max_kb`) and pHelmIvP's `IVPHELM_CPU`: the share of one CPU the
//! process used since the last sample (user + system time over wall time, in percent), its
//! resident memory and the most it ever had.
//!
//! Measured only when an app runs as its own MOOS process (single-app mode): in `coug run`
//! the apps share one process, and a lockstep log stays byte-identical from run to run.

use std::time::Instant;

/// One sample of the process's load.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Load {
    /// CPU used since the previous sample, percent of one CPU.
    pub cpu_percent: f64,
    /// Resident memory now, KiB.
    pub memory_kb: u64,
    /// Peak resident memory, KiB.
    pub memory_max_kb: u64,
}

/// Samples the process's CPU time and memory.
#[derive(Debug)]
pub struct ProcInfo {
    last: Option<(Instant, f64)>,
}

impl Default for ProcInfo {
    fn default() -> Self {
        ProcInfo::new()
    }
}

/// User + system CPU seconds of this process and its peak resident memory (KiB), from
/// `getrusage`.
fn usage() -> Option<(f64, u64)> {
    // SAFETY: `getrusage` only writes the struct it is given, which lives on this stack
    // frame and is fully initialised (zeroed) beforehand.
    let mut ru: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: as above; RUSAGE_SELF is a valid `who`.
    if unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut ru) } != 0 {
        return None;
    }
    let secs = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 / 1e6;
    let max_kb = u64::try_from(ru.ru_maxrss).unwrap_or(0);
    Some((secs(ru.ru_utime) + secs(ru.ru_stime), max_kb))
}

/// Resident memory now, KiB (`/proc/self/statm` pages; 0 where that file does not exist).
fn resident_kb() -> u64 {
    let Ok(text) = std::fs::read_to_string("/proc/self/statm") else {
        return 0;
    };
    let pages: u64 = text
        .split_whitespace()
        .nth(1)
        .and_then(|p| p.parse().ok())
        .unwrap_or(0);
    // SAFETY: `sysconf` has no preconditions.
    let page = unsafe { libc::sysconf(libc::_SC_PAGESIZE) };
    pages * u64::try_from(page).unwrap_or(4096) / 1024
}

impl ProcInfo {
    /// A monitor whose first sample reports the load since the process started.
    pub fn new() -> ProcInfo {
        ProcInfo { last: None }
    }

    /// The load since the previous sample (the first: 0 % CPU, as MOOS's first value).
    pub fn sample(&mut self) -> Load {
        let now = Instant::now();
        let (cpu_s, max_kb) = usage().unwrap_or((0.0, 0));
        let cpu_percent = match self.last {
            Some((t, c)) => {
                let wall = now.duration_since(t).as_secs_f64();
                if wall > 0.0 {
                    (100.0 * (cpu_s - c) / wall).max(0.0)
                } else {
                    0.0
                }
            }
            None => 0.0,
        };
        self.last = Some((now, cpu_s));
        Load {
            cpu_percent,
            memory_kb: resident_kb(),
            memory_max_kb: max_kb,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn samples_are_sane() {
        let mut p = ProcInfo::new();
        let first = p.sample();
        assert_eq!(
            first.cpu_percent, 0.0,
            "the first sample has nothing to compare"
        );
        assert!(first.memory_max_kb > 0);
        let next = p.sample();
        assert!(next.cpu_percent >= 0.0 && next.cpu_percent.is_finite());
        assert!(next.memory_max_kb >= first.memory_max_kb);
    }
}
