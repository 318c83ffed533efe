//! Gauss-Newton on the window: the normal equations of a chain of keyframes are block
//! tridiagonal (every factor joins a keyframe and the next, the prior sits on the first), so
//! they are solved by block Cholesky elimination from the oldest keyframe to the newest in
//! O(n * 7^3). The last Schur complement is the marginal information of the newest keyframe,
//! whose inverse is the covariance reported to the user.
//!
//! [`solve_batch`] is the same Gauss-Newton with a dense matrix over any number of keyframes:
//! the reference the window is tested against.

use crate::chol::{self, Chol7};
use crate::factors::{Blocks, Factor, IntervalBlocks, Linearized, PairHessian, Sink};
use crate::state::{DIM, M7, V7};
use nalgebra::{Cholesky, DMatrix, DVector};

/// A Gaussian prior on one keyframe in information form: its cost is
/// `g'd + d'Hd/2` with `d = x - xbar` (an initial prior has `g = 0`; a marginalisation prior
/// keeps the gradient it had at its linearisation point `xbar`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Prior {
    /// Information matrix.
    pub h: M7,
    /// Gradient at `xbar`.
    pub g: V7,
    /// Linearisation point.
    pub xbar: V7,
}

impl Prior {
    /// An independent prior: `mean` with per-component standard deviations `sigma`.
    pub fn diagonal(mean: V7, sigma: &[f64; DIM]) -> Prior {
        let mut h = M7::zeros();
        for k in 0..DIM {
            h[(k, k)] = 1.0 / (sigma[k] * sigma[k]);
        }
        Prior {
            h,
            g: V7::zeros(),
            xbar: mean,
        }
    }

    /// Adds the prior's Hessian and gradient at `x` to a diagonal block and its gradient.
    pub fn add_to(&self, x: &V7, h: &mut M7, g: &mut V7) {
        *h += self.h;
        *g += self.h * (x - self.xbar) + self.g;
    }

    /// The prior's cost at `x`.
    pub fn cost(&self, x: &V7) -> f64 {
        let d = x - self.xbar;
        self.g.dot(&d) + 0.5 * d.dot(&(self.h * d))
    }
}

/// Why a solve failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SolveError {
    /// A block was not positive definite (an unconstrained state or non-finite numbers).
    NotPositiveDefinite,
}

/// The block-tridiagonal normal equations of a window (buffers reused across solves).
#[derive(Debug, Default, Clone)]
pub struct BlockSystem {
    /// Diagonal blocks.
    pub d: Vec<M7>,
    /// Off-diagonal blocks: `o[k]` joins keyframes `k` and `k + 1` (a solve turns it into
    /// its `V_k`).
    pub o: Vec<M7>,
    /// Gradient blocks.
    pub g: Vec<V7>,
    /// The Cholesky factors `L_k` of the Schur complements.
    l: Vec<Chol7>,
    /// `z_k = L_k^-1 gh_k` (`gh_k` the gradient of keyframe `k` once the older ones are
    /// eliminated).
    z: Vec<[f64; DIM]>,
    /// Whether `o[k]` had the usual pattern ([`chol::OFF_DIAGONAL_START`]).
    sparse: Vec<bool>,
    /// Where the factor of the newest keyframe's marginal information is in `l` (last
    /// successful solve).
    last: Option<usize>,
}

impl BlockSystem {
    /// Clears the system for `n` keyframes, keeping the allocations.
    pub fn reset(&mut self, n: usize) {
        self.d.clear();
        self.d.resize(n, M7::zeros());
        self.o.clear();
        self.o.resize(n.saturating_sub(1), M7::zeros());
        self.g.clear();
        self.g.resize(n, V7::zeros());
    }

