//! [`AppCasting`]: the appcasting half of libMOOS's `AppCastingMOOSApp` without the MOOS I/O:
//! start-up configuration, warnings and events, `APPCAST_REQ` / `TERM_REPORT_INTERVAL` /
//! `COMMS_POLICY` mail, and when and what to post as `APPCAST`.
//!
//! # Time
//!
//! Every `now` argument is **MOOS time**, i.e. warped time (`MOOSTime()`, what the C++ keeps in
//! `m_curr_time`), in seconds. As in C++:
//! - a request's `duration` is compared with MOOS time elapsed since it arrived (so under a
//!   time warp of 10 a 3 s request lasts 0.3 s of wall-clock time);
//! - event stamps are MOOS seconds since [`AppCasting::start_up`];
//! - only the posting rate limit ([`AppCasting::due`]) is in real time: MOOS time elapsed
//!   since the last `APPCAST`, divided by the time warp, against
//!   [`AppCasting::term_report_interval`].

use std::collections::BTreeMap;

use crate::appcast::AppCast;
use crate::cstr::{atof, atoi, chomp, fmt_g, is_numeric, trim};

/// The variables every appcasting app subscribes to (interval 0) in `RegisterVariables()`.
pub const REGISTERED_VARIABLES: [&str; 4] = [
    "APPCAST_REQ",
    "LOADCAST_REQ",
    "TERM_REPORT_INTERVAL",
    "COMMS_POLICY",
];
/// The variable an appcast is posted to.
pub const APPCAST_VAR: &str = "APPCAST";
/// The request variable an app reads.
pub const APPCAST_REQ_VAR: &str = "APPCAST_REQ";

/// `APPCAST_REQ_<NODE>`: the second copy of a request that viewers (uMAC, pMarineViewer) post
/// next to `APPCAST_REQ`, with the node name upper-cased (ASCII), for the shore broker to bridge
/// to that vehicle, where it arrives as `APPCAST_REQ`. The C++ app itself never subscribes it;
/// its value has the same syntax, so [`AppCasting::on_request`] takes it as well.
pub fn node_request_var(node: &str) -> String {
    format!("APPCAST_REQ_{}", node.to_ascii_uppercase())
}

/// Default `TERM_REPORT_INTERVAL`, real seconds.
pub const DEFAULT_TERM_REPORT_INTERVAL: f64 = 0.5;
/// Largest `TERM_REPORT_INTERVAL` the configuration accepts (clipped to it).
pub const MAX_CONFIG_TERM_REPORT_INTERVAL: f64 = 10.0;
/// Smallest `TERM_REPORT_INTERVAL` mail accepts (raised to it; there is no upper clip).
pub const MIN_MAIL_TERM_REPORT_INTERVAL: f64 = 0.4;
/// Largest `MAX_APPCAST_EVENTS` (clipped to it).
pub const MAX_CONFIG_EVENTS: i32 = 50;
/// Longest request duration honoured, MOOS seconds (clipped to it).
pub const MAX_REQUEST_DURATION: f64 = 30.0;
/// The time warp used in place of a zero or negative one.
pub const FALLBACK_TIME_WARP: f64 = 0.001;

/// Config lines `reportUnhandledConfigWarning` stays silent about (upper-cased parameter).
/// `COMMS_POLICY` and `MAX_APPCAST_RUN_WARNINGS` are *not* in the C++ list.
pub const UNHANDLED_EXEMPT: [&str; 7] = [
    "APPTICK",
    "APP_LOGGING",
    "MAXAPPTICK",
    "TERM_REPORT_INTERVAL",
    "COMMSTICK",
    "MAX_APPCAST_EVENTS",
    "DEPRECATED_OK",
];

/// `COMMS_POLICY`: how much an app should publish.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CommsPolicy {
    /// `open` (the default).
    Open,
    /// `lean`.
    Lean,
    /// `dire`.
    Dire,
}

