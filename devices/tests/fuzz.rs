//! The fuzz bodies of `devices::fuzz` on stable: each over seeds taken from the vendors'
//! documentation (the same lines as the unit tests) and then a fixed number of deterministic
//! mutants (`test_support::fuzz::Campaign`), a few seconds each in a debug build.

use test_support::fuzz::Campaign;

/// Mutants per protocol.
const ITERATIONS: usize = 60_000;

fn seeds(lines: &[&[u8]]) -> Vec<Vec<u8>> {
    let mut all: Vec<Vec<u8>> = lines.iter().map(|l| l.to_vec()).collect();
    all.push(lines.concat());
    all
}

#[test]
fn fuzz_nmea_and_gpsd() {
    let s = seeds(&[
        b"$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47\r\n",
        b"$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A\r\n",
        b"$GPVTG,054.7,T,034.4,M,005.5,N,010.2,K*48\r\n",
        br#"{"class":"TPV","device":"/dev/pts/1","time":"2005-06-08T10:34:48.283Z","ept":0.005,"lat":46.498293369,"lon":7.567411672,"alt":1343.127,"eph":36.000,"epv":32.321,"track":10.3788,"speed":0.091,"climb":-0.085,"mode":3}
"#,
        br#"{"class":"SKY","device":"/dev/pts/1","time":"2005-07-08T11:28:07.114Z","xdop":1.55,"hdop":1.24,"pdop":1.99,"satellites":[{"PRN":23,"el":6,"az":84,"ss":0,"used":false},{"PRN":8,"el":66,"az":189,"ss":44,"used":true}]}
"#,
    ]);
    let r = Campaign::new("nmea", s)
        .tokens(&[
            "$GPGGA,",
            "$GNRMC,",
            "$GPVTG,",
            "*",
            ",N,",
            ",W,",
            "\r\n",
            "{\"class\":\"TPV\"",
            "\"mode\":",
        ])
        .iterations(ITERATIONS)
        .run(devices::fuzz::nmea);
    assert_eq!((r.seeds, r.mutants), (6, ITERATIONS));
    assert!(r.changed > ITERATIONS / 2, "{r:?}");
}

#[test]
fn fuzz_a50() {
    let s = seeds(&[
        br#"{"time": 106.39, "vx": -3.7e-05, "vy": 5.7e-05, "vz": 2.4e-05, "fom": 0.00016, "covariance": [[2.4e-08, -3.3e-09, -1.6e-10], [-3.3e-09, 1.4e-08, 4.0e-10], [-1.6e-10, 4.0e-10, 1.5e-09]], "altitude": 0.49, "transducers": [{"id": 0, "velocity": 0.0001, "distance": 0.5568, "rssi": -30.49, "nsd": -88.73, "beam_valid": true}], "velocity_valid": true, "status": 0, "format": "json_v3.1", "type": "velocity", "time_of_validity": 1638191471563017, "time_of_transmission": 1638191471752336}
"#,
        br#"{"ts": 49056.809, "x": 12.43, "y": 64.61, "z": 1.76, "std": 0.10, "roll": -0.54, "pitch": 1.61, "yaw": 2.02, "type": "position_local", "status": 0, "format": "json_v3.1"}
"#,
        br#"{"response_to":"get_config","success":true,"error_message":"","result":{"speed_of_sound":1475.0,"acoustic_enabled":true,"dark_mode_enabled":false,"mounting_rotation_offset":0.0,"range_mode":"auto"},"format":"json_v3.1","type":"response"}
"#,
        b"{\"command\":\"set_config\",\"parameters\":{\"acoustic_enabled\":false}}\n",
        b"{\"command\":\"calibrate_gyro\"}\n",
    ]);
    let r = Campaign::new("a50", s)
        .tokens(&[
            "\"type\":",
            "\"velocity\"",
            "\"altitude\":",
            "\"pitch\":",
            "\"response_to\":",
            "null",
            "true",
            "1e308",
            "[",
            "]",
            "{",
            "}",
        ])
        .iterations(ITERATIONS)
        .run(devices::fuzz::a50);
    assert_eq!((r.seeds, r.mutants), (6, ITERATIONS));
}

#[test]
fn fuzz_seatrac() {
    let s = seeds(&[
        b"#01C1C0\r\n",
        b"#400F0405E7\r\n",
        b"$40300F55D0\r\n",
        b"$100340E2010000000000762FD700810400000F000000E4398403E7FF0C00C13B\r\n",
        b"$61000303050807000000001400E43944FDE803000068890900CF010444FD3AFD3FFD42FDC201D4FE0C00000361626378BC\r\n",
    ]);
    let r = Campaign::new("seatrac", s)
        .tokens(&["$", "#", "\r\n", "10", "3F", "61", "42", "FF", "0000"])
        .iterations(ITERATIONS)
        .run(devices::fuzz::seatrac);
    assert_eq!((r.seeds, r.mutants), (6, ITERATIONS));
}

#[test]
fn fuzz_teensy() {
    let s = seeds(&[
        b"$DEPTH,101919.6,14.2\r\n",
        b"$BATTE,16.4,2.3\r\n",
        b"$LEAK,0\r\n",
        b"$CONTR,12.5,-3,0.333333,30\n",
    ]);
    let r = Campaign::new("teensy", s)
        .tokens(&[
            "$DEPTH,", "$BATTE,", "$LEAK,", "$CONTR,", ",", "-", "e", "\r\n",
        ])
        .iterations(ITERATIONS)
        .run(devices::fuzz::teensy);
    assert_eq!((r.seeds, r.mutants), (5, ITERATIONS));
}
