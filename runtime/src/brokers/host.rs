//! The host record the brokers exchange (lib_ufield's `HostRecord` format): a community's
//! name, address, MOOSDB port, pShare input routes and time warp as `key=value` fields
//! separated by commas, e.g.
//! `community=henry,hostip=localhost,port_db=9001,port_udp=9301,pshare_iroutes=localhost:9301,timewarp=1,time=10.25,key=0`.

use moos_types::text::{is_number, parse_string};

/// One community's host record.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct HostRecord {
    /// `community` (or `vname`).
    pub community: String,
    /// `hostip`.
    pub hostip: String,
    /// `hostip_alts`.
    pub hostip_alts: String,
    /// `port_db`.
    pub port_db: String,
    /// `port_udp` (taken from the first input route when not given).
    pub port_udp: String,
    /// `pshare_iroutes`: the pShare input routes, `&`-separated.
    pub pshare_iroutes: String,
    /// `keyword`.
    pub keyword: String,
    /// `key`: which of a vehicle's shore hosts a ping went to (its index).
    pub key: String,
    /// `timewarp`.
    pub timewarp: String,
    /// `status` (`ok`, `keyword_mismatch`, `timewarp (A!=B)`).
    pub status: String,
    /// `time`: the MOOS time the record was sent at.
    pub timestamp: String,
}

/// MOOS-IvP `isValidIPAddress`: `localhost` or four numbers from 0 to 255.
pub fn is_valid_ip(s: &str) -> bool {
    if s.eq_ignore_ascii_case("localhost") {
        return true;
    }
    let parts = parse_string(s, '.');
    parts.len() == 4
        && parts.iter().all(|p| {
            let p = p.trim();
            is_number(p) && p.parse::<f64>().is_ok_and(|v| (0.0..=255.0).contains(&v))
        })
}

/// MOOS-IvP `isValidPShareRoute` (the form uFldNodeBroker checks): `host:port` with a
/// valid address and a number, or `multicast_N`.
pub fn is_valid_pshare_route(route: &str) -> bool {
    let parts = parse_string(route, ':');
    match parts.as_slice() {
        [one] => one
            .strip_prefix("multicast_")
            .is_some_and(|n| !n.contains('_') && is_number(n)),
        [host, port] => is_valid_ip(host) && is_number(port),
        _ => false,
    }
}

/// `left = right` of a field, both trimmed (MOOS `biteStringX`); a field without `=` is all
/// left.
pub(crate) fn bite(field: &str) -> (&str, &str) {
    match field.split_once('=') {
        Some((l, r)) => (l.trim(), r.trim()),
        None => (field.trim(), ""),
    }
}

impl HostRecord {
    /// Reads a record (`string2HostRecord`); `None` when it is not [`HostRecord::valid`].
    ///
    /// ```
    /// use runtime::brokers::HostRecord;
    /// let r = HostRecord::parse("community=ike,hostip=10.0.0.2,port_db=9002,pshare_iroutes=10.0.0.2:9302,key=1").unwrap();
    /// assert_eq!((r.port_udp.as_str(), r.key.as_str()), ("9302", "1"));
    /// assert!(HostRecord::parse("community=ike,hostip=here,port_db=9002").is_none());
    /// ```
    pub fn parse(s: &str) -> Option<HostRecord> {
        let mut r = HostRecord::default();
        for f in parse_string(s, ',') {
            let (k, v) = bite(f);
            let v = v.to_string();
            match k.to_ascii_lowercase().as_str() {
                "community" | "vname" => r.community = v,
                "hostip" => r.hostip = v,
                "port_db" => r.port_db = v,
                "port_udp" => r.port_udp = v,
                "pshare_iroutes" => r.set_iroutes(&v),
                "keyword" => r.keyword = v,
                "key" => r.key = v,
                "hostip_alts" => r.hostip_alts = v,
                "timewarp" => r.timewarp = v,
                "status" => r.status = v,
                "time" => r.timestamp = v,
                _ => {}
            }
        }
        r.valid().then_some(r)
    }

    /// Sets the input routes; `port_udp`, when not set yet, becomes what follows the first
    /// `:` if that is a number (one route `host:port`).
    pub fn set_iroutes(&mut self, routes: &str) {
        self.pshare_iroutes = routes.to_string();
        if self.port_udp.is_empty()
            && let Some((_, port)) = routes.split_once(':')
            && is_number(port)
        {
            self.port_udp = port.to_string();
        }
    }

    /// A community, a valid address and a numeric MOOSDB port.
    pub fn valid(&self) -> bool {
        !self.community.is_empty() && is_valid_ip(&self.hostip) && is_number(&self.port_db)
    }

