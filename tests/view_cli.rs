//! `coug view`'s command line: a non-loopback bind without a token is refused before anything
//! is bound or joined; the help names every option.

mod common;

use common::*;

#[test]
fn non_loopback_bind_without_token_is_refused() {
    let dir = fresh_dir("view-cli");
    let out = coug(&dir, &["view", "--bind", "0.0.0.0", "--http-port", "0"]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("coug view: error:") && err.contains("needs a token"),
        "{err}"
    );
}

#[test]
fn help_names_the_options() {
    let dir = fresh_dir("view-help");
    let out = coug(&dir, &["view", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for opt in [
        "MISSION.moos",
        "--host",
        "--port",
        "--http-port",
        "--bind",
        "--token",
    ] {
        assert!(text.contains(opt), "{opt}: {text}");
    }
}
