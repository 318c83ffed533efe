//! AppCastingMOOSApp for coug's apps: the part of an app's life that libMOOS's appcasting base
//! class adds around the app's own work, over the pure [`appcast::AppCasting`] state.
//!
//! An app holds an [`AppcastLayer`] and calls it at the same points the C++ base class runs:
//! - at construction, the block's appcasting keys are read ([`AppcastLayer::config_warnings`]
//!   says what was refused);
//! - [`AppcastLayer::subscriptions`] are registered with the app's own;
//! - [`AppcastLayer::take_mail`] consumes `APPCAST_REQ`, `LOADCAST_REQ`,
//!   `TERM_REPORT_INTERVAL` and `COMMS_POLICY` before the app sees its mail;
//! - [`AppcastLayer::begin`] starts each iteration (`APP_LOG`, `<APP>_ITER_GAP`);
//! - [`AppcastLayer::end`] is `PostReport()`: `<APP>_ITER_LEN`, then the `APPCAST` when one
//!   is due, with the body the app writes.

use mission::moos::{MissionFile, ProcessConfig};

use crate::app::{Mail, Post, Subscription, Value};

/// What an app reports for its appcast besides its body.
pub use appcast::Note;

/// The appcasting state of one app.
#[derive(Debug, Clone)]
pub struct AppcastLayer {
    cast: appcast::AppCasting,
    upper: String,
    iter: u32,
    body: String,
    start_warnings: Vec<String>,
}

impl AppcastLayer {
    /// The layer of app `name`, configured from its `block` (`None` when the mission has
    /// none) and the mission's `Community` and `MOOSTimeWarp`. A missing community or block
    /// is not reported here (each app reports its own); refused appcasting keys are, see
    /// [`AppcastLayer::config_warnings`].
    pub fn new(name: &str, block: Option<&ProcessConfig>, mission: &MissionFile) -> Self {
        let warp = mission
            .global("MOOSTimeWarp")
            .and_then(|w| w.trim().parse::<f64>().ok())
            .filter(|w| *w > 0.0)
            .unwrap_or(1.0);
        Self::with_globals(name, block, mission.global("Community"), warp)
    }

    /// [`AppcastLayer::with_globals`] with the app's configuration warnings already posted
    /// (each as `file:line: message`), as every app that reads a block starts.
    pub fn with_config_warnings(
        name: &str,
        block: &ProcessConfig,
        community: Option<&str>,
        warp: f64,
        warnings: &[mission::diagnostic::Diagnostic],
    ) -> Self {
        let mut layer = Self::with_globals(name, Some(block), community, warp);
        for w in warnings {
            layer.config_warning(&w.located());
        }
        layer
    }

    /// [`AppcastLayer::new`] from the values themselves.
    pub fn with_globals(
        name: &str,
        block: Option<&ProcessConfig>,
        community: Option<&str>,
        warp: f64,
    ) -> Self {
        let mut cast = appcast::AppCasting::new(name);
        // libMOOS's mission reader hands a block's lines over last first.
        let lines: Vec<String> = block
            .iter()
            .flat_map(|b| b.entries.iter().rev())
            .map(|p| format!("{}={}", p.key, p.value))
            .collect();
        cast.start_up(
            Some(community.unwrap_or("").trim()),
            Some(lines.as_slice()),
            0.0,
            warp,
        );
        let start_warnings = cast.appcast().config_warnings().to_vec();
        Self {
            cast,
            upper: name.to_ascii_uppercase(),
            iter: 0,
            body: String::new(),
            start_warnings,
        }
    }

    /// The configuration warnings of the appcasting keys (`Invalid TERM_REPORT_INTERVAL:
    /// abc`, ...), in libMOOS's words.
    pub fn config_warnings(&self) -> &[String] {
        &self.start_warnings
    }

    /// Adds a configuration warning of the app's own.
    pub fn config_warning(&mut self, text: &str) {
        self.cast.report_config_warning(text);
    }

    /// The variables the layer registers (before the app's own).
    pub fn subscriptions() -> impl Iterator<Item = Subscription> {
        appcast::casting::REGISTERED_VARIABLES
            .iter()
            .map(|v| Subscription::var(*v))
    }

