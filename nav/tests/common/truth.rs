//! A tiny deterministic truth generator: a vehicle on a lawnmower at 1.5 m/s through the water,
//! 3-5 m deep, surfacing every `dive_s` seconds for `surface_s` seconds, in a constant water
//! current, seen by a DVL, an AHRS with a heading bias, a gyro, a depth sensor and a GPS that
//! only reports at the surface. Shared by the tests, the bench and the six-hour driver.
#![allow(dead_code)]

use nav::{Attitude, Depth, DvlVelocity, GpsFix, GyroRates, VelocityReference};
use std::f64::consts::PI;

/// Scenario settings.
#[derive(Debug, Clone)]
pub struct Scenario {
    pub seed: u64,
    pub speed_mps: f64,
    pub leg_s: f64,
    pub turn_rate_radps: f64,
    pub first_heading_rad: f64,
    pub surface_s: f64,
    pub dive_s: f64,
    pub bias_rad: f64,
    pub current: [f64; 2],
    pub reference: VelocityReference,
    pub dvl_sigma_mps: f64,
    pub yaw_sigma_rad: f64,
    pub gyro_sigma_radps: f64,
    pub depth_sigma_m: f64,
    pub gps_sigma_m: f64,
    pub tilt_sigma_rad: f64,
}

impl Default for Scenario {
    fn default() -> Self {
        Scenario {
            seed: 1,
            speed_mps: 1.5,
            leg_s: 133.0,
            turn_rate_radps: 6f64.to_radians(),
            first_heading_rad: PI / 2.0,
            surface_s: 60.0,
            dive_s: 300.0,
            bias_rad: 3f64.to_radians(),
            current: [0.08, -0.06],
            reference: VelocityReference::Water,
            dvl_sigma_mps: 0.02,
            yaw_sigma_rad: 0.5f64.to_radians(),
            gyro_sigma_radps: 0.002,
            depth_sigma_m: 0.02,
            gps_sigma_m: 1.5,
            tilt_sigma_rad: 0.003,
        }
    }
}

/// One sensor event.
#[derive(Debug, Clone, Copy)]
pub enum Event {
    Dvl(DvlVelocity),
    Att(Attitude),
    Gyro(GyroRates),
    Depth(Depth),
    Gps(GpsFix),
}

impl Event {
    pub fn t_s(&self) -> f64 {
        match self {
            Event::Dvl(m) => m.t_s,
            Event::Att(m) => m.t_s,
            Event::Gyro(m) => m.t_s,
            Event::Depth(m) => m.t_s,
            Event::Gps(m) => m.t_s,
        }
    }
}

/// The true state at one time.
#[derive(Debug, Clone, Copy, Default)]
pub struct Truth {
    pub t_s: f64,
    pub x_m: f64,
    pub y_m: f64,
    pub depth_m: f64,
    pub heading_rad: f64,
}

/// Streams the events in time order, integrating the truth between them.
pub struct Sim {
    pub sc: Scenario,
    rng: fastrand::Rng,
    truth: Truth,
    /// Next time of each sensor: DVL, AHRS, gyro, depth, GPS.
    next: [f64; 5],
    period: [f64; 5],
}

fn gauss(rng: &mut fastrand::Rng) -> f64 {
    let u1 = rng.f64().max(1e-300);
    let u2 = rng.f64();
    (-2.0 * u1.ln()).sqrt() * (2.0 * PI * u2).cos()
}

impl Sim {
    pub fn new(sc: Scenario) -> Sim {
        Sim {
            rng: fastrand::Rng::with_seed(sc.seed),
            sc,
            truth: Truth::default(),
            next: [0.013, 0.037, 0.041, 0.005, 0.11],
            period: [0.2, 0.1, 0.1, 0.05, 0.2],
        }
    }

    pub fn truth(&self) -> Truth {
        self.truth
    }

    /// Heading and heading rate at `t`: legs joined by 180-degree turns, alternately left and
    /// right.
    pub fn heading(&self, t: f64) -> (f64, f64) {
        let turn_s = PI / self.sc.turn_rate_radps;
        let period = self.sc.leg_s + turn_s;
        let k = (t / period).floor();
        let tau = t - k * period;
        let side = if (k as i64) % 2 == 0 { 1.0 } else { -1.0 };
        let base = self.sc.first_heading_rad + k * PI;
        if tau < self.sc.leg_s {
            (base, 0.0)
        } else {
            let w = side * self.sc.turn_rate_radps;
            (base + w * (tau - self.sc.leg_s), w)
        }
    }

