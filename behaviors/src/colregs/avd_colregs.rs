//! BHV_AvdColregsV22 and its siblings V17, V19 and V26 (MOOS-IvP
//! `lib_behaviors-colregs/BHV_AvdColregsV*.cpp` at a2a9b716): collision avoidance with one
//! contact by the COLREGS rules, a constraint over course and speed.
//!
//! # Modes
//!
//! Each running iteration the behaviour classifies the encounter from the pair's geometry
//! ([`ContactState`]) into an avoid mode and submode, then builds the mode's function:
//!
//! | mode | rule | entry (from `none` or `cpa`) | release | function |
//! |---|---|---|---|---|
//! | `overtaking:port/starboard` | 13 | ownship within ±`overtaking_bng_range` (67.5°) of the contact's stern, closing, and on a course that passes it; submode the side away from the contact | range ≥ `pwt_outer_dist` or opening; to `cpa:cpa` once the contact angle is within 22.5° of its bow; the side flips with a 5° buffer | [`AofR13`] |
//! | `headon` | 14 | range < 2·`pwt_outer_dist`, both relative bearings within `headon_abs_relbng_thresh` (12°) of dead ahead | opening beyond `min_util_cpa_dist`; ownship aft of the contact; both starboard of each other by more than 5°/7.5° past the threshold | [`AofR14`] |
//! | `standon_ot:port/starboard/inextremis` | 17 (overtaken) | the contact within 112.5°..247.5° of ownship's bow, on a course that passes ownship, its CPA at most `max_util_cpa_dist` | the contact crosses ownship's bow-stern line, or opening | hold course and speed (ZAICs) or, in extremis, [`AofCpa`] |
//! | `giveway:stern/bow` | 15/16 | contact angle ≥ 247.5° and the contact within 112.5° of ownship's bow (it is on our starboard side); `bow` when ownship already crosses ahead by more than `giveway_bow_dist` (default (2·max + min)/3) or cannot turn behind it, or runs alongside | to `cpa` when opening beyond `min_util_cpa_dist` or once ownship is on the contact's starboard side | [`AofR16`] |
//! | `standon:bow/stern/unsure*/neither/inextremis` | 17 | the contact on ownship's port bow (≥ 247.5°) seeing ownship on its starboard side (≤ 112.5°), crossing ownship's bow-stern line and closing; the submode from the contact's bow-crossing distance, its relative bearing band and its turn rate over the last 5 s | the contact crosses ownship's bow-stern line; opening beyond `min_util_cpa_dist` | hold course and speed (ZAICs) or, in extremis, [`AofCpa`] |
//! | `cpa` | catch-all | within `pwt_outer_dist` | beyond it | [`AofCpa`] |
//!
//! The relevance (weight factor) is 0 at or beyond `pwt_outer_dist`, 1 within
//! `pwt_inner_dist`, and the graded (`pwt_grade`) fraction between. Stand-on holds the course
//! and speed ownship had when it entered the mode: course ZAIC_HDG (summit, ±20°, 25 at the
//! deltas), speed ZAIC_SPD (summit, 0.1, summit + 0.4, 50/50), coupled 50/50.
//!
//! # Versions
//!
//! [`Version`] selects what the C++ classes do differently over the same engine:
//!
//! | | V17 | V19 | V22 | V26 |
//! |---|---|---|---|---|
//! | completes at range ≥ | `completed_dist` | 1.1·`completed_dist` | 1.1·`completed_dist` | 1.1·`completed_dist` |
//! | head-on time on leg | 120 | `time_on_leg` | `time_on_leg` | `time_on_leg` |
//! | give-way / CPA time on leg | 120 | 120 | 120 | `time_on_leg` |
//! | give-way function | fails (`Unable to init AOF_R16:bad param[osh]...`, BHV_ERROR) | AOF_R16 | AOF_R16 (`pts_port_turns_ok`) | as V22 |
//! | `giveway_bow_dist` upper clip | refused | `max_util_cpa_dist` | 2·`max_util_cpa_dist` | as V22 |
//! | `verbose`, `use_refinery`, `check_plateaus`, `check_validity`, `pcheck_thresh`, `can_disable` | refused | yes | yes | yes |
//! | `headon_only`, `eval_tol`, `velocity_filter`, `post_status_info_on_idle`, `pts_port_turns_ok` | refused | refused | yes | yes |
//! | relevance posting | `COL17_RELEVANCE` | `COL19_RELEVANCE` | `COL22_RELEVANCE_<CN>` (per-contact info) | as V22 |
//! | `AVD_INFO` each running iteration | no | `V19 CN:<cn>  Mode:<mode>:<sub>` | no | no |
//! | `HEADON_DEBUG_<US>`, `XCN_BOW_DIST_<CN>`, `XCN_BOW_TURN_GAP_<CN>` | always | always | per-contact info | as V22 |
//! | status on idle | always | always | `post_status_info_on_idle` | as V22 |
//! | `VIEW_SEGLIST` | the mode line (`<us><name>`, msg the mode) with every status | as V17 | the bearing line with a function | as V22 |
//! | macros `AVD_MODE`, `AVD_SMODE`, `APWT`, `MODE_ID`, `FULL_MODE` | no | no | yes | yes |
//! | CPA engine | OG | OG | OG | platform model (see below) |
//!
//! # Conformance with BHV_AvdColregsV22 (MOOS-IvP a2a9b716)
//!
//! The contact parameters (`contact`, `decay`, filters, bearing lines, ...) are those of
//! [`crate::contact`]'s table; `time_on_leg` defaults to 120.
//!
//! | parameter | default | validation (C++ rule) | coug |
//! |---|---|---|---|
//! | pwt_outer_dist | 100 | number >= 0; pwt_inner_dist lowered to it | done |
//! | pwt_inner_dist | 90 | number >= 0; pwt_outer_dist raised to it | done |
//! | min_util_cpa_dist | 10 | number >= 0; max raised to it | done |
//! | max_util_cpa_dist | 75 | number >= 0; min lowered to it | done |
//! | completed_dist | 100 | number >= 0; pwt_outer/inner_dist lowered to it | done |
//! | giveway_bow_dist | -1 (off) | number >= 0, clipped to [min_util, 2·max_util]; completed_dist raised to pwt_outer_dist | done |
//! | turn_radius | 0 | number >= 0; as above | done |
//! | avoid_mode, avoid_submode | none | a mode (`headon`, `giveway`, `none`, `overtaking`, `standon`, `cpa`) and a submode that mode allows | done |
//! | pwt_grade | linear | linear, quadratic, quasi (any case) | done |
//! | contact_type_required | "" | any non-empty text (lowered); empty refused | done (kept; unused by the C++) |
//! | no_alert_request, headon_only, verbose, use_refinery, check_plateaus, check_validity, post_status_info_on_idle, pts_port_turns_ok, can_disable | false, false, false, false, false, false, false, true, false | boolean | done; `use_refinery` (V19 and later): the catch-all CPA function (mode `cpa`, stand-on in extremis) gets the plateau regions of [`crate::refinery_cpa`] (MOOS `RefineryCPA` with the behaviour's `time_on_leg` and its unhalved `min_util_cpa_dist`, whatever time on leg the AOF uses), fitted as any piece since AOF_CPA does not know its extremes; `check_plateaus` with it: the checks and their postings; `verbose` and `check_validity` are read and change nothing (the C++ prints with `verbose` and never reads `check_validity`); `can_disable` done: `BHV_ABLE_FILTER` disables, enables or expunges the behaviour (V19 and later; `on_disabled` as the C++ `onDisabledState`) |
//! | pcheck_thresh | 0.001 | number >= 0 | done: the checks' threshold (outside `[0, 1]` the reflector keeps 0.001; the C++ posts none of its warnings here) |
//! | eval_tol | 120 (the time on leg) | number in [5, 300] | done |
//! | velocity_filter | off | `min_spd=..,max_spd=..,pct=..`, valid ([`VelocityFilter`]) | done |
//!
//! | variable | when | format | coug |
//! |---|---|---|---|
//! | BCM_ALERT_REQUEST | helm start, for a spawning template with `updates`, unless `no_alert_request` | as BHV_AvoidCollision's, `alert_range` = pwt_outer_dist | done |
//! | COL22_RELEVANCE_<CN>, COL22_AVOID_MODE_<CN> | running, per-contact info | relevance, mode | done |
//! | CN_FORE_OF_OS_<CN>, CN_PORT_OF_OS__<CN>, CN_CROSSED_OS_PORT_STAR_<CN>, AVDCOL_RANGE_<CN>, COLREGS_AVOID_MODE_<CN>, COLREGS_SUMMARY_<CN>, COLREGS_AVOID_IX_<CN> (repeatable), COLREGS_AVOID_PWT_<CN> (repeatable), COLREGS_CONTACT_HDG_<CN> | each status, per-contact info | 1/0, range, `mode:sub`, `mode=mode:sub`, the mode index (3 complete, 10 head-on, 20/22/25 give-way, 30..39 stand-on, 43/47 overtaking, 50 cpa), pwt | done |
//! | HEADON_DEBUG_<US>, XCN_BOW_DIST_<CN>, XCN_BOW_TURN_GAP_<CN> | mode checks, per-contact info | text, distances | done |
//! | AOF_R16 | the reflector's messages | text | none: coug's reflector has no messages |
//! | VIEW_SEGLIST | bearing lines configured | see [`crate::contact`] | done |
//! | PLATEAU_CHECK_OK, BASIN_CHECK_OK | `check_plateaus` with `use_refinery`, each refined CPA function | `true`/`false` (on change): the plateau check fails (answers 1) whenever there is a region, AOF_CPA's extremes being unknown; the basin check holds (no basin) | done |
//! | PLATEAU_LOGIC_CASE | as above | `aft`, `fore_in_rgam`, `fore_out_rgam` (repeatable) | done |
//! | PLATEAU_WORST_FAIL | as above, per failed check (plateaus, then basins) | the worst difference (repeatable) | done |
//!
//! V26 evaluates its functions with MOOS-IvP's platform-model engine (`CPXEnginePM`): with
//! the helm's Dubins model (`pmgen = alg=dubins`) the CPA and the passing and crossing
//! predicates of each course follow the model's turn to it ([`super::plat_cpx`]); with the
//! holonomic model (the default) the path is a ray and V26's functions are the OG engine's,
//! as before. Its contact state (modes, postings) comes from the platform-model engines as
//! the C++ works it out ([`super::plat_cpx::contact_state`]): the forward engine holds the
//! model V26 handed it on its previous running iteration (none before the first: the empty
//! model, a ray from the origin), the reverse engine never gets one. `use_plat_model =
//! false` puts V26 on the OG engines (contact state and functions), as in the C++; with
//! `use_plat_model = true` V17, V19 and V22 get the platform-model engines without a model
//! (the C++ never hands them one): their contact state and their CPA, passing and crossing
//! follow rays from the origin ([`crate::contact`]).

