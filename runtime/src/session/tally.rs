//! The run report's totals counted while the alog is written, instead of reading the whole
//! log back after the run: a [`TallyWriter`] in front of the log file sees every byte
//! written and reads the lines as [`alog::parse`] would read them back from the file, but
//! only builds the records the totals use ([`TotalsBuilder::wants`]); the others count for
//! their time alone. The totals are those of the file read back (a line that `alog::parse`
//! refuses, or bytes that are not UTF-8, give no totals, as a failed read-back does).

use std::io::{self, Write};
use std::sync::{Arc, Mutex};

use moos_types::text::is_number;

use super::report::{LogTotals, TotalsBuilder};
use crate::app::Value;

/// A log file's path and the tally of what was written to it.
#[derive(Clone)]
pub(super) struct OpenLog {
    /// The alog's path.
    pub(super) path: String,
    pub(super) tally: LogTally,
}

impl std::ops::Deref for OpenLog {
    type Target = str;
    fn deref(&self) -> &str {
        &self.path
    }
}

/// The totals of the bytes a [`TallyWriter`] passed on (shared with it).
#[derive(Clone, Default)]
pub(super) struct LogTally(Arc<Mutex<Scanner>>);

impl LogTally {
    /// A writer passing every byte to `inner` and counting it here.
    pub(super) fn writer<W: Write>(&self, inner: W) -> TallyWriter<W> {
        TallyWriter {
            inner,
            scanner: self.0.clone(),
        }
    }

    /// The totals of everything written so far, as `alog::parse` and
    /// [`LogTotals::from_alog`] would give them for the file (`None` when it would refuse it).
    pub(super) fn totals(&self) -> Option<LogTotals> {
        let s = self.0.lock().unwrap_or_else(|p| p.into_inner()).clone();
        s.finish()
    }
}

/// Writes to `inner` and counts what was written (see the module).
pub(super) struct TallyWriter<W> {
    inner: W,
    scanner: Arc<Mutex<Scanner>>,
}

impl<W: Write> Write for TallyWriter<W> {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let n = self.inner.write(buf)?;
        self.scanner
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .feed(&buf[..n]);
        Ok(n)
    }

    fn flush(&mut self) -> io::Result<()> {
        self.inner.flush()
    }
}

/// A record the totals want, held until the next record line (a line that is not a record
/// continues a string value).
#[derive(Clone)]
struct Pending {
    time: f64,
    var: String,
    value: Value,
}

/// Reads the log line by line as it is written.
#[derive(Clone, Default)]
struct Scanner {
    /// The start of a line not finished yet.
    carry: Vec<u8>,
    totals: TotalsBuilder,
    /// `%% DATATYPE MARKING ON` was in the banner.
    marked: bool,
    /// A record was read (the banner is over).
    records: bool,
    /// The last record, when the totals want it.
    pending: Option<Pending>,
    /// The text after the last record's source when the totals do not want the record
    /// (whether its value is a string decides whether a following non-record line is legal).
    last_raw: String,
    /// `alog::parse` would refuse the file (or it is not UTF-8).
    broken: bool,
}

impl Scanner {
    fn feed(&mut self, mut bytes: &[u8]) {
        if self.broken {
            return;
        }
        if !self.carry.is_empty() {
            let Some(i) = memchr::memchr(b'\n', bytes) else {
                self.carry.extend_from_slice(bytes);
                return;
            };
            let mut line = std::mem::take(&mut self.carry);
            line.extend_from_slice(&bytes[..i]);
            self.line(&line, true);
            line.clear();
            self.carry = line;
            bytes = &bytes[i + 1..];
        }
        while let Some(i) = memchr::memchr(b'\n', bytes) {
            self.line(&bytes[..i], true);
            bytes = &bytes[i + 1..];
        }
        self.carry.extend_from_slice(bytes);
    }

    /// One line (without its `\n`; `ended`: it had one).
    fn line(&mut self, bytes: &[u8], ended: bool) {
        if self.broken {
            return;
        }
        let Ok(mut line) = std::str::from_utf8(bytes) else {
            self.broken = true;
            return;
        };
        // `str::lines` drops the `\r` of a `\r\n`; `alog::parse` then drops one more.
        if ended {
            line = line.strip_suffix('\r').unwrap_or(line);
        }
        line = line.strip_suffix('\r').unwrap_or(line);
        if !self.records {
            if let Some(rest) = line.strip_prefix("%%") {
                self.banner(rest.trim());
                return;
            }
            if line.trim().is_empty() {
                return;
            }
        }
        match self.record(line) {
            Some(()) => self.records = true,
            None => self.continuation(line),
        }
    }

    fn banner(&mut self, rest: &str) {
        if let Some(v) = rest.strip_prefix("LOGSTART") {
            if v.trim().parse::<f64>().is_err() {
                self.broken = true;
            }
        } else if rest == "DATATYPE MARKING ON" {
            self.marked = true;
        }
    }

