//! The reflector: samples any function of the decision variables into linear (or scalar)
//! pieces (MOOS-IvP's `OF_Reflector` with uniform pieces, plateau and basin regions, directed
//! refinement, smart refinement and auto-peak refinement, every piece fitted by the C++
//! `Regressor`'s rule).

mod autopeak;
mod checks;
mod refinery;
mod regressor;
mod smart;

pub use checks::DEFAULT_PCHECK_THRESH;
pub use refinery::{RegionBox, boxes_all_speeds, make_regions_apart};
pub use regressor::Degree;

use regressor::Regressor;

use super::domain::Domain;
use super::error::IvpError;
use super::function::IvpFunction;

/// A grid-index box: inclusive `[lo, hi]` per dimension.
#[derive(Debug, Clone, PartialEq, Eq)]
struct IxBox {
    lo: Vec<u32>,
    hi: Vec<u32>,
}

/// Builds an [`IvpFunction`] approximating `f` (evaluated on domain *values*, one per
/// variable) by linear pieces.
///
/// Stages, as in MOOS-IvP: (1) a uniform partition (`uniform_piece` sizes or
/// `uniform_amount` pieces), less the plateau and basin regions, which become pieces of
/// their own ([`Reflector::plateau_region`], [`RegionBox`]); (2) directed refinement: each `refine_region` (in domain values)
/// is cut out of the pieces it overlaps and re-partitioned with its `refine_piece` sizes;
/// (3) smart refinement (`smart_amount`, `smart_percent`, `smart_thresh`, `queue_levels`):
/// the worst-fitted pieces are cut in two, see `reflector/smart.rs`.
/// (4) `auto_peak`: the piece of the highest value is cut, again and again, until that piece
/// is one grid point (`reflector/autopeak.rs`). Every piece, at every stage, is fitted by one
/// routine, MOOS-IvP's `Regressor` (`reflector/regressor.rs`): its corners and centre sampled,
/// the slope per dimension the mean rise over run of corner pairs, the intercept the mean
/// residual, kept within the sampled values by `strict_range` (on by default, as in the C++).
///
/// ```
/// # use ivp::{Domain, Reflector};
/// let d = Domain::from_vars(&[("x", 0.0, 100.0, 101)]).unwrap();
/// let f = Reflector::new(&d, |v: &[f64]| 2.0 * v[0] + 1.0)
///     .set_param("uniform_piece", "x:10").unwrap()
///     .build().unwrap();
/// assert_eq!(f.piece_count(), 11);
/// assert!((f.eval(&[37]).unwrap() - 75.0).abs() < 1e-9);
/// ```
pub struct Reflector<F> {
    domain: Domain,
    func: F,
    uniform_piece: Option<Vec<u32>>,
    uniform_amount: usize,
    refine: Vec<(IxBox, Option<Vec<u32>>)>,
    strict_range: bool,
    normalize: bool,
    /// Plateau regions (`refinery.rs`).
    plateaus: Vec<RegionBox>,
    /// Basin regions.
    basins: Vec<RegionBox>,
    /// The function's known minimum and maximum, for plateau and basin pieces.
    known: Option<(f64, f64)>,
    /// Smart refinement (`smart.rs`).
    smart: smart::Smart,
    /// Linear or scalar pieces.
    degree: Degree,
    /// The auto-peak stage (`autopeak.rs`).
    auto_peak: bool,
    /// `auto_peak_max_pcs`, checked and kept but unused, as in the C++.
    auto_peak_max_pcs: Option<u32>,
    /// `refine_point` settings, checked and kept but unused, as in the C++.
    refine_points: Vec<Vec<i64>>,
}

