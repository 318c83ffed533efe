//! The SeaTrac X150 USBL modem on its serial line (`cougars-vehicle.md` §3.5; Blueprint
//! Subsea UM-140): `#`-framed commands in, `$`-framed answers and events out, with their
//! CRC16.
//!
//! | command | answer |
//! |---|---|
//! | SYS_ALIVE | SYS_ALIVE with the seconds since power-up |
//! | STATUS (blocks) | a STATUS with those blocks |
//! | SETTINGS_GET | the settings (110 bytes) |
//! | SETTINGS_SET | status OK, the settings in effect at once (status rate, blocks, beacon id, salinity); CMD_PARAM_INVALID and no change for a beacon id outside 1–15 |
//! | SETTINGS_SAVE | status OK (the saved copy is what a power-up would start with) |
//! | PING_SEND | PING_SEND with OK (or XCVR_BUSY), then PING_RESP with the fix after the sound's round trip, or PING_ERROR XCVR_RESP_TIMEOUT after 4 s when no beacon answers |
//! | DAT_SEND | DAT_SEND with OK (or XCVR_BUSY); for a request type (REQ, REQU, REQX) a DAT_RECEIVE (ack set) with the remote's answer and the fix after the round trip, or DAT_ERROR XCVR_RESP_TIMEOUT after 4 s |
//! | a frame with a bad CRC, or a CID this emulator does not know | nothing (counted) |
//!
//! DAT_SEND frames are read as the CoUGARs driver writes them: the payload length byte,
//! then the payload, then whatever padding the driver's fixed 31-byte array adds (ignored).
//!
//! The transceiver is busy (XCVR_BUSY) while a request waits for its answer and for 0.4 s
//! after any transmission, and, with [`X150Settings::busy_prob`], at random; the first
//! [`X150Settings::busy_first`] sends are refused as busy whatever the channel.
//!
//! STATUS goes out at the settings' rate (0 manual, then 1, 2.5, 5, 10, 25 Hz) with the
//! settings' blocks:
//! - ENVIRONMENT: supply (the battery, 16.4 V less the falling-battery fault), 15 °C, the
//!   absolute pressure in mbar, the depth (σ 0.1 m, the modem's depth sensor), the speed of
//!   sound;
//! - ATTITUDE: the AHRS model of `vehicle::sensors::ahrs` (noise, bias, decidegrees), the
//!   yaw magnetic (the true heading less [`X150Settings::declination_deg`], as the real
//!   AHRS gives it and the driver corrects);
//! - AHRS_COMP_DATA: accelerometer (g), magnetometer (µT, an Earth field of 21, 4, 46 µT
//!   north, east, down) and gyro (deg/s), in the modem's frame ([`Mount`]);
//! - MAG_CAL and ACC_CAL: a valid calibration; AHRS_RAW_DATA: the compensated values scaled
//!   to the raw units (1 g = 250).
//!
//! Acoustic fixes follow the HoloOcean modem bridge: range on responses, USBL angles (σ 1°)
//! on OWAYU, REQU, RESPU, REQX and RESPX, position on RESPU and RESPX (enhanced on RESPX).
//! The azimuth is the bearing of the remote beacon relative to the local heading, 0–360°;
//! the elevation is positive when the remote beacon is above (shallower; the vendor's
//! document gives only the range −90..90, see `drivers::seatrac`); the position is the
//! remote beacon's easting and northing relative to the local beacon on *magnetic* north
//! (the real beacon resolves them with its magnetic heading, UM-140 §6.4.2: the true
//! offsets turned by [`X150Settings::declination_deg`]) and its depth below the surface.

use devices::line::LineSplitter;
use devices::seatrac::{
    self, AcoFix, AhrsComp, Attitude, Command, Cst, Environment, MagCal, Position, Range, Response,
    Settings, Status, Usbl, cid, msg_type, status_bits,
};
use vehicle::angle::{angle180, angle360};
use vehicle::sensors::ahrs::{Ahrs, AhrsConfig};
use vehicle::sensors::{Noise, Schedule};

use crate::device::{Device, Situation};
use crate::truth::Truth;

/// How long a request waits for its answer, s.
pub const RESPONSE_TIMEOUT_S: f64 = 4.0;

/// How long the channel stays busy after a transmission, s.
pub const CHANNEL_BUSY_S: f64 = 0.4;

/// The speed of sound the beacon uses, m/s.
pub const VOS_MPS: f64 = 1475.0;

