//! Reading alog files (coug's or MOOS-IvP's pLogger output).

use thiserror::Error;

/// A value read from an alog record: a double (`D:`-marked, or unmarked text that is a
/// number) or a string (as written, trimmed at both ends, as MOOS-IvP's alog tools do);
/// the workspace's one MOOS value type.
pub use moos_types::Value;

/// One record: `(time, var, source, value)`; `time` is relative to LOGSTART as written.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// Seconds since LOGSTART.
    pub time: f64,
    /// Variable name.
    pub var: String,
    /// Publishing app (with any `:aux` / `@community` suffix pLogger added).
    pub source: String,
    /// The value.
    pub value: Value,
}

/// A parsed alog file.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Alog {
    /// The `LOG FILE:` path of the banner.
    pub log_file: Option<String>,
    /// The `FILE OPENED ON` text.
    pub opened_on: Option<String>,
    /// LOGSTART (absolute MOOS time of record time 0).
    pub log_start: Option<f64>,
    /// True when the banner says `DATATYPE MARKING ON`.
    pub data_type_marking: bool,
    /// The records in file order.
    pub entries: Vec<Entry>,
}

/// A file that is not an alog.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum AlogError {
    /// A line before the first record that is neither a `%%` banner line nor a record.
    #[error("line {line}: not an alog record: {text:?}")]
    NotARecord {
        /// 1-based line number.
        line: usize,
        /// The line (up to 80 characters).
        text: String,
    },
    /// The LOGSTART line does not hold a number.
    #[error("line {line}: LOGSTART is not a number: {text:?}")]
    BadLogStart {
        /// 1-based line number.
        line: usize,
        /// The text after `LOGSTART`.
        text: String,
    },
}

/// Parses a whole alog text.
///
/// Banner lines start with `%%`. A record line is `TIME VAR SOURCE VALUE`, fields
/// separated by white space, the value being the rest of the line. Since pLogger writes
/// string values raw, a line that is not a record after the first record continues the
/// previous record's string value (joined with `\n`).
///
/// ```
/// let log = alog::parse("%% LOGSTART 100.5\n1.25000 DEPLOY pMarineViewer true \n").unwrap();
/// assert_eq!(log.log_start, Some(100.5));
/// assert_eq!(log.entries[0].value.as_str(), Some("true"));
/// ```
pub fn parse(text: &str) -> Result<Alog, AlogError> {
    let mut log = Alog::default();
    for (i, raw) in text.lines().enumerate() {
        let line_no = i + 1;
        let line = raw.strip_suffix('\r').unwrap_or(raw);
        if let Some(rest) = line.strip_prefix("%%")
            && log.entries.is_empty()
        {
            banner_line(&mut log, rest.trim(), line_no)?;
            continue;
        }
        if line.trim().is_empty() && log.entries.is_empty() {
            continue;
        }
        match parse_line_marked(line, log.data_type_marking) {
            Some(e) => log.entries.push(e),
            None => match log.entries.last_mut() {
                Some(Entry {
                    value: Value::String(s),
                    ..
                }) => {
                    // A value continued on the next line (rare): joined into a new text.
                    *s = format!("{s}\n{}", line.trim_end()).into();
                }
                _ => {
                    return Err(AlogError::NotARecord {
                        line: line_no,
                        text: line.chars().take(80).collect(),
                    });
                }
            },
        }
    }
    Ok(log)
}

fn banner_line(log: &mut Alog, rest: &str, line: usize) -> Result<(), AlogError> {
    if let Some(v) = rest.strip_prefix("LOG FILE:") {
        log.log_file = Some(v.trim().to_string());
    } else if let Some(v) = rest.strip_prefix("FILE OPENED ON") {
        log.opened_on = Some(v.trim().to_string());
    } else if let Some(v) = rest.strip_prefix("LOGSTART") {
        let v = v.trim();
        let t = v.parse::<f64>().map_err(|_| AlogError::BadLogStart {
            line,
            text: v.to_string(),
        })?;
        log.log_start = Some(t);
    } else if rest == "DATATYPE MARKING ON" {
        log.data_type_marking = true;
    }
    Ok(())
}

