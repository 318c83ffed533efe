//! BHV_ZigZag: alternating legs either side of a stem heading.
//!
//! # Conformance with BHV_ZigZag (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | speed | | m/s | 0 | number ≥ 0 (`setNonNegDoubleOnString`) | yes | done |
//! | mod_speed | | m/s | | `reset` (back to the speed taken on activation, 0 without `speed_on_active`) or a number added to the speed, clipped to the domain | yes | done |
//! | speed_on_active | spd_on_active | bool | false | MOOS boolean | yes | done |
//! | stem_hdg | | deg | 0 | number, wrapped to [0, 360) | yes | done |
//! | stem_on_active | | bool | false | MOOS boolean | yes | done |
//! | hdg_thresh | | deg | 0 | number ≥ 0 | yes | done |
//! | fierce_zigging | | bool | false | MOOS boolean | yes | done |
//! | zig_angle | | deg | 0 | number in [1, 75] | yes | done |
//! | zig_angle_fierce | delta_heading | deg | −1 (= zig_angle) | number in [1, 75] | yes | done |
//! | zig_first | | port/star | port | `port`, `star`, `starboard`, `left`, `right` (any case) | yes | done |
//! | max_zig_legs | | count | 2 | number ≥ 0, truncated | yes | done |
//! | max_zig_zags | | count | | number ≥ 1: `max_zig_legs` = 2 × its integer part | yes | done |
//! | max_stem_odo | | m | −1 (none) | number > 0 | yes | done |
//! | zigflag, zagflag, portflag, starflag, portflagx, starflagx | | flag | none | `VAR = value` | yes | done |
//! | visual_hints | | | | `draw_set_hdg`, `draw_req_hdg` (booleans), `set_hdg_color`, `req_hdg_color` (colours); anything else refused | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | VIEW_SEGLIST | each running iteration (unless its hint is off) | 20 m lines along the set and requested headings, labels `zig_set_<ownship>`, `zig_req_<ownship>`, label colour off, edge/vertex colours from the hints (white, yellow), edge size 1, vertex size 2, duration 5 | done |
//! | VIEW_SEGLIST | running → idle | `pts={0,0:9,0:0,9},active=false,label=..` for both | done |
//! | zigflag | each finished leg | flag | done |
//! | zagflag | each second finished leg | flag | done |
//! | portflagx, starflagx | a port (starboard) leg finishes | flag | done |
//! | portflag, starflag | a port (starboard) leg starts, unless the legs are done | flag | done |
//! | BHV_ERROR | running (or activated) without fresh NAV_X/NAV_Y, NAV_HEADING or NAV_SPEED (older than 5 s) | `ownship NAV_... not found or stale.` | done |
//!
//! Macros: `ODO`, `ZIG_ODO`, `ZAG_ODO`, `STEM_DIST`, `STEM_ODO`, `ZIGS`, `ZAGS`, `ZIGS_EVER`,
//! `ZAGS_EVER`, `STEM_HDG`, `STEM_SPD`, `ZIG_START_SPD`, `ZIG_MIN_SPD`, `ZIG_SPD_DELTA`,
//! `ZIGS_TOGO`, `ZAGS_TOGO`, `ZIG_PORT`, `ZIG_STAR`, `ZIG_SIDE`, expanded when a flag is posted,
//! as the C++ does. Two C++ quirks are kept: `ZIG_START_SPD` holds the heading at the last
//! turn (the C++ stores the heading there), and `ZAGS_TOGO` equals `ZIGS_TOGO` (its integer
//! `1 / 2` is 0). The behaviour completes once more than `max_zig_legs` legs are finished
//! (the C++ test is `zig_cnt > max_zig_legs`) or the distance along the stem reaches
//! `max_stem_odo`.
//!
//! Objective function: ZAIC_PEAK on course (summit the requested heading, base width 180,
//! wrapping) coupled 50/50 with ZAIC_SPD on speed (summit `speed`, 0.1 and `speed + 0.4` at
//! utilities 85 and 20), normalised to [0, 100].