impl<F: Fn(&[f64]) -> f64> Reflector<F> {
    /// A reflector over `domain` for `func`, with one uniform linear piece, `strict_range`
    /// on and no normalization (the C++ `OF_Reflector`'s defaults).
    pub fn new(domain: &Domain, func: F) -> Self {
        Self {
            domain: domain.clone(),
            func,
            uniform_piece: None,
            uniform_amount: 1,
            refine: Vec::new(),
            strict_range: true,
            normalize: false,
            plateaus: Vec::new(),
            basins: Vec::new(),
            known: None,
            smart: smart::Smart::default(),
            degree: Degree::Linear,
            auto_peak: false,
            auto_peak_max_pcs: None,
            refine_points: Vec::new(),
        }
    }

    /// The pieces' interior functions: linear (the default) or scalar (MOOS `OF_Reflector`'s
    /// `degree` argument, 1 or 0).
    pub fn degree(mut self, degree: Degree) -> Self {
        self.degree = degree;
        self
    }

    /// The `refine_point` settings given, each a grid index per variable as the C++ converts
    /// them (see [`Reflector::set_param`]).
    pub fn refine_points(&self) -> &[Vec<i64>] {
        &self.refine_points
    }

    /// A regressor for this reflector's pieces.
    fn regressor(&self) -> Regressor {
        Regressor::new(
            self.domain.len(),
            self.degree,
            self.strict_range,
            self.known,
        )
    }

    /// Sets one parameter by MOOS-IvP name: `uniform_piece` / `uniform_box` (`"x:5,y:3"`,
    /// piece sizes in grid points), `uniform_amount` (`"100"`), `refine_region`
    /// (`"x:0:10,y:-5:5"`, in domain values; variables not named span their range),
    /// `refine_piece` (sizes, pairs with the latest region), `strict_range` and `normalize`
    /// (`true`/`false`); smart refinement: `smart_amount` (alias `priority_amt`) and
    /// `smart_percent` (pieces to add, numbers >= 0, their whole part taken), `smart_thresh`
    /// (the fit error at or below which a piece is not cut, >= 0), `queue_levels` (>= 1,
    /// default 8); `auto_peak` (`true`/`false`: the auto-peak stage, off by default);
    /// `auto_peak_max_pcs` (a number > 0) and `refine_point` (a value for every variable,
    /// `"x:3,y:all"`, optionally prefixed `native@`, `float@` or `discrete@`), both checked as
    /// the C++ checks them and kept, but used by no stage, as in `OF_Reflector` at a2a9b716.
    pub fn set_param(mut self, name: &str, value: &str) -> Result<Self, IvpError> {
        let value = value.trim();
        match name.trim().to_ascii_lowercase().as_str() {
            "uniform_piece" | "uniform_box" => self.uniform_piece = Some(self.parse_sizes(value)?),
            "uniform_amount" => {
                self.uniform_amount =
                    value
                        .parse::<usize>()
                        .ok()
                        .filter(|&n| n >= 1)
                        .ok_or_else(|| {
                            IvpError::Reflector(format!(
                                "uniform_amount {value:?} is not a whole number >= 1"
                            ))
                        })?;
            }
            "refine_region" => {
                let region = self.parse_region(value)?;
                self.refine.push((region, None));
            }
            "refine_piece" => {
                let sizes = self.parse_sizes(value)?;
                match self.refine.last_mut() {
                    Some((_, slot @ None)) => *slot = Some(sizes),
                    _ => {
                        return Err(IvpError::Reflector(
                            "refine_piece must follow a refine_region".to_string(),
                        ));
                    }
                }
            }
            "smart_amount" | "priority_amt" => self.smart.amount = parse_count(name, value)?,
            "smart_percent" => self.smart.percent = parse_count(name, value)?,
            "smart_thresh" => {
                self.smart.thresh =
                    value
                        .parse::<f64>()
                        .ok()
                        .filter(|t| *t >= 0.0)
                        .ok_or_else(|| {
                            IvpError::Reflector(format!(
                                "smart_thresh {value:?} is not a number >= 0"
                            ))
                        })?;
            }
            "queue_levels" => {
                self.smart.levels = u32::try_from(parse_count(name, value)?)
                    .ok()
                    .filter(|&n| n >= 1)
                    .ok_or_else(|| {
                        IvpError::Reflector(format!("queue_levels {value:?} is not >= 1"))
                    })?;
            }
            "strict_range" => self.strict_range = parse_bool(value)?,
            "auto_peak" => {
                self.auto_peak = parse_bool(value).map_err(|_| {
                    IvpError::Reflector(format!("auto_peak {value:?} is not true or false"))
                })?;
            }
            "auto_peak_max_pcs" => {
                let n = value.parse::<f64>().ok().filter(|n| n.is_finite());
                let n = n.map(|n| n.trunc()).filter(|n| *n >= 1.0).ok_or_else(|| {
                    IvpError::Reflector(format!("auto_peak_max_pcs {value:?} is not > 0"))
                })?;
                self.auto_peak_max_pcs = Some(n.min(f64::from(u32::MAX)) as u32);
            }
            "refine_point" => {
                let point = self.parse_point(value)?;
                self.refine_points.push(point);
            }
            "normalize" => self.normalize = parse_bool(value)?,
            other => {
                return Err(IvpError::Reflector(format!("unknown parameter {other:?}")));
            }
        }
        Ok(self)
    }

