//! The apps wired together through their MOOS adapters, as `coug run` does: helm set-points
//! in, either the marine PID and uSimMarine, or the CoUGARs controllers and the CougUV
//! simulator, and node reports.

mod common;

use vehicle::angle::angle180;
use vehicle::cougars::CougarsControl;
use vehicle::couguv::{CougUvSim, CougUvSimConfig};
use vehicle::moos::last_posting;
use vehicle::node_report::{NodeReportConfig, NodeReporter};
use vehicle::pid::{MarinePid, PidConfig};
use vehicle::sim::{SimConfig, Simulator};
use vehicle::{Posting, ValueRef};

enum Controller {
    Marine(Box<MarinePid>, Box<Simulator>),
    Cougars(Box<CougarsControl>, Box<CougUvSim>),
}

impl Controller {
    fn on_mail(&mut self, var: &str, v: ValueRef<'_>, t: f64) {
        match self {
            Controller::Marine(c, _) => c.on_mail(var, v, t),
            Controller::Cougars(c, _) => c.on_mail(var, v, t),
        }
    }
    fn iterate(&mut self, t: f64, out: &mut Vec<Posting>) {
        match self {
            Controller::Marine(c, _) => c.iterate(t, out),
            Controller::Cougars(c, _) => c.iterate(t, out),
        }
    }
    fn sim_mail(&mut self, var: &str, v: ValueRef<'_>, t: f64) {
        match self {
            Controller::Marine(_, s) => {
                s.on_mail(var, v, t);
            }
            Controller::Cougars(_, s) => s.on_mail(var, v, t),
        }
    }
    fn sim_iterate(&mut self, t: f64, out: &mut Vec<Posting>) {
        match self {
            Controller::Marine(_, s) => s.iterate(t, out),
            Controller::Cougars(_, s) => s.iterate(t, out),
        }
    }
}

fn deliver(postings: &[Posting], t: f64, mut to: impl FnMut(&str, ValueRef<'_>, f64)) {
    for p in postings {
        to(&p.key, p.value.as_ref(), t);
    }
}

struct Mission {
    ctl: Controller,
    reporter: NodeReporter,
    dt: f64,
    t: f64,
    nav: Vec<Posting>,
    last_report: String,
}

impl Mission {
    fn new(ctl: Controller, dt: f64) -> Self {
        let reporter = NodeReporter::new(
            NodeReportConfig::from_params([("platform_type", "uuv")]).unwrap(),
            "coug1",
            0.0,
        );
        Mission {
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
            deliver(&cmds, t, |v, x, t| self.ctl.sim_mail(v, x, t));
            let mut nav = Vec::new();
            self.ctl.sim_iterate(t, &mut nav);
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
    let cfg = SimConfig::from_params([
        ("prefix", "NAV"),
        ("start_pos", "x=0,y=0,heading=90,speed=0"),
    ])
    .unwrap();
    let sim = Simulator::new(cfg, None, 0.0);
    let mut m = Mission::new(Controller::Marine(Box::new(pid), Box::new(sim)), 0.1);
    m.run(120.0, 180.0, 2.0, 5.0);
    let Controller::Marine(_, sim) = &m.ctl else {
        unreachable!()
    };
    let s = *sim.state();
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
fn cougars_controllers_drive_the_couguv_simulator() {
    let cfg = common::mission_controls();
    let mut c = CougarsControl::new(cfg);
    c.on_mail("DEPLOY", ValueRef::String("true"), 0.0);
    c.on_mail("MOOS_MANUAL_OVERIDE", ValueRef::String("false"), 0.0);
    let sim = CougUvSim::new(
        CougUvSimConfig::from_params([("prefix", "NAV"), ("start_pos", "heading=90")]).unwrap(),
        None,
    );
    let mut m = Mission::new(Controller::Cougars(Box::new(c), Box::new(sim)), 0.08);
    // 1 m/s at 50 %/(m/s): 50 % thrust, 1 m/s in the model after its 20 s surge lag.
    m.run(200.0, 180.0, 1.0, 3.0);
    let truth = |m: &Mission| match &m.ctl {
        Controller::Cougars(_, s) => *s.truth(),
        Controller::Marine(..) => unreachable!(),
    };
    let s = truth(&m);
    assert!(
        angle180(s.body.heading - 180.0).abs() < 2.0,
        "heading {}",
        s.body.heading
    );
    assert!((s.body.surge - 1.0).abs() < 0.01, "speed {}", s.body.surge);
    assert!((s.body.depth - 3.0).abs() < 0.2, "depth {}", s.body.depth);
    // Still there 60 s later.
    m.run(60.0, 180.0, 1.0, 3.0);
    assert!((truth(&m).body.depth - 3.0).abs() < 0.2);
    assert!(m.last_report.contains(",TYPE=uuv,"));
}
