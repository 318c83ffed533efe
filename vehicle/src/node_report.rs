//! Node reports, equivalent to MOOS-IvP's `pNodeReporter` (`NODE_REPORT_LOCAL`).
//!
//! The report is built field by field in the order of MOOS-IvP's `NodeRecord::getSpec`, each
//! field only when set, numbers formatted like `doubleToStringX` (fixed decimals, trailing
//! zeros dropped):
//!
//! `NAME,X,Y,SPD,HDG,DEP,LAT,LON,TYPE,COLOR,GROUP,MODE,MODE_AUX,ALLSTOP,LOAD_WARNING,ALTITUDE,
//! INDEX,THRUST_MODE_REVERSE,YAW,TIME,TRANSPARENCY,LENGTH,BEAM`
//!
//! (X/Y/SPD/HDG/DEP/ALTITUDE/TIME/LENGTH/BEAM/TRANSPARENCY 2 decimals, LAT/LON 8, YAW 7;
//! YAW is the heading as a mathematical angle in radians, present once `NAV_YAW` was seen).
//!
//! MODE is `NOHELM-EVER` when no helm message was ever received, `NOHELM-<secs>` when the
//! last one is older than `nohelm_threshold` (5 s), else the helm state (`DRIVE`, `PARK`,
//! ...), replaced by the `modes=` field of `IVPHELM_SUMMARY` when driving with modes.
//! `TRAJECTORY={..}` (from `NAV_TRAJECTORY`) follows BEAM. Mail is stamped with the app's
//! own time when it reads it (MOOS `m_curr_time`), not the writer's.
//!
//! Besides the node report: platform reports (`plat_report_input`), a second report from
//! alternative navigation (`alt_nav_prefix`), extrapolation pruning (`extrap_enabled`), the
//! mission-hash odometer, and PNODEREPORTER_PID in single-app mode.
//!
//! # Conformance with pNodeReporter (MOOS-IvP a2a9b716)
//!
//! A bad value or a setting coug does not implement is a config warning; the app runs on.
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | platform_type | vessel_type | text | unknown | any (length guessed from it, skyw/skywalker 2 m among them) | no | done |
//! | platform_color | | colour | none | MOOS `isColor`: a name of ColorParse's table (any case, `_` ignored, its `tomatao` spelling), grey/gray05..95, `hex:rr,gg,bb`, decimal triples, or black/empty/off/invisible (else unhandled warning) | PLATFORM_COLOR, NODE_COLOR_CHANGE (allow_color_change), each only with a MOOS colour, both to the alt-nav record too | done |
//! | platform_length | vessel_length | m | by type | number >= 0 | no | done |
//! | platform_beam | | m | none | number >= 0; `BEAM=` after LENGTH | no | done |
//! | platform_transparency | | number | none | any number (negative too) | NAV_TRANSP (the vehicle's record only; the alt-nav one keeps it or takes `<prefix>TRANSP`) | done |
//! | platform_group | group | text | none | any | NODE_GROUP_UPDATE | done |
//! | coord_policy_global | | bool | false | MOOS boolean | no | done |
//! | terse_reports | | bool | false | MOOS boolean | no | done |
//! | blackout_interval | | s | 0 | number >= 0; holds back no report: the first is always due and each report resets the blackout to a base of 0 that nothing sets | no | done |
//! | node_report_output | node_report_summary, node_report_var | var | NODE_REPORT_LOCAL | no white space | no | done |
//! | nohelm_threshold | | s | 5 | number > 0; NOHELM when the last helm message is strictly older, its age as `%.0f` | no | done |
//! | nav_grace_period | | s | 60 | number; <= 0 is none; within it a report needs only a position (X and Y, or a longitude: the C++'s `isSetLatLon` tests the longitude twice) | no | done |
//! | paused | | bool | false | MOOS boolean (`toggle` flips); no node, alt-nav or platform reports, PNR_POST_GAP or index counting while paused (extrapolation gaps still posted) | PNR_PAUSE (`setBooleanOnString`: any case, no blanks, `toggle`) | done |
//! | allow_color_change | | bool | false | MOOS boolean (`toggle` flips) | no | done |
//! | cross_fill_policy | crossfill_policy | enum | literal | literal, fill-empty, global, use-latest, local, global-terse (`_` read as `-`); fills before each report with the mission's origin | no | done |
//! | platform_aspect | | `key=value` | none | both sides non-empty, no second `=`; appended to the reports in key order | no | done |
//! | blackout_variance | | s | 0 | number >= 0; after each report the next blackout is `-v + 2k/100` for a whole `k` in `[0, v·100)`, clipped at 0 (coug's seeded generator stands for libc `rand()`; below 0.01 the C++ takes `rand() % 0`, coug draws 0) | no | done |
//! | rider | | `var=..,policy=always\|updated\|updated+S\|S,rfld=..,prec=..` | none | not a report field; policy, alphanumeric rfld, prec >= 0 (max 10); one per variable; subscribed | yes (mail) | done |
//! | plat_report_input | plat_report_var, platform_variable | `VAR[, gap=S][, alias=NAME]` | none | always taken; the last piece without `=` names it; `gap` any case, C `atof`, below 0 is 0; `alias` lower case only, no white space; a name with white space or a repeat ignored; subscribed | no | done |
//! | plat_report_output | | var | PLATFORM_REPORT_LOCAL | no white space | no | done |
//! | platform_vsource | vsource | text | none | any; `VSOURCE=` after GROUP | no | done |
//! | alt_nav_prefix, alt_nav_name, alt_nav_group | | text | none, `_GT`, none | prefix any (`_` appended; X, Y, LAT, LONG, SPEED, HEADING, YAW, DEPTH, TRANSP subscribed, ALTITUDE only through the `NAV_*` wildcard), name any (`_X` appended to the vehicle's), group no white space | no | done |
//! | extrap_enabled, extrap_pos_thresh, extrap_hdg_thresh, extrap_max_gap | | bool, m, deg, s | false, 0.25, 1, 5 | boolean, numbers >= 0; a report is skipped when both gaps are strictly under the thresholds, compared only while the last report posted is under `extrap_max_gap` old | no | done |
//! | json_report | | `true` or a var | none (`false`: none) | no white space; `true`: the report variable carries JSON; a var: JSON there beside the usual report | no | done |
//! | report_cog | | bool | false | MOOS boolean; `COG=` (bearing between iterations) from the next report on | no | done |
//! | hdg_error | | degrees | 0 | number > 0; added to the reported heading | no | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | NODE_REPORT_LOCAL (node_report_output) | each iteration (blackout permitting) | NodeRecord spec (above) | done |
//! | PNR_POST_GAP | each report | seconds since the last | done |
//! | `<output>_FIRST` | the first report | as the report | done |
//! | JSON reports (and `<json var>_FIRST`) | with json_report | `{"NAME":"abe","X":1.5,...}` (MOOS `cspToJson`) | done |
//! | PLATFORM_REPORT_LOCAL (plat_report_output) | each iteration (with or without a node report, not while paused), with the inputs received (at a time other than 0) after their last report and more than their gap after it | `platform=<name>,utc_time=<5 dp>,VAR=value,...` (a number as `dstringCompact(doubleToString(v, 8))`, so `-0` stays) | done |
//! | PNR_EXTRAP_POS_GAP, PNR_EXTRAP_HDG_GAP | extrap_enabled, from the second report on, while the last report posted is under extrap_max_gap old (also when paused or pruned) | metres from the position extrapolated (speed for at most 5 s, none within 0.05 s), degrees (MOOS `angleDiff`) | done |
//! | alternative-nav report in node_report_output | with alt_nav_prefix, after the node report, while an alt-nav variable is under 5 s old | the start-up copy of the record (type, colour, length, beam, transparency, vsource, aspects) named `<name>_GT` with its own navigation and group (`alt_nav_group`, then NODE_GROUP_UPDATE), colour updates, the helm's mode and all-stop, the index after the report, riders asked again; no MODE_AUX, LOAD_WARNING, THRUST_MODE_REVERSE, COG, TRAJECTORY; no `_FIRST`, no JSON | done |
//! | PNR_MHASH | after MISSION_HASH, when the largest distance from the start grows by 2 % and 1 m | `mhash=<hash>,ext=<m, 1 decimal>` | done |
//! | PNODEREPORTER_PID | start-up, in OnStartUp (single-app mode; in `coug run` the apps share one process and the log stays reproducible) | process id, a double (`Notify(.., getpid())`) | done |
//! | APPCAST, APP_LOG, PNODEREPORTER_ITER_GAP/_ITER_LEN (AppCastingMOOSApp) | on request, a new config warning, the first iteration; load casts | the AppCast string; the body is `buildReport`'s ([`NodeReporter::appcast_body`]); the run warning `Waiting for NAV_X/Y or NAV_LAT/LONG` and its retraction | done (`runtime::appcasting`, `runtime/src/vehicle.rs` tests) |
//! | ALLSTOP field (all-stop sources) | each report | `IVPHELM_ALLSTOP` as received (`unknown` before); `n/a` once `IVPHELM_STATE` begins with MALCONFIG; the first state ending in `+` (a standby helm stepping in) clears it and the modes, so no ALLSTOP field until the next `IVPHELM_ALLSTOP`. No other all-stop source exists at a2a9b716 (`AUX_MODE` is the MODE_AUX field only) | done |
//! | riders' mail | | every variable but AUX_MODE, PNR_PAUSE, LOAD_WARNING, NODE_GROUP_UPDATE and the IVPHELM_ ones (which the C++ handles before it); with hdg_error the riders are asked twice per report (the first report is discarded), so updated and periodic values are spent | done |
//! | subscriptions | start-up | `NAV_*` (wildcard) and NAV_X/Y/LAT/LONG/SPEED/HEADING/YAW/DEPTH/TRAJECTORY/TRANSP, the alt-nav variables, NODE_COLOR_CHANGE, IVPHELM_SUMMARY/STATE/ALLSTOP, AUX_MODE, LOAD_WARNING, THRUST_MODE_REVERSE, NODE_GROUP_UPDATE, PNR_PAUSE, PLATFORM_COLOR, MISSION_HASH, the riders, the platform inputs | done |
//!
//! Two starting values differ from the C++ only at MOOS times under 5 s, which never occur
//! (MOOS time is Unix time; coug's lockstep runs start in 2026): the C++ takes "no helm
//! message yet" as one at time −1 and "no alt-nav variable yet" as one at time 0, and does
//! not count a report posted at time 0 as a last report; coug takes them as never.

