//! The evaluator: mail in, rules judged at a time given as an argument, postings out.

use rustc_hash::FxHashMap as HashMap;
use std::fmt::Write as _;

use moos_types::{Post, Value};

use crate::config::{Flag, SafetyConfig, SurfaceVia};
use crate::rule::{Action, Operand, Release, Rule, Term};

/// The variable of the mode word.
pub const MODE_VAR: &str = "SAFETY_MODE";
/// The variable of the health word.
pub const HEALTH_VAR: &str = "SAFETY_HEALTH";
/// The variable of every trigger, clear and phase change.
pub const EVENT_VAR: &str = "SAFETY_EVENT";
/// Posting a rule's name (or `all`) here releases a latched rule whose condition is false.
pub const RESET_VAR: &str = "SAFETY_RESET";
/// The helm's state variable (a MALCONFIG helm is a failed helm).
pub const HELM_STATE_VAR: &str = "IVPHELM_STATE";
/// How far (m) the helm must raise the vehicle within `helm_grace` when surfacing through it.
pub const HELM_ASCENT_M: f64 = 0.5;

/// What the app tells its appcast besides postings.
#[derive(Debug, Clone, PartialEq)]
pub enum Notice {
    /// An appcast event.
    Event(String),
    /// An appcast run warning.
    Warning(String),
}

/// Where the supervisor is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Nothing triggered.
    Ok,
    /// Only warn rules triggered.
    Warn,
    /// A return is commanded (the return flags are posted).
    Return,
    /// The helm is overridden and the actuators held at zero.
    AllStop,
    /// Coming up.
    Surfacing,
    /// Up, thruster disarmed.
    Disarmed,
}

impl Phase {
    /// The `SAFETY_MODE` word.
    pub fn word(self) -> &'static str {
        match self {
            Phase::Ok => "OK",
            Phase::Warn => "WARN",
            Phase::Return => "RETURN",
            Phase::AllStop => "ALLSTOP",
            Phase::Surfacing => "SURFACE",
            Phase::Disarmed => "DISARMED",
        }
    }
}

/// The state of one rule.
#[derive(Debug, Clone, PartialEq)]
pub struct RuleState {
    /// Triggered now.
    pub active: bool,
    /// How many times it triggered.
    pub triggers: u32,
    /// When it last triggered.
    pub since: Option<f64>,
    /// Why it last triggered.
    pub reason: String,
    false_since: Option<f64>,
}

#[derive(Debug, Clone, Copy)]
struct Surfacing {
    since: f64,
    start_depth: Option<f64>,
    direct: bool,
    up_since: Option<f64>,
}

/// The supervisor.
#[derive(Debug, Clone)]
pub struct Supervisor {
    cfg: SafetyConfig,
    errors: Vec<String>,
    start: Option<f64>,
    /// Each variable's latest mail: value, time, and [`Supervisor::unwatched`] when it came
    /// (one map, one lookup per mail).
    values: HashMap<String, Seen>,
    /// When each watched app was last heard, and [`Supervisor::unwatched`] then.
    heard: HashMap<String, (f64, f64)>,
    status_vars: HashMap<String, String>,
    states: Vec<RuleState>,
    phase: Phase,
    surfacing: Option<Surfacing>,
    taken_over: bool,
    override_released: bool,
    resets: Vec<String>,
    helm_state: Option<String>,
    posted_mode: Option<&'static str>,
    posted_health: Option<u32>,
    commander: Option<usize>,
    /// The supervisor's own period, s (0 until told).
    period: f64,
    /// When it last evaluated.
    last_eval: Option<f64>,
    /// Time it did not watch so far, s (see [`Supervisor::unwatched`]).
    unwatched: f64,
}

/// A variable's latest mail.
#[derive(Debug, Clone)]
struct Seen {
    value: Value,
    time: f64,
    /// [`Supervisor::unwatched`] when it arrived.
    unwatched: f64,
}

