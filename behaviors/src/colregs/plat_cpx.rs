//! BHV_AvdColregsV26's platform-model engine (MOOS-IvP `CPXEnginePM` over `CPXEngineThin` at
//! a2a9b716; facts only, coug's own code): the CPA and the passing and crossing predicates of
//! a course evaluated along the path the helm's platform model gives for it
//! ([`PlatModel::turn`]) instead of along a ray from ownship.
//!
//! For course `crs` and speed `spd` the path's vertices are taken in order. At vertex `i`
//! ownship is on the vertex heading to the next one (the ray's heading at the last), after
//! `t_i = pdist_i / spd` seconds (`pdist_i` the path's length up to the vertex), and the
//! contact has moved `t_i · cnv` along its heading. The question (CPA, passing, crossing) is
//! put to the pair as it stands there, on that heading held for the time on leg (the
//! engine's single-heading formulas, headings at the whole degree below). The first vertex
//! whose answer falls within its segment's time (`dist_i / spd`; any time on the ray)
//! answers, with `t_i` added to its time; the others do not count. An answer without a time
//! (ownship exactly abeam or on the contact's stern line: distance now, time −1) never counts,
//! as in the C++. At speed 0 every vertex is the first one, unmoved.
//!
//! Where the C++ differs from plain reading, coug keeps it: the first segment that answers
//! wins even when a later one comes closer; the predicates are "a distance was found" (so a
//! pass or crossing without a distance is no pass). Where it has no defined value, coug
//! picks the natural one: for a contact at rest the C++ reads uninitialised positions at
//! every vertex after the first, coug keeps the contact where it is.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use geometry::{angle_180, angle_360, relative_angle};

use crate::plat_model::{PlatModel, project};

/// The platform model the AvdColregs functions follow this iteration: none without
/// `use_plat_model` (the OG engine); for V26 the helm's model when it is not the holonomic
/// one (with the holonomic model V26's CPA is the OG engine's, see the module docs of
/// [`super`]'s `AvdColregs`); for the other versions the empty model (the C++ never hands
/// their platform-model engine one).
pub(super) fn turning_model(
    version: super::Version,
    use_plat_model: bool,
    ctx: &crate::behavior::Ctx<'_>,
) -> Option<Arc<PlatModel>> {
    if !use_plat_model {
        return None;
    }
    if version != super::Version::V26 {
        return Some(empty_model());
    }
    let m = ctx.info.plat_model()?;
    (!m.is_holonomic()).then(|| Arc::new(m.clone()))
}

/// The model of a platform-model engine no behaviour handed one (a default MOOS
/// `PlatModel`): no spokes, at the origin, so every course's path is the ray from `(0, 0)`.
/// IvPContactBehavior's reverse engine (the contact as ownship) always has it, and so has
/// its forward engine in the behaviours that never hand it the helm's model (CutRange,
/// Trail, Shadow, Convoy, AvdColregs V17/V19/V22) and in AvoidCollision and V26 before their
/// first running iteration.
pub fn empty_model() -> Arc<PlatModel> {
    Arc::new(PlatModel::holonomic(0.0, 0.0, 0.0, 0.0))
}

/// The rate of closure at ownship course `osh` and speed `osv` (MOOS
/// `CPXEnginePM::evalROC`: the exact heading, no whole-degree cache): ownship's speed toward
/// the contact plus the contact's toward ownship.
pub fn pm_roc(pair: &super::geometry::Cpx, osh: f64, osv: f64) -> f64 {
    let mut delta = osh - pair.abs_bng_os_cn;
    // The C++'s wrap (its second test compares with +180, so it adds a turn to anything
    // below it): the cosine is the same.
    if delta > 180.0 {
        delta -= 360.0;
    } else if delta < 180.0 {
        delta += 360.0;
    }
    if delta < 0.0 {
        delta = -delta;
    }
    rad(delta).cos() * osv + pair.cn_to_os_spd
}

/// The contact's bearing rate seen from ownship at course `osh` and speed `osv`, degrees per
/// second (MOOS `CPXEnginePM::bearingRate`: the exact heading, the tangent 90° to port of
/// the bearing, the C++'s 12-digit pi).
pub fn pm_bearing_rate(pair: &super::geometry::Cpx, osh: f64, osv: f64) -> f64 {
    #[allow(clippy::approx_constant)]
    const MPI: f64 = 3.14159265359;
    let tangent = angle_360(pair.abs_bng_os_cn - 90.0);
    let off = |h: f64| {
        let mut d = h - tangent;
        if d > 180.0 {
            d -= 360.0;
        } else if d < -180.0 {
            d += 360.0;
        }
        d.abs()
    };
    let (d_os, d_cn) = (off(osh), off(pair.cn.2));
    let os_at = if d_os != 90.0 {
        rad(d_os).cos() * -osv
    } else {
        0.0
    };
    let cn_at = if d_cn != 90.0 {
        rad(d_cn).cos() * pair.cn.3
    } else {
        0.0
    };
    (os_at + cn_at) * (-360.0 / (2.0 * pair.range * MPI))
}

