//! Pattern generators: the vertex lists MOOS-IvP builds from `format=...` strings.
//!
//! Each generator reproduces MOOS-IvP's own construction (vertex order, start vertex,
//! direction, snapping), as found in `ivp/src/lib_geometry/XYFormatUtilsSegl.cpp`,
//! `XYFormatUtilsPoly.cpp`, `XYPatternBlock.cpp` and `XYOval.cpp` and summarised in
//! `shared/reference/moos-apps-extra.md` §2. Where the reference was incomplete or the real code
//! has a quirk, the item's doc comment says so.
//!
//! Seglist patterns: [`Lawnmower`], [`Bowtie`], [`ZigZag`]. Polygon patterns: [`Radial`],
//! [`Ellipse`], [`Wedge`], [`RangeWedge`], [`Pylon`], [`Oval`].
//!
//! Deliberate differences, all on inputs MOOS would mishandle: non-positive sizes are rejected
//! with [`ParseError::InvalidValue`] (MOOS's `XYPatternBlock` silently substitutes its defaults
//! 40 / 80 / 10), and any pattern that would have more than [`MAX_VERTICES`] vertices is
//! rejected instead of exhausting memory.

use crate::angle::{angle_360, project_point, relative_angle};
use crate::error::ParseError;
use crate::point::Point;
use crate::polygon::Polygon;
use crate::seglist::SegList;
use crate::spec::Attributes;
use crate::text::{lower, need_number, split_kv, split_top};

/// Upper bound on generated vertices (protects against e.g. `pts=1000000000`).
pub const MAX_VERTICES: u64 = 100_000;

fn check_count(n: f64) -> Result<(), ParseError> {
    if !n.is_finite() || n > MAX_VERTICES as f64 {
        let shown = if n.is_finite() { n as u64 } else { u64::MAX };
        return Err(ParseError::TooManyVertices(shown));
    }
    Ok(())
}

fn positive(key: &str, v: f64) -> Result<f64, ParseError> {
    if v > 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(ParseError::InvalidValue {
            key: key.into(),
            found: v.to_string(),
            expected: "a number > 0",
        })
    }
}

fn non_negative(key: &str, v: f64) -> Result<f64, ParseError> {
    if v >= 0.0 && v.is_finite() {
        Ok(v)
    } else {
        Err(ParseError::InvalidValue {
            key: key.into(),
            found: v.to_string(),
            expected: "a number >= 0",
        })
    }
}

/// Parses a count the way MOOS does (`atoi` of a value that passed `isNumber`: truncated).
fn count(key: &str, v: &str) -> Result<i64, ParseError> {
    let f = need_number(key, v)?;
    check_count(f.abs())?;
    Ok(f.trunc() as i64)
}

/// Polygon generators: convexity is judged before the snap, a snap that breaks convexity is
/// undone, and the result must be convex (MOOS returns a null polygon otherwise).
fn finish_convex(pts: Vec<Point>, snap: f64) -> Result<Polygon, ParseError> {
    let mut poly = Polygon::new(pts);
    if snap > 0.0 {
        poly.apply_snap(snap);
    }
    if poly.is_convex() {
        Ok(poly)
    } else {
        Err(ParseError::NotConvex)
    }
}

/// Iterates the non-empty `key=value` pieces of a comma list, key lower-cased.
fn pairs(s: &str) -> impl Iterator<Item = (std::borrow::Cow<'_, str>, &str)> {
    split_top(s, ',').filter(|p| !p.is_empty()).map(|p| {
        let (k, v) = split_kv(p);
        (lower(k), v)
    })
}

/// Handles `format=<expected>` (must match) and the common object keys; anything else is an
/// unknown key for formats that reject those.
fn common_or_unknown(
    key: &str,
    value: &str,
    format: &'static str,
    accepted: &[&str],
    attrs: &mut Attributes,
) -> Result<(), ParseError> {
    if key == "format" {
        if accepted.contains(&value) {
            return Ok(());
        }
        return Err(ParseError::UnknownFormat {
            kind: "polygon",
            found: value.into(),
            expected: format,
        });
    }
    if attrs.set(key, value)? {
        Ok(())
    } else {
        Err(ParseError::UnknownKey {
            key: key.into(),
            format,
        })
    }
}

// ---------------------------------------------------------------------------------------------
// Lawnmower

/// Lane direction of a [`Lawnmower`]: `rows=ew` (default) or `rows=ns`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Rows {
    /// Lanes run east-west (`ew`, `east-west`; also any unrecognised value, as in MOOS).
    #[default]
    EastWest,
    /// Lanes run north-south (`ns`, `north-south`).
    NorthSouth,
}

/// `format=lawnmower` (or `lawnmower:` prefix): a back-and-forth survey of a rectangle.
///
/// Construction (MOOS `stringLawnmower2SegList` + `XYPatternBlock`): with `rows=ew` the width
/// and height are swapped and 90 is added to `degs`; then block width `bw`, block length `bl`,
/// angle `ang`. Quirk kept from the real code: `XYPatternBlock::setParam` ignores an angle
/// below 1, so any effective angle `< 1` (including negative `degs` with `rows=ns`) is 0.
/// Lane count is `trunc(bw/swath + 1 + 0.99999)`; lane `i` is centred `bw/2 − i·swath` from
/// `(x, y)` on bearing `ang − 90` (`ang + 90` when negative); its ends are `bl/2` along `ang`
/// and `ang − 180`. The entry vertex is the lane end (of the first or last lane only) nearest
/// `(startx, starty)`, first one winning ties; the path then alternates direction lane by
/// lane. Finally every vertex is snapped to `snap` (default 0.00001).
///
/// The reference (§2) describes each lane edge as tagged "lane"; edge tags are not modelled.
#[derive(Debug, Clone, PartialEq)]
pub struct Lawnmower {
    /// Centre x.
    pub x: f64,
    /// Centre y.
    pub y: f64,
    /// East-west extent before rotation.
    pub width: f64,
    /// North-south extent before rotation.
    pub height: f64,
    /// Lane spacing (`swath` or `lane_width`).
    pub swath: f64,
    /// Rotation in degrees (default 0).
    pub degs: f64,
    /// Lane direction.
    pub rows: Rows,
    /// Point the entry vertex is chosen nearest to (default 0).
    pub startx: f64,
    /// Point the entry vertex is chosen nearest to (default 0).
    pub starty: f64,
    /// Snap step applied to every vertex (default 0.00001; 0 = none).
    pub snap: f64,
}

