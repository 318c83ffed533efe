//! Reading a driver's `ProcessConfig` parameters: the link keys every driver shares, then
//! the driver's own, leniently (a bad value keeps the default and is reported, as the vehicle
//! apps do: a driver never exits on its configuration).

use std::path::PathBuf;
use std::time::Duration;

use vehicle::ConfigError;
use vehicle::config::{is_generic_app_key, parse_bool, parse_number};

use crate::link::{Endpoint, LinkConfig, baud_supported};

/// One parameter being read: its app, key (as given) and value.
#[derive(Debug, Clone, Copy)]
pub struct Param<'a> {
    /// The app whose block holds it.
    pub app: &'static str,
    /// The key as written.
    pub key: &'a str,
    /// The value as written (trimmed).
    pub value: &'a str,
}

impl Param<'_> {
    /// The error for a value not of the form `expected`.
    pub fn bad(&self, expected: &'static str) -> ConfigError {
        ConfigError::BadValue {
            app: self.app,
            key: self.key.to_string(),
            value: self.value.to_string(),
            expected,
        }
    }

    /// A number.
    pub fn f64(&self) -> Result<f64, ConfigError> {
        parse_number(self.value).ok_or_else(|| self.bad("a number"))
    }

    /// A number at or above zero.
    pub fn non_neg(&self) -> Result<f64, ConfigError> {
        match parse_number(self.value) {
            Some(v) if v >= 0.0 && v.is_finite() => Ok(v),
            _ => Err(self.bad("a non-negative number")),
        }
    }

    /// A number above zero.
    pub fn pos(&self) -> Result<f64, ConfigError> {
        match parse_number(self.value) {
            Some(v) if v > 0.0 && v.is_finite() => Ok(v),
            _ => Err(self.bad("a positive number")),
        }
    }

    /// An integer within `lo..=hi`.
    pub fn int(&self, lo: i64, hi: i64, expected: &'static str) -> Result<i64, ConfigError> {
        match self.value.parse::<i64>() {
            Ok(v) if (lo..=hi).contains(&v) => Ok(v),
            _ => Err(self.bad(expected)),
        }
    }

    /// A MOOS boolean.
    pub fn bool(&self) -> Result<bool, ConfigError> {
        parse_bool(self.value).ok_or_else(|| self.bad("true or false"))
    }

    /// A non-empty string.
    pub fn text(&self) -> Result<String, ConfigError> {
        if self.value.is_empty() {
            Err(self.bad("a non-empty value"))
        } else {
            Ok(self.value.to_string())
        }
    }
}

/// The link keys every driver reads.
#[derive(Debug, Clone, PartialEq)]
pub struct Common {
    /// `device`: a serial path.
    pub device: Option<PathBuf>,
    /// `baud`.
    pub baud: Option<u32>,
    /// `host`.
    pub host: Option<String>,
    /// `port`.
    pub port: Option<u16>,
    /// `reconnect_min`, s.
    pub reconnect_min: f64,
    /// `reconnect_max`, s.
    pub reconnect_max: f64,
    /// `stall_timeout`, s (`None`: the driver's default).
    pub stall_timeout: Option<f64>,
    /// `status_period`, s.
    pub status_period: f64,
}

impl Default for Common {
    fn default() -> Self {
        Common {
            device: None,
            baud: None,
            host: None,
            port: None,
            reconnect_min: 0.2,
            reconnect_max: 5.0,
            stall_timeout: None,
            status_period: 1.0,
        }
    }
}

impl Common {
    /// The serial link at `device` (or `default_device`) and `baud` (or `default_baud`).
    pub fn serial_link(&self, default_device: &str, default_baud: u32) -> LinkConfig {
        self.finish(LinkConfig::new(Endpoint::Serial {
            path: self
                .device
                .clone()
                .unwrap_or_else(|| PathBuf::from(default_device)),
            baud: self.baud.unwrap_or(default_baud),
        }))
    }