use moos_types::ByteString;
use std::fmt::Write as _;

use crate::angle::{angle360, heading_to_radians};
use crate::config::{ConfigError, Param, apply_params, strict};
use crate::moos::{Posting, ValueRef};

const APP: &str = "pNodeReporter";

/// `pNodeReporter` configuration. `Default` gives the MOOS defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct NodeReportConfig {
    /// `platform_type` / `vessel_type` (`unknown`).
    pub platform_type: String,
    /// `platform_color`.
    pub platform_color: Option<String>,
    /// `platform_length` / `vessel_length`, m; 0 = guess from the type.
    pub platform_length: f64,
    /// `platform_beam`, m.
    pub platform_beam: Option<f64>,
    /// `platform_group` / `group`.
    pub group: Option<String>,
    /// `platform_transparency`.
    pub transparency: Option<f64>,
    /// `coord_policy_global`: no X/Y in reports.
    pub coord_policy_global: bool,
    /// `terse_reports`: no DEP, LAT/LON, YAW.
    pub terse_reports: bool,
    /// `blackout_interval`, s.
    pub blackout_interval: f64,
    /// `node_report_output` (`NODE_REPORT_LOCAL`).
    pub node_report_output: String,
    /// `nohelm_threshold`, s (5).
    pub nohelm_threshold: f64,
    /// `nav_grace_period`, s (60).
    pub nav_grace_period: f64,
    /// `paused`.
    pub paused: bool,
    /// `allow_color_change`: honour `NODE_COLOR_CHANGE`.
    pub allow_color_change: bool,
    /// `REPORT_COG`: add the course over ground (bearing from the previous iteration's
    /// position) as `COG=` to the reports.
    pub report_cog: bool,
    /// `HDG_ERROR`: degrees added to the reported heading (for testing how heading errors are
    /// handled downstream); 0 = none.
    pub hdg_error_deg: f64,
    /// `PLATFORM_VSOURCE` / `VSOURCE`: the `VSOURCE=` field (where the position comes from).
    pub vsource: String,
    /// `PLATFORM_ASPECT = key=value` lines: extra `key=value` fields at the end of each
    /// report, in key order.
    pub aspects: std::collections::BTreeMap<String, String>,
    /// `RIDER` lines: MOOS variables whose latest values ride along in the reports.
    pub riders: Vec<RiderConfig>,
    /// `JSON_REPORT`: empty (reports as `key=value`), `true` (the report variable carries
    /// JSON instead) or a variable that receives the JSON beside the usual report.
    pub json_report: String,
    /// `CROSS_FILL_POLICY`: how local and global positions fill each other in the reports.
    pub crossfill: CrossFill,
    /// `blackout_variance`, s: after each report the next blackout is drawn uniformly from
    /// [−variance, +variance) around 0 (see [`NodeReporter::iterate`]).
    pub blackout_variance: f64,
    /// `plat_report_input` lines: variables whose changes go into the platform report.
    pub plat_vars: Vec<PlatVar>,
    /// `plat_report_output` (`PLATFORM_REPORT_LOCAL`).
    pub plat_report_output: String,
    /// `alt_nav_prefix` (e.g. `NAV_GT_`; empty: off): a second report of the same vehicle
    /// from these variables, `_` appended when missing.
    pub alt_nav_prefix: String,
    /// `alt_nav_name` (`_GT`): the second report's name, after the vehicle's when it starts
    /// with `_`.
    pub alt_nav_name: String,
    /// `alt_nav_group`: the second report's group (default: the vehicle's).
    pub alt_nav_group: Option<String>,
    /// `extrap_enabled`: skip a report a receiver could extrapolate from the last one.
    pub extrap_enabled: bool,
    /// `extrap_pos_thresh`, m (0.25).
    pub extrap_pos_thresh_m: f64,
    /// `extrap_hdg_thresh`, degrees (1).
    pub extrap_hdg_thresh_deg: f64,
    /// `extrap_max_gap`, s (5): no pruning once the last report is this old.
    pub extrap_max_gap_s: f64,
}

/// One `plat_report_input = VAR[, gap=S][, alias=NAME]` line.
#[derive(Debug, Clone, PartialEq)]
pub struct PlatVar {
    /// The MOOS variable.
    pub var: String,
    /// The name it is reported under (default: the variable).
    pub alias: Option<String>,
    /// Least time between two reports of it, s (0).
    pub gap_s: f64,
}

impl PlatVar {
    /// Reads a line as MOOS `addPlatformVar`: the piece without `=` names the variable,
    /// `gap=` (C `atof`, at least 0) and `alias=` (case as written, no white space) are
    /// options. `None` for a variable name with white space or none at all.
    ///
    /// ```
    /// let v = vehicle::node_report::PlatVar::parse("BATT_V, gap=2, alias=BV").unwrap();
    /// assert_eq!((v.var.as_str(), v.alias.as_deref(), v.gap_s), ("BATT_V", Some("BV"), 2.0));
    /// ```
    pub fn parse(spec: &str) -> Option<PlatVar> {
        let mut v = PlatVar {
            var: String::new(),
            alias: None,
            gap_s: 0.0,
        };
        for piece in spec.split(',') {
            let (left, right) = piece.split_once('=').unwrap_or((piece, ""));
            let (left, right) = (left.trim(), right.trim());
            if right.is_empty() {
                v.var = left.to_string();
            } else if left.eq_ignore_ascii_case("gap") {
                v.gap_s = crate::sim::atof(right).max(0.0);
            } else if left == "alias" && !right.contains(char::is_whitespace) {
                v.alias = Some(right.to_string());
            }
        }
        (!v.var.is_empty() && !v.var.contains(char::is_whitespace)).then_some(v)
    }
}

impl Default for NodeReportConfig {
    fn default() -> Self {
        NodeReportConfig {
            platform_type: "unknown".to_string(),
            platform_color: None,
            platform_length: 0.0,
            platform_beam: None,
            group: None,
            transparency: None,
            coord_policy_global: false,
            terse_reports: false,
            blackout_interval: 0.0,
            node_report_output: "NODE_REPORT_LOCAL".to_string(),
            nohelm_threshold: 5.0,
            nav_grace_period: 60.0,
            paused: false,
            allow_color_change: false,
            report_cog: false,
            hdg_error_deg: 0.0,
            vsource: String::new(),
            aspects: std::collections::BTreeMap::new(),
            riders: Vec::new(),
            json_report: String::new(),
            crossfill: CrossFill::Literal,
            blackout_variance: 0.0,
            plat_vars: Vec::new(),
            plat_report_output: "PLATFORM_REPORT_LOCAL".to_string(),
            alt_nav_prefix: String::new(),
            alt_nav_name: "_GT".to_string(),
            alt_nav_group: None,
            extrap_enabled: false,
            extrap_pos_thresh_m: 0.25,
            extrap_hdg_thresh_deg: 1.0,
            extrap_max_gap_s: 5.0,
        }
    }
}

/// The length pNodeReporter assumes for a platform type when none is configured.
pub fn default_length(platform_type: &str) -> Option<f64> {
    Some(match platform_type.to_ascii_lowercase().as_str() {
        "kayak" | "mokai" | "auv" | "uuv" => 4.0,
        "skyw" | "skywalker" => 2.0,
        "cray" | "crayx" | "bcray" | "bcrayx" | "glider" | "heron" | "swimmer" | "buoy" => 3.0,
        "ship" => 8.0,
        "longship" => 15.0,
        "usv" | "smr" => 6.0,
        _ => return None,
    })
}

impl NodeReportConfig {
    /// Strict construction from ProcessConfig pairs.
    pub fn from_params<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<Self, ConfigError> {
        strict(Self::from_params_lenient(params))
    }

    /// As [`NodeReportConfig::from_params`], with unknown keys returned as non-fatal errors.
    pub fn from_params_lenient<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<(Self, Vec<ConfigError>), ConfigError> {
        let mut cfg = NodeReportConfig::default();
        let unknown = apply_params(APP, &mut cfg, params, Self::apply_one)?;
        Ok((cfg, unknown))
    }

