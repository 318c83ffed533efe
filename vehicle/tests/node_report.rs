//! NODE_REPORT_LOCAL strings, character for character.

mod common;

use vehicle::ValueRef;
use vehicle::moos::last_posting;
use vehicle::node_report::{NodeReportConfig, NodeReporter};

fn report(out: &[vehicle::Posting]) -> String {
    last_posting(out, "NODE_REPORT_LOCAL")
        .expect("no report")
        .as_str()
        .unwrap()
        .to_string()
}

fn d(app: &mut NodeReporter, var: &str, v: f64, t: f64) {
    app.on_mail(var, ValueRef::Double(v), t);
}

fn s(app: &mut NodeReporter, var: &str, v: &str, t: f64) {
    app.on_mail(var, ValueRef::String(v), t);
}

#[test]
fn kayak_without_helm() {
    let cfg =
        NodeReportConfig::from_params([("platform_type", "kayak"), ("platform_color", "yellow")])
            .unwrap();
    let mut app = NodeReporter::new(cfg, "alpha", 1000.0);
    d(&mut app, "NAV_X", 10.0, 1000.0);
    d(&mut app, "NAV_Y", -20.5, 1000.0);
    d(&mut app, "NAV_SPEED", 1.2, 1000.0);
    d(&mut app, "NAV_HEADING", 180.0, 1000.0);
    d(&mut app, "NAV_DEPTH", 0.0, 1000.0);
    let mut out = Vec::new();
    app.iterate(1001.25, &mut out);
    let expected = "NAME=alpha,X=10,Y=-20.5,SPD=1.2,HDG=180,DEP=0,TYPE=kayak,COLOR=yellow,\
                    MODE=NOHELM-EVER,ALLSTOP=unknown,TIME=1001.25,LENGTH=4";
    assert_eq!(report(&out), expected);
    assert_eq!(
        last_posting(&out, "NODE_REPORT_LOCAL_FIRST")
            .unwrap()
            .as_str(),
        Some(expected)
    );
    assert_eq!(
        last_posting(&out, "PNR_POST_GAP").unwrap().as_f64(),
        Some(0.0)
    );
}

#[test]
fn uuv_driving_with_modes_lat_lon_yaw_and_index() {
    let cfg = NodeReportConfig::from_params([
        ("vessel_type", "UUV"),
        ("platform_length", "3.5"),
        ("platform_group", "red"),
    ])
    .unwrap();
    let mut app = NodeReporter::new(cfg, "henry", 0.0);
    let t = 5000.0;
    d(&mut app, "NAV_X", -4.934, t);
    d(&mut app, "NAV_Y", -96.0512, t);
    d(&mut app, "NAV_LAT", 43.824434651, t);
    d(&mut app, "NAV_LONG", -70.330442139, t);
    d(&mut app, "NAV_SPEED", 2.0, t);
    d(&mut app, "NAV_HEADING", -315.0, t); // wrapped to 45
    d(&mut app, "NAV_DEPTH", 12.345, t);
    d(&mut app, "NAV_YAW", 0.785, t);
    s(&mut app, "IVPHELM_STATE", "DRIVE", t);
    s(
        &mut app,
        "IVPHELM_SUMMARY",
        "iter=12,utc_time=5000,modes=MODE@ACTIVE:SURVEYING,var=x",
        t,
    );
    s(&mut app, "IVPHELM_ALLSTOP", "clear", t);
    let mut out = Vec::new();
    app.iterate(t + 1.0, &mut out);
    out.clear();
    app.iterate(t + 2.0, &mut out);
    let expected = "NAME=henry,X=-4.93,Y=-96.05,SPD=2,HDG=45,DEP=12.35,LAT=43.82443465,LON=-70.33044214,\
                    TYPE=UUV,GROUP=red,MODE=MODE@ACTIVE:SURVEYING,ALLSTOP=clear,INDEX=1,YAW=0.7853982,\
                    TIME=5002,LENGTH=3.5";
    assert_eq!(report(&out), expected);
    assert!(last_posting(&out, "NODE_REPORT_LOCAL_FIRST").is_none());
    assert_eq!(
        last_posting(&out, "PNR_POST_GAP").unwrap().as_f64(),
        Some(1.0)
    );
}

#[test]
fn helm_gone_quiet_park_and_terse_global() {
    let cfg =
        NodeReportConfig::from_params([("terse_reports", "true"), ("coord_policy_global", "true")])
            .unwrap();
    let mut app = NodeReporter::new(cfg, "abe", 0.0);
    d(&mut app, "NAV_LAT", 0.5, 100.0);
    d(&mut app, "NAV_LONG", -0.25, 100.0);
    d(&mut app, "NAV_X", 1.0, 100.0);
    d(&mut app, "NAV_Y", 2.0, 100.0);
    d(&mut app, "NAV_SPEED", 0.0, 100.0);
    d(&mut app, "NAV_HEADING", 359.996, 100.0);
    d(&mut app, "NAV_DEPTH", 3.0, 100.0);
    d(&mut app, "NAV_YAW", 1.0, 100.0);
    s(&mut app, "IVPHELM_STATE", "PARK", 100.0);
    let mut out = Vec::new();
    app.iterate(102.0, &mut out);
    // Helm fresh, PARK: the modes of a summary only replace DRIVE.
    let expected = "NAME=abe,SPD=0,HDG=360,LAT=0.5,LON=-0.25,TYPE=unknown,MODE=PARK,ALLSTOP=unknown,\
                    TIME=102,LENGTH=0";
    assert_eq!(report(&out), expected);
    out.clear();
    // 7.4 s after the last helm message: NOHELM-7.
    app.iterate(107.4, &mut out);
    assert!(report(&out).contains(",MODE=NOHELM-7,"), "{}", report(&out));
}

/// A reporter with position, speed and heading known at `t`.
fn with_nav(cfg: NodeReportConfig, t: f64) -> NodeReporter {
    let mut app = NodeReporter::new(cfg, "ben", 0.0);
    for (v, x) in [
        ("NAV_X", 0.0),
        ("NAV_Y", 0.0),
        ("NAV_SPEED", 0.0),
        ("NAV_HEADING", 0.0),
    ] {
        d(&mut app, v, x, t);
    }
    app
}

#[test]
fn waits_for_nav_and_the_blackout_holds_only_until_the_first_report() {
    let cfg =
        NodeReportConfig::from_params([("blackout_interval", "5"), ("node_report_output", "NR")])
            .unwrap();
    let mut app = NodeReporter::new(cfg, "ben", 0.0);
    let mut out = Vec::new();
    app.iterate(1.0, &mut out);
    assert!(out.is_empty(), "no position yet");
    d(&mut app, "NAV_X", 0.0, 1.0);
    d(&mut app, "NAV_Y", 0.0, 1.0);
    d(&mut app, "NAV_SPEED", 0.0, 1.0);
    d(&mut app, "NAV_HEADING", 0.0, 1.0);
    app.iterate(2.0, &mut out);
    assert!(last_posting(&out, "NR").is_some());
    // pNodeReporter at a2a9b716 resets the blackout after each report to a base value no
    // parameter sets (0): the next iteration reports again.
    out.clear();
    app.iterate(2.25, &mut out);
    let r = last_posting(&out, "NR").expect("reported again");
    assert!(r.as_str().unwrap().contains("INDEX=1"), "{r:?}");
}

