//! BHV_FixedTurn: turns a fixed number of degrees from the heading held when it starts, by
//! steering a fixed offset from the current heading; optionally a schedule of turns.
//!
//! # Conformance with BHV_FixedTurn (MOOS-IvP a2a9b716)
//!
//! | parameter | aliases | type | default | validation (C++ rule) | runtime update | coug |
//! |---|---|---|---|---|---|---|
//! | fix_turn | | deg | 0 | number ≥ 0 | yes | done |
//! | mod_hdg | | deg | 20 | number | yes | done |
//! | turn_dir | | | port | `port`, `star`, `starboard`, `toggle` (any case) | yes | done |
//! | speed | | m/s | 1 | number ≥ 0, or `auto` (the speed when the turn starts) | yes | done |
//! | timeout | | s | −1 (none) | number | yes | done |
//! | turn_delay | | s | −1 (none) | number | yes | done |
//! | turn_spec | | | | `spd=`, `mhdg=`, `fhdg=`/`fix=`, `tdir=`/`turn=`, `key=`, `timeout=`, `flag=` (numbers where numbers are due, `tdir` one of port/star/starboard/auto/rand); `clear`/`clearall` (optionally followed by `,` and a spec) empties the schedule; a spec whose key matches a scheduled turn (or reaches one without a key) updates it | yes | done |
//! | schedule_repeat | | bool | false | MOOS boolean | yes | done |
//! | stale_nav_thresh | | s | 5 | number > 0 | yes | done |
//! | radius_rep_var | | var | none | not empty, no white space (stored only, as in the C++) | yes | done |
//! | visual_hints | | | | MOOS hints (`HintHolder`; read, not drawn, as in the C++) | yes | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | FT_REPORT | each finished turn | `spd=..,mod_hdg=..,rudder_avg=..[,avg_rad=..,min_rad=..,max_rad=..]` | done |
//! | VIEW_SEGLIST | each finished turn: a diameter for each pair of positions 180 degrees of turn apart | labels `<ownship>ft<i>`, gray70 edges, light_green vertices of size 5, 60 s | done |
//! | VIEW_SEGLIST | when the next turn starts | those diameters erased (`pts={0,0:9,0:0,9},active=false,label=..`, labels in string order) | done |
//! | the turn's `flag=` flags | each finished turn | flags | done |
//! | BHV_ERROR | NAV_X/Y, NAV_HEADING or NAV_SPEED missing or older than `stale_nav_thresh` | `ownship NAV_... not found or stale.` | done |
//!
//! Macros: `TURN_DIST` (1 decimal), `TURN_TIME`, `TURN_RAD`. The behaviour completes when the
//! heading has turned `fix_turn` degrees in the turn's direction (turning the other way
//! counts against it) or the turn's `timeout` is over; a perpetual one then starts afresh.
//! Its endflags see the finished turn's macros, as in the C++ (which posts them before the
//! reset). The objective function is ZigZag's: ZAIC_PEAK on course (summit the heading ∓
//! the offset, base width 180, wrapping) coupled 50/50 with ZAIC_SPD on speed (the turn speed;
//! 0.1 and speed + 0.4 at 85 and 20), normalised to [0, 100]; during a `turn_delay` the
//! offset is 0.

use std::collections::BTreeSet;

use geometry::Point;
use ivp::{IvpFunction, ZaicPeak, ZaicSpd, couple_weighted};
use moos_types::fmt::compact;

use crate::behavior::{Behavior, Ctx, Out, ParamError, add_vars};
use crate::color::Hints;
use crate::common::{Common, Flag, FlagValue};
use crate::param::{is_number, moos_boolean, number};

/// One scheduled turn (MOOS `FixedTurn`): values ≤ 0 (and direction `auto`) defer to the
/// behaviour's own settings.
#[derive(Debug, Clone)]
pub struct ScheduledTurn {
    /// Turn speed (−1 = unset).
    pub spd: f64,
    /// Heading offset (−1 = unset).
    pub mod_hdg: f64,
    /// Degrees to turn (−1 = unset).
    pub fix_hdg: f64,
    /// Timeout (−1 = unset).
    pub timeout: f64,
    /// Key naming the turn ("" = none).
    pub key: String,
    /// `port`, `star` or `auto`.
    pub dir: String,
    /// Flags posted when the turn is done.
    pub flags: Vec<Flag>,
}

