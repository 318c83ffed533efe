//! BHV_Convoy (MOOS-IvP `BHV_Convoy` at a2a9b716): follows a contact along its own track,
//! through marks dropped every `inter_mark_range` metres of the contact's path.
//!
//! Each running iteration: the contact's speed is averaged over 2 and 5 s; a mark is added
//! when the contact is more than `inter_mark_range` from the newest, and the oldest dropped
//! while the marks' path is longer than `max_mark_range`; marks within `radius` of ownship are
//! passed. The objective (none once every mark is passed) couples (0.5/0.5, normalised) a
//! course ZAIC (summed components: the bearing to the oldest mark, 0/180/50, utilities
//! 0..100; ownship's heading, 30/180/5, 0..20) and a speed ZAIC_PEAK at the set speed (peak
//! width half of it, base 1.6, summit delta 20): 0 inside `rng_estop`, else `cruise_speed`
//! if set, else the 2 s average times `spd_faster` beyond `rng_lagging`, times 1 beyond
//! `rng_tgating`, times `spd_slower` nearer. The C++ never sets the function's priority
//! weight, so it keeps IvPFunction's default 10 whatever `pwt` says: coug's weight factor is
//! `10 / pwt` (with `pwt = 0` the helm drops the function, where the C++ would weigh it 10).
//!
//! # Conformance with BHV_Convoy (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | default | validation (C++ rule) | coug |
//! |---|---|---|---|---|
//! | radius | | 5 | number >= 0 | done |
//! | nm_radius | | 20 | number >= 0 | done (read; unused by the C++) |
//! | max_mark_range | | 150 | number > 0 | done |
//! | inter_mark_range | | 10 | number > 0 | done |
//! | cruise_speed | | off | number > 0; capped at spd_max (warning) | done |
//! | spd_max | | 2 | number > 0 | done |
//! | spd_slower | | 0.5 | number in (0, 1] | done |
//! | spd_faster | | 1.5 | number in [1, 3] | done |
//! | rng_estop | range_estop | 15 | number > 0; at least 5 with rng_safety | done |
//! | rng_tgating | range_tailgating | 30 | number > 0; at least rng_estop + 10 | done |
//! | rng_lagging | range_lagging | 70 | number > 0; at least rng_tgating + 10 | done |
//! | rng_safety | | true | boolean | done |
//! | contact parameters | | | see [`crate::contact`] | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | TLEN, QLEN, MXRNG, AVG2, AVG5, WPTX, WPTY | each running iteration (filtered on change) | numbers | done |
//! | VIEW_POINT | a mark added (drawn) or passed/dropped (erased) | label `<us>_<contact>_<id>`, white, label invisible | done |
//! | BHV_WARNING | configuration: ranges or cruise speed adjusted | `Safety ranges were auto-adusted bigger.`, `Cruise speed auto-capped at max speed.` | done |

use std::collections::VecDeque;

use ivp::{Combine, IvpFunction, PeakComponent, ZaicPeak, couple_weighted};

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::common::Common;
use crate::contact::ContactBase;
use crate::param::{is_number, moos_boolean};

/// BHV_Convoy.
#[derive(Debug, Clone)]
pub struct Convoy {
    /// The contact and the shared contact parameters.
    pub base: ContactBase,
    /// `radius`, m.
    pub radius: f64,
    /// `nm_radius`, m.
    pub nm_radius: f64,
    /// `max_mark_range`, m.
    pub max_mark_range: f64,
    /// `inter_mark_range`, m.
    pub inter_mark_range: f64,
    /// `cruise_speed`, m/s (<= 0: off).
    pub cruise_speed: f64,
    /// `spd_max`, m/s.
    pub spd_max: f64,
    /// `spd_faster`.
    pub spd_faster: f64,
    /// `spd_slower`.
    pub spd_slower: f64,
    /// `rng_estop`, m.
    pub rng_estop: f64,
    /// `rng_tgating`, m.
    pub rng_tgating: f64,
    /// `rng_lagging`, m.
    pub rng_lagging: f64,
    /// `rng_safety`.
    pub rng_safety: bool,
    marks_up_bound: u32,
    /// Marks, newest first: (x, y, id).
    marks: VecDeque<(f64, f64, u32)>,
    next_id: u32,
    total_length: f64,
    spds: VecDeque<(f64, f64)>,
    avg2: f64,
    avg5: f64,
    set_speed: f64,
    pwt: f64,
}

impl Default for Convoy {
    fn default() -> Self {
        Self::new()
    }
}

impl Convoy {
    /// The C++ defaults.
    pub fn new() -> Self {
        Convoy {
            base: ContactBase::new(60.0),
            radius: 5.0,
            nm_radius: 20.0,
            max_mark_range: 150.0,
            inter_mark_range: 10.0,
            cruise_speed: -1.0,
            spd_max: 2.0,
            spd_faster: 1.5,
            spd_slower: 0.5,
            rng_estop: 15.0,
            rng_tgating: 30.0,
            rng_lagging: 70.0,
            rng_safety: true,
            marks_up_bound: 200,
            marks: VecDeque::new(),
            next_id: 0,
            total_length: 0.0,
            spds: VecDeque::new(),
            avg2: 0.0,
            avg5: 0.0,
            set_speed: 0.0,
            pwt: 100.0,
        }
    }