#[test]
fn blackout_variance_draws_each_next_blackout_from_minus_to_plus_the_variance() {
    let cfg = NodeReportConfig::from_params([("blackout_variance", "2")]).unwrap();
    let mut app = with_nav(cfg, 0.0);
    let (mut out, mut gaps) = (Vec::new(), Vec::new());
    for i in 0..400 {
        out.clear();
        app.iterate(1.0 + f64::from(i) * 0.25, &mut out);
        if let Some(g) = last_posting(&out, "PNR_POST_GAP").and_then(|v| v.as_f64()) {
            gaps.push(g);
        }
    }
    // A report is held while the gap is within the drawn blackout (< 2 s): every gap after
    // the first is one tick (a draw of 0, half the time) up to just over 2 s.
    assert!(gaps.len() > 100, "{}", gaps.len());
    assert!(
        gaps[1..].iter().all(|g| *g >= 0.25 && *g <= 2.25),
        "{gaps:?}"
    );
    assert!(
        gaps.iter().filter(|g| **g == 0.25).count() > gaps.len() / 3,
        "{gaps:?}"
    );
    assert!(gaps.iter().any(|g| *g > 1.0), "{gaps:?}");
}

#[test]
fn reads_real_mission_blocks() {
    let text = test_support::mission_text("s7_golf/golf.moos");
    let block = common::process_config(&text, "pNodeReporter");
    let cfg = NodeReportConfig::from_params(common::pairs(&block)).unwrap();
    assert_eq!(cfg.platform_type, "UUV");
    let name = common::global(&text, "Community").unwrap();
    let mut app = NodeReporter::new(cfg, &name, 0.0);
    for (v, x) in [
        ("NAV_X", 1.0),
        ("NAV_Y", 2.0),
        ("NAV_SPEED", 0.5),
        ("NAV_HEADING", 90.0),
    ] {
        d(&mut app, v, x, 0.0);
    }
    let mut out = Vec::new();
    app.iterate(3.0, &mut out);
    assert_eq!(
        report(&out),
        "NAME=henry,X=1,Y=2,SPD=0.5,HDG=90,TYPE=UUV,MODE=NOHELM-EVER,ALLSTOP=unknown,TIME=3,LENGTH=4"
    );
    assert!(NodeReportConfig::from_params([("platform_length", "-1")]).is_err());
}

#[test]
fn heading_error_and_course_over_ground() {
    let cfg = NodeReportConfig::from_params([
        ("platform_type", "kayak"),
        ("hdg_error", "15"),
        ("report_cog", "true"),
    ])
    .unwrap();
    assert!(
        NodeReportConfig::from_params([("hdg_error", "0")]).is_err(),
        "must be > 0"
    );
    let mut app = NodeReporter::new(cfg, "abe", 0.0);
    let nav = |app: &mut NodeReporter, x: f64, y: f64, t: f64| {
        d(app, "NAV_X", x, t);
        d(app, "NAV_Y", y, t);
        d(app, "NAV_SPEED", 1.0, t);
        d(app, "NAV_HEADING", 350.0, t);
    };
    nav(&mut app, 0.0, 0.0, 0.0);
    let mut out = Vec::new();
    app.iterate(1.0, &mut out);
    // The heading is reported with the error (350 + 15 = 5); no COG before two positions.
    let first = report(&out);
    assert!(
        first.contains(",HDG=5,") && !first.contains("COG"),
        "{first}"
    );
    // Moving north-east: the COG of the step appears from the next report on.
    nav(&mut app, 10.0, 10.0, 2.0);
    out.clear();
    app.iterate(2.0, &mut out);
    assert!(!report(&out).contains("COG"), "{}", report(&out));
    out.clear();
    app.iterate(3.0, &mut out);
    assert!(report(&out).contains(",HDG=5,COG=45,"), "{}", report(&out));
}

#[test]
fn vsource_and_aspects_in_the_report() {
    let cfg = NodeReportConfig::from_params([
        ("platform_type", "kayak"),
        ("group", "blue"),
        ("vsource", "gps"),
        ("platform_aspect", "zeta=1"),
        ("platform_aspect", "alpha=two"),
    ])
    .unwrap();
    assert!(NodeReportConfig::from_params([("platform_aspect", "a=b=c")]).is_err());
    assert!(NodeReportConfig::from_params([("platform_aspect", "=b")]).is_err());
    let mut app = NodeReporter::new(cfg, "abe", 0.0);
    d(&mut app, "NAV_X", 1.0, 0.0);
    d(&mut app, "NAV_Y", 2.0, 0.0);
    let mut out = Vec::new();
    app.iterate(1.0, &mut out);
    let r = report(&out);
    assert!(r.contains(",GROUP=blue,VSOURCE=gps,"), "{r}");
    assert!(
        r.ends_with(",alpha=two,zeta=1"),
        "properties in key order: {r}"
    );
}

#[test]
fn mission_hash_odometer_posts_the_growing_extent() {
    let cfg = NodeReportConfig::from_params([("platform_type", "kayak")]).unwrap();
    let mut app = NodeReporter::new(cfg, "abe", 0.0);
    assert!(NodeReporter::subscriptions().contains(&"MISSION_HASH"));
    let mut posted = Vec::new();
    let mut step = |app: &mut NodeReporter, x: f64, y: f64, t: f64| {
        d(app, "NAV_X", x, t);
        d(app, "NAV_Y", y, t);
        let mut out = Vec::new();
        app.iterate(t, &mut out);
        if let Some(p) = last_posting(&out, "PNR_MHASH") {
            posted.push(p.as_str().unwrap().to_string());
        }
    };
    // Nothing before a mission hash is known.
    step(&mut app, 50.0, 0.0, 1.0);
    s(
        &mut app,
        "MISSION_HASH",
        "mhash=ABC-123,utc=1786000000",
        1.5,
    );
    step(&mut app, 50.0, 0.0, 2.0);
    step(&mut app, 50.5, 0.0, 3.0); // 0.5 m: under the 1 m step
    step(&mut app, 53.0, 4.0, 4.0); // 5 m from the start
    step(&mut app, 53.05, 4.0, 5.0); // not 2 % more
    step(&mut app, 60.0, 0.0, 6.0); // 10 m
    assert_eq!(posted, ["mhash=ABC-123,ext=5", "mhash=ABC-123,ext=10"]);
}

#[test]
fn riders_follow_their_policies_with_the_cpp_quirks() {
    let cfg = NodeReportConfig::from_params([
        ("platform_type", "kayak"),
        ("rider", "var=LEG_ID, policy=always, rfld=LEG"),
        ("rider", "var=BATT, policy=updated"),
        ("rider", "var=TEMP, policy=5, prec=1"),
    ])
    .unwrap();
    for bad in [
        "var=X",
        "var=A, policy=sometimes",
        "var=A, rfld=a-b",
        "var=A, color=red",
        "var=A, prec=-1",
    ] {
        assert!(
            NodeReportConfig::from_params([("rider", bad)]).is_err(),
            "{bad}"
        );
    }
    assert!(
        NodeReportConfig::from_params([("rider", "var=A"), ("rider", "var=A, policy=updated")])
            .is_err(),
        "one rider per variable"
    );
    let mut app = NodeReporter::new(cfg, "abe", 0.0);
    assert_eq!(
        app.rider_vars().collect::<Vec<_>>(),
        ["LEG_ID", "BATT", "TEMP"]
    );
    d(&mut app, "NAV_X", 1.0, 0.0);
    d(&mut app, "NAV_Y", 2.0, 0.0);
    s(&mut app, "LEG_ID", "leg_3", 0.5);
    d(&mut app, "BATT", 12.345_67, 0.5);
    d(&mut app, "TEMP", 20.26, 0.5);
    let mut out = Vec::new();
    app.iterate(1.0, &mut out);
    // TEMP (every 5 s) has nothing to say yet: MOOS leaves the comma.
    assert!(
        report(&out).ends_with(",LENGTH=4,LEG=leg_3,BATT=12.3457,"),
        "{}",
        report(&out)
    );
    out.clear();
    app.iterate(6.0, &mut out);
    // BATT is no longer fresh; TEMP's period has passed.
    assert!(
        report(&out).ends_with(",LENGTH=4,LEG=leg_3,,TEMP=20.3"),
        "{}",
        report(&out)
    );
}

