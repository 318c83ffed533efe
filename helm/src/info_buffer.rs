//! The helm's info buffer: the latest value, source and times of every variable it has seen,
//! plus the string values received during the current iteration (MOOS `InfoBuffer`).

use behaviors::contact::ContactInfo;
use behaviors::plat_model::PlatModel;
use behaviors::{Info, Value};

use moos_types::ByteString;
use rustc_hash::FxHashMap;

/// One variable's latest state.
#[derive(Debug, Clone, PartialEq)]
pub struct Entry {
    /// Latest value.
    pub value: Value,
    /// Helm time when it was written.
    pub time: f64,
    /// Time stamp of the message that carried it.
    pub msg_time: f64,
    /// Who posted it ("" for the helm itself).
    pub source: String,
}

/// Latest value of every variable, and this iteration's string deltas.
///
/// ```
/// use helm::info_buffer::InfoBuffer;
/// use behaviors::{Info, Value};
/// let mut b = InfoBuffer::new();
/// b.set_now(10.0);
/// b.set("DEPLOY", Value::String("true".into()), "uPokeDB", 9.5);
/// assert_eq!(b.text("DEPLOY"), Some("true"));
/// assert_eq!(b.deltas("DEPLOY"), ["true"]);
/// b.clear_deltas();
/// assert!(b.deltas("DEPLOY").is_empty());
/// ```
#[derive(Debug, Clone, Default)]
pub struct InfoBuffer {
    vars: FxHashMap<String, Var>,
    now: f64,
    /// The contact ledger's snapshot for the behaviours (pHelmIvP's `LedgerSnap`).
    contacts: FxHashMap<String, ContactInfo>,
    /// The platform model of the latest decision iteration with ownship's navigation known.
    plat_model: Option<PlatModel>,
}

/// A variable's entry and its string values of this iteration (one map lookup per write).
#[derive(Debug, Clone)]
struct Var {
    entry: Entry,
    deltas: Deltas,
}

/// One variable's string values of this iteration: the first `len` of `items`, each sharing
/// the buffer of the value written (the slots past `len` are reused).
#[derive(Debug, Clone, Default)]
struct Deltas {
    items: Vec<ByteString>,
    len: usize,
}

impl Deltas {
    fn push(&mut self, s: &ByteString) {
        match self.items.get_mut(self.len) {
            Some(slot) => slot.clone_from(s),
            None => self.items.push(s.clone()),
        }
        self.len += 1;
    }
    fn as_slice(&self) -> &[ByteString] {
        &self.items[..self.len]
    }
}

impl InfoBuffer {
    /// An empty buffer at time 0.
    pub fn new() -> Self {
        Self::default()
    }
    /// Sets the current helm time.
    pub fn set_now(&mut self, now: f64) {
        self.now = now;
    }
    /// Writes a variable (string values are also recorded as this iteration's deltas).
    pub fn set(&mut self, var: &str, value: Value, source: &str, msg_time: f64) {
        match self.vars.get_mut(var) {
            Some(v) => {
                if let Value::String(s) = &value {
                    v.deltas.push(s);
                }
                v.entry.value = value;
                Self::touch(&mut v.entry, self.now, source, msg_time);
            }
            None => self.insert(var, value, source, msg_time),
        }
    }

    /// [`InfoBuffer::set`] from a borrowed value (a string value is shared, not copied).
    pub fn set_ref(&mut self, var: &str, value: &Value, source: &str, msg_time: f64) {
        match self.vars.get_mut(var) {
            Some(v) => {
                match (&mut v.entry.value, value) {
                    (Value::String(old), Value::String(new)) => {
                        v.deltas.push(new);
                        if old != new {
                            old.clone_from(new);
                        }
                    }
                    (slot, new) => {
                        if let Value::String(s) = new {
                            v.deltas.push(s);
                        }
                        *slot = new.clone();
                    }
                }
                Self::touch(&mut v.entry, self.now, source, msg_time);
            }
            None => self.insert(var, value.clone(), source, msg_time),
        }
    }

    fn touch(e: &mut Entry, now: f64, source: &str, msg_time: f64) {
        e.time = now;
        e.msg_time = msg_time;
        if e.source != source {
            e.source.clear();
            e.source.push_str(source);
        }
    }

    fn insert(&mut self, var: &str, value: Value, source: &str, msg_time: f64) {
        let mut deltas = Deltas::default();
        if let Value::String(s) = &value {
            deltas.push(s);
        }
        let entry = Entry {
            value,
            time: self.now,
            msg_time,
            source: source.to_string(),
        };
        self.vars.insert(var.to_string(), Var { entry, deltas });
    }

