//! Test helpers: reading the blocks of real mission files (from `test_support`).
#![allow(dead_code)]

/// The `key = value` lines of `ProcessConfig = <app>` in a `.moos` text (a minimal reader
/// for tests: comments `//` stripped, first `=` splits).
pub fn process_config(text: &str, app: &str) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut lines = text
        .lines()
        .map(|l| l.split("//").next().unwrap_or("").trim());
    while let Some(l) = lines.next() {
        let Some((k, v)) = l.split_once('=') else {
            continue;
        };
        if !(k.trim().eq_ignore_ascii_case("processconfig") && v.trim() == app) {
            continue;
        }
        for l in lines.by_ref() {
            if l == "{" || l.is_empty() {
                continue;
            }
            if l == "}" {
                return out;
            }
            if let Some((k, v)) = l.split_once('=') {
                out.push((k.trim().to_string(), v.trim().to_string()));
            }
        }
    }
    panic!("no ProcessConfig = {app} block");
}

/// A global `Key = value` line of a `.moos` text.
pub fn global(text: &str, key: &str) -> Option<String> {
    text.lines().find_map(|l| {
        let (k, v) = l.split("//").next()?.split_once('=')?;
        k.trim()
            .eq_ignore_ascii_case(key)
            .then(|| v.trim().to_string())
    })
}

/// Borrowing view for `from_params`.
pub fn pairs(v: &[(String, String)]) -> impl Iterator<Item = (&str, &str)> {
    v.iter().map(|(k, v)| (k.as_str(), v.as_str()))
}

/// pCougControls as `missions/cougUV` configures it: coug1's gains and kinematics, 50 %
/// thrust per m/s, `pitch_ki = 0.2`, the gain schedule on the measured speed.
pub fn mission_controls() -> vehicle::cougars::ControlsConfig {
    vehicle::cougars::ControlsConfig::from_params([
        ("vehicle", "coug1"),
        ("speed_factor", "50"),
        ("pitch_ki", "0.2"),
        ("fixed_surge", "none"),
    ])
    .unwrap()
}
