//! The IvP solver: exact maximization of the weighted sum of piecewise-linear functions by
//! branch and bound (MOOS-IvP's `IvPProblem` as used by pHelmIvP).
//!
//! Semantics kept from pHelmIvP:
//! - functions are taken in the order of their owners' names (pHelmIvP keeps them in a map
//!   keyed by behaviour name); functions with priority weight `<= 0` or NaN are dropped;
//! - the problem is solved over the sub-domain of variables some function uses, in first-seen
//!   order; each function is embedded there (unused variables span their range, slope 0);
//! - a function whose value range exceeds 100 is first normalized to `[0, 100]`, then every
//!   weight is multiplied by the priority weight;
//! - branch and bound goes piece by piece of the first function, intersecting with the pieces
//!   of each next function; a branch is followed only if its upper bound is strictly greater
//!   than the best value so far, and a leaf replaces the best only if strictly greater, so the
//!   first optimum found wins ties;
//! - the decision per variable is the domain value of the best box's maximum point (low end
//!   where the combined slope is negative, else the high end).
//!
//! The upper bound of a branch is its exact maximum so far plus, for each function not yet
//! intersected, the largest value that function takes in the grid cells the branch overlaps.

use super::domain::Domain;
use super::error::IvpError;
use super::function::IvpFunction;

/// One decided variable.
#[derive(Debug, Clone, PartialEq)]
pub struct DecisionVar {
    /// Variable name, e.g. `course`.
    pub name: String,
    /// Chosen grid index.
    pub index: u32,
    /// Chosen value.
    pub value: f64,
}

/// The solver's answer.
#[derive(Debug, Clone, PartialEq)]
pub struct Decision {
    /// Decided variables, in sub-domain order (only variables some function uses).
    pub vars: Vec<DecisionVar>,
    /// The optimal collective value `Σ pwt_i * f_i(x)`.
    pub value: f64,
}

impl Decision {
    /// The decided value of `name`, if any function used it.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.vars.iter().find(|v| v.name == name).map(|v| v.value)
    }
}

/// A set of objective functions over a helm domain, each with an owner name.
///
/// ```
/// # use ivp::{Domain, Problem, ZaicPeak};
/// let d = Domain::from_vars(&[("course", 0.0, 359.0, 360), ("speed", 0.0, 4.0, 41)]).unwrap();
/// let mut z = ZaicPeak::new(&d, "course").unwrap();
/// z.set_params(45.0, 0.0, 90.0, 0.0, 0.0, 100.0).unwrap();
/// z.set_value_wrap(true);
/// let mut p = Problem::new(d);
/// p.add("bhv_a", z.extract().unwrap().with_pwt(100.0)).unwrap();
/// let decision = p.solve().unwrap();
/// assert_eq!(decision.get("course"), Some(45.0));
/// assert_eq!(decision.get("speed"), None); // nobody decided speed
/// ```
#[derive(Debug, Clone)]
pub struct Problem {
    domain: Domain,
    entries: Vec<(String, IvpFunction)>,
}

impl Problem {
    /// An empty problem over the helm's `domain`.
    pub fn new(domain: Domain) -> Self {
        Self {
            domain,
            entries: Vec::new(),
        }
    }
    /// The helm domain.
    pub fn domain(&self) -> &Domain {
        &self.domain
    }
    /// Adds `f`, owned by behaviour `owner`. Every variable of `f` must be in the helm
    /// domain with the same grid.
    pub fn add(&mut self, owner: &str, f: IvpFunction) -> Result<(), IvpError> {
        f.dim_map(&self.domain)?;
        self.entries.push((owner.to_string(), f));
        Ok(())
    }
    /// Removes every function (keeps the domain and the allocation).
    pub fn clear(&mut self) {
        self.entries.clear();
    }
    /// Number of functions added.
    pub fn len(&self) -> usize {
        self.entries.len()
    }
    /// True when no function was added.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }
    /// The functions with their owners, in the order added.
    pub fn functions(&self) -> impl Iterator<Item = (&str, &IvpFunction)> {
        self.entries.iter().map(|(o, f)| (o.as_str(), f))
    }
    /// Solves with a fresh [`Solver`]; `None` when no function takes part (no decision).
    pub fn solve(&self) -> Option<Decision> {
        Solver::default().solve(self)
    }
}

