//! A bounded-length line accumulator shared by the four protocols, and the counters of a link.
//!
//! Bytes arrive in arbitrary pieces; [`LineSplitter::push`] hands each complete line (without
//! its `\r\n` or `\n`) to a callback. A line longer than the bound is dropped up to its next
//! newline and counted; with start bytes set (`$` for NMEA and the Teensy, `#`/`$` for the
//! SeaTrac), bytes before a start byte are counted as garbage, and a start byte in the middle
//! of a line restarts the line (the partial one is garbage: a device that was cut off).

/// What a link has seen: every counter the drivers report in their status.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LinkStats {
    /// Bytes pushed.
    pub bytes: u64,
    /// Complete lines handed on.
    pub lines: u64,
    /// Lines dropped because they exceeded the length bound.
    pub oversize: u64,
    /// Bytes dropped outside any line (before a start byte, or a partial line restarted).
    pub garbage_bytes: u64,
    /// Lines whose checksum or CRC was wrong (counted by the caller through [`LinkStats::record`]).
    pub bad_checksum: u64,
    /// Lines that did not parse for another reason (counted through [`LinkStats::record`]).
    pub parse_errors: u64,
}

/// A parse error that may be a checksum failure, so [`LinkStats::record`] can count it.
pub trait ProtocolError {
    /// True when the line was framed correctly but its checksum or CRC was wrong.
    fn is_checksum(&self) -> bool;
}

impl LinkStats {
    /// Counts a parse result: nothing for `Ok`, a bad checksum or a parse error otherwise.
    pub fn record<T, E: ProtocolError>(&mut self, result: &Result<T, E>) {
        if let Err(e) = result {
            if e.is_checksum() {
                self.bad_checksum += 1;
            } else {
                self.parse_errors += 1;
            }
        }
    }
}

/// Splits a byte stream into lines of at most `max_len` bytes.
#[derive(Debug, Clone)]
pub struct LineSplitter {
    buf: Vec<u8>,
    max_len: usize,
    starts: Vec<u8>,
    discarding: bool,
    stats: LinkStats,
}

impl LineSplitter {
    /// A splitter keeping lines of at most `max_len` bytes (not counting the line end).
    pub fn new(max_len: usize) -> Self {
        LineSplitter {
            buf: Vec::with_capacity(max_len.min(1 << 16)),
            max_len: max_len.max(1),
            starts: Vec::new(),
            discarding: false,
            stats: LinkStats::default(),
        }
    }

    /// Lines begin only at one of `starts`: other bytes outside a line are garbage, and a
    /// start byte inside a line begins a new one.
    pub fn with_starts(mut self, starts: &[u8]) -> Self {
        self.starts = starts.to_vec();
        self
    }

    /// The counters so far.
    pub fn stats(&self) -> &LinkStats {
        &self.stats
    }

    /// The counters, for the caller to [`LinkStats::record`] its parse results.
    pub fn stats_mut(&mut self) -> &mut LinkStats {
        &mut self.stats
    }

    /// Bytes of the line being accumulated.
    pub fn pending(&self) -> usize {
        self.buf.len()
    }

    /// Drops the partial line (a reconnection), counting its bytes as garbage.
    pub fn reset(&mut self) {
        self.stats.garbage_bytes += self.buf.len() as u64;
        self.buf.clear();
        self.discarding = false;
    }

    /// Feeds `data`, calling `on_line` with each complete, non-empty line.
    pub fn push(&mut self, data: &[u8], mut on_line: impl FnMut(&[u8])) {
        self.stats.bytes += data.len() as u64;
        for &b in data {
            if self.discarding {
                if b == b'\n' {
                    self.discarding = false;
                }
                continue;
            }
            let is_start = !self.starts.is_empty() && self.starts.contains(&b);
            if !self.starts.is_empty() && self.buf.is_empty() && !is_start {
                if b != b'\n' && b != b'\r' {
                    self.stats.garbage_bytes += 1;
                }
                continue;
            }
            if is_start && !self.buf.is_empty() {
                self.stats.garbage_bytes += self.buf.len() as u64;
                self.buf.clear();
            }
            if b == b'\n' {
                let mut line = &self.buf[..];
                if let [rest @ .., b'\r'] = line {
                    line = rest;
                }
                if line.len() > self.max_len {
                    self.stats.oversize += 1;
                } else if !line.is_empty() {
                    self.stats.lines += 1;
                    on_line(line);
                }
                self.buf.clear();
                continue;
            }
            if self.buf.len() > self.max_len {
                // The bound plus one byte for a `\r` before the `\n` is already held.
                self.stats.oversize += 1;
                self.buf.clear();
                self.discarding = true;
                continue;
            }
            self.buf.push(b);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lines(s: &mut LineSplitter, data: &[u8]) -> Vec<String> {
        let mut out = Vec::new();
        s.push(data, |l| out.push(String::from_utf8_lossy(l).into_owned()));
        out
    }

    #[test]
    fn partial_lines_join_across_pushes_and_crlf_is_stripped() {
        let mut s = LineSplitter::new(20);
        assert!(lines(&mut s, b"ab").is_empty());
        assert_eq!(lines(&mut s, b"c\r\nde\n\n"), vec!["abc", "de"]);
        assert_eq!(s.stats().lines, 2);
        assert_eq!(s.pending(), 0);
    }

    #[test]
    fn oversize_lines_are_dropped_to_their_newline_and_counted() {
        let mut s = LineSplitter::new(4);
        assert_eq!(
            lines(&mut s, b"abcd\r\nabcdefgh\nabcde\nxy\n"),
            vec!["abcd", "xy"]
        );
        assert_eq!(s.stats().oversize, 2);
    }

    #[test]
    fn garbage_before_a_start_byte_and_restarted_lines_are_counted() {
        let mut s = LineSplitter::new(40).with_starts(b"#$");
        assert_eq!(lines(&mut s, b"zz$AB$CD\r\n\r\n#EF\n"), vec!["$CD", "#EF"]);
        assert_eq!(s.stats().garbage_bytes, 2 + 3);
        s.push(b"$part", |_| {});
        s.reset();
        assert_eq!(s.stats().garbage_bytes, 10);
    }

    #[test]
    fn record_counts_checksum_and_other_errors_apart() {
        struct E(bool);
        impl ProtocolError for E {
            fn is_checksum(&self) -> bool {
                self.0
            }
        }
        let mut st = LinkStats::default();
        st.record::<(), E>(&Err(E(true)));
        st.record::<(), E>(&Err(E(false)));
        st.record::<(), E>(&Ok(()));
        assert_eq!((st.bad_checksum, st.parse_errors), (1, 1));
    }
}
