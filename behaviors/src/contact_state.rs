//! What every contact behaviour shares about the pair it reasons about (MOOS-IvP
//! `ContactState` / `ContactStateSet` and `AOF_ContactX` at a2a9b716): the relative geometry
//! of ownship and the contact over the last iterations ([`ContactState`], filled once per
//! update by [`crate::contact::ContactBase::update`]), which the event `cnflag`s (`@cpa`,
//! `@os_passed_cn`, ...), the relative-geometry macros (`$[ROC]`, `$[OS_CN_REL_BNG]`,
//! `$[OS_FORE_OF_CN]`, ...) and the COLREGS encounter classification read; and the CPA
//! set-up of the avoidance objectives ([`Distances`]: the CPA engine, time on leg, collision
//! and all-clear distances; [`reflect`]: the 3 × 3 uniform sampling over course and speed),
//! shared by BHV_AvoidCollision and the AvdColregs family.
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

use ivp::{Domain, IvpFunction, Reflector};

use crate::colregs::geometry::Cpx;
use crate::cpa::CpaEngine;

/// The geometry of one update (MOOS `ContactState`, IvPContactBehavior's `m_cnos`): the pair
/// seen both ways, ownship to contact ([`Cpx`]) and contact to ownship
/// ([`Cpx::reversed`]), as `IvPContactBehavior::updatePlatformInfo` (part 3) fills it from
/// its two CPA engines. The one contact-state type of every contact behaviour: the event
/// flags and macros read it ([`ContactStates`]), the COLREGS behaviours classify encounters
/// with it.
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
    /// Rate of closure at ownship's present course and speed, m/s (negative: opening).
    pub rate_of_closure: f64,
    /// The contact's bearing rate seen from ownship, degrees per second (MOOS
    /// `CPXEngine::bearingRate`: the course's whole degree, the C++'s 12-digit pi).
    pub bearing_rate: f64,
    /// Ownship on its course passes the contact (crosses its beam line).
    pub os_passes_cn: bool,
    /// The contact on its course passes ownship.
    pub cn_passes_os: bool,
    /// Ownship crosses the contact's bow-stern line.
    pub os_crosses_cn: bool,
    /// Ownship crosses the contact's bow.
    pub os_crosses_cn_bow: bool,
    /// How far ahead of the contact ownship crosses, or −1.
    pub os_crosses_cn_bow_dist: f64,
    /// The contact crosses ownship's bow-stern line.
    pub cn_crosses_os: bool,
    /// How far ahead of ownship the contact crosses, or −1.
    pub cn_crosses_os_bow_dist: f64,
    /// The CPA distance if both hold course and speed for 120 s, m.
    pub os_curr_cpa_dist: f64,
}

impl ContactState {
    /// The state of ownship `(x, y, heading, speed)` and contact `(x, y, heading, speed)`.
    pub fn new(os: (f64, f64, f64, f64), cn: (f64, f64, f64, f64)) -> Self {
        let (osx, osy, osh, osv) = os;
        let (cnx, cny, cnh, cnv) = cn;
        let fwd = Cpx::new(cnx, cny, cnh, cnv, osx, osy, osh, osv);
        Self::of_pair(&fwd, &CpaEngine::new(cnx, cny, cnh, cnv, osx, osy))
    }

    /// The state of the pair `fwd` (ownship to contact) with its CPA engine.
    pub fn of_pair(fwd: &Cpx, engine: &CpaEngine) -> Self {
        let (_, _, osh, osv) = fwd.os;
        Self::of_engines(
            fwd,
            &fwd.reversed(),
            engine.eval_roc(osh, osv),
            fwd.bearing_rate(osh, osv),
            engine.eval_cpa(osh, osv, 120.0),
        )
    }

