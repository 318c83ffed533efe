//! The CougUV's own control and simulation apps (issue #15): `pCougControls`, the CoUGARs
//! controllers ([`vehicle::cougars::CougarsControl`]: heading loop, depth → pitch → elevator
//! cascade, fin mixing) from the helm's set-points and the navigator's estimate to the fin
//! angles and thrust the Teensy driver sends; and `uSimCougUV`, the CougUV torpedo model
//! ([`vehicle::couguv`]) that flies those fins and posts the truth as uSimMarine does, so the
//! cascade runs closed loop in simulation.
//!
//! # pCougControls
//!
//! The variables, conventions (compass vs ENU heading, depth positive down, declination
//! applied once, MOOS pitch), arming and all-stop rules are documented on
//! [`vehicle::cougars::CougarsControl`] and [`vehicle::cougars::vars`]. Configuration:
//!
//! | parameter | default | meaning |
//! |---|---|---|
//! | `vehicle` | none (all gains 0, as the ROS node's declared defaults) | `coug1` or `coug2`: the field gains, limits, filters, kinematics and servo ranges of that vehicle (§1.2, §1.5); the keys below override them, wherever the line is |
//! | `AppTick` | 12.5 (from `timer_period`) | the loop rate; the cascade's period is `1/AppTick` |
//! | `timer_period` (alias `pid_timer_period`) | 80 | ms; sets the rate when the block has no `AppTick` (a different one is warned about) |
//! | `depth_kp`, `depth_ki`, `depth_kd`, `depth_min_output`, `depth_max_output` | preset | depth loop, output the pitch reference (deg) |
//! | `pitch_kp`, ... `pitch_max_output` | preset | pitch loop, output the elevator fin (deg) |
//! | `heading_kp`, ... `heading_max_output` | preset | heading loop, output the top fin (deg) |
//! | `wn_d_z`, `wn_d_theta`, `outer_loop_threshold`, `saturation_offset`, `surge_threshold` | 0.09, 0.25, 2.5, 1.7, −1 (coug1/2: 0.30, 0.15) | the cascade's filters and saturated mode |
//! | `fixed_surge`, `min_schedule_speed` | 0.6, 0.1 | m/s: the pitch loop's gain-schedule speed (`none`: `NAV_SPEED`) |
//! | `fin_0_direction` .. `fin_2_direction`, `top_fin_offset`, `right_fin_offset`, `left_fin_offset`, `trim_ratio`, `demo_mode` | preset | the kinematics (servo frame = direction · deflection + offset + trim · thrust) |
//! | `servo_min_us`, `servo_max_us`, `thruster_min_us`, `thruster_max_us` | preset | the Teensy's pulse ranges (for the appcast only; the Teensy maps) |
//! | `speed_factor` | 0 | thrust % per m/s of `DESIRED_SPEED`; 0: `DESIRED_SPEED` is the thrust % (Gen-1) |
//! | `max_thrust` | 100 | % |
//! | `tardy_helm_threshold`, `tardy_nav_threshold` | 2, 2 | s: older set-points or navigation stop the vehicle (0: never) |
//!
//! # uSimCougUV
//!
//! Its parameters, the model and the posted truth are documented in [`vehicle::couguv`].
//! Unknown keys and bad values of either block are warnings (`mission::Diagnostic`, kind
//! `AppSetting`); the apps run on with the defaults.

use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::ProcessConfig;
use vehicle::cougars::{ControlsConfig, CougarsControl};
use vehicle::couguv::{CougUvSim, CougUvSimConfig};
use vehicle::geodesy::LocalGrid;

use crate::app::{Mail, Post, Subscription, Value};
use crate::appcasting::Note;
use crate::hosted::{AppCore, Hosted};

/// The MOOS name of the controllers app.
pub const CONTROLS_PROGRAM: &str = "pCougControls";

/// The MOOS name of the CougUV simulator.
pub const SIM_PROGRAM: &str = "uSimCougUV";

fn pairs(block: &ProcessConfig) -> impl Iterator<Item = (&str, &str)> {
    block
        .entries
        .iter()
        .map(|p| (p.key.as_str(), p.value.as_str()))
}

/// The controllers: the core of the `pCougControls` app.
pub struct CougControls {
    ctl: CougarsControl,
    postings: Vec<Post>,
}

/// The `pCougControls` app.
pub type CougControlsApp = Hosted<CougControls>;

