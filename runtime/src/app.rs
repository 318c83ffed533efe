//! The [`App`] trait: a MOOS app (CMOOSApp) as the scheduler drives it, and the values it
//! exchanges ([`Mail`] in, [`Post`] out).

use mission::moos::ProcessConfig;

/// CMOOSApp's default AppTick (`DEFAULT_MOOS_APP_FREQ`), Hz.
pub const DEFAULT_APP_TICK: f64 = 5.0;

/// The highest AppTick CMOOSApp allows (`MOOS_MAX_APP_FREQ`), Hz; `AppTick <= 0` (no sleep)
/// also runs at this rate in lockstep.
pub const MAX_APP_TICK: f64 = 100.0;

/// Seconds between `<APP>_STATUS` posts (`STATUS_PERIOD`).
pub const STATUS_PERIOD: f64 = 2.0;

pub use moos_types::{Mail, Post, Value};

/// Why an app failed: the run ends with it (a failing disk is a failed run).
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    /// A file the app writes could not be written (a log on a full or read-only disk).
    #[error("{app}: {what} could not be written: {source}")]
    Io {
        /// The app's MOOS name.
        app: String,
        /// What was being written (`the log logs/X/X.alog`).
        what: String,
        /// The error.
        #[source]
        source: std::io::Error,
    },
}

/// What an app's hooks return.
pub type AppResult = Result<(), AppError>;

/// A registration: an exact variable name, or a MOOS wildcard pattern (`*`, `?`) on
/// variable names, with the DB's minimum interval between deliveries (0 = every write).
#[derive(Debug, Clone, PartialEq)]
pub struct Subscription {
    /// Name or pattern.
    pub pattern: String,
    /// Minimum seconds between deliveries (MOOS `Register(var, interval)`).
    pub interval: f64,
}

impl Subscription {
    /// Every write of `name`.
    pub fn var(name: impl Into<String>) -> Subscription {
        Subscription {
            pattern: name.into(),
            interval: 0.0,
        }
    }

    /// `name` at most every `interval` seconds.
    pub fn every(name: impl Into<String>, interval: f64) -> Subscription {
        Subscription {
            pattern: name.into(),
            interval,
        }
    }

    /// True when the pattern holds `*` or `?` (a wildcard registration).
    pub fn is_wildcard(&self) -> bool {
        self.pattern.contains(['*', '?'])
    }
}

/// A MOOS app as the scheduler drives it (CMOOSApp's life cycle):
/// registrations, then [`App::on_startup`], then at every AppTick period:
/// fetch mail sorted by time → [`App::on_mail`] → [`App::iterate`].
///
/// Apps never read a clock: `now` (MOOS time, seconds) is always an argument. An app is
/// `Send`: a lockstep fleet run steps its communities on several threads.
pub trait App: Send {
    /// The MOOS name (the ANTLER alias when one was given, e.g. `pHelmIvP_2`).
    fn name(&self) -> &str;

    /// The `ProcessConfig` block the app was configured from, if any.
    fn process_config(&self) -> Option<&ProcessConfig> {
        None
    }

    /// Iterations per second. Default: the block's `AppTick` (see [`app_tick_of`]).
    fn app_tick(&self) -> f64 {
        app_tick_of(self.process_config())
    }

    /// The registrations made when the app connects.
    fn subscriptions(&self) -> Vec<Subscription> {
        Vec::new()
    }

    /// The variables whose mail the app drops unread although its registrations match them
    /// (pLogger's omitted variables): the in-process bus does not deliver them, and the DB
    /// skips its summaries nobody reads ([`moosdb::db::Database::set_unread`]). Default:
    /// none.
    fn unread(&self) -> moosdb::db::Unread {
        moosdb::db::Unread::default()
    }

    /// Registrations the app wants to add now (polled after every callback).
    fn new_subscriptions(&mut self) -> Vec<Subscription> {
        Vec::new()
    }

    /// OnStartUp: called once, after connecting, before the first mail and iterate.
    fn on_startup(&mut self, _now: f64, _out: &mut Vec<Post>) -> AppResult {
        Ok(())
    }

    /// OnNewMail: everything delivered since the last call, sorted by time.
    fn on_mail(&mut self, _mail: &[Mail], _now: f64, _out: &mut Vec<Post>) -> AppResult {
        Ok(())
    }

    /// Iterate: one step of the app's work at time `now`. An error ends the run.
    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> AppResult;

    /// The run is over (at MOOS time `now`): flush, close and report. An error fails the
    /// run (a log that could not be completed).
    fn stop(&mut self, _now: f64) -> AppResult {
        Ok(())
    }

    /// True once the app wants to stop (e.g. uTimerScript's `quit`); it is then no longer
    /// scheduled.
    fn finished(&self) -> bool {
        false
    }

    /// Told the process's load (sampled with each `<APP>_STATUS`) when the app runs as its
    /// own MOOS process (pHelmIvP posts it as IVPHELM_CPU every iteration).
    fn set_process_load(&mut self, _load: crate::procinfo::Load) {}

