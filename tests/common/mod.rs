//! Helpers shared by the `coug run` end-to-end tests: run the binary in a fresh folder,
//! find and read the alog it wrote, follow the track, and check a plot.

#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub use runtime::session::RunOptions;
use runtime::session::{self, Mode};

/// A file of the project's own `missions/` folder.
pub fn project_mission(rel: &str) -> PathBuf {
    let p = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/missions")).join(rel);
    assert!(p.is_file(), "mission file {} is missing", p.display());
    p
}

/// A fresh, empty folder for one run.
pub fn fresh_dir(name: &str) -> PathBuf {
    test_support::fresh_dir(Path::new(env!("CARGO_TARGET_TMPDIR")).join(name))
}

/// Runs `coug` with `args` in `cwd`.
pub fn coug(cwd: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_coug"))
        .current_dir(cwd)
        .args(args)
        .output()
        .expect("coug runs")
}

/// The one `.alog` file under `dir` (searched recursively).
pub fn find_alog(dir: &Path) -> PathBuf {
    let mut found = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("readable dir").flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if p.extension().is_some_and(|x| x == "alog") {
                found.push(p);
            }
        }
    }
    assert_eq!(
        found.len(),
        1,
        "expected one alog under {}: {found:?}",
        dir.display()
    );
    found.pop().unwrap()
}

/// Lockstep options that deploy the mission and run until `until` holds, at most
/// `max_time` simulated seconds.
pub fn deploy_until(until: &str, max_time: f64) -> RunOptions {
    RunOptions {
        deploy: true,
        until: Some(until.to_string()),
        max_time,
        ..RunOptions::default()
    }
}

/// Runs a mission in lockstep, in process (`runtime::session`, what `coug run --lockstep`
/// calls), with nsplug `macros`, logging to `logs/` in a fresh folder `name`; asserts the
/// run completed (its `until` condition held) and returns the alog bytes and the closing
/// summary `coug run` prints. The alog names its own path (as pLogger's does): two runs meant
/// to log the same bytes use the same `name` (the folder is emptied first).
pub fn run_lockstep(
    name: &str,
    mission: &Path,
    macros: &[&str],
    mut opts: RunOptions,
) -> (Vec<u8>, String) {
    let dir = fresh_dir(name);
    let macros: Vec<String> = macros.iter().map(|m| m.to_string()).collect();
    let loaded = session::load(mission, &macros, &[])
        .unwrap_or_else(|e| panic!("{} does not load: {e}", mission.display()));
    let checked = session::validate(&loaded);
    assert!(checked.errors.is_empty(), "{:?}", checked.errors);
    opts.mode = Mode::Lockstep;
    opts.log_dir = Some(dir.join("logs"));
    let report = session::run(&loaded, &opts, &mut session::Quiet)
        .unwrap_or_else(|e| panic!("run of {} failed: {e}", mission.display()));
    let summary = report.to_string();
    assert!(
        !report.until_pending(),
        "run of {} ended before its until condition:\n{summary}",
        mission.display()
    );
    let alog = find_alog(&dir.join("logs"));
    assert_eq!(Path::new(&report.alog), alog, "the report names the log");
    (std::fs::read(&alog).expect("alog readable"), summary)
}

/// The last `n` lines of a text.
pub fn tail(s: &str, n: usize) -> String {
    let lines: Vec<&str> = s.lines().collect();
    lines[lines.len().saturating_sub(n)..].join("\n")
}

/// The parsed log.
pub fn parse(bytes: &[u8]) -> alog::Alog {
    alog::parse(std::str::from_utf8(bytes).expect("utf-8 alog")).expect("valid alog")
}

/// `(time, x, y)` each time the position changes.
pub fn track(log: &alog::Alog) -> Vec<(f64, f64, f64)> {
    let (mut x, mut y) = (None, None);
    let mut out = Vec::new();
    for e in &log.entries {
        match (e.var.as_str(), e.value.as_f64()) {
            ("NAV_X", Some(v)) => x = Some(v),
            ("NAV_Y", Some(v)) => y = Some(v),
            _ => continue,
        }
        if let (Some(x), Some(y)) = (x, y) {
            out.push((e.time, x, y));
        }
    }
    out
}

/// `(time, depth)` of every NAV_DEPTH record.
pub fn depths(log: &alog::Alog) -> Vec<(f64, f64)> {
    log.entries
        .iter()
        .filter(|e| e.var == "NAV_DEPTH")
        .filter_map(|e| Some((e.time, e.value.as_f64()?)))
        .collect()
}

