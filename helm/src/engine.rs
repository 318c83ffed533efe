//! The helm engine: pHelmIvP's iteration (reference §4.3) over the behaviours of a `.bhv` file.
//!
//! Pure and deterministic: [`Helm::on_mail`] queues mail, [`Helm::iterate`] takes the current
//! time, applies the mail and returns the postings in the order pHelmIvP makes them. Nothing
//! here reads a clock; CPU-time fields pHelmIvP measures are posted as 0.
//!
//! Driving it from a bus (as `coug run` will): subscribe to [`Helm::subscriptions`]; each
//! tick, hand the helm the mail received since the last tick, call `iterate(now)`, publish the
//! postings (with their `aux` as the MOOS source-aux), and deliver the helm's own postings
//! back to it like any other subscriber (source [`APP_NAME`], or the name given to
//! [`Helm::with_app_name`]): pHelmIvP relies on seeing its own `IVPHELM_STATE` (deferred
//! `initialize_` lines) and on flags it posts reaching other behaviours' conditions via the
//! info buffer, which it updates directly.
//!
//! `goals_mandatory = true` all-stops with `NoGoalBehavior` when no active behaviour is a goal
//! behaviour (one whose type is not a constraint, [`Behavior::is_constraint`]).
//!
//! Not modelled: standby helms and behaviour spawning (`templating = spawn`) are refused at
//! configuration (MALCONFIG, never silently different); node reports (the contact ledger)
//! only reach the info buffer. `RESTART_HELM` is handled by the app around the engine, which
//! reads the files again ([`Helm::restart_from`]).

use behaviors::fmt::{compact, fixed, uint};
use behaviors::{Behavior, Common, Ctx, Emit, FlagKind, FlagValue, Info, Out, ParamError, PostKey};
use ivp::{Problem, Solver};
use mission::bhv::{BehaviorFile, param_name};

use crate::allstop::{AllStop, AllStopAction};
use crate::config::{ConfigError, Globals, HelmConfig};
use crate::info_buffer::InfoBuffer;
use crate::macro_expand::expand;
use crate::mode::ModeSet;
use crate::report::{BhvLine, HelmReport, Rendered};
use crate::runstate::{DurationClock, RunState};
use rustc_hash::{FxHashMap, FxHashSet};

pub use behaviors::Value;

/// The MOOS application name the helm posts under; mail from this source is its own.
pub const APP_NAME: &str = "pHelmIvP";

/// One incoming MOOS message: the workspace's one mail type.
pub use moos_types::Mail;

use moos_types::ByteString;
/// One posting of the helm (the workspace's one posting type; its `aux` is `HELM_VAR_INIT`,
/// `HELM_MODE`, `<iter>:<behaviour>`, or empty).
pub use moos_types::Post as Posting;

/// The helm state posted as `IVPHELM_STATE` (reference §4.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HelmState {
    /// Enabled, not driving.
    Park,
    /// Enabled and driving.
    Drive,
    /// Configuration problems: never drives.
    Malconfig,
    /// Yielded to another helm.
    Disabled,
}

impl HelmState {
    /// The posted string.
    pub fn as_str(self) -> &'static str {
        match self {
            HelmState::Park => "PARK",
            HelmState::Drive => "DRIVE",
            HelmState::Malconfig => "MALCONFIG",
            HelmState::Disabled => "DISABLED",
        }
    }
    fn enabled(self) -> bool {
        matches!(self, HelmState::Park | HelmState::Drive)
    }
}

/// One behaviour in the set, with the bookkeeping pHelmIvP keeps for it.
struct Slot {
    common: Common,
    bhv: Box<dyn Behavior>,
    state: RunState,
    entered: f64,
    clock: DurationClock,
    first_done: bool,
    /// The configuration-time postings went out (see [`Helm::holding`]).
    config_posted: bool,
    completed: bool,
    ok: bool,
    good_updates: u32,
    bad_updates: u32,
    prev_update: String,
    pcs: usize,
    ctr: [u32; 6],
    now_start: Option<f64>,
    /// What the behaviour posted while being configured: sent on its first iteration.
    config_out: Out,
}

impl Slot {
    fn duration(&self) -> f64 {
        self.common
            .duration
            .unwrap_or_else(|| self.bhv.default_duration())
    }
    /// Appends `good/total` updates, or `n/a` without an `updates` variable.
    fn write_update_summary(&self, out: &mut String) {
        if self.common.update_var.is_empty() {
            out.push_str("n/a");
        } else {
            uint(out, u64::from(self.good_updates));
            out.push('/');
            uint(out, u64::from(self.good_updates + self.bad_updates));
        }
    }
}

/// Why a behaviour is not running (`pc=` of `BHV_STATUS`): the text of its `k`-th condition,
/// or another reason.
enum Failed {
    Condition(usize),
    Other(String),
}

/// A behaviour message waiting to be posted: var, value and how the duplicate filter keys it
/// (the key string `<behaviour><var><tag>` is only assembled when the message is posted).
struct Message {
    var: String,
    value: Value,
    key: PostKey,
}

/// The postings of one iteration. The `Posting`s of earlier iterations are kept and
/// overwritten in place, so a steady-state iteration reuses their value strings; variable
/// names and aux fields are shared [`ByteString`]s ([`Names`]), so the app that publishes the
/// postings copies only their string values.
#[derive(Default)]
struct Outbox {
    posts: Vec<Posting>,
    len: usize,
    names: Names,
    /// Where [`Outbox::text`] writes.
    scratch: String,
}

/// Most names [`Names`] keeps before it starts afresh.
const NAMES_LIMIT: usize = 4096;

/// One shared copy of each name the helm posts under (variables, aux fields such as a
/// behaviour's name): posting a name is a reference count, not a copy.
#[derive(Default)]
struct Names {
    set: FxHashSet<ByteString>,
}

impl Names {
    fn get(&mut self, s: &str) -> ByteString {
        if s.is_empty() {
            return ByteString::new();
        }
        if let Some(n) = self.set.get(s) {
            return n.clone();
        }
        if self.set.len() >= NAMES_LIMIT {
            self.set.clear();
        }
        let n = ByteString::from(s);
        // The first clone makes the buffer a shared one; later clones only count references.
        let shared = n.clone();
        self.set.insert(n);
        shared
    }
}

impl Outbox {
    fn clear(&mut self) {
        self.len = 0;
    }
    fn as_slice(&self) -> &[Posting] {
        &self.posts[..self.len]
    }
    /// The next posting, with `var` and an empty `aux` (the caller sets value and aux).
    fn next(&mut self, var: &str) -> &mut Posting {
        let key = self.names.get(var);
        if self.len == self.posts.len() {
            self.posts.push(Posting::double(ByteString::new(), 0.0));
        }
        let p = &mut self.posts[self.len];
        self.len += 1;
        p.key = key;
        p.aux = ByteString::new();
        p
    }
    /// The next posting, with `var` and the shared `aux`.
    fn next_with_aux(&mut self, var: &str, aux: &str) -> &mut Posting {
        let aux = self.names.get(aux);
        let p = self.next(var);
        p.aux = aux;
        p
    }
    fn push(&mut self, var: &str, value: Value, aux: &str) {
        let p = self.next_with_aux(var, aux);
        p.value = value;
    }
    /// Posts a string value that `write` writes into a cleared, reused buffer; the text is
    /// copied into a shared string unless the posting in this place last iteration had the
    /// same text, which is then shared again (a steady `IVPHELM_STATE = DRIVE` costs nothing).
    fn text(&mut self, var: &str, write: impl FnOnce(&mut String)) {
        let mut buf = std::mem::take(&mut self.scratch);
        buf.clear();
        write(&mut buf);
        let p = self.next(var);
        if !matches!(&p.value, Value::String(old) if *old == *buf) {
            p.value = Value::String(ByteString::from(buf.as_str()));
        }
        self.scratch = buf;
    }
    /// Posts a copy of `text`.
    fn text_copy(&mut self, var: &str, text: &str) {
        self.text(var, |s| s.push_str(text));
    }
}

/// pHelmIvP's duplicate-post filter: the last value posted under each key.
#[derive(Default)]
struct DupFilter {
    text: FxHashMap<String, ByteString>,
    num: FxHashMap<String, f64>,
}

impl DupFilter {
    /// Whether a posting under `key` is new (updates the filter when it is).
    fn changed(&mut self, key: &str, value: &Value) -> bool {
        match value {
            Value::String(s) => match self.text.get_mut(key) {
                Some(old) if *old == *s => false,
                Some(old) => {
                    old.clone_from(s);
                    true
                }
                None => {
                    self.text.insert(key.to_string(), s.clone());
                    true
                }
            },
            Value::Double(x) => match self.num.get_mut(key) {
                Some(old) if *old == *x => false,
                Some(old) => {
                    *old = *x;
                    true
                }
                None => {
                    self.num.insert(key.to_string(), *x);
                    true
                }
            },
            // Behaviours post no binary data; were one to, it would never be filtered.
            Value::Binary(_) => true,
        }
    }
    fn clear(&mut self) {
        self.text.clear();
        self.num.clear();
    }
}

/// The helm engine. See the module docs.
///
/// ```
/// use helm::{Helm, Mail};
/// use helm::config::Globals;
/// use mission::source::SourceMap;
/// let bhv = mission::bhv::parse_bhv(&SourceMap::from_text("a.bhv",
///     "Behavior = BHV_ConstantHeading\n{\n name = ch\n heading = 90\n duration = no-time-limit\n}\n"));
/// let g = Globals { lat_origin: Some("0".into()), long_origin: Some("0".into()), community: Some("abe".into()) };
/// let mut helm = Helm::from_parsed(&[("domain", "course:0:359:360"), ("start_engaged", "true")], &g, &bhv);
/// for (var, v) in [("NAV_X", 0.0), ("NAV_Y", 0.0), ("NAV_HEADING", 0.0), ("NAV_SPEED", 0.0)] {
///     helm.on_mail(&[Mail::new(var, v, 0.0)]);
/// }
/// helm.iterate(0.0);
/// let posts = helm.iterate(1.0);
/// let hdg = posts.iter().find(|p| p.key == "DESIRED_HEADING").unwrap();
/// assert_eq!(hdg.value.as_f64(), Some(90.0));
/// ```
pub struct Helm {
    app_name: String,
    config: HelmConfig,
    errors: Vec<ConfigError>,
    ownship: String,
    /// `hold_on_apps`, each with whether DB_CLIENTS has named it yet.
    held_apps: Vec<(String, bool)>,
    info: InfoBuffer,
    modes: ModeSet,
    slots: Vec<Slot>,
    initializes: Vec<(String, Value, bool)>,
    solver: Solver,
    problem: Problem,
    state: HelmState,
    has_control: bool,
    started: bool,
    start_time: f64,
    iteration: u64,
    pending: Vec<Mail>,
    out: Outbox,
    allstop: AllStop,
    filter: DupFilter,
    key_buf: String,
    init_vars_ready: bool,
    init_vars_done: bool,
    prev_report: Rendered,
    /// Last-but-one report's buffers, reused for the next one.
    cur_report: Rendered,
    /// Report lines of earlier iterations, reused for the next report.
    line_pool: Vec<BhvLine>,
    /// `DESIRED_<VAR>` (with the helm prefix) for each domain variable, in domain order.
    desired_vars: Vec<String>,
    domain_str: String,
    lists: [String; 3],
    bhv_count: Option<usize>,
    bhv_count_ever: Option<usize>,
    state_vars: String,
    /// The state-space variables may have changed since `state_vars` was computed.
    state_vars_dirty: bool,
    completed_pending: Option<bool>,
    completed_count: Option<usize>,
    update_results: Vec<String>,
    messages: Vec<(usize, Message)>,
    /// Scratch for the parts of a `BHV_IPF` posting.
    ipf_parts: Vec<String>,
    warnings: u64,
    update_vars: String,
    rejournal: bool,
    refresh_pending: bool,
    refresh_time: f64,
    disabled_posted: bool,
    /// Set by [`Helm::restart_from`]: IVPHELM_RESTARTED is posted once decisions resume.
    restart_post_pending: bool,
    /// A `type1` restart keeps the info buffer and does not post the initializes again.
    skip_initialize: bool,
    emit: Out,
    scratch: String,
    registered: Vec<String>,
    subs_dirty: bool,
    /// The latest iteration ended in the first second of deciding (pHelmIvP returns before
    /// its appcast then).
    delayed: bool,
    /// The latest decision iteration's report (for the appcast).
    last_report: HelmReport,
    /// The latest value each variable was posted with by a behaviour (the appcast's table;
    /// pHelmIvP's `m_outgoing_*` maps), by variable name.
    outgoing: std::collections::BTreeMap<String, Outgoing>,
    /// Node reports from other vehicles (`IVPHELM_LEDGER_SUMMARY`).
    ledger: crate::ledger::ContactLedger,
    /// Contacts `BHV_ABLE_FILTER` disabled spawning for.
    disabled_contacts: crate::ledger::DisabledContacts,
    /// Run warnings and events for the appcast, oldest first.
    notes: Vec<AppcastNote>,
}

