//! The built-in pLogger: logs mail to an alog file through the [`alog`] crate.
//!
//! File I/O stays with the caller: the logger writes to any [`Write`] it is given (a file
//! the binary opened with [`LoggerConfig::claim_session`], a [`LateSink`] the file is attached
//! to once the mission has started, or a [`SharedBuffer`] in tests).
//! Supported: `Log = VAR @ period`, `WildcardLogging` (in-process: every variable),
//! `WildCardOmitPattern`, `WildcardExclusionLog` (`.xlog`), `AsyncLog`, `File`, `PATH` /
//! global `GlobalLogPath`, `FileTimeStamp`, `DoublePrecision`, `LogAuxSrc`, `MarkDataType`,
//! `MarkExternalCommunityMessages` (the first line of a key counts, as MOOS reads it), the `LOGGER_DIRECTORY` post (at start
//! and every 10 s), the mission copy `<root>._moos` and `PLOGGER_CMD = COPY_FILE_REQUEST=<path>`
//! copies (`<name>._<ext>`). Not written, each named in a config warning when asked for:
//! `.slog` (`SyncLog`), `WildCardPattern`, `UTCLogDirectories`, `LoggingDirectorySummaryFile`,
//! `CompressAlogs`, `DynamicSyncLogColumns`; `.ylog` and the
//! `.blog` bytes (a binary value is logged as its `<MOOS_BINARY>` reference only).

use std::io::{self, Write};
use std::sync::{Arc, Mutex};

use alog::{AlogWriter, Header};
use chrono::NaiveDateTime;
use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::ProcessConfig;
use moosdb::db::wildcard_match;

use crate::antler::BuiltInApp;
use crate::app::{App, Mail, Post, Subscription, Value};
use crate::appcasting::AppcastLayer;
use crate::session::tally::{LogTally, Name, Tally};

/// Seconds between `LOGGER_DIRECTORY` posts.
pub const DIRECTORY_PERIOD: f64 = 10.0;

/// A log writer handed to the apps before its file exists: the file is attached with
/// [`LateSink::attach`] once the mission has been read and checked, so a mission that fails
/// to start creates nothing on disk. Writing before a file is attached is an error.
#[derive(Clone, Default)]
pub struct LateSink(Arc<Mutex<Option<Attached>>>, LogTally);

/// What a [`LateSink`] writes to once attached.
struct Attached {
    alog: Box<dyn Write + Send>,
    folder: std::path::PathBuf,
    /// The first write error (the run has failed: see [`LateSink::close`]).
    failed: Option<io::Error>,
    /// Further files written record by record (pLogger's `.xlog`).
    streams: Vec<io::BufWriter<std::fs::File>>,
}

impl Attached {
    /// Remembers the first error of the session.
    fn keep_first_error<T>(&mut self, r: &io::Result<T>) {
        if let Err(e) = r
            && self.failed.is_none()
        {
            self.failed = Some(io::Error::new(e.kind(), e.to_string()));
        }
    }
}

/// A further log file of a [`LateSink`]'s session (see [`LateSink::open_stream`]); its write
/// errors fail the session like the alog's.
pub struct SideStream {
    sink: LateSink,
    index: usize,
}

impl Write for SideStream {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.sink.with_stream(self.index, |w| w.write(buf))
    }

    fn flush(&mut self) -> io::Result<()> {
        self.sink.with_stream(self.index, |w| w.flush())
    }
}

impl LateSink {
    /// A sink with no file yet.
    pub fn new() -> Self {
        LateSink::default()
    }

    /// The tally of the records written to the alog (the run report's totals): pLogger counts
    /// each line it writes into it (see [`Logger::with_side_files`]).
    pub(crate) fn tally(&self) -> LogTally {
        self.1.clone()
    }

    /// Attaches the alog writer every later write goes to, and the session folder side files
    /// ([`LateSink::side_file`]) are written in.
    pub fn attach(&self, alog: Box<dyn Write + Send>, folder: std::path::PathBuf) {
        *self.lock() = Some(Attached {
            alog,
            folder,
            failed: None,
            streams: Vec::new(),
        });
    }

    /// Writes `bytes` as a new file `name` in the session folder (never over an existing
    /// file), as pLogger writes `<root>._moos` and the copies apps request.
    pub fn side_file(&self, name: &str, bytes: &[u8]) -> io::Result<()> {
        let mut g = self.lock();
        let Some(a) = g.as_mut() else {
            return Err(io::Error::other("the log folder is not open yet"));
        };
        let r = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(a.folder.join(name))
            .and_then(|mut f| {
                f.write_all(bytes)?;
                f.flush()
            });
        // A name already there is not a disk failure: the caller decides.
        if !matches!(&r, Err(e) if e.kind() == io::ErrorKind::AlreadyExists) {
            a.keep_first_error(&r);
        }
        r
    }

    /// Opens a new file `name` in the session folder (never over an existing one) to be
    /// written through the returned stream; it is flushed by [`LateSink::close`].
    pub fn open_stream(&self, name: &str) -> io::Result<SideStream> {
        let mut g = self.lock();
        let Some(a) = g.as_mut() else {
            return Err(io::Error::other("the log folder is not open yet"));
        };
        let f = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(a.folder.join(name));
        a.keep_first_error(&f);
        a.streams.push(io::BufWriter::with_capacity(1 << 14, f?));
        Ok(SideStream {
            sink: self.clone(),
            index: a.streams.len() - 1,
        })
    }

