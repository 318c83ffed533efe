//! The helm's info buffer: the latest value, source and times of every variable it has seen,
//! plus the string values received during the current iteration (MOOS `InfoBuffer`).

use std::collections::HashMap;

use behaviors::{Info, Value};

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
/// b.set("DEPLOY", Value::Str("true".into()), "uPokeDB", 9.5);
/// assert_eq!(b.text("DEPLOY"), Some("true"));
/// assert_eq!(b.deltas("DEPLOY"), ["true"]);
/// b.clear_deltas();
/// assert!(b.deltas("DEPLOY").is_empty());
/// ```
#[derive(Debug, Clone, Default)]
pub struct InfoBuffer {
    vars: HashMap<String, Entry>,
    deltas: HashMap<String, Vec<String>>,
    now: f64,
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
        if let Value::Str(s) = &value {
            match self.deltas.get_mut(var) {
                Some(v) => v.push(s.clone()),
                None => {
                    self.deltas.insert(var.to_string(), vec![s.clone()]);
                }
            }
        }
        match self.vars.get_mut(var) {
            Some(e) => {
                e.value = value;
                e.time = self.now;
                e.msg_time = msg_time;
                if e.source != source {
                    e.source = source.to_string();
                }
            }
            None => {
                self.vars.insert(
                    var.to_string(),
                    Entry {
                        value,
                        time: self.now,
                        msg_time,
                        source: source.to_string(),
                    },
                );
            }
        }
    }
    /// The entry of a variable.
    pub fn get(&self, var: &str) -> Option<&Entry> {
        self.vars.get(var)
    }
    /// Whether the variable has ever been written.
    pub fn is_known(&self, var: &str) -> bool {
        self.vars.contains_key(var)
    }
    /// Seconds since the variable was written (`None` if never): 0 for mail applied in this
    /// iteration.
    pub fn age(&self, var: &str) -> Option<f64> {
        self.vars.get(var).map(|e| self.now - e.time)
    }
    /// The string values written during this iteration, oldest first.
    pub fn deltas(&self, var: &str) -> &[String] {
        self.deltas.get(var).map_or(&[], Vec::as_slice)
    }
    /// Forgets this iteration's deltas (keeps the allocations).
    pub fn clear_deltas(&mut self) {
        for v in self.deltas.values_mut() {
            v.clear();
        }
    }
    /// The value as a condition operand.
    pub fn condition_value(&self, var: &str) -> Option<mission::condition::Value<'_>> {
        Some(match &self.vars.get(var)?.value {
            Value::Num(v) => mission::condition::Value::Num(*v),
            Value::Str(s) => mission::condition::Value::Str(s),
        })
    }
}

impl Info for InfoBuffer {
    fn now(&self) -> f64 {
        self.now
    }
    fn num(&self, var: &str) -> Option<f64> {
        match &self.vars.get(var)?.value {
            Value::Num(v) => Some(*v),
            Value::Str(s) if mission::condition::is_numeric(s.trim()) => s.trim().parse().ok(),
            Value::Str(_) => None,
        }
    }
    fn text(&self, var: &str) -> Option<&str> {
        self.vars.get(var)?.value.as_str()
    }
    fn age(&self, var: &str) -> Option<f64> {
        InfoBuffer::age(self, var)
    }
}

impl InfoBuffer {
    /// The current helm time.
    pub fn now_time(&self) -> f64 {
        self.now
    }
}