/// A behaviour's latest posting of a variable.
#[derive(Debug, Clone)]
struct Outgoing {
    value: Value,
    time: f64,
    bhv: String,
    iter: u64,
}

/// What the helm reports for its appcast: the workspace's one appcast note type.
pub use appcast::Note as AppcastNote;

fn auto_value(v: &str) -> Value {
    let t = v.trim();
    if mission::condition::is_numeric(t)
        && let Ok(x) = t.parse::<f64>()
    {
        return Value::Double(x);
    }
    if t.len() >= 2 && t.starts_with('"') && t.ends_with('"') {
        return Value::text(&t[1..t.len() - 1]);
    }
    Value::text(t)
}

impl Helm {
    /// A helm from a parsed `.moos` mission (its `pHelmIvP` block and globals) and a parsed
    /// `.bhv` file. A missing `pHelmIvP` block is a configuration error.
    pub fn from_mission(
        moos: &mission::moos::MissionFile,
        bhv: &mission::Parsed<BehaviorFile>,
    ) -> Helm {
        let globals = Globals::from_mission(moos);
        match moos.process("pHelmIvP") {
            Some(p) => {
                let params: Vec<(&str, &str)> = p
                    .entries
                    .iter()
                    .map(|e| (e.key.as_str(), e.value.as_str()))
                    .collect();
                Helm::from_parsed(&params, &globals, bhv)
            }
            None => {
                let mut h = Helm::from_config::<&str, &str>(&[], &globals, &bhv.value);
                h.errors.push(ConfigError::Behavior(
                    "No ProcessConfig = pHelmIvP block".into(),
                ));
                h.state = HelmState::Malconfig;
                h
            }
        }
    }

    /// A helm from its ProcessConfig parameters, the globals and a parsed `.bhv` file whose
    /// diagnostics (bad lines) count as configuration errors.
    pub fn from_parsed<K: AsRef<str>, V: AsRef<str>>(
        params: &[(K, V)],
        globals: &Globals,
        bhv: &mission::Parsed<BehaviorFile>,
    ) -> Helm {
        let mut h = Helm::from_config(params, globals, &bhv.value);
        for d in bhv.errors() {
            h.errors.push(ConfigError::Behavior(format!(
                "{}: Line {}: {}",
                d.span.file_name(),
                d.span.line,
                d.message
            )));
        }
        if !h.errors.is_empty() {
            h.state = HelmState::Malconfig;
            h.has_control = false;
        }
        h
    }

    /// A helm from its ProcessConfig parameters (file order), the globals and a `.bhv` file.
    /// Never fails: any problem puts the helm in MALCONFIG, and [`Helm::config_errors`] says
    /// why (they are also posted as `IVPHELM_CONFIG_WARNING` on the first iteration).
    pub fn from_config<K: AsRef<str>, V: AsRef<str>>(
        params: &[(K, V)],
        globals: &Globals,
        bhv: &BehaviorFile,
    ) -> Helm {
        let (config, mut errors) = HelmConfig::parse(params, globals);
        let ownship = globals.community.clone().unwrap_or_default();
        let info = InfoBuffer::new();
        let mut slots: Vec<Slot> = Vec::new();
        for spec in &bhv.behaviors {
            let Some(b) = behaviors::create(&spec.kind) else {
                errors.push(ConfigError::Behavior(format!(
                    "{}: Line {}: unknown behavior type {}",
                    spec.span.file_name(),
                    spec.span.line,
                    spec.kind
                )));
                continue;
            };
            let mut common = Common::new(b.kind());
            common.name = b.default_name().to_string();
            let mut slot = Slot {
                common,
                bhv: b,
                state: RunState::New,
                entered: 0.0,
                clock: DurationClock::default(),
                first_done: false,
                config_posted: false,
                completed: false,
                ok: true,
                good_updates: 0,
                bad_updates: 0,
                prev_update: String::new(),
                pcs: 0,
                ctr: [0; 6],
                now_start: None,
                config_out: Out::default(),
            };
            for p in &spec.params {
                let key = param_name(&p.key);
                let res = apply_param(&mut slot, &key, &p.value, &info, &config, &ownship);
                if let Err(e) = res {
                    errors.push(ConfigError::Behavior(format!(
                        "{}: Line {}: {} = {} ({e})",
                        p.span.file_name(),
                        p.span.line,
                        p.key,
                        p.value
                    )));
                }
            }
            // The C++ helm gives every loaded behaviour its own name as `us`.
            slot.common.us = None;
            if slots.iter().any(|s| s.common.name == slot.common.name) {
                errors.push(ConfigError::Behavior(format!(
                    "{}: Line {}: duplicate behavior name {}",
                    spec.span.file_name(),
                    spec.span.line,
                    slot.common.name
                )));
                continue;
            }
            {
                let ctx = Ctx {
                    info: &info,
                    domain: &config.domain,
                    ownship: &ownship,
                    name: &slot.common.name,
                    perpetual: slot.common.perpetual,
                };
                slot.bhv.on_set_param_complete(&ctx, &mut slot.config_out);
            }
            slots.push(slot);
        }
        let initializes = bhv
            .initializes
            .iter()
            .map(|i| (i.var.trim().to_string(), auto_value(&i.value), i.deferred))
            .collect();
        let state = if errors.is_empty() {
            HelmState::Park
        } else {
            HelmState::Malconfig
        };
        let has_control = config.start_engaged && errors.is_empty();
        let problem = Problem::new(config.domain.clone());
        let held_apps = config
            .hold_on_apps
            .iter()
            .map(|a| (a.clone(), false))
            .collect();
        let mut helm = Helm {
            app_name: APP_NAME.to_string(),
            modes: ModeSet::new(&bhv.modes),
            held_apps,
            config,
            errors,
            ownship,
            info,
            slots,
            initializes,
            solver: Solver::new(),
            problem,
            state,
            has_control,
            started: false,
            start_time: 0.0,
            iteration: 0,
            pending: Vec::new(),
            out: Outbox::default(),
            allstop: AllStop::default(),
            filter: DupFilter::default(),
            key_buf: String::new(),
            init_vars_ready: false,
            init_vars_done: false,
            prev_report: Rendered::default(),
            cur_report: Rendered::default(),
            line_pool: Vec::new(),
            desired_vars: Vec::new(),
            domain_str: String::new(),
            lists: Default::default(),
            bhv_count: None,
            bhv_count_ever: None,
            state_vars: String::new(),
            state_vars_dirty: true,
            completed_pending: None,
            completed_count: None,
            update_results: Vec::new(),
            messages: Vec::new(),
            ipf_parts: Vec::new(),
            warnings: 0,
            update_vars: String::new(),
            rejournal: false,
            refresh_pending: false,
            refresh_time: 0.0,
            disabled_posted: false,
            restart_post_pending: false,
            skip_initialize: false,
            emit: Out::default(),
            scratch: String::new(),
            registered: Vec::new(),
            subs_dirty: false,
            delayed: false,
            last_report: HelmReport::default(),
            outgoing: std::collections::BTreeMap::new(),
            ledger: crate::ledger::ContactLedger::new(45.0),
            disabled_contacts: crate::ledger::DisabledContacts::default(),
            notes: Vec::new(),
        };
        helm.ledger = crate::ledger::ContactLedger::new(helm.config.contact_max_age);
        helm.registered = helm.wanted_subscriptions();
        helm.desired_vars = helm
            .config
            .domain
            .vars()
            .iter()
            .map(|v| {
                let upper = v.name().to_ascii_uppercase();
                if upper == "COURSE" {
                    format!("{}DESIRED_HEADING", helm.config.helm_prefix)
                } else {
                    format!("{}DESIRED_{upper}", helm.config.helm_prefix)
                }
            })
            .collect();
        helm
    }

    /// Sets the MOOS application name the helm runs as (default `pHelmIvP`); mail from this
    /// source is the helm's own (not skew-checked, and its `IVPHELM_STATE` does not disable
    /// the helm).
    pub fn with_app_name(mut self, name: &str) -> Self {
        self.app_name = name.to_string();
        self
    }

    /// Adds a configuration problem found outside the engine (e.g. a behaviour file that
    /// cannot be read): the helm goes to MALCONFIG, as pHelmIvP does on any config warning
    /// before its first iteration, and never drives.
    ///
    /// ```
    /// use helm::{Helm, HelmState};
    /// use helm::config::{ConfigError, Globals};
    /// let bhv = mission::bhv::BehaviorFile::default();
    /// let mut h = Helm::from_config(&[("domain", "course:0:359:360")], &Globals::default(), &bhv);
    /// h.add_config_error(ConfigError::Behavior("behaviour file `x.bhv` not found".into()));
    /// assert_eq!(h.state(), HelmState::Malconfig);
    /// ```
    pub fn add_config_error(&mut self, error: ConfigError) {
        self.errors.push(error);
        self.state = HelmState::Malconfig;
        self.has_control = false;
    }

    /// The configuration problems (empty unless MALCONFIG).
    pub fn config_errors(&self) -> &[ConfigError] {
        &self.errors
    }
    /// The current helm state.
    pub fn state(&self) -> HelmState {
        self.state
    }
    /// The decision domain (in pHelmIvP's order).
    pub fn domain(&self) -> &ivp::Domain {
        &self.config.domain
    }
    /// The info buffer.
    pub fn info(&self) -> &InfoBuffer {
        &self.info
    }
    /// Names of the behaviours still in the set, in order.
    pub fn behavior_names(&self) -> Vec<&str> {
        self.slots.iter().map(|s| s.common.name.as_str()).collect()
    }
    /// The variables the helm subscribes to (reference §4.3 registrations): its own, the mode
    /// conditions' variables, and every variable a behaviour reads (conditions, flag
    /// conditions, `updates`, `duration_reset`,
    /// `nostarve` and [`Behavior::info_vars`], e.g. `GPS_UPDATE_RECEIVED`). The list only
    /// grows: a run-time update that makes a behaviour read a new variable adds it (and the
    /// helm posts `IVPHELM_REGISTER = <var>` for it, as pHelmIvP registers new info vars).
    /// New variables are appended, so a caller that remembers how many it has registered
    /// finds the new ones past that length (an unchanged length: nothing new), without a copy.
    pub fn subscriptions(&self) -> &[String] {
        &self.registered
    }