impl Default for ScheduledTurn {
    fn default() -> Self {
        ScheduledTurn {
            spd: -1.0,
            mod_hdg: -1.0,
            fix_hdg: -1.0,
            timeout: -1.0,
            key: String::new(),
            dir: "auto".into(),
            flags: Vec::new(),
        }
    }
}

impl ScheduledTurn {
    /// Applies a `turn_spec` (all or nothing); false if any piece is bad or its key names
    /// another turn.
    fn set_spec(&mut self, spec: &str) -> bool {
        let (mut spd, mut mhdg, mut fhdg, mut key, mut dir, mut timeout) =
            ("", "", "", "", String::new(), "");
        let mut flags = Vec::new();
        for piece in geometry::split_unquoted(spec, ',') {
            let (p, v) = piece.split_once('=').unwrap_or((piece, ""));
            let (p, v) = (p.trim(), v.trim());
            match p {
                "spd" => spd = v,
                "mhdg" => mhdg = v,
                "fhdg" | "fix" => fhdg = v,
                "tdir" | "turn" => dir = v.to_ascii_lowercase(),
                "key" => key = v,
                "timeout" => timeout = v,
                "flag" => flags.push(v),
                _ => return false,
            }
        }
        if !key.is_empty() && !self.key.is_empty() && key != self.key {
            return false;
        }
        if spd == "auto" {
            spd = "-1";
        }
        let num_ok = |s: &str| s.is_empty() || is_number(s);
        if !num_ok(spd) || !num_ok(mhdg) || !num_ok(fhdg) || !num_ok(timeout) {
            return false;
        }
        if !matches!(
            dir.as_str(),
            "port" | "star" | "starboard" | "auto" | "rand" | ""
        ) {
            return false;
        }
        let mut parsed = Vec::new();
        for f in flags {
            match Flag::parse(f) {
                Some(f) => parsed.push(f),
                None => return false,
            }
        }
        let set = |s: &str, slot: &mut f64| {
            if !s.is_empty() {
                *slot = crate::param::atof(s);
            }
        };
        set(spd, &mut self.spd);
        set(mhdg, &mut self.mod_hdg);
        set(fhdg, &mut self.fix_hdg);
        set(timeout, &mut self.timeout);
        // MOOS `setPortStarOnString`: `rand` and `auto` leave the direction as it was.
        match dir.as_str() {
            "port" => self.dir = "port".into(),
            "star" | "starboard" => self.dir = "star".into(),
            _ => {}
        }
        if !key.is_empty() {
            self.key = key.to_string();
        }
        self.flags.extend(parsed);
        true
    }
}

/// The schedule of turns (MOOS `FixedTurnSet`).
#[derive(Debug, Clone, Default)]
struct TurnSet {
    turns: Vec<ScheduledTurn>,
    ix: usize,
    repeats: bool,
}

impl TurnSet {
    fn set_spec(&mut self, spec: &str) -> bool {
        let lower = spec.to_ascii_lowercase();
        if lower == "clear" || lower == "clearall" {
            self.turns.clear();
            self.ix = 0;
            return true;
        }
        let mut spec = spec;
        if lower.starts_with("clear,") || lower.starts_with("clearall,") {
            self.turns.clear();
            self.ix = 0;
            spec = spec.split_once(',').map_or("", |(_, r)| r).trim();
        }
        let mut turn = ScheduledTurn::default();
        if !turn.set_spec(spec) {
            return false;
        }
        if turn.key.is_empty() {
            self.turns.push(turn);
            return true;
        }
        for t in &mut self.turns {
            if t.set_spec(spec) {
                return true;
            }
        }
        self.turns.push(turn);
        true
    }

    /// The current turn, or the unset turn past the end.
    fn current(&self) -> ScheduledTurn {
        self.turns.get(self.ix).cloned().unwrap_or_default()
    }