/// A uniform grid over one function: per cell the best value reachable in it and the pieces
/// overlapping it (compressed rows).
#[derive(Debug, Default, Clone)]
struct Grid {
    width: Vec<u32>,
    cells: Vec<u32>,
    stride: Vec<usize>,
    cell_max: Vec<f64>,
    start: Vec<u32>,
    members: Vec<u32>,
}

/// Reusable buffers for building grids.
#[derive(Debug, Default, Clone)]
struct GridScratch {
    active: Vec<bool>,
    clo: Vec<u32>,
    chi: Vec<u32>,
    odo: Vec<u32>,
    fill: Vec<u32>,
}

/// One function ready for the search: embedded in the sub-domain and weighted.
#[derive(Debug, Default, Clone)]
struct Prepared {
    lo: Vec<u32>,
    hi: Vec<u32>,
    wts: Vec<f64>,
    n: usize,
    max: f64,
    grid: Grid,
    stamp: Vec<u32>,
    stamp_id: u32,
}

/// The branch-and-bound solver. Keeping one `Solver` across helm iterations reuses its
/// buffers, so a steady-state solve allocates nothing but the returned [`Decision`].
#[derive(Debug, Default, Clone)]
pub struct Solver {
    order: Vec<usize>,
    sub: Vec<usize>,
    funcs: Vec<Prepared>,
    used: usize,
    dim: usize,
    suffix_max: Vec<f64>,
    // per level: node box and weights
    node_lo: Vec<u32>,
    node_hi: Vec<u32>,
    node_w: Vec<f64>,
    cand: Vec<Vec<u32>>,
    cells_lo: Vec<u32>,
    cells_hi: Vec<u32>,
    odo: Vec<u32>,
    points: Vec<u32>,
    map: Vec<usize>,
    scratch: GridScratch,
    best_val: f64,
    best_pt: Vec<u32>,
    found: bool,
    nodes: u64,
    no_seed: bool,
}

impl Solver {
    /// A solver with empty buffers.
    pub fn new() -> Self {
        Self::default()
    }

    /// Turns the seed threshold (see the module docs) on or off; on by default. The decision is
    /// the same either way; this exists to measure and test that.
    pub fn with_seeding(mut self, on: bool) -> Self {
        self.no_seed = !on;
        self
    }

    /// Branch-and-bound nodes visited by the last solve (for benchmarks and tests).
    pub fn nodes_visited(&self) -> u64 {
        self.nodes
    }

    /// Solves `problem`; `None` when no function takes part.
    pub fn solve(&mut self, problem: &Problem) -> Option<Decision> {
        self.prepare(problem);
        self.nodes = 0;
        if self.used == 0 || self.funcs[..self.used].iter().any(|f| f.n == 0) {
            return None;
        }
        if !self.no_seed {
            self.seed();
        }
        self.search();
        if !self.found {
            return None;
        }
        let vars = self
            .sub
            .iter()
            .enumerate()
            .map(|(k, &t)| {
                let v = &problem.domain.vars()[t];
                DecisionVar {
                    name: v.name().to_string(),
                    index: self.best_pt[k],
                    value: v.value(self.best_pt[k]),
                }
            })
            .collect();
        Some(Decision {
            vars,
            value: self.best_val,
        })
    }

