//! The Water Linked DVL A50's TCP protocol: newline-delimited JSON (Water Linked, "DVL
//! protocol", JSON over TCP, `https://docs.waterlinked.com/dvl/dvl-protocol`, protocol
//! `json_v3.1`; `cougars-vehicle.md` §3.2).
//!
//! The DVL sends velocity reports (`"type":"velocity"`), dead-reckoning reports
//! (`"type":"position_local"`) and responses to commands (`"type":"response"`); it accepts
//! commands (`{"command":"set_config","parameters":{...}}`, `get_config`, `calibrate_gyro`,
//! `reset_dead_reckoning`). Velocities are in the DVL's body frame (FRD), metres per second.
//! Encoders for each message serve the emulator. Use [`crate::line::LineSplitter`] with
//! [`MAX_LINE`] to bound the line length.

use serde_json::{Map, Value, json};

use crate::line::ProtocolError;

/// The longest line accepted from the DVL: a velocity report with its four transducers and
/// covariance is about 1.3 kB.
pub const MAX_LINE: usize = 8192;

/// Why a line was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum A50Error {
    /// Not a JSON object.
    #[error("not a JSON object: {0}")]
    Json(String),
    /// A required member is missing.
    #[error("missing member {0}")]
    Missing(&'static str),
    /// A member has the wrong JSON type or shape.
    #[error("member {0} has the wrong type")]
    BadMember(&'static str),
    /// A JSON object that is none of the known messages.
    #[error("unknown message")]
    Unknown,
}

impl ProtocolError for A50Error {
    fn is_checksum(&self) -> bool {
        false
    }
}

/// One transducer (beam) of a velocity report.
#[derive(Debug, Clone, PartialEq)]
pub struct Transducer {
    /// Beam id, 0–3.
    pub id: i64,
    /// Velocity along the beam, m/s.
    pub velocity_mps: f64,
    /// Distance to the bottom along the beam, metres.
    pub distance_m: f64,
    /// Received signal strength, dBm.
    pub rssi_dbm: f64,
    /// Noise spectral density, dBm.
    pub nsd_dbm: f64,
    /// The beam has bottom lock.
    pub beam_valid: bool,
}

/// A velocity report (`"type":"velocity"`).
#[derive(Debug, Clone, PartialEq)]
pub struct VelocityReport {
    /// Milliseconds since the previous velocity report (`time`).
    pub time_ms: f64,
    /// When the velocity was valid, µs since the Unix epoch (`time_of_validity`).
    pub time_of_validity_us: Option<u64>,
    /// When the report was sent, µs since the Unix epoch (`time_of_transmission`).
    pub time_of_transmission_us: Option<u64>,
    /// Velocity in the DVL frame (vx, vy, vz), m/s.
    pub vel_body_mps: [f64; 3],
    /// Figure of merit (velocity uncertainty), m/s.
    pub fom_mps: f64,
    /// Covariance of the velocity, (m/s)², row-major.
    pub covariance: Option<[[f64; 3]; 3]>,
    /// Distance to the bottom, metres (negative when invalid).
    pub altitude_m: f64,
    /// The beams.
    pub transducers: Vec<Transducer>,
    /// The velocity is valid (bottom lock).
    pub velocity_valid: bool,
    /// Status: 0 normal, 1 high temperature (acoustics throttled).
    pub status: i64,
    /// The protocol format (`json_v3.1`).
    pub format: Option<String>,
}

/// A dead-reckoning report (`"type":"position_local"`).
#[derive(Debug, Clone, PartialEq)]
pub struct DeadReckoningReport {
    /// Time stamp, seconds (`ts`).
    pub ts_s: f64,
    /// Position from the reset point, x (forward at reset), metres.
    pub x_m: f64,
    /// Position y, metres.
    pub y_m: f64,
    /// Position z (down), metres.
    pub z_m: f64,
    /// Standard deviation of the position, metres.
    pub std_m: f64,
    /// Roll, degrees.
    pub roll_deg: f64,
    /// Pitch, degrees.
    pub pitch_deg: f64,
    /// Yaw, degrees.
    pub yaw_deg: f64,
    /// Status: 0 normal, 1 error.
    pub status: i64,
    /// The protocol format.
    pub format: Option<String>,
}

/// The DVL's configuration (`set_config` parameters and the `get_config` result). Every
/// member is optional: `set_config` sends only what it changes.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Config {
    /// Speed of sound, m/s.
    pub speed_of_sound_mps: Option<f64>,
    /// Acoustics on (off in air, or the unit overheats).
    pub acoustic_enabled: Option<bool>,
    /// The LED off.
    pub dark_mode_enabled: Option<bool>,
    /// Mounting rotation offset, degrees.
    pub mounting_rotation_offset_deg: Option<f64>,
    /// Range mode (`auto` or a fixed mode).
    pub range_mode: Option<String>,
}