    fn increment(&mut self) {
        self.ix += 1;
        if self.repeats && self.ix >= self.turns.len() {
            self.ix = 0;
        }
    }
}

/// Distance and elapsed time since a reset (MOOS `Odometer`).
#[derive(Debug, Clone, Default)]
struct TurnOdometer {
    prev: Option<(f64, f64)>,
    dist: f64,
    start: f64,
    curr: f64,
}

impl TurnOdometer {
    fn reset(&mut self, utc: f64) {
        *self = TurnOdometer {
            start: utc,
            curr: utc,
            ..TurnOdometer::default()
        };
    }
    fn update(&mut self, x: f64, y: f64, utc: f64) {
        if let Some((px, py)) = self.prev {
            self.dist += (x - px).hypot(y - py);
        }
        self.prev = Some((x, y));
        if self.start == 0.0 {
            self.start = utc;
        }
        self.curr = utc;
    }
    fn elapsed(&self) -> f64 {
        self.curr - self.start
    }
}

/// Where the behaviour is in its turn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum TurnState {
    Stem,
    Delay,
    Turning,
}

/// Turns `fix_turn` degrees by steering `mod_hdg` off the current heading.
#[derive(Debug, Clone)]
pub struct FixedTurn {
    /// Degrees to turn.
    pub fix_turn: f64,
    /// Offset from the current heading steered, degrees.
    pub mod_hdg: f64,
    /// Turn to port (else starboard).
    pub port_turn: bool,
    /// Seconds before giving up (≤ 0 = never).
    pub timeout: f64,
    /// Turn speed, m/s (−1 = the speed at the turn's start).
    pub cruise_spd: f64,
    /// Seconds straight before turning (≤ 0 = none).
    pub turn_delay: f64,
    /// Seconds after which navigation is stale.
    pub stale_nav_thresh: f64,
    /// `radius_rep_var` (stored only).
    pub radius_rep_var: String,
    hints: Hints,
    schedule: TurnSet,
    // State.
    state: TurnState,
    os: (f64, f64, f64, f64),
    osh_prev: f64,
    stem_spd: f64,
    delay_start: f64,
    hdg_delta_sofar: f64,
    rudder: f64,
    last_turn_rad: f64,
    marks: Vec<Option<Point>>,
    mark_rudder: Vec<f64>,
    odometer: TurnOdometer,
    radials: BTreeSet<String>,
    /// The finished turn's macros, for the endflags of a perpetual behaviour (reset since).
    finished: Option<(f64, f64, f64)>,
}

impl Default for FixedTurn {
    fn default() -> Self {
        Self::new()
    }
}

impl FixedTurn {
    /// The MOOS defaults.
    pub fn new() -> Self {
        FixedTurn {
            fix_turn: 0.0,
            mod_hdg: 20.0,
            port_turn: true,
            timeout: -1.0,
            cruise_spd: 1.0,
            turn_delay: -1.0,
            stale_nav_thresh: 5.0,
            radius_rep_var: String::new(),
            hints: Hints::default(),
            schedule: TurnSet::default(),
            state: TurnState::Stem,
            os: (0.0, 0.0, 0.0, 0.0),
            osh_prev: 0.0,
            stem_spd: 0.0,
            delay_start: -1.0,
            hdg_delta_sofar: 0.0,
            rudder: 0.0,
            last_turn_rad: -1.0,
            marks: vec![None; 360],
            mark_rudder: Vec::new(),
            odometer: TurnOdometer::default(),
            radials: BTreeSet::new(),
            finished: None,
        }
    }

    fn reset_state(&mut self) {
        self.state = TurnState::Stem;
        self.odometer.reset(0.0);
        self.osh_prev = 0.0;
        self.stem_spd = 0.0;
        self.hdg_delta_sofar = 0.0;
        self.rudder = 0.0;
        self.last_turn_rad = -1.0;
        self.marks = vec![None; 360];
        self.mark_rudder.clear();
    }

