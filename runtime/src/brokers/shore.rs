//! uFldShoreBroker: the shoreside's side of the handshake (see the module docs of
//! [`crate::brokers`]).

use std::collections::{BTreeSet, HashMap, HashSet};
use std::fmt::Write as _;

use mission::diagnostic::Diagnostic;
use mission::moos::ProcessConfig;
use moos_types::text::{atof, is_number, parse_string, set_boolean_on_string};
use vehicle::config::is_generic_app_key;

use super::host::{HostRecord, bite, is_valid_ip};
use super::{OwnHost, host_ip, warn};
use crate::antler::BuiltInApp;
use crate::app::{App, AppResult, Mail, Post, Subscription};
use crate::appcasting::{AppcastLayer, Note};

/// The MOOS name of the app.
pub const SHORE_BROKER: &str = "uFldShoreBroker";

/// Seconds without a ping after which a node is stale (and gets no more acknowledgements).
const STALE_AFTER: f64 = 10.0;

/// One vehicle node heard.
#[derive(Debug, Clone)]
struct Node {
    record: HostRecord,
    total_skew: f64,
    last: f64,
    stale: bool,
    pings: u64,
}

/// The `uFldShoreBroker` app.
pub struct ShoreBrokerApp {
    name: String,
    block: ProcessConfig,
    warnings: Vec<Diagnostic>,
    appcast: AppcastLayer,
    own: OwnHost,
    keyword: String,
    warning_on_stale: bool,
    time_warp: String,
    bridges: Vec<(String, String)>,
    bridge_vars: BTreeSet<String>,
    qbridge_vars: BTreeSet<String>,
    try_vnodes: Vec<String>,
    nodes: Vec<Node>,
    pshares: HashMap<String, HashSet<String>>,
    cmd_interval: f64,
    last_cmd: f64,
    prev_count: usize,
    prev_count_time: f64,
    last_vnode_cmds: f64,
    last_vnode_posts: f64,
    pings: u64,
    acks_posted: u64,
    cmds_posted: u64,
    tests_posted: u64,
}

impl BuiltInApp for ShoreBrokerApp {
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

impl ShoreBrokerApp {
    /// The app `name` of community `community` (its MOOSDB on `port_db`, time warp `warp`)
    /// from its `block`; bad lines are [`ShoreBrokerApp::warnings`].
    pub fn new(name: &str, block: ProcessConfig, community: &str, port_db: u16, warp: f64) -> Self {
        let mut app = ShoreBrokerApp {
            name: name.to_string(),
            block: block.clone(),
            warnings: Vec::new(),
            appcast: AppcastLayer::with_globals(name, Some(&block), Some(community), warp),
            own: OwnHost::new(community, "localhost", port_db, warp),
            keyword: String::new(),
            warning_on_stale: false,
            time_warp: moos_types::fmt::compact_string(warp, 5),
            bridges: Vec::new(),
            bridge_vars: BTreeSet::new(),
            qbridge_vars: BTreeSet::new(),
            try_vnodes: Vec::new(),
            nodes: Vec::new(),
            pshares: HashMap::new(),
            cmd_interval: 5.0,
            last_cmd: 0.0,
            prev_count: 0,
            prev_count_time: 0.0,
            last_vnode_cmds: 0.0,
            last_vnode_posts: 0.0,
            pings: 0,
            acks_posted: 0,
            cmds_posted: 0,
            tests_posted: 0,
        };
        let (mut realmcast, mut appcast, mut mhash) = (true, true, true);
        for p in &block.entries {
            let key = p.key.trim().to_ascii_lowercase();
            let value = p.value.trim();
            let line = Some(p.span.line);
            let mut problems = Vec::new();
            let handled = match key.as_str() {
                "bridge" => {
                    problems = app.bridge(value);
                    true
                }
                "qbridge" => {
                    problems = app.qbridge(value);
                    true
                }
                "keyword" => {
                    app.keyword = value.to_string();
                    true
                }
                "auto_bridge_realmcast"
                | "auto_bridge_appcast"
                | "auto_bridge_mhash"
                | "warning_on_stale" => {
                    let slot = match key.as_str() {
                        "auto_bridge_realmcast" => &mut realmcast,
                        "auto_bridge_appcast" => &mut appcast,
                        "auto_bridge_mhash" => &mut mhash,
                        _ => &mut app.warning_on_stale,
                    };
                    set_boolean_on_string(*slot, value)
                        .map(|b| *slot = b)
                        .is_some()
                }
                "try_vnode" => match app.try_vnode(value) {
                    Ok(()) => true,
                    Err(None) => false,
                    Err(Some(w)) => {
                        problems.push(w);
                        false
                    }
                },
                "host_ip" => match host_ip(value) {
                    Some(ip) => {
                        app.own.record.hostip = ip;
                        true
                    }
                    None => false,
                },
                k => is_generic_app_key(k),
            };
            for w in problems {
                app.warnings
                    .push(warn(&block, line, format!("{SHORE_BROKER}: {w}")));
            }
            if !handled {
                app.warnings.push(warn(
                    &block,
                    line,
                    format!(
                        "{SHORE_BROKER}: unhandled config line: {} = {value}",
                        p.key.trim()
                    ),
                ));
            }
        }
        if realmcast {
            app.qbridge("REALMCAST_REQ");
        }
        if appcast {
            app.qbridge("APPCAST_REQ");
        }
        if mhash {
            app.bridge("src=MISSION_HASH");
        }
        app.appcast =
            AppcastLayer::with_config_warnings(name, &block, Some(community), warp, &app.warnings);
        app
    }

