//! The [`Behavior`] trait and what the helm hands to and takes from a behaviour.

use std::collections::HashMap;

use ivp::{Domain, IvpFunction};

use crate::common::{Common, Flag};

/// A posted value: the workspace's one MOOS value type.
pub use moos_types::Value;

/// How the helm's duplicate filter treats a posting (reference §4.5): by default a posting is
/// made only when its value differs from the last one posted under the same key.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PostKey {
    /// Key `<behaviour name><var>` (MOOS `postMessage(var, val)`).
    Var,
    /// Key `<behaviour name><var><tag>` (MOOS `postMessage(var, val, tag)`), e.g. the waypoint's
    /// `VIEW_POINT` for the next point (`wpt`) and the track point (`trk`).
    Tag(&'static str),
    /// Never filtered (MOOS key `repeatable`).
    Repeatable,
}

/// One thing a behaviour emits during a call, in order.
#[derive(Debug, Clone, PartialEq)]
pub enum Emit {
    /// A message posted as is.
    Post {
        /// MOOS variable.
        var: String,
        /// Value.
        value: Value,
        /// Duplicate-filter key.
        key: PostKey,
    },
    /// A flag (`VAR = value`) posted by the behaviour itself (waypoint `wptflag`, `cycleflag`):
    /// the helm expands macros and types the value as for the common flags.
    Flag {
        /// The flag.
        flag: Flag,
        /// Never filtered by the duplicate filter.
        repeatable: bool,
    },
    /// The behaviour declared itself complete at this point of its output (MOOS
    /// `setComplete()`): the helm posts the endflags here.
    Complete,
    /// The behaviour's common endflags, posted without completing (BHV_LegRun's
    /// `postFlags(m_end_flags)` when its legs are done).
    EndFlags {
        /// Never filtered by the duplicate filter.
        repeatable: bool,
    },
}

/// The output buffer of one behaviour call: postings, completion, errors.
#[derive(Debug, Default, Clone)]
pub struct Out {
    /// Emitted postings and flags, in order.
    pub emits: Vec<Emit>,
    /// The behaviour declared itself complete (MOOS `setComplete()`): the helm posts the
    /// endflags and, unless the behaviour is perpetual, marks it completed.
    pub completed: bool,
    /// The behaviour hit an error (MOOS `postEMessage`): the helm posts `BHV_ERROR` and halts.
    pub error: Option<String>,
    /// The behaviour makes the helm's process fail (BHV_TestFailure): the helm keeps the
    /// first one until its app acts on it ([`Fault`]).
    pub fault: Option<Fault>,
    /// Why the behaviour completed (MOOS `setComplete(post_mortem)`), given to
    /// [`Behavior::post_mortem`] when the helm records its death; empty by default.
    pub post_mortem: String,
}

/// A failure a behaviour inflicts on the helm's process, as MOOS-IvP's BHV_TestFailure does
/// to pHelmIvP.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Fault {
    /// The process aborts (the C++ `assert(0)`): the postings of that iteration are never
    /// published and the helm is gone from the community.
    Crash,
    /// The process hangs for this many seconds (the C++ busy loop), then goes on: the
    /// iteration's postings come out late and no iteration runs meanwhile.
    Burn(f64),
}

