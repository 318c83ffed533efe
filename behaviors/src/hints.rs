//! Reading `visual_hints = key=value, ...` the way MOOS-IvP behaviours read them: the list is
//! split on commas outside double quotes (MOOS `parseStringQ`), each key lower-cased and
//! trimmed; a colour is kept only when MOOS knows it (`isColor`), a size only when it is a
//! number (`isNumber`). Hints that fail those checks are ignored, as in the C++.

use crate::param::{atof, is_number};

/// The `(key, value)` pairs of a hint list: key lower-cased, both trimmed; a pair without `=`
/// has an empty value.
///
/// ```
/// let p: Vec<_> = behaviors::hints::pairs(r#"Edge_Color = red, label="a,b""#).collect();
/// assert_eq!(p, [("edge_color".to_string(), "red"), ("label".to_string(), "\"a,b\"")]);
/// ```
pub fn pairs(spec: &str) -> impl Iterator<Item = (String, &str)> {
    geometry::split_unquoted(spec, ',').into_iter().map(|hint| {
        let (k, v) = hint.split_once('=').unwrap_or((hint, ""));
        (k.trim().to_ascii_lowercase(), v.trim())
    })
}

/// `value` when it is a MOOS colour (see [`geometry::color::is_color`]).
pub fn color(value: &str) -> Option<&str> {
    geometry::color::is_color(value).then_some(value)
}

/// `value` as a size when it is a MOOS number (C `atof` of it), else `None`.
pub fn size(value: &str) -> Option<f64> {
    is_number(value).then(|| atof(value))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_and_sizes_are_checked() {
        assert_eq!(color("light_blue"), Some("light_blue"));
        assert_eq!(color("bluish"), None);
        assert_eq!(size("-2"), Some(-2.0));
        assert_eq!(size("2m"), None);
        let keys: Vec<_> = pairs("a=1,,b").map(|(k, v)| (k, v.to_string())).collect();
        assert_eq!(keys.len(), 3);
        assert_eq!(keys[2], ("b".to_string(), String::new()));
    }
}
