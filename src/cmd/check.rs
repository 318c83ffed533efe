//! `coug check FILE... [NAME=VALUE]...`: preprocess, parse and validate mission files.

use std::path::PathBuf;

use clap::Args;
use mission::check::check_files;
use mission::nsplug::Options;
use mission::source::FsSource;

/// Arguments of `coug check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Mission files (`.moos`, `.bhv`) and nsplug macro definitions (`NAME=VALUE`).
    #[arg(required = true, value_name = "FILE|NAME=VALUE")]
    pub items: Vec<String>,
    /// Extra directory searched for `#include` files (repeatable).
    #[arg(short = 'p', long = "path", value_name = "DIR")]
    pub include_paths: Vec<PathBuf>,
    /// Also print each finding's source line with a caret under the column.
    #[arg(long)]
    pub context: bool,
}

/// Runs the check, prints one line per finding on stdout; returns the exit code:
/// 1 if any finding is an error, 0 otherwise.
pub fn run(args: &CheckArgs) -> i32 {
    let mut opts = Options::new();
    opts.include_paths = args.include_paths.clone();
    let mut files = Vec::new();
    for item in &args.items {
        if item.contains('=') {
            opts.define_arg(item);
        } else {
            files.push(PathBuf::from(item));
        }
    }
    if files.is_empty() {
        errln!("coug check: error: no file given (arguments with `=` are macro definitions)");
        return 2;
    }
    let findings = check_files(&FsSource, &files, &opts);
    for f in &findings {
        if args.context {
            outln!("{}", f.render());
        } else {
            outln!("{f}");
        }
    }
    i32::from(findings.iter().any(|f| f.is_error()))
}
