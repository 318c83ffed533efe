//! `coug scope [MISSION.moos] [--host H] [--port N] [--once] VAR...`: watch variables like
//! uXMS: the latest value, source and time of each, refreshed every second.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::time::Duration;

use anyhow::bail;
use clap::Args;
use moosdb_client::{DataType, Message, Value};

use super::db::{ConnectArgs, connect, split_mission};

/// Arguments of `coug scope`.
#[derive(Debug, Args)]
pub struct ScopeArgs {
    /// An optional mission file (first argument ending in `.moos`), then variable names.
    #[arg(required = true, value_name = "[MISSION.moos] VAR")]
    pub items: Vec<String>,
    /// Print the current values once and exit.
    #[arg(long)]
    pub once: bool,
    /// Where the DB is.
    #[command(flatten)]
    pub connect: ConnectArgs,
}

fn value_text(m: &Message) -> String {
    match m.data_type {
        DataType::Double => moosdb_client::db::fmt_g6(m.dval),
        DataType::String => format!("\"{}\"", m.sval_str()),
        DataType::Binary => format!("<binary {} bytes>", m.sval.len()),
        DataType::NotSet => "n/a".into(),
    }
}

/// The table for `vars` (in the given order); times relative to `start` (MOOS time).
pub fn render(vars: &[String], latest: &HashMap<String, Message>, start: f64) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<24} {:<20} {:>10}  VarValue",
        "VarName", "(S)ource", "Time"
    );
    let _ = writeln!(
        out,
        "{:<24} {:<20} {:>10}  --------",
        "-------", "--------", "----"
    );
    for v in vars {
        match latest.get(v) {
            Some(m) => {
                let _ = writeln!(
                    out,
                    "{:<24} {:<20} {:>10.2}  {}",
                    v,
                    m.src_str(),
                    m.time - start,
                    value_text(m)
                );
            }
            None => {
                let _ = writeln!(out, "{v:<24} {:<20} {:>10}  n/a", "n/a", "n/a");
            }
        }
    }
    out
}

/// Connects, registers and prints until Ctrl-C (or once with `--once`).
pub fn run(args: &ScopeArgs) -> anyhow::Result<()> {
    let (mission, vars) = split_mission(&args.items);
    if vars.is_empty() {
        bail!("nothing to scope: give variable names");
    }
    let name = format!("coug_scope_{}", std::process::id());
    let rt = tokio::runtime::Runtime::new()?;
    rt.block_on(async {
        let (client, mut mail) = connect(&name, mission.as_deref(), &args.connect).await?;
        let start = client.moos_time();
        for v in vars {
            client.register(v, 0.0);
        }
        let status_var = format!("{}_STATUS", name.to_ascii_uppercase());
        let mut latest: HashMap<String, Message> = HashMap::new();
        let mut refresh = tokio::time::interval(Duration::from_secs(1));
        let mut status = tokio::time::interval(Duration::from_secs(2));
        // With --once: print when every variable has a value, or after 2 s.
        let deadline = tokio::time::sleep(Duration::from_secs(2));
        tokio::pin!(deadline);
        loop {
            tokio::select! {
                m = mail.recv() => {
                    let Some(m) = m else { break };
                    latest.insert(m.key_str().into_owned(), m);
                    if args.once && vars.iter().all(|v| latest.contains_key(v)) {
                        break;
                    }
                }
                _ = refresh.tick(), if !args.once => {
                    out!("\x1b[2J\x1b[H{}", render(vars, &latest, start));
                }
                _ = status.tick() => {
                    // Like every MOOS app: keeps the DB's pushes flowing to idle clients.
                    let uptime = client.moos_time() - start;
                    let s = format!("AppErrorFlag=false,Uptime={uptime:.2},MOOSName={name}");
                    let _ = client.notify(&status_var, Value::string(&s));
                }
                _ = &mut deadline, if args.once => break,
                _ = super::signal::shutdown() => break,
            }
        }
        out!("{}", render(vars, &latest, start));
        client.close().await;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_shows_value_source_and_relative_time() {
        let mut latest = HashMap::new();
        let mut m = Message::notify("FOO", Value::Double(1.5), 105.25);
        m.src = "uPokeDB".into();
        latest.insert("FOO".to_string(), m);
        let mut s = Message::notify("BAR", Value::string("hi there"), 101.0);
        s.src = "pHelmIvP".into();
        latest.insert("BAR".to_string(), s);
        let t = render(&["FOO".into(), "BAR".into(), "BAZ".into()], &latest, 100.0);
        let lines: Vec<&str> = t.lines().collect();
        assert_eq!(lines.len(), 5);
        assert!(lines[2].starts_with("FOO "));
        assert!(
            lines[2].contains("uPokeDB") && lines[2].contains("5.25") && lines[2].ends_with("1.5")
        );
        assert!(lines[3].contains("pHelmIvP") && lines[3].ends_with("\"hi there\""));
        assert!(lines[4].starts_with("BAZ") && lines[4].ends_with("n/a"));
    }
}