    fn turn_spd(&self) -> f64 {
        let t = self.schedule.current();
        if t.spd > 0.0 {
            t.spd
        } else if self.cruise_spd < 0.0 {
            self.stem_spd
        } else {
            self.cruise_spd
        }
    }

    fn curr_mod_hdg(&self) -> f64 {
        if self.state == TurnState::Delay {
            return 0.0;
        }
        let t = self.schedule.current();
        if t.mod_hdg > 0.0 {
            t.mod_hdg
        } else {
            self.mod_hdg
        }
    }

    fn fix_turn_now(&self) -> f64 {
        let t = self.schedule.current();
        if t.fix_hdg > 0.0 {
            t.fix_hdg
        } else {
            self.fix_turn
        }
    }

    fn port_now(&self) -> bool {
        match self.schedule.current().dir.as_str() {
            "port" => true,
            "star" => false,
            _ => self.port_turn,
        }
    }

    fn timeout_now(&self) -> f64 {
        let t = self.schedule.current();
        if t.timeout > 0.0 {
            t.timeout
        } else {
            self.timeout
        }
    }

    fn fresh(&self, ctx: &Ctx<'_>, var: &str) -> Option<f64> {
        match (ctx.info.num(var), ctx.info.age(var)) {
            (Some(v), Some(age)) if age <= self.stale_nav_thresh => Some(v),
            _ => None,
        }
    }

    fn update_nav(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        // As the C++ (and BHV_ZigZag): NAV_Y's presence is tested, NAV_X's only its age.
        let stale = |v: &str| ctx.info.age(v).is_some_and(|a| a > self.stale_nav_thresh);
        if ctx.info.num("NAV_Y").is_none() || stale("NAV_X") || stale("NAV_Y") {
            out.error("ownship NAV_X/Y not found or stale.");
            return false;
        }
        self.os.0 = ctx.info.num("NAV_X").unwrap_or(0.0);
        self.os.1 = ctx.info.num("NAV_Y").unwrap_or(0.0);
        let Some(h) = self.fresh(ctx, "NAV_HEADING") else {
            out.error("ownship NAV_HEADING not found or stale.");
            return false;
        };
        self.os.2 = h;
        let Some(v) = self.fresh(ctx, "NAV_SPEED") else {
            out.error("ownship NAV_SPEED not found or stale.");
            return false;
        };
        self.os.3 = v;
        true
    }

    /// MOOS `handleNewHdg`: true when the turn is done.
    fn handle_new_hdg(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        let now = ctx.info.now();
        let osh = self.os.2;
        if self.state == TurnState::Stem && self.turn_delay > 0.0 {
            self.state = TurnState::Delay;
            self.delay_start = now;
            return false;
        }
        if self.state == TurnState::Delay && now - self.delay_start < self.turn_delay {
            return false;
        }
        if self.state != TurnState::Turning {
            self.state = TurnState::Turning;
            self.osh_prev = osh;
            self.stem_spd = self.os.3;
            self.hdg_delta_sofar = 0.0;
            self.odometer.reset(now);
            for label in std::mem::take(&mut self.radials) {
                out.post(
                    "VIEW_SEGLIST",
                    format!("pts={{0,0:9,0:0,9}},active=false,label={label}"),
                );
            }
        }
        let mut delta = geometry::angle::angle_diff(self.osh_prev, osh);
        if delta > 0.0 {
            let delta_port = !(osh > self.osh_prev || self.osh_prev - osh > 180.0);
            if self.port_now() != delta_port {
                delta = -delta;
            }
            self.hdg_delta_sofar += delta;
            let ix = geometry::angle_360(self.hdg_delta_sofar) as usize;
            if ix < 360 {
                let here = Point::new(self.os.0, self.os.1);
                self.marks[ix] = Some(match self.marks[ix] {
                    Some(p) => Point::new((p.x + here.x) / 2.0, (p.y + here.y) / 2.0),
                    None => here,
                });
            }
            self.mark_rudder.push(self.rudder);
        }
        self.osh_prev = osh;
        if self.hdg_delta_sofar < self.fix_turn_now() {
            return false;
        }
        self.state = TurnState::Stem;
        true
    }