    /// Solves `H step = -g` into `step` by block Cholesky elimination from the oldest
    /// keyframe: with `S_0 = d[0]`, each `S_k = L_k L_k'` gives `V_k = L_k^-1 o[k]`,
    /// `z_k = L_k^-1 gh_k` and the next Schur complement `S_k+1 = d[k+1] - V_k' V_k`
    /// (`gh_k+1 = g[k+1] - V_k' z_k`); the steps come back from the newest,
    /// `step_k = -L_k'^-1 (z_k + V_k step_k+1)`. The newest keyframe's marginal information is
    /// kept for [`BlockSystem::covariance`].
    pub fn solve(&mut self, step: &mut Vec<V7>) -> Result<(), SolveError> {
        let n = self.d.len();
        step.clear();
        step.resize(n, V7::zeros());
        if n == 0 {
            self.last = None;
            return Ok(());
        }
        if self.l.len() < n {
            self.l.resize(n, Chol7::default());
            self.z.resize(n, [0.0; DIM]);
            self.sparse.resize(n, false);
        }
        let mut s = self.d[0];
        let mut gh = self.g[0];
        for k in 0..n {
            let c = &mut self.l[k];
            if !c.factor(&s) {
                return Err(SolveError::NotPositiveDefinite);
            }
            let z = &mut self.z[k];
            *z = gh.data.0[0];
            c.forward(z);
            if k + 1 < n {
                // V_k in place of o[k] (not needed after).
                let v = &mut self.o[k];
                // The usual pattern of the off-diagonal block skips its structural zeros
                // (the same sums without their exact-zero terms); any other block is full.
                let sparse = chol::has_pattern(v, &chol::OFF_DIAGONAL_START);
                self.sparse[k] = sparse;
                if sparse {
                    c.forward_columns_pattern(v);
                    chol::sub_gram_lower_pattern(&self.d[k + 1], v, &mut s);
                    gh = chol::sub_tr_mul_pattern(&self.g[k + 1], v, z);
                } else {
                    let start = &chol::FULL;
                    c.forward_columns_from(v, start);
                    chol::sub_gram_lower_from(&self.d[k + 1], v, start, &mut s);
                    gh = chol::sub_tr_mul_from(&self.g[k + 1], v, start, z);
                }
            }
        }
        let mut next = V7::zeros();
        for k in (0..n).rev() {
            let mut x = if k + 1 < n {
                let (z, v) = (&self.z[k], &self.o[k]);
                if self.sparse[k] {
                    chol::add_mul_pattern(z, v, &next)
                } else {
                    chol::add_mul_from(z, v, &chol::FULL, &next)
                }
            } else {
                self.z[k]
            };
            self.l[k].backward(&mut x);
            for e in x.iter_mut() {
                *e = -*e;
            }
            next = V7::from(x);
            step[k] = next;
        }
        if step.iter().any(|v| !v.iter().all(|e| e.is_finite())) {
            return Err(SolveError::NotPositiveDefinite);
        }
        self.last = Some(n - 1);
        Ok(())
    }

    /// The covariance of the newest keyframe (the inverse of its marginal information) at
    /// the last successful [`BlockSystem::solve`]; zero before any.
    pub fn covariance(&self) -> M7 {
        self.last.map_or_else(M7::zeros, |k| self.l[k].inverse())
    }
}

impl Blocks for BlockSystem {
    #[inline(always)]
    fn keyframe(&mut self, k: usize) -> (&mut M7, &mut V7) {
        (&mut self.d[k], &mut self.g[k])
    }

    #[inline(always)]
    fn off_diagonal(&mut self, i: usize) -> &mut M7 {
        &mut self.o[i]
    }

    #[inline(always)]
    fn interval(&mut self, i: usize) -> IntervalBlocks<'_> {
        let (d0, d1) = self.d.split_at_mut(i + 1);
        let (g0, g1) = self.g.split_at_mut(i + 1);
        IntervalBlocks {
            di: &mut d0[i],
            dj: &mut d1[0],
            o: &mut self.o[i],
            gi: &mut g0[i],
            gj: &mut g1[0],
        }
    }
}

impl BlockSystem {
    /// Starts the system for the keyframes of `pairs` (one per keyframe, oldest first) from
    /// their intervals' kept Hessian parts: `d[k] = jj[k-1] + ii[k]`, `o[k] = ij[k]` (the
    /// newest keyframe's `jj` and `ij` have no interval and are left out), zero gradients.
    pub fn reset_with<'a>(&mut self, pairs: impl Iterator<Item = &'a PairHessian>) {
        self.d.clear();
        self.o.clear();
        self.g.clear();
        let mut carry: Option<&M7> = None;
        for p in pairs {
            self.d.push(carry.map_or(p.ii, |jj| jj + p.ii));
            self.o.push(p.ij);
            self.g.push(V7::zeros());
            carry = Some(&p.jj);
        }
        self.o.pop();
    }
}

/// Dense normal equations over all keyframes (the batch reference).
#[derive(Debug, Clone)]
pub struct DenseSystem {
    /// Hessian, `7n x 7n`.
    pub h: DMatrix<f64>,
    /// Gradient, `7n`.
    pub g: DVector<f64>,
}

