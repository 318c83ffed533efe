//! MOOS colour names and specs (`lib_mbutil` `isColor` / `colorParse` at a2a9b716).
//!
//! A colour is a name from MOOS's table (case-insensitive, `_` ignored: `light_blue`), a
//! `grey05`..`grey95` / `gray05`..`gray95` level, `hex:rr,gg,bb`, or three numbers in 0..1
//! separated by `,`, `%`, `$`, `#` or `:`. `black`, `empty`, `off` and `invisible` are colours
//! too. Anything that parses to pure black other than those four is not a colour (MOOS reads
//! a failed parse as black).

use crate::text::is_number;

/// MOOS's named colours with their 24-bit RGB value, sorted by name for binary search.
/// (`tomatao` is spelt as MOOS spells it: `tomato` is not a MOOS colour.)
const NAMED: &[(&str, u32)] = &[
    ("antiquewhite", 0xfaebd7),
    ("aqua", 0x00ffff),
    ("aquamarine", 0x7fffd4),
    ("azure", 0xf0ffff),
    ("beige", 0xf5f5dc),
    ("bisque", 0xffe4c4),
    ("black", 0x000000),
    ("blanchedalmond", 0xffebcd),
    ("blue", 0x0000ff),
    ("blueviolet", 0x8a2be2),
    ("brown", 0xa52a2a),
    ("burlywood", 0xdeb887),
    ("cadetblue", 0x5f9ea0),
    ("chartreuse", 0x7fff00),
    ("chocolate", 0xd2691e),
    ("coral", 0xff7f50),
    ("cornflowerblue", 0x6495ed),
    ("cornsilk", 0xfff8dc),
    ("crimson", 0xde143c),
    ("cyan", 0x00ffff),
    ("darkblue", 0x00008b),
    ("darkcyan", 0x008b8b),
    ("darkgoldenrod", 0xb8860b),
    ("darkgray", 0xa9a9a9),
    ("darkgreen", 0x006400),
    ("darkkhaki", 0xbdb76b),
    ("darkmagenta", 0x8b008b),
    ("darkolivegreen", 0x556b2f),
    ("darkorange", 0xff8c00),
    ("darkorchid", 0x9932cc),
    ("darkred", 0x8b0000),
    ("darksalmon", 0xe9967a),
    ("darkseagreen", 0x8fbc8f),
    ("darkslateblue", 0x483d8b),
    ("darkslategray", 0x2f4f4f),
    ("darkturquoise", 0x00ced1),
    ("darkviolet", 0x9400d3),
    ("deeppink", 0xff1493),
    ("deepskyblue", 0x00bfff),
    ("dimgray", 0x696969),
    ("dodgerblue", 0x1e90ff),
    ("firebrick", 0xb22222),
    ("floralwhite", 0xfffaf0),
    ("forestgreen", 0x228b22),
    ("fuchsia", 0xff00ff),
    ("gainsboro", 0xdcdcdc),
    ("ghostwhite", 0xf8f8ff),
    ("gold", 0xffd700),
    ("goldenrod", 0xdaa520),
    ("gray", 0x808080),
    ("green", 0x008000),
    ("greenyellow", 0xadff2f),
    ("hillside", 0xd8d0a4),
    ("honeydew", 0xf0fff0),
    ("hotpink", 0xff69b4),
    ("indianred", 0xcd5c5c),
    ("indigo", 0x4b0082),
    ("ivory", 0xfffff0),
    ("khaki", 0xf0e68c),
    ("lavender", 0xe6e6fa),
    ("lavenderblush", 0xfff0f5),
    ("lawngreen", 0x7cfc00),
    ("lemonchiffon", 0xfffacd),
    ("lightblue", 0xadd8e6),
    ("lightcoral", 0xf08080),
    ("lightcyan", 0xe0ffff),
    ("lightgoldenrod", 0xfafad2),
    ("lightgray", 0xd3d3d3),
    ("lightgreen", 0x90ee90),
    ("lightpink", 0xffb6c1),
    ("lightsalmon", 0xffa07a),
    ("lightseagreen", 0x20b2aa),
    ("lightskyblue", 0x87cefa),
    ("lightslategray", 0x778899),
    ("lightsteelblue", 0xb0c4de),
    ("lightyellow", 0xffffe0),
    ("lime", 0x00ff00),
    ("limegreen", 0x32cd32),
    ("linen", 0xfaf0e6),
    ("macbeige", 0xdfdbc3),
    ("macpurple", 0x493d78),
    ("magenta", 0xff00ff),
    ("maroon", 0x800000),
    ("mediumblue", 0x0000cd),
    ("mediumprchid", 0xba55d3),
    ("mediumseagreen", 0x3cb371),
    ("mediumslateblue", 0x7b68ee),
    ("mediumspringgreen", 0x00fa9a),
    ("mediumturquoise", 0x48d1cc),
    ("mediumvioletred", 0xc71585),
    ("midnightblue", 0x191970),
    ("mintcream", 0xf5fffa),
    ("mistyrose", 0xffe4e1),
    ("moccasin", 0xffe4b5),
    ("navajowhite", 0xffdead),
    ("navy", 0x000080),
    ("oldlace", 0xfdf5e6),
    ("olive", 0x808000),
    ("olivedrab", 0x6b8e23),
    ("orange", 0xffa500),
    ("orangered", 0xff4500),
    ("orchid", 0xda70d6),
    ("oxfordindigo", 0x415798),
    ("palegreen", 0x98fb98),
    ("paleturquoise", 0xafeeee),
    ("palevioletred", 0xdb7093),
    ("papayawhip", 0xffefd5),
    ("peachpuff", 0xffdab9),
    ("pelegoldenrod", 0xeee8aa),
    ("peru", 0xcd853f),
    ("pink", 0xffc0cb),
    ("plum", 0xdda0dd),
    ("powderblue", 0xb0e0e6),
    ("purple", 0x800080),
    ("red", 0xff0000),
    ("rosybrown", 0xbc8f8f),
    ("royalblue", 0x4169e1),
    ("saddlebrowm", 0x8b4513),
    ("salmon", 0xfa8072),
    ("sandybrown", 0xf4a460),
    ("seagreen", 0x2e8b57),
    ("seashell", 0xfff5ee),
    ("sienna", 0xa0522d),
    ("silver", 0xc0c0c0),
    ("skyblue", 0x87ceeb),
    ("slateblue", 0x6a5acd),
    ("slategray", 0x708090),
    ("snow", 0xfffafa),
    ("springgreen", 0x00ff7f),
    ("steelblue", 0x4682b4),
    ("tan", 0xd2b48c),
    ("teal", 0x008080),
    ("thistle", 0xd8bfd8),
    ("tomatao", 0xff6347),
    ("turquoise", 0x40e0d0),
    ("violet", 0xee82ee),
    ("vlightpink", 0xffd6e1),
    ("wheat", 0xf5deb3),
    ("white", 0xffffff),
    ("whitesmoke", 0xf5f5f5),
    ("yellow", 0xffff00),
    ("yellowgreen", 0x9acd32),
];

