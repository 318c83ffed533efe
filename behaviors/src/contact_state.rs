//! The relative geometry of ownship and a contact over the last iterations (MOOS-IvP
//! `ContactState` / `ContactStateSet` at a2a9b716): what the contact behaviours' event
//! `cnflag`s (`@cpa`, `@os_passed_cn`, ...) and relative-geometry macros (`$[ROC]`,
//! `$[OS_CN_REL_BNG]`, `$[OS_FORE_OF_CN]`, ...) read.
//!
//! The C++ archives a state at each `updatePlatformInfo`, which its contact behaviours call
//! twice per running iteration (`onEveryState`, then `onRunState`), so its five history
//! entries hold each of the last iterations twice; coug's behaviours update once per
//! iteration, and the history here keeps the last three iterations, the same span.
//!
//! ```
//! use behaviors::contact_state::{ContactState, ContactStates};
//! let mut s = ContactStates::default();
//! // Ownship at the origin heading north at 2 m/s; a contact 100 m north heading south.
//! s.record(ContactState::new((0.0, 0.0, 0.0, 2.0), (0.0, 100.0, 180.0, 2.0)));
//! let mut v = String::new();
//! assert!(s.macro_value("ROC", &mut v));
//! assert_eq!(v, "4");
//! ```

use std::collections::VecDeque;

use moos_types::fmt::compact;

use crate::cpa::{CpaEngine, rel_bearing};

/// The geometry of one update (MOOS `ContactState`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ContactState {
    /// Range, m.
    pub range: f64,
    /// Ownship is ahead of the contact's beam.
    pub os_fore_of_cn: bool,
    /// Ownship is behind the contact's beam.
    pub os_aft_of_cn: bool,
    /// Ownship is on the contact's port side.
    pub os_port_of_cn: bool,
    /// Ownship is on the contact's starboard side.
    pub os_star_of_cn: bool,
    /// The contact is ahead of ownship's beam.
    pub cn_fore_of_os: bool,
    /// The contact is behind ownship's beam.
    pub cn_aft_of_os: bool,
    /// The contact is on ownship's port side.
    pub cn_port_of_os: bool,
    /// The contact is on ownship's starboard side.
    pub cn_star_of_os: bool,
    /// The contact's speed toward ownship's position, m/s.
    pub cn_spd_in_os_pos: f64,
    /// The contact's bearing relative to ownship's heading, degrees.
    pub os_cn_rel_bng: f64,
    /// Ownship's bearing relative to the contact's heading (the target angle), degrees.
    pub cn_os_rel_bng: f64,
    /// Rate of closure, m/s.
    pub rate_of_closure: f64,
    /// Bearing rate, degrees per second.
    pub bearing_rate: f64,
}

/// Whether `(px, py)` is on the side of `(x, y, h)` that `rel` bearings select (MOOS
/// `ptForeOfOwnship` and its siblings): never for the same point.
fn side(x: f64, y: f64, h: f64, px: f64, py: f64, rel: impl Fn(f64) -> bool) -> bool {
    if x == px && y == py {
        return false;
    }
    rel(rel_bearing(x, y, h, px, py))
}

fn fore(b: f64) -> bool {
    b <= 90.0 || b >= 270.0
}
fn aft(b: f64) -> bool {
    (90.0..=270.0).contains(&b)
}
fn port(b: f64) -> bool {
    (180.0..=360.0).contains(&b)
}
fn star(b: f64) -> bool {
    (0.0..=180.0).contains(&b)
}

/// MOOS `CPXEngine::bearingRate`: the speed of both vehicles across the line of sight, as
/// degrees per second at the present range.
pub fn bearing_rate(os: (f64, f64, f64, f64), cn: (f64, f64, f64, f64)) -> f64 {
    let (osx, osy, osh, osv) = os;
    let (cnx, cny, cnh, cnv) = cn;
    let tangent = geometry::angle_360(geometry::relative_angle(osx, osy, cnx, cny) - 90.0);
    let across = |h: f64, v: f64| {
        let mut d = h - tangent;
        if d > 180.0 {
            d -= 360.0;
        } else if d < -180.0 {
            d += 360.0;
        }
        let d = d.abs();
        if d != 90.0 {
            d.to_radians().cos() * v
        } else {
            0.0
        }
    };
    let spd = across(osh, -osv) + across(geometry::angle_360(cnh), cnv.max(0.0));
    let range = (osx - cnx).hypot(osy - cny);
    spd * (-360.0 / (2.0 * range * std::f64::consts::PI))
}

impl ContactState {
    /// The state of ownship `(x, y, heading, speed)` and contact `(x, y, heading, speed)`
    /// (MOOS `IvPContactBehavior::updatePlatformInfo`, part 3).
    pub fn new(os: (f64, f64, f64, f64), cn: (f64, f64, f64, f64)) -> Self {
        let (osx, osy, osh, osv) = os;
        let (cnx, cny, cnh, cnv) = cn;
        let (osh, cnh) = (geometry::angle_360(osh), geometry::angle_360(cnh));
        let engine = CpaEngine::new(cnx, cny, cnh, cnv, osx, osy);
        ContactState {
            range: (osx - cnx).hypot(osy - cny),
            os_fore_of_cn: side(cnx, cny, cnh, osx, osy, fore),
            os_aft_of_cn: side(cnx, cny, cnh, osx, osy, aft),
            os_port_of_cn: side(cnx, cny, cnh, osx, osy, port),
            os_star_of_cn: side(cnx, cny, cnh, osx, osy, star),
            cn_fore_of_os: side(osx, osy, osh, cnx, cny, fore),
            cn_aft_of_os: side(osx, osy, osh, cnx, cny, aft),
            cn_port_of_os: side(osx, osy, osh, cnx, cny, port),
            cn_star_of_os: side(osx, osy, osh, cnx, cny, star),
            cn_spd_in_os_pos: engine.cn_speed_toward_os(),
            os_cn_rel_bng: rel_bearing(osx, osy, osh, cnx, cny),
            cn_os_rel_bng: rel_bearing(cnx, cny, cnh, osx, osy),
            rate_of_closure: engine.eval_roc(osh, osv),
            bearing_rate: bearing_rate((osx, osy, osh, osv), (cnx, cny, cnh, cnv)),
        }
    }
}

