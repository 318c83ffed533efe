//! Benchmark: the real s1_alpha mission in lockstep with every app in-process (helm,
//! simulator, PID, node reporter, pLogger writing to memory), deployed, until
//! `MISSION = complete`; prints the speed-up over real time. Best of N runs:
//! `cargo run --release -p runtime --example alpha_speed [N]`.

use std::time::Instant;

use chrono::NaiveDate;
use mission::source::SourceMap;
use runtime::antler::{Launch, LogTarget, logger_config, plan};
use runtime::helm::HelmApp;
use runtime::logger::SharedBuffer;
use runtime::{App, Bus, Poke, Scheduler, VirtualClock};

const START: f64 = 1_786_000_000.0;

fn main() {
    let runs: usize = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(5);
    let read = |n: &str| test_support::mission_text(&format!("s1_alpha/{n}"));
    let m =
        mission::moos::parse_moos(&SourceMap::from_text("alpha.moos", &read("alpha.moos"))).value;
    let bhv = mission::bhv::parse_bhv(&SourceMap::from_text("alpha.bhv", &read("alpha.bhv")));
    let mut best = f64::INFINITY;
    let mut simulated = 0.0;
    for _ in 0..runs {
        let buf = SharedBuffer::default();
        let target = LogTarget {
            config: logger_config(&m),
            writer: Box::new(buf.clone()),
            opened: NaiveDate::from_ymd_opt(2026, 1, 1)
                .unwrap()
                .and_hms_opt(0, 0, 0)
                .unwrap(),
            opened_on: "Thu Jan  1 00:00:00 1970".into(),
            side: None,
        };
        let p = plan(
            &m,
            Launch::new(START, 1).with_log(target),
            &mut |run, block| {
                (run.app == "pHelmIvP").then(|| {
                    Ok(
                        Box::new(HelmApp::new(run.moos_name(), block.cloned(), &m, &bhv))
                            as Box<dyn App>,
                    )
                })
            },
        )
        .expect("alpha plans");
        let mut s = Scheduler::new(Bus::new(&p.globals.community, START), VirtualClock, START);
        for app in p.apps {
            s.add_app(app).expect("unique names");
        }
        for poke in ["DEPLOY=true", "MOOS_MANUAL_OVERRIDE=false"] {
            s.add_poke(Poke::parse(poke, "pHelmIvP").unwrap()).unwrap();
        }
        s.set_until(mission::condition::parse_condition("MISSION = complete").unwrap());
        let wall = Instant::now();
        let outcome = s.run(3600.0).expect("run");
        s.deliver_pending().expect("flush");
        best = best.min(wall.elapsed().as_secs_f64());
        simulated = s.now() - START;
        println!("{outcome:?}, log {} bytes", buf.contents().len());
    }
    println!(
        "alpha: {simulated:.1} simulated s; best wall {best:.3} s of {runs}: {:.0}x real time",
        simulated / best
    );
}
