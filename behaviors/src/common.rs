//! Parameters every behaviour accepts (reference §5.5, MOOS `IvPBehavior::setParam`) and the
//! flag syntax (§4.5).
//!
//! # Conformance with IvPBehavior (MOOS-IvP a2a9b716)
//!
//! Keys are case-insensitive; a leading `_` is ignored.
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | name | descriptor | text | the type's descriptor | set by the spec | no | done |
//! | pwt | priwt, priority | number | 100 | number >= 0 | yes | done |
//! | condition | | condition | none | parses (`,` read as `=`); each line adds one | yes | done |
//! | comms_policy | | enum | open | open, lean, dire | yes | done |
//! | duration | | seconds | −1 (0 for ConstantSpeed/Heading/Depth) | number >= 0, `-1` or `no-time-limit` | yes | done |
//! | duration_status | | var | none | any | yes | done |
//! | duration_reset | | `VAR=VAL` | none | VAR non-empty | yes | done |
//! | duration_idle_decay | | bool | true | MOOS boolean (yes/no/on/off/toggle) | yes | done |
//! | perpetual | | bool | false | any value; `true` (any case) sets it | yes | done |
//! | post_mapping | | `VAR,NEWVAR` | none | no white space in either | yes | done |
//! | updates | | var | none | any; subscribed | no | done |
//! | nostarve | no_starve | `VAR,...,secs` | none | variables and a number | yes | done |
//! | build_info | | text | none | `clear`, else prepended (`a # b`) | yes | done |
//! | precision | | text | none | as `build_info = precision=<v>` | yes | done |
//! | runflag, runxflag, activeflag, inactiveflag, idleflag, endflag, configflag | run_flag, runx_flag, active_flag, inactive_flag, idle_flag, end_flag, config_flag | flag | none | `VAR = value [[if] condition]`, `clearall` | yes | done |
//! | spawnflag, spawnxflag | spawn_flag, spawnx_flag | flag | none | as above | yes | done (spawnflags when spawned, spawnx on the first iteration) |
//! | templating | | enum | disallow | `spawn`, `clone`, `disallow` (exact); other values ignored (the spec's `setTemplatingType` result is unused) | no | done (helm spawning, see `helm::spawn`) |
//! | max_spawnings | | number | 0 (no limit) | a number >= 0, else ignored (`setUIntOnString`) | no | done |
//! | us | | name | community | any; overwritten by the helm's community after loading, an update changes `$[OWNSHIP]`, node messages' `src_node` and `<US>_NAV_GROUP` | yes | done |

use mission::condition::{Condition, parse_condition};

use crate::behavior::ParamError;
use crate::param::{is_number, moos_boolean, number};

/// Which flag list a flag belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FlagKind {
    /// `runflag`: on idle→running.
    Run,
    /// `runxflag`: every running iteration.
    Runx,
    /// `idleflag`: on entering idle.
    Idle,
    /// `activeflag`: on entering active.
    Active,
    /// `inactiveflag`: on leaving active, and on entering idle.
    Inactive,
    /// `endflag`: on completion.
    End,
    /// `spawnflag`: when spawned.
    Spawn,
    /// `spawnxflag`: on the first iteration.
    Spawnx,
    /// `configflag`: on the first iteration ever.
    Config,
}

impl FlagKind {
    /// Every flag list, in parameter order.
    pub const ALL: [FlagKind; 9] = [
        FlagKind::Run,
        FlagKind::Runx,
        FlagKind::Idle,
        FlagKind::Active,
        FlagKind::Inactive,
        FlagKind::End,
        FlagKind::Spawn,
        FlagKind::Spawnx,
        FlagKind::Config,
    ];

    /// The flag list for a parameter name (`runflag` or `run_flag`, ...).
    pub fn from_param(p: &str) -> Option<FlagKind> {
        let base = p.strip_suffix("flag")?;
        let base = base.strip_suffix('_').unwrap_or(base);
        Some(match base {
            "run" => FlagKind::Run,
            "runx" => FlagKind::Runx,
            "idle" => FlagKind::Idle,
            "active" => FlagKind::Active,
            "inactive" => FlagKind::Inactive,
            "end" => FlagKind::End,
            "spawn" => FlagKind::Spawn,
            "spawnx" => FlagKind::Spawnx,
            "config" => FlagKind::Config,
            _ => return None,
        })
    }

