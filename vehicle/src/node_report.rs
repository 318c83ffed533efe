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
//!
//! Not implemented yet, each reported as a config warning when set (the app runs on without
//! it): platform reports, alternative-nav reports, extrapolation pruning,
//! blackout variance.
//!
//! # Conformance with pNodeReporter (MOOS-IvP a2a9b716)
//!
//! A bad value or a setting coug does not implement is a config warning; the app runs on.
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | platform_type | vessel_type | text | unknown | any | no | done |
//! | platform_color | | colour | none | a colour | PLATFORM_COLOR, NODE_COLOR_CHANGE (allow_color_change) | open: colour names not checked |
//! | platform_length | vessel_length | m | by type | number >= 0 | no | done |
//! | platform_beam | | m | none | number >= 0 | no | open: implemented, untested |
//! | platform_transparency | | number | none | number | no | open: implemented, untested |
//! | platform_group | group | text | none | any | NODE_GROUP_UPDATE | done |
//! | coord_policy_global | | bool | false | MOOS boolean | no | done |
//! | terse_reports | | bool | false | MOOS boolean | no | done |
//! | blackout_interval | | s | 0 | number >= 0 | no | done |
//! | node_report_output | node_report_summary, node_report_var | var | NODE_REPORT_LOCAL | no white space | no | done |
//! | nohelm_threshold | | s | 5 | number > 0 | no | open: implemented, untested |
//! | nav_grace_period | | s | 60 | number | no | open: implemented, untested |
//! | paused | | bool | false | MOOS boolean | PNR_PAUSE | open: implemented, untested |
//! | allow_color_change | | bool | false | MOOS boolean | no | open: implemented, untested |
//! | cross_fill_policy | crossfill_policy | enum | literal | literal, fill-empty, global, use-latest, local, global-terse (`_` read as `-`); fills before each report with the mission's origin | no | done |
//! | platform_aspect | | `key=value` | none | both sides non-empty, no second `=`; appended to the reports in key order | no | done |
//! | blackout_variance | | s | 0 | >= 0 | no | refused: warning, not implemented |
//! | rider | | `var=..,policy=always\|updated\|updated+S\|S,rfld=..,prec=..` | none | not a report field; policy, alphanumeric rfld, prec >= 0 (max 10); one per variable; subscribed | yes (mail) | done |
//! | plat_report_input | plat_report_var, platform_variable | spec | none | | no | refused: warning, platform reports not implemented |
//! | plat_report_output | | var | PLATFORM_REPORT_LOCAL | | no | refused: warning |
//! | platform_vsource | vsource | text | none | any; `VSOURCE=` after GROUP | no | done |
//! | alt_nav_prefix, alt_nav_name, alt_nav_group | | text | none | | no | refused: warning, alternative-nav reports not implemented |
//! | extrap_enabled, extrap_pos_thresh, extrap_hdg_thresh, extrap_max_gap | | | | | no | refused: warning, extrapolation pruning not implemented |
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
//! | PLATFORM_REPORT_LOCAL | platform reports | | refused (see plat_report_input) |
//! | PNR_EXTRAP_POS_GAP, PNR_EXTRAP_HDG_GAP | extrapolation | | refused (see extrap_*) |
//! | PNR_MHASH | after MISSION_HASH, when the largest distance from the start grows by 2 % and 1 m | `mhash=<hash>,ext=<m, 1 decimal>` | done |
//! | PNODEREPORTER_PID | start-up | pid | open: not posted |

use std::fmt::Write as _;
use std::sync::Arc;

use crate::angle::{angle360, heading_to_radians};
use crate::config::{ConfigError, Param, apply_params, strict};
use crate::moos::{MailValue, Posting, push_double_x};

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
        }
    }
}

