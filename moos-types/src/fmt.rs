//! Number formatting as MOOS-IvP writes numbers: `doubleToString` ([`fixed`]),
//! `doubleToStringX` ([`compact`]), `dstringCompact(doubleToString(..))`
//! ([`dstring_compact`]), C++ stream `%g` ([`g`]) and unsigned integers ([`uint`],
//! [`uint_padded`], through `itoa`). Every crate formats MOOS numbers through these.

use std::fmt::Write as _;

/// Appends `v` with `prec` decimals, as MOOS `doubleToString(v, prec)` (C `%.Nf`): a
/// negative value that rounds to zero keeps its sign (`-0.00`), `nan` and `inf` as Rust
/// writes them.
///
/// ```
/// let mut s = String::new();
/// moos_types::fmt::fixed(&mut s, 100.0, 5);
/// s.push(',');
/// moos_types::fmt::fixed(&mut s, -0.001, 2);
/// assert_eq!(s, "100.00000,-0.00");
/// ```
pub fn fixed(out: &mut String, v: f64, prec: usize) {
    if non_finite(out, v) || fixed_fast(out, v, prec) {
        return;
    }
    write!(out, "{v:.prec$}").ok();
}

/// Appends `v` as MOOS `dstringCompact(doubleToString(v, prec))`: [`fixed`], then trailing
/// zeros and a trailing point removed; unlike [`compact`] a negative value that rounds to
/// zero stays `-0`.
///
/// ```
/// let mut s = String::new();
/// moos_types::fmt::dstring_compact(&mut s, 100.0, 5);
/// s.push(',');
/// moos_types::fmt::dstring_compact(&mut s, -1e-12, 8);
/// assert_eq!(s, "100,-0");
/// ```
pub fn dstring_compact(out: &mut String, v: f64, prec: usize) {
    let start = out.len();
    fixed(out, v, prec);
    if out[start..].contains('.') {
        let keep = out[start..]
            .trim_end_matches('0')
            .trim_end_matches('.')
            .len();
        out.truncate(start + keep);
    }
}

