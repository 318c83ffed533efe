//! ZAIC builders: one-variable objective functions from a few intuitive parameters
//! (MOOS-IvP's `ZAIC_PEAK`, `ZAIC_LEQ`, `ZAIC_HEQ`, `ZAIC_SPD`, `ZAIC_HDG`).
//!
//! Each builder produces the same pieces and values as its MOOS-IvP namesake; where we
//! deliberately differ it is said on the item.

use super::domain::{Domain, DomainVar};
use super::error::IvpError;
use super::function::IvpFunction;

/// Tolerance of the greedy linear segmentation used by [`ZaicPeak`] and [`ZaicHdg`].
pub const SEGMENT_TOLERANCE: f64 = 0.001;

/// Slope magnitude that makes flat regions prefer the summit side (LEQ/HEQ tie breaking).
pub const BREAK_TIES: f64 = 0.00001;

fn one_var(builder: &'static str, domain: &Domain, var: &str) -> Result<Domain, IvpError> {
    let d = domain.sub_domain(var)?;
    Ok(match d.var(0) {
        Some(_) => d,
        None => {
            return Err(IvpError::BadDomain {
                builder,
                reason: format!("no variable {var:?}"),
            });
        }
    })
}

fn check_finite(builder: &'static str, param: &'static str, v: f64) -> Result<f64, IvpError> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(IvpError::BadParam {
            builder,
            param,
            value: v,
            expected: "a finite number",
        })
    }
}

fn check_min_max(builder: &'static str, min: f64, max: f64) -> Result<(), IvpError> {
    check_finite(builder, "minutil", min)?;
    check_finite(builder, "maxutil", max)?;
    if min >= max {
        return Err(IvpError::BadParam {
            builder,
            param: "minutil",
            value: min,
            expected: "min utility below max utility",
        });
    }
    Ok(())
}

/// Greedy linear segmentation of per-index values into 1-D pieces, as MOOS-IvP's ZAIC_PEAK
/// and ZAIC_HDG do: a piece is extended while the next value stays within `tol` of the line
/// through the piece's first two values and the local slope keeps its sign. A break on the
/// very last index makes that index a singleton piece (emitted before the piece it ends).
///
/// Unlike MOOS-IvP, a one-point domain yields one piece instead of none.
pub fn segment(vals: &[f64], tol: f64, out: &mut IvpFunction) {
    let n = vals.len();
    if n == 0 {
        return;
    }
    if n == 1 {
        out.push_unchecked(&[0], &[0], &[0.0], vals[0]);
        return;
    }
    let mut first = 0usize;
    let mut first_val = vals[0];
    let mut trend: Option<(f64, f64)> = None;
    let span = |from: usize, from_val: f64, to: usize, to_val: f64| -> (f64, f64) {
        let run = (to - from) as f64;
        let slope = if run > 0.0 {
            (to_val - from_val) / run
        } else {
            0.0
        };
        (slope, from_val - slope * from as f64)
    };
    for i in 1..n {
        let x = i as f64;
        let (s_m, s_b) = *trend.get_or_insert_with(|| {
            let m = (vals[i] - first_val) / (i - first) as f64;
            (m, vals[i] - m * x)
        });
        let extrapolated = s_m * x + s_b;
        let local = vals[i] - vals[i - 1];
        let brk = (extrapolated - vals[i]).abs() > tol
            || (local < 0.0 && s_m > 0.0)
            || (local > 0.0 && s_m < 0.0);
        if i == n - 1 {
            if brk {
                out.push_unchecked(&[i as u32], &[i as u32], &[0.0], vals[i]);
            } else {
                let (m, b) = span(first, first_val, i, vals[i]);
                out.push_unchecked(&[first as u32], &[i as u32], &[m], b);
            }
        }
        if brk {
            let (m, b) = span(first, first_val, i - 1, vals[i - 1]);
            out.push_unchecked(&[first as u32], &[(i - 1) as u32], &[m], b);
            trend = None;
            first = i;
            first_val = vals[i];
        }
    }
}

