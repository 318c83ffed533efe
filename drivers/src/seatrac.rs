//! `iSeaTrac`: the SeaTrac X150 USBL modem on a serial port (`cougars-vehicle.md` §3.5): its
//! start-up sequence, the 10 Hz STATUS (the Gen-1 vehicles' only AHRS), PING and DAT with
//! their acoustic fixes, and a send queue that retries on XCVR_BUSY.
//!
//! # Start-up
//!
//! At each connection: `SYS_ALIVE` until the beacon answers, `SETTINGS_GET`, then the settings
//! with `xcvr_beacon_id = beacon_id`, `env_salinity = salinity·10`, status mode 10 Hz and the
//! status output ATTITUDE | AHRS_COMP_DATA | ENVIRONMENT go back with `SETTINGS_SET`, then
//! `SETTINGS_SAVE` (unless `save_settings = false`). A step not answered within
//! `startup_timeout` (1 s) is sent again; a step answered with a status other than OK is a run
//! warning and is sent again after the timeout. The send queue waits for `running`.
//!
//! # Conventions
//!
//! The angles on the wire are signed 16-bit deci-degrees (`i16`, divide by 10), little-endian,
//! as the UM-140 field tables give them; the driver posts degrees. Three frames meet here
//! (`cougars-vehicle.md` §2.1, §3.5 and the HoloOcean modem bridge of §7):
//!
//! - **The modem's frame** is the vehicle's body frame, FRD (forward, starboard, down): the
//!   CoUGARs' converter hands the ATTITUDE block straight to the `ned → modem` transform (roll,
//!   pitch, yaw), and its `modem → robot` transform is the identity. So ATTITUDE is the
//!   vehicle's attitude: yaw clockwise from *magnetic* north (the AHRS's compass), pitch nose
//!   up, roll starboard down. `AHRS_HEADING` = yaw + `declination` (the true heading, the
//!   declination applied here once), wrapped to `[0, 360)`.
//! - **The AHRS chip** inside the modem is turned 45° (§2.1, "determined experimentally"):
//!   the AHRS_COMP vectors are in the chip's axes, and the converter's own mapping gives the
//!   body rates, `ω = [√½(gy − gx), √½(gx + gy), −gz]` about forward, starboard and down, in
//!   the frame of the attitude above (FRD): turning right is a positive `AHRS_YAW_RATE`, as
//!   uSimSensors posts it. (Its accelerometer mapping is the negative of that rotation:
//!   the converter turns the chip's specific force into ROS's "+g up"; the driver posts no
//!   acceleration.) With `ahrs_mount = aligned` the chip's axes are taken as the body's.
//! - **The USBL angles** of an acoustic fix are in the modem's frame, FRD: the azimuth is the
//!   bearing of the remote beacon from the vehicle's bow, clockwise seen from above, `[0,
//!   360)` (Gen-2 negates it for FLU; the HoloOcean bridge turns its FLU angle into this one);
//!   the elevation is positive when the remote beacon is above the local one (shallower),
//!   `[−90, 90]`. The position block is the remote beacon's easting and northing from the
//!   local beacon and its depth below the surface, decimetres. The beacon resolves the
//!   easting and northing with its own attitude and *magnetic* heading, so they are on
//!   magnetic north: the driver turns them onto true north with `declination` (applied
//!   here once, as to the yaw), so `USBL_X`/`USBL_Y` are on the mission's grid.
//!
//! What the vendor's document says (Blueprint Subsea, *SeaTrac X100 Series Serial Command
//! Interface Reference*, UM-140-D00221-02, firmware 1.2, §6.4.2 `ACOFIX_T`, pp. 46–49): the
//! azimuth is "the incoming signal azimuth angle from 0° to 360°" and the elevation "the
//! incoming signal elevation angle from −90° to +90°", both in deci-degrees, with no sign
//! convention stated for the elevation (nor in §7.6.8 `CID_XCVR_USBL`, p. 102); the
//! position's easting and northing are "the relative position of the remote beacon to the
//! local beacon computed from the range, incoming signal angle, local beacon depth, attitude
//! and magnetic heading" (hence magnetic north, confirmed), and its depth "the vertical
//! depth distance component of the remote beacon from the surface" (an absolute depth,
//! confirmed; with `REQX` the remote's own depth sensor, `POSITION_ENHANCED`). The
//! elevation's sign stays unconfirmed by the vendor: positive-up is the HoloOcean modem
//! bridge's and the emulator's convention. Nothing downstream depends on it while the
//! position block is present (pAcomms prefers the offsets, then the depths, to the
//! elevation).
//!
//! So a remote beacon 20 m east of the vehicle and 20 m deeper, the vehicle heading north
//! and level, is at azimuth 90°, elevation −45°, range 28.3 m: `USBL_AZIMUTH = 90`,
//! `USBL_ELEVATION = -45`, `USBL_RANGE = 28.3`, `USBL_X = 20`, `USBL_Y = 0`, `USBL_Z` the
//! remote's depth (the tests build that frame from the field tables); with a declination
//! of 10° E the beacon writes that position as easting 19.7, northing 3.5 (magnetic), and the
//! driver posts 20, 0 again.
//!
//! # Variables
//!
//! Posted from STATUS, as uSimSensors posts the AHRS (closed by `AHRS_HEADING` ✱):
//!
//! | variable | type | unit | meaning |
//! |---|---|---|---|
//! | `AHRS_PITCH`, `AHRS_ROLL` | double | deg | the beacon's attitude (nose up, starboard down positive) |
//! | `AHRS_ROLL_RATE`, `AHRS_PITCH_RATE`, `AHRS_YAW_RATE` | double | deg/s | body FRD gyro rates (about forward, starboard, down: yaw rate positive turning right) from AHRS_COMP; with `ahrs_mount = x45` (the CoUGARs' 45° mount, §2.1) `[√½(gy−gx), √½(gx+gy), −gz]`, with `aligned` `[gx, gy, gz]`; only when the block is present |
//! | `AHRS_HEADING` ✱ | double | deg | yaw + `declination`, `[0, 360)` (the Gen-1 converter applies the declination here, once) |
//! | `SEATRAC_DEPTH` | double | m | ENVIRONMENT depth |
//! | `SEATRAC_SUPPLY_VOLTAGE` | double | V | ENVIRONMENT supply |
//! | `SEATRAC_TEMP` | double | °C | ENVIRONMENT temperature |
//! | `SEATRAC_PRESSURE` | double | Pa | ENVIRONMENT pressure (mbar × 100) |
//! | `SEATRAC_VOS` | double | m/s | ENVIRONMENT speed of sound |
//!
//! Posted from an acoustic fix (PING_RESP, PING_REQ and DAT_RECEIVE carry one), each field
//! when the fix has it, closed by `USBL_FIX` ✱:
//!
//! | variable | type | unit | meaning |
//! |---|---|---|---|
//! | `USBL_SRC` | double | id | the remote beacon |
//! | `USBL_RANGE` | double | m | range (dm / 10) |
//! | `USBL_AZIMUTH`, `USBL_ELEVATION` | double | deg | USBL angles in the modem's (body FRD) frame: azimuth clockwise from the bow `[0, 360)`, elevation positive above (see Conventions) |
//! | `USBL_X`, `USBL_Y`, `USBL_Z` | double | m | the remote's position: easting and northing from the local beacon (true north: the beacon's magnetic ones turned by `declination`), depth below the surface |
//! | `USBL_FIX` ✱ | string | | `src=2,dest=1,type=..,rssi=..` and `range=`, `azimuth=`, `elevation=`, `x=`, `y=`, `z=` for the fields present |
//! | `ACOMMS_RX` | string | | a DAT received: `src=<id>,dest=<id>,ack=<0\|1>,hex=<payload as uppercase hex>` |
//! | `ACOMMS_TX_ACK` | string | | `dest=<id>,cid=<DAT_SEND\|PING_SEND>`: the beacon sent it |
//! | `ACOMMS_ERROR` | string | | `<what>: <status>`: a send refused (other than busy), a PING_ERROR or DAT_ERROR, a send never answered |
//! | `SEATRAC_BEACON_ID` | double | id | the beacon id in force, once running |
//!
//! Read:
//!
//! | variable | format | meaning |
//! |---|---|---|
//! | `ACOMMS_TX` | `dest=<id>,hex=<payload>[,type=<OWAY\|OWAYU\|REQ\|REQU\|REQX>]` | queue a DAT_SEND (at most 31 bytes; type OWAYU by default: the receiver gets a USBL bearing; dest 0 is every beacon) |
//! | `SEATRAC_PING` | `<id>` or `dest=<id>[,type=REQ\|REQU\|REQX]` | queue a PING_SEND (type REQU by default: range and USBL) |
//!
//! The send queue is serviced once per iteration: a sent message waits for the beacon's
//! answer; XCVR_BUSY keeps it queued and sends it again after `send_wait` (0.5 s, the
//! CoUGARs' five ticks at 10 Hz); OK or any other status pops it (other statuses post
//! `ACOMMS_ERROR`); no answer within `send_wait` sends it again, up to `send_tries` (3) times.
//! A queue of 8 or more is a run warning; beyond `max_queue` (32) the oldest is dropped.
//!
//! # Parameters
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `device`, `baud` | `/dev/frost/rs232_connector_seatrac`, 115200 | the serial link |
//! | `beacon_id` | 1 | 1–15 |
//! | `salinity` | 0 | ppt |
//! | `declination` | 0 | deg east, added to the yaw and to the bearing of the acoustic fixes' easting/northing (Utah Lake: 10.7) |
//! | `ahrs_mount` | `x45` | `x45` or `aligned` |
//! | `save_settings` | true | SETTINGS_SAVE after SETTINGS_SET |
//! | `startup_timeout`, `send_wait`, `send_tries`, `max_queue` | 1, 0.5, 3, 32 | |