/// Health-word bits besides the kinds' (see the crate documentation).
pub mod bits {
    /// A rule is triggered.
    pub const TRIGGERED: u32 = 1;
    /// A warn rule is triggered.
    pub const WARN: u32 = 1 << 1;
    /// A return is commanded.
    pub const RETURN: u32 = 1 << 2;
    /// All-stop.
    pub const ALLSTOP: u32 = 1 << 3;
    /// Surfacing.
    pub const SURFACING: u32 = 1 << 4;
    /// Up and disarmed.
    pub const DISARMED: u32 = 1 << 5;
    /// pSafety holds the helm off and drives the actuators.
    pub const ACTUATORS: u32 = 1 << 6;
    /// The configuration has errors: deployment refused.
    pub const MALCONFIG: u32 = 1 << 7;
}

fn as_bool(v: &Value) -> Option<bool> {
    match v {
        Value::Double(d) => Some(*d != 0.0),
        Value::String(s) => moos_types::text::set_boolean_on_string(false, s.trim()),
        Value::Binary(_) => None,
    }
}

/// `map[key] = value`, the key copied only when it is new (this runs for every mail).
fn set<T>(map: &mut HashMap<String, T>, key: &str, value: T) {
    match map.get_mut(key) {
        Some(slot) => *slot = value,
        None => {
            map.insert(key.to_string(), value);
        }
    }
}

fn show(v: &Value) -> String {
    match v {
        Value::Double(d) => format!("{d}"),
        Value::String(s) => s.to_string(),
        Value::Binary(b) => format!("<{} bytes>", b.len()),
    }
}

impl Supervisor {
    /// A supervisor of `cfg`; non-empty `errors` (the block's located configuration errors)
    /// make it MALCONFIG: it runs the rules it has and refuses deployment.
    pub fn new(cfg: SafetyConfig, errors: Vec<String>) -> Self {
        let mut status_vars = HashMap::default();
        let mut watch = |app: &str| {
            status_vars.insert(
                format!("{}_STATUS", app.to_ascii_uppercase()),
                app.to_string(),
            );
        };
        for r in &cfg.rules {
            for t in &r.terms {
                if let Term::Silent { app, .. } = t {
                    watch(app);
                }
            }
        }
        if cfg.surface_via == SurfaceVia::Helm {
            watch(&cfg.helm_app);
        }
        Supervisor {
            states: vec![
                RuleState {
                    active: false,
                    triggers: 0,
                    since: None,
                    reason: String::new(),
                    false_since: None,
                };
                cfg.rules.len()
            ],
            cfg,
            errors,
            start: None,
            values: HashMap::default(),
            heard: HashMap::default(),
            status_vars,
            phase: Phase::Ok,
            surfacing: None,
            taken_over: false,
            override_released: false,
            resets: Vec::new(),
            helm_state: None,
            posted_mode: None,
            posted_health: None,
            commander: None,
            period: 0.0,
            last_eval: None,
            unwatched: 0.0,
        }
    }

    /// Tells the supervisor its own evaluation period, s (the app's 1/AppTick): a gap up to
    /// twice it is never unwatched time. Only a supervisor told its period counts unwatched
    /// time (one evaluated at irregular times, as on events, counts every gap).
    pub fn set_period(&mut self, seconds: f64) {
        if seconds.is_finite() && seconds > 0.0 {
            self.period = seconds;
        }
    }

    /// The MOOS time the supervisor did not watch so far: the excess of each gap between two
    /// of its evaluations over `max_gap` (or twice its period, if longer). A machine that
    /// stalls the whole community (every app, the drivers and the supervisor) for a while
    /// moves MOOS time on without anyone posting; that time is no evidence of a silent sensor,
    /// and `stale`/`silent` ages leave it out. In lockstep the gaps are the period: always 0.
    pub fn unwatched(&self) -> f64 {
        self.unwatched
    }

