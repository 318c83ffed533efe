//! The corpus missions the non-contact stock behaviours let run (issue #18, point 4): s5_echo
//! (BHV_BearingLine), s6_foxtrot (community alpha) and s8_hotel (BHV_HSLine, switched on by a poke of the
//! variable their viewer button posts), and s11_kilo (BHV_TestFailure and a standby helm), in
//! lockstep, one vehicle each.

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

/// `(time, source, state)` of every `IVPHELM_STATE` post.
fn helm_states(log: &Alog) -> Vec<(f64, String, String)> {
    log.entries
        .iter()
        .filter(|e| e.var == "IVPHELM_STATE")
        .filter_map(|e| Some((e.time, e.source.clone(), e.value.as_str()?.to_string())))
        .collect()
}

#[test]
fn s11_kilo_standby_helm_takes_over_when_the_primary_burns() {
    // kilo.moos: a second pHelmIvP named pHelmIvP_Standby through pAntler's
    // `ExtraProcessParams` (`--alias=`), `STANDBY = 2`; kilo.bhv's BHV_TestFailure burns the
    // primary for 3 s at the end of its 120 s. pLogger's `AsyncLog = true @ 0` reads as false,
    // but wildcard logging logs anyway (as pLogger).
    let log = run("stockbhv-kilo", "s11_kilo/kilo.moos", &[], 180.0);
    let states = helm_states(&log);
    let of = |who: &str| -> Vec<(f64, String)> {
        states
            .iter()
            .filter(|(_, s, _)| s.split(':').next() == Some(who))
            .map(|(t, _, v)| (*t, v.clone()))
            .collect()
    };
    let primary = of("pHelmIvP");
    let standby = of("pHelmIvP_Standby");
    // The primary drives until the burn; the standby waits.
    let last_drive = primary
        .iter()
        .filter(|(_, v)| v == "DRIVE")
        .map(|(t, _)| *t)
        .fold(f64::NAN, f64::max);
    assert!(standby.iter().any(|(_, v)| v == "STANDBY"));
    // Silent for more than STANDBY = 2 s, the primary is taken over: `DRIVE+`.
    let first_takeover = standby
        .iter()
        .find(|(_, v)| v == "DRIVE+")
        .map(|(t, _)| *t)
        .expect("the standby helm takes over");
    let silent_from = primary
        .iter()
        .filter(|(t, _)| *t < first_takeover)
        .map(|(t, _)| *t)
        .fold(f64::NAN, f64::max);
    let gap = first_takeover - silent_from;
    assert!(
        (2.0..=2.75).contains(&gap),
        "took over {gap} s after the primary's last state"
    );
    // Before it, the standby only waited; after it, it drives to the end.
    assert!(
        standby
            .iter()
            .filter(|(t, _)| *t < first_takeover)
            .all(|(_, v)| v == "STANDBY")
    );
    assert!(
        standby
            .iter()
            .filter(|(t, _)| *t >= first_takeover)
            .all(|(_, v)| v == "DRIVE+")
    );
    // The primary, back from its burn, hears a helm that is not on standby and yields once.
    let disabled: Vec<f64> = primary
        .iter()
        .filter(|(_, v)| v == "DISABLED")
        .map(|(t, _)| *t)
        .collect();
    assert_eq!(disabled.len(), 1, "{primary:?}");
    assert!(disabled[0] > first_takeover && disabled[0] - first_takeover < 2.0);
    assert!(last_drive < disabled[0]);
    // The vehicle keeps going under the standby helm (its behaviours post desired values).
    assert!(log.entries.iter().any(|e| e.var == "DESIRED_SPEED"
        && e.time > disabled[0] + 10.0
        && e.source.starts_with("pHelmIvP_Standby")));
}
