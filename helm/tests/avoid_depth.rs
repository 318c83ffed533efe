//! BHV_AvoidCollision with `collision_depth` in a closed loop on virtual time: the helm with a
//! course, speed and depth domain drives a simple vehicle (turn, speed and depth rates
//! limited) toward a contact that comes head-on at the surface. Below the collision depth
//! every course is safe, so the helm keeps its course and dives under the contact instead of
//! turning away; without `collision_depth` it turns. The weights make leaving the track
//! dearer than leaving the surface (waypoint 400, constant depth 20, avoidance 300): with
//! the waypoint at 200 and the depth at 50 the helm prefers to turn at the surface.

mod common;

use common::Vehicle;
use helm::{Helm, Mail, Value, testing};

fn bhv(depth_line: &str) -> String {
    format!(
        "\
Behavior = BHV_Waypoint
{{
  name   = transit
  pwt    = 400
  speed  = 2
  points = 0,400
}}
Behavior = BHV_ConstantDepth
{{
  name     = surface
  pwt      = 20
  depth    = 0
  duration = no-time-limit
}}
Behavior = BHV_AvoidCollision
{{
  name              = avd_bob
  pwt               = 300
  contact           = bob
  pwt_outer_dist    = 100
  pwt_inner_dist    = 40
  completed_dist    = 500
  min_util_cpa_dist = 10
  max_util_cpa_dist = 30
  {depth_line}
}}
"
    )
}

fn helm(depth_line: &str) -> Helm {
    testing::engaged(&bhv(depth_line), &[("domain", "depth:0:40:41")])
}

/// One run of 120 s: ownship from the origin north at 2 m/s, diving at most 1 m/s; bob
/// from (0, 240) heading south at 2 m/s at the surface. Returns, at each step, ownship's
/// `(t, x, y, depth)` and bob's range.
fn run(depth_line: &str) -> Vec<(f64, f64, f64, f64, f64)> {
    let mut h = helm(depth_line);
    let mut v = Vehicle::new(0.0, 0.0, 0.0);
    v.speed = 2.0;
    let (mut depth, mut des_depth) = (0.0f64, 0.0f64);
    let (mut des_h, mut des_s) = (0.0, 2.0);
    let dt = 0.25;
    let mut t = 0.0;
    let mut track = Vec::new();
    while t < 120.0 {
        v.step(dt, des_h, des_s);
        depth += (des_depth - depth).clamp(-dt, dt);
        t += dt;
        let (bx, by) = (0.0, 240.0 - 2.0 * t);
        let mut mail = v.nav_mail(t);
        mail.push(Mail::new("NAV_DEPTH", depth, t));
        mail.push(Mail::new(
            "NODE_REPORT",
            format!("NAME=bob,TYPE=kayak,X={bx},Y={by},SPD=2,HDG=180,DEP=0,TIME={t}").as_str(),
            t,
        ));
        h.on_mail(&mail);
        for p in h.iterate(t) {
            match (&*p.key, &p.value) {
                ("DESIRED_HEADING", Value::Double(x)) => des_h = *x,
                ("DESIRED_SPEED", Value::Double(x)) => des_s = *x,
                ("DESIRED_DEPTH", Value::Double(x)) => des_depth = *x,
                _ => {}
            }
        }
        track.push((t, v.x, v.y, depth, (v.x - bx).hypot(v.y - by)));
    }
    track
}

#[test]
fn collision_depth_dives_under_the_contact_instead_of_turning() {
    let with = run("collision_depth = 10");
    let without = run("");
    let closest = |tr: &[(f64, f64, f64, f64, f64)]| {
        *tr.iter()
            .min_by(|a, b| a.4.total_cmp(&b.4))
            .expect("a track")
    };
    let (t, x, _, z, r) = closest(&with);
    eprintln!("with collision_depth: closest {r:.2} m at t={t:.2}, x={x:.2}, depth {z:.2}");
    // Ownship kept its course (the contact passes overhead) and was at or below the collision
    // depth when they met.
    assert!(r < 5.0, "no turn away: closest {r:.2} m");
    assert!(
        z >= 10.0,
        "below the collision depth at the closest approach: {z:.2} m"
    );
    // It stayed near the surface until the contact came within pwt_outer_dist.
    let first_dive = with.iter().find(|s| s.3 > 0.5).expect("a dive");
    assert!(first_dive.4 <= 100.0, "dived at range {:.1}", first_dive.4);
    // Without collision_depth the helm turns away: every approach stays beyond 10 m and it
    // never leaves the surface.
    let (t0, _, _, z0, r0) = closest(&without);
    eprintln!("without: closest {r0:.2} m at t={t0:.2}, depth {z0:.2}");
    assert!(r0 > 10.0, "without collision_depth: {r0:.2} m");
    assert!(without.iter().all(|s| s.3 == 0.0));
}