    /// The variables the helm and its behaviours read now.
    fn wanted_subscriptions(&self) -> Vec<String> {
        let mut v: Vec<String> = [
            "DB_CLIENTS",
            "MOOS_MANUAL_OVERIDE",
            "MOOS_MANUAL_OVERRIDE",
            "RESTART_HELM",
            "IVPHELM_REJOURNAL",
            "BHV_ABLE_FILTER",
            "NAV_X",
            "NAV_Y",
            "NAV_SPEED",
            "NAV_HEADING",
            "NAV_DEPTH",
            "HELM_MAP_CLEAR",
            "AIS_REPORT",
            "NODE_REPORT",
            "AIS_REPORT_LOCAL",
            "NODE_REPORT_LOCAL",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        if !self.config.other_override_var.is_empty() {
            v.push(self.config.other_override_var.clone());
        }
        let push = |v: &mut Vec<String>, s: &str| {
            if !s.is_empty() && !v.iter().any(|x| x == s) {
                v.push(s.to_string());
            }
        };
        let mut bhv_vars = Vec::new();
        // pHelmIvP also registers the variables of the mode declarations' conditions.
        for var in self.modes.condition_vars() {
            push(&mut v, var);
        }
        for s in &self.slots {
            for (_, c) in &s.common.conditions {
                for var in c.variables() {
                    push(&mut v, var);
                }
            }
            for k in FlagKind::ALL {
                for f in s.common.flags(k) {
                    if let Some(c) = &f.condition {
                        for var in c.variables() {
                            push(&mut v, var);
                        }
                    }
                }
            }
            if let Some((var, _)) = &s.common.duration_reset {
                push(&mut v, var);
            }
            push(&mut v, &s.common.update_var);
            for (var, _) in &s.common.starve {
                push(&mut v, var);
            }
            s.bhv.info_vars(&mut bhv_vars);
        }
        for var in &bhv_vars {
            push(&mut v, var);
        }
        for var in self.initializes.iter().filter(|i| i.2).map(|i| i.0.clone()) {
            push(&mut v, &var);
        }
        push(&mut v, "IVPHELM_STATE");
        v
    }

    /// Adds the variables behaviours read now but the helm has not registered yet (after a
    /// run-time update), posting `IVPHELM_REGISTER` for each.
    fn refresh_subscriptions(&mut self) {
        for var in self.wanted_subscriptions() {
            if !self.registered.contains(&var) {
                self.registered.push(var.clone());
                self.notify("IVPHELM_REGISTER", Value::String(var.into()), "");
            }
        }
    }

    /// Queues mail for the next [`Helm::iterate`].
    pub fn on_mail<'a>(&mut self, mail: impl IntoIterator<Item = &'a Mail>) {
        let holding = self.held_apps.iter().any(|(_, seen)| !seen);
        for m in mail {
            // hold_on_apps: note each app named in DB_CLIENTS (pHelmIvP `checkHoldOnApps`).
            if holding
                && m.key == "DB_CLIENTS"
                && let Value::String(list) = &m.value
            {
                for (app, seen) in &mut self.held_apps {
                    *seen |= list.split(',').any(|c| c.trim() == app.as_str());
                }
            }
            self.pending.push(m.clone());
        }
    }

    /// Makes this freshly built helm the restart of `old` (pHelmIvP `RESTART_HELM`): it keeps
    /// `old`'s control (manual override), its pending mail and, for `type1` (`keep_info`),
    /// its info buffer without posting the initializes again (`type2` starts a fresh
    /// buffer and posts them). It starts over (registrations, domain, mode set) at its next
    /// iteration and posts `IVPHELM_RESTARTED = true` once it decides again.
    pub fn restart_from(&mut self, old: Helm, keep_info: bool) {
        self.has_control = old.has_control && self.errors.is_empty();
        self.pending = old.pending;
        self.held_apps = old.held_apps;
        if keep_info {
            self.info = old.info;
            self.skip_initialize = true;
        }
        self.restart_post_pending = true;
    }

    /// True while an app of `hold_on_apps` has not yet appeared in DB_CLIENTS: the
    /// behaviours' configuration-time postings (MOOS's helm start messages) wait.
    pub fn holding(&self) -> bool {
        self.held_apps.iter().any(|(_, seen)| !seen)
    }

    fn notify(&mut self, var: &str, value: Value, aux: &str) {
        self.out.push(var, value, aux);
    }

    fn startup(&mut self, now: f64) {
        self.started = true;
        self.start_time = now;
        if self.state == HelmState::Malconfig {
            for e in self.errors.clone() {
                self.notify("IVPHELM_CONFIG_WARNING", Value::text(e.to_string()), "");
            }
            return;
        }
        for (var, value, deferred) in self.initializes.clone() {
            if !deferred && !self.skip_initialize {
                self.info.set(&var, value.clone(), APP_NAME, now);
                self.notify(&var, value, "HELM_VAR_INIT");
            }
        }
        for var in self.registered.clone() {
            self.notify("IVPHELM_REGISTER", Value::String(var.into()), "");
        }
        // pHelmIvP keeps the files in a set: one request per file, in name order.
        let mut files = self.config.behavior_files.clone();
        files.sort();
        for f in files {
            self.notify(
                "PLOGGER_CMD",
                Value::String(format!("COPY_FILE_REQUEST = {f}").into()),
                "",
            );
        }
        let dom = self.config.domain.to_string();
        self.domain_str.clone_from(&dom);
        self.notify("IVPHELM_DOMAIN", Value::String(dom.into()), "");
        let ms = self.modes.definition();
        self.notify("IVPHELM_MODESET", Value::String(ms.into()), "");
        for var in [
            "IVPHELM_BHV_ACTIVE_CNT",
            "IVPHELM_BHV_IDLE_CNT",
            "IVPHELM_BHV_RUNNING_CNT",
            "IVPHELM_BHV_DISABLED_CNT",
        ] {
            self.notify(var, Value::Double(0.0), "");
        }
        if !self.config.helm_alias.is_empty() {
            let a = self.config.helm_alias.clone();
            self.notify("IVPHELM_ALIAS", Value::String(a.into()), "");
        }
    }

    fn status_update(&mut self) {
        self.state = match self.state {
            HelmState::Drive if !self.has_control => HelmState::Park,
            HelmState::Park if self.has_control => HelmState::Drive,
            s => s,
        };
    }

    fn handle_mail(&mut self, now: f64) {
        let mail = std::mem::take(&mut self.pending);
        for m in &mail {
            if self.state == HelmState::Disabled {
                break;
            }
            if let Some(ok) = self.config.ok_skew {
                let skew = (now - m.time).abs().min(now - self.start_time);
                if skew > ok && m.source != self.app_name && m.key != "HELM_MAP_CLEAR" {
                    let mut msg = format!(
                        "Helm ignores MOOS msg due to skew: {} Source={} Skew=",
                        m.key, m.source
                    );
                    fixed(&mut msg, skew, 2);
                    self.notes.push(AppcastNote::Warning(msg.clone()));
                    msg.push_str(" curr_time: ");
                    fixed(&mut msg, now, 3);
                    self.notify("IVPHELM_SKEW", Value::String(msg.into()), "");
                    continue;
                }
            }
            let is_override = m.key == "MOOS_MANUAL_OVERRIDE"
                || m.key == "MOOS_MANUAL_OVERIDE"
                || (!self.config.other_override_var.is_empty()
                    && m.key == self.config.other_override_var);
            if is_override {
                if let Value::String(s) = &m.value {
                    if s.trim().eq_ignore_ascii_case("false") {
                        self.has_control = self.state != HelmState::Malconfig;
                    } else if s.trim().eq_ignore_ascii_case("true") && self.config.allow_park {
                        self.has_control = false;
                    }
                    self.status_update();
                }
                self.info.set(&m.key, m.value.clone(), &m.source, m.time);
            } else if m.key == "IVPHELM_STATE" {
                self.init_vars_ready = true;
                let other = m.source != self.app_name;
                if other
                    && m.value.as_str() != Some("STANDBY")
                    && self.state.enabled()
                    && self.config.standby.is_none()
                {
                    self.post_allstop("DisabledByStandbyHelm");
                    self.state = HelmState::Disabled;
                }
            } else if m.key == "IVPHELM_REJOURNAL" {
                self.rejournal = true;
            } else if m.key == "BHV_ABLE_FILTER" {
                // BehaviorSet: every behaviour sees the filter (only contact behaviours act
                // on it, none of coug's yet), then the helm's spawn blacklist.
                if let Value::String(s) = &m.value {
                    self.disabled_contacts.apply(s);
                }
            } else if m.key == "NODE_REPORT_LOCAL" {
                self.node_report_local(&m.value, now);
            } else if matches!(&*m.key, "AIS_REPORT" | "NODE_REPORT" | "AIS_REPORT_LOCAL") {
                self.node_report(&m.value, now);
                self.info.set(&m.key, m.value.clone(), &m.source, m.time);
            } else if m.key == "HELM_MAP_CLEAR" {
                self.refresh_pending = true;
            } else if m.source_aux != "HELM_VAR_INIT" {
                self.info.set(&m.key, m.value.clone(), &m.source, m.time);
            }
        }
        self.pending = mail;
        self.pending.clear();
    }

    /// A node report from another vehicle (pHelmIvP `processNodeReport`): into the ledger,
    /// and its group and type into the info buffer as `<VNAME>_NAV_GROUP` / `_NAV_TYPE`
    /// (for a rejected report the C++ sets `_NAV_GROUP` and `_NAV_TYPE`, empty, too).
    fn node_report(&mut self, value: &Value, now: f64) {
        let text = match value {
            Value::String(s) => &s[..],
            _ => "",
        };
        let report = crate::ledger::NodeReport::parse(text);
        let name = match self.ledger.process(&report, now) {
            Ok(name) => name,
            Err(why) => {
                self.notes
                    .push(AppcastNote::Warning(format!("Bad NodeReport: {text}")));
                self.notes
                    .push(AppcastNote::Warning(format!("The issue: {why}")));
                String::new()
            }
        };
        let (group, vtype) = match self.ledger.get(&name) {
            Some(c) => (c.group.clone(), c.vtype.clone()),
            None => (String::new(), String::new()),
        };
        let upper = name.to_ascii_uppercase();
        self.info.set(
            &format!("{upper}_NAV_GROUP"),
            Value::String(group.into()),
            APP_NAME,
            now,
        );
        self.info.set(
            &format!("{upper}_NAV_TYPE"),
            Value::String(vtype.into()),
            APP_NAME,
            now,
        );
    }

    /// The vehicle's own report (pHelmIvP `processNodeReportLocal`): only its group, type,
    /// color and length reach the info buffer, as `<VNAME>_NAV_*`; the report itself does
    /// not.
    fn node_report_local(&mut self, value: &Value, now: f64) {
        let text = match value {
            Value::String(s) => &s[..],
            _ => "",
        };
        let r = crate::ledger::NodeReport::parse(text);
        let upper = r.name.to_ascii_uppercase();
        if upper.is_empty() {
            self.notes
                .push(AppcastNote::Warning("Unhandled NODE_REPORT_LOCAL".into()));
            return;
        }
        for (suffix, v) in [("GROUP", r.group), ("TYPE", r.vtype), ("COLOR", r.color)] {
            if !v.is_empty() {
                self.info.set(
                    &format!("{upper}_NAV_{suffix}"),
                    Value::String(v.into()),
                    APP_NAME,
                    now,
                );
            }
        }
        if let Some(len) = r.length_m.filter(|&l| l != 0.0) {
            self.info.set(
                &format!("{upper}_NAV_LENGTH"),
                Value::Double(len),
                APP_NAME,
                now,
            );
        }
    }