use std::collections::VecDeque;
use std::fmt::Write as _;

use devices::line::{LineSplitter, LinkStats};
use devices::seatrac::{
    self, AcoFix, Command, Cst, MAX_DAT_PAYLOAD, Response, Settings, Status, msg_type, status_bits,
};
use moos_types::Value;
use vehicle::ConfigError;

use crate::link::LinkConfig;
use crate::params::{self, Common};
use crate::retry::{Next, Tries};
use crate::{Io, Protocol, g};

/// The program name.
pub const PROGRAM: &str = "iSeaTrac";

/// The status blocks the driver asks for.
pub const STATUS_OUTPUT: u8 =
    status_bits::ATTITUDE | status_bits::AHRS_COMP_DATA | status_bits::ENVIRONMENT;

/// Status mode 10 Hz.
pub const STATUS_MODE_10HZ: u8 = 4;

/// The queue length that is warned about (as the CoUGARs' node).
pub const QUEUE_WARN: usize = 8;

/// How the beacon is mounted.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mount {
    /// Turned 45° about the vertical (the CoUGARs).
    X45,
    /// Its axes are the body's FRD axes.
    Aligned,
}

/// `iSeaTrac`'s settings.
#[derive(Debug, Clone, PartialEq)]
pub struct SeaTracConfig {
    /// Beacon id, 1–15.
    pub beacon_id: u8,
    /// Salinity, ppt.
    pub salinity_ppt: f64,
    /// Magnetic declination, degrees east.
    pub declination_deg: f64,
    /// The mount.
    pub mount: Mount,
    /// Save the settings to EEPROM.
    pub save_settings: bool,
    /// Seconds before a start-up step is sent again.
    pub startup_timeout_s: f64,
    /// Seconds a send waits for its answer (and before a busy send is tried again).
    pub send_wait_s: f64,
    /// Tries of a send never answered.
    pub send_tries: u32,
    /// The longest queue.
    pub max_queue: usize,
}

impl Default for SeaTracConfig {
    fn default() -> Self {
        SeaTracConfig {
            beacon_id: 1,
            salinity_ppt: 0.0,
            declination_deg: 0.0,
            mount: Mount::X45,
            save_settings: true,
            startup_timeout_s: 1.0,
            send_wait_s: 0.5,
            send_tries: 3,
            max_queue: 32,
        }
    }
}

