//! The scheduler: runs apps on the bus, each at its own AppTick, paced by a [`Clock`].
//!
//! Time is virtual: app `i` iterates at `start + k / AppTick_i` (k = 0, 1, ...). Events are
//! processed in time order; at equal times, timed pokes come first, then apps in the order
//! they were added (ANTLER order). Before each iterate an app gets, sorted by time, all
//! mail posted to it up to and including that time. With a [`VirtualClock`] two runs of
//! the same apps give the same sequence of posts, bit for bit.

use std::collections::BTreeSet;

use mission::condition::{self, Condition};
use moosdb::db::ClientId;
use moosdb::{DataType, Message};
use thiserror::Error;

use crate::app::{App, AppError, Mail, Post, STATUS_PERIOD, Value};
use crate::bus::{Bus, BusError, DbHost, LocalDb};
use crate::clock::{Clock, VirtualClock};
use moos_types::ByteString;
use rustc_hash::FxHashSet;

/// When a poke is posted.
#[derive(Debug, Clone, PartialEq)]
pub enum PokeAt {
    /// At this many simulated seconds after the start.
    Time(f64),
    /// Right after the named app's first iterate (e.g. "once the helm is up"); at the
    /// start if no such app runs.
    AfterFirstIterate(String),
}

/// A value posted once by the runner, as uPokeDB would (source `uPokeDB`).
#[derive(Debug, Clone, PartialEq)]
pub struct Poke {
    /// Variable.
    pub key: String,
    /// Value.
    pub value: Value,
    /// When.
    pub at: PokeAt,
}

/// Why a lockstep run stopped with an error: the bus refused something, or an app failed
/// (its error ends the run at once).
#[derive(Debug, Error)]
pub enum RunError {
    /// The bus (the in-process MOOSDB) refused a client or a registration.
    #[error(transparent)]
    Bus(#[from] BusError),
    /// An app failed.
    #[error(transparent)]
    App(#[from] AppError),
}

/// A `--poke` argument that cannot be read.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum PokeError {
    /// No `=` or an empty variable name.
    #[error("poke {0:?}: expected VAR=VALUE, VAR:=VALUE or VAR=VALUE@SECONDS")]
    Syntax(String),
}

impl Poke {
    /// Reads `VAR=VALUE`, `VAR:=VALUE` (always a string) or either with `@T` (posted at
    /// `T` simulated seconds after the start; `T` must be a number >= 0, otherwise the
    /// `@...` is part of the value). Without a time, the poke goes out after `default_app`'s
    /// first iterate. The `VAR=VALUE` part is read as uPokeDB reads it
    /// ([`moos_types::text::parse_poke`]).
    ///
    /// ```
    /// use runtime::scheduler::{Poke, PokeAt};
    /// use runtime::app::Value;
    /// let p = Poke::parse("SURVEY=true@300", "pHelmIvP").unwrap();
    /// assert_eq!((p.key.as_str(), &p.value, &p.at), ("SURVEY", &Value::text("true"), &PokeAt::Time(300.0)));
    /// ```
    pub fn parse(arg: &str, default_app: &str) -> Result<Poke, PokeError> {
        let (body, at) = match arg.rsplit_once('@') {
            Some((b, t)) => match t.trim().parse::<f64>() {
                Ok(t) if t.is_finite() && t >= 0.0 => (b, PokeAt::Time(t)),
                _ => (arg, PokeAt::AfterFirstIterate(default_app.to_string())),
            },
            None => (arg, PokeAt::AfterFirstIterate(default_app.to_string())),
        };
        let Some((key, value)) = moos_types::text::parse_poke(body) else {
            return Err(PokeError::Syntax(arg.to_string()));
        };
        if key.is_empty() {
            return Err(PokeError::Syntax(arg.to_string()));
        }
        Ok(Poke {
            key: key.to_string(),
            value,
            at,
        })
    }
}

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// The `until` condition held at this MOOS time.
    ConditionMet {
        /// MOOS time.
        time: f64,
    },
    /// The time limit was reached first.
    MaxTime {
        /// MOOS time.
        time: f64,
    },
    /// Every app finished (none left to schedule).
    AllFinished {
        /// MOOS time.
        time: f64,
    },
}

