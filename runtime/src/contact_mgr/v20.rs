//! What `pContactMgrV20` changes in the contact manager (MOOS-IvP's `pContactMgrV20` at
//! a2a9b716: `ContactMgrV20`, its `CMAlert`, `PlatformAlertRecord` and `RangeMark`, over
//! `ContactLedger` and `ExFilterSet`).
//!
//! The block is read last line first (the C++ walks its lines in reverse), so of two lines
//! setting one thing the first wins, and `alert = id=a, alert_range=15, cpa_range=5` read after
//! a later line of the same id sees that line's ranges first. An alert has no default ranges:
//! until one is given (here or by the helm's `BCM_ALERT_REQUEST`) it is not valid and never
//! applies. Contacts go through the manager's filters (`match_name`, `ignore_group`,
//! `match_region`, ..., ownship's name always ignored) when their report arrives: one that
//! fails is retired at the next iteration. A report without x/y gets them from its latitude and
//! longitude on the mission's grid (the C++ ledger's geodesy; `contact_local_coords` is
//! accepted and has no effect, as in the C++). Types are fixed as the ledger does (`uuv` is
//! `auv`, an unknown type `ship`; an `auv`/`glider` without depth is refused).
//!
//! Each iteration: coordinates, ranges (actual, extrapolated, CPA and rate of closure), early
//! warnings and their end, the early-warning circles, the alerts (held until the helm is seen
//! in `DRIVE` when `hold_alerts_for_helm`), the alert circle, retirement (age, 5 % beyond
//! `reject_range`, and culling past `max_contacts`: the stalest half first, then the farthest),
//! range reports, summaries.
//!
//! # Conformance with pContactMgrV20 (MOOS-IvP a2a9b716)
//!
//! | parameter | default | validation (C++ rule) | coug |
//! |---|---|---|---|
//! | alert | none | `id`, `var`, `val`/`pattern`, `on_flag`, `off_flag` (`#`-separated), `alert_range`, `cpa_range` (numbers), the filter keys; `action=disable`/`enable` (dis)ables an id; anything else: `unhandled alert config component` | done |
//! | match_name, ignore_name, match_group, ignore_group, match_type, ignore_type | none | not both match and ignore | done |
//! | match_region, ignore_region | none | convex polygon | done |
//! | strict_ignore | true | boolean | done |
//! | max_contacts | 500 | unsigned | done |
//! | decay | 15,30 | `start,end`, `0 <= start <= end` | done |
//! | range_report_timeout | 10 | >= 0 | done |
//! | range_report_maxsize | 20 | unsigned | done |
//! | display_radii | false | boolean | done |
//! | display_radii_id, contact_local_coords, cpa_range_color | | accepted, no effect | done |
//! | post_closest_range, post_closest_relbng, post_all_ranges | false | boolean | done |
//! | max_retired_history | 5 | unsigned, clipped to 1..50 (warned) | done |
//! | recap_interval (contacts_recap_interval: deprecated) | 1 | `off` or > 0 | done |
//! | reject_range | 2000 | `off` or > 0 | done |
//! | alert_verbose | false | boolean | done |
//! | contact_max_age | 60 | > 0 | done |
//! | alert_range_color (default_alert_range_color: deprecated) | gray65 | colour | done |
//! | alert_range, alert_cpa_range | | deprecated: warned and unhandled | done |
//! | hold_alerts_for_helm | false | boolean | done |
//! | ownship_group, ownship_type | none | no white space | done (appcast only) |
//! | disable_var, enable_var, expunge_var | none | no white space | done |
//! | able_flag, disable_flag, enable_flag, early_warning_flag, cease_warning_flag, retire_flag | none | `VAR = value` (`clearall` empties) | done |
//! | early_warning_time | -1 (off) | >= 0 | done |
//! | early_warning_radii | false | boolean | done |
//! | ewarn_radii_color | green | colour | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | the alerts' flags | a contact enters (on) or leaves (off) an alert | `VAR = value`, macros `$[X]` `$[Y]` `$[LAT]` `$[LON]` `$[HDG]` `$[DEP]` `$[VNAME]` `$[VTYPE]` `$[GROUP]` `$[UTIME]` `%[VNAME]` `%[VTYPE]` `%[GROUP]` (`$[SPD}` as the C++ spells it) | done |
//! | CONTACTS_LIST, CONTACTS_ALERTED, CONTACTS_RETIRED, CONTACTS_COUNT | on change | as pBasicContactMgr (no CONTACTS_UNALERTED) | done |
//! | CONTACTS_RECAP | every `recap_interval` s | `vname=..,range=..,age=.. # ...` | done |
//! | CONTACT_CLOSEST, CONTACT_CLOSEST_TIME | the closest changes | name; time | done |
//! | CONTACT_CLOSEST_RANGE, CONTACT_CLOSEST_RELBNG | when enabled, on change | whole metres; whole degrees | done |
//! | CONTACT_RANGES | `post_all_ranges`, each iteration | ranges ascending, 1 decimal, compacted | done |
//! | ALERT_VERBOSE | `alert_verbose` | `new_contact=..`; `contact=..,alert_id=..,<transition>,alert_range=..,alert_range_cpa=..,range_actual=..[,range_cpa=..][,after_warning=..]` | done |
//! | VIEW_CIRCLE | `display_radii`: the largest alert range, label `alert_<ownship>`, duration 3; `early_warning_radii`: `xewarn_<contact>` | spec | done |
//! | BHV_ABLE_FILTER | mail on `disable_var`/`enable_var`/`expunge_var` | `contact=..,action=..` or `vsource=..,action=..` | done |
//! | the warning, cease and retire flags | a contact closes within the early-warning range, opens 5 % past it, retires | macros `$[CONTACT]`, `$[RNG]`, `$[RNG_EXT]`, `$[CPA]`, `$[ROC]`, `$[UTC]` | done |
//! | `<var>` of a `BCM_REPORT_REQUEST` | on change, or once with `refresh=true` | names, comma-separated | done |
//! | PCONTACTMGRV20_PID | at start-up, as its own process | pid | done |

use std::collections::{BTreeMap, BTreeSet, VecDeque};
use std::fmt::Write as _;

use behaviors::contact::ContactFilter;
use helm::ledger::NodeReport;
use moos_types::fmt::compact_string;
use moos_types::text::{is_number, set_boolean_on_string};

use super::{ContactMgr, Flag, flag};
use crate::app::{Post, Value};
use crate::appcasting::Note;

/// The program name.
pub const PROGRAM: &str = "pContactMgrV20";

/// What only pContactMgrV20 keeps.
#[derive(Debug, Clone)]
pub(super) struct Extra {
    pub(super) filter: ContactFilter,
    pub(super) max_contacts: usize,
    pub(super) range_report_maxsize: usize,
    pub(super) post_closest_relbng: bool,
    pub(super) post_all_ranges: bool,
    pub(super) alert_rng_color: String,
    pub(super) hold_alerts_for_helm: bool,
    pub(super) helm_in_drive: bool,
    pub(super) os_group: String,
    pub(super) os_type: String,
    pub(super) disable_var: String,
    pub(super) enable_var: String,
    pub(super) expunge_var: String,
    pub(super) able_flags: Vec<Flag>,
    pub(super) disable_flags: Vec<Flag>,
    pub(super) enable_flags: Vec<Flag>,
    pub(super) early_warning_flags: Vec<Flag>,
    pub(super) cease_warning_flags: Vec<Flag>,
    pub(super) retire_flags: Vec<Flag>,
    pub(super) early_warning_time: f64,
    pub(super) early_warning_radii: bool,
    pub(super) ewarn_radii_color: String,
    pub(super) will_warn: BTreeMap<String, f64>,
    pub(super) was_warned: BTreeMap<String, f64>,
    pub(super) utc_warned: BTreeMap<String, f64>,
    pub(super) alerts_disabled: BTreeSet<String>,
    pub(super) disabled_contacts: VecDeque<String>,
    pub(super) enabled_contacts: VecDeque<String>,
    pub(super) filtered: BTreeSet<String>,
    pub(super) alerts_total: BTreeMap<String, u32>,
    pub(super) alerts_active: BTreeMap<String, u32>,
    pub(super) prev_closest_relbng: f64,
}