    /// The age at `now` of something last heard at `last` (`None`: since the start), the
    /// unwatched time since then left out.
    fn age(&self, last: Option<f64>, unwatched_then: Option<f64>, now: f64) -> f64 {
        let start = self.start.unwrap_or(now);
        let since = match last {
            Some(_) => self.unwatched - unwatched_then.unwrap_or(0.0),
            None => self.unwatched,
        };
        (now - last.unwrap_or(start) - since).max(0.0)
    }

    /// The configuration.
    pub fn config(&self) -> &SafetyConfig {
        &self.cfg
    }

    /// The configuration errors (MALCONFIG when not empty).
    pub fn errors(&self) -> &[String] {
        &self.errors
    }

    /// True when the configuration has errors.
    pub fn malconfig(&self) -> bool {
        !self.errors.is_empty()
    }

    /// The phase.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// Each rule with its state.
    pub fn rules(&self) -> impl Iterator<Item = (&Rule, &RuleState)> {
        self.cfg.rules.iter().zip(&self.states)
    }

    /// The rule commanding the vehicle, if any.
    pub fn commander(&self) -> Option<&Rule> {
        self.commander.map(|i| &self.cfg.rules[i])
    }

    /// True while pSafety holds the helm off and drives the actuators.
    pub fn on_actuators(&self) -> bool {
        self.taken_over
    }

    /// The variables to register for.
    pub fn subscriptions(&self) -> Vec<String> {
        let mut v: Vec<String> = Vec::new();
        let mut add = |s: &str| {
            if !v.iter().any(|x| x == s) {
                v.push(s.to_string());
            }
        };
        for r in &self.cfg.rules {
            for t in &r.terms {
                match t {
                    Term::Compare { var, .. } | Term::Stale { var, .. } => add(var),
                    Term::Silent { .. } => {}
                }
            }
        }
        let mut status: Vec<&String> = self.status_vars.keys().collect();
        status.sort();
        for s in status {
            add(s);
        }
        for s in [
            self.cfg.depth_var.as_str(),
            self.cfg.override_var.as_str(),
            RESET_VAR,
            HELM_STATE_VAR,
        ] {
            if !s.is_empty() {
                add(s);
            }
        }
        v
    }

    /// Takes one piece of mail of `key` from `source` posted at `time`.
    pub fn on_mail(&mut self, key: &str, value: &Value, source: &str, time: f64) {
        let unwatched = self.unwatched;
        if let Some(app) = self.status_vars.get(key) {
            set(&mut self.heard, app, (time, unwatched));
        }
        if let Some((t, u)) = self.heard.get_mut(source) {
            *t = t.max(time);
            *u = unwatched;
        } else if self.status_vars.values().any(|a| a == source) {
            self.heard.insert(source.to_string(), (time, unwatched));
        }
        if key == RESET_VAR
            && let Some(s) = value.as_str()
        {
            self.resets.push(s.trim().to_string());
        }
        if key == HELM_STATE_VAR && source == self.cfg.helm_app {
            self.helm_state = value.as_str().map(str::to_string);
        }
        if !self.cfg.override_var.is_empty()
            && key == self.cfg.override_var
            && as_bool(value) == Some(false)
        {
            self.override_released = true;
        }
        match self.values.get_mut(key) {
            Some(seen) => {
                seen.value.clone_from(value);
                seen.time = time;
                seen.unwatched = unwatched;
            }
            None => {
                let seen = Seen {
                    value: value.clone(),
                    time,
                    unwatched,
                };
                self.values.insert(key.to_string(), seen);
            }
        }
    }

    /// OnStartUp at `now`: silence and staleness count from here; a MALCONFIG supervisor
    /// takes the helm off at once.
    pub fn start(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Notice>) {
        self.start = Some(now);
        if self.malconfig() {
            self.post_override(out);
            for e in &self.errors {
                notes.push(Notice::Warning(format!("MALCONFIG: {e}")));
            }
        }
        self.post_words(out);
    }

