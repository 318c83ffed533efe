//! `coug appcast [MISSION.moos] [--host H] [--port N] [--node N [--app A]] [--once]`: the
//! appcasts of a MOOS community in the terminal, like uMAC. Joins the DB, registers
//! `APPCAST`, posts `APPCAST_REQ` (and `APPCAST_REQ_<NODE>`) every 2 s and prints, refreshed
//! every second, the node table, one node's apps, or one app's report
//! ([`appcast::monitor::Monitor`] does all but the I/O).

use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Duration;

use appcast::monitor::Monitor;
use clap::Args;
use moosdb::Value;

use super::db::{ConnectArgs, connect};

/// Arguments of `coug appcast`.
#[derive(Debug, Args)]
pub struct AppcastArgs {
    /// The mission (its ServerHost/ServerPort).
    #[arg(value_name = "MISSION.moos")]
    pub mission: Option<PathBuf>,
    /// Show this node's apps (with --app: that app's report).
    #[arg(long)]
    pub node: Option<String>,
    /// With --node: show this app's report.
    #[arg(long, requires = "node")]
    pub app: Option<String>,
    /// Print once, after the first round of answers (3 s, or --timeout), and exit.
    #[arg(long)]
    pub once: bool,
    /// Where the DB is.
    #[command(flatten)]
    pub connect: ConnectArgs,
}

/// Connects and prints until Ctrl-C (or once with `--once`).
pub fn run(args: &AppcastArgs) -> anyhow::Result<()> {
    let name = format!("coug_appcast_{}", std::process::id());
    let mut monitor = Monitor::new(&name);
    let terminal = std::io::stdout().is_terminal();
    let rt = tokio::runtime::Runtime::new()?;
    rt.block_on(async {
        let (client, mut mail) = connect(&name, args.mission.as_deref(), &args.connect).await?;
        client.register(appcast::casting::APPCAST_VAR, 0.0);
        let mut request = tokio::time::interval(Duration::from_secs(2));
        let mut refresh = tokio::time::interval(Duration::from_secs(1));
        let done = tokio::time::sleep(Duration::from_secs(3));
        tokio::pin!(done);
        let page = |m: &Monitor, now: f64| m.page(args.node.as_deref(), args.app.as_deref(), now);
        loop {
            tokio::select! {
                m = mail.recv() => {
                    let Some(m) = m else { break };
                    if m.key_str() == appcast::casting::APPCAST_VAR && !m.is_double() {
                        monitor.on_appcast(&m.sval_str(), client.moos_time());
                    }
                }
                _ = request.tick() => {
                    for (var, value) in monitor.requests() {
                        let _ = client.notify(&var, Value::String(value.into()));
                    }
                }
                _ = refresh.tick(), if !args.once => {
                    let text = page(&monitor, client.moos_time());
                    if terminal {
                        out!("\x1b[2J\x1b[H{text}");
                    } else {
                        outln!("{text}");
                    }
                }
                _ = &mut done, if args.once => break,
                _ = super::signal::shutdown() => break,
            }
        }
        if args.once {
            out!("{}", page(&monitor, client.moos_time()));
        }
        client.close().await;
        Ok(())
    })
}
