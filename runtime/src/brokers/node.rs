//! uFldNodeBroker: a vehicle's side of the handshake (see the module docs of
//! [`crate::brokers`]).

use std::fmt::Write as _;

use mission::diagnostic::Diagnostic;
use mission::moos::ProcessConfig;
use moos_types::text::{is_number, parse_string, set_boolean_on_string};
use vehicle::config::is_generic_app_key;

use super::host::{HostRecord, bite, is_valid_ip, is_valid_pshare_route};
use super::{OwnHost, host_ip, warn};
use crate::antler::BuiltInApp;
use crate::app::{App, AppResult, Mail, Post, Subscription};
use crate::appcasting::{AppcastLayer, Note};

/// The MOOS name of the app.
pub const NODE_BROKER: &str = "uFldNodeBroker";

/// One shore host to try and what it answered.
#[derive(Debug, Clone, Default)]
struct Shore {
    route: String,
    community: String,
    pings_sent: u64,
    pings_ack: u64,
    ipaddr: String,
    timewarp: String,
    bridged: bool,
}

/// The `uFldNodeBroker` app.
pub struct NodeBrokerApp {
    name: String,
    block: ProcessConfig,
    warnings: Vec<Diagnostic>,
    appcast: AppcastLayer,
    own: OwnHost,
    shores: Vec<Shore>,
    try_host_ips: Vec<String>,
    bridges: Vec<(String, String)>,
    policy: &'static str,
    pshare_cmds: u64,
    pings_posted: u64,
    ok_acks: u64,
    bad_acks: u64,
    ok_ack_time: f64,
    ping_sent_time: f64,
}

/// Why a `try_shore_host` value is not taken.
enum TryError {
    Unhandled,
    Warn(String),
}

impl BuiltInApp for NodeBrokerApp {
    /// Bad lines of the block.
    fn warnings(&self) -> &[Diagnostic] {
        &self.warnings
    }

    /// The broker takes `Community` and `MOOSTimeWarp` when it is made (its handshake needs
    /// them): nothing changes here.
    fn with_appcast_globals(self, _community: Option<&str>, _warp: f64) -> Self {
        self
    }
}

impl NodeBrokerApp {
    /// The app `name` of community `community` (its MOOSDB on `port_db`, time warp `warp`)
    /// from its `block`; bad lines are [`NodeBrokerApp::warnings`].
    pub fn new(name: &str, block: ProcessConfig, community: &str, port_db: u16, warp: f64) -> Self {
        let mut app = NodeBrokerApp {
            name: name.to_string(),
            appcast: AppcastLayer::with_globals(name, Some(&block), Some(community), warp),
            own: OwnHost::new(community, "localhost", port_db, warp),
            block: block.clone(),
            warnings: Vec::new(),
            shores: Vec::new(),
            try_host_ips: Vec::new(),
            bridges: Vec::new(),
            policy: "",
            pshare_cmds: 0,
            pings_posted: 0,
            ok_acks: 0,
            bad_acks: 0,
            ok_ack_time: 0.0,
            ping_sent_time: 0.0,
        };
        let (mut realmcast, mut appcast, mut pshare_vars) = (true, true, true);
        for p in &block.entries {
            let key = p.key.trim().to_ascii_lowercase();
            let value = p.value.trim();
            let line = Some(p.span.line);
            let unhandled = |why: &str| {
                warn(
                    &block,
                    line,
                    format!(
                        "{NODE_BROKER}: unhandled config line: {} = {value}{why}",
                        p.key.trim()
                    ),
                )
            };
            let handled = match key.as_str() {
                "try_shore_host" => match app.try_shore_host(value, true) {
                    Ok(()) => true,
                    Err(TryError::Unhandled) => false,
                    Err(TryError::Warn(w)) => {
                        app.warnings.push(unhandled(&format!(" ({w})")));
                        continue;
                    }
                },
                "bridge" => match app.bridge(value) {
                    Ok(ok) => ok,
                    Err(w) => {
                        app.warnings.push(unhandled(&format!(" ({w})")));
                        continue;
                    }
                },
                "auto_bridge_realmcast" | "auto_bridge_appcast" | "auto_bridge_pshare_vars" => {
                    let slot = match key.as_str() {
                        "auto_bridge_realmcast" => &mut realmcast,
                        "auto_bridge_appcast" => &mut appcast,
                        _ => &mut pshare_vars,
                    };
                    set_boolean_on_string(*slot, value)
                        .map(|b| *slot = b)
                        .is_some()
                }
                "host_ip" => match host_ip(value) {
                    Some(ip) => {
                        app.own.record.hostip = ip;
                        true
                    }
                    None => false,
                },
                k => is_generic_app_key(k),
            };
            if !handled {
                app.warnings.push(unhandled(""));
            }
        }
        if realmcast {
            for v in ["REALMCAST", "WATCHCAST", "REALMCAST_CHANNELS"] {
                let _ = app.bridge(&format!("src={v}"));
            }
        }
        if appcast {
            let _ = app.bridge("src=APPCAST");
        }
        if pshare_vars {
            let _ = app.bridge("src=NODE_PSHARE_VARS");
        }
        app.appcast =
            AppcastLayer::with_config_warnings(name, &block, Some(community), warp, &app.warnings);
        app
    }

