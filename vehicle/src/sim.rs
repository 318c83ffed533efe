//! Marine vehicle simulator, equivalent to MOOS-IvP's `uSimMarineV22` (and, with
//! [`SimConfig::legacy`], the older `uSimMarine`).
//!
//! One [`step`] advances the vehicle by `dt` seconds in the same order as the C++ model:
//!
//! 1. **speed** from the thrust map, reduced by `|rudder|/100 * turn_spd_loss`, then limited by
//!    `max_acceleration` / `max_deceleration`;
//! 2. **heading**: `Δ = rudder * rate/100 * dt * (1 + (thrust-50)/50) + rotate_speed*dt`, with
//!    `rate = turn_rate` scaled by the turn-speed map (linear from `null_speed` to 5 m/s; the
//!    legacy model has no map), rudder ignored at zero speed;
//! 3. **depth/pitch**: at zero speed the vehicle rises at `buoyancy_rate` with pitch 0;
//!    otherwise the elevator gives an actuator rate `a = (elevator/100) *
//!    sqrt(min(v/max_depth_rate_speed,1)) * max_depth_rate`, the previous pitch a rate
//!    `p = -sin(pitch)*v`, depth grows by `(p + a - buoyancy_rate)*dt`, and the new pitch is
//!    `-asin((p + a)/v)` (0 when `|p + a| > v`). As in the C++ model the pitch therefore
//!    integrates the elevator once per *iteration*, whatever `dt` is, so the loop gain of
//!    the PID's pitch loop depends on how often the simulator iterates and publishes;
//! 4. **position** from the mean of the prior and new speed and the circular mean of the prior
//!    and new heading, plus drift; SOG/COG from the displacement.
//!
//! Like the C++ model, the stored speed after a step is that mean speed, so a step change in
//! thrust reaches the thrust-map speed geometrically (half the remaining gap per step).
//!
//! [`Simulator`] is the MOOS adapter: it takes `DESIRED_THRUST`/`DESIRED_RUDDER`/
//! `DESIRED_ELEVATOR` and the environment variables as mail, and publishes `<prefix>_X`, ...
//! every second iteration (`nav_modulo = 2`), as `uSimMarineV22` does; the legacy `uSimMarine`
//! publishes on every iteration.
//!
//! # Conformance with uSimMarineV22 (MOOS-IvP a2a9b716)
//!
//! A bad value or a setting coug does not simulate is a config warning; the app runs on.
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | start_pos | | `x=,y=,heading=,speed=,depth=` | origin | pairs | USM_RESET | done |
//! | start_x, start_y, start_heading, start_speed, start_depth | | number | 0 | number | no | open: implemented, no test of each key |
//! | prefix | | word | NAV | | no | done |
//! | turn_rate | | 0..100 | 70 | number, clipped | USM_TURN_RATE | done |
//! | turn_radius | | m | | number | USM_TURN_RADIUS | done |
//! | thrust_map | | `thrust:speed,...` | none | ascending pairs | no | done |
//! | thrust_factor | | number | 20 | >= 0 | no | done |
//! | thrust_reflect | | bool | false | MOOS boolean | no | done |
//! | thrust_mode_reverse, thrust_mode_diff | | bool / mode | false / normal | | THRUST_MODE_REVERSE, THRUST_MODE_DIFFERENTIAL | done |
//! | turn_spd_loss | | 0..1 | 0.85 | number in range | no | done |
//! | turn_spd_map_full_speed, _null_speed, _full_rate, _null_rate | | number | | number | no | open: implemented, untested |
//! | max_acceleration, max_deceleration | | m/s² | 0 (off), 0.5 | >= 0 | no | done |
//! | max_speed | | m/s | 5 | > 0 | no | done |
//! | buoyancy_rate | | m/s | 0.025 | number | BUOYANCY_RATE | done |
//! | max_depth_rate, max_depth_rate_speed | | number | 0.5, 2.0 | number | no | done (rate), open: speed untested |
//! | default_water_depth | | m | 0 | number | WATER_DEPTH | done |
//! | drift_x, drift_y, drift_vector | | m/s, `ang,mag` | 0 | number / pair | CURRENT_X/Y, DRIFT_X/Y, DRIFT_VECTOR(_ADD/_MULT) | done |
//! | rotate_speed | | deg/s | 0 | number | ROTATE_SPEED | open: implemented, untested |
//! | max_rudder_degs_per_sec | | deg/s | 0 (one change still capped at 100) | number | no | done |
//! | sim_pause | | bool | false | MOOS boolean | USM_SIM_PAUSED | open: implemented, untested |
//! | post_des_thrust, post_des_rudder | | var | none | not DESIRED_THRUST/RUDDER | no | done (posted from the embedded PID only) |
//! | post_navpos_summary | | bool | false | MOOS boolean | no | open: implemented, untested |
//! | PID keys (`yaw_pid_kp` ... `maxelevator`, `speed_factor`, `depth_control`, ...) | | | | as pMarinePIDV22; yaw gains embed the PID | SPEED_FACTOR, MOOS_MANUAL_OVERRIDE, DESIRED_* | done |
//! | dual_state | | bool | false | MOOS boolean; nav without drift, `<P>_GT_*` with it | no | done |
//! | wind_conditions | | `spd=..,dir=..` | none | known keys, numbers, dir and spd >= 0 | WIND_CONDITIONS | done |
//! | polar_plot | | `angle,pct:...` | none | angles 0..180 each once, pct >= 0; with a wind, speed capped at pct × wind speed (only above 0) | no | done |
//! | wormhole | | spec | none | | no | refused: warning, wormholes not simulated |
//! | trim_tolerance, max_trim_delay | | number | | | TRIM_CONTROL | refused: warning, trim handshake not simulated |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | `<P>_X`, `_Y`, `_LAT`, `_LONG`, `_HEADING`, `_SPEED`, `_DEPTH` | every 2nd iteration (legacy: every) | numbers | done |
//! | `<P>_Z`, `_PITCH`, `_YAW`, SIMULATION_MODE, TRUE_X, TRUE_Y | with depth | numbers, `TRUE` | done |
//! | `<P>_HEADING_OVER_GROUND`, `_SPEED_OVER_GROUND`, `_ALTITUDE` | with nav | numbers | done |
//! | USM_RESET_COUNT | on USM_RESET | count | done |
//! | USM_DRIFT_SUMMARY | drift changes | `ang=..,mag=..,xmag=..,ymag=..` | done |
//! | USM_NAVPOS_SUMMARY | with post_navpos_summary | `x=..,y=..[,lat=..,lon=..]` | open: untested |
//! | PID_* (embedded PID) | as pMarinePIDV22 | | done |
//! | `<P>_GT_*` | with dual_state, with the nav | the ground-truth record | done |
//! | USM_NOGO | skewed PID mail | skew | open: mail skew not checked |
//! | BUOYANCY_REPORT, TRIM_REPORT | buoyancy/trim control | | open: not posted |
//! | VIEW_ARROW (wind), VIEW_POLYGON and `<P>_TRANSP` (wormholes) | visuals | | open: not posted |

use std::sync::Arc;

use crate::angle::{angle180, angle360, rel_ang};
use crate::config::{ConfigError, Param, apply_params, parse_number, strict};
use crate::geodesy::LocalGrid;
use crate::moos::{MailValue, Posting, double_x};

