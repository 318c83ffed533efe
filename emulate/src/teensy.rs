//! The Teensy 4.1 on its USB serial line (`cougars-vehicle.md` §3.1, §1.6): it prints
//! `$DEPTH,<Pa>,<°C>`, `$BATTE,<V>,<A>` and `$LEAK,<0|1>` (one decimal place, `\r\n`) each
//! at its rate (20 Hz each by default: the serial firmware prints all three every loop), and
//! reads `$CONTR,<fin0>,<fin1>,<fin2>,<thruster>` lines into its 50-byte buffer, accepting
//! only lines of four numeric fields.
//!
//! - Pressure: the MS5837 model of `vehicle::sensors::pressure` (atmosphere, water density,
//!   noise, quantum); temperature 15 °C plus 0.05 °C noise.
//! - Battery: `battery_v` (16.4 V) less the falling-battery fault, less 0.01 V per ampere;
//!   current `0.4 A + 0.12 A` per percent of thrust, plus 0.05 A noise.
//! - Leak: 0 until the leak fault starts.
//! - Commands ([`TeensyPort`], shared with whoever drives the emulator, e.g. the simulator):
//!   the last accepted command and its time, counts of accepted and refused lines, and the
//!   actuator outputs the firmware would drive: servo angles `trunc(fin) + 90` and the
//!   thruster pulse, held neutral for 7 s after power-up (ESC arming) and put back to
//!   neutral (fins centred, 1500 µs) when no command has come for 5 s (the failsafe).

use std::sync::{Arc, Mutex};

use devices::line::LineSplitter;
use devices::teensy::{self, Contr, Telemetry};
use vehicle::sensors::pressure::{PressureConfig, PressureSensor};
use vehicle::sensors::{Noise, Schedule};

use crate::device::{Device, Situation};

/// The Teensy's settings.
#[derive(Debug, Clone)]
pub struct TeensySettings {
    /// The pressure sensor model; its rate is the `$DEPTH` rate.
    pub pressure: PressureConfig,
    /// `$BATTE` rate, Hz (20).
    pub battery_hz: f64,
    /// `$LEAK` rate, Hz (20).
    pub leak_hz: f64,
    /// Battery voltage with no fault and no load, V (16.4).
    pub battery_v: f64,
    /// Water temperature, °C (15).
    pub temp_degc: f64,
}

impl Default for TeensySettings {
    fn default() -> Self {
        TeensySettings {
            pressure: PressureConfig::default(),
            battery_hz: 20.0,
            leak_hz: 20.0,
            battery_v: 16.4,
            temp_degc: 15.0,
        }
    }
}

/// What the Teensy has been told, and what it drives.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TeensyInputs {
    /// The last accepted `$CONTR` and its emulator time.
    pub last: Option<(f64, Contr)>,
    /// `$CONTR` lines accepted.
    pub accepted: u64,
    /// Lines refused (not four numeric fields, not `$CONTR`, longer than the buffer).
    pub refused: u64,
    /// Servo angles driven now, degrees (0–180, 90 centred).
    pub servo_deg: [u8; 3],
    /// Thruster pulse driven now, µs (1500 neutral).
    pub thruster_us: u16,
    /// True while the command-loss failsafe holds the actuators neutral.
    pub failsafe: bool,
}

/// The Teensy's inputs, shared between the emulator and its owner.
#[derive(Debug, Clone, Default)]
pub struct TeensyPort(Arc<Mutex<TeensyInputs>>);

