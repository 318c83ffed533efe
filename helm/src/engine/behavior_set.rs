//! The behaviour set (pHelmIvP's `BehaviorSet::produceOF`, reference §4.4): each
//! behaviour's updates, duration, run state from its conditions, the hooks called in each
//! state, its objective function and `BHV_STATUS`.

use super::*;

/// One behaviour in the set, with the bookkeeping pHelmIvP keeps for it.
pub(super) struct Slot {
    pub(super) common: Common,
    pub(super) bhv: Box<dyn Behavior>,
    pub(super) state: RunState,
    pub(super) entered: f64,
    pub(super) clock: DurationClock,
    pub(super) first_done: bool,
    /// The configuration-time postings went out (see [`Helm::holding`]).
    pub(super) config_posted: bool,
    pub(super) completed: bool,
    pub(super) ok: bool,
    pub(super) good_updates: u32,
    pub(super) bad_updates: u32,
    pub(super) prev_update: String,
    pub(super) pcs: usize,
    pub(super) ctr: [u32; 6],
    pub(super) now_start: Option<f64>,
    /// What the behaviour posted while being configured: sent on its first iteration.
    pub(super) config_out: Out,
    /// For a spawned behaviour, its template's name prefix (an update's `name=` then names
    /// it without the prefix, MOOS `getSpawnBaseName`).
    pub(super) spawn_base: Option<String>,
    /// Why the behaviour completed (its death event's `post_mortem`, MOOS `m_post_mortem`).
    pub(super) post_mortem: String,
    /// The generator of the `$[HASH..]` macros (0 until first used, then seeded from the
    /// behaviour's name).
    pub(super) hash_rng: u64,
    /// The aux of its postings (`<iteration>:<behaviour>`) and the iteration it is for.
    pub(super) aux: (u64, ByteString),
    /// Its latest `BHV_STATUS` text, shared again while unchanged.
    pub(super) status: ByteString,
    /// The shared name `BHV_STATUS` is posted under (`post_mapping` applied; `None` when
    /// silenced), resolved at the first posting after the behaviour's parameters change.
    pub(super) status_var: Option<Option<ByteString>>,
}

/// The characters of a `$[HASH]` (MOOS `hashAlphaNum`: digits and letters without `o`/`O`).
const HASH_CHARS: &[u8] = b"0123456789abcdefghijklmnpqrstuvwxyzABCDEFGHIJKLMNPQRSTUVWXYZ";

