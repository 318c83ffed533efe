//! The Teensy 4.1's ASCII serial link (`cougars-vehicle.md` §3.1, §1.5, §1.6, §2.1): the
//! actuator command `$CONTR,<fin0>,<fin1>,<fin2>,<thruster>\n` to the Teensy, and its
//! telemetry `$DEPTH,<Pa>,<°C>`, `$BATTE,<V>,<A>`, `$LEAK,<0|1>` (each ending `\r\n`) back;
//! the fin mixing with per-vehicle directions, offsets and trim; the firmware's servo and
//! thruster pulse mapping (for the emulator); and pressure to depth with the water density
//! and an atmospheric offset calibrated at the surface.

use std::fmt::Write as _;

use crate::line::ProtocolError;

/// The Teensy's line buffer: a `$CONTR` line must fit in it.
pub const TEENSY_LINE_BUFFER: usize = 50;

/// The longest telemetry line accepted from the Teensy.
pub const MAX_LINE: usize = 64;

/// The firmware's failsafe: with no command for this long, fins centre and thrust stops.
pub const FAILSAFE_TIMEOUT_MS: u64 = 5000;

/// The firmware holds the thruster at neutral this long after boot (ESC arming).
pub const ARM_DELAY_MS: u64 = 7000;

/// Thruster neutral pulse, µs.
pub const NEUTRAL_US: u16 = 1500;

/// Standard gravity used by the CoUGARs depth conversion, m/s².
pub const G_MPS2: f64 = 9.81;

/// Why a line was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TeensyError {
    /// Not one of `$CONTR`, `$DEPTH`, `$BATTE`, `$LEAK`.
    #[error("unknown sentence")]
    Unknown,
    /// The wrong number of fields for the sentence.
    #[error("{kind}: {found} fields, {needed} expected")]
    FieldCount {
        /// The sentence.
        kind: &'static str,
        /// Fields present.
        found: usize,
        /// Fields expected.
        needed: usize,
    },
    /// A field that is not a finite number (or not 0/1 for the leak).
    #[error("{kind}: bad field {index}")]
    BadField {
        /// The sentence.
        kind: &'static str,
        /// The field's index (1-based).
        index: usize,
    },
}

impl ProtocolError for TeensyError {
    fn is_checksum(&self) -> bool {
        false
    }
}

/// One actuator command: three fin angles and a thruster percentage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contr {
    /// Fin angles (top, starboard, port), degrees from the servo centre.
    pub fins_deg: [f64; 3],
    /// Thruster, percent from −100 to 100.
    pub thrust_pct: i32,
}

impl Contr {
    /// All fins centred, thruster stopped (what the failsafe does).
    pub const NEUTRAL: Contr = Contr {
        fins_deg: [0.0; 3],
        thrust_pct: 0,
    };

    /// The line sent to the Teensy: fins clamped to the servo range (±90°, a non-finite fin
    /// centred) in a C++ stream's default format (6 significant digits), the thruster
    /// clamped to ±100, and `\n`. At most [`TEENSY_LINE_BUFFER`] bytes.
    pub fn encode(&self) -> String {
        let mut s = String::with_capacity(40);
        s.push_str("$CONTR");
        for f in self.fins_deg {
            s.push(',');
            let f = if f.is_finite() {
                f.clamp(-90.0, 90.0)
            } else {
                0.0
            };
            moos_types::fmt::g(&mut s, f, 6);
        }
        let _ = writeln!(s, ",{}", self.thrust_pct.clamp(-100, 100));
        s
    }

    /// Parses a `$CONTR` line as the firmware accepts it: exactly four numeric fields.
    pub fn parse(line: &[u8]) -> Result<Contr, TeensyError> {
        let f = fields(line, "$CONTR", "CONTR", 4)?;
        let mut fins_deg = [0.0; 3];
        for (k, v) in fins_deg.iter_mut().enumerate() {
            *v = num("CONTR", &f, k)?;
        }
        let t = num("CONTR", &f, 3)?;
        if t.fract() != 0.0 || !(-1000.0..=1000.0).contains(&t) {
            return Err(TeensyError::BadField {
                kind: "CONTR",
                index: 4,
            });
        }
        Ok(Contr {
            fins_deg,
            thrust_pct: t as i32,
        })
    }

