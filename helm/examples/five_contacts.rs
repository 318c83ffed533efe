//! A deterministic driver for the helm's cost with contacts: the alpha helm plus a contact
//! behaviour template (BHV_AvoidCollision, or BHV_AvdColregsV22 with a third argument
//! `colregs`; a fourth argument `refinery` adds `use_refinery = true`), driven to mid-survey, then `K` contacts (second argument, default 5) around
//! the vehicle, each reported every iteration and each with a spawned behaviour, then `N`
//! measured iterations (first argument, default 2000).
//!
//! ```text
//! cargo build --release -p helm --example five_contacts
//! valgrind --tool=callgrind target/release/examples/five_contacts 2000 5
//! valgrind --tool=callgrind target/release/examples/five_contacts 2000 0
//! valgrind --tool=callgrind target/release/examples/five_contacts 2000 5 colregs
//! valgrind --tool=callgrind target/release/examples/five_contacts 2000 5 avoid refinery
//! ```
//! The difference of the two instruction counts over `N` is the contacts' cost per iteration.

#[path = "../benches/common/mod.rs"]
#[allow(dead_code)]
mod common;
use common::nav;
use helm::{Helm, Mail};
use mission::source::SourceMap;

/// The contact behaviour's block after its `Behavior =` line, the same for both types
/// (BHV_AvdColregsV22 takes `pwt_grade` too, at its default).
const TEMPLATE: &str = "
{
  name       = avd_
  pwt        = 300
  condition  = DEPLOY = true
  updates    = CONTACT_INFO
  templating = spawn
             contact = to-be-set
    on_no_contact_ok = true
      pwt_outer_dist = 150
      pwt_inner_dist = 40
      completed_dist = 300
   min_util_cpa_dist = 10
   max_util_cpa_dist = 30
}
";

fn main() {
    let mut args = std::env::args().skip(1);
    let n: usize = args.next().map_or(2000, |a| a.parse().expect("iterations"));
    let k: usize = args.next().map_or(5, |a| a.parse().expect("contacts"));
    let kind = match args.next().as_deref() {
        None | Some("avoid") => "BHV_AvoidCollision",
        Some("colregs") => "BHV_AvdColregsV22",
        Some(other) => panic!("third argument: `avoid` or `colregs`, not `{other}`"),
    };
    let refinery = match args.next().as_deref() {
        None => "",
        Some("refinery") => "\n  use_refinery = true",
        Some(other) => panic!("fourth argument: `refinery`, not `{other}`"),
    };
    let template = TEMPLATE.replacen('{', &format!("{{{refinery}"), 1);
    let moos = mission::moos::parse_moos(&SourceMap::from_text(
        "alpha.moos",
        &test_support::mission_text("s1_alpha/alpha.moos"),
    ));
    let bhv_text =
        test_support::mission_text("s1_alpha/alpha.bhv") + "\nBehavior = " + kind + &template;
    let bhv = mission::bhv::parse_bhv(&SourceMap::from_text("alpha.bhv", &bhv_text));
    let mut helm = Helm::from_mission(&moos.value, &bhv);
    assert!(
        helm.config_errors().is_empty(),
        "{:?}",
        helm.config_errors()
    );
    // Mid-survey with a point-mass vehicle, as the `iteration` bench.
    let (mut t, (x, y, h, v)) = common::fly_to_mid_survey(&mut helm);
    let dt = 0.25;
    // K contacts 40..120 m away, each heading for the vehicle at 1.5 m/s.
    let contacts: Vec<(String, f64, f64, f64)> = (0..k)
        .map(|i| {
            let bearing = 360.0 * i as f64 / k.max(1) as f64 + 10.0;
            let range = 40.0 + 20.0 * i as f64;
            let cx = x + bearing.to_radians().sin() * range;
            let cy = y + bearing.to_radians().cos() * range;
            (format!("c{i}"), cx, cy, (bearing + 180.0) % 360.0)
        })
        .collect();
    let reports = |t: f64| -> Vec<Mail> {
        contacts
            .iter()
            .map(|(name, cx, cy, ch)| {
                let r = format!("NAME={name},TYPE=kayak,X={cx},Y={cy},SPD=1.5,HDG={ch},TIME={t}");
                Mail::new("NODE_REPORT", r.as_str(), t)
            })
            .collect()
    };
    t += dt;
    helm.on_mail(&reports(t));
    for (name, ..) in &contacts {
        let spawn = format!("name={name} # contact={name}");
        helm.on_mail(&[Mail::new("CONTACT_INFO", spawn.as_str(), t)]);
    }
    helm.iterate(t);
    // The measured part: nav and the contacts' reports in, one iteration.
    let mut posts = 0usize;
    let mut functions = 0usize;
    for _ in 0..n {
        t += dt;
        helm.on_mail(&nav(x, y, h, v, t));
        helm.on_mail(&reports(t));
        for p in helm.iterate(t) {
            posts += 1;
            if &*p.key == "BHV_IPF" && p.value.as_str().is_some_and(|s| s.contains("avd_c")) {
                functions += 1;
            }
        }
    }
    println!(
        "{n} iterations, {k} contacts, {posts} postings, {functions} BHV_IPF parts from the {kind} behaviours"
    );
}