    /// Told the process id when the app runs as its own MOOS process (single-app mode), for
    /// the apps that post it (pNodeReporter's PNODEREPORTER_PID, pHelmIvP's PHELMIVP_PID).
    fn set_process_id(&mut self, _pid: u32) {}

    /// Why the C++ app would end at start-up with this configuration (its `OnStartUp`
    /// returning false), if it would: the runner then leaves the app out and says why, and
    /// `coug check` reports it as an error.
    fn startup_failure(&self) -> Option<String> {
        None
    }

    /// Why the app refuses to act on its configuration while it stays connected (pHelmIvP's
    /// MALCONFIG: it posts `IVPHELM_STATE = MALCONFIG` and never drives); empty when it is
    /// configured.
    fn malconfig(&self) -> Vec<String> {
        Vec::new()
    }
}

/// The AppTick of a block as CMOOSApp reads it: `AppTick` (default 5), values above 100 or
/// at or below 0 (no sleep) become 100, an unreadable value the default.
///
/// ```
/// assert_eq!(runtime::app::app_tick_of(None), 5.0);
/// ```
pub fn app_tick_of(config: Option<&ProcessConfig>) -> f64 {
    let Some(v) = config.and_then(|c| c.get("AppTick")) else {
        return DEFAULT_APP_TICK;
    };
    match v.trim().parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => x.min(MAX_APP_TICK),
        Ok(x) if x.is_finite() => MAX_APP_TICK,
        _ => DEFAULT_APP_TICK,
    }
}

/// CMOOSApp's `<APP>_STATUS` text:
/// `AppErrorFlag=false,Uptime=..,cpuload=..,memory_kb=..,memory_max_kb=..,MOOSName=..,
/// Publishing="A,B,",Subscribing="C,"`, the load figures with 4 significant digits; 0 when
/// the process's load is not measured (`load` `None`: apps sharing `coug run`'s process).
///
/// ```
/// let s = runtime::app::status_text("pX", 2.5, None, &["A".to_string()].into(), &Default::default());
/// assert!(s.contains("cpuload=0,memory_kb=0,memory_max_kb=0,"));
/// assert!(s.ends_with("MOOSName=pX,Publishing=\"A,\",Subscribing=\"\""));
/// ```
pub fn status_text(
    name: &str,
    uptime: f64,
    load: Option<crate::procinfo::Load>,
    published: &std::collections::BTreeSet<String>,
    subscribed: &std::collections::BTreeSet<String>,
) -> String {
    // Sized once: the name lists are most of the text (its pieces are appended, not copied
    // again as the buffer grows).
    let names: usize = published
        .iter()
        .chain(subscribed)
        .map(|p| p.len() + 1)
        .sum();
    let mut s = String::with_capacity(160 + name.len() + names);
    s.push_str("AppErrorFlag=false,Uptime=");
    moos_types::fmt::g(&mut s, uptime, 6);
    let l = load.unwrap_or_default();
    s.push_str(",cpuload=");
    moos_types::fmt::g(&mut s, l.cpu_percent, 4);
    s.push_str(",memory_kb=");
    moos_types::fmt::g(&mut s, l.memory_kb as f64, 4);
    s.push_str(",memory_max_kb=");
    moos_types::fmt::g(&mut s, l.memory_max_kb as f64, 4);
    s.push_str(",MOOSName=");
    s.push_str(name);
    s.push_str(",Publishing=\"");
    for p in published {
        s.push_str(p);
        s.push(',');
    }
    s.push_str("\",Subscribing=\"");
    for p in subscribed {
        s.push_str(p);
        s.push(',');
    }
    s.push('"');
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use mission::source::SourceMap;

    fn block(text: &str) -> ProcessConfig {
        let src = SourceMap::from_text("t.moos", text);
        mission::moos::parse_moos(&src).value.processes[0].clone()
    }

    #[test]
    fn app_tick_follows_moos_limits() {
        let t = |s: &str| app_tick_of(Some(&block(&format!("ProcessConfig = a\n{{\n{s}\n}}\n"))));
        assert_eq!(t("AppTick = 4"), 4.0);
        assert_eq!(t("apptick = 0.5"), 0.5);
        assert_eq!(t("AppTick = 250"), MAX_APP_TICK);
        assert_eq!(t("AppTick = 0"), MAX_APP_TICK);
        assert_eq!(t("AppTick = -1"), MAX_APP_TICK);
        assert_eq!(t("AppTick = fast"), DEFAULT_APP_TICK);
        assert_eq!(t("CommsTick = 4"), DEFAULT_APP_TICK);
    }

    #[test]
    fn wildcard_detection() {
        assert!(Subscription::var("NAV_*").is_wildcard());
        assert!(Subscription::var("A?").is_wildcard());
        assert!(!Subscription::var("NAV_X").is_wildcard());
    }
}
