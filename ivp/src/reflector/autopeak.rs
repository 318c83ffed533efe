//! The auto-peak stage (MOOS-IvP `RT_AutoPeak` at a2a9b716, which `OF_Reflector` runs last
//! when `auto_peak = true`).
//!
//! Every piece is queued by the largest value its plane takes over its box (MOOS
//! `IvPBox::maxVal`) in a priority queue of 8 levels (`PQueue`, with the quirks described in
//! `smart.rs`). Then, until the piece at the top of the queue is a single grid point, that
//! piece is cut in two along its longest edge (the first such dimension) and both parts are
//! fitted again and queued. A linear piece is cut unevenly toward where its plane rises
//! (MOOS `quarterBox`): when its slope along the edge is at least 1 the piece keeps its low
//! `⌊0.75 n⌋ + 1` points of the `n` and the new piece takes the rest; otherwise (a slope below
//! 1, zero and small rises included, as the C++ tests it) the piece keeps its low
//! `max(⌊0.25 n⌋, 1) + 1` points; an edge of two points is cut into two single points. A
//! scalar piece is halved (MOOS `cutBox`, the lower part taking `(n + 1) / 2` points). New
//! pieces follow the old ones, in the order they were made. The count of new pieces is not
//! bounded (the C++ stage runs with no limit: `auto_peak_max_pcs` is read but unused).
//!
//! Where coug departs from the C++, whose behaviour there is undefined:
//! - `quarterBox` at a2a9b716 keeps `⌊0.75 n⌋ + 1` points, which for an edge of 3 or 4 points
//!   is the whole edge and leaves the new piece empty (its low end above its high end); the
//!   C++ then fits that empty piece and cuts the same piece again without end. coug cuts
//!   such an edge as the comment table in `quarterBox` describes: the last point apart.
//! - When the top of the queue is the empty slot the C++ queue keeps (all queued values
//!   below 0), the C++ reads the piece at index -1; coug ends the stage there.

use super::regressor::{Degree, Regressor};
use super::smart::PQueue;
use super::{IxBox, Reflector};
use crate::error::IvpError;
use crate::function::IvpFunction;

/// The auto-peak queue's levels (the C++ `PQueue(8, true)`).
const LEVELS: u32 = 8;

/// A piece of the stage: its box, plateau value and plane (slopes, then intercept).
struct Piece {
    b: IxBox,
    plat: i32,
    wts: Vec<f64>,
}

impl Piece {
    /// MOOS `IvPBox::maxVal` for a linear (or scalar) piece.
    fn max_val(&self) -> f64 {
        let d = self.b.lo.len();
        let mut v = self.wts[d];
        for k in 0..d {
            let w = self.wts[k];
            v += w * f64::from(if w < 0.0 { self.b.lo[k] } else { self.b.hi[k] });
        }
        v
    }
}

/// The dimension of the longest edge, the first of equals (the C++ compares point counts).
fn longest_dim(b: &IxBox) -> usize {
    let mut best = 0;
    for k in 1..b.lo.len() {
        if b.hi[k] - b.lo[k] > b.hi[best] - b.lo[best] {
            best = k;
        }
    }
    best
}

/// MOOS `quarterBox`: `b` keeps its low part along `dim`, the high part is returned (`None`
/// for an edge of one point). See the module docs for the sizes and coug's rule where the
/// C++ would leave the new piece empty.
pub(super) fn quarter_box(b: &mut IxBox, dim: usize, split_high: bool) -> Option<IxBox> {
    let len = b.hi[dim] - b.lo[dim] + 1;
    if len <= 1 {
        return None;
    }
    let mut upper = b.clone();
    let keep_hi = if len == 2 {
        b.lo[dim]
    } else {
        let share = if split_high { 0.75 } else { 0.25 };
        let delta = ((f64::from(len) * share) as u32).max(1);
        // The C++ keeps lo + delta; where that is the whole edge, the last point apart.
        (b.lo[dim] + delta).min(b.hi[dim] - 1)
    };
    b.hi[dim] = keep_hi;
    upper.lo[dim] = keep_hi + 1;
    Some(upper)
}

/// MOOS `cutBox`: `b` keeps the lower `(n + 1) / 2` points along `dim`.
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

impl<F: Fn(&[f64]) -> f64> Reflector<F> {
    /// The auto-peak stage over the built function `f`, whose pieces have the plateau values
    /// `plats` (empty: all 0).
    pub(super) fn build_auto_peak(
        &self,
        f: &IvpFunction,
        plats: &[i32],
    ) -> Result<IvpFunction, IvpError> {
        let d = self.domain.len();
        let mut pieces: Vec<Piece> = f
            .pieces()
            .enumerate()
            .map(|(i, p)| Piece {
                b: IxBox {
                    lo: p.lo.to_vec(),
                    hi: p.hi.to_vec(),
                },
                plat: plats.get(i).copied().unwrap_or(0),
                wts: p.wts.to_vec(),
            })
            .collect();
        let mut queue = PQueue::new(LEVELS);
        for (i, p) in pieces.iter().enumerate() {
            queue.insert(i, p.max_val());
        }
        let mut reg: Regressor = self.regressor();
        while let Some(i) = queue.remove_best() {
            if pieces[i].b.lo == pieces[i].b.hi {
                break;
            }
            let dim = longest_dim(&pieces[i].b);
            let cut = match reg.degree() {
                Degree::Linear => {
                    let split_high = pieces[i].wts[dim] >= 1.0;
                    quarter_box(&mut pieces[i].b, dim, split_high)
                }
                Degree::Scalar => cut_box(&mut pieces[i].b, dim),
            };
            let Some(upper) = cut else { continue };
            let plat = pieces[i].plat;
            let lower = &mut pieces[i];
            reg.fit(&lower.b.lo, &lower.b.hi, plat, &self.domain, &self.func)?;
            lower.wts.copy_from_slice(reg.wts());
            let lower_max = lower.max_val();
            reg.fit(&upper.lo, &upper.hi, plat, &self.domain, &self.func)?;
            let new = Piece {
                b: upper,
                plat,
                wts: reg.wts().to_vec(),
            };
            queue.insert(i, lower_max);
            queue.insert(pieces.len(), new.max_val());
            pieces.push(new);
        }
        let mut out = IvpFunction::new(self.domain.clone());
        out.reserve(pieces.len());
        for p in &pieces {
            out.push_piece(&p.b.lo, &p.b.hi, &p.wts[..d], p.wts[d])?;
        }
        Ok(out)
    }
}
