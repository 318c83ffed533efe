//! One MOOS message (`CMOOSMsg` on the wire): its type codes, fields and byte layout.
//!
//! Layout (little-endian; a "string" is an `i32` length followed by that many raw bytes, no NUL,
//! not necessarily UTF-8):
//!
//! ```text
//! i32 length (whole message, this field included) | i32 id | u8 type | u8 data type
//! string src | string src_aux | string community | string key
//! f64 time | f64 dval | f64 dval2 | string sval
//! ```

use std::borrow::Cow;

use bytes::Bytes;

use crate::error::DecodeError;

/// Bytes of a message with five empty strings: 4 + 4 + 1 + 1 + 5×4 + 3×8.
pub const MESSAGE_FIXED_LEN: usize = 54;

/// Message id used by messages that do not go through the client's counter (`'i'`, `'T'`,
/// replays of a current value).
pub const NO_ID: i32 = -1;

/// Message id of server requests and of the DB's replies to them (`MOOS_SERVER_REQUEST_ID`).
pub const SERVER_REQUEST_ID: i32 = -2;

/// Handshake key of an asynchronous (V10) client, and the Welcome's string value of a V10 DB.
pub const ASYNCHRONOUS: &str = "asynchronous";

/// Key of the asynchronous timing (heartbeat / skew probe) message.
pub const ASYNC_TIMING_KEY: &str = "_async_timing";

/// The message type code (`m_cMsgType`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MsgType {
    /// `'N'`: publish a value (client to DB) or deliver mail (DB to client).
    Notify,
    /// `'R'`: subscribe to a variable; `dval` is the minimum interval in seconds.
    Register,
    /// `'U'`: unsubscribe from a variable.
    Unregister,
    /// `'*'`: subscribe by pattern; `sval` is `AppPattern=..,VarPattern=..,Interval=..`.
    WildcardRegister,
    /// `'/'`: unsubscribe by pattern (same `sval` format).
    WildcardUnregister,
    /// `'.'`: keep-alive of synchronous clients; carries the DB time in replies to them.
    Null,
    /// `'i'`: the handshake's name message.
    Data,
    /// `'W'`: the DB's handshake acceptance.
    Welcome,
    /// `'K'`: the DB's handshake rejection (reason in `sval`).
    Poison,
    /// `'Q'`: a server request (`ALL`, `VAR_SUMMARY`, `PROC_SUMMARY`, `DB_CLEAR`), id -2.
    ServerRequest,
    /// `'T'`: the asynchronous timing message.
    Timing,
    /// `'C'`: command (accepted and ignored by the DB).
    Command,
    /// `'A'`: anonymous (defined, unused).
    Anonymous,
    /// `'~'`: "not set".
    NotSet,
    /// `'^'`: terminate connection (a client-internal sentinel; never expected on the wire).
    TerminateConnection,
}

impl MsgType {
    /// Every message type, in table order.
    pub const ALL: [MsgType; 15] = [
        MsgType::Notify,
        MsgType::Register,
        MsgType::Unregister,
        MsgType::WildcardRegister,
        MsgType::WildcardUnregister,
        MsgType::Null,
        MsgType::Data,
        MsgType::Welcome,
        MsgType::Poison,
        MsgType::ServerRequest,
        MsgType::Timing,
        MsgType::Command,
        MsgType::Anonymous,
        MsgType::NotSet,
        MsgType::TerminateConnection,
    ];

    /// The one-byte wire code, e.g. `b'N'`.
    pub const fn code(self) -> u8 {
        match self {
            MsgType::Notify => b'N',
            MsgType::Register => b'R',
            MsgType::Unregister => b'U',
            MsgType::WildcardRegister => b'*',
            MsgType::WildcardUnregister => b'/',
            MsgType::Null => b'.',
            MsgType::Data => b'i',
            MsgType::Welcome => b'W',
            MsgType::Poison => b'K',
            MsgType::ServerRequest => b'Q',
            MsgType::Timing => b'T',
            MsgType::Command => b'C',
            MsgType::Anonymous => b'A',
            MsgType::NotSet => b'~',
            MsgType::TerminateConnection => b'^',
        }
    }

