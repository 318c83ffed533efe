//! MOOS's text conventions, each once, with the C++ behaviour: MBUtils `isNumber`
//! ([`is_number`]), libMOOS `MOOSIsNumeric` ([`moos_is_numeric`]), `MOOSChomp`
//! ([`chomp`]), `MOOSTrimWhiteSpace` ([`trim`]), and C `atof` / `atoi` as glibc reads
//! them ([`atof`], [`atoi`]). MOOS-IvP validates numbers with `isNumber` (no exponent) almost
//! everywhere; `MOOSIsNumeric` (a character-set test) is libMOOS's, used by AppCasting.

/// MBUtils `isNumber(s)` (blanks allowed): after trimming blanks and one leading `+` (when
/// more follows), only digits, at most one `.`, and `-` signs before any digit or point;
/// at least one digit. No exponent: `1e3` is not a number to MOOS-IvP; `--5` is.
///
/// ```
/// use moos_types::text::is_number;
/// assert!(is_number(" -3.5 ") && is_number("+.5") && is_number("--5"));
/// assert!(!is_number("1e3") && !is_number("3m") && !is_number("1.2.3") && !is_number("-"));
/// ```
pub fn is_number(s: &str) -> bool {
    let t = strip_blank_ends(s);
    let t = if t.len() > 1 {
        t.strip_prefix('+').unwrap_or(t)
    } else {
        t
    };
    let (mut digits, mut points) = (0usize, 0usize);
    for b in t.bytes() {
        match b {
            b'0'..=b'9' => digits += 1,
            b'.' => {
                points += 1;
                if points > 1 {
                    return false;
                }
            }
            b'-' if digits == 0 && points == 0 => {}
            _ => return false,
        }
    }
    digits > 0
}

/// MBUtils `setBooleanOnString(current, s)` (case-insensitive): `true`/`yes`/`on` and
/// `false`/`no`/`off`, `toggle` flips `current`; `None` for anything else (blanks are not
/// trimmed).
///
/// ```
/// use moos_types::text::set_boolean_on_string as b;
/// assert_eq!(b(false, "Yes"), Some(true));
/// assert_eq!(b(true, "toggle"), Some(false));
/// assert_eq!(b(false, "1"), None);
/// assert_eq!(b(false, " true"), None);
/// ```
pub fn set_boolean_on_string(current: bool, s: &str) -> Option<bool> {
    match s.to_ascii_lowercase().as_str() {
        "toggle" => Some(!current),
        "on" | "true" | "yes" => Some(true),
        "off" | "false" | "no" => Some(false),
        _ => None,
    }
}

/// libMOOS `GetConfigurationParam(name, bool&)`, how MOOS core apps (pLogger, the DB) read a
/// boolean setting: `TRUE` in any case, or a `MOOSIsNumeric` value whose `atof` is above 0;
/// anything else is false (`yes` and `on` are false here).
///
/// ```
/// use moos_types::text::config_bool;
/// assert!(config_bool("True") && config_bool("1") && config_bool("2.5"));
/// assert!(!config_bool("yes") && !config_bool("0") && !config_bool("false"));
/// ```
pub fn config_bool(s: &str) -> bool {
    s.eq_ignore_ascii_case("true") || (moos_is_numeric(s) && atof(s) > 0.0)
}

/// A strict `true` / `false` (any case), as MOOS-IvP reads booleans with
/// `tolower(value) == "true"`: geometry specs (`active=`), the IvP reflector; `None`
/// otherwise.
pub fn strict_bool(s: &str) -> Option<bool> {
    if s.eq_ignore_ascii_case("true") {
        Some(true)
    } else if s.eq_ignore_ascii_case("false") {
        Some(false)
    } else {
        None
    }
}

/// `MOOSWildCmp`: case-sensitive glob where `*` matches any run (also empty) and `?` any one
/// byte.
///
/// ```
/// use moos_types::text::wildcard_match;
/// assert!(wildcard_match(b"NAV_*", b"NAV_X"));
/// assert!(wildcard_match(b"*", b""));
/// assert!(!wildcard_match(b"nav_*", b"NAV_X"));
/// ```
pub fn wildcard_match(pattern: &[u8], text: &[u8]) -> bool {
    let (mut p, mut t) = (0usize, 0usize);
    let mut star: Option<(usize, usize)> = None;
    while t < text.len() {
        if p < pattern.len() && (pattern[p] == b'?' || pattern[p] == text[t]) {
            p += 1;
            t += 1;
        } else if p < pattern.len() && pattern[p] == b'*' {
            star = Some((p, t));
            p += 1;
        } else if let Some((sp, st)) = star {
            p = sp + 1;
            t = st + 1;
            star = Some((sp, st + 1));
        } else {
            return false;
        }
    }
    pattern[p..].iter().all(|&b| b == b'*')
}

