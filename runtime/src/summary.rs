//! What a run did, for `coug run`'s progress line and closing summary: behaviour lists
//! from `IVPHELM_SUMMARY`, and totals (distance, depth, helm state) from an alog.

use alog::{Alog, Value};

/// The behaviour names of one list field of an `IVPHELM_SUMMARY` (`active_bhvs`,
/// `running_bhvs`, `idle_bhvs`, `completed_bhvs`, `disabled_bhvs`): `None` when the report
/// does not carry the field (the helm sends only changed fields after the first report).
/// Entries are `:`-separated, each `name$details...`; `none` means an empty list.
///
/// ```
/// let s = "iter=9,utc_time=1.5,active_bhvs=waypt_survey$12.3$100$9$0.01$1/1$1$$:bhv_b$1$50,idle_bhvs=none";
/// let f = runtime::summary::behaviour_list(s, "active_bhvs").unwrap();
/// assert_eq!(f, vec!["waypt_survey", "bhv_b"]);
/// assert_eq!(runtime::summary::behaviour_list(s, "idle_bhvs"), Some(vec![]));
/// assert_eq!(runtime::summary::behaviour_list(s, "completed_bhvs"), None);
/// ```
pub fn behaviour_list(summary: &str, field: &str) -> Option<Vec<String>> {
    let value = summary.split(',').find_map(|kv| {
        let (k, v) = kv.split_once('=')?;
        (k.trim() == field).then_some(v.trim())
    })?;
    if value.is_empty() || value.eq_ignore_ascii_case("none") {
        return Some(Vec::new());
    }
    Some(
        value
            .split(':')
            .map(|e| e.split('$').next().unwrap_or("").trim())
            .filter(|n| !n.is_empty())
            .map(String::from)
            .collect(),
    )
}

/// Totals of a run read back from its alog.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RunSummary {
    /// Seconds from LOGSTART to the last record.
    pub duration: f64,
    /// Horizontal distance travelled (sum of the NAV_X/NAV_Y steps), metres.
    pub distance: f64,
    /// Deepest NAV_DEPTH, metres.
    pub max_depth: f64,
    /// Last NAV_X/NAV_Y.
    pub final_position: Option<(f64, f64)>,
    /// Last NAV_DEPTH.
    pub final_depth: Option<f64>,
    /// Last IVPHELM_STATE.
    pub helm_state: Option<String>,
    /// Behaviours named in the last `completed_bhvs` field of IVPHELM_SUMMARY.
    pub completed: Vec<String>,
    /// Behaviours named in the last `active_bhvs` field of IVPHELM_SUMMARY.
    pub active: Vec<String>,
}

impl RunSummary {
    /// Reads the totals from a parsed alog.
    pub fn from_alog(log: &Alog) -> RunSummary {
        let mut b = SummaryBuilder::default();
        for e in &log.entries {
            b.entry(e.time, &e.var, &e.value);
        }
        b.finish()
    }
}

/// Builds a [`RunSummary`] record by record, in the log's order (what
/// [`RunSummary::from_alog`] does over a parsed log, and what a run's log tally does while
/// the log is written).
#[derive(Debug, Clone, Default)]
pub struct SummaryBuilder {
    s: RunSummary,
    x: Option<f64>,
    y: Option<f64>,
    last: Option<(f64, f64)>,
}

impl SummaryBuilder {
    /// True when a record of `var` changes the totals beyond the duration (only these need
    /// their value: see [`SummaryBuilder::time`]).
    pub fn wants(var: &str) -> bool {
        matches!(
            var,
            "NAV_X" | "NAV_Y" | "NAV_DEPTH" | "IVPHELM_STATE" | "IVPHELM_SUMMARY"
        )
    }

    /// Counts a record of a variable [`SummaryBuilder::wants`] does not want: its time only.
    pub fn time(&mut self, time: f64) {
        self.s.duration = self.s.duration.max(time);
    }

    /// Counts one record (time relative to LOGSTART, as written).
    pub fn entry(&mut self, time: f64, var: &str, value: &Value) {
        let s = &mut self.s;
        s.duration = s.duration.max(time);
        match (var, value) {
            ("NAV_X", Value::Double(v)) => self.x = Some(*v),
            ("NAV_Y", Value::Double(v)) => self.y = Some(*v),
            ("NAV_DEPTH", Value::Double(v)) => {
                s.max_depth = s.max_depth.max(*v);
                s.final_depth = Some(*v);
                return;
            }
            ("IVPHELM_STATE", Value::String(v)) => {
                s.helm_state = Some(v.to_string());
                return;
            }
            ("IVPHELM_SUMMARY", Value::String(v)) => {
                if let Some(c) = behaviour_list(v, "completed_bhvs") {
                    s.completed = c;
                }
                if let Some(a) = behaviour_list(v, "active_bhvs") {
                    s.active = a;
                }
                return;
            }
            _ => return,
        }
        if let (Some(x), Some(y)) = (self.x, self.y) {
            if let Some((lx, ly)) = self.last {
                s.distance += (x - lx).hypot(y - ly);
            }
            self.last = Some((x, y));
        }
    }

    /// The totals of the records counted.
    pub fn finish(mut self) -> RunSummary {
        self.s.final_position = self.last;
        self.s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn totals_from_a_log() {
        let text = "%% LOGSTART 0\n\
            0.0 NAV_X s 0\n0.0 NAV_Y s 0\n1.0 NAV_X s 3\n1.0 NAV_Y s 4\n\
            1.0 NAV_DEPTH s 2\n2.0 NAV_DEPTH s 1.5\n\
            2.0 IVPHELM_STATE h DRIVE\n\
            2.5 IVPHELM_SUMMARY h iter=1,active_bhvs=a$1$2:b$3,completed_bhvs=none\n\
            3.0 IVPHELM_SUMMARY h iter=2,completed_bhvs=a$9\n\
            4.0 NAV_X s 3\n4.0 NAV_Y s 0\n";
        let s = RunSummary::from_alog(&alog::parse(text).unwrap());
        // (0,0) → (3,0) → (3,4) → (3,4) → (3,0): 3 + 4 + 0 + 4.
        assert_eq!(s.distance, 11.0);
        assert_eq!(s.max_depth, 2.0);
        assert_eq!(s.final_depth, Some(1.5));
        assert_eq!(s.final_position, Some((3.0, 0.0)));
        assert_eq!(s.helm_state.as_deref(), Some("DRIVE"));
        assert_eq!(s.active, vec!["a", "b"]);
        assert_eq!(s.completed, vec!["a"]);
        assert_eq!(s.duration, 4.0);
    }

    #[test]
    fn behaviour_lists() {
        assert_eq!(behaviour_list("active_bhvs=", "active_bhvs"), Some(vec![]));
        assert_eq!(
            behaviour_list("x=1, completed_bhvs = ret$5:srv", "completed_bhvs"),
            Some(vec!["ret".to_string(), "srv".to_string()])
        );
    }
}
