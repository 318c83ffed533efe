//! [`AppCast`]: one app's report, its `APPCAST` string ([`AppCast::to_moos_string`]) and the
//! parser viewers use on it ([`AppCast::parse`]), after libMOOS's `AppCast` class and
//! `string2AppCast`.

use std::collections::{BTreeMap, VecDeque};
use std::fmt::Write as _;

use moos_types::text::{atoi, chomp, trim};

/// Separator between the `param=value` fields of an `APPCAST` string.
pub const OUTER_SEPARATOR: &str = "!@#";
/// Separator between the items (lines, warnings, events) inside one field.
pub const INNER_SEPARATOR: &str = "!@";
/// The run warning under which warnings are counted once the verbatim list is full.
pub const OTHER_RUN_WARNINGS: &str = "Other Run Warnings";

/// Default cap on the events kept (the oldest is dropped beyond it).
pub const DEFAULT_MAX_EVENTS: usize = 8;
/// Default cap on the distinct run warnings kept verbatim.
pub const DEFAULT_MAX_RUN_WARNINGS: usize = 10;
/// Cap used by the C++ for configuration warnings: a new one is refused once the list holds
/// *more* than this many, so at most 101 are ever kept.
pub const MAX_CONFIG_WARNINGS: usize = 100;
/// The caps a parsed appcast gets (`string2AppCast` rebuilds what it is given, up to this).
pub const PARSED_MAX: usize = 1000;

/// One application's appcast: identity, iteration, the free-form report body, and the three
/// warning/event lists with their caps.
///
/// The run warnings are kept in a map ordered by text (byte order, as `std::map<std::string>`),
/// each with its repeat count, plus a separate running total that keeps counting when the map is
/// full.
#[derive(Debug, Clone, PartialEq)]
pub struct AppCast {
    proc_name: String,
    node_name: String,
    iteration: u32,
    messages: String,
    config_warnings: Vec<String>,
    events: VecDeque<String>,
    run_warnings: BTreeMap<String, u32>,
    run_warning_total: u32,
    max_events: usize,
    max_run_warnings: usize,
}

impl Default for AppCast {
    fn default() -> Self {
        Self::new()
    }
}

impl AppCast {
    /// An empty appcast with the C++ defaults: iteration 0, at most 8 events, 10 distinct run
    /// warnings.
    pub fn new() -> Self {
        Self {
            proc_name: String::new(),
            node_name: String::new(),
            iteration: 0,
            messages: String::new(),
            config_warnings: Vec::new(),
            events: VecDeque::new(),
            run_warnings: BTreeMap::new(),
            run_warning_total: 0,
            max_events: DEFAULT_MAX_EVENTS,
            max_run_warnings: DEFAULT_MAX_RUN_WARNINGS,
        }
    }

    /// Sets the application name (`proc=`).
    pub fn set_proc_name(&mut self, name: &str) {
        self.proc_name = name.to_string();
    }

    /// The application name.
    pub fn proc_name(&self) -> &str {
        &self.proc_name
    }

    /// Sets the node (community) name (`node=`); empty means the field is left out.
    pub fn set_node_name(&mut self, name: &str) {
        self.node_name = name.to_string();
    }

    /// The node (community) name.
    pub fn node_name(&self) -> &str {
        &self.node_name
    }

    /// Sets the iteration number (`iter=`).
    pub fn set_iteration(&mut self, iteration: u32) {
        self.iteration = iteration;
    }

    /// The iteration number.
    pub fn iteration(&self) -> u32 {
        self.iteration
    }

    /// Replaces the report body (`msg()` in C++): free text, lines separated by `\n`.
    pub fn set_messages(&mut self, text: &str) {
        self.messages = text.to_string();
    }

    /// The report body.
    pub fn messages(&self) -> &str {
        &self.messages
    }

    /// Sets the cap on kept events. Lowering it does not drop events at once: each later event
    /// drops only the oldest one, as in C++.
    pub fn set_max_events(&mut self, max: usize) {
        self.max_events = max;
    }

    /// The cap on kept events.
    pub fn max_events(&self) -> usize {
        self.max_events
    }

    /// Sets the cap on distinct run warnings kept verbatim.
    pub fn set_max_run_warnings(&mut self, max: usize) {
        self.max_run_warnings = max;
    }

    /// The cap on distinct run warnings kept verbatim.
    pub fn max_run_warnings(&self) -> usize {
        self.max_run_warnings
    }

