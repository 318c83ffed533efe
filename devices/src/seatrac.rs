//! The SeaTrac X150 USBL modem's serial protocol (Blueprint Subsea, "SeaTrac Developer
//! Guide" UM-140; `cougars-vehicle.md` §3.5): ASCII-hex frames and the messages the CoUGARs
//! driver uses.
//!
//! A frame is a start byte (`#` for a command to the beacon, `$` for a message from it), the
//! message bytes (a command id, CID, then its little-endian payload) as uppercase hex, the
//! CRC16 of those bytes as four hex characters, low byte first, and `\r\n`. The CRC is
//! CRC-16/ARC: reflected polynomial 0xA001, initial value 0.
//!
//! [`Command`] is what the driver sends (the emulator decodes it); [`Response`] is what the
//! beacon sends (the emulator encodes it). Field units are in the names as the wire carries
//! them (`_ddeg` decidegrees, `_dm` decimetres, `_dmps` decimetres per second, `_cb`
//! centibels, `_mv` millivolts) with helpers giving SI values.

use std::fmt::Write as _;

use crate::line::ProtocolError;

/// The longest frame line accepted: `$`, a CID and a 255-byte payload in hex, the CRC.
pub const MAX_FRAME: usize = 1 + 2 * 256 + 4;

/// The longest DAT payload (the driver's `data[31]`).
pub const MAX_DAT_PAYLOAD: usize = 31;

/// The size of the SETTINGS_T structure.
pub const SETTINGS_LEN: usize = 110;

/// Command ids (CID) used here.
pub mod cid {
    /// CID_SYS_ALIVE.
    pub const SYS_ALIVE: u8 = 0x01;
    /// CID_STATUS.
    pub const STATUS: u8 = 0x10;
    /// CID_SETTINGS_GET.
    pub const SETTINGS_GET: u8 = 0x15;
    /// CID_SETTINGS_SET.
    pub const SETTINGS_SET: u8 = 0x16;
    /// CID_SETTINGS_SAVE.
    pub const SETTINGS_SAVE: u8 = 0x18;
    /// CID_PING_SEND.
    pub const PING_SEND: u8 = 0x40;
    /// CID_PING_REQ (a ping was received and answered).
    pub const PING_REQ: u8 = 0x41;
    /// CID_PING_RESP (the answer to our ping, with its fix).
    pub const PING_RESP: u8 = 0x42;
    /// CID_PING_ERROR.
    pub const PING_ERROR: u8 = 0x43;
    /// CID_DAT_SEND.
    pub const DAT_SEND: u8 = 0x60;
    /// CID_DAT_RECEIVE.
    pub const DAT_RECEIVE: u8 = 0x61;
    /// CID_DAT_ERROR.
    pub const DAT_ERROR: u8 = 0x63;
}

/// Acoustic message types (AMSGTYPE_E).
pub mod msg_type {
    /// One way, no reply.
    pub const OWAY: u8 = 0;
    /// One way with a USBL bearing.
    pub const OWAYU: u8 = 1;
    /// Request, reply with range.
    pub const REQ: u8 = 2;
    /// Response to REQ.
    pub const RESP: u8 = 3;
    /// Request, reply with range and USBL.
    pub const REQU: u8 = 4;
    /// Response to REQU.
    pub const RESPU: u8 = 5;
    /// Request, reply with range, USBL and the remote depth.
    pub const REQX: u8 = 6;
    /// Response to REQX.
    pub const RESPX: u8 = 7;
}

/// STATUS content flags (STATUS_BITS_T), also the settings' `status_output`.
pub mod status_bits {
    /// Supply, temperature, pressure, depth, speed of sound.
    pub const ENVIRONMENT: u8 = 0x01;
    /// Yaw, pitch, roll.
    pub const ATTITUDE: u8 = 0x02;
    /// Magnetometer calibration state.
    pub const MAG_CAL: u8 = 0x04;
    /// Accelerometer calibration limits.
    pub const ACC_CAL: u8 = 0x08;
    /// Raw accelerometer, magnetometer and gyro.
    pub const AHRS_RAW_DATA: u8 = 0x10;
    /// Compensated accelerometer, magnetometer and gyro.
    pub const AHRS_COMP_DATA: u8 = 0x20;
}

/// ACOFIX_T flags.
pub mod fix_flags {
    /// Range fields present.
    pub const RANGE: u8 = 0x01;
    /// USBL fields present.
    pub const USBL: u8 = 0x02;
    /// Position fields present.
    pub const POSITION: u8 = 0x04;
    /// The position used the remote depth (from a REQX).
    pub const POSITION_ENHANCED: u8 = 0x08;
    /// The position filter flagged the fix.
    pub const POSITION_FLT_ERROR: u8 = 0x10;
}

/// A command status code (CST_E).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Cst {
    /// 0x00: success.
    Ok,
    /// 0x01: failed.
    Fail,
    /// 0x03: EEPROM error.
    EepromError,
    /// 0x04: a parameter is missing.
    CmdParamMissing,
    /// 0x05: a parameter is invalid.
    CmdParamInvalid,
    /// 0x30: the transceiver is busy (retry later).
    XcvrBusy,
    /// 0x31: the message was for another beacon.
    XcvrIdRejected,
    /// 0x32: acoustic checksum error.
    XcvrCsumError,
    /// 0x33: acoustic length error.
    XcvrLengthError,
    /// 0x34: the remote beacon did not answer in time.
    XcvrRespTimeout,
    /// 0x35: the answer was in error.
    XcvrRespError,
    /// 0x36: the answer was not the expected one.
    XcvrRespWrong,
    /// 0x37: payload error.
    XcvrPloadError,
    /// Any other code.
    Other(u8),
}

