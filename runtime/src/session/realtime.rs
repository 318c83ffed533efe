//! A run in real time on a TCP MOOSDB, with the ANTLER apps coug does not build in started
//! from PATH.

use std::path::{Path, PathBuf};
use std::process::{Child, Command};
use std::time::{Duration, Instant};

use mission::condition::Condition;
use mission::moos::{AntlerRun, override_globals};
use moosdb::time::Warp;
use moosdb::{Server, ServerConfig};

use crate::antler::MissionGlobals;
use crate::app::Value;
use crate::realtime::{RunSpec, run_apps};
use crate::remote::{RemoteConfig, RemoteError};
use crate::scheduler::Poke;

use super::run::*;
use super::*;
/// The mission as the external apps must read it, or `None` when the original file
/// describes this run: macros expanded, and the run's settings written over the file's, as
/// pAntler does with its `--NAME=VALUE` overloads: the DB's actual `ServerPort`, and the
/// run's `MOOSTimeWarp` when the option changed it.
pub fn mission_for_externals(
    loaded: &LoadedMission,
    globals: &MissionGlobals,
    port: u16,
    warp: f64,
) -> Option<String> {
    let mut overrides: Vec<(&str, String)> = Vec::new();
    if port != globals.server_port {
        overrides.push(("ServerPort", port.to_string()));
    }
    if warp != globals.time_warp {
        overrides.push(("MOOSTimeWarp", moos_types::fmt::g_string(warp, 6)));
    }
    if !loaded.expanded && overrides.is_empty() {
        return None;
    }
    let edits: Vec<(&str, &str)> = overrides.iter().map(|(k, v)| (*k, v.as_str())).collect();
    Some(override_globals(&loaded.text, &edits))
}

/// Writes the externals' mission (see [`mission_for_externals`]) into `log_dir` as
/// `expanded_<name>`, or returns the original path.
pub(super) fn write_mission_for_externals(
    loaded: &LoadedMission,
    globals: &MissionGlobals,
    port: u16,
    warp: f64,
    log_dir: &Path,
) -> Result<PathBuf, SessionError> {
    let Some(text) = mission_for_externals(loaded, globals, port, warp) else {
        return Ok(loaded.path.clone());
    };
    std::fs::create_dir_all(log_dir)
        .map_err(|e| SessionError::LogOpen(format!("cannot create {}: {e}", log_dir.display())))?;
    let name = loaded.path.file_name().map_or_else(
        || "mission.moos".into(),
        |n| n.to_string_lossy().into_owned(),
    );
    let path = log_dir.join(format!("expanded_{name}"));
    std::fs::write(&path, text)
        .map_err(|e| SessionError::LogOpen(format!("cannot write {}: {e}", path.display())))?;
    Ok(path)
}

/// Starts the ANTLER apps coug does not build in, from PATH, as pAntler does.
pub(super) fn start_externals(
    externals: &[AntlerRun],
    mission: &Path,
    observer: &mut dyn Observer,
) -> Vec<Child> {
    let mut children = Vec::new();
    for ext in externals {
        // pAntler's argv: `app mission_file moos_name [extra params]`.
        let mut cmd = Command::new(&ext.app);
        cmd.arg(mission).arg(ext.moos_name()).args(&ext.extra_args);
        cmd.stdin(std::process::Stdio::null())
            .stdout(std::process::Stdio::null());
        match cmd.spawn() {
            Ok(c) => {
                observer.notice(&format!("started {} (pid {})", ext.app, c.id()));
                children.push(c);
            }
            Err(e) => observer.warning(&format!(
                "{}:{}: cannot start {}: {e}; running without it",
                ext.span.file_name(),
                ext.span.line,
                ext.app
            )),
        }
    }
    children
}

/// The children of a real-time run, killed when the run ends however it ends.
pub(super) struct Children(Vec<Child>);