    /// The type of a wire code, or `None` for a byte that is not a MOOS message type.
    pub const fn from_code(code: u8) -> Option<MsgType> {
        Some(match code {
            b'N' => MsgType::Notify,
            b'R' => MsgType::Register,
            b'U' => MsgType::Unregister,
            b'*' => MsgType::WildcardRegister,
            b'/' => MsgType::WildcardUnregister,
            b'.' => MsgType::Null,
            b'i' => MsgType::Data,
            b'W' => MsgType::Welcome,
            b'K' => MsgType::Poison,
            b'Q' => MsgType::ServerRequest,
            b'T' => MsgType::Timing,
            b'C' => MsgType::Command,
            b'A' => MsgType::Anonymous,
            b'~' => MsgType::NotSet,
            b'^' => MsgType::TerminateConnection,
            _ => return None,
        })
    }
}

/// The data type code (`m_cDataType`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DataType {
    /// `'D'`: the value is `dval`.
    Double,
    /// `'S'`: the value is `sval`, a string.
    String,
    /// `'B'`: the value is `sval`, binary bytes.
    Binary,
    /// `'~'`: a DB variable registered for but never written (seen in `ALL` replies).
    NotSet,
}

impl DataType {
    /// The one-byte wire code, e.g. `b'D'`.
    pub const fn code(self) -> u8 {
        match self {
            DataType::Double => b'D',
            DataType::String => b'S',
            DataType::Binary => b'B',
            DataType::NotSet => b'~',
        }
    }

    /// The data type of a wire code, or `None`.
    pub const fn from_code(code: u8) -> Option<DataType> {
        Some(match code {
            b'D' => DataType::Double,
            b'S' => DataType::String,
            b'B' => DataType::Binary,
            b'~' => DataType::NotSet,
            _ => return None,
        })
    }
}

/// A value to publish: the workspace's one MOOS value type (a string's or binary value's
/// buffer becomes the message's without a copy).
pub use moos_types::Value;
use moos_types::{Mail, text_of};

/// One MOOS message with every wire field.
///
/// The five strings are [`Bytes`] so that a decoded message shares its packet's buffer and
/// copies handed to many subscribers cost no allocation.
#[derive(Debug, Clone, PartialEq)]
pub struct Message {
    /// Message id (`m_nID`).
    pub id: i32,
    /// Message type.
    pub msg_type: MsgType,
    /// Data type.
    pub data_type: DataType,
    /// Source: the writer's MOOS name.
    pub src: Bytes,
    /// Auxiliary source information.
    pub src_aux: Bytes,
    /// Originating community (filled by the DB when empty).
    pub community: Bytes,
    /// Variable name.
    pub key: Bytes,
    /// Time stamp (MOOS time, seconds).
    pub time: f64,
    /// Double value.
    pub dval: f64,
    /// Second double (timing messages, `ALL` replies).
    pub dval2: f64,
    /// String or binary value.
    pub sval: Bytes,
}

fn text(s: &str) -> Bytes {
    Bytes::copy_from_slice(s.as_bytes())
}

impl Message {
    /// A message with the `CMOOSMsg` defaults: id -1, time/dval/dval2 -1, empty strings.
    pub fn new(msg_type: MsgType, data_type: DataType, key: &str) -> Message {
        Message {
            id: NO_ID,
            msg_type,
            data_type,
            src: Bytes::new(),
            src_aux: Bytes::new(),
            community: Bytes::new(),
            key: text(key),
            time: -1.0,
            dval: -1.0,
            dval2: -1.0,
            sval: Bytes::new(),
        }
    }

