//! The evaluator on hand-made mail: triggers, priorities, latch and clear, the surfacing and
//! the disarm, the helm's failure, MALCONFIG; and a proptest that no mail sequence panics.

use moos_types::{Post, Value};
use proptest::prelude::*;
use safety::{Notice, Phase, SafetyConfig, Supervisor, bits, parse_rule};

fn sup(rules: &[&str], tweak: impl FnOnce(&mut SafetyConfig)) -> Supervisor {
    let mut c = SafetyConfig {
        rules: rules.iter().map(|r| parse_rule(r).unwrap()).collect(),
        ..SafetyConfig::default()
    };
    c.return_flags = vec![safety::config::Flag::parse("RETURN=true").unwrap()];
    c.clear_flags = vec![safety::config::Flag::parse("RETURN=false").unwrap()];
    tweak(&mut c);
    Supervisor::new(c, Vec::new())
}

fn step(s: &mut Supervisor, now: f64) -> Vec<Post> {
    let mut out = Vec::new();
    let mut notes = Vec::new();
    s.evaluate(now, &mut out, &mut notes);
    out
}

fn find<'a>(out: &'a [Post], key: &str) -> Option<&'a Value> {
    out.iter().rev().find(|p| p.key == key).map(|p| &p.value)
}

fn started(s: &mut Supervisor, now: f64) -> Vec<Post> {
    let mut out = Vec::new();
    s.start(now, &mut out, &mut Vec::new());
    out
}

#[test]
fn leak_surfaces_on_the_actuators_then_disarms_once_up() {
    let mut s = sup(&["leak: LEAK == true -> surface_disarm"], |_| {});
    let out = started(&mut s, 0.0);
    assert_eq!(find(&out, "SAFETY_MODE"), Some(&Value::text("OK")));
    assert_eq!(find(&out, "SAFETY_HEALTH"), Some(&Value::Double(0.0)));
    s.on_mail("LEAK", &Value::text("false"), "iTeensy", 1.0);
    s.on_mail("NAV_DEPTH", &Value::Double(4.0), "pNavGraph", 1.0);
    assert!(find(&step(&mut s, 1.0), "SAFETY_EVENT").is_none());
    s.on_mail("LEAK", &Value::Double(1.0), "iTeensy", 2.0);
    let out = step(&mut s, 2.0);
    assert_eq!(
        find(&out, "MOOS_MANUAL_OVERRIDE"),
        Some(&Value::text("true"))
    );
    assert_eq!(find(&out, "DESIRED_THRUST"), Some(&Value::Double(20.0)));
    assert_eq!(find(&out, "DESIRED_ELEVATOR"), Some(&Value::Double(-100.0)));
    assert_eq!(find(&out, "DESIRED_RUDDER"), Some(&Value::Double(0.0)));
    assert_eq!(find(&out, "SAFETY_MODE"), Some(&Value::text("SURFACE")));
    let events: Vec<&str> = out
        .iter()
        .filter(|p| p.key == "SAFETY_EVENT")
        .filter_map(|p| p.value.as_str())
        .collect();
    assert_eq!(
        events,
        [
            "trigger=leak,action=surface_disarm,priority=1,reason=LEAK == true (LEAK=1)",
            "mode=SURFACE,via=actuators"
        ]
    );
    let h = bits::TRIGGERED | bits::SURFACING | bits::ACTUATORS | safety::Kind::Leak.bit();
    assert_eq!(
        find(&out, "SAFETY_HEALTH"),
        Some(&Value::Double(f64::from(h)))
    );
    // The leak stops: latched, the vehicle keeps coming up.
    s.on_mail("LEAK", &Value::Double(0.0), "iTeensy", 3.0);
    s.on_mail("NAV_DEPTH", &Value::Double(0.2), "pNavGraph", 10.0);
    let out = step(&mut s, 10.0);
    assert_eq!(find(&out, "DESIRED_THRUST"), Some(&Value::Double(20.0)));
    assert_eq!(s.phase(), Phase::Surfacing);
    // Up for less than surface_hold (5 s): still surfacing; then disarmed.
    assert_eq!(s.phase(), Phase::Surfacing);
    step(&mut s, 14.9);
    assert_eq!(s.phase(), Phase::Surfacing);
    let out = step(&mut s, 15.0);
    assert_eq!(s.phase(), Phase::Disarmed);
    assert_eq!(find(&out, "DESIRED_THRUST"), Some(&Value::Double(0.0)));
    assert_eq!(find(&out, "SAFETY_MODE"), Some(&Value::text("DISARMED")));
    assert!(
        out.iter()
            .any(|p| p.value.as_str() == Some("mode=DISARMED,depth=0.20,after=13.0"))
    );
    // Someone lifts the override: pSafety puts it back.
    s.on_mail(
        "MOOS_MANUAL_OVERRIDE",
        &Value::text("false"),
        "uPokeDB",
        16.0,
    );
    let out = step(&mut s, 16.0);
    assert_eq!(
        find(&out, "MOOS_MANUAL_OVERRIDE"),
        Some(&Value::text("true"))
    );
    assert_eq!(find(&out, "DESIRED_THRUST"), Some(&Value::Double(0.0)));
    // A reset releases the latched rule (its condition is false): the actuators are let go.
    s.on_mail("SAFETY_RESET", &Value::text("leak"), "uPokeDB", 17.0);
    let out = step(&mut s, 17.0);
    assert_eq!(s.phase(), Phase::Ok);
    assert!(find(&out, "DESIRED_THRUST").is_none());
    assert_eq!(find(&out, "SAFETY_EVENT"), Some(&Value::text("mode=OK")));
    assert_eq!(find(&out, "SAFETY_HEALTH"), Some(&Value::Double(0.0)));
    assert!(
        out.iter()
            .any(|p| p.value.as_str() == Some("clear=leak,by=reset"))
    );
    assert!(find(&step(&mut s, 18.0), "MOOS_MANUAL_OVERRIDE").is_none());
}

