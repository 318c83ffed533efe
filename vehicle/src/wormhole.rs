//! uSimMarineV22's wormholes (MOOS-IvP a2a9b716 `WormHole`, `WormHoleSet`): a vehicle that
//! enters the entry polygon of a wormhole fades out for half the tunnel time (10 s in all),
//! is moved to the same offset from the centroid of the exit polygon, and fades back in.
//!
//! Each wormhole has a tag and two convex polygons, "madrid" and "weber", a connection
//! (`from_madrid`, the default, `from_weber`, or `both`, which as in the C++ never
//! transports), and `delay` / `id_change` settings that are kept but, as in the C++, unused.
//! While a transit is under way [`WormHoleSet::transparency`] goes 1 → 0 (fading) and
//! 0 → 1 (emerging); the simulator posts it as `<prefix>_TRANSP`.

use geometry::spec::{ViewPolygon, parse_polygon};
use geometry::{Point, Polygon, Segment, project_point, relative_angle};

/// Why a `wormhole =` value was rejected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum WormHoleError {
    /// No `tag=` in the spec.
    #[error("a wormhole needs tag=<name>")]
    NoTag,
    /// A polygon that does not parse or is not convex.
    #[error("{0} must be a convex polygon")]
    BadPolygon(&'static str),
    /// `connection` other than both, from_madrid, from_weber.
    #[error("connection must be both, from_madrid or from_weber")]
    BadConnection,
    /// `delay` not a non-negative number.
    #[error("delay must be a non-negative number")]
    BadDelay,
    /// `id_change` not a boolean.
    #[error("id_change must be true or false")]
    BadIdChange,
    /// A key the wormhole does not know.
    #[error("unknown wormhole field `{0}`")]
    UnknownField(String),
}

/// Which way a wormhole carries a vehicle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Connection {
    /// Enter the madrid polygon, come out of the weber one (the default).
    FromMadrid,
    /// Enter the weber polygon, come out of the madrid one.
    FromWeber,
    /// Accepted, but (as in the C++) never used for an entry.
    Both,
}

/// One wormhole.
#[derive(Debug, Clone, PartialEq)]
pub struct WormHole {
    /// Its tag (lower case).
    pub tag: String,
    /// The madrid polygon, with its display attributes.
    pub madrid: Option<ViewPolygon>,
    /// The weber polygon, with its display attributes.
    pub weber: Option<ViewPolygon>,
    /// The connection.
    pub connection: Connection,
    /// `delay`, seconds (kept, unused as in the C++).
    pub delay_s: f64,
    /// `id_change` (kept, unused as in the C++).
    pub id_change: bool,
}

impl WormHole {
    fn new(tag: &str) -> Self {
        WormHole {
            tag: tag.to_string(),
            madrid: None,
            weber: None,
            connection: Connection::FromMadrid,
            delay_s: 0.0,
            id_change: true,
        }
    }

    /// The polygons to draw: weber first, then madrid (each when set).
    pub fn polygons(&self) -> impl Iterator<Item = &ViewPolygon> {
        self.weber.iter().chain(self.madrid.iter())
    }
}

/// Where a wormhole transit stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    Normal,
    Fading,
    Emerging,
}

/// The wormholes of one simulator and the state of a transit.
#[derive(Debug, Clone, PartialEq)]
pub struct WormHoleSet {
    holes: Vec<WormHole>,
    /// Seconds a transit takes (10): half fading out, half emerging.
    pub tunnel_time_s: f64,
    phase: Phase,
    phase_time: f64,
    transparency: f64,
    entry: Point,
    active_tag: String,
}

impl Default for WormHoleSet {
    fn default() -> Self {
        WormHoleSet {
            holes: Vec::new(),
            tunnel_time_s: 10.0,
            phase: Phase::Normal,
            phase_time: 0.0,
            transparency: 1.0,
            entry: Point::default(),
            active_tag: String::new(),
        }
    }
}

