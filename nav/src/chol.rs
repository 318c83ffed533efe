//! The 7x7 block arithmetic of the window's elimination, on stack arrays: a Cholesky factor
//! computed from the lower half of a symmetric block, forward and backward substitution, and
//! the symmetric products the Schur complements need.
//!
//! Compared with a general solve of `S^-1 O` followed by `O' (S^-1 O)`, the elimination keeps
//! `V = L^-1 O` (forward substitution only) and forms `O' S^-1 O = V' V` on its lower half,
//! so every Schur complement is exactly symmetric and costs about half the products.
//!
//! The triangular loops index several arrays by row and column, as the formulas are written.
#![allow(clippy::needless_range_loop)]

use crate::state::{DIM, M7, V7};

/// `$s.$f::<I>($args)` for each constant `I` listed, in that order, joined by `$op` (`;` for
/// statements, `&&` to stop at the first false): each call's loops have fixed bounds.
macro_rules! per_index {
    ($s:ident . $f:ident ($arg:expr), $op:tt, $first:literal $($i:literal)*) => {
        $s.$f::<$first>($arg) $($op $s.$f::<$i>($arg))*
    };
}

/// The lower Cholesky factor `L` of a symmetric positive definite 7x7 block (`S = L L'`),
/// row-major, with the reciprocals of its diagonal (substitution multiplies by them).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Chol7 {
    /// `l[i][j]` for `j <= i`; the upper part is zero.
    l: [[f64; DIM]; DIM],
    /// `1 / l[i][i]`.
    inv_diag: [f64; DIM],
}

impl Chol7 {
    /// Factors `s` from its lower half; `None` when it is not positive definite (or holds
    /// non-finite numbers).
    pub(crate) fn new(s: &M7) -> Option<Chol7> {
        let mut c = Chol7::default();
        c.factor(s).then_some(c)
    }

    /// Factors `s` (its lower half only is read) into `self`; false when it is not positive
    /// definite (or holds non-finite numbers), `self` then being garbage.
    #[inline]
    pub(crate) fn factor(&mut self, s: &M7) -> bool {
        // One call per column, each with fixed loop bounds (unrolled).
        per_index!(self.factor_column(s), &&, 0 1 2 3 4 5 6)
    }

    /// Column `J` of the factor (the columns before it done).
    #[inline(always)]
    fn factor_column<const J: usize>(&mut self, s: &M7) -> bool {
        let s = &s.data.0; // column-major: s[j][i] is row i, column j
        let mut d = s[J][J];
        for k in 0..J {
            d -= self.l[J][k] * self.l[J][k];
        }
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        let ljj = d.sqrt();
        let inv = 1.0 / ljj;
        self.l[J][J] = ljj;
        self.inv_diag[J] = inv;
        for i in J + 1..DIM {
            let mut v = s[J][i];
            for k in 0..J {
                v -= self.l[i][k] * self.l[J][k];
            }
            self.l[i][J] = v * inv;
        }
        true
    }

    /// `b <- L^-1 b`.
    #[inline(always)]
    pub(crate) fn forward(&self, b: &mut [f64; DIM]) {
        per_index!(self.forward_row(b), ;, 0 1 2 3 4 5 6);
    }

    /// Row `I` of the forward substitution.
    #[inline(always)]
    fn forward_row<const I: usize>(&self, b: &mut [f64; DIM]) {
        let mut v = b[I];
        for k in 0..I {
            v -= self.l[I][k] * b[k];
        }
        b[I] = v * self.inv_diag[I];
    }

    /// `b <- L'^-1 b`.
    #[inline]
    pub(crate) fn backward(&self, b: &mut [f64; DIM]) {
        per_index!(self.backward_row(b), ;, 6 5 4 3 2 1 0);
    }

    /// Row `I` of the backward substitution.
    #[inline(always)]
    fn backward_row<const I: usize>(&self, b: &mut [f64; DIM]) {
        let mut v = b[I];
        for k in I + 1..DIM {
            v -= self.l[k][I] * b[k];
        }
        b[I] = v * self.inv_diag[I];
    }

    /// `b <- L^-1 b` for a `b` that is zero above row `r` (so is the result).
    #[inline(always)]
    fn forward_from(&self, b: &mut [f64; DIM], r: usize) {
        for i in r..DIM {
            let mut v = b[i];
            for k in r..i {
                v -= self.l[i][k] * b[k];
            }
            b[i] = v * self.inv_diag[i];
        }
    }

