//! Loading the recorded captures of the real C++ MOOSDB (`../shared/corpus/captures`).
#![allow(dead_code)]

use std::path::PathBuf;

use bytes::Bytes;
use moosdb::{DataType, Message, MsgType};
use serde_json::Value as Json;

/// The captures folder; panics loudly when it is missing.
pub fn captures_dir() -> PathBuf {
    test_support::corpus("captures/README.md")
        .parent()
        .expect("a folder")
        .to_path_buf()
}

/// Every scenario folder (sorted).
pub fn scenarios() -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(captures_dir())
        .expect("read captures dir")
        .filter_map(|e| e.ok())
        .filter(|e| e.path().join("index.json").is_file())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    assert!(
        v.len() >= 7,
        "expected the 7 recorded scenarios, found {v:?}"
    );
    v
}

/// A scenario's index.json.
pub fn index(scenario: &str) -> Json {
    let p = captures_dir().join(scenario).join("index.json");
    let text = std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// A capture file's bytes.
pub fn bin(scenario: &str, file: &str) -> Vec<u8> {
    let p = captures_dir().join(scenario).join(file);
    std::fs::read(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

fn s(j: &Json, k: &str) -> String {
    j[k].as_str()
        .unwrap_or_else(|| panic!("field {k} missing in {j}"))
        .to_string()
}

fn f(j: &Json, k: &str) -> f64 {
    j[k].as_f64()
        .unwrap_or_else(|| panic!("field {k} missing in {j}"))
}

fn hex(h: &str) -> Vec<u8> {
    (0..h.len())
        .step_by(2)
        .map(|i| u8::from_str_radix(&h[i..i + 2], 16).expect("hex"))
        .collect()
}

fn code(j: &Json, k: &str) -> u8 {
    let t = s(j, k);
    assert_eq!(t.len(), 1, "{k} should be one char: {t:?}");
    t.as_bytes()[0]
}

/// The message an index.json entry describes, every field.
pub fn json_msg(j: &Json) -> Message {
    let sval = match j.get("sval_hex").and_then(|v| v.as_str()) {
        Some(h) => hex(h),
        None => s(j, "sval").into_bytes(),
    };
    Message {
        id: j["id"].as_i64().expect("id") as i32,
        msg_type: MsgType::from_code(code(j, "type")).expect("known type"),
        data_type: DataType::from_code(code(j, "dtype")).expect("known data type"),
        src: Bytes::from(s(j, "src")),
        src_aux: Bytes::from(s(j, "src_aux")),
        community: Bytes::from(s(j, "community")),
        key: Bytes::from(s(j, "key")),
        time: f(j, "time"),
        dval: f(j, "dval"),
        dval2: f(j, "dval2"),
        sval: Bytes::from(sval),
    }
}

/// One recorded packet.
#[derive(Debug, Clone)]
pub struct RecPacket {
    pub off: usize,
    pub len: usize,
    pub t: f64,
    pub msgs: Vec<Message>,
    /// Each message's own length field as recorded.
    pub lens: Vec<usize>,
}

/// The recorded packets of one connection direction (`c2s_packets` / `s2c_packets`).
pub fn packets(conn: &Json, dir: &str) -> Vec<RecPacket> {
    conn[dir]
        .as_array()
        .unwrap_or_else(|| panic!("{dir} missing"))
        .iter()
        .map(|p| RecPacket {
            off: p["off"].as_u64().expect("off") as usize,
            len: p["len"].as_u64().expect("len") as usize,
            t: f(p, "t"),
            msgs: p["msgs"]
                .as_array()
                .expect("msgs")
                .iter()
                .map(json_msg)
                .collect(),
            lens: p["msgs"]
                .as_array()
                .expect("msgs")
                .iter()
                .map(|m| m["len"].as_u64().expect("len") as usize)
                .collect(),
        })
        .collect()
}

/// `key = value` of the mission text (first match, case-insensitive key).
pub fn mission_value(mission: &str, key: &str) -> Option<String> {
    mission.lines().find_map(|l| {
        let (k, v) = l.split_once('=')?;
        k.trim()
            .eq_ignore_ascii_case(key)
            .then(|| v.trim().to_string())
    })
}
