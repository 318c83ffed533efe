//! BHV_BearingLine: draws a line from the vehicle toward a fixed point; no objective function.
//!
//! # Conformance with BHV_BearingLine (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | bearing_point | | point | 0,0 (no label) | a valid point (MOOS `string2Point`); labelled `x,y` rounded to integers | yes | done |
//! | line_pct | | % | 50 | number, clipped to [0, 100] | yes | done |
//! | show_pt | | bool | true | MOOS boolean (`setBooleanOnString`) | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | VIEW_SEGLIST | every running iteration | `pts={x,y:x2,y2},label=<ownship>_<name>`: `line_pct` % of the way to the point | done |
//! | VIEW_POINT | every running iteration | the bearing point, `active=false` unless `show_pt` | done |
//! | VIEW_SEGLIST, VIEW_POINT | idle and completed iterations | the same with `active=false` (before any run: `active=false` alone for the line) | done |
//! | BHV_WARNING | running without NAV_X or NAV_Y | `No <VAR> info in the info_buffer` (read as 0) | done |

use geometry::{Point, SegList, ViewPoint, ViewSegList};
use ivp::IvpFunction;

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::common::Common;
use crate::hs_line::num_or_warn;
use crate::param::{moos_boolean, number};

/// A line from the vehicle toward `bearing_point` (a visual aid).
#[derive(Debug, Clone)]
pub struct BearingLine {
    /// The point the line points at, with its display attributes.
    pub point: ViewPoint,
    /// How much of the distance the line covers, percent.
    pub line_pct: f64,
    /// Whether the point is drawn.
    pub show_pt: bool,
    /// The last line drawn.
    line: ViewSegList,
}

impl Default for BearingLine {
    fn default() -> Self {
        Self::new()
    }
}

impl BearingLine {
    /// The MOOS defaults (point 0,0, `line_pct` 50, `show_pt` true).
    pub fn new() -> Self {
        BearingLine {
            point: ViewPoint::new(Point::new(0.0, 0.0)),
            line_pct: 50.0,
            show_pt: true,
            line: ViewSegList::new(SegList::new()),
        }
    }
}

impl Behavior for BearingLine {
    fn kind(&self) -> &'static str {
        "BHV_BearingLine"
    }

    fn default_name(&self) -> &'static str {
        "bhv_bngline"
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_X", "NAV_Y"]);
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        match param {
            "bearing_point" => {
                let mut p = geometry::spec::parse_point(value)
                    .map_err(|_| ParamError::bad(param, value, "a point"))?;
                let mut label = String::new();
                moos_types::fmt::fixed(&mut label, p.point.x, 0);
                label.push(',');
                moos_types::fmt::fixed(&mut label, p.point.y, 0);
                p.attrs.label = label;
                self.point = p;
            }
            "line_pct" => self.line_pct = number(param, value)?.clamp(0.0, 100.0),
            "show_pt" => self.show_pt = moos_boolean(param, value, self.show_pt)?,
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn on_idle(&mut self, _ctx: &Ctx<'_>, out: &mut Out) {
        self.erase(out);
    }

    fn on_complete(&mut self, _ctx: &Ctx<'_>, out: &mut Out) {
        self.erase(out);
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let x = num_or_warn(ctx, out, "NAV_X");
        let y = num_or_warn(ctx, out, "NAV_Y");
        let (bx, by) = (self.point.point.x, self.point.point.y);
        let dist = (x - bx).hypot(y - by);
        let ang = geometry::relative_angle(x, y, bx, by);
        let len = self.line_pct / 100.0 * dist;
        // MOOS's XYPoint-returning projectPoint: plain sin/cos, no exact cardinal cases.
        let r = ang.to_radians();
        let end = Point::new(x + r.sin() * len, y + r.cos() * len);
        self.line.seglist.clear();
        self.line.seglist.push_xy(x, y);
        self.line.seglist.push(end);
        self.line.attrs.active = true;
        self.line.attrs.label = format!("{}_{}", ctx.ownship, ctx.name);
        out.post("VIEW_SEGLIST", self.line.to_spec());
        self.point.attrs.active = self.show_pt;
        out.post("VIEW_POINT", self.point.to_spec());
        None
    }
}

impl BearingLine {
    fn erase(&mut self, out: &mut Out) {
        self.line.attrs.active = false;
        out.post("VIEW_SEGLIST", self.line.to_spec());
        self.point.attrs.active = false;
        out.post("VIEW_POINT", self.point.to_spec());
    }
}
