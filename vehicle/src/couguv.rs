//! The CougUV simulator (`uSimCougUV`): the three-fin, one-thruster torpedo model of
//! [`crate::cougars::CougUvModel`] (the Gen-1 HoloOcean `torpedo_3fin` parameters) driven by
//! the physical fin deflections and the thrust that `pCougControls` posts, with the position
//! integrated over the ground and the truth posted as uSimMarine posts it, so that
//! uSimSensors, pNodeReporter and the plots read it unchanged.
//!
//! It is a separate app rather than a mode of uSimMarineV22: its inputs are fins and thrust
//! instead of `DESIRED_RUDDER`/`DESIRED_ELEVATOR`/`DESIRED_THRUST`, and uSimMarineV22's
//! behaviour (and every existing mission's log) stays as it is.
//!
//! # Model
//!
//! Per [`CougUvModel::step`]: each fin follows its command through a first-order lag
//! (`t_delta`), clamped to `±delta_max`; surge follows `thrust/100 · max_speed` with time
//! constant `t_surge`; pitch is a damped pendulum (restoring moment `m g r_bg sin θ`,
//! damping ratio `zeta_pitch`) driven by the lift of the two lower fins, `½ ρ A CLδ cos(cant)
//! u² δ` at a lever of half the length, the elevator being `(port − stbd)/2`; yaw rate is a
//! first-order Nomoto model of the top fin (`k_nomoto · δ · u`, `t_yaw`); depth rate is
//! `u sin θ − buoyancy_rate`, depth at least 0. Here the position follows: the horizontal
//! speed `u cos θ` along the heading, plus the water current (`drift_x`, `drift_y`).
//!
//! Without a fin or thrust command for `command_timeout` seconds (5 s: the Teensy's
//! failsafe) the fins go to zero and the thrust to 0.
//!
//! # Large steps
//!
//! In a real-time run a starved process iterates late: at a warp of 8 a stall of 5 s of
//! wall time is one step of 40 simulated seconds. The model then integrates the whole gap
//! in steps of at most [`MAX_STEP_S`] (and the model's own 5 ms), so a long step gives the
//! same vehicle as many short ones, and the actuator failsafe takes effect inside the step:
//! the command flies until `command_timeout` after it was given, the rest of the gap with
//! the actuators stopped ([`CougUvSim::advance_to`]). The C++ uSimMarine makes one Euler
//! step of the whole gap; its model is kinematic (rates and speeds with limits), so that
//! stays bounded, and uSimMarineV22 here does the same. This model has dynamics (the pitch
//! pendulum, the actuator lags), which an explicit step of seconds would make diverge,
//! hence the substeps. A state that is not finite (which no finite command can produce) is
//! refused: the truth stays where it was, and a warning says so ([`CougUvSim::take_warnings`]).
//!
//! # Configuration
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `prefix` | `SIM` | prefix of the posted truth |
//! | `start_pos` | `x=0,y=0,heading=0,speed=0,depth=0` | as uSimMarine's (speed is the initial surge) |
//! | `drift_x`, `drift_y` | 0 | m/s, water current east, north |
//! | `default_water_depth` | 0 | m; with a positive depth `<P>_ALTITUDE` is posted |
//! | `command_timeout` | 5 | s, actuator failsafe (0 = never) |
//! | `mass`, `length`, `diameter`, `rho` | 31.03, 1.6, 0.19, 1026 | kg, m, m, kg/m³ |
//! | `r_bg`, `zeta_pitch` | 0.02, 0.8 | m (centre of gravity below buoyancy), 1 |
//! | `fin_area`, `cl_delta`, `fin_cant`, `delta_max`, `t_delta` | 0.00665, 0.9, 30, 25, 0.1 | m², 1/rad, deg, deg, s |
//! | `t_surge`, `max_speed` | 20, 2.0 | s, m/s at 100 % thrust |
//! | `k_nomoto`, `t_yaw` | 0.25, 1 | 1/m, s |
//! | `buoyancy_rate` | 0.025 | m/s of rise from positive buoyancy |
//!
//! # Variables
//!
//! Read: `FIN_DEFLECT_TOP_DEG`, `FIN_DEFLECT_STBD_DEG`, `FIN_DEFLECT_PORT_DEG` (deg),
//! `THRUST_PCT` (%) — see [`crate::cougars::vars`].
//!
//! Posted every iteration (`<P>` the prefix): `<P>_X`, `<P>_Y` (m east, north),
//! `<P>_LAT`, `<P>_LONG` (with the mission's origin), `<P>_HEADING` (deg, compass),
//! `<P>_SPEED` (surge through the water, m/s), `<P>_DEPTH` (m, positive down), `<P>_Z`
//! (−depth), `<P>_PITCH` (rad, nose up positive, as uSimMarine), `<P>_YAW`
//! (`−rad(angle180(heading))`, as uSimMarine), `<P>_HEADING_OVER_GROUND` (deg),
//! `<P>_SPEED_OVER_GROUND` (horizontal, m/s), `<P>_ALTITUDE` (with a water depth).