    fn apply_one(&mut self, key: &str, p: Param<'_>) -> Result<bool, ConfigError> {
        match key {
            // Any text, as the C++ (`setType(value)`).
            "platform_type" | "vessel_type" => self.platform_type = p.value.to_string(),
            "platform_color" => {
                if !geometry::color::is_color(p.value) {
                    return Err(p.bad("a MOOS colour"));
                }
                self.platform_color = Some(p.value.to_string());
            }
            "platform_length" | "vessel_length" => self.platform_length = p.non_neg()?,
            "platform_beam" => self.platform_beam = Some(p.non_neg()?),
            "platform_group" | "group" => self.group = Some(p.value.to_string()),
            "platform_transparency" => self.transparency = Some(p.f64()?),
            "coord_policy_global" => {
                self.coord_policy_global = p.bool_or_toggle(self.coord_policy_global)?
            }
            "terse_reports" => self.terse_reports = p.bool_or_toggle(self.terse_reports)?,
            "blackout_interval" => self.blackout_interval = p.non_neg()?,
            "node_report_output" | "node_report_summary" | "node_report_var" => {
                self.node_report_output = p.word()?
            }
            "nohelm_threshold" => self.nohelm_threshold = p.pos()?,
            "nav_grace_period" => self.nav_grace_period = p.f64()?,
            "paused" => self.paused = p.bool_or_toggle(self.paused)?,
            "allow_color_change" => {
                self.allow_color_change = p.bool_or_toggle(self.allow_color_change)?
            }
            "report_cog" => self.report_cog = p.bool_or_toggle(self.report_cog)?,
            "json_report" => {
                let v = p.word()?;
                // As the C++: exactly `false` means none.
                self.json_report = if v == "false" { String::new() } else { v };
            }
            "platform_vsource" | "vsource" => self.vsource = p.value.to_string(),
            "platform_aspect" => {
                let (k, v) = p.value.split_once('=').unwrap_or((p.value, ""));
                let (k, v) = (k.trim(), v.trim());
                if k.is_empty() || v.is_empty() || v.contains('=') {
                    return Err(p.bad("key=value"));
                }
                self.aspects.insert(k.to_string(), v.to_string());
            }
            "hdg_error" => self.hdg_error_deg = p.pos()?,
            "crossfill_policy" | "cross_fill_policy" => {
                let v = p.value.to_ascii_lowercase().replace('_', "-");
                if ![
                    "literal",
                    "fill-empty",
                    "global",
                    "use-latest",
                    "local",
                    "global-terse",
                ]
                .contains(&v.as_str())
                {
                    return Err(
                        p.bad("literal, fill-empty, global, use-latest, local or global-terse")
                    );
                }
                self.crossfill = match v.as_str() {
                    "fill-empty" => CrossFill::FillEmpty,
                    "global" => CrossFill::Global,
                    "global-terse" => CrossFill::GlobalTerse,
                    "use-latest" => CrossFill::UseLatest,
                    "local" => CrossFill::Local,
                    _ => CrossFill::Literal,
                };
            }
            // pNodeReporter settings coug does not implement yet: a config warning each (the
            // app runs on), never a silent difference.
            "rider" => {
                let r = RiderConfig::parse(p.value).ok_or_else(|| {
                    p.bad("var=VAR[, policy=always|updated|updated+S|S][, rfld=F][, prec=N]")
                })?;
                if self.riders.iter().any(|x| x.var == r.var) {
                    return Err(p.bad("a rider variable given once"));
                }
                self.riders.push(r);
            }
            "blackout_variance" => self.blackout_variance = p.non_neg()?,
            // Always taken (MOOS ignores a bad or repeated line without a word).
            "plat_report_input" | "plat_report_var" | "platform_variable" => {
                if let Some(v) = PlatVar::parse(p.value)
                    && !self.plat_vars.iter().any(|x| x.var == v.var)
                {
                    self.plat_vars.push(v);
                }
            }
            "plat_report_output" => self.plat_report_output = p.word()?,
            "alt_nav_prefix" => {
                self.alt_nav_prefix = p.value.to_string();
                if !self.alt_nav_prefix.is_empty() && !self.alt_nav_prefix.ends_with('_') {
                    self.alt_nav_prefix.push('_');
                }
            }
            "alt_nav_name" => self.alt_nav_name = p.value.to_string(),
            "alt_nav_group" => self.alt_nav_group = Some(p.word()?),
            "extrap_enabled" => self.extrap_enabled = p.bool_or_toggle(self.extrap_enabled)?,
            "extrap_pos_thresh" => self.extrap_pos_thresh_m = p.non_neg()?,
            "extrap_hdg_thresh" => self.extrap_hdg_thresh_deg = p.non_neg()?,
            "extrap_max_gap" => self.extrap_max_gap_s = p.non_neg()?,
            _ => return Ok(false),
        }
        Ok(true)
    }
}

/// How a report's local (X/Y) and global (LAT/LON) positions fill each other (MOOS
/// `crossFillCoords`), using the mission's LatOrigin/LongOrigin.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CrossFill {
    /// Each as received (default).
    Literal,
    /// X/Y from LAT/LON when both are known (`global`).
    Global,
    /// As [`CrossFill::Global`] (`global-terse`).
    GlobalTerse,
    /// LAT/LON from X/Y when both are known.
    Local,
    /// Fill the pair never received from the other.
    FillEmpty,
    /// Fill the staler pair from the fresher one.
    UseLatest,
}

impl CrossFill {
    /// The policy's name as configured (lower case, `-` for `_`).
    pub fn as_str(self) -> &'static str {
        match self {
            CrossFill::Literal => "literal",
            CrossFill::Global => "global",
            CrossFill::GlobalTerse => "global-terse",
            CrossFill::Local => "local",
            CrossFill::FillEmpty => "fill-empty",
            CrossFill::UseLatest => "use-latest",
        }
    }
}

/// When a rider's value goes into a report (MOOS `NodeRider` policies).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RiderPolicy {
    /// In every report (once a value is known).
    Always,
    /// In the reports that follow an update; with a period > 0 also repeated every that
    /// many seconds (then under the variable's own name).
    Updated {
        /// Repeat period, s (−1 or 0: never).
        period_s: f64,
    },
    /// Every that many seconds.
    Every {
        /// Period, s.
        period_s: f64,
    },
}

/// One `rider = var=..., policy=..., rfld=..., prec=...` line.
#[derive(Debug, Clone, PartialEq)]
pub struct RiderConfig {
    /// The MOOS variable (not a report field name such as `X` or `MODE`).
    pub var: String,
    /// When it rides.
    pub policy: RiderPolicy,
    /// The report field name (default: the variable).
    pub field: String,
    /// Decimals for a number (default 4, at most 10).
    pub precision: usize,
}

impl RiderConfig {
    /// Parses a rider line as MOOS `NodeRiderSet::addNodeRider`; `None` when any part is bad.
    ///
    /// ```
    /// use vehicle::node_report::{RiderConfig, RiderPolicy};
    /// let r = RiderConfig::parse("var=LEG_ID, policy=updated+10, rfld=LEG").unwrap();
    /// assert_eq!(r.policy, RiderPolicy::Updated { period_s: 10.0 });
    /// assert!(RiderConfig::parse("var=X").is_none(), "a report field");
    /// ```
    pub fn parse(spec: &str) -> Option<RiderConfig> {
        const RESERVED: &[&str] = &[
            "NAME", "X", "Y", "SPD", "HDG", "DEP", "LAT", "LON", "TYPE", "COLOR", "MODE",
            "ALLSTOP", "INDEX", "YAW", "TIME", "LENGTH",
        ];
        let mut r = RiderConfig {
            var: String::new(),
            policy: RiderPolicy::Always,
            field: String::new(),
            precision: 4,
        };
        let number = |v: &str| crate::config::parse_number(v).filter(|d| *d >= 0.0);
        for part in spec.split(',') {
            let (k, v) = part.split_once('=').unwrap_or((part, ""));
            let (k, v) = (k.trim(), v.trim());
            match k {
                "var" if !v.contains(char::is_whitespace) && !RESERVED.contains(&v) => {
                    r.var = v.to_string()
                }
                "policy" => {
                    r.policy = match v {
                        "always" => RiderPolicy::Always,
                        "updated" => RiderPolicy::Updated { period_s: -1.0 },
                        _ => match v.strip_prefix("updated+") {
                            Some(f) => RiderPolicy::Updated {
                                period_s: number(f)?,
                            },
                            None => RiderPolicy::Every {
                                period_s: number(v)?,
                            },
                        },
                    }
                }
                "rfld" if !v.is_empty() && v.chars().all(|c| c.is_ascii_alphanumeric()) => {
                    r.field = v.to_string()
                }
                "prec" => {
                    // C `atoi`: the leading integer, 0 when there is none; negative is bad.
                    let digits: String = v
                        .char_indices()
                        .take_while(|(i, c)| c.is_ascii_digit() || (*i == 0 && *c == '-'))
                        .map(|(_, c)| c)
                        .collect();
                    let n: i64 = digits.parse().unwrap_or(0);
                    r.precision = usize::try_from(n).ok()?.min(10);
                }
                _ => return None,
            }
        }
        (!r.var.is_empty()).then_some(r)
    }
}

impl RiderConfig {
    /// The rider as the appcast lists it (MOOS `NodeRider::getSpec`):
    /// `var=V, policy=always|updated|updated+S|S[, rfld=F]`, periods with at most 2 decimals.
    pub fn spec(&self) -> String {
        let mut s = format!("var={}, policy=", self.var);
        match self.policy {
            RiderPolicy::Always => s.push_str("always"),
            RiderPolicy::Updated { period_s } if period_s > 0.0 => {
                s.push_str("updated+");
                moos_types::fmt::compact(&mut s, period_s, 2);
            }
            RiderPolicy::Updated { .. } => s.push_str("updated"),
            RiderPolicy::Every { period_s } => moos_types::fmt::compact(&mut s, period_s, 2),
        }
        if !self.field.is_empty() {
            s.push_str(", rfld=");
            s.push_str(&self.field);
        }
        s
    }
}

/// A rider's latest value and freshness.
#[derive(Debug, Clone, Default)]
struct RiderState {
    value: String,
    last_time: f64,
    fresh: bool,
}

/// How far the report `cur` at `now` is from what a receiver extrapolates from `last`,
/// posted at `t` (MOOS `extrapolateRecord` with a 5 s decay, `rangeBetweenRecords`,
/// `angleDiff`): (distance in m, heading difference in degrees). Unset values count as 0.
fn extrapolation_gap(last: &NavRecord, t: f64, cur: &NavRecord, now: f64) -> (f64, f64) {
    const DECAY_S: f64 = 5.0;
    let (lx, ly) = (last.x.unwrap_or(0.0), last.y.unwrap_or(0.0));
    let (lh, ls) = (last.heading.unwrap_or(0.0), last.speed.unwrap_or(0.0));
    let (ex, ey) = if now <= 0.0 || now <= t + 0.05 {
        (lx, ly)
    } else {
        // With the decay starting and ending at 5 s the speed holds for 5 s, then stops.
        let dist = ls * (now - t).min(DECAY_S);
        let p = geometry::project_point(lx, ly, lh, dist);
        (p.x, p.y)
    };
    let d = (cur.x.unwrap_or(0.0) - ex).hypot(cur.y.unwrap_or(0.0) - ey);
    // MOOS `angleDiff`: 360 minus the difference from 180 on.
    let (h1, h2) = (angle360(cur.heading.unwrap_or(0.0)), angle360(lh));
    let mut dh = if h2 > h1 { h2 - h1 } else { h1 - h2 };
    if dh >= 180.0 {
        dh = 360.0 - dh;
    }
    (d, dh)
}

/// Fills X/Y or LAT/LON of `n` as `policy` says (MOOS `crossFillCoords`); `xy_time` and
/// `latlon_time` say which pair arrived last.
fn cross_fill(
    policy: CrossFill,
    grid: Option<&crate::geodesy::LocalGrid>,
    n: &mut NavRecord,
    xy_time: f64,
    latlon_time: f64,
) {
    let Some(grid) = grid else {
        return;
    };
    let (xy, ll) = (n.x.zip(n.y), n.lat.zip(n.lon));
    let to_local = |(lat, lon): (f64, f64)| grid.to_local(lat, lon).ok();
    let to_global = |(x, y): (f64, f64)| grid.to_latlon(x, y).ok();
    let fill = match policy {
        CrossFill::Literal => None,
        CrossFill::Global | CrossFill::GlobalTerse => ll.and_then(to_local).map(|p| (true, p)),
        CrossFill::Local => xy.and_then(to_global).map(|p| (false, p)),
        CrossFill::FillEmpty => match (n.x.is_none() && n.y.is_none(), ll, xy) {
            (true, Some(g), _) => to_local(g).map(|p| (true, p)),
            (false, _, Some(l)) if n.lat.is_none() && n.lon.is_none() => {
                to_global(l).map(|p| (false, p))
            }
            _ => None,
        },
        CrossFill::UseLatest if xy_time == latlon_time => None,
        CrossFill::UseLatest if xy_time < latlon_time => ll.and_then(to_local).map(|p| (true, p)),
        CrossFill::UseLatest => xy.and_then(to_global).map(|p| (false, p)),
    };
    match fill {
        Some((true, (x, y))) => (n.x, n.y) = (Some(x), Some(y)),
        Some((false, (lat, lon))) => (n.lat, n.lon) = (Some(lat), Some(lon)),
        None => {}
    }
}