    fn depth(&self) -> Option<f64> {
        self.values
            .get(&self.cfg.depth_var)
            .and_then(|seen| seen.value.as_f64())
    }

    /// Whether `t` holds at `now` (evaluated every iteration: no text is built).
    fn holds(&self, t: &Term, now: f64) -> bool {
        match t {
            Term::Compare { var, op, value } => {
                let Some(Seen { value: v, .. }) = self.values.get(var) else {
                    return false;
                };
                match value {
                    Operand::Number(x) => {
                        let n = v
                            .as_f64()
                            .or_else(|| v.as_str().and_then(|s| s.trim().parse::<f64>().ok()));
                        n.is_some_and(|n| op.holds(n, *x))
                    }
                    Operand::Bool(b) => {
                        as_bool(v).is_some_and(|a| (a == *b) == (*op == crate::rule::Op::Eq))
                    }
                    Operand::Word(w) => v.as_str().is_some_and(|s| {
                        s.trim().eq_ignore_ascii_case(w) == (*op == crate::rule::Op::Eq)
                    }),
                }
            }
            Term::Stale { var, seconds } => self.stale_age(var, now) > *seconds,
            Term::Silent { app, seconds } => self.silent_age(app, now) > *seconds,
        }
    }

    /// What was seen of `t` at `now`, for a trigger's reason.
    fn seen(&self, t: &Term, now: f64) -> String {
        match t {
            Term::Compare { var, .. } => match self.values.get(var) {
                None => format!("{var} never received"),
                Some(seen) => format!("{var}={}", show(&seen.value)),
            },
            Term::Stale { var, .. } => {
                let age = self.stale_age(var, now);
                match self.values.get(var) {
                    Some(_) => format!("no {var} for {age:.1} s"),
                    None => format!("no {var} since start ({age:.1} s)"),
                }
            }
            Term::Silent { app, .. } => {
                format!("{app} silent for {:.1} s", self.silent_age(app, now))
            }
        }
    }

    /// Seconds since `var`'s latest mail (or the start), time not watched left out.
    fn stale_age(&self, var: &str, now: f64) -> f64 {
        let seen = self.values.get(var);
        self.age(seen.map(|s| s.time), seen.map(|s| s.unwatched), now)
    }

    /// Seconds since `app` was last heard (or the start), time not watched left out.
    fn silent_age(&self, app: &str, now: f64) -> f64 {
        let heard = self.heard.get(app);
        self.age(heard.map(|h| h.0), heard.map(|h| h.1), now)
    }

    fn event(&self, text: String, out: &mut Vec<Post>, notes: &mut Vec<Notice>) {
        out.push(Post::text(EVENT_VAR, text.as_str()));
        notes.push(Notice::Event(text));
    }

    fn update_rules(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Notice>) {
        let resets = std::mem::take(&mut self.resets);
        for i in 0..self.cfg.rules.len() {
            let rule = &self.cfg.rules[i];
            let holds = rule.terms.iter().all(|t| self.holds(t, now));
            let st = &self.states[i];
            if !st.active {
                if holds {
                    let seen: Vec<String> = rule.terms.iter().map(|t| self.seen(t, now)).collect();
                    let reason = format!("{} ({})", rule.condition_text(), seen.join(", "));
                    let text = format!(
                        "trigger={},action={},priority={},reason={reason}",
                        rule.name,
                        rule.action.as_str(),
                        rule.priority
                    );
                    if rule.action == Action::Warn {
                        notes.push(Notice::Warning(format!("{}: {reason}", rule.name)));
                    }
                    let st = &mut self.states[i];
                    st.active = true;
                    st.triggers += 1;
                    st.since = Some(now);
                    st.reason = reason;
                    st.false_since = None;
                    self.event(text, out, notes);
                }
                continue;
            }
            if holds {
                self.states[i].false_since = None;
                continue;
            }
            let false_since = *self.states[i].false_since.get_or_insert(now);
            let released = match rule.release {
                Release::Clear(s) => (now - false_since >= s).then_some("cleared"),
                Release::Latch => resets
                    .iter()
                    .any(|r| r.eq_ignore_ascii_case(&rule.name) || r.eq_ignore_ascii_case("all"))
                    .then_some("reset"),
            };
            if let Some(how) = released {
                let text = format!("clear={},by={how}", rule.name);
                if rule.action == Action::Warn {
                    let reason = format!("{}: {}", rule.name, self.states[i].reason);
                    notes.push(Notice::Event(format!("retract: {reason}")));
                }
                self.states[i].active = false;
                self.states[i].false_since = None;
                self.event(text, out, notes);
            }
        }
        for r in &resets {
            let held = self.cfg.rules.iter().zip(&self.states).any(|(rule, st)| {
                st.active
                    && st.false_since.is_none()
                    && (r.eq_ignore_ascii_case(&rule.name) || r.eq_ignore_ascii_case("all"))
            });
            if held {
                notes.push(Notice::Event(format!(
                    "reset {r} refused: the condition still holds"
                )));
            }
        }
    }

