//! Structural snapshots of four complete corpus missions: s1_alpha and s4_delta.

use mission::bhv::{BehaviorFile, parse_bhv};
use mission::condition::{Condition, Operand, RelOp};
use mission::moos::{MissionFile, parse_moos};
use mission::nsplug::{Options, preprocess};
use mission::source::FsSource;

fn load_moos(rel: &str) -> MissionFile {
    let pre = preprocess(&FsSource, &test_support::mission_file(rel), &Options::new())
        .expect("preprocess");
    let parsed = parse_moos(&pre.source);
    assert!(parsed.diagnostics.is_empty(), "{:?}", parsed.diagnostics);
    parsed.value
}

fn load_bhv(rel: &str) -> BehaviorFile {
    let pre = preprocess(&FsSource, &test_support::mission_file(rel), &Options::new())
        .expect("preprocess");
    let parsed = parse_bhv(&pre.source);
    assert!(parsed.diagnostics.is_empty(), "{:?}", parsed.diagnostics);
    parsed.value
}

fn names(m: &MissionFile) -> Vec<&str> {
    m.processes.iter().map(|p| p.name.as_str()).collect()
}

fn cmp(var: &str, op: RelOp, rhs: Operand) -> Condition {
    Condition::Compare {
        lhs: Operand::Var(var.into()),
        op,
        rhs,
    }
}

fn s(v: &str) -> Operand {
    Operand::Str(v.into())
}

/// (kind, name, keys in order) of every behaviour.
fn shape(b: &BehaviorFile) -> Vec<(String, String, Vec<String>)> {
    b.behaviors
        .iter()
        .map(|s| {
            (
                s.kind.clone(),
                s.name().unwrap_or("").to_string(),
                s.params.iter().map(|p| p.key.clone()).collect(),
            )
        })
        .collect()
}

#[test]
fn alpha_moos_structure() {
    let m = load_moos("s1_alpha/alpha.moos");
    let g: Vec<(&str, &str)> = m
        .globals
        .iter()
        .map(|p| (p.key.as_str(), p.value.as_str()))
        .collect();
    assert_eq!(
        g,
        [
            ("ServerHost", "localhost"),
            ("ServerPort", "9000"),
            ("Community", "alpha"),
            ("MOOSTimeWarp", "1"),
            ("LatOrigin", "43.825300"),
            ("LongOrigin", "-70.330400"),
        ]
    );
    assert_eq!(m.global("latorigin"), Some("43.825300"));
    assert_eq!(
        names(&m),
        [
            "ANTLER",
            "pLogger",
            "uProcessWatch",
            "uSimMarineV22",
            "pHelmIvP",
            "pMarinePIDV22",
            "pMarineViewer",
            "pNodeReporter"
        ]
    );
    let runs = m.antler_runs();
    let apps: Vec<&str> = runs.iter().map(|r| r.app.as_str()).collect();
    assert_eq!(
        apps,
        [
            "MOOSDB",
            "pLogger",
            "uSimMarineV22",
            "pMarinePIDV22",
            "pHelmIvP",
            "pMarineViewer",
            "uProcessWatch",
            "pNodeReporter",
            "pRealm"
        ]
    );
    assert!(
        runs.iter()
            .all(|r| r.option("NewConsole") == Some("false") && r.alias.is_none())
    );
    assert_eq!(runs[0].span.line, 25);
    let helm = m.process("phelmivp").unwrap();
    assert_eq!(helm.get("Behaviors"), Some("alpha.bhv"));
    assert_eq!(
        helm.get_all("domain").collect::<Vec<_>>(),
        ["course:0:359:360", "speed:0:4:41"]
    );
    let sim = m.process("uSimMarineV22").unwrap();
    assert_eq!(
        sim.get("start_pos"),
        Some("x=0, y=-20, heading=180, speed=0")
    );
    assert_eq!(sim.get("turn_spd_loss"), Some("0.4"));
    let log = m.process("pLogger").unwrap();
    assert_eq!(
        log.get_all("wildcardomitpattern").collect::<Vec<_>>(),
        ["*_STATUS", "DB_VARSUMMARY", "DB_RWSUMMARY"]
    );
    let viewer = m.process("pMarineViewer").unwrap();
    // Commented-out lines are not entries; `//` inside a value would be cut.
    assert_eq!(viewer.get("tiff_file"), Some("forrest19.tif"));
    assert_eq!(viewer.get_all("right_context[return]").count(), 3);
    assert_eq!(
        viewer.get("action+"),
        Some("MENU_KEY=deploy # MOOS_MANUAL_OVERRIDE=false")
    );
}