impl SeaTracConfig {
    /// Reads a block's parameters: the settings, the link and the problems found.
    pub fn from_params<'a>(
        params: impl IntoIterator<Item = (&'a str, &'a str)>,
    ) -> (SeaTracConfig, Common, LinkConfig, Vec<ConfigError>) {
        let mut c = SeaTracConfig::default();
        let (common, problems) = params::read(PROGRAM, params, |p, k| {
            Some(match k {
                "beacon_id" => p
                    .int(1, 15, "a beacon id from 1 to 15")
                    .map(|v| c.beacon_id = v as u8),
                "salinity" => match p.non_neg() {
                    Ok(v) if v <= 6553.5 => {
                        c.salinity_ppt = v;
                        Ok(())
                    }
                    _ => Err(p.bad("a salinity in ppt (0-6553)")),
                },
                "declination" => p.f64().map(|v| c.declination_deg = v),
                "ahrs_mount" => match p.value.to_ascii_lowercase().as_str() {
                    "x45" => {
                        c.mount = Mount::X45;
                        Ok(())
                    }
                    "aligned" => {
                        c.mount = Mount::Aligned;
                        Ok(())
                    }
                    _ => Err(p.bad("x45 or aligned")),
                },
                "save_settings" => p.bool().map(|v| c.save_settings = v),
                "startup_timeout" => p.pos().map(|v| c.startup_timeout_s = v),
                "send_wait" => p.pos().map(|v| c.send_wait_s = v),
                "send_tries" => p
                    .int(1, 100, "a count from 1")
                    .map(|v| c.send_tries = v as u32),
                "max_queue" => p
                    .int(1, 10_000, "a count from 1")
                    .map(|v| c.max_queue = v as usize),
                _ => return None,
            })
        });
        let link = common.serial_link("/dev/frost/rs232_connector_seatrac", 115_200);
        (c, common, link, problems)
    }
}

/// The start-up sequence.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Startup {
    /// No connection.
    Waiting,
    /// SYS_ALIVE sent.
    Alive,
    /// SETTINGS_GET sent.
    SettingsGet,
    /// SETTINGS_SET sent.
    SettingsSet,
    /// SETTINGS_SAVE sent.
    SettingsSave,
    /// Done: STATUS flows, the queue is serviced.
    Running,
}

impl Startup {
    fn name(self) -> &'static str {
        match self {
            Startup::Waiting => "waiting",
            Startup::Alive => "alive",
            Startup::SettingsGet => "settings_get",
            Startup::SettingsSet => "settings_set",
            Startup::SettingsSave => "settings_save",
            Startup::Running => "running",
        }
    }
}

/// Counts of what came in and went out.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SeaTracCounts {
    /// STATUS messages.
    pub status: u64,
    /// Acoustic fixes.
    pub fixes: u64,
    /// DAT payloads received.
    pub dat_rx: u64,
    /// Sends the beacon accepted.
    pub sent_ok: u64,
    /// XCVR_BUSY answers.
    pub busy: u64,
    /// Sends that failed.
    pub send_errors: u64,
    /// Start-up steps sent again.
    pub startup_retries: u64,
    /// Sends dropped from a full queue.
    pub queue_dropped: u64,
}

/// The `iSeaTrac` protocol.
pub struct SeaTrac {
    cfg: SeaTracConfig,
    lines: LineSplitter,
    startup: Startup,
    step_sent: f64,
    queue: VecDeque<Tries<Command>>,
    counts: SeaTracCounts,
    last_status: Option<Status>,
    queue_warned: bool,
}

impl SeaTrac {
    /// A protocol with `cfg`.
    pub fn new(cfg: SeaTracConfig) -> Self {
        SeaTrac {
            cfg,
            lines: LineSplitter::new(seatrac::MAX_FRAME).with_starts(b"$#"),
            startup: Startup::Waiting,
            step_sent: 0.0,
            queue: VecDeque::new(),
            counts: SeaTracCounts::default(),
            last_status: None,
            queue_warned: false,
        }
    }

    /// The start-up state.
    pub fn startup(&self) -> Startup {
        self.startup
    }

    /// The counts so far.
    pub fn counts(&self) -> SeaTracCounts {
        self.counts
    }

    /// Sends waiting (the one awaiting its answer included).
    pub fn queued(&self) -> usize {
        self.queue.len()
    }

    fn step(&mut self, s: Startup, cmd: &Command, now: f64, io: &mut Io) {
        self.startup = s;
        self.step_sent = now;
        if let Ok(f) = cmd.encode() {
            io.send(f);
        }
    }

    fn enqueue(&mut self, cmd: Command, io: &mut Io) {
        if self.queue.len() >= self.cfg.max_queue {
            self.queue.pop_front();
            self.counts.queue_dropped += 1;
            io.warnings
                .push("acoustic send queue full: the oldest send dropped".into());
        }
        self.queue.push_back(Tries::new(cmd));
        if self.queue.len() >= QUEUE_WARN && !self.queue_warned {
            self.queue_warned = true;
            io.warnings
                .push(format!("acoustic send queue at {}", self.queue.len()));
        }
    }

    fn status(&mut self, s: Status, io: &mut Io) {
        self.counts.status += 1;
        if let Some(a) = s.attitude {
            io.double("AHRS_PITCH", a.pitch_deg());
            io.double("AHRS_ROLL", a.roll_deg());
            if let Some(c) = s.ahrs_comp {
                let [gx, gy, gz] = c.gyro.map(f64::from);
                let r = std::f64::consts::FRAC_1_SQRT_2;
                let frd = match self.cfg.mount {
                    Mount::X45 => [r * (gy - gx), r * (gx + gy), -gz],
                    Mount::Aligned => [gx, gy, gz],
                };
                io.double("AHRS_ROLL_RATE", frd[0]);
                io.double("AHRS_PITCH_RATE", frd[1]);
                io.double("AHRS_YAW_RATE", frd[2]);
            }
            let h = (a.yaw_deg() + self.cfg.declination_deg).rem_euclid(360.0);
            // rem_euclid of a value just below 0 can round to 360.
            io.double("AHRS_HEADING", if h >= 360.0 { 0.0 } else { h });
        }
        if let Some(e) = s.environment {
            io.double("SEATRAC_DEPTH", e.depth_m());
            io.double("SEATRAC_SUPPLY_VOLTAGE", e.supply_v());
            io.double("SEATRAC_TEMP", e.temp_degc());
            io.double("SEATRAC_PRESSURE", f64::from(e.pressure_mbar) * 100.0);
            io.double("SEATRAC_VOS", f64::from(e.vos_dmps) / 10.0);
        }
        self.last_status = Some(s);
    }

