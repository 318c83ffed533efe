//! uSimMarineV22 (truth under `SIM_*`) and uSimSensors, both built from a mission's ANTLER
//! block through the app registry, driven by a scripted controller on the lockstep
//! scheduler: the sensor variables, their rates, and what each sensor says about the truth.

mod support;

use std::sync::Arc;

use mission::moos::MissionFile;
use mission::source::SourceMap;
use runtime::antler::{Launch, plan};
use runtime::{App, Bus, Mail, Post, Scheduler, Subscription, Value, VirtualClock};
use support::RefCell;
use vehicle::sensors::dvl::DvlConfig;
use vehicle::sensors::pressure::depth_from_pressure;

const START: f64 = 1_786_000_000.0;

fn mission(seed: &str) -> MissionFile {
    let text = format!(
        "ServerHost = localhost\nServerPort = 9000\nCommunity = abe\n\
         LatOrigin = 40.0717976\nLongOrigin = -111.6002054\n\n\
         ProcessConfig = ANTLER\n{{\n  Run = MOOSDB @ NewConsole = false\n  \
         Run = uSimMarineV22 @ NewConsole = false\n  Run = uSimSensors @ NewConsole = false\n  \
         Run = pScript @ NewConsole = false\n}}\n\n\
         ProcessConfig = uSimMarineV22\n{{\n  AppTick = 20\n  prefix = SIM\n  \
         start_pos = x=0, y=0, heading=45, speed=0, depth=0\n}}\n\n\
         ProcessConfig = uSimSensors\n{{\n  AppTick = 20\n  water_depth = 20\n  \
         heading_bias = 3\n  {seed}\n}}\n"
    );
    let parsed = mission::moos::parse_moos(&SourceMap::from_text("sensors.moos", &text));
    assert!(!parsed.has_errors());
    parsed.value
}

/// Thrust 30 (1.5 m/s), a gentle turn; a proportional elevator holds the surface until
/// 30 s, then 5 m until 120 s, then the surface again.
struct Script {
    depth: f64,
}

impl App for Script {
    fn name(&self) -> &str {
        "pScript"
    }
    fn app_tick(&self) -> f64 {
        10.0
    }
    fn subscriptions(&self) -> Vec<Subscription> {
        vec![Subscription::var("SIM_DEPTH")]
    }
    fn on_mail(&mut self, mail: &[Mail], _now: f64, _out: &mut Vec<Post>) -> runtime::AppResult {
        for m in mail {
            if let Value::Double(d) = m.value {
                self.depth = d;
            }
        }
        Ok(())
    }
    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> runtime::AppResult {
        let t = now - START;
        let target = if (30.0..120.0).contains(&t) { 5.0 } else { 0.0 };
        let elevator = (20.0 * (target - self.depth)).clamp(-100.0, 100.0);
        out.push(Post::double("DESIRED_THRUST", 30.0));
        out.push(Post::double("DESIRED_RUDDER", 5.0));
        out.push(Post::double("DESIRED_ELEVATOR", elevator));
        Ok(())
    }
}

type Record = Arc<RefCell<Vec<(String, f64, f64)>>>;

/// Records every sensor and truth posting: (variable, time, value).
struct Recorder(Record);

impl App for Recorder {
    fn name(&self) -> &str {
        "uRecorder"
    }
    fn app_tick(&self) -> f64 {
        1.0
    }
    fn subscriptions(&self) -> Vec<Subscription> {
        ["DVL_*", "AHRS_*", "PRESSURE", "GPS_*", "SIM_*"]
            .into_iter()
            .map(Subscription::var)
            .collect()
    }
    fn on_mail(&mut self, mail: &[Mail], _now: f64, _out: &mut Vec<Post>) -> runtime::AppResult {
        let mut r = self.0.borrow_mut();
        for m in mail {
            if let Value::Double(v) = m.value {
                r.push((m.key.to_string(), m.time - START, v));
            }
        }
        Ok(())
    }
    fn iterate(&mut self, _now: f64, _out: &mut Vec<Post>) -> runtime::AppResult {
        Ok(())
    }
}