    /// In a real-time run (`shared` holds the community's [`crate::realtime::RunningDb`]),
    /// its host record carries the MOOSDB's actual port and the run's time warp, which is
    /// also the warp the nodes' pings are compared with; otherwise nothing changes.
    pub fn with_shared(mut self, shared: &crate::shared::Shared) -> Self {
        if let Some(db) = OwnHost::running(shared, &self.own.record.community) {
            self.own.set_running(&db);
            self.time_warp = moos_types::fmt::compact_string(db.warp, 5);
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

    /// The bridges `(src, alias)` made for every node, in order (`$V`, `$v`, `$N` unexpanded).
    pub fn bridges(&self) -> &[(String, String)] {
        &self.bridges
    }

    /// The nodes heard so far, by community, in the order they were first heard.
    pub fn nodes(&self) -> Vec<&str> {
        self.nodes
            .iter()
            .map(|n| n.record.community.as_str())
            .collect()
    }

    /// The host record its acknowledgements carry.
    pub fn host_record(&self) -> &HostRecord {
        &self.own.record
    }

    /// `bridge = src=VAR[, alias=ALIAS]`; the problems found.
    fn bridge(&mut self, value: &str) -> Vec<String> {
        let mut problems = Vec::new();
        let (mut src, mut alias) = ("", "");
        for f in parse_string(value, ',') {
            match bite(f) {
                (k, v) if k.eq_ignore_ascii_case("src") => src = v,
                (k, v) if k.eq_ignore_ascii_case("alias") => alias = v,
                (k, _) => problems.push(format!(
                    "BRIDGE config with unhandled param: {}",
                    k.to_ascii_lowercase()
                )),
            }
        }
        if src.is_empty() {
            problems.push("BRIDGE config empty src field".into());
            return problems;
        }
        if alias.is_empty() {
            alias = src;
        }
        self.bridge_vars.insert(src.to_string());
        self.add_bridge(src, alias);
        problems
    }

    /// `qbridge = A, B`: `A_ALL -> A` and `A_$V -> A` for each.
    fn qbridge(&mut self, value: &str) -> Vec<String> {
        let mut problems = Vec::new();
        for v in parse_string(value, ',') {
            let v = v.trim();
            if v.contains('=') {
                problems.push(format!("Invalid QBRIDGE component: {v}"));
                continue;
            }
            self.qbridge_vars.insert(v.to_string());
            self.add_bridge(&format!("{v}_ALL"), v);
            self.add_bridge(&format!("{v}_$V"), v);
        }
        problems
    }

    fn add_bridge(&mut self, src: &str, alias: &str) {
        // Each name checked on its own, as a2a9b716 does.
        if self.bridges.iter().any(|(s, _)| s == src)
            && self.bridges.iter().any(|(_, a)| a == alias)
        {
            return;
        }
        self.bridges.push((src.to_string(), alias.to_string()));
    }

    /// `try_vnode = route=host[:port]`: `Err(None)` unusable, `Err(Some)` a duplicate.
    fn try_vnode(&mut self, value: &str) -> Result<(), Option<String>> {
        let (mut ip, mut port) = (String::new(), String::new());
        for f in parse_string(value, ',') {
            match bite(f) {
                ("route", v) => {
                    let (h, p) = v.split_once(':').unwrap_or((v, ""));
                    ip = h.trim().to_string();
                    port = if p.trim().is_empty() {
                        "9200".to_string()
                    } else {
                        p.trim().to_string()
                    };
                }
                _ => return Err(None),
            }
        }
        if !is_valid_ip(&ip) || !is_number(&port) {
            return Err(None);
        }
        let route = format!("{ip}:{port}");
        if self.try_vnodes.contains(&route) {
            return Err(Some(format!("Duplicate vnode route:{route}")));
        }
        self.try_vnodes.push(route);
        Ok(())
    }

    fn on_ping(&mut self, text: &str, now: f64) {
        self.pings += 1;
        let Some(mut r) = HostRecord::parse(text) else {
            let w = "Invalid Incoming NODE_BROKER_PING".to_string();
            self.appcast.note(Note::Warning(w.clone()), now);
            self.appcast.note(Note::Event(w), now);
            return;
        };
        let mut status = "ok".to_string();
        if self.time_warp != r.timewarp {
            status = format!("timewarp ({}!={})", self.time_warp, r.timewarp);
            self.appcast.note(Note::Warning(status.clone()), now);
        }
        if !self.keyword.is_empty() && self.keyword != r.keyword {
            status = "keyword_mismatch".into();
        }
        r.status = status.clone();
        let skew = now - atof(&r.timestamp);
        if r.hostip != self.own.record.hostip {
            let routes = r.pshare_iroutes.replace("localhost", &r.hostip);
            r.set_iroutes(&routes);
        }
        if let Some(n) = self
            .nodes
            .iter_mut()
            .find(|n| n.record.community == r.community)
        {
            n.last = now;
            n.total_skew += skew;
            n.pings += 1;
            n.record.status = status;
            return;
        }
        self.bridge("src=NODE_BROKER_ACK_$V, alias=NODE_BROKER_ACK");
        self.cmd_interval = 5.0;
        let e = format!("New node discovered: {}", r.community);
        self.appcast.note(Note::Event(e), now);
        self.nodes.push(Node {
            record: r,
            total_skew: skew,
            last: now,
            stale: false,
            pings: 1,
        });
    }

    /// `PSHARE_OUTPUT_SUMMARY`: the shares pShare already has, so none is asked twice.
    fn on_output_summary(&mut self, text: &str) {
        for share in parse_string(text, ',') {
            let share = share.trim();
            let (src, dests) = share.split_once("->").unwrap_or((share, ""));
            for d in parse_string(dests, '&') {
                self.pshares
                    .entry(src.to_string())
                    .or_default()
                    .insert(d.trim().to_string());
            }
        }
    }

    fn bridge_requests(&mut self, now: f64, out: &mut Vec<Post>) {
        if now - self.last_cmd < self.cmd_interval {
            return;
        }
        self.last_cmd = now;
        self.cmd_interval += 3.0;
        for i in 0..self.nodes.len() {
            let record = self.nodes[i].record.clone();
            for (src, alias) in self.bridges.clone() {
                self.bridge_request(&src, &record, &alias, i + 1, now, out);
            }
        }
    }

    fn bridge_request(
        &mut self,
        src: &str,
        record: &HostRecord,
        alias: &str,
        index: usize,
        now: f64,
        out: &mut Vec<Post>,
    ) {
        if !record.valid() {
            let w = "Failed to make bridge request. Invalid Host Record".to_string();
            self.appcast.note(Note::Warning(w), now);
            return;
        }
        let src = if src.contains("$V") {
            src.replace("$V", &record.community.to_ascii_uppercase())
        } else if src.contains("$v") {
            src.replace("$v", &record.community)
        } else {
            src.replace("$N", &index.to_string())
        };
        let routes = &record.pshare_iroutes;
        let post = format!("cmd=output,src_name={src},dest_name={alias},route={routes}");
        let dest = format!("{alias}:{routes}");
        let needed = !self.pshares.get(&src).is_some_and(|d| d.contains(&dest));
        out.push(Post::text("PSHARE_TEST", self.tests_posted.to_string()));
        out.push(Post::text("PSHARE_TEST", format!("{src}->{dest}")));
        out.push(Post::text("PSHARE_TEST", format!("needed={needed}")));
        self.tests_posted += 1;
        if needed {
            out.push(Post::text("PSHARE_CMD", post.clone()));
        }
        if self.bridge_vars.insert(src) {
            let vars: Vec<&str> = self.bridge_vars.iter().map(String::as_str).collect();
            out.push(Post::text("UFSB_BRIDGE_VARS", vars.join(",")));
        }
        self.appcast
            .note(Note::Event(format!("PSHARE_CMD:{post}")), now);
        self.cmds_posted += 1;
    }

    fn send_acks(&mut self, now: f64, out: &mut Vec<Post>) {
        if !self.own.record.valid() {
            return;
        }
        let spec = self.own.record.spec();
        for n in &self.nodes {
            if now - n.last >= STALE_AFTER {
                continue;
            }
            let mut value = format!("{spec},status={}", n.record.status);
            if !n.record.key.is_empty() {
                value.push_str(&format!(",key={}", n.record.key));
            }
            value.push_str(&format!(",id={}", self.acks_posted));
            out.push(Post::text(
                format!(
                    "NODE_BROKER_ACK_{}",
                    n.record.community.to_ascii_uppercase()
                ),
                value,
            ));
            out.push(Post::text("NODE_BROKER_VACK", n.record.community.clone()));
        }
        self.acks_posted += 1;
    }

    fn check_stale(&mut self, now: f64) {
        for i in 0..self.nodes.len() {
            let stale = now - self.nodes[i].last > STALE_AFTER;
            if stale == self.nodes[i].stale {
                continue;
            }
            self.nodes[i].stale = stale;
            if self.warning_on_stale {
                let w = format!("Node {} is stale.", self.nodes[i].record.community);
                let note = if stale {
                    Note::Warning(w)
                } else {
                    Note::Retract(w)
                };
                self.appcast.note(note, now);
            }
        }
    }

    fn node_count(&mut self, now: f64, out: &mut Vec<Post>) {
        let n = self.nodes.len();
        if n == self.prev_count && now - self.prev_count_time <= 30.0 {
            return;
        }
        out.push(Post::double("UFSB_NODE_COUNT", n as f64));
        self.prev_count = n;
        self.prev_count_time = now;
    }

    fn try_vnodes(&mut self, now: f64, out: &mut Vec<Post>) {
        if now - self.last_vnode_cmds > 30.0 {
            self.last_vnode_cmds = now;
            for v in &self.try_vnodes {
                out.push(Post::text(
                    "PSHARE_CMD",
                    format!(
                        "cmd=output,src_name=TRY_SHORE_HOST,dest_name=TRY_SHORE_HOST,route={v}"
                    ),
                ));
            }
        }
        if now - self.last_vnode_posts > 10.0 {
            self.last_vnode_posts = now;
            let r = &self.own.record;
            if !r.hostip.is_empty() && !r.port_udp.is_empty() {
                for _ in &self.try_vnodes {
                    out.push(Post::text(
                        "TRY_SHORE_HOST",
                        format!("pshare_route={}:{}", r.hostip, r.port_udp),
                    ));
                }
            }
        }
    }

    fn body(&self, now: f64, out: &mut String) {
        let r = &self.own.record;
        let _ = writeln!(
            out,
            " Total PHI_HOST_INFO    received: {}",
            self.own.ok_phis + self.own.bad_phis
        );
        let _ = writeln!(out, " Total NODE_BROKER_PING received: {}", self.pings);
        let _ = writeln!(
            out,
            " Total NODE_BROKER_ACK    posted: {}",
            self.acks_posted
        );
        let _ = writeln!(
            out,
            " Total PSHARE_CMD         posted: {}",
            self.cmds_posted
        );
        let _ = writeln!(
            out,
            "\nShoreside node: {} at {} (MOOSDB {}, warp {})",
            r.community, r.hostip, r.port_db, r.timewarp
        );
        let _ = writeln!(out, "  IRoutes: {}", r.pshare_iroutes);
        let _ = writeln!(
            out,
            "\nVehicle nodes (name, IP, status, elapsed, input routes, skew):"
        );
        for n in &self.nodes {
            let mut elapsed = String::new();
            moos_types::fmt::fixed(&mut elapsed, now - n.last, 1);
            let mut skew = String::new();
            moos_types::fmt::fixed(&mut skew, n.total_skew / n.pings as f64, 4);
            let _ = writeln!(
                out,
                "  {} {} {} {elapsed} {} {skew}",
                n.record.community, n.record.hostip, n.record.status, n.record.pshare_iroutes
            );
        }
    }
}

impl App for ShoreBrokerApp {
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
                    "NODE_BROKER_PING",
                    "PHI_HOST_INFO",
                    "PSHARE_OUTPUT_SUMMARY",
                    "PSHARE_INPUT_SUMMARY",
                ]
                .into_iter()
                .map(Subscription::var),
            )
            .collect()
    }