impl Default for Extra {
    fn default() -> Self {
        Extra {
            filter: ContactFilter::default(),
            max_contacts: 500,
            range_report_maxsize: 20,
            post_closest_relbng: false,
            post_all_ranges: false,
            alert_rng_color: "gray65".into(),
            hold_alerts_for_helm: false,
            helm_in_drive: false,
            os_group: String::new(),
            os_type: String::new(),
            disable_var: String::new(),
            enable_var: String::new(),
            expunge_var: String::new(),
            able_flags: Vec::new(),
            disable_flags: Vec::new(),
            enable_flags: Vec::new(),
            early_warning_flags: Vec::new(),
            cease_warning_flags: Vec::new(),
            retire_flags: Vec::new(),
            early_warning_time: -1.0,
            early_warning_radii: false,
            ewarn_radii_color: "green".into(),
            will_warn: BTreeMap::new(),
            was_warned: BTreeMap::new(),
            utc_warned: BTreeMap::new(),
            alerts_disabled: BTreeSet::new(),
            disabled_contacts: VecDeque::new(),
            enabled_contacts: VecDeque::new(),
            filtered: BTreeSet::new(),
            alerts_total: BTreeMap::new(),
            alerts_active: BTreeMap::new(),
            prev_closest_relbng: 0.0,
        }
    }
}

/// MOOS `setBooleanOnString` into `b`: false when `v` is not a boolean.
fn set_bool(b: &mut bool, v: &str) -> bool {
    match set_boolean_on_string(*b, v) {
        Some(x) => {
            *b = x;
            true
        }
        None => false,
    }
}

/// MOOS `setPosDoubleOnString`.
fn pos(v: &str) -> Option<f64> {
    let d = geometry::atof(v);
    (is_number(v) && d > 0.0).then_some(d)
}

/// MOOS `setNonNegDoubleOnString`.
fn non_neg(v: &str) -> Option<f64> {
    let d = geometry::atof(v);
    (is_number(v) && d >= 0.0).then_some(d)
}

/// MOOS `setUIntOnString`.
fn uint(v: &str) -> Option<usize> {
    let d = geometry::atof(v);
    (is_number(v) && d >= 0.0).then_some(d as usize)
}

/// MOOS `setNonWhiteVarOnString`.
fn non_white(slot: &mut String, v: &str) -> bool {
    let v = v.trim();
    if v.is_empty() || v.contains(char::is_whitespace) {
        return false;
    }
    *slot = v.to_string();
    true
}

/// MOOS `addVarDataPairOnString`.
fn add_flag(flags: &mut Vec<Flag>, v: &str) -> bool {
    if v == "clearall" {
        flags.clear();
        return true;
    }
    match flag(v) {
        Some(f) => {
            flags.push(f);
            true
        }
        None => false,
    }
}

/// MOOS `macroExpand` of `$[name]` and `$(name)`.
pub(super) fn expand(s: &str, name: &str, repl: &str) -> String {
    s.replace(&format!("$({name})"), repl)
        .replace(&format!("$[{name}]"), repl)
}

impl ContactMgr {
    /// A pContactMgrV20 for vehicle `ownship` on the mission's `grid` from the block's
    /// `param = value` lines (in file order; read last first, as the C++ does), with the
    /// warnings the C++ app reports.
    ///
    /// ```
    /// use runtime::contact_mgr::ContactMgr;
    /// use runtime::app::Value;
    /// let (mut cm, w) = ContactMgr::new_v20("abe", None, &[
    ///     "alert = id=avd, on_flag=CONTACT_INFO=name=$[VNAME]",
    ///     "alert = id=avd, alert_range=50",
    /// ]);
    /// assert_eq!(w, ["Lat or Lon Origin not set in *.moos file."]);
    /// let mut out = Vec::new();
    /// cm.on_mail("NODE_REPORT", &Value::text("NAME=bob,X=30,Y=0,SPD=1,HDG=270,TIME=10,TYPE=kayak"), 10.0, &mut out);
    /// cm.iterate(10.0, &mut out);
    /// assert!(out.iter().any(|p| p.key == "CONTACT_INFO" && p.value == Value::text("name=bob")));
    /// ```
    pub fn new_v20(
        ownship: &str,
        grid: Option<vehicle::geodesy::LocalGrid>,
        lines: &[&str],
    ) -> (ContactMgr, Vec<String>) {
        let mut cm = ContactMgr::blank(ownship, super::Variant::V20, grid);
        let mut warnings = cm.startup_v20();
        for line in lines.iter().rev() {
            let (p, v) = super::split_line(line);
            if let Err(w) = cm.configure(&p.to_ascii_lowercase(), &v) {
                warnings.extend(w.split('\n').map(str::to_string));
            }
        }
        warnings.extend(cm.validate_alerts_v20());
        (cm, warnings)
    }

    /// OnStartUp before the block: the geodesy and ownship warnings, ownship's name ignored.
    pub(super) fn startup_v20(&mut self) -> Vec<String> {
        let mut w = Vec::new();
        if self.grid.is_none() {
            w.push("Lat or Lon Origin not set in *.moos file.".to_string());
        }
        if self.ownship.is_empty() {
            w.push("ownship name unknown, host_community unset".to_string());
        }
        let own = self.ownship.clone();
        self.x.filter.set_param("ignore_name", &own);
        w
    }

    /// After the block: every alert must be valid.
    pub(super) fn validate_alerts_v20(&self) -> Vec<String> {
        self.alerts
            .iter()
            .filter(|(_, a)| !a.valid_v20())
            .map(|(id, _)| format!("Invalid alert config:{id}"))
            .collect()
    }

    /// One line of the block (`param` in lower case).
    pub(super) fn configure_v20(&mut self, param: &str, value: &str) -> Result<(), String> {
        let mut warns = Vec::new();
        let renamed = match param {
            "alert_range" | "alert_cpa_range" => {
                warns.push(format!("{param} is deprecated"));
                param
            }
            "default_alert_range_color" => "alert_range_color",
            "default_cpa_range_color" => "cpa_range_color",
            "contacts_recap_interval" => "recap_interval",
            _ => param,
        };
        if renamed != param {
            warns.push(format!("{param} is deprecated. Use instead: {renamed}"));
        }
        let handled = self.config_line_v20(renamed, value, &mut warns);
        let exempt = appcast::casting::UNHANDLED_EXEMPT
            .contains(&param.to_ascii_uppercase().as_str())
            || matches!(param, "comms_policy" | "max_appcast_run_warnings");
        if !handled && !exempt {
            warns.push(format!("Unhandled config line: {param}={value}"));
        }
        if warns.is_empty() {
            Ok(())
        } else {
            Err(warns.join("\n"))
        }
    }

