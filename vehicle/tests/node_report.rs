//! NODE_REPORT_LOCAL strings, character for character.

mod common;

use vehicle::MailValue;
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
    app.on_mail(var, MailValue::Double(v), t);
}

fn s(app: &mut NodeReporter, var: &str, v: &str, t: f64) {
    app.on_mail(var, MailValue::Str(v), t);
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
    let text = common::mission_file("s7_golf/golf.moos");
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
        .filter(|p| &*p.var == var)
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
    assert_eq!(&*out[0].var, "PNODEREPORTER_PID");
    assert_eq!(out[0].value.as_f64(), Some(4242.0));
    out.clear();
    app.iterate(1.0, &mut out);
    assert!(all_of(&out, "PNODEREPORTER_PID").is_empty(), "once");
}
