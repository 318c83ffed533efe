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
    use moos_types::text::is_number;
    let (t, rest) = token(line)?;
    if !is_number(t) {
        return None;
    }
    let time = t.parse::<f64>().ok()?;
    let (var, rest) = token(rest)?;
    let (source, rest) = token(rest)?;
    let raw = rest.trim();
    let value = if marked {
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
    };
    Some(Entry {
        time,
        var: var.to_string(),
        source: source.to_string(),
        value,
    })
}

/// The first white-space separated token and the text after it.
fn token(s: &str) -> Option<(&str, &str)> {
    let s = s.trim_start();
    if s.is_empty() {
        return None;
    }
    let end = s.find([' ', '\t']).unwrap_or(s.len());
    Some((&s[..end], &s[end..]))
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
}
