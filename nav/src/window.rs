//! The navigator: keyframes, time association, the sliding window and its outputs.
//!
//! # Model
//! Per keyframe: position (x east, y north, depth down; m), heading (NED yaw, rad), heading
//! bias (rad) and water current (east, north; m/s). Between keyframes:
//! - odometry: the displacement is the trapezoid of the two keyframes' level-frame velocities
//!   (DVL body velocity rotated by the AHRS pitch and roll), each rotated by its keyframe's
//!   *estimated* heading; a velocity through the water (water track, or dead reckoning) has the
//!   current added, a bottom-locked one (over ground) does not;
//! - the gyro's heading increment; a random walk on bias and current.
//!
//! On keyframes (interpolated at the measurement's own time): AHRS yaw = heading + bias, depth,
//! GPS (Huber kernel, innovation gate, refused below `gps_max_depth_m`).
//!
//! Observability: the AHRS fixes heading + bias only; GPS positions fix where the odometry
//! went, so over a dive (or along a surface track with a turn) the bias is the rotation between
//! the DVL track and the GPS track. The current enters only velocities through the water: with
//! water-track (or dead-reckoned) velocity, GPS against the DVL gives it; with bottom lock it is
//! not observable (and not needed) and is only held by its random walk until the DVL loses the
//! bottom, when dead reckoning continues on the last velocity through the water plus the
//! current.
//!
//! Keyframes come at the DVL rate; after `dvl_timeout_s` without a valid DVL report, a timer
//! makes them every `timer_period_s` with the last velocity through the water (the vehicle is
//! assumed to keep its speed through the water) and `dr_sigma_mps`, so the sigma grows.
//!
//! Time association: a measurement older than the newest keyframe is attached to the interval
//! that contains it; a newer one waits (bounded queue) for the next keyframe. A measurement
//! older than the window is refused (`TooOld`). Unlike the Gen-1 graph (one measurement per
//! sensor per key, nearest in time, dropped otherwise) nothing in the window is thrown away,
//! and unlike Gen-2 (newest at or before the keyframe) no measurement is moved in time.

use crate::config::NavConfig;
use crate::dive::{DiveReport, DiveTracker};
use crate::factors::{
    AffineGradient, DepthObs, Factor, GpsPosition, Heading, Odometry, PairHessian, RandomWalk,
    YawIncrement,
};
use crate::marginal::marginalize_first_kept;
use crate::measurements::{
    Attitude, Depth, DvlVelocity, GpsFix, GyroRates, Rejection, RejectionCounters, Sensor,
    VelocityReference,
};
use crate::solver::{BlockSystem, IndexedFactor, Prior};
use crate::state::{
    BIAS, CX, CY, M7, PSI, V7, X, Y, Z, body_to_level, grid_to_level, level_to_grid, wrap_pi,
    yaw_rate,
};
use std::collections::VecDeque;

