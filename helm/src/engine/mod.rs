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
//! A standby helm (`STANDBY = secs`) starts in `STANDBY`, makes no decision, and takes over
//! (PARK, or DRIVE with control; posted `PARK+`/`DRIVE+`) once no other helm's
//! `IVPHELM_STATE` has come for that long; a primary helm that hears another helm in any
//! state but `STANDBY` yields (`DISABLED`). Not modelled: node reports (the contact ledger) only reach the info buffer. `RESTART_HELM`
//! is handled by the app around the engine, which reads the files again
//! ([`Helm::restart_from`]).
//!
//! # Where each part of the pHelmIvP loop is
//!
//! | part | pHelmIvP | here |
//! |---|---|---|
//! | configuration: the behaviour set from the `.bhv` entries (through a [`Registry`]), templates | `Populator_BehaviorSet`, `BehaviorSet::buildBehaviorsFromSpecs` | [`Helm::from_config_in`] (this file) |
//! | mail in, the info buffer, registrations | `OnNewMail`, `registerVariables` | `mail.rs`, [`crate::info_buffer`] |
//! | one iteration: status, nav hold, initializes, ledger, override, decision | `HelmIvP::Iterate` | [`Helm::iterate`] (this file) |
//! | spawning from templates | `BehaviorSet::handlePossibleSpawnings` | `spawn.rs` |
//! | modes and conditions | `ModeSet::evaluate`, `IvPBehavior::checkConditions` | [`crate::mode`], `behavior_set.rs` (`runnable`) |
//! | each behaviour's state, hooks and function | `BehaviorSet::produceOF` | `behavior_set.rs` |
//! | `BHV_ABLE_FILTER`, the `disabled` state, spawned behaviours whose contact left the ledger | `BehaviorSet::applyAbleFilterMsg`, `IvPBehavior::isRunnable` | `able.rs` |
//! | the solve and the summary postings | `HelmEngine::determineNextDecision`, `HelmIvP::Iterate` | `decide` (this file), [`crate::report`] |
//! | behaviour postings, flags, macros, deaths, all-stop | `postBehaviorMessages`, `IvPBehavior::postFlags`, `postAllStop` | `postings.rs`, [`crate::macro_expand`], [`crate::allstop`] |
//! | the outgoing buffers and the duplicate filter | `m_outgoing_key_strings` | `outbox.rs` |

mod able;
mod behavior_set;
mod mail;
mod outbox;
mod postings;
mod spawn;

use behavior_set::{Slot, apply_param};
use outbox::{DupFilter, Outbox};
use postings::{Message, Outgoing};

use behaviors::fmt::{compact, fixed, uint};
use behaviors::{
    Behavior, Common, Ctx, Emit, FlagKind, FlagValue, Info, Out, ParamError, PostKey, Registry,
    Templating,
};
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
    /// A standby helm (`STANDBY = secs`) waiting: it takes over, as PARK or DRIVE, once the
    /// primary helm's `IVPHELM_STATE` has been silent that long.
    Standby,
}

