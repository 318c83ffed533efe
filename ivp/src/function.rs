//! Piecewise-linear objective functions over integer index space (MOOS-IvP's `IvPFunction`).

use super::domain::Domain;
use super::error::{DomainError, IvpError};

/// Default priority weight of a freshly built function (MOOS-IvP's `IvPFunction` default).
pub const DEFAULT_PWT: f64 = 10.0;

/// One piece of a function: an axis-aligned box of grid indices (both ends inclusive) with a
/// linear interior function `value = Σ slope[d]*ix[d] + intercept`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Piece<'a> {
    /// Lowest index per dimension.
    pub lo: &'a [u32],
    /// Highest index per dimension (inclusive).
    pub hi: &'a [u32],
    /// Slope per dimension, then the intercept.
    pub wts: &'a [f64],
}

impl Piece<'_> {
    /// The intercept of the interior function.
    pub fn intercept(&self) -> f64 {
        self.wts[self.lo.len()]
    }
    /// Whether the grid point `ix` lies in the box.
    pub fn contains(&self, ix: &[u32]) -> bool {
        ix.iter()
            .zip(self.lo.iter().zip(self.hi))
            .all(|(&i, (&l, &h))| l <= i && i <= h)
    }
    /// The interior function's value at `ix` (whether or not `ix` is inside the box).
    pub fn eval(&self, ix: &[u32]) -> f64 {
        let d = self.lo.len();
        let mut v = self.wts[d];
        for k in 0..d {
            v += self.wts[k] * f64::from(ix[k]);
        }
        v
    }
    /// The largest value over the box: each slope taken at the end that favours it.
    pub fn max_val(&self) -> f64 {
        let d = self.lo.len();
        let mut v = self.wts[d];
        for k in 0..d {
            let w = self.wts[k];
            v += if w < 0.0 {
                w * f64::from(self.lo[k])
            } else {
                w * f64::from(self.hi[k])
            };
        }
        v
    }
    /// The smallest value over the box.
    pub fn min_val(&self) -> f64 {
        let d = self.lo.len();
        let mut v = self.wts[d];
        for k in 0..d {
            let w = self.wts[k];
            v += if w > 0.0 {
                w * f64::from(self.lo[k])
            } else {
                w * f64::from(self.hi[k])
            };
        }
        v
    }
    /// Where the maximum is attained: per dimension the low end if the slope is negative,
    /// otherwise the high end (so a flat dimension picks its HIGH end, as MOOS-IvP does).
    pub fn max_pt(&self, out: &mut [u32]) {
        for k in 0..self.lo.len() {
            out[k] = if self.wts[k] < 0.0 {
                self.lo[k]
            } else {
                self.hi[k]
            };
        }
    }
}

/// A piecewise-linear objective function with a priority weight.
///
/// Pieces live in the integer index space of the function's own domain, stored flat so that
/// solving touches contiguous memory.
///
/// ```
/// # use ivp::{Domain, IvpFunction};
/// let d = Domain::from_vars(&[("speed", 0.0, 4.0, 41)]).unwrap();
/// let mut f = IvpFunction::new(d);
/// f.push_piece(&[0], &[20], &[5.0], 0.0).unwrap();    // rising to 100 at 2 m/s
/// f.push_piece(&[21], &[40], &[-5.0], 200.0).unwrap(); // then falling
/// assert_eq!(f.eval(&[20]), Some(100.0));
/// assert_eq!(f.max_val(), 100.0);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct IvpFunction {
    domain: Domain,
    lo: Vec<u32>,
    hi: Vec<u32>,
    wts: Vec<f64>,
    pwt: f64,
}

impl IvpFunction {
    /// An empty function (no pieces) over `domain`, with the default priority weight.
    pub fn new(domain: Domain) -> Self {
        Self {
            domain,
            lo: Vec::new(),
            hi: Vec::new(),
            wts: Vec::new(),
            pwt: DEFAULT_PWT,
        }
    }

