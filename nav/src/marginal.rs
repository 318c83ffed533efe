//! Marginalisation of the oldest keyframe by Schur complement.
//!
//! The oldest keyframe `0` is joined only to keyframe `1` (by its own factors) and carries the
//! window's prior. Linearising the prior and those factors at the current estimate gives a
//! 14-variable Gaussian; eliminating keyframe `0` leaves a Gaussian on keyframe `1`:
//! `H' = H11 - H10 H00^-1 H01`, `g' = g1 - H10 H00^-1 g0`, linearised at `x1`. The prior keeps
//! that linearisation point for ever (its Jacobian is the identity), while the factors that
//! remain on keyframe `1` are relinearised at each iteration: with heading observed by the AHRS
//! and position by GPS there is no unobservable direction the mix could make look observable,
//! and the only nonlinearity left (the heading in the odometry) is mild over a window.

use crate::chol::{self, Chol7};
use crate::factors::{Blocks, Factor, IntervalBlocks, PairHessian};
use crate::solver::Prior;
use crate::state::{M7, V7};

/// A two-keyframe system (keyframes 0 and 1) for marginalising keyframe 0.
#[derive(Debug, Default, Clone)]
struct PairSystem {
    h00: M7,
    h01: M7,
    h11: M7,
    g0: V7,
    g1: V7,
}

impl Blocks for PairSystem {
    #[inline(always)]
    fn keyframe(&mut self, k: usize) -> (&mut M7, &mut V7) {
        debug_assert!(k <= 1);
        if k == 0 {
            (&mut self.h00, &mut self.g0)
        } else {
            (&mut self.h11, &mut self.g1)
        }
    }

    #[inline(always)]
    fn off_diagonal(&mut self, i: usize) -> &mut M7 {
        debug_assert_eq!(i, 0);
        &mut self.h01
    }

    #[inline(always)]
    fn interval(&mut self, i: usize) -> IntervalBlocks<'_> {
        debug_assert_eq!(i, 0);
        IntervalBlocks {
            di: &mut self.h00,
            dj: &mut self.h11,
            o: &mut self.h01,
            gi: &mut self.g0,
            gj: &mut self.g1,
        }
    }
}

/// Marginalises keyframe 0 (state `x0`, carrying `prior` and `factors`) onto keyframe 1
/// (state `x1`). Returns `None` when keyframe 0's information is not positive definite.
pub fn marginalize_first<'a>(
    prior: &Prior,
    x0: &V7,
    x1: &V7,
    factors: impl IntoIterator<Item = &'a Factor>,
) -> Option<Prior> {
    marginalize_first_kept(prior, x0, x1, factors, None)
}

/// [`marginalize_first`] given the Hessian part of the factors with constant Jacobians
/// ([`Factor::constant_jacobian`]) already assembled, when `kept` is given: those factors
/// then add only their gradients.
pub fn marginalize_first_kept<'a>(
    prior: &Prior,
    x0: &V7,
    x1: &V7,
    factors: impl IntoIterator<Item = &'a Factor>,
    kept: Option<&PairHessian>,
) -> Option<Prior> {
    let mut s = PairSystem::default();
    if let Some(k) = kept {
        s.h00 = k.ii;
        s.h11 = k.jj;
        s.h01 = k.ij;
    }
    prior.add_to(x0, &mut s.h00, &mut s.g0);
    for f in factors {
        if kept.is_some() && f.constant_jacobian() {
            f.linearize_gradient(0, x0, x1, &mut s);
        } else {
            f.linearize(0, x0, x1, &mut s);
        }
    }
    // H10 H00^-1 H01 = V'V and H10 H00^-1 g0 = V'z with V = L^-1 H01, z = L^-1 g0: the
    // result is exactly symmetric.
    let c = Chol7::new(&s.h00)?;
    let v = c.forward_columns(&s.h01);
    let mut z = s.g0.data.0[0];
    c.forward(&mut z);
    let h = chol::sub_gram(&s.h11, &v);
    let g = chol::sub_tr_mul(&s.g1, &v, &z);
    if !h.iter().chain(g.iter()).all(|v| v.is_finite()) {
        return None;
    }
    Some(Prior { h, g, xbar: *x1 })
}
