//! pHelmIvP: the `helm` crate's engine behind the [`App`] trait.

use std::path::Path;

use ::helm::config::{ConfigError, Globals};
use ::helm::{Helm, HelmState};
use mission::Parsed;
use mission::bhv::BehaviorFile;
use mission::moos::{MissionFile, ProcessConfig};
use mission::nsplug::Options;
use mission::source::FileSource;

use crate::app::{App, Mail, Post, Subscription, Value};
use crate::appcasting::AppcastLayer;

/// The helm app: mail in, IvP decisions and behaviour postings out.
pub struct HelmApp {
    name: String,
    block: Option<ProcessConfig>,
    /// The block's AppTick, read once.
    tick: f64,
    helm: Helm,
    registered: Vec<String>,
    pid: Option<u32>,
    /// Where the helm's files come from, to read them again on `RESTART_HELM`.
    reload: Option<Reload>,
    /// Variables to register at the next `new_subscriptions` (after a restart).
    unregistered: Vec<String>,
    /// How many of the helm's registrations (`Helm::subscriptions`, which only grows) have
    /// been taken into `registered`.
    helm_seen: usize,
    /// The process's CPU load, percent (single-app mode).
    cpu_percent: Option<f64>,
    /// Appcasting (AppCastingMOOSApp): requests, warnings, events, `APPCAST` postings.
    appcast: AppcastLayer,
    /// What a behaviour did to the process (BHV_TestFailure), if anything.
    failed: Option<Failed>,
}

/// The helm's process after a BHV_TestFailure fault.
#[derive(Debug)]
enum Failed {
    /// Aborted: no more postings, the app has finished.
    Crashed,
    /// Hung until `until`; `held` are the postings of the iteration that hung.
    Burning { until: f64, held: Vec<Post> },
}

/// What a helm needs to read its configuration again (pHelmIvP `RESTART_HELM`).
#[derive(Debug, Clone)]
struct Reload {
    mission: MissionFile,
    dir: std::path::PathBuf,
    opts: Options,
}

impl HelmApp {
    /// A helm called `name` configured from `block` (the `ProcessConfig` of its MOOS name;
    /// `None` puts the helm in MALCONFIG, as pHelmIvP without a block), the mission's
    /// globals and the parsed (nsplug-expanded) `.bhv` file. Problems do not fail here:
    /// the helm reports them ([`HelmApp::config_errors`]) and never drives.
    pub fn new(
        name: &str,
        block: Option<ProcessConfig>,
        mission: &MissionFile,
        bhv: &Parsed<BehaviorFile>,
    ) -> HelmApp {
        let helm = match &block {
            Some(b) => {
                let params: Vec<(&str, &str)> = b
                    .entries
                    .iter()
                    .map(|p| (p.key.as_str(), p.value.as_str()))
                    .collect();
                Helm::from_parsed(&params, &Globals::from_mission(mission), bhv)
            }
            None => Helm::from_mission(&MissionFile::default(), bhv),
        }
        // Its own `IVPHELM_STATE` comes back under its MOOS name (an alias included): only
        // another helm's can disable it or keep a standby helm waiting.
        .with_app_name(name);
        let mut registered = helm.subscriptions().to_vec();
        let helm_seen = registered.len();
        // pHelmIvP also registers the variables of the mode declarations' conditions
        // (e.g. DEPLOY in `set MODE = ACTIVE { DEPLOY = true }`).
        for m in &bhv.value.modes {
            for c in &m.conditions {
                for v in c.condition.variables() {
                    if !registered.iter().any(|r| r == v) {
                        registered.push(v.to_string());
                    }
                }
            }
        }
        // AppCastingMOOSApp reads its own keys first; a bad one is a configuration warning,
        // which puts the helm in MALCONFIG. (A missing community or block is the helm's own
        // configuration error already.)
        let mut appcast = AppcastLayer::new(name, block.as_ref(), mission);
        let mut helm = helm;
        for w in appcast.config_warnings() {
            helm.add_config_error(::helm::config::ConfigError::Appcast(w.clone()));
        }
        for e in helm.config_errors() {
            if !matches!(e, ::helm::config::ConfigError::Appcast(_)) {
                appcast.config_warning(&e.to_string());
            }
        }
        HelmApp {
            name: name.to_string(),
            tick: crate::app::app_tick_of(block.as_ref()),
            block,
            helm,
            registered,
            pid: None,
            reload: None,
            unregistered: Vec::new(),
            helm_seen,
            cpu_percent: None,
            appcast,
            failed: None,
        }
    }

