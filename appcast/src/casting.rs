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
use moos_types::text::{atof, atoi, chomp, moos_is_numeric as is_numeric, trim};

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
    /// `LOADCAST_REQ`: how long (MOOS s) the latest request is honoured, and when it came.
    lcast_duration: f64,
    lcast_start: f64,
    lcast_due: bool,
    last_iterate: Option<f64>,
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
            lcast_duration: 0.0,
            lcast_start: 0.0,
            lcast_due: false,
            last_iterate: None,
        }
    }

    /// A `LOADCAST_REQ` value (`app=<name|all|any>,duration=<s>,thresh=<load>`) received at MOOS
    /// time `now`: for this app (exact name, `all` or `any`), the load figures are posted for
    /// `duration` seconds (`atof`, clipped to [0, 30]); another app's request is ignored. The
    /// threshold is read and, as in libMOOS, never used.
    pub fn on_loadcast_request(&mut self, value: &str, now: f64) {
        let (mut app, mut duration) = ("", "");
        let mut rest = value;
        while !rest.is_empty() {
            let mut pair = chomp(&mut rest, ",");
            let param = trim(chomp(&mut pair, "=")).to_ascii_uppercase();
            let v = trim(pair);
            match param.as_str() {
                "APP" => app = v,
                "DURATION" => duration = v,
                _ => {}
            }
        }
        if app != self.ac.proc_name() && app != "all" && app != "any" {
            return;
        }
        self.lcast_duration = atof(duration).clamp(0.0, 30.0);
        self.lcast_start = now;
    }

    /// Called as an iteration starts at MOOS time `now` (AppCastingMOOSApp::Iterate), with the
    /// app's tick in Hz: while a load-cast request is fresh, the `<APP>_ITER_GAP` value, the
    /// time since the previous iteration over the tick period (none for the first iteration
    /// or a tick of 0).
    pub fn iteration_started(&mut self, now: f64, app_freq: f64) -> Option<f64> {
        self.lcast_due = now - self.lcast_start < self.lcast_duration;
        let gap = match self.last_iterate {
            Some(last) if self.lcast_due && app_freq > 0.0 => Some((now - last) * app_freq),
            _ => None,
        };
        self.last_iterate = Some(now);
        gap
    }

    /// With `APP_LOGGING = log`, the `APP_LOG` value posted first in iteration `iteration`
    /// (counted from 1): `iter=<iteration>,log=` followed by what the app wrote to its
    /// terminal during the previous iteration, newlines as `!@#`. coug's apps write no
    /// terminal text per iteration (their logs go through `tracing` to stderr), so `captured`
    /// is normally empty.
    pub fn app_log(&self, iteration: u32, captured: &str) -> Option<String> {
        (self.app_logging == AppLogging::Log)
            .then(|| format!("iter={iteration},log={}", captured.replace('\n', "!@#")))
    }

    /// While a load-cast request is fresh, the `<APP>_ITER_LEN` value for an iteration that
    /// took `len_s` seconds: its length over the tick period (PostReport).
    pub fn iteration_length(&self, len_s: f64, app_freq: f64) -> Option<f64> {
        (self.lcast_due && app_freq > 0.0).then_some(len_s * app_freq)
    }

    /// Moves the start time (the zero of event stamps) to MOOS time `now`, for an app whose
    /// configuration is read before it connects.
    pub fn set_start_time(&mut self, now: f64) {
        self.start_time = now;
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
                moos_types::fmt::g_string(time_warp, 6)
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
                    // Same as the C++ pair of ifs, NaN included (it stays NaN).
                    let v = atof(value).clamp(0.0, MAX_CONFIG_TERM_REPORT_INTERVAL);
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
                "NODE" if value != self.ac.node_name() && value != "all" => return false,
                "APP" if value != self.ac.proc_name() && value != "all" => return false,
                "DURATION" => duration = value,
                "THRESH" => thresh = value,
                "KEY" => key = value,
                _ => {}
            }
        }
        if key.is_empty() {
            return false;
        }
        // Same as the C++ pair of ifs, NaN included (it stays NaN).
        let d = atof(duration).clamp(0.0, MAX_REQUEST_DURATION);
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
    /// Before the start time (a negative stamp) the text is kept bare, as in C++. The C++ stamps
    /// with `m_curr_time`, the MOOS time at which the current iteration (or mail batch) began,
    /// not the instant of the call; pass that time for identical stamps.
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
    /// marks a new run warning, which triggers the `thresh=run_warning` requests. (The C++
    /// returns `false` always, a convenience for `return reportRunWarning(..)`; nothing here.)
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
    /// separated by `\n`), and marks it posted at MOOS time `now` (the same iteration-start time
    /// given to [`due`](Self::due), as the C++ records `m_curr_time`): the new run / config warning
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

