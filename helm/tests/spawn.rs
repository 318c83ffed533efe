//! Behaviour spawning (`templating = spawn`), as pHelmIvP's BehaviorSet does it at
//! a2a9b716: requests on the template's `updates` variable with `name=` spawn instances
//! named `<prefix><name>`; a taken name is an update; completed instances leave the set;
//! a request with a bad parameter aborts with a warning.

use helm::testing::{self, texts};
use helm::{Helm, HelmState, Posting};

const TEMPLATE: &str = "\
Behavior = BHV_ConstantHeading
{
  name       = hdg_
  templating = spawn
  updates    = HDG_REQ
  duration   = no-time-limit
  heading    = 90
  spawnflag  = SPAWNED = $[BHVNAME]
  endflag    = ENDED = $[BHVNAME]
}
";

fn helm_with(bhv: &str) -> Helm {
    let params = [("domain", "course:0:359:360"), ("start_engaged", "true")];
    testing::from_text("s.bhv", bhv, &params)
}

/// One iteration at `t` with the navigation and `mail` (var, string value).
fn step(h: &mut Helm, t: f64, mail: &[(&str, &str)]) -> Vec<Posting> {
    testing::step(h, t, (0.0, 0.0, 0.0, 0.0), mail)
}

fn num(posts: &[Posting], var: &str) -> Option<f64> {
    posts.iter().rev().find(|p| p.key == var)?.value.as_f64()
}

#[test]
fn a_template_is_no_behaviour_until_a_request_with_a_name_spawns_one() {
    let mut h = helm_with(TEMPLATE);
    assert!(h.config_errors().is_empty(), "{:?}", h.config_errors());
    assert!(h.behavior_names().is_empty());
    // Its updates variable is registered at start-up.
    let p = step(&mut h, 0.0, &[]);
    assert!(texts(&p, "IVPHELM_REGISTER").contains(&"HDG_REQ".to_string()));
    let p = step(&mut h, 1.0, &[]);
    assert_eq!(texts(&p, "IVPHELM_ALLSTOP"), ["NothingToDo"]);
    // An update without a name is no spawning request.
    let p = step(&mut h, 1.25, &[("HDG_REQ", "heading=30")]);
    assert!(h.behavior_names().is_empty());
    assert!(texts(&p, "IVPHELM_LIFE_EVENT").is_empty());

    let p = step(&mut h, 1.5, &[("HDG_REQ", "name=a # heading=45")]);
    assert_eq!(h.behavior_names(), ["hdg_a"]);
    assert_eq!(
        texts(&p, "IVPHELM_LIFE_EVENT"),
        [
            "iter=0,time=1.50, bname=hdg_a, btype=BHV_ConstantHeading, event=spawn, seed=name=a # heading=45,iter=3"
        ]
    );
    assert_eq!(texts(&p, "SPAWNED"), ["hdg_a"]);
    // The new instance also reads the request as its first update (the C++ applies it
    // twice), and decides at once.
    assert_eq!(
        texts(&p, "IVPHELM_UPDATE_RESULT"),
        ["bhv=hdg_a,var=HDG_REQ,time=1.50,result=success,val=name=a # heading=45"]
    );
    assert_eq!(num(&p, "DESIRED_HEADING"), Some(45.0));
    assert_eq!(num(&p, "IVPHELM_BHV_CNT"), Some(1.0));
    assert_eq!(num(&p, "IVPHELM_BHV_CNT_EVER"), Some(1.0));
    let status = texts(&p, "BHV_STATUS");
    assert!(status[0].starts_with("name=hdg_a,pwt="), "{status:?}");
    assert!(
        status[0].ends_with("state=active,updates=1/1"),
        "{status:?}"
    );
}

#[test]
fn two_instances_coexist_and_a_taken_name_is_an_update() {
    let mut h = helm_with(TEMPLATE);
    step(&mut h, 0.0, &[]);
    step(&mut h, 1.0, &[("HDG_REQ", "name=a # heading=45")]);
    let p = step(&mut h, 1.25, &[("HDG_REQ", "name=b # heading=135")]);
    assert_eq!(h.behavior_names(), ["hdg_a", "hdg_b"]);
    assert_eq!(num(&p, "IVPHELM_BHV_CNT"), Some(2.0));
    assert_eq!(num(&p, "IVPHELM_BHV_CNT_EVER"), Some(2.0));
    assert_eq!(texts(&p, "SPAWNED"), ["hdg_b"]);
    // The first instance sees b's request as not for it.
    assert_eq!(
        texts(&p, "IVPHELM_UPDATE_RESULT"),
        [
            "bhv=hdg_a,var=HDG_REQ,time=1.25,result=name_mismatch,val=name=b # heading=135",
            "bhv=hdg_b,var=HDG_REQ,time=1.25,result=success,val=name=b # heading=135"
        ]
    );
    assert_eq!(texts(&p, "IVPHELM_BHV_ACTIVE"), ["hdg_a,hdg_b"]);
    // name=a again: no spawn, an update of hdg_a (pushed to 100 degrees, b keeps 135).
    let p = step(
        &mut h,
        1.5,
        &[("HDG_REQ", "name=a # heading=100 # pwt=300")],
    );
    assert_eq!(h.behavior_names(), ["hdg_a", "hdg_b"]);
    assert!(texts(&p, "IVPHELM_LIFE_EVENT").is_empty());
    assert!(texts(&p, "IVPHELM_BHVSET_WARNING").is_empty());
    assert_eq!(num(&p, "DESIRED_HEADING"), Some(100.0));
    // The full name is a spawn request too; it names hdg_a, so nothing is spawned.
    let p = step(&mut h, 1.75, &[("HDG_REQ", "name=hdg_a")]);
    assert_eq!(h.behavior_names(), ["hdg_a", "hdg_b"]);
    assert!(texts(&p, "IVPHELM_LIFE_EVENT").is_empty());
}

