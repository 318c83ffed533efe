//! The run report's totals counted while the alog is written, instead of reading the whole
//! log back after the run. pLogger shows the session's [`LogTally`] (held by its
//! [`crate::logger::LateSink`]) every line it writes to the alog: the banner, then each
//! record with what the writer knows of its line ([`alog::Line`]: the time and a double
//! value as they read back). A record whose line reads back as one record of the variable
//! and source given and a one-line value (nearly all) counts from those alone, and only the
//! records the totals use ([`TotalsBuilder::wants`]) have their value read; the others count
//! for their time alone. Any other line (an empty variable or source, or one holding white
//! space, a value over several lines, a time written other than from its rounded digits) is
//! read as [`alog::parse`] would read it from the file. The totals are those of the file
//! read back (a file `alog::parse` refuses gives no totals, as a failed read-back does).

use std::sync::{Arc, Mutex, MutexGuard};

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

/// The totals of the lines written to an alog (shared by the session and its pLogger).
#[derive(Clone, Default)]
pub(crate) struct LogTally(Arc<Mutex<Tally>>);

impl LogTally {
    /// The tally, to count lines into (pLogger holds it over a batch of mail).
    pub(crate) fn lock(&self) -> MutexGuard<'_, Tally> {
        self.0.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// The totals of everything written so far, as `alog::parse` and
    /// [`LogTotals::from_alog`] would give them for the file (`None` when it would refuse it).
    pub(super) fn totals(&self) -> Option<LogTotals> {
        self.lock().clone().finish()
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

/// The totals of an alog's lines, counted in the order they are written.
#[derive(Clone, Default)]
pub(crate) struct Tally {
    /// The start of a line not finished yet.
    carry: String,
    totals: TotalsBuilder,
    /// `%% DATATYPE MARKING ON` was in the banner.
    marked: bool,
    /// A record was read (the banner is over).
    records: bool,
    /// The last record, when the totals want it.
    pending: Option<Pending>,
    /// The last pending record's variable name, kept for its allocation.
    spare: String,
    /// The last record's value reads back as a double, not a string, when the totals do not
    /// want the record (a following non-record line is then not legal).
    last_double: bool,
    /// `alog::parse` would refuse the file.
    broken: bool,
}

/// True when `name`, written as a record's variable or source column, reads back as itself:
/// not empty, no white space.
#[inline]
fn plain(name: &str) -> bool {
    !name.is_empty() && (graphic(name.as_bytes()) || !name.chars().any(char::is_whitespace))
}

/// True when every byte of `b` is ASCII above the space (no white space, no control
/// character but DEL), eight bytes at a time: a byte outside `!` ..= DEL sets its top bit
/// in `x` itself (from 0x80) or in `x - 0x2121…21` (below 0x21: the lowest such byte gets
/// no borrow from the bytes below it, which are all in range and borrow nothing).
/// Shorter texts byte by byte; the last eight bytes of a longer one read as a word of
/// their own (overlapping the last whole word).
#[inline]
fn graphic(b: &[u8]) -> bool {
    const ONES: u64 = 0x0101_0101_0101_0101;
    let outside = |x: u64| (x.wrapping_sub(0x21 * ONES) | x) & (0x80 * ONES) != 0;
    let word = |at: usize| u64::from_le_bytes(b[at..at + 8].try_into().expect("8 bytes"));
    if b.len() < 8 {
        return b.iter().all(|&c| c.wrapping_sub(b'!') < 0x5f);
    }
    (0..b.len() / 8).all(|k| !outside(word(8 * k))) && !outside(word(b.len() - 8))
}

/// What the tally needs to know of a variable's name, found once per name (pLogger keeps it
/// with the variable).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Name {
    /// The name reads back as itself from its column (see [`plain`]).
    plain: bool,
    /// The totals use the variable's values ([`TotalsBuilder::wants`]).
    wanted: bool,
}

impl Name {
    /// The facts of the variable `var`.
    pub(crate) fn of(var: &str) -> Name {
        Name {
            plain: plain(var),
            wanted: TotalsBuilder::wants(var),
        }
    }
}

impl Tally {
    /// Counts a record pLogger wrote: `var` (whose facts are `name`) and `source` as given to
    /// the writer, `line` as it wrote them.
    #[inline]
    pub(crate) fn record(&mut self, var: &str, name: Name, source: &str, line: alog::Line<'_>) {
        if self.broken {
            return;
        }
        match line.time {
            // The line reads back as the record of `var` (`alog::field` splits it at its
            // padding, the time field reads back as `time`), its value the text `line.value`.
            Some(time)
                if name.plain
                    && plain(source)
                    && self.carry.is_empty()
                    && (line.double.is_some()
                        || memchr::memchr(b'\n', line.value.as_bytes()).is_none()) =>
            {
                self.take_pending();
                if name.wanted {
                    let value = match line.double {
                        Some(x) => Value::Double(x),
                        None => self.value(line.value.trim()),
                    };
                    self.pend(time, var, value);
                } else {
                    self.totals.time(time);
                    self.last_double = line.double.is_some()
                        || alog::parse_double(line.value.trim(), self.marked).is_some();
                }
                self.records = true;
            }
            _ => self.text(line.text),
        }
    }