#[cfg(test)]
mod loadcast_tests {
    use super::*;

    #[test]
    fn app_log_is_posted_only_with_app_logging_log() {
        let mut a = AppCasting::new("pFoo");
        assert_eq!(a.app_log(1, ""), None);
        assert!(a.consume_config_key("APP_LOGGING", "log").is_some());
        assert_eq!(a.app_log(1, "").as_deref(), Some("iter=1,log="));
        assert_eq!(
            a.app_log(7, "a\nb\n").as_deref(),
            Some("iter=7,log=a!@#b!@#")
        );
        let mut f = AppCasting::new("pFoo");
        f.consume_config_key("APP_LOGGING", "file");
        assert_eq!(f.app_log(1, ""), None, "file logging posts nothing");
    }

    #[test]
    fn load_figures_follow_a_fresh_request_for_this_app() {
        let mut a = AppCasting::new("pFoo");
        assert_eq!(a.iteration_started(10.0, 4.0), None, "no request");
        a.on_loadcast_request("app=pBar,duration=5", 10.0);
        assert_eq!(
            a.iteration_started(10.25, 4.0),
            None,
            "another app's request"
        );
        a.on_loadcast_request(" app = pFoo , duration=50,thresh=2", 10.25);
        // Gap 0.5 s at 4 Hz (period 0.25 s): 2; the duration is clipped to 30 s.
        assert_eq!(a.iteration_started(10.75, 4.0), Some(2.0));
        assert_eq!(a.iteration_length(0.05, 4.0), Some(0.2));
        assert_eq!(a.iteration_started(11.0, 0.0), None, "no tick");
        assert_eq!(
            a.iteration_started(40.24, 4.0).map(|g| g.round()),
            Some(117.0)
        );
        assert_eq!(a.iteration_started(40.25, 4.0), None, "30 s later: stale");
        assert_eq!(a.iteration_length(0.05, 4.0), None);
        a.on_loadcast_request("app=any,duration=-3", 41.0);
        assert_eq!(
            a.iteration_started(41.0, 4.0),
            None,
            "a negative duration is 0"
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const NO_LINES: &[&str] = &[];

    /// pFoo on community alpha, started at MOOS time 1000 with the given warp, no config.
    fn started(warp: f64) -> AppCasting {
        let mut app = AppCasting::new("pFoo");
        assert!(app.start_up(Some("alpha"), Some(NO_LINES), 1000.0, warp));
        app
    }

    #[test]
    fn constructor_defaults() {
        let app = AppCasting::new("pFoo");
        assert_eq!(app.proc_name(), "pFoo");
        assert_eq!(app.community(), "");
        assert_eq!(app.term_report_interval(), 0.5);
        assert_eq!(app.time_warp(), 1.0);
        assert_eq!(app.comms_policy(), CommsPolicy::Open);
        assert_eq!(app.app_logging(), AppLogging::Off);
        assert!(!app.deprecated_ok());
        assert_eq!(app.appcast().max_events(), 8);
        assert_eq!(app.appcast().max_run_warnings(), 10);
        assert_eq!(app.last_appcast_time(), None);
    }

    #[test]
    fn start_up_warnings_in_cpp_order() {
        let mut app = AppCasting::new("pFoo");
        let lines = [
            "MAX_APPCAST_EVENTS=x",
            "COMMS_POLICY=loose",
            "TERM_REPORT_INTERVAL=2",
        ];
        assert!(!app.start_up(None, Some(&lines[..]), 5.0, 0.0));
        assert_eq!(
            app.appcast().config_warnings(),
            [
                "Invalid comms_policy: loose",
                "XCommunity/Vehicle name not found in mission file",
                "Invalid MAX_APPCAST_EVENTS: x",
                "MOOSTimeWarp invalid: 0. Using 0.001 instead.",
            ]
        );
        assert_eq!(app.time_warp(), 0.001);
        assert_eq!(app.term_report_interval(), 2.0);
        assert_eq!(app.start_time(), 5.0);
        assert!(app.new_cfg_warning());

        let mut app = AppCasting::new("pFoo");
        assert!(!app.start_up(Some("alpha"), None::<&[&str]>, 0.0, -2.5));
        assert_eq!(
            app.appcast().config_warnings(),
            [
                "No mission config block found for pFoo",
                "MOOSTimeWarp invalid: -2.5. Using 0.001 instead.",
            ]
        );
        assert_eq!(app.community(), "alpha");

        let mut app = AppCasting::new("pFoo");
        assert!(app.start_up(Some("alpha"), Some(NO_LINES), 0.0, 10.0));
        assert!(app.appcast().config_warnings().is_empty());
        assert!(!app.new_cfg_warning());
    }

    #[test]
    fn config_keys_not_owned_are_left_to_the_app() {
        let mut app = AppCasting::new("pFoo");
        assert_eq!(app.consume_config_key("speed", "3"), None);
        assert_eq!(app.consume_config_key("APPTICK", "4"), None);
        assert_eq!(
            app.consume_config_key(" term_report_interval ", " 2 "),
            Some(Ok(()))
        );
        assert_eq!(app.term_report_interval(), 2.0);
    }

    #[test]
    fn term_report_interval_config_clip_and_numeric_test() {
        let mut app = AppCasting::new("pFoo");
        let k = "TERM_REPORT_INTERVAL";
        assert_eq!(app.consume_config_key(k, "-1"), Some(Ok(())));
        assert_eq!(app.term_report_interval(), 0.0);
        assert_eq!(app.consume_config_key(k, "20"), Some(Ok(())));
        assert_eq!(app.term_report_interval(), 10.0);
        assert_eq!(app.consume_config_key(k, "1e-1"), Some(Ok(())));
        assert_eq!(app.term_report_interval(), 0.1);
        // Numeric by character set, so "1.5.2" is accepted and reads as 1.5.
        assert_eq!(app.consume_config_key(k, "1.5.2"), Some(Ok(())));
        assert_eq!(app.term_report_interval(), 1.5);
        assert_eq!(
            app.consume_config_key(k, "fast"),
            Some(Err("Invalid TERM_REPORT_INTERVAL: fast".to_string()))
        );
        assert_eq!(app.term_report_interval(), 1.5);
        assert_eq!(
            app.appcast().config_warnings(),
            ["Invalid TERM_REPORT_INTERVAL: fast"]
        );
        assert!(app.new_cfg_warning());
    }

    #[test]
    fn term_report_interval_mail_has_a_floor_only() {
        let mut app = AppCasting::new("pFoo");
        app.on_term_report_interval(0.1);
        assert_eq!(app.term_report_interval(), 0.4);
        app.on_term_report_interval(-1.0);
        assert_eq!(app.term_report_interval(), 0.4);
        app.on_term_report_interval(100.0);
        assert_eq!(app.term_report_interval(), 100.0);
        app.on_term_report_interval(0.4);
        assert_eq!(app.term_report_interval(), 0.4);
    }

    #[test]
    fn max_appcast_events_clip() {
        let mut app = AppCasting::new("pFoo");
        let k = "max_appcast_events";
        assert_eq!(app.consume_config_key(k, "-3"), Some(Ok(())));
        assert_eq!(app.appcast().max_events(), 0);
        assert_eq!(app.consume_config_key(k, "99"), Some(Ok(())));
        assert_eq!(app.appcast().max_events(), 50);
        assert_eq!(app.consume_config_key(k, "12.9"), Some(Ok(())));
        assert_eq!(app.appcast().max_events(), 12);
        assert_eq!(
            app.consume_config_key(k, "ten"),
            Some(Err("Invalid MAX_APPCAST_EVENTS: ten".to_string()))
        );
        assert_eq!(app.appcast().max_events(), 12);
    }

    #[test]
    fn max_appcast_run_warnings_quirks() {
        let mut app = AppCasting::new("pFoo");
        let k = "MAX_APPCAST_RUN_WARNINGS";
        assert_eq!(app.consume_config_key(k, "-3"), Some(Ok(())));
        assert_eq!(app.appcast().max_run_warnings(), 0);
        assert_eq!(app.consume_config_key(k, "1000"), Some(Ok(())));
        assert_eq!(app.appcast().max_run_warnings(), 1000);
        // Above 1000 becomes 100, not 1000.
        assert_eq!(app.consume_config_key(k, "1001"), Some(Ok(())));
        assert_eq!(app.appcast().max_run_warnings(), 100);
        // The warning names the events parameter.
        assert_eq!(
            app.consume_config_key(k, "many"),
            Some(Err("Invalid MAX_APPCAST_EVENTS: many".to_string()))
        );
    }

    #[test]
    fn comms_policy_app_logging_deprecated_ok_config() {
        let mut app = AppCasting::new("pFoo");
        assert_eq!(app.consume_config_key("COMMS_POLICY", "LEAN"), Some(Ok(())));
        assert_eq!(app.comms_policy(), CommsPolicy::Lean);
        assert_eq!(
            app.consume_config_key("COMMS_POLICY", "Closed"),
            Some(Err("Invalid comms_policy: Closed".to_string()))
        );
        assert_eq!(app.comms_policy(), CommsPolicy::Lean);
        assert_eq!(app.consume_config_key("APP_LOGGING", "TRUE"), Some(Ok(())));
        assert_eq!(app.app_logging(), AppLogging::Log);
        assert_eq!(app.consume_config_key("app_logging", "file"), Some(Ok(())));
        assert_eq!(app.app_logging(), AppLogging::File);
        assert_eq!(app.consume_config_key("APP_LOGGING", "off"), Some(Ok(())));
        assert_eq!(app.app_logging(), AppLogging::Off);
        assert_eq!(
            app.consume_config_key("APP_LOGGING", "yes"),
            Some(Err("Invalid APP_LOGGING: yes".to_string()))
        );
        assert_eq!(
            app.consume_config_key("DEPRECATED_OK", "True"),
            Some(Ok(()))
        );
        assert!(app.deprecated_ok());
        assert_eq!(
            app.consume_config_key("DEPRECATED_OK", "1"),
            Some(Err("Invalid DEPRECATED_OK: 1".to_string()))
        );
        assert!(app.deprecated_ok());
        assert_eq!(app.appcast().config_warnings().len(), 3);
    }

    #[test]
    fn comms_policy_mail_never_laxer_than_config() {
        let mut app = AppCasting::new("pFoo");
        assert!(app.on_comms_policy("DIRE"));
        assert_eq!(app.comms_policy(), CommsPolicy::Dire);
        assert!(app.on_comms_policy("open"));
        assert_eq!(app.comms_policy(), CommsPolicy::Open);
        assert!(!app.on_comms_policy("Loose"));
        assert_eq!(
            app.appcast()
                .run_warnings()
                .get("Unhandled COMMS_POLICY:loose"),
            Some(&1)
        );

        let mut app = AppCasting::new("pFoo");
        let _ = app.consume_config_key("COMMS_POLICY", "lean");
        // open under lean: accepted, ignored, no warning.
        assert!(app.on_comms_policy("open"));
        assert_eq!(app.comms_policy(), CommsPolicy::Lean);
        assert!(app.on_comms_policy("dire"));
        assert_eq!(app.comms_policy(), CommsPolicy::Dire);
        assert!(app.on_comms_policy("lean"));
        assert_eq!(app.comms_policy(), CommsPolicy::Lean);
        assert_eq!(app.appcast().run_warning_total(), 0);

        let mut app = AppCasting::new("pFoo");
        let _ = app.consume_config_key("COMMS_POLICY", "dire");
        assert!(!app.on_comms_policy("lean"));
        assert!(app.on_comms_policy("open"));
        assert_eq!(app.comms_policy(), CommsPolicy::Dire);
        assert_eq!(
            app.appcast()
                .run_warnings()
                .get("Unhandled COMMS_POLICY:lean"),
            Some(&1)
        );
        assert!(app.new_run_warning());
    }

    #[test]
    fn request_matching_node_and_app() {
        let mut app = started(1.0);
        assert!(app.on_request("node=alpha,app=pFoo,duration=3,key=k1", 1001.0));
        assert!(app.on_request("node=all,app=all,duration=3,key=k2", 1001.0));
        assert!(app.on_request(" NODE = alpha , App=pFoo , Key = k3 ", 1001.0));
        assert!(!app.on_request("node=bravo,app=pFoo,duration=3,key=k4", 1001.0));
        assert!(!app.on_request("node=alpha,app=pBar,duration=3,key=k5", 1001.0));
        // Values are compared exactly.
        assert!(!app.on_request("node=ALPHA,app=pFoo,key=k6", 1001.0));
        assert!(!app.on_request("node=alpha,app=pfoo,key=k7", 1001.0));
        assert!(!app.on_request("node=alpha,app=ALL,key=k8", 1001.0));
        // The mismatch drops the request even after the key was read.
        assert!(!app.on_request("key=k9,duration=3,node=bravo", 1001.0));
        // No node / app pair at all: accepted.
        assert!(app.on_request("key=k10,duration=3", 1001.0));
        // No key or an empty one: dropped.
        assert!(!app.on_request("node=alpha,app=pFoo,duration=3", 1001.0));
        assert!(!app.on_request("node=alpha,app=pFoo,duration=3,key=", 1001.0));
        let keys: Vec<&str> = app.requests().keys().map(String::as_str).collect();
        assert_eq!(keys, ["k1", "k10", "k2", "k3"]);
        assert_eq!(app.requests()["k3"].duration, 0.0);
        assert_eq!(app.requests()["k3"].thresh, "any");
        assert_eq!(app.requests()["k1"].start, 1001.0);
    }

    #[test]
    fn request_duration_clip_and_atof() {
        let mut app = started(1.0);
        let d = |app: &mut AppCasting, v: &str| {
            assert!(app.on_request(&format!("node=all,app=all,key=k,duration={v}"), 0.0));
            app.requests()["k"].duration
        };
        assert_eq!(d(&mut app, "-5"), 0.0);
        assert_eq!(d(&mut app, "45"), 30.0);
        assert_eq!(d(&mut app, "3.0"), 3.0);
        assert_eq!(d(&mut app, "2.5s"), 2.5);
        assert_eq!(d(&mut app, "abc"), 0.0);
        assert_eq!(d(&mut app, "inf"), 30.0);
        assert!(d(&mut app, "nan").is_nan());
    }

    #[test]
    fn later_request_with_same_key_replaces_the_earlier() {
        let mut app = started(1.0);
        assert!(app.on_request("node=all,app=all,duration=10,key=k,thresh=any", 1000.0));
        assert!(app.on_request(
            "node=all,app=all,duration=2,key=k,thresh=run_warning",
            1005.0
        ));
        assert_eq!(app.requests().len(), 1);
        assert_eq!(
            app.requests()["k"],
            Request {
                duration: 2.0,
                start: 1005.0,
                thresh: "run_warning".to_string()
            }
        );
    }

    #[test]
    fn pending_by_request_age_is_strict_and_in_moos_time() {
        let mut app = started(10.0);
        assert!(!app.appcast_requested(1000.0));
        assert!(app.on_request("node=alpha,app=pFoo,duration=3,key=uMAC", 1000.0));
        assert!(app.appcast_requested(1000.0));
        assert!(app.appcast_requested(1002.999));
        // 3 MOOS seconds, whatever the warp: elapsed == duration is expired.
        assert!(!app.appcast_requested(1003.0));
        // A zero-duration request is never live.
        assert!(app.on_request("node=alpha,app=pFoo,duration=0,key=uMAC", 1000.0));
        assert!(!app.appcast_requested(1000.0));
    }

    #[test]
    fn thresh_run_warning_needs_a_new_run_warning() {
        let mut app = started(1.0);
        assert!(app.on_request(
            "node=all,app=all,duration=5,key=k,thresh=run_warning",
            1000.0
        ));
        assert!(!app.appcast_requested(1001.0));
        app.report_run_warning("low battery");
        assert!(app.appcast_requested(1001.0));
        let _ = app.build(3, "", 1001.0);
        assert!(!app.appcast_requested(1001.5));
        // An unknown thresh never triggers, even with a new run warning.
        assert!(app.on_request("node=all,app=all,duration=5,key=k,thresh=Any", 1002.0));
        app.report_run_warning("again");
        assert!(!app.appcast_requested(1002.0));
    }

    #[test]
    fn new_config_warning_is_pending_without_any_request() {
        let mut app = started(1.0);
        app.report_config_warning("");
        assert!(!app.appcast_requested(1000.0));
        app.report_config_warning("bad param");
        assert!(app.appcast_requested(1000.0));
        assert!(app.due(1000.0, 10));
        let _ = app.build(10, "", 1000.0);
        assert!(!app.new_cfg_warning());
        assert!(!app.due(1010.0, 11));
    }

    #[test]
    fn first_iteration_is_always_pending() {
        let app = started(1.0);
        assert!(app.due(1000.0, 0));
        assert!(app.due(1000.0, 1));
        assert!(!app.due(1000.0, 2));
    }

    #[test]
    fn rate_limit_is_real_time() {
        let mut app = started(10.0);
        assert!(app.on_request("node=all,app=all,duration=30,key=k", 1000.0));
        assert!(app.due(1000.0, 1));
        let _ = app.build(1, "", 1000.0);
        assert_eq!(app.last_appcast_time(), Some(1000.0));
        // Warp 10: 4.9 MOOS seconds are 0.49 real seconds, under the 0.5 s interval.
        assert!(!app.due(1004.9, 2));
        assert!(app.due(1005.0, 2));
        // Even iteration 1 waits for the interval once something was posted.
        assert!(!app.due(1001.0, 1));

        let mut app = started(1.0);
        let _ = app.consume_config_key("TERM_REPORT_INTERVAL", "0");
        assert!(app.on_request("node=all,app=all,duration=30,key=k", 1000.0));
        let _ = app.build(1, "", 1000.0);
        assert!(app.due(1000.0, 2));
    }

    #[test]
    fn rate_limit_nan_interval_or_warp_never_holds_back() {
        let mut app = started(1.0);
        app.on_term_report_interval(f64::NAN);
        assert!(app.on_request("node=all,app=all,duration=30,key=k", 1000.0));
        let _ = app.build(1, "", 1000.0);
        assert!(app.due(1000.0, 2));
        // A NaN warp passes the `<= 0` test, as in C++.
        let mut app = AppCasting::new("pFoo");
        assert!(app.start_up(Some("alpha"), Some(NO_LINES), 0.0, f64::NAN));
        let _ = app.build(1, "", 0.0);
        assert!(!app.due(0.1, 2));
        assert!(app.on_request("key=k,duration=5", 0.1));
        assert!(app.due(0.1, 2));
    }

    #[test]
    fn build_returns_the_appcast_and_resets_the_flags() {
        let mut app = started(1.0);
        app.report_run_warning("w");
        app.report_config_warning("c");
        app.report_event("go", 1012.345);
        let s = app.build(4, "line1\nline2", 1013.0);
        assert_eq!(
            s,
            concat!(
                "proc=pFoo!@#iter=4!@#node=alpha!@#iter=4!@#messages=line1!@line2!@!@#",
                "config_warnings=c!@#events_total=1!@#events=[12.35]: go!@#",
                "run_warning_total=1!@#run_warnings=1:w"
            )
        );
        assert!(!app.new_run_warning());
        assert!(!app.new_cfg_warning());
        assert_eq!(app.appcast().iteration(), 4);
        assert_eq!(app.appcast().messages(), "line1\nline2");
    }

    #[test]
    fn events_are_stamped_from_start_up() {
        let mut app = started(1.0);
        app.report_event("a", 1002.5);
        app.report_event("early", 999.0);
        app.report_event("zero", 1000.0);
        assert_eq!(
            app.appcast().events().collect::<Vec<_>>(),
            ["[2.50]: a", "early", "[0.00]: zero"]
        );
    }

    #[test]
    fn run_warnings_and_retraction() {
        let mut app = started(1.0);
        app.report_run_warning("");
        assert!(!app.new_run_warning());
        assert_eq!(app.warning_count(WarningFilter::Run), 0);
        // Retracting with no run warnings at all does nothing.
        app.retract_run_warning("x");
        assert!(!app.new_run_warning());
        app.report_run_warning("x");
        app.report_run_warning("x");
        app.report_config_warning("c");
        assert_eq!(app.warning_count(WarningFilter::Run), 2);
        assert_eq!(app.warning_count(WarningFilter::Config), 1);
        assert_eq!(app.warning_count(WarningFilter::All), 3);
        let _ = app.build(2, "", 1000.0);
        app.retract_run_warning("y");
        assert!(!app.new_run_warning());
        app.retract_run_warning("x");
        assert!(app.new_run_warning());
        assert_eq!(app.warning_count(WarningFilter::Run), 0);
    }

    #[test]
    fn run_warning_cap_from_config() {
        let mut app = AppCasting::new("pFoo");
        let lines = ["MAX_APPCAST_RUN_WARNINGS=1"];
        assert!(app.start_up(Some("alpha"), Some(&lines[..]), 0.0, 1.0));
        app.report_run_warning("a");
        app.report_run_warning("b");
        app.report_run_warning("a");
        assert_eq!(app.appcast().run_warnings().get("a"), Some(&1));
        assert_eq!(
            app.appcast().run_warnings().get("Other Run Warnings"),
            Some(&2)
        );
        assert_eq!(app.appcast().run_warning_total(), 3);
    }

    #[test]
    fn unhandled_config_warning_text_and_exemptions() {
        let mut app = AppCasting::new("pFoo");
        app.report_unhandled_config_warning("");
        for exempt in [
            "AppTick=4",
            "MAXAPPTICK = 10",
            "commstick=4",
            "APP_LOGGING=log",
            "TERM_REPORT_INTERVAL=1",
            "MAX_APPCAST_EVENTS=5",
            "DEPRECATED_OK=true",
        ] {
            app.report_unhandled_config_warning(exempt);
        }
        assert!(app.appcast().config_warnings().is_empty());
        app.report_unhandled_config_warning("foo = bar");
        app.report_unhandled_config_warning("MAX_APPCAST_RUN_WARNINGS=3");
        app.report_unhandled_config_warning("COMMS_POLICY=lean");
        assert_eq!(
            app.appcast().config_warnings(),
            [
                "Unhandled config line: foo = bar",
                "Unhandled config line: MAX_APPCAST_RUN_WARNINGS=3",
                "Unhandled config line: COMMS_POLICY=lean",
            ]
        );
        assert!(app.new_cfg_warning());
    }

    #[test]
    fn node_request_variable_is_upper_case() {
        assert_eq!(node_request_var("henry"), "APPCAST_REQ_HENRY");
        assert_eq!(node_request_var("abe_2"), "APPCAST_REQ_ABE_2");
    }
}
