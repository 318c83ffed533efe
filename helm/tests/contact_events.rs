//! The event flags and macros pHelmIvP's behaviours have at a2a9b716 that coug lacked: the
//! contact behaviours' event `cnflag`s (`@cpa`, `@os_passed_cn_star`, ...) with the
//! relative-geometry macros (`$[ROC]`, `$[OS_CN_REL_BNG]`, `$[OS_FORE_OF_CN]`, ...), the
//! `$[HASH]` macros of every behaviour's flags, and the `post_mortem` of a death life event
//! (IvPContactBehavior's `rng=..#bng=..` after the reason).

use helm::testing::{self, texts};
use helm::{Helm, Posting};

fn helm_with(bhv: &str) -> Helm {
    testing::engaged(bhv, &[])
}

/// One iteration at `t`: ownship still at the origin heading north, `mail` (string values).
fn step(h: &mut Helm, t: f64, mail: &[(&str, String)]) -> Vec<Posting> {
    testing::step(h, t, (0.0, 0.0, 0.0, 0.0), mail)
}

const AVOID: &str = "\
Behavior = BHV_AvoidCollision
{
  name       = avd_
  pwt        = 300
  updates    = CONTACT_INFO
  templating = spawn
             contact = to-be-set
    on_no_contact_ok = true
         extrapolate = true
               decay = 30,60
      pwt_outer_dist = 100
      pwt_inner_dist = 40
      completed_dist = 50
   min_util_cpa_dist = 10
   max_util_cpa_dist = 30
           pwt_grade = linear
  cnflag = @cpa CPA_RANGE = $[RANGE]
  cnflag = @os_passed_cn PASSED = bng=$[OS_CN_REL_BNG],fore=$[OS_FORE_OF_CN],star=$[OS_STAR_OF_CN]
  cnflag = @os_passed_cn_star PASSED_STAR = true
  cnflag = @os_passed_cn_port PASSED_PORT = true
  cnflag = @cn_passed_os CN_PASSED = true
  cnflag = @os_crossed_cn CROSSED = true
  cnflag = <30 CLOSE = roc=$[ROC],tgt=$[CN_OS_REL_BNG],spd=$[CN_SPD_IN_OS_POS],brate=$[BNG_RATE]
}
";

/// The contact bob crossing ownship's bow 20 m ahead, heading east at 5 m/s: at x = -40
/// when `t = 1` (44.7 m away, inside 1.1 x completed_dist), at x = 0 when `t = 9`.
fn report(t: f64) -> String {
    let x = -40.0 + 5.0 * (t - 1.0);
    format!("NAME=bob,TYPE=kayak,X={x},Y=20,SPD=5,HDG=90,DEP=0,TIME={t}")
}

