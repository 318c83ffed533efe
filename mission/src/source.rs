//! Where text comes from: the [`FileSource`] trait that the preprocessor reads files through,
//! source locations ([`Span`]) and the [`SourceMap`] that maps every preprocessed line back to
//! the file and line it came from, through `#include`s.

use std::collections::HashMap;
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Why a file could not be read through a [`FileSource`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SourceError {
    /// No file at this path.
    #[error("no such file: {0}")]
    NotFound(PathBuf),
    /// The file exists but reading it failed.
    #[error("cannot read {path}: {reason}")]
    Unreadable {
        /// The path that was read.
        path: PathBuf,
        /// The operating system's explanation.
        reason: String,
    },
}

/// Reads whole files by path. The parsers never touch the file system themselves: they go
/// through this trait, so tests can feed strings with [`MemorySource`].
pub trait FileSource {
    /// The whole text of the file at `path`.
    fn read(&self, path: &Path) -> Result<String, SourceError>;

    /// Whether a file exists at `path` (used by the include-path search).
    fn exists(&self, path: &Path) -> bool {
        self.read(path).is_ok()
    }
}

/// The real file system. Bytes that are not UTF-8 are replaced (lossy), as mission files are
/// plain ASCII in practice and a stray Latin-1 byte in a comment must not stop a parse.
#[derive(Debug, Clone, Copy, Default)]
pub struct FsSource;

impl FileSource for FsSource {
    fn read(&self, path: &Path) -> Result<String, SourceError> {
        match std::fs::read(path) {
            Ok(bytes) => Ok(String::from_utf8_lossy(&bytes).into_owned()),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
                Err(SourceError::NotFound(path.to_path_buf()))
            }
            Err(e) => Err(SourceError::Unreadable {
                path: path.to_path_buf(),
                reason: e.to_string(),
            }),
        }
    }

    fn exists(&self, path: &Path) -> bool {
        path.is_file()
    }
}

/// An in-memory set of files, for tests and fuzzing.
///
/// ```
/// use mission::source::{FileSource, MemorySource};
/// let src = MemorySource::new().with("a.moos", "ServerPort = 9000\n");
/// assert!(src.read("a.moos".as_ref()).is_ok());
/// ```
#[derive(Debug, Clone, Default)]
pub struct MemorySource {
    files: HashMap<PathBuf, String>,
}

impl MemorySource {
    /// An empty set of files.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds (or replaces) a file and returns the set, for chaining.
    pub fn with(mut self, path: impl Into<PathBuf>, text: impl Into<String>) -> Self {
        self.insert(path, text);
        self
    }

    /// Adds (or replaces) a file.
    pub fn insert(&mut self, path: impl Into<PathBuf>, text: impl Into<String>) {
        self.files.insert(normalize(&path.into()), text.into());
    }
}

impl FileSource for MemorySource {
    fn read(&self, path: &Path) -> Result<String, SourceError> {
        self.files
            .get(&normalize(path))
            .cloned()
            .ok_or_else(|| SourceError::NotFound(path.to_path_buf()))
    }
}

/// Removes `.` components and resolves `x/..` pairs lexically, so `./a/../b.moos` and `b.moos`
/// name the same file (used for include-cycle detection and by [`MemorySource`]).
pub fn normalize(path: &Path) -> PathBuf {
    use std::path::Component;
    let mut out: Vec<Component<'_>> = Vec::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => match out.last() {
                Some(Component::Normal(_)) => {
                    out.pop();
                }
                _ => out.push(c),
            },
            other => out.push(other),
        }
    }
    out.iter().collect()
}

/// One file that took part in a preprocessed text, and where it was included from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SourceFile {
    /// The path as it should be shown to the user.
    pub name: String,
    /// The `#include` line that pulled this file in (`None` for the top file).
    pub included_from: Option<Span>,
}