    fn fix(&mut self, f: &AcoFix, io: &mut Io) {
        self.counts.fixes += 1;
        let mut s = format!(
            "src={},dest={},type={},rssi={}",
            f.src_id,
            f.dest_id,
            type_name(f.msg_type),
            g(f64::from(f.rssi_cb) / 10.0)
        );
        io.double("USBL_SRC", f64::from(f.src_id));
        if let Some(r) = f.range_m() {
            io.double("USBL_RANGE", r);
            let _ = write!(s, ",range={}", g(r));
        }
        if let Some(u) = &f.usbl {
            let az = f64::from(u.azimuth_ddeg) / 10.0;
            let el = f64::from(u.elevation_ddeg) / 10.0;
            io.double("USBL_AZIMUTH", az);
            io.double("USBL_ELEVATION", el);
            let _ = write!(s, ",azimuth={},elevation={}", g(az), g(el));
        }
        if let Some(p) = &f.position {
            // Magnetic easting and northing onto true north: bearings grow by the
            // declination.
            let (em, nm) = (
                f64::from(p.easting_dm) / 10.0,
                f64::from(p.northing_dm) / 10.0,
            );
            let (sin, cos) = self.cfg.declination_deg.to_radians().sin_cos();
            let (x, y, z) = (
                em * cos + nm * sin,
                nm * cos - em * sin,
                f64::from(p.depth_dm) / 10.0,
            );
            io.double("USBL_X", x);
            io.double("USBL_Y", y);
            io.double("USBL_Z", z);
            let _ = write!(s, ",x={},y={},z={}", g(x), g(y), g(z));
        }
        io.text("USBL_FIX", s);
    }

    /// The answer to the send at the queue's head.
    fn send_answer(&mut self, cid_name: &str, status: Cst, beacon: u8, now: f64, io: &mut Io) {
        let Some(head) = self.queue.front_mut() else {
            return;
        };
        if !head.awaiting() {
            return;
        }
        match status {
            Cst::XcvrBusy => {
                self.counts.busy += 1;
                head.busy(now, self.cfg.send_wait_s);
            }
            Cst::Ok => {
                self.counts.sent_ok += 1;
                self.queue.pop_front();
                io.text("ACOMMS_TX_ACK", format!("dest={beacon},cid={cid_name}"));
            }
            other => {
                self.counts.send_errors += 1;
                self.queue.pop_front();
                let why = format!("{cid_name} to {beacon}: {other:?}");
                io.text("ACOMMS_ERROR", why.clone());
                io.warnings.push(why);
            }
        }
        if self.queue.len() < QUEUE_WARN {
            self.queue_warned = false;
        }
    }

    fn frame(&mut self, line: &[u8], now: f64, io: &mut Io) {
        // Our own commands echoed (a loopback) are not the beacon's: skip them quietly.
        if line.first() == Some(&b'#') {
            return;
        }
        let r = Response::decode(line);
        self.lines.stats_mut().record(&r);
        let Ok(m) = r else { return };
        match m {
            Response::SysAlive { .. } => {
                if self.startup == Startup::Alive {
                    io.events.push("beacon alive".into());
                    self.step(Startup::SettingsGet, &Command::SettingsGet, now, io);
                }
            }
            Response::SettingsGet(mut s) => {
                if self.startup == Startup::SettingsGet {
                    s.set_beacon_id(self.cfg.beacon_id);
                    s.set_env_salinity_dppt((self.cfg.salinity_ppt * 10.0).round() as u16);
                    s.set_status_mode(STATUS_MODE_10HZ);
                    s.set_status_output(STATUS_OUTPUT);
                    self.step(Startup::SettingsSet, &Command::SettingsSet(s), now, io);
                }
            }
            Response::SettingsSet(c) => {
                if self.startup == Startup::SettingsSet {
                    if c == Cst::Ok {
                        if self.cfg.save_settings {
                            self.step(Startup::SettingsSave, &Command::SettingsSave, now, io);
                        } else {
                            self.running(io);
                        }
                    } else {
                        io.warnings.push(format!("SETTINGS_SET: {c:?}"));
                    }
                }
            }
            Response::SettingsSave(c) => {
                if self.startup == Startup::SettingsSave {
                    if c == Cst::Ok {
                        self.running(io);
                    } else {
                        io.warnings.push(format!("SETTINGS_SAVE: {c:?}"));
                    }
                }
            }
            Response::Status(s) => self.status(s, io),
            Response::PingSend { status, beacon_id } => {
                self.send_answer("PING_SEND", status, beacon_id, now, io);
            }
            Response::DatSend { status, beacon_id } => {
                self.send_answer("DAT_SEND", status, beacon_id, now, io);
            }
            Response::PingReq(f) | Response::PingResp(f) => self.fix(&f, io),
            Response::PingError { status, beacon_id } => {
                self.counts.send_errors += 1;
                io.text("ACOMMS_ERROR", format!("PING to {beacon_id}: {status:?}"));
            }
            Response::DatReceive { fix, ack, data } => {
                self.counts.dat_rx += 1;
                self.fix(&fix, io);
                io.text(
                    "ACOMMS_RX",
                    format!(
                        "src={},dest={},ack={},hex={}",
                        fix.src_id,
                        fix.dest_id,
                        u8::from(ack),
                        hex(&data)
                    ),
                );
            }
            Response::DatError { status, beacon_id } => {
                self.counts.send_errors += 1;
                io.text("ACOMMS_ERROR", format!("DAT to {beacon_id}: {status:?}"));
            }
            Response::Other { .. } => {}
        }
    }

    fn running(&mut self, io: &mut Io) {
        self.startup = Startup::Running;
        io.events.push(format!(
            "configured: beacon {}, status 10 Hz",
            self.cfg.beacon_id
        ));
        io.double("SEATRAC_BEACON_ID", f64::from(self.cfg.beacon_id));
    }
}

/// A message type's name.
fn type_name(t: u8) -> &'static str {
    match t {
        msg_type::OWAY => "OWAY",
        msg_type::OWAYU => "OWAYU",
        msg_type::REQ => "REQ",
        msg_type::RESP => "RESP",
        msg_type::REQU => "REQU",
        msg_type::RESPU => "RESPU",
        msg_type::REQX => "REQX",
        msg_type::RESPX => "RESPX",
        _ => "?",
    }
}

fn type_of(name: &str) -> Option<u8> {
    Some(
        match name.trim().to_ascii_uppercase().trim_start_matches("MSG_") {
            "OWAY" => msg_type::OWAY,
            "OWAYU" => msg_type::OWAYU,
            "REQ" => msg_type::REQ,
            "REQU" => msg_type::REQU,
            "REQX" => msg_type::REQX,
            _ => return None,
        },
    )
}

/// Bytes as uppercase hex.
pub fn hex(data: &[u8]) -> String {
    let mut s = String::with_capacity(data.len() * 2);
    for b in data {
        let _ = write!(s, "{b:02X}");
    }
    s
}

