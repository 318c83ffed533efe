//! pObstacleMgr's core against values worked out from the C++ (`ObstacleManager.cpp`,
//! `Obstacle.cpp`, `ConvexHullGenerator.cpp` at a2a9b716).

use super::*;

fn texts<'a>(out: &'a [Post], key: &str) -> Vec<&'a str> {
    out.iter()
        .filter(|p| p.key == key)
        .map(|p| p.value.as_str().unwrap_or(""))
        .collect()
}

fn nums(out: &[Post], key: &str) -> Vec<f64> {
    out.iter()
        .filter(|p| p.key == key)
        .filter_map(|p| p.value.as_ref().as_f64())
        .collect()
}

fn mail(om: &mut ObstacleMgr, key: &str, v: Value, now: f64, out: &mut Vec<Post>) {
    om.on_mail(key, &v, now, out);
    om.end_mail(out);
}

fn at(om: &mut ObstacleMgr, x: f64, y: f64, now: f64, out: &mut Vec<Post>) {
    mail(om, "NAV_X", Value::Double(x), now, out);
    mail(om, "NAV_Y", Value::Double(y), now, out);
}

const SQUARE: &str = "pts={50,-100:50,-120:80,-120:80,-100},label=one";

#[test]
fn bad_lines_are_refused_as_the_cpp_refuses_them() {
    let (om, w) = ObstacleMgr::new(&[
        "alert_range = -5",
        "alert_range = 0",
        "post_dist_to_polys = maybe",
        "obstacles_color = bluish",
        "lasso_points = 2",
        "lasso_radius = -1",
        "given_max_duration = 0",
        "given_obstacle = pts={0,0:10,10:10,0:0,10},label=bowtie",
        "general_alert = name=g,update_var=G,alert_range=5,extra=1",
        "point_var = GIVEN_OBSTABLE",
        "new_obs_flag = NOVALUE=",
        "mailflag = DEPLOY # X=1",
        "bogus = 1",
        "AppTick = 4",
        "CommsTick = 4",
    ]);
    assert_eq!(
        w,
        [
            "Unhandled config line: alert_range=-5",
            "Unhandled config line: alert_range=0",
            "Unhandled config line: post_dist_to_polys=maybe",
            "Unhandled config line: obstacles_color=bluish",
            "lasso_points must be at least 3 points",
            "lasso_radius must be at positive number",
            "Unhandled config line: given_max_duration=0",
            "Unhandled config line: given_obstacle=pts={0,0:10,10:10,0:0,10},label=bowtie",
            "Unhandled config line: general_alert=name=g,update_var=G,alert_range=5,extra=1",
            "Unhandled config line: point_var=GIVEN_OBSTABLE",
            "Unhandled config line: new_obs_flag=NOVALUE=",
            "Unhandled config line: mailflag=DEPLOY#X=1",
            "Unhandled config line: bogus=1",
        ]
    );
    // The defaults stand; the lasso's clipped values are kept.
    assert_eq!(om.s.alert_range, 20.0);
    assert_eq!(om.s.post_dist_to_polys, "close");
    assert_eq!(om.s.obstacles_color, "blue");
    assert_eq!((om.s.lasso_points, om.s.lasso_radius), (3, 1.0));
    assert_eq!(om.s.given_max_duration, 60.0);
    assert_eq!(om.s.point_var, "TRACKED_FEATURE");
    let (om, w) = ObstacleMgr::new(&[
        "given_max_duration = off",
        "point_var = FEATURE",
        "general_alert = update_var=GEN_ALERT, alert_range=100",
    ]);
    assert!(w.is_empty(), "{w:?}");
    assert_eq!(om.s.given_max_duration, -1.0);
    assert_eq!(om.s.gen_alert_name, "gen_alert_");
    assert!(om.subscriptions().contains(&"FEATURE".to_string()));
}

