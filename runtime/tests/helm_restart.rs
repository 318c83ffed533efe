//! RESTART_HELM as pHelmIvP: the behaviour files are read again; `type1` keeps the info
//! buffer (the initializes are not posted again), `type2` starts over; IVPHELM_RESTARTED =
//! true once the helm decides again (a second after the restart).

use mission::nsplug::Options;
use mission::source::FsSource;
use runtime::app::{App, Mail, Post, Value};
use runtime::helm::HelmApp;

const MOOS: &str = "ServerPort = 9000\nCommunity = abe\nLatOrigin = 43.8\nLongOrigin = -70.3\n\
    ProcessConfig = pHelmIvP\n{\n  behaviors = r.bhv\n  domain = course:0:359:360\n  \
    domain = speed:0:4:41\n  start_engaged = true\n}\n";

fn bhv(speed: f64) -> String {
    format!(
        "initialize READY = yes\nBehavior = BHV_ConstantSpeed\n{{\n  name = cs\n  speed = {speed}\n  \
         duration = no-time-limit\n}}\nBehavior = BHV_ConstantHeading\n{{\n  name = ch\n  heading = 90\n  \
         duration = no-time-limit\n}}\n"
    )
}

fn mail(key: &str, value: Value, t: f64) -> Mail {
    Mail {
        key: key.into(),
        value,
        time: t,
        source: "test".into(),
        source_aux: Default::default(),
        community: "abe".into(),
    }
}

/// One iteration at `t` with nav (and `extra`); the posts.
fn step(h: &mut HelmApp, t: f64, extra: &[Mail]) -> Vec<Post> {
    let mut m: Vec<Mail> = ["NAV_X", "NAV_Y", "NAV_SPEED", "NAV_HEADING", "NAV_DEPTH"]
        .iter()
        .map(|k| mail(k, Value::Double(0.0), t))
        .collect();
    m.extend_from_slice(extra);
    let mut out = Vec::new();
    h.on_mail(&m, t, &mut out).unwrap();
    h.iterate(t, &mut out).unwrap();
    out
}

fn values<'a>(p: &'a [Post], key: &str) -> Vec<&'a Value> {
    p.iter()
        .filter(|x| x.key == key)
        .map(|x| &x.value)
        .collect()
}

#[test]
fn restart_reads_the_behaviours_again_and_confirms_once_deciding() {
    let dir = test_support::scratch_dir("restart");
    std::fs::write(dir.join("r.bhv"), bhv(1.0)).unwrap();
    let src = mission::source::SourceMap::from_text("r.moos", MOOS);
    let m = mission::moos::parse_moos(&src).value;
    let mut h = HelmApp::from_mission_files("pHelmIvP", &m, &dir, &Options::new(), &FsSource);
    assert!(h.config_errors().is_empty(), "{:?}", h.config_errors());
    let first = step(&mut h, 0.0, &[]);
    assert_eq!(values(&first, "READY"), [&Value::String("yes".into())]);
    let p = step(&mut h, 2.0, &[]);
    assert_eq!(values(&p, "DESIRED_SPEED"), [&Value::Double(1.0)]);

    // type1: the new file's speed, no initialize posted again, the confirmation after 1 s.
    std::fs::write(dir.join("r.bhv"), bhv(2.0)).unwrap();
    let p = step(
        &mut h,
        3.0,
        &[mail("RESTART_HELM", Value::String("type1".into()), 3.0)],
    );
    assert!(
        values(&p, "READY").is_empty(),
        "type1 keeps the info buffer"
    );
    assert!(values(&p, "IVPHELM_RESTARTED").is_empty());
    assert!(
        values(&p, "DESIRED_SPEED").is_empty(),
        "no decision in the first second"
    );
    let p = step(&mut h, 4.5, &[]);
    assert_eq!(
        values(&p, "IVPHELM_RESTARTED"),
        [&Value::String("true".into())]
    );
    assert_eq!(values(&p, "DESIRED_SPEED"), [&Value::Double(2.0)]);
    let p = step(&mut h, 5.0, &[]);
    assert!(values(&p, "IVPHELM_RESTARTED").is_empty(), "once");

    // type2: a fresh buffer, the initializes posted again; anything else is ignored.
    let p = step(
        &mut h,
        6.0,
        &[mail("RESTART_HELM", Value::String("type3".into()), 6.0)],
    );
    assert!(values(&p, "READY").is_empty());
    let p = step(
        &mut h,
        7.0,
        &[mail("RESTART_HELM", Value::String("type2".into()), 7.0)],
    );
    assert_eq!(values(&p, "READY"), [&Value::String("yes".into())]);
    std::fs::remove_dir_all(&dir).unwrap();
}
