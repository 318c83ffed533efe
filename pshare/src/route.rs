//! The routing table and its decisions, with time as an argument.
//!
//! As `Share.cpp` keeps them: a share whose `src_name` holds none of `*`, `?`, `:` is a
//! *named* route (the app registers for that variable); any other is a *wildcard* route,
//! `var_pattern[:app_pattern]` (app pattern default `*`). Mail of a variable with named routes
//! goes out on them; mail of any other variable is matched against the wildcard routes, and
//! every match is copied into the named routes of that variable (so its later mail takes the
//! named path). A wildcard route's destination name is a prefix put before the variable's
//! name (none when the written `dest_name` holds `*` or `?`, as it does by default), or, with
//! `^` and a pattern with one `*` at its start or end, the part of the name that `*` matched.
//!
//! A route is active ([`Route::is_active`]) unless its `duration` has passed since it was
//! made, it has made `max_shares` shares, or it shared less than `1/frequency` seconds ago;
//! `duration = 0` (a dynamic "send the latest once") is active while shares remain.
//!
//! Where coug differs on purpose: when a wildcard route is copied into the named routes, the
//! C++ app sends on every named route of the variable once per matching wildcard route (two
//! matches send the first copy twice) and renames the message in place between matches; coug
//! sends each route once.

use std::collections::BTreeMap;

use moos_types::text::wildcard_match;

use crate::config::{Endpoint, OutputSpec};

/// One share of one variable to one endpoint, with its counters.
#[derive(Debug, Clone, PartialEq)]
pub struct Route {
    /// The variable shared (the pattern, for a wildcard route's template).
    pub src_name: String,
    /// The name it is sent under (a wildcard template's prefix, or `^`).
    pub dest_name: String,
    /// Where it goes.
    pub endpoint: Endpoint,
    /// Most shares per second (0: every write).
    pub frequency: f64,
    /// Seconds it stays active after `created` (`None`: for ever).
    pub duration: Option<f64>,
    /// Most shares in all (`None`: no limit).
    pub max_shares: Option<u32>,
    /// MOOS time it was made (or last restated).
    pub created: f64,
    /// MOOS time of its last share (0 before the first).
    pub last_sent: f64,
    /// Shares made.
    pub shares: u64,
}

impl Route {
    fn from_spec(spec: &OutputSpec, dest_name: String, now: f64) -> Route {
        Route {
            src_name: spec.src_name.clone(),
            dest_name,
            endpoint: spec.endpoint.clone(),
            frequency: spec.frequency,
            duration: spec.duration,
            max_shares: spec.max_shares,
            created: now,
            last_sent: 0.0,
            shares: 0,
        }
    }

    /// Whether the route shares a write made at `now` (see the module docs).
    ///
    /// ```
    /// use pshare::{config::parse_output, RouteTable};
    /// let mut t = RouteTable::default();
    /// for s in parse_output("X->h:1@2").unwrap() { t.add(&s, 0.0); }
    /// assert_eq!(t.route("X", "a", 10.0).len(), 1);
    /// assert_eq!(t.route("X", "a", 10.3).len(), 0, "2 Hz: too soon");
    /// assert_eq!(t.route("X", "a", 10.5).len(), 1);
    /// ```
    pub fn is_active(&self, now: f64) -> bool {
        let under_max = self.max_shares.is_none_or(|m| self.shares < u64::from(m));
        if self.duration == Some(0.0) && under_max {
            return true;
        }
        if let Some(d) = self.duration
            && now - self.created > d
        {
            return false;
        }
        if !under_max {
            return false;
        }
        !(self.frequency > 0.0 && now - self.last_sent < 1.0 / self.frequency)
    }

    /// Same share as `other` (pShare's route equality: endpoint, names).
    fn same(&self, other: &Route) -> bool {
        self.endpoint == other.endpoint
            && self.dest_name == other.dest_name
            && self.src_name == other.src_name
    }
}

/// What adding a share did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Added {
    /// A new named route: register for this variable.
    Named(String),
    /// A new wildcard route: register for this variable pattern (the app pattern is applied
    /// by [`RouteTable::route`]).
    Wildcard(String),
    /// An existing route restated: its limits and counters start afresh.
    Refreshed,
    /// A named route restated with `duration = 0`: it will share the variable's latest value
    /// once; the caller asks the DB for it again (pShare unregisters and registers).
    ResendLatest(String),
}

/// One datagram to send: the route's destination name and endpoint.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Send {
    /// The name the message carries out.
    pub dest_name: String,
    /// Where it goes.
    pub endpoint: Endpoint,
}

/// Every route of one pShare.
#[derive(Debug, Clone, Default)]
pub struct RouteTable {
    named: BTreeMap<String, Vec<Route>>,
    wildcard: BTreeMap<(String, String), Vec<Route>>,
}

/// True when `src_name` makes a wildcard route (`*`, `?` or an app part after `:`).
pub fn is_wildcard(src_name: &str) -> bool {
    src_name.contains(['*', '?', ':'])
}