#[test]
fn a_reset_while_the_condition_holds_is_refused() {
    let mut s = sup(&["leak: LEAK == true -> allstop"], |_| {});
    started(&mut s, 0.0);
    s.on_mail("LEAK", &Value::text("true"), "iTeensy", 1.0);
    step(&mut s, 1.0);
    s.on_mail("SAFETY_RESET", &Value::text("all"), "uPokeDB", 2.0);
    let mut notes = Vec::new();
    s.evaluate(2.0, &mut Vec::new(), &mut notes);
    assert_eq!(s.phase(), Phase::AllStop);
    assert!(notes.contains(&Notice::Event(
        "reset all refused: the condition still holds".into()
    )));
}

/// A stalled machine: the whole community (the sensor's driver, the helm, pSafety) stops
/// for 6 s of MOOS time (0.75 s of wall time at warp 8) and comes back; the time nobody
/// could post is not taken for silence. A sensor that really stops is still caught after its
/// 5 s, and one that dies during a stall at most `max_gap` after its 5 s of watched time.
#[test]
fn a_stalled_machine_is_no_stale_sensor_but_a_dead_one_still_is() {
    let rules = [
        "pressure: stale(PRESSURE) > 5 -> surface_disarm, kind=sensor",
        "helm: silent(pHelmIvP) > 5 -> surface_disarm, kind=app",
    ];
    let mut s = sup(&rules, |_| {});
    s.set_period(0.25);
    started(&mut s, 0.0);
    let mut t = 0.0;
    let feed = |s: &mut Supervisor, t: f64| {
        s.on_mail("PRESSURE", &Value::Double(130_000.0), "iTeensy", t);
        s.on_mail("PHELMIVP_STATUS", &Value::text("x"), "pHelmIvP", t);
    };
    while t < 10.0 {
        t += 0.25;
        feed(&mut s, t);
        step(&mut s, t);
    }
    assert_eq!(s.phase(), Phase::Ok);
    // The stall: pSafety's next evaluation comes 6 s later, before anyone else has posted.
    t += 6.0;
    step(&mut s, t);
    assert_eq!(s.phase(), Phase::Ok, "6 s of which 5 unwatched");
    assert!((s.unwatched() - 5.0).abs() < 1e-9, "{}", s.unwatched());
    for _ in 0..8 {
        t += 0.25;
        feed(&mut s, t);
        step(&mut s, t);
    }
    assert_eq!(s.phase(), Phase::Ok);
    // Then the pressure sensor dies (the helm lives on): caught once 5 watched seconds have
    // passed, as without any stall.
    let last = t;
    let caught = loop {
        t += 0.25;
        s.on_mail("PHELMIVP_STATUS", &Value::text("x"), "pHelmIvP", t);
        let out = step(&mut s, t);
        if let Some(e) = out
            .iter()
            .filter(|p| p.key == "SAFETY_EVENT")
            .filter_map(|p| p.value.as_str())
            .find(|e| e.starts_with("trigger="))
        {
            assert!(e.starts_with("trigger=pressure,"), "{e}");
            break t;
        }
        assert!(t < last + 20.0, "never caught");
    };
    assert_eq!(caught - last, 5.25, "the first evaluation past 5 s");
    // Without the period (evaluations at irregular times), every gap counts, as before.
    let mut plain = sup(&rules, |_| {});
    started(&mut plain, 0.0);
    plain.on_mail("PRESSURE", &Value::Double(130_000.0), "iTeensy", 0.0);
    plain.on_mail("PHELMIVP_STATUS", &Value::text("x"), "pHelmIvP", 0.0);
    step(&mut plain, 0.25);
    step(&mut plain, 6.25);
    assert_eq!((plain.phase(), plain.unwatched()), (Phase::Surfacing, 0.0));
}