/// How the modem sits in the vehicle: the frame of its accelerometer, magnetometer and gyro.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mount {
    /// Aligned with the vehicle (forward, starboard, down).
    Body,
    /// As on the CoUGARs vehicles (`cougars-vehicle.md` "What a Rust re-implementation must
    /// match": the driver turns the gyro into body rates with `ω = [√½(gy − gx),
    /// √½(gx + gy), −gz]`): the emulator writes the inverse, `gx = √½(ω₁ − ω₀)`,
    /// `gy = √½(ω₀ + ω₁)`, `gz = −ω₂`, and the same for the accelerometer and magnetometer.
    Cougars,
}

impl Mount {
    /// The modem-frame vector of a body-frame one.
    pub fn from_body(self, v: [f64; 3]) -> [f64; 3] {
        match self {
            Mount::Body => v,
            Mount::Cougars => {
                let a = std::f64::consts::FRAC_1_SQRT_2;
                [a * (v[1] - v[0]), a * (v[0] + v[1]), -v[2]]
            }
        }
    }
}

/// Another beacon in the water, answering this one's requests.
pub trait RemoteBeacon: Send {
    /// Its beacon id (1–15).
    fn id(&self) -> u8;
    /// Where it is at `t`: metres east and north of the origin, depth (m, positive down).
    fn position(&mut self, t: f64) -> (f64, f64, f64);
    /// It received a message from `src_id` at `t`; for a request type it returns its answer
    /// (the data of the response; empty for a ping), or `None` to stay silent.
    fn on_message(&mut self, t: f64, src_id: u8, msg_type: u8, data: &[u8]) -> Option<Vec<u8>>;
    /// Messages it sends on its own by `t`: (destination id, message type, data).
    fn poll(&mut self, t: f64) -> Vec<(u8, u8, Vec<u8>)> {
        let _ = t;
        Vec::new()
    }
}

/// A beacon standing still that echoes every request's data back (the local loopback).
#[derive(Debug, Clone)]
pub struct EchoBeacon {
    /// Its id (15, the CoUGARs base station).
    pub id: u8,
    /// Its position (x east, y north, depth), m.
    pub position: (f64, f64, f64),
    /// What it has received: (time, source id, message type, data).
    pub received: Vec<(f64, u8, u8, Vec<u8>)>,
}

impl Default for EchoBeacon {
    fn default() -> Self {
        EchoBeacon {
            id: 15,
            position: (0.0, 0.0, 1.0),
            received: Vec::new(),
        }
    }
}

impl RemoteBeacon for EchoBeacon {
    fn id(&self) -> u8 {
        self.id
    }
    fn position(&mut self, _: f64) -> (f64, f64, f64) {
        self.position
    }
    fn on_message(&mut self, t: f64, src_id: u8, msg_type: u8, data: &[u8]) -> Option<Vec<u8>> {
        self.received.push((t, src_id, msg_type, data.to_vec()));
        Some(data.to_vec())
    }
}

/// The X150's settings.
pub struct X150Settings {
    /// The settings at power-up (beacon id 1, status off, no blocks, salinity 0).
    pub settings: Settings,
    /// The AHRS model (its rate is not used: attitude goes with each STATUS).
    pub ahrs: AhrsConfig,
    /// Magnetic declination, degrees east (0): the yaw written is the true heading less it.
    pub declination_deg: f64,
    /// How the modem is mounted.
    pub mount: Mount,
    /// Chance that a send is refused with XCVR_BUSY although the channel is free (0).
    pub busy_prob: f64,
    /// The first this many sends (PING_SEND, DAT_SEND) are refused with XCVR_BUSY whatever
    /// the channel (0): a deterministic busy transceiver for the drivers' retry tests.
    pub busy_first: u32,
    /// Supply voltage with no fault, V (16.4, the vehicle battery).
    pub supply_v: f64,
    /// Atmospheric pressure, Pa (101325), and water density, kg/m³ (997), for the pressure.
    pub atmospheric_pa: f64,
    /// Water density, kg/m³.
    pub density_kgm3: f64,
    /// The other beacon.
    pub remote: Box<dyn RemoteBeacon>,
}

impl Default for X150Settings {
    fn default() -> Self {
        let mut settings = Settings {
            raw: [0; seatrac::SETTINGS_LEN],
        };
        settings.set_beacon_id(1);
        X150Settings {
            settings,
            ahrs: AhrsConfig::default(),
            declination_deg: 0.0,
            mount: Mount::Cougars,
            busy_prob: 0.0,
            busy_first: 0,
            supply_v: 16.4,
            atmospheric_pa: 101_325.0,
            density_kgm3: 997.0,
            remote: Box::new(EchoBeacon::default()),
        }
    }
}

/// An acoustic exchange in flight.
#[derive(Debug, Clone)]
enum Pending {
    /// A ping's answer (or its timeout) is due.
    Ping { dest: u8, msg_type: u8 },
    /// A data request's answer (or its timeout) is due.
    Dat {
        dest: u8,
        msg_type: u8,
        answer: Option<Vec<u8>>,
    },
}