struct Run {
    rec: Vec<(String, f64, f64)>,
}

impl Run {
    fn series(&self, var: &str) -> Vec<(f64, f64)> {
        self.rec
            .iter()
            .filter(|(k, _, _)| k == var)
            .map(|(_, t, v)| (*t, *v))
            .collect()
    }

    /// The latest value of `var` posted at or before `t`.
    fn truth_at(&self, var: &str, t: f64) -> f64 {
        self.rec
            .iter()
            .rev()
            .find(|(k, tt, _)| k == var && *tt <= t)
            .unwrap_or_else(|| panic!("no {var} by {t}"))
            .2
    }

    fn count_in(&self, var: &str, from: f64, to: f64) -> usize {
        self.series(var)
            .iter()
            .filter(|(t, _)| (from..to).contains(t))
            .count()
    }
}

fn run(seed: &str) -> Run {
    let m = mission(seed);
    let mut custom = |r: &mission::moos::AntlerRun, _: Option<&mission::moos::ProcessConfig>| {
        (r.app == "pScript").then(|| Ok(Box::new(Script { depth: 0.0 }) as Box<dyn App>))
    };
    let p = plan(&m, Launch::new(START, 1), &mut custom).unwrap();
    assert!(p.warnings.is_empty(), "{:?}", p.warnings);
    assert!(p.external.is_empty(), "every app is built in or scripted");
    let names: Vec<&str> = p.apps.iter().map(|a| a.name()).collect();
    assert_eq!(names, ["uSimMarineV22", "uSimSensors", "pScript"]);
    let mut s = Scheduler::new(Bus::new("abe", START), VirtualClock, START);
    let rec: Record = Arc::default();
    for app in p.apps {
        s.add_app(app).unwrap();
    }
    s.add_app(Box::new(Recorder(rec.clone()))).unwrap();
    s.run(180.0).unwrap();
    let rec = rec.borrow().clone();
    Run { rec }
}

fn mean_std(v: &[f64]) -> (f64, f64) {
    let n = v.len() as f64;
    let m = v.iter().sum::<f64>() / n;
    (
        m,
        (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / n).sqrt(),
    )
}

