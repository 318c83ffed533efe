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
//! A bad value, or a line the C++ reports as unhandled, is a config warning
//! ([`SimConfig::from_params_lenient`]); the app runs on, as the C++ does. Keys of the PID
//! engine (see [`crate::pid::ENGINE_KEYS`]) are taken silently and used only when the block
//! has a yaw gain (the embedded PID).
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | start_pos | | `x=,y=,heading=,speed=,depth=` or `x,y,hdg,spd,dep` | origin | fields in turn (`deg`/`hdg`, `spd`, `dep` aliases), values by atof; an unknown field warns, the fields before it stay; each line counts as a reset | USM_RESET | done |
//! | start_x, start_y, start_heading, start_speed, start_depth | | number | 0 | number; start_depth >= 0 | no | done |
//! | prefix | | word | USM | no white space | no | done |
//! | turn_rate | | 0..100 | 70 | number, clipped | USM_TURN_RATE | done |
//! | turn_radius | | m | 0 | number >= 0 | USM_TURN_RADIUS | done |
//! | thrust_map | | `thrust:speed,...` | none | thrust in -100..100, sign rules, ascending | no | done |
//! | thrust_factor | | number | 20 | number >= 0 applied; the line is always reported unhandled | no | done |
//! | thrust_reflect | | `true`/`false` | false | true or false only | no | done |
//! | thrust_mode_reverse | | reverse/normal/true/false | false | applied when valid; always reported unhandled | THRUST_MODE_REVERSE | done |
//! | thrust_mode_diff | | differential/normal/true/false | normal | one of those | THRUST_MODE_DIFFERENTIAL | done |
//! | turn_spd_loss | | 0..1 | 0.85 | atof, in [0, 1] | no | done |
//! | turn_spd_map_null_speed | | m/s | 0 | > 0 | no | done |
//! | turn_spd_map_null_rate | | 0..100 | 0 | in [0, 100] | no | done |
//! | turn_spd_map_full_speed, turn_spd_map_full_rate | | number | 5 / turn_rate | > 0 / (0, 100]; overwritten each step by the C++ (no effect) | no | done |
//! | max_acceleration, max_deceleration | | m/s² | 0 (off), 0.5 | number >= 0 | no | done |
//! | max_speed | | m/s | 5 | number > 0 | no | done |
//! | buoyancy_rate | | m/s | 0.025 | number | BUOYANCY_RATE | done |
//! | max_depth_rate, max_depth_rate_speed | | number | 0.5, 2.0 | number | no | done |
//! | default_water_depth | | m | 0 | number >= 0 | WATER_DEPTH | done |
//! | drift_x, drift_y, drift_vector | | m/s, `ang,mag` | 0 | number / two numbers | CURRENT_X/Y, DRIFT_X/Y, DRIFT_VECTOR(_ADD/_MULT) | done |
//! | rotate_speed | | deg/s | 0 | number | ROTATE_SPEED | done |
//! | max_rudder_degs_per_sec | | deg/s | 0 (one change still capped at 100) | number >= 0 | no | done |
//! | sim_pause | | bool | false | MOOS boolean | USM_SIM_PAUSED | done |
//! | dual_state | | bool | false | MOOS boolean; nav without drift, `<P>_GT_*` with it | USM_RESET_NAV | done |
//! | wind_conditions | | `spd=..,dir=..` | none | piece by piece: spd (a negative one skipped), dir >= 0; anything else warns, earlier pieces stay; the polar's wind angle only on success | WIND_CONDITIONS | done |
//! | polar_plot | | `angle,pct:...` | none | angles 0..180 each once, pct >= 0; with a wind, speed capped at pct × wind speed (only above 0) | no | done |
//! | wormhole | | `tag=..,madrid_poly=..,weber_poly=..,connection=..,delay=..,id_change=..` | none | tag required; convex polygons; connection both/from_madrid/from_weber; delay >= 0; id_change boolean; unknown field warns | no | done |
//! | trim_tolerance, max_trim_delay | | number | 5, 10 | number | TRIM_CONTROL | done |
//! | post_des_thrust, post_des_rudder | | var | none | no white space; DESIRED_THRUST / DESIRED_RUDDER is unhandled | no | done |
//! | post_navpos_summary | | bool | false | MOOS boolean | no | done |
//! | PID keys (`yaw_pid_kp` ... `maxelevator`, `speed_factor`, `depth_control`, ...) | | | | as pMarinePIDV22; a yaw gain embeds the PID; a non-boolean depth_control then leaves the sim uncoupled with all defaults (Improper DEP PID Setting) | SPEED_FACTOR, MOOS_MANUAL_OVERRIDE, DESIRED_* | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | `<P>_X`, `_Y`, `_LAT`, `_LONG`, `_HEADING`, `_SPEED`, `_DEPTH` | every 2nd iteration (legacy: every), also while paused | numbers; speed snapped to 0.01, capped at max_speed | done |
//! | `<P>_Z`, `_PITCH`, `_YAW`, SIMULATION_MODE, TRUE_X, TRUE_Y | with the nav, with depth control | numbers, `TRUE` | done |
//! | `<P>_HEADING_OVER_GROUND`, `_SPEED_OVER_GROUND`, `_ALTITUDE` | with the nav (altitude with a water depth) | numbers | done |
//! | `<P>_GT_*` | with dual_state, after the nav | the ground-truth record | done |
//! | USM_RESET_COUNT | on USM_RESET | count (start_pos lines included) | done |
//! | USM_DRIFT_SUMMARY | at start, and when a new source first sets the drift | `ang=..,  mag=.., xmag=.., ymag=..` | done |
//! | USM_NAVPOS_SUMMARY | with post_navpos_summary, with the nav | `x=..,y=..[,lat=..,lon=..]` | done |
//! | post_des_thrust / post_des_rudder variables | embedded PID, every iteration | numbers | done |
//! | PID_HAS_CONTROL, PID_STALE, PID_*_DEBUG (embedded PID) | as pMarinePIDV22 | | done |
//! | BUOYANCY_REPORT | on BUOYANCY_CONTROL=true, every 5 s, completed after 5 s | `status=1,error=0,progressing,buoyancy=0.0` / `status=2,...completed...` | done |
//! | TRIM_REPORT | on TRIM_CONTROL=true, every 5 s, completed within tolerance after 5 s or after max_trim_delay | `status=..,error=0,..,trim_pitch=<deg, 5 dp>,trim_roll=0.0` | done |
//! | VIEW_ARROW | sailing (wind and polar), every 50th iteration | `ctrx=0,ctry=0,ang=..,bwid=5,blen=20,hwid=10,hlen=10,label=windmod,...` | done |
//! | `<P>_TRANSP` | with wormholes, every iteration | transparency 0..1 | done |
//! | VIEW_POLYGON | with wormholes, every 10th iteration, weber then madrid | polygon spec, `label=<tag>_weber`, white fill 0.1 | done |
//! | USM_NOGO | skewed PID mail | skew | refused: mail skew is not modelled (in-process mail carries no clock skew) |
//! | APPCAST, APP_LOG, USIMMARINEV22_ITER_GAP/_ITER_LEN (AppCastingMOOSApp) | on request, a new config warning, the first iteration; load casts | the AppCast string; the body is `buildReport`'s ([`Simulator::appcast_body`]; the wormhole lines are `WormHoleSet::getConfigSummary`'s) | done (`runtime::appcasting`; body test in this file) |
//!
//! Subscriptions (done): DESIRED_RUDDER/THRUST/ELEVATOR/THRUST_L/THRUST_R (without the
//! embedded PID) or DESIRED_HEADING/SPEED/DEPTH, SPEED_FACTOR, MOOS_MANUAL_OVERIDE/OVERRIDE
//! (with it); NAV_X, NAV_Y, NAV_HEADING (informed while disabled), USM_ENABLED,
//! USM_TURN_RADIUS, USM_TURN_RATE, OBSTACLE_HIT, USM_RESET_NAV, WIND_CONDITIONS,
//! BUOYANCY_RATE, WATER_DEPTH, CURRENT_X/Y, DRIFT_X/Y, DRIFT_VECTOR(_ADD/_MULT), ROTATE_SPEED,
//! USM_SIM_PAUSED, USM_RESET, TRIM_CONTROL, BUOYANCY_CONTROL, THRUST_MODE_REVERSE,
//! THRUST_MODE_DIFFERENTIAL.
//!
//! Known differences kept on purpose: where the C++ turn limit would take `asin` of a ratio
//! above 1 (NaN position) the step is left unlimited; the wind arrow's angle follows the wind
//! direction even when only a speed was ever given (the C++ arrow then stays at 0).

use moos_types::ByteString;

use crate::angle::{angle180, angle360, rel_ang};
use crate::config::{ConfigError, Param, apply_params, parse_number, strict};
use crate::geodesy::LocalGrid;
use crate::moos::{Posting, ValueRef};

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
    pub heading_deg: f64,
    /// Speed through the water, m/s.
    pub speed_mps: f64,
    /// Depth, metres (>= 0).
    pub depth: f64,
}