    fn config_line_v20(&mut self, param: &str, value: &str, warns: &mut Vec<String>) -> bool {
        let x = &mut self.x;
        let s = &mut self.s;
        match param {
            "alert" => match self.config_alert(value, "") {
                Ok(()) => true,
                Err(w) => {
                    warns.push(w);
                    false
                }
            },
            "ignore_name" | "match_name" | "ignore_group" | "match_group" | "ignore_type"
            | "match_type" | "match_region" | "ignore_region" | "strict_ignore" => {
                x.filter.set_param(param, value) == Some(true)
            }
            "max_contacts" => uint(value).map(|n| x.max_contacts = n).is_some(),
            "decay" => {
                let (l, r) = value.split_once(',').unwrap_or((value, ""));
                let (l, r) = (l.trim(), r.trim());
                let (a, b) = (geometry::atof(l), geometry::atof(r));
                if is_number(l) && is_number(r) && a >= 0.0 && a <= b {
                    s.decay = (a, b);
                    true
                } else {
                    false
                }
            }
            "range_report_timeout" => non_neg(value).map(|d| s.range_report_timeout = d).is_some(),
            "range_report_maxsize" => uint(value).map(|n| x.range_report_maxsize = n).is_some(),
            "display_radii" => set_bool(&mut s.display_radii, value),
            "display_radii_id" | "contact_local_coords" | "cpa_range_color" => true,
            "post_closest_range" => set_bool(&mut s.post_closest_range, value),
            "post_closest_relbng" => set_bool(&mut x.post_closest_relbng, value),
            "post_all_ranges" => set_bool(&mut x.post_all_ranges, value),
            "max_retired_history" => match uint(value) {
                Some(n) => {
                    if !(1..=50).contains(&n) {
                        warns.push("max_retired_hist should be in range [1,50]".into());
                    }
                    s.max_retired = n.clamp(1, 50);
                    true
                }
                None => false,
            },
            "recap_interval" | "reject_range" => {
                let slot = if param == "reject_range" {
                    &mut s.reject_range
                } else {
                    &mut s.recap_interval
                };
                if value.eq_ignore_ascii_case("off") {
                    *slot = -1.0;
                    true
                } else {
                    pos(value).map(|d| *slot = d).is_some()
                }
            }
            "alert_verbose" => set_bool(&mut s.alert_verbose, value),
            "contact_max_age" => pos(value).map(|d| s.contact_max_age = d).is_some(),
            "alert_range_color" => {
                let ok = geometry::color::is_color(value);
                if ok {
                    x.alert_rng_color = value.to_string();
                }
                ok
            }
            "hold_alerts_for_helm" => set_bool(&mut x.hold_alerts_for_helm, value),
            "ownship_group" => non_white(&mut x.os_group, value),
            "ownship_type" => non_white(&mut x.os_type, value),
            "disable_var" => non_white(&mut x.disable_var, value),
            "enable_var" => non_white(&mut x.enable_var, value),
            "expunge_var" => non_white(&mut x.expunge_var, value),
            "able_flag" => add_flag(&mut x.able_flags, value),
            "disable_flag" => add_flag(&mut x.disable_flags, value),
            "enable_flag" => add_flag(&mut x.enable_flags, value),
            "early_warning_flag" => add_flag(&mut x.early_warning_flags, value),
            "cease_warning_flag" => add_flag(&mut x.cease_warning_flags, value),
            "retire_flag" => add_flag(&mut x.retire_flags, value),
            "early_warning_time" => non_neg(value).map(|d| x.early_warning_time = d).is_some(),
            "early_warning_radii" => set_bool(&mut x.early_warning_radii, value),
            "ewarn_radii_color" => {
                let ok = geometry::color::is_color(value);
                if ok {
                    x.ewarn_radii_color = value.to_string();
                }
                ok
            }
            _ => false,
        }
    }