    /// `b <- L^-1 b` for a `b` that is zero above row `R` (a constant, so every loop has
    /// fixed bounds).
    #[inline(always)]
    fn forward_below<const R: usize>(&self, b: &mut [f64; DIM]) {
        for i in R..DIM {
            let mut v = b[i];
            for k in R..i {
                v -= self.l[i][k] * b[k];
            }
            b[i] = v * self.inv_diag[i];
        }
    }

    /// `V <- L^-1 V` for a `V` with the pattern [`OFF_DIAGONAL_START`].
    #[inline]
    pub(crate) fn forward_columns_pattern(&self, v: &mut M7) {
        let cols = &mut v.data.0;
        for col in cols[..4].iter_mut() {
            self.forward_below::<0>(col);
        }
        self.forward_below::<3>(&mut cols[4]);
        self.forward_below::<5>(&mut cols[5]);
        self.forward_below::<6>(&mut cols[6]);
    }

    /// `V <- L^-1 V` for a `V` whose column `c` is zero above row `start[c]`.
    #[inline(always)]
    pub(crate) fn forward_columns_from(&self, v: &mut M7, start: &[usize; DIM]) {
        for (col, &r) in v.data.0.iter_mut().zip(start) {
            self.forward_from(col, r);
        }
    }

    /// `V = L^-1 O`, column by column.
    pub(crate) fn forward_columns(&self, o: &M7) -> M7 {
        let mut v = *o;
        self.forward_columns_in_place(&mut v);
        v
    }

    /// `V <- L^-1 V`, column by column.
    #[inline]
    pub(crate) fn forward_columns_in_place(&self, v: &mut M7) {
        for col in v.data.0.iter_mut() {
            self.forward(col);
        }
    }

    /// `S^-1 = L'^-1 L^-1`, exactly symmetric (each entry one dot product of two columns of
    /// `L^-1`).
    pub(crate) fn inverse(&self) -> M7 {
        // Columns of L^-1 (lower triangular: column c is zero above row c).
        let mut li = [[0.0; DIM]; DIM];
        for (c, col) in li.iter_mut().enumerate() {
            col[c] = 1.0;
            self.forward(col);
        }
        let mut out = M7::zeros();
        for a in 0..DIM {
            for b in 0..=a {
                // Row k of L^-1 is zero before column k: only k >= a contributes.
                let mut t = 0.0;
                for k in a..DIM {
                    t += li[a][k] * li[b][k];
                }
                out[(a, b)] = t;
                out[(b, a)] = t;
            }
        }
        out
    }
}

/// `d - V' V`, computed on the lower half and mirrored (exactly symmetric).
pub(crate) fn sub_gram(d: &M7, v: &M7) -> M7 {
    let mut out = M7::zeros();
    sub_gram_lower(d, v, &mut out);
    let o = &mut out.data.0;
    for b in 0..DIM {
        for a in b + 1..DIM {
            o[a][b] = o[b][a];
        }
    }
    out
}

/// The lower half of `d - V' V` into `out` (its upper half is left as it was: enough for
/// [`Chol7::factor`]).
#[inline]
pub(crate) fn sub_gram_lower(d: &M7, v: &M7, out: &mut M7) {
    let cols = &v.data.0;
    let (d, o) = (&d.data.0, &mut out.data.0);
    for b in 0..DIM {
        for a in b..DIM {
            let mut t = 0.0;
            for k in 0..DIM {
                t += cols[a][k] * cols[b][k];
            }
            // Row a, column b.
            o[b][a] = d[b][a] - t;
        }
    }
}

/// The sparsity pattern of the window's off-diagonal blocks: columns x, y, z and heading are
/// full, the bias column is zero above the heading row (the AHRS yaw and the random walk
/// join heading and bias only), each current column is zero above its own row (the random
/// walk alone). `L^-1` keeps a column's leading zeros, so `V = L^-1 O` has the same pattern.
pub(crate) const OFF_DIAGONAL_START: [usize; DIM] = [0, 0, 0, 0, 3, 5, 6];

/// No pattern: every column full.
pub(crate) const FULL: [usize; DIM] = [0; DIM];

/// Whether every column `c` of `o` is zero above row `start[c]`.
#[inline]
pub(crate) fn has_pattern(o: &M7, start: &[usize; DIM]) -> bool {
    let cols = &o.data.0;
    let mut nonzero = false;
    for c in 0..DIM {
        for r in 0..start[c] {
            nonzero |= cols[c][r] != 0.0;
        }
    }
    !nonzero
}

/// `sum a[k] b[k]` over `k >= K0`.
#[inline(always)]
fn dot_below<const K0: usize>(a: &[f64; DIM], b: &[f64; DIM]) -> f64 {
    let mut t = 0.0;
    for k in K0..DIM {
        t += a[k] * b[k];
    }
    t
}

