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
        super::function_of(&self.domain, pieces.iter().map(|p| (&p.b, &p.wts[..])))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::domain::Domain;

    fn cut(lo: u32, hi: u32, high: bool) -> ((u32, u32), (u32, u32)) {
        let mut b = IxBox {
            lo: vec![lo],
            hi: vec![hi],
        };
        let up = quarter_box(&mut b, 0, high).unwrap();
        ((b.lo[0], b.hi[0]), (up.lo[0], up.hi[0]))
    }

    #[test]
    fn quarter_box_keeps_the_cpp_sizes() {
        // Toward the high end: lo + ⌊0.75 n⌋ kept.
        assert_eq!(cut(5, 9, true), ((5, 8), (9, 9))); // n 5: delta 3
        assert_eq!(cut(5, 12, true), ((5, 11), (12, 12))); // n 8: delta 6
        assert_eq!(cut(0, 8, true), ((0, 6), (7, 8))); // n 9: delta 6
        // n 3 and 4, where the C++ would keep the whole edge: the last point apart.
        assert_eq!(cut(5, 7, true), ((5, 6), (7, 7)));
        assert_eq!(cut(5, 8, true), ((5, 7), (8, 8)));
        // Toward the low end: lo + max(⌊0.25 n⌋, 1) kept.
        assert_eq!(cut(5, 7, false), ((5, 6), (7, 7))); // n 3: delta 0, taken as 1
        assert_eq!(cut(5, 12, false), ((5, 7), (8, 12))); // n 8: delta 2
        // Two points: one each.
        assert_eq!(cut(5, 6, true), ((5, 5), (6, 6)));
        assert_eq!(cut(5, 6, false), ((5, 5), (6, 6)));
        let mut p = IxBox {
            lo: vec![4],
            hi: vec![4],
        };
        assert!(quarter_box(&mut p, 0, true).is_none());
    }

    fn pieces(f: &IvpFunction) -> Vec<((u32, u32), Vec<f64>)> {
        f.pieces()
            .map(|p| ((p.lo[0], p.hi[0]), p.wts.to_vec()))
            .collect()
    }

    #[test]
    fn auto_peak_cuts_toward_the_peak_until_it_is_a_point() {
        // 100 - (x - 6)² over 0..8, one uniform piece. Worked by hand:
        // - 0..8 samples 64, 96 (centre 4), 96: slope 4, the chord 64 + 4x (strict_range),
        //   its maximum 96 at 8: the uniform function's argmax is 8.
        // - Cut with slope 4 >= 1 toward the high end (n 9: delta 6): 0..6 and 7..8.
        //   0..6 samples 64, 91 (3), 100: slope 6, chord 64 + 6x, maximum 100 at 6.
        //   7..8 samples 99, 96: slope -3, intercept 120, maximum 99 at 7.
        // - 0..6 is on top (100): n 7, delta 5: 0..5 and 6..6. 0..5 samples 64, 84 (2),
        //   99: slope 7, chord 64 + 7x, maximum 99; 6..6 is the point 100.
        // - The point 6..6 is on top: done. The argmax is the true peak, 6.
        let d = Domain::from_vars(&[("x", 0.0, 8.0, 9)]).unwrap();
        let f = |v: &[f64]| 100.0 - (v[0] - 6.0).powi(2);
        let r = || {
            Reflector::new(&d, f)
                .set_param("uniform_piece", "x:9")
                .unwrap()
        };
        let plain = r().build().unwrap();
        assert_eq!(pieces(&plain), [((0, 8), vec![4.0, 64.0])]);
        assert_eq!(plain.max_pt(), Some(vec![8]));
        let peaked = r().set_param("auto_peak", "true").unwrap().build().unwrap();
        assert_eq!(
            pieces(&peaked),
            [
                ((0, 5), vec![7.0, 64.0]),
                ((7, 8), vec![-3.0, 120.0]),
                ((6, 6), vec![0.0, 100.0]),
            ]
        );
        assert_eq!(peaked.max_pt(), Some(vec![6]));
    }

    #[test]
    fn auto_peak_isolates_the_peak_of_a_2d_function() {
        // A smooth hill over course x speed, peak at (123, 2.7), on 3 x 3 pieces.
        let d = Domain::from_vars(&[("course", 0.0, 359.0, 360), ("speed", 0.0, 4.0, 41)]).unwrap();
        let hill =
            |v: &[f64]| 100.0 - ((v[0] - 123.0) / 20.0).powi(2) - (v[1] - 2.7).powi(2) * 10.0;
        let r = || {
            Reflector::new(&d, hill)
                .set_param("uniform_piece", "course:30,speed:10")
                .unwrap()
        };
        let peak = [123u32, 27];
        let dist = |p: &[u32]| {
            let dc = f64::from(p[0]) - f64::from(peak[0]);
            let ds = f64::from(p[1]) - f64::from(peak[1]);
            (dc * dc + ds * ds).sqrt()
        };
        let plain = r().build().unwrap();
        let peaked = r().set_param("auto_peak", "true").unwrap().build().unwrap();
        assert!(peaked.piece_count() > plain.piece_count());
        let top = peaked.max_pt().unwrap();
        // The piece holding the argmax is a single point.
        let holder: Vec<_> = peaked.pieces().filter(|p| p.contains(&top)).collect();
        assert_eq!(holder.len(), 1);
        assert_eq!(holder[0].lo, holder[0].hi);
        let before = dist(&plain.max_pt().unwrap());
        let after = dist(&top);
        assert!(
            after < before,
            "auto_peak argmax {top:?} ({after:.1}) vs uniform ({before:.1})"
        );
        // Every grid point is still covered once.
        for c in (0..360).step_by(7) {
            for s in 0..41 {
                assert_eq!(peaked.pieces().filter(|p| p.contains(&[c, s])).count(), 1);
            }
        }
    }

    #[test]
    fn scalar_pieces_are_halved() {
        // Degree 0 cuts with cutBox: 0..8 (the mean of 64, 96 at 4, 96 is 256/3) -> 0..4
        // and 5..8; 0..4 (64, 84 at 2, 96: 244/3) and 5..8 (99, 100 at 6, 96: 295/3) ->
        // 5..8 on top: 5..6 (99, 100: 99.5) and 7..8 (99, 96: 97.5) -> 5..6 on top: 5..5
        // (99) and 6..6 (100) -> 6..6 on top, a point.
        let d = Domain::from_vars(&[("x", 0.0, 8.0, 9)]).unwrap();
        let f = |v: &[f64]| 100.0 - (v[0] - 6.0).powi(2);
        let g = Reflector::new(&d, f)
            .degree(Degree::Scalar)
            .set_params("uniform_piece = x:9 # auto_peak = true")
            .unwrap()
            .build()
            .unwrap();
        let got: Vec<_> = pieces(&g).into_iter().map(|(b, w)| (b, w[1])).collect();
        assert_eq!(
            got,
            [
                ((0, 4), 244.0 / 3.0),
                ((5, 5), 99.0),
                ((7, 8), 97.5),
                ((6, 6), 100.0),
            ]
        );
    }
}
