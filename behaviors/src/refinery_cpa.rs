//! The CPA refinery of the contact behaviours with `use_refinery = true` (MOOS-IvP
//! `RefineryCPA` at a2a9b716, used by BHV_AvoidCollision and BHV_AvdColregsV19/V22/V26's
//! catch-all CPA function): from the pair's geometry and a few dozen CPA queries it finds
//! regions of course × speed where every point's CPA distance is at least
//! `max_util_cpa_dist`, so the CPA utility is flat there at its maximum. The reflector takes
//! them as plateau regions ([`ivp::Reflector::plateau_region`]): cut out of the uniform
//! pieces, each one piece of its own.
//!
//! # The logic cases
//!
//! `max_util_cpa_dist` is first lowered to the range when the contact is closer, and
//! `θ = asin(max_util_cpa_dist / range)` (degrees) is the half-width of the cone of bearings
//! toward the contact that would bring it within that distance. The case
//! ([`RefineryCpa::logic_case`], posted as `PLATEAU_LOGIC_CASE`) follows from where
//! ownship is:
//!
//! - `aft` (ownship abaft the contact's beam): nothing when the contact closes on ownship's
//!   position; else all courses below the speed at which ownship could catch up (the
//!   contact's opening speed plus the range to close over the time on leg, one grid step
//!   lower), and the courses from the passing side (the contact's heading, or with ownship
//!   within `max_util_cpa_dist` of its track the last clear course from `bearing ∓ θ`) to
//!   the crossing side (`bearing ± θ` searched outward), above that speed;
//! - `fore_out_rgam` (ahead of the beam, farther than `max_util_cpa_dist` from the contact's
//!   track): the courses on the passing side clear at every speed (the crossing course
//!   searched from `bearing ± θ` at top speed, the passing course from the contact's heading
//!   tightened down to the largest speed clear over that whole span), all courses below that
//!   speed, and the "shadow" wedges at 2/3 and 1/3 of the way from the contact's speed to the
//!   top speed and the wedge ahead of the cone at 1/3 of the way to the contact's speed;
//! - `fore_in_rgam` (ahead of the beam within `max_util_cpa_dist` of its track): the courses
//!   from the first clear course either side of the contact's reciprocal heading at the
//!   largest of the speeds clear abeam to port, to starboard and fleeing (the contact's
//!   speed), or with ownship clear at rest at `range / time_on_leg − contact speed`, above
//!   that speed; and the wedges to port and starboard a quarter of the way from the abeam
//!   speed to the fleeing speed.
//!
//! The searches step over the domain's grid (MOOS `IvPDomain` snapping: floor, ceiling,
//! nearest with ties down) and each CPA evaluation is counted ([`RefineryCpa::cpa_queries`]).
//! Boxes are made as MOOS `buildBoxHdgAll` (all courses, speeds snapped inward) and
//! `buildBoxesHdgSpd` (courses and speeds snapped inward, a course span through north as two
//! boxes, a span between two grid points as the one nearest its middle); `buildBoxesSpdAll`
//! is [`ivp::boxes_all_speeds`]. The search failures' −1 and −2 flow into the boxes as the
//! C++ lets them (snapped to course 0). The C++'s unreachable parts (its `Part D` of the
//! in-cone case, `getFleeSpeed`, `getMinSpdAtHdg`) are not written; where its speed loops
//! could never end (a grid value that does not move), the search ends there.
//!
//! # Conformance with RefineryCPA (MOOS-IvP a2a9b716)
//!
//! | part | C++ | coug |
//! |---|---|---|
//! | `init` sanity | fails on a negative distance or time on leg, min > max, no course or speed | done (`None`) |
//! | max lowered to the range, `θ` | `asin(max/range)` | done |
//! | cases `aft`, `fore_out_rgam`, `fore_in_rgam` | by `foreOfContact`, then range gamma < max | done |
//! | the sweeps (`getMax/MinFirst/LastSatHdgAtSpd`, `getMaxSpdAtHdg`, `getMinSpdClockwise/CounterClock`, `getPassHdgClockwise/CounterClock`) | grid walks, their −1/−2 returns | done |
//! | CPA query count | `getTotalQueriesCPA` | done |
//! | `setQuit1/2/3` | test switches, off in the behaviours | not written |

use std::cell::Cell;

use geometry::{angle_360, relative_angle};
use ivp::{Domain, DomainVar, IvpFunction, Reflector, RegionBox, Snap, boxes_all_speeds};

use crate::behavior::{Out, PostKey};
use crate::colregs::geometry::Cpx;

/// What the refinery reads of the pair (MOOS `CPXEngine`'s static part): positions, the
/// contact's motion, the range, the range to the contact's track line (gamma), the sides and
/// the bearing to the contact.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PairGeometry {
    /// Ownship x, m.
    pub osx: f64,
    /// Ownship y, m.
    pub osy: f64,
    /// Contact x, m.
    pub cnx: f64,
    /// Contact y, m.
    pub cny: f64,
    /// Contact heading, degrees.
    pub cnh: f64,
    /// Contact speed, m/s.
    pub cnv: f64,
    /// Range, m.
    pub range: f64,
    /// Distance from ownship to the contact's bow-stern line, m.
    pub range_gamma: f64,
    /// Ownship is fore of the contact's beam.
    pub os_fore_of_cn: bool,
    /// Ownship is on the contact's port side.
    pub os_port_of_cn: bool,
    /// Ownship is on the contact's starboard side.
    pub os_star_of_cn: bool,
    /// Absolute bearing from ownship to the contact, degrees.
    pub os_cn_abs_bng: f64,
    /// The contact's speed toward ownship's position, m/s.
    pub cn_spd_in_os_pos: f64,
}

impl PairGeometry {
    /// The geometry of a pair (ownship to contact).
    pub fn of(cpx: &Cpx) -> Self {
        let (osx, osy, _, _) = cpx.os;
        let (cnx, cny, cnh, cnv) = cpx.cn;
        PairGeometry {
            osx,
            osy,
            cnx,
            cny,
            cnh,
            cnv,
            range: cpx.range,
            range_gamma: cpx.range_gam,
            os_fore_of_cn: cpx.fore,
            os_port_of_cn: cpx.port,
            os_star_of_cn: cpx.star,
            os_cn_abs_bng: cpx.abs_bng_os_cn,
            cn_spd_in_os_pos: cpx.cn_to_os_spd,
        }
    }
}