/// A location in a source file: file, 1-based line and 1-based column (in characters).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Span {
    /// The file (shared by every span of that file).
    pub file: Arc<SourceFile>,
    /// 1-based line number in `file`.
    pub line: u32,
    /// 1-based column (character index + 1) in that line; 0 when the whole line is meant.
    pub col: u32,
}

impl Span {
    /// A span in a top-level file with no include parent.
    pub fn new(file: &str, line: u32, col: u32) -> Self {
        Span {
            file: Arc::new(SourceFile {
                name: file.to_string(),
                included_from: None,
            }),
            line,
            col,
        }
    }

    /// The file name as shown to users.
    pub fn file_name(&self) -> &str {
        &self.file.name
    }

    /// The same line, another column.
    pub fn at_col(&self, col: u32) -> Span {
        Span {
            file: self.file.clone(),
            line: self.line,
            col,
        }
    }
}

impl fmt::Display for Span {
    /// `file:line:col`, or `file:line` when the column is 0 (the whole line is meant).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.col == 0 {
            write!(f, "{}:{}", self.file.name, self.line)
        } else {
            write!(f, "{}:{}:{}", self.file.name, self.line, self.col)
        }
    }
}

/// One line of preprocessed text with its origin.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SourceLine {
    /// The text of the line after macro expansion (no trailing newline).
    pub text: String,
    /// The file the line came from.
    pub file: Arc<SourceFile>,
    /// Its 1-based line number there.
    pub line: u32,
}

impl SourceLine {
    /// The span of character column `col` (1-based) of this line.
    pub fn span(&self, col: u32) -> Span {
        Span {
            file: self.file.clone(),
            line: self.line,
            col,
        }
    }
}

/// Preprocessed text, line by line, each line knowing which file and line it came from.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct SourceMap {
    lines: Vec<SourceLine>,
}

impl SourceMap {
    /// Wraps a text that was not preprocessed: line `i` maps to line `i` of `file`.
    ///
    /// ```
    /// let map = mission::source::SourceMap::from_text("x.bhv", "a\nb\n");
    /// assert_eq!(map.lines()[1].line, 2);
    /// ```
    pub fn from_text(file: &str, text: &str) -> Self {
        let file = Arc::new(SourceFile {
            name: file.to_string(),
            included_from: None,
        });
        let lines = split_lines(text)
            .enumerate()
            .map(|(i, l)| SourceLine {
                text: l.to_string(),
                file: file.clone(),
                line: line_number(i),
            })
            .collect();
        SourceMap { lines }
    }

    /// Appends one line.
    pub fn push(&mut self, line: SourceLine) {
        self.lines.push(line);
    }

    /// All lines in order.
    pub fn lines(&self) -> &[SourceLine] {
        &self.lines
    }

    /// The preprocessed text: every line followed by `\n` (what `nsplug` writes).
    pub fn text(&self) -> String {
        let mut out = String::with_capacity(self.lines.iter().map(|l| l.text.len() + 1).sum());
        for l in &self.lines {
            out.push_str(&l.text);
            out.push('\n');
        }
        out
    }
}

/// Splits a text into lines on `\n`, dropping a `\r` before it, without a phantom last line.
pub fn split_lines(text: &str) -> impl Iterator<Item = &str> {
    let body = text.strip_suffix('\n').unwrap_or(text);
    let empty = text.is_empty();
    body.split('\n')
        .filter(move |_| !empty)
        .map(|l| l.strip_suffix('\r').unwrap_or(l))
}

/// 1-based line number of the 0-based index `i`, saturating (files never reach 4 billion lines).
pub fn line_number(i: usize) -> u32 {
    u32::try_from(i + 1).unwrap_or(u32::MAX)
}

/// 1-based character column of byte offset `byte` in `line` (clamped to the line).
pub fn column_of(line: &str, byte: usize) -> u32 {
    let byte = byte.min(line.len());
    let mut b = byte;
    while !line.is_char_boundary(b) {
        b -= 1;
    }
    u32::try_from(line[..b].chars().count() + 1).unwrap_or(u32::MAX)
}