    /// Depth and depth rate at `t`.
    pub fn depth(&self, t: f64) -> (f64, f64) {
        let cycle = self.sc.surface_s + self.sc.dive_s;
        let tau = t % cycle;
        if tau < self.sc.surface_s {
            return (0.0, 0.0);
        }
        let s = tau - self.sc.surface_s;
        let ramp = 8.0;
        let body = 4.0 + (2.0 * PI * s / 100.0).sin();
        let body_rate = 2.0 * PI / 100.0 * (2.0 * PI * s / 100.0).cos();
        if s < ramp {
            let f = s / ramp;
            (f * body, body / ramp + f * body_rate)
        } else if s > self.sc.dive_s - ramp {
            let f = (self.sc.dive_s - s) / ramp;
            (f * body, -body / ramp + f * body_rate)
        } else {
            (body, body_rate)
        }
    }

    pub fn ground_velocity(&self, t: f64) -> [f64; 2] {
        let (h, _) = self.heading(t);
        [
            self.sc.speed_mps * h.sin() + self.sc.current[0],
            self.sc.speed_mps * h.cos() + self.sc.current[1],
        ]
    }

    fn integrate_to(&mut self, t: f64) {
        while self.truth.t_s < t {
            let dt = (t - self.truth.t_s).min(0.01);
            let tm = self.truth.t_s + 0.5 * dt;
            let v = self.ground_velocity(tm);
            self.truth.x_m += v[0] * dt;
            self.truth.y_m += v[1] * dt;
            self.truth.t_s += dt;
        }
        self.truth.t_s = t;
        self.truth.heading_rad = self.heading(t).0;
        self.truth.depth_m = self.depth(t).0;
    }

    /// The next event (GPS only while the antenna is out of the water).
    pub fn next_event(&mut self) -> Event {
        loop {
            let (k, t) = self
                .next
                .iter()
                .copied()
                .enumerate()
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .unwrap();
            self.next[k] += self.period[k];
            self.integrate_to(t);
            let tr = self.truth;
            let (h, hdot) = self.heading(t);
            let g = |s: &mut Self| gauss(&mut s.rng);
            match k {
                0 => {
                    let (_, ddot) = self.depth(t);
                    let body = match self.sc.reference {
                        VelocityReference::Water => [self.sc.speed_mps, 0.0, ddot],
                        VelocityReference::Ground => {
                            let v = self.ground_velocity(t);
                            let (s, c) = h.sin_cos();
                            [s * v[0] + c * v[1], c * v[0] - s * v[1], ddot]
                        }
                    };
                    let n = self.sc.dvl_sigma_mps;
                    return Event::Dvl(DvlVelocity {
                        t_s: t,
                        vel_body_mps: [
                            body[0] + n * g(self),
                            body[1] + n * g(self),
                            body[2] + n * g(self),
                        ],
                        valid: true,
                        fom_mps: 0.01,
                        reference: self.sc.reference,
                    });
                }
                1 => {
                    let yaw = (h + self.sc.bias_rad + self.sc.yaw_sigma_rad * g(self))
                        .rem_euclid(2.0 * PI);
                    return Event::Att(Attitude {
                        t_s: t,
                        yaw_rad: yaw,
                        pitch_rad: self.sc.tilt_sigma_rad * g(self),
                        roll_rad: self.sc.tilt_sigma_rad * g(self),
                    });
                }
                2 => {
                    let r = hdot + self.sc.gyro_sigma_radps * g(self);
                    return Event::Gyro(GyroRates {
                        t_s: t,
                        rates_body_radps: [0.0, 0.0, r],
                    });
                }
                3 => {
                    return Event::Depth(Depth {
                        t_s: t,
                        depth_m: tr.depth_m + self.sc.depth_sigma_m * g(self),
                    });
                }
                _ => {
                    if tr.depth_m < 0.2 {
                        let s = self.sc.gps_sigma_m;
                        return Event::Gps(GpsFix {
                            t_s: t,
                            x_m: tr.x_m + s * g(self),
                            y_m: tr.y_m + s * g(self),
                            hdop: 1.0,
                            sats: 9,
                        });
                    }
                }
            }
        }
    }
}

/// Feeds one event to a navigator and a dead reckoner.
pub fn feed(nav: &mut nav::Navigator, dr: &mut nav::DeadReckoner, e: &Event) {
    match e {
        Event::Dvl(m) => {
            let _ = nav.dvl(m);
            dr.dvl(m);
        }
        Event::Att(m) => {
            let _ = nav.attitude(m);
            dr.attitude(m);
        }
        Event::Gyro(m) => {
            let _ = nav.gyro(m);
        }
        Event::Depth(m) => {
            let _ = nav.depth(m);
            dr.depth(m);
        }
        Event::Gps(m) => {
            let _ = nav.gps(m);
            dr.gps(m);
        }
    }
}