impl CommsPolicy {
    /// The lower-case name.
    pub fn as_str(self) -> &'static str {
        match self {
            CommsPolicy::Open => "open",
            CommsPolicy::Lean => "lean",
            CommsPolicy::Dire => "dire",
        }
    }

    /// Reads an exact lower-case name.
    fn from_lower(s: &str) -> Option<Self> {
        match s {
            "open" => Some(CommsPolicy::Open),
            "lean" => Some(CommsPolicy::Lean),
            "dire" => Some(CommsPolicy::Dire),
            _ => None,
        }
    }
}

/// `APP_LOGGING`: where the C++ sends the app's terminal output. Stored only; coug does not
/// redirect anything.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AppLogging {
    /// `off` (the default).
    Off,
    /// `log` (or `true`): published as `APP_LOG`.
    Log,
    /// `file`.
    File,
}

/// Which warnings [`AppCasting::warning_count`] counts (`"config"`, `"run"`, `"all"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WarningFilter {
    /// Configuration warnings held.
    Config,
    /// The run warning total.
    Run,
    /// Both.
    All,
}

/// One requester's standing appcast request (per `key=`).
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    /// How long the request is honoured, MOOS seconds, clipped to `[0, 30]` (NaN stays NaN and
    /// never matches).
    pub duration: f64,
    /// MOOS time the request arrived.
    pub start: f64,
    /// `thresh=`: `any` (the default) or `run_warning`; any other text never triggers.
    pub thresh: String,
}

/// The appcasting state of one app (`AppCastingMOOSApp` minus the MOOS I/O and terminal
/// output).
///
/// Typical use: [`start_up`](Self::start_up) once; feed `APPCAST_REQ`, `TERM_REPORT_INTERVAL`,
/// `COMMS_POLICY` mail to [`on_request`](Self::on_request),
/// [`on_term_report_interval`](Self::on_term_report_interval),
/// [`on_comms_policy`](Self::on_comms_policy); report warnings and events as they happen; at
/// the end of each iteration, if [`due`](Self::due), post [`build`](Self::build) as `APPCAST`.
#[derive(Debug, Clone)]
pub struct AppCasting {
    ac: AppCast,
    start_time: f64,
    time_warp: f64,
    term_report_interval: f64,
    last_appcast_time: Option<f64>,
    new_run_warning: bool,
    new_cfg_warning: bool,
    requests: BTreeMap<String, Request>,
    comms_policy: CommsPolicy,
    comms_policy_config: CommsPolicy,
    app_logging: AppLogging,
    deprecated_ok: bool,
}

impl AppCasting {
    /// The state the C++ constructor leaves: the app name set, no community, start time 0, time
    /// warp 1, interval 0.5 s, policy `open`, logging `off`, no appcast posted yet.
    pub fn new(proc_name: &str) -> Self {
        let mut ac = AppCast::new();
        ac.set_proc_name(proc_name);
        Self {
            ac,
            start_time: 0.0,
            time_warp: 1.0,
            term_report_interval: DEFAULT_TERM_REPORT_INTERVAL,
            last_appcast_time: None,
            new_run_warning: false,
            new_cfg_warning: false,
            requests: BTreeMap::new(),
            comms_policy: CommsPolicy::Open,
            comms_policy_config: CommsPolicy::Open,
            app_logging: AppLogging::Off,
            deprecated_ok: false,
        }
    }

