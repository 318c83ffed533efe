//! `iTeensy`: the Teensy 4.1's ASCII serial link (`cougars-vehicle.md` §3.1): `$CONTR` out,
//! `$DEPTH`, `$BATTE` and `$LEAK` in.
//!
//! # Variables
//!
//! Read (the names pCougControls posts, `vehicle::cougars::vars`):
//!
//! | variable | unit | meaning |
//! |---|---|---|
//! | `FIN_TOP_DEG`, `FIN_STBD_DEG`, `FIN_PORT_DEG` | deg | the mixed fin angles in the servo frame (top, starboard, port), sent as they are |
//! | `THRUST_PCT` | % | thruster, −100..100, rounded to an integer |
//! | `DEPLOY` | bool | the mission is under way: the atmospheric calibration stops (the vehicle may leave the surface) |
//! | `TEENSY_CALIBRATE` | any | run the atmospheric calibration again (refused while deployed) |
//!
//! A `$CONTR,<fin0>,<fin1>,<fin2>,<thrust>` line goes out in the iteration after any of the
//! four commands changed, and again every `command_period` (so the firmware's 5 s failsafe
//! trips only when MOOS is gone) and at each reconnection; nothing goes out before the first
//! command arrives. A fin not yet posted is 0.
//!
//! Posted (each line as it arrives, at the iteration's time):
//!
//! | variable | type | unit | meaning |
//! |---|---|---|---|
//! | `PRESSURE` | double | Pa | absolute (atmosphere included), as uSimSensors posts it |
//! | `DEPTH` | double | m | `(P − P_atm) / (ρ g)`, positive down; only once the atmospheric calibration is done (or has fallen back to `atmospheric_pressure`) |
//! | `PRESSURE_TEMP` | double | °C | the MS5837's temperature |
//! | `BATTERY_VOLTAGE` | double | V | |
//! | `BATTERY_CURRENT` | double | A | |
//! | `LEAK` | double | 1/0 | the leak sensor |
//! | `TEENSY_ATM_PRESSURE` | double | Pa | the atmospheric pressure in force, at each calibration's end |
//!
//! The atmospheric calibration (as the Gen-1 depth converter, §2.1) starts at the first
//! connection: it averages the `$DEPTH` pressures and succeeds with `calibration_samples`
//! (20) of them, or fails after `calibration_timeout` (5 s) and keeps `atmospheric_pressure`.
//! Because a calibration under water would make every depth wrong by the depth it was taken
//! at (the reference's warning), samples are taken only while `DEPLOY` is not true and the
//! pressure is below `calibration_max_pressure` (110 kPa: about 1 m of water at sea level);
//! `DEPLOY = true` ends a calibration in progress, which then keeps the pressure in force.
//!
//! # Parameters
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `device`, `baud` | `/dev/frost/teensy`, 115200 | the serial link |
//! | `salinity` | 0 | ppt, for the water density `997 + 0.8 S` |
//! | `density` | (from salinity) | kg/m³, overrides it |
//! | `atmospheric_pressure` | 87250 | Pa, the fallback (the CoUGARs default, Utah Lake's altitude) |
//! | `calibration_samples`, `calibration_timeout`, `calibration_max_pressure` | 20, 5, 110000 | |
//! | `command_period` | 0.5 | s, between repeats of the last `$CONTR` |

use std::fmt::Write as _;

use devices::line::{LineSplitter, LinkStats};
use devices::teensy::{Contr, DepthConverter, MAX_LINE, Telemetry, water_density_kgm3};
use moos_types::Value;
use vehicle::ConfigError;
use vehicle::cougars::vars;

use crate::link::LinkConfig;
use crate::params::{self, Common};
use crate::{Io, Protocol, g};

/// The program name.
pub const PROGRAM: &str = "iTeensy";

/// `iTeensy`'s settings.
#[derive(Debug, Clone, PartialEq)]
pub struct TeensyConfig {
    /// Salinity, ppt.
    pub salinity_ppt: f64,
    /// Water density override, kg/m³.
    pub density_kgm3: Option<f64>,
    /// Fallback atmospheric pressure, Pa.
    pub atmospheric_pa: f64,
    /// Samples for a calibration.
    pub calibration_samples: u32,
    /// Seconds a calibration may take.
    pub calibration_timeout_s: f64,
    /// Pressure above which a sample is not the atmosphere, Pa.
    pub calibration_max_pa: f64,
    /// Seconds between repeats of the last command.
    pub command_period_s: f64,
}

