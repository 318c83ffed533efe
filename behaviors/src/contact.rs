//! What contact behaviours share (MOOS-IvP `IvPContactBehavior` at a2a9b716): the contact a
//! behaviour reasons about, read each iteration from the helm's contact ledger
//! ([`Info::contact`], pHelmIvP's ledger snapshot: the last report's position, heading,
//! speed, group and type, not extrapolated, as the C++ helm leaves the ledger's
//! extrapolation off), the parameters every contact behaviour takes, and the relative
//! geometry (range, CPA engine) each behaviour builds its function from.
//!
//! A contact behaviour holds a [`ContactBase`], hands it every parameter first
//! ([`ContactBase::set_param`]) and calls [`ContactBase::update`] at the start of its idle and
//! running iterations.
//!
//! # Conformance with IvPContactBehavior (MOOS-IvP a2a9b716)
//!
//! | parameter | default | validation (C++ rule) | coug |
//! |---|---|---|---|
//! | contact | "" | any; `unset_ok` = no contact needed | done |
//! | on_no_contact_ok | true | boolean | done: a missing contact is a BHV_WARNING, else BHV_ERROR |
//! | extrapolate | true | boolean | done (read; the C++ never extrapolates at a2a9b716) |
//! | decay | 15,30 | `start,end` numbers, `0 <= start <= end` | done (read, as above) |
//! | decay_end | 30 | number | done (read) |
//! | time_on_leg | 60 (AvoidCollision 120) | number >= 0 | done |
//! | post_per_contact_info | false | boolean | done |
//! | match_name, ignore_name, match_group, ignore_group, match_type, ignore_type | none | comma list, case-folded; a name both matched and ignored is refused | done |
//! | match_region, ignore_region | none | convex polygon | done |
//! | strict_ignore | true | boolean | done |
//! | exit_on_filter_vtype, exit_on_filter_group, exit_on_filter_region | false | boolean | done |
//! | bearing_line_show, bearing_line_label_show | false | boolean | done |
//! | bearing_lines, bearing_line_config | none | `color:threshold, ..., info:range|relevance`; never refused | done |
//! | cnflag | none | `<N`, `>N`, `@<N`, `@>N`, `@cpa`, `@os_passed_cn*`, `@cn_passed_os*`, `@*crossed*` prefixes | done: range flags and the events `@cpa`, `@os_passed_cn[_port|_star]`, `@cn_passed_os[_port|_star]` (posted in running iterations, repeatable; `contact_state`); the `@*crossed*` tags are accepted and never posted, as the C++ at a2a9b716 |
//! | use_plat_model | false (V26: true) | `true` or `false` (any case; nothing else) | done: the platform-model engines (`CPXEnginePM`) work out the contact state, see below |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | BHV_WARNING | the contact is not in the ledger (`on_no_contact_ok`) | `<contact> x/y/heading/speed info not found` | done |
//! | BHV_ERROR | the same without `on_no_contact_ok`; no contact named | `... info not found`, `contact IDX not set.` | done |
//! | macros in flags | always | `$[CONTACT]`, `$[CN_NAME]`, `$[CNX]`, `$[CNY]`, `$[CNH]`, `$[CNV]`, `$[CN_VTYPE]`, `$[CN_GROUP]`, `$[CN_RANGE]`, `$[RANGE]` | done, with the relative-geometry macros `$[ROC]`, `$[OS_CN_REL_BNG]`, `$[CN_OS_REL_BNG]`, `$[BNG_RATE]`, `$[CN_SPD_IN_OS_POS]`, `$[OS_FORE_OF_CN]` ... `$[CN_STAR_OF_OS]` (`contact_state`) |
//! | VIEW_SEGLIST | `bearing_lines` given, each running iteration | ownship to contact, label `<us>_<name>`, edge colour by relevance or range, duration 100 | done |
//!
//! # `use_plat_model`
//!
//! With `use_plat_model = true` IvPContactBehavior swaps its two CPA engines (ownship to
//! contact, contact to ownship) for platform-model ones (`CPXEnginePM`), which evaluate the
//! CPA, passing and crossing along the path a platform model gives for a heading
//! ([`crate::colregs::plat_cpx`]). The contact state of each update
//! ([`crate::colregs::plat_cpx::contact_state`]) comes from them: the forward engine holds the
//! model its behaviour last handed it ([`ContactBase::engine_model`]), the reverse one never
//! gets one (the empty model: a ray from the origin). Who hands the forward engine the
//! helm's model, always after the update, so that the state reads the previous iteration's:
//! BHV_AvoidCollision on each running iteration with a positive relevance (its objective then
//! uses the iteration's model: [`crate::avoid_collision`]) and BHV_AvdColregsV26 on each
//! running iteration (V26 has the platform-model engines by default). CutRange, Trail,
//! Shadow, Convoy and AvdColregs V17/V19/V22 never do: their forward engine keeps the empty
//! model, and the C++'s AvdColregs functions evaluate their CPA along a ray from the origin
//! too, which coug keeps (CutRange and Trail build their CPA objective on an engine of their
//! own, unchanged).

use std::collections::BTreeSet;

use geometry::Polygon;

use crate::behavior::{Ctx, Out, ParamError, nav};
use crate::cpa::CpaEngine;
use crate::param::{is_number, moos_boolean};