/// MOOS-IvP `parseString(s, sep)`: the pieces between separators; a separator at the very
/// end adds no empty piece, and an empty string has none.
pub fn parse_string(s: &str, sep: char) -> Vec<&str> {
    let mut pieces = Vec::new();
    let mut rest = s;
    while !rest.is_empty() {
        match rest.find(sep) {
            Some(i) => {
                pieces.push(&rest[..i]);
                rest = &rest[i + sep.len_utf8()..];
            }
            None => {
                pieces.push(rest);
                rest = "";
            }
        }
    }
    pieces
}

/// MOOS-IvP `parseStringQ(s, sep)`: as [`parse_string`], but a separator inside double
/// quotes or braces does not split.
pub fn parse_string_q(s: &str, sep: char) -> Vec<&str> {
    let (mut pieces, mut in_quotes, mut braces, mut start) = (Vec::new(), false, 0u32, 0);
    for (i, c) in s.char_indices() {
        match c {
            '"' => in_quotes = !in_quotes,
            '{' => braces += 1,
            '}' => braces = braces.saturating_sub(1),
            c if c == sep && !in_quotes && braces == 0 => {
                pieces.push(&s[start..i]);
                start = i + c.len_utf8();
            }
            _ => {}
        }
    }
    if start < s.len() {
        pieces.push(&s[start..]);
    }
    pieces
}

/// MOOS-IvP `tokStringParse(s, key, ',', '=')`: the value (blank ends stripped) of the first
/// `key=value` piece whose key (blank ends stripped) is `key`; empty when there is none, or
/// when a piece before it is not exactly one `left=right` pair.
///
/// ```
/// use moos_types::text::tok_string_parse;
/// assert_eq!(tok_string_parse("app=pHelmIvP, maxgap=2.5", "maxgap"), "2.5");
/// assert_eq!(tok_string_parse("app=pHelmIvP,junk,maxgap=2.5", "maxgap"), "");
/// ```
pub fn tok_string_parse<'a>(s: &'a str, key: &str) -> &'a str {
    for piece in parse_string_q(s, ',') {
        let parts = parse_string(piece, '=');
        if parts.len() != 2 {
            return "";
        }
        if parts[0].trim() == key {
            return parts[1].trim();
        }
    }
    ""
}

/// uPokeDB's `VAR=VALUE` (`setPoke`): with a `:=` anywhere, the text splits at it into
/// exactly two parts, blank ends stripped, and the value is a string; otherwise the variable
/// is what comes before the first `=` and the value what follows (blank ends stripped),
/// a double when MOOS reads it as a number ([`is_number`], then [`atof`]), else a string.
/// `None` without an `=` (or with more than one `:=`).
///
/// ```
/// use moos_types::{Value, text::parse_poke};
/// assert_eq!(parse_poke("DEPLOY = true"), Some(("DEPLOY", Value::from("true"))));
/// assert_eq!(parse_poke("SPEED=1.5"), Some(("SPEED", Value::Double(1.5))));
/// assert_eq!(parse_poke("ID:=42"), Some(("ID", Value::from("42"))));
/// assert_eq!(parse_poke("X=1e3"), Some(("X", Value::from("1e3"))));
/// assert_eq!(parse_poke("WPT=points=1,2"), Some(("WPT", Value::from("points=1,2"))));
/// assert_eq!(parse_poke("novalue"), None);
/// ```
pub fn parse_poke(s: &str) -> Option<(&str, crate::Value)> {
    if !s.contains('=') {
        return None;
    }
    if s.contains(":=") {
        let mut parts = s.split(":=");
        let (left, right) = (parts.next()?, parts.next()?);
        if parts.next().is_some() {
            return None;
        }
        return Some((
            strip_blank_ends(left),
            crate::Value::from(strip_blank_ends(right)),
        ));
    }
    let (left, right) = s.split_once('=')?;
    let (left, right) = (strip_blank_ends(left), strip_blank_ends(right));
    let value = if is_number(right) {
        crate::Value::Double(atof(right))
    } else {
        crate::Value::from(right)
    };
    Some((left, value))
}

/// MBUtils `stripBlankEnds`: blanks and tabs in front; blanks, tabs, NULs, carriage returns
/// and line feeds behind.
pub fn strip_blank_ends(s: &str) -> &str {
    s.trim_start_matches([' ', '\t'])
        .trim_end_matches([' ', '\t', '\0', '\r', '\n'])
}

