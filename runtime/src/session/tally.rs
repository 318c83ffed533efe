//! The run report's totals counted while the alog is written, instead of reading the whole
//! log back after the run: a [`TallyWriter`] in front of the log file sees every byte
//! written and reads the lines as [`alog::parse`] would read them back from the file, but
//! only builds the records the totals use ([`TotalsBuilder::wants`]); the others count for
//! their time alone. The totals are those of the file read back (a line that `alog::parse`
//! refuses, or bytes that are not UTF-8, give no totals, as a failed read-back does).

use std::io::{self, Write};
use std::sync::{Arc, Mutex};

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
            match std::str::from_utf8(&line) {
                Ok(text) => self.line(text, true),
                Err(_) => self.broken = true,
            }
            line.clear();
            self.carry = line;
            bytes = &bytes[i + 1..];
        }
        // The whole lines of the piece are checked as UTF-8 at once: a `\n` never sits
        // inside a character, so they are all text exactly when each line is.
        let whole = memchr::memrchr(b'\n', bytes).map_or(0, |i| i + 1);
        let Ok(mut text) = std::str::from_utf8(&bytes[..whole]) else {
            self.broken = true;
            return;
        };
        while let Some(i) = memchr::memchr(b'\n', text.as_bytes()) {
            if self.broken {
                return;
            }
            self.line(&text[..i], true);
            text = &text[i + 1..];
        }
        self.carry.extend_from_slice(&bytes[whole..]);
    }

    /// One line (without its `\n`; `ended`: it had one).
    fn line(&mut self, mut line: &str, ended: bool) {
        if self.broken {
            return;
        }
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
        let (t, rest) = alog::field(line)?;
        let time = alog::parse_time(t)?;
        let (var, rest) = alog::field(rest)?;
        let (_source, rest) = alog::field(rest)?;
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
        alog::parse_value(raw, self.marked)
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
            match std::str::from_utf8(&line) {
                Ok(text) => self.line(text, false),
                Err(_) => self.broken = true,
            }
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
            // Characters beyond ASCII (split across pieces when written in small ones),
            // white space beyond ASCII between fields.
            "%% LOGSTART 0\n1 NAV_X s\u{2003}4\n1 NAV_Y é 3\n2 IVPHELM_STATE h DRIVÉ\n\
             3\u{a0}NAV_X s 5\n4 NAV_Y s 日本\n",
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
        assert!(read_back(texts[5]).is_none());
    }

    #[test]
    fn bytes_that_are_not_utf8_give_no_totals() {
        let tally = LogTally::default();
        let mut w = tally.writer(Vec::new());
        w.write_all(b"%% LOGSTART 0\n1 NAV_X s \xff\n").unwrap();
        assert!(tally.totals().is_none());
    }
}