    /// Keeps at most this many untaken notes (the oldest go first).
    const MAX_APPCAST_NOTES: usize = appcast::MAX_NOTES;

    fn cap_appcast_notes(&mut self) {
        let n = self.notes.len();
        if n > Self::MAX_APPCAST_NOTES {
            self.notes.drain(..n - Self::MAX_APPCAST_NOTES);
        }
    }

    /// Takes the run warnings reported since the last call (the appcast shows them).
    pub fn take_appcast_notes(&mut self) -> Vec<AppcastNote> {
        std::mem::take(&mut self.notes)
    }

    /// The contact ledger.
    pub fn ledger(&self) -> &crate::ledger::ContactLedger {
        &self.ledger
    }

    /// Whether `BHV_ABLE_FILTER` has disabled spawning contact behaviours for `contact`.
    pub fn contact_disabled(&self, contact: &str) -> bool {
        self.disabled_contacts.contains(contact)
    }

    fn post_allstop(&mut self, msg: &str) {
        if !self.state.enabled() {
            return;
        }
        match self.allstop.update(msg) {
            AllStopAction::None => {}
            AllStopAction::Announce(m) => {
                self.notify("IVPHELM_ALLSTOP", Value::String(m.into()), "")
            }
            AllStopAction::AnnounceAndZero(m) => {
                self.notify("IVPHELM_ALLSTOP", Value::String(m.into()), "");
                for i in 0..self.config.domain.len() {
                    let name = self.config.domain.vars()[i].name().to_ascii_uppercase();
                    let var = if name == "COURSE" {
                        "DESIRED_HEADING".to_string()
                    } else {
                        format!("DESIRED_{name}")
                    };
                    self.notify(&var, Value::Double(0.0), "");
                }
            }
        }
    }

    /// Reference §4.3 step 3: NAV_X, NAV_Y, NAV_HEADING, NAV_SPEED (and NAV_DEPTH with a
    /// depth domain) must each have been received once.
    fn nav_ready(&self) -> bool {
        ["NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"]
            .iter()
            .all(|v| self.info.is_known(v))
            && (self.config.domain.get("depth").is_none() || self.info.is_known("NAV_DEPTH"))
    }

    /// Runs one helm iteration at time `now` (seconds) with the mail queued since the last
    /// one, and returns the postings in pHelmIvP's order.
    pub fn iterate(&mut self, now: f64) -> &[Posting] {
        // Cheap when not enabled (`RUST_LOG=helm=trace` shows each iteration's events).
        let _span = tracing::trace_span!("helm_iterate", iter = self.iteration + 1, now).entered();
        self.out.clear();
        self.delayed = false;
        self.info.set_now(now);
        if !self.started {
            self.startup(now);
        }
        self.handle_mail(now);
        self.cap_appcast_notes();

        // §4.3 step 1: status, IVPHELM_STATE.
        self.status_update();
        if self.state == HelmState::Disabled {
            if !self.disabled_posted {
                self.disabled_posted = true;
                self.notify("IVPHELM_STATE", Value::String("DISABLED".into()), "");
            }
        } else {
            let s = self.state.as_str();
            self.out.text_copy("IVPHELM_STATE", s);
        }
        if !self.state.enabled() {
            self.info.clear_deltas();
            return self.out.as_slice();
        }
        // Step 3: hold for the nav solution.
        if !self.nav_ready() {
            self.info.clear_deltas();
            return self.out.as_slice();
        }
        // Step 4: deferred initializes.
        if self.init_vars_ready && !self.init_vars_done {
            self.init_vars_done = true;
            for (var, value, deferred) in self.initializes.clone() {
                if deferred && !self.info.is_known(&var) {
                    self.info.set(&var, value.clone(), APP_NAME, now);
                    self.notify(&var, value, "HELM_VAR_INIT");
                }
            }
        }
        // Step 5: the contact ledger drops stale contacts (those a behaviour still reasons
        // about get twice the time: none until contact behaviours exist) and is summarised.
        self.ledger.clear_stale(now, &[], 2.0);
        let ledger = &self.ledger;
        self.out
            .text("IVPHELM_LEDGER_SUMMARY", |s| ledger.summary(20, s));
        // Step 6: manual override.
        if !self.has_control {
            self.post_allstop("ManualOverride");
            return self.out.as_slice();
        }
        // Step 7: no decision in the first second.
        if now - self.start_time < 1.0 {
            self.delayed = true;
            return self.out.as_slice();
        }
        // After a RESTART_HELM, one confirmation once decisions resume.
        if self.restart_post_pending {
            self.restart_post_pending = false;
            self.notify("IVPHELM_RESTARTED", Value::String("true".into()), "");
        }
        self.decide(now);
        self.cap_appcast_notes();
        self.out.as_slice()
    }

    fn decide(&mut self, now: f64) {
        self.iteration += 1;
        let iter = self.iteration;
        self.update_results.clear();
        self.messages.clear();
        self.problem.clear();

        // A behaviour error halts this iteration only (MOOS resets the state each time).
        for s in &mut self.slots {
            s.ok = true;
        }
        let modes: Vec<(String, String)> = self.modes.evaluate(&mut self.info).to_vec();

        let mut report = HelmReport {
            iteration: iter,
            time: now,
            domain: None,
            modes: self.modes.summary(),
            ..HelmReport::default()
        };
        let mut halted = false;
        for i in 0..self.slots.len() {
            let f = self.produce(i, now);
            let slot = &self.slots[i];
            if !slot.ok {
                halted = true;
                report.halted = true;
                break;
            }
            // Report lines reuse the strings of earlier iterations' lines.
            let mut line = self.line_pool.pop().unwrap_or_else(|| BhvLine {
                name: String::new(),
                time: 0.0,
                updates: String::new(),
                pwt: 0.0,
                pcs: 0,
            });
            line.name.clone_from(&slot.common.name);
            line.time = slot.entered;
            line.updates.clear();
            slot.write_update_summary(&mut line.updates);
            line.pwt = slot.common.pwt;
            line.pcs = slot.pcs;
            if let Some(f) = f {
                if !self.slots[i].bhv.is_constraint() {
                    report.active_goal = true;
                }
                let name = &self.slots[i].common.name;
                if let Err(e) = self.problem.add(name, f) {
                    let msg = format!("{name}: DomainVar not recognized: {e}");
                    self.messages.push((
                        i,
                        Message {
                            var: "BHV_ERROR".into(),
                            value: Value::String(msg.into()),
                            key: PostKey::Repeatable,
                        },
                    ));
                    self.slots[i].ok = false;
                    halted = true;
                    report.halted = true;
                    break;
                }
            }
            match self.slots[i].state {
                RunState::Active => report.active.push(line),
                RunState::Running => report.running.push(line),
                RunState::Idle | RunState::New => report.idle.push(line),
                RunState::Completed => report.completed.push(line),
            }
        }
        report.active_goal &= !halted;
        report.ofnum = if halted { 0 } else { self.problem.len() };
        report.pcs_formed = if halted {
            0
        } else {
            self.problem.functions().map(|(_, f)| f.piece_count()).sum()
        };
        let decision = if halted || self.problem.is_empty() {
            None
        } else {
            self.solver.solve(&self.problem)
        };
        if let Some(d) = &decision {
            for v in &d.vars {
                report.decisions.push((v.name.clone(), v.value));
            }
        }

        // Step 9: postings.
        for r in std::mem::take(&mut self.update_results) {
            self.notify("IVPHELM_UPDATE_RESULT", Value::String(r.into()), "");
        }
        if self.refresh_pending && now - self.refresh_time > 2.0 {
            self.filter.clear();
            self.refresh_time = now;
            self.refresh_pending = false;
        }
        for (var, val) in modes {
            let v = Value::String(val.into());
            if self.filter.changed("mode_set", &v) {
                self.notify(&var, v, "HELM_MODE");
            }
        }
        self.post_behavior_messages(iter, now);

        report.warnings = self.warnings;
        let mut rendered = std::mem::take(&mut self.cur_report);
        report.render_into(&self.domain_str, Some(&self.config.domain), &mut rendered);
        let full = std::mem::take(&mut self.rejournal);
        let prev = &self.prev_report;
        self.out.text("IVPHELM_SUMMARY", |summary| {
            if full {
                rendered.summary(iter, now, &Rendered::default(), summary);
            } else {
                rendered.summary(iter, now, prev, summary);
            }
        });
        self.notify("IVPHELM_IPF_CNT", Value::Double(report.ofnum as f64), "");
        self.notify(
            "IVPHELM_TOTAL_PCS_FORMED",
            Value::Double(report.pcs_formed as f64),
            "",
        );
        self.notify(
            "IVPHELM_TOTAL_PCS_CACHED",
            Value::Double(report.pcs_cached as f64),
            "",
        );
        let counts = [report.active.len(), report.running.len(), report.idle.len()];
        for (k, cnt) in counts.into_iter().enumerate() {
            let mut list = std::mem::take(&mut self.scratch);
            report.write_names(k, &mut list);
            if self.lists[k] != list {
                let [base, base_cnt] = [
                    ["IVPHELM_BHV_ACTIVE", "IVPHELM_BHV_ACTIVE_CNT"],
                    ["IVPHELM_BHV_RUNNING", "IVPHELM_BHV_RUNNING_CNT"],
                    ["IVPHELM_BHV_IDLE", "IVPHELM_BHV_IDLE_CNT"],
                ][k];
                self.out.text_copy(base, &list);
                self.notify(base_cnt, Value::Double(cnt as f64), "");
                std::mem::swap(&mut self.lists[k], &mut list);
            }
            self.scratch = list;
        }

        // Step 10: all-stop or decisions.
        let mut allstop: std::borrow::Cow<'static, str> = "clear".into();
        if report.halted {
            allstop = "BehaviorError".into();
        } else if report.ofnum == 0 {
            allstop = "NothingToDo".into();
        } else if self.config.goals_mandatory && !report.active_goal {
            allstop = "NoGoalBehavior".into();
        } else {
            let missing: Vec<&str> = self
                .config
                .domain
                .vars()
                .iter()
                .filter(|v| {
                    !v.is_optional() && !report.decisions.iter().any(|(n, _)| n == v.name())
                })
                .map(|v| v.name())
                .collect();
            if !missing.is_empty() {
                let msg = format!("MissingDecVars:{}", missing.join(","));
                self.notify("BHV_ERROR", Value::String(msg.clone().into()), "");
                allstop = msg.into();
            }
        }
        if allstop != "clear" {
            self.post_allstop(&allstop);
        } else {
            self.post_allstop("clear");
            for (i, v) in self.config.domain.vars().iter().enumerate() {
                let val = report
                    .decisions
                    .iter()
                    .find(|(n, _)| n == v.name())
                    .map_or(0.0, |d| d.1);
                self.out.push(&self.desired_vars[i], Value::Double(val), "");
            }
        }
        self.notify("IVPHELM_CREATE_CPU", Value::Double(0.0), "");
        self.notify("IVPHELM_LOOP_CPU", Value::Double(0.0), "");
        let mut upd: Vec<(&str, &str)> = self
            .slots
            .iter()
            .filter(|s| !s.common.update_var.is_empty())
            .map(|s| (s.common.name.as_str(), s.common.update_var.as_str()))
            .collect();
        upd.sort_unstable();
        let mut text = std::mem::take(&mut self.scratch);
        text.clear();
        for (k, (a, b)) in upd.into_iter().enumerate() {
            if k > 0 {
                text.push(',');
            }
            text.push_str(a);
            text.push('=');
            text.push_str(b);
        }
        if text != self.update_vars {
            self.update_vars.clone_from(&text);
            self.out.text_copy("IVPHELM_UPDATEVARS", &text);
        }
        self.scratch = text;
        if allstop != "clear" && self.config.allow_park && self.config.park_on_allstop {
            self.has_control = false;
        }
        if self.subs_dirty {
            self.subs_dirty = false;
            self.refresh_subscriptions();
        }
        self.info.clear_deltas();
        self.cur_report = std::mem::replace(&mut self.prev_report, rendered);
        // The report stays for the appcast; the one before it gives its lines back.
        let mut old = std::mem::replace(&mut self.last_report, report);
        for list in [
            &mut old.active,
            &mut old.running,
            &mut old.idle,
            &mut old.completed,
        ] {
            self.line_pool.append(list);
        }
    }