use geometry::{Point, Segment};
use ivp::{IvpFunction, ZaicPeak, ZaicSpd, couple_weighted};
use moos_types::fmt::compact;

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_flag_vars, add_vars};
use crate::common::{Common, Flag, FlagValue};
use crate::param::{is_number, moos_boolean, number};

/// Which leg the behaviour is on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Leg {
    /// Not started (before the first run, after deactivation).
    Stem,
    /// Heading `stem_hdg − zig_angle`.
    Port,
    /// Heading `stem_hdg + zig_angle`.
    Star,
}

impl Leg {
    fn name(self) -> &'static str {
        match self {
            Leg::Stem => "stem",
            Leg::Port => "port",
            Leg::Star => "star",
        }
    }
}

/// Distance travelled since the last reset (MOOS `Odometer`'s total distance).
#[derive(Debug, Clone, Default)]
struct Odometer {
    prev: Option<(f64, f64)>,
    total: f64,
}

impl Odometer {
    fn update(&mut self, x: f64, y: f64) {
        if let Some((px, py)) = self.prev {
            self.total += (x - px).hypot(y - py);
        }
        self.prev = Some((x, y));
    }
    fn reset(&mut self) {
        *self = Odometer::default();
    }
}

/// The flags of one kind.
#[derive(Debug, Clone, Default)]
struct Flags {
    zig: Vec<Flag>,
    zag: Vec<Flag>,
    port: Vec<Flag>,
    star: Vec<Flag>,
    portx: Vec<Flag>,
    starx: Vec<Flag>,
}

/// Zig-zags about a stem heading: legs alternate between `stem_hdg ∓ zig_angle`, each turn
/// finishing when the heading is within `hdg_thresh` of the leg's heading (or has swung past
/// it).
#[derive(Debug, Clone)]
pub struct ZigZag {
    /// Speed, m/s.
    pub speed: f64,
    /// The speed `mod_speed = reset` returns to.
    pub speed_orig: f64,
    /// Take the speed at activation.
    pub speed_on_active: bool,
    /// The stem heading, degrees.
    pub stem_hdg: f64,
    /// Take the stem heading at activation.
    pub stem_on_active: bool,
    /// Heading tolerance ending a turn, degrees.
    pub hdg_thresh: f64,
    /// Ask for `heading ∓ zig_angle_fierce` rather than the leg's heading.
    pub fierce_zigging: bool,
    /// The legs' angle off the stem, degrees.
    pub zig_angle: f64,
    /// The fierce zigging offset (−1 = `zig_angle`).
    pub zig_angle_fierce: f64,
    /// The first leg's side (port unless star).
    pub zig_first_star: bool,
    /// Legs before completion.
    pub max_zig_legs: u32,
    /// Distance along the stem ending the behaviour (−1 = none).
    pub max_stem_odo: f64,
    draw_set_hdg: bool,
    draw_req_hdg: bool,
    set_hdg_color: String,
    req_hdg_color: String,
    flags: Flags,
    // State.
    leg: Leg,
    set_hdg: f64,
    req_hdg: f64,
    zig_cnt: u32,
    zig_cnt_ever: u32,
    stem: Segment,
    stem_dist: f64,
    stem_odo: f64,
    zig_spd_start: f64,
    zig_spd_min: f64,
    zig_spd_delta: f64,
    odometer: Odometer,
    zig_odo: Odometer,
    zag_odo: Odometer,
    os: (f64, f64, f64, f64),
}

impl Default for ZigZag {
    fn default() -> Self {
        Self::new()
    }
}

/// Seconds after which a navigation variable is stale.
const STALE_NAV: f64 = 5.0;

