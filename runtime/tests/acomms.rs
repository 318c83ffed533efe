//! pAcomms and uSimModem in process: a base and two vehicles, three "communities" of two apps
//! each (the mail between the two apps of a community routed by hand, as a MOOSDB would), one
//! run-wide `Shared` holding the acoustic channel, driven on a virtual clock at 10 Hz.

use mission::moos::{ProcessConfig, parse_moos};
use mission::source::SourceMap;
use runtime::acomms_apps::{AcommsApp, SharedNet, SimModemApp};
use runtime::antler::BuiltInApp;
use runtime::app::{App, Mail, Post, Value};
use runtime::shared::Shared;

const KEY: &str = "key = a fleet secret for the tests";
const FLEET: &str = "node = 15:base\n  node = 2:coug2\n  node = 3:coug3";

fn block(file: &str, text: &str) -> ProcessConfig {
    parse_moos(&SourceMap::from_text(file, text))
        .value
        .processes[0]
        .clone()
}

/// A vehicle's (or the base's) truth: a straight line at constant depth.
#[derive(Clone, Copy)]
struct Track {
    x0: f64,
    y0: f64,
    vx: f64,
    vy: f64,
    depth: f64,
}

impl Track {
    fn at(&self, t: f64) -> (f64, f64, f64) {
        (self.x0 + self.vx * t, self.y0 + self.vy * t, self.depth)
    }
}

struct Community {
    name: &'static str,
    acomms: AcommsApp,
    modem: SimModemApp,
    track: Track,
    to_acomms: Vec<Mail>,
    to_modem: Vec<Mail>,
    /// Everything both apps posted: (time, app, variable, value).
    log: Vec<(f64, &'static str, String, Value)>,
}

fn text(v: &Value) -> String {
    match v {
        Value::String(s) => s.to_string(),
        Value::Double(d) => d.to_string(),
        Value::Binary(b) => format!("{b:?}"),
    }
}

impl Community {
    fn new(shared: &Shared, name: &'static str, id: u8, role: &str, track: Track) -> Self {
        let a = block(
            &format!("{name}.moos"),
            &format!(
                "ProcessConfig = pAcomms\n{{\n  AppTick = 10\n  modem_id = {id}\n  role = {role}\n  \
                 {KEY}\n  {FLEET}\n}}\n"
            ),
        );
        let m = block(
            &format!("{name}.moos"),
            &format!(
                "ProcessConfig = uSimModem\n{{\n  AppTick = 10\n  modem_id = {id}\n  \
                 channel = acoustic\n  seed = 7\n}}\n"
            ),
        );
        let acomms = AcommsApp::new("pAcomms", a);
        assert!(acomms.warnings().is_empty(), "{:?}", acomms.warnings());
        let modem = SimModemApp::new("uSimModem", m, shared, 1);
        assert!(modem.warnings().is_empty(), "{:?}", modem.warnings());
        Community {
            name,
            acomms,
            modem,
            track,
            to_acomms: Vec::new(),
            to_modem: Vec::new(),
            log: Vec::new(),
        }
    }

    fn start(&mut self, now: f64) {
        let mut out = Vec::new();
        self.acomms.on_startup(now, &mut out).unwrap();
        self.modem.on_startup(now, &mut out).unwrap();
    }

    fn poke(&mut self, key: &str, value: Value, now: f64) {
        self.to_acomms.push(Mail::new(key, value, now));
    }

    fn record(&mut self, now: f64, app: &'static str, posts: Vec<Post>) {
        for p in posts {
            let key: &str = &p.key;
            match (app, key) {
                ("pAcomms", "ACOMMS_TX") => {
                    self.to_modem.push(Mail::new(key, p.value.clone(), now))
                }
                ("uSimModem", k) if k.starts_with("USBL_") || k.starts_with("ACOMMS_") => {
                    self.to_acomms.push(Mail::new(key, p.value.clone(), now))
                }
                _ => {}
            }
            if key != "APPCAST" && !key.ends_with("_ITER_GAP") && !key.ends_with("_ITER_LEN") {
                self.log.push((now, app, key.to_string(), p.value));
            }
        }
    }