    /// The speed the objective asks for at range `r` (MOOS `updateSetSpeed`), given the
    /// contact's 2 s average speed `avg2`.
    pub fn set_speed_at(&self, r: f64, avg2: f64) -> f64 {
        if r < self.rng_estop {
            0.0
        } else if self.cruise_speed > 0.0 {
            self.cruise_speed
        } else if r > self.rng_lagging {
            avg2 * self.spd_faster
        } else if r > self.rng_tgating {
            avg2
        } else {
            avg2 * self.spd_slower
        }
    }

    /// The objective toward `(wx, wy)` from ownship at `(osx, osy)` heading `osh`, at
    /// speed `speed` (MOOS `buildOF`).
    pub fn objective(
        ctx: &Ctx<'_>,
        (osx, osy, osh): (f64, f64, f64),
        (wx, wy): (f64, f64),
        speed: f64,
    ) -> Option<IvpFunction> {
        let mut spd = ZaicPeak::new(ctx.domain, "speed").ok()?;
        spd.set_params(speed, speed / 2.0, 1.6, 20.0, 0.0, 100.0)
            .ok()?;
        let spd = spd.extract().ok()?;
        let mut crs = ZaicPeak::new(ctx.domain, "course").ok()?;
        crs.set_value_wrap(true);
        let bearing = geometry::relative_angle(osx, osy, wx, wy);
        crs.set_params(bearing, 0.0, 180.0, 50.0, 0.0, 100.0).ok()?;
        crs.add_component(PeakComponent {
            summit: osh,
            peakwidth: 30.0,
            basewidth: 180.0,
            summitdelta: 5.0,
            minutil: 0.0,
            maxutil: 20.0,
        })
        .ok()?;
        crs.set_combine(Combine::Sum);
        let crs = crs.extract().ok()?;
        couple_weighted(&crs, &spd, 0.5, 0.5, true).ok()
    }

    fn mark_label(&self, ctx: &Ctx<'_>, id: u32) -> String {
        format!("{}_{}_{id}", ctx.ownship, self.base.contact)
    }

    fn post_mark(&self, ctx: &Ctx<'_>, out: &mut Out, x: f64, y: f64, id: u32) {
        let mut vp = geometry::ViewPoint::new(geometry::Point::new(x, y));
        vp.attrs.label = self.mark_label(ctx, id);
        vp.attrs.label_color = Some("invisible".into());
        vp.attrs.vertex_color = Some("white".into());
        out.post("VIEW_POINT", vp.to_spec());
    }

    fn erase_mark(&self, ctx: &Ctx<'_>, out: &mut Out, id: u32) {
        let mut s = String::new();
        geometry::ViewPoint::erase_spec(&self.mark_label(ctx, id), &mut s);
        out.post("VIEW_POINT", s);
    }

    fn push_mark(&mut self, ctx: &Ctx<'_>, out: &mut Out, x: f64, y: f64) {
        if let Some(&(nx, ny, _)) = self.marks.front() {
            self.total_length += (x - nx).hypot(y - ny);
        }
        let id = self.next_id;
        self.marks.push_front((x, y, id));
        self.post_mark(ctx, out, x, y, id);
        self.next_id += 1;
        if self.next_id > self.marks_up_bound {
            self.next_id = 0;
        }
    }

    fn pop_mark(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        let Some((px, py, id)) = self.marks.pop_back() else {
            return;
        };
        self.erase_mark(ctx, out, id);
        if let Some(&(ox, oy, _)) = self.marks.back() {
            self.total_length -= (ox - px).hypot(oy - py);
        }
    }

    fn average_speed(&mut self, now: f64, cnv: f64) {
        self.spds.push_front((cnv, now));
        while self.spds.back().is_some_and(|(_, t)| now - t > 5.0) {
            self.spds.pop_back();
        }
        let mean = |it: &mut dyn Iterator<Item = f64>| {
            let (s, n) = it.fold((0.0, 0u32), |(s, n), v| (s + v, n + 1));
            (n > 0).then(|| s / f64::from(n))
        };
        if let Some(a) = mean(&mut self.spds.iter().map(|(v, _)| *v)) {
            self.avg5 = a;
        }
        if let Some(a) = mean(
            &mut self
                .spds
                .iter()
                .filter(|(_, t)| now - t <= 2.0)
                .map(|(v, _)| *v),
        ) {
            self.avg2 = a;
        }
    }
}

impl Behavior for Convoy {
    /// IvPContactBehavior's post mortem: the reason, range and bearing to the contact.
    fn post_mortem(&self, reason: &str) -> String {
        self.base.post_mortem(reason)
    }

