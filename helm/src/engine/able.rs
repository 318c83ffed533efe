//! Disabling behaviours and completing those whose contact is gone (pHelmIvP at a2a9b716).
//!
//! `BHV_ABLE_FILTER` (`HelmIvP::OnNewMail` → `BehaviorSet::applyAbleFilterMsg`): every
//! behaviour of the set gets the message ([`Behavior::apply_able_filter`]); one that can be
//! disabled (a contact behaviour with `can_disable = true`) disables, enables or expunges
//! itself; a malformed message is a run warning, `Unhandled BHV_ABLE_FILTER`. The `contact`
//! field also feeds the spawn blacklist ([`crate::ledger::DisabledContacts`]): a behaviour
//! spawned for a blacklisted contact is disabled at once (`action=disable,contact=<name>`).
//! A disabled behaviour's state is `disabled` (`IvPBehavior::isRunnable`, before its
//! conditions): it runs [`Behavior::on_disabled`] and no other state hook, produces no
//! function, reports `state=disabled` in `BHV_STATUS` and is listed in
//! `IVPHELM_BHV_DISABLED` (with `_CNT`) and `disabled_bhvs` of `IVPHELM_SUMMARY`.
//!
//! The C++ applies the message when the mail arrives; here the messages wait for the next
//! decision iteration and are applied at its start (before spawning, as the mail handler
//! runs before `handlePossibleSpawnings`), so that what an `expunge` posts (the endflags)
//! goes out with that iteration's postings, as the C++ behaviour's message queue holds them
//! until then. No behaviour iterates in between, so the states seen are the same.
//!
//! A dynamically spawned behaviour whose contact (MOOS `m_contact`,
//! [`Behavior::contact_name`]) is not in the helm's contact ledger this iteration completes
//! (`IvPBehavior::isRunnable`, "Added mikerb Jun2525"): `setComplete()` with an empty
//! reason, so its endflags go out and its death event's `post_mortem` is the contact
//! behaviour's `rng=..#bng=..` of its last update. `isRunnable` runs twice in
//! `BehaviorSet::produceOF` (before the hooks and once more after them), and each call
//! completes it again: its (repeatable) endflags go out twice in that iteration, as in the
//! C++. A behaviour from the `.bhv` file (not spawned) is never completed this way; a
//! perpetual one posts its endflags and stays.

use behaviors::{Behavior, Ctx};

use super::{AppcastNote, Helm};

impl Helm {
    /// Takes a `BHV_ABLE_FILTER` message from the mail: the spawn blacklist now, the
    /// behaviours at the start of the next decision ([`Helm::apply_able_filters`]).
    pub(super) fn able_filter_mail(&mut self, msg: &str) {
        self.able_pending.push(msg.to_string());
        self.disabled_contacts.apply(msg);
    }

    /// Hands the pending `BHV_ABLE_FILTER` messages to every behaviour (MOOS
    /// `applyAbleFilterMsg`); a message some behaviour finds malformed is a run warning.
    pub(super) fn apply_able_filters(&mut self) {
        if self.able_pending.is_empty() {
            return;
        }
        for msg in std::mem::take(&mut self.able_pending) {
            let mut all_ok = true;
            for i in 0..self.slots.len() {
                let mut ok = true;
                self.call(i, |b, _ctx, out| {
                    ok = b.apply_able_filter(&msg, out);
                    None
                });
                all_ok &= ok;
            }
            if !all_ok {
                self.notes
                    .push(AppcastNote::Warning("Unhandled BHV_ABLE_FILTER".into()));
            }
        }
    }

    /// After spawning behaviour `i` from `request` (BehaviorSet, "Mod mikerb Sep 0625"):
    /// when the request's `contact` is on the blacklist, the new behaviour is told
    /// `action=disable,contact=<contact>`.
    pub(super) fn disable_if_blacklisted(&mut self, i: usize, request: &str) {
        let contact = super::spawn::field(request, "contact");
        if !self.disabled_contacts.contains(contact) {
            return;
        }
        let msg = format!("action=disable,contact={contact}");
        self.call(i, |b, _ctx, out| {
            b.apply_able_filter(&msg, out);
            None
        });
    }

    /// IvPBehavior's `isRunnable` check of the contact: a spawned behaviour whose contact is
    /// not in the ledger completes (see the module docs). True when it did.
    pub(super) fn complete_if_contact_gone(&mut self, i: usize) -> bool {
        let slot = &self.slots[i];
        if slot.spawn_base.is_none() {
            return false;
        }
        let Some(contact) = slot.bhv.contact_name() else {
            return false;
        };
        if self.ledger.get(contact).is_some() {
            return false;
        }
        self.set_complete(i, "");
        true
    }

    /// One disabled iteration of behaviour `i` (MOOS `onDisabledState`).
    pub(super) fn run_disabled(&mut self, i: usize) {
        self.call(i, |b: &mut dyn Behavior, ctx: &Ctx<'_>, out| {
            b.on_disabled(ctx, out);
            None
        });
    }
}
