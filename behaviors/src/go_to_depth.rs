//! BHV_GoToDepth (reference §6.6): a sequence of depths, each held for a time.
//!
//! # Conformance with BHV_GoToDepth (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | depth | | `d[,t]:d[,t]:...` | none | each depth and time a number >= 0; appends | yes | done |
//! | repeat | | integer | 0 | integer >= 0 | yes | done |
//! | arrival_delta | capture_delta | m | 1 | number >= 0 | yes | done |
//! | arrival_flag | capture_flag | var | none | posted as `GTD_<value>` | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | `GTD_<arrival_flag>` | each arrival at a level | arrivals so far | done |
//! | LEVEL_DEPTH | each running iteration | current level's depth | done |
//! | BHV_ERROR | running without NAV_DEPTH | `No ownship Depth info in Helm info_buffer.` | done |

use ivp::{IvpFunction, ZaicPeak};

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::common::Common;
use crate::param::{is_number, number};

/// Goes to a list of depths in order (`depth = d1,t1:d2,t2:...`, hold time in seconds,
/// optional and 0 by default; each `depth` line appends). A level is reached when within
/// `capture_delta` (`arrival_delta`, default 1 m) of it, or when the vehicle crossed it since
/// the last iteration; the behaviour then holds it for its time, moves on and posts
/// `LEVEL_DEPTH = <next depth>`. After the last level it completes (`repeat` = number of extra
/// passes through the list; a perpetual behaviour starts over). Each arrival posts the arrival
/// count to `GTD_<capture_flag>` when `capture_flag` is set.
///
/// The function is ZAIC_PEAK(summit current level, peak width 0, base width 5). A missing
/// `NAV_DEPTH` is an error, as in MOOS-IvP.
#[derive(Debug, Clone)]
pub struct GoToDepth {
    levels: Vec<(f64, f64)>,
    /// Extra passes through the levels.
    pub repeat: u32,
    /// Arrival distance, m.
    pub capture_delta: f64,
    arrival_flag: String,
    curr: usize,
    prior_depth: f64,
    plateau: Option<f64>,
    arrivals: u32,
    first_iteration: bool,
}

impl Default for GoToDepth {
    fn default() -> Self {
        Self::new()
    }
}

impl GoToDepth {
    /// The MOOS defaults: no levels, no repeat, 1 m capture.
    pub fn new() -> Self {
        GoToDepth {
            levels: Vec::new(),
            repeat: 0,
            capture_delta: 1.0,
            arrival_flag: String::new(),
            curr: 0,
            prior_depth: 0.0,
            plateau: None,
            arrivals: 0,
            first_iteration: true,
        }
    }

    /// The configured `(depth, hold seconds)` levels.
    pub fn levels(&self) -> &[(f64, f64)] {
        &self.levels
    }

    /// The index of the level being sought or held.
    pub fn current_index(&self) -> usize {
        self.curr
    }

    /// Moves to the next level; false when the list is done (and the behaviour completes).
    fn advance(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        self.curr += 1;
        if self.curr >= self.levels.len() {
            if self.repeat == 0 {
                out.complete();
                if ctx.perpetual {
                    self.curr = 0;
                    self.first_iteration = true;
                    self.arrivals = 0;
                }
                return false;
            }
            self.repeat -= 1;
            self.curr = 0;
        }
        out.post("LEVEL_DEPTH", self.levels[self.curr].0);
        true
    }

    /// Updates the level; false when there is no level to seek now.
    fn next_level(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        let Some(depth) = ctx.info.num("NAV_DEPTH") else {
            out.error("No ownship Depth info in Helm info_buffer.");
            return false;
        };
        let now = ctx.info.now();
        if let Some(start) = self.plateau {
            if now - start < self.levels[self.curr].1 {
                return true;
            }
            self.plateau = None;
            if !self.advance(ctx, out) {
                return false;
            }
        }
        let target = self.levels[self.curr].0;
        let mut arrived = (depth - target).abs() <= self.capture_delta;
        if !self.first_iteration {
            let down = depth >= target && target >= self.prior_depth;
            let up = depth <= target && target <= self.prior_depth;
            arrived |= down || up;
        }
        if arrived {
            self.arrivals += 1;
            if !self.arrival_flag.is_empty() {
                out.post(self.arrival_flag.clone(), f64::from(self.arrivals));
            }
            self.plateau = Some(now);
        }
        self.prior_depth = depth;
        true
    }
}

impl Behavior for GoToDepth {
    fn kind(&self) -> &'static str {
        "BHV_GoToDepth"
    }

    fn default_name(&self) -> &'static str {
        "bhv_goto_depth"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["depth"]
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_DEPTH"]);
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        let v = value.trim();
        match param {
            "depth" => {
                let expected = "depth[,seconds]:depth[,seconds]:... with values >= 0";
                let mut parsed = Vec::new();
                for level in v.split(':') {
                    let parts: Vec<&str> = level.split(',').map(str::trim).collect();
                    if parts.is_empty() || parts.len() > 2 || !parts.iter().all(|p| is_number(p)) {
                        return Err(ParamError::bad(param, value, expected));
                    }
                    let d = number(param, parts[0])?;
                    let t = match parts.get(1) {
                        Some(t) => number(param, t)?,
                        None => 0.0,
                    };
                    if d < 0.0 || t < 0.0 {
                        return Err(ParamError::bad(param, value, expected));
                    }
                    parsed.push((d, t));
                }
                self.levels.extend(parsed);
            }
            "repeat" => {
                let r = number(param, v)?;
                if r < 0.0 {
                    return Err(ParamError::bad(param, value, "a whole number >= 0"));
                }
                self.repeat = r.trunc() as u32;
            }
            "arrival_delta" | "capture_delta" => {
                let d = number(param, v)?;
                if d < 0.0 {
                    return Err(ParamError::bad(param, value, "a number >= 0"));
                }
                self.capture_delta = d;
            }
            "arrival_flag" | "capture_flag" => self.arrival_flag = format!("GTD_{v}"),
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        ctx.domain.get("depth")?;
        if self.levels.is_empty() {
            out.warning(ctx.name, "No depth levels configured.");
            return None;
        }
        let valid = self.next_level(ctx, out);
        self.first_iteration = false;
        if !valid {
            return None;
        }
        let mut z = ZaicPeak::new(ctx.domain, "depth").ok()?;
        let built = z
            .set_params(self.levels[self.curr].0, 0.0, 5.0, 0.0, 0.0, 100.0)
            .and_then(|_| z.extract());
        match built {
            Ok(f) => Some(f),
            Err(e) => {
                out.error(format!("Unable to build the go-to-depth function: {e}"));
                None
            }
        }
    }
}