    fn prepare(&mut self, problem: &Problem) {
        let entries = &problem.entries;
        self.order.clear();
        self.order.extend(
            (0..entries.len())
                .filter(|&i| entries[i].1.pwt() > 0.0 && entries[i].1.pwt().is_finite()),
        );
        self.order.sort_by(|&a, &b| entries[a].0.cmp(&entries[b].0));
        // sub-domain: variables in first-seen order
        self.sub.clear();
        for &i in &self.order {
            for v in entries[i].1.domain().vars() {
                if let Some(t) = problem.domain.index_of(v.name())
                    && !self.sub.contains(&t)
                {
                    self.sub.push(t);
                }
            }
        }
        let d = self.sub.len();
        self.dim = d;
        self.used = self.order.len();
        while self.funcs.len() < self.used {
            self.funcs.push(Prepared::default());
        }
        let mut points = std::mem::take(&mut self.points);
        points.clear();
        points.extend(self.sub.iter().map(|&t| problem.domain.vars()[t].points()));
        let mut map = std::mem::take(&mut self.map);
        for slot in 0..self.used {
            let f = &entries[self.order[slot]].1;
            // map each function dim to a sub-domain dim
            map.clear();
            map.extend(f.domain().vars().iter().map(|v| {
                let t = problem.domain.index_of(v.name()).unwrap_or(0);
                self.sub.iter().position(|&s| s == t).unwrap_or(0)
            }));
            let (fmin, fmax) = (f.min_val(), f.max_val());
            let (shift, scale) = if fmax - fmin > 100.0 {
                (-fmin, 100.0 / (fmax - fmin))
            } else {
                (0.0, 1.0)
            };
            let k = scale * f.pwt();
            let p = &mut self.funcs[slot];
            p.lo.clear();
            p.hi.clear();
            p.wts.clear();
            p.n = f.piece_count();
            let mut max = f64::NEG_INFINITY;
            for piece in f.pieces() {
                let base = p.lo.len();
                p.lo.extend(std::iter::repeat_n(0, d));
                p.hi.extend(points.iter().map(|&n| n - 1));
                let wbase = p.wts.len();
                p.wts.extend(std::iter::repeat_n(0.0, d + 1));
                for (fd, &sd) in map.iter().enumerate() {
                    p.lo[base + sd] = piece.lo[fd];
                    p.hi[base + sd] = piece.hi[fd];
                    p.wts[wbase + sd] = piece.wts[fd] * k;
                }
                p.wts[wbase + d] = (piece.intercept() + shift) * k;
                max = max.max(box_max(
                    &p.lo[base..base + d],
                    &p.hi[base..base + d],
                    &p.wts[wbase..wbase + d + 1],
                ));
            }
            p.max = max;
            p.build_grid(d, &points, &mut self.scratch);
            p.stamp.clear();
            p.stamp.resize(p.n, 0);
            p.stamp_id = 0;
        }
        self.points = points;
        self.map = map;
        self.suffix_max.clear();
        self.suffix_max.resize(self.used + 1, 0.0);
        for i in (0..self.used).rev() {
            self.suffix_max[i] = self.suffix_max[i + 1] + self.funcs[i].max;
        }
        let levels = self.used + 1;
        self.node_lo.resize(levels * d, 0);
        self.node_hi.resize(levels * d, 0);
        self.node_w.resize(levels * (d + 1), 0.0);
        while self.cand.len() < levels {
            self.cand.push(Vec::new());
        }
        self.cells_lo.resize(d, 0);
        self.cells_hi.resize(d, 0);
        self.odo.resize(d, 0);
        self.best_pt.resize(d, 0);
        self.found = false;
        self.best_val = f64::NEG_INFINITY;
    }

    fn search(&mut self) {
        let d = self.dim;
        let n0 = self.funcs[0].n;
        for i in 0..n0 {
            {
                let f = &self.funcs[0];
                self.node_lo[..d].copy_from_slice(&f.lo[i * d..(i + 1) * d]);
                self.node_hi[..d].copy_from_slice(&f.hi[i * d..(i + 1) * d]);
                self.node_w[..d + 1].copy_from_slice(&f.wts[i * (d + 1)..(i + 1) * (d + 1)]);
            }
            if self.worth_descending(0) {
                self.descend(1);
            }
        }
    }