/// Ownship navigation as last received (`NAV_*`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NavRecord {
    /// NAV_X.
    pub x: Option<f64>,
    /// NAV_Y.
    pub y: Option<f64>,
    /// NAV_LAT.
    pub lat: Option<f64>,
    /// NAV_LONG.
    pub lon: Option<f64>,
    /// NAV_SPEED.
    pub speed: Option<f64>,
    /// NAV_HEADING (wrapped to 0..360).
    pub heading: Option<f64>,
    /// NAV_DEPTH.
    pub depth: Option<f64>,
    /// NAV_ALTITUDE.
    pub altitude: Option<f64>,
    /// True once NAV_YAW was received.
    pub yaw_seen: bool,
}

impl NavRecord {
    /// A report can be posted: heading, speed, and x/y or lat/lon known.
    pub fn valid(&self) -> bool {
        self.speed.is_some()
            && self.heading.is_some()
            && ((self.x.is_some() && self.y.is_some())
                || (self.lat.is_some() && self.lon.is_some()))
    }
}

/// What the helm last said (`IVPHELM_STATE`, `IVPHELM_SUMMARY`, `IVPHELM_ALLSTOP`).
#[derive(Debug, Clone, PartialEq)]
pub struct HelmInfo {
    /// Time of the last helm message.
    pub last_msg: Option<f64>,
    /// `DRIVE`, `PARK`, `MALCONFIG`, `DISABLED` (initially `unknown`).
    pub status_primary: String,
    /// `DRIVE+`, `PARK+`, `MALCONFIG+`, `STANDBY` from a standby helm.
    pub status_standby: String,
    /// `modes=` of the summary (`none`).
    pub modes: String,
    /// Last `IVPHELM_ALLSTOP` (`unknown`; `n/a` once the helm is MALCONFIG; empty, so no
    /// ALLSTOP field, after a standby helm first stepped in until the next one).
    pub allstop: String,
    /// A standby helm has stepped in (an `IVPHELM_STATE` ending in `+` was seen): the modes
    /// and all-stop are cleared only the first time.
    pub switch_noted: bool,
}

impl Default for HelmInfo {
    fn default() -> Self {
        HelmInfo {
            last_msg: None,
            status_primary: "unknown".to_string(),
            status_standby: String::new(),
            modes: "none".to_string(),
            allstop: "unknown".to_string(),
            switch_noted: false,
        }
    }
}

impl HelmInfo {
    /// The MODE field at time `now`: `NOHELM-EVER` (no helm message yet) or `NOHELM-<s>`
    /// (the last one more than `nohelm_threshold` ago), else the helm's state or modes.
    ///
    /// The C++ stands for "no message yet" with a message at time −1, which differs from
    /// "never" only at MOOS times under the threshold; MOOS time is Unix time.
    pub fn mode(&self, now: f64, nohelm_threshold: f64) -> String {
        match self.last_msg {
            None => return "NOHELM-EVER".to_string(),
            Some(last) if now - last > nohelm_threshold => {
                let mut m = String::from("NOHELM-");
                moos_types::fmt::fixed(&mut m, now - last, 0);
                return m;
            }
            Some(_) => {}
        }
        let status = if self.status_standby == "DRIVE+" || self.status_standby == "PARK+" {
            &self.status_standby
        } else {
            &self.status_primary
        };
        if (status == "DRIVE" || status == "DRIVE+")
            && self.modes != "none"
            && !self.modes.is_empty()
        {
            self.modes.clone()
        } else {
            status.clone()
        }
    }
}

/// Everything a report needs besides the config.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ReportInputs<'a> {
    /// Vehicle name (the MOOS community).
    pub name: &'a str,
    /// Navigation.
    pub nav: NavRecord,
    /// Colour now in effect.
    pub color: Option<&'a str>,
    /// Group now in effect.
    pub group: Option<&'a str>,
    /// MODE field.
    pub mode: &'a str,
    /// `AUX_MODE`.
    pub mode_aux: Option<&'a str>,
    /// ALLSTOP field.
    pub allstop: &'a str,
    /// `LOAD_WARNING` (`app:maxgap`).
    pub load_warning: Option<&'a str>,
    /// Report index (0 is not written).
    pub index: u64,
    /// `THRUST_MODE_REVERSE`.
    pub thrust_mode_reverse: bool,
    /// TIME field.
    pub time: f64,
    /// TRANSPARENCY field.
    pub transparency: Option<f64>,
    /// COG field (course over ground, degrees), once known with `report_cog`.
    pub cog: Option<f64>,
    /// `NAV_TRAJECTORY`, written `TRAJECTORY={...}` after BEAM.
    pub trajectory: Option<&'a str>,
}

/// Appends a `NODE_REPORT_LOCAL` string to `out` (the `NodeRecord::getSpec` layout).
pub fn write_report(out: &mut String, cfg: &NodeReportConfig, r: &ReportInputs<'_>) {
    let num = |out: &mut String, key: &str, v: f64, digits: usize| {
        out.push_str(key);
        moos_types::fmt::compact(out, v, digits);
    };
    let text = |out: &mut String, key: &str, v: &str| {
        if !v.is_empty() {
            out.push_str(key);
            out.push_str(v);
        }
    };
    let nav = &r.nav;
    out.push_str("NAME=");
    out.push_str(r.name);
    if !cfg.coord_policy_global {
        if let Some(x) = nav.x {
            num(out, ",X=", x, 2);
        }
        if let Some(y) = nav.y {
            num(out, ",Y=", y, 2);
        }
    }
    if let Some(v) = nav.speed {
        num(out, ",SPD=", v, 2);
    }
    if let Some(v) = nav.heading {
        num(out, ",HDG=", v, 2);
    }
    if let Some(v) = r.cog {
        num(out, ",COG=", v, 2);
    }
    if let (false, Some(v)) = (cfg.terse_reports, nav.depth) {
        num(out, ",DEP=", v, 2);
    }
    if cfg.coord_policy_global || !cfg.terse_reports {
        if let Some(v) = nav.lat {
            num(out, ",LAT=", v, 8);
        }
        if let Some(v) = nav.lon {
            num(out, ",LON=", v, 8);
        }
    }
    text(out, ",TYPE=", &cfg.platform_type);
    text(out, ",COLOR=", r.color.unwrap_or(""));
    text(out, ",GROUP=", r.group.unwrap_or(""));
    text(out, ",VSOURCE=", &cfg.vsource);
    text(out, ",MODE=", r.mode);
    text(out, ",MODE_AUX=", r.mode_aux.unwrap_or(""));
    text(out, ",ALLSTOP=", r.allstop);
    text(out, ",LOAD_WARNING=", r.load_warning.unwrap_or(""));
    if let Some(v) = nav.altitude {
        num(out, ",ALTITUDE=", v, 2);
    }
    if r.index != 0 {
        let _ = write!(out, ",INDEX={}", r.index);
    }
    if r.thrust_mode_reverse {
        out.push_str(",THRUST_MODE_REVERSE=true");
    }
    if nav.yaw_seen && !cfg.terse_reports {
        num(
            out,
            ",YAW=",
            heading_to_radians(nav.heading.unwrap_or(0.0)),
            7,
        );
    }
    num(out, ",TIME=", r.time, 2);
    if let Some(t) = r.transparency {
        num(out, ",TRANSPARENCY=", t, 2);
    }
    let length = if cfg.platform_length > 0.0 {
        cfg.platform_length
    } else {
        default_length(&cfg.platform_type).unwrap_or(0.0)
    };
    num(out, ",LENGTH=", length, 2);
    if let Some(b) = cfg.platform_beam {
        num(out, ",BEAM=", b, 2);
    }
    if let Some(t) = r.trajectory {
        out.push_str(",TRAJECTORY={");
        out.push_str(t);
        out.push('}');
    }
    for (k, v) in &cfg.aspects {
        out.push(',');
        out.push_str(k);
        out.push('=');
        out.push_str(v);
    }
}

/// A `key=value,...` report as JSON (MOOS `cspToJson`): keys quoted, values quoted unless
/// numbers or already quoted; a braced input gives an empty string.
///
/// ```
/// assert_eq!(
///     vehicle::node_report::csp_to_json("NAME=abe,X=1.5,TYPE=kayak"),
///     r#"{"NAME":"abe","X":1.5,"TYPE":"kayak"}"#
/// );
/// ```
pub fn csp_to_json(csp: &str) -> String {
    let t = csp.trim();
    if t.starts_with('{') && t.ends_with('}') {
        return String::new();
    }
    let quoted = |x: &str| x.len() >= 2 && x.starts_with('"') && x.ends_with('"');
    let t = if quoted(t) { &t[1..t.len() - 1] } else { t };
    let mut out = String::from("{");
    for (i, pair) in t.split(',').enumerate() {
        let (k, v) = pair.split_once('=').unwrap_or((pair, ""));
        let (k, v) = (k.trim(), v.trim());
        if i != 0 {
            out.push(',');
        }
        if quoted(k) {
            out.push_str(k);
        } else {
            let _ = write!(out, "\"{k}\"");
        }
        out.push(':');
        if quoted(v) || crate::config::parse_number(v).is_some() {
            out.push_str(v);
        } else {
            let _ = write!(out, "\"{v}\"");
        }
    }
    out.push('}');
    out
}

/// The odometer behind `PNR_MHASH` (MOOS `Odometer` plus pNodeReporter's posting rule).
#[derive(Debug, Clone, Copy, Default)]
struct MhashOdometer {
    /// Position at the previous update, and where the extent is measured from.
    curr: Option<(f64, f64)>,
    orig: (f64, f64),
    /// Largest extent since the last reset.
    max_extent: f64,
    /// Largest extent in this mission, and the value last posted.
    max_extent_mission: f64,
    max_extent_posted: f64,
}

