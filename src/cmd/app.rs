//! Single-app mode, for swapping coug in under pAntler: one built-in app as its own MOOS
//! process, with MOOS command-line conventions (`APP MISSION.moos [ALIAS]`,
//! `--alias=NAME`), connecting to the mission's `ServerHost:ServerPort` at its
//! `MOOSTimeWarp`, configured by the `ProcessConfig` block of its MOOS name.
//!
//! Reached three ways: the binary invoked under an app's name (links made by
//! `coug install-aliases DIR`), or `coug helm|sim|pid|nodereporter MISSION.moos [ALIAS]`.

use std::path::{Path, PathBuf};

use clap::Args;
use runtime::App;
use runtime::antler::{Built, HelmFiles, Launch, LogTarget, MissionGlobals, build};
use runtime::logger::{LateSink, LoggerConfig, SideFiles};
use runtime::remote::{AppArgs, RemoteConfig};

use runtime::session::{LoadedMission, OPENED_ON, load};

use super::run::report_malconfig;

/// The MOOS app names coug answers to when invoked under them (links made by
/// `coug install-aliases`): every built-in app (`runtime::antler::BUILT_INS`, MOOSDB
/// first), then the command aliases.
pub fn app_names() -> impl Iterator<Item = &'static str> {
    runtime::antler::BUILT_INS
        .iter()
        .map(|a| a.program)
        .chain(["uPokeDB", "uXMS"])
}

/// The `coug` command line an alias that is a coug command stands for: `uPokeDB ARGS` is
/// `coug poke ARGS`, `uXMS ARGS` is `coug scope ARGS`. `None` for the MOOS apps.
pub fn command_for_alias(app: &str, args: &[String]) -> Option<Vec<String>> {
    let sub = match app {
        "uPokeDB" => "poke",
        "uXMS" => "scope",
        _ => return None,
    };
    let mut argv = vec!["coug".to_string(), sub.to_string()];
    argv.extend(args.iter().cloned());
    Some(argv)
}

/// The usage text of an app alias (`--help`, `-h`).
fn usage(program: &str) -> String {
    let v = env!("CARGO_PKG_VERSION");
    if program == "MOOSDB" {
        return format!(
            "{program} (coug {v}): a MOOSDB that C++ MOOS clients can join.\n\nUsage: {program} [MISSION.moos] [--moos_port=N]\n"
        );
    }
    let what = runtime::antler::built_in(program).map_or("a MOOS app", |a| a.what);
    format!(
        "{program} (coug {v}): {what}, as its own MOOS process configured by the mission's\n\
         ProcessConfig block of its MOOS name.\n\n\
         Usage: {program} MISSION.moos [ALIAS] [--alias=NAME]\n"
    )
}

/// Arguments of `coug helm|sim|pid|nodereporter`: MOOS app conventions.
#[derive(Debug, Args)]
pub struct AppCommandArgs {
    /// `MISSION.moos [ALIAS]`, `--alias=NAME` (as pAntler passes them).
    #[arg(
        trailing_var_arg = true,
        allow_hyphen_values = true,
        value_name = "ARGS"
    )]
    pub args: Vec<String>,
}

/// The app name coug should act as, from the program name it was invoked under:
/// `/usr/local/bin/pHelmIvP` acts as `pHelmIvP`, `/usr/bin/coug` as none (unit tests below).
pub fn app_from_argv0(argv0: &str) -> Option<&'static str> {
    let file = Path::new(argv0).file_name()?.to_str()?;
    let stem = file.strip_suffix(".exe").unwrap_or(file);
    app_names().find(|n| *n == stem)
}