/// MOOS `angleMinContains`: of the two angles, the low one if `c` lies between them, else
/// the high one.
fn angle_min_contains(a: f64, b: f64, c: f64) -> f64 {
    if a == b {
        return a;
    }
    let (lo, hi) = if a > b { (b, a) } else { (a, b) };
    if c >= lo && c <= hi { lo } else { hi }
}

/// MOOS `angleMaxContains`.
fn angle_max_contains(a: f64, b: f64, c: f64) -> f64 {
    if a == b {
        return a;
    }
    let (lo, hi) = if a > b { (b, a) } else { (a, b) };
    if c >= lo && c <= hi { hi } else { lo }
}

/// MOOS `IvPDomain` snap types: 0 floor, 1 ceiling, 2 nearest.
fn snap(kind: u8) -> Snap {
    match kind {
        0 => Snap::Floor,
        1 => Snap::Ceil,
        _ => Snap::Nearest,
    }
}

/// MOOS `getSnappedVal`.
fn snapped(v: &DomainVar, val: f64, kind: u8) -> f64 {
    v.value(v.index(val, snap(kind)))
}

/// MOOS `getNextLowerVal`.
fn next_lower(v: &DomainVar, val: f64, kind: u8, wrap: bool) -> f64 {
    match v.index(val, snap(kind)) {
        0 if wrap => v.high(),
        0 => val,
        j => v.value(j - 1),
    }
}

/// MOOS `getNextHigherVal`.
fn next_higher(v: &DomainVar, val: f64, kind: u8, wrap: bool) -> f64 {
    let j = v.index(val, snap(kind));
    if j + 1 >= v.points() {
        if wrap { v.low() } else { val }
    } else {
        v.value(j + 1)
    }
}

/// The refinery for one pair and one CPA function (MOOS `RefineryCPA`).
///
/// `cpa(course, speed, time_on_leg)` is the CPA engine's evaluation (the behaviour's own
/// engine: the holonomic ray or its platform model's turn).
pub struct RefineryCpa<F> {
    domain: Domain,
    ci: usize,
    si: usize,
    g: PairGeometry,
    ostol: f64,
    max_ucd: f64,
    theta_delta: f64,
    cpa: F,
    queries: Cell<u32>,
    logic_case: &'static str,
}

impl<F: Fn(f64, f64, f64) -> f64> RefineryCpa<F> {
    /// MOOS `init`: `None` when a distance or the time on leg is negative, `min_ucd >
    /// max_ucd`, or the domain lacks `course` or `speed`.
    pub fn new(
        domain: &Domain,
        g: PairGeometry,
        ostol: f64,
        min_ucd: f64,
        max_ucd: f64,
        cpa: F,
    ) -> Option<Self> {
        if min_ucd < 0.0 || max_ucd < 0.0 || ostol < 0.0 || min_ucd > max_ucd {
            return None;
        }
        let ci = domain.index_of("course")?;
        let si = domain.index_of("speed")?;
        let max_ucd = max_ucd.min(g.range);
        let theta_delta = if max_ucd > 0.0 && g.range > 0.0 {
            (max_ucd / g.range).asin().to_degrees()
        } else {
            0.0
        };
        Some(RefineryCpa {
            domain: domain.clone(),
            ci,
            si,
            g,
            ostol,
            max_ucd,
            theta_delta,
            cpa,
            queries: Cell::new(0),
            logic_case: "",
        })
    }

    /// The CPA evaluations made so far (MOOS `getTotalQueriesCPA`).
    pub fn cpa_queries(&self) -> u32 {
        self.queries.get()
    }

