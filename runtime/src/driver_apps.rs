//! The device drivers `iGPS`, `iDVL`, `iSeaTrac` and `iTeensy` as MOOS apps: one
//! [`DriverApp`] over a [`drivers::Driver`] (the protocol state machine and its link).
//!
//! The link (serial port or TCP client) is opened at start-up, on its own thread: the app's
//! iterate only takes what arrived and queues what goes out, so a stalled device never
//! blocks the community. The variables each driver posts and reads, and its parameters, are
//! in the `drivers` crate's module docs ([`drivers::gps`], [`drivers::dvl`],
//! [`drivers::seatrac`], [`drivers::teensy`]); they are those of uSimSensors, so the
//! navigator cannot tell hardware from simulation.
//!
//! Configuration problems are warnings (`mission::Diagnostic`, kind `AppSetting`, at the
//! parameter's line) and the app runs with the defaults; the appcast shows the link (state,
//! reconnections, bytes, drops), the protocol's counters (lines, garbage, oversize lines, bad
//! checksums, parse errors) and the latest values. Each driver also posts its status line,
//! `<DEV>_DRIVER_STATUS`.

use mission::diagnostic::{Diagnostic, DiagnosticKind};
use mission::moos::ProcessConfig;
use vehicle::ConfigError;
use vehicle::geodesy::LocalGrid;

use drivers::link::LinkConfig;
use drivers::{Driver, Io, Protocol};

use crate::app::{AppResult, Mail, Post, Subscription};
use crate::appcasting::Note;
use crate::hosted::{AppCore, Hosted};

fn params(block: &ProcessConfig) -> impl Iterator<Item = (&str, &str)> {
    block
        .entries
        .iter()
        .map(|p| (p.key.as_str(), p.value.as_str()))
}

/// A driver: the core of a driver app (the protocol, its link, and what one callback
/// produced).
pub struct DriverCore<P> {
    driver: Driver<P>,
    io: Io,
}

/// A driver as a MOOS app.
pub type DriverApp<P> = Hosted<DriverCore<P>>;

fn driver_app<P: Protocol>(
    name: &str,
    block: ProcessConfig,
    protocol: P,
    link: LinkConfig,
    status_period: f64,
    problems: &[ConfigError],
    extra: Option<Diagnostic>,
) -> DriverApp<P> {
    let mut warnings = crate::vehicle::config_warnings(&block, problems);
    warnings.extend(extra);
    let core = DriverCore {
        driver: Driver::new(protocol, link, status_period),
        io: Io::default(),
    };
    Hosted::host(name, block, warnings, core)
}

impl<P: Protocol> Hosted<DriverCore<P>> {
    /// The driver (its protocol, link settings and counters).
    pub fn driver(&self) -> &Driver<P> {
        &self.core().driver
    }
}

impl<P> DriverCore<P> {
    /// Hands on what the driver produced: posts, and events and warnings for the appcast.
    fn drain(&mut self, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        out.append(&mut self.io.posts);
        notes.extend(self.io.events.drain(..).map(Note::Event));
        notes.extend(self.io.warnings.drain(..).map(Note::Warning));
    }
}

/// `iGPS` from its block; `grid` (the mission's origin) gives GPS_X/GPS_Y.
pub fn gps(
    name: &str,
    block: ProcessConfig,
    grid: Option<LocalGrid>,
) -> DriverApp<drivers::gps::Gps> {
    let (source, common, link, problems) = drivers::gps::config_from_params(params(&block));
    let no_grid = grid.is_none().then(|| {
        Diagnostic::line_warning(
            DiagnosticKind::AppSetting,
            &block.span,
            format!(
                "{}: the mission has no valid LatOrigin/LongOrigin: no GPS_X/GPS_Y, only GPS_LAT/GPS_LONG",
                drivers::gps::PROGRAM
            ),
        )
    });
    driver_app(
        name,
        block,
        drivers::gps::Gps::new(source, grid),
        link,
        common.status_period,
        &problems,
        no_grid,
    )
}

/// `iDVL` from its block.
pub fn dvl(name: &str, block: ProcessConfig) -> DriverApp<drivers::dvl::Dvl> {
    let (cfg, common, link, problems) = drivers::dvl::DvlConfig::from_params(params(&block));
    driver_app(
        name,
        block,
        drivers::dvl::Dvl::new(cfg),
        link,
        common.status_period,
        &problems,
        None,
    )
}

/// `iSeaTrac` from its block.
pub fn seatrac(name: &str, block: ProcessConfig) -> DriverApp<drivers::seatrac::SeaTrac> {
    let (cfg, common, link, problems) =
        drivers::seatrac::SeaTracConfig::from_params(params(&block));
    driver_app(
        name,
        block,
        drivers::seatrac::SeaTrac::new(cfg),
        link,
        common.status_period,
        &problems,
        None,
    )
}

/// `iTeensy` from its block.
pub fn teensy(name: &str, block: ProcessConfig) -> DriverApp<drivers::teensy::Teensy> {
    let (cfg, common, link, problems) = drivers::teensy::TeensyConfig::from_params(params(&block));
    driver_app(
        name,
        block,
        drivers::teensy::Teensy::new(cfg),
        link,
        common.status_period,
        &problems,
        None,
    )
}

impl<P: Protocol> AppCore for DriverCore<P> {
    fn subscriptions(&self) -> Vec<Subscription> {
        self.driver
            .protocol
            .subscriptions()
            .into_iter()
            .map(Subscription::var)
            .collect()
    }

