//! `coug nav LOG.alog [-o OUT.csv]`: replays the navigation sensors of a log (DVL_*, AHRS_*,
//! PRESSURE, GPS_*) through the navigator, as pNavGraph runs it (`runtime::navreplay`), writes
//! the trajectory and, when the simulator's truth (SIM_X/SIM_Y) is in the log, prints the
//! errors of the estimate and of dead reckoning and the per-dive reports.

use std::io::Write as _;
use std::path::PathBuf;

use anyhow::{Context, bail};
use clap::Args;
use nav::feed::FeedConfig;
use runtime::navreplay::{Figures, replay, truth, write_csv};

/// Arguments of `coug nav`.
#[derive(Debug, Args)]
pub struct NavArgs {
    /// The alog file to replay.
    pub log: PathBuf,
    /// The trajectory CSV to write.
    #[arg(short = 'o', long = "output", value_name = "OUT.csv")]
    pub output: Option<PathBuf>,
    /// GPS standard deviation per axis at HDOP 1, m (pNavGraph's `gps_noise`).
    #[arg(long, default_value_t = 1.5)]
    pub gps_noise: f64,
    /// Keyframes in the window (pNavGraph's `window_size`).
    #[arg(long, default_value_t = 20)]
    pub window: usize,
}

/// Replays the log, writes the CSV and prints the figures.
pub fn run(args: &NavArgs) -> anyhow::Result<()> {
    if !(args.gps_noise.is_finite() && args.gps_noise > 0.0) {
        bail!("--gps-noise {}: expected a positive number", args.gps_noise);
    }
    if !(2..=1000).contains(&args.window) {
        bail!("--window {}: expected 2..1000", args.window);
    }
    let text = std::fs::read_to_string(&args.log)
        .with_context(|| format!("cannot read {}", args.log.display()))?;
    let log = alog::parse(&text).with_context(|| format!("{}", args.log.display()))?;
    let mut cfg = FeedConfig::default();
    cfg.nav.gps_sigma_m = args.gps_noise;
    cfg.nav.window_size = args.window;
    let nav = replay(&log, cfg);
    if nav.rows.is_empty() {
        bail!(
            "{}: the navigator never initialised (no AHRS_HEADING and GPS fix in the log?)",
            args.log.display()
        );
    }
    outln!("keyframes: {}", nav.rows.len());
    if let Some(path) = &args.output {
        let mut buf = Vec::new();
        write_csv(&nav, &mut buf)?;
        let mut f = std::fs::File::create(path)
            .with_context(|| format!("cannot create {}", path.display()))?;
        f.write_all(&buf)
            .with_context(|| format!("cannot write {}", path.display()))?;
        outln!("trajectory: {}", path.display());
    }
    let truth = truth(&log);
    if truth.is_empty() {
        outln!("no truth (SIM_X/SIM_Y) in the log: no errors to report");
        for (t, d) in &nav.dives {
            outln!(
                "dive {:>2} (fix at {t:>7.1} s): dist {:.1} m  correction {:.2} m ({:.2} %)",
                d.dive,
                d.distance_m,
                d.correction_m,
                d.ratio_pct
            );
        }
    } else {
        out!("{}", Figures::of(&nav, &truth).report());
    }
    Ok(())
}