impl Lawnmower {
    /// A lawnmower with MOOS defaults for the optional parameters.
    pub fn new(x: f64, y: f64, width: f64, height: f64, swath: f64) -> Self {
        Lawnmower {
            x,
            y,
            width,
            height,
            swath,
            degs: 0.0,
            rows: Rows::EastWest,
            startx: 0.0,
            starty: 0.0,
            snap: 0.00001,
        }
    }

    /// The vertex list, in travel order.
    ///
    /// ```
    /// use geometry::pattern::Lawnmower;
    /// let v = Lawnmower::new(0.0, 0.0, 100.0, 60.0, 20.0).vertices().unwrap();
    /// assert_eq!(v.len(), 8);
    /// assert!((v[0].x - 50.0).abs() < 1e-9 && (v[0].y - 30.0).abs() < 1e-9);
    /// ```
    pub fn vertices(&self) -> Result<Vec<Point>, ParseError> {
        positive("width", self.width)?;
        positive("height", self.height)?;
        positive("swath", self.swath)?;
        non_negative("snap", self.snap)?;
        let (bw, bl, ang) = match self.rows {
            Rows::EastWest => (self.height, self.width, self.degs + 90.0),
            Rows::NorthSouth => (self.width, self.height, self.degs),
        };
        let ang = if ang >= 1.0 { ang } else { 0.0 };
        let lanes_f = ((bw / self.swath) + 1.0 + 0.99999).trunc();
        check_count(lanes_f * 2.0)?;
        let lanes = lanes_f as usize;
        let side1 = angle_360(ang - 90.0);
        let side2 = angle_360(ang + 90.0);
        let fwd = angle_360(ang);
        let back = angle_360(ang - 180.0);
        let mut ends: Vec<(Point, Point)> = Vec::with_capacity(lanes);
        for i in 0..lanes {
            let mut d = (bw / 2.0) - (i as f64) * self.swath;
            let mut side = side1;
            if d < 0.0 {
                side = side2;
                d = -d;
            }
            let mid = if d == 0.0 {
                Point::new(self.x, self.y)
            } else {
                project_point(self.x, self.y, side, d)
            };
            let p1 = project_point(mid.x, mid.y, fwd, bl / 2.0);
            let p2 = project_point(mid.x, mid.y, back, bl / 2.0);
            ends.push((p1, p2));
        }
        let (Some(first), Some(last)) = (ends.first().copied(), ends.last().copied()) else {
            return Ok(Vec::new());
        };
        let (sx, sy) = (self.startx, self.starty);
        let dist = |p: Point| (p.x - sx).hypot(p.y - sy);
        let mut first_lane_zero = true;
        let mut first_pt_zero = true;
        let mut best = dist(first.0);
        if dist(first.1) < best {
            best = dist(first.1);
            first_pt_zero = false;
        }
        if dist(last.0) < best {
            best = dist(last.0);
            first_lane_zero = false;
            first_pt_zero = true;
        }
        if dist(last.1) < best {
            first_lane_zero = false;
            first_pt_zero = false;
        }
        if !first_lane_zero {
            ends.reverse();
        }
        let mut out = Vec::with_capacity(ends.len() * 2);
        let mut zeroth = first_pt_zero;
        for (p1, p2) in ends {
            if zeroth {
                out.push(p1);
                out.push(p2);
            } else {
                out.push(p2);
                out.push(p1);
            }
            zeroth = !zeroth;
        }
        if self.snap > 0.0 {
            for p in &mut out {
                *p = p.snapped(self.snap);
            }
        }
        Ok(out)
    }

    /// Parses the key=value list (without or with `format=lawnmower`). Required: `x`, `y`,
    /// `width`, `height`, `swath`/`lane_width`. Keys MOOS does not know are ignored, as in
    /// MOOS; style keys go to `attrs`.
    pub(crate) fn parse(s: &str, attrs: &mut Attributes) -> Result<Self, ParseError> {
        let (mut x, mut y, mut w, mut h, mut sw) = (None, None, None, None, None);
        let mut m = Lawnmower::new(0.0, 0.0, 0.0, 0.0, 0.0);
        for (k, v) in pairs(s) {
            match k.as_ref() {
                "x" => x = Some(need_number("x", v)?),
                "y" => y = Some(need_number("y", v)?),
                "width" => w = Some(need_number("width", v)?),
                "height" => h = Some(need_number("height", v)?),
                "swath" | "lane_width" => sw = Some(need_number(&k, v)?),
                "degs" => m.degs = need_number("degs", v)?,
                "startx" => m.startx = need_number("startx", v)?,
                "starty" => m.starty = need_number("starty", v)?,
                "snap" => m.snap = non_negative("snap", need_number("snap", v)?)?,
                "rows" => {
                    m.rows = match lower(v).as_ref() {
                        "ns" | "north-south" => Rows::NorthSouth,
                        _ => Rows::EastWest,
                    }
                }
                "format" => {}
                other => {
                    attrs.set(other, v)?;
                }
            }
        }
        m.x = x.ok_or(ParseError::Missing {
            key: "x",
            format: "lawnmower",
        })?;
        m.y = y.ok_or(ParseError::Missing {
            key: "y",
            format: "lawnmower",
        })?;
        m.width = w.ok_or(ParseError::Missing {
            key: "width",
            format: "lawnmower",
        })?;
        m.height = h.ok_or(ParseError::Missing {
            key: "height",
            format: "lawnmower",
        })?;
        m.swath = sw.ok_or(ParseError::Missing {
            key: "swath",
            format: "lawnmower",
        })?;
        Ok(m)
    }
}