/// The contact state (IvPContactBehavior's `m_cnos`) its `updatePlatformInfo` fills with
/// `use_plat_model = true` (its two `CPXEnginePM`s): ownship `os` and contact `cn` as
/// `(x, y, heading, speed)`; the forward engine holds `model` (the one the behaviour last
/// handed it, `None`: [`empty_model`]), the reverse engine (the contact as ownship) the
/// empty model. The sides, bearings and the contact's speed toward ownship are the pair's
/// as they stand; the rate of closure and the bearing rate are [`pm_roc`] and
/// [`pm_bearing_rate`]; passing, crossing and the present CPA (120 s) follow the engines'
/// paths at the present headings and speeds ([`PlatCpx`]).
pub fn contact_state(
    os: (f64, f64, f64, f64),
    cn: (f64, f64, f64, f64),
    model: Option<Arc<PlatModel>>,
) -> crate::contact_state::ContactState {
    let (osx, osy, osh, osv) = os;
    let (cnx, cny, cnh, cnv) = cn;
    let model = model.unwrap_or_else(empty_model);
    let fwd = super::geometry::Cpx::new(cnx, cny, cnh, cnv, osx, osy, osh, osv);
    let rev = fwd.reversed().with_plat_model(empty_model());
    let fwd = fwd.with_plat_model(model);
    let (_, _, osh, osv) = fwd.os;
    let pm = fwd.pm.as_ref().expect("a model was just given");
    crate::contact_state::ContactState::of_engines(
        &fwd,
        &rev,
        pm_roc(&fwd, osh, osv),
        pm_bearing_rate(&fwd, osh, osv),
        pm.eval_cpa(osh, osv, 120.0),
    )
}

/// MOOS `degToRadians`.
fn rad(deg: f64) -> f64 {
    (deg / 180.0) * std::f64::consts::PI
}

/// The whole degree below a heading wrapped into `[0, 360)` (the C++'s cache index).
fn whole(osh: f64) -> f64 {
    angle_360(osh).trunc().min(359.0)
}

/// The cosine of the angle between whole-degree heading `i` and `theta`, 0 at exactly 90°.
fn cos_between(i: f64, theta: f64) -> f64 {
    let d = angle_180(i - theta).abs();
    if d == 90.0 { 0.0 } else { rad(d).cos() }
}

/// Where ownship stands relative to the contact at one vertex (the statics of MOOS
/// `CPXEngine`'s `setStaticRoot`, the parts the single-heading questions read): on it, on
/// its bow or stern line, abeam, fore, aft, port, starboard; the range and its parts across
/// (`gam`, to the bow-stern line) and along (`eps`, to the beam line) the contact's heading.
#[derive(Debug, Clone, Copy)]
struct Pair {
    on_contact: bool,
    on_bowline: bool,
    on_sternline: bool,
    on_beam: bool,
    fore: bool,
    aft: bool,
    port: bool,
    star: bool,
    range: f64,
    gam: f64,
    eps: f64,
}

impl Pair {
    fn new((cnx, cny): (f64, f64), cnh: f64, (osx, osy): (f64, f64)) -> Pair {
        let on_contact = osx == cnx && osy == cny;
        let ang_cn_os = relative_angle(cnx, cny, osx, osy);
        let rb = angle_360(ang_cn_os - cnh);
        let on_bowline = ang_cn_os == cnh;
        let on_sternline = !on_bowline && ang_cn_os == angle_360(cnh - 180.0);
        let (fore, aft, port, star) = if on_contact {
            (false, false, false, false)
        } else {
            (
                rb <= 90.0 || rb >= 270.0,
                (90.0..=270.0).contains(&rb),
                (180.0..=360.0).contains(&rb),
                (0.0..=180.0).contains(&rb),
            )
        };
        let range = (osx - cnx).hypot(osy - cny);
        let rb180 = angle_180(rb).abs();
        let (gam, eps) = if rb180 == 0.0 || rb180 == 180.0 {
            (0.0, range)
        } else {
            let gam = range * rad(90.0 - rb180).cos();
            (gam, (range * range - gam * gam).max(0.0).sqrt())
        };
        Pair {
            on_contact,
            on_bowline,
            on_sternline,
            on_beam: on_contact || (fore && aft),
            fore,
            aft,
            port,
            star,
            range,
            gam,
            eps,
        }
    }
}

