//! Drawing hints as MOOS-IvP keeps them (`ColorPack`, `HintHolder`): the `visual_hints`
//! parameter of the drawing behaviours. Colour names are [`geometry::color`]'s.

use std::collections::BTreeMap;

use crate::param::{atof, is_number};

/// Whether `s` names a colour as MOOS `isColor` reads it (see [`geometry::color::is_color`]).
pub fn is_color(s: &str) -> bool {
    geometry::color::is_color(s)
}

/// Whether `s` gives a colour other than black (MOOS `colorParse` not all zero).
fn nonblack(s: &str) -> bool {
    geometry::color::color_rgb(s).is_some_and(|c| c != [0.0; 3])
}

/// The text a drawing writes for the colour `s` (MOOS `ColorPack(s).str()`), or `None` when
/// MOOS would not set the colour at all: `invisible` for exactly `invisible`, `empty` or
/// `off`; `s` itself for any other colour (black in any case); `None` otherwise.
///
/// ```
/// use behaviors::color::pack;
/// assert_eq!(pack("off").as_deref(), Some("invisible"));
/// assert_eq!(pack("Yellow").as_deref(), Some("Yellow"));
/// assert_eq!(pack("OFF"), None);
/// ```
pub fn pack(s: &str) -> Option<String> {
    if matches!(s, "invisible" | "empty" | "off") {
        return Some("invisible".into());
    }
    if s.eq_ignore_ascii_case("black") || nonblack(s) {
        Some(s.to_string())
    } else {
        None
    }
}

/// Named colours and sizes for drawing (MOOS `HintHolder`), set by `visual_hints`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Hints {
    colors: BTreeMap<String, String>,
    measures: BTreeMap<String, f64>,
}

impl Hints {
    /// Sets a colour; `lcolor` in the key stands for `label_color`. False (nothing set) if
    /// `value` is not a colour.
    pub fn set_color(&mut self, key: &str, value: &str) -> bool {
        if !is_color(value) {
            return false;
        }
        self.colors
            .insert(key.replace("lcolor", "label_color"), value.to_string());
        true
    }

    /// Sets a size. False if `value` is not a number; a negative number is accepted and
    /// ignored (as MOOS).
    pub fn set_measure(&mut self, key: &str, value: &str) -> bool {
        if !is_number(value) {
            return false;
        }
        let d = atof(value);
        if d >= 0.0 {
            self.measures.insert(key.to_string(), d);
        }
        true
    }

    /// Sets one `key=value` hint: a key containing `color` is a colour, any other a size.
    pub fn set_hint(&mut self, hint: &str) -> bool {
        let (k, v) = hint.split_once('=').unwrap_or((hint, ""));
        let (k, v) = (k.trim().to_ascii_lowercase(), v.trim());
        if k.contains("color") {
            self.set_color(&k, v)
        } else {
            self.set_measure(&k, v)
        }
    }

    /// Sets comma-separated hints in order, stopping at the first bad one (those before it
    /// stay set). An empty list is accepted.
    ///
    /// ```
    /// let mut h = behaviors::color::Hints::default();
    /// assert!(h.set_hints("edge_color=red,vertex_size=4"));
    /// assert!(!h.set_hints("edge_size=2,edge_color=bleu,vertex_size=9"));
    /// assert_eq!((h.measure("edge_size"), h.measure("vertex_size")), (2.0, 4.0));
    /// ```
    pub fn set_hints(&mut self, hints: &str) -> bool {
        let mut rest = hints;
        while !rest.is_empty() {
            let (hint, tail) = rest.split_once(',').unwrap_or((rest, ""));
            if !self.set_hint(hint) {
                return false;
            }
            rest = tail;
        }
        true
    }

    /// The colour under `key`, if set.
    pub fn color(&self, key: &str) -> Option<&str> {
        self.colors.get(key).map(String::as_str)
    }

    /// The size under `key`, 0 if unset.
    pub fn measure(&self, key: &str) -> f64 {
        self.measures.get(key).copied().unwrap_or(0.0)
    }

    /// The size under `key`, if set.
    pub fn get_measure(&self, key: &str) -> Option<f64> {
        self.measures.get(key).copied()
    }

    /// The colour under `<prefix>_<key>`, else under `key` (MOOS `applyHints`).
    pub fn color_for(&self, prefix: &str, key: &str) -> Option<&str> {
        if !prefix.is_empty()
            && let Some(c) = self.color(&format!("{prefix}_{key}"))
        {
            return Some(c);
        }
        self.color(key)
    }

    /// The size under `<prefix>_<key>`, else under `key` (MOOS `applyHints`).
    pub fn measure_for(&self, prefix: &str, key: &str) -> Option<f64> {
        if !prefix.is_empty()
            && let Some(m) = self.get_measure(&format!("{prefix}_{key}"))
        {
            return Some(m);
        }
        self.get_measure(key)
    }

    /// Applies the hints under `prefix` to drawing attributes as MOOS `applyHints` does:
    /// label, vertex, edge (`edges`) and fill (`fill`) colours, edge (`edges`) and vertex
    /// sizes. A colour MOOS would not set leaves the attribute as it was.
    pub fn apply(&self, a: &mut geometry::Attributes, prefix: &str, edges: bool, fill: bool) {
        let set = |slot: &mut Option<String>, c: Option<&str>| {
            if let Some(p) = c.and_then(pack) {
                *slot = Some(p);
            }
        };
        set(&mut a.label_color, self.color_for(prefix, "label_color"));
        set(&mut a.vertex_color, self.color_for(prefix, "vertex_color"));
        if edges {
            set(&mut a.edge_color, self.color_for(prefix, "edge_color"));
        }
        if fill {
            set(&mut a.fill_color, self.color_for(prefix, "fill_color"));
        }
        if edges && let Some(m) = self.measure_for(prefix, "edge_size") {
            a.edge_size = Some(m);
        }
        if let Some(m) = self.measure_for(prefix, "vertex_size") {
            a.vertex_size = Some(m);
        }
    }
}