// ---------------------------------------------------------------------------------------------
// Bowtie

/// `format=bowtie`: a figure-eight over two trapezoids (MOOS `stringBowTie2SegList`).
///
/// With `h = height/2`: P1=(x−w2, y+h), P2=(x−w1, y+h), P3=(x+w1, y+h), P4=(x+w2, y+h),
/// P5=(x−w3, y), P6=(x+w3, y), P7=(x−w2, y−h), P8=(x−w1, y−h), P9=(x+w1, y−h), P10=(x+w2, y−h).
/// The case comes from the bearing centre→start: `[0,90)` ne, `[90,180)` se, `[180,270)` sw,
/// else nw; without a start point (both `startx` and `starty` needed) the case is ne.
/// Orders: ne 8,7,5,1,2,9,10,6,4,3 · se 2,1,5,7,8,3,4,6,10,9 · sw 3,4,6,10,9,2,1,5,7,8 ·
/// nw 9,10,6,4,3,8,7,5,1,2. No snap is applied.
#[derive(Debug, Clone, PartialEq)]
pub struct Bowtie {
    /// Centre x.
    pub x: f64,
    /// Centre y.
    pub y: f64,
    /// Total height (top row at `y + height/2`).
    pub height: f64,
    /// Inner half-width of the top/bottom rows.
    pub wid1: f64,
    /// Outer half-width of the top/bottom rows.
    pub wid2: f64,
    /// Half-width of the middle row.
    pub wid3: f64,
    /// Optional start point choosing the case.
    pub start: Option<Point>,
}

impl Bowtie {
    /// The vertex list in travel order.
    pub fn vertices(&self) -> Vec<Point> {
        let (x, y, h) = (self.x, self.y, self.height / 2.0);
        let p = [
            Point::new(x - self.wid2, y + h),
            Point::new(x - self.wid1, y + h),
            Point::new(x + self.wid1, y + h),
            Point::new(x + self.wid2, y + h),
            Point::new(x - self.wid3, y),
            Point::new(x + self.wid3, y),
            Point::new(x - self.wid2, y - h),
            Point::new(x - self.wid1, y - h),
            Point::new(x + self.wid1, y - h),
            Point::new(x + self.wid2, y - h),
        ];
        let bearing = self.start.map(|s| relative_angle(x, y, s.x, s.y));
        let order: [usize; 10] = match bearing {
            None => [8, 7, 5, 1, 2, 9, 10, 6, 4, 3],
            Some(b) if (0.0..90.0).contains(&b) => [8, 7, 5, 1, 2, 9, 10, 6, 4, 3],
            Some(b) if (90.0..180.0).contains(&b) => [2, 1, 5, 7, 8, 3, 4, 6, 10, 9],
            Some(b) if (180.0..270.0).contains(&b) => [3, 4, 6, 10, 9, 2, 1, 5, 7, 8],
            Some(_) => [9, 10, 6, 4, 3, 8, 7, 5, 1, 2],
        };
        order.iter().map(|&i| p[i - 1]).collect()
    }

    /// Parses the key=value list. Required: `x`, `y`, `height`, `wid1`, `wid2`, `wid3`. Other
    /// keys go to `attrs` and are ignored when unknown (as MOOS's `set_param` does).
    pub(crate) fn parse(s: &str, attrs: &mut Attributes) -> Result<Self, ParseError> {
        let mut v: [Option<f64>; 8] = [None; 8];
        const KEYS: [&str; 8] = [
            "x", "y", "height", "wid1", "wid2", "wid3", "startx", "starty",
        ];
        for (k, val) in pairs(s) {
            if let Some(i) = KEYS.iter().position(|&n| n == k.as_ref()) {
                v[i] = Some(need_number(KEYS[i], val)?);
            } else if k != "format" {
                attrs.set(&k, val)?;
            }
        }
        let req = |i: usize| {
            v[i].ok_or(ParseError::Missing {
                key: KEYS[i],
                format: "bowtie",
            })
        };
        Ok(Bowtie {
            x: req(0)?,
            y: req(1)?,
            height: req(2)?,
            wid1: req(3)?,
            wid2: req(4)?,
            wid3: req(5)?,
            start: match (v[6], v[7]) {
                (Some(sx), Some(sy)) => Some(Point::new(sx, sy)),
                _ => None,
            },
        })
    }
}

// ---------------------------------------------------------------------------------------------
// ZigZag