    /// What the serial firmware writes to the servos: `trunc(fin) + 90`, within 0–180.
    pub fn servo_angles_deg(&self) -> [u8; 3] {
        self.fins_deg.map(|f| {
            let f = if f.is_finite() { f.trunc() } else { 0.0 };
            (f + 90.0).clamp(0.0, 180.0) as u8
        })
    }

    /// The thruster pulse of the serial firmware: −100..100 % mapped onto 1100..1900 µs
    /// (integer map, neutral 1500).
    pub fn thruster_pulse_us(&self) -> u16 {
        let t = i64::from(self.thrust_pct.clamp(-100, 100));
        ((t + 100) * (1900 - 1100) / 200 + 1100) as u16
    }
}

/// The servo pulse for a servo angle (0–180°) on a servo with the given pulse range (COUG1
/// 500–2500 µs, COUG2 1000–2000 µs), as the Arduino Servo library maps it.
pub fn servo_pulse_us(angle_deg: u8, min_us: u16, max_us: u16) -> u16 {
    let a = i64::from(angle_deg.min(180));
    let (lo, hi) = (i64::from(min_us), i64::from(max_us));
    (a * (hi - lo) / 180 + lo) as u16
}

/// The per-vehicle fin mixing (`coug_kinematics`): `out[i] = dir[i]·in[i] + offset[i] +
/// trim_ratio·thrust`, then clamped to `fin_limit_deg`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FinMixing {
    /// Direction of each fin, ±1.
    pub dir: [f64; 3],
    /// Offset (trim) of each fin, degrees.
    pub offset_deg: [f64; 3],
    /// Fin trim per percent of thrust, degrees.
    pub trim_ratio_deg_per_pct: f64,
    /// The largest fin angle sent, degrees.
    pub fin_limit_deg: f64,
}

impl FinMixing {
    /// COUG1: top offset −10°, directions (1, −1, −1).
    pub const COUG1: FinMixing = FinMixing {
        dir: [1.0, -1.0, -1.0],
        offset_deg: [-10.0, 0.0, 0.0],
        trim_ratio_deg_per_pct: 0.0,
        fin_limit_deg: 90.0,
    };
    /// COUG2: right offset −20°, left +45°, directions (1, 1, 1).
    pub const COUG2: FinMixing = FinMixing {
        dir: [1.0, 1.0, 1.0],
        offset_deg: [0.0, -20.0, 45.0],
        trim_ratio_deg_per_pct: 0.0,
        fin_limit_deg: 90.0,
    };

    /// The command for controller fins (top, starboard, port) and a thrust.
    pub fn mix(&self, fins_deg: [f64; 3], thrust_pct: i32) -> Contr {
        let t = f64::from(thrust_pct.clamp(-100, 100));
        let lim = self.fin_limit_deg.abs();
        let mut out = [0.0; 3];
        for i in 0..3 {
            let v =
                self.dir[i] * fins_deg[i] + self.offset_deg[i] + self.trim_ratio_deg_per_pct * t;
            out[i] = if v.is_finite() {
                v.clamp(-lim, lim)
            } else {
                0.0
            };
        }
        Contr {
            fins_deg: out,
            thrust_pct: thrust_pct.clamp(-100, 100),
        }
    }
}

/// One telemetry line from the Teensy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Telemetry {
    /// `$DEPTH`: the pressure sensor.
    Depth {
        /// Absolute pressure, pascals.
        pressure_pa: f64,
        /// Water temperature, °C.
        temp_degc: f64,
    },
    /// `$BATTE`: the battery monitor.
    Battery {
        /// Voltage, volts.
        voltage_v: f64,
        /// Current, amperes.
        current_a: f64,
    },
    /// `$LEAK`: the leak sensor.
    Leak {
        /// Water detected.
        leak: bool,
    },
}

