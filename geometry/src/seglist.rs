//! [`SegList`]: an ordered list of vertices (a waypoint path), MOOS `XYSegList`.

use crate::point::{Point, snap_to_step};
use crate::segment::Segment;

/// An ordered vertex list. Each vertex may carry a free-text property (written as the fourth
/// field of a `pts={x,y,z,prop}` vertex); most lists have none.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SegList {
    pts: Vec<Point>,
    props: Vec<String>,
}

impl SegList {
    /// An empty list.
    pub fn new() -> Self {
        SegList::default()
    }

    /// A list of the given points, in order.
    pub fn from_points(pts: Vec<Point>) -> Self {
        let props = vec![String::new(); pts.len()];
        SegList { pts, props }
    }

    /// Appends a vertex.
    pub fn push(&mut self, p: Point) {
        self.pts.push(p);
        self.props.push(String::new());
    }

    /// Appends a 2-D vertex.
    pub fn push_xy(&mut self, x: f64, y: f64) {
        self.push(Point::new(x, y));
    }

    /// Appends a vertex with a property string (empty = none).
    pub fn push_with_prop(&mut self, p: Point, prop: impl Into<String>) {
        self.pts.push(p);
        self.props.push(prop.into());
    }

    /// The vertices in order.
    pub fn points(&self) -> &[Point] {
        &self.pts
    }

    /// The vertex at `i`, if any.
    pub fn get(&self, i: usize) -> Option<Point> {
        self.pts.get(i).copied()
    }

    /// The property of vertex `i` (empty if none or out of range).
    pub fn prop(&self, i: usize) -> &str {
        self.props.get(i).map_or("", String::as_str)
    }

    /// Number of vertices.
    pub fn len(&self) -> usize {
        self.pts.len()
    }

    /// True if there are no vertices.
    pub fn is_empty(&self) -> bool {
        self.pts.is_empty()
    }

    /// Removes every vertex.
    pub fn clear(&mut self) {
        self.pts.clear();
        self.props.clear();
    }

    /// The segments between consecutive vertices (not closed).
    pub fn segments(&self) -> impl Iterator<Item = Segment> + '_ {
        self.pts.windows(2).map(|w| Segment::new(w[0], w[1]))
    }

    /// Total path length through the vertices in order.
    pub fn length(&self) -> f64 {
        self.segments().map(|s| s.length()).sum()
    }

    /// Index of the vertex nearest `(x, y)` (first one on ties), `None` if empty.
    pub fn closest_vertex(&self, x: f64, y: f64) -> Option<usize> {
        closest_vertex(&self.pts, x, y)
    }

    /// Index `i` of the segment `i → i+1` nearest to `(x, y)` (first one on ties); `None` with
    /// fewer than two vertices. Unlike MOOS's `closest_segment`, the implied closing segment is
    /// not considered (a seglist is an open path).
    pub fn closest_segment(&self, x: f64, y: f64) -> Option<usize> {
        let mut best: Option<(usize, f64)> = None;
        for (i, s) in self.segments().enumerate() {
            let d = s.dist_to_point(x, y);
            if best.is_none_or(|(_, bd)| d < bd) {
                best = Some((i, d));
            }
        }
        best.map(|(i, _)| i)
    }

    /// Reverses the vertex order (MOOS `reverse`, used by waypoint `order = reverse`).
    pub fn reverse(&mut self) {
        self.pts.reverse();
        self.props.reverse();
    }

    /// Moves every vertex by `(dx, dy)`.
    pub fn shift(&mut self, dx: f64, dy: f64) {
        for p in &mut self.pts {
            p.x += dx;
            p.y += dy;
        }
    }

    /// Moves the list so the middle of its bounding box is at `(x, y)` (MOOS `new_center`).
    pub fn new_center(&mut self, x: f64, y: f64) {
        let c = self.center();
        self.shift(x - c.x, y - c.y);
    }

    /// Snaps every vertex's `x` and `y` to multiples of `step` (MOOS `apply_snap`).
    pub fn apply_snap(&mut self, step: f64) {
        for p in &mut self.pts {
            p.x = snap_to_step(p.x, step);
            p.y = snap_to_step(p.y, step);
        }
    }

    /// Middle of the bounding box (MOOS `get_center_x/y`); origin if empty.
    pub fn center(&self) -> Point {
        bbox_center(&self.pts)
    }
}

impl FromIterator<Point> for SegList {
    fn from_iter<I: IntoIterator<Item = Point>>(iter: I) -> Self {
        SegList::from_points(iter.into_iter().collect())
    }
}

impl std::str::FromStr for SegList {
    type Err = crate::ParseError;

    /// Parses any seglist form (see [`crate::spec::parse_seglist`]), keeping only the vertices.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        crate::spec::parse_seglist(s).map(|v| v.seglist)
    }
}

pub(crate) fn closest_vertex(pts: &[Point], x: f64, y: f64) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for (i, p) in pts.iter().enumerate() {
        let d = (p.x - x).hypot(p.y - y);
        if best.is_none_or(|(_, bd)| d < bd) {
            best = Some((i, d));
        }
    }
    best.map(|(i, _)| i)
}

pub(crate) fn bbox_center(pts: &[Point]) -> Point {
    let Some(first) = pts.first() else {
        return Point::default();
    };
    let (mut lx, mut hx, mut ly, mut hy) = (first.x, first.x, first.y, first.y);
    for p in pts {
        lx = lx.min(p.x);
        hx = hx.max(p.x);
        ly = ly.min(p.y);
        hy = hy.max(p.y);
    }
    Point::new((lx + hx) / 2.0, (ly + hy) / 2.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basics() {
        let mut s: SegList = [
            Point::new(0.0, 0.0),
            Point::new(3.0, 4.0),
            Point::new(3.0, 10.0),
        ]
        .into_iter()
        .collect();
        assert_eq!(s.len(), 3);
        assert_eq!(s.length(), 11.0);
        assert_eq!(s.closest_vertex(3.0, 6.0), Some(1));
        assert_eq!(s.closest_segment(4.0, 7.0), Some(1));
        assert_eq!(s.closest_segment(0.0, 1.0), Some(0));
        assert_eq!(s.center(), Point::new(1.5, 5.0));
        let mut moved = s.clone();
        moved.new_center(0.0, 0.0);
        assert_eq!(moved.get(2), Some(Point::new(1.5, 5.0)));
        s.reverse();
        assert_eq!(s.get(0), Some(Point::new(3.0, 10.0)));
        s.push_with_prop(Point::new(0.4, 0.6), "x");
        s.apply_snap(1.0);
        assert_eq!(s.get(3), Some(Point::new(0.0, 1.0)));
        assert_eq!(s.prop(3), "x");
        assert_eq!(s.prop(0), "");
        assert_eq!(SegList::new().closest_vertex(0.0, 0.0), None);
    }
}