/// `zigzag: startx,starty,angle,length,period,amplitude[,snap]` (positional form only).
///
/// The first vertex is the start; then for `d = period/4, period/4 + period/2, …` while
/// `d < length`: project along `angle` by `d`, then sideways by `amplitude` at `angle − 90`,
/// `angle + 90`, alternating. Snap defaults to 0.0001. The `format=zigzag, key=val` form is
/// rejected by the real parser (every comma field must be numeric), so it is an error here too.
#[derive(Debug, Clone, PartialEq)]
pub struct ZigZag {
    /// Start x.
    pub startx: f64,
    /// Start y.
    pub starty: f64,
    /// Axis heading, degrees.
    pub angle: f64,
    /// Axis length.
    pub length: f64,
    /// Full period along the axis.
    pub period: f64,
    /// Sideways amplitude.
    pub amplitude: f64,
    /// Snap step (0 = none).
    pub snap: f64,
}

impl ZigZag {
    /// The vertex list in travel order.
    pub fn vertices(&self) -> Result<Vec<Point>, ParseError> {
        positive("period", self.period)?;
        positive("amplitude", self.amplitude)?;
        positive("length", self.length)?;
        non_negative("snap", self.snap)?;
        check_count(self.length / (self.period / 2.0) + 2.0)?;
        let mut out = vec![Point::new(self.startx, self.starty)];
        let mut side = -90.0;
        let mut d = self.period / 4.0;
        while d < self.length {
            let axis = project_point(self.startx, self.starty, self.angle, d);
            out.push(project_point(
                axis.x,
                axis.y,
                self.angle + side,
                self.amplitude,
            ));
            side = -side;
            d += self.period / 2.0;
        }
        if self.snap > 0.0 {
            for p in &mut out {
                *p = p.snapped(self.snap);
            }
        }
        Ok(out)
    }

    pub(crate) fn parse(s: &str) -> Result<Self, ParseError> {
        let fields: Vec<&str> = s.split(',').map(str::trim).collect();
        if !(6..=7).contains(&fields.len()) {
            return Err(ParseError::FieldCount {
                format: "zigzag",
                expected: "6 or 7",
                found: fields.len(),
            });
        }
        const NAMES: [&str; 7] = [
            "startx",
            "starty",
            "angle",
            "length",
            "period",
            "amplitude",
            "snap",
        ];
        let mut v = [0.0f64; 7];
        v[6] = 0.0001;
        for (i, f) in fields.iter().enumerate() {
            v[i] = need_number(NAMES[i], f)?;
        }
        Ok(ZigZag {
            startx: v[0],
            starty: v[1],
            angle: v[2],
            length: v[3],
            period: v[4],
            amplitude: v[5],
            snap: v[6],
        })
    }
}

// ---------------------------------------------------------------------------------------------
// Radial

/// `format=radial` / `radial:: key=val` / `radial: x,y,radius,pts[,snap[,label]]`: a regular
/// polygon approximating a circle.
///
/// `delta = 360/pts`; vertices at compass bearings `delta/2, 3·delta/2, …` below 360 (the
/// first just clockwise of north; clockwise order), around `(x + shiftx, y + shifty)`.
/// Convexity is judged, then the snap applied (undone if it breaks convexity).
/// The positional form in MOOS reads `pts` with `atof`, so a fractional count gives unevenly
/// spaced vertices there; here `pts` must be a whole number.
#[derive(Debug, Clone, PartialEq)]
pub struct Radial {
    /// Centre x.
    pub x: f64,
    /// Centre y.
    pub y: f64,
    /// Vertex z (default 0).
    pub z: f64,
    /// Radius, > 0.
    pub radius: f64,
    /// Vertex count, >= 3.
    pub pts: u32,
    /// Snap step (0 = none).
    pub snap: f64,
}

impl Radial {
    /// The raw (unsnapped) vertices.
    pub fn vertices(&self) -> Result<Vec<Point>, ParseError> {
        positive("radius", self.radius)?;
        if self.pts < 3 {
            return Err(ParseError::InvalidValue {
                key: "pts".into(),
                found: self.pts.to_string(),
                expected: "an integer >= 3",
            });
        }
        check_count(f64::from(self.pts))?;
        let delta = 360.0 / f64::from(self.pts);
        let mut out = Vec::with_capacity(self.pts as usize);
        let mut deg = delta / 2.0;
        while deg < 360.0 {
            let p = project_point(self.x, self.y, deg, self.radius);
            out.push(Point::new_3d(p.x, p.y, self.z));
            deg += delta;
        }
        Ok(out)
    }

    /// The polygon (convex, snapped).
    ///
    /// ```
    /// use geometry::pattern::Radial;
    /// let p = Radial { x: 0.0, y: 0.0, z: 0.0, radius: 10.0, pts: 4, snap: 0.0 }.polygon().unwrap();
    /// assert!((p.vertices()[0].x - 7.0710678).abs() < 1e-6);
    /// ```
    pub fn polygon(&self) -> Result<Polygon, ParseError> {
        finish_convex(self.vertices()?, self.snap)
    }

    pub(crate) fn parse(s: &str, attrs: &mut Attributes) -> Result<Self, ParseError> {
        let (mut x, mut y, mut radius, mut pts) = (None, None, None, None);
        let mut r = Radial {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            radius: 0.0,
            pts: 0,
            snap: 0.0,
        };
        let (mut shiftx, mut shifty) = (0.0, 0.0);
        for (k, v) in pairs(s) {
            match k.as_ref() {
                "x" => x = Some(need_number("x", v)?),
                "y" => y = Some(need_number("y", v)?),
                "z" => r.z = need_number("z", v)?,
                "shiftx" => shiftx = need_number("shiftx", v)?,
                "shifty" => shifty = need_number("shifty", v)?,
                "radius" => radius = Some(positive("radius", need_number("radius", v)?)?),
                "pts" => pts = Some(count("pts", v)?),
                "snap" => r.snap = non_negative("snap", need_number("snap", v)?)?,
                other => common_or_unknown(other, v, "radial", &["radial"], attrs)?,
            }
        }
        r.x = x.ok_or(ParseError::Missing {
            key: "x",
            format: "radial",
        })? + shiftx;
        r.y = y.ok_or(ParseError::Missing {
            key: "y",
            format: "radial",
        })? + shifty;
        r.radius = radius.ok_or(ParseError::Missing {
            key: "radius",
            format: "radial",
        })?;
        let n = pts.ok_or(ParseError::Missing {
            key: "pts",
            format: "radial",
        })?;
        r.pts = pts_at_least("pts", n, 3)?;
        Ok(r)
    }

