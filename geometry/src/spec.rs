//! Geometry strings: parsing every `point =` / `points =` / `polygon =` form, and writing and
//! reading the `VIEW_POINT`, `VIEW_SEGLIST` and `VIEW_POLYGON` specs (reference
//! `ivp-helm.md` §8, `moos-apps-extra.md` §2).
//!
//! Parsers ([`parse_point`], [`parse_seglist`], [`parse_polygon`], [`parse_waypoints`]) never
//! panic; they return a [`ParseError`] naming what was expected. Writers append to a caller
//! buffer (`spec(&self, out: &mut String)`) so a behaviour can reuse one `String` per
//! iteration; `to_spec()` is the allocating convenience.
//!
//! Differences from MOOS-IvP, all on the lenient side or more explicit:
//! - keys are matched case-insensitively (MOOS's standard form matches lower case only);
//! - a value that must be numeric but is not is an error, where MOOS uses `atof` (0);
//! - in the standard `pts={...}` form, unknown keys are ignored exactly as MOOS ignores them
//!   (a `tags={...}` edge-tag group is skipped whole: edge tags are not modelled);
//! - per-vertex properties are kept for seglists but dropped for polygons.

use crate::error::ParseError;
use crate::pattern::{
    Bowtie, Ellipse, Lawnmower, Oval, Pylon, Radial, RangeWedge, Wedge, ZigZag, seglist_of,
};
use crate::point::Point;
use crate::polygon::Polygon;
use crate::seglist::SegList;
use crate::text::{
    bite, boolean, lower, need_number, number, remove_white, split_kv, split_top, write_num,
};

/// The common fields of every viewable object (MOOS `XYObject`): label, colours, sizes, ...
///
/// Written in MOOS order: `active=false` (only when inactive), `label`, `msg`, `source`,
/// `vsource`, `id`, `label_color`, `edge_color`, `vertex_color`, `fill_color`, `time` (2 dp),
/// `duration` (2 dp), `vertex_size` (1 dp), `edge_size` (1 dp), `fill_transparency` (2 dp);
/// numbers compacted (`5.0` → `5`).
#[derive(Debug, Clone, PartialEq)]
pub struct Attributes {
    /// False = erase the object with this label in the viewer.
    pub active: bool,
    /// Label; objects of one type with the same label replace each other.
    pub label: String,
    /// Free message.
    pub msg: String,
    /// Source (e.g. `<vehicle>:<behaviour>`).
    pub source: String,
    /// Vehicle source.
    pub vsource: String,
    /// Object id.
    pub id: String,
    /// Label colour.
    pub label_color: Option<String>,
    /// Edge colour.
    pub edge_color: Option<String>,
    /// Vertex colour.
    pub vertex_color: Option<String>,
    /// Fill colour.
    pub fill_color: Option<String>,
    /// Timestamp, seconds.
    pub time: Option<f64>,
    /// Display duration, seconds (negative is stored as −1 = forever).
    pub duration: Option<f64>,
    /// Vertex size (>= 0).
    pub vertex_size: Option<f64>,
    /// Edge size (>= 0).
    pub edge_size: Option<f64>,
    /// Fill transparency, clipped to `[0, 1]`.
    pub fill_transparency: Option<f64>,
}

impl Default for Attributes {
    fn default() -> Self {
        Attributes {
            active: true,
            label: String::new(),
            msg: String::new(),
            source: String::new(),
            vsource: String::new(),
            id: String::new(),
            label_color: None,
            edge_color: None,
            vertex_color: None,
            fill_color: None,
            time: None,
            duration: None,
            vertex_size: None,
            edge_size: None,
            fill_transparency: None,
        }
    }
}

fn sep(out: &mut String, base: usize) {
    if out.len() > base {
        out.push(',');
    }
}

impl Attributes {
    /// Attributes with just a label.
    pub fn labeled(label: impl Into<String>) -> Self {
        Attributes {
            label: label.into(),
            ..Attributes::default()
        }
    }

