//! The base station's screen for a known fleet, pinned to `docs/base/screen.txt` (the
//! picture the docs show). `COUG_UPDATE_DOCS=1` rewrites the file instead of comparing.

use base::console::Console;

fn fleet() -> Console {
    let mut c = Console::new();
    for (var, value) in [
        (
            "ACOMMS_VEHICLE",
            "id=1,name=coug1,time=1200,x=152.3,y=-88.1,depth=6.2,heading=87,speed=1.4,\
             battery_v=15.9,health=0x0,polls=40,answers=39,timeouts=1",
        ),
        (
            "ACOMMS_VEHICLE",
            "id=2,name=coug2,time=1164,x=-40.8,y=-120.5,depth=8.0,heading=265,speed=1.5,\
             battery_v=15.2,health=0x4,polls=40,answers=31,timeouts=9",
        ),
        (
            "ACOMMS_VEHICLE",
            "id=3,name=coug3,time=1010,x=12,y=4,depth=0,heading=10,speed=0,\
             battery_v=14.1,health=0x0,polls=40,answers=12,timeouts=28",
        ),
        (
            "ACOMMS_COMMAND_ACK",
            "to=3,cmd=surface,seq=12,state=confirmed",
        ),
        (
            "NODE_REPORT",
            "NAME=base,X=0,Y=0,SPD=0,HDG=0,DEP=0,TIME=1203,TYPE=ship",
        ),
    ] {
        c.mail(var, value);
    }
    assert!(c.type_line("goto coug2 100 -150").is_empty());
    c
}

#[test]
fn the_documented_screen_is_what_the_console_draws() {
    let screen = fleet().render_text(1205.0, 118, 16);
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/base/screen.txt");
    if std::env::var("COUG_UPDATE_DOCS").is_ok_and(|v| v == "1") {
        std::fs::write(&path, &screen).unwrap();
    }
    let doc = std::fs::read_to_string(&path).expect("docs/base/screen.txt");
    assert_eq!(screen, doc, "the console draws:\n{screen}");
}