/// The length pNodeReporter assumes for a platform type when none is configured.
pub fn default_length(platform_type: &str) -> Option<f64> {
    Some(match platform_type.to_ascii_lowercase().as_str() {
        "kayak" | "mokai" | "auv" | "uuv" => 4.0,
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
            "platform_type" | "vessel_type" => self.platform_type = p.word()?,
            "platform_color" => self.platform_color = Some(p.word()?),
            "platform_length" | "vessel_length" => self.platform_length = p.non_neg()?,
            "platform_beam" => self.platform_beam = Some(p.non_neg()?),
            "platform_group" | "group" => self.group = Some(p.word()?),
            "platform_transparency" => self.transparency = Some(p.f64()?),
            "coord_policy_global" => self.coord_policy_global = p.bool()?,
            "terse_reports" => self.terse_reports = p.bool()?,
            "blackout_interval" => self.blackout_interval = p.non_neg()?,
            "node_report_output" | "node_report_summary" | "node_report_var" => {
                self.node_report_output = p.word()?
            }
            "nohelm_threshold" => self.nohelm_threshold = p.pos()?,
            "nav_grace_period" => self.nav_grace_period = p.f64()?,
            "paused" => self.paused = p.bool()?,
            "allow_color_change" => self.allow_color_change = p.bool()?,
            "report_cog" => self.report_cog = p.bool()?,
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
                    "global" | "global-terse" => CrossFill::Global,
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
            "blackout_variance" | "plat_report_input" | "plat_report_var" | "platform_variable"
            | "plat_report_output" | "alt_nav_prefix" | "alt_nav_name" | "alt_nav_group"
            | "extrap_enabled" | "extrap_pos_thresh" | "extrap_hdg_thresh" | "extrap_max_gap" => {
                return Err(
                    p.bad("a setting coug's node reporter implements (not implemented yet)")
                );
            }
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
    /// X/Y from LAT/LON when both are known (`global`, `global-terse`).
    Global,
    /// LAT/LON from X/Y when both are known.
    Local,
    /// Fill the pair never received from the other.
    FillEmpty,
    /// Fill the staler pair from the fresher one.
    UseLatest,
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

/// A rider's latest value and freshness.
#[derive(Debug, Clone, Default)]
struct RiderState {
    value: String,
    last_time: f64,
    fresh: bool,
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
    /// Last `IVPHELM_ALLSTOP` (`unknown`).
    pub allstop: String,
}

impl Default for HelmInfo {
    fn default() -> Self {
        HelmInfo {
            last_msg: None,
            status_primary: "unknown".to_string(),
            status_standby: String::new(),
            modes: "none".to_string(),
            allstop: "unknown".to_string(),
        }
    }
}

impl HelmInfo {
    /// The MODE field at time `now`.
    pub fn mode(&self, now: f64, nohelm_threshold: f64) -> String {
        match self.last_msg {
            None => "NOHELM-EVER".to_string(),
            Some(t) if now - t > nohelm_threshold => format!("NOHELM-{:.0}", now - t),
            Some(_) => {
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
}

/// Appends a `NODE_REPORT_LOCAL` string to `out` (the `NodeRecord::getSpec` layout).
pub fn write_report(out: &mut String, cfg: &NodeReportConfig, r: &ReportInputs<'_>) {
    let num = |out: &mut String, key: &str, v: f64, digits: usize| {
        out.push_str(key);
        push_double_x(out, v, digits);
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
    buf: String,
    var_report: Arc<str>,
    var_first: Arc<str>,
    var_gap: Arc<str>,
    var_mhash: Arc<str>,
}

impl NodeReporter {
    /// A reporter for vehicle `name` (the MOOS community), started at `start_time`.
    pub fn new(cfg: NodeReportConfig, name: &str, start_time: f64) -> Self {
        let rider_count = cfg.riders.len();
        NodeReporter {
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
    pub fn subscriptions() -> &'static [&'static str] {
        &[
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

    /// The mission's local grid (from LatOrigin/LongOrigin), for the cross-fill policies.
    pub fn with_grid(mut self, grid: Option<crate::geodesy::LocalGrid>) -> Self {
        self.grid = grid;
        self
    }

    /// Fills X/Y or LAT/LON of the kept record as the policy says (before a report).
    fn cross_fill(&mut self) {
        let Some(grid) = &self.grid else {
            return;
        };
        let n = &mut self.nav;
        let (xy, ll) = (n.x.zip(n.y), n.lat.zip(n.lon));
        let to_local = |(lat, lon): (f64, f64)| grid.to_local(lat, lon).ok();
        let to_global = |(x, y): (f64, f64)| grid.to_latlon(x, y).ok();
        let fill = match self.cfg.crossfill {
            CrossFill::Literal => None,
            CrossFill::Global => ll.and_then(to_local).map(|p| (true, p)),
            CrossFill::Local => xy.and_then(to_global).map(|p| (false, p)),
            CrossFill::FillEmpty => match (n.x.is_none() && n.y.is_none(), ll, xy) {
                (true, Some(g), _) => to_local(g).map(|p| (true, p)),
                (false, _, Some(l)) if n.lat.is_none() && n.lon.is_none() => {
                    to_global(l).map(|p| (false, p))
                }
                _ => None,
            },
            CrossFill::UseLatest if self.xy_time == self.latlon_time => None,
            CrossFill::UseLatest if self.xy_time < self.latlon_time => {
                ll.and_then(to_local).map(|p| (true, p))
            }
            CrossFill::UseLatest => xy.and_then(to_global).map(|p| (false, p)),
        };
        match fill {
            Some((true, (x, y))) => (n.x, n.y) = (Some(x), Some(y)),
            Some((false, (lat, lon))) => (n.lat, n.lon) = (Some(lat), Some(lon)),
            None => {}
        }
    }

    /// The rider variables (subscribed in addition to [`NodeReporter::subscriptions`]).
    pub fn rider_vars(&self) -> impl Iterator<Item = &str> {
        self.cfg.riders.iter().map(|r| r.var.as_str())
    }

    /// The riders' part of a report (MOOS `NodeRiderSet::getRiderReports`), with its quirks:
    /// an `updated` rider repeated by its period rides under the variable's name, and a rider
    /// with nothing to say after one that did leaves a trailing comma.
    fn rider_reports(&mut self, now: f64) -> String {
        let mut reports = String::new();
        for (cfg, st) in self.cfg.riders.iter().zip(&mut self.riders) {
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

    /// Takes one piece of mail received at `time`.
    pub fn on_mail(&mut self, var: &str, value: MailValue<'_>, time: f64) {
        let d = value.as_f64();
        let s = value.as_str().unwrap_or("");
        for (cfg, state) in self.cfg.riders.iter().zip(&mut self.riders) {
            if cfg.var == var {
                state.value = match (s, d) {
                    ("", Some(x)) => format!("{x:.*}", cfg.precision),
                    _ => s.to_string(),
                };
                state.last_time = time;
                state.fresh = true;
            }
        }
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
            ("NAV_TRANSP", Some(v)) => self.transparency = Some(v),
            ("PLATFORM_COLOR", _) if !s.trim().is_empty() => {
                self.color = Some(s.trim().to_string())
            }
            ("NODE_COLOR_CHANGE", _) if self.cfg.allow_color_change && !s.trim().is_empty() => {
                self.color = Some(s.trim().to_string())
            }
            ("THRUST_MODE_REVERSE", _) => self.thrust_mode_reverse = s.eq_ignore_ascii_case("true"),
            ("AUX_MODE", _) => self.mode_aux = Some(s.to_string()),
            ("MISSION_HASH", _) => {
                // The `mhash=` token of the posting; a new mission restarts the extent.
                self.mhash = s
                    .split(',')
                    .filter_map(|t| t.split_once('='))
                    .find(|(k, _)| k.trim() == "mhash")
                    .map(|(_, v)| v.trim().to_string())
                    .unwrap_or_default();
                self.odo.max_extent_mission = 0.0;
                self.odo.reset_extent();
            }
            ("PNR_PAUSE", _) => {
                if let Some(b) = crate::config::parse_bool(s) {
                    self.paused = b;
                }
            }
            ("LOAD_WARNING", _) => {
                let field = |k: &str| {
                    s.split(',').find_map(|kv| {
                        let (a, b) = kv.split_once('=')?;
                        (a.trim() == k).then(|| b.trim().to_string())
                    })
                };
                if let (Some(app), Some(gap)) = (field("app"), field("maxgap")) {
                    self.load_warning = Some(format!("{app}:{gap}"));
                }
            }
            ("NODE_GROUP_UPDATE", _) => self.group = Some(s.to_string()),
            ("IVPHELM_SUMMARY", _) => {
                self.helm.last_msg = Some(time);
                for kv in s.split(',') {
                    if let Some(("modes", m)) =
                        kv.split_once('=').map(|(a, b)| (a.trim(), b.trim()))
                    {
                        self.helm.modes = m.to_string();
                    }
                }
            }
            ("IVPHELM_ALLSTOP", _) => {
                self.helm.last_msg = Some(time);
                self.helm.allstop = s.to_string();
            }
            ("IVPHELM_STATE", _) => {
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
                if st.starts_with("MALCONFIG") {
                    self.helm.allstop = "n/a".to_string();
                }
            }
            _ => {}
        }
    }

    /// One iteration at `now`; appends `NODE_REPORT_LOCAL` (and `_FIRST`, `PNR_POST_GAP`).
    pub fn iterate(&mut self, now: f64, out: &mut Vec<Posting>) {
        let time_to_post = match self.last_post_time {
            None => true,
            Some(t) => self.cfg.blackout_interval <= 0.0 || now - t > self.cfg.blackout_interval,
        };
        let in_grace =
            self.cfg.nav_grace_period > 0.0 && now - self.start_time < self.cfg.nav_grace_period;
        let ok_nav = self.nav.valid() || in_grace;
        let has_pos = (self.nav.x.is_some() && self.nav.y.is_some())
            || (self.nav.lat.is_some() && self.nav.lon.is_some());
        let post = ok_nav && time_to_post && (has_pos || !in_grace) && !self.paused;
        if post {
            let gap = self.last_post_time.map_or(0.0, |t| now - t);
            let mode = self.helm.mode(now, self.cfg.nohelm_threshold);
            self.cross_fill();
            // HDG_ERROR: the posted report carries the heading plus the error.
            let mut nav = self.nav;
            if self.cfg.hdg_error_deg != 0.0 {
                nav.heading = nav.heading.map(|h| angle360(h + self.cfg.hdg_error_deg));
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
            };
            self.buf.clear();
            write_report(&mut self.buf, &self.cfg, &inputs);
            let riders = self.rider_reports(now);
            if !riders.is_empty() {
                self.buf.push(',');
                self.buf.push_str(&riders);
            }
            let json = &self.cfg.json_report;
            let first = self.reports_posted == 0;
            if json.is_empty() {
                if first {
                    out.push(Posting::string(&self.var_first, self.buf.as_str()));
                }
                out.push(Posting::string(&self.var_report, self.buf.as_str()));
            } else if json.eq_ignore_ascii_case("true") {
                let j = csp_to_json(&self.buf);
                if first {
                    out.push(Posting::string(&self.var_first, j.as_str()));
                }
                out.push(Posting::string(&self.var_report, j));
            } else {
                let j = csp_to_json(&self.buf);
                if first {
                    let var: Arc<str> = format!("{json}_FIRST").into();
                    out.push(Posting::string(&var, j.as_str()));
                    out.push(Posting::string(&self.var_first, self.buf.as_str()));
                }
                let var: Arc<str> = json.as_str().into();
                out.push(Posting::string(&var, j));
                out.push(Posting::string(&self.var_report, self.buf.as_str()));
            }
            out.push(Posting::double(&self.var_gap, gap));
            self.reports_posted += 1;
            self.last_post_time = Some(now);
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
        // MISSION_HASH odometer: the largest distance from where the mission started,
        // posted when it has grown by 2 % and at least 1 m (MOOS `updateMHashOdo`).
        if !self.mhash.is_empty()
            && let Some(ext) = self
                .odo
                .update(self.nav.x.unwrap_or(0.0), self.nav.y.unwrap_or(0.0))
        {
            let mut msg = format!("mhash={},ext=", self.mhash);
            push_double_x(&mut msg, ext, 1);
            out.push(Posting::string(&self.var_mhash, msg));
        }
    }
}