    pub(crate) fn parse_positional(s: &str, attrs: &mut Attributes) -> Result<Self, ParseError> {
        let fields: Vec<&str> = s.split(',').map(str::trim).collect();
        if !(4..=6).contains(&fields.len()) {
            return Err(ParseError::FieldCount {
                format: "radial:",
                expected: "4 to 6",
                found: fields.len(),
            });
        }
        let num = |i: usize, k: &str| need_number(k, fields[i]);
        let x = num(0, "x")?;
        let y = num(1, "y")?;
        let radius = positive("radius", num(2, "radius")?)?;
        let n = need_number("pts", fields[3])?;
        if n.fract() != 0.0 {
            return Err(ParseError::InvalidValue {
                key: "pts".into(),
                found: fields[3].into(),
                expected: "an integer >= 3",
            });
        }
        check_count(n.abs())?;
        let pts = pts_at_least("pts", n as i64, 3)?;
        let snap = match fields.get(4) {
            Some(f) => need_number("snap", f)?.max(0.0),
            None => 0.0,
        };
        if let Some(label) = fields.get(5) {
            attrs.label = (*label).to_string();
        }
        Ok(Radial {
            x,
            y,
            z: 0.0,
            radius,
            pts,
            snap,
        })
    }
}

fn pts_at_least(key: &str, n: i64, min: i64) -> Result<u32, ParseError> {
    if n < min {
        return Err(ParseError::InvalidValue {
            key: key.into(),
            found: n.to_string(),
            expected: if min == 3 {
                "an integer >= 3"
            } else {
                "an integer >= 4"
            },
        });
    }
    u32::try_from(n).map_err(|_| ParseError::TooManyVertices(n.unsigned_abs()))
}

// ---------------------------------------------------------------------------------------------
// Ellipse

/// `format=ellipse` / `ellipse:: key=val`: an ellipse approximated by `pts` vertices.
///
/// For `i` in `0..pts`, `a = −π + i·2π/pts` and rotation `r` (math convention,
/// counter-clockwise from +x; `rads`, or `degs` converted, `rads` winning if both):
/// `x' = x + (major/2)cos a cos r − (minor/2) sin a sin r`,
/// `y' = y + (minor/2) sin a cos r + (major/2) cos a sin r`.
/// The first vertex is the −major end (west when `r = 0`), counter-clockwise order; the
/// result must be convex. `major`/`minor` are full axis lengths. `snap_value` is an alias of
/// `snap`.
#[derive(Debug, Clone, PartialEq)]
pub struct Ellipse {
    /// Centre x.
    pub x: f64,
    /// Centre y.
    pub y: f64,
    /// Vertex z.
    pub z: f64,
    /// Major axis length, > 0.
    pub major: f64,
    /// Minor axis length, > 0.
    pub minor: f64,
    /// Rotation in radians, counter-clockwise from +x.
    pub rads: f64,
    /// Vertex count, >= 4.
    pub pts: u32,
    /// Snap step (0 = none).
    pub snap: f64,
}

impl Ellipse {
    /// The raw (unsnapped) vertices.
    pub fn vertices(&self) -> Result<Vec<Point>, ParseError> {
        positive("major", self.major)?;
        positive("minor", self.minor)?;
        if self.pts < 4 {
            return Err(ParseError::InvalidValue {
                key: "pts".into(),
                found: self.pts.to_string(),
                expected: "an integer >= 4",
            });
        }
        check_count(f64::from(self.pts))?;
        let delta = (2.0 * std::f64::consts::PI) / f64::from(self.pts);
        let (cr, sr) = (self.rads.cos(), self.rads.sin());
        Ok((0..self.pts)
            .map(|i| {
                let a = -std::f64::consts::PI + f64::from(i) * delta;
                let nx =
                    self.x + (self.major / 2.0 * a.cos() * cr) - (self.minor / 2.0 * a.sin() * sr);
                let ny =
                    self.y + (self.minor / 2.0 * a.sin() * cr) + (self.major / 2.0 * a.cos() * sr);
                Point::new_3d(nx, ny, self.z)
            })
            .collect())
    }

    /// The polygon (convex, snapped).
    pub fn polygon(&self) -> Result<Polygon, ParseError> {
        finish_convex(self.vertices()?, self.snap)
    }