/// A contact `(x, y, heading, speed)` with ownship's platform model.
///
/// The answers at the spokes before a path's last vertex do not depend on the course (every
/// course turning to that side shares them), so the first spoke that answers is kept per
/// question, side and speed: a course then costs one lookup and its last vertex.
#[derive(Debug)]
pub struct PlatCpx {
    /// The platform model.
    pub model: Arc<PlatModel>,
    /// The contact: x, y, heading (in `[0, 360)`), speed (>= 0).
    pub cn: (f64, f64, f64, f64),
    first: Mutex<HashMap<Key, Option<(usize, Answer)>>>,
}

/// A kept answer's question (with its time on leg's bits), side and speed's bits.
type Key = (Q, u64, bool, u64);

/// The questions the engine answers along a path.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Q {
    Cpa,
    PassPort,
    PassStar,
    CrossBow,
    CrossStern,
}

impl Clone for PlatCpx {
    fn clone(&self) -> Self {
        PlatCpx::new(self.model.clone(), self.cn)
    }
}

impl PartialEq for PlatCpx {
    fn eq(&self, other: &Self) -> bool {
        self.model == other.model && self.cn == other.cn
    }
}

/// One vertex's answer: a distance and the time it happens, each −1 when there is none.
type Answer = (f64, f64);

const NONE: Answer = (-1.0, -1.0);

impl PlatCpx {
    /// The engine for the contact `cn` and the model.
    pub fn new(model: Arc<PlatModel>, cn: (f64, f64, f64, f64)) -> Self {
        let (x, y, h, v) = cn;
        PlatCpx {
            model,
            cn: (x, y, angle_360(h), v.max(0.0)),
            first: Mutex::new(HashMap::new()),
        }
    }

    /// The contact after `t` seconds.
    fn cn_at(&self, t: f64) -> (f64, f64) {
        let (cnx, cny, cnh, cnv) = self.cn;
        if cnv > 0.0 {
            let p = project(cnh, t * cnv, cnx, cny);
            (p.x, p.y)
        } else {
            (cnx, cny)
        }
    }

    /// The first spoke of side `port` before the side's last that answers within its
    /// segment at speed `spd` (> 0): its index and answer, time from now.
    fn first_spoke(
        &self,
        port: bool,
        spd: f64,
        f: &impl Fn((f64, f64), (f64, f64, f64)) -> Answer,
    ) -> Option<(usize, Answer)> {
        let (spokes, segs) = self.model.side(port);
        let mut pdist = 0.0;
        for (j, (v, &(hdg, len))) in spokes.iter().zip(segs).enumerate() {
            let tp = pdist / spd;
            let (xd, xt) = f(self.cn_at(tp), (v.x, v.y, hdg));
            if xt >= 0.0 && xt <= len / spd {
                return Some((j, (xd, xt + tp)));
            }
            pdist += len;
        }
        None
    }

    /// Walks the path of course `crs` (see the module docs) asking `q` (`tol` its time on
    /// leg, 0 for the others); `f` answers at one vertex with the contact's position,
    /// ownship's position and heading.
    fn walk(
        &self,
        q: Q,
        tol: f64,
        crs: f64,
        spd: f64,
        f: impl Fn((f64, f64), (f64, f64, f64)) -> Answer,
    ) -> Answer {
        let path = self.model.turn(crs);
        if spd <= 0.0 {
            let v = path.vertex(0);
            let a = f((self.cn.0, self.cn.1), (v.x, v.y, path.vert_angle(0)));
            return if a.1 >= 0.0 { a } else { NONE };
        }
        let last = path.len() - 1;
        if last > 0 {
            let key = (q, tol.to_bits(), path.port, spd.to_bits());
            let mut first = self.first.lock().unwrap_or_else(|e| e.into_inner());
            let hit = *first
                .entry(key)
                .or_insert_with(|| self.first_spoke(path.port, spd, &f));
            if let Some((k, a)) = hit
                && k < last
            {
                return a;
            }
        }
        let tp = path.vert_pdist(last) / spd;
        let v = path.vertex(last);
        let (xd, xt) = f(self.cn_at(tp), (v.x, v.y, path.ray));
        if xt >= 0.0 { (xd, xt + tp) } else { NONE }
    }