    /// The session folder's name (the root of the files on disk), once attached.
    pub fn root(&self) -> Option<String> {
        let g = self.lock();
        let folder = &g.as_ref()?.folder;
        Some(folder.file_name()?.to_string_lossy().into_owned())
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Option<Attached>> {
        self.0.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Flushes the alog and reports the first write error of the whole session, if any: a
    /// log that could not be written is a failed run. Later writes fail.
    pub fn close(&self) -> io::Result<()> {
        let Some(mut a) = self.lock().take() else {
            return Ok(());
        };
        let mut flushed = a.alog.flush();
        for st in &mut a.streams {
            flushed = flushed.and(st.flush());
        }
        match a.failed.take() {
            Some(e) => Err(e),
            None => flushed,
        }
    }

    fn with<R>(&self, f: impl FnOnce(&mut (dyn Write + Send)) -> io::Result<R>) -> io::Result<R> {
        self.with_target(None, f)
    }

    fn with_stream<R>(
        &self,
        index: usize,
        f: impl FnOnce(&mut (dyn Write + Send)) -> io::Result<R>,
    ) -> io::Result<R> {
        self.with_target(Some(index), f)
    }

    /// Runs `f` on the alog (`None`) or a side stream, keeping the first error.
    fn with_target<R>(
        &self,
        stream: Option<usize>,
        f: impl FnOnce(&mut (dyn Write + Send)) -> io::Result<R>,
    ) -> io::Result<R> {
        let mut g = self.lock();
        let Some(a) = g.as_mut() else {
            return Err(io::Error::other("the log file is not open"));
        };
        let r = match stream {
            None => f(a.alog.as_mut()),
            Some(i) => f(&mut a.streams[i]),
        };
        a.keep_first_error(&r);
        r
    }
}

impl Write for LateSink {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        self.with(|w| w.write(buf))
    }

    fn flush(&mut self) -> io::Result<()> {
        self.with(|w| w.flush())
    }
}

/// Why a log session could not be claimed.
#[derive(Debug, thiserror::Error)]
pub enum ClaimError {
    /// A log already exists under the name; coug never writes over a log.
    #[error(
        "{0} exists already; coug never writes over a log (remove it, or keep FileTimeStamp = true)"
    )]
    Exists(String),
    /// The disk refused.
    #[error("cannot create {0}: {1}")]
    Io(String, #[source] io::Error),
}

/// pLogger's settings, read from its `ProcessConfig` block.
#[derive(Debug, Clone, PartialEq)]
pub struct LoggerConfig {
    /// `File`: the log name stem (default `MOOSLog`).
    pub file: String,
    /// `GlobalLogPath` (global) or `PATH` (default `./`), without a trailing `/`.
    pub path: String,
    /// `FileTimeStamp` (default true): add `_D_M_YYYY_____HH_MM_SS` to the stem.
    pub file_time_stamp: bool,
    /// `AsyncLog` (default true): write the alog at all.
    pub async_log: bool,
    /// `WildcardLogging`: log every variable (default true without a block, else false).
    pub wildcard: bool,
    /// `WildCardOmitPattern`: variables not logged (MISSION_FILE is always omitted).
    pub omit: Vec<String>,
    /// `Log = VAR @ period` lines, in file order.
    pub logs: Vec<(String, f64)>,
    /// `DoublePrecision` (default 5).
    pub double_precision: usize,
    /// `LogAuxSrc` (default false): source written as `src:aux` when aux is set.
    pub log_aux_src: bool,
    /// `MarkDataType` (default false).
    pub mark_data_type: bool,
    /// `MarkExternalCommunityMessages` (default false): the source of a message from another
    /// community (bridged by pShare) is written `src@community`.
    pub mark_external_community: bool,
    /// `WildcardExclusionLog` (default false): variables the omit patterns keep out of the
    /// alog go to `<root>.xlog` (same line format, no banner) instead of nowhere.
    pub exclusion_log: bool,
}

impl Default for LoggerConfig {
    fn default() -> Self {
        LoggerConfig {
            file: "MOOSLog".into(),
            path: ".".into(),
            file_time_stamp: true,
            async_log: true,
            wildcard: true,
            omit: Vec::new(),
            logs: Vec::new(),
            double_precision: 5,
            log_aux_src: false,
            mark_data_type: false,
            mark_external_community: false,
            exclusion_log: false,
        }
    }
}

/// C `atof` on a prefix: the longest leading number, 0 if none (`0NOSYNC` gives 0).
fn atof(s: &str) -> f64 {
    let s = s.trim_start();
    let n = s
        .find(|c: char| !matches!(c, '0'..='9' | '.' | '+' | '-' | 'e' | 'E'))
        .unwrap_or(s.len());
    (1..=n)
        .rev()
        .find_map(|k| s[..k].parse::<f64>().ok())
        .unwrap_or(0.0)
}

impl LoggerConfig {
    /// Reads a pLogger block (`None`: no block, so wildcard logging) and the mission's
    /// `GlobalLogPath`.
    ///
    /// ```
    /// let c = runtime::logger::LoggerConfig::from_config(None, Some("/tmp/logs/"));
    /// assert_eq!((c.path.as_str(), c.wildcard), ("/tmp/logs", true));
    /// ```
    pub fn from_config(block: Option<&ProcessConfig>, global_log_path: Option<&str>) -> Self {
        let mut c = LoggerConfig::default();
        if let Some(b) = block {
            c.wildcard = false;
            // As MOOS's GetConfigurationParam: the first line of a key counts (`Log` and
            // `WildCardOmitPattern` lines all do).
            let mut seen = std::collections::HashSet::new();
            for p in &b.entries {
                let v: String = p.value.chars().filter(|ch| !ch.is_whitespace()).collect();
                let key = p.key.to_ascii_lowercase();
                let multi = matches!(key.as_str(), "log" | "wildcardomitpattern");
                if !multi && (v.is_empty() || !seen.insert(key.clone())) {
                    continue;
                }
                match key.as_str() {
                    "file" => c.file = v,
                    "path" => c.path = v,
                    "filetimestamp" => c.file_time_stamp = moos_types::text::config_bool(&v),
                    "asynclog" => c.async_log = moos_types::text::config_bool(&v),
                    "wildcardlogging" => c.wildcard = moos_types::text::config_bool(&v),
                    "wildcardomitpattern" => c
                        .omit
                        .extend(v.split(',').filter(|s| !s.is_empty()).map(String::from)),
                    "doubleprecision" => {
                        if let Ok(n) = v.parse::<usize>() {
                            c.double_precision = n.min(17);
                        }
                    }
                    "logauxsrc" => c.log_aux_src = moos_types::text::config_bool(&v),
                    "markdatatype" => c.mark_data_type = moos_types::text::config_bool(&v),
                    "markexternalcommunitymessages" => {
                        c.mark_external_community = moos_types::text::config_bool(&v)
                    }
                    "wildcardexclusionlog" => c.exclusion_log = moos_types::text::config_bool(&v),
                    "log" => {
                        let (var, period) = match v.split_once('@') {
                            Some((var, rest)) => (var, atof(rest.split(',').next().unwrap_or(""))),
                            None => (v.as_str(), 2.0),
                        };
                        if !var.is_empty() {
                            c.logs.push((var.to_string(), period));
                        }
                    }
                    _ => {}
                }
            }
        }
        // pLogger turns the asynchronous log on whenever it logs by wildcard, whatever
        // `AsyncLog` says (so `AsyncLog = true @ 0`, which MOOS reads as false, still logs).
        if c.wildcard {
            c.async_log = true;
        }
        if let Some(g) = global_log_path.filter(|g| !g.trim().is_empty()) {
            c.path = g.trim().to_string();
        }
        while c.path.len() > 1 && c.path.ends_with('/') {
            c.path.pop();
        }
        c
    }