impl Cst {
    /// The code of a byte.
    pub fn from_u8(b: u8) -> Self {
        match b {
            0x00 => Cst::Ok,
            0x01 => Cst::Fail,
            0x03 => Cst::EepromError,
            0x04 => Cst::CmdParamMissing,
            0x05 => Cst::CmdParamInvalid,
            0x30 => Cst::XcvrBusy,
            0x31 => Cst::XcvrIdRejected,
            0x32 => Cst::XcvrCsumError,
            0x33 => Cst::XcvrLengthError,
            0x34 => Cst::XcvrRespTimeout,
            0x35 => Cst::XcvrRespError,
            0x36 => Cst::XcvrRespWrong,
            0x37 => Cst::XcvrPloadError,
            other => Cst::Other(other),
        }
    }

    /// The byte of a code.
    pub fn to_u8(self) -> u8 {
        match self {
            Cst::Ok => 0x00,
            Cst::Fail => 0x01,
            Cst::EepromError => 0x03,
            Cst::CmdParamMissing => 0x04,
            Cst::CmdParamInvalid => 0x05,
            Cst::XcvrBusy => 0x30,
            Cst::XcvrIdRejected => 0x31,
            Cst::XcvrCsumError => 0x32,
            Cst::XcvrLengthError => 0x33,
            Cst::XcvrRespTimeout => 0x34,
            Cst::XcvrRespError => 0x35,
            Cst::XcvrRespWrong => 0x36,
            Cst::XcvrPloadError => 0x37,
            Cst::Other(b) => b,
        }
    }
}

/// Why a frame or a message was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SeatracError {
    /// The line does not start with `#` or `$`.
    #[error("no '#' or '$' start")]
    NoStart,
    /// A character that is not a hex digit, or an odd number of them.
    #[error("bad hex")]
    BadHex,
    /// Fewer than a CID and a CRC.
    #[error("frame too short")]
    TooShort,
    /// The CRC does not match.
    #[error("CRC {found:04X} where the bytes give {computed:04X}")]
    BadCrc {
        /// The CRC in the frame.
        found: u16,
        /// The CRC of the bytes.
        computed: u16,
    },
    /// A command frame where a response was expected, or the reverse.
    #[error("frame in the wrong direction")]
    WrongDirection,
    /// The payload length does not fit the message.
    #[error("CID {cid:#04x}: bad payload length {len}")]
    BadLength {
        /// The command id.
        cid: u8,
        /// The payload length.
        len: usize,
    },
    /// A field value the protocol does not allow.
    #[error("CID {cid:#04x}: bad field {what}")]
    BadField {
        /// The command id.
        cid: u8,
        /// Which field.
        what: &'static str,
    },
    /// A command id this module does not decode (commands only; responses keep them).
    #[error("unsupported CID {0:#04x}")]
    Unsupported(u8),
    /// A DAT payload over [`MAX_DAT_PAYLOAD`] bytes (encoding).
    #[error("payload of {0} bytes, at most 31")]
    PayloadTooLong(usize),
}

impl ProtocolError for SeatracError {
    fn is_checksum(&self) -> bool {
        matches!(self, SeatracError::BadCrc { .. })
    }
}

/// CRC-16/ARC (reflected 0xA001, initial 0) of `data`.
pub fn crc16(data: &[u8]) -> u16 {
    let mut crc = 0u16;
    for &b in data {
        crc ^= u16::from(b);
        for _ in 0..8 {
            crc = if crc & 1 != 0 {
                (crc >> 1) ^ 0xA001
            } else {
                crc >> 1
            };
        }
    }
    crc
}

/// Which way a frame goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// `#`: a command to the beacon.
    Command,
    /// `$`: a response or event from the beacon.
    Response,
}

/// The frame of `msg` (CID and payload) with its CRC and `\r\n`.
pub fn encode_frame(dir: Direction, msg: &[u8]) -> String {
    let mut s = String::with_capacity(msg.len() * 2 + 7);
    s.push(match dir {
        Direction::Command => '#',
        Direction::Response => '$',
    });
    for b in msg {
        let _ = write!(s, "{b:02X}");
    }
    let crc = crc16(msg);
    let _ = write!(s, "{:02X}{:02X}\r\n", crc & 0xff, crc >> 8);
    s
}

fn nibble(c: u8) -> Option<u8> {
    match c {
        b'0'..=b'9' => Some(c - b'0'),
        b'A'..=b'F' => Some(c - b'A' + 10),
        b'a'..=b'f' => Some(c - b'a' + 10),
        _ => None,
    }
}

/// Decodes a frame line (a trailing `\r\n` is allowed): its direction and message bytes
/// (CID and payload), the CRC checked.
pub fn decode_frame(line: &[u8]) -> Result<(Direction, Vec<u8>), SeatracError> {
    let line = line.strip_suffix(b"\n").unwrap_or(line);
    let line = line.strip_suffix(b"\r").unwrap_or(line);
    let (dir, hex) = match line.split_first() {
        Some((b'#', rest)) => (Direction::Command, rest),
        Some((b'$', rest)) => (Direction::Response, rest),
        _ => return Err(SeatracError::NoStart),
    };
    if hex.len() % 2 != 0 {
        return Err(SeatracError::BadHex);
    }
    let mut bytes = Vec::with_capacity(hex.len() / 2);
    for p in hex.chunks_exact(2) {
        match (nibble(p[0]), nibble(p[1])) {
            (Some(h), Some(l)) => bytes.push(h << 4 | l),
            _ => return Err(SeatracError::BadHex),
        }
    }
    if bytes.len() < 3 {
        return Err(SeatracError::TooShort);
    }
    let n = bytes.len() - 2;
    let found = u16::from(bytes[n]) | u16::from(bytes[n + 1]) << 8;
    bytes.truncate(n);
    let computed = crc16(&bytes);
    if found != computed {
        return Err(SeatracError::BadCrc { found, computed });
    }
    Ok((dir, bytes))
}

/// A little-endian reader over a payload that reports a short payload as an error.
struct Rd<'a> {
    cid: u8,
    b: &'a [u8],
    at: usize,
}