    /// Whether the latest [`Helm::iterate`] stopped in the first second of deciding, before
    /// any decision (pHelmIvP posts no appcast in that case).
    pub fn in_decision_delay(&self) -> bool {
        self.delayed
    }

    /// The report of the latest decision iteration (empty before the first).
    pub fn last_report(&self) -> &HelmReport {
        &self.last_report
    }

    /// The appcast body pHelmIvP builds (`buildReport`) at helm time `now`: in MALCONFIG a
    /// boxed notice; otherwise the comms policy, the latest report's summary
    /// ([`HelmReport::formatted_summary`]), the hold-on-apps status and the table of the
    /// behaviours' latest postings.
    pub fn appcast_body(&self, now: f64, comms_policy: &str, out: &mut String) {
        if self.state == HelmState::Malconfig {
            let bang = "!".repeat(49);
            let blank = format!("!!{}!!", " ".repeat(45));
            for line in [
                bang.as_str(),
                blank.as_str(),
                "!!  The helm is in the MALCONFIG state due to  !!",
                "!!  unresolved configuration warnings.         !!",
                blank.as_str(),
                bang.as_str(),
            ] {
                out.push_str(line);
                out.push('\n');
            }
            return;
        }
        out.push_str("  Comms Policy: ");
        out.push_str(comms_policy);
        out.push('\n');
        self.last_report
            .formatted_summary(now, &self.config.domain, out);
        let hold = if self.held_apps.is_empty() {
            "none"
        } else if self.holding() {
            "waiting"
        } else {
            "satisfied"
        };
        out.push_str("Hold-On-Apps: ");
        out.push_str(hold);
        out.push_str("\n\n\n");
        let mut table = appcast::Table::new(5);
        table.push("Variable | Behavior | Time | Iter | Value");
        table.add_header_lines();
        table.set_max_width(4, 55);
        table.set_no_pad(4);
        let mut cell = String::new();
        for (var, o) in &self.outgoing {
            table.push(var);
            table.push(&o.bhv);
            cell.clear();
            fixed(&mut cell, o.time - self.start_time, 2);
            table.push(&cell);
            cell.clear();
            uint(&mut cell, o.iter);
            table.push(&cell);
            cell.clear();
            match &o.value {
                Value::String(v) => cell.push_str(v),
                Value::Double(x) => behaviors::fmt::compact(&mut cell, *x, 5),
                Value::Binary(b) => cell.push_str(&format!("<{} bytes>", b.len())),
            }
            table.push(&cell);
        }
        table.write(out);
    }

    fn post_behavior_messages(&mut self, iter: u64, now: f64) {
        let n = self.slots.len();
        if self.bhv_count != Some(n) {
            self.bhv_count = Some(n);
            self.notify("IVPHELM_BHV_CNT", Value::Double(n as f64), "");
        }
        // No spawning: every behaviour ever is one of the file's.
        let ever = self.slots.len().max(self.bhv_count_ever.unwrap_or(0));
        if self.bhv_count_ever != Some(ever) {
            self.bhv_count_ever = Some(ever);
            self.notify("IVPHELM_BHV_CNT_EVER", Value::Double(ever as f64), "");
        }
        self.notify("IVPHELM_ITER", Value::Double(iter as f64), "");
        let mut messages = std::mem::take(&mut self.messages);
        for (i, m) in messages.drain(..) {
            if m.var == "BHV_IPF" {
                // Muxed into parts of 2000 characters, id `<bhv>^<iteration>`, each posted
                // with the behaviour's name as its source aux; not kept in the info buffer.
                if let Value::String(text) = &m.value {
                    let name = &self.slots[i].common.name;
                    let mut id = String::with_capacity(name.len() + 12);
                    id.push_str(name);
                    id.push('^');
                    uint(&mut id, iter);
                    let mut parts = std::mem::take(&mut self.ipf_parts);
                    ivp::encode::mux(text, &id, 2000, &mut parts);
                    for part in parts.drain(..) {
                        let p = self.out.next_with_aux(&m.var, name);
                        p.value = Value::String(part.into());
                    }
                    self.ipf_parts = parts;
                }
                continue;
            }
            self.info.set_ref(&m.var, &m.value, APP_NAME, now);
            if m.var == "BHV_WARNING" || m.var == "BHV_ERROR" {
                self.warnings += 1;
                // pHelmIvP shows them in its appcast; a warning whose key ends in
                // `retract` withdraws the same text.
                let text = match &m.value {
                    Value::String(t) => t.clone(),
                    v => v.to_string().into(),
                };
                let w = format!("{}: {text}", m.var);
                let retract = m.var == "BHV_WARNING"
                    && matches!(&m.key, PostKey::Tag(t) if t.ends_with("retract"));
                self.notes.push(if retract {
                    AppcastNote::Retract(w)
                } else {
                    AppcastNote::Warning(w)
                });
            }
            let name = &self.slots[i].common.name;
            let tag = match m.key {
                PostKey::Repeatable => None,
                PostKey::Var => Some(""),
                PostKey::Tag(t) => Some(t),
            };
            let post = match tag {
                None => true,
                Some(t) => {
                    let key = &mut self.key_buf;
                    key.clear();
                    key.push_str(name);
                    key.push_str(&m.var);
                    key.push_str(t);
                    self.filter.changed(key, &m.value)
                }
            };
            if post {
                match self.outgoing.get_mut(&m.var) {
                    Some(o) => {
                        o.value.clone_from(&m.value);
                        o.time = now;
                        o.bhv.clone_from(name);
                        o.iter = iter;
                    }
                    None => {
                        self.outgoing.insert(
                            m.var.clone(),
                            Outgoing {
                                value: m.value.clone(),
                                time: now,
                                bhv: name.clone(),
                                iter,
                            },
                        );
                    }
                }
                if m.var == "BHV_EVENT"
                    && let Value::String(e) = &m.value
                {
                    self.notes.push(AppcastNote::Event(e.to_string()));
                }
                // `<iteration>:<behaviour>` differs every iteration: its own buffer.
                let mut aux = String::with_capacity(name.len() + 8);
                uint(&mut aux, iter);
                aux.push(':');
                aux.push_str(name);
                let p = self.out.next(&m.var);
                p.value = m.value;
                p.aux = aux.into();
            }
        }
        self.messages = messages;
        // Condition and flag variables change only with the behaviour set or an update.
        if self.state_vars_dirty {
            self.state_vars_dirty = false;
            let vars = self.state_space_vars();
            if vars != self.state_vars {
                self.notify("IVPHELM_STATEVARS", Value::String(vars.clone().into()), "");
                self.state_vars = vars;
            }
        }
        let pending = self.slots.iter().any(|s| s.state == RunState::Completed);
        if self.completed_pending != Some(pending) {
            self.completed_pending = Some(pending);
            let v = if pending { "true" } else { "false" };
            self.notify("IVPHELM_COMPLETED_PENDING", Value::String(v.into()), "");
        }
        // Completed behaviours leave the set (reference §4.4).
        let mut removed = 0;
        let mut k = 0;
        while k < self.slots.len() {
            if self.slots[k].state == RunState::Completed {
                let s = self.slots.remove(k);
                let mut ev = String::from("time=");
                fixed(&mut ev, now - self.start_time, 2);
                ev.push_str(&format!(
                    ", iter={iter}, bname={}, btype={}, event=death, seed=",
                    s.common.name, s.common.kind
                ));
                self.notify("IVPHELM_LIFE_EVENT", Value::String(ev.into()), "");
                removed += 1;
                self.state_vars_dirty = true;
            } else {
                k += 1;
            }
        }
        if self.completed_count != Some(removed) {
            self.completed_count = Some(removed);
            self.notify("IVPHELM_COMPLETED_COUNT", Value::Double(removed as f64), "");
        }
    }

    /// The variables of the behaviours' state space (MOOS `getStateSpaceVars`): condition
    /// variables and the variables of run, runx, idle, end, active and inactive flags,
    /// comma-separated, each once, in behaviour order.
    fn state_space_vars(&self) -> String {
        let mut out: Vec<&str> = Vec::new();
        for s in &self.slots {
            for (_, c) in &s.common.conditions {
                for v in c.variables() {
                    if !out.contains(&v) {
                        out.push(v);
                    }
                }
            }
            for kind in [
                FlagKind::Run,
                FlagKind::Runx,
                FlagKind::Idle,
                FlagKind::End,
                FlagKind::Active,
                FlagKind::Inactive,
            ] {
                for f in s.common.flags(kind) {
                    if !out.contains(&f.var.as_str()) {
                        out.push(&f.var);
                    }
                }
            }
        }
        out.join(",")
    }

    /// [`Helm::queue`] for a variable name the caller owns (kept unless `post_mapping`
    /// renames it).
    fn queue_owned(&mut self, i: usize, var: String, value: Value, key: &PostKey) {
        let renamed = match self.slots[i].common.mapped(&var) {
            None => return,
            Some(m) if m == var => None,
            Some(m) => Some(m.to_string()),
        };
        let var = renamed.unwrap_or(var);
        let key = key.clone();
        self.messages.push((i, Message { var, value, key }));
    }

    /// Queues a behaviour message with the duplicate-filter key of `key`.
    fn queue(&mut self, i: usize, var: &str, value: Value, key: &PostKey) {
        let common = &self.slots[i].common;
        let Some(var) = common.mapped(var) else {
            return;
        };
        let var = var.to_string();
        let key = key.clone();
        self.messages.push((i, Message { var, value, key }));
    }

    fn post_flags(&mut self, i: usize, kind: FlagKind) {
        let flags = self.slots[i].common.flags(kind).to_vec();
        for f in &flags {
            self.post_flag(i, f, true);
        }
    }

    /// Posts one flag (reference §4.5, MOOS `postFlag`): the `[if]` condition is checked now,
    /// macros are expanded, a lone numeric macro posts a double; `#all`/`#group` destinations
    /// go off-board as `NODE_MESSAGE_LOCAL` (the `+` forms are also posted locally).
    fn post_flag(&mut self, i: usize, f: &behaviors::Flag, repeatable: bool) {
        if let Some(c) = &f.condition {
            let info = &self.info;
            if !c.evaluate(&|n: &str| info.condition_value(n)) {
                return;
            }
        }
        let value = match &f.value {
            FlagValue::Double(x) => Value::Double(*x),
            FlagValue::String(s) => {
                let mut out = std::mem::take(&mut self.scratch);
                out.clear();
                self.expand_macros(i, s, &mut out);
                let v = if f.solo_macro
                    && mission::condition::is_numeric(out.trim())
                    && let Ok(x) = out.trim().parse::<f64>()
                {
                    Value::Double(x)
                } else {
                    Value::String(out.clone().into())
                };
                self.scratch = out;
                v
            }
            // A flag's value is parsed from text: never binary.
            FlagValue::Binary(b) => Value::Binary(b.clone()),
        };
        let key = if repeatable {
            PostKey::Repeatable
        } else {
            PostKey::Var
        };
        let dest = f.dest.as_str();
        if matches!(dest, "" | "all+" | "group+") {
            self.queue(i, &f.var, value.clone(), &key);
        }
        if matches!(dest, "all" | "all+" | "group" | "group+") {
            let group = if dest.starts_with("group") {
                let var = format!("{}_NAV_GROUP", self.us(i).to_ascii_uppercase());
                Some(self.info.text(&var).unwrap_or("").to_string())
            } else {
                None
            };
            let spec = self.node_message(i, &f.var, &value, group.as_deref());
            let key = match key {
                PostKey::Repeatable => PostKey::Repeatable,
                _ => PostKey::Tag(""),
            };
            self.queue(i, "NODE_MESSAGE_LOCAL", Value::String(spec.into()), &key);
        }
    }