impl Default for TeensyConfig {
    fn default() -> Self {
        TeensyConfig {
            salinity_ppt: 0.0,
            density_kgm3: None,
            atmospheric_pa: DepthConverter::DEFAULT.atmospheric_pa,
            calibration_samples: 20,
            calibration_timeout_s: 5.0,
            calibration_max_pa: 110_000.0,
            command_period_s: 0.5,
        }
    }
}

impl TeensyConfig {
    /// Reads a block's parameters: the settings, the link and the problems found.
    pub fn from_params<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> (TeensyConfig, Common, LinkConfig, Vec<ConfigError>) {
        let mut c = TeensyConfig::default();
        let (common, problems) = params::read(PROGRAM, params, |p, k| {
            Some(match k {
                "salinity" => p.non_neg().map(|v| c.salinity_ppt = v),
                "density" => p.pos().map(|v| c.density_kgm3 = Some(v)),
                "atmospheric_pressure" => p.pos().map(|v| c.atmospheric_pa = v),
                "calibration_samples" => p
                    .int(1, 100_000, "a count from 1")
                    .map(|v| c.calibration_samples = v as u32),
                "calibration_timeout" => p.pos().map(|v| c.calibration_timeout_s = v),
                "calibration_max_pressure" => p.pos().map(|v| c.calibration_max_pa = v),
                "command_period" => p.pos().map(|v| c.command_period_s = v),
                _ => return None,
            })
        });
        let link = common.serial_link("/dev/frost/teensy", 115_200);
        (c, common, link, problems)
    }
}

/// The atmospheric calibration's state.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Calibration {
    /// Not started (no connection yet).
    Idle,
    /// Collecting since `start`.
    Running { start: f64, sum: f64, n: u32 },
    /// Over: the pressure in force.
    Done,
}

/// Counts of what came in.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TeensyCounts {
    /// `$DEPTH` lines.
    pub depth: u64,
    /// `$BATTE` lines.
    pub battery: u64,
    /// `$LEAK` lines.
    pub leak: u64,
    /// `$CONTR` lines sent.
    pub commands: u64,
    /// Calibrations that succeeded.
    pub calibrations: u64,
    /// Calibrations that fell back or were cut.
    pub calibration_failures: u64,
}

/// The `iTeensy` protocol.
pub struct Teensy {
    cfg: TeensyConfig,
    lines: LineSplitter,
    conv: DepthConverter,
    cal: Calibration,
    deployed: bool,
    fins: [f64; 3],
    thrust: i32,
    have_command: bool,
    dirty: bool,
    last_sent: Option<f64>,
    counts: TeensyCounts,
    last: (Option<f64>, Option<f64>, Option<bool>, Option<f64>),
    pending_calibration: bool,
}

impl Teensy {
    /// A protocol with `cfg`.
    pub fn new(cfg: TeensyConfig) -> Self {
        let density = cfg
            .density_kgm3
            .unwrap_or_else(|| water_density_kgm3(cfg.salinity_ppt));
        Teensy {
            conv: DepthConverter {
                atmospheric_pa: cfg.atmospheric_pa,
                density_kgm3: density,
            },
            cfg,
            lines: LineSplitter::new(MAX_LINE).with_starts(b"$"),
            cal: Calibration::Idle,
            deployed: false,
            fins: [0.0; 3],
            thrust: 0,
            have_command: false,
            dirty: false,
            last_sent: None,
            counts: TeensyCounts::default(),
            last: (None, None, None, None),
            pending_calibration: false,
        }
    }

    /// The counts so far.
    pub fn counts(&self) -> TeensyCounts {
        self.counts
    }

    /// The pressure-to-depth law in force.
    pub fn converter(&self) -> DepthConverter {
        self.conv
    }

    /// True while the atmospheric calibration runs.
    pub fn calibrating(&self) -> bool {
        matches!(self.cal, Calibration::Running { .. })
    }

    fn start_calibration(&mut self, now: f64, io: &mut Io) {
        if self.deployed {
            io.warnings.push(
                "atmospheric calibration refused: deployed (it needs the vehicle at the surface)"
                    .into(),
            );
            return;
        }
        self.cal = Calibration::Running {
            start: now,
            sum: 0.0,
            n: 0,
        };
        io.events.push("atmospheric calibration started".into());
    }