    /// Starts the search with a threshold just below the best collective value found at the
    /// maximum points of the individual functions. Branches and leaves at or below the
    /// threshold cannot hold the optimum, and every branch that can is still explored in the
    /// same order, so the first optimum found is the same as without the threshold.
    fn seed(&mut self) {
        let d = self.dim;
        let mut pt = std::mem::take(&mut self.best_pt);
        let mut seed = f64::NEG_INFINITY;
        for i in 0..self.used {
            let f = &self.funcs[i];
            let Some(p) = f.argmax() else { continue };
            for k in 0..d {
                let w = f.wts[p * (d + 1) + k];
                pt[k] = if w < 0.0 {
                    f.lo[p * d + k]
                } else {
                    f.hi[p * d + k]
                };
            }
            let mut total = 0.0;
            let mut covered = true;
            for g in &self.funcs[..self.used] {
                match g.eval(&pt, d) {
                    Some(v) => total += v,
                    None => {
                        covered = false;
                        break;
                    }
                }
            }
            if covered && total > seed {
                seed = total;
            }
        }
        self.best_pt = pt;
        if seed.is_finite() {
            self.best_val = seed - 1e-9 * seed.abs().max(1.0);
        }
    }

    /// Whether the node at `level` (which already includes function `level`) can still beat
    /// the best value (or the seed threshold).
    fn worth_descending(&mut self, level: usize) -> bool {
        self.nodes += 1;
        if self.best_val == f64::NEG_INFINITY {
            return true;
        }
        let d = self.dim;
        let exact = box_max(
            &self.node_lo[level * d..(level + 1) * d],
            &self.node_hi[level * d..(level + 1) * d],
            &self.node_w[level * (d + 1)..(level + 1) * (d + 1)],
        );
        // cheap test with each remaining function's global maximum first
        if exact + self.suffix_max[level + 1] <= self.best_val {
            return false;
        }
        let mut bound = exact;
        for k in level + 1..self.used {
            bound += self.grid_bound(k, level);
            if bound + self.suffix_max[k + 1] <= self.best_val {
                return false;
            }
        }
        bound > self.best_val
    }

    fn descend(&mut self, level: usize) {
        let d = self.dim;
        if level == self.used {
            let prev = level - 1;
            let lo = &self.node_lo[prev * d..level * d];
            let hi = &self.node_hi[prev * d..level * d];
            let w = &self.node_w[prev * (d + 1)..level * (d + 1)];
            let val = box_max(lo, hi, w);
            if val > self.best_val {
                self.found = true;
                self.best_val = val;
                for k in 0..d {
                    self.best_pt[k] = if w[k] < 0.0 { lo[k] } else { hi[k] };
                }
            }
            return;
        }
        self.collect_candidates(level);
        let count = self.cand[level].len();
        for ci in 0..count {
            let piece = self.cand[level][ci] as usize;
            if !self.intersect_into(level, piece) {
                continue;
            }
            if self.worth_descending(level) {
                self.descend(level + 1);
            }
        }
    }

    /// Node at `level` = node at `level-1` ∩ piece `piece` of function `level`, weights
    /// summed. False when the intersection is empty.
    fn intersect_into(&mut self, level: usize, piece: usize) -> bool {
        let d = self.dim;
        let f = &self.funcs[level];
        let (plo, phi) = (
            &f.lo[piece * d..(piece + 1) * d],
            &f.hi[piece * d..(piece + 1) * d],
        );
        let (prev, cur) = ((level - 1) * d, level * d);
        for k in 0..d {
            let lo = self.node_lo[prev + k].max(plo[k]);
            let hi = self.node_hi[prev + k].min(phi[k]);
            if lo > hi {
                return false;
            }
            self.node_lo[cur + k] = lo;
            self.node_hi[cur + k] = hi;
        }
        let (pw, cw) = ((level - 1) * (d + 1), level * (d + 1));
        let fw = &f.wts[piece * (d + 1)..(piece + 1) * (d + 1)];
        for k in 0..=d {
            self.node_w[cw + k] = self.node_w[pw + k] + fw[k];
        }
        true
    }

