//! Helm-like IvP problems shared by the solver benchmark and the callgrind driver.
//!
//! (a) course 0:359:360 x speed 0:4:41: a waypoint-like function (ZAIC_HDG on course coupled
//!     with ZAIC_SPD on speed) plus a constant-speed function (ZAIC_PEAK on speed).
//! (b) course x speed x depth 0:100:101 with five functions: the waypoint function, constant
//!     speed, constant depth (ZAIC_PEAK), max depth (ZAIC_LEQ) and a reflector-built
//!     avoidance-like function over course x speed.

use ivp::{Domain, IvpFunction, Problem, Reflector, ZaicHdg, ZaicLeq, ZaicPeak, ZaicSpd, couple};

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

pub fn problem_a() -> Problem {
    let d = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
    let mut p = Problem::new(d.clone());
    p.add("waypt_survey", waypoint(&d)).unwrap();
    p.add("const_speed", const_speed(&d)).unwrap();
    p
}

pub fn problem_b() -> Problem {
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