/// Which program a subcommand runs: the variant the mission's ANTLER block runs (e.g.
/// legacy `uSimMarine` for `sim`), else the V22 one.
fn variant(mission: &mission::moos::MissionFile, choices: &[&'static str]) -> &'static str {
    let runs = mission.antler_runs();
    choices
        .iter()
        .copied()
        .find(|c| runs.iter().any(|r| r.app.rsplit('/').next() == Some(*c)))
        .unwrap_or(choices[0])
}

/// Runs `coug helm|sim|pid|nodereporter`; returns the exit code.
pub fn run_subcommand(which: &str, args: &AppCommandArgs) -> i32 {
    let parsed = AppArgs::parse(&args.args);
    let Some(path) = parsed.mission.as_deref() else {
        errln!("coug {which}: usage: coug {which} MISSION.moos [ALIAS] [--alias=NAME]");
        return 1;
    };
    let loaded = match load(Path::new(path), &[], &[]) {
        Ok(l) => l,
        Err(errors) => {
            for e in errors.messages() {
                errln!("coug {which}: error: {e}");
            }
            return 1;
        }
    };
    let program = match which {
        "helm" => "pHelmIvP",
        "sim" => variant(&loaded.mission, &["uSimMarineV22", "uSimMarine"]),
        "pid" => variant(&loaded.mission, &["pMarinePIDV22", "pMarinePID"]),
        _ => "pNodeReporter",
    };
    run_app(program, &args.args)
}

/// Runs coug as the MOOS app `program` with the MOOS-style arguments `args` (after the
/// program name); returns the exit code.
pub fn run_app(program: &str, args: &[String]) -> i32 {
    if args.iter().any(|a| a == "--help" || a == "-h") {
        out!("{}", usage(program));
        return 0;
    }
    if args.iter().any(|a| a == "--version" || a == "-v") {
        outln!("{program} (coug {})", env!("CARGO_PKG_VERSION"));
        return 0;
    }
    let parsed = AppArgs::parse(args);
    if program == "MOOSDB" {
        let port = args.iter().find_map(|a| {
            a.strip_prefix("--moos_port=")
                .and_then(|p| p.parse::<u16>().ok())
        });
        let db = super::db::DbArgs {
            mission: parsed.mission.map(PathBuf::from),
            port,
            host: None,
            community: None,
        };
        return match super::db::run(&db) {
            Ok(()) => 0,
            Err(e) => {
                errln!("MOOSDB: error: {e:#}");
                1
            }
        };
    }
    let Some(path) = parsed.mission.as_deref() else {
        errln!("{program}: usage: {program} MISSION.moos [ALIAS] [--alias=NAME]");
        return 1;
    };
    let moos_name = parsed.alias.clone().unwrap_or_else(|| program.to_string());
    let loaded = match load(Path::new(path), &[], &[]) {
        Ok(l) => l,
        Err(errors) => {
            for e in errors.messages() {
                errln!("{moos_name}: error: {e}");
            }
            return 1;
        }
    };
    for w in &loaded.warnings {
        errln!("{moos_name}: {w}");
    }
    let m = &loaded.mission;
    let (globals, warnings) = MissionGlobals::from_mission(m);
    for w in warnings {
        errln!("{moos_name}: {w}");
    }
    let warp = globals.time_warp;
    let start = moosdb::time::unix_now() * warp;
    let mut log_sink: Option<LateSink> = None;
    let mut launch = Launch::new(start, 1).with_helm_files(HelmFiles {
        dir: loaded.dir.clone(),
        opts: loaded.opts.clone(),
        loaded: loaded.behaviors.clone(),
    });
    if program == "pLogger" {
        match open_session(&moos_name, &loaded) {
            Ok((target, sink)) => {
                launch.log = Some(target);
                log_sink = Some(sink);
            }
            Err(e) => {
                errln!("{moos_name}: error: {e}");
                return 1;
            }
        }
    }
    let mut warnings = Vec::new();
    let app: Box<dyn App> =
        match build(program, &moos_name, m, &globals, &mut launch, &mut warnings) {
            Ok(Built::App(a)) => {
                for w in warnings {
                    errln!("{moos_name}: {w}");
                }
                // A bad configuration never ends the helm: it joins the community in MALCONFIG,
                // says why, and never drives (as pHelmIvP).
                report_malconfig(&moos_name, &a.malconfig());
                // As the C++ app: a configuration it cannot start with ends it.
                if let Some(why) = a.startup_failure() {
                    errln!("{moos_name}: error: {why}");
                    return 1;
                }
                a
            }
            Ok(_) => {
                errln!("{program}: not an app coug builds");
                return 1;
            }
            Err(e) => {
                errln!("{moos_name}: error: {e}");
                return 1;
            }
        };
    let host = if globals.server_host.eq_ignore_ascii_case("localhost") {
        "127.0.0.1".to_string()
    } else {
        globals.server_host.clone()
    };
    let cfg = RemoteConfig {
        host,
        port: globals.server_port,
        warp,
    };
    let rt = match tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
    {
        Ok(rt) => rt,
        Err(e) => {
            errln!("{moos_name}: error: {e}");
            return 1;
        }
    };
    let mut app = app;
    let result = rt.block_on(async {
        let stop = super::signal::shutdown();
        runtime::remote::run(&mut *app, &cfg, stop).await
    });
    drop(app);
    // A log that could not be written is a failed run.
    if let Some(sink) = log_sink
        && let Err(e) = sink.close()
    {
        errln!("{moos_name}: error: the log could not be written: {e}");
        return 1;
    }
    match result {
        Ok(()) => 0,
        Err(e) => {
            errln!("{moos_name}: error: {e}");
            1
        }
    }
}

/// pLogger as its own process: claims a new log session where the mission's block of
/// `moos_name` (or GlobalLogPath) says, named from now, with the mission copy beside it.
fn open_session(moos_name: &str, loaded: &LoadedMission) -> Result<(LogTarget, LateSink), String> {
    let m = &loaded.mission;
    let config = LoggerConfig::from_config(m.process(moos_name), m.global("GlobalLogPath"));
    let now = runtime::chrono::Local::now().naive_local();
    let (at, file) = config.claim_session(&now).map_err(|e| e.to_string())?;
    let sink = LateSink::new();
    sink.attach(
        Box::new(std::io::BufWriter::with_capacity(1 << 16, file)),
        PathBuf::from(config.directory(&at)),
    );
    let target = LogTarget {
        config,
        writer: Box::new(sink.clone()),
        opened: at,
        opened_on: OPENED_ON.into(),
        side: Some(SideFiles {
            mission_text: loaded.text.clone(),
            folder: sink.clone(),
            base_dir: loaded.dir.clone(),
        }),
    };
    Ok((target, sink))
}

/// Arguments of `coug install-aliases`.
#[derive(Debug, Args)]
pub struct InstallAliasesArgs {
    /// Folder for the links (created if needed); put it first on PATH so pAntler finds them.
    pub dir: PathBuf,
}

/// Creates `DIR/<app>` links to this binary for every app of [`app_names`]; existing links
/// are replaced, other files are left alone (an error).
pub fn install_aliases(args: &InstallAliasesArgs) -> anyhow::Result<()> {
    use anyhow::{Context, bail};
    let exe = std::env::current_exe().context("cannot find the coug binary")?;
    std::fs::create_dir_all(&args.dir)
        .with_context(|| format!("cannot create {}", args.dir.display()))?;
    for name in app_names() {
        let link = args.dir.join(name);
        match std::fs::symlink_metadata(&link) {
            Ok(md) if md.file_type().is_symlink() => std::fs::remove_file(&link)
                .with_context(|| format!("cannot replace {}", link.display()))?,
            Ok(_) => bail!("{} exists and is not a link; not replaced", link.display()),
            Err(_) => {}
        }
        make_link(&exe, &link).with_context(|| format!("cannot create {}", link.display()))?;
        outln!("{} -> {}", link.display(), exe.display());
    }
    Ok(())
}

#[cfg(unix)]
fn make_link(target: &Path, link: &Path) -> std::io::Result<()> {
    std::os::unix::fs::symlink(target, link)
}

#[cfg(not(unix))]
fn make_link(target: &Path, link: &Path) -> std::io::Result<()> {
    std::fs::copy(target, link).map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn program_names_select_apps() {
        assert_eq!(app_from_argv0("/usr/local/bin/pHelmIvP"), Some("pHelmIvP"));
        assert_eq!(app_from_argv0("uSimMarineV22"), Some("uSimMarineV22"));
        assert_eq!(app_from_argv0("bin/MOOSDB.exe"), Some("MOOSDB"));
        assert_eq!(app_from_argv0("/usr/bin/coug"), None);
        assert_eq!(app_from_argv0("pHelmIvPx"), None);
    }
}