/// Whether `s` names a colour MOOS accepts (MOOS `isColor`).
///
/// ```
/// use geometry::color::is_color;
/// assert!(is_color("Light_Blue"));
/// assert!(is_color("hex:ff,80,00"));
/// assert!(is_color("0.2,0.4,0.6"));
/// assert!(is_color("invisible"));
/// assert!(!is_color("bluish"));
/// ```
pub fn is_color(s: &str) -> bool {
    let lower = s.to_ascii_lowercase();
    if matches!(lower.as_str(), "black" | "empty" | "off" | "invisible") {
        return true;
    }
    color_rgb(s).is_some_and(|rgb| rgb != [0.0; 3])
}

/// The RGB fractions (each 0..1) of a colour spec, as MOOS `colorParse` reads it; `None`
/// where MOOS's parse fails (which MOOS itself reads as black).
///
/// ```
/// assert_eq!(geometry::color::color_rgb("red"), Some([1.0, 0.0, 0.0]));
/// assert_eq!(geometry::color::color_rgb("gray50"), Some([0.5, 0.5, 0.5]));
/// ```
pub fn color_rgb(s: &str) -> Option<[f64; 3]> {
    if s.starts_with("hex:") {
        return hex_rgb(s);
    }
    if s.contains([',', '%', '$', '#', ':']) {
        return dec_rgb(s);
    }
    let name: String = s
        .trim()
        .chars()
        .filter(|&c| c != '_')
        .map(|c| c.to_ascii_lowercase())
        .collect();
    if let Some(level) = grey_level(&name) {
        return Some([level; 3]);
    }
    let i = NAMED
        .binary_search_by(|(n, _)| n.cmp(&name.as_str()))
        .ok()?;
    let v = NAMED[i].1;
    let byte = |shift: u32| f64::from((v >> shift) & 0xff) / 255.0;
    Some([byte(16), byte(8), byte(0)])
}