/// The STATUS rate of a settings' status mode, Hz (0 for manual).
pub fn status_rate_hz(mode: u8) -> f64 {
    match mode {
        1 => 1.0,
        2 => 2.5,
        3 => 5.0,
        4 => 10.0,
        5 => 25.0,
        _ => 0.0,
    }
}

fn ddeg(deg: f64) -> i16 {
    (deg * 10.0).round().clamp(-32768.0, 32767.0) as i16
}

fn dm_i16(m: f64) -> i16 {
    (m * 10.0).round().clamp(-32768.0, 32767.0) as i16
}

/// Counters of what the beacon was sent.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct X150Counts {
    /// Commands decoded and answered.
    pub commands: u64,
    /// Frames refused (bad CRC, bad hex, unknown CID, bad length).
    pub refused: u64,
    /// Sends refused with XCVR_BUSY.
    pub busy: u64,
}

/// The X150.
pub struct X150 {
    cfg: X150Settings,
    settings: Settings,
    saved: Settings,
    ahrs: Ahrs,
    noise: Noise,
    status: Schedule,
    lines: LineSplitter,
    /// The exchange in flight and when it completes.
    pending: Option<(f64, Pending)>,
    busy_until: f64,
    /// Sends still to refuse from [`X150Settings::busy_first`].
    forced_busy: u32,
    counts: X150Counts,
}

impl X150 {
    /// An X150 with these settings, drawing from `seed`.
    pub fn new(cfg: X150Settings, seed: u64) -> Self {
        let mut ahrs_cfg = cfg.ahrs.clone();
        ahrs_cfg.rate_hz = 1e6;
        X150 {
            settings: cfg.settings.clone(),
            saved: cfg.settings.clone(),
            ahrs: Ahrs::new(ahrs_cfg, seed),
            noise: Noise::new(seed, 0x5ea7),
            status: Schedule::default(),
            lines: LineSplitter::new(seatrac::MAX_FRAME).with_starts(b"#$"),
            pending: None,
            busy_until: f64::NEG_INFINITY,
            forced_busy: cfg.busy_first,
            counts: X150Counts::default(),
            cfg,
        }
    }

    /// The settings in effect.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// The settings last saved.
    pub fn saved_settings(&self) -> &Settings {
        &self.saved
    }

    /// What it was sent.
    pub fn counts(&self) -> X150Counts {
        self.counts
    }

    fn attitude(&mut self, truth: &Truth) -> (Attitude, [f64; 3]) {
        let r = self
            .ahrs
            .sample(truth)
            .unwrap_or(vehicle::sensors::AhrsReport {
                time: truth.time,
                heading_deg: truth.heading_deg,
                pitch_deg: truth.pitch_rad.to_degrees(),
                roll_deg: truth.roll_rad.to_degrees(),
                gyro_deg_s: [0.0; 3],
            });
        let yaw = angle360(r.heading_deg - self.cfg.declination_deg);
        (
            Attitude {
                yaw_ddeg: ddeg(yaw) % 3600,
                pitch_ddeg: ddeg(r.pitch_deg),
                roll_ddeg: ddeg(r.roll_deg),
            },
            r.gyro_deg_s,
        )
    }