impl StartPose {
    /// Applies a `start_pos`/`USM_RESET` spec: `x=0,y=-20,heading=180,speed=0,depth=0`, or the
    /// older positional `x,y,heading,speed,depth` (MOOS `initPosition`): each field is applied
    /// in turn, values read as C `atof` reads them (a non-number is 0); an unknown field stops
    /// there with an error, the fields before it staying applied.
    pub fn apply_spec(&mut self, spec: &str) -> Result<(), &'static str> {
        for (i, item) in spec.split(',').enumerate() {
            let item = item.trim().to_ascii_lowercase();
            let (key, val) = match item.split_once('=') {
                Some((k, v)) if !v.trim().is_empty() => {
                    (k.trim().to_string(), v.trim().to_string())
                }
                Some((k, _)) => (String::new(), k.trim().to_string()),
                None => (String::new(), item.clone()),
            };
            let key = if key.is_empty() {
                ["x", "y", "heading", "speed", "depth"]
                    .get(i)
                    .map_or(String::new(), |k| (*k).to_string())
            } else {
                key
            };
            let v = atof(&val);
            match key.as_str() {
                "x" => self.x = v,
                "y" => self.y = v,
                "heading" | "deg" | "hdg" => self.heading_deg = v,
                "speed" | "spd" => self.speed_mps = v,
                "depth" | "dep" => self.depth = v,
                _ => return Err("x, y, heading (deg, hdg), speed (spd) or depth (dep)"),
            }
        }
        Ok(())
    }
}

/// C's `atof` as MOOS reads unvalidated numbers (see [`geometry::atof`]).
pub use geometry::atof;

/// `uSimMarineV22` configuration. `Default` gives the MOOS defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct SimConfig {
    /// Output prefix (`prefix`, default `USM`; missions set `NAV`).
    pub prefix: String,
    /// Starting pose.
    pub start: StartPose,
    /// Heading rate at full rudder (100), 50% thrust and full speed, degrees/s, 0..100
    /// (`turn_rate`, 70).
    pub turn_rate_deg_s: f64,
    /// Thrust to speed (`thrust_map`, `thrust_factor` 20, `thrust_reflect`).
    pub thrust_map: ThrustMap,
    /// Speed lost at full rudder, fraction 0..1 (`turn_spd_loss`, 0.85).
    pub turn_spd_loss: f64,
    /// m/s², 0 = unlimited (`max_acceleration`, 0).
    pub max_acceleration_mps2: f64,
    /// m/s², 0 = unlimited (`max_deceleration`, 0.5).
    pub max_deceleration_mps2: f64,
    /// Rise rate at zero speed, m/s (`buoyancy_rate`, 0.025).
    pub buoyancy_rate_mps: f64,
    /// Depth rate at full elevator and speed, m/s (`max_depth_rate`, 0.5).
    pub max_depth_rate_mps: f64,
    /// Speed at which `max_depth_rate` is reached, m/s (`max_depth_rate_speed`, 2).
    pub max_depth_rate_speed_mps: f64,
    /// Cap on the published speed, m/s (`max_speed`, 5).
    pub max_speed_mps: f64,
    /// Drift east (world frame), m/s (`drift_x`, or from `drift_vector`).
    pub drift_x_mps: f64,
    /// Drift north (world frame), m/s (`drift_y`).
    pub drift_y_mps: f64,
    /// External rotation, degrees/s (`rotate_speed`).
    pub rotate_speed_deg_s: f64,
    /// Water depth, m; 0 = unknown, no altitude (`default_water_depth`).
    pub water_depth: f64,
    /// Minimum turn radius, m; 0 = off (`turn_radius`).
    pub turn_radius: f64,
    /// Rudder slew-rate limit, degrees/s; 0 = off (`max_rudder_degs_per_sec`).
    pub max_rudder_rate_deg_s: f64,
    /// Turn-speed map: speed at and below which the turn rate is `tsm_null_rate_deg_s`, m/s
    /// (`turn_spd_map_null_speed`, 0).
    pub tsm_null_speed_mps: f64,
    /// Turn-speed map: the turn rate at the null speed, degrees/s at full rudder, 0..100
    /// (`turn_spd_map_null_rate`, 0).
    pub tsm_null_rate_deg_s: f64,
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
    /// The wind direction the polar plot was last told (MOOS `PolarPlot::setWindAngle`, only on
    /// a fully read `wind_conditions`), degrees.
    pub polar_wind_deg: f64,
    /// How many `start_pos` lines the block had: each counts as a reset (MOOS `initPosition`),
    /// so the first `USM_RESET` posts `USM_RESET_COUNT` = this + 1.
    pub start_pos_count: u32,
    /// The wormholes (`wormhole = tag=..,madrid_poly=..,weber_poly=..,connection=..`).
    pub wormholes: crate::wormhole::WormHoleSet,
    /// `trim_tolerance`, degrees (5): a TRIM_CONTROL request completes once |pitch| is within it.
    pub trim_tolerance_deg: f64,
    /// `max_trim_delay`, seconds (10): a TRIM_CONTROL request completes after this anyway.
    pub max_trim_delay_s: f64,
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
            turn_rate_deg_s: 70.0,
            thrust_map: ThrustMap::default(),
            turn_spd_loss: 0.85,
            max_acceleration_mps2: 0.0,
            max_deceleration_mps2: 0.5,
            buoyancy_rate_mps: 0.025,
            max_depth_rate_mps: 0.5,
            max_depth_rate_speed_mps: 2.0,
            max_speed_mps: 5.0,
            drift_x_mps: 0.0,
            drift_y_mps: 0.0,
            rotate_speed_deg_s: 0.0,
            water_depth: 0.0,
            turn_radius: 0.0,
            max_rudder_rate_deg_s: 0.0,
            tsm_null_speed_mps: 0.0,
            tsm_null_rate_deg_s: 0.0,
            thrust_mode_reverse: false,
            thrust_mode_differential: false,
            paused: false,
            post_navpos_summary: false,
            dual_state: false,
            wind: None,
            polar: crate::polar::Polar::default(),
            polar_wind_deg: 0.0,
            start_pos_count: 0,
            wormholes: crate::wormhole::WormHoleSet::default(),
            trim_tolerance_deg: 5.0,
            max_trim_delay_s: 10.0,
            post_des_thrust: None,
            post_des_rudder: None,
            depth_control: true,
            pid: None,
            legacy: false,
            nav_modulo: 2,
        }
    }
}

/// Speed at which the turn-speed map reaches the full turn rate, m/s (hard-coded in the C++
/// engine).
pub const TURN_MAP_FULL_SPEED_MPS: f64 = 5.0;