#[test]
fn stale_and_silent_count_from_start_and_clear_rules_let_go() {
    let mut s = sup(
        &[
            "dvl: stale(DVL_VALID) > 2 -> allstop, clear=1, kind=sensor",
            "helm: silent(pHelmIvP) > 5 -> warn, clear",
        ],
        |_| {},
    );
    let subs = s.subscriptions();
    assert!(
        subs.contains(&"DVL_VALID".to_string()) && subs.contains(&"PHELMIVP_STATUS".to_string())
    );
    started(&mut s, 100.0);
    assert_eq!(s.phase(), Phase::Ok);
    step(&mut s, 102.0);
    assert_eq!(s.phase(), Phase::Ok, "2 s is not more than 2 s");
    let out = step(&mut s, 102.5);
    assert_eq!(s.phase(), Phase::AllStop);
    assert_eq!(
        find(&out, "SAFETY_EVENT").and_then(Value::as_str),
        Some("mode=ALLSTOP")
    );
    assert!(out.iter().any(|p| p.value.as_str()
        == Some("trigger=dvl,action=allstop,priority=2,reason=stale(DVL_VALID) > 2 (no DVL_VALID since start (2.5 s))")));
    s.on_mail("DVL_VALID", &Value::Double(1.0), "iDVL", 103.0);
    step(&mut s, 103.0);
    assert_eq!(
        s.phase(),
        Phase::AllStop,
        "clears 1 s after the condition is false"
    );
    let out = step(&mut s, 104.0);
    assert_eq!(s.phase(), Phase::Ok);
    assert!(
        out.iter()
            .any(|p| p.value.as_str() == Some("clear=dvl,by=cleared"))
    );
    // Any post from the app keeps it alive, not only its status.
    s.on_mail("IVPHELM_SUMMARY", &Value::text("x"), "pHelmIvP", 104.5);
    s.on_mail("DVL_VALID", &Value::Double(1.0), "iDVL", 107.5);
    step(&mut s, 109.0);
    assert_eq!(s.phase(), Phase::Ok);
    s.on_mail("DVL_VALID", &Value::Double(1.0), "iDVL", 109.5);
    step(&mut s, 109.6);
    assert_eq!(s.phase(), Phase::Warn);
    assert_eq!(
        s.health(),
        bits::TRIGGERED | bits::WARN | safety::Kind::Other.bit()
    );
    s.on_mail("PHELMIVP_STATUS", &Value::text("x"), "pHelmIvP", 110.0);
    step(&mut s, 110.0);
    assert_eq!(s.phase(), Phase::Ok);
}