use crate::refinery_cpa::{
    PairGeometry, RefineryCpa, RefinerySettings, distances_cpa, post_colregs_checks,
    reflect_refined,
};
use ivp::{IvpFunction, ZaicHdg, ZaicSpd};

use super::geometry::{Cpx, project_point, speed_in_heading, turn_gap};
use super::{AofCpa, AofR13, AofR14, AofR16, Distances, GiveWaySide, VelocityFilter, reflect};
use crate::PwtGrade;
use crate::behavior::{Behavior, Ctx, Out, ParamError, PostKey, add_vars};
use crate::common::Common;
use crate::contact::ContactBase;
use crate::contact_state::ContactState;
use crate::param::{is_number, moos_boolean};

/// Which MOOS-IvP class the behaviour is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Version {
    /// BHV_AvdColregsV17.
    V17,
    /// BHV_AvdColregsV19.
    V19,
    /// BHV_AvdColregsV22.
    V22,
    /// BHV_AvdColregsV26.
    V26,
}

impl Version {
    /// The type name (`BHV_AvdColregsV22`, ...).
    pub fn kind(self) -> &'static str {
        match self {
            Version::V17 => "BHV_AvdColregsV17",
            Version::V19 => "BHV_AvdColregsV19",
            Version::V22 => "BHV_AvdColregsV22",
            Version::V26 => "BHV_AvdColregsV26",
        }
    }

    /// The parameters this version takes besides the contact ones (for `coug check`): V17's,
    /// then those V19 added, then those V22 added (V26 takes V22's).
    pub fn params(self) -> impl Iterator<Item = &'static str> {
        const V17: &[&str] = &[
            "pwt_inner_dist",
            "pwt_outer_dist",
            "min_util_cpa_dist",
            "max_util_cpa_dist",
            "completed_dist",
            "turn_radius",
            "avoid_mode",
            "avoid_submode",
            "no_alert_request",
            "contact_type_required",
            "pwt_grade",
        ];
        const FROM_V19: &[&str] = &[
            "giveway_bow_dist",
            "verbose",
            "use_refinery",
            "check_plateaus",
            "check_validity",
            "pcheck_thresh",
            "can_disable",
        ];
        const FROM_V22: &[&str] = &[
            "headon_only",
            "eval_tol",
            "velocity_filter",
            "post_status_info_on_idle",
            "pts_port_turns_ok",
        ];
        let v19: &[&str] = if self.at_least_v19() { FROM_V19 } else { &[] };
        let v22: &[&str] = if self.at_least_v22() { FROM_V22 } else { &[] };
        V17.iter().chain(v19).chain(v22).copied()
    }

    fn at_least_v19(self) -> bool {
        self != Version::V17
    }

    fn at_least_v22(self) -> bool {
        matches!(self, Version::V22 | Version::V26)
    }
}

