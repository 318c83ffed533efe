//! `coug` as a library: the whole command line, callable from a binary that adds behaviours
//! of its own to the helm.
//!
//! A user's crate implements [`behaviors::Behavior`] for its behaviour, registers it in a
//! [`behaviors::Registry`] and hands the registry to [`main_with`]; the resulting binary is
//! `coug` with one more behaviour type, in `coug run`, `coug helm` and the `pHelmIvP` alias
//! alike (the workspace's `examples/my-behaviour` is such a crate):
//!
//! ```no_run
//! # use behaviors::{Behavior, Ctx, Out};
//! # struct Orbit;
//! # impl Orbit { fn new() -> Self { Orbit } }
//! # impl Behavior for Orbit {
//! #     fn kind(&self) -> &'static str { "BHV_Orbit" }
//! #     fn on_run(&mut self, _: &Ctx<'_>, _: &mut Out) -> Option<helm::ivp::IvpFunction> { None }
//! # }
//! fn main() {
//!     coug::main_with(behaviors::Registry::with_stock().register("BHV_Orbit", Orbit::new))
//! }
//! ```
//!
//! In-process runs (tests) install the registry themselves, `registry.install()`, and call
//! `runtime::session` as `coug run` does.

// The command line lives in the binary's source; the library compiles the same file.
#[path = "main.rs"]
mod cli;
// The output macros write through `$crate::out`.
use cli::out;

/// The behaviour registry type [`main_with`] takes.
pub use behaviors::Registry;
pub use cli::main_with;