    pub(crate) fn parse(s: &str, attrs: &mut Attributes) -> Result<Self, ParseError> {
        let (mut x, mut y, mut major, mut minor, mut pts, mut rads, mut degs) =
            (None, None, None, None, None, None, None);
        let mut e = Ellipse {
            x: 0.0,
            y: 0.0,
            z: 0.0,
            major: 0.0,
            minor: 0.0,
            rads: 0.0,
            pts: 0,
            snap: 0.0,
        };
        for (k, v) in pairs(s) {
            match k.as_ref() {
                "x" => x = Some(need_number("x", v)?),
                "y" => y = Some(need_number("y", v)?),
                "z" => e.z = need_number("z", v)?,
                "major" => major = Some(positive("major", need_number("major", v)?)?),
                "minor" => minor = Some(positive("minor", need_number("minor", v)?)?),
                "rads" => rads = Some(need_number("rads", v)?),
                "degs" => degs = Some(need_number("degs", v)?),
                "pts" => pts = Some(count("pts", v)?),
                "snap" | "snap_value" => e.snap = non_negative("snap", need_number("snap", v)?)?,
                other => common_or_unknown(other, v, "ellipse", &["ellipse"], attrs)?,
            }
        }
        e.x = x.ok_or(ParseError::Missing {
            key: "x",
            format: "ellipse",
        })?;
        e.y = y.ok_or(ParseError::Missing {
            key: "y",
            format: "ellipse",
        })?;
        e.major = major.ok_or(ParseError::Missing {
            key: "major",
            format: "ellipse",
        })?;
        e.minor = minor.ok_or(ParseError::Missing {
            key: "minor",
            format: "ellipse",
        })?;
        e.pts = pts_at_least(
            "pts",
            pts.ok_or(ParseError::Missing {
                key: "pts",
                format: "ellipse",
            })?,
            4,
        )?;
        e.rads = match (rads, degs) {
            (Some(r), _) => r,
            (None, Some(d)) => d.to_radians(),
            (None, None) => {
                return Err(ParseError::Missing {
                    key: "rads or degs",
                    format: "ellipse",
                });
            }
        };
        Ok(e)
    }
}

// ---------------------------------------------------------------------------------------------
// Wedges

fn arc_angles(lang: f64, rang: f64, pts: u32) -> Result<(f64, f64, f64), ParseError> {
    let lang = angle_360(lang);
    let mut rang = angle_360(rang);
    if rang < lang {
        rang += 360.0;
    }
    check_count(f64::from(pts) + 2.0)?;
    let delta = if rang > lang {
        (rang - lang) / f64::from(pts)
    } else {
        0.0
    };
    Ok((lang, rang, delta))
}

/// Pushes arc vertices from `from` toward `to` stepping by `delta` and clamping at `to`
/// (MOOS's accumulate-and-clamp loop). `up` = increasing angles.
fn push_arc(out: &mut Vec<Point>, c: Point, r: f64, from: f64, to: f64, delta: f64, up: bool) {
    let mut a = from;
    let mut guard = 0u64;
    loop {
        let more = if up { a < to } else { a > to };
        if !more || guard > MAX_VERTICES {
            break;
        }
        guard += 1;
        if up {
            a += delta;
            if a > to {
                a = to;
            }
        } else {
            a -= delta;
            if a < to {
                a = to;
            }
        }
        out.push(project_point(c.x, c.y, a, r));
    }
}

/// `format=wedge` / `format=piewedge` / `wedge:` / `piewedge:`: a pie slice.
///
/// `lang`/`rang` are normalised to `[0,360)` and `rang += 360` if `rang < lang`. Vertices: the
/// centre, the arc point at `lang`, then arc points every `(rang − lang)/pts` degrees clockwise,
/// the last clamped at `rang` (`pts = 0` gives a triangle). Must be convex.
#[derive(Debug, Clone, PartialEq)]
pub struct Wedge {
    /// Centre x.
    pub x: f64,
    /// Centre y.
    pub y: f64,
    /// Left (start) compass angle.
    pub lang: f64,
    /// Right (end) compass angle.
    pub rang: f64,
    /// Radius.
    pub range: f64,
    /// Arc steps (default 0).
    pub pts: u32,
    /// Snap step (0 = none).
    pub snap: f64,
}

impl Wedge {
    /// The raw (unsnapped) vertices.
    pub fn vertices(&self) -> Result<Vec<Point>, ParseError> {
        let (lang, rang, delta) = arc_angles(self.lang, self.rang, self.pts)?;
        let mut out = vec![
            Point::new(self.x, self.y),
            project_point(self.x, self.y, lang, self.range),
        ];
        push_arc(
            &mut out,
            Point::new(self.x, self.y),
            self.range,
            lang,
            rang,
            delta,
            true,
        );
        Ok(out)
    }

    /// The polygon (convex, snapped).
    pub fn polygon(&self) -> Result<Polygon, ParseError> {
        finish_convex(self.vertices()?, self.snap)
    }

    pub(crate) fn parse(s: &str, attrs: &mut Attributes) -> Result<Self, ParseError> {
        let (mut x, mut y, mut lang, mut rang, mut range) = (None, None, None, None, None);
        let mut w = Wedge {
            x: 0.0,
            y: 0.0,
            lang: 0.0,
            rang: 0.0,
            range: 0.0,
            pts: 0,
            snap: 0.0,
        };
        for (k, v) in pairs(s) {
            match k.as_ref() {
                "x" => x = Some(need_number("x", v)?),
                "y" => y = Some(need_number("y", v)?),
                "lang" => lang = Some(need_number("lang", v)?),
                "rang" => rang = Some(need_number("rang", v)?),
                "range" => range = Some(need_number("range", v)?),
                "pts" => w.pts = pts_at_least("pts", count("pts", v)?.max(0), 0)?,
                "snap" | "snap_value" => w.snap = non_negative("snap", need_number("snap", v)?)?,
                other => common_or_unknown(other, v, "wedge", &["wedge", "piewedge"], attrs)?,
            }
        }
        w.x = x.ok_or(ParseError::Missing {
            key: "x",
            format: "wedge",
        })?;
        w.y = y.ok_or(ParseError::Missing {
            key: "y",
            format: "wedge",
        })?;
        w.lang = lang.ok_or(ParseError::Missing {
            key: "lang",
            format: "wedge",
        })?;
        w.rang = rang.ok_or(ParseError::Missing {
            key: "rang",
            format: "wedge",
        })?;
        w.range = range.ok_or(ParseError::Missing {
            key: "range",
            format: "wedge",
        })?;
        Ok(w)
    }
}