    /// The state of the pair seen both ways, `fwd` (ownship to contact) and `rev` (the
    /// contact as ownship), with what the engine in use works out at ownship's present
    /// heading and speed: the rate of closure, the bearing rate and the 120 s CPA. The sides,
    /// bearings, passing and crossing are the pairs' own (each [`Cpx`] answers along its
    /// platform model when it has one), so the OG engines ([`Self::of_pair`]) and the
    /// platform-model ones (`colregs::plat_cpx::contact_state`) fill the state alike.
    pub(crate) fn of_engines(
        fwd: &Cpx,
        rev: &Cpx,
        rate_of_closure: f64,
        bearing_rate: f64,
        os_curr_cpa_dist: f64,
    ) -> Self {
        let (_, _, osh, osv) = fwd.os;
        let (_, _, cnh, cnv) = fwd.cn;
        ContactState {
            range: fwd.range,
            os_fore_of_cn: fwd.fore,
            os_aft_of_cn: fwd.aft,
            os_port_of_cn: fwd.port,
            os_star_of_cn: fwd.star,
            cn_fore_of_os: rev.fore,
            cn_aft_of_os: rev.aft,
            cn_port_of_os: rev.port,
            cn_star_of_os: rev.star,
            cn_spd_in_os_pos: fwd.cn_to_os_spd,
            os_cn_rel_bng: fwd.rel_bng_os_cn,
            cn_os_rel_bng: fwd.rel_bng_cn_os,
            rate_of_closure,
            bearing_rate,
            os_passes_cn: fwd.passes(osh, osv),
            cn_passes_os: rev.passes(cnh, cnv),
            os_crosses_cn: fwd.crosses_bow_or_stern(osh, osv),
            os_crosses_cn_bow: fwd.crosses_bow(osh, osv),
            os_crosses_cn_bow_dist: fwd.crosses_bow_dist(osh, osv),
            cn_crosses_os: rev.crosses_bow_or_stern(cnh, cnv),
            cn_crosses_os_bow_dist: rev.crosses_bow_dist(cnh, cnv),
            os_curr_cpa_dist,
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

/// What every CPA objective shares (MOOS `AOF_ContactX`): the CPA engine of the pair, the
/// time on leg its CPA is evaluated over, and the distances below which a CPA is a collision
/// and above which it is all clear.
#[derive(Debug, Clone)]
pub struct Distances {
    /// The CPA engine (contact and ownship positions, the contact's motion).
    pub engine: CpaEngine,
    /// Time on leg, s (`tol`).
    pub tol: f64,
    /// `collision_distance`, m.
    pub collision_distance: f64,
    /// `all_clear_distance`, m.
    pub all_clear_distance: f64,
    /// V26 with a Dubins platform model: the CPA along the model's turn
    /// ([`crate::colregs::plat_cpx::PlatCpx::eval_cpa`]) instead of the engine's ray.
    pub pm: Option<crate::colregs::plat_cpx::PlatCpx>,
}

/// The collision distance of a CPA objective (the contact behaviours' `buildCPA_IPF` and
/// `onRunState`): `min_util_cpa_dist`, or half the range once the contact is within it (so
/// the function keeps a preference).
///
/// ```
/// use behaviors::contact_state::collision_distance;
/// assert_eq!(collision_distance(80.0, 10.0), 10.0);
/// assert_eq!(collision_distance(8.0, 10.0), 4.0);
/// ```
pub fn collision_distance(range: f64, min_util_cpa_dist: f64) -> f64 {
    if range <= min_util_cpa_dist {
        range / 2.0
    } else {
        min_util_cpa_dist
    }
}

impl Distances {
    /// The distances, or `None` when `collision > all_clear` (MOOS `AOF_ContactX::initialize`
    /// fails: "collision_dist > all_clear_dist").
    pub fn new(engine: CpaEngine, tol: f64, collision: f64, all_clear: f64) -> Option<Self> {
        (collision <= all_clear).then_some(Distances {
            engine,
            tol,
            collision_distance: collision,
            all_clear_distance: all_clear,
            pm: None,
        })
    }

    /// The distances with the CPA taken along ownship's platform model's turns to each
    /// course, for the contact `cn` (`x, y, heading, speed`).
    pub fn with_plat_model(
        mut self,
        model: std::sync::Arc<crate::plat_model::PlatModel>,
        cn: (f64, f64, f64, f64),
    ) -> Self {
        self.pm = Some(crate::colregs::plat_cpx::PlatCpx::new(model, cn));
        self
    }

    /// The set-up of a contact behaviour's CPA objective at its last update: its CPA engine,
    /// time on leg `tol`, [`collision_distance`] from `min_util_cpa_dist` and the all-clear
    /// distance `max_util_cpa_dist`; `None` as [`Distances::new`].
    pub fn for_contact(
        base: &crate::contact::ContactBase,
        tol: f64,
        min_util_cpa_dist: f64,
        max_util_cpa_dist: f64,
    ) -> Option<Self> {
        Self::new(
            base.cpa_engine(),
            tol,
            collision_distance(base.range, min_util_cpa_dist),
            max_util_cpa_dist,
        )
    }

    /// The CPA distance at ownship course `crs` and speed `spd` over the time on leg.
    pub fn cpa(&self, crs: f64, spd: f64) -> f64 {
        if let Some(pm) = &self.pm {
            return pm.eval_cpa(crs, spd, self.tol);
        }
        self.engine.eval_cpa(crs, spd, self.tol)
    }

    /// The CPA metric most of the COLREGS objectives use: 0 below `collision_distance`, 100
    /// above `all_clear_distance`, `25 + 75 · (d − collision) / (all_clear − collision)`
    /// between.
    pub fn metric25(&self, dist: f64) -> f64 {
        let (min, max) = (self.collision_distance, self.all_clear_distance);
        if dist < min {
            0.0
        } else if dist > max {
            100.0
        } else {
            25.0 + 75.0 * (dist - min) / (max - min)
        }
    }
}

/// Samples `f(course, speed)` over the course and speed variables of `domain` in uniform
/// pieces of 3 courses × 3 speeds (the contact behaviours' `build_info`); `None` when the
/// domain lacks either variable.
pub fn reflect(domain: &Domain, f: impl Fn(f64, f64) -> f64) -> Option<IvpFunction> {
    let mut d = Domain::new();
    d.add(domain.get("course")?.clone()).ok()?;
    d.add(domain.get("speed")?.clone()).ok()?;
    Reflector::new(&d, |v: &[f64]| f(v[0], v[1]))
        .set_param("uniform_piece", "course:3,speed:3")
        .ok()?
        .build()
        .ok()
}
