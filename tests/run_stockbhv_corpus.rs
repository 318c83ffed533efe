//! The corpus missions the non-contact stock behaviours let run (issue #18, point 4): s5_echo
//! (BHV_BearingLine), s6_foxtrot (community alpha) and s8_hotel (BHV_HSLine, switched on by a poke of the
//! variable their viewer button posts), in lockstep, one vehicle each.

mod common;

use alog::Alog;
use common::*;

/// Runs corpus mission `rel` deployed, with `pokes`, until `CHECK_END` poked at `end` s.
fn run(name: &str, rel: &str, pokes: &[&str], end: f64) -> Alog {
    let mission = test_support::mission_file(rel);
    let mut opts = deploy_until("CHECK_END = true", end + 30.0);
    opts.pokes = pokes.iter().map(|p| p.to_string()).collect();
    opts.pokes.push(format!("CHECK_END=true@{end}"));
    let (bytes, _) = run_lockstep(name, &mission, &[], opts);
    parse(&bytes)
}

/// `(time, text)` of the posts of `var` whose text ends with `suffix`.
fn drawn(log: &Alog, var: &str, suffix: &str) -> Vec<(f64, String)> {
    log.entries
        .iter()
        .filter(|e| e.var == var)
        .filter_map(|e| Some((e.time, e.value.as_str()?.to_string())))
        .filter(|(_, s)| s.ends_with(suffix))
        .collect()
}

#[test]
fn s5_echo_draws_its_bearing_line_while_surveying() {
    let log = run("stockbhv-echo", "s5_echo/echo.moos", &[], 120.0);
    // echo.bhv: bearing point 100,-100, line 50 % of the way, point shown.
    let lines = drawn(&log, "VIEW_SEGLIST", "label=echo_bng-line-");
    assert!(lines.len() > 100, "{}", lines.len());
    let pts = drawn(&log, "VIEW_POINT", "label=100,-100");
    assert!(pts.iter().all(|(_, s)| s == "x=100,y=-100,label=100,-100"));
    assert!(!pts.is_empty());
    // The vehicle surveys (it reaches the polygon's second vertex, 60,-140).
    let t = track(&log);
    visits_in_order(&t, &[(60.0, -40.0), (60.0, -140.0)], 10.0, 0);
}

#[test]
fn s6_foxtrot_and_s8_hotel_draw_their_heading_lines_when_switched_on() {
    for (name, rel, on, label) in [
        (
            "stockbhv-foxtrot",
            "s6_foxtrot/foxtrot.moos",
            "HSLINE=true@30",
            "label=alpha_hsline",
        ),
        (
            "stockbhv-hotel",
            "s8_hotel/hotel.moos",
            "HSLINE=on@30",
            "label=hotel_hsline",
        ),
    ] {
        let log = run(name, rel, &[on], 90.0);
        let lines = drawn(&log, "VIEW_SEGLIST", label);
        // Drawn from the poke on (the helm's 4 Hz), never before it.
        assert!(lines.len() > 100, "{rel}: {}", lines.len());
        assert!(lines.iter().all(|(t, _)| *t >= 30.0), "{rel}");
        assert!(
            lines.iter().all(|(_, s)| s.contains(",active=true,")),
            "{rel}"
        );
    }
}
