//! The base station against coug's MOOSDB on 127.0.0.1 (port 0): a stand-in for pAcomms
//! posts the interface's mail, the console (joined as `coug_base`) shows it, and the
//! commands typed reach the DB exactly. Every wait is bounded and waits for an event,
//! never for a duration.

use std::time::Duration;

use base::console::Console;
use moosdb::{Client, ClientConfig, MailStream, Server, ServerConfig, Value};
use tokio::time::timeout;

const WAIT: Duration = Duration::from_secs(15);

async fn db() -> Server {
    Server::bind(ServerConfig::with_addr(([127, 0, 0, 1], 0).into()))
        .await
        .expect("bind loopback")
}

async fn client(srv: &Server, name: &str) -> (Client, MailStream) {
    let (c, m) = Client::start(ClientConfig::new(
        name,
        "127.0.0.1",
        srv.local_addr().port(),
    ));
    timeout(WAIT, c.wait_connected())
        .await
        .expect("connect in time")
        .expect("welcomed");
    (c, m)
}

async fn subscribed(srv: &Server, client: &str, key: &str) {
    timeout(WAIT, async {
        while !srv.with_db(|db| db.subscribers(key).iter().any(|c| c == client)) {
            tokio::task::yield_now().await;
            tokio::time::sleep(Duration::from_millis(5)).await;
        }
    })
    .await
    .unwrap_or_else(|_| panic!("{client} never subscribed to {key}"));
}

/// Drains the base's mail into the console until `done` holds.
async fn until(console: &mut Console, mail: &mut MailStream, done: impl Fn(&Console) -> bool) {
    timeout(WAIT, async {
        while !done(console) {
            let m = mail.recv().await.expect("mail stream open");
            if !m.is_double() {
                console.mail(&m.key_str(), &m.sval_str());
            }
        }
    })
    .await
    .expect("the mail in time");
}

/// The next `ACOMMS_COMMAND` the listener gets.
async fn next_command(mail: &mut MailStream) -> String {
    timeout(WAIT, async {
        loop {
            let m = mail.recv().await.expect("open");
            if &*m.key_str() == "ACOMMS_COMMAND" {
                return m.sval_str().to_string();
            }
        }
    })
    .await
    .expect("a command in time")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_table_shows_pacomms_mail_and_typed_commands_reach_the_db() {
    let srv = db().await;
    let (acomms, _acomms_mail) = client(&srv, "pAcomms").await;
    let (listener, mut heard) = client(&srv, "listener").await;
    listener.register("ACOMMS_COMMAND", 0.0);
    subscribed(&srv, "listener", "ACOMMS_COMMAND").await;

    let (station, mut mail) = client(&srv, "coug_base").await;
    base::terminal::subscribe(&station);
    for var in base::READS {
        subscribed(&srv, "coug_base", var).await;
    }
    let mut console = Console::new();

    let t = 1000.0;
    let post = |k: &str, v: &str| acomms.notify(k, Value::text(v)).unwrap();
    post(
        "ACOMMS_VEHICLE",
        "id=2,name=coug2,time=1000,x=120.5,y=-40.25,depth=8.5,heading=271,speed=1.2,\
         battery_v=15.8,health=0x0,polls=10,answers=8,timeouts=2",
    );
    post(
        "ACOMMS_VEHICLE",
        "id=3,name=coug3,time=0,polls=3,answers=0,timeouts=3",
    );
    post(
        "NODE_REPORT",
        "NAME=coug3,X=-5,Y=7,SPD=0,HDG=10,DEP=0,TIME=990,TYPE=UUV",
    );
    post("ACOMMS_COMMAND_ACK", "to=2,cmd=abort,seq=4,state=confirmed");
    until(&mut console, &mut mail, |c| {
        c.fleet.by_name("coug3").is_some_and(|v| v.report.is_some())
            && c.fleet.by_id(2).is_some_and(|v| v.ack.is_some())
    })
    .await;

    let screen = console.render_text(t + 12.0, 130, 16);
    let line = |name: &str| {
        screen
            .lines()
            .find(|l| l.contains(name))
            .unwrap_or_else(|| panic!("no {name} row in\n{screen}"))
            .split_whitespace()
            .collect::<Vec<_>>()
            .join(" ")
    };
    // Ages are the base's MOOS time minus the last answer (coug3: its node report, at 990).
    assert_eq!(
        line("coug2"),
        "│2 coug2 12s 8/10 80% t2 120.5 -40.2 8.5 271 1.2 15.8 0x0 abort #4 confirmed │",
        "\n{screen}"
    );
    assert_eq!(
        line("coug3"),
        "│3 coug3 22s 0/3 0% t3 -5.0* 7.0 0.0 10 0.0 - │",
        "\n{screen}"
    );

    // A moving command without its confirmation posts nothing; an abort goes at once, so
    // the first command the listener hears is the abort.
    let mut typed = console.type_line("goto coug2 50 -60");
    typed.extend(console.key(base::console::Key::Char('n')));
    assert!(typed.is_empty(), "{typed:?}");
    let abort = console.type_line("abort 3");
    base::terminal::post(&mut console, &station, abort);
    assert_eq!(next_command(&mut heard).await, "to=3,cmd=abort");

    // Confirmed, the go-to is posted exactly.
    let none = console.type_line("goto coug2 50 -60.5");
    assert!(none.is_empty());
    let confirmed: Vec<_> = console
        .key(base::console::Key::Char('y'))
        .into_iter()
        .collect();
    base::terminal::post(&mut console, &station, confirmed);
    assert_eq!(next_command(&mut heard).await, "to=2,cmd=goto,x=50,y=-60.5");
    assert_eq!(console.sent(), 2);
}
