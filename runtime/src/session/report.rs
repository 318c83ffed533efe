//! What a run did: how it ended and the totals of its log.

use std::fmt;
use std::path::PathBuf;

use crate::app::Value;
use crate::scheduler::Outcome;
use crate::summary::{RunSummary, SummaryBuilder, behaviour_list};

/// How a run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Ended {
    /// The scheduler's outcome (condition met, max time, every app finished).
    Outcome(Outcome),
    /// The caller asked it to stop ([`super::Observer::stop_requested`]) at MOOS time `time`.
    Interrupted {
        /// MOOS time of the stop.
        time: f64,
    },
}

/// Totals of a run's alog (as read back from the file; a run counts them while writing it).
#[derive(Debug, Clone, PartialEq)]
pub struct LogTotals {
    /// Distance, position and the helm's last state (see [`RunSummary`]).
    pub summary: RunSummary,
    /// Every behaviour that completed during the run, in order of completion.
    pub completed: Vec<String>,
    /// Each `IVPHELM_CONFIG_WARNING` posted (why a helm was in MALCONFIG).
    pub malconfig: Vec<String>,
}

impl LogTotals {
    /// The totals of a parsed alog.
    pub fn from_alog(log: &alog::Alog) -> LogTotals {
        let mut b = TotalsBuilder::default();
        for e in &log.entries {
            b.entry(e.time, &e.var, &e.value);
        }
        b.finish()
    }
}

/// Builds [`LogTotals`] record by record, in the log's order: over a parsed log
/// ([`LogTotals::from_alog`]) or while the log is written (`super::tally`).
#[derive(Debug, Clone, Default)]
pub(crate) struct TotalsBuilder {
    summary: SummaryBuilder,
    /// Every behaviour that completed during the run (the helm's later reports may drop
    /// it, e.g. once the mission is no longer active).
    completed: Vec<String>,
    malconfig: Vec<String>,
}

impl TotalsBuilder {
    /// True when a record of `var` counts beyond its time.
    pub(crate) fn wants(var: &str) -> bool {
        SummaryBuilder::wants(var) || var == "IVPHELM_CONFIG_WARNING"
    }

    /// Counts a record of a variable [`TotalsBuilder::wants`] does not want.
    pub(crate) fn time(&mut self, time: f64) {
        self.summary.time(time);
    }

    /// Counts one record.
    pub(crate) fn entry(&mut self, time: f64, var: &str, value: &Value) {
        self.summary.entry(time, var, value);
        match var {
            "IVPHELM_SUMMARY" => {
                let list = value
                    .as_str()
                    .and_then(|v| behaviour_list(v, "completed_bhvs"));
                for b in list.unwrap_or_default() {
                    if !self.completed.contains(&b) {
                        self.completed.push(b);
                    }
                }
            }
            "IVPHELM_CONFIG_WARNING" => {
                if let Some(why) = value.as_str() {
                    self.malconfig.push(why.to_string());
                }
            }
            _ => {}
        }
    }

    /// The totals of the records counted.
    pub(crate) fn finish(self) -> LogTotals {
        LogTotals {
            summary: self.summary.finish(),
            completed: self.completed,
            malconfig: self.malconfig,
        }
    }
}

/// What a run did: how it ended, its times, the `until` values and its log.
#[derive(Debug, Clone)]
pub struct RunReport {
    /// The mission file.
    pub mission: PathBuf,
    /// How it ended.
    pub ended: Ended,
    /// The `until` condition as given.
    pub until: Option<String>,
    /// The max time as given (simulated seconds).
    pub max_time: f64,
    /// MOOS time of the start.
    pub start: f64,
    /// Wall-clock seconds the run took.
    pub wall_s: f64,
    /// The `until` condition's variables and their last values.
    pub until_values: Vec<(String, Option<Value>)>,
    /// The alog written.
    pub alog: String,
    /// The alog's totals (`None` when the file would not read back as an alog).
    pub totals: Option<LogTotals>,
}

impl RunReport {
    /// MOOS time at the end.
    pub fn end_time(&self) -> f64 {
        match self.ended {
            Ended::Outcome(
                Outcome::ConditionMet { time }
                | Outcome::MaxTime { time }
                | Outcome::AllFinished { time },
            )
            | Ended::Interrupted { time } => time,
        }
    }

    /// Simulated seconds from start to end.
    pub fn sim_s(&self) -> f64 {
        self.end_time() - self.start
    }

    /// True when an `until` condition was given and did not hold by the end.
    pub fn until_pending(&self) -> bool {
        self.until.is_some() && !matches!(self.ended, Ended::Outcome(Outcome::ConditionMet { .. }))
    }

    /// `VAR = value` of each `until` variable, as the closing lines show them.
    pub fn until_text(&self) -> Vec<String> {
        self.until_values
            .iter()
            .map(|(k, v)| format!("{k} = {}", fmt_value(v)))
            .collect()
    }
}

pub(super) fn fmt_value(v: &Option<Value>) -> String {
    match v {
        None => "(never posted)".into(),
        Some(Value::Double(x)) => format!("{x}"),
        Some(Value::String(s)) => format!("\"{s}\""),
        Some(Value::Binary(b)) => format!("({} bytes)", b.len()),
    }
}

impl fmt::Display for RunReport {
    /// The closing summary `coug run` prints: how it ended, times, distance, depth,
    /// completed behaviours, helm state, the `until` values and the log.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "coug run: {}", self.mission.display())?;
        let how = match self.ended {
            Ended::Outcome(Outcome::ConditionMet { .. }) => format!(
                "until condition met ({})",
                self.until.as_deref().unwrap_or("")
            ),
            Ended::Outcome(Outcome::MaxTime { .. }) => {
                format!("max time {} s reached", self.max_time)
            }
            Ended::Outcome(Outcome::AllFinished { .. }) => "every app finished".into(),
            Ended::Interrupted { .. } => "interrupted".into(),
        };
        writeln!(f, "  ended:       {how}")?;
        let sim = self.sim_s();
        writeln!(
            f,
            "  simulated:   {sim:.1} s   wall: {:.3} s   speed-up: {:.0}x",
            self.wall_s,
            sim / self.wall_s.max(1e-9)
        )?;
        match &self.totals {
            Some(t) => {
                let s = &t.summary;
                writeln!(f, "  distance:    {:.1} m", s.distance)?;
                if s.max_depth > 0.0 {
                    writeln!(f, "  max depth:   {:.2} m", s.max_depth)?;
                }
                if let Some((x, y)) = s.final_position {
                    writeln!(f, "  final x,y:   {x:.1}, {y:.1}")?;
                }
                let done = if t.completed.is_empty() {
                    "none".to_string()
                } else {
                    t.completed.join(", ")
                };
                writeln!(f, "  completed:   {done}")?;
                if let Some(h) = &s.helm_state {
                    writeln!(f, "  helm state:  {h}")?;
                }
                for why in &t.malconfig {
                    writeln!(f, "  malconfig:   {why}")?;
                }
            }
            None => writeln!(f, "  (the log could not be read back for totals)")?,
        }
        for line in self.until_text() {
            writeln!(f, "  {line}")?;
        }
        writeln!(f, "  log:         {}", self.alog)
    }
}
