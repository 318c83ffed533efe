//! pHelmIvP's `TURN_RATE` (HelmIvP `updatePlatModel` at a2a9b716): each decision iteration
//! with `NAV_X/Y/HEADING/SPEED` known the platform model is made and the mean heading change
//! of the last five seconds is posted, a double, whatever the model (holonomic by default),
//! before anything the behaviours post.

use helm::config::Globals;
use helm::{Helm, Mail, Posting, Value};
use mission::source::SourceMap;

const BHV: &str = "\
initialize DEPLOY = true
Behavior = BHV_ConstantHeading
{
  name      = hdg
  condition = DEPLOY = true
  heading   = 45
  duration  = no-time-limit
}
";

fn helm(params: &[(&str, &str)]) -> Helm {
    let parsed = mission::bhv::parse_bhv(&SourceMap::from_text("t.bhv", BHV));
    let mut p = vec![("domain", "course:0:359:360"), ("domain", "speed:0:4:41")];
    p.extend_from_slice(params);
    let g = Globals {
        lat_origin: Some("43.8253".into()),
        long_origin: Some("-70.3304".into()),
        community: Some("abe".into()),
    };
    Helm::from_parsed(&p, &g, &parsed)
}

fn nav(h: &mut Helm, t: f64, hdg: f64) {
    h.on_mail(&[
        Mail::new("NAV_X", 0.0, t),
        Mail::new("NAV_Y", 0.0, t),
        Mail::new("NAV_HEADING", hdg, t),
        Mail::new("NAV_SPEED", 1.0, t),
    ]);
}

fn turn_rates(posts: &[Posting]) -> Vec<f64> {
    posts
        .iter()
        .filter(|p| &*p.key == "TURN_RATE")
        .map(|p| match &p.value {
            Value::Double(d) => *d,
            v => panic!("TURN_RATE is a double, not {v:?}"),
        })
        .collect()
}

fn drive(h: &mut Helm, t: f64, hdg: f64) -> Vec<Posting> {
    nav(h, t, hdg);
    h.on_mail(&[Mail::new("MOOS_MANUAL_OVERRIDE", "false", t).from("uPokeDB")]);
    h.iterate(t).to_vec()
}

#[test]
fn turn_rate_is_the_mean_heading_change_of_the_last_five_seconds() {
    let mut h = helm(&[]);
    // Before the nav solution and in the first second: no decision, no TURN_RATE.
    let posts = h.iterate(0.0).to_vec();
    assert!(turn_rates(&posts).is_empty());
    let posts = drive(&mut h, 0.75, 10.0);
    assert!(turn_rates(&posts).is_empty(), "first second");
    // The first decision: one heading in the history, no change yet: 0.
    assert_eq!(turn_rates(&drive(&mut h, 1.0, 10.0)), vec![0.0]);
    // 10 then 20 (starboard): +10 over one change.
    assert_eq!(turn_rates(&drive(&mut h, 2.0, 20.0)), vec![10.0]);
    // 20 then 15 (port) is -5; with 10 then 20: (10 - 5) / 2.
    assert_eq!(turn_rates(&drive(&mut h, 3.0, 15.0)), vec![2.5]);
    // Across north: 15 -> 355 is -20: (10 - 5 - 20) / 3 = -5.
    assert_eq!(turn_rates(&drive(&mut h, 4.0, 355.0)), vec![-5.0]);
    // Unchanged values are posted again every iteration (no duplicate filter): the same
    // heading adds a change of 0: (10 - 5 - 20 + 0) / 4.
    assert_eq!(turn_rates(&drive(&mut h, 5.0, 355.0)), vec![-3.75]);
    // At 6.5 the heading of 1.0 is older than 5 s and leaves: the history is 355@6.5,
    // 355@5, 355@4, 15@3, 20@2 (4.5 s old): changes 0, 0, -20, -5.
    assert_eq!(turn_rates(&drive(&mut h, 6.5, 355.0)), vec![-6.25]);
    // Exactly 5 s old stays (the C++ prunes only what is older): at 7.0 the heading of 2.0
    // is kept: changes 0, 0, 0, -20, -5.
    assert_eq!(turn_rates(&drive(&mut h, 7.0, 355.0)), vec![-5.0]);
}

#[test]
fn turn_rate_comes_first_and_with_any_platform_model() {
    for params in [vec![], vec![("pmgen", "alg=dubins#radius=10")]] {
        let mut h = helm(&params);
        let _ = drive(&mut h, 0.0, 90.0);
        let posts = drive(&mut h, 1.0, 90.0);
        let keys: Vec<&str> = posts.iter().map(|p| &*p.key).collect();
        let at = keys.iter().position(|k| *k == "TURN_RATE").expect("posted");
        for later in ["IVPHELM_ITER", "BHV_IPF", "IVPHELM_LIFE_EVENT"] {
            let i = keys.iter().position(|k| *k == later);
            assert!(i.is_some_and(|i| at < i), "{later}: {keys:?}");
        }
        assert_eq!(
            keys[at - 1],
            "IVPHELM_LEDGER_SUMMARY",
            "right after the ledger summary: {keys:?}"
        );
        assert_eq!(turn_rates(&posts), vec![0.0]);
    }
}

#[test]
fn no_turn_rate_without_control() {
    let mut h = helm(&[]);
    let _ = drive(&mut h, 0.0, 90.0);
    assert_eq!(turn_rates(&drive(&mut h, 1.0, 90.0)).len(), 1);
    nav(&mut h, 2.0, 100.0);
    h.on_mail(&[Mail::new("MOOS_MANUAL_OVERRIDE", "true", 2.0).from("uPokeDB")]);
    let posts = h.iterate(2.0).to_vec();
    assert!(
        turn_rates(&posts).is_empty(),
        "manual override: no decision"
    );
    // The heading of 2.0 never joined the history: back in control at 3.0, 90 -> 110.
    assert_eq!(turn_rates(&drive(&mut h, 3.0, 110.0)), vec![20.0]);
}
