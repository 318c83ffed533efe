//! Configuration forms of pShare's readme and `Share.cpp`, bad lines with their line, and
//! routing decisions (rename, wildcard, caret, frequency, duration, max shares).

use pshare::config::{Command, ConfigError, Endpoint, parse_command, parse_input, parse_output};
use pshare::{Added, Config, RouteTable};

fn udp(host: &str, port: u16) -> Endpoint {
    Endpoint::Udp {
        host: host.into(),
        port,
    }
}

fn table(lines: &[&str], now: f64) -> RouteTable {
    let (c, bad) =
        Config::from_params(lines.iter().enumerate().map(|(i, l)| (i + 1, "output", *l)));
    assert!(bad.is_empty(), "{bad:?}");
    let mut t = RouteTable::default();
    for s in &c.outputs {
        t.add(s, now);
    }
    t
}

fn sends(t: &mut RouteTable, key: &str, src: &str, now: f64) -> Vec<String> {
    t.route(key, src, now)
        .into_iter()
        .map(|s| format!("{}@{}", s.dest_name, s.endpoint))
        .collect()
}

#[test]
fn short_forms() {
    let s = parse_output("X->192.168.0.4:10000").unwrap();
    assert_eq!(
        (s[0].src_name.as_str(), s[0].dest_name.as_str()),
        ("X", "X")
    );
    assert_eq!(s[0].endpoint, udp("192.168.0.4", 10000));
    let s = parse_output("X->Y:192.168.0.4:10000").unwrap();
    assert_eq!(s[0].dest_name, "Y");
    let s = parse_output("X->192.168.0.4:10000 & Y:192.168.0.4:20000").unwrap();
    assert_eq!(s.len(), 2);
    assert_eq!(
        (s[1].dest_name.as_str(), &s[1].endpoint),
        ("Y", &udp("192.168.0.4", 20000))
    );
    let s = parse_output("X->Y:multicast_7 & Z:multicast_3 & multicast_1").unwrap();
    let got: Vec<_> = s
        .iter()
        .map(|o| (o.dest_name.as_str(), o.endpoint.clone()))
        .collect();
    assert_eq!(
        got,
        vec![
            ("Y", Endpoint::Multicast(7)),
            ("Z", Endpoint::Multicast(3)),
            ("X", Endpoint::Multicast(1))
        ]
    );
    // `@` is a frequency in Hz; a non-number reads as 0 (every write).
    let s = parse_output("X->Y:165.45.3.61:9000@0.5 & Z:multicast_8@fast").unwrap();
    assert_eq!((s[0].frequency, s[1].frequency), (0.5, 0.0));
    // Wildcards with an app part.
    let s = parse_output("*time:camera_*->multicast_7").unwrap();
    assert_eq!(s[0].src_name, "*time:camera_*");
}

#[test]
fn long_forms() {
    let s = parse_output("src_name=W, dest_name=W2, route=multicast_8, max_shares = 2").unwrap();
    assert_eq!((s[0].dest_name.as_str(), s[0].max_shares), ("W2", Some(2)));
    let s = parse_output("src_name=W,dest_name=W2,route=multicast_8, duration = 60").unwrap();
    assert_eq!((s[0].duration, s[0].max_shares), (Some(60.0), None));
    let s = parse_output("src_name=Y, route=localhost:9832, frequency=4").unwrap();
    assert_eq!((s[0].dest_name.as_str(), s[0].frequency), ("Y", 4.0));
    let s =
        parse_output("src_name =X,dest_name=Z,route=161.4.5.6:9000&multicast_21&localhost:9832")
            .unwrap();
    assert_eq!(s.len(), 3);
    assert_eq!(s[2].endpoint, udp("localhost", 9832));
    // -1 means "no limit", as in the C++ defaults.
    let s = parse_output("src_name=A,route=h:1,max_shares=-1,duration=-1").unwrap();
    assert_eq!((s[0].max_shares, s[0].duration), (None, None));

    let i = parse_input("route=multicast_21&localhost:9833&multicast_3").unwrap();
    assert_eq!(
        i.endpoints,
        vec![
            Endpoint::Multicast(21),
            udp("localhost", 9833),
            Endpoint::Multicast(3)
        ]
    );
    assert!(i.white_list.is_empty());
    let i = parse_input("route = localhost:9200, white_list = foo* & ?bar").unwrap();
    assert_eq!(i.white_list, vec!["foo*", "?bar"]);
    // Port 0 on an input: the system picks one.
    assert_eq!(
        parse_input("route=127.0.0.1:0").unwrap().endpoints,
        vec![udp("127.0.0.1", 0)]
    );
}

