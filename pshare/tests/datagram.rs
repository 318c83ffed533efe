//! Datagrams byte for byte against frames built by hand from `CMOOSMsg::Serialize`'s layout
//! (little-endian: i32 length, i32 id, u8 type, u8 data type, strings src, src_aux,
//! community, key as i32 length + bytes, f64 time, f64 dval, f64 dval2, string sval), and
//! garbage refused without a panic.

use bytes::Bytes;
use moos_wire::{DataType, Message, MsgType, Value};
use proptest::prelude::*;
use pshare::datagram::{self, DatagramError, MAX_UDP_SIZE};

fn put_str(v: &mut Vec<u8>, s: &[u8]) {
    v.extend_from_slice(&(s.len() as i32).to_le_bytes());
    v.extend_from_slice(s);
}

/// A frame written field by field, as the C++ serialiser lays it out.
#[allow(clippy::too_many_arguments)]
fn frame(
    id: i32,
    data_type: u8,
    src: &str,
    aux: &str,
    community: &str,
    key: &str,
    time: f64,
    dval: f64,
    sval: &[u8],
) -> Vec<u8> {
    let mut v = vec![0u8; 4];
    v.extend_from_slice(&id.to_le_bytes());
    v.push(b'N');
    v.push(data_type);
    put_str(&mut v, src.as_bytes());
    put_str(&mut v, aux.as_bytes());
    put_str(&mut v, community.as_bytes());
    put_str(&mut v, key.as_bytes());
    v.extend_from_slice(&time.to_le_bytes());
    v.extend_from_slice(&dval.to_le_bytes());
    v.extend_from_slice(&(-1.0f64).to_le_bytes());
    put_str(&mut v, sval);
    let len = v.len() as i32;
    v[..4].copy_from_slice(&len.to_le_bytes());
    v
}

fn mail(key: &str, value: Value) -> Message {
    let mut m = Message::notify(key, value, 1234.5);
    m.id = 17;
    m.src = Bytes::from_static(b"uSimMarine");
    m.src_aux = Bytes::from_static(b"aux1");
    m.community = Bytes::from_static(b"alpha");
    m
}

#[test]
fn a_double_is_renamed_and_laid_out_as_pshare_sends_it() {
    let mut out = Vec::new();
    datagram::encode(
        &mail("NAV_X", Value::Double(-12.25)),
        "REMOTE_NAV_X",
        &mut out,
    )
    .unwrap();
    let want = frame(
        17,
        b'D',
        "uSimMarine",
        "aux1",
        "alpha",
        "REMOTE_NAV_X",
        1234.5,
        -12.25,
        b"",
    );
    assert_eq!(out, want);
    // 54 fixed bytes and the strings.
    assert_eq!(out.len(), 54 + 10 + 4 + 5 + 12);
    let back = datagram::decode(Bytes::from(want)).unwrap();
    assert_eq!(back.key, "REMOTE_NAV_X");
    assert_eq!(back.src, "uSimMarine");
    assert_eq!(back.community, "alpha");
    assert_eq!((back.time, back.dval), (1234.5, -12.25));
}

#[test]
fn a_string_and_a_binary_string() {
    let mut out = Vec::new();
    datagram::encode(&mail("DEPLOY", Value::text("true")), "DEPLOY_ALL", &mut out).unwrap();
    assert_eq!(
        out,
        frame(
            17,
            b'S',
            "uSimMarine",
            "aux1",
            "alpha",
            "DEPLOY_ALL",
            1234.5,
            -1.0,
            b"true"
        )
    );
    let s = datagram::decode(Bytes::from(out.clone())).unwrap();
    assert_eq!(s.data_type, DataType::String);
    assert_eq!(s.value(), Some(Value::text("true")));

    let bin = vec![0u8, 255, 10, 13, 0];
    datagram::encode(&mail("BLOB", Value::Binary(bin.clone())), "BLOB", &mut out).unwrap();
    assert_eq!(
        out,
        frame(
            17,
            b'B',
            "uSimMarine",
            "aux1",
            "alpha",
            "BLOB",
            1234.5,
            -1.0,
            &bin
        )
    );
    let b = datagram::decode(Bytes::from(out)).unwrap();
    assert_eq!(b.value(), Some(Value::Binary(bin)));
}

