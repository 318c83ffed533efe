//! The factors: residuals with analytic Jacobians, whitened by their noise.
//!
//! Every factor sits between keyframe `i` and the next keyframe `j = i + 1` (the window is a
//! chain): odometry and random walks join the two; a measurement at time `t` with
//! `t_i <= t <= t_j` is attached by linear interpolation of the two states with
//! `alpha = (t - t_i) / (t_j - t_i)`, so measurements of any rate, delay or phase are used at
//! their own time. With `alpha = 0` a factor touches `i` only (its `j` Jacobian is zero).
//!
//! Residuals are `prediction - measurement` divided by the standard deviation; angles are wrapped
//! to (-pi, pi]. The GPS factor's robust (Huber) kernel is applied when it is linearised into the
//! normal equations (iteratively reweighted), not in [`GpsPosition::residual`], so the Jacobian
//! tests see the plain whitened residual.

use crate::state::{
    BIAS, CX, CY, DIM, M7, PSI, V7, X, Y, Z, level_to_grid, level_to_grid_dpsi, wrap_pi,
};
use nalgebra::{SMatrix, SVector};

/// A factor's Jacobian on one keyframe restricted to the state columns it can be non-zero in:
/// column `c` of `m` is the derivative with respect to state component `cols[c]` (every other
/// component's derivative is exactly zero). The normal equations are assembled from these
/// small blocks: the same products as the full `R x 7` Jacobian gives, without the zeros.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Jac<const R: usize, const C: usize> {
    /// The state components (indices into a keyframe's state) of the columns.
    pub cols: [usize; C],
    /// The non-zero columns.
    pub m: SMatrix<f64, R, C>,
}

impl<const R: usize, const C: usize> Jac<R, C> {
    /// A zero Jacobian on the components `cols`.
    pub fn zeros(cols: [usize; C]) -> Self {
        Jac {
            cols,
            m: SMatrix::zeros(),
        }
    }

    /// The full `R x 7` Jacobian.
    pub fn dense(&self) -> SMatrix<f64, R, DIM> {
        let mut d = SMatrix::<f64, R, DIM>::zeros();
        for (c, &col) in self.cols.iter().enumerate() {
            d.set_column(col, &self.m.column(c));
        }
        d
    }

    /// The Jacobian scaled by `w`.
    pub fn scaled(&self, w: f64) -> Self {
        Jac {
            cols: self.cols,
            m: self.m * w,
        }
    }
}

/// `h += a' b` for Jacobians on their non-zero columns: the products of the full Jacobians
/// (bit for bit: each entry is the same dot product over the rows; the entries left out are
/// exact zeros).
pub fn add_outer<const R: usize, const CA: usize, const CB: usize>(
    h: &mut M7,
    a: &Jac<R, CA>,
    b: &Jac<R, CB>,
) {
    let t = a.m.tr_mul(&b.m);
    for (q, &cb) in b.cols.iter().enumerate() {
        for (p, &ra) in a.cols.iter().enumerate() {
            h[(ra, cb)] += t[(p, q)];
        }
    }
}

/// `h += a' a` for a Jacobian on its non-zero columns: [`add_outer`] of `a` with itself, each
/// dot product computed once for the two symmetric entries (the same dot product nalgebra's
/// `tr_mul` computes for either, so the same bits).
pub fn add_gram<const R: usize, const C: usize>(h: &mut M7, a: &Jac<R, C>) {
    for q in 0..C {
        let cq = a.m.column(q);
        for p in 0..q {
            let t = a.m.column(p).dot(&cq);
            h[(a.cols[p], a.cols[q])] += t;
            h[(a.cols[q], a.cols[p])] += t;
        }
        h[(a.cols[q], a.cols[q])] += cq.dot(&cq);
    }
}

/// `g += a' r` for a Jacobian on its non-zero columns.
pub fn add_gradient<const R: usize, const C: usize>(
    g: &mut V7,
    a: &Jac<R, C>,
    r: &SVector<f64, R>,
) {
    let t = a.m.tr_mul(r);
    for (p, &ra) in a.cols.iter().enumerate() {
        g[ra] += t[p];
    }
}

/// One linearised factor: its whitened residual and its Jacobians on keyframes `i` and
/// `i + 1` (on their non-zero columns); a factor with `touches_j` false is on `i` only (its
/// `jj` is zero).
#[derive(Debug, Clone, Copy)]
pub struct Linearized<'a, const R: usize, const CI: usize, const CJ: usize> {
    /// The first keyframe.
    pub i: usize,
    /// The whitened residual.
    pub r: &'a SVector<f64, R>,
    /// The Jacobian on `i`.
    pub ji: &'a Jac<R, CI>,
    /// The Jacobian on `i + 1`.
    pub jj: &'a Jac<R, CJ>,
    /// Whether the factor involves `i + 1`.
    pub touches_j: bool,
}

/// Receives linearised factors.
pub trait Sink {
    /// Adds one factor of `R` rows.
    fn add<const R: usize, const CI: usize, const CJ: usize>(&mut self, f: &Linearized<R, CI, CJ>);