    /// The TCP link to `host` (or `default_host`) and `port` (or `default_port`).
    pub fn tcp_link(&self, default_host: &str, default_port: u16) -> LinkConfig {
        self.finish(LinkConfig::new(Endpoint::Tcp {
            host: self
                .host
                .clone()
                .unwrap_or_else(|| default_host.to_string()),
            port: self.port.unwrap_or(default_port),
        }))
    }

    fn finish(&self, mut l: LinkConfig) -> LinkConfig {
        l.backoff_min = Duration::from_secs_f64(self.reconnect_min);
        l.backoff_max = Duration::from_secs_f64(self.reconnect_max.max(self.reconnect_min));
        l.stall_timeout = self
            .stall_timeout
            .filter(|t| *t > 0.0)
            .map(Duration::from_secs_f64);
        l
    }
}

/// Reads `params` (key, value pairs): the generic MOOS keys are skipped, the link keys go to
/// [`Common`], the rest to `own` (which returns `None` for a key it does not know: reported as
/// unknown). Returns the link keys and every problem, in the block's order.
pub fn read<'a>(
    app: &'static str,
    params: impl IntoIterator<Item = (&'a str, &'a str)>,
    mut own: impl FnMut(&Param<'_>, &str) -> Option<Result<(), ConfigError>>,
) -> (Common, Vec<ConfigError>) {
    let mut c = Common::default();
    let mut problems = Vec::new();
    for (key, value) in params {
        let lower = key.trim().to_ascii_lowercase();
        if is_generic_app_key(&lower) || lower == "term_report_interval" {
            continue;
        }
        let p = Param {
            app,
            key: key.trim(),
            value: value.trim(),
        };
        let r = match lower.as_str() {
            "device" => p.text().map(|v| c.device = Some(PathBuf::from(v))),
            "baud" | "baudrate" => p.int(1, i64::from(u32::MAX), "a baud rate").and_then(|v| {
                if baud_supported(v as u32) {
                    c.baud = Some(v as u32);
                    Ok(())
                } else {
                    Err(p.bad("a standard baud rate (9600, 19200, 38400, 57600, 115200, ...)"))
                }
            }),
            "host" => p.text().map(|v| c.host = Some(v)),
            "port" => p
                .int(1, 65535, "a TCP port (1-65535)")
                .map(|v| c.port = Some(v as u16)),
            "reconnect_min" => p.pos().map(|v| c.reconnect_min = v),
            "reconnect_max" => p.pos().map(|v| c.reconnect_max = v),
            "stall_timeout" => p.non_neg().map(|v| c.stall_timeout = Some(v)),
            "status_period" => p.pos().map(|v| c.status_period = v),
            _ => match own(&p, &lower) {
                Some(r) => r,
                None => Err(ConfigError::UnknownKey {
                    app,
                    key: p.key.to_string(),
                }),
            },
        };
        if let Err(e) = r {
            problems.push(e);
        }
    }
    (c, problems)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn link_keys_generic_keys_and_unknown_keys() {
        let (c, p) = read(
            "iX",
            [
                ("AppTick", "10"),
                ("device", "/dev/ttyX"),
                ("baud", "115200"),
                ("port", "99999"),
                ("colour", "red"),
                ("reconnect_max", "2"),
            ],
            |_, _| None,
        );
        assert_eq!(c.device, Some(PathBuf::from("/dev/ttyX")));
        assert_eq!(c.baud, Some(115_200));
        assert_eq!(c.reconnect_max, 2.0);
        let msgs: Vec<String> = p.iter().map(ToString::to_string).collect();
        assert_eq!(msgs.len(), 2, "{msgs:?}");
        assert!(msgs[0].contains("port = 99999"));
        assert!(msgs[1].contains("unknown parameter `colour`"));
        let l = c.serial_link("/dev/null", 9600);
        assert_eq!(
            l.endpoint,
            Endpoint::Serial {
                path: "/dev/ttyX".into(),
                baud: 115_200
            }
        );
        assert_eq!(l.backoff_max, Duration::from_secs(2));
    }

    #[test]
    fn a_nonstandard_baud_rate_is_refused() {
        let (c, p) = read("iX", [("baud", "12345")], |_, _| None);
        assert_eq!(c.baud, None);
        assert_eq!(p.len(), 1);
    }
}