/// [`sub_gram_lower_from`] for the pattern [`OFF_DIAGONAL_START`], every loop with fixed
/// bounds (the same sums).
#[inline]
pub(crate) fn sub_gram_lower_pattern(d: &M7, v: &M7, out: &mut M7) {
    let cols = &v.data.0;
    let (d, o) = (&d.data.0, &mut out.data.0);
    // o[b][a] is row a, column b (a >= b).
    for b in 0..4 {
        for a in b..4 {
            o[b][a] = d[b][a] - dot_below::<0>(&cols[a], &cols[b]);
        }
    }
    for b in 0..5 {
        o[b][4] = d[b][4] - dot_below::<3>(&cols[4], &cols[b]);
    }
    for b in 0..6 {
        o[b][5] = d[b][5] - dot_below::<5>(&cols[5], &cols[b]);
    }
    for b in 0..7 {
        o[b][6] = d[b][6] - dot_below::<6>(&cols[6], &cols[b]);
    }
}

/// [`sub_tr_mul_from`] for the pattern [`OFF_DIAGONAL_START`].
#[inline]
pub(crate) fn sub_tr_mul_pattern(g: &V7, v: &M7, z: &[f64; DIM]) -> V7 {
    let cols = &v.data.0;
    let mut out = *g;
    for a in 0..4 {
        out[a] -= dot_below::<0>(&cols[a], z);
    }
    out[4] -= dot_below::<3>(&cols[4], z);
    out[5] -= dot_below::<5>(&cols[5], z);
    out[6] -= dot_below::<6>(&cols[6], z);
    out
}

/// `out[k] += col[k] x` for `k >= K0`.
#[inline(always)]
fn axpy_below<const K0: usize>(out: &mut [f64; DIM], col: &[f64; DIM], x: f64) {
    for k in K0..DIM {
        out[k] += col[k] * x;
    }
}

/// [`add_mul_from`] for the pattern [`OFF_DIAGONAL_START`].
#[inline]
pub(crate) fn add_mul_pattern(z: &[f64; DIM], v: &M7, x: &V7) -> [f64; DIM] {
    let cols = &v.data.0;
    let mut out = *z;
    for c in 0..4 {
        axpy_below::<0>(&mut out, &cols[c], x[c]);
    }
    axpy_below::<3>(&mut out, &cols[4], x[4]);
    axpy_below::<5>(&mut out, &cols[5], x[5]);
    axpy_below::<6>(&mut out, &cols[6], x[6]);
    out
}

/// The lower half of `d - V' V` for `V` with the leading zeros `start` (see
/// [`sub_gram_lower`]).
#[inline(always)]
pub(crate) fn sub_gram_lower_from(d: &M7, v: &M7, start: &[usize; DIM], out: &mut M7) {
    let cols = &v.data.0;
    let (d, o) = (&d.data.0, &mut out.data.0);
    for b in 0..DIM {
        for a in b..DIM {
            let mut t = 0.0;
            for k in start[a].max(start[b])..DIM {
                t += cols[a][k] * cols[b][k];
            }
            o[b][a] = d[b][a] - t;
        }
    }
}

/// `g - V' z` for `V` with the leading zeros `start`.
#[inline(always)]
pub(crate) fn sub_tr_mul_from(g: &V7, v: &M7, start: &[usize; DIM], z: &[f64; DIM]) -> V7 {
    let cols = &v.data.0;
    let mut out = *g;
    for a in 0..DIM {
        let mut t = 0.0;
        for k in start[a]..DIM {
            t += cols[a][k] * z[k];
        }
        out[a] -= t;
    }
    out
}

/// `z + V x` for `V` with the leading zeros `start`.
#[inline(always)]
pub(crate) fn add_mul_from(z: &[f64; DIM], v: &M7, start: &[usize; DIM], x: &V7) -> [f64; DIM] {
    let mut out = *z;
    for (c, col) in v.data.0.iter().enumerate() {
        let xc = x[c];
        for k in start[c]..DIM {
            out[k] += col[k] * xc;
        }
    }
    out
}