    /// The case the last [`RefineryCpa::regions`] took (MOOS `getLogicCase`): `aft`,
    /// `fore_in_rgam`, `fore_out_rgam`; empty before.
    pub fn logic_case(&self) -> &'static str {
        self.logic_case
    }

    /// `θ`, degrees.
    pub fn theta_delta(&self) -> f64 {
        self.theta_delta
    }

    /// The plateau regions (MOOS `getRefineRegions`), in grid indices of the domain given,
    /// in the C++'s order; their plateau values are 0 (the reflector sets them).
    pub fn regions(&mut self) -> Vec<RegionBox> {
        if self.g.os_fore_of_cn {
            if self.g.range_gamma < self.max_ucd {
                self.logic_case = "fore_in_rgam";
                self.fore_in_rgam()
            } else {
                self.logic_case = "fore_out_rgam";
                self.fore_out_rgam()
            }
        } else {
            self.logic_case = "aft";
            self.aft()
        }
    }

    fn crs(&self) -> &DomainVar {
        &self.domain.vars()[self.ci]
    }

    fn spd(&self) -> &DomainVar {
        &self.domain.vars()[self.si]
    }

    fn eval(&self, hdg: f64, spd: f64) -> f64 {
        self.queries.set(self.queries.get() + 1);
        (self.cpa)(hdg, spd, self.ostol)
    }

    fn clear(&self, hdg: f64, spd: f64) -> bool {
        self.eval(hdg, spd) >= self.max_ucd
    }

    /// A box of the domain's full extent with the given course and speed index spans.
    fn make_box(&self, c: (u32, u32), s: (u32, u32)) -> RegionBox {
        let mut lo = vec![0; self.domain.len()];
        let mut hi: Vec<u32> = self.domain.vars().iter().map(|v| v.points() - 1).collect();
        (lo[self.ci], hi[self.ci]) = c;
        (lo[self.si], hi[self.si]) = s;
        RegionBox { lo, hi, plat: 0 }
    }

    /// The speed index span of `[smin, smax]` snapped inward (MOOS's box builders).
    fn spd_span(&self, smin: f64, smax: f64) -> (u32, u32) {
        let s = self.spd();
        let (lo, hi) = (s.index(smin, Snap::Ceil), s.index(smax, Snap::Floor));
        if lo > hi {
            let mid = s.index((smin + smax) / 2.0, Snap::Nearest);
            (mid, mid)
        } else {
            (lo, hi)
        }
    }

    /// MOOS `buildBoxHdgAll`: every course, speeds `smin..smax` snapped inward; `None` when
    /// `smin > smax`.
    fn hdg_all(&self, smin: f64, smax: f64) -> Option<RegionBox> {
        (smin <= smax)
            .then(|| self.make_box((0, self.crs().points() - 1), self.spd_span(smin, smax)))
    }

    /// MOOS `buildBoxesHdgSpd`.
    fn hdg_spd(&self, hmin: f64, hmax: f64, smin: f64, smax: f64) -> Vec<RegionBox> {
        let c = self.crs();
        let s = self.spd_span(smin, smax);
        let (mut lo, mut hi) = (c.index(hmin, Snap::Ceil), c.index(hmax, Snap::Floor));
        let mid = || c.index((hmin + hmax) / 2.0, Snap::Nearest);
        if hmin <= hmax {
            if lo > hi {
                lo = mid();
                hi = lo;
            }
            return vec![self.make_box((lo, hi), s)];
        }
        if hi > lo {
            lo = mid();
            hi = lo;
        }
        vec![
            self.make_box((0, hi), s),
            self.make_box((lo, c.points() - 1), s),
        ]
    }

    fn push_all(&self, out: &mut Vec<RegionBox>, boxes: Vec<RegionBox>) {
        out.extend(boxes);
    }

    fn valid_hdg(&self, h: f64) -> bool {
        h >= self.crs().low() && h <= self.crs().high()
    }

    fn valid_spd(&self, s: f64) -> bool {
        s >= self.spd().low() && s <= self.spd().high()
    }

    /// MOOS `getHdgSnappedHgh`.
    fn hdg_snapped_high(&self, h: f64) -> f64 {
        if h > self.crs().high() {
            0.0
        } else {
            snapped(self.crs(), h, 1)
        }
    }

    /// The course index `steps` grid points clockwise (or counter-clockwise) of `first`.
    fn crs_at(&self, first: u32, steps: u32, clockwise: bool) -> f64 {
        let n = self.crs().points();
        let ix = if clockwise {
            (first + steps) % n
        } else {
            (first + n - steps % n) % n
        };
        self.crs().value(ix)
    }

    /// MOOS `getMaxSpdAtHdg`: the largest speed from the top down whose CPA is clear, before
    /// the first that is not; −1 when the top speed is not.
    fn max_spd_at_hdg(&self, hdg: f64) -> f64 {
        let s = self.spd();
        let mut found = -1.0;
        for i in (0..s.points()).rev() {
            let spd = s.value(i);
            if self.clear(hdg, spd) {
                found = spd;
            } else {
                return found;
            }
        }
        found
    }

    /// Common sanity of the heading sweeps: a positive speed, a course within the domain.
    fn sweep_ok(&self, spd: f64, h: f64) -> bool {
        spd > 0.0 && h >= self.crs().low() && h <= self.crs().high()
    }

    /// MOOS `getMinFirstSatHdgAtSpd`: clockwise from `hmin` (snapped up), the first clear
    /// course; −1 if none.
    fn min_first_sat(&self, spd: f64, hmin: f64) -> f64 {
        if !self.sweep_ok(spd, hmin) {
            return -1.0;
        }
        let first = self.crs().index(hmin, Snap::Ceil);
        for i in 0..self.crs().points() {
            let hdg = self.crs_at(first, i, true);
            if self.clear(hdg, spd) {
                return hdg;
            }
        }
        -1.0
    }

    /// MOOS `getMaxFirstSatHdgAtSpd`: counter-clockwise from `hmax` (nearest), the first
    /// clear course; −1 if none.
    fn max_first_sat(&self, spd: f64, hmax: f64) -> f64 {
        if !self.sweep_ok(spd, hmax) {
            return -1.0;
        }
        let first = self.crs().index(hmax, Snap::Nearest);
        for i in 0..self.crs().points() {
            let hdg = self.crs_at(first, i, false);
            if self.clear(hdg, spd) {
                return hdg;
            }
        }
        -1.0
    }

    /// MOOS `getMinLastSatHdgAtSpd`: counter-clockwise from `hmax` (nearest), the last
    /// course before the first that is not clear (`hmax` itself if that first one is); −2
    /// when every course is clear, −1 on a bad speed or course.
    fn min_last_sat(&self, spd: f64, hmax: f64) -> f64 {
        if !self.sweep_ok(spd, hmax) {
            return -1.0;
        }
        let first = self.crs().index(hmax, Snap::Nearest);
        let mut prev = hmax;
        for i in 0..self.crs().points() {
            let hdg = self.crs_at(first, i, false);
            if !self.clear(hdg, spd) {
                return prev;
            }
            prev = hdg;
        }
        -2.0
    }

    /// MOOS `getMaxLastSatHdgAtSpd`: as [`Self::min_last_sat`] clockwise from `hmin` (a
    /// course between 359 and 360 taken as 359).
    fn max_last_sat(&self, spd: f64, hmin: f64) -> f64 {
        if spd <= 0.0 || hmin < self.crs().low() {
            return -1.0;
        }
        let hmin = if hmin > 359.0 && hmin < 360.0 {
            359.0
        } else {
            hmin
        };
        if hmin > self.crs().high() {
            return -1.0;
        }
        let first = self.crs().index(hmin, Snap::Nearest);
        let mut prev = hmin;
        for i in 0..self.crs().points() {
            let hdg = self.crs_at(first, i, true);
            if !self.clear(hdg, spd) {
                return prev;
            }
            prev = hdg;
        }
        -2.0
    }

    /// MOOS `getHdgDiscPts` with snap 1: the grid courses from `hmin` clockwise to `hmax`,
    /// rounded up.
    fn hdg_disc_pts(&self, hmin: f64, hmax: f64) -> u32 {
        let delta = self.crs().delta();
        if delta <= 0.0 {
            return 0;
        }
        let range = if hmin <= hmax {
            hmax - hmin
        } else {
            (360.0 - hmin) + hmax
        };
        let dcount = 1.0 + range / delta;
        let count = dcount as u32;
        if f64::from(count) != dcount {
            count + 1
        } else {
            count
        }
    }

    /// MOOS `getMinSpdClockwise` (`clockwise`, from `hmin`) and `getMinSpdCounterClock`
    /// (from `hmax`): sweeping the span, the speed is lowered a grid step at a time at each
    /// course that is not clear until it is; the speed left (the domain's lowest or 0 ends
    /// the sweep); −1 on a bad course or speed.
    fn min_spd_sweep(&self, hmin: f64, hmax: f64, start: f64, clockwise: bool) -> f64 {
        if !self.valid_hdg(hmin) || !self.valid_hdg(hmax) || !self.valid_spd(start) {
            return -1.0;
        }
        let pts = self.hdg_disc_pts(hmin, hmax);
        let from = if clockwise { hmin } else { hmax };
        let first = self.crs().index(from, Snap::Nearest);
        let low = self.spd().low();
        let mut curr = start;
        for i in 0..pts {
            let hdg = self.crs_at(first, i, clockwise);
            if !self.clear(hdg, curr) {
                loop {
                    let next = next_lower(self.spd(), curr, 0, false);
                    let stuck = next == curr;
                    curr = next;
                    if curr == 0.0 || curr == low || stuck {
                        return curr;
                    }
                    if self.clear(hdg, curr) {
                        break;
                    }
                }
            }
        }
        curr
    }

    /// MOOS `getPassHdgClockwise` (`clockwise`) and `getPassHdgCounterClock`: from the last
    /// clear course at `start` speed swept from `hdg`, back the other way until a course is
    /// clear at every speed down to `end` (each course's speed moved down while clear, up
    /// while not); `hdg` itself when the first sweep fails or nothing is found.
    fn pass_hdg(&self, hdg0: f64, start: f64, end: f64, clockwise: bool) -> f64 {
        if !self.valid_hdg(hdg0) || !self.valid_spd(start) {
            return -1.0;
        }
        let hdgx = if clockwise {
            self.max_last_sat(start, hdg0)
        } else {
            self.min_last_sat(start, hdg0)
        };
        if hdgx < 0.0 {
            return hdg0;
        }
        let first = self.crs().index(hdgx, Snap::Nearest);
        let mut curr = start;
        for i in 0..self.crs().points() {
            let hdg = self.crs_at(first, i, !clockwise);
            if self.clear(hdg, curr) {
                let mut prev = curr;
                loop {
                    let next = next_lower(self.spd(), curr, 0, false);
                    let stuck = next == curr;
                    curr = next;
                    if curr == 0.0 || curr <= end || stuck {
                        return hdg;
                    }
                    if !self.clear(hdg, curr) {
                        curr = prev;
                        break;
                    }
                    prev = curr;
                }
            } else {
                loop {
                    let next = next_higher(self.spd(), curr, 0, false);
                    if next == curr {
                        break;
                    }
                    curr = next;
                    if self.clear(hdg, curr) {
                        break;
                    }
                }
            }
        }
        hdg0
    }

    /// MOOS `getRefineRegionsAft`.
    fn aft(&self) -> Vec<RegionBox> {
        let g = self.g;
        let cn_to_os = angle_360(relative_angle(g.osx, g.osy, g.cnx, g.cny) + 180.0);
        let mut regions = Vec::new();
        if g.cn_spd_in_os_pos > 0.0 {
            return regions;
        }
        let max_spd = self.spd().high();
        // Part A: every course below the speed that would catch up.
        let range_to_close = g.range - self.max_ucd;
        let mut inner = -g.cn_spd_in_os_pos;
        if range_to_close > 0.0 && self.ostol > 0.0 {
            inner += range_to_close / self.ostol;
        }
        let inner = next_lower(self.spd(), inner, 0, false);
        if inner > 0.0 {
            regions.extend(self.hdg_all(0.0, inner));
        }
        // Part B: the courses between the passing side and the crossing side.
        let mut pass = g.cnh;
        let mut cross = if g.os_star_of_cn {
            next_lower(
                self.crs(),
                angle_360(g.os_cn_abs_bng - self.theta_delta),
                1,
                true,
            )
        } else {
            next_higher(
                self.crs(),
                angle_360(g.os_cn_abs_bng + self.theta_delta),
                0,
                true,
            )
        };
        if g.range_gamma < self.max_ucd {
            pass = if g.os_star_of_cn {
                self.min_last_sat(max_spd, angle_360(g.os_cn_abs_bng + self.theta_delta))
            } else {
                self.max_last_sat(max_spd, angle_360(g.os_cn_abs_bng - self.theta_delta))
            };
        }
        cross = if g.os_star_of_cn {
            self.max_last_sat(max_spd, cross)
        } else {
            self.min_last_sat(max_spd, cross)
        };
        let min_hdg = angle_min_contains(pass, cross, cn_to_os);
        let max_hdg = angle_max_contains(pass, cross, cn_to_os);
        let inner_next = next_higher(self.spd(), inner, 1, false);
        self.push_all(
            &mut regions,
            self.hdg_spd(min_hdg, max_hdg, inner_next, max_spd),
        );
        regions
    }

    /// MOOS `getRefineRegionsForeOutRGam`.
    fn fore_out_rgam(&self) -> Vec<RegionBox> {
        let g = self.g;
        let star = g.os_star_of_cn;
        let (crs, spd) = (self.crs(), self.spd());
        let max_spd = spd.high();
        let mut regions = Vec::new();
        // Part A: the crossing course, tight at top speed.
        let mut pass = g.cnh;
        let cross = if star {
            let c = snapped(crs, angle_360(g.os_cn_abs_bng - self.theta_delta), 0);
            self.max_last_sat(max_spd, c)
        } else {
            let c = self.hdg_snapped_high(angle_360(g.os_cn_abs_bng + self.theta_delta));
            self.min_last_sat(max_spd, c)
        };
        let (mut min_hdg, mut max_hdg) = if star { (pass, cross) } else { (cross, pass) };
        if cross == -2.0 {
            // Every course clear at top speed: one region of everything.
            regions.extend(self.hdg_all(0.0, max_spd));
            return regions;
        }
        // Part B: every course below the speed clear over the whole span.
        let max_inner = self.min_spd_sweep(max_hdg, min_hdg, max_spd, star);
        if max_inner > spd.low() {
            regions.extend(self.hdg_all(0.0, max_inner));
        }
        // Part C: the passing course tightened, the span at every speed.
        pass = self.pass_hdg(pass, max_spd, max_inner, !star);
        if star {
            (min_hdg, max_hdg) = (pass, cross);
        } else {
            (min_hdg, max_hdg) = (cross, pass);
        }
        regions.extend(boxes_all_speeds(&self.domain, min_hdg, max_hdg));
        // Part D: the shadow beyond the cone.
        let cnv_up = snapped(spd, g.cnv, 1);
        let mut do_shadows = cnv_up < max_spd;
        let mut mid1 = snapped(spd, ((max_spd - cnv_up) * 2.0) / 3.0 + cnv_up, 1);
        let mut mid2 = snapped(spd, (max_spd - cnv_up) / 3.0 + cnv_up, 1);
        let midx = next_lower(spd, mid1, 2, false);
        if mid1 > max_spd {
            mid1 = max_spd;
        }
        if mid2 < cnv_up {
            mid2 = cnv_up;
        }
        if mid1 <= mid2 {
            do_shadows = false;
        }
        if do_shadows {
            if star {
                let h1 = self.min_last_sat(mid1, min_hdg);
                regions.extend(self.hdg_spd(h1, min_hdg, mid1, max_spd));
                let h2 = self.min_last_sat(mid2, min_hdg);
                regions.extend(self.hdg_spd(h2, min_hdg, mid2, midx));
            } else {
                let h1 = self.max_last_sat(mid1, max_hdg);
                regions.extend(self.hdg_spd(max_hdg, h1, mid1, max_spd));
                let h2 = self.max_last_sat(mid2, max_hdg);
                regions.extend(self.hdg_spd(max_hdg, h2, mid2, midx));
            }
        }
        // Part E: the fore shadow, ahead of the cone.
        let fore_spdx = if max_inner > 0.0 {
            next_higher(spd, max_inner, 2, false)
        } else {
            0.0
        };
        let mut fore1 = snapped(spd, (cnv_up - max_inner) / 3.0 + max_inner, 1);
        if fore1 >= max_spd {
            fore1 = max_spd;
        }
        if fore1 > fore_spdx {
            if star {
                let max_hdg = snapped(crs, max_hdg, 0);
                let h1 = snapped(crs, self.max_last_sat(fore1, max_hdg), 0);
                regions.extend(self.hdg_spd(max_hdg, h1, fore_spdx, fore1));
            } else {
                let min_hdg = self.hdg_snapped_high(min_hdg);
                let h1 = snapped(crs, self.min_last_sat(fore1, min_hdg), 1);
                regions.extend(self.hdg_spd(h1, min_hdg, fore_spdx, fore1));
            }
        }
        regions
    }

    /// MOOS `getRefineRegionsForeInRGam`.
    fn fore_in_rgam(&self) -> Vec<RegionBox> {
        let g = self.g;
        let (crs, spd) = (self.crs(), self.spd());
        let mut regions = Vec::new();
        // Part A.
        let port_hdg = angle_360(g.cnh - 90.0);
        let star_hdg = angle_360(g.cnh + 90.0);
        let flee_hdg = angle_360(g.cnh - 180.0);
        let flee_down = snapped(crs, flee_hdg, 0);
        let flee_up = self.hdg_snapped_high(flee_hdg);
        // Part B: the initial wedge.
        let port_speed = self.max_spd_at_hdg(port_hdg);
        let star_speed = self.max_spd_at_hdg(star_hdg);
        let flee_speed = snapped(spd, g.cnv, 1);
        let mut inner = flee_speed;
        if port_speed > inner {
            inner = port_speed;
        }
        if star_speed > inner {
            inner = star_speed;
        }
        if self.eval(0.0, 0.0) >= self.max_ucd {
            if self.ostol != 0.0 {
                inner = g.range / self.ostol - g.cnv;
            }
            inner = snapped(spd, inner, 1);
        }
        let port_bnd = self.min_first_sat(inner, flee_up);
        let star_bnd = self.max_first_sat(inner, flee_down);
        let inner = next_higher(spd, inner, 0, false);
        let max_spd = spd.high();
        if port_bnd >= 0.0 && star_bnd >= 0.0 {
            regions.extend(self.hdg_spd(port_bnd, star_bnd, inner, max_spd));
        }
        // Part C: the wedges to port and starboard below that speed.
        let inner_m1 = next_lower(spd, inner, 1, false);
        if port_speed > 0.0 {
            let s = snapped(spd, (flee_speed - port_speed) / 4.0 + port_speed, 1);
            let hmin = self.min_first_sat(s, flee_up);
            let hmax = self.max_last_sat(s, hmin);
            if s < inner_m1 {
                regions.extend(self.hdg_spd(hmin, hmax, s, inner_m1));
            }
        }
        if star_speed > 0.0 {
            let s = snapped(spd, (flee_speed - star_speed) / 4.0 + star_speed, 1);
            let hmax = self.max_first_sat(s, flee_down);
            let hmin = self.min_last_sat(s, hmax);
            if s < inner_m1 {
                regions.extend(self.hdg_spd(hmin, hmax, s, inner_m1));
            }
        }
        regions
    }
}