    /// The vehicle name behaviour `i` goes by (its `us`, else the helm's community).
    fn us(&self, i: usize) -> &str {
        self.slots[i].common.us.as_deref().unwrap_or(&self.ownship)
    }

    /// A `NODE_MESSAGE` spec (MOOS `NodeMessage::getSpec`) from this helm's behaviour `i`.
    fn node_message(&self, i: usize, var: &str, value: &Value, group: Option<&str>) -> String {
        let mut s = format!("src_node={},dest_node=all", self.us(i));
        if let Some(g) = group.filter(|g| !g.is_empty()) {
            s.push_str(",dest_group=");
            s.push_str(g);
        }
        s.push_str(&format!(
            ",src_app={},src_bhv={},var_name={var}",
            self.app_name, self.slots[i].common.name
        ));
        match value {
            Value::Double(x) => {
                s.push_str(",double_val=");
                compact(&mut s, *x, 6);
            }
            Value::String(v) if v.contains(',') && !(v.starts_with('"') && v.ends_with('"')) => {
                s.push_str(&format!(",string_val=\"{v}\""));
            }
            Value::String(v) => {
                s.push_str(",string_val=");
                s.push_str(v);
            }
            // Behaviours post no binary data.
            Value::Binary(_) => {}
        }
        s
    }

    fn expand_macros(&mut self, i: usize, text: &str, out: &mut String) {
        let now = self.info.now_time();
        let info = &self.info;
        let slot = &mut self.slots[i];
        // Each counter macro present (in its `$[..]` form) counts once per expansion, and all
        // its occurrences get the same value (MOOS `expandCtrMacro`).
        for (k, m) in [
            "$[CTR]", "$[CTR1]", "$[CTR2]", "$[CTR3]", "$[CTR4]", "$[CTR5]",
        ]
        .iter()
        .enumerate()
        {
            if text.contains(m) {
                slot.ctr[k] += 1;
            }
        }
        let ownship = slot.common.us.as_deref().unwrap_or(&self.ownship);
        let nav = |v: &str| info.num(v).unwrap_or(0.0);
        expand(text, out, |name, o| {
            if slot.bhv.macro_value(name, o) {
                return true;
            }
            match name {
                "OWNSHIP" => o.push_str(ownship),
                "BHVNAME" => o.push_str(&slot.common.name),
                "BHVTYPE" => o.push_str(&slot.common.kind),
                "PWT" => compact(o, slot.common.pwt, MACRO_DIGITS),
                "CONTACT" => {}
                "UTC" => compact(o, now, MACRO_DIGITS),
                "OSX" => compact(o, nav("NAV_X"), MACRO_DIGITS),
                "OSY" => compact(o, nav("NAV_Y"), MACRO_DIGITS),
                "OSH" => compact(o, geometry_angle(nav("NAV_HEADING")), MACRO_DIGITS),
                "OSV" => compact(o, nav("NAV_SPEED"), MACRO_DIGITS),
                "DUR_RUN_TIME" => compact(o, slot.clock.running_time, MACRO_DIGITS),
                "DUR_IDLE_TIME" => compact(o, slot.clock.idle_time, MACRO_DIGITS),
                "NOW" => {
                    let t0 = *slot.now_start.get_or_insert(now);
                    compact(o, now - t0, MACRO_DIGITS)
                }
                "CTR" | "CTR1" | "CTR2" | "CTR3" | "CTR4" | "CTR5" => {
                    let k = name[3..].parse::<usize>().unwrap_or(0);
                    o.push_str(&slot.ctr[k].to_string());
                }
                _ => return false,
            }
            true
        });
    }

    /// Converts a behaviour call's output into queued messages.
    fn absorb(&mut self, i: usize) {
        let mut emit = std::mem::take(&mut self.emit);
        for e in emit.emits.drain(..) {
            match e {
                Emit::Post { var, value, key } => self.queue_owned(i, var, value, &key),
                Emit::Flag { flag, repeatable } => self.post_flag(i, &flag, repeatable),
                Emit::Complete => self.set_complete(i),
            }
        }
        if let Some(msg) = emit.error.take() {
            let name = self.slots[i].common.name.clone();
            self.queue(
                i,
                "BHV_ERROR",
                Value::String(format!("{name}: {msg}").into()),
                &PostKey::Repeatable,
            );
            self.slots[i].ok = false;
        }
        emit.clear();
        self.emit = emit;
    }

    fn set_complete(&mut self, i: usize) {
        self.post_flags(i, FlagKind::End);
        if !self.slots[i].common.perpetual {
            self.slots[i].completed = true;
        }
    }

    fn check_updates(&mut self, i: usize, now: f64) -> bool {
        let var = &self.slots[i].common.update_var;
        if var.is_empty() || self.info.deltas(var).is_empty() {
            return false;
        }
        let var = var.clone();
        let updates: Vec<String> = self.info.deltas(&var).to_vec();
        let mut made = false;
        // Even a faulty update applies its good parameters (conditions, flags...).
        self.state_vars_dirty |= !updates.is_empty();
        for u in updates {
            let name = self.slots[i].common.name.clone();
            let mut result = format!("bhv={name},var={var},time=");
            fixed(&mut result, now - self.start_time, 2);
            let lower = u.to_ascii_lowercase();
            let fresh = lower.contains("toggle")
                || lower.contains("engage")
                || lower.contains("mod")
                || (!u.is_empty() && u != self.slots[i].prev_update);
            if !fresh {
                result.push_str(",result=duplicate");
            } else {
                let pairs: Vec<(String, String)> = u
                    .split('#')
                    .filter(|p| !p.trim().is_empty())
                    .map(|p| {
                        let (k, v) = p.split_once('=').unwrap_or((p, ""));
                        (param_name(k.trim()), v.trim().to_string())
                    })
                    .collect();
                if pairs.iter().any(|(k, v)| k == "name" && *v != name) {
                    result.push_str(",result=name_mismatch");
                } else {
                    let mut bad = Vec::new();
                    for (k, v) in pairs.iter().filter(|(k, _)| k != "name") {
                        let slot = &mut self.slots[i];
                        let r = apply_param(slot, k, v, &self.info, &self.config, &self.ownship);
                        if r.is_err() {
                            bad.push(k.clone());
                        }
                    }
                    if bad.is_empty() {
                        made = true;
                        self.slots[i].good_updates += 1;
                        self.slots[i].prev_update = u.clone();
                        result.push_str(",result=success");
                    } else {
                        self.slots[i].bad_updates += 1;
                        let w = format!(
                            "Faulty update for behavior: {name}. Bad parameter(s): {}",
                            bad.join(",")
                        );
                        self.queue(
                            i,
                            "BHV_WARNING",
                            Value::String(w.clone().into()),
                            &PostKey::Var,
                        );
                        self.queue(
                            i,
                            "BHV_CONFIG_WARNING",
                            Value::String(w.into()),
                            &PostKey::Var,
                        );
                        result.push_str(",result=param_error");
                    }
                }
            }
            result.push_str(",val=");
            result.push_str(&u);
            self.update_results.push(result);
        }
        made
    }

    fn check_duration_reset(&mut self, i: usize) {
        let Some((var, val)) = self.slots[i].common.duration_reset.clone() else {
            return;
        };
        let Some(e) = self.info.get(&var) else {
            return;
        };
        let triggered = val.is_empty()
            || match &e.value {
                Value::String(s) => *s == val,
                Value::Double(x) => val.trim().parse::<f64>().ok() == Some(*x),
                Value::Binary(_) => false,
            };
        if !triggered {
            return;
        }
        let stamp = e.time;
        let slot = &mut self.slots[i];
        if slot.clock.reset_stamp.is_none_or(|s| stamp > s) {
            slot.clock.reset_stamp = Some(stamp);
            self.reset_duration(i);
        }
    }

    fn reset_duration(&mut self, i: usize) {
        self.slots[i].clock.reset();
        let status = self.slots[i].common.duration_status.clone();
        if !status.is_empty() {
            let d = self.slots[i].duration();
            self.queue(i, &status, Value::Double(d), &PostKey::Var);
        }
    }

    fn post_remaining(&mut self, i: usize, remaining: f64) {
        let status = self.slots[i].common.duration_status.clone();
        if status.is_empty() {
            return;
        }
        let v = if remaining <= 10.0 {
            remaining
        } else {
            (remaining + 0.5).floor()
        };
        self.queue(i, &status, Value::Double(v), &PostKey::Var);
    }

    /// MOOS `isRunnable`: the state from conditions, duration and starvation. Returns the
    /// state and the first failed condition.
    fn runnable(&mut self, i: usize, now: f64) -> (RunState, Option<Failed>) {
        if self.slots[i].completed {
            return (RunState::Completed, None);
        }
        let failed = {
            let info = &self.info;
            let lookup = |n: &str| info.condition_value(n);
            self.slots[i]
                .common
                .conditions
                .iter()
                .position(|(_, c)| !c.evaluate(&lookup))
        };
        if let Some(k) = failed {
            return (RunState::Idle, Some(Failed::Condition(k)));
        }
        if self.slots[i].clock.reset_pending {
            self.reset_duration(i);
        }
        let (dur, decay) = (
            self.slots[i].duration(),
            self.slots[i].common.duration_idle_decay,
        );
        let (exceeded, remaining) = self.slots[i].clock.check(now, dur, decay);
        if dur >= 0.0 {
            self.post_remaining(i, remaining);
        }
        if exceeded {
            self.set_complete(i);
            if self.slots[i].common.perpetual {
                self.slots[i].clock.reset_pending = true;
            } else {
                return (
                    RunState::Completed,
                    Some(Failed::Other("completed-byduration".into())),
                );
            }
        }
        // MOOS `subDomain` leaves a behaviour an empty domain when the helm lacks one of its
        // decision variables; `isRunnable` then posts an error (which halts the helm) and
        // keeps it idle.
        let null_domain = self.config.domain.is_empty()
            || self.slots[i]
                .bhv
                .domain_vars()
                .iter()
                .any(|v| self.config.domain.get(v).is_none());
        if null_domain {
            let msg = format!(
                "{}: Null IvPDomain given to Behavior",
                self.slots[i].common.name
            );
            self.queue(
                i,
                "BHV_ERROR",
                Value::String(msg.into()),
                &PostKey::Repeatable,
            );
            self.slots[i].ok = false;
            return (RunState::Idle, Some(Failed::Other("null-domain".into())));
        }
        for (var, secs) in self.slots[i].common.starve.clone() {
            let age = self.info.age(&var);
            if age.is_none_or(|a| a > secs) {
                return (
                    RunState::Idle,
                    Some(Failed::Other(format!("VarStarve: {var}"))),
                );
            }
        }
        (RunState::Running, None)
    }

