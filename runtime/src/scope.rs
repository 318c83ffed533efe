//! What `coug scope` (uXMS) shows: the latest value of each scoped variable with its source,
//! time and community, as uXMS at MOOS-IvP a2a9b716 keeps them. Pure: mail in, text out.
//!
//! - Times are seconds since the MOOSDB started: the DB's start is taken once from the first
//!   `DB_UPTIME` (its value subtracted from the time it was received), as uXMS does.
//! - A variable with `*` or `?` is a MOOS wildcard: every variable it matches is shown.
//! - `all` shows every variable except `*_STATUS`, `APPCAST`, `DB_RWSUMMARY` and
//!   `DB_VARSUMMARY` (uXMS `--all`); `really_all` shows those too (`--alll`).

use std::collections::BTreeMap;
use std::fmt::Write as _;

use moosdb::db::wildcard_match;
use moosdb::{DataType, Message};

/// The columns shown besides the name and value (uXMS `--show=source,time,community`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Columns {
    /// `(S)ource`: the app that posted.
    pub source: bool,
    /// `(T)ime`: seconds since the DB started.
    pub time: bool,
    /// `(C)ommunity`: the community it came from.
    pub community: bool,
}

impl Default for Columns {
    fn default() -> Self {
        Columns {
            source: true,
            time: true,
            community: true,
        }
    }
}

/// The latest value of one variable.
#[derive(Debug, Clone, PartialEq)]
struct Entry {
    value: String,
    source: String,
    time: Option<f64>,
    community: String,
}

/// The scope's state.
#[derive(Debug, Clone, Default)]
pub struct Scope {
    names: Vec<String>,
    patterns: Vec<String>,
    all: bool,
    really_all: bool,
    db_start: Option<f64>,
    entries: BTreeMap<String, Entry>,
}

/// Whether a name is a MOOS wildcard pattern.
pub fn is_pattern(name: &str) -> bool {
    name.contains(['*', '?'])
}

impl Scope {
    /// A scope of `vars` (names or wildcard patterns); `all`/`really_all` as uXMS `--all` /
    /// `--alll`.
    pub fn new(vars: &[String], all: bool, really_all: bool) -> Scope {
        let mut s = Scope {
            all: all || really_all,
            really_all,
            ..Scope::default()
        };
        for v in vars {
            if is_pattern(v) {
                s.patterns.push(v.clone());
            } else if !s.names.contains(v) {
                s.names.push(v.clone());
            }
        }
        s
    }

    /// Whether `key` is shown.
    fn wanted(&self, key: &str) -> bool {
        if self.names.iter().any(|n| n == key)
            || self
                .patterns
                .iter()
                .any(|p| wildcard_match(p.as_bytes(), key.as_bytes()))
        {
            return true;
        }
        if self.really_all {
            return true;
        }
        self.all
            && !key.ends_with("_STATUS")
            && !matches!(key, "APPCAST" | "DB_RWSUMMARY" | "DB_VARSUMMARY")
    }

    /// Takes one message received at MOOS time `now`.
    pub fn on_message(&mut self, m: &Message, now: f64) {
        let key = m.key_str();
        if self.db_start.is_none() && key == "DB_UPTIME" {
            self.db_start = Some(now - m.dval);
        }
        if !self.wanted(&key) {
            return;
        }
        let value = match m.data_type {
            DataType::Double => moosdb::db::fmt_g6(m.dval),
            DataType::String => format!("\"{}\"", m.sval_str()),
            DataType::Binary => format!("<binary {} bytes>", m.sval.len()),
            DataType::NotSet => "n/a".into(),
        };
        self.entries.insert(
            key.into_owned(),
            Entry {
                value,
                source: m.src_str().into_owned(),
                time: Some(m.time),
                community: String::from_utf8_lossy(&m.community).into_owned(),
            },
        );
    }

    /// True once the DB's start is known (its first `DB_UPTIME`).
    pub fn db_started(&self) -> bool {
        self.db_start.is_some()
    }

    /// True once the DB's start is known and every named variable has a value (patterns and
    /// `all` never complete).
    pub fn complete(&self) -> bool {
        self.db_start.is_some() && self.names.iter().all(|n| self.entries.contains_key(n))
    }

