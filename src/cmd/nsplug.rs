//! `coug nsplug IN OUT [NAME=VALUE]... [--strict] [-p PATH]`: MOOS-IvP's nsplug preprocessor.

use std::path::PathBuf;

use clap::Args;
use mission::nsplug::{Options, preprocess};
use mission::source::FsSource;

/// Arguments of `coug nsplug`.
#[derive(Debug, Args)]
pub struct NsplugArgs {
    /// The template to expand.
    pub input: PathBuf,
    /// The file to write (`-` writes to standard output).
    pub output: PathBuf,
    /// Macro definitions: `NAME=VALUE`, or a bare `NAME` (defined, empty value).
    #[arg(value_name = "NAME=VALUE")]
    pub defines: Vec<String>,
    /// An undefined macro (or an `#ifdef` mixing `||` and `&&`) is an error.
    #[arg(short = 's', long)]
    pub strict: bool,
    /// Keep partially expanded lines (by default a line with an undefined macro is kept as
    /// written, as nsplug does).
    #[arg(short = 'l', long)]
    pub lenient: bool,
    /// Directory searched for `#include` files after the including file's directory
    /// (repeatable; `DIR1:DIR2` also accepted).
    #[arg(short = 'p', long = "path", value_name = "DIR")]
    pub include_paths: Vec<String>,
    /// Accepted for compatibility with nsplug; coug always overwrites OUT.
    #[arg(short = 'f', long)]
    pub force: bool,
}

/// Expands the template; prints warnings (and the error, if any) on stderr. Returns the exit
/// code: 0 on success, 1 if the expansion failed (nothing is written then).
pub fn run(args: &NsplugArgs) -> i32 {
    let mut opts = Options::new();
    opts.strict = args.strict;
    opts.lenient = args.lenient;
    opts.include_paths = args
        .include_paths
        .iter()
        .flat_map(|p| p.split(':'))
        .filter(|p| !p.is_empty())
        .map(PathBuf::from)
        .collect();
    for d in &args.defines {
        opts.define_arg(d);
    }
    let out = match preprocess(&FsSource, &args.input, &opts) {
        Ok(out) => out,
        Err(e) => {
            errln!("{}", e.render());
            errln!(
                "coug nsplug: aborted without writing {}",
                args.output.display()
            );
            return 1;
        }
    };
    for w in &out.diagnostics {
        errln!("{}", w.render());
    }
    let text = out.source.text();
    if args.output.as_os_str() == "-" {
        out!("{text}");
        return 0;
    }
    match std::fs::write(&args.output, text) {
        Ok(()) => 0,
        Err(e) => {
            errln!(
                "coug nsplug: error: cannot write {}: {e}",
                args.output.display()
            );
            1
        }
    }
}
