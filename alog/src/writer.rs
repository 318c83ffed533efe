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

/// Writes an alog file: the banner on creation, then one line per [`AlogWriter::record`].
///
/// Records are written in the order given; pLogger sorts each batch of mail by time first
/// (callers do the same).
#[derive(Debug)]
pub struct AlogWriter<W: Write> {
    out: W,
    log_start: f64,
    precision: usize,
    mark_data_type: bool,
    line: String,
}

impl<W: Write> AlogWriter<W> {
    /// Writes the banner to `out` and returns the writer (DoublePrecision 5).
    pub fn new(out: W, header: &Header<'_>) -> io::Result<Self> {
        let mut w = AlogWriter {
            out,
            log_start: header.log_start,
            precision: 5,
            mark_data_type: header.mark_data_type,
            line: String::with_capacity(256),
        };
        let mut banner = String::with_capacity(256);
        write_banner(&mut banner, header);
        w.out.write_all(banner.as_bytes())?;
        Ok(w)
    }

    /// A writer without a banner (pLogger's `.xlog` of excluded variables has none): records
    /// relative to `log_start`, DoublePrecision 5.
    pub fn headless(out: W, log_start: f64, mark_data_type: bool) -> Self {
        AlogWriter {
            out,
            log_start,
            precision: 5,
            mark_data_type,
            line: String::with_capacity(256),
        }
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
    pub fn record(
        &mut self,
        time: f64,
        var: &str,
        source: &str,
        value: LogValue<'_>,
    ) -> io::Result<()> {
        self.line.clear();
        format_record(
            &mut self.line,
            time - self.log_start,
            var,
            source,
            value,
            self.precision,
            self.mark_data_type,
        );
        self.out.write_all(self.line.as_bytes())
    }

    /// Flushes the underlying writer.
    pub fn flush(&mut self) -> io::Result<()> {
        self.out.flush()
    }

    /// The underlying writer.
    pub fn get_ref(&self) -> &W {
        &self.out
    }

    /// Gives back the underlying writer.
    pub fn into_inner(self) -> W {
        self.out
    }
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

fn push_padded(out: &mut String, s: &str, width: usize) {
    out.push_str(s);
    for _ in s.chars().count()..width {
        out.push(' ');
    }
}

/// Appends one record line (with its newline) to `out`.
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
}