use moos_types::ByteString;

use crate::angle::{angle180, angle360};
use crate::config::{ConfigError, apply_params, strict};
use crate::cougars::{CougUvModel, CougUvState, UCommand, vars};
use crate::geodesy::LocalGrid;
use crate::moos::{Posting, ValueRef};
use crate::sim::StartPose;

const APP: &str = "uSimCougUV";

/// Longest integration step, seconds (the model substeps further, at 5 ms), whatever the gap
/// between two iterations.
pub const MAX_STEP_S: f64 = 0.01;

/// `uSimCougUV` configuration.
#[derive(Debug, Clone, PartialEq)]
pub struct CougUvSimConfig {
    /// Prefix of the posted truth (`SIM`).
    pub prefix: String,
    /// Starting pose.
    pub start: StartPose,
    /// The vehicle.
    pub model: CougUvModel,
    /// Water current east, m/s.
    pub drift_x_mps: f64,
    /// Water current north, m/s.
    pub drift_y_mps: f64,
    /// Water depth, m (0: unknown, no altitude).
    pub water_depth: f64,
    /// Seconds without a command after which the actuators stop (0: never).
    pub command_timeout_s: f64,
}

impl Default for CougUvSimConfig {
    fn default() -> Self {
        CougUvSimConfig {
            prefix: "SIM".to_string(),
            start: StartPose::default(),
            model: CougUvModel {
                buoyancy_rate: 0.025,
                ..CougUvModel::default()
            },
            drift_x_mps: 0.0,
            drift_y_mps: 0.0,
            water_depth: 0.0,
            command_timeout_s: 5.0,
        }
    }
}

impl CougUvSimConfig {
    /// Strict construction from `(key, value)` pairs.
    pub fn from_params<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<Self, ConfigError> {
        strict(Self::from_params_lenient(params))
    }