#[test]
fn block_settings_and_bad_lines_with_their_line() {
    let (c, bad) = Config::from_params([
        (10, "Output", "src_name=X,dest_name=Z,route=multicast_8"),
        (11, "output", "X>192.168.0.4:10000"),
        (12, "input", "localhost:9000"),
        (13, "OUTPUT", "X->a:b:c:d"),
        (14, "output", "src_name=X,route=host:99999"),
        (15, "output", "dest_name=Y,route=host:9"),
        (16, "input", "route=multicast_300"),
        (17, "output", "src_name=X,route=h:1,duration=soon"),
        (18, "multicast_base_port", "30000"),
        (19, "multicast_address", "239.1.1.1"),
        (20, "multicast_base_port", "-4"),
        (21, "AppTick", "10"),
        (22, "output", "X->host:0"),
        (23, "verbose", "true"),
    ]);
    assert_eq!(c.outputs.len(), 1);
    assert_eq!(
        (c.multicast_base_port, c.multicast_address.as_str()),
        (30000, "239.1.1.1")
    );
    assert!(c.verbose);
    let got: Vec<(usize, ConfigError)> = bad.into_iter().map(|b| (b.line, b.error)).collect();
    assert_eq!(
        got,
        vec![
            (11, ConfigError::NoArrow("X>192.168.0.4:10000".into())),
            (12, ConfigError::MissingField("route")),
            (13, ConfigError::BadShortRoute("a:b:c:d".into())),
            (14, ConfigError::BadPort("99999".into())),
            (15, ConfigError::MissingField("src_name")),
            (16, ConfigError::BadChannel("300".into())),
            (
                17,
                ConfigError::BadNumber {
                    field: "duration",
                    value: "soon".into()
                }
            ),
            (20, ConfigError::BadPort("-4".into())),
            (22, ConfigError::BadPort("0".into())),
        ]
    );
}

#[test]
fn commands() {
    let Command::Output(s) =
        parse_command("cmd = Output , src_name = X?, route = localhost:9021").unwrap()
    else {
        panic!("not an output")
    };
    assert_eq!(s[0].src_name, "X?");
    let Command::Input(i) = parse_command("cmd=input,route=127.0.0.1:9100").unwrap() else {
        panic!("not an input")
    };
    assert_eq!(i.endpoints, vec![udp("127.0.0.1", 9100)]);
    assert_eq!(
        parse_command("cmd=delete,src_name=X,route=h:1"),
        Err(ConfigError::UnknownCommand("delete".into()))
    );
}

#[test]
fn named_routes_rename() {
    let mut t = table(
        &["NAV_X->REMOTE_NAV_X:127.0.0.1:9201 & 127.0.0.1:9202"],
        0.0,
    );
    assert_eq!(
        sends(&mut t, "NAV_X", "sim", 1.0),
        ["REMOTE_NAV_X@127.0.0.1:9201", "NAV_X@127.0.0.1:9202"]
    );
    assert!(sends(&mut t, "NAV_Y", "sim", 1.0).is_empty());
    assert!(t.registered_for("NAV_X"));
    assert!(!t.registered_for("REMOTE_NAV_X"));
    assert_eq!(
        t.output_summary("224.1.1.11", 24460),
        "NAV_X->REMOTE_NAV_X:127.0.0.1:9201 & NAV_X:127.0.0.1:9202"
    );
}