    /// Adds an odometry factor on `i` and `i + 1` ([`Odometry::jac`]'s Jacobians, whose only
    /// non-zero entries are the first three columns' diagonals, the heading column and, on
    /// `i`, the current's two entries). The default is [`Sink::add`]; a sink may use the
    /// pattern.
    fn add_odometry(&mut self, i: usize, r: &SVector<f64, 3>, ji: &Jac<3, 6>, jj: &Jac<3, 4>) {
        self.add(&Linearized {
            i,
            r,
            ji,
            jj,
            touches_j: true,
        });
    }
}

/// The five blocks of the normal equations one interval (keyframes `i` and `j = i + 1`)
/// writes into.
#[derive(Debug)]
pub struct IntervalBlocks<'a> {
    /// The diagonal block of `i`.
    pub di: &'a mut M7,
    /// The diagonal block of `j`.
    pub dj: &'a mut M7,
    /// The off-diagonal block joining `i` and `j` (row `i`, column `j`).
    pub o: &'a mut M7,
    /// The gradient of `i`.
    pub gi: &'a mut V7,
    /// The gradient of `j`.
    pub gj: &'a mut V7,
}

/// Normal equations kept as 7x7 blocks, per keyframe (diagonal block and gradient) and per
/// interval (the off-diagonal block): the window's [`crate::solver::BlockSystem`] and the
/// marginalisation's pair. Every such store is a [`Sink`] (factors assembled with
/// [`add_gram`], [`add_outer`] and [`add_gradient`], the odometry by its pattern), and
/// [`GradientOnly`] of one a sink of the gradients alone.
pub trait Blocks {
    /// The diagonal block and the gradient of keyframe `k`.
    fn keyframe(&mut self, k: usize) -> (&mut M7, &mut V7);
    /// The off-diagonal block joining keyframes `i` and `i + 1`.
    fn off_diagonal(&mut self, i: usize) -> &mut M7;
    /// All the blocks of the interval from keyframe `i`.
    fn interval(&mut self, i: usize) -> IntervalBlocks<'_>;
}

/// Adds a linearised factor to blocks: its gradient `J' r`, and its Hessian part `J' J`
/// when `HESSIAN`.
#[inline(always)]
fn assemble<
    B: Blocks + ?Sized,
    const HESSIAN: bool,
    const R: usize,
    const CI: usize,
    const CJ: usize,
>(
    b: &mut B,
    f: &Linearized<R, CI, CJ>,
) {
    let (d, g) = b.keyframe(f.i);
    if HESSIAN {
        add_gram(d, f.ji);
    }
    add_gradient(g, f.ji, f.r);
    if f.touches_j {
        let (d, g) = b.keyframe(f.i + 1);
        if HESSIAN {
            add_gram(d, f.jj);
        }
        add_gradient(g, f.jj, f.r);
        if HESSIAN {
            add_outer(b.off_diagonal(f.i), f.ji, f.jj);
        }
    }
}

impl<B: Blocks> Sink for B {
    #[inline]
    fn add<const R: usize, const CI: usize, const CJ: usize>(&mut self, f: &Linearized<R, CI, CJ>) {
        assemble::<B, true, R, CI, CJ>(self, f);
    }

    #[inline]
    fn add_odometry(&mut self, i: usize, r: &SVector<f64, 3>, ji: &Jac<3, 6>, jj: &Jac<3, 4>) {
        odometry_blocks(r, ji, jj, self.interval(i));
    }
}

/// The gradient part alone (`J' r`) of the factors added to it, into the blocks' gradients,
/// for factors whose Hessian part is kept ([`Factor::constant_jacobian`]).
#[derive(Debug)]
pub struct GradientOnly<'a, B: ?Sized>(pub &'a mut B);

impl<B: Blocks + ?Sized> Sink for GradientOnly<'_, B> {
    #[inline]
    fn add<const R: usize, const CI: usize, const CJ: usize>(&mut self, f: &Linearized<R, CI, CJ>) {
        assemble::<B, false, R, CI, CJ>(self.0, f);
    }
}