    /// Sets one field from a `key=value` pair (MOOS `XYObject::set_param`; `key` lower case).
    /// Returns `Ok(false)` for a key that is not an object field, an error for a bad value.
    /// Negative sizes are ignored, as in MOOS.
    pub fn set(&mut self, key: &str, value: &str) -> Result<bool, ParseError> {
        let v = value.trim();
        match key {
            "label" => self.label = v.to_string(),
            "msg" => self.msg = v.to_string(),
            "source" => self.source = v.to_string(),
            "vsource" => self.vsource = v.to_string(),
            "id" => self.id = v.to_string(),
            "label_color" => self.label_color = Some(v.to_string()),
            "edge_color" => self.edge_color = Some(v.to_string()),
            "vertex_color" => self.vertex_color = Some(v.to_string()),
            "fill_color" => self.fill_color = Some(v.to_string()),
            "time" => self.time = Some(need_number(key, v)?),
            "duration" | "dur" => {
                let d = need_number(key, v)?;
                self.duration = Some(if d < 0.0 { -1.0 } else { d });
            }
            "vertex_size" => {
                let d = need_number(key, v)?;
                if d >= 0.0 {
                    self.vertex_size = Some(d);
                }
            }
            "edge_size" => {
                let d = need_number(key, v)?;
                if d >= 0.0 {
                    self.edge_size = Some(d);
                }
            }
            "fill_transparency" => {
                self.fill_transparency = Some(need_number(key, v)?.clamp(0.0, 1.0))
            }
            "active" => {
                self.active = boolean(v).ok_or_else(|| ParseError::InvalidValue {
                    key: "active".into(),
                    found: v.into(),
                    expected: "true or false",
                })?
            }
            "type" => {} // deprecated in MOOS; accepted and ignored
            _ => return Ok(false),
        }
        Ok(true)
    }

    /// Appends the fields, comma-separated, to `out`. A comma is put before the first field
    /// only if `out` has grown past `base` (the length of `out` when the object's spec began).
    pub fn write_spec(&self, out: &mut String, base: usize) {
        if !self.active {
            sep(out, base);
            out.push_str("active=false");
        }
        let texts = [
            ("label=", self.label.as_str()),
            ("msg=", self.msg.as_str()),
            ("source=", self.source.as_str()),
            ("vsource=", self.vsource.as_str()),
            ("id=", self.id.as_str()),
        ];
        for (k, v) in texts {
            if !v.is_empty() {
                sep(out, base);
                out.push_str(k);
                out.push_str(v);
            }
        }
        let colors = [
            ("label_color=", &self.label_color),
            ("edge_color=", &self.edge_color),
            ("vertex_color=", &self.vertex_color),
            ("fill_color=", &self.fill_color),
        ];
        for (k, v) in colors {
            if let Some(c) = v {
                sep(out, base);
                out.push_str(k);
                out.push_str(c);
            }
        }
        let nums = [
            ("time=", self.time, 2),
            ("duration=", self.duration, 2),
            ("vertex_size=", self.vertex_size, 1),
            ("edge_size=", self.edge_size, 1),
            ("fill_transparency=", self.fill_transparency, 2),
        ];
        for (k, v, prec) in nums {
            if let Some(n) = v {
                sep(out, base);
                out.push_str(k);
                write_num(out, n, prec);
            }
        }
    }
}

/// Appends `pts={x,y[,z]:...}` for `pts` (nothing for an empty slice), numbers with
/// `precision` decimals, compacted. `z` is written only when non-zero.
pub fn write_points(out: &mut String, pts: &[Point], precision: usize) {
    write_points_dyn(out, pts, &|_| "", precision.min(6));
}

fn write_points_dyn<'a>(
    out: &mut String,
    pts: &[Point],
    props: &dyn Fn(usize) -> &'a str,
    precision: usize,
) {
    if pts.is_empty() {
        return;
    }
    out.push_str("pts={");
    for (i, p) in pts.iter().enumerate() {
        if i > 0 {
            out.push(':');
        }
        write_num(out, p.x, precision);
        out.push(',');
        write_num(out, p.y, precision);
        let prop = props(i);
        if p.z != 0.0 || !prop.is_empty() {
            out.push(',');
            write_num(out, p.z, precision);
        }
        if !prop.is_empty() {
            out.push(',');
            out.push_str(prop);
        }
    }
    out.push('}');
}

// ---------------------------------------------------------------------------------------------
// VIEW_POINT