    /// `OnStartUp()` with no directives, in the C++ order (which is the order of the warnings):
    ///
    /// 1. `COMMS_POLICY`, `APP_LOGGING`, `DEPRECATED_OK` lines of the config block;
    /// 2. no `community` → `XCommunity/Vehicle name not found in mission file`;
    /// 3. no config block → `No mission config block found for <proc>`;
    /// 4. `TERM_REPORT_INTERVAL`, `MAX_APPCAST_EVENTS`, `MAX_APPCAST_RUN_WARNINGS` lines;
    /// 5. the node name becomes the community (empty without one);
    /// 6. the start time becomes `now` (MOOS time); a time warp `<= 0` →
    ///    `MOOSTimeWarp invalid: <warp>. Using 0.001 instead.` and 0.001 is used.
    ///
    /// `config_block` holds `PARAM=value` lines as the mission reader returns them (blanks
    /// removed; note that `GetConfiguration` returns a block's lines in reverse file order, so
    /// for a repeated parameter the first line in the file is applied last). Returns false
    /// when step 2, 3 or 6 warned, as the C++ does. `TERM_REPORTING` and the deprecation
    /// warnings are not handled (coug has no terminal reports).
    pub fn start_up<S: AsRef<str>>(
        &mut self,
        community: Option<&str>,
        config_block: Option<&[S]>,
        now: f64,
        time_warp: f64,
    ) -> bool {
        let mut ok = true;
        let lines: &[S] = config_block.unwrap_or(&[]);
        for line in lines {
            let (param, value) = split_line(line.as_ref());
            if matches!(
                param.as_str(),
                "COMMS_POLICY" | "APP_LOGGING" | "DEPRECATED_OK"
            ) {
                let _ = self.apply_key(&param, value);
            }
        }
        if community.is_none() {
            self.report_config_warning("XCommunity/Vehicle name not found in mission file");
            ok = false;
        }
        if config_block.is_none() {
            let msg = format!("No mission config block found for {}", self.ac.proc_name());
            self.report_config_warning(&msg);
            ok = false;
        }
        for line in lines {
            let (param, value) = split_line(line.as_ref());
            if matches!(
                param.as_str(),
                "TERM_REPORT_INTERVAL" | "MAX_APPCAST_EVENTS" | "MAX_APPCAST_RUN_WARNINGS"
            ) {
                let _ = self.apply_key(&param, value);
            }
        }
        self.ac.set_node_name(community.unwrap_or(""));
        self.start_time = now;
        self.time_warp = time_warp;
        if time_warp <= 0.0 {
            let msg = format!(
                "MOOSTimeWarp invalid: {}. Using 0.001 instead.",
                fmt_g(time_warp)
            );
            self.report_config_warning(&msg);
            self.time_warp = FALLBACK_TIME_WARP;
            ok = false;
        }
        ok
    }

    /// One config parameter the appcasting layer owns; `None` for any other key (the app's
    /// own). The key is matched case-insensitively (upper-cased, trimmed), the value trimmed:
    ///
    /// | key | rule |
    /// |---|---|
    /// | `COMMS_POLICY` | `open`, `lean`, `dire` (any case); sets the policy and its configured floor |
    /// | `APP_LOGGING` | `true` (= `log`), `log`, `file`, `off` (any case) |
    /// | `DEPRECATED_OK` | `true` / `false` (any case) |
    /// | `TERM_REPORT_INTERVAL` | numeric (`MOOSIsNumeric`), `atof`, clipped to `[0, 10]` |
    /// | `MAX_APPCAST_EVENTS` | numeric, `atoi`, clipped to `[0, 50]` |
    /// | `MAX_APPCAST_RUN_WARNINGS` | numeric, `atoi`, below 0 → 0, **above 1000 → 100** (C++) |
    ///
    /// `Some(Err(text))` when the value is refused: `text` is the C++ warning (e.g.
    /// `Invalid TERM_REPORT_INTERVAL: abc`; a bad `MAX_APPCAST_RUN_WARNINGS` says
    /// `Invalid MAX_APPCAST_EVENTS: ...`, as in C++) and **has already been recorded as a
    /// config warning**; do not report it again.
    ///
    /// (The C++ lower-cases the untrimmed value of the first three keys; the mission reader has
    /// removed all blanks by then, so trimming first changes nothing.)
    pub fn consume_config_key(&mut self, key: &str, value: &str) -> Option<Result<(), String>> {
        let param = trim(key).to_ascii_uppercase();
        self.apply_key(&param, trim(value))
    }

