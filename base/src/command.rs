//! The operator's command line, read and checked, and the `ACOMMS_COMMAND` it posts; pure.
//!
//! Syntax (words separated by blanks; the vehicle is its modem id or its name as pAcomms
//! reported it, case-insensitive):
//!
//! | typed | posted (`ACOMMS_COMMAND`) | moves the vehicle |
//! |---|---|---|
//! | `kill V` | `to=<id>,cmd=kill` | no (disarms the thrusters) |
//! | `abort V` | `to=<id>,cmd=abort` | no (stops and holds) |
//! | `surface V` | `to=<id>,cmd=surface` | yes |
//! | `return V` | `to=<id>,cmd=return` | yes |
//! | `goto V X Y` | `to=<id>,cmd=goto,x=X,y=Y` | yes |
//! | `loiter V X Y [R]` | `to=<id>,cmd=loiter,x=X,y=Y[,radius=R]` | yes |
//! | `depth V D` | `to=<id>,cmd=depth,depth=D` | yes |
//!
//! Numbers are local metres, posted with at most two decimals, trailing zeros trimmed. The
//! checks: the vehicle must be one pAcomms reported (an id the base never heard of is
//! refused); coordinates finite and within 100 km of the origin; depth in 0..=1000 m; a
//! loiter radius in (0, 10000] m; no extra words.

use crate::fleet::Fleet;

/// The variable the base posts commands to.
pub const COMMAND_VAR: &str = "ACOMMS_COMMAND";

const MAX_XY_M: f64 = 100_000.0;
const MAX_DEPTH_M: f64 = 1000.0;
const MAX_RADIUS_M: f64 = 10_000.0;

/// One command to a vehicle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Command {
    /// Disarm the thrusters.
    Kill,
    /// Stop the mission and hold.
    Abort,
    /// Drive to the surface.
    Surface,
    /// Return to the launch point.
    Return,
    /// Go to a point (local metres).
    Goto {
        /// x, metres.
        x: f64,
        /// y, metres.
        y: f64,
    },
    /// Loiter at a point, with an optional radius.
    Loiter {
        /// x, metres.
        x: f64,
        /// y, metres.
        y: f64,
        /// Radius, metres (the vehicle's default when absent).
        radius: Option<f64>,
    },
    /// Hold a depth.
    Depth {
        /// Depth, metres.
        depth: f64,
    },
}

impl Command {
    /// The `cmd=` word.
    pub fn name(&self) -> &'static str {
        match self {
            Command::Kill => "kill",
            Command::Abort => "abort",
            Command::Surface => "surface",
            Command::Return => "return",
            Command::Goto { .. } => "goto",
            Command::Loiter { .. } => "loiter",
            Command::Depth { .. } => "depth",
        }
    }

    /// True for a command that makes the vehicle move somewhere (it needs the operator's
    /// confirmation); kill and abort only stop it and go at once.
    pub fn moves_vehicle(&self) -> bool {
        !matches!(self, Command::Kill | Command::Abort)
    }
}

/// A checked command for one vehicle.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    /// The vehicle's modem id.
    pub to: u32,
    /// Its name.
    pub name: String,
    /// What it is told.
    pub command: Command,
}

fn num(s: &mut String, v: f64) {
    moos_types::fmt::compact(s, v, 2);
}

impl Request {
    /// The `ACOMMS_COMMAND` value.
    pub fn to_value(&self) -> String {
        let mut s = format!("to={},cmd={}", self.to, self.command.name());
        match self.command {
            Command::Goto { x, y } => {
                s.push_str(",x=");
                num(&mut s, x);
                s.push_str(",y=");
                num(&mut s, y);
            }
            Command::Loiter { x, y, radius } => {
                s.push_str(",x=");
                num(&mut s, x);
                s.push_str(",y=");
                num(&mut s, y);
                if let Some(r) = radius {
                    s.push_str(",radius=");
                    num(&mut s, r);
                }
            }
            Command::Depth { depth } => {
                s.push_str(",depth=");
                num(&mut s, depth);
            }
            Command::Kill | Command::Abort | Command::Surface | Command::Return => {}
        }
        s
    }