/// `format=rangewedge` / `rangewedge:`: an annular sector.
///
/// The outer arc runs `lang → rang` at `range_max` (same stepping as [`Wedge`]), then the inner
/// arc runs `rang → lang` at `range_min` (default 0). Must be convex — note that with
/// `range_min = 0` the inner arc collapses onto the centre, which MOOS (and this crate) reject
/// as non-convex.
#[derive(Debug, Clone, PartialEq)]
pub struct RangeWedge {
    /// Centre x.
    pub x: f64,
    /// Centre y.
    pub y: f64,
    /// Left (start) compass angle.
    pub lang: f64,
    /// Right (end) compass angle.
    pub rang: f64,
    /// Inner radius (default 0).
    pub range_min: f64,
    /// Outer radius, > `range_min`.
    pub range_max: f64,
    /// Arc steps (default 0).
    pub pts: u32,
    /// Snap step (0 = none).
    pub snap: f64,
}

impl RangeWedge {
    /// The raw (unsnapped) vertices.
    pub fn vertices(&self) -> Result<Vec<Point>, ParseError> {
        if self.range_min >= self.range_max {
            return Err(ParseError::InvalidValue {
                key: "range_min".into(),
                found: self.range_min.to_string(),
                expected: "a value below range_max",
            });
        }
        let (lang, rang, delta) = arc_angles(self.lang, self.rang, self.pts)?;
        let mut out = vec![project_point(self.x, self.y, lang, self.range_max)];
        push_arc(
            &mut out,
            Point::new(self.x, self.y),
            self.range_max,
            lang,
            rang,
            delta,
            true,
        );
        out.push(project_point(self.x, self.y, rang, self.range_min));
        push_arc(
            &mut out,
            Point::new(self.x, self.y),
            self.range_min,
            rang,
            lang,
            delta,
            false,
        );
        Ok(out)
    }

    /// The polygon (convex, snapped).
    pub fn polygon(&self) -> Result<Polygon, ParseError> {
        finish_convex(self.vertices()?, self.snap)
    }

    pub(crate) fn parse(s: &str, attrs: &mut Attributes) -> Result<Self, ParseError> {
        let (mut x, mut y, mut lang, mut rang, mut rmax) = (None, None, None, None, None);
        let mut w = RangeWedge {
            x: 0.0,
            y: 0.0,
            lang: 0.0,
            rang: 0.0,
            range_min: 0.0,
            range_max: 0.0,
            pts: 0,
            snap: 0.0,
        };
        for (k, v) in pairs(s) {
            match k.as_ref() {
                "x" => x = Some(need_number("x", v)?),
                "y" => y = Some(need_number("y", v)?),
                "lang" => lang = Some(need_number("lang", v)?),
                "rang" => rang = Some(need_number("rang", v)?),
                "range_min" => w.range_min = need_number("range_min", v)?,
                "range_max" => rmax = Some(need_number("range_max", v)?),
                "pts" => w.pts = pts_at_least("pts", count("pts", v)?.max(0), 0)?,
                "snap" | "snap_value" => w.snap = non_negative("snap", need_number("snap", v)?)?,
                other => common_or_unknown(other, v, "rangewedge", &["rangewedge"], attrs)?,
            }
        }
        w.x = x.ok_or(ParseError::Missing {
            key: "x",
            format: "rangewedge",
        })?;
        w.y = y.ok_or(ParseError::Missing {
            key: "y",
            format: "rangewedge",
        })?;
        w.lang = lang.ok_or(ParseError::Missing {
            key: "lang",
            format: "rangewedge",
        })?;
        w.rang = rang.ok_or(ParseError::Missing {
            key: "rang",
            format: "rangewedge",
        })?;
        w.range_max = rmax.ok_or(ParseError::Missing {
            key: "range_max",
            format: "rangewedge",
        })?;
        Ok(w)
    }
}

// ---------------------------------------------------------------------------------------------
// Pylon

/// `format=pylon` / `pylon:`: a rectangle around the segment p1→p2.
///
/// With `b` = bearing p1→p2: V1 = p1 moved back `axis_pad` along `b`, then `perp_pad` toward
/// `b − 90`; V2 = the same but toward `b + 90`; V3 = p2 moved forward `axis_pad`, then toward
/// `b + 90`; V4 = the same but toward `b − 90`. `perp_pad` is required although MOOS's header
/// comment omits it.
#[derive(Debug, Clone, PartialEq)]
pub struct Pylon {
    /// First end x.
    pub x1: f64,
    /// First end y.
    pub y1: f64,
    /// Second end x.
    pub x2: f64,
    /// Second end y.
    pub y2: f64,
    /// Vertex z.
    pub z: f64,
    /// Padding along the axis, >= 0.
    pub axis_pad: f64,
    /// Padding across the axis, >= 0.
    pub perp_pad: f64,
    /// Snap step (0 = none).
    pub snap: f64,
}

impl Pylon {
    /// The raw (unsnapped) vertices.
    pub fn vertices(&self) -> Vec<Point> {
        let b = relative_angle(self.x1, self.y1, self.x2, self.y2);
        let back = project_point(self.x1, self.y1, b - 180.0, self.axis_pad);
        let fwd = project_point(self.x2, self.y2, b, self.axis_pad);
        [
            project_point(back.x, back.y, b - 90.0, self.perp_pad),
            project_point(back.x, back.y, b + 90.0, self.perp_pad),
            project_point(fwd.x, fwd.y, b + 90.0, self.perp_pad),
            project_point(fwd.x, fwd.y, b - 90.0, self.perp_pad),
        ]
        .into_iter()
        .map(|p| Point::new_3d(p.x, p.y, self.z))
        .collect()
    }