    pub(super) fn subscriptions_v20(&self) -> Vec<String> {
        let mut v: Vec<String> = [
            "NODE_REPORT",
            "BCM_DISPLAY_RADII",
            "BCM_ALERT_REQUEST",
            "BCM_REPORT_REQUEST",
            "NAV_X",
            "NAV_Y",
            "NAV_SPEED",
            "NAV_HEADING",
            "IVPHELM_STATE",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        for var in [&self.x.disable_var, &self.x.enable_var, &self.x.expunge_var] {
            if !var.is_empty() {
                v.push(var.clone());
            }
        }
        v
    }

    /// One mail but ownship's navigation (MOOS `OnNewMail`).
    pub(super) fn on_mail_v20(
        &mut self,
        key: &str,
        value: &Value,
        source: &str,
        now: f64,
        out: &mut Vec<Post>,
    ) {
        let sval = value.as_str().unwrap_or("");
        let mut whynot = String::new();
        let handled = match key {
            "NODE_REPORT" => match self.node_report_v20(sval, out) {
                Ok(()) => true,
                Err(w) => {
                    whynot = w;
                    false
                }
            },
            "BCM_REPORT_REQUEST" => {
                self.report_request(sval, source, now);
                true
            }
            "BCM_DISPLAY_RADII" => set_bool(&mut self.s.display_radii, sval),
            "BCM_ALERT_REQUEST" => {
                self.requests += 1;
                self.notes.push(Note::Event(format!(
                    "New BCM_ALERT_REQUEST (src={source}): {sval}"
                )));
                if let Err(w) = self.config_alert(sval, source) {
                    self.notes.push(Note::Warning(w));
                    self.notes
                        .push(Note::Warning(format!("Unhandled Alert Request: {sval}")));
                }
                true
            }
            "IVPHELM_STATE" => {
                if sval == "DRIVE" {
                    self.x.helm_in_drive = true;
                }
                true
            }
            k if !self.x.disable_var.is_empty() && k == self.x.disable_var => {
                self.able_contact(sval, "disable", out);
                true
            }
            k if !self.x.enable_var.is_empty() && k == self.x.enable_var => {
                self.able_contact(sval, "enable", out);
                true
            }
            k if !self.x.expunge_var.is_empty() && k == self.x.expunge_var => {
                self.able_contact(sval, "expunge", out);
                true
            }
            _ => false,
        };
        if !handled {
            self.notes
                .push(Note::Warning(format!("Bad Mail: {key}:{whynot}")));
        }
    }

    /// A node report (MOOS `handleMailNodeReport`): `Err` with the C++'s reason.
    fn node_report_v20(&mut self, text: &str, out: &mut Vec<Post>) -> Result<(), String> {
        let mut r = NodeReport::parse(text);
        let vname = r.name.clone();
        if vname.is_empty() {
            return Err("Empty vname".into());
        }
        if vname.eq_ignore_ascii_case(&self.ownship) {
            return Ok(());
        }
        let (x, y) = (r.x_m.unwrap_or(0.0), r.y_m.unwrap_or(0.0));
        if !self.x.filter.check_all(&vname, &r.group, &r.vtype, x, y) {
            self.x.filtered.insert(vname);
            return Ok(());
        }
        // The ledger's type fixing (`processNodeRecord`).
        let vtype = helm::ledger::fixed_type(&r.vtype);
        if (vtype == "auv" || vtype == "glider") && r.depth_m.is_none() {
            return Err(format!("1:{vname}2:"));
        }
        r.vtype = vtype;
        self.upsert(vname, r, out);
        Ok(())
    }

    /// A mail on `disable_var`, `enable_var` or `expunge_var` (MOOS
    /// `handleMailModEnableContact`).
    fn able_contact(&mut self, text: &str, action: &str, out: &mut Vec<Post>) {
        let mut contact = String::new();
        let msg = if !text.contains('=') && !text.contains(',') {
            format!("contact={text}")
        } else {
            contact = moos_types::text::tok_string_parse(text, "contact").to_string();
            if !contact.is_empty() {
                format!("contact={contact}")
            } else {
                let vsource = moos_types::text::tok_string_parse(text, "vsource");
                if vsource.is_empty() {
                    return;
                }
                format!("vsource={vsource}")
            }
        };
        out.push(Post::text(
            "BHV_ABLE_FILTER",
            format!("{msg},action={action}"),
        ));
        if contact.is_empty() {
            return;
        }
        let x = &mut self.x;
        let (add, other, max, flags) = match action {
            "enable" => (
                &mut x.enabled_contacts,
                &mut x.disabled_contacts,
                250,
                x.enable_flags.clone(),
            ),
            "disable" => (
                &mut x.disabled_contacts,
                &mut x.enabled_contacts,
                25,
                x.disable_flags.clone(),
            ),
            _ => return,
        };
        other.retain(|c| *c != contact);
        add.retain(|c| *c != contact);
        add.push_front(contact);
        if add.len() > max {
            add.pop_back();
        }
        let able = self.x.able_flags.clone();
        self.post_able_flags(&able, out);
        self.post_able_flags(&flags, out);
    }

    /// MOOS `postFlags` with `expandMacros` (`$[RECENT_DISABLED]`, `$[RECENT_ENABLED]`,
    /// `$[TOTAL_DISABLED]`, `$[ALL_DISABLED]`).
    fn post_able_flags(&mut self, flags: &[Flag], out: &mut Vec<Post>) {
        let x = &self.x;
        let expand_all = |s: &str| {
            super::expand_able_macros(s, &x.disabled_contacts, &x.enabled_contacts, expand)
        };
        for f in flags {
            self.notes.push(f.post(expand_all, out));
        }
    }

    /// One iteration (MOOS `ContactMgrV20::Iterate`).
    pub(super) fn iterate_v20(&mut self, now: f64, out: &mut Vec<Post>) {
        // The ledger derives x/y from lat/lon for reports without them.
        if let Some(grid) = &self.grid {
            for rec in self.records.values_mut() {
                let r = &mut rec.report;
                if (r.x_m.is_none() || r.y_m.is_none())
                    && let (Some(lat), Some(lon)) = (r.lat_deg, r.lon_deg)
                    && let Ok((x, y)) = grid.to_local(lat, lon)
                {
                    r.x_m = Some(x);
                    r.y_m = Some(y);
                }
            }
        }
        self.update_ranges(now);
        self.early_warnings(now, out);
        self.cease_warnings(now, out);
        self.early_warning_radii(now, out);
        if !self.x.hold_alerts_for_helm || self.x.helm_in_drive {
            self.check_alerts(now, out);
        }
        self.post_radii_v20(now, out);
        self.retire(now, out);
        self.post_range_reports(now, out);
        self.post_summaries(now, out);
    }

    /// The largest far range of the enabled alerts (-1 without one).
    fn max_alert_range(&self) -> f64 {
        self.alerts
            .iter()
            .filter(|(id, _)| !self.x.alerts_disabled.contains(*id))
            .map(|(_, a)| a.range_far)
            .fold(-1.0, f64::max)
    }

    fn early_warnings(&mut self, now: f64, out: &mut Vec<Post>) {
        if self.x.early_warning_time <= 0.0 {
            return;
        }
        let max_range = self.max_alert_range();
        let names: Vec<String> = self.records.keys().cloned().collect();
        for name in names {
            if self.x.was_warned.contains_key(&name) {
                continue;
            }
            self.x.will_warn.insert(name.clone(), 0.0);
            let rec = &self.records[&name];
            let (range, roc) = (rec.range_extrap, rec.range_roc);
            if roc <= 0.0 || max_range <= 0.0 {
                continue;
            }
            let warn_range = max_range + roc * self.x.early_warning_time;
            self.x.will_warn.insert(name.clone(), warn_range);
            if range < warn_range {
                let flags = self.x.early_warning_flags.clone();
                self.post_warning_flags(&flags, &name, now, out);
                self.x.was_warned.insert(name.clone(), range);
                self.x.utc_warned.insert(name.clone(), now);
                self.x.will_warn.insert(name, 0.0);
            }
        }
    }

    fn cease_warnings(&mut self, now: f64, out: &mut Vec<Post>) {
        let names: Vec<String> = self.records.keys().cloned().collect();
        for name in names {
            let Some(warned) = self.x.was_warned.get(&name).copied() else {
                continue;
            };
            if self.records[&name].range_extrap > warned * 1.05 {
                self.x.was_warned.remove(&name);
                self.x.utc_warned.remove(&name);
                let flags = self.x.cease_warning_flags.clone();
                self.post_warning_flags(&flags, &name, now, out);
            }
        }
    }

    /// MOOS `postWarningFlags`: string values with `$[CONTACT]`, `$[RNG_EXT]`, `$[RNG]`,
    /// `$[CPA]`, `$[ROC]`, `$[UTC]`.
    fn post_warning_flags(&mut self, flags: &[Flag], contact: &str, now: f64, out: &mut Vec<Post>) {
        let rec = self.records.get(contact);
        let expand_all = |s: &str| {
            let mut v = expand(s, "CONTACT", contact);
            if let Some(r) = rec {
                v = expand(&v, "RNG_EXT", &compact_string(r.range_extrap, 3));
                v = expand(&v, "RNG", &compact_string(r.range_actual, 3));
                v = expand(&v, "CPA", &compact_string(r.range_cpa, 3));
                v = expand(&v, "ROC", &compact_string(r.range_roc, 3));
            }
            expand(&v, "UTC", &compact_string(now, 3))
        };
        for f in flags {
            self.notes.push(f.post(expand_all, out));
        }
    }

    fn early_warning_radii(&self, now: f64, out: &mut Vec<Post>) {
        if !self.x.early_warning_radii || self.x.early_warning_time <= 0.0 {
            return;
        }
        for name in self.records.keys() {
            let Some(&r) = self.x.will_warn.get(name) else {
                continue;
            };
            if r <= 0.0 {
                continue;
            }
            let spec = self.circle(
                r,
                &format!("xewarn_{name}"),
                &self.x.ewarn_radii_color,
                true,
                Some("gray50"),
                Some(now),
            );
            out.push(Post::text("VIEW_CIRCLE", spec));
        }
    }

    /// PlatformAlertRecord's `setAlertedValue` with its counts.
    pub(super) fn set_alerted_v20(&mut self, name: &str, id: &str, b: bool) {
        let v = name.to_ascii_lowercase();
        if !self.alert_ids.contains(&id.to_ascii_lowercase()) {
            return;
        }
        let Some(row) = self.par.get_mut(&v) else {
            return;
        };
        let was = row.get(id).copied().unwrap_or(false);
        if b && !was {
            *self.x.alerts_total.entry(v.clone()).or_default() += 1;
            *self.x.alerts_active.entry(v.clone()).or_default() += 1;
        } else if !b && was {
            let n = self.x.alerts_active.entry(v.clone()).or_default();
            *n = n.saturating_sub(1);
        }
        row.insert(id.to_string(), b);
    }

    fn post_radii_v20(&self, now: f64, out: &mut Vec<Post>) {
        if !self.s.display_radii || self.alerts.is_empty() {
            return;
        }
        let max = self.max_alert_range();
        let color = &self.x.alert_rng_color;
        let active = !(max <= 0.0 || matches!(color.as_str(), "invisible" | "empty" | ""));
        let label = format!("alert_{}", self.ownship);
        out.push(Post::text(
            "VIEW_CIRCLE",
            self.circle(max, &label, color, active, None, Some(now)),
        ));
    }

    /// Past `max_contacts` (`start` contacts, `gone` already leaving): the stale half (older
    /// than half `contact_max_age`) go, then the farthest (MOOS `checkForNewRetiredContacts`).
    pub(super) fn cull(&self, gone: &mut BTreeSet<String>, start: usize, now: f64) {
        let max = self.x.max_contacts;
        if gone.len() + max < start {
            for (name, rec) in &self.records {
                if now - rec.time() > self.s.contact_max_age / 2.0 {
                    gone.insert(name.clone());
                }
            }
        }
        if gone.len() + max < start {
            let to_cull = start - (gone.len() + max);
            // Farthest first (RangeMark order: ascending range, stable, from a list built
            // by pushing each name in name order to its front).
            let mut marks: Vec<(&String, f64)> = self
                .records
                .iter()
                .rev()
                .map(|(n, r)| (n, r.range_actual))
                .collect();
            marks.sort_by(|a, b| a.1.total_cmp(&b.1));
            let mut culled = 0;
            let mut extra = Vec::new();
            for (name, _) in marks.iter().rev() {
                if !gone.contains(*name) && !extra.contains(*name) {
                    extra.push((*name).clone());
                    culled += 1;
                }
                if culled >= to_cull {
                    break;
                }
            }
            gone.extend(extra);
        }
    }

    /// Forgets the oldest range report request past its timeout when there are more than
    /// `range_report_maxsize`.
    pub(super) fn prune_range_reports(&mut self, now: f64) {
        if self.reports.len() > self.x.range_report_maxsize {
            let oldest = self
                .reports
                .iter()
                .map(|(v, r)| (v, now - r.reqtime))
                .filter(|(_, age)| *age >= self.s.range_report_timeout)
                .fold(None::<(&String, f64)>, |best, (v, age)| match best {
                    Some((_, a)) if age <= a => best,
                    _ => Some((v, age)),
                })
                .map(|(v, _)| v.clone());
            if let Some(v) = oldest {
                self.reports.remove(&v);
            }
        }
    }

    /// The appcast body (MOOS `ContactMgrV20::buildReport`).
    pub(super) fn report_v20(&self, b: &mut String) {
        let x = &self.x;
        let or = |s: &str| {
            if s.is_empty() {
                "not specified".to_string()
            } else {
                s.to_string()
            }
        };
        let reject = if self.s.reject_range > 0.0 {
            compact_string(self.s.reject_range, 2)
        } else {
            "off".into()
        };
        let _ = writeln!(b, "Ownship Group:      {}", or(&x.os_group));
        let _ = writeln!(b, "Ownship Type:       {}", or(&x.os_type));
        let _ = writeln!(
            b,
            "Contact Max Age:    {}",
            compact_string(self.s.contact_max_age, 2)
        );
        let _ = writeln!(b, "Reject Range:       {reject}");
        let _ = writeln!(
            b,
            "Early Warning Time: {}",
            moos_types::fmt::g_string(x.early_warning_time, 6)
        );
        if x.early_warning_time > 0.0 {
            let disabled: Vec<&str> = x.alerts_disabled.iter().map(String::as_str).collect();
            let _ = writeln!(b, "EarlyWarn Radii:    {}", x.early_warning_radii);
            let _ = writeln!(b, "EarlyWarn EWFlags:  {}", x.cease_warning_flags.len());
            let _ = writeln!(b, "EarlyWarn CWFlags:  {}", x.early_warning_flags.len());
            let _ = writeln!(b, "AlertsDisabled:     {}", disabled.join(","));
            let _ = writeln!(
                b,
                "max_alert_range:    {}",
                compact_string(self.max_alert_range(), 2)
            );
        }
        if !x.disable_var.is_empty() {
            let _ = writeln!(b, "Disable Var:        {}", x.disable_var);
        }
        if !x.enable_var.is_empty() {
            let _ = writeln!(b, "Enable Var:         {}", x.enable_var);
        }
        let _ = writeln!(b, "BCM_ALERT_REQUESTs: {}", self.requests);
        let _ = writeln!(b, "DisplayRadii:       {}", self.s.display_radii);
        let _ = writeln!(b);
        let _ = writeln!(b, "Alert Configurations ({}):", self.alerts.len());
        let _ = writeln!(b, "---------------------");
        for (i, (id, a)) in self.alerts.iter().enumerate() {
            let _ = writeln!(b, "{} ID: {id}", i + 1);
            for line in a.summary_v20() {
                let _ = writeln!(b, "  {line}");
            }
        }
        self.report_status(b);
    }
}

impl super::Alert {
    /// V20's `CMAlert::valid`: a range given, and a flag.
    pub(super) fn valid_v20(&self) -> bool {
        self.range != -1.0 && !(self.on_flags.is_empty() && self.off_flags.is_empty())
    }