/// A contact as the helm's ledger last had it (the fields IvPContactBehavior reads through
/// `getLedgerInfoDbl`/`getLedgerInfoStr`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ContactInfo {
    /// Local x, m.
    pub x_m: f64,
    /// Local y, m.
    pub y_m: f64,
    /// Heading, degrees.
    pub heading_deg: f64,
    /// Speed, m/s.
    pub speed_mps: f64,
    /// Depth, m.
    pub depth_m: f64,
    /// The report's time stamp (`utc`), s.
    pub utc: f64,
    /// Group.
    pub group: String,
    /// Vehicle type.
    pub vtype: String,
}

/// The contact filters of a contact behaviour (MOOS `ExFilterSet`): names, groups and types
/// are kept in lower case; regions are convex polygons.
#[derive(Debug, Clone)]
pub struct ContactFilter {
    match_names: BTreeSet<String>,
    ignore_names: BTreeSet<String>,
    match_groups: BTreeSet<String>,
    ignore_groups: BTreeSet<String>,
    match_types: BTreeSet<String>,
    ignore_types: BTreeSet<String>,
    match_regions: Vec<(Polygon, String)>,
    ignore_regions: Vec<(Polygon, String)>,
    /// A contact with no group (type, name) fails an ignore filter on groups (types, names).
    pub strict_ignore: bool,
}

impl Default for ContactFilter {
    fn default() -> Self {
        ContactFilter {
            match_names: BTreeSet::new(),
            ignore_names: BTreeSet::new(),
            match_groups: BTreeSet::new(),
            ignore_groups: BTreeSet::new(),
            match_types: BTreeSet::new(),
            ignore_types: BTreeSet::new(),
            match_regions: Vec::new(),
            ignore_regions: Vec::new(),
            strict_ignore: true,
        }
    }
}

/// Adds the comma list `value` (braces and case dropped) to `add`; false when a name is in
/// `other` (kept out, the others still added), as ExFilterSet.
fn add_names(add: &mut BTreeSet<String>, other: &BTreeSet<String>, value: &str) -> bool {
    let v = value.trim().to_ascii_lowercase();
    let v = v
        .strip_prefix('{')
        .and_then(|s| s.strip_suffix('}'))
        .unwrap_or(&v);
    let mut ok = true;
    for n in v.split(',') {
        let n = n.trim();
        if other.contains(n) {
            ok = false;
        } else {
            add.insert(n.to_string());
        }
    }
    ok
}

fn check(matches: &BTreeSet<String>, ignores: &BTreeSet<String>, strict: bool, v: &str) -> bool {
    if !matches.is_empty() && !matches.contains(v) {
        return false;
    }
    if !ignores.is_empty() && ((strict && v.is_empty()) || ignores.contains(v)) {
        return false;
    }
    true
}

impl ContactFilter {
    /// Takes one filter parameter; `None` when `param` is not one.
    pub fn set_param(&mut self, param: &str, value: &str) -> Option<bool> {
        let ok = match param {
            "match_name" => add_names(&mut self.match_names, &self.ignore_names, value),
            "ignore_name" => add_names(&mut self.ignore_names, &self.match_names, value),
            "match_group" => add_names(&mut self.match_groups, &self.ignore_groups, value),
            "ignore_group" => add_names(&mut self.ignore_groups, &self.match_groups, value),
            "match_type" => add_names(&mut self.match_types, &self.ignore_types, value),
            "ignore_type" => add_names(&mut self.ignore_types, &self.match_types, value),
            "match_region" | "ignore_region" => match value.parse::<Polygon>() {
                Ok(p) if p.is_convex() => {
                    let pts = pts_spec(&p);
                    if param == "match_region" {
                        self.match_regions.push((p, pts));
                    } else {
                        self.ignore_regions.push((p, pts));
                    }
                    true
                }
                _ => false,
            },
            "strict_ignore" => {
                match moos_types::text::set_boolean_on_string(self.strict_ignore, value) {
                    Some(b) => {
                        self.strict_ignore = b;
                        true
                    }
                    None => false,
                }
            }
            _ => return None,
        };
        Some(ok)
    }

    /// Whether a contact of group `group` passes the group filters (case as reported).
    pub fn check_group(&self, group: &str) -> bool {
        check(
            &self.match_groups,
            &self.ignore_groups,
            self.strict_ignore,
            group,
        )
    }

    /// Whether a contact of type `vtype` passes the type filters (case as reported).
    pub fn check_vtype(&self, vtype: &str) -> bool {
        check(
            &self.match_types,
            &self.ignore_types,
            self.strict_ignore,
            vtype,
        )
    }

    /// Whether a contact named `name` passes the name filters (MOOS `filterCheckVName`: the
    /// name in lower case).
    pub fn check_name(&self, name: &str) -> bool {
        check(
            &self.match_names,
            &self.ignore_names,
            self.strict_ignore,
            &name.to_ascii_lowercase(),
        )
    }

    /// Whether a contact passes every filter (MOOS `ExFilterSet::filterCheck`: group, name,
    /// type, then region).
    pub fn check_all(&self, name: &str, group: &str, vtype: &str, x: f64, y: f64) -> bool {
        self.check_group(group)
            && self.check_name(name)
            && self.check_vtype(vtype)
            && self.check_region(x, y)
    }

