//! Builder benchmarks: the functions a waypoint behaviour builds every helm iteration.
//!
//! Run with `cargo bench -p ivp --bench builders`.

use criterion::{Criterion, criterion_group, criterion_main};
use ivp::{Combine, Domain, PeakComponent, ZaicHdg, ZaicPeak, ZaicSpd, couple_weighted};
use std::hint::black_box;

fn course_peak(d: &Domain, bearing: f64, heading: f64) -> ZaicPeak {
    let mut crs = ZaicPeak::new(d, "course").unwrap();
    crs.set_value_wrap(true);
    crs.set_params(bearing, 0.0, 180.0, 50.0, 0.0, 100.0)
        .unwrap();
    crs.add_component(PeakComponent {
        summit: heading,
        peakwidth: 30.0,
        basewidth: 180.0,
        summitdelta: 5.0,
        minutil: 0.0,
        maxutil: 20.0,
    })
    .unwrap();
    crs.set_combine(Combine::Sum);
    crs
}

fn bench(c: &mut Criterion) {
    let d = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
    c.bench_function("zaic_peak_course_2comp", |b| {
        let z = course_peak(&d, 127.3, 95.0);
        b.iter(|| black_box(z.extract().unwrap()))
    });
    c.bench_function("zaic_hdg_course", |b| {
        let z = ZaicHdg::new(&d, "course", 127.0, 30.0, 30.0, 50.0, 50.0, 0.0, 100.0).unwrap();
        b.iter(|| black_box(z.extract().unwrap()))
    });
    c.bench_function("waypoint_like_coupled", |b| {
        let z = course_peak(&d, 127.3, 95.0);
        b.iter(|| {
            let mut s = ZaicPeak::new(&d, "speed").unwrap();
            s.set_params(1.2, 0.6, 1.6, 20.0, 0.0, 100.0).unwrap();
            let spd = s.extract().unwrap();
            black_box(couple_weighted(&z.extract().unwrap(), &spd, 50.0, 50.0, true).unwrap())
        })
    });
    c.bench_function("zaic_spd", |b| {
        let z = ZaicSpd::new(&d, "speed", 1.5, 1.2, 1.8, 70.0, 70.0).unwrap();
        b.iter(|| black_box(z.extract().unwrap()))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
