//! The derive on every field kind: sizes, round trips within resolution, the clamp and reject
//! policies, and strict decoding of foreign bits.

use compact::{BitReader, BitWriter, Compact, DecodeError, EncodeError};
use proptest::prelude::*;

#[derive(Compact, Debug, Clone, Copy, PartialEq, Eq)]
enum Three {
    A,
    B,
    C,
}

#[derive(Compact, Debug, Clone, Copy, PartialEq)]
struct Inner(
    #[compact(min = -1.0, max = 1.0, resolution = 0.25)] f32,
    bool,
);

#[derive(Compact, Debug, Clone, Copy, PartialEq)]
struct Unit;

#[derive(Compact, Debug, Clone, PartialEq)]
struct All {
    #[compact(min = -5000.0, max = 5000.0, resolution = 0.1)]
    x: f64,
    #[compact(min = 0.0, max = 100.0, resolution = 0.5, reject)]
    r: f64,
    #[compact(min = -3, max = 12)]
    i: i8,
    #[compact(min = 10, max = 20, reject)]
    j: u32,
    word: u16,
    flag: bool,
    three: Three,
    #[compact(min = 0.0, max = 10.0, resolution = 1.0)]
    maybe: Option<f64>,
    maybe_flag: Option<bool>,
    #[compact(min = 0, max = 2)]
    maybe_int: Option<u8>,
    inner: Inner,
    maybe_inner: Option<Inner>,
    unit: Unit,
}

/// x 17, r 8, i 4, j 4, word 16, flag 1, three 2, maybe 4 (11 codes), maybe_flag 2,
/// maybe_int 2, inner 4 + 1, maybe_inner 1 + 5, unit 0.
const ALL_BITS: usize = 17 + 8 + 4 + 4 + 16 + 1 + 2 + 4 + 2 + 2 + 5 + 6;

#[test]
fn sizes_are_the_sum_of_the_fields() {
    assert_eq!(Three::SIZE_BITS, 2);
    assert_eq!(Inner::SIZE_BITS, 5);
    assert_eq!(Unit::SIZE_BITS, 0);
    assert_eq!(Unit::SIZE_BYTES, 0);
    assert_eq!(All::SIZE_BITS, ALL_BITS);
    assert_eq!(All::SIZE_BYTES, ALL_BITS.div_ceil(8));
    assert_eq!(compact::bits_for(0), 0);
    assert_eq!(compact::bits_for(1), 1);
    assert_eq!(compact::bits_for(100_000), 17);
    assert_eq!(compact::bits_for(u64::MAX), 64);
}

fn sample() -> All {
    All {
        x: 12.3,
        r: 50.0,
        i: 0,
        j: 15,
        word: 0xBEEF,
        flag: true,
        three: Three::C,
        maybe: None,
        maybe_flag: Some(false),
        maybe_int: Some(2),
        inner: Inner(-0.5, true),
        maybe_inner: None,
        unit: Unit,
    }
}

fn three() -> impl Strategy<Value = Three> {
    prop_oneof![Just(Three::A), Just(Three::B), Just(Three::C)]
}

fn inner() -> impl Strategy<Value = Inner> {
    (-1.0f32..=1.0, any::<bool>()).prop_map(|(a, b)| Inner(a, b))
}

fn all_in_range() -> impl Strategy<Value = All> {
    (
        (-5000.0f64..=5000.0, 0.0f64..=100.0, -3i8..=12, 10u32..=20),
        (any::<u16>(), any::<bool>(), three()),
        (
            proptest::option::of(0.0f64..=10.0),
            proptest::option::of(any::<bool>()),
            proptest::option::of(0u8..=2),
        ),
        (inner(), proptest::option::of(inner())),
    )
        .prop_map(
            |((x, r, i, j), (word, flag, three), (maybe, maybe_flag, maybe_int), (inner, mi))| {
                All {
                    x,
                    r,
                    i,
                    j,
                    word,
                    flag,
                    three,
                    maybe,
                    maybe_flag,
                    maybe_int,
                    inner,
                    maybe_inner: mi,
                    unit: Unit,
                }
            },
        )
}

fn close(a: f64, b: f64, res: f64) -> bool {
    (a - b).abs() <= res / 2.0 + 1e-9
}