    fn step(&mut self, now: f64) {
        let (x, y, d) = self.track.at(now);
        for (k, v) in [("NAV_X", x), ("NAV_Y", y), ("NAV_DEPTH", d)] {
            self.to_modem.push(Mail::new(k, v, now));
            self.to_acomms.push(Mail::new(k, v, now));
        }
        self.to_acomms.push(Mail::new("NAV_HEADING", 90.0, now));
        self.to_acomms.push(Mail::new("NAV_SPEED", 1.0, now));
        let mut out = Vec::new();
        let mail = std::mem::take(&mut self.to_modem);
        self.modem.on_mail(&mail, now, &mut out).unwrap();
        self.modem.iterate(now, &mut out).unwrap();
        self.record(now, "uSimModem", out);
        let mut out = Vec::new();
        let mail = std::mem::take(&mut self.to_acomms);
        self.acomms.on_mail(&mail, now, &mut out).unwrap();
        self.acomms.iterate(now, &mut out).unwrap();
        self.record(now, "pAcomms", out);
    }

    fn posts(&self, var: &str) -> Vec<(f64, String)> {
        self.log
            .iter()
            .filter(|(_, _, k, _)| k == var)
            .map(|(t, _, _, v)| (*t, text(v)))
            .collect()
    }
}

fn field<'a>(s: &'a str, key: &str) -> Option<&'a str> {
    s.split(',')
        .find_map(|p| p.strip_prefix(&format!("{key}=")))
}

fn num(s: &str, key: &str) -> f64 {
    field(s, key)
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{key} in {s}"))
}

const BASE: Track = Track {
    x0: 0.0,
    y0: 0.0,
    vx: 0.0,
    vy: 0.0,
    depth: 1.0,
};
const COUG2: Track = Track {
    x0: 200.0,
    y0: 100.0,
    vx: 0.5,
    vy: -0.2,
    depth: 5.0,
};
const COUG3: Track = Track {
    x0: -150.0,
    y0: 300.0,
    vx: -0.3,
    vy: 0.4,
    depth: 8.0,
};

/// Runs the fleet for `seconds`, the communities iterated in `order` at every instant; the
/// base is told to kill coug3 at 60 s.
fn run(order: [usize; 3], seconds: f64) -> (Vec<Community>, Shared) {
    let shared = Shared::new();
    let mut fleet = vec![
        Community::new(&shared, "base", 15, "base", BASE),
        Community::new(&shared, "coug2", 2, "vehicle", COUG2),
        Community::new(&shared, "coug3", 3, "vehicle", COUG3),
    ];
    for &i in &order {
        fleet[i].start(0.0);
    }
    let steps = (seconds * 10.0).round() as u64;
    for k in 1..=steps {
        let now = k as f64 / 10.0;
        if k == 600 {
            fleet[0].poke("ACOMMS_COMMAND", Value::from("to=3,cmd=kill"), now);
        }
        for &i in &order {
            fleet[i].step(now);
        }
    }
    (fleet, shared)
}

