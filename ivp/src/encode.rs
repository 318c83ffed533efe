//! The text form of an IvP function that pHelmIvP posts as `BHV_IPF` (MOOS-IvP's
//! `FunctionEncoder`), its split into MOOS-sized parts, and the way back.
//!
//! A function is written as
//!
//! ```text
//! H,<context length>,<context>,<dim>,<pieces>,<degree>,<pwt>,D,<domain>,G,<grid>,F,<pieces>
//! ```
//!
//! - the context is `<helm iteration>:<behaviour name>`, prefixed by its length because it may
//!   hold commas;
//! - the degree is 1 (every coug piece is linear: one slope per dimension, then the
//!   intercept);
//! - the domain is the `IVPHELM_DOMAIN` form with `;` for `,` (`course;0;359;360:speed;0;4;21`);
//! - the grid lists, per dimension, the highest index of the grid-element box (MOOS
//!   `PDMap::getGelBox`). Functions built by the ZAIC tools and the coupler keep the PDMap
//!   default, the whole domain (`points - 1`), and every coug behaviour builds with those;
//! - each piece is its box, low then high index per dimension, then its weights. A bound
//!   the box does not include would be prefixed by `X`; coug's boxes are closed, so none is.
//!   Weights are rounded to 4 decimals with trailing zeros dropped, keeping the point
//!   (`0.5`, `12.`, `0.0001`; a value that rounds to zero but is not zero is `0.0000`, and an
//!   exact zero is `0`), as the C++ writer does.
//!
//! The whole text is then split by [`mux`] into parts of at most `packet_size` characters
//! (`P,<id>,<parts>,<part>,<text>`; pHelmIvP uses 2000 and the id `<behaviour>^<iteration>`).
//!
//! Piece layouts are coug's own: a function coug posts decodes to the same values over the
//! domain as coug's solver uses, but its pieces need not be cut where the C++ builders cut
//! theirs, so the text is not byte-identical to pHelmIvP's for the same behaviour.

use crate::domain::{Domain, DomainVar};
use crate::error::IvpError;
use crate::function::IvpFunction;

/// Appends the text form of `f` with the context string `context` (pHelmIvP uses
/// `<iteration>:<behaviour>`) to `out`.
pub fn encode(f: &IvpFunction, context: &str, out: &mut String) {
    let dim = f.dim();
    let pcs = f.piece_count();
    out.reserve(32 + context.len() + pcs * (dim * 2 + dim + 1) * 8);
    out.push_str("H,");
    push_uint(out, context.len() as u64);
    out.push(',');
    out.push_str(context);
    out.push(',');
    push_uint(out, dim as u64);
    out.push(',');
    push_uint(out, pcs as u64);
    out.push_str(",1,");
    push_compact5(out, f.pwt());
    out.push_str(",D,");
    for (i, v) in f.domain().vars().iter().enumerate() {
        if i > 0 {
            out.push(':');
        }
        out.push_str(v.name());
        out.push(';');
        push_compact5(out, v.low());
        out.push(';');
        push_compact5(out, v.high());
        out.push(';');
        push_uint(out, u64::from(v.points()));
    }
    out.push_str(",G,");
    for v in f.domain().vars() {
        push_uint(out, u64::from(v.points() - 1));
        out.push(',');
    }
    out.push_str("F,");
    for (i, p) in f.pieces().enumerate() {
        for d in 0..dim {
            push_index(out, p.lo[d]);
            out.push(',');
            push_index(out, p.hi[d]);
            out.push(',');
        }
        for (j, &w) in p.wts.iter().enumerate() {
            push_weight(out, w);
            if i + 1 < pcs || j + 1 < p.wts.len() {
                out.push(',');
            }
        }
    }
}

/// [`encode`] into a new string.
pub fn encode_string(f: &IvpFunction, context: &str) -> String {
    let mut s = String::new();
    encode(f, context, &mut s);
    s
}