/// A command to the DVL.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// `set_config` with the given parameters.
    SetConfig(Config),
    /// `get_config`.
    GetConfig,
    /// `calibrate_gyro` (hold still; takes seconds).
    CalibrateGyro,
    /// `reset_dead_reckoning`.
    ResetDeadReckoning,
}

/// The DVL's answer to a command (`"type":"response"`).
#[derive(Debug, Clone, PartialEq)]
pub struct Response {
    /// The command answered (`response_to`).
    pub response_to: String,
    /// The command succeeded.
    pub success: bool,
    /// Why it failed (empty on success).
    pub error_message: String,
    /// The configuration, for `get_config` (and `set_config` on recent firmware).
    pub result: Option<Config>,
    /// The protocol format.
    pub format: Option<String>,
}

/// One message from the DVL.
#[derive(Debug, Clone, PartialEq)]
pub enum Message {
    /// A velocity report.
    Velocity(VelocityReport),
    /// A dead-reckoning report.
    DeadReckoning(DeadReckoningReport),
    /// A response to a command.
    Response(Response),
}

type Obj = Map<String, Value>;

fn f(o: &Obj, k: &'static str) -> Result<f64, A50Error> {
    o.get(k)
        .ok_or(A50Error::Missing(k))?
        .as_f64()
        .ok_or(A50Error::BadMember(k))
}

fn opt_f(o: &Obj, k: &'static str) -> Result<Option<f64>, A50Error> {
    match o.get(k) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => v.as_f64().map(Some).ok_or(A50Error::BadMember(k)),
    }
}

fn i(o: &Obj, k: &'static str) -> Result<i64, A50Error> {
    match o.get(k) {
        None => Ok(0),
        Some(v) => v.as_i64().ok_or(A50Error::BadMember(k)),
    }
}

fn opt_u(o: &Obj, k: &'static str) -> Result<Option<u64>, A50Error> {
    match o.get(k) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => v.as_u64().map(Some).ok_or(A50Error::BadMember(k)),
    }
}

fn b(o: &Obj, k: &'static str) -> Result<bool, A50Error> {
    o.get(k)
        .ok_or(A50Error::Missing(k))?
        .as_bool()
        .ok_or(A50Error::BadMember(k))
}

fn opt_b(o: &Obj, k: &'static str) -> Result<Option<bool>, A50Error> {
    match o.get(k) {
        None | Some(Value::Null) => Ok(None),
        Some(v) => v.as_bool().map(Some).ok_or(A50Error::BadMember(k)),
    }
}

fn opt_s(o: &Obj, k: &'static str) -> Result<Option<String>, A50Error> {
    match o.get(k) {
        None | Some(Value::Null) => Ok(None),
        Some(Value::String(s)) => Ok(Some(s.clone())),
        Some(_) => Err(A50Error::BadMember(k)),
    }
}

fn object(line: &[u8]) -> Result<Obj, A50Error> {
    match serde_json::from_slice::<Value>(line) {
        Ok(Value::Object(o)) => Ok(o),
        Ok(_) => Err(A50Error::Json("not an object".into())),
        Err(e) => Err(A50Error::Json(e.to_string())),
    }
}

/// Parses one line from the DVL. The message is chosen by `type`; without one, by the
/// CoUGARs driver's rule (`altitude` → velocity, `pitch` → dead reckoning, `response_to` →
/// response).
pub fn parse(line: &[u8]) -> Result<Message, A50Error> {
    let o = object(line)?;
    let kind = match o.get("type") {
        Some(Value::String(t)) => t.as_str(),
        Some(_) => return Err(A50Error::BadMember("type")),
        None if o.contains_key("altitude") => "velocity",
        None if o.contains_key("pitch") => "position_local",
        None if o.contains_key("response_to") => "response",
        None => return Err(A50Error::Unknown),
    };
    match kind {
        "velocity" => velocity(&o).map(Message::Velocity),
        "position_local" => dead_reckoning(&o).map(Message::DeadReckoning),
        "response" => response(&o).map(Message::Response),
        _ => Err(A50Error::Unknown),
    }
}

