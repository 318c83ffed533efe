//! `BHV_ABLE_FILTER` and `can_disable` (pHelmIvP's `BehaviorSet::applyAbleFilterMsg`,
//! IvPContactBehavior's `applyAbleFilter`, the `disabled` run state at a2a9b716), and the
//! completion of a spawned contact behaviour whose contact left the helm's ledger
//! (`IvPBehavior::isRunnable`).

use appcast::Note as AppcastNote;
use helm::testing::{self, texts};
use helm::{Helm, Posting, Value};

fn helm_with(bhv: &str) -> Helm {
    testing::engaged(bhv, &[])
}

/// One iteration at `t`: ownship at the origin heading north at 1 m/s, then `mail`.
fn step(h: &mut Helm, t: f64, mail: &[(&str, String)]) -> Vec<Posting> {
    testing::step(h, t, (0.0, 0.0, 0.0, 1.0), mail)
}

fn num(posts: &[Posting], var: &str) -> Option<f64> {
    posts
        .iter()
        .rev()
        .find(|p| p.key == var)
        .map(|p| match p.value {
            Value::Double(x) => x,
            _ => panic!("{var} is not a number"),
        })
}

/// A spawning AvoidCollision template (`can_disable` as given) and a constant speed.
fn avoid(can_disable: &str) -> String {
    format!(
        "\
Behavior = BHV_ConstantSpeed
{{
  name     = spd
  speed    = 1
  duration = no-time-limit
}}
Behavior = BHV_AvoidCollision
{{
  name        = avd_
  pwt         = 300
  updates     = CONTACT_INFO
  templating  = spawn
  contact     = to-be-set
  can_disable = {can_disable}
  pwt_outer_dist = 100
  pwt_inner_dist = 40
  completed_dist = 50
  endflag = AVD_DONE = $[CONTACT]
}}
"
    )
}

/// The contact `name` lying still 40 m north of ownship (inside the inner distance: the
/// behaviour is fully relevant and never completes on range).
fn report(name: &str, t: f64) -> String {
    format!("NAME={name},TYPE=kayak,X=0,Y=40,SPD=0,HDG=180,DEP=0,TIME={t}")
}

/// A helm with `avd_bob` spawned and active at t = 1.
fn spawned(can_disable: &str) -> Helm {
    let mut h = helm_with(&avoid(can_disable));
    step(&mut h, 0.0, &[]);
    let p = step(
        &mut h,
        1.0,
        &[
            ("NODE_REPORT", report("bob", 1.0)),
            ("CONTACT_INFO", "name=bob # contact=bob".into()),
        ],
    );
    assert_eq!(h.behavior_names(), ["spd", "avd_bob"]);
    assert!(
        texts(&p, "BHV_STATUS")
            .iter()
            .any(|s| s.starts_with("name=avd_bob,pwt=") && s.contains("state=active")),
        "{:?}",
        texts(&p, "BHV_STATUS")
    );
    h
}

fn status_of(p: &[Posting], name: &str) -> String {
    texts(p, "BHV_STATUS")
        .into_iter()
        .find(|s| s.starts_with(&format!("name={name},")))
        .unwrap_or_else(|| panic!("no BHV_STATUS of {name}"))
}

/// The state the latest report lists `name` in.
fn state(h: &Helm, name: &str) -> &'static str {
    let r = h.last_report();
    for (list, s) in [
        (&r.active, "active"),
        (&r.running, "running"),
        (&r.idle, "idle"),
        (&r.disabled, "disabled"),
        (&r.completed, "completed"),
    ] {
        if list.iter().any(|b| b.name == name) {
            return s;
        }
    }
    panic!("{name} is in no list");
}

fn ipf_from(p: &[Posting], name: &str) -> bool {
    texts(p, "BHV_IPF")
        .iter()
        .any(|s| s.contains(&format!(":{name},")) || s.contains(&format!(":{name}")))
}