#[test]
fn alpha_bhv_structure() {
    let b = load_bhv("s1_alpha/alpha.bhv");
    let inits: Vec<(&str, &str, bool)> = b
        .initializes
        .iter()
        .map(|i| (i.var.as_str(), i.value.as_str(), i.deferred))
        .collect();
    assert_eq!(
        inits,
        [("DEPLOY", "false", false), ("RETURN", "false", false)]
    );
    assert!(b.modes.is_empty());
    let sh = shape(&b);
    let kinds: Vec<(&str, &str)> = sh
        .iter()
        .map(|(k, n, _)| (k.as_str(), n.as_str()))
        .collect();
    assert_eq!(
        kinds,
        [
            ("BHV_Waypoint", "waypt_survey"),
            ("BHV_Waypoint", "waypt_return"),
            ("BHV_ConstantSpeed", "const_speed")
        ]
    );
    assert_eq!(
        sh[1].2,
        [
            "name",
            "pwt",
            "condition",
            "condition",
            "perpetual",
            "updates",
            "endflag",
            "endflag",
            "endflag",
            "speed",
            "capture_radius",
            "slip_radius",
            "points"
        ]
    );
    assert_eq!(
        sh[2].2,
        [
            "name",
            "pwt",
            "condition",
            "condition",
            "perpetual",
            "updates",
            "endflag",
            "speed",
            "duration",
            "duration_reset"
        ]
    );
    let survey = &b.behaviors[0];
    assert_eq!(survey.params.len(), 36);
    assert_eq!(survey.get("speed"), Some("3"), "trailing comment cut");
    // Behaviour macros stay text, even through nsplug.
    assert_eq!(survey.get_all("wptflag").nth(1), Some("NEXT=$(NX),$(NY)"));
    assert_eq!(survey.get("endflag"), Some("RETURN = true"));
    assert_eq!(
        survey.get_all("endflag").nth(1),
        Some("SUMMARY=speed=$[SPEED],time=$[DUR_RUN_TIME]")
    );
    assert_eq!(
        survey.get("polygon"),
        Some("60,-40:60,-160:150,-160:180,-100:150,-40")
    );
    let conds: Vec<&Condition> = survey.conditions.iter().map(|c| &c.condition).collect();
    assert_eq!(
        conds,
        [
            &cmp("RETURN", RelOp::Eq, s("false")),
            &cmp("DEPLOY", RelOp::Eq, s("true"))
        ]
    );
    assert_eq!(
        b.behaviors[2].conditions[0].condition,
        cmp("SPD", RelOp::Eq, s("true"))
    );
    assert_eq!(b.behaviors[2].span.line, 76);
}