const APP: &str = "uSimMarineV22";

/// Piecewise-linear map from thrust (percent, -100..100) to speed (m/s).
///
/// Without positive pairs, speed = thrust / `thrust_factor` (0 when the factor is 0). Negative
/// thrust uses the negative pairs, or the reflected positive map when `reflect` is set, else 0.
#[derive(Debug, Clone, PartialEq)]
pub struct ThrustMap {
    pos: Vec<(f64, f64)>,
    neg: Vec<(f64, f64)>,
    /// Speed = thrust / factor when no positive pairs are given.
    pub thrust_factor: f64,
    /// Mirror the positive map for negative thrust when no negative pairs are given.
    pub reflect: bool,
}

impl Default for ThrustMap {
    fn default() -> Self {
        ThrustMap {
            pos: Vec::new(),
            neg: Vec::new(),
            thrust_factor: 20.0,
            reflect: false,
        }
    }
}

/// Why a thrust-map pair was rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum ThrustMapError {
    /// Thrust outside -100..=100.
    #[error("thrust out of range -100..100")]
    ThrustOutOfRange,
    /// A positive thrust mapped to a negative speed, or the reverse.
    #[error("speed sign does not match thrust sign")]
    SignMismatch,
    /// Zero thrust mapped to a non-zero speed.
    #[error("zero thrust must map to zero speed")]
    NonZeroAtZero,
    /// Speed does not grow with thrust.
    #[error("speeds must not decrease as thrust grows")]
    NotAscending,
    /// Not of the form `thrust:speed, ...`.
    #[error("expected `thrust:speed` pairs separated by commas")]
    Syntax,
}

impl ThrustMap {
    /// Adds one `thrust -> speed` pair (same checks as MOOS-IvP's `ThrustMap::addPair`).
    pub fn add_pair(&mut self, thrust: f64, speed: f64) -> Result<(), ThrustMapError> {
        if !(-100.0..=100.0).contains(&thrust) {
            return Err(ThrustMapError::ThrustOutOfRange);
        }
        let side = if thrust > 0.0 {
            if speed < 0.0 {
                return Err(ThrustMapError::SignMismatch);
            }
            &mut self.pos
        } else if thrust < 0.0 {
            if speed > 0.0 {
                return Err(ThrustMapError::SignMismatch);
            }
            &mut self.neg
        } else if speed != 0.0 {
            return Err(ThrustMapError::NonZeroAtZero);
        } else {
            return Ok(());
        };
        let mut next = side.clone();
        match next.iter_mut().find(|(t, _)| *t == thrust) {
            Some(pair) => pair.1 = speed,
            None => next.push((thrust, speed)),
        }
        next.sort_by(|a, b| a.0.total_cmp(&b.0));
        if next.windows(2).any(|w| w[1].1 < w[0].1) {
            return Err(ThrustMapError::NotAscending);
        }
        *side = next;
        Ok(())
    }

    /// Parses `0:0, 20:1, 40:2, ...` (pairs added in order, as `thrust_map = ...`).
    pub fn add_spec(&mut self, spec: &str) -> Result<(), ThrustMapError> {
        if spec.trim().is_empty() {
            return Err(ThrustMapError::Syntax);
        }
        for item in spec.split(',') {
            let (t, s) = item.split_once(':').ok_or(ThrustMapError::Syntax)?;
            let t = parse_number(t).ok_or(ThrustMapError::Syntax)?;
            let s = parse_number(s).ok_or(ThrustMapError::Syntax)?;
            self.add_pair(t, s)?;
        }
        Ok(())
    }

    /// True when speed comes from `thrust_factor` (no positive pairs).
    pub fn using_thrust_factor(&self) -> bool {
        self.pos.is_empty()
    }

    /// Speed (m/s) for a thrust (percent).
    pub fn speed(&self, thrust: f64) -> f64 {
        if thrust > 0.0 {
            self.speed_pos(thrust)
        } else if thrust < 0.0 {
            if self.neg.is_empty() {
                if self.reflect {
                    -self.speed_pos(-thrust)
                } else {
                    0.0
                }
            } else {
                self.speed_neg(thrust)
            }
        } else {
            0.0
        }
    }

    fn speed_pos(&self, thrust: f64) -> f64 {
        let Some(&(_, top)) = self.pos.last() else {
            return if self.thrust_factor == 0.0 {
                0.0
            } else {
                thrust / self.thrust_factor
            };
        };
        if thrust >= 100.0 {
            return top;
        }
        // Between (left) the largest pair at or below thrust (or 0:0) and (right) the next
        // pair above it (or 100:top).
        let (mut ld, mut lv) = (0.0, 0.0);
        let (mut rd, mut rv) = (100.0, top);
        for &(t, s) in self.pos.iter().rev() {
            if thrust >= t {
                ld = t;
                lv = s;
                break;
            }
            rd = t;
            rv = s;
        }
        interpolate(thrust, ld, lv, rd, rv)
    }

    fn speed_neg(&self, thrust: f64) -> f64 {
        let bottom = self.neg[0].1;
        if thrust <= -100.0 {
            return bottom;
        }
        let (mut ld, mut lv) = (-100.0, bottom);
        let (mut rd, mut rv) = (0.0, 0.0);
        for &(t, s) in &self.neg {
            if thrust <= t {
                rd = t;
                rv = s;
                break;
            }
            ld = t;
            lv = s;
        }
        interpolate(thrust, ld, lv, rd, rv)
    }
}

fn interpolate(x: f64, ld: f64, lv: f64, rd: f64, rv: f64) -> f64 {
    let run = rd - ld;
    if run <= 0.0 {
        return 0.0;
    }
    (x - ld) * (rv - lv) / run + lv
}

/// Starting pose (`start_pos`, or `start_x` ... `start_depth`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StartPose {
    /// x, metres east.
    pub x: f64,
    /// y, metres north.
    pub y: f64,
    /// Compass heading, degrees.
    pub heading: f64,
    /// Speed, m/s.
    pub speed: f64,
    /// Depth, metres (>= 0).
    pub depth: f64,
}

impl StartPose {
    /// Applies a `start_pos`/`USM_RESET` spec: `x=0,y=-20,heading=180,speed=0,depth=0`, or the
    /// older positional `x,y,heading,speed,depth`.
    pub fn apply_spec(&mut self, spec: &str) -> Result<(), &'static str> {
        for (i, item) in spec.split(',').enumerate() {
            let item = item.trim();
            if item.is_empty() {
                continue;
            }
            let (key, val) = match item.split_once('=') {
                Some((k, v)) => (k.trim().to_ascii_lowercase(), v.trim()),
                None => {
                    let k = ["x", "y", "heading", "speed", "depth"]
                        .get(i)
                        .ok_or("too many fields")?;
                    ((*k).to_string(), item)
                }
            };
            let v = parse_number(val).ok_or("a number")?;
            match key.as_str() {
                "x" => self.x = v,
                "y" => self.y = v,
                "heading" | "deg" | "hdg" => self.heading = v,
                "speed" | "spd" => self.speed = v,
                "depth" | "dep" => self.depth = v.max(0.0),
                _ => return Err("x, y, heading, speed or depth"),
            }
        }
        Ok(())
    }
}