    fn kind(&self) -> &'static str {
        "BHV_Convoy"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course", "speed"]
    }

    fn default_name(&self) -> &'static str {
        "convoy"
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        if let Some(r) = self.base.set_param(param, value) {
            return r;
        }
        let d = geometry::atof(value);
        let num = is_number(value);
        let bad = |e| Err(ParamError::bad(param, value, e));
        let slot = match param {
            "nm_radius" | "radius" => {
                if !(num && d >= 0.0) {
                    return bad("a number >= 0");
                }
                if param == "radius" {
                    &mut self.radius
                } else {
                    &mut self.nm_radius
                }
            }
            "spd_slower" if !(num && d > 0.0 && d <= 1.0) => return bad("a number in (0, 1]"),
            "spd_faster" if !(num && (1.0..=3.0).contains(&d)) => {
                return bad("a number in [1, 3]");
            }
            "rng_safety" => {
                self.rng_safety = moos_boolean(param, value, self.rng_safety)?;
                return Ok(());
            }
            _ => {
                let slot = match param {
                    "max_mark_range" => &mut self.max_mark_range,
                    "inter_mark_range" => &mut self.inter_mark_range,
                    "cruise_speed" => &mut self.cruise_speed,
                    "spd_max" => &mut self.spd_max,
                    "spd_slower" => &mut self.spd_slower,
                    "spd_faster" => &mut self.spd_faster,
                    "rng_estop" | "range_estop" => &mut self.rng_estop,
                    "rng_tgating" | "range_tailgating" => &mut self.rng_tgating,
                    "rng_lagging" | "range_lagging" => &mut self.rng_lagging,
                    _ => return Err(ParamError::unknown(param)),
                };
                if !(num && d > 0.0) {
                    return bad("a number > 0");
                }
                slot
            }
        };
        *slot = d;
        Ok(())
    }

    fn on_set_param_complete(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        if self.inter_mark_range > 0.0 {
            self.marks_up_bound = (self.max_mark_range / self.inter_mark_range + 1.0) as u32;
        }
        if self.rng_safety {
            let mut adjusted = false;
            if self.rng_estop < 5.0 {
                self.rng_estop = 5.0;
                adjusted = true;
            }
            if self.rng_tgating < self.rng_estop + 10.0 {
                self.rng_tgating = self.rng_estop + 10.0;
                adjusted = true;
            }
            if self.rng_lagging < self.rng_tgating + 10.0 {
                self.rng_lagging = self.rng_tgating + 10.0;
                adjusted = true;
            }
            if adjusted {
                out.warning(ctx.name, "Safety ranges were auto-adusted bigger.");
            }
            if self.cruise_speed > self.spd_max {
                self.cruise_speed = self.spd_max;
                out.warning(ctx.name, "Cruise speed auto-capped at max speed.");
            }
        }
        crate::behavior::post_config_status(&*self, ctx, out);
    }

    fn set_common(&mut self, common: &Common) {
        self.pwt = common.pwt;
    }

    fn contact_name(&self) -> Option<&str> {
        self.base.contact_name()
    }

    fn macro_value(&self, name: &str, out: &mut String) -> bool {
        self.base.macro_value(name, out)
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_X", "NAV_Y", "NAV_SPEED", "NAV_HEADING"]);
    }

    fn pwt_factor(&self) -> f64 {
        if self.pwt > 0.0 {
            ivp::DEFAULT_PWT / self.pwt
        } else {
            0.0
        }
    }

    fn on_run_to_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        for &(_, _, id) in &self.marks {
            self.erase_mark(ctx, out, id);
        }
        self.marks.clear();
        self.total_length = 0.0;
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        if !self.base.update(ctx, out) {
            return None;
        }
        self.base.post_contact_flags(out);
        let (cnx, cny, _, cnv) = self.base.cn;
        out.post("TLEN", self.total_length);
        out.post("QLEN", self.marks.len() as f64);
        out.post("MXRNG", self.max_mark_range);
        self.average_speed(ctx.info.now(), cnv);
        out.post("AVG2", self.avg2);
        out.post("AVG5", self.avg5);
        match self.marks.front() {
            None => self.push_mark(ctx, out, cnx, cny),
            Some(&(nx, ny, _)) if (cnx - nx).hypot(cny - ny) > self.inter_mark_range => {
                self.push_mark(ctx, out, cnx, cny)
            }
            Some(_) => {}
        }
        if !self.marks.is_empty() && self.total_length > self.max_mark_range {
            self.pop_mark(ctx, out);
        }
        let (osx, osy, osh, _) = self.base.os;
        let mut wpt = self.marks.back().map_or((0.0, 0.0), |&(x, y, _)| (x, y));
        let mut active = false;
        loop {
            if (osx - wpt.0).hypot(osy - wpt.1) < self.radius {
                self.pop_mark(ctx, out);
                match self.marks.back() {
                    Some(&(x, y, _)) => wpt = (x, y),
                    None => break,
                }
            } else {
                active = true;
                break;
            }
        }
        out.post("WPTX", wpt.0);
        out.post("WPTY", wpt.1);
        if !active {
            return None;
        }
        self.set_speed = self.set_speed_at(self.base.range, self.avg2);
        Self::objective(ctx, (osx, osy, osh), wpt, self.set_speed)
    }
}