    fn call<F>(&mut self, i: usize, f: F) -> Option<ivp::IvpFunction>
    where
        F: FnOnce(&mut dyn Behavior, &Ctx<'_>, &mut Out) -> Option<ivp::IvpFunction>,
    {
        let mut emit = std::mem::take(&mut self.emit);
        let r = {
            let slot = &mut self.slots[i];
            let ctx = Ctx {
                info: &self.info,
                domain: &self.config.domain,
                ownship: slot.common.us.as_deref().unwrap_or(&self.ownship),
                name: &slot.common.name,
                perpetual: slot.common.perpetual,
            };
            f(slot.bhv.as_mut(), &ctx, &mut emit)
        };
        self.emit = emit;
        self.absorb(i);
        r
    }

    /// One behaviour's iteration (MOOS `BehaviorSet::produceOF`, reference §4.4).
    fn produce(&mut self, i: usize, now: f64) -> Option<ivp::IvpFunction> {
        let old = self.slots[i].state;
        if !self.slots[i].config_posted && !self.holding() {
            // Configuration-time postings first (MOOS queues them in the behaviour's message
            // list before this iteration's), then the configflags; with hold_on_apps, only
            // once every named app is in DB_CLIENTS.
            self.slots[i].config_posted = true;
            let pending = std::mem::take(&mut self.slots[i].config_out);
            if !pending.emits.is_empty() || pending.error.is_some() {
                let buffer = std::mem::replace(&mut self.emit, pending);
                self.absorb(i);
                self.emit = buffer;
            }
            self.post_flags(i, FlagKind::Config);
        }
        if self.check_updates(i, now) {
            self.subs_dirty = true;
            self.state_vars_dirty = true;
            // MOOS: `checkUpdates` posts the settings, then `onSetParamComplete` runs.
            self.call(i, |b, ctx, out| {
                behaviors::post_config_status(b, ctx, out);
                b.on_set_param_complete(ctx, out);
                None
            });
        }
        let iteration = self.iteration;
        self.slots[i].bhv.set_helm_iteration(iteration);
        self.check_duration_reset(i);
        let (mut state, failed) = self.runnable(i, now);
        let mut ipf = None;
        match state {
            RunState::Completed => {
                self.call(i, |b, ctx, out| {
                    b.on_complete(ctx, out);
                    None
                });
            }
            RunState::Idle => {
                if old != RunState::Idle {
                    self.post_flags(i, FlagKind::Idle);
                    self.post_flags(i, FlagKind::Inactive);
                }
                if old.is_running() {
                    self.call(i, |b, ctx, out| {
                        b.on_run_to_idle(ctx, out);
                        None
                    });
                }
                let (idle, run) = (
                    self.slots[i].clock.idle_time,
                    self.slots[i].clock.running_time,
                );
                self.call(i, |b, ctx, out| {
                    b.state_durations(idle, run);
                    b.on_idle(ctx, out);
                    None
                });
                self.slots[i].clock.account(now, false);
            }
            _ => {
                if old == RunState::Idle {
                    self.call(i, |b, ctx, out| {
                        b.on_idle_to_run(ctx, out);
                        None
                    });
                }
                let (idle, run) = (
                    self.slots[i].clock.idle_time,
                    self.slots[i].clock.running_time,
                );
                let mut f = self.call(i, |b, ctx, out| {
                    b.state_durations(idle, run);
                    b.on_run(ctx, out)
                });
                // As pHelmIvP's BehaviorSet since Feb 2026: run flags (on entering the run
                // state) and runx flags (every running iteration) go out after on_run, so
                // behaviour macros set there are current in them.
                if matches!(old, RunState::Idle | RunState::New) {
                    self.post_flags(i, FlagKind::Run);
                }
                self.post_flags(i, FlagKind::Runx);
                if f.as_ref().is_some_and(|f| {
                    f.pieces()
                        .any(|p| p.max_val().is_nan() || p.min_val().is_nan())
                }) {
                    f = None;
                    let name = self.slots[i].common.name.clone();
                    let msg = format!("{name}: NaN detected in IvP Function");
                    self.queue(
                        i,
                        "BHV_ERROR",
                        Value::String(msg.into()),
                        &PostKey::Repeatable,
                    );
                    self.slots[i].ok = false;
                }
                let pwt = self.slots[i].common.pwt;
                let f = f.filter(|_| pwt > 0.0).map(|f| f.with_pwt(pwt));
                if let Some(f) = f {
                    // BehaviorSet reports every function it receives (`m_report_ipf` is on
                    // by default), before the active flags; the helm splits it into parts
                    // when it posts the behaviour's messages.
                    let mut text = String::new();
                    let mut context = String::with_capacity(24);
                    uint(&mut context, self.iteration);
                    context.push(':');
                    context.push_str(&self.slots[i].common.name);
                    ivp::encode::encode(&f, &context, &mut text);
                    self.queue(
                        i,
                        "BHV_IPF",
                        Value::String(text.into()),
                        &PostKey::Repeatable,
                    );
                    if old != RunState::Active {
                        self.post_flags(i, FlagKind::Active);
                    }
                    self.slots[i].pcs = f.piece_count();
                    state = RunState::Active;
                    ipf = Some(f);
                } else {
                    self.slots[i].pcs = 0;
                    if old == RunState::Active {
                        self.post_flags(i, FlagKind::Inactive);
                    }
                }
                self.slots[i].clock.account(now, true);
            }
        }
        if state != RunState::Completed && self.slots[i].completed {
            state = RunState::Completed;
            ipf = None;
            self.call(i, |b, ctx, out| {
                b.on_complete(ctx, out);
                None
            });
        }
        // BHV_STATUS, filtered on change.
        let slot = &self.slots[i];
        let mut status = String::with_capacity(64);
        status.push_str("name=");
        status.push_str(&slot.common.name);
        match &failed {
            Some(Failed::Condition(k)) => {
                status.push_str(",pc=");
                status.push_str(&slot.common.conditions[*k].0);
            }
            Some(Failed::Other(f)) => {
                status.push_str(",pc=");
                status.push_str(f);
            }
            None => {}
        }
        if state == RunState::Active {
            status.push_str(",pwt=");
            fixed(&mut status, slot.common.pwt, 5);
            status.push_str(",pcs=");
            uint(&mut status, slot.pcs as u64);
        }
        status.push_str(",state=");
        status.push_str(state.as_str());
        status.push_str(",updates=");
        slot.write_update_summary(&mut status);
        self.queue(
            i,
            "BHV_STATUS",
            Value::String(status.into()),
            &PostKey::Tag(""),
        );
        if !self.slots[i].first_done {
            self.slots[i].first_done = true;
            self.post_flags(i, FlagKind::Spawnx);
        }
        if old != state {
            self.slots[i].entered = now;
        }
        self.slots[i].state = state;
        ipf
    }
}

/// Decimals of numeric macro values (MOOS `macroExpand(str, macro, double)`, 3 by default;
/// trailing zeros dropped).
const MACRO_DIGITS: usize = 3;

fn geometry_angle(h: f64) -> f64 {
    let a = h % 360.0;
    if a < 0.0 { a + 360.0 } else { a }
}

/// Applies one parameter to a behaviour: common parameters first, then the behaviour's own
/// (as pHelmIvP's populator does).
fn apply_param(
    slot: &mut Slot,
    key: &str,
    value: &str,
    info: &InfoBuffer,
    config: &HelmConfig,
    ownship: &str,
) -> Result<(), ParamError> {
    if slot.common.set_param(key, value)? {
        return Ok(());
    }
    let perpetual = slot.common.perpetual;
    let name = slot.common.name.clone();
    let ctx = Ctx {
        info,
        domain: &config.domain,
        ownship,
        name: &name,
        perpetual,
    };
    slot.bhv
        .set_param(key, value.trim(), &mut slot.common, &ctx)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mission::source::SourceMap;

    /// A behaviour of another type that declares itself a constraint (as MOOS-IvP's avoidance
    /// behaviours do); everything else is delegated.
    struct AsConstraint(Box<dyn Behavior>);

    impl Behavior for AsConstraint {
        fn kind(&self) -> &'static str {
            self.0.kind()
        }
        fn is_constraint(&self) -> bool {
            true
        }
        fn default_duration(&self) -> f64 {
            self.0.default_duration()
        }
        fn set_param(
            &mut self,
            param: &str,
            value: &str,
            common: &mut Common,
            ctx: &Ctx<'_>,
        ) -> Result<(), ParamError> {
            self.0.set_param(param, value, common, ctx)
        }
        fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<ivp::IvpFunction> {
            self.0.on_run(ctx, out)
        }
    }

    const BHV: &str = "\
Behavior = BHV_ConstantHeading
{
  name     = hdg
  heading  = 90
  duration = no-time-limit
}
Behavior = BHV_ConstantSpeed
{
  name     = spd
  speed    = 2
  duration = no-time-limit
}
";

    /// A driving helm (goals_mandatory as given) whose behaviours named in `constraints` are
    /// turned into constraint behaviours.
    fn helm(goals_mandatory: &str, constraints: &[&str]) -> Helm {
        let bhv = mission::bhv::parse_bhv(&SourceMap::from_text("g.bhv", BHV));
        let g = Globals {
            lat_origin: Some("0".into()),
            long_origin: Some("0".into()),
            community: Some("abe".into()),
        };
        let params = [
            ("domain", "course:0:359:360"),
            ("domain", "speed:0:4:41"),
            ("start_engaged", "true"),
            ("goals_mandatory", goals_mandatory),
        ];
        let mut h = Helm::from_parsed(&params, &g, &bhv);
        assert!(h.config_errors().is_empty(), "{:?}", h.config_errors());
        for slot in &mut h.slots {
            if constraints.contains(&slot.common.name.as_str()) {
                let inner = std::mem::replace(&mut slot.bhv, Box::new(behaviors::Timer::new()));
                slot.bhv = Box::new(AsConstraint(inner));
            }
        }
        h
    }

    fn step(h: &mut Helm, t: f64) -> Vec<Posting> {
        for (var, v) in [
            ("NAV_X", 0.0),
            ("NAV_Y", 0.0),
            ("NAV_HEADING", 0.0),
            ("NAV_SPEED", 0.0),
        ] {
            h.on_mail(&[Mail::new(var, v, t)]);
        }
        h.iterate(t).to_vec()
    }

