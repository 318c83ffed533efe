//! BHV_Timer (reference §6.9): no objective function; posts its idle and running time.
//!
//! # Conformance with BHV_Timer (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | var_status_idle | | var | TIMER_IDLE | no white space (coug also refuses an empty name) | yes | done |
//! | var_status_running | | var | TIMER_RUNNING | no white space (coug also refuses an empty name) | yes | done |
//! | status_suffix | | text | none | no white space; `_` prefixed unless present (the C++ crashes on an empty one; coug refuses it) | yes | done |
//! | duration (common) | | s | −1 | | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | `var_status_idle` + suffix | every iteration, idle or running | seconds idle (duration clock) | done |
//! | `var_status_running` + suffix | every iteration, idle or running | seconds running (duration clock) | done |

use ivp::IvpFunction;

use crate::behavior::{Behavior, Ctx, Out, ParamError};
use crate::common::Common;

/// Posts the seconds spent idle and running (the helm's duration clock, so a `duration_reset`
/// restarts them) every iteration, idle or running: `TIMER_IDLE` then `TIMER_RUNNING`, each
/// with `status_suffix`. Usually combined with `duration` and `endflag`.
#[derive(Debug, Clone)]
pub struct Timer {
    /// Variable for the idle time.
    pub var_idle: String,
    /// Variable for the running time.
    pub var_running: String,
    /// Suffix appended to both variables.
    pub suffix: String,
    idle: f64,
    running: f64,
}

impl Default for Timer {
    fn default() -> Self {
        Self::new()
    }
}

impl Timer {
    /// Defaults: `TIMER_IDLE`, `TIMER_RUNNING`.
    pub fn new() -> Self {
        Timer {
            var_idle: "TIMER_IDLE".into(),
            var_running: "TIMER_RUNNING".into(),
            suffix: String::new(),
            idle: 0.0,
            running: 0.0,
        }
    }

    fn post(&self, out: &mut Out) {
        out.post(format!("{}{}", self.var_idle, self.suffix), self.idle);
        out.post(format!("{}{}", self.var_running, self.suffix), self.running);
    }
}

impl Behavior for Timer {
    fn kind(&self) -> &'static str {
        "BHV_Timer"
    }

    fn default_name(&self) -> &'static str {
        "bhv_timer"
    }
    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        let v = value.trim();
        let ok_var = !v.is_empty() && !v.contains(char::is_whitespace);
        match param {
            "var_status_idle" if ok_var => self.var_idle = v.into(),
            "var_status_running" if ok_var => self.var_running = v.into(),
            "status_suffix" if ok_var => {
                self.suffix = if v.starts_with('_') {
                    v.into()
                } else {
                    format!("_{v}")
                };
            }
            "var_status_idle" | "var_status_running" | "status_suffix" => {
                return Err(ParamError::bad(param, value, "a name without spaces"));
            }
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn state_durations(&mut self, idle: f64, running: f64) {
        self.idle = idle;
        self.running = running;
    }

    fn on_idle(&mut self, _ctx: &Ctx<'_>, out: &mut Out) {
        self.post(out);
    }

    fn on_run(&mut self, _ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        self.post(out);
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::behavior::MapInfo;
    use ivp::Domain;

    #[test]
    fn posts_both_times_with_suffix() {
        let d = Domain::parse_specs(["course:0:359:360"]).unwrap();
        let info = MapInfo::new(10.0);
        let ctx = Ctx {
            info: &info,
            domain: &d,
            ownship: "a",
            name: "t",
            perpetual: false,
        };
        let mut t = Timer::new();
        let mut c = Common::new("BHV_Timer");
        t.set_param("status_suffix", "A", &mut c, &ctx).unwrap();
        assert!(
            t.set_param("var_status_idle", "two words", &mut c, &ctx)
                .is_err()
        );
        let mut out = Out::default();
        t.state_durations(2.5, 0.0);
        t.on_idle(&ctx, &mut out);
        t.state_durations(2.5, 1.5);
        assert!(t.on_run(&ctx, &mut out).is_none());
        let posts: Vec<(String, f64)> = out
            .emits
            .iter()
            .map(|e| match e {
                crate::Emit::Post { var, value, .. } => (var.clone(), value.as_f64().unwrap()),
                _ => unreachable!(),
            })
            .collect();
        assert_eq!(
            posts,
            [
                ("TIMER_IDLE_A".to_string(), 2.5),
                ("TIMER_RUNNING_A".to_string(), 0.0),
                ("TIMER_IDLE_A".to_string(), 2.5),
                ("TIMER_RUNNING_A".to_string(), 1.5)
            ]
        );
    }

    #[test]
    fn names_and_suffix_follow_the_cpp_rules() {
        let d = ivp::Domain::parse_specs(["course:0:359:360"]).unwrap();
        let info = MapInfo::new(0.0);
        let ctx = Ctx {
            info: &info,
            domain: &d,
            ownship: "abe",
            name: "t",
            perpetual: false,
        };
        let mut t = Timer::new();
        let mut c = Common::new("BHV_Timer");
        t.set_param("status_suffix", "leg", &mut c, &ctx).unwrap();
        assert_eq!(t.suffix, "_leg");
        t.set_param("status_suffix", "_two", &mut c, &ctx).unwrap();
        assert_eq!(t.suffix, "_two");
        t.set_param("var_status_idle", "IDLE_T", &mut c, &ctx)
            .unwrap();
        for (p, v) in [
            ("var_status_running", "A B"),
            ("status_suffix", ""),
            ("var_status_idle", " "),
        ] {
            assert!(t.set_param(p, v, &mut c, &ctx).is_err(), "{p} = {v:?}");
        }
        t.state_durations(2.0, 3.5);
        let mut out = Out::default();
        t.on_idle(&ctx, &mut out);
        let posted: Vec<(String, f64)> = out
            .emits
            .iter()
            .filter_map(|e| match e {
                crate::Emit::Post { var, value, .. } => Some((var.clone(), value.as_f64()?)),
                _ => None,
            })
            .collect();
        assert_eq!(
            posted,
            [
                ("IDLE_T_two".to_string(), 2.0),
                ("TIMER_RUNNING_two".to_string(), 3.5)
            ]
        );
    }
}