    /// Reads a record line as `alog::parse_line` does; `None` if it is not one.
    fn record(&mut self, line: &str) -> Option<()> {
        let (t, rest) = token(line)?;
        let time = number(t)?;
        let (var, rest) = token(rest)?;
        let (_source, rest) = token(rest)?;
        if let Some(p) = self.pending.take() {
            self.totals.entry(p.time, &p.var, &p.value);
        }
        if TotalsBuilder::wants(var) {
            self.pending = Some(Pending {
                time,
                var: var.to_string(),
                value: self.value(rest.trim()),
            });
        } else {
            self.totals.time(time);
            // Kept untrimmed (trimmed only if a continuation line needs its type).
            self.last_raw.clear();
            self.last_raw.push_str(rest);
        }
        Some(())
    }

    /// A record's value as `alog::parse` reads it.
    fn value(&self, raw: &str) -> Value {
        if self.marked {
            if let Some(d) = raw.strip_prefix("D:") {
                d.trim()
                    .parse::<f64>()
                    .map(Value::Double)
                    .unwrap_or_else(|_| Value::text(d))
            } else {
                Value::text(raw.strip_prefix("S:").unwrap_or(raw))
            }
        } else if is_number(raw) {
            raw.parse::<f64>()
                .map(Value::Double)
                .unwrap_or_else(|_| Value::text(raw))
        } else {
            Value::text(raw)
        }
    }

    /// A line that is not a record: it continues the last record's string value, or the
    /// file is not an alog.
    fn continuation(&mut self, line: &str) {
        match &mut self.pending {
            Some(Pending {
                value: Value::String(s),
                ..
            }) => *s = format!("{s}\n{}", line.trim_end()).into(),
            Some(_) => self.broken = true,
            None if !self.records => self.broken = true,
            None => {
                if !matches!(self.value(self.last_raw.trim()), Value::String(_)) {
                    self.broken = true;
                }
            }
        }
    }

    fn finish(mut self) -> Option<LogTotals> {
        if !self.carry.is_empty() {
            let line = std::mem::take(&mut self.carry);
            self.line(&line, false);
        }
        if self.broken {
            return None;
        }
        if let Some(p) = self.pending.take() {
            self.totals.entry(p.time, &p.var, &p.value);
        }
        Some(self.totals.finish())
    }
}

/// The first white-space separated token and the text after it, as `alog`'s reader splits
/// a line (`str::trim_start`, then up to a space or a tab), on the bytes while they are
/// ASCII.
fn token(s: &str) -> Option<(&str, &str)> {
    let b = s.as_bytes();
    let mut i = 0;
    // The ASCII characters `char::is_whitespace` holds: tab, LF, VT, FF, CR and space.
    while i < b.len() && matches!(b[i], b'\t' | b'\n' | 0x0b | 0x0c | b'\r' | b' ') {
        i += 1;
    }
    if i == b.len() {
        return None;
    }
    if b[i] >= 0x80 {
        // A character beyond ASCII may be white space too.
        let s = s[i..].trim_start();
        if s.is_empty() {
            return None;
        }
        let end = s.find([' ', '\t']).unwrap_or(s.len());
        return Some((&s[..end], &s[end..]));
    }
    let s = &s[i..];
    let end = s
        .bytes()
        .position(|c| c == b' ' || c == b'\t')
        .unwrap_or(s.len());
    Some((&s[..end], &s[end..]))
}

/// Powers of ten that are exact doubles.
const POW10: [f64; 16] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

/// A record's time token as `alog`'s reader takes it (`is_number`, then `str::parse`):
/// `[-]digits[.digits]` of at most 15 digits directly (the integer of its digits and the power
/// of ten are exact doubles, so their quotient is the correctly rounded value `str::parse`
/// gives), anything else through the reader's own two steps.
fn number(t: &str) -> Option<f64> {
    let b = t.as_bytes();
    let (negative, digits) = match b.first() {
        Some(b'-') => (true, &b[1..]),
        _ => (false, b),
    };
    let (mut m, mut n, mut decimals) = (0u64, 0usize, None::<usize>);
    for &c in digits {
        match c {
            b'0'..=b'9' => {
                n += 1;
                if n > 15 {
                    return number_slow(t);
                }
                m = m * 10 + u64::from(c - b'0');
                if let Some(d) = decimals.as_mut() {
                    *d += 1;
                }
            }
            b'.' if decimals.is_none() => decimals = Some(0),
            _ => return number_slow(t),
        }
    }
    if n == 0 {
        return number_slow(t);
    }
    let v = m as f64 / POW10[decimals.unwrap_or(0)];
    Some(if negative { -v } else { v })
}

