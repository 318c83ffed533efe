//! Hierarchical modes: the `set MODE = VALUE { ... } ELSE` blocks evaluated at the start of
//! every iteration (reference §5.3, MOOS `ModeSet::evaluate`).

use mission::bhv::ModeBlock;
use mission::condition::{Condition, Operand, RelOp, Value};

use crate::info_buffer::InfoBuffer;

struct Entry {
    var: String,
    value: String,
    else_value: String,
    prefix: String,
    conditions: Vec<Condition>,
    /// The conditions on the mode variable itself (e.g. `MODE = ACTIVE`).
    mode_conditions: Vec<Condition>,
}

/// The mode entries of a behaviour file.
pub struct ModeSet {
    entries: Vec<Entry>,
    /// Results of the last evaluation, sorted by variable: (var, value).
    results: Vec<(String, String)>,
}

fn mentions(c: &Condition, var: &str) -> bool {
    c.variables().contains(&var)
}

impl ModeSet {
    /// Builds the set from the parsed blocks, in file order.
    pub fn new(blocks: &[ModeBlock]) -> Self {
        let entries = blocks
            .iter()
            .map(|b| Entry {
                var: b.var.clone(),
                value: b.value.clone(),
                else_value: b.else_value.clone().unwrap_or_default(),
                prefix: b.parent().unwrap_or("").to_string(),
                conditions: b.conditions.iter().map(|c| c.condition.clone()).collect(),
                mode_conditions: b
                    .conditions
                    .iter()
                    .filter(|c| mentions(&c.condition, &b.var))
                    .map(|c| c.condition.clone())
                    .collect(),
            })
            .collect();
        ModeSet {
            entries,
            results: Vec::new(),
        }
    }

    /// The variables the mode conditions read (MOOS `ModeEntry::getConditionVars`), each once,
    /// in declaration order.
    pub fn condition_vars(&self) -> Vec<&str> {
        let mut out: Vec<&str> = Vec::new();
        for e in &self.entries {
            for c in &e.conditions {
                for v in c.variables() {
                    if !out.contains(&v) {
                        out.push(v);
                    }
                }
            }
        }
        out
    }

    /// Whether there are no mode blocks.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Evaluates every entry in order with the buffer's values; each value produced is
    /// immediately visible to later entries. Writes the final values into the buffer and
    /// returns them (sorted by variable name, as pHelmIvP's map orders them).
    pub fn evaluate(&mut self, info: &mut InfoBuffer) -> &[(String, String)] {
        self.results.clear();
        let mut local: Vec<(String, String)> = Vec::new();
        for e in &self.entries {
            let lookup = |name: &str| -> Option<Value<'_>> {
                if let Some((_, v)) = local.iter().find(|(k, _)| k == name) {
                    return Some(Value::String(v));
                }
                info.condition_value(name)
            };
            let value = if e.conditions.iter().all(|c| c.evaluate(&lookup)) {
                e.value.clone()
            } else if e.mode_conditions.iter().all(|c| c.evaluate(&lookup)) {
                e.else_value.clone()
            } else {
                String::new()
            };
            if value.is_empty() {
                continue;
            }
            let value = if e.prefix.is_empty() {
                value
            } else {
                format!("{}:{value}", e.prefix)
            };
            match local.iter_mut().find(|(k, _)| *k == e.var) {
                Some(slot) => slot.1 = value,
                None => local.push((e.var.clone(), value)),
            }
        }
        local.sort_by(|a, b| a.0.cmp(&b.0));
        let now = info.now_time();
        for (k, v) in &local {
            info.set(
                k,
                behaviors::Value::String(v.clone().into()),
                "HELM_MODE",
                now,
            );
        }
        self.results = local;
        &self.results
    }

    /// The last evaluation's values.
    pub fn results(&self) -> &[(String, String)] {
        &self.results
    }

    /// The `modes=` summary: `MODE@ACTIVE:SURVEYING` (several variables joined by `#`).
    pub fn summary(&self) -> String {
        self.results
            .iter()
            .map(|(k, v)| format!("{k}@{v}"))
            .collect::<Vec<_>>()
            .join("#")
    }

    /// The `IVPHELM_MODESET` description: per variable `VAR` followed by
    /// `#<parent|--->,<value>` for every value an entry can give (reference §5.3 example:
    /// `MODE#---,ACTIVE#---,INACTIVE#ACTIVE,RETURNING#ACTIVE,SURVEYING`).
    pub fn definition(&self) -> String {
        let mut vars: Vec<&str> = Vec::new();
        for e in &self.entries {
            if !vars.contains(&e.var.as_str()) {
                vars.push(&e.var);
            }
        }
        let mut parts = Vec::new();
        for var in vars {
            let mut s = var.to_string();
            for e in self.entries.iter().filter(|e| e.var == var) {
                let parent = if e.prefix.is_empty() {
                    "---"
                } else {
                    &e.prefix
                };
                s.push_str(&format!("#{parent},{}", e.value));
                if !e.else_value.is_empty() {
                    s.push_str(&format!("#{parent},{}", e.else_value));
                }
            }
            parts.push(s);
        }
        parts.join("#")
    }
}

/// Whether a condition is exactly `VAR = literal` (used by tests and tools).
pub fn is_simple_equality(c: &Condition, var: &str) -> bool {
    matches!(c, Condition::Compare { lhs: Operand::Var(v), op: RelOp::Eq, .. } if v == var)
}

#[cfg(test)]
mod tests {
    use super::*;
    use mission::source::SourceMap;

    #[test]
    fn hierarchical_modes_like_the_reference() {
        let text = "set MODE = ACTIVE {\n  DEPLOY = true\n} INACTIVE\n\
                    set MODE = RETURNING {\n  MODE = ACTIVE\n  RETURN = true\n} SURVEYING\n";
        let f = mission::bhv::parse_bhv(&SourceMap::from_text("m.bhv", text)).value;
        let mut m = ModeSet::new(&f.modes);
        assert_eq!(
            m.definition(),
            "MODE#---,ACTIVE#---,INACTIVE#ACTIVE,RETURNING#ACTIVE,SURVEYING"
        );
        let mut info = InfoBuffer::new();
        info.set("DEPLOY", behaviors::Value::String("false".into()), "x", 0.0);
        assert_eq!(
            m.evaluate(&mut info),
            [("MODE".to_string(), "INACTIVE".to_string())]
        );
        info.set("DEPLOY", behaviors::Value::String("true".into()), "x", 0.0);
        info.set("RETURN", behaviors::Value::String("false".into()), "x", 0.0);
        m.evaluate(&mut info);
        assert_eq!(m.summary(), "MODE@ACTIVE:SURVEYING");
        info.set("RETURN", behaviors::Value::String("true".into()), "x", 0.0);
        m.evaluate(&mut info);
        assert_eq!(
            behaviors::Info::text(&info, "MODE"),
            Some("ACTIVE:RETURNING")
        );
        assert!(is_simple_equality(
            &f.modes[1].conditions[0].condition,
            "MODE"
        ));
    }
}
