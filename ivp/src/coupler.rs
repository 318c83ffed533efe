//! Coupling two functions over disjoint variables into one (MOOS-IvP's `OF_Coupler`).

use super::domain::Domain;
use super::error::{DomainError, IvpError};
use super::function::IvpFunction;

/// Couples `f1` and `f2` with equal weights 50/50 and normalizes the result to `[0, 100]`,
/// like MOOS-IvP's `OF_Coupler::couple(f1, f2)`.
///
/// ```
/// # use ivp::{couple, Domain, ZaicPeak, ZaicSpd};
/// let d = Domain::from_vars(&[("course", 0.0, 359.0, 360), ("speed", 0.0, 4.0, 41)]).unwrap();
/// let mut hdg = ZaicPeak::new(&d, "course").unwrap();
/// hdg.set_params(90.0, 0.0, 180.0, 0.0, 0.0, 100.0).unwrap();
/// hdg.set_value_wrap(true);
/// let spd = ZaicSpd::new(&d, "speed", 2.0, 1.0, 3.0, 50.0, 50.0).unwrap();
/// let f = couple(&hdg.extract().unwrap(), &spd.extract().unwrap()).unwrap();
/// assert_eq!(f.eval(&[90, 20]), Some(100.0));
/// ```
pub fn couple(f1: &IvpFunction, f2: &IvpFunction) -> Result<IvpFunction, IvpError> {
    couple_weighted(f1, f2, 50.0, 50.0, true)
}

/// Couples `f1` (normalized to `[0, w1]`) and `f2` (normalized to `[0, w2]`) into one function
/// over the union of their domains: the cross product of their pieces, with summed interior
/// functions. With `normalize`, the result is normalized to `[0, 100]`.
pub fn couple_weighted(
    f1: &IvpFunction,
    f2: &IvpFunction,
    w1: f64,
    w2: f64,
    normalize: bool,
) -> Result<IvpFunction, IvpError> {
    if !(w1.is_finite() && w2.is_finite()) || w1 < 0.0 || w2 < 0.0 {
        return Err(IvpError::BadParam {
            builder: "OF_Coupler",
            param: "weight",
            value: if w1.is_finite() && w1 >= 0.0 { w2 } else { w1 },
            expected: "finite non-negative weights",
        });
    }
    let mut domain = Domain::new();
    for v in f1.domain().vars() {
        domain.add(v.clone())?;
    }
    for v in f2.domain().vars() {
        if domain.index_of(v.name()).is_some() {
            return Err(DomainError::Overlap(v.name().to_string()).into());
        }
        domain.add(v.clone())?;
    }
    let mut a = f1.clone();
    a.normalize(0.0, w1);
    let mut b = f2.clone();
    b.normalize(0.0, w2);

    let (d1, d2) = (a.dim(), b.dim());
    let mut out = IvpFunction::new(domain);
    out.reserve_pieces(a.piece_count() * b.piece_count());
    let mut lo = vec![0u32; d1 + d2];
    let mut hi = vec![0u32; d1 + d2];
    let mut w = vec![0.0; d1 + d2];
    for p in a.pieces() {
        lo[..d1].copy_from_slice(p.lo);
        hi[..d1].copy_from_slice(p.hi);
        w[..d1].copy_from_slice(&p.wts[..d1]);
        for q in b.pieces() {
            lo[d1..].copy_from_slice(q.lo);
            hi[d1..].copy_from_slice(q.hi);
            w[d1..].copy_from_slice(&q.wts[..d2]);
            out.push_unchecked(&lo, &hi, &w, p.intercept() + q.intercept());
        }
    }
    if normalize {
        out.normalize(0.0, 100.0);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ZaicPeak;

    #[test]
    fn coupled_values_are_the_normalized_sum() {
        let d = Domain::from_vars(&[("x", 0.0, 10.0, 11), ("y", 0.0, 4.0, 5)]).unwrap();
        let mut zx = ZaicPeak::new(&d, "x").unwrap();
        zx.set_params(5.0, 0.0, 5.0, 0.0, 0.0, 100.0).unwrap();
        let mut zy = ZaicPeak::new(&d, "y").unwrap();
        zy.set_params(0.0, 0.0, 4.0, 0.0, 0.0, 100.0).unwrap();
        let fx = zx.extract().unwrap();
        let fy = zy.extract().unwrap();
        let f = couple(&fx, &fy).unwrap();
        assert_eq!(f.piece_count(), fx.piece_count() * fy.piece_count());
        // x=5 (100), y=0 (100): sum 50+50 -> 100 after normalization
        assert!((f.eval(&[5, 0]).unwrap() - 100.0).abs() < 1e-9);
        // x=0 (0), y=4 (0): 0
        assert!(f.eval(&[0, 4]).unwrap().abs() < 1e-9);
        // x=5, y=2 (50): 50 + 25 = 75
        assert!((f.eval(&[5, 2]).unwrap() - 75.0).abs() < 1e-9);
        // unequal weights, no final normalization
        let g = couple_weighted(&fx, &fy, 80.0, 20.0, false).unwrap();
        assert!((g.eval(&[5, 2]).unwrap() - 90.0).abs() < 1e-9);
    }

    #[test]
    fn overlapping_domains_are_rejected() {
        let d = Domain::from_vars(&[("x", 0.0, 10.0, 11)]).unwrap();
        let z = ZaicPeak::new(&d, "x").unwrap().extract().unwrap();
        assert!(matches!(
            couple(&z, &z),
            Err(IvpError::Domain(DomainError::Overlap(_)))
        ));
        assert!(couple_weighted(&z, &z, -1.0, 1.0, true).is_err());
    }
}
