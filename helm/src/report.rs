//! `IVPHELM_SUMMARY` and the behaviour lists (reference §4.7, MOOS `HelmReport`).

use behaviors::fmt::{compact, fixed, uint};
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
    /// Some active behaviour is a goal (not a constraint) behaviour (`active_goal=`).
    pub active_goal: bool,
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
    /// Behaviours disabled by a `BHV_ABLE_FILTER`.
    pub disabled: Vec<BhvLine>,
    /// Completed behaviours.
    pub completed: Vec<BhvLine>,
    /// The templates (`templating = spawn`), each `KIND::prefix (Spawned:made/tried)`.
    pub spawnable: Vec<String>,
}

fn names(v: &[BhvLine]) -> String {
    let mut s = String::new();
    write_names(v, &mut s);
    s
}

fn write_names(v: &[BhvLine], s: &mut String) {
    for (i, b) in v.iter().enumerate() {
        if i > 0 {
            s.push(',');
        }
        s.push_str(&b.name);
    }
}

/// Whether two behaviour lists would render the same text (times and weights compared by
/// their bits, so `-0` and `0` differ as their text does).
fn same_lines(a: &[BhvLine], b: &[BhvLine]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| {
            x.name == y.name
                && x.updates == y.updates
                && x.pcs == y.pcs
                && x.time.to_bits() == y.time.to_bits()
                && x.pwt.to_bits() == y.pwt.to_bits()
        })
}

fn full(v: &[BhvLine], active: bool, s: &mut String) {
    s.clear();
    for (i, b) in v.iter().enumerate() {
        if i > 0 {
            s.push(':');
        }
        s.push_str(&b.name);
        s.push('$');
        fixed(s, b.time, 2);
        if active {
            s.push('$');
            fixed(s, b.pwt, 5);
            s.push('$');
            uint(s, b.pcs as u64);
            s.push_str("$0.00000");
        }
        s.push('$');
        s.push_str(&b.updates);
        if active {
            s.push_str("$1");
        }
    }
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
    /// Writes the comma-separated names of list `k` (0 active, 1 running, 2 idle, 3
    /// disabled) into `out`.
    pub fn write_names(&self, k: usize, out: &mut String) {
        out.clear();
        let v = match k {
            0 => &self.active,
            1 => &self.running,
            3 => &self.disabled,
            _ => &self.idle,
        };
        write_names(v, out);
    }

    /// The behaviour lists in [`Rendered::lists`]' order.
    fn lists(&self) -> [&Vec<BhvLine>; 5] {
        [
            &self.running,
            &self.active,
            &self.idle,
            &self.disabled,
            &self.completed,
        ]
    }

    fn decision_summary(&self, domain: Option<&Domain>, s: &mut String) {
        s.clear();
        if let Some(d) = self.domain.as_ref().or(domain) {
            for (i, v) in d.vars().iter().enumerate() {
                if i > 0 {
                    s.push(',');
                }
                s.push_str("var=");
                s.push_str(v.name());
                s.push(':');
                match self.decisions.iter().find(|(n, _)| n == v.name()) {
                    Some((_, x)) => compact(s, *x, 5),
                    None => s.push_str("varbalk"),
                }
            }
        }
    }

    /// The report's fields as strings, for comparing with the next report (the helm keeps the
    /// previous one rendered). `domain` is the rendered domain (`IVPHELM_DOMAIN` format).
    pub fn render(&self, domain: &str) -> Rendered {
        let mut r = Rendered::default();
        self.render_into(domain, None, &mut r);
        r
    }

    /// [`HelmReport::render`] into an existing [`Rendered`], reusing its strings. `dom` is the
    /// decision domain when the report carries none (`domain: None` spares the helm a copy of
    /// its domain every iteration).
    pub fn render_into(&self, domain: &str, dom: Option<&Domain>, r: &mut Rendered) {
        self.render_after(domain, dom, None, r);
    }

    /// [`HelmReport::render_into`], copying from `last` (an earlier report and its rendering)
    /// each behaviour list whose lines are the same, to the bit, instead of formatting it
    /// again (the helm's lists rarely change from one iteration to the next).
    pub fn render_after(
        &self,
        domain: &str,
        dom: Option<&Domain>,
        last: Option<(&HelmReport, &Rendered)>,
        r: &mut Rendered,
    ) {
        r.ofnum = self.ofnum;
        r.pcs_formed = self.pcs_formed;
        r.pcs_cached = self.pcs_cached;
        r.warnings = self.warnings;
        self.decision_summary(dom, &mut r.decisions);
        r.halted = self.halted;
        r.active_goal = self.active_goal;
        r.modes.clone_from(&self.modes);
        let mine = self.lists();
        let before = last.map(|(l, lr)| (l.lists(), lr.lists()));
        for (k, out) in r.lists_mut().into_iter().enumerate() {
            match before {
                Some((lines, text)) if same_lines(mine[k], lines[k]) => out.clone_from(text[k]),
                _ => full(mine[k], k == 1, out),
            }
        }
        r.domain.clear();
        r.domain.push_str(domain);
        r.halt_msg.clone_from(&self.halt_msg);
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
    /// let goal = HelmReport { active_goal: true, ..r.clone() };
    /// assert_eq!(goal.summary(&r), "iter=3,utc_time=12.50,active_goal=true");
    /// ```
    pub fn summary(&self, prev: &HelmReport) -> String {
        let dom = |r: &HelmReport| r.domain.as_ref().map(|d| d.to_string()).unwrap_or_default();
        let mut s = String::new();
        self.render(&dom(self)).summary(
            self.iteration,
            self.time,
            &prev.render(&dom(prev)),
            &mut s,
        );
        s
    }
}

/// A [`HelmReport`] rendered to strings (see [`HelmReport::render`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Rendered {
    ofnum: usize,
    pcs_formed: usize,
    pcs_cached: usize,
    warnings: u64,
    decisions: String,
    halted: bool,
    active_goal: bool,
    modes: String,
    running: String,
    active: String,
    idle: String,
    disabled: String,
    completed: String,
    domain: String,
    halt_msg: String,
}

