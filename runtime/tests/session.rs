//! A mission run as a library: `runtime::session` loads, validates and runs the project's
//! surface survey in process, stops when its observer asks, and refuses what cannot run.

use std::path::{Path, PathBuf};

use mission::diagnostic::DiagnosticKind;
use runtime::Outcome;
use runtime::session::{self, Ended, Mode, Observer, RunOptions, SessionError};

fn survey() -> PathBuf {
    let p = Path::new(env!("CARGO_MANIFEST_DIR")).join("../missions/surface_survey/survey.moos");
    assert!(p.is_file(), "{} is missing", p.display());
    p
}

fn fresh(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("temp dir");
    d
}

/// Counts steps and helm summaries; asks to stop after `stop_after` steps.
#[derive(Default)]
struct Counting {
    steps: Vec<f64>,
    summaries: usize,
    stop_after: usize,
    saw_drive: bool,
}

impl Observer for Counting {
    fn helm_summary(&mut self, _summary: &str) {
        self.summaries += 1;
    }

    fn step(&mut self, sim_s: f64, current: &dyn Fn(&str) -> Option<runtime::Value>) {
        self.steps.push(sim_s);
        if current("IVPHELM_STATE").and_then(|v| v.as_str().map(String::from))
            == Some("DRIVE".into())
        {
            self.saw_drive = true;
        }
    }

    fn stop_requested(&self) -> bool {
        self.stop_after > 0 && self.steps.len() >= self.stop_after
    }
}

#[test]
fn a_survey_runs_in_process_and_reports_its_log_totals() {
    let dir = fresh("session-survey");
    let loaded = session::load(&survey(), &[], &[]).expect("loads");
    let v = session::validate(&loaded);
    assert!(v.errors.is_empty() && v.malconfig.is_empty(), "{v:?}");
    let opts = RunOptions {
        deploy: true,
        until: Some("MISSION = complete".into()),
        max_time: 900.0,
        log_dir: Some(dir.clone()),
        ..RunOptions::default()
    };
    let mut obs = Counting::default();
    let report = session::run(&loaded, &opts, &mut obs).expect("runs");
    let Ended::Outcome(Outcome::ConditionMet { time }) = report.ended else {
        panic!("ended {:?}", report.ended)
    };
    assert!(time > session::LOCKSTEP_START + 60.0);
    assert!(!report.until_pending());
    // One step per simulated second, the helm's summaries seen, the helm driving.
    assert!(
        obs.steps.len() as f64 >= report.sim_s() - 1.0,
        "{}",
        obs.steps.len()
    );
    assert!(
        obs.steps
            .windows(2)
            .all(|w| (w[1] - w[0] - 1.0).abs() < 1e-9)
    );
    assert!(obs.summaries > 10 && obs.saw_drive);
    assert!(Path::new(&report.alog).starts_with(&dir), "{}", report.alog);
    let totals = report.totals.as_ref().expect("the log reads back");
    // Counted while the log was written: what reading the file back gives, and so the same
    // report text.
    let text = std::fs::read_to_string(&report.alog).expect("the alog is readable");
    let back = session::LogTotals::from_alog(&alog::parse(&text).expect("an alog"));
    assert_eq!(totals, &back);
    let mut read_back = report.clone();
    read_back.totals = Some(back);
    assert_eq!(read_back.to_string(), report.to_string());
    assert_eq!(totals.completed, vec!["survey", "return"]);
    assert!(
        totals.summary.distance > 100.0,
        "{}",
        totals.summary.distance
    );
    let text = report.to_string();
    assert!(
        text.contains("until condition met (MISSION = complete)"),
        "{text}"
    );
    assert!(text.contains("MISSION = \"complete\""), "{text}");
}

