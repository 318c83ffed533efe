//! The background image end to end, without a browser: a generated `.tif` (four coloured
//! quadrants) and its `.info` (lat/lon bounds computed from known local corners), named by
//! a mission's pMarineViewer `tiff_file`; the websocket snapshot places the image's corners
//! at those local metres on the mission's LatOrigin/LongOrigin, and `/background.png` is
//! the image, pixel for pixel.

use std::path::Path;
use std::sync::Arc;
use std::time::Duration;

use futures_util::StreamExt;
use moos_types::Value;
use serde_json::Value as Json;
use tokio::time::timeout;
use tokio_tungstenite::tungstenite::Message;
use viewer::background::Background;
use viewer::server::{Outbox, Viewer, ViewerConfig, serve};

const WAIT: Duration = Duration::from_secs(15);
const ORIGIN: (f64, f64) = (43.825300, -70.330400);
/// The image's local box: left, right, bottom, top (metres).
const BOX: [f64; 4] = [-100.0, 300.0, -200.0, 100.0];
const QUADRANTS: [[u8; 3]; 4] = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]];

struct NoPosts;

impl Outbox for NoPosts {
    fn post(&self, _: &str, _: Value) -> Result<(), String> {
        Err("test".into())
    }
    fn moos_time(&self) -> f64 {
        0.0
    }
}

/// Writes `map.tif` (40 x 20 px: red, green on top; blue, white below) and `map.info`, and
/// returns the mission naming it.
fn write_map(dir: &Path) -> String {
    let (w, h) = (40u32, 20u32);
    let mut rgb = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let q = usize::from(y >= h / 2) * 2 + usize::from(x >= w / 2);
            rgb.extend_from_slice(&QUADRANTS[q]);
        }
    }
    let file = std::fs::File::create(dir.join("map.tif")).unwrap();
    let mut enc = tiff::encoder::TiffEncoder::new(std::io::BufWriter::new(file)).unwrap();
    enc.write_image::<tiff::encoder::colortype::RGB8>(w, h, &rgb)
        .unwrap();
    drop(enc);
    let grid = vehicle::geodesy::LocalGrid::new(ORIGIN.0, ORIGIN.1).unwrap();
    let (north, west) = grid.to_latlon(BOX[0], BOX[3]).unwrap();
    let (south, east) = grid.to_latlon(BOX[1], BOX[2]).unwrap();
    std::fs::write(
        dir.join("map.info"),
        format!(
            "// generated\nlat_north = {north:.10}\nlat_south = {south:.10}\n\
             lon_west = {west:.10}\nlon_east = {east:.10}\n"
        ),
    )
    .unwrap();
    format!(
        "LatOrigin = {}\nLongOrigin = {}\nProcessConfig = pMarineViewer\n{{\n  tiff_file = map.tif\n}}\n",
        ORIGIN.0, ORIGIN.1
    )
}

fn mission(text: &str) -> mission::moos::MissionFile {
    let src = mission::source::SourceMap::from_text("m.moos", text);
    mission::moos::parse_moos(&src).value
}

#[tokio::test]
async fn the_image_corners_land_on_the_mission_grid_and_the_png_is_the_tiff() {
    let dir = test_support::scratch_dir("viewer-background");
    let m = mission(&write_map(&dir));
    let bg = Background::for_mission(&m, Some(&dir))
        .expect("the mission names a tiff_file")
        .expect("it loads");
    let config = ViewerConfig {
        bind: "127.0.0.1:0".parse().unwrap(),
        background: Some(Arc::new(bg)),
        ..ViewerConfig::for_mission(&m)
    };
    let viewer = Viewer::new(&config, Arc::new(NoPosts)).unwrap();
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
    let addr = listener.local_addr().unwrap();
    tokio::spawn(serve(viewer, listener));

    let (mut ws, _) = timeout(
        WAIT,
        tokio_tungstenite::connect_async(format!("ws://{addr}/ws")),
    )
    .await
    .expect("in time")
    .expect("accepted");
    let snapshot: Json = timeout(WAIT, async {
        loop {
            if let Message::Text(t) = ws.next().await.unwrap().unwrap() {
                break serde_json::from_str(t.as_str()).unwrap();
            }
        }
    })
    .await
    .unwrap();
    let b = &snapshot["background"];
    assert_eq!(b["url"], "/background.png");
    assert_eq!(
        (b["width"].as_u64(), b["height"].as_u64()),
        (Some(40), Some(20))
    );
    for (key, want) in [
        ("left", BOX[0]),
        ("right", BOX[1]),
        ("bottom", BOX[2]),
        ("top", BOX[3]),
    ] {
        let got = b[key].as_f64().unwrap();
        assert!((got - want).abs() < 0.01, "{key}: {got} (expected {want})");
    }

    // The PNG, over plain HTTP.
    use tokio::io::{AsyncReadExt, AsyncWriteExt};
    let mut s = tokio::net::TcpStream::connect(addr).await.unwrap();
    s.write_all(
        format!("GET /background.png HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n")
            .as_bytes(),
    )
    .await
    .unwrap();
    let mut resp = Vec::new();
    timeout(WAIT, s.read_to_end(&mut resp))
        .await
        .unwrap()
        .unwrap();
    let split = resp.windows(4).position(|w| w == b"\r\n\r\n").unwrap();
    let head = String::from_utf8_lossy(&resp[..split]).to_ascii_lowercase();
    assert!(head.starts_with("http/1.1 200"), "{head}");
    assert!(head.contains("content-type: image/png"), "{head}");
    let body = &resp[split + 4..];
    let mut reader = png::Decoder::new(std::io::Cursor::new(body))
        .read_info()
        .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!((info.width, info.height), (40, 20));
    let px = |x: usize, y: usize| {
        let i = (y * 40 + x) * 4;
        [buf[i], buf[i + 1], buf[i + 2], buf[i + 3]]
    };
    assert_eq!(px(0, 0), [255, 0, 0, 255], "north-west red");
    assert_eq!(px(39, 0), [0, 255, 0, 255], "north-east green");
    assert_eq!(px(0, 19), [0, 0, 255, 255], "south-west blue");
    assert_eq!(px(39, 19), [255, 255, 255, 255], "south-east white");
}

#[test]
fn a_missing_info_file_is_reported_with_where_it_was_looked_for() {
    let dir = test_support::scratch_dir("viewer-background-missing");
    let m = mission(&write_map(&dir));
    std::fs::remove_file(dir.join("map.info")).unwrap();
    let err = Background::for_mission(&m, Some(&dir))
        .unwrap()
        .unwrap_err();
    let text = err.to_string();
    assert!(text.contains("map.tif with its .info"), "{text}");
    assert!(
        Background::for_mission(&mission("ProcessConfig = pMarineViewer\n{\n}\n"), None).is_none()
    );
}
