//! The built-in uTimerScript: posts scripted values at scripted times (reference
//! `moos-apps-extra.md` §1).
//!
//! Supported: `event` (var/val/time, time ranges, `amt` with `$(IDX)`, `quit`),
//! `script_name`, `script_atomic`, `paused`, `pause_var`, `reset_var`, `forward_var`,
//! `status_var`, `reset_max`, `reset_time`, `condition` (mission-crate conditions),
//! `upon_awake`, `delay_start`, `delay_reset`, `time_warp`, `rand_var` (uniform, and
//! gaussian/normal as MOOS's `RandVarGaussian`: `mu + MOOSWhiteNoise(sigma)` by the polar
//! Box-Muller method on the seeded generator, snapped, clamped to `[min, max]`, expanded
//! with 5 decimals; its bad specs are config warnings with the C++'s words),
//! `block_on`, `shuffle`, `time_zero`, and the post-time macros (`$(COUNT)`, `$(TCOUNT)`,
//! `$(DBTIME)`, `$(UTCTIME)`, `$[NAV_X]`, `$[VNAME]`, `$(1)`..`$(20)`, rand vars,
//! `{a op b}` math). Not supported: `rand_pair` (refused with an error naming the line).
//! Random draws come from a seeded generator, so a lockstep run is repeatable.
//!
//! Like MOOS, every config value has its white space removed before it is read.

use std::collections::HashMap;

use mission::condition::{self, Condition, parse_condition};
use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::ProcessConfig;
use thiserror::Error;

use crate::antler::BuiltInApp;
use crate::app::{App, Mail, Post, Subscription, Value};
use crate::appcasting::AppcastLayer;
use moos_types::text::set_boolean_on_string;

/// A config line uTimerScript cannot use.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{file}:{line}: uTimerScript: {message}")]
pub struct TimerScriptError {
    /// File of the line.
    pub file: String,
    /// Line number.
    pub line: u32,
    /// What is wrong.
    pub message: String,
}

/// A uniform draw between `min` and `max` (equal for a fixed value).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Range {
    min: f64,
    max: f64,
}

impl Range {
    fn fixed(x: f64) -> Self {
        Range { min: x, max: x }
    }

    fn parse(s: &str, positive: bool) -> Result<Range, String> {
        let num = |t: &str| {
            t.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("{t:?} is not a number"))
        };
        let r = match s.split_once(':') {
            Some((a, b)) => Range {
                min: num(a)?,
                max: num(b)?,
            },
            None => Range::fixed(num(s)?),
        };
        if r.min > r.max {
            return Err(format!("range {s:?}: min is above max"));
        }
        if positive && r.min <= 0.0 {
            return Err(format!("{s:?} must be > 0"));
        }
        if !positive && r.min < 0.0 {
            return Err(format!("{s:?} must be >= 0"));
        }
        Ok(r)
    }

    /// MOOS's draw: `min + (rand()%10000)/10000 * (max-min)`.
    fn draw(&self, rng: &mut fastrand::Rng) -> f64 {
        if self.min == self.max {
            self.min
        } else {
            self.min + f64::from(rng.u32(0..10000)) / 10000.0 * (self.max - self.min)
        }
    }
}

/// An event's value as configured.
#[derive(Debug, Clone, PartialEq)]
enum EventValue {
    Double(f64),
    /// Text; `quoted` values stay strings even if they expand to a number.
    Text {
        text: String,
        quoted: bool,
    },
}