/// The CPA of a contact behaviour's [`crate::contact_state::Distances`] at course `h`, speed
/// `s` over `t` seconds (its platform model's turn when it has one, else the engine's ray):
/// the refinery's queries, which take their own time on leg.
pub fn distances_cpa(d: &crate::contact_state::Distances, h: f64, s: f64, t: f64) -> f64 {
    match &d.pm {
        Some(pm) => pm.eval_cpa(h, s, t),
        None => d.engine.eval_cpa(h, s, t),
    }
}

/// The refinery-related parameters of a contact behaviour (`use_refinery`,
/// `check_plateaus`, `check_validity`, `pcheck_thresh`, `verbose`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefinerySettings {
    /// `use_refinery`.
    pub use_refinery: bool,
    /// `check_plateaus`.
    pub check_plateaus: bool,
    /// `check_validity`.
    pub check_validity: bool,
    /// `pcheck_thresh`.
    pub pcheck_thresh: f64,
    /// `verbose`.
    pub verbose: bool,
}

impl Default for RefinerySettings {
    fn default() -> Self {
        RefinerySettings {
            use_refinery: false,
            check_plateaus: false,
            check_validity: false,
            pcheck_thresh: ivp::DEFAULT_PCHECK_THRESH,
            verbose: false,
        }
    }
}