    /// The function's own domain.
    pub fn domain(&self) -> &Domain {
        &self.domain
    }
    /// Number of dimensions.
    pub fn dim(&self) -> usize {
        self.domain.len()
    }
    /// Number of pieces.
    pub fn piece_count(&self) -> usize {
        if self.dim() == 0 {
            self.wts.len()
        } else {
            self.lo.len() / self.dim()
        }
    }
    /// Priority weight.
    pub fn pwt(&self) -> f64 {
        self.pwt
    }
    /// Sets the priority weight.
    pub fn set_pwt(&mut self, pwt: f64) {
        self.pwt = pwt;
    }
    /// Builder-style [`set_pwt`](Self::set_pwt).
    pub fn with_pwt(mut self, pwt: f64) -> Self {
        self.pwt = pwt;
        self
    }

    /// Adds a piece. Fails if the box is not inside the domain, is inverted, or any weight
    /// is not finite.
    pub fn push_piece(
        &mut self,
        lo: &[u32],
        hi: &[u32],
        slopes: &[f64],
        intercept: f64,
    ) -> Result<(), IvpError> {
        let d = self.dim();
        let piece = self.piece_count();
        if lo.len() != d || hi.len() != d || slopes.len() != d {
            return Err(IvpError::BadPiece {
                piece,
                reason: format!("expected {d} dimensions"),
            });
        }
        for k in 0..d {
            let pts = self.domain.vars()[k].points();
            if lo[k] > hi[k] || hi[k] >= pts {
                return Err(IvpError::BadPiece {
                    piece,
                    reason: format!(
                        "interval [{}, {}] of {:?} not within 0..{}",
                        lo[k],
                        hi[k],
                        self.domain.vars()[k].name(),
                        pts
                    ),
                });
            }
        }
        if !intercept.is_finite() || slopes.iter().any(|w| !w.is_finite()) {
            return Err(IvpError::BadPiece {
                piece,
                reason: "weights must be finite".to_string(),
            });
        }
        self.push_unchecked(lo, hi, slopes, intercept);
        Ok(())
    }

    /// Room for `pieces` more pieces.
    pub(crate) fn reserve(&mut self, pieces: usize) {
        let d = self.dim();
        self.lo.reserve(pieces * d);
        self.hi.reserve(pieces * d);
        self.wts.reserve(pieces * (d + 1));
    }

    /// Makes room for `pieces` more pieces (a builder that knows its count pushes them
    /// without regrowing the buffers).
    pub(crate) fn reserve_pieces(&mut self, pieces: usize) {
        let d = self.dim();
        self.lo.reserve(pieces * d);
        self.hi.reserve(pieces * d);
        self.wts.reserve(pieces * (d + 1));
    }

    pub(crate) fn push_unchecked(
        &mut self,
        lo: &[u32],
        hi: &[u32],
        slopes: &[f64],
        intercept: f64,
    ) {
        self.lo.extend_from_slice(lo);
        self.hi.extend_from_slice(hi);
        self.wts.extend_from_slice(slopes);
        self.wts.push(intercept);
    }

