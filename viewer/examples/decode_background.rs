//! Decodes background images as `coug view` does and says what each is: the TIFF's kind,
//! its size, and the PNG the page would be served, or why it cannot be shown.
//!
//! `cargo run --release -p viewer --example decode_background FILE.tif [FILE.tif ...]`

use std::time::Instant;

use viewer::background::{decode_tiff, describe_tiff, encode_png};

fn main() {
    let files: Vec<String> = std::env::args().skip(1).collect();
    if files.is_empty() {
        eprintln!("usage: decode_background FILE.tif [FILE.tif ...]");
        std::process::exit(2);
    }
    let mut failed = false;
    for f in files {
        let bytes = match std::fs::read(&f) {
            Ok(b) => b,
            Err(e) => {
                println!("{f}: {e}");
                failed = true;
                continue;
            }
        };
        let t0 = Instant::now();
        match decode_tiff(&bytes) {
            Ok(img) => {
                let png = encode_png(&img);
                println!(
                    "{f}: {}, {} x {} px, decoded and re-encoded in {:.2} s, PNG {} kB",
                    describe_tiff(&bytes),
                    img.width,
                    img.height,
                    t0.elapsed().as_secs_f64(),
                    png.len() / 1000
                );
            }
            Err(e) => {
                println!("{f}: {e}");
                failed = true;
            }
        }
    }
    if failed {
        std::process::exit(1);
    }
}
