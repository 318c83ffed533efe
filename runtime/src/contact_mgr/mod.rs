//! `pBasicContactMgr`: other vehicles' `NODE_REPORT`s become contacts with ranges and a
//! closest point of approach, and alerts (configured, or requested by the helm's contact
//! behaviours through `BCM_ALERT_REQUEST`) post a flag per contact that comes within range, so
//! the helm spawns a behaviour per contact (issue #18, point 3).
//!
//! [`ContactMgr`] is the pure core (mail and time in, posts out); [`ContactMgrApp`] is the
//! app with its appcast (a [`Hosted`] core). Facts from MOOS-IvP's `dep_pBasicContactMgr` at
//! a2a9b716 (`BasicContactMgr`, `CMAlert`, `PlatformAlertRecord`).
//!
//! With `contact_local_coords` at `lazy_lat_lon` or `force_lat_lon` and the mission's grid
//! ([`ContactMgr::with_grid`]), a report's x/y come from its latitude and longitude when it
//! arrives (lazy: only for a report without x or y).
//!
//! The same core is `pContactMgrV20` when built as [`Variant::V20`] ([`ContactMgr::new_v20`]):
//! what V20 changes (its keys and defaults, filters, alert ranges and validity, the helm hold,
//! range and closest-bearing postings, retirement and culling, early warnings, enabling and
//! disabling contacts, its appcast) is in [`v20`] with its own conformance table.
//!
//! Each iteration: ranges (actual, extrapolated with the `decay` policy, and the CPA over 10
//! hours holding ownship's heading and speed), retirement (report older than
//! `contact_max_age`, or beyond `reject_range + 10` m), requested range reports, summaries,
//! alerts, the close-in evaluation, then the alert circles when `display_radii`.
//!
//! An alert applies to a contact when the report is not older than `contact_max_age`, its
//! type and group pass the alert's match/ignore lists, and, for an alert range `> 0`, the
//! contact is within `cpa_range` and either within `alert_range` or its CPA is; and, for an
//! alert with a region, the contact is inside it. On the transition the alert's `on_flag`s
//! (off: `off_flag`s) are posted with the macros `$[X]`, `$[Y]`, `$[LAT]`, `$[LON]`, `$[HDG]`,
//! `$[DEP]`, `$[VNAME]`, `$[VTYPE]`, `$[UTIME]`, `%[VNAME]`, `%[VTYPE]` (lower case) expanded
//! (`$[SPD]` is not: the C++ looks for `$[SPD}`).
//!
//! # Conformance with pBasicContactMgr (MOOS-IvP a2a9b716)
//!
//! | parameter | default | validation (C++ rule) | coug |
//! |---|---|---|---|
//! | alert | none | `id=..`, `var=`, `val=`/`pattern=`, `on_flag=`/`onflag=`, `off_flag=`/`offflag=`, `region=` (convex), `alert_range=`, `cpa_range=` (numbers), `alert_range_color=`, `cpa_range_color=` (colours), `match_type=`, `ignore_type=`, `match_group=`, `ignore_group=`; anything else: `Failed alert config` | done |
//! | ignore_group | none | a group not already ignored | done |
//! | decay | 15,30 | `start,end` numbers, `0 <= start <= end` | done |
//! | range_report_timeout | 10 | number >= 0 | done |
//! | display_radii | false | boolean | done |
//! | post_closest_range | false | boolean | done |
//! | max_retired_history | 5 | 1..50 (clipped, warned) | done |
//! | contact_local_coords | verbatim | verbatim, lazy_lat_lon, force_lat_lon; other than verbatim needs `LatOrigin`/`LongOrigin` (warned without) | done: x/y from the report's lat/lon on the mission's grid (`vehicle::geodesy`, UTM as the C++ builds), lazy only when x or y is missing, force always, before the reject range |
//! | alert_range, default_alert_range | 1000 | > 0 | done |
//! | alert_cpa_range, default_cpa_range | 1000 | > 0 | done |
//! | contacts_recap_interval | 1 | `off` or >= 0 | done |
//! | reject_range | 2000 | `off` or >= 0 | done |
//! | alert_cpa_time | | deprecated (warned) | done |
//! | alert_verbose | false | boolean | done |
//! | default_alert_range_color, default_cpa_range_color | gray65, gray35 | colours | done |
//! | contact_max_age | 600 | > 0 | done |
//! | eval_range_far, eval_range_near | 20, 10 | >= 0, kept ordered | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | the alerts' flags | a contact enters (on) or leaves (off) an alert | `VAR = value` with macros | done |
//! | CONTACTS_LIST | on change | names, comma-separated, in name order | done |
//! | CONTACTS_ALERTED, CONTACTS_UNALERTED | on change | `(vname,alert_id)...` (names in lower case) | done |
//! | CONTACTS_RETIRED | on change | newest first, at most `max_retired_history` kept | done |
//! | CONTACTS_COUNT | on change | the alerted pairs' count (double) | done |
//! | CONTACTS_RECAP | every `contacts_recap_interval` s | `vname=..,range=..,age=.. # ...` (2 decimals) | done |
//! | CONTACT_CLOSEST, CONTACT_CLOSEST_TIME | the closest contact changes | name; time | done |
//! | CONTACT_CLOSEST_RANGE | `post_closest_range`, on change | range truncated to whole metres | done |
//! | CONTACT_CLOSEST_EVAL | on change | 1 within `eval_range_far`, else 0 | done |
//! | ALERT_VERBOSE | `alert_verbose`: new contacts, alert transitions | `new_contact=..`, `contact=..,alert_id=..,<transition>, alerted=..` | done |
//! | VIEW_CIRCLE | `display_radii` (erased when turned off) | `x=..,y=..,radius=..,label=<id>_in`/`_out`, edge colour, vertex size 0, edge size 1 | done |
//! | `<var>` of a `BCM_REPORT_REQUEST` | its contacts within range change | names, comma-separated | done |
//! | CONTACT_MGR_WARNING | a bad `CONTACT_RESOLVED` | the C++ text | done |
//! | PBASICCONTACTMGR_PID | at start-up, as its own process | pid | done |

mod v20;

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fmt::Write as _;

use behaviors::cpa::CpaEngine;
use helm::ledger::NodeReport;
use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::ProcessConfig;
use moos_types::fmt::{compact_string, fixed};
use moos_types::text::{is_number, parse_string_q, set_boolean_on_string, tok_string_parse};

use behaviors::contact::ContactFilter;
use vehicle::geodesy::LocalGrid;

use crate::app::{Mail, Post, Subscription, Value};
use crate::appcasting::Note;
use crate::hosted::{AppCore, Hosted};

/// The program name.
pub const PROGRAM: &str = "pBasicContactMgr";

/// Which contact manager the core is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variant {
    /// `pBasicContactMgr` (MOOS-IvP's `dep_pBasicContactMgr`).
    Basic,
    /// `pContactMgrV20`.
    V20,
}

impl Variant {
    /// The MOOS program name.
    pub fn program(self) -> &'static str {
        match self {
            Variant::Basic => PROGRAM,
            Variant::V20 => v20::PROGRAM,
        }
    }
}

/// A `VAR = value` flag as MOOS `VarDataPair(.., "auto")` reads it: the value is a number
/// when it reads as one. The contact managers' alert, warning, retire and able flags and
/// pObstacleMgr's flags.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Flag {
    /// The variable.
    pub(crate) var: String,
    /// The value: a double or a string (which may hold macros).
    pub(crate) value: Value,
}

/// `VAR=value` (both sides trimmed, neither empty), as `addVarDataPairOnString` reads it.
pub(crate) fn flag(s: &str) -> Option<Flag> {
    let (l, r) = s.split_once('=')?;
    let (l, r) = (l.trim(), r.trim());
    if l.is_empty() || r.is_empty() {
        return None;
    }
    let value = if is_number(r) {
        Value::Double(geometry::atof(r))
    } else {
        Value::String(r.into())
    };
    Some(Flag {
        var: l.to_string(),
        value,
    })
}

/// The macros of pContactMgrV20's and pObstacleMgr's flags about (dis)abled contacts or
/// obstacles: `RECENT_DISABLED`, `RECENT_ENABLED` (the newest of each, when there is one),
/// `TOTAL_DISABLED`, `ALL_DISABLED` (comma-separated), each replaced in `s` by `expand(s,
/// name, value)` (the apps differ in the macro forms they read).
pub(crate) fn expand_able_macros(
    s: &str,
    disabled: &VecDeque<String>,
    enabled: &VecDeque<String>,
    expand: impl Fn(&str, &str, &str) -> String,
) -> String {
    let mut v = s.to_string();
    if let Some(c) = disabled.front() {
        v = expand(&v, "RECENT_DISABLED", c);
    }
    if let Some(c) = enabled.front() {
        v = expand(&v, "RECENT_ENABLED", c);
    }
    v = expand(&v, "TOTAL_DISABLED", &disabled.len().to_string());
    if v.contains("ALL_DISABLED") {
        let all: Vec<&str> = disabled.iter().map(String::as_str).collect();
        v = expand(&v, "ALL_DISABLED", &all.join(","));
    }
    v
}

impl Flag {
    /// Posts the flag as the apps' `postFlags` do: a string value trimmed and run through
    /// `expand`, posted unless that leaves it empty; a number posted as it is. Returns the
    /// appcast event `VAR=value` (a number compacted to 4 decimals).
    pub(crate) fn post(&self, expand: impl FnOnce(&str) -> String, out: &mut Vec<Post>) -> Note {
        let shown = match &self.value {
            Value::String(s) => {
                let v = expand(s.trim());
                if !v.is_empty() {
                    out.push(Post::text(self.var.as_str(), v.as_str()));
                }
                v
            }
            v => {
                let d = v.as_ref().as_f64().unwrap_or(0.0);
                out.push(Post::double(self.var.as_str(), d));
                compact_string(d, 4)
            }
        };
        Note::Event(format!("{}={shown}", self.var))
    }
}

/// One alert (MOOS `CMAlert`).
#[derive(Debug, Clone, Default)]
struct Alert {
    range: f64,
    range_far: f64,
    color: String,
    far_color: String,
    region: Option<geometry::Polygon>,
    on_flags: Vec<Flag>,
    off_flags: Vec<Flag>,
    match_type: Vec<String>,
    ignore_type: Vec<String>,
    match_group: Vec<String>,
    ignore_group: Vec<String>,
    /// V20: the alert's exclusion filters (MOOS `ExFilterSet`).
    filter: ContactFilter,
    /// V20: who asked for it (`BCM_ALERT_REQUEST`'s source), empty from the block.
    source: String,
    /// V20: the flags' texts already added (duplicates are dropped).
    on_raw: BTreeSet<String>,
    off_raw: BTreeSet<String>,
}

