//! Properties of the helm under arbitrary mail: it never panics, decisions only come out in
//! DRIVE with a clear all-stop, and a MALCONFIG helm never decides.

mod common;

use helm::{Helm, Mail, Value};
use mission::source::SourceMap;
use proptest::prelude::*;
use test_support::mission_text;

fn alpha(extra: &str) -> Helm {
    let moos_text = mission_text("s1_alpha/alpha.moos");
    let moos_text = moos_text.replace(
        "behaviors  = alpha.bhv",
        &format!("behaviors  = alpha.bhv\n{extra}"),
    );
    let moos = mission::moos::parse_moos(&SourceMap::from_text("alpha.moos", &moos_text));
    let bhv = mission::bhv::parse_bhv(&SourceMap::from_text(
        "alpha.bhv",
        &mission_text("s1_alpha/alpha.bhv"),
    ));
    Helm::from_mission(&moos.value, &bhv)
}

#[derive(Debug, Clone)]
enum Ev {
    Nav(f64, f64, f64, f64),
    Text(&'static str, &'static str),
    Num(&'static str, f64),
    Wait,
}

fn event() -> impl Strategy<Value = Ev> {
    prop_oneof![
        (
            -300.0..300.0f64,
            -300.0..300.0f64,
            -720.0..720.0f64,
            -1.0..5.0f64
        )
            .prop_map(|(x, y, h, v)| Ev::Nav(x, y, h, v)),
        prop::sample::select(vec![
            ("MOOS_MANUAL_OVERRIDE", "false"),
            ("MOOS_MANUAL_OVERRIDE", "true"),
            ("MOOS_MANUAL_OVERIDE", "FALSE"),
            ("DEPLOY", "true"),
            ("DEPLOY", "false"),
            ("RETURN", "true"),
            ("RETURN", "false"),
            ("SPD", "true"),
            ("WPT_UPDATE", "speed=2.5"),
            ("WPT_UPDATE", "speed=fast"),
            ("WPT_UPDATE", "points=radial:: x=0,y=0,radius=20,pts=5"),
            ("WPT_UPDATE", "currix=3"),
            ("WPT_UPDATE", "name=x # speed=1"),
            ("SPEED_UPDATE", "duration=2"),
            ("CONST_SPD_RESET", "true"),
            ("RETURN_UPDATE", "points=garbage"),
            ("HELM_MAP_CLEAR", "0"),
            ("IVPHELM_REJOURNAL", "true"),
        ])
        .prop_map(|(k, v)| Ev::Text(k, v)),
        prop::sample::select(vec!["DEPLOY", "NAV_X", "WPT_UPDATE", "NAV_SPEED"])
            .prop_flat_map(|k| (-1e6..1e6f64).prop_map(move |v| Ev::Num(k, v))),
        Just(Ev::Wait),
    ]
}

fn run(helm: &mut Helm, events: &[Ev]) -> Vec<(String, Vec<helm::Posting>)> {
    let mut t = 0.0;
    let mut out = Vec::new();
    for e in events {
        t += 0.25;
        let m = match e {
            Ev::Nav(x, y, h, v) => vec![
                Mail::new("NAV_X", *x, t),
                Mail::new("NAV_Y", *y, t),
                Mail::new("NAV_HEADING", *h, t),
                Mail::new("NAV_SPEED", *v, t),
            ],
            Ev::Text(k, v) => vec![Mail::new(k, *v, t)],
            Ev::Num(k, v) => vec![Mail::new(k, *v, t)],
            Ev::Wait => vec![],
        };
        helm.on_mail(&m);
        let posts = helm.iterate(t).to_vec();
        out.push((helm.state().as_str().to_string(), posts));
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    #[test]
    fn decisions_only_in_drive_and_clear(events in prop::collection::vec(event(), 1..120)) {
        let mut helm = alpha("");
        prop_assert!(helm.config_errors().is_empty());
        let mut allstop = String::new();
        for (state, posts) in run(&mut helm, &events) {
            for p in &posts {
                if p.key == "IVPHELM_ALLSTOP" {
                    allstop = p.value.as_str().unwrap_or("").to_string();
                }
                if p.key.starts_with("DESIRED_") {
                    let v = p.value.as_f64().expect("decisions are numbers");
                    prop_assert!(v.is_finite());
                    if v != 0.0 {
                        prop_assert_eq!(&state, "DRIVE");
                        prop_assert_eq!(&allstop, "clear");
                    }
                }
                if p.key == "DESIRED_SPEED" {
                    let v = p.value.as_f64().unwrap();
                    prop_assert!((0.0..=4.0).contains(&v));
                }
            }
        }
    }

    #[test]
    fn malconfig_never_decides(events in prop::collection::vec(event(), 1..60)) {
        let mut helm = alpha("  no_such_param = 1");
        prop_assert!(!helm.config_errors().is_empty());
        for (state, posts) in run(&mut helm, &events) {
            prop_assert_eq!(&state, "MALCONFIG");
            prop_assert!(posts.iter().all(|p| !p.key.starts_with("DESIRED_")));
            prop_assert!(posts.iter().all(|p| p.value != Value::String("DRIVE".into())));
        }
    }
}