    /// What the operator is asked to confirm.
    pub fn describe(&self) -> String {
        let what = match self.command {
            Command::Kill => "kill (disarm the thrusters)".to_string(),
            Command::Abort => "abort (stop and hold)".to_string(),
            Command::Surface => "surface".to_string(),
            Command::Return => "return".to_string(),
            Command::Goto { x, y } => format!("go to x={x} y={y}"),
            Command::Loiter { x, y, radius } => match radius {
                Some(r) => format!("loiter at x={x} y={y} radius {r} m"),
                None => format!("loiter at x={x} y={y}"),
            },
            Command::Depth { depth } => format!("hold depth {depth} m"),
        };
        format!("{} (modem {}): {what}", self.name, self.to)
    }
}

/// Why a typed command is refused.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum CommandError {
    /// Nothing typed.
    Empty,
    /// Not one of the commands.
    UnknownCommand(String),
    /// No vehicle named.
    NoVehicle,
    /// No vehicle with that id or name was reported by pAcomms.
    UnknownVehicle(String),
    /// The vehicle is known by name only (no modem id yet).
    NoModemId(String),
    /// A value is missing.
    Missing(&'static str),
    /// A value is not a number or out of its range.
    Bad(&'static str, String),
    /// Words after the command's last argument.
    Extra(String),
}

impl std::fmt::Display for CommandError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CommandError::Empty => write!(f, "type a command (help: h)"),
            CommandError::UnknownCommand(c) => write!(
                f,
                "unknown command {c:?}: kill, abort, surface, return, goto, loiter, depth"
            ),
            CommandError::NoVehicle => write!(f, "which vehicle? (modem id or name)"),
            CommandError::UnknownVehicle(v) => write!(f, "no vehicle {v:?} reported by pAcomms"),
            CommandError::NoModemId(v) => write!(f, "{v} has no modem id yet"),
            CommandError::Missing(what) => write!(f, "missing {what}"),
            CommandError::Bad(what, v) => write!(f, "bad {what}: {v:?}"),
            CommandError::Extra(w) => write!(f, "unexpected {w:?}"),
        }
    }
}

impl std::error::Error for CommandError {}

fn value(
    words: &mut std::str::SplitWhitespace<'_>,
    what: &'static str,
    ok: impl Fn(f64) -> bool,
) -> Result<f64, CommandError> {
    let w = words.next().ok_or(CommandError::Missing(what))?;
    match w.parse::<f64>() {
        Ok(v) if v.is_finite() && ok(v) => Ok(v),
        _ => Err(CommandError::Bad(what, w.to_string())),
    }
}