    /// [`consume_config_key`](Self::consume_config_key) on an upper-cased, trimmed key and a
    /// trimmed value.
    fn apply_key(&mut self, param: &str, value: &str) -> Option<Result<(), String>> {
        let lvalue = value.to_ascii_lowercase();
        let warning = match param {
            "COMMS_POLICY" => match CommsPolicy::from_lower(&lvalue) {
                Some(p) => {
                    self.comms_policy = p;
                    self.comms_policy_config = p;
                    None
                }
                None => Some(format!("Invalid comms_policy: {value}")),
            },
            "APP_LOGGING" => match lvalue.as_str() {
                "true" | "log" => {
                    self.app_logging = AppLogging::Log;
                    None
                }
                "file" => {
                    self.app_logging = AppLogging::File;
                    None
                }
                "off" => {
                    self.app_logging = AppLogging::Off;
                    None
                }
                _ => Some(format!("Invalid APP_LOGGING: {value}")),
            },
            "DEPRECATED_OK" => match lvalue.as_str() {
                "true" => {
                    self.deprecated_ok = true;
                    None
                }
                "false" => {
                    self.deprecated_ok = false;
                    None
                }
                _ => Some(format!("Invalid DEPRECATED_OK: {value}")),
            },
            "TERM_REPORT_INTERVAL" => {
                if is_numeric(value) {
                    let mut v = atof(value);
                    if v < 0.0 {
                        v = 0.0;
                    }
                    if v > MAX_CONFIG_TERM_REPORT_INTERVAL {
                        v = MAX_CONFIG_TERM_REPORT_INTERVAL;
                    }
                    self.term_report_interval = v;
                    None
                } else {
                    Some(format!("Invalid TERM_REPORT_INTERVAL: {value}"))
                }
            }
            "MAX_APPCAST_EVENTS" => {
                if is_numeric(value) {
                    let v = atoi(value).clamp(0, MAX_CONFIG_EVENTS);
                    self.ac.set_max_events(v as usize);
                    None
                } else {
                    Some(format!("Invalid MAX_APPCAST_EVENTS: {value}"))
                }
            }
            "MAX_APPCAST_RUN_WARNINGS" => {
                if is_numeric(value) {
                    let mut v = atoi(value).max(0);
                    if v > 1000 {
                        v = 100;
                    }
                    self.ac.set_max_run_warnings(v as usize);
                    None
                } else {
                    Some(format!("Invalid MAX_APPCAST_EVENTS: {value}"))
                }
            }
            _ => return None,
        };
        Some(match warning {
            None => Ok(()),
            Some(text) => {
                self.report_config_warning(&text);
                Err(text)
            }
        })
    }

    /// An `APPCAST_REQ` (or `APPCAST_REQ_<NODE>`) value, received at MOOS time `now`:
    /// `node=<community|all>,app=<name|all>,duration=<s>,key=<requester>,thresh=<any|run_warning>`.
    ///
    /// Pairs are cut at `,` then at the first `=`; names are matched case-insensitively, values
    /// trimmed and compared exactly. A `node` other than the community or `all`, or an `app`
    /// other than this app or `all`, drops the request at once; so does a missing or empty
    /// `key`. `duration` is read with `atof` (missing → 0) and clipped to `[0, 30]`; `thresh`
    /// defaults to `any`. The request replaces the one stored under its key. Returns whether
    /// it was stored (the C++ returns nothing).
    pub fn on_request(&mut self, value: &str, now: f64) -> bool {
        let mut key = "";
        let mut duration = "";
        let mut thresh = "any";
        let mut rest = value;
        while !rest.is_empty() {
            let (param, value) = split_line(chomp(&mut rest, ","));
            match param.as_str() {
                "NODE" => {
                    if value != self.ac.node_name() && value != "all" {
                        return false;
                    }
                }
                "APP" => {
                    if value != self.ac.proc_name() && value != "all" {
                        return false;
                    }
                }
                "DURATION" => duration = value,
                "THRESH" => thresh = value,
                "KEY" => key = value,
                _ => {}
            }
        }
        if key.is_empty() {
            return false;
        }
        let mut d = atof(duration);
        if d < 0.0 {
            d = 0.0;
        }
        if d > MAX_REQUEST_DURATION {
            d = MAX_REQUEST_DURATION;
        }
        self.requests.insert(
            key.to_string(),
            Request {
                duration: d,
                start: now,
                thresh: thresh.to_string(),
            },
        );
        true
    }