    /// Whether a contact at `(x, y)` passes the region filters.
    pub fn check_region(&self, x: f64, y: f64) -> bool {
        if !self.match_regions.is_empty()
            && !self.match_regions.iter().any(|(p, _)| p.contains(x, y))
        {
            return false;
        }
        !self.ignore_regions.iter().any(|(p, _)| p.contains(x, y))
    }

    /// The filters as the contact manager's alert request carries them (MOOS
    /// `ExFilterSet::getSummary`): `ignore_group=..`, `match_group=..`, names, types, regions,
    /// then `strict_ignore` when a group or type is ignored, joined by `", "`.
    pub fn summary(&self) -> String {
        let mut parts: Vec<String> = Vec::new();
        let sets = [
            ("ignore_group=", &self.ignore_groups),
            ("match_group=", &self.match_groups),
            ("ignore_name=", &self.ignore_names),
            ("match_name=", &self.match_names),
            ("ignore_type=", &self.ignore_types),
            ("match_type=", &self.match_types),
        ];
        for (k, set) in sets {
            parts.extend(set.iter().map(|v| format!("{k}{v}")));
        }
        parts.extend(
            self.ignore_regions
                .iter()
                .map(|(_, s)| format!("ignore_region={s}")),
        );
        parts.extend(
            self.match_regions
                .iter()
                .map(|(_, s)| format!("match_region={s}")),
        );
        if !self.ignore_types.is_empty() || !self.ignore_groups.is_empty() {
            parts.push(format!("strict_ignore={}", self.strict_ignore));
        }
        parts.join(", ")
    }
}

/// `pts={x,y:...}` of a polygon (MOOS `get_spec_pts`, two decimals, compacted).
fn pts_spec(p: &Polygon) -> String {
    let mut s = String::new();
    geometry::spec::write_points(&mut s, p.vertices(), 2);
    s
}

/// Accepted `cnflag` prefixes (MOOS `addContactFlag`).
const CNFLAG_EVENTS: [&str; 13] = [
    "@cpa",
    "@os_passed_cn_port",
    "@os_passed_cn_star",
    "@os_passed_cn",
    "@cn_passed_os_port",
    "@cn_passed_os_star",
    "@cn_passed_os",
    "@os_crossed_cn",
    "@os_crossed_cn_bow",
    "@os_crossed_cn_stern",
    "@cn_crossed_os",
    "@cn_crossed_os_bow",
    "@cn_crossed_os_stern",
];

fn cnflag_ok(s: &str) -> bool {
    let s = s.trim();
    let range = s
        .strip_prefix("@<")
        .or_else(|| s.strip_prefix("@>"))
        .or_else(|| s.strip_prefix('<'))
        .or_else(|| s.strip_prefix('>'));
    if let Some(rest) = range {
        let rng = rest.split(' ').next().unwrap_or("");
        return is_number(rng) && geometry::atof(rng) >= 0.0 && rest.contains('=');
    }
    CNFLAG_EVENTS.iter().any(|e| s.starts_with(e)) && s.contains('=')
}

/// [`crate::Behavior::apply_able_filter`] for a behaviour over `base`: the filter applied,
/// `expunge` completing it through `out`; false for a malformed message.
pub fn able_filter_hook(base: &mut ContactBase, msg: &str, kind: &str, out: &mut Out) -> bool {
    match base.apply_able_filter(msg, kind) {
        Ok(Some(AbleAction::Expunge)) => {
            out.complete();
            true
        }
        Ok(_) => true,
        Err(MalformedAbleFilter) => false,
    }
}

/// A `BHV_ABLE_FILTER` message a behaviour refuses (the helm warns `Unhandled
/// BHV_ABLE_FILTER`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MalformedAbleFilter;

/// What a `BHV_ABLE_FILTER` message asks (its `action`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AbleAction {
    /// `action=disable`: the behaviour stops producing functions.
    Disable,
    /// `action=enable`: it resumes.
    Enable,
    /// `action=expunge`: it completes.
    Expunge,
}

/// A `BHV_ABLE_FILTER` message as IvPContactBehavior's `applyAbleFilter` parses it:
/// `action=disable|enable|expunge` and at least one of `contact`, `bhv_type`, `vsource`,
/// comma-separated `field=value` pairs, keys and values case-folded, each field at most once.
/// Any other field (e.g. `gen_type`, which the C++ comment lists but its parser refuses) or
/// a repeated one makes the message malformed.
///
/// ```
/// use behaviors::contact::{AbleAction, AbleFilter};
/// let f = AbleFilter::parse("action=disable, contact=Ben, bhv_type=BHV_AvoidCollision").unwrap();
/// assert_eq!(f.action, AbleAction::Disable);
/// assert_eq!((f.contact.as_str(), f.bhv_type.as_str()), ("ben", "bhv_avoidcollision"));
/// assert!(AbleFilter::parse("action=disable,gen_type=safety").is_none());
/// assert!(AbleFilter::parse("action=able,contact=ben").is_none());
/// ```
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AbleFilter {
    /// The action.
    pub action: AbleAction,
    /// `contact` (lower case; empty: any).
    pub contact: String,
    /// `bhv_type` (lower case; empty: any).
    pub bhv_type: String,
    /// `vsource` (lower case; empty: any).
    pub vsource: String,
}

