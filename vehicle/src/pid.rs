//! Marine PID controller, equivalent to MOOS-IvP's `pMarinePIDV22`.
//!
//! Three loops turn the helm's `DESIRED_HEADING` / `DESIRED_SPEED` / `DESIRED_DEPTH` into
//! `DESIRED_RUDDER` / `DESIRED_THRUST` / `DESIRED_ELEVATOR`:
//!
//! * **yaw**: `e = angle180(heading - angle180(desired))`, `rudder = -PID(e)` (+ the optional
//!   `sim_instability` bias), clamped to `±maxrudder`;
//! * **speed**: `thrust = previous_thrust + PID(desired - speed)`, or `desired * speed_factor`
//!   when `speed_factor != 0`, clamped to `±maxthrust`;
//! * **depth**: `pitch_des = PID_z(depth - desired)` clamped to `±maxpitch` (degrees in the
//!   config, radians inside), then `elevator = deg(PID_pitch(pitch - pitch_des))` clamped to
//!   `±maxelevator`.
//!
//! Each loop is a [`ScalarPid`]: `out = kp*e + kd*mean(last 9 de/dt) + I`, `I += ki*e*dt`
//! clamped to the integral limit (and held at 0 when `ki <= 0`), output clamped.
//!
//! pMarinePIDV22 at MOOS-IvP a2a9b716 ([`step`]): control requires every input to have been
//! received and, unless `simulation = true`, to be fresher than `tardy_helm_threshold` /
//! `tardy_nav_threshold` (else `PID_STALE` is posted and the outputs are zero); thrust below
//! 0.01 is 0, and rudder and elevator are computed only with a positive thrust; the loops run
//! during a manual override (`MOOS_MANUAL_OVERRIDE`, initially true), whose outputs are the
//! all-stop, posted once. [`PidConfig::legacy`] selects the older pMarinePID rules.
//!
//! As the C++ (its quirks kept, so that a swap-in behaves the same): `PID_THRUST_CAP` (a
//! string mail) is read and clipped but not applied to the posted thrust; with
//! `simulation = true` the controller never takes control; inputs are stamped with the
//! engine's clock (the last iteration's time, 0 = never received before the first
//! iteration), so ages in `PID_STALE` count from there. Mail skew (`ok_skew`) is not checked:
//! mail carries no separate source time here.
//!
//! # Conformance with pMarinePIDV22 (MOOS-IvP a2a9b716)
//!
//! A bad or missing value is a config warning ([`PidConfig::from_params_lenient`]); the app
//! runs on (gains default to 0), as the C++ does.
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | yaw_pid_kp, yaw_pid_kd, yaw_pid_ki | | number | 0 (warning when missing) | number | no | done |
//! | yaw_pid_integral_limit | yaw_pid_ki_limit | number | 0 (warning when missing) | number | no | done |
//! | maxrudder | | number | 100 (warning when missing) | number | no | done |
//! | speed_pid_kp, _kd, _ki, _integral_limit | | number | 0 (warning when missing) | number | no | done |
//! | maxthrust | | number | 100 (warning when missing) | number | no | done |
//! | speed_factor | | number | 0 | number >= 0 (a negative one is not taken) | SPEED_FACTOR (any number) | done |
//! | depth_control | | bool | true | MOOS boolean | no | done |
//! | z_to_pitch_pid_kp, _kd, _ki, _integral_limit | | number | 0 | number | no | done |
//! | maxpitch | | degrees | 15 | number | no | done |
//! | pitch_pid_kp, _kd, _ki, _integral_limit | | number | 0 | number | no | done |
//! | maxelevator | | degrees | 13 | number | no | done |
//! | simulation | | bool | false | MOOS boolean (no staleness check; never in control) | no | done |
//! | sim_instability | | 0..100 | 0 | clipped | no | done |
//! | tardy_helm_threshold, tardy_nav_threshold | | s | 2 | number, negative to 0 | no | done |
//! | heading_debug, speed_debug, depth_debug | | bool | false | `true` enables | no | done |
//! | ignore_nav_yaw | | bool | false | MOOS boolean | no | done |
//! | pid_verbose | verbose | bool | true | MOOS boolean | PID_VERBOSE | done |
//! | enable_thrust_cap | | bool | false | MOOS boolean; registers PID_THRUST_CAP | PID_THRUST_CAP (string mail, clipped 20..100, not applied to the posting as in the C++) | done |
//! | output_suffix | | word | none | no white space; upper-cased | no | done |
//! | active_start | | | | deprecated, accepted | no | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | DESIRED_RUDDER`<sfx>`, DESIRED_THRUST`<sfx>`, DESIRED_ELEVATOR`<sfx>` (with depth control) | every iteration in control; zeros once on losing control | numbers | done |
//! | PID_HAS_CONTROL | override changes | `true` / `false` | done |
//! | PID_STALE | each stale input, each iteration | `Stale DesHdg:<s>` (DesSpd, NavHdg, NavSpd, DesDepth, NavDep, NavPitch) | done |
//! | PID_SPD_DEBUG, PID_HDG_DEBUG, PID_DEP_DEBUG | with the `*_debug` switch, when the loop ran | `PID_SPEED:  (Want):.. (Curr):.. (Diff):.. (Fctr\|Delt):.. THRUST:..` etc. | done |
//! | PID_MAX_SAT_HDG_DEBUG, _SPD_, _DEP_ | with the debug switch, on saturation of that loop, before its report | ScalarPID's debug string, always empty at a2a9b716: `""`, `""`, `Z:` / `P:` | done |
//! | APPCAST, APP_LOG, PMARINEPIDV22_ITER_GAP/_ITER_LEN (AppCastingMOOSApp) | on request, a new config warning, the first iteration; load casts | the AppCast string; the body is `buildReport`'s ([`MarinePid::appcast_body`]; the frequency is counted in MOOS time) | done (`runtime::appcasting`, `runtime/src/vehicle.rs` tests) |
//! | DESIRED_* on zero/negative desired speed or negative SPEED_FACTOR | in control | thrust below 0.01 is 0, then rudder and elevator 0 | done |
//!
//! Subscriptions: NAV_HEADING, NAV_SPEED, NAV_DEPTH, NAV_PITCH, DESIRED_HEADING, DESIRED_SPEED,
//! DESIRED_DEPTH, PID_VERBOSE, SPEED_FACTOR, MOOS_MANUAL_OVERIDE, MOOS_MANUAL_OVERRIDE,
//! PID_THRUST_CAP (with the cap), NAV_YAW (unless ignored). done.

use moos_types::ByteString;

use crate::angle::{angle180, angle360};
use crate::config::{ConfigError, Param, apply_params, strict};
use crate::moos::{Posting, ValueRef};

const APP: &str = "pMarinePIDV22";
const DIFF_HISTORY: usize = 9;