fn number_slow(t: &str) -> Option<f64> {
    if !is_number(t) {
        return None;
    }
    t.parse::<f64>().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tally of `text` written in pieces of `step` bytes.
    fn tallied(text: &str, step: usize) -> Option<LogTotals> {
        let tally = LogTally::default();
        let mut w = tally.writer(Vec::new());
        for chunk in text.as_bytes().chunks(step) {
            w.write_all(chunk).unwrap();
        }
        assert_eq!(w.inner, text.as_bytes());
        tally.totals()
    }

    /// What reading the text back gives.
    fn read_back(text: &str) -> Option<LogTotals> {
        alog::parse(text).ok().map(|l| LogTotals::from_alog(&l))
    }

    #[test]
    fn the_tally_is_the_read_back_of_the_same_bytes() {
        let texts = [
            "%% LOGSTART 0\n\
             0.0 NAV_X s 0\n0.0 NAV_Y s 0\n1.0 NAV_X s 3\n1.0 NAV_Y s 4\n\
             1.0 NAV_DEPTH s 2\n2.0 NAV_DEPTH s 1.5\n\
             2.0 IVPHELM_STATE h DRIVE\n\
             2.5 IVPHELM_SUMMARY h iter=1,active_bhvs=a$1$2:b$3,completed_bhvs=none\n\
             3.0 IVPHELM_SUMMARY h iter=2,completed_bhvs=a$9\n\
             3.5 IVPHELM_CONFIG_WARNING h bad behaviour\n\
             4.0 NAV_X s 3\n4.0 NAV_Y s 0\n9.5 OTHER s 1\n",
            // A string continued on the next lines (a wanted one and another), \r\n ends,
            // a last line without its newline.
            "%% LOGSTART 10\r\n\r\n1.0 IVPHELM_SUMMARY h completed_bhvs=a\nb,x=1\n\
             2.0 NOTE s two\nlines\n3.0 NAV_X s 1\r\n3.0 NAV_Y s 2\r\n4 NAV_X s 5",
            // Type marking: a D: value is a double, an S: one a string.
            "%% LOGSTART 0\n%% DATATYPE MARKING ON\n1 NAV_X s D:2\n1 NAV_Y s D:3\n\
             2 NAV_X s S:9\n3 NAV_Y s D:7\n",
            // A numeric string is read back as a double.
            "%% LOGSTART 0\n1 NAV_X s 4\n1 NAV_Y a 3\n2 NAV_DEPTH s deep\n",
            // Not alogs: a line that continues a double, a bad LOGSTART, a line before any
            // record.
            "%% LOGSTART 0\n1 NAV_X s 4\nnot a record\n",
            "%% LOGSTART 0\n1 OTHER s 4\nnot a record\n",
            "%% LOGSTART x\n1 NAV_X s 4\n",
            "hello\n1 NAV_X s 4\n",
            "",
        ];
        for text in texts {
            let back = read_back(text);
            for step in [1, 3, 7, 1000] {
                assert_eq!(tallied(text, step), back, "{text:?} in pieces of {step}");
            }
        }
        assert!(read_back(texts[0]).is_some_and(|t| t.summary.distance == 11.0));
        assert!(read_back(texts[4]).is_none());
    }

    #[test]
    fn times_are_the_numbers_the_reader_takes() {
        let reader = |t: &str| is_number(t).then(|| t.parse::<f64>().ok()).flatten();
        let cases = [
            "0",
            "12.34567",
            "-0",
            "-0.10000",
            "5.",
            ".5",
            "-.5",
            "123456789012345",
            "1234567890123456",
            "0.000000000000001",
            "9007199254740993",
            "+3",
            "-",
            ".",
            "",
            "1.2.3",
            "1e5",
            "--1",
            "0x10",
            "86399.99999",
            "1.00000000000000000001",
        ];
        for t in cases {
            let (got, want) = (number(t), reader(t));
            assert_eq!(got.map(f64::to_bits), want.map(f64::to_bits), "{t:?}");
        }
        // Every time pLogger writes over a day, to the bit.
        let mut s = String::new();
        for k in 0..200_000u32 {
            let x = f64::from(k) * 0.43201 + 0.000_01 * f64::from(k % 7);
            s.clear();
            moos_types::fmt::fixed(&mut s, x, 5);
            assert_eq!(
                number(&s).map(f64::to_bits),
                reader(&s).map(f64::to_bits),
                "{s}"
            );
        }
    }

    #[test]
    fn tokens_split_as_the_reader_splits() {
        for line in [
            "  1.0 \tNAV_X   src   3 ",
            "\u{a0}1.0 NAV_X s 3",
            "1.0\u{2003}NAV_X s 3",
            "\x0b\x0c1 A\tB",
            "   ",
            "",
            "\u{85}",
        ] {
            fn reader(s: &str) -> Option<(&str, &str)> {
                let s = s.trim_start();
                if s.is_empty() {
                    return None;
                }
                let end = s.find([' ', '\t']).unwrap_or(s.len());
                Some((&s[..end], &s[end..]))
            }
            assert_eq!(token(line), reader(line), "{line:?}");
        }
    }

    #[test]
    fn bytes_that_are_not_utf8_give_no_totals() {
        let tally = LogTally::default();
        let mut w = tally.writer(Vec::new());
        w.write_all(b"%% LOGSTART 0\n1 NAV_X s \xff\n").unwrap();
        assert!(tally.totals().is_none());
    }
}
