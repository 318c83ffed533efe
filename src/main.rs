//! `coug`: one binary that runs MOOS-IvP missions with a native Rust helm, MOOSDB and vehicle.

use clap::{Parser, Subcommand};

/// Command line of the `coug` binary.
#[derive(Debug, Parser)]
#[command(name = "coug", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

/// The subcommands. Later issues add `check`, `nsplug`, `db`, `poke`, `scope`, `run`, `plot`.
#[derive(Debug, Subcommand)]
enum Command {
    /// Print the version and what each part of coug does today.
    Info,
}

fn main() -> anyhow::Result<()> {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .with_writer(std::io::stderr)
        .init();
    let cli = Cli::parse();
    match cli.command.unwrap_or(Command::Info) {
        Command::Info => {
            println!("coug {}", env!("CARGO_PKG_VERSION"));
            println!("`coug run MISSION.moos` arrives with issue #8; today coug provides the IvP core (helm::ivp).");
        }
    }
    Ok(())
}