/// One PID loop with MOOS-IvP `ScalarPID` semantics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScalarPid {
    /// Proportional gain.
    pub kp: f64,
    /// Derivative gain (on the mean of the last 9 error derivatives).
    pub kd: f64,
    /// Integral gain.
    pub ki: f64,
    /// Bound on the integral term (already multiplied by `ki`).
    pub integral_limit: f64,
    /// Bound on the output.
    pub output_limit: f64,
    e_old: f64,
    old_time: f64,
    dt: f64,
    iterations: u64,
    diffs: [f64; DIFF_HISTORY],
    n_diffs: usize,
    next_diff: usize,
    e_sum: f64,
    out: f64,
    max_sat: bool,
}

impl ScalarPid {
    /// A fresh loop with these gains and limits.
    pub fn new(kp: f64, kd: f64, ki: f64, integral_limit: f64, output_limit: f64) -> Self {
        ScalarPid {
            kp,
            kd,
            ki,
            integral_limit,
            output_limit,
            e_old: 0.0,
            old_time: 0.0,
            dt: 0.0,
            iterations: 0,
            diffs: [0.0; DIFF_HISTORY],
            n_diffs: 0,
            next_diff: 0,
            e_sum: 0.0,
            out: 0.0,
            max_sat: false,
        }
    }

    /// The accumulated integral term.
    pub fn integral(&self) -> f64 {
        self.e_sum
    }

    /// True when the last output hit the output limit.
    pub fn saturated(&self) -> bool {
        self.max_sat
    }

    /// Runs the loop on error `e` at time `time` (seconds) and returns the output.
    /// A time going backwards gives 0; a repeated time repeats the last output.
    pub fn run(&mut self, e: f64, time: f64) -> f64 {
        self.max_sat = false;
        let mut diff = 0.0;
        if self.iterations != 0 {
            self.dt = time - self.old_time;
            if self.dt < 0.0 {
                self.iterations += 1;
                return 0.0;
            }
            if self.dt == 0.0 {
                self.iterations += 1;
                return self.out;
            }
            self.diffs[self.next_diff] = (e - self.e_old) / self.dt;
            self.next_diff = (self.next_diff + 1) % DIFF_HISTORY;
            self.n_diffs = (self.n_diffs + 1).min(DIFF_HISTORY);
            diff = self.diffs[..self.n_diffs].iter().sum::<f64>() / self.n_diffs as f64;
        }
        self.iterations += 1;
        if self.ki > 0.0 {
            self.e_sum += self.ki * e * self.dt;
            let lim = self.integral_limit.abs();
            if self.e_sum.abs() >= lim {
                self.e_sum = lim.copysign(self.e_sum);
            }
        } else {
            self.e_sum = 0.0;
        }
        let mut out = self.kp * e + self.kd * diff + self.e_sum;
        let olim = self.output_limit.abs();
        if out.abs() >= olim {
            out = olim.copysign(out);
            self.max_sat = true;
        }
        self.e_old = e;
        self.old_time = time;
        self.out = out;
        out
    }
}

/// Gains of one loop as configured.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Gains {
    /// `*_PID_KP`.
    pub kp: f64,
    /// `*_PID_KD`.
    pub kd: f64,
    /// `*_PID_KI`.
    pub ki: f64,
    /// `*_PID_INTEGRAL_LIMIT`.
    pub integral_limit: f64,
}

/// `pMarinePIDV22` configuration. `Default` gives the engine defaults with all gains 0
/// (the real app requires the gains; see [`PidConfig::from_params`]).
#[derive(Debug, Clone, PartialEq)]
pub struct PidConfig {
    /// Heading loop (`YAW_PID_*`).
    pub yaw: Gains,
    /// `MAXRUDDER` (100).
    pub max_rudder: f64,
    /// Speed loop (`SPEED_PID_*`).
    pub speed: Gains,
    /// `MAXTHRUST` (100).
    pub max_thrust: f64,
    /// `SPEED_FACTOR` (0 = use the speed PID; else thrust = desired speed * factor).
    pub speed_factor: f64,
    /// `DEPTH_CONTROL` (true).
    pub depth_control: bool,
    /// Depth-to-pitch loop (`Z_TO_PITCH_PID_*`).
    pub z_to_pitch: Gains,
    /// `MAXPITCH`, degrees (15).
    pub max_pitch_deg: f64,
    /// Pitch-to-elevator loop (`PITCH_PID_*`).
    pub pitch: Gains,
    /// `MAXELEVATOR`, degrees (13).
    pub max_elevator: f64,
    /// `TARDY_HELM_THRESHOLD`, s (2).
    pub tardy_helm_threshold: f64,
    /// `TARDY_NAV_THRESHOLD`, s (2).
    pub tardy_nav_threshold: f64,
    /// `SIM_INSTABILITY`: amplitude of a saw-tooth rudder bias, 0..100 (0).
    pub sim_instability: f64,
    /// `SIMULATION`: skip the staleness check.
    pub simulation: bool,
    /// `IGNORE_NAV_YAW`: take heading from NAV_HEADING only.
    pub ignore_nav_yaw: bool,
    /// `OUTPUT_SUFFIX`, appended to the DESIRED_* names (upper-cased).
    pub output_suffix: String,
    /// `ENABLE_THRUST_CAP`: honour `PID_THRUST_CAP`.
    pub enable_thrust_cap: bool,
    /// `HEADING_DEBUG`: post `PID_HDG_DEBUG`.
    pub heading_debug: bool,
    /// `SPEED_DEBUG`: post `PID_SPD_DEBUG`.
    pub speed_debug: bool,
    /// `DEPTH_DEBUG`: post `PID_DEP_DEBUG`.
    pub depth_debug: bool,
    /// `VERBOSE` / `PID_VERBOSE` (console only in the C++ app; kept for completeness).
    pub verbose: bool,
    /// Run as the older `pMarinePID` (thrust floored at 0, rudder always computed, no
    /// control while overridden) rather than `pMarinePIDV22`. Set by the app's program name.
    pub legacy: bool,
}

impl Default for PidConfig {
    fn default() -> Self {
        PidConfig {
            yaw: Gains::default(),
            max_rudder: 100.0,
            speed: Gains::default(),
            max_thrust: 100.0,
            speed_factor: 0.0,
            depth_control: true,
            z_to_pitch: Gains::default(),
            max_pitch_deg: 15.0,
            pitch: Gains::default(),
            max_elevator: 13.0,
            tardy_helm_threshold: 2.0,
            tardy_nav_threshold: 2.0,
            sim_instability: 0.0,
            simulation: false,
            ignore_nav_yaw: false,
            output_suffix: String::new(),
            enable_thrust_cap: false,
            heading_debug: false,
            speed_debug: false,
            depth_debug: false,
            verbose: true,
            legacy: false,
        }
    }
}

