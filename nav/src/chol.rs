//! The 7x7 block arithmetic of the window's elimination, on stack arrays: a Cholesky factor
//! computed from the lower half of a symmetric block, forward and backward substitution, and
//! the symmetric products the Schur complements need.
//!
//! Compared with a general solve of `S^-1 O` followed by `O' (S^-1 O)`, the elimination keeps
//! `V = L^-1 O` (forward substitution only) and forms `O' S^-1 O = V' V` on its lower half,
//! so every Schur complement is exactly symmetric and costs about half the products.

use crate::state::{DIM, M7, V7};

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
        let s = &s.data.0; // column-major: s[j][i] is row i, column j
        for j in 0..DIM {
            let mut d = s[j][j];
            for k in 0..j {
                d -= self.l[j][k] * self.l[j][k];
            }
            // Also refuses NaN.
            if !(d > 0.0) {
                return false;
            }
            let ljj = d.sqrt();
            let inv = 1.0 / ljj;
            self.l[j][j] = ljj;
            self.inv_diag[j] = inv;
            for i in j + 1..DIM {
                let mut v = s[j][i];
                for k in 0..j {
                    v -= self.l[i][k] * self.l[j][k];
                }
                self.l[i][j] = v * inv;
            }
        }
        true
    }

    /// `b <- L^-1 b`.
    #[inline(always)]
    pub(crate) fn forward(&self, b: &mut [f64; DIM]) {
        for i in 0..DIM {
            let mut v = b[i];
            for k in 0..i {
                v -= self.l[i][k] * b[k];
            }
            b[i] = v * self.inv_diag[i];
        }
    }

    /// `b <- L'^-1 b`.
    #[inline]
    pub(crate) fn backward(&self, b: &mut [f64; DIM]) {
        for i in (0..DIM).rev() {
            let mut v = b[i];
            for k in i + 1..DIM {
                v -= self.l[k][i] * b[k];
            }
            b[i] = v * self.inv_diag[i];
        }
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
