//! `iDVL`: the Water Linked DVL A50's newline-delimited JSON over TCP (`cougars-vehicle.md`
//! §3.2): velocity and dead-reckoning reports in, commands out, each command's response
//! checked.
//!
//! # Variables
//!
//! Posted: a velocity report as uSimSensors posts it (closed by `DVL_VALID` ✱), a
//! dead-reckoning report under `DVL_DR_*`, and the commands' outcomes.
//!
//! | variable | type | unit | meaning |
//! |---|---|---|---|
//! | `DVL_VEL_X`, `DVL_VEL_Y`, `DVL_VEL_Z` | double | m/s | `vx`, `vy`, `vz`: the DVL's FRD frame (forward, starboard, down); only when `velocity_valid` |
//! | `DVL_ALTITUDE` | double | m | `altitude` (the A50 gives −1 without bottom lock) |
//! | `DVL_FOM` | double | m/s | `fom` |
//! | `DVL_VALID` ✱ | double | 1/0 | `velocity_valid` |
//! | `DVL_DR_X`, `DVL_DR_Y`, `DVL_DR_Z` | double | m | dead reckoning from the last reset (FRD at reset) |
//! | `DVL_DR_STD` | double | m | its standard deviation |
//! | `DVL_DR_ROLL`, `DVL_DR_PITCH`, `DVL_DR_YAW` ✱ | double | deg | the DVL's attitude |
//! | `DVL_ACOUSTIC_ENABLED` | double | 1/0 | the acoustics as the DVL confirmed them (a successful `set_config`) |
//! | `DVL_COMMAND_ACK` | string | | `<command>` when the DVL answered success |
//! | `DVL_COMMAND_ERROR` | string | | `<command>: <why>` when it answered failure or did not answer after `command_retries` tries |
//!
//! Read:
//!
//! | variable | meaning |
//! |---|---|
//! | `DVL_ACOUSTIC_ENABLE` | `true`/`false`: force the acoustics on or off; `auto` (the start): automatic |
//! | `DEPLOY` | automatic mode: the acoustics are on only while deployed and deeper than `acoustic_on_depth`, off again above `acoustic_off_depth` or when `DEPLOY` is false (the A50 overheats in air) |
//! | `NAV_DEPTH` (`depth_var`) | the depth for the automatic mode, m |
//! | `DVL_CALIBRATE_GYRO` | any value: `calibrate_gyro` (hold the vehicle still) |
//! | `DVL_RESET_DR` | any value: `reset_dead_reckoning` |
//! | `DVL_GET_CONFIG` | any value: `get_config` (the answer's acoustics are posted) |
//!
//! On every connection the driver sends `set_config` with the acoustics it wants (off unless
//! forced on or deployed deep: the real driver sends off, so the unit does not overheat in
//! air). Commands go one at a time: each waits for its response for `command_timeout` (3 s;
//! 15 s for `calibrate_gyro`) and is sent again up to `command_retries` (3) times in all, as
//! the CoUGARs' helper does.
//!
//! # Parameters
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `host`, `port` | `192.168.194.95`, 16171 | the A50 |
//! | `acoustic_on_depth`, `acoustic_off_depth` | 0.5, 0.2 | m, the automatic mode's thresholds |
//! | `depth_var` | `NAV_DEPTH` | the depth variable |
//! | `command_timeout`, `gyro_timeout`, `command_retries` | 3, 15, 3 | |

use std::collections::VecDeque;
use std::fmt::Write as _;

use devices::a50::{self, Command, Config, Message, Response};
use devices::line::{LineSplitter, LinkStats};
use moos_types::Value;
use vehicle::ConfigError;

use crate::link::LinkConfig;
use crate::params::{self, Common};
use crate::retry::{Next, Tries};
use crate::{Io, Protocol, g};

/// The program name.
pub const PROGRAM: &str = "iDVL";

/// The A50's default TCP port.
pub const DEFAULT_PORT: u16 = 16171;