    fn on_startup(&mut self, _now: f64, _out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        if let Err(e) = self.driver.start() {
            notes.push(Note::Warning(format!("cannot start the link thread: {e}")));
        }
    }

    fn on_mail(&mut self, m: &Mail, now: f64, _out: &mut Vec<Post>, _notes: &mut Vec<Note>) {
        self.driver.on_mail(&m.key, &m.value, now, &mut self.io);
    }

    fn mail_done(&mut self, _now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        self.drain(out, notes);
    }

    fn iterate(&mut self, now: f64, out: &mut Vec<Post>, notes: &mut Vec<Note>) {
        self.driver.step(now, &mut self.io);
        self.drain(out, notes);
    }

    fn report(&self, _now: f64, body: &mut String) {
        self.driver.report(body);
    }

    fn stop(&mut self, _now: f64) -> AppResult {
        self.driver.stop();
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::antler::BuiltInApp;
    use crate::app::{App, Value};
    use std::io::{BufRead, BufReader, Write};
    use std::net::TcpListener;
    use std::time::{Duration, Instant};

    fn block(text: &str) -> ProcessConfig {
        crate::testing::block("d.moos", text)
    }

    #[test]
    fn bad_keys_are_warnings_at_their_lines_and_igps_wants_an_origin() {
        let b =
            block("ProcessConfig = iDVL\n{\n  AppTick = 10\n  port = seventy\n  colour = red\n}\n");
        let app = dvl("iDVL", b);
        let w: Vec<String> = app.warnings().iter().map(Diagnostic::located).collect();
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(w[0].contains("d.moos:4") && w[0].contains("port = seventy"));
        assert!(w[1].contains("d.moos:5") && w[1].contains("unknown parameter `colour`"));
        let g = gps(
            "iGPS",
            block("ProcessConfig = iGPS\n{\n  port = 2947\n}\n"),
            None,
        );
        assert_eq!(g.warnings().len(), 1);
        assert!(g.warnings()[0].located().contains("LatOrigin"));
        let subs: Vec<String> = dvl("iDVL", block("ProcessConfig = iDVL\n{\n}\n"))
            .subscriptions()
            .into_iter()
            .map(|s| s.pattern)
            .collect();
        assert!(subs.contains(&"DEPLOY".to_string()) && subs.contains(&"NAV_DEPTH".to_string()));
    }

    /// The app over a real loopback TCP link: a fake A50 answers the start-up command and
    /// sends a report; the app posts it and its status (bounded waits, no timing asserted).
    #[test]
    fn idvl_app_over_loopback_tcp() {
        let l = TcpListener::bind("127.0.0.1:0").unwrap();
        let port = l.local_addr().unwrap().port();
        let fake = std::thread::spawn(move || {
            let (s, _) = l.accept().unwrap();
            s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
            let mut r = BufReader::new(s.try_clone().unwrap());
            let mut line = String::new();
            r.read_line(&mut line).unwrap();
            let mut w = s;
            w.write_all(
                b"{\"response_to\":\"set_config\",\"success\":true,\"error_message\":\"\",\"result\":null,\"type\":\"response\"}\n\
                  {\"time\":100,\"vx\":0.5,\"vy\":0.0,\"vz\":0.1,\"fom\":0.01,\"altitude\":3.5,\"velocity_valid\":true,\"status\":0,\"type\":\"velocity\"}\n",
            )
            .unwrap();
            line
        });
        let b = block(&format!(
            "ProcessConfig = iDVL\n{{\n  host = 127.0.0.1\n  port = {port}\n}}\n"
        ));
        let mut app = dvl("iDVL", b);
        assert!(app.warnings().is_empty());
        let mut out = Vec::new();
        app.on_startup(0.0, &mut out).unwrap();
        let deadline = Instant::now() + Duration::from_secs(20);
        let mut t = 0.0;
        while !out.iter().any(|p| &*p.key == "DVL_VALID") {
            assert!(Instant::now() < deadline, "no report within the bound");
            t += 0.1;
            app.iterate(t, &mut out).unwrap();
            std::thread::sleep(Duration::from_millis(5));
        }
        let sent = fake.join().unwrap();
        assert!(sent.contains("\"acoustic_enabled\":false"), "{sent}");
        let get = |k: &str| out.iter().find(|p| &*p.key == k).map(|p| p.value.clone());
        assert_eq!(get("DVL_VEL_X"), Some(Value::Double(0.5)));
        assert_eq!(get("DVL_ACOUSTIC_ENABLED"), Some(Value::Double(0.0)));
        let status = out
            .iter()
            .rev()
            .find(|p| &*p.key == "DVL_DRIVER_STATUS")
            .and_then(|p| p.value.as_str().map(str::to_string))
            .unwrap();
        // The fake may have hung up by now: the link's state is not asserted.
        assert!(
            status.contains(",connects=1,")
                && status.contains(",velocity=1,")
                && status.contains(",acks=1,"),
            "{status}"
        );
        // The first iteration's appcast shows the link and the protocol's counters.
        let cast = out
            .iter()
            .find(|p| &*p.key == "APPCAST")
            .and_then(|p| p.value.as_str().map(str::to_string))
            .expect("an appcast at the first iteration");
        assert!(
            cast.contains(&format!("Link: tcp://127.0.0.1:{port}")),
            "{cast}"
        );
        assert!(
            cast.contains("Lines  Garbage  Oversize  BadChecksum  ParseErrors"),
            "{cast}"
        );
        app.stop(t).unwrap();
    }
}