/// What the navigator is doing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// Not initialised yet (no NAV_* should be posted); the reason says what is missing.
    Initialising(&'static str),
    /// Navigating on the DVL with fresh attitude.
    Ok,
    /// No usable DVL: keyframes from the timer on the last velocity and the current.
    DeadReckoning(&'static str),
    /// Navigating, but something is wrong (the reason).
    Degraded(&'static str),
}

impl Status {
    /// A short text: `initialising: ...`, `ok`, `dead_reckoning: ...`, `degraded: ...`.
    pub fn describe(&self) -> String {
        match self {
            Status::Initialising(r) => format!("initialising: {r}"),
            Status::Ok => "ok".to_string(),
            Status::DeadReckoning(r) => format!("dead_reckoning: {r}"),
            Status::Degraded(r) => format!("degraded: {r}"),
        }
    }
}

/// The navigator's output at its newest keyframe.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Time of the newest keyframe, s (the input clock, unless a clock jump was accepted).
    pub t_s: f64,
    /// East, m.
    pub x_m: f64,
    /// North, m.
    pub y_m: f64,
    /// Depth, m (down).
    pub depth_m: f64,
    /// Heading, rad (compass: 0 north, clockwise), wrapped to [0, 2 pi).
    pub heading_rad: f64,
    /// Pitch, rad (from the AHRS).
    pub pitch_rad: f64,
    /// Roll, rad (from the AHRS).
    pub roll_rad: f64,
    /// Velocity over ground, east, m/s.
    pub vel_east_mps: f64,
    /// Velocity over ground, north, m/s.
    pub vel_north_mps: f64,
    /// Horizontal speed over ground, m/s.
    pub speed_mps: f64,
    /// Heading bias, rad (AHRS yaw minus true heading).
    pub heading_bias_rad: f64,
    /// Water current east, m/s.
    pub current_east_mps: f64,
    /// Water current north, m/s.
    pub current_north_mps: f64,
    /// Horizontal 1-sigma, m: the square root of the largest eigenvalue of the marginal
    /// east/north covariance (the error ellipse's semi-major axis).
    pub pos_sigma_m: f64,
    /// Heading-bias 1-sigma, rad.
    pub heading_bias_sigma_rad: f64,
    /// Current 1-sigma (larger axis), m/s.
    pub current_sigma_mps: f64,
}

#[derive(Debug, Clone)]
struct Keyframe {
    t_s: f64,
    x: V7,
    pitch_rad: f64,
    roll_rad: f64,
    /// Level-frame velocity.
    u: [f64; 3],
    water: bool,
    sigma_v: f64,
    /// Factors whose first keyframe is this one.
    factors: Vec<Factor>,
    /// The Hessian part of `factors` with constant Jacobians, once assembled (`None` after a
    /// factor is added).
    kept: Option<PairHessian>,
    /// The gradient of its depth and random-walk factors, kept with `kept`.
    affine: AffineGradient,
}

impl Keyframe {
    fn push(&mut self, f: Factor) {
        self.factors.push(f);
        self.kept = None;
    }
}

#[derive(Debug, Clone, Copy)]
enum Pending {
    Heading(f64, f64),
    Depth(f64, f64),
    Gps(f64, f64, f64, f64),
}

impl Pending {
    fn t_s(&self) -> f64 {
        match *self {
            Pending::Heading(t, _) | Pending::Depth(t, _) | Pending::Gps(t, ..) => t,
        }
    }
}

#[derive(Debug, Clone, Copy)]
struct HeldDvl {
    t_s: f64,
    u: [f64; 3],
    water: bool,
    sigma_v: f64,
}

const PENDING_CAP: usize = 64;
const GYRO_CAP: usize = 64;

/// The sliding-window navigator. Feed it measurements in (roughly) time order; it makes a
/// keyframe per DVL report (or per timer period without DVL), solves the window and
/// marginalises the oldest keyframe. Nothing grows with time: the window, the queues and the
/// counters are bounded.
#[derive(Debug, Clone)]
pub struct Navigator {
    cfg: NavConfig,
    window: VecDeque<Keyframe>,
    pool: Vec<Vec<Factor>>,
    prior: Prior,
    pending: VecDeque<Pending>,
    gyro: VecDeque<(f64, f64)>,
    sys: BlockSystem,
    step: Vec<V7>,
    cov: M7,
    last_att: Option<Attitude>,
    last_depth: Option<(f64, f64)>,
    held_dvl: Option<HeldDvl>,
    last_valid_dvl_t: f64,
    last_t: [f64; 5],
    clock: Option<f64>,
    /// The latest time given to [`Navigator::advance`] (mapped as the inputs are): the app's
    /// clock, which keeps running while every sensor is silent.
    advanced: f64,
    time_offset: f64,
    jump_candidate: Option<(f64, u32)>,
    clock_jump_t: f64,
    gate_run: u32,
    depth_run: u32,
    solver_failed: bool,
    counters: RejectionCounters,
    dives: DiveTracker,
    dive_report: Option<DiveReport>,
    keyframes: u64,
}

fn sensor_slot(s: Sensor) -> usize {
    Sensor::ALL.iter().position(|x| *x == s).unwrap_or(0)
}

impl Navigator {
    /// A navigator waiting to be initialised.
    pub fn new(cfg: NavConfig) -> Navigator {
        let n = cfg.window_size.max(2);
        let cap = cfg.max_per_interval * 3 + 4;
        Navigator {
            window: VecDeque::with_capacity(n + 2),
            pool: (0..n + 2).map(|_| Vec::with_capacity(cap)).collect(),
            prior: Prior::diagonal(V7::zeros(), &[1.0; 7]),
            pending: VecDeque::with_capacity(PENDING_CAP),
            gyro: VecDeque::with_capacity(GYRO_CAP),
            sys: BlockSystem::default(),
            step: Vec::with_capacity(n + 2),
            cov: M7::zeros(),
            last_att: None,
            last_depth: None,
            held_dvl: None,
            last_valid_dvl_t: f64::NEG_INFINITY,
            last_t: [f64::NEG_INFINITY; 5],
            clock: None,
            advanced: f64::NEG_INFINITY,
            time_offset: 0.0,
            jump_candidate: None,
            clock_jump_t: f64::NEG_INFINITY,
            gate_run: 0,
            depth_run: 0,
            solver_failed: false,
            counters: RejectionCounters::default(),
            dives: DiveTracker::default(),
            dive_report: None,
            keyframes: 0,
            cfg,
        }
    }

    /// The settings.
    pub fn config(&self) -> &NavConfig {
        &self.cfg
    }

    /// Whether the navigator has a state (NAV_* may be posted).
    pub fn initialised(&self) -> bool {
        !self.window.is_empty()
    }

    /// Keyframes made so far.
    pub fn keyframes(&self) -> u64 {
        self.keyframes
    }

    /// Keyframes in the window now.
    pub fn window_len(&self) -> usize {
        self.window.len()
    }

    /// The rejection counters.
    pub fn rejections(&self) -> &RejectionCounters {
        &self.counters
    }

    /// The latest dive report (taken: the next call returns `None` until the next dive).
    pub fn take_dive_report(&mut self) -> Option<DiveReport> {
        self.dive_report.take()
    }

    fn reject(&mut self, s: Sensor, why: Rejection) -> Result<(), Rejection> {
        self.counters.count(s, why);
        Err(why)
    }

    /// Maps a raw time through the clock guard and checks the sensor's order. `votes` is false
    /// for [`Navigator::advance`], which never confirms a clock jump.
    fn admit_time(&mut self, s: Sensor, raw: f64) -> Result<f64, Rejection> {
        let t = raw + self.time_offset;
        let Some(clock) = self.clock else {
            self.clock = Some(t);
            return self.order(s, t);
        };
        // A time far from the inputs' clock is no jump when the app's clock went there too
        // (every sensor silent while the app ran on, as when the drivers' lines are held up).
        let clock = clock.max(self.advanced);
        if (t - clock).abs() > self.cfg.max_time_jump_s {
            let off = t - clock;
            let count = match self.jump_candidate {
                Some((o, c)) if (o - off).abs() < self.cfg.max_time_jump_s => c + 1,
                _ => 1,
            };
            self.jump_candidate = Some((off, count));
            if count < self.cfg.clock_jump_confirm {
                return self.reject(s, Rejection::ClockJump).map(|_| t);
            }
            // Confirmed: re-anchor the input clock just after ours.
            self.time_offset += clock + 0.1 - t;
            self.jump_candidate = None;
            self.clock_jump_t = clock;
            // The same mapping later calls will use (bit for bit, so a duplicate stays one).
            let t = raw + self.time_offset;
            self.clock = Some(t);
            return self.order(s, t);
        }
        self.jump_candidate = None;
        if t > clock {
            self.clock = Some(t);
        }
        self.order(s, t)
    }

    fn order(&mut self, s: Sensor, t: f64) -> Result<f64, Rejection> {
        let last = self.last_t[sensor_slot(s)];
        if t == last {
            return self.reject(s, Rejection::Duplicate).map(|_| t);
        }
        if t < last {
            return self.reject(s, Rejection::OutOfOrder).map(|_| t);
        }
        Ok(t)
    }

    fn accept_time(&mut self, s: Sensor, t: f64) {
        self.last_t[sensor_slot(s)] = t;
    }

    /// An AHRS attitude.
    pub fn attitude(&mut self, m: &Attitude) -> Result<(), Rejection> {
        if let Err(e) = m.check() {
            return self.reject(Sensor::Attitude, e);
        }
        let t = self.admit_time(Sensor::Attitude, m.t_s)?;
        self.accept_time(Sensor::Attitude, t);
        self.last_att = Some(Attitude { t_s: t, ..*m });
        self.tick(t);
        if self.initialised() {
            self.place(Sensor::Attitude, Pending::Heading(t, m.yaw_rad))?;
        }
        Ok(())
    }

    /// Gyro rates (their heading rate is integrated between keyframes).
    pub fn gyro(&mut self, m: &GyroRates) -> Result<(), Rejection> {
        if let Err(e) = m.check() {
            return self.reject(Sensor::Gyro, e);
        }
        let t = self.admit_time(Sensor::Gyro, m.t_s)?;
        self.accept_time(Sensor::Gyro, t);
        let (p, r) = self
            .last_att
            .map_or((0.0, 0.0), |a| (a.pitch_rad, a.roll_rad));
        if self.gyro.len() == GYRO_CAP {
            self.gyro.pop_front();
        }
        self.gyro
            .push_back((t, yaw_rate(&m.rates_body_radps, p, r)));
        self.tick(t);
        Ok(())
    }

    /// A depth.
    pub fn depth(&mut self, m: &Depth) -> Result<(), Rejection> {
        if let Err(e) = m.check() {
            return self.reject(Sensor::Depth, e);
        }
        let t = self.admit_time(Sensor::Depth, m.t_s)?;
        if let Some((lt, ld)) = self.last_depth {
            let allowed = self.cfg.depth_max_rate_mps * (t - lt).abs() + 0.5;
            if (m.depth_m - ld).abs() > allowed && self.depth_run < 10 {
                self.depth_run += 1;
                return self.reject(Sensor::Depth, Rejection::Jump);
            }
        }
        self.depth_run = 0;
        self.accept_time(Sensor::Depth, t);
        self.last_depth = Some((t, m.depth_m));
        self.tick(t);
        if self.initialised() {
            self.place(Sensor::Depth, Pending::Depth(t, m.depth_m))?;
        }
        Ok(())
    }

    /// A DVL velocity: makes a keyframe (or updates the held velocity when too close to the
    /// last keyframe or older than it).
    pub fn dvl(&mut self, m: &DvlVelocity) -> Result<(), Rejection> {
        if let Err(e) = m.check(self.cfg.max_fom_mps) {
            return self.reject(Sensor::Dvl, e);
        }
        let t = self.admit_time(Sensor::Dvl, m.t_s)?;
        self.accept_time(Sensor::Dvl, t);
        let (p, r) = self
            .last_att
            .map_or((0.0, 0.0), |a| (a.pitch_rad, a.roll_rad));
        let held = HeldDvl {
            t_s: t,
            u: body_to_level(&m.vel_body_mps, p, r),
            water: m.reference == VelocityReference::Water,
            sigma_v: self.cfg.dvl_sigma_mps.max(m.fom_mps),
        };
        self.held_dvl = Some(held);
        self.last_valid_dvl_t = t;
        let Some(newest) = self.window.back().map(|k| k.t_s) else {
            return Ok(());
        };
        if t - newest >= self.cfg.min_keyframe_interval_s {
            self.add_keyframe(t, held.u, held.water, held.sigma_v);
        }
        Ok(())
    }

    /// A GPS fix: initialises the navigator (with an attitude known) or adds a robust position
    /// factor after the innovation gate.
    pub fn gps(&mut self, m: &GpsFix) -> Result<(), Rejection> {
        if let Err(e) = m.check(self.cfg.gps_min_sats, self.cfg.gps_max_hdop) {
            return self.reject(Sensor::Gps, e);
        }
        let t = self.admit_time(Sensor::Gps, m.t_s)?;
        let sigma = self.cfg.gps_sigma_m * m.hdop.max(1.0);
        if !self.initialised() {
            self.accept_time(Sensor::Gps, t);
            if self.last_att.is_some() {
                self.initialise_at(t, m.x_m, m.y_m, self.cfg.prior_sigma.position_m);
                self.place(Sensor::Gps, Pending::Gps(t, m.x_m, m.y_m, sigma))?;
            }
            return Ok(());
        }
        self.tick(t);
        let Some(newest) = self.window.back() else {
            return Ok(());
        };
        if newest.x[Z] > self.cfg.gps_max_depth_m {
            return self.reject(Sensor::Gps, Rejection::Submerged);
        }
        let pred = self.predict_xy(t);
        let (dx, dy) = (m.x_m - pred[0], m.y_m - pred[1]);
        let s = nalgebra::Matrix2::new(
            self.cov[(X, X)] + sigma * sigma,
            self.cov[(X, Y)],
            self.cov[(Y, X)],
            self.cov[(Y, Y)] + sigma * sigma,
        );
        let d = nalgebra::Vector2::new(dx, dy);
        let m2 = s.try_inverse().map_or(f64::INFINITY, |si| d.dot(&(si * d)));
        if (m2.is_nan() || m2 > self.cfg.gps_gate_chi2) && self.gate_run < self.cfg.gps_gate_reset {
            self.gate_run += 1;
            return self.reject(Sensor::Gps, Rejection::Jump);
        }
        self.gate_run = 0;
        self.place(Sensor::Gps, Pending::Gps(t, m.x_m, m.y_m, sigma))?;
        self.accept_time(Sensor::Gps, t);
        if let Some(r) = self.dives.gps_fix(t, [m.x_m, m.y_m], pred) {
            self.dive_report = Some(r);
        }
        Ok(())
    }

    /// Initialises at a known position (east, north; m) with its sigma (m), when an attitude is
    /// known; a GPS fix does this itself. Does nothing when already initialised.
    pub fn initialise_at(&mut self, t_s: f64, x_m: f64, y_m: f64, sigma_m: f64) {
        if self.initialised() {
            return;
        }
        let Some(att) = self.last_att else {
            return;
        };
        let ps = self.cfg.prior_sigma;
        let depth = self.last_depth.map_or(0.0, |d| d.1);
        let mut x = V7::zeros();
        x[X] = x_m;
        x[Y] = y_m;
        x[Z] = depth;
        x[PSI] = att.yaw_rad;
        self.prior = Prior::diagonal(
            x,
            &[
                sigma_m,
                sigma_m,
                ps.depth_m,
                ps.heading_rad,
                ps.bias_rad,
                ps.current_mps,
                ps.current_mps,
            ],
        );
        let (u, water, sigma_v) = match self.held_dvl {
            Some(h) if t_s - h.t_s < self.cfg.dvl_timeout_s => (h.u, h.water, h.sigma_v),
            _ => ([0.0; 3], true, self.cfg.dr_sigma_mps),
        };
        let mut factors = self.pool.pop().unwrap_or_default();
        factors.clear();
        factors.push(Factor::Heading(Heading {
            alpha: 0.0,
            yaw_rad: att.yaw_rad,
            sigma_rad: self.cfg.yaw_sigma_rad,
        }));
        self.window.push_back(Keyframe {
            t_s,
            x,
            pitch_rad: att.pitch_rad,
            roll_rad: att.roll_rad,
            u,
            water,
            sigma_v,
            factors,
            kept: None,
            affine: AffineGradient::default(),
        });
        self.keyframes += 1;
        self.cov = M7::zeros();
        for k in 0..7 {
            self.cov[(k, k)] = 1.0 / self.prior.h[(k, k)];
        }
        self.pending.clear();
    }

    /// Advances the navigator's notion of time (the app calls it each iteration): when the DVL
    /// has been silent or invalid for `dvl_timeout_s`, makes a dead-reckoning keyframe once per
    /// `timer_period_s`. Times the clock guard refuses are ignored.
    pub fn advance(&mut self, t_s: f64) {
        let t = t_s + self.time_offset;
        if !t.is_finite() {
            return;
        }
        if let Some(c) = self.clock
            && (t - c.max(self.advanced)).abs() > self.cfg.max_time_jump_s
        {
            return;
        }
        self.advanced = self.advanced.max(t);
        self.tick(t);
    }

    fn tick(&mut self, t: f64) {
        let Some(newest) = self.window.back() else {
            return;
        };
        if t - self.last_valid_dvl_t < self.cfg.dvl_timeout_s
            || t - newest.t_s < self.cfg.timer_period_s
        {
            return;
        }
        // Keep the vehicle's velocity through the water, add the current.
        let u = if newest.water {
            newest.u
        } else {
            let c = grid_to_level(newest.x[PSI], &[newest.x[CX], newest.x[CY], 0.0]);
            [newest.u[0] - c[0], newest.u[1] - c[1], newest.u[2]]
        };
        self.add_keyframe(t, u, true, self.cfg.dr_sigma_mps);
    }

    fn predict_xy(&self, t: f64) -> [f64; 2] {
        let n = self.window.len();
        let Some(last) = self.window.back() else {
            return [0.0, 0.0];
        };
        if t >= last.t_s {
            let v = self.ground_velocity(last);
            let dt = t - last.t_s;
            return [last.x[X] + v[0] * dt, last.x[Y] + v[1] * dt];
        }
        for k in (0..n - 1).rev() {
            let (a, b) = (&self.window[k], &self.window[k + 1]);
            if t >= a.t_s {
                let al = (t - a.t_s) / (b.t_s - a.t_s);
                return [
                    (1.0 - al) * a.x[X] + al * b.x[X],
                    (1.0 - al) * a.x[Y] + al * b.x[Y],
                ];
            }
        }
        [self.window[0].x[X], self.window[0].x[Y]]
    }

    fn ground_velocity(&self, k: &Keyframe) -> [f64; 2] {
        let v = level_to_grid(k.x[PSI], &k.u);
        let w = f64::from(u8::from(k.water));
        [v[0] + w * k.x[CX], v[1] + w * k.x[CY]]
    }

    /// Attaches a measurement to its interval, or queues it when newer than the newest
    /// keyframe.
    fn place(&mut self, s: Sensor, p: Pending) -> Result<(), Rejection> {
        let t = p.t_s();
        let n = self.window.len();
        let Some(newest) = self.window.back() else {
            return Ok(());
        };
        if t > newest.t_s {
            if self.pending.len() == PENDING_CAP {
                self.pending.pop_front();
                self.counters.count(s, Rejection::Crowded);
            }
            self.pending.push_back(p);
            return Ok(());
        }
        if t < self.window[0].t_s {
            return self.reject(s, Rejection::TooOld);
        }
        let mut k = n - 1;
        while k > 0 && self.window[k].t_s > t {
            k -= 1;
        }
        let alpha = if k + 1 < n {
            (t - self.window[k].t_s) / (self.window[k + 1].t_s - self.window[k].t_s)
        } else {
            0.0
        };
        let f = match p {
            Pending::Heading(_, yaw) => Factor::Heading(Heading {
                alpha,
                yaw_rad: yaw,
                sigma_rad: self.cfg.yaw_sigma_rad,
            }),
            Pending::Depth(_, d) => Factor::Depth(DepthObs {
                alpha,
                depth_m: d,
                sigma_m: self.cfg.depth_sigma_m,
            }),
            Pending::Gps(_, x, y, sigma) => Factor::Gps(GpsPosition {
                alpha,
                x_m: x,
                y_m: y,
                sigma_m: sigma,
                huber_k: self.cfg.gps_huber_k,
            }),
        };
        let kf = &mut self.window[k];
        let same = kf
            .factors
            .iter()
            .filter(|g| std::mem::discriminant(*g) == std::mem::discriminant(&f))
            .count();
        if same >= self.cfg.max_per_interval {
            return self.reject(s, Rejection::Crowded);
        }
        kf.push(f);
        Ok(())
    }

    fn gyro_increment(&self, ta: f64, tb: f64) -> Option<f64> {
        let first = self.gyro.front()?;
        let last = self.gyro.back()?;
        if last.0 < ta - 1.0 || first.0 > tb {
            return None;
        }
        let mut total = 0.0;
        let mut rate = first.1;
        let mut t = ta;
        for &(ts, r) in &self.gyro {
            if ts <= ta {
                rate = r;
                continue;
            }
            if ts >= tb {
                break;
            }
            total += rate * (ts - t);
            t = ts;
            rate = r;
        }
        total += rate * (tb - t);
        Some(total)
    }

    fn add_keyframe(&mut self, t: f64, u: [f64; 3], water: bool, sigma_v: f64) {
        let Some(prev) = self.window.back() else {
            return;
        };
        let dt = t - prev.t_s;
        if dt <= 0.0 {
            return;
        }
        let sp = dt * ((prev.sigma_v * prev.sigma_v + sigma_v * sigma_v) * 0.5).sqrt();
        let sp = sp.max(1e-4);
        let odo = Odometry {
            dt_s: dt,
            u_i: prev.u,
            u_j: u,
            water_i: prev.water,
            water_j: water,
            sigma_m: [sp, sp, sp],
        };
        let dpsi = self.gyro_increment(prev.t_s, t);
        let (pitch, roll) = self.last_att.map_or((prev.pitch_rad, prev.roll_rad), |a| {
            (a.pitch_rad, a.roll_rad)
        });
        // Initial guess: heading from the gyro, else the latest AHRS yaw minus bias.
        let mut x = prev.x;
        x[PSI] = match (dpsi, self.last_att) {
            (Some(d), _) => prev.x[PSI] + d,
            (None, Some(a)) => prev.x[PSI] + wrap_pi(a.yaw_rad - prev.x[BIAS] - prev.x[PSI]),
            (None, None) => prev.x[PSI],
        };
        let xi = prev.x;
        let r = odo.residual(&xi, &x);
        for k in 0..3 {
            x[X + k] -= r[k] * odo.sigma_m[k];
        }
        let gyro_sigma = self.cfg.gyro_sigma_rad_per_sqrt_s * dt.sqrt();
        let rw = RandomWalk {
            dt_s: dt,
            bias_rad_per_sqrt_s: self.cfg.bias_rw_rad_per_sqrt_s,
            current_mps_per_sqrt_s: self.cfg.current_rw_mps_per_sqrt_s,
        };
        let prev = self.window.back_mut().expect("checked above");
        prev.push(Factor::Odometry(odo));
        prev.push(Factor::RandomWalk(rw));
        // Without a gyro over the interval the heading still changes by a bounded amount:
        // an unmeasured turn of `unmeasured_yaw_rate_sigma_radps`, never a free heading.
        let yaw = match dpsi {
            Some(d) => YawIncrement {
                dpsi_rad: d,
                sigma_rad: gyro_sigma.max(1e-5),
            },
            None => YawIncrement {
                dpsi_rad: 0.0,
                sigma_rad: (self.cfg.unmeasured_yaw_rate_sigma_radps * dt).max(1e-5),
            },
        };
        prev.push(Factor::YawIncrement(yaw));
        let mut factors = self.pool.pop().unwrap_or_default();
        factors.clear();
        self.window.push_back(Keyframe {
            t_s: t,
            x,
            pitch_rad: pitch,
            roll_rad: roll,
            u,
            water,
            sigma_v,
            factors,
            kept: None,
            affine: AffineGradient::default(),
        });
        self.keyframes += 1;
        // Measurements that were waiting for this keyframe.
        let mut kept = self.pending.len();
        while kept > 0 {
            kept -= 1;
            let Some(p) = self.pending.pop_front() else {
                break;
            };
            if p.t_s() <= t {
                let s = match p {
                    Pending::Heading(..) => Sensor::Attitude,
                    Pending::Depth(..) => Sensor::Depth,
                    Pending::Gps(..) => Sensor::Gps,
                };
                let _ = self.place(s, p);
            } else {
                self.pending.push_back(p);
            }
        }
        self.solve();
        while self.window.len() > self.cfg.window_size.max(2) {
            self.marginalise_oldest();
        }
        if let Some(k) = self.window.back() {
            let (t, x, y, z) = (k.t_s, k.x[X], k.x[Y], k.x[Z]);
            self.dives.update(t, x, y, z);
        }
    }

    fn solve(&mut self) {
        let n = self.window.len();
        let mut solved = false;
        for _ in 0..self.cfg.max_iterations.max(1) {
            // The Hessian part of the factors with constant Jacobians is assembled once per
            // interval (until a factor is added); their gradients at every iteration.
            for (k, kf) in self.window.iter_mut().enumerate() {
                if kf.kept.is_none() {
                    let mut h = PairHessian::default();
                    let mut a = AffineGradient::default();
                    for f in kf.factors.iter().filter(|f| f.constant_jacobian()) {
                        f.linearize(k, &kf.x, &kf.x, &mut h);
                        a.add_factor(f);
                    }
                    kf.kept = Some(h);
                    kf.affine = a;
                }
            }
            self.sys
                .reset_with(self.window.iter().filter_map(|kf| kf.kept.as_ref()));
            {
                let k0 = &self.window[0];
                self.prior
                    .add_to(&k0.x, &mut self.sys.d[0], &mut self.sys.g[0]);
            }
            for k in 0..n {
                let xi = self.window[k].x;
                let xj = if k + 1 < n { self.window[k + 1].x } else { xi };
                {
                    let (g0, g1) = self.sys.g.split_at_mut(k + 1);
                    self.window[k]
                        .affine
                        .add_to(&xi, &xj, &mut g0[k], g1.first_mut());
                }
                for f in &self.window[k].factors {
                    if AffineGradient::takes(f) {
                        continue;
                    }
                    if f.constant_jacobian() {
                        f.linearize_gradient(k, &xi, &xj, &mut self.sys);
                    } else {
                        f.linearize(k, &xi, &xj, &mut self.sys);
                    }
                }
            }
            match self.sys.solve(&mut self.step) {
                Ok(()) => {
                    self.solver_failed = false;
                    solved = true;
                    let mut biggest: f64 = 0.0;
                    for (kf, d) in self.window.iter_mut().zip(&self.step) {
                        kf.x += d;
                        biggest = biggest.max(d.amax());
                    }
                    if biggest < self.cfg.step_tolerance {
                        break;
                    }
                }
                Err(_) => {
                    self.solver_failed = true;
                    break;
                }
            }
        }
        // The newest keyframe's covariance at the last iteration, inverted once, when that
        // iteration succeeded: a failed one may have left its factor half made (the
        // previous update's covariance is kept then).
        if solved && !self.solver_failed {
            self.cov = self.sys.covariance();
        }
    }

    fn marginalise_oldest(&mut self) {
        let Some(old) = self.window.pop_front() else {
            return;
        };
        let Some(next) = self.window.front() else {
            return;
        };
        let prior = marginalize_first_kept(
            &self.prior,
            &old.x,
            &next.x,
            &old.factors,
            old.kept.as_ref(),
        );
        self.prior = prior.unwrap_or_else(|| {
            self.solver_failed = true;
            let mut s = [0.0; 7];
            for (k, v) in s.iter_mut().enumerate() {
                *v = self.cov[(k, k)].max(1e-6).sqrt();
            }
            Prior::diagonal(next.x, &s)
        });
        let mut v = old.factors;
        v.clear();
        self.pool.push(v);
    }

    /// The estimate at the newest keyframe, once initialised.
    pub fn estimate(&self) -> Option<Estimate> {
        let k = self.window.back()?;
        let v = self.ground_velocity(k);
        let c = &self.cov;
        let (a, b, d) = (c[(X, X)], c[(Y, Y)], c[(X, Y)]);
        let lmax = 0.5 * (a + b) + (0.25 * (a - b) * (a - b) + d * d).sqrt();
        let cmax = c[(CX, CX)].max(c[(CY, CY)]);
        Some(Estimate {
            t_s: k.t_s,
            x_m: k.x[X],
            y_m: k.x[Y],
            depth_m: k.x[Z],
            heading_rad: k.x[PSI].rem_euclid(std::f64::consts::TAU),
            pitch_rad: k.pitch_rad,
            roll_rad: k.roll_rad,
            vel_east_mps: v[0],
            vel_north_mps: v[1],
            speed_mps: v[0].hypot(v[1]),
            heading_bias_rad: k.x[BIAS],
            current_east_mps: k.x[CX],
            current_north_mps: k.x[CY],
            pos_sigma_m: lmax.max(0.0).sqrt(),
            heading_bias_sigma_rad: c[(BIAS, BIAS)].max(0.0).sqrt(),
            current_sigma_mps: cmax.max(0.0).sqrt(),
        })
    }

    /// The status at the navigator's latest time.
    pub fn status(&self) -> Status {
        let Some(k) = self.window.back() else {
            return Status::Initialising(if self.last_att.is_none() {
                "waiting for an attitude and a GPS fix"
            } else {
                "waiting for a GPS fix"
            });
        };
        let now = self.clock.unwrap_or(k.t_s).max(k.t_s);
        if self.solver_failed {
            return Status::Degraded("solver failure");
        }
        if now - self.clock_jump_t < 30.0 {
            return Status::Degraded("clock jump");
        }
        if self
            .last_att
            .is_none_or(|a| now - a.t_s > self.cfg.attitude_timeout_s)
        {
            return Status::Degraded("attitude lost");
        }
        if let Some(e) = self.estimate()
            && e.pos_sigma_m > self.cfg.degraded_sigma_m
        {
            return Status::Degraded("position uncertainty");
        }
        if now - self.last_valid_dvl_t >= self.cfg.dvl_timeout_s {
            return Status::DeadReckoning("DVL lost or invalid");
        }
        Status::Ok
    }

    /// The window as a standalone problem (states, the prior on the first, the factors with
    /// their keyframe index), for checking the window solve against [`crate::solve_batch`].
    pub fn problem(&self) -> (Vec<V7>, Prior, Vec<IndexedFactor>) {
        let states = self.window.iter().map(|k| k.x).collect();
        let factors = self
            .window
            .iter()
            .enumerate()
            .flat_map(|(i, k)| k.factors.iter().map(move |f| (i, *f)))
            .collect();
        (states, self.prior, factors)
    }

    /// The states in the window, oldest first.
    pub fn window_states(&self) -> Vec<(f64, V7)> {
        self.window.iter().map(|k| (k.t_s, k.x)).collect()
    }

    /// Replaces the window's states (oldest first; extra values are ignored) and solves again:
    /// lets a test start the window and a batch solve from the same point.
    pub fn resolve_from(&mut self, states: &[V7]) {
        for (k, x) in self.window.iter_mut().zip(states) {
            k.x = *x;
        }
        self.solve();
    }
}
