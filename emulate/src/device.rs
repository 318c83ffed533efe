//! The pure side of every emulator: the [`Device`] trait (time and truth in, bytes out; bytes
//! in, state changes and answers out) and [`Emulator`], a device with its truth source and
//! its faults, which the I/O edge ([`crate::transport`]) drives.

use crate::fault::{FaultClock, FaultPlan};
use crate::truth::{Truth, TruthSource};

/// What a device knows at one instant besides the truth.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Situation {
    /// Emulator time, s.
    pub t: f64,
    /// The Unix time at `t`, s (for the UTC fields and time stamps of the reports).
    pub unix_s: f64,
    /// The vehicle's truth at `t` (with any noise burst already added).
    pub truth: Truth,
    /// The leak sensor reads wet.
    pub leak: bool,
    /// How far the battery has fallen, volts.
    pub battery_drop_v: f64,
}

/// One emulated device: pure, no I/O, no clock.
pub trait Device: Send {
    /// The device's name (`gps`, `gpsd`, `dvl`, `seatrac`, `teensy`).
    fn name(&self) -> &'static str;

    /// How often the edge calls [`Device::tick`], s (the fastest report's period or less).
    fn period(&self) -> f64;

    /// A host connected (a TCP client, or a pseudo-terminal was made): per-connection state
    /// is reset; returns what the device sends first (gpsd's VERSION banner), often nothing.
    fn connected(&mut self, s: &Situation) -> Vec<u8> {
        let _ = s;
        Vec::new()
    }

    /// The reports due at `s.t`.
    fn tick(&mut self, s: &Situation) -> Vec<u8>;

    /// Bytes from the host at `s.t` (any piece of a line); returns the answers.
    fn receive(&mut self, s: &Situation, data: &[u8]) -> Vec<u8>;
}

/// What one step of an [`Emulator`] produced.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Output {
    /// Bytes to send (empty while silent or off).
    pub bytes: Vec<u8>,
    /// The edge must close its connection now (a disconnection fault began).
    pub disconnect: bool,
}

/// A device with its truth, faults and seeded generator.
pub struct Emulator {
    device: Box<dyn Device>,
    truth: Box<dyn TruthSource>,
    faults: FaultPlan,
    clock: FaultClock,
    rng: fastrand::Rng,
    epoch_unix_s: f64,
    last_t: f64,
}

impl std::fmt::Debug for Emulator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Emulator")
            .field("device", &self.device.name())
            .field("faults", &self.faults)
            .finish_non_exhaustive()
    }
}

/// Base σ of a noise burst (times its scale): position m, depth m, velocity m/s, heading
/// deg, pitch and roll deg (the table of [`crate::fault`]).
const NOISE_POS_M: f64 = 2.0;
const NOISE_DEPTH_M: f64 = 0.1;
const NOISE_VEL_MPS: f64 = 0.2;
const NOISE_HEADING_DEG: f64 = 5.0;
const NOISE_ATT_DEG: f64 = 2.0;