/// `grey05`..`grey95` and `gray05`..`gray95` in steps of 5: the level as a fraction.
fn grey_level(name: &str) -> Option<f64> {
    let digits = name
        .strip_prefix("grey")
        .or_else(|| name.strip_prefix("gray"))?;
    if digits.len() != 2 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    let n: u32 = digits.parse().ok()?;
    (n.is_multiple_of(5) && (5..=95).contains(&n)).then(|| f64::from(n) / 100.0)
}

/// `hex:rr,gg,bb` (also `hex,rr,gg,bb`): three two-digit hex bytes, blanks ignored.
fn hex_rgb(s: &str) -> Option<[f64; 3]> {
    let body: String = s
        .to_ascii_lowercase()
        .replace("hex:", "")
        .replace("hex,", "")
        .chars()
        .filter(|&c| c != ' ' && c != '\t')
        .collect();
    if !body
        .bytes()
        .all(|b| b.is_ascii_digit() || b == b',' || (b'a'..=b'f').contains(&b))
    {
        return None;
    }
    let parts: Vec<&str> = body.split(',').collect();
    if parts.len() != 3 || parts.iter().any(|p| p.len() != 2) {
        return None;
    }
    let mut rgb = [0.0; 3];
    for (out, p) in rgb.iter_mut().zip(&parts) {
        *out = f64::from(u8::from_str_radix(p, 16).ok()?) / 255.0;
    }
    Some(rgb)
}

/// Three numbers split on the first separator found of `,` `%` `$` `#` `:`, each clipped to 0..1.
fn dec_rgb(s: &str) -> Option<[f64; 3]> {
    let sep = [',', '%', '$', '#', ':']
        .into_iter()
        .find(|&c| s.contains(c))?;
    // MOOS `parseString`: a trailing separator adds no empty piece.
    let parts: Vec<&str> = s
        .strip_suffix(sep)
        .unwrap_or(s)
        .split(sep)
        .map(str::trim)
        .collect();
    if parts.len() != 3 || !parts.iter().all(|p| is_number(p)) {
        return None;
    }
    let mut rgb = [0.0; 3];
    for (out, p) in rgb.iter_mut().zip(&parts) {
        *out = p.parse::<f64>().ok()?.clamp(0.0, 1.0);
    }
    Some(rgb)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_sorted_for_binary_search() {
        assert!(NAMED.windows(2).all(|w| w[0].0 < w[1].0));
    }

    #[test]
    fn names_levels_and_specs() {
        assert_eq!(color_rgb("light_blue"), color_rgb("LightBlue"));
        assert!(color_rgb("lightblue").is_some());
        assert!(is_color("grey05") && is_color("gray95"));
        assert!(!is_color("grey07") && !is_color("grey100") && !is_color("grey00"));
        assert!(is_color("tomatao") && !is_color("tomato"));
        assert_eq!(color_rgb("hex:00,80,ff").map(|c| c[1]), Some(128.0 / 255.0));
        assert!(!is_color("hex:00,00,00"));
        assert!(!is_color("hex:0,80,ff") && !is_color("hex:00,80,fg"));
        assert_eq!(color_rgb("2,-1,0.5"), Some([1.0, 0.0, 0.5]));
        assert!(!is_color("0,0,0") && !is_color("1,x,0") && !is_color("1,1"));
        assert!(is_color("0.5:0.5:0.5") && is_color("0.1%0.2%0.3") && is_color("1,1,1,"));
        assert!(is_color("OFF") && is_color("Empty") && !is_color(""));
    }
}
