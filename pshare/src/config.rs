//! pShare's configuration: `Output` and `Input` directives (long and short forms), the
//! multicast base settings, and the same directives arriving at run time as `PSHARE_CMD`.
//!
//! Forms read (as `Share.cpp` reads them):
//!
//! | form | example |
//! |---|---|
//! | long output | `output = src_name=X, dest_name=Y, route=host:port & multicast_8, frequency=2, duration=60, max_shares=3` |
//! | short output | `output = X->Y:host:port@2 & Z:multicast_8 & host:port` (`@` is a frequency in Hz) |
//! | long input | `input = route=localhost:9201 & multicast_3, white_list=NAV_* & DEPLOY` |
//! | command | `PSHARE_CMD = "cmd=output, src_name=X, route=localhost:9201"` |
//!
//! An `output` line is long when it contains `route` or `Route`, short otherwise; an `input`
//! line is always long (`input = localhost:9201` lacks its `route=` and is refused, as the C++
//! app throws on it). Spaces are removed from long forms before reading them; a field is
//! `token=value` between commas, the token case-sensitive.
//!
//! Where coug is stricter than the C++ app (which skips the rest of the block after the first
//! bad line, and reads a bad number as "not given"): every bad line is refused on its own with
//! a typed [`ConfigError`], and the other lines are kept.

use std::fmt;

use moos_types::text::{chomp, moos_is_numeric};
use thiserror::Error;

/// pShare's multicast group when `multicast_address` is not given (`DEFAULT_MULTICAST_GROUP_ADDRESS`).
pub const DEFAULT_MULTICAST_ADDRESS: &str = "224.1.1.11";

/// Port of channel 0 when `multicast_base_port` is not given; channel N is this plus N.
pub const DEFAULT_MULTICAST_BASE_PORT: u16 = 24460;

/// The highest multicast channel number (pShare's `MAX_MULTICAST_CHANNELS` is 256).
pub const MAX_CHANNEL: u16 = 255;

/// Where a route sends to or listens on.
#[derive(Debug, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Endpoint {
    /// A unicast UDP address, `host:port` (the host as written: a name or dotted quad).
    Udp {
        /// Host name or address.
        host: String,
        /// UDP port (0 on an input: the system picks one, a coug extension for tests).
        port: u16,
    },
    /// A multicast channel alias, `multicast_N`: the group address at the base port plus N.
    Multicast(u16),
}

impl Endpoint {
    /// True for a multicast channel.
    pub fn is_multicast(&self) -> bool {
        matches!(self, Endpoint::Multicast(_))
    }
}

impl fmt::Display for Endpoint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Endpoint::Udp { host, port } => write!(f, "{host}:{port}"),
            Endpoint::Multicast(n) => write!(f, "multicast_{n}"),
        }
    }
}

/// One output share: what to send, under which name, where, and its limits.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputSpec {
    /// The variable (or `var_pattern[:app_pattern]` with wildcards) to share, trimmed.
    pub src_name: String,
    /// The name it arrives under (default: `src_name`), trimmed.
    pub dest_name: String,
    /// Where it goes.
    pub endpoint: Endpoint,
    /// Most shares per second (0: every write).
    pub frequency: f64,
    /// Seconds the share stays active from its creation (`None`: for ever; 0: the special
    /// "send the latest value once" of dynamic shares).
    pub duration: Option<f64>,
    /// Most shares in all (`None`: no limit).
    pub max_shares: Option<u32>,
}

/// One input directive: where to listen and which names to let in.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct InputSpec {
    /// Where to listen.
    pub endpoints: Vec<Endpoint>,
    /// Name masks (`*`, `?`) a received message must match; empty: every name.
    pub white_list: Vec<String>,
}

/// A directive of a `PSHARE_CMD` posting.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// `cmd=output,...`: shares to add or refresh.
    Output(Vec<OutputSpec>),
    /// `cmd=input,...`: a listener to add.
    Input(InputSpec),
}