fn fields<'a>(
    line: &'a [u8],
    tag: &str,
    kind: &'static str,
    needed: usize,
) -> Result<Vec<&'a str>, TeensyError> {
    let line = line.strip_suffix(b"\n").unwrap_or(line);
    let line = line.strip_suffix(b"\r").unwrap_or(line);
    let s = std::str::from_utf8(line).map_err(|_| TeensyError::Unknown)?;
    let mut it = s.split(',');
    if it.next() != Some(tag) {
        return Err(TeensyError::Unknown);
    }
    let f: Vec<&str> = it.collect();
    if f.len() != needed {
        return Err(TeensyError::FieldCount {
            kind,
            found: f.len(),
            needed,
        });
    }
    Ok(f)
}

fn num(kind: &'static str, f: &[&str], k: usize) -> Result<f64, TeensyError> {
    let s = f[k].trim();
    let plain = !s.is_empty()
        && s.bytes()
            .all(|b| b.is_ascii_digit() || matches!(b, b'.' | b'-' | b'+' | b'e' | b'E'));
    match s.parse::<f64>() {
        Ok(v) if plain && v.is_finite() => Ok(v),
        _ => Err(TeensyError::BadField { kind, index: k + 1 }),
    }
}

impl Telemetry {
    /// Parses one telemetry line (a trailing `\r\n` is allowed).
    pub fn parse(line: &[u8]) -> Result<Telemetry, TeensyError> {
        let tag_end = line.iter().position(|&b| b == b',').unwrap_or(line.len());
        match &line[..tag_end] {
            b"$DEPTH" => {
                let f = fields(line, "$DEPTH", "DEPTH", 2)?;
                Ok(Telemetry::Depth {
                    pressure_pa: num("DEPTH", &f, 0)?,
                    temp_degc: num("DEPTH", &f, 1)?,
                })
            }
            b"$BATTE" => {
                let f = fields(line, "$BATTE", "BATTE", 2)?;
                Ok(Telemetry::Battery {
                    voltage_v: num("BATTE", &f, 0)?,
                    current_a: num("BATTE", &f, 1)?,
                })
            }
            b"$LEAK" => {
                let f = fields(line, "$LEAK", "LEAK", 1)?;
                match f[0].trim() {
                    "0" => Ok(Telemetry::Leak { leak: false }),
                    "1" => Ok(Telemetry::Leak { leak: true }),
                    _ => Err(TeensyError::BadField {
                        kind: "LEAK",
                        index: 1,
                    }),
                }
            }
            _ => Err(TeensyError::Unknown),
        }
    }

    /// The line as the firmware prints it: one decimal place, `\r\n`.
    pub fn encode(&self) -> String {
        let one = |v: f64| if v.is_finite() { v } else { 0.0 };
        match *self {
            Telemetry::Depth {
                pressure_pa,
                temp_degc,
            } => format!("$DEPTH,{:.1},{:.1}\r\n", one(pressure_pa), one(temp_degc)),
            Telemetry::Battery {
                voltage_v,
                current_a,
            } => format!("$BATTE,{:.1},{:.1}\r\n", one(voltage_v), one(current_a)),
            Telemetry::Leak { leak } => format!("$LEAK,{}\r\n", u8::from(leak)),
        }
    }
}

/// Water density from salinity, as the CoUGARs depth converter computes it:
/// `997 + 0.8·salinity` kg/m³ (0 ppt fresh, 35 ppt sea).
pub fn water_density_kgm3(salinity_ppt: f64) -> f64 {
    997.0 + 0.8 * salinity_ppt
}

/// Pressure to depth: `(p − p_atm) / (ρ·g)`, metres, positive down. (The CoUGARs converter
/// publishes the negative of this, an ENU z.)
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthConverter {
    /// Atmospheric pressure at the surface, pascals.
    pub atmospheric_pa: f64,
    /// Water density, kg/m³.
    pub density_kgm3: f64,
}