/// Every key the PID engine takes from a block (MOOS-IvP `PIDEngine::setConfigParams`): the
/// ones uSimMarineV22 hands to its embedded PID.
pub const ENGINE_KEYS: &[&str] = &[
    "speed_factor",
    "simulation",
    "sim_instability",
    "tardy_helm_threshold",
    "tardy_nav_threshold",
    "yaw_pid_kp",
    "yaw_pid_kd",
    "yaw_pid_ki",
    "yaw_pid_integral_limit",
    "yaw_pid_ki_limit",
    "maxrudder",
    "heading_debug",
    "speed_pid_kp",
    "speed_pid_kd",
    "speed_pid_ki",
    "speed_pid_integral_limit",
    "maxthrust",
    "speed_debug",
    "depth_control",
    "z_to_pitch_pid_kp",
    "z_to_pitch_pid_kd",
    "z_to_pitch_pid_ki",
    "z_to_pitch_pid_integral_limit",
    "maxpitch",
    "depth_debug",
    "pitch_pid_kp",
    "pitch_pid_kd",
    "pitch_pid_ki",
    "pitch_pid_integral_limit",
    "maxelevator",
];

/// The gains every PID block should set (a missing one is a config warning; its loop runs
/// with 0).
pub const REQUIRED_ALWAYS: &[&str] = &[
    "yaw_pid_kp",
    "yaw_pid_kd",
    "yaw_pid_ki",
    "yaw_pid_integral_limit",
    "maxrudder",
    "speed_pid_kp",
    "speed_pid_kd",
    "speed_pid_ki",
    "speed_pid_integral_limit",
    "maxthrust",
];
/// The gains a block should set besides [`REQUIRED_ALWAYS`] when `depth_control` is on.
pub const REQUIRED_DEPTH: &[&str] = &[
    "z_to_pitch_pid_kp",
    "z_to_pitch_pid_kd",
    "z_to_pitch_pid_ki",
    "z_to_pitch_pid_integral_limit",
    "maxpitch",
    "pitch_pid_kp",
    "pitch_pid_kd",
    "pitch_pid_ki",
    "pitch_pid_integral_limit",
    "maxelevator",
];

impl PidConfig {
    /// Strict construction from ProcessConfig pairs. As in the C++ app, the yaw and speed gains,
    /// integral limits, `MAXRUDDER` and `MAXTHRUST` are required, and with depth control also
    /// the z-to-pitch and pitch gains, `MAXPITCH` and `MAXELEVATOR`
    /// ([`ConfigError::Missing`]).
    pub fn from_params<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<Self, ConfigError> {
        strict(Self::from_params_lenient(params))
    }

    /// As [`PidConfig::from_params`], with unknown keys returned as non-fatal errors.
    pub fn from_params_lenient<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<(Self, Vec<ConfigError>), ConfigError> {
        let mut cfg = PidConfig::default();
        let mut seen: Vec<&'static str> = Vec::new();
        let unknown = apply_params(APP, &mut cfg, params, |c, key, p| {
            let known = c.apply_one(key, p)?;
            if let Some(k) = REQUIRED_ALWAYS
                .iter()
                .chain(REQUIRED_DEPTH)
                .find(|k| **k == key)
            {
                seen.push(k);
            }
            if key == "yaw_pid_ki_limit" {
                seen.push("yaw_pid_integral_limit");
            }
            Ok(known)
        })?;
        let required = REQUIRED_ALWAYS.iter().chain(if cfg.depth_control {
            REQUIRED_DEPTH
        } else {
            &[]
        });
        // As the C++ (`handleYawSettings` ...): a missing gain is a config warning and the
        // loop runs with 0.
        let mut unknown = unknown;
        for key in required {
            if !seen.contains(key) {
                unknown.push(ConfigError::Missing { app: APP, key });
            }
        }
        Ok((cfg, unknown))
    }

    fn apply_one(&mut self, key: &str, p: Param<'_>) -> Result<bool, ConfigError> {
        match key {
            "yaw_pid_kp" => self.yaw.kp = p.f64()?,
            "yaw_pid_kd" => self.yaw.kd = p.f64()?,
            "yaw_pid_ki" => self.yaw.ki = p.f64()?,
            "yaw_pid_integral_limit" | "yaw_pid_ki_limit" => self.yaw.integral_limit = p.f64()?,
            "maxrudder" => self.max_rudder = p.f64()?,
            "speed_pid_kp" => self.speed.kp = p.f64()?,
            "speed_pid_kd" => self.speed.kd = p.f64()?,
            "speed_pid_ki" => self.speed.ki = p.f64()?,
            "speed_pid_integral_limit" => self.speed.integral_limit = p.f64()?,
            "maxthrust" => self.max_thrust = p.f64()?,
            "speed_factor" => self.speed_factor = p.non_neg()?,
            "depth_control" => self.depth_control = p.bool()?,
            "z_to_pitch_pid_kp" => self.z_to_pitch.kp = p.f64()?,
            "z_to_pitch_pid_kd" => self.z_to_pitch.kd = p.f64()?,
            "z_to_pitch_pid_ki" => self.z_to_pitch.ki = p.f64()?,
            "z_to_pitch_pid_integral_limit" => self.z_to_pitch.integral_limit = p.f64()?,
            "maxpitch" => self.max_pitch_deg = p.f64()?,
            "pitch_pid_kp" => self.pitch.kp = p.f64()?,
            "pitch_pid_kd" => self.pitch.kd = p.f64()?,
            "pitch_pid_ki" => self.pitch.ki = p.f64()?,
            "pitch_pid_integral_limit" => self.pitch.integral_limit = p.f64()?,
            "maxelevator" => self.max_elevator = p.f64()?,
            "tardy_helm_threshold" => self.tardy_helm_threshold = p.f64()?.max(0.0),
            "tardy_nav_threshold" => self.tardy_nav_threshold = p.f64()?.max(0.0),
            "sim_instability" => self.sim_instability = p.f64()?.clamp(0.0, 100.0),
            "simulation" => self.simulation = p.bool()?,
            "ignore_nav_yaw" => self.ignore_nav_yaw = p.bool()?,
            "output_suffix" => self.output_suffix = p.word()?.to_ascii_uppercase(),
            "enable_thrust_cap" => self.enable_thrust_cap = p.bool()?,
            "heading_debug" => self.heading_debug = p.bool()?,
            "speed_debug" => self.speed_debug = p.bool()?,
            "depth_debug" => self.depth_debug = p.bool()?,
            "verbose" | "pid_verbose" => self.verbose = p.bool()?,
            // Accepted for compatibility (deprecated / older saturation-debug switches).
            "active_start" => {}
            "max_sat_hdg_debug" | "max_sat_spd_debug" => {
                p.bool()?;
            }
            _ => return Ok(false),
        }
        Ok(true)
    }
}

/// A value with the time it was received.
pub type Stamped = Option<(f64, f64)>;

/// Latest inputs of the controller, each with its receive time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PidInputs {
    /// DESIRED_HEADING, degrees.
    pub desired_heading: Stamped,
    /// DESIRED_SPEED, m/s.
    pub desired_speed: Stamped,
    /// DESIRED_DEPTH, m.
    pub desired_depth: Stamped,
    /// NAV_HEADING (or from NAV_YAW), degrees.
    pub heading: Stamped,
    /// NAV_SPEED, m/s.
    pub speed: Stamped,
    /// NAV_DEPTH, m.
    pub depth: Stamped,
    /// NAV_PITCH, radians.
    pub pitch: Stamped,
    /// MOOS_MANUAL_OVERRIDE (true at start).
    pub manual_override: bool,
}