/// Splits an encoded function into parts of at most `packet_size` characters:
/// `P,<id>,<n>,<k>,<text k>` for `k` in `1..=n` (MOOS-IvP `IvPFunctionToVector`). Room for
/// the header is `id.len() + 50` characters; the number of parts is `len / body + 1`, so a
/// text that fills its parts exactly gets an empty last part, as the C++ does. A
/// `packet_size` too small for the header gives one part holding the whole text.
pub fn mux(whole: &str, id: &str, packet_size: usize, out: &mut Vec<String>) {
    let header = id.len() + 50;
    let body = packet_size.saturating_sub(header);
    let bytes = whole.as_bytes();
    let n = bytes.len().checked_div(body).map_or(1, |q| q + 1);
    let body = if body == 0 { bytes.len() } else { body };
    for k in 0..n {
        let from = (k * body).min(bytes.len());
        let to = ((k + 1) * body).min(bytes.len());
        let mut part = String::with_capacity(header + to - from);
        part.push_str("P,");
        part.push_str(id);
        part.push(',');
        push_uint(&mut part, n as u64);
        part.push(',');
        push_uint(&mut part, k as u64 + 1);
        part.push(',');
        // The encoded text is ASCII (names in a MOOS domain and context are), so any byte
        // offset is a character boundary; fall back to lossless handling otherwise.
        // Cut at character boundaries (always so for ASCII text) the slice is the text
        // itself: no check and no copy; a cut inside a character reads lossily.
        if whole.is_char_boundary(from) && whole.is_char_boundary(to) {
            part.push_str(&whole[from..to]);
        } else {
            part.push_str(&String::from_utf8_lossy(&bytes[from..to]));
        }
        out.push(part);
    }
}

/// Joins the parts made by [`mux`] (in any order) back into the encoded text. `None` if
/// the parts disagree on their id or count, or one is missing or malformed.
pub fn demux<'a>(parts: impl IntoIterator<Item = &'a str>) -> Option<String> {
    let mut id_n: Option<(&str, usize)> = None;
    let mut bodies: Vec<Option<&str>> = Vec::new();
    for part in parts {
        let rest = part.strip_prefix("P,")?;
        // The id may hold commas only if the behaviour name does; MOOS names do not.
        let (id, rest) = rest.split_once(',')?;
        let (n, rest) = rest.split_once(',')?;
        let (k, body) = rest.split_once(',')?;
        let n: usize = n.parse().ok()?;
        let k: usize = k.parse().ok()?;
        match id_n {
            None => {
                id_n = Some((id, n));
                bodies = vec![None; n];
            }
            Some((i, m)) if i != id || m != n => return None,
            Some(_) => {}
        }
        *bodies.get_mut(k.checked_sub(1)?)? = Some(body);
    }
    id_n?;
    let mut s = String::new();
    for b in bodies {
        s.push_str(b?);
    }
    Some(s)
}

/// Reads the text form back into a function and its context string (MOOS-IvP
/// `StringToIvPFunction`). Accepts degree 1 only; open bounds (`X`) are read as closed.
pub fn decode(text: &str) -> Result<(IvpFunction, String), IvpError> {
    let bad = |why: &str| IvpError::Decode(why.to_string());
    let rest = text.strip_prefix("H,").ok_or_else(|| bad("no H header"))?;
    let (len, rest) = rest
        .split_once(',')
        .ok_or_else(|| bad("no context length"))?;
    let len: usize = len.parse().map_err(|_| bad("context length"))?;
    if rest.len() < len + 1 || !rest.is_char_boundary(len) {
        return Err(bad("context shorter than its length"));
    }
    let context = rest[..len].to_string();
    let mut fields = rest[len..]
        .strip_prefix(',')
        .ok_or_else(|| bad("no comma after the context"))?
        .split(',');
    let mut next = |what: &str| fields.next().ok_or_else(|| bad(what));
    let dim: usize = next("dim")?.parse().map_err(|_| bad("dim"))?;
    let pcs: usize = next("pieces")?.parse().map_err(|_| bad("pieces"))?;
    let deg: usize = next("degree")?.parse().map_err(|_| bad("degree"))?;
    if deg != 1 {
        return Err(bad("only degree 1 is supported"));
    }
    let pwt: f64 = next("pwt")?.parse().map_err(|_| bad("pwt"))?;
    if next("D")? != "D" {
        return Err(bad("no D section"));
    }
    let mut domain = Domain::new();
    for spec in next("domain")?.split(':') {
        let v: Vec<&str> = spec.split(';').collect();
        let [name, lo, hi, pts] = v[..] else {
            return Err(bad("domain variable"));
        };
        let num = |s: &str| s.parse::<f64>().map_err(|_| bad("domain number"));
        let pts: u32 = pts.parse().map_err(|_| bad("domain points"))?;
        domain.add(DomainVar::new(name, num(lo)?, num(hi)?, pts)?)?;
    }
    if domain.len() != dim {
        return Err(bad("domain size differs from dim"));
    }
    if next("G")? != "G" {
        return Err(bad("no G section"));
    }
    for _ in 0..dim {
        next("grid")?;
    }
    if next("F")? != "F" {
        return Err(bad("no F section"));
    }
    let mut f = IvpFunction::new(domain).with_pwt(pwt);
    let (mut lo, mut hi, mut wts) = (vec![0; dim], vec![0; dim], vec![0.0; dim + 1]);
    for _ in 0..pcs {
        for d in 0..dim {
            let read = |s: &str| {
                s.trim_start_matches('X')
                    .parse::<u32>()
                    .map_err(|_| bad("piece bound"))
            };
            lo[d] = read(next("piece low")?)?;
            hi[d] = read(next("piece high")?)?;
        }
        for w in wts.iter_mut() {
            *w = next("weight")?.parse().map_err(|_| bad("weight"))?;
        }
        f.push_piece(&lo, &hi, &wts[..dim], wts[dim])?;
    }
    Ok((f, context))
}