    /// Applies `"name=value # name=value ..."` settings in order (MOOS-IvP's combined form).
    pub fn set_params(mut self, spec: &str) -> Result<Self, IvpError> {
        for part in spec.split('#').map(str::trim).filter(|p| !p.is_empty()) {
            let (k, v) = part
                .split_once('=')
                .ok_or_else(|| IvpError::Reflector(format!("setting {part:?} has no `=`")))?;
            self = self.set_param(k, v)?;
        }
        Ok(self)
    }

    fn parse_sizes(&self, spec: &str) -> Result<Vec<u32>, IvpError> {
        let mut sizes: Vec<u32> = self.domain.vars().iter().map(|v| v.points()).collect();
        for part in spec.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let (name, n) = part.split_once(':').ok_or_else(|| {
                IvpError::Reflector(format!("piece size {part:?} is not name:size"))
            })?;
            let ix = self.domain.index_of(name.trim()).ok_or_else(|| {
                IvpError::Reflector(format!("unknown variable {:?}", name.trim()))
            })?;
            let n: u32 = n.trim().parse().ok().filter(|&n| n >= 1).ok_or_else(|| {
                IvpError::Reflector(format!("piece size {part:?} is not a whole number >= 1"))
            })?;
            sizes[ix] = n;
        }
        Ok(sizes)
    }

    /// A `refine_point` value as MOOS `stringToPointBox` reads it: `native@` (the default, or
    /// `float@`) takes a number or `all` (the variable's high value) for every variable,
    /// clipped to its range, and makes it the index `(int)(value / delta + 0.5) - 1` (the
    /// C++ reads the value as a piece's extent); `discrete@` takes a whole number of points
    /// `n >= 1` (at most the variable's points) and makes it `n - 1`. A variable left out, a
    /// value that is not a number, another prefix or a second `@` is an error.
    fn parse_point(&self, spec: &str) -> Result<Vec<i64>, IvpError> {
        let bad = || IvpError::Reflector(format!("refine_point {spec:?} is ill-defined"));
        let parts: Vec<&str> = spec.split('@').collect();
        let (discrete, body) = match parts.as_slice() {
            [body] => (false, *body),
            [pre, body] => match pre.trim().to_ascii_lowercase().as_str() {
                "discrete" => (true, *body),
                "native" | "float" => (false, *body),
                _ => return Err(bad()),
            },
            _ => return Err(bad()),
        };
        let fields: Vec<(String, String)> = body
            .split(',')
            .filter_map(|part| {
                let f: Vec<&str> = part.split(':').map(str::trim).collect();
                (f.len() == 2).then(|| (f[0].to_ascii_lowercase(), f[1].to_ascii_lowercase()))
            })
            .collect();
        let number = |v: &str| v.parse::<f64>().ok().filter(|n| n.is_finite());
        let mut point = Vec::with_capacity(self.domain.len());
        for var in self.domain.vars() {
            let name = var.name().to_ascii_lowercase();
            let value = fields
                .iter()
                .find(|(n, _)| *n == name)
                .map(|(_, v)| v.as_str())
                .ok_or_else(bad)?;
            if discrete {
                let n = number(value).map(|n| n.trunc()).filter(|n| *n >= 1.0);
                let n = n.ok_or_else(bad)?.min(f64::from(var.points()));
                point.push(n as i64 - 1);
            } else {
                let v = if value == "all" {
                    var.high()
                } else {
                    number(value).ok_or_else(bad)?.clamp(var.low(), var.high())
                };
                point.push((v / var.delta() + 0.5) as i64 - 1);
            }
        }
        Ok(point)
    }

    fn parse_region(&self, spec: &str) -> Result<IxBox, IvpError> {
        use super::domain::Snap;
        let mut b = self.universe();
        for part in spec.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let f: Vec<&str> = part.split(':').map(str::trim).collect();
            let bad = || IvpError::Reflector(format!("region {part:?} is not name:low:high"));
            if f.len() != 3 {
                return Err(bad());
            }
            let ix = self
                .domain
                .index_of(f[0])
                .ok_or_else(|| IvpError::Reflector(format!("unknown variable {:?}", f[0])))?;
            let lo: f64 = f[1].parse().map_err(|_| bad())?;
            let hi: f64 = f[2].parse().map_err(|_| bad())?;
            if lo.is_nan() || hi.is_nan() || lo > hi {
                return Err(bad());
            }
            let v = &self.domain.vars()[ix];
            b.lo[ix] = v.index(lo, Snap::Ceil);
            b.hi[ix] = v.index(hi, Snap::Floor).max(b.lo[ix]);
        }
        Ok(b)
    }

    fn universe(&self) -> IxBox {
        IxBox {
            lo: vec![0; self.domain.len()],
            hi: self.domain.vars().iter().map(|v| v.points() - 1).collect(),
        }
    }

    /// Piece sizes giving at most `amount` uniform pieces (MOOS `genUnifBox`): one more
    /// piece at a time along the variable whose pieces are longest, a variable maxed out
    /// once one more piece there would pass the amount or give more pieces than points.
    fn sizes_for_amount(&self, amount: usize) -> Vec<u32> {
        let pts: Vec<f64> = self
            .domain
            .vars()
            .iter()
            .map(|v| f64::from(v.points()))
            .collect();
        let d = pts.len();
        let mut pcs = vec![1.0f64; d];
        let mut maxed = vec![false; d];
        while !maxed.iter().all(|&m| m) {
            let mut grow = 0;
            let mut biggest = 0.0;
            for k in 0..d {
                if !maxed[k] && pts[k] / pcs[k] > biggest {
                    biggest = pts[k] / pcs[k];
                    grow = k;
                }
            }
            pcs[grow] += 1.0;
            if pcs.iter().product::<f64>() > amount as f64 {
                maxed[grow] = true;
                pcs[grow] -= 1.0;
            }
            if pcs[grow] >= pts[grow] {
                maxed[grow] = true;
            }
        }
        (0..d).map(|k| (pts[k] / pcs[k]).ceil() as u32).collect()
    }

    /// Builds the function.
    pub fn build(self) -> Result<IvpFunction, IvpError> {
        if self.domain.is_empty() {
            return Err(IvpError::Reflector("empty domain".to_string()));
        }
        let sizes = match &self.uniform_piece {
            Some(s) => s.clone(),
            None => self.sizes_for_amount(self.uniform_amount),
        };
        let (mut f, plats) = if self.smart.active() {
            (self.build_smart(&sizes)?, Vec::new())
        } else if !self.plateaus.is_empty() || !self.basins.is_empty() {
            self.build_with_regions(&sizes)?
        } else if self.refine.is_empty() {
            (self.build_uniform(&sizes)?, Vec::new())
        } else {
            (self.build_boxes(&sizes)?, Vec::new())
        };
        if self.auto_peak {
            f = self.build_auto_peak(&f, &plats)?;
        }
        if self.normalize {
            f.normalize(0.0, 100.0);
        }
        Ok(f)
    }

    /// Stages 1 and 2 through the list of boxes: the uniform grid, then each refine
    /// region's split.
    fn build_boxes(&self, sizes: &[u32]) -> Result<IvpFunction, IvpError> {
        let boxes = self.directed_boxes(sizes);
        let mut f = IvpFunction::new(self.domain.clone());
        let mut reg = self.regressor();
        let d = self.domain.len();
        for b in &boxes {
            reg.fit(&b.lo, &b.hi, 0, &self.domain, &self.func)?;
            f.push_piece(&b.lo, &b.hi, &reg.wts()[..d], reg.wts()[d])?;
        }
        Ok(f)
    }
}