/// Joins knots `(index, value)` (strictly increasing indices from 0 to the last grid index)
/// with linear pieces, like MOOS-IvP's `PDMapBuilder`: the first piece spans the first two
/// knots, each later one starts one index after the previous knot.
///
/// MOOS-IvP lets a piece between two adjacent knots overlap its neighbour on one index (both
/// give the same value there); here that piece starts one index later, so pieces never overlap.
pub fn join_knots(knots: &[(u32, f64)], out: &mut IvpFunction) {
    let line = |(a, va): (u32, f64), (b, vb): (u32, f64)| -> (f64, f64) {
        let run = f64::from(b - a);
        let slope = if run > 0.0 { (vb - va) / run } else { 0.0 };
        (slope, va - slope * f64::from(a))
    };
    match knots {
        [] => {}
        [k] => out.push_unchecked(&[k.0], &[k.0], &[0.0], k.1),
        _ => {
            for (i, pair) in knots.windows(2).enumerate() {
                let (m, b) = line(pair[0], pair[1]);
                let start = if i == 0 { pair[0].0 } else { pair[0].0 + 1 };
                out.push_unchecked(&[start], &[pair[1].0], &[m], b);
            }
        }
    }
}

/// How the components of a multi-component [`ZaicPeak`] combine at each point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Combine {
    /// The largest component value (MOOS-IvP's `extractOF(true)`, the default).
    #[default]
    Max,
    /// The sum of the component values (`extractOF(false)`).
    Sum,
}

/// One peak of a [`ZaicPeak`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeakComponent {
    /// Most preferred value.
    pub summit: f64,
    /// Half-width of the plateau around the summit.
    pub peakwidth: f64,
    /// Width of the ramp from the plateau edge down to `minutil`.
    pub basewidth: f64,
    /// Drop in utility across the plateau.
    pub summitdelta: f64,
    /// Utility outside the base.
    pub minutil: f64,
    /// Utility at the summit.
    pub maxutil: f64,
}

impl Default for PeakComponent {
    fn default() -> Self {
        Self {
            summit: 0.0,
            peakwidth: 0.0,
            basewidth: 0.0,
            summitdelta: 0.0,
            minutil: 0.0,
            maxutil: 100.0,
        }
    }
}

impl PeakComponent {
    /// Checks and clips like MOOS-IvP's setters: negative widths/delta clip to 0, the delta
    /// clips to the utility range, and `minutil >= maxutil` is an error.
    fn validated(mut self) -> Result<Self, IvpError> {
        const B: &str = "ZAIC_PEAK";
        check_finite(B, "summit", self.summit)?;
        check_finite(B, "peakwidth", self.peakwidth)?;
        check_finite(B, "basewidth", self.basewidth)?;
        check_finite(B, "summitdelta", self.summitdelta)?;
        check_min_max(B, self.minutil, self.maxutil)?;
        self.peakwidth = self.peakwidth.max(0.0);
        self.basewidth = self.basewidth.max(0.0);
        self.summitdelta = self.summitdelta.clamp(0.0, self.maxutil - self.minutil);
        Ok(self)
    }
}

/// Per-component constants of the ZAIC_PEAK formula, computed once per extraction.
struct PeakConsts {
    low: f64,
    delta: f64,
    sd: f64,
    peak_slope: f64,
    edge: f64,
    base_slope: f64,
    reach: f64,
    above_around: f64,
    below_around: f64,
}

impl PeakConsts {
    fn new(c: &PeakComponent, v: &DomainVar) -> Self {
        let (low, high, delta) = (v.low(), v.high(), v.delta());
        let sd = if c.peakwidth > 0.0 {
            c.summitdelta
        } else {
            0.0
        };
        let edge = c.maxutil - sd;
        Self {
            low,
            delta,
            sd,
            peak_slope: if sd > 0.0 { sd / c.peakwidth } else { 0.0 },
            edge,
            base_slope: (edge - c.minutil) / c.basewidth,
            reach: c.peakwidth + c.basewidth,
            // Going round the seam costs one extra grid step.
            above_around: (high - c.summit) + delta - low,
            below_around: (c.summit - low) + delta + high,
        }
    }

    /// Utility at grid index `ix` (as a float).
    #[inline]
    fn value(&self, c: &PeakComponent, ix: f64, wrap: bool) -> f64 {
        let x = ix * self.delta + self.low;
        let dist = if !wrap {
            (c.summit - x).abs()
        } else if c.summit > x {
            lesser(x + self.above_around, c.summit - x)
        } else {
            lesser(self.below_around - x, x - c.summit)
        };
        let val = if dist <= c.peakwidth {
            if self.sd > 0.0 {
                c.maxutil - self.peak_slope * dist
            } else {
                c.maxutil
            }
        } else if dist <= self.reach {
            self.edge - self.base_slope * (dist - c.peakwidth)
        } else {
            c.minutil
        };
        lesser(val, c.maxutil)
    }
}

/// The smaller of two finite numbers (a plain compare: parameters are checked finite, so the
/// NaN handling of `f64::min` is not needed in this per-point loop).
#[inline]
fn lesser(a: f64, b: f64) -> f64 {
    if b < a { b } else { a }
}