    /// Config warnings for a pLogger block: each key coug's pLogger does not support (named,
    /// with file:line) and each key pLogger does not know (pLogger ignores those silently).
    /// The generic MOOS app keys (AppTick, CommsTick, ...) pass.
    pub fn warnings(block: &ProcessConfig) -> Vec<Diagnostic> {
        const SUPPORTED: &[&str] = &[
            "file",
            "path",
            "filetimestamp",
            "asynclog",
            "wildcardlogging",
            "wildcardomitpattern",
            "doubleprecision",
            "logauxsrc",
            "markdatatype",
            "markexternalcommunitymessages",
            "wildcardexclusionlog",
            "log",
        ];
        const UNSUPPORTED: &[&str] = &[
            "synclog",
            "wildcardpattern",
            "utclogdirectories",
            "loggingdirectorysummaryfile",
            "compressalogs",
            "dynamicsynclogcolumns",
        ];
        const GENERIC: &[&str] = &["apptick", "commstick", "maxapptick", "iteratemode"];
        let mut out = Vec::new();
        for p in &block.entries {
            let k = p.key.to_ascii_lowercase();
            // A switch set off asks for nothing: no warning (`SyncLog = false`).
            let switch = matches!(
                k.as_str(),
                "synclog" | "utclogdirectories" | "compressalogs"
            );
            let on = moos_types::text::config_bool(p.value.split('@').next().unwrap_or("").trim());
            let why = if UNSUPPORTED.contains(&k.as_str()) && switch && !on {
                continue;
            } else if UNSUPPORTED.contains(&k.as_str()) {
                "not supported by coug's pLogger; ignored"
            } else if SUPPORTED.contains(&k.as_str()) || GENERIC.contains(&k.as_str()) {
                continue;
            } else {
                "not a pLogger parameter; ignored (as pLogger does)"
            };
            out.push(Diagnostic::line_warning(
                DiagnosticKind::AppSetting,
                &p.span,
                format!("{}: {} = {}: {why}", block.name, p.key, p.value),
            ));
        }
        out
    }

    /// The session's root name (`<File>_D_M_YYYY_____HH_MM_SS`, or `<File>`).
    pub fn root_name(&self, opened: &NaiveDateTime) -> String {
        alog::log_root(&self.file, opened, self.file_time_stamp)
    }

    /// The session directory: `<path>/<root>`.
    pub fn directory(&self, opened: &NaiveDateTime) -> String {
        format!("{}/{}", self.path, self.root_name(opened))
    }

    /// The alog file's path: `<path>/<root>/<root>.alog`.
    pub fn alog_path(&self, opened: &NaiveDateTime) -> String {
        let root = self.root_name(opened);
        format!("{}/{root}/{root}.alog", self.path)
    }

    /// Claims a new session for a log opened at `opened`: creates `<path>/` if needed, then the
    /// session directory `<path>/<root>/` (which must not exist yet) and the alog file in it,
    /// created new. When the name is taken (another run in the same second), the next
    /// second's name is tried, up to 60 times: an existing log is never opened for writing.
    /// Returns the time whose name was claimed and the open file.
    ///
    /// Everything else in this module is free of I/O; this is the one place that touches the
    /// disk, for the binary to call once the mission has been read and checked.
    pub fn claim_session(
        &self,
        opened: &NaiveDateTime,
    ) -> Result<(NaiveDateTime, std::fs::File), ClaimError> {
        std::fs::create_dir_all(&self.path).map_err(|e| ClaimError::Io(self.path.clone(), e))?;
        let mut at = *opened;
        for _ in 0..60 {
            let dir = self.directory(&at);
            match std::fs::create_dir(&dir) {
                Ok(()) => {
                    let path = self.alog_path(&at);
                    let file = std::fs::OpenOptions::new()
                        .write(true)
                        .create_new(true)
                        .open(&path)
                        .map_err(|e| ClaimError::Io(path, e))?;
                    return Ok((at, file));
                }
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
                    if !self.file_time_stamp {
                        return Err(ClaimError::Exists(dir));
                    }
                    at += chrono::Duration::seconds(1);
                }
                Err(e) => return Err(ClaimError::Io(dir, e)),
            }
        }
        Err(ClaimError::Exists(self.directory(&at)))
    }

    /// True when a variable is not logged: MISSION_FILE always; a `WildCardOmitPattern`
    /// match unless the variable has its own `Log =` line.
    fn omitted(&self, key: &str) -> bool {
        key == "MISSION_FILE"
            || (self
                .omit
                .iter()
                .any(|p| wildcard_match(p.as_bytes(), key.as_bytes()))
                && !self.logs.iter().any(|(v, _)| v == key))
    }
}

/// A cloneable in-memory [`Write`] target (for tests and for callers that keep the bytes).
#[derive(Debug, Clone, Default)]
pub struct SharedBuffer(Arc<Mutex<Vec<u8>>>);

impl SharedBuffer {
    /// A copy of everything written so far.
    pub fn contents(&self) -> Vec<u8> {
        self.0.lock().map(|b| b.clone()).unwrap_or_default()
    }
}

