//! XY geometry for the helm and viewer: points, segment lists, polygons, and MOOS-IvP's
//! geometry strings (point patterns, `VIEW_POINT` / `VIEW_SEGLIST` / `VIEW_POLYGON` specs).
//!
//! Conventions follow MOOS-IvP's local grid: `x` grows east, `y` grows north, and every angle
//! given to or returned by this crate is a *compass* angle in degrees (0 = north = +y, growing
//! clockwise, 90 = east).
//!
//! Modules:
//! - [`angle`]: angle normalisation, bearings, point projection.
//! - [`point`]: [`Point`] and snapping.
//! - [`segment`]: [`Segment`], distances, crossings, and the track helpers a waypoint follower needs.
//! - [`seglist`]: [`SegList`], an ordered vertex list (a waypoint path).
//! - [`polygon`]: [`Polygon`] with MOOS's convexity test, containment, distances.
//! - [`pattern`]: generators for the pattern formats (lawnmower, bowtie, zigzag, radial, ellipse,
//!   wedge, rangewedge, pylon, oval), reproducing MOOS-IvP's vertex order and snapping.
//! - [`spec`]: parsing every `points =` / `polygon =` / `point =` form and writing / reading the
//!   `VIEW_POINT`, `VIEW_SEGLIST`, `VIEW_POLYGON` strings.
//! - [`error`]: the typed [`ParseError`].
//!
//! ```
//! use geometry::spec::parse_polygon;
//! let loiter = parse_polygon("radial:: x=20, y=-80, radius=20, pts=8, snap=1, label=L").unwrap();
//! assert!(loiter.polygon.contains(20.0, -80.0));
//! assert_eq!(loiter.to_spec(), "pts={28,-62:38,-72:38,-88:28,-98:12,-98:2,-88:2,-72:12,-62},label=L");
//! ```
#![warn(missing_docs)]

pub mod angle;
pub mod color;
pub mod error;
pub mod pattern;
pub mod point;
pub mod polygon;
pub mod seglist;
pub mod segment;
pub mod spec;
mod text;
pub use text::{atof, is_number, split_unquoted};

pub use angle::{angle_180, angle_360, project_point, relative_angle};
pub use error::ParseError;
pub use point::Point;
pub use polygon::Polygon;
pub use seglist::SegList;
pub use segment::Segment;
pub use spec::{Attributes, ViewPoint, ViewPolygon, ViewSegList};