    /// The commanding rule: the triggered non-warn rule of highest priority (then the more
    /// drastic action, then block order).
    fn pick(&self) -> Option<usize> {
        (0..self.cfg.rules.len())
            .filter(|&i| self.states[i].active && self.cfg.rules[i].action != Action::Warn)
            .min_by_key(|&i| {
                let r = &self.cfg.rules[i];
                (r.priority, std::cmp::Reverse(r.action), i)
            })
    }

    fn post_flags(flags: &[Flag], out: &mut Vec<Post>) {
        for f in flags {
            out.push(Post::new(f.var.as_str(), f.value.clone()));
        }
    }

    fn post_override(&self, out: &mut Vec<Post>) {
        if !self.cfg.override_var.is_empty() {
            out.push(Post::text(self.cfg.override_var.as_str(), "true"));
        }
    }

    fn take_over(&mut self, out: &mut Vec<Post>) {
        if !self.taken_over {
            self.post_override(out);
            self.taken_over = true;
        }
    }

    fn actuators(&self, thrust: f64, elevator: f64, out: &mut Vec<Post>) {
        for (var, x) in [
            (&self.cfg.thrust_var, thrust),
            (&self.cfg.elevator_var, elevator),
            (&self.cfg.rudder_var, 0.0),
        ] {
            if !var.is_empty() {
                out.push(Post::double(var.as_str(), x));
            }
        }
    }

    /// Why the helm cannot be trusted to bring the vehicle up, if it cannot.
    fn helm_failure(&self, s: &Surfacing, now: f64) -> Option<String> {
        let heard = self.heard.get(&self.cfg.helm_app);
        let silent = self.age(heard.map(|h| h.0), heard.map(|h| h.1), now);
        if silent > self.cfg.helm_timeout {
            return Some(format!("{} silent for {silent:.1} s", self.cfg.helm_app));
        }
        if self
            .helm_state
            .as_deref()
            .is_some_and(|s| s.eq_ignore_ascii_case("MALCONFIG"))
        {
            return Some(format!("{} is in MALCONFIG", self.cfg.helm_app));
        }
        if now - s.since > self.cfg.helm_grace
            && let (Some(d0), Some(d)) = (s.start_depth, self.depth())
            && d > d0 - HELM_ASCENT_M
            && d >= self.cfg.surface_depth
        {
            return Some(format!(
                "no ascent in {:.0} s (depth {d:.2} m from {d0:.2} m)",
                now - s.since
            ));
        }
        None
    }