impl Alert {
    /// pBasicContactMgr's type and group lists: a contact's type (group), when it has one,
    /// must be matched when there are matches and not ignored.
    fn lists_pass(&self, vtype: &str, group: &str) -> bool {
        let pass = |v: &str, matches: &[String], ignores: &[String]| {
            let v = v.to_string();
            v.is_empty() || ((matches.is_empty() || matches.contains(&v)) && !ignores.contains(&v))
        };
        pass(vtype, &self.match_type, &self.ignore_type)
            && pass(group, &self.match_group, &self.ignore_group)
    }

    fn set_range(&mut self, d: f64) -> bool {
        if d < 0.0 {
            return false;
        }
        self.range = d;
        if self.range_far < self.range {
            self.range_far = self.range;
        }
        true
    }
    fn set_range_far(&mut self, d: f64) -> bool {
        if d < 0.0 {
            return false;
        }
        self.range_far = d;
        if self.range > self.range_far {
            self.range = self.range_far;
        }
        true
    }
}

/// Adds the entries of `s` (`:` read as `,`) to `list`; for all but match types the C++ then
/// splits on `:` (which is gone), so the whole text is one entry.
fn add_entries(list: &mut Vec<String>, s: &str, split: bool) {
    let s = s.replace(':', ",");
    let parts: Vec<&str> = if split {
        s.split(',').collect()
    } else {
        vec![s.as_str()]
    };
    for p in parts {
        let p = p.trim().to_string();
        if !list.contains(&p) {
            list.push(p);
        }
    }
}

/// One contact.
#[derive(Debug, Clone)]
struct Record {
    report: NodeReport,
    alerts_total: u32,
    alerts_active: i64,
    alerts_resolved: u32,
    range_actual: f64,
    range_extrap: f64,
    range_cpa: f64,
    range_roc: f64,
}

impl Record {
    fn time(&self) -> f64 {
        self.report.time.unwrap_or(0.0)
    }
}

/// A requested range report (`BCM_REPORT_REQUEST`).
#[derive(Debug, Clone, Default)]
struct RangeReport {
    range: f64,
    reqtime: f64,
    group: String,
    vtype: String,
    contacts: String,
    refresh: bool,
}

/// The settings of the block.
#[derive(Debug, Clone)]
struct Settings {
    default_range: f64,
    default_range_far: f64,
    default_color: String,
    default_far_color: String,
    reject_range: f64,
    ignore_groups: Vec<String>,
    display_radii: bool,
    post_closest_range: bool,
    contact_max_age: f64,
    recap_interval: f64,
    range_report_timeout: f64,
    local_coords: String,
    alert_verbose: bool,
    decay: (f64, f64),
    eval_range_far: f64,
    eval_range_near: f64,
    max_retired: usize,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            default_range: 1000.0,
            default_range_far: 1000.0,
            default_color: "gray65".into(),
            default_far_color: "gray35".into(),
            reject_range: 2000.0,
            ignore_groups: Vec::new(),
            display_radii: false,
            post_closest_range: false,
            contact_max_age: 600.0,
            recap_interval: 1.0,
            range_report_timeout: 10.0,
            local_coords: "verbatim".into(),
            alert_verbose: false,
            decay: (15.0, 30.0),
            eval_range_far: 20.0,
            eval_range_near: 10.0,
            max_retired: 5,
        }
    }
}

/// MOOS `LinearExtrapolator::getPosition` with a decay policy: the contact keeps its speed
/// until `beg` seconds, slows linearly to a stop at `end`, then stays.
fn extrapolate(r: &NodeReport, decay: (f64, f64), now: f64) -> Option<(f64, f64)> {
    let (x, y) = (r.x_m.unwrap_or(0.0), r.y_m.unwrap_or(0.0));
    let dt = now - r.time.unwrap_or(0.0);
    if dt < -0.1 {
        return None;
    }
    if dt == 0.0 {
        return Some((x, y));
    }
    let spd = r.speed_mps.unwrap_or(0.0);
    let (beg, end) = decay;
    let dist = if dt <= beg {
        spd * dt
    } else if dt <= end {
        let rate = spd / (end - beg);
        let t = dt - beg;
        let cur = spd - rate * t;
        spd * beg + (spd + cur) / 2.0 * t
    } else {
        spd * beg + spd / 2.0 * (end - beg)
    };
    let p = geometry::project_point(x, y, r.heading_deg.unwrap_or(0.0), dist);
    Some((p.x, p.y))
}

/// The pure contact manager.
///
/// ```
/// use runtime::contact_mgr::ContactMgr;
/// use runtime::app::Value;
/// let (mut cm, warnings) = ContactMgr::new("abe", &["alert = id=avd, var=CONTACT_INFO, val=name=$[VNAME] # contact=$[VNAME], alert_range=50"]);
/// assert!(warnings.is_empty());
/// let mut out = Vec::new();
/// cm.on_mail("NODE_REPORT", &Value::text("NAME=bob,X=30,Y=0,SPD=1,HDG=270,TIME=10"), 10.0, &mut out);
/// cm.iterate(10.0, &mut out);
/// assert!(out.iter().any(|p| p.key == "CONTACT_INFO" && p.value == Value::text("name=bob#contact=bob")));
/// ```
#[derive(Debug, Clone)]
pub struct ContactMgr {
    ownship: String,
    s: Settings,
    alerts: BTreeMap<String, Alert>,
    alert_ids: BTreeSet<String>,
    /// Alerted matrix: lower-case vehicle name -> alert id -> alerted.
    par: BTreeMap<String, BTreeMap<String, bool>>,
    records: BTreeMap<String, Record>,
    retired: VecDeque<String>,
    reports: BTreeMap<String, RangeReport>,
    nav: (f64, f64, f64, f64),
    recap_posted: f64,
    prev_list: String,
    prev_retired: String,
    prev_alerted: String,
    prev_unalerted: String,
    prev_recap: String,
    prev_closest: String,
    prev_count: u32,
    prev_closest_range: f64,
    prev_eval: f64,
    requests: u32,
    notes: Vec<Note>,
    variant: Variant,
    /// The mission's local grid (V20 derives x/y from lat/lon with it).
    grid: Option<LocalGrid>,
    /// pBasicContactMgr: `contact_local_coords` is not `verbatim` and the grid is known, so
    /// reports' x/y may come from their lat/lon.
    use_geodesy: bool,
    /// What only V20 keeps.
    x: v20::Extra,
    /// The process id, posted at start-up (single-app mode).
    pid: Option<u32>,
}

impl ContactMgr {
    /// A manager for vehicle `ownship` from the block's `param = value` lines (in file
    /// order), with the warnings the C++ app reports for them.
    pub fn new(ownship: &str, lines: &[&str]) -> (ContactMgr, Vec<String>) {
        ContactMgr::with_grid(ownship, None, lines)
    }

    /// As [`ContactMgr::new`], on the mission's local `grid` (`None` without
    /// `LatOrigin`/`LongOrigin`), which `contact_local_coords` uses.
    ///
    /// ```
    /// use runtime::contact_mgr::ContactMgr;
    /// use vehicle::geodesy::LocalGrid;
    /// let grid = LocalGrid::new(43.8, -69.0).ok();
    /// let (mut cm, w) = ContactMgr::with_grid("abe", grid, &["contact_local_coords = lazy_lat_lon"]);
    /// assert!(w.is_empty());
    /// let mut out = Vec::new();
    /// cm.on_mail("NODE_REPORT", &runtime::app::Value::text("NAME=bob,LAT=43.801,LON=-69,SPD=1,HDG=0,TIME=1"), 1.0, &mut out);
    /// cm.iterate(1.0, &mut out);
    /// let (range, _, _) = cm.ranges("bob").unwrap();
    /// assert!((range - 111.064).abs() < 1e-3);
    /// ```
    pub fn with_grid(
        ownship: &str,
        grid: Option<LocalGrid>,
        lines: &[&str],
    ) -> (ContactMgr, Vec<String>) {
        let mut cm = ContactMgr::blank(ownship, Variant::Basic, grid);
        let mut warnings = Vec::new();
        for line in lines {
            let (p, v) = split_line(line);
            if let Err(w) = cm.configure(&p.to_ascii_lowercase(), &v) {
                warnings.extend(w.split('\n').map(str::to_string));
            }
        }
        warnings.extend(cm.startup_basic());
        (cm, warnings)
    }

    /// pBasicContactMgr's start-up after its block: with `contact_local_coords` other than
    /// `verbatim` the grid is needed (warned without it, and reports are then taken
    /// verbatim).
    fn startup_basic(&mut self) -> Vec<String> {
        if self.s.local_coords == "verbatim" {
            return Vec::new();
        }
        if self.grid.is_none() {
            // coug knows the grid or not: the C++ names the missing origin of the two.
            return vec![
                "No LatOrigin in *.moos file".into(),
                "Wont derive x/y from lat/lon in node reports.".into(),
            ];
        }
        self.use_geodesy = true;
        self.notes.push(Note::Event(
            "Geodesy init ok: Will derive x/y from lat/lon in node reports.".into(),
        ));
        Vec::new()
    }

    /// pBasicContactMgr's `contact_local_coords`: x/y from the report's lat/lon on the grid,
    /// always with `force_lat_lon`, with `lazy_lat_lon` only when x or y is missing, never
    /// `verbatim` or without the grid or a lat/lon.
    fn local_coords(&self, r: &mut NodeReport) {
        let wanted = match self.s.local_coords.as_str() {
            "force_lat_lon" => true,
            "lazy_lat_lon" => r.x_m.is_none() || r.y_m.is_none(),
            _ => false,
        };
        if !(wanted && self.use_geodesy) {
            return;
        }
        if let (Some(grid), Some(lat), Some(lon)) = (&self.grid, r.lat_deg, r.lon_deg)
            && let Ok((x, y)) = grid.to_local(lat, lon)
        {
            r.x_m = Some(x);
            r.y_m = Some(y);
        }
    }

    /// Which manager this is.
    pub fn variant(&self) -> Variant {
        self.variant
    }