impl AbleFilter {
    /// Parses a message; `None` when malformed (the fields alone: whether one of `contact`,
    /// `bhv_type`, `vsource` is given is the caller's check, as in the C++).
    pub fn parse(msg: &str) -> Option<AbleFilter> {
        let (mut action, mut contact, mut bhv_type, mut vsource) = (
            None::<String>,
            None::<String>,
            None::<String>,
            None::<String>,
        );
        for piece in moos_types::text::parse_string(msg, ',') {
            let (k, v) = piece.split_once('=').unwrap_or((piece, ""));
            let (k, v) = (k.trim().to_ascii_lowercase(), v.trim().to_ascii_lowercase());
            // A field may come once; an empty value leaves it open to a second (as the C++
            // tests the value, not the presence).
            let slot = match k.as_str() {
                "action" => &mut action,
                "contact" => &mut contact,
                "bhv_type" => &mut bhv_type,
                "vsource" => &mut vsource,
                _ => return None,
            };
            if slot.as_deref().is_some_and(|s| !s.is_empty()) {
                return None;
            }
            *slot = Some(v);
        }
        let action = match action.as_deref() {
            Some("disable") => AbleAction::Disable,
            Some("enable") => AbleAction::Enable,
            Some("expunge") => AbleAction::Expunge,
            _ => return None,
        };
        Some(AbleFilter {
            action,
            contact: contact.unwrap_or_default(),
            bhv_type: bhv_type.unwrap_or_default(),
            vsource: vsource.unwrap_or_default(),
        })
    }
}

/// The state and parameters every contact behaviour shares (MOOS `IvPContactBehavior`).
#[derive(Debug, Clone)]
pub struct ContactBase {
    /// The contact's name (`contact`), as reported.
    pub contact: String,
    /// `on_no_contact_ok`: a missing contact is only a warning.
    pub on_no_contact_ok: bool,
    /// `extrapolate` (read; not applied, as in the C++ at a2a9b716).
    pub extrapolate: bool,
    /// `decay` start and end, s.
    pub decay: (f64, f64),
    /// `time_on_leg`, s: the horizon of the CPA evaluations.
    pub time_on_leg: f64,
    /// `post_per_contact_info`: post variables named after the contact.
    pub post_per_contact_info: bool,
    /// The contact filters.
    pub filter: ContactFilter,
    /// `exit_on_filter_vtype`.
    pub exit_on_filter_vtype: bool,
    /// `exit_on_filter_group`.
    pub exit_on_filter_group: bool,
    /// `exit_on_filter_region`.
    pub exit_on_filter_region: bool,
    /// `bearing_line_show`.
    pub bearing_line_show: bool,
    /// `bearing_line_label_show`.
    pub bearing_line_label_show: bool,
    /// What the bearing line's colour follows: `relevance` or `range`.
    pub bearing_line_info: String,
    /// Bearing line colours and their upper thresholds, in order.
    pub bearing_lines: Vec<(String, f64)>,
    /// The `cnflag`s: their tag (`<20`, `@cpa`, ...) and flag.
    pub cnflags: Vec<(String, crate::common::Flag)>,
    /// The range at the previous update (the C++ contact-state history), m.
    pub prev_range: Option<f64>,
    /// Ownship x, y, heading, speed at the last update.
    pub os: (f64, f64, f64, f64),
    /// The contact's x, y, heading, speed at the last update.
    pub cn: (f64, f64, f64, f64),
    /// The contact's group and type at the last update.
    pub cn_group: String,
    /// The contact's type at the last update.
    pub cn_vtype: String,
    /// Range to the contact at the last update, m.
    pub range: f64,
    /// The behaviour's relevance (its weight factor) at the last running iteration.
    pub relevance: f64,
    /// `can_disable` (IvPBehavior's `m_can_disable`, false): whether `BHV_ABLE_FILTER`
    /// messages act on the behaviour ([`ContactBase::apply_able_filter`]).
    pub can_disable: bool,
    /// Disabled by a `BHV_ABLE_FILTER` (MOOS `m_disabled`).
    pub disabled: bool,
    /// The relative geometry of this and the last iterations (event flags, macros).
    pub states: crate::contact_state::ContactStates,
    /// `use_plat_model`: the contact state comes from the platform-model engines (see the
    /// module docs).
    pub use_plat_model: bool,
    /// The model the forward platform-model engine holds (MOOS `m_cpa_engine_pm`'s
    /// `setPlatModel`), handed by the behaviour after its update; `None`: the empty model.
    pub engine_model: Option<std::sync::Arc<crate::plat_model::PlatModel>>,
}

impl ContactBase {
    /// The C++ defaults with `time_on_leg` (60 in IvPContactBehavior, 120 in AvoidCollision).
    pub fn new(time_on_leg: f64) -> Self {
        ContactBase {
            contact: String::new(),
            on_no_contact_ok: true,
            extrapolate: true,
            decay: (15.0, 30.0),
            time_on_leg,
            post_per_contact_info: false,
            filter: ContactFilter::default(),
            exit_on_filter_vtype: false,
            exit_on_filter_group: false,
            exit_on_filter_region: false,
            bearing_line_show: false,
            bearing_line_label_show: false,
            bearing_line_info: "relevance".into(),
            bearing_lines: Vec::new(),
            cnflags: Vec::new(),
            prev_range: None,
            os: (0.0, 0.0, 0.0, 0.0),
            cn: (0.0, 0.0, 0.0, 0.0),
            cn_group: String::new(),
            cn_vtype: String::new(),
            range: 0.0,
            relevance: 0.0,
            can_disable: false,
            disabled: false,
            states: Default::default(),
            use_plat_model: false,
            engine_model: None,
        }
    }