/// A peaked preference around one or more summits, optionally wrapping (for course).
///
/// ```
/// # use ivp::{Domain, ZaicPeak};
/// let d = Domain::from_vars(&[("course", 0.0, 359.0, 360)]).unwrap();
/// let mut z = ZaicPeak::new(&d, "course").unwrap();
/// z.set_params(90.0, 10.0, 20.0, 0.0, 0.0, 100.0).unwrap();
/// z.set_value_wrap(true);
/// let f = z.extract().unwrap();
/// assert_eq!(f.eval(&[90]), Some(100.0));
/// assert_eq!(f.eval(&[200]), Some(0.0));
/// ```
#[derive(Debug, Clone)]
pub struct ZaicPeak {
    domain: Domain,
    var: DomainVar,
    components: Vec<PeakComponent>,
    value_wrap: bool,
    summit_insist: bool,
    combine: Combine,
}

impl ZaicPeak {
    /// A builder over variable `var` of `domain`, with one default component.
    pub fn new(domain: &Domain, var: &str) -> Result<Self, IvpError> {
        let domain = one_var("ZAIC_PEAK", domain, var)?;
        let var = domain.vars()[0].clone();
        Ok(Self {
            domain,
            var,
            components: vec![PeakComponent::default()],
            value_wrap: false,
            summit_insist: true,
            combine: Combine::Max,
        })
    }

    /// Sets component 0.
    pub fn set_params(
        &mut self,
        summit: f64,
        peakwidth: f64,
        basewidth: f64,
        summitdelta: f64,
        minutil: f64,
        maxutil: f64,
    ) -> Result<(), IvpError> {
        self.components[0] = PeakComponent {
            summit,
            peakwidth,
            basewidth,
            summitdelta,
            minutil,
            maxutil,
        }
        .validated()?;
        Ok(())
    }

    /// Adds a component; returns its index.
    pub fn add_component(&mut self, c: PeakComponent) -> Result<usize, IvpError> {
        self.components.push(c.validated()?);
        Ok(self.components.len() - 1)
    }

    /// The components.
    pub fn components(&self) -> &[PeakComponent] {
        &self.components
    }
    /// Measure distance around the seam (course: 359 and 0 are neighbours).
    pub fn set_value_wrap(&mut self, wrap: bool) {
        self.value_wrap = wrap;
    }
    /// When every point is at min utility, force max utility at the point nearest the summit
    /// (default on).
    pub fn set_summit_insist(&mut self, insist: bool) {
        self.summit_insist = insist;
    }
    /// How components combine (default [`Combine::Max`]).
    pub fn set_combine(&mut self, combine: Combine) {
        self.combine = combine;
    }

    /// Utility of component `c` at grid index `ix`, from the ZAIC_PEAK formula.
    pub fn eval_component(&self, c: &PeakComponent, ix: u32) -> f64 {
        if ix >= self.var.points() {
            return c.minutil;
        }
        PeakConsts::new(c, &self.var).value(c, f64::from(ix), self.value_wrap)
    }

    /// Utility at grid index `ix`, combining the components.
    pub fn eval_point(&self, ix: u32) -> f64 {
        let mut it = self.components.iter().map(|c| self.eval_component(c, ix));
        let first = it.next().unwrap_or(0.0);
        match self.combine {
            Combine::Max => it.fold(first, |a, b| if b > a { b } else { a }),
            Combine::Sum => it.fold(first, |a, b| a + b),
        }
    }

    /// The utility of every grid index, combined over the components: the same numbers as
    /// [`eval_point`](Self::eval_point), with the per-component constants computed once.
    pub fn values(&self, out: &mut Vec<f64>) {
        let n = self.var.points() as usize;
        out.clear();
        out.resize(n, 0.0);
        for (ci, c) in self.components.iter().enumerate() {
            let k = PeakConsts::new(c, &self.var);
            for (ix, slot) in out.iter_mut().enumerate() {
                let val = k.value(c, ix as f64, self.value_wrap);
                *slot = match (ci, self.combine) {
                    (0, _) => val,
                    (_, Combine::Max) => {
                        if val > *slot {
                            val
                        } else {
                            *slot
                        }
                    }
                    (_, Combine::Sum) => *slot + val,
                };
            }
        }
    }

    /// Builds the function.
    pub fn extract(&self) -> Result<IvpFunction, IvpError> {
        let mut vals = Vec::with_capacity(self.var.points() as usize);
        self.values(&mut vals);
        if self.summit_insist {
            for c in &self.components {
                self.insist_summit(c, &mut vals);
            }
        }
        let mut f = IvpFunction::new(self.domain.clone());
        segment(&vals, SEGMENT_TOLERANCE, &mut f);
        Ok(f)
    }