/// The avoid modes (`avoid_mode` accepts the first six).
const MODES: [&str; 8] = [
    "headon",
    "giveway",
    "none",
    "overtaking",
    "standon",
    "cpa",
    "standon_ot",
    "complete",
];

/// The submodes.
const SUBMODES: [&str; 12] = [
    "none",
    "port",
    "starboard",
    "stern",
    "bow",
    "unsure",
    "unsure_bow",
    "unsure_stern",
    "neither",
    "inextremis",
    "cpa",
    "bow_must",
];

fn find(list: &[&'static str], v: &str) -> Option<&'static str> {
    list.iter().copied().find(|m| *m == v)
}

/// BHV_AvdColregsV22 (and V17, V19, V26 by [`Version`]).
#[derive(Debug, Clone)]
pub struct AvdColregs {
    /// Which class.
    pub version: Version,
    /// The contact and the shared contact parameters.
    pub base: ContactBase,
    /// `pwt_outer_dist`, m.
    pub pwt_outer_dist: f64,
    /// `pwt_inner_dist`, m.
    pub pwt_inner_dist: f64,
    /// `min_util_cpa_dist`, m.
    pub min_util_cpa_dist: f64,
    /// `max_util_cpa_dist`, m.
    pub max_util_cpa_dist: f64,
    /// `completed_dist`, m.
    pub completed_dist: f64,
    /// `giveway_bow_dist`, m (−1: off).
    pub giveway_bow_dist: f64,
    /// `turn_radius`, m.
    pub turn_radius: f64,
    /// Half the overtaking sector around the contact's stern, degrees (67.5).
    pub overtaking_bng_range: f64,
    /// The head-on relative bearing threshold, degrees (12).
    pub headon_abs_relbng_thresh: f64,
    /// `pwt_grade`.
    pub pwt_grade: PwtGrade,
    /// `headon_only`: every mode but head-on becomes `cpa`.
    pub headon_only: bool,
    /// `post_status_info_on_idle`.
    pub post_status_info_on_idle: bool,
    /// `pts_port_turns_ok`.
    pub pts_port_turns_ok: bool,
    /// `no_alert_request`.
    pub no_alert_request: bool,
    /// `velocity_filter`.
    pub velocity_filter: Option<VelocityFilter>,
    /// `contact_type_required` (lower case).
    pub contact_type_required: String,
    /// The avoid mode.
    pub mode: &'static str,
    /// The avoid submode.
    pub submode: &'static str,
    /// The mode's index (`MODE_ID`).
    pub mode_ix: u32,
    /// The contact state at the last update.
    pub state: ContactState,
    /// The contact crossed ownship's bow-stern line since the previous running iteration.
    pub cn_crossed_os_port_star: bool,
    /// The weight of the last function: relevance × pwt.
    pub actual_pwt: f64,
    mode_start: f64,
    submode_start: f64,
    osh_orig_standon: f64,
    spd_orig_standon: f64,
    standon_set: bool,
    iterations: u64,
    cn_headings: std::collections::VecDeque<(f64, f64)>,
    cn_rel_bngs: std::collections::VecDeque<(f64, f64)>,
    memory_time: f64,
    pwt: f64,
    update_var: String,
    spawnable: bool,
    flags: [bool; 5],
    pcheck_thresh: f64,
    segl: Option<[(f64, f64); 2]>,
    /// V26's platform model this iteration when it is not holonomic (see [`super::plat_cpx`]).
    plat_model: Option<std::sync::Arc<crate::plat_model::PlatModel>>,
}

impl AvdColregs {
    /// The C++ defaults of `version`.
    pub fn new(version: Version) -> Self {
        let mut base = ContactBase::new(120.0);
        // V26 starts on the platform-model engines (its constructor's `m_cpa_engine_pm`).
        base.use_plat_model = version == Version::V26;
        AvdColregs {
            version,
            base,
            pwt_outer_dist: 100.0,
            pwt_inner_dist: 90.0,
            min_util_cpa_dist: 10.0,
            max_util_cpa_dist: 75.0,
            completed_dist: 100.0,
            giveway_bow_dist: -1.0,
            turn_radius: 0.0,
            overtaking_bng_range: 67.5,
            headon_abs_relbng_thresh: 12.0,
            pwt_grade: PwtGrade::Linear,
            headon_only: false,
            post_status_info_on_idle: false,
            pts_port_turns_ok: true,
            no_alert_request: false,
            velocity_filter: None,
            contact_type_required: String::new(),
            mode: "none",
            submode: "none",
            mode_ix: 0,
            state: ContactState::default(),
            plat_model: None,
            cn_crossed_os_port_star: false,
            actual_pwt: 0.0,
            mode_start: 0.0,
            submode_start: 0.0,
            osh_orig_standon: 0.0,
            spd_orig_standon: 0.0,
            standon_set: false,
            iterations: 0,
            cn_headings: Default::default(),
            cn_rel_bngs: Default::default(),
            memory_time: 5.0,
            pwt: 100.0,
            update_var: String::new(),
            spawnable: false,
            flags: [false; 5],
            pcheck_thresh: 0.001,
            segl: None,
        }
    }

    /// BHV_AvdColregsV22 with its defaults.
    pub fn v22() -> Self {
        Self::new(Version::V22)
    }

    /// The seconds spent in the present mode and submode.
    pub fn mode_times(&self, now: f64) -> (f64, f64) {
        (now - self.mode_start, now - self.submode_start)
    }

    /// The full mode, `mode:submode`.
    pub fn full_mode(&self) -> String {
        format!("{}:{}", self.mode, self.submode)
    }

    /// The relevance at the present range (MOOS `getRelevance`).
    pub fn relevance(&self) -> f64 {
        let (osx, osy, _, _) = self.base.os;
        let (cnx, cny, _, _) = self.base.cn;
        let r = (osx - cnx).hypot(osy - cny);
        let (outer, inner) = (self.pwt_outer_dist, self.pwt_inner_dist);
        if r >= outer {
            return 0.0;
        }
        if r <= inner {
            return 1.0;
        }
        let pct = ((outer - self.base.range) / (outer - inner)).clamp(0.0, 1.0);
        let g = match self.pwt_grade {
            PwtGrade::Linear => pct,
            PwtGrade::Quadratic => pct * pct,
            PwtGrade::Quasi => pct.powf(1.5),
        };
        g.clamp(0.0, 1.0)
    }

    /// Sets the mode and submode if they are a valid pair (MOOS `resetAvoidModes`).
    pub fn reset_modes(&mut self, mode: &str, submode: &str) -> bool {
        let Some(m) = find(&MODES[..6], mode) else {
            return false;
        };
        let Some(s) = find(&SUBMODES, submode) else {
            return false;
        };
        let ok = match m {
            "giveway" => matches!(s, "stern" | "bow" | "neither" | "none"),
            "overtaking" => matches!(s, "port" | "starboard" | "none"),
            "standon" => matches!(
                s,
                "bow" | "stern" | "unsure" | "neither" | "none" | "inextremis"
            ),
            _ => true,
        };
        if ok {
            self.mode = m;
            self.submode = s;
        }
        ok
    }

    fn reset(&mut self) {
        self.mode = "none";
        self.submode = "none";
    }

    /// Reads ownship and the contact and works out their state; false when the iteration
    /// cannot go on.
    fn update(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> bool {
        if !self.base.update(ctx, out) {
            return false;
        }
        // The contact state ContactBase::update recorded (IvPContactBehavior's `m_cnos`).
        self.state = self.base.states.now();
        self.plat_model =
            super::plat_cpx::turning_model(self.version, self.base.use_plat_model, ctx);
        true
    }

    fn per_contact(&self) -> bool {
        self.base.post_per_contact_info
    }

    fn debug_posts(&self) -> bool {
        !self.version.at_least_v22() || self.per_contact()
    }

    fn suffix(&self) -> String {
        format!("_{}", self.base.contact.to_ascii_uppercase())
    }

    fn headon_debug(&self, ctx: &Ctx<'_>, out: &mut Out, msg: &str) {
        if self.debug_posts() {
            out.post(
                format!("HEADON_DEBUG_{}", ctx.ownship.to_ascii_uppercase()),
                format!("contact={},{msg}", self.base.contact),
            );
        }
    }

    /// The mode machine (MOOS `updateAvoidMode`) at time `now`.
    pub fn update_avoid_mode(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        let (prev_mode, prev_sub) = (self.mode, self.submode);
        let m = |s: &Self, x: &str| s.mode == "none" || s.mode == x || s.mode == "cpa";
        if m(self, "overtaking") {
            self.check_overtaking();
        }
        if m(self, "headon") {
            self.check_head_on(ctx, out);
        }
        if m(self, "standon_ot") {
            self.check_stand_on_ot();
        }
        if m(self, "giveway") {
            self.check_give_way(out);
        }
        if m(self, "standon") {
            self.check_stand_on();
        }
        if self.mode == "none" || self.mode == "cpa" {
            self.check_cpa();
        }
        let now = ctx.info.now();
        if prev_mode != self.mode {
            self.mode_start = now;
        }
        if prev_mode != self.mode || prev_sub != self.submode {
            self.submode_start = now;
        }
        let standing = |s: &str| s == "standon" || s == "standon_ot";
        if !standing(prev_mode) && standing(self.mode) {
            if !self.standon_set {
                self.osh_orig_standon = self.base.os.2;
                self.spd_orig_standon = self.base.os.3;
                self.standon_set = true;
            }
        } else {
            self.standon_set = false;
        }
        if self.version.at_least_v22()
            && self.headon_only
            && matches!(
                self.mode,
                "overtaking" | "giveway" | "standon_ot" | "standon"
            )
        {
            self.mode = "cpa";
            self.submode = "none";
        }
        if self.version == Version::V19 {
            out.post(
                "AVD_INFO",
                format!(
                    "V19 CN:{}  Mode:{}:{}",
                    self.base.contact, self.mode, self.submode
                ),
            );
        }
        self.mode_ix = self.mode_index();
    }

    /// Rule 13 (MOOS `checkModeOvertaking`).
    fn check_overtaking(&mut self) {
        let s = &self.state;
        if self.base.range >= self.pwt_outer_dist || s.rate_of_closure < 0.0 {
            self.reset();
            return;
        }
        if self.mode == "overtaking" {
            if s.cn_os_rel_bng > 337.5 || s.cn_os_rel_bng < 22.5 {
                self.mode = "cpa";
                self.submode = "cpa";
            }
            let buffer = 5.0;
            if self.submode == "port" {
                if s.os_cn_rel_bng > 180.0 && s.os_cn_rel_bng < 360.0 - buffer {
                    self.submode = "starboard";
                }
            } else if s.os_cn_rel_bng < buffer {
                self.submode = "port";
            }
            return;
        }
        let (lo, hi) = (
            180.0 - self.overtaking_bng_range,
            180.0 + self.overtaking_bng_range,
        );
        if s.cn_os_rel_bng < lo || s.cn_os_rel_bng > hi || !s.os_passes_cn {
            self.reset();
            return;
        }
        self.mode = "overtaking";
        self.submode = if s.cn_port_of_os { "starboard" } else { "port" };
    }

    /// Rule 14 (MOOS `checkModeHeadOn`).
    fn check_head_on(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        let s = self.state;
        if self.mode == "headon" {
            if self.base.range > self.min_util_cpa_dist && s.rate_of_closure < 0.0 {
                self.headon_debug(ctx, out, "release due to opening range");
                self.reset();
            }
            if s.os_aft_of_cn {
                self.headon_debug(ctx, out, "release due to os aft of cn");
                self.reset();
            }
            if s.os_star_of_cn && s.cn_star_of_os {
                let os_extra = s.os_cn_rel_bng - self.headon_abs_relbng_thresh;
                let cn_extra = s.cn_os_rel_bng - self.headon_abs_relbng_thresh;
                if os_extra > 5.0 || cn_extra > 5.0 || os_extra + cn_extra > 7.5 {
                    self.reset();
                    self.headon_debug(ctx, out, "release due to passing to port");
                }
            }
            return;
        }
        if self.base.range >= self.pwt_outer_dist * 2.0 {
            self.reset();
            self.headon_debug(ctx, out, "not entered due to range");
            return;
        }
        let abs_rel = |b: f64| if b > 180.0 { 360.0 - b } else { b };
        let (osx, osy, osh, _) = self.base.os;
        let (cnx, cny, cnh, _) = self.base.cn;
        let os_cn = abs_rel(crate::cpa::rel_bearing(osx, osy, osh, cnx, cny));
        let cn_os = abs_rel(crate::cpa::rel_bearing(cnx, cny, cnh, osx, osy));
        if os_cn > self.headon_abs_relbng_thresh || cn_os > self.headon_abs_relbng_thresh {
            self.headon_debug(ctx, out, "not entered due to rel bearing");
            self.reset();
            return;
        }
        self.headon_debug(ctx, out, "entered head-on mode");
        self.mode = "headon";
        self.submode = "none";
    }

    /// Rules 15/16 (MOOS `checkModeGiveWay`).
    fn check_give_way(&mut self, out: &mut Out) {
        let s = self.state;
        if self.base.range >= self.pwt_outer_dist {
            self.reset();
            return;
        }
        if self.mode == "giveway" {
            if self.base.range > self.min_util_cpa_dist && s.rate_of_closure < 0.0 {
                self.mode = "cpa";
                self.submode = "none";
            }
            if s.os_star_of_cn {
                self.mode = "cpa";
                self.submode = "none";
            }
            return;
        }
        if s.cn_os_rel_bng < 247.5 || s.os_cn_rel_bng > 112.5 {
            self.reset();
            return;
        }
        self.mode = "giveway";
        self.submode = "stern";
        let sfx = self.suffix();
        if self.debug_posts() {
            out.post(format!("XCN_BOW_DIST{sfx}"), s.os_crosses_cn_bow_dist);
        }
        let (osx, osy, osh, osv) = self.base.os;
        let (cnx, cny, cnh, _) = self.base.cn;
        if s.os_crosses_cn_bow {
            let mut acceptable = (2.0 * self.max_util_cpa_dist + self.min_util_cpa_dist) / 3.0;
            if self.version.at_least_v19() && self.giveway_bow_dist > 0.0 {
                acceptable = self.giveway_bow_dist;
            }
            if s.os_crosses_cn_bow_dist > acceptable {
                self.submode = "bow";
            }
            let p2 = project_point(cnh, 100.0, cnx, cny);
            let gap = turn_gap(osx, osy, osh, self.turn_radius, (cnx, cny), p2, true);
            if gap < acceptable {
                self.submode = "bow";
            }
            if self.debug_posts() {
                out.post(format!("XCN_BOW_TURN_GAP{sfx}"), gap);
            }
        }
        if !s.os_crosses_cn && speed_in_heading(osh, osv, cnh) > 0.0 {
            self.submode = "bow";
        }
    }

    /// The contact's turn rate over the remembered headings, degrees/s, if they span at
    /// least `min_secs` (MOOS `getHeadingRate`).
    pub fn heading_rate(&self, min_secs: f64) -> Option<f64> {
        if self.cn_headings.len() <= 1 {
            return None;
        }
        let total_time = self.cn_headings.back()?.1 - self.cn_headings.front()?.1;
        if total_time < min_secs {
            return None;
        }
        let mut total = 0.0;
        let mut prev = 0.0;
        for (i, (h, _)) in self.cn_headings.iter().enumerate() {
            if i > 0 {
                let mut d = h - prev;
                if d < -180.0 {
                    d += 360.0;
                } else if d > 180.0 {
                    d -= 360.0;
                }
                total += d;
            }
            prev = *h;
        }
        Some(total / total_time)
    }

    /// Rule 17 (MOOS `checkModeStandOn`).
    fn check_stand_on(&mut self) {
        let s = self.state;
        if self.base.range >= self.pwt_outer_dist {
            self.reset();
            return;
        }
        if self.mode == "standon"
            && (self.cn_crossed_os_port_star
                || (self.base.range > self.min_util_cpa_dist && s.rate_of_closure < 0.0))
        {
            self.reset();
            return;
        }
        if s.os_cn_rel_bng < 247.5 || s.cn_os_rel_bng > 112.5 {
            return;
        }
        if !s.cn_crosses_os || s.rate_of_closure < 0.0 {
            return;
        }
        self.mode = "standon";
        self.submode = "unsure";
        if self.base.range <= self.max_util_cpa_dist && s.os_curr_cpa_dist <= self.min_util_cpa_dist
        {
            self.submode = "inextremis";
            return;
        }
        if s.os_port_of_cn {
            // "neither" is terminal.
            self.submode = "neither";
            return;
        }
        let rate = self.heading_rate(4.0);
        let turning = |lim: f64| rate.is_some_and(|r| r < lim);
        let half = (self.max_util_cpa_dist + self.min_util_cpa_dist) / 2.0;
        let (min, max) = (self.min_util_cpa_dist, self.max_util_cpa_dist);
        let bow = s.cn_crosses_os_bow_dist;
        self.submode = if s.os_cn_rel_bng > 350.0 {
            if bow >= min {
                if turning(0.0) { "bow" } else { "unsure_bow" }
            } else if bow > 0.0 {
                if turning(0.0) { "unsure_bow" } else { "unsure" }
            } else {
                "unsure_stern"
            }
        } else if s.os_cn_rel_bng > 315.0 {
            if bow >= half {
                if turning(3.0) { "bow" } else { "unsure_bow" }
            } else if bow >= min {
                if turning(0.1) { "bow" } else { "unsure_bow" }
            } else if bow > 0.0 {
                if turning(0.0) { "unsure_bow" } else { "unsure" }
            } else {
                "stern"
            }
        } else if s.os_cn_rel_bng >= 270.0 {
            if bow >= max {
                "bow"
            } else if bow >= half {
                if turning(0.1) { "bow" } else { "unsure_bow" }
            } else if bow > 0.0 {
                if turning(0.0) { "unsure_bow" } else { "unsure" }
            } else {
                "stern"
            }
        } else if bow >= half {
            if turning(0.1) { "unsure_bow" } else { "unsure" }
        } else if bow > 0.0 {
            "unsure"
        } else {
            "stern"
        };
    }

    /// Rule 17 for the overtaken vessel (MOOS `checkModeStandOnOT`).
    fn check_stand_on_ot(&mut self) {
        let s = self.state;
        if self.base.range >= self.pwt_outer_dist {
            self.reset();
            return;
        }
        if self.mode == "standon_ot" {
            if self.cn_crossed_os_port_star || s.rate_of_closure < 0.0 {
                self.reset();
                return;
            }
        } else if s.os_cn_rel_bng < 112.5
            || s.os_cn_rel_bng > 247.5
            || !s.cn_passes_os
            || s.os_curr_cpa_dist > self.max_util_cpa_dist
        {
            self.reset();
            return;
        }
        self.mode = "standon_ot";
        self.submode = "unsure";
        if self.base.range <= self.max_util_cpa_dist && s.os_curr_cpa_dist <= self.min_util_cpa_dist
        {
            self.submode = "inextremis";
            return;
        }
        self.submode = if s.cn_port_of_os { "port" } else { "starboard" };
    }

    /// The catch-all (MOOS `checkModeCPA`).
    fn check_cpa(&mut self) {
        if self.mode != "cpa" && self.mode != "none" {
            return;
        }
        if self.base.range > self.pwt_outer_dist {
            self.reset();
            return;
        }
        self.mode = "cpa";
        self.submode = "none";
    }

    /// The mode's index (MOOS `setAvoidModeIndex`).
    pub fn mode_index(&self) -> u32 {
        match (self.mode, self.submode) {
            ("complete", _) => 3,
            ("headon", _) => 10,
            ("giveway", "stern") => 20,
            ("giveway", "bow") => 22,
            ("giveway", "bow_must") => 25,
            ("standon", "stern") => 30,
            ("standon", "inextremis") => 31,
            ("standon", "bow") => 32,
            ("standon", "unsure_stern") => 34,
            ("standon", "unsure_bow") => 36,
            ("standon", "unsure") => 38,
            ("standon", "neither") => 39,
            ("overtaking", "port") => 43,
            ("overtaking", _) => 47,
            ("cpa", _) => 50,
            _ => 0,
        }
    }

    fn distances(&self, tol: f64) -> Option<Distances> {
        let d = Distances::for_contact(
            &self.base,
            tol,
            self.min_util_cpa_dist,
            self.max_util_cpa_dist,
        )?;
        Some(match &self.plat_model {
            Some(m) => d.with_plat_model(m.clone(), self.base.cn),
            None => d,
        })
    }

    fn geo(&self) -> Cpx {
        let (osx, osy, osh, osv) = self.base.os;
        let (cnx, cny, cnh, cnv) = self.base.cn;
        let g = Cpx::new(cnx, cny, cnh, cnv, osx, osy, osh, osv);
        match &self.plat_model {
            Some(m) => g.with_plat_model(m.clone()),
            None => g,
        }
    }

    /// The time on leg of the catch-all and give-way functions.
    fn fixed_tol(&self) -> f64 {
        if self.version == Version::V26 {
            self.base.time_on_leg
        } else {
            120.0
        }
    }

    /// The function of the present mode (before normalisation and weight), or `None`.
    pub fn objective(&self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let domain = ctx.domain;
        match self.mode {
            "headon" => {
                let tol = if self.version == Version::V17 {
                    120.0
                } else {
                    self.base.time_on_leg
                };
                let Some(d) = self.distances(tol) else {
                    out.error("Unable to init AOF_R14.");
                    return None;
                };
                let aof = AofR14::new(d, self.geo());
                reflect(domain, |c, s| aof.eval(c, s))
            }
            "overtaking" => {
                let pass_to_port = match self.submode {
                    "port" => true,
                    "starboard" => false,
                    _ => {
                        out.error("Unable to init AOF_R13.");
                        return None;
                    }
                };
                let Some(d) = self.distances(self.base.time_on_leg) else {
                    out.error("Unable to init AOF_R13.");
                    return None;
                };
                let aof = AofR13 {
                    d,
                    geo: self.geo(),
                    pass_to_port,
                };
                reflect(domain, |c, s| aof.eval(c, s))
            }
            "giveway" => {
                if self.version == Version::V17 {
                    let osh = moos_types::fmt::compact_string(self.base.os.2, 5);
                    out.error(format!(
                        "Unable to init AOF_R16:bad param[osh], value[{osh}]"
                    ));
                    return None;
                }
                let side = match self.submode {
                    "stern" => GiveWaySide::Stern,
                    "bow" => GiveWaySide::Bow,
                    _ => {
                        out.error("Unable to init AOF_R16:passing side is not set");
                        return None;
                    }
                };
                let Some(d) = self.distances(self.fixed_tol()) else {
                    out.error("Unable to init AOF_R16:collision_dist > all_clear_dist");
                    return None;
                };
                let aof = AofR16 {
                    d,
                    geo: self.geo(),
                    side,
                    ok_cn_bow_cross_dist: 0.0,
                    pts_port_turns_ok: !self.version.at_least_v22() || self.pts_port_turns_ok,
                };
                reflect(domain, |c, s| aof.eval(c, s))
            }
            "standon" | "standon_ot" if self.submode != "inextremis" => self.stand_on(ctx, out),
            "standon" | "standon_ot" | "cpa" => {
                let Some(d) = self.distances(self.fixed_tol()) else {
                    out.error(if self.version.at_least_v22() {
                        "Unable to init AOF_CPA."
                    } else {
                        "Unable to init AOF_AvoidCollision."
                    });
                    return None;
                };
                let aof = AofCpa { d };
                if self.flags[1] {
                    return self.cpa_refined(domain, &aof, out);
                }
                reflect(domain, |c, s| aof.eval(c, s))
            }
            _ => None,
        }
    }

    /// The refinery parameters (`use_refinery`, `check_plateaus`, `check_validity`,
    /// `pcheck_thresh`, `verbose`; V19 and later).
    pub fn refinery_settings(&self) -> RefinerySettings {
        RefinerySettings {
            use_refinery: self.flags[1],
            check_plateaus: self.flags[2],
            check_validity: self.flags[3],
            pcheck_thresh: self.pcheck_thresh,
            verbose: self.flags[0],
        }
    }

    /// The catch-all CPA function with `use_refinery` (MOOS `buildCPA_IPF`'s refinery):
    /// `RefineryCPA` over the pair with the behaviour's time on leg and its own
    /// `min/max_util_cpa_dist` (not halved), its plateau regions handed to the reflector
    /// (fitted as any piece: AOF_CPA's extremes are not known), and with `check_plateaus`
    /// the checks' postings ([`crate::refinery_cpa::post_colregs_checks`]).
    fn cpa_refined(
        &self,
        domain: &ivp::Domain,
        aof: &AofCpa,
        out: &mut Out,
    ) -> Option<IvpFunction> {
        let rd = self.distances(self.base.time_on_leg)?;
        let geo = PairGeometry::of(&self.geo());
        let refinery = |dom: &ivp::Domain| {
            RefineryCpa::new(
                dom,
                geo,
                self.base.time_on_leg,
                self.min_util_cpa_dist,
                self.max_util_cpa_dist,
                |h, s, t| distances_cpa(&rd, h, s, t),
            )
        };
        let settings = self.refinery_settings();
        let (f, info) = reflect_refined(domain, refinery, &settings, None, |c, s| aof.eval(c, s))?;
        post_colregs_checks(&info, out);
        Some(f)
    }

    /// Hold the course and speed of the mode's start (MOOS `buildStandOnIPF`).
    fn stand_on(&self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        let d = ctx.domain;
        let spd = ZaicSpd::new(
            d,
            "speed",
            self.spd_orig_standon,
            0.1,
            self.spd_orig_standon + 0.4,
            50.0,
            50.0,
        )
        .and_then(|z| z.extract());
        if spd.is_err() {
            out.warning(ctx.name, "Failure on the SPD ZAIC");
        }
        let high = d.get("course").map_or(359.0, |v| v.high());
        let summit = self.osh_orig_standon.min(high);
        let crs = ZaicHdg::new(d, "course", summit, 20.0, 20.0, 25.0, 25.0, 0.0, 100.0)
            .and_then(|z| z.extract());
        if crs.is_err() {
            out.warning(ctx.name, "Failure on the CRS ZAIC");
        }
        match (crs, spd) {
            (Ok(c), Ok(s)) => ivp::couple(&c, &s).ok(),
            _ => {
                out.warning(ctx.name, "Failure on the CRS_SPD COUPLER");
                None
            }
        }
    }

    fn post_status(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        let full = if self.submode == "none" {
            self.mode.to_string()
        } else {
            format!("{}:{}", self.mode, self.submode)
        };
        if !self.version.at_least_v22() {
            let active = self.mode != "none" && self.mode != "complete";
            if active {
                let (osx, osy, _, _) = self.base.os;
                let (cnx, cny, _, _) = self.base.cn;
                self.segl = Some([(osx, osy), (cnx, cny)]);
            }
            let mut s = String::new();
            if let Some(pts) = self.segl {
                let pts = pts.map(|(x, y)| geometry::Point::new(x, y));
                geometry::spec::write_points(&mut s, &pts, 1);
            }
            let mut a = geometry::Attributes::labeled(format!("{}{}", ctx.ownship, ctx.name));
            a.active = active;
            if active {
                a.msg = full.clone();
            }
            a.write_spec(&mut s, 0);
            out.post("VIEW_SEGLIST", s);
        }
        if !self.per_contact() {
            return;
        }
        let sfx = self.suffix();
        let b = |v: bool| if v { 1.0 } else { 0.0 };
        let fore = if self.version == Version::V17 {
            "CN_FORE_OF_OS_"
        } else {
            "CN_FORE_OF_OS"
        };
        let crossed = if self.version == Version::V17 {
            "CN_CROSSED_OS_PORT_STAR_"
        } else {
            "CN_CROSSED_OS_PORT_STAR"
        };
        out.post(format!("{fore}{sfx}"), b(self.state.cn_fore_of_os));
        out.post(format!("CN_PORT_OF_OS_{sfx}"), b(self.state.cn_port_of_os));
        out.post(format!("{crossed}{sfx}"), b(self.cn_crossed_os_port_star));
        out.post(format!("AVDCOL_RANGE{sfx}"), self.base.range);
        out.post(format!("COLREGS_AVOID_MODE{sfx}"), full);
        out.post(
            format!("COLREGS_SUMMARY{sfx}"),
            format!("mode={}:{}", self.mode, self.submode),
        );
        let ix = if self.version.at_least_v22() {
            self.mode_ix
        } else {
            self.mode_index()
        };
        out.post_key(
            format!("COLREGS_AVOID_IX{sfx}"),
            f64::from(ix),
            PostKey::Repeatable,
        );
        out.post_key(
            format!("COLREGS_AVOID_PWT{sfx}"),
            self.actual_pwt,
            PostKey::Repeatable,
        );
        out.post(format!("COLREGS_CONTACT_HDG{sfx}"), self.base.cn.2);
    }

    fn done(&self) -> bool {
        if !self.base.filter_holds() {
            return true;
        }
        if self.version == Version::V17 {
            self.base.range >= self.completed_dist
        } else {
            self.base.range >= self.completed_dist * 1.1
        }
    }

    fn remember(&mut self, now: f64) {
        let keep = |q: &mut std::collections::VecDeque<(f64, f64)>, v: f64, mem: f64| {
            q.push_back((v, now));
            while q.front().is_some_and(|(_, t)| now - t >= mem) {
                q.pop_front();
            }
        };
        let mem = self.memory_time;
        keep(&mut self.cn_headings, self.base.cn.2, mem);
        keep(&mut self.cn_rel_bngs, self.state.os_cn_rel_bng, mem);
    }
}

fn nonneg(param: &str, v: &str) -> Result<f64, ParamError> {
    if is_number(v) && geometry::atof(v) >= 0.0 {
        Ok(geometry::atof(v))
    } else {
        Err(ParamError::bad(param, v, "a number >= 0"))
    }
}

impl Behavior for AvdColregs {
    fn kind(&self) -> &'static str {
        self.version.kind()
    }

    fn domain_vars(&self) -> &'static [&'static str] {
        &["course", "speed"]
    }

    fn default_name(&self) -> &'static str {
        "colregs"
    }

    fn is_constraint(&self) -> bool {
        true
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
        let v19 = self.version.at_least_v19();
        let v22 = self.version.at_least_v22();
        let pair = |lo: &mut f64, hi: &mut f64, low: bool| -> Result<(), ParamError> {
            let d = nonneg(param, value)?;
            if low {
                *lo = d;
                if *hi < *lo {
                    *hi = *lo;
                }
            } else {
                *hi = d;
                if *lo > *hi {
                    *lo = *hi;
                }
            }
            Ok(())
        };
        let boolean = |cur: bool| moos_boolean(param, value, cur);
        match param {
            "pwt_inner_dist" => {
                return pair(&mut self.pwt_inner_dist, &mut self.pwt_outer_dist, true);
            }
            "pwt_outer_dist" => {
                return pair(&mut self.pwt_inner_dist, &mut self.pwt_outer_dist, false);
            }
            "min_util_cpa_dist" => {
                return pair(
                    &mut self.min_util_cpa_dist,
                    &mut self.max_util_cpa_dist,
                    true,
                );
            }
            "max_util_cpa_dist" => {
                return pair(
                    &mut self.min_util_cpa_dist,
                    &mut self.max_util_cpa_dist,
                    false,
                );
            }
            "completed_dist" => {
                let d = nonneg(param, value)?;
                self.completed_dist = d;
                self.pwt_outer_dist = self.pwt_outer_dist.min(d);
                self.pwt_inner_dist = self.pwt_inner_dist.min(d);
            }
            "giveway_bow_dist" if v19 => {
                let mut d = nonneg(param, value)?;
                let cap = if v22 {
                    self.max_util_cpa_dist * 2.0
                } else {
                    self.max_util_cpa_dist
                };
                if d < self.min_util_cpa_dist {
                    d = self.min_util_cpa_dist;
                }
                if d > cap {
                    d = cap;
                }
                self.giveway_bow_dist = d;
            }
            "turn_radius" => self.turn_radius = nonneg(param, value)?,
            "avoid_mode" => {
                return if self.reset_modes(value, "none") {
                    Ok(())
                } else {
                    Err(ParamError::bad(
                        param,
                        value,
                        "headon, giveway, none, overtaking, standon or cpa",
                    ))
                };
            }
            "avoid_submode" => {
                let mode = self.mode;
                return if self.reset_modes(mode, value) {
                    Ok(())
                } else {
                    Err(ParamError::bad(param, value, "a submode of the avoid mode"))
                };
            }
            "no_alert_request" => {
                self.no_alert_request = boolean(self.no_alert_request)?;
                return Ok(());
            }
            "headon_only" if v22 => {
                self.headon_only = boolean(self.headon_only)?;
                return Ok(());
            }
            "contact_type_required" if !value.is_empty() => {
                self.contact_type_required = value.to_ascii_lowercase();
                return Ok(());
            }
            "verbose" | "use_refinery" | "check_plateaus" | "check_validity" | "can_disable"
                if v19 =>
            {
                let i = [
                    "verbose",
                    "use_refinery",
                    "check_plateaus",
                    "check_validity",
                ]
                .iter()
                .position(|p| *p == param)
                .unwrap_or(4);
                self.flags[i] = boolean(self.flags[i])?;
                self.base.can_disable = self.flags[4];
                return Ok(());
            }
            "pcheck_thresh" if v19 => {
                self.pcheck_thresh = nonneg(param, value)?;
                return Ok(());
            }
            "eval_tol" if v22 => {
                let d = geometry::atof(value);
                if !is_number(value) || !(5.0..=300.0).contains(&d) {
                    return Err(ParamError::bad(param, value, "a number in [5, 300]"));
                }
                self.base.time_on_leg = d;
                return Ok(());
            }
            "velocity_filter" if v22 => {
                self.velocity_filter = VelocityFilter::parse(value);
                return match self.velocity_filter {
                    Some(_) => Ok(()),
                    None => Err(ParamError::bad(
                        param,
                        value,
                        "min_spd=..,max_spd=..[,pct=..] with 0 <= min <= max, pct <= 100",
                    )),
                };
            }
            "post_status_info_on_idle" if v22 => {
                self.post_status_info_on_idle = boolean(self.post_status_info_on_idle)?;
                return Ok(());
            }
            "pts_port_turns_ok" if v22 => {
                self.pts_port_turns_ok = boolean(self.pts_port_turns_ok)?;
                return Ok(());
            }
            "pwt_grade" => {
                self.pwt_grade = match value.to_ascii_lowercase().as_str() {
                    "linear" => PwtGrade::Linear,
                    "quadratic" => PwtGrade::Quadratic,
                    "quasi" => PwtGrade::Quasi,
                    _ => return Err(ParamError::bad(param, value, "linear, quadratic or quasi")),
                };
                return Ok(());
            }
            _ => {
                return Err(if self.version.params().any(|p| p == param) {
                    ParamError::bad(param, value, "a non-empty value")
                } else {
                    ParamError::unknown(param)
                });
            }
        }
        // completed_dist, giveway_bow_dist and turn_radius end here, as in the C++.
        if self.completed_dist < self.pwt_outer_dist {
            self.completed_dist = self.pwt_outer_dist;
        }
        Ok(())
    }

    fn set_common(&mut self, common: &Common) {
        self.update_var.clone_from(&common.update_var);
        self.spawnable = common.templating.spawns();
        self.pwt = common.pwt;
    }

    fn contact_name(&self) -> Option<&str> {
        self.base.contact_name()
    }

    fn on_helm_start(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        if self.no_alert_request || self.update_var.is_empty() || !self.spawnable {
            return;
        }
        let ranges = (self.pwt_outer_dist, self.completed_dist);
        crate::avoid_collision::post_alert_request(
            ctx.name,
            &self.update_var,
            ranges,
            &self.base,
            out,
        );
    }

    fn info_vars(&self, out: &mut Vec<String>) {
        add_vars(out, ["NAV_X", "NAV_Y", "NAV_SPEED", "NAV_HEADING"]);
    }

    fn macro_value(&self, name: &str, out: &mut String) -> bool {
        if self.base.macro_value(name, out) {
            return true;
        }
        use moos_types::fmt::compact;
        match name {
            "AVD_MODE" if self.version.at_least_v22() => out.push_str(self.mode),
            "AVD_SMODE" if self.version.at_least_v22() => out.push_str(self.submode),
            "APWT" if self.version.at_least_v22() => compact(out, self.actual_pwt, 3),
            "MODE_ID" if self.version.at_least_v22() => {
                out.push_str(&self.mode_ix.to_string());
            }
            "FULL_MODE" if self.version.at_least_v22() => out.push_str(&self.full_mode()),
            _ => return false,
        }
        true
    }

    fn pwt_factor(&self) -> f64 {
        self.base.relevance
    }

    fn on_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        if !self.update(ctx, out) {
            return;
        }
        if !self.version.at_least_v22() || self.post_status_info_on_idle {
            self.post_status(ctx, out);
        }
        if self.done() {
            out.complete();
        }
    }

    fn apply_able_filter(&mut self, msg: &str, out: &mut Out) -> bool {
        let kind = self.kind();
        crate::contact::able_filter_hook(&mut self.base, msg, kind, out)
    }

    fn is_disabled(&self) -> bool {
        self.base.disabled
    }

    /// MOOS `onDisabledState` (V19, V22, V26; V17 cannot be disabled): the bearing line
    /// erased, completion on the filters or the range (V22 and V26 give the reasons
    /// `filterb`, `rng1p1b`).
    fn on_disabled(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.update(ctx, out);
        self.base.post_bearing_line(ctx, out, false);
        if self.version.at_least_v22() {
            if !self.base.filter_holds() {
                out.complete_because("filterb");
            }
            if self.base.range >= self.completed_dist * 1.1 {
                out.complete_because("rng1p1b");
            }
        } else if self.done() {
            out.complete();
        }
    }

    fn on_run_to_idle(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        if self.version.at_least_v22() {
            self.base.post_bearing_line(ctx, out, false);
        }
    }

    fn on_complete(&mut self, ctx: &Ctx<'_>, out: &mut Out) {
        self.mode = "complete";
        self.post_status(ctx, out);
    }

    fn on_run(&mut self, ctx: &Ctx<'_>, out: &mut Out) -> Option<IvpFunction> {
        self.iterations += 1;
        self.base.relevance = 0.0;
        let prev_cn_port = self.state.cn_port_of_os;
        if !self.update(ctx, out) {
            return None;
        }
        if self.version == Version::V26 && self.base.use_plat_model {
            // MOOS V26 `m_cpa_engine->setPlatModel(m_plat_model)`, after the update: the next
            // iteration's contact state reads this model.
            self.base.hand_model(ctx);
        }
        self.base.post_contact_flags(out);
        self.cn_crossed_os_port_star =
            self.iterations > 1 && self.state.cn_port_of_os != prev_cn_port;
        if self.done() {
            out.complete();
            return None;
        }
        self.remember(ctx.info.now());
        self.update_avoid_mode(ctx, out);
        let relevance = self.relevance();
        let cn = self.base.contact.to_ascii_uppercase();
        match self.version {
            Version::V17 => out.post("COL17_RELEVANCE", relevance),
            Version::V19 => out.post("COL19_RELEVANCE", relevance),
            _ if self.per_contact() => out.post(format!("COL22_RELEVANCE_{cn}"), relevance),
            _ => {}
        }
        let held = (self.min_util_cpa_dist, self.max_util_cpa_dist);
        if let Some(f) = self.velocity_filter.filter(|_| self.version.at_least_v22()) {
            let pct = f.factor(self.base.os.3, self.base.cn.3);
            self.min_util_cpa_dist *= pct;
            self.max_util_cpa_dist *= pct;
        }
        let ipf = if relevance > 0.0 {
            self.objective(ctx, out)
        } else {
            None
        };
        if self.version.at_least_v22() && self.per_contact() {
            out.post(format!("COL22_AVOID_MODE_{cn}"), self.mode);
        }
        (self.min_util_cpa_dist, self.max_util_cpa_dist) = held;
        let ipf = ipf.map(|mut f| {
            self.actual_pwt = relevance * self.pwt;
            self.base.relevance = relevance;
            f.normalize(0.0, 100.0);
            f
        });
        self.post_status(ctx, out);
        if ipf.is_some() && self.version.at_least_v22() {
            self.base.post_bearing_line(ctx, out, true);
        }
        ipf
    }
}