    /// Takes one of the shared parameters (`param` lower case); `None` when `param` is not
    /// one of them, so the behaviour tries its own.
    pub fn set_param(&mut self, param: &str, value: &str) -> Option<Result<(), ParamError>> {
        let bad = |expected| Err(ParamError::bad(param, value, expected));
        let boolean = |cur: bool| moos_boolean(param, value, cur);
        let r = match param {
            "contact" => {
                self.contact = value.to_string();
                Ok(())
            }
            "extrapolate" => boolean(self.extrapolate).map(|b| self.extrapolate = b),
            "post_per_contact_info" => {
                boolean(self.post_per_contact_info).map(|b| self.post_per_contact_info = b)
            }
            "on_no_contact_ok" => boolean(self.on_no_contact_ok).map(|b| self.on_no_contact_ok = b),
            "exit_on_filter_vtype" => {
                boolean(self.exit_on_filter_vtype).map(|b| self.exit_on_filter_vtype = b)
            }
            "exit_on_filter_group" => {
                boolean(self.exit_on_filter_group).map(|b| self.exit_on_filter_group = b)
            }
            "exit_on_filter_region" => {
                boolean(self.exit_on_filter_region).map(|b| self.exit_on_filter_region = b)
            }
            "bearing_line_show" => {
                boolean(self.bearing_line_show).map(|b| self.bearing_line_show = b)
            }
            "bearing_line_label_show" => {
                boolean(self.bearing_line_label_show).map(|b| self.bearing_line_label_show = b)
            }
            "decay" => {
                let (l, r) = value.split_once(',').unwrap_or((value, ""));
                let (l, r) = (l.trim(), r.trim());
                if is_number(l) && is_number(r) {
                    let (s, e) = (geometry::atof(l), geometry::atof(r));
                    if s >= 0.0 && s <= e {
                        self.decay = (s, e);
                        return Some(Ok(()));
                    }
                }
                bad("start,end with 0 <= start <= end")
            }
            "decay_end" => {
                if is_number(value) {
                    self.decay.1 = geometry::atof(value);
                    Ok(())
                } else {
                    bad("a number")
                }
            }
            "time_on_leg" => {
                if is_number(value) && geometry::atof(value) >= 0.0 {
                    self.time_on_leg = geometry::atof(value);
                    Ok(())
                } else {
                    bad("a number >= 0")
                }
            }
            "bearing_lines" | "bearing_line_config" => {
                self.set_bearing_lines(value);
                Ok(())
            }
            "cnflag" => {
                let v = value.trim();
                let (tag, rest) = v.split_once(char::is_whitespace).unwrap_or((v, ""));
                match crate::common::Flag::parse(rest) {
                    Some(f) if cnflag_ok(v) => {
                        self.cnflags.push((tag.to_string(), f));
                        Ok(())
                    }
                    _ => bad("<N, >N, @<N, @>N, @cpa, ... then VAR=VALUE"),
                }
            }
            "use_plat_model" => match value.to_ascii_lowercase().as_str() {
                "true" => {
                    self.use_plat_model = true;
                    Ok(())
                }
                "false" => {
                    self.use_plat_model = false;
                    Ok(())
                }
                _ => bad("true or false"),
            },
            _ => match self.filter.set_param(param, value) {
                Some(true) => Ok(()),
                Some(false) => bad("names not both matched and ignored, or a convex polygon"),
                None => return None,
            },
        };
        Some(r)
    }

    /// `bearing_lines = white:0, green:0.65, info:range`: colours with thresholds (a bad
    /// component ends the colour list, as the C++); never refused.
    fn set_bearing_lines(&mut self, value: &str) {
        self.bearing_line_show = false;
        let mut valid = true;
        for part in value.split(',') {
            let (l, r) = part.split_once(':').unwrap_or((part, ""));
            let (l, r) = (l.trim().to_ascii_lowercase(), r.trim());
            if l == "info" && (r == "range" || r == "relevance") {
                self.bearing_line_info = r.to_string();
            } else if geometry::color::is_color(&l) && is_number(r) && valid {
                self.bearing_lines.push((l, geometry::atof(r)));
                self.bearing_line_show = true;
            } else {
                valid = false;
            }
        }
    }