fn velocity(o: &Obj) -> Result<VelocityReport, A50Error> {
    let covariance = match o.get("covariance") {
        None | Some(Value::Null) => None,
        Some(Value::Array(rows)) if rows.len() == 3 => {
            let mut c = [[0.0; 3]; 3];
            for (r, row) in rows.iter().enumerate() {
                let row = row
                    .as_array()
                    .filter(|a| a.len() == 3)
                    .ok_or(A50Error::BadMember("covariance"))?;
                for (k, v) in row.iter().enumerate() {
                    c[r][k] = v.as_f64().ok_or(A50Error::BadMember("covariance"))?;
                }
            }
            Some(c)
        }
        Some(_) => return Err(A50Error::BadMember("covariance")),
    };
    let mut transducers = Vec::new();
    match o.get("transducers") {
        None | Some(Value::Null) => {}
        Some(Value::Array(a)) => {
            for t in a {
                let t = t.as_object().ok_or(A50Error::BadMember("transducers"))?;
                transducers.push(Transducer {
                    id: i(t, "id")?,
                    velocity_mps: f(t, "velocity")?,
                    distance_m: f(t, "distance")?,
                    rssi_dbm: f(t, "rssi")?,
                    nsd_dbm: f(t, "nsd")?,
                    beam_valid: b(t, "beam_valid")?,
                });
            }
        }
        Some(_) => return Err(A50Error::BadMember("transducers")),
    }
    Ok(VelocityReport {
        time_ms: f(o, "time")?,
        time_of_validity_us: opt_u(o, "time_of_validity")?,
        time_of_transmission_us: opt_u(o, "time_of_transmission")?,
        vel_body_mps: [f(o, "vx")?, f(o, "vy")?, f(o, "vz")?],
        fom_mps: f(o, "fom")?,
        covariance,
        altitude_m: f(o, "altitude")?,
        transducers,
        velocity_valid: b(o, "velocity_valid")?,
        status: i(o, "status")?,
        format: opt_s(o, "format")?,
    })
}

fn dead_reckoning(o: &Obj) -> Result<DeadReckoningReport, A50Error> {
    Ok(DeadReckoningReport {
        ts_s: f(o, "ts")?,
        x_m: f(o, "x")?,
        y_m: f(o, "y")?,
        z_m: f(o, "z")?,
        std_m: f(o, "std")?,
        roll_deg: f(o, "roll")?,
        pitch_deg: f(o, "pitch")?,
        yaw_deg: f(o, "yaw")?,
        status: i(o, "status")?,
        format: opt_s(o, "format")?,
    })
}

fn config(o: &Obj) -> Result<Config, A50Error> {
    Ok(Config {
        speed_of_sound_mps: opt_f(o, "speed_of_sound")?,
        acoustic_enabled: opt_b(o, "acoustic_enabled")?,
        dark_mode_enabled: opt_b(o, "dark_mode_enabled")?,
        mounting_rotation_offset_deg: opt_f(o, "mounting_rotation_offset")?,
        range_mode: opt_s(o, "range_mode")?,
    })
}

fn response(o: &Obj) -> Result<Response, A50Error> {
    let result = match o.get("result") {
        None | Some(Value::Null) => None,
        Some(Value::Object(r)) => Some(config(r)?),
        Some(_) => return Err(A50Error::BadMember("result")),
    };
    Ok(Response {
        response_to: opt_s(o, "response_to")?.ok_or(A50Error::Missing("response_to"))?,
        success: b(o, "success")?,
        error_message: opt_s(o, "error_message")?.unwrap_or_default(),
        result,
        format: opt_s(o, "format")?,
    })
}

/// Parses a command line (the emulator's side).
pub fn parse_command(line: &[u8]) -> Result<Command, A50Error> {
    let o = object(line)?;
    match o.get("command") {
        Some(Value::String(c)) => match c.as_str() {
            "set_config" => match o.get("parameters") {
                Some(Value::Object(p)) => config(p).map(Command::SetConfig),
                Some(_) => Err(A50Error::BadMember("parameters")),
                None => Err(A50Error::Missing("parameters")),
            },
            "get_config" => Ok(Command::GetConfig),
            "calibrate_gyro" => Ok(Command::CalibrateGyro),
            "reset_dead_reckoning" => Ok(Command::ResetDeadReckoning),
            _ => Err(A50Error::Unknown),
        },
        Some(_) => Err(A50Error::BadMember("command")),
        None => Err(A50Error::Missing("command")),
    }
}