impl Write for SharedBuffer {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        let mut b = self
            .0
            .lock()
            .map_err(|_| io::Error::other("log buffer poisoned"))?;
        b.extend_from_slice(buf);
        Ok(buf.len())
    }

    fn flush(&mut self) -> io::Result<()> {
        Ok(())
    }
}

/// The pLogger app.
pub struct Logger<W: Write> {
    name: String,
    block: Option<ProcessConfig>,
    config: LoggerConfig,
    sink: Option<W>,
    writer: Option<AlogWriter<W>>,
    file_path: String,
    directory: String,
    opened_on: String,
    last_dir_post: f64,
    blog_offset: u64,
    /// Reused to assemble `src:aux` sources.
    scratch: String,
    /// The community this logger's DB serves (for `MarkExternalCommunityMessages`).
    community: String,
    blog_name: String,
    root: String,
    side: Option<SideFiles>,
    xlog: Option<AlogWriter<SideStream>>,
    error: Option<io::Error>,
    /// The write error was reported as the app's failure (later ones are not).
    failed: bool,
    /// Appcasting (not in C++ pLogger, a plain CMOOSApp; issue #17 asks every coug app to
    /// appcast): its files and counts.
    appcast: AppcastLayer,
    /// Records written to the alog and to the exclusion log.
    logged: u64,
    excluded: u64,
    /// What the logger knows of each variable, found once per name.
    fates: rustc_hash::FxHashMap<moos_types::ByteString, Known>,
    /// Distinct variables logged.
    variables: usize,
    copies: u32,
    /// Counts every line written to the alog (the session's run report).
    tally: Option<LogTally>,
}

/// What [`Logger`] knows of a variable (see [`Logger::log`]).
struct Known {
    /// What becomes of its mail (the omit patterns and `Log =` lines are fixed at start-up),
    /// and whether it was logged yet.
    fate: Fate,
    /// What the tally needs to know of the name.
    name: Name,
    /// The columns of its last record in the alog.
    cache: alog::RecordCache,
}

/// What [`Logger`] does with a variable's mail (memoised per variable name).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Fate {
    /// Omitted (`WildCardOmitPattern`, MISSION_FILE): to the exclusion log if any.
    Omitted,
    /// pLogger's command and the appcast variables, without wildcard logging or a `Log =`
    /// line: dropped.
    Dropped,
    /// Logged; not written yet.
    Log,
    /// Logged, and written at least once.
    Logged,
}

/// How a record's source column is written.
#[derive(Debug, Clone, Copy)]
struct SourceStyle<'a> {
    /// `LogAuxSrc`: `src:aux` when the aux is set.
    aux: bool,
    /// `MarkExternalCommunityMessages`: this community's name; a message from any other is
    /// written `src@community` (after the aux), as pLogger does.
    own_community: Option<&'a str>,
}

/// Writes one mail as a log record: the source as [`SourceStyle`] says (assembled in
/// `scratch`, reused), binary data as its reference into the `.blog` at `blog_offset` (which
/// advances); with the variable's `cache` if any (the alog's), counting the line into
/// `tally` if any.
fn record<W: Write>(
    w: &mut AlogWriter<W>,
    m: &Mail,
    style: SourceStyle<'_>,
    blog: (&str, &mut u64),
    scratch: &mut String,
    cache: Option<&mut alog::RecordCache>,
    tally: Option<(&mut Tally, Name)>,
) -> io::Result<()> {
    let (blog_name, blog_offset) = blog;
    let with_aux = style.aux && !m.source_aux.is_empty();
    let external = style
        .own_community
        .is_some_and(|own| !m.community.is_empty() && *m.community != *own);
    let source = if with_aux || external {
        scratch.clear();
        scratch.push_str(&m.source);
        if with_aux {
            scratch.push(':');
            scratch.push_str(&m.source_aux);
        }
        if external {
            scratch.push('@');
            scratch.push_str(&m.community);
        }
        scratch.as_str()
    } else {
        &m.source
    };
    let value = match &m.value {
        Value::Double(x) => alog::LogValue::Double(*x),
        Value::String(s) => alog::LogValue::String(s),
        Value::Binary(b) => {
            let offset = *blog_offset;
            *blog_offset += b.len() as u64;
            alog::LogValue::Binary {
                file: blog_name,
                offset,
                bytes: b.len() as u64,
            }
        }
    };
    let seen = |line: alog::Line<'_>| {
        if let Some((t, name)) = tally {
            t.record(&m.key, name, source, line);
        }
    };
    match cache {
        Some(c) => w.record_cached(m.time, c, source, value, seen),
        None => w.record_seen(m.time, &m.key, source, value, seen),
    }
}

/// pLogger's files beside the alog: the mission copy `<root>._moos` written at start-up, and
/// the copies apps request with `PLOGGER_CMD = COPY_FILE_REQUEST=<path>` (the helm asks for
/// each behaviour file): `<name>._<ext>` (`<name>._bak` without an extension).
#[derive(Clone)]
pub struct SideFiles {
    /// The mission text as run (after nsplug), copied under the banner into `<root>._moos`.
    pub mission_text: String,
    /// Where the files go (the session folder, once claimed).
    pub folder: LateSink,
    /// The folder relative request paths are read from (the mission file's folder, where
    /// pAntler starts the apps).
    pub base_dir: std::path::PathBuf,
}

impl<W: Write + Send + 'static> BuiltInApp for Logger<W> {
    /// None: pLogger's block is judged before the log target is known
    /// ([`LoggerConfig::warnings`]), so its findings are reported even when it does not run.
    fn warnings(&self) -> &[Diagnostic] {
        &[]
    }

    /// Sets the mission's `Community` and `MOOSTimeWarp` for the logger's appcasts; the
    /// block's appcasting keys are read with them.
    fn with_appcast_globals(mut self, community: Option<&str>, warp: f64) -> Self {
        self.appcast = AppcastLayer::with_globals(&self.name, self.block.as_ref(), community, warp);
        self
    }
}