impl<F: Fn(&[f64]) -> f64> Reflector<F> {
    /// The uniform grid's boxes, then each refine region's split (stages 1 and 2 without
    /// plateau or basin regions).
    fn directed_boxes(&self, sizes: &[u32]) -> Vec<IxBox> {
        let mut boxes = Vec::new();
        partition(&self.universe(), sizes, &mut boxes);
        for (region, piece) in &self.refine {
            let piece = piece.clone().unwrap_or_else(|| vec![1; self.domain.len()]);
            let mut next = Vec::with_capacity(boxes.len());
            for b in boxes {
                refine_box(b, region, &piece, &mut next);
            }
            boxes = next;
        }
        boxes
    }

    /// Stage 1 without refinement: the pieces of the uniform grid, visited in `partition`'s
    /// order (the last variable fastest) through two reused bound buffers, so the pieces and
    /// weights are those of the general path without a box per piece.
    fn build_uniform(&self, sizes: &[u32]) -> Result<IvpFunction, IvpError> {
        let d = self.domain.len();
        let top: Vec<u32> = self.domain.vars().iter().map(|v| v.points() - 1).collect();
        let step: Vec<u32> = sizes.iter().map(|s| s.max(&1) - 1).collect();
        let count: usize = (0..d)
            .map(|k| (top[k] + 1).div_ceil(step[k] + 1) as usize)
            .product();
        let mut f = IvpFunction::new(self.domain.clone());
        f.reserve(count);
        let mut reg = self.regressor();
        let mut lo = vec![0u32; d];
        let mut hi = vec![0u32; d];
        loop {
            for k in 0..d {
                hi[k] = lo[k].saturating_add(step[k]).min(top[k]);
            }
            reg.fit(&lo, &hi, 0, &self.domain, &self.func)?;
            f.push_piece(&lo, &hi, &reg.wts()[..d], reg.wts()[d])?;
            let mut k = d;
            loop {
                if k == 0 {
                    return Ok(f);
                }
                k -= 1;
                if hi[k] < top[k] {
                    lo[k] = hi[k] + 1;
                    lo[k + 1..].fill(0);
                    break;
                }
            }
        }
    }
}