    /// In a real-time run (`shared` holds the community's [`crate::realtime::RunningDb`]),
    /// its host record carries the MOOSDB's actual port and the run's time warp rather than
    /// the mission's `ServerPort` and `MOOSTimeWarp` (a port of 0 is the system's pick);
    /// otherwise nothing changes.
    pub fn with_shared(mut self, shared: &crate::shared::Shared) -> Self {
        if let Some(db) = OwnHost::running(shared, &self.own.record.community) {
            self.own.set_running(&db);
            self.appcast = AppcastLayer::with_config_warnings(
                &self.name,
                &self.block,
                Some(&self.own.record.community),
                db.warp,
                &self.warnings,
            );
        }
        self
    }

    /// The bridges `(src, alias)` it asks for once a shore host answers, in order.
    pub fn bridges(&self) -> &[(String, String)] {
        &self.bridges
    }

    /// The shore hosts to try (their pShare routes), in order.
    pub fn shore_routes(&self) -> Vec<&str> {
        self.shores.iter().map(|s| s.route.as_str()).collect()
    }

    /// Acknowledgements taken and refused.
    pub fn acks(&self) -> (u64, u64) {
        (self.ok_acks, self.bad_acks)
    }

    /// The host record its pings carry (before the time stamp).
    pub fn host_record(&self) -> &HostRecord {
        &self.own.record
    }

    fn try_shore_host(&mut self, value: &str, dup_warn: bool) -> Result<(), TryError> {
        let mut route = "";
        for f in parse_string(value, ',') {
            match bite(f) {
                ("pshare_route", r) => route = r,
                _ => return Err(TryError::Unhandled),
            }
        }
        if !is_valid_pshare_route(route) {
            return Err(TryError::Warn(format!("invalid pshare_route {route:?}")));
        }
        if self.shores.iter().any(|s| s.route == route) {
            return if dup_warn {
                Err(TryError::Warn(format!("duplicate try_shore_host: {route}")))
            } else {
                Ok(())
            };
        }
        self.shores.push(Shore {
            route: route.to_string(),
            ..Shore::default()
        });
        if let Some((ip, _)) = route.split_once(':')
            && !route.starts_with("localhost:")
            && is_valid_ip(ip)
        {
            self.try_host_ips.push(ip.to_string());
        }
        Ok(())
    }

    /// `bridge = src=VAR, alias=ALIAS`: `Ok(false)` when unusable, `Err` for a policy clash.
    fn bridge(&mut self, value: &str) -> Result<bool, String> {
        let (mut src, mut alias) = ("", "");
        for f in parse_string(value, ',') {
            match bite(f) {
                (k, v) if k.eq_ignore_ascii_case("src") => src = v,
                (k, v) if k.eq_ignore_ascii_case("alias") => alias = v,
                _ => {}
            }
        }
        if src.is_empty() || src.contains(char::is_whitespace) {
            return Ok(false);
        }
        if alias.is_empty() || alias.contains(char::is_whitespace) {
            alias = src;
        }
        // A pair already there is ignored (each name checked on its own, as a2a9b716 does).
        if self.bridges.iter().any(|(s, _)| s == src)
            && self.bridges.iter().any(|(_, a)| a == alias)
        {
            return Ok(true);
        }
        match (src, alias) {
            ("NODE_MESSAGE_LOCAL", "NODE_MESSAGE") if self.policy == "mediated" => {
                return Err("conflicted messaging policy".into());
            }
            ("NODE_MESSAGE_LOCAL", "NODE_MESSAGE") => self.policy = "unmediated",
            ("MEDIATED_MESSAGE_LOCAL", "MEDIATED_MESSAGE") if self.policy == "unmediated" => {
                return Err("conflicted messaging policy".into());
            }
            ("MEDIATED_MESSAGE_LOCAL", "MEDIATED_MESSAGE") => self.policy = "mediated",
            _ => {}
        }
        self.bridges.push((src.to_string(), alias.to_string()));
        Ok(true)
    }

