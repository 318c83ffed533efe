//! The fleet file: several MOOS communities run together by `coug run` (issue #16, point 4).
//!
//! A `.fleet` file names a base (shoreside) mission and the vehicles, usually all from one
//! template mission made different by nsplug macros (name, start position, ports, modem id).
//! One `KEY = VALUE` per line; a line whose first non-blank characters are `//` or `#` is a
//! comment, and so is the rest of a line after ` //`; blank lines are skipped:
//!
//! ```text
//! macro    = SHORE_LISTEN=9300                  // given to every community
//! base     = shoreside shoreside.moos           // NAME FILE [MACRO=VALUE ...], at most one
//! template = vehicle.moos                       // the vehicles' mission unless one names its own
//! vehicle  = henry START_POS=0,0 VPORT=9001     // NAME [FILE] [MACRO=VALUE ...]
//! vehicle  = ike   START_POS=30,0 VPORT=9002
//! ```
//!
//! Each community is preprocessed with, in this order (a later definition wins): the command
//! line's macros, the fleet's `macro =` lines, `VNAME=<name>` and `VINDEX=<n>` (1 for the
//! first vehicle, 0 for the base), and the line's own macros. Files are read relative to the
//! fleet file's folder. Names are unique and contain no blank, `:` or `=` (they prefix
//! `--poke` and `--until`: `henry:DEPLOY=true`). Every problem is an error at its line
//! ([`FleetFileError`]).
//!
//! A list of `.moos` files is a fleet too ([`LoadedFleet::from_missions`]): each community is
//! named by its mission's `Community`, and those running a `pHelmIvP` are its vehicles.

use std::fmt;
use std::path::{Path, PathBuf};

use thiserror::Error;

use crate::session::{LoadError, LoadedMission, load};

/// What a community is in its fleet.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// The base (shoreside) community.
    Base,
    /// A vehicle: a plain `--until` condition applies to every vehicle.
    Vehicle,
}

/// One line of a fleet file that names a community, before its mission is read.
#[derive(Debug, Clone, PartialEq)]
pub struct MemberSpec {
    /// The community's name in the fleet (`--poke NAME:...`, its log folder).
    pub name: String,
    /// Base or vehicle.
    pub role: Role,
    /// The mission file (resolved against the fleet file's folder).
    pub mission: PathBuf,
    /// Its nsplug macros, in the order they are defined.
    pub macros: Vec<String>,
    /// The fleet file's line.
    pub line: usize,
}

/// A fleet file read: its communities in order (the base first).
#[derive(Debug, Clone, PartialEq)]
pub struct FleetSpec {
    /// The fleet file.
    pub path: PathBuf,
    /// The base first, then the vehicles in file order.
    pub members: Vec<MemberSpec>,
}

/// A line of a fleet file that cannot be used.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{file}:{line}: {message}")]
pub struct FleetFileError {
    /// The fleet file.
    pub file: String,
    /// 1-based line (0: the file as a whole).
    pub line: usize,
    /// What is wrong.
    pub message: String,
}

/// Why a fleet cannot be loaded.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FleetError {
    /// Errors in the fleet file, each at its line.
    #[error("{}", join(.0))]
    File(Vec<FleetFileError>),
    /// A community's mission cannot be loaded.
    #[error("{name}: {error}")]
    Mission {
        /// The community.
        name: String,
        /// Why.
        error: LoadError,
    },
}

impl FleetError {
    /// One message per finding.
    pub fn messages(&self) -> Vec<String> {
        match self {
            FleetError::File(e) => e.iter().map(ToString::to_string).collect(),
            FleetError::Mission { name, error } => error
                .messages()
                .into_iter()
                .map(|m| format!("{name}: {m}"))
                .collect(),
        }
    }
}

fn join<T: fmt::Display>(items: &[T]) -> String {
    items
        .iter()
        .map(ToString::to_string)
        .collect::<Vec<_>>()
        .join("\n")
}

