//! `coug emulate gps|dvl|seatrac|teensy [--tcp PORT | --pty [--link PATH]] [--seed N]
//! [--fault SPEC]...`: one device emulator (issue #15) serving its wire protocol until
//! SIGINT/SIGTERM, measuring the built-in box scenario. Everything is in the `emulate`
//! crate; this reads the arguments and prints the endpoint (and every new one after a
//! disconnection fault).

use std::path::PathBuf;

use anyhow::{Context, bail};
use clap::Args;
use emulate::build::{self, Kind, Options, Settings};
use emulate::fault::FaultPlan;
use emulate::transport::Transport;
use emulate::truth::BoxScenario;

/// Arguments of `coug emulate`.
#[derive(Debug, Args)]
pub struct EmulateArgs {
    /// The device: gps, dvl, seatrac or teensy.
    #[arg(value_name = "DEVICE")]
    pub device: String,
    /// Serve on TCP at 127.0.0.1:PORT (0: any free port). The DVL's default; the GPS then
    /// speaks gpsd's JSON.
    #[arg(long, value_name = "PORT", conflicts_with_all = ["pty", "link"])]
    pub tcp: Option<u16>,
    /// Serve on a pseudo-terminal (the default of gps, seatrac and teensy; the GPS then
    /// writes NMEA).
    #[arg(long)]
    pub pty: bool,
    /// With a pseudo-terminal: a symbolic link to its slave, for the driver to open.
    #[arg(long, value_name = "PATH")]
    pub link: Option<PathBuf>,
    /// Seeds every random draw (sensor noise, faults).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// A fault, repeatable: noise@T+D[:K], dropout@T+D, disconnect@T[+D],
    /// garbage@T+D[:BYTES_PER_S], leak@T, battery@T:VOLTS_PER_S (times in seconds from start).
    #[arg(long = "fault", value_name = "SPEC")]
    pub faults: Vec<String>,
    /// Side of the scenario's square, m.
    #[arg(long, default_value_t = 100.0)]
    pub side: f64,
    /// Speed of the scenario's vehicle, m/s.
    #[arg(long, default_value_t = 1.5)]
    pub speed: f64,
    /// Depth of the submerged sides, m.
    #[arg(long, default_value_t = 5.0)]
    pub depth: f64,
    /// Depth of the (flat) bottom the DVL sees, m.
    #[arg(long, default_value_t = 30.0)]
    pub water_depth: f64,
    /// The GPS's local origin, degrees: LAT,LON.
    #[arg(long, value_name = "LAT,LON", default_value = "40.3394,-111.90721")]
    pub origin: String,
    /// SeaTrac: chance that a send is refused with XCVR_BUSY although the channel is free.
    #[arg(long, default_value_t = 0.0)]
    pub busy_prob: f64,
    /// SeaTrac: magnetic declination, degrees east (the yaw written is true less it).
    #[arg(long, default_value_t = 0.0)]
    pub declination: f64,
    /// SeaTrac: the frame of its accelerometer, magnetometer and gyro: cougars or body.
    #[arg(long, default_value = "cougars")]
    pub mount: String,
}

/// Runs the emulator until SIGINT/SIGTERM.
pub fn run(args: &EmulateArgs) -> anyhow::Result<()> {
    let kind: Kind = args.device.parse().map_err(anyhow::Error::msg)?;
    let faults = FaultPlan::parse(&args.faults)?;
    if !(args.side > 0.0 && args.speed > 0.0 && args.depth >= 0.0 && args.water_depth > 0.0) {
        bail!("--side, --speed and --water-depth must be positive, --depth not negative");
    }
    let transport = match (args.tcp, args.pty || args.link.is_some()) {
        (Some(port), _) => Transport::loopback(port),
        (None, true) => Transport::Pty {
            link: args.link.clone(),
        },
        (None, false) => kind.default_transport(),
    };
    let mut settings = Settings::default();
    settings.dvl.water_depth_m = args.water_depth;
    let origin = args
        .origin
        .split_once(',')
        .and_then(|(a, o)| Some((a.trim().parse::<f64>().ok()?, o.trim().parse::<f64>().ok()?)))
        .filter(|(a, o)| vehicle::geodesy::LocalGrid::new(*a, *o).is_ok())
        .with_context(|| format!("bad --origin {:?} (LAT,LON in degrees)", args.origin))?;
    settings.gps.origin_lat_lon = origin;
    if !(0.0..=1.0).contains(&args.busy_prob) {
        bail!("--busy-prob must be a probability in [0, 1]");
    }
    settings.seatrac.busy_prob = args.busy_prob;
    settings.seatrac.declination_deg = args.declination;
    settings.seatrac.mount = match args.mount.as_str() {
        "cougars" => emulate::seatrac::Mount::Cougars,
        "body" => emulate::seatrac::Mount::Body,
        other => bail!("bad --mount {other:?} (cougars or body)"),
    };
    let epoch_unix_s = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_secs_f64())
        .unwrap_or(0.0);
    let options = Options {
        seed: args.seed,
        faults,
        epoch_unix_s,
    };
    let scenario = BoxScenario::new(args.side, args.speed, args.depth);
    let rt = tokio::runtime::Runtime::new()?;
    rt.block_on(async {
        let run = build::spawn_with(kind, settings, transport, options, Box::new(scenario))
            .await
            .with_context(|| format!("cannot start the {} emulator", kind.name()))?;
        // Listening for SIGINT/SIGTERM before the endpoint is announced.
        let stop = super::signal::shutdown();
        outln!("coug emulate {}: {}", kind.name(), run.handle.endpoint());
        let mut endpoints = run.handle.endpoints();
        let announce = async {
            while endpoints.changed().await.is_ok() {
                let e = endpoints.borrow_and_update().clone();
                outln!("coug emulate {}: {}", kind.name(), e);
            }
        };
        tokio::select! {
            _ = stop => {}
            _ = announce => {}
        }
        let stats = run.handle.stop().await?;
        outln!(
            "coug emulate {}: {} connection(s), {} disconnection(s), {} bytes out, {} in, {} dropped, {} flushed unread",
            kind.name(),
            stats.connections,
            stats.disconnects,
            stats.bytes_out,
            stats.bytes_in,
            stats.dropped,
            stats.flushed
        );
        Ok(())
    })
}
