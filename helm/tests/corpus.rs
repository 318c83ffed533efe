//! Every `.bhv` file of the mission corpus configures a helm without panicking; the ones that
//! use only implemented behaviours and need no nsplug values run a few iterations.

use helm::config::Globals;
use helm::{Helm, Mail};
use mission::source::SourceMap;

#[test]
fn every_corpus_behavior_file_configures() {
    let root = test_support::mission_file("");
    let files = test_support::files_with_ext(&root, &["bhv"]);
    assert!(
        files.len() > 20,
        "expected the corpus .bhv files, found {}",
        files.len()
    );
    let globals = Globals {
        lat_origin: Some("0".into()),
        long_origin: Some("0".into()),
        community: Some("abe".into()),
    };
    let params = [
        ("domain", "course:0:359:360"),
        ("domain", "speed:0:5:26"),
        ("domain", "depth:0:500:101:optional"),
        ("start_engaged", "true"),
    ];
    let mut clean = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let bhv = mission::bhv::parse_bhv(&SourceMap::from_text(&f.display().to_string(), &text));
        let mut helm = Helm::from_parsed(&params, &globals, &bhv);
        if helm.config_errors().is_empty() {
            clean.push(f.strip_prefix(&root).unwrap().display().to_string());
        }
        // The only acceptable reasons: a behaviour type coug does not implement, nsplug macros
        // left unexpanded (this test does not run nsplug), or both branches of an nsplug
        // `#ifdef` defining the same behaviour. Every real parameter value is accepted.
        for e in helm.config_errors() {
            let m = e.to_string();
            // m3_casar's `active_grade` (in a BHV_AvoidCollision) is a parameter no
            // behaviour of MOOS-IvP a2a9b716 has: pHelmIvP refuses it as well; so are
            // x1_legs's `legflag` and `mid_pct`, which its BHV_LegRun does not know.
            assert!(
                m.contains("unknown behavior type")
                    || m.contains("$(")
                    || m.contains("duplicate behavior name")
                    || m.contains("active_grade = linear (unknown parameter `active_grade`)")
                    || m.contains("(unknown parameter `legflag`)")
                    || m.contains("(unknown parameter `mid_pct`)")
                    // m2_berta_obstacles gives BHV_AvoidObstacleV24 a `buffer_dist`, which
                    // only the older BHV_AvoidObstacle takes: refused by pHelmIvP as well.
                    || (m.contains("buffer_dist = 3 (unknown parameter `buffer_dist`)")
                        && f.ends_with("m2_berta_obstacles/meta_vehicle.bhv")),
                "{m}"
            );
        }
        // Malconfigured or not, iterating with mail never panics.
        for k in 0..8 {
            let t = f64::from(k) * 0.5;
            helm.on_mail(&[
                Mail::new("NAV_X", 10.0, t),
                Mail::new("NAV_Y", -20.0, t),
                Mail::new("NAV_HEADING", 90.0, t),
                Mail::new("NAV_SPEED", 1.0, t),
                Mail::new("NAV_DEPTH", 3.0, t),
                Mail::new("DEPLOY", "true", t),
                Mail::new("MOOS_MANUAL_OVERRIDE", "false", t),
            ]);
            helm.iterate(t);
        }
    }
    for expected in [
        "s1_alpha/alpha.bhv",
        "s2_bravo/bravo.bhv",
        "s3_charlie/charlie.bhv",
    ] {
        assert!(
            clean.iter().any(|c| c == expected),
            "{expected} not in {clean:?}"
        );
    }
}
