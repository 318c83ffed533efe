//! C++ iostream number formats used by pLogger.

use std::fmt::Write as _;

/// Appends `x` as C++ `fixed` with `decimals` places (`nan`, `inf`, `-inf` for non-finite).
///
/// ```
/// let mut s = String::new();
/// alog::fmt_fixed(&mut s, 1.5, 5);
/// assert_eq!(s, "1.50000");
/// ```
pub fn fmt_fixed(out: &mut String, x: f64, decimals: usize) {
    if non_finite(out, x) {
        return;
    }
    if !fixed_fast(out, x, decimals) {
        let _ = write!(out, "{x:.decimals$}");
    }
}

/// Powers of ten that are exact in an `f64` and in a `u64`.
const POW10: [f64; 10] = [1.0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9];

/// Integer formatting of `x` with `decimals` places when the rounding is unambiguous
/// (the scaled fraction is not within 1e-6 of a half and the scaled value fits well
/// inside the exact integer range); `false` leaves the work to the exact formatter.
fn fixed_fast(out: &mut String, x: f64, decimals: usize) -> bool {
    let Some(&p) = POW10.get(decimals) else {
        return false;
    };
    let scaled = x.abs() * p;
    if scaled >= 1e15 {
        return false;
    }
    let frac = scaled - scaled.floor();
    if (frac - 0.5).abs() < 1e-6 {
        return false;
    }
    let n = scaled.round() as u64;
    let p = p as u64;
    let (int, dec) = (n / p, n % p);
    if x.is_sign_negative() {
        out.push('-');
    }
    let _ = write!(out, "{int}");
    if decimals > 0 {
        let _ = write!(out, ".{dec:0decimals$}");
    }
    true
}

/// Appends `x` as C++ default float notation with `precision` significant digits (`%g`):
/// fixed when the decimal exponent is in `-4..precision`, otherwise scientific
/// (`1.5e+20`); trailing zeros and a trailing point are removed.
///
/// ```
/// let mut s = String::new();
/// alog::fmt_g(&mut s, 1786054975.123456, 16);
/// assert_eq!(s, "1786054975.123456");
/// ```
pub fn fmt_g(out: &mut String, x: f64, precision: usize) {
    if non_finite(out, x) {
        return;
    }
    if x == 0.0 {
        out.push_str(if x.is_sign_negative() { "-0" } else { "0" });
        return;
    }
    let p = precision.max(1);
    let sci = format!("{:.*e}", p - 1, x);
    let (mant, exp) = sci.split_once('e').unwrap_or((&sci, "0"));
    let exp: i32 = exp.parse().unwrap_or(0);
    if exp < -4 || exp >= p as i32 {
        out.push_str(trim_zeros(mant));
        let sign = if exp < 0 { '-' } else { '+' };
        let _ = write!(out, "e{sign}{:02}", exp.abs());
    } else {
        let decimals = (p as i32 - 1 - exp).max(0) as usize;
        let fixed = format!("{x:.decimals$}");
        out.push_str(trim_zeros(&fixed));
    }
}

fn non_finite(out: &mut String, x: f64) -> bool {
    if x.is_nan() {
        out.push_str(if x.is_sign_negative() { "-nan" } else { "nan" });
        true
    } else if x.is_infinite() {
        out.push_str(if x > 0.0 { "inf" } else { "-inf" });
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

#[cfg(test)]
mod tests {
    use super::*;

    fn g(x: f64, p: usize) -> String {
        let mut s = String::new();
        fmt_g(&mut s, x, p);
        s
    }

    fn f(x: f64, d: usize) -> String {
        let mut s = String::new();
        fmt_fixed(&mut s, x, d);
        s
    }

    #[test]
    fn g_matches_printf() {
        // Values checked against printf("%.16g") / printf("%.6g").
        assert_eq!(g(1786054975.123456, 16), "1786054975.123456");
        assert_eq!(g(1786054975.5, 16), "1786054975.5");
        assert_eq!(g(1000.0, 16), "1000");
        assert_eq!(g(0.0, 16), "0");
        assert_eq!(g(0.0001, 6), "0.0001");
        assert_eq!(g(0.00001, 6), "1e-05");
        assert_eq!(g(123456.0, 6), "123456");
        assert_eq!(g(1234567.0, 6), "1.23457e+06");
        assert_eq!(g(-2.5, 6), "-2.5");
        assert_eq!(g(f64::NAN, 6), "nan");
        assert_eq!(g(f64::NEG_INFINITY, 6), "-inf");
    }

    #[test]
    fn fast_fixed_agrees_with_the_exact_formatter() {
        let mut rng_state: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = || {
            rng_state ^= rng_state << 13;
            rng_state ^= rng_state >> 7;
            rng_state ^= rng_state << 17;
            rng_state
        };
        let mut fast = String::new();
        for i in 0..50_000 {
            let bits = next();
            let x = match i % 4 {
                0 => f64::from_bits(bits),
                1 => (bits % 2_000_000_000) as f64 / 1000.0 - 1e6,
                2 => (bits % 100_000_000) as f64 * 0.000_005,
                _ => (bits as f64 / u64::MAX as f64 - 0.5) * 1e4,
            };
            if !x.is_finite() {
                continue;
            }
            for d in [0, 2, 5, 9] {
                fast.clear();
                fmt_fixed(&mut fast, x, d);
                assert_eq!(fast, format!("{x:.d$}"), "{x:e} with {d} decimals");
            }
        }
    }

    #[test]
    fn fixed_matches_printf() {
        assert_eq!(f(1.5, 5), "1.50000");
        assert_eq!(f(-23.1, 5), "-23.10000");
        assert_eq!(f(0.000004, 5), "0.00000");
        assert_eq!(f(12.345675, 2), "12.35");
        assert_eq!(f(f64::INFINITY, 5), "inf");
        assert_eq!(f(-0.0, 5), "-0.00000");
        assert_eq!(f(-0.000001, 5), "-0.00000");
        assert_eq!(f(0.125, 2), "0.12", "a half rounds to even as printf does");
        assert_eq!(f(1e20, 5), "100000000000000000000.00000");
    }
}
