//! The MOOS data every coug crate exchanges: a variable's [`Value`] (a double, a string or
//! binary data, as a `CMOOSMsg` carries), a borrowed view of one ([`ValueRef`]), a message an
//! app receives ([`Mail`]) and one it publishes ([`Post`]).
//!
//! This crate sits at the bottom of the workspace: it depends only on `bytes` (the wire
//! codec's buffer type) and `bytestring`, and the wire codec, the DB, the helm, the
//! behaviours, the vehicle apps and the logger all speak these types, so no layer translates
//! between private copies of them.
//!
//! A [`Mail`]'s names ([`Mail::key`], [`Mail::source`], ...), a [`Post`]'s names and a
//! string [`Value`] are [`ByteString`]s: UTF-8 text over a shared [`Bytes`] buffer (the wire
//! codec's buffer type). The DB hands the same message to every subscriber, and a mail made
//! from it shares the message's buffers, so delivering it copies no text and allocates
//! nothing; cloning a mail, a post or a value is a reference-count increment per string.
//!
//! ```
//! use moos_types::{Mail, Post, Value};
//! let m = Mail::new("DEPLOY", "true", 12.5).from("uPokeDB");
//! assert_eq!(m.value.as_str(), Some("true"));
//! let p = Post::double("DESIRED_SPEED", 1.5).with_aux("7:cruise");
//! assert_eq!(p.value, Value::Double(1.5));
//! ```

#![warn(missing_docs)]

pub mod fmt;
pub mod node_record;
pub mod text;

pub use bytes::Bytes;
pub use bytestring::ByteString;

use std::fmt as stdfmt;

/// A MOOS variable's value.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// A double (`'D'`).
    Double(f64),
    /// A string (`'S'`): shared text, so copies of a value (a message delivered to many
    /// apps, a posting kept by the helm) share one buffer.
    String(ByteString),
    /// Binary data (`'B'`).
    Binary(Vec<u8>),
}

impl Value {
    /// The double, if this is one.
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            Value::Double(x) => Some(*x),
            _ => None,
        }
    }

    /// The string, if this is one.
    pub fn as_str(&self) -> Option<&str> {
        match self {
            Value::String(s) => Some(s),
            _ => None,
        }
    }

    /// A string value (see [`IntoText`]).
    pub fn text(s: impl IntoText) -> Value {
        Value::String(s.into_text())
    }

    /// The borrowed view.
    pub fn as_ref(&self) -> ValueRef<'_> {
        match self {
            Value::Double(x) => ValueRef::Double(*x),
            Value::String(s) => ValueRef::String(s),
            Value::Binary(b) => ValueRef::Binary(b),
        }
    }
}

impl From<f64> for Value {
    fn from(v: f64) -> Self {
        Value::Double(v)
    }
}

impl From<&str> for Value {
    fn from(v: &str) -> Self {
        Value::String(v.into())
    }
}

impl From<String> for Value {
    fn from(v: String) -> Self {
        Value::String(v.into())
    }
}

impl From<ByteString> for Value {
    fn from(v: ByteString) -> Self {
        Value::String(v)
    }
}

impl stdfmt::Display for Value {
    /// Doubles as Rust prints them, strings as they are, binary data as `<N bytes>`.
    fn fmt(&self, f: &mut stdfmt::Formatter<'_>) -> stdfmt::Result {
        match self {
            Value::Double(x) => write!(f, "{x}"),
            Value::String(s) => f.write_str(s),
            Value::Binary(b) => write!(f, "<{} bytes>", b.len()),
        }
    }
}

/// A borrowed MOOS value (mail handed to an app without a copy).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ValueRef<'a> {
    /// A double.
    Double(f64),
    /// A string.
    String(&'a str),
    /// Binary data.
    Binary(&'a [u8]),
}

impl<'a> ValueRef<'a> {
    /// The double, or a string that reads as a number (trimmed), as the MOOS apps take
    /// numeric mail posted as text.
    pub fn as_f64(&self) -> Option<f64> {
        match *self {
            ValueRef::Double(x) => Some(x),
            ValueRef::String(s) => s.trim().parse().ok(),
            ValueRef::Binary(_) => None,
        }
    }

    /// The string, if this is one.
    pub fn as_str(&self) -> Option<&'a str> {
        match *self {
            ValueRef::String(s) => Some(s),
            _ => None,
        }
    }

    /// An owned copy.
    pub fn to_owned(&self) -> Value {
        match *self {
            ValueRef::Double(x) => Value::Double(x),
            ValueRef::String(s) => Value::String(s.into()),
            ValueRef::Binary(b) => Value::Binary(b.to_vec()),
        }
    }
}

/// A message delivered to an app. Its names share their buffers with the message the DB
/// delivered (see the crate documentation); they read as `&str` (`Deref`) and compare with
/// `&str` and `String` (`mail.key == "DEPLOY"`).
#[derive(Debug, Clone, PartialEq)]
pub struct Mail {
    /// Variable name.
    pub key: ByteString,
    /// Value.
    pub value: Value,
    /// MOOS time of the write, seconds.
    pub time: f64,
    /// The writer's MOOS name.
    pub source: ByteString,
    /// The writer's auxiliary source field (the helm's `<iter>:<behaviour>`,
    /// `HELM_VAR_INIT`, ...).
    pub source_aux: ByteString,
    /// The writer's community.
    pub community: ByteString,
}