/// A count as the C++ reads it: a number >= 0, its whole part taken (`atoi`).
/// The function of fitted pieces, in their order: each piece's box and its weights (one
/// slope per dimension, then the intercept), as smart refinement and `auto_peak` leave them.
fn function_of<'a>(
    domain: &Domain,
    pieces: impl ExactSizeIterator<Item = (&'a IxBox, &'a [f64])>,
) -> Result<IvpFunction, IvpError> {
    let d = domain.len();
    let mut f = IvpFunction::new(domain.clone());
    f.reserve(pieces.len());
    for (b, wts) in pieces {
        f.push_piece(&b.lo, &b.hi, &wts[..d], wts[d])?;
    }
    Ok(f)
}

fn parse_count(name: &str, v: &str) -> Result<usize, IvpError> {
    v.parse::<f64>()
        .ok()
        .filter(|n| n.is_finite() && *n >= 0.0)
        .map(|n| n as usize)
        .ok_or_else(|| IvpError::Reflector(format!("{name} {v:?} is not a number >= 0")))
}

fn parse_bool(v: &str) -> Result<bool, IvpError> {
    moos_types::text::strict_bool(v)
        .ok_or_else(|| IvpError::Reflector(format!("{v:?} is not true or false")))
}

/// Splits `b` into pieces of `sizes` (the last piece per dimension may be smaller), first
/// dimension slowest.
fn partition(b: &IxBox, sizes: &[u32], out: &mut Vec<IxBox>) {
    let d = b.lo.len();
    let mut cur = b.lo.clone();
    loop {
        let hi: Vec<u32> = (0..d)
            .map(|k| (cur[k].saturating_add(sizes[k].max(1) - 1)).min(b.hi[k]))
            .collect();
        out.push(IxBox {
            lo: cur.clone(),
            hi: hi.clone(),
        });
        // advance the odometer, last dimension fastest
        let mut k = d;
        loop {
            if k == 0 {
                return;
            }
            k -= 1;
            if hi[k] < b.hi[k] {
                cur[k] = hi[k] + 1;
                cur[k + 1..].copy_from_slice(&b.lo[k + 1..]);
                break;
            }
        }
    }
}

