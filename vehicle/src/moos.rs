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

/// MOOS-IvP's string splitting (`parseString`, `parseStringQ`, `tokStringParse`): the
/// workspace's one definition of each.
pub use moos_types::text::{parse_string, parse_string_q, tok_string_parse};

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