impl<W: Write> Logger<W> {
    /// A logger called `name` (usually `pLogger`) writing to `sink`. `opened` is the
    /// session's date-time (names the files; with `opened_on`, the banner's `FILE OPENED
    /// ON` text, which pLogger 2024 prints as the Unix epoch). LOGSTART is the time of
    /// [`App::on_startup`].
    pub fn new(
        name: &str,
        block: Option<ProcessConfig>,
        config: LoggerConfig,
        sink: W,
        opened: &NaiveDateTime,
        opened_on: &str,
    ) -> Self {
        let root = config.root_name(opened);
        Logger {
            name: name.to_string(),
            file_path: config.alog_path(opened),
            directory: config.directory(opened),
            blog_name: format!("{root}.blog"),
            root,
            side: None,
            xlog: None,
            block,
            config,
            sink: Some(sink),
            writer: None,
            opened_on: opened_on.to_string(),
            last_dir_post: f64::NEG_INFINITY,
            blog_offset: 0,
            scratch: String::new(),
            error: None,
            failed: false,
            appcast: AppcastLayer::with_globals(name, None, None, 1.0),
            logged: 0,
            excluded: 0,
            fates: rustc_hash::FxHashMap::default(),
            variables: 0,
            copies: 0,
            community: String::new(),
            tally: None,
        }
    }

    /// Sets the community this logger's DB serves: with `MarkExternalCommunityMessages`,
    /// messages from any other are marked `src@community`.
    pub fn with_community(mut self, community: &str) -> Self {
        self.community = community.to_string();
        self
    }

    /// The appcast report: the files, the counts, the first write error.
    fn appcast_body(&self, out: &mut String) {
        use std::fmt::Write as _;
        let _ = writeln!(out, "        Log File: {}", self.file_path);
        let _ = writeln!(out, "       Directory: {}", self.directory);
        let _ = writeln!(
            out,
            "   Wildcard Logs: {}",
            if self.config.wildcard {
                "true"
            } else {
                "false"
            }
        );
        let _ = writeln!(out, "  Logged Records: {}", self.logged);
        let _ = writeln!(out, "Excluded Records: {}", self.excluded);
        let _ = writeln!(out, "Variables Logged: {}", self.variables);
        let _ = writeln!(out, "    Binary Bytes: {}", self.blog_offset);
        let _ = writeln!(out, "    Files Copied: {}", self.copies);
        let state = if self.failed || self.error.is_some() {
            "write failed"
        } else if self.writer.is_some() {
            "writing"
        } else {
            "not open"
        };
        let _ = writeln!(out, "           State: {state}");
    }

    /// Also writes the mission copy and requested copies beside the alog, and counts the
    /// alog's lines into the folder's tally ([`LateSink::tally`]: the folder's sink is the
    /// alog's writer in a session).
    pub fn with_side_files(mut self, side: Option<SideFiles>) -> Self {
        if let Some(s) = &side {
            self = self.with_tally(s.folder.tally());
        }
        self.side = side;
        self
    }

    /// Counts every line written to the alog into `tally` (the banner, then each record as
    /// the writer shows it: see [`Tally::record`]).
    pub(crate) fn with_tally(mut self, tally: LogTally) -> Self {
        self.tally = Some(tally);
        self
    }

    /// Copies a file an app asked for (`COPY_FILE_REQUEST=<path>`) into the session folder.
    /// A file that cannot be read is skipped with a warning (pLogger skips it too); a failed
    /// write is a failed log.
    fn copy_requested(&mut self, path: &str) {
        let Some(side) = &self.side else {
            return;
        };
        let p = side.base_dir.join(path);
        let stem = p
            .file_stem()
            .map_or_else(String::new, |s| s.to_string_lossy().into_owned());
        let ext = p
            .extension()
            .map_or_else(|| "bak".to_string(), |e| e.to_string_lossy().into_owned());
        match std::fs::read(&p) {
            Ok(bytes) => match side.folder.side_file(&format!("{stem}._{ext}"), &bytes) {
                // Asked again (a restarted helm): the copy is there already.
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {}
                r => {
                    if r.is_ok() {
                        self.copies += 1;
                    }
                    self.note(r)
                }
            },
            Err(e) => tracing::warn!("{}: cannot copy {path}: {e}", self.name),
        }
    }

    /// Writes `<root>._moos`: the banner naming the copy, then the mission text.
    fn copy_mission(&mut self, log_start: f64) {
        let Some(side) = &self.side else {
            return;
        };
        let dir = self.file_path.rsplit_once('/').map_or(".", |(d, _)| d);
        let path = format!("{dir}/{}._moos", self.root);
        let header = Header {
            path: &path,
            opened_on: &self.opened_on,
            log_start,
            mark_data_type: false,
        };
        let r = AlogWriter::new(Vec::new(), &header).and_then(|w| {
            let mut bytes = w.into_inner();
            for line in side.mission_text.lines() {
                bytes.extend_from_slice(line.as_bytes());
                bytes.push(b'\n');
            }
            let root = side.folder.root().unwrap_or_else(|| self.root.clone());
            side.folder.side_file(&format!("{root}._moos"), &bytes)
        });
        self.note(r);
    }

    /// The first write error as the app's failure (once: the run ends with it).
    fn failure(&mut self) -> crate::app::AppResult {
        match self.error.take() {
            None => Ok(()),
            Some(source) => {
                self.failed = true;
                Err(crate::app::AppError::Io {
                    app: self.name.clone(),
                    what: format!("the log {}", self.file_path),
                    source,
                })
            }
        }
    }

    /// The alog path written in the banner.
    pub fn file_path(&self) -> &str {
        &self.file_path
    }

    fn note(&mut self, r: io::Result<()>) {
        if let Err(e) = r
            && self.error.is_none()
            && !self.failed
        {
            self.error = Some(e);
            self.writer = None;
        }
    }

    /// What becomes of mail of `key` (the patterns matched once per variable name).
    fn fate(&self, key: &str) -> Fate {
        if self.config.omitted(key) {
            Fate::Omitted
        } else if (key == "PLOGGER_CMD" || appcast::casting::REGISTERED_VARIABLES.contains(&key))
            && !self.config.wildcard
            && !self.config.logs.iter().any(|(v, _)| v == key)
        {
            // Subscribed as pLogger's command variable only: logged like any other variable
            // only when wildcard logging or a `Log =` line asks for it. So are the
            // appcasting layer's variables.
            Fate::Dropped
        } else {
            Fate::Log
        }
    }