/// Splits on commas outside braces (MOOS `parseStringZ(str, ',', "{")`).
fn split_outside_braces(s: &str) -> Vec<&str> {
    let mut parts = Vec::new();
    let (mut depth, mut start) = (0usize, 0usize);
    for (i, c) in s.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth = depth.saturating_sub(1),
            ',' if depth == 0 => {
                parts.push(&s[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&s[start..]);
    parts
}

fn wormhole_polygon(
    value: &str,
    label: String,
    what: &'static str,
) -> Result<ViewPolygon, WormHoleError> {
    let v = value.trim();
    let spec = if v.starts_with('{') && v.ends_with('}') && v.len() >= 2 {
        v[1..v.len() - 1].to_string()
    } else if v.starts_with("pts=") {
        v.to_string()
    } else {
        format!("pts={{{v}}}")
    };
    let mut poly = parse_polygon(&spec).map_err(|_| WormHoleError::BadPolygon(what))?;
    if !poly.polygon.is_convex() {
        return Err(WormHoleError::BadPolygon(what));
    }
    poly.attrs.label = label;
    poly.attrs.fill_color = Some("white".into());
    poly.attrs.label_color = Some("invisible".into());
    poly.attrs.fill_transparency = Some(0.1);
    poly.attrs.edge_color = Some("invisible".into());
    poly.attrs.vertex_color = Some("invisible".into());
    Ok(poly)
}

/// The point of `poly`'s boundary where the ray from its bounding-box centre towards
/// `(x, y)` leaves it (MOOS `closest_point_on_poly`).
fn boundary_towards(poly: &Polygon, x: f64, y: f64) -> Option<Point> {
    let c = poly.center();
    let mut s = Point::new(x, y);
    if poly.contains(x, y) {
        let ang = relative_angle(c.x, c.y, x, y);
        s = project_point(c.x, c.y, ang, 2.0 * poly.max_radius());
    }
    let probe = Segment::new(c, s);
    poly.edges().find_map(|e| probe.intersection(&e))
}

impl WormHoleSet {
    /// True when no wormhole is configured.
    pub fn is_empty(&self) -> bool {
        self.holes.is_empty()
    }

    /// How many wormholes are configured.
    pub fn len(&self) -> usize {
        self.holes.len()
    }

    /// The wormholes, in configuration order.
    pub fn holes(&self) -> &[WormHole] {
        &self.holes
    }

    /// The fade (1 visible, 0 in the tunnel).
    pub fn transparency(&self) -> f64 {
        self.transparency
    }

    /// Adds or updates a wormhole from `tag=..,madrid_poly=..,weber_poly=..,connection=..,
    /// delay=..,id_change=..` (MOOS `addWormHoleConfig`). As in the C++, a new tag is
    /// registered before its fields are checked, and a bad field leaves the wormhole as it was.
    pub fn add_config(&mut self, spec: &str) -> Result<(), WormHoleError> {
        let parts = split_outside_braces(spec);
        let tag = parts
            .iter()
            .filter_map(|p| p.split_once('='))
            .find(|(k, _)| k.trim() == "tag")
            .map(|(_, v)| v.trim().to_ascii_lowercase())
            .filter(|t| !t.is_empty())
            .ok_or(WormHoleError::NoTag)?;
        let ix = match self.holes.iter().position(|h| h.tag == tag) {
            Some(ix) => ix,
            None => {
                self.holes.push(WormHole::new(&tag));
                self.holes.len() - 1
            }
        };
        let mut hole = self.holes[ix].clone();
        for part in parts {
            let (key, value) = match part.split_once('=') {
                Some((k, v)) => (k.trim(), v.trim()),
                None => (part.trim(), ""),
            };
            match key {
                "madrid_poly" => {
                    hole.madrid = Some(wormhole_polygon(
                        value,
                        format!("{tag}_madrid"),
                        "madrid_poly",
                    )?)
                }
                "weber_poly" => {
                    hole.weber = Some(wormhole_polygon(
                        value,
                        format!("{tag}_weber"),
                        "weber_poly",
                    )?)
                }
                "connection" => {
                    hole.connection = match value.to_ascii_lowercase().as_str() {
                        "both" => Connection::Both,
                        "from_madrid" => Connection::FromMadrid,
                        "from_weber" => Connection::FromWeber,
                        _ => return Err(WormHoleError::BadConnection),
                    }
                }
                "delay" => match crate::config::parse_number(value) {
                    Some(d) if d >= 0.0 => hole.delay_s = d,
                    _ => return Err(WormHoleError::BadDelay),
                },
                "id_change" => {
                    hole.id_change = match value.to_ascii_lowercase().as_str() {
                        "true" => true,
                        "false" => false,
                        _ => return Err(WormHoleError::BadIdChange),
                    }
                }
                "tag" => {}
                other => return Err(WormHoleError::UnknownField(other.to_string())),
            }
        }
        self.holes[ix] = hole;
        Ok(())
    }

    fn entry_at(&self, x: f64, y: f64) -> Option<&WormHole> {
        self.holes.iter().find(|h| {
            let entry = match h.connection {
                Connection::FromWeber => &h.weber,
                Connection::FromMadrid => &h.madrid,
                Connection::Both => &None,
            };
            entry.as_ref().is_some_and(|p| p.polygon.contains(x, y))
        })
    }

    /// One simulator iteration at `now` with the vehicle at `(x, y)`: advances a transit and
    /// returns the new position when the vehicle is carried through (MOOS `apply`).
    pub fn apply(&mut self, now: f64, x: f64, y: f64) -> Option<Point> {
        let half = self.tunnel_time_s / 2.0;
        if self.phase == Phase::Emerging {
            let dt = now - self.phase_time;
            if dt > half {
                self.phase = Phase::Normal;
                self.phase_time = now;
                self.transparency = 1.0;
            } else {
                self.transparency = dt / half;
            }
            return None;
        }
        if self.phase == Phase::Normal {
            let tag = self.entry_at(x, y)?.tag.clone();
            self.phase = Phase::Fading;
            self.phase_time = now;
            self.active_tag = tag;
            self.entry = Point::new(x, y);
        }
        let dt = now - self.phase_time;
        if dt < half {
            self.transparency = 1.0 - dt / half;
            return None;
        }
        self.phase = Phase::Emerging;
        self.phase_time = now;
        self.transparency = 0.0;
        let hole = self.holes.iter().find(|h| h.tag == self.active_tag)?;
        let (from, to) = match hole.connection {
            Connection::FromWeber => (&hole.weber, &hole.madrid),
            Connection::FromMadrid => (&hole.madrid, &hole.weber),
            Connection::Both => return None,
        };
        let (Some(from), Some(to)) = (from, to) else {
            // The C++ leaves the position as it was.
            return Some(Point::new(x, y));
        };
        Some(cross_position(&from.polygon, &to.polygon, self.entry))
    }
}

/// The point at the same bearing and range from `to`'s vertex centroid as `p` is from
/// `from`'s, pulled onto `to`'s boundary if it falls outside (MOOS `getCrossPosition`).
fn cross_position(from: &Polygon, to: &Polygon, p: Point) -> Point {
    let ca = vertex_centroid(from);
    let cb = vertex_centroid(to);
    let range = (p.x - ca.x).hypot(p.y - ca.y);
    let ang = relative_angle(ca.x, ca.y, p.x, p.y);
    let q = project_point(cb.x, cb.y, ang, range);
    if to.contains(q.x, q.y) {
        return q;
    }
    boundary_towards(to, q.x, q.y).unwrap_or(q)
}

/// The mean of the vertices (MOOS `get_centroid_x/y`, not the area centroid).
fn vertex_centroid(p: &Polygon) -> Point {
    let v = p.vertices();
    if v.is_empty() {
        return Point::default();
    }
    let n = v.len() as f64;
    Point::new(
        v.iter().map(|p| p.x).sum::<f64>() / n,
        v.iter().map(|p| p.y).sum::<f64>() / n,
    )
}