    fn enter(&mut self, phase: Phase, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Notice>) {
        let from = self.phase;
        self.phase = phase;
        match phase {
            Phase::Ok | Phase::Warn => {
                if !matches!(from, Phase::Ok | Phase::Warn) {
                    Self::post_flags(&self.cfg.clear_flags, out);
                    if self.taken_over && !self.malconfig() {
                        // The override stays: the operator resumes the mission.
                        self.taken_over = false;
                    }
                    self.surfacing = None;
                }
                self.event(format!("mode={}", phase.word()), out, notes);
            }
            Phase::Return => {
                Self::post_flags(&self.cfg.return_flags, out);
                self.event("mode=RETURN".into(), out, notes);
            }
            Phase::AllStop => {
                self.take_over(out);
                Self::post_flags(&self.cfg.allstop_flags, out);
                self.surfacing = None;
                self.event("mode=ALLSTOP".into(), out, notes);
            }
            Phase::Surfacing => {
                let mut s = Surfacing {
                    since: now,
                    start_depth: self.depth(),
                    direct: self.cfg.surface_via == SurfaceVia::Direct || self.taken_over,
                    up_since: None,
                };
                // A helm that has already failed is not asked.
                let failed = if s.direct {
                    None
                } else {
                    self.helm_failure(&s, now)
                };
                s.direct |= failed.is_some();
                self.surfacing = Some(s);
                if s.direct {
                    self.take_over(out);
                }
                Self::post_flags(&self.cfg.surface_flags, out);
                let text = match (s.direct, failed) {
                    (_, Some(why)) => format!("mode=SURFACE,via=actuators,helm_failed={why}"),
                    (true, None) => "mode=SURFACE,via=actuators".to_string(),
                    (false, None) => "mode=SURFACE,via=helm".to_string(),
                };
                self.event(text, out, notes);
            }
            Phase::Disarmed => {
                self.take_over(out);
                Self::post_flags(&self.cfg.disarm_flags, out);
                let d = self
                    .depth()
                    .map_or_else(|| "unknown".to_string(), |d| format!("{d:.2}"));
                let after = self.surfacing.map_or(0.0, |s| now - s.since);
                self.event(
                    format!("mode=DISARMED,depth={d},after={after:.1}"),
                    out,
                    notes,
                );
            }
        }
    }

    /// Judges every rule at `now` and acts; appends the postings to `out` and the appcast
    /// notices to `notes`.
    pub fn evaluate(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Notice>) {
        if self.start.is_none() {
            self.start = Some(now);
        }
        let allowed = self.cfg.max_gap.max(2.0 * self.period);
        if self.period > 0.0
            && let Some(prev) = self.last_eval
        {
            let gap = now - prev;
            if gap > allowed {
                self.unwatched += gap - allowed;
            }
        }
        self.last_eval = Some(now);
        self.update_rules(now, out, notes);
        self.commander = self.pick();
        let command = self
            .commander
            .map(|i| self.cfg.rules[i].action)
            .or_else(|| self.states.iter().any(|s| s.active).then_some(Action::Warn));
        let target = match command {
            None => Phase::Ok,
            Some(Action::Warn) => Phase::Warn,
            Some(Action::Return) => Phase::Return,
            Some(Action::AllStop) => Phase::AllStop,
            Some(Action::SurfaceDisarm) => match self.phase {
                Phase::Disarmed => Phase::Disarmed,
                _ => Phase::Surfacing,
            },
        };
        if target != self.phase {
            self.enter(target, now, out, notes);
        }
        match self.phase {
            Phase::Surfacing => self.surface_step(now, out, notes),
            Phase::AllStop | Phase::Disarmed => self.actuators(0.0, 0.0, out),
            _ => {}
        }
        if self.override_released && (self.taken_over || self.malconfig()) {
            self.post_override(out);
            let why = if self.malconfig() {
                "MALCONFIG: deployment refused"
            } else {
                self.phase.word()
            };
            notes.push(Notice::Event(format!("manual override held ({why})")));
        }
        self.override_released = false;
        self.post_words(out);
    }