impl<'a> Rd<'a> {
    fn new(cid: u8, b: &'a [u8]) -> Self {
        Rd { cid, b, at: 0 }
    }
    fn take<const N: usize>(&mut self) -> Result<[u8; N], SeatracError> {
        let s = self
            .b
            .get(self.at..self.at + N)
            .ok_or(SeatracError::BadLength {
                cid: self.cid,
                len: self.b.len(),
            })?;
        self.at += N;
        let mut a = [0; N];
        a.copy_from_slice(s);
        Ok(a)
    }
    fn u8(&mut self) -> Result<u8, SeatracError> {
        Ok(self.take::<1>()?[0])
    }
    fn u16(&mut self) -> Result<u16, SeatracError> {
        Ok(u16::from_le_bytes(self.take()?))
    }
    fn i16(&mut self) -> Result<i16, SeatracError> {
        Ok(i16::from_le_bytes(self.take()?))
    }
    fn u32(&mut self) -> Result<u32, SeatracError> {
        Ok(u32::from_le_bytes(self.take()?))
    }
    fn i32(&mut self) -> Result<i32, SeatracError> {
        Ok(i32::from_le_bytes(self.take()?))
    }
    fn u64(&mut self) -> Result<u64, SeatracError> {
        Ok(u64::from_le_bytes(self.take()?))
    }
    fn f32(&mut self) -> Result<f32, SeatracError> {
        Ok(f32::from_le_bytes(self.take()?))
    }
    fn i16s<const N: usize>(&mut self) -> Result<[i16; N], SeatracError> {
        let mut a = [0; N];
        for v in &mut a {
            *v = self.i16()?;
        }
        Ok(a)
    }
    fn f32s<const N: usize>(&mut self) -> Result<[f32; N], SeatracError> {
        let mut a = [0.0; N];
        for v in &mut a {
            *v = self.f32()?;
        }
        Ok(a)
    }
    fn bytes(&mut self, n: usize) -> Result<&'a [u8], SeatracError> {
        let s = self
            .b
            .get(self.at..self.at + n)
            .ok_or(SeatracError::BadLength {
                cid: self.cid,
                len: self.b.len(),
            })?;
        self.at += n;
        Ok(s)
    }
    /// The payload must end here.
    fn end(&self) -> Result<(), SeatracError> {
        if self.at == self.b.len() {
            Ok(())
        } else {
            Err(SeatracError::BadLength {
                cid: self.cid,
                len: self.b.len(),
            })
        }
    }
}

/// The STATUS environment block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Environment {
    /// Supply voltage, millivolts.
    pub supply_mv: u16,
    /// Temperature, tenths of a degree Celsius.
    pub temp_ddegc: i16,
    /// Pressure, millibar.
    pub pressure_mbar: i32,
    /// Depth, decimetres.
    pub depth_dm: i32,
    /// Speed of sound, decimetres per second.
    pub vos_dmps: u16,
}

impl Environment {
    /// Supply voltage, volts.
    pub fn supply_v(&self) -> f64 {
        f64::from(self.supply_mv) / 1000.0
    }
    /// Depth, metres.
    pub fn depth_m(&self) -> f64 {
        f64::from(self.depth_dm) / 10.0
    }
    /// Temperature, degrees Celsius.
    pub fn temp_degc(&self) -> f64 {
        f64::from(self.temp_ddegc) / 10.0
    }
}

/// Yaw, pitch and roll in decidegrees.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Attitude {
    /// Yaw (heading), decidegrees.
    pub yaw_ddeg: i16,
    /// Pitch, decidegrees.
    pub pitch_ddeg: i16,
    /// Roll, decidegrees.
    pub roll_ddeg: i16,
}

impl Attitude {
    /// Yaw, degrees.
    pub fn yaw_deg(&self) -> f64 {
        f64::from(self.yaw_ddeg) / 10.0
    }
    /// Pitch, degrees.
    pub fn pitch_deg(&self) -> f64 {
        f64::from(self.pitch_ddeg) / 10.0
    }
    /// Roll, degrees.
    pub fn roll_deg(&self) -> f64 {
        f64::from(self.roll_ddeg) / 10.0
    }
}

/// The STATUS magnetometer calibration block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MagCal {
    /// Calibration buffer fill, percent.
    pub buf_pct: u8,
    /// A calibration is valid.
    pub valid: bool,
    /// Age of the calibration, seconds.
    pub age_s: u32,
    /// Fit quality, percent.
    pub fit_pct: u8,
}

/// The STATUS compensated AHRS block (accelerometer, magnetometer, gyro as the beacon
/// scales them: the accelerometer in g, the magnetometer in µT, the gyro in deg/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AhrsComp {
    /// Accelerometer x, y, z.
    pub acc: [f32; 3],
    /// Magnetometer x, y, z.
    pub mag: [f32; 3],
    /// Gyro x, y, z.
    pub gyro: [f32; 3],
}

/// A STATUS message: whatever blocks its content flags announce, in flag order.
#[derive(Debug, Clone, PartialEq)]
pub struct Status {
    /// Milliseconds since the beacon powered up.
    pub timestamp_ms: u64,
    /// ENVIRONMENT block.
    pub environment: Option<Environment>,
    /// ATTITUDE block.
    pub attitude: Option<Attitude>,
    /// MAG_CAL block.
    pub mag_cal: Option<MagCal>,
    /// ACC_CAL block: minimum x, y, z then maximum x, y, z.
    pub acc_cal: Option<[i16; 6]>,
    /// AHRS_RAW_DATA block: accelerometer, magnetometer, gyro x, y, z.
    pub ahrs_raw: Option<[i16; 9]>,
    /// AHRS_COMP_DATA block.
    pub ahrs_comp: Option<AhrsComp>,
}

impl Status {
    /// The content flags of the blocks present.
    pub fn content_flags(&self) -> u8 {
        use status_bits::*;
        let f = |b: bool, v: u8| if b { v } else { 0 };
        f(self.environment.is_some(), ENVIRONMENT)
            | f(self.attitude.is_some(), ATTITUDE)
            | f(self.mag_cal.is_some(), MAG_CAL)
            | f(self.acc_cal.is_some(), ACC_CAL)
            | f(self.ahrs_raw.is_some(), AHRS_RAW_DATA)
            | f(self.ahrs_comp.is_some(), AHRS_COMP_DATA)
    }
}