    /// The entry of a variable.
    pub fn get(&self, var: &str) -> Option<&Entry> {
        self.vars.get(var).map(|v| &v.entry)
    }
    /// Whether the variable has ever been written.
    pub fn is_known(&self, var: &str) -> bool {
        self.vars.contains_key(var)
    }
    /// Seconds since the variable was written (`None` if never): 0 for mail applied in this
    /// iteration.
    pub fn age(&self, var: &str) -> Option<f64> {
        self.get(var).map(|e| self.now - e.time)
    }
    /// The string values written during this iteration, oldest first.
    pub fn deltas(&self, var: &str) -> &[ByteString] {
        self.vars.get(var).map_or(&[], |v| v.deltas.as_slice())
    }
    /// Forgets this iteration's deltas (keeps the allocations).
    pub fn clear_deltas(&mut self) {
        for v in self.vars.values_mut() {
            v.deltas.len = 0;
        }
    }
    /// Replaces the contacts behaviours read ([`Info::contact`]) with the ledger's, as
    /// reported (pHelmIvP's `updateLedgerSnap`; the ledger does not extrapolate). A contact
    /// known only by latitude and longitude is at x = y = 0, as the C++ ledger without a
    /// geodesy gives it.
    pub fn set_contacts(&mut self, ledger: &crate::ledger::ContactLedger) {
        if self.contacts.is_empty() && ledger.is_empty() {
            return;
        }
        self.contacts.retain(|name, _| ledger.get(name).is_some());
        for (name, c) in ledger.iter() {
            // Updated in place: the group and type strings are copied only when they change.
            let slot = match self.contacts.get_mut(name) {
                Some(slot) => slot,
                None => self.contacts.entry(name.to_string()).or_default(),
            };
            slot.x_m = c.x_m.unwrap_or(0.0);
            slot.y_m = c.y_m.unwrap_or(0.0);
            slot.heading_deg = c.heading_deg;
            slot.speed_mps = c.speed_mps;
            slot.depth_m = c.depth_m.unwrap_or(0.0);
            slot.utc = c.time;
            if slot.group != c.group {
                slot.group.clone_from(&c.group);
            }
            if slot.vtype != c.vtype {
                slot.vtype.clone_from(&c.vtype);
            }
        }
    }

    /// pHelmIvP's `updatePlatModel`: with `NAV_X`, `NAV_Y`, `NAV_HEADING` and `NAV_SPEED` all
    /// known, `pmgen` makes this iteration's platform model (true); otherwise the last one
    /// stays (false).
    pub fn update_plat_model(&mut self, pmgen: &mut crate::plat_model::PmGen, now: f64) -> bool {
        let (Some(x), Some(y), Some(h), Some(v)) = (
            self.num("NAV_X"),
            self.num("NAV_Y"),
            self.num("NAV_HEADING"),
            self.num("NAV_SPEED"),
        ) else {
            return false;
        };
        self.plat_model = Some(pmgen.generate(now, x, y, h, v));
        true
    }

    /// The value as a condition operand.
    pub fn condition_value(&self, var: &str) -> Option<mission::condition::Value<'_>> {
        Some(self.get(var)?.value.as_ref())
    }
}

impl Info for InfoBuffer {
    fn now(&self) -> f64 {
        self.now
    }
    fn num(&self, var: &str) -> Option<f64> {
        match &self.get(var)?.value {
            Value::Double(v) => Some(*v),
            Value::String(s) if mission::condition::is_numeric(s.trim()) => s.trim().parse().ok(),
            Value::String(_) | Value::Binary(_) => None,
        }
    }
    fn text(&self, var: &str) -> Option<&str> {
        self.get(var)?.value.as_str()
    }
    fn age(&self, var: &str) -> Option<f64> {
        InfoBuffer::age(self, var)
    }
    fn contact(&self, name: &str) -> Option<&ContactInfo> {
        self.contacts.get(name)
    }
    fn plat_model(&self) -> Option<&PlatModel> {
        self.plat_model.as_ref()
    }
}

impl InfoBuffer {
    /// The current helm time.
    pub fn now_time(&self) -> f64 {
        self.now
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_ref_matches_set_and_deltas_reuse_their_buffers() {
        let mut a = InfoBuffer::new();
        let mut b = InfoBuffer::new();
        for (k, (now, v)) in [
            (1.0, Value::String("x=1".into())),
            (1.0, Value::String("x=22".into())),
            (2.0, Value::Double(3.0)),
            (3.0, Value::String("y".into())),
        ]
        .into_iter()
        .enumerate()
        {
            a.set_now(now);
            b.set_now(now);
            let src = if k % 2 == 0 { "pHelmIvP" } else { "uPokeDB" };
            a.set("V", v.clone(), src, now - 0.5);
            b.set_ref("V", &v, src, now - 0.5);
            assert_eq!(a.get("V"), b.get("V"));
            assert_eq!(a.deltas("V"), b.deltas("V"));
            if now == 1.0 && k == 1 {
                assert_eq!(b.deltas("V"), ["x=1", "x=22"]);
            }
            if k >= 1 {
                a.clear_deltas();
                b.clear_deltas();
                assert!(b.deltas("V").is_empty());
            }
        }
        b.set_ref("V", &Value::String("z".into()), "p", 3.0);
        assert_eq!(b.deltas("V"), ["z"]);
        assert_eq!(b.text("V"), Some("z"));
        assert_eq!(b.get("V").unwrap().source, "p");
    }
}