    /// Applies a `BHV_ABLE_FILTER` message to a behaviour of type `kind` (MOOS
    /// `IvPContactBehavior::applyAbleFilter`): without `can_disable` it is ignored (true, even
    /// when malformed); a malformed message is false; one whose `bhv_type`, `contact` and
    /// `vsource` (those given, case-folded) match this behaviour disables it, enables it, or,
    /// for `expunge`, completes it (`Some(Expunge)` returned in the `Ok`). Contacts carry no
    /// `vsource` in coug's ledger (an empty one), so a filter naming a `vsource` never
    /// applies.
    pub fn apply_able_filter(
        &mut self,
        msg: &str,
        kind: &str,
    ) -> Result<Option<AbleAction>, MalformedAbleFilter> {
        if !self.can_disable {
            return Ok(None);
        }
        let f = AbleFilter::parse(msg).ok_or(MalformedAbleFilter)?;
        if f.contact.is_empty() && f.bhv_type.is_empty() && f.vsource.is_empty() {
            return Err(MalformedAbleFilter);
        }
        let applies = (f.bhv_type.is_empty() || f.bhv_type == kind.to_ascii_lowercase())
            && (f.contact.is_empty() || f.contact == self.contact.to_ascii_lowercase())
            && f.vsource.is_empty();
        if !applies {
            return Ok(None);
        }
        match f.action {
            AbleAction::Expunge => return Ok(Some(AbleAction::Expunge)),
            AbleAction::Disable => self.disabled = true,
            AbleAction::Enable => self.disabled = false,
        }
        Ok(Some(f.action))
    }

    /// The contact the behaviour reasons about, if named.
    pub fn contact_name(&self) -> Option<&str> {
        (!self.contact.is_empty()).then_some(self.contact.as_str())
    }

    /// Reads ownship and the contact (MOOS `updatePlatformInfo`): false when the iteration
    /// cannot go on (no navigation, no contact), after posting the C++ warning or error.
    /// With no contact named and `on_no_contact_ok`, or contact `unset_ok`, it returns true
    /// with the contact fields unchanged.
    pub fn update(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        let info = ctx.info;
        let (Some(x), Some(y)) = (info.num("NAV_X"), info.num("NAV_Y")) else {
            out.error("No ownship X/Y info in info_buffer.");
            return false;
        };
        let Some((_, _, h, v)) = nav(info) else {
            out.error("No ownship heading info in info_buffer.");
            return false;
        };
        self.os = (x, y, h, v);
        if self.contact.is_empty() {
            if self.on_no_contact_ok {
                return true;
            }
            out.error("contact IDX not set.");
            return false;
        }
        if self.contact.eq_ignore_ascii_case("unset_ok") {
            return true;
        }
        let Some(c) = info.contact(&self.contact) else {
            let msg = format!("{} x/y/heading/speed info not found", self.contact);
            if self.on_no_contact_ok {
                out.warning(ctx.name, &msg);
            } else {
                out.error(msg);
            }
            return false;
        };
        self.cn = (c.x_m, c.y_m, c.heading_deg, c.speed_mps);
        self.cn_group.clone_from(&c.group);
        self.cn_vtype.clone_from(&c.vtype);
        self.prev_range = Some(self.range);
        self.range = (x - c.x_m).hypot(y - c.y_m);
        let state = if self.use_plat_model {
            crate::colregs::plat_cpx::contact_state(self.os, self.cn, self.engine_model.clone())
        } else {
            crate::contact_state::ContactState::new(self.os, self.cn)
        };
        self.states.record(state);
        true
    }

    /// Posts the range `cnflag`s that hold (MOOS `handleContactFlags`, called in running
    /// iterations after [`ContactBase::update`]): `<N` while the range is at most `N`, `>N`
    /// while at least `N`, `@<N` when it comes within `N`, `@>N` when it leaves; and the
    /// event tags when their event happened this iteration
    /// ([`crate::contact_state::ContactStates::event`]); repeatable.
    pub fn post_contact_flags(&self, out: &mut Out) {
        let prev = self.prev_range.unwrap_or(0.0);
        for (tag, flag) in &self.cnflags {
            let thresh = |t: &str| (is_number(t)).then(|| geometry::atof(t));
            let holds = if let Some(t) = tag.strip_prefix("@<").and_then(thresh) {
                self.range <= t && prev > t
            } else if let Some(t) = tag.strip_prefix("@>").and_then(thresh) {
                self.range >= t && prev < t
            } else if let Some(t) = tag.strip_prefix('<').and_then(thresh) {
                self.range <= t
            } else if let Some(t) = tag.strip_prefix('>').and_then(thresh) {
                self.range >= t
            } else {
                self.states.event(tag)
            };
            if holds {
                out.flag(flag, true);
            }
        }
    }

    /// Appends the value of a contact macro and returns true (MOOS `expandMacros` of
    /// IvPBehavior and IvPContactBehavior): `CONTACT`/`CN_NAME` (the name), `CNX`, `CNY`,
    /// `CNH`, `CNV` (3 decimals, compacted), `CN_VTYPE`, `CN_GROUP`, `CN_RANGE` and `RANGE`
    /// (1 decimal), and the relative-geometry macros
    /// ([`crate::contact_state::ContactStates::macro_value`]). False for any other name.
    pub fn macro_value(&self, name: &str, out: &mut String) -> bool {
        use moos_types::fmt::compact;
        match name {
            "CONTACT" | "CN_NAME" => out.push_str(&self.contact),
            "CNX" => compact(out, self.cn.0, 3),
            "CNY" => compact(out, self.cn.1, 3),
            "CNH" => compact(out, self.cn.2, 3),
            "CNV" => compact(out, self.cn.3, 3),
            "CN_VTYPE" => out.push_str(&self.cn_vtype),
            "CN_GROUP" => out.push_str(&self.cn_group),
            "CN_RANGE" | "RANGE" => compact(out, self.range, 1),
            _ => return self.states.macro_value(name, out),
        }
        true
    }