impl MhashOdometer {
    fn reset_extent(&mut self) {
        self.max_extent = 0.0;
        if let Some(c) = self.curr {
            self.orig = c;
        }
    }

    /// Takes a position; returns the extent to post, if any.
    fn update(&mut self, x: f64, y: f64) -> Option<f64> {
        if self.curr.is_none() {
            self.orig = (x, y);
        }
        self.curr = Some((x, y));
        let ext = (x - self.orig.0).hypot(y - self.orig.1);
        self.max_extent = self.max_extent.max(ext);
        self.max_extent_mission = self.max_extent_mission.max(self.max_extent);
        let (now, prev) = (self.max_extent_mission, self.max_extent_posted);
        let grew = (prev == 0.0 && now > 0.0) || now > prev * 1.02;
        if grew && now - prev >= 1.0 {
            self.max_extent_posted = now;
            Some(now)
        } else {
            None
        }
    }
}

/// The riders' part of a report (MOOS `NodeRiderSet::getRiderReports`) from `states`,
/// which it updates (freshness spent, periods restarted).
fn rider_reports_of(riders: &[RiderConfig], states: &mut [RiderState], now: f64) -> String {
    let mut reports = String::new();
    for (cfg, st) in riders.iter().zip(states.iter_mut()) {
        if st.value.is_empty() {
            continue;
        }
        let field = if cfg.field.is_empty() {
            &cfg.var
        } else {
            &cfg.field
        };
        let value = if st.value.contains(',') {
            format!("{{{}}}", st.value)
        } else {
            st.value.clone()
        };
        let elapsed = now - st.last_time;
        let report = match cfg.policy {
            RiderPolicy::Always => format!("{field}={value}"),
            RiderPolicy::Updated { .. } if st.fresh => format!("{field}={value}"),
            RiderPolicy::Updated { period_s } if period_s > 0.0 && elapsed >= period_s => {
                st.last_time = now;
                format!("{}={value}", cfg.var)
            }
            RiderPolicy::Updated { .. } => String::new(),
            RiderPolicy::Every { period_s } if elapsed >= period_s => {
                st.last_time = now;
                format!("{field}={value}")
            }
            RiderPolicy::Every { .. } => String::new(),
        };
        st.fresh = false;
        if !reports.is_empty() {
            reports.push(',');
        }
        reports.push_str(&report);
    }
    reports
}

/// Appends `msg` as MOOS `ACBlock(label, msg, maxlen).getFormattedString()`: the pieces
/// between commas (outside quotes and braces) joined again while a line stays within
/// `maxlen`, a broken line ending in a comma; the first line after `label`, the others
/// after as many blanks; each line ended by a newline.
fn write_block(out: &mut String, label: &str, msg: &str, maxlen: usize) {
    if msg.is_empty() {
        out.push_str(label);
        return;
    }
    let mut lines: Vec<String> = Vec::new();
    let mut buffer = String::new();
    for piece in crate::moos::parse_string_q(msg, ',') {
        if buffer.is_empty() {
            buffer = piece.to_string();
        } else if buffer.len() + 1 + piece.len() <= maxlen {
            buffer.push(',');
            buffer.push_str(piece);
        } else {
            lines.push(std::mem::take(&mut buffer) + ",");
            buffer = piece.to_string();
        }
    }
    if !buffer.is_empty() {
        lines.push(buffer);
    }
    let blank = " ".repeat(label.len());
    for (i, l) in lines.iter().enumerate() {
        out.push_str(if i == 0 { label } else { &blank });
        out.push_str(l);
        out.push('\n');
    }
}

/// The `pNodeReporter` app.
pub struct NodeReporter {
    cfg: NodeReportConfig,
    name: String,
    nav: NavRecord,
    helm: HelmInfo,
    color: Option<String>,
    group: Option<String>,
    mode_aux: Option<String>,
    load_warning: Option<String>,
    thrust_mode_reverse: bool,
    transparency: Option<f64>,
    paused: bool,
    start_time: f64,
    last_post_time: Option<f64>,
    reports_posted: u64,
    /// The mission hash (`MISSION_HASH`, `mhash=` token) and its odometer (`PNR_MHASH`).
    mhash: String,
    odo: MhashOdometer,
    /// One state per configured rider.
    riders: Vec<RiderState>,
    /// The mission's local grid (cross-filling), and when X/Y and LAT/LON last arrived.
    grid: Option<crate::geodesy::LocalGrid>,
    xy_time: f64,
    latlon_time: f64,
    /// Position at the previous iteration and the course over ground (`report_cog`).
    last_xy: Option<(f64, f64)>,
    cog: Option<f64>,
    /// The alternative-nav record (`alt_nav_prefix`).
    gt: AltNav,
    /// The last report posted (extrapolation and PNR_POST_GAP), and when.
    last_posted: Option<(NavRecord, f64)>,
    /// The blackout now in effect, s (`blackout_interval` until the first report).
    blackout_s: f64,
    rng: fastrand::Rng,
    /// One state per platform-report variable.
    plat: Vec<PlatState>,
    /// The process id to post once as PNODEREPORTER_PID (single-app mode).
    pid: Option<u32>,
    /// `NAV_TRAJECTORY`: the report's `TRAJECTORY={...}` field.
    trajectory: Option<String>,
    buf: String,
    var_report: ByteString,
    var_first: ByteString,
    var_gap: ByteString,
    var_mhash: ByteString,
    var_plat: ByteString,
    /// Alternative-nav reports posted (the appcast's `alt_nav_postings`).
    reports_posted_alt_nav: u64,
    /// The INDEX of the record last reported (set when a report is formed).
    record_index: u64,
    /// The appcast's terminal report interval (`tr_interval`).
    term_report_interval: f64,
    /// The NAV run warning is up (MOOS `m_nav_warning_posted`).
    nav_warning_posted: bool,
    /// Run warnings and retractions not yet taken.
    notes: std::collections::VecDeque<crate::AppcastNote>,
}

/// The second, alternative-nav record of the vehicle (MOOS `m_record_gt`).
#[derive(Debug, Clone, Default)]
struct AltNav {
    nav: NavRecord,
    transparency: Option<f64>,
    name: String,
    group: Option<String>,
    /// When one of its variables last arrived. (The C++ starts from time 0, which differs
    /// from "never" only at MOOS times under 5 s; MOOS time is Unix time.)
    updated: Option<f64>,
    xy_time: f64,
    latlon_time: f64,
    /// The INDEX of its last report.
    index: u64,
}

/// A platform-report variable's latest value and when it arrived and was last reported.
#[derive(Debug, Clone, Default)]
struct PlatState {
    value: String,
    received: f64,
    posted: f64,
}

impl NodeReporter {
    /// A reporter for vehicle `name` (the MOOS community), started at `start_time`.
    pub fn new(cfg: NodeReportConfig, name: &str, start_time: f64) -> Self {
        let rider_count = cfg.riders.len();
        let gt = AltNav {
            transparency: cfg.transparency,
            name: match cfg.alt_nav_name.strip_prefix('_') {
                Some(_) => format!("{name}{}", cfg.alt_nav_name),
                None => cfg.alt_nav_name.clone(),
            },
            group: cfg.alt_nav_group.clone().or_else(|| cfg.group.clone()),
            ..AltNav::default()
        };
        NodeReporter {
            gt,
            last_posted: None,
            blackout_s: cfg.blackout_interval,
            rng: fastrand::Rng::with_seed(0),
            plat: vec![PlatState::default(); cfg.plat_vars.len()],
            pid: None,
            trajectory: None,
            var_plat: cfg.plat_report_output.as_str().into(),
            var_report: cfg.node_report_output.as_str().into(),
            var_first: format!("{}_FIRST", cfg.node_report_output).into(),
            var_gap: "PNR_POST_GAP".into(),
            var_mhash: "PNR_MHASH".into(),
            color: cfg.platform_color.clone(),
            group: cfg.group.clone(),
            transparency: cfg.transparency,
            paused: cfg.paused,
            cfg,
            name: name.to_string(),
            nav: NavRecord::default(),
            helm: HelmInfo::default(),
            mode_aux: None,
            load_warning: None,
            thrust_mode_reverse: false,
            start_time,
            last_post_time: None,
            reports_posted: 0,
            last_xy: None,
            cog: None,
            mhash: String::new(),
            odo: MhashOdometer::default(),
            riders: vec![RiderState::default(); rider_count],
            grid: None,
            xy_time: 0.0,
            latlon_time: 0.0,
            buf: String::with_capacity(256),
            reports_posted_alt_nav: 0,
            record_index: 0,
            term_report_interval: appcast::casting::DEFAULT_TERM_REPORT_INTERVAL,
            nav_warning_posted: false,
            notes: std::collections::VecDeque::new(),
        }
    }

    /// Sets the terminal report interval the appcast shows as `tr_interval` (the app's
    /// `TERM_REPORT_INTERVAL`; by default [`appcast::casting::DEFAULT_TERM_REPORT_INTERVAL`]).
    pub fn set_term_report_interval(&mut self, seconds: f64) {
        self.term_report_interval = seconds;
    }

    /// Takes the run warnings and retractions reported since the last call, oldest first
    /// (at most [`crate::MAX_APPCAST_NOTES`]; see [`NodeReporter::appcast_body`]).
    pub fn take_appcast_notes(&mut self) -> Vec<crate::AppcastNote> {
        self.notes.drain(..).collect()
    }

    /// The inputs of the alternative-navigation (ground truth) report.
    fn gt_inputs<'a>(&'a self, mode: &'a str, now: f64) -> ReportInputs<'a> {
        ReportInputs {
            name: &self.gt.name,
            nav: self.gt.nav,
            color: self.color.as_deref(),
            group: self.gt.group.as_deref(),
            mode,
            mode_aux: None,
            allstop: &self.helm.allstop,
            load_warning: None,
            index: self.gt.index,
            thrust_mode_reverse: false,
            time: now,
            transparency: self.gt.transparency,
            cog: None,
            trajectory: None,
        }
    }