    fn pshare_cmd(&mut self, src: &str, dest: &str, route: &str, out: &mut Vec<Post>) {
        if (src == "NODE_MESSAGE_LOCAL" && self.policy != "unmediated")
            || (src == "MEDIATED_MESSAGE_LOCAL" && self.policy != "mediated")
        {
            return;
        }
        out.push(Post::text(
            "PSHARE_CMD",
            format!("cmd=output,src_name={src},dest_name={dest},route={route}"),
        ));
        self.pshare_cmds += 1;
    }

    fn ping_bridges(&mut self, only_latest: bool, out: &mut Vec<Post>) {
        let from = if only_latest {
            self.shores.len().saturating_sub(1)
        } else {
            0
        };
        for i in from..self.shores.len() {
            let route = self.shores[i].route.clone();
            self.pshare_cmd(
                &format!("NODE_BROKER_PING_{i}"),
                "NODE_BROKER_PING",
                &route,
                out,
            );
        }
    }

    fn user_bridges(&mut self, out: &mut Vec<Post>) {
        for k in 0..self.shores.len() {
            if self.shores[k].bridged || self.shores[k].pings_ack == 0 {
                continue;
            }
            self.shores[k].bridged = true;
            let route = self.shores[k].route.clone();
            for (src, alias) in self.bridges.clone() {
                self.pshare_cmd(&src, &alias, &route, out);
            }
        }
    }

    fn send_ping(&mut self, now: f64, out: &mut Vec<Post>) {
        if self.own.record.pshare_iroutes.is_empty() || self.own.record.timewarp.is_empty() {
            return;
        }
        let mut stamp = String::new();
        moos_types::fmt::fixed(&mut stamp, now, 2);
        self.own.record.timestamp = stamp;
        let msg = self.own.record.spec();
        for i in 0..self.shores.len() {
            // Every 5 s, every 20 s while acknowledgements keep coming.
            let thresh = if now - self.ok_ack_time > 5.0 {
                5.0
            } else {
                20.0
            };
            if now - self.ping_sent_time > thresh {
                out.push(Post::text(
                    format!("NODE_BROKER_PING_{i}"),
                    format!("{msg},key={i}"),
                ));
                self.shores[i].pings_sent += 1;
                self.pings_posted += 1;
                self.ping_sent_time = now;
            }
        }
    }

    fn on_ack(&mut self, text: &str, now: f64, out: &mut Vec<Post>) {
        let r = HostRecord::parse(text).unwrap_or_default();
        let ix = r.key.parse::<usize>().ok().filter(|_| is_number(&r.key));
        let Some(ix) = ix.filter(|i| *i < self.shores.len()) else {
            self.bad_acks += 1;
            let w = format!(
                "NODE_BROKER_ACK recvd from {} w/ null or bad key, for now.",
                r.hostip
            );
            self.appcast.note(Note::Warning(w), now);
            return;
        };
        let s = &mut self.shores[ix];
        s.community = r.community;
        s.ipaddr = r.hostip;
        s.timewarp = r.timewarp;
        s.pings_ack += 1;
        let aliases: Vec<&str> = self.bridges.iter().map(|(_, a)| a.as_str()).collect();
        out.push(Post::text("NODE_PSHARE_VARS", aliases.join(",")));
        self.ok_acks += 1;
        self.ok_ack_time = now;
        self.user_bridges(out);
    }