#[test]
fn wildcard_routes_prefix_caret_and_app_patterns() {
    let mut t = table(
        &[
            "src_name=NAV_*, route=127.0.0.1:9201",
            "*->T:127.0.0.1:9202",
            "src_name=Q?:procA, route=127.0.0.1:9203",
            "*_X->^:127.0.0.1:9204",
        ],
        0.0,
    );
    assert_eq!(
        t.registrations().collect::<Vec<_>>(),
        vec!["*", "*_X", "NAV_*", "Q?"]
    );
    assert_eq!(
        sends(&mut t, "NAV_X", "sim", 1.0),
        [
            "TNAV_X@127.0.0.1:9202",
            "NAV@127.0.0.1:9204",
            "NAV_X@127.0.0.1:9201"
        ]
    );
    assert_eq!(
        sends(&mut t, "A_X", "sim", 1.0),
        ["TA_X@127.0.0.1:9202", "A@127.0.0.1:9204"]
    );
    // The app pattern is checked against the writer.
    assert_eq!(sends(&mut t, "QZ", "procB", 1.0), ["TQZ@127.0.0.1:9202"]);
    assert_eq!(
        sends(&mut t, "QY", "procA", 1.0),
        ["TQY@127.0.0.1:9202", "QY@127.0.0.1:9203"]
    );
    // Once copied into the named routes, the variable goes out on them.
    assert!(t.registered_for("NAV_X"));
    assert_eq!(sends(&mut t, "NAV_X", "other", 2.0).len(), 3);
}

#[test]
fn a_variable_with_named_routes_is_not_matched_by_wildcards() {
    let mut t = table(&["X->127.0.0.1:9201", "*->W:127.0.0.1:9202"], 0.0);
    assert_eq!(sends(&mut t, "X", "a", 1.0), ["X@127.0.0.1:9201"]);
}

#[test]
fn frequency_limits_shares() {
    let mut t = table(&["X->127.0.0.1:9201@1"], 0.0);
    let mut sent = Vec::new();
    for i in 0..40 {
        let now = 100.0 + f64::from(i) * 0.25;
        if !t.route("X", "a", now).is_empty() {
            sent.push(now);
        }
    }
    assert_eq!(
        sent,
        vec![
            100.0, 101.0, 102.0, 103.0, 104.0, 105.0, 106.0, 107.0, 108.0, 109.0
        ]
    );
}

#[test]
fn duration_and_max_shares() {
    let mut t = table(
        &[
            "src_name=A,route=127.0.0.1:1,duration=10",
            "src_name=B,route=127.0.0.1:1,max_shares=2",
        ],
        50.0,
    );
    assert_eq!(t.route("A", "x", 60.0).len(), 1);
    assert!(
        t.route("A", "x", 60.5).is_empty(),
        "10 s after its creation"
    );
    assert_eq!(t.route("B", "x", 51.0).len(), 1);
    assert_eq!(t.route("B", "x", 52.0).len(), 1);
    assert!(t.route("B", "x", 53.0).is_empty());
    // Restating a share starts its limits afresh.
    let (c, _) = Config::from_params([(1, "output", "src_name=B,route=127.0.0.1:1,max_shares=1")]);
    assert_eq!(t.add(&c.outputs[0], 60.0), Added::Refreshed);
    assert_eq!(t.route("B", "x", 61.0).len(), 1);
    assert!(t.route("B", "x", 62.0).is_empty());
    // duration=0 restated: the latest value once.
    let (c, _) = Config::from_params([(1, "output", "src_name=B,route=127.0.0.1:1,duration=0")]);
    assert_eq!(t.add(&c.outputs[0], 70.0), Added::ResendLatest("B".into()));
    assert_eq!(t.route("B", "x", 70.0).len(), 1);
    assert!(t.route("B", "x", 71.0).is_empty());
}