    /// The helm called `name` of `mission` (whose folder is `dir`), with the behaviour file
    /// its block names read through `fs` and nsplug-expanded with `opts`. Never fails, as
    /// pHelmIvP never exits on a bad configuration: a missing block, a missing or unreadable
    /// behaviour file and every error in it put the helm in MALCONFIG with the reasons
    /// ([`HelmApp::config_errors`], `file:line` where known); the app still joins the
    /// community, posts `IVPHELM_STATE = MALCONFIG` every iteration and never drives.
    pub fn from_mission_files(
        name: &str,
        mission: &MissionFile,
        dir: &Path,
        opts: &Options,
        fs: &dyn FileSource,
    ) -> HelmApp {
        let loaded = load_behaviors(mission, dir, name, opts, fs);
        HelmApp::from_behaviors(name, mission, loaded.as_ref().map_err(Vec::as_slice))
            .with_reload(mission, dir, opts)
    }

    /// Lets the helm read its files again (from the file system) on `RESTART_HELM = type1`
    /// (keeping its info buffer) or `type2` (a fresh one, initializes posted again), as
    /// pHelmIvP does; without this a restart request is ignored.
    pub fn with_reload(mut self, mission: &MissionFile, dir: &Path, opts: &Options) -> Self {
        self.reload = Some(Reload {
            mission: mission.clone(),
            dir: dir.to_path_buf(),
            opts: opts.clone(),
        });
        self
    }

    /// Rebuilds the helm from its files (see [`HelmApp::with_reload`]).
    fn restart(&mut self, keep_info: bool) {
        let Some(r) = self.reload.clone() else {
            return;
        };
        let fresh = HelmApp::from_mission_files(
            &self.name,
            &r.mission,
            &r.dir,
            &r.opts,
            &mission::source::FsSource,
        );
        let old = std::mem::replace(&mut self.helm, fresh.helm);
        self.helm.restart_from(old, keep_info);
        self.helm_seen = 0;
        // The new set's registrations (mode-condition variables included) are made at the
        // next `new_subscriptions`.
        for v in fresh.registered {
            if !self.registered.contains(&v) && !self.unregistered.contains(&v) {
                self.unregistered.push(v);
            }
        }
        tracing::warn!("{}: pHelmIvP has been re-started", self.name);
    }

    /// The helm called `name` of `mission` with its behaviour file as [`load_behaviors`]
    /// returned it: `Err` reasons put the helm in MALCONFIG (see
    /// [`HelmApp::from_mission_files`]).
    pub fn from_behaviors(
        name: &str,
        mission: &MissionFile,
        loaded: Result<&Parsed<BehaviorFile>, &[String]>,
    ) -> HelmApp {
        let block = mission.process(name).cloned();
        match loaded {
            Ok(bhv) => HelmApp::new(name, block, mission, bhv),
            Err(errors) => {
                let empty = Parsed {
                    value: BehaviorFile::default(),
                    diagnostics: Vec::new(),
                };
                let mut app = HelmApp::new(name, block, mission, &empty);
                for e in errors {
                    app.helm.add_config_error(ConfigError::Behavior(e.clone()));
                }
                app
            }
        }
    }