#[test]
fn a_given_obstacle_within_range_alerts_once_per_change() {
    let (mut om, w) = ObstacleMgr::new(&[&format!("given_obstacle = {SQUARE}")]);
    assert!(w.is_empty(), "{w:?}");
    let mut out = Vec::new();
    om.on_startup(1.0, &mut out);
    assert_eq!(texts(&out, "OBM_CONNECT"), ["true"]);
    out.clear();
    // 20 m north of the square's top edge (y = -100).
    at(&mut om, 60.0, -80.0, 1.0, &mut out);
    om.iterate(1.0, &mut out);
    // No alert requested yet: only the closest range.
    assert_eq!(nums(&out, "OBM_MIN_DIST_EVER"), [20.0]);
    assert!(texts(&out, "OBM_DIST_TO_OBJ").is_empty());
    out.clear();
    mail(
        &mut om,
        "OBM_ALERT_REQUEST",
        Value::text("name=avd_,update_var=OBSTACLE_ALERT,alert_range=25"),
        1.5,
        &mut out,
    );
    om.iterate(1.5, &mut out);
    assert_eq!(
        texts(&out, "OBSTACLE_ALERT"),
        ["name=avd_one#poly=pts={50,-100:50,-120:80,-120:80,-100},label=one#id=one"]
    );
    assert_eq!(texts(&out, "OBM_DIST_TO_OBJ"), ["ONE,20.0"]);
    // Unchanged: the distance again, no second alert.
    out.clear();
    om.iterate(2.0, &mut out);
    assert!(texts(&out, "OBSTACLE_ALERT").is_empty());
    assert_eq!(texts(&out, "OBM_DIST_TO_OBJ"), ["ONE,20.0"]);
    // Out of the alert range: nothing posted (post_dist_to_polys = close).
    out.clear();
    at(&mut om, 60.0, -70.0, 2.5, &mut out);
    om.iterate(2.5, &mut out);
    assert!(out.is_empty(), "{out:?}");
    // Coming back within range marks it changed: a new alert.
    at(&mut om, 60.0, -76.0, 3.0, &mut out);
    om.iterate(3.0, &mut out);
    assert_eq!(texts(&out, "OBSTACLE_ALERT").len(), 1);
    assert_eq!(texts(&out, "OBM_DIST_TO_OBJ"), ["ONE,24.0"]);
    // No duration: never expires.
    out.clear();
    om.iterate(10_000.0, &mut out);
    assert!(texts(&out, "OBM_RESOLVED").is_empty());
}

#[test]
fn given_mail_needs_a_duration_within_the_maximum_and_expires_after_it() {
    let (mut om, _) = ObstacleMgr::new(&["new_obs_flag = NEW_OBS=$[OBS_NOW] of $[OBS_EVER]"]);
    let mut out = Vec::new();
    om.on_startup(0.0, &mut out);
    out.clear();
    mail(
        &mut om,
        "GIVEN_OBSTACLE",
        Value::text(SQUARE),
        5.0,
        &mut out,
    );
    mail(
        &mut om,
        "GIVEN_OBSTACLE",
        Value::text(format!("{SQUARE},duration=61")),
        5.0,
        &mut out,
    );
    let notes = om.take_notes();
    assert!(notes.contains(&Note::Warning(
        "Incoming GIVEN_OBSTACLE has missing duration".into()
    )));
    assert!(notes.contains(&Note::Warning(
        "Incoming GIVEN_OBSTACLE has duration exceeding max duration".into()
    )));
    assert!(notes.contains(&Note::Warning("Unhandled Mail: GIVEN_OBSTACLE".into())));
    assert_eq!(om.obstacles().count(), 0);
    mail(
        &mut om,
        "GIVEN_OBSTACLE",
        Value::text(format!("{SQUARE},duration=30")),
        5.0,
        &mut out,
    );
    // The MOOS reader took the blanks out of the line.
    assert_eq!(texts(&out, "NEW_OBS"), ["1of1"]);
    assert_eq!((om.given_mail_ever, om.given_mail_good), (3, 1));
    out.clear();
    // 30 s later it is still there (age not above the duration), then it goes.
    om.iterate(35.0, &mut out);
    assert!(texts(&out, "OBM_RESOLVED").is_empty());
    om.iterate(35.5, &mut out);
    assert_eq!(texts(&out, "OBM_RESOLVED"), ["one"]);
    assert_eq!(
        texts(&out, "VIEW_POLYGON"),
        ["pts={0,0:9,0:0,9},active=false,label=one"]
    );
    assert_eq!(om.obstacles().count(), 0);
    // An inactive given polygon of a new key goes at the next iteration. (One with the
    // key of a known obstacle and the same vertices is the same polygon to `setPoly`.)
    mail(
        &mut om,
        "GIVEN_OBSTACLE",
        Value::text("pts={0,0:0,9:9,9},label=two,active=false,duration=30"),
        41.0,
        &mut out,
    );
    out.clear();
    om.iterate(41.0, &mut out);
    assert_eq!(texts(&out, "OBM_RESOLVED"), ["two"]);
}