impl Out {
    /// Posts `var = value` with the default key (filtered on change).
    pub fn post(&mut self, var: impl Into<String>, value: impl Into<Value>) {
        self.post_key(var, value, PostKey::Var);
    }
    /// Posts `var = value` with the given duplicate-filter key.
    pub fn post_key(&mut self, var: impl Into<String>, value: impl Into<Value>, key: PostKey) {
        self.emits.push(Emit::Post {
            var: var.into(),
            value: value.into(),
            key,
        });
    }
    /// Posts a number rounded to the nearest integer (MOOS `postIntMessage`).
    pub fn post_int(&mut self, var: impl Into<String>, v: f64) {
        self.post(var, (v + 0.5).floor());
    }
    /// Posts a flag for macro expansion by the helm.
    pub fn flag(&mut self, flag: &Flag, repeatable: bool) {
        self.emits.push(Emit::Flag {
            flag: flag.clone(),
            repeatable,
        });
    }
    /// Declares the behaviour complete.
    pub fn complete(&mut self) {
        self.completed = true;
        self.emits.push(Emit::Complete);
    }
    /// Declares the behaviour complete, saying why (MOOS `setComplete(post_mortem)`): the
    /// reason goes into the `post_mortem` of its death's `IVPHELM_LIFE_EVENT`.
    pub fn complete_because(&mut self, reason: impl Into<String>) {
        self.post_mortem = reason.into();
        self.complete();
    }
    /// Asks the helm to post the behaviour's common endflags now, without completing it.
    pub fn end_flags(&mut self, repeatable: bool) {
        self.emits.push(Emit::EndFlags { repeatable });
    }
    /// Reports an error (`BHV_ERROR`, helm halts).
    pub fn error(&mut self, msg: impl Into<String>) {
        self.error = Some(msg.into());
    }
    /// Posts a warning (`BHV_WARNING = <name>: <msg>`, repeatable).
    pub fn warning(&mut self, name: &str, msg: &str) {
        self.post_key("BHV_WARNING", format!("{name}: {msg}"), PostKey::Repeatable);
    }
    /// Makes the helm's process fail ([`Fault`]).
    pub fn fault(&mut self, fault: Fault) {
        self.fault = Some(fault);
    }
    /// Empties the buffer for reuse.
    pub fn clear(&mut self) {
        self.emits.clear();
        self.completed = false;
        self.error = None;
        self.fault = None;
        self.post_mortem.clear();
    }
}

/// What a behaviour may read from the helm's info buffer.
pub trait Info {
    /// The current helm time, seconds.
    fn now(&self) -> f64;
    /// A variable's value as a number: a double, or a numeric string.
    fn num(&self, var: &str) -> Option<f64>;
    /// A variable's value if it is a string.
    fn text(&self, var: &str) -> Option<&str>;
    /// Seconds since the variable was last written (MOOS `getBufferTimeVal`): 0 when it was
    /// posted during this iteration, even with the same value as before; `None` if never.
    fn age(&self, var: &str) -> Option<f64>;
    /// Whether the variable was posted during this iteration (age 0).
    fn is_fresh(&self, var: &str) -> bool {
        self.age(var) == Some(0.0)
    }
    /// The contact `name` (as reported, case-sensitive) in the helm's contact ledger this
    /// iteration (pHelmIvP's ledger snapshot), or `None`. The default knows no contact.
    fn contact(&self, _name: &str) -> Option<&crate::contact::ContactInfo> {
        None
    }
    /// The helm's platform model this iteration (pHelmIvP's `setPlatModel`), once it has
    /// known all of `NAV_X`, `NAV_Y`, `NAV_HEADING` and `NAV_SPEED`. The default has none.
    fn plat_model(&self) -> Option<&crate::plat_model::PlatModel> {
        None
    }
}

/// A small [`Info`] over a map, for tests and examples.
#[derive(Debug, Clone, Default)]
pub struct MapInfo {
    now: f64,
    vars: HashMap<String, (Value, f64)>,
    contacts: HashMap<String, crate::contact::ContactInfo>,
    plat_model: Option<crate::plat_model::PlatModel>,
}