impl ZigZag {
    /// The MOOS defaults.
    pub fn new() -> Self {
        ZigZag {
            speed: 0.0,
            speed_orig: 0.0,
            speed_on_active: false,
            stem_hdg: 0.0,
            stem_on_active: false,
            hdg_thresh: 0.0,
            fierce_zigging: false,
            zig_angle: 0.0,
            zig_angle_fierce: -1.0,
            zig_first_star: false,
            max_zig_legs: 2,
            max_stem_odo: -1.0,
            draw_set_hdg: true,
            draw_req_hdg: true,
            set_hdg_color: "white".into(),
            req_hdg_color: "yellow".into(),
            flags: Flags::default(),
            leg: Leg::Stem,
            set_hdg: 0.0,
            req_hdg: 0.0,
            zig_cnt: 0,
            zig_cnt_ever: 0,
            stem: Segment::from_xy(0.0, 0.0, 0.0, 0.0),
            stem_dist: 0.0,
            stem_odo: 0.0,
            zig_spd_start: 0.0,
            zig_spd_min: -1.0,
            zig_spd_delta: 0.0,
            odometer: Odometer::default(),
            zig_odo: Odometer::default(),
            zag_odo: Odometer::default(),
            os: (0.0, 0.0, 0.0, 0.0),
        }
    }

    /// The leg the behaviour is on.
    pub fn leg(&self) -> Leg {
        self.leg
    }

    /// Finished legs since activation.
    pub fn legs_done(&self) -> u32 {
        self.zig_cnt
    }

    fn legs_complete(&self) -> bool {
        self.zig_cnt > self.max_zig_legs
    }

    /// Reads a fresh navigation number; `None` (with a BHV_ERROR) when missing or stale.
    fn fresh(ctx: &Ctx<'_>, out: &mut Out, var: &str, what: &str) -> Option<f64> {
        match (ctx.info.num(var), ctx.info.age(var)) {
            (Some(v), Some(age)) if age <= STALE_NAV => Some(v),
            _ => {
                out.error(format!("ownship {what} not found or stale."));
                None
            }
        }
    }

    fn update_pos(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        // The C++ tests NAV_Y's presence twice and NAV_X's never: a missing NAV_X reads 0.
        let x = ctx.info.num("NAV_X");
        let y = ctx.info.num("NAV_Y");
        let stale = |v: &str| ctx.info.age(v).is_some_and(|a| a > STALE_NAV);
        if y.is_none() || stale("NAV_X") || stale("NAV_Y") {
            out.error("ownship NAV_X/Y not found or stale.");
            return false;
        }
        self.os.0 = x.unwrap_or(0.0);
        self.os.1 = y.unwrap_or(0.0);
        true
    }

    fn update_hdg(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        match Self::fresh(ctx, out, "NAV_HEADING", "NAV_HEADING") {
            Some(h) => {
                self.os.2 = h;
                true
            }
            None => false,
        }
    }

    fn update_spd(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        match Self::fresh(ctx, out, "NAV_SPEED", "NAV_SPEED") {
            Some(v) => {
                self.os.3 = v;
                true
            }
            None => false,
        }
    }

    fn post_flags(&self, flags: &[Flag], out: &mut Out) {
        for f in flags {
            out.flag(&self.flag_now(f), false);
        }
    }

    /// `f` with this behaviour's macros expanded now, as the C++ does when it posts a flag.
    fn flag_now(&self, f: &Flag) -> Flag {
        let mut f = f.clone();
        if let FlagValue::String(s) = &mut f.value
            && s.contains('$')
        {
            for m in MACROS {
                for pat in [format!("$[{m}]"), format!("$({m})")] {
                    if s.contains(&pat) {
                        let mut v = String::new();
                        self.macro_value(m, &mut v);
                        *s = s.replace(&pat, &v).into();
                    }
                }
            }
        }
        f
    }