/// A `VIEW_POINT`: a point plus display attributes.
///
/// ```
/// use geometry::{Attributes, Point, ViewPoint};
/// let mut vp = ViewPoint::new(Point::new(10.0, -20.5));
/// vp.attrs.label = "abe's nextpt".into();
/// vp.attrs.vertex_color = Some("yellow".into());
/// vp.attrs.vertex_size = Some(5.0);
/// assert_eq!(vp.to_spec(), "x=10,y=-20.5,label=abe's nextpt,vertex_color=yellow,vertex_size=5");
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ViewPoint {
    /// The position.
    pub point: Point,
    /// Point transparency in `[0, 1]` (0 = not written).
    pub trans: f64,
    /// Display attributes.
    pub attrs: Attributes,
    /// Decimals for x, y, z (MOOS default 2, at most 6).
    pub precision: usize,
}

impl ViewPoint {
    /// A point with default attributes and 2-decimal precision.
    pub fn new(point: Point) -> Self {
        ViewPoint {
            point,
            trans: 0.0,
            attrs: Attributes::default(),
            precision: 2,
        }
    }

    /// Appends the spec to `out`: `x=..,y=..[,z=..][,trans=..][,<attributes>]`.
    pub fn spec(&self, out: &mut String) {
        let base = out.len();
        let prec = self.precision.min(6);
        out.push_str("x=");
        write_num(out, self.point.x, prec);
        out.push_str(",y=");
        write_num(out, self.point.y, prec);
        if self.point.z != 0.0 {
            out.push_str(",z=");
            write_num(out, self.point.z, prec);
        }
        if self.trans != 0.0 {
            out.push_str(",trans=");
            write_num(out, self.trans, 2);
        }
        self.attrs.write_spec(out, base);
    }

    /// The spec as a new string.
    pub fn to_spec(&self) -> String {
        let mut s = String::new();
        self.spec(&mut s);
        s
    }

    /// Appends the erase form `x=0,y=0,active=false[,label=<label>]`.
    ///
    /// ```
    /// let mut s = String::new();
    /// geometry::ViewPoint::erase_spec("abe's nextpt", &mut s);
    /// assert_eq!(s, "x=0,y=0,active=false,label=abe's nextpt");
    /// ```
    pub fn erase_spec(label: &str, out: &mut String) {
        out.push_str("x=0,y=0,active=false");
        if !label.is_empty() {
            out.push_str(",label=");
            out.push_str(label);
        }
    }
}

impl std::str::FromStr for ViewPoint {
    type Err = ParseError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_point(s)
    }
}

/// Parses a point (MOOS `string2Point`):
/// - standard `x=..,y=..[,z=..][,trans=..][,shiftx=..][,shifty=..][,shiftz=..][,<attributes>]`,
///   keys in any order; `heading`/`hdg` are accepted and ignored, unknown keys ignored;
/// - abbreviated `x,y[,z]`, optionally with `:`-separated `key,value` pieces
///   (`4,5:label,foo:source,bravo`) — the form used by `point =` and `station_pt =`.
///
/// MOOS's standard parser sets `z` from the *x* text (a bug: `double dz = atof(x)`); here `z`
/// is read from `z=`, so specs written by [`ViewPoint::spec`] read back unchanged.
///
/// ```
/// let p = geometry::spec::parse_point("x=15, y=0").unwrap();
/// assert_eq!((p.point.x, p.point.y), (15.0, 0.0));
/// assert_eq!(geometry::spec::parse_point("20,-20").unwrap().point.y, -20.0);
/// ```
pub fn parse_point(s: &str) -> Result<ViewPoint, ParseError> {
    let t = s.trim();
    if t.is_empty() {
        return Err(ParseError::Empty);
    }
    let mut vp = ViewPoint::new(Point::default());
    if !t.contains('=') {
        let mut found = false;
        for piece in t.split(':') {
            let (param, value) = bite(piece, ',');
            if vp.attrs.set(&lower(param), value)? {
                continue;
            }
            let (ys, zs) = bite(value, ',');
            let bad = || ParseError::BadVertex(piece.trim().into());
            vp.point.x = number(param).ok_or_else(bad)?;
            vp.point.y = number(ys).ok_or_else(bad)?;
            vp.point.z = if zs.is_empty() {
                0.0
            } else {
                number(zs).ok_or_else(bad)?
            };
            found = true;
        }
        return if found {
            Ok(vp)
        } else {
            Err(ParseError::NoVertices(t.into()))
        };
    }
    let (mut x, mut y) = (None, None);
    let (mut sx, mut sy, mut sz) = (0.0, 0.0, 0.0);
    for piece in split_top(t, ',').filter(|p| !p.is_empty()) {
        let (k, v) = split_kv(piece);
        let k = lower(k);
        match k.as_ref() {
            "x" => x = Some(need_number("x", v)?),
            "y" => y = Some(need_number("y", v)?),
            "z" => vp.point.z = need_number("z", v)?,
            "shiftx" => sx = need_number("shiftx", v)?,
            "shifty" => sy = need_number("shifty", v)?,
            "shiftz" => sz = need_number("shiftz", v)?,
            "trans" => vp.trans = need_number("trans", v)?.clamp(0.0, 1.0),
            "heading" | "hdg" => {}
            other => {
                vp.attrs.set(other, v)?;
            }
        }
    }
    vp.point.x = x.ok_or(ParseError::Missing {
        key: "x",
        format: "point",
    })? + sx;
    vp.point.y = y.ok_or(ParseError::Missing {
        key: "y",
        format: "point",
    })? + sy;
    vp.point.z += sz;
    Ok(vp)
}