impl HelmState {
    /// The posted string.
    pub fn as_str(self) -> &'static str {
        match self {
            HelmState::Park => "PARK",
            HelmState::Drive => "DRIVE",
            HelmState::Malconfig => "MALCONFIG",
            HelmState::Disabled => "DISABLED",
            HelmState::Standby => "STANDBY",
        }
    }
    fn enabled(self) -> bool {
        matches!(self, HelmState::Park | HelmState::Drive)
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
    /// The behaviour types spawning builds from.
    registry: Registry,
    /// The `templating = spawn`/`clone` entries.
    templates: Vec<spawn::Template>,
    /// This iteration's behaviour-set warnings (`IVPHELM_BHVSET_WARNING`).
    bhvset_warnings: Vec<String>,
    /// This iteration's spawn and abort events (`IVPHELM_LIFE_EVENT`).
    life_events: Vec<String>,
    /// The file's behaviours' `seed=helm_startup` spawn events are still to be posted (with
    /// the first decision, as pHelmIvP posts them on its first deciding iteration).
    startup_events_pending: bool,
    /// Behaviours ever in the set (`IVPHELM_BHV_CNT_EVER`).
    bhv_total_ever: usize,
    /// The behaviours' start messages (`on_helm_start`), posted once the hold-on apps are up.
    start_msgs: Vec<(String, Value)>,
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
    /// A standby helm's last sight of another helm's `IVPHELM_STATE` (0: none yet, so no
    /// take-over before the primary has been heard once).
    standby_last_heartbeat: f64,
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
    /// `DESIRED_<VAR>` (with the helm prefix) for each domain variable, in domain order,
    /// made once.
    desired_vars: Vec<ByteString>,
    domain_str: String,
    lists: [String; 4],
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
    /// A behaviour made the process fail (BHV_TestFailure), until the app takes it.
    fault: Option<behaviors::Fault>,
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
    /// `BHV_ABLE_FILTER` messages not yet given to the behaviours (`able.rs`).
    able_pending: Vec<String>,
    /// Run warnings and events for the appcast, oldest first.
    notes: Vec<AppcastNote>,
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
    /// diagnostics (bad lines) count as configuration errors; its behaviour types from the
    /// process's registry ([`Registry::global`]).
    pub fn from_parsed<K: AsRef<str>, V: AsRef<str>>(
        params: &[(K, V)],
        globals: &Globals,
        bhv: &mission::Parsed<BehaviorFile>,
    ) -> Helm {
        Helm::from_parsed_in(Registry::global(), params, globals, bhv)
    }

    /// [`Helm::from_parsed`] with the behaviour types of `registry`.
    pub fn from_parsed_in<K: AsRef<str>, V: AsRef<str>>(
        registry: &Registry,
        params: &[(K, V)],
        globals: &Globals,
        bhv: &mission::Parsed<BehaviorFile>,
    ) -> Helm {
        let mut h = Helm::from_config_in(registry, params, globals, &bhv.value);
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

    /// A helm from its ProcessConfig parameters (file order), the globals and a `.bhv` file,
    /// its behaviour types from the process's registry ([`Registry::global`]). Never fails:
    /// any problem puts the helm in MALCONFIG, and [`Helm::config_errors`] says why (they are
    /// also posted as `IVPHELM_CONFIG_WARNING` on the first iteration).
    pub fn from_config<K: AsRef<str>, V: AsRef<str>>(
        params: &[(K, V)],
        globals: &Globals,
        bhv: &BehaviorFile,
    ) -> Helm {
        Helm::from_config_in(Registry::global(), params, globals, bhv)
    }

    /// [`Helm::from_config`] with the behaviour types of `registry`. Every entry is built and
    /// configured (a type the registry lacks or a bad line is a configuration error); a
    /// `templating = spawn` entry is kept as a template only (see the `spawn` module), a
    /// `clone` entry both ways.
    pub fn from_config_in<K: AsRef<str>, V: AsRef<str>>(
        registry: &Registry,
        params: &[(K, V)],
        globals: &Globals,
        bhv: &BehaviorFile,
    ) -> Helm {
        let (config, mut errors) = HelmConfig::parse(params, globals);
        let ownship = globals.community.clone().unwrap_or_default();
        let info = InfoBuffer::new();
        let mut slots: Vec<Slot> = Vec::new();
        let mut templates = Vec::new();
        let mut start_out = Out::default();
        for spec in &bhv.behaviors {
            let Some(b) = registry.create(&spec.kind) else {
                errors.push(ConfigError::Behavior(format!(
                    "{}: Line {}: unknown behavior type {}",
                    spec.span.file_name(),
                    spec.span.line,
                    spec.kind
                )));
                continue;
            };
            let mut slot = Slot::new(b);
            let mut ok = true;
            for p in &spec.params {
                let key = param_name(&p.key);
                let res = apply_param(&mut slot, &key, &p.value, &info, &config, &ownship);
                if let Err(e) = res {
                    ok = false;
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
            if ok {
                slot.bhv.set_common(&slot.common);
                // pHelmIvP's start messages (`onHelmStart`), templates' included.
                let ctx = Ctx {
                    info: &info,
                    domain: &config.domain,
                    ownship: &ownship,
                    name: &slot.common.name,
                    perpetual: slot.common.perpetual,
                };
                slot.bhv.on_helm_start(&ctx, &mut start_out);
            }
            let templating = slot.common.templating;
            if templating.spawns() {
                templates.push(spawn::Template::new(spec, &slot.common));
                if templating == Templating::Spawn {
                    continue;
                }
            }
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
        let start_msgs = start_out
            .emits
            .into_iter()
            .filter_map(|e| match e {
                Emit::Post { var, value, .. } => Some((var, value)),
                _ => None,
            })
            .collect();
        let initializes = bhv
            .initializes
            .iter()
            .map(|i| (i.var.trim().to_string(), auto_value(&i.value), i.deferred))
            .collect();
        let state = if !errors.is_empty() {
            HelmState::Malconfig
        } else if config.standby.is_some() {
            HelmState::Standby
        } else {
            HelmState::Park
        };
        let has_control = config.start_engaged && errors.is_empty();
        let problem = Problem::new(config.domain.clone());
        let held_apps = config
            .hold_on_apps
            .iter()
            .map(|a| (a.clone(), false))
            .collect();
        let bhv_total_ever = slots.len();
        let mut helm = Helm {
            app_name: APP_NAME.to_string(),
            registry: registry.clone(),
            templates,
            bhvset_warnings: Vec::new(),
            life_events: Vec::new(),
            startup_events_pending: true,
            bhv_total_ever,
            start_msgs,
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
            standby_last_heartbeat: 0.0,
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
            fault: None,
            scratch: String::new(),
            registered: Vec::new(),
            subs_dirty: false,
            delayed: false,
            last_report: HelmReport::default(),
            outgoing: std::collections::BTreeMap::new(),
            ledger: crate::ledger::ContactLedger::new(45.0),
            disabled_contacts: crate::ledger::DisabledContacts::default(),
            able_pending: Vec::new(),
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
                let name = if upper == "COURSE" {
                    format!("{}DESIRED_HEADING", helm.config.helm_prefix)
                } else {
                    format!("{}DESIRED_{upper}", helm.config.helm_prefix)
                };
                ByteString::from(name)
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
    fn startup(&mut self, now: f64) {
        self.started = true;
        self.start_time = now;
        if self.state == HelmState::Malconfig {
            for e in self.errors.clone() {
                self.notify_static("IVPHELM_CONFIG_WARNING", Value::text(e.to_string()));
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
            self.notify_static("IVPHELM_REGISTER", Value::String(var.into()));
        }
        // pHelmIvP keeps the files in a set: one request per file, in name order.
        let mut files = self.config.behavior_files.clone();
        files.sort();
        for f in files {
            self.notify_static(
                "PLOGGER_CMD",
                Value::String(format!("COPY_FILE_REQUEST = {f}").into()),
            );
        }
        let dom = self.config.domain.to_string();
        self.domain_str.clone_from(&dom);
        self.notify_static("IVPHELM_DOMAIN", Value::String(dom.into()));
        let ms = self.modes.definition();
        self.notify_static("IVPHELM_MODESET", Value::String(ms.into()));
        for var in [
            "IVPHELM_BHV_ACTIVE_CNT",
            "IVPHELM_BHV_IDLE_CNT",
            "IVPHELM_BHV_RUNNING_CNT",
            "IVPHELM_BHV_DISABLED_CNT",
        ] {
            self.notify_static(var, Value::Double(0.0));
        }
        if !self.config.helm_alias.is_empty() {
            let a = self.config.helm_alias.clone();
            self.notify_static("IVPHELM_ALIAS", Value::String(a.into()));
        }
    }

    fn status_update(&mut self) {
        self.state = match self.state {
            HelmState::Drive if !self.has_control => HelmState::Park,
            HelmState::Park if self.has_control => HelmState::Drive,
            s => s,
        };
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

    /// Reference §4.3 step 3: NAV_X, NAV_Y, NAV_HEADING, NAV_SPEED (and NAV_DEPTH with a
    /// depth domain) must each have been received once.
    fn nav_ready(&self) -> bool {
        ["NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"]
            .iter()
            .all(|v| self.info.is_known(v))
            && (self.config.domain.get("depth").is_none() || self.info.is_known("NAV_DEPTH"))
    }

    /// Takes the failure a behaviour inflicted on the helm's process during the last
    /// iteration (BHV_TestFailure), for the app to act on: a crash ends the app before it
    /// publishes that iteration's postings, a burn holds them back.
    pub fn take_fault(&mut self) -> Option<behaviors::Fault> {
        self.fault.take()
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
        // The behaviours' start messages (MOOS `handleHelmStartMessages`), once every
        // hold-on app is up.
        if !self.start_msgs.is_empty() && !self.holding() && self.state != HelmState::Malconfig {
            for (var, value) in std::mem::take(&mut self.start_msgs) {
                let var = var.trim();
                if var.contains(char::is_whitespace) {
                    continue;
                }
                self.info.set(var, value.clone(), APP_NAME, now);
                self.notify(var, value, "HELM_STARTUP_MSG");
            }
        }

        // §4.3 step 1: status, IVPHELM_STATE.
        self.status_update();
        if self.state == HelmState::Disabled {
            if !self.disabled_posted {
                self.disabled_posted = true;
                self.notify_static("IVPHELM_STATE", Value::String("DISABLED".into()));
            }
        } else {
            let s = self.state.as_str();
            if self.config.standby.is_some() && self.state.enabled() {
                // A standby helm that took over says so: `DRIVE+`, `PARK+`.
                self.out.text_copy("IVPHELM_STATE", &format!("{s}+"));
            } else {
                self.out.text_copy("IVPHELM_STATE", s);
            }
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
        // about get twice the time), the behaviours' snapshot of it is refreshed, and it is
        // summarised.
        let keep: Vec<&str> = self
            .slots
            .iter()
            .filter_map(|s| s.bhv.contact_name())
            .collect();
        self.ledger.clear_stale(now, &keep, 2.0);
        self.info.set_contacts(&self.ledger);
        if !keep.is_empty() {
            let summary = keep.join(",");
            self.out.text_copy("IVPHELM_CONTACT_SUMMARY", &summary);
        }
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
            self.notify_static("IVPHELM_RESTARTED", Value::String("true".into()));
        }
        // pHelmIvP's `updatePlatModel`: the behaviours' platform model for this decision,
        // and the turn rate of its heading history (`crate::plat_model`).
        if self.info.update_plat_model(&mut self.config.pmgen, now) {
            let rate = self.config.pmgen.turn_rate();
            self.notify_static("TURN_RATE", Value::Double(rate));
        }
        self.decide(now);
        self.cap_appcast_notes();
        self.out.as_slice()
    }

    fn decide(&mut self, now: f64) {
        self.iteration += 1;
        let iter = self.iteration;
        if std::mem::take(&mut self.startup_events_pending) {
            for i in 0..self.slots.len() {
                let (name, kind) = (
                    self.slots[i].common.name.clone(),
                    self.slots[i].common.kind.clone(),
                );
                self.life_event(&name, &kind, "spawn", "helm_startup", "", now);
            }
        }
        self.update_results.clear();
        self.messages.clear();
        self.problem.clear();

        // A behaviour error halts this iteration only (MOOS resets the state each time).
        for s in &mut self.slots {
            s.ok = true;
        }
        self.apply_able_filters();
        self.handle_spawnings(now);
        let modes: Vec<(String, String)> = self.modes.evaluate(&mut self.info).to_vec();

        let mut report = HelmReport {
            iteration: iter,
            time: now,
            domain: None,
            modes: self.modes.summary(),
            spawnable: self
                .templates
                .iter()
                .map(spawn::Template::summary)
                .collect(),
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
                            var: ByteString::from_static("BHV_ERROR"),
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
                RunState::Disabled => report.disabled.push(line),
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
            self.notify_static("IVPHELM_UPDATE_RESULT", Value::String(r.into()));
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
        report.render_after(
            &self.domain_str,
            Some(&self.config.domain),
            Some((&self.last_report, &self.prev_report)),
            &mut rendered,
        );
        let full = std::mem::take(&mut self.rejournal);
        let prev = &self.prev_report;
        self.out.text("IVPHELM_SUMMARY", |summary| {
            if full {
                rendered.summary(iter, now, &Rendered::default(), summary);
            } else {
                rendered.summary(iter, now, prev, summary);
            }
        });
        self.notify_static("IVPHELM_IPF_CNT", Value::Double(report.ofnum as f64));
        self.notify_static(
            "IVPHELM_TOTAL_PCS_FORMED",
            Value::Double(report.pcs_formed as f64),
        );
        self.notify_static(
            "IVPHELM_TOTAL_PCS_CACHED",
            Value::Double(report.pcs_cached as f64),
        );
        let counts = [
            report.active.len(),
            report.running.len(),
            report.idle.len(),
            report.disabled.len(),
        ];
        for (k, cnt) in counts.into_iter().enumerate() {
            let mut list = std::mem::take(&mut self.scratch);
            report.write_names(k, &mut list);
            if self.lists[k] != list {
                let [base, base_cnt] = [
                    ["IVPHELM_BHV_ACTIVE", "IVPHELM_BHV_ACTIVE_CNT"],
                    ["IVPHELM_BHV_RUNNING", "IVPHELM_BHV_RUNNING_CNT"],
                    ["IVPHELM_BHV_IDLE", "IVPHELM_BHV_IDLE_CNT"],
                    ["IVPHELM_BHV_DISABLED", "IVPHELM_BHV_DISABLED_CNT"],
                ][k];
                self.out.text_copy(base, &list);
                self.notify_static(base_cnt, Value::Double(cnt as f64));
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
                self.notify_static("BHV_ERROR", Value::String(msg.clone().into()));
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
                let key = self.desired_vars[i].clone();
                self.out.next_key(key).value = Value::Double(val);
            }
        }
        self.notify_static("IVPHELM_CREATE_CPU", Value::Double(0.0));
        self.notify_static("IVPHELM_LOOP_CPU", Value::Double(0.0));
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
            &mut old.disabled,
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
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testing;

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
        let mut h = testing::engaged(BHV, &[("goals_mandatory", goals_mandatory)]);
        for slot in &mut h.slots {
            if constraints.contains(&slot.common.name.as_str()) {
                let inner = std::mem::replace(&mut slot.bhv, Box::new(behaviors::Timer::new()));
                slot.bhv = Box::new(AsConstraint(inner));
            }
        }
        h
    }

    fn step(h: &mut Helm, t: f64) -> Vec<Posting> {
        testing::nav(h, t, (0.0, 0.0, 0.0, 0.0));
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
    use crate::testing;

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
        let mut h = testing::engaged(BHV, &[]);
        let nav = |h: &mut Helm, t: f64| testing::nav(h, t, (0.0, 0.0, 0.0, 0.0));
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
    use crate::testing;
    use behaviors::Info;

    fn helm(extra: &[(&str, &str)]) -> Helm {
        let mut params = testing::COURSE_SPEED.to_vec();
        params.extend_from_slice(extra);
        testing::from_text(
            "g.bhv",
            "Behavior = BHV_ConstantSpeed\n{\n name = spd\n speed = 1\n duration = no-time-limit\n}\n",
            &params,
        )
    }

    fn nav(h: &mut Helm, t: f64) {
        testing::nav(h, t, (0.0, 0.0, 0.0, 0.0));
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
    fn contact_behaviours_read_the_ledger_and_keep_their_contact_twice_as_long() {
        let mut h = testing::engaged(
            "Behavior = BHV_ConstantSpeed\n{\n name = spd\n speed = 1\n duration = no-time-limit\n}\n\
             Behavior = BHV_AvoidCollision\n{\n name = avd_ben\n pwt = 200\n contact = ben\n}\n",
            &[("contact_max_age", "20")],
        );
        nav(&mut h, 0.0);
        h.on_mail(&[Mail::new(
            "NODE_REPORT",
            "NAME=ben,X=0,Y=100,SPD=2,HDG=180,TIME=0.5,TYPE=kayak,GROUP=red",
            0.0,
        )]);
        h.iterate(0.0);
        let c = h
            .info()
            .contact("ben")
            .expect("the snapshot has the contact");
        assert_eq!(
            (c.x_m, c.y_m, c.heading_deg, c.speed_mps),
            (0.0, 100.0, 180.0, 2.0)
        );
        assert_eq!((c.group.as_str(), c.vtype.as_str()), ("red", "kayak"));
        nav(&mut h, 2.0);
        let p = h.iterate(2.0).to_vec();
        let summary = p
            .iter()
            .find(|p| p.key == "IVPHELM_CONTACT_SUMMARY")
            .unwrap();
        assert_eq!(summary.value, Value::String("ben".into()));
        // The behaviour's function weighs pwt x relevance: ((200-100)/150)^1.5.
        assert!(
            p.iter()
                .any(|p| p.key == "BHV_IPF"
                    && p.value.as_str().is_some_and(|s| s.contains("avd_ben")))
        );
        let relevance = (100.0f64 / 150.0).powf(1.5);
        let w = h
            .problem
            .functions()
            .find(|(n, _)| *n == "avd_ben")
            .map(|(_, f)| f.pwt())
            .expect("in the problem");
        assert!((w - 200.0 * relevance).abs() < 1e-9, "{w}");
        // 30 s old (past contact_max_age 20, within twice it): kept for the behaviour.
        nav(&mut h, 30.0);
        h.iterate(30.0);
        assert!(h.info().contact("ben").is_some());
        assert_eq!(h.ledger().len(), 1);
        nav(&mut h, 41.0);
        h.iterate(41.0);
        assert_eq!(
            h.ledger().len(),
            0,
            "gone from the ledger after twice the age"
        );
        assert!(h.info().contact("ben").is_none(), "and from the snapshot");
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
        // A constant-speed behaviour ignores the filter: none listed, it stays active.
        assert!(p.iter().all(|p| p.key != "IVPHELM_BHV_DISABLED"));
        let active = p.iter().find(|p| p.key == "IVPHELM_BHV_ACTIVE").unwrap();
        assert_eq!(active.value, Value::String("spd".into()));
        assert!(h.take_appcast_notes().is_empty());
    }
}