/// Why a directive was refused.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ConfigError {
    /// A long form lacks a field it needs (`src_name`, `route`).
    #[error("\"{0}\" is a required field")]
    MissingField(&'static str),
    /// A short output has no `->`.
    #[error("short form {0:?} has no \"->\" between the variable and its routes")]
    NoArrow(String),
    /// A short output route has too few or too many `:` parts.
    #[error("route {0:?} is neither [new_name:]host:port nor [new_name:]multicast_N")]
    BadShortRoute(String),
    /// A route is neither `host:port` nor `multicast_N`.
    #[error("route {0:?} is not of host:port format")]
    BadRoute(String),
    /// A port is not a number from 0 to 65535 (1 to 65535 on outputs).
    #[error("port {0:?} is not a UDP port")]
    BadPort(String),
    /// A multicast channel is not a number from 0 to 255.
    #[error("multicast channel {0:?} is not a number from 0 to 255")]
    BadChannel(String),
    /// A numeric field does not hold a number.
    #[error("{field} = {value:?} is not a number")]
    BadNumber {
        /// The field.
        field: &'static str,
        /// What it held.
        value: String,
    },
    /// A `PSHARE_CMD` names neither `output` nor `input`.
    #[error("cmd={0:?} is neither \"output\" nor \"input\"")]
    UnknownCommand(String),
    /// The routes of a directive are empty.
    #[error("no route given")]
    NoRoute,
}

/// A refused line of a configuration block.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("line {line}: {key} = {value}: {error}")]
pub struct LineError {
    /// The line in the mission file.
    pub line: usize,
    /// The parameter as written.
    pub key: String,
    /// Its value as written.
    pub value: String,
    /// Why it was refused.
    pub error: ConfigError,
}

/// What a `ProcessConfig = pShare` block configures.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// Every output share, in file order.
    pub outputs: Vec<OutputSpec>,
    /// Every input directive, in file order.
    pub inputs: Vec<InputSpec>,
    /// `multicast_address` (default 224.1.1.11).
    pub multicast_address: String,
    /// `multicast_base_port` (default 24460).
    pub multicast_base_port: u16,
    /// `verbose`.
    pub verbose: bool,
    /// `radio_max_depth` (coug only; `None`, the default: no gate, as MOOS's pShare): the
    /// deepest `NAV_DEPTH` in metres at which the bridge is up. Deeper, the vehicle is
    /// submerged and its radio or Wi-Fi link is down: nothing is sent, and what arrives is
    /// dropped, never queued (see [`RadioGate`]).
    pub radio_max_depth: Option<f64>,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            outputs: Vec::new(),
            inputs: Vec::new(),
            multicast_address: DEFAULT_MULTICAST_ADDRESS.to_string(),
            multicast_base_port: DEFAULT_MULTICAST_BASE_PORT,
            verbose: false,
            radio_max_depth: None,
        }
    }
}

impl Config {
    /// Reads a block's `(line, key, value)` parameters: `output`, `input`,
    /// `multicast_address`, `multicast_base_port`, `verbose` and coug's `radio_max_depth`
    /// (a number of metres, at least 0; case-insensitive keys);
    /// others (AppTick, CommsTick, ...) are not pShare's and are left alone, as the C++ app
    /// does. Refused lines are returned beside what was read.
    ///
    /// ```
    /// let (c, bad) = pshare::Config::from_params([
    ///     (3, "output", "NAV_X->REMOTE_NAV_X:127.0.0.1:9201"),
    ///     (4, "input", "route = localhost:9200"),
    ///     (5, "output", "DEPLOY"),
    /// ]);
    /// assert_eq!(c.outputs[0].dest_name, "REMOTE_NAV_X");
    /// assert_eq!(c.inputs[0].endpoints[0].to_string(), "localhost:9200");
    /// assert_eq!(bad[0].line, 5);
    /// ```
    pub fn from_params<'a>(
        params: impl IntoIterator<Item = (usize, &'a str, &'a str)>,
    ) -> (Config, Vec<LineError>) {
        let mut c = Config::default();
        let mut bad = Vec::new();
        for (line, key, value) in params {
            let k = key.trim().to_ascii_lowercase();
            let refuse = |error| LineError {
                line,
                key: key.trim().to_string(),
                value: value.trim().to_string(),
                error,
            };
            match k.as_str() {
                "output" => match parse_output(value) {
                    Ok(specs) => c.outputs.extend(specs),
                    Err(e) => bad.push(refuse(e)),
                },
                "input" => match parse_input(value) {
                    Ok(spec) => c.inputs.push(spec),
                    Err(e) => bad.push(refuse(e)),
                },
                "multicast_address" => c.multicast_address = value.trim().to_string(),
                "multicast_base_port" => match parse_port(value.trim()) {
                    Some(p) => c.multicast_base_port = p,
                    None => bad.push(refuse(ConfigError::BadPort(value.trim().to_string()))),
                },
                "verbose" => c.verbose = moos_types::text::config_bool(value.trim()),
                "radio_max_depth" => match value.trim().parse::<f64>() {
                    Ok(d) if d.is_finite() && d >= 0.0 => c.radio_max_depth = Some(d),
                    _ => bad.push(refuse(ConfigError::BadNumber {
                        field: "radio_max_depth",
                        value: value.trim().to_string(),
                    })),
                },
                _ => {}
            }
        }
        (c, bad)
    }
}