struct Slot {
    app: Box<dyn App>,
    id: ClientId,
    name: String,
    status_var: String,
    /// Iterations per second; tick `k` is at `origin + k / hz` (a division, so apps whose
    /// ticks coincide exactly get the same time and tie by app order).
    hz: f64,
    ticks: u64,
    origin: f64,
    next: f64,
    started_at: f64,
    last_status: Option<f64>,
    published: BTreeSet<String>,
    /// The names in `published`, hashed: a post's name is looked up here, cheaply, and
    /// added to the sorted set only the first time.
    published_known: FxHashSet<ByteString>,
    subscribed: BTreeSet<String>,
    done: bool,
}

/// Runs apps on a [`Bus`]. See the module documentation.
pub struct Scheduler<C: Clock = VirtualClock, H: DbHost = LocalDb> {
    bus: Bus<H>,
    clock: C,
    start: f64,
    now: f64,
    slots: Vec<Slot>,
    timed: Vec<(f64, Post)>,
    after: Vec<(String, Post)>,
    poke_client: Option<ClientId>,
    until: Option<Condition>,
    /// True when the `until` condition ends [`Scheduler::advance`] (false: it is only
    /// watched, see [`Scheduler::watch_until`]).
    until_ends_run: bool,
    /// The `until` condition's variables, each once.
    until_vars: Vec<String>,
    /// Their current values at the last check (reused, so a check allocates nothing).
    until_msgs: Vec<Option<Message>>,
    armed: bool,
    status_posts: bool,
    started: bool,
    mail: Vec<Mail>,
    posts: Vec<Post>,
    tapped: Vec<String>,
    taps: Vec<Post>,
}

impl<C: Clock, H: DbHost> Scheduler<C, H> {
    /// A scheduler over `bus`, paced by `clock`, starting at MOOS time `start`.
    pub fn new(bus: Bus<H>, clock: C, start: f64) -> Self {
        Scheduler {
            bus,
            clock,
            start,
            now: start,
            slots: Vec::new(),
            timed: Vec::new(),
            after: Vec::new(),
            poke_client: None,
            until: None,
            until_ends_run: true,
            until_vars: Vec::new(),
            until_msgs: Vec::new(),
            armed: true,
            status_posts: true,
            started: false,
            mail: Vec::new(),
            posts: Vec::new(),
            tapped: Vec::new(),
            taps: Vec::new(),
        }
    }

    /// Keeps a copy of every app post of `key` (e.g. `IVPHELM_SUMMARY`, whose reports
    /// carry only changed fields) for [`Scheduler::take_taps`]; does not touch the bus.
    pub fn tap(&mut self, key: &str) {
        if !self.tapped.iter().any(|k| k == key) {
            self.tapped.push(key.to_string());
        }
    }

    /// The tapped posts since the last call, in the order they were made.
    pub fn take_taps(&mut self) -> Vec<Post> {
        std::mem::take(&mut self.taps)
    }

    fn record_taps(tapped: &[String], taps: &mut Vec<Post>, posts: &[Post]) {
        if tapped.is_empty() {
            return;
        }
        taps.extend(
            posts
                .iter()
                .filter(|p| tapped.iter().any(|k| **k == *p.key))
                .cloned(),
        );
    }

    /// Turns the CMOOSApp `<APP>_STATUS` posts (every 2 s per app) on or off (default on).
    pub fn set_status_posts(&mut self, on: bool) {
        self.status_posts = on;
    }