/// The range part of a fix.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Range {
    /// Round-trip time in 16 kHz ticks.
    pub count: u32,
    /// One-way time, 100 ns units.
    pub time_100ns: i32,
    /// Range, decimetres.
    pub dist_dm: u16,
}

/// The USBL part of a fix.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Usbl {
    /// Signal strength per channel (at most 4), centibels.
    pub rssi_cb: Vec<i16>,
    /// Azimuth of the remote beacon, decidegrees (0–3600).
    pub azimuth_ddeg: i16,
    /// Elevation, decidegrees.
    pub elevation_ddeg: i16,
    /// Fit error of the angle solution, hundredths.
    pub fit_error_centi: i16,
}

/// The position part of a fix, decimetres from the local beacon.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Position {
    /// Easting, decimetres.
    pub easting_dm: i16,
    /// Northing, decimetres.
    pub northing_dm: i16,
    /// Depth, decimetres.
    pub depth_dm: i16,
}

/// ACOFIX_T: what the beacon knows about an acoustic message it received.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AcoFix {
    /// Destination beacon id.
    pub dest_id: u8,
    /// Source beacon id.
    pub src_id: u8,
    /// The message type (see [`msg_type`]).
    pub msg_type: u8,
    /// The local beacon's attitude.
    pub attitude: Attitude,
    /// The local beacon's depth, decimetres.
    pub depth_local_dm: u16,
    /// Speed of sound used, decimetres per second.
    pub vos_dmps: u16,
    /// Received signal strength, centibels.
    pub rssi_cb: i16,
    /// Range, when measured.
    pub range: Option<Range>,
    /// USBL angles, when measured.
    pub usbl: Option<Usbl>,
    /// Position, when computed.
    pub position: Option<Position>,
    /// The position used the remote depth.
    pub position_enhanced: bool,
    /// The position filter flagged the fix.
    pub position_flt_error: bool,
}

impl AcoFix {
    /// The fix's flags byte.
    pub fn flags(&self) -> u8 {
        use fix_flags::*;
        let f = |b: bool, v: u8| if b { v } else { 0 };
        f(self.range.is_some(), RANGE)
            | f(self.usbl.is_some(), USBL)
            | f(self.position.is_some(), POSITION)
            | f(self.position_enhanced, POSITION_ENHANCED)
            | f(self.position_flt_error, POSITION_FLT_ERROR)
    }

    /// Range in metres, when measured.
    pub fn range_m(&self) -> Option<f64> {
        self.range.map(|r| f64::from(r.dist_dm) / 10.0)
    }

    fn read(r: &mut Rd) -> Result<Self, SeatracError> {
        let (dest_id, src_id, flags, msg_type) = (r.u8()?, r.u8()?, r.u8()?, r.u8()?);
        let attitude = Attitude {
            yaw_ddeg: r.i16()?,
            pitch_ddeg: r.i16()?,
            roll_ddeg: r.i16()?,
        };
        let (depth_local_dm, vos_dmps, rssi_cb) = (r.u16()?, r.u16()?, r.i16()?);
        let range = if flags & fix_flags::RANGE != 0 {
            Some(Range {
                count: r.u32()?,
                time_100ns: r.i32()?,
                dist_dm: r.u16()?,
            })
        } else {
            None
        };
        let usbl = if flags & fix_flags::USBL != 0 {
            let n = r.u8()?;
            if n > 4 {
                return Err(SeatracError::BadField {
                    cid: r.cid,
                    what: "usbl channels",
                });
            }
            let mut rssi_cb = Vec::with_capacity(n.into());
            for _ in 0..n {
                rssi_cb.push(r.i16()?);
            }
            Some(Usbl {
                rssi_cb,
                azimuth_ddeg: r.i16()?,
                elevation_ddeg: r.i16()?,
                fit_error_centi: r.i16()?,
            })
        } else {
            None
        };
        let position = if flags & fix_flags::POSITION != 0 {
            Some(Position {
                easting_dm: r.i16()?,
                northing_dm: r.i16()?,
                depth_dm: r.i16()?,
            })
        } else {
            None
        };
        if flags & 0xE0 != 0 {
            return Err(SeatracError::BadField {
                cid: r.cid,
                what: "fix flags",
            });
        }
        Ok(AcoFix {
            dest_id,
            src_id,
            msg_type,
            attitude,
            depth_local_dm,
            vos_dmps,
            rssi_cb,
            range,
            usbl,
            position,
            position_enhanced: flags & fix_flags::POSITION_ENHANCED != 0,
            position_flt_error: flags & fix_flags::POSITION_FLT_ERROR != 0,
        })
    }

    fn write(&self, o: &mut Vec<u8>) {
        o.extend([self.dest_id, self.src_id, self.flags(), self.msg_type]);
        put_i16s(
            o,
            &[
                self.attitude.yaw_ddeg,
                self.attitude.pitch_ddeg,
                self.attitude.roll_ddeg,
            ],
        );
        o.extend(self.depth_local_dm.to_le_bytes());
        o.extend(self.vos_dmps.to_le_bytes());
        o.extend(self.rssi_cb.to_le_bytes());
        if let Some(r) = &self.range {
            o.extend(r.count.to_le_bytes());
            o.extend(r.time_100ns.to_le_bytes());
            o.extend(r.dist_dm.to_le_bytes());
        }
        if let Some(u) = &self.usbl {
            let ch = &u.rssi_cb[..u.rssi_cb.len().min(4)];
            o.push(ch.len() as u8);
            put_i16s(o, ch);
            put_i16s(o, &[u.azimuth_ddeg, u.elevation_ddeg, u.fit_error_centi]);
        }
        if let Some(p) = &self.position {
            put_i16s(o, &[p.easting_dm, p.northing_dm, p.depth_dm]);
        }
    }
}

fn put_i16s(o: &mut Vec<u8>, v: &[i16]) {
    for x in v {
        o.extend(x.to_le_bytes());
    }
}