/// Cuts `region` out of `b`: the parts outside stay whole, the overlap is re-partitioned.
fn refine_box(mut b: IxBox, region: &IxBox, piece: &[u32], out: &mut Vec<IxBox>) {
    let d = b.lo.len();
    if (0..d).any(|k| b.hi[k] < region.lo[k] || region.hi[k] < b.lo[k]) {
        out.push(b);
        return;
    }
    for k in 0..d {
        if b.lo[k] < region.lo[k] {
            let mut below = b.clone();
            below.hi[k] = region.lo[k] - 1;
            out.push(below);
            b.lo[k] = region.lo[k];
        }
        if b.hi[k] > region.hi[k] {
            let mut above = b.clone();
            above.lo[k] = region.hi[k] + 1;
            out.push(above);
            b.hi[k] = region.hi[k];
        }
    }
    partition(&b, piece, out);
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dom2() -> Domain {
        Domain::from_vars(&[("x", 0.0, 20.0, 21), ("y", -5.0, 5.0, 11)]).unwrap()
    }

    #[test]
    fn planes_are_reproduced_exactly() {
        let f = Reflector::new(&dom2(), |v: &[f64]| 3.0 * v[0] - 2.0 * v[1] + 4.0)
            .set_params("uniform_piece = x:4,y:3")
            .unwrap()
            .build()
            .unwrap();
        // x: 21 pts / 4 -> 6 pieces; y: 11 / 3 -> 4 pieces
        assert_eq!(f.piece_count(), 24);
        for x in 0..21u32 {
            for y in 0..11u32 {
                let want = 3.0 * f64::from(x) - 2.0 * (f64::from(y) - 5.0) + 4.0;
                assert!((f.eval(&[x, y]).unwrap() - want).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn uniform_amount_and_refinement_partition_the_domain() {
        let f = Reflector::new(&dom2(), |v: &[f64]| -(v[0] - 10.0).powi(2) - v[1].powi(2))
            .set_param("uniform_amount", "4")
            .unwrap()
            .set_param("refine_region", "x:8:12,y:-1:1")
            .unwrap()
            .set_param("refine_piece", "x:1,y:1")
            .unwrap()
            .build()
            .unwrap();
        // every grid point is covered by exactly one piece
        for x in 0..21u32 {
            for y in 0..11u32 {
                let n = f.pieces().filter(|p| p.contains(&[x, y])).count();
                assert_eq!(n, 1, "point {x},{y}");
            }
        }
        // inside the refined region the fit is exact (unit pieces)
        let v = f.eval(&[10, 5]).unwrap();
        assert!(v.abs() < 1e-9);
        let v = f.eval(&[11, 6]).unwrap();
        assert!((v + 2.0).abs() < 1e-9);
    }

    #[test]
    fn the_uniform_grid_gives_the_pieces_of_the_box_list() {
        let d3 = Domain::from_vars(&[
            ("course", 0.0, 359.0, 360),
            ("speed", 0.0, 4.0, 41),
            ("depth", 0.0, 20.0, 5),
        ])
        .unwrap();
        let wavy = |v: &[f64]| {
            let c = v[0].to_radians();
            (c.sin() * 40.0 + v[1] * v[1] * 3.0 - v.get(2).copied().unwrap_or(0.0)).max(-10.0)
        };
        for (dom, spec) in [
            (dom2(), "uniform_piece = x:4,y:3"),
            (dom2(), "uniform_piece = x:1,y:11 # strict_range = true"),
            (dom2(), "uniform_amount = 7 # normalize = true"),
            (
                d3.clone(),
                "uniform_piece = course:3,speed:3,depth:2 # normalize = true",
            ),
            (d3, "uniform_piece = course:7,speed:5 # strict_range = true"),
        ] {
            let r = || Reflector::new(&dom, wavy).set_params(spec).unwrap();
            let sizes = match &r().uniform_piece {
                Some(s) => s.clone(),
                None => r().sizes_for_amount(r().uniform_amount),
            };
            let fast = r().build().unwrap();
            let mut boxes = r().build_boxes(&sizes).unwrap();
            if spec.contains("normalize") {
                boxes.normalize(0.0, 100.0);
            }
            assert!(fast.piece_count() > 1, "{spec}");
            assert_eq!(fast.piece_count(), boxes.piece_count(), "{spec}");
            for (a, b) in fast.pieces().zip(boxes.pieces()) {
                assert_eq!((a.lo, a.hi), (b.lo, b.hi), "{spec}");
                // The same arithmetic in the same order: equal to the bit.
                let bits = |w: &[f64]| w.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(a.wts), bits(b.wts), "{spec}");
            }
        }
    }

    #[test]
    fn strict_range_and_normalize() {
        let d = Domain::from_vars(&[("x", 0.0, 10.0, 11)]).unwrap();
        let f = Reflector::new(&d, |v: &[f64]| (v[0] - 5.0).abs())
            .set_params("uniform_piece=x:11 # strict_range=true # normalize=true")
            .unwrap()
            .build()
            .unwrap();
        assert_eq!(f.piece_count(), 1);
        assert!(f.max_val() <= 100.0 + 1e-9);
    }

    #[test]
    fn bad_settings_are_errors() {
        let d = dom2();
        let r = || Reflector::new(&d, |_: &[f64]| 0.0);
        assert!(r().set_param("uniform_piece", "z:3").is_err());
        assert!(r().set_param("uniform_piece", "x:0").is_err());
        assert!(r().set_param("uniform_amount", "-3").is_err());
        assert!(r().set_param("refine_piece", "x:1").is_err());
        assert!(r().set_param("refine_region", "x:5:1").is_err());
        assert!(r().set_param("bogus", "1").is_err());
        assert!(r().set_params("uniform_amount").is_err());
        let nan = Reflector::new(&d, |_: &[f64]| f64::NAN).build();
        assert!(nan.is_err());
    }

    #[test]
    fn auto_peak_and_refine_point_are_checked_as_the_cpp_checks_them() {
        let d = dom2();
        let r = || Reflector::new(&d, |v: &[f64]| v[0]);
        assert!(r().set_param("auto_peak", "TRUE").unwrap().auto_peak);
        assert!(!r().set_param("auto_peak", "false").unwrap().auto_peak);
        assert!(r().set_param("auto_peak", "yes").is_err());
        // auto_peak_max_pcs: a number whose whole part is > 0 (kept, unused).
        assert_eq!(
            r().set_param("auto_peak_max_pcs", "2.5")
                .unwrap()
                .auto_peak_max_pcs,
            Some(2)
        );
        for bad in ["0", "0.9", "-3", "many"] {
            assert!(r().set_param("auto_peak_max_pcs", bad).is_err(), "{bad}");
        }
        // refine_point: every variable, the value read as an extent (value / delta + 0.5,
        // truncated, less 1), clipped to the range first; `all` is the high value. x 12.85:
        // 13.35 -> 12; y 7.4 clipped to y's high 5: 5.5 -> 4.
        let p = r().set_param("refine_point", "y:7.4, x:12.85").unwrap();
        assert_eq!(p.refine_points(), [vec![12, 4]]);
        let p = r()
            .set_params("refine_point = native@x:all,y:-9 # refine_point = discrete@x:3,y:40")
            .unwrap();
        // x all: 20 -> 19; y -9 clipped to -5 -> (-5 + 0.5) as int = -4, less 1: -5;
        // discrete: 3 points -> 2, 40 points clipped to y's 11 -> 10.
        assert_eq!(p.refine_points(), [vec![19, -5], vec![2, 10]]);
        for bad in [
            "x:3",
            "x:3,y:abc",
            "",
            "discrete@x:0,y:1",
            "grid@x:1,y:1",
            "native@x:1@y:1",
        ] {
            assert!(r().set_param("refine_point", bad).is_err(), "{bad:?}");
        }
        // No stage uses them: the function is the same.
        let f = |r: Reflector<_>| r.set_param("uniform_piece", "x:4,y:3").unwrap().build();
        let plain = f(r()).unwrap();
        let with = f(r()
            .set_params("refine_point = x:3,y:2 # auto_peak_max_pcs = 1")
            .unwrap())
        .unwrap();
        assert_eq!(plain, with);
    }

    #[test]
    fn every_path_fits_a_piece_alike() {
        // The piece x 0..3, y 0..2 of a curved function, built on each path: uniform,
        // directed (a region elsewhere), with a plateau region elsewhere, with smart
        // refinement that cuts elsewhere, and after auto_peak when the peak is elsewhere.
        let curved = |v: &[f64]| 50.0 - (v[0] - 15.0).powi(2) / 4.0 + v[1] * v[1];
        let d = dom2();
        let r = || {
            Reflector::new(&d, curved)
                .set_param("uniform_piece", "x:4,y:3")
                .unwrap()
        };
        let piece = |f: &IvpFunction| {
            let p = f.pieces().find(|p| p.lo == [0, 0]).unwrap();
            assert_eq!(p.hi, [3, 2]);
            p.wts.to_vec()
        };
        let want = piece(&r().build().unwrap());
        let mut reg = Regressor::new(2, Degree::Linear, true, None);
        reg.fit(&[0, 0], &[3, 2], 0, &d, &curved).unwrap();
        assert_eq!(want, reg.wts());
        let directed = r()
            .set_params("refine_region = x:12:20,y:-5:5 # refine_piece = x:1,y:1")
            .unwrap();
        let plateau = r()
            .plateau_region(RegionBox {
                lo: vec![16, 0],
                hi: vec![20, 10],
                plat: 1,
            })
            .unwrap();
        let smart = r().set_param("smart_amount", "3").unwrap();
        let peak = r().set_param("auto_peak", "true").unwrap();
        for (name, r) in [
            ("directed", directed),
            ("plateau", plateau),
            ("smart", smart),
            ("auto_peak", peak),
        ] {
            let f = r.build().unwrap();
            assert_eq!(piece(&f), want, "{name}");
        }
    }
}