#[test]
fn a_hand_built_frame_decodes() {
    let f = frame(
        3,
        b'D',
        "pHelmIvP",
        "",
        "shore",
        "RETURN_ALL",
        10.0,
        1.0,
        b"",
    );
    let m = datagram::decode(Bytes::from(f)).unwrap();
    assert_eq!(m.msg_type, MsgType::Notify);
    assert_eq!((m.id, &m.key[..], m.dval), (3, &b"RETURN_ALL"[..], 1.0));
}

#[test]
fn messages_over_48_kib_are_not_sent() {
    let mut out = Vec::new();
    let fits = MAX_UDP_SIZE - 54 - "uSimMarine".len() - 4 - 5 - 1;
    datagram::encode(&mail("X", Value::Binary(vec![7; fits])), "Y", &mut out).unwrap();
    assert_eq!(out.len(), MAX_UDP_SIZE);
    let err = datagram::encode(&mail("X", Value::Binary(vec![7; fits])), "YY", &mut out);
    assert_eq!(err, Err(pshare::EncodeError::TooLarge(MAX_UDP_SIZE + 1)));
    assert!(out.is_empty());
}

#[test]
fn garbage_is_refused_with_its_reason() {
    let good = frame(1, b'D', "a", "", "c", "K", 0.0, 1.0, b"");
    let mut trailing = good.clone();
    trailing.push(0);
    assert_eq!(
        datagram::decode(Bytes::from(trailing)),
        Err(DatagramError::Trailing(1))
    );
    let mut register = good.clone();
    register[8] = b'R';
    assert_eq!(
        datagram::decode(Bytes::from(register)),
        Err(DatagramError::NotNotify(MsgType::Register))
    );
    let mut unset = good.clone();
    unset[9] = b'~';
    assert_eq!(
        datagram::decode(Bytes::from(unset)),
        Err(DatagramError::NoValue)
    );
    assert!(matches!(
        datagram::decode(Bytes::from(good[..good.len() - 1].to_vec())),
        Err(DatagramError::Decode(_))
    ));
    assert!(matches!(
        datagram::decode(Bytes::from_static(b"hello pShare")),
        Err(DatagramError::Decode(_))
    ));
    assert!(datagram::decode(Bytes::new()).is_err());
}

#[test]
fn the_white_list_takes_wildcards() {
    let wl = vec!["foo*".to_string(), "?bar".to_string()];
    assert!(datagram::wanted(&wl, b"foo_1"));
    assert!(datagram::wanted(&wl, b"xbar"));
    assert!(!datagram::wanted(&wl, b"xxbar"));
    assert!(datagram::wanted(&[], b"anything"));
}

proptest! {
    #[test]
    fn the_decoder_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
        let _ = datagram::decode(Bytes::from(bytes));
    }

    #[test]
    fn mutated_frames_never_panic(
        at in 0usize..90,
        byte in any::<u8>(),
        cut in 0usize..90,
    ) {
        let mut f = frame(5, b'S', "src", "aux", "comm", "KEY", 1.0, 2.0, b"value");
        let at = at % f.len();
        f[at] = byte;
        f.truncate(f.len().min(cut.max(1) + 10));
        let _ = datagram::decode(Bytes::from(f));
    }

    #[test]
    fn encode_then_decode_is_identity(
        key in "[A-Z_]{1,20}",
        dest in "[A-Z_]{1,20}",
        src in "[a-zA-Z]{0,12}",
        x in any::<f64>(),
        s in proptest::option::of(".{0,40}"),
        t in -1e9f64..1e9,
    ) {
        let value = match s { Some(s) => Value::text(s), None => Value::Double(x) };
        let mut m = Message::notify(&key, value, t);
        m.src = Bytes::from(src.into_bytes());
        let mut out = Vec::new();
        datagram::encode(&m, &dest, &mut out).unwrap();
        let back = datagram::decode(Bytes::from(out)).unwrap();
        let mut want = m.clone();
        want.key = Bytes::from(dest.into_bytes());
        // NaN != NaN: compare the bits.
        prop_assert_eq!(back.dval.to_bits(), want.dval.to_bits());
        want.dval = 0.0;
        let mut back = back;
        back.dval = 0.0;
        prop_assert_eq!(back, want);
    }
}
