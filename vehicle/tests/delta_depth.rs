//! Depth control of the real `s4_delta` mission: its own `uSimMarine` and `pMarinePID` blocks,
//! run through the MOOS adapters at their AppTicks (in lockstep, the simulator first at a
//! shared instant as in delta's Antler order), with helm set-points at the helm's AppTick.
//!
//! delta's blocks pair a fast elevator (`max_depth_rate = 5`, ten times the default) with a
//! stiff pitch loop (`pitch_pid_kp = 1.5`). The simulator turns every iteration's elevator
//! into a pitch change, so the pitch loop only behaves when it sees every pitch the simulator
//! makes: the legacy `uSimMarine` that delta launches posts the navigation on every
//! iteration. (Posting every second iteration, as `uSimMarineV22` does, left the vehicle
//! at 3.8 m of a 5 m set-point, and overshooting 7 m by 1.4 m in the full mission.)
//!
//! Tolerance: 0.5 m, half of `BHV_MaxDepth`'s `tolerance = 1` in delta.bhv, so a vehicle
//! holding a depth that closely never leaves the band the mission itself accepts.

mod common;

use moos_types::ByteString;

use vehicle::pid::{MarinePid, PidConfig};
use vehicle::sim::{SimConfig, Simulator};
use vehicle::{Posting, ValueRef};

const TOL: f64 = 0.5;

fn deliver(postings: &[(Posting, f64)], mut to: impl FnMut(&str, ValueRef<'_>, f64)) {
    for (p, t) in postings {
        to(&p.key, p.value.as_ref(), *t);
    }
}

/// `AppTick` of a block.
fn app_tick(block: &[(String, String)]) -> f64 {
    block
        .iter()
        .find(|(k, _)| k.eq_ignore_ascii_case("apptick"))
        .and_then(|(_, v)| v.parse().ok())
        .expect("AppTick in block")
}

/// The `speed = ...` values of delta.bhv's behaviours (comments stripped), ascending.
fn bhv_speeds() -> Vec<f64> {
    let text = test_support::mission_text("s4_delta/delta.bhv");
    let mut v: Vec<f64> = text
        .lines()
        .map(|l| l.split("//").next().unwrap_or(""))
        .filter_map(|l| {
            let (k, v) = l.split_once('=')?;
            (k.trim() == "speed").then(|| v.trim().parse::<f64>().ok())?
        })
        .collect();
    v.sort_by(f64::total_cmp);
    v.dedup();
    v
}

struct Delta {
    sim: Simulator,
    pid: MarinePid,
    hz: [f64; 3],
    ticks: [u64; 3],
    to_sim: Vec<(Posting, f64)>,
    to_pid: Vec<(Posting, f64)>,
    helm_vars: [ByteString; 3],
    /// (time, depth) after every simulator iteration.
    trace: Vec<(f64, f64)>,
}

impl Delta {
    /// delta's simulator (legacy `uSimMarine`, as its Antler block launches) and marine PID,
    /// with the manual override lifted at t = 0.
    fn new() -> Self {
        let text = test_support::mission_text("s4_delta/delta.moos");
        let run = common::process_config(&text, "ANTLER");
        let order: Vec<&str> = run
            .iter()
            .filter(|(k, _)| k.eq_ignore_ascii_case("run"))
            .map(|(_, v)| v.split('@').next().unwrap().trim())
            .collect();
        let pos = |app: &str| order.iter().position(|a| *a == app).expect(app);
        assert!(
            pos("uSimMarine") < pos("pMarinePID") && pos("pMarinePID") < pos("pHelmIvP"),
            "delta launches uSimMarine, pMarinePID, pHelmIvP in that order: {order:?}"
        );
        let sb = common::process_config(&text, "uSimMarine");
        let pb = common::process_config(&text, "pMarinePID");
        let hb = common::process_config(&text, "pHelmIvP");
        let sim_cfg = SimConfig {
            legacy: true,
            ..SimConfig::from_params(common::pairs(&sb)).expect("delta's uSimMarine block")
        };
        assert_eq!(sim_cfg.max_depth_rate_mps, 5.0, "delta's block as expected");
        let pid_cfg = PidConfig::from_params(common::pairs(&pb)).expect("delta's pMarinePID block");
        let mut pid = MarinePid::new(pid_cfg);
        pid.on_mail("MOOS_MANUAL_OVERRIDE", ValueRef::String("false"), 0.0);
        Delta {
            sim: Simulator::new(sim_cfg, None, 0.0),
            pid,
            hz: [app_tick(&sb), app_tick(&pb), app_tick(&hb)],
            ticks: [0; 3],
            to_sim: Vec::new(),
            to_pid: Vec::new(),
            helm_vars: ["DESIRED_HEADING", "DESIRED_SPEED", "DESIRED_DEPTH"].map(ByteString::from),
            trace: Vec::new(),
        }
    }

    /// Runs until `until` with the helm asking for this heading, speed and depth.
    fn run(&mut self, until: f64, hdg: f64, spd: f64, dep: f64) {
        let mut out = Vec::new();
        loop {
            // Next app: earliest tick, ties in launch order (simulator, PID, helm).
            let (app, t) = (0..3)
                .map(|i| (i, self.ticks[i] as f64 / self.hz[i]))
                .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
                .unwrap();
            if t > until {
                return;
            }
            self.ticks[app] += 1;
            out.clear();
            match app {
                0 => {
                    let sim = &mut self.sim;
                    deliver(&self.to_sim, |v, x, t| {
                        sim.on_mail(v, x, t);
                    });
                    self.to_sim.clear();
                    sim.iterate(t, &mut out);
                    self.trace.push((t, sim.state().depth));
                    self.to_pid.extend(out.drain(..).map(|p| (p, t)));
                }
                1 => {
                    let pid = &mut self.pid;
                    deliver(&self.to_pid, |v, x, t| pid.on_mail(v, x, t));
                    self.to_pid.clear();
                    pid.iterate(t, &mut out);
                    self.to_sim.extend(out.drain(..).map(|p| (p, t)));
                }
                _ => {
                    for (var, x) in self.helm_vars.iter().zip([hdg, spd, dep]) {
                        self.to_pid.push((Posting::double(var, x), t));
                    }
                }
            }
        }
    }

    /// Depths after time `from`.
    fn depths_after(&self, from: f64) -> impl Iterator<Item = f64> + '_ {
        self.trace
            .iter()
            .filter(move |(t, _)| *t >= from)
            .map(|(_, d)| *d)
    }
}