// ---------------------------------------------------------------------------------------------
// VIEW_SEGLIST

/// A `VIEW_SEGLIST` (or a parsed `points =` value): a seglist plus display attributes.
///
/// ```
/// let v = geometry::spec::parse_seglist("pts={60,-40:60,-160:150,-160},label=survey").unwrap();
/// assert_eq!(v.seglist.len(), 3);
/// assert_eq!(v.to_spec(), "pts={60,-40:60,-160:150,-160},label=survey");
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct ViewSegList {
    /// The vertices.
    pub seglist: SegList,
    /// Display attributes.
    pub attrs: Attributes,
    /// Decimals for vertices (MOOS default 1, at most 6; the waypoint behaviour posts 3).
    pub precision: usize,
}

impl ViewSegList {
    /// A seglist with default attributes and 1-decimal precision.
    pub fn new(seglist: SegList) -> Self {
        ViewSegList {
            seglist,
            attrs: Attributes::default(),
            precision: 1,
        }
    }

    /// An inactive, empty seglist that erases the one with `label` (`active=false,label=..`).
    pub fn erase(label: &str) -> Self {
        let mut v = ViewSegList::new(SegList::new());
        v.attrs.active = false;
        v.attrs.label = label.to_string();
        v
    }

    /// Appends the spec: `pts={x,y:...}[,<attributes>]`.
    pub fn spec(&self, out: &mut String) {
        let base = out.len();
        let sl = &self.seglist;
        write_points_dyn(out, sl.points(), &|i| sl.prop(i), self.precision.min(6));
        self.attrs.write_spec(out, base);
    }

    /// The spec as a new string.
    pub fn to_spec(&self) -> String {
        let mut s = String::new();
        self.spec(&mut s);
        s
    }
}

impl std::str::FromStr for ViewSegList {
    type Err = ParseError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_seglist(s)
    }
}

/// The value of the first `format=` key, if any.
fn format_value(s: &str) -> Option<String> {
    split_top(s, ',').find_map(|p| {
        let (k, v) = split_kv(p);
        k.eq_ignore_ascii_case("format").then(|| v.to_string())
    })
}