    /// Adds an app (connects it and makes its registrations). Apps run in the order added.
    /// An app added after the run began starts at the current time.
    pub fn add_app(&mut self, mut app: Box<dyn App>) -> Result<(), RunError> {
        let now = self.now;
        let name = app.name().to_string();
        let id = self.bus.connect(&name, now)?;
        self.bus.set_unread(id, app.unread(), now)?;
        let mut subscribed = BTreeSet::new();
        for s in app.subscriptions() {
            self.bus.subscribe(id, &s, now)?;
            subscribed.insert(s.pattern);
        }
        let hz = app.app_tick();
        let mut published = BTreeSet::new();
        let mut published_known = FxHashSet::default();
        if self.started {
            self.posts.clear();
            app.on_startup(now, &mut self.posts)?;
            published.extend(self.posts.iter().map(|p| p.key.to_string()));
            published_known.extend(self.posts.iter().map(|p| p.key.clone()));
            self.bus.publish(id, self.posts.drain(..), &name, now)?;
        }
        self.slots.push(Slot {
            status_var: format!("{}_STATUS", name.to_ascii_uppercase()),
            app,
            id,
            name,
            hz,
            ticks: 0,
            origin: now,
            next: now,
            started_at: now,
            last_status: None,
            published,
            published_known,
            subscribed,
            done: false,
        });
        Ok(())
    }

    /// Schedules a poke.
    pub fn add_poke(&mut self, poke: Poke) -> Result<(), BusError> {
        if self.poke_client.is_none() {
            self.poke_client = Some(self.bus.connect("uPokeDB", self.start)?);
        }
        let post = Post {
            key: poke.key.into(),
            value: poke.value,
            source: ByteString::from_static("uPokeDB"),
            aux: ByteString::new(),
            relayed: None,
        };
        match poke.at {
            PokeAt::Time(t) => {
                let at = self.start + t;
                let i = self.timed.partition_point(|(pt, _)| *pt <= at);
                self.timed.insert(i, (at, post));
            }
            PokeAt::AfterFirstIterate(app) => {
                self.after.push((app, post));
                self.armed = false;
            }
        }
        Ok(())
    }

    /// Ends the run when `cond` holds on the bus's current values. It is checked after
    /// every event, once every after-first-iterate poke has gone out (so `DEPLOY = false`
    /// is not met by the helm's initial value before `--deploy` is posted).
    pub fn set_until(&mut self, cond: Condition) {
        self.until_vars.clear();
        for v in cond.variables() {
            if !self.until_vars.iter().any(|u| u == v) {
                self.until_vars.push(v.to_string());
            }
        }
        self.until = Some(cond);
        self.until_ends_run = true;
    }

    /// Keeps `cond` as the `until` condition without ending the run on it: the caller asks
    /// [`Scheduler::until_holds`] when it wants (a fleet run ends when every community's
    /// condition holds at once, so no community may stop on its own).
    pub fn watch_until(&mut self, cond: Condition) {
        self.set_until(cond);
        self.until_ends_run = false;
    }

    /// The MOOS time of the next event (an app's tick or a timed poke), `None` when no app
    /// is left to run and no poke is waiting. Before the first [`Scheduler::advance`] it is
    /// the start time.
    pub fn next_event_time(&self) -> Option<f64> {
        let app = self
            .slots
            .iter()
            .filter(|s| !s.done)
            .map(|s| s.next)
            .min_by(f64::total_cmp);
        let poke = self.timed.first().map(|(t, _)| *t);
        match (app, poke) {
            (Some(a), Some(p)) => Some(a.min(p)),
            (a, p) => a.or(p),
        }
    }

    /// The start time.
    pub fn start_time(&self) -> f64 {
        self.start
    }

    /// The time of the last event processed.
    pub fn now(&self) -> f64 {
        self.now
    }

    /// The bus.
    pub fn bus(&self) -> &Bus<H> {
        &self.bus
    }

    /// The bus, mutably (e.g. to serve TCP clients from the same DB).
    pub fn bus_mut(&mut self) -> &mut Bus<H> {
        &mut self.bus
    }

    /// The current value of a variable on the bus.
    pub fn current(&self, key: &str) -> Option<Value> {
        self.bus.current(key).map(|m| m.value)
    }

    /// The `until` condition's variables with their current values (for a summary or a
    /// "still pending" message).
    pub fn until_values(&self) -> Vec<(String, Option<Value>)> {
        let Some(c) = &self.until else {
            return Vec::new();
        };
        let mut seen = BTreeSet::new();
        c.variables()
            .into_iter()
            .filter(|v| seen.insert(v.to_string()))
            .map(|v| (v.to_string(), self.current(v)))
            .collect()
    }