/// The present state and the last iterations' (MOOS `ContactStateSet`).
#[derive(Debug, Clone, Default)]
pub struct ContactStates {
    curr: Option<ContactState>,
    /// Most recent first.
    hist: VecDeque<ContactState>,
}

/// Iterations kept in the history.
const HISTORY: usize = 3;

/// The range margin of `@cpa` (MOOS `cpa_reached`'s default threshold), m.
const CPA_THRESH: f64 = 0.05;

impl ContactStates {
    /// Records this iteration's state, the previous one going into the history.
    pub fn record(&mut self, s: ContactState) {
        if let Some(c) = self.curr.replace(s) {
            self.hist.push_front(c);
            self.hist.truncate(HISTORY);
        }
    }

    /// The present state (default before any update).
    pub fn now(&self) -> ContactState {
        self.curr.unwrap_or_default()
    }

    /// The previous iteration's state (the present one without history, as the C++).
    fn prev(&self) -> ContactState {
        self.hist.front().copied().unwrap_or_else(|| self.now())
    }

    /// The closest point of approach has just been passed: the range fell (within 5 cm) over
    /// the history and now rose by at least 5 cm (MOOS `cpa_reached`).
    pub fn cpa_reached(&self) -> bool {
        let Some(c) = self.curr else {
            return false;
        };
        let Some(h0) = self.hist.front() else {
            return false;
        };
        let falling = self
            .hist
            .iter()
            .zip(self.hist.iter().skip(1))
            .all(|(newer, older)| newer.range <= older.range + CPA_THRESH);
        falling && c.range >= h0.range + CPA_THRESH
    }

    /// The range fell to `t` or below this iteration (MOOS `rng_entered`).
    pub fn rng_entered(&self, t: f64) -> bool {
        self.now().range <= t && self.prev().range > t
    }

    /// The range rose to `t` or above this iteration (MOOS `rng_exited`).
    pub fn rng_exited(&self, t: f64) -> bool {
        self.now().range >= t && self.prev().range < t
    }

    /// Whether the contact event of `tag` happened this iteration: `@cpa`,
    /// `@os_passed_cn[_port|_star]` (ownship crossed the contact's beam line, on its port or
    /// starboard side), `@cn_passed_os[_port|_star]`. Other tags never (the C++ at
    /// a2a9b716 accepts the `@*crossed*` tags and never posts them).
    pub fn event(&self, tag: &str) -> bool {
        let (n, p) = (self.now(), self.prev());
        let os_passed = n.os_aft_of_cn != p.os_aft_of_cn;
        let cn_passed = n.cn_aft_of_os != p.cn_aft_of_os;
        match tag {
            "@cpa" => self.cpa_reached(),
            "@os_passed_cn" => os_passed,
            "@os_passed_cn_port" => os_passed && n.os_port_of_cn,
            "@os_passed_cn_star" => os_passed && n.os_star_of_cn,
            "@cn_passed_os" => cn_passed,
            "@cn_passed_os_port" => cn_passed && n.cn_port_of_os,
            "@cn_passed_os_star" => cn_passed && n.cn_star_of_os,
            _ => false,
        }
    }

    /// Appends a relative-geometry macro's value (MOOS `cnMacroExpand`): `ROC`,
    /// `OS_CN_REL_BNG`, `CN_OS_REL_BNG`, `BNG_RATE`, `CN_SPD_IN_OS_POS` (1 decimal) and the
    /// booleans `OS_FORE_OF_CN`, `OS_AFT_OF_CN`, `OS_PORT_OF_CN`, `OS_STAR_OF_CN`,
    /// `CN_FORE_OF_OS`, `CN_AFT_OF_OS`, `CN_PORT_OF_OS`, `CN_STAR_OF_OS`; false for others.
    pub fn macro_value(&self, name: &str, out: &mut String) -> bool {
        let s = self.now();
        let b = |out: &mut String, v: bool| out.push_str(if v { "true" } else { "false" });
        match name {
            "ROC" => compact(out, s.rate_of_closure, 1),
            "OS_CN_REL_BNG" => compact(out, s.os_cn_rel_bng, 1),
            "CN_OS_REL_BNG" => compact(out, s.cn_os_rel_bng, 1),
            "BNG_RATE" => compact(out, s.bearing_rate, 1),
            "CN_SPD_IN_OS_POS" => compact(out, s.cn_spd_in_os_pos, 1),
            "OS_FORE_OF_CN" => b(out, s.os_fore_of_cn),
            "OS_AFT_OF_CN" => b(out, s.os_aft_of_cn),
            "OS_PORT_OF_CN" => b(out, s.os_port_of_cn),
            "OS_STAR_OF_CN" => b(out, s.os_star_of_cn),
            "CN_FORE_OF_OS" => b(out, s.cn_fore_of_os),
            "CN_AFT_OF_OS" => b(out, s.cn_aft_of_os),
            "CN_PORT_OF_OS" => b(out, s.cn_port_of_os),
            "CN_STAR_OF_OS" => b(out, s.cn_star_of_os),
            _ => return false,
        }
        true
    }
}
