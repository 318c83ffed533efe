//! The alog writer: banner and records, byte for byte as pLogger writes them.

use std::io::{self, Write};

use moos_types::fmt::{fixed as fmt_fixed, g as fmt_g};

/// The banner's first and last line: 59 `%`.
pub const BANNER_RULE: &str = "%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%";

/// What the banner says about the file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Header<'a> {
    /// The log file's path as pLogger prints it (`./LOG_X_.../LOG_X_....alog`).
    pub path: &'a str,
    /// The `FILE OPENED ON` text, without newline (see [`crate::ctime`]). pLogger 2024
    /// prints the Unix epoch here (`Thu Jan  1 00:00:00 1970`, a MOOSGetDate quirk).
    pub opened_on: &'a str,
    /// LOGSTART: the logger's start MOOS time; record times are written relative to it.
    pub log_start: f64,
    /// `MarkDataType=true`: adds `%% DATATYPE MARKING ON` and `D:`/`S:` value prefixes.
    pub mark_data_type: bool,
}

/// A value to log.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LogValue<'a> {
    /// A double, written fixed with the writer's precision, left-aligned in 12 columns.
    Double(f64),
    /// A string, written raw.
    String(&'a str),
    /// Binary data already stored in the `.blog` file: written as the
    /// `<MOOS_BINARY>File=..,Offset=..,Bytes=..</MOOS_BINARY>` reference.
    Binary {
        /// The `.blog` file name (`<root>.blog`).
        file: &'a str,
        /// Byte offset of the data in that file.
        offset: u64,
        /// Length of the data.
        bytes: u64,
    },
}

/// A record's line as the writer formatted it, with what its text reads back as where the
/// writer knows it without reading the text: for a caller that counts the records as the
/// file will read back (the run report's tally) without parsing every line. See
/// [`AlogWriter::record_seen`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line<'a> {
    /// The whole line, with its `\n`.
    pub text: &'a str,
    /// The value's text: from its `D:`/`S:` mark (or its first byte) up to the line's final
    /// ` \n` (a double's padding included). [`crate::parse_value`] of it, trimmed, is the
    /// value as read back when the line reads back as one record.
    pub value: &'a str,
    /// The time as the line's time field reads back ([`crate::parse_time`]), when the writer
    /// wrote it from the rounded integer of its digits (not for NaN, infinities, times of
    /// 2^37 / 10^5 s and more, nor within 1e-10 s of a rounding tie).
    pub time: Option<f64>,
    /// A double value as its text reads back ([`crate::parse_value`]), when the writer wrote
    /// it from the rounded integer of its digits (see [`Line::time`]; also not with more
    /// than 6 decimals).
    pub double: Option<f64>,
}

/// Writes an alog file: the banner on creation, then one line per [`AlogWriter::record`].
///
/// Records are written in the order given; pLogger sorts each batch of mail by time first
/// (callers do the same). Lines are formatted straight into the writer's own buffer, which
/// goes to `out` in large pieces (once it holds [`AlogWriter::CHUNK`] bytes) and on
/// [`AlogWriter::flush`]; dropping the writer hands `out` what is left, as a `BufWriter` does.
#[derive(Debug)]
pub struct AlogWriter<W: Write> {
    /// `None` only once [`AlogWriter::into_inner`] took it.
    out: Option<W>,
    log_start: f64,
    precision: usize,
    mark_data_type: bool,
    /// The lines not handed on yet (text only: every piece pushed is text or ASCII).
    buf: String,
    /// The last record's time column (most records share their time with the one before).
    time: TimeColumn,
}

/// What the writer keeps of one variable's last record, to write the next one with less work
/// (see [`AlogWriter::record_cached`]; pLogger keeps one per variable): the variable and
/// source columns, and the value column when the value was a double (about half of a
/// CougUV's records repeat their variable's last value).
#[derive(Debug, Clone)]
pub struct RecordCache {
    /// The variable's column, its space, then the last source's column and its space.
    names: String,
    /// The length of the variable's name, then where the source's column starts.
    var_len: usize,
    source_at: usize,
    /// The last source (`None`: no record yet).
    source: Option<std::ops::Range<usize>>,
    /// The last double value's bits, with the precision and the type marking written.
    double: Option<(u64, usize, bool)>,
    /// That value's column, and the value it reads back as.
    double_text: String,
    double_back: Option<f64>,
}

