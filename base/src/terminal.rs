//! The base station's one I/O edge: the MOOS client's mail into the [`Console`], keys from
//! the terminal (crossterm, through ratatui), the console's postings out as the client.

use std::time::Duration;

use ratatui::crossterm::event::{self, Event, KeyCode, KeyEventKind, KeyModifiers};

use crate::console::{Console, Key};

/// Registers the variables the base reads ([`crate::READS`]).
pub fn subscribe(client: &moosdb::Client) {
    for var in crate::READS {
        client.register(var, 0.0);
    }
}

/// Hands every mail waiting on `mail` to the console (numbers are not part of the
/// interface and are skipped). Returns how many were taken.
pub fn drain(console: &mut Console, mail: &mut moosdb::MailStream) -> usize {
    let mut n = 0;
    while let Some(m) = mail.try_recv() {
        if !m.is_double() {
            console.mail(&m.key_str(), &m.sval_str());
        }
        n += 1;
    }
    n
}

/// Posts a console's postings as the client; a failed post is noted on the console.
pub fn post(console: &mut Console, client: &moosdb::Client, posts: Vec<crate::console::Posting>) {
    for (var, value) in posts {
        if let Err(e) = client.notify(&var, moosdb::Value::text(value.as_str())) {
            console.mail("coug_base", &format!("post failed: {e}"));
        }
    }
}

fn key(ev: &event::KeyEvent) -> Option<Key> {
    if ev.kind == KeyEventKind::Release {
        return None;
    }
    match ev.code {
        KeyCode::Char('c') if ev.modifiers.contains(KeyModifiers::CONTROL) => Some(Key::Interrupt),
        KeyCode::Char(c) => Some(Key::Char(c)),
        KeyCode::Enter => Some(Key::Enter),
        KeyCode::Backspace => Some(Key::Backspace),
        KeyCode::Esc => Some(Key::Esc),
        _ => None,
    }
}

/// Runs the console in the terminal (alternate screen, raw mode) until the operator quits
/// or `stop` is set (a signal): redraws at least every 250 ms (ages move), takes keys and
/// mail as they come, and gives the terminal back as it found it. The client must be
/// connected and live on a runtime other threads drive. Returns the number of commands
/// posted.
pub fn run(
    client: &moosdb::Client,
    mail: &mut moosdb::MailStream,
    stop: &std::sync::atomic::AtomicBool,
) -> std::io::Result<u64> {
    subscribe(client);
    let mut console = Console::new();
    let mut terminal = ratatui::init();
    let result = (|| -> std::io::Result<()> {
        while !console.quit() && !stop.load(std::sync::atomic::Ordering::Relaxed) {
            drain(&mut console, mail);
            let now = client.moos_time();
            terminal.draw(|f| console.render(f, now))?;
            if event::poll(Duration::from_millis(250))?
                && let Event::Key(ev) = event::read()?
                && let Some(k) = key(&ev)
            {
                let posts: Vec<_> = console.key(k).into_iter().collect();
                post(&mut console, client, posts);
            }
        }
        Ok(())
    })();
    ratatui::restore();
    result.map(|()| console.sent())
}