    /// Reads a `uSimCougUV` block (keys in the module docs); unknown keys and bad values come
    /// back as non-fatal errors.
    pub fn from_params_lenient<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> Result<(Self, Vec<ConfigError>), ConfigError> {
        let mut cfg = CougUvSimConfig::default();
        let unknown = apply_params(APP, &mut cfg, params, |c, key, p| {
            let m = &mut c.model;
            match key {
                "prefix" => c.prefix = p.word()?,
                "start_pos" => {
                    let mut s = c.start;
                    s.apply_spec(p.value).map_err(|e| p.bad(e))?;
                    c.start = s;
                }
                "drift_x" => c.drift_x_mps = p.f64()?,
                "drift_y" => c.drift_y_mps = p.f64()?,
                "default_water_depth" => c.water_depth = p.non_neg()?,
                "command_timeout" => c.command_timeout_s = p.non_neg()?,
                "mass" => m.mass = p.pos()?,
                "length" => m.length = p.pos()?,
                "diameter" => m.diameter = p.pos()?,
                "rho" => m.rho = p.pos()?,
                "r_bg" => m.r_bg = p.pos()?,
                "zeta_pitch" => m.zeta_pitch = p.non_neg()?,
                "fin_area" => m.fin_area = p.non_neg()?,
                "cl_delta" => m.cl_delta = p.non_neg()?,
                "fin_cant" => m.fin_cant_deg = p.range(0.0, 89.0, "degrees in 0..89")?,
                "delta_max" => m.delta_max_deg = p.range(0.0, 90.0, "degrees in 0..90")?,
                "t_delta" => m.t_delta = p.pos()?,
                "t_surge" => m.t_surge = p.pos()?,
                "max_speed" => m.max_speed = p.non_neg()?,
                "k_nomoto" => m.k_nomoto = p.f64()?,
                "t_yaw" => m.t_yaw = p.pos()?,
                "buoyancy_rate" => m.buoyancy_rate = p.f64()?,
                _ => return Ok(false),
            }
            Ok(true)
        })?;
        Ok((cfg, unknown))
    }
}

/// The full simulated state: the model's plus the position over the ground.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CougUvTruth {
    /// Attitude, depth, rates, surge and fins.
    pub body: CougUvState,
    /// Metres east of the origin.
    pub x: f64,
    /// Metres north of the origin.
    pub y: f64,
    /// Velocity over ground, east, m/s.
    pub vel_east_mps: f64,
    /// Velocity over ground, north, m/s.
    pub vel_north_mps: f64,
}

impl CougUvTruth {
    /// True when every number of the state is finite.
    pub fn is_finite(&self) -> bool {
        let b = &self.body;
        [
            self.x,
            self.y,
            self.vel_east_mps,
            self.vel_north_mps,
            b.depth,
            b.depth_rate,
            b.pitch,
            b.pitch_rate,
            b.heading,
            b.yaw_rate,
            b.surge,
        ]
        .iter()
        .chain(&b.fins)
        .all(|v| v.is_finite())
    }
}

/// Advances `truth` by `dt` seconds under the physical command `cmd` and the current.
pub fn advance(
    model: &CougUvModel,
    truth: &CougUvTruth,
    cmd: &UCommand,
    drift: (f64, f64),
    dt: f64,
) -> CougUvTruth {
    let mut t = *truth;
    if dt <= 0.0 {
        return t;
    }
    let n = (dt / MAX_STEP_S).ceil().max(1.0) as usize;
    let h = dt / n as f64;
    for _ in 0..n {
        let before = t.body;
        t.body = model.step(&before, cmd, h);
        // Mean of the step's horizontal velocities (heading and pitch at both ends).
        let v = |s: &CougUvState| {
            let (sh, ch) = s.heading.to_radians().sin_cos();
            let u = s.surge * s.pitch.cos();
            (u * sh, u * ch)
        };
        let (e0, n0) = v(&before);
        let (e1, n1) = v(&t.body);
        t.vel_east_mps = (e0 + e1) / 2.0 + drift.0;
        t.vel_north_mps = (n0 + n1) / 2.0 + drift.1;
        t.x += t.vel_east_mps * h;
        t.y += t.vel_north_mps * h;
    }
    t
}

/// The `uSimCougUV` MOOS adapter: fins and thrust in, truth out.
pub struct CougUvSim {
    cfg: CougUvSimConfig,
    grid: Option<LocalGrid>,
    truth: CougUvTruth,
    cmd: UCommand,
    last_cmd: Option<f64>,
    last_time: Option<f64>,
    names: [ByteString; 13],
    warnings: Vec<String>,
    refused_steps: u64,
}

