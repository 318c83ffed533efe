//! `coug plot LOG.alog -o OUT.svg|OUT.png [--width N] [--title TEXT]`: the vehicle track
//! with the behaviours' waypoints and polygons, and a depth panel when the vehicle dived.

use std::path::PathBuf;

use anyhow::{Context, bail};
use clap::Args;
use runtime::plot::{PlotData, PlotOptions, to_png, to_svg};

/// Arguments of `coug plot`.
#[derive(Debug, Args)]
pub struct PlotArgs {
    /// The alog file to plot.
    pub log: PathBuf,
    /// The image to write: `.svg` or `.png`.
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    pub output: PathBuf,
    /// Image width in pixels.
    #[arg(long, default_value_t = 900)]
    pub width: u32,
    /// Title (default: the mission's name, from the log's `LOG FILE` banner line, else
    /// from the log file's name).
    #[arg(long)]
    pub title: Option<String>,
}

/// Reads the log, draws the plot and writes it.
pub fn run(args: &PlotArgs) -> anyhow::Result<()> {
    let ext = args
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("svg" | "png")) {
        bail!(
            "{}: the output must end in .svg or .png",
            args.output.display()
        );
    }
    if !(200..=8000).contains(&args.width) {
        bail!("--width {}: expected 200..8000 pixels", args.width);
    }
    let text = std::fs::read_to_string(&args.log)
        .with_context(|| format!("cannot read {}", args.log.display()))?;
    let log = alog::parse(&text).with_context(|| format!("{}", args.log.display()))?;
    let data = PlotData::from_alog(&log);
    let opts = PlotOptions {
        width: args.width,
        title: args.title.clone().unwrap_or_else(|| {
            let file = args.log.file_name().unwrap_or_default().to_string_lossy();
            runtime::plot::mission_title(&log, &file)
        }),
    };
    let bytes = if ext.as_deref() == Some("svg") {
        to_svg(&data, &opts)
            .with_context(|| args.log.display().to_string())?
            .into_bytes()
    } else {
        to_png(&data, &opts).with_context(|| args.log.display().to_string())?
    };
    std::fs::write(&args.output, bytes)
        .with_context(|| format!("cannot write {}", args.output.display()))?;
    Ok(())
}
