//! Several communities in one `coug run` (issue #16, point 4): the project's fleet mission
//! (missions/fleet_survey: a shoreside and three vehicles from one template) in lockstep,
//! deployed and recalled from the shoreside through pShare's in-process route; every
//! vehicle completes, the shoreside logs every vehicle's node reports, and two runs write
//! the same bytes in every community's alog (one on one thread, one with a thread per
//! community). Also the `coug run a.moos b.moos` form, the
//! fleet file's errors, and a small real-time fleet (one TCP MOOSDB per community).

mod common;

use test_support::missions::{self, counting_events, pshare_community};

use std::collections::BTreeMap;
use std::path::Path;

use common::*;
use runtime::fleet::LoadedFleet;
use runtime::session::{self, Ended, FleetOptions, FleetReport, Mode};

const VEHICLES: [&str; 3] = ["henry", "ike", "jing"];

/// Runs the fleet file in lockstep in process, logging under a fresh folder `name`; returns
/// the report and every community's alog bytes by name.
fn run_fleet(
    name: &str,
    fleet: &Path,
    opts: FleetOptions,
) -> (FleetReport, BTreeMap<String, Vec<u8>>) {
    let dir = fresh_dir(name);
    let loaded = LoadedFleet::from_file(fleet, &[], &[])
        .unwrap_or_else(|e| panic!("{} does not load: {e}", fleet.display()));
    let checked = session::validate_fleet(&loaded);
    assert!(checked.errors.is_empty(), "{:?}", checked.errors);
    assert!(checked.malconfig.is_empty(), "{:?}", checked.malconfig);
    let opts = FleetOptions {
        mode: Mode::Lockstep,
        log_dir: Some(dir.join("logs")),
        ..opts
    };
    let report = session::run_fleet(&loaded, &opts, &mut session::Quiet)
        .unwrap_or_else(|e| panic!("fleet run failed: {e}"));
    let mut logs = BTreeMap::new();
    for (member, r) in &report.members {
        // Each community logs in its own folder.
        let alog = find_alog(&dir.join("logs").join(member));
        assert_eq!(Path::new(&r.alog), alog, "the report names {member}'s log");
        logs.insert(member.clone(), std::fs::read(&alog).expect("alog readable"));
    }
    (report, logs)
}

fn deployed_until_complete() -> FleetOptions {
    FleetOptions {
        buttons: vec!["shoreside:DEPLOY".into()],
        until: vec!["MISSION = complete".into()],
        max_time: 900.0,
        ..FleetOptions::default()
    }
}

#[test]
fn fleet_survey_completes_through_the_shoreside_and_is_repeatable() {
    let fleet = project_mission("fleet_survey/fleet_survey.fleet");
    // One thread steps the communities, then one thread each: the same bytes.
    let threads = |n| FleetOptions {
        threads: n,
        ..deployed_until_complete()
    };
    let (report, a) = run_fleet("run-fleet-1", &fleet, threads(1));
    let (_, b) = run_fleet("run-fleet-1", &fleet, threads(4));
    let summary = report.to_string();
    assert!(
        matches!(
            report.ended,
            Ended::Outcome(runtime::Outcome::ConditionMet { .. })
        ),
        "{summary}"
    );
    assert_eq!(a.len(), 4, "{summary}");
    for (name, bytes) in &a {
        assert!(
            *bytes == b[name],
            "lockstep runs of the fleet on 1 and 4 threads wrote different alogs for {name}"
        );
    }
    assert!(report.in_process > 0, "{summary}");

    // Every vehicle surveyed its own lane and came home; the deploy came from the shoreside.
    let lanes = [
        (0.0, 20.0, 40.0),
        (60.0, 80.0, 100.0),
        (120.0, 140.0, 160.0),
    ];
    for (v, (home, x1, x2)) in VEHICLES.iter().zip(lanes) {
        let r = report.member(v).expect("a report per vehicle");
        let totals = r.totals.as_ref().expect("totals");
        assert_eq!(totals.completed, ["survey", "return"], "{v}: {summary}");
        let log = parse(&a[*v]);
        assert_eq!(
            last_str(&log, "MISSION").as_deref(),
            Some("complete"),
            "{v}"
        );
        let t = track(&log);
        let points = [(x1, -20.0), (x1, -100.0), (x2, -100.0), (x2, -20.0)];
        let after = visits_in_order(&t, &points, 10.0, 0);
        visits_in_order(&t, &[(home, 0.0)], 8.0, after);
        // DEPLOY and MOOS_MANUAL_OVERRIDE reached the vehicle relayed by pShare from the
        // shoreside's button press (posted there by uPokeDB): never poked in the vehicle.
        let deploys: Vec<&alog::Entry> = log
            .entries
            .iter()
            .filter(|e| e.var == "DEPLOY" && e.value.as_str() == Some("true"))
            .collect();
        assert_eq!(deploys.len(), 1, "{v}: one DEPLOY=true");
        assert_eq!(deploys[0].source, "uPokeDB");
        assert!(!log.entries.iter().any(|e| e.var == "DEPLOY_ALL"));
        let overrides = log
            .entries
            .iter()
            .filter(|e| e.var == "MOOS_MANUAL_OVERRIDE")
            .count();
        assert_eq!(overrides, 1, "{v}: MOOS_MANUAL_OVERRIDE relayed once");
    }

    // The shoreside heard every vehicle's node reports, renamed NODE_REPORT, all along.
    let shore = parse(&a["shoreside"]);
    for v in VEHICLES {
        let reports: Vec<f64> = shore
            .entries
            .iter()
            .filter(|e| e.var == "NODE_REPORT")
            .filter(|e| {
                e.value
                    .as_str()
                    .is_some_and(|s| s.starts_with(&format!("NAME={v},")))
            })
            .map(|e| e.time)
            .collect();
        assert!(reports.len() > 200, "{v}: {} node reports", reports.len());
        let last = reports.last().copied().unwrap_or(0.0);
        assert!(last > report.sim_s() - 2.0, "{v}: last report at {last}");
    }
    assert!(!shore.entries.iter().any(|e| e.var == "NODE_REPORT_LOCAL"));
}

