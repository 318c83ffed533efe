//! The swap-in contract of pHelmIvP on a bad configuration: started through the
//! `pHelmIvP` link (as pAntler starts it) with a behaviour file the C++ helm rejects, coug
//! stays connected to the MOOSDB, posts `IVPHELM_STATE = MALCONFIG` every iteration, says
//! why on stderr, never posts a non-zero `DESIRED_*`, and ends promptly on SIGINT and on
//! SIGTERM (pAntler's teardown). Loopback only, OS-picked DB port, bounded waits.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::Duration;

use common::*;
use moosdb::{Client, ClientConfig, Server, ServerConfig};

/// Kills a child left running when the test ends, pass or fail.
struct Proc(Child);

impl Drop for Proc {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// A behaviour file that would drive at once (deployed, no manual override) were it not
/// for one bad value: `capture_radius` must be a number (BHV_Waypoint rejects it).
const BAD_BHV: &str = "\
initialize DEPLOY = true
initialize MOOS_MANUAL_OVERRIDE = false

Behavior = BHV_Waypoint
{
  name           = wpt
  condition      = DEPLOY = true
  speed          = 2
  capture_radius = wide
  points         = 60,-40 : 60,-160
}
";

fn write_mission(dir: &Path, port: u16) {
    let moos = format!(
        "ServerHost = localhost\nServerPort = {port}\nCommunity = abe\nMOOSTimeWarp = 1\n\
         LatOrigin = 43.825300\nLongOrigin = -70.330400\n\n\
         ProcessConfig = pHelmIvP\n{{\n  AppTick = 10\n  CommsTick = 10\n  behaviors = bad.bhv\n  \
         domain = course:0:359:360\n  domain = speed:0:4:41\n}}\n"
    );
    std::fs::write(dir.join("m.moos"), moos).unwrap();
    std::fs::write(dir.join("bad.bhv"), BAD_BHV).unwrap();
}

fn start_helm(dir: &Path, bin: &Path, tag: &str) -> (Proc, PathBuf) {
    let err_path = dir.join(format!("{tag}.stderr"));
    let child = Command::new(bin.join("pHelmIvP"))
        .current_dir(dir)
        .arg("m.moos")
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&err_path).unwrap())
        .spawn()
        .expect("pHelmIvP starts through its link");
    (Proc(child), err_path)
}

/// What the observer saw while the helm ran: MALCONFIG postings and any DESIRED_* values.
async fn observe(port: u16, count: usize) -> (usize, Vec<(String, f64)>) {
    let (client, mut inbox) = Client::start(ClientConfig::new("observer", "127.0.0.1", port));
    tokio::time::timeout(Duration::from_secs(30), client.wait_connected())
        .await
        .expect("connects within 30 s")
        .expect("accepted");
    for v in ["IVPHELM_STATE", "DESIRED_HEADING", "DESIRED_SPEED"] {
        client.register(v, 0.0);
    }
    let mut malconfig = 0;
    let mut desired = Vec::new();
    let deadline = tokio::time::Instant::now() + Duration::from_secs(60);
    while let Ok(Some(m)) = tokio::time::timeout_at(deadline, inbox.recv()).await {
        match m.key_str().as_ref() {
            "IVPHELM_STATE" => {
                assert_eq!(m.sval_str(), "MALCONFIG", "the helm left MALCONFIG");
                malconfig += 1;
                if malconfig == count {
                    break;
                }
            }
            k if k.starts_with("DESIRED_") => desired.push((k.to_string(), m.dval)),
            _ => {}
        }
    }
    client.close().await;
    (malconfig, desired)
}

/// Sends `sig` (`INT` or `TERM`) and waits at most 2 s for the process to end.
fn signal_and_wait(p: &mut Proc, sig: &str) -> std::process::ExitStatus {
    let ok = Command::new("kill")
        .args([&format!("-{sig}"), &p.0.id().to_string()])
        .status()
        .expect("kill runs")
        .success();
    assert!(ok, "kill -{sig} failed");
    for _ in 0..40 {
        if let Some(status) = p.0.try_wait().unwrap() {
            return status;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    panic!("pHelmIvP still running 2 s after SIG{sig}");
}

#[test]
fn a_misconfigured_helm_stays_up_in_malconfig_and_stops_on_sigint_and_sigterm() {
    let dir = fresh_dir("helm-malconfig");
    let bin = dir.join("bin");
    let out = coug(&dir, &["install-aliases", bin.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );

    let rt = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .unwrap();
    let server = rt
        .block_on(Server::bind(ServerConfig::with_addr(
            "127.0.0.1:0".parse().unwrap(),
        )))
        .expect("DB binds on loopback");
    let port = server.local_addr().port();
    write_mission(&dir, port);

    for sig in ["INT", "TERM"] {
        let (mut helm, err_path) = start_helm(&dir, &bin, sig);
        let (malconfig, desired) = rt.block_on(observe(port, 8));
        assert_eq!(malconfig, 8, "IVPHELM_STATE = MALCONFIG posted repeatedly");
        assert!(
            desired.iter().all(|(_, v)| *v == 0.0),
            "a MALCONFIG helm drove: {desired:?}"
        );
        assert!(
            helm.0.try_wait().unwrap().is_none(),
            "the helm exited on a configuration error"
        );
        // PHELMIVP_PID: its process id, posted at start-up.
        let pid = server.with_db(|d| d.current("PHELMIVP_PID").map(|m| m.dval));
        assert_eq!(pid, Some(f64::from(helm.0.id())));
        // IVPHELM_CPU every iteration (even in MALCONFIG), and the process's measured load
        // in its status: a percentage, and a peak memory above 0 KiB.
        let cpu = server.with_db(|d| d.current("IVPHELM_CPU").map(|m| m.dval));
        assert!(cpu.is_some_and(|c| c.is_finite() && c >= 0.0), "{cpu:?}");
        let status = server
            .with_db(|d| {
                d.current("PHELMIVP_STATUS")
                    .map(|m| m.sval_str().into_owned())
            })
            .expect("a status");
        let max_kb: f64 = status
            .split(',')
            .find_map(|kv| kv.strip_prefix("memory_max_kb="))
            .and_then(|v| v.parse().ok())
            .expect("memory_max_kb");
        assert!(max_kb > 0.0, "{status}");
        // Its appcast carries the reason as a configuration warning and the MALCONFIG
        // notice as its report (posted unasked: a new configuration warning is due).
        let cast = server
            .with_db(|d| d.current("APPCAST").map(|m| m.sval_str().into_owned()))
            .expect("an APPCAST");
        let cast = appcast::AppCast::parse(&cast);
        assert_eq!(cast.proc_name(), "pHelmIvP");
        assert_eq!(cast.node_name(), "abe");
        assert!(
            cast.config_warnings()
                .iter()
                .any(|w| w.contains("capture_radius")),
            "{:?}",
            cast.config_warnings()
        );
        assert!(
            cast.messages()
                .contains("The helm is in the MALCONFIG state")
        );
        let status = signal_and_wait(&mut helm, sig);
        let stderr = std::fs::read_to_string(&err_path).unwrap();
        assert!(stderr.contains("MALCONFIG"), "{stderr}");
        assert!(
            stderr.contains("bad.bhv: Line 9") && stderr.contains("capture_radius"),
            "the reason names the file, line and parameter: {stderr}"
        );
        // Ended by the signal's handler, not killed by the default action.
        assert!(status.code().is_some(), "SIG{sig}: {status:?}");
    }
    rt.block_on(async move { server.shutdown() });
}