#[test]
fn the_highest_priority_commands_and_the_most_drastic_breaks_ties() {
    let mut s = sup(
        &[
            "nav: NAV_POS_STD > 5 -> return, priority=1, clear",
            "low: BATT < 14 -> surface_disarm, priority=2, clear",
            "deep: NAV_DEPTH > 6 -> allstop, priority=1, clear",
        ],
        |_| {},
    );
    started(&mut s, 0.0);
    s.on_mail("BATT", &Value::Double(13.0), "iTeensy", 1.0);
    s.on_mail("NAV_POS_STD", &Value::Double(9.0), "pNavGraph", 1.0);
    let out = step(&mut s, 1.0);
    assert_eq!(s.commander().map(|r| r.name.as_str()), Some("nav"));
    assert_eq!(s.phase(), Phase::Return);
    assert_eq!(find(&out, "RETURN"), Some(&Value::text("true")));
    s.on_mail("NAV_DEPTH", &Value::Double(7.0), "pNavGraph", 2.0);
    step(&mut s, 2.0);
    assert_eq!(s.commander().map(|r| r.name.as_str()), Some("deep"));
    assert_eq!(s.phase(), Phase::AllStop);
    s.on_mail("NAV_DEPTH", &Value::Double(5.0), "pNavGraph", 3.0);
    s.on_mail("NAV_POS_STD", &Value::Double(1.0), "pNavGraph", 3.0);
    step(&mut s, 3.0);
    assert_eq!(s.commander().map(|r| r.name.as_str()), Some("low"));
    assert_eq!(s.phase(), Phase::Surfacing);
    s.on_mail("BATT", &Value::Double(15.0), "iTeensy", 4.0);
    let out = step(&mut s, 4.0);
    assert_eq!(s.phase(), Phase::Ok);
    assert_eq!(
        find(&out, "RETURN"),
        Some(&Value::text("false")),
        "the clear flag"
    );
}

#[test]
fn surfacing_through_the_helm_falls_back_to_the_actuators_when_the_helm_fails() {
    let mut s = sup(&["leak: LEAK == 1 -> surface_disarm"], |c| {
        c.surface_via = safety::SurfaceVia::Helm;
        c.surface_flags = vec![safety::config::Flag::parse("SAFETY_SURFACE=true").unwrap()];
    });
    started(&mut s, 0.0);
    let alive =
        |s: &mut Supervisor, t: f64| s.on_mail("PHELMIVP_STATUS", &Value::text("x"), "pHelmIvP", t);
    alive(&mut s, 1.0);
    s.on_mail("NAV_DEPTH", &Value::Double(4.0), "pNavGraph", 1.0);
    s.on_mail("LEAK", &Value::Double(1.0), "iTeensy", 1.0);
    let out = step(&mut s, 1.0);
    assert_eq!(s.phase(), Phase::Surfacing);
    assert!(!s.on_actuators());
    assert!(find(&out, "MOOS_MANUAL_OVERRIDE").is_none());
    assert!(find(&out, "DESIRED_THRUST").is_none());
    assert_eq!(find(&out, "SAFETY_SURFACE"), Some(&Value::text("true")));
    assert_eq!(
        find(&out, "SAFETY_EVENT"),
        Some(&Value::text("mode=SURFACE,via=helm"))
    );
    // The helm keeps talking and the vehicle comes up: nothing more.
    for t in [3.0, 5.0, 7.0] {
        alive(&mut s, t);
        s.on_mail("NAV_DEPTH", &Value::Double(4.0 - t / 4.0), "pNavGraph", t);
        step(&mut s, t);
    }
    assert!(!s.on_actuators());
    // Then it goes quiet: after helm_timeout (5 s) pSafety takes the actuators.
    step(&mut s, 12.0);
    assert!(!s.on_actuators());
    let out = step(&mut s, 12.5);
    assert!(s.on_actuators());
    assert_eq!(
        find(&out, "MOOS_MANUAL_OVERRIDE"),
        Some(&Value::text("true"))
    );
    assert_eq!(find(&out, "DESIRED_THRUST"), Some(&Value::Double(20.0)));
    assert!(out.iter().any(|p| p.value.as_str()
        == Some("helm_failed=pHelmIvP silent for 5.5 s,mode=SURFACE,via=actuators")));

    // A MALCONFIG helm, and a helm that does not bring the vehicle up, fail too.
    for (state, depth, t, why) in [
        ("MALCONFIG", 4.0, 2.0, "pHelmIvP is in MALCONFIG"),
        (
            "DRIVE",
            3.8,
            62.0,
            "no ascent in 61 s (depth 3.80 m from 4.00 m)",
        ),
    ] {
        let mut s = sup(&["leak: LEAK == 1 -> surface_disarm"], |c| {
            c.surface_via = safety::SurfaceVia::Helm;
        });
        started(&mut s, 0.0);
        s.on_mail("NAV_DEPTH", &Value::Double(4.0), "pNavGraph", 1.0);
        s.on_mail("LEAK", &Value::Double(1.0), "iTeensy", 1.0);
        alive(&mut s, 1.0);
        step(&mut s, 1.0);
        assert!(!s.on_actuators());
        s.on_mail("IVPHELM_STATE", &Value::text(state), "pHelmIvP", t);
        s.on_mail("NAV_DEPTH", &Value::Double(depth), "pNavGraph", t);
        alive(&mut s, t);
        let out = step(&mut s, t);
        assert!(s.on_actuators(), "{why}");
        assert!(
            out.iter()
                .any(|p| p.value.as_str().is_some_and(|v| v.contains(why))),
            "{why}: {out:?}"
        );
    }
}