    /// Pieces of function `level` in grid cells overlapping the node at `level-1`, in piece
    /// order, without duplicates.
    fn collect_candidates(&mut self, level: usize) {
        let d = self.dim;
        let prev = (level - 1) * d;
        let mut cand = std::mem::take(&mut self.cand[level]);
        cand.clear();
        let f = &mut self.funcs[level];
        f.stamp_id = f.stamp_id.wrapping_add(1);
        if f.stamp_id == 0 {
            f.stamp.iter_mut().for_each(|s| *s = 0);
            f.stamp_id = 1;
        }
        let id = f.stamp_id;
        let g = &f.grid;
        for k in 0..d {
            self.cells_lo[k] = self.node_lo[prev + k] / g.width[k];
            self.cells_hi[k] = self.node_hi[prev + k] / g.width[k];
        }
        for_each_cell(
            &self.cells_lo,
            &self.cells_hi,
            &g.stride,
            &mut self.odo,
            |cell| {
                let (s, e) = (g.start[cell] as usize, g.start[cell + 1] as usize);
                for &m in &g.members[s..e] {
                    let st = &mut f.stamp[m as usize];
                    if *st != id {
                        *st = id;
                        cand.push(m);
                    }
                }
            },
        );
        cand.sort_unstable();
        self.cand[level] = cand;
    }

    /// Upper bound of function `k` over the node at `level`.
    fn grid_bound(&mut self, k: usize, level: usize) -> f64 {
        let d = self.dim;
        let g = &self.funcs[k].grid;
        for j in 0..d {
            self.cells_lo[j] = self.node_lo[level * d + j] / g.width[j];
            self.cells_hi[j] = self.node_hi[level * d + j] / g.width[j];
        }
        let mut best = f64::NEG_INFINITY;
        for_each_cell(
            &self.cells_lo,
            &self.cells_hi,
            &g.stride,
            &mut self.odo,
            |cell| {
                best = best.max(g.cell_max[cell]);
            },
        );
        best
    }
}

/// Calls `visit` with the flat index of every cell in the inclusive range `lo..=hi`.
fn for_each_cell(
    lo: &[u32],
    hi: &[u32],
    stride: &[usize],
    odo: &mut [u32],
    mut visit: impl FnMut(usize),
) {
    let d = lo.len();
    odo.copy_from_slice(lo);
    loop {
        let flat: usize = odo.iter().zip(stride).map(|(&c, &s)| c as usize * s).sum();
        visit(flat);
        let mut k = d;
        loop {
            if k == 0 {
                return;
            }
            k -= 1;
            if odo[k] < hi[k] {
                odo[k] += 1;
                break;
            }
            odo[k] = lo[k];
        }
    }
}

/// Maximum of a linear function over an integer box.
#[inline]
fn box_max(lo: &[u32], hi: &[u32], w: &[f64]) -> f64 {
    let d = lo.len();
    let mut v = w[d];
    for k in 0..d {
        let s = w[k];
        v += if s < 0.0 {
            s * f64::from(lo[k])
        } else {
            s * f64::from(hi[k])
        };
    }
    v
}

/// Cell budget per function: enough to separate pieces, small enough to build quickly.
const MAX_CELLS: usize = 1024;

impl Prepared {
    /// Index of the first piece with the largest maximum.
    fn argmax(&self) -> Option<usize> {
        let d = self.grid.width.len();
        let mut best: Option<(f64, usize)> = None;
        for i in 0..self.n {
            let v = box_max(
                &self.lo[i * d..(i + 1) * d],
                &self.hi[i * d..(i + 1) * d],
                &self.wts[i * (d + 1)..(i + 1) * (d + 1)],
            );
            if best.is_none_or(|(b, _)| v > b) {
                best = Some((v, i));
            }
        }
        best.map(|(_, i)| i)
    }

