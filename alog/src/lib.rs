//! pLogger's alog format (MOOS-IvP `.alog` files): a byte-exact [`AlogWriter`] over any
//! [`std::io::Write`], a [`parse`] / [`parse_line`] reader, and the log naming helpers.
//!
//! Everything here is pure formatting: no clock is read. The log start time and the
//! "opened on" text are arguments, so the same inputs always give the same bytes.
//!
//! ```
//! use alog::{AlogWriter, Header, LogValue};
//! let header = Header { path: "./LOG_A/LOG_A.alog", opened_on: "Thu Jan  1 00:00:00 1970",
//!                       log_start: 1000.0, mark_data_type: false };
//! let mut w = AlogWriter::new(Vec::new(), &header).unwrap();
//! w.record(1012.5, "NAV_X", "uSimMarine", LogValue::Double(-23.1)).unwrap();
//! let text = String::from_utf8(w.into_inner()).unwrap();
//! assert!(text.ends_with("12.50000        NAV_X                uSimMarine      -23.10000    \n"));
//! let log = alog::parse(&text).unwrap();
//! assert_eq!(log.log_start, Some(1000.0));
//! assert_eq!(log.entries[0].value, alog::Value::Double(-23.1));
//! ```
#![warn(missing_docs)]

mod naming;
mod reader;
mod writer;

pub use naming::{ctime, log_root};
pub use reader::{
    Alog, AlogError, Entry, Value, field, parse, parse_double, parse_line, parse_time, parse_value,
};
pub use writer::{AlogWriter, BANNER_RULE, Header, Line, LogValue, RecordCache, banner};
