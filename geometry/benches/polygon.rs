//! Polygon containment and boundary distance: the per-iteration checks of BHV_OpRegion and
//! BHV_Loiter.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use geometry::spec::parse_polygon;

fn polygon_queries(c: &mut Criterion) {
    let small = parse_polygon("pts={60,-40:60,-160:150,-160:180,-100:150,-40}")
        .expect("corpus polygon")
        .polygon;
    let circle = parse_polygon("format=radial, x=0, y=0, radius=100, pts=64")
        .expect("radial")
        .polygon;
    let probes: Vec<(f64, f64)> = (0..64)
        .map(|i| (f64::from(i) * 5.0 - 40.0, f64::from(i) * -3.0))
        .collect();

    c.bench_function("contains/pentagon x64", |b| {
        b.iter(|| {
            probes
                .iter()
                .filter(|&&(x, y)| small.contains(black_box(x), black_box(y)))
                .count()
        })
    });
    c.bench_function("contains/64-gon x64", |b| {
        b.iter(|| {
            probes
                .iter()
                .filter(|&&(x, y)| circle.contains(black_box(x), black_box(y)))
                .count()
        })
    });
    c.bench_function("dist_to_boundary/pentagon x64", |b| {
        b.iter(|| {
            probes
                .iter()
                .map(|&(x, y)| {
                    small
                        .dist_to_boundary(black_box(x), black_box(y))
                        .unwrap_or(0.0)
                })
                .sum::<f64>()
        })
    });
    c.bench_function("dist_to_boundary/64-gon x64", |b| {
        b.iter(|| {
            probes
                .iter()
                .map(|&(x, y)| {
                    circle
                        .dist_to_boundary(black_box(x), black_box(y))
                        .unwrap_or(0.0)
                })
                .sum::<f64>()
        })
    });
    let mut buf = String::with_capacity(2048);
    let view = parse_polygon("format=radial, x=0, y=0, radius=100, pts=64, label=abe_loiter")
        .expect("radial");
    c.bench_function("spec/64-gon into buffer", |b| {
        b.iter(|| {
            buf.clear();
            view.spec(black_box(&mut buf));
            buf.len()
        })
    });
}

criterion_group!(benches, polygon_queries);
criterion_main!(benches);
