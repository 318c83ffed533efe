//! pSafety's `ProcessConfig` block: rules and settings, every problem a located error.
//!
//! Nothing is left at a guess: an unknown key, a bad value and a rule that cannot be read are
//! each a [`Diagnostic`] (severity error, kind `AppSetting`, at its `file:line`), and any of
//! them puts the supervisor in MALCONFIG (see [`crate::supervisor`]): it still runs the
//! rules it could read, and it keeps the vehicle from deploying.

use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::ProcessConfig;

use crate::rule::{Action, Rule, parse_rule};

/// How the supervisor brings the vehicle up on `surface_disarm`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SurfaceVia {
    /// Manual override (the helm parks) and the actuators driven by pSafety.
    Direct,
    /// The helm's mission brings it up (`SAFETY_MODE = SURFACE` and the surface flags for the
    /// `.bhv` to condition on); pSafety takes the actuators when the helm fails.
    Helm,
}

/// A `VAR=VALUE` posting of a flag (`surface_flag`, `disarm_flag`, ...).
#[derive(Debug, Clone, PartialEq)]
pub struct Flag {
    /// The variable.
    pub var: String,
    /// The value: a number posts a double, anything else a string.
    pub value: moos_types::Value,
}

impl Flag {
    /// Reads `VAR=VALUE` (no white space in VAR, a value present).
    pub fn parse(text: &str) -> Option<Flag> {
        let (var, value) = text.split_once('=')?;
        let (var, value) = (var.trim(), value.trim());
        if var.is_empty() || var.contains(char::is_whitespace) || value.is_empty() {
            return None;
        }
        let value = match value.parse::<f64>() {
            Ok(x) if x.is_finite() => moos_types::Value::Double(x),
            _ => moos_types::Value::text(value.trim_matches('"')),
        };
        Some(Flag {
            var: var.to_string(),
            value,
        })
    }
}

/// Everything the block says.
#[derive(Debug, Clone, PartialEq)]
pub struct SafetyConfig {
    /// The rules, in block order.
    pub rules: Vec<Rule>,
    /// `depth_var`: the depth the surfacing is judged on (NAV_DEPTH).
    pub depth_var: String,
    /// `surface_depth`: m, the vehicle is up when shallower (0.3).
    pub surface_depth: f64,
    /// `surface_hold`: s, up for this long before disarming (5).
    pub surface_hold: f64,
    /// `surface_timeout`: s, disarm anyway after this long surfacing (300).
    pub surface_timeout: f64,
    /// `surface_via`: `direct` (default) or `helm`.
    pub surface_via: SurfaceVia,
    /// `helm_app`: the helm watched when surfacing through it (pHelmIvP).
    pub helm_app: String,
    /// `helm_timeout`: s of silence that make the helm failed (5).
    pub helm_timeout: f64,
    /// `helm_grace`: s the helm has to raise the vehicle by 0.5 m (60).
    pub helm_grace: f64,
    /// `override_var`: MOOS_MANUAL_OVERRIDE (empty: `none`, never posted).
    pub override_var: String,
    /// `thrust_var`, `elevator_var`, `rudder_var`: the actuators (DESIRED_THRUST, ...;
    /// empty: `none`, never posted).
    pub thrust_var: String,
    /// See `thrust_var`.
    pub elevator_var: String,
    /// See `thrust_var`.
    pub rudder_var: String,
    /// `surface_thrust`: the thrust while surfacing on the actuators (20).
    pub surface_thrust: f64,
    /// `surface_elevator`: the elevator while surfacing (-100: uSimMarine rises on negative).
    pub surface_elevator: f64,
    /// `surface_flag`: posted when surfacing starts (e.g. `COUG_SURFACE=true`).
    pub surface_flags: Vec<Flag>,
    /// `disarm_flag`: posted at the disarm (e.g. `DEPLOY=false`, which disarms pCougControls).
    pub disarm_flags: Vec<Flag>,
    /// `return_flag`: posted when a return is commanded (e.g. `RETURN=true`).
    pub return_flags: Vec<Flag>,
    /// `clear_flag`: posted when every rule has let go (e.g. `RETURN=false`).
    pub clear_flags: Vec<Flag>,
    /// `allstop_flag`: posted when an all-stop starts (e.g. `DEPLOY=false`, which disarms pCougControls).
    pub allstop_flags: Vec<Flag>,
    /// `max_gap`: s of MOOS time; a gap between two of the supervisor's own evaluations
    /// longer than this (or than two of its periods, if longer) is time it did not watch,
    /// and `stale`/`silent` ages leave the excess out (1).
    pub max_gap: f64,
}

