//! uFldNodeBroker and uFldShoreBroker: how the communities of a MOOS-IvP fleet find each
//! other and set up their pShare routes at run time (issue #16, point 5), so no mission
//! writes another community's address.
//!
//! The handshake, as MOOS-IvP's apps run it (facts from `uFldNodeBroker`,
//! `uFldShoreBroker` and `lib_ufield` at a2a9b716; the code is coug's own):
//!
//! 1. Each community knows its own host record ([`HostRecord`]: community, address,
//!    MOOSDB port, pShare input routes, time warp), from pHostInfo's `PHI_HOST_INFO`.
//! 2. A vehicle's uFldNodeBroker asks its pShare (`PSHARE_CMD = cmd=output,
//!    src_name=NODE_BROKER_PING_<i>,dest_name=NODE_BROKER_PING,route=<try_shore_host i>`)
//!    to carry its pings to every shore host it was told to try, and posts
//!    `NODE_BROKER_PING_<i>` (its record, `time=` and `key=<i>`) every 5 s, every 20 s once
//!    an acknowledgement came in the last 5 s.
//! 3. The shoreside's uFldShoreBroker, on a ping from a new community, adds the bridge
//!    `NODE_BROKER_ACK_$V -> NODE_BROKER_ACK` and, at growing intervals (5 s, then 3 s
//!    longer each time, back to 5 s when a node is new), posts a `PSHARE_CMD` per bridge
//!    and node to that node's input routes (`$V` the node's name upper-cased, `$v` as
//!    written, `$N` its index from 1), unless `PSHARE_OUTPUT_SUMMARY` shows pShare has it.
//!    Each iteration it posts `NODE_BROKER_ACK_<NAME>` (its own record, the node's
//!    `status`, `key`, and `id`) for every node heard in the last 10 s.
//! 4. The vehicle, on `NODE_BROKER_ACK` from another community, posts `NODE_PSHARE_VARS`
//!    and asks its pShare to bridge every configured variable to that shore host.
//!
//! `qbridge = FOO` on the shoreside is `bridge = src=FOO_ALL, alias=FOO` plus `bridge =
//! src=FOO_$V, alias=FOO`: a command posted as `FOO_ALL` reaches every vehicle as `FOO`.
//!
//! # coug's host record without pHostInfo
//!
//! coug has no pHostInfo. Each broker starts from a record of its own: the mission's
//! `Community`, `ServerPort` (`port_db`) and `MOOSTimeWarp` (`timewarp`, as pHostInfo
//! writes it), the address `host_ip` (a coug parameter, default `localhost`), and the input
//! routes its own pShare reports in `PSHARE_INPUT_SUMMARY` (reduced as pHostInfo reduces
//! them). A valid `PHI_HOST_INFO` from its own community (a real pHostInfo beside coug)
//! replaces that record for good. Within one lockstep `coug run` the routes the brokers set
//! up go through pShare's in-process route like static ones; in real time, over UDP. coug
//! opens no multicast socket, so only unicast `host:port` shore hosts carry pings.
//!
//! # Conformance with uFldNodeBroker
//!
//! | parameter / posting | coug |
//! |---|---|
//! | `try_shore_host = pshare_route=host:port` (several; invalid or duplicate: config warning) | done |
//! | `bridge = src=VAR[, alias=ALIAS]` (alias defaults to src; repeated pairs ignored) | done |
//! | `auto_bridge_realmcast` (REALMCAST, WATCHCAST, REALMCAST_CHANNELS), `auto_bridge_appcast` (APPCAST), `auto_bridge_pshare_vars` (NODE_PSHARE_VARS), default true | done |
//! | messaging policy: `NODE_MESSAGE_LOCAL->NODE_MESSAGE` and `MEDIATED_MESSAGE_LOCAL->MEDIATED_MESSAGE` exclusive | done |
//! | `host_ip` (coug only, default `localhost`) | the address of coug's own host record |
//! | mail `TRY_SHORE_HOST` (a shore host added at run time), `NODE_BROKER_ACK` (other community), `PHI_HOST_INFO` (own community) | done |
//! | mail `PSHARE_INPUT_SUMMARY` (coug only) | the own record's input routes until a `PHI_HOST_INFO` |
//! | `PSHARE_CMD`, `NODE_BROKER_PING_<i>`, `NODE_PSHARE_VARS` | done |
//! | `UFLDNODEBROKER_PID` | refused: a process id would make two lockstep runs log different bytes |
//! | `DB_CLIENTS` check of pMediator | open: never registered at a2a9b716 either (policy `auto` is never set) |
//!
//! # Conformance with uFldShoreBroker
//!
//! | parameter / posting | coug |
//! |---|---|
//! | `bridge = src=VAR[, alias=ALIAS]` (`$V`, `$v`, `$N` in src) | done |
//! | `qbridge = A, B` | done |
//! | `keyword` (a ping with another keyword gets `status=keyword_mismatch`) | done |
//! | `auto_bridge_realmcast` (qbridge REALMCAST_REQ), `auto_bridge_appcast` (qbridge APPCAST_REQ), `auto_bridge_mhash` (bridge MISSION_HASH), default true | done |
//! | `warning_on_stale` (default false: a node silent for 10 s is a run warning) | done |
//! | `try_vnode = route=host[:port]` (port 9200 by default) | done |
//! | `host_ip` (coug only, default `localhost`) | the address of coug's own host record |
//! | mail `NODE_BROKER_PING` (other community), `PSHARE_OUTPUT_SUMMARY`, `PHI_HOST_INFO` (own community) | done |
//! | mail `PSHARE_INPUT_SUMMARY` (coug only) | the own record's input routes until a `PHI_HOST_INFO` |
//! | `NODE_BROKER_ACK_<NAME>`, `NODE_BROKER_VACK`, `PSHARE_CMD`, `UFSB_NODE_COUNT` (on change, else every 30 s), `UFSB_QBRIDGE_VARS`, `UFSB_BRIDGE_VARS`, `TRY_SHORE_HOST` (every 10 s per try_vnode, its `PSHARE_CMD` every 30 s), `PSHARE_TEST` (the debugging trace a2a9b716 posts) | done |