    fn on_startup(&mut self, now: f64, out: &mut Vec<Post>) -> AppResult {
        self.appcast.on_startup(now);
        let vars: Vec<&str> = self.qbridge_vars.iter().map(String::as_str).collect();
        out.push(Post::text("UFSB_QBRIDGE_VARS", vars.join(",")));
        Ok(())
    }

    fn on_mail(&mut self, mail: &[Mail], now: f64, _out: &mut Vec<Post>) -> AppResult {
        for m in mail {
            if !self.appcast.take_mail(m) {
                continue;
            }
            let text = m.value.as_str().unwrap_or("");
            let local = self.own.is_local(m);
            match &*m.key {
                "NODE_BROKER_PING" if !local => self.on_ping(text, now),
                "PSHARE_OUTPUT_SUMMARY" => self.on_output_summary(text),
                "PHI_HOST_INFO" if local => {
                    self.own.on_phi(text);
                }
                "PSHARE_INPUT_SUMMARY" if local => self.own.on_input_summary(text),
                k => {
                    let w = format!("Unhandled mail: {k}");
                    self.appcast.note(Note::Warning(w), now);
                }
            }
        }
        Ok(())
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> AppResult {
        let tick = self.app_tick();
        self.appcast.begin(now, tick, out);
        self.bridge_requests(now, out);
        self.send_acks(now, out);
        self.check_stale(now);
        self.node_count(now, out);
        self.try_vnodes(now, out);
        if self.appcast.end_due(now, tick, out) {
            let mut b = String::new();
            self.body(now, &mut b);
            self.appcast.post_cast(now, out, &b);
        }
        Ok(())
    }
}
