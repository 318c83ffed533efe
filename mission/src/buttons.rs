//! pMarineViewer's buttons (`button_one = DEPLOY # DEPLOY=true # MOOS_MANUAL_OVERRIDE=false`):
//! how stock missions say what "start" means. Read as pMarineViewer reads them at MOOS-IvP
//! a2a9b716: keys `button_one`..`button_twenty` (or `button_1`..`button_20`); each line is
//! split on `#` outside quotes; a piece `VAR=VALUE` is a posting, a piece without `=` the
//! label, `color=...` the colour; several lines of one button add up.

use crate::moos::MissionFile;
use crate::source::Span;

/// The value a button posts, typed as pMarineViewer types it.
#[derive(Debug, Clone, PartialEq)]
pub enum ButtonValue {
    /// A MOOS number (`isNumber`).
    Double(f64),
    /// Text (a quoted value loses its quotes and stays text).
    Text(String),
    /// `$[UTC]`: the time of the press.
    Utc,
    /// `$[BIX]`: how many button presses came before this one.
    PressCount,
}

/// One button of the mission's pMarineViewer block.
#[derive(Debug, Clone, PartialEq)]
pub struct Button {
    /// Its key, normalised (`button_one`).
    pub key: String,
    /// Its label (the key when none was given).
    pub label: String,
    /// What a press posts, in order.
    pub postings: Vec<(String, ButtonValue)>,
    /// Where it was first defined.
    pub span: Span,
}

const NAMES: [&str; 20] = [
    "one",
    "two",
    "three",
    "four",
    "five",
    "six",
    "seven",
    "eight",
    "nine",
    "ten",
    "eleven",
    "twelve",
    "thirteen",
    "fourteen",
    "fifteen",
    "sixteen",
    "seventeen",
    "eighteen",
    "nineteen",
    "twenty",
];

/// `button_3` and `button_three` both name `button_three`.
fn button_key(param: &str) -> Option<String> {
    let rest = param.to_ascii_lowercase();
    let rest = rest.strip_prefix("button_")?;
    let name = match rest.parse::<usize>() {
        Ok(n) if (1..=20).contains(&n) => NAMES[n - 1],
        _ => NAMES.iter().copied().find(|n| *n == rest)?,
    };
    Some(format!("button_{name}"))
}

fn typed(value: &str) -> ButtonValue {
    if value.len() >= 2 && value.starts_with('"') && value.ends_with('"') {
        return ButtonValue::Text(value[1..value.len() - 1].to_string());
    }
    if geometry::is_number(value) {
        return ButtonValue::Double(value.trim().parse().unwrap_or(0.0));
    }
    match value {
        "$[UTC]" => ButtonValue::Utc,
        "$[BIX]" => ButtonValue::PressCount,
        _ => ButtonValue::Text(value.to_string()),
    }
}

/// The buttons of the mission's pMarineViewer block, in key order (`button_one` first).
///
/// ```
/// use mission::buttons::{ButtonValue, buttons};
/// let src = mission::source::SourceMap::from_text("m.moos", "\
/// ProcessConfig = pMarineViewer
/// {
///   button_one = DEPLOY # DEPLOY=true
///   button_one = MOOS_MANUAL_OVERRIDE=false # SPEED=1.5
/// }
/// ");
/// let m = mission::moos::parse_moos(&src).value;
/// let b = &buttons(&m)[0];
/// assert_eq!(b.label, "DEPLOY");
/// assert_eq!(b.postings[2], ("SPEED".to_string(), ButtonValue::Double(1.5)));
/// ```
pub fn buttons(m: &MissionFile) -> Vec<Button> {
    let Some(block) = m.process("pMarineViewer") else {
        return Vec::new();
    };
    let mut out: Vec<Button> = Vec::new();
    for p in &block.entries {
        let Some(key) = button_key(&p.key) else {
            continue;
        };
        let i = match out.iter().position(|b| b.key == key) {
            Some(i) => i,
            None => {
                out.push(Button {
                    label: key.clone(),
                    key,
                    postings: Vec::new(),
                    span: p.span.clone(),
                });
                out.len() - 1
            }
        };
        for piece in geometry::split_unquoted(&p.value, '#') {
            let (param, value) = piece.split_once('=').unwrap_or((piece, ""));
            let (param, value) = (param.trim(), value.trim());
            if param.is_empty() || param == "color" {
                continue;
            }
            if value.is_empty() {
                out[i].label = param.to_string();
            } else {
                out[i].postings.push((param.to_string(), typed(value)));
            }
        }
    }
    out.sort_by_key(|b| NAMES.iter().position(|n| b.key.ends_with(&format!("_{n}"))));
    out
}

/// The button called `name`: by label (any case), else by key (`button_one`, `button_1`).
pub fn find<'a>(all: &'a [Button], name: &str) -> Option<&'a Button> {
    all.iter()
        .find(|b| b.label.eq_ignore_ascii_case(name))
        .or_else(|| {
            let key = button_key(name)?;
            all.iter().find(|b| b.key == key)
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::source::SourceMap;

    fn mission(text: &str) -> MissionFile {
        crate::moos::parse_moos(&SourceMap::from_text("m.moos", text)).value
    }

    #[test]
    fn lines_of_one_button_add_up_and_values_are_typed_as_pmarineviewer() {
        let m = mission(
            "ProcessConfig = pMarineViewer\n{\n  button_two = RETURN # RETURN=true # color=red\n  button_1 = DEPLOY # DEPLOY=true\n  button_one = MOOS_MANUAL_OVERRIDE=false # NOTE=\"a # b\" # N=-2 # T=$[UTC] # C=$[BIX] # E=1e3\n}\n",
        );
        let b = buttons(&m);
        assert_eq!(b.len(), 2);
        assert_eq!(
            (b[0].key.as_str(), b[0].label.as_str()),
            ("button_one", "DEPLOY")
        );
        assert_eq!(
            b[0].postings,
            [
                ("DEPLOY".to_string(), ButtonValue::Text("true".into())),
                (
                    "MOOS_MANUAL_OVERRIDE".to_string(),
                    ButtonValue::Text("false".into())
                ),
                ("NOTE".to_string(), ButtonValue::Text("a # b".into())),
                ("N".to_string(), ButtonValue::Double(-2.0)),
                ("T".to_string(), ButtonValue::Utc),
                ("C".to_string(), ButtonValue::PressCount),
                ("E".to_string(), ButtonValue::Text("1e3".into())),
            ]
        );
        assert_eq!(b[1].label, "RETURN");
        assert_eq!(b[1].postings.len(), 1, "color is not a posting");
        assert_eq!(find(&b, "deploy").unwrap().key, "button_one");
        assert_eq!(find(&b, "button_2").unwrap().label, "RETURN");
        assert!(find(&b, "SURVEY").is_none());
        assert!(buttons(&mission("ServerPort = 9000\n")).is_empty());
    }
}