/// SETTINGS_T, kept as its 110 bytes with accessors for the fields the start-up changes.
/// Offsets follow the structure's field table (UM-140): status_flags 0, status_output 1,
/// env_salinity 33 (u16, ppt × 10), xcvr_beacon_id 96.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Settings {
    /// The raw structure.
    pub raw: [u8; SETTINGS_LEN],
}

impl Settings {
    /// Status output rate (the low three bits of status_flags): 0 manual, 1 1 Hz, 2 2.5 Hz,
    /// 3 5 Hz, 4 10 Hz, 5 25 Hz.
    pub fn status_mode(&self) -> u8 {
        self.raw[0] & 0x07
    }
    /// Sets the status output rate, keeping the other status flags.
    pub fn set_status_mode(&mut self, mode: u8) {
        self.raw[0] = (self.raw[0] & !0x07) | (mode & 0x07);
    }
    /// The blocks of the automatic STATUS (see [`status_bits`]).
    pub fn status_output(&self) -> u8 {
        self.raw[1]
    }
    /// Sets the blocks of the automatic STATUS.
    pub fn set_status_output(&mut self, bits: u8) {
        self.raw[1] = bits;
    }
    /// Salinity, tenths of a part per thousand.
    pub fn env_salinity_dppt(&self) -> u16 {
        u16::from_le_bytes([self.raw[33], self.raw[34]])
    }
    /// Sets the salinity, tenths of a part per thousand.
    pub fn set_env_salinity_dppt(&mut self, v: u16) {
        self.raw[33..35].copy_from_slice(&v.to_le_bytes());
    }
    /// The beacon id (1–15).
    pub fn beacon_id(&self) -> u8 {
        self.raw[96]
    }
    /// Sets the beacon id.
    pub fn set_beacon_id(&mut self, id: u8) {
        self.raw[96] = id;
    }
}

/// A command to the beacon (`#` frames).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Command {
    /// CID_SYS_ALIVE: is the beacon there?
    SysAlive,
    /// CID_STATUS: a status with these blocks ([`status_bits`]).
    Status {
        /// The blocks wanted.
        output: u8,
    },
    /// CID_SETTINGS_GET.
    SettingsGet,
    /// CID_SETTINGS_SET.
    SettingsSet(Settings),
    /// CID_SETTINGS_SAVE (to EEPROM).
    SettingsSave,
    /// CID_PING_SEND.
    PingSend {
        /// The beacon pinged.
        dest_id: u8,
        /// The message type ([`msg_type`]).
        msg_type: u8,
    },
    /// CID_DAT_SEND.
    DatSend {
        /// The beacon addressed.
        dest_id: u8,
        /// The message type ([`msg_type`]).
        msg_type: u8,
        /// The payload (at most 31 bytes).
        data: Vec<u8>,
    },
}

impl Command {
    /// The frame, or [`SeatracError::PayloadTooLong`] for a DAT payload over 31 bytes.
    pub fn encode(&self) -> Result<String, SeatracError> {
        let mut o = Vec::new();
        match self {
            Command::SysAlive => o.push(cid::SYS_ALIVE),
            Command::Status { output } => o.extend([cid::STATUS, *output]),
            Command::SettingsGet => o.push(cid::SETTINGS_GET),
            Command::SettingsSet(s) => {
                o.push(cid::SETTINGS_SET);
                o.extend(s.raw);
            }
            Command::SettingsSave => o.push(cid::SETTINGS_SAVE),
            Command::PingSend { dest_id, msg_type } => {
                o.extend([cid::PING_SEND, *dest_id, *msg_type]);
            }
            Command::DatSend {
                dest_id,
                msg_type,
                data,
            } => {
                if data.len() > MAX_DAT_PAYLOAD {
                    return Err(SeatracError::PayloadTooLong(data.len()));
                }
                o.extend([cid::DAT_SEND, *dest_id, *msg_type, data.len() as u8]);
                o.extend(data);
            }
        }
        Ok(encode_frame(Direction::Command, &o))
    }

    /// Decodes a command from a frame line (the emulator's side).
    pub fn decode(line: &[u8]) -> Result<Self, SeatracError> {
        let (dir, msg) = decode_frame(line)?;
        if dir != Direction::Command {
            return Err(SeatracError::WrongDirection);
        }
        let (c, p) = (msg[0], &msg[1..]);
        let mut r = Rd::new(c, p);
        let cmd = match c {
            cid::SYS_ALIVE => Command::SysAlive,
            cid::STATUS => Command::Status { output: r.u8()? },
            cid::SETTINGS_GET => Command::SettingsGet,
            cid::SETTINGS_SET => Command::SettingsSet(Settings { raw: r.take()? }),
            cid::SETTINGS_SAVE => Command::SettingsSave,
            cid::PING_SEND => Command::PingSend {
                dest_id: r.u8()?,
                msg_type: r.u8()?,
            },
            cid::DAT_SEND => {
                let (dest_id, msg_type, n) = (r.u8()?, r.u8()?, r.u8()?);
                if usize::from(n) > MAX_DAT_PAYLOAD {
                    return Err(SeatracError::BadField {
                        cid: c,
                        what: "packet length",
                    });
                }
                Command::DatSend {
                    dest_id,
                    msg_type,
                    data: r.bytes(n.into())?.to_vec(),
                }
            }
            other => return Err(SeatracError::Unsupported(other)),
        };
        r.end()?;
        Ok(cmd)
    }
}

