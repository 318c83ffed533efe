//! pHelmIvP's ProcessConfig block (reference §4.1) and the globals the helm needs.

use ivp::{Domain, DomainVar};

/// A configuration problem. Any of these puts the helm in MALCONFIG (reference §4.1).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConfigError {
    /// A parameter pHelmIvP does not know.
    #[error("Unhandled config line: {key} = {value}")]
    UnknownParam {
        /// The key as written.
        key: String,
        /// The value.
        value: String,
    },
    /// A known parameter with a bad value.
    #[error("Bad config line: {key} = {value} (expected {expected})")]
    BadValue {
        /// The key as written.
        key: String,
        /// The value.
        value: String,
        /// What is accepted.
        expected: String,
    },
    /// A required global (`LatOrigin`, `LongOrigin`, `Community`) is missing.
    #[error("Missing global {0}")]
    MissingGlobal(&'static str),
    /// No `domain` lines.
    #[error("No decision domain configured (domain = course:0:359:360 ...)")]
    NoDomain,
    /// A problem in the behaviour file.
    #[error("{0}")]
    Behavior(String),
    /// A bad value of a parameter the appcasting layer reads (`TERM_REPORT_INTERVAL`,
    /// `MAX_APPCAST_EVENTS`, `MAX_APPCAST_RUN_WARNINGS`), in libMOOS's words.
    #[error("{0}")]
    Appcast(String),
}

/// The mission-file globals pHelmIvP reads.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Globals {
    /// `LatOrigin`.
    pub lat_origin: Option<String>,
    /// `LongOrigin`.
    pub long_origin: Option<String>,
    /// `Community` (the vehicle name, `$[OWNSHIP]`).
    pub community: Option<String>,
}

impl Globals {
    /// Globals from a parsed `.moos` file.
    pub fn from_mission(m: &mission::moos::MissionFile) -> Self {
        Globals {
            lat_origin: m.global("LatOrigin").map(str::to_string),
            long_origin: m.global("LongOrigin").map(str::to_string),
            community: m.global("Community").map(str::to_string),
        }
    }
}

/// The helm's settings. Defaults as in pHelmIvP.
#[derive(Debug, Clone, PartialEq)]
pub struct HelmConfig {
    /// Decision domain, in pHelmIvP's order: the REVERSE of the `domain =` lines (pHelmIvP reads
    /// its block in reverse; reference §1).
    pub domain: Domain,
    /// `ok_skew` seconds; `None` = `any` (skew ignored).
    pub ok_skew: Option<f64>,
    /// `start_engaged` (and aliases): start in DRIVE.
    pub start_engaged: bool,
    /// `allow_park`: MOOS_MANUAL_OVERRIDE=true may park the helm.
    pub allow_park: bool,
    /// `park_on_allstop`.
    pub park_on_allstop: bool,
    /// `helm_alias`.
    pub helm_alias: String,
    /// `helm_prefix` on decision postings.
    pub helm_prefix: String,
    /// `nav_grace` seconds.
    pub nav_grace: f64,
    /// `goals_mandatory`: all-stop (`NoGoalBehavior`) when no active behaviour is a goal
    /// behaviour (see `behaviors::Behavior::is_constraint`).
    pub goals_mandatory: bool,
    /// `other_override_var`.
    pub other_override_var: String,
    /// `behaviors` files, in file order.
    pub behavior_files: Vec<String>,
    /// `standby` seconds. Standby helms are not supported yet: setting it is a configuration
    /// error rather than a silently different helm.
    pub standby: Option<f64>,
    /// `verbose`.
    pub verbose: String,
    /// `contact_max_age` seconds.
    pub contact_max_age: f64,
    /// `seed_random`.
    pub seed_random: bool,
    /// `hold_on_apps`.
    pub hold_on_apps: Vec<String>,
    /// `node_skew` entries.
    pub node_skews: Vec<(String, f64)>,
    /// `pmgen`: the platform-model generator (holonomic unless set).
    pub pmgen: crate::plat_model::PmGen,
}

impl Default for HelmConfig {
    fn default() -> Self {
        HelmConfig {
            domain: Domain::new(),
            ok_skew: Some(60.0),
            start_engaged: false,
            allow_park: true,
            park_on_allstop: false,
            helm_alias: String::new(),
            helm_prefix: String::new(),
            nav_grace: 5.0,
            goals_mandatory: false,
            other_override_var: String::new(),
            behavior_files: Vec::new(),
            standby: None,
            verbose: "verbose".into(),
            contact_max_age: 45.0,
            seed_random: true,
            hold_on_apps: Vec::new(),
            node_skews: Vec::new(),
            pmgen: crate::plat_model::PmGen::default(),
        }
    }
}