/// The odometry's normal-equation entries from the non-zero entries of its Jacobians (see
/// [`Sink::add_odometry`]): each the dot product the full Jacobians give, with the same
/// order of sums (`(a + b) + c`, the terms that are exact zeros left out), so the same bits.
fn odometry_blocks(r: &SVector<f64, 3>, ji: &Jac<3, 6>, jj: &Jac<3, 4>, b: IntervalBlocks<'_>) {
    debug_assert_eq!(ji.cols, [0, 1, 2, PSI, CX, CY]);
    debug_assert_eq!(jj.cols, [0, 1, 2, PSI]);
    let IntervalBlocks { di, dj, o, gi, gj } = b;
    let (mi, mj) = (&ji.m, &jj.m);
    let a = [mi[(0, 0)], mi[(1, 1)], mi[(2, 2)]];
    let p = [mi[(0, 3)], mi[(1, 3)], mi[(2, 3)]];
    let (c0, c1) = (mi[(0, 4)], mi[(1, 5)]);
    let b = [mj[(0, 0)], mj[(1, 1)], mj[(2, 2)]];
    let q = [mj[(0, 3)], mj[(1, 3)], mj[(2, 3)]];
    let dot = |u: &[f64; 3], v: &[f64; 3]| u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    let rv = [r[0], r[1], r[2]];
    for k in 0..3 {
        di[(k, k)] += a[k] * a[k];
        let e = a[k] * p[k];
        di[(k, PSI)] += e;
        di[(PSI, k)] += e;
        dj[(k, k)] += b[k] * b[k];
        let e = b[k] * q[k];
        dj[(k, PSI)] += e;
        dj[(PSI, k)] += e;
        o[(k, k)] += a[k] * b[k];
        o[(k, PSI)] += a[k] * q[k];
        o[(PSI, k)] += p[k] * b[k];
        gi[k] += a[k] * rv[k];
        gj[k] += b[k] * rv[k];
    }
    di[(PSI, PSI)] += dot(&p, &p);
    // The current's two entries on i, each on its own axis.
    for (k, c, w) in [(0, CX, c0), (1, CY, c1)] {
        let e = a[k] * w;
        di[(k, c)] += e;
        di[(c, k)] += e;
        let e = p[k] * w;
        di[(PSI, c)] += e;
        di[(c, PSI)] += e;
        di[(c, c)] += w * w;
        o[(c, k)] += w * b[k];
        o[(c, PSI)] += w * q[k];
        gi[c] += w * rv[k];
    }
    dj[(PSI, PSI)] += dot(&q, &q);
    o[(PSI, PSI)] += dot(&p, &q);
    gi[PSI] += dot(&p, &rv);
    gj[PSI] += dot(&q, &rv);
}

/// The Hessian part `J' J` of the factors of one interval (keyframes `i` and `j = i + 1`):
/// a [`Sink`] that ignores the residuals. For factors with constant Jacobians it does not
/// change between Gauss-Newton iterations or keyframe updates, so the window keeps it per
/// interval until a factor is added.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairHessian {
    /// `J_i' J_i`.
    pub ii: M7,
    /// `J_j' J_j`.
    pub jj: M7,
    /// `J_i' J_j`.
    pub ij: M7,
}

impl Default for PairHessian {
    fn default() -> Self {
        PairHessian {
            ii: M7::zeros(),
            jj: M7::zeros(),
            ij: M7::zeros(),
        }
    }
}

impl Sink for PairHessian {
    fn add<const R: usize, const CI: usize, const CJ: usize>(&mut self, f: &Linearized<R, CI, CJ>) {
        add_gram(&mut self.ii, f.ji);
        if f.touches_j {
            add_gram(&mut self.jj, f.jj);
            add_outer(&mut self.ij, f.ji, f.jj);
        }
    }
}

/// The gradient of an interval's depth and random-walk factors, which are affine in the
/// states (no wrap, constant Jacobians, each row on one state component of `i` and the same
/// of `j`): per component z, bias, current east and north, the gradient is
/// `g_i = A x_i + B x_j - e`, `g_j = B x_i + C x_j - f`, summed once over the factors instead
/// of evaluated factor by factor at every iteration (the same sums in another order).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct AffineGradient {
    /// `[A, B, C, e, f]` per component of [`AffineGradient::COMPONENTS`].
    rows: [[f64; 5]; 4],
}

impl AffineGradient {
    /// The state components, in the order of the rows.
    pub const COMPONENTS: [usize; 4] = [Z, BIAS, CX, CY];

    /// Whether [`AffineGradient::add_factor`] takes the factor (depth, random walk).
    pub fn takes(f: &Factor) -> bool {
        matches!(f, Factor::Depth(_) | Factor::RandomWalk(_))
    }

    /// Adds a factor's row `r = wi x_i[c] + wj x_j[c] - m` on component slot `slot`.
    fn add_row(&mut self, slot: usize, wi: f64, wj: f64, m: f64) {
        let row = &mut self.rows[slot];
        row[0] += wi * wi;
        row[1] += wi * wj;
        row[2] += wj * wj;
        row[3] += wi * m;
        row[4] += wj * m;
    }

    /// Adds a depth or random-walk factor; returns false (adding nothing) for any other.
    pub fn add_factor(&mut self, f: &Factor) -> bool {
        match f {
            Factor::Depth(d) => {
                let (ji, jj) = d.jac();
                self.add_row(0, ji.m[0], jj.m[0], d.depth_m / d.sigma_m);
                true
            }
            Factor::RandomWalk(w) => {
                let (ji, jj) = w.jac();
                for k in 0..3 {
                    self.add_row(1 + k, ji.m[(k, k)], jj.m[(k, k)], 0.0);
                }
                true
            }
            _ => false,
        }
    }

    /// Adds the gradient at `xi`, `xj` to `gi` (and `gj`, when keyframe `j` exists).
    pub fn add_to(&self, xi: &V7, xj: &V7, gi: &mut V7, gj: Option<&mut V7>) {
        for (row, &c) in self.rows.iter().zip(&Self::COMPONENTS) {
            gi[c] += row[0] * xi[c] + row[1] * xj[c] - row[3];
        }
        if let Some(gj) = gj {
            for (row, &c) in self.rows.iter().zip(&Self::COMPONENTS) {
                gj[c] += row[1] * xi[c] + row[2] * xj[c] - row[4];
            }
        }
    }
}