    /// Hands the alog's and the exclusion log's buffered lines to their writers (`flush`:
    /// and flushes those), noting the first error.
    fn hand_on(&mut self, flush: bool) {
        fn hand<W: Write>(w: &mut AlogWriter<W>, flush: bool) -> io::Result<()> {
            if flush { w.flush() } else { w.pass_on() }
        }
        let alog = self.writer.as_mut().map(|w| hand(w, flush));
        let xlog = self.xlog.as_mut().map(|x| hand(x, flush));
        for r in [alog, xlog].into_iter().flatten() {
            self.note(r);
        }
    }

    /// Logs one mail (counting the alog's line into `tally`).
    fn log(&mut self, m: &Mail, tally: Option<&mut Tally>) {
        let Some(known) = self.fates.get_mut(&m.key) else {
            let known = Known {
                fate: self.fate(&m.key),
                name: Name::of(&m.key),
                cache: alog::RecordCache::new(&m.key),
            };
            self.fates.insert(m.key.clone(), known);
            return self.log(m, tally);
        };
        let style = SourceStyle {
            aux: self.config.log_aux_src,
            own_community: self
                .config
                .mark_external_community
                .then_some(self.community.as_str()),
        };
        match known.fate {
            Fate::Dropped => return,
            Fate::Omitted => {
                if self.config.wildcard
                    && let Some(x) = self.xlog.as_mut()
                {
                    let r = record(
                        x,
                        m,
                        style,
                        (&self.blog_name, &mut self.blog_offset),
                        &mut self.scratch,
                        None,
                        None,
                    );
                    self.excluded += 1;
                    self.note(r);
                }
                return;
            }
            Fate::Log | Fate::Logged => {}
        }
        let Some(w) = self.writer.as_mut() else {
            return;
        };
        let r = record(
            w,
            m,
            style,
            (&self.blog_name, &mut self.blog_offset),
            &mut self.scratch,
            Some(&mut known.cache),
            tally.map(|t| (t, known.name)),
        );
        if known.fate == Fate::Log {
            known.fate = Fate::Logged;
            self.variables += 1;
        }
        self.logged += 1;
        self.note(r);
    }
}