    /// V20's `addAlertOnFlag`: `VAR=value`, a repeated text ignored.
    pub(super) fn add_on_flag(&mut self, s: &str) -> bool {
        let s = s.trim();
        if !self.on_raw.insert(s.to_string()) {
            return true;
        }
        match flag(s) {
            Some(f) => {
                self.on_flags.push(f);
                true
            }
            None => false,
        }
    }

    /// V20's `addAlertOffFlag`: `#`-separated `VAR=value`s, repeated texts ignored.
    pub(super) fn add_off_flags(&mut self, s: &str) -> bool {
        for part in s.split('#') {
            let part = part.trim();
            if !self.off_raw.insert(part.to_string()) {
                continue;
            }
            match flag(part) {
                Some(f) => self.off_flags.push(f),
                None => return false,
            }
        }
        true
    }

    /// V20's `CMAlert::getSummary` lines.
    pub(super) fn summary_v20(&self) -> Vec<String> {
        let range = |r: f64| {
            if r == -1.0 {
                "unspecified".to_string()
            } else if r >= 0.0 {
                compact_string(r, 2)
            } else {
                "off".to_string()
            }
        };
        let mut v = vec![
            format!(
                "Alert Ranges: {}/{}",
                range(self.range),
                range(self.range_far)
            ),
            format!(
                "Source: {}",
                if self.source.is_empty() {
                    "--"
                } else {
                    &self.source
                }
            ),
        ];
        // The C++ labels the off flags "OnFlag" too.
        for f in self.on_flags.iter().chain(&self.off_flags) {
            let val = match &f.value {
                Value::String(s) => s.to_string(),
                v => compact_string(v.as_ref().as_f64().unwrap_or(0.0), 3),
            };
            v.push(format!("OnFlag: {}={val}", f.var));
        }
        let filters = self.filter.summary();
        if !filters.is_empty() {
            v.extend(filters.split(", ").map(str::to_string));
        }
        v
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::antler::BuiltInApp;
    use crate::contact_mgr::ContactMgrApp;
    use crate::contact_mgr::tests::{kayak_tick, no_warnings, posts, report};
    use mission::diagnostic::Diagnostic;

    fn texts<'a>(out: &'a [Post], key: &str) -> Vec<&'a str> {
        posts(out, key)
            .into_iter()
            .filter_map(Value::as_str)
            .collect()
    }

    fn nav(cm: &mut ContactMgr, x: f64, y: f64, hdg: f64, spd: f64) {
        let mut out = Vec::new();
        for (k, v) in [
            ("NAV_X", x),
            ("NAV_Y", y),
            ("NAV_HEADING", hdg),
            ("NAV_SPEED", spd),
        ] {
            cm.on_mail(k, &Value::Double(v), 0.0, &mut out);
        }
    }

