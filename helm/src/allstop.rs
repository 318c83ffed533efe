//! The all-stop logic (reference §4.6, MOOS `HelmIvP::postAllStop`).

/// Why the helm is not driving, as posted in `IVPHELM_ALLSTOP`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AllStopReason {
    /// Decisions are being made.
    Clear,
    /// MOOS_MANUAL_OVERRIDE=true (helm in PARK).
    ManualOverride,
    /// No behaviour produced an objective function.
    NothingToDo,
    /// A behaviour reported an error; the helm is halted.
    BehaviorError,
    /// `goals_mandatory` and no goal behaviour is active.
    NoGoalBehavior,
    /// A non-optional domain variable got no decision.
    MissingDecVars,
}

/// The all-stop state machine: posts `IVPHELM_ALLSTOP` on change, and zero decisions on the
/// second consecutive "no decision" iteration (the first is a grace iteration).
#[derive(Debug, Clone, Default)]
pub struct AllStop {
    msg: String,
    no_decisions: u32,
    no_goal: u32,
}

/// What [`AllStop::update`] asks the helm to post.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AllStopAction {
    /// Nothing (the message did not change).
    None,
    /// Post `IVPHELM_ALLSTOP = msg` only.
    Announce(String),
    /// Post `IVPHELM_ALLSTOP = msg` and `DESIRED_<VAR> = 0` for every domain variable.
    AnnounceAndZero(String),
}

impl AllStop {
    /// The current message.
    pub fn message(&self) -> &str {
        &self.msg
    }

    /// Applies a new all-stop message (`clear`, `ManualOverride`, `NothingToDo`,
    /// `NoGoalBehavior`, `MissingDecVars:x,y`, ...). The first consecutive `NothingToDo` /
    /// `MissingDecVars` and the first consecutive `NoGoalBehavior` are grace iterations: the
    /// message is announced, the internal message becomes `IncompleteOrEmptyDecision` /
    /// `NoActiveGoalBehavior`, and nothing is zeroed.
    ///
    /// ```
    /// use helm::allstop::{AllStop, AllStopAction};
    /// let mut a = AllStop::default();
    /// assert_eq!(a.update("NothingToDo"), AllStopAction::Announce("NothingToDo".into()));
    /// assert_eq!(a.message(), "IncompleteOrEmptyDecision");
    /// assert_eq!(a.update("NothingToDo"), AllStopAction::AnnounceAndZero("NothingToDo".into()));
    /// assert_eq!(a.update("NothingToDo"), AllStopAction::None);
    /// assert_eq!(a.update("clear"), AllStopAction::Announce("clear".into()));
    /// assert_eq!(a.update("NoGoalBehavior"), AllStopAction::Announce("NoGoalBehavior".into()));
    /// assert_eq!(a.message(), "NoActiveGoalBehavior");
    /// assert_eq!(a.update("NoGoalBehavior"), AllStopAction::AnnounceAndZero("NoGoalBehavior".into()));
    /// ```
    pub fn update(&mut self, msg: &str) -> AllStopAction {
        if msg == self.msg {
            return AllStopAction::None;
        }
        self.msg = msg.to_string();
        if msg == "NothingToDo" || msg.starts_with("MissingDecVars") {
            self.no_decisions += 1;
        } else {
            self.no_decisions = 0;
        }
        if msg == "NoGoalBehavior" {
            self.no_goal += 1;
        } else {
            self.no_goal = 0;
        }
        if msg.eq_ignore_ascii_case("clear") {
            return AllStopAction::Announce(self.msg.clone());
        }
        if self.no_decisions == 1 {
            let announced = std::mem::replace(&mut self.msg, "IncompleteOrEmptyDecision".into());
            return AllStopAction::Announce(announced);
        }
        if self.no_goal == 1 {
            let announced = std::mem::replace(&mut self.msg, "NoActiveGoalBehavior".into());
            return AllStopAction::Announce(announced);
        }
        AllStopAction::AnnounceAndZero(self.msg.clone())
    }
}