    /// Appends the pNodeReporter appcast report body (`NodeReporter::buildReport`) as it
    /// reads at the end of the iteration at `now`:
    ///
    /// ```text
    /// tr_interval:0.5
    /// extrap_enabled:    false
    /// extrap_pos_thresh: 0.25
    /// extrap_hdg_thresh: 1
    /// extrap_max_gap:    0.25
    /// Paused: false
    /// Vehicle Configuration:
    /// ...
    /// Node Report Summary:
    /// ----------------------------
    /// Reports Posted: 12
    ///  Latest Report: NAME=abe,X=1,Y=2,SPD=1.5,HDG=90,DEP=0,
    ///                 LAT=43.8253,LON=-70.3304,TYPE=kayak,...
    /// ```
    ///
    /// As the C++: `extrap_max_gap` shows the position threshold (its quirk),
    /// `Blackout interval` the blackout now in effect (0 after a report without
    /// `blackout_variance`), `Vehicle group` the configured group (not NODE_GROUP_UPDATE's).
    /// The latest report is the vehicle's record reassembled at `now` (mode from the helm's
    /// messages at `now`, the INDEX of its last report, no LOAD_WARNING, which an iteration
    /// clears, the heading without `hdg_error`, the riders' values), cut into lines of at most
    /// 50 characters at commas (MOOS `ACBlock`); the alternative-nav record follows as
    /// ` Latest GT Report: ` once one of its variables arrived. `tr_interval` is written as a
    /// C++ stream writes a double (6 significant digits), from
    /// [`NodeReporter::set_term_report_interval`].
    ///
    /// One difference: the C++ reassembles the reports with its rider set, so building an
    /// appcast spends `updated` riders and restarts periodic ones; coug's appcast reads a copy
    /// of the riders and leaves the next posted report as it would be without an appcast.
    ///
    /// Appcast notes of pNodeReporter (`take_appcast_notes` reproduces the run warnings):
    /// * run warning `Waiting for NAV_X/Y or NAV_LAT/LONG`, when an iteration finds no valid
    ///   navigation (speed, heading and a position) after the `nav_grace_period`, once until
    ///   retracted;
    /// * its retraction, at the first iteration that finds navigation valid (or within the
    ///   grace period) again;
    /// * no events. Config warnings (at start-up only): `Lat or Lon Origin not set in *.moos
    ///   file.`, `Geodesy init failed.`, `No config block found for pNodeReporter`,
    ///   `Unrecognized platform type: <type>` (no length given and no guess for the type),
    ///   and each unhandled line.
    pub fn appcast_body(&self, now: f64, out: &mut String) {
        let b = |v: bool| if v { "true" } else { "false" };
        let cfg = &self.cfg;
        const RULE: &str = "----------------------------\n";
        let line = |out: &mut String, label: &str, value: &str| {
            out.push_str(label);
            out.push_str(value);
            out.push('\n');
        };
        line(
            out,
            "tr_interval:",
            &moos_types::fmt::g_string(self.term_report_interval, 6),
        );
        line(out, "extrap_enabled:    ", b(cfg.extrap_enabled));
        let pos_thresh = moos_types::fmt::compact_string(cfg.extrap_pos_thresh_m, 2);
        line(out, "extrap_pos_thresh: ", &pos_thresh);
        let hdg_thresh = moos_types::fmt::compact_string(cfg.extrap_hdg_thresh_deg, 2);
        line(out, "extrap_hdg_thresh: ", &hdg_thresh);
        // As the C++: the position threshold under the max-gap label.
        line(out, "extrap_max_gap:    ", &pos_thresh);
        line(out, "Paused: ", b(self.paused));
        out.push_str("Vehicle Configuration:\n");
        out.push_str(RULE);
        line(out, "     Vehicle name: ", &self.name);
        line(out, "     Vehicle type: ", &cfg.platform_type);
        let mut len = String::new();
        moos_types::fmt::fixed(&mut len, self.length(), 1);
        line(out, "   Vehicle length: ", &len);
        line(
            out,
            "    Vehicle group: ",
            cfg.group.as_deref().unwrap_or(""),
        );
        out.push_str("\nCrossFill Policy:\n");
        out.push_str(RULE);
        line(out, " cross_fill_policy: ", cfg.crossfill.as_str());
        out.push_str("\nBlackout Configuration:\n");
        out.push_str(RULE);
        let mut v = String::new();
        moos_types::fmt::fixed(&mut v, self.blackout_s, 2);
        line(out, "Blackout interval: ", &v);
        v.clear();
        moos_types::fmt::fixed(&mut v, cfg.blackout_variance, 2);
        line(out, "Blackout variance: ", &v);
        out.push_str("\nAltNav Config and Status:\n");
        out.push_str(RULE);
        line(out, "   alt_nav_prefix: ", &cfg.alt_nav_prefix);
        line(out, "     alt_nav_name: ", &cfg.alt_nav_name);
        let alt_group = cfg.alt_nav_group.as_deref().unwrap_or("");
        line(out, "    alt_nav_group: ", alt_group);
        line(
            out,
            " alt_nav_postings: ",
            &self.reports_posted_alt_nav.to_string(),
        );
        out.push('\n');
        if !cfg.riders.is_empty() {
            out.push_str("Riders:                     \n");
            out.push_str(RULE);
            for r in &cfg.riders {
                line(out, "  ", &r.spec());
            }
            out.push('\n');
        }
        out.push_str("Node Report Summary:\n");
        out.push_str(RULE);
        line(out, "Reports Posted: ", &self.reports_posted.to_string());
        // The records as they would be reassembled now, riders from a copy.
        let mode = self.helm.mode(now, cfg.nohelm_threshold);
        let mut riders = self.riders.clone();
        let mut report = String::new();
        let inputs = ReportInputs {
            name: &self.name,
            nav: self.nav,
            color: self.color.as_deref(),
            group: self.group.as_deref(),
            mode: &mode,
            mode_aux: self.mode_aux.as_deref(),
            allstop: &self.helm.allstop,
            load_warning: None,
            index: self.record_index,
            thrust_mode_reverse: self.thrust_mode_reverse,
            time: now,
            transparency: self.transparency,
            cog: self.cog,
            trajectory: self.trajectory.as_deref(),
        };
        write_report(&mut report, cfg, &inputs);
        let r = rider_reports_of(&cfg.riders, &mut riders, now);
        if !r.is_empty() {
            report.push(',');
            report.push_str(&r);
        }
        write_block(out, " Latest Report: ", &report, 50);
        if self.gt.updated.is_some() {
            let inputs = self.gt_inputs(&mode, now);
            report.clear();
            write_report(&mut report, cfg, &inputs);
            let r = rider_reports_of(&cfg.riders, &mut riders, now);
            if !r.is_empty() {
                report.push(',');
                report.push_str(&r);
            }
            write_block(out, " Latest GT Report: ", &report, 50);
        }
    }

    /// The platform length: configured, else guessed from the type (0 when unknown).
    fn length(&self) -> f64 {
        if self.cfg.platform_length > 0.0 {
            self.cfg.platform_length
        } else {
            default_length(&self.cfg.platform_type).unwrap_or(0.0)
        }
    }

    /// Navigation as last received.
    pub fn nav(&self) -> &NavRecord {
        &self.nav
    }

    /// Helm information as last received.
    pub fn helm(&self) -> &HelmInfo {
        &self.helm
    }

