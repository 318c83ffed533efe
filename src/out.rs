//! Writing to stdout and stderr the way Unix tools do: a closed pipe (`coug check ... | head`)
//! ends the program quietly instead of panicking, as `println!` does. Every command prints
//! through `outln!`, `out!` and `errln!`; the print macros of `std` are denied in this binary
//! (see `main.rs`).

use std::fmt;
use std::io::{self, Write};

/// Where a line goes.
#[derive(Debug, Clone, Copy)]
pub enum Stream {
    /// Standard output.
    Out,
    /// Standard error.
    Err,
}

/// Writes `args` to `stream`. A closed reader (EPIPE) ends the process at once with status 0,
/// the normal end of a pipeline whose reader has seen enough; any other write error ends it
/// with status 1 (a failing terminal or disk is not ignored).
pub fn write(stream: Stream, args: fmt::Arguments<'_>) {
    let result = match stream {
        Stream::Out => {
            let mut o = io::stdout().lock();
            o.write_fmt(args).and_then(|()| o.flush())
        }
        Stream::Err => io::stderr().lock().write_fmt(args),
    };
    if let Err(e) = result {
        std::process::exit(exit_code(&e));
    }
}

/// The exit status for a failed write: 0 for a closed pipe, 1 otherwise.
fn exit_code(e: &io::Error) -> i32 {
    if e.kind() == io::ErrorKind::BrokenPipe {
        0
    } else {
        1
    }
}

/// `println!` to stdout that ends quietly on a closed pipe.
macro_rules! outln {
    () => { $crate::out::write($crate::out::Stream::Out, format_args!("\n")) };
    ($($t:tt)*) => { $crate::out::write($crate::out::Stream::Out, format_args!("{}\n", format_args!($($t)*))) };
}

/// `print!` to stdout that ends quietly on a closed pipe.
macro_rules! out {
    ($($t:tt)*) => { $crate::out::write($crate::out::Stream::Out, format_args!($($t)*)) };
}

/// `eprintln!` to stderr that ends quietly on a closed pipe.
macro_rules! errln {
    () => { $crate::out::write($crate::out::Stream::Err, format_args!("\n")) };
    ($($t:tt)*) => { $crate::out::write($crate::out::Stream::Err, format_args!("{}\n", format_args!($($t)*))) };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_closed_pipe_is_a_normal_end_other_errors_are_not() {
        assert_eq!(exit_code(&io::Error::from(io::ErrorKind::BrokenPipe)), 0);
        assert_eq!(exit_code(&io::Error::other("disk full")), 1);
    }
}