#[test]
fn json_reports_replace_or_join_the_usual_report() {
    let nav = |app: &mut NodeReporter| {
        d(app, "NAV_X", 1.5, 0.0);
        d(app, "NAV_Y", 2.0, 0.0);
    };
    // `true`: the report variable carries JSON.
    let cfg = NodeReportConfig::from_params([("platform_type", "kayak"), ("json_report", "true")])
        .unwrap();
    let mut app = NodeReporter::new(cfg, "abe", 0.0);
    nav(&mut app);
    let mut out = Vec::new();
    app.iterate(1.0, &mut out);
    let r = report(&out);
    assert!(
        r.starts_with(r#"{"NAME":"abe","X":1.5,"Y":2,"TYPE":"kayak","#),
        "{r}"
    );
    assert_eq!(
        last_posting(&out, "NODE_REPORT_LOCAL_FIRST")
            .unwrap()
            .as_str(),
        Some(r.as_str())
    );
    // A variable: JSON there, the usual report as before.
    let cfg =
        NodeReportConfig::from_params([("platform_type", "kayak"), ("json_report", "NR_JSON")])
            .unwrap();
    let mut app = NodeReporter::new(cfg, "abe", 0.0);
    nav(&mut app);
    let mut out = Vec::new();
    app.iterate(1.0, &mut out);
    assert!(report(&out).starts_with("NAME=abe,X=1.5,Y=2,"));
    let j = last_posting(&out, "NR_JSON")
        .unwrap()
        .as_str()
        .unwrap()
        .to_string();
    assert!(j.starts_with(r#"{"NAME":"abe""#), "{j}");
    assert!(last_posting(&out, "NR_JSON_FIRST").is_some());
    // `false` is none.
    let cfg = NodeReportConfig::from_params([("json_report", "false")]).unwrap();
    assert!(cfg.json_report.is_empty());
}

#[test]
fn cross_fill_policies_fill_positions_from_the_mission_origin() {
    use vehicle::geodesy::LocalGrid;
    let grid = LocalGrid::new(43.8253, -70.3304).unwrap();
    let (lat, lon) = grid.to_latlon(100.0, 200.0).unwrap();
    let run = |policy: &str, mail: &[(&str, f64)]| -> String {
        let cfg = NodeReportConfig::from_params([
            ("platform_type", "kayak"),
            ("cross_fill_policy", policy),
        ])
        .unwrap();
        let mut app = NodeReporter::new(cfg, "abe", 0.0).with_grid(Some(grid.clone()));
        for (i, (var, v)) in mail.iter().enumerate() {
            d(&mut app, var, *v, i as f64);
        }
        let mut out = Vec::new();
        app.iterate(10.0, &mut out);
        report(&out)
    };
    // global: X/Y from LAT/LON.
    let r = run("global", &[("NAV_LAT", lat), ("NAV_LONG", lon)]);
    assert!(r.starts_with("NAME=abe,X=100,Y=200,"), "{r}");
    // local: LAT/LON from X/Y (8 decimals).
    let r = run("local", &[("NAV_X", 100.0), ("NAV_Y", 200.0)]);
    assert!(
        r.contains(format!(",LAT={lat:.8}").trim_end_matches('0')),
        "{r}"
    );
    // fill_empty (underscore read as dash): only the pair never received.
    let r = run("fill_empty", &[("NAV_X", 100.0), ("NAV_Y", 200.0)]);
    assert!(r.contains(",LAT="), "{r}");
    // use-latest: the staler pair (X/Y here, older) comes from the fresher one.
    let r = run(
        "use-latest",
        &[
            ("NAV_X", 1.0),
            ("NAV_Y", 1.0),
            ("NAV_LAT", lat),
            ("NAV_LONG", lon),
        ],
    );
    assert!(r.starts_with("NAME=abe,X=100,Y=200,"), "{r}");
    // literal: as received.
    let r = run("literal", &[("NAV_X", 1.0), ("NAV_Y", 1.0)]);
    assert!(!r.contains("LAT="), "{r}");
    assert!(NodeReportConfig::from_params([("cross_fill_policy", "sometimes")]).is_err());
}

/// Every posting of `var`, as text (numbers in `{}` form).
fn all_of(out: &[vehicle::Posting], var: &str) -> Vec<String> {
    out.iter()
        .filter(|p| &*p.key == var)
        .map(|p| match (p.value.as_str(), p.value.as_f64()) {
            (Some(s), _) => s.to_string(),
            (None, Some(x)) => x.to_string(),
            _ => String::new(),
        })
        .collect()
}

#[test]
fn platform_reports_follow_changes_gaps_and_aliases() {
    let cfg = NodeReportConfig::from_params([
        ("plat_report_input", "BATT_V, gap=2"),
        ("plat_report_var", "MODEM_STATE, alias=MODEM"),
        ("platform_variable", "BATT_V"), // a repeat: ignored, as MOOS does
        ("plat_report_output", "PLAT_OUT"),
    ])
    .unwrap();
    assert_eq!(cfg.plat_vars.len(), 2);
    let mut app = with_nav(cfg, 100.0);
    assert!(app.extra_subscriptions().iter().any(|v| v == "MODEM_STATE"));
    let mut out = Vec::new();
    app.iterate(101.0, &mut out);
    assert!(all_of(&out, "PLAT_OUT").is_empty(), "nothing received yet");
    d(&mut app, "BATT_V", 12.500000001, 101.5);
    s(&mut app, "MODEM_STATE", "idle", 101.5);
    out.clear();
    app.iterate(102.0, &mut out);
    // Doubles as doubleToString(v, 8) compacted; utc_time with 5 decimals.
    assert_eq!(
        all_of(&out, "PLAT_OUT"),
        ["platform=ben,utc_time=102.00000,BATT_V=12.5,MODEM=idle"]
    );
    // Unchanged: nothing. BATT_V changes again 0.5 s later: held by its 2 s gap, MODEM not.
    out.clear();
    app.iterate(102.25, &mut out);
    assert!(all_of(&out, "PLAT_OUT").is_empty());
    d(&mut app, "BATT_V", 12.4, 102.4);
    s(&mut app, "MODEM_STATE", "busy", 102.4);
    out.clear();
    app.iterate(102.5, &mut out);
    assert_eq!(
        all_of(&out, "PLAT_OUT"),
        ["platform=ben,utc_time=102.50000,MODEM=busy"]
    );
    out.clear();
    app.iterate(104.25, &mut out);
    assert_eq!(
        all_of(&out, "PLAT_OUT"),
        ["platform=ben,utc_time=104.25000,BATT_V=12.4"]
    );
    // Paused (PNR_PAUSE): no platform report either.
    s(&mut app, "PNR_PAUSE", "true", 105.0);
    d(&mut app, "BATT_V", 12.3, 105.0);
    out.clear();
    app.iterate(107.0, &mut out);
    assert!(all_of(&out, "PLAT_OUT").is_empty());
    assert!(all_of(&out, "NODE_REPORT_LOCAL").is_empty());
}

#[test]
fn alternative_nav_reports_ride_in_the_same_variable_while_fresh() {
    let cfg = NodeReportConfig::from_params([
        ("alt_nav_prefix", "NAV_GT"),
        ("alt_nav_group", "truth"),
        ("platform_group", "blue"),
    ])
    .unwrap();
    assert_eq!(cfg.alt_nav_prefix, "NAV_GT_", "`_` appended");
    let mut app = with_nav(cfg, 0.0);
    assert!(
        app.extra_subscriptions()
            .iter()
            .any(|v| v == "NAV_GT_HEADING")
    );
    let mut out = Vec::new();
    app.iterate(1.0, &mut out);
    assert_eq!(
        all_of(&out, "NODE_REPORT_LOCAL").len(),
        1,
        "no GT record yet"
    );
    for (v, x) in [
        ("NAV_GT_X", 3.0),
        ("NAV_GT_Y", 4.0),
        ("NAV_GT_SPEED", 1.0),
        ("NAV_GT_HEADING", 90.0),
    ] {
        d(&mut app, v, x, 1.5);
    }
    out.clear();
    app.iterate(2.0, &mut out);
    let reports = all_of(&out, "NODE_REPORT_LOCAL");
    assert_eq!(reports.len(), 2, "{reports:?}");
    assert!(
        reports[0].starts_with("NAME=ben,X=0,Y=0,"),
        "{}",
        reports[0]
    );
    assert!(reports[0].contains(",GROUP=blue,"), "{}", reports[0]);
    // `<name>_GT` (alt_nav_name `_GT`), its own position and group; the index after the
    // primary report's increment.
    let gt = &reports[1];
    assert!(gt.starts_with("NAME=ben_GT,X=3,Y=4,SPD=1,HDG=90,"), "{gt}");
    assert!(
        gt.contains(",GROUP=truth,") && gt.contains(",INDEX=2,"),
        "{gt}"
    );
    // 5 s without a GT variable: the GT report stops.
    out.clear();
    app.iterate(6.5, &mut out);
    assert_eq!(all_of(&out, "NODE_REPORT_LOCAL").len(), 1);
    // A name without `_` is the name itself.
    let cfg = NodeReportConfig::from_params([("alt_nav_prefix", "GT_"), ("alt_nav_name", "ghost")])
        .unwrap();
    let mut app = with_nav(cfg, 0.0);
    d(&mut app, "GT_X", 1.0, 0.5);
    out.clear();
    app.iterate(1.0, &mut out);
    assert!(all_of(&out, "NODE_REPORT_LOCAL")[1].starts_with("NAME=ghost,X=1,"));
}

#[test]
fn extrapolation_prunes_reports_a_receiver_could_predict() {
    let cfg = NodeReportConfig::from_params([("extrap_enabled", "true")]).unwrap();
    let mut app = NodeReporter::new(cfg, "ben", 0.0);
    // Straight east at 2 m/s.
    let nav = |app: &mut NodeReporter, t: f64, x: f64, h: f64| {
        d(app, "NAV_X", x, t);
        d(app, "NAV_Y", 0.0, t);
        d(app, "NAV_SPEED", 2.0, t);
        d(app, "NAV_HEADING", h, t);
    };
    let mut out = Vec::new();
    nav(&mut app, 1.0, 0.0, 90.0);
    app.iterate(1.0, &mut out);
    assert_eq!(all_of(&out, "NODE_REPORT_LOCAL").len(), 1);
    // 1 s later exactly where extrapolation puts it: gaps 0 and 0, pruned.
    nav(&mut app, 2.0, 2.0, 90.0);
    out.clear();
    app.iterate(2.0, &mut out);
    let pos: f64 = all_of(&out, "PNR_EXTRAP_POS_GAP")[0].parse().unwrap();
    assert!(pos < 1e-9, "{pos}");
    assert_eq!(all_of(&out, "PNR_EXTRAP_HDG_GAP"), ["0"]);
    assert!(all_of(&out, "NODE_REPORT_LOCAL").is_empty(), "pruned");
    // 0.3 m off the line (over the 0.25 m threshold): reported.
    nav(&mut app, 3.0, 4.3, 90.0);
    out.clear();
    app.iterate(3.0, &mut out);
    let gap: f64 = all_of(&out, "PNR_EXTRAP_POS_GAP")[0].parse().unwrap();
    assert!((gap - 0.3).abs() < 1e-9, "{gap}");
    assert_eq!(all_of(&out, "NODE_REPORT_LOCAL").len(), 1);
    // On the line but turned 2 degrees (over 1): reported.
    nav(&mut app, 4.0, 6.3, 92.0);
    out.clear();
    app.iterate(4.0, &mut out);
    assert_eq!(all_of(&out, "PNR_EXTRAP_HDG_GAP"), ["2"]);
    assert_eq!(all_of(&out, "NODE_REPORT_LOCAL").len(), 1);
}

#[test]
fn display_settings_helm_threshold_grace_pause_and_colour_changes() {
    let cfg = NodeReportConfig::from_params([
        ("platform_beam", "1.5"),
        ("platform_transparency", "0.3"),
        ("nohelm_threshold", "2"),
        ("nav_grace_period", "0"),
        ("platform_color", "Dark_Green"),
    ])
    .unwrap();
    let mut app = NodeReporter::new(cfg, "ben", 0.0);
    let mut out = Vec::new();
    // nav_grace_period 0: no grace; without nav nothing is reported at all.
    app.iterate(0.5, &mut out);
    assert!(out.is_empty());
    for (v, x) in [
        ("NAV_X", 0.0),
        ("NAV_Y", 0.0),
        ("NAV_SPEED", 0.0),
        ("NAV_HEADING", 0.0),
    ] {
        d(&mut app, v, x, 1.0);
    }
    s(&mut app, "IVPHELM_STATE", "DRIVE", 1.0);
    app.iterate(2.5, &mut out);
    let r = report(&out);
    assert!(
        r.contains(",COLOR=Dark_Green,") && r.contains(",MODE=DRIVE,"),
        "{r}"
    );
    assert!(
        r.contains(",TRANSPARENCY=0.3,") && r.ends_with(",BEAM=1.5"),
        "{r}"
    );
    // nohelm_threshold 2: 3.5 s after the helm's last word, NOHELM-4 (rounded).
    out.clear();
    app.iterate(4.5, &mut out);
    assert!(report(&out).contains(",MODE=NOHELM-4,"), "{}", report(&out));
    // NODE_COLOR_CHANGE is ignored without allow_color_change; PLATFORM_COLOR needs a colour.
    s(&mut app, "NODE_COLOR_CHANGE", "red", 5.0);
    s(&mut app, "PLATFORM_COLOR", "reddish", 5.0);
    out.clear();
    app.iterate(5.0, &mut out);
    assert!(report(&out).contains(",COLOR=Dark_Green,"));
    // paused = true from the block: no reports until PNR_PAUSE = false.
    let cfg = NodeReportConfig::from_params([("paused", "true"), ("allow_color_change", "true")])
        .unwrap();
    let mut app = with_nav(cfg, 0.0);
    out.clear();
    app.iterate(1.0, &mut out);
    assert!(all_of(&out, "NODE_REPORT_LOCAL").is_empty());
    s(&mut app, "PNR_PAUSE", "false", 1.5);
    s(&mut app, "NODE_COLOR_CHANGE", "orange", 1.5);
    app.iterate(2.0, &mut out);
    assert!(report(&out).contains(",COLOR=orange,"), "{}", report(&out));
    // A colour MOOS does not know is a config warning; the PID posting of single-app mode.
    let (_, w) = NodeReportConfig::from_params_lenient([("platform_color", "bluish")]).unwrap();
    assert_eq!(w.len(), 1);
    // PNODEREPORTER_PID: posted by OnStartUp (`Notify(.., getpid())`, a double), not by
    // the iterations.
    let mut app = with_nav(NodeReportConfig::default(), 0.0);
    app.set_pid(4242);
    out.clear();
    app.on_startup(&mut out);
    assert_eq!(out.len(), 1);
    assert_eq!(&*out[0].key, "PNODEREPORTER_PID");
    assert_eq!(out[0].value.as_f64(), Some(4242.0));
    out.clear();
    app.iterate(1.0, &mut out);
    assert!(all_of(&out, "PNODEREPORTER_PID").is_empty(), "once");
}

// ---------------------------------------------------------------------------------------
// Case for case with NodeReporter.cpp at a2a9b716 (expected values worked out from it).

/// A reporter started at 0 with position, speed and heading received at `t`.
fn nav_at(cfg: NodeReportConfig, name: &str, t: f64) -> NodeReporter {
    let mut app = NodeReporter::new(cfg, name, 0.0);
    for (v, x) in [
        ("NAV_X", 0.0),
        ("NAV_Y", 0.0),
        ("NAV_SPEED", 0.0),
        ("NAV_HEADING", 0.0),
    ] {
        d(&mut app, v, x, t);
    }
    app
}

#[test]
fn platform_report_inputs_gaps_aliases_and_numbers() {
    use vehicle::node_report::PlatVar;
    // addPlatformVar: the last piece without `=` names the variable; `gap` any case, below 0
    // is 0; `alias` only in lower case (the C++ lowers a bool, not the key).
    let v = PlatVar::parse("A, gap=2, B").unwrap();
    assert_eq!((v.var.as_str(), v.gap_s), ("B", 2.0));
    assert_eq!(PlatVar::parse("A, GAP=-3").unwrap().gap_s, 0.0);
    assert_eq!(PlatVar::parse("A, ALIAS=Z").unwrap().alias, None);
    assert_eq!(PlatVar::parse("A, alias=Z Z").unwrap().alias, None);
    assert!(PlatVar::parse("A B").is_none());
    let cfg = NodeReportConfig::from_params([
        ("plat_report_input", "DEPTH_ERR, gap=1"),
        ("plat_report_input", "GPS_SAT, alias=SATS"),
    ])
    .unwrap();
    assert_eq!(cfg.plat_report_output, "PLATFORM_REPORT_LOCAL");
    // No navigation at all (past the grace period): no node report, the platform report
    // all the same.
    let mut app = NodeReporter::new(cfg, "ben", 0.0);
    d(&mut app, "DEPTH_ERR", -1e-12, 100.0);
    d(&mut app, "GPS_SAT", 7.0, 100.0);
    let mut out = Vec::new();
    app.iterate(100.5, &mut out);
    assert!(all_of(&out, "NODE_REPORT_LOCAL").is_empty());
    // dstringCompact(doubleToString(v, 8)) keeps the sign of a negative zero.
    assert_eq!(
        all_of(&out, "PLATFORM_REPORT_LOCAL"),
        ["platform=ben,utc_time=100.50000,DEPTH_ERR=-0,SATS=7"]
    );
    // Two changes within DEPTH_ERR's 1 s gap: the latest goes out once the gap has passed
    // (strictly: exactly 1 s later is not enough).
    d(&mut app, "DEPTH_ERR", 0.25, 100.7);
    d(&mut app, "DEPTH_ERR", 0.125, 101.2);
    out.clear();
    app.iterate(101.5, &mut out);
    assert!(all_of(&out, "PLATFORM_REPORT_LOCAL").is_empty());
    out.clear();
    app.iterate(101.75, &mut out);
    assert_eq!(
        all_of(&out, "PLATFORM_REPORT_LOCAL"),
        ["platform=ben,utc_time=101.75000,DEPTH_ERR=0.125"]
    );
    // A string value as it came.
    s(&mut app, "GPS_SAT", "none, lost", 102.0);
    out.clear();
    app.iterate(102.0, &mut out);
    assert_eq!(
        all_of(&out, "PLATFORM_REPORT_LOCAL"),
        ["platform=ben,utc_time=102.00000,SATS=none, lost"]
    );
    // A value received at time 0 counts as never received.
    let cfg = NodeReportConfig::from_params([("plat_report_input", "Z")]).unwrap();
    let mut app = NodeReporter::new(cfg, "ben", 0.0);
    d(&mut app, "Z", 1.0, 0.0);
    out.clear();
    app.iterate(1.0, &mut out);
    assert!(all_of(&out, "PLATFORM_REPORT_LOCAL").is_empty());
    // plat_report_output must be one word.
    let (_, w) =
        NodeReportConfig::from_params_lenient([("plat_report_output", "PLAT OUT")]).unwrap();
    assert_eq!(w.len(), 1);
}

#[test]
fn alternative_nav_report_field_for_field() {
    let cfg = NodeReportConfig::from_params([
        ("platform_type", "kayak"),
        ("platform_color", "red"),
        ("platform_group", "blue"),
        ("platform_transparency", "0.5"),
        ("alt_nav_prefix", "NAV_GT_"),
        ("alt_nav_group", "truth"),
        ("rider", "var=LEG, policy=always"),
        ("rider", "var=BATT, policy=updated"),
    ])
    .unwrap();
    assert_eq!(cfg.alt_nav_prefix, "NAV_GT_", "an ending `_` is kept");
    let mut app = nav_at(cfg, "ben", 90.0);
    s(&mut app, "IVPHELM_STATE", "DRIVE", 99.0);
    s(&mut app, "IVPHELM_SUMMARY", "modes=MODE@ACTIVE", 99.0);
    s(&mut app, "IVPHELM_ALLSTOP", "clear", 99.0);
    s(&mut app, "AUX_MODE", "survey", 99.0);
    s(&mut app, "THRUST_MODE_REVERSE", "TRUE", 99.0);
    d(&mut app, "NAV_TRANSP", 0.9, 99.0);
    s(&mut app, "LEG", "3", 99.0);
    d(&mut app, "BATT", 12.5, 99.0);
    for (v, x) in [
        ("NAV_GT_X", 3.0),
        ("NAV_GT_Y", 4.0),
        ("NAV_GT_SPEED", 1.0),
        ("NAV_GT_HEADING", 450.0),
        ("NAV_GT_DEPTH", 2.0),
        ("NAV_GT_ALTITUDE", 7.0),
        ("NAV_GT_YAW", 1.0),
    ] {
        d(&mut app, v, x, 99.5);
    }
    let mut out = Vec::new();
    app.iterate(100.0, &mut out);
    let reports = all_of(&out, "NODE_REPORT_LOCAL");
    // The vehicle's own report (index 0 unwritten), then the GT record: a copy of the
    // record made at start-up (type, length, colour, transparency) with its own navigation,
    // name and group, no MODE_AUX / THRUST_MODE_REVERSE / NAV_TRANSP, the index after the
    // first report, YAW from its heading, and the riders asked a second time (the updated
    // one has nothing more to say).
    assert_eq!(
        reports,
        [
            "NAME=ben,X=0,Y=0,SPD=0,HDG=0,TYPE=kayak,COLOR=red,GROUP=blue,MODE=MODE@ACTIVE,\
             MODE_AUX=survey,ALLSTOP=clear,THRUST_MODE_REVERSE=true,TIME=100,TRANSPARENCY=0.9,\
             LENGTH=4,LEG=3,BATT=12.5000",
            "NAME=ben_GT,X=3,Y=4,SPD=1,HDG=90,DEP=2,TYPE=kayak,COLOR=red,GROUP=truth,\
             MODE=MODE@ACTIVE,ALLSTOP=clear,ALTITUDE=7,INDEX=1,YAW=0,TIME=100,TRANSPARENCY=0.5,\
             LENGTH=4,LEG=3,"
        ]
    );
    // Only the vehicle's report is the _FIRST one.
    assert_eq!(
        all_of(&out, "NODE_REPORT_LOCAL_FIRST"),
        [reports[0].clone()]
    );
    // Colour and group updates reach both records (the group overrides alt_nav_group).
    s(&mut app, "PLATFORM_COLOR", "orange", 101.0);
    s(&mut app, "NODE_GROUP_UPDATE", "green", 101.0);
    out.clear();
    app.iterate(104.0, &mut out);
    let reports = all_of(&out, "NODE_REPORT_LOCAL");
    assert_eq!(reports.len(), 2);
    assert!(reports[1].contains(",COLOR=orange,GROUP=green,") && reports[1].contains(",INDEX=2,"));
    // Fresh while less than 5 s old: 4.9 s after the update yes, exactly 5 s no.
    d(&mut app, "NAV_GT_X", 5.0, 100.0);
    out.clear();
    app.iterate(104.9, &mut out);
    assert_eq!(all_of(&out, "NODE_REPORT_LOCAL").len(), 2);
    out.clear();
    app.iterate(105.0, &mut out);
    assert_eq!(all_of(&out, "NODE_REPORT_LOCAL").len(), 1);
    // An unknown `<prefix>` variable does not refresh the record.
    d(&mut app, "NAV_GT_PITCH", 1.0, 105.0);
    out.clear();
    app.iterate(105.5, &mut out);
    assert_eq!(all_of(&out, "NODE_REPORT_LOCAL").len(), 1);
    // Paused: neither report.
    s(&mut app, "PNR_PAUSE", "true", 106.0);
    d(&mut app, "NAV_GT_X", 5.0, 106.0);
    out.clear();
    app.iterate(106.5, &mut out);
    assert!(all_of(&out, "NODE_REPORT_LOCAL").is_empty());
}

#[test]
fn blackout_variance_range_and_the_interval_that_holds_nothing() {
    // blackout_interval alone: the first report is due at once and the blackout is reset
    // to 0 by every report, so every iteration reports.
    let cfg = NodeReportConfig::from_params([("blackout_interval", "30")]).unwrap();
    let mut app = nav_at(cfg, "ben", 1.0);
    let mut out = Vec::new();
    for i in 0..4 {
        app.iterate(100.0 + f64::from(i), &mut out);
    }
    assert_eq!(all_of(&out, "NODE_REPORT_LOCAL").len(), 4);
    assert_eq!(all_of(&out, "PNR_POST_GAP"), ["0", "1", "1", "1"]);
    // Variance 0.5: the next blackout is -0.5 + 2k/100 for a whole k in [0, 50), clipped at
    // 0, so at most 0.48 s: at 4 Hz a gap is one tick or two, never more.
    let cfg = NodeReportConfig::from_params([("blackout_variance", "0.5")]).unwrap();
    let mut app = nav_at(cfg, "ben", 1.0).with_seed(7);
    out.clear();
    for i in 0..2000 {
        app.iterate(100.0 + f64::from(i) * 0.25, &mut out);
    }
    let gaps: Vec<String> = all_of(&out, "PNR_POST_GAP");
    assert!(
        gaps[1..].iter().all(|g| g == "0.25" || g == "0.5"),
        "{gaps:?}"
    );
    // A two-tick gap needs k >= 38 (a blackout of at least 0.26 s): 12 draws in 50.
    let long = gaps.iter().filter(|g| *g == "0.5").count() as f64;
    let share = long / (gaps.len() - 1) as f64;
    assert!((0.15..0.33).contains(&share), "{share}");
    let (_, w) = NodeReportConfig::from_params_lenient([("blackout_variance", "-1")]).unwrap();
    assert_eq!(w.len(), 1);
}

#[test]
fn extrapolation_gaps_with_decay_and_strict_limits() {
    let cfg = NodeReportConfig::from_params([("extrap_enabled", "true"), ("extrap_max_gap", "10")])
        .unwrap();
    let mut app = NodeReporter::new(cfg, "ben", 0.0);
    let nav = |app: &mut NodeReporter, t: f64, x: f64, y: f64, h: f64| {
        d(app, "NAV_X", x, t);
        d(app, "NAV_Y", y, t);
        d(app, "NAV_SPEED", 2.0, t);
        d(app, "NAV_HEADING", h, t);
    };
    let mut out = Vec::new();
    nav(&mut app, 10.0, 0.0, 0.0, 45.0);
    app.iterate(10.0, &mut out);
    assert!(
        all_of(&out, "PNR_EXTRAP_POS_GAP").is_empty(),
        "no report yet"
    );
    // 1 s on at 2 m/s, heading 45: predicted (sqrt 2, sqrt 2); at (1.5, 1.5) and 45.5 deg
    // the gaps are sqrt 2 * (1.5 - sqrt 2) m and 0.5 deg, both under the limits: pruned.
    nav(&mut app, 11.0, 1.5, 1.5, 45.5);
    out.clear();
    app.iterate(11.0, &mut out);
    let r2 = std::f64::consts::SQRT_2;
    let pos = last_posting(&out, "PNR_EXTRAP_POS_GAP")
        .unwrap()
        .as_f64()
        .unwrap();
    assert!((pos - r2 * (1.5 - r2)).abs() < 1e-12, "{pos}");
    assert_eq!(
        last_posting(&out, "PNR_EXTRAP_HDG_GAP").unwrap().as_f64(),
        Some(0.5)
    );
    assert!(all_of(&out, "NODE_REPORT_LOCAL").is_empty());
    // 7 s after the last report posted (t = 10; the pruned one does not count), under
    // extrap_max_gap 10: the speed holds for 5 s only (decay from 5 to 5 s), so the
    // prediction is 10 m along 45 degrees, not 14.
    let p = 10.0 / r2;
    nav(&mut app, 17.0, p, p, 45.0);
    out.clear();
    app.iterate(17.0, &mut out);
    let pos = last_posting(&out, "PNR_EXTRAP_POS_GAP")
        .unwrap()
        .as_f64()
        .unwrap();
    assert!(pos < 1e-9, "{pos}");
    assert!(all_of(&out, "NODE_REPORT_LOCAL").is_empty(), "pruned");
    // Exactly extrap_max_gap after the last report: no comparison, reported.
    out.clear();
    app.iterate(20.0, &mut out);
    assert!(all_of(&out, "PNR_EXTRAP_POS_GAP").is_empty());
    assert_eq!(all_of(&out, "PNR_POST_GAP"), ["10"]);
    // Exactly where predicted 0.5 s on, turned exactly the threshold (1 degree: not under
    // it): reported.
    let step = 0.5 * 2.0 * (45.0f64 / 180.0 * std::f64::consts::PI).sin();
    nav(&mut app, 20.5, p + step, p + step, 46.0);
    out.clear();
    app.iterate(20.5, &mut out);
    let pos = last_posting(&out, "PNR_EXTRAP_POS_GAP")
        .unwrap()
        .as_f64()
        .unwrap();
    assert!(pos < 1e-9, "{pos}");
    assert_eq!(all_of(&out, "PNR_EXTRAP_HDG_GAP"), ["1"]);
    assert_eq!(all_of(&out, "NODE_REPORT_LOCAL").len(), 1);
    // Across north: 359 against 1 is 2 degrees (MOOS angleDiff).
    let cfg = NodeReportConfig::from_params([("extrap_enabled", "true")]).unwrap();
    let mut app = NodeReporter::new(cfg, "ben", 0.0);
    nav(&mut app, 1.0, 0.0, 0.0, 359.0);
    app.iterate(1.0, &mut out);
    nav(&mut app, 1.02, 0.0, 0.0, 1.0);
    out.clear();
    // Within 0.05 s of the last report nothing is extrapolated.
    app.iterate(1.02, &mut out);
    assert_eq!(all_of(&out, "PNR_EXTRAP_POS_GAP"), ["0"]);
    assert_eq!(all_of(&out, "PNR_EXTRAP_HDG_GAP"), ["2"]);
    for (k, v) in [
        ("extrap_pos_thresh", "-0.1"),
        ("extrap_hdg_thresh", "x"),
        ("extrap_max_gap", "-5"),
        ("extrap_enabled", "maybe"),
    ] {
        let (_, w) = NodeReportConfig::from_params_lenient([(k, v)]).unwrap();
        assert_eq!(w.len(), 1, "{k}");
    }
    let cfg = NodeReportConfig::from_params([("extrap_enabled", "toggle")]).unwrap();
    assert!(cfg.extrap_enabled, "setBooleanOnString toggles the default");
}

#[test]
fn colours_beam_transparency_and_trajectory() {
    for (c, ok) in [
        ("hex:ff,80,00", true),
        ("0.2,0.4,0.6", true),
        ("Dark_Green", true),
        ("black", true),
        ("invisible", true),
        ("gray95", true),
        ("grey07", false),
        ("tomato", false),
        ("tomatao", true),
        ("bluish", false),
    ] {
        let (cfg, w) = NodeReportConfig::from_params_lenient([("platform_color", c)]).unwrap();
        assert_eq!(w.is_empty(), ok, "{c}");
        assert_eq!(cfg.platform_color.is_some(), ok, "{c}");
    }
    for (k, v) in [
        ("platform_beam", "-1"),
        ("platform_beam", "wide"),
        ("platform_transparency", "clear"),
        ("nohelm_threshold", "0"),
        ("nav_grace_period", "soon"),
        ("paused", "maybe"),
        ("allow_color_change", "perhaps"),
    ] {
        let (_, w) = NodeReportConfig::from_params_lenient([(k, v)]).unwrap();
        assert_eq!(w.len(), 1, "{k} = {v}");
    }
    let cfg = NodeReportConfig::from_params([
        ("platform_beam", "0"),
        ("platform_transparency", "-2"),
        ("platform_aspect", "ID=439"),
        ("allow_color_change", "true"),
    ])
    .unwrap();
    let mut app = nav_at(cfg, "ben", 1.0);
    s(&mut app, "NAV_TRAJECTORY", "pts={0,0:5,5}", 1.0);
    // A colour change must name a colour even when allowed.
    s(&mut app, "NODE_COLOR_CHANGE", "reddish", 1.0);
    let mut out = Vec::new();
    app.iterate(100.0, &mut out);
    assert_eq!(
        report(&out),
        "NAME=ben,X=0,Y=0,SPD=0,HDG=0,TYPE=unknown,MODE=NOHELM-EVER,ALLSTOP=unknown,TIME=100,\
         TRANSPARENCY=-2,LENGTH=0,BEAM=0,TRAJECTORY={pts={0,0:5,5}},ID=439"
    );
    s(&mut app, "NODE_COLOR_CHANGE", "hex:00,ff,00", 100.0);
    d(&mut app, "NAV_TRANSP", 0.25, 100.0);
    out.clear();
    app.iterate(101.0, &mut out);
    let r = report(&out);
    assert!(r.contains(",TYPE=unknown,COLOR=hex:00,ff,00,MODE="), "{r}");
    assert!(r.contains(",TRANSPARENCY=0.25,"), "{r}");
}

#[test]
fn helm_silence_grace_period_and_pause() {
    // nohelm_threshold 2: NOHELM only when strictly over it; the age with no decimals
    // (printf rounds 2.5 to even: 2).
    let cfg = NodeReportConfig::from_params([("nohelm_threshold", "2")]).unwrap();
    let mut app = nav_at(cfg, "ben", 1.0);
    s(&mut app, "IVPHELM_STATE", "PARK", 100.0);
    let mut out = Vec::new();
    app.iterate(102.0, &mut out);
    assert!(report(&out).contains(",MODE=PARK,"), "{}", report(&out));
    out.clear();
    app.iterate(102.5, &mut out);
    assert!(report(&out).contains(",MODE=NOHELM-2,"), "{}", report(&out));
    // nav_grace_period (60 s by default): reports without speed or heading while in it,
    // once there is a position (X and Y, or as the C++ tests it, a longitude alone).
    let mut app = NodeReporter::new(NodeReportConfig::default(), "ben", 1000.0);
    d(&mut app, "NAV_X", 5.0, 1001.0);
    out.clear();
    app.iterate(1001.0, &mut out);
    assert!(out.is_empty(), "X without Y is no position");
    d(&mut app, "NAV_LONG", -70.5, 1002.0);
    app.iterate(1002.0, &mut out);
    assert_eq!(
        report(&out),
        "NAME=ben,X=5,LON=-70.5,TYPE=unknown,MODE=NOHELM-EVER,ALLSTOP=unknown,TIME=1002,LENGTH=0"
    );
    out.clear();
    app.iterate(1060.0, &mut out);
    assert!(out.is_empty(), "grace over, still no speed/heading");
    // A negative grace period is none.
    let cfg = NodeReportConfig::from_params([("nav_grace_period", "-1")]).unwrap();
    let mut app = NodeReporter::new(cfg, "ben", 1000.0);
    d(&mut app, "NAV_X", 5.0, 1001.0);
    d(&mut app, "NAV_Y", 5.0, 1001.0);
    app.iterate(1001.0, &mut out);
    assert!(out.is_empty());
    // paused = toggle (from false); PNR_PAUSE toggles back; no report, _FIRST, PNR_POST_GAP
    // or index while paused, the extrapolation gaps all the same.
    let cfg =
        NodeReportConfig::from_params([("paused", "toggle"), ("extrap_enabled", "true")]).unwrap();
    assert!(cfg.paused);
    let mut app = nav_at(cfg, "ben", 1.0);
    out.clear();
    app.iterate(100.0, &mut out);
    assert!(out.is_empty());
    s(&mut app, "PNR_PAUSE", " false", 100.0);
    app.iterate(101.0, &mut out);
    assert!(
        out.is_empty(),
        "` false` is no boolean to setBooleanOnString"
    );
    s(&mut app, "PNR_PAUSE", "Toggle", 101.0);
    app.iterate(102.0, &mut out);
    assert_eq!(all_of(&out, "PNR_POST_GAP"), ["0"]);
    assert_eq!(all_of(&out, "NODE_REPORT_LOCAL_FIRST").len(), 1);
    assert!(!report(&out).contains("INDEX"));
    s(&mut app, "PNR_PAUSE", "ON", 102.0);
    d(&mut app, "NAV_X", 3.0, 102.0);
    out.clear();
    app.iterate(103.0, &mut out);
    assert_eq!(all_of(&out, "PNR_EXTRAP_POS_GAP"), ["3"]);
    assert!(all_of(&out, "NODE_REPORT_LOCAL").is_empty());
    s(&mut app, "PNR_PAUSE", "off", 103.0);
    out.clear();
    app.iterate(104.0, &mut out);
    assert_eq!(all_of(&out, "PNR_POST_GAP"), ["2"]);
    assert!(report(&out).contains(",INDEX=1,"), "{}", report(&out));
}

#[test]
fn all_stop_sources_and_a_standby_helm_stepping_in() {
    let mut app = nav_at(NodeReportConfig::default(), "ben", 1.0);
    let mode_allstop = |app: &mut NodeReporter, t: f64| {
        let mut out = Vec::new();
        app.iterate(t, &mut out);
        let r = report(&out);
        let field = |k: &str| {
            r.split(',')
                .find_map(|kv| kv.strip_prefix(k))
                .map(str::to_string)
        };
        (field("MODE="), field("ALLSTOP="))
    };
    let some = |a: &str, b: &str| (Some(a.to_string()), Some(b.to_string()));
    // Before any helm word: ALLSTOP=unknown.
    assert_eq!(
        mode_allstop(&mut app, 100.0),
        some("NOHELM-EVER", "unknown")
    );
    s(&mut app, "IVPHELM_STATE", "DRIVE", 100.0);
    s(
        &mut app,
        "IVPHELM_SUMMARY",
        "iter=3,modes=MODE@SURVEY",
        100.0,
    );
    s(&mut app, "IVPHELM_ALLSTOP", "clear", 100.0);
    assert_eq!(mode_allstop(&mut app, 100.5), some("MODE@SURVEY", "clear"));
    // STANDBY from a standby helm changes nothing shown.
    s(&mut app, "IVPHELM_STATE", "STANDBY", 101.0);
    assert_eq!(mode_allstop(&mut app, 101.0), some("MODE@SURVEY", "clear"));
    // The standby helm steps in (DRIVE+): the first time, modes and all-stop are forgotten.
    s(&mut app, "IVPHELM_STATE", "DRIVE+", 102.0);
    assert_eq!(mode_allstop(&mut app, 102.0), (Some("DRIVE+".into()), None));
    s(&mut app, "IVPHELM_ALLSTOP", "ManualOverride", 103.0);
    s(&mut app, "IVPHELM_SUMMARY", "modes=MODE@RETURN", 103.0);
    assert_eq!(
        mode_allstop(&mut app, 103.0),
        some("MODE@RETURN", "ManualOverride")
    );
    // A second `+` state does not clear again; PARK+ shows as the state.
    s(&mut app, "IVPHELM_STATE", "PARK+", 104.0);
    assert_eq!(
        mode_allstop(&mut app, 104.0),
        some("PARK+", "ManualOverride")
    );
    // MALCONFIG (primary or standby): ALLSTOP=n/a; MALCONFIG+ leaves the primary state.
    s(&mut app, "IVPHELM_STATE", "MALCONFIG+", 105.0);
    assert_eq!(mode_allstop(&mut app, 105.0), some("MODE@RETURN", "n/a"));
    s(&mut app, "IVPHELM_STATE", " MALCONFIG ", 106.0);
    assert_eq!(mode_allstop(&mut app, 106.0), some("MALCONFIG", "n/a"));
    // AUX_MODE is the MODE_AUX field, no all-stop source.
    s(&mut app, "AUX_MODE", "ALLSTOP", 107.0);
    let mut out = Vec::new();
    app.iterate(107.0, &mut out);
    assert!(report(&out).contains(",MODE=MALCONFIG,MODE_AUX=ALLSTOP,ALLSTOP=n/a,"));
}

#[test]
fn riders_skip_the_keys_the_cpp_handles_itself_and_heading_error_spends_them() {
    let cfg = NodeReportConfig::from_params([
        ("rider", "var=AUX_MODE, policy=always"),
        ("rider", "var=MISSION_HASH, policy=always, rfld=MH"),
        ("rider", "var=NAV_X, policy=always, rfld=NX, prec=1"),
    ])
    .unwrap();
    let mut app = nav_at(cfg, "ben", 1.0);
    s(&mut app, "AUX_MODE", "m1", 1.0);
    s(&mut app, "MISSION_HASH", "mhash=abc", 1.0);
    d(&mut app, "NAV_X", 2.25, 1.0);
    let mut out = Vec::new();
    app.iterate(100.0, &mut out);
    // AUX_MODE never reaches its rider (the C++'s mail chain handles it first), so the
    // rider has no value and is skipped; MISSION_HASH and NAV_X do ride (2.25 as %.1f: 2.2).
    assert!(
        report(&out)
            .ends_with(",MODE_AUX=m1,ALLSTOP=unknown,TIME=100,LENGTH=0,MH=mhash=abc,NX=2.2"),
        "{}",
        report(&out)
    );
    // With hdg_error the report is formed twice: an updated rider is spent on the first (and
    // an empty report before any other leaves no comma).
    let cfg = NodeReportConfig::from_params([
        ("hdg_error", "1"),
        ("rider", "var=BATT, policy=updated"),
        ("rider", "var=LEG, policy=always"),
    ])
    .unwrap();
    let mut app = nav_at(cfg, "ben", 1.0);
    d(&mut app, "BATT", 12.0, 1.0);
    s(&mut app, "LEG", "2", 1.0);
    out.clear();
    app.iterate(100.0, &mut out);
    assert!(
        report(&out).ends_with(
            ",HDG=1,TYPE=unknown,MODE=NOHELM-EVER,ALLSTOP=unknown,TIME=100,LENGTH=0,LEG=2"
        ),
        "{}",
        report(&out)
    );
    // LOAD_WARNING as tokStringParse reads it: a malformed piece before `maxgap` spoils it.
    s(&mut app, "LOAD_WARNING", "app=pHelmIvP,maxgap=2.1", 100.0);
    out.clear();
    app.iterate(101.0, &mut out);
    assert!(
        report(&out).contains(",LOAD_WARNING=pHelmIvP:2.1,"),
        "{}",
        report(&out)
    );
    out.clear();
    app.iterate(102.0, &mut out);
    assert!(
        !report(&out).contains("LOAD_WARNING"),
        "cleared after one iteration"
    );
    s(
        &mut app,
        "LOAD_WARNING",
        "app=pHelmIvP,late,maxgap=2.1",
        102.0,
    );
    out.clear();
    app.iterate(103.0, &mut out);
    assert!(!report(&out).contains("LOAD_WARNING"), "{}", report(&out));
}

#[test]
fn platform_type_and_group_are_any_text_and_skywalkers_are_two_metres() {
    let cfg =
        NodeReportConfig::from_params([("platform_type", "SkyWalker"), ("group", "red team")])
            .unwrap();
    let mut app = nav_at(cfg, "ben", 1.0);
    let mut out = Vec::new();
    app.iterate(100.0, &mut out);
    assert_eq!(
        report(&out),
        "NAME=ben,X=0,Y=0,SPD=0,HDG=0,TYPE=SkyWalker,GROUP=red team,MODE=NOHELM-EVER,\
         ALLSTOP=unknown,TIME=100,LENGTH=2"
    );
}