#[test]
fn the_shoreside_recalls_every_vehicle_mid_survey() {
    let fleet = project_mission("fleet_survey/fleet_survey.fleet");
    let opts = FleetOptions {
        buttons: vec!["shoreside:DEPLOY".into()],
        pokes: vec!["shoreside:RETURN_ALL=true@30".into()],
        until: vec!["MISSION = complete".into()],
        max_time: 600.0,
        ..FleetOptions::default()
    };
    let (report, logs) = run_fleet("run-fleet-return", &fleet, opts);
    assert!(!report.until_pending(), "{report}");
    let lanes = [20.0, 80.0, 140.0];
    for (v, x1) in VEHICLES.iter().zip(lanes) {
        let log = parse(&logs[*v]);
        let totals = report.member(v).and_then(|r| r.totals.clone()).unwrap();
        // Recalled: the return completed, the survey did not.
        assert_eq!(totals.completed, ["return"], "{v}");
        let t = track(&log);
        assert!(
            t.iter().all(|&(_, x, y)| (x - x1).hypot(y + 100.0) > 20.0),
            "{v} reached the far end of its first leg"
        );
        let ret = log
            .entries
            .iter()
            .find(|e| e.var == "RETURN" && e.value.as_str() == Some("true"))
            .expect("RETURN reached the vehicle");
        assert_eq!(
            ret.source, "uPokeDB",
            "{v}: RETURN relayed from the shoreside"
        );
    }
}

#[test]
fn a_list_of_missions_is_a_fleet_named_by_community() {
    let dir = fresh_dir("run-fleet-list");
    let survey = project_mission("surface_survey/survey.moos");
    let shore = project_mission("fleet_survey/shoreside.moos");
    let o = coug(
        &dir,
        &[
            "run",
            survey.to_str().unwrap(),
            shore.to_str().unwrap(),
            "VNAME=base",
            "SHORE_PORT=9000",
            "SHORE_LISTEN=9300",
            "--lockstep",
            "--deploy",
            "--until",
            "MISSION = complete",
            "--log-dir",
            "logs",
        ],
    );
    let stdout = String::from_utf8_lossy(&o.stdout);
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{stdout}\n{}", tail(&stderr, 20));
    assert!(
        stdout.contains("[surveyor]") && stdout.contains("[base]"),
        "{stdout}"
    );
    assert!(stdout.contains("completed: survey, return"), "{stdout}");
    let base = parse(&std::fs::read(find_alog(&dir.join("logs/base"))).unwrap());
    // The base's DEPLOY button was pressed too (--deploy deploys every community).
    assert_eq!(last_str(&base, "DEPLOY_ALL").as_deref(), Some("true"));
    let surveyor = parse(&std::fs::read(find_alog(&dir.join("logs/surveyor"))).unwrap());
    assert_eq!(last_str(&surveyor, "MISSION").as_deref(), Some("complete"));
}