    /// The helm's configuration problems (empty when it can drive).
    pub fn config_errors(&self) -> Vec<String> {
        self.helm
            .config_errors()
            .iter()
            .map(|e| e.to_string())
            .collect()
    }

    /// The helm state (PARK, DRIVE, MALCONFIG, DISABLED).
    pub fn state(&self) -> HelmState {
        self.helm.state()
    }
}

/// Reads the behaviour files named by the `behaviors =` lines of helm block `name` (relative
/// to the mission's folder `dir`), each nsplug-expanded with `opts`, as one set (pHelmIvP
/// reads every file, each once, in name order). The errors are
/// `file:line: ...` messages: no block, no `behaviors =` line, a file that cannot be read, or
/// error lines in it (warnings stay in the returned file's diagnostics).
pub fn load_behaviors(
    mission: &MissionFile,
    dir: &Path,
    name: &str,
    opts: &Options,
    fs: &dyn FileSource,
) -> Result<Parsed<BehaviorFile>, Vec<String>> {
    let Some(block) = mission.process(name) else {
        return Err(vec![format!(
            "no ProcessConfig = {name} block in the mission"
        )]);
    };
    // pHelmIvP keeps its `behaviors =` files in a set: each file once, read in name order.
    let mut files: Vec<_> = block.params("behaviors").collect();
    if files.is_empty() {
        return Err(vec![format!(
            "{}:{}: {name}: no `behaviors =` file in its ProcessConfig block",
            block.span.file_name(),
            block.span.line
        )]);
    }
    files.sort_by(|a, b| a.value.cmp(&b.value));
    files.dedup_by(|a, b| a.value == b.value);
    let mut b = Parsed {
        value: BehaviorFile::default(),
        diagnostics: Vec::new(),
    };
    for file in files {
        let bpath = dir.join(&file.value);
        let mut one = mission::load_bhv(fs, &bpath, opts).map_err(|d| {
            vec![format!(
                "{}:{}: behaviour file `{}`: {d}",
                file.span.file_name(),
                file.span.line,
                bpath.display()
            )]
        })?;
        b.value.initializes.append(&mut one.value.initializes);
        b.value.modes.append(&mut one.value.modes);
        b.value.behaviors.append(&mut one.value.behaviors);
        b.diagnostics.append(&mut one.diagnostics);
    }
    let errors: Vec<String> = b
        .diagnostics
        .iter()
        .filter(|d| d.is_error())
        .map(|d| d.to_string())
        .collect();
    if errors.is_empty() {
        Ok(b)
    } else {
        Err(errors)
    }
}

impl App for HelmApp {
    fn malconfig(&self) -> Vec<String> {
        self.config_errors()
    }

    fn name(&self) -> &str {
        &self.name
    }

    fn process_config(&self) -> Option<&ProcessConfig> {
        self.block.as_ref()
    }

    fn app_tick(&self) -> f64 {
        self.tick
    }

    fn subscriptions(&self) -> Vec<Subscription> {
        AppcastLayer::subscriptions()
            .chain(self.registered.iter().cloned().map(Subscription::var))
            .collect()
    }

    // pHelmIvP posts its process id first thing in OnStartUp (single-app mode only: in
    // `coug run` the apps share one process and the log stays reproducible).
    fn set_process_id(&mut self, pid: u32) {
        self.pid = Some(pid);
    }

    fn set_process_load(&mut self, load: crate::procinfo::Load) {
        self.cpu_percent = Some(load.cpu_percent);
    }

    fn on_startup(&mut self, now: f64, out: &mut Vec<Post>) -> crate::app::AppResult {
        self.appcast.on_startup(now);
        if let Some(pid) = self.pid {
            out.push(Post::double("PHELMIVP_PID", f64::from(pid)));
        }
        Ok(())
    }

