//! The connection preamble and, with the `codec` feature, packet framing for tokio_util.
//!
//! A client opens with [`PREAMBLE`] (32 raw bytes, not framed), then exchanges packets
//! ([`crate::packet`]). With the `codec` feature, `MoosCodec` is that packet framing as a
//! `tokio_util::codec::{Decoder, Encoder}`: read the preamble off the raw stream first, then
//! wrap the stream (or its halves) in `Framed`, `FramedRead` or `FramedWrite` to read whole
//! packets with a length cap and write one packet per item.

#[cfg(feature = "codec")]
use bytes::BytesMut;
#[cfg(feature = "codec")]
use tokio_util::codec::{Decoder, Encoder};

#[cfg(feature = "codec")]
use crate::error::ReadError;
#[cfg(feature = "codec")]
use crate::message::Message;
#[cfg(feature = "codec")]
use crate::packet::{DEFAULT_MAX_PACKET_LEN, decode_packet, encode_packet, split_frame};

/// `MOOS_PROTOCOL_STRING`.
pub const PROTOCOL_STRING: &[u8] = b"ELKS CAN'T DANCE 2/8/10";

/// Size of the preamble buffer (`MOOS_PROTOCOL_STRING_BUFFER_SIZE`).
pub const PREAMBLE_LEN: usize = 32;

/// The 32 bytes a client sends first: the protocol string padded with NULs.
pub const PREAMBLE: [u8; PREAMBLE_LEN] = {
    let mut b = [0u8; PREAMBLE_LEN];
    let mut i = 0;
    while i < PROTOCOL_STRING.len() {
        b[i] = PROTOCOL_STRING[i];
        i += 1;
    }
    b
};

/// True if `buf` holds the protocol string as the C++ server checks it: the bytes up to the
/// first NUL compared case-insensitively.
///
/// ```
/// assert!(moos_wire::codec::preamble_ok(&moos_wire::codec::PREAMBLE));
/// assert!(!moos_wire::codec::preamble_ok(b"GET / HTTP/1.1\r\n"));
/// ```
pub fn preamble_ok(buf: &[u8]) -> bool {
    let end = buf.iter().position(|&b| b == 0).unwrap_or(buf.len());
    buf[..end].eq_ignore_ascii_case(PROTOCOL_STRING)
}

/// MOOS packet framing for `tokio_util::codec`: decodes whole packets (their messages), at
/// most `max_len` bytes each, and encodes a slice of messages (`&[Message]`, the one item
/// type, so `flush` and `close` need no annotation) as one packet.
///
/// Decoding errors are [`ReadError`]s: [`ReadError::Decode`] for malformed bytes or a packet
/// announcing more than the cap (framing is lost after it: stop reading),
/// [`ReadError::ClosedMidPacket`] when the stream ends inside a packet, [`ReadError::Io`] from
/// the stream. A clean end of stream between packets ends the stream of packets. Encoding does
/// not apply the cap (the receiver applies its own) and fails only on I/O.
///
/// ```
/// use bytes::BytesMut;
/// use moos_wire::{Message, MoosCodec, Value};
/// use tokio_util::codec::{Decoder, Encoder};
///
/// let mut codec = MoosCodec::new(1 << 20);
/// let mut buf = BytesMut::new();
/// codec.encode(&[Message::notify("X", Value::Double(1.0), 0.0)][..], &mut buf).unwrap();
/// let packet = codec.decode(&mut buf).unwrap().unwrap();
/// assert_eq!(packet[0].key_str(), "X");
/// ```
#[cfg(feature = "codec")]
#[derive(Debug, Clone)]
pub struct MoosCodec {
    max_len: usize,
    scratch: Vec<u8>,
}

#[cfg(feature = "codec")]
impl Default for MoosCodec {
    /// A codec with the [`DEFAULT_MAX_PACKET_LEN`] cap.
    fn default() -> Self {
        MoosCodec::new(DEFAULT_MAX_PACKET_LEN)
    }
}

#[cfg(feature = "codec")]
impl MoosCodec {
    /// A codec rejecting packets that announce more than `max_len` bytes.
    pub fn new(max_len: usize) -> MoosCodec {
        MoosCodec {
            max_len,
            scratch: Vec::new(),
        }
    }

    /// The cap on a decoded packet's announced length.
    pub fn max_len(&self) -> usize {
        self.max_len
    }
}

#[cfg(feature = "codec")]
impl Decoder for MoosCodec {
    type Item = Vec<Message>;
    type Error = ReadError;

    fn decode(&mut self, src: &mut BytesMut) -> Result<Option<Vec<Message>>, ReadError> {
        match split_frame(src, self.max_len)? {
            Some(frame) => Ok(Some(decode_packet(frame)?)),
            None => Ok(None),
        }
    }

    fn decode_eof(&mut self, src: &mut BytesMut) -> Result<Option<Vec<Message>>, ReadError> {
        match self.decode(src)? {
            Some(packet) => Ok(Some(packet)),
            None if src.is_empty() => Ok(None),
            None => Err(ReadError::ClosedMidPacket(src.len())),
        }
    }
}

#[cfg(feature = "codec")]
impl Encoder<&[Message]> for MoosCodec {
    type Error = std::io::Error;