/// The surface-only radio of a vehicle's bridge (coug only; issue #16, point 4): vehicles
/// talk through the acoustic channel underwater and through a radio or Wi-Fi link only at
/// the surface. MOOS's pShare and uFldNodeComms have no such gate (a simulated MOOS-IvP
/// fleet shares whatever the depth); coug's pShare applies one when its block sets
/// `radio_max_depth`: the link is up while the latest `NAV_DEPTH` is at most that many
/// metres (and before any `NAV_DEPTH` arrives: vehicles start at the surface). A radio does
/// not store and forward: what is sent or arrives while it is down is dropped and counted.
///
/// ```
/// use pshare::config::RadioGate;
/// let mut g = RadioGate::new(Some(0.5));
/// assert!(g.up());
/// g.depth(3.0);
/// assert!(!g.up());
/// g.depth(0.2);
/// assert!(g.up());
/// assert!(RadioGate::new(None).up());
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RadioGate {
    max_depth: Option<f64>,
    depth: Option<f64>,
}

impl RadioGate {
    /// A gate that opens at `max_depth` metres and shallower (`None`: always open).
    pub fn new(max_depth: Option<f64>) -> RadioGate {
        RadioGate {
            max_depth,
            depth: None,
        }
    }

    /// True when the gate depends on depth (`radio_max_depth` was given).
    pub fn enabled(&self) -> bool {
        self.max_depth.is_some()
    }

    /// The vehicle's latest depth in metres (`NAV_DEPTH`).
    pub fn depth(&mut self, depth_m: f64) {
        self.depth = Some(depth_m);
    }

    /// True when the link is up: no gate, no depth yet, or at most `max_depth` deep (a NaN
    /// depth counts as submerged).
    pub fn up(&self) -> bool {
        match (self.max_depth, self.depth) {
            (Some(max), Some(d)) => d <= max,
            _ => true,
        }
    }
}

/// An `output` value, long or short form (long when it mentions `route` or `Route`).
///
/// ```
/// use pshare::config::{parse_output, Endpoint};
/// let s = parse_output("src_name=X, dest_name=Y, route=localhost:9000 & multicast_8, max_shares=2").unwrap();
/// assert_eq!(s.len(), 2);
/// assert_eq!(s[1].endpoint, Endpoint::Multicast(8));
/// assert_eq!(s[0].max_shares, Some(2));
/// ```
pub fn parse_output(value: &str) -> Result<Vec<OutputSpec>, ConfigError> {
    if value.contains("route") || value.contains("Route") {
        parse_long_output(value)
    } else {
        parse_short_output(value)
    }
}

/// An `input` value: always the long form, `route=A & B[, white_list=P & Q]`.
pub fn parse_input(value: &str) -> Result<InputSpec, ConfigError> {
    let s: String = value.chars().filter(|c| *c != ' ').collect();
    let white_list = match field(&s, "white_list") {
        Some(w) if !w.is_empty() => split_amp(w).map(str::to_string).collect(),
        _ => Vec::new(),
    };
    let routes = field(&s, "route").ok_or(ConfigError::MissingField("route"))?;
    let endpoints = split_amp(routes)
        .map(|r| parse_endpoint(r, true))
        .collect::<Result<Vec<_>, _>>()?;
    if endpoints.is_empty() {
        return Err(ConfigError::NoRoute);
    }
    Ok(InputSpec {
        endpoints,
        white_list,
    })
}

