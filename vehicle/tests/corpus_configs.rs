//! Every uSimMarine / pMarinePID / pNodeReporter block of the MOOS-IvP mission corpus is read
//! by the config types: no value is rejected, and the keys reported unknown are exactly the
//! ones the current C++ apps do not know either.

mod common;

use std::collections::BTreeMap;

use vehicle::ConfigError;
use vehicle::node_report::NodeReportConfig;
use vehicle::pid::PidConfig;
use vehicle::sim::SimConfig;

type Blocks = Vec<(String, Vec<(String, String)>)>;

/// All `ProcessConfig = <app>` blocks (by exact app name) of the corpus's `.moos` files.
fn blocks(apps: &[&str]) -> Blocks {
    let root = test_support::mission_file("");
    let files = test_support::files_with_ext(&root, &["moos"]);
    let mut out = Vec::new();
    for f in files {
        let text = std::fs::read_to_string(&f).unwrap();
        for app in apps {
            let count = text
                .lines()
                .filter(|l| {
                    let l = l.split("//").next().unwrap_or("");
                    l.split_once('=').is_some_and(|(k, v)| {
                        k.trim().eq_ignore_ascii_case("processconfig") && v.trim() == *app
                    })
                })
                .count();
            if count > 0 {
                let name = f.strip_prefix(&root).unwrap().display().to_string();
                out.push((name, common::process_config(&text, app)));
            }
        }
    }
    out
}

fn has_macro(v: &str) -> bool {
    v.contains("$(") || v.contains("%(")
}

fn check<T>(
    app_blocks: &Blocks,
    parse: impl Fn(&[(String, String)]) -> Result<(T, Vec<ConfigError>), ConfigError>,
) -> BTreeMap<String, usize> {
    let mut unknown = BTreeMap::new();
    for (file, block) in app_blocks {
        let clean: Vec<_> = block
            .iter()
            .filter(|(_, v)| !has_macro(v))
            .cloned()
            .collect();
        match parse(&clean) {
            Ok((_, unk)) => {
                // Unknown keys by name; bad values and missing keys as `bad:<key>` /
                // `missing:<key>` (none is fatal: the apps run on with the defaults).
                for e in unk {
                    let k = match e {
                        ConfigError::UnknownKey { key, .. } => key.to_ascii_lowercase(),
                        ConfigError::BadValue { key, .. } => {
                            format!("bad:{}", key.to_ascii_lowercase())
                        }
                        ConfigError::Missing { key, .. } => format!("missing:{key}"),
                    };
                    *unknown.entry(k).or_insert(0) += 1;
                }
            }
            Err(e) => panic!("{file}: {e}"),
        }
    }
    unknown
}

#[test]
fn simulator_blocks() {
    let b = blocks(&["uSimMarine", "uSimMarineV22"]);
    assert!(b.len() > 50, "only {} simulator blocks found", b.len());
    let unknown = check(&b, |kv| SimConfig::from_params_lenient(common::pairs(kv)));
    eprintln!("unknown simulator keys: {unknown:?}");
    // Parameters of older simulator versions (FLOAT_RATE, FORCE_X/Y) and a typo of CommsTick
    // in three missions: uSimMarineV22 reports all of them as unhandled too.
    let keys: Vec<&str> = unknown.keys().map(String::as_str).collect();
    assert_eq!(keys, ["commstic", "float_rate", "force_x", "force_y"]);
}

#[test]
fn marine_pid_blocks() {
    let b = blocks(&["pMarinePID", "pMarinePIDV22"]);
    assert!(b.len() > 40, "only {} pid blocks found", b.len());
    let unknown = check(&b, |kv| PidConfig::from_params_lenient(common::pairs(kv)));
    eprintln!("unknown pid keys: {unknown:?}");
    assert!(unknown.is_empty(), "{unknown:?}");
}

#[test]
fn node_reporter_blocks() {
    let b = blocks(&["pNodeReporter"]);
    assert!(b.len() > 50, "only {} reporter blocks found", b.len());
    let unknown = check(&b, |kv| {
        NodeReportConfig::from_params_lenient(common::pairs(kv))
    });
    eprintln!("unknown reporter keys: {unknown:?}");
    // Every pNodeReporter line of the corpus is read (the alternative-nav report included).
    assert!(unknown.is_empty(), "{unknown:?}");
}