    fn pair(&self, cn: (f64, f64), os: (f64, f64, f64)) -> Pair {
        Pair::new(cn, self.cn.2, (os.0, os.1))
    }

    /// The CPA distance at course `crs` and speed `spd` over the time on leg `tol` (MOOS
    /// `CPXEnginePM::evalCPA`).
    pub fn eval_cpa(&self, crs: f64, spd: f64, tol: f64) -> f64 {
        self.walk(Q::Cpa, tol, crs, spd, |cn, os| {
            self.thin_cpa(cn, os, spd, tol)
        })
        .0
    }

    /// The CPA and its time with the pair as it stands, ownship holding `os.2` (MOOS
    /// `CPXEngineThin::evalCPA`): the present range at time 0 when they are opening (or
    /// ownship outruns a closing contact), else the range at the vertex of the range's
    /// parabola, clipped to the time on leg.
    fn thin_cpa(
        &self,
        (cnx, cny): (f64, f64),
        (osx, osy, osh): (f64, f64, f64),
        osv: f64,
        tol: f64,
    ) -> Answer {
        let (_, _, cnh, cnv) = self.cn;
        let range = (osx - cnx).hypot(osy - cny);
        let ang_cn_os = relative_angle(cnx, cny, osx, osy);
        let rb = angle_360(ang_cn_os - cnh);
        let cn_to_os = if rb != 90.0 { cnv * rad(rb).cos() } else { 0.0 };
        let closing = cn_to_os > 0.0;
        let i = whole(osh);
        let (from, sign) = if closing {
            (ang_cn_os, 1.0)
        } else {
            (relative_angle(osx, osy, cnx, cny), -1.0)
        };
        let cos_delta = rad(i - from).cos();
        let vthresh = if cos_delta > 0.0001 {
            sign * cn_to_os / cos_delta
        } else {
            999.0
        };
        let now = (range, 0.0);
        if closing {
            if osv > cn_to_os && osv >= vthresh {
                return now;
            }
        } else if osv <= vthresh {
            return now;
        }
        let (sin_cnh, cos_cnh) = rad(cnh).sin_cos();
        let (s, c) = rad(i).sin_cos();
        let k2_i = c * (-2.0 * cos_cnh * cnv) + s * (-2.0 * sin_cnh * cnv);
        let k2 = cnv * cnv + (k2_i + osv) * osv;
        if k2 < 0.0 {
            return now;
        }
        let mut k1 = -2.0 * osy * cos_cnh * cnv;
        k1 += -2.0 * osx * sin_cnh * cnv;
        k1 += 2.0 * cny * cos_cnh * cnv;
        k1 += 2.0 * cnx * sin_cnh * cnv;
        let mut k1_i = 2.0 * c * osy;
        k1_i += 2.0 * s * osx;
        k1_i += -2.0 * c * cny;
        k1_i += -2.0 * s * cnx;
        k1 += k1_i * osv;
        let mut k0 = osy * osy;
        k0 += osx * osx;
        k0 += -2.0 * osy * cny;
        k0 += -2.0 * osx * cnx;
        k0 += cny * cny;
        k0 += cnx * cnx;
        let mut t = 0.0;
        if k2 != 0.0 {
            t = k1 / (-2.0 * k2);
        }
        if t <= 0.0 {
            return now;
        }
        if t >= tol {
            t = tol;
        }
        let d2 = t * ((k2 * t) + k1) + k0;
        if d2 < 0.0 {
            return now;
        }
        (d2.sqrt(), t)
    }

    /// Passing the contact's beam line on its port (`port`) or starboard side, as the pair
    /// stands (MOOS `CPXEngineThin::passesPortDist`/`passesStarDist`).
    fn thin_passes(&self, c: &Pair, osh: f64, osv: f64, port: bool) -> Answer {
        let (same, other) = if port {
            (c.port, c.star)
        } else {
            (c.star, c.port)
        };
        if c.on_contact || (c.on_beam && other) {
            return NONE;
        }
        if c.on_beam && same {
            return (c.range, -1.0);
        }
        let (_, _, cnh, cnv) = self.cn;
        let i = whole(osh);
        let v_cnh = cos_between(i, cnh) * osv;
        let v_eps = if c.aft { v_cnh - cnv } else { cnv - v_cnh };
        if v_eps <= 0.0 {
            return NONE;
        }
        let t = c.eps / v_eps;
        let gam_dist = t * cos_between(i, self.theta_gam(c)) * osv;
        let mut x = -1.0;
        if same && gam_dist <= c.gam {
            x = c.gam - gam_dist;
        }
        if other && gam_dist > c.gam {
            x = gam_dist - c.gam;
        }
        if x < 0.0 { NONE } else { (x, t) }
    }