    /// Adds an event. With a timestamp `t >= 0` the text becomes `[<t, 2 decimals>]: text`;
    /// `None`, a negative time or NaN keeps the text as is (the C++ default argument is −1).
    /// Beyond the cap the oldest event is dropped (one per call).
    pub fn event(&mut self, text: &str, timestamp: Option<f64>) {
        let entry = match timestamp {
            Some(t) if t >= 0.0 => format!("[{t:.2}]: {text}"),
            _ => text.to_string(),
        };
        self.events.push_back(entry);
        if self.events.len() > self.max_events {
            self.events.pop_front();
        }
    }

    /// The kept events, oldest first.
    pub fn events(&self) -> impl ExactSizeIterator<Item = &str> {
        self.events.iter().map(String::as_str)
    }

    /// `events_total=`: the number of events kept (not the number ever reported).
    pub fn events_total(&self) -> usize {
        self.events.len()
    }

    /// Adds a configuration warning, unless more than [`MAX_CONFIG_WARNINGS`] are held already.
    /// An empty text is accepted here (the app-level filter is in
    /// [`AppCasting::report_config_warning`](crate::AppCasting::report_config_warning)).
    pub fn cfg_warning(&mut self, text: &str) {
        if self.config_warnings.len() > MAX_CONFIG_WARNINGS {
            return;
        }
        self.config_warnings.push(text.to_string());
    }

    /// The configuration warnings, in the order reported.
    pub fn config_warnings(&self) -> &[String] {
        &self.config_warnings
    }

    /// Counts a run warning. While fewer than the cap distinct texts are held, the text's own
    /// count grows (a new text is added); once the map holds the cap, *every* warning, even a
    /// repeat of a held text, is counted under [`OTHER_RUN_WARNINGS`] (which may thus make the
    /// map one longer than the cap). The total grows in every case.
    pub fn run_warning(&mut self, text: &str) {
        let key = if self.run_warnings.len() < self.max_run_warnings {
            text
        } else {
            OTHER_RUN_WARNINGS
        };
        let count = self.run_warnings.entry(key.to_string()).or_insert(0);
        *count = count.wrapping_add(1);
        self.run_warning_total = self.run_warning_total.wrapping_add(1);
    }

    /// Removes a held run warning (exact text) and takes its count off the total (not below 0).
    /// Returns whether the text was held.
    pub fn retract_run_warning(&mut self, text: &str) -> bool {
        match self.run_warnings.remove(text) {
            Some(count) => {
                self.run_warning_total = self.run_warning_total.saturating_sub(count);
                true
            }
            None => false,
        }
    }

    /// The held run warnings with their counts, in text (byte) order.
    pub fn run_warnings(&self) -> &BTreeMap<String, u32> {
        &self.run_warnings
    }

    /// `run_warning_total=`: all run warnings counted (minus retracted ones), including those
    /// beyond the verbatim list (`getRunWarningCount()` in C++).
    pub fn run_warning_total(&self) -> u32 {
        self.run_warning_total
    }

    /// Sets a run warning's count outright (`setRunWarnings`, used when rebuilding from a
    /// string); ignored once the map holds the cap, even for a text already held.
    pub fn set_run_warning(&mut self, text: &str, count: u32) {
        if self.run_warnings.len() < self.max_run_warnings {
            self.run_warnings.insert(text.to_string(), count);
        }
    }

    /// Sets the run warning total outright (used when rebuilding from a string).
    pub fn set_run_warning_total(&mut self, total: u32) {
        self.run_warning_total = total;
    }

