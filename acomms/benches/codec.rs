//! Encoding and receiving each message: `encode/<message>` builds the frame (bit packing,
//! plus HMAC-SHA256 for the authenticated ones), `receive/<message>` runs every check of
//! `Receiver::receive` on it (length, tag, fields, addressing, replay window).

use acomms::{FleetKey, Receiver};
use criterion::{BatchSize, Criterion, criterion_group, criterion_main};

fn bench(c: &mut Criterion) {
    let key = FleetKey::new(acomms::fuzz::KEY);
    let frames = acomms::fuzz::seeds();
    let rx = Receiver::new(acomms::fuzz::ME, key.clone());
    let mut enc = c.benchmark_group("encode");
    for (row, frame) in acomms::SIZE_TABLE.iter().zip(&frames) {
        let packet = rx.clone().receive(frame).expect("a seed is valid");
        enc.bench_function(row.name, |b| {
            b.iter(|| std::hint::black_box(&packet).encode(&key).unwrap())
        });
    }
    enc.finish();
    let mut dec = c.benchmark_group("receive");
    for (row, frame) in acomms::SIZE_TABLE.iter().zip(&frames) {
        dec.bench_function(row.name, |b| {
            // A fresh receiver each time, so the replay window never refuses the frame.
            b.iter_batched_ref(
                || rx.clone(),
                |r| r.receive(std::hint::black_box(frame)).unwrap(),
                BatchSize::SmallInput,
            )
        });
    }
    dec.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