/// What the refined reflection found besides the function.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Refined {
    /// The plateau regions handed to the reflector (over the course × speed domain).
    pub regions: Vec<RegionBox>,
    /// The refinery's logic case.
    pub logic_case: &'static str,
    /// CPA evaluations the refinery made.
    pub cpa_queries: u32,
    /// With `check_plateaus`: the worst plateau and basin failures (0: the check holds).
    pub checks: Option<(f64, f64)>,
    /// The reflector's warnings (MOOS `getWarnings`: `pcheck_thresh` out of `[0, 1]`).
    pub warnings: String,
}

/// The course × speed domain the contact behaviours reflect over.
pub fn course_speed(domain: &Domain) -> Option<Domain> {
    let mut d = Domain::new();
    d.add(domain.get("course")?.clone()).ok()?;
    d.add(domain.get("speed")?.clone()).ok()?;
    Some(d)
}

/// The contact behaviours' reflection (3 × 3 uniform pieces over course × speed, as
/// [`crate::contact_state::reflect`]) with the refinery's plateau regions: the regions of
/// `refinery` (built over [`course_speed`]) are added as plateau regions; with
/// `settings.check_plateaus` the plateaus and basins are checked (threshold
/// `pcheck_thresh`, or the reflector's default with a warning when it is outside `[0, 1]`,
/// as MOOS `OF_Reflector::setParam`); `known` (the AOF's known minimum and maximum, MOOS
/// `minMaxKnown`) makes each plateau piece that maximum. `None` when the domain lacks
/// course or speed, or the refinery cannot start.
pub fn reflect_refined<F, G>(
    domain: &Domain,
    refinery: impl FnOnce(&Domain) -> Option<RefineryCpa<G>>,
    settings: &RefinerySettings,
    known: Option<(f64, f64)>,
    f: F,
) -> Option<(IvpFunction, Refined)>
where
    F: Fn(f64, f64) -> f64,
    G: Fn(f64, f64, f64) -> f64,
{
    let d = course_speed(domain)?;
    let mut r = Reflector::new(&d, |v: &[f64]| f(v[0], v[1]))
        .set_param("uniform_piece", "course:3,speed:3")
        .ok()?;
    let mut info = Refined::default();
    if let Some(mut rf) = refinery(&d) {
        info.regions = rf.regions();
        info.logic_case = rf.logic_case();
        info.cpa_queries = rf.cpa_queries();
    }
    for region in &info.regions {
        r = r.plateau_region(region.clone()).ok()?;
    }
    if let Some((min, max)) = known {
        r = r.known_min_max(min, max);
    }
    if settings.check_plateaus {
        let thresh = if (0.0..=1.0).contains(&settings.pcheck_thresh) {
            settings.pcheck_thresh
        } else {
            info.warnings = "pcheck_thresh value must be in range [0,1]".to_string();
            ivp::DEFAULT_PCHECK_THRESH
        };
        info.checks = Some((r.check_plateaus(thresh), r.check_basins(thresh)));
    }
    let f = r.build().ok()?;
    Some((f, info))
}