    /// A V20 manager with a grid (no origin warning) from `lines`.
    fn v20(lines: &[&str]) -> (ContactMgr, Vec<String>) {
        let grid = vehicle::geodesy::LocalGrid::new(43.8253, -70.3304).unwrap();
        ContactMgr::new_v20("abe", Some(grid), lines)
    }

    #[test]
    fn the_block_is_read_last_line_first_with_the_cpp_warnings() {
        let (cm, w) = v20(&[
            "alert = id=a, on_flag=X=1",
            "alert = id=a, alert_range=15, cpa_range=5",
            "alert = id=b, on_flag=Y=2",
            "contacts_recap_interval = 2",
            "alert_range = 50",
            "max_retired_history = 0",
            "reject_range = -5",
            "alert = id=c, bogus=1",
            "match_name = ben",
            "ignore_name = ben",
            "strict_ignore = maybe",
            "contact_local_coords = force_lat_lon",
            "AppTick = 4",
        ]);
        assert_eq!(
            w,
            [
                "Unhandled config line: strict_ignore=maybe",
                "Unhandled config line: match_name=ben",
                "unhandled alert config component: bogus",
                "Unhandled config line: alert=id=c,bogus=1",
                "Unhandled config line: reject_range=-5",
                "max_retired_hist should be in range [1,50]",
                "alert_range is deprecated",
                "Unhandled config line: alert_range=50",
                "contacts_recap_interval is deprecated. Use instead: recap_interval",
                // b has no range, c neither flag nor range: neither is valid.
                "Invalid alert config:b",
                "Invalid alert config:c",
            ]
        );
        // a: 15 then, read before it, cpa_range 5 pulls the range down to 5.
        let mut body = String::new();
        cm.report(&mut body);
        assert!(body.contains("1 ID: a\n  Alert Ranges: 5/5\n  Source: --\n  OnFlag: X=1\n"));
        assert!(body.contains("Alert Ranges: unspecified/unspecified"));
        assert_eq!(cm.s.recap_interval, 2.0);
        assert_eq!(cm.s.max_retired, 1);
    }

    #[test]
    fn an_alert_per_contact_follows_its_range_and_cpa_range() {
        let (mut cm, w) = v20(&["alert_verbose = true"]);
        assert!(w.is_empty(), "{w:?}");
        let mut out = Vec::new();
        let req = "id=avd_, on_flag=CONTACT_INFO=name=$[VNAME] # contact=$[VNAME], off_flag=GONE=$[VNAME]#N=3, alert_range=50, cpa_range=100";
        cm.on_mail_from(
            "BCM_ALERT_REQUEST",
            &Value::text(req),
            "pHelmIvP",
            0.0,
            &mut out,
        );
        assert!(cm.take_notes().contains(&Note::Event(format!(
            "New BCM_ALERT_REQUEST (src=pHelmIvP): {req}"
        ))));
        nav(&mut cm, 0.0, 0.0, 0.0, 0.0);
        // 120 m east coming west at 2 m/s: beyond cpa_range.
        kayak_tick(&mut cm, ("bob", 120.0, 0.0, 270.0, 2.0), 1.0, &mut out);
        assert_eq!(texts(&out, "ALERT_VERBOSE"), ["new_contact=bob"]);
        assert!(posts(&out, "CONTACT_INFO").is_empty());
        // 90 m: within cpa_range, its CPA (0) within alert_range: alerted.
        out.clear();
        cm.on_mail(
            "NODE_REPORT",
            &report("bob", 90.0, 0.0, 270.0, 2.0, 16.0),
            16.0,
            &mut out,
        );
        // cal 95 m north going north: within cpa_range, its CPA 95 m: not alerted.
        kayak_tick(&mut cm, ("cal", 0.0, 95.0, 0.0, 1.0), 16.0, &mut out);
        assert_eq!(texts(&out, "CONTACT_INFO"), ["name=bob # contact=bob"]);
        assert_eq!(
            texts(&out, "ALERT_VERBOSE"),
            [
                "new_contact=cal",
                "contact=bob,alert_id=avd_,off-->alerted,alert_range=50,alert_range_cpa=100,range_actual=90.0,range_cpa=0.0"
            ]
        );
        // The summaries follow the alerts within an iteration (V20's order).
        assert_eq!(texts(&out, "CONTACTS_ALERTED"), ["(bob,avd_)"]);
        assert_eq!(posts(&out, "CONTACTS_COUNT"), [&Value::Double(1.0)]);
        assert_eq!(texts(&out, "CONTACTS_LIST"), ["bob,cal"]);
        assert!(
            posts(&out, "CONTACTS_UNALERTED").is_empty(),
            "not a V20 posting"
        );
        // bob turns away, 110 m: off, with both off flags.
        out.clear();
        kayak_tick(&mut cm, ("bob", 110.0, 0.0, 90.0, 2.0), 26.0, &mut out);
        assert_eq!(texts(&out, "GONE"), ["bob"]);
        assert_eq!(posts(&out, "N"), [&Value::Double(3.0)]);
        assert_eq!(
            texts(&out, "ALERT_VERBOSE"),
            [
                "contact=bob,alert_id=avd_,alerted-->off,alert_range=50,alert_range_cpa=100,range_actual=110.0"
            ]
        );
        // The same on flag again adds nothing; a request can disable the alert.
        cm.on_mail("BCM_ALERT_REQUEST", &Value::text(req), 27.0, &mut out);
        assert_eq!(cm.alerts["avd_"].on_flags.len(), 1);
        cm.on_mail(
            "BCM_ALERT_REQUEST",
            &Value::text("id=avd_, action=disable"),
            27.0,
            &mut out,
        );
        out.clear();
        kayak_tick(&mut cm, ("bob", 40.0, 0.0, 270.0, 2.0), 28.0, &mut out);
        assert!(posts(&out, "CONTACT_INFO").is_empty(), "disabled");
        // An underwater type without depth is bad mail.
        cm.on_mail(
            "NODE_REPORT",
            &Value::text("NAME=dan,X=1,Y=1,TIME=28,TYPE=uuv"),
            28.0,
            &mut out,
        );
        assert!(
            cm.take_notes()
                .contains(&Note::Warning("Bad Mail: NODE_REPORT:1:dan2:".into()))
        );
    }

    #[test]
    fn alerts_wait_for_the_helm_when_asked_to() {
        let (mut cm, _) = v20(&[
            "hold_alerts_for_helm = true",
            "alert = id=a, on_flag=HIT=$[VNAME]@$[X]:$[Y]/$[GROUP]/%[VTYPE], alert_range=30",
        ]);
        let mut out = Vec::new();
        kayak_tick(&mut cm, ("bob", 10.0, 0.0, 0.0, 0.0), 1.0, &mut out);
        cm.on_mail("IVPHELM_STATE", &Value::text("PARK"), 2.0, &mut out);
        cm.iterate(2.0, &mut out);
        assert!(posts(&out, "HIT").is_empty());
        cm.on_mail("IVPHELM_STATE", &Value::text("DRIVE"), 3.0, &mut out);
        cm.iterate(3.0, &mut out);
        assert_eq!(texts(&out, "HIT"), ["bob@10:0/blue/kayak"]);
    }