impl Drop for Children {
    fn drop(&mut self) {
        for c in &mut self.0 {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

#[allow(clippy::too_many_arguments)]
pub(super) fn realtime(
    loaded: &LoadedMission,
    opts: &RunOptions,
    (warp, port): (Option<f64>, Option<u16>),
    pokes: Vec<Poke>,
    until: Option<Condition>,
    log_dir: &Path,
    shared: crate::shared::Shared,
    observer: &mut dyn Observer,
) -> Result<RunReport, SessionError> {
    let (globals, _) = MissionGlobals::from_mission(&loaded.mission);
    let warp_f = warp.unwrap_or(globals.time_warp);
    let warp =
        Warp::new(warp_f).map_err(|e| SessionError::Invalid(format!("--warp {warp_f}: {e}")))?;
    let port = port.unwrap_or(globals.server_port);
    let host = if globals.server_host.eq_ignore_ascii_case("localhost") {
        "127.0.0.1".to_string()
    } else {
        globals.server_host.clone()
    };
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .map_err(|e| SessionError::Net(e.to_string()))?;
    let local = tokio::task::LocalSet::new();
    local.block_on(&rt, async {
        let addr: std::net::SocketAddr = format!("{host}:{port}")
            .parse()
            .or_else(|_| {
                use std::net::ToSocketAddrs;
                (host.as_str(), port)
                    .to_socket_addrs()
                    .ok()
                    .and_then(|mut a| a.next())
                    .ok_or(())
            })
            .map_err(|_| SessionError::Net(format!("cannot resolve ServerHost {host}")))?;
        let mut sc = ServerConfig::with_addr(addr);
        sc.warp = warp;
        sc.db.community = globals.community.clone();
        let server = Server::bind(sc)
            .await
            .map_err(|e| SessionError::Net(format!("cannot listen on {addr}: {e}")))?;
        let port = server.local_addr().port();
        let running = crate::realtime::RunningDb { port, warp: warp_f };
        shared.get_or_insert_with(&crate::realtime::RunningDb::key(&globals.community), || {
            running
        });
        observer.db_listening(server.local_addr(), warp_f);
        observer.notice(&format!(
            "MOOSDB_{} listening on {} (warp {warp_f})",
            globals.community,
            server.local_addr()
        ));
        let start = moosdb::time::unix_now() * warp_f;
        let opened = wall_now();
        let (target, sink) = log_target(loaded, log_dir, opened);
        let p = loaded
            .plan_shared(start, opts.seed, Some(target), shared)
            .map_err(|e| SessionError::Invalid(e.to_string()))?;
        let alog = open_log(loaded, log_dir, opened, &sink, super::run::LOG_BUFFER)?;
        let mut children = Children(Vec::new());
        if !p.external.is_empty() {
            let path = write_mission_for_externals(loaded, &globals, port, warp_f, log_dir)?;
            children.0 = start_externals(&p.external, &path, observer);
        }
        let cfg = RemoteConfig {
            host: addr.ip().to_string(),
            port,
            warp: warp_f,
        };
        let spec = RunSpec {
            pokes,
            until,
            max_time: opts.max_time,
        };
        let wall = Instant::now();
        let db = &server;
        db.with_db(|d| d.tap("IVPHELM_SUMMARY"));
        let watch = async {
            let mut tick = tokio::time::interval(Duration::from_millis(50));
            loop {
                tick.tick().await;
                if observer.stop_requested() {
                    return moosdb::time::unix_now() * warp_f;
                }
                let now = moosdb::time::unix_now() * warp_f;
                let current = |k: &str| -> Option<Value> {
                    db.with_db(|d| d.current(k))
                        .and_then(|m| match m.data_type {
                            moosdb::DataType::Double => Some(Value::Double(m.dval)),
                            moosdb::DataType::String => {
                                Some(Value::String(m.sval_str().into_owned().into()))
                            }
                            _ => None,
                        })
                };
                for m in db.with_db(|d| d.take_taps()) {
                    observer.helm_summary(&m.sval_str());
                }
                observer.step(now - start, &current);
            }
        };
        let result = tokio::select! {
            r = run_apps(p.apps, &cfg, spec) => Ok(r),
            t = watch => Err(t),
        };
        let wall_s = wall.elapsed().as_secs_f64();
        drop(children);
        server.shutdown();
        let (ended, until_values) = match result {
            Err(time) => (Ended::Interrupted { time }, Vec::new()),
            // An app's failure (a log that could not be written) fails the run.
            Ok(r) => {
                let end = r.map_err(|e| match e {
                    RemoteError::App(e) => app_failed(e, &alog),
                    e => SessionError::Remote(e),
                })?;
                (Ended::Outcome(end.outcome), end.values)
            }
        };
        let end = Ending(ended, start, wall_s, until_values);
        close_and_report(loaded, opts, &sink, alog, end)
    })
}
