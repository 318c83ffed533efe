//! The base station's screen and keyboard, without a terminal: keys in, postings out, and
//! the ratatui rendering (tested on ratatui's `TestBackend`).
//!
//! The operator types a command ([`crate::command`]) and presses Enter. Kill and abort are
//! posted at once; a command that moves a vehicle (surface, return, go-to, loiter, depth) is
//! only shown with its details and posted when the operator then presses `y` (`n` or Esc
//! cancels, nothing is posted). `q` or `quit` on an empty line, or Ctrl-C, ends the
//! program.

use std::collections::VecDeque;

use ratatui::Frame;
use ratatui::layout::{Constraint, Layout};
use ratatui::style::{Color, Modifier, Style};
use ratatui::text::Line;
use ratatui::widgets::{Block, Borders, Cell, Paragraph, Row, Table};

use crate::command::{COMMAND_VAR, Request, parse};
use crate::fleet::{Fleet, Source, Vehicle};

/// A key the console understands (the terminal edge maps crossterm's events to these).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Key {
    /// A printable character.
    Char(char),
    /// Enter.
    Enter,
    /// Backspace.
    Backspace,
    /// Escape.
    Esc,
    /// Ctrl-C.
    Interrupt,
}

/// A posting the console asks for: `(variable, string value)`.
pub type Posting = (String, String);

/// Seconds after which a vehicle's age is shown in yellow.
pub const LATE_S: f64 = 30.0;
/// Seconds after which it is shown in red.
pub const LOST_S: f64 = 120.0;

const NOTES_KEPT: usize = 50;

/// The console's state.
#[derive(Debug, Clone, Default)]
pub struct Console {
    /// The fleet as the mail made it.
    pub fleet: Fleet,
    input: String,
    pending: Option<Request>,
    notes: VecDeque<String>,
    quit: bool,
    sent: u64,
}

impl Console {
    /// An empty console.
    pub fn new() -> Console {
        Console::default()
    }

    /// Takes one mail into the fleet; mail it cannot read is noted, and so is every
    /// command acknowledgement (the operator sees a command queued, sent, confirmed or
    /// timed out).
    pub fn mail(&mut self, var: &str, value: &str) {
        match self.fleet.apply(var, value) {
            Err(e) => self.note(format!("{var}: {e}")),
            Ok(()) if var == crate::fleet::ACK_VAR => {
                self.note(format!("{var} = {value}"));
            }
            Ok(()) => {}
        }
    }

    /// The line being typed.
    pub fn input(&self) -> &str {
        &self.input
    }

    /// The command awaiting confirmation.
    pub fn pending(&self) -> Option<&Request> {
        self.pending.as_ref()
    }

    /// The notes shown under the table, oldest first.
    pub fn notes(&self) -> impl Iterator<Item = &str> {
        self.notes.iter().map(String::as_str)
    }

    /// True once the operator asked to leave.
    pub fn quit(&self) -> bool {
        self.quit
    }

    /// Commands posted so far.
    pub fn sent(&self) -> u64 {
        self.sent
    }

    fn note(&mut self, s: String) {
        if self.notes.len() == NOTES_KEPT {
            self.notes.pop_front();
        }
        self.notes.push_back(s);
    }

    fn send(&mut self, r: Request) -> Option<Posting> {
        let value = r.to_value();
        self.sent += 1;
        self.note(format!("sent {COMMAND_VAR} = {value}"));
        Some((COMMAND_VAR.to_string(), value))
    }

    /// Takes one key; returns the posting it causes, if any.
    pub fn key(&mut self, key: Key) -> Option<Posting> {
        if key == Key::Interrupt {
            self.quit = true;
            return None;
        }
        if let Some(r) = self.pending.take() {
            return match key {
                Key::Char('y' | 'Y') => self.send(r),
                Key::Char('n' | 'N') | Key::Esc => {
                    self.note(format!("cancelled: {}", r.describe()));
                    None
                }
                _ => {
                    // Anything else leaves the question open.
                    self.pending = Some(r);
                    None
                }
            };
        }
        match key {
            Key::Char(c) => {
                self.input.push(c);
                None
            }
            Key::Backspace => {
                self.input.pop();
                None
            }
            Key::Esc => {
                self.input.clear();
                None
            }
            Key::Enter => {
                let line = std::mem::take(&mut self.input);
                self.enter(line.trim())
            }
            Key::Interrupt => None,
        }
    }