    /// A `TERM_REPORT_INTERVAL` posting: its double value, raised to 0.4 if smaller, no upper
    /// limit (unlike the config parameter). A string posting carries the MOOS message's double
    /// field, −1, hence 0.4. NaN is kept (it then never holds a posting back).
    pub fn on_term_report_interval(&mut self, value: f64) {
        self.term_report_interval = if value < MIN_MAIL_TERM_REPORT_INTERVAL {
            MIN_MAIL_TERM_REPORT_INTERVAL
        } else {
            value
        };
    }

    /// A `COMMS_POLICY` posting. The value is lower-cased; `open`, `lean`, `dire` are valid. The
    /// policy can never be made laxer than the configured one: `open` under a `lean` or `dire`
    /// configuration is ignored silently (accepted), `lean` under `dire` is refused. A refused
    /// or invalid value adds the run warning `Unhandled COMMS_POLICY:<lower-cased value>`.
    /// Returns whether it was handled.
    pub fn on_comms_policy(&mut self, value: &str) -> bool {
        let sval = value.to_ascii_lowercase();
        let handled = match CommsPolicy::from_lower(&sval) {
            None => false,
            Some(CommsPolicy::Open) if self.comms_policy_config != CommsPolicy::Open => true,
            Some(CommsPolicy::Lean) if self.comms_policy_config == CommsPolicy::Dire => false,
            Some(p) => {
                self.comms_policy = p;
                true
            }
        };
        if !handled {
            self.report_run_warning(&format!("Unhandled COMMS_POLICY:{sval}"));
        }
        handled
    }

    /// Adds an event stamped with MOOS seconds since start-up, `[<now - start, 2 decimals>]: `.
    /// Before the start time (a negative stamp) the text is kept bare, as in C++.
    pub fn report_event(&mut self, text: &str, now: f64) {
        self.ac.event(text, Some(now - self.start_time));
    }

    /// Adds a configuration warning (ignored if empty) and makes an appcast pending.
    pub fn report_config_warning(&mut self, text: &str) {
        if text.is_empty() {
            return;
        }
        self.new_cfg_warning = true;
        self.ac.cfg_warning(text);
    }

    /// Reports a config line the app did not handle as `Unhandled config line: <orig>`, unless
    /// empty or its parameter (upper-cased, before the first `=`) is one of
    /// [`UNHANDLED_EXEMPT`].
    pub fn report_unhandled_config_warning(&mut self, orig: &str) {
        if orig.is_empty() {
            return;
        }
        let (param, _) = split_line(orig);
        if UNHANDLED_EXEMPT.contains(&param.as_str()) {
            return;
        }
        self.report_config_warning(&format!("Unhandled config line: {orig}"));
    }

    /// Counts a run warning (ignored if empty; see [`AppCast::run_warning`] for the cap) and
    /// marks a new run warning, which triggers the `thresh=run_warning` requests.
    pub fn report_run_warning(&mut self, text: &str) {
        if text.is_empty() {
            return;
        }
        self.new_run_warning = true;
        self.ac.run_warning(text);
    }

    /// Withdraws a run warning by its exact text. Nothing happens while the run warning total
    /// is 0; a successful retraction counts as a new run warning (so viewers get the update).
    pub fn retract_run_warning(&mut self, text: &str) {
        if self.ac.run_warning_total() == 0 {
            return;
        }
        if self.ac.retract_run_warning(text) {
            self.new_run_warning = true;
        }
    }

    /// Configuration warnings held and/or the run warning total.
    pub fn warning_count(&self, filter: WarningFilter) -> usize {
        let config = self.ac.config_warnings().len();
        let run = self.ac.run_warning_total() as usize;
        match filter {
            WarningFilter::Config => config,
            WarningFilter::Run => run,
            WarningFilter::All => config + run,
        }
    }

    /// `appcastRequested()`: some stored request is younger than its duration (MOOS time,
    /// `now - start < duration`, strictly) with `thresh=any`, or with `thresh=run_warning` while
    /// a new run warning waits; or a new configuration warning waits (even with no request at
    /// all).
    pub fn appcast_requested(&self, now: f64) -> bool {
        let by_request = self.requests.values().any(|r| {
            now - r.start < r.duration
                && (r.thresh == "any" || (r.thresh == "run_warning" && self.new_run_warning))
        });
        by_request || self.new_cfg_warning
    }