impl Rendered {
    /// The rendered behaviour lists: running, active, idle, disabled, completed.
    fn lists(&self) -> [&String; 5] {
        [
            &self.running,
            &self.active,
            &self.idle,
            &self.disabled,
            &self.completed,
        ]
    }
    fn lists_mut(&mut self) -> [&mut String; 5] {
        [
            &mut self.running,
            &mut self.active,
            &mut self.idle,
            &mut self.disabled,
            &mut self.completed,
        ]
    }
}

fn none_if_empty(s: &str) -> &str {
    if s.is_empty() { "none" } else { s }
}

impl Rendered {
    /// Writes the `IVPHELM_SUMMARY` of iteration `iter` at `time` into `s`: `iter` and
    /// `utc_time`, then each field that differs from `prev` (reference §4.7).
    pub fn summary(&self, iter: u64, time: f64, prev: &Rendered, s: &mut String) {
        use std::fmt::Write as _;
        // The fields of every iteration are written without `core::fmt`.
        s.push_str("iter=");
        uint(s, iter);
        s.push_str(",utc_time=");
        fixed(s, time, 2);
        for (key, mine, theirs) in [
            (",ofnum=", self.ofnum as u64, prev.ofnum as u64),
            (
                ",total_pcs_formed=",
                self.pcs_formed as u64,
                prev.pcs_formed as u64,
            ),
            (
                ",total_pcs_cached=",
                self.pcs_cached as u64,
                prev.pcs_cached as u64,
            ),
            (",warnings=", self.warnings, prev.warnings),
        ] {
            if mine != theirs {
                s.push_str(key);
                uint(s, mine);
            }
        }
        if self.decisions != prev.decisions {
            s.push(',');
            s.push_str(&self.decisions);
        }
        if self.halted != prev.halted {
            write!(s, ",halted={}", self.halted).ok();
        }
        if self.active_goal != prev.active_goal {
            write!(s, ",active_goal={}", self.active_goal).ok();
        }
        if self.modes != prev.modes {
            write!(s, ",modes={}", none_if_empty(&self.modes)).ok();
        }
        for (key, mine, theirs) in [
            ("running_bhvs", &self.running, &prev.running),
            ("active_bhvs", &self.active, &prev.active),
            ("disabled_bhvs", &self.disabled, &prev.disabled),
            ("idle_bhvs", &self.idle, &prev.idle),
            ("completed_bhvs", &self.completed, &prev.completed),
        ] {
            if mine != theirs {
                write!(s, ",{key}={}", none_if_empty(mine)).ok();
            }
        }
        if self.domain != prev.domain {
            write!(s, ",ivpdomain=\"{}\"", self.domain).ok();
        }
        if self.halt_msg != prev.halt_msg {
            write!(s, ",halt_msg={}", none_if_empty(&self.halt_msg)).ok();
        }
    }
}