#[test]
fn an_instance_that_completes_leaves_the_set_and_its_name_is_free_again() {
    let bhv = TEMPLATE.replace("duration   = no-time-limit", "duration   = 2");
    let mut h = helm_with(&bhv);
    step(&mut h, 0.0, &[]);
    step(&mut h, 1.0, &[("HDG_REQ", "name=a")]);
    let mut t = 1.0;
    let death = loop {
        t += 0.25;
        assert!(t < 5.0, "never completed");
        let p = step(&mut h, t, &[]);
        let ev = texts(&p, "IVPHELM_LIFE_EVENT");
        if !ev.is_empty() {
            assert_eq!(texts(&p, "ENDED"), ["hdg_a"]);
            assert_eq!(num(&p, "IVPHELM_COMPLETED_COUNT"), Some(1.0));
            break ev;
        }
    };
    assert!(
        death[0].ends_with(", bname=hdg_a, btype=BHV_ConstantHeading, event=death,iter=9"),
        "{death:?}"
    );
    assert!((3.0..=3.5).contains(&t), "completed at {t}");
    assert!(h.behavior_names().is_empty());
    let p = step(&mut h, t + 0.25, &[("HDG_REQ", "name=a")]);
    assert_eq!(h.behavior_names(), ["hdg_a"]);
    assert_eq!(num(&p, "IVPHELM_BHV_CNT_EVER"), Some(2.0));
}

#[test]
fn a_request_with_a_bad_parameter_aborts_with_warnings() {
    let mut h = helm_with(TEMPLATE);
    step(&mut h, 0.0, &[]);
    let p = step(&mut h, 1.0, &[("HDG_REQ", "name=c # heading=abc")]);
    assert!(h.behavior_names().is_empty());
    assert_eq!(
        texts(&p, "IVPHELM_LIFE_EVENT"),
        [
            "iter=0,time=1.00, bname=hdg_c, btype=BHV_ConstantHeading, event=abort, seed=name=c # heading=abc,iter=1"
        ]
    );
    // As the C++ words them: the pair as split from the request (blanks kept), then the
    // name nobody has.
    assert_eq!(
        texts(&p, "IVPHELM_BHVSET_WARNING"),
        [
            "0:Failed to spawn hdg_c. Bad config:  heading=abc",
            "1:Behavior named [c] or [hdg_c] not found or spawned."
        ]
    );
    assert!(texts(&p, "SPAWNED").is_empty());
    assert_eq!(
        h.state(),
        HelmState::Drive,
        "a bad request is no configuration error"
    );
    let notes = h.take_appcast_notes();
    assert!(
        notes
            .iter()
            .any(|n| format!("{n:?}").contains("Failed to spawn hdg_c"))
    );
    // A name MOOS does not accept aborts the same way.
    let p = step(&mut h, 1.25, &[("HDG_REQ", "name=c d")]);
    assert!(texts(&p, "IVPHELM_LIFE_EVENT")[0].contains("event=abort"));
    assert!(h.behavior_names().is_empty());
}

#[test]
fn max_spawnings_caps_the_instances_without_a_warning() {
    let bhv = TEMPLATE.replace(
        "templating = spawn",
        "templating = spawn\n  max_spawnings = 1",
    );
    let mut h = helm_with(&bhv);
    step(&mut h, 0.0, &[]);
    step(&mut h, 1.0, &[("HDG_REQ", "name=a")]);
    let p = step(&mut h, 1.25, &[("HDG_REQ", "name=b")]);
    assert_eq!(h.behavior_names(), ["hdg_a"]);
    assert!(texts(&p, "IVPHELM_LIFE_EVENT").is_empty());
    assert!(texts(&p, "IVPHELM_BHVSET_WARNING").is_empty());
    let mut body = String::new();
    h.appcast_body(1.25, "open", &mut body);
    assert!(
        body.contains(
            "Behaviors Spawnable: --------- (1)\n  BHV_ConstantHeading::hdg_ (Spawned:1/1)\n"
        ),
        "{body}"
    );
}

#[test]
fn a_bad_template_is_a_configuration_error_and_clone_keeps_the_entry() {
    let bad = TEMPLATE.replace("heading    = 90", "heading    = east");
    let h = helm_with(&bad);
    assert_eq!(h.state(), HelmState::Malconfig);
    let clone = TEMPLATE.replace("templating = spawn", "templating = clone");
    let mut h = helm_with(&clone);
    assert_eq!(h.behavior_names(), ["hdg_"]);
    step(&mut h, 0.0, &[]);
    step(&mut h, 1.0, &[("HDG_REQ", "name=x")]);
    assert_eq!(h.behavior_names(), ["hdg_", "hdg_x"]);
}
