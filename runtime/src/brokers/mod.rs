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