/// MOOS `HelmReport::timeInState`: seconds in the state (2 decimals), `always` for a
/// behaviour that entered it at time 0 or before.
fn time_in_state(now: f64, entered: f64, out: &mut String) {
    if entered > 0.0 {
        fixed(out, now - entered, 2);
    } else {
        out.push_str("always");
    }
}

impl HelmReport {
    /// The lines of pHelmIvP's appcast summary (`HelmReport::formattedSummary`, terse), at
    /// app time `now`, each ended by a newline. Solve, create and loop times are 0: the
    /// engine reads no clock.
    pub fn formatted_summary(&self, now: f64, domain: &Domain, out: &mut String) {
        let line = |out: &mut String, label: &str, v: u64| {
            out.push_str(label);
            uint(out, v);
            out.push('\n');
        };
        line(out, "  Helm Iteration:  ", self.iteration);
        line(out, "  IvP Functions:   ", self.ofnum as u64);
        line(out, "  Pieces (Formed): ", self.pcs_formed as u64);
        line(out, "  Pieces (Cached): ", self.pcs_cached as u64);
        out.push_str("  Mode(s):         ");
        out.push_str(&self.modes);
        out.push('\n');
        for label in ["  SolveTime:   ", "  CreateTime:  ", "  LoopTime:    "] {
            out.push_str(label);
            out.push_str("0.00   (max=0.00)\n");
        }
        out.push_str("  Halted:         ");
        out.push_str(if self.halted { "true" } else { "false" });
        out.push_str("   (");
        uint(out, self.warnings);
        out.push_str(" warnings)\n");
        out.push_str("  Active Goal:    ");
        out.push_str(if self.active_goal { "true" } else { "false" });
        out.push('\n');
        out.push_str("Helm Decision: [");
        out.push_str(&domain.to_string().replace(':', "] ["));
        out.push_str("]\n");
        {
            for v in domain.vars() {
                out.push_str("  ");
                out.push_str(v.name());
                match self.decisions.iter().find(|(n, _)| n == v.name()) {
                    Some((_, x)) => {
                        out.push_str(" = ");
                        compact(out, *x, 5);
                    }
                    None => out.push_str(" = no-decision"),
                }
                out.push('\n');
            }
        }
        out.push_str("Behaviors Spawnable: --------- (");
        uint(out, self.spawnable.len() as u64);
        out.push_str(")\n");
        for t in &self.spawnable {
            out.push_str("  ");
            out.push_str(t);
            out.push('\n');
        }
        out.push_str("Behaviors Active: ---------- (");
        uint(out, self.active.len() as u64);
        out.push_str(")\n");
        for b in &self.active {
            out.push_str("  ");
            out.push_str(&b.name);
            out.push_str(" [");
            time_in_state(now, b.time, out);
            out.push_str("] (pwt=");
            compact(out, b.pwt, 5);
            out.push_str(") (pcs=");
            uint(out, b.pcs as u64);
            out.push_str(") (cpu=0) (upd=");
            out.push_str(&b.updates);
            out.push_str(")\n");
        }
        out.push_str("Behaviors Running: --------- (");
        uint(out, self.running.len() as u64);
        out.push_str(")\n");
        for b in &self.running {
            out.push_str("  ");
            out.push_str(&b.name);
            out.push_str(" [");
            time_in_state(now, b.time, out);
            out.push_str("]\n");
        }
        out.push_str("Behaviors Disabled: --------- (");
        uint(out, self.disabled.len() as u64);
        out.push_str(")\n");
        for b in &self.disabled {
            out.push_str("  ");
            out.push_str(&b.name);
            out.push_str(" [");
            time_in_state(now, b.time, out);
            out.push_str("]\n");
        }
        out.push_str("Behaviors Idle: ------------ (");
        uint(out, self.idle.len() as u64);
        out.push_str(")\n  ");
        for (i, b) in self.idle.iter().enumerate() {
            if i > 0 {
                out.push_str(", ");
            }
            out.push_str(&b.name);
            out.push('[');
            time_in_state(now, b.time, out);
            out.push(']');
        }
        out.push('\n');
        out.push_str("Behaviors Completed: ------- (");
        uint(out, self.completed.len() as u64);
        out.push_str(")\n");
        // Latest first (by time, then name, both descending), repeats counted.
        let mut done: Vec<(f64, &str, usize)> = Vec::new();
        for b in &self.completed {
            match done.iter_mut().find(|(_, n, _)| *n == b.name) {
                Some(e) => {
                    e.0 = e.0.max(b.time);
                    e.2 += 1;
                }
                None => done.push((b.time.max(0.0), &b.name, 1)),
            }
        }
        done.sort_by(|a, b| b.0.total_cmp(&a.0).then_with(|| b.1.cmp(a.1)));
        for (i, (t, name, n)) in done.iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            out.push_str(name);
            if *n > 1 {
                out.push('(');
                uint(out, *n as u64);
                out.push(')');
            }
            out.push('[');
            time_in_state(self.time, *t, out);
            out.push(']');
        }
        out.push('\n');
    }
}