#[test]
fn points_make_a_hull_posted_as_a_view_polygon_and_age_away() {
    let (mut om, _) = ObstacleMgr::new(&[]);
    let mut out = Vec::new();
    om.on_startup(0.0, &mut out);
    out.clear();
    for (x, y) in [(10.0, 10.0), (14.0, 10.0), (12.0, 14.0)] {
        mail(
            &mut om,
            "TRACKED_FEATURE",
            Value::text(format!("x={x},y={y},label=a")),
            1.0,
            &mut out,
        );
    }
    om.iterate(1.0, &mut out);
    // Root (10,10); (14,10) at 90°, (12,14) at 26.57°: scanned in that order, a left turn
    // at (14,10); the stack from its top is (12,14), (14,10), (10,10).
    let view = "pts={12,14:14,10:10,10},label=obmgr_a,edge_color=blue,vertex_color=blue,\
                fill_color=blue,vertex_size=3,edge_size=1,fill_transparency=0.15";
    assert_eq!(texts(&out, "VIEW_POLYGON"), [view]);
    // Nav at (0,0): the closest vertex (10,10) is 14.14 m away.
    let d = nums(&out, "OBM_MIN_DIST_EVER");
    assert!(
        d.len() == 1 && (d[0] - 200f64.sqrt()).abs() < 1e-12,
        "{d:?}"
    );
    // Without an alert nothing clears the change: the hull is posted again.
    out.clear();
    om.iterate(2.0, &mut out);
    assert_eq!(texts(&out, "VIEW_POLYGON"), [view]);
    // 20 s is the points' age limit: at 21.5 they are 20.5 s old.
    out.clear();
    om.iterate(21.0, &mut out);
    assert!(texts(&out, "OBM_RESOLVED").is_empty());
    om.iterate(21.5, &mut out);
    assert_eq!(texts(&out, "OBM_RESOLVED"), ["a"]);
    assert_eq!(
        texts(&out, "VIEW_POLYGON").last(),
        Some(&"pts={0,0:9,0:0,9},active=false,label=obmgr_a")
    );
}

#[test]
fn a_lasso_is_a_snapped_regular_polygon_around_the_points_mean() {
    let (mut om, w) = ObstacleMgr::new(&["lasso = true", "lasso_radius = 6", "lasso_points = 8"]);
    assert!(w.is_empty());
    let mut out = Vec::new();
    for (x, y) in [(10.0, 10.0), (14.0, 10.0), (12.0, 14.0)] {
        mail(
            &mut om,
            "TRACKED_FEATURE",
            Value::text(format!("x={x},y={y},key=a")),
            1.0,
            &mut out,
        );
    }
    om.iterate(1.0, &mut out);
    // Mean (12, 11.333) written as 11.33; first vertex at bearing 22.5:
    // 12 + 6 sin 22.5° = 14.296 -> 14.3, 11.33 + 6 cos 22.5° = 16.873 -> 16.87.
    let p = om.polygon("a").unwrap();
    assert_eq!(p.len(), 8);
    assert!((p.vertices()[0].x - 14.3).abs() < 1e-9);
    assert!((p.vertices()[0].y - 16.87).abs() < 1e-9);
    assert!(texts(&out, "VIEW_POLYGON")[0].starts_with("pts={14.3,16.87:"));
}

#[test]
fn far_points_are_ignored_and_bad_points_warned() {
    let (mut om, _) = ObstacleMgr::new(&["ignore_range = 40"]);
    let mut out = Vec::new();
    mail(
        &mut om,
        "TRACKED_FEATURE",
        Value::text("x=50,y=0,label=far"),
        1.0,
        &mut out,
    );
    mail(
        &mut om,
        "TRACKED_FEATURE",
        Value::text("x=5,y=0,msg=b"),
        1.0,
        &mut out,
    );
    assert_eq!((om.points_ignored, om.points_invalid), (1, 1));
    assert_eq!(om.obstacles().count(), 0);
    let notes = om.take_notes();
    assert_eq!(
        notes,
        [
            Note::Warning("Invalid point:x=5,y=0,msg=b".into()),
            Note::Warning("Unhandled Mail: TRACKED_FEATURE".into()),
        ]
    );
}

