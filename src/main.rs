//! `coug`: one binary that runs MOOS-IvP missions with a native Rust helm, MOOSDB and vehicle.

// Doc comments here are clap help texts, where `[ALIAS]` is usage notation, not a link.
#![allow(rustdoc::broken_intra_doc_links)]
// Output goes through `out.rs`, which ends quietly on a closed pipe instead of panicking.
#![deny(clippy::print_stdout, clippy::print_stderr)]

use clap::{Parser, Subcommand};

/// mimalloc instead of the system allocator: a fleet run makes millions of small
/// allocations per simulated minute (messages, mail, deliveries), and glibc's malloc cost
/// about a third more CPU on 100 CougUVs (`fleet_scale --stack cougar 100 120 2`).
#[global_allocator]
static GLOBAL: mimalloc::MiMalloc = mimalloc::MiMalloc;

#[macro_use]
pub(crate) mod out;

mod cmd {
    pub mod app;
    pub mod appcast;
    pub mod base;
    pub mod check;
    pub mod db;
    pub mod emulate;
    pub mod nav;
    pub mod nsplug;
    pub mod plot;
    pub mod poke;
    pub mod run;
    pub mod scope;
    pub mod signal;
    pub mod view;
}

/// Command line of the `coug` binary.
#[derive(Debug, Parser)]
#[command(name = "coug", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
enum Command {
    /// Print the version and what each command does.
    Info,
    /// Preprocess, parse and validate mission files (.moos, .bhv); exit 1 on any error.
    Check(cmd::check::CheckArgs),
    /// Expand an nsplug template (MOOS-IvP's nsplug): IN OUT [NAME=VALUE]...
    Nsplug(cmd::nsplug::NsplugArgs),
    /// Plot an alog: LOG.alog -o OUT.svg|OUT.png (track, waypoints, polygons, depth).
    Plot(cmd::plot::PlotArgs),
    /// Replay a log's navigation sensors through the navigator: LOG.alog [-o OUT.csv] (errors against SIM_* truth).
    Nav(cmd::nav::NavArgs),
    /// Run a standalone MOOSDB: [MISSION.moos] [--port N] [--host ADDR].
    Db(cmd::db::DbArgs),
    /// Post values like uPokeDB: [MISSION.moos] VAR=VALUE... (VAR:=VALUE forces a string).
    Poke(cmd::poke::PokeArgs),
    /// Watch variables like uXMS: [MISSION.moos] VAR|PATTERN... [--all] [--show=COLS] [--once].
    Scope(cmd::scope::ScopeArgs),
    /// Run a whole mission: MISSION.moos [NAME=VALUE]... [--lockstep | --warp N] [--deploy] [--until COND].
    Run(cmd::run::RunArgs),
    /// pHelmIvP as its own MOOS process: MISSION.moos [ALIAS] [--alias=NAME].
    Helm(cmd::app::AppCommandArgs),
    /// uSimMarineV22 (or the mission's uSimMarine) as its own MOOS process: MISSION.moos [ALIAS].
    Sim(cmd::app::AppCommandArgs),
    /// pMarinePIDV22 (or the mission's pMarinePID) as its own MOOS process: MISSION.moos [ALIAS].
    Pid(cmd::app::AppCommandArgs),
    /// pNodeReporter as its own MOOS process: MISSION.moos [ALIAS].
    Nodereporter(cmd::app::AppCommandArgs),
    /// Web viewer like pMarineViewer: [MISSION.moos] [--host H] [--port N] [--http-port P] [--bind ADDR] [--token T].
    View(cmd::view::ViewArgs),
    /// The fleet's base station in the terminal over pAcomms: [MISSION.moos] [--host H] [--port N].
    Base(cmd::base::BaseArgs),
    /// Watch the appcasts of a MOOS community like uMAC: [MISSION.moos] [--node N [--app A]] [--once].
    Appcast(cmd::appcast::AppcastArgs),
    /// Create links named MOOSDB, pHelmIvP, uSimMarine(V22), pMarinePID(V22), pNodeReporter,
    /// pLogger, uTimerScript, uPokeDB and uXMS in DIR so pAntler starts coug in place of the
    /// C++ apps.
    InstallAliases(cmd::app::InstallAliasesArgs),
    /// Emulate a device on a pty or TCP: gps|dvl|seatrac|teensy [--tcp PORT | --pty [--link PATH]] [--seed N] [--fault SPEC]...
    Emulate(cmd::emulate::EmulateArgs),
}

fn init_tracing(level: &str) {
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new(level)),
        )
        .with_writer(std::io::stderr)
        // Colour codes only for a terminal: a log file or pipe gets plain text.
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .init();
}