#[cfg(test)]
mod summary_tests {
    use super::*;

    fn line(name: &str, time: f64) -> BhvLine {
        BhvLine {
            name: name.into(),
            time,
            updates: "n/a".into(),
            pwt: 100.0,
            pcs: 4,
        }
    }

    #[test]
    fn the_appcast_summary_has_pphelmivps_lines() {
        let r = HelmReport {
            iteration: 12,
            time: 30.0,
            ofnum: 1,
            pcs_formed: 4,
            warnings: 2,
            decisions: vec![("speed".into(), 1.5)],
            active_goal: true,
            modes: "MODE@ACTIVE".into(),
            active: vec![line("wpt", 20.5)],
            idle: vec![line("ret", 0.0), line("sk", 10.0)],
            completed: vec![line("a", 25.0), line("b", 28.0), line("a", 26.0)],
            ..HelmReport::default()
        };
        let mut s = String::new();
        let d = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
        r.formatted_summary(31.0, &d, &mut s);
        let expected = "  Helm Iteration:  12
  IvP Functions:   1
  Pieces (Formed): 4
  Pieces (Cached): 0
  Mode(s):         MODE@ACTIVE
  SolveTime:   0.00   (max=0.00)
  CreateTime:  0.00   (max=0.00)
  LoopTime:    0.00   (max=0.00)
  Halted:         false   (2 warnings)
  Active Goal:    true
Helm Decision: [course,0,359,360] [speed,0,4,41]
  course = no-decision
  speed = 1.5
Behaviors Spawnable: --------- (0)
Behaviors Active: ---------- (1)
  wpt [10.50] (pwt=100) (pcs=4) (cpu=0) (upd=n/a)
Behaviors Running: --------- (0)
Behaviors Disabled: --------- (0)
Behaviors Idle: ------------ (2)
  ret[always], sk[21.00]
Behaviors Completed: ------- (3)
b[2.00],a(2)[4.00]
";
        assert_eq!(s, expected);
    }
}
