//! The reflector's one piece-fitting routine, MOOS-IvP's `Regressor` at a2a9b716
//! (`setWeight0`, `setWeight1`, `setCorners`, `centerBox`), which every stage uses: the
//! uniform pieces, the directed refinement, the plateau and basin regions, the smart
//! refinement and the auto-peak stage.
//!
//! A piece's samples are its corners and, when some edge spans more than two grid points, one
//! centre point at `lo + (hi - lo) / 2` in every dimension (rounded down, so an edge of an
//! even number of points puts it below the middle). A corner that repeats another (an edge of
//! one point) takes that corner's value instead of evaluating the function again.
//!
//! Degree 1 (linear pieces, the default and what every MOOS-IvP behaviour builds): the slope
//! along a dimension is the mean, over the corner pairs along it, of their rise over their
//! run in grid steps (0 on an edge of one point); the intercept is the mean of each sample's
//! value less the sloped part at it. With `strict_range` (on by default, as the C++
//! `Regressor`), the plane is kept within the samples' range at every sample: the intercept is
//! first lowered to the largest value that keeps it at or below the highest sample, then
//! raised to the smallest value that keeps it at or above the lowest, so the lower bound wins
//! when both cannot hold. A piece of a plateau (basin) region takes the function's known
//! maximum (minimum) when they are known ([`super::Reflector::known_min_max`]).
//!
//! Degree 0 (scalar pieces): the piece's value is the mean of its samples; no plateau or
//! basin value, and `strict_range` plays no part (a mean is within its samples).
//!
//! The fit error, which the smart stage queues pieces by, is for a linear piece the square
//! root of the summed squared differences between the plane and the samples, divided by the
//! number of samples; for a scalar piece the square root of the summed squared differences at
//! the corners alone, undivided (as the C++ computes each).

use crate::domain::Domain;
use crate::error::IvpError;

/// The kind of interior function of the pieces (the C++ reflector's `degree`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Degree {
    /// Constant pieces (degree 0).
    Scalar,
    /// Linear pieces (degree 1, the default).
    #[default]
    Linear,
}

/// MOOS `Regressor`: fits pieces of one domain, reusing its scratch space.
pub(super) struct Regressor {
    degree: Degree,
    strict: bool,
    /// The function's known minimum and maximum, for plateau and basin pieces.
    known: Option<(f64, f64)>,
    /// Corner values, corner `c` having `hi` where bit `k` of `c` is set.
    vals: Vec<f64>,
    /// A sample's grid indices and domain values (reused).
    ix: Vec<u32>,
    x: Vec<f64>,
    /// The centre sample, when the piece has one.
    centre: Vec<u32>,
    centre_val: Option<f64>,
    /// The fitted piece: a slope per dimension, then the intercept.
    wts: Vec<f64>,
}

impl Regressor {
    /// A regressor for pieces of `d` dimensions.
    pub fn new(d: usize, degree: Degree, strict: bool, known: Option<(f64, f64)>) -> Self {
        Self {
            degree,
            strict,
            known,
            vals: Vec::with_capacity(1 << d.min(16)),
            ix: vec![0; d],
            x: vec![0.0; d],
            centre: vec![0; d],
            centre_val: None,
            wts: vec![0.0; d + 1],
        }
    }

    /// The pieces' degree.
    pub fn degree(&self) -> Degree {
        self.degree
    }

    /// The last fitted piece's weights: a slope per dimension, then the intercept.
    pub fn wts(&self) -> &[f64] {
        &self.wts
    }