impl RouteTable {
    /// Adds (or restates) a share at MOOS time `now`.
    pub fn add(&mut self, spec: &OutputSpec, now: f64) -> Added {
        if !is_wildcard(&spec.src_name) {
            let route = Route::from_spec(spec, spec.dest_name.clone(), now);
            let list = self.named.entry(spec.src_name.clone()).or_default();
            return match list.iter_mut().find(|r| r.same(&route)) {
                None => {
                    list.push(route);
                    Added::Named(spec.src_name.clone())
                }
                Some(existing) => {
                    let mut route = route;
                    let resend = spec.duration == Some(0.0);
                    if resend {
                        route.max_shares = Some(1);
                        route.duration = None;
                    }
                    *existing = route;
                    if resend {
                        Added::ResendLatest(spec.src_name.clone())
                    } else {
                        Added::Refreshed
                    }
                }
            };
        }
        let dest = if spec.dest_name.contains(['*', '?']) {
            String::new()
        } else {
            spec.dest_name.clone()
        };
        let mut route = Route::from_spec(spec, dest, now);
        let (var, app) = match spec.src_name.split_once(':') {
            Some((v, a)) if !a.is_empty() => (v.to_string(), a.to_string()),
            Some((v, _)) => (v.to_string(), "*".to_string()),
            None => (spec.src_name.clone(), "*".to_string()),
        };
        route.src_name = var.clone();
        let list = self.wildcard.entry((var.clone(), app)).or_default();
        match list.iter_mut().find(|r| r.same(&route)) {
            None => {
                list.push(route);
                Added::Wildcard(var)
            }
            Some(existing) => {
                *existing = route;
                Added::Refreshed
            }
        }
    }

    /// The datagrams a write of `key` by `source` at `now` makes; the routes taken count
    /// the share. Wildcard routes that match are first copied into `key`'s named routes.
    pub fn route(&mut self, key: &str, source: &str, now: f64) -> Vec<Send> {
        if !self.named.contains_key(key) {
            let mut made = Vec::new();
            for ((var, app), routes) in &self.wildcard {
                if !(wildcard_match(app.as_bytes(), source.as_bytes())
                    && wildcard_match(var.as_bytes(), key.as_bytes()))
                {
                    continue;
                }
                for r in routes {
                    let mut copy = r.clone();
                    copy.src_name = key.to_string();
                    copy.dest_name = wildcard_dest(var, &r.dest_name, key);
                    made.push(copy);
                }
            }
            if made.is_empty() {
                return Vec::new();
            }
            self.named.insert(key.to_string(), made);
        }
        let Some(routes) = self.named.get_mut(key) else {
            return Vec::new();
        };
        let mut out = Vec::new();
        for r in routes.iter_mut().filter(|r| r.is_active(now)) {
            r.last_sent = now;
            r.shares += 1;
            out.push(Send {
                dest_name: r.dest_name.clone(),
                endpoint: r.endpoint.clone(),
            });
        }
        out
    }

    /// True when pShare registers for exactly `key` (its named routes): received messages
    /// of such names are not posted (the loop guard).
    pub fn registered_for(&self, key: &str) -> bool {
        self.named.contains_key(key)
    }

    /// The variables and patterns to register for: named routes, then wildcard patterns.
    pub fn registrations(&self) -> impl Iterator<Item = &str> {
        self.named
            .keys()
            .map(String::as_str)
            .chain(self.wildcard.keys().map(|(v, _)| v.as_str()))
    }

    /// Every named route, by variable.
    pub fn named(&self) -> impl Iterator<Item = (&str, &[Route])> {
        self.named.iter().map(|(k, v)| (k.as_str(), v.as_slice()))
    }

    /// Every wildcard route, by `(var_pattern, app_pattern)`.
    pub fn wildcards(&self) -> impl Iterator<Item = (&str, &str, &[Route])> {
        self.wildcard
            .iter()
            .map(|((v, a), r)| (v.as_str(), a.as_str(), r.as_slice()))
    }

    /// `PSHARE_OUTPUT_SUMMARY`: `VAR->dest:host:port & dest:host:port, VAR2->...`, a
    /// multicast route as `dest:group:port:multicast_N`.
    pub fn output_summary(&self, group: &str, base_port: u16) -> String {
        let mut s = String::new();
        for (i, (var, routes)) in self.named.iter().enumerate() {
            if i > 0 {
                s.push_str(", ");
            }
            s.push_str(var);
            s.push_str("->");
            for (j, r) in routes.iter().enumerate() {
                if j > 0 {
                    s.push_str(" & ");
                }
                s.push_str(&r.dest_name);
                s.push(':');
                s.push_str(&endpoint_address(&r.endpoint, group, base_port));
                if let Endpoint::Multicast(n) = r.endpoint {
                    s.push_str(&format!(":multicast_{n}"));
                }
            }
        }
        s
    }
}

/// `host:port` of an endpoint, a multicast channel as its group and port.
pub fn endpoint_address(e: &Endpoint, group: &str, base_port: u16) -> String {
    match e {
        Endpoint::Udp { host, port } => format!("{host}:{port}"),
        Endpoint::Multicast(n) => format!("{group}:{}", u32::from(base_port) + u32::from(*n)),
    }
}

/// The name a wildcard route sends `key` under: the caret's matched part, else the prefix
/// and the name.
fn wildcard_dest(var_pattern: &str, dest: &str, key: &str) -> String {
    if dest == "^" && var_pattern.matches('*').count() == 1 {
        if let Some(tail) = var_pattern.strip_prefix('*') {
            // `*X`: what comes before the first X.
            return key.split_once(tail).map_or(key, |(a, _)| a).to_string();
        }
        if let Some(head) = var_pattern.strip_suffix('*') {
            // `X*`: what comes after the first X.
            return key.split_once(head).map_or("", |(_, b)| b).to_string();
        }
        return String::new();
    }
    format!("{dest}{key}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn caret_takes_the_starred_part() {
        assert_eq!(wildcard_dest("*_X", "^", "A_X"), "A");
        assert_eq!(wildcard_dest("A_*", "^", "A_X"), "X");
        assert_eq!(wildcard_dest("*", "T", "donkey"), "Tdonkey");
        assert_eq!(wildcard_dest("X?", "", "XY"), "XY");
    }
}