/// Appends `v` as C `%.<sig>g` (and a C++ stream's default notation with that precision):
/// fixed when the decimal exponent is in `-4..sig`, otherwise scientific (`1.5e+20`);
/// trailing zeros and a trailing point removed; `nan`, `inf`, `-inf`.
///
/// ```
/// let mut s = String::new();
/// moos_types::fmt::g(&mut s, 1786054975.123456, 16);
/// s.push(',');
/// moos_types::fmt::g(&mut s, 1234567.0, 6);
/// assert_eq!(s, "1786054975.123456,1.23457e+06");
/// ```
pub fn g(out: &mut String, v: f64, sig: usize) {
    if non_finite(out, v) {
        return;
    }
    if v == 0.0 {
        out.push_str(if v.is_sign_negative() { "-0" } else { "0" });
        return;
    }
    let p = sig.max(1);
    if g_fast(out, v, p) {
        return;
    }
    let sci = format!("{:.*e}", p - 1, v);
    let (mant, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    if exp < -4 || exp >= p as i32 {
        out.push_str(trim_zeros(mant));
        let sign = if exp < 0 { '-' } else { '+' };
        write!(out, "e{sign}{:02}", exp.abs()).ok();
    } else {
        let decimals = (p as i32 - 1 - exp).max(0) as usize;
        let fixed = format!("{v:.decimals$}");
        out.push_str(trim_zeros(&fixed));
    }
}

/// [`g`] without `core::fmt` for `1 <= |v| < 10^min(p, 15)`: [`fixed`]'s integer path with
/// the decimals the value's integer digits leave, then trailing zeros removed; false (the
/// caller formats it exactly) when that path declines or the rounding carries into another
/// digit (`9.9999996` -> `10`), which changes the exponent `%g` picks.
fn g_fast(out: &mut String, v: f64, p: usize) -> bool {
    let a = v.abs();
    if !(1.0..1e15).contains(&a) {
        return false;
    }
    let digits = (a.trunc() as u64).ilog10() as usize + 1;
    if digits > p {
        return false;
    }
    let start = out.len();
    if !fixed_fast(out, v, p - digits) {
        return false;
    }
    let int_len = out[start..]
        .trim_start_matches('-')
        .split('.')
        .next()
        .map_or(0, str::len);
    if int_len != digits {
        out.truncate(start);
        return false;
    }
    let keep = trim_zeros(&out[start..]).len();
    out.truncate(start + keep);
    true
}

/// [`g`] into a new string (`g_string(v, 6)` is a default-formatted C++ stream's `<< v`).
pub fn g_string(v: f64, sig: usize) -> String {
    let mut s = String::new();
    g(&mut s, v, sig);
    s
}

/// `nan`, `-nan`, `inf`, `-inf` as C prints them; false for a finite value.
fn non_finite(out: &mut String, v: f64) -> bool {
    if v.is_nan() {
        out.push_str(if v.is_sign_negative() { "-nan" } else { "nan" });
        true
    } else if v.is_infinite() {
        out.push_str(if v > 0.0 { "inf" } else { "-inf" });
        true
    } else {
        false
    }
}

fn trim_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

/// Appends `v` with at most `prec` decimals, trailing zeros and a trailing `.` removed
/// (MOOS `doubleToStringX(v, prec)`).
///
/// ```
/// let mut s = String::new();
/// moos_types::fmt::compact(&mut s, 2.50, 2);
/// s.push(',');
/// moos_types::fmt::compact(&mut s, -0.001, 2);
/// assert_eq!(s, "2.5,0");
/// ```
pub fn compact(out: &mut String, v: f64, prec: usize) {
    let start = out.len();
    dstring_compact(out, v, prec);
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

/// Integer fast path of [`fixed`]; false when the value is too large, not finite, or too close
/// to a rounding tie to decide without the exact decimal expansion. The whole part and the
/// fraction are split first (both exact), so epoch times (~1.8e9 s) take it too: only the
/// fraction is scaled, and its product's rounding error stays far below the 1e-6 tie margin.
fn fixed_fast(out: &mut String, v: f64, prec: usize) -> bool {
    let Some(&scale) = POW10.get(prec) else {
        return false;
    };
    let a = v.abs();
    // Also false for NaN and the infinities.
    if !a.is_finite() || a >= 1e15 {
        return false;
    }
    let whole = a.trunc();
    let s = (a - whole) * scale as f64;
    let fl = s.floor();
    let frac = s - fl;
    if (frac - 0.5).abs() < 1e-6 {
        return false;
    }
    let mut n = fl as u64 + u64::from(frac > 0.5);
    let mut whole = whole as u64;
    if n >= scale {
        whole += 1;
        n -= scale;
    }
    if v.is_sign_negative() {
        out.push('-');
    }
    digits(out, whole, 1);
    if prec > 0 {
        out.push('.');
        digits(out, n, prec);
    }
    true
}

/// Appends `n` in decimal, zero-padded to at least `min` digits, without the `core::fmt`
/// machinery (this runs for most numbers the helm posts).
fn digits(out: &mut String, n: u64, min: usize) {
    let mut buf = itoa::Buffer::new();
    let s = buf.format(n);
    for _ in s.len()..min {
        out.push('0');
    }
    out.push_str(s);
}

/// Appends an unsigned integer in decimal (`n.to_string()` without the allocation).
///
/// ```
/// let mut s = String::from("pcs=");
/// moos_types::fmt::uint(&mut s, 1207);
/// moos_types::fmt::uint(&mut s, 0);
/// assert_eq!(s, "pcs=12070");
/// ```
pub fn uint(out: &mut String, n: u64) {
    digits(out, n, 1);
}

/// Appends an unsigned integer in decimal, zero-padded to at least `width` digits (`%0*u`).
///
/// ```
/// let mut s = String::new();
/// moos_types::fmt::uint_padded(&mut s, 25, 4);
/// s.push(',');
/// moos_types::fmt::uint_padded(&mut s, 12345, 4);
/// assert_eq!(s, "0025,12345");
/// ```
pub fn uint_padded(out: &mut String, n: u64, width: usize) {
    digits(out, n, width);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(v: f64, prec: usize) -> String {
        let mut s = String::new();
        fixed(&mut s, v, prec);
        s
    }

    fn gs(v: f64, sig: usize) -> String {
        let mut s = String::new();
        g(&mut s, v, sig);
        s
    }

    #[test]
    fn fixed_is_printf() {
        // Values checked against printf("%.Nf").
        assert_eq!(f(1.5, 5), "1.50000");
        assert_eq!(f(-23.1, 5), "-23.10000");
        assert_eq!(f(0.000004, 5), "0.00000");
        assert_eq!(f(12.345675, 2), "12.35");
        assert_eq!(f(-0.0, 5), "-0.00000");
        assert_eq!(f(-0.000001, 5), "-0.00000");
        assert_eq!(f(-0.2, 0), "-0");
        assert_eq!(f(0.125, 2), "0.12", "a half rounds to even as printf does");
        assert_eq!(f(2.5, 0), "2");
        assert_eq!(f(1e20, 5), "100000000000000000000.00000");
        assert_eq!(f(f64::INFINITY, 5), "inf");
        assert_eq!(f(f64::NAN, 2), "nan");
    }

    #[test]
    fn the_compact_forms_differ_only_on_negative_zero() {
        let (mut a, mut b) = (String::new(), String::new());
        compact(&mut a, -0.001, 2);
        dstring_compact(&mut b, -0.001, 2);
        assert_eq!((a.as_str(), b.as_str()), ("0", "-0"));
        a.clear();
        compact(&mut a, 12.50, 2);
        assert_eq!(a, "12.5");
    }

    #[test]
    fn g_is_printf() {
        // Values checked against printf("%.16g") / printf("%.6g").
        assert_eq!(gs(1786054975.5, 16), "1786054975.5");
        assert_eq!(gs(1000.0, 16), "1000");
        assert_eq!(gs(0.0, 16), "0");
        assert_eq!(gs(0.0001, 6), "0.0001");
        assert_eq!(gs(0.00001, 6), "1e-05");
        assert_eq!(gs(123456.0, 6), "123456");
        assert_eq!(gs(-2.5, 6), "-2.5");
        assert_eq!(gs(f64::NAN, 6), "nan");
        assert_eq!(gs(f64::NEG_INFINITY, 6), "-inf");
    }

    fn g6(v: f64) -> String {
        g_string(v, 6)
    }

    /// [`g`]'s exact path, for comparing its fast path with.
    fn g_exact(v: f64, p: usize) -> String {
        let sci = format!("{:.*e}", p - 1, v);
        let (mant, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
        let exp: i32 = exp.parse().unwrap_or(0);
        if exp < -4 || exp >= p as i32 {
            format!(
                "{}e{}{:02}",
                trim_zeros(mant),
                if exp < 0 { '-' } else { '+' },
                exp.abs()
            )
        } else {
            let decimals = (p as i32 - 1 - exp).max(0) as usize;
            trim_zeros(&format!("{v:.decimals$}")).to_string()
        }
    }

    #[test]
    fn g_fast_path_agrees_with_the_exact_formatter() {
        let mut state: u64 = 0x2545_f491_4f6c_dd1d;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let cases = [
            1.0,
            9.9999996,
            99999.95,
            999999.5,
            12.25,
            -12.25,
            1786054975.123456,
            1234567.0,
            100000.0,
            0.5,
            1.5,
            2.5,
            123456.5,
            -99.999995,
        ];
        let random = (0..20_000).map(|i| {
            let bits = next();
            match i % 3 {
                0 => (bits % 2_000_000_000) as f64 / 1000.0 - 1e6,
                1 => (bits % 100_000_000) as f64 * 0.25,
                _ => 1.786e9 + (bits % 100_000_000) as f64 * 0.001,
            }
        });
        for v in cases.into_iter().chain(random) {
            for p in [1, 4, 6, 10, 16] {
                assert_eq!(gs(v, p), g_exact(v, p), "{v} with {p} digits");
            }
        }
    }

    #[test]
    fn g_6_is_a_default_cpp_stream() {
        assert_eq!(g6(0.0), "0");
        assert_eq!(g6(-0.0), "-0");
        assert_eq!(g6(-1.0), "-1");
        assert_eq!(g6(-0.5), "-0.5");
        assert_eq!(g6(0.001), "0.001");
        assert_eq!(g6(0.0001), "0.0001");
        assert_eq!(g6(0.00001), "1e-05");
        assert_eq!(g6(-123456.0), "-123456");
        assert_eq!(g6(-1234567.0), "-1.23457e+06");
        assert_eq!(g6(1.0 / 3.0), "0.333333");
        assert_eq!(g6(-2.5e-7), "-2.5e-07");
        assert_eq!(g6(f64::NEG_INFINITY), "-inf");
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
    fn the_fast_path_agrees_with_the_exact_formatter() {
        let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let cases = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.125,
            2.675,
            1.005,
            99.995,
            1234.5678,
            -0.004,
            -0.006,
            100.0,
            1e-7,
            12345678.9,
            3e12,
            1786000002.0,
            1786000002.25,
            1786000002.125,
            -1786000002.995,
            999999999999999.9,
            0.9999999,
            9.9999995,
        ];
        let random = (0..20_000).map(|i| {
            let bits = next();
            match i % 3 {
                0 => (bits % 2_000_000_000) as f64 / 1000.0 - 1e6,
                1 => (bits % 100_000_000) as f64 * 0.000_005,
                // Epoch times with a few decimals (the helm's and the logs' times).
                2 if i % 2 == 0 => 1.786e9 + (bits % 100_000_000) as f64 * 0.001,
                _ => (bits as f64 / u64::MAX as f64 - 0.5) * 1e4,
            }
        });
        for v in cases.into_iter().chain(random) {
            for prec in 0..7 {
                assert_eq!(
                    f(v, prec),
                    format!("{v:.prec$}"),
                    "{v} with {prec} decimals"
                );
            }
        }
    }
}