    fn blank(ownship: &str, variant: Variant, grid: Option<LocalGrid>) -> ContactMgr {
        let mut s = Settings::default();
        if variant == Variant::V20 {
            s.contact_max_age = 60.0;
        }
        ContactMgr {
            ownship: ownship.to_string(),
            s,
            alerts: BTreeMap::new(),
            alert_ids: BTreeSet::new(),
            par: BTreeMap::new(),
            records: BTreeMap::new(),
            retired: VecDeque::new(),
            reports: BTreeMap::new(),
            nav: (0.0, 0.0, 0.0, 0.0),
            recap_posted: 0.0,
            prev_list: String::new(),
            prev_retired: String::new(),
            prev_alerted: String::new(),
            prev_unalerted: String::new(),
            prev_recap: String::new(),
            prev_closest: String::new(),
            prev_count: 0,
            prev_closest_range: 0.0,
            prev_eval: 0.0,
            requests: 0,
            notes: Vec::new(),
            variant,
            grid,
            use_geodesy: false,
            x: v20::Extra::default(),
            pid: None,
        }
    }

    /// One configuration line; `Err(warning)` as the C++ reports it.
    fn configure(&mut self, param: &str, value: &str) -> Result<(), String> {
        if self.variant == Variant::V20 {
            return self.configure_v20(param, value);
        }
        let s = &mut self.s;
        let dval = geometry::atof(value);
        let lower = value.to_ascii_lowercase();
        match param {
            "alert" => self
                .config_alert(value, "")
                .map_err(|w| format!("{w}\nFailed alert config: {value}")),
            "ignore_group" => {
                let g = value.to_ascii_lowercase();
                if s.ignore_groups.contains(&g) {
                    return Err(format!("Unhandled ignore_group: {value}"));
                }
                s.ignore_groups.push(g);
                Ok(())
            }
            "decay" => {
                let (l, r) = value.split_once(',').unwrap_or((value, ""));
                if is_number(l.trim()) && is_number(r.trim()) {
                    let (a, b) = (geometry::atof(l), geometry::atof(r));
                    if a >= 0.0 && a <= b {
                        s.decay = (a, b);
                        return Ok(());
                    }
                }
                Err(format!("Unhandled decay config: decay={value}"))
            }
            "range_report_timeout" => {
                if is_number(value) && dval >= 0.0 {
                    s.range_report_timeout = dval;
                    Ok(())
                } else {
                    Err("range_report_timeout cannot be negative val".into())
                }
            }
            "display_radii" => {
                if let Some(b) = set_boolean_on_string(s.display_radii, value) {
                    s.display_radii = b;
                }
                Ok(())
            }
            "post_closest_range" => match set_boolean_on_string(s.post_closest_range, value) {
                Some(b) => {
                    s.post_closest_range = b;
                    Ok(())
                }
                None => Err("post_closest_range must be a Boolean".into()),
            },
            "max_retired_history" => {
                let n = if is_number(value) && dval >= 0.0 {
                    Some(dval as usize)
                } else {
                    None
                };
                match n {
                    Some(n) if (1..=50).contains(&n) => {
                        s.max_retired = n;
                        Ok(())
                    }
                    _ => {
                        if let Some(n) = n {
                            s.max_retired = n.clamp(1, 50);
                        }
                        Err("max_retired_hist should be in range [1,50]".into())
                    }
                }
            }
            "contact_local_coords" => {
                if matches!(
                    lower.as_str(),
                    "verbatim" | "lazy_lat_lon" | "force_lat_lon"
                ) {
                    s.local_coords = lower;
                    Ok(())
                } else {
                    Err("Illegal contact_local_coords configuration".into())
                }
            }
            "alert_range" | "default_alert_range" => {
                if is_number(value) && dval > 0.0 {
                    s.default_range = dval;
                    Ok(())
                } else {
                    Err(format!("alert_range must be > zero: {value}"))
                }
            }
            "alert_cpa_range" | "default_cpa_range" => {
                if is_number(value) && dval > 0.0 {
                    s.default_range_far = dval;
                    Ok(())
                } else {
                    Err(format!("default_alert_range_cpa must be >0: {value}"))
                }
            }
            "contacts_recap_interval" | "reject_range" => {
                let slot = if param == "reject_range" {
                    &mut s.reject_range
                } else {
                    &mut s.recap_interval
                };
                if lower == "off" {
                    *slot = -1.0;
                    Ok(())
                } else if dval >= 0.0 {
                    *slot = dval;
                    Ok(())
                } else {
                    Err(format!("{param} must be >=0: {value}"))
                }
            }
            "alert_cpa_time" => Err("alert_cpa_time parameter has been deprecated.".into()),
            "alert_verbose" => match set_boolean_on_string(s.alert_verbose, value) {
                Some(b) => {
                    s.alert_verbose = b;
                    Ok(())
                }
                None => Err("alert_verbose must be either true or false".into()),
            },
            "default_alert_range_color" | "default_cpa_range_color" => {
                if geometry::color::is_color(value) {
                    if param == "default_alert_range_color" {
                        s.default_color = value.to_string();
                    } else {
                        s.default_far_color = value.to_string();
                    }
                    Ok(())
                } else {
                    let which = if param == "default_alert_range_color" {
                        "default_alert_range_color"
                    } else {
                        "default_alert_range_cpa_color"
                    };
                    Err(format!("{which}, {value}, not a color"))
                }
            }
            "contact_max_age" => {
                if dval > 0.0 {
                    s.contact_max_age = dval;
                    Ok(())
                } else {
                    Err(format!("contact_max_age must be > zero: {value}"))
                }
            }
            "eval_range_far" => {
                if dval >= 0.0 {
                    s.eval_range_far = dval;
                    if s.eval_range_near > s.eval_range_far {
                        s.eval_range_near = s.eval_range_far;
                    }
                    Ok(())
                } else {
                    Err(format!("eval_range_far must be >= zero: {value}"))
                }
            }
            "eval_range_near" => {
                if dval >= 0.0 {
                    s.eval_range_near = dval;
                    if s.eval_range_far < s.eval_range_near {
                        s.eval_range_far = s.eval_range_near;
                    }
                    Ok(())
                } else {
                    Err(format!("eval_range_near must be >= zero: {value}"))
                }
            }
            _ if appcast::casting::UNHANDLED_EXEMPT
                .contains(&param.to_ascii_uppercase().as_str())
                || matches!(param, "comms_policy" | "max_appcast_run_warnings") =>
            {
                Ok(())
            }
            _ => Err(format!("Unhandled config line: {param}={value}")),
        }
    }

    /// A new alert with the configured defaults.
    fn new_alert(s: &Settings, variant: Variant) -> Alert {
        let mut a = Alert::default();
        if variant == Variant::V20 {
            // V20: no default ranges; an alert without one is not valid.
            a.range = -1.0;
            a.range_far = -1.0;
            return a;
        }
        a.set_range(s.default_range);
        a.set_range_far(s.default_range_far);
        a.color = s.default_color.clone();
        a.far_color = s.default_far_color.clone();
        a
    }

    /// An alert specification from the block (`source` empty) or a `BCM_ALERT_REQUEST`
    /// (MOOS `handleConfigAlert`): `Err` with the first component refused. The variants read
    /// the same keys but for these: pBasicContactMgr's flags are one `VAR=value` each and it
    /// reads regions, colours and type/group lists; V20 drops a repeated flag, reads `#`-joined
    /// off flags and its filter keys, and `action=disable`/`enable` (dis)ables an id.
    fn config_alert(&mut self, spec: &str, source: &str) -> Result<(), String> {
        let v20 = self.variant == Variant::V20;
        let mut id = tok_string_parse(spec, "id").to_string();
        if id.is_empty() {
            id = "no_id".into();
        }
        if v20 {
            let lower = spec.to_ascii_lowercase();
            for (action, disable) in [("action=disable", true), ("action=enable", false)] {
                if lower.contains(action) {
                    if id != "no_id" {
                        if disable {
                            self.x.alerts_disabled.insert(id);
                        } else {
                            self.x.alerts_disabled.remove(&id);
                        }
                    }
                    return Ok(());
                }
            }
        }
        self.add_alert_id(&id);
        let (s, variant) = (&self.s, self.variant);
        let alert = self
            .alerts
            .entry(id)
            .or_insert_with(|| Self::new_alert(s, variant));
        if !source.is_empty() {
            alert.source = source.to_string();
        }
        let (mut var, mut pattern) = (String::new(), String::new());
        for part in parse_string_q(spec, ',') {
            let (l, r) = part.split_once('=').unwrap_or((part, ""));
            let left = l.trim().to_ascii_lowercase();
            let mut right = r.trim();
            let dval = geometry::atof(right);
            if right.len() >= 2 && right.starts_with('"') && right.ends_with('"') {
                right = &right[1..right.len() - 1];
            }
            let ok = match left.as_str() {
                "var" => {
                    var = right.to_string();
                    true
                }
                "val" | "pattern" => {
                    pattern = right.to_string();
                    true
                }
                "on_flag" | "onflag" if v20 => alert.add_on_flag(right),
                "off_flag" | "offflag" if v20 => alert.add_off_flags(right),
                "on_flag" | "onflag" => flag(right).map(|f| alert.on_flags.push(f)).is_some(),
                "off_flag" | "offflag" => flag(right).map(|f| alert.off_flags.push(f)).is_some(),
                "alert_range" if is_number(right) => alert.set_range(dval),
                "cpa_range" if is_number(right) => alert.set_range_far(dval),
                "match_name" | "ignore_name" | "match_group" | "ignore_group" | "match_type"
                | "ignore_type" | "match_region" | "ignore_region" | "strict_ignore"
                    if v20 =>
                {
                    alert.filter.set_param(&left, right) == Some(true)
                }
                _ if v20 => false,
                "region" => match right.parse::<geometry::Polygon>() {
                    Ok(p) if p.is_convex() => {
                        alert.region = Some(p);
                        true
                    }
                    _ => false,
                },
                "alert_range_color" if geometry::color::is_color(right) => {
                    alert.color = right.to_string();
                    true
                }
                "cpa_range_color" if geometry::color::is_color(right) => {
                    alert.far_color = right.to_string();
                    true
                }
                "match_type" => {
                    add_entries(&mut alert.match_type, right, true);
                    true
                }
                "ignore_type" => {
                    add_entries(&mut alert.ignore_type, right, false);
                    true
                }
                "match_group" => {
                    add_entries(&mut alert.match_group, right, false);
                    true
                }
                "ignore_group" => {
                    add_entries(&mut alert.ignore_group, right, false);
                    true
                }
                _ => false,
            };
            if !ok && left != "id" {
                return Err(format!("unhandled alert config component: {left}"));
            }
        }
        if !var.is_empty() && !pattern.is_empty() {
            if v20 {
                alert.add_on_flag(&format!("{var}={pattern}"));
            } else {
                alert.on_flags.push(Flag {
                    var: var.trim().to_string(),
                    value: if is_number(pattern.trim()) {
                        Value::Double(geometry::atof(&pattern))
                    } else {
                        Value::String(pattern.trim().into())
                    },
                });
            }
        }
        Ok(())
    }