/// DVL (or dead-reckoned) odometry between keyframes `i` and `j`: the displacement is the
/// trapezoid of the two keyframes' level-frame velocities rotated by their estimated headings,
/// plus the current (of keyframe `i`) for each velocity measured through the water.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Odometry {
    /// `t_j - t_i`, seconds.
    pub dt_s: f64,
    /// Level-frame velocity at `i`, m/s `[forward, starboard, down]`.
    pub u_i: [f64; 3],
    /// Level-frame velocity at `j`.
    pub u_j: [f64; 3],
    /// Whether `u_i` is through the water (the current is added).
    pub water_i: bool,
    /// Whether `u_j` is through the water.
    pub water_j: bool,
    /// Standard deviation of the displacement, metres, per axis (east, north, down).
    pub sigma_m: [f64; 3],
}

impl Odometry {
    fn current_weight(&self) -> f64 {
        0.5 * self.dt_s * (f64::from(u8::from(self.water_i)) + f64::from(u8::from(self.water_j)))
    }

    /// The whitened residual.
    pub fn residual(&self, xi: &V7, xj: &V7) -> SVector<f64, 3> {
        let a = level_to_grid(xi[PSI], &self.u_i);
        let b = level_to_grid(xj[PSI], &self.u_j);
        self.residual_from(xi, xj, &a, &b)
    }

    /// The residual from the two velocities already on the grid.
    fn residual_from(&self, xi: &V7, xj: &V7, a: &[f64; 3], b: &[f64; 3]) -> SVector<f64, 3> {
        let w = self.current_weight();
        let h = 0.5 * self.dt_s;
        let cur = [xi[CX], xi[CY], 0.0];
        let mut r = SVector::<f64, 3>::zeros();
        for k in 0..3 {
            let pred = h * (a[k] + b[k]) + w * cur[k];
            r[k] = (xj[X + k] - xi[X + k] - pred) / self.sigma_m[k];
        }
        r
    }

    /// The Jacobians of [`Odometry::residual`] on `i` and `j`.
    pub fn jacobians(&self, xi: &V7, xj: &V7) -> (SMatrix<f64, 3, DIM>, SMatrix<f64, 3, DIM>) {
        let (ji, jj) = self.jac(xi, xj);
        (ji.dense(), jj.dense())
    }

    /// [`Odometry::jacobians`] on their non-zero columns: x, y, z, heading and the current on
    /// `i`; x, y, z and heading on `j`.
    pub fn jac(&self, xi: &V7, xj: &V7) -> (Jac<3, 6>, Jac<3, 4>) {
        let da = level_to_grid_dpsi(xi[PSI], &self.u_i);
        let db = level_to_grid_dpsi(xj[PSI], &self.u_j);
        self.jac_from(&da, &db)
    }

    /// [`Odometry::residual`] and [`Odometry::jac`] together, each heading's sine and cosine
    /// computed once (the same bits as the two calls).
    pub fn linearized(&self, xi: &V7, xj: &V7) -> (SVector<f64, 3>, Jac<3, 6>, Jac<3, 4>) {
        let (si, ci) = xi[PSI].sin_cos();
        let (sj, cj) = xj[PSI].sin_cos();
        let (ui, uj) = (&self.u_i, &self.u_j);
        // level_to_grid and level_to_grid_dpsi, written out on the shared sines and cosines.
        let a = [si * ui[0] + ci * ui[1], ci * ui[0] - si * ui[1], ui[2]];
        let b = [sj * uj[0] + cj * uj[1], cj * uj[0] - sj * uj[1], uj[2]];
        let da = [ci * ui[0] - si * ui[1], -si * ui[0] - ci * ui[1], 0.0];
        let db = [cj * uj[0] - sj * uj[1], -sj * uj[0] - cj * uj[1], 0.0];
        let (ji, jj) = self.jac_from(&da, &db);
        (self.residual_from(xi, xj, &a, &b), ji, jj)
    }

    fn jac_from(&self, da: &[f64; 3], db: &[f64; 3]) -> (Jac<3, 6>, Jac<3, 4>) {
        let h = 0.5 * self.dt_s;
        let w = self.current_weight();
        let mut ji = Jac::zeros([X, Y, Z, PSI, CX, CY]);
        let mut jj = Jac::zeros([X, Y, Z, PSI]);
        for k in 0..3 {
            let s = 1.0 / self.sigma_m[k];
            ji.m[(k, k)] = -s;
            jj.m[(k, k)] = s;
            ji.m[(k, 3)] = -h * da[k] * s;
            jj.m[(k, 3)] = -h * db[k] * s;
        }
        ji.m[(0, 4)] = -w / self.sigma_m[0];
        ji.m[(1, 5)] = -w / self.sigma_m[1];
        (ji, jj)
    }
}

/// The gyro's heading increment between keyframes `i` and `j`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct YawIncrement {
    /// Integrated heading rate over the interval, radians.
    pub dpsi_rad: f64,
    /// Standard deviation, radians.
    pub sigma_rad: f64,
}