/// Parses one record line (no type marking): `None` if it is not a record.
///
/// ```
/// let e = alog::parse_line("12.34567        NAV_X                uSimMarine      -23.10000    ").unwrap();
/// assert_eq!((e.time, e.var.as_str(), e.source.as_str()), (12.34567, "NAV_X", "uSimMarine"));
/// assert_eq!(e.value.as_f64(), Some(-23.1));
/// ```
pub fn parse_line(line: &str) -> Option<Entry> {
    parse_line_marked(line, false)
}

fn parse_line_marked(line: &str, marked: bool) -> Option<Entry> {
    let (t, rest) = field(line)?;
    let time = parse_time(t)?;
    let (var, rest) = field(rest)?;
    let (source, rest) = field(rest)?;
    Some(Entry {
        time,
        var: var.to_string(),
        source: source.to_string(),
        value: parse_value(rest.trim(), marked),
    })
}

/// A record's value from its text (after the source, trimmed): with type marking a `D:`
/// text is a double (a string if it does not parse) and an `S:` one a string; without, a
/// text MOOS reads as a number (`isNumber`: no exponent) is a double.
///
/// ```
/// use alog::{Value, parse_value};
/// assert_eq!(parse_value("-2.5", false), Value::Double(-2.5));
/// assert_eq!(parse_value("1e5", false), Value::String("1e5".into()));
/// assert_eq!(parse_value("S:42", true), Value::String("42".into()));
/// ```
pub fn parse_value(raw: &str, marked: bool) -> Value {
    if let Some(x) = parse_double(raw, marked) {
        return Value::Double(x);
    }
    let text = if marked {
        raw.strip_prefix("D:")
            .or_else(|| raw.strip_prefix("S:"))
            .unwrap_or(raw)
    } else {
        raw
    };
    Value::text(text)
}

/// The double a record's value text (after the source, trimmed) reads back as, `None` when
/// it reads back as a string: [`parse_value`] without building the string.
///
/// ```
/// assert_eq!(alog::parse_double("-2.5", false), Some(-2.5));
/// assert_eq!(alog::parse_double("D: 4", true), Some(4.0));
/// assert_eq!(alog::parse_double("S:42", true), None);
/// assert_eq!(alog::parse_double("1e5", false), None);
/// ```
pub fn parse_double(raw: &str, marked: bool) -> Option<f64> {
    use moos_types::text::is_number;
    let number = if marked {
        raw.strip_prefix("D:")?.trim()
    } else if is_number(raw) {
        raw
    } else {
        return None;
    };
    number.parse::<f64>().ok()
}

/// The first white-space separated field of a record line and the text after it: white
/// space (`char::is_whitespace`) skipped, then up to a space or a tab; `None` when only
/// white space is left. Fast on the ASCII lines pLogger writes (padding skipped eight
/// spaces at a time, the field's end found by `memchr`).
///
/// ```
/// assert_eq!(alog::field("  12.5  NAV_X s 3"), Some(("12.5", "  NAV_X s 3")));
/// assert_eq!(alog::field(" \t "), None);
/// ```
pub fn field(s: &str) -> Option<(&str, &str)> {
    let b = s.as_bytes();
    let mut i = 0;
    while b.len() - i >= 8 && b[i..i + 8] == *b"        " {
        i += 8;
    }
    // The ASCII characters `char::is_whitespace` holds: tab, LF, VT, FF, CR and space.
    while i < b.len() && matches!(b[i], b'\t' | b'\n' | 0x0b | 0x0c | b'\r' | b' ') {
        i += 1;
    }
    if i == b.len() {
        return None;
    }
    let s = if b[i] >= 0x80 {
        // A character beyond ASCII may be white space too.
        let s = s[i..].trim_start();
        if s.is_empty() {
            return None;
        }
        s
    } else {
        &s[i..]
    };
    let end = memchr::memchr2(b' ', b'\t', s.as_bytes()).unwrap_or(s.len());
    Some((&s[..end], &s[end..]))
}

/// Powers of ten that are exact doubles.
const POW10: [f64; 16] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
];