    #[test]
    fn range_marks_closest_bearing_and_all_ranges() {
        let (mut cm, _) = v20(&[
            "post_all_ranges = true",
            "post_closest_range = true",
            "post_closest_relbng = true",
        ]);
        nav(&mut cm, 0.0, 0.0, 90.0, 1.0);
        let mut out = Vec::new();
        for (n, x, y) in [("bob", 30.0, 2.5), ("cal", 0.0, 5.0), ("dan", 12.04, 0.0)] {
            cm.on_mail(
                "NODE_REPORT",
                &report(n, x, y, 0.0, 0.0, 1.0),
                1.0,
                &mut out,
            );
        }
        cm.iterate(1.0, &mut out);
        // hypot(30, 2.5) = 30.10; ranges ascending, one decimal, compacted.
        assert_eq!(texts(&out, "CONTACT_RANGES"), ["5,12,30.1"]);
        assert_eq!(texts(&out, "CONTACT_CLOSEST"), ["cal"]);
        assert_eq!(posts(&out, "CONTACT_CLOSEST_RANGE"), [&Value::Double(5.0)]);
        // cal is due north, ownship heads east: 270 degrees relative.
        assert_eq!(
            posts(&out, "CONTACT_CLOSEST_RELBNG"),
            [&Value::Double(270.0)]
        );
        // CONTACT_RANGES goes out every iteration; the others on change.
        out.clear();
        cm.iterate(1.5, &mut out);
        assert_eq!(texts(&out, "CONTACT_RANGES"), ["5,12,30.1"]);
        assert!(posts(&out, "CONTACT_CLOSEST_RELBNG").is_empty());
    }

    #[test]
    fn filters_keep_contacts_out_and_retire_the_ones_that_fail_later() {
        let mut cm = no_warnings(v20(&[
            "ignore_group = red",
            "retire_flag = RETIRED=$[CONTACT]",
            "alert = id=k, on_flag=K=$[VNAME], alert_range=100, match_type=kayak",
            "alert = id=r, on_flag=R=$[VNAME], alert_range=100, match_region=pts={0,0:50,0:50,50:0,50}",
        ]));
        let mut out = Vec::new();
        let ship = "NAME=cal,X=10,Y=10,HDG=0,SPD=0,TIME=1,TYPE=ship,GROUP=blue";
        cm.on_mail("NODE_REPORT", &Value::text(ship), 1.0, &mut out);
        cm.on_mail(
            "NODE_REPORT",
            &report("bob", -10.0, 10.0, 0.0, 0.0, 1.0),
            1.0,
            &mut out,
        );
        cm.on_mail(
            "NODE_REPORT",
            &report("ABE", 1.0, 1.0, 0.0, 0.0, 1.0),
            1.0,
            &mut out,
        );
        let red = "NAME=dan,X=5,Y=5,HDG=0,SPD=0,TIME=1,TYPE=kayak,GROUP=red";
        cm.on_mail("NODE_REPORT", &Value::text(red), 1.0, &mut out);
        cm.iterate(1.0, &mut out);
        // Ownship (any case) and the red group are not contacts; dan's retire flag fires.
        assert_eq!(texts(&out, "CONTACTS_LIST"), ["bob,cal"]);
        assert_eq!(texts(&out, "RETIRED"), ["dan"]);
        // k matches kayaks (bob), r the region (cal).
        assert_eq!(texts(&out, "K"), ["bob"]);
        assert_eq!(texts(&out, "R"), ["cal"]);
        // bob turns red: retired at the next iteration, and listed.
        out.clear();
        let bob_red = "NAME=bob,X=-10,Y=10,HDG=0,SPD=0,TIME=2,TYPE=kayak,GROUP=red";
        cm.on_mail("NODE_REPORT", &Value::text(bob_red), 2.0, &mut out);
        cm.iterate(2.0, &mut out);
        assert_eq!(texts(&out, "CONTACTS_RETIRED"), ["bob"]);
        assert_eq!(texts(&out, "CONTACTS_LIST"), ["cal"]);
    }

    #[test]
    fn contacts_retire_by_age_and_past_max_contacts_the_farthest_go() {
        let (mut cm, _) = v20(&["contact_max_age = 10", "max_contacts = 2"]);
        let mut out = Vec::new();
        for (n, x) in [("bob", 30.0), ("cal", 10.0), ("dan", 20.0)] {
            cm.on_mail(
                "NODE_REPORT",
                &report(n, x, 0.0, 0.0, 0.0, 1.0),
                1.0,
                &mut out,
            );
        }
        cm.iterate(1.0, &mut out);
        assert_eq!(texts(&out, "CONTACTS_RETIRED"), ["bob"]);
        assert_eq!(texts(&out, "CONTACTS_LIST"), ["cal,dan"]);
        cm.on_mail(
            "NODE_REPORT",
            &report("dan", 20.0, 0.0, 0.0, 0.0, 9.0),
            9.0,
            &mut out,
        );
        out.clear();
        cm.iterate(11.5, &mut out);
        // cal's report is 10.5 s old: retired, newest first.
        assert_eq!(texts(&out, "CONTACTS_RETIRED"), ["cal,bob"]);
        assert_eq!(texts(&out, "CONTACTS_LIST"), ["dan"]);
    }

    #[test]
    fn reports_in_lat_lon_are_placed_on_the_grid() {
        let grid = vehicle::geodesy::LocalGrid::new(43.8253, -70.3304).unwrap();
        let (lat, lon) = grid.to_latlon(30.0, 40.0).unwrap();
        let (mut cm, w) = ContactMgr::new_v20("abe", Some(grid), &[]);
        assert!(w.is_empty());
        let mut out = Vec::new();
        let r = format!("NAME=bob,LAT={lat},LON={lon},HDG=0,SPD=0,TIME=1,TYPE=kayak");
        cm.on_mail("NODE_REPORT", &Value::text(r), 1.0, &mut out);
        cm.iterate(1.0, &mut out);
        let (actual, _, _) = cm.ranges("bob").unwrap();
        assert!((actual - 50.0).abs() < 0.01, "{actual}");
    }

    #[test]
    fn disabling_a_contact_posts_the_able_filter_and_flags() {
        let (mut cm, w) = v20(&[
            "disable_var = XYZ_DISABLE",
            "enable_var = XYZ_ENABLE",
            "able_flag = ABLE = 1",
            "disable_flag = DIS = $[TOTAL_DISABLED]:$[RECENT_DISABLED]:$[ALL_DISABLED]",
        ]);
        assert!(w.is_empty(), "{w:?}");
        assert!(cm.subscriptions().contains(&"XYZ_DISABLE".to_string()));
        let mut out = Vec::new();
        // A bare id: the filter only.
        cm.on_mail("XYZ_DISABLE", &Value::text("87993"), 1.0, &mut out);
        assert_eq!(
            texts(&out, "BHV_ABLE_FILTER"),
            ["contact=87993,action=disable"]
        );
        assert!(posts(&out, "ABLE").is_empty());
        out.clear();
        cm.on_mail(
            "XYZ_DISABLE",
            &Value::text("contact=ben, action=x"),
            1.0,
            &mut out,
        );
        cm.on_mail("XYZ_DISABLE", &Value::text("contact=cal"), 1.0, &mut out);
        assert_eq!(
            texts(&out, "BHV_ABLE_FILTER"),
            ["contact=ben,action=disable", "contact=cal,action=disable"]
        );
        assert_eq!(
            posts(&out, "ABLE"),
            [&Value::Double(1.0), &Value::Double(1.0)]
        );
        assert_eq!(texts(&out, "DIS"), ["1:ben:ben", "2:cal:cal,ben"]);
        out.clear();
        cm.on_mail("XYZ_ENABLE", &Value::text("vsource=ais"), 2.0, &mut out);
        assert_eq!(
            texts(&out, "BHV_ABLE_FILTER"),
            ["vsource=ais,action=enable"]
        );
    }