#[test]
fn a_base_polls_two_vehicles_and_kills_one_over_the_simulated_channel() {
    let (fleet, shared) = run([0, 1, 2], 300.0);
    let (base, coug2, coug3) = (&fleet[0], &fleet[1], &fleet[2]);

    // The kill reached coug3 only, through the variables pSafety and the helm read (once per
    // transmission it heard: a lost confirmation makes the base send it again).
    let kills = coug3.posts("ACOMMS_KILL").len();
    for var in ["ACOMMS_KILL", "MOOS_MANUAL_OVERRIDE"] {
        assert!((1..=2).contains(&coug3.posts(var).len()), "{var} on coug3");
        assert!(coug2.posts(var).is_empty(), "{var} on coug2");
    }
    assert_eq!(coug3.posts("ACOMMS_KILL")[0].1, "true");
    let received = coug3.posts("ACOMMS_CMD_RECEIVED");
    assert_eq!(received.len(), kills);
    assert!(
        received[0].1.starts_with("from=15,cmd=kill,seq="),
        "{received:?}"
    );
    // The base saw it queued, sent and confirmed.
    let acks: Vec<String> = base
        .posts("ACOMMS_COMMAND_ACK")
        .into_iter()
        .map(|(_, s)| s)
        .collect();
    assert_eq!(acks[0], "to=3,cmd=kill,seq=0,state=queued");
    assert!(
        acks.contains(&"to=3,cmd=kill,seq=0,state=sent".to_string()),
        "{acks:?}"
    );
    assert!(
        acks.iter()
            .any(|a| a.starts_with("to=3,cmd=kill,") && a.ends_with("state=confirmed")),
        "{acks:?}"
    );
    // coug3 reports itself killed from then on.
    let last3 = base
        .posts("ACOMMS_VEHICLE")
        .into_iter()
        .rfind(|(_, s)| s.starts_with("id=3,") && s.contains(",time="))
        .unwrap()
        .1;
    assert!(last3.contains(",mode=killed,"), "{last3}");

    // Poll statistics.
    let status = base.posts("ACOMMS_STATUS").last().unwrap().1.clone();
    let (polls, answers, timeouts) = (
        num(&status, "polls"),
        num(&status, "answers"),
        num(&status, "timeouts"),
    );
    let net = shared.get::<SharedNet>("acoustic").unwrap();
    let stats = *net.lock().unwrap().channel().stats();
    eprintln!(
        "300 s, seed 7: polls={polls} answers={answers} timeouts={timeouts} \
         channel: transmitted={} delivered={} lost={} collisions={} half_duplex={}",
        stats.transmitted, stats.delivered, stats.lost, stats.collisions, stats.half_duplex
    );
    // One poll every 4 s at most (a command takes a slot): about 75 in 300 s.
    assert!((70.0..=75.0).contains(&polls), "{status}");
    assert_eq!(polls, answers + timeouts, "{status}");
    // DUNE's loss curve at 220-340 m: 0.91-0.96 each way.
    assert!(answers >= 0.7 * polls, "{status}");
    assert_eq!(num(&status, "bad_tag"), 0.0);
    assert_eq!(num(&status, "confirmed"), 1.0);
    assert!(stats.delivered > 0 && stats.transmitted >= polls as u64);

    // Every vehicle has its view after answers and timeouts; before its first answer the
    // position keys are left out.
    let views = base.posts("ACOMMS_VEHICLE");
    let v2: Vec<&String> = views
        .iter()
        .map(|(_, s)| s)
        .filter(|s| s.starts_with("id=2,name=coug2"))
        .collect();
    assert!(!v2.is_empty());
    let answered = v2.iter().find(|s| s.contains(",time=")).unwrap();
    for k in [
        "x",
        "y",
        "depth",
        "heading",
        "speed",
        "battery_v",
        "health",
        "polls",
        "answers",
        "timeouts",
    ] {
        assert!(field(answered, k).is_some(), "{k} in {answered}");
    }
    assert!(field(answered, "health").unwrap().starts_with("0x"));

    // The base's contact reports of coug2: its own reported position within the codec's
    // 0.1 m of its navigation when it answered, and the USBL one within a few metres of its
    // truth (1 degree and 0.1 m of noise at about 220 m).
    let reports = base.posts("NODE_REPORT");
    let mut reported = 0;
    let mut usbl = 0;
    let mut worst_usbl: f64 = 0.0;
    for (t, r) in &reports {
        let name = field(r, "NAME").unwrap();
        let (x, y) = (num(r, "X"), num(r, "Y"));
        let track = match name {
            "coug2" | "coug2_usbl" => COUG2,
            "coug3" | "coug3_usbl" => COUG3,
            other => panic!("a report of {other}"),
        };
        if name.ends_with("_usbl") {
            assert_eq!(field(r, "VSOURCE"), Some("acomms_usbl"), "{r}");
            // Within 3.4 degrees (1 degree of noise) of the bearing plus the ~3 m the sender
            // moves while the packet travels; its depth is the one the packet reports.
            let (tx, ty, tz) = track.at(*t);
            let e = (x - tx).hypot(y - ty);
            let range = tx.hypot(ty);
            worst_usbl = worst_usbl.max(e / range);
            assert!(e < 0.06 * range + 3.0, "{r}: {e} m from the truth");
            if name.starts_with("coug2") {
                assert_eq!(num(r, "DEP"), tz, "{r}");
            }
            usbl += 1;
        } else {
            assert_eq!(field(r, "VSOURCE"), Some("acomms_reported"), "{r}");
            // Its navigation at the time it answered (up to ~2.5 s before it is heard).
            let ok = (0..40).any(|k| {
                let (tx, ty, _) = track.at(t - k as f64 * 0.1);
                (x - tx).abs() <= 0.051 && (y - ty).abs() <= 0.051
            });
            assert!(ok, "{r}");
            reported += 1;
        }
    }
    eprintln!(
        "base: {reported} reported and {usbl} USBL reports, worst USBL error {:.1} % of range",
        worst_usbl * 100.0
    );
    assert!(reported >= answers as usize && usbl >= answers as usize);

    // The vehicles heard the base (its polls) with a fix and know it is there.
    assert!(!coug2.posts("ACOMMS_LAST_BASE_CONTACT").is_empty());
    assert!(
        coug2
            .posts("ACOMMS_CONTACT")
            .iter()
            .any(|(_, s)| s.starts_with("name=base,id=15,source=usbl"))
    );
}