/// MOOS `PDMap::valid`: every grid point of the function's domain lies in exactly one piece.
pub fn covers_once(f: &IvpFunction) -> bool {
    let vars = f.domain().vars();
    let total = f.domain().size();
    let Ok(total) = usize::try_from(total) else {
        return false;
    };
    let mut count = vec![0u8; total];
    let mut ix = Vec::with_capacity(vars.len());
    for p in f.pieces() {
        ix.clear();
        ix.extend_from_slice(p.lo);
        loop {
            // Row-major offset, the first variable slowest.
            let mut off = 0usize;
            for (k, v) in vars.iter().enumerate() {
                off = off * v.points() as usize + ix[k] as usize;
            }
            count[off] = count[off].saturating_add(1);
            // Next point of the piece, the last variable fastest.
            let mut k = ix.len();
            let done = loop {
                if k == 0 {
                    break true;
                }
                k -= 1;
                if ix[k] < p.hi[k] {
                    ix[k] += 1;
                    break false;
                }
                ix[k] = p.lo[k];
            };
            if done {
                break;
            }
        }
    }
    count.iter().all(|&c| c == 1)
}

/// The postings of the COLREGS behaviours' `check_plateaus` (MOOS
/// `BHV_AvdColregsV19/V22/V26::buildCPA_IPF`): `PLATEAU_CHECK_OK` and `BASIN_CHECK_OK`
/// (`true`/`false`), `PLATEAU_LOGIC_CASE` (repeatable), and `PLATEAU_WORST_FAIL`
/// (repeatable, the worst difference) for each check that failed, the plateaus' first.
pub fn post_colregs_checks(info: &Refined, out: &mut Out) {
    let Some((plats, basins)) = info.checks else {
        return;
    };
    out.post("PLATEAU_CHECK_OK", bool_text(plats == 0.0));
    out.post("BASIN_CHECK_OK", bool_text(basins == 0.0));
    out.post_key("PLATEAU_LOGIC_CASE", info.logic_case, PostKey::Repeatable);
    if plats != 0.0 {
        out.post_key("PLATEAU_WORST_FAIL", plats, PostKey::Repeatable);
    }
    if basins != 0.0 {
        out.post_key("PLATEAU_WORST_FAIL", basins, PostKey::Repeatable);
    }
}

/// The postings of BHV_AvoidCollision's `check_plateaus` (MOOS
/// `BHV_AvoidCollision::getAvoidIPF`): with `verbose`, `PLATEAU_CHECK_OK` and
/// `PLATEAU_LOGIC_CASE` (repeatable); `PLATEAU_WORST_FAIL` (repeatable) when the plateau
/// check failed. It does not check basins.
pub fn post_avoid_checks(info: &Refined, verbose: bool, out: &mut Out) {
    let Some((plats, _)) = info.checks else {
        return;
    };
    if verbose {
        out.post("PLATEAU_CHECK_OK", bool_text(plats == 0.0));
        out.post_key("PLATEAU_LOGIC_CASE", info.logic_case, PostKey::Repeatable);
    }
    if plats != 0.0 {
        out.post_key("PLATEAU_WORST_FAIL", plats, PostKey::Repeatable);
    }
}