    #[test]
    fn early_warnings_come_before_the_alert_and_cease_when_it_opens() {
        let (mut cm, _) = v20(&[
            "early_warning_time = 10",
            "early_warning_radii = true",
            // (The MOOS reader drops the blanks of a block's lines.)
            "early_warning_flag = EW = $[CONTACT] at $[RNG]",
            "cease_warning_flag = CW = $[CONTACT]",
            "alert = id=a, on_flag=A=$[VNAME], alert_range=50",
            "alert_verbose = true",
        ]);
        nav(&mut cm, 0.0, 0.0, 0.0, 0.0);
        let mut out = Vec::new();
        // Closing at 2 m/s: warned within 50 + 2 * 10 = 70 m.
        kayak_tick(&mut cm, ("bob", 80.0, 0.0, 270.0, 2.0), 1.0, &mut out);
        assert!(posts(&out, "EW").is_empty());
        assert_eq!(
            texts(&out, "VIEW_CIRCLE"),
            [
                "x=0,y=0,radius=70,label=xewarn_bob,label_color=gray50,edge_color=green,time=1,duration=3,vertex_size=0,edge_size=1"
            ]
        );
        out.clear();
        kayak_tick(&mut cm, ("bob", 65.0, 0.0, 270.0, 2.0), 8.5, &mut out);
        assert_eq!(texts(&out, "EW"), ["bobat65"]);
        out.clear();
        kayak_tick(&mut cm, ("bob", 45.0, 0.0, 270.0, 2.0), 18.5, &mut out);
        assert!(texts(&out, "ALERT_VERBOSE")[0].ends_with(",range_cpa=0.0,after_warning=10"));
        // Opening past 65 * 1.05: the warning ceases.
        out.clear();
        kayak_tick(&mut cm, ("bob", 69.0, 0.0, 90.0, 2.0), 30.0, &mut out);
        assert_eq!(texts(&out, "CW"), ["bob"]);
    }

    #[test]
    fn the_alert_circle_and_refreshed_range_reports() {
        let (mut cm, _) = v20(&[
            "display_radii = true",
            "alert = id=avd, on_flag=A=1, alert_range=20, cpa_range=40",
        ]);
        let mut out = Vec::new();
        cm.on_mail("NAV_X", &Value::Double(5.5), 0.0, &mut out);
        cm.on_mail(
            "NODE_REPORT",
            &report("bob", 30.0, 0.0, 0.0, 0.0, 1.0),
            1.0,
            &mut out,
        );
        let req = "var=NEAR, range=50, refresh=true, reason=teaming";
        cm.on_mail_from(
            "BCM_REPORT_REQUEST",
            &Value::text(req),
            "pX:aux",
            1.0,
            &mut out,
        );
        assert!(cm.take_notes().contains(&Note::Event(format!(
            "New BCM_REPORT_REQUEST (src=pX:aux): {req}"
        ))));
        cm.iterate(1.0, &mut out);
        assert_eq!(
            texts(&out, "VIEW_CIRCLE"),
            [
                "x=5.5,y=0,radius=40,label=alert_abe,edge_color=gray65,time=1,duration=3,vertex_size=0,edge_size=1"
            ]
        );
        assert_eq!(texts(&out, "NEAR"), ["bob"]);
        out.clear();
        cm.iterate(2.0, &mut out);
        assert!(posts(&out, "NEAR").is_empty(), "refreshed once");
        cm.on_mail("BCM_REPORT_REQUEST", &Value::text(req), 2.0, &mut out);
        cm.iterate(2.5, &mut out);
        assert_eq!(texts(&out, "NEAR"), ["bob"]);
        // BCM_DISPLAY_RADII turns the circle off; a bad value is bad mail.
        cm.on_mail("BCM_DISPLAY_RADII", &Value::text("false"), 3.0, &mut out);
        cm.on_mail("BCM_DISPLAY_RADII", &Value::text("maybe"), 3.0, &mut out);
        assert!(
            cm.take_notes()
                .contains(&Note::Warning("Bad Mail: BCM_DISPLAY_RADII:".into()))
        );
        out.clear();
        cm.iterate(3.0, &mut out);
        assert!(posts(&out, "VIEW_CIRCLE").is_empty());
    }

    #[test]
    fn every_catalog_parameter_is_read_and_no_other() {
        // A value each key takes.
        let value = |k: &str| match k {
            "alert" => "id=a, on_flag=A=1, alert_range=5",
            "decay" => "10,20",
            "match_region" | "ignore_region" => "pts={0,0:10,0:10,10:0,10}",
            "alert_range_color"
            | "default_alert_range_color"
            | "cpa_range_color"
            | "default_cpa_range_color"
            | "ewarn_radii_color" => "white",
            k if k.ends_with("_flag") => "V=1",
            k if k.ends_with("_var") || k.starts_with("ownship") || k.ends_with("_id") => "X",
            k if k.ends_with("_name") || k.ends_with("_group") || k.ends_with("_type") => "q",
            "contact_local_coords" => "verbatim",
            "strict_ignore"
            | "display_radii"
            | "alert_verbose"
            | "hold_alerts_for_helm"
            | "early_warning_radii"
            | "app_logging"
            | "deprecated_ok" => "true",
            k if k.starts_with("post_") => "true",
            _ => "3",
        };
        for key in mission::catalog::CONTACT_MGR_V20_PARAMS {
            let line = format!("{key} = {}", value(key));
            let (_, w) = v20(&[&line]);
            assert!(
                w.iter().all(|w| !w.starts_with("Unhandled config line")),
                "{line}: {w:?}"
            );
        }
        let (_, w) = v20(&["alert_cpa_range = 3", "post_closest_rng = true"]);
        assert_eq!(
            w,
            [
                "Unhandled config line: post_closest_rng=true",
                "alert_cpa_range is deprecated",
                "Unhandled config line: alert_cpa_range=3",
            ]
        );
    }

    #[test]
    fn the_app_reports_bad_lines_at_their_line_and_its_pid() {
        let block = crate::testing::block(
            "m.moos",
            "ProcessConfig = pContactMgrV20\n{\n  AppTick = 2\n  contact_max_age = -3\n  bogus = 1\n}\n",
        );
        let mut app = ContactMgrApp::new_v20("pContactMgrV20", block, "abe", None);
        let w: Vec<String> = app.warnings().iter().map(Diagnostic::located).collect();
        assert_eq!(w.len(), 3, "{w:?}");
        assert!(w[0].contains("Lat or Lon Origin not set"), "{w:?}");
        // Last line first.
        assert!(
            w[1].contains("m.moos:5") && w[1].contains("bogus=1"),
            "{w:?}"
        );
        assert!(
            w[2].contains("m.moos:4") && w[2].contains("contact_max_age=-3"),
            "{w:?}"
        );
        use crate::app::App;
        app.set_process_id(42);
        let mut out = Vec::new();
        app.on_startup(0.0, &mut out).unwrap();
        assert_eq!(posts(&out, "PCONTACTMGRV20_PID"), [&Value::Double(42.0)]);
        let subs: Vec<String> = app.subscriptions().into_iter().map(|s| s.pattern).collect();
        assert!(subs.contains(&"IVPHELM_STATE".to_string()));
        assert!(!subs.contains(&"CONTACT_RESOLVED".to_string()));
    }
}