    fn values<'a>(posts: &'a [Posting], var: &str) -> Vec<&'a Value> {
        posts
            .iter()
            .filter(|p| p.key == var)
            .map(|p| &p.value)
            .collect()
    }

    fn summary(posts: &[Posting]) -> &str {
        values(posts, "IVPHELM_SUMMARY")[0].as_str().unwrap()
    }

    #[test]
    fn no_goal_behaviour_all_stops_after_one_grace_iteration() {
        let mut h = helm("true", &["hdg", "spd"]);
        step(&mut h, 0.0);
        // First decision iteration: announced, nothing zeroed.
        let p = step(&mut h, 1.0);
        assert_eq!(values(&p, "IVPHELM_IPF_CNT"), [&Value::Double(2.0)]);
        assert_eq!(
            values(&p, "IVPHELM_ALLSTOP"),
            [&Value::String("NoGoalBehavior".into())]
        );
        assert!(!p.iter().any(|p| p.key.starts_with("DESIRED_")), "{p:?}");
        assert!(!summary(&p).contains("active_goal"), "{}", summary(&p));
        // Second consecutive one: announced again, with zero decisions.
        let p = step(&mut h, 1.25);
        assert_eq!(
            values(&p, "IVPHELM_ALLSTOP"),
            [&Value::String("NoGoalBehavior".into())]
        );
        assert_eq!(values(&p, "DESIRED_HEADING"), [&Value::Double(0.0)]);
        assert_eq!(values(&p, "DESIRED_SPEED"), [&Value::Double(0.0)]);
        // Then quiet: the all-stop message is unchanged.
        let p = step(&mut h, 1.5);
        assert!(values(&p, "IVPHELM_ALLSTOP").is_empty());
        assert!(!p.iter().any(|p| p.key.starts_with("DESIRED_")), "{p:?}");
    }

    #[test]
    fn one_active_goal_behaviour_is_enough() {
        let mut h = helm("true", &["spd"]);
        step(&mut h, 0.0);
        let p = step(&mut h, 1.0);
        assert_eq!(
            values(&p, "IVPHELM_ALLSTOP"),
            [&Value::String("clear".into())]
        );
        assert_eq!(values(&p, "DESIRED_HEADING"), [&Value::Double(90.0)]);
        assert_eq!(values(&p, "DESIRED_SPEED"), [&Value::Double(2.0)]);
        assert!(summary(&p).contains(",active_goal=true"), "{}", summary(&p));
    }

    #[test]
    fn without_goals_mandatory_constraints_alone_drive() {
        let mut h = helm("false", &["hdg", "spd"]);
        step(&mut h, 0.0);
        let p = step(&mut h, 1.0);
        assert_eq!(
            values(&p, "IVPHELM_ALLSTOP"),
            [&Value::String("clear".into())]
        );
        assert_eq!(values(&p, "DESIRED_SPEED"), [&Value::Double(2.0)]);
        assert!(!summary(&p).contains("active_goal"), "{}", summary(&p));
    }

    #[test]
    fn a_goal_behaviour_returning_clears_the_no_goal_all_stop() {
        let mut h = helm("true", &["hdg", "spd"]);
        step(&mut h, 0.0);
        step(&mut h, 1.0);
        step(&mut h, 1.25);
        // The speed behaviour becomes a goal behaviour again.
        for slot in &mut h.slots {
            if slot.common.name == "spd" {
                slot.bhv = behaviors::create("BHV_ConstantSpeed").unwrap();
                let ctx_info = InfoBuffer::new();
                let ctx = Ctx {
                    info: &ctx_info,
                    domain: &h.config.domain,
                    ownship: "abe",
                    name: "spd",
                    perpetual: false,
                };
                slot.bhv
                    .set_param("speed", "2", &mut slot.common, &ctx)
                    .unwrap();
            }
        }
        let p = step(&mut h, 1.5);
        assert_eq!(
            values(&p, "IVPHELM_ALLSTOP"),
            [&Value::String("clear".into())]
        );
        assert_eq!(values(&p, "DESIRED_SPEED"), [&Value::Double(2.0)]);
        assert!(summary(&p).contains(",active_goal=true"), "{}", summary(&p));
    }
}

#[cfg(test)]
mod ipf_tests {
    use super::*;
    use mission::source::SourceMap;

    const BHV: &str = "\
Behavior = BHV_ConstantSpeed
{
  name     = spd
  pwt      = 50
  speed    = 2
  duration = no-time-limit
}
";

    #[test]
    fn every_active_behaviour_posts_its_function_as_bhv_ipf_parts() {
        let bhv = mission::bhv::parse_bhv(&SourceMap::from_text("g.bhv", BHV));
        let g = Globals {
            lat_origin: Some("0".into()),
            long_origin: Some("0".into()),
            community: Some("abe".into()),
        };
        let params = [
            ("domain", "course:0:359:360"),
            ("domain", "speed:0:4:41"),
            ("start_engaged", "true"),
        ];
        let mut h = Helm::from_parsed(&params, &g, &bhv);
        let nav = |h: &mut Helm, t: f64| {
            for var in ["NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"] {
                h.on_mail(&[Mail::new(var, 0.0, t)]);
            }
        };
        nav(&mut h, 0.0);
        assert!(h.iterate(0.0).iter().all(|p| p.key != "BHV_IPF"));
        for (t, iter) in [(1.0, 1), (1.25, 2)] {
            nav(&mut h, t);
            let posts = h.iterate(t).to_vec();
            let ipf: Vec<&Posting> = posts.iter().filter(|p| p.key == "BHV_IPF").collect();
            assert_eq!(ipf.len(), 1, "{posts:?}");
            assert_eq!(ipf[0].aux, "spd");
            let text = ipf[0].value.as_str().unwrap();
            let head = format!("P,spd^{iter},1,1,H,");
            assert!(text.starts_with(&head), "{text}");
            let whole = ivp::encode::demux([text]).unwrap();
            // Context `<iteration>:<behaviour>`, one dimension, pwt 50, the speed domain,
            // its whole-domain grid box.
            let ctx = format!("{iter}:spd");
            let expect = format!("H,{},{ctx},1,", ctx.len());
            assert!(whole.starts_with(&expect), "{whole}");
            assert!(whole.contains(",1,50,D,speed;0;4;41,G,40,F,0,"), "{whole}");
            let (f, c) = ivp::encode::decode(&whole).unwrap();
            assert_eq!(c, ctx);
            assert_eq!(f.pwt(), 50.0);
            // The speed objective peaks at 2 m/s (index 20), within the 4-dp rounding.
            let top = f.eval(&[20]).unwrap();
            assert!((top - 100.0).abs() < 1e-3, "{top}");
            assert!(f.eval(&[0]).unwrap() < top);
            // The function is not kept in the info buffer.
            assert!(!h.info().is_known("BHV_IPF"));
            // It goes out with the behaviours' messages: after IVPHELM_ITER, before the
            // summary.
            let at = |v: &str| posts.iter().position(|p| p.key == v).unwrap();
            assert!(at("IVPHELM_ITER") < at("BHV_IPF"));
            assert!(at("BHV_IPF") < at("IVPHELM_SUMMARY"));
        }
    }
}

#[cfg(test)]
mod ledger_tests {
    use super::*;
    use behaviors::Info;
    use mission::source::SourceMap;

    fn helm(extra: &[(&str, &str)]) -> Helm {
        let bhv = mission::bhv::parse_bhv(&SourceMap::from_text(
            "g.bhv",
            "Behavior = BHV_ConstantSpeed\n{\n name = spd\n speed = 1\n duration = no-time-limit\n}\n",
        ));
        let g = Globals {
            lat_origin: Some("0".into()),
            long_origin: Some("0".into()),
            community: Some("abe".into()),
        };
        let mut params = vec![("domain", "course:0:359:360"), ("domain", "speed:0:4:41")];
        params.extend_from_slice(extra);
        Helm::from_parsed(&params, &g, &bhv)
    }

    fn nav(h: &mut Helm, t: f64) {
        for var in ["NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"] {
            h.on_mail(&[Mail::new(var, 0.0, t)]);
        }
    }

    fn summaries(p: &[Posting]) -> Vec<String> {
        p.iter()
            .filter(|p| p.key == "IVPHELM_LEDGER_SUMMARY")
            .map(|p| p.value.as_str().unwrap().to_string())
            .collect()
    }

    #[test]
    fn start_up_posts_zero_counts_between_the_mode_set_and_the_alias() {
        let mut h = helm(&[("helm_alias", "hx")]);
        let p = h.iterate(0.0).to_vec();
        let vars: Vec<&str> = p.iter().map(|p| &*p.key).collect();
        let at = vars.iter().position(|v| *v == "IVPHELM_MODESET").unwrap();
        assert_eq!(
            vars[at + 1..at + 6],
            [
                "IVPHELM_BHV_ACTIVE_CNT",
                "IVPHELM_BHV_IDLE_CNT",
                "IVPHELM_BHV_RUNNING_CNT",
                "IVPHELM_BHV_DISABLED_CNT",
                "IVPHELM_ALIAS"
            ]
        );
        assert!(
            p[at + 1..at + 5]
                .iter()
                .all(|p| p.value == Value::Double(0.0))
        );
        // BHV_ABLE_FILTER is registered right after IVPHELM_REJOURNAL, as pHelmIvP does.
        let regs: Vec<&str> = p
            .iter()
            .filter(|p| p.key == "IVPHELM_REGISTER")
            .map(|p| p.value.as_str().unwrap())
            .collect();
        let r = regs.iter().position(|v| *v == "IVPHELM_REJOURNAL").unwrap();
        assert_eq!(regs[r + 1], "BHV_ABLE_FILTER");
    }

    #[test]
    fn node_reports_feed_the_ledger_and_the_info_buffer() {
        let mut h = helm(&[("contact_max_age", "20")]);
        // Held for navigation: no summary.
        assert!(summaries(h.iterate(0.0)).is_empty());
        nav(&mut h, 0.5);
        h.on_mail(&[
            Mail::new(
                "NODE_REPORT",
                "NAME=ben,X=5,Y=6,SPD=1,HDG=0,TIME=0.5,TYPE=kayak,GROUP=red",
                0.5,
            ),
            Mail::new(
                "NODE_REPORT_LOCAL",
                "NAME=abe,X=0,Y=0,TIME=0.5,TYPE=UUV,LENGTH=4",
                0.5,
            ),
            Mail::new("NODE_REPORT", "NAME=cal,X=5,Y=6", 0.5),
        ]);
        // Posted in the first second too (before the decision delay).
        assert_eq!(summaries(h.iterate(0.5)), ["now:1, reps:1, who:ben"]);
        let info = h.info();
        assert_eq!(info.text("BEN_NAV_GROUP"), Some("red"));
        assert_eq!(info.text("BEN_NAV_TYPE"), Some("kayak"));
        assert!(info.is_known("NODE_REPORT"), "the report itself is kept");
        // Own report: fields only, raw; the report is not kept.
        assert_eq!(info.text("ABE_NAV_TYPE"), Some("UUV"));
        assert_eq!(info.num("ABE_NAV_LENGTH"), Some(4.0));
        assert!(!info.is_known("NODE_REPORT_LOCAL"));
        assert!(!info.is_known("ABE_NAV_GROUP"), "no group reported");
        // The rejected report: warnings, and the C++'s empty-name entries.
        assert_eq!(info.text("_NAV_GROUP"), Some(""));
        assert_eq!(
            h.take_appcast_notes(),
            [
                AppcastNote::Warning("Bad NodeReport: NAME=cal,X=5,Y=6".into()),
                AppcastNote::Warning("The issue: Missing timestamp.".into())
            ]
        );
        // Every iteration, also under manual override; stale after contact_max_age.
        h.on_mail(&[Mail::new("MOOS_MANUAL_OVERRIDE", "true", 2.0)]);
        nav(&mut h, 2.0);
        assert_eq!(summaries(h.iterate(2.0)), ["now:1, reps:1, who:ben"]);
        nav(&mut h, 20.6);
        assert_eq!(summaries(h.iterate(20.6)), ["now:0, reps:1, who:"]);
    }

    #[test]
    fn the_able_filter_is_taken_but_not_kept_in_the_info_buffer() {
        let mut h = helm(&[("start_engaged", "true")]);
        nav(&mut h, 0.0);
        h.iterate(0.0);
        h.on_mail(&[Mail::new(
            "BHV_ABLE_FILTER",
            "action=disable,contact=ben",
            1.0,
        )]);
        nav(&mut h, 1.0);
        let p = h.iterate(1.0).to_vec();
        assert!(h.contact_disabled("ben"));
        assert!(!h.info().is_known("BHV_ABLE_FILTER"));
        // No behaviour of coug's can be disabled: none listed, the behaviour stays active.
        assert!(p.iter().all(|p| p.key != "IVPHELM_BHV_DISABLED"));
        let active = p.iter().find(|p| p.key == "IVPHELM_BHV_ACTIVE").unwrap();
        assert_eq!(active.value, Value::String("spd".into()));
        assert!(h.take_appcast_notes().is_empty());
    }
}