    fn insist_summit(&self, c: &PeakComponent, vals: &mut [f64]) {
        if vals.iter().any(|&v| v != c.minutil) {
            return;
        }
        let v = &self.var;
        let ix = if c.summit < v.low() {
            0
        } else if c.summit > v.high() {
            v.points() - 1
        } else {
            // nearest grid point; the lower one wins an exact tie
            let mut best = 0;
            let mut best_d = f64::INFINITY;
            for i in 0..v.points() {
                let d = (v.value(i) - c.summit).abs();
                if d < best_d {
                    best_d = d;
                    best = i;
                }
            }
            best
        };
        vals[ix as usize] = c.maxutil;
    }
}

/// Shared state of [`ZaicLeq`] and [`ZaicHeq`].
#[derive(Debug, Clone)]
struct Hleq {
    domain: Domain,
    var: DomainVar,
    summit: f64,
    summit_delta: f64,
    basewidth: f64,
    minutil: f64,
    maxutil: f64,
}

impl Hleq {
    fn new(builder: &'static str, domain: &Domain, var: &str) -> Result<Self, IvpError> {
        let domain = one_var(builder, domain, var)?;
        let v = domain.vars()[0].clone();
        if v.delta() <= 0.0 {
            return Err(IvpError::BadDomain {
                builder,
                reason: format!("variable {var:?} needs more than one point"),
            });
        }
        Ok(Self {
            domain,
            var: v,
            summit: 0.0,
            summit_delta: 0.0,
            basewidth: 0.0,
            minutil: 0.0,
            maxutil: 100.0,
        })
    }

    /// Index of a value, `round((value - low) / delta)`, clamped to the grid.
    ///
    /// MOOS-IvP divides the raw value by delta without subtracting the domain's low end;
    /// the two agree for the usual domains that start at 0, and this is right for the rest.
    fn ix(&self, value: f64) -> u32 {
        let raw = ((value - self.var.low()) / self.var.delta() + 0.5).floor();
        raw.clamp(0.0, f64::from(self.var.points() - 1)) as u32
    }

    fn i_basewidth(&self) -> f64 {
        let d = self.var.delta();
        ((self.basewidth + d / 2.0) / d).floor().max(1.0)
    }
}

macro_rules! hleq_setters {
    ($name:literal) => {
        /// Sets the summit (a value outside the domain is allowed, as in MOOS-IvP).
        pub fn set_summit(&mut self, v: f64) -> Result<(), IvpError> {
            self.0.summit = check_finite($name, "summit", v)?;
            Ok(())
        }
        /// Sets the extra utility of the summit point itself (negative clips to 0).
        pub fn set_summit_delta(&mut self, v: f64) -> Result<(), IvpError> {
            self.0.summit_delta = check_finite($name, "summitdelta", v)?.max(0.0);
            Ok(())
        }
        /// Sets the width of the ramp; negative is an error.
        pub fn set_basewidth(&mut self, v: f64) -> Result<(), IvpError> {
            check_finite($name, "basewidth", v)?;
            if v < 0.0 {
                return Err(IvpError::BadParam {
                    builder: $name,
                    param: "basewidth",
                    value: v,
                    expected: "basewidth >= 0",
                });
            }
            self.0.basewidth = v;
            Ok(())
        }
        /// Sets the utility range; `min >= max` is an error.
        pub fn set_min_max_util(&mut self, min: f64, max: f64) -> Result<(), IvpError> {
            check_min_max($name, min, max)?;
            self.0.minutil = min;
            self.0.maxutil = max;
            Ok(())
        }
    };
}

/// "Value at or below the summit is best" (MOOS-IvP's `ZAIC_LEQ`), e.g. for a max depth.
///
/// Pieces: `[0, s]` at max utility with slope +[`BREAK_TIES`] (nearer the summit wins ties);
/// an optional singleton at `s` worth `maxutil + summitdelta`; a ramp down to min utility over
/// the base width; then min utility with slope −`BREAK_TIES`. As in MOOS-IvP, a summit at the
/// domain's low end leaves index 0 uncovered.
///
/// ```
/// # use ivp::{Domain, ZaicLeq};
/// let d = Domain::from_vars(&[("depth", 0.0, 100.0, 101)]).unwrap();
/// let mut z = ZaicLeq::new(&d, "depth").unwrap();
/// z.set_summit(20.0).unwrap();
/// z.set_basewidth(10.0).unwrap();
/// let f = z.extract().unwrap();
/// assert!((f.eval(&[25]).unwrap() - 50.0).abs() < 1e-9);
/// ```
#[derive(Debug, Clone)]
pub struct ZaicLeq(Hleq);