impl YawIncrement {
    /// The whitened residual.
    pub fn residual(&self, xi: &V7, xj: &V7) -> SVector<f64, 1> {
        SVector::<f64, 1>::new(wrap_pi(xj[PSI] - xi[PSI] - self.dpsi_rad) / self.sigma_rad)
    }

    /// The Jacobians on `i` and `j`.
    pub fn jacobians(&self) -> (SMatrix<f64, 1, DIM>, SMatrix<f64, 1, DIM>) {
        let (ji, jj) = self.jac();
        (ji.dense(), jj.dense())
    }

    /// [`YawIncrement::jacobians`] on their non-zero column (the heading).
    pub fn jac(&self) -> (Jac<1, 1>, Jac<1, 1>) {
        let mut ji = Jac::zeros([PSI]);
        let mut jj = Jac::zeros([PSI]);
        ji.m[0] = -1.0 / self.sigma_rad;
        jj.m[0] = 1.0 / self.sigma_rad;
        (ji, jj)
    }
}

/// Random walk of the slow states (heading bias, current) between keyframes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RandomWalk {
    /// `t_j - t_i`, seconds.
    pub dt_s: f64,
    /// Bias random walk, rad per square-root second.
    pub bias_rad_per_sqrt_s: f64,
    /// Current random walk, m/s per square-root second.
    pub current_mps_per_sqrt_s: f64,
}

impl RandomWalk {
    fn sigmas(&self) -> [f64; 3] {
        let s = self.dt_s.max(1e-6).sqrt();
        let c = self.current_mps_per_sqrt_s * s;
        [self.bias_rad_per_sqrt_s * s, c, c]
    }

    /// The whitened residual.
    pub fn residual(&self, xi: &V7, xj: &V7) -> SVector<f64, 3> {
        let s = self.sigmas();
        SVector::<f64, 3>::new(
            (xj[BIAS] - xi[BIAS]) / s[0],
            (xj[CX] - xi[CX]) / s[1],
            (xj[CY] - xi[CY]) / s[2],
        )
    }

    /// The Jacobians on `i` and `j`.
    pub fn jacobians(&self) -> (SMatrix<f64, 3, DIM>, SMatrix<f64, 3, DIM>) {
        let (ji, jj) = self.jac();
        (ji.dense(), jj.dense())
    }

    /// [`RandomWalk::jacobians`] on their non-zero columns (bias and current).
    pub fn jac(&self) -> (Jac<3, 3>, Jac<3, 3>) {
        let s = self.sigmas();
        let mut ji = Jac::zeros([BIAS, CX, CY]);
        let mut jj = Jac::zeros([BIAS, CX, CY]);
        for (k, sk) in s.iter().enumerate() {
            ji.m[(k, k)] = -1.0 / sk;
            jj.m[(k, k)] = 1.0 / sk;
        }
        (ji, jj)
    }
}

/// An AHRS yaw: measured yaw = heading + heading bias (both interpolated at the measurement's
/// time).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Heading {
    /// Interpolation weight of keyframe `j`, in [0, 1].
    pub alpha: f64,
    /// Measured yaw, radians (compass, NED).
    pub yaw_rad: f64,
    /// Standard deviation of the white part, radians.
    pub sigma_rad: f64,
}

impl Heading {
    /// The whitened residual.
    pub fn residual(&self, xi: &V7, xj: &V7) -> SVector<f64, 1> {
        let a = self.alpha;
        let psi = (1.0 - a) * xi[PSI] + a * xj[PSI];
        let b = (1.0 - a) * xi[BIAS] + a * xj[BIAS];
        SVector::<f64, 1>::new(wrap_pi(psi + b - self.yaw_rad) / self.sigma_rad)
    }

    /// The Jacobians on `i` and `j`.
    pub fn jacobians(&self) -> (SMatrix<f64, 1, DIM>, SMatrix<f64, 1, DIM>) {
        let (ji, jj) = self.jac();
        (ji.dense(), jj.dense())
    }

    /// [`Heading::jacobians`] on their non-zero columns (heading and bias).
    pub fn jac(&self) -> (Jac<1, 2>, Jac<1, 2>) {
        let s = 1.0 / self.sigma_rad;
        let mut ji = Jac::zeros([PSI, BIAS]);
        let mut jj = Jac::zeros([PSI, BIAS]);
        ji.m[0] = (1.0 - self.alpha) * s;
        ji.m[1] = (1.0 - self.alpha) * s;
        jj.m[0] = self.alpha * s;
        jj.m[1] = self.alpha * s;
        (ji, jj)
    }
}

/// A depth measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthObs {
    /// Interpolation weight of keyframe `j`, in [0, 1].
    pub alpha: f64,
    /// Measured depth, metres (down).
    pub depth_m: f64,
    /// Standard deviation, metres.
    pub sigma_m: f64,
}

impl DepthObs {
    /// The whitened residual.
    pub fn residual(&self, xi: &V7, xj: &V7) -> SVector<f64, 1> {
        let z = (1.0 - self.alpha) * xi[Z] + self.alpha * xj[Z];
        SVector::<f64, 1>::new((z - self.depth_m) / self.sigma_m)
    }