#[test]
fn contact_event_flags_macros_and_the_post_mortem() {
    let mut h = helm_with(AVOID);
    assert!(h.config_errors().is_empty(), "{:?}", h.config_errors());
    step(&mut h, 0.0, &[]);
    let mut t = 1.0;
    step(
        &mut h,
        t,
        &[
            ("NODE_REPORT", report(t)),
            ("CONTACT_INFO", "name=bob # contact=bob".into()),
        ],
    );
    assert_eq!(h.behavior_names(), ["avd_bob"]);
    let mut seen: Vec<(f64, String, String)> = Vec::new();
    let mut death = None;
    while t < 60.0 {
        t += 0.25;
        let p = step(&mut h, t, &[("NODE_REPORT", report(t))]);
        for var in [
            "CPA_RANGE",
            "PASSED",
            "PASSED_STAR",
            "PASSED_PORT",
            "CN_PASSED",
            "CROSSED",
            "CLOSE",
        ] {
            for v in texts(&p, var) {
                seen.push((t, var.to_string(), v));
            }
        }
        if let Some(ev) = texts(&p, "IVPHELM_LIFE_EVENT").pop() {
            death = Some((t, ev));
            break;
        }
    }
    let of = |var: &str| -> Vec<(f64, String)> {
        seen.iter()
            .filter(|s| s.1 == var)
            .map(|s| (s.0, s.2.clone()))
            .collect()
    };
    // The contact passes ownship's bow at x = 0, t = 9: seen from the contact (heading 90),
    // ownship's relative bearing goes from below 90 (ahead of its beam) to above (behind);
    // at x = 0 it is exactly 90, both fore and aft, so the change shows at t = 9. Ownship is
    // on its starboard side (south of an eastbound contact). The contact stays ahead of
    // ownship (north of it): no @cn_passed_os. The @*crossed* tags are never posted at
    // a2a9b716.
    let passed = of("PASSED");
    assert_eq!(passed, [(9.0, "bng=0,fore=true,star=true".to_string())]);
    assert_eq!(of("PASSED_STAR").len(), 1);
    assert!(of("PASSED_PORT").is_empty());
    assert!(of("CN_PASSED").is_empty());
    assert!(of("CROSSED").is_empty());
    // @cpa: the range has fallen (within 5 cm) over the history and now rose by at least
    // 5 cm: 20 at t = 9, 20.039 at 9.25 (+0.039), 20.156 at 9.5 (+0.117 over 9.25): posted
    // once, at 9.5, with the range then (a solo macro: posted as a number).
    let cpa = of("CPA_RANGE");
    assert_eq!(cpa, [(9.5, "20.2".to_string())]);
    // <30: every running iteration within 30 m (|x| <= 22.36: t from 4.75 to 13.25), with
    // the relative-geometry macros. At t = 7 the contact is at (-10, 20): from it, ownship
    // bears 153.43, relative to its heading 90 (the target angle) 63.43; its speed toward
    // ownship 5 cos 63.43 = 2.24, which is the rate of closure (ownship is still). The
    // bearing rate (CPXEngine::bearingRate): the line of sight's tangent is relAng(os, cn)
    // - 90 = 243.43; the contact's heading is 153.43 off it, 5 cos 153.43 = -4.47 m/s
    // across, times -360 / (2 pi 22.36 m) = 11.46 deg/s.
    let close = of("CLOSE");
    assert_eq!(close.len(), 35);
    assert_eq!(close[0].0, 4.75);
    let at7 = close.iter().find(|c| c.0 == 7.0).expect("close at t=7");
    assert_eq!(at7.1, "roc=2.2,tgt=63.4,spd=2.2,brate=11.5");
    // Past 55 m (1.1 x completed_dist) the behaviour completes and dies, its post mortem
    // the range and bearing from ownship to the contact (IvPContactBehavior::setComplete).
    let (td, ev) = death.expect("the behaviour completes");
    assert!(
        ev.contains("bname=avd_bob, btype=BHV_AvoidCollision, event=death"),
        "{ev}"
    );
    let pm = ev
        .split(", post_mortem=")
        .nth(1)
        .and_then(|s| s.split(",iter=").next())
        .unwrap_or_else(|| panic!("no post mortem in {ev}"));
    // The range at completion: the first report with range >= 55 (x >= 51.24, t = 19.25).
    assert_eq!(td, 19.25);
    let x = -40.0 + 5.0 * (td - 1.0);
    let rng = x.hypot(20.0);
    let bng = geometry::relative_angle(0.0, 0.0, x, 20.0);
    let expect = format!(
        "rng={}#bng={}",
        moos_types::fmt::compact_string(rng, 1),
        moos_types::fmt::compact_string(bng, 1)
    );
    assert_eq!(pm, expect);
}

#[test]
fn hash_macros_are_random_characters_the_same_run_to_run() {
    let bhv = "\
Behavior = BHV_ConstantHeading
{
  name     = hdg
  heading  = 90
  duration = no-time-limit
  runflag  = H = $[HASH]-$[HASH]-$[HASH3]-$(HASH6)
}
";
    // (The helm decides from its first second on.)
    let first = |h: &mut Helm| {
        step(h, 0.0, &[]);
        texts(&step(h, 1.0, &[]), "H")
    };
    let a = first(&mut helm_with(bhv));
    let b = first(&mut helm_with(bhv));
    assert_eq!(a.len(), 1, "{a:?}");
    assert_eq!(a, b, "deterministic");
    let parts: Vec<&str> = a[0].split('-').collect();
    assert_eq!(parts.len(), 4);
    // One value per macro and expansion; HASH and HASH6 are different macros.
    assert_eq!(parts[0], parts[1]);
    assert_eq!(parts[0].len(), 6);
    assert_eq!(parts[2].len(), 3);
    assert_eq!(parts[3].len(), 6);
    assert_ne!(parts[0], parts[3]);
    let ok = |c: char| c.is_ascii_alphanumeric() && c != 'o' && c != 'O';
    assert!(a[0].chars().all(|c| c == '-' || ok(c)), "{}", a[0]);
}
