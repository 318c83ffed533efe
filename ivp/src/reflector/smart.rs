//! Smart refinement: the reflector's stages 3 and 4 at a2a9b716 (MOOS-IvP `RT_Evaluator`,
//! `PQueue`, `RT_Smart`, and `Regressor::setWeight1`'s fit error).
//!
//! When `smart_amount` or `smart_percent` is set, every piece of the uniform (and directed)
//! partition is fitted and its fit error queued in a bounded priority queue of
//! `queue_levels` levels (8 by default). Then, while pieces are left to add and the worst
//! queued error is above `smart_thresh`, the worst piece is cut in two along its longest
//! edge (the first such dimension; the lower half keeps the piece's place and takes
//! `(len + 1) / 2` points, the upper half is appended), both halves are fitted again and
//! queued unless they are single points. The amount of pieces added is the larger of
//! `smart_amount` and `smart_percent` of the pieces before this stage.
//!
//! Pieces are fitted, and their fit error measured, by the reflector's regressor (MOOS
//! `Regressor::setWeight` with feedback, `reflector/regressor.rs`), as on every other path.
//!
//! The queue is the C++ `PQueue`, its quirks included: its capacity is `2^(levels - 1)`
//! entries; inserting into an empty (or one-entry) heap stores the entry twice and leaves
//! an empty slot of value 0, so the first piece queued can be cut twice; a full heap
//! replaces a random leaf when the new error is not below it. The C++ draws that leaf
//! with `rand()`, which pHelmIvP seeds from the clock and the process id; coug draws it
//! from a generator with a fixed seed, so a build gives the same pieces every time.
//! Smart refinement with plateau or basin regions is refused (no caller uses it).

use super::{IxBox, Reflector};
use crate::error::IvpError;
use crate::function::IvpFunction;

/// The smart-refinement settings (`OF_Reflector`'s `m_smart_amount`, `m_smart_percent`,
/// `m_smart_thresh`, `m_qlevels`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Smart {
    /// Pieces to add at least.
    pub amount: usize,
    /// Pieces to add at least, in percent of the pieces before this stage.
    pub percent: usize,
    /// Pieces whose fit error is at or below this are not cut.
    pub thresh: f64,
    /// The priority queue's levels (capacity `2^(levels - 1)`).
    pub levels: u32,
}

impl Default for Smart {
    fn default() -> Self {
        Self {
            amount: 0,
            percent: 0,
            thresh: 0.0,
            levels: 8,
        }
    }
}

impl Smart {
    /// Whether the stage runs.
    pub fn active(&self) -> bool {
        self.amount > 0 || self.percent > 0
    }

    /// The pieces to add given the count before the stage.
    pub fn pieces_to_add(&self, before: usize) -> usize {
        self.amount.max(before * self.percent / 100)
    }
}

/// The most levels the C++ queue takes.
const MAX_LEVELS: u32 = 10;

/// MOOS `PQueue`: a max-heap of (piece index, fit error) in a full binary tree of fixed
/// capacity. `None` keys are the empty slots the C++ marks with -1.
#[derive(Debug, Clone)]
pub(crate) struct PQueue {
    key: Vec<Option<usize>>,
    val: Vec<f64>,
    /// Index of the last active entry (-1: empty).
    end: isize,
    leaves: usize,
    inodes: usize,
    rng: u64,
}

impl PQueue {
    /// A queue of `levels` levels (at least 2, at most 10).
    pub fn new(levels: u32) -> Self {
        let levels = levels.clamp(2, MAX_LEVELS);
        let size = 1usize << (levels - 1);
        let leaves = size.div_ceil(2);
        Self {
            key: vec![None; size],
            val: vec![0.0; size],
            end: 0,
            leaves,
            inodes: leaves - 1,
            rng: 0x9E37_79B9_7F4A_7C15,
        }
    }

    fn last(&self) -> isize {
        self.key.len() as isize - 1
    }

    /// A leaf index drawn from the queue's own generator (xorshift64*).
    fn random_leaf(&mut self) -> usize {
        self.rng ^= self.rng >> 12;
        self.rng ^= self.rng << 25;
        self.rng ^= self.rng >> 27;
        let r = self.rng.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 33;
        self.inodes + (r as usize) % self.leaves
    }