impl CougUvSim {
    /// The simulator at its start pose; `grid` (the mission's origin) adds latitude and
    /// longitude.
    pub fn new(cfg: CougUvSimConfig, grid: Option<LocalGrid>) -> Self {
        let p = |s: &str| -> ByteString { format!("{}_{s}", cfg.prefix).into() };
        let names = [
            p("X"),
            p("Y"),
            p("LAT"),
            p("LONG"),
            p("HEADING"),
            p("SPEED"),
            p("DEPTH"),
            p("Z"),
            p("PITCH"),
            p("YAW"),
            p("HEADING_OVER_GROUND"),
            p("SPEED_OVER_GROUND"),
            p("ALTITUDE"),
        ];
        let s = cfg.start;
        let truth = CougUvTruth {
            body: CougUvState {
                depth: s.depth.max(0.0),
                heading: angle360(s.heading_deg),
                surge: s.speed_mps,
                ..CougUvState::default()
            },
            x: s.x,
            y: s.y,
            ..CougUvTruth::default()
        };
        CougUvSim {
            cfg,
            grid,
            truth,
            cmd: UCommand::default(),
            last_cmd: None,
            last_time: None,
            names,
            warnings: Vec::new(),
            refused_steps: 0,
        }
    }

    /// The variables the app registers for.
    pub fn subscriptions() -> [&'static str; 4] {
        [
            vars::FIN_DEFLECT_TOP_DEG,
            vars::FIN_DEFLECT_STBD_DEG,
            vars::FIN_DEFLECT_PORT_DEG,
            vars::THRUST_PCT,
        ]
    }

    /// The configuration in force.
    pub fn config(&self) -> &CougUvSimConfig {
        &self.cfg
    }

    /// The simulated truth.
    pub fn truth(&self) -> &CougUvTruth {
        &self.truth
    }

    /// The command in force (physical fins, thrust).
    pub fn command(&self) -> &UCommand {
        &self.cmd
    }

    /// Takes one piece of mail posted at `time`.
    pub fn on_mail(&mut self, var: &str, value: ValueRef<'_>, time: f64) {
        let Some(v) = value.as_f64().filter(|v| v.is_finite()) else {
            return;
        };
        let slot = match var {
            vars::FIN_DEFLECT_TOP_DEG => &mut self.cmd.fin[0],
            vars::FIN_DEFLECT_STBD_DEG => &mut self.cmd.fin[1],
            vars::FIN_DEFLECT_PORT_DEG => &mut self.cmd.fin[2],
            vars::THRUST_PCT => &mut self.cmd.thruster,
            _ => return,
        };
        *slot = v;
        self.last_cmd = Some(time);
    }

    /// The command the actuators follow at `now`: the last one, or all-stop once it is older
    /// than the timeout (or before any).
    fn effective(&self, now: f64) -> UCommand {
        match self.last_cmd {
            Some(t)
                if self.cfg.command_timeout_s <= 0.0 || now - t <= self.cfg.command_timeout_s =>
            {
                self.cmd
            }
            _ => UCommand::default(),
        }
    }

    /// The MOOS time of the last advance (`None` before the first iteration).
    pub fn last_time(&self) -> Option<f64> {
        self.last_time
    }

    /// Steps whose result was not finite and was refused (the truth was kept).
    pub fn refused_steps(&self) -> u64 {
        self.refused_steps
    }

    /// Run warnings raised since the last call (a refused non-finite step).
    pub fn take_warnings(&mut self) -> Vec<String> {
        std::mem::take(&mut self.warnings)
    }