    /// The polygon (convex, snapped).
    pub fn polygon(&self) -> Result<Polygon, ParseError> {
        finish_convex(self.vertices(), self.snap)
    }

    pub(crate) fn parse(s: &str, attrs: &mut Attributes) -> Result<Self, ParseError> {
        let mut v: [Option<f64>; 6] = [None; 6];
        const KEYS: [&str; 6] = ["x1", "y1", "x2", "y2", "axis_pad", "perp_pad"];
        let (mut z, mut snap) = (0.0, 0.0);
        for (k, val) in pairs(s) {
            if let Some(i) = KEYS.iter().position(|&n| n == k.as_ref()) {
                let n = need_number(KEYS[i], val)?;
                v[i] = Some(if i >= 4 { non_negative(KEYS[i], n)? } else { n });
                continue;
            }
            match k.as_ref() {
                "z" => z = need_number("z", val)?,
                "snap" | "snap_value" => snap = non_negative("snap", need_number("snap", val)?)?,
                other => common_or_unknown(other, val, "pylon", &["pylon"], attrs)?,
            }
        }
        let req = |i: usize| {
            v[i].ok_or(ParseError::Missing {
                key: KEYS[i],
                format: "pylon",
            })
        };
        Ok(Pylon {
            x1: req(0)?,
            y1: req(1)?,
            x2: req(2)?,
            y2: req(3)?,
            z,
            axis_pad: req(4)?,
            perp_pad: req(5)?,
            snap,
        })
    }
}

// ---------------------------------------------------------------------------------------------
// Oval

/// `format=oval` / `oval:`: a stadium shape (MOOS `XYOval::getOvalPoly(15)`).
///
/// `il = (len − 2·rad)/2` must be > 0; `c1` = centre moved `il` along `ang`, `c2` = moved `il`
/// along `ang − 180`. Vertices: 13 points on the half circle of radius `rad` round `c1` at
/// bearings `ang − 90 … ang + 90` in 15-degree steps, then 13 round `c2` at
/// `ang + 90 … ang + 270`: 26 vertices, clockwise. No convexity gate (as in MOOS).
/// `draw_degs` is accepted and ignored, and so is any key that is not an object attribute (as
/// MOOS's `stringToOval` does). Checked against `XYOval.cpp` (the corpus uses `oval:` only
/// with an unexpanded macro).
#[derive(Debug, Clone, PartialEq)]
pub struct Oval {
    /// Centre x.
    pub x: f64,
    /// Centre y.
    pub y: f64,
    /// End radius, > 0.
    pub rad: f64,
    /// Total length, > 2·rad.
    pub len: f64,
    /// Compass heading of the long axis.
    pub ang: f64,
}

impl Oval {
    /// The 26 vertices.
    pub fn vertices(&self) -> Result<Vec<Point>, ParseError> {
        positive("rad", self.rad)?;
        let il = (self.len - 2.0 * self.rad) / 2.0;
        if il.is_nan() || il <= 0.0 {
            return Err(ParseError::InvalidValue {
                key: "len".into(),
                found: self.len.to_string(),
                expected: "a length greater than 2*rad",
            });
        }
        let c1 = project_point(self.x, self.y, self.ang, il);
        let c2 = project_point(self.x, self.y, self.ang - 180.0, il);
        let mut out = Vec::with_capacity(26);
        for k in 0..13 {
            out.push(project_point(
                c1.x,
                c1.y,
                self.ang - 90.0 + 15.0 * f64::from(k),
                self.rad,
            ));
        }
        for k in 0..13 {
            out.push(project_point(
                c2.x,
                c2.y,
                self.ang + 90.0 + 15.0 * f64::from(k),
                self.rad,
            ));
        }
        Ok(out)
    }

    /// The polygon (no convexity gate).
    pub fn polygon(&self) -> Result<Polygon, ParseError> {
        Ok(Polygon::new(self.vertices()?))
    }

    pub(crate) fn parse(s: &str, attrs: &mut Attributes) -> Result<Self, ParseError> {
        let (mut x, mut y, mut rad, mut len, mut ang) = (None, None, None, None, None);
        for (k, v) in pairs(s) {
            match k.as_ref() {
                "x" => x = Some(need_number("x", v)?),
                "y" => y = Some(need_number("y", v)?),
                "rad" => rad = Some(need_number("rad", v)?),
                "len" => len = Some(need_number("len", v)?),
                "ang" => ang = Some(need_number("ang", v)?),
                "draw_degs" => {
                    need_number("draw_degs", v)?;
                }
                // `stringToOval` hands anything else to set_param and ignores failures.
                other => {
                    attrs.set(other, v)?;
                }
            }
        }
        Ok(Oval {
            x: x.ok_or(ParseError::Missing {
                key: "x",
                format: "oval",
            })?,
            y: y.ok_or(ParseError::Missing {
                key: "y",
                format: "oval",
            })?,
            rad: rad.ok_or(ParseError::Missing {
                key: "rad",
                format: "oval",
            })?,
            len: len.ok_or(ParseError::Missing {
                key: "len",
                format: "oval",
            })?,
            ang: ang.ok_or(ParseError::Missing {
                key: "ang",
                format: "oval",
            })?,
        })
    }
}

/// Builds a [`SegList`] from generated points.
pub(crate) fn seglist_of(pts: Vec<Point>) -> SegList {
    SegList::from_points(pts)
}