impl DenseSystem {
    /// A zero system for `n` keyframes.
    pub fn new(n: usize) -> DenseSystem {
        DenseSystem {
            h: DMatrix::zeros(DIM * n, DIM * n),
            g: DVector::zeros(DIM * n),
        }
    }
}

impl Sink for DenseSystem {
    fn add<const R: usize, const CI: usize, const CJ: usize>(&mut self, f: &Linearized<R, CI, CJ>) {
        let (ji, jj, r) = (f.ji.dense(), f.jj.dense(), f.r);
        let (a, b) = (DIM * f.i, DIM * (f.i + 1));
        let mut hii = self.h.fixed_view_mut::<DIM, DIM>(a, a);
        hii += ji.tr_mul(&ji);
        let mut gi = self.g.fixed_rows_mut::<DIM>(a);
        gi += ji.tr_mul(r);
        if f.touches_j {
            let mut hjj = self.h.fixed_view_mut::<DIM, DIM>(b, b);
            hjj += jj.tr_mul(&jj);
            let mut hij = self.h.fixed_view_mut::<DIM, DIM>(a, b);
            hij += ji.tr_mul(&jj);
            let mut hji = self.h.fixed_view_mut::<DIM, DIM>(b, a);
            hji += jj.tr_mul(&ji);
            let mut gj = self.g.fixed_rows_mut::<DIM>(b);
            gj += jj.tr_mul(r);
        }
    }
}

/// A factor on keyframe `i` (and `i + 1`), for [`solve_batch`].
pub type IndexedFactor = (usize, Factor);

/// Total cost of a problem (prior on keyframe 0 plus the factors).
pub fn total_cost(states: &[V7], prior: &Prior, factors: &[IndexedFactor]) -> f64 {
    let mut c = prior.cost(&states[0]);
    for (i, f) in factors {
        let xj = states.get(i + 1).unwrap_or(&states[*i]);
        c += f.cost(&states[*i], xj);
    }
    c
}