/// `uSimMarineV22` configuration. `Default` gives the MOOS defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct SimConfig {
    /// Output prefix (`prefix`, default `USM`; missions set `NAV`).
    pub prefix: String,
    /// Starting pose.
    pub start: StartPose,
    /// Full-rudder turn rate at full speed, 0..100 (`turn_rate`, 70).
    pub turn_rate: f64,
    /// Thrust to speed (`thrust_map`, `thrust_factor` 20, `thrust_reflect`).
    pub thrust_map: ThrustMap,
    /// Speed lost at full rudder, fraction 0..1 (`turn_spd_loss`, 0.85).
    pub turn_spd_loss: f64,
    /// m/s², 0 = unlimited (`max_acceleration`, 0).
    pub max_acceleration: f64,
    /// m/s², 0 = unlimited (`max_deceleration`, 0.5).
    pub max_deceleration: f64,
    /// Rise rate at zero speed, m/s (`buoyancy_rate`, 0.025).
    pub buoyancy_rate: f64,
    /// Depth rate at full elevator and speed, m/s (`max_depth_rate`, 0.5).
    pub max_depth_rate: f64,
    /// Speed at which `max_depth_rate` is reached, m/s (`max_depth_rate_speed`, 2).
    pub max_depth_rate_speed: f64,
    /// Cap on the published speed, m/s (`max_speed`, 5).
    pub max_speed: f64,
    /// Drift east, m/s (`drift_x`, or from `drift_vector`).
    pub drift_x: f64,
    /// Drift north, m/s (`drift_y`).
    pub drift_y: f64,
    /// External rotation, degrees/s (`rotate_speed`).
    pub rotate_speed: f64,
    /// Water depth, m; 0 = unknown, no altitude (`default_water_depth`).
    pub water_depth: f64,
    /// Minimum turn radius, m; 0 = off (`turn_radius`).
    pub turn_radius: f64,
    /// Rudder slew-rate limit, degrees/s; 0 = off (`max_rudder_degs_per_sec`).
    pub max_rudder_degs_per_sec: f64,
    /// Turn-speed map: speed at and below which the turn rate is `tsm_null_rate`
    /// (`turn_spd_map_null_speed`, 0).
    pub tsm_null_speed: f64,
    /// Turn-speed map: rate at the null speed (`turn_spd_map_null_rate`, 0).
    pub tsm_null_rate: f64,
    /// Thrust and rudder reversed (`thrust_mode_reverse`).
    pub thrust_mode_reverse: bool,
    /// Differential thrust (`DESIRED_THRUST_L/R`) instead of thrust + rudder (`thrust_mode_diff`).
    pub thrust_mode_differential: bool,
    /// Start paused (`sim_pause`).
    pub paused: bool,
    /// Also post `USM_NAVPOS_SUMMARY` (`post_navpos_summary`).
    pub post_navpos_summary: bool,
    /// `WIND_CONDITIONS` at start-up (`spd=..,dir=..`); with a polar plot it caps the speed.
    pub wind: Option<crate::polar::Wind>,
    /// `POLAR_PLOT` set points (`angle,pct:...`).
    pub polar: crate::polar::Polar,
    /// `DUAL_STATE`: the navigation (`<P>_*`) ignores the drift and a second, ground-truth
    /// state with the drift is posted as `<P>_GT_*` (uSimMarineV22 `m_dual_state`).
    pub dual_state: bool,
    /// Echo the applied thrust/rudder under these names (`post_des_thrust`, `post_des_rudder`).
    pub post_des_thrust: Option<String>,
    /// See `post_des_thrust`.
    pub post_des_rudder: Option<String>,
    /// Publish depth-related outputs (`<P>_Z`, `<P>_PITCH`, `<P>_YAW`, `TRUE_X/Y`,
    /// `SIMULATION_MODE`); true as in `uSimMarineV22` unless `depth_control = false`.
    pub depth_control: bool,
    /// The embedded PID (uSimMarineV22 with PID gains in its block): it turns DESIRED_HEADING,
    /// DESIRED_SPEED and DESIRED_DEPTH into the simulator's actuators directly.
    pub pid: Option<crate::pid::PidConfig>,
    /// Older `uSimMarine` model: no turn-speed map (turn rate independent of speed), and
    /// the navigation is published on every iteration (`nav_modulo` is not used).
    pub legacy: bool,
    /// `uSimMarineV22` publishes the navigation every n-th iteration (2, as the C++ app);
    /// 0 or 1 = every iteration. The legacy model ignores it (see [`SimConfig::nav_every`]).
    pub nav_modulo: u32,
}

impl Default for SimConfig {
    fn default() -> Self {
        SimConfig {
            prefix: "USM".to_string(),
            start: StartPose::default(),
            turn_rate: 70.0,
            thrust_map: ThrustMap::default(),
            turn_spd_loss: 0.85,
            max_acceleration: 0.0,
            max_deceleration: 0.5,
            buoyancy_rate: 0.025,
            max_depth_rate: 0.5,
            max_depth_rate_speed: 2.0,
            max_speed: 5.0,
            drift_x: 0.0,
            drift_y: 0.0,
            rotate_speed: 0.0,
            water_depth: 0.0,
            turn_radius: 0.0,
            max_rudder_degs_per_sec: 0.0,
            tsm_null_speed: 0.0,
            tsm_null_rate: 0.0,
            thrust_mode_reverse: false,
            thrust_mode_differential: false,
            paused: false,
            post_navpos_summary: false,
            dual_state: false,
            wind: None,
            polar: crate::polar::Polar::default(),
            post_des_thrust: None,
            post_des_rudder: None,
            depth_control: true,
            pid: None,
            legacy: false,
            nav_modulo: 2,
        }
    }
}

/// Speed at which the turn-speed map reaches the full turn rate (hard-coded in the C++ engine).
pub const TURN_MAP_FULL_SPEED: f64 = 5.0;

/// Turns a drift vector `angle,magnitude` (compass degrees, m/s) into `(x, y)` m/s.
pub fn drift_from_vector(spec: &str) -> Option<(f64, f64)> {
    let (a, m) = spec.split_once(',')?;
    let ang = angle360(parse_number(a)?);
    let mag = parse_number(m)?;
    let r = crate::angle::heading_to_radians(ang);
    Some((r.cos() * mag, r.sin() * mag))
}

impl SimConfig {
    /// The older `uSimMarine` model (no turn-speed map, navigation posted every iteration).
    pub fn legacy() -> Self {
        SimConfig {
            legacy: true,
            ..SimConfig::default()
        }
    }

    /// Iterations per navigation posting: 1 for the legacy `uSimMarine` (it posts on every
    /// iteration), else `nav_modulo` (at least 1).
    ///
    /// This matters for depth control: the model turns each iteration's elevator into a pitch
    /// change (not a rate times dt), so when the navigation is posted every other iteration
    /// the PID's pitch loop sees every second pitch only and two elevator steps land per
    /// observation.
    ///
    /// ```
    /// use vehicle::sim::SimConfig;
    /// assert_eq!(SimConfig::default().nav_every(), 2);
    /// assert_eq!(SimConfig::legacy().nav_every(), 1);
    /// ```
    pub fn nav_every(&self) -> u32 {
        if self.legacy {
            1
        } else {
            self.nav_modulo.max(1)
        }
    }