/// `MOOSChomp(s, sep)`: everything before the first `sep` is returned and removed from `s`
/// together with the separator; without a separator (or with an empty one) the whole of `s` is
/// returned and `s` is left empty.
pub fn chomp<'a>(s: &mut &'a str, sep: &str) -> &'a str {
    let whole: &'a str = s;
    if !sep.is_empty()
        && let Some(at) = whole.find(sep)
    {
        *s = &whole[at + sep.len()..];
        return &whole[..at];
    }
    *s = "";
    whole
}

/// The characters `MOOSTrimWhiteSpace` strips from both ends (no vertical tab, no form feed).
fn is_moos_blank(c: char) -> bool {
    matches!(c, ' ' | '\t' | '\n' | '\r')
}

/// `MOOSTrimWhiteSpace`: strips spaces, tabs, line feeds and carriage returns from both ends.
pub fn trim(s: &str) -> &str {
    s.trim_matches(is_moos_blank)
}

/// `MOOSIsNumeric`: after trimming, every character is one of `0-9 . e E - +`. The empty string
/// counts as numeric (there is no character outside the set).
pub fn moos_is_numeric(s: &str) -> bool {
    trim(s)
        .chars()
        .all(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '-' | '+'))
}

/// Where a C number conversion starts reading digits (after white space and one sign), and
/// whether the sign was `-`.
fn sign_prefix(b: &[u8]) -> (usize, bool) {
    let mut i = 0;
    while i < b.len() && is_c_space(b[i]) {
        i += 1;
    }
    let negative = b.get(i) == Some(&b'-');
    if matches!(b.get(i), Some(b'+' | b'-')) {
        i += 1;
    }
    (i, negative)
}

/// The white space C's `isspace` skips in the "C" locale.
fn is_c_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\n' | 0x0b | 0x0c | b'\r')
}

/// C `atof` (glibc `strtod` without the end pointer): leading white space, an optional sign,
/// then the longest prefix that is a decimal number, a hexadecimal number (`0x`), `inf`,
/// `infinity` or `nan`; 0 when nothing converts.
pub fn atof(s: &str) -> f64 {
    let (i, negative) = sign_prefix(s.as_bytes());
    let rest = &s[i..];
    let magnitude = unsigned_float(rest).unwrap_or(0.0);
    if negative { -magnitude } else { magnitude }
}

/// The unsigned part of [`atof`]; `None` when no conversion can be made.
fn unsigned_float(s: &str) -> Option<f64> {
    // The first (up to) eight bytes, when they end on a character boundary, compared without
    // a lower-cased copy.
    let head = s.get(..8.min(s.len())).unwrap_or("").as_bytes();
    let starts = |word: &[u8]| head.get(..3).is_some_and(|h| h.eq_ignore_ascii_case(word));
    if starts(b"inf") {
        return Some(f64::INFINITY);
    }
    if starts(b"nan") {
        return Some(f64::NAN);
    }
    let b = s.as_bytes();
    if b.len() >= 2 && b[0] == b'0' && (b[1] == b'x' || b[1] == b'X') {
        if let Some(v) = hex_float(&s[2..]) {
            return Some(v);
        }
        // "0x" with no hexadecimal digit after it: strtod converts the leading "0".
        return Some(0.0);
    }
    let mut i = 0;
    let mut digits = 0;
    while i < b.len() && b[i].is_ascii_digit() {
        i += 1;
        digits += 1;
    }
    if i < b.len() && b[i] == b'.' {
        i += 1;
        while i < b.len() && b[i].is_ascii_digit() {
            i += 1;
            digits += 1;
        }
    }
    if digits == 0 {
        return None;
    }
    let mantissa_end = i;
    if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
        let mut j = i + 1;
        if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
            j += 1;
        }
        let exp_digits_start = j;
        while j < b.len() && b[j].is_ascii_digit() {
            j += 1;
        }
        if j > exp_digits_start {
            i = j;
        }
    }
    let text = &s[..i];
    // Rust's parser accepts "5.", ".5" and exponents; a mantissa alone is always valid.
    text.parse::<f64>()
        .ok()
        .or_else(|| s[..mantissa_end].parse::<f64>().ok())
}