/// True when `name` can name a community (`--poke NAME:VAR=VALUE`).
pub fn valid_name(name: &str) -> bool {
    !name.is_empty()
        && !name
            .chars()
            .any(|c| c.is_whitespace() || c == ':' || c == '=' || c == ',')
}

/// Reads a fleet file's text (`path` names it in errors and resolves relative files).
pub fn parse_fleet(path: &Path, text: &str) -> Result<FleetSpec, Vec<FleetFileError>> {
    let file = path.display().to_string();
    let dir = path.parent().unwrap_or(Path::new("")).to_path_buf();
    let err = |line: usize, message: String| FleetFileError {
        file: file.clone(),
        line,
        message,
    };
    let mut errors = Vec::new();
    let mut fleet_macros = Vec::new();
    let mut template: Option<(PathBuf, usize)> = None;
    let mut base: Option<MemberSpec> = None;
    // Vehicles with their file, if they name one.
    let mut vehicles: Vec<(String, Option<PathBuf>, Vec<String>, usize)> = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let n = i + 1;
        let mut line = raw.trim();
        if line.is_empty() || line.starts_with("//") || line.starts_with('#') {
            continue;
        }
        if let Some(c) = line.find(" //").or_else(|| line.find("\t//")) {
            line = line[..c].trim_end();
        }
        let Some((key, value)) = line.split_once('=') else {
            errors.push(err(n, format!("expected KEY = VALUE, found {line:?}")));
            continue;
        };
        let key = key.trim();
        let value = value.trim();
        let words: Vec<&str> = value.split_whitespace().collect();
        match key.to_ascii_lowercase().as_str() {
            "macro" => {
                if !value.contains('=') || value.starts_with('=') {
                    errors.push(err(n, format!("macro = {value}: expected NAME=VALUE")));
                } else if words.len() != 1 {
                    errors.push(err(
                        n,
                        format!("macro = {value}: one NAME=VALUE per line, without blanks"),
                    ));
                } else {
                    fleet_macros.push(value.to_string());
                }
            }
            "template" => {
                if words.len() != 1 {
                    errors.push(err(n, format!("template = {value}: expected one file")));
                } else if let Some((_, first)) = &template {
                    errors.push(err(
                        n,
                        format!("a second template (the first at line {first})"),
                    ));
                } else {
                    template = Some((dir.join(words[0]), n));
                }
            }
            "base" | "vehicle" => {
                let Some(name) = words.first() else {
                    errors.push(err(n, format!("{key} = : expected a name")));
                    continue;
                };
                if !valid_name(name) {
                    errors.push(err(
                        n,
                        format!("{key} name {name:?}: no blanks, ':', '=' or ','"),
                    ));
                    continue;
                }
                let mut file = None;
                let mut macros = Vec::new();
                let mut bad = false;
                for w in &words[1..] {
                    if w.contains('=') {
                        if w.starts_with('=') {
                            errors.push(err(n, format!("{w}: a macro needs a name")));
                            bad = true;
                        }
                        macros.push((*w).to_string());
                    } else if file.is_none() && macros.is_empty() {
                        file = Some(dir.join(w));
                    } else {
                        errors.push(err(
                            n,
                            format!(
                                "{w}: expected MACRO=VALUE (the file comes right after the name)"
                            ),
                        ));
                        bad = true;
                    }
                }
                if bad {
                    continue;
                }
                if key.eq_ignore_ascii_case("base") {
                    let Some(file) = file else {
                        errors.push(err(
                            n,
                            "base = NAME FILE: the base names its mission".into(),
                        ));
                        continue;
                    };
                    if let Some(b) = &base {
                        errors.push(err(
                            n,
                            format!("a second base (the first at line {})", b.line),
                        ));
                        continue;
                    }
                    base = Some(MemberSpec {
                        name: (*name).to_string(),
                        role: Role::Base,
                        mission: file,
                        macros,
                        line: n,
                    });
                } else {
                    vehicles.push(((*name).to_string(), file, macros, n));
                }
            }
            other => errors.push(err(
                n,
                format!("unknown key {other:?} (expected macro, base, template or vehicle)"),
            )),
        }
    }
    let mut members = Vec::new();
    if let Some(mut b) = base {
        let mut m = fleet_macros.clone();
        m.push(format!("VNAME={}", b.name));
        m.push("VINDEX=0".into());
        m.append(&mut b.macros);
        b.macros = m;
        members.push(b);
    }
    for (i, (name, file, own, n)) in vehicles.into_iter().enumerate() {
        let mission = match (file, &template) {
            (Some(f), _) => f,
            (None, Some((t, _))) => t.clone(),
            (None, None) => {
                errors.push(err(
                    n,
                    format!("vehicle {name} names no mission and the fleet has no template"),
                ));
                continue;
            }
        };
        let mut macros = fleet_macros.clone();
        macros.push(format!("VNAME={name}"));
        macros.push(format!("VINDEX={}", i + 1));
        macros.extend(own);
        members.push(MemberSpec {
            name,
            role: Role::Vehicle,
            mission,
            macros,
            line: n,
        });
    }
    for (i, m) in members.iter().enumerate() {
        if let Some(first) = members[..i].iter().find(|o| o.name == m.name) {
            errors.push(err(
                m.line,
                format!("{} is named twice (first at line {})", m.name, first.line),
            ));
        }
    }
    if members.is_empty() && errors.is_empty() {
        errors.push(err(0, "no base and no vehicle: nothing to run".into()));
    }
    if errors.is_empty() {
        Ok(FleetSpec {
            path: path.to_path_buf(),
            members,
        })
    } else {
        errors.sort_by_key(|e| e.line);
        Err(errors)
    }
}