/// A record's time field: a number as MOOS reads one (`isNumber`), then its value as
/// `str::parse` gives it. `[-]digits[.digits]` of at most 15 digits is read directly (the
/// integer of its digits and the power of ten are exact doubles, so their quotient is the
/// correctly rounded value `str::parse` gives); anything else takes the two steps.
///
/// ```
/// assert_eq!(alog::parse_time("12.34567"), Some(12.34567));
/// assert_eq!(alog::parse_time("1e3"), None);
/// ```
pub fn parse_time(t: &str) -> Option<f64> {
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
                    return parse_time_slow(t);
                }
                m = m * 10 + u64::from(c - b'0');
                if let Some(d) = decimals.as_mut() {
                    *d += 1;
                }
            }
            b'.' if decimals.is_none() => decimals = Some(0),
            _ => return parse_time_slow(t),
        }
    }
    if n == 0 {
        return parse_time_slow(t);
    }
    let v = m as f64 / POW10[decimals.unwrap_or(0)];
    Some(if negative { -v } else { v })
}

fn parse_time_slow(t: &str) -> Option<f64> {
    if !moos_types::text::is_number(t) {
        return None;
    }
    t.parse::<f64>().ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unmarked_values_are_doubles_when_moos_reads_them_as_numbers() {
        let v = |raw: &str| parse_line(&format!("1.0 X src {raw}")).unwrap().value;
        assert_eq!(v("-2.5"), Value::Double(-2.5));
        assert_eq!(v("+3."), Value::Double(3.0));
        // MOOS `isNumber` has no exponent.
        assert_eq!(v("1e5"), Value::String("1e5".into()));
        assert_eq!(v("true"), Value::String("true".into()));
        assert!(
            parse_line("1e3 X src 1").is_none(),
            "a time must be a number"
        );
    }
    #[test]
    fn parse_double_is_parse_value_s_double() {
        for raw in [
            "", "1", "-2.5", "+3.", "1e5", "D:", "D:4", "D: 4 ", "D:x", "S:4", "S:", "4 ", "nan",
            "D:nan", "inf", "-", ".", "x", "é", "D:1e5",
        ] {
            for marked in [false, true] {
                let want = match parse_value(raw, marked) {
                    Value::Double(x) => Some(x.to_bits()),
                    _ => None,
                };
                let got = parse_double(raw, marked).map(f64::to_bits);
                assert_eq!(got, want, "{raw:?} {marked}");
            }
        }
        assert_eq!(parse_value("D:x", true), Value::String("x".into()));
        assert_eq!(parse_value("S:D:1", true), Value::String("D:1".into()));
    }

    #[test]
    fn times_are_the_numbers_moos_reads() {
        use moos_types::text::is_number;
        let two_steps = |t: &str| is_number(t).then(|| t.parse::<f64>().ok()).flatten();
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
            let (got, want) = (parse_time(t), two_steps(t));
            assert_eq!(got.map(f64::to_bits), want.map(f64::to_bits), "{t:?}");
        }
        // Every time pLogger writes over a day, to the bit.
        let mut s = String::new();
        for k in 0..200_000u32 {
            let x = f64::from(k) * 0.43201 + 0.000_01 * f64::from(k % 7);
            s.clear();
            moos_types::fmt::fixed(&mut s, x, 5);
            assert_eq!(
                parse_time(&s).map(f64::to_bits),
                two_steps(&s).map(f64::to_bits),
                "{s}"
            );
        }
    }

    #[test]
    fn fields_split_as_trim_start_and_find_split_them() {
        fn plain(s: &str) -> Option<(&str, &str)> {
            let s = s.trim_start();
            if s.is_empty() {
                return None;
            }
            let end = s.find([' ', '\t']).unwrap_or(s.len());
            Some((&s[..end], &s[end..]))
        }
        for line in [
            "  1.0 \tNAV_X   src   3 ",
            "\u{a0}1.0 NAV_X s 3",
            "1.0\u{2003}NAV_X s 3",
            "\x0b\x0c1 A\tB",
            "                 NAV_X                uSimMarine      -23.10000    ",
            "        ",
            "                \t",
            "        \u{2003}x",
            "   ",
            "",
            "\u{85}",
        ] {
            assert_eq!(field(line), plain(line), "{line:?}");
        }
    }
}