    /// The `APPCAST` value, byte for byte as `AppCast::getAppCastString()`:
    ///
    /// `proc=P!@#iter=N!@#[node=C!@#]iter=N!@#messages=L1!@L2!@!@#[config_warnings=W1!@W2]!@#`
    /// `events_total=K!@#[events=E1!@E2]!@#run_warning_total=T!@#[run_warnings=n1:R1!@n2:R2]`
    ///
    /// `iter` really appears twice; `node=` (with its separator) is left out when the node name
    /// is empty; each message line (split at `\n`, a trailing `\n` adds no empty line) is
    /// followed by `!@`; `config_warnings=` and `events=` are left out when empty but their
    /// `!@#` stays; `run_warnings=` is left out when empty and nothing follows it (no trailing
    /// separator).
    pub fn to_moos_string(&self) -> String {
        let o = OUTER_SEPARATOR;
        let i = INNER_SEPARATOR;
        let mut s = String::new();
        let _ = write!(s, "proc={}{o}iter={}{o}", self.proc_name, self.iteration);
        if !self.node_name.is_empty() {
            let _ = write!(s, "node={}{o}", self.node_name);
        }
        let _ = write!(s, "iter={}{o}", self.iteration);
        s.push_str("messages=");
        let mut rest = self.messages.as_str();
        while !rest.is_empty() {
            s.push_str(chomp(&mut rest, "\n"));
            s.push_str(i);
        }
        s.push_str(o);
        if !self.config_warnings.is_empty() {
            s.push_str("config_warnings=");
            s.push_str(&self.config_warnings.join(i));
        }
        s.push_str(o);
        let _ = write!(s, "events_total={}{o}", self.events.len());
        if !self.events.is_empty() {
            s.push_str("events=");
            for (k, e) in self.events.iter().enumerate() {
                if k > 0 {
                    s.push_str(i);
                }
                s.push_str(e);
            }
        }
        s.push_str(o);
        let _ = write!(s, "run_warning_total={}{o}", self.run_warning_total);
        if !self.run_warnings.is_empty() {
            s.push_str("run_warnings=");
            for (k, (text, count)) in self.run_warnings.iter().enumerate() {
                if k > 0 {
                    s.push_str(i);
                }
                let _ = write!(s, "{count}:{text}");
            }
        }
        s
    }

    /// Rebuilds an appcast from an `APPCAST` string as `string2AppCast` does; never fails.
    ///
    /// The string is cut at each `!@#` into `param=value` (both trimmed of spaces, tabs, CR,
    /// LF; unknown params and `events_total` are ignored; a repeated param is applied again).
    /// The caps become 1000 events and 1000 run warnings (the config warning cap stays).
    /// `iter` and `run_warning_total` are read with C `atoi` (a negative `iter` wraps).
    /// `messages` items each become a line ending in `\n`; config warnings, events and run
    /// warnings are trimmed items; a run warning is `count:text`, cut at its first `:`, a
    /// negative count read as 0. Events are kept verbatim (their `[t]: ` prefix is text).
    ///
    /// A field text that itself contains `!@#` or `!@` cannot survive the round trip, as in
    /// C++.
    pub fn parse(text: &str) -> AppCast {
        let mut ac = AppCast::new();
        ac.set_max_events(PARSED_MAX);
        ac.set_max_run_warnings(PARSED_MAX);
        let mut rest = text;
        while !rest.is_empty() {
            let mut pair = chomp(&mut rest, OUTER_SEPARATOR);
            let param = trim(chomp(&mut pair, "="));
            let mut value = trim(pair);
            match param {
                "proc" => ac.set_proc_name(value),
                "iter" => ac.set_iteration(atoi(value) as u32),
                "node" => ac.set_node_name(value),
                "messages" => {
                    let mut body = String::new();
                    while !value.is_empty() {
                        body.push_str(chomp(&mut value, INNER_SEPARATOR));
                        body.push('\n');
                    }
                    ac.set_messages(&body);
                }
                "config_warnings" => {
                    while !value.is_empty() {
                        ac.cfg_warning(trim(chomp(&mut value, INNER_SEPARATOR)));
                    }
                }
                "events" => {
                    while !value.is_empty() {
                        ac.event(trim(chomp(&mut value, INNER_SEPARATOR)), None);
                    }
                }
                "run_warning_total" => ac.set_run_warning_total(atoi(value) as u32),
                "run_warnings" => {
                    while !value.is_empty() {
                        let mut full = trim(chomp(&mut value, INNER_SEPARATOR));
                        let count = trim(chomp(&mut full, ":"));
                        let warning = trim(full);
                        let n = atoi(count).max(0) as u32;
                        ac.set_run_warning(warning, n);
                    }
                }
                _ => {}
            }
        }
        ac
    }