    /// The table: the named variables (in order, `n/a` until written), then every other
    /// variable shown, by name.
    pub fn render(&self, cols: Columns) -> String {
        let mut rows: Vec<(String, Option<&Entry>)> = self
            .names
            .iter()
            .map(|n| (n.clone(), self.entries.get(n)))
            .collect();
        for (k, e) in &self.entries {
            if !self.names.contains(k) {
                rows.push((k.clone(), Some(e)));
            }
        }
        let width = rows.iter().map(|(k, _)| k.len()).max().unwrap_or(0).max(7);
        let mut out = String::new();
        let head =
            |s: &str, short: &str, on: bool| if on { s.to_string() } else { short.to_string() };
        let _ = writeln!(
            out,
            "{:<width$}  {:<16}  {:>9}  {:<12}  VarValue",
            "VarName",
            head("(S)ource", "(S)", cols.source),
            head("(T)ime", "(T)", cols.time),
            head("(C)ommunity", "(C)", cols.community),
        );
        let _ = writeln!(
            out,
            "{:<width$}  {:<16}  {:>9}  {:<12}  --------",
            "-------", "--------", "------", "-----------"
        );
        for (k, e) in rows {
            let (src, time, comm, val) = match e {
                Some(e) => {
                    let t = match (e.time, self.db_start) {
                        (Some(t), Some(s)) => format!("{:.2}", t - s),
                        _ => "n/a".into(),
                    };
                    (e.source.as_str(), t, e.community.as_str(), e.value.as_str())
                }
                None => ("n/a", "n/a".to_string(), "n/a", "n/a"),
            };
            let _ = writeln!(
                out,
                "{k:<width$}  {:<16}  {:>9}  {:<12}  {val}",
                if cols.source { src } else { "" },
                if cols.time { time.as_str() } else { "" },
                if cols.community { comm } else { "" },
            );
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use moosdb::Value;

    fn msg(key: &str, v: Value, time: f64, src: &str) -> Message {
        let mut m = Message::notify(key, v, time);
        m.src = src.as_bytes().to_vec().into();
        m.community = b"abe".to_vec().into();
        m
    }

    #[test]
    fn times_from_the_db_start_wildcards_and_all() {
        let mut s = Scope::new(&["NAV_*".into(), "DEPLOY".into()], false, false);
        // The DB has been up 50 s when its DB_UPTIME arrives at 1050: it started at 1000.
        s.on_message(
            &msg("DB_UPTIME", Value::Double(50.0), 1050.0, "MOOSDB_abe"),
            1050.0,
        );
        s.on_message(
            &msg("NAV_X", Value::Double(1.5), 1010.25, "uSimMarineV22"),
            1051.0,
        );
        s.on_message(
            &msg("NAV_Y", Value::Double(-2.0), 1010.25, "uSimMarineV22"),
            1051.0,
        );
        s.on_message(&msg("FOO", Value::Double(1.0), 1011.0, "uPokeDB"), 1051.0);
        assert!(!s.complete());
        let t = s.render(Columns::default());
        let lines: Vec<&str> = t.lines().collect();
        assert_eq!(lines.len(), 5, "{t}");
        assert!(lines[0].starts_with("VarName") && lines[0].contains("(C)ommunity"));
        assert!(lines[2].starts_with("DEPLOY") && lines[2].ends_with("n/a"));
        assert!(
            lines[3].starts_with("NAV_X")
                && lines[3].contains(" 10.25 ")
                && lines[3].contains("abe"),
            "{}",
            lines[3]
        );
        assert!(!t.contains("FOO"));
        let mut all = Scope::new(&[], true, false);
        for (k, v) in [
            ("FOO", 1.0),
            ("PHELMIVP_STATUS", 1.0),
            ("DB_VARSUMMARY", 1.0),
            ("DB_UPTIME", 5.0),
        ] {
            all.on_message(&msg(k, Value::Double(v), 10.0, "x"), 10.0);
        }
        let t = all.render(Columns::default());
        assert!(t.contains("FOO") && t.contains("DB_UPTIME"), "{t}");
        assert!(
            !t.contains("_STATUS") && !t.contains("DB_VARSUMMARY"),
            "{t}"
        );
        let mut really = Scope::new(&[], false, true);
        really.on_message(&msg("PHELMIVP_STATUS", Value::Double(1.0), 10.0, "x"), 10.0);
        assert!(
            really
                .render(Columns::default())
                .contains("PHELMIVP_STATUS")
        );
    }
}
