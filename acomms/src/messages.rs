//! The message bodies, each declared once with its fields' bounds and resolution
//! (`#[derive(Compact)]`). Node ids are SeaTrac beacon ids: 1 to 15 name a node, 0 is
//! "every vehicle" (SeaTrac's BEACON_ALL) and only valid as a destination. Positions are the
//! mission's local x (east) and y (north) in metres; depth is positive down.

use compact::Compact;

/// The state a vehicle reports.
#[derive(Compact, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum VehicleMode {
    /// Powered, no mission running.
    Idle,
    /// Following its mission.
    Mission,
    /// Loitering at a commanded point.
    Loiter,
    /// Going home.
    Returning,
    /// Driving up to the surface.
    Surfacing,
    /// At the surface.
    Surfaced,
    /// Thrusters disarmed by a kill.
    Killed,
    /// A safety fault holds it.
    Fault,
}

/// The command a [`Confirm`] answers.
#[derive(Compact, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CommandKind {
    /// [`Kill`].
    Kill,
    /// [`Surface`].
    Surface,
    /// [`GoTo`].
    GoTo,
    /// [`Loiter`].
    Loiter,
    /// [`Return`].
    Return,
    /// [`SetDepth`].
    SetDepth,
    /// [`Abort`].
    Abort,
}

/// A vehicle's status (the Gen-1 VEHICLE_STATUS and the Gen-2 RESP_STATUS in one).
#[derive(Compact, Debug, Clone, Copy, PartialEq)]
pub struct Status {
    /// The reporting vehicle (1-15).
    #[compact(min = 0, max = 15, reject)]
    pub from: u8,
    /// Its state.
    pub mode: VehicleMode,
    /// Local x (east), metres, 0.1 m over +-5 km.
    #[compact(min = -5000.0, max = 5000.0, resolution = 0.1)]
    pub x_m: f64,
    /// Local y (north), metres, 0.1 m over +-5 km.
    #[compact(min = -5000.0, max = 5000.0, resolution = 0.1)]
    pub y_m: f64,
    /// Depth, metres, 0.1 m to 200 m.
    #[compact(min = 0.0, max = 200.0, resolution = 0.1)]
    pub depth_m: f64,
    /// Heading, degrees in [0, 359.5] at 0.5 (give it in [0, 360)).
    #[compact(min = 0.0, max = 359.5, resolution = 0.5)]
    pub heading_deg: f64,
    /// Speed through the water, m/s, 0.05 to 3.15.
    #[compact(min = 0.0, max = 3.15, resolution = 0.05)]
    pub speed_mps: f64,
    /// Battery voltage, volts, 0.05 V from 10 to 22.75 V.
    #[compact(min = 10.0, max = 22.75, resolution = 0.05)]
    pub battery_v: f64,
    /// Index of the waypoint it is heading for.
    pub waypoint: u8,
    /// The safety supervisor's health word.
    pub health: u16,
    /// The navigator's horizontal 1-sigma, metres, 0.1 m to 51 m; `None` without an estimate.
    #[compact(min = 0.0, max = 51.0, resolution = 0.1)]
    pub nav_sigma_m: Option<f64>,
}

/// Asks a vehicle for its [`Status`] (Gen-1 REQUEST_STATUS, Gen-2 REQ_STATUS).
#[derive(Compact, Debug, Clone, Copy, PartialEq, Eq)]
pub struct StatusRequest {
    /// The asking node (1-15).
    #[compact(min = 0, max = 15, reject)]
    pub from: u8,
    /// The vehicle asked (1-15).
    #[compact(min = 0, max = 15, reject)]
    pub to: u8,
}

/// Asks a vehicle for its [`Localisation`] (Gen-1 REQUEST_LOCALIZATION_INFO).
#[derive(Compact, Debug, Clone, Copy, PartialEq, Eq)]
pub struct LocalisationRequest {
    /// The asking node (1-15).
    #[compact(min = 0, max = 15, reject)]
    pub from: u8,
    /// The vehicle asked (1-15).
    #[compact(min = 0, max = 15, reject)]
    pub to: u8,
}

