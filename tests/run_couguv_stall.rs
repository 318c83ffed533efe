//! A stalled real-time run, made deterministic: `missions/cougUV` (its simulation form:
//! uSimCougUV, uSimSensors, pNavGraph, pCougControls, pSafety, the helm) in lockstep with
//! every app frozen for 40 simulated seconds mid-dive, as a process starved for 5 s of wall
//! time at a warp of 8 is: no app iterates in the gap, then each takes the whole gap in one
//! step with the mail that waited for it. No wall clock: the stall is a window of MOOS time
//! in which a wrapper holds the apps' mail and skips their iterations.
//!
//! What must hold: every truth and estimate stays finite and physically plausible, the
//! simulator flies the command given before the stall only until the actuator failsafe's 5 s
//! and coasts the rest, and the survey still completes.

mod common;

use common::*;
use runtime::app::{App, AppResult, Mail, Post, Subscription};
use runtime::session;
use runtime::{Bus, Poke, Scheduler, Value, VirtualClock};

/// An app frozen from `from` to `until` (MOOS time): its mail is held and handed over, with
/// the new mail, at its first iteration after the stall; its iterations in the gap are
/// skipped.
struct Stalled {
    inner: Box<dyn App>,
    from: f64,
    until: f64,
    held: Vec<Mail>,
}

impl Stalled {
    fn frozen(&self, now: f64) -> bool {
        now >= self.from && now < self.until
    }
}

impl App for Stalled {
    fn name(&self) -> &str {
        self.inner.name()
    }
    fn process_config(&self) -> Option<&mission::moos::ProcessConfig> {
        self.inner.process_config()
    }
    fn app_tick(&self) -> f64 {
        self.inner.app_tick()
    }
    fn subscriptions(&self) -> Vec<Subscription> {
        self.inner.subscriptions()
    }
    fn unread(&self) -> moosdb::db::Unread {
        self.inner.unread()
    }
    fn new_subscriptions(&mut self) -> Vec<Subscription> {
        self.inner.new_subscriptions()
    }
    fn on_startup(&mut self, now: f64, out: &mut Vec<Post>) -> AppResult {
        self.inner.on_startup(now, out)
    }
    fn on_mail(&mut self, mail: &[Mail], now: f64, out: &mut Vec<Post>) -> AppResult {
        if self.frozen(now) || !self.held.is_empty() {
            self.held.extend(mail.iter().cloned());
            if self.frozen(now) {
                return Ok(());
            }
            let all = std::mem::take(&mut self.held);
            return self.inner.on_mail(&all, now, out);
        }
        self.inner.on_mail(mail, now, out)
    }
    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> AppResult {
        if self.frozen(now) {
            return Ok(());
        }
        if !self.held.is_empty() {
            let all = std::mem::take(&mut self.held);
            self.inner.on_mail(&all, now, out)?;
        }
        self.inner.iterate(now, out)
    }
    fn stop(&mut self, now: f64) -> AppResult {
        self.inner.stop(now)
    }
    fn finished(&self) -> bool {
        self.inner.finished()
    }
}

fn number(s: &Scheduler, var: &str) -> Option<f64> {
    s.current(var).and_then(|v| match v {
        Value::Double(x) => Some(x),
        _ => None,
    })
}

#[test]
fn a_forty_second_stall_mid_dive_stays_finite_plausible_and_completes() {
    let mission = project_mission("cougUV/cougUV.moos");
    let loaded = session::load(&mission, &[], &[]).expect("the mission loads");
    let start = 1_000_000.0;
    // 60 s in: on the first leg, diving at about 0.85 m/s.
    let (from, until) = (start + 60.0, start + 100.0);
    let plan = loaded.plan(start, 1, None).expect("the plan");
    let mut s = Scheduler::new(
        Bus::new(&plan.globals.community, start),
        VirtualClock,
        start,
    );
    for app in plan.apps {
        s.add_app(Box::new(Stalled {
            inner: app,
            from,
            until,
            held: Vec::new(),
        }))
        .unwrap();
    }
    for t in ["DEPLOY=true", "MOOS_MANUAL_OVERRIDE=false"] {
        s.add_poke(Poke::parse(t, "pHelmIvP").unwrap()).unwrap();
    }
    s.set_until(mission::condition::parse_condition("MISSION = complete").unwrap());
    let mut t = start;
    let mut before = None;
    let mut across = None;
    let ended = loop {
        t += 1.0;
        if let Some(o) = s.advance(t).unwrap() {
            break Some(o);
        }
        if t > start + 900.0 {
            break None;
        }
        for v in [
            "SIM_X",
            "SIM_Y",
            "SIM_DEPTH",
            "SIM_SPEED",
            "SIM_PITCH",
            "SIM_HEADING",
            "NAV_X",
            "NAV_Y",
            "NAV_DEPTH",
            "NAV_SPEED",
            "NAV_HEADING",
            "NAV_PITCH",
        ] {
            if let Some(x) = number(&s, v) {
                assert!(x.is_finite(), "{v} = {x} at {}", t - start);
                assert!(x.abs() < 1e4, "{v} = {x} at {}", t - start);
            }
        }
        let depth = number(&s, "SIM_DEPTH").unwrap_or(0.0);
        let speed = number(&s, "SIM_SPEED").unwrap_or(0.0);
        let pitch = number(&s, "SIM_PITCH").unwrap_or(0.0);
        assert!(
            (0.0..6.0).contains(&depth),
            "depth {depth} at {}",
            t - start
        );
        assert!(speed.abs() <= 2.0, "speed {speed} at {}", t - start);
        assert!(pitch.abs() < 1.0, "pitch {pitch} at {}", t - start);
        let pos = (number(&s, "SIM_X"), number(&s, "SIM_Y"));
        if t == from {
            before = Some(pos);
        }
        if t == until {
            across = Some(pos);
        }
    };
    assert!(
        ended.is_some(),
        "the survey did not complete within 900 s: MISSION = {:?}",
        s.current("MISSION")
    );
    // Over the stall: 5 s under the command (about 0.85 m/s) and 35 s coasting down from it
    // (the 20 s surge lag: about 14.6 m); all 40 s coasting would be 14.6 m alone.
    let (Some((Some(x0), Some(y0))), Some((Some(x1), Some(y1)))) = (before, across) else {
        panic!("no position around the stall");
    };
    let d = (x1 - x0).hypot(y1 - y0);
    assert!((17.0..22.0).contains(&d), "{d:.2} m over the stall");
    assert_eq!(
        s.current("SAFETY_MODE")
            .and_then(|v| v.as_str().map(String::from)),
        Some("OK".to_string())
    );
}
