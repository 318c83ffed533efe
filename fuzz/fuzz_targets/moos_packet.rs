//! Fuzz the MOOS packet decoder: arbitrary bytes must never panic, and whatever decodes must
//! re-encode to the same bytes (apart from the ignored compression flag).
#![no_main]

use libfuzzer_sys::fuzz_target;
use moos_wire::packet::{StreamDecoder, decode_packet, encode_packet};

fuzz_target!(|data: &[u8]| {
    if let Ok(msgs) = decode_packet(bytes::Bytes::copy_from_slice(data)) {
        let mut again = Vec::new();
        encode_packet(&msgs, &mut again);
        let mut expect = data.to_vec();
        expect[8] = 0;
        assert_eq!(again, expect);
    }
    let mut d = StreamDecoder::new(1 << 20);
    for chunk in data.chunks(13) {
        d.extend(chunk);
        loop {
            match d.next_packet() {
                Ok(Some(_)) => continue,
                Ok(None) => break,
                Err(_) => return,
            }
        }
    }
});
