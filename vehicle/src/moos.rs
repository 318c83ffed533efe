//! MOOS-facing value types shared by the app adapters, and MOOS-IvP number formatting.

/// A value arriving as MOOS mail, borrowed: the workspace's one view of a MOOS value.
pub use moos_types::ValueRef;

/// A value an app publishes: the workspace's one MOOS value type.
pub use moos_types::Value;

/// One posting an app wants published: the workspace's one posting type.
pub use moos_types::Post as Posting;

/// Finds the last posting of `var` in `postings`.
pub fn last_posting<'a>(postings: &'a [Posting], var: &str) -> Option<&'a Value> {
    postings
        .iter()
        .rev()
        .find(|p| p.key == var)
        .map(|p| &p.value)
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
/// use vehicle::moos::tok_string_parse;
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn double_x_compacts() {
        assert_eq!(moos_types::fmt::compact_string(0.0, 2), "0");
        assert_eq!(moos_types::fmt::compact_string(-0.001, 2), "0");
        assert_eq!(moos_types::fmt::compact_string(100.0, 2), "100");
        assert_eq!(moos_types::fmt::compact_string(12.34567, 2), "12.35");
        assert_eq!(moos_types::fmt::compact_string(-20.5, 2), "-20.5");
        assert_eq!(moos_types::fmt::compact_string(43.825300001, 8), "43.8253");
        assert_eq!(moos_types::fmt::compact_string(7.0, 0), "7");
    }

    #[test]
    fn moos_string_parsing() {
        assert_eq!(parse_string("a,,b,", ','), ["a", "", "b"]);
        assert_eq!(parse_string(",a", ','), ["", "a"]);
        assert!(parse_string("", ',').is_empty());
        assert_eq!(
            parse_string_q(r#"a="x,y",b={1,2},c"#, ','),
            [r#"a="x,y""#, "b={1,2}", "c"]
        );
        assert_eq!(tok_string_parse("mhash=abc-1 , utc=5", "mhash"), "abc-1");
        assert_eq!(tok_string_parse("a=1=2,mhash=x", "mhash"), "");
        assert_eq!(tok_string_parse("a=,mhash=x", "mhash"), "");
        assert_eq!(tok_string_parse("", "mhash"), "");
    }
}