impl Default for PidInputs {
    fn default() -> Self {
        PidInputs {
            desired_heading: None,
            desired_speed: None,
            desired_depth: None,
            heading: None,
            speed: None,
            depth: None,
            pitch: None,
            manual_override: true,
        }
    }
}

/// The inputs whose age is checked, in the order `PID_STALE` reports them.
pub const STALE_LABELS: [&str; 7] = [
    "DesHdg", "DesSpd", "NavHdg", "NavSpd", "DesDepth", "NavDep", "NavPitch",
];

/// Controller memory between steps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PidState {
    /// Heading loop.
    pub heading_pid: ScalarPid,
    /// Speed loop.
    pub speed_pid: ScalarPid,
    /// Depth-to-pitch loop.
    pub z_pid: ScalarPid,
    /// Pitch-to-elevator loop.
    pub pitch_pid: ScalarPid,
    /// Thrust of the previous step (the speed loop adds to it).
    pub thrust: f64,
    /// True while inputs are missing or stale.
    pub stale: bool,
    bias_side: f64,
    bias_time: f64,
}

impl PidState {
    /// Fresh loops built from the config.
    pub fn new(cfg: &PidConfig) -> Self {
        let g = |g: &Gains, lim: f64| ScalarPid::new(g.kp, g.kd, g.ki, g.integral_limit, lim);
        PidState {
            heading_pid: g(&cfg.yaw, cfg.max_rudder),
            speed_pid: g(&cfg.speed, cfg.max_thrust),
            z_pid: g(&cfg.z_to_pitch, cfg.max_pitch_deg.to_radians()),
            pitch_pid: g(&cfg.pitch, cfg.max_elevator),
            thrust: 0.0,
            stale: true,
            bias_side: 1.0,
            bias_time: 0.0,
        }
    }
}

/// Result of one controller step.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PidOutputs {
    /// DESIRED_RUDDER.
    pub rudder: f64,
    /// DESIRED_THRUST.
    pub thrust: f64,
    /// DESIRED_ELEVATOR (0 without depth control).
    pub elevator: f64,
    /// Desired pitch of the depth loop, radians (diagnostic).
    pub desired_pitch: f64,
    /// True when not overridden, and all inputs present and fresh.
    pub has_control: bool,
    /// Age in seconds of each stale input, indexed as [`STALE_LABELS`].
    pub stale: [Option<f64>; 7],
    /// The speed loop ran this step (pMarinePIDV22 debug postings follow the loops run).
    pub ran_speed: bool,
    /// The heading loop ran this step.
    pub ran_heading: bool,
    /// The depth loops ran this step.
    pub ran_depth: bool,
    /// Speed loop output added to the previous thrust (0 with a speed factor).
    pub delta_thrust: f64,
    /// Desired heading in (−180, 180] and heading error, degrees (heading loop inputs).
    pub heading_terms: (f64, f64),
    /// Which loops hit their output limit this step: heading, speed, depth-to-pitch, pitch.
    pub saturated: Saturation,
}

/// Which of the PID loops hit their output limit in a step (ScalarPID `getMaxSat`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Saturation {
    /// The heading loop.
    pub heading: bool,
    /// The speed loop (never with a speed factor: that loop does not run).
    pub speed: bool,
    /// The depth-to-pitch loop.
    pub depth_to_pitch: bool,
    /// The pitch-to-elevator loop.
    pub pitch: bool,
}

fn age(now: f64, v: Stamped) -> Option<f64> {
    v.map(|(_, t)| now - t)
}

/// The age of each input older than its threshold (`tardy_helm_threshold` for the helm's
/// DESIRED_*, `tardy_nav_threshold` for NAV_*; depth inputs only with depth control),
/// indexed as [`STALE_LABELS`].
fn stale_ages(cfg: &PidConfig, inputs: &PidInputs, now: f64) -> [Option<f64>; 7] {
    let helm = cfg.tardy_helm_threshold;
    let nav = cfg.tardy_nav_threshold;
    let checks: [(Stamped, f64, bool); 7] = [
        (inputs.desired_heading, helm, true),
        (inputs.desired_speed, helm, true),
        (inputs.heading, nav, true),
        (inputs.speed, nav, true),
        (inputs.desired_depth, helm, cfg.depth_control),
        (inputs.depth, nav, cfg.depth_control),
        (inputs.pitch, nav, cfg.depth_control),
    ];
    checks.map(|(v, thresh, active)| age(now, v).filter(|a| active && *a > thresh))
}

/// One controller step at time `now`. Pure: the returned state replaces the given one.
///
/// As pMarinePIDV22 at MOOS-IvP a2a9b716 (`PIDEngine::setDesiredValues`): nothing is computed
/// until every input has been received; unless `simulation`, stale inputs stop the step (and
/// `stale` is remembered); thrust is `desired speed × speed_factor` or the previous thrust
/// plus the speed loop, **set to 0 below 0.01** (so a zero or negative desired speed, or a
/// negative `SPEED_FACTOR`, stops the vehicle) and clamped to `±maxthrust`; the rudder and
/// the elevator are computed only when the thrust is positive. The loops run even under a
/// manual override; control is `!override && !stale`. As in the C++, `stale` starts true and
/// is only updated by the staleness check, so with `simulation = true` the controller never
/// has control (its outputs stay at the all-stop).
pub fn step(
    cfg: &PidConfig,
    state: &PidState,
    inputs: &PidInputs,
    now: f64,
) -> (PidState, PidOutputs) {
    if cfg.legacy {
        return step_legacy(cfg, state, inputs, now);
    }
    let mut s = *state;
    let mut out = PidOutputs::default();
    let control = |s: &PidState| !inputs.manual_override && !s.stale;
    let (Some((des_hdg, _)), Some((des_spd, _)), Some((hdg, _)), Some((spd, _))) = (
        inputs.desired_heading,
        inputs.desired_speed,
        inputs.heading,
        inputs.speed,
    ) else {
        out.has_control = control(&s);
        return (s, out);
    };
    if cfg.depth_control
        && (inputs.desired_depth.is_none() || inputs.depth.is_none() || inputs.pitch.is_none())
    {
        out.has_control = control(&s);
        return (s, out);
    }
    if !cfg.simulation {
        out.stale = stale_ages(cfg, inputs, now);
        s.stale = out.stale.iter().any(Option::is_some);
        if s.stale {
            return (s, out);
        }
    }

    // Speed.
    out.ran_speed = true;
    let mut thrust = if cfg.speed_factor != 0.0 {
        des_spd * cfg.speed_factor
    } else {
        out.delta_thrust = s.speed_pid.run(des_spd - spd, now);
        out.saturated.speed = s.speed_pid.saturated();
        s.thrust + out.delta_thrust
    };
    if thrust < 0.01 {
        thrust = 0.0;
    }
    thrust = thrust.clamp(-cfg.max_thrust.abs(), cfg.max_thrust.abs());
    s.thrust = thrust;
    out.thrust = thrust;

    if thrust > 0.0 {
        // Heading.
        out.ran_heading = true;
        let des180 = angle180(des_hdg);
        let err = angle180(hdg - des180);
        out.heading_terms = (des180, err);
        let mut rudder = -s.heading_pid.run(err, now);
        out.saturated.heading = s.heading_pid.saturated();
        if cfg.sim_instability > 0.0 {
            let duration = 10.0;
            let mut elapsed = now - s.bias_time;
            if elapsed > duration {
                elapsed = 0.0;
                s.bias_time = now;
                s.bias_side = -s.bias_side;
            }
            rudder += s.bias_side * (elapsed / duration) * cfg.sim_instability;
        }
        out.rudder = rudder.clamp(-cfg.max_rudder.abs(), cfg.max_rudder.abs());

        // Depth.
        if cfg.depth_control
            && let (Some((des_dep, _)), Some((dep, _)), Some((pitch, _))) =
                (inputs.desired_depth, inputs.depth, inputs.pitch)
        {
            out.ran_depth = true;
            let max_pitch = cfg.max_pitch_deg.to_radians();
            let pitch_des = s.z_pid.run(dep - des_dep, now).clamp(-max_pitch, max_pitch);
            out.saturated.depth_to_pitch = s.z_pid.saturated();
            out.desired_pitch = pitch_des;
            let elev = s.pitch_pid.run(pitch - pitch_des, now).to_degrees();
            out.saturated.pitch = s.pitch_pid.saturated();
            out.elevator = elev.clamp(-cfg.max_elevator.abs(), cfg.max_elevator.abs());
        }
    }
    out.has_control = control(&s);
    (s, out)
}