    fn new_subscriptions(&mut self) -> Vec<Subscription> {
        let mut fresh = Vec::new();
        for v in std::mem::take(&mut self.unregistered) {
            if !self.registered.contains(&v) {
                fresh.push(Subscription::var(v.clone()));
                self.registered.push(v);
            }
        }
        // Only the helm's registrations added since the last call (usually none).
        let subs = self.helm.subscriptions();
        for v in subs.get(self.helm_seen..).unwrap_or_default() {
            if !self.registered.contains(v) {
                fresh.push(Subscription::var(v.clone()));
                self.registered.push(v.clone());
            }
        }
        self.helm_seen = subs.len();
        fresh
    }

    fn on_mail(&mut self, mail: &[Mail], _now: f64, _out: &mut Vec<Post>) -> crate::app::AppResult {
        // RESTART_HELM = type1 | type2: the behaviours are read again (pHelmIvP).
        for m in mail.iter().filter(|m| m.key == "RESTART_HELM") {
            if let Value::String(kind) = &m.value
                && (kind == "type1" || kind == "type2")
            {
                self.restart(kind == "type1");
            }
        }
        // AppCastingMOOSApp takes its own mail before the app sees any; the helm reads no
        // binary data.
        let appcast = &mut self.appcast;
        let theirs = mail
            .iter()
            .filter(|m| appcast.take_mail(m) && !matches!(m.value, Value::Binary(_)));
        self.helm.on_mail(theirs);
        Ok(())
    }