/// Parses a seglist in any form MOOS-IvP's `string2SegList` accepts, tried in MOOS's order:
///
/// 1. standard `pts={x,y[,z][,prop]:...}` with comma-separated `key=value` pairs (vertices may
///    also be written `x=1,y=2`);
/// 2. `format=lawnmower` / `format=bowtie` (see [`crate::pattern`]); `format=zigzag` is
///    rejected as MOOS rejects it;
/// 3. `zigzag:` and `lawnmower:` prefixes;
/// 4. a `key=value` list without points: accepted only as an erase (`active=false`);
/// 5. abbreviated `x1,y1:x2,y2[:x3,y3,z3]`, with optional `pts:`/`points:` prefix and
///    `label,foo` style pieces.
pub fn parse_seglist(s: &str) -> Result<ViewSegList, ParseError> {
    let t = s.trim();
    if t.is_empty() {
        return Err(ParseError::Empty);
    }
    let nw = remove_white(t);
    if nw.contains("pts={") {
        return standard_seglist(t);
    }
    if nw.contains("format=") {
        let mut v = ViewSegList::new(SegList::new());
        if nw.contains("format=zigzag") {
            return Err(ParseError::Unsupported(
                "format=zigzag with key=value pairs (MOOS-IvP only accepts `zigzag: x,y,angle,length,period,amplitude[,snap]`)",
            ));
        } else if nw.contains("format=lawnmower") {
            let m = Lawnmower::parse(t, &mut v.attrs)?;
            v.seglist = seglist_of(m.vertices()?);
        } else if nw.contains("format=bowtie") {
            let b = Bowtie::parse(t, &mut v.attrs)?;
            v.seglist = seglist_of(b.vertices());
        } else {
            return Err(ParseError::UnknownFormat {
                kind: "seglist",
                found: format_value(t).unwrap_or_default(),
                expected: "lawnmower, bowtie (polygon formats are read by parse_polygon / parse_waypoints)",
            });
        }
        return Ok(v);
    }
    if let Some(rest) = t.strip_prefix("zigzag:") {
        return Ok(ViewSegList::new(seglist_of(
            ZigZag::parse(rest)?.vertices()?,
        )));
    }
    if let Some(rest) = t.strip_prefix("lawnmower:") {
        let mut v = ViewSegList::new(SegList::new());
        let m = Lawnmower::parse(rest, &mut v.attrs)?;
        v.seglist = seglist_of(m.vertices()?);
        return Ok(v);
    }
    if t.contains('=') {
        // A key=value list without points: only meaningful as an erase.
        let v = standard_seglist(t)?;
        return if v.seglist.is_empty() && v.attrs.active {
            Err(ParseError::NoVertices(t.into()))
        } else {
            Ok(v)
        };
    }
    abbreviated(t).map(|(pts, attrs)| ViewSegList {
        seglist: SegList::from_points(pts),
        attrs,
        precision: 1,
    })
}

/// One `x,y[,z][,prop]` vertex of a `pts={...}` group.
fn standard_vertex(v: &str) -> Result<(Point, String), ParseError> {
    let mut it = v.trim().split(',').map(str::trim);
    let xs = it.next().unwrap_or("");
    let ys = it.next().unwrap_or("");
    let zs = it.next().unwrap_or("");
    let ps = it.next().unwrap_or("");
    let xs = xs.strip_prefix("x=").unwrap_or(xs);
    let ys = ys.strip_prefix("y=").unwrap_or(ys);
    let zs = zs.strip_prefix("z=").unwrap_or(zs);
    let (Some(x), Some(y)) = (number(xs), number(ys)) else {
        return Err(ParseError::BadVertex(v.trim().into()));
    };
    let mut prop = String::new();
    let z = match number(zs) {
        Some(z) => z,
        None => {
            prop.push_str(zs);
            0.0
        }
    };
    if !ps.is_empty() {
        if !prop.is_empty() {
            prop.push(',');
        }
        prop.push_str(ps);
    }
    Ok((Point::new_3d(x, y, z), prop))
}

/// The standard form, walked exactly as MOOS does: bite `key` up to `=`; `pts` takes up to `}`,
/// other keys take up to the next `,`.
fn standard_walk(
    t: &str,
    mut on_vertex: impl FnMut(Point, String),
    attrs: &mut Attributes,
) -> Result<(), ParseError> {
    let mut rest = t.trim();
    while !rest.is_empty() {
        let (left, r) = bite(rest, '=');
        rest = r;
        if left == "pts" {
            let (group, r2) = bite(rest, '}');
            let Some(inner) = group.strip_prefix('{') else {
                return Err(ParseError::BadPointGroup(group.into()));
            };
            rest = r2;
            if !rest.is_empty() {
                match rest.strip_prefix(',') {
                    Some(r3) => rest = r3.trim(),
                    None => return Err(ParseError::BadPointGroup(rest.into())),
                }
            }
            for v in inner.split(':') {
                let (p, prop) = standard_vertex(v)?;
                on_vertex(p, prop);
            }
        } else if left == "tags" && rest.starts_with('{') {
            // Edge tags (`tags={0:1:lane#...}`) are not modelled: skip the whole group.
            let (_, r2) = bite(rest, '}');
            rest = r2.strip_prefix(',').unwrap_or(r2).trim();
        } else {
            let (right, r2) = bite(rest, ',');
            rest = r2;
            attrs.set(&lower(left), right)?;
        }
    }
    Ok(())
}