/// The older pMarinePID's step (see [`PidConfig::legacy`]).
fn step_legacy(
    cfg: &PidConfig,
    state: &PidState,
    inputs: &PidInputs,
    now: f64,
) -> (PidState, PidOutputs) {
    let mut s = *state;
    let mut out = PidOutputs::default();
    let (Some((des_hdg, _)), Some((des_spd, _)), Some((hdg, _)), Some((spd, _))) = (
        inputs.desired_heading,
        inputs.desired_speed,
        inputs.heading,
        inputs.speed,
    ) else {
        return (s, out);
    };
    if cfg.depth_control
        && (inputs.desired_depth.is_none() || inputs.depth.is_none() || inputs.pitch.is_none())
    {
        return (s, out);
    }
    if !cfg.simulation {
        out.stale = stale_ages(cfg, inputs, now);
        s.stale = out.stale.iter().any(Option::is_some);
        if s.stale {
            return (s, out);
        }
    } else {
        s.stale = false;
    }
    if inputs.manual_override {
        return (s, out);
    }
    out.has_control = true;

    // Speed.
    let mut thrust = if cfg.speed_factor != 0.0 {
        des_spd * cfg.speed_factor
    } else {
        s.thrust + s.speed_pid.run(des_spd - spd, now)
    };
    thrust = thrust.clamp(-cfg.max_thrust.abs(), cfg.max_thrust.abs());
    s.thrust = thrust;
    out.thrust = thrust;

    // Heading.
    let err = angle180(hdg - angle180(des_hdg));
    let mut rudder = -s.heading_pid.run(err, now);
    if cfg.sim_instability > 0.0 {
        let duration = 10.0;
        let mut elapsed = now - s.bias_time;
        if elapsed > duration {
            elapsed = 0.0;
            s.bias_time = now;
            s.bias_side = -s.bias_side;
        }
        rudder += s.bias_side * (elapsed / duration) * cfg.sim_instability;
    }
    out.rudder = rudder.clamp(-cfg.max_rudder.abs(), cfg.max_rudder.abs());

    // Depth.
    if cfg.depth_control {
        let (Some((des_dep, _)), Some((dep, _)), Some((pitch, _))) =
            (inputs.desired_depth, inputs.depth, inputs.pitch)
        else {
            return (s, out);
        };
        let max_pitch = cfg.max_pitch_deg.to_radians();
        let pitch_des = s.z_pid.run(dep - des_dep, now).clamp(-max_pitch, max_pitch);
        out.desired_pitch = pitch_des;
        let elev = s.pitch_pid.run(pitch - pitch_des, now).to_degrees();
        out.elevator = elev.clamp(-cfg.max_elevator.abs(), cfg.max_elevator.abs());
    }
    (s, out)
}

/// The `pMarinePIDV22` app: inputs by MOOS name, outputs as postings.
pub struct MarinePid {
    cfg: PidConfig,
    state: PidState,
    inputs: PidInputs,
    thrust_cap: f64,
    allstop_posted: bool,
    pending: Vec<Posting>,
    rudder_var: ByteString,
    thrust_var: ByteString,
    elevator_var: ByteString,
    has_control_var: ByteString,
    stale_var: ByteString,
    debug_vars: [ByteString; 3],
    /// PID_MAX_SAT_HDG_DEBUG, PID_MAX_SAT_SPD_DEBUG, PID_MAX_SAT_DEP_DEBUG.
    max_sat_vars: [ByteString; 3],
    last: PidOutputs,
    /// The engine's clock: the time of the last iteration (0 before the first). As in
    /// `PIDEngine`, mail is stamped with it, and a stamp of 0 means "never received".
    engine_time: f64,
    /// Iterations run (the engine's `m_iterations`, for the appcast's frequency).
    iterations: u64,
    /// When the app started (the engine's `m_start_time`); `None`: the first iteration's.
    start_time: Option<f64>,
}

impl MarinePid {
    /// A controller with this config; starts under manual override, as the C++ app.
    pub fn new(cfg: PidConfig) -> Self {
        let sfx = cfg.output_suffix.clone();
        MarinePid {
            state: PidState::new(&cfg),
            inputs: PidInputs::default(),
            thrust_cap: 100.0,
            allstop_posted: false,
            pending: Vec::new(),
            rudder_var: format!("DESIRED_RUDDER{sfx}").into(),
            thrust_var: format!("DESIRED_THRUST{sfx}").into(),
            elevator_var: format!("DESIRED_ELEVATOR{sfx}").into(),
            has_control_var: "PID_HAS_CONTROL".into(),
            stale_var: "PID_STALE".into(),
            debug_vars: [
                "PID_HDG_DEBUG".into(),
                "PID_SPD_DEBUG".into(),
                "PID_DEP_DEBUG".into(),
            ],
            max_sat_vars: [
                "PID_MAX_SAT_HDG_DEBUG".into(),
                "PID_MAX_SAT_SPD_DEBUG".into(),
                "PID_MAX_SAT_DEP_DEBUG".into(),
            ],
            last: PidOutputs::default(),
            engine_time: 0.0,
            iterations: 0,
            start_time: None,
            cfg,
        }
    }

    /// Sets the start time (MOOS `OnStartUp`'s `MOOSTime()`), from which the appcast's
    /// frequency counts. Without it the time of the first iteration stands in.
    pub fn set_start_time(&mut self, time: f64) {
        self.start_time = Some(time);
    }

    /// Counts one engine iteration at `now` (the C++ `setDesiredValues` count).
    fn count_iteration(&mut self, now: f64) {
        self.iterations += 1;
        self.start_time.get_or_insert(now);
    }