#[test]
fn a_surfacing_never_confirmed_disarms_at_the_timeout() {
    let mut s = sup(&["leak: LEAK == 1 -> surface_disarm"], |c| {
        c.surface_timeout = 60.0
    });
    started(&mut s, 0.0);
    s.on_mail("LEAK", &Value::Double(1.0), "iTeensy", 1.0);
    step(&mut s, 1.0);
    step(&mut s, 60.9);
    assert_eq!(s.phase(), Phase::Surfacing);
    let mut notes = Vec::new();
    s.evaluate(61.0, &mut Vec::new(), &mut notes);
    assert_eq!(s.phase(), Phase::Disarmed);
    assert!(
        notes
            .iter()
            .any(|n| matches!(n, Notice::Warning(w) if w.contains("disarmed anyway")))
    );
}

#[test]
fn a_malconfig_supervisor_refuses_deployment() {
    let c = SafetyConfig {
        rules: vec![parse_rule("leak: LEAK == 1 -> surface_disarm").unwrap()],
        ..SafetyConfig::default()
    };
    let mut s = Supervisor::new(c, vec!["s.moos:4: pSafety: unknown parameter `x`".into()]);
    let mut out = Vec::new();
    let mut notes = Vec::new();
    s.start(0.0, &mut out, &mut notes);
    assert_eq!(
        find(&out, "MOOS_MANUAL_OVERRIDE"),
        Some(&Value::text("true"))
    );
    assert_eq!(find(&out, "SAFETY_MODE"), Some(&Value::text("MALCONFIG")));
    assert_eq!(
        find(&out, "SAFETY_HEALTH"),
        Some(&Value::Double(f64::from(bits::MALCONFIG)))
    );
    assert!(matches!(&notes[0], Notice::Warning(w) if w.contains("unknown parameter")));
    s.on_mail(
        "MOOS_MANUAL_OVERRIDE",
        &Value::text("false"),
        "uPokeDB",
        1.0,
    );
    let out = step(&mut s, 1.0);
    assert_eq!(
        find(&out, "MOOS_MANUAL_OVERRIDE"),
        Some(&Value::text("true"))
    );
    // Its good rules still act.
    s.on_mail("LEAK", &Value::Double(1.0), "iTeensy", 2.0);
    let out = step(&mut s, 2.0);
    assert_eq!(find(&out, "SAFETY_MODE"), Some(&Value::text("SURFACE")));
    assert_eq!(find(&out, "DESIRED_THRUST"), Some(&Value::Double(20.0)));
    let mut body = String::new();
    s.report(&mut body);
    assert!(
        body.contains("MALCONFIG: s.moos:4") && body.contains("LATCHED"),
        "{body}"
    );
}

fn key() -> impl Strategy<Value = String> {
    prop::sample::select(vec![
        "LEAK",
        "BATT",
        "NAV_DEPTH",
        "DVL_VALID",
        "NAV_POS_STD",
        "PHELMIVP_STATUS",
        "IVPHELM_STATE",
        "SAFETY_RESET",
        "MOOS_MANUAL_OVERRIDE",
        "OTHER",
    ])
    .prop_map(String::from)
}