impl DepthConverter {
    /// The CoUGARs default: 87250 Pa (Utah altitude), fresh water.
    pub const DEFAULT: DepthConverter = DepthConverter {
        atmospheric_pa: 87250.0,
        density_kgm3: 997.0,
    };

    /// Depth for an absolute pressure, metres, positive down.
    pub fn depth_m(&self, pressure_pa: f64) -> f64 {
        (pressure_pa - self.atmospheric_pa) / (self.density_kgm3 * G_MPS2)
    }

    /// The absolute pressure at a depth (the emulator's side).
    pub fn pressure_pa(&self, depth_m: f64) -> f64 {
        self.atmospheric_pa + depth_m * self.density_kgm3 * G_MPS2
    }
}

/// The atmospheric calibration: the mean of the pressures seen while the vehicle is at the
/// surface (the caller must only feed surface readings: calibrating under water would
/// zero the depth there). It succeeds with at least `min_samples` readings (20 in CoUGARs).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AtmosphericCalibration {
    sum_pa: f64,
    count: u32,
}

impl AtmosphericCalibration {
    /// Adds a surface reading (non-finite readings are ignored).
    pub fn add(&mut self, pressure_pa: f64) {
        if pressure_pa.is_finite() {
            self.sum_pa += pressure_pa;
            self.count += 1;
        }
    }

    /// Readings so far.
    pub fn count(&self) -> u32 {
        self.count
    }

