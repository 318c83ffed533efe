//! Two in-process communities bridged by two pShare apps over loopback UDP (127.0.0.1 only,
//! ports picked by the system): `NAV_X->REMOTE_NAV_X:127.0.0.1:<port>` arrives in the other
//! community with its value, source, community and time; garbage datagrams are counted and
//! never stop the app; the white list and the loop guard hold.

mod support;

use std::net::UdpSocket;
use std::sync::Arc;

use mission::moos::ProcessConfig;
use mission::source::SourceMap;
use moosdb::{Message, Value as WireValue};
use runtime::antler::BuiltInApp;
use runtime::pshare::PShareApp;
use runtime::{App, AppResult, Bus, Mail, Post, Scheduler, Subscription, Value, VirtualClock};
use support::RefCell;

const START: f64 = 1_700_000_000.0;

fn block(text: &str) -> ProcessConfig {
    let src = SourceMap::from_text("share.moos", text);
    mission::moos::parse_moos(&src).value.processes[0].clone()
}

/// A pShare the test can look into after handing it to a scheduler.
struct Shared(Arc<RefCell<PShareApp>>);

impl App for Shared {
    fn name(&self) -> &str {
        "pShare"
    }
    fn app_tick(&self) -> f64 {
        self.0.borrow().app_tick()
    }
    fn subscriptions(&self) -> Vec<Subscription> {
        self.0.borrow().subscriptions()
    }
    fn new_subscriptions(&mut self) -> Vec<Subscription> {
        self.0.borrow_mut().new_subscriptions()
    }
    fn on_startup(&mut self, now: f64, out: &mut Vec<Post>) -> AppResult {
        self.0.borrow_mut().on_startup(now, out)
    }
    fn on_mail(&mut self, mail: &[Mail], now: f64, out: &mut Vec<Post>) -> AppResult {
        self.0.borrow_mut().on_mail(mail, now, out)
    }
    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> AppResult {
        self.0.borrow_mut().iterate(now, out)
    }
}

/// Posts `NAV_X = 100 + k` (and `SECRET = k`) at each of its first `count` iterations.
struct Nav {
    k: u32,
    count: u32,
    sent: Arc<RefCell<Vec<(f64, f64)>>>,
}

impl App for Nav {
    fn name(&self) -> &str {
        "uSimMarine"
    }
    fn app_tick(&self) -> f64 {
        4.0
    }
    fn iterate(&mut self, now: f64, out: &mut Vec<Post>) -> AppResult {
        if self.k < self.count {
            let x = 100.0 + f64::from(self.k);
            out.push(Post::double("NAV_X", x));
            out.push(Post::double("SECRET", f64::from(self.k)));
            self.sent.borrow_mut().push((now, x));
            self.k += 1;
        }
        Ok(())
    }
}

/// Keeps every mail of its variables.
struct Recorder {
    vars: Vec<&'static str>,
    got: Arc<RefCell<Vec<Mail>>>,
}

impl App for Recorder {
    fn name(&self) -> &str {
        "recorder"
    }
    fn subscriptions(&self) -> Vec<Subscription> {
        self.vars.iter().map(|v| Subscription::var(*v)).collect()
    }
    fn on_mail(&mut self, mail: &[Mail], _now: f64, _out: &mut Vec<Post>) -> AppResult {
        self.got.borrow_mut().extend(mail.iter().cloned());
        Ok(())
    }
    fn iterate(&mut self, _now: f64, _out: &mut Vec<Post>) -> AppResult {
        Ok(())
    }
}

fn shared(text: &str) -> Arc<RefCell<PShareApp>> {
    let app = PShareApp::new("pShare", block(text));
    assert!(app.warnings().is_empty(), "{:?}", app.warnings());
    Arc::new(RefCell::new(app))
}

fn port_of(app: &Arc<RefCell<PShareApp>>) -> u16 {
    app.borrow_mut().open();
    let ports = app.borrow().listening();
    ports[0].1.expect("the listener is open")
}