    /// Whether an `APPCAST` must be posted at the end of iteration `iteration` (counted from 1,
    /// as the C++ increments it before the app's `Iterate`), at MOOS time `now` (the time the
    /// iteration started, `m_curr_time`).
    ///
    /// `PostReport()`'s rules for the appcast: the time warp must be positive; real time since
    /// the last `APPCAST` ((`now` − last) / warp) must be at least the interval; and an appcast
    /// must be pending: [`appcast_requested`](Self::appcast_requested) or `iteration < 2`. The
    /// terminal-report clock of the C++ never changes this outcome, since it is reset whenever
    /// the appcast clock is. Before the first `APPCAST` the elapsed time counts as infinite (the
    /// C++ starts from 0 against an epoch-based MOOS time). The app's `buildReport()` returning
    /// false (no appcast that iteration) is the caller's to honour.
    pub fn due(&self, now: f64, iteration: u32) -> bool {
        if self.time_warp <= 0.0 {
            return false;
        }
        if let Some(last) = self.last_appcast_time {
            let real_elapsed = (now - last) / self.time_warp;
            if real_elapsed < self.term_report_interval {
                return false;
            }
        }
        self.appcast_requested(now) || iteration < 2
    }

    /// The `APPCAST` value for iteration `iteration` with report body `messages` (lines
    /// separated by `\n`), and marks it posted at MOOS time `now`: the new run / config warning
    /// flags are cleared and the rate-limit clock restarts. Call it only when
    /// [`due`](Self::due).
    pub fn build(&mut self, iteration: u32, messages: &str, now: f64) -> String {
        self.ac.set_iteration(iteration);
        self.ac.set_messages(messages);
        self.new_run_warning = false;
        self.new_cfg_warning = false;
        self.last_appcast_time = Some(now);
        self.ac.to_moos_string()
    }

    /// The appcast as last built (warnings and events are current).
    pub fn appcast(&self) -> &AppCast {
        &self.ac
    }

    /// The app name.
    pub fn proc_name(&self) -> &str {
        self.ac.proc_name()
    }

    /// The community (node name); empty before start-up or without one.
    pub fn community(&self) -> &str {
        self.ac.node_name()
    }

    /// MOOS time of start-up (event stamps count from it).
    pub fn start_time(&self) -> f64 {
        self.start_time
    }

    /// The time warp in use (never `<= 0` after start-up).
    pub fn time_warp(&self) -> f64 {
        self.time_warp
    }

    /// Minimum real seconds between two `APPCAST` postings.
    pub fn term_report_interval(&self) -> f64 {
        self.term_report_interval
    }

    /// MOOS time of the last `APPCAST` built, if any.
    pub fn last_appcast_time(&self) -> Option<f64> {
        self.last_appcast_time
    }

    /// Whether a run warning was reported (or retracted) since the last `APPCAST`.
    pub fn new_run_warning(&self) -> bool {
        self.new_run_warning
    }

    /// Whether a configuration warning was reported since the last `APPCAST`.
    pub fn new_cfg_warning(&self) -> bool {
        self.new_cfg_warning
    }

    /// The stored requests by requester key.
    pub fn requests(&self) -> &BTreeMap<String, Request> {
        &self.requests
    }

    /// The comms policy in force.
    pub fn comms_policy(&self) -> CommsPolicy {
        self.comms_policy
    }

    /// `APP_LOGGING` as configured.
    pub fn app_logging(&self) -> AppLogging {
        self.app_logging
    }

    /// `DEPRECATED_OK` as configured.
    pub fn deprecated_ok(&self) -> bool {
        self.deprecated_ok
    }
}

/// A `param=value` line: the parameter before the first `=`, upper-cased (ASCII) and trimmed,
/// and the trimmed rest.
fn split_line(line: &str) -> (String, &str) {
    let mut rest = line;
    let param = trim(chomp(&mut rest, "=")).to_ascii_uppercase();
    (param, trim(rest))
}