mod host;
mod node;
mod shore;

pub use host::{HostRecord, iroutes_of_input_summary, is_valid_ip, is_valid_pshare_route};
pub use node::{NODE_BROKER, NodeBrokerApp};
pub use shore::{SHORE_BROKER, ShoreBrokerApp};

use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::ProcessConfig;

use crate::app::Mail;

/// The community's own host record: built from the mission until a `PHI_HOST_INFO` comes.
#[derive(Debug, Clone)]
struct OwnHost {
    record: HostRecord,
    from_phi: bool,
    ok_phis: u64,
    bad_phis: u64,
    changes: u64,
}

impl OwnHost {
    fn new(community: &str, host_ip: &str, port_db: u16, warp: f64) -> OwnHost {
        OwnHost {
            record: HostRecord {
                community: community.to_string(),
                hostip: host_ip.to_string(),
                port_db: port_db.to_string(),
                timewarp: moos_types::fmt::compact_string(warp, 1),
                ..HostRecord::default()
            },
            from_phi: false,
            ok_phis: 0,
            bad_phis: 0,
            changes: 0,
        }
    }

    /// The run's actual MOOSDB port and time warp (a real-time run, see
    /// [`crate::realtime::RunningDb`]) instead of the mission's.
    fn set_running(&mut self, db: &crate::realtime::RunningDb) {
        self.record.port_db = db.port.to_string();
        self.record.timewarp = moos_types::fmt::compact_string(db.warp, 1);
    }

    /// The run's MOOSDB as bound, if the run is a real-time one.
    fn running(
        shared: &crate::shared::Shared,
        community: &str,
    ) -> Option<crate::realtime::RunningDb> {
        shared
            .get::<crate::realtime::RunningDb>(&crate::realtime::RunningDb::key(community))
            .map(|db| *db)
    }

    /// True when `m` was written in this community.
    fn is_local(&self, m: &Mail) -> bool {
        *m.community == *self.record.community
    }

    /// A `PHI_HOST_INFO`; false when it is not a valid record.
    fn on_phi(&mut self, text: &str) -> bool {
        let Some(r) = HostRecord::parse(text) else {
            self.bad_phis += 1;
            return false;
        };
        self.ok_phis += 1;
        let o = &self.record;
        if (
            &o.community,
            &o.timewarp,
            &o.hostip,
            &o.port_db,
            &o.port_udp,
            &o.pshare_iroutes,
        ) != (
            &r.community,
            &r.timewarp,
            &r.hostip,
            &r.port_db,
            &r.port_udp,
            &r.pshare_iroutes,
        ) {
            self.changes += 1;
        }
        self.record = r;
        self.from_phi = true;
        true
    }