    fn body(&self, out: &mut String) {
        let r = &self.own.record;
        let _ = writeln!(
            out,
            "  Total OK  PHI_HOST_INFO    received: {}",
            self.own.ok_phis
        );
        let _ = writeln!(
            out,
            "  Total BAD PHI_HOST_INFO    received: {}",
            self.own.bad_phis
        );
        let _ = writeln!(
            out,
            "  Total HOST_INFO changes    received: {}",
            self.own.changes
        );
        let _ = writeln!(
            out,
            "  Total          PSHARE_CMD    posted: {}",
            self.pshare_cmds
        );
        let _ = writeln!(
            out,
            "  Total BAD NODE_BROKER_ACK  received: {}",
            self.bad_acks
        );
        let _ = writeln!(
            out,
            "\nVehicle node: {} at {} (MOOSDB {}, warp {})",
            r.community, r.hostip, r.port_db, r.timewarp
        );
        let _ = writeln!(out, "  IRoutes: {}", r.pshare_iroutes);
        let _ = writeln!(out, "  TryHost IPs: {}", self.try_host_ips.join(","));
        let _ = writeln!(
            out,
            "\nShore hosts (community, route, pings sent, acked, IP, warp):"
        );
        for s in &self.shores {
            let _ = writeln!(
                out,
                "  {} {} {} {} {} {}",
                s.community, s.route, s.pings_sent, s.pings_ack, s.ipaddr, s.timewarp
            );
        }
        let phase = |done: bool| if done { "(Y)" } else { "(N)" };
        let _ = writeln!(
            out,
            "\n Phase 1: {} host information known (iroutes)",
            phase(!r.pshare_iroutes.is_empty())
        );
        let _ = writeln!(
            out,
            " Phase 2: {} valid TryHosts ({})",
            phase(!self.shores.is_empty()),
            self.shores.len()
        );
        let _ = writeln!(
            out,
            " Phase 3: {} NODE_BROKER_PINGs sent",
            phase(self.pings_posted > 0)
        );
        let _ = writeln!(
            out,
            " Phase 4: {} a valid NODE_BROKER_ACK received",
            phase(self.ok_acks > 0)
        );
        let _ = writeln!(
            out,
            " Phase 5: {} user variables bridged",
            phase(self.shores.iter().any(|s| s.bridged))
        );
    }
}

impl App for NodeBrokerApp {
    fn name(&self) -> &str {
        &self.name
    }

    fn process_config(&self) -> Option<&ProcessConfig> {
        Some(&self.block)
    }

    fn subscriptions(&self) -> Vec<Subscription> {
        AppcastLayer::subscriptions()
            .chain(
                [
                    "NODE_BROKER_ACK",
                    "PHI_HOST_INFO",
                    "TRY_SHORE_HOST",
                    "PSHARE_INPUT_SUMMARY",
                ]
                .into_iter()
                .map(Subscription::var),
            )
            .collect()
    }

    fn on_startup(&mut self, now: f64, out: &mut Vec<Post>) -> AppResult {
        self.appcast.on_startup(now);
        self.ping_bridges(false, out);
        Ok(())
    }

    fn on_mail(&mut self, mail: &[Mail], now: f64, out: &mut Vec<Post>) -> AppResult {
        for m in mail {
            if !self.appcast.take_mail(m) {
                continue;
            }
            let text = m.value.as_str().unwrap_or("");
            let local = self.own.is_local(m);
            match &*m.key {
                "PHI_HOST_INFO" if local => {
                    if !self.own.on_phi(text) {
                        let w = format!("Invalid PHI_HOST_INFO recd: {text}");
                        self.appcast.note(Note::Warning(w), now);
                    }
                }
                "PSHARE_INPUT_SUMMARY" if local => self.own.on_input_summary(text),
                "TRY_SHORE_HOST" => {
                    if self.try_shore_host(text, false).is_ok() {
                        self.ping_bridges(true, out);
                    } else {
                        let w = format!("Invalid incoming TRY_SHORE_HOST:{text}");
                        self.appcast.note(Note::Warning(w), now);
                    }
                }
                "NODE_BROKER_ACK" if !local => self.on_ack(text, now, out),
                k => {
                    let w = format!("Unhandled Mail: {k}");
                    self.appcast.note(Note::Warning(w), now);
                }
            }
        }
        Ok(())
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> AppResult {
        let tick = self.app_tick();
        self.appcast.begin(now, tick, out);
        if self.shores.iter().all(|s| s.pings_ack == 0) {
            self.ping_bridges(false, out);
        }
        self.send_ping(now, out);
        if self.appcast.end_due(now, tick, out) {
            let mut b = String::new();
            self.body(&mut b);
            self.appcast.post_cast(now, out, &b);
        }
        Ok(())
    }
}
