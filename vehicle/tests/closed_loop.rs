//! The apps wired together through their MOOS adapters, as `coug run` will do: helm set-points
//! in, either the marine PID or the CoUGARs controllers, the simulator, and node reports.

use vehicle::angle::angle180;
use vehicle::cougars::{CougarsConfig, CougarsControl};
use vehicle::moos::last_posting;
use vehicle::node_report::{NodeReportConfig, NodeReporter};
use vehicle::pid::{MarinePid, PidConfig};
use vehicle::sim::{SimConfig, Simulator};
use vehicle::{Posting, ValueRef};

enum Controller {
    Marine(Box<MarinePid>),
    Cougars(Box<CougarsControl>),
}

impl Controller {
    fn on_mail(&mut self, var: &str, v: ValueRef<'_>, t: f64) {
        match self {
            Controller::Marine(c) => c.on_mail(var, v, t),
            Controller::Cougars(c) => c.on_mail(var, v, t),
        }
    }
    fn iterate(&mut self, t: f64, out: &mut Vec<Posting>) {
        match self {
            Controller::Marine(c) => c.iterate(t, out),
            Controller::Cougars(c) => c.iterate(t, out),
        }
    }
}

fn deliver(postings: &[Posting], t: f64, mut to: impl FnMut(&str, ValueRef<'_>, f64)) {
    for p in postings {
        to(&p.key, p.value.as_ref(), t);
    }
}

struct Mission {
    sim: Simulator,
    ctl: Controller,
    reporter: NodeReporter,
    dt: f64,
    t: f64,
    nav: Vec<Posting>,
    last_report: String,
}

impl Mission {
    fn new(ctl: Controller, dt: f64) -> Self {
        let cfg = SimConfig::from_params([
            ("prefix", "NAV"),
            ("start_pos", "x=0,y=0,heading=90,speed=0"),
        ])
        .unwrap();
        let reporter = NodeReporter::new(
            NodeReportConfig::from_params([("platform_type", "uuv")]).unwrap(),
            "coug1",
            0.0,
        );
        Mission {
            sim: Simulator::new(cfg, None, 0.0),
            ctl,
            reporter,
            dt,
            t: 0.0,
            nav: Vec::new(),
            last_report: String::new(),
        }
    }

    fn run(&mut self, secs: f64, hdg: f64, spd: f64, dep: f64) {
        let end = self.t + secs;
        while self.t < end {
            self.t += self.dt;
            let t = self.t;
            let helm = [
                ("DESIRED_HEADING", hdg),
                ("DESIRED_SPEED", spd),
                ("DESIRED_DEPTH", dep),
            ];
            for (v, x) in helm {
                self.ctl.on_mail(v, ValueRef::Double(x), t);
            }
            deliver(&self.nav, t, |v, x, t| self.ctl.on_mail(v, x, t));
            let mut cmds = Vec::new();
            self.ctl.iterate(t, &mut cmds);
            deliver(&cmds, t, |v, x, t| {
                self.sim.on_mail(v, x, t);
            });
            let mut nav = Vec::new();
            self.sim.iterate(t, &mut nav);
            if !nav.is_empty() {
                self.nav = nav;
            }
            deliver(&self.nav, t, |v, x, t| self.reporter.on_mail(v, x, t));
            let mut rep = Vec::new();
            self.reporter.iterate(t, &mut rep);
            if let Some(r) = last_posting(&rep, "NODE_REPORT_LOCAL") {
                self.last_report = r.as_str().unwrap().to_string();
            }
        }
    }
}

fn surface_pid() -> PidConfig {
    PidConfig::from_params([
        ("yaw_pid_kp", "1.2"),
        ("yaw_pid_kd", "0"),
        ("yaw_pid_ki", "0"),
        ("yaw_pid_integral_limit", "0.07"),
        ("speed_pid_kp", "1"),
        ("speed_pid_kd", "0"),
        ("speed_pid_ki", "0"),
        ("speed_pid_integral_limit", "0.07"),
        ("maxrudder", "100"),
        ("maxthrust", "100"),
        ("speed_factor", "20"),
        ("z_to_pitch_pid_kp", "0.12"),
        ("z_to_pitch_pid_kd", "0"),
        ("z_to_pitch_pid_ki", "0.004"),
        ("z_to_pitch_pid_integral_limit", "0.05"),
        ("maxpitch", "15"),
        ("pitch_pid_kp", "0.5"),
        ("pitch_pid_kd", "1.0"),
        ("pitch_pid_ki", "0"),
        ("pitch_pid_integral_limit", "0"),
        ("maxelevator", "13"),
    ])
    .unwrap()
}

#[test]
fn marine_pid_drives_the_simulator_through_moos_names() {
    let mut pid = MarinePid::new(surface_pid());
    pid.on_mail("MOOS_MANUAL_OVERRIDE", ValueRef::String("false"), 0.0);
    let mut m = Mission::new(Controller::Marine(Box::new(pid)), 0.1);
    m.run(120.0, 180.0, 2.0, 5.0);
    let s = m.sim.state();
    assert!(
        angle180(s.heading_deg - 180.0).abs() < 2.0,
        "heading {}",
        s.heading_deg
    );
    assert!((s.speed_mps - 2.0).abs() < 0.05, "speed {}", s.speed_mps);
    assert!((s.depth - 5.0).abs() < 0.3, "depth {}", s.depth);
    assert!(
        m.last_report.starts_with("NAME=coug1,X="),
        "{}",
        m.last_report
    );
    let field = |k: &str| -> f64 {
        let kv = m
            .last_report
            .split(',')
            .find_map(|f| f.strip_prefix(k))
            .expect("field");
        kv.parse().unwrap()
    };
    assert!((field("HDG=") - s.heading_deg).abs() < 0.01);
    assert!((field("DEP=") - s.depth).abs() < 0.01);
}

#[test]
fn cougars_controllers_drive_the_simulator_instead() {
    let mut c = CougarsControl::new(CougarsConfig::coug1(), 0.0);
    c.on_mail("MOOS_MANUAL_OVERIDE", ValueRef::String("false"), 0.0);
    let mut m = Mission::new(Controller::Cougars(Box::new(c)), 0.08);
    // DESIRED_SPEED is thrust percent for the CoUGARs stack: 30 % -> 1.5 m/s in the simulator.
    m.run(150.0, 180.0, 30.0, 3.0);
    let s = *m.sim.state();
    assert!(
        angle180(s.heading_deg - 180.0).abs() < 2.0,
        "heading {}",
        s.heading_deg
    );
    assert!((s.speed_mps - 1.5).abs() < 0.05, "speed {}", s.speed_mps);
    assert!((s.depth - 3.0).abs() < 0.2, "depth {}", s.depth);
    // Still there 60 s later.
    m.run(60.0, 180.0, 30.0, 3.0);
    assert!((m.sim.state().depth - 3.0).abs() < 0.2);
    assert!(m.last_report.contains(",TYPE=uuv,"));
}
