//! COLREGS encounters in lockstep (issue #18, point 4): the fleets of
//! `missions/encounters_colregs` (two vehicles head-on, crossing and overtaking, three
//! converging), each vehicle's pBasicContactMgr alerting its helm and the helm spawning a
//! BHV_AvdColregsV22 per contact. With the behaviour every closest approach stays above its
//! `min_util_cpa_dist` (10 m) and each vehicle enters the rule's mode; the same fleets with
//! `AVOID=false` collide (closest approach under 3 m). Each fleet runs a third time with
//! `REFINERY=on` (the CPA function's `use_refinery` and `check_plateaus`, MOOS `RefineryCPA`):
//! the same modes, the give-way vessel turning to starboard, every closest approach above
//! the minimum, and the checks' `PLATEAU_CHECK_OK`, `BASIN_CHECK_OK`, `PLATEAU_LOGIC_CASE`
//! and `PLATEAU_WORST_FAIL` postings; BHV_AvdColregsV19 likewise in the two-vehicle
//! encounters. Also the stock berta missions
//! (m2_berta, berta_cmgr) checked and run as fleets: the shoreside's uFldNodeComms relays each
//! vehicle's reports to the other, whose pContactMgrV20 alerts its helm, which spawns and
//! runs an AvdColregsV22 for it; they keep above its `min_util_cpa_dist`, repeatably.

mod common;
mod encounters;

use std::collections::BTreeMap;
use std::path::Path;

use common::*;
use encounters::{closest, has, run_fleet, values};
use runtime::fleet::LoadedFleet;
use runtime::session::{self, FleetOptions, Mode};

/// The behaviour's `min_util_cpa_dist` in `vehicle.bhv`.
const MIN_UTIL_CPA: f64 = 10.0;

/// Runs `fleet` (a file of `missions/encounters_colregs`) with the extra command-line
/// `macros` until every vehicle completes its transit; returns every vehicle's parsed alog.
fn run(name: &str, fleet: &str, macros: &[&str]) -> BTreeMap<String, alog::Alog> {
    run_fleet("encounters_colregs", name, fleet, macros)
}

/// One fleet's runs with the behaviour: as the mission has it, and with `REFINERY=on`.
struct Runs {
    on: BTreeMap<String, alog::Alog>,
    refined: BTreeMap<String, alog::Alog>,
}

impl Runs {
    /// Both runs' logs.
    fn both(&self) -> [&BTreeMap<String, alog::Alog>; 2] {
        [&self.on, &self.refined]
    }
}

/// Runs `fleet` with the behaviour, with it and its refinery ([`refined`]), and without it:
/// with it, every closest approach is above `min_util_cpa_dist`; without it, some pair
/// comes within 3 m.
fn encounter(fleet: &str) -> Runs {
    let stem = fleet.trim_end_matches(".fleet");
    let refined = refined(fleet, "V22");
    let on = run(&format!("colregs-{stem}-on"), fleet, &[]);
    for ((a, b), (r, t)) in closest(&on) {
        eprintln!("{stem} with AvdColregsV22: {a}-{b} closest {r:.2} m at t={t:.2}");
        assert!(
            r > MIN_UTIL_CPA,
            "{stem}: {a} and {b} came within {r:.2} m at t={t:.2}"
        );
    }
    let off = run(&format!("colregs-{stem}-off"), fleet, &["AVOID=false"]);
    let pairs = closest(&off);
    for ((a, b), (r, t)) in &pairs {
        eprintln!("{stem} without: {a}-{b} closest {r:.2} m at t={t:.2}");
    }
    assert!(
        pairs.iter().any(|(_, (r, _))| *r < 3.0),
        "{stem}: without the behaviour the vehicles should have collided: {pairs:?}"
    );
    // Off, the spawned behaviours never ran: no function.
    for log in off.values() {
        assert!(!has(log, "BHV_IPF", "col_"));
    }
    Runs { on, refined }
}