    /// Advances the truth from the last advance to MOOS time `now` without posting: the
    /// command in force flies until `command_timeout` after it was given, the actuators are
    /// stopped for the rest of the gap, however long the gap is (see "Large steps"). The
    /// first call only sets the time; a `now` before the last advance changes nothing.
    pub fn advance_to(&mut self, now: f64) {
        let Some(t0) = self.last_time else {
            self.last_time = Some(now);
            return;
        };
        if now.is_nan() || now <= t0 {
            return;
        }
        self.last_time = Some(now);
        let drift = (self.cfg.drift_x_mps, self.cfg.drift_y_mps);
        let stop = UCommand::default();
        // Until when the command flies: never without one, always without a timeout.
        let until = match self.last_cmd {
            None => t0,
            Some(_) if self.cfg.command_timeout_s <= 0.0 => now,
            Some(t) => (t + self.cfg.command_timeout_s).clamp(t0, now),
        };
        let mut next = self.truth;
        if until > t0 {
            next = advance(&self.cfg.model, &next, &self.cmd, drift, until - t0);
        }
        if now > until {
            next = advance(&self.cfg.model, &next, &stop, drift, now - until);
        }
        if next.is_finite() {
            self.truth = next;
        } else {
            self.refused_steps += 1;
            self.warnings.push(format!(
                "the model's state over {:.3} s to {now:.3} is not finite: kept the previous \
                 truth (command top={} stbd={} port={} thrust={})",
                now - t0,
                self.cmd.fin[0],
                self.cmd.fin[1],
                self.cmd.fin[2],
                self.cmd.thruster
            ));
        }
    }

    /// One iteration at MOOS time `now`: advance from the previous iteration
    /// ([`CougUvSim::advance_to`]) and post the truth.
    pub fn iterate(&mut self, now: f64, out: &mut Vec<Posting>) {
        self.advance_to(now);
        let t = &self.truth;
        let b = &t.body;
        let n = &self.names;
        out.push(Posting::double(&n[0], t.x));
        out.push(Posting::double(&n[1], t.y));
        if let Some(Ok((lat, lon))) = self.grid.as_ref().map(|g| g.to_latlon(t.x, t.y)) {
            out.push(Posting::double(&n[2], lat));
            out.push(Posting::double(&n[3], lon));
        }
        out.push(Posting::double(&n[4], b.heading));
        out.push(Posting::double(&n[5], b.surge));
        out.push(Posting::double(&n[6], b.depth));
        out.push(Posting::double(&n[7], -b.depth));
        // The model's pitch is nose down positive; MOOS's is nose up positive.
        out.push(Posting::double(&n[8], -b.pitch));
        out.push(Posting::double(&n[9], -angle180(b.heading).to_radians()));
        let sog = t.vel_east_mps.hypot(t.vel_north_mps);
        let hog = if sog > 0.0 {
            angle360(t.vel_east_mps.atan2(t.vel_north_mps).to_degrees())
        } else {
            b.heading
        };
        out.push(Posting::double(&n[10], hog));
        out.push(Posting::double(&n[11], sog));
        if self.cfg.water_depth > 0.0 {
            out.push(Posting::double(
                &n[12],
                (self.cfg.water_depth - b.depth).max(0.0),
            ));
        }
    }

    /// The appcast body: the command in force and the truth.
    pub fn appcast_body(&self, now: f64, out: &mut String) {
        use std::fmt::Write as _;
        let c = self.effective(now);
        let t = &self.truth;
        let b = &t.body;
        let _ = writeln!(
            out,
            "Command: top={:.1} stbd={:.1} port={:.1} deg  thrust={} %{}",
            c.fin[0],
            c.fin[1],
            c.fin[2],
            c.thruster,
            if self.last_cmd.is_some() && c == UCommand::default() && self.cmd != c {
                "  (timed out)"
            } else {
                ""
            }
        );
        let _ = writeln!(
            out,
            "Fins now: top={:.1} stbd={:.1} port={:.1} deg",
            b.fins[0], b.fins[1], b.fins[2]
        );
        let _ = writeln!(out);
        let _ = writeln!(
            out,
            "{}: x={:.2} y={:.2} depth={:.2} heading={:.1} pitch={:.1} (nose up) surge={:.2}",
            self.cfg.prefix,
            t.x,
            t.y,
            b.depth,
            b.heading,
            -b.pitch.to_degrees(),
            b.surge
        );
    }
}