/// A vehicle's pose for cooperative localisation (Gen-1 LOCALIZATION_INFO: the listener
/// adds the USBL range and bearing of the packet).
#[derive(Compact, Debug, Clone, Copy, PartialEq)]
pub struct Localisation {
    /// The reporting vehicle (1-15).
    #[compact(min = 0, max = 15, reject)]
    pub from: u8,
    /// Local x (east), metres, 0.1 m over +-5 km.
    #[compact(min = -5000.0, max = 5000.0, resolution = 0.1)]
    pub x_m: f64,
    /// Local y (north), metres, 0.1 m over +-5 km.
    #[compact(min = -5000.0, max = 5000.0, resolution = 0.1)]
    pub y_m: f64,
    /// Depth, metres, 0.1 m to 200 m.
    #[compact(min = 0.0, max = 200.0, resolution = 0.1)]
    pub depth_m: f64,
    /// Roll, degrees, 0.5 over +-90.
    #[compact(min = -90.0, max = 90.0, resolution = 0.5)]
    pub roll_deg: f64,
    /// Pitch, degrees, 0.5 over +-90.
    #[compact(min = -90.0, max = 90.0, resolution = 0.5)]
    pub pitch_deg: f64,
    /// Heading, degrees in [0, 359.5] at 0.5.
    #[compact(min = 0.0, max = 359.5, resolution = 0.5)]
    pub heading_deg: f64,
}

/// The authenticated header of every command and confirmation: who sends, to whom, the
/// sender's sequence number (24 bits) and the time it was sent (12 bits: whole seconds of the
/// sender's clock modulo an hour; see [`crate::auth`]).
#[derive(Compact, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Auth {
    /// The sender (1-15).
    #[compact(min = 0, max = 15, reject)]
    pub from: u8,
    /// The destination (1-15), or 0 for every vehicle.
    #[compact(min = 0, max = 15, reject)]
    pub to: u8,
    /// The sender's sequence number, strictly increasing per sender and key.
    #[compact(min = 0, max = 16_777_215, reject)]
    pub seq: u32,
    /// When it was sent: whole seconds of the sender's clock modulo
    /// [`crate::auth::TIME_MODULO`] ([`crate::auth::time_stamp`]).
    #[compact(min = 0, max = 3599, reject)]
    pub time_s: u16,
}

impl Auth {
    /// A header from `from` to `to` with sequence number `seq`, sent at stamp 0 (see
    /// [`Auth::at`]).
    pub fn new(from: u8, to: u8, seq: u32) -> Self {
        Self {
            from,
            to,
            seq,
            time_s: 0,
        }
    }

    /// The header stamped as sent at `now` (seconds of the sender's clock, MOOS time).
    ///
    /// ```
    /// let a = acomms::Auth::new(1, 2, 3).at(1_786_000_123.7);
    /// assert_eq!(u32::from(a.time_s), 1_786_000_123 % 3600);
    /// ```
    pub fn at(self, now: f64) -> Self {
        Self {
            time_s: crate::auth::time_stamp(now),
            ..self
        }
    }
}

/// Emergency kill: disarm the thrusters (Gen-1 EMERGENCY_KILL, Gen-2 SRV_EMERGENCY_STOP).
#[derive(Compact, Debug, Clone, Copy, PartialEq, Eq)]
pub struct Kill {
    /// Sender, destination, sequence.
    pub auth: Auth,
}

/// Emergency surface: drive to the surface (Gen-1 EMERGENCY_SURFACE, Gen-2
/// SRV_EMERGENCY_SURFACE).
#[derive(Compact, Debug, Clone, Copy, PartialEq, Eq)]
pub struct Surface {
    /// Sender, destination, sequence.
    pub auth: Auth,
}