    fn index(self) -> usize {
        FlagKind::ALL.iter().position(|k| *k == self).unwrap_or(0)
    }
}

/// A flag's value, typed as MOOS `VarDataPair` "auto" does: a number is a double, a quoted
/// text a string without its quotes, anything else a string (which may contain macros). The
/// workspace's one MOOS value type.
pub use moos_types::Value as FlagValue;

/// One `VAR = value [if] CONDITION` flag (reference §4.5).
#[derive(Debug, Clone, PartialEq)]
pub struct Flag {
    /// Variable.
    pub var: String,
    /// Value.
    pub value: FlagValue,
    /// The whole value is one macro (`$[X]` or `$(X)`): posted as a double if it expands to
    /// a number.
    pub solo_macro: bool,
    /// Destination tag (`all`, `group`, `all+`, `group+`), empty = local.
    pub dest: String,
    /// Condition evaluated at post time.
    pub condition: Option<Condition>,
}

impl Flag {
    /// Parses `[#dest] VAR = value [if] CONDITION`; `None` if malformed.
    ///
    /// ```
    /// use behaviors::{Flag, FlagValue};
    /// let f = Flag::parse("RETURN = true").unwrap();
    /// assert_eq!((f.var.as_str(), &f.value), ("RETURN", &FlagValue::String("true".into())));
    /// assert_eq!(Flag::parse("N = 3").unwrap().value, FlagValue::Double(3.0));
    /// assert!(Flag::parse("SUMMARY=speed=$[SPEED]").is_some());
    /// assert!(Flag::parse("= 3").is_none());
    /// ```
    pub fn parse(text: &str) -> Option<Flag> {
        let mut t = text.trim();
        let mut condition = None;
        if let Some(at) = t.find("[if]") {
            let ctext = t[at + 4..].trim();
            if !ctext.is_empty() {
                condition = Some(parse_condition(ctext).ok()?);
            }
            t = t[..at].trim();
        }
        let mut dest = String::new();
        if let Some(rest) = t.strip_prefix('#') {
            let end = rest.find(char::is_whitespace)?;
            dest = rest[..end].to_ascii_lowercase();
            t = rest[end..].trim();
        }
        let (var, val) = t.split_once('=')?;
        let (var, val) = (var.trim(), val.trim());
        if var.is_empty() || val.is_empty() || var.contains(char::is_whitespace) {
            return None;
        }
        let solo_macro = is_solo_macro(val);
        let value = if is_number(val) {
            FlagValue::Double(val.parse().ok()?)
        } else if val.len() >= 2 && val.starts_with('"') && val.ends_with('"') {
            FlagValue::text(&val[1..val.len() - 1])
        } else {
            FlagValue::text(val)
        };
        Some(Flag {
            var: var.to_string(),
            value,
            solo_macro,
            dest,
            condition,
        })
    }

    /// Whether the flag is posted to the local MOOSDB (no dest, or `all+`/`group+`).
    pub fn is_local(&self) -> bool {
        self.dest.is_empty() || self.dest.ends_with('+')
    }
}