#[test]
fn fleet_errors_name_their_line_and_targets_must_exist() {
    let dir = fresh_dir("run-fleet-errors");
    std::fs::write(
        dir.join("bad.fleet"),
        "template = v.moos\nvehicle = a\nboat = b\nvehicle = a\n",
    )
    .unwrap();
    let o = coug(&dir, &["run", "bad.fleet", "--lockstep"]);
    assert_eq!(o.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("bad.fleet:3: unknown key \"boat\"")
            && stderr.contains("bad.fleet:4: a is named twice (first at line 2)"),
        "{stderr}"
    );
    let fleet = project_mission("fleet_survey/fleet_survey.fleet");
    let o = coug(
        &dir,
        &[
            "run",
            fleet.to_str().unwrap(),
            "--lockstep",
            "--poke",
            "bob:DEPLOY=true",
        ],
    );
    assert_eq!(o.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("--poke bob:DEPLOY=true: no community bob in the fleet (it has shoreside, henry, ike, jing)"),
        "{stderr}"
    );
}

/// The surface-only radio in a lockstep fleet: a vehicle whose pShare sets
/// `radio_max_depth` stops reaching the shoreside (and hearing it) while its `NAV_DEPTH` is
/// deeper, hears and is heard again on surfacing, and nothing of the dive is replayed.
#[test]
fn a_diving_vehicle_leaves_the_radio_link_and_rejoins_it_at_the_surface() {
    let dir = fresh_dir("run-fleet-radio");
    let events = |var: &str| counting_events(var, 30);
    // Lockstep opens neither the MOOSDB ports nor the in-process pShare routes.
    let mission = pshare_community;
    let diver = mission(
        "diver",
        "  radio_max_depth = 1\n  input = route = localhost:39511\n  \
         output = PING->localhost:39510\n",
        &format!(
            "  event = var=NAV_DEPTH, val=0, time=0.5\n  event = var=NAV_DEPTH, val=3, time=9.5\n  \
             event = var=NAV_DEPTH, val=0.4, time=19.5\n  event = var=DONE, val=1, time=31\n{}",
            events("PING")
        ),
    );
    let shore = mission(
        "shore",
        "  input = route = localhost:39510\n  output = SHORE_PING->localhost:39511\n",
        &events("SHORE_PING"),
    );
    std::fs::write(dir.join("diver.moos"), diver).unwrap();
    std::fs::write(dir.join("shore.moos"), shore).unwrap();
    let loaded =
        LoadedFleet::from_missions(&[dir.join("shore.moos"), dir.join("diver.moos")], &[], &[])
            .expect("loads");
    let checked = session::validate_fleet(&loaded);
    assert!(checked.warnings.is_empty(), "{:?}", checked.warnings);
    let opts = FleetOptions {
        mode: Mode::Lockstep,
        until: vec!["diver: DONE = 1".into()],
        max_time: 60.0,
        log_dir: Some(dir.join("logs")),
        ..FleetOptions::default()
    };
    let report = session::run_fleet(&loaded, &opts, &mut session::Quiet).expect("runs");
    assert!(!report.until_pending(), "{report}");
    let heard = |community: &str, var: &str| -> Vec<u32> {
        let log = parse(&std::fs::read(find_alog(&dir.join("logs").join(community))).unwrap());
        log.entries
            .iter()
            .filter(|e| e.var == var)
            .map(|e| e.value.as_f64().expect("a number") as u32)
            .collect()
    };
    // Sent at 1..9 s (at the surface) and from 20 s on; none from the dive, none replayed.
    let pings = heard("shore", "PING");
    let want: Vec<u32> = (1..=9).chain(20..=30).collect();
    assert_eq!(pings, want);
    // What the shoreside sent during the dive (and at 19 s, read by the diver at 19.25 s,
    // still under) was dropped on arrival.
    let shore_pings = heard("diver", "SHORE_PING");
    assert_eq!(shore_pings[..9], [1, 2, 3, 4, 5, 6, 7, 8, 9]);
    assert!(
        shore_pings[9..].iter().all(|k| *k >= 20) && shore_pings.contains(&20),
        "{shore_pings:?}"
    );
}

/// A real-time fleet of two tiny communities, each with its own TCP MOOSDB on a port the
/// system picks (ServerPort = 0): each runs until its own condition holds.
#[test]
fn a_real_time_fleet_gives_each_community_its_own_db() {
    let dir = fresh_dir("run-fleet-realtime");
    let mission = |community: &str, var: &str| {
        let script = format!("  AppTick = 20\n  event = var={var}, val=1, time=0.2\n");
        missions::community(
            community,
            0,
            &[
                ("pLogger", missions::WILDCARD_LOGGER),
                ("uTimerScript", &script),
            ],
        )
    };
    std::fs::write(dir.join("a.moos"), mission("alpha", "A_DONE")).unwrap();
    std::fs::write(dir.join("b.moos"), mission("bravo", "B_DONE")).unwrap();
    let loaded = LoadedFleet::from_missions(&[dir.join("a.moos"), dir.join("b.moos")], &[], &[])
        .expect("loads");
    let opts = realtime_two(&dir, ["alpha: A_DONE = 1", "bravo: B_DONE = 1"]);
    let mut notices = Notices::default();
    let report = session::run_fleet(&loaded, &opts, &mut notices).expect("runs");
    assert!(!report.until_pending(), "{report}");
    // Two DBs, each on its own port.
    let listening: Vec<&String> = notices
        .0
        .iter()
        .filter(|n| n.contains("listening on"))
        .collect();
    assert_eq!(listening.len(), 2, "{:?}", notices.0);
    assert!(
        listening
            .iter()
            .any(|n| n.starts_with("alpha: MOOSDB_alpha"))
    );
    assert!(
        listening
            .iter()
            .any(|n| n.starts_with("bravo: MOOSDB_bravo"))
    );
    for (name, var) in [("alpha", "A_DONE"), ("bravo", "B_DONE")] {
        let log = parse(&std::fs::read(find_alog(&dir.join("logs").join(name))).unwrap());
        assert!(
            log.entries.iter().any(|e| e.var == var),
            "{name} logged {var}"
        );
    }
}