proptest! {
    #[test]
    fn round_trip_within_resolution(v in all_in_range()) {
        let bytes = v.to_vec().unwrap();
        prop_assert_eq!(bytes.len(), All::SIZE_BYTES);
        let d = All::decode(&bytes).unwrap();
        prop_assert!(close(d.x, v.x, 0.1), "{} {}", d.x, v.x);
        prop_assert!(close(d.r, v.r, 0.5));
        prop_assert_eq!((d.i, d.j, d.word, d.flag, d.three), (v.i, v.j, v.word, v.flag, v.three));
        prop_assert_eq!(d.maybe.is_some(), v.maybe.is_some());
        if let (Some(a), Some(b)) = (d.maybe, v.maybe) {
            prop_assert!(close(a, b, 1.0));
        }
        prop_assert_eq!((d.maybe_flag, d.maybe_int), (v.maybe_flag, v.maybe_int));
        prop_assert!(close(f64::from(d.inner.0), f64::from(v.inner.0), 0.25));
        prop_assert_eq!(d.inner.1, v.inner.1);
        prop_assert_eq!(d.maybe_inner.is_some(), v.maybe_inner.is_some());
        // Encoding what was decoded gives the same bytes: the grid is stable.
        prop_assert_eq!(d.to_vec().unwrap(), bytes);
    }

    #[test]
    fn clamp_fields_send_the_nearest_bound(x in prop_oneof![-1e12f64..-5000.1, 5000.1f64..1e12],
                                           i in prop_oneof![-128i8..-3, 13i8..=127]) {
        let v = All { x, i, ..sample() };
        let d = All::decode(&v.to_vec().unwrap()).unwrap();
        prop_assert_eq!(d.x, if x < 0.0 { -5000.0 } else { 5000.0 });
        prop_assert_eq!(d.i, if i < 0 { -3 } else { 12 });
    }

    #[test]
    fn reject_fields_refuse_out_of_range(r in prop_oneof![-1e12f64..-0.26, 100.26f64..1e12],
                                         j in prop_oneof![0u32..10, 21u32..]) {
        let too_far = All { r, ..sample() }.to_vec();
        prop_assert!(
            matches!(too_far, Err(EncodeError::OutOfRange { field: "r", .. })),
            "{:?}",
            too_far
        );
        let bad = All { j, ..sample() }.to_vec();
        prop_assert!(matches!(bad, Err(EncodeError::OutOfRange { field: "j", .. })), "{:?}", bad);
    }

    #[test]
    fn any_bytes_decode_or_fail_cleanly(bytes in proptest::collection::vec(any::<u8>(), 0..20)) {
        if let Ok(v) = All::decode(&bytes) {
            // What decodes is a valid message that encodes back to the same bytes.
            prop_assert_eq!(v.to_vec().unwrap(), bytes);
        }
    }
}

#[test]
fn infinities_and_nan() {
    let v = All {
        x: f64::INFINITY,
        ..sample()
    };
    assert_eq!(All::decode(&v.to_vec().unwrap()).unwrap().x, 5000.0);
    let v = All {
        x: f64::NAN,
        ..sample()
    };
    assert_eq!(v.to_vec(), Err(EncodeError::NotANumber { field: "x" }));
    let v = All {
        r: f64::NEG_INFINITY,
        ..sample()
    };
    assert!(matches!(
        v.to_vec(),
        Err(EncodeError::OutOfRange { field: "r", .. })
    ));
    // Half a resolution past a bound still rounds onto it.
    let v = All {
        r: 100.2,
        ..sample()
    };
    assert_eq!(All::decode(&v.to_vec().unwrap()).unwrap().r, 100.0);
}

#[test]
fn strict_decoding() {
    let good = sample().to_vec().unwrap();
    assert_eq!(All::decode(&good).unwrap().word, 0xBEEF);
    assert_eq!(
        All::decode(&good[..good.len() - 1]),
        Err(DecodeError::WrongLength {
            expected: All::SIZE_BYTES,
            got: good.len() - 1
        })
    );
    let mut long = good.clone();
    long.push(0);
    assert!(matches!(
        All::decode(&long),
        Err(DecodeError::WrongLength { .. })
    ));

    // The last byte holds 1 padding bit (ALL_BITS = 71): setting it is refused.
    assert_eq!(ALL_BITS, 71);
    let mut padded = good.clone();
    *padded.last_mut().unwrap() |= 1;
    assert_eq!(All::decode(&padded), Err(DecodeError::NonZeroPadding));

    // The enum index 3 does not exist (bits 50..52: x 17, r 8, i 4, j 4, word 16, flag 1).
    let mut e = good.clone();
    e[6] |= 0b0011_0000;
    assert_eq!(
        All::decode(&e),
        Err(DecodeError::BadValue { field: "Three" })
    );

    // x's code past 100000 (all ones in its 17 bits).
    let mut x = good.clone();
    x[0] = 0xFF;
    x[1] = 0xFF;
    x[2] |= 0x80;
    assert_eq!(All::decode(&x), Err(DecodeError::BadValue { field: "x" }));

    // An absent optional sub-message must be zeros: the last 5 field bits are maybe_inner's.
    let mut absent = good;
    let n = absent.len();
    absent[n - 1] |= 0b0000_1000;
    assert_eq!(
        All::decode(&absent),
        Err(DecodeError::BadValue {
            field: "maybe_inner"
        })
    );
}

#[test]
fn buffer_too_small() {
    let mut buf = [0u8; 3];
    assert_eq!(
        sample().encode_into(&mut buf),
        Err(EncodeError::BufferTooSmall {
            need: All::SIZE_BYTES,
            have: 3
        })
    );
    let mut big = [0xAAu8; 32];
    assert_eq!(sample().encode_into(&mut big), Ok(All::SIZE_BYTES));
    assert_eq!(
        All::decode(&big[..All::SIZE_BYTES]),
        Ok(All::decode(&sample().to_vec().unwrap()).unwrap())
    );
}

proptest! {
    #[test]
    fn bit_writer_and_reader_agree(fields in proptest::collection::vec((any::<u64>(), 0u32..=64), 0..20)) {
        let total: usize = fields.iter().map(|f| f.1 as usize).sum();
        let mut buf = vec![0u8; total.div_ceil(8)];
        let mut w = BitWriter::new(&mut buf);
        for &(v, n) in &fields {
            w.write(v, n).unwrap();
        }
        prop_assert_eq!(w.position(), total);
        let mut r = BitReader::new(&buf);
        for &(v, n) in &fields {
            let mask = if n == 64 { u64::MAX } else { (1u64 << n) - 1 };
            prop_assert_eq!(r.read(n).unwrap(), v & mask);
        }
        prop_assert!(r.finish().is_ok());
        prop_assert_eq!(r.read(1), if total.is_multiple_of(8) { Err(DecodeError::Truncated) } else { Ok(0) });
    }
}
