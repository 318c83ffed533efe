//! What the tests, benches and examples of every coug crate share: the paths of the shared
//! corpus (`../shared` beside the repository), scratch folders, a recursive file listing, and
//! the stable fuzz runner ([`fuzz`]). A dev-dependency only; never published.
//!
//! The corpus is data nobody on this team wrote (`../shared/README.md`): tests read it in
//! place. When it is missing every helper here panics with a message naming the folder it
//! expected, so a test never passes by skipping its checks.
//!
//! ```
//! let alpha = test_support::mission_file("s1_alpha/alpha.moos");
//! assert!(alpha.ends_with("corpus/moos-ivp-missions/s1_alpha/alpha.moos"));
//! assert!(test_support::mission_text("s1_alpha/alpha.moos").contains("ProcessConfig"));
//! ```

#![warn(missing_docs)]

pub mod fuzz;
pub mod missions;

use std::path::{Path, PathBuf};

/// The workspace root (the folder of the top `Cargo.toml`).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("test-support sits in the workspace root")
        .to_path_buf()
}

/// The shared folder, `../shared` beside the repository; panics when it has no `corpus`.
pub fn shared() -> PathBuf {
    let p = workspace_root().join("../shared");
    assert!(
        p.join("corpus").is_dir(),
        "the shared corpus is missing: expected {}/corpus (../shared must sit beside the \
         repository; see its README.md)",
        p.display()
    );
    p
}

/// A file or folder of `../shared/corpus` (`rel` relative to it, `""` for the folder itself);
/// panics when it is missing.
pub fn corpus(rel: &str) -> PathBuf {
    let mut p = shared().join("corpus");
    if !rel.is_empty() {
        p.push(rel);
    }
    assert!(
        p.exists(),
        "corpus path {} is missing: the tests need ../shared/corpus",
        p.display()
    );
    p
}

/// The text of a corpus file (`rel` relative to `../shared/corpus`); panics when unreadable.
pub fn corpus_text(rel: &str) -> String {
    let p = corpus(rel);
    std::fs::read_to_string(&p)
        .unwrap_or_else(|e| panic!("cannot read corpus file {}: {e}", p.display()))
}

/// The bytes of a corpus file (`rel` relative to `../shared/corpus`); panics when unreadable.
pub fn corpus_bytes(rel: &str) -> Vec<u8> {
    let p = corpus(rel);
    std::fs::read(&p).unwrap_or_else(|e| panic!("cannot read corpus file {}: {e}", p.display()))
}

/// A file or folder of the MOOS-IvP missions, `../shared/corpus/moos-ivp-missions/<rel>`
/// (`""` for the folder itself); panics when it is missing.
pub fn mission_file(rel: &str) -> PathBuf {
    if rel.is_empty() {
        corpus("moos-ivp-missions")
    } else {
        corpus(&format!("moos-ivp-missions/{rel}"))
    }
}

/// The text of a MOOS-IvP mission file (`rel` relative to `moos-ivp-missions`).
pub fn mission_text(rel: &str) -> String {
    corpus_text(&format!("moos-ivp-missions/{rel}"))
}

/// Every file under `dir` (recursively) whose extension is one of `exts`, sorted; each path
/// is `dir` joined with the file's relative path. Panics when a folder cannot be read.
pub fn files_with_ext(dir: &Path, exts: &[&str]) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let entries =
            std::fs::read_dir(&d).unwrap_or_else(|e| panic!("cannot read {}: {e}", d.display()));
        for e in entries {
            let p = e
                .unwrap_or_else(|e| panic!("cannot read {}: {e}", d.display()))
                .path();
            if p.is_dir() {
                stack.push(p);
            } else if p
                .extension()
                .and_then(|x| x.to_str())
                .is_some_and(|x| exts.contains(&x))
            {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// Makes `dir` a fresh, empty folder (removing what was there) and returns it.
pub fn fresh_dir(dir: impl Into<PathBuf>) -> PathBuf {
    let dir = dir.into();
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir)
        .unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
    dir
}

/// A fresh, empty scratch folder `target/tmp/scratch/<name>` in the workspace (emptied by the
/// next run of the same test, removed by `cargo clean`; nothing is left in the system's
/// temporary folder).
pub fn scratch_dir(name: &str) -> PathBuf {
    fresh_dir(workspace_root().join("target/tmp/scratch").join(name))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shared_is_beside_the_workspace_root() {
        let s = shared();
        assert_eq!(s, workspace_root().join("../shared"));
        assert!(corpus("README.md").is_file());
        assert!(mission_file("").is_dir());
        assert!(mission_file("").ends_with("corpus/moos-ivp-missions"));
        assert_eq!(mission_file(""), corpus("moos-ivp-missions"));
    }

    #[test]
    #[should_panic(expected = "corpus path")]
    fn a_missing_corpus_file_panics_with_its_path() {
        corpus("no/such/file.moos");
    }

    #[test]
    fn files_are_listed_recursively_sorted_and_filtered() {
        let d = scratch_dir("test-support-list");
        std::fs::create_dir_all(d.join("b/c")).unwrap();
        for f in ["z.moos", "a.bhv", "b/c/m.moos", "b/skip.txt"] {
            std::fs::write(d.join(f), "").unwrap();
        }
        let got = files_with_ext(&d, &["moos", "bhv"]);
        let rel: Vec<_> = got
            .iter()
            .map(|p| p.strip_prefix(&d).unwrap().to_str().unwrap().to_string())
            .collect();
        assert_eq!(rel, ["a.bhv", "b/c/m.moos", "z.moos"]);
        // A fresh dir is empty again.
        let d2 = fresh_dir(&d);
        assert_eq!(std::fs::read_dir(&d2).unwrap().count(), 0);
        std::fs::remove_dir_all(&d2).unwrap();
    }
}