fn bool_text(b: bool) -> &'static str {
    if b { "true" } else { "false" }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cpa::CpaEngine;

    fn dom() -> Domain {
        Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap()
    }

    /// The refinery over `dom()` for ownship at `os` and the contact `cn` (x, y, heading,
    /// speed), time on leg 60 s, min 10 m, max 30 m.
    fn run(os: (f64, f64), cn: (f64, f64, f64, f64)) -> (Vec<RegionBox>, &'static str, u32) {
        let (cnx, cny, cnh, cnv) = cn;
        let cpx = Cpx::new(cnx, cny, cnh, cnv, os.0, os.1, 0.0, 0.0);
        let e = CpaEngine::new(cnx, cny, cnh, cnv, os.0, os.1);
        let mut r = RefineryCpa::new(
            &dom(),
            PairGeometry::of(&cpx),
            60.0,
            10.0,
            30.0,
            |h, s, t| e.eval_cpa(h, s, t),
        )
        .unwrap();
        let regions = r.regions();
        (regions, r.logic_case(), r.cpa_queries())
    }

    fn b(c: (u32, u32), s: (u32, u32)) -> RegionBox {
        RegionBox {
            lo: vec![c.0, s.0],
            hi: vec![c.1, s.1],
            plat: 0,
        }
    }

    /// Every point of every region has a CPA of at least `max_util_cpa_dist` (30 m): the
    /// AvoidCollision metric is flat at its known maximum there (the reflector's check).
    fn plateaus_hold(os: (f64, f64), cn: (f64, f64, f64, f64), regions: &[RegionBox]) {
        let e = CpaEngine::new(cn.0, cn.1, cn.2, cn.3, os.0, os.1);
        let mut r = Reflector::new(&dom(), |v: &[f64]| {
            crate::AvoidCollision::metric(e.eval_cpa(v[0], v[1], 60.0), 10.0, 30.0)
        });
        for g in regions {
            r = r.plateau_region(g.clone()).unwrap();
        }
        assert_eq!(r.known_min_max(0.0, 100.0).check_plateaus(0.001), 0.0);
    }

    // Each case: domain course 0:359:360 × speed 0:4:41 (0.1 m/s steps), time on leg 60 s,
    // max_util_cpa_dist 30 m. The CPA values quoted were worked by hand from the relative
    // motion (the contact's velocity less ownship's, the closest point within 60 s).

    #[test]
    fn a_stationary_contact_ahead_is_the_aft_case() {
        // Contact at (0, 100) heading north at rest; ownship at the origin, dead astern of it
        // (so on both its sides: the starboard branch runs). Range 100, θ = asin(0.3) =
        // 17.4576°.
        let (os, cn) = ((0.0, 0.0), (0.0, 100.0, 0.0, 0.0));
        let (r, case, q) = run(os, cn);
        assert_eq!(case, "aft");
        // Part A: 70 m to close in 60 s: 1.1667 m/s, one step below its floor: 1.0 m/s.
        // Part B: crossing course 342.54 (bearing 0 − θ) stepped down from its ceiling to
        // 342, clear at 4 m/s (CPA 100·sin 18° = 30.9) and 343 not (29.2): 342; passing
        // course 17.4576 (range gamma 0 < 30): course 17 fails at 4 m/s (29.2), so it stays;
        // the span holding the contact's reciprocal bearing 180 is 17.46..342, above 1.1.
        assert_eq!(r, [b((0, 359), (0, 10)), b((18, 342), (11, 40))]);
        // One query for the passing course, two for the crossing one.
        assert_eq!(q, 3);
        plateaus_hold(os, cn, &r);
    }

    #[test]
    fn overtaking_a_slower_contact_is_the_aft_case() {
        // Contact at (0, 100) heading north at 1 m/s, ownship at the origin behind it.
        let (os, cn) = ((0.0, 0.0), (0.0, 100.0, 0.0, 1.0));
        let (r, case, q) = run(os, cn);
        assert_eq!(case, "aft");
        // Part A: the contact opens at 1 m/s, plus 70 m over 60 s: 2.1667, stepped: 2.0.
        // Part B at 4 m/s: from 17 counter-clockwise 17..14 are clear (14: 31.8), 13 is not
        // (29.7); from 342 clockwise 342..346 clear (346: 31.8), 347 not (29.7).
        assert_eq!(r, [b((0, 359), (0, 20)), b((14, 346), (21, 40))]);
        assert_eq!(q, 5 + 6);
        plateaus_hold(os, cn, &r);
    }

    #[test]
    fn head_on_is_the_fore_in_cone_case() {
        // Contact at (0, 100) heading south at 1 m/s toward ownship at the origin.
        let (os, cn) = ((0.0, 0.0), (0.0, 100.0, 180.0, 1.0));
        let (r, case, q) = run(os, cn);
        assert_eq!(case, "fore_in_rgam");
        // Abeam (90 and 270) every speed down to 0 is clear (at rest the contact comes to
        // 40 m in 60 s): port and starboard speeds 0, no side wedges. Fleeing speed 1.0; at
        // rest the CPA is 40 >= 30, so the inner speed is 100/60 − 1 = 0.667, up to 0.7.
        // At 0.7 the first clear course clockwise from 0 is 43 (42: 29.4, 43: 30.1) and
        // counter-clockwise 317; the wedge 43..317 above 0.7 (from 0.8).
        assert_eq!(r, [b((43, 317), (8, 40))]);
        // 41 speeds at each beam course, the CPA at rest, 44 courses each way.
        assert_eq!(q, 41 + 41 + 1 + 44 + 44);
        plateaus_hold(os, cn, &r);
    }

    #[test]
    fn a_contact_astern_closing_is_the_fore_in_cone_case() {
        // Contact at (0, 0) heading north at 1 m/s, ownship at (0, 100) ahead of it.
        let (os, cn) = ((0.0, 100.0), (0.0, 0.0, 0.0, 1.0));
        let (r, case, q) = run(os, cn);
        assert_eq!(case, "fore_in_rgam");
        // The head-on case turned round: from 180 clockwise the first clear course at 0.7
        // is 223 (222: 29.4, 223: 30.1), counter-clockwise 137; the wedge runs through
        // north, two boxes.
        assert_eq!(r, [b((0, 137), (8, 40)), b((223, 359), (8, 40))]);
        assert_eq!(q, 171);
        plateaus_hold(os, cn, &r);
    }

    #[test]
    fn crossing_ahead_outside_the_cone_is_the_fore_out_case() {
        // Contact at (100, 100) heading west at 1 m/s; ownship at the origin, on its port
        // bow, 100 m from its track (range gamma 100 >= 30). Range 141.4, θ = 12.25°.
        let (os, cn) = ((0.0, 0.0), (100.0, 100.0, 270.0, 1.0));
        let (r, case, _) = run(os, cn);
        assert_eq!(case, "fore_out_rgam");
        // Part A: crossing course from 57.25 (bearing 45 + θ, up to 58) counter-clockwise
        // at 4 m/s: 50 clear (31.0), 49 not (29.1).
        // Part B: sweeping 50 back to 270 at falling speed, course 22 fails at 1.3 (29.7)
        // and holds at 1.2 (35.7): every course below 1.2.
        // Part C: passing course from 270 clockwise at 4 m/s ends at 20 (21: 29.2); from 20
        // back, the first course clear at every speed above 1.2 is 5 (6 fails at 1.7:
        // 29.4): courses 50..5 through south, every speed (two boxes).
        // Part D: the contact's 1.0 up to 4.0: shadow speeds 3.0 and 2.0 (below: 2.9); at
        // 3.0 from 5 clockwise the last clear is 16 (17: 28.9), at 2.0 it is 7 (8: 29.8).
        // Part E: fore speed (1.0 − 1.2)/3 + 1.2 up to 1.2, not above 1.3: no box.
        assert_eq!(
            r,
            [
                b((0, 359), (0, 12)),
                b((0, 5), (0, 40)),
                b((50, 359), (0, 40)),
                b((5, 16), (30, 40)),
                b((5, 7), (20, 29)),
            ]
        );
        plateaus_hold(os, cn, &r);
    }

    #[test]
    fn the_sanity_checks_of_init() {
        let cpx = Cpx::new(0.0, 100.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let g = PairGeometry::of(&cpx);
        let f = |_: f64, _: f64, _: f64| 0.0;
        assert!(RefineryCpa::new(&dom(), g, 60.0, 40.0, 30.0, f).is_none());
        assert!(RefineryCpa::new(&dom(), g, -1.0, 10.0, 30.0, f).is_none());
        let speed_only = Domain::parse_specs(["speed:0:4:41"]).unwrap();
        assert!(RefineryCpa::new(&speed_only, g, 60.0, 10.0, 30.0, f).is_none());
        // max_util_cpa_dist beyond the range is lowered to it: θ = 90°.
        let r = RefineryCpa::new(&dom(), g, 60.0, 10.0, 300.0, f).unwrap();
        assert_eq!(r.theta_delta(), 90.0);
    }

    #[test]
    fn coverage_is_checked_point_by_point() {
        let d = Domain::from_vars(&[("x", 0.0, 3.0, 4), ("y", 0.0, 1.0, 2)]).unwrap();
        let mut f = IvpFunction::new(d.clone());
        f.push_piece(&[0, 0], &[1, 1], &[0.0, 0.0], 1.0).unwrap();
        assert!(!covers_once(&f), "x 2..3 uncovered");
        f.push_piece(&[2, 0], &[3, 1], &[0.0, 0.0], 1.0).unwrap();
        assert!(covers_once(&f));
        f.push_piece(&[3, 1], &[3, 1], &[0.0, 0.0], 1.0).unwrap();
        assert!(!covers_once(&f), "3,1 twice");
    }
}
#[cfg(test)]
mod quirks {
    use super::*;
    use crate::cpa::CpaEngine;

