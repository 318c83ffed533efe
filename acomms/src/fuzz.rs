//! The decoder's fuzz body, shared by `tests/fuzz.rs` (stable, a fixed count of seeded
//! mutants through `test_support::fuzz::Campaign`) and the cargo-fuzz target
//! `fuzz/fuzz_targets/acomms.rs`.
//!
//! ```
//! acomms::fuzz::receive(&[0x78, 0xF2, 0, 0, 7, 1, 2, 3, 4]);
//! acomms::fuzz::receive(&acomms::fuzz::seeds()[0]);
//! ```

use crate::{
    Abort, Auth, CommandKind, Confirm, FleetKey, GoTo, Kill, Localisation, LocalisationRequest,
    Loiter, Packet, Receiver, Return, SetDepth, Status, StatusRequest, Surface, VehicleMode,
};

/// The key the seeds are signed with.
pub const KEY: &[u8] = b"coug fuzz key";

/// The receiving node of the fuzz body.
pub const ME: u8 = 2;

/// One valid frame of every message, for node [`ME`] from node 15 (and a status from 3),
/// signed with [`KEY`].
pub fn seeds() -> Vec<Vec<u8>> {
    let key = FleetKey::new(KEY);
    let a = |seq| Auth::new(15, ME, seq);
    let packets: Vec<Packet> = vec![
        Packet::Status(Status {
            from: 3,
            mode: VehicleMode::Mission,
            x_m: -120.5,
            y_m: 842.1,
            depth_m: 12.3,
            heading_deg: 271.5,
            speed_mps: 1.2,
            battery_v: 15.85,
            waypoint: 4,
            health: 0x00F1,
            nav_sigma_m: Some(2.4),
        }),
        Packet::StatusRequest(StatusRequest { from: 15, to: ME }),
        Packet::LocalisationRequest(LocalisationRequest { from: 15, to: ME }),
        Packet::Localisation(Localisation {
            from: 3,
            x_m: 10.0,
            y_m: -20.0,
            depth_m: 5.0,
            roll_deg: 1.5,
            pitch_deg: -3.0,
            heading_deg: 90.0,
        }),
        Packet::Confirm(Confirm {
            auth: Auth::new(3, ME, 1),
            command: CommandKind::Kill,
            command_seq: 9,
            success: true,
        }),
        Packet::Kill(Kill { auth: a(1) }),
        Packet::Surface(Surface { auth: a(2) }),
        Packet::Abort(Abort { auth: a(3) }),
        Packet::Return(Return { auth: a(4) }),
        Packet::GoTo(GoTo {
            auth: a(5),
            x_m: 100.0,
            y_m: 200.0,
            depth_m: Some(10.0),
            speed_mps: 1.5,
        }),
        Packet::Loiter(Loiter {
            auth: a(6),
            x_m: -50.0,
            y_m: 75.5,
            radius_m: 20.0,
            depth_m: None,
            speed_mps: 1.0,
            clockwise: true,
        }),
        Packet::SetDepth(SetDepth {
            auth: a(7),
            depth_m: 25.0,
        }),
    ];
    packets
        .iter()
        .map(|p| p.encode(&key).expect("the seeds encode").to_vec())
        .collect()
}

/// Feeds `data` to a fresh receiver, whole and then split at every 31 bytes (a SeaTrac
/// payload), and checks: every payload is counted once; what is accepted re-encodes to the
/// same bytes; an accepted authenticated frame given again is refused as a replay.
pub fn receive(data: &[u8]) {
    let key = FleetKey::new(KEY);
    let mut rx = Receiver::new(ME, key.clone());
    let mut payloads = vec![data];
    payloads.extend(data.chunks(crate::MAX_FRAME));
    for p in &payloads {
        if let Ok(packet) = rx.receive(p) {
            let again = packet.encode(&key).expect("an accepted message re-encodes");
            assert_eq!(again.as_bytes(), *p, "{packet:?}");
            if packet.auth().is_some() {
                assert!(rx.receive(p).is_err(), "a replay was accepted: {packet:?}");
            }
        }
    }
    let c = rx.counters();
    assert_eq!(c.accepted + c.rejected(), c.received);
}