impl TeensyPort {
    /// A snapshot of the inputs.
    pub fn get(&self) -> TeensyInputs {
        *self.0.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn update(&self, f: impl FnOnce(&mut TeensyInputs)) {
        f(&mut self.0.lock().unwrap_or_else(|e| e.into_inner()));
    }
}

/// The Teensy.
pub struct Teensy {
    settings: TeensySettings,
    pressure: PressureSensor,
    noise: Noise,
    battery: Schedule,
    leak: Schedule,
    lines: LineSplitter,
    port: TeensyPort,
}

impl Teensy {
    /// A Teensy with these settings, drawing from `seed`.
    pub fn new(settings: TeensySettings, seed: u64) -> Self {
        Teensy {
            pressure: PressureSensor::new(settings.pressure.clone(), seed),
            noise: Noise::new(seed, 0x7ee5),
            battery: Schedule::default(),
            leak: Schedule::default(),
            lines: LineSplitter::new(teensy::TEENSY_LINE_BUFFER),
            port: TeensyPort::default(),
            settings,
        }
    }

    /// The shared view of its inputs.
    pub fn port(&self) -> TeensyPort {
        self.port.clone()
    }

    /// The actuators the firmware drives at `t`.
    fn drive(&self, t: f64) {
        self.port.update(|p| {
            let cmd = match p.last {
                Some((at, c)) if (t - at) * 1000.0 < teensy::FAILSAFE_TIMEOUT_MS as f64 => {
                    p.failsafe = false;
                    c
                }
                Some(_) => {
                    p.failsafe = true;
                    Contr::NEUTRAL
                }
                None => Contr::NEUTRAL,
            };
            p.servo_deg = cmd.servo_angles_deg();
            p.thruster_us = if t * 1000.0 < teensy::ARM_DELAY_MS as f64 {
                teensy::NEUTRAL_US
            } else {
                cmd.thruster_pulse_us()
            };
        });
    }
}

impl Device for Teensy {
    fn name(&self) -> &'static str {
        "teensy"
    }

    fn period(&self) -> f64 {
        let fastest = self
            .settings
            .pressure
            .rate_hz
            .max(self.settings.battery_hz)
            .max(self.settings.leak_hz);
        (1.0 / fastest.max(1.0)).min(0.05)
    }

    fn connected(&mut self, _: &Situation) -> Vec<u8> {
        self.lines.reset();
        Vec::new()
    }

    fn tick(&mut self, s: &Situation) -> Vec<u8> {
        self.drive(s.t);
        let mut out = String::new();
        if let Some(p) = self.pressure.sample(&s.truth) {
            out.push_str(
                &Telemetry::Depth {
                    pressure_pa: p.pressure_pa,
                    temp_degc: self.settings.temp_degc + self.noise.gauss(0.05),
                }
                .encode(),
            );
        }
        if self.battery.due(s.t) {
            self.battery
                .done(s.t, 1.0 / self.settings.battery_hz.max(0.01));
            let thrust = self
                .port
                .get()
                .last
                .map_or(0.0, |(_, c)| f64::from(c.thrust_pct.unsigned_abs()));
            let current = 0.4 + 0.12 * thrust + self.noise.gauss(0.05);
            let voltage = (self.settings.battery_v - s.battery_drop_v - 0.01 * current).max(0.0);
            out.push_str(
                &Telemetry::Battery {
                    voltage_v: voltage,
                    current_a: current,
                }
                .encode(),
            );
        }
        if self.leak.due(s.t) {
            self.leak.done(s.t, 1.0 / self.settings.leak_hz.max(0.01));
            out.push_str(&Telemetry::Leak { leak: s.leak }.encode());
        }
        out.into_bytes()
    }