impl MapInfo {
    /// An empty buffer at time `now`.
    pub fn new(now: f64) -> Self {
        MapInfo {
            now,
            vars: HashMap::new(),
            contacts: HashMap::new(),
            plat_model: None,
        }
    }
    /// Builder: the helm's platform model [`Info::plat_model`] gives.
    pub fn with_plat_model(mut self, m: crate::plat_model::PlatModel) -> Self {
        self.plat_model = Some(m);
        self
    }
    /// Builder: puts contact `name` in the ledger [`Info::contact`] reads.
    pub fn with_contact(mut self, name: &str, c: crate::contact::ContactInfo) -> Self {
        self.contacts.insert(name.to_string(), c);
        self
    }
    /// Builder: sets a number (written at the current time).
    pub fn num(mut self, var: &str, v: f64) -> Self {
        self.set(var, Value::Double(v));
        self
    }
    /// Builder: sets a string (written at the current time).
    pub fn text(mut self, var: &str, v: &str) -> Self {
        self.set(var, Value::text(v));
        self
    }
    /// Sets a variable, written at the current time (its age is 0 until the time moves on).
    ///
    /// ```
    /// use behaviors::{Info, MapInfo, Value};
    /// let mut info = MapInfo::new(5.0);
    /// info.set("RESET", Value::String("true".into()));
    /// assert!(info.is_fresh("RESET"));
    /// info.set_now(7.5);
    /// assert_eq!(info.age("RESET"), Some(2.5));
    /// assert_eq!(info.age("NEVER"), None);
    /// ```
    pub fn set(&mut self, var: &str, v: Value) {
        self.vars.insert(var.to_string(), (v, self.now));
    }
    /// Sets the time.
    pub fn set_now(&mut self, now: f64) {
        self.now = now;
    }
}

impl Info for MapInfo {
    fn now(&self) -> f64 {
        self.now
    }
    fn num(&self, var: &str) -> Option<f64> {
        self.vars.get(var)?.0.as_ref().as_f64()
    }
    fn text(&self, var: &str) -> Option<&str> {
        self.vars.get(var)?.0.as_str()
    }
    fn age(&self, var: &str) -> Option<f64> {
        self.vars.get(var).map(|(_, t)| self.now - t)
    }
    fn contact(&self, name: &str) -> Option<&crate::contact::ContactInfo> {
        self.contacts.get(name)
    }
    fn plat_model(&self) -> Option<&crate::plat_model::PlatModel> {
        self.plat_model.as_ref()
    }
}

/// The context of one behaviour call.
#[derive(Clone, Copy)]
pub struct Ctx<'a> {
    /// The helm's variables and time.
    pub info: &'a dyn Info,
    /// The helm's decision domain.
    pub domain: &'a Domain,
    /// The vehicle name (MOOS community), `$[OWNSHIP]`.
    pub ownship: &'a str,
    /// The behaviour's name.
    pub name: &'a str,
    /// Whether the behaviour is perpetual (common parameter `perpetual`).
    pub perpetual: bool,
}

/// Ownship navigation from the info buffer: `(NAV_X, NAV_Y, NAV_HEADING, NAV_SPEED)`; `None`
/// unless x, y and heading are known (speed defaults to 0, as MOOS only warns about it).
pub fn nav(info: &dyn Info) -> Option<(f64, f64, f64, f64)> {
    let x = info.num("NAV_X")?;
    let y = info.num("NAV_Y")?;
    let h = info.num("NAV_HEADING")?;
    let v = info.num("NAV_SPEED").unwrap_or(0.0);
    Some((x, y, geometry::angle_360(h), v))
}

/// Appends each of `vars` to `out` unless already there (for [`Behavior::info_vars`]).
pub(crate) fn add_vars<'a>(out: &mut Vec<String>, vars: impl IntoIterator<Item = &'a str>) {
    for v in vars {
        if !v.is_empty() && !out.iter().any(|o| o == v) {
            out.push(v.to_string());
        }
    }
}

/// Appends the variables of the `[if]` conditions of `flags` (for [`Behavior::info_vars`]).
pub(crate) fn add_flag_vars(out: &mut Vec<String>, flags: &[Flag]) {
    for f in flags {
        if let Some(c) = &f.condition {
            add_vars(out, c.variables());
        }
    }
}