/// `iDVL`'s settings.
#[derive(Debug, Clone, PartialEq)]
pub struct DvlConfig {
    /// Depth above which the automatic mode turns the acoustics on, m.
    pub acoustic_on_depth: f64,
    /// Depth below which it turns them off, m.
    pub acoustic_off_depth: f64,
    /// The depth variable.
    pub depth_var: String,
    /// Seconds to wait for a response.
    pub command_timeout_s: f64,
    /// Seconds to wait for `calibrate_gyro`'s response.
    pub gyro_timeout_s: f64,
    /// Tries per command.
    pub command_retries: u32,
}

impl Default for DvlConfig {
    fn default() -> Self {
        DvlConfig {
            acoustic_on_depth: 0.5,
            acoustic_off_depth: 0.2,
            depth_var: "NAV_DEPTH".into(),
            command_timeout_s: 3.0,
            gyro_timeout_s: 15.0,
            command_retries: 3,
        }
    }
}

impl DvlConfig {
    /// Reads a block's parameters: the settings, the link and the problems found.
    pub fn from_params<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> (DvlConfig, Common, LinkConfig, Vec<ConfigError>) {
        let mut c = DvlConfig::default();
        let (common, problems) = params::read(PROGRAM, params, |p, k| {
            Some(match k {
                "acoustic_on_depth" => p.f64().map(|v| c.acoustic_on_depth = v),
                "acoustic_off_depth" => p.f64().map(|v| c.acoustic_off_depth = v),
                "depth_var" => p.text().map(|v| c.depth_var = v),
                "command_timeout" => p.pos().map(|v| c.command_timeout_s = v),
                "gyro_timeout" => p.pos().map(|v| c.gyro_timeout_s = v),
                "command_retries" => p
                    .int(1, 100, "a count from 1")
                    .map(|v| c.command_retries = v as u32),
                _ => return None,
            })
        });
        let link = common.tcp_link("192.168.194.95", DEFAULT_PORT);
        (c, common, link, problems)
    }
}

/// The acoustics mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AcousticMode {
    /// From `DEPLOY` and the depth.
    Auto,
    /// Forced on or off.
    Forced(bool),
}

/// Counts of what came in and went out.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DvlCounts {
    /// Velocity reports.
    pub velocity: u64,
    /// Of which valid.
    pub valid: u64,
    /// Dead-reckoning reports.
    pub dead_reckoning: u64,
    /// Commands sent (each try).
    pub sent: u64,
    /// Successful responses.
    pub acks: u64,
    /// Failures (a failure response or no response after every try).
    pub errors: u64,
    /// Tries that timed out.
    pub timeouts: u64,
}

/// The `iDVL` protocol.
pub struct Dvl {
    cfg: DvlConfig,
    lines: LineSplitter,
    mode: AcousticMode,
    deployed: bool,
    depth: Option<f64>,
    want: bool,
    queue: VecDeque<Command>,
    in_flight: Option<Tries<Command>>,
    connected: bool,
    confirmed: Option<bool>,
    counts: DvlCounts,
    last_vel: Option<([f64; 3], f64, bool)>,
    hot: bool,
}

impl Dvl {
    /// A protocol with `cfg`.
    pub fn new(cfg: DvlConfig) -> Self {
        Dvl {
            cfg,
            // JSON nests objects: a `{` does not start a line.
            lines: LineSplitter::new(a50::MAX_LINE),
            mode: AcousticMode::Auto,
            deployed: false,
            depth: None,
            want: false,
            queue: VecDeque::new(),
            in_flight: None,
            connected: false,
            confirmed: None,
            counts: DvlCounts::default(),
            last_vel: None,
            hot: false,
        }
    }

    /// The counts so far.
    pub fn counts(&self) -> DvlCounts {
        self.counts
    }

    /// The acoustics the driver wants now.
    pub fn wants_acoustics(&self) -> bool {
        self.want
    }

    /// Commands waiting (not counting the one in flight).
    pub fn queued(&self) -> usize {
        self.queue.len()
    }

    fn set_acoustics(&mut self) -> Command {
        Command::SetConfig(Config {
            acoustic_enabled: Some(self.want),
            ..Config::default()
        })
    }