    fn post_report(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        let (mut min, mut max, mut total, mut count) = (-1.0f64, -1.0f64, 0.0, 0u32);
        let mut diameters = Vec::new();
        for i in 0..180 {
            if let (Some(a), Some(b)) = (self.marks[i], self.marks[i + 180]) {
                let rad = a.dist(&b) / 2.0;
                if min < 0.0 || rad < min {
                    min = rad;
                }
                if max < 0.0 || rad > max {
                    max = rad;
                }
                total += rad;
                count += 1;
                diameters.push([a, b]);
            }
        }
        for (i, pts) in diameters.iter().enumerate() {
            let label = format!("{}ft{i}", ctx.ownship);
            let mut s = String::new();
            geometry::spec::write_points(&mut s, pts, 1);
            s.push_str(",label=");
            s.push_str(&label);
            s.push_str(
                ",label_color=invisible,edge_color=gray70,vertex_color=light_green,\
                 duration=60,vertex_size=5",
            );
            out.post("VIEW_SEGLIST", s);
            self.radials.insert(label);
        }
        let rudder_avg = if self.mark_rudder.is_empty() {
            0.0
        } else {
            self.mark_rudder.iter().sum::<f64>() / self.mark_rudder.len() as f64
        };
        let mut r = String::from("spd=");
        compact(&mut r, self.turn_spd(), 5);
        r.push_str(",mod_hdg=");
        compact(&mut r, self.curr_mod_hdg(), 5);
        r.push_str(",rudder_avg=");
        compact(&mut r, rudder_avg, 1);
        if total > 0.0 {
            let avg = if count > 0 {
                let a = total / f64::from(count);
                self.last_turn_rad = a;
                a
            } else {
                0.0
            };
            for (k, v) in [("avg_rad", avg), ("min_rad", min), ("max_rad", max)] {
                r.push(',');
                r.push_str(k);
                r.push('=');
                compact(&mut r, v, 2);
            }
        }
        out.post("FT_REPORT", r);
    }

