//! BHV_TestFailure: makes the helm's process fail once the behaviour completes, to test what
//! watches the helm (a standby helm, uProcessWatch, a safety supervisor).
//!
//! # Conformance with BHV_TestFailure (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | failure_type | | | crash | `crash`, or `burn`/`hang` optionally followed by `,SECONDS` (default 3; a time that is not a number keeps the previous one); any other text is accepted and changes nothing, as in the C++ | yes | done |
//!
//! | what | when | coug |
//! |---|---|---|
//! | crash (`assert(0)`): the helm's process aborts; the iteration's postings are never published | every completed iteration (the first one ends the process) | done: [`Fault::Crash`]; the helm app publishes nothing more and leaves the community |
//! | burn: the helm's process busy-loops for the burn time | every completed iteration | done: [`Fault::Burn`]; the helm app runs no iteration for that long (virtual time in lockstep), then publishes the postings of the iteration that hung |
//!
//! The behaviour never returns an objective function (the C++ keeps `IvPBehavior`'s empty
//! `onRunState`), so it completes through its `duration` (or an `updates` setting).

use ivp::IvpFunction;

use crate::behavior::{Behavior, Ctx, Fault, Out, ParamError};
use crate::common::Common;
use crate::param::is_number;

/// The failure a completed BHV_TestFailure inflicts (default: a crash).
#[derive(Debug, Clone)]
pub struct TestFailure {
    /// Crash (true) or burn (false).
    pub crash: bool,
    /// How long a burn lasts, seconds (default 3).
    pub burn_time: f64,
}

impl Default for TestFailure {
    fn default() -> Self {
        Self::new()
    }
}

impl TestFailure {
    /// The MOOS defaults: crash; a burn lasts 3 s.
    pub fn new() -> Self {
        TestFailure {
            crash: true,
            burn_time: 3.0,
        }
    }

    /// The failure on completion.
    pub fn fault(&self) -> Fault {
        if self.crash {
            Fault::Crash
        } else {
            Fault::Burn(self.burn_time)
        }
    }
}

impl Behavior for TestFailure {
    fn kind(&self) -> &'static str {
        "BHV_TestFailure"
    }

    fn default_name(&self) -> &'static str {
        "test_failure"
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        if param != "failure_type" {
            return Err(ParamError::unknown(param));
        }
        let v = value.trim().to_ascii_lowercase();
        if v == "crash" {
            self.crash = true;
        } else if v.starts_with("burn") || v.starts_with("hang") {
            self.crash = false;
            // MOOS `biteString(val, ',')`: what follows the first comma, as is.
            let time = v.split_once(',').map_or("", |(_, t)| t);
            if is_number(time)
                && let Ok(secs) = time.trim().parse()
            {
                self.burn_time = secs;
            }
        }
        Ok(())
    }

    fn on_run(&mut self, _ctx: &Ctx<'_>, _out: &mut Out) -> Option<IvpFunction> {
        None
    }

    fn on_complete(&mut self, _ctx: &Ctx<'_>, out: &mut Out) {
        out.fault(self.fault());
    }
}