/// A message from the beacon (`$` frames).
#[derive(Debug, Clone, PartialEq)]
pub enum Response {
    /// CID_SYS_ALIVE: seconds since power-up.
    SysAlive {
        /// Seconds since power-up.
        seconds: u32,
    },
    /// CID_STATUS.
    Status(Status),
    /// CID_SETTINGS_GET: the settings.
    SettingsGet(Settings),
    /// CID_SETTINGS_SET: its status.
    SettingsSet(Cst),
    /// CID_SETTINGS_SAVE: its status.
    SettingsSave(Cst),
    /// CID_PING_SEND: the ping was (or was not) sent.
    PingSend {
        /// The status (XCVR_BUSY: retry).
        status: Cst,
        /// The beacon pinged.
        beacon_id: u8,
    },
    /// CID_PING_REQ: a ping for this beacon was received (and answered).
    PingReq(AcoFix),
    /// CID_PING_RESP: the answer to our ping, with its fix.
    PingResp(AcoFix),
    /// CID_PING_ERROR: the ping failed (XCVR_RESP_TIMEOUT, ...).
    PingError {
        /// Why.
        status: Cst,
        /// The beacon pinged.
        beacon_id: u8,
    },
    /// CID_DAT_SEND: the data was (or was not) sent.
    DatSend {
        /// The status (XCVR_BUSY: retry).
        status: Cst,
        /// The beacon addressed.
        beacon_id: u8,
    },
    /// CID_DAT_RECEIVE: data received, with its fix.
    DatReceive {
        /// The acoustic fix of the message.
        fix: AcoFix,
        /// The message was an acknowledgement of ours.
        ack: bool,
        /// The payload.
        data: Vec<u8>,
    },
    /// CID_DAT_ERROR: the data exchange failed.
    DatError {
        /// Why.
        status: Cst,
        /// The beacon addressed.
        beacon_id: u8,
    },
    /// Another CID, kept whole.
    Other {
        /// The command id.
        cid: u8,
        /// Its payload.
        payload: Vec<u8>,
    },
}

impl Response {
    /// Decodes a message from a frame line.
    pub fn decode(line: &[u8]) -> Result<Self, SeatracError> {
        let (dir, msg) = decode_frame(line)?;
        if dir != Direction::Response {
            return Err(SeatracError::WrongDirection);
        }
        Self::decode_message(&msg)
    }

    /// Decodes a message from its bytes (CID and payload; at least the CID).
    pub fn decode_message(msg: &[u8]) -> Result<Self, SeatracError> {
        let Some((&c, p)) = msg.split_first() else {
            return Err(SeatracError::TooShort);
        };
        let mut r = Rd::new(c, p);
        let status_and_id = |r: &mut Rd| -> Result<(Cst, u8), SeatracError> {
            Ok((Cst::from_u8(r.u8()?), r.u8()?))
        };
        let m = match c {
            cid::SYS_ALIVE => Response::SysAlive { seconds: r.u32()? },
            cid::STATUS => Response::Status(read_status(&mut r)?),
            cid::SETTINGS_GET => Response::SettingsGet(Settings { raw: r.take()? }),
            cid::SETTINGS_SET => Response::SettingsSet(Cst::from_u8(r.u8()?)),
            cid::SETTINGS_SAVE => Response::SettingsSave(Cst::from_u8(r.u8()?)),
            cid::PING_SEND => {
                let (status, beacon_id) = status_and_id(&mut r)?;
                Response::PingSend { status, beacon_id }
            }
            cid::PING_REQ => Response::PingReq(AcoFix::read(&mut r)?),
            cid::PING_RESP => Response::PingResp(AcoFix::read(&mut r)?),
            cid::PING_ERROR => {
                let (status, beacon_id) = status_and_id(&mut r)?;
                Response::PingError { status, beacon_id }
            }
            cid::DAT_SEND => {
                let (status, beacon_id) = status_and_id(&mut r)?;
                Response::DatSend { status, beacon_id }
            }
            cid::DAT_RECEIVE => {
                let fix = AcoFix::read(&mut r)?;
                let ack = match r.u8()? {
                    0 => false,
                    1 => true,
                    _ => {
                        return Err(SeatracError::BadField {
                            cid: c,
                            what: "ack flag",
                        });
                    }
                };
                let n = r.u8()?;
                Response::DatReceive {
                    fix,
                    ack,
                    data: r.bytes(n.into())?.to_vec(),
                }
            }
            cid::DAT_ERROR => {
                let (status, beacon_id) = status_and_id(&mut r)?;
                Response::DatError { status, beacon_id }
            }
            other => {
                return Ok(Response::Other {
                    cid: other,
                    payload: p.to_vec(),
                });
            }
        };
        r.end()?;
        Ok(m)
    }

    /// The message bytes (CID and payload).
    pub fn message(&self) -> Vec<u8> {
        let mut o = Vec::new();
        match self {
            Response::SysAlive { seconds } => {
                o.push(cid::SYS_ALIVE);
                o.extend(seconds.to_le_bytes());
            }
            Response::Status(s) => {
                o.push(cid::STATUS);
                write_status(s, &mut o);
            }
            Response::SettingsGet(s) => {
                o.push(cid::SETTINGS_GET);
                o.extend(s.raw);
            }
            Response::SettingsSet(st) => o.extend([cid::SETTINGS_SET, st.to_u8()]),
            Response::SettingsSave(st) => o.extend([cid::SETTINGS_SAVE, st.to_u8()]),
            Response::PingSend { status, beacon_id } => {
                o.extend([cid::PING_SEND, status.to_u8(), *beacon_id]);
            }
            Response::PingReq(f) => {
                o.push(cid::PING_REQ);
                f.write(&mut o);
            }
            Response::PingResp(f) => {
                o.push(cid::PING_RESP);
                f.write(&mut o);
            }
            Response::PingError { status, beacon_id } => {
                o.extend([cid::PING_ERROR, status.to_u8(), *beacon_id]);
            }
            Response::DatSend { status, beacon_id } => {
                o.extend([cid::DAT_SEND, status.to_u8(), *beacon_id]);
            }
            Response::DatReceive { fix, ack, data } => {
                o.push(cid::DAT_RECEIVE);
                fix.write(&mut o);
                let data = &data[..data.len().min(255)];
                o.extend([u8::from(*ack), data.len() as u8]);
                o.extend(data);
            }
            Response::DatError { status, beacon_id } => {
                o.extend([cid::DAT_ERROR, status.to_u8(), *beacon_id]);
            }
            Response::Other { cid, payload } => {
                o.push(*cid);
                o.extend(payload);
            }
        }
        o
    }

    /// The frame (`$`, hex, CRC, `\r\n`).
    pub fn encode(&self) -> String {
        encode_frame(Direction::Response, &self.message())
    }
}