#[test]
fn a_spawned_behaviour_is_disabled_and_enabled_again_by_postings() {
    let mut h = spawned("true");
    let p = step(
        &mut h,
        2.0,
        &[
            ("NODE_REPORT", report("bob", 2.0)),
            (
                "BHV_ABLE_FILTER",
                "action=disable, contact=bob, bhv_type=BHV_AvoidCollision".into(),
            ),
        ],
    );
    assert_eq!(
        status_of(&p, "avd_bob"),
        "name=avd_bob,state=disabled,updates=1/1"
    );
    assert!(!ipf_from(&p, "avd_bob"), "no function while disabled");
    assert_eq!(texts(&p, "IVPHELM_BHV_DISABLED"), ["avd_bob"]);
    assert_eq!(num(&p, "IVPHELM_BHV_DISABLED_CNT"), Some(1.0));
    assert_eq!(texts(&p, "IVPHELM_BHV_ACTIVE"), ["spd"]);
    let summary = texts(&p, "IVPHELM_SUMMARY").pop().unwrap();
    assert!(
        summary.contains(",active_bhvs=spd$")
            && summary.contains(",disabled_bhvs=avd_bob$2.00$1/1"),
        "{summary}"
    );
    let mut body = String::new();
    h.appcast_body(2.0, "open", &mut body);
    assert!(
        body.contains("Behaviors Disabled: --------- (1)\n  avd_bob [0.00]\n"),
        "{body}"
    );

    // Still disabled, unchanged lists are not posted again.
    let p = step(&mut h, 3.0, &[("NODE_REPORT", report("bob", 3.0))]);
    assert_eq!(state(&h, "avd_bob"), "disabled");
    assert!(texts(&p, "IVPHELM_BHV_DISABLED").is_empty());

    // A filter for another contact or another type leaves it as it is.
    for other in [
        "action=enable,contact=ann",
        "action=enable,contact=bob,bhv_type=BHV_AvdColregsV22",
        "action=enable,vsource=ais",
    ] {
        let p = step(
            &mut h,
            4.0,
            &[
                ("NODE_REPORT", report("bob", 4.0)),
                ("BHV_ABLE_FILTER", other.into()),
            ],
        );
        assert_eq!(state(&h, "avd_bob"), "disabled", "{other}");
        assert!(!ipf_from(&p, "avd_bob"));
    }

    let p = step(
        &mut h,
        5.0,
        &[
            ("NODE_REPORT", report("bob", 5.0)),
            ("BHV_ABLE_FILTER", "action=enable,contact=BOB".into()),
        ],
    );
    assert!(status_of(&p, "avd_bob").contains("state=active"));
    assert!(ipf_from(&p, "avd_bob"));
    assert_eq!(texts(&p, "IVPHELM_BHV_DISABLED"), [""]);
    assert_eq!(num(&p, "IVPHELM_BHV_DISABLED_CNT"), Some(0.0));
    assert!(h.take_appcast_notes().is_empty());
}

#[test]
fn without_can_disable_the_filter_is_ignored_even_when_malformed() {
    let mut h = spawned("false");
    for msg in [
        "action=disable,contact=bob",
        "action=disable,gen_type=safety",
    ] {
        let p = step(
            &mut h,
            2.0,
            &[
                ("NODE_REPORT", report("bob", 2.0)),
                ("BHV_ABLE_FILTER", msg.into()),
            ],
        );
        assert_eq!(state(&h, "avd_bob"), "active", "{msg}");
        assert!(ipf_from(&p, "avd_bob"));
        assert!(texts(&p, "IVPHELM_BHV_DISABLED").is_empty());
    }
    assert!(
        h.take_appcast_notes().is_empty(),
        "nobody found it malformed"
    );
}

#[test]
fn a_malformed_filter_is_a_run_warning_and_changes_nothing() {
    let mut h = spawned("true");
    for msg in [
        "action=disable,contact=bob,gen_type=safety",
        "action=disable",
        "action=able,contact=bob",
        "action=disable,contact=bob,contact=ann",
        "contact=bob",
    ] {
        let p = step(
            &mut h,
            2.0,
            &[
                ("NODE_REPORT", report("bob", 2.0)),
                ("BHV_ABLE_FILTER", msg.into()),
            ],
        );
        assert_eq!(state(&h, "avd_bob"), "active", "{msg}");
        assert!(ipf_from(&p, "avd_bob"), "{msg}");
        assert_eq!(
            h.take_appcast_notes(),
            [AppcastNote::Warning("Unhandled BHV_ABLE_FILTER".into())],
            "{msg}"
        );
    }
}