impl Hosted<CougControls> {
    /// The app `name` from its `block`. The loop rate is the block's `AppTick`, else
    /// `1000/timer_period`; configuration problems are [`Hosted::warnings`].
    pub fn new(name: &str, block: ProcessConfig) -> Self {
        let (mut cfg, problems) = ControlsConfig::from_params_lenient(pairs(&block))
            .unwrap_or_else(|e| (ControlsConfig::default(), vec![e]));
        let mut warnings = crate::vehicle::config_warnings(&block, &problems);
        let has_tick = block.get("AppTick").is_some();
        let period_line = block.entries.iter().find(|p| {
            let k = p.key.trim();
            k.eq_ignore_ascii_case("timer_period") || k.eq_ignore_ascii_case("pid_timer_period")
        });
        let tick = if has_tick {
            let tick = crate::app::app_tick_of(Some(&block));
            let period_ms = 1000.0 / tick;
            if let Some(p) = period_line
                && (cfg.cougars.timer_period_ms - period_ms).abs() > 1e-6 * period_ms
            {
                warnings.push(Diagnostic::line_warning(
                    DiagnosticKind::AppSetting,
                    &p.span,
                    format!(
                        "{CONTROLS_PROGRAM}: timer_period {} ms disagrees with AppTick {tick} \
                         ({period_ms} ms): the loop runs at the AppTick",
                        cfg.cougars.timer_period_ms
                    ),
                ));
            }
            cfg.cougars.timer_period_ms = period_ms;
            tick
        } else {
            (1000.0 / cfg.cougars.timer_period_ms).min(crate::app::MAX_APP_TICK)
        };
        cfg.cougars.timer_period_ms = 1000.0 / tick;
        let core = CougControls {
            ctl: CougarsControl::new(cfg),
            postings: Vec::with_capacity(16),
        };
        Hosted::host(name, block, warnings, core).with_tick(tick)
    }

    /// The controllers.
    pub fn controls(&self) -> &CougarsControl {
        &self.core().ctl
    }
}

impl AppCore for CougControls {
    fn subscriptions(&self) -> Vec<Subscription> {
        CougarsControl::subscriptions()
            .into_iter()
            .map(Subscription::var)
            .collect()
    }

    fn on_mail(&mut self, m: &Mail, _now: f64, _out: &mut Vec<Post>, _notes: &mut Vec<Note>) {
        if !matches!(m.value, Value::Binary(_)) {
            self.ctl.on_mail(&m.key, m.value.as_ref(), m.time);
        }
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        self.ctl.iterate(now, &mut self.postings);
        out.append(&mut self.postings);
        notes.extend(self.ctl.take_warnings().into_iter().map(Note::Warning));
    }

    fn report(&self, _now: f64, body: &mut String) {
        self.ctl.appcast_body(body);
    }
}

/// The simulator: the core of the `uSimCougUV` app.
pub struct CougUvSimCore {
    sim: CougUvSim,
    postings: Vec<Post>,
}

/// The `uSimCougUV` app.
pub type CougUvSimApp = Hosted<CougUvSimCore>;

impl Hosted<CougUvSimCore> {
    /// The app `name` from its `block`; `grid` (the mission's origin) adds `<P>_LAT` and
    /// `<P>_LONG`.
    pub fn new(name: &str, block: ProcessConfig, grid: Option<LocalGrid>) -> Self {
        let (cfg, problems) = CougUvSimConfig::from_params_lenient(pairs(&block))
            .unwrap_or_else(|e| (CougUvSimConfig::default(), vec![e]));
        let warnings = crate::vehicle::config_warnings(&block, &problems);
        let core = CougUvSimCore {
            sim: CougUvSim::new(cfg, grid),
            postings: Vec::with_capacity(16),
        };
        Hosted::host(name, block, warnings, core)
    }

    /// The simulator.
    pub fn sim(&self) -> &CougUvSim {
        &self.core().sim
    }
}

impl AppCore for CougUvSimCore {
    fn subscriptions(&self) -> Vec<Subscription> {
        CougUvSim::subscriptions()
            .into_iter()
            .map(Subscription::var)
            .collect()
    }

    fn on_mail(&mut self, m: &Mail, _now: f64, _out: &mut Vec<Post>, _notes: &mut Vec<Note>) {
        if !matches!(m.value, Value::Binary(_)) {
            self.sim.on_mail(&m.key, m.value.as_ref(), m.time);
        }
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        self.sim.iterate(now, &mut self.postings);
        out.append(&mut self.postings);
        notes.extend(self.sim.take_warnings().into_iter().map(Note::Warning));
    }