impl Slot {
    /// The state of this behaviour's `$[HASH]` generator: a xorshift generator seeded from
    /// its name (FNV-1a), so a lockstep run posts the same hashes every time (MOOS
    /// `hashAlphaNum` draws from the process's `rand()`).
    pub(super) fn hash_state(&mut self) -> u64 {
        if self.hash_rng == 0 {
            let mut h: u64 = 0xcbf2_9ce4_8422_2325;
            for b in self.common.name.bytes() {
                h = (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
            }
            self.hash_rng = h | 1;
        }
        self.hash_rng
    }

    /// A new behaviour of the set with its type's defaults (name: the type's
    /// [`Behavior::default_name`]).
    pub(super) fn new(bhv: Box<dyn Behavior>) -> Slot {
        let mut common = Common::new(bhv.kind());
        common.name = bhv.default_name().to_string();
        for (param, value) in bhv.default_common_params() {
            // The type's own defaults: valid by construction.
            let _ = common.set_param(param, value);
        }
        Slot {
            common,
            bhv,
            state: RunState::New,
            entered: 0.0,
            clock: DurationClock::default(),
            first_done: false,
            config_posted: false,
            completed: false,
            ok: true,
            good_updates: 0,
            bad_updates: 0,
            prev_update: String::new(),
            pcs: 0,
            ctr: [0; 6],
            now_start: None,
            config_out: Out::default(),
            spawn_base: None,
            post_mortem: String::new(),
            hash_rng: 0,
            aux: (0, ByteString::new()),
            status: ByteString::new(),
            status_var: None,
        }
    }

    /// The aux of this behaviour's postings in iteration `iter`, `<iter>:<name>`.
    pub(super) fn post_aux(&mut self, iter: u64) -> ByteString {
        if self.aux.0 != iter || self.aux.1.is_empty() {
            let mut aux = String::with_capacity(self.common.name.len() + 8);
            uint(&mut aux, iter);
            aux.push(':');
            aux.push_str(&self.common.name);
            self.aux = (iter, ByteString::from(aux));
        }
        self.aux.1.clone()
    }

    pub(super) fn duration(&self) -> f64 {
        self.common
            .duration
            .unwrap_or_else(|| self.bhv.default_duration())
    }
    /// Appends `good/total` updates, or `n/a` without an `updates` variable.
    pub(super) fn write_update_summary(&self, out: &mut String) {
        if self.common.update_var.is_empty() {
            out.push_str("n/a");
        } else {
            uint(out, u64::from(self.good_updates));
            out.push('/');
            uint(out, u64::from(self.good_updates + self.bad_updates));
        }
    }
}

/// Appends `len` random characters of [`HASH_CHARS`] drawn from the generator `state`.
pub(super) fn push_hash(state: &mut u64, len: usize, out: &mut String) {
    for _ in 0..len {
        let mut x = *state;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        *state = x;
        out.push(HASH_CHARS[(x % HASH_CHARS.len() as u64) as usize] as char);
    }
}

/// Why a behaviour is not running (`pc=` of `BHV_STATUS`): the text of its `k`-th condition,
/// or another reason.
pub(super) enum Failed {
    Condition(usize),
    Other(String),
}

/// Applies one parameter to a behaviour: common parameters first, then the behaviour's own
/// (as pHelmIvP's populator does).
pub(super) fn apply_param(
    slot: &mut Slot,
    key: &str,
    value: &str,
    info: &InfoBuffer,
    config: &HelmConfig,
    ownship: &str,
) -> Result<(), ParamError> {
    // A parameter may change the post mapping.
    slot.status_var = None;
    if slot.common.set_param(key, value)? {
        return Ok(());
    }
    let perpetual = slot.common.perpetual;
    let name = slot.common.name.clone();
    let ctx = Ctx {
        info,
        domain: &config.domain,
        ownship,
        name: &name,
        perpetual,
    };
    slot.bhv
        .set_param(key, value.trim(), &mut slot.common, &ctx)
}

impl Helm {
    /// Converts a behaviour call's output into queued messages.
    pub(super) fn absorb(&mut self, i: usize) {
        // Most calls emit nothing: the buffer is left as it is.
        let e = &self.emit;
        if e.emits.is_empty()
            && e.error.is_none()
            && e.fault.is_none()
            && !e.completed
            && e.post_mortem.is_empty()
        {
            return;
        }
        let mut emit = std::mem::take(&mut self.emit);
        for e in emit.emits.drain(..) {
            match e {
                Emit::Post { var, value, key } => self.queue_owned(i, var, value, &key),
                Emit::Flag { flag, repeatable } => self.post_flag(i, &flag, repeatable),
                Emit::Complete => self.set_complete(i, &emit.post_mortem),
                Emit::EndFlags { repeatable } => {
                    let flags = self.slots[i].common.flags(FlagKind::End).to_vec();
                    for f in &flags {
                        self.post_flag(i, f, repeatable);
                    }
                }
            }
        }
        if let Some(msg) = emit.error.take() {
            let name = self.slots[i].common.name.clone();
            self.queue(
                i,
                "BHV_ERROR",
                Value::String(format!("{name}: {msg}").into()),
                &PostKey::Repeatable,
            );
            self.slots[i].ok = false;
        }
        if let Some(f) = emit.fault.take() {
            self.fault.get_or_insert(f);
        }
        emit.clear();
        self.emit = emit;
    }

    /// MOOS `setComplete(reason)`: the endflags, then, unless perpetual, completion with
    /// the behaviour's post mortem for `reason` ([`Behavior::post_mortem`]).
    pub(super) fn set_complete(&mut self, i: usize, reason: &str) {
        self.post_flags(i, FlagKind::End);
        if !self.slots[i].common.perpetual {
            let slot = &mut self.slots[i];
            slot.completed = true;
            slot.post_mortem = slot.bhv.post_mortem(reason);
        }
    }