/// Turns a drift vector `angle,magnitude` (compass degrees, m/s) into `(x, y)` m/s.
pub fn drift_from_vector(spec: &str) -> Option<(f64, f64)> {
    let (a, m) = spec.split_once(',')?;
    let ang_deg = angle360(parse_number(a)?);
    let mag_mps = parse_number(m)?;
    let math_rad = crate::angle::heading_to_radians(ang_deg);
    Some((math_rad.cos() * mag_mps, math_rad.sin() * mag_mps))
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
        // The PID engine takes its keys first (`PIDEngine::setConfigParams`): they are never
        // reported as unhandled by the simulator, and have effect only when the PID is embedded.
        let sim_pairs = pairs.iter().filter(|(k, _)| !is_pid(k)).copied();
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
            // A depth_control that is not a boolean fails the PID's depth settings: the C++
            // start-up stops there, so the simulator runs uncoupled with every default.
            if let Some((k, v)) = pid_pairs
                .iter()
                .find(|(k, _)| lower(k) == "depth_control")
                .filter(|(_, v)| crate::config::parse_bool(v).is_none() && lower(v) != "toggle")
            {
                return Ok((
                    SimConfig::default(),
                    vec![ConfigError::BadValue {
                        app: APP,
                        key: k.trim().to_string(),
                        value: v.trim().to_string(),
                        expected: "true or false (Improper DEP PID Setting: the simulator runs uncoupled, with its defaults)",
                    }],
                ));
            }
        }
        let mut unknown = apply_params(APP, &mut cfg, sim_pairs, Self::apply_one)?;
        if coupled {
            let (pid, w) = crate::pid::PidConfig::from_params_lenient(pid_pairs)?;
            unknown.extend(w);
            cfg.depth_control = pid.depth_control;
            cfg.pid = Some(pid);
        }
        Ok((cfg, unknown))
    }

    fn apply_one(&mut self, key: &str, p: Param<'_>) -> Result<bool, ConfigError> {
        match key {
            "prefix" => self.prefix = p.word()?,
            "start_x" => self.start.x = p.f64()?,
            "start_y" => self.start.y = p.f64()?,
            "start_heading" => self.start.heading_deg = p.f64()?,
            "start_speed" => self.start.speed_mps = p.f64()?,
            "start_depth" => self.start.depth = p.non_neg()?,
            "start_pos" => {
                self.start_pos_count += 1;
                self.start.apply_spec(p.value).map_err(|e| p.bad(e))?
            }
            "turn_rate" => self.turn_rate_deg_s = p.f64()?.clamp(0.0, 100.0),
            "thrust_map" => self
                .thrust_map
                .add_spec(p.value)
                .map_err(|_| p.bad("ascending thrust:speed pairs, thrust in -100..100"))?,
            // The C++ applies a number >= 0 but never marks the line handled: it always warns.
            "thrust_factor" => {
                if let Ok(v) = p.non_neg() {
                    self.thrust_map.thrust_factor = v;
                }
                return Err(p.bad("(uSimMarineV22 reports every thrust_factor line as unhandled)"));
            }
            "thrust_reflect" => {
                self.thrust_map.reflect = match p.value.to_ascii_lowercase().as_str() {
                    "true" => true,
                    "false" => false,
                    _ => return Err(p.bad("true or false")),
                }
            }
            // Read with `atof` (a non-number is 0), then checked against [0, 1].
            "turn_spd_loss" => match atof(p.value) {
                v if (0.0..=1.0).contains(&v) => self.turn_spd_loss = v,
                _ => return Err(p.bad("a number in 0..1")),
            },
            "max_acceleration" => self.max_acceleration_mps2 = p.non_neg()?,
            "max_deceleration" => self.max_deceleration_mps2 = p.non_neg()?,
            "buoyancy_rate" => self.buoyancy_rate_mps = p.f64()?,
            "max_depth_rate" => self.max_depth_rate_mps = p.f64()?,
            "max_depth_rate_speed" => self.max_depth_rate_speed_mps = p.f64()?,
            "max_speed" => self.max_speed_mps = p.pos()?,
            "drift_x" => self.drift_x_mps = p.f64()?,
            "drift_y" => self.drift_y_mps = p.f64()?,
            "drift_vector" => {
                let (x, y) = drift_from_vector(p.value).ok_or_else(|| p.bad("angle,magnitude"))?;
                self.drift_x_mps = x;
                self.drift_y_mps = y;
            }
            "rotate_speed" => self.rotate_speed_deg_s = p.f64()?,
            "default_water_depth" => self.water_depth = p.non_neg()?,
            "turn_radius" => self.turn_radius = p.non_neg()?,
            "max_rudder_degs_per_sec" => self.max_rudder_rate_deg_s = p.non_neg()?,
            "turn_spd_map_null_speed" => self.tsm_null_speed_mps = p.pos()?,
            "turn_spd_map_null_rate" => self.tsm_null_rate_deg_s = p.range(0.0, 100.0, "0..100")?,
            // The C++ engine overwrites the full speed (5 m/s) and full rate (turn_rate) of the
            // map on every step, so these two keys are checked but have no effect there either.
            "turn_spd_map_full_speed" => {
                p.pos()?;
            }
            "turn_spd_map_full_rate" => match parse_number(p.value) {
                Some(v) if v > 0.0 && v <= 100.0 => {}
                _ => return Err(p.bad("a number in (0, 100]")),
            },
            // The C++ applies a valid value but never marks the line handled: it always warns.
            "thrust_mode_reverse" => {
                match p.value.to_ascii_lowercase().as_str() {
                    "reverse" | "true" => self.thrust_mode_reverse = true,
                    "normal" | "false" => self.thrust_mode_reverse = false,
                    _ => {}
                }
                return Err(p.bad(
                    "reverse, normal, true or false (uSimMarineV22 reports every thrust_mode_reverse line as unhandled)",
                ));
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
            "post_des_thrust" if p.value != "DESIRED_THRUST" => {
                self.post_des_thrust = Some(p.word()?)
            }
            "post_des_rudder" if p.value != "DESIRED_RUDDER" => {
                self.post_des_rudder = Some(p.word()?)
            }
            "post_des_thrust" | "post_des_rudder" => {
                return Err(p.bad("a variable other than the one the PID posts"));
            }
            "dual_state" => self.dual_state = p.bool()?,
            "wind_conditions" => {
                if !crate::polar::Wind::apply(p.value, &mut self.wind) {
                    return Err(p.bad("spd=<m/s>,dir=<degrees>"));
                }
                self.polar_wind_deg = self.wind.map_or(0.0, |w| w.dir_deg);
            }
            "polar_plot" => {
                if !self.polar.add_points(p.value) {
                    return Err(p.bad("angle,pct:... with angles in 0..180, each once, pct >= 0"));
                }
            }
            "trim_tolerance" => self.trim_tolerance_deg = p.f64()?,
            "max_trim_delay" => self.max_trim_delay_s = p.f64()?,
            "wormhole" => self.wormholes.add_config(p.value).map_err(|e| {
                p.bad(match e {
                    crate::wormhole::WormHoleError::NoTag => "a wormhole with tag=<name>",
                    crate::wormhole::WormHoleError::BadPolygon(_) => {
                        "convex madrid_poly / weber_poly polygons"
                    }
                    crate::wormhole::WormHoleError::BadConnection => {
                        "connection = both, from_madrid or from_weber"
                    }
                    crate::wormhole::WormHoleError::BadDelay => "delay >= 0",
                    crate::wormhole::WormHoleError::BadIdChange => "id_change = true or false",
                    crate::wormhole::WormHoleError::UnknownField(_) => {
                        "tag, madrid_poly, weber_poly, connection, delay, id_change"
                    }
                })
            })?,
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
    pub heading_deg: f64,
    /// Speed through the water, m/s.
    pub speed_mps: f64,
    /// Depth, metres (>= 0).
    pub depth: f64,
    /// Pitch, radians (negative = nose down, as in the C++ model).
    pub pitch_rad: f64,
    /// Yaw, radians: `-rad(angle180(heading_deg))`.
    pub yaw_rad: f64,
    /// Speed over ground (water speed plus drift), m/s.
    pub speed_og_mps: f64,
    /// Heading over ground (the direction of the last step's displacement), degrees.
    pub heading_og_deg: f64,
    /// Elapsed simulated time, seconds (the sum of the steps' `dt_s`, not MOOS time).
    pub elapsed_s: f64,
}

impl SimState {
    /// The state at a starting pose.
    pub fn at(start: &StartPose) -> Self {
        SimState {
            x: start.x,
            y: start.y,
            heading_deg: angle360(start.heading_deg),
            speed_mps: start.speed_mps,
            depth: start.depth.max(0.0),
            yaw_rad: -angle180(start.heading_deg).to_radians(),
            ..SimState::default()
        }
    }
}

/// Actuator and environment inputs of one step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SimInputs {
    /// `DESIRED_THRUST`, percent.
    pub thrust: f64,
    /// `DESIRED_RUDDER`, degrees, -100..100 (100 is full rudder in the model).
    pub rudder_deg: f64,
    /// `DESIRED_ELEVATOR`, degrees, -100..100 (positive dives; 100 is full elevator in the
    /// model).
    pub elevator_deg: f64,
    /// `DESIRED_THRUST_L` (differential mode).
    pub thrust_left: f64,
    /// `DESIRED_THRUST_R` (differential mode).
    pub thrust_right: f64,
    /// Drift east (world frame), m/s.
    pub drift_x_mps: f64,
    /// Drift north (world frame), m/s.
    pub drift_y_mps: f64,
    /// External rotation, degrees/s.
    pub rotate_speed_deg_s: f64,
    /// Rise rate, m/s.
    pub buoyancy_rate_mps: f64,
    /// The wind (start-up `wind_conditions`, then `WIND_CONDITIONS` mail).
    pub wind: Option<crate::polar::Wind>,
    /// The wind direction the polar plot uses (updated only by a fully read wind spec).
    pub polar_wind_deg: f64,
}

impl SimInputs {
    /// Inputs with the environment (drift, rotation, buoyancy) taken from the config.
    pub fn from_config(cfg: &SimConfig) -> Self {
        SimInputs {
            drift_x_mps: cfg.drift_x_mps,
            drift_y_mps: cfg.drift_y_mps,
            rotate_speed_deg_s: cfg.rotate_speed_deg_s,
            buoyancy_rate_mps: cfg.buoyancy_rate_mps,
            wind: cfg.wind,
            polar_wind_deg: cfg.polar_wind_deg,
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
    /// `<P>_HEADING`, degrees.
    pub heading_deg: f64,
    /// `<P>_SPEED`, m/s: snapped to 0.01 and capped at `max_speed_mps`.
    pub speed_mps: f64,
    /// `<P>_DEPTH`.
    pub depth: f64,
    /// `<P>_Z` = -depth.
    pub z: f64,
    /// `<P>_PITCH`, radians.
    pub pitch_rad: f64,
    /// `<P>_YAW`, radians.
    pub yaw_rad: f64,
    /// `<P>_HEADING_OVER_GROUND`, degrees.
    pub heading_og_deg: f64,
    /// `<P>_SPEED_OVER_GROUND`, m/s.
    pub speed_og_mps: f64,
    /// `<P>_ALTITUDE` (when the water depth is known).
    pub altitude: Option<f64>,
}

/// Turn rate at full rudder (degrees/s, 0..100) at a speed (m/s), from the turn-speed map
/// (or the bare rate for `legacy`).
pub fn turn_rate_at(cfg: &SimConfig, speed_mps: f64) -> f64 {
    if cfg.legacy {
        return cfg.turn_rate_deg_s;
    }
    // Each step the C++ sets the map's full speed to 5 m/s and its full rate to turn_rate
    // (refused when turn_rate is 0, leaving the map's own 100); both setters pull the null
    // point down to the full one.
    let full_mps = TURN_MAP_FULL_SPEED_MPS;
    let full_deg_s = if cfg.turn_rate_deg_s > 0.0 && cfg.turn_rate_deg_s <= 100.0 {
        cfg.turn_rate_deg_s
    } else {
        100.0
    };
    let null_mps = cfg.tsm_null_speed_mps.min(full_mps);
    let null_deg_s = cfg.tsm_null_rate_deg_s.min(full_deg_s);
    if speed_mps <= null_mps {
        null_deg_s
    } else if speed_mps >= full_mps {
        full_deg_s
    } else {
        null_deg_s + (full_deg_s - null_deg_s) * (speed_mps - null_mps) / (full_mps - null_mps)
    }
}

/// The speed (m/s) after `dt_s` from `prev_mps`: the thrust map's, capped by sailing,
/// reduced by the rudder's turn loss, then limited by the acceleration limits.
fn step_speed(
    cfg: &SimConfig,
    prev_mps: f64,
    dt_s: f64,
    thrust: f64,
    rudder_deg: f64,
    max_sail_mps: f64,
) -> f64 {
    let mut next_mps = cfg.thrust_map.speed(thrust);
    if max_sail_mps > 0.0 && next_mps > max_sail_mps {
        next_mps = max_sail_mps;
    }
    let loss = (rudder_deg.clamp(-100.0, 100.0).abs() / 100.0) * cfg.turn_spd_loss;
    next_mps *= 1.0 - loss;
    if next_mps > prev_mps
        && cfg.max_acceleration_mps2 > 0.0
        && (next_mps - prev_mps) / dt_s > cfg.max_acceleration_mps2
    {
        next_mps = prev_mps + cfg.max_acceleration_mps2 * dt_s;
    }
    if next_mps < prev_mps
        && cfg.max_deceleration_mps2 > 0.0
        && (prev_mps - next_mps) / dt_s > cfg.max_deceleration_mps2
    {
        next_mps = prev_mps - cfg.max_deceleration_mps2 * dt_s;
    }
    next_mps
}

/// Advances the vehicle by `dt_s` seconds. Pure: same inputs, same result.
///
/// `grid` (from the mission's `LatOrigin`/`LongOrigin`) adds latitude/longitude.
pub fn step(
    cfg: &SimConfig,
    state: &SimState,
    inputs: &SimInputs,
    dt_s: f64,
    grid: Option<&LocalGrid>,
) -> (SimState, NavOutputs) {
    let mut s = *state;
    if dt_s > 0.0 {
        let prior_speed_mps = s.speed_mps;
        let prior_heading_deg = s.heading_deg;
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
            s.speed_mps = step_speed(
                cfg,
                prior_speed_mps,
                dt_s,
                (l + r) / 2.0,
                (l - r) / 2.0,
                -1.0,
            );
            36.0 * ((l - r) / 200.0) * dt_s + inputs.rotate_speed_deg_s * dt_s
        } else {
            let thrust = sign * inputs.thrust;
            let mut rudder_deg = sign * inputs.rudder_deg;
            // Sailing: wind and polar plot cap the speed on the prior heading.
            let max_sail_mps = match inputs.wind {
                Some(w) if cfg.polar.is_set() => {
                    cfg.polar.fraction(prior_heading_deg, inputs.polar_wind_deg) * w.speed_mps
                }
                _ => -1.0,
            };
            s.speed_mps = step_speed(cfg, prior_speed_mps, dt_s, thrust, rudder_deg, max_sail_mps);
            if s.speed_mps == 0.0 {
                rudder_deg = 0.0;
            }
            let rate_deg_s = turn_rate_at(cfg, s.speed_mps).clamp(0.0, 100.0);
            let raw_deg = rudder_deg.clamp(-100.0, 100.0) * (rate_deg_s / 100.0) * dt_s;
            raw_deg * (1.0 + (thrust - 50.0) / 50.0) + inputs.rotate_speed_deg_s * dt_s
        };
        s.heading_deg = angle360(prior_heading_deg + delta_deg);
        s.yaw_rad = -angle180(s.heading_deg).to_radians();

        // 3: depth and pitch.
        let elevator_deg = inputs.elevator_deg.clamp(-100.0, 100.0);
        if s.speed_mps <= 0.0 {
            s.depth -= inputs.buoyancy_rate_mps * dt_s;
            s.pitch_rad = 0.0;
        } else {
            let mut pct = 1.0;
            if cfg.max_depth_rate_speed_mps > 0.0 {
                pct = (s.speed_mps / cfg.max_depth_rate_speed_mps).min(1.0);
            }
            let pct = if pct < 0.0 {
                -(-pct).sqrt()
            } else {
                pct.sqrt()
            };
            // Depth rates (m/s), not angular rates: the prior pitch's and the elevator's.
            let pitch_depth_rate_mps = -s.pitch_rad.sin() * s.speed_mps;
            let elevator_depth_rate_mps = (elevator_deg / 100.0) * pct * cfg.max_depth_rate_mps;
            s.depth +=
                (-inputs.buoyancy_rate_mps + pitch_depth_rate_mps + elevator_depth_rate_mps) * dt_s;
            let dive_mps = pitch_depth_rate_mps + elevator_depth_rate_mps;
            s.pitch_rad = if dive_mps.abs() <= s.speed_mps {
                -(dive_mps / s.speed_mps).asin()
            } else {
                0.0
            };
        }
        if s.depth < 0.0 {
            s.depth = 0.0;
        }
        if cfg.thrust_mode_reverse {
            s.heading_deg = angle360(s.heading_deg + 180.0);
            s.yaw_rad += std::f64::consts::PI;
            if s.yaw_rad > 2.0 * std::f64::consts::PI {
                s.yaw_rad -= 2.0 * std::f64::consts::PI;
            }
        }

        // 4: position from the mean speed and the circular mean heading.
        let model_speed_mps = s.speed_mps;
        let mean_speed_mps = (s.speed_mps + prior_speed_mps) / 2.0;
        let (h0_rad, h1_rad) = (prior_heading_deg.to_radians(), s.heading_deg.to_radians());
        // Compass convention: east = sin, north = cos of the heading.
        let mean_heading_rad = (h0_rad.sin() + h1_rad.sin()).atan2(h0_rad.cos() + h1_rad.cos());
        // Velocity through the water, east and north (world frame); the drift adds to it.
        let (water_vx_mps, water_vy_mps) = (
            mean_heading_rad.sin() * mean_speed_mps,
            mean_heading_rad.cos() * mean_speed_mps,
        );
        let mut new_speed_mps = water_vx_mps.hypot(water_vy_mps);
        if mean_speed_mps < 0.0 {
            new_speed_mps = -new_speed_mps;
        }
        let (px, py) = (s.x, s.y);
        s.x = px + water_vx_mps * dt_s + inputs.drift_x_mps * dt_s;
        s.y = py + water_vy_mps * dt_s + inputs.drift_y_mps * dt_s;
        s.speed_mps = new_speed_mps;
        s.speed_og_mps =
            (water_vx_mps + inputs.drift_x_mps).hypot(water_vy_mps + inputs.drift_y_mps);
        s.heading_og_deg = rel_ang(px, py, s.x, s.y);
        if cfg.turn_radius > 0.0 {
            enforce_turn_limit(cfg, state, prior_heading_deg, model_speed_mps, &mut s);
        }
        s.elapsed_s += dt_s;
    }
    let out = nav_outputs(cfg, &s, grid);
    (s, out)
}

/// Limits the heading change of a step to what the minimum turn radius allows (the C++
/// `enforceTurnLimit`): the radius is scaled by speed/max_speed, the speed being the mean of
/// the thrust-map speed of this step (`model_speed_mps`) and the new (mean) speed, as the C++
/// record copies give it. As in the C++ only x, y and the heading change (not the yaw).
/// Where the C++ would take `asin` of a ratio above 1 (a step longer than the turn circle)
/// and produce NaN, the step is left unlimited.
fn enforce_turn_limit(
    cfg: &SimConfig,
    prev: &SimState,
    prior_heading_deg: f64,
    model_speed_mps: f64,
    s: &mut SimState,
) {
    let (h1_deg, h2_deg) = (prior_heading_deg, s.heading_deg);
    if h1_deg == h2_deg {
        return;
    }
    let v_mps = (model_speed_mps + s.speed_mps) / 2.0;
    let mut radius = cfg.turn_radius;
    if cfg.max_speed_mps > 0.0 && v_mps < cfg.max_speed_mps {
        radius *= 1.0 - (cfg.max_speed_mps - v_mps) / cfg.max_speed_mps;
    }
    let dist = (prev.x - s.x).hypot(prev.y - s.y);
    if radius <= 0.0 {
        return;
    }
    let ratio = dist / (2.0 * radius);
    if ratio > 1.0 {
        return;
    }
    let phi_deg = ratio.asin().to_degrees();
    let adiff_deg = angle180(rel_ang(prev.x, prev.y, s.x, s.y) - h1_deg).abs();
    if phi_deg >= adiff_deg {
        return;
    }
    let port = angle180(h2_deg - h1_deg) < 0.0;
    let dir_deg = if port {
        h1_deg - phi_deg
    } else {
        h1_deg + phi_deg
    };
    s.x = prev.x + dir_deg.to_radians().sin() * dist;
    s.y = prev.y + dir_deg.to_radians().cos() * dist;
    s.heading_deg = angle360(if port {
        h1_deg - 2.0 * phi_deg
    } else {
        h1_deg + 2.0 * phi_deg
    });
}

/// The published view of a state.
pub fn nav_outputs(cfg: &SimConfig, s: &SimState, grid: Option<&LocalGrid>) -> NavOutputs {
    let (lat, lon) = match grid.map(|g| g.to_latlon(s.x, s.y)) {
        Some(Ok((lat, lon))) => (Some(lat), Some(lon)),
        _ => (None, None),
    };
    let speed_mps = ((s.speed_mps / 0.01).round() * 0.01).min(cfg.max_speed_mps);
    NavOutputs {
        x: s.x,
        y: s.y,
        lat,
        lon,
        heading_deg: s.heading_deg,
        speed_mps,
        depth: s.depth,
        z: -s.depth,
        pitch_rad: s.pitch_rad,
        yaw_rad: s.yaw_rad,
        heading_og_deg: angle360(s.heading_og_deg),
        speed_og_mps: s.speed_og_mps,
        altitude: (cfg.water_depth > 0.0).then(|| (cfg.water_depth - s.depth).max(0.0)),
    }
}

struct SimVars {
    x: ByteString,
    y: ByteString,
    lat: ByteString,
    lon: ByteString,
    heading: ByteString,
    speed: ByteString,
    depth: ByteString,
    z: ByteString,
    pitch: ByteString,
    yaw: ByteString,
    hog: ByteString,
    sog: ByteString,
    altitude: ByteString,
    sim_mode: ByteString,
    true_x: ByteString,
    true_y: ByteString,
    drift_summary: ByteString,
    reset_count: ByteString,
    navpos_summary: ByteString,
    post_thrust: Option<ByteString>,
    post_rudder: Option<ByteString>,
}

impl SimVars {
    fn new(cfg: &SimConfig) -> Self {
        let p = |s: &str| -> ByteString { format!("{}_{s}", cfg.prefix).into() };
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
/// use vehicle::{ValueRef, sim::{SimConfig, Simulator}};
/// let cfg = SimConfig::from_params([("prefix", "NAV")]).unwrap();
/// let mut sim = Simulator::new(cfg, None, 0.0);
/// sim.on_mail("DESIRED_THRUST", ValueRef::Double(40.0), 0.0);
/// let mut out = Vec::new();
/// for i in 1..=20 { sim.iterate(f64::from(i) * 0.25, &mut out); }
/// assert!(vehicle::moos::last_posting(&out, "NAV_SPEED").unwrap().as_f64().unwrap() > 1.9);
/// ```
pub struct Simulator {
    cfg: SimConfig,
    grid: Option<LocalGrid>,
    state: SimState,
    /// The ground-truth record (MOOS `m_record_gt`): propagated (with the drift) only with
    /// `dual_state`, but always kept, reset and informed with the navigation record.
    gt: SimState,
    inputs: SimInputs,
    vars: SimVars,
    /// `<P>_GT_*` names, with `dual_state`.
    gt_vars: Option<SimVars>,
    last_time: f64,
    paused: bool,
    enabled: bool,
    obstacle_hit: bool,
    iteration: u64,
    drift_fresh: bool,
    drift_sources: std::collections::BTreeSet<String>,
    reset_count: u32,
    rudder_time: f64,
    pid: Option<Box<crate::pid::MarinePid>>,
    buoyancy_request: Option<f64>,
    trim_request: Option<f64>,
    last_report: f64,
    transp_var: ByteString,
    /// The environment at start-up (the C++ `cacheStartingInfo`), for the appcast.
    start_inputs: SimInputs,
    /// The water depth at start-up.
    start_water_depth: f64,
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

/// The mail whose value is a number.
const NUMERIC_MAIL: &[&str] = &[
    "DESIRED_THRUST",
    "DESIRED_RUDDER",
    "DESIRED_ELEVATOR",
    "DESIRED_THRUST_L",
    "DESIRED_THRUST_R",
    "BUOYANCY_RATE",
    "ROTATE_SPEED",
    "CURRENT_X",
    "DRIFT_X",
    "CURRENT_Y",
    "DRIFT_Y",
    "DRIFT_VECTOR_MULT",
    "WATER_DEPTH",
    "USM_TURN_RATE",
    "USM_TURN_RADIUS",
    "NAV_X",
    "NAV_Y",
    "NAV_HEADING",
];

/// Seconds before a BUOYANCY_CONTROL / TRIM_CONTROL request may complete (the C++ `m_buoyancy_delay`).
const BUOYANCY_DELAY_S: f64 = 5.0;
/// Seconds between "progressing" reports (the C++ `m_report_interval`).
const REPORT_INTERVAL_S: f64 = 5.0;

impl Simulator {
    /// A simulator at the configured start pose; `start_time` is the MOOS time of start-up.
    pub fn new(cfg: SimConfig, grid: Option<LocalGrid>, start_time: f64) -> Self {
        let cfg_pid = cfg.pid.clone();
        let state = SimState::at(&cfg.start);
        let inputs = SimInputs::from_config(&cfg);
        let vars = SimVars::new(&cfg);
        let gt_vars = cfg.dual_state.then(|| {
            SimVars::new(&SimConfig {
                prefix: format!("{}_GT", cfg.prefix),
                ..cfg.clone()
            })
        });
        Simulator {
            paused: cfg.paused,
            grid,
            state,
            gt: state,
            inputs,
            vars,
            gt_vars,
            last_time: start_time,
            enabled: true,
            obstacle_hit: false,
            iteration: 0,
            drift_fresh: true,
            drift_sources: std::collections::BTreeSet::new(),
            reset_count: cfg.start_pos_count,
            rudder_time: 0.0,
            pid: cfg_pid.map(|c| Box::new(crate::pid::MarinePid::new(c))),
            buoyancy_request: None,
            trim_request: None,
            last_report: 0.0,
            transp_var: format!("{}_TRANSP", cfg.prefix).into(),
            start_inputs: inputs,
            start_water_depth: cfg.water_depth,
            cfg,
        }
    }

    /// Appends the uSimMarineV22 appcast report body (`USM_MOOSApp::buildReport`): the
    /// settings, the pose table (start, navigation, ground truth with `dual_state`), the
    /// buoyancy, the drift table, the velocity and depth settings and the wormholes. `now`
    /// is not needed (the C++ report shows no time) and is taken for a uniform signature.
    ///
    /// Reproduced as the C++ writes them, quirks included: the ground-truth column's heading
    /// is the navigation heading, the positive thrust map is written `thrust,speed` pairs
    /// (`, ` between pairs), `Accereration`/`Decereration`, the start column's latitude and
    /// longitude are always 0 and its altitude is the water depth minus the start depth
    /// unclipped. Approximated: the wind model without a `wind_conditions` is written as
    /// the C++ default `spd=0, dir=0`; the polar plot as its points as configured
    /// (`angle,pct` joined by `:`) where the C++ writes its interpolated set points; the
    /// wormhole section as `Total WormHoles: N`, then per wormhole its `tag=..,
    /// connection=.., delay=.., id_change=..` line and its two polygon specs.
    ///
    /// Appcast notes: uSimMarineV22 reports no run warnings and no events at a2a9b716;
    /// its appcast messages are config warnings at start-up (`No config block found for
    /// uSimMarineV22`, `Improper YAW PID Setting`, `Improper SPD PID Setting`,
    /// `Improper DEP PID Setting`, and each unhandled line), which coug reports through
    /// [`SimConfig::from_params_lenient`].
    pub fn appcast_body(&self, _now: f64, out: &mut String) {
        let b = |v: bool| if v { "true" } else { "false" };
        let x = moos_types::fmt::compact_string;
        let line = |out: &mut String, label: &str, value: &str| {
            out.push_str(label);
            out.push_str(value);
            out.push('\n');
        };
        let cfg = &self.cfg;
        let wd = cfg.water_depth;
        let alt = |depth: f64| (wd - depth).max(0.0);
        let latlon = |st: &SimState| {
            self.grid
                .as_ref()
                .and_then(|g| g.to_latlon(st.x, st.y).ok())
                .unwrap_or((0.0, 0.0))
        };
        let (nav, gt) = (&self.state, &self.gt);
        let dual = cfg.dual_state;
        let sailing = self.inputs.wind.is_some() && cfg.polar.is_set();
        line(out, "Enabled:  ", b(self.enabled));
        line(out, "TurnRate: ", &x(cfg.turn_rate_deg_s, 2));
        line(out, "TurnRadius: ", &x(cfg.turn_radius, 2));
        let datum = match &self.grid {
            Some(g) => format!("{},{}", x(g.lat_origin(), 9), x(g.lon_origin(), 9)),
            None => "?,?".to_string(),
        };
        line(out, "Datum: ", &datum);
        out.push_str("Sailing:\n");
        let wind = match self.inputs.wind {
            Some(w) => format!("spd={}, dir={}", x(w.speed_mps, 3), x(w.dir_deg, 5)),
            None => "spd=0, dir=0".to_string(),
        };
        line(out, "  WindModel: ", &wind);
        line(out, "  PolarPlot: ", &cfg.polar.spec());
        line(out, "  Enabled:   ", b(sailing));
        if let Some(v) = &cfg.post_des_thrust {
            line(out, "  post_des_thrust:   ", v);
        }
        if let Some(v) = &cfg.post_des_rudder {
            line(out, "  post_des_rudder:   ", v);
        }
        out.push_str("\n\n");

        // Part 1: the poses.
        let mut t = appcast::Table::with_pad(6, 1);
        t.push("Start | Pose | Current | Pose (NAV) | Current | Pose (GT)");
        t.add_header_lines();
        t.set_column_pad_str(1, "   ");
        t.set_column_pad_str(3, "   ");
        for ix in [0, 2, 4] {
            t.set_right_justify(ix, true);
        }
        let st = &cfg.start;
        let (nav_lat, nav_lon) = latlon(nav);
        let (gt_lat, gt_lon) = latlon(gt);
        let rows: [(&str, String, String, String); 7] = [
            (
                "Headng:",
                x(st.heading_deg, 1),
                x(nav.heading_deg, 1),
                x(nav.heading_deg, 1),
            ),
            (
                "Speed:",
                x(st.speed_mps, 2),
                x(nav.speed_mps, 2),
                x(gt.speed_mps, 2),
            ),
            ("Depth:", x(st.depth, 2), x(nav.depth, 1), x(gt.depth, 1)),
            (
                "Alt:",
                x(self.start_water_depth - st.depth, 2),
                x(alt(nav.depth), 1),
                x(alt(gt.depth), 1),
            ),
            (
                "(X,Y):",
                format!("{},{}", x(st.x, 2), x(st.y, 2)),
                format!("{},{}", x(nav.x, 2), x(nav.y, 2)),
                format!("{},{}", x(gt.x, 2), x(gt.y, 2)),
            ),
            ("Lat:", "0".into(), x(nav_lat, 8), x(gt_lat, 8)),
            ("Lon:", "0".into(), x(nav_lon, 8), x(gt_lon, 8)),
        ];
        for (i, (label, start, now_nav, now_gt)) in rows.iter().enumerate() {
            t.push(label);
            t.push(start);
            t.push(label);
            t.push(now_nav);
            if dual {
                t.push(label);
                t.push(now_gt);
            } else {
                t.push(if i == 0 { "(same)" } else { " " });
                t.push("-");
            }
        }
        t.write(out);

        // Part 2: buoyancy.
        out.push_str("\n\n");
        line(
            out,
            "Present Buoyancy rate: ",
            &x(self.inputs.buoyancy_rate_mps, 8),
        );
        line(
            out,
            "        Starting rate: ",
            &x(self.start_inputs.buoyancy_rate_mps, 8),
        );

        // Part 3: drift.
        out.push('\n');
        let mut t = appcast::Table::with_pad(7, 2);
        t.push("Ext Drift | X | Y | Mag | Ang | Rot. |Source(s)");
        t.add_header_lines();
        t.set_right_justify(0, true);
        for ix in [2, 4, 5] {
            t.set_column_pad_str(ix, "  |  ");
        }
        let si = &self.start_inputs;
        let (sx, sy) = (si.drift_x_mps, si.drift_y_mps);
        t.push("Starting");
        t.push(&x(sx, 4));
        t.push(&x(sy, 4));
        t.push(&x(sx.hypot(sy), 4));
        t.push(&x(rel_ang(0.0, 0.0, sx, sy), 4));
        t.push(&x(si.rotate_speed_deg_s, 4));
        t.push("init_config");
        let (dx, dy) = (self.inputs.drift_x_mps, self.inputs.drift_y_mps);
        let mag = x(dx.hypot(dy), 4);
        let ang = if mag == "0" {
            "0".to_string()
        } else {
            x(rel_ang(0.0, 0.0, dx, dy), 4)
        };
        let sources: Vec<&str> = self.drift_sources.iter().map(String::as_str).collect();
        let sources = if sources.is_empty() {
            "n/a".to_string()
        } else {
            sources.join(",")
        };
        t.push("Present");
        t.push(&x(dx, 3));
        t.push(&x(dy, 3));
        t.push(&mag);
        t.push(&ang);
        t.push(&x(self.inputs.rotate_speed_deg_s, 4));
        t.push(&sources);
        t.write(out);
        out.push_str("\n\n");

        // Part 4: speed and thrust.
        out.push_str("Velocity Information: \n");
        out.push_str("--------------------- \n");
        out.push_str("     DESIRED_THRUST=");
        out.push_str(&x(self.inputs.thrust, 1));
        line(out, " ==> SPEED=", &x(nav.speed_mps, 2));
        let map = &cfg.thrust_map;
        out.push_str("     Using Thrust_Factor: ");
        out.push_str(b(map.using_thrust_factor()));
        if map.using_thrust_factor() {
            out.push_str(" (");
            moos_types::fmt::compact(out, map.thrust_factor, 4);
            out.push(')');
        }
        out.push('\n');
        line(out, "           Using Sailing: ", b(sailing));
        line(out, "    PID Coupled: ", b(self.pid.is_some()));
        let pairs = |v: &[(f64, f64)], sep: &str| {
            v.iter()
                .map(|(t, s)| format!("{}{sep}{}", x(*t, 4), x(*s, 4)))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let mut pos = pairs(&map.pos, ",");
        let mut neg = if map.reflect {
            "Positive thrust-map reflected".to_string()
        } else {
            pairs(&map.neg, ":")
        };
        for m in [&mut pos, &mut neg] {
            if m.is_empty() {
                *m = "n/a".into();
            }
        }
        line(out, "     Positive Thrust Map: ", &pos);
        line(out, "     Negative Thrust Map: ", &neg);
        line(
            out,
            "        Max Accereration: ",
            &x(cfg.max_acceleration_mps2, 6),
        );
        line(
            out,
            "        Max Decereration: ",
            &x(cfg.max_deceleration_mps2, 6),
        );
        out.push('\n');
        let diff = cfg.thrust_mode_differential;
        line(
            out,
            "             Thrust Mode: ",
            if diff { "differential" } else { "normal" },
        );
        line(
            out,
            "     Thrust Mode Reverse: ",
            b(cfg.thrust_mode_reverse),
        );
        let (l, r) = if diff {
            (
                x(self.inputs.thrust_left, 2),
                x(self.inputs.thrust_right, 2),
            )
        } else {
            ("n/a".to_string(), "n/a".to_string())
        };
        line(out, "        DESIRED_THRUST_L: ", &l);
        line(out, "        DESIRED_THRUST_R: ", &r);

        // Part 5: depth.
        out.push_str("\nDepth Information: \n");
        out.push_str("------------------ \n");
        line(
            out,
            "           Max Depth Rate: ",
            &x(cfg.max_depth_rate_mps, 6),
        );
        line(
            out,
            "     Max Depth Rate Speed: ",
            &x(cfg.max_depth_rate_speed_mps, 6),
        );
        line(
            out,
            "              Water Depth: ",
            &moos_types::fmt::g_string(wd, 6),
        );
        let holes = cfg.wormholes.len();
        if holes > 0 {
            out.push_str("\nWormHole Information:\n---------------------\n");
            line(out, "Total WormHoles: ", &holes.to_string());
            for h in cfg.wormholes.holes() {
                let connection = match h.connection {
                    crate::wormhole::Connection::FromMadrid => "from_madrid",
                    crate::wormhole::Connection::FromWeber => "from_weber",
                    crate::wormhole::Connection::Both => "both",
                };
                out.push_str("tag=");
                out.push_str(&h.tag);
                out.push_str(", connection=");
                out.push_str(connection);
                out.push_str(", delay=");
                out.push_str(&moos_types::fmt::compact_string(h.delay_s, 5));
                out.push_str(", id_change=");
                out.push_str(if h.id_change { "true" } else { "false" });
                out.push('\n');
                // Only convex polygons are accepted; an unset one prints `null`.
                for (label, poly) in [("madrid_poly: ", &h.madrid), ("weber_poly:  ", &h.weber)] {
                    out.push_str(label);
                    match poly {
                        Some(p) => p.spec(out),
                        None => out.push_str("null"),
                    }
                    out.push('\n');
                }
            }
        }
    }

    /// The current simulated (navigation) state.
    pub fn state(&self) -> &SimState {
        &self.state
    }

    /// The ground-truth state (moves apart from [`Simulator::state`] only with `dual_state`).
    pub fn ground_truth(&self) -> &SimState {
        &self.gt
    }

    /// The current inputs (latest actuator commands and environment).
    pub fn inputs(&self) -> &SimInputs {
        &self.inputs
    }

    /// The configuration.
    pub fn config(&self) -> &SimConfig {
        &self.cfg
    }

    /// The number of resets so far (`start_pos` lines and USM_RESET mail).
    pub fn reset_count(&self) -> u32 {
        self.reset_count
    }

    /// The variables this app subscribes to. With the embedded PID, the helm's DESIRED_*
    /// and the override replace the actuator commands (uSimMarineV22 `registerVariables`).
    pub fn subscriptions(&self) -> Vec<&'static str> {
        let mut v: Vec<&'static str> = Vec::with_capacity(40);
        if self.pid.is_some() {
            v.extend([
                "DESIRED_HEADING",
                "DESIRED_SPEED",
                "DESIRED_DEPTH",
                "SPEED_FACTOR",
                "MOOS_MANUAL_OVERIDE",
                "MOOS_MANUAL_OVERRIDE",
            ]);
        } else {
            v.extend([
                "DESIRED_RUDDER",
                "DESIRED_THRUST",
                "DESIRED_ELEVATOR",
                "DESIRED_THRUST_L",
                "DESIRED_THRUST_R",
            ]);
        }
        v.extend([
            "NAV_X",
            "NAV_Y",
            "NAV_HEADING",
            "USM_ENABLED",
            "USM_TURN_RADIUS",
            "USM_TURN_RATE",
            "OBSTACLE_HIT",
            "USM_RESET_NAV",
            "WIND_CONDITIONS",
            "BUOYANCY_RATE",
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
            "TRIM_CONTROL",
            "BUOYANCY_CONTROL",
            "THRUST_MODE_REVERSE",
            "THRUST_MODE_DIFFERENTIAL",
        ]);
        v
    }

    /// MOOS `setRudder(value, time)`: the change from the current rudder is capped at
    /// `max_rudder_degs_per_sec` × the time since the last command (100 without a limit).
    fn set_rudder(&mut self, desired_deg: f64, time: f64) {
        if self.cfg.thrust_mode_differential {
            return;
        }
        let prev_deg = self.inputs.rudder_deg;
        let max_change_deg = if self.cfg.max_rudder_rate_deg_s > 0.0 {
            (time - self.rudder_time) * self.cfg.max_rudder_rate_deg_s
        } else {
            100.0
        };
        let mut change_deg = desired_deg - prev_deg;
        if change_deg > 0.0 {
            change_deg = change_deg.min(max_change_deg);
        } else if -change_deg > max_change_deg {
            change_deg = -max_change_deg;
        }
        self.inputs.rudder_deg = prev_deg + change_deg;
        self.rudder_time = time;
    }

    fn set_drift(&mut self, x_mps: f64, y_mps: f64, source: &str) {
        self.inputs.drift_x_mps = x_mps;
        self.inputs.drift_y_mps = y_mps;
        // As `setDriftX/Y`: the summary is re-posted when a source drifts the vehicle for the
        // first time.
        if !source.is_empty() && self.drift_sources.insert(source.to_string()) {
            self.drift_fresh = true;
        }
    }

    /// Takes one piece of mail with no known source; see [`Simulator::on_mail_from`].
    pub fn on_mail(&mut self, var: &str, value: ValueRef<'_>, time: f64) -> Option<Posting> {
        self.on_mail_from(var, value, time, "")
    }

    /// Takes one piece of mail written by `source` (the first drift mail from each source
    /// re-posts `USM_DRIFT_SUMMARY`). Unknown variables are ignored; returns any immediate
    /// posting (`USM_RESET_COUNT`, `BUOYANCY_REPORT`, `TRIM_REPORT`).
    pub fn on_mail_from(
        &mut self,
        var: &str,
        value: ValueRef<'_>,
        time: f64,
        source: &str,
    ) -> Option<Posting> {
        if let Some(pid) = &mut self.pid
            && PID_MAIL.contains(&var)
        {
            pid.on_mail(var, value, time);
        }
        // Numeric variables take double mail only (a string leaves the setting as it was).
        let num = match value {
            ValueRef::Double(d) => Some(d),
            ValueRef::String(_) | ValueRef::Binary(_) => None,
        };
        let d = num.unwrap_or(0.0);
        let s = value.as_str().unwrap_or("");
        let normal = !self.cfg.thrust_mode_differential;
        match var {
            _ if num.is_none() && NUMERIC_MAIL.contains(&var) => {}
            "DESIRED_THRUST" if normal => self.inputs.thrust = d,
            "DESIRED_RUDDER" => self.set_rudder(d, time),
            "DESIRED_ELEVATOR" => self.inputs.elevator_deg = d,
            "DESIRED_THRUST_L" | "DESIRED_THRUST_R" if !normal => {
                let v = d.clamp(-100.0, 100.0);
                match (var == "DESIRED_THRUST_L", self.cfg.thrust_mode_reverse) {
                    (true, false) => self.inputs.thrust_left = v,
                    (true, true) => self.inputs.thrust_right = -v,
                    (false, false) => self.inputs.thrust_right = v,
                    (false, true) => self.inputs.thrust_left = -v,
                }
            }
            "USM_SIM_PAUSED" => {
                if let Some(p) = crate::config::parse_bool(s) {
                    self.paused = p;
                }
            }
            "THRUST_MODE_REVERSE" => match s.to_ascii_lowercase().as_str() {
                "reverse" | "true" => self.cfg.thrust_mode_reverse = true,
                "normal" | "false" => self.cfg.thrust_mode_reverse = false,
                _ => {}
            },
            "THRUST_MODE_DIFFERENTIAL" => match s.to_ascii_lowercase().as_str() {
                "differential" | "true" => self.cfg.thrust_mode_differential = true,
                "normal" | "false" => self.cfg.thrust_mode_differential = false,
                _ => {}
            },
            "BUOYANCY_RATE" => self.inputs.buoyancy_rate_mps = d,
            // Applied piece by piece; the polar's wind angle follows only a fully read spec.
            "WIND_CONDITIONS" if crate::polar::Wind::apply(s, &mut self.inputs.wind) => {
                self.inputs.polar_wind_deg = self.inputs.wind.map_or(0.0, |w| w.dir_deg);
            }
            "ROTATE_SPEED" => self.inputs.rotate_speed_deg_s = d,
            "CURRENT_X" | "DRIFT_X" => self.set_drift(d, self.inputs.drift_y_mps, source),
            "CURRENT_Y" | "DRIFT_Y" => self.set_drift(self.inputs.drift_x_mps, d, source),
            "DRIFT_VECTOR" | "DRIFT_VECTOR_ADD" => {
                if let Some((x, y)) = drift_from_vector(s) {
                    if var == "DRIFT_VECTOR" {
                        self.set_drift(x, y, source);
                    } else {
                        let (dx, dy) = (self.inputs.drift_x_mps + x, self.inputs.drift_y_mps + y);
                        self.set_drift(dx, dy, source);
                    }
                }
            }
            "DRIFT_VECTOR_MULT" => {
                let (dx, dy) = (self.inputs.drift_x_mps, self.inputs.drift_y_mps);
                let ang_deg = rel_ang(0.0, 0.0, dx, dy);
                let mag_mps = dx.hypot(dy) * d;
                let math_rad = crate::angle::heading_to_radians(ang_deg);
                self.set_drift(math_rad.cos() * mag_mps, math_rad.sin() * mag_mps, source);
            }
            "WATER_DEPTH" if d >= 0.0 => self.cfg.water_depth = d,
            "USM_RESET" => {
                self.reset_count += 1;
                let pose = |st: &SimState| StartPose {
                    x: st.x,
                    y: st.y,
                    heading_deg: st.heading_deg,
                    speed_mps: st.speed_mps,
                    depth: st.depth,
                };
                let mut p = pose(&self.state);
                let _ = p.apply_spec(s);
                let mut g = pose(&self.gt);
                let _ = g.apply_spec(s);
                for (st, p) in [(&mut self.state, p), (&mut self.gt, g)] {
                    st.x = p.x;
                    st.y = p.y;
                    st.heading_deg = p.heading_deg;
                    st.speed_mps = p.speed_mps;
                    st.depth = p.depth;
                }
                return Some(Posting::double(
                    &self.vars.reset_count,
                    f64::from(self.reset_count),
                ));
            }
            "USM_TURN_RATE" => self.cfg.turn_rate_deg_s = d.clamp(0.0, 100.0),
            "USM_TURN_RADIUS" if d >= 0.0 => self.cfg.turn_radius = d,
            "USM_ENABLED" => {
                if let Some(e) = crate::config::parse_bool(s) {
                    self.enabled = e;
                }
            }
            "OBSTACLE_HIT" => {
                if let Some(h) = crate::config::parse_bool(s) {
                    self.obstacle_hit = h;
                }
            }
            "USM_RESET_NAV" => self.state = self.gt,
            "NAV_X" if !self.enabled => self.inform(Some(d), None, None),
            "NAV_Y" if !self.enabled => self.inform(None, Some(d), None),
            "NAV_HEADING" if !self.enabled => self.inform(None, None, Some(d)),
            "BUOYANCY_CONTROL" if s.eq_ignore_ascii_case("true") => {
                self.inputs.buoyancy_rate_mps = 0.0;
                self.buoyancy_request = Some(time);
                self.last_report = time;
                return Some(Posting::text(
                    "BUOYANCY_REPORT",
                    "status=1,error=0,progressing,buoyancy=0.0",
                ));
            }
            "TRIM_CONTROL" if s.eq_ignore_ascii_case("true") => {
                self.trim_request = Some(time);
                self.last_report = time;
                return Some(Posting::text(
                    "TRIM_REPORT",
                    "status=1,error=0,progressing,trim_pitch=0.0,trim_roll=0.0",
                ));
            }
            _ => {}
        }
        None
    }

    /// MOOS `informX/Y/Heading`: both records take the value and the rudder is centred.
    fn inform(&mut self, x: Option<f64>, y: Option<f64>, heading_deg: Option<f64>) {
        for st in [&mut self.state, &mut self.gt] {
            if let Some(x) = x {
                st.x = x;
            }
            if let Some(y) = y {
                st.y = y;
            }
            if let Some(h) = heading_deg {
                st.heading_deg = h;
            }
        }
        self.inputs.rudder_deg = 0.0;
    }

    fn nav_due(&self) -> bool {
        self.iteration
            .is_multiple_of(u64::from(self.cfg.nav_every()))
    }

    /// One app iteration at MOOS time `time`: advance the model and append this iteration's
    /// postings to `out`, in the C++ order: the embedded PID's, the navigation (and ground
    /// truth), trim/buoyancy reports, the drift summary, the wind arrow, the wormholes.
    pub fn iterate(&mut self, time: f64, out: &mut Vec<Posting>) {
        self.iteration += 1;
        if self.obstacle_hit {
            // Stopped where it hit: the record is posted (twice, as the C++ does) with zero
            // speed and the model's clock is not advanced.
            if self.nav_due() {
                let st = SimState {
                    speed_mps: 0.0,
                    ..self.state
                };
                let nav = nav_outputs(&self.cfg, &st, self.grid.as_ref());
                self.post_nav_as(&self.vars, &nav, out);
                self.post_nav_as(&self.vars, &nav, out);
            }
            return;
        }
        if !self.enabled {
            self.last_time = time;
            return;
        }
        // The embedded PID: fed ownship from the model, its outputs set the actuators
        // directly (whether or not it has control, as the C++ does); `post_des_thrust` /
        // `post_des_rudder` publish them.
        if let Some(mut pid) = self.pid.take() {
            let st = self.state;
            pid.on_mail("NAV_HEADING", ValueRef::Double(st.heading_deg), time);
            pid.on_mail("NAV_SPEED", ValueRef::Double(st.speed_mps), time);
            if pid.config().depth_control {
                pid.on_mail("NAV_DEPTH", ValueRef::Double(st.depth), time);
                pid.on_mail("NAV_PITCH", ValueRef::Double(st.pitch_rad), time);
            }
            let o = pid.iterate_embedded(time, out);
            self.set_rudder(o.rudder, time);
            if !self.cfg.thrust_mode_differential {
                self.inputs.thrust = o.thrust;
            }
            self.inputs.elevator_deg = o.elevator;
            if let Some(v) = &self.vars.post_thrust {
                out.push(Posting::double(v, o.thrust));
            }
            if let Some(v) = &self.vars.post_rudder {
                out.push(Posting::double(v, o.rudder));
            }
            self.pid = Some(pid);
        }
        if self.paused {
            // Paused time is excluded from the model's clock; the record is still posted.
            self.last_time = time;
        } else {
            let dt = time - self.last_time;
            self.last_time = time;
            if self.gt_vars.is_some() {
                // The navigation state does not feel the drift; the ground truth does.
                let still = SimInputs {
                    drift_x_mps: 0.0,
                    drift_y_mps: 0.0,
                    ..self.inputs
                };
                self.state = step(&self.cfg, &self.state, &still, dt, self.grid.as_ref()).0;
                self.gt = step(&self.cfg, &self.gt, &self.inputs, dt, self.grid.as_ref()).0;
            } else {
                self.state = step(&self.cfg, &self.state, &self.inputs, dt, self.grid.as_ref()).0;
            }
        }
        self.buoyancy_and_trim(time, out);
        if self.nav_due() {
            let nav = nav_outputs(&self.cfg, &self.state, self.grid.as_ref());
            self.post_nav_as(&self.vars, &nav, out);
            if let Some(gv) = &self.gt_vars {
                let gnav = nav_outputs(&self.cfg, &self.gt, self.grid.as_ref());
                self.post_nav_as(gv, &gnav, out);
            }
        }
        if self.drift_fresh {
            let (dx, dy) = (self.inputs.drift_x_mps, self.inputs.drift_y_mps);
            let summary = format!(
                "ang={}, mag={}, xmag={}, ymag={}",
                moos_types::fmt::compact_string(rel_ang(0.0, 0.0, dx, dy), 2),
                moos_types::fmt::compact_string(dx.hypot(dy), 2),
                moos_types::fmt::compact_string(dx, 3),
                moos_types::fmt::compact_string(dy, 3)
            );
            out.push(Posting::text(&self.vars.drift_summary, summary));
            self.drift_fresh = false;
        }
        if let Some(w) = self.inputs.wind
            && self.cfg.polar.is_set()
            && self.iteration.is_multiple_of(50)
        {
            out.push(Posting::text("VIEW_ARROW", w.arrow_spec()));
        }
        if !self.cfg.wormholes.is_empty() {
            if let Some(p) = self.cfg.wormholes.apply(time, self.state.x, self.state.y) {
                self.inform(Some(p.x), Some(p.y), None);
            }
            out.push(Posting::double(
                &self.transp_var,
                self.cfg.wormholes.transparency(),
            ));
            if self.iteration.is_multiple_of(10) {
                let view: ByteString = "VIEW_POLYGON".into();
                for hole in self.cfg.wormholes.holes() {
                    for poly in hole.polygons() {
                        out.push(Posting::text(&view, poly.to_spec()));
                    }
                }
            }
        }
    }

    /// The BUOYANCY_CONTROL / TRIM_CONTROL handshakes (MOOS `handleBuoyancyAndTrim`), which
    /// run only with depth control.
    fn buoyancy_and_trim(&mut self, now: f64, out: &mut Vec<Posting>) {
        if !self.cfg.depth_control {
            return;
        }
        if let Some(t0) = self.buoyancy_request {
            if now - t0 >= BUOYANCY_DELAY_S {
                out.push(Posting::text(
                    "BUOYANCY_REPORT",
                    "status=2,error=0,completed,buoyancy=0.0",
                ));
                self.buoyancy_request = None;
            } else if now - self.last_report >= REPORT_INTERVAL_S {
                out.push(Posting::text(
                    "BUOYANCY_REPORT",
                    "status=1,error=0,progressing,buoyancy=0.0",
                ));
                self.last_report = now;
            }
        }
        if let Some(t0) = self.trim_request {
            let pitch_deg = self.state.pitch_rad.to_degrees();
            let pitch_text = format!("{pitch_deg:.5}");
            let elapsed = now - t0;
            if (pitch_deg.abs() <= self.cfg.trim_tolerance_deg && elapsed >= BUOYANCY_DELAY_S)
                || elapsed >= self.cfg.max_trim_delay_s
            {
                out.push(Posting::text(
                    "TRIM_REPORT",
                    format!("status=2,error=0,completed,trim_pitch={pitch_text},trim_roll=0.0"),
                ));
                self.trim_request = None;
            } else if now - self.last_report >= REPORT_INTERVAL_S {
                out.push(Posting::text(
                    "TRIM_REPORT",
                    format!("status=1,error=0,progressing,trim_pitch={pitch_text},trim_roll=0.0"),
                ));
                self.last_report = now;
            }
        }
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
            let mut s = format!(
                "x={},y={}",
                moos_types::fmt::compact_string(nav.x, 3),
                moos_types::fmt::compact_string(nav.y, 3)
            );
            if let (Some(lat), Some(lon)) = (nav.lat, nav.lon)
                && lat != 0.0
                && lon != 0.0
            {
                s.push_str(&format!(
                    ",lat={},lon={}",
                    moos_types::fmt::compact_string(lat, 7),
                    moos_types::fmt::compact_string(lon, 7)
                ));
            }
            out.push(Posting::text(&v.navpos_summary, s));
        }
        out.push(Posting::double(&v.heading, nav.heading_deg));
        out.push(Posting::double(&v.speed, nav.speed_mps));
        out.push(Posting::double(&v.depth, nav.depth));
        if self.cfg.depth_control {
            out.push(Posting::text(&v.sim_mode, "TRUE"));
            out.push(Posting::double(&v.z, nav.z));
            out.push(Posting::double(&v.pitch, nav.pitch_rad));
            out.push(Posting::double(&v.yaw, nav.yaw_rad));
            out.push(Posting::double(&v.true_x, nav.x));
            out.push(Posting::double(&v.true_y, nav.y));
        }
        out.push(Posting::double(&v.hog, nav.heading_og_deg));
        out.push(Posting::double(&v.sog, nav.speed_og_mps));
        if let Some(a) = nav.altitude {
            out.push(Posting::double(&v.altitude, a));
        }
    }
}

#[cfg(test)]
mod appcast_tests {
    use super::*;

    #[test]
    fn appcast_body_lists_each_wormhole_as_its_config_summary() {
        let cfg = SimConfig::from_params([
            ("start_pos", "x=0, y=-20, heading=180, speed=0"),
            (
                "wormhole",
                "tag=a,madrid_poly={0,0:10,0:10,10:0,10},weber_poly={100,0:110,0:110,10:100,10},\
                 connection=from_weber,delay=2.5",
            ),
        ])
        .unwrap();
        let sim = Simulator::new(cfg, None, 0.0);
        let mut body = String::new();
        sim.appcast_body(0.0, &mut body);
        let tail: Vec<&str> = body
            .split('\n')
            .skip_while(|l| *l != "WormHole Information:")
            .collect();
        assert_eq!(
            tail[..4],
            [
                "WormHole Information:",
                "---------------------",
                "Total WormHoles: 1",
                "tag=a, connection=from_weber, delay=2.5, id_change=true",
            ]
        );
        assert!(
            tail[4].starts_with("madrid_poly: pts={0,0:10,0:10,10:0,10}"),
            "{}",
            tail[4]
        );
        assert!(tail[4].contains("label=a_madrid"), "{}", tail[4]);
        assert!(
            tail[5].starts_with("weber_poly:  pts={100,0:110,0:110,10:100,10}"),
            "{}",
            tail[5]
        );
        assert_eq!(tail[6], "");
    }

    #[test]
    fn appcast_body_as_usim_marine_builds_it() {
        let cfg = SimConfig::from_params([
            ("start_pos", "x=0, y=-20, heading=180, speed=0"),
            ("prefix", "NAV"),
        ])
        .unwrap();
        let mut sim = Simulator::new(cfg, None, 0.0);
        let mut out = Vec::new();
        sim.on_mail("DRIFT_X", ValueRef::Double(0.5), 0.0);
        // No thrust: only the drift (0.5 m/s east, no source named) moves the vehicle.
        for i in 1..=4 {
            sim.iterate(f64::from(i) * 0.25, &mut out);
        }
        let mut body = String::new();
        sim.appcast_body(1.0, &mut body);
        let lines: Vec<&str> = body.split('\n').collect();
        // The drifted position is the simulator's; the (X,Y) row is checked against it.
        let nav = *sim.state();
        let xy = format!(
            "{},{}",
            moos_types::fmt::compact_string(nav.x, 2),
            moos_types::fmt::compact_string(nav.y, 2)
        );
        assert_eq!(
            lines[..9],
            [
                "Enabled:  true",
                "TurnRate: 70",
                "TurnRadius: 0",
                "Datum: ?,?",
                "Sailing:",
                "  WindModel: spd=0, dir=0",
                "  PolarPlot: ",
                "  Enabled:   false",
                "",
            ]
        );
        assert_eq!(lines[9], "");
        assert_eq!(
            lines[10],
            "  Start Pose    Current Pose (NAV)   Current Pose (GT)"
        );
        assert_eq!(
            lines[11],
            "------- -----   ------- ----------   ------- ---------"
        );
        assert_eq!(lines[12], "Headng: 180     Headng: 180           (same) -");
        assert_eq!(lines[13], " Speed: 0        Speed: 0                    -");
        assert_eq!(lines[14], " Depth: 0        Depth: 0                    -");
        assert_eq!(lines[15], "   Alt: 0          Alt: 0                    -");
        assert_eq!(&lines[16][..18], " (X,Y): 0,-20    (");
        assert!(lines[16].contains(&format!("(X,Y): {xy}")), "{}", lines[16]);
        assert_eq!(lines[17], "   Lat: 0          Lat: 0                    -");
        assert_eq!(lines[18], "   Lon: 0          Lon: 0                    -");
        let rest = [
            "",
            "Present Buoyancy rate: 0.025",
            "        Starting rate: 0.025",
            "",
            "Ext Drift  X    Y   |  Mag  Ang  |  Rot.  |  Source(s)",
            "---------  ---  --  |  ---  ---  |  ----  |  -----------",
            " Starting  0    0   |  0    0    |  0     |  init_config",
            "  Present  0.5  0   |  0.5  90   |  0     |  n/a",
            "",
            "Velocity Information: ",
            "--------------------- ",
            "     DESIRED_THRUST=0 ==> SPEED=0",
            "     Using Thrust_Factor: true (20)",
            "           Using Sailing: false",
            "    PID Coupled: false",
            "     Positive Thrust Map: n/a",
            "     Negative Thrust Map: n/a",
            "        Max Accereration: 0",
            "        Max Decereration: 0.5",
            "",
            "             Thrust Mode: normal",
            "     Thrust Mode Reverse: false",
            "        DESIRED_THRUST_L: n/a",
            "        DESIRED_THRUST_R: n/a",
            "",
            "Depth Information: ",
            "------------------ ",
            "           Max Depth Rate: 0.5",
            "     Max Depth Rate Speed: 2",
            "              Water Depth: 0",
            "",
        ];
        assert_eq!(lines[19..], rest);
    }
}