/// Hex (either case, even length) as bytes.
pub fn unhex(s: &str) -> Option<Vec<u8>> {
    let s = s.trim().as_bytes();
    if !s.len().is_multiple_of(2) {
        return None;
    }
    s.chunks(2)
        .map(|p| {
            let d = |c: u8| (c as char).to_digit(16);
            Some((d(p[0])? * 16 + d(p[1])?) as u8)
        })
        .collect()
}

/// Reads `ACOMMS_TX`: `dest=..,hex=..[,type=..]`.
fn parse_tx(s: &str) -> Result<Command, String> {
    let mut dest = None;
    let mut data = None;
    let mut kind = msg_type::OWAYU;
    for part in s.split(',') {
        let (k, v) = part.split_once('=').unwrap_or((part, ""));
        match k.trim().to_ascii_lowercase().as_str() {
            "dest" => dest = v.trim().parse::<u8>().ok().filter(|d| *d <= 15),
            "hex" => data = unhex(v),
            "type" => kind = type_of(v).ok_or_else(|| format!("unknown type `{v}`"))?,
            _ => return Err(format!("unknown field `{}`", k.trim())),
        }
    }
    let dest_id = dest.ok_or("dest: expected a beacon id 0-15")?;
    let data = data.ok_or("hex: expected the payload as hex")?;
    if data.len() > MAX_DAT_PAYLOAD {
        return Err(format!(
            "payload of {} bytes: at most {MAX_DAT_PAYLOAD}",
            data.len()
        ));
    }
    Ok(Command::DatSend {
        dest_id,
        msg_type: kind,
        data,
    })
}

/// Reads `SEATRAC_PING`: `<id>` or `dest=..[,type=..]`.
fn parse_ping(s: &str) -> Result<Command, String> {
    if let Ok(d) = s.trim().parse::<u8>() {
        return (1..=15)
            .contains(&d)
            .then_some(Command::PingSend {
                dest_id: d,
                msg_type: msg_type::REQU,
            })
            .ok_or_else(|| "expected a beacon id 1-15".to_string());
    }
    let mut dest = None;
    let mut kind = msg_type::REQU;
    for part in s.split(',') {
        let (k, v) = part.split_once('=').unwrap_or((part, ""));
        match k.trim().to_ascii_lowercase().as_str() {
            "dest" => dest = v.trim().parse::<u8>().ok().filter(|d| (1..=15).contains(d)),
            "type" => kind = type_of(v).ok_or_else(|| format!("unknown type `{v}`"))?,
            _ => return Err(format!("unknown field `{}`", k.trim())),
        }
    }
    Ok(Command::PingSend {
        dest_id: dest.ok_or("dest: expected a beacon id 1-15")?,
        msg_type: kind,
    })
}

impl Protocol for SeaTrac {
    fn program(&self) -> &'static str {
        PROGRAM
    }

    fn status_var(&self) -> &'static str {
        "SEATRAC_DRIVER_STATUS"
    }

    fn subscriptions(&self) -> Vec<String> {
        vec!["ACOMMS_TX".into(), "SEATRAC_PING".into()]
    }

    fn on_connect(&mut self, now: f64, io: &mut Io) {
        self.lines.reset();
        // A send awaiting its answer on the old connection goes again.
        for q in &mut self.queue {
            q.unsent();
        }
        self.step(Startup::Alive, &Command::SysAlive, now, io);
    }

    fn on_disconnect(&mut self, _now: f64, _io: &mut Io) {
        self.startup = Startup::Waiting;
    }

    fn on_bytes(&mut self, data: &[u8], now: f64, io: &mut Io) {
        let mut got = Vec::new();
        self.lines.push(data, |l| got.push(l.to_vec()));
        for l in got {
            self.frame(&l, now, io);
        }
    }

    fn on_mail(&mut self, key: &str, value: &Value, _now: f64, io: &mut Io) {
        let parsed = match (key, value.as_str()) {
            ("ACOMMS_TX", Some(s)) => parse_tx(s),
            ("SEATRAC_PING", Some(s)) => parse_ping(s),
            ("SEATRAC_PING", None) => match value.as_f64() {
                Some(d) => parse_ping(&g(d)),
                None => Err("expected a beacon id".into()),
            },
            ("ACOMMS_TX", None) => Err("expected a string".into()),
            _ => return,
        };
        match parsed {
            Ok(c) => self.enqueue(c, io),
            Err(why) => io.warnings.push(format!("{key}: {why}")),
        }
    }

    fn tick(&mut self, now: f64, io: &mut Io) {
        let late = now - self.step_sent >= self.cfg.startup_timeout_s - 1e-9;
        let again = match self.startup {
            Startup::Alive if late => Some(Command::SysAlive),
            Startup::SettingsGet if late => Some(Command::SettingsGet),
            // The settings to set came from the beacon: start over from SETTINGS_GET.
            Startup::SettingsSet if late => Some(Command::SettingsGet),
            Startup::SettingsSave if late => Some(Command::SettingsSave),
            _ => None,
        };
        if let Some(c) = again {
            self.counts.startup_retries += 1;
            let s = if c == Command::SettingsGet {
                Startup::SettingsGet
            } else {
                self.startup
            };
            self.step(s, &c, now, io);
            return;
        }
        if self.startup != Startup::Running {
            return;
        }
        let Some(head) = self.queue.front_mut() else {
            return;
        };
        match head.next(now, self.cfg.send_wait_s, self.cfg.send_tries) {
            Next::Wait => {}
            Next::Send => {
                if let Ok(f) = head.cmd.encode() {
                    io.send(f);
                }
                head.sent(now);
            }
            Next::GiveUp => {
                let q = self.queue.pop_front().expect("a head");
                self.counts.send_errors += 1;
                let why = format!("{}: no answer after {} tries", cmd_name(&q.cmd), q.tries());
                io.text("ACOMMS_ERROR", why.clone());
                io.warnings.push(why);
            }
        }
    }

    fn stats(&self) -> LinkStats {
        *self.lines.stats()
    }

    fn state(&self) -> &'static str {
        self.startup.name()
    }

    fn status_extra(&self, out: &mut String) {
        let c = &self.counts;
        let _ = write!(
            out,
            ",status={},fixes={},dat_rx={},sent={},busy={},send_errors={},queue={},\
             startup_retries={}",
            c.status,
            c.fixes,
            c.dat_rx,
            c.sent_ok,
            c.busy,
            c.send_errors,
            self.queue.len(),
            c.startup_retries
        );
    }

    fn report(&self, out: &mut String) {
        let _ = writeln!(
            out,
            "Beacon {}   mount {:?}   declination {} deg   queue {}",
            self.cfg.beacon_id,
            self.cfg.mount,
            g(self.cfg.declination_deg),
            self.queue.len()
        );
        if let Some(s) = &self.last_status {
            if let Some(a) = s.attitude {
                let _ = writeln!(
                    out,
                    "Attitude: yaw {} pitch {} roll {} deg",
                    g(a.yaw_deg()),
                    g(a.pitch_deg()),
                    g(a.roll_deg())
                );
            }
            if let Some(e) = s.environment {
                let _ = writeln!(
                    out,
                    "Environment: depth {} m  supply {} V  temp {} C",
                    g(e.depth_m()),
                    g(e.supply_v()),
                    g(e.temp_degc())
                );
            }
        }
        let c = &self.counts;
        let _ = writeln!(
            out,
            "Status {}  fixes {}  DAT in {}  sends ok {}  busy {}  errors {}",
            c.status, c.fixes, c.dat_rx, c.sent_ok, c.busy, c.send_errors
        );
    }
}