    pub(super) fn check_updates(&mut self, i: usize, now: f64) -> bool {
        let var = &self.slots[i].common.update_var;
        if var.is_empty() || self.info.deltas(var).is_empty() {
            return false;
        }
        let var = var.clone();
        let updates: Vec<String> = self
            .info
            .deltas(&var)
            .iter()
            .map(|u| u.to_string())
            .collect();
        let mut made = false;
        // Even a faulty update applies its good parameters (conditions, flags...).
        self.state_vars_dirty |= !updates.is_empty();
        for u in updates {
            let name = self.slots[i].common.name.clone();
            let mut result = format!("bhv={name},var={var},time=");
            fixed(&mut result, now - self.start_time, 2);
            let lower = u.to_ascii_lowercase();
            let fresh = lower.contains("toggle")
                || lower.contains("engage")
                || lower.contains("mod")
                || (!u.is_empty() && u != self.slots[i].prev_update);
            if !fresh {
                result.push_str(",result=duplicate");
            } else {
                let pairs: Vec<(String, String)> = u
                    .split('#')
                    .filter(|p| !p.trim().is_empty())
                    .map(|p| {
                        let (k, v) = p.split_once('=').unwrap_or((p, ""));
                        (param_name(k.trim()), v.trim().to_string())
                    })
                    .collect();
                // A spawned behaviour is named by its template's prefix and the update's name.
                let base = self.slots[i].spawn_base.as_deref();
                let mismatch = |v: &str| match base {
                    Some(b) => name.strip_prefix(b) != Some(v),
                    None => v != name,
                };
                if pairs.iter().any(|(k, v)| k == "name" && mismatch(v)) {
                    result.push_str(",result=name_mismatch");
                } else {
                    let mut bad = Vec::new();
                    for (k, v) in pairs.iter().filter(|(k, _)| k != "name") {
                        let slot = &mut self.slots[i];
                        let r = apply_param(slot, k, v, &self.info, &self.config, &self.ownship);
                        if r.is_err() {
                            bad.push(k.clone());
                        }
                    }
                    if bad.is_empty() {
                        made = true;
                        self.slots[i].good_updates += 1;
                        self.slots[i].prev_update = u.clone();
                        result.push_str(",result=success");
                    } else {
                        self.slots[i].bad_updates += 1;
                        let w = format!(
                            "Faulty update for behavior: {name}. Bad parameter(s): {}",
                            bad.join(",")
                        );
                        self.queue(
                            i,
                            "BHV_WARNING",
                            Value::String(w.clone().into()),
                            &PostKey::Var,
                        );
                        self.queue(
                            i,
                            "BHV_CONFIG_WARNING",
                            Value::String(w.into()),
                            &PostKey::Var,
                        );
                        result.push_str(",result=param_error");
                    }
                }
            }
            result.push_str(",val=");
            result.push_str(&u);
            self.update_results.push(result);
        }
        made
    }

    pub(super) fn check_duration_reset(&mut self, i: usize) {
        let Some((var, val)) = self.slots[i].common.duration_reset.clone() else {
            return;
        };
        let Some(e) = self.info.get(&var) else {
            return;
        };
        let triggered = val.is_empty()
            || match &e.value {
                Value::String(s) => *s == val,
                Value::Double(x) => val.trim().parse::<f64>().ok() == Some(*x),
                Value::Binary(_) => false,
            };
        if !triggered {
            return;
        }
        let stamp = e.time;
        let slot = &mut self.slots[i];
        if slot.clock.reset_stamp.is_none_or(|s| stamp > s) {
            slot.clock.reset_stamp = Some(stamp);
            self.reset_duration(i);
        }
    }

    pub(super) fn reset_duration(&mut self, i: usize) {
        self.slots[i].clock.reset();
        let status = self.slots[i].common.duration_status.clone();
        if !status.is_empty() {
            let d = self.slots[i].duration();
            self.queue(i, &status, Value::Double(d), &PostKey::Var);
        }
    }

    pub(super) fn post_remaining(&mut self, i: usize, remaining: f64) {
        let status = self.slots[i].common.duration_status.clone();
        if status.is_empty() {
            return;
        }
        let v = if remaining <= 10.0 {
            remaining
        } else {
            (remaining + 0.5).floor()
        };
        self.queue(i, &status, Value::Double(v), &PostKey::Var);
    }