fn standard_seglist(t: &str) -> Result<ViewSegList, ParseError> {
    let mut v = ViewSegList::new(SegList::new());
    let mut sl = SegList::new();
    standard_walk(t, |p, prop| sl.push_with_prop(p, prop), &mut v.attrs)?;
    v.seglist = sl;
    Ok(v)
}

/// Abbreviated `x,y:x,y:...` with `key,value` pieces.
fn abbreviated(t: &str) -> Result<(Vec<Point>, Attributes), ParseError> {
    let mut t = t;
    if let Some(r) = t.strip_prefix("pts:") {
        t = r;
    }
    if let Some(r) = t.strip_prefix("points:") {
        t = r;
    }
    let mut attrs = Attributes::default();
    let mut pts = Vec::new();
    for piece in t.split(':') {
        let (left, rest) = bite(piece, ',');
        if attrs.set(&lower(left), rest)? {
            continue;
        }
        let (ys, zs) = bite(rest, ',');
        let bad = || ParseError::BadVertex(piece.trim().into());
        let x = number(left).ok_or_else(bad)?;
        let y = number(ys).ok_or_else(bad)?;
        let z = if zs.is_empty() {
            0.0
        } else {
            number(zs).ok_or_else(bad)?
        };
        pts.push(Point::new_3d(x, y, z));
    }
    Ok((pts, attrs))
}

// ---------------------------------------------------------------------------------------------
// VIEW_POLYGON

/// A `VIEW_POLYGON` (or a parsed `polygon =` value): a polygon plus display attributes.
#[derive(Debug, Clone, PartialEq)]
pub struct ViewPolygon {
    /// The shape.
    pub polygon: Polygon,
    /// Display attributes.
    pub attrs: Attributes,
    /// Decimals for vertices (MOOS default 1, at most 6).
    pub precision: usize,
}

impl ViewPolygon {
    /// A polygon with default attributes and 1-decimal precision.
    pub fn new(polygon: Polygon) -> Self {
        ViewPolygon {
            polygon,
            attrs: Attributes::default(),
            precision: 1,
        }
    }

    /// An inactive, empty polygon that erases the one with `label` (`active=false,label=..`).
    pub fn erase(label: &str) -> Self {
        let mut v = ViewPolygon::new(Polygon::default());
        v.attrs.active = false;
        v.attrs.label = label.to_string();
        v
    }

    /// Appends the spec: `pts={x,y:...}[,<attributes>]`.
    pub fn spec(&self, out: &mut String) {
        let base = out.len();
        write_points_dyn(out, self.polygon.vertices(), &|_| "", self.precision.min(6));
        self.attrs.write_spec(out, base);
    }

    /// The spec as a new string.
    pub fn to_spec(&self) -> String {
        let mut s = String::new();
        self.spec(&mut s);
        s
    }
}

impl std::str::FromStr for ViewPolygon {
    type Err = ParseError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_polygon(s)
    }
}