    /// True when the `until` condition is set, armed and holds now. Reads the DB's values
    /// in place: a check allocates nothing (a string that is not UTF-8 is compared as its
    /// lossy copy).
    pub fn until_holds(&mut self) -> bool {
        let Some(c) = &self.until else {
            return false;
        };
        if !self.armed {
            return false;
        }
        self.until_msgs.clear();
        for v in &self.until_vars {
            let mut m = self.bus.current_message(v);
            if let Some(m) = m.as_mut().filter(|m| m.data_type == DataType::String)
                && std::str::from_utf8(&m.sval).is_err()
            {
                m.sval = String::from_utf8_lossy(&m.sval).into_owned().into();
            }
            self.until_msgs.push(m);
        }
        let (vars, msgs) = (&self.until_vars, &self.until_msgs);
        let lookup = |name: &str| -> Option<condition::Value<'_>> {
            let i = vars.iter().position(|v| v == name)?;
            let m = msgs.get(i)?.as_ref()?;
            match m.data_type {
                DataType::Double => Some(condition::Value::Double(m.dval)),
                DataType::String => std::str::from_utf8(&m.sval)
                    .ok()
                    .map(condition::Value::String),
                DataType::Binary | DataType::NotSet => None,
            }
        };
        c.evaluate(&lookup)
    }

    fn startup(&mut self) -> Result<(), RunError> {
        let _span = tracing::debug_span!("startup", apps = self.slots.len()).entered();
        self.started = true;
        let now = self.start;
        for i in 0..self.slots.len() {
            self.posts.clear();
            let slot = &mut self.slots[i];
            slot.app.on_startup(now, &mut self.posts)?;
            Self::record_taps(&self.tapped, &mut self.taps, &self.posts);
            Self::publish(&mut self.bus, slot, &mut self.posts, now)?;
        }
        // Pokes waiting for apps that do not run go out at the start.
        let names: Vec<String> = self.slots.iter().map(|s| s.name.clone()).collect();
        let orphans: Vec<Post> = self
            .after
            .iter()
            .filter(|(a, _)| !names.contains(a))
            .map(|(_, p)| p.clone())
            .collect();
        self.after.retain(|(a, _)| names.contains(a));
        self.post_pokes(&orphans, now)?;
        if self.after.is_empty() {
            self.armed = true;
        }
        Ok(())
    }

    fn post_pokes(&mut self, posts: &[Post], now: f64) -> Result<(), BusError> {
        if let Some(id) = self.poke_client {
            self.bus
                .publish(id, posts.iter().cloned(), "uPokeDB", now)?;
        }
        Ok(())
    }

    /// Publishes (and empties) `posts`, the slot's app's.
    fn publish(
        bus: &mut Bus<H>,
        slot: &mut Slot,
        posts: &mut Vec<Post>,
        now: f64,
    ) -> Result<(), BusError> {
        for p in posts.iter() {
            if !slot.published_known.contains(&p.key) {
                slot.published_known.insert(p.key.clone());
                slot.published.insert(p.key.to_string());
            }
        }
        bus.publish(slot.id, posts.drain(..), &slot.name, now)
    }

    /// Processes every event due at or before MOOS time `t_end`. Returns the outcome if
    /// the run ended (condition met, or every app finished), `None` otherwise.
    pub fn advance(&mut self, t_end: f64) -> Result<Option<Outcome>, RunError> {
        let _span = tracing::trace_span!("advance", t_end).entered();
        if !self.started {
            self.startup()?;
            if self.until_ends_run && self.until_holds() {
                return Ok(Some(Outcome::ConditionMet { time: self.now }));
            }
        }
        loop {
            let next_app = self
                .slots
                .iter()
                .enumerate()
                .filter(|(_, s)| !s.done)
                .min_by(|a, b| a.1.next.total_cmp(&b.1.next).then(a.0.cmp(&b.0)))
                .map(|(i, s)| (i, s.next));
            let next_poke = self.timed.first().map(|(t, _)| *t);
            let (t, which) = match (next_app, next_poke) {
                (None, None) => return Ok(Some(Outcome::AllFinished { time: self.now })),
                (Some((i, ta)), Some(tp)) if ta < tp => (ta, Some(i)),
                (Some((i, ta)), None) => (ta, Some(i)),
                (_, Some(tp)) => (tp, None),
            };
            if t > t_end {
                return Ok(None);
            }
            self.now = self.clock.wait_until(t);
            match which {
                None => {
                    let (_, post) = self.timed.remove(0);
                    self.post_pokes(std::slice::from_ref(&post), t)?;
                }
                Some(i) => self.step(i, t)?,
            }
            if self.until_ends_run && self.until_holds() {
                return Ok(Some(Outcome::ConditionMet { time: t }));
            }
            if self.slots.iter().all(|s| s.done) && self.timed.is_empty() {
                return Ok(Some(Outcome::AllFinished { time: t }));
            }
        }
    }

    /// Runs until the `until` condition holds, every app finished, or `max_time`
    /// simulated seconds after the start.
    pub fn run(&mut self, max_time: f64) -> Result<Outcome, RunError> {
        let end = self.start + max_time;
        Ok(self.advance(end)?.unwrap_or(Outcome::MaxTime { time: end }))
    }

    /// Delivers the mail still waiting to every running app (on_mail only, no iterate),
    /// at the current time. Call it when a run ends, so the logger records the posts of
    /// the last event (such as the one that met the `until` condition). Posts the apps
    /// make in reply are published.
    pub fn deliver_pending(&mut self) -> Result<(), RunError> {
        let now = self.now;
        for i in 0..self.slots.len() {
            if self.slots[i].done {
                continue;
            }
            self.mail.clear();
            self.posts.clear();
            let slot = &mut self.slots[i];
            self.bus.fetch(slot.id, now, &mut self.mail)?;
            if !self.mail.is_empty() {
                slot.app.on_mail(&self.mail, now, &mut self.posts)?;
                Self::record_taps(&self.tapped, &mut self.taps, &self.posts);
                Self::publish(&mut self.bus, slot, &mut self.posts, now)?;
            }
        }
        Ok(())
    }

    /// Ends the run: every app's stop hook (flush, close, report), in order. All run; the
    /// first error is returned.
    pub fn stop(&mut self) -> Result<(), AppError> {
        let _span = tracing::debug_span!("stop", now = self.now).entered();
        let now = self.now;
        let mut first = None;
        for slot in &mut self.slots {
            if let Err(e) = slot.app.stop(now)
                && first.is_none()
            {
                first = Some(e);
            }
        }
        first.map_or(Ok(()), Err)
    }

    fn step(&mut self, i: usize, now: f64) -> Result<(), RunError> {
        self.mail.clear();
        self.posts.clear();
        let slot = &mut self.slots[i];
        // One span per app iteration: `RUST_LOG=runtime=trace` shows which app and when.
        let _span = tracing::trace_span!("app", name = %slot.name, now).entered();
        self.bus.fetch(slot.id, now, &mut self.mail)?;
        if !self.mail.is_empty() {
            slot.app.on_mail(&self.mail, now, &mut self.posts)?;
        }
        if self.status_posts
            && slot
                .last_status
                .is_none_or(|last| now - last >= STATUS_PERIOD - 1e-9)
        {
            slot.last_status = Some(now);
            let status = status_text(slot, now);
            let key = slot.status_var.clone();
            self.posts.push(Post::text(key, status));
        }
        slot.app.iterate(now, &mut self.posts)?;
        for s in slot.app.new_subscriptions() {
            self.bus.subscribe(slot.id, &s, now)?;
            slot.subscribed.insert(s.pattern);
        }
        Self::record_taps(&self.tapped, &mut self.taps, &self.posts);
        Self::publish(&mut self.bus, slot, &mut self.posts, now)?;
        let first = slot.ticks == 0;
        slot.ticks += 1;
        slot.next = slot.origin + slot.ticks as f64 / slot.hz;
        if slot.app.finished() {
            slot.done = true;
            let id = slot.id;
            self.bus.disconnect(id, now);
        }
        if first && !self.after.is_empty() {
            let name = self.slots[i].name.clone();
            let due: Vec<Post> = self
                .after
                .iter()
                .filter(|(a, _)| *a == name)
                .map(|(_, p)| p.clone())
                .collect();
            self.after.retain(|(a, _)| *a != name);
            self.post_pokes(&due, now)?;
            if self.after.is_empty() {
                self.armed = true;
            }
        }
        Ok(())
    }
}