    /// MOOS `setState`: the port/star flags of a new leg, unless the legs are done.
    fn set_leg(&mut self, leg: Leg, out: &mut Out) {
        if self.leg == leg {
            return;
        }
        if leg == Leg::Star && !self.legs_complete() {
            self.post_flags(&self.flags.star.clone(), out);
        }
        if leg == Leg::Port && !self.legs_complete() {
            self.post_flags(&self.flags.port.clone(), out);
        }
        self.leg = leg;
    }

    fn update_odometry(&mut self) {
        let (x, y) = (self.os.0, self.os.1);
        self.odometer.update(x, y);
        self.zig_odo.update(x, y);
        self.zag_odo.update(x, y);
        let s = self.stem;
        if s.a.x == 0.0 && s.a.y == 0.0 && s.b.x == 0.0 && s.b.y == 0.0 {
            return;
        }
        let foot = s.line_foot(x, y);
        self.stem_dist = (x - foot.x).hypot(y - foot.y);
        let on_seg = s.closest_point(x, y);
        self.stem_odo = (s.a.x - on_seg.x).hypot(s.a.y - on_seg.y);
    }

    fn reset_odometry(&mut self) {
        self.odometer.reset();
        self.zig_odo.reset();
        self.zag_odo.reset();
        self.stem_dist = 0.0;
        self.stem_odo = 0.0;
    }

    fn update_set_hdg(&mut self, out: &mut Out) {
        if self.leg == Leg::Stem {
            if self.zig_first_star {
                self.set_leg(Leg::Star, out);
                self.set_hdg = geometry::angle_360(self.stem_hdg + self.zig_angle);
            } else {
                self.set_leg(Leg::Port, out);
                self.set_hdg = geometry::angle_360(self.stem_hdg - self.zig_angle);
            }
            return;
        }
        let (osh, osv) = (self.os.2, self.os.3);
        let diff = geometry::angle::angle_diff(osh, self.set_hdg);
        let turn_complete = if diff < self.hdg_thresh {
            true
        } else if self.leg == Leg::Port {
            !geometry::angle::contains_angle(osh, osh - 170.0, self.set_hdg)
        } else {
            !geometry::angle::contains_angle(osh, osh + 170.0, self.set_hdg)
        };
        if self.zig_spd_min < 0.0 || osv < self.zig_spd_min {
            self.zig_spd_min = osv;
        }
        self.zig_spd_delta = self.zig_spd_start - self.zig_spd_min;
        if !turn_complete {
            return;
        }
        self.zig_cnt += 1;
        self.zig_cnt_ever += 1;
        self.post_flags(&self.flags.zig.clone(), out);
        if self.zig_cnt.is_multiple_of(2) {
            self.post_flags(&self.flags.zag.clone(), out);
        }
        if self.leg == Leg::Port {
            self.post_flags(&self.flags.portx.clone(), out);
            self.set_leg(Leg::Star, out);
            self.set_hdg = geometry::angle_360(self.stem_hdg + self.zig_angle);
        } else {
            self.post_flags(&self.flags.starx.clone(), out);
            self.set_leg(Leg::Port, out);
            self.set_hdg = geometry::angle_360(self.stem_hdg - self.zig_angle);
        }
        self.zig_odo.reset();
        if self.zig_cnt.is_multiple_of(2) {
            self.zag_odo.reset();
        }
        // As the C++: the heading, not the speed.
        self.zig_spd_start = osh;
        self.zig_spd_min = -1.0;
        self.zig_spd_delta = 0.0;
    }

    fn update_req_hdg(&mut self) {
        let req = if !self.fierce_zigging {
            self.set_hdg
        } else {
            let delta = if self.zig_angle_fierce > 0.0 {
                self.zig_angle_fierce
            } else {
                self.zig_angle
            };
            match self.leg {
                Leg::Port => self.os.2 - delta,
                Leg::Star => self.os.2 + delta,
                Leg::Stem => self.stem_hdg,
            }
        };
        self.req_hdg = geometry::angle_360(req);
    }