/// A rejected parameter.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ParamError {
    /// The behaviour has no such parameter.
    #[error("unknown parameter `{param}`")]
    Unknown {
        /// The parameter name (lower case).
        param: String,
    },
    /// The value is not acceptable.
    #[error("bad value `{value}` for `{param}`: expected {expected}")]
    BadValue {
        /// The parameter name.
        param: String,
        /// The value given.
        value: String,
        /// What is accepted.
        expected: &'static str,
    },
}

impl ParamError {
    /// An [`ParamError::Unknown`] for `param`.
    pub fn unknown(param: &str) -> Self {
        ParamError::Unknown {
            param: param.to_string(),
        }
    }
    /// A [`ParamError::BadValue`].
    pub fn bad(param: &str, value: &str, expected: &'static str) -> Self {
        ParamError::BadValue {
            param: param.to_string(),
            value: value.to_string(),
            expected,
        }
    }
}

/// A helm behaviour. The helm calls the hooks as pHelmIvP's `BehaviorSet::produceOF` does
/// (reference §4.4): `on_idle_to_run` / `on_run_to_idle` on transitions, `on_idle` every idle
/// iteration, `on_run` every running iteration (returning the objective function or `None`),
/// `on_complete` when completed.
pub trait Behavior: Send {
    /// The type name, e.g. `BHV_Waypoint` (`$[BHVTYPE]`).
    fn kind(&self) -> &'static str;

