//! The connection preamble and async packet I/O over any tokio stream.
//!
//! A client opens with [`PREAMBLE`] (32 raw bytes, not framed), then exchanges packets
//! ([`crate::packet`]). [`PacketReader`] reads whole packets with a length cap; [`write_packet`]
//! encodes and writes one.

use tokio::io::{AsyncRead, AsyncReadExt, AsyncWrite, AsyncWriteExt};

use crate::error::ReadError;
use crate::message::Message;
use crate::packet::{StreamDecoder, encode_packet};

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
/// assert!(moosdb_client::codec::preamble_ok(&moosdb_client::codec::PREAMBLE));
/// assert!(!moosdb_client::codec::preamble_ok(b"GET / HTTP/1.1\r\n"));
/// ```
pub fn preamble_ok(buf: &[u8]) -> bool {
    let end = buf.iter().position(|&b| b == 0).unwrap_or(buf.len());
    buf[..end].eq_ignore_ascii_case(PROTOCOL_STRING)
}

/// Reads whole packets from an async byte stream.
#[derive(Debug)]
pub struct PacketReader<R> {
    inner: R,
    decoder: StreamDecoder,
}

impl<R: AsyncRead + Unpin> PacketReader<R> {
    /// Wraps `inner`, rejecting packets longer than `max_len`.
    pub fn new(inner: R, max_len: usize) -> PacketReader<R> {
        PacketReader {
            inner,
            decoder: StreamDecoder::new(max_len),
        }
    }

    /// Reads exactly `buf.len()` raw bytes (used for the preamble); bytes already buffered
    /// are consumed first.
    pub async fn read_raw(&mut self, buf: &mut [u8]) -> std::io::Result<()> {
        let have = self.decoder.pending().min(buf.len());
        if have > 0 {
            let b = self.decoder.buffer_mut().split_to(have);
            buf[..have].copy_from_slice(&b);
        }
        self.inner.read_exact(&mut buf[have..]).await.map(|_| ())
    }

    /// The next packet's messages; `Ok(None)` on a clean end of stream between packets.
    pub async fn read_packet(&mut self) -> Result<Option<Vec<Message>>, ReadError> {
        loop {
            if let Some(p) = self.decoder.next_packet()? {
                return Ok(Some(p));
            }
            let n = self.inner.read_buf(self.decoder.buffer_mut()).await?;
            if n == 0 {
                let pending = self.decoder.pending();
                return if pending == 0 {
                    Ok(None)
                } else {
                    Err(ReadError::ClosedMidPacket(pending))
                };
            }
        }
    }

    /// The wrapped stream.
    pub fn get_mut(&mut self) -> &mut R {
        &mut self.inner
    }
}

/// Encodes `msgs` as one packet and writes it.
pub async fn write_packet<W: AsyncWrite + Unpin>(
    w: &mut W,
    msgs: &[Message],
) -> std::io::Result<()> {
    let mut buf = Vec::new();
    encode_packet(msgs, &mut buf);
    w.write_all(&buf).await
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
}