fn read_status(r: &mut Rd) -> Result<Status, SeatracError> {
    use status_bits::*;
    let flags = r.u8()?;
    if flags & 0xC0 != 0 {
        return Err(SeatracError::BadField {
            cid: r.cid,
            what: "status content flags",
        });
    }
    let timestamp_ms = r.u64()?;
    let environment = if flags & ENVIRONMENT != 0 {
        Some(Environment {
            supply_mv: r.u16()?,
            temp_ddegc: r.i16()?,
            pressure_mbar: r.i32()?,
            depth_dm: r.i32()?,
            vos_dmps: r.u16()?,
        })
    } else {
        None
    };
    let attitude = if flags & ATTITUDE != 0 {
        let [yaw_ddeg, pitch_ddeg, roll_ddeg] = r.i16s()?;
        Some(Attitude {
            yaw_ddeg,
            pitch_ddeg,
            roll_ddeg,
        })
    } else {
        None
    };
    let mag_cal = if flags & MAG_CAL != 0 {
        Some(MagCal {
            buf_pct: r.u8()?,
            valid: r.u8()? != 0,
            age_s: r.u32()?,
            fit_pct: r.u8()?,
        })
    } else {
        None
    };
    let acc_cal = if flags & ACC_CAL != 0 {
        Some(r.i16s()?)
    } else {
        None
    };
    let ahrs_raw = if flags & AHRS_RAW_DATA != 0 {
        Some(r.i16s()?)
    } else {
        None
    };
    let ahrs_comp = if flags & AHRS_COMP_DATA != 0 {
        let [a0, a1, a2, m0, m1, m2, g0, g1, g2] = r.f32s()?;
        Some(AhrsComp {
            acc: [a0, a1, a2],
            mag: [m0, m1, m2],
            gyro: [g0, g1, g2],
        })
    } else {
        None
    };
    Ok(Status {
        timestamp_ms,
        environment,
        attitude,
        mag_cal,
        acc_cal,
        ahrs_raw,
        ahrs_comp,
    })
}

