//! The vehicle safety supervisor's pure core, run by the `pSafety` app (`runtime::safety`).
//!
//! Modelled on the CoUGARs emergency node (`../shared/reference/cougars-vehicle.md` §6) without
//! its defects, and on LSTS DUNE's monitors (independent watchers that each raise an entity
//! state, with one supervisor choosing the vehicle's response). No I/O and no clock: mail goes
//! in with its time, [`Supervisor::evaluate`] takes `now`, postings come out.
//!
//! # Rules
//!
//! Each `rule =` line of the block is one rule:
//!
//! ```text
//! rule = NAME : CONDITION -> ACTION [, priority=N] [, latch | clear[=SECONDS]] [, kind=KIND]
//! CONDITION = TERM [and TERM]...
//! TERM      = VAR OP VALUE             (OP: == != < <= > >=; VALUE: number, true, false, word)
//!           | stale(VAR) > SECONDS     (no mail of VAR for longer than that)
//!           | silent(APP) > SECONDS    (no <APP>_STATUS nor other mail from APP for that long)
//! ACTION    = surface_disarm | allstop | return | warn
//! ```
//!
//! - A comparison reads the latest value: a number compares the double (or a numeric
//!   string); `true`/`false` a MOOS boolean string or a double (non-zero is true); a word a
//!   string, ignoring case (only `==`, `!=`). A variable never received makes the term false:
//!   pair it with a `stale(..)` rule so that a sensor that never reports is caught.
//! - `stale` and `silent` count from pSafety's start while nothing has been received.
//! - `stale` and `silent` ages are MOOS time the supervisor watched: a gap between two of
//!   its own evaluations longer than `max_gap` (1 s, or twice its period if longer) is a
//!   stalled machine (every app of the community, the drivers and pSafety itself stopped
//!   together; at a time warp of 8 a 0.6 s stall of the wall clock is 5 s of MOOS time), and
//!   the excess is left out of every age, since nobody could post during it. A sensor that
//!   stops while the community runs is caught after its timeout as before (in lockstep every
//!   gap is the period, so nothing is ever left out); a sensor that dies during a stall is
//!   caught at most `max_gap` later than its timeout after the stall. `max_gap` sets the
//!   tolerance (s of MOOS time, > 0); the pSafety app tells the supervisor its period
//!   ([`Supervisor::set_period`]), without which every gap counts.
//! - `priority`: 1 (highest) to 99; default by action: surface_disarm 1, allstop 2, return 3,
//!   warn 4. The triggered rule of highest priority commands the vehicle (ties: the more
//!   drastic action, then the earlier rule); warn rules never command.
//! - `latch` (the default: a guard never lets go by itself) holds the rule until
//!   `SAFETY_RESET = NAME` (or `all`) is posted while its condition is false; `clear` lets it
//!   go once its condition has been false for `SECONDS` (default 0).
//! - `kind` (leak, battery, depth, sensor, nav, comms, app, other) picks the rule's health bit;
//!   a rule named after a kind takes it, others default to `other`.
//!
//! The issue's rule kinds, in this syntax (the variable names are the mission's):
//!
//! ```text
//! rule = leak:    LEAK == true -> surface_disarm, latch
//! rule = battery: BATTERY_VOLTAGE < 14.0 -> surface_disarm
//! rule = depth:   NAV_DEPTH > 6 -> surface_disarm
//! rule = dvl:     stale(DVL_VALID) > 2 -> allstop, kind=sensor
//! rule = depthsensor: stale(PRESSURE) > 2 -> surface_disarm, kind=sensor
//! rule = ahrs:    stale(AHRS_HEADING) > 2 -> surface_disarm, kind=sensor
//! rule = gps:     stale(GPS_FIX) > 10 and NAV_DEPTH < 0.5 -> warn, kind=sensor, clear=5
//! rule = nav:     NAV_POS_STD > 5 -> return, kind=nav, clear=30
//! rule = comms:   stale(ACOMMS_LAST_BASE_CONTACT) > 300 -> return
//! rule = helm:    silent(pHelmIvP) > 5 -> surface_disarm, kind=app
//! rule = helmcfg: IVPHELM_STATE == MALCONFIG -> surface_disarm, kind=app
//! ```
//!
//! # Actions
//!
//! - `surface_disarm`: with `surface_via = direct` (default) pSafety posts the manual
//!   override (`override_var = true`: the helm parks and posts its all-stop, pMarinePID stops
//!   driving) and drives the actuators itself every iteration: `thrust_var = surface_thrust`,
//!   `elevator_var = surface_elevator`, `rudder_var = 0`, plus the `surface_flag`s once (for a
//!   CougUV, `COUG_SURFACE=true`: pCougControls' fins-up command). With `surface_via = helm` it
//!   posts `SAFETY_MODE = SURFACE` and the surface flags for the `.bhv` to act on, and takes the
//!   actuators when the helm fails: `helm_app` silent longer than `helm_timeout`,
//!   `IVPHELM_STATE = MALCONFIG`, or less than 0.5 m of ascent within `helm_grace`. Once
//!   `depth_var` has stayed under `surface_depth` for `surface_hold` seconds (CoUGARs: 0.1 m,
//!   checked every 5 s), or after `surface_timeout`, the thruster is disarmed: thrust,
//!   elevator and rudder 0 every iteration and the `disarm_flag`s (e.g. `DEPLOY=false`).
//! - `allstop`: the manual override, the `allstop_flag`s once, and the actuators held at 0
//!   every iteration.
//! - `return`: the `return_flag`s once (the `.bhv` takes the vehicle home).
//! - `warn`: a SAFETY_EVENT and an appcast run warning.
//!
//! When every rule has let go the `clear_flag`s are posted and pSafety stops driving the
//! actuators; it never lifts the override nor re-arms by itself (the operator resumes). While
//! pSafety holds the override, a `MOOS_MANUAL_OVERRIDE = false` from anyone is answered by
//! `true` again.
//!
//! Any of `override_var`, `thrust_var`, `elevator_var`, `rudder_var` may be `none` (never
//! posted). A CougUV under pCougControls (`vehicle::cougars::CougarsControl`: it stops on
//! `MOOS_MANUAL_OVERRIDE = true`, forces the fins-up command on `COUG_SURFACE = true` while
//! keeping the controller's thrust, and disarms when `DEPLOY` is false: thrust 0 and the fins
//! centred, where CoUGARs left them up) surfaces as the CoUGARs emergency node did, swimming up
//! with its fins up, with the helm dead or alive:
//!
//! ```text
//! override_var = none
//! thrust_var   = none
//! elevator_var = none
//! rudder_var   = none
//! surface_flag = COUG_SURFACE=true
//! disarm_flag  = DEPLOY=false
//! allstop_flag = DEPLOY=false
//! ```
//!
//! (the thruster then stays disarmed: the vehicle comes up on its positive buoyancy).
//!
//! # Configuration errors
//!
//! An unknown key, a bad value, a rule that cannot be read, a rule name given twice, a block
//! without rules or a return without `return_flag` are errors ([`mission::Diagnostic`] at
//! their `file:line`). The supervisor is then MALCONFIG: the errors are appcast config
//! warnings, `coug check` reports them, and the vehicle is kept from deploying (the override
//! is posted at start and re-posted at every `false`); the rules it could read still run.
//!
//! # Postings
//!
//! | variable | when | value |
//! |---|---|---|
//! | `SAFETY_MODE` | at start and on change | `OK`, `WARN`, `RETURN`, `ALLSTOP`, `SURFACE`, `DISARMED`, `MALCONFIG` |
//! | `SAFETY_HEALTH` | at start and on change | the health word, a double (bits below) |
//! | `SAFETY_EVENT` | each trigger, release and phase change | `trigger=NAME,action=A,priority=P,reason=COND (seen)`, `clear=NAME,by=cleared\|reset`, `mode=SURFACE,via=actuators\|helm` (`,helm_failed=WHY` when the helm had already failed), `mode=DISARMED,depth=D,after=S`, `helm_failed=WHY,mode=SURFACE,via=actuators`, `mode=M` |
//! | `override_var`, `thrust_var`, `elevator_var`, `rudder_var`, flags | as the actions say | |
//!
//! # Health word (`SAFETY_HEALTH`)
//!
//! | bit | value | meaning |
//! |---|---|---|
//! | 0 | 1 | a rule is triggered |
//! | 1 | 2 | a warn rule is triggered |
//! | 2 | 4 | return commanded |
//! | 3 | 8 | all-stop |
//! | 4 | 16 | surfacing |
//! | 5 | 32 | surfaced, thruster disarmed |
//! | 6 | 64 | pSafety holds the override and drives the actuators |
//! | 7 | 128 | configuration errors: MALCONFIG, deployment refused |
//! | 8..15 | 256..32768 | a triggered rule of kind leak, battery, depth, sensor, nav, comms, app, other |
//!
//! # Against the CoUGARs emergency node
//!
//! Its known defects are not reproduced: the emergency status is one word that is never
//! overwritten by a boolean; every bit has its own mask; monitoring cannot be switched off by
//! a flag (a rule is there or not, and a rule that cannot be read stops deployment instead of
//! vanishing); staleness counts from start, so a sensor that never publishes is caught; the
//! disarm waits for a confirmed surface, held for `surface_hold`.

pub mod config;
pub mod rule;
pub mod supervisor;

pub use config::{PROGRAM, SafetyConfig, SurfaceVia};
pub use rule::{Action, Kind, Release, Rule, RuleError, parse_rule};
pub use supervisor::{Notice, Phase, Supervisor, bits};

/// The health word's bits by name, in bit order (the crate documentation's table).
pub const HEALTH_BITS: [&str; 16] = [
    "triggered",
    "warn",
    "return",
    "allstop",
    "surfacing",
    "disarmed",
    "actuators",
    "malconfig",
    "leak",
    "battery",
    "depth",
    "sensor",
    "nav",
    "comms",
    "app",
    "other",
];
