//! The alog format end to end: MOOS-IvP-style text read back, and writer output read back.

use alog::{AlogWriter, Header, LogValue, Value, ctime, log_root, parse};
use chrono::NaiveDate;

/// A file laid out as pLogger 2024 writes it (banner with the epoch date quirk, the
/// DB's variables, helm strings with spaces and commas), built by hand per the reference.
const MOOS_IVP_STYLE: &str = "\
%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%
%% LOG FILE:       ./LOG_ALPHA_5_8_2026_____18_22_55/LOG_ALPHA_5_8_2026_____18_22_55.alog
%% FILE OPENED ON  Thu Jan  1 00:00:00 1970
%% LOGSTART           1786054975.123456
%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%
0.07912         DB_TIME              MOOSDB_alpha    1786054975.20258 
0.07912         DB_CLIENTS           MOOSDB_alpha    pHelmIvP,uSimMarine,pLogger, 
1.85123         NAV_X                uSimMarine      -23.10000    
1.85123         IVPHELM_SUMMARY      pHelmIvP        iter=4,utc_time=1786054976.97,ofnum=1,var=speed:1.2,var=course:181 
2.00000         VIEW_SEGLIST         pHelmIvP        pts={60,-40:60,-160:150,-160},label=alpha_waypt_survey,edge_color=white 
12.34567        DESIRED_SPEED        pHelmIvP        1.50000      
";

#[test]
fn reads_a_moos_ivp_style_file() {
    let log = parse(MOOS_IVP_STYLE).unwrap();
    assert_eq!(log.log_start, Some(1786054975.123456));
    assert_eq!(log.opened_on.as_deref(), Some("Thu Jan  1 00:00:00 1970"));
    assert_eq!(
        log.log_file.as_deref(),
        Some("./LOG_ALPHA_5_8_2026_____18_22_55/LOG_ALPHA_5_8_2026_____18_22_55.alog")
    );
    assert!(!log.data_type_marking);
    assert_eq!(log.entries.len(), 6);
    let e = &log.entries[0];
    assert_eq!(
        (e.time, e.var.as_str(), e.source.as_str()),
        (0.07912, "DB_TIME", "MOOSDB_alpha")
    );
    assert_eq!(e.value, Value::Double(1786054975.20258));
    assert_eq!(
        log.entries[1].value.as_str(),
        Some("pHelmIvP,uSimMarine,pLogger,")
    );
    assert_eq!(log.entries[2].value.as_f64(), Some(-23.1));
    assert_eq!(
        log.entries[4].value.as_str(),
        Some("pts={60,-40:60,-160:150,-160},label=alpha_waypt_survey,edge_color=white")
    );
    assert_eq!(log.entries[5].time, 12.34567);
    assert_eq!(log.entries[5].value.as_f64(), Some(1.5));
}

#[test]
fn writer_output_reads_back_and_is_deterministic() {
    let header = Header {
        path: "./LOG_T/LOG_T.alog",
        opened_on: "Thu Jan  1 00:00:00 1970",
        log_start: 5000.25,
        mark_data_type: false,
    };
    let write = || {
        let mut w = AlogWriter::new(Vec::new(), &header).unwrap();
        w.record(5000.25, "DEPLOY", "uPokeDB", LogValue::String("true"))
            .unwrap();
        w.record(5001.5, "NAV_DEPTH", "uSimMarine", LogValue::Double(3.25))
            .unwrap();
        w.record(5002.0, "NOTE", "app", LogValue::String("a b  c"))
            .unwrap();
        w.record(5003.0, "MULTI", "app", LogValue::String("one\ntwo"))
            .unwrap();
        w.record(5004.0, "LAST", "app", LogValue::Double(-0.5))
            .unwrap();
        w.into_inner()
    };
    let a = write();
    assert_eq!(a, write());
    let text = String::from_utf8(a).unwrap();
    let log = parse(&text).unwrap();
    assert_eq!(log.log_start, Some(5000.25));
    let got: Vec<(f64, &str, &str, Value)> = log
        .entries
        .iter()
        .map(|e| (e.time, e.var.as_str(), e.source.as_str(), e.value.clone()))
        .collect();
    assert_eq!(
        got,
        vec![
            (0.0, "DEPLOY", "uPokeDB", Value::String("true".into())),
            (1.25, "NAV_DEPTH", "uSimMarine", Value::Double(3.25)),
            (1.75, "NOTE", "app", Value::String("a b  c".into())),
            (2.75, "MULTI", "app", Value::String("one\ntwo".into())),
            (3.75, "LAST", "app", Value::Double(-0.5)),
        ]
    );
}

#[test]
fn marked_types_read_back_as_written() {
    let header = Header {
        path: "x.alog",
        opened_on: "Thu Jan  1 00:00:00 1970",
        log_start: 0.0,
        mark_data_type: true,
    };
    let mut w = AlogWriter::new(Vec::new(), &header).unwrap();
    w.record(1.0, "S_NUM", "a", LogValue::String("42")).unwrap();
    w.record(2.0, "D_NUM", "a", LogValue::Double(42.0)).unwrap();
    w.flush().unwrap();
    let log = parse(std::str::from_utf8(w.get_ref()).unwrap()).unwrap();
    assert!(log.data_type_marking);
    assert_eq!(log.entries[0].value, Value::String("42".into()));
    assert_eq!(log.entries[1].value, Value::Double(42.0));
}

#[test]
fn rejects_non_alog_text() {
    let err = parse("hello world\n1.0 X a 2\n").unwrap_err();
    assert_eq!(
        err.to_string(),
        "line 1: not an alog record: \"hello world\""
    );
    let err = parse("%% LOGSTART abc\n").unwrap_err();
    assert!(matches!(err, alog::AlogError::BadLogStart { line: 1, .. }));
    assert!(parse("").unwrap().entries.is_empty());
}

#[test]
fn names_and_dates() {
    let t = NaiveDate::from_ymd_opt(2026, 12, 25)
        .unwrap()
        .and_hms_opt(9, 7, 3)
        .unwrap();
    assert_eq!(
        log_root("MOOSLog", &t, true),
        "MOOSLog_25_12_2026_____09_07_03"
    );
    assert_eq!(ctime(&t), "Fri Dec 25 09:07:03 2026");
    let t = NaiveDate::from_ymd_opt(2026, 8, 5)
        .unwrap()
        .and_hms_opt(18, 22, 55)
        .unwrap();
    assert_eq!(
        log_root("LOG_ALPHA", &t, true),
        "LOG_ALPHA_5_8_2026_____18_22_55"
    );
    assert_eq!(ctime(&t), "Wed Aug  5 18:22:55 2026");
}
