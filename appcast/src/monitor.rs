//! A uMAC-like monitor without I/O: the latest `APPCAST` of every node and app, the requests
//! a monitor posts, and the terminal pages it prints (the node list, one node's apps, one
//! app's report). `coug appcast` is this over a MOOS client.
//!
//! ```
//! use appcast::monitor::Monitor;
//! let mut m = Monitor::new("coug_appcast");
//! m.on_appcast("proc=pHelmIvP!@#iter=3!@#node=abe!@#iter=3!@#messages=Mode: SURVEYING!@#\
//!               !@#events_total=0!@#!@#run_warning_total=0!@#", 10.0);
//! assert_eq!(m.nodes(), vec!["abe".to_string()]);
//! assert!(m.page(None, None, 11.0).contains("abe"));
//! assert!(m.page(Some("abe"), Some("pHelmIvP"), 11.0).contains("Mode: SURVEYING"));
//! ```

use std::collections::BTreeMap;

use crate::appcast::AppCast;
use crate::casting::{APPCAST_REQ_VAR, node_request_var};
use crate::table::Table;

/// One app's latest appcast and when it came (MOOS time).
#[derive(Debug, Clone)]
pub struct Entry {
    /// The appcast.
    pub cast: AppCast,
    /// MOOS time it arrived.
    pub received: f64,
}

/// The latest appcast per (node, app).
#[derive(Debug, Clone)]
pub struct Monitor {
    key: String,
    casts: BTreeMap<(String, String), Entry>,
}

impl Monitor {
    /// A monitor whose requests carry `key=<key>`.
    pub fn new(key: &str) -> Self {
        Monitor {
            key: key.to_string(),
            casts: BTreeMap::new(),
        }
    }

    /// Takes an `APPCAST` value received at MOOS time `now`; returns the (node, app) it
    /// updated, or `None` for a value without a `proc=`.
    pub fn on_appcast(&mut self, value: &str, now: f64) -> Option<(String, String)> {
        let cast = AppCast::parse(value);
        if cast.proc_name().is_empty() {
            return None;
        }
        let key = (cast.node_name().to_string(), cast.proc_name().to_string());
        self.casts.insert(
            key.clone(),
            Entry {
                cast,
                received: now,
            },
        );
        Some(key)
    }

    /// The requests to post (every app of every node, 3 s, any threshold): `APPCAST_REQ`
    /// and one `APPCAST_REQ_<NODE>` per known node, as uMAC and pMarineViewer post them.
    pub fn requests(&self) -> Vec<(String, String)> {
        let value = format!("node=all,app=all,duration=3.0,key={},thresh=any", self.key);
        let mut out = vec![(APPCAST_REQ_VAR.to_string(), value.clone())];
        for n in self.nodes() {
            if !n.is_empty() {
                out.push((node_request_var(&n), value.clone()));
            }
        }
        out
    }

    /// The nodes seen, sorted.
    pub fn nodes(&self) -> Vec<String> {
        let mut v: Vec<String> = self.casts.keys().map(|(n, _)| n.clone()).collect();
        v.dedup();
        v
    }

    /// The latest appcast of `app` on `node`.
    pub fn get(&self, node: &str, app: &str) -> Option<&Entry> {
        self.casts.get(&(node.to_string(), app.to_string()))
    }

    /// A terminal page: with no node, the node table (apps, configuration and run warnings
    /// per node); with a node, its apps (iteration, warnings, age); with a node and an app,
    /// that app's report as uMAC prints it. `now` (MOOS time) dates the ages.
    pub fn page(&self, node: Option<&str>, app: Option<&str>, now: f64) -> String {
        let mut s = String::new();
        match (node, app) {
            (None, _) => {
                let mut t = Table::new(4);
                t.push("Node | AppCasts | CfgWarnings | RunWarnings");
                t.add_header_lines();
                for n in self.nodes() {
                    let apps = self.casts.iter().filter(|((k, _), _)| *k == n);
                    let (mut count, mut cfg, mut run) = (0usize, 0usize, 0u32);
                    for (_, e) in apps {
                        count += 1;
                        cfg += e.cast.config_warnings().len();
                        run += e.cast.run_warning_total();
                    }
                    let name = if n.is_empty() { "(none)" } else { n.as_str() };
                    t.push(name);
                    t.push(&count.to_string());
                    t.push(&cfg.to_string());
                    t.push(&run.to_string());
                }
                t.write(&mut s);
                s.push('\n');
            }
            (Some(n), None) => {
                let mut t = Table::new(5);
                t.push("App | Iter | CfgWarnings | RunWarnings | Age");
                t.add_header_lines();
                for ((_, a), e) in self.casts.iter().filter(|((k, _), _)| k == n) {
                    t.push(a);
                    t.push(&e.cast.iteration().to_string());
                    t.push(&e.cast.config_warnings().len().to_string());
                    t.push(&e.cast.run_warning_total().to_string());
                    t.push(&format!("{:.1}", (now - e.received).max(0.0)));
                }
                t.write(&mut s);
                s.push('\n');
            }
            (Some(n), Some(a)) => match self.get(n, a) {
                Some(e) => s.push_str(&e.cast.to_formatted_string(true)),
                None => s.push_str(&format!("no appcast from {a} on {n} yet\n")),
            },
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::AppCasting;

    fn cast(app: &str, node: &str, body: &str, warn: Option<&str>) -> String {
        let mut c = AppCasting::new(app);
        // No config block: one configuration warning per app.
        c.start_up(Some(node), None::<&[&str]>, 0.0, 1.0);
        if let Some(w) = warn {
            c.report_run_warning(w);
        }
        c.build(4, body, 1.0)
    }

    #[test]
    fn pages_list_nodes_apps_and_one_report() {
        let mut m = Monitor::new("k");
        m.on_appcast(&cast("pHelmIvP", "abe", "Mode: LOITER\n", None), 10.0);
        m.on_appcast(&cast("uSimMarineV22", "abe", "x\n", Some("slow")), 10.0);
        m.on_appcast(&cast("pHelmIvP", "ben", "Mode: RETURN\n", None), 11.0);
        assert_eq!(m.nodes(), ["abe", "ben"]);
        let nodes = m.page(None, None, 12.0);
        let abe = nodes.lines().find(|l| l.starts_with("abe")).unwrap();
        assert_eq!(
            abe.split_whitespace().collect::<Vec<_>>(),
            ["abe", "2", "2", "1"]
        );
        let apps = m.page(Some("abe"), None, 12.0);
        assert!(apps.contains("pHelmIvP"), "{apps}");
        assert!(apps.contains("uSimMarineV22"), "{apps}");
        assert!(!apps.contains("RETURN"));
        let one = m.page(Some("ben"), Some("pHelmIvP"), 12.0);
        assert!(one.contains("Mode: RETURN"), "{one}");
        // A newer cast replaces the older.
        m.on_appcast(&cast("pHelmIvP", "ben", "Mode: PARK\n", None), 13.0);
        assert!(
            m.page(Some("ben"), Some("pHelmIvP"), 13.0)
                .contains("Mode: PARK")
        );
        let req = m.requests();
        assert_eq!(req[0].0, "APPCAST_REQ");
        assert_eq!(req[0].1, "node=all,app=all,duration=3.0,key=k,thresh=any");
        assert_eq!(req[1].0, "APPCAST_REQ_ABE");
        assert_eq!(req.len(), 3);
        assert!(m.on_appcast("garbage", 1.0).is_none());
    }
}