impl RecordCache {
    /// The cache of the records of `var`.
    pub fn new(var: &str) -> RecordCache {
        let mut names = String::with_capacity(40);
        push_padded(&mut names, var, 20);
        names.push(' ');
        RecordCache {
            source_at: names.len(),
            names,
            var_len: var.len(),
            source: None,
            double: None,
            double_text: String::new(),
            double_back: None,
        }
    }

    /// The variable's name.
    pub fn var(&self) -> &str {
        &self.names[..self.var_len]
    }

    /// The variable and source columns for a record from `source`.
    #[inline]
    fn names(&mut self, source: &str) -> &str {
        if self.source.clone().map(|r| &self.names[r]) != Some(source) {
            self.names.truncate(self.source_at);
            push_padded(&mut self.names, source, 15);
            self.source = Some(self.source_at..self.source_at + source.len());
            self.names.push(' ');
        }
        &self.names
    }

    /// Appends the value column of the double `x` (the one kept when it is the last value).
    #[inline]
    fn push_double(
        &mut self,
        out: &mut String,
        x: f64,
        precision: usize,
        mark: bool,
    ) -> Option<f64> {
        let key = (x.to_bits(), precision, mark);
        if self.double != Some(key) {
            self.double_text.clear();
            self.double_back = push_double(&mut self.double_text, x, precision, mark);
            self.double = Some(key);
        }
        out.push_str(&self.double_text);
        self.double_back
    }
}

/// A record's time column, kept for the next record of the same time.
#[derive(Debug, Default)]
struct TimeColumn {
    /// The bits of the time relative to LOGSTART (`None`: no record yet).
    rel: Option<u64>,
    /// The time written, with its padding.
    text: String,
    /// The time as it reads back (see [`Line::time`]).
    back: Option<f64>,
}

impl TimeColumn {
    /// Appends the time column of `rel` (the one kept when `rel` is the last record's time).
    #[inline]
    fn push(&mut self, out: &mut String, rel: f64) -> Option<f64> {
        if self.rel != Some(rel.to_bits()) {
            self.text.clear();
            self.back = push_time(&mut self.text, rel);
            self.rel = Some(rel.to_bits());
        }
        out.push_str(&self.text);
        self.back
    }
}

impl<W: Write> AlogWriter<W> {
    /// The size at which the buffered lines are handed to the underlying writer.
    pub const CHUNK: usize = 8 << 10;

    fn with_out(out: W, log_start: f64, mark_data_type: bool) -> Self {
        AlogWriter {
            out: Some(out),
            log_start,
            precision: 5,
            mark_data_type,
            buf: String::with_capacity(Self::CHUNK + 512),
            time: TimeColumn::default(),
        }
    }

    /// Writes the banner to `out` and returns the writer (DoublePrecision 5).
    pub fn new(out: W, header: &Header<'_>) -> io::Result<Self> {
        let mut w = Self::with_out(out, header.log_start, header.mark_data_type);
        w.out_mut().write_all(banner(header).as_bytes())?;
        Ok(w)
    }

    /// A writer without a banner (pLogger's `.xlog` of excluded variables has none): records
    /// relative to `log_start`, DoublePrecision 5.
    pub fn headless(out: W, log_start: f64, mark_data_type: bool) -> Self {
        Self::with_out(out, log_start, mark_data_type)
    }

    fn out_mut(&mut self) -> &mut W {
        self.out
            .as_mut()
            .expect("the writer is only taken by into_inner")
    }

    /// Sets the number of decimals of double values (pLogger `DoublePrecision`, default 5).
    pub fn set_double_precision(&mut self, decimals: usize) {
        self.precision = decimals;
    }

    /// The LOGSTART time.
    pub fn log_start(&self) -> f64 {
        self.log_start
    }