fn is_solo_macro(v: &str) -> bool {
    let inner = v
        .strip_prefix("$[")
        .and_then(|r| r.strip_suffix(']'))
        .or_else(|| v.strip_prefix("$(").and_then(|r| r.strip_suffix(')')));
    inner
        .is_some_and(|s| !s.is_empty() && s.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_'))
}

/// The common parameters of a behaviour.
#[derive(Debug, Clone)]
pub struct Common {
    /// The behaviour type as written (`BHV_Waypoint`).
    pub kind: String,
    /// Name (`name`/`descriptor`); [`Common::new`] sets the type name in lower case, the
    /// helm the type's [`Behavior::default_name`](crate::Behavior::default_name).
    pub name: String,
    /// Priority weight (default 100).
    pub pwt: f64,
    /// Run conditions (text as written, parsed), all must hold.
    pub conditions: Vec<(String, Condition)>,
    /// `updates` variable ("" = none).
    pub update_var: String,
    /// `duration` seconds (−1 = none); `None` = the behaviour type's default.
    pub duration: Option<f64>,
    /// `duration_status` variable ("" = none).
    pub duration_status: String,
    /// `duration_reset` variable and value ("" value = any post).
    pub duration_reset: Option<(String, String)>,
    /// `duration_idle_decay` (default true): idle time counts toward the duration.
    pub duration_idle_decay: bool,
    /// `perpetual`.
    pub perpetual: bool,
    flags: [Vec<Flag>; 9],
    /// `nostarve` variables with their maximum age.
    pub starve: Vec<(String, f64)>,
    /// `post_mapping` renames (`silent` suppresses).
    pub post_mapping: Vec<(String, String)>,
    /// `comms_policy` (open/lean/dire).
    pub comms_policy: String,
    /// `build_info` hints (kept, unused).
    pub build_info: String,
    /// `us`: the vehicle name this behaviour uses for `$[OWNSHIP]`, node messages and
    /// `<US>_NAV_GROUP` (MOOS `m_us_name`). The helm sets it to its own community once the
    /// behaviours are loaded (so a `.bhv` line has no lasting effect, as in the C++); a later
    /// update may change it. `None`: the helm's community.
    pub us: Option<String>,
    /// `templating`: whether this `.bhv` entry is a template the helm spawns instances of.
    pub templating: Templating,
    /// `max_spawnings`: the most instances a template spawns (0 = no limit).
    pub max_spawnings: u32,
}

/// A behaviour entry's `templating` (MOOS `BehaviorSpec::setTemplatingType`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Templating {
    /// `disallow` (the default): an ordinary behaviour.
    #[default]
    Disallow,
    /// `spawn`: a template only; every `updates` posting with a new `name=` spawns an
    /// instance named `<name prefix><name>`.
    Spawn,
    /// `clone`: as `spawn`, and the entry is also an ordinary behaviour from the start.
    Clone,
}

impl Templating {
    /// Whether the entry spawns instances (`spawn` or `clone`).
    pub fn spawns(self) -> bool {
        self != Templating::Disallow
    }
}

impl Common {
    /// Defaults for a behaviour of type `kind`.
    pub fn new(kind: &str) -> Self {
        Common {
            kind: kind.to_string(),
            name: kind.to_ascii_lowercase(),
            pwt: 100.0,
            conditions: Vec::new(),
            update_var: String::new(),
            duration: None,
            duration_status: String::new(),
            duration_reset: None,
            duration_idle_decay: true,
            perpetual: false,
            flags: Default::default(),
            starve: Vec::new(),
            post_mapping: Vec::new(),
            comms_policy: "open".to_string(),
            build_info: String::new(),
            us: None,
            templating: Templating::Disallow,
            max_spawnings: 0,
        }
    }

    /// The flags of one kind.
    pub fn flags(&self, kind: FlagKind) -> &[Flag] {
        &self.flags[kind.index()]
    }

    /// The variable a posting to `var` goes to after `post_mapping` (`None` = silent).
    pub fn mapped<'a>(&'a self, var: &'a str) -> Option<&'a str> {
        match self.post_mapping.iter().find(|(a, _)| a == var) {
            Some((_, b)) if b.eq_ignore_ascii_case("silent") => None,
            Some((_, b)) => Some(b),
            None => Some(var),
        }
    }