fn write_status(s: &Status, o: &mut Vec<u8>) {
    o.push(s.content_flags());
    o.extend(s.timestamp_ms.to_le_bytes());
    if let Some(e) = &s.environment {
        o.extend(e.supply_mv.to_le_bytes());
        o.extend(e.temp_ddegc.to_le_bytes());
        o.extend(e.pressure_mbar.to_le_bytes());
        o.extend(e.depth_dm.to_le_bytes());
        o.extend(e.vos_dmps.to_le_bytes());
    }
    if let Some(a) = &s.attitude {
        put_i16s(o, &[a.yaw_ddeg, a.pitch_ddeg, a.roll_ddeg]);
    }
    if let Some(m) = &s.mag_cal {
        o.extend([m.buf_pct, u8::from(m.valid)]);
        o.extend(m.age_s.to_le_bytes());
        o.push(m.fit_pct);
    }
    if let Some(a) = &s.acc_cal {
        put_i16s(o, a);
    }
    if let Some(a) = &s.ahrs_raw {
        put_i16s(o, a);
    }
    if let Some(a) = &s.ahrs_comp {
        for v in a.acc.iter().chain(&a.mag).chain(&a.gyro) {
            o.extend(v.to_le_bytes());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn crc_is_crc16_arc() {
        // The CRC-16/ARC check value (the catalogue's "123456789" → 0xBB3D).
        assert_eq!(crc16(b"123456789"), 0xBB3D);
        assert_eq!(crc16(&[]), 0);
    }

    // Frames built from UM-140's field tables; the CRCs were computed by an independent
    // bitwise CRC-16/ARC (Python), not by this module.
    #[test]
    fn commands_frame_as_the_guide_lays_them_out() {
        assert_eq!(Command::SysAlive.encode().unwrap(), "#01C1C0\r\n");
        let ping = Command::PingSend {
            dest_id: 15,
            msg_type: msg_type::REQU,
        };
        assert_eq!(ping.encode().unwrap(), "#400F0405E7\r\n");
        assert_eq!(Command::decode(b"#400F0405E7\r\n"), Ok(ping));
        assert_eq!(
            Command::DatSend {
                dest_id: 0,
                msg_type: 0,
                data: vec![0; 32]
            }
            .encode(),
            Err(SeatracError::PayloadTooLong(32))
        );
    }

    #[test]
    fn ping_send_status_codes_are_typed() {
        assert_eq!(
            Response::decode(b"$40000F41D0"),
            Ok(Response::PingSend {
                status: Cst::Ok,
                beacon_id: 15
            })
        );
        assert_eq!(
            Response::decode(b"$40300F55D0\r\n"),
            Ok(Response::PingSend {
                status: Cst::XcvrBusy,
                beacon_id: 15
            })
        );
        assert_eq!(
            Response::decode(b"$40300F55D1"),
            Err(SeatracError::BadCrc {
                found: 0xD155,
                computed: 0xD055
            })
        );
        assert_eq!(
            Response::decode(b"#40300F55D0"),
            Err(SeatracError::WrongDirection)
        );
        assert_eq!(Response::decode(b"$40300F55D"), Err(SeatracError::BadHex));
        assert_eq!(Response::decode(b"$4030"), Err(SeatracError::TooShort));
        assert_eq!(Cst::from_u8(0x34), Cst::XcvrRespTimeout);
    }

    #[test]
    fn status_with_environment_and_attitude_decodes() {
        // flags ENVIRONMENT|ATTITUDE, 123456 ms, 12.15 V, 21.5 °C, 1153 mbar, 1.5 m,
        // 1482.0 m/s, yaw 90.0°, pitch -2.5°, roll 1.2°.
        let line = b"$100340E2010000000000762FD700810400000F000000E4398403E7FF0C00C13B";
        let Response::Status(s) = Response::decode(line).unwrap() else {
            panic!()
        };
        assert_eq!(s.timestamp_ms, 123_456);
        let e = s.environment.unwrap();
        assert_eq!(
            (e.supply_v(), e.temp_degc(), e.pressure_mbar),
            (12.15, 21.5, 1153)
        );
        assert_eq!((e.depth_m(), e.vos_dmps), (1.5, 14820));
        let a = s.attitude.unwrap();
        assert_eq!(
            (a.yaw_deg(), a.pitch_deg(), a.roll_deg()),
            (90.0, -2.5, 1.2)
        );
        assert_eq!(s.ahrs_comp, None);
        assert_eq!(Response::Status(s).encode().trim_end().as_bytes(), line);
    }

    #[test]
    fn dat_receive_with_range_and_usbl_decodes() {
        // From beacon 3, RESPU, range 46.3 m, USBL azimuth 45.0°, elevation -30.0°, "abc".
        let line = b"$61000303050807000000001400E43944FDE803000068890900CF010444FD3AFD3FFD42FDC201D4FE0C00000361626378BC";
        let Response::DatReceive { fix, ack, data } = Response::decode(line).unwrap() else {
            panic!()
        };
        assert_eq!(
            (fix.src_id, fix.msg_type, ack, data.as_slice()),
            (3, 5, false, &b"abc"[..])
        );
        assert_eq!(fix.range_m(), Some(46.3));
        let u = fix.usbl.clone().unwrap();
        assert_eq!(u.rssi_cb, vec![-700, -710, -705, -702]);
        assert_eq!((u.azimuth_ddeg, u.elevation_ddeg), (450, -300));
        assert_eq!(fix.position, None);
        assert_eq!(fix.flags(), fix_flags::RANGE | fix_flags::USBL);
        let again = Response::DatReceive { fix, ack, data }.encode();
        assert_eq!(again.trim_end().as_bytes(), line);
    }

    #[test]
    fn settings_accessors_hit_the_startup_fields() {
        let mut s = Settings {
            raw: [0; SETTINGS_LEN],
        };
        s.set_beacon_id(7);
        s.set_env_salinity_dppt(350);
        s.set_status_mode(4);
        s.set_status_output(
            status_bits::ATTITUDE | status_bits::AHRS_COMP_DATA | status_bits::ENVIRONMENT,
        );
        assert_eq!(
            (s.raw[96], s.raw[33], s.raw[34], s.raw[0], s.raw[1]),
            (7, 94, 1, 4, 0x23)
        );
        let cmd = Command::SettingsSet(s.clone());
        assert_eq!(Command::decode(cmd.encode().unwrap().as_bytes()), Ok(cmd));
        let r = Response::SettingsGet(s);
        assert_eq!(Response::decode(r.encode().as_bytes()), Ok(r));
    }

    fn fix() -> impl Strategy<Value = AcoFix> {
        (
            (
                any::<u8>(),
                any::<u8>(),
                0u8..8,
                any::<[i16; 3]>(),
                any::<u16>(),
                any::<i16>(),
            ),
            proptest::option::of((any::<u32>(), any::<i32>(), any::<u16>())),
            proptest::option::of((
                proptest::collection::vec(any::<i16>(), 0..5),
                any::<[i16; 3]>(),
            )),
            proptest::option::of(any::<[i16; 3]>()),
            any::<(bool, bool)>(),
        )
            .prop_map(
                |((d, s, t, att, depth, rssi), range, usbl, pos, (e, fe))| AcoFix {
                    dest_id: d,
                    src_id: s,
                    msg_type: t,
                    attitude: Attitude {
                        yaw_ddeg: att[0],
                        pitch_ddeg: att[1],
                        roll_ddeg: att[2],
                    },
                    depth_local_dm: depth,
                    vos_dmps: 15000,
                    rssi_cb: rssi,
                    range: range.map(|(count, time_100ns, dist_dm)| Range {
                        count,
                        time_100ns,
                        dist_dm,
                    }),
                    usbl: usbl.map(|(rssi_cb, a)| Usbl {
                        rssi_cb,
                        azimuth_ddeg: a[0],
                        elevation_ddeg: a[1],
                        fit_error_centi: a[2],
                    }),
                    position: pos.map(|p| Position {
                        easting_dm: p[0],
                        northing_dm: p[1],
                        depth_dm: p[2],
                    }),
                    position_enhanced: e,
                    position_flt_error: fe,
                },
            )
    }

    proptest! {
        #[test]
        fn arbitrary_bytes_never_panic(data in proptest::collection::vec(any::<u8>(), 0..200)) {
            let _ = Response::decode(&data);
            let _ = Command::decode(&data);
            let _ = Response::decode_message(&data);
            let framed = encode_frame(Direction::Response, &data);
            let _ = Response::decode(framed.as_bytes());
        }

        #[test]
        fn fixes_and_status_encode_decode_is_identity(
            f in fix(), ack in any::<bool>(), data in proptest::collection::vec(any::<u8>(), 0..32),
            ts in any::<u64>(), env in proptest::option::of(any::<(u16, i16, i32, i32, u16)>()),
            raw in proptest::option::of(any::<[i16; 9]>()), comp in proptest::option::of(any::<[f32; 9]>()),
        ) {
            let mut f = f;
            if let Some(u) = &mut f.usbl { u.rssi_cb.truncate(4); }
            for r in [Response::PingResp(f.clone()), Response::DatReceive { fix: f, ack, data }] {
                prop_assert_eq!(Response::decode(r.encode().as_bytes()), Ok(r));
            }
            let s = Response::Status(Status { timestamp_ms: ts,
                environment: env.map(|(supply_mv, temp_ddegc, pressure_mbar, depth_dm, vos_dmps)|
                    Environment { supply_mv, temp_ddegc, pressure_mbar, depth_dm, vos_dmps }),
                attitude: None, mag_cal: None, acc_cal: None, ahrs_raw: raw,
                ahrs_comp: comp.map(|c| AhrsComp { acc: [c[0], c[1], c[2]], mag: [c[3], c[4], c[5]], gyro: [c[6], c[7], c[8]] }) });
            let line = s.encode();
            let back = Response::decode(line.as_bytes()).unwrap();
            prop_assert_eq!(back.encode(), line);
        }
    }
}