fn value() -> impl Strategy<Value = Value> {
    prop_oneof![
        any::<f64>().prop_map(Value::Double),
        prop::sample::select(vec![
            "true",
            "false",
            "all",
            "leak",
            "MALCONFIG",
            "DRIVE",
            "",
            "1e400",
            "NaN",
            "x y",
        ])
        .prop_map(Value::text),
        prop::collection::vec(any::<u8>(), 0..8).prop_map(Value::Binary),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// No mail sequence makes the evaluator panic; the words it posts stay consistent.
    #[test]
    fn no_mail_sequence_panics(
        via_helm in any::<bool>(),
        mail in prop::collection::vec(
            (key(), value(), prop::sample::select(vec!["pHelmIvP", "iTeensy", "uPokeDB"]), 0.0f64..5.0, any::<bool>()),
            0..80,
        ),
    ) {
        let mut s = sup(
            &[
                "leak: LEAK == true -> surface_disarm",
                "low: BATT < 14 -> allstop, clear=2",
                "deep: NAV_DEPTH > 6 -> return, clear",
                "dvl: stale(DVL_VALID) > 2 -> warn, clear=1",
                "helm: silent(pHelmIvP) > 5 -> surface_disarm, priority=3",
                "cfg: IVPHELM_STATE == MALCONFIG -> allstop",
                "nav: NAV_POS_STD >= 5 and NAV_DEPTH != 0 -> warn",
            ],
            |c| if via_helm { c.surface_via = safety::SurfaceVia::Helm },
        );
        let mut t = 0.0;
        started(&mut s, t);
        for (k, v, src, dt, eval) in mail {
            t += dt;
            s.on_mail(&k, &v, src, t);
            if eval {
                let out = step(&mut s, t);
                for p in &out {
                    if p.key == "SAFETY_HEALTH" {
                        let h = p.value.as_f64().unwrap();
                        prop_assert!((0.0..65536.0).contains(&h) && h.fract() == 0.0);
                    }
                }
                let h = s.health();
                prop_assert_eq!(h & bits::SURFACING != 0, s.phase() == Phase::Surfacing);
                prop_assert_eq!(h & bits::TRIGGERED != 0, s.rules().any(|(_, st)| st.active));
                prop_assert_eq!(s.phase() == Phase::Ok, !s.rules().any(|(_, st)| st.active));
            }
        }
        let mut body = String::new();
        s.report(&mut body);
        prop_assert!(body.starts_with("Mode: "));
    }
}

#[test]
fn a_couguv_surfaces_through_pcougcontrols_flags_only() {
    let b = {
        let src = mission::source::SourceMap::from_text(
            "c.moos",
            "ProcessConfig = pSafety\n{\n  rule = leak: LEAK == true -> surface_disarm\n  \
             rule = ahrs: stale(AHRS_HEADING) > 2 -> allstop\n  override_var = none\n  \
             thrust_var = none\n  elevator_var = NONE\n  rudder_var = none\n  \
             surface_flag = COUG_SURFACE=true\n  disarm_flag = COUG_ARM=false\n  \
             allstop_flag = COUG_ARM=false\n}\n",
        );
        mission::moos::parse_moos(&src).value.processes[0].clone()
    };
    let (cfg, errors) = SafetyConfig::from_block(&b);
    assert!(errors.is_empty(), "{errors:?}");
    let mut s = Supervisor::new(cfg.clone(), Vec::new());
    assert!(
        !s.subscriptions()
            .iter()
            .any(|v| v.is_empty() || v == "MOOS_MANUAL_OVERRIDE")
    );
    started(&mut s, 0.0);
    s.on_mail("AHRS_HEADING", &Value::Double(90.0), "iSeaTrac", 1.0);
    s.on_mail("NAV_DEPTH", &Value::Double(3.0), "pNavGraph", 1.0);
    s.on_mail("LEAK", &Value::text("true"), "iTeensy", 1.0);
    let out = step(&mut s, 1.0);
    let keys: Vec<&str> = out.iter().map(|p| &*p.key).collect();
    assert_eq!(
        keys,
        [
            "SAFETY_EVENT",
            "COUG_SURFACE",
            "SAFETY_EVENT",
            "SAFETY_MODE",
            "SAFETY_HEALTH"
        ]
    );
    s.on_mail("AHRS_HEADING", &Value::Double(90.0), "iSeaTrac", 2.0);
    s.on_mail("NAV_DEPTH", &Value::Double(0.1), "pNavGraph", 2.0);
    step(&mut s, 2.0);
    s.on_mail("AHRS_HEADING", &Value::Double(90.0), "iSeaTrac", 7.0);
    let out = step(&mut s, 7.0);
    assert_eq!(s.phase(), Phase::Disarmed);
    assert_eq!(find(&out, "COUG_ARM"), Some(&Value::text("false")));
    assert!(
        out.iter()
            .all(|p| !p.key.starts_with("DESIRED_") && p.key != "MOOS_MANUAL_OVERRIDE")
    );

    // An all-stop disarms through its flag.
    let mut s = Supervisor::new(cfg, Vec::new());
    started(&mut s, 0.0);
    let out = step(&mut s, 2.5);
    assert_eq!(s.phase(), Phase::AllStop);
    assert_eq!(find(&out, "COUG_ARM"), Some(&Value::text("false")));
    assert!(out.iter().all(|p| !p.key.starts_with("DESIRED_")));
}