#[test]
fn a_stop_request_ends_the_run_with_its_log_closed() {
    let dir = fresh("session-stop");
    let loaded = session::load(&survey(), &[], &[]).expect("loads");
    let opts = RunOptions {
        deploy: true,
        max_time: 900.0,
        log_dir: Some(dir),
        ..RunOptions::default()
    };
    let mut obs = Counting {
        stop_after: 30,
        ..Counting::default()
    };
    let report = session::run(&loaded, &opts, &mut obs).expect("runs");
    assert_eq!(
        report.ended,
        Ended::Interrupted {
            time: session::LOCKSTEP_START + 30.0
        }
    );
    assert_eq!(obs.steps.len(), 30);
    // The log is complete up to the stop: it parses and ends near 30 s.
    let text = std::fs::read_to_string(&report.alog).expect("the alog exists");
    let log = alog::parse(&text).expect("a whole alog");
    let last = log.entries.last().expect("entries").time;
    assert!((29.0..=30.0).contains(&last), "last entry at {last}");
}

#[test]
fn what_cannot_run_is_refused_with_the_reason() {
    let loaded = session::load(&survey(), &[], &[]).expect("loads");
    let bad = |opts: RunOptions| match session::run(&loaded, &opts, &mut session::Quiet) {
        Err(SessionError::Invalid(why)) => why,
        other => panic!("{:?}", other.map(|r| r.ended)),
    };
    let why = bad(RunOptions {
        until: Some("MISSION = ".into()),
        ..RunOptions::default()
    });
    assert!(why.starts_with("--until \"MISSION = \":"), "{why}");
    let why = bad(RunOptions {
        max_time: -1.0,
        ..RunOptions::default()
    });
    assert!(why.contains("positive number of seconds"), "{why}");
    let why = bad(RunOptions {
        buttons: vec!["LAUNCH".into()],
        ..RunOptions::default()
    });
    assert!(why.starts_with("--button LAUNCH"), "{why}");
    let why = bad(RunOptions {
        mode: Mode::RealTime {
            warp: Some(-2.0),
            port: Some(0),
        },
        ..RunOptions::default()
    });
    assert!(why.starts_with("--warp -2"), "{why}");
    // Not a mission at all.
    let dir = fresh("session-not-a-mission");
    let f = dir.join("x.moos");
    std::fs::write(&f, "just = text\n").unwrap();
    assert!(matches!(
        session::load(&f, &[], &[]),
        Err(session::LoadError::NotAMission(_))
    ));
}

#[test]
fn validation_gives_each_warning_its_line_and_kind() {
    let dir = fresh("session-validate");
    let f = dir.join("m.moos");
    std::fs::write(
        &f,
        "ServerPort = 9000\nCommunity = v\nLatOrigin = north\nLongOrigin = 0\n\
         ProcessConfig = ANTLER\n{\n  Run = MOOSDB\n  Run = uSimMarineV22\n  Run = pNodeReporter\n}\n\
         ProcessConfig = uSimMarineV22\n{\n  AppTick = four\n  wormhole = 1\n}\n",
    )
    .unwrap();
    let loaded = session::load(&f, &[], &[]).expect("loads");
    let v = session::validate(&loaded);
    let kinds: Vec<(DiagnosticKind, u32)> =
        v.warnings.iter().map(|d| (d.kind, d.span.line)).collect();
    for want in [
        (DiagnosticKind::AppSetting, 13),
        (DiagnosticKind::NoConfigBlock, 9),
        (DiagnosticKind::BadGlobal, 3),
        (DiagnosticKind::AppSetting, 14),
    ] {
        assert!(
            kinds.contains(&want),
            "{want:?} missing from {:?}",
            v.warnings
        );
    }
    assert!(v.warnings.iter().all(|d| !d.is_error()));
    let shown = v
        .warnings
        .iter()
        .find(|d| d.span.line == 13)
        .unwrap()
        .to_string();
    assert!(
        shown.ends_with("m.moos:13: warning: uSimMarineV22: AppTick = four: not a number; MOOS cannot read it and keeps its default"),
        "{shown}"
    );
}
