//! Mission files: the nsplug preprocessor and the `.moos` and `.bhv` parsers.
//!
//! MOOS-IvP missions are `.moos` files (process configuration) and `.bhv` files (helm
//! behaviours), usually nsplug templates. This crate reads them unchanged:
//!
//! - [`nsplug`]: the preprocessor (`#include`, `#define`, `$(X)`, `%(X)`, `#ifdef`...),
//!   producing text with a [`source::SourceMap`] back to every file and line;
//! - [`moos`]: `.moos` files ([`moos::MissionFile`]: globals, `ProcessConfig` blocks, ANTLER);
//! - [`bhv`]: `.bhv` files ([`bhv::BehaviorFile`]: initializes, modes, behaviours);
//! - [`condition`]: the logic-condition AST used by behaviours and modes;
//! - [`catalog`]: the behaviour types and parameters coug knows, for `coug check`;
//! - [`check`]: the validations behind `coug check`;
//! - [`diagnostic`]: errors and warnings with file, line, column and caret;
//! - [`fuzz`]: the bodies of the fuzz targets (cargo-fuzz and the stable bounded runs);
//! - [`load_moos`] / [`load_bhv`]: preprocess and parse in one call.
//!
//! Parsing is pure: files are read through [`source::FileSource`], and no input makes the
//! parsers panic (they report [`diagnostic::Diagnostic`]s instead).
//!
//! ```
//! use mission::source::SourceMap;
//! let src = SourceMap::from_text("a.moos", "LatOrigin = 43.8\nProcessConfig = pHelmIvP\n{\n  AppTick = 4\n}\n");
//! let parsed = mission::moos::parse_moos(&src);
//! assert!(parsed.diagnostics.is_empty());
//! assert_eq!(parsed.value.global("latorigin"), Some("43.8"));
//! assert_eq!(parsed.value.process("PHELMIVP").unwrap().get("apptick"), Some("4"));
//! ```

#![warn(missing_docs)]

pub mod bhv;
pub mod buttons;
pub mod catalog;
pub mod check;
pub mod condition;
pub mod diagnostic;
pub mod fuzz;
pub mod moos;
pub mod nsplug;
pub mod source;
pub mod until;

use diagnostic::Diagnostic;
use source::Span;

/// One `key = value` line: key as written, value trimmed (inner spaces kept), and where.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Param {
    /// The key as written (compare with [`Param::is`], which ignores case).
    pub key: String,
    /// The value after the first `=`, trimmed at both ends.
    pub value: String,
    /// Where the key starts.
    pub span: Span,
}

impl Param {
    /// Whether the key is `name`, ignoring ASCII case.
    pub fn is(&self, name: &str) -> bool {
        self.key.eq_ignore_ascii_case(name)
    }

    /// The line number of the parameter.
    pub fn line(&self) -> u32 {
        self.span.line
    }
}

/// A parse result: the value built from everything that could be read, and the findings.
#[derive(Debug, Clone)]
pub struct Parsed<T> {
    /// The parsed file (lines with errors are left out of it).
    pub value: T,
    /// Errors and warnings, in file order.
    pub diagnostics: Vec<Diagnostic>,
}

impl<T> Parsed<T> {
    /// Whether any diagnostic is an error.
    pub fn has_errors(&self) -> bool {
        self.diagnostics.iter().any(Diagnostic::is_error)
    }

    /// The errors only.
    pub fn errors(&self) -> impl Iterator<Item = &Diagnostic> {
        self.diagnostics.iter().filter(|d| d.is_error())
    }
}

/// Strips a `//` comment that is not inside double quotes, returning the text before it.
///
/// ```
/// assert_eq!(mission::strip_comment("a = b // c"), "a = b ");
/// assert_eq!(mission::strip_comment("a = \"x//y\""), "a = \"x//y\"");
/// ```
pub fn strip_comment(line: &str) -> &str {
    let b = line.as_bytes();
    let mut quoted = false;
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'"' => quoted = !quoted,
            b'/' if !quoted && b.get(i + 1) == Some(&b'/') => return &line[..i],
            _ => {}
        }
        i += 1;
    }
    line
}

/// Preprocesses (nsplug) and parses a `.moos` file: the one call a runtime needs. nsplug's
/// warnings come first in the diagnostics; a fatal preprocessing error is returned as `Err`.
///
/// ```
/// use mission::source::MemorySource;
/// let fs = MemorySource::new().with("m.moos", "Community = $(V)\n");
/// let opts = mission::nsplug::Options::new().define("V", "abe");
/// let m = mission::load_moos(&fs, "m.moos".as_ref(), &opts).unwrap();
/// assert_eq!(m.value.global("community"), Some("abe"));
/// ```
pub fn load_moos(
    fs: &dyn source::FileSource,
    path: &std::path::Path,
    opts: &nsplug::Options,
) -> Result<Parsed<moos::MissionFile>, Diagnostic> {
    let pre = nsplug::preprocess(fs, path, opts)?;
    let mut parsed = moos::parse_moos(&pre.source);
    let mut diagnostics = pre.diagnostics;
    diagnostics.append(&mut parsed.diagnostics);
    Ok(Parsed {
        value: parsed.value,
        diagnostics,
    })
}

/// Preprocesses (nsplug) and parses a `.bhv` file, like [`load_moos`].
///
/// ```
/// use mission::source::MemorySource;
/// let fs = MemorySource::new().with("b.bhv", "initialize DEPLOY = %(D)\n");
/// let opts = mission::nsplug::Options::new().define("D", "false");
/// let b = mission::load_bhv(&fs, "b.bhv".as_ref(), &opts).unwrap();
/// assert_eq!(b.value.initializes[0].value, "FALSE");
/// ```
pub fn load_bhv(
    fs: &dyn source::FileSource,
    path: &std::path::Path,
    opts: &nsplug::Options,
) -> Result<Parsed<bhv::BehaviorFile>, Diagnostic> {
    let pre = nsplug::preprocess(fs, path, opts)?;
    let mut parsed = bhv::parse_bhv(&pre.source);
    let mut diagnostics = pre.diagnostics;
    diagnostics.append(&mut parsed.diagnostics);
    Ok(Parsed {
        value: parsed.value,
        diagnostics,
    })
}

/// Whether a parsed `.moos` file is a MOOS mission at all: it has a `ProcessConfig` block or
/// one of the community settings (`ServerHost`, `ServerPort`, `Community`, `MOOSTimeWarp`,
/// `LatOrigin`, `LongOrigin`). Commands refuse other files as missions (a random text file
/// parses to nothing, with the MOOS reader skipping its lines).
///
/// ```
/// let m = |t: &str| mission::moos::parse_moos(&mission::source::SourceMap::from_text("m", t)).value;
/// assert!(mission::is_mission(&m("ServerPort = 9000\n")));
/// assert!(!mission::is_mission(&m("just some words\n")));
/// ```
pub fn is_mission(m: &moos::MissionFile) -> bool {
    const GLOBALS: &[&str] = &[
        "ServerHost",
        "ServerPort",
        "Community",
        "MOOSTimeWarp",
        "LatOrigin",
        "LongOrigin",
    ];
    !m.processes.is_empty() || GLOBALS.iter().any(|k| m.global(k).is_some())
}