    /// MOOS `isRunnable`: the state from conditions, duration and starvation. Returns the
    /// state and the first failed condition.
    pub(super) fn runnable(&mut self, i: usize, now: f64) -> (RunState, Option<Failed>) {
        self.complete_if_contact_gone(i);
        if self.slots[i].completed {
            return (RunState::Completed, None);
        }
        if self.slots[i].bhv.is_disabled() {
            return (RunState::Disabled, None);
        }
        let failed = {
            let info = &self.info;
            let lookup = |n: &str| info.condition_value(n);
            self.slots[i]
                .common
                .conditions
                .iter()
                .position(|(_, c)| !c.evaluate(&lookup))
        };
        if let Some(k) = failed {
            return (RunState::Idle, Some(Failed::Condition(k)));
        }
        if self.slots[i].clock.reset_pending {
            self.reset_duration(i);
        }
        let (dur, decay) = (
            self.slots[i].duration(),
            self.slots[i].common.duration_idle_decay,
        );
        let (exceeded, remaining) = self.slots[i].clock.check(now, dur, decay);
        if dur >= 0.0 {
            self.post_remaining(i, remaining);
        }
        if exceeded {
            self.set_complete(i, "");
            if self.slots[i].common.perpetual {
                self.slots[i].clock.reset_pending = true;
            } else {
                return (
                    RunState::Completed,
                    Some(Failed::Other("completed-byduration".into())),
                );
            }
        }
        // MOOS `subDomain` leaves a behaviour an empty domain when the helm lacks one of its
        // decision variables; `isRunnable` then posts an error (which halts the helm) and
        // keeps it idle.
        let null_domain = self.config.domain.is_empty()
            || self.slots[i]
                .bhv
                .domain_vars()
                .iter()
                .any(|v| self.config.domain.get(v).is_none());
        if null_domain {
            let msg = format!(
                "{}: Null IvPDomain given to Behavior",
                self.slots[i].common.name
            );
            self.queue(
                i,
                "BHV_ERROR",
                Value::String(msg.into()),
                &PostKey::Repeatable,
            );
            self.slots[i].ok = false;
            return (RunState::Idle, Some(Failed::Other("null-domain".into())));
        }
        for (var, secs) in self.slots[i].common.starve.clone() {
            let age = self.info.age(&var);
            if age.is_none_or(|a| a > secs) {
                return (
                    RunState::Idle,
                    Some(Failed::Other(format!("VarStarve: {var}"))),
                );
            }
        }
        (RunState::Running, None)
    }

