//! MOOS appcasting without I/O: the data model and `APPCAST` string of libMOOS's `AppCast`
//! ([`AppCast`]), and the request, warning, event and rate-limit rules of `AppCastingMOOSApp`
//! ([`AppCasting`]). Nothing here reads a clock or touches the network: every time is an
//! argument (f64 seconds of MOOS time; see [`casting`] for which time each method expects).
//!
//! ```
//! use appcast::{AppCast, AppCasting};
//!
//! let mut app = AppCasting::new("pFoo");
//! assert!(app.start_up(Some("alpha"), Some(&["TERM_REPORT_INTERVAL=1"]), 100.0, 1.0));
//! app.report_event("hello", 102.5);
//! assert!(app.on_request("node=alpha,app=all,duration=3.0,key=uMAC_1,thresh=any", 103.0));
//! assert!(app.due(104.0, 5));
//! let value = app.build(5, "speed: 2\n", 104.0);
//! assert_eq!(
//!     value,
//!     "proc=pFoo!@#iter=5!@#node=alpha!@#iter=5!@#messages=speed: 2!@!@#!@#events_total=1!@#\
//!      events=[2.50]: hello!@#run_warning_total=0!@#"
//! );
//! assert!(!app.due(104.5, 6)); // 0.5 s < 1 s interval
//! assert_eq!(AppCast::parse(&value).events().next(), Some("[2.50]: hello"));
//! ```
//!
//! The facts come from libMOOS (MOOS_Jul2724) `Thirdparty/AppCasting/AppCast.cpp` and
//! `AppCastingMOOSApp.cpp`. Where `shared/reference/moos-protocol.md` §10 says less or differs,
//! the C++ source was followed:
//! - the reference gives `MAX_APPCAST_EVENTS` as 0..50 but says nothing of
//!   `MAX_APPCAST_RUN_WARNINGS`' odd clip (above 1000 becomes 100) or of its warning text
//!   (`Invalid MAX_APPCAST_EVENTS: ...`);
//! - it presents the request duration next to the real-time rate limit; in C++ the duration is
//!   compared with MOOS (warped) time, only the rate limit divides by the warp;
//! - it omits that a new configuration warning makes an appcast pending with no request at
//!   all, and that the `run_warnings=` field ends the string without a trailing `!@#`;
//! - the `APPCAST_REQ_<NODE>` variable it mentions is never read by the app; it is the
//!   viewers' copy for the shore broker, bridged to the vehicle as `APPCAST_REQ`.
//!
//! # Conformance with AppCastingMOOSApp / AppCast (libMOOS MOOS_Jul2724)
//!
//! | parameter | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|
//! | `TERM_REPORT_INTERVAL` | 0.5 s real | `MOOSIsNumeric`, `atof`, clip `[0, 10]` | mail: double, below 0.4 → 0.4 | done |
//! | `MAX_APPCAST_EVENTS` | 8 | numeric, `atoi`, clip `[0, 50]` | no | done |
//! | `MAX_APPCAST_RUN_WARNINGS` | 10 | numeric, `atoi`, < 0 → 0, > 1000 → 100 | no | done |
//! | `COMMS_POLICY` | open | `open`/`lean`/`dire` (any case) | mail: never laxer than config | done |
//! | `APP_LOGGING` | off | `true`(=log)/`log`/`file`/`off` | no | done: stored only, no redirection |
//! | `DEPRECATED_OK` | false | `true`/`false` | no | done: stored only, no deprecation warnings |
//! | global `Community` | none | missing → config warning | no | done |
//! | global `TERM_REPORTING` | true | `true`/`false` | no | refused: coug has no terminal reports |
//! | MOOS time warp | 1 | `<= 0` → config warning, 0.001 | no | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | `APPCAST` (posted) | end of an iteration when pending and the interval has passed | [`AppCast::to_moos_string`] | done ([`AppCasting::due`], [`AppCasting::build`]) |
//! | `APPCAST_REQ` (read) | viewer request | `node=,app=,duration=,key=,thresh=` | done ([`AppCasting::on_request`]) |
//! | `TERM_REPORT_INTERVAL` (read) | any time | double | done |
//! | `COMMS_POLICY` (read) | any time | `open`/`lean`/`dire` | done |
//! | `LOADCAST_REQ` (read), `<APP>_ITER_GAP`, `<APP>_ITER_LEN` (posted) | load requests | ratios to the tick period | done (`AppCasting::on_loadcast_request`, `iteration_started`, `iteration_length`) |
//! | `APP_LOG` (posted) | `APP_LOGGING=log`, first in each iteration | `iter=<n>,log=<terminal text of the previous iteration>` | done ([`AppCasting::app_log`]; coug's apps write no per-iteration terminal text, so the log part is empty) |
#![deny(missing_docs)]

pub mod appcast;
pub mod casting;
pub mod monitor;
pub mod table;

pub use appcast::AppCast;
pub use casting::{AppCasting, AppLogging, CommsPolicy, Request, WarningFilter};
pub use table::Table;

/// What an app reports for its appcast besides its body (MOOS `reportRunWarning`,
/// `retractRunWarning`, `reportEvent`); apps queue these and their appcasting layer
/// applies them ([`AppCasting::report_run_warning`], ...).
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Note {
    /// A run warning (repeats are counted).
    Warning(String),
    /// A run warning withdrawn.
    Retract(String),
    /// An event.
    Event(String),
}

/// The most notes an app keeps before its layer takes them (the oldest go first).
pub const MAX_NOTES: usize = 256;