    /// Strict construction from ProcessConfig pairs (unknown keys are errors).
    ///
    /// ```
    /// let cfg = vehicle::sim::SimConfig::from_params([("PREFIX", "NAV"), ("start_pos", "x=0,y=-20,heading=180")]).unwrap();
    /// assert_eq!(cfg.prefix, "NAV");
    /// assert_eq!(cfg.start.y, -20.0);
    /// ```
    pub fn from_params<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<Self, ConfigError> {
        strict(Self::from_params_lenient(params))
    }

    /// Construction that returns unknown keys as non-fatal errors next to the config.
    pub fn from_params_lenient<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<(Self, Vec<ConfigError>), ConfigError> {
        let mut cfg = SimConfig::default();
        let pairs: Vec<(&str, &str)> = params.into_iter().collect();
        let lower = |k: &str| k.trim().to_ascii_lowercase();
        let is_pid = |k: &str| crate::pid::ENGINE_KEYS.contains(&lower(k).as_str());
        // The PID engine takes its keys first (`depth_control` also serves the model).
        let sim_pairs = pairs
            .iter()
            .filter(|(k, _)| !is_pid(k) || lower(k) == "depth_control")
            .copied();
        let mut unknown = apply_params(APP, &mut cfg, sim_pairs, Self::apply_one)?;
        let pid_pairs: Vec<(&str, &str)> =
            pairs.iter().filter(|(k, _)| is_pid(k)).copied().collect();
        // uSimMarineV22 embeds the PID when the block has yaw gains
        // (`PIDEngine::hasConfigSettingsForPID`); other PID keys alone are taken and unused.
        let coupled = pid_pairs.iter().any(|(k, _)| {
            matches!(
                lower(k).as_str(),
                "yaw_pid_kp"
                    | "yaw_pid_kd"
                    | "yaw_pid_ki"
                    | "yaw_pid_integral_limit"
                    | "yaw_pid_ki_limit"
            )
        });
        if coupled {
            let (pid, w) = crate::pid::PidConfig::from_params_lenient(pid_pairs)?;
            unknown.extend(w);
            cfg.pid = Some(pid);
        }
        Ok((cfg, unknown))
    }

    fn apply_one(&mut self, key: &str, p: Param<'_>) -> Result<bool, ConfigError> {
        match key {
            "prefix" => self.prefix = p.word()?,
            "start_x" => self.start.x = p.f64()?,
            "start_y" => self.start.y = p.f64()?,
            "start_heading" => self.start.heading = p.f64()?,
            "start_speed" => self.start.speed = p.f64()?,
            "start_depth" => self.start.depth = p.non_neg()?,
            "start_pos" => self.start.apply_spec(p.value).map_err(|e| p.bad(e))?,
            "turn_rate" => self.turn_rate = p.f64()?.clamp(0.0, 100.0),
            "thrust_map" => self
                .thrust_map
                .add_spec(p.value)
                .map_err(|_| p.bad("ascending thrust:speed pairs, thrust in -100..100"))?,
            "thrust_factor" => self.thrust_map.thrust_factor = p.non_neg()?,
            "thrust_reflect" => self.thrust_map.reflect = p.bool()?,
            "turn_spd_loss" => self.turn_spd_loss = p.range(0.0, 1.0, "a number in 0..1")?,
            "max_acceleration" => self.max_acceleration = p.non_neg()?,
            "max_deceleration" => self.max_deceleration = p.non_neg()?,
            "buoyancy_rate" => self.buoyancy_rate = p.f64()?,
            "max_depth_rate" => self.max_depth_rate = p.f64()?,
            "max_depth_rate_speed" => self.max_depth_rate_speed = p.f64()?,
            "max_speed" => self.max_speed = p.pos()?,
            "drift_x" | "current_x" => self.drift_x = p.f64()?,
            "drift_y" | "current_y" => self.drift_y = p.f64()?,
            "drift_vector" => {
                let (x, y) = drift_from_vector(p.value).ok_or_else(|| p.bad("angle,magnitude"))?;
                self.drift_x = x;
                self.drift_y = y;
            }
            "rotate_speed" => self.rotate_speed = p.f64()?,
            "default_water_depth" | "water_depth" => self.water_depth = p.non_neg()?,
            "turn_radius" => self.turn_radius = p.non_neg()?,
            "max_rudder_degs_per_sec" => self.max_rudder_degs_per_sec = p.non_neg()?,
            "turn_spd_map_null_speed" => self.tsm_null_speed = p.non_neg()?,
            "turn_spd_map_null_rate" => self.tsm_null_rate = p.range(0.0, 100.0, "0..100")?,
            // The C++ engine overwrites the full speed (5 m/s) and full rate (turn_rate) of the
            // map on every step, so these two keys are accepted but have no effect there either.
            "turn_spd_map_full_speed" | "turn_spd_map_full_rate" => {
                p.non_neg()?;
            }
            "thrust_mode_reverse" => {
                self.thrust_mode_reverse = match p.value.to_ascii_lowercase().as_str() {
                    "reverse" | "true" => true,
                    "normal" | "false" => false,
                    _ => return Err(p.bad("reverse, normal, true or false")),
                }
            }
            "thrust_mode_diff" => {
                self.thrust_mode_differential = match p.value.to_ascii_lowercase().as_str() {
                    "differential" | "true" => true,
                    "normal" | "false" => false,
                    _ => return Err(p.bad("differential, normal, true or false")),
                }
            }
            "sim_pause" => self.paused = p.bool()?,
            "post_navpos_summary" => self.post_navpos_summary = p.bool()?,
            "post_des_thrust" => {
                let w = p.word()?;
                self.post_des_thrust = (w != "DESIRED_THRUST").then_some(w);
            }
            "post_des_rudder" => {
                let w = p.word()?;
                self.post_des_rudder = (w != "DESIRED_RUDDER").then_some(w);
            }
            "depth_control" => self.depth_control = p.bool()?,
            "legacy" => self.legacy = p.bool()?,
            // Not simulated by coug yet (trim handshakes, worm
            // holes): a config warning, never a silent difference.
            "dual_state" => self.dual_state = p.bool()?,
            "wind_conditions" => {
                self.wind = Some(
                    crate::polar::Wind::parse(p.value, self.wind)
                        .ok_or_else(|| p.bad("spd=<m/s>,dir=<degrees>"))?,
                )
            }
            "polar_plot" => {
                if !self.polar.add_points(p.value) {
                    return Err(p.bad("angle,pct:... with angles in 0..180, each once, pct >= 0"));
                }
            }
            "trim_tolerance" | "max_trim_delay" | "wormhole" => {
                return Err(p.bad(
                    "a setting coug's simulator supports (this feature is not simulated yet)",
                ));
            }
            _ => return Ok(false),
        }
        Ok(true)
    }
}

/// Simulated vehicle state (the C++ `NodeRecord` of the model).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SimState {
    /// x, metres east of the origin.
    pub x: f64,
    /// y, metres north of the origin.
    pub y: f64,
    /// Compass heading, degrees `[0, 360)`.
    pub heading: f64,
    /// Speed through the water, m/s.
    pub speed: f64,
    /// Depth, metres (>= 0).
    pub depth: f64,
    /// Pitch, radians (negative = nose down, as in the C++ model).
    pub pitch: f64,
    /// Yaw, radians: `-rad(angle180(heading))`.
    pub yaw: f64,
    /// Speed over ground, m/s.
    pub speed_og: f64,
    /// Heading over ground, degrees.
    pub heading_og: f64,
    /// Elapsed simulated time, seconds.
    pub time: f64,
}