/// A MOOS boolean as pHelmIvP reads it (MOOS-IvP `setBooleanOnString`, case-insensitive):
/// `true`/`yes`/`on`, `false`/`no`/`off`, or `toggle` (flips `current`).
fn boolean(v: &str, current: bool) -> Option<bool> {
    moos_types::text::set_boolean_on_string(current, v.trim())
}

fn number(v: &str) -> Option<f64> {
    let t = v.trim();
    if mission::condition::is_numeric(t) {
        t.parse().ok()
    } else {
        None
    }
}

impl HelmConfig {
    /// Reads the pHelmIvP block (`key`, `value` pairs in file order) and the globals.
    /// Never fails: problems are returned alongside the best-effort configuration.
    ///
    /// ```
    /// use helm::config::{Globals, HelmConfig};
    /// let g = Globals { lat_origin: Some("43".into()), long_origin: Some("-70".into()), community: Some("abe".into()) };
    /// let (c, errs) = HelmConfig::parse(&[("domain", "course:0:359:360"), ("domain", "speed:0:4:41"), ("bogus", "1")], &g);
    /// assert_eq!(c.domain.to_string(), "speed,0,4,41:course,0,359,360");
    /// assert_eq!(errs.len(), 1);
    /// ```
    pub fn parse<K: AsRef<str>, V: AsRef<str>>(
        params: &[(K, V)],
        globals: &Globals,
    ) -> (HelmConfig, Vec<ConfigError>) {
        let mut c = HelmConfig::default();
        let mut errs = Vec::new();
        let mut domain_vars: Vec<DomainVar> = Vec::new();
        for (k, v) in params {
            let (key, value) = (k.as_ref().trim(), v.as_ref().trim());
            let bad = |expected: &str| ConfigError::BadValue {
                key: key.to_string(),
                value: value.to_string(),
                expected: expected.to_string(),
            };
            let set_bool =
                |slot: &mut bool, errs: &mut Vec<ConfigError>| match boolean(value, *slot) {
                    Some(b) => *slot = b,
                    None => errs.push(bad("true, false, yes, no, on, off or toggle")),
                };
            match key.to_ascii_lowercase().as_str() {
                "behaviors" => {
                    if c.behavior_files.iter().any(|f| f == value) {
                        errs.push(bad("a behaviour file not already given"));
                    } else {
                        c.behavior_files.push(value.to_string());
                    }
                }
                "domain" => match DomainVar::parse(value) {
                    Ok(d) => domain_vars.push(d),
                    Err(e) => errs.push(bad(&e.to_string())),
                },
                "ok_skew" => {
                    if value.eq_ignore_ascii_case("any") {
                        c.ok_skew = None;
                    } else {
                        match number(value) {
                            Some(s) if s >= 0.0 => c.ok_skew = Some(s),
                            _ => errs.push(bad("seconds >= 0 or any")),
                        }
                    }
                }
                "verbose" => match value.to_ascii_lowercase().as_str() {
                    "verbose" | "true" | "terse" | "false" | "quiet" => {
                        c.verbose = value.to_ascii_lowercase()
                    }
                    _ => errs.push(bad("verbose, terse or quiet")),
                },
                "start_engaged" | "active_start" | "start_indrive" | "start_in_drive" => {
                    set_bool(&mut c.start_engaged, &mut errs)
                }
                "allow_park" => set_bool(&mut c.allow_park, &mut errs),
                "park_on_allstop" => set_bool(&mut c.park_on_allstop, &mut errs),
                "goals_mandatory" => set_bool(&mut c.goals_mandatory, &mut errs),
                "seed_random" => set_bool(&mut c.seed_random, &mut errs),
                "helm_alias" | "helm_prefix" | "other_override_var" => {
                    if value.is_empty() || value.contains(char::is_whitespace) {
                        errs.push(bad("a name without spaces"));
                    } else {
                        let slot = match key.to_ascii_lowercase().as_str() {
                            "helm_alias" => &mut c.helm_alias,
                            "helm_prefix" => &mut c.helm_prefix,
                            _ => &mut c.other_override_var,
                        };
                        *slot = value.to_string();
                    }
                }
                "standby" => match number(value) {
                    Some(s) if s > 0.0 => c.standby = Some(s),
                    _ => errs.push(bad("positive seconds")),
                },
                // Any number (MOOS `setDoubleOnString`: negative values are taken too).
                "nav_grace" => match number(value) {
                    Some(s) => c.nav_grace = s,
                    _ => errs.push(bad("seconds")),
                },
                // MOOS `setDoubleRngOnString(10, 1800)`: a value outside the range is clipped
                // AND reported, so the helm is MALCONFIG.
                "contact_max_age" => match number(value) {
                    Some(s) => {
                        c.contact_max_age = s.clamp(10.0, 1800.0);
                        if !(10.0..=1800.0).contains(&s) {
                            errs.push(bad("seconds in [10, 1800]"));
                        }
                    }
                    _ => errs.push(bad("seconds")),
                },
                // Comma-separated app names: each non-empty, without white space, and not
                // given before (in this line or an earlier one).
                "hold_on_app" | "hold_on_apps" => {
                    for app in value.split(',').map(str::trim) {
                        if app.is_empty()
                            || app.contains(char::is_whitespace)
                            || c.hold_on_apps.iter().any(|a| a == app)
                        {
                            errs.push(bad("app names, each once, without white space"));
                            break;
                        }
                        c.hold_on_apps.push(app.to_string());
                    }
                }
                // `vname,seconds`, one line per vehicle.
                "node_skew" => match value.split_once(',') {
                    Some((name, secs))
                        if !name.trim().is_empty()
                            && number(secs).is_some()
                            && !c.node_skews.iter().any(|(n, _)| n == name.trim()) =>
                    {
                        c.node_skews
                            .push((name.trim().to_string(), number(secs).unwrap_or(0.0)))
                    }
                    _ => errs.push(bad("vname,seconds (once per vehicle)")),
                },
                // Dynamic behaviour libraries are accepted; coug links its behaviours statically.
                "ivp_behavior_dir" | "ivp_behavior_dirs" => {}
                // The platform-model generator's settings (MOOS
                // `PlatModelGenerator::setParams`, see `crate::plat_model`).
                "pmgen" => {
                    if !c.pmgen.apply(v.as_ref()) {
                        errs.push(bad(
                            "alg=holo|dubins#... (dubins: radius/rad >= 0, spoke_degs/degs > 0, mod_radius, mod_spoke_degs)",
                        ))
                    }
                }
                "bhv_dir_not_found_ok" | "bhv_dirs_not_found_ok" => {
                    let mut ok = false;
                    set_bool(&mut ok, &mut errs)
                }
                // The lines AppCastingMOOSApp's unhandled-line check lets through (MOOS-IvP
                // a2a9b716); any other unknown line is a config warning, so MALCONFIG.
                k if mission::catalog::APP_CASTING_PARAMS.contains(&k) => {}
                _ => errs.push(ConfigError::UnknownParam {
                    key: key.to_string(),
                    value: value.to_string(),
                }),
            }
        }
        for d in domain_vars.into_iter().rev() {
            let name = d.name().to_string();
            if c.domain.add(d).is_err() {
                errs.push(ConfigError::BadValue {
                    key: "domain".into(),
                    value: name,
                    expected: "a variable not already in the domain".into(),
                });
            }
        }
        if c.domain.is_empty() {
            errs.push(ConfigError::NoDomain);
        }
        if globals.lat_origin.is_none() {
            errs.push(ConfigError::MissingGlobal("LatOrigin"));
        }
        if globals.long_origin.is_none() {
            errs.push(ConfigError::MissingGlobal("LongOrigin"));
        }
        if globals.community.is_none() {
            errs.push(ConfigError::MissingGlobal("Community"));
        }
        (c, errs)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn g() -> Globals {
        Globals {
            lat_origin: Some("43.8".into()),
            long_origin: Some("-70.3".into()),
            community: Some("alpha".into()),
        }
    }

    #[test]
    fn defaults_and_aliases() {
        let (c, e) = HelmConfig::parse(
            &[
                ("domain", "course,0,359,360"),
                ("start_in_drive", "TRUE"),
                ("ok_skew", "any"),
                ("AppTick", "4"),
                ("helm_prefix", "H1"),
            ],
            &g(),
        );
        assert!(e.is_empty(), "{e:?}");
        assert!(c.start_engaged && c.allow_park && !c.park_on_allstop);
        assert_eq!(c.ok_skew, None);
        assert_eq!(c.helm_prefix, "H1");
        assert_eq!(c.nav_grace, 5.0);
        assert!(!c.goals_mandatory);
    }

    #[test]
    fn goals_mandatory_is_accepted() {
        let (c, e) = HelmConfig::parse(
            &[("domain", "course,0,359,360"), ("goals_mandatory", "TRUE")],
            &g(),
        );
        assert!(e.is_empty(), "{e:?}");
        assert!(c.goals_mandatory);
        let (c, e) = HelmConfig::parse(
            &[
                ("domain", "course,0,359,360"),
                ("goals_mandatory", "perhaps"),
            ],
            &g(),
        );
        assert!(!c.goals_mandatory);
        assert_eq!(e.len(), 1, "{e:?}");
    }

    #[test]
    fn problems_are_reported() {
        let (_, e) = HelmConfig::parse(
            &[
                ("domain", "speed:0:4"),
                ("allow_park", "maybe"),
                ("behaviors", "a.bhv"),
                ("behaviors", "a.bhv"),
                ("foo", "bar"),
            ],
            &Globals::default(),
        );
        assert!(e.contains(&ConfigError::UnknownParam {
            key: "foo".into(),
            value: "bar".into()
        }));
        assert!(e.contains(&ConfigError::MissingGlobal("LatOrigin")));
        assert!(e.contains(&ConfigError::MissingGlobal("Community")));
        assert!(e.contains(&ConfigError::NoDomain));
        assert_eq!(
            e.iter()
                .filter(|x| matches!(x, ConfigError::BadValue { .. }))
                .count(),
            3
        );
    }

    fn parse_one(key: &str, value: &str) -> (HelmConfig, Vec<ConfigError>) {
        HelmConfig::parse(&[("domain", "course,0,359,360"), (key, value)], &g())
    }

    #[test]
    fn every_parameter_coug_check_accepts_is_one_the_helm_accepts() {
        // `coug check` (mission::catalog) and the helm must agree on the block's keys.
        for key in mission::catalog::HELM_PARAMS {
            let (_, e) = parse_one(key, "1");
            assert!(
                !e.iter()
                    .any(|e| matches!(e, ConfigError::UnknownParam { .. })),
                "{key}: {e:?}"
            );
        }
    }

    #[test]
    fn booleans_are_read_as_moos_set_boolean_on_string() {
        for (v, want) in [
            ("yes", true),
            ("ON", true),
            ("True", true),
            ("no", false),
            ("off", false),
        ] {
            let (c, e) = parse_one("start_engaged", v);
            assert!(e.is_empty(), "{v}: {e:?}");
            assert_eq!(c.start_engaged, want, "{v}");
        }
        // `toggle` flips the current value (allow_park defaults to true).
        let (c, e) = parse_one("allow_park", "toggle");
        assert!(e.is_empty() && !c.allow_park);
        let (_, e) = parse_one("park_on_allstop", "1");
        assert_eq!(e.len(), 1, "1 is not a MOOS boolean: {e:?}");
    }

    #[test]
    fn contact_max_age_out_of_range_is_clipped_and_reported() {
        let (c, e) = parse_one("contact_max_age", "60");
        assert!(e.is_empty() && c.contact_max_age == 60.0);
        for (v, clipped) in [("5", 10.0), ("4000", 1800.0)] {
            let (c, e) = parse_one("contact_max_age", v);
            assert_eq!(c.contact_max_age, clipped);
            assert_eq!(e.len(), 1, "{v}: {e:?}");
        }
    }

    #[test]
    fn node_skew_and_hold_on_apps_follow_the_cpp_rules() {
        let (c, e) = HelmConfig::parse(
            &[
                ("domain", "course,0,359,360"),
                ("node_skew", "abe,2"),
                ("node_skew", "ben, 3.5"),
            ],
            &g(),
        );
        assert!(e.is_empty(), "{e:?}");
        assert_eq!(c.node_skews, vec![("abe".into(), 2.0), ("ben".into(), 3.5)]);
        let (_, e) = HelmConfig::parse(
            &[
                ("domain", "course,0,359,360"),
                ("node_skew", "abe,2"),
                ("node_skew", "abe,4"),
            ],
            &g(),
        );
        assert_eq!(e.len(), 1, "a second skew for one vehicle: {e:?}");
        assert_eq!(parse_one("node_skew", "abe,soon").1.len(), 1);
        let (c, e) = parse_one("hold_on_apps", "pContactMgrV20, uFldNodeComms");
        assert!(e.is_empty(), "{e:?}");
        assert_eq!(c.hold_on_apps, ["pContactMgrV20", "uFldNodeComms"]);
        for bad in ["a,,b", "a,a", "p Contact"] {
            assert_eq!(parse_one("hold_on_app", bad).1.len(), 1, "{bad}");
        }
    }

    #[test]
    fn only_the_app_casting_lines_pass_the_unhandled_check() {
        for key in [
            "AppTick",
            "CommsTick",
            "MaxAppTick",
            "app_logging",
            "term_report_interval",
            "max_appcast_events",
            "deprecated_ok",
        ] {
            assert!(parse_one(key, "4").1.is_empty(), "{key}");
        }
        // Unhandled in pHelmIvP at a2a9b716 (config warning, hence MALCONFIG).
        for key in [
            "IterateMode",
            "max_appcast_run_warnings",
            "max_run_warnings",
        ] {
            let (_, e) = parse_one(key, "1");
            assert!(
                matches!(e[..], [ConfigError::UnknownParam { .. }]),
                "{key}: {e:?}"
            );
        }
        // nav_grace takes any number, as setDoubleOnString.
        let (c, e) = parse_one("nav_grace", "-1");
        assert!(e.is_empty() && c.nav_grace == -1.0);
    }

    #[test]
    fn the_remaining_keys_validate_as_the_cpp() {
        // ok_skew: `any` (skews ignored) or seconds >= 0.
        assert_eq!(parse_one("ok_skew", "ANY").0.ok_skew, None);
        assert_eq!(parse_one("ok_skew", "2.5").0.ok_skew, Some(2.5));
        assert_eq!(parse_one("ok_skew", "-1").1.len(), 1);
        // verbose: verbose/true/terse/false/quiet only.
        for v in ["verbose", "TRUE", "terse", "false", "quiet"] {
            assert!(parse_one("verbose", v).1.is_empty(), "{v}");
        }
        assert_eq!(parse_one("verbose", "loud").1.len(), 1);
        // helm_alias, helm_prefix, other_override_var: non-empty, no white space.
        for key in ["helm_alias", "helm_prefix", "other_override_var"] {
            assert!(parse_one(key, "NAME_1").1.is_empty(), "{key}");
            assert_eq!(parse_one(key, "two words").1.len(), 1, "{key}");
        }
        // seed_random, goals_mandatory, bhv_dir_not_found_ok: booleans.
        assert!(!parse_one("seed_random", "false").0.seed_random);
        assert_eq!(parse_one("seed_random", "sometimes").1.len(), 1);
        assert_eq!(parse_one("bhv_dir_not_found_ok", "sometimes").1.len(), 1);
        // standby: positive seconds (MOOS `setPosDoubleOnString`).
        let (c, e) = parse_one("standby", "5");
        assert_eq!(c.standby, Some(5.0));
        assert!(e.is_empty(), "{e:?}");
        assert_eq!(parse_one("standby", "0").1.len(), 1);
        assert_eq!(parse_one("standby", "soon").1.len(), 1);
        // Behaviour libraries are accepted (coug links its behaviours statically).
        for key in [
            "ivp_behavior_dir",
            "ivp_behavior_dirs",
            "bhv_dir_not_found_ok",
        ] {
            assert!(parse_one(key, "true").1.is_empty(), "{key}");
        }
        // pmgen: MOOS's PlatModelGenerator rules.
        for ok in [
            "alg=holo",
            "alg=HOLO#anything=1",
            "alg=dubins#rad=10#degs=15",
            "alg=dubins#radius=0#mod_radius=-2",
        ] {
            assert!(parse_one("pmgen", ok).1.is_empty(), "{ok}");
        }
        for bad in [
            "true",
            "alg=ackermann",
            "alg=dubins#rad=-1",
            "alg=dubins#degs=0",
            "alg=dubins#speed=2",
            "radius=3",
        ] {
            assert_eq!(parse_one("pmgen", bad).1.len(), 1, "{bad}");
        }
    }
}
