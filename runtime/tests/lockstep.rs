//! Lockstep runs of small fake apps on the in-process bus, logged by the built-in pLogger.

mod support;

use std::sync::Arc;

use chrono::NaiveDate;
use mission::condition::parse_condition;
use runtime::logger::{Logger, LoggerConfig, SharedBuffer};
use runtime::{App, Bus, Mail, Outcome, Poke, Post, Scheduler, Subscription, Value, VirtualClock};
use support::RefCell;

const START: f64 = 1_700_000_000.0;

/// Posts COUNT = 0, 1, 2, ... once per iterate.
struct Counter {
    n: u32,
}

impl App for Counter {
    fn name(&self) -> &str {
        "counter"
    }
    fn app_tick(&self) -> f64 {
        4.0
    }
    fn iterate(&mut self, _now: f64, out: &mut Vec<Post>) -> runtime::AppResult {
        out.push(Post::double("COUNT", f64::from(self.n)));
        self.n += 1;
        Ok(())
    }
}

/// What the doubler saw: per iterate, its time and the times/values of the mail before it.
type Seen = Arc<RefCell<Vec<(f64, Vec<(f64, f64)>)>>>;

/// Posts DOUBLE = 2 × the latest COUNT it has received.
struct Doubler {
    last: Option<f64>,
    pending: Vec<(f64, f64)>,
    seen: Seen,
}

impl App for Doubler {
    fn name(&self) -> &str {
        "doubler"
    }
    fn app_tick(&self) -> f64 {
        2.0
    }
    fn subscriptions(&self) -> Vec<Subscription> {
        vec![Subscription::var("COUNT")]
    }
    fn on_mail(&mut self, mail: &[Mail], _now: f64, _out: &mut Vec<Post>) -> runtime::AppResult {
        for m in mail {
            assert_eq!(m.source, "counter");
            let v = m.value.as_f64().unwrap();
            self.pending.push((m.time, v));
            self.last = Some(v);
        }
        Ok(())
    }
    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> runtime::AppResult {
        self.seen
            .borrow_mut()
            .push((now, std::mem::take(&mut self.pending)));
        if let Some(v) = self.last {
            out.push(Post::double("DOUBLE", 2.0 * v));
        }
        Ok(())
    }
}

struct Run {
    outcome: Outcome,
    alog: Vec<u8>,
    seen: Vec<(f64, Vec<(f64, f64)>)>,
    go: Option<Value>,
}

fn run(until: &str, max_time: f64) -> Run {
    let seen: Seen = Arc::default();
    let mut s = Scheduler::new(Bus::new("lockstep", START), VirtualClock, START);
    s.add_app(Box::new(Counter { n: 0 })).unwrap();
    s.add_app(Box::new(Doubler {
        last: None,
        pending: Vec::new(),
        seen: seen.clone(),
    }))
    .unwrap();
    let buf = SharedBuffer::default();
    let opened = NaiveDate::from_ymd_opt(2026, 8, 5)
        .unwrap()
        .and_hms_opt(18, 22, 55)
        .unwrap();
    let config = LoggerConfig::from_config(None, None);
    let logger = Logger::new(
        "pLogger",
        None,
        config,
        buf.clone(),
        &opened,
        "Thu Jan  1 00:00:00 1970",
    );
    s.add_app(Box::new(logger)).unwrap();
    s.add_poke(Poke::parse("GO=true@3.0", "counter").unwrap())
        .unwrap();
    s.add_poke(Poke::parse("HELLO=1", "counter").unwrap())
        .unwrap();
    s.set_until(parse_condition(until).unwrap());
    let outcome = s.run(max_time).unwrap();
    let before = buf.contents().len();
    s.deliver_pending().unwrap();
    assert!(
        buf.contents().len() > before,
        "the last posts reach the log"
    );
    let go = s.current("GO");
    Run {
        outcome,
        alog: buf.contents(),
        seen: seen.take(),
        go,
    }
}

