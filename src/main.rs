//! `coug`: one binary that runs MOOS-IvP missions with a native Rust helm, MOOSDB and vehicle.

use clap::{Parser, Subcommand};

mod cmd {
    pub mod check;
    pub mod db;
    pub mod nsplug;
    pub mod plot;
    pub mod poke;
    pub mod run;
    pub mod scope;
}

/// Command line of the `coug` binary.
#[derive(Debug, Parser)]
#[command(name = "coug", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
enum Command {
    /// Print the version and what each part of coug does today.
    Info,
    /// Preprocess, parse and validate mission files (.moos, .bhv); exit 1 on any error.
    Check(cmd::check::CheckArgs),
    /// Expand an nsplug template (MOOS-IvP's nsplug): IN OUT [NAME=VALUE]...
    Nsplug(cmd::nsplug::NsplugArgs),
    /// Plot an alog: LOG.alog -o OUT.svg|OUT.png (track, waypoints, polygons, depth).
    Plot(cmd::plot::PlotArgs),
    /// Run a standalone MOOSDB: [MISSION.moos] [--port N] [--host ADDR].
    Db(cmd::db::DbArgs),
    /// Post values like uPokeDB: [MISSION.moos] VAR=VALUE... (VAR:=VALUE forces a string).
    Poke(cmd::poke::PokeArgs),
    /// Watch variables like uXMS: [MISSION.moos] VAR... [--once].
    Scope(cmd::scope::ScopeArgs),
    /// Run a whole mission: MISSION.moos [NAME=VALUE]... [--lockstep | --warp N] [--deploy] [--until COND].
    Run(cmd::run::RunArgs),
}

fn main() -> anyhow::Result<()> {
    let cli = Cli::parse();
    // `coug run` prints its own progress; the DB's per-client log lines would drown it.
    let level = match cli.command {
        Some(Command::Run(_)) => "warn",
        _ => "info",
    };
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new(level)),
        )
        .with_writer(std::io::stderr)
        .init();
    match cli.command.unwrap_or(Command::Info) {
        Command::Check(args) => std::process::exit(cmd::check::run(&args)),
        Command::Nsplug(args) => std::process::exit(cmd::nsplug::run(&args)),
        Command::Plot(args) => cmd::plot::run(&args)?,
        Command::Db(args) => cmd::db::run(&args)?,
        Command::Poke(args) => cmd::poke::run(&args)?,
        Command::Scope(args) => cmd::scope::run(&args)?,
        Command::Run(args) => std::process::exit(cmd::run::run(&args)),
        Command::Info => {
            println!("coug {}", env!("CARGO_PKG_VERSION"));
            println!(
                "Commands: run, check, nsplug, plot, db, poke, scope (`coug help` for details)."
            );
        }
    }
    Ok(())
}
