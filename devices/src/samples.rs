//! Sample device traffic for the benches, the drivers' real-rate example and fuzz seeds: a
//! typical message of each device as it comes off the wire (the vendors' documented examples,
//! or this crate's encoders over typical values), and [`repeat`], a buffer of many.
//!
//! ```
//! use devices::line::LineSplitter;
//! let buf = devices::samples::repeat(&devices::samples::teensy(), 30);
//! let mut n = 0;
//! LineSplitter::new(devices::teensy::MAX_LINE)
//!     .with_starts(b"$")
//!     .push(&buf, |l| n += usize::from(devices::teensy::Telemetry::parse(l).is_ok()));
//! assert_eq!(n, 30);
//! ```

use crate::a50::{DeadReckoningReport, Transducer, VelocityReport};
use crate::seatrac::{AhrsComp, Attitude, Environment, Response, Status};
use crate::teensy::Telemetry;

/// `n` lines taken in turn from `lines`, end to end.
pub fn repeat<T: AsRef<[u8]>>(lines: &[T], n: usize) -> Vec<u8> {
    let mut v = Vec::new();
    for k in 0..n {
        if let Some(l) = lines.get(k % lines.len().max(1)) {
            v.extend_from_slice(l.as_ref());
        }
    }
    v
}

/// NMEA 0183 GGA, RMC and VTG: the standard's worked examples (Munich, 1994), with their
/// checksums and CRLF.
pub fn nmea() -> Vec<Vec<u8>> {
    [
        &b"$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n"[..],
        b"$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A\r\n",
        b"$GPVTG,054.7,T,034.4,M,005.5,N,010.2,K*48\r\n",
    ]
    .map(<[u8]>::to_vec)
    .to_vec()
}

/// A gpsd TPV report (3D fix near the NMEA examples' position) and its newline.
pub fn gpsd_tpv() -> Vec<u8> {
    b"{\"class\":\"TPV\",\"device\":\"/dev/ttyUSB0\",\"mode\":3,\"time\":\"2026-11-26T12:00:00.000Z\",\"lat\":48.1173,\"lon\":11.5167,\"altMSL\":545.4,\"track\":84.4,\"speed\":11.5,\"eph\":2.1}\n".to_vec()
}

/// The A50's velocity report with bottom lock and its four beams (`json_v3.1`), newline
/// ended.
pub fn a50_velocity() -> Vec<u8> {
    VelocityReport {
        time_ms: 106.39,
        time_of_validity_us: Some(1_638_191_471_563_017),
        time_of_transmission_us: Some(1_638_191_471_752_336),
        vel_body_mps: [0.512, -0.0213, 0.0041],
        fom_mps: 0.0016,
        covariance: Some([[2.4e-8, -3.3e-9, -1.6e-10]; 3]),
        altitude_m: 4.95,
        transducers: (0..4)
            .map(|id| Transducer {
                id,
                velocity_mps: 0.25,
                distance_m: 5.5,
                rssi_dbm: -30.4,
                nsd_dbm: -88.7,
                beam_valid: true,
            })
            .collect(),
        velocity_valid: true,
        status: 0,
        format: Some("json_v3.1".into()),
    }
    .encode()
    .into_bytes()
}

/// The A50's dead-reckoning report (`position_local`), newline ended.
pub fn a50_dead_reckoning() -> Vec<u8> {
    DeadReckoningReport {
        ts_s: 49056.809,
        x_m: 12.0,
        y_m: -3.5,
        z_m: 1.25,
        std_m: 0.3,
        roll_deg: 1.0,
        pitch_deg: -2.0,
        yaw_deg: 271.5,
        status: 0,
        format: Some("json_v3.1".into()),
    }
    .encode()
    .into_bytes()
}

/// The X150's STATUS with the blocks the CoUGARs driver asks for (environment, attitude,
/// compensated AHRS), framed with its CRC and CRLF.
pub fn seatrac_status() -> Vec<u8> {
    Response::Status(seatrac_status_fields())
        .encode()
        .into_bytes()
}

/// The fields of [`seatrac_status`]: 1.2 m deep on 15.6 V; yaw 355.0, pitch -2.5 and roll
/// 1.0 deg.
pub fn seatrac_status_fields() -> Status {
    Status {
        timestamp_ms: 123_456,
        environment: Some(Environment {
            supply_mv: 15_600,
            temp_ddegc: 215,
            pressure_mbar: 1100,
            depth_dm: 12,
            vos_dmps: 14_820,
        }),
        attitude: Some(Attitude {
            yaw_ddeg: 3550,
            pitch_ddeg: -25,
            roll_ddeg: 10,
        }),
        mag_cal: None,
        acc_cal: None,
        ahrs_raw: None,
        ahrs_comp: Some(AhrsComp {
            acc: [0.01, -0.02, 0.99],
            mag: [20.0, -3.0, 40.0],
            gyro: [0.1, -0.2, 1.5],
        }),
    }
}

/// The Teensy's `$DEPTH`, `$BATTE` and `$LEAK` lines of one loop.
pub fn teensy() -> Vec<Vec<u8>> {
    [
        Telemetry::Depth {
            pressure_pa: 101_325.0,
            temp_degc: 21.3,
        },
        Telemetry::Battery {
            voltage_v: 15.9,
            current_a: 2.1,
        },
        Telemetry::Leak { leak: false },
    ]
    .map(|t| t.encode().into_bytes())
    .to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::line::LineSplitter;

    #[test]
    fn every_sample_parses() {
        for l in nmea() {
            assert!(crate::nmea::parse(l.strip_suffix(b"\r\n").unwrap()).is_ok());
        }
        assert!(crate::nmea::gpsd::parse(gpsd_tpv().trim_ascii_end()).is_ok());
        for l in [a50_velocity(), a50_dead_reckoning()] {
            assert!(crate::a50::parse(l.trim_ascii_end()).is_ok());
        }
        assert!(Response::decode(seatrac_status().trim_ascii_end()).is_ok());
        for l in teensy() {
            assert!(Telemetry::parse(l.trim_ascii_end()).is_ok());
        }
        let mut s = LineSplitter::new(crate::nmea::MAX_LINE).with_starts(b"$");
        let mut n = 0;
        s.push(&repeat(&nmea(), 7), |_| n += 1);
        assert_eq!(n, 7);
        assert!(repeat::<Vec<u8>>(&[], 3).is_empty());
    }
}