#[test]
fn two_runs_give_byte_identical_logs() {
    let a = run("(DOUBLE >= 20) and (GO = true)", 60.0);
    let b = run("(DOUBLE >= 20) and (GO = true)", 60.0);
    assert!(a.alog.len() > 1000, "log too small: {}", a.alog.len());
    assert_eq!(a.alog, b.alog);
    assert_eq!(a.outcome, b.outcome);
}

#[test]
fn until_ends_the_run_when_the_poke_makes_it_true() {
    let r = run("(DOUBLE >= 20) and (GO = true)", 60.0);
    // DOUBLE reaches 20 at 2.5 s (COUNT 10 posted at 2.5, seen by the doubler in the same
    // tick since it runs after the counter); GO is poked at 3.0.
    assert_eq!(r.outcome, Outcome::ConditionMet { time: START + 3.0 });
    assert_eq!(r.go, Some(Value::text("true")));
    let r = run("DOUBLE >= 20", 60.0);
    assert_eq!(r.outcome, Outcome::ConditionMet { time: START + 2.5 });
    // The post that met the condition is in the log (delivered after the run ended).
    let log = alog::parse(std::str::from_utf8(&r.alog).unwrap()).unwrap();
    let last = log
        .entries
        .iter()
        .rev()
        .find(|e| e.var == "DOUBLE")
        .unwrap();
    assert_eq!((last.time, last.value.as_f64()), (2.5, Some(20.0)));
}

#[test]
fn max_time_ends_a_run_whose_condition_never_holds() {
    let r = run("DOUBLE < 0", 4.0);
    assert_eq!(r.outcome, Outcome::MaxTime { time: START + 4.0 });
}

#[test]
fn app_tick_cadence_and_mail_order() {
    let r = run("DOUBLE < 0", 10.0);
    let log = alog::parse(std::str::from_utf8(&r.alog).unwrap()).unwrap();
    assert_eq!(log.log_start, Some(START));
    // Counter: 4 Hz from t = 0, values 0, 1, 2, ... in order.
    let counts: Vec<(f64, f64)> = log
        .entries
        .iter()
        .filter(|e| e.var == "COUNT")
        .map(|e| (e.time, e.value.as_f64().unwrap()))
        .collect();
    assert!(counts.len() >= 39, "{}", counts.len());
    for (k, (t, v)) in counts.iter().enumerate() {
        assert_eq!(*t, k as f64 * 0.25, "COUNT #{k} time");
        assert_eq!(*v, k as f64);
    }
    // Doubler: 2 Hz; before each iterate it gets, sorted, every COUNT posted up to then
    // and not yet delivered: all of them, none twice, none from the future.
    let mut expected_next = 0.0;
    for (k, (now, mail)) in r.seen.iter().enumerate() {
        assert_eq!(*now, START + k as f64 * 0.5, "doubler iterate #{k}");
        for (t, v) in mail {
            assert!(*t <= *now, "mail from the future");
            assert_eq!(*v, expected_next, "mail out of order or lost at {now}");
            expected_next += 1.0;
        }
        let due = ((now - START) / 0.25).floor() + 1.0;
        assert_eq!(expected_next, due, "all COUNTs up to {now} delivered");
    }
    // The pokes went out from uPokeDB: HELLO after the counter's first iterate, GO at 3 s.
    let poke = |var: &str| {
        log.entries
            .iter()
            .find(|e| e.var == var)
            .map(|e| (e.time, e.source.clone(), e.value.clone()))
            .unwrap()
    };
    assert_eq!(
        poke("HELLO"),
        (0.0, "uPokeDB".into(), alog::Value::Double(1.0))
    );
    assert_eq!(
        poke("GO"),
        (3.0, "uPokeDB".into(), alog::Value::String("true".into()))
    );
    // CMOOSApp-style status every 2 s, and the DB's own variables.
    let status: Vec<f64> = log
        .entries
        .iter()
        .filter(|e| e.var == "COUNTER_STATUS")
        .map(|e| e.time)
        .collect();
    assert_eq!(&status[..4], &[0.0, 2.0, 4.0, 6.0]);
    let st = log
        .entries
        .iter()
        .find(|e| e.var == "DOUBLER_STATUS")
        .unwrap();
    assert!(
        st.value
            .as_str()
            .unwrap()
            .ends_with("MOOSName=doubler,Publishing=\"\",Subscribing=\"COUNT,\"")
    );
    assert!(log.entries.iter().any(|e| e.var == "DB_CLIENTS"));
    assert!(log.entries.iter().any(|e| e.var == "LOGGER_DIRECTORY"));
    // Records are in time order.
    assert!(log.entries.windows(2).all(|w| w[0].time <= w[1].time));
}