    /// Types `text` then Enter (tests, scripts).
    pub fn type_line(&mut self, text: &str) -> Vec<Posting> {
        let mut out: Vec<Posting> = text
            .chars()
            .filter_map(|c| self.key(Key::Char(c)))
            .collect();
        out.extend(self.key(Key::Enter));
        out
    }

    fn enter(&mut self, line: &str) -> Option<Posting> {
        match line {
            "" => None,
            "q" | "quit" | "exit" => {
                self.quit = true;
                None
            }
            "h" | "help" | "?" => {
                self.note(
                    "kill V | abort V | surface V | return V | goto V X Y | loiter V X Y [R] | \
                     depth V D   (V: modem id or name; moving commands ask y/n)"
                        .to_string(),
                );
                None
            }
            _ => match parse(line, &self.fleet) {
                Ok(r) if r.command.moves_vehicle() => {
                    self.note(format!("confirm {}? y/n", r.describe()));
                    self.pending = Some(r);
                    None
                }
                Ok(r) => self.send(r),
                Err(e) => {
                    self.note(format!("{line}: {e}"));
                    None
                }
            },
        }
    }

    /// Draws the console at MOOS time `now` (ages are `now` minus each vehicle's last
    /// answer).
    pub fn render(&self, frame: &mut Frame, now: f64) {
        let [table_area, notes_area, input_area] = Layout::vertical([
            Constraint::Min(4),
            Constraint::Length(6),
            Constraint::Length(3),
        ])
        .areas(frame.area());
        let header = Row::new(COLUMNS.iter().map(|c| Cell::from(*c)))
            .style(Style::default().add_modifier(Modifier::BOLD));
        let rows: Vec<Row> = self
            .fleet
            .vehicles()
            .values()
            .map(|v| row(v, now))
            .collect();
        let widths = WIDTHS.map(Constraint::Length);
        let table = Table::new(rows, widths).header(header).block(
            Block::default().borders(Borders::ALL).title(format!(
                " coug base: {} vehicles ",
                self.fleet.vehicles().len()
            )),
        );
        frame.render_widget(table, table_area);
        let shown = notes_area.height.saturating_sub(2) as usize;
        let notes: Vec<Line> = self
            .notes
            .iter()
            .skip(self.notes.len().saturating_sub(shown))
            .map(|n| Line::from(n.as_str()))
            .collect();
        frame.render_widget(
            Paragraph::new(notes).block(Block::default().borders(Borders::ALL).title(" notes ")),
            notes_area,
        );
        let (title, text, style) = match &self.pending {
            Some(r) => (
                " confirm: y sends, n cancels ",
                r.describe(),
                Style::default().fg(Color::Yellow),
            ),
            None => (
                " command (h: help, q: quit) ",
                format!("> {}", self.input),
                Style::default(),
            ),
        };
        frame.render_widget(
            Paragraph::new(text)
                .style(style)
                .block(Block::default().borders(Borders::ALL).title(title)),
            input_area,
        );
    }

    /// The screen as text, `width` x `height` cells, one line per row, trailing blanks
    /// trimmed (rendered on ratatui's `TestBackend`).
    pub fn render_text(&self, now: f64, width: u16, height: u16) -> String {
        let backend = ratatui::backend::TestBackend::new(width, height);
        let mut term = ratatui::Terminal::new(backend).expect("a test backend never fails");
        term.draw(|f| self.render(f, now))
            .expect("a test backend never fails");
        let buf = term.backend().buffer();
        let mut out = String::new();
        for y in 0..buf.area.height {
            let mut line = String::new();
            for x in 0..buf.area.width {
                line.push_str(buf[(x, y)].symbol());
            }
            out.push_str(line.trim_end());
            out.push('\n');
        }
        out
    }
}

const COLUMNS: [&str; 12] = [
    "ID",
    "NAME",
    "AGE",
    "LINK",
    "X",
    "Y",
    "DEPTH",
    "HDG",
    "SPD",
    "BATT",
    "HEALTH",
    "LAST COMMAND",
];
const WIDTHS: [u16; 12] = [4, 10, 7, 15, 8, 8, 6, 4, 4, 5, 7, 24];