/// A `PSHARE_CMD` value: `cmd=output,...` or `cmd=input,...` (`cmd` case-insensitive in its
/// value, as `MOOSStrCmp`), the rest as a long form.
///
/// ```
/// use pshare::config::{parse_command, Command};
/// let Command::Output(s) = parse_command("cmd = Output, src_name = T, dest_name = TT, route=127.0.0.1:9832").unwrap() else { panic!() };
/// assert_eq!(s[0].dest_name, "TT");
/// ```
pub fn parse_command(value: &str) -> Result<Command, ConfigError> {
    let s: String = value.chars().filter(|c| *c != ' ').collect();
    let cmd = field(&s, "cmd").unwrap_or("");
    if cmd.eq_ignore_ascii_case("output") {
        Ok(Command::Output(parse_long_output(&s)?))
    } else if cmd.eq_ignore_ascii_case("input") {
        Ok(Command::Input(parse_input(&s)?))
    } else {
        Err(ConfigError::UnknownCommand(cmd.to_string()))
    }
}

fn parse_long_output(value: &str) -> Result<Vec<OutputSpec>, ConfigError> {
    let s: String = value.chars().filter(|c| *c != ' ').collect();
    let src = field(&s, "src_name").ok_or(ConfigError::MissingField("src_name"))?;
    let dest = field(&s, "dest_name").unwrap_or(src);
    let duration = number(&s, "duration")?.filter(|d| *d >= 0.0);
    let max_shares = match field(&s, "max_shares") {
        None => None,
        Some(v) => {
            let n: i64 = v.parse().map_err(|_| ConfigError::BadNumber {
                field: "max_shares",
                value: v.to_string(),
            })?;
            u32::try_from(n).ok()
        }
    };
    let frequency = number(&s, "frequency")?.unwrap_or(0.0);
    let routes = field(&s, "route").ok_or(ConfigError::MissingField("route"))?;
    let mut out = Vec::new();
    for r in split_amp(routes) {
        out.push(OutputSpec {
            src_name: src.trim().to_string(),
            dest_name: dest.trim().to_string(),
            endpoint: parse_endpoint(r, false)?,
            frequency,
            duration,
            max_shares,
        });
    }
    if out.is_empty() {
        return Err(ConfigError::NoRoute);
    }
    Ok(out)
}

fn parse_short_output(value: &str) -> Result<Vec<OutputSpec>, ConfigError> {
    let Some((src, mut routes)) = value.split_once("->") else {
        return Err(ConfigError::NoArrow(value.trim().to_string()));
    };
    let src = src.trim();
    let mut out = Vec::new();
    while !routes.is_empty() {
        let whole = chomp(&mut routes, "&").trim_matches([' ', '\t']);
        let (route, freq) = match whole.split_once('@') {
            Some((r, f)) => (r, f),
            None => (whole, ""),
        };
        // A frequency that is not a number is read as "every write", as pShare does.
        let frequency = if !freq.is_empty() && moos_is_numeric(freq) {
            moos_types::text::atof(freq)
        } else {
            0.0
        };
        let parts: Vec<&str> = route.split(':').collect();
        let bad = || ConfigError::BadShortRoute(route.to_string());
        let (dest, endpoint) = if parts.last().is_some_and(|p| p.starts_with("multicast_")) {
            match parts.as_slice() {
                [ch] => (src, parse_endpoint(ch, false)?),
                [d, ch] => (*d, parse_endpoint(ch, false)?),
                _ => return Err(bad()),
            }
        } else {
            match parts.as_slice() {
                [h, p] => (src, udp(h, p, false)?),
                [d, h, p] => (*d, udp(h, p, false)?),
                _ => return Err(bad()),
            }
        };
        out.push(OutputSpec {
            src_name: src.to_string(),
            dest_name: dest.trim().to_string(),
            endpoint,
            frequency,
            duration: None,
            max_shares: None,
        });
    }
    if out.is_empty() {
        return Err(ConfigError::NoRoute);
    }
    Ok(out)
}