impl<W: Write + Send + 'static> App for Logger<W> {
    fn name(&self) -> &str {
        &self.name
    }

    fn process_config(&self) -> Option<&ProcessConfig> {
        self.block.as_ref()
    }

    /// Under wildcard logging without an exclusion log, the omitted variables are dropped
    /// unread (but those with their own `Log =` line, the appcasting layer's and
    /// `PLOGGER_CMD`, which [`Logger::on_mail`] reads).
    fn unread(&self) -> moosdb::db::Unread {
        if !self.config.wildcard || (self.config.exclusion_log && self.side.is_some()) {
            return moosdb::db::Unread::default();
        }
        let bytes = |s: &str| bytes::Bytes::copy_from_slice(s.as_bytes());
        moosdb::db::Unread {
            patterns: self.config.omit.iter().map(|p| bytes(p)).collect(),
            except: self
                .config
                .logs
                .iter()
                .map(|(v, _)| v.as_str())
                .chain(appcast::casting::REGISTERED_VARIABLES)
                .chain(["PLOGGER_CMD"])
                .map(bytes)
                .collect(),
        }
    }

    fn subscriptions(&self) -> Vec<Subscription> {
        let mut subs: Vec<Subscription> = AppcastLayer::subscriptions()
            .chain(
                self.config
                    .logs
                    .iter()
                    .map(|(v, p)| Subscription::every(v.clone(), *p)),
            )
            .collect();
        if self.config.wildcard {
            subs.push(Subscription::var("*"));
        }
        if self.side.is_some() {
            subs.push(Subscription::var("PLOGGER_CMD"));
        }
        subs
    }

    fn on_startup(&mut self, now: f64, out: &mut Vec<Post>) -> crate::app::AppResult {
        self.appcast.on_startup(now);
        if self.config.async_log
            && let Some(sink) = self.sink.take()
        {
            let header = Header {
                path: &self.file_path,
                opened_on: &self.opened_on,
                log_start: now,
                mark_data_type: self.config.mark_data_type,
            };
            match AlogWriter::new(sink, &header) {
                Ok(mut w) => {
                    w.set_double_precision(self.config.double_precision);
                    self.writer = Some(w);
                    if let Some(t) = &self.tally {
                        t.lock().text(&alog::banner(&header));
                    }
                }
                Err(e) => self.error = Some(e),
            }
        }
        self.copy_mission(now);
        if self.config.exclusion_log
            && self.config.wildcard
            && let Some(side) = &self.side
        {
            let root = side.folder.root().unwrap_or_else(|| self.root.clone());
            match side.folder.open_stream(&format!("{root}.xlog")) {
                Ok(st) => {
                    let mut x = AlogWriter::headless(st, now, self.config.mark_data_type);
                    x.set_double_precision(self.config.double_precision);
                    self.xlog = Some(x);
                }
                Err(e) => self.note(Err(e)),
            }
        }
        out.push(Post::text("LOGGER_DIRECTORY", self.directory.clone()));
        self.last_dir_post = now;
        self.failure()
    }

    fn on_mail(&mut self, mail: &[Mail], _now: f64, _out: &mut Vec<Post>) -> crate::app::AppResult {
        // The tally is held over the batch.
        let tally = self.tally.clone();
        let mut counting = tally.as_ref().map(LogTally::lock);
        for m in mail {
            self.log(m, counting.as_deref_mut());
            if !self.appcast.take_mail(m) {
                continue;
            }
            if m.key == "PLOGGER_CMD"
                && let Value::String(cmd) = &m.value
                && let Some((task, path)) = cmd.split_once('=')
                && task.trim().eq_ignore_ascii_case("COPY_FILE_REQUEST")
            {
                self.copy_requested(path.trim());
            }
        }
        // The batch's lines reach the sink now (the writer formats into its own buffer).
        self.hand_on(false);
        self.failure()
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> crate::app::AppResult {
        let tick = self.app_tick();
        self.appcast.begin(now, tick, out);
        if now - self.last_dir_post >= DIRECTORY_PERIOD {
            self.last_dir_post = now;
            out.push(Post::text("LOGGER_DIRECTORY", self.directory.clone()));
        }
        if let Some(w) = self.writer.as_mut() {
            let r = w.flush();
            self.note(r);
        }
        if self.appcast.end_due(now, tick, out) {
            let mut body = String::new();
            self.appcast_body(&mut body);
            self.appcast.post_cast(now, out, &body);
        }
        self.failure()
    }

    /// Flushes the alog and the exclusion log; a failed write is the run's failure.
    fn stop(&mut self, _now: f64) -> crate::app::AppResult {
        self.hand_on(true);
        self.failure()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use mission::source::SourceMap;

    fn block(text: &str) -> ProcessConfig {
        let src = SourceMap::from_text("t.moos", text);
        mission::moos::parse_moos(&src).value.processes[0].clone()
    }

    #[test]
    fn unsupported_keys_are_named_unless_switched_off() {
        let b = block(
            "ProcessConfig = pLogger\n{\n  AppTick = 4\n  SyncLog = false\n  CompressAlogs = true\n  \
             LoggingDirectorySummaryFile = x\n  Filetime = 1\n  File = LOG\n}\n",
        );
        let w: Vec<String> = LoggerConfig::warnings(&b)
            .iter()
            .map(ToString::to_string)
            .collect();
        assert_eq!(w.len(), 3, "{w:?}");
        assert!(
            w[0].contains("CompressAlogs = true: not supported"),
            "{w:?}"
        );
        assert!(
            w[1].contains("LoggingDirectorySummaryFile = x: not supported"),
            "{w:?}"
        );
        assert!(
            w[2].contains("Filetime = 1: not a pLogger parameter"),
            "{w:?}"
        );
    }

    #[test]
    fn a_claimed_session_never_reuses_an_existing_name() {
        let root = std::env::temp_dir().join(format!("coug-claim-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        let mut c = LoggerConfig {
            file: "LOG".into(),
            path: root.to_string_lossy().into_owned(),
            ..LoggerConfig::default()
        };
        let t = chrono::NaiveDate::from_ymd_opt(2026, 11, 24)
            .unwrap()
            .and_hms_opt(10, 0, 0)
            .unwrap();
        let (a, _) = c.claim_session(&t).unwrap();
        assert_eq!(a, t);
        // The same second again: the next second's name.
        let (b, _) = c.claim_session(&t).unwrap();
        assert_eq!(b, t + chrono::Duration::seconds(1));
        assert!(std::path::Path::new(&c.alog_path(&b)).is_file());
        // Without time stamps the one name is taken: refused, the old file untouched.
        c.file_time_stamp = false;
        c.claim_session(&t).unwrap();
        std::fs::write(c.alog_path(&t), "old").unwrap();
        assert!(matches!(c.claim_session(&t), Err(ClaimError::Exists(_))));
        assert_eq!(std::fs::read_to_string(c.alog_path(&t)).unwrap(), "old");
        std::fs::remove_dir_all(&root).unwrap();
    }

    /// A disk that refuses every write.
    struct Full;

    impl Write for Full {
        fn write(&mut self, _: &[u8]) -> io::Result<usize> {
            Err(io::Error::new(io::ErrorKind::StorageFull, "no space left"))
        }
        fn flush(&mut self) -> io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_late_sink_fails_before_it_is_attached_and_reports_the_first_write_error_on_close() {
        let mut sink = LateSink::new();
        assert!(sink.write_all(b"x").is_err(), "nothing is open yet");
        assert!(sink.side_file("a._moos", b"x").is_err());
        sink.attach(Box::new(Full), std::env::temp_dir());
        assert!(sink.write_all(b"x").is_err());
        let e = sink.close().unwrap_err();
        assert_eq!(e.kind(), io::ErrorKind::StorageFull);
        // Closed: later writes fail, a second close has nothing to report.
        assert!(sink.write_all(b"x").is_err());
        assert!(sink.close().is_ok());
        // A healthy session closes cleanly and its bytes are all written.
        let buf = SharedBuffer::default();
        let mut ok = LateSink::new();
        ok.attach(Box::new(buf.clone()), std::env::temp_dir());
        ok.write_all(b"abc").unwrap();
        ok.close().unwrap();
        assert_eq!(buf.contents(), b"abc");
    }

    #[test]
    fn the_logger_appcasts_its_file_and_counts_and_keeps_requests_out_of_a_listed_log() {
        let b = block(
            "ProcessConfig = pLogger\n{\n  AppTick = 4\n  Log = NAV_X @ 0\n  WildCardLogging = false\n}\n",
        );
        let config = LoggerConfig::from_config(Some(&b), None);
        let buf = SharedBuffer::default();
        let opened = chrono::NaiveDate::from_ymd_opt(2026, 11, 26)
            .unwrap()
            .and_hms_opt(12, 0, 0)
            .unwrap();
        let mut lg = Logger::new("pLogger", Some(b), config, buf.clone(), &opened, "x")
            .with_appcast_globals(Some("abe"), 1.0);
        assert!(
            lg.subscriptions()
                .iter()
                .any(|s| s.pattern == "APPCAST_REQ"),
            "registers APPCAST_REQ"
        );
        let mail = |key: &str, value: Value, t: f64| crate::testing::mail(key, value, t, "uMAC");
        let mut out = Vec::new();
        lg.on_startup(0.0, &mut out).unwrap();
        for k in 1..=4 {
            lg.iterate(f64::from(k) * 0.25, &mut out).unwrap();
        }
        out.clear();
        lg.on_mail(
            &[
                mail("NAV_X", Value::Double(1.5), 1.1),
                mail("NAV_X", Value::Double(1.75), 1.2),
                mail(
                    "APPCAST_REQ",
                    Value::text("node=abe,app=pLogger,duration=3.0,key=k,thresh=any"),
                    1.2,
                ),
            ],
            1.2,
            &mut out,
        )
        .unwrap();
        lg.iterate(1.25, &mut out).unwrap();
        let cast = out
            .iter()
            .find(|p| p.key == "APPCAST")
            .map(|p| appcast::AppCast::parse(p.value.as_str().unwrap()))
            .expect("an appcast on request");
        assert_eq!(cast.proc_name(), "pLogger");
        assert_eq!(cast.node_name(), "abe");
        let m = cast.messages();
        assert!(m.contains("Logged Records: 2"), "{m}");
        assert!(m.contains("Variables Logged: 1"), "{m}");
        assert!(m.contains("State: writing"), "{m}");
        lg.stop(1.5).unwrap();
        let text = String::from_utf8(buf.contents()).unwrap();
        assert!(text.contains("NAV_X"), "{text}");
        assert!(
            !text.contains("APPCAST_REQ"),
            "a request is logged only when asked for: {text}"
        );
    }

    /// Logs one mail from community `from` with `extra` lines in the block; returns its
    /// record's source column.
    fn logged_source(extra: &str, from: &str) -> String {
        let b = block(&format!(
            "ProcessConfig = pLogger\n{{\n  AsyncLog = true\n  WildCardLogging = true\n  LogAuxSrc = true\n{extra}}}\n"
        ));
        let config = LoggerConfig::from_config(Some(&b), None);
        let buf = SharedBuffer::default();
        let opened = chrono::NaiveDate::from_ymd_opt(2026, 11, 26)
            .unwrap()
            .and_hms_opt(12, 0, 0)
            .unwrap();
        let mut lg = Logger::new("pLogger", Some(b), config, buf.clone(), &opened, "x")
            .with_community("shore");
        let mut out = Vec::new();
        lg.on_startup(0.0, &mut out).unwrap();
        let mut m = crate::testing::mail("HENRY_COUNT", Value::Double(3.0), 1.0, "uTimerScript");
        m.source_aux = "k".into();
        m.community = from.into();
        lg.on_mail(&[m], 1.0, &mut out).unwrap();
        lg.iterate(1.0, &mut out).unwrap();
        lg.stop(1.5).unwrap();
        let text = String::from_utf8(buf.contents()).unwrap();
        let line = text
            .lines()
            .find(|l| l.contains("HENRY_COUNT"))
            .expect("the mail is logged")
            .to_string();
        line.split_whitespace().nth(2).unwrap().to_string()
    }

    #[test]
    fn mark_external_community_messages_writes_src_at_community_for_other_communities_only() {
        // Off by default, as in pLogger: the source alone.
        assert_eq!(logged_source("", "henry"), "uTimerScript:k");
        let on = "  MarkExternalCommunityMessages = true\n";
        assert_eq!(logged_source(on, "henry"), "uTimerScript:k@henry");
        assert_eq!(logged_source(on, "shore"), "uTimerScript:k");
        // Asking for it is no longer an unsupported-key warning.
        let b = block(&format!("ProcessConfig = pLogger\n{{\n{on}}}\n"));
        assert!(LoggerConfig::warnings(&b).is_empty());
    }

    #[test]
    fn wildcard_logging_turns_the_asynchronous_log_on_as_plogger_does() {
        // MOOS reads `true @ 0` as false; pLogger logs anyway when it logs by wildcard.
        let b = block(
            "ProcessConfig = pLogger\n{\n  AsyncLog = true @ 0\n  WildCardLogging = true\n}\n",
        );
        assert!(LoggerConfig::from_config(Some(&b), None).async_log);
        let b = block("ProcessConfig = pLogger\n{\n  AsyncLog = true @ 0\n  Log = NAV_X @ 0\n}\n");
        assert!(!LoggerConfig::from_config(Some(&b), None).async_log);
        let b =
            block("ProcessConfig = pLogger\n{\n  AsyncLog = false\n  WildCardLogging = true\n}\n");
        assert!(LoggerConfig::from_config(Some(&b), None).async_log);
    }

    #[test]
    fn atof_prefix() {
        assert_eq!(atof("0NOSYNC"), 0.0);
        assert_eq!(atof("0.5"), 0.5);
        assert_eq!(atof("2e1x"), 20.0);
        assert_eq!(atof(""), 0.0);
        assert_eq!(atof("abc"), 0.0);
    }

    #[test]
    fn reads_a_plogger_block() {
        let b = block(
            "ProcessConfig = pLogger\n{\n  AppTick = 8\n  File = LOG_ALPHA\n  PATH = ./logs/\n  \
             FileTimeStamp = false\n  Log = NAV_X @ 0.5\n  Log = NAV_Y @ 0 NOSYNC\n  Log = IVPHELM_STATE\n  \
             WildCardOmitPattern = *_STATUS, DB_*\n  DoublePrecision = 3\n}\n",
        );
        let c = LoggerConfig::from_config(Some(&b), None);
        assert_eq!(c.file, "LOG_ALPHA");
        assert_eq!(c.path, "./logs");
        assert!(!c.file_time_stamp && !c.wildcard && c.async_log);
        assert_eq!(
            c.logs,
            vec![
                ("NAV_X".to_string(), 0.5),
                ("NAV_Y".to_string(), 0.0),
                ("IVPHELM_STATE".to_string(), 2.0)
            ]
        );
        assert_eq!(c.double_precision, 3);
        assert!(c.omitted("PHELMIVP_STATUS") && c.omitted("DB_TIME") && c.omitted("MISSION_FILE"));
        assert!(!c.omitted("NAV_X"));
        let mut explicit = c.clone();
        explicit.logs.push(("PHELMIVP_STATUS".into(), 0.0));
        assert!(!explicit.omitted("PHELMIVP_STATUS") && explicit.omitted("DB_TIME"));
        let t = chrono::NaiveDate::from_ymd_opt(2026, 8, 5)
            .unwrap()
            .and_hms_opt(18, 22, 55)
            .unwrap();
        assert_eq!(c.alog_path(&t), "./logs/LOG_ALPHA/LOG_ALPHA.alog");
        let g = LoggerConfig::from_config(Some(&b), Some("/data/"));
        assert_eq!(g.path, "/data");
        let mut s = LoggerConfig::from_config(Some(&b), None);
        s.file_time_stamp = true;
        assert_eq!(s.directory(&t), "./logs/LOG_ALPHA_5_8_2026_____18_22_55");
    }
}