    /// Appends the pMarinePIDV22 appcast report body (`MarinePID::buildReport`) as of `now`,
    /// line by line as the C++ writes it:
    ///
    /// ```text
    /// Frequency:<iterations / (now - start), 3 decimals>
    /// Speed Factor:    <speed_factor>
    /// PID has_control: <true|false>
    ///   PID override: <true|false>
    ///   PID stale:    <true|false>
    ///
    /// PID Settings:
    /// ----------------------------
    /// Thrust Cap Enabled: <bool>
    /// Thrust Cap: <cap, 5 decimals>
    /// YAW_PID_KP             = <kp>  (and KD, KI, INTEGRAL_LIMIT; SPEED_, then with depth
    /// ...                              control PITCH_ and Z_TO_PITCH_ blocks)
    /// ```
    ///
    /// Gains are written with at most 3 decimals, the maxima with at most 5 (MOOS
    /// `doubleToStringX`); `Max pitch` is in radians, as the C++ engine holds it after
    /// reading `maxpitch` (when `maxpitch` is missing, a config warning, the C++ would write
    /// the unconverted 15 where coug writes 15° in radians). The frequency counts iterations
    /// from [`MarinePid::set_start_time`] (else from the first iteration); it does not
    /// depend on wall-clock time.
    ///
    /// Appcast notes: pMarinePIDV22 reports no run warnings and no events. Its only
    /// appcast messages are config warnings at start-up (`Improper PID Setting`, and each
    /// missing gain, `<KEY> not in Mission File`), which coug reports through
    /// [`PidConfig::from_params_lenient`].
    pub fn appcast_body(&self, now: f64, out: &mut String) {
        let elapsed = now - self.start_time.unwrap_or(now);
        let freq = if elapsed > 0.0 {
            self.iterations as f64 / elapsed
        } else {
            0.0
        };
        let b = |v: bool| if v { "true" } else { "false" };
        let cfg = &self.cfg;
        let stale = self.state.stale;
        let over = self.inputs.manual_override;
        out.push_str("Frequency:");
        moos_types::fmt::fixed(out, freq, 3);
        out.push('\n');
        out.push_str("Speed Factor:    ");
        out.push_str(&moos_types::fmt::compact_string(cfg.speed_factor, 5));
        out.push('\n');
        out.push_str("PID has_control: ");
        out.push_str(b(!over && !stale));
        out.push_str("\n  PID override: ");
        out.push_str(b(over));
        out.push_str("\n  PID stale:    ");
        out.push_str(b(stale));
        out.push_str("\n\nPID Settings: \n");
        const RULE: &str = "----------------------------\n";
        out.push_str(RULE);
        out.push_str("Thrust Cap Enabled: ");
        out.push_str(b(cfg.enable_thrust_cap));
        out.push_str("\nThrust Cap: ");
        moos_types::fmt::fixed(out, self.thrust_cap, 5);
        out.push('\n');
        let gains = |out: &mut String, prefix: &str, g: &Gains| {
            // The `=` lines up: the label is padded to the longest (`..._INTEGRAL_LIMIT`).
            let width = prefix.len() + "INTEGRAL_LIMIT".len();
            for (name, v) in [
                ("KP", g.kp),
                ("KD", g.kd),
                ("KI", g.ki),
                ("INTEGRAL_LIMIT", g.integral_limit),
            ] {
                let label = format!("{prefix}{name}");
                out.push_str(&format!("{label:<width$} = "));
                out.push_str(&moos_types::fmt::compact_string(v, 3));
                out.push('\n');
            }
        };
        let max = |out: &mut String, label: &str, v: f64| {
            out.push_str(label);
            out.push_str(&moos_types::fmt::compact_string(v, 5));
            out.push('\n');
        };
        gains(out, "YAW_PID_", &cfg.yaw);
        max(out, "Max rudder: ", cfg.max_rudder);
        out.push_str(RULE);
        gains(out, "SPEED_PID_", &cfg.speed);
        max(out, "Max thrust: ", cfg.max_thrust);
        if cfg.depth_control {
            out.push_str(RULE);
            gains(out, "PITCH_PID_", &cfg.pitch);
            max(out, "Max pitch: ", cfg.max_pitch_deg.to_radians());
            out.push_str(RULE);
            gains(out, "Z_TO_PITCH_PID_", &cfg.z_to_pitch);
            max(out, "Max elevator: ", cfg.max_elevator);
        }
    }

    /// The configuration.
    pub fn config(&self) -> &PidConfig {
        &self.cfg
    }

    /// The latest inputs.
    pub fn inputs(&self) -> &PidInputs {
        &self.inputs
    }

    /// The outputs of the last iteration.
    pub fn last_outputs(&self) -> &PidOutputs {
        &self.last
    }