/// A real-time fleet tells its observer every community's progress values (`NAME:VAR`) and
/// helm summaries, as a lockstep one does: what `coug run X.fleet` prints per community.
#[test]
fn a_real_time_fleet_reports_each_communitys_progress() {
    let dir = fresh_dir("run-fleet-realtime-progress");
    let mission = |community: &str, x: f64| {
        let script = format!(
            "  AppTick = 20\n  event = var=NAV_X, val={x}, time=0.1\n  \
             event = var=IVPHELM_STATE, val=PARK, time=0.1\n  event = var=DONE, val=1, time=4\n"
        );
        missions::community(community, 0, &[("uTimerScript", &script)])
    };
    std::fs::write(dir.join("a.moos"), mission("alpha", 1.5)).unwrap();
    std::fs::write(dir.join("b.moos"), mission("bravo", -2.5)).unwrap();
    let loaded = LoadedFleet::from_missions(&[dir.join("a.moos"), dir.join("b.moos")], &[], &[])
        .expect("loads");
    let opts = realtime_two(&dir, ["alpha: DONE = 1", "bravo: DONE = 1"]);
    let mut seen = Progress::default();
    let report = session::run_fleet(&loaded, &opts, &mut seen).expect("runs");
    assert!(!report.until_pending(), "{report}");
    assert!(seen.steps > 0);
    for (key, want) in [
        ("alpha:NAV_X", "1.5"),
        ("bravo:NAV_X", "-2.5"),
        ("alpha:IVPHELM_STATE", "PARK"),
        ("bravo:IVPHELM_STATE", "PARK"),
        // A plain name reads the first vehicle's (here the first community: no helm runs).
        ("NAV_X", "1.5"),
    ] {
        assert_eq!(
            seen.values.get(key).map(String::as_str),
            Some(want),
            "{key}"
        );
    }
    // Nothing is reported for a community the fleet does not have.
    assert!(!seen.values.contains_key("charlie:NAV_X"));
    // Simulated time only grows.
    assert!(
        seen.times.windows(2).all(|w| w[0] <= w[1]),
        "{:?}",
        seen.times
    );
}

/// What a fleet's observer was told about progress.
#[derive(Default)]
struct Progress {
    steps: usize,
    times: Vec<f64>,
    values: BTreeMap<String, String>,
}

impl session::Observer for Progress {
    fn step(&mut self, sim_s: f64, current: &dyn Fn(&str) -> Option<runtime::app::Value>) {
        self.steps += 1;
        self.times.push(sim_s);
        for k in [
            "alpha:NAV_X",
            "bravo:NAV_X",
            "alpha:IVPHELM_STATE",
            "bravo:IVPHELM_STATE",
            "NAV_X",
            "charlie:NAV_X",
        ] {
            if let Some(v) = current(k) {
                let text = match v {
                    runtime::app::Value::Double(x) => x.to_string(),
                    v => v.as_str().unwrap_or_default().to_string(),
                };
                self.values.insert(k.to_string(), text);
            }
        }
    }
}

#[derive(Default)]
struct Notices(Vec<String>);

impl session::Observer for Notices {
    fn notice(&mut self, text: &str) {
        self.0.push(text.to_string());
    }
}

/// Real-time options for the two-community fleets above: warp 4, system-picked ports, until
/// both conditions hold, at most 60 s, logs in `dir/logs`.
fn realtime_two(dir: &std::path::Path, until: [&str; 2]) -> FleetOptions {
    FleetOptions {
        mode: Mode::RealTime {
            warp: Some(4.0),
            port: None,
        },
        until: until.iter().map(|u| u.to_string()).collect(),
        max_time: 60.0,
        log_dir: Some(dir.join("logs")),
        ..FleetOptions::default()
    }
}