    /// The Jacobians on `i` and `j`.
    pub fn jacobians(&self) -> (SMatrix<f64, 1, DIM>, SMatrix<f64, 1, DIM>) {
        let (ji, jj) = self.jac();
        (ji.dense(), jj.dense())
    }

    /// [`DepthObs::jacobians`] on their non-zero column (the depth).
    pub fn jac(&self) -> (Jac<1, 1>, Jac<1, 1>) {
        let mut ji = Jac::zeros([Z]);
        let mut jj = Jac::zeros([Z]);
        ji.m[0] = (1.0 - self.alpha) / self.sigma_m;
        jj.m[0] = self.alpha / self.sigma_m;
        (ji, jj)
    }
}

/// A GPS horizontal position, with a Huber kernel on the whitened residual's norm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GpsPosition {
    /// Interpolation weight of keyframe `j`, in [0, 1].
    pub alpha: f64,
    /// Measured east, metres.
    pub x_m: f64,
    /// Measured north, metres.
    pub y_m: f64,
    /// Standard deviation per axis, metres.
    pub sigma_m: f64,
    /// Huber threshold on the whitened residual norm (1.345 as in the Gen-2 graph).
    pub huber_k: f64,
}

impl GpsPosition {
    /// The whitened residual (before the robust kernel).
    pub fn residual(&self, xi: &V7, xj: &V7) -> SVector<f64, 2> {
        let a = self.alpha;
        SVector::<f64, 2>::new(
            ((1.0 - a) * xi[X] + a * xj[X] - self.x_m) / self.sigma_m,
            ((1.0 - a) * xi[Y] + a * xj[Y] - self.y_m) / self.sigma_m,
        )
    }

    /// The Jacobians on `i` and `j` (before the robust kernel).
    pub fn jacobians(&self) -> (SMatrix<f64, 2, DIM>, SMatrix<f64, 2, DIM>) {
        let (ji, jj) = self.jac();
        (ji.dense(), jj.dense())
    }

    /// [`GpsPosition::jacobians`] on their non-zero columns (x and y).
    pub fn jac(&self) -> (Jac<2, 2>, Jac<2, 2>) {
        let s = 1.0 / self.sigma_m;
        let mut ji = Jac::zeros([X, Y]);
        let mut jj = Jac::zeros([X, Y]);
        ji.m[(0, 0)] = (1.0 - self.alpha) * s;
        ji.m[(1, 1)] = (1.0 - self.alpha) * s;
        jj.m[(0, 0)] = self.alpha * s;
        jj.m[(1, 1)] = self.alpha * s;
        (ji, jj)
    }

    /// The Huber weight for a whitened residual norm: 1 inside `huber_k`, `k / norm` outside.
    pub fn huber_weight(&self, norm: f64) -> f64 {
        if norm <= self.huber_k {
            1.0
        } else {
            self.huber_k / norm
        }
    }
}

/// Any factor of the window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Factor {
    /// DVL or dead-reckoned odometry.
    Odometry(Odometry),
    /// Gyro heading increment.
    YawIncrement(YawIncrement),
    /// Slow-state random walk.
    RandomWalk(RandomWalk),
    /// AHRS yaw.
    Heading(Heading),
    /// Depth.
    Depth(DepthObs),
    /// GPS position.
    Gps(GpsPosition),
}

impl Factor {
    /// Whether the factor involves keyframe `j` (all between factors; interpolated
    /// measurements with `alpha > 0`).
    pub fn touches_j(&self) -> bool {
        match self {
            Factor::Odometry(_) | Factor::YawIncrement(_) | Factor::RandomWalk(_) => true,
            Factor::Heading(f) => f.alpha > 0.0,
            Factor::Depth(f) => f.alpha > 0.0,
            Factor::Gps(f) => f.alpha > 0.0,
        }
    }

    /// Linearises the factor at `xi`, `xj` into `sink` (keyframe index `i`). `xj` is ignored
    /// when the factor does not touch `j`.
    pub fn linearize<S: Sink + ?Sized>(&self, i: usize, xi: &V7, xj: &V7, sink: &mut S) {
        let touches_j = self.touches_j();
        macro_rules! add {
            ($r:expr, $ji:expr, $jj:expr) => {
                sink.add(&Linearized {
                    i,
                    r: &$r,
                    ji: &$ji,
                    jj: &$jj,
                    touches_j,
                })
            };
        }
        match self {
            Factor::Odometry(f) => {
                let (r, ji, jj) = f.linearized(xi, xj);
                sink.add_odometry(i, &r, &ji, &jj);
            }
            Factor::YawIncrement(f) => {
                let (ji, jj) = f.jac();
                add!(f.residual(xi, xj), ji, jj);
            }
            Factor::RandomWalk(f) => {
                let (ji, jj) = f.jac();
                add!(f.residual(xi, xj), ji, jj);
            }
            Factor::Heading(f) => {
                let (ji, jj) = f.jac();
                add!(f.residual(xi, xj), ji, jj);
            }
            Factor::Depth(f) => {
                let (ji, jj) = f.jac();
                add!(f.residual(xi, xj), ji, jj);
            }
            Factor::Gps(f) => {
                let r = f.residual(xi, xj);
                let (ji, jj) = f.jac();
                let w = f.huber_weight(r.norm()).sqrt();
                add!(r * w, ji.scaled(w), jj.scaled(w));
            }
        }
    }