/// Abort the mission: stop following it and hold, the helm parked (Gen-2 SRV_STOP).
#[derive(Compact, Debug, Clone, Copy, PartialEq, Eq)]
pub struct Abort {
    /// Sender, destination, sequence.
    pub auth: Auth,
}

/// Return home (Gen-2 SRV_HOME).
#[derive(Compact, Debug, Clone, Copy, PartialEq, Eq)]
pub struct Return {
    /// Sender, destination, sequence.
    pub auth: Auth,
}

/// Go to a point.
#[derive(Compact, Debug, Clone, Copy, PartialEq)]
pub struct GoTo {
    /// Sender, destination, sequence.
    pub auth: Auth,
    /// Local x (east), metres, 0.1 m over +-5 km; refused outside.
    #[compact(min = -5000.0, max = 5000.0, resolution = 0.1, reject)]
    pub x_m: f64,
    /// Local y (north), metres, 0.1 m over +-5 km; refused outside.
    #[compact(min = -5000.0, max = 5000.0, resolution = 0.1, reject)]
    pub y_m: f64,
    /// Depth to hold, metres, 0.1 m to 200 m; refused outside; `None` keeps the current one.
    #[compact(min = 0.0, max = 200.0, resolution = 0.1, reject)]
    pub depth_m: Option<f64>,
    /// Speed, m/s, 0.05 to 3.15; clamped.
    #[compact(min = 0.0, max = 3.15, resolution = 0.05)]
    pub speed_mps: f64,
}

/// Loiter at a point.
#[derive(Compact, Debug, Clone, Copy, PartialEq)]
pub struct Loiter {
    /// Sender, destination, sequence.
    pub auth: Auth,
    /// Centre x (east), metres, 0.1 m over +-5 km; refused outside.
    #[compact(min = -5000.0, max = 5000.0, resolution = 0.1, reject)]
    pub x_m: f64,
    /// Centre y (north), metres, 0.1 m over +-5 km; refused outside.
    #[compact(min = -5000.0, max = 5000.0, resolution = 0.1, reject)]
    pub y_m: f64,
    /// Radius, metres, 1 m from 1 to 256; clamped.
    #[compact(min = 1.0, max = 256.0, resolution = 1.0)]
    pub radius_m: f64,
    /// Depth to hold, metres, 0.1 m to 200 m; refused outside; `None` keeps the current one.
    #[compact(min = 0.0, max = 200.0, resolution = 0.1, reject)]
    pub depth_m: Option<f64>,
    /// Speed, m/s, 0.05 to 3.15; clamped.
    #[compact(min = 0.0, max = 3.15, resolution = 0.05)]
    pub speed_mps: f64,
    /// Clockwise (seen from above) rather than counter-clockwise.
    pub clockwise: bool,
}

/// Hold a new depth.
#[derive(Compact, Debug, Clone, Copy, PartialEq)]
pub struct SetDepth {
    /// Sender, destination, sequence.
    pub auth: Auth,
    /// Depth, metres, 0.1 m to 200 m; refused outside.
    #[compact(min = 0.0, max = 200.0, resolution = 0.1, reject)]
    pub depth_m: f64,
}

/// A vehicle's answer to a command (Gen-1 CONFIRM_EMERGENCY_KILL and
/// CONFIRM_EMERGENCY_SURFACE, for every command), authenticated so a forged confirmation
/// cannot tell the base a kill took effect.
#[derive(Compact, Debug, Clone, Copy, PartialEq, Eq)]
pub struct Confirm {
    /// The vehicle (sender) and the commander (destination), the vehicle's own sequence.
    pub auth: Auth,
    /// Which command.
    pub command: CommandKind,
    /// The command's sequence number.
    #[compact(min = 0, max = 16_777_215, reject)]
    pub command_seq: u32,
    /// Whether it was carried out.
    pub success: bool,
}