impl SimState {
    /// The state at a starting pose.
    pub fn at(start: &StartPose) -> Self {
        SimState {
            x: start.x,
            y: start.y,
            heading: angle360(start.heading),
            speed: start.speed,
            depth: start.depth.max(0.0),
            yaw: -angle180(start.heading).to_radians(),
            ..SimState::default()
        }
    }
}

/// Actuator and environment inputs of one step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SimInputs {
    /// `DESIRED_THRUST`, percent.
    pub thrust: f64,
    /// `DESIRED_RUDDER`, -100..100.
    pub rudder: f64,
    /// `DESIRED_ELEVATOR`, -100..100 (positive dives).
    pub elevator: f64,
    /// `DESIRED_THRUST_L` (differential mode).
    pub thrust_left: f64,
    /// `DESIRED_THRUST_R` (differential mode).
    pub thrust_right: f64,
    /// Drift east, m/s.
    pub drift_x: f64,
    /// Drift north, m/s.
    pub drift_y: f64,
    /// External rotation, degrees/s.
    pub rotate_speed: f64,
    /// Rise rate, m/s.
    pub buoyancy_rate: f64,
    /// The wind (start-up `wind_conditions`, then `WIND_CONDITIONS` mail).
    pub wind: Option<crate::polar::Wind>,
}

impl SimInputs {
    /// Inputs with the environment (drift, rotation, buoyancy) taken from the config.
    pub fn from_config(cfg: &SimConfig) -> Self {
        SimInputs {
            drift_x: cfg.drift_x,
            drift_y: cfg.drift_y,
            rotate_speed: cfg.rotate_speed,
            buoyancy_rate: cfg.buoyancy_rate,
            wind: cfg.wind,
            ..SimInputs::default()
        }
    }
}

/// Navigation outputs of one step, as the app publishes them (before the prefix).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct NavOutputs {
    /// `<P>_X`.
    pub x: f64,
    /// `<P>_Y`.
    pub y: f64,
    /// `<P>_LAT` (when a local grid is known).
    pub lat: Option<f64>,
    /// `<P>_LONG`.
    pub lon: Option<f64>,
    /// `<P>_HEADING`.
    pub heading: f64,
    /// `<P>_SPEED`: snapped to 0.01 and capped at `max_speed`.
    pub speed: f64,
    /// `<P>_DEPTH`.
    pub depth: f64,
    /// `<P>_Z` = -depth.
    pub z: f64,
    /// `<P>_PITCH`, radians.
    pub pitch: f64,
    /// `<P>_YAW`, radians.
    pub yaw: f64,
    /// `<P>_HEADING_OVER_GROUND`.
    pub heading_og: f64,
    /// `<P>_SPEED_OVER_GROUND`.
    pub speed_og: f64,
    /// `<P>_ALTITUDE` (when the water depth is known).
    pub altitude: Option<f64>,
}

/// Turn rate (0..100) at a speed, from the turn-speed map (or the bare rate for `legacy`).
pub fn turn_rate_at(cfg: &SimConfig, speed: f64) -> f64 {
    if cfg.legacy {
        return cfg.turn_rate;
    }
    let (ns, nr, fs, fr) = (
        cfg.tsm_null_speed,
        cfg.tsm_null_rate,
        TURN_MAP_FULL_SPEED,
        cfg.turn_rate,
    );
    if speed <= ns {
        nr
    } else if speed >= fs || fs <= ns {
        fr
    } else {
        nr + (fr - nr) * (speed - ns) / (fs - ns)
    }
}

fn step_speed(
    cfg: &SimConfig,
    prev: f64,
    dt: f64,
    thrust: f64,
    rudder: f64,
    max_sail_mps: f64,
) -> f64 {
    let mut next = cfg.thrust_map.speed(thrust);
    if max_sail_mps > 0.0 && next > max_sail_mps {
        next = max_sail_mps;
    }
    let loss = (rudder.clamp(-100.0, 100.0).abs() / 100.0) * cfg.turn_spd_loss;
    next *= 1.0 - loss;
    if next > prev && cfg.max_acceleration > 0.0 && (next - prev) / dt > cfg.max_acceleration {
        next = prev + cfg.max_acceleration * dt;
    }
    if next < prev && cfg.max_deceleration > 0.0 && (prev - next) / dt > cfg.max_deceleration {
        next = prev - cfg.max_deceleration * dt;
    }
    next
}

/// Advances the vehicle by `dt` seconds. Pure: same inputs, same result.
///
/// `grid` (from the mission's `LatOrigin`/`LongOrigin`) adds latitude/longitude.
pub fn step(
    cfg: &SimConfig,
    state: &SimState,
    inputs: &SimInputs,
    dt: f64,
    grid: Option<&LocalGrid>,
) -> (SimState, NavOutputs) {
    let mut s = *state;
    if dt > 0.0 {
        let prior_speed = s.speed;
        let prior_heading = s.heading;
        let sign = if cfg.thrust_mode_reverse { -1.0 } else { 1.0 };

        // 1 + 2: speed and heading.
        let delta_deg = if cfg.thrust_mode_differential {
            let (l, r) = (
                inputs.thrust_left.clamp(-100.0, 100.0),
                inputs.thrust_right.clamp(-100.0, 100.0),
            );
            let (l, r) = if cfg.thrust_mode_reverse {
                (-r, -l)
            } else {
                (l, r)
            };
            s.speed = step_speed(cfg, prior_speed, dt, (l + r) / 2.0, (l - r) / 2.0, -1.0);
            36.0 * ((l - r) / 200.0) * dt + inputs.rotate_speed * dt
        } else {
            let thrust = sign * inputs.thrust;
            let mut rudder = sign * inputs.rudder;
            // Sailing: wind and polar plot cap the speed on the prior heading.
            let max_sail = match inputs.wind {
                Some(w) if cfg.polar.is_set() => {
                    cfg.polar.fraction(prior_heading, w.dir_deg) * w.speed_mps
                }
                _ => -1.0,
            };
            s.speed = step_speed(cfg, prior_speed, dt, thrust, rudder, max_sail);
            if s.speed == 0.0 {
                rudder = 0.0;
            }
            let rate = turn_rate_at(cfg, s.speed).clamp(0.0, 100.0);
            let raw = rudder.clamp(-100.0, 100.0) * (rate / 100.0) * dt;
            raw * (1.0 + (thrust - 50.0) / 50.0) + inputs.rotate_speed * dt
        };
        s.heading = angle360(prior_heading + delta_deg);
        s.yaw = -angle180(s.heading).to_radians();

        // 3: depth and pitch.
        let elevator = inputs.elevator.clamp(-100.0, 100.0);
        if s.speed <= 0.0 {
            s.depth -= inputs.buoyancy_rate * dt;
            s.pitch = 0.0;
        } else {
            let mut pct = 1.0;
            if cfg.max_depth_rate_speed > 0.0 {
                pct = (s.speed / cfg.max_depth_rate_speed).min(1.0);
            }
            let pct = if pct < 0.0 {
                -(-pct).sqrt()
            } else {
                pct.sqrt()
            };
            let pitch_rate = -s.pitch.sin() * s.speed;
            let actuator_rate = (elevator / 100.0) * pct * cfg.max_depth_rate;
            s.depth += (-inputs.buoyancy_rate + pitch_rate + actuator_rate) * dt;
            let r = pitch_rate + actuator_rate;
            s.pitch = if r.abs() <= s.speed {
                -(r / s.speed).asin()
            } else {
                0.0
            };
        }
        if s.depth < 0.0 {
            s.depth = 0.0;
        }
        if cfg.thrust_mode_reverse {
            s.heading = angle360(s.heading + 180.0);
            s.yaw += std::f64::consts::PI;
            if s.yaw > 2.0 * std::f64::consts::PI {
                s.yaw -= 2.0 * std::f64::consts::PI;
            }
        }

        // 4: position from the mean speed and the circular mean heading.
        let speed = (s.speed + prior_speed) / 2.0;
        let (h0, h1) = (prior_heading.to_radians(), s.heading.to_radians());
        let hdg = (h0.sin() + h1.sin()).atan2(h0.cos() + h1.cos());
        let (xdot, ydot) = (hdg.sin() * speed, hdg.cos() * speed);
        let mut new_speed = xdot.hypot(ydot);
        if speed < 0.0 {
            new_speed = -new_speed;
        }
        let (px, py) = (s.x, s.y);
        s.x = px + xdot * dt + inputs.drift_x * dt;
        s.y = py + ydot * dt + inputs.drift_y * dt;
        s.speed = new_speed;
        s.speed_og = (xdot + inputs.drift_x).hypot(ydot + inputs.drift_y);
        s.heading_og = rel_ang(px, py, s.x, s.y);
        if cfg.turn_radius > 0.0 {
            enforce_turn_limit(cfg, state, prior_heading, &mut s);
        }
        s.time += dt;
    }
    let out = nav_outputs(cfg, &s, grid);
    (s, out)
}

