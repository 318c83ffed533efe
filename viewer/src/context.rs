//! The pMarineViewer block's mouse context pokes: `left_context[KEY] = VAR = value` and
//! `right_context[KEY] = ...` (no `[KEY]`: `any_left` / `any_right`, posted on every click
//! of that side), and their macros, read from pMarineViewer's source (PMV_MOOSApp.cpp
//! `getContextKey`, PMV_Viewer.cpp `handleMouseClick`): in the value `$(XPOS)`/`$(YPOS)`
//! (the click, one decimal, trailing zeros trimmed), `$(X)`/`$(Y)` (no decimals), `$(IX)`
//! (a per-side click counter), `$(BIX)` (a counter over both sides), `$(UTC)`, `$(HDG)` (from
//! the active vehicle to the click, degrees), `$(LAT)`/`$(LON)` (the click on the mission's
//! LatOrigin/LongOrigin grid, eight decimals), `$(VNAME)`/`$(UP_VNAME)` (the active
//! vehicle) and `$(VNAME_CLOSEST)`/`$(UP_VNAME_CLOSEST)` (the vehicle nearest the click),
//! also in the variable's name. A value that is a number is posted as a double. Without an
//! origin, a click whose pokes use `$(LAT)`/`$(LON)` is refused (pMarineViewer posts nothing
//! when the click cannot be converted).

use mission::moos::MissionFile;
use moos_types::Value;
use serde_json::{Value as Json, json};

/// Which mouse button a context poke belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// `left_context`.
    Left,
    /// `right_context`.
    Right,
}

impl Side {
    /// `left` or `right`.
    pub fn as_str(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }
}

/// One configured context posting.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ContextPoke {
    /// The mouse side.
    pub side: Side,
    /// The menu key (`any_left`/`any_right` without brackets).
    pub key: String,
    /// The variable, macros unexpanded.
    pub var: String,
    /// The value, macros unexpanded.
    pub value: String,
}

/// Where and by whom a context poke is made.
#[derive(Debug, Clone, PartialEq)]
pub struct Click {
    /// Local x of the click, metres.
    pub x: f64,
    /// Local y of the click, metres.
    pub y: f64,
    /// The active vehicle, with its position if known.
    pub vname: String,
    /// The active vehicle's position.
    pub vpos: Option<(f64, f64)>,
    /// The side's click counter (`$(IX)`).
    pub ix: u64,
    /// The counter over both sides (`$(BIX)`).
    pub bix: u64,
    /// MOOS time (`$(UTC)`).
    pub utc: f64,
    /// The click's latitude and longitude, degrees (`$(LAT)`, `$(LON)`), when the mission
    /// has an origin.
    pub lat_lon: Option<(f64, f64)>,
    /// The vehicle nearest the click (`$(VNAME_CLOSEST)`), empty when none is known.
    pub closest: String,
}

/// The key of a `left_context[...]`/`right_context[...]` parameter, or `None` when the
/// parameter is neither or is malformed.
fn context_key(param: &str) -> Option<(Side, String)> {
    let lower = param.trim().to_ascii_lowercase();
    let (side, rest, any) = if let Some(r) = lower.strip_prefix("left_context") {
        (
            Side::Left,
            &param.trim()[param.trim().len() - r.len()..],
            "any_left",
        )
    } else if let Some(r) = lower.strip_prefix("right_context") {
        (
            Side::Right,
            &param.trim()[param.trim().len() - r.len()..],
            "any_right",
        )
    } else {
        return None;
    };
    if rest.is_empty() {
        return Some((side, any.to_string()));
    }
    let inner = rest.strip_prefix('[')?.strip_suffix(']')?;
    let key = if inner.is_empty() { any } else { inner };
    Some((side, key.to_string()))
}

/// The context pokes of the mission's pMarineViewer block, in order.
pub fn context_pokes(m: &MissionFile) -> Vec<ContextPoke> {
    let Some(block) = m.process("pMarineViewer") else {
        return Vec::new();
    };
    block
        .entries
        .iter()
        .filter_map(|p| {
            let (side, key) = context_key(&p.key)?;
            let (var, value) = p.value.split_once('=')?;
            let (var, value) = (var.trim(), value.trim());
            (!var.is_empty()).then(|| ContextPoke {
                side,
                key,
                var: var.to_string(),
                value: value.to_string(),
            })
        })
        .collect()
}

fn expand(s: &str, name: &str, with: &str) -> String {
    s.replace(&format!("$({name})"), with)
}

/// `doubleToStringX(v, 1)`: one decimal, trailing zeros and point trimmed.
fn one_decimal(v: f64) -> String {
    let s = format!("{v:.1}");
    let s = s.strip_suffix(".0").unwrap_or(&s).to_string();
    if s == "-0" { "0".to_string() } else { s }
}