/// Records its start-up and iterate times.
struct Recorder {
    times: Arc<RefCell<Vec<(&'static str, f64)>>>,
}

impl App for Recorder {
    fn name(&self) -> &str {
        "recorder"
    }
    fn app_tick(&self) -> f64 {
        4.0
    }
    fn on_startup(&mut self, now: f64, out: &mut Vec<Post>) -> runtime::AppResult {
        self.times.borrow_mut().push(("startup", now));
        out.push(Post::text("RECORDER_UP", "yes"));
        Ok(())
    }
    fn iterate(&mut self, now: f64, _out: &mut Vec<Post>) -> runtime::AppResult {
        self.times.borrow_mut().push(("iterate", now));
        Ok(())
    }
}

#[test]
fn an_app_added_during_a_run_starts_at_the_current_time() {
    let mut s = Scheduler::new(Bus::new("late", START), VirtualClock, START);
    s.add_app(Box::new(Counter { n: 0 })).unwrap();
    assert_eq!(s.advance(START + 1.1).unwrap(), None);
    assert_eq!(s.now(), START + 1.0);
    let times: Arc<RefCell<Vec<(&'static str, f64)>>> = Arc::default();
    s.add_app(Box::new(Recorder {
        times: times.clone(),
    }))
    .unwrap();
    assert_eq!(s.current("RECORDER_UP"), Some(Value::text("yes")));
    s.advance(START + 1.6).unwrap();
    assert_eq!(
        times.take(),
        vec![
            ("startup", START + 1.0),
            ("iterate", START + 1.0),
            ("iterate", START + 1.25),
            ("iterate", START + 1.5)
        ]
    );
}

/// Records the times it iterates, under a given name and rate.
struct Ticker {
    name: &'static str,
    hz: f64,
    log: Arc<RefCell<Vec<(&'static str, f64)>>>,
}

impl App for Ticker {
    fn name(&self) -> &str {
        self.name
    }
    fn app_tick(&self) -> f64 {
        self.hz
    }
    fn iterate(&mut self, now: f64, _out: &mut Vec<Post>) -> runtime::AppResult {
        self.log.borrow_mut().push((self.name, now));
        Ok(())
    }
}

#[test]
fn coinciding_ticks_of_different_rates_tie_by_app_order() {
    // 3 × (1/5) and 15 × (1/25) differ as floats; tick k is k / AppTick, so 0.6 s is one
    // instant for both apps and the earlier-added app goes first.
    let log: Arc<RefCell<Vec<(&'static str, f64)>>> = Arc::default();
    let mut s = Scheduler::new(Bus::new("ties", 0.0), VirtualClock, 0.0);
    s.set_status_posts(false);
    for (name, hz) in [("slow", 5.0), ("fast", 25.0)] {
        s.add_app(Box::new(Ticker {
            name,
            hz,
            log: log.clone(),
        }))
        .unwrap();
    }
    s.advance(0.61).unwrap();
    let at_06: Vec<&str> = log
        .borrow()
        .iter()
        .filter(|(_, t)| *t == 0.6)
        .map(|(n, _)| *n)
        .collect();
    assert_eq!(at_06, vec!["slow", "fast"]);
    assert_eq!(
        log.borrow().iter().filter(|(n, _)| *n == "fast").count(),
        16
    );
}