    /// The heading toward the contact's bow-stern line from ownship's side of it.
    fn theta_gam(&self, c: &Pair) -> f64 {
        if c.port {
            angle_360(self.cn.2 + 90.0)
        } else {
            angle_360(self.cn.2 - 90.0)
        }
    }

    /// Crossing the contact's bow-stern line ahead (`bow`) or astern of it, as the pair
    /// stands (MOOS `CPXEngineThin::crossesBowDist`/`crossesSternDist`).
    fn thin_crosses(&self, c: &Pair, osh: f64, osv: f64, bow: bool) -> Answer {
        let (on_same, on_other) = if bow {
            (c.on_bowline, c.on_sternline)
        } else {
            (c.on_sternline, c.on_bowline)
        };
        if on_same {
            return (c.range, -1.0);
        }
        if on_other || c.on_contact {
            return NONE;
        }
        let i = whole(osh);
        let v_gam = cos_between(i, self.theta_gam(c)) * osv;
        if v_gam <= 0.0 {
            return NONE;
        }
        let t = c.gam / v_gam;
        let cn_run = t * self.cn.3;
        let os_run = t * cos_between(i, self.cn.2) * osv;
        let mut x = if bow { os_run - cn_run } else { cn_run };
        let ahead = if bow { c.fore } else { !c.fore };
        if ahead {
            x += c.eps;
        } else {
            x -= c.eps;
        }
        if !bow {
            x -= os_run;
        }
        if x < 0.0 { NONE } else { (x, t) }
    }

    fn passes_side(&self, crs: f64, spd: f64, port: bool) -> Answer {
        let q = if port { Q::PassPort } else { Q::PassStar };
        self.walk(q, 0.0, crs, spd, |cn, os| {
            self.thin_passes(&self.pair(cn, os), os.2, spd, port)
        })
    }

    fn crosses_side(&self, crs: f64, spd: f64, bow: bool) -> Answer {
        let q = if bow { Q::CrossBow } else { Q::CrossStern };
        self.walk(q, 0.0, crs, spd, |cn, os| {
            self.thin_crosses(&self.pair(cn, os), os.2, spd, bow)
        })
    }

    /// Ownship passes the contact on its port side (MOOS `CPXEnginePM::passesPort`).
    pub fn passes_port(&self, crs: f64, spd: f64) -> bool {
        self.passes_side(crs, spd, true).1 >= 0.0
    }

    /// The port passing distance, or −1 (MOOS `passesPortDist`).
    pub fn passes_port_dist(&self, crs: f64, spd: f64) -> f64 {
        self.passes_side(crs, spd, true).0
    }

    /// Ownship passes the contact on its starboard side (MOOS `passesStar`).
    pub fn passes_star(&self, crs: f64, spd: f64) -> bool {
        self.passes_side(crs, spd, false).1 >= 0.0
    }

    /// The starboard passing distance, or −1 (MOOS `passesStarDist`).
    pub fn passes_star_dist(&self, crs: f64, spd: f64) -> f64 {
        self.passes_side(crs, spd, false).0
    }

    /// Ownship passes the contact on either side (MOOS `passesPortOrStar`).
    pub fn passes(&self, crs: f64, spd: f64) -> bool {
        self.passes_port(crs, spd) || self.passes_star(crs, spd)
    }

    /// Ownship crosses the contact's stern (MOOS `crossesStern`).
    pub fn crosses_stern(&self, crs: f64, spd: f64) -> bool {
        self.crosses_side(crs, spd, false).1 >= 0.0
    }

    /// Ownship crosses the contact's bow (MOOS `crossesBow`).
    pub fn crosses_bow(&self, crs: f64, spd: f64) -> bool {
        self.crosses_side(crs, spd, true).1 >= 0.0
    }

    /// How far ahead of the contact ownship crosses, or −1 (MOOS `crossesBowDist`).
    pub fn crosses_bow_dist(&self, crs: f64, spd: f64) -> f64 {
        self.crosses_side(crs, spd, true).0
    }

    /// Ownship crosses the contact's bow-stern line (MOOS `crossesBowOrStern`).
    pub fn crosses_bow_or_stern(&self, crs: f64, spd: f64) -> bool {
        self.crosses_bow(crs, spd) || self.crosses_stern(crs, spd)
    }
}