/// Limits the heading change of a step to what the minimum turn radius allows (the C++
/// `enforceTurnLimit`, with the radius scaled by speed/max_speed).
fn enforce_turn_limit(cfg: &SimConfig, prev: &SimState, prior_heading: f64, s: &mut SimState) {
    let (h1, h2) = (prior_heading, s.heading);
    if h1 == h2 {
        return;
    }
    let v = (prev.speed + s.speed) / 2.0;
    let mut radius = cfg.turn_radius;
    if cfg.max_speed > 0.0 && v < cfg.max_speed {
        radius *= v / cfg.max_speed;
    }
    let dist = (prev.x - s.x).hypot(prev.y - s.y);
    if radius <= 0.0 || dist <= 0.0 {
        return;
    }
    let ratio = dist / (2.0 * radius);
    if ratio >= 1.0 {
        return;
    }
    let phi = ratio.asin().to_degrees();
    let adiff = angle180(rel_ang(prev.x, prev.y, s.x, s.y) - h1).abs();
    if phi >= adiff {
        return;
    }
    let port = angle180(h2 - h1) < 0.0;
    let dir = if port { h1 - phi } else { h1 + phi };
    s.x = prev.x + dir.to_radians().sin() * dist;
    s.y = prev.y + dir.to_radians().cos() * dist;
    s.heading = angle360(if port { h1 - 2.0 * phi } else { h1 + 2.0 * phi });
    s.yaw = -angle180(s.heading).to_radians();
}

/// The published view of a state.
pub fn nav_outputs(cfg: &SimConfig, s: &SimState, grid: Option<&LocalGrid>) -> NavOutputs {
    let (lat, lon) = match grid.map(|g| g.to_latlon(s.x, s.y)) {
        Some(Ok((lat, lon))) => (Some(lat), Some(lon)),
        _ => (None, None),
    };
    let speed = ((s.speed / 0.01).round() * 0.01).min(cfg.max_speed);
    NavOutputs {
        x: s.x,
        y: s.y,
        lat,
        lon,
        heading: s.heading,
        speed,
        depth: s.depth,
        z: -s.depth,
        pitch: s.pitch,
        yaw: s.yaw,
        heading_og: angle360(s.heading_og),
        speed_og: s.speed_og,
        altitude: (cfg.water_depth > 0.0).then(|| (cfg.water_depth - s.depth).max(0.0)),
    }
}

struct SimVars {
    x: Arc<str>,
    y: Arc<str>,
    lat: Arc<str>,
    lon: Arc<str>,
    heading: Arc<str>,
    speed: Arc<str>,
    depth: Arc<str>,
    z: Arc<str>,
    pitch: Arc<str>,
    yaw: Arc<str>,
    hog: Arc<str>,
    sog: Arc<str>,
    altitude: Arc<str>,
    sim_mode: Arc<str>,
    true_x: Arc<str>,
    true_y: Arc<str>,
    drift_summary: Arc<str>,
    reset_count: Arc<str>,
    navpos_summary: Arc<str>,
    post_thrust: Option<Arc<str>>,
    post_rudder: Option<Arc<str>>,
}

impl SimVars {
    fn new(cfg: &SimConfig) -> Self {
        let p = |s: &str| -> Arc<str> { format!("{}_{s}", cfg.prefix).into() };
        SimVars {
            x: p("X"),
            y: p("Y"),
            lat: p("LAT"),
            lon: p("LONG"),
            heading: p("HEADING"),
            speed: p("SPEED"),
            depth: p("DEPTH"),
            z: p("Z"),
            pitch: p("PITCH"),
            yaw: p("YAW"),
            hog: p("HEADING_OVER_GROUND"),
            sog: p("SPEED_OVER_GROUND"),
            altitude: p("ALTITUDE"),
            sim_mode: "SIMULATION_MODE".into(),
            true_x: "TRUE_X".into(),
            true_y: "TRUE_Y".into(),
            drift_summary: "USM_DRIFT_SUMMARY".into(),
            reset_count: "USM_RESET_COUNT".into(),
            navpos_summary: "USM_NAVPOS_SUMMARY".into(),
            post_thrust: cfg.post_des_thrust.as_deref().map(Into::into),
            post_rudder: cfg.post_des_rudder.as_deref().map(Into::into),
        }
    }
}

/// The `uSimMarineV22` app: state, latest inputs and MOOS naming around [`step`].
///
/// ```
/// use vehicle::{MailValue, sim::{SimConfig, Simulator}};
/// let cfg = SimConfig::from_params([("prefix", "NAV")]).unwrap();
/// let mut sim = Simulator::new(cfg, None, 0.0);
/// sim.on_mail("DESIRED_THRUST", MailValue::Double(40.0), 0.0);
/// let mut out = Vec::new();
/// for i in 1..=20 { sim.iterate(f64::from(i) * 0.25, &mut out); }
/// assert!(vehicle::moos::last_posting(&out, "NAV_SPEED").unwrap().as_f64().unwrap() > 1.9);
/// ```
pub struct Simulator {
    cfg: SimConfig,
    grid: Option<LocalGrid>,
    state: SimState,
    inputs: SimInputs,
    vars: SimVars,
    /// The ground-truth state and its variables, with `dual_state`.
    ground_truth: Option<(SimState, SimVars)>,
    last_time: f64,
    paused: bool,
    enabled: bool,
    obstacle_hit: bool,
    iteration: u64,
    drift_fresh: bool,
    reset_count: u32,
    rudder_time: f64,
    pid: Option<Box<crate::pid::MarinePid>>,
}