#[test]
fn the_general_alert_posts_once_a_helm_alert_exists() {
    let (mut om, _) = ObstacleMgr::new(&[
        "general_alert = name=gen, update_var=GEN_ALERT, alert_range=500",
        &format!("given_obstacle = {SQUARE},vsource=radar"),
        "post_dist_to_polys = false",
    ]);
    let mut out = Vec::new();
    om.on_startup(1.0, &mut out);
    at(&mut om, 0.0, 200.0, 1.0, &mut out);
    om.iterate(1.0, &mut out);
    assert!(texts(&out, "GEN_ALERT").is_empty());
    mail(
        &mut om,
        "OBM_ALERT_REQUEST",
        Value::text("name=avd_,update_var=OBSTACLE_ALERT,alert_range=25"),
        2.0,
        &mut out,
    );
    out.clear();
    om.iterate(2.0, &mut out);
    assert!(texts(&out, "OBSTACLE_ALERT").is_empty());
    assert!(texts(&out, "OBM_DIST_TO_OBJ").is_empty());
    assert_eq!(
        texts(&out, "GEN_ALERT"),
        ["name=gen_one#poly=pts={50,-100:50,-120:80,-120:80,-100},label=one,vsource=radar#id=one"]
    );
}

#[test]
fn mail_flags_and_the_able_variables() {
    let (mut om, w) = ObstacleMgr::new(&[
        "mailflag = @DEPLOY # DEPLOY_SEEN=$[CNT]",
        "mailflag = @DEPLOY # DEPLOYS=2",
        "disable_var = OBS_DISABLE",
        "new_obs_flag = LAST_DISABLED=$[RECENT_DISABLED]/$[TOTAL_DISABLED]",
    ]);
    assert!(w.is_empty(), "{w:?}");
    assert!(om.subscriptions().contains(&"DEPLOY".to_string()));
    let mut out = Vec::new();
    om.on_mail("DEPLOY", &Value::text("true"), 1.0, &mut out);
    om.on_mail("DEPLOY", &Value::text("true"), 1.0, &mut out);
    assert!(out.is_empty());
    om.end_mail(&mut out);
    assert_eq!(texts(&out, "DEPLOY_SEEN"), ["1", "2"]);
    assert_eq!(nums(&out, "DEPLOYS"), [2.0, 2.0]);
    out.clear();
    mail(&mut om, "OBS_DISABLE", Value::text("ob_1"), 2.0, &mut out);
    mail(
        &mut om,
        "OBS_DISABLE",
        Value::text("obstacle_id=ob_2"),
        2.0,
        &mut out,
    );
    mail(
        &mut om,
        "OBS_DISABLE",
        Value::text("vsource=radar"),
        2.0,
        &mut out,
    );
    assert_eq!(
        texts(&out, "BHV_ABLE_FILTER"),
        [
            "obstacle_id=ob_1,action=disable",
            "obstacle_id=ob_2,action=disable",
            "vsource=radar,action=disable",
        ]
    );
    // The bare id form does not enter the list (as in the C++): only ob_2 did.
    out.clear();
    om.s.given_max_duration = -1.0;
    mail(
        &mut om,
        "GIVEN_OBSTACLE",
        Value::text(SQUARE),
        3.0,
        &mut out,
    );
    assert_eq!(texts(&out, "LAST_DISABLED"), ["ob_2/1"]);
}

#[test]
fn the_report_lists_each_obstacle() {
    let (mut om, _) = ObstacleMgr::new(&[&format!("given_obstacle = {SQUARE},duration=100")]);
    let mut out = Vec::new();
    om.on_startup(10.0, &mut out);
    at(&mut om, 60.0, -80.0, 10.0, &mut out);
    om.iterate(20.0, &mut out);
    let mut b = String::new();
    om.report(&mut b, 20.0);
    assert!(b.contains("  Given Obstacles (config):    1\n"), "{b}");
    assert!(b.contains("  Closest range ever: 20\n"), "{b}");
    let row = b.lines().find(|l| l.starts_with("one")).expect(&b);
    let cells: Vec<&str> = row.split_whitespace().collect();
    assert_eq!(
        cells,
        ["one", "0", "4", "1", "given", "100", "90", "20.0", "20.0"]
    );
}
