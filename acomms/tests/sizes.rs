//! The size table of the crate docs, pinned: a change of any field's bounds shows here.

use acomms::{SIZE_TABLE, SizeRow};

#[test]
fn size_table() {
    let rows: Vec<(&str, u8, usize, usize, bool)> = SIZE_TABLE
        .iter()
        .map(|r: &SizeRow| (r.name, r.id, r.body_bits, r.wire_bytes, r.authenticated))
        .collect();
    println!("{rows:#?}");
    assert_eq!(
        rows,
        [
            ("Status", 0x71, 109, 15, false),
            ("StatusRequest", 0x72, 8, 2, false),
            ("LocalisationRequest", 0x73, 8, 2, false),
            ("Localisation", 0x74, 77, 11, false),
            ("Confirm", 0x75, 72, 14, true),
            ("Kill", 0x78, 44, 11, true),
            ("Surface", 0x79, 44, 11, true),
            ("Abort", 0x7A, 44, 11, true),
            ("Return", 0x7B, 44, 11, true),
            ("GoTo", 0x7C, 95, 17, true),
            ("Loiter", 0x7D, 104, 18, true),
            ("SetDepth", 0x7E, 55, 12, true),
        ]
    );
}

#[test]
fn every_message_fits_one_seatrac_packet_and_the_status_is_far_below_the_papers() {
    for r in SIZE_TABLE {
        assert!(r.wire_bytes <= devices::seatrac::MAX_DAT_PAYLOAD, "{r:?}");
        assert_eq!(
            r.wire_bytes,
            1 + r.body_bits.div_ceil(8) + if r.authenticated { 4 } else { 0 }
        );
    }
    let status = SIZE_TABLE.iter().find(|r| r.name == "Status").unwrap();
    // Gen-1 VEHICLE_STATUS: 1 + 26 bytes; Gen-2 RESP_STATUS: 29 bytes.
    assert!(status.wire_bytes * 2 <= 1 + 26 + 4, "{status:?}");
}
