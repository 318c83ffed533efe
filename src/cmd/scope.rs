//! `coug scope [MISSION.moos] [--host H] [--port N] [--once] [--all] [--show=COLS] VAR...`:
//! watch variables like uXMS (see [`runtime::scope`]): names or wildcard patterns (`NAV_*`),
//! times since the DB started, source and community columns; a plain table when stdout is
//! not a terminal.

use std::io::IsTerminal;
use std::time::Duration;

use anyhow::bail;
use clap::Args;
use moosdb::Value;
use runtime::scope::{Columns, Scope, is_pattern};

use super::db::{ConnectArgs, connect, split_mission};

/// Arguments of `coug scope`.
#[derive(Debug, Args)]
pub struct ScopeArgs {
    /// An optional mission file (first argument ending in `.moos`), then variable names or
    /// MOOS wildcard patterns (`NAV_*`).
    #[arg(value_name = "[MISSION.moos] VAR")]
    pub items: Vec<String>,
    /// Print the current values once and exit.
    #[arg(long)]
    pub once: bool,
    /// Every variable, except `*_STATUS`, APPCAST, DB_RWSUMMARY and DB_VARSUMMARY (uXMS `-a`).
    #[arg(short = 'a', long)]
    pub all: bool,
    /// Every variable, those included (uXMS `--alll`).
    #[arg(long)]
    pub alll: bool,
    /// The columns besides name and value: any of `source`, `time`, `community`, comma
    /// separated (default: all three).
    #[arg(long, value_name = "COLS")]
    pub show: Option<String>,
    /// Where the DB is.
    #[command(flatten)]
    pub connect: ConnectArgs,
}

/// Connects, registers and prints until Ctrl-C (or once with `--once`).
pub fn run(args: &ScopeArgs) -> anyhow::Result<()> {
    let (mission, vars) = split_mission(&args.items);
    if vars.is_empty() && !args.all && !args.alll {
        bail!("nothing to scope: give variable names or patterns, or --all");
    }
    let cols = match &args.show {
        None => Columns::default(),
        Some(s) => {
            let has = |c: &str| s.split(',').any(|x| x.trim().eq_ignore_ascii_case(c));
            for x in s.split(',') {
                if !["source", "time", "community"]
                    .contains(&x.trim().to_ascii_lowercase().as_str())
                {
                    bail!("--show {s}: expected source, time or community");
                }
            }
            Columns {
                source: has("source"),
                time: has("time"),
                community: has("community"),
            }
        }
    };
    let mut scope = Scope::new(vars, args.all, args.alll);
    let terminal = std::io::stdout().is_terminal();
    let name = format!("coug_scope_{}", std::process::id());
    let rt = tokio::runtime::Runtime::new()?;
    rt.block_on(async {
        let (client, mut mail) = connect(&name, mission.as_deref(), &args.connect).await?;
        let start = client.moos_time();
        // The DB's uptime dates its start (times are shown since then).
        client.register("DB_UPTIME", 0.0);
        if args.all || args.alll {
            client.register_pattern("*", "*", 0.0);
        }
        for v in vars {
            if is_pattern(v) {
                client.register_pattern(v, "*", 0.0);
            } else {
                client.register(v, 0.0);
            }
        }
        let status_var = format!("{}_STATUS", name.to_ascii_uppercase());
        let mut refresh = tokio::time::interval(Duration::from_secs(1));
        let mut status = tokio::time::interval(Duration::from_secs(2));
        // With --once: print when every named variable has a value and the DB's start is
        // known, or after 2 s once that start is known (patterns and --all wait the 2 s), at
        // the latest after --timeout.
        let deadline = tokio::time::sleep(Duration::from_secs(2));
        tokio::pin!(deadline);
        let give_up = tokio::time::sleep(Duration::from_secs_f64(args.connect.timeout.max(2.0)));
        tokio::pin!(give_up);
        let mut waited = false;
        let waits = args.all || args.alll || vars.iter().any(|v| is_pattern(v));
        let mut first = true;
        loop {
            tokio::select! {
                m = mail.recv() => {
                    let Some(m) = m else { break };
                    scope.on_message(&m, client.moos_time());
                    if args.once
                        && ((!waits && scope.complete()) || (waited && scope.db_started()))
                    {
                        break;
                    }
                }
                _ = refresh.tick(), if !args.once => {
                    if terminal {
                        out!("\x1b[2J\x1b[H{}", scope.render(cols));
                    } else {
                        if !first {
                            outln!();
                        }
                        out!("{}", scope.render(cols));
                    }
                    first = false;
                }
                _ = status.tick() => {
                    // Like every MOOS app: keeps the DB's pushes flowing to idle clients.
                    let uptime = client.moos_time() - start;
                    let s = format!("AppErrorFlag=false,Uptime={uptime:.2},MOOSName={name}");
                    let _ = client.notify(&status_var, Value::String(s.into()));
                }
                _ = &mut deadline, if args.once && !waited => {
                    waited = true;
                    if scope.db_started() {
                        break;
                    }
                }
                _ = &mut give_up, if args.once => break,
                _ = super::signal::shutdown() => break,
            }
        }
        if args.once {
            out!("{}", scope.render(cols));
        }
        client.close().await;
        Ok(())
    })
}