    fn add_alert_id(&mut self, id: &str) {
        if self.alert_ids.insert(id.to_string()) {
            for row in self.par.values_mut() {
                row.insert(id.to_string(), false);
            }
        }
    }

    fn alerted(&self, vname: &str, id: &str) -> bool {
        self.par
            .get(&vname.to_ascii_lowercase())
            .and_then(|r| r.get(id))
            .copied()
            .unwrap_or(false)
    }

    fn set_alerted(&mut self, vname: &str, id: &str, b: bool) {
        let v = vname.to_ascii_lowercase();
        if !(id == "all_alerts" || self.alert_ids.contains(&id.to_ascii_lowercase())) {
            return;
        }
        let Some(row) = self.par.get_mut(&v) else {
            return;
        };
        if id == "all_alerts" {
            row.values_mut().for_each(|x| *x = b);
        } else {
            row.insert(id.to_string(), b);
        }
    }

    fn group_text(&self, alerted: bool) -> (String, u32) {
        let mut s = String::new();
        let mut n = 0;
        for (v, row) in &self.par {
            for (id, b) in row {
                if *b == alerted {
                    s.push('(');
                    s.push_str(v);
                    s.push(',');
                    s.push_str(id);
                    s.push(')');
                    n += 1;
                }
            }
        }
        (s, n)
    }

    /// The variables pBasicContactMgr registers for.
    pub const SUBSCRIPTIONS: [&'static str; 9] = [
        "NODE_REPORT",
        "CONTACT_RESOLVED",
        "BCM_DISPLAY_RADII",
        "BCM_ALERT_REQUEST",
        "BCM_REPORT_REQUEST",
        "NAV_X",
        "NAV_Y",
        "NAV_SPEED",
        "NAV_HEADING",
    ];

    /// The variables the app registers for (besides the appcast layer's).
    pub fn subscriptions(&self) -> Vec<String> {
        match self.variant {
            Variant::Basic => Self::SUBSCRIPTIONS.iter().map(|v| v.to_string()).collect(),
            Variant::V20 => self.subscriptions_v20(),
        }
    }

    /// One mail (MOOS `OnNewMail`); posts what a mail makes the C++ post at once.
    pub fn on_mail(&mut self, key: &str, value: &Value, now: f64, out: &mut Vec<Post>) {
        self.on_mail_from(key, value, "", now, out);
    }

    /// One mail from `source` (`source:aux` when the mail has an aux, as V20's events name
    /// it).
    pub fn on_mail_from(
        &mut self,
        key: &str,
        value: &Value,
        source: &str,
        now: f64,
        out: &mut Vec<Post>,
    ) {
        let dval = value.as_ref().as_f64().unwrap_or(0.0);
        match key {
            "NAV_X" => self.nav.0 = dval,
            "NAV_Y" => self.nav.1 = dval,
            "NAV_HEADING" => self.nav.2 = dval,
            "NAV_SPEED" => self.nav.3 = dval,
            _ if self.variant == Variant::V20 => self.on_mail_v20(key, value, source, now, out),
            _ => self.on_mail_basic(key, value.as_str().unwrap_or(""), source, now, out),
        }
    }

    /// pBasicContactMgr's mail but ownship's navigation: `sval`, the mail's text.
    fn on_mail_basic(&mut self, key: &str, sval: &str, src: &str, now: f64, out: &mut Vec<Post>) {
        match key {
            "NODE_REPORT" => self.node_report(sval, out),
            "BCM_REPORT_REQUEST" => self.report_request(sval, src, now),
            "BCM_DISPLAY_RADII" => match set_boolean_on_string(self.s.display_radii, sval) {
                Some(b) => {
                    self.s.display_radii = b;
                    self.notes
                        .push(Note::Event(format!("DISPLAY_RADII set to {b}")));
                    if !b {
                        self.post_radii(false, out);
                    }
                }
                None => {
                    let msg = format!("Failed attempt so set DISPLAY_RADII to: {sval}");
                    self.notes.push(Note::Event(msg.clone()));
                    self.notes.push(Note::Warning(msg));
                    if !self.s.display_radii {
                        self.post_radii(false, out);
                    }
                }
            },
            "BCM_ALERT_REQUEST" => {
                self.requests += 1;
                if let Err(w) = self.config_alert(sval, "") {
                    self.notes.push(Note::Warning(w));
                    self.notes
                        .push(Note::Warning(format!("Unhandled Alert Request: {sval}")));
                }
            }
            "CONTACT_RESOLVED" => self.resolved(sval, out),
            _ => self
                .notes
                .push(Note::Warning(format!("Unhandled Mail: {key}"))),
        }
    }

    fn node_report(&mut self, text: &str, out: &mut Vec<Post>) {
        let mut r = NodeReport::parse(text);
        if self.s.ignore_groups.contains(&r.group.to_ascii_lowercase()) {
            return;
        }
        self.local_coords(&mut r);
        let vname = r.name.clone();
        if vname == self.ownship {
            return;
        }
        let newly = !self.records.contains_key(&vname);
        if newly && self.s.reject_range > 0.0 {
            let range =
                (self.nav.0 - r.x_m.unwrap_or(0.0)).hypot(self.nav.1 - r.y_m.unwrap_or(0.0));
            if range > self.s.reject_range {
                return;
            }
        }
        self.upsert(vname, r, out);
    }

    /// Keeps the report `r` of contact `vname`: a new record (its alert row, the
    /// `ALERT_VERBOSE` note) for a contact not seen before; a contact back from retirement is
    /// no longer retired.
    fn upsert(&mut self, vname: String, r: NodeReport, out: &mut Vec<Post>) {
        match self.records.get_mut(&vname) {
            Some(rec) => rec.report = r,
            None => {
                self.records.insert(
                    vname.clone(),
                    Record {
                        report: r,
                        alerts_total: 0,
                        alerts_active: 0,
                        alerts_resolved: 0,
                        range_actual: 0.0,
                        range_extrap: 0.0,
                        range_cpa: 0.0,
                        range_roc: 0.0,
                    },
                );
                let row = self
                    .alert_ids
                    .iter()
                    .map(|id| (id.clone(), false))
                    .collect();
                self.par.entry(vname.to_ascii_lowercase()).or_insert(row);
                if self.s.alert_verbose {
                    out.push(Post::text("ALERT_VERBOSE", format!("new_contact={vname}")));
                }
            }
        }
        self.retired.retain(|v| *v != vname);
    }

    fn resolved(&mut self, text: &str, out: &mut Vec<Post>) {
        let lower = text.to_ascii_lowercase();
        let (vehicle, id) = lower.split_once(',').unwrap_or((&lower, ""));
        let (vehicle, mut id) = (vehicle.trim().to_string(), id.trim().to_string());
        if id.is_empty() {
            id = "all_alerts".into();
        }
        self.notes
            .push(Note::Event(format!("TryResolve: ({vehicle},{id})")));
        let warn = if !self.par.contains_key(&vehicle) {
            Some(format!(
                "Resolution failed. Nothing known about vehicle: {vehicle}"
            ))
        } else if id != "all_alerts" && !self.alert_ids.contains(&id) {
            Some(format!(
                "Resolution failed. Nothing known about alertid: {id}"
            ))
        } else {
            None
        };
        if let Some(w) = warn {
            out.push(Post::text("CONTACT_MGR_WARNING", w.clone()));
            self.notes.push(Note::Warning(w));
            return;
        }
        // The C++ counts by the name as given (lower case here).
        if let Some(rec) = self.records.get_mut(&vehicle) {
            rec.alerts_active -= 1;
            rec.alerts_resolved += 1;
        }
        self.set_alerted(&vehicle, &id, false);
        self.notes
            .push(Note::Event(format!("Resolved: ({vehicle},{id})")));
    }

    /// `BCM_REPORT_REQUEST` from `source`: `var`, `range`, `group`, `type`; V20 also reads
    /// `refresh` (post the list at the next iteration even if unchanged) and `reason`.
    fn report_request(&mut self, text: &str, source: &str, now: f64) {
        let v20 = self.variant == Variant::V20;
        let mut ok = true;
        let (mut var, mut range, mut group, mut vtype, mut refresh) =
            (String::new(), -1.0, String::new(), String::new(), false);
        for part in moos_types::text::parse_string(text, ',') {
            let (l, r) = part.split_once('=').unwrap_or((part, ""));
            let (l, r) = (l.trim().to_ascii_lowercase(), r.trim());
            match l.as_str() {
                "var" if !r.is_empty() && !r.contains(char::is_whitespace) => var = r.to_string(),
                "range" if is_number(r) => range = geometry::atof(r),
                "group" => group = r.to_string(),
                "type" => vtype = r.to_string(),
                "refresh" if v20 => refresh = r.eq_ignore_ascii_case("true"),
                "reason" if v20 => {}
                _ => ok = false,
            }
        }
        if !ok || var.is_empty() || range < 0.0 {
            let msg = format!("Failed REPORT_REQUEST: {text}");
            self.notes.push(Note::Event(msg.clone()));
            self.notes.push(Note::Warning(msg));
            return;
        }
        self.notes.push(Note::Event(if v20 {
            format!("New BCM_REPORT_REQUEST (src={source}): {text}")
        } else {
            format!("New REPORT_REQUEST: {text}")
        }));
        let e = self.reports.entry(var).or_insert_with(|| RangeReport {
            range: -2.0,
            ..RangeReport::default()
        });
        if e.range != range {
            e.range = range;
            e.group = group;
            e.vtype = vtype;
            e.contacts.clear();
        }
        e.refresh = refresh;
        e.reqtime = now;
    }

    /// One iteration (MOOS `Iterate`).
    pub fn iterate(&mut self, now: f64, out: &mut Vec<Post>) {
        if self.variant == Variant::V20 {
            self.iterate_v20(now, out);
            return;
        }
        self.update_ranges(now);
        self.retire(now, out);
        self.post_range_reports(now, out);
        self.post_summaries(now, out);
        self.check_alerts(now, out);
        self.check_close_in(now, out);
        if self.s.display_radii {
            self.post_radii(true, out);
        }
    }