/// A hexadecimal float body (after `0x`): hex digits, an optional fraction, an optional binary
/// exponent `p[+-]digits`. `None` when there is no hex digit.
fn hex_float(s: &str) -> Option<f64> {
    let b = s.as_bytes();
    let mut i = 0;
    let mut value = 0.0f64;
    let mut digits = 0;
    while i < b.len() && b[i].is_ascii_hexdigit() {
        value = value * 16.0 + f64::from((b[i] as char).to_digit(16).unwrap_or(0));
        i += 1;
        digits += 1;
    }
    let mut scale = 0i32;
    if i < b.len() && b[i] == b'.' {
        i += 1;
        while i < b.len() && b[i].is_ascii_hexdigit() {
            value = value * 16.0 + f64::from((b[i] as char).to_digit(16).unwrap_or(0));
            scale -= 4;
            i += 1;
            digits += 1;
        }
    }
    if digits == 0 {
        return None;
    }
    if i < b.len() && (b[i] == b'p' || b[i] == b'P') {
        let mut j = i + 1;
        let mut neg = false;
        if j < b.len() && (b[j] == b'+' || b[j] == b'-') {
            neg = b[j] == b'-';
            j += 1;
        }
        let start = j;
        let mut exp: i32 = 0;
        while j < b.len() && b[j].is_ascii_digit() {
            exp = exp
                .saturating_mul(10)
                .saturating_add(i32::from(b[j] - b'0'));
            j += 1;
        }
        if j > start {
            scale = scale.saturating_add(if neg { -exp } else { exp });
        }
    }
    Some(value * 2f64.powi(scale))
}

/// C `atoi` as glibc does it, `(int) strtol(s, NULL, 10)`: leading white space, an optional
/// sign, decimal digits; an out-of-range value saturates to the 64-bit `long` range and is then
/// truncated to 32 bits; 0 when nothing converts.
pub fn atoi(s: &str) -> i32 {
    let b = s.as_bytes();
    let (mut i, negative) = sign_prefix(b);
    let mut value: i128 = 0;
    while i < b.len() && b[i].is_ascii_digit() {
        value = (value * 10 + i128::from(b[i] - b'0')).min(i128::from(i64::MAX) + 1);
        i += 1;
    }
    if negative {
        value = -value;
    }
    let long = value.clamp(i128::from(i64::MIN), i128::from(i64::MAX)) as i64;
    long as i32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chomp_splits_at_the_first_separator_or_takes_everything() {
        let mut s = "a!@b!@#c";
        assert_eq!(chomp(&mut s, "!@#"), "a!@b");
        assert_eq!(s, "c");
        assert_eq!(chomp(&mut s, "!@#"), "c");
        assert_eq!(s, "");
        let mut t = "x=1=2";
        assert_eq!(chomp(&mut t, "="), "x");
        assert_eq!(t, "1=2");
        let mut u = "abc";
        assert_eq!(chomp(&mut u, ""), "abc");
        assert_eq!(u, "");
    }

    #[test]
    fn trim_strips_only_the_four_moos_blanks() {
        assert_eq!(trim(" \t\r\n a b \n"), "a b");
        assert_eq!(trim("\x0ba\x0c"), "\x0ba\x0c");
        assert_eq!(trim("   "), "");
    }

    #[test]
    fn is_numeric_is_a_character_set_test() {
        assert!(moos_is_numeric(" 12.5 "));
        assert!(moos_is_numeric(""));
        assert!(moos_is_numeric("1.2.3e--"));
        assert!(!moos_is_numeric("0x10"));
        assert!(!moos_is_numeric("1 2"));
        assert!(!moos_is_numeric("inf"));
    }

    #[test]
    fn atof_takes_the_longest_number_prefix() {
        assert_eq!(atof("3.0"), 3.0);
        assert_eq!(atof("  -2.5xyz"), -2.5);
        assert_eq!(atof("1.2.3"), 1.2);
        assert_eq!(atof("1e3"), 1000.0);
        assert_eq!(atof("1e"), 1.0);
        assert_eq!(atof("1e+"), 1.0);
        assert_eq!(atof(".5"), 0.5);
        assert_eq!(atof("5."), 5.0);
        assert_eq!(atof("abc"), 0.0);
        assert_eq!(atof(""), 0.0);
        assert_eq!(atof("-"), 0.0);
        assert_eq!(atof("."), 0.0);
        assert_eq!(atof("0x1A"), 26.0);
        assert_eq!(atof("0x1p3"), 8.0);
        assert_eq!(atof("0x.8"), 0.5);
        assert_eq!(atof("0xg"), 0.0);
        assert_eq!(atof("1e999"), f64::INFINITY);
        assert_eq!(atof("-Infinity"), f64::NEG_INFINITY);
        assert!(atof("nan").is_nan());
    }

    #[test]
    fn atoi_reads_a_decimal_prefix_and_wraps_like_glibc() {
        assert_eq!(atoi("42"), 42);
        assert_eq!(atoi(" -7x"), -7);
        assert_eq!(atoi("1e3"), 1);
        assert_eq!(atoi("2.9"), 2);
        assert_eq!(atoi("+"), 0);
        assert_eq!(atoi(""), 0);
        // 2^32 + 5 fits a long and truncates to 5.
        assert_eq!(atoi("4294967301"), 5);
        // Beyond a long: LONG_MAX, whose low 32 bits are all ones.
        assert_eq!(atoi("99999999999999999999999"), -1);
        assert_eq!(atoi("-99999999999999999999999"), 0);
    }
}