#[test]
fn head_on_both_vehicles_turn_to_starboard() {
    let runs = encounter("headon.fleet");
    for on in runs.both() {
        // Each spawned a behaviour for the other and classified the encounter as head-on.
        assert!(has(
            &on["abe"],
            "IVPHELM_LIFE_EVENT",
            "bname=col_ben, btype=BHV_AvdColregsV22, event=spawn"
        ));
        assert!(has(&on["abe"], "COLREGS_AVOID_MODE_BEN", "headon"));
        assert!(has(&on["ben"], "COLREGS_AVOID_MODE_ABE", "headon"));
        assert!(has(&on["abe"], "COL22_AVOID_MODE_BEN", "headon"));
        // Starboard to port: abe (heading north) passes ben on its own left, i.e. abe ends
        // up east of ben when abeam; each turned to starboard first.
        let at = |log: &alog::Alog, t0: f64| {
            track(log)
                .into_iter()
                .find(|(t, _, _)| *t >= t0)
                .map(|(_, x, _)| x)
                .unwrap()
        };
        let (_, (_, t)) = &closest(on)[0];
        assert!(
            at(&on["abe"], *t) > at(&on["ben"], *t),
            "abe passes east of ben"
        );
        for v in ["abe", "ben"] {
            let turn = first_turn(&on[v]);
            assert!(turn > 0.0, "{v} turned {turn:.1} degrees");
        }
        // Once clear, the behaviours completed.
        assert!(has(&on["abe"], "CONTACT_RESOLVED", "ben"));
    }
}

#[test]
fn crossing_the_give_way_vessel_keeps_clear_and_the_other_stands_on() {
    let runs = encounter("crossing.fleet");
    for on in runs.both() {
        // ben comes from abe's starboard side: abe gives way, turning to starboard; ben
        // stands on.
        assert!(has(&on["abe"], "COLREGS_AVOID_MODE_BEN", "giveway"));
        assert!(has(&on["ben"], "COLREGS_AVOID_MODE_ABE", "standon"));
        let turn = first_turn(&on["abe"]);
        assert!(turn > 0.0, "abe turned {turn:.1} degrees");
    }
}

#[test]
fn overtaking_the_faster_vessel_keeps_clear() {
    let runs = encounter("overtaking.fleet");
    for on in runs.both() {
        assert!(has(&on["ben"], "COLREGS_AVOID_MODE_ABE", "overtaking"));
        assert!(has(&on["abe"], "COLREGS_AVOID_MODE_BEN", "standon_ot"));
    }
}

#[test]
fn three_vehicles_converging_keep_apart() {
    let runs = encounter("three.fleet");
    for on in runs.both() {
        // cal crosses abe's bow from its starboard side and ben's from its port side.
        assert!(has(&on["abe"], "COLREGS_AVOID_MODE_CAL", "giveway"));
        assert!(has(&on["cal"], "COLREGS_AVOID_MODE_ABE", "standon"));
        assert!(has(&on["cal"], "COLREGS_AVOID_MODE_BEN", "giveway"));
        assert!(has(&on["ben"], "COLREGS_AVOID_MODE_CAL", "standon"));
        let turn = first_turn(&on["abe"]);
        assert!(turn > 0.0, "abe turned {turn:.1} degrees");
        // Every vehicle spawned one behaviour per other vehicle.
        for (me, log) in on {
            for other in on.keys().filter(|o| *o != me) {
                let bname = format!("bname=col_{other}, btype=BHV_AvdColregsV22, event=spawn");
                assert!(has(log, "IVPHELM_LIFE_EVENT", &bname), "{me}: {bname}");
            }
        }
    }
}