    fn update_ranges(&mut self, now: f64) {
        let (ox, oy, oh, ov) = self.nav;
        for rec in self.records.values_mut() {
            let r = &rec.report;
            let (cx, cy) = (r.x_m.unwrap_or(0.0), r.y_m.unwrap_or(0.0));
            rec.range_actual = (ox - cx).hypot(oy - cy);
            let (ex, ey) = extrapolate(r, self.s.decay, now).unwrap_or((cx, cy));
            rec.range_extrap = (ox - ex).hypot(oy - ey);
            let engine = CpaEngine::new(
                ex,
                ey,
                r.heading_deg.unwrap_or(0.0),
                r.speed_mps.unwrap_or(0.0),
                ox,
                oy,
            );
            rec.range_cpa = engine.eval_cpa(oh, ov, 36000.0);
            rec.range_roc = engine.eval_roc(oh, ov);
        }
    }

    /// Retires the contacts older than `contact_max_age` or beyond the reject range (10 m past
    /// it for pBasicContactMgr, 5 % for V20), and for V20 also the ones its filters refused
    /// and those culled past `max_contacts`, with V20's retire flags. Each goes to the front
    /// of the retired list, in name order.
    fn retire(&mut self, now: f64, out: &mut Vec<Post>) {
        let start = self.records.len();
        let reject = match self.variant {
            Variant::Basic => self.s.reject_range + 10.0,
            Variant::V20 => self.s.reject_range * 1.05,
        };
        let mut gone: BTreeSet<String> = std::mem::take(&mut self.x.filtered);
        for (name, rec) in &self.records {
            let age = now - rec.time();
            if age > self.s.contact_max_age
                || (self.s.reject_range > 0.0 && rec.range_actual > reject)
            {
                gone.insert(name.clone());
            }
        }
        if self.variant == Variant::V20 {
            self.cull(&mut gone, start, now);
        }
        for name in gone {
            if self.records.remove(&name).is_some() {
                self.retired.push_front(name.clone());
            }
            self.par.remove(&name.to_ascii_lowercase());
            for f in &self.x.retire_flags {
                let expand_all = |v: &str| {
                    let v = v20::expand(v, "CONTACT", &name);
                    v20::expand(&v, "UTC", &compact_string(now, 3))
                };
                self.notes.push(f.post(expand_all, out));
            }
            self.x.will_warn.remove(&name);
            self.x.was_warned.remove(&name);
            self.x.utc_warned.remove(&name);
        }
    }

    /// Posts each requested range report's contacts (by extrapolated range, group and type)
    /// when they changed or a refresh was asked for. pBasicContactMgr forgets requests not
    /// renewed within `range_report_timeout`; V20 forgets the oldest timed-out one when it
    /// has more than `range_report_maxsize`.
    fn post_range_reports(&mut self, now: f64, out: &mut Vec<Post>) {
        let timeout = self.s.range_report_timeout;
        match self.variant {
            Variant::Basic => self.reports.retain(|_, r| now - r.reqtime <= timeout),
            Variant::V20 => self.prune_range_reports(now),
        }
        for (var, rep) in &mut self.reports {
            let mut contacts = String::new();
            for (name, rec) in &self.records {
                let group_ok =
                    rep.group.is_empty() || rep.group.eq_ignore_ascii_case(&rec.report.group);
                let type_ok =
                    rep.vtype.is_empty() || rep.vtype.eq_ignore_ascii_case(&rec.report.vtype);
                if group_ok && type_ok && rec.range_extrap < rep.range {
                    if !contacts.is_empty() {
                        contacts.push(',');
                    }
                    contacts.push_str(name);
                }
            }
            if rep.refresh || contacts != rep.contacts {
                out.push(Post::text(var.as_str(), contacts.clone()));
                rep.contacts = contacts;
                rep.refresh = false;
            }
        }
    }

    /// MOOS `postSummaries`: `CONTACTS_RETIRED`, the closest contact (its range and, V20, its
    /// relative bearing when asked), the lists, `CONTACTS_UNALERTED` (pBasicContactMgr),
    /// `CONTACTS_RECAP` and `CONTACT_RANGES` (V20's `post_all_ranges`).
    fn post_summaries(&mut self, now: f64, out: &mut Vec<Post>) {
        let retired = self
            .retired
            .iter()
            .map(String::as_str)
            .collect::<Vec<_>>()
            .join(",");
        if retired != self.prev_retired {
            out.push(Post::text("CONTACTS_RETIRED", retired.clone()));
            self.prev_retired = retired;
        }
        self.retired.truncate(self.s.max_retired);

        let mut list = String::new();
        let mut recap = String::new();
        let mut ranges = Vec::new();
        let mut closest: Option<(&str, f64, &Record)> = None;
        for (name, rec) in &self.records {
            if !list.is_empty() {
                list.push(',');
            }
            list.push_str(name);
            let age = now - rec.time();
            let range = rec.range_actual;
            ranges.push(range);
            if closest.is_none_or(|(_, r, _)| range < r) {
                closest = Some((name, range, rec));
            }
            if !recap.is_empty() {
                recap.push_str(" # ");
            }
            recap.push_str("vname=");
            recap.push_str(name);
            recap.push_str(",range=");
            fixed(&mut recap, range, 2);
            recap.push_str(",age=");
            fixed(&mut recap, age, 2);
        }
        if let Some((name, range, rec)) = closest {
            if self.s.post_closest_range {
                let r = range.trunc();
                if r != self.prev_closest_range {
                    out.push(Post::double("CONTACT_CLOSEST_RANGE", r));
                    self.prev_closest_range = r;
                }
            }
            if self.x.post_closest_relbng {
                let (ox, oy, oh, _) = self.nav;
                let (cx, cy) = (rec.report.x_m.unwrap_or(0.0), rec.report.y_m.unwrap_or(0.0));
                let b = behaviors::cpa::rel_bearing(ox, oy, oh, cx, cy).trunc();
                if b != self.x.prev_closest_relbng {
                    out.push(Post::double("CONTACT_CLOSEST_RELBNG", b));
                    self.x.prev_closest_relbng = b;
                }
            }
            if name != self.prev_closest {
                out.push(Post::text("CONTACT_CLOSEST", name.to_string()));
                out.push(Post::double("CONTACT_CLOSEST_TIME", now));
                self.prev_closest = name.to_string();
            }
        }
        self.post_lists(list, out);
        if self.variant == Variant::Basic {
            let (unalerted, _) = self.group_text(false);
            if unalerted != self.prev_unalerted {
                out.push(Post::text("CONTACTS_UNALERTED", unalerted.clone()));
                self.prev_unalerted = unalerted;
            }
        }
        self.post_recap(now, recap, out);
        if self.x.post_all_ranges {
            ranges.sort_by(f64::total_cmp);
            let text: Vec<String> = ranges.iter().map(|r| compact_string(*r, 1)).collect();
            out.push(Post::text("CONTACT_RANGES", text.join(",")));
        }
    }

    /// `CONTACTS_COUNT`, `CONTACTS_LIST` (`list`) and `CONTACTS_ALERTED`, each when it changed
    /// (both managers' `postSummaries`).
    fn post_lists(&mut self, list: String, out: &mut Vec<Post>) {
        let (alerted, count) = self.group_text(true);
        if count != self.prev_count {
            out.push(Post::double("CONTACTS_COUNT", f64::from(count)));
            self.prev_count = count;
        }
        if list != self.prev_list {
            out.push(Post::text("CONTACTS_LIST", list.clone()));
            self.prev_list = list;
        }
        if alerted != self.prev_alerted {
            out.push(Post::text("CONTACTS_ALERTED", alerted.clone()));
            self.prev_alerted = alerted;
        }
    }

    /// `CONTACTS_RECAP` (`recap`) every `recap_interval` seconds, when one is set.
    fn post_recap(&mut self, now: f64, recap: String, out: &mut Vec<Post>) {
        if self.s.recap_interval > 0.0 && now - self.recap_posted > self.s.recap_interval {
            self.recap_posted = now;
            out.push(Post::text("CONTACTS_RECAP", recap.clone()));
            self.prev_recap = recap;
        }
    }

    /// Whether alert `id` applies to contact `name` (MOOS `checkAlertApplies`): the report is
    /// not older than `contact_max_age`, the contact passes the alert's type and group lists
    /// (V20: the alert is valid and its filters pass), is within its ranges and inside its
    /// region.
    fn applies(&self, name: &str, id: &str, now: f64) -> bool {
        let (Some(a), Some(rec)) = (self.alerts.get(id), self.records.get(name)) else {
            return false;
        };
        if now - rec.time() > self.s.contact_max_age {
            return false;
        }
        let r = &rec.report;
        let (x, y) = (r.x_m.unwrap_or(0.0), r.y_m.unwrap_or(0.0));
        let passes = match self.variant {
            Variant::Basic => a.lists_pass(&r.vtype, &r.group),
            Variant::V20 => a.valid_v20() && a.filter.check_all(&r.name, &r.group, &r.vtype, x, y),
        };
        if !passes {
            return false;
        }
        if a.range > 0.0 {
            if rec.range_actual > a.range_far {
                return false;
            }
            if rec.range_actual > a.range && rec.range_cpa > a.range {
                return false;
            }
        }
        a.region.as_ref().is_none_or(|region| region.contains(x, y))
    }

    /// Every contact against every enabled alert: the flags of each transition, the alerted
    /// matrix and its counts, and `ALERT_VERBOSE` when asked.
    fn check_alerts(&mut self, now: f64, out: &mut Vec<Post>) {
        let names: Vec<String> = self.records.keys().cloned().collect();
        let ids: Vec<String> = self.alerts.keys().cloned().collect();
        for name in &names {
            for id in &ids {
                if self.x.alerts_disabled.contains(id) {
                    continue;
                }
                let applies = self.applies(name, id, now);
                let was = self.alerted(name, id);
                if applies == was {
                    continue;
                }
                self.post_alert(name, id, applies, out);
                self.mark_alerted(name, id, applies);
                if self.s.alert_verbose {
                    let line = self.verbose_line(name, id, applies, now);
                    out.push(Post::text("ALERT_VERBOSE", line));
                }
            }
        }
    }

    /// Sets contact `name` (un)alerted for alert `id` with the variant's counts.
    fn mark_alerted(&mut self, name: &str, id: &str, on: bool) {
        match self.variant {
            Variant::Basic => {
                self.set_alerted(name, id, on);
                if on && let Some(rec) = self.records.get_mut(name) {
                    rec.alerts_total += 1;
                    rec.alerts_active += 1;
                }
            }
            Variant::V20 => self.set_alerted_v20(name, id, on),
        }
    }