/// What the embedded PID takes from the mail (uSimMarineV22 `OnNewMail`, PID part).
const PID_MAIL: &[&str] = &[
    "MOOS_MANUAL_OVERIDE",
    "MOOS_MANUAL_OVERRIDE",
    "PID_VERBOSE",
    "SPEED_FACTOR",
    "DESIRED_HEADING",
    "DESIRED_SPEED",
    "DESIRED_DEPTH",
    "NAV_HEADING",
    "NAV_SPEED",
    "NAV_DEPTH",
    "NAV_PITCH",
];

impl Simulator {
    /// A simulator at the configured start pose; `start_time` is the MOOS time of start-up.
    pub fn new(cfg: SimConfig, grid: Option<LocalGrid>, start_time: f64) -> Self {
        let cfg_pid = cfg.pid.clone();
        let state = SimState::at(&cfg.start);
        let inputs = SimInputs::from_config(&cfg);
        let vars = SimVars::new(&cfg);
        let ground_truth = cfg.dual_state.then(|| {
            let gt_cfg = SimConfig {
                prefix: format!("{}_GT", cfg.prefix),
                ..cfg.clone()
            };
            (state, SimVars::new(&gt_cfg))
        });
        Simulator {
            paused: cfg.paused,
            cfg,
            grid,
            state,
            inputs,
            vars,
            ground_truth,
            last_time: start_time,
            enabled: true,
            obstacle_hit: false,
            iteration: 0,
            drift_fresh: true,
            reset_count: 0,
            rudder_time: start_time,
            pid: cfg_pid.map(|c| Box::new(crate::pid::MarinePid::new(c))),
        }
    }

    /// The current simulated state.
    pub fn state(&self) -> &SimState {
        &self.state
    }

    /// The current inputs (latest actuator commands and environment).
    pub fn inputs(&self) -> &SimInputs {
        &self.inputs
    }

    /// The configuration.
    pub fn config(&self) -> &SimConfig {
        &self.cfg
    }