/// BHV_AvdColregsV19 (the same engine, V19's parameters and postings) with `REFINERY=on`
/// in the two-vehicle encounters: the same modes, the give-way turns to starboard, every
/// closest approach above `min_util_cpa_dist`, and the refinery's checks posted.
#[test]
fn v19_with_the_refinery_keeps_clear() {
    let on = refined("headon.fleet", "V19");
    assert!(has(&on["abe"], "COLREGS_AVOID_MODE_BEN", "headon"));
    assert!(has(&on["ben"], "COLREGS_AVOID_MODE_ABE", "headon"));
    assert!(first_turn(&on["abe"]) > 0.0 && first_turn(&on["ben"]) > 0.0);
    let on = refined("crossing.fleet", "V19");
    assert!(has(&on["abe"], "COLREGS_AVOID_MODE_BEN", "giveway"));
    assert!(has(&on["ben"], "COLREGS_AVOID_MODE_ABE", "standon"));
    assert!(first_turn(&on["abe"]) > 0.0);
    let on = refined("overtaking.fleet", "V19");
    assert!(has(&on["ben"], "COLREGS_AVOID_MODE_ABE", "overtaking"));
    assert!(has(&on["abe"], "COLREGS_AVOID_MODE_BEN", "standon_ot"));
}

#[test]
fn the_encounter_fleets_check_clean() {
    for fleet in ["headon", "crossing", "overtaking", "three"] {
        let path = project_mission(&format!("encounters_colregs/{fleet}.fleet"));
        let dir = path.parent().unwrap();
        let out = coug(dir, &["check", &format!("{fleet}.fleet")]);
        assert!(
            out.status.success(),
            "{fleet}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert!(Path::new(dir).join("vehicle.bhv").exists());
    }
}

/// A stock two-vehicle berta mission (m2_berta: a loiter each, swapped at 180 s by the
/// shoreside's uTimerScript; berta_cmgr: a transit each; BHV_AvdColregsV22 spawned per
/// contact) as its launch.sh makes it: its `targ_<vname>.bhv` files are its
/// `meta_vehicle.bhv`, which coug preprocesses with each vehicle's macros, as launch.sh's
/// nsplug does. `starts` are abe's and ben's `START_POS`.
fn berta_fleet(mission: &str, dir: &Path, starts: [&str; 2]) -> std::path::PathBuf {
    std::fs::create_dir_all(dir).unwrap();
    let src = test_support::corpus(&format!("moos-ivp-missions/{mission}"));
    for f in std::fs::read_dir(&src).expect("m2_berta").flatten() {
        std::fs::copy(f.path(), dir.join(f.file_name())).unwrap();
    }
    for v in ["abe", "ben"] {
        std::fs::copy(
            dir.join("meta_vehicle.bhv"),
            dir.join(format!("targ_{v}.bhv")),
        )
        .unwrap();
    }
    // The stock `<pShare>` plug, shared by the shoreside and the vehicles, white-lists only
    // DEPLOY, MOOS_MANUAL_OVERRIDE, NODE_BROKER_ACK and APPCAST_REQ on every input: MOOS's
    // pShare (as coug's) would drop the brokers' pings and every bridged NODE_REPORT, so the
    // vehicles would never hear of each other. The fleet runs without that white list.
    let plugs = dir.join("plugs.moos");
    let text = std::fs::read_to_string(&plugs).unwrap();
    let white = ", white_list=DEPLOY & MOOS_MANUAL_OVERRIDE & NODE_BROKER_ACK & APPCAST_REQ";
    assert!(text.contains(white), "the stock plug changed");
    std::fs::write(&plugs, text.replace(white, "")).unwrap();
    // launch.sh's values (init_field.sh's speeds, names and colours; vdestpos.txt's
    // destinations).
    let [abe, ben] = starts;
    let fleet = format!(
        "\
macro    = XMODE=SIM
macro    = SHORE_IP=localhost
macro    = SHORE_PSHARE=9200
macro    = IP_ADDR=localhost
macro    = WARP=1
macro    = MAX_SPD=2
base     = shoreside meta_shoreside.moos MOOS_PORT=9000 PSHARE_PORT=9200 VNAMES=abe:ben
template = meta_vehicle.moos
vehicle  = abe MOOS_PORT=9001 PSHARE_PORT=9201 START_POS={abe} STOCK_SPD=2 COLOR=yellow LOITER_POS=x=0,y=-75   DEST_POS=x=-30,y=-80
vehicle  = ben MOOS_PORT=9002 PSHARE_PORT=9202 START_POS={ben} STOCK_SPD=2 COLOR=red    LOITER_POS=x=125,y=-50 DEST_POS=x=170,y=-80
"
    );
    let path = dir.join("berta.fleet");
    std::fs::write(&path, fleet).unwrap();
    path
}

/// A berta run: each vehicle's parsed alog, and every community's alog bytes.
struct Berta {
    logs: BTreeMap<String, alog::Alog>,
    bytes: BTreeMap<String, Vec<u8>>,
}

/// Checks and runs a berta mission for `secs` seconds in `name`'s folder.
fn berta(mission: &str, name: &str, starts: [&str; 2], secs: f64) -> Berta {
    let dir = fresh_dir(name);
    let path = berta_fleet(mission, &dir.join("mission"), starts);
    // coug check: no error, no MALCONFIG (BHV_AvdColregsV22's parameters are all known).
    let out = coug(path.parent().unwrap(), &["check", "berta.fleet"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let loaded = LoadedFleet::from_file(&path, &[], &[]).expect("berta.fleet loads");
    let checked = session::validate_fleet(&loaded);
    assert!(checked.errors.is_empty(), "{:?}", checked.errors);
    assert!(checked.malconfig.is_empty(), "{:?}", checked.malconfig);
    let opts = FleetOptions {
        mode: Mode::Lockstep,
        deploy: true,
        max_time: secs,
        log_dir: Some(dir.join("logs")),
        ..FleetOptions::default()
    };
    let report = session::run_fleet(&loaded, &opts, &mut session::Quiet)
        .unwrap_or_else(|e| panic!("fleet run failed: {e}"));
    let names: Vec<&str> = report.members.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(names, ["shoreside", "abe", "ben"], "{report}");
    let bytes: BTreeMap<String, Vec<u8>> = names
        .iter()
        .map(|n| {
            let b = std::fs::read(find_alog(&dir.join("logs").join(n))).unwrap();
            (n.to_string(), b)
        })
        .collect();
    let logs = ["abe", "ben"]
        .into_iter()
        .map(|v| {
            let log = parse(&bytes[v]);
            // The helm drives, with no behaviour error, and the vehicle moves off.
            assert!(has(&log, "IVPHELM_STATE", "DRIVE"), "{v}");
            assert!(!log.entries.iter().any(|e| e.var == "BHV_ERROR"), "{v}");
            let moved = track(&log);
            let (_, x0, y0) = moved[0];
            let (_, x1, y1) = moved[moved.len() - 1];
            assert!((x1 - x0).hypot(y1 - y0) > 20.0, "{v} stayed put");
            (v.to_string(), log)
        })
        .collect();
    Berta { logs, bytes }
}

/// The `min_util_cpa_dist` of `mission`'s AvdColregsV22 template.
fn min_util_cpa(mission: &str) -> f64 {
    let bhv = test_support::corpus(&format!("moos-ivp-missions/{mission}/meta_vehicle.bhv"));
    let text = std::fs::read_to_string(bhv).unwrap();
    let line = text
        .lines()
        .map(str::trim)
        .find(|l| l.starts_with("min_util_cpa_dist"))
        .expect("min_util_cpa_dist");
    line.split('=').nth(1).unwrap().trim().parse().unwrap()
}

/// Each vehicle's pContactMgrV20 learns of the other through the shoreside's
/// uFldNodeComms, alerts its helm, the helm spawns `avdcol_<other>` (BHV_AvdColregsV22) and
/// runs it; the two keep above the template's `min_util_cpa_dist`.
fn assert_encounter(mission: &str, run: &Berta) {
    for (me, log) in &run.logs {
        let other = if me == "abe" { "ben" } else { "abe" };
        assert!(has(log, "CONTACTS_LIST", other), "{me}: no contact");
        assert!(
            log.entries
                .iter()
                .any(|e| e.var == "NODE_REPORT" && e.source == "uFldNodeComms"),
            "{me}: no relayed report"
        );
        assert!(
            has(log, "CONTACT_INFO", &format!("name={other}")),
            "{me}: no alert"
        );
        let spawn = format!("bname=avdcol_{other}, btype=BHV_AvdColregsV22, event=spawn");
        assert!(has(log, "IVPHELM_LIFE_EVENT", &spawn), "{me}: {spawn}");
        assert!(
            has(log, "IVPHELM_BHV_ACTIVE", &format!("avdcol_{other}")),
            "{me}: the behaviour never ran"
        );
    }
    let min = min_util_cpa(mission);
    for ((a, b), (r, t)) in closest(&run.logs) {
        eprintln!("{mission}: {a}-{b} closest {r:.2} m at t={t:.2}");
        assert!(
            r > min,
            "{mission}: {a} and {b} came within {r:.2} m at t={t:.2}"
        );
    }
}

#[test]
fn m2_berta_vehicles_meet_and_keep_apart_with_colregs_repeatably() {
    let starts = ["x=0,y=0,heading=180", "x=180,y=0,heading=180"];
    let run = berta("m2_berta", "colregs-m2_berta", starts, 300.0);
    for (v, log) in &run.logs {
        // Loitering: its mode tree from the .bhv.
        assert!(has(log, "MODE", "ACTIVE:LOITERING"), "{v}");
        assert!(has(log, "LOITER_REPORT_A", "capture_hits="), "{v}");
    }
    assert_encounter("m2_berta", &run);
    // Lockstep: a second run writes the same bytes in every community's alog.
    // (The same folder: the logs name their path.)
    let again = berta("m2_berta", "colregs-m2_berta", starts, 300.0);
    for (community, bytes) in &run.bytes {
        assert!(
            *bytes == again.bytes[community],
            "{community}: the two runs differ"
        );
    }
}

#[test]
fn berta_cmgr_crossing_transits_spawn_colregs() {
    // Each transits to its vdestpos.txt point from the other's side, so their paths cross.
    let starts = ["x=170,y=0,heading=180", "x=-30,y=0,heading=180"];
    let run = berta("berta_cmgr", "colregs-berta_cmgr", starts, 200.0);
    for (v, log) in &run.logs {
        assert!(has(log, "MODE", "ACTIVE:TRANSITING"), "{v}");
    }
    assert_encounter("berta_cmgr", &run);
}

/// The platform model these tests give the helm (`pmgen`): Dubins turns of 10 m radius.
const DUBINS: &str = "PMGEN=alg=dubins#radius=10#spoke_degs=10";

/// BHV_AvdColregsV26 on the helm's Dubins platform model (its CPA, passing and crossing along
/// the model's turns): the head-on and crossing encounters keep every closest approach above
/// `min_util_cpa_dist`.
#[test]
fn v26_on_the_dubins_platform_model_keeps_clear() {
    for fleet in ["headon.fleet", "crossing.fleet"] {
        let stem = fleet.trim_end_matches(".fleet");
        let on = run(
            &format!("colregs-{stem}-v26-dubins"),
            fleet,
            &["COLREGS=V26", DUBINS],
        );
        assert!(has(
            &on["abe"],
            "IVPHELM_LIFE_EVENT",
            "btype=BHV_AvdColregsV26, event=spawn"
        ));
        for ((a, b), (r, t)) in closest(&on) {
            eprintln!(
                "{stem} with AvdColregsV26 on Dubins turns: {a}-{b} closest {r:.2} m at t={t:.2}"
            );
            assert!(
                r > MIN_UTIL_CPA,
                "{stem}: {a} and {b} came within {r:.2} m at t={t:.2}"
            );
        }
    }
}

/// Ownship's first turn away from its start heading, degrees (positive: to starboard): the
/// first `NAV_HEADING` more than 10° off the first one, as the signed difference.
fn first_turn(log: &alog::Alog) -> f64 {
    let hdgs: Vec<f64> = log
        .entries
        .iter()
        .filter(|e| e.var == "NAV_HEADING")
        .filter_map(|e| e.value.to_string().parse().ok())
        .collect();
    let h0 = hdgs[0];
    let off = |h: f64| (h - h0 + 540.0).rem_euclid(360.0) - 180.0;
    hdgs.iter()
        .map(|h| off(*h))
        .find(|d| d.abs() > 10.0)
        .expect("the vehicle never turned")
}

/// `fleet` with the AvdColregs `version` (`V22`, `V19`) and `REFINERY=on` (`use_refinery`,
/// `check_plateaus`): every closest approach stays above `min_util_cpa_dist`, and each
/// vehicle's refined CPA functions posted their checks. AOF_CPA does not know its
/// extremes (MOOS `minMaxKnown` is false), so the plateau check fails with 1 whenever the
/// refinery gave a region (`PLATEAU_CHECK_OK = false`, `PLATEAU_WORST_FAIL = 1`), and the
/// basin check always holds (RefineryCPA gives no basin). Returns the logs.
fn refined(fleet: &str, version: &str) -> BTreeMap<String, alog::Alog> {
    let stem = fleet.trim_end_matches(".fleet");
    let colregs = format!("COLREGS={version}");
    let on = run(
        &format!("colregs-{stem}-refinery-{version}"),
        fleet,
        &["REFINERY=on", &colregs],
    );
    for ((a, b), (r, t)) in closest(&on) {
        eprintln!(
            "{stem} with AvdColregs{version} and use_refinery: {a}-{b} closest {r:.2} m at t={t:.2}"
        );
        assert!(
            r > MIN_UTIL_CPA,
            "{stem} {version}: {a} and {b} came within {r:.2} m at t={t:.2}"
        );
    }
    let spawn = format!("btype=BHV_AvdColregs{version}, event=spawn");
    for (name, log) in &on {
        assert!(has(log, "IVPHELM_LIFE_EVENT", &spawn), "{name}: {spawn}");
        let ok = values(log, "PLATEAU_CHECK_OK");
        let basin = values(log, "BASIN_CHECK_OK");
        let cases = values(log, "PLATEAU_LOGIC_CASE");
        let fails = values(log, "PLATEAU_WORST_FAIL");
        eprintln!(
            "{stem} {version} {name}: PLATEAU_CHECK_OK {ok:?}, BASIN_CHECK_OK {basin:?}, {} PLATEAU_LOGIC_CASE, {} PLATEAU_WORST_FAIL",
            cases.len(),
            fails.len()
        );
        assert!(
            !ok.is_empty(),
            "{stem} {version} {name}: no PLATEAU_CHECK_OK"
        );
        assert!(basin.iter().all(|v| v == "true"), "{basin:?}");
        assert!(!cases.is_empty(), "{stem} {version} {name}");
        for c in &cases {
            assert!(
                ["aft", "fore_in_rgam", "fore_out_rgam"].contains(&c.as_str()),
                "{stem} {version} {name}: case {c}"
            );
        }
        // Each refined function here had plateau regions, so each check failed with 1.
        assert!(ok.iter().all(|v| v == "false"), "{ok:?}");
        assert!(fails.iter().all(|v| v == "1"), "{fails:?}");
        assert_eq!(fails.len(), cases.len());
    }
    on
}
