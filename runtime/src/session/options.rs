//! What a run is asked to do, and what its caller is told while it runs.

use std::path::PathBuf;

use crate::app::Value;

/// How the apps run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mode {
    /// Every app and the bus in one thread on a virtual clock: deterministic, as fast as the
    /// CPU allows, starting at [`super::LOCKSTEP_START`].
    Lockstep,
    /// Real time times a warp, the MOOSDB on TCP so real MOOS apps can join; ANTLER apps
    /// coug does not build in are started from PATH.
    RealTime {
        /// The speed-up (default: the mission's MOOSTimeWarp).
        warp: Option<f64>,
        /// The MOOSDB port (default: the mission's ServerPort; 0 picks a free one).
        port: Option<u16>,
    },
}

/// What a run does besides running the mission's apps.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// Lockstep or real time.
    pub mode: Mode,
    /// Values to post (`VAR=VALUE`, `VAR:=VALUE`, `VAR=VALUE@T`), after the first helm's
    /// first iteration unless timed.
    pub pokes: Vec<String>,
    /// Press the mission's DEPLOY button, or post DEPLOY=true and
    /// MOOS_MANUAL_OVERRIDE=false when it has none.
    pub deploy: bool,
    /// pMarineViewer buttons to press (by label or key), in order.
    pub buttons: Vec<String>,
    /// End the run when this condition (.bhv syntax) holds.
    pub until: Option<String>,
    /// End the run after this many simulated seconds.
    pub max_time: f64,
    /// The folder pLogger's session folder goes in (default: the mission's GlobalLogPath,
    /// else the pLogger block's PATH, else the current directory, as pLogger).
    pub log_dir: Option<PathBuf>,
    /// Seed of every random draw.
    pub seed: u64,
}

impl Default for RunOptions {
    fn default() -> Self {
        RunOptions {
            mode: Mode::Lockstep,
            pokes: Vec::new(),
            deploy: false,
            buttons: Vec::new(),
            until: None,
            max_time: 3600.0,
            log_dir: None,
            seed: 1,
        }
    }
}

/// What the caller is told during a run (all methods do nothing by default).
pub trait Observer {
    /// A finding that does not stop the run (the caller prints it).
    fn warning(&mut self, _text: &str) {}

    /// Something the run did (the MOOSDB listening, an external app started).
    fn notice(&mut self, _text: &str) {}

    /// One `IVPHELM_SUMMARY` posting.
    fn helm_summary(&mut self, _summary: &str) {}

    /// One `IVPHELM_SUMMARY` posting of community `member` of a fleet run (a fleet's
    /// [`Observer::step`] reads each community's values as `NAME:VAR`).
    fn member_helm_summary(&mut self, _member: &str, _summary: &str) {}

    /// The run is at `sim_s` simulated seconds; `current` reads the DB's current values.
    fn step(&mut self, _sim_s: f64, _current: &dyn Fn(&str) -> Option<Value>) {}

    /// True to end the run now (Ctrl-C): the log is flushed and closed.
    fn stop_requested(&self) -> bool {
        false
    }

    /// Variables whose every posting the observer wants ([`Observer::posting`]), asked
    /// once as a lockstep run starts (a viewer: NODE_REPORT, VIEW_*, APPCAST). Watching
    /// reads the bus and never changes what the apps see or log.
    fn watched(&self) -> Vec<String> {
        Vec::new()
    }

    /// One posting of a watched variable, at the MOOS time `time` of the step it was made
    /// in (lockstep; in real time an observer joins the DB as a client, see
    /// [`Observer::db_listening`]).
    fn posting(&mut self, _key: &str, _value: &Value, _time: f64) {}

    /// Postings the observer makes (a viewer's button presses), taken at each lockstep
    /// step and posted at that step's time as `--poke`s are.
    fn take_posts(&mut self) -> Vec<(String, Value)> {
        Vec::new()
    }

    /// Simulated seconds between two lockstep steps (each step calls [`Observer::step`];
    /// smaller steps give a viewer more frames). The apps' instants, and so the log, do
    /// not depend on it.
    fn step_seconds(&self) -> f64 {
        1.0
    }

    /// The real-time run's MOOSDB listens at `addr`, with time warp `warp`.
    fn db_listening(&mut self, _addr: std::net::SocketAddr, _warp: f64) {}
}

/// An observer that ignores everything (tests, batch runs).
#[derive(Debug, Default, Clone, Copy)]
pub struct Quiet;

impl Observer for Quiet {}