impl Default for SafetyConfig {
    fn default() -> Self {
        SafetyConfig {
            rules: Vec::new(),
            depth_var: "NAV_DEPTH".into(),
            surface_depth: 0.3,
            surface_hold: 5.0,
            surface_timeout: 300.0,
            surface_via: SurfaceVia::Direct,
            helm_app: "pHelmIvP".into(),
            helm_timeout: 5.0,
            helm_grace: 60.0,
            override_var: "MOOS_MANUAL_OVERRIDE".into(),
            thrust_var: "DESIRED_THRUST".into(),
            elevator_var: "DESIRED_ELEVATOR".into(),
            rudder_var: "DESIRED_RUDDER".into(),
            surface_thrust: 20.0,
            surface_elevator: -100.0,
            surface_flags: Vec::new(),
            disarm_flags: Vec::new(),
            return_flags: Vec::new(),
            clear_flags: Vec::new(),
            allstop_flags: Vec::new(),
            max_gap: 1.0,
        }
    }
}

/// Keys of the generic MOOS app layer (CMOOSApp, AppCastingMOOSApp), accepted and ignored.
const GENERIC_KEYS: &[&str] = &[
    "apptick",
    "commstick",
    "maxapptick",
    "iteratemode",
    "term_reporting",
    "app_logging",
    "max_appcast_events",
    "max_appcast_run_warnings",
    "uselogging",
    "debug",
    "deprecated_ok",
];

/// The MOOS name of the app.
pub const PROGRAM: &str = "pSafety";