    /// The variables this app subscribes to.
    pub fn subscriptions(&self) -> Vec<&'static str> {
        let mut v = vec![
            "NAV_HEADING",
            "NAV_SPEED",
            "NAV_DEPTH",
            "NAV_PITCH",
            "DESIRED_HEADING",
            "DESIRED_SPEED",
            "DESIRED_DEPTH",
            "PID_VERBOSE",
            "SPEED_FACTOR",
            "MOOS_MANUAL_OVERIDE",
            "MOOS_MANUAL_OVERRIDE",
        ];
        if self.cfg.enable_thrust_cap {
            v.push("PID_THRUST_CAP");
        }
        if !self.cfg.ignore_nav_yaw {
            v.push("NAV_YAW");
        }
        v
    }

    fn set_override(&mut self, sval: &str) {
        match sval.trim().to_ascii_lowercase().as_str() {
            "true" => {
                if !self.inputs.manual_override {
                    self.pending
                        .push(Posting::text(&self.has_control_var, "false"));
                }
                self.inputs.manual_override = true;
            }
            "false" => {
                if self.inputs.manual_override {
                    // New values of every input are needed after an override is lifted.
                    let o = PidInputs {
                        manual_override: false,
                        ..PidInputs::default()
                    };
                    self.inputs = o;
                }
                self.inputs.manual_override = false;
                self.pending
                    .push(Posting::text(&self.has_control_var, "true"));
            }
            _ => {}
        }
    }

    /// Takes one piece of mail. As `PIDEngine` does, each input is stamped with the engine's
    /// time (the time of the last iteration), not with `_time`; before the first iteration
    /// that stamp is 0, which the engine reads as "not received". The legacy pMarinePID
    /// stamps mail with the time it is handled (`time`).
    pub fn on_mail(&mut self, var: &str, value: ValueRef<'_>, time: f64) {
        let d = value.as_f64();
        let (now, legacy) = (self.engine_time, self.cfg.legacy);
        let stamp = |v: f64| {
            if legacy {
                Some((v, time))
            } else {
                (now != 0.0).then_some((v, now))
            }
        };
        match (var, d) {
            ("MOOS_MANUAL_OVERIDE" | "MOOS_MANUAL_OVERRIDE", _) => {
                if let Some(s) = value.as_str() {
                    self.set_override(s);
                }
            }
            ("PID_VERBOSE", _) => {
                if let Some(b) = value.as_str().and_then(crate::config::parse_bool) {
                    self.cfg.verbose = b;
                }
            }
            ("SPEED_FACTOR", Some(v)) => self.cfg.speed_factor = v,
            ("DESIRED_HEADING", Some(v)) => self.inputs.desired_heading = stamp(v),
            ("DESIRED_SPEED", Some(v)) => self.inputs.desired_speed = stamp(v),
            ("DESIRED_DEPTH", Some(v)) => self.inputs.desired_depth = stamp(v),
            ("NAV_YAW", Some(v)) if !self.cfg.ignore_nav_yaw => {
                self.inputs.heading = stamp(angle360(-v.to_degrees()))
            }
            ("NAV_HEADING", Some(v)) => self.inputs.heading = stamp(angle360(v)),
            ("NAV_SPEED", Some(v)) => self.inputs.speed = stamp(v),
            ("NAV_DEPTH", Some(v)) => self.inputs.depth = stamp(v),
            ("NAV_PITCH", Some(v)) => self.inputs.pitch = stamp(v),
            // A string mail only (`setDoubleClipRngOnString` on the string value).
            ("PID_THRUST_CAP", _) => {
                if let Some(v) = value.as_str().and_then(crate::config::parse_number) {
                    self.thrust_cap = v.clamp(20.0, 100.0);
                }
            }
            _ => {}
        }
    }

    /// One step of the engine at `now` as uSimMarineV22's embedded PID runs it: the
    /// outputs are returned (for the simulator to apply, whether or not the PID has control,
    /// as the C++ does) and only the engine's own postings (`PID_HAS_CONTROL`, `PID_STALE`,
    /// debug reports) are appended to `out`.
    pub fn iterate_embedded(&mut self, now: f64, out: &mut Vec<Posting>) -> PidOutputs {
        self.engine_time = now;
        self.count_iteration(now);
        let (s, o) = step(&self.cfg, &self.state, &self.inputs, now);
        self.state = s;
        self.last = o;
        self.post_engine(&o, out);
        o
    }

    fn post_engine(&mut self, o: &PidOutputs, out: &mut Vec<Posting>) {
        out.append(&mut self.pending);
        for (label, a) in STALE_LABELS.iter().zip(o.stale) {
            if let Some(a) = a {
                out.push(Posting::text(
                    &self.stale_var,
                    format!("Stale {label}:{}", moos_types::fmt::compact_string(a, 3)),
                ));
            }
        }
        if !self.cfg.legacy {
            self.post_debug_v22(o, out);
        }
    }

    /// One iteration at time `now`; appends the postings to `out`.
    pub fn iterate(&mut self, now: f64, out: &mut Vec<Posting>) {
        self.engine_time = now;
        self.count_iteration(now);
        let (s, o) = step(&self.cfg, &self.state, &self.inputs, now);
        self.state = s;
        self.last = o;
        if !o.has_control {
            if !self.allstop_posted {
                out.push(Posting::double(&self.rudder_var, 0.0));
                out.push(Posting::double(&self.thrust_var, 0.0));
                if self.cfg.depth_control {
                    out.push(Posting::double(&self.elevator_var, 0.0));
                }
                self.allstop_posted = true;
            }
        } else {
            out.push(Posting::double(&self.rudder_var, o.rudder));
            // As the C++ at a2a9b716: PID_THRUST_CAP is read and clipped to [20, 100] but the
            // posted thrust is the uncapped one (the capped value is computed and unused).
            let thrust = if self.cfg.legacy && self.cfg.enable_thrust_cap {
                o.thrust.min(self.thrust_cap)
            } else {
                o.thrust
            };
            out.push(Posting::double(&self.thrust_var, thrust));
            if self.cfg.depth_control {
                out.push(Posting::double(&self.elevator_var, o.elevator));
            }
            self.allstop_posted = false;
            if self.cfg.legacy {
                self.post_debug(&o, out);
            }
        }
        // The engine's postings, in the order the C++ engine queues them: control changes
        // (from mail), staleness, then the loops' debug reports.
        self.post_engine(&o, out);
    }

    /// The cap `PID_THRUST_CAP` last set (20..100; 100 by default).
    pub fn thrust_cap(&self) -> f64 {
        self.thrust_cap
    }

    /// pMarinePIDV22's `PID_SPD_DEBUG`, `PID_HDG_DEBUG`, `PID_DEP_DEBUG` (each when its loop
    /// ran and its `*_debug` switch is on), numbers as `doubleToString(v, 5)`.
    ///
    /// Before each report, on saturation of that loop, `PID_MAX_SAT_<HDG|SPD|DEP>_DEBUG`: the
    /// C++ posts ScalarPID's debug string, which stays empty at a2a9b716 (nothing turns the
    /// loops' own debug switch on), so the heading and speed ones are empty strings and the
    /// depth one is `Z:` (depth-to-pitch loop) and/or `P:` (pitch loop).
    fn post_debug_v22(&self, o: &PidOutputs, out: &mut Vec<Posting>) {
        let val = |v: Stamped| v.map_or(0.0, |(v, _)| v);
        let f = |v: f64| format!("{v:.5}");
        let sat = &o.saturated;
        if self.cfg.speed_debug && o.ran_speed && sat.speed {
            out.push(Posting::text(&self.max_sat_vars[1], ""));
        }
        if self.cfg.speed_debug && o.ran_speed {
            let (want, curr) = (val(self.inputs.desired_speed), val(self.inputs.speed));
            let mid = if self.cfg.speed_factor != 0.0 {
                format!(" (Fctr):{}", f(self.cfg.speed_factor))
            } else {
                format!(" (Delt):{}", f(o.delta_thrust))
            };
            let s = format!(
                "PID_SPEED:  (Want):{} (Curr):{} (Diff):{}{mid} THRUST:{}",
                f(want),
                f(curr),
                f(want - curr),
                f(o.thrust)
            );
            out.push(Posting::text(&self.debug_vars[1], s));
        }
        if self.cfg.heading_debug && o.ran_heading && sat.heading {
            out.push(Posting::text(&self.max_sat_vars[0], ""));
        }
        if self.cfg.heading_debug && o.ran_heading {
            let (des180, err) = o.heading_terms;
            let s = format!(
                "PID_COURSE:  (Want):{} (Curr):{} (Diff):{} RUDDER:{}",
                f(des180),
                f(val(self.inputs.heading)),
                f(err),
                f(o.rudder)
            );
            out.push(Posting::text(&self.debug_vars[0], s));
        }
        if self.cfg.depth_debug && o.ran_depth {
            for (hit, tag) in [(sat.depth_to_pitch, "Z:"), (sat.pitch, "P:")] {
                if hit {
                    out.push(Posting::text(&self.max_sat_vars[2], tag));
                }
            }
            let (want, curr) = (val(self.inputs.desired_depth), val(self.inputs.depth));
            let s = format!(
                "PID_DEPTH:  (Want):{} (Curr):{} (Diff):{} ELEVATOR:{}",
                f(want),
                f(curr),
                f(curr - want),
                f(o.elevator)
            );
            out.push(Posting::text(&self.debug_vars[2], s));
        }
    }

    fn post_debug(&self, o: &PidOutputs, out: &mut Vec<Posting>) {
        let val = |v: Stamped| v.map_or(0.0, |(v, _)| v);
        if self.cfg.heading_debug {
            let s = format!(
                "PID_COURSE:  (Want):{:.5} (Curr):{:.5} RUDDER:{:.5}",
                val(self.inputs.desired_heading),
                val(self.inputs.heading),
                o.rudder
            );
            out.push(Posting::text(&self.debug_vars[0], s));
        }
        if self.cfg.speed_debug {
            let s = format!(
                "PID_SPEED:  (Want):{:.5} (Curr):{:.5} THRUST:{:.5}",
                val(self.inputs.desired_speed),
                val(self.inputs.speed),
                o.thrust
            );
            out.push(Posting::text(&self.debug_vars[1], s));
        }
        if self.cfg.depth_debug && self.cfg.depth_control {
            let s = format!(
                "PID_DEPTH:  (Want):{:.5} (Curr):{:.5} ELEVATOR:{:.5}",
                val(self.inputs.desired_depth),
                val(self.inputs.depth),
                o.elevator
            );
            out.push(Posting::text(&self.debug_vars[2], s));
        }
    }
}