    fn finished(&self) -> bool {
        matches!(self.failed, Some(Failed::Crashed))
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> crate::app::AppResult {
        // A process hung by BHV_TestFailure runs no iteration until the hang is over, then
        // publishes what the hung iteration posted; a crashed one posts nothing more.
        match &mut self.failed {
            Some(Failed::Crashed) => return Ok(()),
            Some(Failed::Burning { until, held }) => {
                if now < *until {
                    return Ok(());
                }
                out.append(held);
                self.failed = None;
                return Ok(());
            }
            None => {}
        }
        let start = out.len();
        self.iterate_helm(now, out);
        match self.helm.take_fault() {
            Some(::helm::Fault::Crash) => {
                out.truncate(start);
                self.failed = Some(Failed::Crashed);
            }
            Some(::helm::Fault::Burn(secs)) => {
                let held = out.split_off(start);
                self.failed = Some(Failed::Burning {
                    until: now + secs,
                    held,
                });
            }
            None => {}
        }
        Ok(())
    }
}

impl HelmApp {
    /// One pHelmIvP `Iterate`: the appcast layer, the helm's iteration, the appcast.
    fn iterate_helm(&mut self, now: f64, out: &mut Vec<Post>) {
        // AppCastingMOOSApp::Iterate comes first (APP_LOG, the load cast's gap).
        let tick = self.app_tick();
        self.appcast.begin(now, tick, out);
        // pHelmIvP posts its process's CPU load first thing in every iteration (single-app
        // mode: `coug run`'s apps share one process).
        if let Some(cpu) = self.cpu_percent {
            out.push(Post::double("IVPHELM_CPU", cpu));
        }
        // The helm's names are shared: copying a posting copies only a string value.
        for p in self.helm.iterate(now) {
            out.push(Post::new(&p.key, p.value.clone()).with_aux(&p.aux));
        }
        for note in self.helm.take_appcast_notes() {
            self.appcast.note(note, now);
        }
        // pHelmIvP posts no report in the first second of deciding (it returns early).
        if self.helm.in_decision_delay() {
            return;
        }
        let helm = &self.helm;
        let policy = self.appcast.comms_policy();
        self.appcast
            .end(now, tick, out, |body| helm.appcast_body(now, policy, body));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mission::source::SourceMap;

    #[test]
    fn registers_the_variables_of_mode_conditions() {
        let moos = "Community = c\nLatOrigin = 43.8\nLongOrigin = -70.3\nProcessConfig = pHelmIvP\n{\n  domain = course:0:359:360\n  domain = speed:0:4:41\n}\n";
        let m = mission::moos::parse_moos(&SourceMap::from_text("m.moos", moos)).value;
        let bhv = "initialize DEPLOY = false\nset MODE = ACTIVE {\n  DEPLOY = true\n  (QUIT != yes)\n} INACTIVE\n\
                   Behavior = BHV_ConstantSpeed\n{\n  name = cs\n  condition = MODE == ACTIVE\n  speed = 1\n}\n";
        let b = mission::bhv::parse_bhv(&SourceMap::from_text("m.bhv", bhv));
        let h = HelmApp::new("pHelmIvP", m.process("pHelmIvP").cloned(), &m, &b);
        assert!(h.config_errors().is_empty(), "{:?}", h.config_errors());
        let subs: Vec<String> = h.subscriptions().into_iter().map(|s| s.pattern).collect();
        for v in ["DEPLOY", "QUIT", "MODE", "NAV_X"] {
            assert!(subs.iter().any(|s| s == v), "{v} not in {subs:?}");
        }
        let n = subs.len();
        let mut dedup = subs.clone();
        dedup.sort();
        dedup.dedup();
        assert_eq!(dedup.len(), n, "no duplicate registrations");
    }

    const MOOS_TWO_FILES: &str = "Community = c\nLatOrigin = 43.8\nLongOrigin = -70.3\n\
        ProcessConfig = pHelmIvP\n{\n  behaviors = b.bhv\n  behaviors = a.bhv\n  \
        domain = course:0:359:360\n  domain = speed:0:4:41\n}\n";

    fn mission_of(text: &str) -> MissionFile {
        mission::moos::parse_moos(&SourceMap::from_text("m.moos", text)).value
    }

    #[test]
    fn every_behaviors_file_is_read_in_name_order() {
        let m = mission_of(MOOS_TWO_FILES);
        let fs = mission::source::MemorySource::new()
            .with(
                "a.bhv",
                "Behavior = BHV_ConstantSpeed\n{\n  name = spd\n  speed = 1\n}\n",
            )
            .with(
                "b.bhv",
                "Behavior = BHV_ConstantHeading\n{\n  name = hdg\n  heading = 10\n}\n",
            );
        let b = load_behaviors(&m, Path::new(""), "pHelmIvP", &Options::new(), &fs).unwrap();
        let names: Vec<&str> = b.value.behaviors.iter().map(|s| s.kind.as_str()).collect();
        assert_eq!(names, ["BHV_ConstantSpeed", "BHV_ConstantHeading"]);
        let h = HelmApp::from_mission_files("pHelmIvP", &m, Path::new(""), &Options::new(), &fs);
        assert!(h.config_errors().is_empty(), "{:?}", h.config_errors());
    }

    #[test]
    fn a_missing_or_broken_behaviour_file_is_malconfig_not_a_failure() {
        let m = mission_of(MOOS_TWO_FILES);
        let only_a = mission::source::MemorySource::new().with(
            "a.bhv",
            "Behavior = BHV_ConstantSpeed\n{\n  name = spd\n  speed = 1\n}\n",
        );
        let h =
            HelmApp::from_mission_files("pHelmIvP", &m, Path::new(""), &Options::new(), &only_a);
        assert_eq!(h.state(), HelmState::Malconfig);
        let errors = h.config_errors();
        assert!(
            errors.len() == 1 && errors[0].contains("m.moos:") && errors[0].contains("b.bhv"),
            "{errors:?}"
        );
        // No block at all: MALCONFIG too.
        let h =
            HelmApp::from_mission_files("pHelmIvP_2", &m, Path::new(""), &Options::new(), &only_a);
        assert_eq!(h.state(), HelmState::Malconfig);
        assert!(!h.config_errors().is_empty());
    }
}

#[cfg(test)]
mod appcast_tests {
    use super::*;
    use mission::source::SourceMap;