    /// The variables this app subscribes to.
    ///
    /// As the C++: every `NAV_*` variable (a wildcard registration, which brings e.g.
    /// `NAV_GT_ALTITUDE` to an `alt_nav_prefix` of `NAV_GT`) besides the named ones.
    pub fn subscriptions() -> &'static [&'static str] {
        &[
            "NAV_*",
            "NAV_X",
            "NAV_Y",
            "NAV_LAT",
            "NAV_LONG",
            "NAV_SPEED",
            "NAV_HEADING",
            "NAV_DEPTH",
            "NAV_ALTITUDE",
            "NAV_YAW",
            "NAV_TRANSP",
            "NAV_TRAJECTORY",
            "IVPHELM_SUMMARY",
            "IVPHELM_STATE",
            "IVPHELM_ALLSTOP",
            "AUX_MODE",
            "LOAD_WARNING",
            "THRUST_MODE_REVERSE",
            "NODE_GROUP_UPDATE",
            "NODE_COLOR_CHANGE",
            "PLATFORM_COLOR",
            "PNR_PAUSE",
            "MISSION_HASH",
        ]
    }

    /// Seeds the draw of blackout intervals (`blackout_variance`).
    pub fn with_seed(mut self, seed: u64) -> Self {
        self.rng = fastrand::Rng::with_seed(seed);
        self
    }

    /// The process id to post as `PNODEREPORTER_PID` at start-up ([`NodeReporter::on_startup`]),
    /// as the C++ app posts its own (single-app mode; `coug run`'s apps share one process and
    /// post none, so the log stays reproducible).
    pub fn set_pid(&mut self, pid: u32) {
        self.pid = Some(pid);
    }

    /// Start-up (MOOS `OnStartUp`): posts `PNODEREPORTER_PID`, a double, when a process id
    /// was given ([`NodeReporter::set_pid`]).
    pub fn on_startup(&mut self, out: &mut Vec<Posting>) {
        if let Some(pid) = self.pid.take() {
            out.push(Posting::double("PNODEREPORTER_PID", f64::from(pid)));
        }
    }

    /// Variables subscribed besides [`NodeReporter::subscriptions`]: the riders, the
    /// alternative-nav variables and the platform-report inputs.
    pub fn extra_subscriptions(&self) -> Vec<String> {
        let mut v: Vec<String> = self.rider_vars().map(str::to_string).collect();
        let pre = &self.cfg.alt_nav_prefix;
        if !pre.is_empty() {
            for f in [
                "X", "Y", "LAT", "LONG", "SPEED", "HEADING", "YAW", "DEPTH", "TRANSP",
            ] {
                v.push(format!("{pre}{f}"));
            }
        }
        v.extend(self.cfg.plat_vars.iter().map(|p| p.var.clone()));
        v
    }

    /// The mission's local grid (from LatOrigin/LongOrigin), for the cross-fill policies.
    pub fn with_grid(mut self, grid: Option<crate::geodesy::LocalGrid>) -> Self {
        self.grid = grid;
        self
    }

    /// Fills X/Y or LAT/LON of the kept record as the policy says (before a report).
    fn cross_fill(&mut self) {
        let (xy_t, ll_t) = (self.xy_time, self.latlon_time);
        cross_fill(
            self.cfg.crossfill,
            self.grid.as_ref(),
            &mut self.nav,
            xy_t,
            ll_t,
        );
    }

    /// Posts the report in `self.buf` as `json_report` says, then PNR_POST_GAP = `gap`.
    fn post_report(&mut self, out: &mut Vec<Posting>, gap: f64) {
        let json = &self.cfg.json_report;
        let first = self.reports_posted == 0;
        if json.is_empty() {
            if first {
                out.push(Posting::text(&self.var_first, self.buf.as_str()));
            }
            out.push(Posting::text(&self.var_report, self.buf.as_str()));
        } else if json.eq_ignore_ascii_case("true") {
            let j = csp_to_json(&self.buf);
            if first {
                out.push(Posting::text(&self.var_first, j.as_str()));
            }
            out.push(Posting::text(&self.var_report, j));
        } else {
            let j = csp_to_json(&self.buf);
            if first {
                let var: ByteString = format!("{json}_FIRST").into();
                out.push(Posting::text(&var, j.as_str()));
                out.push(Posting::text(&self.var_first, self.buf.as_str()));
            }
            let var: ByteString = json.as_str().into();
            out.push(Posting::text(&var, j));
            out.push(Posting::text(&self.var_report, self.buf.as_str()));
        }
        out.push(Posting::double(&self.var_gap, gap));
        self.reports_posted += 1;
    }

    /// The platform report (MOOS `assemblePlatformReport`): each input changed since it was
    /// last reported and at least its gap ago, as `VAR=value` (or its alias), after
    /// `platform=<name>,utc_time=<now, 5 decimals>`; empty when none is due.
    fn platform_report(&mut self, now: f64) -> String {
        let mut r = String::new();
        for (cfg, st) in self.cfg.plat_vars.iter().zip(&mut self.plat) {
            if st.received != 0.0 && st.received > st.posted && now - st.posted > cfg.gap_s {
                if !r.is_empty() {
                    r.push(',');
                }
                r.push_str(cfg.alias.as_deref().unwrap_or(&cfg.var));
                r.push('=');
                r.push_str(&st.value);
                st.posted = now;
            }
        }
        if r.is_empty() {
            return r;
        }
        let mut report = format!("platform={},utc_time=", self.name);
        moos_types::fmt::fixed(&mut report, now, 5);
        report.push(',');
        report.push_str(&r);
        report
    }

    /// The rider variables (subscribed in addition to [`NodeReporter::subscriptions`]).
    pub fn rider_vars(&self) -> impl Iterator<Item = &str> {
        self.cfg.riders.iter().map(|r| r.var.as_str())
    }

    /// The riders' part of a report (MOOS `NodeRiderSet::getRiderReports`), with its quirks:
    /// an `updated` rider repeated by its period rides under the variable's name, and a rider
    /// with nothing to say after one that did leaves a trailing comma.
    fn rider_reports(&mut self, now: f64) -> String {
        rider_reports_of(&self.cfg.riders, &mut self.riders, now)
    }

    /// Takes one piece of mail, handled at `time`: the app's own time when it reads its mail
    /// (MOOS `m_curr_time` in `OnNewMail`), not the time the message was posted. The
    /// freshness of the alternative-nav record, the platform reports' gaps, the riders'
    /// periods and the helm's silence all count from it.
    pub fn on_mail(&mut self, var: &str, value: ValueRef<'_>, time: f64) {
        let d = value.as_f64();
        let s = value.as_str().unwrap_or("");
        match (var, d) {
            ("NAV_X", Some(v)) => {
                self.nav.x = Some(v);
                self.xy_time = time;
            }
            ("NAV_Y", Some(v)) => {
                self.nav.y = Some(v);
                self.xy_time = time;
            }
            ("NAV_LAT", Some(v)) => {
                self.nav.lat = Some(v);
                self.latlon_time = time;
            }
            ("NAV_LONG", Some(v)) => {
                self.nav.lon = Some(v);
                self.latlon_time = time;
            }
            ("NAV_SPEED", Some(v)) => self.nav.speed = Some(v),
            ("NAV_HEADING", Some(v)) => self.nav.heading = Some(angle360(v)),
            ("NAV_DEPTH", Some(v)) => self.nav.depth = Some(v),
            ("NAV_ALTITUDE", Some(v)) => self.nav.altitude = Some(v),
            ("NAV_YAW", Some(_)) => self.nav.yaw_seen = true,
            ("NAV_TRAJECTORY", _) => self.trajectory = Some(s.to_string()),
            ("PLATFORM_COLOR", _) if geometry::color::is_color(s) => {
                self.color = Some(s.to_string())
            }
            ("NODE_COLOR_CHANGE", _)
                if self.cfg.allow_color_change && geometry::color::is_color(s) =>
            {
                self.color = Some(s.to_string())
            }
            ("THRUST_MODE_REVERSE", _) => self.thrust_mode_reverse = s.eq_ignore_ascii_case("true"),
            ("NAV_TRANSP", Some(v)) => self.transparency = Some(v),
            _ => {}
        }
        // The alternative-nav record's own variables (`<prefix>X`, ...).
        if let Some(field) = (!self.cfg.alt_nav_prefix.is_empty())
            .then(|| var.strip_prefix(self.cfg.alt_nav_prefix.as_str()))
            .flatten()
            && let Some(v) = d
        {
            let g = &mut self.gt;
            let known = match field {
                "X" => {
                    g.nav.x = Some(v);
                    g.xy_time = time;
                    true
                }
                "Y" => {
                    g.nav.y = Some(v);
                    g.xy_time = time;
                    true
                }
                "LAT" => {
                    g.nav.lat = Some(v);
                    g.latlon_time = time;
                    true
                }
                "LONG" => {
                    g.nav.lon = Some(v);
                    g.latlon_time = time;
                    true
                }
                "TRANSP" => {
                    g.transparency = Some(v);
                    true
                }
                "SPEED" => {
                    g.nav.speed = Some(v);
                    true
                }
                "HEADING" => {
                    g.nav.heading = Some(angle360(v));
                    true
                }
                "DEPTH" => {
                    g.nav.depth = Some(v);
                    true
                }
                "ALTITUDE" => {
                    g.nav.altitude = Some(v);
                    true
                }
                "YAW" => {
                    g.nav.yaw_seen = true;
                    true
                }
                _ => false,
            };
            if known {
                g.updated = Some(time);
            }
        }
        if var == "MISSION_HASH" {
            // The `mhash=` token of the posting; a new mission restarts the extent.
            self.mhash = crate::moos::tok_string_parse(s, "mhash").to_string();
            self.odo.max_extent_mission = 0.0;
            self.odo.reset_extent();
        }
        match var {
            "AUX_MODE" => self.mode_aux = Some(s.to_string()),
            "PNR_PAUSE" => {
                if let Some(b) = crate::config::set_bool_on_string(self.paused, s) {
                    self.paused = b;
                }
            }
            "LOAD_WARNING" => {
                let app = crate::moos::tok_string_parse(s, "app");
                let gap = crate::moos::tok_string_parse(s, "maxgap");
                if !app.is_empty() && !gap.is_empty() {
                    self.load_warning = Some(format!("{app}:{gap}"));
                }
            }
            "NODE_GROUP_UPDATE" => {
                self.group = Some(s.to_string());
                self.gt.group = Some(s.to_string());
            }
            "IVPHELM_SUMMARY" => {
                self.helm.last_msg = Some(time);
                for kv in crate::moos::parse_string(s, ',') {
                    let (left, right) = kv.split_once('=').unwrap_or((kv, ""));
                    if left.trim() == "modes" {
                        self.helm.modes = right.trim().to_string();
                    }
                }
            }
            "IVPHELM_ALLSTOP" => {
                self.helm.last_msg = Some(time);
                self.helm.allstop = s.to_string();
            }
            "IVPHELM_STATE" => {
                self.helm.last_msg = Some(time);
                let st = s.trim();
                match st {
                    "DRIVE" | "PARK" | "MALCONFIG" | "DISABLED" => {
                        self.helm.status_primary = st.to_string()
                    }
                    "DRIVE+" | "PARK+" | "MALCONFIG+" | "STANDBY" => {
                        self.helm.status_standby = st.to_string()
                    }
                    _ => {}
                }
                // A standby helm stepping in (`...+`): the first time, forget the modes and
                // all-stop of the helm it replaced (MOOS `handleHelmSwitch`).
                if st.ends_with('+') && !self.helm.switch_noted {
                    self.helm.modes.clear();
                    self.helm.allstop.clear();
                    self.helm.switch_noted = true;
                }
                if st.starts_with("MALCONFIG") {
                    self.helm.allstop = "n/a".to_string();
                }
            }
            // Riders take every other variable (not the ones just above, as the C++).
            _ => {
                for (cfg, state) in self.cfg.riders.iter().zip(&mut self.riders) {
                    if cfg.var == var {
                        state.value = match (s, d) {
                            ("", Some(x)) => {
                                let mut v = String::new();
                                moos_types::fmt::fixed(&mut v, x, cfg.precision);
                                v
                            }
                            _ => s.to_string(),
                        };
                        state.last_time = time;
                        state.fresh = true;
                    }
                }
            }
        }
        // The platform report's inputs: a number as `doubleToString(v, 8)`, compacted.
        for (cfg, st) in self.cfg.plat_vars.iter().zip(&mut self.plat) {
            if cfg.var == var {
                st.value = match (value.as_str(), d) {
                    (None, Some(x)) => {
                        let mut v = String::new();
                        moos_types::fmt::dstring_compact(&mut v, x, 8);
                        v
                    }
                    _ => s.to_string(),
                };
                st.received = time;
            }
        }
    }

    /// One iteration at `now`, in the C++ app's order: the extrapolation gaps, the node report
    /// (`_FIRST` before the first, then PNR_POST_GAP), the alternative-nav report, the
    /// platform report, the mission-hash odometer.
    ///
    /// As pNodeReporter at a2a9b716, `blackout_interval` holds back no report at all: the
    /// first report is always due, and after each report the blackout becomes 0 (the C++
    /// resets it to a base value that no parameter sets), then with `blackout_variance` `v`
    /// is drawn as `-v + 2 * k / 100` for a whole `k` in `[0, v * 100)`, clipped at 0.
    pub fn iterate(&mut self, now: f64, out: &mut Vec<Posting>) {
        let time_to_post = match self.last_post_time {
            None => true,
            Some(t) => self.blackout_s <= 0.0 || now - t > self.blackout_s,
        };
        let in_grace =
            self.cfg.nav_grace_period > 0.0 && now - self.start_time < self.cfg.nav_grace_period;
        let ok_nav = self.nav.valid() || in_grace;
        const NAV_WARNING: &str = "Waiting for NAV_X/Y or NAV_LAT/LONG";
        if !ok_nav && !self.nav_warning_posted {
            crate::push_note(
                &mut self.notes,
                crate::AppcastNote::Warning(NAV_WARNING.into()),
            );
            self.nav_warning_posted = true;
        }
        if ok_nav && self.nav_warning_posted {
            crate::push_note(
                &mut self.notes,
                crate::AppcastNote::Retract(NAV_WARNING.into()),
            );
            self.nav_warning_posted = false;
        }
        // Seconds since the last report posted, 0 before the first. (The C++ tests the
        // record's timestamp for > 0, which differs only for a report at MOOS time 0.)
        let gap = self.last_posted.map_or(0.0, |(_, t)| now - t);
        let mut pruned = false;
        if self.cfg.extrap_enabled
            && gap > 0.0
            && gap < self.cfg.extrap_max_gap_s
            && let Some((last, t)) = self.last_posted
        {
            let (dist, hdg_delta) = extrapolation_gap(&last, t, &self.nav, now);
            pruned =
                dist < self.cfg.extrap_pos_thresh_m && hdg_delta < self.cfg.extrap_hdg_thresh_deg;
            out.push(Posting::double("PNR_EXTRAP_POS_GAP", dist));
            out.push(Posting::double("PNR_EXTRAP_HDG_GAP", hdg_delta));
        }
        // Within the grace period a report needs a position: X and Y, or (as the C++'s
        // `isSetLatLon`, which tests the longitude twice) just a longitude.
        let has_pos = (self.nav.x.is_some() && self.nav.y.is_some()) || self.nav.lon.is_some();
        let post = ok_nav && time_to_post && !pruned && (has_pos || !in_grace);
        if post {
            self.record_index = self.reports_posted;
            let mode = self.helm.mode(now, self.cfg.nohelm_threshold);
            self.cross_fill();
            // HDG_ERROR: the posted report carries the heading plus the error.
            let mut nav = self.nav;
            if self.cfg.hdg_error_deg != 0.0 {
                nav.heading = nav.heading.map(|h| angle360(h + self.cfg.hdg_error_deg));
            }
            if self.cfg.hdg_error_deg != 0.0 {
                // The C++ forms the report twice (without, then with the error) and posts the
                // second: the riders' updated and periodic values go to the discarded one.
                let _ = self.rider_reports(now);
            }
            let inputs = ReportInputs {
                name: &self.name,
                nav,
                color: self.color.as_deref(),
                group: self.group.as_deref(),
                mode: &mode,
                mode_aux: self.mode_aux.as_deref(),
                allstop: &self.helm.allstop,
                load_warning: self.load_warning.as_deref(),
                index: self.reports_posted,
                thrust_mode_reverse: self.thrust_mode_reverse,
                time: now,
                transparency: self.transparency,
                cog: self.cog,
                trajectory: self.trajectory.as_deref(),
            };
            self.buf.clear();
            write_report(&mut self.buf, &self.cfg, &inputs);
            let riders = self.rider_reports(now);
            if !riders.is_empty() {
                self.buf.push(',');
                self.buf.push_str(&riders);
            }
            if !self.paused {
                self.post_report(out, gap);
                self.last_posted = Some((self.nav, now));
            }
            // The alternative-nav report, while its variables are fresh (5 s).
            if self.gt.updated.is_some_and(|t| now - t < 5.0) {
                let (xy_t, ll_t) = (self.gt.xy_time, self.gt.latlon_time);
                cross_fill(
                    self.cfg.crossfill,
                    self.grid.as_ref(),
                    &mut self.gt.nav,
                    xy_t,
                    ll_t,
                );
                self.gt.index = self.reports_posted;
                let inputs = self.gt_inputs(&mode, now);
                let mut report = String::new();
                write_report(&mut report, &self.cfg, &inputs);
                let riders = self.rider_reports(now);
                if !riders.is_empty() {
                    report.push(',');
                    report.push_str(&riders);
                }
                if !self.paused {
                    out.push(Posting::text(&self.var_report, report));
                    self.reports_posted_alt_nav += 1;
                }
            }
            self.last_post_time = Some(now);
            self.blackout_s = 0.0;
            let v = self.cfg.blackout_variance;
            if v > 0.0 {
                // The C++ draws `rand() % (int)(v * 100)` hundredths.
                let range = (v * 100.0) as u64;
                let hundredths = if range > 0 { self.rng.u64(0..range) } else { 0 };
                self.blackout_s = -v + 2.0 * (hundredths as f64 / 100.0);
            }
            self.blackout_s = self.blackout_s.max(0.0);
        }
        self.load_warning = None;
        // REPORT_COG: the bearing from the previous iteration's position to this one goes
        // into the next reports (MOOS `cogRecord` on the last formed record).
        let xy = self.nav.x.zip(self.nav.y);
        if self.cfg.report_cog
            && let (Some((x0, y0)), Some((x1, y1))) = (self.last_xy, xy)
        {
            self.cog = Some(crate::angle::rel_ang(x0, y0, x1, y1));
        }
        self.last_xy = xy;
        let plat = self.platform_report(now);
        if !plat.is_empty() && !self.paused {
            out.push(Posting::text(&self.var_plat, plat));
        }
        // MISSION_HASH odometer: the largest distance from where the mission started,
        // posted when it has grown by 2 % and at least 1 m (MOOS `updateMHashOdo`).
        if !self.mhash.is_empty()
            && let Some(ext) = self
                .odo
                .update(self.nav.x.unwrap_or(0.0), self.nav.y.unwrap_or(0.0))
        {
            let mut msg = format!("mhash={},ext=", self.mhash);
            moos_types::fmt::compact(&mut msg, ext, 1);
            out.push(Posting::text(&self.var_mhash, msg));
        }
    }
}