impl Mail {
    /// Mail with no source, aux or community.
    pub fn new(key: &str, value: impl Into<Value>, time: f64) -> Mail {
        Mail {
            key: ByteString::from(key),
            value: value.into(),
            time,
            source: ByteString::new(),
            source_aux: ByteString::new(),
            community: ByteString::new(),
        }
    }

    /// Builder: sets the source.
    pub fn from(mut self, source: &str) -> Mail {
        self.source = ByteString::from(source);
        self
    }

    /// Builder: sets the auxiliary source field.
    pub fn with_aux(mut self, aux: &str) -> Mail {
        self.source_aux = ByteString::from(aux);
        self
    }
}

/// UTF-8 text over `bytes` without a copy (a reference-count increment when `bytes` is
/// shared); text that is not UTF-8 is copied lossily (U+FFFD for bad sequences), as MOOS
/// strings read from the wire need not be UTF-8.
///
/// ```
/// use moos_types::{Bytes, text_of};
/// assert_eq!(text_of(&Bytes::from_static(b"NAV_X")), "NAV_X");
/// assert_eq!(text_of(&Bytes::from_static(b"a\xffb")), "a\u{fffd}b");
/// ```
pub fn text_of(bytes: &Bytes) -> ByteString {
    ByteString::try_from(bytes.clone())
        .unwrap_or_else(|_| ByteString::from(String::from_utf8_lossy(bytes).into_owned()))
}

/// A value an app publishes. Its names are [`ByteString`]s, so an app that keeps its
/// variable names as `ByteString`s posts them without a copy, and the bus hands their
/// buffers on to the DB.
#[derive(Debug, Clone, PartialEq)]
pub struct Post {
    /// Variable name.
    pub key: ByteString,
    /// Value.
    pub value: Value,
    /// The source to publish under, if not the app's own name (empty: the app's).
    pub source: ByteString,
    /// Auxiliary source field.
    pub aux: ByteString,
    /// For a message relayed from another community (pShare): the time and community it
    /// was written with, kept instead of the poster's (`None` for the apps' own posts).
    pub relayed: Option<Box<Relayed>>,
}

/// The fields a relayed [`Post`] keeps from the message it relays (as a C++ pShare posts
/// with the source kept and the DB keeps a non-empty originating community).
#[derive(Debug, Clone, PartialEq)]
pub struct Relayed {
    /// MOOS time of the original write.
    pub time: f64,
    /// The community it was written in.
    pub community: ByteString,
}

impl Post {
    /// A posting of `value` to `key` (see [`IntoText`]: a `ByteString` key is shared, not
    /// copied).
    pub fn new(key: impl IntoText, value: Value) -> Post {
        Post {
            key: key.into_text(),
            value,
            source: ByteString::new(),
            aux: ByteString::new(),
            relayed: None,
        }
    }

    /// Builder: sets the auxiliary source field.
    pub fn with_aux(mut self, aux: impl IntoText) -> Post {
        self.aux = aux.into_text();
        self
    }

    /// A double posting.
    pub fn double(key: impl IntoText, x: f64) -> Post {
        Post::new(key, Value::Double(x))
    }

    /// A string posting.
    pub fn text(key: impl IntoText, s: impl IntoText) -> Post {
        Post::new(key, Value::text(s))
    }
}

/// Text that becomes a [`ByteString`] name: `&str`, `&String` (copied) and `String` (its
/// buffer kept), or a `ByteString` / `&ByteString` (shared: a reference count, no copy).
///
/// ```
/// use moos_types::{ByteString, IntoText, Post};
/// let key = ByteString::from_static("NAV_X");
/// let p = Post::double(&key, 1.0);
/// assert_eq!(p.key, "NAV_X");
/// assert_eq!(p.key.as_bytes().as_ptr(), key.as_bytes().as_ptr(), "shared, not copied");
/// assert_eq!("X".into_text(), String::from("X").into_text());
/// ```
pub trait IntoText {
    /// The text as a `ByteString`.
    fn into_text(self) -> ByteString;
}

impl IntoText for &str {
    fn into_text(self) -> ByteString {
        ByteString::from(self)
    }
}

impl IntoText for String {
    fn into_text(self) -> ByteString {
        ByteString::from(self)
    }
}

impl IntoText for &String {
    fn into_text(self) -> ByteString {
        ByteString::from(self.as_str())
    }
}

impl IntoText for ByteString {
    fn into_text(self) -> ByteString {
        self
    }
}

impl IntoText for &ByteString {
    fn into_text(self) -> ByteString {
        self.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn views_and_conversions_agree() {
        let v = Value::from(2.5);
        assert_eq!(v.as_f64(), Some(2.5));
        assert_eq!(v.as_str(), None);
        assert_eq!(v.as_ref().to_owned(), v);
        let s = Value::from(" 3.25 ");
        assert_eq!(s.as_f64(), None, "an owned string is not a double");
        assert_eq!(
            s.as_ref().as_f64(),
            Some(3.25),
            "mail text that reads as a number"
        );
        assert_eq!(Value::text("x").to_string(), "x");
        assert_eq!(Value::Binary(vec![1, 2]).to_string(), "<2 bytes>");
        assert_eq!(ValueRef::Binary(&[1]).as_f64(), None);
    }
}