    const MOOS: &str = "Community = alpha\nLatOrigin = 43.8\nLongOrigin = -70.3\n\
        ProcessConfig = pHelmIvP\n{\n  behaviors = a.bhv\n  term_report_interval = 0.5\n  \
        start_engaged = true\n  domain = course:0:359:360\n  domain = speed:0:4:41\n}\n";
    const BHV: &str = "Behavior = BHV_ConstantSpeed\n{\n  name = spd\n  speed = 1\n  \
        duration = no-time-limit\n}\n";

    fn app(moos: &str) -> HelmApp {
        let m = mission::moos::parse_moos(&SourceMap::from_text("m.moos", moos)).value;
        let fs = mission::source::MemorySource::new().with("a.bhv", BHV);
        HelmApp::from_mission_files("pHelmIvP", &m, Path::new(""), &Options::new(), &fs)
    }

    fn mail(key: &str, value: Value, time: f64) -> Mail {
        Mail {
            key: key.into(),
            value,
            time,
            source: "uMAC".into(),
            source_aux: Default::default(),
            community: "alpha".into(),
        }
    }

    fn step(h: &mut HelmApp, t: f64, extra: Vec<Mail>) -> Vec<Post> {
        let mut m: Vec<Mail> = ["NAV_X", "NAV_Y", "NAV_HEADING", "NAV_SPEED"]
            .iter()
            .map(|v| mail(v, Value::Double(0.0), t))
            .collect();
        m.extend(extra);
        let mut out = Vec::new();
        h.on_mail(&m, t, &mut out).unwrap();
        h.iterate(t, &mut out).unwrap();
        out
    }

    fn appcasts(p: &[Post]) -> Vec<appcast::AppCast> {
        p.iter()
            .filter(|p| p.key == "APPCAST")
            .map(|p| appcast::AppCast::parse(p.value.as_str().unwrap()))
            .collect()
    }

