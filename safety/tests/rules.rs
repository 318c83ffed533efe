//! The rule parser and the block reader, good and bad input.

use mission::source::SourceMap;
use safety::rule::{Op, Operand, Term};
use safety::{Action, Kind, Release, RuleError, SafetyConfig, SurfaceVia, parse_rule};

fn block(text: &str) -> mission::moos::ProcessConfig {
    let src = SourceMap::from_text("s.moos", text);
    mission::moos::parse_moos(&src).value.processes[0].clone()
}

#[test]
fn every_rule_kind_of_the_issue_reads() {
    let r = parse_rule("leak: LEAK == true -> surface_disarm, priority=1, latch").unwrap();
    assert_eq!(
        r.terms,
        [Term::Compare {
            var: "LEAK".into(),
            op: Op::Eq,
            value: Operand::Bool(true)
        }]
    );
    assert_eq!(
        (r.action, r.priority, r.release, r.kind),
        (Action::SurfaceDisarm, 1, Release::Latch, Kind::Leak)
    );

    let r = parse_rule("battery: BATTERY_VOLTAGE < 14.0 -> surface_disarm").unwrap();
    assert_eq!(
        r.terms[0],
        Term::Compare {
            var: "BATTERY_VOLTAGE".into(),
            op: Op::Lt,
            value: Operand::Number(14.0)
        }
    );
    assert_eq!(
        (r.priority, r.release, r.kind),
        (1, Release::Latch, Kind::Battery)
    );

    let r = parse_rule("dvl: stale(DVL_VALID) > 2 -> allstop, kind=sensor, clear=3").unwrap();
    assert_eq!(
        r.terms[0],
        Term::Stale {
            var: "DVL_VALID".into(),
            seconds: 2.0
        }
    );
    assert_eq!(
        (r.action, r.priority, r.release, r.kind),
        (Action::AllStop, 2, Release::Clear(3.0), Kind::Sensor)
    );

    let r = parse_rule("gps: stale(GPS_FIX) > 10 AND NAV_DEPTH < 0.5 -> warn, kind=sensor, clear")
        .unwrap();
    assert_eq!(r.terms.len(), 2);
    assert_eq!(r.release, Release::Clear(0.0));
    assert_eq!(
        r.condition_text(),
        "stale(GPS_FIX) > 10 and NAV_DEPTH < 0.5"
    );

    let r = parse_rule("helm: silent(pHelmIvP) > 5 -> surface, kind=app").unwrap();
    assert_eq!(
        r.terms[0],
        Term::Silent {
            app: "pHelmIvP".into(),
            seconds: 5.0
        }
    );
    assert_eq!(r.action, Action::SurfaceDisarm);

    let r = parse_rule("helmcfg: IVPHELM_STATE == MALCONFIG -> all-stop").unwrap();
    assert_eq!(
        r.terms[0],
        Term::Compare {
            var: "IVPHELM_STATE".into(),
            op: Op::Eq,
            value: Operand::Word("MALCONFIG".into())
        }
    );
    assert_eq!((r.kind, r.action), (Kind::Other, Action::AllStop));

    let r = parse_rule("deep:NAV_DEPTH>=-2->return,priority=7").unwrap();
    assert_eq!(r.priority, 7);
    assert_eq!(
        r.terms[0],
        Term::Compare {
            var: "NAV_DEPTH".into(),
            op: Op::Ge,
            value: Operand::Number(-2.0)
        }
    );
}

#[test]
fn bad_rules_say_what_is_wrong() {
    let e = |s: &str| parse_rule(s).unwrap_err();
    assert_eq!(e("LEAK == true -> warn"), RuleError::MissingName);
    assert_eq!(
        e("le ak: LEAK == true -> warn"),
        RuleError::BadName("le ak".into())
    );
    assert_eq!(e("leak: LEAK == true"), RuleError::MissingArrow);
    assert_eq!(e("leak:  -> warn"), RuleError::EmptyCondition);
    assert_eq!(
        e("leak: LEAK = true -> warn"),
        RuleError::BadOperator("LEAK = true".into())
    );
    assert_eq!(
        e("leak: LEAK => 1 -> warn"),
        RuleError::BadVariable("LEAK =".into())
    );
    assert_eq!(e("leak: LEAK -> warn"), RuleError::BadTerm("LEAK".into()));
    assert_eq!(
        e("leak: LEAK == -> warn"),
        RuleError::MissingValue("LEAK ==".into())
    );
    assert_eq!(
        e("leak: LEAK > true -> warn"),
        RuleError::OrderOnWord("LEAK > true".into())
    );
    assert_eq!(
        e("leak: LEAK == true -> explode"),
        RuleError::UnknownAction("explode".into())
    );
    assert_eq!(e("leak: LEAK == true ->"), RuleError::MissingAction);
    assert_eq!(
        e("leak: LEAK == true -> warn, loud"),
        RuleError::UnknownOption("loud".into())
    );
    assert_eq!(
        e("leak: LEAK == true -> warn, priority=0"),
        RuleError::BadPriority("0".into())
    );
    assert_eq!(
        e("leak: LEAK == true -> warn, priority=high"),
        RuleError::BadPriority("high".into())
    );
    assert_eq!(
        e("leak: LEAK == true -> warn, clear=-1"),
        RuleError::BadClear("-1".into())
    );
    assert_eq!(
        e("leak: LEAK == true -> warn, kind=wet"),
        RuleError::UnknownKind("wet".into())
    );
    assert_eq!(
        e("leak: LEAK == true -> warn, latch, clear=2"),
        RuleError::ConflictingOption("clear".into())
    );
    assert_eq!(
        e("leak: LEAK == true -> warn, priority=2, priority=3"),
        RuleError::ConflictingOption("priority".into())
    );
    assert_eq!(
        e("dvl: stale(DVL_VALID) < 2 -> warn"),
        RuleError::BadTimeout("stale(DVL_VALID) < 2".into())
    );
    assert_eq!(
        e("dvl: stale(DVL_VALID) > 0 -> warn"),
        RuleError::BadTimeout("stale(DVL_VALID) > 0".into())
    );
    assert_eq!(
        e("dvl: stale(DVL_VALID) > soon -> warn"),
        RuleError::BadTimeout("stale(DVL_VALID) > soon".into())
    );
    assert_eq!(
        e("dvl: stale(DVL VALID) > 2 -> warn"),
        RuleError::BadVariable("DVL VALID".into())
    );
    assert_eq!(
        e("dvl: stale(DVL_VALID > 2 -> warn"),
        RuleError::BadTerm("stale(DVL_VALID > 2".into())
    );
    assert_eq!(e("x: A == 1 and -> warn"), RuleError::EmptyCondition);
    // The messages name the fix.
    assert!(
        e("leak: LEAK = true -> warn")
            .to_string()
            .contains("== != < <= > >=")
    );
}