    /// Fits the piece `lo..=hi` whose plateau value is `plat` (> 0 plateau, < 0 basin, 0 an
    /// ordinary piece) to `func`; the weights are then in [`Regressor::wts`]. Returns the fit
    /// error (see the module docs). A sample where `func` is not finite is an error.
    pub fn fit<F: Fn(&[f64]) -> f64>(
        &mut self,
        lo: &[u32],
        hi: &[u32],
        plat: i32,
        domain: &Domain,
        func: &F,
    ) -> Result<f64, IvpError> {
        let d = lo.len();
        if let (Degree::Linear, Some((min, max))) = (self.degree, self.known)
            && plat != 0
        {
            self.wts[..d].fill(0.0);
            self.wts[d] = if plat > 0 { max } else { min };
            return Ok(0.0);
        }
        self.sample(lo, hi, domain, func)?;
        match self.degree {
            Degree::Scalar => Ok(self.fit_scalar(d)),
            Degree::Linear => Ok(self.fit_linear(lo, hi)),
        }
    }

    /// MOOS `setCorners` and `centerBox`: the corner values (borrowed along edges of one
    /// point) and the centre sample.
    fn sample<F: Fn(&[f64]) -> f64>(
        &mut self,
        lo: &[u32],
        hi: &[u32],
        domain: &Domain,
        func: &F,
    ) -> Result<(), IvpError> {
        let d = lo.len();
        let vars = domain.vars();
        let flat: usize = (0..d).filter(|&k| lo[k] == hi[k]).map(|k| 1 << k).sum();
        self.vals.clear();
        for c in 0..1usize << d {
            if c & flat != 0 {
                let v = self.vals[c & !flat];
                self.vals.push(v);
                continue;
            }
            for k in 0..d {
                self.ix[k] = if c >> k & 1 == 1 { hi[k] } else { lo[k] };
                self.x[k] = vars[k].value(self.ix[k]);
            }
            let v = eval(func, &self.x)?;
            self.vals.push(v);
        }
        self.centre_val = None;
        if (0..d).any(|k| hi[k] - lo[k] > 1) {
            for k in 0..d {
                self.centre[k] = lo[k] + (hi[k] - lo[k]) / 2;
                self.x[k] = vars[k].value(self.centre[k]);
            }
            self.centre_val = Some(eval(func, &self.x)?);
        }
        Ok(())
    }

    /// MOOS `setWeight0`.
    fn fit_scalar(&mut self, d: usize) -> f64 {
        let mut sum: f64 = self.vals.iter().sum();
        let mut n = self.vals.len() as f64;
        if let Some(c) = self.centre_val {
            sum += c;
            n += 1.0;
        }
        let val = sum / n;
        self.wts[..d].fill(0.0);
        self.wts[d] = val;
        self.vals
            .iter()
            .map(|v| (v - val) * (v - val))
            .sum::<f64>()
            .sqrt()
    }

    /// MOOS `setWeight1`'s general case.
    fn fit_linear(&mut self, lo: &[u32], hi: &[u32]) -> f64 {
        let d = lo.len();
        let corners = self.vals.len();
        let mut high = self.vals.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let mut low = self.vals.iter().copied().fold(f64::INFINITY, f64::min);
        if let Some(c) = self.centre_val {
            high = high.max(c);
            low = low.min(c);
        }
        // Slopes: the mean rise over run of the corner pairs along each dimension.
        for k in 0..d {
            let run = f64::from(hi[k] - lo[k]);
            if run == 0.0 {
                self.wts[k] = 0.0;
                continue;
            }
            let mut rise = 0.0;
            for c in 0..corners {
                if c >> k & 1 == 0 {
                    rise += self.vals[c | 1 << k] - self.vals[c];
                }
            }
            rise /= corners as f64 / 2.0;
            self.wts[k] = rise / run;
        }
        let slopes = &self.wts[..d];
        let corner = |c: usize| move |k: usize| if c >> k & 1 == 1 { hi[k] } else { lo[k] };
        // The mean intercept, and the range that keeps the plane within the samples.
        let mut total = 0.0;
        let (mut max_icpt, mut min_icpt) = (f64::INFINITY, f64::NEG_INFINITY);
        for c in 0..corners {
            let p = plane(0.0, slopes, corner(c));
            total += self.vals[c] - p;
            max_icpt = max_icpt.min(high - p);
            min_icpt = min_icpt.max(low - p);
        }
        let mut n = corners as f64;
        let centre = &self.centre;
        let centre_p = self
            .centre_val
            .map(|v| (v, plane(0.0, slopes, |k| centre[k])));
        if let Some((v, p)) = centre_p {
            total += v - p;
            max_icpt = max_icpt.min(high - p);
            min_icpt = min_icpt.max(low - p);
            n += 1.0;
        }
        let mut icpt = total / n;
        if self.strict {
            if icpt > max_icpt {
                icpt = max_icpt;
            }
            if icpt < min_icpt {
                icpt = min_icpt;
            }
        }
        // The fit error at the samples (the plane summed from the intercept, as the C++).
        let mut err = 0.0;
        for c in 0..corners {
            let lin = plane(icpt, slopes, corner(c));
            err += (lin - self.vals[c]) * (lin - self.vals[c]);
        }
        if let Some(v) = self.centre_val {
            let lin = plane(icpt, slopes, |k| centre[k]);
            err += (lin - v) * (lin - v);
        }
        self.wts[d] = icpt;
        err.sqrt() / n
    }
}