    /// `ALERT_VERBOSE` for a transition of contact `name` for alert `id` (`on`: it became
    /// alerted): V20 adds the ranges and the time since the early warning.
    fn verbose_line(&self, name: &str, id: &str, on: bool, now: f64) -> String {
        let transition = if on { "off-->alerted" } else { "alerted-->off" };
        let alerted = self.alerted(name, id);
        let mut m = format!("contact={name},alert_id={id},{transition}");
        if self.variant == Variant::Basic {
            let _ = write!(m, ", alerted={alerted}");
            return m;
        }
        let (a, rec) = (&self.alerts[id], &self.records[name]);
        let _ = write!(
            m,
            ",alert_range={},alert_range_cpa={},range_actual=",
            compact_string(a.range, 1),
            compact_string(a.range_far, 1)
        );
        fixed(&mut m, rec.range_actual, 1);
        if alerted {
            m.push_str(",range_cpa=");
            fixed(&mut m, rec.range_cpa, 1);
        }
        if on
            && self.x.early_warning_time > 0.0
            && let Some(t) = self.x.utc_warned.get(name)
        {
            let _ = write!(m, ",after_warning={}", compact_string(now - t, 2));
        }
        m
    }

    /// The macros of alert flags about report `r` (`for_var`: in the variable's name, else in
    /// the value), in the order they are expanded. Both variants expand the position, motion
    /// and name macros (`$[SPD}` as the C++ spells it); pBasicContactMgr adds `$[UTIME]` and
    /// the lower-case names everywhere; V20 adds `$[UTC]` to names and `$[GROUP]` to values,
    /// and its `%[VNAME]` is the name as reported.
    fn alert_macros(&self, r: &NodeReport, for_var: bool) -> Vec<(&'static str, String)> {
        let num = |v: Option<f64>, p| compact_string(v.unwrap_or(0.0), p);
        let time = num(r.time, 2);
        let mut m = vec![
            ("$[X]", num(r.x_m, 2)),
            ("$[Y]", num(r.y_m, 2)),
            ("$[LAT]", num(r.lat_deg, 8)),
            ("$[LON]", num(r.lon_deg, 8)),
            ("$[SPD}", num(r.speed_mps, 2)),
            ("$[HDG]", num(r.heading_deg, 2)),
            ("$[DEP]", num(r.depth_m, 2)),
            ("$[VNAME]", r.name.clone()),
            ("$[VTYPE]", r.vtype.clone()),
        ];
        let vtype = r.vtype.to_ascii_lowercase();
        match (self.variant, for_var) {
            (Variant::Basic, _) => m.extend([
                ("$[UTIME]", time),
                ("%[VNAME]", r.name.to_ascii_lowercase()),
                ("%[VTYPE]", vtype),
            ]),
            (Variant::V20, true) => m.extend([
                ("$[UTIME]", time.clone()),
                ("$[UTC]", time),
                ("%[VNAME]", r.name.clone()),
                ("%[VTYPE]", vtype),
            ]),
            (Variant::V20, false) => m.extend([
                ("$[GROUP]", r.group.clone()),
                ("$[UTIME]", time),
                ("%[VNAME]", r.name.clone()),
                ("%[VTYPE]", vtype),
                ("%[GROUP]", r.group.to_ascii_lowercase()),
            ]),
        }
        m
    }

    /// MOOS `postAlert`: each on (off) flag of alert `id` about contact `name`, its macros
    /// expanded.
    fn post_alert(&mut self, name: &str, id: &str, on: bool, out: &mut Vec<Post>) {
        let (Some(a), Some(rec)) = (self.alerts.get(id), self.records.get(name)) else {
            return;
        };
        let r = &rec.report;
        let (var_macros, msg_macros) = (self.alert_macros(r, true), self.alert_macros(r, false));
        let apply = |s: &str, macros: &[(&str, String)]| {
            let mut s = s.to_string();
            for (k, v) in macros {
                if s.contains(k) {
                    s = s.replace(k, v);
                }
            }
            s
        };
        let flags = if on { &a.on_flags } else { &a.off_flags };
        for f in flags {
            let var = apply(&f.var, &var_macros);
            match &f.value {
                Value::String(s) => {
                    let msg = apply(s, &msg_macros);
                    self.notes.push(Note::Event(format!("{var}={msg}")));
                    out.push(Post::text(var, msg));
                }
                v => {
                    let d = v.as_ref().as_f64().unwrap_or(0.0);
                    self.notes
                        .push(Note::Event(format!("{var}={}", compact_string(d, 3))));
                    out.push(Post::double(var, d));
                }
            }
        }
    }

    fn check_close_in(&mut self, now: f64, out: &mut Vec<Post>) {
        let mut val: f64 = 0.0;
        for rec in self.records.values() {
            if now - rec.time() > self.s.contact_max_age {
                continue;
            }
            let this = if rec.range_actual < self.s.eval_range_far {
                1.0
            } else if rec.range_actual < self.s.eval_range_near {
                2.0
            } else {
                0.0
            };
            val = val.max(this);
        }
        if val != self.prev_eval {
            out.push(Post::double("CONTACT_CLOSEST_EVAL", val));
            self.prev_eval = val;
        }
    }

    fn post_radii(&self, active: bool, out: &mut Vec<Post>) {
        let mut active = active;
        for (id, a) in &self.alerts {
            let invisible = |c: &str| matches!(c, "invisible" | "empty" | "");
            if !active || invisible(&a.color) {
                active = false;
            }
            out.push(Post::text(
                "VIEW_CIRCLE",
                self.circle(a.range, &format!("{id}_in"), &a.color, active, None, None),
            ));
            if a.range_far > a.range {
                if !active || invisible(&a.far_color) {
                    active = false;
                }
                out.push(Post::text(
                    "VIEW_CIRCLE",
                    self.circle(
                        a.range_far,
                        &format!("{id}_out"),
                        &a.far_color,
                        active,
                        None,
                        None,
                    ),
                ));
            }
        }
    }

    /// A `VIEW_CIRCLE` around ownship (MOOS `XYCircle::get_spec`): `x=..,y=..,radius=..` (2
    /// decimals, compacted) then the object fields; V20's circles have a label colour, a
    /// duration of 3 s and the time `timed`.
    fn circle(
        &self,
        radius: f64,
        label: &str,
        color: &str,
        active: bool,
        label_color: Option<&str>,
        timed: Option<f64>,
    ) -> String {
        let mut s = String::from("x=");
        moos_types::fmt::compact(&mut s, self.nav.0, 2);
        s.push_str(",y=");
        moos_types::fmt::compact(&mut s, self.nav.1, 2);
        s.push_str(",radius=");
        moos_types::fmt::compact(&mut s, radius, 2);
        let mut a = geometry::Attributes::labeled(label);
        a.label_color = label_color.map(str::to_string);
        a.edge_color = Some(color.to_string());
        a.vertex_size = Some(0.0);
        a.edge_size = Some(1.0);
        a.active = active;
        if let Some(t) = timed {
            a.duration = Some(3.0);
            a.time = Some(t);
        }
        a.write_spec(&mut s, 0);
        s
    }

    /// Takes the appcast events and warnings gathered since the last call.
    pub fn take_notes(&mut self) -> Vec<Note> {
        std::mem::take(&mut self.notes)
    }

    /// The contacts' names, in name order.
    pub fn contacts(&self) -> impl Iterator<Item = &str> + '_ {
        self.records.keys().map(String::as_str)
    }

    /// The actual, extrapolated and CPA ranges to contact `name`.
    pub fn ranges(&self, name: &str) -> Option<(f64, f64, f64)> {
        self.records
            .get(name)
            .map(|r| (r.range_actual, r.range_extrap, r.range_cpa))
    }

    /// The appcast body (MOOS `buildReport`).
    pub fn report(&self, b: &mut String) {
        if self.variant == Variant::V20 {
            self.report_v20(b);
            return;
        }
        let reject = if self.s.reject_range > 0.0 {
            compact_string(self.s.reject_range, 2)
        } else {
            "off".into()
        };
        let _ = writeln!(b, "DisplayRadii:              {}", self.s.display_radii);
        let _ = writeln!(b, "Deriving X/Y from Lat/Lon: {}", self.use_geodesy);
        let _ = writeln!(
            b,
            "Contact Max Age: {}",
            compact_string(self.s.contact_max_age, 2)
        );
        let _ = writeln!(b, "Reject Range: {reject}");
        let _ = writeln!(b, "BCM_ALERT_REQUEST count: {}\n", self.requests);
        let _ = writeln!(b, "Alert Configurations ({}):", self.alerts.len());
        let _ = writeln!(b, "---------------------");
        for (id, a) in &self.alerts {
            let region = a.region.as_ref().map_or("n/a".to_string(), |p| {
                let mut s = String::from("pts=");
                geometry::spec::write_points(&mut s, p.vertices(), 2);
                s
            });
            let _ = writeln!(b, "Alert ID = {id}");
            let _ = writeln!(
                b,
                "  RANGE     = {}, {}",
                compact_string(a.range, 5),
                a.color
            );
            let _ = writeln!(
                b,
                "  CPA_RANGE = {}, {}",
                compact_string(a.range_far, 5),
                a.far_color
            );
            let _ = writeln!(b, "  ALERT_REG = {region}");
            for (tag, flags) in [("ON_FLAG", &a.on_flags), ("OFF_FLAG", &a.off_flags)] {
                for f in flags {
                    let v = match &f.value {
                        Value::String(s) => s.to_string(),
                        v => compact_string(v.as_ref().as_f64().unwrap_or(0.0), 3),
                    };
                    let _ = writeln!(b, "  {tag} = {}={v}", f.var);
                }
            }
        }
        self.report_status(b);
    }

    /// The appcast's status part, after the alert configurations (both variants'
    /// `buildReport`): the lists (pBasicContactMgr with the unalerted pairs), a contact table
    /// (pBasicContactMgr: every contact with its resolved count; V20: the first 7), and the
    /// requested range reports.
    fn report_status(&self, b: &mut String) {
        let basic = self.variant == Variant::Basic;
        let _ = writeln!(b);
        let _ = writeln!(b, "Alert Status Summary: ");
        let _ = writeln!(b, "----------------------");
        let _ = writeln!(b, "       List: {}", self.prev_list);
        let _ = writeln!(b, "    Alerted: {}", self.prev_alerted);
        if basic {
            let _ = writeln!(b, "  UnAlerted: {}", self.prev_unalerted);
        }
        let _ = writeln!(b, "    Retired: {}", self.prev_retired);
        let _ = writeln!(b, "      Recap: {}", self.prev_recap);
        let _ = writeln!(b);
        let _ = writeln!(b, "Contact Status Summary:");
        let _ = writeln!(b, "-----------------------");
        let mut t = if basic {
            let mut t = appcast::Table::with_pad(5, 5);
            t.push("Contact | Range  | Alerts  | Alerts | Alerts   ");
            t.push("        | Actual | Total   | Active | Resolved ");
            t
        } else {
            let mut t = appcast::Table::with_pad(4, 4);
            t.push("Contact | Range  | Alerts  | Alerts ");
            t.push("        | Actual | Total   | Active ");
            t
        };
        t.set_right_justify(1, true);
        t.add_header_lines();
        let shown = if basic { usize::MAX } else { 7 };
        for (name, r) in self.records.iter().take(shown) {
            let mut range = String::new();
            fixed(&mut range, r.range_actual, 1);
            t.push(name);
            t.push(&range);
            if basic {
                t.push(&r.alerts_total.to_string());
                t.push(&r.alerts_active.max(0).to_string());
                t.push(&r.alerts_resolved.to_string());
            } else {
                // The C++ looks the counts up by the contact's name as reported.
                let count = |m: &BTreeMap<String, u32>| m.get(name).copied().unwrap_or(0);
                t.push(&count(&self.x.alerts_total).to_string());
                t.push(&count(&self.x.alerts_active).to_string());
            }
        }
        t.write(b);
        let _ = writeln!(b, "\n\nCustom Contact Reports:");
        let _ = writeln!(b, "-----------------------");
        let mut t = appcast::Table::with_pad(5, 5);
        t.set_right_justify(1, true);
        t.push("VarName | Range  | Group  | VType | Contacts   ");
        t.add_header_lines();
        for (var, r) in &self.reports {
            let n = r.contacts.split(',').filter(|s| !s.is_empty()).count();
            t.push(var);
            t.push(&compact_string(r.range, 2));
            t.push(&r.group);
            t.push(&r.vtype);
            t.push(&n.to_string());
        }
        t.write(b);
    }
}