    /// OnStartUp at MOOS time `now`: event times count from here.
    pub fn on_startup(&mut self, now: f64) {
        self.cast.set_start_time(now);
    }

    /// Takes the layer's own mail; returns whether `m` is the app's.
    pub fn take_mail(&mut self, m: &Mail) -> bool {
        match (&*m.key, &m.value) {
            ("APPCAST_REQ", Value::String(v)) => {
                self.cast.on_request(v, m.time);
            }
            ("LOADCAST_REQ", Value::String(v)) => self.cast.on_loadcast_request(v, m.time),
            // A string posting reads as -1, which the floor turns into 0.4.
            ("TERM_REPORT_INTERVAL", v) => {
                self.cast
                    .on_term_report_interval(v.as_f64().unwrap_or(-1.0));
            }
            // An unknown or laxer-than-allowed policy is a run warning.
            ("COMMS_POLICY", Value::String(v)) => {
                self.cast.on_comms_policy(v);
            }
            (k, _) if appcast::casting::REGISTERED_VARIABLES.contains(&k) => {}
            _ => return true,
        }
        false
    }

    /// Reports a note (run warning, retraction, event) at MOOS time `now`.
    pub fn note(&mut self, note: Note, now: f64) {
        match note {
            Note::Warning(w) => self.cast.report_run_warning(&w),
            Note::Retract(w) => self.cast.retract_run_warning(&w),
            Note::Event(e) => self.cast.report_event(&e, now),
        }
    }

    /// The term-report interval in force, seconds of real time.
    pub fn term_report_interval(&self) -> f64 {
        self.cast.term_report_interval()
    }

    /// The comms policy in force (`open`, `lean`, `dire`).
    pub fn comms_policy(&self) -> &'static str {
        self.cast.comms_policy().as_str()
    }

    /// AppCastingMOOSApp::Iterate at MOOS time `now` for an app ticking at `tick_hz`:
    /// counts the iteration, posts `APP_LOG` (with `APP_LOGGING = log`) and, while a load
    /// cast is requested, `<APP>_ITER_GAP`.
    pub fn begin(&mut self, now: f64, tick_hz: f64, out: &mut Vec<Post>) {
        self.iter = self.iter.saturating_add(1);
        if let Some(log) = self.cast.app_log(self.iter, "") {
            out.push(Post::text("APP_LOG", log));
        }
        if let Some(gap) = self.cast.iteration_started(now, tick_hz) {
            out.push(Post::double(format!("{}_ITER_GAP", self.upper), gap));
        }
    }

    /// PostReport at MOOS time `now`: `<APP>_ITER_LEN` while a load cast is requested (0:
    /// an iteration takes no MOOS time in coug, where time is an argument), then the
    /// `APPCAST` if one is due, its body written by `body`.
    pub fn end(
        &mut self,
        now: f64,
        tick_hz: f64,
        out: &mut Vec<Post>,
        body: impl FnOnce(&mut String),
    ) {
        if !self.end_due(now, tick_hz, out) {
            return;
        }
        let mut text = std::mem::take(&mut self.body);
        text.clear();
        body(&mut text);
        self.post_cast(now, out, &text);
        self.body = text;
    }

    /// [`AppcastLayer::end`] in two steps, for an app whose body reads the struct that
    /// holds the layer: posts `<APP>_ITER_LEN` when asked and says whether an `APPCAST` is
    /// due; if so the app writes its body and hands it to [`AppcastLayer::post_cast`].
    pub fn end_due(&mut self, now: f64, tick_hz: f64, out: &mut Vec<Post>) -> bool {
        if let Some(len) = self.cast.iteration_length(0.0, tick_hz) {
            out.push(Post::double(format!("{}_ITER_LEN", self.upper), len));
        }
        self.cast.due(now, self.iter)
    }

    /// Posts the `APPCAST` with `body` (after [`AppcastLayer::end_due`] said one is due).
    pub fn post_cast(&mut self, now: f64, out: &mut Vec<Post>, body: &str) {
        let value = self.cast.build(self.iter, body, now);
        out.push(Post::text(appcast::casting::APPCAST_VAR, value));
    }
}