    /// The post mortem of a contact behaviour completing for `reason` (MOOS
    /// `IvPContactBehavior::setComplete`): the reason, then `rng=<range>#bng=<bearing from
    /// ownship to the contact>` (1 decimal), `#`-separated.
    ///
    /// ```
    /// let mut b = behaviors::contact::ContactBase::new(60.0);
    /// b.os = (0.0, 0.0, 0.0, 1.0);
    /// b.cn = (30.0, 40.0, 0.0, 1.0);
    /// b.range = 50.0;
    /// assert_eq!(b.post_mortem(""), "rng=50#bng=36.9");
    /// assert_eq!(b.post_mortem("filtera"), "filtera#rng=50#bng=36.9");
    /// ```
    pub fn post_mortem(&self, reason: &str) -> String {
        let mut s = reason.to_string();
        if !s.is_empty() {
            s.push('#');
        }
        s.push_str("rng=");
        moos_types::fmt::compact(&mut s, self.range, 1);
        s.push_str("#bng=");
        let bng = geometry::relative_angle(self.os.0, self.os.1, self.cn.0, self.cn.1);
        moos_types::fmt::compact(&mut s, bng, 1);
        s
    }

    /// Hands the forward platform-model engine the helm's model of this iteration (MOOS
    /// `m_cpa_engine_pm.setPlatModel(m_plat_model)`; no model yet: the empty one), for the
    /// next update's contact state.
    pub fn hand_model(&mut self, ctx: &Ctx<'_>) {
        self.engine_model = ctx
            .info
            .plat_model()
            .map(|m| std::sync::Arc::new(m.clone()));
    }

    /// The forward platform-model engine's CPA along the model's turns, for the objective of
    /// this iteration, when `use_plat_model` is on: the contact at its last update with
    /// `model` (`None`: the empty model).
    pub fn plat_cpx(
        &self,
        model: Option<std::sync::Arc<crate::plat_model::PlatModel>>,
    ) -> Option<crate::colregs::plat_cpx::PlatCpx> {
        self.use_plat_model.then(|| {
            crate::colregs::plat_cpx::PlatCpx::new(
                model.unwrap_or_else(crate::colregs::plat_cpx::empty_model),
                self.cn,
            )
        })
    }

    /// A CPA engine for the present geometry.
    pub fn cpa_engine(&self) -> CpaEngine {
        let (cnx, cny, cnh, cnv) = self.cn;
        CpaEngine::new(cnx, cny, cnh, cnv, self.os.0, self.os.1)
    }

    /// Whether the contact still passes the filters the behaviour exits on (MOOS
    /// `filterCheckHolds`).
    pub fn filter_holds(&self) -> bool {
        if self.exit_on_filter_vtype && !self.filter.check_vtype(&self.cn_vtype) {
            return false;
        }
        if self.exit_on_filter_group && !self.filter.check_group(&self.cn_group) {
            return false;
        }
        if self.exit_on_filter_region && !self.filter.check_region(self.cn.0, self.cn.1) {
            return false;
        }
        true
    }