fn push_uint(out: &mut String, v: u64) {
    moos_types::fmt::uint(out, v);
}

/// A grid index in decimal: the pieces' boxes are most of the text, and their indices are
/// small (a domain has at most a few thousand points), so the common widths are written
/// digit by digit, without a call per number.
fn push_index(out: &mut String, v: u32) {
    let digit = |d: u32| char::from(b'0' + d as u8);
    if v < 10 {
        out.push(digit(v));
    } else if v < 100 {
        out.push(digit(v / 10));
        out.push(digit(v % 10));
    } else if v < 1000 {
        out.push(digit(v / 100));
        out.push(digit(v / 10 % 10));
        out.push(digit(v % 10));
    } else {
        push_uint(out, u64::from(v));
    }
}

/// MOOS `dstringCompact(doubleToString(v))`: 5 decimals, then trailing zeros and a trailing
/// point dropped.
pub(crate) fn push_compact5(out: &mut String, v: f64) {
    // A whole number (a domain's bounds, most priority weights) is its integer digits, the
    // text the fixed-then-trimmed form gives, without making it; `-0` stays with that form.
    if v.fract() == 0.0 && v.abs() < 1e15 && !(v == 0.0 && v.is_sign_negative()) {
        if v < 0.0 {
            out.push('-');
        }
        push_uint(out, v.abs() as u64);
        return;
    }
    moos_types::fmt::dstring_compact(out, v, 5);
}