/// A JSON number, or null for a non-finite value (JSON has no NaN).
fn num(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

fn line(v: Value) -> String {
    format!("{v}\n")
}

impl Config {
    fn to_json(&self) -> Value {
        let mut o = Obj::new();
        if let Some(v) = self.speed_of_sound_mps {
            o.insert("speed_of_sound".into(), num(v));
        }
        if let Some(v) = self.acoustic_enabled {
            o.insert("acoustic_enabled".into(), json!(v));
        }
        if let Some(v) = self.dark_mode_enabled {
            o.insert("dark_mode_enabled".into(), json!(v));
        }
        if let Some(v) = self.mounting_rotation_offset_deg {
            o.insert("mounting_rotation_offset".into(), num(v));
        }
        if let Some(v) = &self.range_mode {
            o.insert("range_mode".into(), json!(v));
        }
        Value::Object(o)
    }
}

impl Command {
    /// The command's name on the wire.
    pub fn name(&self) -> &'static str {
        match self {
            Command::SetConfig(_) => "set_config",
            Command::GetConfig => "get_config",
            Command::CalibrateGyro => "calibrate_gyro",
            Command::ResetDeadReckoning => "reset_dead_reckoning",
        }
    }

    /// The command as one JSON line with its `\n`.
    pub fn encode(&self) -> String {
        match self {
            Command::SetConfig(c) => {
                line(json!({"command": "set_config", "parameters": c.to_json()}))
            }
            other => line(json!({ "command": other.name() })),
        }
    }
}

impl VelocityReport {
    /// The report as one JSON line with its `\n`, members named as the A50 names them.
    pub fn encode(&self) -> String {
        let mut o = Obj::new();
        o.insert("time".into(), num(self.time_ms));
        o.insert("vx".into(), num(self.vel_body_mps[0]));
        o.insert("vy".into(), num(self.vel_body_mps[1]));
        o.insert("vz".into(), num(self.vel_body_mps[2]));
        o.insert("fom".into(), num(self.fom_mps));
        if let Some(c) = &self.covariance {
            let rows: Vec<Value> = c
                .iter()
                .map(|r| Value::Array(r.iter().map(|&v| num(v)).collect()))
                .collect();
            o.insert("covariance".into(), Value::Array(rows));
        }
        o.insert("altitude".into(), num(self.altitude_m));
        let ts: Vec<Value> = self
            .transducers
            .iter()
            .map(|t| {
                json!({"id": t.id, "velocity": num(t.velocity_mps), "distance": num(t.distance_m),
                       "rssi": num(t.rssi_dbm), "nsd": num(t.nsd_dbm), "beam_valid": t.beam_valid})
            })
            .collect();
        o.insert("transducers".into(), Value::Array(ts));
        o.insert("velocity_valid".into(), json!(self.velocity_valid));
        o.insert("status".into(), json!(self.status));
        if let Some(v) = &self.format {
            o.insert("format".into(), json!(v));
        }
        o.insert("type".into(), json!("velocity"));
        if let Some(v) = self.time_of_validity_us {
            o.insert("time_of_validity".into(), json!(v));
        }
        if let Some(v) = self.time_of_transmission_us {
            o.insert("time_of_transmission".into(), json!(v));
        }
        line(Value::Object(o))
    }
}

impl DeadReckoningReport {
    /// The report as one JSON line with its `\n`.
    pub fn encode(&self) -> String {
        let mut o = Obj::new();
        for (k, v) in [
            ("ts", self.ts_s),
            ("x", self.x_m),
            ("y", self.y_m),
            ("z", self.z_m),
            ("std", self.std_m),
            ("roll", self.roll_deg),
            ("pitch", self.pitch_deg),
            ("yaw", self.yaw_deg),
        ] {
            o.insert(k.into(), num(v));
        }
        o.insert("type".into(), json!("position_local"));
        o.insert("status".into(), json!(self.status));
        if let Some(v) = &self.format {
            o.insert("format".into(), json!(v));
        }
        line(Value::Object(o))
    }
}