#[derive(Debug, Clone, PartialEq)]
struct Event {
    var: String,
    value: EventValue,
    time: Range,
    quit: bool,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum UponAwake {
    None,
    Reset,
    Restart,
}

impl UponAwake {
    fn as_str(self) -> &'static str {
        match self {
            UponAwake::None => "n/a",
            UponAwake::Reset => "reset",
            UponAwake::Restart => "restart",
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum RandKey {
    Start,
    Reset,
    Post,
}

/// How a random variable draws.
#[derive(Debug, Clone, Copy, PartialEq)]
enum RandKind {
    /// MOOS `RandVarUniform`: `min + (rand()%10000)/10000 * (max-min)`, posted with 3 decimals.
    Uniform,
    /// MOOS `RandVarGaussian`: `mu + MOOSWhiteNoise(sigma)`, snapped, clamped to
    /// `[min, max]`, posted with 5 decimals.
    Gaussian { mu: f64, sigma: f64 },
}

#[derive(Debug, Clone, PartialEq)]
struct RandVar {
    name: String,
    min: f64,
    max: f64,
    snap: f64,
    key: RandKey,
    kind: RandKind,
    value: f64,
}

/// MOOS `MOOSWhiteNoise(sigma)`: the polar Box-Muller method on uniform draws in `[0, 1]`,
/// making two normal deviates at a time; the second is kept in `spare` (the C++ keeps it in a
/// static, one per process: here one per uTimerScript) and returned, scaled by that call's
/// `sigma`, at the next call. A pair on the unit circle's centre (`s = 0`, where the C++
/// would take the logarithm of 0) is drawn again.
fn white_noise(rng: &mut fastrand::Rng, spare: &mut Option<f64>, sigma: f64) -> f64 {
    if let Some(g) = spare.take() {
        return g * sigma;
    }
    loop {
        let v1 = 2.0 * rng.f64() - 1.0;
        let v2 = 2.0 * rng.f64() - 1.0;
        let s = v1 * v1 + v2 * v2;
        if s > 1.0 || s == 0.0 {
            continue;
        }
        let fac = (-2.0 * s.ln() / s).sqrt();
        *spare = Some(v1 * fac);
        return v2 * fac * sigma;
    }
}

impl RandVar {
    fn draw(&mut self, rng: &mut fastrand::Rng, spare: &mut Option<f64>) {
        match self.kind {
            RandKind::Uniform => {
                let v = Range {
                    min: self.min,
                    max: self.max,
                }
                .draw(rng);
                let v = if self.snap > 0.0 {
                    (v / self.snap).round() * self.snap
                } else {
                    v
                };
                self.value = v.clamp(self.min, self.max);
            }
            RandKind::Gaussian { mu, sigma } => {
                let mut v =
                    geometry::point::snap_to_step(mu + white_noise(rng, spare, sigma), self.snap);
                // The C++ clamps to the maximum first, then to the minimum.
                if v > self.max {
                    v = self.max;
                }
                if v < self.min {
                    v = self.min;
                }
                self.value = v;
            }
        }
    }

    /// The value as its macros expand (MOOS `getStringValue`): `doubleToStringX` with 3
    /// decimals for a uniform variable, 5 for a gaussian one.
    fn text(&self) -> String {
        match self.kind {
            RandKind::Uniform => fmt_x(self.value, 3),
            RandKind::Gaussian { .. } => fmt_x(self.value, 5),
        }
    }
}

/// Splits on commas outside `"..."` and `{...}` (MOOS `parseStringQ`).
fn split_q(s: &str) -> Vec<&str> {
    let mut out = Vec::new();
    let (mut quote, mut depth, mut start) = (false, 0i32, 0);
    for (i, c) in s.char_indices() {
        match c {
            '"' => quote = !quote,
            '{' if !quote => depth += 1,
            '}' if !quote => depth -= 1,
            ',' if !quote && depth <= 0 => {
                out.push(&s[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    out.push(&s[start..]);
    out
}

/// `doubleToStringX`: `decimals` places, trailing zeros and point removed.
fn fmt_x(x: f64, decimals: usize) -> String {
    let s = format!("{x:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if s == "-0" { "0".to_string() } else { s }
}

/// The built-in uTimerScript app.
pub struct TimerScript {
    name: String,
    block: Option<ProcessConfig>,
    community: String,
    rng: fastrand::Rng,
    // configuration
    events: Vec<Event>,
    script_name: String,
    atomic: bool,
    pause_var: String,
    reset_var: String,
    forward_var: String,
    status_var: String,
    reset_max: Option<u32>,
    reset_time: f64,
    upon_awake: UponAwake,
    delay_start: Range,
    delay_reset: Range,
    time_warp: Range,
    rand_vars: Vec<RandVar>,
    /// MOOSWhiteNoise's second normal deviate, kept for the next gaussian draw.
    gauss_spare: Option<f64>,
    conditions: Vec<Condition>,
    block_on: Vec<String>,
    shuffle: bool,
    time_zero_db: bool,
    needs_nav: bool,
    warnings: Vec<Diagnostic>,
    /// Messages of the line being read that it ignores (located into `warnings`).
    ignored: Vec<String>,
    // state
    paused: bool,
    conditions_ok: bool,
    info: HashMap<String, Value>,
    ptimes: Vec<f64>,
    posted: Vec<bool>,
    posted_local: usize,
    posted_total: usize,
    reset_count: u32,
    script_start: Option<f64>,
    previous_time: Option<f64>,
    pause_time: f64,
    skip_time: f64,
    elapsed: f64,
    warp_value: f64,
    delay_start_value: f64,
    delay_reset_value: f64,
    status_needed: bool,
    last_status: Option<f64>,
    db_start: Option<f64>,
    started_at: f64,
    nav_x: Option<f64>,
    nav_y: Option<f64>,
    quit_sent: bool,
    finished: bool,
    /// AppCastingMOOSApp around the script (`None` only while its report is written).
    appcast: Option<AppcastLayer>,
    /// The latest postings, for the appcast (newest last).
    event_log: std::collections::VecDeque<String>,
}

/// Postings the appcast lists.
const EVENT_LOG_LEN: usize = 20;

impl BuiltInApp for TimerScript {
    /// Config lines ignored as MOOS ignores them (with a warning), each at its line.
    fn warnings(&self) -> &[Diagnostic] {
        &self.warnings
    }

    /// Sets the mission's `Community` and `MOOSTimeWarp` for the script's appcasts (the node
    /// name, the real-time rate limit); the block's appcasting keys are read again with them.
    fn with_appcast_globals(mut self, community: Option<&str>, warp: f64) -> Self {
        if let Some(block) = &self.block {
            self.appcast = Some(AppcastLayer::with_config_warnings(
                &self.name,
                block,
                community,
                warp,
                &self.warnings,
            ));
        }
        self
    }
}

impl TimerScript {
    /// Reads a uTimerScript block. `name` is the MOOS name (alias), `community` the
    /// mission's community (for `$[VNAME]`), `seed` seeds the random draws.
    pub fn new(
        name: &str,
        block: ProcessConfig,
        community: &str,
        seed: u64,
    ) -> Result<TimerScript, TimerScriptError> {
        let mut ts = TimerScript {
            name: name.to_string(),
            block: None,
            community: community.to_string(),
            rng: fastrand::Rng::with_seed(seed),
            events: Vec::new(),
            script_name: "unnamed".into(),
            atomic: false,
            pause_var: "UTS_PAUSE".into(),
            reset_var: "UTS_RESET".into(),
            forward_var: "UTS_FORWARD".into(),
            status_var: "UTS_STATUS".into(),
            reset_max: None,
            reset_time: -1.0,
            upon_awake: UponAwake::None,
            delay_start: Range::fixed(0.0),
            delay_reset: Range::fixed(0.0),
            time_warp: Range::fixed(1.0),
            rand_vars: Vec::new(),
            gauss_spare: None,
            conditions: Vec::new(),
            block_on: Vec::new(),
            shuffle: true,
            time_zero_db: false,
            needs_nav: false,
            warnings: Vec::new(),
            ignored: Vec::new(),
            paused: false,
            conditions_ok: true,
            info: HashMap::new(),
            ptimes: Vec::new(),
            posted: Vec::new(),
            posted_local: 0,
            posted_total: 0,
            reset_count: 0,
            script_start: None,
            previous_time: None,
            pause_time: 0.0,
            skip_time: 0.0,
            elapsed: 0.0,
            warp_value: 1.0,
            delay_start_value: 0.0,
            delay_reset_value: 0.0,
            status_needed: false,
            last_status: None,
            db_start: None,
            started_at: 0.0,
            nav_x: None,
            nav_y: None,
            quit_sent: false,
            finished: false,
            appcast: None,
            event_log: std::collections::VecDeque::new(),
        };
        for p in &block.entries {
            let v: String = p.value.chars().filter(|c| !c.is_whitespace()).collect();
            let before = ts.ignored.len();
            let r = ts.configure(&p.key.to_ascii_lowercase(), &v);
            for w in ts.ignored.drain(before..) {
                ts.warnings.push(Diagnostic::line_warning(
                    DiagnosticKind::AppSetting,
                    &p.span,
                    w,
                ));
            }
            r.map_err(|message| TimerScriptError {
                file: p.span.file_name().to_string(),
                line: p.line(),
                message,
            })?;
        }
        ts.conditions_ok = ts.conditions.is_empty();
        ts.appcast = Some(AppcastLayer::with_config_warnings(
            name,
            &block,
            None,
            1.0,
            &ts.warnings,
        ));
        ts.block = Some(block);
        Ok(ts)
    }

    fn configure(&mut self, key: &str, v: &str) -> Result<(), String> {
        match key {
            "event" => self.add_event(v)?,
            "script_name" => self.script_name = v.to_string(),
            "script_atomic" => {
                self.atomic = set_boolean_on_string(self.atomic, v).unwrap_or(self.atomic)
            }
            "paused" => self.paused = set_boolean_on_string(self.paused, v).unwrap_or(self.paused),
            "pause_var" | "pause_variable" => self.pause_var = v.to_string(),
            "reset_var" | "reset_variable" => self.reset_var = v.to_string(),
            "forward_var" | "forward_variable" => self.forward_var = v.to_string(),
            "status_var" => self.status_var = v.to_string(),
            "reset_max" => {
                match v.to_ascii_lowercase().as_str() {
                    "any" | "unlimited" | "nolimit" => self.reset_max = None,
                    n => match n.parse::<u32>() {
                        Ok(n) => self.reset_max = Some(n),
                        // MOOS ignores the line with a config warning.
                        Err(_) => self.ignored.push(format!(
                            "reset_max {v:?} ignored: expected a count or any/unlimited/nolimit"
                        )),
                    },
                }
            }
            "reset_time" => {
                self.reset_time = match v.to_ascii_lowercase().as_str() {
                    "none" => -1.0,
                    "end" | "all-posted" => 0.0,
                    n => match n.parse::<f64>() {
                        Ok(x) if x > 0.0 && x.is_finite() => x,
                        _ => {
                            return Err(format!(
                                "reset_time {v:?}: expected none, end, all-posted or seconds > 0"
                            ));
                        }
                    },
                }
            }
            "upon_awake" => {
                self.upon_awake = match v.to_ascii_lowercase().as_str() {
                    "reset" => UponAwake::Reset,
                    "restart" => UponAwake::Restart,
                    "n/a" | "none" | "" => UponAwake::None,
                    _ => {
                        self.ignored.push(format!(
                            "upon_awake {v:?} ignored: expected reset or restart"
                        ));
                        self.upon_awake
                    }
                }
            }
            "delay_start" => self.delay_start = Range::parse(v, false)?,
            "delay_reset" => self.delay_reset = Range::parse(v, false)?,
            "time_warp" => self.time_warp = Range::parse(v, true)?,
            "rand_var" | "randvar" => self.add_rand_var(v)?,
            "rand_pair" | "randpair" => return Err("rand_pair is not supported by coug".into()),
            "condition" => {
                let c = parse_condition(v)
                    .map_err(|e| format!("condition {v:?}: expected {}", e.expected))?;
                self.conditions.push(c);
            }
            "block_on" => self
                .block_on
                .extend(v.split(',').filter(|s| !s.is_empty()).map(String::from)),
            "shuffle" => {
                self.shuffle = set_boolean_on_string(self.shuffle, v).unwrap_or(self.shuffle)
            }
            "time_zero" => self.time_zero_db = v.eq_ignore_ascii_case("db_start"),
            _ => {}
        }
        Ok(())
    }

    fn add_event(&mut self, spec: &str) -> Result<(), String> {
        let mut var = None;
        let mut value = None;
        let mut time = Range::fixed(0.0);
        let mut amt = 1usize;
        let mut quit = false;
        for piece in split_q(spec) {
            if piece.eq_ignore_ascii_case("quit") {
                quit = true;
                continue;
            }
            let Some((k, val)) = piece.split_once('=') else {
                return Err(format!("event piece {piece:?}: expected key=value"));
            };
            match k.to_ascii_lowercase().as_str() {
                "var" => var = Some(val.to_string()),
                "val" => {
                    value = Some(
                        if val.len() >= 2 && val.starts_with('"') && val.ends_with('"') {
                            EventValue::Text {
                                text: val[1..val.len() - 1].to_string(),
                                quoted: true,
                            }
                        } else if condition::is_numeric(val) {
                            EventValue::Double(val.parse::<f64>().unwrap_or(0.0))
                        } else {
                            EventValue::Text {
                                text: val.to_string(),
                                quoted: false,
                            }
                        },
                    )
                }
                "time" => time = Range::parse(val, false)?,
                "amt" => {
                    amt = val
                        .parse::<usize>()
                        .ok()
                        .filter(|n| (1..=10_000).contains(n))
                        .ok_or_else(|| format!("amt {val:?}: expected a count 1..10000"))?
                }
                other => return Err(format!("event: unknown field {other:?}")),
            }
        }
        let (var, value) = if quit {
            (
                "EXITED_NORMALLY".to_string(),
                EventValue::Text {
                    text: self.name.clone(),
                    quoted: true,
                },
            )
        } else {
            let var = var
                .filter(|v| !v.is_empty())
                .ok_or_else(|| format!("event {spec:?}: no var="))?;
            let value = value.ok_or_else(|| format!("event {spec:?}: no val="))?;
            (var, value)
        };
        for _ in 0..amt {
            let idx = format!("{:03}", self.events.len());
            let value = match &value {
                EventValue::Text { text, quoted } => {
                    if text.contains("NAV_X") || text.contains("NAV_Y") {
                        self.needs_nav = true;
                    }
                    EventValue::Text {
                        text: text
                            .replace("$(IDX)", &idx)
                            .replace("$[IDX]", &idx)
                            .replace("$$IDX", &idx),
                        quoted: *quoted,
                    }
                }
                d => d.clone(),
            };
            self.events.push(Event {
                var: var.clone(),
                value,
                time,
                quit,
            });
        }
        self.ptimes.resize(self.events.len(), -1.0);
        self.posted.resize(self.events.len(), false);
        Ok(())
    }

    fn add_rand_var(&mut self, spec: &str) -> Result<(), String> {
        // MOOS `RandomVariableSet::addRandomVar`: the type picks the parser; a gaussian
        // variable's problems, and an unknown type, are config warnings (the line ignored).
        match moos_types::text::tok_string_parse(spec, "type") {
            "" | "uniform" => {}
            "gaussian" | "normal" => {
                if let Err(why) = self.add_gaussian(spec) {
                    self.ignored
                        .push(format!("Rand variable problem: {spec}:{why}"));
                }
                return Ok(());
            }
            t => {
                self.ignored.push(format!(
                    "Rand variable problem: {spec}:unknown random variable type: {t}"
                ));
                return Ok(());
            }
        }
        let mut rv = RandVar {
            name: String::new(),
            min: 0.0,
            max: 0.0,
            snap: 0.001,
            key: RandKey::Start,
            kind: RandKind::Uniform,
            value: 0.0,
        };
        let num = |k: &str, v: &str| {
            v.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| format!("rand_var {k}={v:?}: not a number"))
        };
        for piece in split_q(spec) {
            let (k, v) = piece.split_once('=').unwrap_or((piece, ""));
            match k.to_ascii_lowercase().as_str() {
                "varname" => rv.name = v.to_string(),
                "min" => rv.min = num(k, v)?,
                "max" => rv.max = num(k, v)?,
                "snap" => rv.snap = num(k, v)?,
                "key" => {
                    rv.key = match v.to_ascii_lowercase().as_str() {
                        "at_start" => RandKey::Start,
                        "at_reset" => RandKey::Reset,
                        "at_post" => RandKey::Post,
                        _ => {
                            return Err(format!(
                                "rand_var key {v:?}: expected at_start/at_reset/at_post"
                            ));
                        }
                    }
                }
                "type" => {}
                _ => return Err(format!("rand_var: unknown field {k:?}")),
            }
        }
        if rv.name.is_empty() || rv.min > rv.max {
            return Err(format!("rand_var {spec:?}: needs varname and min <= max"));
        }
        self.rand_vars.push(rv);
        Ok(())
    }

    /// A gaussian `rand_var` (MOOS `addRandomVarGaussian`): `varname`, `key`, `min`, `max`,
    /// `mu` and `sigma` all needed, `snap` optional (used when > 0); `Err` with the C++'s
    /// words.
    fn add_gaussian(&mut self, spec: &str) -> Result<(), String> {
        let (mut name, mut key) = (String::new(), String::new());
        let (mut min, mut max, mut mu, mut sigma) = (None, None, None, None);
        let mut snap = -1.0;
        for piece in moos_types::text::parse_string(spec, ',') {
            let (left, right) = piece.split_once('=').unwrap_or((piece, ""));
            let (left, right) = (left.trim(), right.trim());
            let num = moos_types::text::is_number(right).then(|| geometry::atof(right));
            match (left, num) {
                ("varname", _) => name = right.to_string(),
                ("key", _) => key = right.to_ascii_lowercase(),
                ("min", Some(x)) => min = Some(x),
                ("max", Some(x)) => max = Some(x),
                ("snap", Some(x)) => snap = x,
                ("mu", Some(x)) => mu = Some(x),
                ("sigma", Some(x)) => sigma = Some(x),
                ("type", _) => {}
                _ => return Err(format!("Bad parameterx=value: {left}={right}")),
            }
        }
        let key = match key.as_str() {
            "" => return Err("key is not specified".into()),
            "at_start" => RandKey::Start,
            "at_reset" => RandKey::Reset,
            "at_post" => RandKey::Post,
            k => return Err(format!("unknown random_var key: {k}")),
        };
        if name.is_empty() {
            return Err("Unset variable name".into());
        }
        let min = min.ok_or("Lower value of the range not set")?;
        let max = max.ok_or("Upper value of the range not set")?;
        let mu = mu.ok_or("Mu not set")?;
        let sigma = sigma.ok_or("Sigma not set")?;
        if min > max {
            return Err("Minimum value greater than maximum value".into());
        }
        if self.rand_vars.iter().any(|r| r.name == name) {
            return Err("Duplicate random variable".into());
        }
        self.rand_vars.push(RandVar {
            name,
            min,
            max,
            snap: if snap > 0.0 { snap } else { 0.001 },
            key,
            kind: RandKind::Gaussian { mu, sigma },
            value: 0.0,
        });
        Ok(())
    }

    /// The appcast report: the script's state, what holds it, its random variables and its
    /// latest postings (the content uTimerScript's report shows).
    fn appcast_body(&self, out: &mut String) {
        use std::fmt::Write as _;
        let resets = match self.reset_max {
            None => "any".to_string(),
            Some(m) => m.to_string(),
        };
        let _ = writeln!(out, "Script: {}", self.script_name);
        let _ = writeln!(
            out,
            "     Elements: {}({})",
            self.events.len(),
            self.posted_local
        );
        let _ = writeln!(out, "      Reinits: {}", self.reset_count);
        let _ = writeln!(out, "    Time Warp: {}", fmt_x(self.warp_value, 2));
        let _ = writeln!(out, "  Delay Start: {}", fmt_x(self.delay_start_value, 2));
        let _ = writeln!(out, "  Delay Reset: {}", fmt_x(self.delay_reset_value, 2));
        let _ = writeln!(out, "    Reset Max: {resets}");
        let _ = writeln!(out, "      Elapsed: {:.2}\n", self.elapsed);
        let blocking = if self.block_on.is_empty() {
            "(ok) no blocking apps".to_string()
        } else {
            self.block_on.join(",")
        };
        let _ = writeln!(out, "Run criteria:");
        let _ = writeln!(out, "   Block Apps: {blocking}");
        let _ = writeln!(
            out,
            "       Paused: {}",
            if self.paused {
                "true"
            } else {
                "(ok) Not paused"
            }
        );
        let _ = writeln!(
            out,
            " ConditionsOK: {}\n",
            if self.conditions_ok {
                "(ok) No un-met conditions"
            } else {
                "false - there are un-met conditions"
            }
        );
        let mut t = appcast::Table::new(4);
        t.push("RandomVar | Min | Max | Value");
        t.add_header_lines();
        if self.rand_vars.is_empty() {
            t.push("None");
            t.push("");
            t.push("");
            t.push("");
        }
        for rv in &self.rand_vars {
            t.push(&rv.name);
            t.push(&fmt_x(rv.min, 6));
            t.push(&fmt_x(rv.max, 6));
            t.push(&fmt_x(rv.value, 6));
        }
        t.write(out);
        out.push_str("\n\nP/Tot  P/Loc  T/Total   T/Local  Variable/Var\n");
        out.push_str("-----  -----  --------  -------  ------------\n");
        for line in &self.event_log {
            out.push_str(line);
            out.push('\n');
        }
    }

    /// The number of events (after `amt` cloning).
    pub fn event_count(&self) -> usize {
        self.events.len()
    }

    fn handle_reset(&mut self) {
        if let Some(max) = self.reset_max
            && self.reset_count >= max
        {
            return;
        }
        self.reset_count += 1;
        self.script_start = None;
        self.status_needed = true;
    }

    fn handle_restart(&mut self) {
        self.reset_count = 0;
        self.script_start = None;
        self.status_needed = true;
    }

    fn schedule_events(&mut self) {
        let redraw = self.shuffle || self.ptimes.iter().any(|t| *t < 0.0);
        if redraw {
            for (i, e) in self.events.iter().enumerate() {
                self.ptimes[i] = e.time.draw(&mut self.rng);
            }
        }
        self.warp_value = self.time_warp.draw(&mut self.rng);
        self.delay_start_value = self.delay_start.draw(&mut self.rng);
        self.delay_reset_value = self.delay_reset.draw(&mut self.rng);
        for rv in &mut self.rand_vars {
            if rv.key != RandKey::Start {
                rv.draw(&mut self.rng, &mut self.gauss_spare);
            }
        }
        self.elapsed = 0.0;
        self.skip_time = 0.0;
        self.pause_time = 0.0;
        self.posted_local = 0;
        self.previous_time = None;
        self.posted.iter_mut().for_each(|p| *p = false);
    }

    fn conditions_hold(&self) -> bool {
        let lookup = |name: &str| -> Option<condition::Value<'_>> {
            match self.info.get(name)? {
                Value::Double(x) => Some(condition::Value::Double(*x)),
                Value::String(s) => Some(condition::Value::String(s)),
                Value::Binary(_) => None,
            }
        };
        self.conditions.iter().all(|c| c.evaluate(&lookup))
    }

    fn status_text(&self) -> String {
        let resets = match self.reset_max {
            None => format!("{}/any", self.reset_count),
            Some(m) => format!("{}/{m}", self.reset_count),
        };
        format!(
            "name={}, elapsed_time={:.2}, posted={}, pending={}, paused={}, conditions_ok={}, \
             time_warp={}, delay_start={}, delay_reset={}, shuffle={}, upon_awake={}, resets={}",
            self.script_name,
            self.elapsed,
            self.posted_local,
            self.events.len() - self.posted_local,
            self.paused,
            self.conditions_ok,
            fmt_x(self.warp_value, 5),
            fmt_x(self.delay_start_value, 5),
            fmt_x(self.delay_reset_value, 5),
            self.shuffle,
            self.upon_awake.as_str(),
            resets
        )
    }

    fn db_time(&self, now: f64) -> f64 {
        now - self.db_start.unwrap_or(self.started_at)
    }

    /// Expands post-time macros and math in `text`.
    fn expand(&mut self, text: &str, now: f64) -> String {
        let mut s = text.to_string();
        if s.contains('$') {
            let dbtime = fmt_x2(self.db_time(now));
            let utc = fmt_x2(now);
            let count = self.posted_local.to_string();
            let tcount = self.posted_total.to_string();
            for (name, val) in [
                ("DBTIME", &dbtime),
                ("UTCTIME", &utc),
                ("UTC", &utc),
                ("TCOUNT", &tcount),
                ("COUNT", &count),
            ] {
                s = s
                    .replace(&format!("$({name})"), val)
                    .replace(&format!("$[{name}]"), val);
            }
            for (name, v) in [("NAV_X", self.nav_x), ("NAV_Y", self.nav_y)] {
                if let Some(v) = v {
                    let t = fmt_x2(v);
                    s = s
                        .replace(&format!("$({name})"), &t)
                        .replace(&format!("$[{name}]"), &t);
                }
            }
            s = s.replace("$[VNAME]", &self.community);
            for rv in &self.rand_vars {
                let t = rv.text();
                s = s
                    .replace(&format!("$({})", rv.name), &t)
                    .replace(&format!("$[{}]", rv.name), &t);
            }
            for n in (1..=20).rev() {
                let pat = format!("$({n})");
                while let Some(at) = s.find(&pat) {
                    let mut digits: String = (0..n)
                        .map(|_| char::from(b'0' + self.rng.u8(0..10)))
                        .collect();
                    let trimmed = digits.trim_start_matches('0').len();
                    digits.drain(..digits.len() - trimmed.max(1));
                    s.replace_range(at..at + pat.len(), &digits);
                }
            }
        }
        for _ in 0..11 {
            match eval_innermost(&s) {
                Some(next) => s = next,
                None => break,
            }
        }
        s
    }

    fn execute(&mut self, i: usize, now: f64, out: &mut Vec<Post>) {
        for rv in &mut self.rand_vars {
            if rv.key == RandKey::Post {
                rv.draw(&mut self.rng, &mut self.gauss_spare);
            }
        }
        let e = self.events[i].clone();
        let value = match &e.value {
            EventValue::Double(x) => Value::Double(*x),
            EventValue::Text { text, quoted } => {
                let whole = |names: &[&str]| {
                    names
                        .iter()
                        .any(|n| *text == format!("$({n})") || *text == format!("$[{n}]"))
                };
                if e.quit {
                    Value::text(text.clone())
                } else if whole(&["DBTIME"]) {
                    Value::Double(self.db_time(now))
                } else if whole(&["UTCTIME", "UTC"]) {
                    Value::Double(now)
                } else if whole(&["COUNT"]) {
                    Value::Double(self.posted_local as f64)
                } else if whole(&["TCOUNT"]) {
                    Value::Double(self.posted_total as f64)
                } else {
                    let s = self.expand(text, now);
                    match s.parse::<f64>() {
                        Ok(x) if !quoted && condition::is_numeric(&s) => Value::Double(x),
                        _ => Value::String(s.into()),
                    }
                }
            }
        };
        if e.quit {
            self.quit_sent = true;
        }
        self.posted[i] = true;
        self.posted_local += 1;
        self.posted_total += 1;
        if self.event_log.len() == EVENT_LOG_LEN {
            self.event_log.pop_front();
        }
        self.event_log.push_back(format!(
            "{:<5}  {:<5}  {:<8.2}  {:<7.2}  {} = {}",
            self.posted_total,
            self.posted_local,
            now - self.started_at,
            self.elapsed,
            e.var,
            value
        ));
        out.push(Post::new(e.var, value));
        self.status_needed = true;
    }
}

/// `%.2f` with trailing zeros kept (the C++ uses doubleToString(v, 2)).
fn fmt_x2(x: f64) -> String {
    format!("{x:.2}")
}

/// Evaluates the innermost `{a op b}` of `s`, if it holds two numbers.
fn eval_innermost(s: &str) -> Option<String> {
    let close = s.find('}')?;
    let open = s[..close].rfind('{')?;
    let inner = &s[open + 1..close];
    for op in ['*', '/', '+', '-'] {
        // Skip a leading sign when looking for the operator.
        let Some(pos) = inner
            .char_indices()
            .skip(1)
            .find(|&(_, c)| c == op)
            .map(|(i, _)| i)
        else {
            continue;
        };
        let (a, b) = (&inner[..pos], &inner[pos + 1..]);
        let (Ok(x), Ok(y)) = (a.parse::<f64>(), b.parse::<f64>()) else {
            return None;
        };
        let r = match op {
            '*' => x * y,
            '/' => {
                if y == 0.0 {
                    return None;
                }
                x / y
            }
            '+' => x + y,
            _ => x - y,
        };
        let mut out = String::with_capacity(s.len());
        out.push_str(&s[..open]);
        out.push_str(&fmt_x(r, 6));
        out.push_str(&s[close + 1..]);
        return Some(out);
    }
    None
}

impl App for TimerScript {
    fn name(&self) -> &str {
        &self.name
    }

    fn process_config(&self) -> Option<&ProcessConfig> {
        self.block.as_ref()
    }

    fn subscriptions(&self) -> Vec<Subscription> {
        let mut v: Vec<String> = vec![
            self.forward_var.clone(),
            self.pause_var.clone(),
            self.reset_var.clone(),
            "DB_UPTIME".into(),
            "DB_CLIENTS".into(),
            "EXITED_NORMALLY".into(),
        ];
        for c in &self.conditions {
            v.extend(c.variables().into_iter().map(String::from));
        }
        if self.needs_nav {
            v.push("NAV_X".into());
            v.push("NAV_Y".into());
        }
        let mut seen = std::collections::BTreeSet::new();
        AppcastLayer::subscriptions()
            .chain(
                v.into_iter()
                    .filter(|s| !s.is_empty() && seen.insert(s.clone()))
                    .map(Subscription::var),
            )
            .collect()
    }

    fn on_startup(&mut self, now: f64, _out: &mut Vec<Post>) -> crate::app::AppResult {
        if let Some(a) = self.appcast.as_mut() {
            a.on_startup(now);
        }
        self.started_at = now;
        for rv in &mut self.rand_vars {
            rv.draw(&mut self.rng, &mut self.gauss_spare);
        }
        Ok(())
    }

    fn on_mail(&mut self, mail: &[Mail], now: f64, _out: &mut Vec<Post>) -> crate::app::AppResult {
        for m in mail {
            if let Some(a) = self.appcast.as_mut()
                && !a.take_mail(m)
            {
                continue;
            }
            let key = &*m.key;
            if key == self.pause_var {
                if let Some(s) = m.value.as_str() {
                    match s.to_ascii_lowercase().as_str() {
                        "true" => self.paused = true,
                        "false" => self.paused = false,
                        "toggle" => self.paused = !self.paused,
                        _ => {}
                    }
                    self.status_needed = true;
                }
                self.info.insert(m.key.to_string(), m.value.clone());
            } else if key == self.reset_var {
                if let Some(s) = m.value.as_str()
                    && (s.eq_ignore_ascii_case("reset") || s.eq_ignore_ascii_case("true"))
                {
                    self.handle_reset();
                }
            } else if key == self.forward_var {
                if let Some(x) = m.value.as_f64() {
                    let delay = if self.reset_count == 0 {
                        self.delay_start_value
                    } else {
                        self.delay_reset_value
                    };
                    let jump = if x > 0.0 {
                        x
                    } else {
                        let pending = self
                            .ptimes
                            .iter()
                            .zip(&self.posted)
                            .filter(|(_, p)| !**p)
                            .map(|(t, _)| *t)
                            .fold(f64::INFINITY, f64::min);
                        if pending.is_finite() {
                            ((pending + delay - self.elapsed) / self.warp_value).max(0.0)
                        } else {
                            0.0
                        }
                    };
                    self.skip_time += jump;
                }
            } else if key == "DB_UPTIME" {
                if self.db_start.is_none()
                    && let Some(up) = m.value.as_f64()
                {
                    self.db_start = Some(now - up);
                }
            } else if key == "DB_CLIENTS" {
                if let Some(s) = m.value.as_str() {
                    let clients: Vec<&str> = s.split(',').collect();
                    self.block_on.retain(|b| !clients.contains(&b.as_str()));
                }
            } else if key == "EXITED_NORMALLY" {
                if m.value.as_str() == Some(self.name.as_str()) && self.quit_sent {
                    self.finished = true;
                }
            } else {
                if key == "NAV_X" {
                    self.nav_x = m.value.as_f64();
                } else if key == "NAV_Y" {
                    self.nav_y = m.value.as_f64();
                }
                self.info.insert(m.key.to_string(), m.value.clone());
            }
        }
        Ok(())
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> crate::app::AppResult {
        let tick = self.app_tick();
        if let Some(a) = self.appcast.as_mut() {
            a.begin(now, tick, out);
        }
        self.iterate_script(now, out);
        // The layer is taken out while the body reads the script.
        if let Some(mut appcast) = self.appcast.take() {
            appcast.end(now, tick, out, |b| self.appcast_body(b));
            self.appcast = Some(appcast);
        }
        Ok(())
    }

    fn finished(&self) -> bool {
        self.finished
    }
}

impl TimerScript {
    /// One pass of the script (uTimerScript's Iterate without the appcasting around it).
    fn iterate_script(&mut self, now: f64, out: &mut Vec<Post>) {
        // 1. Conditions (not re-checked mid-pass in atomic mode).
        let mid_pass = self.posted_local > 0 && self.posted_local < self.events.len();
        if !(self.atomic && mid_pass) {
            let ok = self.conditions_hold();
            if ok && !self.conditions_ok {
                match self.upon_awake {
                    UponAwake::Reset if self.elapsed > 0.0 => self.handle_reset(),
                    UponAwake::Restart => self.handle_restart(),
                    _ => {}
                }
            }
            if ok != self.conditions_ok {
                self.status_needed = true;
            }
            self.conditions_ok = ok;
        }
        // 2. (Re)start the script.
        if self.script_start.is_none() {
            let start = if self.time_zero_db {
                self.db_start.unwrap_or(now)
            } else {
                now
            };
            self.script_start = Some(start);
            self.schedule_events();
        }
        // 3. Paused time.
        let held = self.paused || !self.conditions_ok || !self.block_on.is_empty();
        if held && let Some(prev) = self.previous_time {
            self.pause_time += now - prev;
        }
        self.previous_time = Some(now);
        // 4. Elapsed time.
        let start = self.script_start.unwrap_or(now);
        self.elapsed = ((now - start) + self.skip_time - self.pause_time) * self.warp_value;
        // 5. Periodic status.
        if self.last_status.is_none_or(|t| now - t > 5.0) {
            self.status_needed = true;
        }
        // 6. Due events, in config order.
        if !held {
            let delay = if self.reset_count == 0 {
                self.delay_start_value
            } else {
                self.delay_reset_value
            };
            for i in 0..self.events.len() {
                if !self.posted[i]
                    && self.elapsed - delay >= self.ptimes[i]
                    && (self.reset_time <= 0.0 || self.ptimes[i] <= self.reset_time)
                {
                    self.execute(i, now, out);
                }
            }
        }
        // 7. Resets.
        let all_posted = self.posted_local == self.events.len();
        let at_end = all_posted && self.reset_time == 0.0;
        let timed_out = self.reset_time > 0.0 && self.elapsed >= self.reset_time;
        if at_end || timed_out {
            self.handle_reset();
        }
        // 8. Status.
        if self.status_needed {
            self.status_needed = false;
            if !self.status_var.is_empty() && !self.status_var.eq_ignore_ascii_case("silent") {
                out.push(Post::text(self.status_var.clone(), self.status_text()));
            }
            self.last_status = Some(now);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mission::source::SourceMap;

    fn script(body: &str) -> TimerScript {
        try_script(body).unwrap()
    }

    fn try_script(body: &str) -> Result<TimerScript, TimerScriptError> {
        let text = format!("ProcessConfig = uTimerScript\n{{\n{body}\n}}\n");
        let src = SourceMap::from_text("t.moos", &text);
        let block = mission::moos::parse_moos(&src).value.processes[0].clone();
        TimerScript::new("uTimerScript", block, "alpha", 7)
    }

    /// Runs iterates at `start + k*dt` for `n` steps, feeding `mail` before the step whose
    /// time is at least its time; returns (time, post).
    fn run(
        ts: &mut TimerScript,
        start: f64,
        dt: f64,
        n: usize,
        mail: &[(f64, &str, Value)],
    ) -> Vec<(f64, Post)> {
        let mut out = Vec::new();
        let mut posts = Vec::new();
        ts.on_startup(start, &mut posts).unwrap();
        let mut fed = 0;
        for k in 0..n {
            let now = start + k as f64 * dt;
            let due: Vec<Mail> = mail[fed..]
                .iter()
                .take_while(|(t, _, _)| *t <= now + 1e-9)
                .map(|(t, key, v)| Mail {
                    key: (*key).into(),
                    value: v.clone(),
                    time: *t,
                    source: "test".into(),
                    source_aux: Default::default(),
                    community: "alpha".into(),
                })
                .collect();
            fed += due.len();
            if !due.is_empty() {
                ts.on_mail(&due, now, &mut posts).unwrap();
            }
            ts.iterate(now, &mut posts).unwrap();
            out.extend(posts.drain(..).map(|p| (now, p)));
        }
        out
    }

    /// The script's own postings: no status, no appcast (tested apart).
    fn without_status(v: Vec<(f64, Post)>) -> Vec<(f64, Post)> {
        v.into_iter()
            .filter(|(_, p)| p.key != "UTS_STATUS" && p.key != "APPCAST")
            .collect()
    }

    #[test]
    fn the_script_appcasts_its_state_and_postings_on_request() {
        let mut ts = script(
            "AppTick = 4\nevent = var=TICK_D, val=$(COUNT), time=0.5\n\
             event = var=TICK_S, val=\"tick\", time=1.0\nreset_max = 0\n",
        )
        .with_appcast_globals(Some("alpha"), 1.0);
        assert!(
            ts.subscriptions()
                .iter()
                .any(|s| s.pattern == "APPCAST_REQ"),
            "AppCastingMOOSApp registers APPCAST_REQ"
        );
        let casts = |posts: &[(f64, Post)]| -> Vec<(f64, appcast::AppCast)> {
            posts
                .iter()
                .filter(|(_, p)| p.key == "APPCAST")
                .map(|(t, p)| (*t, appcast::AppCast::parse(p.value.as_str().unwrap())))
                .collect()
        };
        // Nobody asks: only the start-up casts of the first iterations.
        let quiet = run(&mut ts, 10.0, 0.25, 12, &[]);
        assert!(casts(&quiet).iter().all(|(t, _)| *t < 10.5), "{quiet:?}");
        // A request for this node and app (at 13.1, for 3 s): the next iteration answers.
        let req = "node=alpha,app=uTimerScript,duration=3.0,key=uMAC_1,thresh=any";
        let mut ts2 = script(
            "AppTick = 4\nevent = var=TICK_D, val=$(COUNT), time=0.5\n\
             event = var=TICK_S, val=\"tick\", time=1.0\nreset_max = 0\n",
        )
        .with_appcast_globals(Some("alpha"), 1.0);
        let posts = run(
            &mut ts2,
            10.0,
            0.25,
            16,
            &[(13.1, "APPCAST_REQ", Value::text(req))],
        );
        let answered = casts(&posts);
        let (t, cast) = answered.last().expect("an appcast");
        assert!(*t >= 13.25, "answered at {t}");
        assert_eq!(cast.proc_name(), "uTimerScript");
        assert_eq!(cast.node_name(), "alpha");
        let m = cast.messages();
        assert!(m.contains("Elements: 2(2)"), "{m}");
        assert!(m.contains("TICK_D = 0"), "{m}");
        assert!(m.contains("TICK_S = tick"), "{m}");
        // A request for another node is not answered.
        let mut ts3 = script("AppTick = 4\nevent = var=A, val=1, time=0.5\n")
            .with_appcast_globals(Some("alpha"), 1.0);
        let other = "node=bravo,app=all,duration=3.0,key=uMAC_1,thresh=any";
        let posts = run(
            &mut ts3,
            10.0,
            0.25,
            16,
            &[(13.1, "APPCAST_REQ", Value::text(other))],
        );
        assert!(casts(&posts).iter().all(|(t, _)| *t < 10.5));
        // The request never reaches the script as information.
        assert!(!ts2.info.contains_key("APPCAST_REQ"));
    }

    #[test]
    fn logger_capture_script_matches_the_real_app() {
        // captures/logger: AppTick 4, TICK_D at 0.5, TICK_S at 1.0, reset when all posted.
        let mut ts = script(
            "AppTick = 4\npaused = false\nevent = var=TICK_D, val=$(COUNT), time=0.5\n\
             event = var=TICK_S, val=\"tick number $(COUNT)\", time=1.0\n\
             reset_max = nolimit\nreset_time = all-posted",
        );
        let out = run(&mut ts, 100.0, 0.25, 12, &[]);
        let first = &out[0];
        assert_eq!(first.0, 100.0);
        assert_eq!(
            first.1.value,
            Value::text(
                "name=unnamed, elapsed_time=0.00, posted=0, pending=2, paused=false, conditions_ok=true, \
                 time_warp=1, delay_start=0, delay_reset=0, shuffle=true, upon_awake=n/a, resets=0/any"
            )
        );
        let posts = without_status(out.clone());
        let got: Vec<(f64, &str, &Value)> =
            posts.iter().map(|(t, p)| (*t, &*p.key, &p.value)).collect();
        assert_eq!(
            got,
            vec![
                (100.5, "TICK_D", &Value::Double(0.0)),
                (101.0, "TICK_S", &Value::text("ticknumber1")),
                // reset at 101.0, restart at the next iterate (101.25), +0.5
                (101.75, "TICK_D", &Value::Double(0.0)),
                (102.25, "TICK_S", &Value::text("ticknumber1")),
            ]
        );
        let status_at_101 = out
            .iter()
            .find(|(t, p)| *t == 101.0 && p.key == "UTS_STATUS")
            .unwrap();
        assert!(
            status_at_101
                .1
                .value
                .as_str()
                .unwrap()
                .contains("elapsed_time=1.00, posted=2, pending=0")
        );
        assert!(
            status_at_101
                .1
                .value
                .as_str()
                .unwrap()
                .ends_with("resets=1/any")
        );
    }

    #[test]
    fn reset_max_limits_passes() {
        let mut ts = script("event = var=A, val=1, time=0\nreset_time = end\nreset_max = 2");
        let out = without_status(run(&mut ts, 0.0, 1.0, 20, &[]));
        assert_eq!(out.len(), 3, "{out:?}");
        let times: Vec<f64> = out.iter().map(|(t, _)| *t).collect();
        assert_eq!(times, vec![0.0, 1.0, 2.0]);
    }

    #[test]
    fn reset_time_number_cuts_late_events() {
        let mut ts = script(
            "event = var=A, val=x, time=1\nevent = var=B, val=y, time=5\nreset_time = 3\nreset_max = 1",
        );
        let out = without_status(run(&mut ts, 0.0, 0.5, 20, &[]));
        let got: Vec<(f64, &str)> = out.iter().map(|(t, p)| (*t, &*p.key)).collect();
        // Pass 1: A at 1, reset at elapsed 3; pass 2 starts at 3.5: A at 4.5; B never.
        assert_eq!(got, vec![(1.0, "A"), (4.5, "A")]);
    }

    #[test]
    fn time_ranges_are_seeded_and_within_bounds() {
        let body = "event = var=A, val=1, time=20:30\nevent = var=B, val=2, time=20:30";
        let a = without_status(run(&mut script(body), 0.0, 0.1, 400, &[]));
        let b = without_status(run(&mut script(body), 0.0, 0.1, 400, &[]));
        assert_eq!(a, b, "same seed, same draws");
        assert_eq!(a.len(), 2);
        for (t, _) in &a {
            assert!((20.0..=30.1).contains(t), "{t}");
        }
        assert_ne!(a[0].0, a[1].0, "two events draw different times");
    }

    #[test]
    fn amt_clones_with_index() {
        let mut ts = script("event = var=P, val=\"pt_$(IDX)\", time=1, amt=3");
        assert_eq!(ts.event_count(), 3);
        let out = without_status(run(&mut ts, 0.0, 1.0, 3, &[]));
        let vals: Vec<&Value> = out.iter().map(|(_, p)| &p.value).collect();
        assert_eq!(
            vals,
            vec![
                &Value::text("pt_000"),
                &Value::text("pt_001"),
                &Value::text("pt_002")
            ]
        );
    }

    #[test]
    fn pause_var_freezes_elapsed_time() {
        let mut ts = script("event = var=A, val=1, time=4\npaused = true");
        let mail = [(3.0, "UTS_PAUSE", Value::text("false"))];
        let out = without_status(run(&mut ts, 0.0, 1.0, 10, &mail));
        // Held at the iterates of 1 and 2 (pause time 2): A due at elapsed 4 = t 6.
        assert_eq!(out.iter().map(|(t, _)| *t).collect::<Vec<_>>(), vec![6.0]);
        let mut ts = script("event = var=A, val=1, time=4");
        let mail = [
            (1.0, "UTS_PAUSE", Value::text("toggle")),
            (3.0, "UTS_PAUSE", Value::text("TOGGLE")),
        ];
        let out = without_status(run(&mut ts, 0.0, 1.0, 10, &mail));
        assert_eq!(out.iter().map(|(t, _)| *t).collect::<Vec<_>>(), vec![6.0]);
    }

    #[test]
    fn reset_var_restarts_the_script() {
        let mut ts = script("event = var=A, val=1, time=2\nevent = var=B, val=1, time=10");
        let mail = [(4.0, "UTS_RESET", Value::text("reset"))];
        let out = without_status(run(&mut ts, 0.0, 1.0, 9, &mail));
        let got: Vec<(f64, &str)> = out.iter().map(|(t, p)| (*t, &*p.key)).collect();
        // A at 2; reset by mail at 4, so the same iterate restarts; A again at 6.
        assert_eq!(got, vec![(2.0, "A"), (6.0, "A")]);
    }

    #[test]
    fn condition_with_upon_awake_restart_and_delays() {
        // delta's GPS script, with a fixed delay to check the timing exactly.
        let mut ts = script(
            "paused = false\nreset_max = any\nreset_time = end\ncondition = TIME_AT_SURFACE > 3\n\
             upon_awake = restart\ndelay_start = 10\nscript_name = GPS_SCRIPT\n\
             event = var=GPS_UPDATE_RECEIVED, val=\"RCVD_$(COUNT)\", time=1",
        );
        assert!(
            ts.subscriptions()
                .iter()
                .any(|s| s.pattern == "TIME_AT_SURFACE")
        );
        let mail = [
            (0.0, "TIME_AT_SURFACE", Value::Double(0.0)),
            (20.0, "TIME_AT_SURFACE", Value::Double(4.0)),
            (40.0, "TIME_AT_SURFACE", Value::Double(0.0)),
        ];
        let out = run(&mut ts, 0.0, 1.0, 45, &mail);
        let first_status = out[0].1.value.as_str().unwrap().to_string();
        assert!(
            first_status.starts_with("name=GPS_SCRIPT,"),
            "{first_status}"
        );
        assert!(first_status.contains("conditions_ok=false"));
        let posts = without_status(out);
        let times: Vec<f64> = posts.iter().map(|(t, _)| *t).collect();
        // Awake at 20 (restart): delay_start 10 + time 1 → 31; then delay_reset 0:
        // reset at 31, restart at 32, post at 33, 35, 37, 39; asleep from 40.
        assert_eq!(times, vec![31.0, 33.0, 35.0, 37.0, 39.0]);
        assert_eq!(posts[0].1.value, Value::text("RCVD_0"));
        assert!(posts.iter().all(|(_, p)| p.key == "GPS_UPDATE_RECEIVED"));
    }

    #[test]
    fn upon_awake_reset_needs_elapsed_time() {
        let mut ts = script(
            "condition = GO = true\nupon_awake = reset\nevent = var=A, val=1, time=2\nreset_max=5",
        );
        let mail = [
            (0.0, "GO", Value::text("true")),
            (2.0, "GO", Value::text("false")),
            (4.0, "GO", Value::text("true")),
        ];
        let out = without_status(run(&mut ts, 0.0, 1.0, 8, &mail));
        // Awake at 0 (elapsed 0: no reset); asleep at 2 and 3 with elapsed 1; awake at 4
        // resets and restarts in that iterate: A at 6 (without the reset it would be 4).
        assert_eq!(out.iter().map(|(t, _)| *t).collect::<Vec<_>>(), vec![6.0]);
        let mut plain = script("condition = GO = true\nevent = var=A, val=1, time=2");
        let out = without_status(run(&mut plain, 0.0, 1.0, 8, &mail));
        assert_eq!(out.iter().map(|(t, _)| *t).collect::<Vec<_>>(), vec![4.0]);
    }

    #[test]
    fn time_warp_scales_elapsed_time() {
        let mut ts = script("time_warp = 2\nevent = var=A, val=1, time=10");
        let out = without_status(run(&mut ts, 0.0, 1.0, 10, &[]));
        assert_eq!(out.iter().map(|(t, _)| *t).collect::<Vec<_>>(), vec![5.0]);
        let st = run(
            &mut script("time_warp = 2:3\nevent = var=A, val=1, time=10"),
            0.0,
            1.0,
            1,
            &[],
        );
        let text = st[0].1.value.as_str().unwrap().to_string();
        let w: f64 = text
            .split("time_warp=")
            .nth(1)
            .and_then(|r| r.split(',').next())
            .and_then(|v| v.parse().ok())
            .unwrap();
        assert!((2.0..=3.0).contains(&w), "{text}");
    }

    #[test]
    fn delay_reset_applies_after_the_first_pass() {
        let mut ts = script(
            "delay_start = 1\ndelay_reset = 3\nevent = var=A, val=1, time=0\nreset_time = end\nreset_max = 1",
        );
        let out = without_status(run(&mut ts, 0.0, 1.0, 10, &[]));
        // First pass: at 1. Reset, restart at 2, +3 → 5.
        assert_eq!(
            out.iter().map(|(t, _)| *t).collect::<Vec<_>>(),
            vec![1.0, 5.0]
        );
    }

    #[test]
    fn forward_var_skips_ahead() {
        let mut ts = script("event = var=A, val=1, time=100\nevent = var=B, val=1, time=200");
        let mail = [
            (2.0, "UTS_FORWARD", Value::Double(0.0)),
            (5.0, "UTS_FORWARD", Value::Double(50.0)),
        ];
        let out = without_status(run(&mut ts, 0.0, 1.0, 160, &mail));
        let got: Vec<(f64, &str)> = out.iter().map(|(t, p)| (*t, &*p.key)).collect();
        // At 2 skip 99 (to the next event from the last elapsed time, 1): A posts at 2;
        // at 5 skip 50 more: elapsed = t + 149, B (200) at t 51.
        assert_eq!(got, vec![(2.0, "A"), (51.0, "B")]);
    }

    #[test]
    fn macros_math_and_types() {
        let mut ts = script(
            "event = var=N, val=\"{2*{3+4}}\", time=0\nevent = var=Q, val=\"5\", time=0\n\
             event = var=U, val=$(UTC), time=0\nevent = var=V, val=\"$[VNAME]:$(TCOUNT)\", time=0\n\
             event = var=R, val=$(4), time=0\nevent = var=X, val=\"x=$[NAV_X]\", time=1\n\
             rand_var = varname=RV, min=10, max=20, key=at_start\nevent = var=W, val=\"$[RV]\", time=0",
        );
        assert!(ts.subscriptions().iter().any(|s| s.pattern == "NAV_X"));
        let mail = [(0.5, "NAV_X", Value::Double(12.346))];
        let out = without_status(run(
            &mut ts,
            50.0,
            1.0,
            2,
            &[(50.0, mail[0].1, mail[0].2.clone())],
        ));
        let get = |k: &str| {
            out.iter()
                .find(|(_, p)| p.key == k)
                .unwrap()
                .1
                .value
                .clone()
        };
        assert_eq!(get("N"), Value::text("14"), "quoted math stays a string");
        assert_eq!(get("Q"), Value::text("5"), "quoted number stays a string");
        assert_eq!(get("U"), Value::Double(50.0));
        assert_eq!(get("V"), Value::text("alpha:3"));
        let r = get("R");
        let r = r.as_f64().expect("unquoted random digits post a double");
        assert!((0.0..10000.0).contains(&r));
        assert_eq!(get("X"), Value::text("x=12.35"));
        let w: f64 = get("W").as_str().unwrap().parse().unwrap();
        assert!((10.0..=20.0).contains(&w));
    }

    #[test]
    fn quit_posts_exited_normally_and_finishes() {
        let mut ts = script("event = quit, time=1");
        let out = without_status(run(&mut ts, 0.0, 1.0, 2, &[]));
        assert_eq!(out[0].1, Post::text("EXITED_NORMALLY", "uTimerScript"));
        assert!(!ts.finished());
        let mut posts = Vec::new();
        ts.on_mail(
            &[Mail {
                key: "EXITED_NORMALLY".into(),
                value: Value::text("uTimerScript"),
                time: 1.0,
                source: "uTimerScript".into(),
                source_aux: Default::default(),
                community: Default::default(),
            }],
            1.2,
            &mut posts,
        )
        .unwrap();
        assert!(ts.finished());
    }

    #[test]
    fn block_on_waits_for_clients() {
        let mut ts = script("block_on = pHelmIvP\nevent = var=A, val=1, time=1");
        let mail = [
            (1.0, "DB_CLIENTS", Value::text("uTimerScript,")),
            (3.0, "DB_CLIENTS", Value::text("pHelmIvP,uTimerScript,")),
        ];
        let out = without_status(run(&mut ts, 0.0, 1.0, 6, &mail));
        // Held at 1 and 2 (pause 2): elapsed reaches 1 at t 3.
        assert_eq!(out.iter().map(|(t, _)| *t).collect::<Vec<_>>(), vec![3.0]);
    }

    #[test]
    fn status_is_silent_when_asked_and_periodic_otherwise() {
        let mut ts = script("status_var = silent\nevent = var=A, val=1, time=1");
        assert!(
            run(&mut ts, 0.0, 1.0, 3, &[])
                .iter()
                .all(|(_, p)| p.key != "UTS_STATUS")
        );
        let mut ts = script("event = var=A, val=1, time=100");
        let out = run(&mut ts, 0.0, 1.0, 13, &[]);
        let st: Vec<f64> = out
            .iter()
            .filter(|(_, p)| p.key == "UTS_STATUS")
            .map(|(t, _)| *t)
            .collect();
        assert_eq!(st, vec![0.0, 6.0, 12.0]);
    }

    #[test]
    fn bad_lines_name_file_and_line() {
        let e = try_script("reset_max = 2\nevent = var=A, val=1, time=-3")
            .err()
            .unwrap();
        assert_eq!(e.line, 4);
        assert!(e.to_string().starts_with("t.moos:4: uTimerScript:"), "{e}");
        assert!(try_script("event = val=1, time=1").is_err());
        assert!(try_script("time_warp = 0").is_err());
        assert!(try_script("condition = (A = ").is_err());
        assert!(try_script("rand_pair = var1=X, var2=Y").is_err());
        let w = try_script("upon_awake = sometimes\nreset_max = no_limit").unwrap();
        assert_eq!(w.upon_awake, UponAwake::None);
        assert_eq!(w.reset_max, None);
        assert_eq!(w.warnings().len(), 2);
        assert!(
            w.warnings()[0]
                .located()
                .starts_with("t.moos:3: upon_awake"),
            "{:?}",
            w.warnings()
        );
    }

    #[test]
    fn every_corpus_timer_script_block_is_read() {
        let root = test_support::mission_file("");
        let mut seen = 0;
        for path in test_support::files_with_ext(&root, &["moos"]) {
            let text = std::fs::read_to_string(&path).unwrap();
            let src = SourceMap::from_text(&path.display().to_string(), &text);
            for b in mission::moos::parse_moos(&src).value.processes {
                if b.name != "uTimerScript" {
                    continue;
                }
                // Blocks that use features coug refuses must say so by line; others load.
                match TimerScript::new("uTimerScript", b.clone(), "c", 1) {
                    Ok(ts) => {
                        seen += 1;
                        let _ = ts.event_count();
                    }
                    Err(e) => assert!(
                        e.message.contains("rand_pair")
                            || e.message.contains("not supported")
                            || e.message.contains("$("),
                        "{}: {e}",
                        path.display()
                    ),
                }
            }
        }
        assert!(seen >= 20, "only {seen} uTimerScript blocks read");
    }

    /// The gaussian variables of the corpus's s1_alpha_obstaclemgr, read as the C++ reads
    /// them: every one kept, with its mu, sigma, range and key.
    #[test]
    fn gaussian_rand_vars_parse_as_moos_does() {
        let ts = script(
            "rand_var = varname=RND_AX, type=gaussian, min=155, max=165, mu=160, sigma=2, key=at_reset\n\
             rand_var = varname=N, type=normal, min=-1, max=1, mu=0, sigma=0.5, snap=0.25, key=AT_POST\n\
             rand_var = varname=U, min=0, max=1, key=at_start",
        );
        assert!(ts.warnings().is_empty(), "{:?}", ts.warnings());
        let rv = &ts.rand_vars;
        assert_eq!(rv.len(), 3);
        assert_eq!(
            (
                rv[0].name.as_str(),
                rv[0].min,
                rv[0].max,
                rv[0].key,
                rv[0].snap
            ),
            ("RND_AX", 155.0, 165.0, RandKey::Reset, 0.001)
        );
        assert_eq!(
            rv[0].kind,
            RandKind::Gaussian {
                mu: 160.0,
                sigma: 2.0
            }
        );
        assert_eq!((rv[1].key, rv[1].snap), (RandKey::Post, 0.25));
        assert_eq!(
            rv[1].kind,
            RandKind::Gaussian {
                mu: 0.0,
                sigma: 0.5
            }
        );
        assert_eq!(rv[2].kind, RandKind::Uniform);
        let ts = corpus_script("s1_alpha_obstaclemgr/alpha.moos", "alpha");
        assert!(ts.warnings().is_empty(), "{:?}", ts.warnings());
        assert_eq!(ts.rand_vars.len(), 10);
        assert!(
            ts.rand_vars
                .iter()
                .all(|r| matches!(r.kind, RandKind::Gaussian { sigma: 2.0, .. }))
        );
    }

    /// Each spec the C++ refuses is a config warning with its words, the line ignored.
    #[test]
    fn bad_gaussian_rand_vars_are_warned_with_the_cpp_words() {
        let base = "varname=G, type=gaussian, min=0, max=10, mu=5, sigma=1, key=at_start";
        let cases = [
            (
                "varname=G, type=gaussian, min=0, max=10, mu=5, sigma=1",
                "key is not specified",
            ),
            (
                "varname=G, type=gaussian, min=0, max=10, mu=5, sigma=1, key=at_noon",
                "unknown random_var key: at_noon",
            ),
            (
                "type=gaussian, min=0, max=10, mu=5, sigma=1, key=at_start",
                "Unset variable name",
            ),
            (
                "varname=G, type=gaussian, max=10, mu=5, sigma=1, key=at_start",
                "Lower value of the range not set",
            ),
            (
                "varname=G, type=gaussian, min=0, mu=5, sigma=1, key=at_start",
                "Upper value of the range not set",
            ),
            (
                "varname=G, type=gaussian, min=0, max=10, sigma=1, key=at_start",
                "Mu not set",
            ),
            (
                "varname=G, type=gaussian, min=0, max=10, mu=5, key=at_start",
                "Sigma not set",
            ),
            (
                "varname=G, type=gaussian, min=10, max=0, mu=5, sigma=1, key=at_start",
                "Minimum value greater than maximum value",
            ),
            (
                "varname=G, type=gaussian, min=zero, max=10, mu=5, sigma=1, key=at_start",
                "Bad parameterx=value: min=zero",
            ),
            (
                "varname=G, type=gaussian, min=0, max=10, mu=5, sigma=1, key=at_start, skew=2",
                "Bad parameterx=value: skew=2",
            ),
            (
                "varname=G, type=poisson, min=0, max=10, key=at_start",
                "unknown random variable type: poisson",
            ),
        ];
        for (spec, why) in cases {
            let ts = script(&format!("rand_var = {spec}"));
            assert!(ts.rand_vars.is_empty(), "{spec}");
            let w: Vec<String> = ts.warnings().iter().map(|d| d.located()).collect();
            let want = format!(
                "t.moos:3: Rand variable problem: {}:{why}",
                spec.replace(' ', "")
            );
            assert_eq!(w, [want], "{spec}");
        }
        let ts = script(&format!("rand_var = {base}\nrand_var = {base}"));
        assert_eq!(ts.rand_vars.len(), 1);
        assert!(
            ts.warnings()[0]
                .located()
                .ends_with(":Duplicate random variable"),
            "{:?}",
            ts.warnings()
        );
    }

    /// A gaussian variable expands with up to 5 decimals (a uniform one with 3), and as a
    /// whole unquoted value posts a double.
    #[test]
    fn gaussian_macros_expand_with_five_decimals() {
        let mut ts = script(
            "rand_var = varname=G, type=gaussian, min=-50, max=50, mu=1.2345678, sigma=0, snap=0.00001, key=at_start\n\
             rand_var = varname=U, min=1.2345678, max=1.2345678, snap=0.00001, key=at_start\n\
             event = var=S, val=\"x=$[G],u=$[U]\", time=0\nevent = var=D, val=$(G), time=0\n\
             event = var=C, val=\"$[G]\", time=0",
        );
        let out = without_status(run(&mut ts, 10.0, 1.0, 2, &[]));
        let get = |k: &str| {
            out.iter()
                .find(|(_, p)| p.key == k)
                .unwrap()
                .1
                .value
                .clone()
        };
        assert_eq!(get("S"), Value::text("x=1.23457,u=1.235"));
        assert_eq!(get("C"), Value::text("1.23457"));
        let d = get("D").as_f64().expect("a double");
        assert!((d - 1.23457).abs() < 1e-12, "{d}");
        // Whole numbers lose their decimals, as doubleToStringX writes them.
        let mut ts = script(
            "rand_var = varname=G, type=gaussian, min=0, max=100, mu=160, sigma=3, key=at_start\n\
             event = var=S, val=\"g=$[G]\", time=0",
        );
        let out = without_status(run(&mut ts, 0.0, 1.0, 1, &[]));
        assert_eq!(out[0].1.value, Value::text("g=100"), "clamped to max");
    }

    /// 10,000 seeded draws: the deviates are N(0, 1) (mean, deviation, the share within one
    /// sigma); a variable's values have its mean and (clamped) deviation, stay within
    /// `[min, max]` and sit on its snap grid.
    #[test]
    fn gaussian_draws_over_ten_thousand_seeded_samples() {
        let n = 10_000;
        let mut rng = fastrand::Rng::with_seed(2026);
        let mut spare = None;
        let z: Vec<f64> = (0..n)
            .map(|_| white_noise(&mut rng, &mut spare, 1.0))
            .collect();
        let stats = |v: &[f64]| {
            let m = v.iter().sum::<f64>() / v.len() as f64;
            let var = v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64;
            (m, var.sqrt())
        };
        let (m, sd) = stats(&z);
        let within = z.iter().filter(|x| x.abs() <= 1.0).count() as f64 / n as f64;
        eprintln!("N(0,1): mean {m:.4}, sd {sd:.4}, within 1 sigma {within:.4}");
        assert!(m.abs() < 0.04, "{m}");
        assert!((0.97..1.03).contains(&sd), "{sd}");
        assert!((0.66..0.71).contains(&within), "{within}");

        let draws = |rv: &mut RandVar, rng: &mut fastrand::Rng, spare: &mut Option<f64>| {
            (0..n)
                .map(|_| {
                    rv.draw(rng, spare);
                    rv.value
                })
                .collect::<Vec<f64>>()
        };
        // s1_alpha_obstaclemgr's RND_AX: clamped at 2.5 sigma, so the deviation is 0.989 of
        // sigma (1.977).
        let mut rv = RandVar {
            name: "RND_AX".into(),
            min: 155.0,
            max: 165.0,
            snap: 0.001,
            key: RandKey::Reset,
            kind: RandKind::Gaussian {
                mu: 160.0,
                sigma: 2.0,
            },
            value: 0.0,
        };
        let v = draws(&mut rv, &mut rng, &mut spare);
        let (m, sd) = stats(&v);
        eprintln!("RND_AX: mean {m:.4}, sd {sd:.4}");
        assert!((m - 160.0).abs() < 0.08, "{m}");
        assert!((1.92..2.03).contains(&sd), "{sd}");
        assert!(v.iter().all(|x| (155.0..=165.0).contains(x)));
        assert!(
            v.iter()
                .all(|x| ((x / 0.001) - (x / 0.001).round()).abs() < 1e-6)
        );

        // A narrow range: a third of the draws beyond one sigma, all on the bounds.
        rv.min = -1.0;
        rv.max = 1.0;
        rv.snap = 0.25;
        rv.kind = RandKind::Gaussian {
            mu: 0.0,
            sigma: 1.0,
        };
        let v = draws(&mut rv, &mut rng, &mut spare);
        assert!(v.iter().all(|x| (-1.0..=1.0).contains(x)));
        assert!(
            v.iter().all(|x| (x * 4.0).fract() == 0.0),
            "on the 0.25 grid"
        );
        let at_bounds = v.iter().filter(|x| x.abs() == 1.0).count() as f64 / n as f64;
        // P(|z| >= 0.875) = 0.381: what snaps to +-1 or lies beyond.
        assert!((0.36..0.40).contains(&at_bounds), "{at_bounds}");
        // The same seed draws the same values.
        let again = |seed| {
            let mut ts = script(
                "rand_var = varname=G, type=gaussian, min=0, max=10, mu=5, sigma=1, key=at_post\n\
                 event = var=S, val=\"$[G]\", time=0, amt=5",
            );
            ts.rng = fastrand::Rng::with_seed(seed);
            without_status(run(&mut ts, 0.0, 1.0, 2, &[]))
                .into_iter()
                .map(|(_, p)| p.value)
                .collect::<Vec<_>>()
        };
        assert_eq!(again(9), again(9));
        assert_ne!(again(9), again(10));
    }

    /// The uTimerScript block of corpus mission `rel`, read for community `community`.
    fn corpus_script(rel: &str, community: &str) -> TimerScript {
        let text = test_support::mission_text(rel);
        let src = SourceMap::from_text(rel, &text);
        let block = mission::moos::parse_moos(&src)
            .value
            .processes
            .into_iter()
            .find(|b| b.name == "uTimerScript")
            .unwrap();
        TimerScript::new("uTimerScript", block, community, 3).unwrap()
    }

    #[test]
    fn delta_block_parses() {
        let ts = corpus_script("s4_delta/delta.moos", "delta");
        assert_eq!(ts.event_count(), 1);
        assert_eq!(ts.app_tick(), 4.0);
        assert_eq!(ts.script_name, "GPS_SCRIPT");
        assert_eq!(ts.upon_awake, UponAwake::Restart);
        assert_eq!(ts.reset_time, 0.0);
        assert_eq!(ts.reset_max, None);
        assert_eq!(
            ts.delay_start,
            Range {
                min: 20.0,
                max: 120.0
            }
        );
        assert_eq!(ts.events[0].time, Range { min: 0.5, max: 1.0 });
        assert!(!ts.conditions_ok);
    }
}