    /// Posts the bearing line (MOOS `postViewableBearingLine`), or its erasure when not
    /// `active`; nothing unless bearing lines are configured.
    pub fn post_bearing_line(&self, ctx: &Ctx<'_>, out: &mut Out, active: bool) {
        if !self.bearing_line_show {
            return;
        }
        let index = if self.bearing_line_info == "range" {
            self.range
        } else {
            self.relevance
        };
        let color = self
            .bearing_lines
            .iter()
            .find(|(_, t)| index <= *t)
            .map_or("blank", |(c, _)| c.as_str());
        let mut a = geometry::Attributes::labeled(format!("{}_{}", ctx.ownship, ctx.name));
        a.label_color = Some(
            if self.bearing_line_label_show {
                "white"
            } else {
                "off"
            }
            .into(),
        );
        a.edge_color = Some(color.to_string());
        a.duration = Some(100.0);
        a.time = Some(ctx.info.now());
        a.active = active;
        let mut s = String::new();
        let pts = [
            geometry::Point::new(self.os.0, self.os.1),
            geometry::Point::new(self.cn.0, self.cn.1),
        ];
        geometry::spec::write_points(&mut s, &pts, 2);
        let base = 0;
        a.write_spec(&mut s, base);
        out.post("VIEW_SEGLIST", s);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filters_fold_case_and_refuse_a_name_both_matched_and_ignored() {
        let mut f = ContactFilter::default();
        assert_eq!(f.set_param("match_type", "{Kayak, ship}"), Some(true));
        assert_eq!(f.set_param("ignore_type", "ship"), Some(false));
        assert!(f.check_vtype("kayak") && f.check_vtype("ship"));
        assert!(
            !f.check_vtype("Kayak"),
            "the reported type is compared as is"
        );
        assert_eq!(f.set_param("ignore_group", "red"), Some(true));
        assert!(!f.check_group("red"));
        assert!(
            !f.check_group(""),
            "strict_ignore: no group fails an ignore filter"
        );
        f.set_param("strict_ignore", "false");
        assert!(f.check_group(""));
        assert_eq!(
            f.summary(),
            "ignore_group=red, match_type=kayak, match_type=ship, strict_ignore=false"
        );
        assert_eq!(
            f.set_param("match_region", "0,0:10,0:5,5:5,-5"),
            Some(false),
            "not convex"
        );
        assert_eq!(
            f.set_param("match_region", "0,0:10,0:10,10:0,10"),
            Some(true)
        );
        assert!(f.check_region(5.0, 5.0) && !f.check_region(20.0, 5.0));
        assert_eq!(f.set_param("colour", "x"), None);
    }

    #[test]
    fn able_filters_parse_as_ivp_contact_behavior() {
        let f = AbleFilter::parse(" Action = Enable ,VSOURCE= AIS").unwrap();
        assert_eq!(f.action, AbleAction::Enable);
        assert_eq!(f.vsource, "ais");
        assert!(f.contact.is_empty() && f.bhv_type.is_empty());
        assert_eq!(
            AbleFilter::parse("action=expunge,contact=ben,").map(|f| f.action),
            Some(AbleAction::Expunge),
            "a trailing comma adds no field"
        );
        // An empty value leaves the field open to a second mention (the C++ tests the value).
        assert_eq!(
            AbleFilter::parse("contact=,contact=ben,action=disable").map(|f| f.contact),
            Some("ben".to_string())
        );
        for bad in [
            "",
            "action=disable,,contact=ben",
            "action=disable,contact=ben,contact=ann",
            "action=disable,action=enable,contact=ben",
            "action=disable,gen_type=safety",
            "action=disable,obstacle_id=3",
            "action=able,contact=ben",
            "action,contact=ben",
            "contact=ben",
        ] {
            assert!(AbleFilter::parse(bad).is_none(), "{bad:?}");
        }

        // Applied to a behaviour of type BHV_AvdColregsV22 for contact Ben.
        let mut b = ContactBase::new(60.0);
        b.contact = "Ben".into();
        let kind = "BHV_AvdColregsV22";
        assert_eq!(
            b.apply_able_filter("action=disable,gen_type=x", kind),
            Ok(None)
        );
        assert!(!b.disabled, "without can_disable, ignored (even malformed)");
        b.can_disable = true;
        assert_eq!(
            b.apply_able_filter("action=disable,gen_type=x", kind),
            Err(MalformedAbleFilter)
        );
        assert_eq!(
            b.apply_able_filter("action=disable", kind),
            Err(MalformedAbleFilter)
        );
        for other in [
            "action=disable,contact=ann",
            "action=disable,contact=ben,bhv_type=BHV_AvoidCollision",
            "action=disable,vsource=ais",
        ] {
            assert_eq!(b.apply_able_filter(other, kind), Ok(None), "{other}");
            assert!(!b.disabled);
        }
        assert_eq!(
            b.apply_able_filter("action=disable,bhv_type=bhv_avdcolregsv22", kind),
            Ok(Some(AbleAction::Disable))
        );
        assert!(b.disabled);
        assert_eq!(
            b.apply_able_filter("action=expunge,contact=BEN", kind),
            Ok(Some(AbleAction::Expunge))
        );
        assert!(b.disabled, "expunge completes; it does not enable");
        assert_eq!(
            b.apply_able_filter("action=enable,contact=ben", kind),
            Ok(Some(AbleAction::Enable))
        );
        assert!(!b.disabled);
    }

    #[test]
    fn shared_parameters_are_checked_as_ivp_contact_behavior() {
        let mut b = ContactBase::new(60.0);
        assert!(b.set_param("decay", "10,20").unwrap().is_ok());
        assert_eq!(b.decay, (10.0, 20.0));
        assert!(b.set_param("decay", "20,10").unwrap().is_err());
        assert!(b.set_param("decay", "-1,10").unwrap().is_err());
        assert!(b.set_param("time_on_leg", "-5").unwrap().is_err());
        assert!(b.set_param("on_no_contact_ok", "maybe").unwrap().is_err());
        // use_plat_model: `true` or `false` in any case, nothing else (not even `yes`).
        assert!(b.set_param("use_plat_model", "TRUE").unwrap().is_ok());
        assert!(b.use_plat_model);
        for bad in ["yes", "1", "on", ""] {
            assert!(
                b.set_param("use_plat_model", bad).unwrap().is_err(),
                "{bad}"
            );
        }
        assert!(b.use_plat_model, "a refused value changes nothing");
        assert!(b.set_param("use_plat_model", "False").unwrap().is_ok());
        assert!(!b.use_plat_model);
        assert!(
            b.set_param("cnflag", "@cpa CPA_REACHED=true")
                .unwrap()
                .is_ok()
        );
        assert!(b.set_param("cnflag", "<20 CLOSE=true").unwrap().is_ok());
        assert!(b.set_param("cnflag", "<x CLOSE=true").unwrap().is_err());
        assert!(b.set_param("cnflag", "@sometime X=1").unwrap().is_err());
        assert!(
            b.set_param("bearing_lines", "white:0, green:0.65, info:range, bogus")
                .unwrap()
                .is_ok()
        );
        assert!(b.bearing_line_show);
        assert_eq!(b.bearing_lines.len(), 2);
        assert_eq!(b.bearing_line_info, "range");
        assert!(b.set_param("speed", "2").is_none());
    }
}