    fn post_hdg_line(&self, ctx: &Ctx<'_>, out: &mut Out, which: &str, hdg: f64, color: &str) {
        let (x, y) = (self.os.0, self.os.1);
        let end = geometry::project_point(x, y, hdg, 20.0);
        let mut s = String::new();
        geometry::spec::write_points(&mut s, &[Point::new(x, y), end], 1);
        s.push_str(",label=zig_");
        s.push_str(which);
        s.push('_');
        s.push_str(ctx.ownship);
        s.push_str(",label_color=invisible");
        if let Some(c) = crate::color::pack(color) {
            s.push_str(",edge_color=");
            s.push_str(&c);
            s.push_str(",vertex_color=");
            s.push_str(&c);
        }
        s.push_str(",duration=5,vertex_size=2,edge_size=1");
        out.post("VIEW_SEGLIST", s);
    }

    fn erase_hdg_line(ctx: &Ctx<'_>, out: &mut Out, which: &str) {
        out.post(
            "VIEW_SEGLIST",
            format!(
                "pts={{0,0:9,0:0,9}},active=false,label=zig_{which}_{}",
                ctx.ownship
            ),
        );
    }

    fn build_of(&self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let spd = match ZaicSpd::new(
            ctx.domain,
            "speed",
            self.speed,
            0.1,
            self.speed + 0.4,
            85.0,
            20.0,
        )
        .and_then(|z| z.extract())
        {
            Ok(f) => f,
            Err(_) => {
                out.warning(ctx.name, "Failure on the SPD ZAIC component");
                return None;
            }
        };
        let crs = ZaicPeak::new(ctx.domain, "course").and_then(|mut z| {
            z.set_value_wrap(true);
            z.set_params(self.req_hdg, 0.0, 180.0, 0.0, 0.0, 100.0)?;
            z.extract()
        });
        let Ok(crs) = crs else {
            out.warning(ctx.name, "Failure on the CRS ZAIC");
            return None;
        };
        match couple_weighted(&crs, &spd, 50.0, 50.0, true) {
            Ok(f) => Some(f),
            Err(_) => {
                out.warning(ctx.name, "Failure on the CRS_SPD COUPLER");
                None
            }
        }
    }

    fn visual_hint(&mut self, hint: &str) -> bool {
        let (p, v) = match hint.split_once('=') {
            Some((p, v)) => (p.trim().to_ascii_lowercase(), v.trim()),
            None => (hint.trim().to_ascii_lowercase(), ""),
        };
        match p.as_str() {
            "draw_set_hdg" => moos_boolean("", v, self.draw_set_hdg)
                .map(|b| self.draw_set_hdg = b)
                .is_ok(),
            "draw_req_hdg" => moos_boolean("", v, self.draw_req_hdg)
                .map(|b| self.draw_req_hdg = b)
                .is_ok(),
            "set_hdg_color" if crate::color::is_color(v) => {
                self.set_hdg_color = v.to_string();
                true
            }
            "req_hdg_color" if crate::color::is_color(v) => {
                self.req_hdg_color = v.to_string();
                true
            }
            _ => false,
        }
    }
}

/// The behaviour's own macros.
const MACROS: [&str; 19] = [
    "ODO",
    "ZIG_ODO",
    "ZAG_ODO",
    "STEM_DIST",
    "STEM_ODO",
    "ZIGS_EVER",
    "ZAGS_EVER",
    "ZIGS_TOGO",
    "ZAGS_TOGO",
    "ZIGS",
    "ZAGS",
    "STEM_HDG",
    "STEM_SPD",
    "ZIG_START_SPD",
    "ZIG_MIN_SPD",
    "ZIG_SPD_DELTA",
    "ZIG_PORT",
    "ZIG_STAR",
    "ZIG_SIDE",
];

/// A number of legs as MOOS `setUIntOnString` reads it (a number ≥ 0, truncated).
fn uint(param: &str, value: &str) -> Result<u32, ParamError> {
    let v = number(param, value)?;
    if v < 0.0 {
        return Err(ParamError::bad(param, value, "a number >= 0"));
    }
    Ok(v as u32)
}