/// A block's text as the MOOS reader gives it (every blank removed).
fn strip_blanks(t: &str) -> String {
    t.chars()
        .filter(|c| !matches!(c, ' ' | '\t' | '\r'))
        .collect()
}

/// `key = value` of a block's line as the MOOS reader gives it (every blank removed).
fn split_line(line: &str) -> (String, String) {
    let line = strip_blanks(line);
    let (p, v) = line.split_once('=').unwrap_or((&line, ""));
    (p.to_string(), v.to_string())
}

/// The `pBasicContactMgr` or `pContactMgrV20` app: the core [`Hosted`].
pub type ContactMgrApp = Hosted<ContactMgr>;

impl Hosted<ContactMgr> {
    /// pBasicContactMgr, the app `name` of vehicle `community`, from its block, with the
    /// mission's local grid (`None` without `LatOrigin`/`LongOrigin`; `contact_local_coords`
    /// needs it).
    pub fn new(name: &str, block: ProcessConfig, community: &str, grid: Option<LocalGrid>) -> Self {
        Self::build(name, block, community, Variant::Basic, grid)
    }

    /// pContactMgrV20, the app `name` of vehicle `community` from its block, with the
    /// mission's local grid (`None` without `LatOrigin`/`LongOrigin`: a warning).
    pub fn new_v20(
        name: &str,
        block: ProcessConfig,
        community: &str,
        grid: Option<LocalGrid>,
    ) -> Self {
        Self::build(name, block, community, Variant::V20, grid)
    }

    fn build(
        name: &str,
        block: ProcessConfig,
        community: &str,
        variant: Variant,
        grid: Option<LocalGrid>,
    ) -> Self {
        let program = variant.program();
        let mut core = ContactMgr::blank(community, variant, grid);
        let mut warnings = Vec::new();
        let mut warn = |span: &mission::source::Span, msg: &str| {
            for m in msg.split('\n') {
                warnings.push(Diagnostic::line_warning(
                    DiagnosticKind::AppSetting,
                    span,
                    format!("{program}: {m}"),
                ));
            }
        };
        if variant == Variant::V20 {
            for w in core.startup_v20() {
                warn(&block.span, &w);
            }
        }
        // V20 reads its block's lines last to first, as the C++ does.
        let entries: Vec<_> = match variant {
            Variant::Basic => block.entries.iter().collect(),
            Variant::V20 => block.entries.iter().rev().collect(),
        };
        for p in entries {
            let (k, v) = (strip_blanks(&p.key), strip_blanks(&p.value));
            if let Err(msg) = core.configure(&k.to_ascii_lowercase(), &v) {
                warn(&p.span, &msg);
            }
        }
        let after = match variant {
            Variant::Basic => core.startup_basic(),
            Variant::V20 => core.validate_alerts_v20(),
        };
        for w in after {
            warn(&block.span, &w);
        }
        Hosted::host(name, block, warnings, core)
    }
}

impl AppCore for ContactMgr {
    fn subscriptions(&self) -> Vec<Subscription> {
        ContactMgr::subscriptions(self)
            .into_iter()
            .map(Subscription::var)
            .collect()
    }

    fn set_process_id(&mut self, pid: u32) {
        self.pid = Some(pid);
    }

    fn on_startup(&mut self, _now: f64, out: &mut Vec<Post>, _notes: &mut Vec<Note>) {
        if let Some(pid) = self.pid {
            let var = match self.variant {
                Variant::Basic => "PBASICCONTACTMGR_PID",
                Variant::V20 => "PCONTACTMGRV20_PID",
            };
            out.push(Post::double(var, f64::from(pid)));
        }
    }

    fn on_mail(&mut self, m: &Mail, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        let source = if m.source_aux.is_empty() {
            m.source.to_string()
        } else {
            format!("{}:{}", m.source, m.source_aux)
        };
        self.on_mail_from(&m.key, &m.value, &source, now, out);
        notes.extend(self.take_notes());
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        ContactMgr::iterate(self, now, out);
        notes.extend(self.take_notes());
    }