/// Dense batch Gauss-Newton over all `states` (updated in place) with `prior` on keyframe 0.
/// Stops when the largest step component is below `tol` or after `max_iter` iterations;
/// returns the iterations run.
pub fn solve_batch(
    states: &mut [V7],
    prior: &Prior,
    factors: &[IndexedFactor],
    max_iter: usize,
    tol: f64,
) -> Result<usize, SolveError> {
    let n = states.len();
    for it in 0..max_iter {
        let mut sys = DenseSystem::new(n);
        for (i, f) in factors {
            let xj = states.get(i + 1).copied().unwrap_or(states[*i]);
            f.linearize(*i, &states[*i], &xj, &mut sys);
        }
        let mut h0 = M7::zeros();
        let mut g0 = V7::zeros();
        prior.add_to(&states[0], &mut h0, &mut g0);
        let mut b = sys.h.fixed_view_mut::<DIM, DIM>(0, 0);
        b += h0;
        let mut gb = sys.g.fixed_rows_mut::<DIM>(0);
        gb += g0;
        let c = Cholesky::new(sys.h).ok_or(SolveError::NotPositiveDefinite)?;
        let step = -c.solve(&sys.g);
        let mut biggest: f64 = 0.0;
        for (k, x) in states.iter_mut().enumerate() {
            let d = step.fixed_rows::<DIM>(DIM * k);
            *x += d;
            biggest = biggest.max(d.amax());
        }
        if !biggest.is_finite() {
            return Err(SolveError::NotPositiveDefinite);
        }
        if biggest < tol {
            return Ok(it + 1);
        }
    }
    Ok(max_iter)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::factors::Jac;
    use nalgebra::SVector;

    /// The blocks assembled from the Jacobians' non-zero columns are, bit for bit, those of the
    /// full `R x 7` Jacobians (the dense system), for every kind of factor, accumulated.
    #[test]
    fn compact_assembly_equals_full_jacobians_bit_for_bit() {
        use crate::factors::{DepthObs, GpsPosition, Heading, Odometry, RandomWalk, YawIncrement};
        let mut rng = fastrand::Rng::with_seed(11);
        let mut v = || rng.f64() * 2.0 - 1.0;
        let n = 3;
        let states: Vec<V7> = (0..n).map(|_| V7::from_fn(|_, _| v())).collect();
        let mut factors = Vec::new();
        for i in 0..n - 1 {
            for alpha in [0.0, 0.3] {
                factors.push((
                    i,
                    Factor::Heading(Heading {
                        alpha,
                        yaw_rad: v(),
                        sigma_rad: 0.02,
                    }),
                ));
                factors.push((
                    i,
                    Factor::Depth(DepthObs {
                        alpha,
                        depth_m: v(),
                        sigma_m: 0.05,
                    }),
                ));
                // One GPS inside the Huber threshold, one far outside.
                for far in [0.0, 40.0] {
                    factors.push((
                        i,
                        Factor::Gps(GpsPosition {
                            alpha,
                            x_m: v() + far,
                            y_m: v(),
                            sigma_m: 1.5,
                            huber_k: 1.345,
                        }),
                    ));
                }
            }
            factors.push((
                i,
                Factor::Odometry(Odometry {
                    dt_s: 0.2,
                    u_i: [1.4, v(), v()],
                    u_j: [1.5, v(), v()],
                    water_i: true,
                    water_j: i == 0,
                    sigma_m: [0.01, 0.02, 0.03],
                }),
            ));
            factors.push((
                i,
                Factor::RandomWalk(RandomWalk {
                    dt_s: 0.2,
                    bias_rad_per_sqrt_s: 1e-4,
                    current_mps_per_sqrt_s: 1e-3,
                }),
            ));
            factors.push((
                i,
                Factor::YawIncrement(YawIncrement {
                    dpsi_rad: v(),
                    sigma_rad: 0.01,
                }),
            ));
        }
        let mut bs = BlockSystem::default();
        bs.reset(n);
        let mut ds = DenseSystem::new(n);
        for (i, f) in &factors {
            f.linearize(*i, &states[*i], &states[i + 1], &mut bs);
            f.linearize(*i, &states[*i], &states[i + 1], &mut ds);
        }
        for i in 0..n {
            for a in 0..DIM {
                assert_eq!(bs.g[i][a].to_bits(), ds.g[DIM * i + a].to_bits());
                for b in 0..DIM {
                    let h = ds.h[(DIM * i + a, DIM * i + b)];
                    assert_eq!(bs.d[i][(a, b)].to_bits(), h.to_bits(), "d[{i}]({a},{b})");
                    if i + 1 < n {
                        let h = ds.h[(DIM * i + a, DIM * (i + 1) + b)];
                        assert_eq!(bs.o[i][(a, b)].to_bits(), h.to_bits(), "o[{i}]({a},{b})");
                    }
                }
            }
        }
    }

    /// The block elimination and the dense Cholesky solve agree on a random SPD chain.
    #[test]
    fn block_solve_equals_dense_solve() {
        let mut rng = fastrand::Rng::with_seed(7);
        let n = 6;
        let mut bs = BlockSystem::default();
        bs.reset(n);
        let mut ds = DenseSystem::new(n);
        for i in 0..n - 1 {
            for _ in 0..3 {
                let mut r = SVector::<f64, 4>::zeros();
                let mut ji = Jac::<4, DIM>::zeros([0, 1, 2, 3, 4, 5, 6]);
                let mut jj = Jac::<4, 3>::zeros([6, 1, 3]);
                for e in r.iter_mut().chain(ji.m.iter_mut()).chain(jj.m.iter_mut()) {
                    *e = rng.f64() - 0.5;
                }
                let f = Linearized {
                    i,
                    r: &r,
                    ji: &ji,
                    jj: &jj,
                    touches_j: true,
                };
                bs.add(&f);
                ds.add(&f);
            }
        }
        for i in 0..n {
            for k in 0..DIM {
                bs.d[i][(k, k)] += 0.5;
                ds.h[(DIM * i + k, DIM * i + k)] += 0.5;
            }
        }
        let mut step = Vec::new();
        bs.solve(&mut step).unwrap();
        let cov = bs.covariance();
        let full = ds.h.clone().cholesky().unwrap();
        let dense = -full.solve(&ds.g);
        let inv = full.inverse();
        for i in 0..n {
            for k in 0..DIM {
                assert!((step[i][k] - dense[DIM * i + k]).abs() < 1e-9);
            }
        }
        let last = DIM * (n - 1);
        for a in 0..DIM {
            for b in 0..DIM {
                assert!((cov[(a, b)] - inv[(last + a, last + b)]).abs() < 1e-9);
            }
        }
    }
}
