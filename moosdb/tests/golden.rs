//! Golden vectors: the reference's worked examples and every byte recorded between the real
//! C++ MOOSDB and real C++ clients decode to the recorded fields and re-encode to the same
//! bytes.

mod common;

use bytes::Bytes;
use moosdb::codec::{PREAMBLE, preamble_ok};
use moosdb::packet::{StreamDecoder, decode_packet, encode_packet};
use moosdb::{DataType, Message, MsgType, Value};

fn unhex(s: &str) -> Vec<u8> {
    let s: String = s.split_whitespace().collect();
    (0..s.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&s[i..i + 2], 16).unwrap())
        .collect()
}

fn check_example(msg: Message, expected_hex: &str) {
    let expected = unhex(expected_hex);
    let mut out = Vec::new();
    encode_packet(std::slice::from_ref(&msg), &mut out);
    assert_eq!(out, expected, "encoding differs from the reference bytes");
    let back = decode_packet(Bytes::from(expected)).unwrap();
    assert_eq!(back, vec![msg]);
}

fn helm_msg(key: &str, value: Value, id: i32) -> Message {
    let mut m = Message::notify(key, value, 1700000000.5);
    m.id = id;
    m.src = Bytes::from_static(b"pHelmIvP");
    m
}

#[test]
fn worked_example_a_notify_double() {
    check_example(
        helm_msg("DESIRED_SPEED", Value::Double(1.5), 7),
        "54000000 01000000 00
         4b000000 07000000 4e 44
         08000000 7048656c6d497650 00000000 00000000
         0d000000 444553495245445f5350454544
         00002040fc54d941 000000000000f83f 000000000000f0bf 00000000",
    );
}

#[test]
fn worked_example_b_notify_string() {
    check_example(
        helm_msg("DEPLOY", Value::from("true"), 8),
        "51000000 01000000 00
         48000000 08000000 4e 53
         08000000 7048656c6d497650 00000000 00000000
         06000000 4445504c4f59
         00002040fc54d941 000000000000f0bf 000000000000f0bf 04000000 74727565",
    );
}

#[test]
fn worked_example_c_handshake() {
    let mut m = Message::new(MsgType::Data, DataType::String, "asynchronous");
    m.time = 1700000000.25;
    m.sval = Bytes::from_static(b"pHelmIvP");
    check_example(
        m,
        "53000000 01000000 00
         4a000000 ffffffff 69 53
         00000000 00000000 00000000
         0c000000 6173796e6368726f6e6f7573
         00001040fc54d941 000000000000f0bf 000000000000f0bf
         08000000 7048656c6d497650",
    );
    let mut sync = Message::new(MsgType::Data, DataType::String, "");
    sync.sval = Bytes::from_static(b"pHelmIvP");
    let mut out = Vec::new();
    encode_packet(&[sync], &mut out);
    assert_eq!(
        out.len(),
        71,
        "a synchronous client's name packet is 71 bytes"
    );
}

/// Decodes a whole direction stream, checks it against the index and re-encodes it.
fn check_stream(scenario: &str, file: &str, bytes: &[u8], recorded: &[common::RecPacket]) -> usize {
    let mut dec = StreamDecoder::default();
    dec.extend(bytes);
    let mut n = 0;
    let mut offset = bytes.len() - dec.pending();
    while let Some(frame) = dec.next_frame().unwrap() {
        let rec = &recorded[n];
        assert_eq!(
            (offset, frame.len()),
            (rec.off, rec.len),
            "{scenario}/{file}: packet {n} bounds"
        );
        let msgs = decode_packet(frame.clone())
            .unwrap_or_else(|e| panic!("{scenario}/{file} packet {n}: {e}"));
        assert_eq!(msgs, rec.msgs, "{scenario}/{file}: packet {n} fields");
        let lens: Vec<usize> = msgs.iter().map(Message::encoded_len).collect();
        assert_eq!(
            lens, rec.lens,
            "{scenario}/{file}: packet {n} message lengths"
        );
        let mut again = Vec::new();
        encode_packet(&msgs, &mut again);
        assert_eq!(
            &again[..],
            &frame[..],
            "{scenario}/{file}: packet {n} re-encoding"
        );
        offset += frame.len();
        n += 1;
    }
    assert_eq!(dec.pending(), 0, "{scenario}/{file}: leftover bytes");
    assert_eq!(n, recorded.len(), "{scenario}/{file}: packet count");
    n
}

#[test]
fn every_recorded_exchange_round_trips() {
    let mut total_packets = 0;
    let mut total_msgs = 0;
    for scenario in common::scenarios() {
        let idx = common::index(&scenario);
        for conn in idx["connections"].as_array().unwrap() {
            let c2s_file = conn["c2s_file"].as_str().unwrap();
            let s2c_file = conn["s2c_file"].as_str().unwrap();
            let c2s = common::bin(&scenario, c2s_file);
            let s2c = common::bin(&scenario, s2c_file);
            assert_eq!(&c2s[..32], &PREAMBLE[..], "{scenario}/{c2s_file} preamble");
            assert!(preamble_ok(&c2s[..32]));
            let c2s_rec = common::packets(conn, "c2s_packets");
            let s2c_rec = common::packets(conn, "s2c_packets");
            // The c2s stream starts after the 32 raw preamble bytes: offsets are absolute.
            let mut dec_input = vec![0u8; 0];
            dec_input.extend_from_slice(&c2s[32..]);
            let shifted: Vec<common::RecPacket> = c2s_rec
                .iter()
                .cloned()
                .map(|mut p| {
                    p.off -= 32;
                    p
                })
                .collect();
            total_packets += check_stream(&scenario, c2s_file, &dec_input, &shifted);
            total_packets += check_stream(&scenario, s2c_file, &s2c, &s2c_rec);
            total_msgs += c2s_rec
                .iter()
                .chain(&s2c_rec)
                .map(|p| p.msgs.len())
                .sum::<usize>();
        }
    }
    // README: 25+116+162+2225+22+22+66 packets, 73+240+443+6478+33+23+110 messages.
    assert_eq!(total_packets, 2638);
    assert_eq!(total_msgs, 7400);
}
