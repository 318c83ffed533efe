//! One emulator by device name, with its usual transport: what `coug emulate` runs and
//! what an in-process caller (the simulator, a driver's test) starts with [`spawn`].

use std::io;
use std::str::FromStr;

use crate::device::{Device, Emulator};
use crate::dvl::{A50, A50Settings};
use crate::fault::{FaultClock, FaultPlan};
use crate::gps::{GpsSettings, Gpsd, NmeaGps};
use crate::seatrac::{X150, X150Settings};
use crate::teensy::{Teensy, TeensyPort, TeensySettings};
use crate::transport::{self, Handle, Transport};
use crate::truth::{SharedTruth, TruthSource};
use crate::warp::{Warped, WarpedTruth, faults_to_wall};

/// The four devices.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// The GPS: NMEA on a pseudo-terminal, or gpsd's JSON on TCP.
    Gps,
    /// The DVL A50 (TCP).
    Dvl,
    /// The SeaTrac X150 (serial).
    Seatrac,
    /// The Teensy (serial).
    Teensy,
}

impl FromStr for Kind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "gps" => Ok(Kind::Gps),
            "dvl" => Ok(Kind::Dvl),
            "seatrac" => Ok(Kind::Seatrac),
            "teensy" => Ok(Kind::Teensy),
            other => Err(format!(
                "unknown device {other:?} (gps, dvl, seatrac or teensy)"
            )),
        }
    }
}

impl Kind {
    /// The device's name.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Gps => "gps",
            Kind::Dvl => "dvl",
            Kind::Seatrac => "seatrac",
            Kind::Teensy => "teensy",
        }
    }

    /// Its transport when none is given: TCP on an OS-picked loopback port for the DVL, a
    /// pseudo-terminal for the others.
    pub fn default_transport(self) -> Transport {
        match self {
            Kind::Dvl => Transport::loopback(0),
            _ => Transport::Pty { link: None },
        }
    }
}

/// The devices' settings (each with its defaults).
#[derive(Default)]
pub struct Settings {
    /// GPS and gpsd.
    pub gps: GpsSettings,
    /// The A50.
    pub dvl: A50Settings,
    /// The X150.
    pub seatrac: X150Settings,
    /// The Teensy.
    pub teensy: TeensySettings,
}

/// A device of `kind` from `settings`, drawing from `seed`. The GPS speaks gpsd's JSON when
/// `transport` is TCP, NMEA on a terminal. The Teensy's port comes back beside it.
pub fn device(
    kind: Kind,
    settings: Settings,
    transport: &Transport,
    seed: u64,
) -> (Box<dyn Device>, Option<TeensyPort>) {
    match kind {
        Kind::Gps => match transport {
            Transport::Tcp(_) => (Box::new(Gpsd::new(settings.gps, seed)), None),
            Transport::Pty { .. } => (Box::new(NmeaGps::new(settings.gps, seed)), None),
        },
        Kind::Dvl => (Box::new(A50::new(settings.dvl, seed)), None),
        Kind::Seatrac => (Box::new(X150::new(settings.seatrac, seed)), None),
        Kind::Teensy => {
            let t = Teensy::new(settings.teensy, seed);
            let port = t.port();
            (Box::new(t), Some(port))
        }
    }
}

/// An emulator running in process.
#[derive(Debug)]
pub struct Running {
    /// Its endpoint and stop.
    pub handle: Handle,
    /// Feed it the vehicle's truth (when started with [`spawn`]).
    pub truth: SharedTruth,
    /// The Teensy's commands and actuators (the Teensy only).
    pub teensy: Option<TeensyPort>,
}

/// What else an emulator needs.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// Seeds every draw.
    pub seed: u64,
    /// The faults.
    pub faults: FaultPlan,
    /// Unix time of emulator time 0, s (for the UTC fields).
    pub epoch_unix_s: f64,
}

/// Starts a `kind` emulator on `transport` in the current tokio runtime, measuring the
/// truth fed through [`Running::truth`] (the simulator's).
pub async fn spawn(
    kind: Kind,
    settings: Settings,
    transport: Transport,
    options: Options,
) -> io::Result<Running> {
    let truth = SharedTruth::new();
    let mut r = spawn_with(kind, settings, transport, options, Box::new(truth.clone())).await?;
    r.truth = truth;
    Ok(r)
}

/// Starts a `kind` emulator measuring any truth source (e.g. the built-in
/// [`crate::truth::BoxScenario`]); [`Running::truth`] is then unused.
pub async fn spawn_with(
    kind: Kind,
    settings: Settings,
    transport: Transport,
    options: Options,
    truth: Box<dyn TruthSource>,
) -> io::Result<Running> {
    let (dev, teensy) = device(kind, settings, &transport, options.seed);
    let emu = Emulator::new(
        dev,
        truth,
        options.faults,
        options.seed,
        options.epoch_unix_s,
    );
    let handle = transport::spawn(emu, transport).await?;
    Ok(Running {
        handle,
        truth: SharedTruth::new(),
        teensy,
    })
}

/// Starts a `kind` emulator as [`spawn`] does, on a clock `warp` times faster than the wall
/// clock ([`crate::warp`]): beside a community at `MOOSTimeWarp = warp`, its rates, delays
/// and the truth fed through [`Running::truth`] are in the community's seconds, and so are
/// the fault plan's times ([`crate::warp::faults_to_wall`]). A warp of 1 is [`spawn`].
pub async fn spawn_warped(
    kind: Kind,
    settings: Settings,
    transport: Transport,
    options: Options,
    warp: f64,
) -> io::Result<Running> {
    spawn_warped_with_clock(
        kind,
        settings,
        transport,
        options,
        warp,
        FaultClock::default(),
    )
    .await
}

/// [`spawn_warped`] with the fault plan counted from `clock`'s origin (in the edge's wall
/// seconds, see [`crate::fault::FaultClock`]) instead of the emulator's start: a caller that
/// learns later when the plan's time 0 is (the mission's start) sets it then.
pub async fn spawn_warped_with_clock(
    kind: Kind,
    settings: Settings,
    transport: Transport,
    options: Options,
    warp: f64,
    clock: FaultClock,
) -> io::Result<Running> {
    let truth = SharedTruth::new();
    let (dev, teensy) = device(kind, settings, &transport, options.seed);
    let dev = Box::new(Warped::new(dev, warp, options.epoch_unix_s));
    let emu = Emulator::new(
        dev,
        Box::new(WarpedTruth::new(truth.clone(), warp)),
        faults_to_wall(&options.faults, warp),
        options.seed,
        options.epoch_unix_s,
    )
    .with_fault_clock(clock);
    let handle = transport::spawn(emu, transport).await?;
    Ok(Running {
        handle,
        truth,
        teensy,
    })
}