    /// The decision variables this behaviour's functions range over (MOOS narrows each
    /// behaviour's domain with `subDomain` in its constructor). When the helm's domain lacks
    /// any of them the behaviour has a null domain: the helm keeps it idle (`pc=null-domain`)
    /// and reports `BHV_ERROR = <name>: Null IvPDomain given to Behavior`, as pHelmIvP does.
    /// Empty (the default) = the helm's whole domain.
    ///
    /// ```
    /// assert_eq!(behaviors::create("BHV_MaxDepth").unwrap().domain_vars(), ["depth"]);
    /// assert!(behaviors::create("BHV_Timer").unwrap().domain_vars().is_empty());
    /// ```
    fn domain_vars(&self) -> &'static [&'static str] {
        &[]
    }

    /// The name a behaviour of this type gets without a `name` line: the descriptor its
    /// MOOS-IvP constructor sets (e.g. `bhv_waypoint`, `maxdepth`, `periodic_surface`).
    /// Defaults to the type name.
    ///
    /// ```
    /// assert_eq!(behaviors::create("BHV_StationKeep").unwrap().default_name(), "station_keep");
    /// ```
    fn default_name(&self) -> &'static str {
        self.kind()
    }

    /// Whether this type is a *constraint* behaviour rather than a *goal* behaviour (MOOS
    /// `IvPBehavior::isConstraint`, a per-type property, false by default). With the helm's
    /// `goals_mandatory = true`, an iteration in which no active behaviour is a goal behaviour
    /// all-stops with `NoGoalBehavior`. In MOOS-IvP the collision/obstacle avoidance, max-speed
    /// and tow-safety types are constraints; of coug's types BHV_MaxSpeed and
    /// BHV_MemoryTurnLimit are, the others are goal behaviours (BHV_MaxDepth included, as in
    /// MOOS-IvP).
    ///
    /// ```
    /// assert!(!behaviors::create("BHV_MaxDepth").unwrap().is_constraint());
    /// assert!(!behaviors::create("BHV_Waypoint").unwrap().is_constraint());
    /// assert!(behaviors::create("BHV_MaxSpeed").unwrap().is_constraint());
    /// ```
    fn is_constraint(&self) -> bool {
        false
    }

    /// Common parameters this type's MOOS constructor sets (`IvPBehavior::setParam` there),
    /// applied by the helm before the file's lines: e.g. BHV_PeriodicSpeed's
    /// `activeflag = PERIODIC_SPEED=1`. None by default.
    ///
    /// ```
    /// let b = behaviors::create("BHV_PeriodicSpeed").unwrap();
    /// assert_eq!(b.default_common_params()[0], ("activeflag", "PERIODIC_SPEED=1"));
    /// assert!(behaviors::create("BHV_Waypoint").unwrap().default_common_params().is_empty());
    /// ```
    fn default_common_params(&self) -> &'static [(&'static str, &'static str)] {
        &[]
    }

    /// The default `duration` of this type (−1 = none). ConstantSpeed/Heading/Depth use 0
    /// (reference §5.5).
    fn default_duration(&self) -> f64 {
        -1.0
    }

    /// Sets one behaviour-specific parameter (`param` lower case, `value` trimmed).
    /// Returns [`ParamError::Unknown`] for a parameter it does not have. `common` is given so
    /// a parameter may also change a common setting (e.g. waypoint `repeat` makes it
    /// perpetual). The common parameters never reach it. The default (a behaviour with no
    /// parameters of its own) refuses every name.
    fn set_param(
        &mut self,
        param: &str,
        _value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        Err(ParamError::unknown(param))
    }

    /// Once, when the helm starts, for every behaviour of the file, `templating = spawn`
    /// templates included (MOOS `onHelmStart`): what it posts goes out once the helm's
    /// `hold_on_apps` are up, with source aux `HELM_STARTUP_MSG`, and into the info buffer
    /// (e.g. a contact behaviour's alert request to the contact manager).
    fn on_helm_start(&mut self, _ctx: &Ctx<'_>, _out: &mut Out) {}

    /// Once configuration is complete, before [`Behavior::on_helm_start`]: the behaviour's
    /// common settings (its `updates` variable, `templating`), for behaviours whose start
    /// messages depend on them (a contact behaviour's alert request).
    fn set_common(&mut self, _common: &Common) {}

    /// The contact this behaviour reasons about, if any (MOOS `getContactName`): the helm
    /// keeps such contacts in its ledger twice as long and lists them in
    /// `IVPHELM_CONTACT_SUMMARY`.
    fn contact_name(&self) -> Option<&str> {
        None
    }

    /// A `BHV_ABLE_FILTER` message (MOOS `applyAbleFilter`), handed to every behaviour of
    /// the set when it arrives: a behaviour that can be disabled (a contact behaviour with
    /// `can_disable`, [`crate::contact::AbleFilter`]) disables or enables itself, or completes
    /// (`expunge`, through [`Out::complete`]). Returns false for a message it finds malformed
    /// (the helm then warns `Unhandled BHV_ABLE_FILTER`). The default ignores it.
    fn apply_able_filter(&mut self, _msg: &str, _out: &mut Out) -> bool {
        true
    }

    /// Whether a `BHV_ABLE_FILTER` disabled this behaviour (MOOS `m_disabled`): the helm
    /// then reports it `disabled` (`IVPHELM_BHV_DISABLED`), calls
    /// [`Behavior::on_disabled`] instead of the idle or running hooks, and builds no
    /// function. False by default.
    fn is_disabled(&self) -> bool {
        false
    }

    /// Every iteration in which the behaviour is disabled (MOOS `onDisabledState`).
    fn on_disabled(&mut self, _ctx: &Ctx<'_>, _out: &mut Out) {}

    /// The factor the helm multiplies the priority weight (`pwt`) by for the function this
    /// iteration's [`Behavior::on_run`] returned: a contact behaviour's relevance (MOOS
    /// behaviours set `m_priority_wt · relevance` on their function). 1 by default.
    fn pwt_factor(&self) -> f64 {
        1.0
    }

    /// When the helm spawns this behaviour from a template (MOOS `onSpawn`), after its
    /// parameters and [`Behavior::on_set_param_complete`], before its `spawnflag`s.
    fn on_spawn(&mut self, _ctx: &Ctx<'_>, _out: &mut Out) {}

    /// Called after configuration and after each successful update. Postings made here at
    /// configuration go out on the helm's first iteration, before the behaviour's own
    /// postings of that iteration (as pHelmIvP does with those made in `onSetParamComplete`);
    /// after an update, in the iteration of the update.
    ///
    /// The default posts [`Behavior::config_status`] (MOOS `IvPBehavior::onSetParamComplete`
    /// calls `postConfigStatus`); an override that should post it calls
    /// [`post_config_status`].
    fn on_set_param_complete(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        post_config_status(&*self, ctx, out);
    }

    /// The behaviour's settings as MOOS `postConfigStatus` posts them in BHV_SETTINGS
    /// (`type=BHV_Loiter,name=..,...`), or `None` for a behaviour that posts none. The helm
    /// posts it after each successful update (MOOS `checkUpdates`), besides what
    /// [`Behavior::on_set_param_complete`] does.
    fn config_status(&self, _name: &str) -> Option<String> {
        None
    }

    /// Appends the MOOS variables this behaviour reads from the info buffer (MOOS
    /// `addInfoVars`), so that the helm subscribes to them: navigation variables, a mark or
    /// reset variable, the variables of its own conditions and flag conditions. The common
    /// parameters' variables (`condition`, `updates`, `duration_reset`, `nostarve`, flag
    /// conditions) are the helm's business and need not be listed. Duplicates are harmless.
    ///
    /// ```
    /// let mut vars = Vec::new();
    /// behaviors::create("BHV_PeriodicSurface").unwrap().info_vars(&mut vars);
    /// assert!(vars.iter().any(|v| v == "GPS_UPDATE_RECEIVED"));
    /// ```
    fn info_vars(&self, _out: &mut Vec<String>) {}

    /// Before `on_idle` / `on_run` each iteration: the seconds spent idle and running since
    /// the duration clock last (re)started (MOOS `m_duration_idle_time`,
    /// `m_duration_running_time`, accounted up to the previous iteration).
    fn state_durations(&mut self, _idle: f64, _running: f64) {}

    /// Each iteration, after updates are applied: the helm's iteration number (MOOS
    /// `setHelmIteration`, the `IVPHELM_ITER` value), for behaviours whose output depends on it.
    fn set_helm_iteration(&mut self, _iteration: u64) {}

    /// Every idle iteration.
    fn on_idle(&mut self, _ctx: &Ctx<'_>, _out: &mut Out) {}

    /// On the idle→running transition (before `on_run`).
    fn on_idle_to_run(&mut self, _ctx: &Ctx<'_>, _out: &mut Out) {}

    /// On the running/active→idle transition.
    fn on_run_to_idle(&mut self, _ctx: &Ctx<'_>, _out: &mut Out) {}

    /// A running iteration: the objective function, or `None` (no opinion).
    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction>;

    /// When the behaviour is found completed.
    fn on_complete(&mut self, _ctx: &Ctx<'_>, _out: &mut Out) {}

    /// The `post_mortem` of this behaviour's death event (MOOS `m_post_mortem`), when it
    /// completes for `reason` ([`Out::complete_because`]; empty for a plain
    /// [`Out::complete`] or a `duration` running out). The default is the reason itself; a
    /// contact behaviour appends the range and bearing to its contact
    /// ([`crate::contact::ContactBase::post_mortem`]), as IvPContactBehavior's `setComplete`.
    fn post_mortem(&self, reason: &str) -> String {
        reason.to_string()
    }

    /// Appends the value of a behaviour-specific macro (e.g. the waypoint's `NX`, `SPEED`) and
    /// returns true, or returns false if `name` is not one of its macros.
    fn macro_value(&self, _name: &str, _out: &mut String) -> bool {
        false
    }
}

/// Posts `b`'s [`Behavior::config_status`] as BHV_SETTINGS (repeatable), if it has one.
pub fn post_config_status<B: Behavior + ?Sized>(b: &B, ctx: &Ctx<'_>, out: &mut Out) {
    if let Some(s) = b.config_status(ctx.name) {
        out.post_key("BHV_SETTINGS", s, PostKey::Repeatable);
    }
}