#[test]
fn a_blacklisted_contact_spawns_a_disabled_behaviour_and_expunge_completes() {
    let mut h = helm_with(&avoid("true"));
    step(&mut h, 0.0, &[]);
    step(
        &mut h,
        1.0,
        &[("BHV_ABLE_FILTER", "action=disable,contact=bob".into())],
    );
    assert!(h.contact_disabled("bob"));
    let p = step(
        &mut h,
        2.0,
        &[
            ("NODE_REPORT", report("bob", 2.0)),
            ("CONTACT_INFO", "name=bob # contact=bob".into()),
        ],
    );
    assert_eq!(h.behavior_names(), ["spd", "avd_bob"]);
    assert!(status_of(&p, "avd_bob").contains("state=disabled"));
    assert_eq!(texts(&p, "IVPHELM_BHV_DISABLED"), ["avd_bob"]);

    // `expunge` completes it: endflags, death, gone from the set.
    let p = step(
        &mut h,
        3.0,
        &[
            ("NODE_REPORT", report("bob", 3.0)),
            ("BHV_ABLE_FILTER", "action=expunge,contact=bob".into()),
        ],
    );
    assert_eq!(texts(&p, "AVD_DONE"), ["bob"]);
    assert!(status_of(&p, "avd_bob").contains("state=completed"));
    let death = texts(&p, "IVPHELM_LIFE_EVENT").pop().unwrap();
    assert!(
        death.contains("bname=avd_bob") && death.contains("event=death"),
        "{death}"
    );
    assert!(death.contains("post_mortem=rng=40#bng=0"), "{death}");
    assert_eq!(h.behavior_names(), ["spd"]);
}

#[test]
fn a_spawned_behaviour_whose_contact_leaves_the_ledger_completes() {
    // The file's own behaviour naming the contact stays; the spawned one completes.
    let bhv = format!(
        "{}
Behavior = BHV_AvoidCollision
{{
  name     = fixed
  contact  = bob
  pwt_outer_dist = 100
  pwt_inner_dist = 40
  completed_dist = 50
  endflag = FIXED_DONE = true
}}
",
        avoid("false")
    );
    let mut h = helm_with(&bhv);
    step(&mut h, 0.0, &[]);
    step(
        &mut h,
        1.0,
        &[
            ("NODE_REPORT", report("bob", 1.0)),
            ("CONTACT_INFO", "name=bob # contact=bob".into()),
        ],
    );
    assert_eq!(h.behavior_names(), ["spd", "fixed", "avd_bob"]);
    // bob reports no more. Named by behaviours, it stays in the ledger twice the 45 s
    // contact_max_age: its report of t = 1 is dropped once older than 90 s, at t = 91.5.
    let mut t = 1.0;
    let mut gone_at = None;
    while t < 100.0 {
        t += 0.5;
        let p = step(&mut h, t, &[]);
        if h.ledger().get("bob").is_none() {
            gone_at = Some(t);
            // Completed twice in the iteration (isRunnable before and after the hooks):
            // the repeatable endflags go out twice.
            assert_eq!(texts(&p, "AVD_DONE"), ["bob", "bob"]);
            assert!(texts(&p, "FIXED_DONE").is_empty(), "not spawned: stays");
            assert!(status_of(&p, "avd_bob").contains("state=completed"));
            let death = texts(&p, "IVPHELM_LIFE_EVENT").pop().unwrap();
            assert!(
                death.contains("bname=avd_bob, btype=BHV_AvoidCollision, event=death"),
                "{death}"
            );
            // The post mortem of setComplete(""): the range and bearing of the last update.
            assert!(death.contains("post_mortem=rng=40#bng=0,"), "{death}");
            break;
        }
        assert!(texts(&p, "AVD_DONE").is_empty(), "t={t}");
    }
    assert_eq!(gone_at, Some(91.5));
    assert_eq!(h.behavior_names(), ["spd", "fixed"]);
    // The file's behaviour carries on without its contact (a warning each iteration).
    step(&mut h, 92.0, &[]);
    assert_ne!(state(&h, "fixed"), "completed");
}