/// One weight as the C++ writer prints it (see the module docs).
fn push_weight(out: &mut String, w: f64) {
    let mut w = w;
    if w < 0.0 {
        out.push('-');
        w = -w;
    }
    if w == 0.0 {
        out.push('0');
        return;
    }
    // Ten-thousandths, rounded half up, as `(long)(w * 10000 + 0.5)`.
    let units = (w * 10000.0 + 0.5) as u64;
    let int_part = units / 10_000;
    let frac = units % 10_000;
    if int_part < 1000 {
        push_index(out, int_part as u32);
    } else {
        push_uint(out, int_part);
    }
    out.push('.');
    if frac == 0 {
        if int_part == 0 {
            out.push_str("0000");
        }
        return;
    }
    // Four digits, the trailing zeros dropped (`frac` is not 0, so one digit stays).
    let mut frac = frac as u32;
    let mut width = 4;
    while frac.is_multiple_of(10) {
        frac /= 10;
        width -= 1;
    }
    let mut div = 10u32.pow(width - 1);
    while div > 0 {
        out.push(char::from(b'0' + (frac / div % 10) as u8));
        div /= 10;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn weight(w: f64) -> String {
        let mut s = String::new();
        push_weight(&mut s, w);
        s
    }

    #[test]
    fn weights_print_as_the_cpp_writer_does() {
        // Worked through FunctionEncoder's digit loop by hand.
        assert_eq!(weight(0.5), "0.5");
        assert_eq!(weight(12.0), "12.");
        assert_eq!(weight(100.0), "100.");
        assert_eq!(weight(0.0001), "0.0001");
        assert_eq!(weight(0.00001), "0.0000");
        assert_eq!(weight(0.0), "0");
        assert_eq!(weight(-0.0), "0");
        assert_eq!(weight(-2.25), "-2.25");
        assert_eq!(weight(1.23456), "1.2346");
        assert_eq!(weight(99.99996), "100.");
        assert_eq!(weight(3.0405), "3.0405");
        assert_eq!(weight(-0.00004), "-0.0000");
    }

    #[test]
    fn weights_and_indices_match_the_plain_formatting() {
        // Every count of ten-thousandths up to 20000.0000 in steps that hit each digit
        // position, against the same rule written with `format!`.
        for units in (0u64..200_000).chain((0..3000).map(|k| k * 66_667)) {
            let w = units as f64 / 10_000.0;
            let (int_part, frac) = (units / 10_000, units % 10_000);
            let plain = if units == 0 {
                "0".to_string()
            } else if frac == 0 {
                format!("{int_part}.{}", if int_part == 0 { "0000" } else { "" })
            } else {
                let f = format!("{frac:04}");
                format!("{int_part}.{}", f.trim_end_matches('0'))
            };
            assert_eq!(weight(w), plain, "{units}");
            assert_eq!(
                weight(-w),
                if units == 0 {
                    plain
                } else {
                    format!("-{plain}")
                }
            );
        }
        for v in (0..5000).chain([u32::MAX]) {
            let mut s = String::new();
            push_index(&mut s, v);
            assert_eq!(s, v.to_string());
        }
    }

    #[test]
    fn compact5_is_dstring_compact_of_double_to_string() {
        let c = |v: f64| {
            let mut s = String::new();
            push_compact5(&mut s, v);
            s
        };
        assert_eq!(c(100.0), "100");
        assert_eq!(c(0.5), "0.5");
        assert_eq!(c(0.123456), "0.12346");
        assert_eq!(c(-3.0), "-3");
        assert_eq!(c(0.0), "0");
        assert_eq!(c(-0.0), "-0");
        // Whole numbers take a path of their own: the same text as the general one.
        for v in [
            1.0,
            -1.0,
            359.0,
            1e14,
            -123456789.0,
            4503599627370496.0,
            1e20,
            0.0,
            -0.0,
        ] {
            let mut general = String::new();
            moos_types::fmt::dstring_compact(&mut general, v, 5);
            assert_eq!(c(v), general, "{v}");
        }
    }

    fn two_piece() -> IvpFunction {
        let d = Domain::parse_specs(["speed:0:4:21"]).unwrap();
        let mut f = IvpFunction::new(d).with_pwt(100.0);
        f.push_piece(&[0], &[10], &[10.0], 0.0).unwrap();
        f.push_piece(&[11], &[20], &[-10.0], 200.0).unwrap();
        f
    }

    #[test]
    fn a_one_dimensional_function_encodes_exactly() {
        let s = encode_string(&two_piece(), "7:cruise");
        assert_eq!(
            s,
            "H,8,7:cruise,1,2,1,100,D,speed;0;4;21,G,20,F,0,10,10.,0,11,20,-10.,200."
        );
    }

    #[test]
    fn a_coupled_function_round_trips() {
        let d = Domain::parse_specs(["course:0:359:360", "speed:0:2:21"]).unwrap();
        let mut f = IvpFunction::new(d).with_pwt(12.5);
        f.push_piece(&[0, 0], &[179, 20], &[0.25, -1.5], 3.125)
            .unwrap();
        f.push_piece(&[180, 0], &[359, 20], &[-0.25, 0.0], 92.0)
            .unwrap();
        let s = encode_string(&f, "12:wpt,1");
        assert!(
            s.starts_with("H,8,12:wpt,1,2,2,1,12.5,D,course;0;359;360:speed;0;2;21,G,359,20,F,")
        );
        assert!(s.ends_with(",180,359,0,20,-0.25,0,92."), "{s}");
        let (g, ctx) = decode(&s).unwrap();
        assert_eq!(ctx, "12:wpt,1");
        assert_eq!(g, f);
    }

    #[test]
    fn mux_splits_and_demux_joins() {
        let whole = "x".repeat(4000);
        let mut parts = Vec::new();
        mux(&whole, "cruise^12", 2000, &mut parts);
        // 2000 - (9 + 50) = 1941 characters a part: 4000 / 1941 + 1 = 3 parts.
        assert_eq!(parts.len(), 3);
        assert!(parts[0].starts_with("P,cruise^12,3,1,xxx"));
        assert_eq!(parts[0].len(), "P,cruise^12,3,1,".len() + 1941);
        assert_eq!(parts[2].len(), "P,cruise^12,3,3,".len() + 4000 - 2 * 1941);
        parts.swap(0, 2);
        assert_eq!(demux(parts.iter().map(|s| s.as_str())).unwrap(), whole);
        // A short text is one part; a text filling its part exactly gets an empty second.
        let mut one = Vec::new();
        mux("H,abc", "b^1", 2000, &mut one);
        assert_eq!(one, ["P,b^1,1,1,H,abc"]);
        let mut exact = Vec::new();
        mux(&"y".repeat(1947), "b^1", 2000, &mut exact);
        assert_eq!(exact.len(), 2);
        assert_eq!(exact[1], "P,b^1,2,2,");
        assert!(demux(["P,a^1,2,1,xy"]).is_none());
    }

    #[test]
    fn decode_rejects_broken_text() {
        assert!(decode("").is_err());
        assert!(decode("H,20,short").is_err());
        assert!(decode("H,1,x,1,1,0,10,D,s;0;1;2,G,1,F,0,1,5").is_err());
        let good = encode_string(&two_piece(), "1:a");
        assert!(decode(&good[..good.rfind(',').unwrap()]).is_err());
    }
}