    fn status_message(&mut self, s: &Situation, blocks: u8) -> Status {
        let truth = &s.truth;
        let has = |b: u8| blocks & b != 0;
        let environment = has(status_bits::ENVIRONMENT).then(|| {
            let depth = (truth.depth + self.noise.gauss(0.1)).max(0.0);
            let pa = self.cfg.atmospheric_pa + self.cfg.density_kgm3 * 9.81 * truth.depth.max(0.0);
            Environment {
                supply_mv: ((self.cfg.supply_v - s.battery_drop_v).max(0.0) * 1000.0)
                    .round()
                    .min(65535.0) as u16,
                temp_ddegc: 150,
                pressure_mbar: (pa / 100.0).round() as i32,
                depth_dm: (depth * 10.0).round() as i32,
                vos_dmps: (VOS_MPS * 10.0) as u16,
            }
        });
        let (attitude, gyro) = self.attitude(truth);
        // Specific force and the Earth's field in the body frame (FRD).
        let (st, ct) = truth.pitch_rad.sin_cos();
        let (sr, cr) = truth.roll_rad.sin_cos();
        let acc_body = [st, -sr * ct, -cr * ct];
        let (sp, cp) = truth.heading_deg.to_radians().sin_cos();
        let m = [21.0, 4.0, 46.0];
        let mag_body = [
            ct * cp * m[0] + ct * sp * m[1] - st * m[2],
            (sr * st * cp - cr * sp) * m[0] + (sr * st * sp + cr * cp) * m[1] + sr * ct * m[2],
            (cr * st * cp + sr * sp) * m[0] + (cr * st * sp - sr * cp) * m[1] + cr * ct * m[2],
        ];
        let mount = self.cfg.mount;
        let f32s = |v: [f64; 3]| v.map(|x| x as f32);
        let comp = AhrsComp {
            acc: f32s(mount.from_body(acc_body)),
            mag: f32s(mount.from_body(mag_body)),
            gyro: f32s(mount.from_body(gyro)),
        };
        let raw = |v: [f32; 3], k: f64| {
            v.map(|x| (f64::from(x) * k).round().clamp(-32768.0, 32767.0) as i16)
        };
        let [a, mg, g] = [
            raw(comp.acc, 250.0),
            raw(comp.mag, 10.0),
            raw(comp.gyro, 10.0),
        ];
        Status {
            timestamp_ms: (s.t.max(0.0) * 1000.0).round() as u64,
            environment,
            attitude: has(status_bits::ATTITUDE).then_some(attitude),
            mag_cal: has(status_bits::MAG_CAL).then_some(MagCal {
                buf_pct: 100,
                valid: true,
                age_s: s.t.max(0.0) as u32,
                fit_pct: 98,
            }),
            acc_cal: has(status_bits::ACC_CAL).then_some([-250, -250, -250, 250, 250, 250]),
            ahrs_raw: has(status_bits::AHRS_RAW_DATA)
                .then_some([a[0], a[1], a[2], mg[0], mg[1], mg[2], g[0], g[1], g[2]]),
            ahrs_comp: has(status_bits::AHRS_COMP_DATA).then_some(comp),
        }
    }

    /// The fix of a message from the remote beacon arriving now.
    fn fix(&mut self, s: &Situation, src: u8, kind: u8) -> AcoFix {
        let truth = &s.truth;
        let (rx, ry, rd) = self.cfg.remote.position(s.t);
        let (dx, dy, dz) = (rx - truth.x, ry - truth.y, rd - truth.depth);
        let horizontal = dx.hypot(dy);
        let slant = horizontal.hypot(dz);
        let (attitude, _) = self.attitude(truth);
        let response = matches!(kind, msg_type::RESP | msg_type::RESPU | msg_type::RESPX);
        let usbl = matches!(
            kind,
            msg_type::OWAYU | msg_type::REQU | msg_type::RESPU | msg_type::REQX | msg_type::RESPX
        );
        let position = matches!(kind, msg_type::RESPU | msg_type::RESPX);
        let range = response.then(|| {
            let r = (slant + self.noise.gauss(0.1)).max(0.0);
            Range {
                count: (2.0 * r / VOS_MPS * 16_000.0).round() as u32,
                time_100ns: (r / VOS_MPS * 1e7).round() as i32,
                dist_dm: (r * 10.0).round().min(65535.0) as u16,
            }
        });
        let usbl = usbl.then(|| {
            let bearing = dx.atan2(dy).to_degrees();
            let az = angle360(bearing - truth.heading_deg + self.noise.gauss(1.0));
            let el = (-dz).atan2(horizontal).to_degrees() + self.noise.gauss(1.0);
            Usbl {
                rssi_cb: vec![-600, -605, -598, -602],
                azimuth_ddeg: ddeg(az) % 3600,
                elevation_ddeg: ddeg(angle180(el)),
                fit_error_centi: 12,
            }
        });
        // The beacon resolves the position with its magnetic heading: true bearings less
        // the declination.
        let (sin, cos) = self.cfg.declination_deg.to_radians().sin_cos();
        let position = position.then(|| Position {
            easting_dm: dm_i16(dx * cos - dy * sin),
            northing_dm: dm_i16(dy * cos + dx * sin),
            depth_dm: dm_i16(rd),
        });
        AcoFix {
            dest_id: self.settings.beacon_id(),
            src_id: src,
            msg_type: kind,
            attitude,
            depth_local_dm: (truth.depth.max(0.0) * 10.0).round().min(65535.0) as u16,
            vos_dmps: (VOS_MPS * 10.0) as u16,
            rssi_cb: -600,
            range,
            usbl,
            position,
            position_enhanced: kind == msg_type::RESPX,
            position_flt_error: false,
        }
    }

    /// The one-way travel time to the remote beacon, s.
    fn travel_s(&mut self, s: &Situation) -> f64 {
        let (rx, ry, rd) = self.cfg.remote.position(s.t);
        let d = (rx - s.truth.x)
            .hypot(ry - s.truth.y)
            .hypot(rd - s.truth.depth);
        d / VOS_MPS
    }