    pub(super) fn call<F>(&mut self, i: usize, f: F) -> Option<ivp::IvpFunction>
    where
        F: FnOnce(&mut dyn Behavior, &Ctx<'_>, &mut Out) -> Option<ivp::IvpFunction>,
    {
        let mut emit = std::mem::take(&mut self.emit);
        let r = {
            let slot = &mut self.slots[i];
            let ctx = Ctx {
                info: &self.info,
                domain: &self.config.domain,
                ownship: slot.common.us.as_deref().unwrap_or(&self.ownship),
                name: &slot.common.name,
                perpetual: slot.common.perpetual,
            };
            f(slot.bhv.as_mut(), &ctx, &mut emit)
        };
        self.emit = emit;
        self.absorb(i);
        r
    }

    /// One behaviour's iteration (MOOS `BehaviorSet::produceOF`, reference §4.4).
    pub(super) fn produce(&mut self, i: usize, now: f64) -> Option<ivp::IvpFunction> {
        let old = self.slots[i].state;
        if !self.slots[i].config_posted && !self.holding() {
            // Configuration-time postings first (MOOS queues them in the behaviour's message
            // list before this iteration's), then the configflags; with hold_on_apps, only
            // once every named app is in DB_CLIENTS.
            self.slots[i].config_posted = true;
            let pending = std::mem::take(&mut self.slots[i].config_out);
            if !pending.emits.is_empty() || pending.error.is_some() {
                let buffer = std::mem::replace(&mut self.emit, pending);
                self.absorb(i);
                self.emit = buffer;
            }
            self.post_flags(i, FlagKind::Config);
        }
        if self.check_updates(i, now) {
            self.subs_dirty = true;
            self.state_vars_dirty = true;
            // MOOS: `checkUpdates` posts the settings, then `onSetParamComplete` runs.
            self.call(i, |b, ctx, out| {
                behaviors::post_config_status(b, ctx, out);
                b.on_set_param_complete(ctx, out);
                None
            });
        }
        let iteration = self.iteration;
        self.slots[i].bhv.set_helm_iteration(iteration);
        self.check_duration_reset(i);
        let (mut state, failed) = self.runnable(i, now);
        let mut ipf = None;
        match state {
            RunState::Completed => {
                self.call(i, |b, ctx, out| {
                    b.on_complete(ctx, out);
                    None
                });
            }
            RunState::Disabled => self.run_disabled(i),
            RunState::Idle => {
                if old != RunState::Idle {
                    self.post_flags(i, FlagKind::Idle);
                    self.post_flags(i, FlagKind::Inactive);
                }
                if old.is_running() {
                    self.call(i, |b, ctx, out| {
                        b.on_run_to_idle(ctx, out);
                        None
                    });
                }
                let (idle, run) = (
                    self.slots[i].clock.idle_time,
                    self.slots[i].clock.running_time,
                );
                self.call(i, |b, ctx, out| {
                    b.state_durations(idle, run);
                    b.on_idle(ctx, out);
                    None
                });
                self.slots[i].clock.account(now, false);
            }
            _ => {
                if old == RunState::Idle {
                    self.call(i, |b, ctx, out| {
                        b.on_idle_to_run(ctx, out);
                        None
                    });
                }
                let (idle, run) = (
                    self.slots[i].clock.idle_time,
                    self.slots[i].clock.running_time,
                );
                let mut f = self.call(i, |b, ctx, out| {
                    b.state_durations(idle, run);
                    b.on_run(ctx, out)
                });
                // As pHelmIvP's BehaviorSet since Feb 2026: run flags (on entering the run
                // state) and runx flags (every running iteration) go out after on_run, so
                // behaviour macros set there are current in them.
                if matches!(old, RunState::Idle | RunState::New) {
                    self.post_flags(i, FlagKind::Run);
                }
                self.post_flags(i, FlagKind::Runx);
                if f.as_ref().is_some_and(|f| {
                    f.pieces()
                        .any(|p| p.max_val().is_nan() || p.min_val().is_nan())
                }) {
                    f = None;
                    let name = self.slots[i].common.name.clone();
                    let msg = format!("{name}: NaN detected in IvP Function");
                    self.queue(
                        i,
                        "BHV_ERROR",
                        Value::String(msg.into()),
                        &PostKey::Repeatable,
                    );
                    self.slots[i].ok = false;
                }
                let pwt = self.slots[i].common.pwt * self.slots[i].bhv.pwt_factor();
                let f = f.filter(|_| pwt > 0.0).map(|f| f.with_pwt(pwt));
                if let Some(f) = f {
                    // BehaviorSet reports every function it receives (`m_report_ipf` is on
                    // by default), before the active flags; the helm splits it into parts
                    // when it posts the behaviour's messages.
                    let mut text = String::new();
                    let mut context = String::with_capacity(24);
                    uint(&mut context, self.iteration);
                    context.push(':');
                    context.push_str(&self.slots[i].common.name);
                    ivp::encode::encode(&f, &context, &mut text);
                    self.queue(
                        i,
                        "BHV_IPF",
                        Value::String(text.into()),
                        &PostKey::Repeatable,
                    );
                    if old != RunState::Active {
                        self.post_flags(i, FlagKind::Active);
                    }
                    self.slots[i].pcs = f.piece_count();
                    state = RunState::Active;
                    ipf = Some(f);
                } else {
                    self.slots[i].pcs = 0;
                    if old == RunState::Active {
                        self.post_flags(i, FlagKind::Inactive);
                    }
                }
                self.slots[i].clock.account(now, true);
            }
        }
        // MOOS calls `isRunnable` once more here: a spawned behaviour whose contact is gone
        // completes again (`able.rs`).
        self.complete_if_contact_gone(i);
        if state != RunState::Completed && self.slots[i].completed {
            state = RunState::Completed;
            ipf = None;
            self.call(i, |b, ctx, out| {
                b.on_complete(ctx, out);
                None
            });
        }
        // BHV_STATUS, filtered on change.
        let slot = &self.slots[i];
        let mut status = std::mem::take(&mut self.scratch);
        status.clear();
        status.push_str("name=");
        status.push_str(&slot.common.name);
        match &failed {
            Some(Failed::Condition(k)) => {
                status.push_str(",pc=");
                status.push_str(&slot.common.conditions[*k].0);
            }
            Some(Failed::Other(f)) => {
                status.push_str(",pc=");
                status.push_str(f);
            }
            None => {}
        }
        if state == RunState::Active {
            status.push_str(",pwt=");
            fixed(&mut status, slot.common.pwt, 5);
            status.push_str(",pcs=");
            uint(&mut status, slot.pcs as u64);
        }
        status.push_str(",state=");
        status.push_str(state.as_str());
        status.push_str(",updates=");
        slot.write_update_summary(&mut status);
        let slot = &mut self.slots[i];
        if slot.status != *status {
            slot.status = ByteString::from(status.as_str());
        }
        let text = slot.status.clone();
        self.scratch = status;
        let var = match &self.slots[i].status_var {
            Some(var) => var.clone(),
            None => {
                let var = self.slots[i]
                    .common
                    .mapped("BHV_STATUS")
                    .map(|v| self.out.names.get(v));
                self.slots[i].status_var = Some(var.clone());
                var
            }
        };
        if let Some(var) = var {
            let value = Value::String(text);
            let key = PostKey::Tag("");
            self.messages.push((i, Message { var, value, key }));
        }
        if !self.slots[i].first_done {
            self.slots[i].first_done = true;
            self.post_flags(i, FlagKind::Spawnx);
        }
        if old != state {
            self.slots[i].entered = now;
        }
        self.slots[i].state = state;
        ipf
    }
}
