//! Packet framing (`CMOOSCommPkt`): a 9-byte header and back-to-back messages.
//!
//! ```text
//! i32 total length (header included) | i32 message count | u8 compression flag (0) | messages
//! ```
//! Pure code: [`encode_packet`], [`decode_packet`] and the incremental [`StreamDecoder`] that
//! cuts a byte stream into packets ([`split_frame`], shared with the tokio_util codec).

use bytes::{Buf, Bytes, BytesMut};

use crate::error::DecodeError;
use crate::message::{MESSAGE_FIXED_LEN, Message};

/// Size of the packet header: length, count, flag.
pub const HEADER_LEN: usize = 9;

/// Default cap on a packet's announced length (the C++ code has none; an absurd length is
/// rejected instead of allocated). 64 MiB.
pub const DEFAULT_MAX_PACKET_LEN: usize = 64 * 1024 * 1024;

/// Appends one packet holding `msgs` to `out`.
///
/// ```
/// use moos_wire::{packet, Message, Value};
/// let mut out = Vec::new();
/// packet::encode_packet(&[Message::notify("X", Value::Double(1.0), 0.0)], &mut out);
/// assert_eq!(out.len(), 9 + 55);
/// ```
pub fn encode_packet<'a>(msgs: impl IntoIterator<Item = &'a Message> + Clone, out: &mut Vec<u8>) {
    let mut body = 0usize;
    let mut count = 0usize;
    for m in msgs.clone() {
        body += m.encoded_len();
        count += 1;
    }
    let total = HEADER_LEN + body;
    out.reserve(total);
    out.extend_from_slice(&i32::try_from(total).unwrap_or(i32::MAX).to_le_bytes());
    out.extend_from_slice(&i32::try_from(count).unwrap_or(i32::MAX).to_le_bytes());
    out.push(0);
    for m in msgs {
        m.encode(out);
    }
}

/// The packet length announced by the first 4 bytes of `prefix`, checked against `max_len`;
/// `Ok(None)` when fewer than 4 bytes are available.
pub fn announced_len(prefix: &[u8], max_len: usize) -> Result<Option<usize>, DecodeError> {
    if prefix.len() < 4 {
        return Ok(None);
    }
    let len = i32::from_le_bytes([prefix[0], prefix[1], prefix[2], prefix[3]]);
    if len < HEADER_LEN as i32 {
        return Err(DecodeError::PacketTooShort(len));
    }
    let len = len as usize;
    if len > max_len {
        return Err(DecodeError::PacketTooLarge { len, max: max_len });
    }
    Ok(Some(len))
}

/// Decodes one complete packet (header included, exactly its announced length).
pub fn decode_packet(frame: Bytes) -> Result<Vec<Message>, DecodeError> {
    decode_packet_limited(frame, usize::MAX)
}

/// [`decode_packet`] with a cap on the announced length.
pub fn decode_packet_limited(frame: Bytes, max_len: usize) -> Result<Vec<Message>, DecodeError> {
    if frame.len() < HEADER_LEN {
        return Err(DecodeError::Truncated {
            needed: HEADER_LEN,
            available: frame.len(),
        });
    }
    let len = announced_len(&frame, max_len)?.unwrap_or(0);
    if len > frame.len() {
        return Err(DecodeError::Truncated {
            needed: len,
            available: frame.len(),
        });
    }
    if len < frame.len() {
        return Err(DecodeError::TrailingBytes(frame.len() - len));
    }
    let count = i32::from_le_bytes([frame[4], frame[5], frame[6], frame[7]]);
    if count < 0 {
        return Err(DecodeError::NegativeCount(count));
    }
    if count as usize > (len - HEADER_LEN) / MESSAGE_FIXED_LEN {
        return Err(DecodeError::CountTooLarge { count, len });
    }
    let mut rest = frame.slice(HEADER_LEN..);
    let mut msgs = Vec::with_capacity(count as usize);
    for _ in 0..count {
        let (m, used) = Message::decode(&rest)?;
        rest.advance(used);
        msgs.push(m);
    }
    if !rest.is_empty() {
        return Err(DecodeError::TrailingBytes(rest.len()));
    }
    Ok(msgs)
}