    /// XCVR_BUSY now?
    fn busy(&mut self, t: f64) -> bool {
        let forced = self.forced_busy > 0;
        self.forced_busy = self.forced_busy.saturating_sub(1);
        let b = forced
            || self.pending.is_some()
            || t < self.busy_until
            || (self.cfg.busy_prob > 0.0 && self.noise.uniform() < self.cfg.busy_prob);
        if b {
            self.counts.busy += 1;
        }
        b
    }

    fn send(&mut self, s: &Situation, dest: u8, kind: u8, data: &[u8], ping: bool) -> Response {
        if self.busy(s.t) {
            return if ping {
                Response::PingSend {
                    status: Cst::XcvrBusy,
                    beacon_id: dest,
                }
            } else {
                Response::DatSend {
                    status: Cst::XcvrBusy,
                    beacon_id: dest,
                }
            };
        }
        self.busy_until = s.t + CHANNEL_BUSY_S;
        let remote_id = self.cfg.remote.id();
        let heard = dest == remote_id || dest == 0;
        let answer = if heard {
            let me = self.settings.beacon_id();
            self.cfg.remote.on_message(s.t, me, kind, data)
        } else {
            None
        };
        let request = matches!(kind, msg_type::REQ | msg_type::REQU | msg_type::REQX);
        if ping || request {
            let due = match &answer {
                Some(_) => s.t + 2.0 * self.travel_s(s) + 0.05,
                None => s.t + RESPONSE_TIMEOUT_S,
            };
            let p = if ping {
                Pending::Ping {
                    dest,
                    msg_type: if answer.is_some() { kind } else { 0xff },
                }
            } else {
                Pending::Dat {
                    dest,
                    msg_type: kind,
                    answer,
                }
            };
            self.pending = Some((due, p));
        }
        if ping {
            Response::PingSend {
                status: Cst::Ok,
                beacon_id: dest,
            }
        } else {
            Response::DatSend {
                status: Cst::Ok,
                beacon_id: dest,
            }
        }
    }

    fn command(&mut self, s: &Situation, line: &[u8]) -> Option<Response> {
        // DAT_SEND as the driver writes it (with padding after the payload).
        if let Ok((seatrac::Direction::Command, msg)) = seatrac::decode_frame(line)
            && msg.first() == Some(&cid::DAT_SEND)
        {
            let (dest, kind, n) = match msg.get(1..4) {
                Some(&[d, k, n]) => (d, k, usize::from(n)),
                _ => return None,
            };
            let data = msg
                .get(4..4 + n)
                .filter(|_| n <= seatrac::MAX_DAT_PAYLOAD)?;
            let data = data.to_vec();
            self.counts.commands += 1;
            return Some(self.send(s, dest, kind, &data, false));
        }
        let cmd = Command::decode(line).ok()?;
        self.counts.commands += 1;
        Some(match cmd {
            Command::SysAlive => Response::SysAlive {
                seconds: s.t.max(0.0) as u32,
            },
            Command::Status { output } => Response::Status(self.status_message(s, output)),
            Command::SettingsGet => Response::SettingsGet(self.settings.clone()),
            Command::SettingsSet(new) => {
                if !(1..=15).contains(&new.beacon_id()) {
                    Response::SettingsSet(Cst::CmdParamInvalid)
                } else {
                    if new.status_mode() != self.settings.status_mode() {
                        self.status = Schedule::default();
                    }
                    self.settings = new;
                    Response::SettingsSet(Cst::Ok)
                }
            }
            Command::SettingsSave => {
                self.saved = self.settings.clone();
                Response::SettingsSave(Cst::Ok)
            }
            Command::PingSend { dest_id, msg_type } => self.send(s, dest_id, msg_type, &[], true),
            Command::DatSend { .. } => return None,
        })
    }

    fn complete(&mut self, s: &Situation, p: Pending) -> Response {
        match p {
            Pending::Ping { msg_type, .. } if msg_type != 0xff => {
                let src = self.cfg.remote.id();
                Response::PingResp(self.fix(s, src, msg_type + 1))
            }
            Pending::Ping { dest, .. } => Response::PingError {
                status: Cst::XcvrRespTimeout,
                beacon_id: dest,
            },
            Pending::Dat {
                msg_type,
                answer: Some(data),
                ..
            } => {
                let src = self.cfg.remote.id();
                let mut data = data;
                data.truncate(seatrac::MAX_DAT_PAYLOAD);
                Response::DatReceive {
                    fix: self.fix(s, src, msg_type + 1),
                    ack: true,
                    data,
                }
            }
            Pending::Dat { dest, .. } => Response::DatError {
                status: Cst::XcvrRespTimeout,
                beacon_id: dest,
            },
        }
    }
}