/// `base` plus each slope times the grid index `at` gives for its dimension, summed in order.
fn plane(base: f64, slopes: &[f64], at: impl Fn(usize) -> u32) -> f64 {
    let mut s = base;
    for (k, w) in slopes.iter().enumerate() {
        s += w * f64::from(at(k));
    }
    s
}

fn eval<F: Fn(&[f64]) -> f64>(func: &F, x: &[f64]) -> Result<f64, IvpError> {
    let v = func(x);
    if v.is_finite() {
        Ok(v)
    } else {
        Err(IvpError::Reflector(format!(
            "function is not finite at {x:?}"
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::cell::RefCell;

    fn line(points: u32) -> Domain {
        Domain::from_vars(&[("x", 0.0, f64::from(points - 1), points)]).unwrap()
    }

    /// `(x - 10)²` right of 10, 0 left of it.
    fn bend(v: &[f64]) -> f64 {
        (v[0] - 10.0).max(0.0).powi(2)
    }

    fn fit(
        reg: &mut Regressor,
        d: &Domain,
        lo: &[u32],
        hi: &[u32],
        f: impl Fn(&[f64]) -> f64,
    ) -> f64 {
        reg.fit(lo, hi, 0, d, &f).unwrap()
    }

    fn near(a: &[f64], b: &[f64]) -> bool {
        a.len() == b.len() && a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12)
    }

    #[test]
    fn a_1d_piece_with_and_without_strict_range() {
        let d = line(21);
        let mut loose = Regressor::new(1, Degree::Linear, false, None);
        let mut strict = Regressor::new(1, Degree::Linear, true, None);
        // 0..6: flat, exact either way.
        assert_eq!(fit(&mut strict, &d, &[0], &[6], bend), 0.0);
        assert!(near(strict.wts(), &[0.0, 0.0]));
        // 7..13: samples 0 at 7, 0 at the centre 10, 9 at 13. Slope 9 / 6 = 1.5; the
        // sloped part 10.5, 15, 19.5; residuals -10.5, -15, -10.5, mean -12.
        let e = fit(&mut loose, &d, &[7], &[13], bend);
        assert!(near(loose.wts(), &[1.5, -12.0]));
        // The plane -1.5, 3, 7.5 against 0, 0, 9: deltas -1.5, 3, -1.5: sqrt(13.5) / 3.
        assert!((e - 13.5f64.sqrt() / 3.0).abs() < 1e-12);
        // strict_range: the intercept at most min(9 - 10.5, 9 - 15, 9 - 19.5) = -10.5 and at
        // least max(0 - 10.5, 0 - 15, 0 - 19.5) = -10.5: the chord, deltas 0, 4.5, 0.
        let e = fit(&mut strict, &d, &[7], &[13], bend);
        assert!(near(strict.wts(), &[1.5, -10.5]));
        assert!((e - 1.5).abs() < 1e-12);
        // An edge of an even number of points samples the centre below the middle
        // (lo + (hi - lo) / 2): 11..14 gives 1 at 11, 4 at 12, 16 at 14; slope 5, the sloped
        // part 55, 60, 70, residuals -54, -56, -54: intercept -164/3.
        let e = fit(&mut loose, &d, &[11], &[14], bend);
        assert!(near(loose.wts(), &[5.0, -164.0 / 3.0]));
        // deltas -2/3, 4/3, -2/3.
        let want = (4.0 / 9.0 + 16.0 / 9.0 + 4.0 / 9.0f64).sqrt() / 3.0;
        assert!((e - want).abs() < 1e-12);
        // strict: bounds 16 - 70 = -54 and 1 - 55 = -54: -164/3 is raised to -54.
        let e = fit(&mut strict, &d, &[11], &[14], bend);
        assert!(near(strict.wts(), &[5.0, -54.0]));
        assert!((e - 2.0 / 3.0).abs() < 1e-12);
    }

    #[test]
    fn a_2d_piece_with_and_without_strict_range() {
        let d = Domain::from_vars(&[("x", 0.0, 4.0, 5), ("y", 0.0, 2.0, 3)]).unwrap();
        let xy = |v: &[f64]| v[0] * v[1];
        // The whole domain: corners 0 (0,0), 0 (4,0), 0 (0,2), 8 (4,2), centre 2 (2,1).
        // Slopes ((0 - 0) + (8 - 0)) / 2 / 4 = 1 and ((0 - 0) + (8 - 0)) / 2 / 2 = 2; the
        // sloped part 0, 4, 4, 8, 4; residuals 0, -4, -4, 0, -2: mean -2.
        let mut loose = Regressor::new(2, Degree::Linear, false, None);
        let e = fit(&mut loose, &d, &[0, 0], &[4, 2], xy);
        assert!(near(loose.wts(), &[1.0, 2.0, -2.0]));
        // The plane -2, 2, 2, 6, 2 against 0, 0, 0, 8, 2: sqrt(4 + 4 + 4 + 4 + 0) / 5.
        assert!((e - 0.8).abs() < 1e-12);
        // strict: at most min(8 - p) = 8 - 8 = 0, at least max(0 - p) = 0: intercept 0.
        let mut strict = Regressor::new(2, Degree::Linear, true, None);
        let e = fit(&mut strict, &d, &[0, 0], &[4, 2], xy);
        assert!(near(strict.wts(), &[1.0, 2.0, 0.0]));
        // The plane 0, 4, 4, 8, 4 against 0, 0, 0, 8, 2: sqrt(16 + 16 + 4) / 5.
        assert!((e - 1.2).abs() < 1e-12);
    }

    #[test]
    fn strict_range_lowers_then_raises_the_intercept() {
        // The majority of three bits: 1 where two or more of x, y, z are 1. Slopes 1/2 each,
        // the sloped part (x + y + z) / 2; residuals 0, -1/2 (one bit), 0 (two bits), -1/2
        // (three bits): mean -1/4. The plane spans 1.5 over corners spanning 1, so no
        // intercept keeps it within them: at most 1 - 1.5 = -1/2, at least 0 - 0 = 0. The
        // C++ lowers -1/4 to -1/2, then raises it to 0 (the lower bound wins).
        let d = Domain::from_vars(&[("x", 0.0, 1.0, 2), ("y", 0.0, 1.0, 2), ("z", 0.0, 1.0, 2)])
            .unwrap();
        let major = |v: &[f64]| if v[0] + v[1] + v[2] >= 2.0 { 1.0 } else { 0.0 };
        let mut strict = Regressor::new(3, Degree::Linear, true, None);
        fit(&mut strict, &d, &[0, 0, 0], &[1, 1, 1], major);
        assert!(near(strict.wts(), &[0.5, 0.5, 0.5, 0.0]));
        let mut loose = Regressor::new(3, Degree::Linear, false, None);
        fit(&mut loose, &d, &[0, 0, 0], &[1, 1, 1], major);
        assert!(near(loose.wts(), &[0.5, 0.5, 0.5, -0.25]));
    }

    #[test]
    fn the_samples_are_the_corners_and_a_centre_when_an_edge_spans_three_points() {
        let d = Domain::from_vars(&[("x", 0.0, 4.0, 5), ("y", 0.0, 2.0, 3)]).unwrap();
        let seen = RefCell::new(Vec::new());
        let f = |v: &[f64]| {
            seen.borrow_mut().push((v[0], v[1]));
            v[0] + 10.0 * v[1]
        };
        let mut reg = Regressor::new(2, Degree::Linear, true, None);
        let mut samples = |lo: [u32; 2], hi: [u32; 2]| {
            seen.borrow_mut().clear();
            reg.fit(&lo, &hi, 0, &d, &f).unwrap();
            std::mem::take(&mut *seen.borrow_mut())
        };
        // Edges of 2 and 3 points: the centre (0 + 1/2, 0 + 2/2) = (0, 1), which an
        // odd-sum rule would miss.
        assert_eq!(
            samples([0, 0], [1, 2]),
            [(0.0, 0.0), (1.0, 0.0), (0.0, 2.0), (1.0, 2.0), (0.0, 1.0)]
        );
        // Edges of 2 points: corners only.
        assert_eq!(
            samples([2, 1], [3, 2]),
            [(2.0, 1.0), (3.0, 1.0), (2.0, 2.0), (3.0, 2.0)]
        );
        // An edge of one point: its repeated corners are borrowed, not evaluated again.
        assert_eq!(
            samples([2, 0], [2, 2]),
            [(2.0, 0.0), (2.0, 2.0), (2.0, 1.0)]
        );
        // A point: one evaluation, the plane its value.
        assert_eq!(samples([4, 2], [4, 2]), [(4.0, 2.0)]);
        assert!(near(reg.wts(), &[0.0, 0.0, 24.0]));
    }

    #[test]
    fn scalar_pieces_are_the_mean_of_their_samples() {
        let d = line(21);
        let mut reg = Regressor::new(1, Degree::Scalar, true, None);
        // 7..13: samples 0, 9 and the centre 0: the value 3; the error over the corners
        // alone, undivided: sqrt(3² + 6²).
        let e = fit(&mut reg, &d, &[7], &[13], bend);
        assert!(near(reg.wts(), &[0.0, 3.0]));
        assert!((e - 45f64.sqrt()).abs() < 1e-12);
        // Plateau values are for linear pieces only (setWeight0 has none).
        let mut known = Regressor::new(1, Degree::Scalar, true, Some((-1.0, 50.0)));
        known.fit(&[7], &[13], 1, &d, &bend).unwrap();
        assert!(near(known.wts(), &[0.0, 3.0]));
    }

    #[test]
    fn plateau_and_basin_pieces_take_the_known_extremes() {
        let d = line(21);
        let mut reg = Regressor::new(1, Degree::Linear, true, Some((-1.0, 50.0)));
        assert_eq!(reg.fit(&[7], &[13], 1, &d, &bend).unwrap(), 0.0);
        assert!(near(reg.wts(), &[0.0, 50.0]));
        reg.fit(&[7], &[13], -1, &d, &bend).unwrap();
        assert!(near(reg.wts(), &[0.0, -1.0]));
        // Unknown extremes: fitted as any piece.
        let mut unknown = Regressor::new(1, Degree::Linear, true, None);
        unknown.fit(&[7], &[13], 1, &d, &bend).unwrap();
        assert!(near(unknown.wts(), &[1.5, -10.5]));
    }

    #[test]
    fn a_sample_that_is_not_finite_is_an_error() {
        let d = line(21);
        let mut reg = Regressor::new(1, Degree::Linear, true, None);
        // Only the centre (10) is not finite.
        let f = |v: &[f64]| if v[0] == 10.0 { f64::NAN } else { v[0] };
        assert!(reg.fit(&[7], &[13], 0, &d, &f).is_err());
        assert!(reg.fit(&[7], &[9], 0, &d, &f).is_ok());
    }
}
