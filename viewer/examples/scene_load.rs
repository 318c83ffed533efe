//! Load figures for the scene: 100 vehicles each reporting at 4 Hz with a VIEW_POINT and a
//! VIEW_SEGLIST per report, for 60 simulated seconds; a page asks for a delta 20 times a
//! second. Prints the time per mail, per delta frame and the frame sizes.
//! `cargo run --release -p viewer --example scene_load`.

use std::time::Instant;

use viewer::scene::{Scene, SceneConfig};

fn main() {
    let mut scene = Scene::new(SceneConfig::default(), Vec::new());
    let (vehicles, hz, seconds, fps) = (100, 4.0, 60.0, 20.0);
    let mut mail = 0u64;
    let (mut apply_ns, mut delta_ns, mut frames, mut bytes) = (0u128, 0u128, 0u64, 0usize);
    let mut seen = 0;
    let steps = (seconds * hz) as usize;
    let frames_per_step = (fps / hz) as usize;
    for k in 0..steps {
        let t = k as f64 / hz;
        let t0 = Instant::now();
        for v in 0..vehicles {
            let (x, y) = (v as f64 * 10.0 + t, (t * 0.3).sin() * 50.0);
            scene
                .apply(
                    "NODE_REPORT",
                    &format!(
                        "NAME=v{v},X={x:.2},Y={y:.2},SPD=1.5,HDG=90,DEP=2,MODE=DRIVE,TIME={t}"
                    ),
                    t,
                )
                .unwrap();
            scene
                .apply(
                    "VIEW_POINT",
                    &format!("x={x:.1},y={y:.1},label=v{v}_next"),
                    t,
                )
                .unwrap();
            scene
                .apply(
                    "VIEW_SEGLIST",
                    &format!(
                        "pts={{{x:.1},{y:.1}:{:.1},{:.1}}},label=v{v}_path",
                        x + 20.0,
                        y
                    ),
                    t,
                )
                .unwrap();
            mail += 3;
        }
        apply_ns += t0.elapsed().as_nanos();
        for _ in 0..frames_per_step {
            let t0 = Instant::now();
            if let Some(d) = scene.delta_since(seen) {
                let text = d.to_string();
                bytes += text.len();
                frames += 1;
                seen = scene.version();
            }
            delta_ns += t0.elapsed().as_nanos();
        }
    }
    let t0 = Instant::now();
    let snap = scene.snapshot().to_string();
    let snap_us = t0.elapsed().as_micros();
    println!(
        "{mail} mails: {:.2} us per mail; {frames} delta frames: {:.0} us and {:.1} kB each; snapshot {snap_us} us, {:.0} kB",
        apply_ns as f64 / mail as f64 / 1e3,
        delta_ns as f64 / frames as f64 / 1e3,
        bytes as f64 / frames as f64 / 1e3,
        snap.len() as f64 / 1e3
    );
    println!(
        "CPU share of one core for the scene at this load: {:.1} %",
        (apply_ns + delta_ns) as f64 / 1e9 / seconds * 100.0
    );
}