#[test]
fn sensors_follow_the_simulated_vehicle_at_their_rates() {
    let r = run("seed = 5");
    // The dive happened: at 5 m (within 0.5 m) from 60 s to 120 s, back at the surface by
    // 170 s.
    for t in [60.0, 90.0, 119.0] {
        let d = r.truth_at("SIM_DEPTH", t);
        assert!((d - 5.0).abs() < 0.5, "{t}: {d}");
    }
    assert!(r.truth_at("SIM_DEPTH", 170.0) < 0.05);

    // Rates over 10 s..170 s (160 s).
    let per_s = |v: &str| r.count_in(v, 10.0, 170.0) as f64 / 160.0;
    assert!(
        (per_s("PRESSURE") - 20.0).abs() < 0.1,
        "{}",
        per_s("PRESSURE")
    );
    assert!((per_s("AHRS_HEADING") - 10.0).abs() < 0.1);
    assert!((per_s("GPS_FIX") - 5.0).abs() < 0.1);
    // DVL: at 5 m over a 20 m bottom (15 m altitude) it pings faster than at the surface
    // (20 m), as the linear law says.
    let dvl = DvlConfig::default();
    let deep = r.count_in("DVL_VALID", 60.0, 120.0) as f64 / 60.0;
    let shallow = r.count_in("DVL_VALID", 2.0, 28.0) as f64 / 26.0;
    assert!((deep - dvl.rate_at(15.0)).abs() < 0.4, "{deep}");
    assert!((shallow - dvl.rate_at(20.0)).abs() < 0.4, "{shallow}");
    assert!(deep > shallow);
    assert!(r.series("DVL_VALID").iter().all(|(_, v)| *v == 1.0));
    assert_eq!(r.series("DVL_VEL_X").len(), r.series("DVL_VALID").len());

    // GPS: a fix only with the antenna out of the water, and fixes at both surface spells.
    let fixes = r.series("GPS_FIX");
    for (t, f) in &fixes {
        if *f == 1.0 {
            assert!(r.truth_at("SIM_DEPTH", *t) < 0.2 + 0.05, "fix at {t}");
        }
    }
    let fix_times: Vec<f64> = fixes
        .iter()
        .filter(|(_, f)| *f == 1.0)
        .map(|(t, _)| *t)
        .collect();
    assert!(fix_times.iter().any(|t| *t < 30.0));
    assert!(fix_times.iter().any(|t| *t > 150.0));
    assert!(!fix_times.iter().any(|t| (40.0..120.0).contains(t)));
    assert_eq!(r.series("GPS_LAT").len(), fix_times.len());
    let gx = r.series("GPS_X");
    for (t, x) in &gx {
        assert!((x - r.truth_at("SIM_X", *t)).abs() < 10.0, "GPS_X at {t}");
    }

    // Pressure gives the depth back (fresh water, 101325 Pa): within a centimetre (20 Pa
    // noise is 2 mm) at the instants the simulator posts its record, and within 0.15 m in
    // between, where the truth is extrapolated at the last depth rate (uSimMarine's pitch
    // jumps from iteration to iteration in a steep dive, and so does its depth rate).
    let record_times: Vec<f64> = r.series("SIM_DEPTH").iter().map(|(t, _)| *t).collect();
    let mut exact = 0;
    for (t, p) in r.series("PRESSURE") {
        let d = depth_from_pressure(p, 101_325.0, 0.0);
        let e = (d - r.truth_at("SIM_DEPTH", t)).abs();
        if record_times.contains(&t) {
            exact += 1;
            assert!(e < 0.01, "{t}: {d}");
        } else {
            assert!(e < 0.15, "{t}: {d}");
        }
    }
    assert!(exact > 1000, "{exact}");

    // The AHRS heading is the truth plus the 3 degree bias.
    let e: Vec<f64> = r
        .series("AHRS_HEADING")
        .iter()
        .map(|(t, h)| geometry::angle_180(h - r.truth_at("SIM_HEADING", *t)))
        .collect();
    let (m, s) = mean_std(&e);
    assert!((m - 3.0).abs() < 0.15, "{m}");
    assert!(s < 1.3, "{s}");

    // The DVL's forward velocity is the truth's body-forward velocity, 0.5 % fast: the
    // simulator moves horizontally at its speed over ground and vertically at the depth
    // rate, so forward = cos(pitch) sog - sin(pitch) depth_rate (pitch nose up). Checked at
    // the instants of the simulator's records (no extrapolation).
    let depth = r.series("SIM_DEPTH");
    let e: Vec<f64> = r
        .series("DVL_VEL_X")
        .iter()
        .filter(|(t, _)| (5.0..175.0).contains(t))
        .filter_map(|(t, v)| {
            let i = depth.iter().position(|(tt, _)| tt == t)?;
            let rate = (depth[i].1 - depth[i - 1].1) / (depth[i].0 - depth[i - 1].0);
            let pitch = r.truth_at("SIM_PITCH", *t);
            let sog = r.truth_at("SIM_SPEED_OVER_GROUND", *t);
            Some(v - 1.005 * (pitch.cos() * sog - pitch.sin() * rate))
        })
        .collect();
    assert!(e.len() > 500, "{}", e.len());
    let (m, s) = mean_std(&e);
    assert!(m.abs() < 0.005, "{m}");
    assert!((s - 0.02).abs() < 0.004, "{s}");
}

#[test]
fn the_same_seed_gives_the_same_sensor_values() {
    let sensors = |r: &Run| -> Vec<(String, f64, f64)> {
        r.rec
            .iter()
            .filter(|(k, _, _)| !k.starts_with("SIM_"))
            .cloned()
            .collect()
    };
    let a = sensors(&run("seed = 5"));
    let b = sensors(&run("seed = 5"));
    let c = sensors(&run("seed = 6"));
    assert!(a.len() > 10_000);
    assert_eq!(a, b);
    assert_ne!(a, c);
}
