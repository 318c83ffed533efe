//! `coug`: one binary that runs MOOS-IvP missions with a native Rust helm, MOOSDB and vehicle.

// Doc comments here are clap help texts, where `[ALIAS]` is usage notation, not a link.
#![allow(rustdoc::broken_intra_doc_links)]
// Output goes through `out.rs`, which ends quietly on a closed pipe instead of panicking.
#![deny(clippy::print_stdout, clippy::print_stderr)]

use clap::{Parser, Subcommand};

#[macro_use]
mod out;

mod cmd {
    pub mod app;
    pub mod check;
    pub mod db;
    pub mod nsplug;
    pub mod plot;
    pub mod poke;
    pub mod run;
    pub mod scope;
    pub mod signal;
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
    /// pHelmIvP as its own MOOS process: MISSION.moos [ALIAS] [--alias=NAME].
    Helm(cmd::app::AppCommandArgs),
    /// uSimMarineV22 (or the mission's uSimMarine) as its own MOOS process: MISSION.moos [ALIAS].
    Sim(cmd::app::AppCommandArgs),
    /// pMarinePIDV22 (or the mission's pMarinePID) as its own MOOS process: MISSION.moos [ALIAS].
    Pid(cmd::app::AppCommandArgs),
    /// pNodeReporter as its own MOOS process: MISSION.moos [ALIAS].
    Nodereporter(cmd::app::AppCommandArgs),
    /// Create links named MOOSDB, pHelmIvP, uSimMarine(V22), pMarinePID(V22), pNodeReporter in DIR
    /// so pAntler starts coug in place of the C++ apps.
    InstallAliases(cmd::app::InstallAliasesArgs),
}

fn init_tracing(level: &str) {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new(level)),
        )
        .with_writer(std::io::stderr)
        .init();
}

fn main() -> anyhow::Result<()> {
    // Invoked under a MOOS app's name (a link from `coug install-aliases`): be that app.
    let argv: Vec<String> = std::env::args().collect();
    if let Some(app) = argv.first().and_then(|a| cmd::app::app_from_argv0(a)) {
        init_tracing("info");
        std::process::exit(cmd::app::run_app(app, &argv[1..]));
    }
    let cli = Cli::parse();
    // `coug run` prints its own progress; the DB's per-client log lines would drown it.
    let level = match cli.command {
        Some(Command::Run(_)) => "warn",
        _ => "info",
    };
    init_tracing(level);
    match cli.command.unwrap_or(Command::Info) {
        Command::Check(args) => std::process::exit(cmd::check::run(&args)),
        Command::Nsplug(args) => std::process::exit(cmd::nsplug::run(&args)),
        Command::Plot(args) => cmd::plot::run(&args)?,
        Command::Db(args) => cmd::db::run(&args)?,
        Command::Poke(args) => cmd::poke::run(&args)?,
        Command::Scope(args) => cmd::scope::run(&args)?,
        Command::Run(args) => std::process::exit(cmd::run::run(&args)),
        Command::Helm(args) => std::process::exit(cmd::app::run_subcommand("helm", &args)),
        Command::Sim(args) => std::process::exit(cmd::app::run_subcommand("sim", &args)),
        Command::Pid(args) => std::process::exit(cmd::app::run_subcommand("pid", &args)),
        Command::Nodereporter(args) => {
            std::process::exit(cmd::app::run_subcommand("nodereporter", &args))
        }
        Command::InstallAliases(args) => cmd::app::install_aliases(&args)?,
        Command::Info => {
            outln!("coug {}", env!("CARGO_PKG_VERSION"));
            outln!(
                "Commands: run, check, nsplug, plot, db, poke, scope, helm, sim, pid, nodereporter, install-aliases (`coug help` for details)."
            );
        }
    }
    Ok(())
}
