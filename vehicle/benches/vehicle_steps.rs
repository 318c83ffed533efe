//! Per-step cost of the vehicle apps (one simulated second of a 10 Hz loop is 10 steps).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use vehicle::cougars::{ControllerInputs, CougarsConfig, CougarsState};
use vehicle::geodesy::LocalGrid;
use vehicle::node_report::{HelmInfo, NavRecord, NodeReportConfig, ReportInputs, write_report};
use vehicle::pid::{PidConfig, PidInputs, PidState};
use vehicle::sim::{SimConfig, SimInputs, SimState};

fn benches(c: &mut Criterion) {
    let cfg = SimConfig::default();
    let state = SimState {
        speed_mps: 2.0,
        heading_deg: 45.0,
        depth: 3.0,
        ..SimState::default()
    };
    let inputs = SimInputs {
        thrust: 40.0,
        rudder_deg: 10.0,
        elevator_deg: 5.0,
        ..SimInputs::from_config(&cfg)
    };
    c.bench_function("sim_step", |b| {
        b.iter(|| vehicle::sim::step(&cfg, black_box(&state), black_box(&inputs), 0.1, None))
    });
    let grid = LocalGrid::new(43.8253, -70.3304).unwrap();
    c.bench_function("sim_step_with_latlon", |b| {
        b.iter(|| {
            vehicle::sim::step(
                &cfg,
                black_box(&state),
                black_box(&inputs),
                0.1,
                Some(&grid),
            )
        })
    });

    let mut pcfg = PidConfig::default();
    pcfg.yaw.kp = 0.5;
    pcfg.speed_factor = 20.0;
    let pstate = PidState::new(&pcfg);
    let s = |v: f64| Some((v, 10.0));
    let pin = PidInputs {
        desired_heading: s(90.0),
        desired_speed: s(2.0),
        desired_depth: s(5.0),
        heading: s(80.0),
        speed: s(2.0),
        depth: s(4.0),
        pitch: s(0.0),
        manual_override: false,
    };
    c.bench_function("pid_step", |b| {
        b.iter(|| vehicle::pid::step(&pcfg, black_box(&pstate), black_box(&pin), 10.1))
    });

    let ccfg = CougarsConfig::coug1();
    let cstate = CougarsState::new(&ccfg);
    let cin = ControllerInputs {
        desired_depth: 3.0,
        depth: 2.5,
        surge: 0.6,
        ..ControllerInputs::default()
    };
    c.bench_function("cougars_step", |b| {
        b.iter(|| vehicle::cougars::step(&ccfg, black_box(&cstate), black_box(&cin)))
    });

    let rcfg = NodeReportConfig::default();
    let nav = NavRecord {
        x: Some(-4.934),
        y: Some(-96.05),
        lat: Some(43.82443465),
        lon: Some(-70.33044214),
        speed: Some(2.0),
        heading: Some(45.0),
        depth: Some(12.3),
        yaw_seen: true,
        ..NavRecord::default()
    };
    let helm = HelmInfo::default();
    let mode = helm.mode(100.0, 5.0);
    let mut buf = String::with_capacity(256);
    c.bench_function("node_report_write", |b| {
        b.iter(|| {
            buf.clear();
            let r = ReportInputs {
                name: "henry",
                nav,
                mode: &mode,
                allstop: "clear",
                time: 1234.5,
                ..ReportInputs::default()
            };
            write_report(&mut buf, &rcfg, black_box(&r));
            buf.len()
        })
    });
}

criterion_group!(vehicle_benches, benches);
criterion_main!(vehicle_benches);