    fn surface_step(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Notice>) {
        let Some(mut s) = self.surfacing else {
            return;
        };
        if !s.direct
            && let Some(why) = self.helm_failure(&s, now)
        {
            s.direct = true;
            self.take_over(out);
            self.event(
                format!("helm_failed={why},mode=SURFACE,via=actuators"),
                out,
                notes,
            );
        }
        let up = match self.depth() {
            Some(d) if d < self.cfg.surface_depth => Some(*s.up_since.get_or_insert(now)),
            _ => None,
        };
        if up.is_none() {
            s.up_since = None;
        }
        self.surfacing = Some(s);
        let timed_out = now - s.since >= self.cfg.surface_timeout;
        if up.is_some_and(|u| now - u >= self.cfg.surface_hold) || timed_out {
            if up.is_none() {
                notes.push(Notice::Warning(format!(
                    "not confirmed at the surface after {:.0} s: disarmed anyway",
                    now - s.since
                )));
            }
            self.enter(Phase::Disarmed, now, out, notes);
            self.actuators(0.0, 0.0, out);
        } else if s.direct {
            self.actuators(self.cfg.surface_thrust, self.cfg.surface_elevator, out);
        }
    }

    /// The health word (see the crate documentation's bit table).
    pub fn health(&self) -> u32 {
        let mut h = 0;
        for (r, st) in self.rules() {
            if st.active {
                h |= bits::TRIGGERED | r.kind.bit();
                if r.action == Action::Warn {
                    h |= bits::WARN;
                }
            }
        }
        h |= match self.phase {
            Phase::Return => bits::RETURN,
            Phase::AllStop => bits::ALLSTOP,
            Phase::Surfacing => bits::SURFACING,
            Phase::Disarmed => bits::DISARMED,
            Phase::Ok | Phase::Warn => 0,
        };
        if self.taken_over {
            h |= bits::ACTUATORS;
        }
        if self.malconfig() {
            h |= bits::MALCONFIG;
        }
        h
    }

    /// The mode word: the phase's, or `MALCONFIG` while nothing more drastic is under way.
    pub fn mode(&self) -> &'static str {
        match self.phase {
            Phase::Ok | Phase::Warn if self.malconfig() => "MALCONFIG",
            p => p.word(),
        }
    }

    fn post_words(&mut self, out: &mut Vec<Post>) {
        let mode = self.mode();
        if self.posted_mode != Some(mode) {
            out.push(Post::text(MODE_VAR, mode));
            self.posted_mode = Some(mode);
        }
        let h = self.health();
        if self.posted_health != Some(h) {
            out.push(Post::double(HEALTH_VAR, f64::from(h)));
            self.posted_health = Some(h);
        }
    }

    /// The appcast body: the mode, the health word and a line per rule.
    pub fn report(&self, out: &mut String) {
        let _ = writeln!(
            out,
            "Mode: {}   Health: {} (0x{:04x})   Actuators: {}",
            self.mode(),
            self.health(),
            self.health(),
            if self.taken_over { "pSafety" } else { "helm" }
        );
        if let Some(r) = self.commander() {
            let _ = writeln!(out, "Commanding: {} ({})", r.name, r.action.as_str());
        }
        for e in &self.errors {
            let _ = writeln!(out, "MALCONFIG: {e}");
        }
        let _ = writeln!(out);
        let _ = writeln!(
            out,
            "Rule            Action          Pri  State    Trig  Condition"
        );
        let _ = writeln!(
            out,
            "--------------  --------------  ---  -------  ----  ---------"
        );
        for (r, st) in self.rules() {
            let state = match (st.active, r.release) {
                (true, Release::Latch) => "LATCHED",
                (true, Release::Clear(_)) => "ACTIVE",
                (false, _) => "ok",
            };
            let _ = writeln!(
                out,
                "{:<14}  {:<14}  {:>3}  {:<7}  {:>4}  {}",
                r.name,
                r.action.as_str(),
                r.priority,
                state,
                st.triggers,
                r.condition_text()
            );
        }
    }
}
