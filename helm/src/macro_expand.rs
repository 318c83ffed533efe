//! Macro expansion in flag values (reference §4.5, MOOS `IvPBehavior::expandMacros`): both
//! `$[NAME]` and `$(NAME)` forms; unknown macros are left as written.

/// Appends `text` to `out` with every `$[NAME]` / `$(NAME)` for which `lookup` appends a value
/// replaced by that value. `lookup(name, out)` returns false for names it does not know.
///
/// ```
/// let mut out = String::new();
/// helm::macro_expand::expand("x=$[OSX],who=$(OWNSHIP),$[NOPE]", &mut out, |n, o| match n {
///     "OSX" => { o.push_str("12.5"); true }
///     "OWNSHIP" => { o.push_str("abe"); true }
///     _ => false,
/// });
/// assert_eq!(out, "x=12.5,who=abe,$[NOPE]");
/// ```
pub fn expand(text: &str, out: &mut String, mut lookup: impl FnMut(&str, &mut String) -> bool) {
    let mut rest = text;
    while let Some(at) = rest.find('$') {
        out.push_str(&rest[..at]);
        let tail = &rest[at..];
        let close = match tail.as_bytes().get(1) {
            Some(b'[') => Some(']'),
            Some(b'(') => Some(')'),
            _ => None,
        };
        if let Some(close) = close
            && let Some(end) = tail[2..].find(close)
        {
            let name = &tail[2..2 + end];
            let valid =
                !name.is_empty() && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_');
            let mark = out.len();
            if valid && lookup(name, out) {
                rest = &tail[2 + end + 1..];
                continue;
            }
            out.truncate(mark);
            out.push_str(&tail[..2 + end + 1]);
            rest = &tail[2 + end + 1..];
            continue;
        }
        out.push('$');
        rest = &tail[1..];
    }
    out.push_str(rest);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn both_forms_and_leftovers() {
        let mut out = String::new();
        expand("$[A]$(A)$[A)$ $(B)", &mut out, |n, o| {
            if n == "A" {
                o.push('1');
                true
            } else {
                false
            }
        });
        assert_eq!(out, "11$[A)$ $(B)");
    }
}