    /// Counts text written to the alog (the banner, a record's line): its lines as
    /// `alog::parse` reads them (a last line without its `\n` waits for the rest).
    pub(crate) fn text(&mut self, mut text: &str) {
        if self.broken {
            return;
        }
        if !self.carry.is_empty() {
            let Some(i) = memchr::memchr(b'\n', text.as_bytes()) else {
                self.carry.push_str(text);
                return;
            };
            let mut line = std::mem::take(&mut self.carry);
            line.push_str(&text[..i]);
            self.line(&line, true);
            line.clear();
            self.carry = line;
            text = &text[i + 1..];
        }
        while let Some(i) = memchr::memchr(b'\n', text.as_bytes()) {
            if self.broken {
                return;
            }
            self.line(&text[..i], true);
            text = &text[i + 1..];
        }
        self.carry.push_str(text);
    }

    /// Counts the pending record, if any.
    #[inline]
    fn take_pending(&mut self) {
        if self.pending.is_some() {
            self.count_pending();
        }
    }

    #[cold]
    fn count_pending(&mut self) {
        if let Some(p) = self.pending.take() {
            self.totals.entry(p.time, &p.var, &p.value);
            self.spare = p.var;
        }
    }

    /// Holds a record the totals want until the next record line.
    fn pend(&mut self, time: f64, var: &str, value: Value) {
        let mut name = std::mem::take(&mut self.spare);
        name.clear();
        name.push_str(var);
        self.pending = Some(Pending {
            time,
            var: name,
            value,
        });
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
        match self.read_record(line) {
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
    fn read_record(&mut self, line: &str) -> Option<()> {
        let (t, rest) = alog::field(line)?;
        let time = alog::parse_time(t)?;
        let (var, rest) = alog::field(rest)?;
        let (_source, rest) = alog::field(rest)?;
        self.take_pending();
        if TotalsBuilder::wants(var) {
            let value = self.value(rest.trim());
            self.pend(time, var, value);
        } else {
            self.totals.time(time);
            self.last_double = alog::parse_double(rest.trim(), self.marked).is_some();
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
                if self.last_double {
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
        self.take_pending();
        Some(self.totals.finish())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::app::App;
    use crate::logger::{Logger, LoggerConfig, SharedBuffer};
    use proptest::prelude::*;

    /// LOGSTART of the logs written here.
    const START: f64 = 100.0;

    /// One mail to log: time relative to LOGSTART, variable, source, value.
    type Rec<'a> = (f64, &'a str, &'a str, Value);

    /// Logs `records` with pLogger (wildcard logging, `extra` lines in its block), counting
    /// them in a tally as a session does; returns the alog's text and the tally's totals.
    fn logged(records: &[Rec<'_>], extra: &str) -> (String, Option<LogTotals>) {
        let text = format!(
            "ProcessConfig = pLogger\n{{\n  AsyncLog = true\n  WildCardLogging = true\n{extra}}}\n"
        );
        let src = mission::source::SourceMap::from_text("t.moos", &text);
        let block = mission::moos::parse_moos(&src).value.processes[0].clone();
        let config = LoggerConfig::from_config(Some(&block), None);
        let buf = SharedBuffer::default();
        let opened = chrono::NaiveDate::from_ymd_opt(2026, 11, 27)
            .unwrap()
            .and_hms_opt(6, 0, 0)
            .unwrap();
        let tally = LogTally::default();
        let mut lg = Logger::new("pLogger", Some(block), config, buf.clone(), &opened, "x")
            .with_tally(tally.clone());
        let mut out = Vec::new();
        lg.on_startup(START, &mut out).unwrap();
        // In batches of three, as mail comes.
        for batch in records.chunks(3) {
            let mail: Vec<_> = batch
                .iter()
                .map(|(t, var, source, value)| {
                    crate::testing::mail(var, value.clone(), START + t, source)
                })
                .collect();
            lg.on_mail(&mail, START, &mut out).unwrap();
        }
        lg.stop(START).unwrap();
        let text = String::from_utf8(buf.contents()).unwrap();
        (text, tally.totals())
    }

    /// What reading the text back gives.
    fn read_back(text: &str) -> Option<LogTotals> {
        alog::parse(text).ok().map(|l| LogTotals::from_alog(&l))
    }

    /// Equal totals, a NaN (a logged `nan` position) equal to a NaN in the same place: the
    /// two print the same.
    fn same(a: &Option<LogTotals>, b: &Option<LogTotals>) -> bool {
        a == b || format!("{a:?}") == format!("{b:?}")
    }

    fn d(x: f64) -> Value {
        Value::Double(x)
    }

    fn s(x: &str) -> Value {
        Value::text(x)
    }

    /// Logs `records` with and without type marking (and with 7 decimals, written through
    /// the general formatter): the tally is what reading the same bytes back gives.
    fn check(records: &[Rec<'_>]) -> Vec<Option<LogTotals>> {
        let mut all = Vec::new();
        for extra in ["", "  MarkDataType = true\n", "  DoublePrecision = 7\n"] {
            let (text, tally) = logged(records, extra);
            let back = read_back(&text);
            assert!(same(&tally, &back), "{tally:?}\n{back:?}\n{extra}{text}");
            all.push(tally);
        }
        all
    }

    #[test]
    fn graphic_names_are_those_of_ascii_bytes_above_the_space() {
        let bytes: Vec<u8> = (0..=255).collect();
        for len in 0..20 {
            for &b in &bytes {
                for at in 0..len {
                    let mut name = vec![b'A'; len];
                    name[at] = b;
                    let want = name.iter().all(|c| (b'!'..=0x7f).contains(c));
                    assert_eq!(graphic(&name), want, "{name:?}");
                }
            }
        }
        assert!(graphic(b""));
        assert!(!plain(""));
        assert!(plain("pNavGraph") && plain("DRIVÉ") && plain("a\x01b"));
        assert!(!plain("a b") && !plain("a\tb") && !plain("\u{2003}x") && !plain("x\n"));
    }

    #[test]
    fn the_tally_is_the_read_back_of_the_same_bytes() {
        // The totals' variables and others.
        let plain = [
            (0.0, "NAV_X", "s", d(0.0)),
            (0.0, "NAV_Y", "s", d(0.0)),
            (1.0, "NAV_X", "s", d(3.0)),
            (1.0, "NAV_Y", "s", d(4.0)),
            (1.0, "NAV_DEPTH", "s", d(2.0)),
            (2.0, "NAV_DEPTH", "s", d(1.5)),
            (2.0, "IVPHELM_STATE", "h", s("DRIVE")),
            (
                2.5,
                "IVPHELM_SUMMARY",
                "h",
                s("iter=1,active_bhvs=a$1$2:b$3,completed_bhvs=none"),
            ),
            (3.0, "IVPHELM_SUMMARY", "h", s("iter=2,completed_bhvs=a$9")),
            (3.5, "IVPHELM_CONFIG_WARNING", "h", s("bad behaviour")),
            (4.0, "NAV_X", "s", d(3.0)),
            (4.0, "NAV_Y", "s", d(0.0)),
            (9.5, "OTHER", "s", d(1.0)),
            (9.75, "TEXT", "s", s("words")),
        ];
        let totals = check(&plain);
        assert!(
            totals[0]
                .as_ref()
                .is_some_and(|t| t.summary.distance == 11.0
                    && t.completed == ["a"]
                    && t.malconfig == ["bad behaviour"])
        );
        let cases: Vec<Vec<Rec<'_>>> = vec![
            // Strings over several lines, wanted and not; a following line that reads as a
            // record of its own, or as a banner line; `\r` at the ends of lines.
            vec![
                (1.0, "IVPHELM_SUMMARY", "h", s("completed_bhvs=a\nb,x=1")),
                (2.0, "NOTE", "s", s("two\nlines")),
                (2.5, "NOTE", "s", s("x\n5 NAV_X s 99")),
                (2.6, "NOTE", "s", s("x\n%% LOGSTART 3")),
                (3.0, "NAV_X", "s", d(1.0)),
                (3.0, "NAV_Y", "s", s("2\r\n")),
                (3.1, "NAV_Y", "s", s("a\r\r\nb\r")),
                (4.0, "IVPHELM_STATE", "h", s("\nDRIVE\n")),
            ],
            // Numeric strings read back as doubles (unmarked); strings like marks.
            vec![
                (1.0, "NAV_X", "s", s("4")),
                (1.0, "NAV_Y", "a", s(" 3 ")),
                (2.0, "NAV_DEPTH", "s", s("deep")),
                (2.0, "NAV_DEPTH", "s", s("-.5")),
                (3.0, "NAV_X", "s", s("D:7")),
                (3.0, "NAV_Y", "s", s("S:1")),
                (3.0, "IVPHELM_STATE", "s", s("12")),
            ],
            // Beyond ASCII: names, values, white space in names (the columns then read back
            // otherwise), empty names.
            vec![
                (1.0, "NAV_X", "s", d(4.0)),
                (1.0, "NAV_Y", "é", s("3")),
                (2.0, "IVPHELM_STATE", "h", s("DRIVÉ")),
                (3.0, "NAV\u{a0}X", "s", d(5.0)),
                (4.0, "NAV_Y", "s", s("日本")),
                (5.0, "NAV_X", "s\u{2003}t", d(8.0)),
                (5.0, "NAV X", "s", d(8.0)),
                (6.0, "", "NAV_X", d(9.0)),
                (6.0, "NAV_DEPTH", "", d(9.0)),
                (6.0, "\u{2003}NAV_DEPTH", "s", d(10.0)),
            ],
            // Times and values the writer writes through the general formatter: NaN,
            // infinities, before LOGSTART, far beyond it, on rounding ties.
            vec![
                (f64::NAN, "NAV_X", "s", d(1.0)),
                (f64::INFINITY, "NAV_Y", "s", d(2.0)),
                (-1.0, "NAV_DEPTH", "s", d(f64::NAN)),
                (1e7, "NAV_DEPTH", "s", d(f64::INFINITY)),
                (0.000_005, "NAV_X", "s", d(0.000_005)),
                (1.0, "NAV_Y", "s", d(1e20)),
                (2.0, "NAV_Y", "s", d(-0.000_001)),
                (3.0, "OTHER", "s", d(f64::NEG_INFINITY)),
            ],
            // Binary data, as its reference.
            vec![
                (1.0, "NAV_X", "s", d(1.0)),
                (2.0, "IMG", "cam", Value::Binary(vec![1, 2, 3])),
                (3.0, "NAV_X", "s", Value::Binary(vec![4])),
            ],
            // Not alogs once read back: a line that continues a double (a record whose
            // variable and source columns are empty).
            vec![(1.0, "NAV_X", "s", d(4.0)), (2.0, "", "", s("word"))],
            vec![(1.0, "OTHER", "s", d(4.0)), (2.0, "", "", s("word"))],
            vec![(1.0, "OTHER", "s", s("4")), (2.0, "", "", s("word"))],
            vec![(1.0, "OTHER", "s", s("w")), (2.0, "", "", s("word"))],
            vec![(2.0, "", "", s("word")), (3.0, "NAV_X", "s", d(4.0))],
            vec![],
            // A position read back as NaN (the CI failure of the proptest below).
            vec![
                (0.0, "NAV_X", "s", d(0.0)),
                (0.0, "NAV_Y", "é", d(f64::NAN)),
            ],
        ];
        for records in &cases {
            check(records);
        }
        assert!(
            logged(&cases[5], "").1.is_none(),
            "a line continuing a double"
        );
        assert!(logged(&cases[8], "").1.is_some());
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(200))]

        /// Records of names and values made of awkward pieces (line breaks, white space,
        /// marks, numbers, text beyond ASCII).
        #[test]
        fn any_records_tally_as_they_read_back(
            records in proptest::collection::vec(
                (
                    proptest::prop_oneof![
                        proptest::strategy::Just(f64::NAN),
                        -2.0f64..1e3,
                        (0u32..1000).prop_map(|k| f64::from(k) / 100.0 + 0.000_005),
                    ],
                    proptest::sample::select(vec![
                        "NAV_X", "NAV_Y", "NAV_DEPTH", "IVPHELM_STATE", "IVPHELM_SUMMARY",
                        "IVPHELM_CONFIG_WARNING", "OTHER", "", "A B", "É", "\u{a0}",
                    ]),
                    proptest::sample::select(vec!["s", "", "x y", "é"]),
                    proptest::prop_oneof![
                        proptest::num::f64::ANY.prop_map(Value::Double),
                        (-1e4f64..1e4).prop_map(Value::Double),
                        proptest::collection::vec(
                            proptest::sample::select(vec![
                                "1", "-2.5", " ", "\n", "\r", "\r\n", "D:", "S:", "x",
                                "completed_bhvs=", "a$1", ",", "é", "\u{2003}", "%%",
                                "5 NAV_X s 1", "NAV_Y",
                            ]),
                            0..6,
                        )
                        .prop_map(|p| Value::text(p.concat())),
                    ],
                ),
                0..12,
            )
        ) {
            let recs: Vec<Rec<'_>> = records
                .iter()
                .map(|(t, var, source, value)| (*t, *var, *source, value.clone()))
                .collect();
            for extra in ["", "  MarkDataType = true\n", "  DoublePrecision = 7\n"] {
                let (text, tally) = logged(&recs, extra);
                let back = read_back(&text);
                proptest::prop_assert!(
                    same(&tally, &back),
                    "{:?}\n{:?}\n{}{}",
                    tally,
                    back,
                    extra,
                    text
                );
            }
        }
    }
}