#[test]
fn the_order_of_the_communities_within_an_instant_changes_nothing() {
    let (a, _) = run([0, 1, 2], 120.0);
    let (b, _) = run([2, 1, 0], 120.0);
    let (c, _) = run([1, 0, 2], 120.0);
    for i in 0..3 {
        assert!(a[i].log.len() > 100, "{}", a[i].name);
        assert_eq!(a[i].log, b[i].log, "{}", a[i].name);
        assert_eq!(a[i].log, c[i].log, "{}", a[i].name);
    }
}

#[test]
fn bad_settings_are_warnings_at_their_lines() {
    let shared = Shared::new();
    let a = AcommsApp::new(
        "pAcomms",
        block(
            "b.moos",
            "ProcessConfig = pAcomms\n{\n  modem_id = 40\n  role = boss\n  node = 2\n  \
             colour = red\n  kill_flag = nothing\n}\n",
        ),
    );
    let w: Vec<String> = a.warnings().iter().map(|d| d.located()).collect();
    for (line, what) in [
        (3, "modem_id = 40: expected 1-15"),
        (4, "role = boss"),
        (5, "node = 2"),
        (6, "unknown parameter `colour`"),
        (7, "kill_flag = nothing: expected VAR=VALUE"),
        (1, "no `key`"),
    ] {
        assert!(
            w.iter()
                .any(|s| s.starts_with(&format!("b.moos:{line}:")) && s.contains(what)),
            "{what} at line {line}: {w:?}"
        );
    }
    assert!(a.node().is_none(), "no valid modem id: idle");
    // A base listing only the vehicles it polls is fine; one listing nobody is told so.
    let ok = AcommsApp::new(
        "pAcomms",
        block(
            "c.moos",
            &format!(
                "ProcessConfig = pAcomms\n{{\n  modem_id = 15\n  role = base\n  {KEY}\n  node = 2:coug2\n}}\n"
            ),
        ),
    );
    assert!(ok.warnings().is_empty(), "{:?}", ok.warnings());
    assert_eq!(ok.node().unwrap().views().len(), 1);
    let alone = AcommsApp::new(
        "pAcomms",
        block(
            "c.moos",
            &format!("ProcessConfig = pAcomms\n{{\n  modem_id = 15\n  role = lead\n  {KEY}\n}}\n"),
        ),
    );
    let w: Vec<String> = alone.warnings().iter().map(|d| d.located()).collect();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("polls nobody"), "{w:?}");
    let m = SimModemApp::new(
        "uSimModem",
        block(
            "m.moos",
            "ProcessConfig = uSimModem\n{\n  modem_id = 2\n  loss = often\n  bit_rate = -3\n}\n",
        ),
        &shared,
        0,
    );
    let w: Vec<String> = m.warnings().iter().map(|d| d.located()).collect();
    assert!(
        w.iter()
            .any(|s| s.starts_with("m.moos:4:") && s.contains("loss = often")),
        "{w:?}"
    );
    assert!(
        w.iter()
            .any(|s| s.starts_with("m.moos:5:") && s.contains("bit_rate")),
        "{w:?}"
    );
    // A second modem with the same id on the same channel is refused.
    let twin = SimModemApp::new(
        "uSimModem",
        block(
            "t.moos",
            "ProcessConfig = uSimModem\n{\n  modem_id = 2\n}\n",
        ),
        &shared,
        0,
    );
    assert!(
        twin.warnings()
            .iter()
            .any(|d| d.located().starts_with("t.moos:3:")
                && d.message.contains("already on channel")),
        "{:?}",
        twin.warnings()
    );
}