    /// From the head-on lockstep encounter with the refinery (`tests/run_refinery.rs`, ben at
    /// t = 83.75): ownship abaft and to starboard of a contact heading 359.78, 32.8 m from
    /// its track (no tightening of the passing course). The passing course 359.78 snaps up
    /// past the last grid course and is clamped to 359 (MOOS `getDiscreteVal`), so the
    /// course-359 column of the wrapped box is in the plateau although it converges on the
    /// contact's track: the C++'s own `PLATEAU_WORST_FAIL`.
    #[test]
    fn a_passing_course_between_359_and_360_is_clamped_into_the_plateau() {
        let d = Domain::parse_specs(["course:0:359:360", "speed:0:4:41"]).unwrap();
        let (os, cn) = ((16.41882, 139.07823), (-16.42, 159.95, 359.78, 1.95));
        let cpx = Cpx::new(cn.0, cn.1, cn.2, cn.3, os.0, os.1, 180.0, 1.95);
        let e = CpaEngine::new(cn.0, cn.1, cn.2, cn.3, os.0, os.1);
        let g = PairGeometry::of(&cpx);
        assert!(!g.os_fore_of_cn && g.os_star_of_cn && g.range_gamma > 30.0);
        let mut r =
            RefineryCpa::new(&d, g, 120.0, 10.0, 30.0, |h, s, t| e.eval_cpa(h, s, t)).unwrap();
        let regions = r.regions();
        assert_eq!(r.logic_case(), "aft");
        let spans: Vec<_> = regions
            .iter()
            .map(|b| ((b.lo[0], b.hi[0]), (b.lo[1], b.hi[1])))
            .collect();
        // Part A: the contact opens at 1.05 m/s, plus (38.9 − 30) / 120: 1.13, stepped down
        // to 1.0; part B: the span from 359.78 clockwise to the crossing course 279 (its
        // crossing side), above 1.1 m/s, two boxes through north.
        assert_eq!(
            spans,
            [
                ((0, 359), (0, 10)),
                ((0, 279), (11, 40)),
                ((359, 359), (11, 40))
            ]
        );
        // At course 359 and 2.1 m/s the CPA is under 30 m; at course 0 it is not.
        assert!(e.eval_cpa(359.0, 2.1, 120.0) < 30.0);
        assert!(e.eval_cpa(0.0, 2.1, 120.0) >= 30.0);
    }
}