/// `g - V' z`.
#[inline]
pub(crate) fn sub_tr_mul(g: &V7, v: &M7, z: &[f64; DIM]) -> V7 {
    let cols = &v.data.0;
    let mut out = *g;
    for a in 0..DIM {
        let mut t = 0.0;
        for k in 0..DIM {
            t += cols[a][k] * z[k];
        }
        out[a] -= t;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spd(seed: u64) -> M7 {
        let mut rng = fastrand::Rng::with_seed(seed);
        let a = M7::from_fn(|_, _| rng.f64() - 0.5);
        a * a.transpose() + M7::identity() * 0.3
    }

    /// The factor, the substitutions and the products agree with nalgebra's general ones.
    #[test]
    fn agrees_with_nalgebra() {
        for seed in 0..20 {
            let s = spd(seed);
            let c = Chol7::new(&s).unwrap();
            let reference = nalgebra::Cholesky::new(s).unwrap();
            let mut rng = fastrand::Rng::with_seed(seed + 100);
            let o = M7::from_fn(|_, _| rng.f64() - 0.5);
            let g = V7::from_fn(|_, _| rng.f64() - 0.5);
            // S^-1 g through forward then backward.
            let mut x = g.data.0[0];
            c.forward(&mut x);
            c.backward(&mut x);
            let want = reference.solve(&g);
            for k in 0..DIM {
                assert!((x[k] - want[k]).abs() < 1e-10);
            }
            // V' V = O' S^-1 O, V' z = O' S^-1 g.
            let v = c.forward_columns(&o);
            let mut z = g.data.0[0];
            c.forward(&mut z);
            let schur = sub_gram(&M7::zeros(), &v);
            let want = -(o.transpose() * reference.solve(&o));
            assert!((schur - want).amax() < 1e-10);
            assert_eq!(schur, schur.transpose());
            let red = sub_tr_mul(&V7::zeros(), &v, &z);
            let want = -(o.transpose() * reference.solve(&g));
            assert!((red - want).amax() < 1e-10);
            let inv = c.inverse();
            assert!((inv - reference.inverse()).amax() < 1e-9);
            assert_eq!(inv, inv.transpose());
            let zx = add_mul_from(&z, &v, &FULL, &g);
            let vg = v * g;
            for k in 0..DIM {
                assert!((zx[k] - (z[k] + vg[k])).abs() < 1e-12);
            }
        }
    }

    /// The fixed-bound versions for the usual pattern give the same bits as the general ones.
    #[test]
    fn pattern_versions_equal_the_general_ones() {
        for seed in 0..10 {
            let c = Chol7::new(&spd(seed)).unwrap();
            let mut rng = fastrand::Rng::with_seed(seed + 200);
            let mut o = M7::from_fn(|_, _| rng.f64() - 0.5);
            for (col, &r) in o.data.0.iter_mut().zip(&OFF_DIAGONAL_START) {
                col[..r].fill(0.0);
            }
            assert!(has_pattern(&o, &OFF_DIAGONAL_START));
            let d = spd(seed + 1);
            let g = V7::from_fn(|_, _| rng.f64() - 0.5);
            let z = [0.1, -0.2, 0.3, 0.4, -0.5, 0.6, 0.7];
            let (mut v1, mut v2) = (o, o);
            c.forward_columns_from(&mut v1, &OFF_DIAGONAL_START);
            c.forward_columns_pattern(&mut v2);
            assert_eq!(v1, v2);
            let (mut s1, mut s2) = (M7::zeros(), M7::zeros());
            sub_gram_lower_from(&d, &v1, &OFF_DIAGONAL_START, &mut s1);
            sub_gram_lower_pattern(&d, &v1, &mut s2);
            assert_eq!(s1, s2);
            assert_eq!(
                sub_tr_mul_from(&g, &v1, &OFF_DIAGONAL_START, &z),
                sub_tr_mul_pattern(&g, &v1, &z)
            );
            assert_eq!(
                add_mul_from(&z, &v1, &OFF_DIAGONAL_START, &g),
                add_mul_pattern(&z, &v1, &g)
            );
        }
        let mut o = M7::from_element(1.0);
        assert!(!has_pattern(&o, &OFF_DIAGONAL_START));
        o.data.0[4][..3].fill(0.0);
        o.data.0[5][..5].fill(0.0);
        o.data.0[6][..6].fill(0.0);
        assert!(has_pattern(&o, &OFF_DIAGONAL_START));
        assert!(has_pattern(&M7::from_element(1.0), &FULL));
    }

    #[test]
    fn refuses_indefinite_and_nan() {
        let mut s = spd(3);
        s[(4, 4)] = -1.0;
        assert!(Chol7::new(&s).is_none());
        let mut s = spd(3);
        s[(2, 1)] = f64::NAN;
        s[(1, 2)] = f64::NAN;
        assert!(Chol7::new(&s).is_none());
        assert!(Chol7::new(&M7::zeros()).is_none());
    }
}