    /// Applies a common parameter (`param` lower case, leading `_` removed). `Ok(true)`:
    /// handled; `Ok(false)`: not a common parameter; `Err`: a common parameter with a bad
    /// value.
    ///
    /// ```
    /// let mut c = behaviors::Common::new("BHV_Waypoint");
    /// assert_eq!(c.set_param("pwt", "200"), Ok(true));
    /// assert_eq!(c.pwt, 200.0);
    /// assert!(c.set_param("pwt", "-1").is_err());
    /// assert_eq!(c.set_param("speed", "2"), Ok(false));
    /// ```
    pub fn set_param(&mut self, param: &str, value: &str) -> Result<bool, ParamError> {
        let v = value.trim();
        let bad = |expected| Err(ParamError::bad(param, value, expected));
        match param {
            "name" | "descriptor" => {
                if v.is_empty()
                    || !v
                        .chars()
                        .all(|c| c.is_ascii_alphanumeric() || "_-[]()#@+".contains(c))
                {
                    return bad("letters, digits and _-[]()#@+");
                }
                self.name = v.to_string();
            }
            // Any text, as the C++ (even empty).
            "us" => self.us = Some(v.to_string()),
            "pwt" | "priwt" | "priority" => {
                let p = number(param, v)?;
                if p < 0.0 {
                    return bad("a non-negative number");
                }
                self.pwt = p;
            }
            "condition" => {
                let text = v.replace(',', "=");
                match parse_condition(&text) {
                    Ok(c) => self.conditions.push((v.to_string(), c)),
                    Err(_) => return bad("a logic condition"),
                }
            }
            "comms_policy" => {
                let l = v.to_ascii_lowercase();
                if !matches!(l.as_str(), "open" | "lean" | "dire") {
                    return bad("open, lean or dire");
                }
                self.comms_policy = l;
            }
            "duration_status" => self.duration_status = v.to_string(),
            "duration_reset" => {
                let (var, val) = v.split_once('=').unwrap_or((v, ""));
                if var.trim().is_empty() {
                    return bad("VAR=value");
                }
                self.duration_reset = Some((var.trim().to_string(), val.trim().to_string()));
            }
            "duration_idle_decay" => {
                self.duration_idle_decay = moos_boolean(param, v, self.duration_idle_decay)?
            }
            "post_mapping" => {
                let Some((a, b)) = v.split_once(',') else {
                    return bad("VAR,NEWVAR");
                };
                let (a, b) = (a.trim(), b.trim());
                if a.contains(char::is_whitespace) || b.contains(char::is_whitespace) {
                    return bad("VAR,NEWVAR");
                }
                self.post_mapping.push((a.to_string(), b.to_string()));
            }
            "nostarve" | "no_starve" => {
                let parts: Vec<&str> = v.split(',').map(str::trim).collect();
                if parts.len() < 2 {
                    return bad("VAR[,VAR...],seconds");
                }
                let secs = number(param, parts[parts.len() - 1])?;
                if secs <= 0.0 {
                    return bad("a positive number of seconds");
                }
                for var in &parts[..parts.len() - 1] {
                    self.starve.push((var.to_string(), secs));
                }
            }
            // MOOS accepts any value and tests for "true".
            "perpetual" => self.perpetual = v.eq_ignore_ascii_case("true"),
            "duration" => {
                if v == "no-time-limit" || v == "-1" {
                    self.duration = Some(-1.0);
                } else {
                    let d = number(param, v)?;
                    if d < 0.0 {
                        return bad("seconds >= 0, or no-time-limit");
                    }
                    self.duration = Some(d);
                }
            }
            "build_info" => {
                let l = v.to_ascii_lowercase();
                if l == "clear" {
                    self.build_info.clear();
                } else if self.build_info.is_empty() {
                    self.build_info = l;
                } else {
                    self.build_info = format!("{l} # {}", self.build_info);
                }
            }
            "precision" => {
                let info = format!("precision={}", v.to_ascii_lowercase());
                return self.set_param("build_info", &info);
            }
            "updates" => self.update_var = v.to_string(),
            // pHelmIvP's behaviour spec takes these two lines for itself and ignores values it
            // cannot read (exact spellings only): never a configuration error.
            "templating" => match v {
                "spawn" => self.templating = Templating::Spawn,
                "clone" => self.templating = Templating::Clone,
                "disallow" => self.templating = Templating::Disallow,
                _ => {}
            },
            "max_spawnings" => {
                if let Ok(n) = number(param, v)
                    && n >= 0.0
                {
                    self.max_spawnings = n as u32;
                }
            }
            _ => {
                let Some(kind) = FlagKind::from_param(param) else {
                    return Ok(false);
                };
                if v.eq_ignore_ascii_case("clearall") {
                    self.flags[kind.index()].clear();
                } else {
                    match Flag::parse(v) {
                        Some(f) => self.flags[kind.index()].push(f),
                        None => return bad("VAR = value [[if] condition]"),
                    }
                }
            }
        }
        Ok(true)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_by_kind_and_clearall() {
        let mut c = Common::new("BHV_Timer");
        c.set_param("endflag", "A = 1").unwrap();
        c.set_param("end_flag", "B = \"x y\"").unwrap();
        assert_eq!(c.flags(FlagKind::End).len(), 2);
        assert_eq!(
            c.flags(FlagKind::End)[1].value,
            FlagValue::String("x y".into())
        );
        c.set_param("endflag", "clearall").unwrap();
        assert!(c.flags(FlagKind::End).is_empty());
        assert!(c.set_param("runflag", "novalue").is_err());
    }

    #[test]
    fn duration_forms() {
        let mut c = Common::new("x");
        c.set_param("duration", "no-time-limit").unwrap();
        assert_eq!(c.duration, Some(-1.0));
        c.set_param("duration", "10").unwrap();
        assert_eq!(c.duration, Some(10.0));
        assert!(c.set_param("duration", "ten").is_err());
        c.set_param("duration_reset", "CONST_SPD_RESET=true")
            .unwrap();
        assert_eq!(
            c.duration_reset,
            Some(("CONST_SPD_RESET".into(), "true".into()))
        );
    }

    #[test]
    fn legacy_comma_condition_and_solo_macro() {
        let mut c = Common::new("x");
        c.set_param("condition", "DEPLOY,true").unwrap();
        assert_eq!(c.conditions[0].1.variables(), ["DEPLOY"]);
        let f = Flag::parse("CRUISE_SPD = $[SPEED]").unwrap();
        assert!(f.solo_macro);
        let f = Flag::parse("#all+ X = 1 [if] (A = 2)").unwrap();
        assert_eq!(f.dest, "all+");
        assert!(f.is_local() && f.condition.is_some());
    }

    #[test]
    fn aliases_and_the_remaining_cpp_rules() {
        let mut c = Common::new("x");
        c.set_param("priwt", "50").unwrap();
        assert_eq!(c.pwt, 50.0);
        c.set_param("priority", "70").unwrap();
        assert_eq!(c.pwt, 70.0);
        assert!(c.set_param("pwt", "-1").is_err());
        c.set_param("duration", "-1").unwrap();
        assert_eq!(c.duration, Some(-1.0));
        assert!(c.set_param("duration", "-2").is_err());
        // duration_idle_decay takes MOOS booleans.
        c.set_param("duration_idle_decay", "no").unwrap();
        assert!(!c.duration_idle_decay);
        c.set_param("duration_idle_decay", "toggle").unwrap();
        assert!(c.duration_idle_decay);
        // build_info prepends; precision is a build_info entry; clear empties it.
        c.set_param("build_info", "A=1").unwrap();
        c.set_param("precision", "LOW").unwrap();
        assert_eq!(c.build_info, "precision=low # a=1");
        c.set_param("build_info", "clear").unwrap();
        assert!(c.build_info.is_empty());
        // Spawn flags parse like the others; templating and max_spawnings read as the C++
        // spec reads them: unreadable values are ignored, never refused.
        c.set_param("spawn_flag", "S = 1").unwrap();
        c.set_param("spawnxflag", "SX = 1").unwrap();
        assert_eq!(c.flags(FlagKind::Spawn).len(), 1);
        assert_eq!(c.flags(FlagKind::Spawnx).len(), 1);
        c.set_param("templating", "spawn").unwrap();
        assert_eq!(c.templating, Templating::Spawn);
        c.set_param("templating", "Clone").unwrap();
        assert_eq!(c.templating, Templating::Spawn, "exact spelling only");
        c.set_param("templating", "clone").unwrap();
        assert!(c.templating.spawns());
        c.set_param("templating", "disallow").unwrap();
        assert!(!c.templating.spawns());
        c.set_param("max_spawnings", "5").unwrap();
        c.set_param("max_spawnings", "many").unwrap();
        c.set_param("max_spawnings", "-2").unwrap();
        assert_eq!(c.max_spawnings, 5);
        assert!(c.set_param("comms_policy", "noisy").is_err());
        c.set_param("comms_policy", "LEAN").unwrap();
    }
}