impl Response {
    /// The response as one JSON line with its `\n`.
    pub fn encode(&self) -> String {
        let mut o = Obj::new();
        o.insert("response_to".into(), json!(self.response_to));
        o.insert("success".into(), json!(self.success));
        o.insert("error_message".into(), json!(self.error_message));
        o.insert(
            "result".into(),
            self.result.as_ref().map_or(Value::Null, Config::to_json),
        );
        if let Some(v) = &self.format {
            o.insert("format".into(), json!(v));
        }
        o.insert("type".into(), json!("response"));
        line(Value::Object(o))
    }
}

impl Message {
    /// The message as one JSON line with its `\n`.
    pub fn encode(&self) -> String {
        match self {
            Message::Velocity(m) => m.encode(),
            Message::DeadReckoning(m) => m.encode(),
            Message::Response(m) => m.encode(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    // Modelled on the examples of Water Linked's DVL protocol page (JSON over TCP, json_v3.1),
    // written from its member tables: a velocity report, a dead-reckoning report and command
    // responses (the numbers are of the documented magnitudes, not checked byte for byte).
    const VELOCITY: &[u8] = br#"{"time": 106.3935775756836, "vx": -3.713480691658333e-05, "vy": 5.703703573090024e-05, "vz": 2.4990416932269e-05, "fom": 0.00016016385052353144, "covariance": [[2.4471841442164077e-08, -3.3937477272871774e-09, -1.6659699175747563e-10], [-3.3937477272871774e-09, 1.4654466085062268e-08, 4.0409570134514183e-10], [-1.6659699175747563e-10, 4.0409570134514183e-10, 1.5971971523143225e-09]], "altitude": 0.4949815273284912, "transducers": [{"id": 0, "velocity": 0.00010825289791682735, "distance": 0.5568000078201294, "rssi": -30.494251251220703, "nsd": -88.73271179199219, "beam_valid": true}, {"id": 1, "velocity": -1.4719001228513662e-05, "distance": 0.5663999915122986, "rssi": -31.095735549926758, "nsd": -89.5116958618164, "beam_valid": true}, {"id": 2, "velocity": 2.7863150535267778e-05, "distance": 0.537600040435791, "rssi": -27.180519104003906, "nsd": -96.98075103759766, "beam_valid": true}, {"id": 3, "velocity": 1.9419496311456896e-05, "distance": 0.5472000241279602, "rssi": -28.006759643554688, "nsd": -93.74205780029297, "beam_valid": true}], "velocity_valid": true, "status": 0, "format": "json_v3.1", "type": "velocity", "time_of_validity": 1638191471563017, "time_of_transmission": 1638191471752336}"#;
    const DEAD_RECKONING: &[u8] = br#"{"ts": 49056.809, "x": 12.43563613697886467, "y": 64.617631213992485, "z": 1.767641040211041, "std": 0.10324677826545026, "roll": -0.5478003225530587, "pitch": 1.6198040974228013, "yaw": 2.0207023024296066, "type": "position_local", "status": 0, "format": "json_v3.1"}"#;
    const GYRO_OK: &[u8] = br#"{"response_to":"calibrate_gyro","success":true,"error_message":"","result":null,"format":"json_v3.1","type":"response"}"#;
    const CONFIG: &[u8] = br#"{"response_to":"get_config","success":true,"error_message":"","result":{"speed_of_sound":1475.0,"acoustic_enabled":true,"dark_mode_enabled":false,"mounting_rotation_offset":0.0,"range_mode":"auto"},"format":"json_v3.1","type":"response"}"#;

    #[test]
    fn documented_velocity_report_decodes_and_round_trips() {
        let Message::Velocity(v) = parse(VELOCITY).unwrap() else {
            panic!()
        };
        assert_eq!(v.vel_body_mps[0], -3.713480691658333e-05);
        assert_eq!(v.altitude_m, 0.4949815273284912);
        assert_eq!(v.time_of_validity_us, Some(1638191471563017));
        assert_eq!(v.transducers.len(), 4);
        assert_eq!(v.transducers[2].distance_m, 0.537600040435791);
        assert!(v.velocity_valid && v.transducers.iter().all(|t| t.beam_valid));
        assert_eq!(v.covariance.unwrap()[1][1], 1.4654466085062268e-08);
        let again = v.encode();
        assert_eq!(parse(again.as_bytes()), Ok(Message::Velocity(v)));
    }

    #[test]
    fn documented_dead_reckoning_and_responses_decode() {
        let Message::DeadReckoning(d) = parse(DEAD_RECKONING).unwrap() else {
            panic!()
        };
        assert_eq!((d.ts_s, d.std_m), (49056.809, 0.10324677826545026));
        assert_eq!(d.yaw_deg, 2.0207023024296066);
        assert_eq!(parse(d.encode().as_bytes()), Ok(Message::DeadReckoning(d)));
        let Message::Response(r) = parse(GYRO_OK).unwrap() else {
            panic!()
        };
        assert_eq!(
            (r.response_to.as_str(), r.success, r.result),
            ("calibrate_gyro", true, None)
        );
        let Message::Response(r) = parse(CONFIG).unwrap() else {
            panic!()
        };
        let c = r.result.clone().unwrap();
        assert_eq!(c.speed_of_sound_mps, Some(1475.0));
        assert_eq!(c.range_mode.as_deref(), Some("auto"));
        assert_eq!(parse(r.encode().as_bytes()), Ok(Message::Response(r)));
    }

    #[test]
    fn the_cougars_driver_dispatch_rule_applies_without_a_type() {
        // Older firmware (json_v2) has no `type`: the driver dispatches on the members.
        let dr =
            br#"{"ts":1.0,"x":1,"y":2,"z":3,"std":0.1,"roll":0,"pitch":0,"yaw":90,"status":0}"#;
        assert!(matches!(parse(dr), Ok(Message::DeadReckoning(d)) if d.yaw_deg == 90.0));
        assert_eq!(parse(br#"{"foo":1}"#), Err(A50Error::Unknown));
        assert_eq!(
            parse(br#"[1]"#),
            Err(A50Error::Json("not an object".into()))
        );
        assert_eq!(
            parse(br#"{"type":"velocity","time":1}"#),
            Err(A50Error::Missing("vx"))
        );
    }

    #[test]
    fn commands_encode_as_documented_and_parse_back() {
        let off = Command::SetConfig(Config {
            acoustic_enabled: Some(false),
            ..Config::default()
        });
        assert_eq!(
            off.encode(),
            "{\"command\":\"set_config\",\"parameters\":{\"acoustic_enabled\":false}}\n"
        );
        assert_eq!(
            Command::CalibrateGyro.encode(),
            "{\"command\":\"calibrate_gyro\"}\n"
        );
        for c in [
            off,
            Command::GetConfig,
            Command::CalibrateGyro,
            Command::ResetDeadReckoning,
        ] {
            assert_eq!(parse_command(c.encode().trim_end().as_bytes()), Ok(c));
        }
        assert_eq!(
            parse_command(br#"{"command":"reboot"}"#),
            Err(A50Error::Unknown)
        );
    }

    fn finite() -> impl Strategy<Value = f64> {
        prop::num::f64::NORMAL | prop::num::f64::ZERO
    }

    proptest! {
        #[test]
        fn arbitrary_bytes_never_panic(data in proptest::collection::vec(any::<u8>(), 0..200)) {
            let _ = parse(&data);
            let _ = parse_command(&data);
        }

        #[test]
        fn velocity_and_dr_encode_decode_is_identity(
            v in [finite(), finite(), finite()], fom in finite(), alt in finite(),
            valid in any::<bool>(), status in -5i64..5, tov in proptest::option::of(any::<u64>()),
            beams in proptest::collection::vec((0i64..4, finite(), finite(), any::<bool>()), 0..5),
            dr in [finite(), finite(), finite(), finite(), finite(), finite(), finite(), finite()],
        ) {
            let r = VelocityReport { time_ms: fom, time_of_validity_us: tov, time_of_transmission_us: None,
                vel_body_mps: v, fom_mps: fom, covariance: Some([v, v, v]), altitude_m: alt,
                transducers: beams.iter().map(|&(id, vel, d, ok)| Transducer { id, velocity_mps: vel,
                    distance_m: d, rssi_dbm: -30.5, nsd_dbm: -90.25, beam_valid: ok }).collect(),
                velocity_valid: valid, status, format: Some("json_v3.1".into()) };
            prop_assert_eq!(parse(r.encode().as_bytes()), Ok(Message::Velocity(r)));
            let d = DeadReckoningReport { ts_s: dr[0], x_m: dr[1], y_m: dr[2], z_m: dr[3], std_m: dr[4],
                roll_deg: dr[5], pitch_deg: dr[6], yaw_deg: dr[7], status, format: None };
            prop_assert_eq!(parse(d.encode().as_bytes()), Ok(Message::DeadReckoning(d)));
        }
    }
}