impl ZaicLeq {
    /// A builder over variable `var` of `domain` (which needs more than one point).
    pub fn new(domain: &Domain, var: &str) -> Result<Self, IvpError> {
        Ok(Self(Hleq::new("ZAIC_LEQ", domain, var)?))
    }
    hleq_setters!("ZAIC_LEQ");

    /// Builds the function.
    pub fn extract(&self) -> Result<IvpFunction, IvpError> {
        let h = &self.0;
        let high = h.var.points() - 1;
        let one = h.ix(h.summit).min(high);
        let two = h.ix(h.summit + h.basewidth).max(one);
        let range = h.maxutil - h.minutil;
        let mut f = IvpFunction::new(h.domain.clone());
        let singleton = h.summit_delta > 0.0 && one > 1;
        if one > 0 {
            let top = if singleton { one - 1 } else { one };
            f.push_unchecked(&[0], &[top], &[BREAK_TIES], h.maxutil);
        }
        if singleton {
            f.push_unchecked(&[one], &[one], &[0.0], h.maxutil + h.summit_delta);
        }
        if one < two {
            let slope = -range / h.i_basewidth();
            let intercept = if one > 0 {
                h.maxutil - slope * f64::from(one)
            } else {
                h.minutil - slope * f64::from(two)
            };
            f.push_unchecked(&[one + 1], &[two], &[slope], intercept);
        }
        if two < high {
            f.push_unchecked(&[two + 1], &[high], &[-BREAK_TIES], h.minutil);
        }
        Ok(f)
    }
}

/// "Value at or above the summit is best" (MOOS-IvP's `ZAIC_HEQ`), the mirror of [`ZaicLeq`].
///
/// ```
/// # use ivp::{Domain, ZaicHeq};
/// let d = Domain::from_vars(&[("speed", 0.0, 4.0, 41)]).unwrap();
/// let mut z = ZaicHeq::new(&d, "speed").unwrap();
/// z.set_summit(2.0).unwrap();
/// z.set_basewidth(1.0).unwrap();
/// let f = z.extract().unwrap();
/// assert!((f.eval(&[15]).unwrap() - 50.0).abs() < 1e-9);
/// ```
#[derive(Debug, Clone)]
pub struct ZaicHeq(Hleq);

impl ZaicHeq {
    /// A builder over variable `var` of `domain` (which needs more than one point).
    pub fn new(domain: &Domain, var: &str) -> Result<Self, IvpError> {
        Ok(Self(Hleq::new("ZAIC_HEQ", domain, var)?))
    }
    hleq_setters!("ZAIC_HEQ");

    /// Builds the function.
    pub fn extract(&self) -> Result<IvpFunction, IvpError> {
        let h = &self.0;
        let high = h.var.points() - 1;
        let two = h.ix(h.summit);
        let one = h.ix(h.summit - h.basewidth).min(two);
        let range = h.maxutil - h.minutil;
        let mut f = IvpFunction::new(h.domain.clone());
        let singleton = h.summit_delta > 0.0 && two + 1 < high;
        if two < high {
            let bottom = if singleton { two + 1 } else { two };
            f.push_unchecked(&[bottom], &[high], &[-BREAK_TIES], h.maxutil);
        }
        if singleton {
            f.push_unchecked(&[two], &[two], &[0.0], h.maxutil + h.summit_delta);
        }
        if one < two {
            let slope = range / h.i_basewidth();
            let intercept = if one > 0 {
                h.minutil - slope * f64::from(one)
            } else {
                h.maxutil - slope * f64::from(two)
            };
            f.push_unchecked(&[one], &[two - 1], &[slope], intercept);
        }
        if one > 0 {
            f.push_unchecked(&[0], &[one - 1], &[BREAK_TIES], h.minutil);
        }
        Ok(f)
    }
}