    fn receive(&mut self, s: &Situation, data: &[u8]) -> Vec<u8> {
        let before = self.lines.stats().oversize;
        let mut got = Vec::new();
        self.lines.push(data, |l| got.push(Contr::parse(l)));
        let oversize = self.lines.stats().oversize - before;
        self.port.update(|p| {
            p.refused += oversize;
            for c in got {
                match c {
                    Ok(c) => {
                        p.accepted += 1;
                        p.last = Some((s.t, c));
                    }
                    Err(_) => p.refused += 1,
                }
            }
        });
        self.drive(s.t);
        Vec::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::truth::Truth;

    fn at(t: f64, depth: f64, leak: bool, drop: f64) -> Situation {
        Situation {
            t,
            unix_s: t,
            truth: Truth {
                time: t,
                depth,
                ..Truth::default()
            },
            leak,
            battery_drop_v: drop,
        }
    }

    fn telemetry(bytes: &[u8]) -> Vec<Telemetry> {
        let mut out = Vec::new();
        let mut s = LineSplitter::new(teensy::MAX_LINE).with_starts(b"$");
        s.push(bytes, |l| out.push(Telemetry::parse(l).unwrap()));
        assert_eq!(s.stats().garbage_bytes, 0);
        out
    }

    #[test]
    fn telemetry_lines_carry_depth_battery_and_leak_at_their_rates() {
        let mut set = TeensySettings::default();
        set.pressure.noise_pa = 0.0;
        set.battery_hz = 5.0;
        let mut t = Teensy::new(set, 2);
        let mut all = Vec::new();
        for k in 0..40 {
            let leak = k >= 30;
            all.extend(telemetry(&t.tick(&at(f64::from(k) * 0.05, 2.0, leak, 0.5))));
        }
        let depths: Vec<f64> = all
            .iter()
            .filter_map(|m| match m {
                Telemetry::Depth { pressure_pa, .. } => Some(*pressure_pa),
                _ => None,
            })
            .collect();
        assert_eq!(depths.len(), 40);
        // 101325 + 997 * 9.81 * 2 = 120886.14, quantised to 10 Pa.
        assert!(depths.iter().all(|p| *p == 120890.0), "{depths:?}");
        let volts: Vec<f64> = all
            .iter()
            .filter_map(|m| match m {
                Telemetry::Battery { voltage_v, .. } => Some(*voltage_v),
                _ => None,
            })
            .collect();
        assert_eq!(volts.len(), 10, "5 Hz over 2 s");
        assert!(volts.iter().all(|v| *v == 15.9), "{volts:?}");
        let leaks: Vec<bool> = all
            .iter()
            .filter_map(|m| match m {
                Telemetry::Leak { leak } => Some(*leak),
                _ => None,
            })
            .collect();
        assert_eq!(leaks.len(), 40);
        assert_eq!(leaks.iter().filter(|l| **l).count(), 10);
        assert!(leaks[29..].iter().skip(1).all(|l| *l) && !leaks[29]);
    }

    #[test]
    fn contr_lines_are_recorded_and_drive_the_actuators_with_arming_and_failsafe() {
        let mut t = Teensy::new(TeensySettings::default(), 2);
        let port = t.port();
        t.receive(
            &at(1.0, 0.0, false, 0.0),
            b"$CONTR,10.7,-5,0,50\n$CONTR,1,2\n",
        );
        let p = port.get();
        assert_eq!((p.accepted, p.refused), (1, 1));
        assert_eq!(p.last.unwrap().1.fins_deg, [10.7, -5.0, 0.0]);
        assert_eq!(p.servo_deg, [100, 85, 90]);
        assert_eq!(p.thruster_us, 1500, "still arming");
        // Partial lines join; an over-long line is refused.
        t.receive(&at(8.0, 0.0, false, 0.0), b"$CONTR,0,0,0,");
        t.receive(&at(8.0, 0.0, false, 0.0), b"-100\r\n");
        t.receive(
            &at(8.0, 0.0, false, 0.0),
            format!("$CONTR,{}\n", "1".repeat(60)).as_bytes(),
        );
        let p = port.get();
        assert_eq!((p.accepted, p.refused), (2, 2));
        assert_eq!((p.thruster_us, p.failsafe), (1100, false));
        // Five seconds without a command: the failsafe.
        t.tick(&at(12.9, 0.0, false, 0.0));
        assert!(!port.get().failsafe);
        t.tick(&at(13.0, 0.0, false, 0.0));
        let p = port.get();
        assert!(p.failsafe);
        assert_eq!((p.servo_deg, p.thruster_us), ([90; 3], 1500));
    }
}