    /// A notify of `value` to `key` at `time` (src, id left for the sender to fill).
    ///
    /// ```
    /// use moos_wire::{Message, Value};
    /// let m = Message::notify("DESIRED_SPEED", Value::Double(1.5), 10.0);
    /// assert_eq!(m.dval, 1.5);
    /// ```
    pub fn notify(key: &str, value: Value, time: f64) -> Message {
        let mut m = Message::new(MsgType::Notify, DataType::Double, key);
        m.time = time;
        match value {
            Value::Double(v) => m.dval = v,
            Value::String(s) => {
                m.data_type = DataType::String;
                m.sval = s.into_bytes();
            }
            Value::Binary(b) => {
                m.data_type = DataType::Binary;
                m.sval = Bytes::from(b);
            }
        }
        m
    }

    /// The value carried by this message, by its data type (`None` for `'~'`): a string
    /// shares the message's buffer (one that is not UTF-8 is copied lossily), binary data is
    /// copied.
    pub fn value(&self) -> Option<Value> {
        match self.data_type {
            DataType::Double => Some(Value::Double(self.dval)),
            DataType::String => Some(Value::String(text_of(&self.sval))),
            DataType::Binary => Some(Value::Binary(self.sval.to_vec())),
            DataType::NotSet => None,
        }
    }

    /// The mail this notify delivers (`None` for data type `'~'`): its names and a string
    /// value share this message's buffers (no copy, see [`moos_types::text_of`]); binary
    /// data is copied.
    ///
    /// ```
    /// use moos_wire::{Message, Value};
    /// let mut m = Message::notify("DEPLOY", Value::from("true"), 3.0);
    /// m.src = bytes::Bytes::from_static(b"uPokeDB");
    /// let mail = m.mail().unwrap();
    /// assert_eq!((&*mail.key, &*mail.source, mail.time), ("DEPLOY", "uPokeDB", 3.0));
    /// assert_eq!(mail.value.as_str(), Some("true"));
    /// ```
    pub fn mail(&self) -> Option<Mail> {
        let value = self.value()?;
        Some(Mail {
            key: text_of(&self.key),
            value,
            time: self.time,
            source: text_of(&self.src),
            source_aux: text_of(&self.src_aux),
            community: text_of(&self.community),
        })
    }

    /// The key as text (lossy for non-UTF-8 bytes).
    pub fn key_str(&self) -> Cow<'_, str> {
        String::from_utf8_lossy(&self.key)
    }

    /// The source as text (lossy).
    pub fn src_str(&self) -> Cow<'_, str> {
        String::from_utf8_lossy(&self.src)
    }

    /// The string value as text (lossy).
    pub fn sval_str(&self) -> Cow<'_, str> {
        String::from_utf8_lossy(&self.sval)
    }

    /// True for a double-valued message.
    pub fn is_double(&self) -> bool {
        self.data_type == DataType::Double
    }

    /// Serialized size in bytes: 54 plus the five string lengths.
    pub fn encoded_len(&self) -> usize {
        MESSAGE_FIXED_LEN
            + self.src.len()
            + self.src_aux.len()
            + self.community.len()
            + self.key.len()
            + self.sval.len()
    }

    /// Appends the serialized message to `out`.
    ///
    /// Strings longer than `i32::MAX` cannot be represented; callers never build such
    /// messages (the packet limit is far smaller), and the length is then saturated.
    pub fn encode(&self, out: &mut Vec<u8>) {
        let len = self.encoded_len();
        out.reserve(len);
        put_i32(out, len_i32(len));
        put_i32(out, self.id);
        out.push(self.msg_type.code());
        out.push(self.data_type.code());
        put_str(out, &self.src);
        put_str(out, &self.src_aux);
        put_str(out, &self.community);
        put_str(out, &self.key);
        out.extend_from_slice(&self.time.to_le_bytes());
        out.extend_from_slice(&self.dval.to_le_bytes());
        out.extend_from_slice(&self.dval2.to_le_bytes());
        put_str(out, &self.sval);
    }

    /// Decodes one message from the front of `buf` (a slice of a packet), returning it and
    /// the number of bytes it used. Strings are zero-copy slices of `buf`.
    pub fn decode(buf: &Bytes) -> Result<(Message, usize), DecodeError> {
        let mut r = Reader { buf, pos: 0 };
        let declared = r.i32()?;
        if declared < MESSAGE_FIXED_LEN as i32 {
            return Err(DecodeError::BadMessageLength { declared });
        }
        if declared as usize > buf.len() {
            return Err(DecodeError::Truncated {
                needed: declared as usize,
                available: buf.len(),
            });
        }
        let id = r.i32()?;
        let tc = r.u8()?;
        let msg_type = MsgType::from_code(tc).ok_or(DecodeError::UnknownMessageType(tc))?;
        let dc = r.u8()?;
        let data_type = DataType::from_code(dc).ok_or(DecodeError::UnknownDataType(dc))?;
        let src = r.string()?;
        let src_aux = r.string()?;
        let community = r.string()?;
        let key = r.string()?;
        let time = r.f64()?;
        let dval = r.f64()?;
        let dval2 = r.f64()?;
        let sval = r.string()?;
        if r.pos != declared as usize {
            return Err(DecodeError::MessageLengthMismatch {
                declared,
                actual: r.pos,
            });
        }
        Ok((
            Message {
                id,
                msg_type,
                data_type,
                src,
                src_aux,
                community,
                key,
                time,
                dval,
                dval2,
                sval,
            },
            r.pos,
        ))
    }
}

