//! `coug base [MISSION.moos] [--host H] [--port N]`: the fleet's base station (issue #16,
//! point 6) in the terminal. Joins the base community's MOOSDB (the mission's
//! ServerHost/ServerPort, or the flags) as `coug_base`; everything else is the `base` crate.

use std::path::PathBuf;

use clap::Args;

use super::db::{ConnectArgs, connect};

/// Arguments of `coug base`.
#[derive(Debug, Args)]
pub struct BaseArgs {
    /// The base (shoreside) community's mission: its ServerHost and ServerPort.
    #[arg(value_name = "MISSION.moos")]
    pub mission: Option<PathBuf>,
    /// Where the DB is.
    #[command(flatten)]
    pub connect: ConnectArgs,
}

/// Joins the DB and runs the terminal console until the operator quits.
pub fn run(args: &BaseArgs) -> anyhow::Result<()> {
    let rt = tokio::runtime::Runtime::new()?;
    let (client, mut mail) =
        rt.block_on(connect("coug_base", args.mission.as_deref(), &args.connect))?;
    // SIGINT or SIGTERM ends the console as `q` does, so the terminal is given back.
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let flag = stop.clone();
    rt.spawn(async move {
        super::signal::shutdown().await;
        flag.store(true, std::sync::atomic::Ordering::Relaxed);
    });
    let sent = base::terminal::run(&client, &mut mail, &stop)?;
    outln!("coug base: {sent} commands sent");
    rt.block_on(client.close());
    Ok(())
}