    /// A `PSHARE_INPUT_SUMMARY` of this community's pShare (ignored once pHostInfo spoke).
    fn on_input_summary(&mut self, text: &str) {
        if self.from_phi {
            return;
        }
        let routes = iroutes_of_input_summary(text).replace("localhost", &self.record.hostip);
        if routes != self.record.pshare_iroutes {
            self.record.port_udp.clear();
            self.record.set_iroutes(&routes);
        }
    }
}

/// A configuration warning at `key`'s line (the block's when absent).
fn warn(block: &ProcessConfig, line: Option<u32>, message: String) -> Diagnostic {
    let span = line
        .and_then(|l| block.entries.iter().find(|p| p.span.line == l))
        .map_or(&block.span, |p| &p.span);
    Diagnostic::line_warning(DiagnosticKind::AppSetting, span, message)
}

/// The `host_ip` parameter (coug only): an address MOOS-IvP's `isValidIPAddress` takes.
fn host_ip(value: &str) -> Option<String> {
    is_valid_ip(value).then(|| value.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::antler::BuiltInApp;
    use crate::app::{App, Post, Value};
    use crate::testing::block;

    fn mail_from(community: &str, key: &str, value: &str, time: f64) -> Mail {
        Mail {
            key: key.into(),
            value: Value::text(value),
            time,
            source: "x".into(),
            source_aux: Default::default(),
            community: community.into(),
        }
    }

    fn texts<'a>(out: &'a [Post], key: &str) -> Vec<&'a str> {
        out.iter()
            .filter(|p| &*p.key == key)
            .filter_map(|p| p.value.as_str())
            .collect()
    }

    fn node(community: &str) -> NodeBrokerApp {
        NodeBrokerApp::new(
            NODE_BROKER,
            block(
                "v.moos",
                "ProcessConfig = uFldNodeBroker\n{\n  try_shore_host = pshare_route=localhost:9300\n  \
                 bridge = src=NODE_REPORT_LOCAL, alias=NODE_REPORT\n  auto_bridge_realmcast = false\n  \
                 auto_bridge_appcast = false\n}\n",
            ),
            community,
            9001,
            1.0,
        )
    }

    fn shore(extra: &str) -> ShoreBrokerApp {
        ShoreBrokerApp::new(
            SHORE_BROKER,
            block(
                "s.moos",
                &format!(
                    "ProcessConfig = uFldShoreBroker\n{{\n  qbridge = DEPLOY\n  \
                     auto_bridge_realmcast = false\n  auto_bridge_appcast = false\n  \
                     auto_bridge_mhash = false\n{extra}}}\n"
                ),
            ),
            "shoreside",
            9000,
            1.0,
        )
    }

    /// The ping of `n` at `t` once its pShare reported its input route.
    fn ping(n: &mut NodeBrokerApp, t: f64) -> String {
        let mut out = Vec::new();
        n.on_mail(
            &[mail_from(
                "henry",
                "PSHARE_INPUT_SUMMARY",
                "localhost:9301",
                t,
            )],
            t,
            &mut out,
        )
        .unwrap();
        n.iterate(t, &mut out).unwrap();
        texts(&out, "NODE_BROKER_PING_0")[0].to_string()
    }

    #[test]
    fn a_ping_is_acknowledged_and_the_node_then_bridges_its_variables() {
        let mut n = node("henry");
        let mut out = Vec::new();
        n.on_startup(100.0, &mut out).unwrap();
        assert_eq!(
            texts(&out, "PSHARE_CMD"),
            [
                "cmd=output,src_name=NODE_BROKER_PING_0,dest_name=NODE_BROKER_PING,route=localhost:9300"
            ]
        );
        let p = ping(&mut n, 101.0);
        assert_eq!(
            p,
            "community=henry,hostip=localhost,port_db=9001,port_udp=9301,\
             pshare_iroutes=localhost:9301,timewarp=1,time=101.00,key=0"
        );
        let mut s = shore("");
        s.on_startup(100.0, &mut out).unwrap();
        out.clear();
        // Its own community's ping is not a node's.
        s.on_mail(
            &[mail_from("shoreside", "NODE_BROKER_PING", &p, 101.0)],
            101.0,
            &mut out,
        )
        .unwrap();
        assert!(s.nodes().is_empty());
        s.on_mail(
            &[mail_from("henry", "NODE_BROKER_PING", &p, 101.0)],
            101.0,
            &mut out,
        )
        .unwrap();
        assert_eq!(s.nodes(), ["henry"]);
        s.on_mail(
            &[mail_from(
                "shoreside",
                "PSHARE_INPUT_SUMMARY",
                "localhost:9300",
                101.0,
            )],
            101.0,
            &mut out,
        )
        .unwrap();
        s.iterate(101.5, &mut out).unwrap();
        let cmds = texts(&out, "PSHARE_CMD");
        assert_eq!(
            cmds,
            [
                "cmd=output,src_name=DEPLOY_ALL,dest_name=DEPLOY,route=localhost:9301",
                "cmd=output,src_name=DEPLOY_HENRY,dest_name=DEPLOY,route=localhost:9301",
                "cmd=output,src_name=NODE_BROKER_ACK_HENRY,dest_name=NODE_BROKER_ACK,route=localhost:9301",
            ]
        );
        let ack = texts(&out, "NODE_BROKER_ACK_HENRY")[0].to_string();
        assert_eq!(
            ack,
            "community=shoreside,hostip=localhost,port_db=9000,port_udp=9300,\
             pshare_iroutes=localhost:9300,timewarp=1,status=ok,key=0,id=0"
        );
        let count: Vec<Option<f64>> = out
            .iter()
            .filter(|p| &*p.key == "UFSB_NODE_COUNT")
            .map(|p| p.value.as_f64())
            .collect();
        assert_eq!(count, [Some(1.0)]);
        // The node takes the acknowledgement (from another community) and bridges.
        out.clear();
        n.on_mail(
            &[mail_from("henry", "NODE_BROKER_ACK", &ack, 102.0)],
            102.0,
            &mut out,
        )
        .unwrap();
        assert_eq!(n.acks(), (0, 0), "its own community's ack is not taken");
        n.on_mail(
            &[mail_from("shoreside", "NODE_BROKER_ACK", &ack, 102.0)],
            102.0,
            &mut out,
        )
        .unwrap();
        assert_eq!(n.acks(), (1, 0));
        assert_eq!(
            texts(&out, "NODE_PSHARE_VARS"),
            ["NODE_REPORT,NODE_PSHARE_VARS"]
        );
        assert_eq!(
            texts(&out, "PSHARE_CMD"),
            [
                "cmd=output,src_name=NODE_REPORT_LOCAL,dest_name=NODE_REPORT,route=localhost:9300",
                "cmd=output,src_name=NODE_PSHARE_VARS,dest_name=NODE_PSHARE_VARS,route=localhost:9300",
            ]
        );
        // Acknowledged (within 5 s): pings every 20 s now, and the ping routes are no longer
        // restated.
        n.on_mail(
            &[mail_from("shoreside", "NODE_BROKER_ACK", &ack, 108.0)],
            108.0,
            &mut out,
        )
        .unwrap();
        out.clear();
        n.iterate(110.0, &mut out).unwrap();
        assert!(texts(&out, "NODE_BROKER_PING_0").is_empty());
        assert!(texts(&out, "PSHARE_CMD").is_empty());
        // A stale node gets no more acknowledgements.
        out.clear();
        s.iterate(111.5, &mut out).unwrap();
        assert!(texts(&out, "NODE_BROKER_ACK_HENRY").is_empty());
    }

    #[test]
    fn in_real_time_the_records_carry_the_db_as_bound() {
        let shared = crate::shared::Shared::new();
        let db = |port, warp| move || crate::realtime::RunningDb { port, warp };
        shared.get_or_insert_with(&crate::realtime::RunningDb::key("henry"), db(41234, 4.0));
        shared.get_or_insert_with(
            &crate::realtime::RunningDb::key("shoreside"),
            db(41000, 4.0),
        );
        // Another community's entry is not this one's.
        let other = node("ike").with_shared(&shared);
        assert_eq!(other.host_record().port_db, "9001");
        let mut n = node("henry").with_shared(&shared);
        let p = ping(&mut n, 101.0);
        assert!(
            p.starts_with("community=henry,hostip=localhost,port_db=41234,port_udp=9301,"),
            "{p}"
        );
        assert!(p.contains(",timewarp=4,"), "{p}");
        let s = shore("").with_shared(&shared);
        assert_eq!(s.host_record().port_db, "41000");
        // A node at the mission's warp of 1 differs from this run's 4.
        let slow = p.replace(",timewarp=4,", ",timewarp=1,");
        for (text, status) in [(&p, ",status=ok,"), (&slow, ",status=timewarp (4!=1),")] {
            let mut s = shore("").with_shared(&shared);
            let mut out = Vec::new();
            s.on_mail(
                &[mail_from("henry", "NODE_BROKER_PING", text, 101.0)],
                101.0,
                &mut out,
            )
            .unwrap();
            s.iterate(101.5, &mut out).unwrap();
            let ack = texts(&out, "NODE_BROKER_ACK_HENRY")[0].to_string();
            assert!(ack.contains(status), "{status} in {ack}");
            assert!(ack.contains(",port_db=41000,"), "{ack}");
        }
    }

    #[test]
    fn mismatched_pings_and_bad_acks_are_flagged() {
        let mut n = node("henry");
        let p = ping(&mut n, 100.0);
        let mut s = shore("  keyword = lemon\n");
        let mut out = Vec::new();
        s.on_mail(
            &[mail_from(
                "shoreside",
                "PSHARE_INPUT_SUMMARY",
                "localhost:9300",
                1.0,
            )],
            1.0,
            &mut out,
        )
        .unwrap();
        let other_warp = p.replace("timewarp=1", "timewarp=2");
        s.on_mail(
            &[mail_from("henry", "NODE_BROKER_PING", &other_warp, 1.0)],
            1.0,
            &mut out,
        )
        .unwrap();
        s.on_mail(
            &[mail_from(
                "henry",
                "NODE_BROKER_PING",
                "community=henry",
                1.0,
            )],
            1.0,
            &mut out,
        )
        .unwrap();
        s.iterate(1.5, &mut out).unwrap();
        // The node has no keyword: a shoreside with one says so.
        let ack = texts(&out, "NODE_BROKER_ACK_HENRY")[0].to_string();
        assert!(ack.contains(",status=keyword_mismatch,key=0,"), "{ack}");
        let mut out = Vec::new();
        for bad in [
            ack.replace("key=0", "key=7"),
            ack.replace(",key=0", ""),
            "community=shoreside".to_string(),
        ] {
            n.on_mail(
                &[mail_from("shoreside", "NODE_BROKER_ACK", &bad, 2.0)],
                2.0,
                &mut out,
            )
            .unwrap();
        }
        assert_eq!(n.acks(), (0, 3));
        assert!(texts(&out, "PSHARE_CMD").is_empty());
    }

    #[test]
    fn try_vnode_sends_the_shore_route_and_a_node_adds_it() {
        let mut s = shore("  try_vnode = route=127.0.0.1:9301\n  try_vnode = route=127.0.0.1\n");
        assert!(s.warnings().is_empty(), "{:?}", s.warnings());
        let mut out = Vec::new();
        s.on_mail(
            &[mail_from(
                "shoreside",
                "PSHARE_INPUT_SUMMARY",
                "localhost:9300",
                50.0,
            )],
            50.0,
            &mut out,
        )
        .unwrap();
        s.iterate(50.0, &mut out).unwrap();
        assert_eq!(
            texts(&out, "PSHARE_CMD"),
            [
                "cmd=output,src_name=TRY_SHORE_HOST,dest_name=TRY_SHORE_HOST,route=127.0.0.1:9301",
                "cmd=output,src_name=TRY_SHORE_HOST,dest_name=TRY_SHORE_HOST,route=127.0.0.1:9200",
            ]
        );
        let tries = texts(&out, "TRY_SHORE_HOST");
        assert_eq!(tries, ["pshare_route=localhost:9300"; 2]);
        let mut n = NodeBrokerApp::new(
            NODE_BROKER,
            block("v.moos", "ProcessConfig = uFldNodeBroker\n{\n}\n"),
            "henry",
            9001,
            1.0,
        );
        let mut out = Vec::new();
        n.on_mail(
            &[mail_from("shoreside", "TRY_SHORE_HOST", tries[0], 50.5)],
            50.5,
            &mut out,
        )
        .unwrap();
        n.on_mail(
            &[mail_from("shoreside", "TRY_SHORE_HOST", tries[0], 50.5)],
            50.5,
            &mut out,
        )
        .unwrap();
        assert_eq!(n.shore_routes(), ["localhost:9300"], "a repeat is ignored");
        // ... but its ping route is restated, as a2a9b716 does.
        assert_eq!(texts(&out, "PSHARE_CMD").len(), 2);
    }
}