    fn end_calibration(&mut self, ok: Option<f64>, why: &str, io: &mut Io) {
        match ok {
            Some(p) => {
                self.conv.atmospheric_pa = p;
                self.counts.calibrations += 1;
                io.events
                    .push(format!("atmospheric calibration: {} Pa", g(p)));
            }
            None => {
                self.counts.calibration_failures += 1;
                io.warnings.push(format!(
                    "atmospheric calibration failed ({why}); keeping {} Pa",
                    g(self.conv.atmospheric_pa)
                ));
            }
        }
        self.cal = Calibration::Done;
        io.double("TEENSY_ATM_PRESSURE", self.conv.atmospheric_pa);
    }

    fn line(&mut self, line: &[u8], now: f64, io: &mut Io) {
        let r = Telemetry::parse(line);
        self.lines.stats_mut().record(&r);
        let Ok(t) = r else { return };
        match t {
            Telemetry::Depth {
                pressure_pa,
                temp_degc,
            } => {
                self.counts.depth += 1;
                io.double("PRESSURE", pressure_pa);
                io.double("PRESSURE_TEMP", temp_degc);
                if let Calibration::Running { sum, n, .. } = &mut self.cal
                    && !self.deployed
                    && pressure_pa < self.cfg.calibration_max_pa
                {
                    *sum += pressure_pa;
                    *n += 1;
                    if *n >= self.cfg.calibration_samples {
                        let mean = *sum / f64::from(*n);
                        self.end_calibration(Some(mean), "", io);
                    }
                }
                if self.cal == Calibration::Done {
                    let d = self.conv.depth_m(pressure_pa);
                    io.double("DEPTH", d);
                    self.last.3 = Some(d);
                }
                self.last.0 = Some(pressure_pa);
            }
            Telemetry::Battery {
                voltage_v,
                current_a,
            } => {
                self.counts.battery += 1;
                io.double("BATTERY_VOLTAGE", voltage_v);
                io.double("BATTERY_CURRENT", current_a);
                self.last.1 = Some(voltage_v);
            }
            Telemetry::Leak { leak } => {
                self.counts.leak += 1;
                io.double("LEAK", if leak { 1.0 } else { 0.0 });
                self.last.2 = Some(leak);
            }
        }
        let _ = now;
    }
}