/// A step of DESIRED_DEPTH from 0 to `target` at 10 s; returns the run and the time the
/// depth first came within the tolerance.
fn dive(spd: f64, target: f64, secs: f64) -> (Delta, f64) {
    let mut d = Delta::new();
    let hdg = 180.0; // delta's start_heading
    d.run(10.0, hdg, spd, 0.0);
    assert!(
        d.depths_after(0.0).all(|x| x < 0.1),
        "stays at the surface while asked to"
    );
    d.run(10.0 + secs, hdg, spd, target);
    let reached = d
        .trace
        .iter()
        .find(|(_, x)| (x - target).abs() <= TOL)
        .map(|(t, _)| *t)
        .unwrap_or_else(|| {
            let max = d.depths_after(0.0).fold(0.0, f64::max);
            panic!("never within {TOL} m of {target} m at {spd} m/s (max depth {max:.2})")
        });
    (d, reached)
}

#[test]
fn delta_dives_to_5m_at_survey_speed_and_holds_it() {
    // delta's survey (and return) waypoints run at 2 m/s.
    let speeds = bhv_speeds();
    assert!(speeds.contains(&2.0), "delta.bhv speeds {speeds:?}");
    let (d, reached) = dive(2.0, 5.0, 200.0);
    // With pitch limited to maxpitch = 15 deg, 2 m/s descends at most 0.52 m/s: ~10 s.
    assert!(
        reached < 10.0 + 30.0,
        "took {:.1} s to get within {TOL} m",
        reached - 10.0
    );
    let (lo, hi) = d
        .depths_after(reached)
        .fold((f64::MAX, f64::MIN), |(lo, hi), x| (lo.min(x), hi.max(x)));
    assert!(
        hi <= 5.0 + TOL && lo >= 5.0 - TOL,
        "after reaching 5 m it stays in {lo:.2}..{hi:.2} m"
    );
    // And on average right at it over the last minute.
    let last: Vec<f64> = d.depths_after(150.0).collect();
    let mean = last.iter().sum::<f64>() / last.len() as f64;
    assert!((mean - 5.0).abs() < 0.2, "mean depth {mean:.3}");
}

#[test]
fn delta_dive_to_7m_stays_above_8m_at_every_bhv_speed() {
    // delta's helm asks for 7 m (BHV_MaxDepth caps BHV_ConstantDepth's 50 m), while
    // loitering at 1.3 m/s and surveying / returning at 2 m/s.
    let speeds = bhv_speeds();
    assert!(speeds.len() >= 2, "delta.bhv speeds {speeds:?}");
    for spd in speeds {
        let (d, reached) = dive(spd, 7.0, 150.0);
        let max = d.depths_after(0.0).fold(0.0, f64::max);
        assert!(max <= 8.0, "{spd} m/s: max depth {max:.2}");
        let (lo, hi) = d
            .depths_after(reached + 30.0)
            .fold((f64::MAX, f64::MIN), |(lo, hi), x| (lo.min(x), hi.max(x)));
        assert!(
            hi <= 7.0 + TOL && lo >= 7.0 - TOL,
            "{spd} m/s: holds {lo:.2}..{hi:.2} m"
        );
    }
}