    /// Writes one record: `time` is the message's MOOS time (written as `time − LOGSTART`),
    /// `source` the publishing app (with any `:aux` / `@community` already appended).
    ///
    /// The line is buffered: a write error of the underlying writer is returned by the
    /// record that fills the buffer, or by [`AlogWriter::flush`].
    pub fn record(
        &mut self,
        time: f64,
        var: &str,
        source: &str,
        value: LogValue<'_>,
    ) -> io::Result<()> {
        self.record_seen(time, var, source, value, |_| {})
    }

    /// Writes one record as [`AlogWriter::record`] does, and shows `seen` its line (before
    /// it is handed on).
    pub fn record_seen(
        &mut self,
        time: f64,
        var: &str,
        source: &str,
        value: LogValue<'_>,
        seen: impl FnOnce(Line<'_>),
    ) -> io::Result<()> {
        let start = self.buf.len();
        let time = self.time.push(&mut self.buf, time - self.log_start);
        let f = push_columns(
            &mut self.buf,
            start,
            var,
            source,
            value,
            self.precision,
            self.mark_data_type,
        );
        self.written(start, f.value_at, time, f.double, seen)
    }

    /// Writes one record of `cache`'s variable as [`AlogWriter::record_seen`] does, with the
    /// columns the cache holds from the variable's last record where they are the same.
    pub fn record_cached(
        &mut self,
        time: f64,
        cache: &mut RecordCache,
        source: &str,
        value: LogValue<'_>,
        seen: impl FnOnce(Line<'_>),
    ) -> io::Result<()> {
        let start = self.buf.len();
        let time = self.time.push(&mut self.buf, time - self.log_start);
        self.buf.push_str(cache.names(source));
        let value_at = self.buf.len() - start;
        let double = match value {
            LogValue::Double(x) => {
                let back = cache.push_double(&mut self.buf, x, self.precision, self.mark_data_type);
                self.buf.push_str(" \n");
                back
            }
            _ => push_value(&mut self.buf, value, self.precision, self.mark_data_type),
        };
        self.written(start, value_at, time, double, seen)
    }

    /// After a record's line (from `start`, its value from `value_at` on): shows `seen` the
    /// line, then hands the buffer on once it is full.
    #[inline]
    fn written(
        &mut self,
        start: usize,
        value_at: usize,
        time: Option<f64>,
        double: Option<f64>,
        seen: impl FnOnce(Line<'_>),
    ) -> io::Result<()> {
        let text = &self.buf[start..];
        seen(Line {
            text,
            value: &text[value_at..text.len() - 2],
            time,
            double,
        });
        if self.buf.len() >= Self::CHUNK {
            self.write_buffered()?;
        }
        Ok(())
    }

    /// Hands the buffered lines to the underlying writer (all of them, or an error; the
    /// buffer is emptied either way, as the bytes' fate is then the writer's).
    fn write_buffered(&mut self) -> io::Result<()> {
        if self.buf.is_empty() {
            return Ok(());
        }
        let Some(out) = self.out.as_mut() else {
            return Ok(());
        };
        let r = out.write_all(self.buf.as_bytes());
        self.buf.clear();
        r
    }

    /// Hands the buffered lines to the underlying writer without flushing it (pLogger does
    /// so after each batch of mail: the writer then holds every record logged so far).
    pub fn pass_on(&mut self) -> io::Result<()> {
        self.write_buffered()
    }

    /// Writes the buffered lines and flushes the underlying writer.
    pub fn flush(&mut self) -> io::Result<()> {
        self.write_buffered()?;
        self.out_mut().flush()
    }

    /// The underlying writer (lines still in the writer's buffer are not in it yet).
    pub fn get_ref(&self) -> &W {
        self.out
            .as_ref()
            .expect("the writer is only taken by into_inner")
    }

    /// Writes the buffered lines and gives back the underlying writer (a write error there
    /// is lost, as when a `BufWriter` is dropped: call [`AlogWriter::flush`] first to see it).
    pub fn into_inner(mut self) -> W {
        let _ = self.write_buffered();
        self.out
            .take()
            .expect("the writer is only taken by into_inner")
    }
}

impl<W: Write> Drop for AlogWriter<W> {
    /// Hands the underlying writer the lines still buffered (errors are lost, as a dropped
    /// `BufWriter`'s are).
    fn drop(&mut self) {
        let _ = self.write_buffered();
    }
}

/// The 5- or 6-line banner [`AlogWriter::new`] writes.
pub fn banner(h: &Header<'_>) -> String {
    let mut out = String::with_capacity(256);
    write_banner(&mut out, h);
    out
}

/// Appends the 5- or 6-line banner.
fn write_banner(out: &mut String, h: &Header<'_>) {
    out.push_str(BANNER_RULE);
    out.push('\n');
    out.push_str("%% LOG FILE:       ");
    out.push_str(h.path);
    out.push('\n');
    out.push_str("%% FILE OPENED ON  ");
    out.push_str(h.opened_on.trim_end_matches('\n'));
    out.push('\n');
    out.push_str("%% LOGSTART        ");
    let mut start = String::new();
    fmt_g(&mut start, h.log_start, 16);
    pad_left(out, &start, 20);
    out.push('\n');
    if h.mark_data_type {
        out.push_str("%% DATATYPE MARKING ON\n");
    }
    out.push_str(BANNER_RULE);
    out.push('\n');
}

fn pad_left(out: &mut String, s: &str, width: usize) {
    for _ in s.chars().count()..width {
        out.push(' ');
    }
    out.push_str(s);
}

/// Spaces to pad a column from (the widest column is 20).
const SPACES: &str = "                    ";

/// Appends `n` spaces (at most 20).
fn spaces(out: &mut String, n: usize) {
    out.push_str(&SPACES[..n.min(SPACES.len())]);
}

/// Appends `s`, then spaces up to `width` characters.
fn push_padded(out: &mut String, s: &str, width: usize) {
    out.push_str(s);
    // A text of 4 × width bytes has at least `width` characters.
    let n = if s.len() >= 4 * width {
        width
    } else if s.is_ascii() {
        s.len()
    } else {
        s.chars().count()
    };
    spaces(out, width.saturating_sub(n));
}

/// Powers of ten that are exact doubles, for the decimals [`push_fixed`] writes directly.
const POW10: [u64; 7] = [1, 10, 100, 1_000, 10_000, 100_000, 1_000_000];

/// Appends `v` with `prec` decimals exactly as [`moos_types::fmt::fixed`] writes it (C
/// `%.Nf`: a negative value that rounds to zero keeps its sign): from the rounded integer
/// of `|v| · 10^prec` (its integer part and its decimals written by `itoa`) when that
/// product is below 2^37 and not within 1e-5 of a rounding tie, else through
/// `moos_types::fmt::fixed` itself. Returns the value the text reads back as (`str::parse`,
/// or [`crate::parse_time`]) when it was written from the rounded integer.
///
/// Below 2^37 the product `|v| · 10^prec` is within half an ulp (2^-17 < 7.7e-6) of the
/// exact one, so away from a tie both round to the same integer. The text `[-]int.dec`
/// then stands for the rounded integer over `10^prec`, both exact doubles: their quotient
/// is the correctly rounded value a reader gives the text.
#[inline]
fn push_fixed(out: &mut String, v: f64, prec: usize) -> Option<f64> {
    if let Some(&scale) = POW10.get(prec) {
        let s = v.abs() * scale as f64;
        if s < 137_438_953_472.0 {
            // Truncation is the floor of a non-negative value.
            let fl = s as u64;
            let frac = s - fl as f64;
            if (frac - 0.5).abs() >= 1e-5 {
                let n = fl + u64::from(frac > 0.5);
                let negative = v.is_sign_negative();
                if negative {
                    out.push('-');
                }
                let mut digits = itoa::Buffer::new();
                out.push_str(digits.format(n / scale));
                if prec > 0 {
                    // `scale + decimals` has a leading 1, then the decimals with their
                    // leading zeros.
                    out.push('.');
                    out.push_str(&digits.format(scale + n % scale)[1..]);
                }
                let back = n as f64 / scale as f64;
                return Some(if negative { -back } else { back });
            }
        }
    }
    fixed_general(out, v, prec);
    None
}

/// NaN, infinities, large values, ties and many decimals.
#[cold]
fn fixed_general(out: &mut String, v: f64, prec: usize) {
    fmt_fixed(out, v, prec);
}

/// What [`push_columns`] knows of the line it wrote (see [`Line`]).
struct Formatted {
    /// Where the value's text starts, from the line's start.
    value_at: usize,
    double: Option<f64>,
}

/// Appends one record line (with its newline) to `out` (the writer keeps the time column
/// of the last record: see [`TimeColumn`]).
#[cfg(test)]
fn format_record(
    out: &mut String,
    rel_time: f64,
    var: &str,
    source: &str,
    value: LogValue<'_>,
    precision: usize,
    mark: bool,
) {
    let start = out.len();
    push_time(out, rel_time);
    push_columns(out, start, var, source, value, precision, mark);
}

/// Appends a record's time column: the time relative to LOGSTART, padded to 16 characters
/// with at least one space. Returns the time as it reads back, as [`push_fixed`] does.
fn push_time(out: &mut String, rel_time: f64) -> Option<f64> {
    let start = out.len();
    let time = push_fixed(out, rel_time, 5);
    let n = out.len() - start;
    spaces(out, 16usize.saturating_sub(n).max(1));
    time
}

/// Appends the rest of a record line after its time column (the line starts at `start`):
/// the variable and source columns, the value, the newline.
fn push_columns(
    out: &mut String,
    start: usize,
    var: &str,
    source: &str,
    value: LogValue<'_>,
    precision: usize,
    mark: bool,
) -> Formatted {
    push_names(out, var, source);
    let value_at = out.len() - start;
    let double = push_value(out, value, precision, mark);
    Formatted { value_at, double }
}

/// Appends the variable and source columns, each followed by its space.
fn push_names(out: &mut String, var: &str, source: &str) {
    push_padded(out, var, 20);
    out.push(' ');
    push_padded(out, source, 15);
    out.push(' ');
}

/// Appends a record's value column and the line's end; returns a double value as it reads
/// back, as [`push_fixed`] does.
fn push_value(out: &mut String, value: LogValue<'_>, precision: usize, mark: bool) -> Option<f64> {
    let mut double = None;
    match value {
        LogValue::Double(x) => double = push_double(out, x, precision, mark),
        LogValue::String(s) => {
            if mark {
                out.push_str("S:");
            }
            out.push_str(s);
        }
        LogValue::Binary {
            file,
            offset,
            bytes,
        } => {
            let mut digits = itoa::Buffer::new();
            out.push_str("<MOOS_BINARY>File=");
            out.push_str(file);
            out.push_str(",Offset=");
            out.push_str(digits.format(offset));
            out.push_str(",Bytes=");
            out.push_str(digits.format(bytes));
            out.push_str("</MOOS_BINARY>");
        }
    }
    out.push_str(" \n");
    double
}

/// Appends a double value: its `D:` mark, its digits, then spaces up to 12 digits.
fn push_double(out: &mut String, x: f64, precision: usize, mark: bool) -> Option<f64> {
    if mark {
        out.push_str("D:");
    }
    let start = out.len();
    let back = push_fixed(out, x, precision);
    let n = out.len() - start;
    spaces(out, 12usize.saturating_sub(n));
    back
}

#[cfg(test)]
mod tests {
    use super::*;

    fn header(mark: bool) -> Header<'static> {
        Header {
            path: "./LOG_ALPHA_5_8_2026_____18_22_55/LOG_ALPHA_5_8_2026_____18_22_55.alog",
            opened_on: "Wed Aug  5 18:22:55 2026",
            log_start: 1786054975.123456,
            mark_data_type: mark,
        }
    }

    #[test]
    fn banner_is_byte_exact() {
        let w = AlogWriter::new(Vec::new(), &header(false)).unwrap();
        let text = String::from_utf8(w.into_inner()).unwrap();
        let expected = "\
%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%
%% LOG FILE:       ./LOG_ALPHA_5_8_2026_____18_22_55/LOG_ALPHA_5_8_2026_____18_22_55.alog
%% FILE OPENED ON  Wed Aug  5 18:22:55 2026
%% LOGSTART           1786054975.123456
%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%
";
        assert_eq!(text, expected);
        assert_eq!(BANNER_RULE.len(), 59);
    }

    #[test]
    fn banner_with_type_marking_and_short_start() {
        let mut h = header(true);
        h.log_start = 1000.0;
        h.opened_on = "Thu Jan  1 00:00:00 1970\n";
        let w = AlogWriter::new(Vec::new(), &h).unwrap();
        let text = String::from_utf8(w.into_inner()).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[2], "%% FILE OPENED ON  Thu Jan  1 00:00:00 1970");
        assert_eq!(lines[3], "%% LOGSTART                        1000");
        assert_eq!(lines[4], "%% DATATYPE MARKING ON");
        assert_eq!(lines[5], BANNER_RULE);
        assert_eq!(lines.len(), 6);
    }

    fn one(time: f64, var: &str, src: &str, v: LogValue<'_>, mark: bool) -> String {
        let mut s = String::new();
        format_record(&mut s, time, var, src, v, 5, mark);
        s
    }

    #[test]
    fn double_record_layout() {
        assert_eq!(
            one(
                12.34567,
                "DESIRED_SPEED",
                "pHelmIvP",
                LogValue::Double(1.5),
                false
            ),
            "12.34567        DESIRED_SPEED        pHelmIvP        1.50000      \n"
        );
        assert_eq!(
            one(
                12.34567,
                "NAV_X",
                "uSimMarine",
                LogValue::Double(-23.1),
                false
            ),
            "12.34567        NAV_X                uSimMarine      -23.10000    \n"
        );
    }

    #[test]
    fn string_record_is_raw_and_wide_fields_are_not_truncated() {
        assert_eq!(
            one(
                0.0,
                "IVPHELM_STATE",
                "pHelmIvP",
                LogValue::String("DRIVE"),
                false
            ),
            "0.00000         IVPHELM_STATE        pHelmIvP        DRIVE \n"
        );
        let long_var = "A_VERY_LONG_VARIABLE_NAME_X";
        let long_src = "pSomeVeryLongAppName";
        assert_eq!(
            one(
                123456789.5,
                long_var,
                long_src,
                LogValue::String("a,b = c"),
                false
            ),
            format!("123456789.50000 {long_var} {long_src} a,b = c \n")
        );
        assert_eq!(
            one(1.0, "V", "s", LogValue::String("two\nlines"), false),
            "1.00000         V                    s               two\nlines \n"
        );
    }

    #[test]
    fn marking_binary_and_precision() {
        assert_eq!(
            one(1.0, "X", "a", LogValue::Double(2.0), true),
            "1.00000         X                    a               D:2.00000      \n"
        );
        assert_eq!(
            one(1.0, "X", "a", LogValue::String("hi"), true),
            "1.00000         X                    a               S:hi \n"
        );
        assert_eq!(
            one(
                1.0,
                "IMG",
                "cam",
                LogValue::Binary {
                    file: "LOG.blog",
                    offset: 10,
                    bytes: 3
                },
                false
            ),
            "1.00000         IMG                  cam             <MOOS_BINARY>File=LOG.blog,Offset=10,Bytes=3</MOOS_BINARY> \n"
        );
        let mut w = AlogWriter::new(Vec::new(), &header(false)).unwrap();
        w.set_double_precision(2);
        w.record(1786054976.123456, "X", "a", LogValue::Double(4.56789))
            .unwrap();
        let text = String::from_utf8(w.into_inner()).unwrap();
        assert!(
            text.ends_with("1.00000         X                    a               4.57         \n"),
            "{text}"
        );
    }
    /// The record formatter as it was before it wrote bytes directly (`core::fmt` behind
    /// `moos_types::fmt::fixed`, padding by characters): the oracle of the new one.
    fn old_format_record(
        out: &mut String,
        rel_time: f64,
        var: &str,
        source: &str,
        value: LogValue<'_>,
        precision: usize,
        mark: bool,
    ) {
        fn push_padded(out: &mut String, s: &str, width: usize) {
            out.push_str(s);
            for _ in s.chars().count()..width {
                out.push(' ');
            }
        }
        let start = out.len();
        fmt_fixed(out, rel_time, 5);
        let n = out.len() - start;
        for _ in n..15 {
            out.push(' ');
        }
        out.push(' ');
        push_padded(out, var, 20);
        out.push(' ');
        push_padded(out, source, 15);
        out.push(' ');
        match value {
            LogValue::Double(x) => {
                if mark {
                    out.push_str("D:");
                }
                let start = out.len();
                fmt_fixed(out, x, precision);
                let n = out.len() - start;
                for _ in n..12 {
                    out.push(' ');
                }
            }
            LogValue::String(s) => {
                if mark {
                    out.push_str("S:");
                }
                out.push_str(s);
            }
            LogValue::Binary {
                file,
                offset,
                bytes,
            } => {
                use std::fmt::Write as _;
                let _ = write!(
                    out,
                    "<MOOS_BINARY>File={file},Offset={offset},Bytes={bytes}</MOOS_BINARY>"
                );
            }
        }
        out.push_str(" \n");
    }

    /// Both formatters' lines for one record.
    fn both(
        t: f64,
        var: &str,
        src: &str,
        v: LogValue<'_>,
        prec: usize,
        mark: bool,
    ) -> (String, String) {
        let mut new = String::new();
        format_record(&mut new, t, var, src, v, prec, mark);
        let mut old = String::new();
        old_format_record(&mut old, t, var, src, v, prec, mark);
        (new, old)
    }

    #[test]
    fn awkward_times_and_values_are_written_as_before() {
        let mut cases = vec![
            0.0,
            -0.0,
            1e-300,
            -1e-300,
            0.000005,
            -0.000005,
            0.000015,
            0.015625,
            2.5e-6,
            1.000005,
            12.345675,
            0.1 + 0.2,
            10737.41824,
            10737.418245,
            1_374_389.534_72,
            1_374_389.534_725,
            999_999.999_995,
            1e6,
            1e6 + 0.000005,
            4503599627370496.5,
            1786054975.123456,
            -1786054975.123455,
            1e300,
            f64::MAX,
            f64::MIN_POSITIVE,
            f64::NAN,
            -f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        // x.0005-style ties at every power of ten, and their neighbours.
        for e in -7..=12 {
            let base = 10f64.powi(e);
            for k in [1.0, 5.0, 0.5, 1.5, 2.5] {
                let x = k * base;
                cases.extend([x, -x, x.next_up(), x.next_down()]);
            }
        }
        for t in &cases {
            for prec in [0, 1, 2, 3, 5, 6, 7, 9] {
                for mark in [false, true] {
                    let (new, old) = both(*t, "V", "src", LogValue::Double(*t), prec, mark);
                    assert_eq!(new, old, "time and value {t:e}, precision {prec}");
                }
            }
        }
    }

    #[test]
    fn names_wider_than_or_outside_ascii_are_padded_by_characters_as_before() {
        for name in [
            "",
            "X",
            "NAV_X",
            "EXACTLY_TWENTY_CHARS",
            "NINETEEN_CHARACTERS",
            "TWENTY_ONE_CHARACTER",
            "DÉPTH",
            "ÉÉÉÉÉÉÉÉÉÉÉÉÉÉÉÉÉÉÉÉÉ",
            "ÉÉÉÉÉÉÉÉÉÉÉÉÉÉÉÉÉÉÉ",
            "日本語のとても長い変数の名前です",
            "🚀🚀🚀🚀🚀🚀🚀🚀🚀🚀🚀🚀🚀🚀🚀🚀🚀🚀🚀🚀🚀🚀",
        ] {
            for v in [
                LogValue::Double(1.0),
                LogValue::String(name),
                LogValue::Binary {
                    file: name,
                    offset: u64::MAX,
                    bytes: 0,
                },
            ] {
                let (new, old) = both(3.0, name, name, v, 5, false);
                assert_eq!(new, old, "{name:?}");
            }
        }
    }

    #[test]
    fn buffered_lines_reach_the_writer_on_flush_when_full_and_when_dropped() {
        let mut w = AlogWriter::headless(Vec::new(), 10.0, false);
        w.record(11.0, "A", "s", LogValue::Double(1.0)).unwrap();
        assert!(w.get_ref().is_empty(), "held until flushed");
        w.flush().unwrap();
        let line = "1.00000         A                    s               1.00000      \n";
        assert_eq!(w.get_ref(), line.as_bytes());
        let mut n = 1;
        while w.get_ref().len() == line.len() {
            w.record(11.0, "A", "s", LogValue::Double(1.0)).unwrap();
            n += 1;
        }
        assert_eq!(
            w.get_ref().len(),
            n * line.len(),
            "a full buffer goes out whole"
        );
        assert!(w.get_ref().len() >= AlogWriter::<Vec<u8>>::CHUNK);
        w.record(12.0, "B", "s", LogValue::String("x")).unwrap();
        let before = w.get_ref().len();
        w.pass_on().unwrap();
        assert_eq!(w.get_ref().len() - before, 56, "passed on, not held");
        let mut out = Vec::new();
        {
            let mut w2 = AlogWriter::headless(&mut out, 0.0, false);
            w2.record(1.0, "C", "s", LogValue::String("y")).unwrap();
        }
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "1.00000         C                    s               y \n"
        );
        let all = String::from_utf8(w.into_inner()).unwrap();
        assert!(all.ends_with("2.00000         B                    s               x \n"));
    }

    proptest::proptest! {
        #![proptest_config(proptest::prelude::ProptestConfig::with_cases(4000))]

        #[test]
        fn the_line_is_the_old_formatter_s(
            t in 0.0f64..1e6,
            ms in 0u64..1_000_000_000,
            half in proptest::bool::ANY,
            v in proptest::num::f64::ANY,
            small in -1e4f64..1e4,
            prec in 0usize..8,
            mark in proptest::bool::ANY,
            var in "[A-Z_]{0,24}",
            src in "[a-zA-Zé]{0,18}",
            text in "\\PC{0,30}",
        ) {
            // A plain time, a time on the millisecond grid, and one on a half-way point
            // of the fifth decimal (x.xxxxx5).
            let grid = ms as f64 / 1000.0;
            let tie = (ms as f64 * 100.0 + if half { 0.5 } else { 0.0 }) / 100_000.0;
            // The writer keeps the time column of the record before: the same lines.
            let mut w = AlogWriter::headless(Vec::new(), 0.0, mark);
            w.set_double_precision(prec);
            let mut lines = String::new();
            // And through a variable's cache: each record twice, then from another source.
            let mut cached = AlogWriter::headless(Vec::new(), 0.0, mark);
            cached.set_double_precision(prec);
            let mut cache = RecordCache::new(&var);
            proptest::prop_assert_eq!(cache.var(), &var);
            let mut cached_lines = String::new();
            for time in [t, grid, tie, -grid] {
                for value in [
                    LogValue::Double(v),
                    LogValue::Double(small),
                    LogValue::Double(tie),
                    LogValue::String(&text),
                ] {
                    let (new, old) = both(time, &var, &src, value, prec, mark);
                    proptest::prop_assert_eq!(&new, &old);
                    lines.push_str(&old);
                    w.record(time, &var, &src, value).unwrap();
                    for from in [src.as_str(), &src, "é"] {
                        let mut seen = None;
                        cached
                            .record_cached(time, &mut cache, from, value, |l| {
                                seen = Some((l.text.to_string(), l.value.to_string()));
                            })
                            .unwrap();
                        let (_, old) = both(time, &var, from, value, prec, mark);
                        let (text, shown) = seen.expect("the line is shown");
                        proptest::prop_assert_eq!(&text, &old);
                        proptest::prop_assert!(old[..old.len() - 2].ends_with(&shown));
                        cached_lines.push_str(&old);
                    }
                }
            }
            proptest::prop_assert_eq!(String::from_utf8(w.into_inner()).unwrap(), lines);
            proptest::prop_assert_eq!(String::from_utf8(cached.into_inner()).unwrap(), cached_lines);
        }
    }
}