impl Protocol for Teensy {
    fn program(&self) -> &'static str {
        PROGRAM
    }

    fn status_var(&self) -> &'static str {
        "TEENSY_DRIVER_STATUS"
    }

    fn subscriptions(&self) -> Vec<String> {
        [
            vars::FIN_TOP_DEG,
            vars::FIN_STBD_DEG,
            vars::FIN_PORT_DEG,
            vars::THRUST_PCT,
            "DEPLOY",
            "TEENSY_CALIBRATE",
        ]
        .map(String::from)
        .to_vec()
    }

    fn on_connect(&mut self, now: f64, io: &mut Io) {
        self.lines.reset();
        if self.cal == Calibration::Idle || self.pending_calibration {
            self.pending_calibration = false;
            self.start_calibration(now, io);
            if self.deployed {
                self.cal = Calibration::Done;
                io.double("TEENSY_ATM_PRESSURE", self.conv.atmospheric_pa);
            }
        }
        // The firmware's failsafe centred everything while we were away: say it again.
        if self.have_command {
            self.dirty = true;
        }
    }

    fn on_bytes(&mut self, data: &[u8], now: f64, io: &mut Io) {
        let mut got = Vec::new();
        self.lines.push(data, |l| got.push(l.to_vec()));
        for l in got {
            self.line(&l, now, io);
        }
    }

    fn on_mail(&mut self, key: &str, value: &Value, now: f64, io: &mut Io) {
        let num = value.as_f64();
        match key {
            vars::FIN_TOP_DEG | vars::FIN_STBD_DEG | vars::FIN_PORT_DEG => {
                if let Some(v) = num.filter(|v| v.is_finite()) {
                    let i = match key {
                        vars::FIN_TOP_DEG => 0,
                        vars::FIN_STBD_DEG => 1,
                        _ => 2,
                    };
                    self.fins[i] = v;
                    self.have_command = true;
                    self.dirty = true;
                }
            }
            vars::THRUST_PCT => {
                if let Some(v) = num.filter(|v| v.is_finite()) {
                    self.thrust = v.round().clamp(-100.0, 100.0) as i32;
                    self.have_command = true;
                    self.dirty = true;
                }
            }
            "DEPLOY" => {
                let on = match value {
                    Value::String(s) => moos_types::text::set_boolean_on_string(self.deployed, s),
                    Value::Double(d) => Some(*d != 0.0),
                    Value::Binary(_) => None,
                };
                if let Some(on) = on {
                    self.deployed = on;
                    if on && self.calibrating() {
                        self.end_calibration(None, "deployed before it finished", io);
                    }
                }
            }
            "TEENSY_CALIBRATE" => {
                if self.calibrating() {
                    return;
                }
                self.start_calibration(now, io);
            }
            _ => {}
        }
    }

    fn tick(&mut self, now: f64, io: &mut Io) {
        if let Calibration::Running { start, n, .. } = self.cal
            && now - start >= self.cfg.calibration_timeout_s
        {
            let why = format!(
                "{n} of {} samples in {} s",
                self.cfg.calibration_samples,
                g(self.cfg.calibration_timeout_s)
            );
            self.end_calibration(None, &why, io);
        }
        let repeat = self
            .last_sent
            .is_some_and(|t| now - t >= self.cfg.command_period_s - 1e-9);
        if self.have_command && (self.dirty || repeat) {
            let c = Contr {
                fins_deg: self.fins,
                thrust_pct: self.thrust,
            };
            io.send(c.encode());
            self.counts.commands += 1;
            self.dirty = false;
            self.last_sent = Some(now);
        }
    }

    fn stats(&self) -> LinkStats {
        *self.lines.stats()
    }

    fn state(&self) -> &'static str {
        match self.cal {
            Calibration::Idle => "waiting",
            Calibration::Running { .. } => "calibrating",
            Calibration::Done => "running",
        }
    }

    fn status_extra(&self, out: &mut String) {
        let c = &self.counts;
        let _ = write!(
            out,
            ",depth={},battery={},leak={},commands={},atm_pa={}",
            c.depth,
            c.battery,
            c.leak,
            c.commands,
            g(self.conv.atmospheric_pa)
        );
    }

    fn report(&self, out: &mut String) {
        let opt = |v: Option<f64>| v.map_or("-".to_string(), g);
        let _ = writeln!(
            out,
            "Pressure: {} Pa   depth: {} m   P_atm: {} Pa   rho: {} kg/m3",
            opt(self.last.0),
            opt(self.last.3),
            g(self.conv.atmospheric_pa),
            g(self.conv.density_kgm3)
        );
        let _ = writeln!(
            out,
            "Battery: {} V   leak: {}",
            opt(self.last.1),
            self.last.2.map_or("-", |l| if l { "LEAK" } else { "dry" })
        );
        let _ = writeln!(
            out,
            "Command: fins {} {} {} thrust {}% ({} sent)",
            g(self.fins[0]),
            g(self.fins[1]),
            g(self.fins[2]),
            self.thrust,
            self.counts.commands
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn doubles(io: &Io, key: &str) -> Vec<f64> {
        io.doubles(key)
    }

    fn t(cfg: TeensyConfig) -> Teensy {
        Teensy::new(cfg)
    }

    #[test]
    fn telemetry_lines_become_the_sensor_variables_and_depth_waits_for_calibration() {
        let mut p = t(TeensyConfig {
            calibration_samples: 2,
            ..TeensyConfig::default()
        });
        let mut io = Io::default();
        p.on_connect(0.0, &mut io);
        assert_eq!(p.state(), "calibrating");
        p.on_bytes(b"junk$DEPTH,100000.0,21.5\r\n$BAT", 0.1, &mut io);
        p.on_bytes(b"TE,15.9,2.1\r\n$LEAK,0\r\n", 0.1, &mut io);
        assert_eq!(doubles(&io, "PRESSURE"), [100000.0]);
        assert_eq!(doubles(&io, "PRESSURE_TEMP"), [21.5]);
        assert_eq!(doubles(&io, "BATTERY_VOLTAGE"), [15.9]);
        assert_eq!(doubles(&io, "BATTERY_CURRENT"), [2.1]);
        assert_eq!(doubles(&io, "LEAK"), [0.0]);
        assert!(
            doubles(&io, "DEPTH").is_empty(),
            "no depth while calibrating"
        );
        p.on_bytes(b"$DEPTH,100002.0,21.5\r\n", 0.2, &mut io);
        assert_eq!(doubles(&io, "TEENSY_ATM_PRESSURE"), [100001.0]);
        assert_eq!(p.state(), "running");
        let mut io = Io::default();
        // 1 m of fresh water: rho g = 997 * 9.81 Pa.
        p.on_bytes(b"$DEPTH,109781.6,20.0\r\n$LEAK,1\r\n", 0.3, &mut io);
        let d = doubles(&io, "DEPTH")[0];
        assert!((d - (109781.6 - 100001.0) / (997.0 * 9.81)).abs() < 1e-12);
        assert_eq!(doubles(&io, "LEAK"), [1.0]);
        let st = p.stats();
        assert_eq!(st.garbage_bytes, 4);
        assert_eq!(st.lines, 6);
    }

    #[test]
    fn calibration_is_cut_by_deploy_and_refused_while_deployed() {
        let mut p = t(TeensyConfig::default());
        let mut io = Io::default();
        p.on_connect(0.0, &mut io);
        p.on_bytes(b"$DEPTH,84000.0,20.0\r\n", 0.1, &mut io);
        p.on_mail("DEPLOY", &Value::String("true".into()), 0.2, &mut io);
        assert_eq!(p.state(), "running");
        assert_eq!(doubles(&io, "TEENSY_ATM_PRESSURE"), [87250.0]);
        assert_eq!(p.counts().calibration_failures, 1);
        assert_eq!(io.warnings.len(), 1);
        p.on_mail("TEENSY_CALIBRATE", &Value::Double(1.0), 0.3, &mut io);
        assert_eq!(p.state(), "running");
        assert_eq!(io.warnings.len(), 2);
    }

    #[test]
    fn calibration_times_out_and_ignores_submerged_samples() {
        let mut p = t(TeensyConfig {
            calibration_samples: 3,
            ..TeensyConfig::default()
        });
        let mut io = Io::default();
        p.on_connect(10.0, &mut io);
        p.on_bytes(
            b"$DEPTH,150000.0,20.0\r\n$DEPTH,84000.0,20.0\r\n$DEPTH,84002.0,20.0\r\n",
            10.1,
            &mut io,
        );
        p.tick(14.9, &mut io);
        assert!(p.calibrating());
        p.tick(15.0, &mut io);
        assert!(!p.calibrating());
        assert_eq!(p.converter().atmospheric_pa, 87250.0);
        assert!(
            io.warnings[0].contains("2 of 3 samples"),
            "{:?}",
            io.warnings
        );
    }

    #[test]
    fn commands_go_out_on_change_and_are_repeated() {
        let mut p = t(TeensyConfig::default());
        let mut io = Io::default();
        p.on_connect(0.0, &mut io);
        p.tick(0.1, &mut io);
        assert!(io.tx.is_empty(), "nothing before the first command");
        p.on_mail(vars::FIN_STBD_DEG, &Value::Double(-3.5), 0.2, &mut io);
        p.on_mail(vars::THRUST_PCT, &Value::Double(29.6), 0.2, &mut io);
        p.tick(0.2, &mut io);
        assert_eq!(io.tx, vec![b"$CONTR,0,-3.5,0,30\n".to_vec()]);
        p.tick(0.3, &mut io);
        assert_eq!(io.tx.len(), 1, "no change, not yet due");
        p.tick(0.7, &mut io);
        assert_eq!(io.tx.len(), 2, "repeated after command_period");
        p.on_disconnect(0.8, &mut io);
        p.on_connect(0.9, &mut io);
        p.tick(0.9, &mut io);
        assert_eq!(io.tx.len(), 3, "said again after a reconnection");
        assert_eq!(p.counts().commands, 3);
    }

    #[test]
    fn config_keys() {
        let (c, _, link, problems) = TeensyConfig::from_params([
            ("salinity", "35"),
            ("device", "/dev/ttyACM0"),
            ("calibration_samples", "0"),
        ]);
        assert_eq!(c.salinity_ppt, 35.0);
        assert_eq!(c.calibration_samples, 20);
        assert_eq!(problems.len(), 1);
        assert_eq!(link.endpoint.to_string(), "/dev/ttyACM0@115200");
    }
}