    /// The short form: community, address, ports, routes, keyword, other addresses.
    pub fn spec_terse(&self) -> String {
        let mut s = format!("community={}", self.community);
        for (k, v) in [
            ("hostip", &self.hostip),
            ("port_db", &self.port_db),
            ("port_udp", &self.port_udp),
            ("pshare_iroutes", &self.pshare_iroutes),
            ("keyword", &self.keyword),
        ] {
            if !v.is_empty() {
                s.push_str(&format!(",{k}={v}"));
            }
        }
        if !self.hostip_alts.is_empty() {
            let alts = self
                .hostip_alts
                .replace(&format!("{},", self.hostip), "")
                .replace(&self.hostip, "");
            s.push_str(&format!(",hostip_alts={alts}"));
        }
        s
    }

    /// The full form: [`HostRecord::spec_terse`], then `timewarp`, `status`, `time` and
    /// `key` when set. As lib_ufield at a2a9b716 writes it, `status=` carries the time
    /// warp's value (kept for the same bytes on the wire).
    pub fn spec(&self) -> String {
        let mut s = self.spec_terse();
        if !self.timewarp.is_empty() {
            s.push_str(&format!(",timewarp={}", self.timewarp));
        }
        if !self.status.is_empty() {
            s.push_str(&format!(",status={}", self.timewarp));
        }
        if !self.timestamp.is_empty() {
            s.push_str(&format!(",time={}", self.timestamp));
        }
        if !self.key.is_empty() {
            s.push_str(&format!(",key={}", self.key));
        }
        s
    }
}

/// pHostInfo's reduction of `PSHARE_INPUT_SUMMARY` (`localhost:9301,224.1.1.11:24469:multicast_9`)
/// to `pshare_iroutes` (`localhost:9301&multicast_9`): `host:port` (or `host:port:udp`) stays
/// `host:port`, a third part other than `udp` stands for the route; anything else is dropped.
pub fn iroutes_of_input_summary(summary: &str) -> String {
    let mut routes: Vec<String> = Vec::new();
    for r in parse_string(summary, ',') {
        let parts = parse_string(r, ':');
        let route = match parts.as_slice() {
            [host, port] if is_valid_ip(host) && is_number(port) => format!("{host}:{port}"),
            [host, port, proto] if is_valid_ip(host) && is_number(port) => {
                if *proto == "udp" {
                    format!("{host}:{port}")
                } else {
                    (*proto).to_string()
                }
            }
            _ => continue,
        };
        routes.push(route);
    }
    routes.join("&")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_record_reads_back_what_it_writes() {
        let mut r = HostRecord {
            community: "henry".into(),
            hostip: "localhost".into(),
            port_db: "9001".into(),
            timewarp: "1".into(),
            timestamp: "12.50".into(),
            ..HostRecord::default()
        };
        r.set_iroutes("localhost:9301");
        assert_eq!(r.port_udp, "9301");
        let s = r.spec();
        assert_eq!(
            s,
            "community=henry,hostip=localhost,port_db=9001,port_udp=9301,\
             pshare_iroutes=localhost:9301,timewarp=1,time=12.50"
        );
        assert_eq!(HostRecord::parse(&s), Some(r));
        // Two routes: no single port to take.
        let mut two = HostRecord::default();
        two.set_iroutes("localhost:9301&multicast_9");
        assert_eq!(two.port_udp, "");
    }

    #[test]
    fn invalid_records_and_routes_are_refused() {
        assert!(HostRecord::parse("hostip=localhost,port_db=9000").is_none());
        assert!(HostRecord::parse("community=a,hostip=1.2.3.256,port_db=9000").is_none());
        assert!(HostRecord::parse("community=a,hostip=1.2.3.4,port_db=x").is_none());
        assert!(HostRecord::parse("vname=a,hostip=1.2.3.4,port_db=9000").is_some());
        assert!(is_valid_pshare_route("localhost:9300"));
        assert!(is_valid_pshare_route("192.168.1.5:9300"));
        assert!(is_valid_pshare_route("multicast_9"));
        assert!(!is_valid_pshare_route("multicast_x"));
        assert!(!is_valid_pshare_route("localhost"));
        assert!(!is_valid_pshare_route("localhost:9300:udp"));
        assert!(!is_valid_pshare_route("there:9300"));
    }

    #[test]
    fn the_input_summary_becomes_iroutes_as_phostinfo_reduces_it() {
        assert_eq!(
            iroutes_of_input_summary("localhost:9301,224.1.1.11:24469:multicast_9,junk"),
            "localhost:9301&multicast_9"
        );
        assert_eq!(
            iroutes_of_input_summary("127.0.0.1:9301:udp"),
            "127.0.0.1:9301"
        );
        assert_eq!(iroutes_of_input_summary(""), "");
    }
}