#[test]
fn delta_moos_structure() {
    let m = load_moos("s4_delta/delta.moos");
    assert_eq!(m.global("Community"), Some("henry"));
    assert_eq!(
        names(&m),
        [
            "ANTLER",
            "uProcessWatch",
            "pLogger",
            "uSimMarine",
            "pHelmIvP",
            "pMarinePID",
            "pMarineViewer",
            "pNodeReporter",
            "uTimerScript"
        ]
    );
    assert_eq!(m.antler_runs().len(), 9);
    assert_eq!(m.antler_runs()[7].moos_name(), "uTimerScript");
    let helm = m.process("pHelmIvP").unwrap();
    assert_eq!(
        helm.get_all("domain").collect::<Vec<_>>(),
        ["course:0:359:360", "speed:0:4:41", "depth:0:199:200"]
    );
    assert_eq!(helm.get("verbose"), Some("quiet"));
    let log = m.process("pLogger").unwrap();
    assert_eq!(log.get("SyncLog"), Some("true @ 0.2"));
    let timer = m.process("uTimerScript").unwrap();
    assert_eq!(timer.get("condition"), Some("TIME_AT_SURFACE > 3"));
    // `$(COUNT)` is a uTimerScript macro: nsplug leaves it (with a warning) and so does the parser.
    assert_eq!(
        timer.get("event"),
        Some("var=GPS_UPDATE_RECEIVED, val=\"RCVD_$(COUNT)\", time=0.5:1.0")
    );
    let viewer = m.process("pMarineViewer").unwrap();
    assert_eq!(
        viewer.get_all("button_two").collect::<Vec<_>>(),
        [
            "MOOS_MANUAL_OVERRIDE=false # RETURN=false",
            "RETURN # RETURN=true"
        ]
    );
}

#[test]
fn delta_bhv_structure() {
    let b = load_bhv("s4_delta/delta.bhv");
    let inits: Vec<&str> = b.initializes.iter().map(|i| i.var.as_str()).collect();
    assert_eq!(inits, ["DEPLOY", "RETURN", "SURVEY", "PSURFACE"]);
    type ModeShape<'a> = (&'a str, &'a str, Option<&'a str>, Option<&'a str>, usize);
    let modes: Vec<ModeShape<'_>> = b
        .modes
        .iter()
        .map(|m| {
            (
                m.var.as_str(),
                m.value.as_str(),
                m.else_value.as_deref(),
                m.parent(),
                m.conditions.len(),
            )
        })
        .collect();
    assert_eq!(
        modes,
        [
            ("MODE", "ACTIVE", Some("INACTIVE"), None, 1),
            ("MODE", "LOITERING", None, Some("ACTIVE"), 3),
            ("MODE", "RETURNING", Some("SURVEYING"), Some("ACTIVE"), 2),
        ]
    );
    assert_eq!(
        b.modes[1].conditions[1].condition,
        cmp("RETURN", RelOp::Ne, s("true"))
    );
    assert_eq!(b.modes[0].span.line, 19, "`Set` is case-insensitive");
    let sh = shape(&b);
    let kinds: Vec<(&str, &str)> = sh
        .iter()
        .map(|(k, n, _)| (k.as_str(), n.as_str()))
        .collect();
    assert_eq!(
        kinds,
        [
            ("BHV_MaxDepth", "maxdepth"),
            ("BHV_Loiter", "loiter"),
            ("BHV_Waypoint", "waypt_return"),
            ("BHV_PeriodicSurface", "bhv_periodic_surface"),
            ("BHV_ConstantDepth", "bhv_const_depth"),
            ("BHV_Waypoint", "waypt_survey"),
        ]
    );
    assert_eq!(
        sh[0].2,
        [
            "name",
            "pwt",
            "condition",
            "max_depth",
            "tolerance",
            "duration"
        ]
    );
    assert_eq!(
        b.behaviors[0].conditions[0].condition,
        cmp("MODE", RelOp::FieldEq, s("ACTIVE"))
    );
    assert_eq!(
        b.behaviors[1].get("polygon"),
        Some("radial:: x=20, y=-80, radius=20, pts=8, snap=1, label=DUDLEY_LOITER")
    );
    let ps = &b.behaviors[3];
    let conds: Vec<&Condition> = ps.conditions.iter().map(|c| &c.condition).collect();
    assert_eq!(
        conds,
        [
            &cmp("MODE", RelOp::FieldEq, s("LOITERING")),
            &cmp("PSURFACE", RelOp::Eq, s("true"))
        ]
    );
    // The commented-out `points` line is not a parameter.
    assert_eq!(b.behaviors[5].get_all("points").count(), 1);
    assert_eq!(b.behaviors[5].get("repeat"), Some("10"));
}