    /// Piece `i`.
    pub fn piece(&self, i: usize) -> Piece<'_> {
        let d = self.dim();
        Piece {
            lo: &self.lo[i * d..(i + 1) * d],
            hi: &self.hi[i * d..(i + 1) * d],
            wts: &self.wts[i * (d + 1)..(i + 1) * (d + 1)],
        }
    }
    /// All pieces in order.
    pub fn pieces(&self) -> impl Iterator<Item = Piece<'_>> + '_ {
        (0..self.piece_count()).map(move |i| self.piece(i))
    }

    /// Value at grid point `ix` from the first piece holding it; `None` where no piece does.
    /// The priority weight is not applied.
    pub fn eval(&self, ix: &[u32]) -> Option<f64> {
        self.pieces().find(|p| p.contains(ix)).map(|p| p.eval(ix))
    }

    /// Value at the grid point nearest to the domain values `vals` (one per dimension).
    pub fn eval_values(&self, vals: &[f64]) -> Option<f64> {
        if vals.len() != self.dim() {
            return None;
        }
        let ix: Vec<u32> = self
            .domain
            .vars()
            .iter()
            .zip(vals)
            .map(|(v, &x)| v.index(x, super::domain::Snap::Nearest))
            .collect();
        self.eval(&ix)
    }

    /// Largest value of any piece (negative infinity with no pieces).
    pub fn max_val(&self) -> f64 {
        self.pieces()
            .map(|p| p.max_val())
            .fold(f64::NEG_INFINITY, f64::max)
    }
    /// Smallest value of any piece (positive infinity with no pieces).
    pub fn min_val(&self) -> f64 {
        self.pieces()
            .map(|p| p.min_val())
            .fold(f64::INFINITY, f64::min)
    }
    /// The grid point of the function's maximum (first piece wins ties), or `None` if empty.
    pub fn max_pt(&self) -> Option<Vec<u32>> {
        let mut best: Option<(f64, usize)> = None;
        for (i, p) in self.pieces().enumerate() {
            let v = p.max_val();
            if best.is_none_or(|(b, _)| v > b) {
                best = Some((v, i));
            }
        }
        best.map(|(_, i)| {
            let mut out = vec![0; self.dim()];
            self.piece(i).max_pt(&mut out);
            out
        })
    }

    /// Adds `v` to every piece's intercept.
    pub fn apply_scalar(&mut self, v: f64) {
        let d = self.dim();
        for w in self.wts.iter_mut().skip(d).step_by(d + 1) {
            *w += v;
        }
    }
    /// Multiplies every weight (slopes and intercepts) by `k`.
    pub fn apply_weight(&mut self, k: f64) {
        for w in &mut self.wts {
            *w *= k;
        }
    }
    /// Rescales so values span `[base*k, base*k + range]` as MOOS-IvP's `PDMap::normalize`
    /// does: shift by `base - min`, then scale by `range / (max - min)`. A flat function is
    /// left unchanged.
    ///
    /// ```
    /// # use ivp::{Domain, IvpFunction};
    /// let mut f = IvpFunction::new(Domain::from_vars(&[("x", 0.0, 10.0, 11)]).unwrap());
    /// f.push_piece(&[0], &[10], &[2.0], 30.0).unwrap(); // 30..50
    /// f.normalize(0.0, 100.0);
    /// assert_eq!(f.eval(&[0]), Some(0.0));
    /// assert_eq!(f.eval(&[10]), Some(100.0));
    /// ```
    pub fn normalize(&mut self, base: f64, range: f64) {
        let lo = self.min_val();
        let hi = self.max_val();
        let spread = hi - lo;
        if spread.is_nan() || spread <= 0.0 || !spread.is_finite() {
            return;
        }
        self.apply_scalar(base - lo);
        self.apply_weight(range / spread);
    }

    /// Re-expresses the function over `target`, a domain that holds every variable of this
    /// one with the same grid; the new dimensions span their whole range with slope 0
    /// (MOOS-IvP's `transDomain`).
    pub fn embed(&self, target: &Domain) -> Result<IvpFunction, IvpError> {
        let map = self.dim_map(target)?;
        let td = target.len();
        let mut out = IvpFunction::new(target.clone()).with_pwt(self.pwt);
        let n = self.piece_count();
        out.lo.reserve(n * td);
        out.hi.reserve(n * td);
        out.wts.reserve(n * (td + 1));
        let mut lo = vec![0u32; td];
        let mut hi = vec![0u32; td];
        let mut w = vec![0.0; td];
        for p in self.pieces() {
            for (t, v) in target.vars().iter().enumerate() {
                lo[t] = 0;
                hi[t] = v.points() - 1;
                w[t] = 0.0;
            }
            for (k, &t) in map.iter().enumerate() {
                lo[t] = p.lo[k];
                hi[t] = p.hi[k];
                w[t] = p.wts[k];
            }
            out.push_unchecked(&lo, &hi, &w, p.intercept());
        }
        Ok(out)
    }

    /// For each of this function's dimensions, its position in `target`.
    pub(crate) fn dim_map(&self, target: &Domain) -> Result<Vec<usize>, IvpError> {
        self.domain
            .vars()
            .iter()
            .map(|v| {
                let t = target
                    .index_of(v.name())
                    .ok_or_else(|| DomainError::UnknownVar(v.name().to_string()))?;
                let tv = &target.vars()[t];
                if tv.points() != v.points() || tv.low() != v.low() || tv.high() != v.high() {
                    return Err(IvpError::BadDomain {
                        builder: "embed",
                        reason: format!("variable {:?} has a different grid", v.name()),
                    });
                }
                Ok(t)
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn two_d() -> Domain {
        Domain::from_vars(&[("course", 0.0, 359.0, 360), ("speed", 0.0, 4.0, 41)]).unwrap()
    }

    #[test]
    fn box_max_val_and_max_pt_follow_slope_signs() {
        let mut f = IvpFunction::new(two_d());
        f.push_piece(&[10, 0], &[20, 40], &[-1.0, 0.0], 50.0)
            .unwrap();
        let p = f.piece(0);
        assert_eq!(p.max_val(), 40.0);
        assert_eq!(p.min_val(), 30.0);
        let mut pt = [0; 2];
        p.max_pt(&mut pt);
        // negative slope -> low end; zero slope -> HIGH end
        assert_eq!(pt, [10, 40]);
    }

    #[test]
    fn bad_pieces_are_rejected() {
        let mut f = IvpFunction::new(two_d());
        assert!(f.push_piece(&[0, 0], &[360, 40], &[0.0, 0.0], 1.0).is_err());
        assert!(f.push_piece(&[5, 0], &[4, 40], &[0.0, 0.0], 1.0).is_err());
        assert!(f.push_piece(&[0], &[4], &[0.0], 1.0).is_err());
        assert!(
            f.push_piece(&[0, 0], &[4, 4], &[f64::NAN, 0.0], 1.0)
                .is_err()
        );
        assert_eq!(f.piece_count(), 0);
    }

    #[test]
    fn weight_scalar_and_embedding() {
        let sd = Domain::from_vars(&[("speed", 0.0, 4.0, 41)]).unwrap();
        let mut f = IvpFunction::new(sd);
        f.push_piece(&[0], &[40], &[1.0], 10.0).unwrap();
        f.apply_weight(2.0);
        assert_eq!(f.eval(&[5]), Some(30.0));
        f.apply_scalar(-20.0);
        assert_eq!(f.eval(&[5]), Some(10.0));
        let g = f.embed(&two_d()).unwrap();
        assert_eq!(g.piece_count(), 1);
        assert_eq!(g.eval(&[123, 5]), Some(10.0));
        assert_eq!(g.piece(0).lo, &[0, 0]);
        assert_eq!(g.piece(0).hi, &[359, 40]);
        let other = Domain::from_vars(&[("speed", 0.0, 5.0, 41)]).unwrap();
        assert!(f.embed(&other).is_err());
        let missing = Domain::from_vars(&[("course", 0.0, 359.0, 360)]).unwrap();
        assert!(f.embed(&missing).is_err());
    }

    #[test]
    fn flat_function_is_not_normalized() {
        let sd = Domain::from_vars(&[("speed", 0.0, 4.0, 41)]).unwrap();
        let mut f = IvpFunction::new(sd);
        f.push_piece(&[0], &[40], &[0.0], 7.0).unwrap();
        f.normalize(0.0, 100.0);
        assert_eq!(f.eval(&[3]), Some(7.0));
    }
}
