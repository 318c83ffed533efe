//! The body of the `moos_packet` fuzz target, shared by the cargo-fuzz binary
//! (`fuzz/fuzz_targets/moos_packet.rs`, nightly) and the bounded stable run of
//! `tests/fuzz.rs`.
//!
//! ```
//! let mut bytes = Vec::new();
//! let msg = moos_wire::Message::notify("X", moos_wire::Value::from(1.0), 2.0);
//! moos_wire::packet::encode_packet(&[msg], &mut bytes);
//! moos_wire::fuzz::moos_packet(&bytes);
//! moos_wire::fuzz::moos_packet(&bytes[..bytes.len() / 2]);
//! ```

use crate::packet::{StreamDecoder, decode_packet, encode_packet};

/// Arbitrary bytes must never make the packet decoder panic; whatever decodes must
/// re-encode to the same bytes (apart from the compression flag, which is ignored); and the
/// stream decoder, fed the bytes in 13-byte chunks, must stop at an error or at the end.
pub fn moos_packet(data: &[u8]) {
    moos_packet_in_chunks(data, 13);
}

/// [`moos_packet`] with the stream decoder fed `chunk`-byte pieces (at least 1).
pub fn moos_packet_in_chunks(data: &[u8], chunk: usize) {
    if let Ok(msgs) = decode_packet(bytes::Bytes::copy_from_slice(data)) {
        let mut again = Vec::new();
        encode_packet(&msgs, &mut again);
        let mut expect = data.to_vec();
        expect[8] = 0;
        assert_eq!(again, expect);
    }
    let mut d = StreamDecoder::new(1 << 20);
    for piece in data.chunks(chunk.max(1)) {
        d.extend(piece);
        loop {
            match d.next_packet() {
                Ok(Some(_)) => continue,
                Ok(None) => break,
                Err(_) => return,
            }
        }
    }
}