impl SafetyConfig {
    /// Reads a block; the errors (empty when the block is good) say what and where.
    pub fn from_block(block: &ProcessConfig) -> (SafetyConfig, Vec<Diagnostic>) {
        let mut c = SafetyConfig::default();
        let mut errors = Vec::new();
        for p in &block.entries {
            let key = p.key.trim().to_ascii_lowercase();
            let value = p.value.trim();
            let mut err = |msg: String| {
                errors.push(Diagnostic::line_warning(
                    DiagnosticKind::AppSetting,
                    &p.span,
                    format!("{PROGRAM}: {msg}"),
                ));
            };
            if GENERIC_KEYS.contains(&key.as_str()) {
                continue;
            }
            let num = value.parse::<f64>().ok().filter(|x| x.is_finite());
            let word = (!value.is_empty() && !value.contains(char::is_whitespace))
                .then(|| value.to_string());
            let bad = |what: &str| format!("`{} = {value}`: expected {what}", p.key.trim());
            let ok = match key.as_str() {
                "rule" => match parse_rule(value) {
                    Ok(r) if c.rules.iter().any(|o| o.name.eq_ignore_ascii_case(&r.name)) => {
                        err(format!("rule `{}` is defined twice", r.name));
                        true
                    }
                    Ok(r) => {
                        c.rules.push(r);
                        true
                    }
                    Err(e) => {
                        err(format!("rule `{value}`: {e}"));
                        true
                    }
                },
                "depth_var" => word.map(|w| c.depth_var = w).is_some(),
                "override_var" | "thrust_var" | "elevator_var" | "rudder_var" => {
                    // `none`: not posted (e.g. pCougControls stops on the override).
                    let w = word.map(|w| {
                        if w.eq_ignore_ascii_case("none") {
                            String::new()
                        } else {
                            w
                        }
                    });
                    let slot = match key.as_str() {
                        "override_var" => &mut c.override_var,
                        "thrust_var" => &mut c.thrust_var,
                        "elevator_var" => &mut c.elevator_var,
                        _ => &mut c.rudder_var,
                    };
                    w.map(|w| *slot = w).is_some()
                }
                "helm_app" => word.map(|w| c.helm_app = w).is_some(),
                "surface_depth" => num
                    .filter(|x| *x > 0.0)
                    .map(|x| c.surface_depth = x)
                    .is_some(),
                "surface_hold" => num
                    .filter(|x| *x >= 0.0)
                    .map(|x| c.surface_hold = x)
                    .is_some(),
                "surface_timeout" => num
                    .filter(|x| *x > 0.0)
                    .map(|x| c.surface_timeout = x)
                    .is_some(),
                "helm_timeout" => num
                    .filter(|x| *x > 0.0)
                    .map(|x| c.helm_timeout = x)
                    .is_some(),
                "helm_grace" => num.filter(|x| *x > 0.0).map(|x| c.helm_grace = x).is_some(),
                "max_gap" => num.filter(|x| *x > 0.0).map(|x| c.max_gap = x).is_some(),
                "surface_thrust" => num
                    .filter(|x| (0.0..=100.0).contains(x))
                    .map(|x| c.surface_thrust = x)
                    .is_some(),
                "surface_elevator" => num
                    .filter(|x| (-100.0..=100.0).contains(x))
                    .map(|x| c.surface_elevator = x)
                    .is_some(),
                "surface_via" => match value.to_ascii_lowercase().as_str() {
                    "direct" => {
                        c.surface_via = SurfaceVia::Direct;
                        true
                    }
                    "helm" => {
                        c.surface_via = SurfaceVia::Helm;
                        true
                    }
                    _ => false,
                },
                "surface_flag" | "disarm_flag" | "return_flag" | "clear_flag" | "allstop_flag" => {
                    match Flag::parse(value) {
                        Some(f) => {
                            match key.as_str() {
                                "surface_flag" => c.surface_flags.push(f),
                                "disarm_flag" => c.disarm_flags.push(f),
                                "return_flag" => c.return_flags.push(f),
                                "allstop_flag" => c.allstop_flags.push(f),
                                _ => c.clear_flags.push(f),
                            }
                            true
                        }
                        None => false,
                    }
                }
                _ => {
                    err(format!("unknown parameter `{}`", p.key.trim()));
                    true
                }
            };
            if !ok {
                let what = match key.as_str() {
                    "surface_via" => "direct or helm",
                    "surface_thrust" => "a number from 0 to 100",
                    "surface_elevator" => "a number from -100 to 100",
                    "surface_hold" => "seconds >= 0",
                    k if k.ends_with("_flag") => "VAR=VALUE",
                    k if k.ends_with("_var") || k == "helm_app" => "a name without spaces",
                    _ => "a positive number",
                };
                err(bad(what));
            }
        }
        if c.rules.is_empty() && errors.is_empty() {
            errors.push(Diagnostic::line_warning(
                DiagnosticKind::AppSetting,
                &block.span,
                format!("{PROGRAM}: no `rule =` line: the supervisor would guard nothing"),
            ));
        }
        if c.rules.iter().any(|r| r.action == Action::Return) && c.return_flags.is_empty() {
            errors.push(Diagnostic::line_warning(
                DiagnosticKind::AppSetting,
                &block.span,
                format!("{PROGRAM}: a rule returns but no `return_flag` says how"),
            ));
        }
        let errors = errors
            .into_iter()
            .map(|mut d| {
                d.severity = mission::diagnostic::Severity::Error;
                d
            })
            .collect();
        (c, errors)
    }
}