    /// The terminal / viewer rendering (`getFormattedString`): an optional 3-line header
    /// (`<proc> <node>`, padded to 62 characters with `<config warnings>/<run total>(<iter>)`),
    /// the configuration warnings, the run warnings, the report body, and the events newest
    /// first.
    pub fn to_formatted_string(&self, with_header: bool) -> String {
        let rule62 = "=".repeat(62);
        let rule67 = "=".repeat(67);
        let mut s = String::new();
        if with_header {
            let iter_str = format!("({})", self.iteration);
            let warn_str = format!("{}/{}", self.config_warnings.len(), self.run_warning_total);
            let title = format!("{} {}", self.proc_name, self.node_name);
            let now_len = warn_str.len() + title.len() + iter_str.len();
            let pad = " ".repeat(62usize.saturating_sub(now_len));
            let _ = writeln!(s, "{rule62}");
            let _ = writeln!(s, "{title}{pad}{warn_str}{iter_str}");
            let _ = writeln!(s, "{rule62}");
        }
        let n = self.config_warnings.len();
        if n > 0 {
            let _ = writeln!(s, "Configuration Warnings: {n}");
            for (j, w) in self.config_warnings.iter().enumerate() {
                let _ = writeln!(s, " [{} of {n}]: {w}", j + 1);
            }
            s.push('\n');
        }
        if self.run_warning_total > 0 {
            let _ = writeln!(s, "Runtime Warnings: {}", self.run_warning_total);
            for (text, count) in &self.run_warnings {
                let _ = writeln!(s, " [{count}]: {text}");
            }
            s.push('\n');
        }
        let _ = writeln!(s, "{}", self.messages);
        if !self.events.is_empty() {
            let _ = writeln!(s, "{rule67}");
            let _ = writeln!(s, "Most Recent Events ({}):", self.events.len());
            let _ = writeln!(s, "{rule67}");
            for e in self.events.iter().rev() {
                let _ = writeln!(s, "{e}");
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bare(proc_name: &str, node: &str, iter: u32) -> AppCast {
        let mut ac = AppCast::new();
        ac.set_proc_name(proc_name);
        ac.set_node_name(node);
        ac.set_iteration(iter);
        ac
    }

    #[test]
    fn empty_appcast_string_keeps_every_outer_separator() {
        let ac = bare("uProc", "henry", 123);
        assert_eq!(
            ac.to_moos_string(),
            "proc=uProc!@#iter=123!@#node=henry!@#iter=123!@#messages=!@#!@#events_total=0!@#!@#run_warning_total=0!@#"
        );
    }

    #[test]
    fn node_field_is_left_out_without_a_community() {
        let ac = bare("pFoo", "", 0);
        assert_eq!(
            ac.to_moos_string(),
            "proc=pFoo!@#iter=0!@#iter=0!@#messages=!@#!@#events_total=0!@#!@#run_warning_total=0!@#"
        );
    }

    #[test]
    fn full_appcast_string_by_hand() {
        let mut ac = bare("pHelm", "alpha", 7);
        // "a\n\nb\n": chomp at "\n" gives "a", "", "b" and stops (nothing after the last \n).
        ac.set_messages("a\n\nb\n");
        ac.cfg_warning("w1");
        ac.cfg_warning("w2");
        ac.event("started", Some(0.0));
        ac.event("turned", Some(12.345));
        ac.event("raw", None);
        ac.run_warning("zeta");
        ac.run_warning("alpha");
        ac.run_warning("zeta");
        assert_eq!(
            ac.to_moos_string(),
            concat!(
                "proc=pHelm!@#iter=7!@#node=alpha!@#iter=7!@#",
                "messages=a!@!@b!@!@#",
                "config_warnings=w1!@w2!@#",
                "events_total=3!@#",
                "events=[0.00]: started!@[12.35]: turned!@raw!@#",
                "run_warning_total=3!@#",
                "run_warnings=1:alpha!@2:zeta"
            )
        );
    }

    #[test]
    fn messages_without_trailing_newline_end_in_an_inner_separator_too() {
        let mut ac = bare("p", "n", 1);
        ac.set_messages("one\ntwo");
        assert!(ac.to_moos_string().contains("messages=one!@two!@!@#"));
        ac.set_messages("\n");
        assert!(ac.to_moos_string().contains("messages=!@!@#"));
    }

    #[test]
    fn event_timestamp_formats_and_cap() {
        let mut ac = AppCast::new();
        ac.event("neg", Some(-0.5));
        ac.event("nan", Some(f64::NAN));
        ac.event("big", Some(1234.5));
        ac.event("round", Some(0.005));
        ac.event("tie", Some(0.125));
        let got: Vec<&str> = ac.events().collect();
        // 0.005 is 0.005000000000000000104 in binary, so it rounds up; 0.125 is an exact tie
        // and printf rounds it to even.
        assert_eq!(
            got,
            [
                "neg",
                "nan",
                "[1234.50]: big",
                "[0.01]: round",
                "[0.12]: tie"
            ]
        );

        let mut ac = AppCast::new();
        for k in 0..10 {
            ac.event(&format!("e{k}"), None);
        }
        assert_eq!(ac.events_total(), 8);
        assert_eq!(ac.events().next(), Some("e2"));

        // A cap of 0 keeps nothing; lowering the cap drops one per event.
        let mut ac = AppCast::new();
        ac.set_max_events(0);
        ac.event("x", None);
        assert_eq!(ac.events_total(), 0);
        let mut ac = AppCast::new();
        for k in 0..5 {
            ac.event(&format!("e{k}"), None);
        }
        ac.set_max_events(2);
        ac.event("e5", None);
        assert_eq!(
            ac.events().collect::<Vec<_>>(),
            ["e1", "e2", "e3", "e4", "e5"]
        );
    }

    #[test]
    fn config_warnings_stop_after_one_hundred_and_one() {
        let mut ac = AppCast::new();
        for k in 0..150 {
            ac.cfg_warning(&format!("w{k}"));
        }
        assert_eq!(ac.config_warnings().len(), 101);
        assert_eq!(ac.config_warnings()[100], "w100");
    }

    #[test]
    fn run_warnings_beyond_the_cap_go_to_other_even_for_a_held_text() {
        let mut ac = AppCast::new();
        ac.set_max_run_warnings(2);
        ac.run_warning("a");
        ac.run_warning("b");
        ac.run_warning("a"); // map is full (2): counted as "Other Run Warnings"
        ac.run_warning("c");
        ac.run_warning("d"); // map now 3 > 2: still "Other Run Warnings"
        assert_eq!(ac.run_warning_total(), 5);
        let map: Vec<(&str, u32)> = ac
            .run_warnings()
            .iter()
            .map(|(k, v)| (k.as_str(), *v))
            .collect();
        assert_eq!(map, [("Other Run Warnings", 3), ("a", 1), ("b", 1)]);
        assert!(
            ac.to_moos_string()
                .ends_with("run_warning_total=5!@#run_warnings=3:Other Run Warnings!@1:a!@1:b")
        );
    }

    #[test]
    fn run_warning_cap_zero_counts_everything_as_other() {
        let mut ac = AppCast::new();
        ac.set_max_run_warnings(0);
        ac.run_warning("x");
        ac.run_warning("y");
        assert_eq!(ac.run_warnings().get(OTHER_RUN_WARNINGS), Some(&2));
        assert_eq!(ac.run_warnings().len(), 1);
    }

    #[test]
    fn retract_removes_the_whole_count() {
        let mut ac = AppCast::new();
        ac.run_warning("a");
        ac.run_warning("a");
        ac.run_warning("b");
        assert!(!ac.retract_run_warning("c"));
        assert!(ac.retract_run_warning("a"));
        assert_eq!(ac.run_warning_total(), 1);
        assert!(!ac.retract_run_warning("a"));
        // Total never goes below zero.
        ac.set_run_warning_total(0);
        assert!(ac.retract_run_warning("b"));
        assert_eq!(ac.run_warning_total(), 0);
    }

    #[test]
    fn byte_order_of_run_warnings_matches_std_map() {
        let mut ac = AppCast::new();
        for w in ["b", "B", "a", "_", "é"] {
            ac.run_warning(w);
        }
        let keys: Vec<&str> = ac.run_warnings().keys().map(String::as_str).collect();
        assert_eq!(keys, ["B", "_", "a", "b", "é"]);
    }

    #[test]
    fn parse_inverts_the_string() {
        let s = concat!(
            "proc=pHelm!@#iter=7!@#node=alpha!@#iter=7!@#",
            "messages=a!@!@b!@!@#",
            "config_warnings=w1!@w2!@#",
            "events_total=3!@#",
            "events=[0.00]: started!@[12.35]: turned!@raw!@#",
            "run_warning_total=3!@#",
            "run_warnings=1:alpha!@2:zeta"
        );
        let ac = AppCast::parse(s);
        assert_eq!(ac.proc_name(), "pHelm");
        assert_eq!(ac.node_name(), "alpha");
        assert_eq!(ac.iteration(), 7);
        assert_eq!(ac.messages(), "a\n\nb\n");
        assert_eq!(ac.config_warnings(), ["w1", "w2"]);
        assert_eq!(
            ac.events().collect::<Vec<_>>(),
            ["[0.00]: started", "[12.35]: turned", "raw"]
        );
        assert_eq!(ac.run_warning_total(), 3);
        assert_eq!(ac.run_warnings().get("zeta"), Some(&2));
        assert_eq!(ac.max_events(), 1000);
        assert_eq!(ac.max_run_warnings(), 1000);
        assert_eq!(ac.to_moos_string(), s);
    }

    #[test]
    fn parse_trims_and_tolerates_odd_input() {
        let ac = AppCast::parse(
            " proc = uX !@#iter=-1!@#bogus=1!@#noequals!@#run_warnings= 2 : a:b !@-3:c!@x!@#run_warning_total=abc",
        );
        assert_eq!(ac.proc_name(), "uX");
        assert_eq!(ac.iteration(), u32::MAX);
        assert_eq!(ac.run_warnings().get("a:b"), Some(&2));
        assert_eq!(ac.run_warnings().get("c"), Some(&0));
        // "x" has no ':': the count is "x" (0) and the text is empty.
        assert_eq!(ac.run_warnings().get(""), Some(&0));
        assert_eq!(ac.run_warning_total(), 0);
        assert_eq!(ac.node_name(), "");
        assert_eq!(AppCast::parse(""), {
            let mut e = AppCast::new();
            e.set_max_events(1000);
            e.set_max_run_warnings(1000);
            e
        });
    }

    #[test]
    fn parse_keeps_leading_spaces_of_items_out_and_events_as_text() {
        let ac = AppCast::parse("messages=  indented!@  second!@!@#events= [1.00]: x !@#");
        // The value is trimmed as a whole, the message items are not trimmed one by one.
        assert_eq!(ac.messages(), "indented\n  second\n");
        assert_eq!(ac.events().collect::<Vec<_>>(), ["[1.00]: x"]);
    }

    #[test]
    fn a_message_line_starting_with_hash_breaks_the_round_trip_as_in_cpp() {
        let mut ac = bare("p", "", 1);
        ac.set_messages("a\n#b");
        let s = ac.to_moos_string();
        assert!(s.contains("messages=a!@#b!@!@#"));
        let back = AppCast::parse(&s);
        assert_eq!(back.messages(), "a\n");
    }

    #[test]
    fn round_trip_normalises_the_messages_only() {
        let mut ac = bare("pX", "n", 2);
        ac.set_messages("a\nb");
        assert_eq!(AppCast::parse(&ac.to_moos_string()).messages(), "a\nb\n");
        ac.set_messages("");
        assert_eq!(AppCast::parse(&ac.to_moos_string()).messages(), "");
        ac.set_messages("  lead\ntrail  ");
        // The field value is trimmed as a whole: the first line loses its leading blanks; the
        // last line's trailing blanks are shielded by the `!@` that follows every line.
        assert_eq!(
            AppCast::parse(&ac.to_moos_string()).messages(),
            "lead\ntrail  \n"
        );
    }

    #[test]
    fn parse_caps_are_one_thousand() {
        let events: Vec<String> = (0..1001).map(|k| format!("e{k}")).collect();
        let warnings: Vec<String> = (0..1001).map(|k| format!("1:w{k:04}")).collect();
        let s = format!(
            "events={}!@#run_warnings={}",
            events.join("!@"),
            warnings.join("!@")
        );
        let ac = AppCast::parse(&s);
        assert_eq!(ac.events_total(), 1000);
        assert_eq!(ac.events().next(), Some("e1"));
        assert_eq!(ac.run_warnings().len(), 1000);
        assert!(!ac.run_warnings().contains_key("w1000"));
        // Once full, even a held text is not updated.
        let mut ac = ac;
        ac.set_run_warning("w0000", 9);
        assert_eq!(ac.run_warnings().get("w0000"), Some(&1));
    }

    #[test]
    fn formatted_string_by_hand() {
        let mut ac = bare("pFoo", "alpha", 3);
        ac.set_messages("body");
        ac.cfg_warning("cw");
        ac.run_warning("rw");
        ac.run_warning("rw");
        ac.event("e1", None);
        ac.event("e2", None);
        // title "pFoo alpha" (10) + "1/2" (3) + "(3)" (3) = 16: 46 spaces of padding.
        let expected = format!(
            "{r}\npFoo alpha{pad}1/2(3)\n{r}\nConfiguration Warnings: 1\n [1 of 1]: cw\n\n\
             Runtime Warnings: 2\n [2]: rw\n\nbody\n{q}\nMost Recent Events (2):\n{q}\ne2\ne1\n",
            r = "=".repeat(62),
            q = "=".repeat(67),
            pad = " ".repeat(46)
        );
        assert_eq!(ac.to_formatted_string(true), expected);
        assert_eq!(bare("p", "", 0).to_formatted_string(false), "\n");
    }
}