/// `MOOSValFromString` on a string without spaces: the value of the comma-separated field
/// `token=value` (token case-sensitive), the first one that has it.
fn field<'a>(s: &'a str, token: &str) -> Option<&'a str> {
    s.split(',').find_map(|f| {
        let rest = f.trim_start_matches([' ', '\t']).strip_prefix(token)?;
        rest.trim_start_matches([' ', '\t']).strip_prefix('=')
    })
}

fn number(s: &str, token: &'static str) -> Result<Option<f64>, ConfigError> {
    match field(s, token) {
        None => Ok(None),
        Some(v) => match v.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(Some(x)),
            _ => Err(ConfigError::BadNumber {
                field: token,
                value: v.to_string(),
            }),
        },
    }
}

fn split_amp(s: &str) -> impl Iterator<Item = &str> {
    s.split('&').map(str::trim).filter(|r| !r.is_empty())
}

fn parse_port(p: &str) -> Option<u16> {
    if p.is_empty() || !p.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    p.parse().ok()
}

fn udp(host: &str, port: &str, input: bool) -> Result<Endpoint, ConfigError> {
    let host = host.trim();
    if host.is_empty() {
        return Err(ConfigError::BadRoute(format!("{host}:{port}")));
    }
    match parse_port(port.trim()) {
        Some(p) if p > 0 || input => Ok(Endpoint::Udp {
            host: host.to_string(),
            port: p,
        }),
        _ => Err(ConfigError::BadPort(port.trim().to_string())),
    }
}

/// `multicast_N` or `host:port`.
fn parse_endpoint(r: &str, input: bool) -> Result<Endpoint, ConfigError> {
    if let Some(n) = r.strip_prefix("multicast_") {
        return match n.parse::<u16>() {
            Ok(ch) if ch <= MAX_CHANNEL && n.bytes().all(|b| b.is_ascii_digit()) => {
                Ok(Endpoint::Multicast(ch))
            }
            _ => Err(ConfigError::BadChannel(n.to_string())),
        };
    }
    let Some((host, port)) = r.split_once(':') else {
        return Err(ConfigError::BadRoute(r.to_string()));
    };
    if port.contains(':') {
        return Err(ConfigError::BadRoute(r.to_string()));
    }
    udp(host, port, input)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_are_read_as_moos_val_from_string() {
        assert_eq!(field("src_name=X,dest_name=Y", "src_name"), Some("X"));
        assert_eq!(field("src_name=X,dest_name=Y", "dest_name"), Some("Y"));
        // A token inside another field's name does not count.
        assert_eq!(field("xsrc_name=X", "src_name"), None);
        assert_eq!(field("SRC_NAME=X", "src_name"), None);
        assert_eq!(
            field("route=a:1&b:2,white_list=A&B", "route"),
            Some("a:1&b:2")
        );
    }

    #[test]
    fn radio_max_depth_is_a_depth_of_zero_or_more_metres() {
        let (c, bad) = Config::from_params([(2, "Radio_Max_Depth", " 0.5 ")]);
        assert!(bad.is_empty());
        assert_eq!(c.radio_max_depth, Some(0.5));
        assert_eq!(Config::default().radio_max_depth, None);
        for v in ["-1", "deep", "inf", ""] {
            let (c, bad) = Config::from_params([(7, "radio_max_depth", v)]);
            assert_eq!(c.radio_max_depth, None, "{v}");
            assert_eq!(bad.len(), 1, "{v}");
            assert_eq!(bad[0].line, 7);
            assert!(matches!(
                bad[0].error,
                ConfigError::BadNumber {
                    field: "radio_max_depth",
                    ..
                }
            ));
        }
    }

    #[test]
    fn the_radio_is_up_at_the_surface_only() {
        let mut g = RadioGate::new(Some(1.0));
        assert!(g.enabled() && g.up(), "up before any depth arrives");
        g.depth(1.0);
        assert!(g.up(), "the threshold itself is the surface");
        g.depth(1.01);
        assert!(!g.up());
        g.depth(f64::NAN);
        assert!(!g.up(), "a NaN depth is not the surface");
        g.depth(0.0);
        assert!(g.up());
        let mut never = RadioGate::new(None);
        never.depth(100.0);
        assert!(!never.enabled() && never.up());
    }
}