fn gauss(rng: &mut fastrand::Rng, std: f64) -> f64 {
    let u1 = 1.0 - rng.f64();
    let u2 = rng.f64();
    std * (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

impl Emulator {
    /// `device` measuring `truth`, with `faults`; every draw of the emulator (noise bursts,
    /// garbage) from `seed`; emulator time 0 is Unix time `epoch_unix_s`.
    pub fn new(
        device: Box<dyn Device>,
        truth: Box<dyn TruthSource>,
        faults: FaultPlan,
        seed: u64,
        epoch_unix_s: f64,
    ) -> Self {
        Emulator {
            device,
            truth,
            faults,
            clock: FaultClock::default(),
            rng: fastrand::Rng::with_seed(seed ^ 0x5eed_e3a1_a7e5),
            epoch_unix_s,
            last_t: f64::NEG_INFINITY,
        }
    }

    /// The same emulator with its fault plan counted from `clock`'s origin (by default the
    /// emulator's time 0).
    pub fn with_fault_clock(mut self, clock: FaultClock) -> Self {
        self.clock = clock;
        self
    }

    /// The device's name.
    pub fn name(&self) -> &'static str {
        self.device.name()
    }

    /// The fault plan's time at emulator time `t`.
    fn ft(&self, t: f64) -> f64 {
        self.clock.plan_time(t)
    }

    /// The edge's tick period, s.
    pub fn period(&self) -> f64 {
        self.device.period()
    }

    /// The faults.
    pub fn faults(&self) -> &FaultPlan {
        &self.faults
    }

    /// True while a disconnection keeps the device off (the edge accepts no connection).
    pub fn offline(&self, t: f64) -> bool {
        self.faults.offline(self.ft(t))
    }

    fn situation(&mut self, t: f64) -> Situation {
        let mut truth = self.truth.truth(t);
        let k = self.faults.noise_scale(self.ft(t));
        if k > 0.0 {
            let r = &mut self.rng;
            truth.x += gauss(r, k * NOISE_POS_M);
            truth.y += gauss(r, k * NOISE_POS_M);
            truth.depth = (truth.depth + gauss(r, k * NOISE_DEPTH_M)).max(0.0);
            truth.vel_east_mps += gauss(r, k * NOISE_VEL_MPS);
            truth.vel_north_mps += gauss(r, k * NOISE_VEL_MPS);
            truth.vel_down_mps += gauss(r, k * NOISE_VEL_MPS);
            truth.heading_deg =
                vehicle::angle::angle360(truth.heading_deg + gauss(r, k * NOISE_HEADING_DEG));
            truth.pitch_rad += gauss(r, k * NOISE_ATT_DEG).to_radians();
            truth.roll_rad += gauss(r, k * NOISE_ATT_DEG).to_radians();
        }
        Situation {
            t,
            unix_s: self.epoch_unix_s + t,
            truth,
            leak: self.faults.leak(self.ft(t)),
            battery_drop_v: self.faults.battery_drop_v(self.ft(t)),
        }
    }

    /// Mixes the garbage due over `dt` seconds into `bytes` at random places.
    fn garble(&mut self, t: f64, dt: f64, bytes: &mut Vec<u8>) {
        let rate = self.faults.garbage_rate(self.ft(t));
        if rate <= 0.0 {
            return;
        }
        let mean = rate * dt;
        // Whole bytes plus one more with the fractional chance, so the mean rate is exact.
        let n = mean.floor() as usize + usize::from(self.rng.f64() < mean.fract());
        for _ in 0..n {
            let at = self.rng.usize(0..=bytes.len());
            bytes.insert(at, self.rng.u8(..));
        }
    }

    /// A host connected at `t`: the device's greeting.
    pub fn connect(&mut self, t: f64) -> Vec<u8> {
        let s = self.situation(t);
        let out = self.device.connected(&s);
        if self.faults.silent(self.ft(t)) {
            Vec::new()
        } else {
            out
        }
    }

    /// Steps the device to `t` (non-decreasing): its reports, faults applied.
    pub fn tick(&mut self, t: f64) -> Output {
        let dt = if self.last_t.is_finite() {
            (t - self.last_t).max(0.0)
        } else {
            0.0
        };
        let disconnect = self
            .faults
            .disconnects_between(self.ft(self.last_t), self.ft(t))
            > 0;
        self.last_t = t;
        let s = self.situation(t);
        let mut bytes = self.device.tick(&s);
        if self.faults.silent(self.ft(t)) || self.faults.offline(self.ft(t)) {
            bytes.clear();
        } else {
            self.garble(t, dt, &mut bytes);
        }
        Output { bytes, disconnect }
    }

    /// Bytes from the host at `t`: the device's answers, faults applied (a silent or
    /// disconnected device hears nothing).
    pub fn receive(&mut self, t: f64, data: &[u8]) -> Vec<u8> {
        if self.faults.silent(self.ft(t)) || self.faults.offline(self.ft(t)) {
            return Vec::new();
        }
        let s = self.situation(t);
        self.device.receive(&s, data)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fault::FaultPlan;
    use crate::truth::Still;

    /// A device that reports the time of every tick and echoes what it hears.
    struct Clock;
    impl Device for Clock {
        fn name(&self) -> &'static str {
            "clock"
        }
        fn period(&self) -> f64 {
            0.5
        }
        fn tick(&mut self, s: &Situation) -> Vec<u8> {
            format!("t={} leak={}\n", s.t, u8::from(s.leak)).into_bytes()
        }
        fn receive(&mut self, _: &Situation, data: &[u8]) -> Vec<u8> {
            data.to_vec()
        }
    }

    fn emu(faults: &[&str]) -> Emulator {
        Emulator::new(
            Box::new(Clock),
            Box::new(Still),
            FaultPlan::parse(faults).unwrap(),
            7,
            0.0,
        )
    }

    #[test]
    fn dropouts_silence_reports_and_answers_at_their_times() {
        let mut e = emu(&["dropout@1+1"]);
        assert_eq!(e.tick(0.5).bytes, b"t=0.5 leak=0\n");
        assert!(e.tick(1.0).bytes.is_empty());
        assert!(e.receive(1.5, b"hi").is_empty());
        assert_eq!(e.tick(2.0).bytes, b"t=2 leak=0\n");
        assert_eq!(e.receive(2.0, b"hi"), b"hi");
    }

    #[test]
    fn a_disconnect_is_signalled_once_and_the_device_is_off_for_its_duration() {
        let mut e = emu(&["disconnect@1+1", "leak@1.5"]);
        let flags: Vec<(bool, bool)> = [0.5, 1.0, 1.5, 2.0, 2.5]
            .iter()
            .map(|&t| {
                let o = e.tick(t);
                (o.disconnect, o.bytes.is_empty())
            })
            .collect();
        assert_eq!(
            flags,
            vec![
                (false, false),
                (true, true),
                (false, true),
                (false, false),
                (false, false)
            ]
        );
        assert_eq!(e.tick(3.0).bytes, b"t=3 leak=1\n");
    }

    #[test]
    fn garbage_comes_at_its_rate_and_is_the_same_for_the_same_seed() {
        let run = || {
            let mut e = emu(&["garbage@1+2:40"]);
            (0..8)
                .map(|k| e.tick(f64::from(k) * 0.5).bytes)
                .collect::<Vec<_>>()
        };
        let a = run();
        assert_eq!(a, run());
        let clean = |k: usize| format!("t={} leak=0\n", k as f64 * 0.5).len();
        let extra: Vec<usize> = a
            .iter()
            .enumerate()
            .map(|(k, b)| b.len() - clean(k))
            .collect();
        // 40 bytes a second over half-second ticks from 1 s to 3 s (the tick at 1 s garbles
        // the half second before it: the rate is taken at the tick's time).
        assert_eq!(extra, vec![0, 0, 20, 20, 20, 20, 0, 0]);
    }

    #[test]
    fn noise_bursts_move_the_truth_only_while_they_last() {
        let mut e = emu(&["noise@1+1:1"]);
        assert_eq!(e.situation(0.5).truth.x, 0.0);
        let noisy = e.situation(1.5).truth;
        assert!(noisy.x != 0.0 && noisy.y != 0.0 && noisy.heading_deg != 0.0);
        assert_eq!(e.situation(2.5).truth.x, 0.0);
    }
}
