//! Measures the lockstep speed-up of the vehicle apps of s1_alpha (simulator, marine PID,
//! node reporter, pLogger into memory) under a scripted helm, over simulated seconds:
//! `cargo run --release -p runtime --example lockstep_speed [SECONDS]`.

use std::time::Instant;

use chrono::NaiveDate;
use mission::source::SourceMap;
use runtime::antler::{LogTarget, logger_config, plan};
use runtime::logger::SharedBuffer;
use runtime::{App, Bus, Poke, Post, Scheduler, VirtualClock};

const START: f64 = 1_786_000_000.0;

/// Turns 90° every 100 s at 2 m/s, as a helm would post at AppTick 4.
struct ScriptedHelm;

impl App for ScriptedHelm {
    fn name(&self) -> &str {
        "pHelmIvP"
    }
    fn app_tick(&self) -> f64 {
        4.0
    }
    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) {
        let leg = ((now - START) / 100.0).floor();
        out.push(Post::text("IVPHELM_STATE", "DRIVE"));
        out.push(Post::double("DESIRED_HEADING", (leg * 90.0) % 360.0));
        out.push(Post::double("DESIRED_SPEED", 2.0));
        out.push(Post::double("DESIRED_DEPTH", 0.0));
    }
}

fn main() {
    let secs: f64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(2000.0);
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../shared/corpus/moos-ivp-missions/s1_alpha/alpha.moos"
    );
    let text = std::fs::read_to_string(path).expect("the shared corpus is required");
    let m = mission::moos::parse_moos(&SourceMap::from_text("alpha.moos", &text)).value;
    let buf = SharedBuffer::default();
    let target = LogTarget {
        config: logger_config(&m),
        writer: Box::new(buf.clone()),
        opened: NaiveDate::from_ymd_opt(2026, 1, 1)
            .unwrap()
            .and_hms_opt(0, 0, 0)
            .unwrap(),
        opened_on: "Thu Jan  1 00:00:00 1970".into(),
    };
    let p = plan(&m, START, 1, Some(target), &mut |run, _| {
        (run.app == "pHelmIvP").then(|| Ok(Box::new(ScriptedHelm) as Box<dyn App>))
    })
    .expect("alpha plans");
    let mut s = Scheduler::new(Bus::new(&p.globals.community, START), VirtualClock, START);
    for app in p.apps {
        s.add_app(app).expect("unique names");
    }
    s.add_poke(Poke::parse("MOOS_MANUAL_OVERRIDE=false", "pHelmIvP").unwrap())
        .unwrap();
    let wall = Instant::now();
    let outcome = s.run(secs).expect("run");
    let elapsed = wall.elapsed().as_secs_f64();
    println!(
        "{secs} simulated s in {elapsed:.3} wall s: {:.0}x real time; {outcome:?}; log {} bytes",
        secs / elapsed,
        buf.contents().len()
    );
}
