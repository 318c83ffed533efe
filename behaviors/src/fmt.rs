//! Number formatting as MOOS-IvP writes numbers (`doubleToString`, `doubleToStringX`).

use std::fmt::Write as _;

/// Appends `v` with `prec` decimals (MOOS `doubleToString(v, prec)`).
///
/// ```
/// let mut s = String::new();
/// behaviors::fmt::fixed(&mut s, 100.0, 5);
/// assert_eq!(s, "100.00000");
/// ```
pub fn fixed(out: &mut String, v: f64, prec: usize) {
    if fixed_fast(out, v, prec) {
        return;
    }
    let start = out.len();
    write!(out, "{v:.prec$}").ok();
    if out[start..].starts_with('-') && out[start + 1..].bytes().all(|b| b == b'0' || b == b'.') {
        out.remove(start);
    }
}

/// Appends `v` with `prec` decimals exactly as Rust's `format!("{v:.prec$}")` does (a
/// negative value that rounds to zero keeps its sign, unlike [`fixed`]).
///
/// ```
/// let mut s = String::new();
/// behaviors::fmt::std_fixed(&mut s, -0.2, 0);
/// s.push(',');
/// behaviors::fmt::std_fixed(&mut s, 12.5, 0);
/// assert_eq!(s, format!("{:.0},{:.0}", -0.2, 12.5));
/// ```
pub fn std_fixed(out: &mut String, v: f64, prec: usize) {
    let start = out.len();
    fixed(out, v, prec);
    if v.is_sign_negative() && !v.is_nan() && !out[start..].starts_with('-') {
        out.insert(start, '-');
    }
}

/// Appends `v` with at most `prec` decimals, trailing zeros and a trailing `.` removed
/// (MOOS `doubleToStringX(v, prec)`).
///
/// ```
/// let mut s = String::new();
/// behaviors::fmt::compact(&mut s, 2.50, 2);
/// s.push(',');
/// behaviors::fmt::compact(&mut s, -0.001, 2);
/// assert_eq!(s, "2.5,0");
/// ```
pub fn compact(out: &mut String, v: f64, prec: usize) {
    let start = out.len();
    fixed(out, v, prec);
    if out[start..].contains('.') {
        let keep = out[start..]
            .trim_end_matches('0')
            .trim_end_matches('.')
            .len();
        out.truncate(start + keep);
    }
    if &out[start..] == "-0" {
        out.truncate(start);
        out.push('0');
    }
}

/// [`compact`] into a new string.
pub fn compact_string(v: f64, prec: usize) -> String {
    let mut s = String::new();
    compact(&mut s, v, prec);
    s
}

const POW10: [u64; 7] = [1, 10, 100, 1_000, 10_000, 100_000, 1_000_000];

/// Integer fast path of [`fixed`] for small magnitudes; false when the value is too large, not
/// finite, or too close to a rounding tie to decide without the exact decimal expansion.
fn fixed_fast(out: &mut String, v: f64, prec: usize) -> bool {
    let Some(&scale) = POW10.get(prec) else {
        return false;
    };
    let s = v.abs() * scale as f64;
    // Below 2^30 the product's rounding error is far below the 1e-6 tie margin.
    if !s.is_finite() || s >= 1_073_741_824.0 {
        return false;
    }
    let fl = s.floor();
    let frac = s - fl;
    if (frac - 0.5).abs() < 1e-6 {
        return false;
    }
    let n = fl as u64 + u64::from(frac > 0.5);
    if v < 0.0 && n != 0 {
        out.push('-');
    }
    digits(out, n / scale, 1);
    if prec > 0 {
        out.push('.');
        digits(out, n % scale, prec);
    }
    true
}

/// Appends `n` in decimal, zero-padded to at least `min` digits, without the `core::fmt`
/// machinery (this runs for most numbers the helm posts).
fn digits(out: &mut String, mut n: u64, min: usize) {
    let mut buf = [b'0'; 20];
    let mut i = buf.len();
    while n > 0 {
        i -= 1;
        buf[i] = b'0' + (n % 10) as u8;
        n /= 10;
    }
    let start = i.min(buf.len().saturating_sub(min.max(1)));
    // Only ASCII digits were written.
    out.push_str(std::str::from_utf8(&buf[start..]).unwrap_or("0"));
}

/// Appends an unsigned integer in decimal (`n.to_string()` without the allocation).
///
/// ```
/// let mut s = String::from("pcs=");
/// behaviors::fmt::uint(&mut s, 1207);
/// behaviors::fmt::uint(&mut s, 0);
/// assert_eq!(s, "pcs=12070");
/// ```
pub fn uint(out: &mut String, n: u64) {
    digits(out, n, 1);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_path_agrees_with_exact_formatting() {
        let cases = [
            0.0, -0.0, 1.0, -1.0, 0.125, 2.675, 1.005, 99.995, 1234.5678, -0.004, -0.006, 100.0,
            1e-7, 12345678.9, 3e12,
        ];
        for v in cases {
            for prec in 0..7 {
                let mut fast = String::new();
                fixed(&mut fast, v, prec);
                let mut exact = format!("{v:.prec$}");
                if exact.starts_with('-') && exact[1..].bytes().all(|b| b == b'0' || b == b'.') {
                    exact.remove(0);
                }
                assert_eq!(fast, exact, "{v} with {prec} decimals");
            }
        }
    }

    #[test]
    fn integers_match_std_formatting() {
        for n in [0u64, 1, 9, 10, 99, 100, 12345, u64::MAX] {
            let mut s = String::new();
            uint(&mut s, n);
            assert_eq!(s, n.to_string());
        }
    }

    #[test]
    fn std_fixed_is_std_formatting() {
        for v in [
            0.0,
            -0.0,
            -0.2,
            0.5,
            1.5,
            2.5,
            -2.5,
            1e12,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
        ] {
            for prec in 0..3 {
                let mut s = String::new();
                std_fixed(&mut s, v, prec);
                assert_eq!(s, format!("{v:.prec$}"), "{v} {prec}");
            }
        }
    }

    proptest::proptest! {
        #[test]
        fn fixed_matches_std_formatting(v in -1.0e7f64..1.0e7, prec in 0usize..7) {
            let mut fast = String::new();
            fixed(&mut fast, v, prec);
            let mut exact = format!("{v:.prec$}");
            if exact.starts_with('-') && exact[1..].bytes().all(|b| b == b'0' || b == b'.') {
                exact.remove(0);
            }
            proptest::prop_assert_eq!(fast, exact);
        }

        #[test]
        fn std_fixed_matches_std(v in -1.0e4f64..1.0e4, prec in 0usize..4) {
            let mut s = String::new();
            std_fixed(&mut s, v, prec);
            proptest::prop_assert_eq!(s, format!("{v:.prec$}"));
        }
    }
}