/// An angle in [1, 75].
fn zig_angle(param: &str, value: &str) -> Result<f64, ParamError> {
    let v = number(param, value)?;
    if !(1.0..=75.0).contains(&v) {
        return Err(ParamError::bad(param, value, "a number in [1, 75]"));
    }
    Ok(v)
}

impl Behavior for ZigZag {
    fn kind(&self) -> &'static str {
        "BHV_ZigZag"
    }

    fn default_name(&self) -> &'static str {
        "zig"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course", "speed"]
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_X", "NAV_Y", "NAV_SPEED", "NAV_HEADING"]);
        let f = &self.flags;
        for l in [&f.zig, &f.zag, &f.port, &f.star, &f.portx, &f.starx] {
            add_flag_vars(out, l);
        }
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        let v = value.trim();
        match param {
            "speed" => {
                let s = number(param, v)?;
                if s < 0.0 {
                    return Err(ParamError::bad(param, value, "a number >= 0"));
                }
                self.speed = s;
            }
            "mod_speed" => {
                if v.eq_ignore_ascii_case("reset") {
                    self.speed = self.speed_orig;
                } else {
                    let m = number(param, v)?;
                    let hi = ctx.domain.get("speed").map_or(0.0, |d| d.high());
                    self.speed = (self.speed + m).clamp(0.0, hi.max(0.0));
                }
            }
            "spd_on_active" | "speed_on_active" => {
                self.speed_on_active = moos_boolean(param, v, self.speed_on_active)?
            }
            "stem_hdg" => self.stem_hdg = geometry::angle_360(number(param, v)?),
            "stem_on_active" => self.stem_on_active = moos_boolean(param, v, self.stem_on_active)?,
            "hdg_thresh" => {
                let t = number(param, v)?;
                if t < 0.0 {
                    return Err(ParamError::bad(param, value, "a number >= 0"));
                }
                self.hdg_thresh = t;
            }
            "fierce_zigging" => self.fierce_zigging = moos_boolean(param, v, self.fierce_zigging)?,
            "zig_angle" => self.zig_angle = zig_angle(param, v)?,
            "zig_angle_fierce" | "delta_heading" => self.zig_angle_fierce = zig_angle(param, v)?,
            "zig_first" => match v.to_ascii_lowercase().as_str() {
                "port" | "left" => self.zig_first_star = false,
                "star" | "starboard" | "right" => self.zig_first_star = true,
                _ => return Err(ParamError::bad(param, value, "port or star")),
            },
            "max_zig_legs" => self.max_zig_legs = uint(param, v)?,
            "max_stem_odo" => {
                let o = number(param, v)?;
                if o <= 0.0 {
                    return Err(ParamError::bad(param, value, "a number > 0"));
                }
                self.max_stem_odo = o;
            }
            "max_zig_zags" => {
                if !is_number(v) {
                    return Err(ParamError::bad(param, value, "a number >= 1"));
                }
                let n = number(param, v)?;
                if n < 1.0 {
                    return Err(ParamError::bad(param, value, "a number >= 1"));
                }
                self.max_zig_legs = 2 * (n as u32);
            }
            "zigflag" | "zagflag" | "portflag" | "starflag" | "portflagx" | "starflagx" => {
                let f =
                    Flag::parse(v).ok_or_else(|| ParamError::bad(param, value, "VAR = value"))?;
                let l = &mut self.flags;
                match param {
                    "zigflag" => l.zig.push(f),
                    "zagflag" => l.zag.push(f),
                    "portflag" => l.port.push(f),
                    "starflag" => l.star.push(f),
                    "portflagx" => l.portx.push(f),
                    _ => l.starx.push(f),
                }
            }
            "visual_hints" => {
                for h in geometry::split_unquoted(v, ',') {
                    if !self.visual_hint(h) {
                        return Err(ParamError::bad(
                            param,
                            value,
                            "draw_set_hdg, draw_req_hdg, set_hdg_color or req_hdg_color hints",
                        ));
                    }
                }
            }
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    /// The C++ `onSetParamComplete` is empty: no BHV_SETTINGS.
    fn on_set_param_complete(&mut self, _ctx: &Ctx<'_>, _out: &mut Out) {}

    fn on_idle_to_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        if self.stem_on_active && self.update_hdg(ctx, out) {
            self.stem_hdg = self.os.2;
        }
        if self.speed_on_active && self.update_spd(ctx, out) {
            self.speed = self.os.3;
            self.speed_orig = self.os.3;
        }
        self.update_pos(ctx, out);
        self.zig_cnt = 0;
        self.reset_odometry();
        let (x, y) = (self.os.0, self.os.1);
        let end = geometry::project_point(x, y, self.stem_hdg, 5000.0);
        self.stem = Segment::new(Point::new(x, y), end);
        self.set_leg(Leg::Stem, out);
    }

    fn on_run_to_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        Self::erase_hdg_line(ctx, out, "set");
        Self::erase_hdg_line(ctx, out, "req");
        self.reset_odometry();
        self.zig_cnt = 0;
        self.set_leg(Leg::Stem, out);
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        if !self.update_pos(ctx, out) || !self.update_hdg(ctx, out) || !self.update_spd(ctx, out) {
            return None;
        }
        self.update_odometry();
        self.update_set_hdg(out);
        self.update_req_hdg();
        if self.draw_set_hdg {
            self.post_hdg_line(ctx, out, "set", self.set_hdg, &self.set_hdg_color);
        }
        if self.draw_req_hdg {
            self.post_hdg_line(ctx, out, "req", self.req_hdg, &self.req_hdg_color);
        }
        let stem_done = self.max_stem_odo > 0.0 && self.stem_odo >= self.max_stem_odo;
        if self.legs_complete() || stem_done {
            out.complete();
            return None;
        }
        let f = self.build_of(ctx, out);
        if f.is_none() {
            out.post("ZIG_DEBUG", "Unable to build IvP Function");
        }
        f
    }

    fn macro_value(&self, name: &str, out: &mut String) -> bool {
        let int = |out: &mut String, n: u32| compact(out, f64::from(n), 0);
        let togo = self.max_zig_legs.saturating_sub(self.zig_cnt);
        match name {
            "ODO" => compact(out, self.odometer.total, 3),
            "ZIG_ODO" => compact(out, self.zig_odo.total, 3),
            "ZAG_ODO" => compact(out, self.zag_odo.total, 3),
            "STEM_DIST" => compact(out, self.stem_dist, 2),
            "STEM_ODO" => compact(out, self.stem_odo, 2),
            "ZIGS" => int(out, self.zig_cnt),
            "ZAGS" => int(out, self.zig_cnt / 2),
            "ZIGS_EVER" => int(out, self.zig_cnt_ever),
            "ZAGS_EVER" => int(out, self.zig_cnt_ever / 2),
            "STEM_HDG" => compact(out, self.stem_hdg, 3),
            "STEM_SPD" => compact(out, self.speed_orig, 3),
            "ZIG_START_SPD" => compact(out, self.zig_spd_start, 3),
            "ZIG_MIN_SPD" => compact(out, self.zig_spd_min, 3),
            "ZIG_SPD_DELTA" => compact(out, self.zig_spd_delta, 3),
            "ZIGS_TOGO" | "ZAGS_TOGO" => int(out, togo),
            "ZIG_PORT" => out.push_str(if self.leg == Leg::Port {
                "true"
            } else {
                "false"
            }),
            "ZIG_STAR" => out.push_str(if self.leg == Leg::Star {
                "true"
            } else {
                "false"
            }),
            "ZIG_SIDE" => out.push_str(self.leg.name()),
            _ => return false,
        }
        true
    }
}