    fn report(&self, now: f64, body: &mut String) {
        self.sim.appcast_body(now, body);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::antler::BuiltInApp;
    use crate::app::App;

    fn block(text: &str) -> ProcessConfig {
        crate::testing::block("c.moos", text)
    }

    fn mail(key: &str, value: Value, time: f64) -> Mail {
        crate::testing::mail(key, value, time, "pHelmIvP")
    }

    #[test]
    fn the_loop_rate_comes_from_the_apptick_or_the_timer_period() {
        let app = CougControlsApp::new(
            "pCougControls",
            block("ProcessConfig = pCougControls\n{\n  vehicle = coug1\n}\n"),
        );
        assert_eq!(app.app_tick(), 12.5, "80 ms, the vehicle's period");
        assert!(app.warnings().is_empty());
        let app = CougControlsApp::new(
            "pCougControls",
            block("ProcessConfig = pCougControls\n{\n  timer_period = 50\n}\n"),
        );
        assert_eq!(app.app_tick(), 20.0);
        let app = CougControlsApp::new(
            "pCougControls",
            block(
                "ProcessConfig = pCougControls\n{\n  AppTick = 10\n  timer_period = 80\n  \
                 colour = red\n  pitch_kp = fast\n}\n",
            ),
        );
        assert_eq!(app.app_tick(), 10.0);
        assert_eq!(app.controls().config().cougars.timer_period_ms, 100.0);
        let w: Vec<String> = app.warnings().iter().map(Diagnostic::located).collect();
        assert_eq!(w.len(), 3, "{w:?}");
        assert!(
            w[0].contains("c.moos:5") && w[0].contains("colour"),
            "{w:?}"
        );
        assert!(
            w[1].contains("c.moos:6") && w[1].contains("pitch_kp"),
            "{w:?}"
        );
        assert!(
            w[2].contains("c.moos:4") && w[2].contains("disagrees with AppTick 10"),
            "{w:?}"
        );
    }

    #[test]
    fn controls_and_simulator_close_the_loop_through_the_bus_names() {
        let mut ctl = CougControlsApp::new(
            "pCougControls",
            block(
                "ProcessConfig = pCougControls\n{\n  AppTick = 12.5\n  vehicle = coug1\n  \
                 speed_factor = 50\n}\n",
            ),
        )
        .with_appcast_globals(Some("abe"), 1.0);
        let mut sim = CougUvSimApp::new(
            "uSimCougUV",
            block("ProcessConfig = uSimCougUV\n{\n  prefix = NAV\n  start_pos = heading=0\n}\n"),
            None,
        )
        .with_appcast_globals(Some("abe"), 1.0);
        let subs: Vec<String> = ctl.subscriptions().into_iter().map(|s| s.pattern).collect();
        for v in [
            "DESIRED_HEADING",
            "NAV_PITCH",
            "DEPLOY",
            "MOOS_MANUAL_OVERRIDE",
        ] {
            assert!(subs.contains(&v.to_string()), "{v}: {subs:?}");
        }
        let mut out = Vec::new();
        ctl.on_startup(0.0, &mut out).unwrap();
        sim.on_startup(0.0, &mut out).unwrap();
        let arm = [
            mail("DEPLOY", Value::text("true"), 0.0),
            mail("MOOS_MANUAL_OVERRIDE", Value::text("false"), 0.0),
        ];
        ctl.on_mail(&arm, 0.0, &mut out).unwrap();
        // The helm wants east at 1 m/s on the surface; the simulator's NAV_* feed back.
        let mut nav: Vec<Post> = Vec::new();
        for k in 1..=1250 {
            let t = f64::from(k) * 0.08;
            let mut m: Vec<Mail> = [
                ("DESIRED_HEADING", 90.0),
                ("DESIRED_SPEED", 1.0),
                ("DESIRED_DEPTH", 0.0),
            ]
            .iter()
            .map(|(k, v)| mail(k, Value::Double(*v), t))
            .collect();
            m.extend(nav.drain(..).map(|p| mail(&p.key, p.value, t)));
            ctl.on_mail(&m, t, &mut out).unwrap();
            let mut cmds = Vec::new();
            ctl.iterate(t, &mut cmds).unwrap();
            let cm: Vec<Mail> = cmds
                .into_iter()
                .map(|p| crate::testing::mail(&p.key, p.value, t, "pCougControls"))
                .collect();
            sim.on_mail(&cm, t, &mut out).unwrap();
            sim.iterate(t, &mut nav).unwrap();
            nav.retain(|p| p.key.starts_with("NAV_"));
        }
        let truth = sim.sim().truth();
        assert!(
            (truth.body.heading - 90.0).abs() < 2.0,
            "{}",
            truth.body.heading
        );
        assert!(
            (truth.body.surge - 1.0).abs() < 0.01,
            "{}",
            truth.body.surge
        );
        assert!(truth.x > 50.0, "{}", truth.x);
        assert_eq!(
            ctl.controls().mode(),
            &vehicle::cougars::ControlsMode::Active
        );
        // Appcasts on request, with the controller's and the simulator's bodies.
        let req = "node=abe,app=all,duration=3,key=k,thresh=any";
        let mut out = Vec::new();
        for app in [&mut ctl as &mut dyn App, &mut sim] {
            app.on_mail(
                &[mail("APPCAST_REQ", Value::text(req), 100.1)],
                100.1,
                &mut out,
            )
            .unwrap();
            app.iterate(100.16, &mut out).unwrap();
        }
        let casts: Vec<appcast::AppCast> = out
            .iter()
            .filter(|p| p.key == "APPCAST")
            .map(|p| appcast::AppCast::parse(p.value.as_str().unwrap()))
            .collect();
        assert_eq!(casts.len(), 2);
        assert!(
            casts[0].messages().contains("Mode: active"),
            "{}",
            casts[0].messages()
        );
        assert!(
            casts[1].messages().contains("NAV: x="),
            "{}",
            casts[1].messages()
        );
    }
}