fn status_text(slot: &Slot, now: f64) -> String {
    crate::app::status_text(
        &slot.name,
        now - slot.started_at,
        None,
        &slot.published,
        &slot.subscribed,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poke_arguments() {
        let p = Poke::parse("DEPLOY=true", "pHelmIvP").unwrap();
        assert_eq!(p.value, Value::text("true"));
        assert_eq!(p.at, PokeAt::AfterFirstIterate("pHelmIvP".into()));
        let p = Poke::parse("X=3.5@12", "h").unwrap();
        assert_eq!((p.value, p.at), (Value::Double(3.5), PokeAt::Time(12.0)));
        let p = Poke::parse("N:=2.5", "h").unwrap();
        assert_eq!(p.value, Value::text("2.5"));
        let p = Poke::parse("MAIL=a@b", "h").unwrap();
        assert_eq!(p.value, Value::text("a@b"));
        let p = Poke::parse("Q=\"42\"", "h").unwrap();
        assert_eq!(p.value, Value::text("\"42\""));
        let p = Poke::parse("E=", "h").unwrap();
        assert_eq!(p.value, Value::text(""));
        assert!(Poke::parse("NOEQUALS", "h").is_err());
        assert!(Poke::parse("=3", "h").is_err());
        assert!(Poke::parse("X=1@-3", "h").unwrap().value == Value::text("1@-3"));
    }

    struct Counter {
        n: u32,
    }

    impl App for Counter {
        fn name(&self) -> &str {
            "counter"
        }
        fn app_tick(&self) -> f64 {
            2.0
        }
        fn iterate(&mut self, _now: f64, out: &mut Vec<Post>) -> crate::app::AppResult {
            self.n += 1;
            out.push(Post::double("COUNT", f64::from(self.n)));
            out.push(Post::text("OTHER", "x"));
            Ok(())
        }
    }

    #[test]
    fn next_event_time_and_a_watched_condition() {
        let mut s = Scheduler::new(Bus::new("t", 10.0), VirtualClock, 10.0);
        assert_eq!(s.next_event_time(), None);
        s.add_app(Box::new(Counter { n: 0 })).unwrap();
        s.add_poke(Poke::parse("X=1@0.2", "h").unwrap()).unwrap();
        assert_eq!(s.next_event_time(), Some(10.0));
        // Watched, not ending: advance runs through the instant the condition holds.
        s.watch_until(mission::condition::parse_condition("COUNT >= 2").unwrap());
        assert_eq!(s.advance(10.0).unwrap(), None);
        assert!(!s.until_holds());
        assert_eq!(s.next_event_time(), Some(10.2));
        assert_eq!(s.advance(10.2).unwrap(), None);
        assert_eq!(s.next_event_time(), Some(10.5));
        assert_eq!(s.advance(11.0).unwrap(), None);
        assert!(s.until_holds());
        assert_eq!(s.current("COUNT"), Some(Value::Double(3.0)));
        // set_until ends the run again.
        s.set_until(mission::condition::parse_condition("COUNT >= 4").unwrap());
        assert_eq!(
            s.advance(20.0).unwrap(),
            Some(Outcome::ConditionMet { time: 11.5 })
        );
    }

    #[test]
    fn taps_copy_every_post_of_a_key_in_order() {
        let mut s = Scheduler::new(Bus::new("t", 0.0), VirtualClock, 0.0);
        s.add_app(Box::new(Counter { n: 0 })).unwrap();
        s.tap("COUNT");
        s.run(2.0).unwrap();
        let taps = s.take_taps();
        // Ticks at 0, 0.5, 1, 1.5 and 2 s: five posts, none of OTHER.
        let values: Vec<f64> = taps.iter().filter_map(|p| p.value.as_f64()).collect();
        assert_eq!(values, vec![1.0, 2.0, 3.0, 4.0, 5.0]);
        assert!(taps.iter().all(|p| p.key == "COUNT"));
        assert!(s.take_taps().is_empty());
    }
}