/// Speed preference (MOOS-IvP's `ZAIC_SPD`): max utility at `med_spd`, chosen utilities at
/// `low_spd` / `hgh_spd` and at the domain's ends, joined linearly.
///
/// ```
/// # use ivp::{Domain, ZaicSpd};
/// let d = Domain::from_vars(&[("speed", 0.0, 4.0, 41)]).unwrap();
/// let z = ZaicSpd::new(&d, "speed", 2.0, 1.5, 2.5, 70.0, 70.0).unwrap();
/// let f = z.extract().unwrap();
/// assert_eq!(f.eval(&[20]), Some(100.0));
/// assert!((f.eval(&[15]).unwrap() - 70.0).abs() < 1e-9);
/// ```
#[derive(Debug, Clone)]
pub struct ZaicSpd {
    domain: Domain,
    var: DomainVar,
    med_spd: f64,
    low_spd: f64,
    hgh_spd: f64,
    low_spd_util: f64,
    hgh_spd_util: f64,
    min_spd_util: f64,
    max_spd_util: f64,
    max_util: f64,
}

impl ZaicSpd {
    /// A builder with `setParams(med, low, hgh, low_util, hgh_util)` and the remaining
    /// parameters at their defaults (`min_spd_util` 0, `max_spd_util` 0, `max_util` 100).
    pub fn new(
        domain: &Domain,
        var: &str,
        med_spd: f64,
        low_spd: f64,
        hgh_spd: f64,
        low_spd_util: f64,
        hgh_spd_util: f64,
    ) -> Result<Self, IvpError> {
        let domain = one_var("ZAIC_SPD", domain, var)?;
        let v = domain.vars()[0].clone();
        let mut z = Self {
            domain,
            var: v,
            med_spd: 0.0,
            low_spd: 0.0,
            hgh_spd: 0.0,
            low_spd_util: 0.0,
            hgh_spd_util: 0.0,
            min_spd_util: 0.0,
            max_spd_util: 0.0,
            max_util: 100.0,
        };
        z.set_params(med_spd, low_spd, hgh_spd, low_spd_util, hgh_spd_util)?;
        Ok(z)
    }

    /// Sets the speeds and their utilities. Speeds clip into the domain; utilities must be
    /// non-negative and clip to `max_util`.
    pub fn set_params(
        &mut self,
        med_spd: f64,
        low_spd: f64,
        hgh_spd: f64,
        low_spd_util: f64,
        hgh_spd_util: f64,
    ) -> Result<(), IvpError> {
        const B: &str = "ZAIC_SPD";
        let lo = self.var.low();
        let hi = self.var.high();
        self.med_spd = check_finite(B, "med_spd", med_spd)?.clamp(lo, hi);
        self.low_spd = check_finite(B, "low_spd", low_spd)?.clamp(lo, hi);
        self.hgh_spd = check_finite(B, "hgh_spd", hgh_spd)?.clamp(lo, hi);
        self.low_spd_util = non_negative(B, "low_spd_util", low_spd_util)?.min(self.max_util);
        self.hgh_spd_util = non_negative(B, "hgh_spd_util", hgh_spd_util)?.min(self.max_util);
        Ok(())
    }

    /// Sets the utilities at the domain's low and high ends and at the summit. `max_util`
    /// must be positive; the others non-negative.
    pub fn set_min_max_util(
        &mut self,
        min_spd_util: f64,
        max_spd_util: f64,
        max_util: f64,
    ) -> Result<(), IvpError> {
        const B: &str = "ZAIC_SPD";
        let max_util = non_negative(B, "max_util", max_util)?;
        if max_util <= 0.0 {
            return Err(IvpError::BadParam {
                builder: B,
                param: "max_util",
                value: max_util,
                expected: "max_util > 0",
            });
        }
        self.max_util = max_util;
        self.min_spd_util = non_negative(B, "min_spd_util", min_spd_util)?;
        self.max_spd_util = non_negative(B, "max_spd_util", max_spd_util)?;
        Ok(())
    }

    /// The knots `(index, utility)` after MOOS-IvP's parameter adjustment.
    pub fn knots(&self) -> Vec<(u32, f64)> {
        let (lo, hi) = (self.var.low(), self.var.high());
        let med = self.med_spd.clamp(lo, hi);
        let low = self.low_spd.clamp(lo, med);
        let hgh = self.hgh_spd.clamp(med, hi);
        let cap = self.max_util;
        let min_u = self.min_spd_util.min(cap);
        let max_u = self.max_spd_util.min(cap);
        let low_u = if low == lo {
            min_u
        } else {
            self.low_spd_util.min(cap)
        };
        let hgh_u = if hgh == hi {
            max_u
        } else {
            self.hgh_spd_util.min(cap)
        };
        let top = self.var.points() - 1;
        let d = self.var.delta();
        let ix = |s: f64| -> u32 {
            if d <= 0.0 {
                0
            } else {
                (((s - lo) / d) + 0.5).floor().clamp(0.0, f64::from(top)) as u32
            }
        };
        let two = ix(med);
        let one = ix(low).min(two);
        let three = ix(hgh).max(two);
        let mut k = Vec::with_capacity(5);
        if two != 0 {
            k.push((0, min_u));
        }
        if one != 0 && one != two {
            k.push((one, low_u));
        }
        k.push((two, cap));
        if three != two {
            k.push((three, hgh_u));
        }
        if top != three {
            k.push((top, max_u));
        }
        k
    }