#[test]
fn nav_x_crosses_to_the_other_community_as_remote_nav_x() {
    // Community bravo listens on a port the system picks, letting in REMOTE_* only.
    let b = shared(
        "ProcessConfig = pShare\n{\n  AppTick = 4\n  listen_address = 127.0.0.1\n  \
         input = route = 127.0.0.1:0, white_list = REMOTE_*\n}\n",
    );
    let port = port_of(&b);
    // Community alpha shares NAV_X renamed, and SECRET, which bravo's white list refuses.
    let a = shared(&format!(
        "ProcessConfig = pShare\n{{\n  AppTick = 4\n  listen_address = 127.0.0.1\n  \
         output = NAV_X->REMOTE_NAV_X:127.0.0.1:{port}\n  \
         output = src_name = SECRET, route = 127.0.0.1:{port}\n}}\n"
    ));

    let sent = Arc::new(RefCell::new(Vec::new()));
    let mut alpha = Scheduler::new(Bus::new("alpha", START), VirtualClock, START);
    alpha
        .add_app(Box::new(Nav {
            k: 0,
            count: 20,
            sent: sent.clone(),
        }))
        .unwrap();
    alpha.add_app(Box::new(Shared(a.clone()))).unwrap();

    let got = Arc::new(RefCell::new(Vec::new()));
    let mut bravo = Scheduler::new(Bus::new("bravo", START), VirtualClock, START);
    bravo.add_app(Box::new(Shared(b.clone()))).unwrap();
    bravo
        .add_app(Box::new(Recorder {
            vars: vec!["REMOTE_NAV_X", "SECRET"],
            got: got.clone(),
        }))
        .unwrap();

    // Garbage from a third socket: never a panic, counted.
    let junk = UdpSocket::bind("127.0.0.1:0").unwrap();
    junk.send_to(b"not a MOOS message", ("127.0.0.1", port))
        .unwrap();
    let mut frame = Vec::new();
    Message::notify("REMOTE_NAV_X", WireValue::Double(1.0), 1.0).encode(&mut frame);
    junk.send_to(&frame[..frame.len() - 3], ("127.0.0.1", port))
        .unwrap();

    for step in 1..=60 {
        let t = START + f64::from(step) * 0.25;
        alpha.advance(t).unwrap();
        bravo.advance(t).unwrap();
    }

    let sent = sent.borrow();
    let got = got.borrow();
    assert_eq!(sent.len(), 20);
    let values: Vec<f64> = got.iter().map(|m| m.value.as_f64().unwrap()).collect();
    let want: Vec<f64> = sent.iter().map(|(_, x)| *x).collect();
    assert_eq!(values, want, "every NAV_X arrives, renamed, in order");
    for (m, (t, _)) in got.iter().zip(sent.iter()) {
        assert_eq!(m.key, "REMOTE_NAV_X");
        // pShare posts with the writer's source, community and time kept.
        assert_eq!(m.source, "uSimMarine");
        assert_eq!(m.community, "alpha");
        assert_eq!(m.time, *t);
    }
    assert_eq!(
        bravo.current("REMOTE_NAV_X"),
        Some(Value::Double(119.0)),
        "the last value is bravo's"
    );
    assert_eq!(bravo.current("SECRET"), None, "refused by the white list");

    let rx = b.borrow().received();
    assert_eq!(rx[0].1.posted, 20);
    assert_eq!(rx[0].1.filtered, 20, "the SECRET shares");
    assert_eq!(rx[0].1.garbage, 2);
    assert_eq!(a.borrow().sent().sent, 40);
    assert_eq!(
        bravo.current("PSHARE_INPUT_SUMMARY"),
        Some(Value::text(format!("127.0.0.1:{port}")))
    );
    assert_eq!(
        alpha.current("PSHARE_OUTPUT_SUMMARY"),
        Some(Value::text(format!(
            "NAV_X->REMOTE_NAV_X:127.0.0.1:{port}, SECRET->SECRET:127.0.0.1:{port}"
        )))
    );
    // The appcast (posted at the first iteration, no viewer asks again) lists the input
    // with the port the system picked.
    let cast = bravo.current("APPCAST").expect("an appcast");
    let cast = cast.as_str().unwrap();
    assert!(
        cast.contains(&format!("127.0.0.1:0 (port {port})")),
        "{cast}"
    );
}

#[test]
fn a_received_name_pshare_shares_is_not_posted_back_and_commands_add_routes() {
    let b = shared(
        "ProcessConfig = pShare\n{\n  listen_address = 127.0.0.1\n  \
         input = route = 127.0.0.1:0\n  output = DEPLOY->127.0.0.1:9\n}\n",
    );
    let port = port_of(&b);
    let mut bravo = Scheduler::new(Bus::new("bravo", START), VirtualClock, START);
    bravo.add_app(Box::new(Shared(b.clone()))).unwrap();
    bravo.advance(START + 0.5).unwrap();

    let tx = UdpSocket::bind("127.0.0.1:0").unwrap();
    let send = |key: &str, v: f64| {
        let mut m = Message::notify(key, WireValue::Double(v), START);
        m.src = bytes::Bytes::from_static(b"pHelmIvP");
        m.community = bytes::Bytes::from_static(b"shore");
        let mut out = Vec::new();
        pshare::datagram::encode(&m, key, &mut out).unwrap();
        tx.send_to(&out, ("127.0.0.1", port)).unwrap();
    };
    // DEPLOY is a name this pShare registers for: the loop guard keeps it out.
    send("DEPLOY", 1.0);
    send("RETURN", 1.0);
    bravo.advance(START + 1.0).unwrap();
    assert_eq!(bravo.current("DEPLOY"), None);
    assert_eq!(bravo.current("RETURN"), Some(Value::Double(1.0)));
    let c = b.borrow().received()[0].1;
    assert_eq!((c.posted, c.looped, c.garbage), (1, 1, 0));

    // A dynamic share registers for its variable.
    bravo
        .add_poke(runtime::Poke {
            key: "PSHARE_CMD".into(),
            value: Value::text("cmd=output, src_name=SPEED, dest_name=S2, route=127.0.0.1:9"),
            at: runtime::PokeAt::Time(1.2),
        })
        .unwrap();
    bravo.advance(START + 2.0).unwrap();
    assert!(b.borrow().routes().registered_for("SPEED"));
}
