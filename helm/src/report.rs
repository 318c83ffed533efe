//! `IVPHELM_SUMMARY` and the behaviour lists (reference §4.7, MOOS `HelmReport`).

use behaviors::fmt::{compact, fixed};
use ivp::Domain;

/// One behaviour line of the report.
#[derive(Debug, Clone, PartialEq)]
pub struct BhvLine {
    /// Behaviour name.
    pub name: String,
    /// Helm time the behaviour entered its state.
    pub time: f64,
    /// `good/total` updates, or `n/a`.
    pub updates: String,
    /// Priority weight (active only).
    pub pwt: f64,
    /// Pieces of its function (active only).
    pub pcs: usize,
}

/// The helm report of one iteration.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct HelmReport {
    /// Helm iteration.
    pub iteration: u64,
    /// Helm time.
    pub time: f64,
    /// Number of objective functions.
    pub ofnum: usize,
    /// Pieces of the objective functions built this iteration.
    pub pcs_formed: usize,
    /// Pieces reused from a cache (coug builds every function afresh: 0).
    pub pcs_cached: usize,
    /// Warnings so far.
    pub warnings: u64,
    /// Decisions (var, value) in domain order; a missing var is `varbalk`.
    pub decisions: Vec<(String, f64)>,
    /// The domain.
    pub domain: Option<Domain>,
    /// Halted by a behaviour error.
    pub halted: bool,
    /// Halt message.
    pub halt_msg: String,
    /// `modes=` summary.
    pub modes: String,
    /// Active behaviours.
    pub active: Vec<BhvLine>,
    /// Running behaviours (no function).
    pub running: Vec<BhvLine>,
    /// Idle behaviours.
    pub idle: Vec<BhvLine>,
    /// Completed behaviours.
    pub completed: Vec<BhvLine>,
}

fn names(v: &[BhvLine]) -> String {
    let mut s = String::new();
    for (i, b) in v.iter().enumerate() {
        if i > 0 {
            s.push(',');
        }
        s.push_str(&b.name);
    }
    s
}

fn full(v: &[BhvLine], active: bool) -> String {
    let mut s = String::new();
    for (i, b) in v.iter().enumerate() {
        if i > 0 {
            s.push(':');
        }
        s.push_str(&b.name);
        s.push('$');
        fixed(&mut s, b.time, 2);
        if active {
            s.push('$');
            fixed(&mut s, b.pwt, 5);
            s.push('$');
            s.push_str(&b.pcs.to_string());
            s.push_str("$0.00000");
        }
        s.push('$');
        s.push_str(&b.updates);
        if active {
            s.push_str("$1");
        }
    }
    s
}

impl HelmReport {
    /// Comma-separated active behaviour names (`IVPHELM_BHV_ACTIVE`).
    pub fn active_names(&self) -> String {
        names(&self.active)
    }
    /// Comma-separated running behaviour names (`IVPHELM_BHV_RUNNING`).
    pub fn running_names(&self) -> String {
        names(&self.running)
    }
    /// Comma-separated idle behaviour names (`IVPHELM_BHV_IDLE`).
    pub fn idle_names(&self) -> String {
        names(&self.idle)
    }

    fn decision_summary(&self) -> String {
        let mut s = String::new();
        if let Some(d) = &self.domain {
            for (i, v) in d.vars().iter().enumerate() {
                if i > 0 {
                    s.push(',');
                }
                s.push_str("var=");
                s.push_str(v.name());
                s.push(':');
                match self.decisions.iter().find(|(n, _)| n == v.name()) {
                    Some((_, x)) => compact(&mut s, *x, 5),
                    None => s.push_str("varbalk"),
                }
            }
        }
        s
    }

    /// The `IVPHELM_SUMMARY` string: `iter` and `utc_time` always, other fields only when they
    /// differ from `prev` (pass the default report for a full report). CPU times are not
    /// measured by coug (the engine reads no clock), so they stay 0 and are never listed.
    ///
    /// ```
    /// use helm::report::HelmReport;
    /// let r = HelmReport { iteration: 3, time: 12.5, ofnum: 1, ..Default::default() };
    /// assert_eq!(r.summary(&HelmReport::default()), "iter=3,utc_time=12.50,ofnum=1");
    /// assert_eq!(r.summary(&r), "iter=3,utc_time=12.50");
    /// ```
    pub fn summary(&self, prev: &HelmReport) -> String {
        let mut s = format!("iter={},utc_time=", self.iteration);
        fixed(&mut s, self.time, 2);
        if self.ofnum != prev.ofnum {
            s.push_str(&format!(",ofnum={}", self.ofnum));
        }
        if self.pcs_formed != prev.pcs_formed {
            s.push_str(&format!(",total_pcs_formed={}", self.pcs_formed));
        }
        if self.pcs_cached != prev.pcs_cached {
            s.push_str(&format!(",total_pcs_cached={}", self.pcs_cached));
        }
        if self.warnings != prev.warnings {
            s.push_str(&format!(",warnings={}", self.warnings));
        }
        let dec = self.decision_summary();
        if dec != prev.decision_summary() {
            s.push(',');
            s.push_str(&dec);
        }
        if self.halted != prev.halted {
            s.push_str(&format!(",halted={}", self.halted));
        }
        if self.modes != prev.modes {
            s.push_str(",modes=");
            s.push_str(if self.modes.is_empty() {
                "none"
            } else {
                &self.modes
            });
        }
        for (key, mine, theirs) in [
            (
                "running_bhvs",
                full(&self.running, false),
                full(&prev.running, false),
            ),
            (
                "active_bhvs",
                full(&self.active, true),
                full(&prev.active, true),
            ),
            (
                "idle_bhvs",
                full(&self.idle, false),
                full(&prev.idle, false),
            ),
            (
                "completed_bhvs",
                full(&self.completed, false),
                full(&prev.completed, false),
            ),
        ] {
            if mine != theirs {
                s.push(',');
                s.push_str(key);
                s.push('=');
                s.push_str(if mine.is_empty() { "none" } else { &mine });
            }
        }
        let dom = self
            .domain
            .as_ref()
            .map(|d| d.to_string())
            .unwrap_or_default();
        let pdom = prev
            .domain
            .as_ref()
            .map(|d| d.to_string())
            .unwrap_or_default();
        if dom != pdom {
            s.push_str(&format!(",ivpdomain=\"{dom}\""));
        }
        if self.halt_msg != prev.halt_msg {
            s.push_str(",halt_msg=");
            s.push_str(if self.halt_msg.is_empty() {
                "none"
            } else {
                &self.halt_msg
            });
        }
        s
    }
}