    fn report(&self, _now: f64, body: &mut String) {
        ContactMgr::report(self, body);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::antler::BuiltInApp;

    /// The values posted to `key`.
    pub(super) fn posts<'a>(out: &'a [Post], key: &str) -> Vec<&'a Value> {
        out.iter()
            .filter(|p| p.key == key)
            .map(|p| &p.value)
            .collect()
    }

    /// Mails node report `report` to `cm` at `t`, then iterates at `t`.
    pub(super) fn tick(cm: &mut ContactMgr, report: &Value, t: f64, out: &mut Vec<Post>) {
        cm.on_mail("NODE_REPORT", report, t, out);
        cm.iterate(t, out);
    }

    /// Mails the kayak `(name, x, y, hdg, spd)`'s node report ([`report`]) stamped `t` to `cm`,
    /// then iterates at `t`.
    pub(super) fn kayak_tick(
        cm: &mut ContactMgr,
        (name, x, y, hdg, spd): (&str, f64, f64, f64, f64),
        t: f64,
        out: &mut Vec<Post>,
    ) {
        tick(cm, &report(name, x, y, hdg, spd, t), t, out);
    }

    /// The manager of a `(manager, warnings)` pair, which must have no warnings.
    pub(super) fn no_warnings((cm, w): (ContactMgr, Vec<String>)) -> ContactMgr {
        assert!(w.is_empty(), "{w:?}");
        cm
    }

    /// A kayak's node report in group blue.
    pub(super) fn report(name: &str, x: f64, y: f64, hdg: f64, spd: f64, t: f64) -> Value {
        Value::text(format!(
            "NAME={name},X={x},Y={y},HDG={hdg},SPD={spd},TIME={t},TYPE=kayak,GROUP=blue"
        ))
    }

    /// On a grid whose origin (43.8 N, 69 W) is on its UTM zone's central meridian, a point
    /// 0.001 degrees north is at x = 0 and y = k0 * M * dlat: M, the meridian radius of
    /// WGS 84 at 43.8005 N, a(1-e^2)/(1-e^2 sin^2)^1.5 = 6366039.38 m, dlat = 1.745329e-5
    /// rad, k0 = 0.9996: y = 111.0639 m.
    #[test]
    fn contact_local_coords_derives_x_y_from_lat_lon_as_configured() {
        const Y: f64 = 111.0639;
        let grid = || vehicle::geodesy::LocalGrid::new(43.8, -69.0).ok();
        let with_xy = Value::text("NAME=bob,X=5,Y=7,LAT=43.801,LON=-69,SPD=0,HDG=0,TIME=1");
        let no_xy = Value::text("NAME=bob,LAT=43.801,LON=-69,SPD=0,HDG=0,TIME=1");
        let no_lat = Value::text("NAME=bob,X=5,Y=7,LON=-69,SPD=0,HDG=0,TIME=1");
        let range = |mode: &str, report: &Value| {
            let line = format!("contact_local_coords = {mode}");
            let alert = "alert = id=a, var=AT, val=y=$[Y], alert_range=500";
            let (mut cm, w) = ContactMgr::with_grid("abe", grid(), &[&line, alert]);
            assert!(w.is_empty(), "{w:?}");
            let mut out = Vec::new();
            cm.on_mail("NODE_REPORT", report, 1.0, &mut out);
            cm.iterate(1.0, &mut out);
            let at = posts(&out, "AT")[0].as_str().unwrap().to_string();
            (cm.ranges("bob").unwrap().0, at)
        };
        let near = |got: (f64, String), want: f64, at: &str| {
            assert!((got.0 - want).abs() < 1e-3, "{} vs {want}", got.0);
            assert_eq!(got.1, at);
        };
        let xy = 5f64.hypot(7.0);
        near(range("verbatim", &with_xy), xy, "y=7");
        near(range("lazy_lat_lon", &with_xy), xy, "y=7");
        near(range("lazy_lat_lon", &no_xy), Y, "y=111.06");
        near(range("force_lat_lon", &with_xy), Y, "y=111.06");
        near(range("force_lat_lon", &no_lat), xy, "y=7");
        // The derived position is what the reject range sees.
        let (mut cm, _) = ContactMgr::with_grid(
            "abe",
            grid(),
            &["contact_local_coords = force_lat_lon", "reject_range = 100"],
        );
        let mut out = Vec::new();
        cm.on_mail("NODE_REPORT", &with_xy, 1.0, &mut out);
        assert_eq!(cm.contacts().count(), 0);
        let mut body = String::new();
        cm.report(&mut body);
        assert!(body.contains("Deriving X/Y from Lat/Lon: true"), "{body}");
        // Without the grid: warned, and reports are taken verbatim.
        let (mut cm, w) = ContactMgr::new("abe", &["contact_local_coords = force_lat_lon"]);
        assert_eq!(
            w,
            [
                "No LatOrigin in *.moos file",
                "Wont derive x/y from lat/lon in node reports."
            ]
        );
        cm.on_mail("NODE_REPORT", &with_xy, 1.0, &mut out);
        cm.iterate(1.0, &mut out);
        assert!((cm.ranges("bob").unwrap().0 - xy).abs() < 1e-9);
        let (_, w) = ContactMgr::new("abe", &["contact_local_coords = utm"]);
        assert_eq!(w, ["Illegal contact_local_coords configuration"]);
    }

    #[test]
    fn a_helm_request_alerts_a_contact_coming_within_range_once() {
        let (mut cm, w) = ContactMgr::new("abe", &[]);
        assert!(w.is_empty());
        let mut out = Vec::new();
        cm.on_mail(
            "BCM_ALERT_REQUEST",
            &Value::text(
                "id=avd_, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME],alert_range=50, cpa_range=100",
            ),
            0.0,
            &mut out,
        );
        for (k, v) in [
            ("NAV_X", 0.0),
            ("NAV_Y", 0.0),
            ("NAV_HEADING", 0.0),
            ("NAV_SPEED", 0.0),
        ] {
            cm.on_mail(k, &Value::Double(v), 0.0, &mut out);
        }
        // 120 m east heading west at 2 m/s: beyond cpa_range (100): no alert.
        kayak_tick(&mut cm, ("bob", 120.0, 0.0, 270.0, 2.0), 1.0, &mut out);
        assert_eq!(posts(&out, "CONTACTS_LIST"), [&Value::text("bob")]);
        assert_eq!(
            posts(&out, "CONTACTS_UNALERTED"),
            [&Value::text("(bob,avd_)")],
            "{out:?}"
        );
        assert!(posts(&out, "CONTACT_INFO").is_empty());
        let (actual, _, cpa) = cm.ranges("bob").unwrap();
        assert_eq!(actual, 120.0);
        assert!(cpa < 1e-6, "coming straight at ownship: CPA 0, got {cpa}");
        // 90 m: within cpa_range, and its CPA (0) within alert_range: alerted.
        out.clear();
        kayak_tick(&mut cm, ("bob", 90.0, 0.0, 270.0, 2.0), 16.0, &mut out);
        assert_eq!(
            posts(&out, "CONTACT_INFO"),
            [&Value::text("name=bob # contact=bob")]
        );
        // The summaries come before the alerts in an iteration: the next one reports it.
        assert!(posts(&out, "CONTACTS_ALERTED").is_empty());
        // Still alerted: no second flag.
        out.clear();
        kayak_tick(&mut cm, ("bob", 80.0, 0.0, 270.0, 2.0), 21.0, &mut out);
        assert!(posts(&out, "CONTACT_INFO").is_empty());
        assert_eq!(
            posts(&out, "CONTACTS_ALERTED"),
            [&Value::text("(bob,avd_)")]
        );
        assert_eq!(posts(&out, "CONTACTS_UNALERTED"), [&Value::text("")]);
        assert_eq!(posts(&out, "CONTACTS_COUNT"), [&Value::Double(1.0)]);
        // Resolved by the helm's endflag: alerted again on the next iteration.
        cm.on_mail("CONTACT_RESOLVED", &Value::text("bob,avd_"), 22.0, &mut out);
        out.clear();
        cm.iterate(22.0, &mut out);
        assert_eq!(posts(&out, "CONTACT_INFO").len(), 1);
    }

    #[test]
    fn old_contacts_retire_and_reports_are_posted_on_change() {
        let (mut cm, w) = ContactMgr::new(
            "abe",
            &[
                "contact_max_age = 30",
                "max_retired_history = 1",
                "post_closest_range = true",
            ],
        );
        assert!(w.is_empty(), "{w:?}");
        let mut out = Vec::new();
        cm.on_mail(
            "NODE_REPORT",
            &report("bob", 30.5, 40.0, 0.0, 0.0, 0.0),
            0.0,
            &mut out,
        );
        cm.on_mail(
            "NODE_REPORT",
            &report("cal", 3.0, 4.0, 0.0, 0.0, 0.0),
            0.0,
            &mut out,
        );
        cm.on_mail(
            "NODE_REPORT",
            &report("abe", 0.0, 0.0, 0.0, 0.0, 0.0),
            0.0,
            &mut out,
        );
        cm.iterate(2.0, &mut out);
        assert_eq!(posts(&out, "CONTACTS_LIST"), [&Value::text("bob,cal")]);
        assert_eq!(posts(&out, "CONTACT_CLOSEST"), [&Value::text("cal")]);
        assert_eq!(posts(&out, "CONTACT_CLOSEST_RANGE"), [&Value::Double(5.0)]);
        assert_eq!(posts(&out, "CONTACT_CLOSEST_EVAL"), [&Value::Double(1.0)]);
        assert_eq!(
            posts(&out, "CONTACTS_RECAP"),
            [&Value::text(
                "vname=bob,range=50.30,age=2.00 # vname=cal,range=5.00,age=2.00"
            )]
        );
        // The recap again only after its interval.
        out.clear();
        cm.iterate(2.5, &mut out);
        assert!(posts(&out, "CONTACTS_RECAP").is_empty());
        assert!(posts(&out, "CONTACTS_LIST").is_empty(), "unchanged");
        // bob reports again; cal is 31 s old: retired.
        cm.on_mail(
            "NODE_REPORT",
            &report("bob", 30.5, 40.0, 0.0, 0.0, 30.0),
            30.0,
            &mut out,
        );
        out.clear();
        cm.iterate(31.0, &mut out);
        assert_eq!(posts(&out, "CONTACTS_RETIRED"), [&Value::text("cal")]);
        assert_eq!(posts(&out, "CONTACTS_LIST"), [&Value::text("bob")]);
    }

    #[test]
    fn configuration_warnings_are_the_cpp_ones() {
        let (_, w) = ContactMgr::new(
            "abe",
            &[
                "contact_max_age = 0",
                "decay = 30,10",
                "alert = id=a, bogus=1",
                "default_alert_range_color = notacolour",
                "alert_cpa_time = 5",
                "max_retired_history = 99",
                "nonsense = 1",
                "AppTick = 4",
            ],
        );
        assert_eq!(
            w,
            [
                "contact_max_age must be > zero: 0",
                "Unhandled decay config: decay=30,10",
                "unhandled alert config component: bogus",
                "Failed alert config: id=a,bogus=1",
                "default_alert_range_color, notacolour, not a color",
                "alert_cpa_time parameter has been deprecated.",
                "max_retired_hist should be in range [1,50]",
                "Unhandled config line: nonsense=1",
            ]
        );
    }

    #[test]
    fn display_radii_draws_each_alert_s_circles() {
        let (mut cm, _) = ContactMgr::new(
            "abe",
            &[
                "display_radii = true",
                "alert = id=avd, alert_range=20, cpa_range=40, cpa_range_color=white",
            ],
        );
        let mut out = Vec::new();
        cm.on_mail("NAV_X", &Value::Double(5.5), 0.0, &mut out);
        cm.iterate(1.0, &mut out);
        assert_eq!(
            posts(&out, "VIEW_CIRCLE"),
            [
                &Value::text(
                    "x=5.5,y=0,radius=20,label=avd_in,edge_color=gray65,vertex_size=0,edge_size=1"
                ),
                &Value::text(
                    "x=5.5,y=0,radius=40,label=avd_out,edge_color=white,vertex_size=0,edge_size=1"
                ),
            ]
        );
        out.clear();
        cm.on_mail("BCM_DISPLAY_RADII", &Value::text("false"), 2.0, &mut out);
        assert_eq!(
            posts(&out, "VIEW_CIRCLE")[0],
            &Value::text(
                "x=5.5,y=0,radius=20,active=false,label=avd_in,edge_color=gray65,vertex_size=0,edge_size=1"
            )
        );
    }

    #[test]
    fn report_requests_list_the_contacts_in_range_until_they_time_out() {
        let (mut cm, _) = ContactMgr::new("abe", &[]);
        let mut out = Vec::new();
        cm.on_mail(
            "NODE_REPORT",
            &report("bob", 30.0, 0.0, 0.0, 0.0, 1.0),
            1.0,
            &mut out,
        );
        cm.on_mail(
            "NODE_REPORT",
            &report("cal", 80.0, 0.0, 0.0, 0.0, 1.0),
            1.0,
            &mut out,
        );
        cm.on_mail(
            "BCM_REPORT_REQUEST",
            &Value::text("var=NEAR, range=50"),
            1.0,
            &mut out,
        );
        cm.on_mail(
            "BCM_REPORT_REQUEST",
            &Value::text("var=X Y, range=50"),
            1.0,
            &mut out,
        );
        assert!(cm.take_notes().contains(&Note::Warning(
            "Failed REPORT_REQUEST: var=X Y, range=50".into()
        )));
        cm.iterate(1.0, &mut out);
        assert_eq!(posts(&out, "NEAR"), [&Value::text("bob")]);
        out.clear();
        cm.iterate(2.0, &mut out);
        assert!(posts(&out, "NEAR").is_empty(), "posted on change only");
        // Not renewed within range_report_timeout (10 s): forgotten.
        cm.on_mail(
            "NODE_REPORT",
            &report("cal", 20.0, 0.0, 0.0, 0.0, 12.0),
            12.0,
            &mut out,
        );
        out.clear();
        cm.iterate(12.0, &mut out);
        assert!(posts(&out, "NEAR").is_empty());
    }

    #[test]
    fn a_bad_resolution_is_a_warning_posted_and_the_app_reports_bad_lines_at_their_line() {
        let (mut cm, _) = ContactMgr::new("abe", &["alert = id=avd, alert_range=10"]);
        let mut out = Vec::new();
        cm.on_mail("CONTACT_RESOLVED", &Value::text("zed,avd"), 1.0, &mut out);
        assert_eq!(
            posts(&out, "CONTACT_MGR_WARNING"),
            [&Value::text(
                "Resolution failed. Nothing known about vehicle: zed"
            )]
        );
        let block = crate::testing::block(
            "m.moos",
            "ProcessConfig = pBasicContactMgr\n{\n  AppTick = 2\n  contact_max_age = -3\n  bogus = 1\n}\n",
        );
        let app = ContactMgrApp::new("pBasicContactMgr", block, "abe", None);
        let w: Vec<String> = app.warnings().iter().map(Diagnostic::located).collect();
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(
            w[0].contains("m.moos:4") && w[0].contains("contact_max_age must be > zero: -3"),
            "{w:?}"
        );
        assert!(
            w[1].contains("m.moos:5") && w[1].contains("Unhandled config line: bogus=1"),
            "{w:?}"
        );
    }
}