fn len_i32(len: usize) -> i32 {
    i32::try_from(len).unwrap_or(i32::MAX)
}

fn put_i32(out: &mut Vec<u8>, v: i32) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn put_str(out: &mut Vec<u8>, s: &[u8]) {
    put_i32(out, len_i32(s.len()));
    out.extend_from_slice(s);
}

/// A bounds-checked little-endian cursor over a `Bytes` buffer.
struct Reader<'a> {
    buf: &'a Bytes,
    pos: usize,
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], DecodeError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.buf.len());
        match end {
            Some(end) => {
                let s = &self.buf[self.pos..end];
                self.pos = end;
                Ok(s)
            }
            None => Err(DecodeError::Truncated {
                needed: self.pos.saturating_add(n),
                available: self.buf.len(),
            }),
        }
    }

    fn u8(&mut self) -> Result<u8, DecodeError> {
        Ok(self.take(1)?[0])
    }

    fn i32(&mut self) -> Result<i32, DecodeError> {
        let b = self.take(4)?;
        Ok(i32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn f64(&mut self) -> Result<f64, DecodeError> {
        let b = self.take(8)?;
        let mut a = [0u8; 8];
        a.copy_from_slice(b);
        Ok(f64::from_le_bytes(a))
    }

    fn string(&mut self) -> Result<Bytes, DecodeError> {
        let len = self.i32()?;
        if len < 0 {
            return Err(DecodeError::NegativeStringLength(len));
        }
        let start = self.pos;
        self.take(len as usize)?;
        Ok(self.buf.slice(start..self.pos))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn type_codes_round_trip() {
        for t in MsgType::ALL {
            assert_eq!(MsgType::from_code(t.code()), Some(t));
        }
        for d in [
            DataType::Double,
            DataType::String,
            DataType::Binary,
            DataType::NotSet,
        ] {
            assert_eq!(DataType::from_code(d.code()), Some(d));
        }
        assert_eq!(MsgType::from_code(b'x'), None);
        assert_eq!(DataType::from_code(b'x'), None);
    }

    #[test]
    fn negative_string_length_is_an_error() {
        let mut m = Message::notify("K", Value::Double(1.0), 0.0);
        m.src = Bytes::from_static(b"ab");
        let mut v = Vec::new();
        m.encode(&mut v);
        // src length field sits at offset 10.
        v[10..14].copy_from_slice(&(-5i32).to_le_bytes());
        let err = Message::decode(&Bytes::from(v)).unwrap_err();
        assert_eq!(err, DecodeError::NegativeStringLength(-5));
    }
}
