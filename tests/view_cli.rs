//! `coug view`'s command line: a non-loopback bind without a token is refused before anything
//! is bound or joined; the help names every option.

mod common;

use common::*;

#[test]
fn non_loopback_bind_without_token_is_refused() {
    let dir = fresh_dir("view-cli");
    let out = coug(&dir, &["view", "--bind", "0.0.0.0", "--http-port", "0"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("coug view: error:") && err.contains("needs a token"),
        "{err}"
    );
}

#[test]
fn help_names_the_options() {
    let dir = fresh_dir("view-help");
    let out = coug(&dir, &["view", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for opt in [
        "MISSION.moos",
        "--host",
        "--port",
        "--http-port",
        "--bind",
        "--token",
    ] {
        assert!(text.contains(opt), "{opt}: {text}");
    }
}

#[test]
fn base_help_names_the_options_and_a_missing_db_is_an_error() {
    let dir = fresh_dir("base-help");
    let out = coug(&dir, &["base", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for opt in ["MISSION.moos", "--host", "--port", "--timeout"] {
        assert!(text.contains(opt), "{opt}: {text}");
    }
    // Nothing listens on port 1: the base says so and exits 1 before touching the terminal.
    let out = coug(
        &dir,
        &[
            "base",
            "--host",
            "127.0.0.1",
            "--port",
            "1",
            "--timeout",
            "0",
        ],
    );
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("coug base: error:"), "{err}");
}

/// `coug run --view` keeps serving the page after the run ends, until SIGINT. No clock in
/// the test: it reads the run's stderr until the line saying the run ended, then fetches the
/// page (the server must still answer), then sends SIGINT and waits for the exit (code 0,
/// the run's report on stdout). The receive timeouts only bound a hung binary.
#[test]
fn run_view_serves_after_the_run_until_sigint() {
    use std::io::{BufRead, BufReader, Read, Write};
    use std::process::{Command, Stdio};
    use std::time::Duration;

    let dir = fresh_dir("run-view-after");
    let alpha = test_support::mission_file("s1_alpha/alpha.moos");
    let logs = dir.join("logs");
    let mut child = Command::new(env!("CARGO_BIN_EXE_coug"))
        .current_dir(&dir)
        .arg("run")
        .arg(&alpha)
        .args(["--lockstep", "--deploy", "--max-time", "20", "--view"])
        .args(["--http-port", "0", "--log-dir"])
        .arg(&logs)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("coug run starts");
    let err = child.stderr.take().expect("piped stderr");
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(err).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let mut addr = None;
    loop {
        let line = rx
            .recv_timeout(Duration::from_secs(300))
            .expect("the run's stderr");
        if let Some(rest) = line.strip_prefix("coug run: viewer at http://") {
            addr = Some(rest.trim_end_matches('/').to_string());
        }
        if line.contains("the run ended; the viewer stays up until Ctrl-C") {
            break;
        }
    }
    let addr = addr.expect("the viewer's address before the run ended");
    let mut stream = std::net::TcpStream::connect(&addr).expect("the viewer still listens");
    stream
        .set_read_timeout(Some(Duration::from_secs(60)))
        .unwrap();
    write!(
        stream,
        "GET / HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n"
    )
    .unwrap();
    let mut page = String::new();
    stream.read_to_string(&mut page).unwrap();
    assert!(page.starts_with("HTTP/1.1 200"), "{page}");
    assert!(page.contains("viewer.js"), "{page}");
    assert!(child.try_wait().unwrap().is_none(), "still running");
    let pid = child.id().to_string();
    assert!(
        Command::new("kill")
            .args(["-INT", &pid])
            .status()
            .unwrap()
            .success()
    );
    let mut out = String::new();
    child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(0), "stdout: {out}");
    assert!(out.contains(".alog"), "the run's report: {out}");
}

#[test]
fn view_warns_of_a_background_it_cannot_find() {
    let dir = fresh_dir("view-background");
    std::fs::write(
        dir.join("m.moos"),
        "ServerHost = 127.0.0.1\nServerPort = 1\nLatOrigin = 43.8253\nLongOrigin = -70.3304\n\
         ProcessConfig = pMarineViewer\n{\n  tiff_file = nowhere.tif\n}\n",
    )
    .unwrap();
    // No DB on port 1: the view ends with an error, after the warning.
    let out = coug(
        &dir,
        &["view", "m.moos", "--http-port", "0", "--timeout", "0"],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("coug view: warning: m.moos: background image not found: nowhere.tif"),
        "{err}"
    );
    assert_eq!(out.status.code(), Some(1), "{err}");
}

/// `coug appcast --once` (uMAC in the terminal) against a DB with one app that answers
/// appcast requests: it asks with `APPCAST_REQ` (its own key, every app of every node), and
/// prints the node table, a node's apps, and an app's report.
#[test]
fn appcast_once_asks_for_casts_and_prints_nodes_apps_and_reports() {
    use moosdb::{Client, ClientConfig, Server, ServerConfig, Value};
    let dir = fresh_dir("appcast-once");
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
    // pFake on node abe: answers every request with its cast, and keeps the requests.
    let requests = std::sync::Arc::new(std::sync::Mutex::new(Vec::<String>::new()));
    {
        let requests = requests.clone();
        let (client, mut mail) = {
            let _in = rt.enter();
            Client::start(ClientConfig::new("pFake", "127.0.0.1", port))
        };
        rt.block_on(client.wait_connected()).unwrap();
        client.register("APPCAST_REQ", 0.0);
        rt.spawn(async move {
            let mut iteration = 0;
            while let Some(m) = mail.recv().await {
                requests.lock().unwrap().push(m.sval_str().into_owned());
                iteration += 1;
                let mut cast = appcast::AppCast::new();
                cast.set_proc_name("pFake");
                cast.set_node_name("abe");
                cast.set_iteration(iteration);
                cast.cfg_warning("unknown parameter: wobble");
                cast.set_messages("Depth goal: 12.5\n");
                let _ = client.notify("APPCAST", Value::text(cast.to_moos_string()));
            }
        });
    }
    let port_s = port.to_string();
    let base = [
        "appcast",
        "--host",
        "127.0.0.1",
        "--port",
        &port_s,
        "--once",
    ];
    let run = |extra: &[&str]| {
        let args: Vec<&str> = base.iter().chain(extra).copied().collect();
        let out = coug(&dir, &args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    // The node table: abe with one app, one configuration warning.
    let nodes = run(&[]);
    let abe = nodes
        .lines()
        .find(|l| l.starts_with("abe"))
        .unwrap_or_else(|| panic!("no abe in {nodes}"));
    assert_eq!(abe.split_whitespace().nth(1), Some("1"), "{nodes}");
    let apps = run(&["--node", "abe"]);
    assert!(apps.contains("pFake"), "{apps}");
    let report = run(&["--node", "abe", "--app", "pFake"]);
    assert!(report.contains("Depth goal: 12.5"), "{report}");
    assert!(report.contains("unknown parameter: wobble"), "{report}");
    let requests = requests.lock().unwrap();
    assert!(
        requests
            .iter()
            .any(|r| r.starts_with("node=all,app=all,duration=3.0,key=coug_appcast_")),
        "{requests:?}"
    );
    drop(requests);
    rt.block_on(async move { server.shutdown() });
}