    fn encode(&mut self, msgs: &[Message], dst: &mut BytesMut) -> std::io::Result<()> {
        self.scratch.clear();
        encode_packet(msgs, &mut self.scratch);
        dst.extend_from_slice(&self.scratch);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn preamble_bytes_match_the_reference() {
        let hex: String = PREAMBLE.iter().map(|b| format!("{b:02x}")).collect();
        assert_eq!(
            hex,
            "454c4b532043414e27542044414e434520322f382f3130000000000000000000"
        );
        assert!(preamble_ok(b"elks can't dance 2/8/10\0\0\0"));
        assert!(!preamble_ok(b"ELKS CAN'T DANCE 2/8/1\0"));
    }

    #[cfg(feature = "codec")]
    mod moos_codec {
        use bytes::{BufMut, BytesMut};
        use tokio_util::codec::{Decoder, Encoder};

        use crate::error::{DecodeError, ReadError};
        use crate::message::{Message, Value};
        use crate::packet::encode_packet;

        use super::super::MoosCodec;

        fn two_packets() -> (Vec<Message>, Vec<Message>, Vec<u8>) {
            let a = vec![
                Message::notify("A", Value::Double(2.0), 1.0),
                Message::notify("B", Value::from("x"), 1.5),
            ];
            let b = vec![Message::notify("C", Value::Binary(vec![0, 255, 7]), 2.0)];
            let mut bytes = Vec::new();
            encode_packet(&a, &mut bytes);
            encode_packet(&b, &mut bytes);
            (a, b, bytes)
        }

        #[test]
        fn a_packet_split_across_chunks_decodes_once_complete() {
            let (a, b, bytes) = two_packets();
            let first_len = 9 + a.iter().map(Message::encoded_len).sum::<usize>();
            let mut codec = MoosCodec::default();
            let mut buf = BytesMut::new();
            let mut got = Vec::new();
            // Chunks of 7 bytes: headers and fields are cut in odd places.
            for chunk in bytes.chunks(7) {
                buf.put_slice(chunk);
                while let Some(p) = codec.decode(&mut buf).unwrap() {
                    got.push(p);
                }
                if got.is_empty() {
                    assert!(buf.len() < first_len, "no packet before its last byte");
                }
            }
            assert_eq!(got, vec![a, b]);
            assert!(buf.is_empty());
            assert_eq!(codec.decode_eof(&mut buf).unwrap(), None, "clean end");
        }

        #[test]
        fn several_packets_in_one_buffer_come_out_in_order() {
            let (a, b, bytes) = two_packets();
            let mut codec = MoosCodec::new(1 << 10);
            let mut buf = BytesMut::from(&bytes[..]);
            assert_eq!(codec.decode(&mut buf).unwrap(), Some(a));
            assert_eq!(codec.decode(&mut buf).unwrap(), Some(b));
            assert_eq!(codec.decode(&mut buf).unwrap(), None);
            assert!(buf.is_empty());
        }

        #[test]
        fn an_oversize_packet_is_an_error_from_its_length_field() {
            let mut codec = MoosCodec::new(100);
            assert_eq!(codec.max_len(), 100);
            let mut buf = BytesMut::new();
            buf.put_slice(&101i32.to_le_bytes());
            match codec.decode(&mut buf) {
                Err(ReadError::Decode(DecodeError::PacketTooLarge { len: 101, max: 100 })) => {}
                other => panic!("expected PacketTooLarge, got {other:?}"),
            }
            // Exactly the cap is accepted (a 100-byte packet: header and one 91-byte message).
            let m = Message::notify("K", Value::from("x".repeat(91 - 55)), 0.0);
            assert_eq!(m.encoded_len(), 91);
            let mut ok = BytesMut::new();
            codec.encode(&[m.clone()][..], &mut ok).unwrap();
            assert_eq!(ok.len(), 100);
            assert_eq!(codec.decode(&mut ok).unwrap(), Some(vec![m]));
        }

        #[test]
        fn malformed_bytes_and_an_end_inside_a_packet_are_errors() {
            let mut codec = MoosCodec::default();
            let mut short = BytesMut::from(&5i32.to_le_bytes()[..]);
            assert!(matches!(
                codec.decode(&mut short),
                Err(ReadError::Decode(DecodeError::PacketTooShort(5)))
            ));
            let (_, _, bytes) = two_packets();
            let mut cut = BytesMut::from(&bytes[..20]);
            assert_eq!(codec.decode(&mut cut).unwrap(), None);
            assert!(matches!(
                codec.decode_eof(&mut cut),
                Err(ReadError::ClosedMidPacket(20))
            ));
        }

        #[test]
        fn encode_then_decode_round_trips_and_matches_encode_packet() {
            let (a, b, bytes) = two_packets();
            let mut codec = MoosCodec::default();
            let mut buf = BytesMut::new();
            codec.encode(&a[..], &mut buf).unwrap();
            codec.encode(&b[..], &mut buf).unwrap();
            assert_eq!(&buf[..], &bytes[..], "same bytes as encode_packet");
            let empty: &[Message] = &[];
            codec.encode(empty, &mut buf).unwrap();
            assert_eq!(codec.decode(&mut buf).unwrap(), Some(a));
            assert_eq!(codec.decode(&mut buf).unwrap(), Some(b));
            assert_eq!(codec.decode(&mut buf).unwrap(), Some(vec![]));
            assert!(buf.is_empty());
        }
    }
}