    fn flag_now(&self, f: &Flag) -> Flag {
        let mut f = f.clone();
        if let FlagValue::String(s) = &mut f.value
            && s.contains('$')
        {
            for m in ["TURN_DIST", "TURN_TIME", "TURN_RAD"] {
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

    fn build_of(&self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let spd = self.turn_spd();
        let Ok(spd_f) = ZaicSpd::new(ctx.domain, "speed", spd, 0.1, spd + 0.4, 85.0, 20.0)
            .and_then(|z| z.extract())
        else {
            out.warning(ctx.name, "Failure on the SPD ZAIC component");
            return None;
        };
        let m = self.curr_mod_hdg();
        let hdg = geometry::angle_360(if self.port_now() {
            self.os.2 - m
        } else {
            self.os.2 + m
        });
        let crs = ZaicPeak::new(ctx.domain, "course").and_then(|mut z| {
            z.set_value_wrap(true);
            z.set_params(hdg, 0.0, 180.0, 0.0, 0.0, 100.0)?;
            z.extract()
        });
        let Ok(crs) = crs else {
            out.warning(ctx.name, "Failure on the CRS ZAIC");
            return None;
        };
        match couple_weighted(&crs, &spd_f, 50.0, 50.0, true) {
            Ok(f) => Some(f),
            Err(_) => {
                out.warning(ctx.name, "Failure on the CRS_SPD COUPLER");
                None
            }
        }
    }
}

/// A number with a rule, refused as MOOS refuses it.
fn num_rule(
    param: &str,
    value: &str,
    ok: fn(f64) -> bool,
    expected: &'static str,
) -> Result<f64, ParamError> {
    let v = number(param, value)?;
    if !ok(v) {
        return Err(ParamError::bad(param, value, expected));
    }
    Ok(v)
}

impl Behavior for FixedTurn {
    fn kind(&self) -> &'static str {
        "BHV_FixedTurn"
    }

    fn default_name(&self) -> &'static str {
        "fixturn"
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course", "speed"]
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(
            out,
            [
                "NAV_X",
                "NAV_Y",
                "NAV_SPEED",
                "NAV_HEADING",
                "DESIRED_RUDDER",
                "DESIRED_RUDDERX",
            ],
        );
    }

    fn set_param(
        &mut self,
        param: &str,
        value: &str,
        _common: &mut Common,
        _ctx: &Ctx<'_>,
    ) -> Result<(), ParamError> {
        let v = value.trim();
        match param {
            "fix_turn" => self.fix_turn = num_rule(param, v, |x| x >= 0.0, "a number >= 0")?,
            "mod_hdg" => self.mod_hdg = number(param, v)?,
            "turn_dir" => match v.to_ascii_lowercase().as_str() {
                "toggle" => self.port_turn = !self.port_turn,
                "port" => self.port_turn = true,
                "star" | "starboard" => self.port_turn = false,
                _ => return Err(ParamError::bad(param, value, "port, star or toggle")),
            },
            "speed" if v == "auto" => self.cruise_spd = -1.0,
            "speed" => self.cruise_spd = num_rule(param, v, |x| x >= 0.0, "a number >= 0 or auto")?,
            "timeout" => self.timeout = number(param, v)?,
            "turn_delay" => self.turn_delay = number(param, v)?,
            "turn_spec" => {
                if !self.schedule.set_spec(v) {
                    return Err(ParamError::bad(param, value, "a turn spec"));
                }
            }
            "stale_nav_thresh" => {
                self.stale_nav_thresh = num_rule(param, v, |x| x > 0.0, "a number > 0")?
            }
            "radius_rep_var" => {
                if v.is_empty() || v.contains(char::is_whitespace) {
                    return Err(ParamError::bad(param, value, "a variable name"));
                }
                self.radius_rep_var = v.to_string();
            }
            "schedule_repeat" => {
                self.schedule.repeats = moos_boolean(param, v, self.schedule.repeats)?
            }
            "visual_hints" => {
                if !self.hints.set_hints(v) {
                    return Err(ParamError::bad(param, value, "visual hints"));
                }
            }
            _ => return Err(ParamError::unknown(param)),
        }
        Ok(())
    }

    fn on_idle_to_run(&mut self, _ctx: &Ctx<'_>, _out: &mut Out) {
        self.state = TurnState::Stem;
    }

    fn on_run_to_idle(&mut self, _ctx: &Ctx<'_>, _out: &mut Out) {
        self.state = TurnState::Stem;
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        self.finished = None;
        if !self.update_nav(ctx, out) {
            return None;
        }
        if let Some(r) = ctx.info.num("DESIRED_RUDDER") {
            self.rudder = r;
        } else if ctx.info.text("DESIRED_RUDDER").is_some() {
            self.rudder = 0.0;
        } else if let Some(r) = ctx.info.num("DESIRED_RUDDERX") {
            self.rudder = r;
        }
        let now = ctx.info.now();
        self.odometer.update(self.os.0, self.os.1, now);
        let timeout = self.timeout_now();
        let timed_out = timeout > 0.0 && self.odometer.elapsed() > timeout;
        let turned = self.handle_new_hdg(ctx, out);
        if timed_out || turned {
            self.post_report(ctx, out);
            out.complete();
            for f in self.schedule.current().flags {
                out.flag(&self.flag_now(&f), false);
            }
            self.schedule.increment();
            if ctx.perpetual {
                self.finished = Some((
                    self.odometer.dist,
                    self.odometer.elapsed(),
                    self.last_turn_rad,
                ));
                self.reset_state();
            }
            return None;
        }
        let f = self.build_of(ctx, out);
        if f.is_none() {
            out.warning(ctx.name, "Unable to build IvP Function");
        }
        f
    }

    fn macro_value(&self, name: &str, out: &mut String) -> bool {
        let (dist, time, rad) = self.finished.unwrap_or((
            self.odometer.dist,
            self.odometer.elapsed(),
            self.last_turn_rad,
        ));
        match name {
            "TURN_DIST" => compact(out, dist, 1),
            "TURN_TIME" => compact(out, time, 3),
            "TURN_RAD" => compact(out, rad, 3),
            _ => return false,
        }
        true
    }
}