impl ContextPoke {
    /// The posting for a click: the variable and value with their macros expanded.
    pub fn expand(&self, c: &Click) -> (String, Value) {
        let up = c.vname.to_ascii_uppercase();
        let up_closest = c.closest.to_ascii_uppercase();
        // The `_CLOSEST` names first: `$(VNAME)` is not a part of `$(VNAME_CLOSEST)`, but
        // keep the order pMarineViewer uses.
        let names = |s: &str| {
            let s = expand(s, "VNAME_CLOSEST", &c.closest);
            let s = expand(&s, "UP_VNAME_CLOSEST", &up_closest);
            expand(&expand(&s, "VNAME", &c.vname), "UP_VNAME", &up)
        };
        let var = names(&self.var);
        let hdg = c.vpos.map_or(0.0, |(vx, vy)| {
            let a = (c.x - vx).atan2(c.y - vy).to_degrees();
            if a < 0.0 { a + 360.0 } else { a }
        });
        let mut v = self.value.clone();
        for (name, with) in [
            ("XPOS", one_decimal(c.x)),
            ("X", format!("{:.0}", c.x)),
            ("YPOS", one_decimal(c.y)),
            ("Y", format!("{:.0}", c.y)),
            ("IX", c.ix.to_string()),
            ("BIX", c.bix.to_string()),
            ("UTC", format!("{:.3}", c.utc)),
            ("HDG", format!("{hdg:.2}")),
        ] {
            v = expand(&v, name, &with);
        }
        if let Some((lat, lon)) = c.lat_lon {
            v = expand(&v, "LAT", &format!("{lat:.8}"));
            v = expand(&v, "LON", &format!("{lon:.8}"));
        }
        let v = names(&v);
        let value = match v.trim().parse::<f64>() {
            Ok(d) if moos_types::text::is_number(v.trim()) => Value::Double(d),
            _ => Value::text(v.trim_matches('"').to_string()),
        };
        (var, value)
    }

    /// True when the value uses `$(LAT)` or `$(LON)` (it needs the mission's origin).
    pub fn needs_lat_lon(&self) -> bool {
        self.value.contains("$(LAT)") || self.value.contains("$(LON)")
    }

    /// Whether a click on `side` with menu key `key` posts this (the key itself, or the
    /// side's `any_*` pokes).
    pub fn matches(&self, side: Side, key: &str) -> bool {
        self.side == side
            && (self.key == key
                || self.key
                    == match side {
                        Side::Left => "any_left",
                        Side::Right => "any_right",
                    })
    }

    /// The page's view: `{"side","key","var","value"}`.
    pub fn to_json(&self) -> Json {
        json!({"side": self.side.as_str(), "key": self.key, "var": self.var, "value": self.value})
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mission(text: &str) -> MissionFile {
        let src = mission::source::SourceMap::from_text("m.moos", text);
        mission::moos::parse_moos(&src).value
    }

    #[test]
    fn context_pokes_are_read_and_expanded_as_pmarineviewer_does() {
        let m = mission(
            "ProcessConfig = pMarineViewer\n{\n  \
             left_context[survey-point] = SURVEY_UPDATES = points = vname=$(VNAME), x=$(XPOS), y=$(YPOS)\n  \
             left_context[survey-point] = SURVEY = true\n  \
             right_context[return] = RETURN_$(UP_VNAME) = true\n  \
             right_context = CLICKS = $(IX)\n  \
             right_context[bad = X = 1\n}\n",
        );
        let c = context_pokes(&m);
        assert_eq!(c.len(), 4, "{c:?}");
        assert_eq!(c[0].key, "survey-point");
        assert_eq!(c[0].var, "SURVEY_UPDATES");
        assert_eq!(c[3].key, "any_right");
        let click = Click {
            x: 12.34,
            y: -7.0,
            vname: "abe".into(),
            vpos: Some((12.34, -17.0)),
            ix: 3,
            bix: 5,
            utc: 100.0,
            lat_lon: None,
            closest: String::new(),
        };
        assert_eq!(
            c[0].expand(&click),
            (
                "SURVEY_UPDATES".to_string(),
                Value::text("points = vname=abe, x=12.3, y=-7")
            )
        );
        assert_eq!(c[1].expand(&click).1, Value::text("true"));
        assert_eq!(c[2].expand(&click).0, "RETURN_ABE");
        assert_eq!(c[3].expand(&click).1, Value::Double(3.0));
        assert!(
            c[3].matches(Side::Right, "return"),
            "any_right goes with every key"
        );
        assert!(c[2].matches(Side::Right, "return"));
        assert!(!c[2].matches(Side::Left, "return"));
        assert!(!c[0].matches(Side::Left, "return"));
    }

    #[test]
    fn lat_lon_and_closest_vehicle_are_expanded() {
        let m = mission(
            "ProcessConfig = pMarineViewer\n{\n  \
             left_context[mark] = MARK_$(UP_VNAME_CLOSEST) = lat=$(LAT),lon=$(LON),near=$(VNAME_CLOSEST),by=$(VNAME)\n}\n",
        );
        let c = context_pokes(&m);
        assert!(c[0].needs_lat_lon());
        let click = Click {
            x: 1.0,
            y: 2.0,
            vname: "abe".into(),
            vpos: None,
            ix: 0,
            bix: 0,
            utc: 0.0,
            lat_lon: Some((43.825300001, -70.3304)),
            closest: "ben".into(),
        };
        assert_eq!(
            c[0].expand(&click),
            (
                "MARK_BEN".to_string(),
                Value::text("lat=43.82530000,lon=-70.33040000,near=ben,by=abe")
            )
        );
    }
}