/// Asserts the track passes within `radius` of each point in order, starting at record
/// `from`; returns the index of the last hit.
pub fn visits_in_order(
    track: &[(f64, f64, f64)],
    points: &[(f64, f64)],
    radius: f64,
    mut from: usize,
) -> usize {
    for &(vx, vy) in points {
        let hit = track[from..]
            .iter()
            .position(|&(_, x, y)| (x - vx).hypot(y - vy) <= radius)
            .unwrap_or_else(|| {
                panic!(
                    "point {vx},{vy} not reached within {radius} m after t={}",
                    track.get(from).map_or(f64::NAN, |t| t.0)
                )
            });
        from += hit;
    }
    from
}

/// The last string value of a variable.
pub fn last_str(log: &alog::Alog, var: &str) -> Option<String> {
    log.entries
        .iter()
        .rev()
        .find(|e| e.var == var)
        .and_then(|e| e.value.as_str().map(String::from))
}

/// Plots `alog` with `coug plot` to SVG and PNG and checks both are sane images; returns
/// the PNG bytes.
pub fn check_plots(alog_bytes: &[u8], name: &str, expect_depth_panel: bool) -> Vec<u8> {
    let dir = fresh_dir(&format!("{name}-plot"));
    std::fs::write(dir.join("run.alog"), alog_bytes).unwrap();
    for out in ["track.svg", "track.png"] {
        let o = coug(&dir, &["plot", "run.alog", "-o", out]);
        assert!(
            o.status.success(),
            "coug plot -o {out}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    let svg = std::fs::read_to_string(dir.join("track.svg")).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("valid SVG (XML)");
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    let polylines = doc
        .descendants()
        .filter(|n| n.has_tag_name("polyline") || n.has_tag_name("path"))
        .count();
    assert!(polylines >= 1, "the SVG draws no track");
    let text: String = doc
        .descendants()
        .filter(|n| n.is_text())
        .filter_map(|n| n.text())
        .collect::<Vec<_>>()
        .join(" ");
    assert_eq!(
        text.to_ascii_lowercase().contains("depth"),
        expect_depth_panel,
        "depth panel presence; SVG texts: {text}"
    );
    let png = std::fs::read(dir.join("track.png")).unwrap();
    let decoder = png::Decoder::new(std::io::Cursor::new(&png));
    let reader = decoder.read_info().expect("valid PNG");
    let info = reader.info();
    assert!(
        info.width >= 200 && info.height >= 200,
        "{}x{}",
        info.width,
        info.height
    );
    png
}

/// Asserts the committed expected-track image of a project mission is a sane PNG.
pub fn check_committed_png(mission_dir: &str) {
    let path = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/missions"))
        .join(mission_dir)
        .join("track.png");
    let bytes =
        std::fs::read(&path).unwrap_or_else(|e| panic!("{} is missing: {e}", path.display()));
    let reader = png::Decoder::new(std::io::Cursor::new(&bytes))
        .read_info()
        .expect("valid PNG");
    let info = reader.info();
    assert!(
        info.width >= 200 && info.height >= 200,
        "{}: {}x{}",
        path.display(),
        info.width,
        info.height
    );
}

/// A child process killed (and reaped) when dropped.
pub struct KillOnDrop(pub std::process::Child);

impl Drop for KillOnDrop {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// Starts `coug db MISSION --port 0` in `cwd` and returns it with the port it announced on
/// 127.0.0.1 (a bounded wait of 60 s).
pub fn spawn_db(cwd: &Path, mission: &str) -> (KillOnDrop, u16) {
    use std::io::{BufRead, BufReader};
    use std::process::Stdio;
    let mut db = Command::new(env!("CARGO_BIN_EXE_coug"))
        .current_dir(cwd)
        .args(["db", mission, "--port", "0"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("coug db starts");
    let out = db.stdout.take().expect("piped stdout");
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(out).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let port = loop {
        let line = rx
            .recv_timeout(std::time::Duration::from_secs(60))
            .expect("coug db announces its port within 60 s");
        if let Some(r) = line.split("listening on 127.0.0.1:").nth(1) {
            break r
                .split_whitespace()
                .next()
                .and_then(|p| p.parse().ok())
                .expect("a port number");
        }
    };
    (KillOnDrop(db), port)
}