    /// Builds the function.
    pub fn extract(&self) -> Result<IvpFunction, IvpError> {
        let mut f = IvpFunction::new(self.domain.clone());
        join_knots(&self.knots(), &mut f);
        Ok(f)
    }
}

fn non_negative(builder: &'static str, param: &'static str, v: f64) -> Result<f64, IvpError> {
    check_finite(builder, param, v)?;
    if v < 0.0 {
        return Err(IvpError::BadParam {
            builder,
            param,
            value: v,
            expected: "a value >= 0",
        });
    }
    Ok(v)
}

/// Heading preference with different slopes to port and starboard (MOOS-IvP's `ZAIC_HDG`).
///
/// From the summit, utility falls linearly to `hdelta_util` at `summit + hdelta` (clockwise)
/// and then to `minutil` at `summit + 180`; the port side mirrors with the `l*` parameters.
///
/// ```
/// # use ivp::{Domain, ZaicHdg};
/// let d = Domain::from_vars(&[("course", 0.0, 359.0, 360)]).unwrap();
/// let z = ZaicHdg::new(&d, "course", 90.0, 10.0, 10.0, 50.0, 50.0, 0.0, 100.0).unwrap();
/// assert_eq!(z.eval_point(90), 100.0);
/// assert_eq!(z.eval_point(100), 50.0);
/// assert_eq!(z.eval_point(270), 0.0);
/// ```
#[derive(Debug, Clone)]
pub struct ZaicHdg {
    domain: Domain,
    var: DomainVar,
    summit: f64,
    ldelta: f64,
    hdelta: f64,
    ldelta_util: f64,
    hdelta_util: f64,
    minutil: f64,
    maxutil: f64,
}

impl ZaicHdg {
    /// A builder with all parameters (`setParams` of MOOS-IvP). Deltas clip to `[0, 180]`,
    /// delta utilities clip into `[minutil, maxutil]`; a summit outside the domain or
    /// `minutil >= maxutil` is an error. A course domain that is not inside `[0, 360)` or has
    /// fewer than 4 points is replaced by `0:359:360`, as MOOS-IvP does.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        domain: &Domain,
        var: &str,
        summit: f64,
        ldelta: f64,
        hdelta: f64,
        ldelta_util: f64,
        hdelta_util: f64,
        minutil: f64,
        maxutil: f64,
    ) -> Result<Self, IvpError> {
        const B: &str = "ZAIC_HDG";
        let mut domain = one_var(B, domain, var)?;
        let mut v = domain.vars()[0].clone();
        if v.low() < 0.0 || v.high() >= 360.0 || v.points() < 4 {
            v = DomainVar::new(var, 0.0, 359.0, 360)?;
            domain = Domain::new();
            domain.add(v.clone())?;
        }
        check_finite(B, "summit", summit)?;
        if summit < v.low() || summit > v.high() {
            return Err(IvpError::BadParam {
                builder: B,
                param: "summit",
                value: summit,
                expected: "a summit inside the course domain",
            });
        }
        check_min_max(B, minutil, maxutil)?;
        let clip_util = |name, u: f64| -> Result<f64, IvpError> {
            Ok(check_finite(B, name, u)?
                .clamp(0.0, 100.0)
                .clamp(minutil, maxutil))
        };
        Ok(Self {
            summit,
            ldelta: check_finite(B, "ldelta", ldelta)?.clamp(0.0, 180.0),
            hdelta: check_finite(B, "hdelta", hdelta)?.clamp(0.0, 180.0),
            ldelta_util: clip_util("ldelta_util", ldelta_util)?,
            hdelta_util: clip_util("hdelta_util", hdelta_util)?,
            minutil,
            maxutil,
            domain,
            var: v,
        })
    }

    /// Utility at grid index `ix`.
    pub fn eval_point(&self, ix: u32) -> f64 {
        if ix >= self.var.points() {
            return self.minutil;
        }
        let x = self.var.value(ix);
        if !(0.0..360.0).contains(&x) {
            return self.minutil;
        }
        let s = self.summit;
        let starboard = if s < 180.0 {
            !(x < s || s + (360.0 - x) < 180.0)
        } else {
            !(s > x && s - x < 180.0)
        };
        // both angles lie in [0, 360), so one wrap suffices (equal to `rem_euclid(360)`)
        let wrap = |a: f64| if a < 0.0 { a + 360.0 } else { a };
        let (delta, delta_util, dist) = if starboard {
            (self.hdelta, self.hdelta_util, wrap(x - s))
        } else {
            (self.ldelta, self.ldelta_util, wrap(s - x))
        };
        if dist == delta {
            delta_util
        } else if dist < delta {
            self.maxutil - (self.maxutil - delta_util) / delta * dist
        } else {
            let run = 180.0 - delta;
            if run <= 0.0 {
                return delta_util;
            }
            delta_util - (delta_util - self.minutil) / run * (dist - delta)
        }
    }

    /// Builds the function.
    pub fn extract(&self) -> Result<IvpFunction, IvpError> {
        let vals: Vec<f64> = (0..self.var.points()).map(|i| self.eval_point(i)).collect();
        let mut f = IvpFunction::new(self.domain.clone());
        segment(&vals, SEGMENT_TOLERANCE, &mut f);
        Ok(f)
    }
}