    /// Queues `key` with priority `v` (MOOS `insert`).
    pub fn insert(&mut self, key: usize, v: f64) {
        let mut at = 0usize;
        if self.end == 0 {
            self.key[0] = Some(key);
            self.val[0] = v;
            self.end += 1;
        }
        if self.end == self.last() {
            at = self.random_leaf();
            if v < self.val[at] {
                return;
            }
        }
        if self.end < self.last() {
            self.end += 1;
            at = self.end as usize;
        }
        while at > 0 {
            let up = (at - 1) / 2;
            if self.val[up] >= v {
                break;
            }
            self.key[at] = self.key[up];
            self.val[at] = self.val[up];
            at = up;
        }
        self.key[at] = Some(key);
        self.val[at] = v;
    }

    /// The top priority (0 when empty; MOOS `returnBestVal`).
    pub fn best_val(&self) -> f64 {
        if self.end < 0 { 0.0 } else { self.val[0] }
    }

    /// Takes the top entry's key: `None` when empty or when the top is an empty slot
    /// (MOOS `removeBest` returning -1).
    pub fn remove_best(&mut self) -> Option<usize> {
        if self.end < 0 {
            return None;
        }
        let end = self.end as usize;
        let top = self.key[0];
        self.key[0] = self.key[end];
        self.val[0] = self.val[end];
        self.key[end] = None;
        self.val[end] = 0.0;
        self.end -= 1;
        self.sift_down(0);
        top
    }

    fn sift_down(&mut self, mut at: usize) {
        loop {
            if at as isize > self.end {
                return;
            }
            let (l, r) = (2 * at + 1, 2 * at + 2);
            let mut big = at;
            if l as isize <= self.end && self.val[l] > self.val[big] {
                big = l;
            }
            if r as isize <= self.end && self.val[r] > self.val[big] {
                big = r;
            }
            if big == at {
                return;
            }
            self.key.swap(at, big);
            self.val.swap(at, big);
            at = big;
        }
    }
}

/// MOOS `cutBox`: splits `b` along `dim`; `b` keeps the lower `(len + 1) / 2` points and
/// the upper part is returned (`None` when the edge is one point).
fn cut_box(b: &mut IxBox, dim: usize) -> Option<IxBox> {
    let len = b.hi[dim] - b.lo[dim] + 1;
    if len <= 1 {
        return None;
    }
    let mut upper = b.clone();
    let cut = b.lo[dim] + len.div_ceil(2);
    b.hi[dim] = cut - 1;
    upper.lo[dim] = cut;
    Some(upper)
}

/// The dimension of the longest edge (the first of equals).
fn longest_dim(b: &IxBox) -> usize {
    let mut best = 0;
    for k in 1..b.lo.len() {
        if b.hi[k] - b.lo[k] > b.hi[best] - b.lo[best] {
            best = k;
        }
    }
    best
}

fn is_point(b: &IxBox) -> bool {
    b.lo == b.hi
}

/// A piece of the smart stage: its box and its plane (slopes, then intercept).
struct Fitted {
    b: IxBox,
    wts: Vec<f64>,
}

