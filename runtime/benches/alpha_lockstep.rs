//! Benchmark: the real s1_alpha mission in lockstep, deployed, until `MISSION = complete`,
//! with every app in-process (helm, simulator, PID, node reporter, pLogger writing to
//! memory), as `coug run --lockstep` runs it. Prints the speed-up over real time.
//! `cargo bench -p runtime --bench alpha_lockstep -- --warm-up-time 1 --measurement-time 10`

use std::time::Instant;

use chrono::NaiveDate;
use criterion::{Criterion, criterion_group, criterion_main};
use mission::Parsed;
use mission::bhv::BehaviorFile;
use mission::moos::MissionFile;
use mission::source::SourceMap;
use runtime::antler::{Launch, LogTarget, logger_config, plan};
use runtime::helm::HelmApp;
use runtime::logger::SharedBuffer;
use runtime::{App, Bus, Outcome, Poke, Scheduler, VirtualClock};

const START: f64 = 1_786_000_000.0;

fn load() -> (MissionFile, Parsed<BehaviorFile>) {
    let read = |n: &str| test_support::mission_text(&format!("s1_alpha/{n}"));
    let m =
        mission::moos::parse_moos(&SourceMap::from_text("alpha.moos", &read("alpha.moos"))).value;
    let bhv = mission::bhv::parse_bhv(&SourceMap::from_text("alpha.bhv", &read("alpha.bhv")));
    (m, bhv)
}

/// One run; returns the simulated seconds.
fn run(m: &MissionFile, bhv: &Parsed<BehaviorFile>) -> f64 {
    let target = LogTarget {
        config: logger_config(m),
        writer: Box::new(SharedBuffer::default()),
        opened: NaiveDate::from_ymd_opt(2026, 1, 1)
            .unwrap()
            .and_hms_opt(0, 0, 0)
            .unwrap(),
        opened_on: "Thu Jan  1 00:00:00 1970".into(),
        side: None,
    };
    let p = plan(
        m,
        Launch::new(START, 1).with_log(target),
        &mut |run, block| {
            (run.app == "pHelmIvP").then(|| {
                Ok(Box::new(HelmApp::new(run.moos_name(), block.cloned(), m, bhv)) as Box<dyn App>)
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
    let outcome = s.run(3600.0).expect("run");
    s.deliver_pending().expect("flush");
    assert!(
        matches!(outcome, Outcome::ConditionMet { .. }),
        "{outcome:?}"
    );
    s.now() - START
}

fn bench(c: &mut Criterion) {
    let (m, bhv) = load();
    let mut g = c.benchmark_group("lockstep");
    g.sample_size(10);
    g.bench_function("alpha_to_mission_complete", |b| b.iter(|| run(&m, &bhv)));
    g.finish();
    let mut best = f64::INFINITY;
    let mut simulated = 0.0;
    for _ in 0..3 {
        let t = Instant::now();
        simulated = run(&m, &bhv);
        best = best.min(t.elapsed().as_secs_f64());
    }
    println!(
        "alpha lockstep: {simulated:.1} simulated s in {best:.3} wall s (best of 3): {:.0}x real time",
        simulated / best
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);