// Also compiled as `coug`'s library (src/lib.rs), where the binary's entry point is unused.
#[allow(dead_code)]
fn main() {
    main_with(behaviors::Registry::with_stock())
}

/// The `coug` command line with the behaviour types of `registry` (installed as the process's
/// registry, [`behaviors::Registry::install`], for every helm this process builds): what
/// `coug`'s `main` does with the stock registry, and what a binary with behaviours of its own
/// calls (see `coug::main_with`). Never returns: exits with the command's status.
pub fn main_with(registry: behaviors::Registry) -> ! {
    registry.install();
    let argv: Vec<String> = std::env::args().collect();
    // Invoked under a MOOS app's name (a link from `coug install-aliases`): be that app.
    let mut cli_args = argv.clone();
    if let Some(app) = argv.first().and_then(|a| cmd::app::app_from_argv0(a)) {
        match cmd::app::command_for_alias(app, &argv[1..]) {
            Some(args) => cli_args = args,
            None => {
                init_tracing("info");
                std::process::exit(cmd::app::run_app(app, &argv[1..]));
            }
        }
    }
    let cli = Cli::parse_from(cli_args);
    // `coug run` prints its own progress; the DB's per-client log lines would drown it.
    let level = match cli.command {
        Some(Command::Run(_)) => "warn",
        _ => "info",
    };
    init_tracing(level);
    std::process::exit(match cli.command.unwrap_or(Command::Info) {
        Command::Check(args) => cmd::check::run(&args),
        Command::Nsplug(args) => cmd::nsplug::run(&args),
        Command::Plot(args) => report("plot", cmd::plot::run(&args)),
        Command::Nav(args) => report("nav", cmd::nav::run(&args)),
        Command::Db(args) => report("db", cmd::db::run(&args)),
        Command::Poke(args) => report("poke", cmd::poke::run(&args)),
        Command::Scope(args) => report("scope", cmd::scope::run(&args)),
        Command::Run(args) => cmd::run::run(&args),
        Command::View(args) => report("view", cmd::view::run(&args)),
        Command::Base(args) => report("base", cmd::base::run(&args)),
        Command::Appcast(args) => report("appcast", cmd::appcast::run(&args)),
        Command::Helm(args) => cmd::app::run_subcommand("helm", &args),
        Command::Sim(args) => cmd::app::run_subcommand("sim", &args),
        Command::Pid(args) => cmd::app::run_subcommand("pid", &args),
        Command::Nodereporter(args) => cmd::app::run_subcommand("nodereporter", &args),
        Command::InstallAliases(args) => {
            report("install-aliases", cmd::app::install_aliases(&args))
        }
        Command::Emulate(args) => report("emulate", cmd::emulate::run(&args)),
        Command::Info => {
            info();
            0
        }
    })
}

/// The one style of a command's error for users: `coug CMD: error: what (why)`, no
/// backtrace; exit status 1.
fn report(command: &str, result: anyhow::Result<()>) -> i32 {
    match result {
        Ok(()) => 0,
        Err(e) => {
            errln!("coug {command}: error: {e:#}");
            1
        }
    }
}

/// `coug info`: the version and what each part does.
fn info() {
    outln!(
        "coug {}: one binary for MOOS-IvP missions, in Rust.",
        env!("CARGO_PKG_VERSION")
    );
    outln!();
    outln!("Run and inspect missions:");
    outln!("  run       a whole mission in one process (lockstep or real time), like pAntler");
    outln!("  check     preprocess, parse and validate .moos/.bhv files");
    outln!("  nsplug    expand an nsplug template");
    outln!("  plot      draw an alog's track, waypoints, polygons and depth");
    outln!("  nav       replay an alog's sensors through the navigator; errors against the truth");
    outln!("Talk to a MOOSDB:");
    outln!("  db        a MOOSDB C++ MOOS apps can join (alias MOOSDB)");
    outln!("  poke      post values (alias uPokeDB)");
    outln!("  scope     watch variables (alias uXMS)");
    outln!("Hardware in the loop:");
    outln!("  emulate   a GPS, DVL, SeaTrac or Teensy on a pty or TCP port, with faults");
    outln!("One app as its own MOOS process (for pAntler):");
    outln!("  helm      pHelmIvP");
    outln!("  sim       uSimMarineV22 / uSimMarine");
    outln!("  pid       pMarinePIDV22 / pMarinePID");
    outln!("  nodereporter  pNodeReporter");
    outln!(
        "  install-aliases DIR  links named after the apps: {}",
        cmd::app::app_names().collect::<Vec<_>>().join(", ")
    );
    outln!();
    outln!("`coug help COMMAND` for the options of each.");
}