/// ZAIC_Vector: a one-variable function through given `(value, utility)` pairs (MOOS-IvP
/// `ZAIC_Vector`, as BHV_OpRegionV24 builds its heading preference). Each value is snapped to
/// the nearest grid index; pairs that land on the same index are averaged; the first and last
/// utilities are extended to the ends of the variable's range; consecutive knots are joined
/// with linear pieces ([`join_knots`]). Values out of order are sorted first.
///
/// ```
/// use ivp::{Domain, ZaicVector};
/// let d = Domain::parse_specs(["course:0:359:360"]).unwrap();
/// let f = ZaicVector::new(&d, "course", &[90.0, 180.0], &[100.0, 0.0]).unwrap().extract().unwrap();
/// assert_eq!(f.eval(&[0]), Some(100.0));   // extended to the low end
/// assert_eq!(f.eval(&[135]), Some(50.0));  // linear between the knots
/// assert_eq!(f.eval(&[359]), Some(0.0));   // extended to the high end
/// ```
#[derive(Debug, Clone)]
pub struct ZaicVector {
    domain: Domain,
    knots: Vec<(u32, f64)>,
}

impl ZaicVector {
    /// A function over `var` of `domain` through the pairs `values[i] -> utilities[i]`.
    /// Fails without the variable, with lengths that differ, or with fewer than one pair.
    pub fn new(
        domain: &Domain,
        var: &str,
        values: &[f64],
        utilities: &[f64],
    ) -> Result<Self, IvpError> {
        let domain = one_var("ZAIC_Vector", domain, var)?;
        let dv = domain.vars()[0].clone();
        if values.len() != utilities.len() || values.is_empty() {
            return Err(IvpError::BadParam {
                builder: "ZAIC_Vector",
                param: "utilities",
                value: utilities.len() as f64,
                expected: "as many utilities as values, at least one",
            });
        }
        if let Some(u) = utilities.iter().find(|u| !u.is_finite()) {
            return Err(IvpError::BadParam {
                builder: "ZAIC_Vector",
                param: "utilities",
                value: *u,
                expected: "finite utilities",
            });
        }
        let mut pairs: Vec<(u32, f64)> = values
            .iter()
            .zip(utilities)
            .map(|(v, u)| (dv.index(*v, crate::Snap::Nearest), *u))
            .collect();
        pairs.sort_by_key(|p| p.0);
        let mut knots: Vec<(u32, f64)> = Vec::with_capacity(pairs.len() + 2);
        let mut k = 0;
        while k < pairs.len() {
            let ix = pairs[k].0;
            let (mut total, mut n) = (0.0, 0.0);
            while k < pairs.len() && pairs[k].0 == ix {
                total += pairs[k].1;
                n += 1.0;
                k += 1;
            }
            knots.push((ix, total / n));
        }
        let last = dv.points() - 1;
        if knots[0].0 != 0 {
            knots.insert(0, (0, knots[0].1));
        }
        if let Some(&(ix, u)) = knots.last()
            && ix != last
        {
            knots.push((last, u));
        }
        Ok(ZaicVector { domain, knots })
    }

    /// The knots `(index, utility)` the function joins.
    pub fn knots(&self) -> &[(u32, f64)] {
        &self.knots
    }

    /// The function.
    pub fn extract(&self) -> Result<IvpFunction, IvpError> {
        let mut f = IvpFunction::new(self.domain.clone());
        join_knots(&self.knots, &mut f);
        Ok(f)
    }
}