    /// Value at grid point `pt` from the first piece holding it, found through the grid.
    fn eval(&self, pt: &[u32], d: usize) -> Option<f64> {
        let g = &self.grid;
        let cell: usize = (0..d)
            .map(|k| (pt[k] / g.width[k]) as usize * g.stride[k])
            .sum();
        let (s, e) = (g.start[cell] as usize, g.start[cell + 1] as usize);
        g.members[s..e].iter().find_map(|&m| {
            let m = m as usize;
            let inside = (0..d).all(|k| self.lo[m * d + k] <= pt[k] && pt[k] <= self.hi[m * d + k]);
            inside.then(|| {
                let w = &self.wts[m * (d + 1)..(m + 1) * (d + 1)];
                (0..d).fold(w[d], |acc, k| acc + w[k] * f64::from(pt[k]))
            })
        })
    }

    fn build_grid(&mut self, d: usize, points: &[u32], scratch: &mut GridScratch) {
        let n = self.n;
        let g = &mut self.grid;
        // dimensions where the function varies get cells; the others one cell
        let active = &mut scratch.active;
        active.clear();
        active.extend((0..d).map(|k| {
            (0..n).any(|i| {
                self.lo[i * d + k] != 0
                    || self.hi[i * d + k] != points[k] - 1
                    || self.wts[i * (d + 1) + k] != 0.0
            })
        }));
        let n_active = active.iter().filter(|a| **a).count().max(1) as f64;
        let budget = (2 * n).clamp(1, MAX_CELLS) as f64;
        let per_dim = budget.powf(1.0 / n_active).floor().max(1.0) as u32;
        g.width.clear();
        g.cells.clear();
        for k in 0..d {
            let want = if active[k] { per_dim.min(points[k]) } else { 1 };
            let w = points[k].div_ceil(want.max(1));
            g.width.push(w.max(1));
            g.cells.push(points[k].div_ceil(w.max(1)));
        }
        g.stride.clear();
        g.stride.resize(d, 0);
        let mut s = 1usize;
        for k in (0..d).rev() {
            g.stride[k] = s;
            s *= g.cells[k] as usize;
        }
        let total = s;
        g.cell_max.clear();
        g.cell_max.resize(total, f64::NEG_INFINITY);
        g.start.clear();
        g.start.resize(total + 1, 0);
        let GridScratch {
            clo,
            chi,
            odo,
            fill,
            ..
        } = scratch;
        clo.resize(d, 0);
        chi.resize(d, 0);
        odo.resize(d, 0);
        // pass 1: counts and bounds
        for i in 0..n {
            let (lo, hi) = (&self.lo[i * d..(i + 1) * d], &self.hi[i * d..(i + 1) * d]);
            let w = &self.wts[i * (d + 1)..(i + 1) * (d + 1)];
            for k in 0..d {
                clo[k] = lo[k] / g.width[k];
                chi[k] = hi[k] / g.width[k];
            }
            let (width, stride) = (&g.width, &g.stride);
            let (cell_max, start) = (&mut g.cell_max, &mut g.start);
            for_each_cell(clo, chi, stride, odo, |cell| {
                start[cell + 1] += 1;
                // max of the piece over (piece ∩ cell)
                let mut rem = cell;
                let mut v = w[d];
                for k in 0..d {
                    let c = (rem / stride[k]) as u32;
                    rem %= stride[k];
                    let c_lo = (c * width[k]).max(lo[k]);
                    let c_hi = (c * width[k] + width[k] - 1).min(hi[k]);
                    v += if w[k] < 0.0 {
                        w[k] * f64::from(c_lo)
                    } else {
                        w[k] * f64::from(c_hi)
                    };
                }
                if v > cell_max[cell] {
                    cell_max[cell] = v;
                }
            });
        }
        for c in 0..total {
            g.start[c + 1] += g.start[c];
        }
        g.members.clear();
        g.members.resize(g.start[total] as usize, 0);
        fill.clear();
        fill.extend_from_slice(&g.start[..total]);
        // pass 2: members, in piece order within each cell
        for i in 0..n {
            for k in 0..d {
                clo[k] = self.lo[i * d + k] / g.width[k];
                chi[k] = self.hi[i * d + k] / g.width[k];
            }
            let members = &mut g.members;
            for_each_cell(clo, chi, &g.stride, odo, |cell| {
                members[fill[cell] as usize] = i as u32;
                fill[cell] += 1;
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ZaicPeak, ZaicSpd};

    fn cs() -> Domain {
        Domain::from_vars(&[("course", 0.0, 359.0, 360), ("speed", 0.0, 4.0, 41)]).unwrap()
    }

    #[test]
    fn no_functions_no_decision() {
        assert_eq!(Problem::new(cs()).solve(), None);
        // a zero-weight function is dropped
        let mut p = Problem::new(cs());
        let mut z = ZaicPeak::new(&cs(), "course").unwrap();
        z.set_params(10.0, 0.0, 10.0, 0.0, 0.0, 100.0).unwrap();
        p.add("a", z.extract().unwrap().with_pwt(0.0)).unwrap();
        assert_eq!(p.solve(), None);
    }

    #[test]
    fn unknown_variable_is_rejected() {
        let d = Domain::from_vars(&[("depth", 0.0, 10.0, 11)]).unwrap();
        let f = ZaicPeak::new(&d, "depth").unwrap().extract().unwrap();
        let mut p = Problem::new(cs());
        assert!(p.add("a", f).is_err());
    }

    #[test]
    fn weighted_sum_is_maximized() {
        let d = cs();
        let mut hdg = ZaicPeak::new(&d, "course").unwrap();
        hdg.set_params(350.0, 0.0, 30.0, 0.0, 0.0, 100.0).unwrap();
        hdg.set_value_wrap(true);
        let mut hdg2 = ZaicPeak::new(&d, "course").unwrap();
        hdg2.set_params(10.0, 0.0, 30.0, 0.0, 0.0, 100.0).unwrap();
        hdg2.set_value_wrap(true);
        let spd = ZaicSpd::new(&d, "speed", 1.5, 1.0, 2.0, 50.0, 50.0).unwrap();
        let mut p = Problem::new(d);
        p.add("b_heading", hdg.extract().unwrap().with_pwt(200.0))
            .unwrap();
        p.add("a_heading", hdg2.extract().unwrap().with_pwt(100.0))
            .unwrap();
        p.add("c_speed", spd.extract().unwrap().with_pwt(100.0))
            .unwrap();
        let dec = p.solve().unwrap();
        // 350 weighted twice as much as 10: for c in [350..10] both ramps sum to
        // 200*(1-|c-350|/31) + 100*(1-|c-10|/31) (wrap distance includes one extra step),
        // maximal at 350.
        assert_eq!(dec.get("course"), Some(350.0));
        assert!((dec.get("speed").unwrap() - 1.5).abs() < 1e-9);
        // sub-domain order: first-seen over owners sorted by name
        assert_eq!(dec.vars[0].name, "course");
        assert_eq!(dec.vars[1].name, "speed");
        let want = 200.0 * 100.0 + 100.0 * hdg2.eval_point(350) + 100.0 * 100.0;
        assert!((dec.value - want).abs() < 1e-6, "{} vs {want}", dec.value);
    }

    #[test]
    fn first_optimum_wins_ties_in_owner_order() {
        let d = Domain::from_vars(&[("x", 0.0, 10.0, 11)]).unwrap();
        let mut p = Problem::new(d.clone());
        // flat function: every point ties; the box's max point is its HIGH end
        let mut f = IvpFunction::new(d.clone());
        f.push_piece(&[0], &[4], &[0.0], 50.0).unwrap();
        f.push_piece(&[5], &[10], &[0.0], 50.0).unwrap();
        p.add("only", f).unwrap();
        let dec = p.solve().unwrap();
        assert_eq!(dec.get("x"), Some(4.0));
    }
}