    /// Recomputes the wanted acoustics; a change queues a `set_config`.
    fn update_want(&mut self) {
        let want = match self.mode {
            AcousticMode::Forced(on) => on,
            AcousticMode::Auto => {
                let d = self.depth.unwrap_or(0.0);
                if !self.deployed {
                    false
                } else if self.want {
                    d > self.cfg.acoustic_off_depth
                } else {
                    d >= self.cfg.acoustic_on_depth
                }
            }
        };
        if want != self.want {
            self.want = want;
            // A newer set_config makes a queued one moot.
            self.queue.retain(|c| !matches!(c, Command::SetConfig(_)));
            let c = self.set_acoustics();
            self.queue.push_back(c);
        }
    }

    fn timeout_of(&self, c: &Command) -> f64 {
        match c {
            Command::CalibrateGyro => self.cfg.gyro_timeout_s,
            _ => self.cfg.command_timeout_s,
        }
    }

    fn send(&mut self, mut cmd: Tries<Command>, now: f64, io: &mut Io) {
        io.send(cmd.cmd.encode());
        self.counts.sent += 1;
        cmd.sent(now);
        self.in_flight = Some(cmd);
    }

    fn response(&mut self, r: Response, io: &mut Io) {
        let Some(f) = &self.in_flight else {
            io.events
                .push(format!("unexpected response to {}", r.response_to));
            return;
        };
        if r.response_to != f.cmd.name() {
            io.events.push(format!(
                "response to {} while waiting for {}",
                r.response_to,
                f.cmd.name()
            ));
            return;
        }
        let f = self.in_flight.take().expect("checked above");
        if r.success {
            self.counts.acks += 1;
            io.text("DVL_COMMAND_ACK", f.cmd.name());
            io.events.push(format!("{}: ok", f.cmd.name()));
            let acoustics = match (&f.cmd, &r.result) {
                (
                    _,
                    Some(Config {
                        acoustic_enabled: Some(a),
                        ..
                    }),
                ) => Some(*a),
                (Command::SetConfig(c), _) => c.acoustic_enabled,
                _ => None,
            };
            if let Some(a) = acoustics {
                self.confirmed = Some(a);
                io.double("DVL_ACOUSTIC_ENABLED", if a { 1.0 } else { 0.0 });
            }
        } else {
            self.counts.errors += 1;
            let why = format!("{}: {}", f.cmd.name(), r.error_message);
            io.text("DVL_COMMAND_ERROR", why.clone());
            io.warnings.push(format!("DVL refused {why}"));
        }
    }

    fn line(&mut self, line: &[u8], io: &mut Io) {
        let r = a50::parse(line);
        self.lines.stats_mut().record(&r);
        let Ok(m) = r else { return };
        match m {
            Message::Velocity(v) => {
                self.counts.velocity += 1;
                if v.velocity_valid {
                    self.counts.valid += 1;
                    io.double("DVL_VEL_X", v.vel_body_mps[0]);
                    io.double("DVL_VEL_Y", v.vel_body_mps[1]);
                    io.double("DVL_VEL_Z", v.vel_body_mps[2]);
                }
                io.double("DVL_ALTITUDE", v.altitude_m);
                io.double("DVL_FOM", v.fom_mps);
                io.double("DVL_VALID", if v.velocity_valid { 1.0 } else { 0.0 });
                let hot = v.status == 1;
                if hot && !self.hot {
                    io.warnings
                        .push("DVL status 1: high temperature, acoustics throttled".into());
                }
                self.hot = hot;
                self.last_vel = Some((v.vel_body_mps, v.altitude_m, v.velocity_valid));
            }
            Message::DeadReckoning(d) => {
                self.counts.dead_reckoning += 1;
                io.double("DVL_DR_X", d.x_m);
                io.double("DVL_DR_Y", d.y_m);
                io.double("DVL_DR_Z", d.z_m);
                io.double("DVL_DR_STD", d.std_m);
                io.double("DVL_DR_ROLL", d.roll_deg);
                io.double("DVL_DR_PITCH", d.pitch_deg);
                io.double("DVL_DR_YAW", d.yaw_deg);
            }
            Message::Response(r) => self.response(r, io),
        }
    }
}

fn truthy(v: &Value) -> Option<bool> {
    match v {
        Value::String(s) => moos_types::text::strict_bool(s),
        Value::Double(d) => Some(*d != 0.0),
        Value::Binary(_) => None,
    }
}

