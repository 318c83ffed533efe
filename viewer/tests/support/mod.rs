//! What the viewer's browser tests share.

use std::path::PathBuf;
use std::process::Command;

/// Chromium's path, or `None` (a loud note; a failure under CI=true).
pub fn chromium() -> Option<PathBuf> {
    for name in ["chromium", "chromium-browser", "google-chrome"] {
        if let Ok(out) = Command::new("which").arg(name).output()
            && out.status.success()
        {
            let p = String::from_utf8_lossy(&out.stdout).trim().to_string();
            if !p.is_empty() {
                return Some(PathBuf::from(p));
            }
        }
    }
    if std::env::var("CI").is_ok_and(|v| v == "true") {
        panic!(
            "chromium is not on PATH: the viewer's browser tests need it (apt-get install chromium)"
        );
    }
    eprintln!(
        "*** viewer browser test NOT RUN: chromium is not on PATH (CI=true makes this a failure)"
    );
    None
}
