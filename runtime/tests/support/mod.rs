//! Shared set-up of the corpus mission tests: a real mission's ANTLER apps (the helm and the
//! built-in apps) in lockstep, with pLogger writing its alog into memory.

#![allow(dead_code)]

use chrono::NaiveDate;
use mission::source::SourceMap;
use runtime::antler::{Launch, LogTarget, logger_config, plan};
use runtime::helm::HelmApp;
use runtime::logger::SharedBuffer;
use runtime::{App, Bus, Outcome, Poke, Scheduler, VirtualClock};

/// The fixed MOOS start time of every lockstep run (so logs are byte-identical).
pub const START: f64 = 1_786_000_000.0;

/// Runs `../shared/corpus/moos-ivp-missions/<folder>/<name>.moos` (with `<name>.bhv`) in
/// lockstep with `pokes` (uPokeDB syntax, `@T` for a time) until `until` holds or `max_time`
/// simulated seconds pass. Returns the outcome and the alog bytes.
pub fn run_corpus(
    folder: &str,
    name: &str,
    pokes: &[&str],
    until: &str,
    max_time: f64,
) -> (Outcome, Vec<u8>) {
    let dir = test_support::mission_file(folder);
    run_dir(
        dir.to_str().expect("a UTF-8 path"),
        name,
        pokes,
        until,
        max_time,
    )
}

/// As [`run_corpus`], for `<dir>/<name>.moos` and `<dir>/<name>.bhv` anywhere (e.g. a mission
/// of this crate's `tests/data`).
pub fn run_dir(
    dir: &str,
    name: &str,
    pokes: &[&str],
    until: &str,
    max_time: f64,
) -> (Outcome, Vec<u8>) {
    let read = |file: &str| {
        let path = format!("{dir}/{file}");
        std::fs::read_to_string(&path)
            .unwrap_or_else(|e| panic!("mission file {path} is required: {e}"))
    };
    let moos_file = format!("{name}.moos");
    let bhv_file = format!("{name}.bhv");
    let m = mission::moos::parse_moos(&SourceMap::from_text(&moos_file, &read(&moos_file)));
    assert!(!m.has_errors(), "{moos_file} has errors");
    let m = m.value;
    let bhv = mission::bhv::parse_bhv(&SourceMap::from_text(&bhv_file, &read(&bhv_file)));
    let buf = SharedBuffer::default();
    let target = LogTarget {
        config: logger_config(&m),
        writer: Box::new(buf.clone()),
        opened: NaiveDate::from_ymd_opt(2026, 8, 5)
            .unwrap()
            .and_hms_opt(18, 22, 55)
            .unwrap(),
        opened_on: "Thu Jan  1 00:00:00 1970".into(),
        side: None,
    };
    let p = plan(
        &m,
        Launch::new(START, 1).with_log(target),
        &mut |run, block| {
            (run.app == "pHelmIvP").then(|| {
                let h = HelmApp::new(run.moos_name(), block.cloned(), &m, &bhv);
                let errors = h.config_errors();
                if errors.is_empty() {
                    Ok(Box::new(h) as Box<dyn App>)
                } else {
                    Err(errors.join("; "))
                }
            })
        },
    )
    .unwrap();
    let mut s = Scheduler::new(Bus::new(&p.globals.community, START), VirtualClock, START);
    for app in p.apps {
        s.add_app(app).unwrap();
    }
    for poke in pokes {
        s.add_poke(Poke::parse(poke, "pHelmIvP").unwrap()).unwrap();
    }
    s.set_until(mission::condition::parse_condition(until).unwrap());
    let outcome = s.run(max_time).unwrap();
    s.deliver_pending().unwrap();
    (outcome, buf.contents())
}

/// `RefCell`'s calls over a `Mutex`: the test apps that hold one are `Send`, as every app is.
#[derive(Debug, Default)]
pub struct RefCell<T>(std::sync::Mutex<T>);

impl<T> RefCell<T> {
    /// A cell holding `value`.
    pub fn new(value: T) -> Self {
        RefCell(std::sync::Mutex::new(value))
    }

    /// The value (a poisoned lock's too: a failed test's panic must not hide the next).
    pub fn borrow(&self) -> std::sync::MutexGuard<'_, T> {
        self.0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }

    /// The value, to change.
    pub fn borrow_mut(&self) -> std::sync::MutexGuard<'_, T> {
        self.borrow()
    }

    /// The value, leaving the default in its place.
    pub fn take(&self) -> T
    where
        T: Default,
    {
        std::mem::take(&mut *self.borrow())
    }
}