#[test]
fn a_bad_command_is_reported_and_never_sent() {
    let shared = Shared::new();
    let mut base = Community::new(&shared, "base", 15, "base", BASE);
    base.start(0.0);
    base.poke("ACOMMS_COMMAND", Value::from("to=2,cmd=fly"), 0.1);
    base.poke("ACOMMS_COMMAND", Value::from("to=2,cmd=goto,x=1"), 0.1);
    base.step(0.1);
    let w = base.posts("ACOMMS_WARNING");
    assert_eq!(w.len(), 2, "{w:?}");
    assert!(w[0].1.contains("cmd=fly"));
    assert!(w[1].1.contains("needs x= and y="));
    assert!(base.posts("ACOMMS_COMMAND_ACK").is_empty());
    let sent = base.posts("ACOMMS_TX");
    assert_eq!(sent.len(), 1, "only the first poll: {sent:?}");
    assert!(sent[0].1.starts_with("dest=2,hex=72"), "{sent:?}");
}

/// The kill and the surface a vehicle's pAcomms applies reach pSafety (with the rules of the
/// module's table), which overrides the helm and drives the vehicle up.
#[test]
fn kill_and_surface_reach_psafety_and_the_helm() {
    use acomms::FleetKey;
    use acomms::net::{Event, NetConfig, Node, Role};
    use runtime::safety::SafetyApp;

    let mut base = {
        let mut c = NetConfig::new(15, Role::Poller);
        c.poll_order = vec![3];
        Node::new(c, FleetKey::new(b"a fleet secret for the tests"))
    };
    for (t, cmd, mode) in [(10.0, "kill", "ALLSTOP"), (20.0, "surface", "SURFACE")] {
        let mut vehicle = AcommsApp::new(
            "pAcomms",
            block(
                "v.moos",
                &format!("ProcessConfig = pAcomms\n{{\n  modem_id = 3\n  {KEY}\n}}\n"),
            ),
        );
        let mut safety = SafetyApp::new(
            "pSafety",
            block(
                "v.moos",
                "ProcessConfig = pSafety\n{\n  \
                 rule = acomms_kill: ACOMMS_KILL == true -> allstop, kind=comms\n  \
                 rule = acomms_surface: ACOMMS_SURFACE == true -> surface_disarm, kind=comms\n}\n",
            ),
        );
        assert!(safety.malconfig().is_empty(), "{:?}", safety.malconfig());
        let mut ev = Vec::new();
        base.command(0.0, &format!("to=3,cmd={cmd}"), &mut ev)
            .unwrap();
        base.tick(t, &mut ev);
        let frame = ev
            .iter()
            .find_map(|e| match e {
                Event::Transmit { frame, .. } if frame[0] != 0x72 => Some(*frame),
                _ => None,
            })
            .expect("the command's frame");
        let hex: String = frame.iter().map(|b| format!("{b:02X}")).collect();
        let mut out = Vec::new();
        vehicle.on_startup(0.0, &mut out).unwrap();
        safety.on_startup(0.0, &mut out).unwrap();
        let rx = Mail::new(
            "ACOMMS_RX",
            format!("src=15,dest=3,ack=0,hex={hex}").as_str(),
            1.0,
        );
        let mut posts = Vec::new();
        vehicle.on_mail(&[rx], 1.0, &mut posts).unwrap();
        vehicle.iterate(1.0, &mut posts).unwrap();
        let keys: Vec<String> = posts.iter().map(|p| p.key.to_string()).collect();
        let mail: Vec<Mail> = posts
            .into_iter()
            .filter(|p| &*p.key != "APPCAST")
            .map(|p| Mail::new(&p.key, p.value, 1.0))
            .collect();
        let mut out = Vec::new();
        safety.on_mail(&mail, 1.1, &mut out).unwrap();
        safety.iterate(1.1, &mut out).unwrap();
        let last = |k: &str| {
            out.iter()
                .rev()
                .find(|p| &*p.key == k)
                .map(|p| text(&p.value))
        };
        assert_eq!(
            last("SAFETY_MODE").as_deref(),
            Some(mode),
            "{cmd}: {keys:?}"
        );
        assert_eq!(
            last("MOOS_MANUAL_OVERRIDE").as_deref(),
            Some("true"),
            "{cmd}"
        );
        // The vehicle confirms to the base.
        assert!(keys.contains(&"ACOMMS_TX".to_string()), "{cmd}: {keys:?}");
    }
}