    #[test]
    fn the_helm_appcasts_on_request_with_its_report() {
        let mut h = app(MOOS);
        assert!(
            h.subscriptions().iter().any(|s| s.pattern == "APPCAST_REQ"),
            "AppCastingMOOSApp registers APPCAST_REQ"
        );
        let mut out = Vec::new();
        h.on_startup(100.0, &mut out).unwrap();
        // First iteration: inside the first second of deciding, no report (pHelmIvP
        // returns early); the second is past it but no longer "iteration < 2" and nobody
        // asked: none either.
        assert!(appcasts(&step(&mut h, 100.0, vec![])).is_empty());
        assert!(appcasts(&step(&mut h, 101.0, vec![])).is_empty());
        // A viewer asks: the next iteration posts one.
        let req = "node=alpha,app=pHelmIvP,duration=3.0,key=uMAC_1,thresh=any";
        let p = step(
            &mut h,
            101.25,
            vec![mail("APPCAST_REQ", Value::text(req), 101.25)],
        );
        let ac = appcasts(&p);
        assert_eq!(ac.len(), 1);
        assert_eq!(ac[0].proc_name(), "pHelmIvP");
        assert_eq!(ac[0].node_name(), "alpha");
        assert_eq!(ac[0].iteration(), 3);
        let raw = p
            .iter()
            .find(|p| p.key == "APPCAST")
            .unwrap()
            .value
            .as_str()
            .unwrap();
        assert!(
            raw.contains("!@#messages=  Comms Policy: open!@  Helm Iteration:  2!@"),
            "{raw}"
        );
        let body = ac[0].messages();
        assert!(
            body.contains("Behaviors Active: ---------- (1)\n  spd ["),
            "{body}"
        );
        assert!(body.contains("Hold-On-Apps: none"), "{body}");
        // The table of the behaviours' latest postings, BHV_STATUS among them.
        assert!(
            body.contains("Variable    Behavior  Time  Iter  Value"),
            "{body}"
        );
        assert!(
            body.contains("\nBHV_STATUS  spd       1.00  1     name=spd,"),
            "{body}"
        );
        // Rate limit: 0.5 s of real time between reports (warp 1).
        assert!(appcasts(&step(&mut h, 101.5, vec![])).is_empty());
        assert_eq!(appcasts(&step(&mut h, 101.75, vec![])).len(), 1);
        // The request expires after its 3 s.
        assert!(appcasts(&step(&mut h, 104.5, vec![])).is_empty());
        // The appcast's own variables do not reach the helm's info buffer.
        assert!(!h.helm.info().is_known("APPCAST_REQ"));
        // A load cast: the gap between iterations over the tick period (AppTick 5: 0.2 s),
        // and the iteration's length, 0 in MOOS time.
        let p = step(
            &mut h,
            105.0,
            vec![mail(
                "LOADCAST_REQ",
                Value::text("app=all,duration=2"),
                105.0,
            )],
        );
        let num =
            |p: &[Post], k: &str| p.iter().find(|p| p.key == k).and_then(|p| p.value.as_f64());
        // Mail comes before the iteration: 0.5 s since the one at 104.5.
        assert_eq!(num(&p, "PHELMIVP_ITER_GAP"), Some(2.5));
        assert_eq!(num(&p, "PHELMIVP_ITER_LEN"), Some(0.0));
        assert_eq!(
            p[0].key, "PHELMIVP_ITER_GAP",
            "first thing in the iteration"
        );
        let p = step(&mut h, 105.2, vec![]);
        assert_eq!(
            num(&p, "PHELMIVP_ITER_GAP").map(|g| (g * 1e9).round() / 1e9),
            Some(1.0)
        );
        let p = step(&mut h, 107.0, vec![]);
        assert_eq!(num(&p, "PHELMIVP_ITER_GAP"), None, "the request lasted 2 s");
        // A parked helm returns before the delay, with its report: the first iteration
        // posts one ("iteration < 2").
        let mut parked = app(&MOOS.replace("start_engaged = true", "start_engaged = false"));
        parked.on_startup(0.0, &mut Vec::new()).unwrap();
        let ac = appcasts(&step(&mut parked, 0.0, vec![]));
        assert_eq!(ac.len(), 1);
        assert!(ac[0].messages().contains("  Helm Iteration:  0\n"));
        assert!(appcasts(&step(&mut parked, 0.25, vec![])).is_empty());
    }

    #[test]
    fn app_logging_log_posts_app_log_first_in_each_iteration() {
        let mut h = app(&MOOS.replace("start_engaged = true", "app_logging = log"));
        assert_eq!(h.state(), HelmState::Park);
        h.on_startup(0.0, &mut Vec::new()).unwrap();
        for (t, k) in [(0.0, 1), (0.2, 2)] {
            let p = step(&mut h, t, vec![]);
            assert_eq!(p[0].key, "APP_LOG");
            assert_eq!(p[0].value.as_str(), Some(format!("iter={k},log=").as_str()));
        }
        assert!(
            !step(&mut app(MOOS), 0.0, vec![])
                .iter()
                .any(|p| p.key == "APP_LOG")
        );
    }

    #[test]
    fn a_malconfig_helm_appcasts_its_reasons_at_once() {
        let moos = MOOS.replace("term_report_interval = 0.5", "term_report_interval = abc");
        let mut h = app(&moos);
        assert_eq!(h.state(), HelmState::Malconfig);
        assert_eq!(
            h.config_errors(),
            ["Invalid TERM_REPORT_INTERVAL: abc".to_string()]
        );
        let mut out = Vec::new();
        h.on_startup(0.0, &mut out).unwrap();
        let ac = appcasts(&step(&mut h, 0.0, vec![]));
        assert_eq!(ac.len(), 1, "a new config warning makes a report due");
        assert_eq!(
            ac[0].config_warnings(),
            ["Invalid TERM_REPORT_INTERVAL: abc".to_string()]
        );
        assert!(
            ac[0]
                .messages()
                .contains("!!  The helm is in the MALCONFIG state due to  !!")
        );
    }
}