fn cmd_name(c: &Command) -> &'static str {
    match c {
        Command::PingSend { .. } => "PING_SEND",
        Command::DatSend { .. } => "DAT_SEND",
        _ => "command",
    }
}

/// The settings a fresh beacon reports (zeros), for tests and emulators.
pub fn blank_settings() -> Settings {
    Settings {
        raw: [0; seatrac::SETTINGS_LEN],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use devices::seatrac::{AhrsComp, Attitude, Position, Range, Usbl, cid};

    fn doubles(io: &Io, key: &str) -> Vec<f64> {
        io.doubles(key)
    }

    fn texts(io: &Io, key: &str) -> Vec<String> {
        io.texts(key)
    }

    fn sent(io: &Io) -> Vec<Command> {
        io.tx.iter().map(|b| Command::decode(b).unwrap()).collect()
    }

    fn started(cfg: SeaTracConfig) -> (SeaTrac, Io) {
        let mut p = SeaTrac::new(cfg);
        let mut io = Io::default();
        p.on_connect(0.0, &mut io);
        p.on_bytes(
            Response::SysAlive { seconds: 5 }.encode().as_bytes(),
            0.1,
            &mut io,
        );
        p.on_bytes(
            Response::SettingsGet(blank_settings()).encode().as_bytes(),
            0.2,
            &mut io,
        );
        p.on_bytes(
            Response::SettingsSet(Cst::Ok).encode().as_bytes(),
            0.3,
            &mut io,
        );
        p.on_bytes(
            Response::SettingsSave(Cst::Ok).encode().as_bytes(),
            0.4,
            &mut io,
        );
        (p, io)
    }

    fn fix() -> AcoFix {
        AcoFix {
            dest_id: 1,
            src_id: 2,
            msg_type: msg_type::RESPU,
            attitude: Attitude::default(),
            depth_local_dm: 25,
            vos_dmps: 14_810,
            rssi_cb: -652,
            range: Some(Range {
                count: 1000,
                time_100ns: 0,
                dist_dm: 1234,
            }),
            usbl: Some(Usbl {
                rssi_cb: vec![-600; 4],
                azimuth_ddeg: 455,
                elevation_ddeg: -120,
                fit_error_centi: 12,
            }),
            position: Some(Position {
                easting_dm: 872,
                northing_dm: 873,
                depth_dm: 50,
            }),
            position_enhanced: false,
            position_flt_error: false,
        }
    }

    #[test]
    fn the_start_up_sequence_configures_the_beacon() {
        let (p, io) = started(SeaTracConfig {
            beacon_id: 3,
            salinity_ppt: 35.0,
            ..SeaTracConfig::default()
        });
        let cmds = sent(&io);
        assert_eq!(cmds.len(), 4);
        assert_eq!(cmds[0], Command::SysAlive);
        assert_eq!(cmds[1], Command::SettingsGet);
        let Command::SettingsSet(s) = &cmds[2] else {
            panic!("{cmds:?}")
        };
        assert_eq!(s.beacon_id(), 3);
        assert_eq!(s.env_salinity_dppt(), 350);
        assert_eq!(s.status_mode(), STATUS_MODE_10HZ);
        assert_eq!(s.status_output(), STATUS_OUTPUT);
        assert_eq!(cmds[3], Command::SettingsSave);
        assert_eq!(p.startup(), Startup::Running);
        assert_eq!(doubles(&io, "SEATRAC_BEACON_ID"), [3.0]);
        // The frames on the wire: `#`, the CID in hex, the CRC (4 hex), CRLF.
        assert!(io.tx[0].starts_with(b"#01") && io.tx[0].ends_with(b"\r\n"));
        assert_eq!(io.tx[0].len(), 9);
    }

    #[test]
    fn an_unanswered_alive_is_sent_again() {
        let mut p = SeaTrac::new(SeaTracConfig::default());
        let mut io = Io::default();
        p.on_connect(0.0, &mut io);
        p.tick(0.5, &mut io);
        p.tick(1.0, &mut io);
        p.tick(2.0, &mut io);
        assert_eq!(sent(&io), vec![Command::SysAlive; 3]);
        assert_eq!(p.counts().startup_retries, 2);
        assert_eq!(p.state(), "alive");
    }

    #[test]
    fn status_becomes_the_ahrs_and_environment_variables() {
        let (mut p, _) = started(SeaTracConfig {
            declination_deg: 10.7,
            ..SeaTracConfig::default()
        });
        let mut io = Io::default();
        let st = Status {
            timestamp_ms: 1234,
            ahrs_comp: Some(AhrsComp {
                acc: [0.0, 0.0, 1.0],
                mag: [0.0; 3],
                gyro: [1.0, 3.0, -2.0],
            }),
            ..devices::samples::seatrac_status_fields()
        };
        p.on_bytes(Response::Status(st).encode().as_bytes(), 1.0, &mut io);
        let keys: Vec<&str> = io.posts.iter().map(|p| &*p.key).collect();
        assert_eq!(
            keys,
            [
                "AHRS_PITCH",
                "AHRS_ROLL",
                "AHRS_ROLL_RATE",
                "AHRS_PITCH_RATE",
                "AHRS_YAW_RATE",
                "AHRS_HEADING",
                "SEATRAC_DEPTH",
                "SEATRAC_SUPPLY_VOLTAGE",
                "SEATRAC_TEMP",
                "SEATRAC_PRESSURE",
                "SEATRAC_VOS"
            ]
        );
        assert_eq!(doubles(&io, "AHRS_PITCH"), [-2.5]);
        let h = doubles(&io, "AHRS_HEADING")[0];
        assert!((h - 5.7).abs() < 1e-9, "355 + 10.7 wraps to 5.7: {h}");
        let r = std::f64::consts::FRAC_1_SQRT_2;
        assert!((doubles(&io, "AHRS_ROLL_RATE")[0] - r * 2.0).abs() < 1e-12);
        assert!((doubles(&io, "AHRS_PITCH_RATE")[0] - r * 4.0).abs() < 1e-12);
        assert_eq!(doubles(&io, "AHRS_YAW_RATE"), [2.0]);
        assert_eq!(doubles(&io, "SEATRAC_DEPTH"), [1.2]);
        assert_eq!(doubles(&io, "SEATRAC_SUPPLY_VOLTAGE"), [15.6]);
        assert_eq!(doubles(&io, "SEATRAC_PRESSURE"), [110_000.0]);
    }

    #[test]
    fn dat_is_sent_retried_on_busy_and_received_with_its_fix() {
        let (mut p, _) = started(SeaTracConfig::default());
        let mut io = Io::default();
        p.on_mail(
            "ACOMMS_TX",
            &Value::String("dest=2,hex=0a0B".into()),
            1.0,
            &mut io,
        );
        p.tick(1.0, &mut io);
        let dat = Command::DatSend {
            dest_id: 2,
            msg_type: msg_type::OWAYU,
            data: vec![0x0A, 0x0B],
        };
        assert_eq!(sent(&io), std::slice::from_ref(&dat));
        let busy = Response::DatSend {
            status: Cst::XcvrBusy,
            beacon_id: 2,
        };
        p.on_bytes(busy.encode().as_bytes(), 1.1, &mut io);
        p.tick(1.2, &mut io);
        assert_eq!(io.tx.len(), 1, "waits send_wait after busy");
        p.tick(1.6, &mut io);
        assert_eq!(sent(&io), [dat.clone(), dat]);
        let ok = Response::DatSend {
            status: Cst::Ok,
            beacon_id: 2,
        };
        p.on_bytes(ok.encode().as_bytes(), 1.7, &mut io);
        assert_eq!(p.queued(), 0);
        assert_eq!(texts(&io, "ACOMMS_TX_ACK"), ["dest=2,cid=DAT_SEND"]);
        assert_eq!(p.counts().busy, 1);
        let rx = Response::DatReceive {
            fix: fix(),
            ack: false,
            data: vec![0xDE, 0xAD],
        };
        let mut io = Io::default();
        p.on_bytes(rx.encode().as_bytes(), 2.0, &mut io);
        assert_eq!(doubles(&io, "USBL_RANGE"), [123.4]);
        assert_eq!(doubles(&io, "USBL_AZIMUTH"), [45.5]);
        assert_eq!(doubles(&io, "USBL_ELEVATION"), [-12.0]);
        assert_eq!(doubles(&io, "USBL_X"), [87.2]);
        assert_eq!(doubles(&io, "USBL_Z"), [5.0]);
        assert_eq!(
            texts(&io, "USBL_FIX"),
            [
                "src=2,dest=1,type=RESPU,rssi=-65.2,range=123.4,azimuth=45.5,elevation=-12,x=87.2,y=87.3,z=5"
            ]
        );
        assert_eq!(texts(&io, "ACOMMS_RX"), ["src=2,dest=1,ack=0,hex=DEAD"]);
    }

    #[test]
    fn pings_errors_and_bad_requests() {
        let (mut p, _) = started(SeaTracConfig::default());
        let mut io = Io::default();
        p.on_mail("SEATRAC_PING", &Value::Double(2.0), 1.0, &mut io);
        p.on_mail(
            "ACOMMS_TX",
            &Value::String("dest=2,hex=0".into()),
            1.0,
            &mut io,
        );
        p.on_mail(
            "ACOMMS_TX",
            &Value::String(format!("dest=2,hex={}", "00".repeat(32)).into()),
            1.0,
            &mut io,
        );
        assert_eq!(io.warnings.len(), 2, "{:?}", io.warnings);
        p.tick(1.0, &mut io);
        assert_eq!(
            sent(&io),
            [Command::PingSend {
                dest_id: 2,
                msg_type: msg_type::REQU
            }]
        );
        let refused = Response::PingSend {
            status: Cst::CmdParamInvalid,
            beacon_id: 2,
        };
        p.on_bytes(refused.encode().as_bytes(), 1.1, &mut io);
        assert_eq!(
            texts(&io, "ACOMMS_ERROR"),
            ["PING_SEND to 2: CmdParamInvalid"]
        );
        assert_eq!(p.queued(), 0);
        // Never answered: three tries, then an error.
        p.on_mail(
            "SEATRAC_PING",
            &Value::String("dest=4,type=REQX".into()),
            2.0,
            &mut io,
        );
        for t in [2.0, 2.5, 3.0, 3.5] {
            p.tick(t, &mut io);
        }
        assert_eq!(io.tx.len(), 4);
        assert_eq!(
            texts(&io, "ACOMMS_ERROR")[1],
            "PING_SEND: no answer after 3 tries"
        );
    }

    /// A PING_RESP built byte by byte from the UM-140 field tables (ACOFIX with the range,
    /// USBL and position blocks): the local beacon 1 at 10 m heading north, level; the
    /// remote beacon 15 due east 20 m away and 20 m deeper (at 30 m), i.e. 45° down.
    #[test]
    fn a_fix_built_from_the_field_tables_is_read_with_its_conventions() {
        let le16 = |v: i16| v.to_le_bytes();
        let mut m = vec![cid::PING_RESP];
        m.extend([1, 15, 0x07, msg_type::RESPU]); // dest, src, flags: range|usbl|position
        for a in [0i16, 0, 0] {
            m.extend(le16(a)); // yaw, pitch, roll (deci-degrees)
        }
        m.extend(100u16.to_le_bytes()); // depth_local: 10 m, dm
        m.extend(14_750u16.to_le_bytes()); // vos: 1475 m/s, dm/s
        m.extend(le16(-600)); // rssi: -60 dB, cB
        let slant = 20f64.hypot(20.0);
        m.extend(((2.0 * slant / 1475.0 * 16_000.0).round() as u32).to_le_bytes()); // count
        m.extend(((slant / 1475.0 * 1e7).round() as i32).to_le_bytes()); // time, 100 ns
        m.extend(((slant * 10.0).round() as u16).to_le_bytes()); // dist: 28.3 m, dm
        m.push(4); // channels
        for r in [-600i16, -605, -598, -602] {
            m.extend(le16(r));
        }
        m.extend(le16(900)); // azimuth: 90.0 deg, to starboard of the bow (north): east
        m.extend(le16(-450)); // elevation: 45.0 deg below
        m.extend(le16(12)); // fit error 0.12
        m.extend(le16(200)); // easting 20 m
        m.extend(le16(0)); // northing 0
        m.extend(le16(300)); // the remote's depth, 30 m
        let frame = seatrac::encode_frame(seatrac::Direction::Response, &m);
        let (mut p, _) = started(SeaTracConfig::default());
        let mut io = Io::default();
        p.on_bytes(frame.as_bytes(), 5.0, &mut io);
        assert_eq!(p.stats().parse_errors + p.stats().bad_checksum, 0);
        assert_eq!(doubles(&io, "USBL_SRC"), [15.0]);
        assert_eq!(doubles(&io, "USBL_RANGE"), [28.3]);
        assert_eq!(doubles(&io, "USBL_AZIMUTH"), [90.0]);
        assert_eq!(doubles(&io, "USBL_ELEVATION"), [-45.0]);
        assert_eq!(doubles(&io, "USBL_X"), [20.0]);
        assert_eq!(doubles(&io, "USBL_Y"), [0.0]);
        assert_eq!(doubles(&io, "USBL_Z"), [30.0]);
        assert_eq!(
            texts(&io, "USBL_FIX"),
            ["src=15,dest=1,type=RESPU,rssi=-60,range=28.3,azimuth=90,elevation=-45,x=20,y=0,z=30"]
        );
        // The range, angles and local depth agree with the position block: horizontal
        // distance r·cos(el) along the azimuth, the remote r·sin(-el) deeper.
        let (az, el) = (90f64.to_radians(), (-45f64).to_radians());
        let h = 28.3 * el.cos();
        assert!((h * az.sin() - 20.0).abs() < 0.05 && (h * az.cos()).abs() < 1e-9);
        assert!((10.0 - 28.3 * el.sin() - 30.0).abs() < 0.05);
    }

    /// The position block is on magnetic north (UM-140 §6.4.2: resolved with the magnetic
    /// heading): with the declination configured, the driver posts it on true north. The
    /// beacon 20 m true east, at 10° E of declination, writes easting 19.7 m and northing
    /// 3.5 m.
    #[test]
    fn the_fix_position_is_turned_from_magnetic_to_true_north() {
        let le16 = |v: i16| v.to_le_bytes();
        let mut m = vec![cid::PING_RESP];
        m.extend([1, 15, 0x04, msg_type::RESPU]); // flags: position only
        for a in [0i16, 0, 0] {
            m.extend(le16(a));
        }
        m.extend(100u16.to_le_bytes());
        m.extend(14_750u16.to_le_bytes());
        m.extend(le16(-600));
        m.extend(le16(197)); // easting 19.7 m, magnetic
        m.extend(le16(35)); // northing 3.5 m, magnetic
        m.extend(le16(300));
        let frame = seatrac::encode_frame(seatrac::Direction::Response, &m);
        let cfg = SeaTracConfig {
            declination_deg: 10.0,
            ..SeaTracConfig::default()
        };
        let (mut p, _) = started(cfg);
        let mut io = Io::default();
        p.on_bytes(frame.as_bytes(), 5.0, &mut io);
        let (x, y) = (doubles(&io, "USBL_X")[0], doubles(&io, "USBL_Y")[0]);
        assert!((x - 20.0).abs() < 0.05 && y.abs() < 0.05, "({x}, {y})");
        assert_eq!(doubles(&io, "USBL_Z"), [30.0]);
        // Without a declination the block is posted as written.
        let (mut p, _) = started(SeaTracConfig::default());
        let mut io = Io::default();
        p.on_bytes(frame.as_bytes(), 5.0, &mut io);
        assert_eq!(doubles(&io, "USBL_X"), [19.7]);
        assert_eq!(doubles(&io, "USBL_Y"), [3.5]);
    }

    /// The chip's gyro for known body rates through the 45° mount: turning right (positive
    /// yaw rate, FRD) with the nose coming up and rolling to starboard.
    #[test]
    fn the_45_degree_mount_gives_body_rates() {
        let (mut p, _) = started(SeaTracConfig::default());
        let r = std::f64::consts::FRAC_1_SQRT_2;
        // Body rates p, q, r = 1, 2, 10 deg/s; the chip's axes are the body's turned by the
        // inverse of the converter's mapping: gx = √½(q − p), gy = √½(p + q), gz = −r.
        let (bp, bq, br) = (1.0f64, 2.0f64, 10.0f64);
        let gyro = [r * (bq - bp), r * (bp + bq), -br].map(|v| v as f32);
        let st = Status {
            timestamp_ms: 1,
            environment: None,
            attitude: Some(Attitude::default()),
            mag_cal: None,
            acc_cal: None,
            ahrs_raw: None,
            ahrs_comp: Some(AhrsComp {
                acc: [0.0; 3],
                mag: [0.0; 3],
                gyro,
            }),
        };
        let mut io = Io::default();
        p.on_bytes(Response::Status(st).encode().as_bytes(), 1.0, &mut io);
        for (k, want) in [
            ("AHRS_ROLL_RATE", bp),
            ("AHRS_PITCH_RATE", bq),
            ("AHRS_YAW_RATE", br),
        ] {
            let got = doubles(&io, k)[0];
            assert!((got - want).abs() < 1e-5, "{k}: {got} != {want}");
        }
    }

    #[test]
    fn garbage_and_bad_crcs_are_counted() {
        let (mut p, _) = started(SeaTracConfig::default());
        let mut io = Io::default();
        let mut f = Response::SysAlive { seconds: 1 }.encode();
        f.replace_range(3..4, if &f[3..4] == "0" { "1" } else { "0" });
        p.on_bytes(b"\xff\xfenoise", 1.0, &mut io);
        p.on_bytes(f.as_bytes(), 1.0, &mut io);
        let st = p.stats();
        assert_eq!(st.garbage_bytes, 7);
        assert_eq!(st.bad_checksum, 1);
    }
}