    /// The variables this app subscribes to. With the embedded PID, the helm's DESIRED_*
    /// and the override replace the actuator commands (uSimMarineV22 `registerVariables`).
    pub fn subscriptions(&self) -> Vec<&'static str> {
        const ACTUATORS: &[&str] = &[
            "DESIRED_THRUST",
            "DESIRED_RUDDER",
            "DESIRED_ELEVATOR",
            "DESIRED_THRUST_L",
            "DESIRED_THRUST_R",
        ];
        let all: &[&str] = &[
            "DESIRED_THRUST",
            "DESIRED_RUDDER",
            "DESIRED_ELEVATOR",
            "DESIRED_THRUST_L",
            "DESIRED_THRUST_R",
            "NAV_X",
            "NAV_Y",
            "NAV_HEADING",
            "USM_ENABLED",
            "USM_TURN_RATE",
            "USM_TURN_RADIUS",
            "OBSTACLE_HIT",
            "BUOYANCY_RATE",
            "WIND_CONDITIONS",
            "WATER_DEPTH",
            "CURRENT_X",
            "DRIFT_X",
            "CURRENT_Y",
            "DRIFT_Y",
            "DRIFT_VECTOR",
            "DRIFT_VECTOR_ADD",
            "DRIFT_VECTOR_MULT",
            "ROTATE_SPEED",
            "USM_SIM_PAUSED",
            "USM_RESET",
            "THRUST_MODE_REVERSE",
            "THRUST_MODE_DIFFERENTIAL",
        ];
        let mut v: Vec<&'static str> = Vec::with_capacity(all.len() + 6);
        if self.pid.is_some() {
            v.extend([
                "DESIRED_HEADING",
                "DESIRED_SPEED",
                "DESIRED_DEPTH",
                "SPEED_FACTOR",
                "MOOS_MANUAL_OVERIDE",
                "MOOS_MANUAL_OVERRIDE",
            ]);
            v.extend(all.iter().filter(|x| !ACTUATORS.contains(x)));
        } else {
            v.extend(all);
        }
        v
    }

    fn set_rudder(&mut self, desired: f64, time: f64) {
        let prev = self.inputs.rudder;
        // Without a slew limit the C++ still caps one change at 100 degrees.
        let max_change = if self.cfg.max_rudder_degs_per_sec > 0.0 {
            (time - self.rudder_time) * self.cfg.max_rudder_degs_per_sec
        } else {
            100.0
        };
        let change = (desired - prev).clamp(-max_change.max(0.0), max_change.max(0.0));
        self.inputs.rudder = prev + change;
        self.rudder_time = time;
    }

    /// Takes one piece of mail. Unknown variables are ignored; returns any immediate postings
    /// (`USM_RESET_COUNT`).
    pub fn on_mail(&mut self, var: &str, value: MailValue<'_>, time: f64) -> Option<Posting> {
        if let Some(pid) = &mut self.pid
            && PID_MAIL.contains(&var)
        {
            pid.on_mail(var, value, time);
        }
        let d = value.as_f64();
        let s = value.as_str().unwrap_or("");
        match (var, d) {
            ("DESIRED_THRUST", Some(v)) if !self.cfg.thrust_mode_differential => {
                self.inputs.thrust = v
            }
            ("DESIRED_RUDDER", Some(v)) if !self.cfg.thrust_mode_differential => {
                self.set_rudder(v, time)
            }
            ("DESIRED_ELEVATOR", Some(v)) => self.inputs.elevator = v,
            ("DESIRED_THRUST_L", Some(v)) if self.cfg.thrust_mode_differential => {
                self.inputs.thrust_left = v.clamp(-100.0, 100.0)
            }
            ("DESIRED_THRUST_R", Some(v)) if self.cfg.thrust_mode_differential => {
                self.inputs.thrust_right = v.clamp(-100.0, 100.0)
            }
            ("BUOYANCY_RATE", Some(v)) => self.inputs.buoyancy_rate = v,
            ("WIND_CONDITIONS", _) => {
                if let Some(w) = crate::polar::Wind::parse(s, self.inputs.wind) {
                    self.inputs.wind = Some(w);
                }
            }
            ("ROTATE_SPEED", Some(v)) => self.inputs.rotate_speed = v,
            ("WATER_DEPTH", Some(v)) if v >= 0.0 => self.cfg.water_depth = v,
            ("CURRENT_X" | "DRIFT_X", Some(v)) => {
                self.inputs.drift_x = v;
                self.drift_fresh = true;
            }
            ("CURRENT_Y" | "DRIFT_Y", Some(v)) => {
                self.inputs.drift_y = v;
                self.drift_fresh = true;
            }
            ("DRIFT_VECTOR" | "DRIFT_VECTOR_ADD", _) => {
                if let Some((x, y)) = drift_from_vector(s) {
                    if var == "DRIFT_VECTOR" {
                        self.inputs.drift_x = x;
                        self.inputs.drift_y = y;
                    } else {
                        self.inputs.drift_x += x;
                        self.inputs.drift_y += y;
                    }
                    self.drift_fresh = true;
                }
            }
            ("DRIFT_VECTOR_MULT", Some(m)) => {
                self.inputs.drift_x *= m;
                self.inputs.drift_y *= m;
                self.drift_fresh = true;
            }
            ("USM_TURN_RATE", Some(v)) => self.cfg.turn_rate = v.clamp(0.0, 100.0),
            ("USM_TURN_RADIUS", Some(v)) if v >= 0.0 => self.cfg.turn_radius = v,
            ("USM_SIM_PAUSED", _) => {
                if let Some(p) = crate::config::parse_bool(s) {
                    self.paused = p;
                }
            }
            ("OBSTACLE_HIT", _) => {
                if let Some(h) = crate::config::parse_bool(s) {
                    self.obstacle_hit = h;
                }
            }
            ("USM_ENABLED", _) => {
                if let Some(e) = crate::config::parse_bool(s) {
                    self.enabled = e;
                }
            }
            ("THRUST_MODE_REVERSE", _) => match s.to_ascii_lowercase().as_str() {
                "reverse" | "true" => self.cfg.thrust_mode_reverse = true,
                "normal" | "false" => self.cfg.thrust_mode_reverse = false,
                _ => {}
            },
            ("THRUST_MODE_DIFFERENTIAL", _) => match s.to_ascii_lowercase().as_str() {
                "differential" | "true" => self.cfg.thrust_mode_differential = true,
                "normal" | "false" => self.cfg.thrust_mode_differential = false,
                _ => {}
            },
            ("USM_RESET", _) => {
                let mut pose = StartPose {
                    x: self.state.x,
                    y: self.state.y,
                    heading: self.state.heading,
                    speed: self.state.speed,
                    depth: self.state.depth,
                };
                if pose.apply_spec(s).is_ok() {
                    let t = self.state.time;
                    self.state = SimState {
                        time: t,
                        ..SimState::at(&pose)
                    };
                    if let Some((gt, _)) = &mut self.ground_truth {
                        *gt = self.state;
                    }
                }
                self.reset_count += 1;
                return Some(Posting::double(
                    &self.vars.reset_count,
                    f64::from(self.reset_count),
                ));
            }
            ("NAV_X", Some(v)) if !self.enabled => {
                self.state.x = v;
                self.inputs.rudder = 0.0;
            }
            ("NAV_Y", Some(v)) if !self.enabled => {
                self.state.y = v;
                self.inputs.rudder = 0.0;
            }
            ("NAV_HEADING", Some(v)) if !self.enabled => {
                self.state.heading = angle360(v);
                self.inputs.rudder = 0.0;
            }
            _ => {}
        }
        None
    }

    /// One app iteration at MOOS time `time`: advance the model and append this iteration's
    /// postings to `out`.
    pub fn iterate(&mut self, time: f64, out: &mut Vec<Posting>) {
        self.iteration += 1;
        let dt = time - self.last_time;
        self.last_time = time;
        if self.obstacle_hit {
            // Stopped where it hit: the pose is published with zero speed, nothing moves.
            self.state.speed = 0.0;
            let nav = nav_outputs(&self.cfg, &self.state, self.grid.as_ref());
            self.post_nav(&nav, out);
            return;
        }
        if !self.enabled {
            return;
        }
        // The embedded PID: fed ownship from the model, its outputs set the actuators
        // directly (whether or not it has control, as the C++ does); `post_des_thrust` /
        // `post_des_rudder` publish them.
        if let Some(mut pid) = self.pid.take() {
            let st = self.state;
            pid.on_mail("NAV_HEADING", MailValue::Double(st.heading), time);
            pid.on_mail("NAV_SPEED", MailValue::Double(st.speed), time);
            if pid.config().depth_control {
                pid.on_mail("NAV_DEPTH", MailValue::Double(st.depth), time);
                pid.on_mail("NAV_PITCH", MailValue::Double(st.pitch), time);
            }
            let o = pid.iterate_embedded(time, out);
            self.set_rudder(o.rudder, time);
            self.inputs.thrust = o.thrust;
            self.inputs.elevator = o.elevator;
            if let Some(v) = &self.vars.post_thrust {
                out.push(Posting::double(v, o.thrust));
            }
            if let Some(v) = &self.vars.post_rudder {
                out.push(Posting::double(v, o.rudder));
            }
            self.pid = Some(pid);
        }
        if self.paused {
            // Paused time is excluded from the model's clock.
            return;
        }
        let (s, nav) = if self.ground_truth.is_some() {
            // The navigation state does not feel the drift; the ground truth does.
            let still = SimInputs {
                drift_x: 0.0,
                drift_y: 0.0,
                ..self.inputs
            };
            step(&self.cfg, &self.state, &still, dt, self.grid.as_ref())
        } else {
            step(&self.cfg, &self.state, &self.inputs, dt, self.grid.as_ref())
        };
        self.state = s;
        let gt_nav = match &mut self.ground_truth {
            Some((gt, _)) => {
                let (g, gnav) = step(&self.cfg, gt, &self.inputs, dt, self.grid.as_ref());
                *gt = g;
                Some(gnav)
            }
            None => None,
        };
        if self
            .iteration
            .is_multiple_of(u64::from(self.cfg.nav_every()))
        {
            self.post_nav(&nav, out);
            if let (Some(gnav), Some((_, gv))) = (&gt_nav, &self.ground_truth) {
                self.post_nav_as(gv, gnav, out);
            }
        }
        if self.drift_fresh {
            let (dx, dy) = (self.inputs.drift_x, self.inputs.drift_y);
            let summary = format!(
                "ang={}, mag={}, xmag={}, ymag={}",
                double_x(rel_ang(0.0, 0.0, dx, dy), 2),
                double_x(dx.hypot(dy), 2),
                double_x(dx, 3),
                double_x(dy, 3)
            );
            out.push(Posting::string(&self.vars.drift_summary, summary));
            self.drift_fresh = false;
        }
    }

    fn post_nav(&self, nav: &NavOutputs, out: &mut Vec<Posting>) {
        self.post_nav_as(&self.vars, nav, out);
    }

    /// Posts a navigation record under the variable names `v` (`<P>_*` or `<P>_GT_*`).
    fn post_nav_as(&self, v: &SimVars, nav: &NavOutputs, out: &mut Vec<Posting>) {
        out.push(Posting::double(&v.x, nav.x));
        out.push(Posting::double(&v.y, nav.y));
        if let (Some(lat), Some(lon)) = (nav.lat, nav.lon) {
            out.push(Posting::double(&v.lat, lat));
            out.push(Posting::double(&v.lon, lon));
        }
        if self.cfg.post_navpos_summary {
            let mut s = format!("x={},y={}", double_x(nav.x, 3), double_x(nav.y, 3));
            if let (Some(lat), Some(lon)) = (nav.lat, nav.lon) {
                s.push_str(&format!(
                    ",lat={},lon={}",
                    double_x(lat, 7),
                    double_x(lon, 7)
                ));
            }
            out.push(Posting::string(&v.navpos_summary, s));
        }
        out.push(Posting::double(&v.heading, nav.heading));
        out.push(Posting::double(&v.speed, nav.speed));
        out.push(Posting::double(&v.depth, nav.depth));
        if self.cfg.depth_control {
            out.push(Posting::string(&v.sim_mode, "TRUE"));
            out.push(Posting::double(&v.z, nav.z));
            out.push(Posting::double(&v.pitch, nav.pitch));
            out.push(Posting::double(&v.yaw, nav.yaw));
            out.push(Posting::double(&v.true_x, nav.x));
            out.push(Posting::double(&v.true_y, nav.y));
        }
        out.push(Posting::double(&v.hog, nav.heading_og));
        out.push(Posting::double(&v.sog, nav.speed_og));
        if let Some(a) = nav.altitude {
            out.push(Posting::double(&v.altitude, a));
        }
    }
}