    /// Whether the factor's Jacobians are the same at every state (the gyro increment, the
    /// random walk, the AHRS yaw and the depth: linear in the states, the yaw's wrap aside),
    /// so its Hessian part `J' J` can be assembled once. The odometry's depends on the
    /// headings, the GPS's on its Huber weight.
    pub fn constant_jacobian(&self) -> bool {
        matches!(
            self,
            Factor::YawIncrement(_) | Factor::RandomWalk(_) | Factor::Heading(_) | Factor::Depth(_)
        )
    }

    /// The gradient part of [`Factor::linearize`] alone (`J' r`: the same residual and
    /// Jacobians) into `blocks`' gradients, for a factor whose Hessian part is kept
    /// ([`Factor::constant_jacobian`]).
    pub fn linearize_gradient<B: Blocks + ?Sized>(
        &self,
        i: usize,
        xi: &V7,
        xj: &V7,
        blocks: &mut B,
    ) {
        self.linearize(i, xi, xj, &mut GradientOnly(blocks));
    }

    /// The robust cost of the factor (half the squared whitened residual, Huber for GPS).
    pub fn cost(&self, xi: &V7, xj: &V7) -> f64 {
        match self {
            Factor::Odometry(f) => 0.5 * f.residual(xi, xj).norm_squared(),
            Factor::YawIncrement(f) => 0.5 * f.residual(xi, xj).norm_squared(),
            Factor::RandomWalk(f) => 0.5 * f.residual(xi, xj).norm_squared(),
            Factor::Heading(f) => 0.5 * f.residual(xi, xj).norm_squared(),
            Factor::Depth(f) => 0.5 * f.residual(xi, xj).norm_squared(),
            Factor::Gps(f) => {
                let n = f.residual(xi, xj).norm();
                if n <= f.huber_k {
                    0.5 * n * n
                } else {
                    f.huber_k * (n - 0.5 * f.huber_k)
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(seed: u64) -> V7 {
        let mut rng = fastrand::Rng::with_seed(seed);
        let mut v = V7::zeros();
        for k in 0..DIM {
            v[k] = rng.f64() * 4.0 - 2.0;
        }
        v[PSI] = rng.f64() * 2.0 - 1.0;
        v[BIAS] = rng.f64() * 0.2 - 0.1;
        v
    }

    /// Central differences of `f` over the 14 variables of (xi, xj) against the analytic pair.
    fn check<const R: usize>(
        f: impl Fn(&V7, &V7) -> SVector<f64, R>,
        ji: SMatrix<f64, R, DIM>,
        jj: SMatrix<f64, R, DIM>,
        xi: &V7,
        xj: &V7,
    ) {
        let h = 1e-6;
        for c in 0..DIM {
            let mut p = *xi;
            let mut m = *xi;
            p[c] += h;
            m[c] -= h;
            let num = (f(&p, xj) - f(&m, xj)) / (2.0 * h);
            for r in 0..R {
                assert!(
                    (num[r] - ji[(r, c)]).abs() < 1e-6 * (1.0 + num[r].abs()),
                    "d r{r} / d xi{c}: numeric {} analytic {}",
                    num[r],
                    ji[(r, c)]
                );
            }
            let mut p = *xj;
            let mut m = *xj;
            p[c] += h;
            m[c] -= h;
            let num = (f(xi, &p) - f(xi, &m)) / (2.0 * h);
            for r in 0..R {
                assert!(
                    (num[r] - jj[(r, c)]).abs() < 1e-6 * (1.0 + num[r].abs()),
                    "d r{r} / d xj{c}: numeric {} analytic {}",
                    num[r],
                    jj[(r, c)]
                );
            }
        }
    }

    #[test]
    fn odometry_residual_and_jacobian() {
        for seed in 0..20 {
            let (xi, xj) = (state(seed), state(seed + 100));
            for (wi, wj) in [(false, false), (true, false), (true, true)] {
                let f = Odometry {
                    dt_s: 0.2 + seed as f64 * 0.01,
                    u_i: [1.4, 0.1, -0.05],
                    u_j: [1.5, -0.2, 0.02],
                    water_i: wi,
                    water_j: wj,
                    sigma_m: [0.01, 0.02, 0.03],
                };
                let (ji, jj) = f.jacobians(&xi, &xj);
                check(|a, b| f.residual(a, b), ji, jj, &xi, &xj);
            }
        }
        // A closed-form value: heading east, 1 m/s forward for 2 s, no current.
        let f = Odometry {
            dt_s: 2.0,
            u_i: [1.0, 0.0, 0.0],
            u_j: [1.0, 0.0, 0.0],
            water_i: true,
            water_j: false,
            sigma_m: [1.0, 1.0, 1.0],
        };
        let mut xi = V7::zeros();
        xi[PSI] = std::f64::consts::FRAC_PI_2;
        xi[CX] = 0.5;
        let mut xj = xi;
        xj[X] = 2.5; // 2 m of motion plus 0.5 m of current (half the interval through water).
        assert!(f.residual(&xi, &xj).norm() < 1e-12);
    }

    #[test]
    fn unary_and_between_residuals_and_jacobians() {
        for seed in 0..20 {
            let (xi, xj) = (state(seed), state(seed + 50));
            let alpha = (seed as f64) / 19.0;
            let y = YawIncrement {
                dpsi_rad: 0.05,
                sigma_rad: 0.01,
            };
            let (a, b) = y.jacobians();
            check(|p, q| y.residual(p, q), a, b, &xi, &xj);
            let w = RandomWalk {
                dt_s: 0.25,
                bias_rad_per_sqrt_s: 1e-4,
                current_mps_per_sqrt_s: 1e-3,
            };
            let (a, b) = w.jacobians();
            check(|p, q| w.residual(p, q), a, b, &xi, &xj);
            let h = Heading {
                alpha,
                yaw_rad: 0.3,
                sigma_rad: 0.02,
            };
            let (a, b) = h.jacobians();
            check(|p, q| h.residual(p, q), a, b, &xi, &xj);
            let d = DepthObs {
                alpha,
                depth_m: 3.0,
                sigma_m: 0.05,
            };
            let (a, b) = d.jacobians();
            check(|p, q| d.residual(p, q), a, b, &xi, &xj);
            let g = GpsPosition {
                alpha,
                x_m: 1.0,
                y_m: -1.0,
                sigma_m: 1.5,
                huber_k: 1.345,
            };
            let (a, b) = g.jacobians();
            check(|p, q| g.residual(p, q), a, b, &xi, &xj);
        }
    }

    /// The affine gradient of depth and random-walk factors equals their per-factor gradients.
    #[test]
    fn affine_gradient_equals_per_factor_gradients() {
        for seed in 0..10 {
            let (xi, xj) = (state(seed), state(seed + 30));
            let mut aff = AffineGradient::default();
            let mut each = crate::solver::BlockSystem::default();
            each.reset(2);
            let alpha = seed as f64 / 9.0;
            let factors = [
                Factor::Depth(DepthObs {
                    alpha,
                    depth_m: 3.0 + alpha,
                    sigma_m: 0.05,
                }),
                Factor::Depth(DepthObs {
                    alpha: 0.0,
                    depth_m: 2.5,
                    sigma_m: 0.05,
                }),
                Factor::RandomWalk(RandomWalk {
                    dt_s: 0.2,
                    bias_rad_per_sqrt_s: 2e-5,
                    current_mps_per_sqrt_s: 5e-4,
                }),
            ];
            for f in &factors {
                assert!(AffineGradient::takes(f) && aff.add_factor(f));
                f.linearize_gradient(0, &xi, &xj, &mut each);
            }
            let (mut gi, mut gj) = (V7::zeros(), V7::zeros());
            aff.add_to(&xi, &xj, &mut gi, Some(&mut gj));
            for k in 0..DIM {
                for (a, b) in [(gi[k], each.g[0][k]), (gj[k], each.g[1][k])] {
                    assert!((a - b).abs() <= 1e-9 * (1.0 + b.abs()), "{k}: {a} vs {b}");
                }
            }
        }
        let other = Factor::YawIncrement(YawIncrement {
            dpsi_rad: 0.1,
            sigma_rad: 0.01,
        });
        assert!(!AffineGradient::takes(&other));
        assert!(!AffineGradient::default().add_factor(&other));
    }

    #[test]
    fn closed_form_values_and_kernel() {
        let mut xi = V7::zeros();
        xi[PSI] = 0.1;
        xi[BIAS] = 0.05;
        let h = Heading {
            alpha: 0.0,
            yaw_rad: 0.15,
            sigma_rad: 0.01,
        };
        assert!(h.residual(&xi, &xi).norm() < 1e-12);
        // Yaw across the +-pi seam.
        let mut a = V7::zeros();
        a[PSI] = std::f64::consts::PI - 0.01;
        let h = Heading {
            alpha: 0.0,
            yaw_rad: -std::f64::consts::PI + 0.01,
            sigma_rad: 1.0,
        };
        assert!((h.residual(&a, &a)[0] + 0.02).abs() < 1e-12);
        let g = GpsPosition {
            alpha: 0.5,
            x_m: 1.0,
            y_m: 0.0,
            sigma_m: 1.0,
            huber_k: 1.345,
        };
        let mut b = V7::zeros();
        b[X] = 2.0;
        assert!(g.residual(&V7::zeros(), &b).norm() < 1e-12);
        assert_eq!(g.huber_weight(1.0), 1.0);
        assert!((g.huber_weight(100.0) - 0.01345).abs() < 1e-15);
        // Huber cost grows linearly far out: a 100 m jump costs ~ k * 100, not 5000.
        let far = GpsPosition { x_m: 101.0, ..g };
        let c = Factor::Gps(far).cost(&V7::zeros(), &b);
        assert!((c - 1.345 * (100.0 - 0.6725)).abs() < 1e-9);
    }
}