#[cfg(test)]
mod appcast_tests {
    use super::*;
    use crate::AppcastNote;

    #[test]
    fn appcast_body_as_node_reporter_builds_it() {
        let cfg = NodeReportConfig::from_params([
            ("platform_type", "kayak"),
            ("platform_color", "yellow"),
            ("group", "red"),
            ("nav_grace_period", "0"),
            ("rider", "var=LEG_ID, policy=updated+10, rfld=LEG"),
            ("alt_nav_prefix", "NAV_GT"),
        ])
        .unwrap();
        let mut nr = NodeReporter::new(cfg, "abe", 1000.0);
        let mut out = Vec::new();
        nr.iterate(1001.0, &mut out);
        for (var, v) in [
            ("NAV_X", 10.0),
            ("NAV_Y", -20.5),
            ("NAV_SPEED", 1.5),
            ("NAV_HEADING", 90.0),
            ("NAV_DEPTH", 0.0),
            ("LEG_ID", 3.0),
            ("NAV_GT_X", 11.0),
            ("NAV_GT_Y", -21.0),
        ] {
            nr.on_mail(var, ValueRef::Double(v), 1001.5);
        }
        nr.on_mail("IVPHELM_STATE", ValueRef::String("DRIVE"), 1001.5);
        nr.on_mail("IVPHELM_ALLSTOP", ValueRef::String("clear"), 1001.5);
        nr.iterate(1002.0, &mut out);
        nr.iterate(1003.0, &mut out);
        let mut body = String::new();
        nr.appcast_body(1003.0, &mut body);
        // The rider was spent by the first report and is not due again for 10 s. The
        // second report carried INDEX=1, the second GT report INDEX=2.
        let expected = [
            "tr_interval:0.5",
            "extrap_enabled:    false",
            "extrap_pos_thresh: 0.25",
            "extrap_hdg_thresh: 1",
            "extrap_max_gap:    0.25",
            "Paused: false",
            "Vehicle Configuration:",
            "----------------------------",
            "     Vehicle name: abe",
            "     Vehicle type: kayak",
            "   Vehicle length: 4.0",
            "    Vehicle group: red",
            "",
            "CrossFill Policy:",
            "----------------------------",
            " cross_fill_policy: literal",
            "",
            "Blackout Configuration:",
            "----------------------------",
            "Blackout interval: 0.00",
            "Blackout variance: 0.00",
            "",
            "AltNav Config and Status:",
            "----------------------------",
            "   alt_nav_prefix: NAV_GT_",
            "     alt_nav_name: _GT",
            "    alt_nav_group: ",
            " alt_nav_postings: 2",
            "",
            "Riders:                     ",
            "----------------------------",
            "  var=LEG_ID, policy=updated+10, rfld=LEG",
            "",
            "Node Report Summary:",
            "----------------------------",
            "Reports Posted: 2",
            " Latest Report: NAME=abe,X=10,Y=-20.5,SPD=1.5,HDG=90,DEP=0,",
            "                TYPE=kayak,COLOR=yellow,GROUP=red,MODE=DRIVE,",
            "                ALLSTOP=clear,INDEX=1,TIME=1003,LENGTH=4",
            " Latest GT Report: NAME=abe_GT,X=11,Y=-21,TYPE=kayak,COLOR=yellow,",
            "                   GROUP=red,MODE=DRIVE,ALLSTOP=clear,INDEX=2,",
            "                   TIME=1003,LENGTH=4",
        ];
        let lines: Vec<&str> = body.split('\n').collect();
        assert_eq!(lines.last(), Some(&""), "every line ends with a newline");
        assert_eq!(lines[..lines.len() - 1], expected);
        assert_eq!(
            nr.take_appcast_notes(),
            [
                AppcastNote::Warning("Waiting for NAV_X/Y or NAV_LAT/LONG".into()),
                AppcastNote::Retract("Waiting for NAV_X/Y or NAV_LAT/LONG".into()),
            ]
        );
        assert!(nr.take_appcast_notes().is_empty());
    }

    #[test]
    fn appcast_helpers() {
        assert_eq!(moos_types::fmt::g_string(0.6, 6), "0.6");
        assert_eq!(moos_types::fmt::g_string(2.0, 6), "2");
        assert_eq!(moos_types::fmt::g_string(1234567.0, 6), "1.23457e+06");
        assert_eq!(moos_types::fmt::g_string(0.00001, 6), "1e-05");
        let mut s = String::new();
        write_block(&mut s, "L: ", "", 50);
        assert_eq!(s, "L: ");
        let spec = RiderConfig::parse("var=A, policy=2.5").unwrap().spec();
        assert_eq!(spec, "var=A, policy=2.5");
        let spec = RiderConfig::parse("var=A, policy=updated").unwrap().spec();
        assert_eq!(spec, "var=A, policy=updated");
    }
}