/// Reads and checks a typed command against the fleet.
pub fn parse(line: &str, fleet: &Fleet) -> Result<Request, CommandError> {
    let mut words = line.split_whitespace();
    let cmd = words
        .next()
        .ok_or(CommandError::Empty)?
        .to_ascii_lowercase();
    if !matches!(
        cmd.as_str(),
        "kill" | "abort" | "surface" | "return" | "goto" | "loiter" | "depth"
    ) {
        return Err(CommandError::UnknownCommand(cmd));
    }
    let who = words.next().ok_or(CommandError::NoVehicle)?;
    let vehicle = match who.parse::<u32>() {
        Ok(id) => fleet.by_id(id),
        Err(_) => fleet.by_name(who),
    }
    .ok_or_else(|| CommandError::UnknownVehicle(who.to_string()))?;
    let to = vehicle
        .id
        .ok_or_else(|| CommandError::NoModemId(vehicle.name.clone()))?;
    let xy = |v: f64| v.abs() <= MAX_XY_M;
    let command = match cmd.as_str() {
        "kill" => Command::Kill,
        "abort" => Command::Abort,
        "surface" => Command::Surface,
        "return" => Command::Return,
        "goto" => Command::Goto {
            x: value(&mut words, "x", xy)?,
            y: value(&mut words, "y", xy)?,
        },
        "loiter" => {
            let x = value(&mut words, "x", xy)?;
            let y = value(&mut words, "y", xy)?;
            let radius = match words.clone().next() {
                Some(_) => Some(value(&mut words, "radius", |r| {
                    r > 0.0 && r <= MAX_RADIUS_M
                })?),
                None => None,
            };
            Command::Loiter { x, y, radius }
        }
        _ => Command::Depth {
            depth: value(&mut words, "depth", |d| (0.0..=MAX_DEPTH_M).contains(&d))?,
        },
    };
    if let Some(w) = words.next() {
        return Err(CommandError::Extra(w.to_string()));
    }
    Ok(Request {
        to,
        name: vehicle.name.clone(),
        command,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fleet() -> Fleet {
        let mut f = Fleet::new();
        f.apply(
            "ACOMMS_VEHICLE",
            "id=2,name=coug2,polls=0,answers=0,timeouts=0",
        )
        .unwrap();
        f.apply("NODE_REPORT", "NAME=radio_only,X=1,Y=2,TIME=3")
            .unwrap();
        f
    }

    #[test]
    fn every_command_posts_the_interface_format() {
        let f = fleet();
        let post = |l: &str| parse(l, &f).unwrap().to_value();
        assert_eq!(post("kill 2"), "to=2,cmd=kill");
        assert_eq!(post("ABORT coug2"), "to=2,cmd=abort");
        assert_eq!(post("surface Coug2"), "to=2,cmd=surface");
        assert_eq!(post("return 2"), "to=2,cmd=return");
        assert_eq!(post("goto 2 100 -50.25"), "to=2,cmd=goto,x=100,y=-50.25");
        assert_eq!(post("goto 2 0.004 1.5"), "to=2,cmd=goto,x=0,y=1.5");
        assert_eq!(post("loiter 2 10 20"), "to=2,cmd=loiter,x=10,y=20");
        assert_eq!(
            post("loiter 2 10 20 15"),
            "to=2,cmd=loiter,x=10,y=20,radius=15"
        );
        assert_eq!(post("depth coug2 7.5"), "to=2,cmd=depth,depth=7.5");
    }

    #[test]
    fn bad_commands_are_refused_with_a_reason() {
        let f = fleet();
        let err = |l: &str| parse(l, &f).unwrap_err();
        assert_eq!(err(""), CommandError::Empty);
        assert_eq!(err("jump 2"), CommandError::UnknownCommand("jump".into()));
        assert_eq!(err("abort"), CommandError::NoVehicle);
        assert_eq!(err("abort 9"), CommandError::UnknownVehicle("9".into()));
        assert_eq!(
            err("abort ghost"),
            CommandError::UnknownVehicle("ghost".into())
        );
        assert_eq!(
            err("abort radio_only"),
            CommandError::NoModemId("radio_only".into())
        );
        assert_eq!(err("goto 2 100"), CommandError::Missing("y"));
        assert_eq!(err("goto 2 x 1"), CommandError::Bad("x", "x".into()));
        assert_eq!(err("goto 2 nan 1"), CommandError::Bad("x", "nan".into()));
        assert_eq!(err("goto 2 1e6 1"), CommandError::Bad("x", "1e6".into()));
        assert_eq!(err("depth 2 -1"), CommandError::Bad("depth", "-1".into()));
        assert_eq!(
            err("loiter 2 1 1 0"),
            CommandError::Bad("radius", "0".into())
        );
        assert_eq!(err("abort 2 now"), CommandError::Extra("now".into()));
    }

    #[test]
    fn only_kill_and_abort_go_without_confirmation() {
        let moving: Vec<bool> = [
            Command::Kill,
            Command::Abort,
            Command::Surface,
            Command::Return,
            Command::Goto { x: 0.0, y: 0.0 },
            Command::Loiter {
                x: 0.0,
                y: 0.0,
                radius: None,
            },
            Command::Depth { depth: 1.0 },
        ]
        .iter()
        .map(Command::moves_vehicle)
        .collect();
        assert_eq!(moving, [false, false, true, true, true, true, true]);
    }
}