#[test]
fn the_block_reads_settings_and_flags() {
    let b = block(
        "ProcessConfig = pSafety\n{\n  AppTick = 4\n  rule = leak: LEAK == true -> surface_disarm\n  \
         rule = nav: NAV_POS_STD > 5 -> return, clear=30\n  depth_var = SIM_DEPTH\n  \
         surface_via = helm\n  surface_thrust = 30\n  surface_elevator = -50\n  \
         surface_flag = COUG_SURFACE=true\n  disarm_flag = COUG_ARM=false\n  return_flag = RETURN=true\n  \
         clear_flag = RETURN = false\n  thrust_var = COUG_THRUST\n  helm_timeout = 3\n}\n",
    );
    let (c, errors) = SafetyConfig::from_block(&b);
    assert!(errors.is_empty(), "{errors:?}");
    assert_eq!(c.rules.len(), 2);
    assert_eq!(c.depth_var, "SIM_DEPTH");
    assert_eq!(c.surface_via, SurfaceVia::Helm);
    assert_eq!(
        (c.surface_thrust, c.surface_elevator, c.helm_timeout),
        (30.0, -50.0, 3.0)
    );
    assert_eq!(c.thrust_var, "COUG_THRUST");
    assert_eq!(c.surface_flags[0].var, "COUG_SURFACE");
    assert_eq!(c.surface_flags[0].value, moos_types::Value::text("true"));
    assert_eq!(c.disarm_flags[0].var, "COUG_ARM");
    assert_eq!(c.clear_flags[0].var, "RETURN");
    assert_eq!(c.clear_flags[0].value, moos_types::Value::text("false"));
}

#[test]
fn block_errors_are_located_and_never_silent() {
    let b = block(
        "ProcessConfig = pSafety\n{\n  rule = leak: LEAK = true -> surface_disarm\n  colour = red\n  \
         surface_depth = -1\n  rule = nav: NAV_POS_STD > 5 -> return\n  rule = NAV: A > 1 -> warn\n  \
         surface_via = sideways\n  surface_flag = COUG_SURFACE\n}\n",
    );
    let (c, errors) = SafetyConfig::from_block(&b);
    let located: Vec<String> = errors.iter().map(|d| d.located()).collect();
    assert!(errors.iter().all(|d| d.is_error()), "{located:?}");
    let at = |line: u32, needle: &str| {
        assert!(
            located
                .iter()
                .any(|l| l.starts_with(&format!("s.moos:{line}:")) && l.contains(needle)),
            "no error at line {line} with `{needle}`: {located:?}"
        )
    };
    at(
        3,
        "rule `leak: LEAK = true -> surface_disarm`: bad operator",
    );
    at(4, "unknown parameter `colour`");
    at(5, "surface_depth = -1");
    at(7, "rule `NAV` is defined twice");
    at(8, "direct or helm");
    at(9, "VAR=VALUE");
    assert!(
        located.iter().any(|l| l.contains("no `return_flag`")),
        "{located:?}"
    );
    assert_eq!(errors.len(), 7, "{located:?}");
    // The rule that could be read is kept.
    assert_eq!(c.rules.len(), 1);
    assert_eq!(c.rules[0].name, "nav");

    let (_, errors) =
        SafetyConfig::from_block(&block("ProcessConfig = pSafety\n{\n  AppTick = 4\n}\n"));
    assert_eq!(errors.len(), 1);
    assert!(
        errors[0].located().contains("no `rule =` line"),
        "{errors:?}"
    );
}