/// Cuts a byte stream into packets: feed bytes with [`StreamDecoder::extend`] (or write into
/// [`StreamDecoder::buffer_mut`]) and take packets with [`StreamDecoder::next_packet`].
#[derive(Debug)]
pub struct StreamDecoder {
    buf: BytesMut,
    max_len: usize,
}

impl Default for StreamDecoder {
    fn default() -> Self {
        StreamDecoder::new(DEFAULT_MAX_PACKET_LEN)
    }
}

impl StreamDecoder {
    /// A decoder that rejects packets announcing more than `max_len` bytes.
    pub fn new(max_len: usize) -> StreamDecoder {
        StreamDecoder {
            buf: BytesMut::with_capacity(8192),
            max_len,
        }
    }

    /// Appends received bytes.
    pub fn extend(&mut self, bytes: &[u8]) {
        self.buf.extend_from_slice(bytes);
    }

    /// The internal buffer, to read into directly.
    pub fn buffer_mut(&mut self) -> &mut BytesMut {
        &mut self.buf
    }

    /// Bytes received but not yet part of a returned packet.
    pub fn pending(&self) -> usize {
        self.buf.len()
    }

    /// The next complete packet's messages, `Ok(None)` if more bytes are needed.
    /// After an error the stream is unusable (framing is lost).
    pub fn next_packet(&mut self) -> Result<Option<Vec<Message>>, DecodeError> {
        match self.next_frame()? {
            Some(frame) => decode_packet(frame).map(Some),
            None => Ok(None),
        }
    }

    /// The next complete packet's raw bytes (header included), `Ok(None)` if incomplete.
    pub fn next_frame(&mut self) -> Result<Option<Bytes>, DecodeError> {
        split_frame(&mut self.buf, self.max_len)
    }
}

/// Takes the first complete packet's raw bytes (header included) off the front of `buf`;
/// `Ok(None)` if `buf` does not hold a whole packet yet, in which case `buf` is grown towards
/// the announced size (never beyond it). A packet announcing more than `max_len` bytes is an
/// error before anything is allocated for it.
pub fn split_frame(buf: &mut BytesMut, max_len: usize) -> Result<Option<Bytes>, DecodeError> {
    let Some(len) = announced_len(buf, max_len)? else {
        return Ok(None);
    };
    if buf.len() < len {
        // Grow towards the announced size, never beyond it.
        buf.reserve(len - buf.len());
        return Ok(None);
    }
    Ok(Some(buf.split_to(len).freeze()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::message::Value;

    #[test]
    fn stream_decoder_handles_byte_by_byte_input() {
        let msgs = vec![
            Message::notify("A", Value::Double(2.0), 1.0),
            Message::notify("B", Value::from("x"), 1.0),
        ];
        let mut bytes = Vec::new();
        encode_packet(&msgs, &mut bytes);
        encode_packet(&msgs[..1], &mut bytes);
        let mut d = StreamDecoder::default();
        let mut got = Vec::new();
        for b in &bytes {
            d.extend(&[*b]);
            while let Some(p) = d.next_packet().unwrap() {
                got.push(p);
            }
        }
        assert_eq!(got, vec![msgs.clone(), msgs[..1].to_vec()]);
        assert_eq!(d.pending(), 0);
    }

    #[test]
    fn absurd_length_is_rejected_before_allocation() {
        let mut d = StreamDecoder::new(1000);
        d.extend(&(1_000_000i32).to_le_bytes());
        assert_eq!(
            d.next_packet(),
            Err(DecodeError::PacketTooLarge {
                len: 1_000_000,
                max: 1000
            })
        );
    }

    #[test]
    fn negative_count_and_lying_count_are_errors() {
        let mut p = Vec::new();
        encode_packet(&[Message::notify("A", Value::Double(2.0), 1.0)], &mut p);
        let mut neg = p.clone();
        neg[4..8].copy_from_slice(&(-3i32).to_le_bytes());
        assert_eq!(
            decode_packet(Bytes::from(neg)),
            Err(DecodeError::NegativeCount(-3))
        );
        let mut big = p.clone();
        big[4..8].copy_from_slice(&(2i32).to_le_bytes());
        assert_eq!(
            decode_packet(Bytes::from(big)),
            Err(DecodeError::CountTooLarge {
                count: 2,
                len: p.len()
            })
        );
    }
}