impl Device for X150 {
    fn name(&self) -> &'static str {
        "seatrac"
    }

    fn period(&self) -> f64 {
        0.02
    }

    fn connected(&mut self, _: &Situation) -> Vec<u8> {
        self.lines.reset();
        Vec::new()
    }

    fn tick(&mut self, s: &Situation) -> Vec<u8> {
        let mut out = String::new();
        if let Some((due, _)) = &self.pending
            && s.t + 1e-9 >= *due
        {
            let (_, p) = self.pending.take().expect("checked");
            out.push_str(&self.complete(s, p).encode());
        }
        let me = self.settings.beacon_id();
        for (dest, kind, mut data) in self.cfg.remote.poll(s.t) {
            if dest == me || dest == 0 {
                data.truncate(seatrac::MAX_DAT_PAYLOAD);
                let src = self.cfg.remote.id();
                let fix = self.fix(s, src, kind);
                out.push_str(
                    &Response::DatReceive {
                        fix,
                        ack: false,
                        data,
                    }
                    .encode(),
                );
            }
        }
        let rate = status_rate_hz(self.settings.status_mode());
        if rate > 0.0 && self.status.due(s.t) {
            self.status.done(s.t, 1.0 / rate);
            let blocks = self.settings.status_output();
            out.push_str(&Response::Status(self.status_message(s, blocks)).encode());
        }
        out.into_bytes()
    }

    fn receive(&mut self, s: &Situation, data: &[u8]) -> Vec<u8> {
        let mut lines = Vec::new();
        self.lines.push(data, |l| lines.push(l.to_vec()));
        let mut out = String::new();
        for l in lines {
            match self.command(s, &l) {
                Some(r) => out.push_str(&r.encode()),
                None => self.counts.refused += 1,
            }
        }
        out.into_bytes()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(t: f64) -> Situation {
        Situation {
            t,
            unix_s: t,
            truth: Truth {
                time: t,
                x: 30.0,
                y: 40.0,
                depth: 1.0,
                heading_deg: 90.0,
                ..Truth::default()
            },
            leak: false,
            battery_drop_v: 0.0,
        }
    }

    fn responses(bytes: &[u8]) -> Vec<Response> {
        bytes
            .split(|&b| b == b'\n')
            .filter(|l| !l.is_empty())
            .map(|l| Response::decode(l).unwrap())
            .collect()
    }

    fn quiet() -> X150Settings {
        X150Settings {
            ahrs: AhrsConfig {
                heading_noise_deg: 0.0,
                attitude_noise_deg: 0.0,
                gyro_noise_deg_s: 0.0,
                ..AhrsConfig::default()
            },
            ..X150Settings::default()
        }
    }

    #[test]
    fn the_drivers_start_up_sequence_is_answered() {
        let mut m = X150::new(quiet(), 1);
        assert!(m.tick(&at(0.0)).is_empty(), "status off at power-up");
        let r = responses(&m.receive(&at(2.5), Command::SysAlive.encode().unwrap().as_bytes()));
        assert_eq!(r, vec![Response::SysAlive { seconds: 2 }]);
        let r = responses(&m.receive(&at(2.6), Command::SettingsGet.encode().unwrap().as_bytes()));
        let Response::SettingsGet(mut s) = r[0].clone() else {
            panic!()
        };
        assert_eq!(s.beacon_id(), 1);
        s.set_beacon_id(3);
        s.set_env_salinity_dppt(350);
        s.set_status_mode(4);
        s.set_status_output(
            status_bits::ATTITUDE | status_bits::AHRS_COMP_DATA | status_bits::ENVIRONMENT,
        );
        let set = Command::SettingsSet(s.clone()).encode().unwrap();
        let save = Command::SettingsSave.encode().unwrap();
        let r = responses(&m.receive(&at(2.7), format!("{set}{save}").as_bytes()));
        assert_eq!(
            r,
            vec![
                Response::SettingsSet(Cst::Ok),
                Response::SettingsSave(Cst::Ok)
            ]
        );
        assert_eq!(m.saved_settings(), &s);
        // A bad beacon id is refused.
        let mut bad = s.clone();
        bad.set_beacon_id(16);
        let r = responses(&m.receive(
            &at(2.8),
            Command::SettingsSet(bad).encode().unwrap().as_bytes(),
        ));
        assert_eq!(r, vec![Response::SettingsSet(Cst::CmdParamInvalid)]);
        assert_eq!(m.settings().beacon_id(), 3);
        // 10 Hz status with the three blocks.
        let mut statuses = Vec::new();
        for k in 0..50 {
            statuses.extend(responses(&m.tick(&at(3.0 + f64::from(k) * 0.02))));
        }
        assert_eq!(statuses.len(), 10);
        let Response::Status(st) = &statuses[0] else {
            panic!()
        };
        assert_eq!(st.timestamp_ms, 3000);
        let att = st.attitude.unwrap();
        assert_eq!((att.yaw_ddeg, att.pitch_ddeg, att.roll_ddeg), (900, 0, 0));
        let env = st.environment.unwrap();
        assert_eq!(
            (env.supply_mv, env.vos_dmps, env.pressure_mbar),
            (16400, 14750, 1111)
        );
        let comp = st.ahrs_comp.unwrap();
        // Level: 1 g up the body's down axis, written in the CoUGARs mount (z flipped).
        assert_eq!(comp.acc, [0.0, 0.0, 1.0]);
        assert!(st.mag_cal.is_none() && st.ahrs_raw.is_none());
        assert_eq!(m.counts().commands, 5);
    }

    #[test]
    fn pings_and_data_requests_get_fixes_after_the_round_trip() {
        let mut m = X150::new(quiet(), 1);
        let ping = Command::PingSend {
            dest_id: 15,
            msg_type: msg_type::REQU,
        };
        let r = responses(&m.receive(&at(1.0), ping.encode().unwrap().as_bytes()));
        assert_eq!(
            r,
            vec![Response::PingSend {
                status: Cst::Ok,
                beacon_id: 15
            }]
        );
        // Busy while waiting.
        let r = responses(&m.receive(&at(1.01), ping.encode().unwrap().as_bytes()));
        assert_eq!(
            r,
            vec![Response::PingSend {
                status: Cst::XcvrBusy,
                beacon_id: 15
            }]
        );
        // The base is 50 m away: 68 ms there and back plus a 50 ms turnaround.
        assert!(m.tick(&at(1.11)).is_empty());
        let r = responses(&m.tick(&at(1.12)));
        let Response::PingResp(fix) = &r[0] else {
            panic!("{r:?}")
        };
        assert_eq!(
            (fix.src_id, fix.dest_id, fix.msg_type),
            (15, 1, msg_type::RESPU)
        );
        assert!((fix.range_m().unwrap() - 50.0).abs() < 0.5);
        let u = fix.usbl.clone().unwrap();
        // The base lies south-west (bearing 216.87°), heading east: 126.87° to the right.
        assert!(
            (f64::from(u.azimuth_ddeg) / 10.0 - 126.87).abs() < 4.0,
            "{u:?}"
        );
        let p = fix.position.unwrap();
        assert_eq!((p.easting_dm, p.northing_dm, p.depth_dm), (-300, -400, 10));
        // A data request is echoed back by the loopback beacon with a RESP fix.
        let dat = Command::DatSend {
            dest_id: 15,
            msg_type: msg_type::REQ,
            data: b"hello".to_vec(),
        };
        let r = responses(&m.receive(&at(2.0), dat.encode().unwrap().as_bytes()));
        assert_eq!(
            r,
            vec![Response::DatSend {
                status: Cst::Ok,
                beacon_id: 15
            }]
        );
        let r = responses(&m.tick(&at(2.3)));
        let Response::DatReceive { fix, ack, data } = &r[0] else {
            panic!()
        };
        assert!(*ack && data == b"hello" && fix.range.is_some() && fix.usbl.is_none());
        // A beacon that is not there: a timeout after 4 s.
        let r = responses(
            &m.receive(
                &at(3.0),
                Command::PingSend {
                    dest_id: 4,
                    msg_type: msg_type::REQ,
                }
                .encode()
                .unwrap()
                .as_bytes(),
            ),
        );
        assert_eq!(
            r,
            vec![Response::PingSend {
                status: Cst::Ok,
                beacon_id: 4
            }]
        );
        assert!(m.tick(&at(6.9)).is_empty());
        assert_eq!(
            responses(&m.tick(&at(7.0))),
            vec![Response::PingError {
                status: Cst::XcvrRespTimeout,
                beacon_id: 4
            }]
        );
    }

    #[test]
    fn padded_dat_send_frames_and_bad_frames() {
        let mut m = X150::new(quiet(), 1);
        // The driver's struct: length 3, then its whole 31-byte array.
        let mut msg = vec![cid::DAT_SEND, 15, msg_type::OWAY, 3, b'a', b'b', b'c'];
        msg.resize(4 + 31, 0);
        let frame = seatrac::encode_frame(seatrac::Direction::Command, &msg);
        let r = responses(&m.receive(&at(1.0), frame.as_bytes()));
        assert_eq!(
            r,
            vec![Response::DatSend {
                status: Cst::Ok,
                beacon_id: 15
            }]
        );
        assert!(m.tick(&at(6.0)).is_empty(), "one way: no answer");
        // Busy for 0.4 s after a transmission.
        let again = m.receive(&at(1.2), frame.as_bytes());
        assert_eq!(
            responses(&again),
            vec![Response::DatSend {
                status: Cst::XcvrBusy,
                beacon_id: 15
            }]
        );
        let mut corrupted = frame.clone().into_bytes();
        corrupted[3] = if corrupted[3] == b'0' { b'1' } else { b'0' };
        assert!(m.receive(&at(2.0), &corrupted).is_empty());
        assert!(m.receive(&at(2.0), b"#7701FFFF\r\n").is_empty());
        assert_eq!(m.counts().refused, 2);
    }

    #[test]
    fn random_busy_answers_are_seeded() {
        let run = || {
            let mut m = X150::new(
                X150Settings {
                    busy_prob: 0.5,
                    ..quiet()
                },
                9,
            );
            (0..20)
                .map(|k| {
                    let d = Command::DatSend {
                        dest_id: 15,
                        msg_type: msg_type::OWAY,
                        data: vec![1],
                    };
                    let r =
                        responses(&m.receive(&at(f64::from(k)), d.encode().unwrap().as_bytes()));
                    matches!(
                        r[0],
                        Response::DatSend {
                            status: Cst::XcvrBusy,
                            ..
                        }
                    )
                })
                .collect::<Vec<_>>()
        };
        let a = run();
        assert_eq!(a, run());
        let n = a.iter().filter(|b| **b).count();
        assert!((4..=16).contains(&n), "{n}");
    }

    /// The conventions of `drivers::seatrac` (body-frame azimuth clockwise from the bow,
    /// elevation positive up): a base 20 m due east and 20 m deeper is at azimuth 90° and
    /// elevation −45° from a level vehicle heading north, 0° and −45° heading east.
    #[test]
    fn a_base_due_east_and_45_degrees_down() {
        for (heading, want_az) in [(0.0, 90.0), (90.0, 0.0), (300.0, 150.0)] {
            let mut m = X150::new(
                X150Settings {
                    remote: Box::new(EchoBeacon {
                        id: 15,
                        position: (20.0, 0.0, 30.0),
                        received: Vec::new(),
                    }),
                    ..quiet()
                },
                4,
            );
            let s = |t: f64| Situation {
                truth: Truth {
                    time: t,
                    depth: 10.0,
                    heading_deg: heading,
                    ..Truth::default()
                },
                ..at(t)
            };
            let ping = Command::PingSend {
                dest_id: 15,
                msg_type: msg_type::REQU,
            };
            m.receive(&s(1.0), ping.encode().unwrap().as_bytes());
            let r = responses(&m.tick(&s(1.5)));
            let Some(Response::PingResp(fix)) = r.first() else {
                panic!("{r:?}")
            };
            let u = fix.usbl.clone().unwrap();
            let az = f64::from(u.azimuth_ddeg) / 10.0;
            let off = (az - want_az + 540.0).rem_euclid(360.0) - 180.0;
            assert!(off.abs() < 4.0, "heading {heading}: azimuth {az}");
            let el = f64::from(u.elevation_ddeg) / 10.0;
            assert!((el + 45.0).abs() < 4.0, "elevation {el}");
            assert!((fix.range_m().unwrap() - 20f64.hypot(20.0)).abs() < 0.5);
            let p = fix.position.unwrap();
            assert_eq!((p.easting_dm, p.northing_dm, p.depth_dm), (200, 0, 300));
        }
    }

    #[test]
    fn the_first_sends_can_be_refused_as_busy() {
        let mut m = X150::new(
            X150Settings {
                busy_first: 2,
                ..quiet()
            },
            1,
        );
        let d = Command::DatSend {
            dest_id: 15,
            msg_type: msg_type::OWAY,
            data: vec![7],
        };
        let answers: Vec<Cst> = (0..3)
            .map(|k| {
                let t = 1.0 + f64::from(k);
                match responses(&m.receive(&at(t), d.encode().unwrap().as_bytes()))[..] {
                    [Response::DatSend { status, .. }] => status,
                    ref r => panic!("{r:?}"),
                }
            })
            .collect();
        assert_eq!(answers, [Cst::XcvrBusy, Cst::XcvrBusy, Cst::Ok]);
        assert_eq!(m.counts().busy, 2);
    }

    #[test]
    fn mounts_round_trip_through_the_drivers_mapping() {
        let w = [0.3, -0.2, 0.1];
        let g = Mount::Cougars.from_body(w);
        let a = std::f64::consts::FRAC_1_SQRT_2;
        let back = [a * (g[1] - g[0]), a * (g[0] + g[1]), -g[2]];
        for (b, x) in back.iter().zip(w) {
            assert!((b - x).abs() < 1e-12);
        }
    }
}
