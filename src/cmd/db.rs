//! `coug db [MISSION.moos] [--port N] [--host ADDR] [--community NAME]`: a standalone MOOSDB.
//!
//! Also holds what `coug poke` and `coug scope` share: a mission's `ServerHost` /
//! `ServerPort` / `Community` / `MOOSTimeWarp` (read with `mission::moos`) and the connect helper.

use std::net::{IpAddr, Ipv4Addr, SocketAddr, ToSocketAddrs};
use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use clap::Args;
use std::time::Duration;

use moosdb::time::Warp;
use moosdb::{Client, ClientConfig, MailStream, Server, ServerConfig};

/// Arguments of `coug db`.
#[derive(Debug, Args)]
pub struct DbArgs {
    /// Mission file: `ServerPort`, `ServerHost`, `Community`, `MOOSTimeWarp`, `ClientTimeout`.
    #[arg(value_name = "MISSION.moos")]
    pub mission: Option<PathBuf>,
    /// Port to listen on (default: the mission's ServerPort, else 9000).
    #[arg(long)]
    pub port: Option<u16>,
    /// Address to listen on (default: the mission's ServerHost, else 127.0.0.1).
    #[arg(long)]
    pub host: Option<String>,
    /// Community name (default: the mission's Community, else `#1`).
    #[arg(long)]
    pub community: Option<String>,
}

/// The global settings of a `.moos` file that the comms need.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct MissionComms {
    /// `ServerHost`.
    pub host: Option<String>,
    /// `ServerPort`.
    pub port: Option<u16>,
    /// `Community`.
    pub community: Option<String>,
    /// `MOOSTimeWarp`.
    pub warp: Option<f64>,
    /// `ClientTimeout` (seconds).
    pub client_timeout: Option<f64>,
}

/// Reads the comms settings from a `.moos` text's top-level parameters (keys
/// case-insensitive, first occurrence wins), with `mission::moos`.
pub fn parse_mission_comms(text: &str) -> anyhow::Result<MissionComms> {
    let src = mission::source::SourceMap::from_text("mission", text);
    let parsed = mission::moos::parse_moos(&src);
    let m = &parsed.value;
    if !mission::is_mission(m) {
        anyhow::bail!(
            "not a MOOS mission file (no ServerHost, ServerPort, Community or ProcessConfig)"
        );
    }
    let text_of = |key: &str| m.global(key).map(str::to_string);
    fn number<T: std::str::FromStr>(
        m: &mission::moos::MissionFile,
        key: &str,
    ) -> anyhow::Result<Option<T>>
    where
        T::Err: std::error::Error + Send + Sync + 'static,
    {
        m.global(key)
            .map(|v| {
                v.trim()
                    .parse::<T>()
                    .with_context(|| format!("{key} `{v}` is not valid"))
            })
            .transpose()
    }
    Ok(MissionComms {
        host: text_of("ServerHost"),
        port: number(m, "ServerPort")?,
        community: text_of("Community"),
        warp: number(m, "MOOSTimeWarp")?,
        client_timeout: number(m, "ClientTimeout")?,
    })
}

/// [`parse_mission_comms`] of a file.
pub fn read_mission_comms(path: &Path) -> anyhow::Result<MissionComms> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read mission file {}", path.display()))?;
    parse_mission_comms(&text).with_context(|| format!("in {}", path.display()))
}

/// Resolves a MOOS host name (`localhost` in any case means 127.0.0.1).
pub fn resolve_host(host: &str, port: u16) -> anyhow::Result<SocketAddr> {
    if host.eq_ignore_ascii_case("localhost") {
        return Ok(SocketAddr::new(IpAddr::V4(Ipv4Addr::LOCALHOST), port));
    }
    if let Ok(ip) = host.parse::<IpAddr>() {
        return Ok(SocketAddr::new(ip, port));
    }
    (host, port)
        .to_socket_addrs()
        .with_context(|| format!("cannot resolve host {host}"))?
        .next()
        .with_context(|| format!("host {host} has no address"))
}

/// Warp from the mission (1 when absent); rejects values MOOS rejects.
pub fn warp_of(m: &MissionComms) -> anyhow::Result<Warp> {
    Ok(Warp::new(m.warp.unwrap_or(1.0))?)
}