/// `12s`, `3m04s`, `2h05m`.
pub fn age_text(s: f64) -> String {
    let s = s.max(0.0).round() as u64;
    if s < 60 {
        format!("{s}s")
    } else if s < 3600 {
        format!("{}m{:02}s", s / 60, s % 60)
    } else {
        format!("{}h{:02}m", s / 3600, (s % 3600) / 60)
    }
}

fn opt(v: Option<f64>, prec: usize) -> String {
    v.map_or_else(|| "-".to_string(), |v| format!("{v:.prec$}"))
}

fn row(v: &Vehicle, now: f64) -> Row<'static> {
    let age = v.age(now);
    let age_style = match age {
        Some(a) if a > LOST_S => Style::default().fg(Color::Red),
        Some(a) if a > LATE_S => Style::default().fg(Color::Yellow),
        Some(_) => Style::default(),
        None => Style::default().fg(Color::DarkGray),
    };
    let link = match (&v.acoustic, v.link_ratio()) {
        (Some(a), Some(r)) => format!(
            "{}/{} {:.0}% t{}",
            a.answers,
            a.polls,
            r * 100.0,
            a.timeouts
        ),
        (Some(_), None) => "no poll".to_string(),
        (None, _) => "radio".to_string(),
    };
    let fix = v.fix();
    let src = match fix.map(|f| f.source) {
        Some(Source::Acoustic) => "",
        Some(Source::NodeReport) => "*",
        None => "",
    };
    let acoustic = v.acoustic.as_ref();
    let last = v
        .ack
        .as_ref()
        .map_or_else(String::new, |a| format!("{} #{} {}", a.cmd, a.seq, a.state));
    Row::new(vec![
        Cell::from(v.id.map_or_else(|| "-".to_string(), |i| i.to_string())),
        Cell::from(v.name.clone()),
        Cell::from(age.map_or_else(|| "never".to_string(), age_text)).style(age_style),
        Cell::from(link),
        Cell::from(format!("{}{src}", opt(fix.map(|f| f.x), 1))),
        Cell::from(opt(fix.map(|f| f.y), 1)),
        Cell::from(opt(fix.and_then(|f| f.depth), 1)),
        Cell::from(opt(fix.and_then(|f| f.heading), 0)),
        Cell::from(opt(fix.and_then(|f| f.speed), 1)),
        Cell::from(opt(acoustic.and_then(|a| a.battery_v), 1)),
        Cell::from(acoustic.map_or_else(String::new, |a| a.health.clone())),
        Cell::from(last),
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn console() -> Console {
        let mut c = Console::new();
        c.mail(
            "ACOMMS_VEHICLE",
            "id=3,name=coug3,time=50,x=1,y=2,depth=3,heading=4,speed=0.5,battery_v=15,\
             health=0x0,polls=2,answers=2,timeouts=0",
        );
        c
    }

    #[test]
    fn a_moving_command_waits_for_y_and_n_cancels_it() {
        let mut c = console();
        assert!(c.type_line("goto 3 10 20").is_empty());
        assert!(c.pending().is_some());
        assert_eq!(c.key(Key::Char('x')), None, "other keys leave it pending");
        assert!(c.pending().is_some());
        assert_eq!(c.key(Key::Char('n')), None);
        assert!(c.pending().is_none());
        assert!(c.type_line("goto 3 10 20").is_empty());
        assert_eq!(
            c.key(Key::Char('y')),
            Some(("ACOMMS_COMMAND".into(), "to=3,cmd=goto,x=10,y=20".into()))
        );
        assert_eq!(
            c.type_line("abort coug3"),
            vec![("ACOMMS_COMMAND".to_string(), "to=3,cmd=abort".to_string())]
        );
        assert_eq!(c.sent(), 2);
        assert!(c.type_line("abort 4").is_empty());
        assert!(c.notes().last().unwrap().contains("no vehicle \"4\""));
        c.type_line("q");
        assert!(c.quit());
    }

    #[test]
    fn ages_read() {
        assert_eq!(age_text(0.4), "0s");
        assert_eq!(age_text(184.0), "3m04s");
        assert_eq!(age_text(7500.0), "2h05m");
    }
}
