//! `coug view [MISSION.moos | LOG.alog] [--host H] [--port DB_PORT] [--http-port P] [--bind ADDR]
//! [--token T] [--speed X]`: the web viewer (issue #17). Given an alog it replays it
//! (`viewer::replay`: time slider, play/pause, speed) and joins no DB. Joins the MOOSDB as the client `coug_view`
//! (registering NODE_REPORT*, VIEW_* and APPCAST, posting APPCAST_REQ every 2 s) and serves
//! the page at `http://ADDR:P/`; everything is in `viewer::server`, this only reads the
//! arguments and the mission's pMarineViewer block (buttons, context pokes, `tiff_file`
//! background) and origin.

use std::net::{IpAddr, Ipv4Addr, SocketAddr};
use std::path::PathBuf;
use std::sync::Arc;

use anyhow::Context;
use clap::Args;
use viewer::server::{JoinConfig, Viewer, ViewerConfig, feed, serve};

use super::db::{ConnectArgs, connect};

/// Arguments of `coug view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// The mission (its ServerHost/ServerPort and pMarineViewer buttons), or a log to replay.
    #[arg(value_name = "MISSION.moos|LOG.alog")]
    pub mission: Option<PathBuf>,
    /// Where the DB is.
    #[command(flatten)]
    pub connect: ConnectArgs,
    /// Port of the web page.
    #[arg(long, default_value_t = 9080)]
    pub http_port: u16,
    /// Address the web server binds; anything but loopback needs --token.
    #[arg(long, default_value_t = IpAddr::V4(Ipv4Addr::LOCALHOST))]
    pub bind: IpAddr,
    /// A token the page must present (`?token=T`); required for a non-loopback --bind.
    #[arg(long)]
    pub token: Option<String>,
    /// Replaying a log: playback speed (times real time).
    #[arg(long, value_name = "X", default_value_t = 1.0)]
    pub speed: f64,
}

/// A replay posts nothing: every press is refused.
struct NoPosts;

impl viewer::server::Outbox for NoPosts {
    fn post(&self, _var: &str, _value: moos_types::Value) -> Result<(), String> {
        Err("a replayed log cannot be poked".into())
    }
    fn moos_time(&self) -> f64 {
        0.0
    }
}

/// `coug view LOG.alog`: the page replaying the log until SIGINT/SIGTERM.
fn replay(args: &ViewArgs, log: &std::path::Path) -> anyhow::Result<()> {
    if !(args.speed.is_finite() && args.speed > 0.0) {
        anyhow::bail!("--speed {}: expected a positive speed-up", args.speed);
    }
    let text =
        std::fs::read_to_string(log).with_context(|| format!("cannot read {}", log.display()))?;
    let parsed = alog::parse(&text).with_context(|| format!("{} is not an alog", log.display()))?;
    let data = Arc::new(viewer::replay::Replay::from_alog(&parsed));
    let config = ViewerConfig {
        bind: SocketAddr::new(args.bind, args.http_port),
        token: args.token.clone(),
        ..ViewerConfig::default()
    };
    config.check()?;
    let rt = tokio::runtime::Runtime::new()?;
    rt.block_on(async {
        let listener = tokio::net::TcpListener::bind(config.bind)
            .await
            .with_context(|| format!("cannot bind {}", config.bind))?;
        let viewer = Viewer::new(&config, Arc::new(NoPosts))?;
        let addr = listener.local_addr()?;
        // Listening for SIGINT/SIGTERM before the address is announced.
        let stop = super::signal::shutdown();
        outln!(
            "coug view: replaying {} ({} records, {:.1} s) at http://{addr}/{}",
            log.display(),
            data.len(),
            data.duration(),
            config
                .token
                .as_ref()
                .map(|t| format!("?token={t}"))
                .unwrap_or_default()
        );
        let server = tokio::spawn(serve(viewer.clone(), listener));
        let driver = tokio::spawn(viewer::replay::drive(
            viewer,
            data,
            false,
            args.speed,
            std::time::Duration::from_millis(100),
        ));
        tokio::select! {
            _ = stop => {}
            r = server => r.context("web server task")?.context("web server")?,
            _ = driver => anyhow::bail!("the replay ended"),
        }
        Ok(())
    })
}

/// Reads the buttons, joins the DB, serves the page until SIGINT/SIGTERM.
pub fn run(args: &ViewArgs) -> anyhow::Result<()> {
    if let Some(p) = &args.mission
        && p.extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("alog"))
    {
        return replay(args, p);
    }
    let from_mission = match &args.mission {
        Some(p) => {
            let text = std::fs::read_to_string(p)
                .with_context(|| format!("cannot read mission file {}", p.display()))?;
            let src = mission::source::SourceMap::from_text(&p.display().to_string(), &text);
            let (config, warning) =
                ViewerConfig::for_mission_file(&mission::moos::parse_moos(&src).value, p);
            if let Some(w) = warning {
                errln!("coug view: warning: {w}");
            }
            config
        }
        None => ViewerConfig::default(),
    };
    let config = ViewerConfig {
        bind: SocketAddr::new(args.bind, args.http_port),
        token: args.token.clone(),
        ..from_mission
    };
    config.check()?;
    let rt = tokio::runtime::Runtime::new()?;
    rt.block_on(async {
        let listener = tokio::net::TcpListener::bind(config.bind)
            .await
            .with_context(|| format!("cannot bind {}", config.bind))?;
        let (client, mail) = connect("coug_view", args.mission.as_deref(), &args.connect).await?;
        let client = Arc::new(client);
        let viewer = Viewer::new(&config, client.clone())?;
        let addr = listener.local_addr()?;
        // Listening for SIGINT/SIGTERM before the address is announced.
        let stop = super::signal::shutdown();
        match &config.token {
            Some(t) => outln!("coug view: http://{addr}/?token={t}"),
            None => outln!("coug view: http://{addr}/"),
        }
        let server = tokio::spawn(serve(viewer.clone(), listener));
        let moos = tokio::spawn(feed(viewer, client, mail, JoinConfig::default()));
        tokio::select! {
            _ = stop => {}
            r = server => r.context("web server task")?.context("web server")?,
            _ = moos => anyhow::bail!("the MOOS client ended"),
        }
        Ok(())
    })
}