/// How `coug poke` and `coug scope` reach the DB.
#[derive(Debug, Clone, Args)]
pub struct ConnectArgs {
    /// DB host (default: mission ServerHost, else localhost). Also `--server_host`,
    /// `--moos_host` (uXMS's names).
    #[arg(
        long,
        visible_alias = "server_host",
        alias = "serverhost",
        alias = "moos_host",
        alias = "mooshost"
    )]
    pub host: Option<String>,
    /// DB port (default: mission ServerPort, else 9000). Also `--server_port`, `--moos_port`.
    #[arg(
        long,
        visible_alias = "server_port",
        alias = "serverport",
        alias = "moos_port",
        alias = "moosport"
    )]
    pub port: Option<u16>,
    /// Seconds to wait for the DB before giving up.
    #[arg(long, default_value_t = 10.0)]
    pub timeout: f64,
}

/// Splits an optional leading mission file (ending in `.moos` or `.moos++`) from the rest.
pub fn split_mission(items: &[String]) -> (Option<PathBuf>, &[String]) {
    match items.first() {
        Some(f) if f.ends_with(".moos") || f.ends_with(".moos++") => {
            (Some(PathBuf::from(f)), &items[1..])
        }
        _ => (None, items),
    }
}

/// Starts a client called `name` per the command line and mission, and waits (bounded by
/// `--timeout`) until the DB welcomes it.
pub async fn connect(
    name: &str,
    mission: Option<&Path>,
    args: &ConnectArgs,
) -> anyhow::Result<(Client, MailStream)> {
    let m = match mission {
        Some(p) => read_mission_comms(p)?,
        None => MissionComms::default(),
    };
    let host = args
        .host
        .clone()
        .or(m.host.clone())
        .unwrap_or_else(|| "localhost".into());
    let port = args.port.or(m.port).unwrap_or(moosdb::server::DEFAULT_PORT);
    let mut cfg = ClientConfig::new(name, &host, port);
    cfg.warp = warp_of(&m)?;
    let (client, mail) = Client::start(cfg);
    tokio::time::timeout(
        Duration::from_secs_f64(args.timeout.max(0.0)),
        client.wait_connected(),
    )
    .await
    .with_context(|| format!("no MOOSDB at {host}:{port} within {} s", args.timeout))??;
    Ok((client, mail))
}

/// Runs the DB until Ctrl-C.
pub fn run(args: &DbArgs) -> anyhow::Result<()> {
    let m = match &args.mission {
        Some(p) => read_mission_comms(p)?,
        None => MissionComms::default(),
    };
    let port = args.port.or(m.port).unwrap_or(moosdb::server::DEFAULT_PORT);
    let host = args
        .host
        .clone()
        .or(m.host.clone())
        .unwrap_or_else(|| "127.0.0.1".to_string());
    let mut cfg = ServerConfig::with_addr(resolve_host(&host, port)?);
    cfg.warp = warp_of(&m)?;
    if let Some(c) = args.community.clone().or(m.community.clone()) {
        cfg.db.community = c;
    }
    if let Some(t) = m.client_timeout {
        if t.is_nan() || t <= 0.0 {
            bail!("ClientTimeout must be positive, got {t}");
        }
        cfg.db.client_timeout = t;
    }
    let rt = tokio::runtime::Runtime::new()?;
    rt.block_on(async {
        let community = cfg.db.community.clone();
        let server = Server::bind(cfg)
            .await
            .with_context(|| format!("cannot listen on {host}:{port}"))?;
        let stop = super::signal::shutdown();
        outln!(
            "coug db: MOOSDB_{community} listening on {} (Ctrl-C to stop)",
            server.local_addr()
        );
        stop.await;
        server.shutdown();
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_globals_and_skips_process_config_blocks() {
        let text = "// a comment\nServerHost = 10.0.0.2 // inline\nserverport=9101\n\
                    Community    = alpha\nMOOSTimeWarp = 10\n\
                    ProcessConfig = pX\n{\n  ServerPort = 1\n  Community = nope\n}\n";
        let m = parse_mission_comms(text).unwrap();
        assert_eq!(m.host.as_deref(), Some("10.0.0.2"));
        assert_eq!(m.port, Some(9101));
        assert_eq!(m.community.as_deref(), Some("alpha"));
        assert_eq!(m.warp, Some(10.0));
        assert!(parse_mission_comms("ServerPort = many").is_err());
    }

    #[test]
    fn localhost_resolves_to_loopback() {
        assert_eq!(
            resolve_host("LOCALHOST", 9000).unwrap(),
            "127.0.0.1:9000".parse().unwrap()
        );
        assert_eq!(
            resolve_host("10.1.2.3", 1).unwrap(),
            "10.1.2.3:1".parse().unwrap()
        );
    }

    #[test]
    fn reads_the_corpus_alpha_mission() {
        let p = test_support::mission_file("s1_alpha/alpha.moos");
        let m = read_mission_comms(&p).unwrap();
        assert_eq!(m.port, Some(9000));
        assert_eq!(m.community.as_deref(), Some("alpha"));
    }
}
