//! Solver benchmarks on helm-like problems.
//!
//! (a) course 0:359:360 x speed 0:4:41: a waypoint-like function (ZAIC_HDG on course coupled
//!     with ZAIC_SPD on speed) plus a constant-speed function (ZAIC_PEAK on speed).
//! (b) course x speed x depth 0:100:101 with five functions: the waypoint function, constant
//!     speed, constant depth (ZAIC_PEAK), max depth (ZAIC_LEQ) and a reflector-built
//!     avoidance-like function over course x speed.
//!
//! Run with `cargo bench -p helm --bench solver`; piece counts are printed once.

use criterion::{Criterion, criterion_group, criterion_main};
use helm::ivp::{
    Domain, IvpFunction, Problem, Reflector, Solver, ZaicHdg, ZaicLeq, ZaicPeak, ZaicSpd, couple,
};
use std::hint::black_box;

fn waypoint(d: &Domain) -> IvpFunction {
    let hdg = ZaicHdg::new(d, "course", 127.0, 30.0, 30.0, 50.0, 50.0, 0.0, 100.0).unwrap();
    let spd = ZaicSpd::new(d, "speed", 1.5, 1.2, 1.8, 70.0, 70.0).unwrap();
    couple(&hdg.extract().unwrap(), &spd.extract().unwrap())
        .unwrap()
        .with_pwt(100.0)
}

fn const_speed(d: &Domain) -> IvpFunction {
    let mut z = ZaicPeak::new(d, "speed").unwrap();
    z.set_params(1.2, 0.0, 0.2, 0.0, 0.0, 100.0).unwrap();
    z.extract().unwrap().with_pwt(50.0)
}

fn problem_a() -> Problem {
    let d = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
    let mut p = Problem::new(d.clone());
    p.add("waypt_survey", waypoint(&d)).unwrap();
    p.add("const_speed", const_speed(&d)).unwrap();
    p
}

fn problem_b() -> Problem {
    let d = Domain::parse_specs(["course:0:359:360", "speed:0:4:41", "depth:0:100:101"]).unwrap();
    let mut p = Problem::new(d.clone());
    p.add("waypt_survey", waypoint(&d)).unwrap();
    p.add("const_speed", const_speed(&d)).unwrap();
    let mut depth = ZaicPeak::new(&d, "depth").unwrap();
    depth.set_params(12.0, 2.0, 10.0, 0.0, 0.0, 100.0).unwrap();
    p.add("const_depth", depth.extract().unwrap().with_pwt(100.0))
        .unwrap();
    let mut maxd = ZaicLeq::new(&d, "depth").unwrap();
    maxd.set_summit(10.0).unwrap();
    maxd.set_basewidth(5.0).unwrap();
    p.add("max_depth", maxd.extract().unwrap().with_pwt(200.0))
        .unwrap();
    let sub = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
    let avoid = Reflector::new(&sub, |v: &[f64]| {
        // penalize courses near 140 at higher speeds (a contact to starboard)
        let dc = ((v[0] - 140.0 + 540.0) % 360.0 - 180.0).abs();
        100.0 - (100.0 - dc.min(100.0)) * (v[1] / 4.0)
    })
    .set_params("uniform_piece = course:10,speed:5 # normalize = true")
    .unwrap()
    .build()
    .unwrap()
    .with_pwt(150.0);
    p.add("avoid_contact", avoid).unwrap();
    p
}

fn bench(c: &mut Criterion) {
    for (name, p) in [
        ("a_course_speed", problem_a()),
        ("b_course_speed_depth", problem_b()),
    ] {
        let counts: Vec<String> = p
            .functions()
            .map(|(o, f)| format!("{o}={}", f.piece_count()))
            .collect();
        let mut solver = Solver::new();
        let dec = solver.solve(&p).unwrap();
        eprintln!(
            "{name}: pieces [{}], nodes {}, decision {:?}",
            counts.join(", "),
            solver.nodes_visited(),
            dec.vars
                .iter()
                .map(|v| (v.name.as_str(), v.value))
                .collect::<Vec<_>>()
        );
        c.bench_function(name, |b| b.iter(|| black_box(solver.solve(black_box(&p)))));
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