/// Parses a polygon in any form MOOS-IvP's `string2Poly` accepts, in MOOS's order:
///
/// 1. standard `pts={...}` — must be convex ([`ParseError::NotConvex`] otherwise); a
///    points-less `label=..,active=false` gives an empty inactive polygon (erase);
/// 2. `format=radial|ellipse|wedge|piewedge|rangewedge|pylon|oval` with `key=value` pairs;
/// 3. prefixes `radial::` (key=value), `radial:` (positional `x,y,radius,pts[,snap[,label]]`),
///    `ellipse::`, `ellipse:`, `wedge:`, `piewedge:`, `rangewedge:`, `pylon:`, `oval:`;
/// 4. abbreviated `x,y:x,y:...` with `label,foo` pieces — *no* convexity gate, as in MOOS.
///
/// Generated shapes other than the oval must be convex. An unknown key in a generated form is
/// an error (MOOS returns a null polygon).
pub fn parse_polygon(s: &str) -> Result<ViewPolygon, ParseError> {
    let t = s.trim();
    if t.is_empty() {
        return Err(ParseError::Empty);
    }
    let nw = remove_white(t);
    if nw.contains("pts={") {
        let mut v = ViewPolygon::new(Polygon::default());
        let mut pts = Vec::new();
        standard_walk(t, |p, _| pts.push(p), &mut v.attrs)?;
        if pts.is_empty() {
            return if v.attrs.active {
                Err(ParseError::NoVertices(t.into()))
            } else {
                Ok(v)
            };
        }
        v.polygon = Polygon::convex(pts)?;
        return Ok(v);
    }
    let mut v = ViewPolygon::new(Polygon::default());
    if nw.contains("format=") {
        let f = format_value(t).unwrap_or_default();
        v.polygon = match lower(&f).as_ref() {
            "radial" => Radial::parse(t, &mut v.attrs)?.polygon()?,
            "ellipse" => Ellipse::parse(t, &mut v.attrs)?.polygon()?,
            "wedge" | "piewedge" => Wedge::parse(t, &mut v.attrs)?.polygon()?,
            "rangewedge" => RangeWedge::parse(t, &mut v.attrs)?.polygon()?,
            "pylon" => Pylon::parse(t, &mut v.attrs)?.polygon()?,
            "oval" => Oval::parse(t, &mut v.attrs)?.polygon()?,
            _ => {
                return Err(ParseError::UnknownFormat {
                    kind: "polygon",
                    found: f,
                    expected: "radial, ellipse, wedge, piewedge, rangewedge, pylon, oval",
                });
            }
        };
        return Ok(v);
    }
    type Gen = fn(&str, &mut Attributes) -> Result<Polygon, ParseError>;
    let prefixes: [(&str, Gen); 9] = [
        ("radial::", |r, a| Radial::parse(r, a)?.polygon()),
        ("radial:", |r, a| Radial::parse_positional(r, a)?.polygon()),
        ("ellipse::", |r, a| Ellipse::parse(r, a)?.polygon()),
        ("ellipse:", |r, a| Ellipse::parse(r, a)?.polygon()),
        ("wedge:", |r, a| Wedge::parse(r, a)?.polygon()),
        ("piewedge:", |r, a| Wedge::parse(r, a)?.polygon()),
        ("rangewedge:", |r, a| RangeWedge::parse(r, a)?.polygon()),
        ("pylon:", |r, a| Pylon::parse(r, a)?.polygon()),
        ("oval:", |r, a| Oval::parse(r, a)?.polygon()),
    ];
    for (prefix, generate) in prefixes {
        if let Some(rest) = t.strip_prefix(prefix) {
            v.polygon = generate(rest, &mut v.attrs)?;
            return Ok(v);
        }
    }
    if t.contains('=') {
        let mut pts = Vec::new();
        standard_walk(t, |p, _| pts.push(p), &mut v.attrs)?;
        return if v.attrs.active {
            Err(ParseError::NoVertices(t.into()))
        } else {
            Ok(v)
        };
    }
    let (pts, attrs) = abbreviated(t)?;
    Ok(ViewPolygon {
        polygon: Polygon::new(pts),
        attrs,
        precision: 1,
    })
}

/// Parses a `BHV_Waypoint` `points =` / `polygon =` value: as a seglist, or, if that fails, as
/// a polygon exported as a seglist that keeps the polygon's order but starts at the vertex
/// nearest the vehicle at `(osx, osy)` (MOOS `BHV_Waypoint` + `XYPolygon::exportSegList`).
///
/// ```
/// let v = geometry::spec::parse_waypoints("format=radial, x=0, y=0, radius=10, pts=4", 10.0, -10.0).unwrap();
/// // Radial vertices run clockwise from bearing 45; the one nearest (10,-10) is at bearing 135.
/// assert!(v.seglist.points()[0].x > 0.0 && v.seglist.points()[0].y < 0.0);
/// ```
pub fn parse_waypoints(s: &str, osx: f64, osy: f64) -> Result<ViewSegList, ParseError> {
    match parse_seglist(s) {
        Ok(v) => Ok(v),
        Err(seg_err) => match parse_polygon(s) {
            Ok(p) => Ok(ViewSegList {
                seglist: p.polygon.export_seglist(osx, osy),
                attrs: p.attrs,
                precision: p.precision,
            }),
            Err(poly_err) => Err(if matches!(seg_err, ParseError::UnknownFormat { .. }) {
                poly_err
            } else {
                seg_err
            }),
        },
    }
}