    /// The mean pressure when at least `min_samples` (and one) readings arrived; `None`
    /// otherwise (keep the previous value, as CoUGARs does).
    pub fn finish(&self, min_samples: u32) -> Option<f64> {
        (self.count >= min_samples.max(1)).then(|| self.sum_pa / f64::from(self.count))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn contr_lines_match_the_firmware_format_and_fit_its_buffer() {
        let c = Contr {
            fins_deg: [12.5, -3.0, 1.0 / 3.0],
            thrust_pct: 30,
        };
        assert_eq!(c.encode(), "$CONTR,12.5,-3,0.333333,30\n");
        let worst = Contr {
            fins_deg: [-89.123456; 3],
            thrust_pct: -100,
        };
        assert!(worst.encode().len() <= TEENSY_LINE_BUFFER);
        let wild = Contr {
            fins_deg: [400.0, f64::NAN, -1e9],
            thrust_pct: 250,
        };
        assert_eq!(wild.encode(), "$CONTR,90,0,-90,100\n");
        assert_eq!(
            Contr::parse(b"$CONTR,12.5,-3,0.333333,30\n")
                .unwrap()
                .thrust_pct,
            30
        );
        assert!(matches!(
            Contr::parse(b"$CONTR,1,2,3"),
            Err(TeensyError::FieldCount { found: 3, .. })
        ));
    }

    #[test]
    fn servo_and_thruster_pulses_follow_the_serial_firmware() {
        let c = Contr {
            fins_deg: [-10.7, 0.0, 95.0],
            thrust_pct: 100,
        };
        assert_eq!(c.servo_angles_deg(), [80, 90, 180]);
        assert_eq!(c.thruster_pulse_us(), 1900);
        assert_eq!(Contr::NEUTRAL.thruster_pulse_us(), NEUTRAL_US);
        assert_eq!(
            Contr {
                thrust_pct: -100,
                ..Contr::NEUTRAL
            }
            .thruster_pulse_us(),
            1100
        );
        assert_eq!(servo_pulse_us(90, 500, 2500), 1500);
        assert_eq!(servo_pulse_us(180, 1000, 2000), 2000);
    }

    #[test]
    fn mixing_applies_directions_offsets_and_limits() {
        // COUG1 with the controller's rudder 5, pitch fin 8 (fin1 = −8, fin2 = +8).
        let c = FinMixing::COUG1.mix([5.0, -8.0, 8.0], 40);
        assert_eq!(c.fins_deg, [-5.0, 8.0, -8.0]);
        let c = FinMixing::COUG2.mix([0.0, 0.0, 60.0], 150);
        assert_eq!((c.fins_deg, c.thrust_pct), ([0.0, -20.0, 90.0], 100));
        let trimmed = FinMixing {
            trim_ratio_deg_per_pct: 0.1,
            ..FinMixing::COUG2
        };
        assert_eq!(trimmed.mix([0.0; 3], 50).fins_deg, [5.0, -15.0, 50.0]);
    }

    #[test]
    fn telemetry_as_the_firmware_prints_it() {
        // A Teensy at 1.5 m in fresh water at Utah's surface pressure.
        let lines = b"$DEPTH,101919.6,14.2\r\n$BATTE,16.4,2.3\r\n$LEAK,0\r\n";
        let mut got = Vec::new();
        let mut s = crate::line::LineSplitter::new(MAX_LINE).with_starts(b"$");
        s.push(lines, |l| got.push(Telemetry::parse(l).unwrap()));
        assert_eq!(
            got,
            vec![
                Telemetry::Depth {
                    pressure_pa: 101919.6,
                    temp_degc: 14.2
                },
                Telemetry::Battery {
                    voltage_v: 16.4,
                    current_a: 2.3
                },
                Telemetry::Leak { leak: false }
            ]
        );
        let text: String = got.iter().map(Telemetry::encode).collect();
        assert_eq!(text.as_bytes(), lines);
        assert_eq!(
            Telemetry::parse(b"$LEAK,2"),
            Err(TeensyError::BadField {
                kind: "LEAK",
                index: 1
            })
        );
        assert_eq!(
            Telemetry::parse(b"$DEPTH,nan,1"),
            Err(TeensyError::BadField {
                kind: "DEPTH",
                index: 1
            })
        );
        assert_eq!(Telemetry::parse(b"$FOO,1"), Err(TeensyError::Unknown));
    }

    #[test]
    fn pressure_to_depth_and_the_surface_calibration() {
        let d = DepthConverter {
            atmospheric_pa: 84246.0,
            density_kgm3: water_density_kgm3(0.0),
        };
        assert!((d.depth_m(84246.0 + 997.0 * 9.81 * 2.0) - 2.0).abs() < 1e-12);
        assert!((d.depth_m(d.pressure_pa(3.25)) - 3.25).abs() < 1e-12);
        assert_eq!(water_density_kgm3(35.0), 1025.0);
        let mut cal = AtmosphericCalibration::default();
        for k in 0..19 {
            cal.add(84000.0 + f64::from(k));
        }
        cal.add(f64::NAN);
        assert_eq!(cal.finish(20), None);
        cal.add(84019.0);
        assert_eq!(cal.finish(20), Some(84009.5));
    }

    proptest! {
        #[test]
        fn arbitrary_bytes_never_panic(data in proptest::collection::vec(any::<u8>(), 0..80)) {
            let _ = Telemetry::parse(&data);
            let _ = Contr::parse(&data);
        }

        #[test]
        fn encode_decode_is_identity_on_the_wire(
            p in 0.0f64..1e7, t in -5.0f64..50.0, v in 0.0f64..30.0, a in -20.0f64..20.0,
            leak in any::<bool>(), fins in [-90.0f64..90.0, -90.0f64..90.0, -90.0f64..90.0],
            thrust in -100i32..=100,
        ) {
            for m in [Telemetry::Depth { pressure_pa: p, temp_degc: t },
                      Telemetry::Battery { voltage_v: v, current_a: a }, Telemetry::Leak { leak }] {
                let line = m.encode();
                let back = Telemetry::parse(line.as_bytes()).unwrap();
                prop_assert_eq!(back.encode(), line);
            }
            let c = Contr { fins_deg: fins, thrust_pct: thrust };
            let line = c.encode();
            prop_assert!(line.len() <= TEENSY_LINE_BUFFER);
            let back = Contr::parse(line.as_bytes()).unwrap();
            prop_assert_eq!(back.encode(), line);
            prop_assert_eq!(back.thrust_pct, thrust);
            for (b, f) in back.fins_deg.iter().zip(fins) { prop_assert!((b - f).abs() <= 1e-4 * f.abs().max(1.0)); }
        }
    }
}