/// In a fleet run every community has its own seed (the run's mixed with its name): a modem
/// without `seed` joins the channel the first one made without a warning, and takes its seed;
/// one with other settings is still told.
#[test]
fn a_modem_without_seed_takes_the_channels() {
    let shared = Shared::new();
    let a = SimModemApp::new(
        "uSimModem",
        block(
            "a.moos",
            "ProcessConfig = uSimModem\n{\n  modem_id = 1\n}\n",
        ),
        &shared,
        11,
    );
    let b = SimModemApp::new(
        "uSimModem",
        block(
            "b.moos",
            "ProcessConfig = uSimModem\n{\n  modem_id = 2\n}\n",
        ),
        &shared,
        12,
    );
    assert!(a.warnings().is_empty() && b.warnings().is_empty());
    let seed = a.net().lock().unwrap().channel().config().seed;
    assert_eq!(b.net().lock().unwrap().channel().config().seed, seed);
    let c = SimModemApp::new(
        "uSimModem",
        block(
            "c.moos",
            "ProcessConfig = uSimModem\n{\n  modem_id = 3\n  seed = 5\n}\n",
        ),
        &shared,
        11,
    );
    assert!(
        c.warnings()
            .iter()
            .any(|d| d.message.contains("other settings")),
        "{:?}",
        c.warnings()
    );
}

/// The net at the tick barrier: what modems ask at one instant is merged in modem order when
/// the run moves on, whichever came first. In a fleet run a community's modem starts and
/// iterates (syncing the net) before the next community's modem starts, and on several threads
/// any of them may come first; here coug2's community or the base's is first, and every
/// reception (payload, arrival, USBL fix drawn from the seeded noise) is the same.
#[test]
fn modems_registering_at_one_instant_in_any_order_hear_the_same() {
    use achannel::Position;
    use runtime::acomms_apps::AcousticNet;
    let run = |first: u8| {
        let mut net = AcousticNet::new(achannel::Config {
            seed: 11,
            ..achannel::Config::default()
        });
        let at = |m: u8| match m {
            15 => Position::new(0.0, 0.0, 1.0),
            1 => Position::new(300.0, 40.0, 3.0),
            _ => Position::new(-200.0, 350.0, 5.0),
        };
        // Start-up: `first` registers and syncs (its first iteration), then the others.
        net.register(0.0, first, at(first));
        net.sync(0.0);
        for m in [15, 1, 2].into_iter().filter(|&m| m != first) {
            net.register(0.0, m, at(m));
            net.sync(0.0);
        }
        for k in 1..=6u8 {
            let t = f64::from(k) * 10.0;
            net.sync(t);
            net.transmit(t, 15, 0, &[k; 12]);
        }
        net.sync(100.0);
        (net.take_inbox(1), net.take_inbox(2), *net.channel().stats())
    };
    let base_first = run(15);
    let coug2_first = run(2);
    assert!(
        base_first.0.len() + base_first.1.len() >= 6,
        "{base_first:?}"
    );
    assert_eq!(base_first, coug2_first);
    assert_eq!(base_first, run(1));
}