impl Protocol for Dvl {
    fn program(&self) -> &'static str {
        PROGRAM
    }

    fn status_var(&self) -> &'static str {
        "DVL_DRIVER_STATUS"
    }

    fn subscriptions(&self) -> Vec<String> {
        let mut v: Vec<String> = [
            "DVL_ACOUSTIC_ENABLE",
            "DEPLOY",
            "DVL_CALIBRATE_GYRO",
            "DVL_RESET_DR",
            "DVL_GET_CONFIG",
        ]
        .map(String::from)
        .to_vec();
        v.push(self.cfg.depth_var.clone());
        v
    }

    fn on_connect(&mut self, now: f64, io: &mut Io) {
        self.lines.reset();
        self.connected = true;
        self.confirmed = None;
        // What was in flight went to a connection that is gone; say the acoustics first.
        self.in_flight = None;
        self.queue.retain(|c| !matches!(c, Command::SetConfig(_)));
        let c = self.set_acoustics();
        self.queue.push_front(c);
        self.tick(now, io);
    }

    fn on_disconnect(&mut self, _now: f64, _io: &mut Io) {
        self.connected = false;
        if let Some(f) = self.in_flight.take() {
            self.queue.push_front(f.cmd);
        }
    }

    fn on_bytes(&mut self, data: &[u8], _now: f64, io: &mut Io) {
        let mut got = Vec::new();
        self.lines.push(data, |l| got.push(l.to_vec()));
        for l in got {
            self.line(&l, io);
        }
    }

    fn on_mail(&mut self, key: &str, value: &Value, _now: f64, io: &mut Io) {
        match key {
            "DVL_ACOUSTIC_ENABLE" => {
                let mode = match value.as_str().map(str::trim) {
                    Some(s) if s.eq_ignore_ascii_case("auto") => Some(AcousticMode::Auto),
                    _ => truthy(value).map(AcousticMode::Forced),
                };
                match mode {
                    Some(m) => {
                        self.mode = m;
                        self.update_want();
                    }
                    None => io
                        .warnings
                        .push("DVL_ACOUSTIC_ENABLE: expected true, false or auto".into()),
                }
            }
            "DEPLOY" => {
                if let Some(d) = truthy(value) {
                    self.deployed = d;
                    self.update_want();
                }
            }
            "DVL_CALIBRATE_GYRO" => self.queue.push_back(Command::CalibrateGyro),
            "DVL_RESET_DR" => self.queue.push_back(Command::ResetDeadReckoning),
            "DVL_GET_CONFIG" => self.queue.push_back(Command::GetConfig),
            k if k == self.cfg.depth_var => {
                if let Some(d) = value.as_f64().filter(|d| d.is_finite()) {
                    self.depth = Some(d);
                    self.update_want();
                }
            }
            _ => {}
        }
    }

    fn tick(&mut self, now: f64, io: &mut Io) {
        if !self.connected {
            return;
        }
        if let Some(f) = &self.in_flight {
            let next = f.next(now, self.timeout_of(&f.cmd), self.cfg.command_retries);
            if next == Next::Wait {
                return;
            }
            let f = self.in_flight.take().expect("checked above");
            self.counts.timeouts += 1;
            if next == Next::Send {
                self.send(f, now, io);
                return;
            }
            self.counts.errors += 1;
            let why = format!("{}: no response after {} tries", f.cmd.name(), f.tries());
            io.text("DVL_COMMAND_ERROR", why.clone());
            io.warnings.push(why);
        }
        if let Some(c) = self.queue.pop_front() {
            self.send(Tries::new(c), now, io);
        }
    }

    fn stats(&self) -> LinkStats {
        *self.lines.stats()
    }

    fn state(&self) -> &'static str {
        if !self.connected {
            "waiting"
        } else if self.in_flight.is_some() {
            "commanding"
        } else {
            "running"
        }
    }

    fn status_extra(&self, out: &mut String) {
        let c = &self.counts;
        let _ = write!(
            out,
            ",velocity={},valid={},dead_reckoning={},acoustics={},commands={},acks={},\
             command_errors={},command_timeouts={}",
            c.velocity,
            c.valid,
            c.dead_reckoning,
            match self.confirmed {
                Some(true) => "on",
                Some(false) => "off",
                None => "unknown",
            },
            c.sent,
            c.acks,
            c.errors,
            c.timeouts
        );
    }

    fn report(&self, out: &mut String) {
        let _ = writeln!(
            out,
            "Acoustics: want {} (mode {}), DVL says {}   deployed: {}   depth: {}",
            if self.want { "on" } else { "off" },
            match self.mode {
                AcousticMode::Auto => "auto",
                AcousticMode::Forced(true) => "forced on",
                AcousticMode::Forced(false) => "forced off",
            },
            match self.confirmed {
                Some(true) => "on",
                Some(false) => "off",
                None => "?",
            },
            self.deployed,
            self.depth.map_or("-".into(), g)
        );
        if let Some((v, alt, valid)) = self.last_vel {
            let _ = writeln!(
                out,
                "Velocity: ({}, {}, {}) m/s  altitude {} m  {}",
                g(v[0]),
                g(v[1]),
                g(v[2]),
                g(alt),
                if valid { "valid" } else { "invalid" }
            );
        }
        let c = &self.counts;
        let _ = writeln!(
            out,
            "Reports: {} velocity ({} valid), {} dead reckoning; commands {} sent, {} ok, {} failed",
            c.velocity, c.valid, c.dead_reckoning, c.sent, c.acks, c.errors
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use devices::a50::{DeadReckoningReport, VelocityReport};

    fn doubles(io: &Io, key: &str) -> Vec<f64> {
        io.doubles(key)
    }

    fn texts(io: &Io, key: &str) -> Vec<String> {
        io.texts(key)
    }

    fn sent(io: &Io) -> Vec<Command> {
        io.tx
            .iter()
            .map(|b| a50::parse_command(b.strip_suffix(b"\n").unwrap()).unwrap())
            .collect()
    }

    fn ok(to: &str) -> String {
        Response {
            response_to: to.into(),
            success: true,
            error_message: String::new(),
            result: None,
            format: Some("json_v3.1".into()),
        }
        .encode()
    }

    fn velocity(valid: bool) -> VelocityReport {
        VelocityReport {
            time_ms: 106.0,
            time_of_validity_us: Some(1_638_191_471_563_017),
            time_of_transmission_us: Some(1_638_191_471_752_336),
            vel_body_mps: [0.7, -0.02, 0.01],
            fom_mps: 0.002,
            covariance: None,
            altitude_m: if valid { 4.2 } else { -1.0 },
            transducers: Vec::new(),
            velocity_valid: valid,
            status: 0,
            format: Some("json_v3.1".into()),
        }
    }

    #[test]
    fn connect_turns_the_acoustics_off_and_checks_the_response() {
        let mut p = Dvl::new(DvlConfig::default());
        let mut io = Io::default();
        p.on_connect(0.0, &mut io);
        assert_eq!(
            sent(&io),
            [Command::SetConfig(Config {
                acoustic_enabled: Some(false),
                ..Config::default()
            })]
        );
        assert_eq!(p.state(), "commanding");
        p.on_bytes(ok("set_config").as_bytes(), 0.1, &mut io);
        assert_eq!(doubles(&io, "DVL_ACOUSTIC_ENABLED"), [0.0]);
        assert_eq!(texts(&io, "DVL_COMMAND_ACK"), ["set_config"]);
        assert_eq!(p.state(), "running");
    }

    #[test]
    fn reports_become_the_sensor_variables() {
        let mut p = Dvl::new(DvlConfig::default());
        let mut io = Io::default();
        let mut bytes = velocity(true).encode();
        bytes += &velocity(false).encode();
        bytes += &DeadReckoningReport {
            ts_s: 49056.809,
            x_m: 12.0,
            y_m: -3.5,
            z_m: 1.25,
            std_m: 0.3,
            roll_deg: 1.0,
            pitch_deg: -2.0,
            yaw_deg: 271.5,
            status: 0,
            format: Some("json_v3.1".into()),
        }
        .encode();
        p.on_bytes(bytes.as_bytes(), 1.0, &mut io);
        let keys: Vec<&str> = io.posts.iter().map(|p| &*p.key).collect();
        assert_eq!(
            keys,
            [
                "DVL_VEL_X",
                "DVL_VEL_Y",
                "DVL_VEL_Z",
                "DVL_ALTITUDE",
                "DVL_FOM",
                "DVL_VALID",
                "DVL_ALTITUDE",
                "DVL_FOM",
                "DVL_VALID",
                "DVL_DR_X",
                "DVL_DR_Y",
                "DVL_DR_Z",
                "DVL_DR_STD",
                "DVL_DR_ROLL",
                "DVL_DR_PITCH",
                "DVL_DR_YAW"
            ]
        );
        assert_eq!(doubles(&io, "DVL_VEL_Y"), [-0.02]);
        assert_eq!(doubles(&io, "DVL_ALTITUDE"), [4.2, -1.0]);
        assert_eq!(doubles(&io, "DVL_VALID"), [1.0, 0.0]);
        assert_eq!(doubles(&io, "DVL_DR_YAW"), [271.5]);
        assert_eq!(p.counts().valid, 1);
    }

    #[test]
    fn automatic_acoustics_follow_deploy_and_depth_with_hysteresis() {
        let mut p = Dvl::new(DvlConfig::default());
        let mut io = Io::default();
        p.on_connect(0.0, &mut io);
        p.on_bytes(ok("set_config").as_bytes(), 0.1, &mut io);
        io.tx.clear();
        p.on_mail("NAV_DEPTH", &Value::Double(2.0), 1.0, &mut io);
        assert!(!p.wants_acoustics(), "not deployed");
        p.on_mail("DEPLOY", &Value::String("true".into()), 1.0, &mut io);
        assert!(p.wants_acoustics());
        p.tick(1.0, &mut io);
        assert_eq!(
            sent(&io),
            [Command::SetConfig(Config {
                acoustic_enabled: Some(true),
                ..Config::default()
            })]
        );
        p.on_mail("NAV_DEPTH", &Value::Double(0.3), 2.0, &mut io);
        assert!(p.wants_acoustics(), "inside the hysteresis");
        p.on_mail("NAV_DEPTH", &Value::Double(0.1), 2.0, &mut io);
        assert!(!p.wants_acoustics(), "at the surface");
        p.on_mail(
            "DVL_ACOUSTIC_ENABLE",
            &Value::String("true".into()),
            3.0,
            &mut io,
        );
        assert!(p.wants_acoustics(), "forced");
        p.on_mail(
            "DVL_ACOUSTIC_ENABLE",
            &Value::String("auto".into()),
            3.0,
            &mut io,
        );
        assert!(!p.wants_acoustics());
        assert_eq!(
            p.queued(),
            1,
            "one set_config queued, the moot ones dropped"
        );
    }

    #[test]
    fn commands_are_retried_then_reported_and_refusals_are_errors() {
        let mut p = Dvl::new(DvlConfig::default());
        let mut io = Io::default();
        p.on_connect(0.0, &mut io);
        p.on_bytes(ok("set_config").as_bytes(), 0.1, &mut io);
        p.on_mail("DVL_CALIBRATE_GYRO", &Value::Double(1.0), 1.0, &mut io);
        p.on_mail("DVL_RESET_DR", &Value::Double(1.0), 1.0, &mut io);
        io.tx.clear();
        p.tick(1.0, &mut io);
        assert_eq!(sent(&io), [Command::CalibrateGyro]);
        p.tick(15.9, &mut io);
        assert_eq!(io.tx.len(), 1, "the gyro has 15 s");
        p.tick(16.0, &mut io);
        p.tick(31.0, &mut io);
        assert_eq!(io.tx.len(), 3, "three tries");
        p.tick(46.0, &mut io);
        assert_eq!(
            texts(&io, "DVL_COMMAND_ERROR"),
            ["calibrate_gyro: no response after 3 tries"]
        );
        assert_eq!(sent(&io)[3], Command::ResetDeadReckoning);
        let refusal = Response {
            response_to: "reset_dead_reckoning".into(),
            success: false,
            error_message: "busy".into(),
            result: None,
            format: None,
        }
        .encode();
        p.on_bytes(refusal.as_bytes(), 46.5, &mut io);
        assert_eq!(
            texts(&io, "DVL_COMMAND_ERROR")[1],
            "reset_dead_reckoning: busy"
        );
        assert_eq!(p.counts().errors, 2);
        assert_eq!(p.counts().timeouts, 3);
    }
}