#[cfg(test)]
mod appcast_tests {
    use super::*;

    /// A typical M2 Kayak block (the alpha mission's pMarinePIDV22, with depth control).
    fn kayak() -> MarinePid {
        let cfg = PidConfig::from_params([
            ("speed_factor", "20"),
            ("sim_instability", "0"),
            ("yaw_pid_kp", "1.2"),
            ("yaw_pid_kd", "0.0"),
            ("yaw_pid_ki", "0.3"),
            ("yaw_pid_integral_limit", "0.07"),
            ("maxrudder", "100"),
            ("speed_pid_kp", "1.0"),
            ("speed_pid_kd", "0.0"),
            ("speed_pid_ki", "0.0"),
            ("speed_pid_integral_limit", "0.07"),
            ("maxthrust", "100"),
            ("depth_control", "true"),
            ("z_to_pitch_pid_kp", "0.12"),
            ("z_to_pitch_pid_kd", "0.1"),
            ("z_to_pitch_pid_ki", "0.004"),
            ("z_to_pitch_pid_integral_limit", "0.05"),
            ("maxpitch", "15"),
            ("pitch_pid_kp", "0.5"),
            ("pitch_pid_kd", "1.0"),
            ("pitch_pid_ki", "0"),
            ("pitch_pid_integral_limit", "0"),
            ("maxelevator", "13"),
        ])
        .unwrap();
        MarinePid::new(cfg)
    }

    #[test]
    fn appcast_body_as_marine_pid_builds_it() {
        let mut pid = kayak();
        pid.set_start_time(100.0);
        let mut out = Vec::new();
        // Four iterations at 4 Hz; the helm lifts the override after the first.
        for (i, t) in [100.25, 100.5, 100.75, 101.0].into_iter().enumerate() {
            if i == 1 {
                pid.on_mail("MOOS_MANUAL_OVERRIDE", ValueRef::String("false"), t);
            }
            pid.iterate(t, &mut out);
        }
        let mut body = String::new();
        pid.appcast_body(101.0, &mut body);
        // 4 iterations over 1 s; no input received, so stale (as at start) and not in control.
        // maxpitch 15 degrees is 0.2617994 rad: 5 decimals 0.26180, trailing zero dropped.
        let expected = [
            "Frequency:4.000",
            "Speed Factor:    20",
            "PID has_control: false",
            "  PID override: false",
            "  PID stale:    true",
            "",
            "PID Settings: ",
            "----------------------------",
            "Thrust Cap Enabled: false",
            "Thrust Cap: 100.00000",
            "YAW_PID_KP             = 1.2",
            "YAW_PID_KD             = 0",
            "YAW_PID_KI             = 0.3",
            "YAW_PID_INTEGRAL_LIMIT = 0.07",
            "Max rudder: 100",
            "----------------------------",
            "SPEED_PID_KP             = 1",
            "SPEED_PID_KD             = 0",
            "SPEED_PID_KI             = 0",
            "SPEED_PID_INTEGRAL_LIMIT = 0.07",
            "Max thrust: 100",
            "----------------------------",
            "PITCH_PID_KP             = 0.5",
            "PITCH_PID_KD             = 1",
            "PITCH_PID_KI             = 0",
            "PITCH_PID_INTEGRAL_LIMIT = 0",
            "Max pitch: 0.2618",
            "----------------------------",
            "Z_TO_PITCH_PID_KP             = 0.12",
            "Z_TO_PITCH_PID_KD             = 0.1",
            "Z_TO_PITCH_PID_KI             = 0.004",
            "Z_TO_PITCH_PID_INTEGRAL_LIMIT = 0.05",
            "Max elevator: 13",
        ];
        let lines: Vec<&str> = body.split('\n').collect();
        assert_eq!(lines.last(), Some(&""), "every line ends with a newline");
        assert_eq!(lines[..lines.len() - 1], expected);
    }

    #[test]
    fn appcast_body_in_control_without_depth() {
        let cfg = PidConfig::from_params([
            ("yaw_pid_kp", "0.5"),
            ("yaw_pid_kd", "0"),
            ("yaw_pid_ki", "0"),
            ("yaw_pid_integral_limit", "0"),
            ("maxrudder", "30.5"),
            ("speed_pid_kp", "0.8"),
            ("speed_pid_kd", "0"),
            ("speed_pid_ki", "0.11"),
            ("speed_pid_integral_limit", "0.07"),
            ("maxthrust", "84"),
            ("depth_control", "false"),
        ])
        .unwrap();
        let mut pid = MarinePid::new(cfg);
        let mut out = Vec::new();
        pid.iterate(10.0, &mut out);
        pid.on_mail("MOOS_MANUAL_OVERRIDE", ValueRef::String("false"), 10.0);
        pid.iterate(10.5, &mut out);
        for (var, v) in [
            ("DESIRED_HEADING", 90.0),
            ("DESIRED_SPEED", 1.5),
            ("NAV_HEADING", 80.0),
            ("NAV_SPEED", 1.0),
        ] {
            pid.on_mail(var, ValueRef::Double(v), 10.5);
        }
        pid.iterate(11.0, &mut out);
        pid.iterate(11.5, &mut out);
        let mut body = String::new();
        pid.appcast_body(11.5, &mut body);
        // Started at the first iteration (10.0): 4 iterations in 1.5 s.
        let head = "Frequency:2.667\nSpeed Factor:    0\nPID has_control: true\n  PID \
                    override: false\n  PID stale:    false\n\n";
        assert!(body.starts_with(head), "{body}");
        assert!(body.ends_with(
            "Max rudder: 30.5\n----------------------------\nSPEED_PID_KP             = \
             0.8\nSPEED_PID_KD             = 0\nSPEED_PID_KI             = 0.11\n\
             SPEED_PID_INTEGRAL_LIMIT = 0.07\nMax thrust: 84\n"
        ));
    }
}
