//! End-to-end tests of `coug plot` (the real binary on an alog written by the alog crate).

use std::process::Command;

use alog::{AlogWriter, Header, LogValue};
use test_support::scratch_dir;

fn coug(args: &[&std::ffi::OsStr]) -> (i32, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_coug"))
        .args(args)
        .output()
        .expect("run coug");
    (
        out.status.code().expect("exit code"),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// A dive along a line and back, with a survey seglist, written as pLogger would.
fn write_log(path: &std::path::Path) {
    let header = Header {
        path: "./logs/Dive_Test_1_1_1970_____00_00_00/Dive_Test_1_1_1970_____00_00_00.alog",
        opened_on: "Thu Jan  1 00:00:00 1970",
        log_start: 1000.0,
        mark_data_type: false,
    };
    let mut w = AlogWriter::new(Vec::new(), &header).unwrap();
    for k in 0..300 {
        let t = 1000.0 + f64::from(k);
        let x = if k < 150 {
            f64::from(k)
        } else {
            f64::from(300 - k)
        };
        w.record(t, "NAV_X", "uSimMarine", LogValue::Double(x))
            .unwrap();
        w.record(t, "NAV_Y", "uSimMarine", LogValue::Double(0.5 * x))
            .unwrap();
        w.record(
            t,
            "NAV_DEPTH",
            "uSimMarine",
            LogValue::Double(if k < 20 { 0.0 } else { 5.0 }),
        )
        .unwrap();
    }
    w.record(
        1001.0,
        "VIEW_SEGLIST",
        "pHelmIvP",
        LogValue::String("pts={0,0:150,75},label=survey"),
    )
    .unwrap();
    std::fs::write(path, w.into_inner()).unwrap();
}

#[test]
fn plot_writes_svg_and_png() {
    let dir = scratch_dir("plot-cli-ok");
    let log = dir.join("dive.alog");
    write_log(&log);
    let svg = dir.join("dive.svg");
    let (code, err) = coug(&[
        "plot".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        svg.as_os_str(),
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&svg).unwrap();
    let doc = roxmltree::Document::parse(&text).expect("valid SVG");
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    let texts: Vec<String> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .filter_map(|n| n.text())
        .map(|t| t.trim().to_string())
        .collect();
    assert!(texts.iter().any(|t| t == "depth (m)"), "{texts:?}");
    // The title defaults to the mission's name as the log's banner gives it (the file was
    // renamed dive.alog), in its own case.
    assert!(
        texts.iter().any(|t| t == "Dive_Test"),
        "title defaults to the mission's name: {texts:?}"
    );
    for label in [
        "x (m)",
        "y (m)",
        "time (s)",
        "track",
        "start",
        "end",
        "waypoints",
    ] {
        assert!(
            texts.iter().any(|t| t == label),
            "missing {label}: {texts:?}"
        );
    }

    let png_path = dir.join("dive.png");
    let (code, err) = coug(&[
        "plot".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        png_path.as_os_str(),
        "--width".as_ref(),
        "500".as_ref(),
    ]);
    assert_eq!(code, 0, "{err}");
    let bytes = std::fs::read(&png_path).unwrap();
    let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.width, 500);
    assert!(
        info.height > 500,
        "track panel plus depth panel: {}",
        info.height
    );
}

#[test]
fn plot_reports_bad_input() {
    let dir = scratch_dir("plot-cli-bad");
    let log = dir.join("x.alog");
    write_log(&log);
    let (code, err) = coug(&[
        "plot".as_ref(),
        log.as_os_str(),
        "-o".as_ref(),
        dir.join("x.jpg").as_os_str(),
    ]);
    assert_eq!(code, 1);
    assert!(err.contains("must end in .svg or .png"), "{err}");
    let (code, err) = coug(&[
        "plot".as_ref(),
        dir.join("missing.alog").as_os_str(),
        "-o".as_ref(),
        dir.join("m.svg").as_os_str(),
    ]);
    assert_eq!(code, 1);
    assert!(err.contains("cannot read"), "{err}");
    let empty = dir.join("empty.alog");
    std::fs::write(&empty, "%% LOGSTART 0\n1.0 DEPLOY uPokeDB true \n").unwrap();
    let (code, err) = coug(&[
        "plot".as_ref(),
        empty.as_os_str(),
        "-o".as_ref(),
        dir.join("e.svg").as_os_str(),
    ]);
    assert_eq!(code, 1);
    assert!(err.contains("no vehicle track"), "{err}");
}