impl<F: Fn(&[f64]) -> f64> Reflector<F> {
    /// [`Reflector::build`] with smart refinement: the uniform grid, the refine regions,
    /// every piece fitted and queued by its error, then the worst pieces cut.
    pub(super) fn build_smart(&self, sizes: &[u32]) -> Result<IvpFunction, IvpError> {
        if !self.plateaus.is_empty() || !self.basins.is_empty() {
            return Err(IvpError::Reflector(
                "smart refinement with plateau or basin regions is not supported".to_string(),
            ));
        }
        let boxes = self.directed_boxes(sizes);
        let mut reg = self.regressor();
        let mut queue = PQueue::new(self.smart.levels);
        let mut pieces: Vec<Fitted> = Vec::with_capacity(boxes.len());
        for (i, b) in boxes.into_iter().enumerate() {
            let err = reg.fit(&b.lo, &b.hi, 0, &self.domain, &self.func)?;
            queue.insert(i, err);
            let wts = reg.wts().to_vec();
            pieces.push(Fitted { b, wts });
        }
        let mut left = self.smart.pieces_to_add(pieces.len());
        let mut worst_err = queue.best_val();
        let mut worst = queue.remove_best();
        while let Some(i) = worst.filter(|_| left > 0 && worst_err > self.smart.thresh) {
            let dim = longest_dim(&pieces[i].b);
            if let Some(upper) = cut_box(&mut pieces[i].b, dim) {
                let lower = &mut pieces[i];
                let err1 = reg.fit(&lower.b.lo, &lower.b.hi, 0, &self.domain, &self.func)?;
                lower.wts.copy_from_slice(reg.wts());
                let err2 = reg.fit(&upper.lo, &upper.hi, 0, &self.domain, &self.func)?;
                let wts = reg.wts().to_vec();
                let new_ix = pieces.len();
                let lower_point = is_point(&pieces[i].b);
                let upper_point = is_point(&upper);
                pieces.push(Fitted { b: upper, wts });
                if !lower_point {
                    queue.insert(i, err1);
                }
                if !upper_point {
                    queue.insert(new_ix, err2);
                }
                left -= 1;
            }
            worst_err = queue.best_val();
            worst = queue.remove_best();
        }
        super::function_of(&self.domain, pieces.iter().map(|p| (&p.b, &p.wts[..])))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::domain::Domain;

    #[test]
    fn the_queue_keeps_the_cpp_quirks() {
        let mut q = PQueue::new(3); // capacity 4
        q.insert(7, 2.0);
        // The first entry is stored twice, with an empty slot of value 0 between.
        assert_eq!(q.key, [Some(7), None, Some(7), None]);
        q.insert(8, 5.0);
        assert_eq!(q.best_val(), 5.0);
        assert_eq!(q.remove_best(), Some(8));
        assert_eq!(q.remove_best(), Some(7));
        assert_eq!(q.remove_best(), Some(7));
        assert_eq!(q.best_val(), 0.0);
        assert_eq!(q.remove_best(), None, "the empty slot");
        assert_eq!(q.remove_best(), None, "empty");
    }

    #[test]
    fn a_full_queue_replaces_a_leaf_only_for_a_worse_fit() {
        let mut q = PQueue::new(3);
        for (k, v) in [(0, 9.0), (1, 8.0), (2, 7.0)] {
            q.insert(k, v);
        }
        assert_eq!(q.end, 3, "full");
        q.insert(3, -1.0); // below every leaf: dropped
        assert!(!q.key.contains(&Some(3)));
        q.insert(4, 100.0); // above every leaf: replaces one and rises to the top
        assert_eq!(q.best_val(), 100.0);
        assert_eq!(q.remove_best(), Some(4));
    }

    #[test]
    fn cut_box_halves_the_longest_edge_the_lower_half_rounded_up() {
        let mut b = IxBox {
            lo: vec![0, 10],
            hi: vec![4, 12],
        };
        assert_eq!(longest_dim(&b), 0);
        let up = cut_box(&mut b, 0).unwrap();
        assert_eq!((b.lo.clone(), b.hi.clone()), (vec![0, 10], vec![2, 12]));
        assert_eq!((up.lo, up.hi), (vec![3, 10], vec![4, 12]));
        let mut p = IxBox {
            lo: vec![3, 3],
            hi: vec![3, 3],
        };
        assert!(cut_box(&mut p, 1).is_none());
    }

    fn line(points: u32) -> Domain {
        Domain::from_vars(&[("x", 0.0, f64::from(points - 1), points)]).unwrap()
    }

    fn boxes(f: &IvpFunction) -> Vec<(u32, u32)> {
        f.pieces().map(|p| (p.lo[0], p.hi[0])).collect()
    }

    #[test]
    fn the_worst_fitted_piece_is_split_first() {
        let d = line(21);
        let r = || {
            Reflector::new(&d, |v: &[f64]| (v[0] - 10.0).max(0.0).powi(2))
                .set_param("uniform_piece", "x:7")
                .unwrap()
        };
        let plain = r().build().unwrap();
        assert_eq!(boxes(&plain), [(0, 6), (7, 13), (14, 20)]);
        // strict_range (the default) makes the two bent pieces chords: 7..13 samples 0, 0
        // (centre 10), 9, the plane 0, 4.5, 9: error 4.5 / 3 = 1.5; 14..20 samples 16, 49
        // (centre 17), 100, the plane 16, 58, 100: error 9 / 3 = 3. Errors 0, 1.5, 3: the
        // parabola's piece is cut, its lower half taking (7 + 1) / 2 points and keeping its
        // place, the upper half appended.
        let one = r().set_param("smart_amount", "1").unwrap().build().unwrap();
        assert_eq!(boxes(&one), [(0, 6), (7, 13), (14, 17), (18, 20)]);
        // A threshold above the worst error cuts nothing.
        let none = r()
            .set_params("smart_amount = 5 # smart_thresh = 3.5")
            .unwrap()
            .build()
            .unwrap();
        assert_eq!(boxes(&none), boxes(&plain));
        // Below it, the cut halves are chords too: 14..17 (16, 25 at 15, 49) errs by
        // 2 / 3, 18..20 (64, 81, 100) by 1 / 3; the worst left is 7..13's 1.5, within a
        // threshold of 2.5: one cut of the five allowed.
        let thresh = r()
            .set_params("smart_amount = 5 # smart_thresh = 2.5")
            .unwrap()
            .build()
            .unwrap();
        assert_eq!(boxes(&thresh), boxes(&one));
        // smart_percent: 34 % of 3 pieces is one piece (whole part), more than amount 0.
        let pct = r()
            .set_param("smart_percent", "34")
            .unwrap()
            .build()
            .unwrap();
        assert_eq!(boxes(&pct), boxes(&one));
        // More pieces fit better: the largest error over the grid falls.
        let worst = |f: &IvpFunction| {
            (0..21u32)
                .map(|x| {
                    let want = (f64::from(x) - 10.0).max(0.0).powi(2);
                    (f.eval(&[x]).unwrap() - want).abs()
                })
                .fold(0.0, f64::max)
        };
        let many = r().set_param("smart_amount", "4").unwrap().build().unwrap();
        assert_eq!(many.piece_count(), 7);
        assert!(worst(&many) < worst(&plain) / 2.0);
    }

    #[test]
    fn a_piecewise_linear_function_is_fitted_exactly() {
        let d = line(21);
        let f = Reflector::new(&d, |v: &[f64]| (v[0] - 10.0).abs())
            .set_params("uniform_piece = x:21 # smart_amount = 10")
            .unwrap()
            .build()
            .unwrap();
        // The one piece is cut at its middle: both halves are exact (error 0) and no more
        // cuts follow, except the queue's stale second entry for piece 0 (the C++ queue
        // stores its first entry twice), which cuts 0..10 once more.
        assert_eq!(boxes(&f), [(0, 5), (11, 20), (6, 10)]);
        for x in 0..21u32 {
            let want = (f64::from(x) - 10.0).abs();
            assert_eq!(f.eval(&[x]).unwrap(), want, "x = {x}");
        }
    }

    #[test]
    fn smart_settings_are_checked() {
        let d = line(21);
        let r = || Reflector::new(&d, |v: &[f64]| v[0]);
        assert!(r().set_param("smart_amount", "-1").is_err());
        assert!(r().set_param("smart_amount", "many").is_err());
        assert!(r().set_param("smart_percent", "-5").is_err());
        assert!(r().set_param("smart_thresh", "-0.1").is_err());
        assert!(r().set_param("queue_levels", "0").is_err());
        // atoi: the whole part.
        assert_eq!(
            r().set_param("smart_amount", "2.7").unwrap().smart.amount,
            2
        );
        assert_eq!(r().set_param("priority_amt", "3").unwrap().smart.amount, 3);
        let with_regions = r()
            .set_param("smart_amount", "2")
            .unwrap()
            .plateau_region(crate::RegionBox {
                lo: vec![0],
                hi: vec![3],
                plat: 1,
            })
            .unwrap()
            .build();
        assert!(with_regions.is_err());
    }

    #[test]
    fn uniform_amount_is_the_cpp_uniform_box() {
        // genUnifBox over 10 x 4 points for 6 pieces: x 2, 3, then y 2, then x 4 would
        // make 8 (x maxed at 3), y 3 would make 9 (maxed at 2): pieces of 4 x 2 points.
        let d = Domain::from_vars(&[("x", 0.0, 9.0, 10), ("y", 0.0, 3.0, 4)]).unwrap();
        let r = Reflector::new(&d, |v: &[f64]| v[0] + v[1]);
        assert_eq!(r.sizes_for_amount(6), [4, 2]);
        assert_eq!(r.sizes_for_amount(1), [10, 4]);
        assert_eq!(r.sizes_for_amount(1000), [1, 1]);
    }
}