/// One community of a fleet, loaded.
pub struct Member {
    /// Its name in the fleet.
    pub name: String,
    /// Base or vehicle.
    pub role: Role,
    /// Its mission, loaded as `coug run` loads one.
    pub loaded: LoadedMission,
}

/// Several communities to run together.
pub struct LoadedFleet {
    /// The fleet file, or the first mission of a list.
    pub path: PathBuf,
    /// The communities in the order they are stepped (the base first).
    pub members: Vec<Member>,
}

impl LoadedFleet {
    /// Reads a fleet file and loads every community's mission with the command line's
    /// `macros` (before the fleet's own) and `include_paths`.
    pub fn from_file(
        path: &Path,
        macros: &[String],
        include_paths: &[PathBuf],
    ) -> Result<LoadedFleet, FleetError> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            FleetError::File(vec![FleetFileError {
                file: path.display().to_string(),
                line: 0,
                message: format!("cannot read the fleet file: {e}"),
            }])
        })?;
        let spec = parse_fleet(path, &text).map_err(FleetError::File)?;
        let mut members = Vec::new();
        for m in spec.members {
            let mut all = macros.to_vec();
            all.extend(m.macros);
            let loaded =
                load(&m.mission, &all, include_paths).map_err(|error| FleetError::Mission {
                    name: m.name.clone(),
                    error,
                })?;
            members.push(Member {
                name: m.name,
                role: m.role,
                loaded,
            });
        }
        Ok(LoadedFleet {
            path: path.to_path_buf(),
            members,
        })
    }

    /// Loads each mission of a list (`coug run a.moos b.moos`), every one with `macros`;
    /// each community is named by its `Community` (two alike are an error), and those that
    /// run a `pHelmIvP` are the vehicles.
    pub fn from_missions(
        paths: &[PathBuf],
        macros: &[String],
        include_paths: &[PathBuf],
    ) -> Result<LoadedFleet, FleetError> {
        let mut members: Vec<Member> = Vec::new();
        for p in paths {
            let loaded = load(p, macros, include_paths).map_err(|error| FleetError::Mission {
                name: p.display().to_string(),
                error,
            })?;
            let name = loaded
                .mission
                .global("Community")
                .unwrap_or("#1")
                .trim()
                .to_string();
            let file_err = |message: String| {
                FleetError::File(vec![FleetFileError {
                    file: p.display().to_string(),
                    line: 0,
                    message,
                }])
            };
            if !valid_name(&name) {
                return Err(file_err(format!(
                    "Community {name:?} cannot name a community of a fleet (no blanks, ':', '=' or ',')"
                )));
            }
            if let Some(o) = members.iter().find(|m| m.name == name) {
                return Err(file_err(format!(
                    "Community {name} is also the community of {}",
                    o.loaded.path.display()
                )));
            }
            let helm = loaded
                .mission
                .antler_runs()
                .iter()
                .any(|r| r.app.rsplit('/').next() == Some("pHelmIvP"));
            members.push(Member {
                name,
                role: if helm { Role::Vehicle } else { Role::Base },
                loaded,
            });
        }
        Ok(LoadedFleet {
            path: paths.first().cloned().unwrap_or_default(),
            members,
        })
    }

    /// The member named `name`.
    pub fn member(&self, name: &str) -> Option<&Member> {
        self.members.iter().find(|m| m.name == name)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<FleetSpec, Vec<String>> {
        parse_fleet(Path::new("dir/f.fleet"), text)
            .map_err(|e| e.iter().map(ToString::to_string).collect())
    }

    #[test]
    fn a_base_and_vehicles_from_a_template() {
        let f = parse(
            "// a fleet\nmacro = SHORE=9300\n\nbase = shore shore.moos PORT=9000\n\
             template = v.moos   // the vehicles\nvehicle = henry X=0 PORT=9001\n\
             # another comment\nvehicle = ike other.moos X=30\n",
        )
        .unwrap();
        let names: Vec<(&str, Role)> = f
            .members
            .iter()
            .map(|m| (m.name.as_str(), m.role))
            .collect();
        assert_eq!(
            names,
            vec![
                ("shore", Role::Base),
                ("henry", Role::Vehicle),
                ("ike", Role::Vehicle)
            ]
        );
        assert_eq!(f.members[0].mission, Path::new("dir/shore.moos"));
        assert_eq!(
            f.members[0].macros,
            ["SHORE=9300", "VNAME=shore", "VINDEX=0", "PORT=9000"]
        );
        assert_eq!(f.members[1].mission, Path::new("dir/v.moos"));
        assert_eq!(
            f.members[1].macros,
            ["SHORE=9300", "VNAME=henry", "VINDEX=1", "X=0", "PORT=9001"]
        );
        assert_eq!(f.members[2].mission, Path::new("dir/other.moos"));
        assert_eq!(
            f.members[2].macros,
            ["SHORE=9300", "VNAME=ike", "VINDEX=2", "X=30"]
        );
        assert_eq!(f.members[2].line, 8);
    }

    #[test]
    fn every_bad_line_is_an_error_at_its_line() {
        let e = parse(
            "vehicle = a\nbase = b\nvessel = c\nvehicle = a v.moos\nmacro = X\n\
             vehicle = d:1 v.moos\nvehicle = e v.moos Y=1 extra.moos\nno equals here\n\
             base = b2 b.moos\nbase = b3 b.moos\n",
        )
        .unwrap_err();
        assert_eq!(
            e,
            vec![
                "dir/f.fleet:1: vehicle a names no mission and the fleet has no template",
                "dir/f.fleet:2: base = NAME FILE: the base names its mission",
                "dir/f.fleet:3: unknown key \"vessel\" (expected macro, base, template or vehicle)",
                "dir/f.fleet:5: macro = X: expected NAME=VALUE",
                "dir/f.fleet:6: vehicle name \"d:1\": no blanks, ':', '=' or ','",
                "dir/f.fleet:7: extra.moos: expected MACRO=VALUE (the file comes right after the name)",
                "dir/f.fleet:8: expected KEY = VALUE, found \"no equals here\"",
                "dir/f.fleet:10: a second base (the first at line 9)",
            ]
        );
        let e = parse("template = v.moos\nvehicle = a\nvehicle = a\n").unwrap_err();
        assert_eq!(e, vec!["dir/f.fleet:3: a is named twice (first at line 2)"]);
        let e = parse("// nothing\n").unwrap_err();
        assert_eq!(
            e,
            vec!["dir/f.fleet:0: no base and no vehicle: nothing to run"]
        );
    }
}
