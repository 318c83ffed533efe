//! pMarineViewer's `tiff_file` in every kind libtiff reads and users are likely to hand in:
//! one picture (four quadrants) written as palette, grey (1 to 16 bits, either polarity,
//! with alpha), RGB and RGBA (8 and 16 bits, chunky and planar, premultiplied alpha), CMYK
//! and JPEG-compressed TIFFs, little- and big-endian, with the compressions MOOS-IvP's own
//! backgrounds use (AerialMIT.tif: RGBA with associated alpha, deflate with a horizontal
//! predictor; forrest19.tif: JPEG-compressed RGB), must come out as the same PNG the
//! viewer serves. Kinds it cannot read are refused with an error naming the file and the
//! kind, never a panic.

use std::path::{Path, PathBuf};

use tiff::encoder::colortype::{self, ColorType};
use tiff::encoder::{Compression, DeflateLevel, Predictor, TiffEncoder};
use tiff::tags::{ExtraSamples, PhotometricInterpretation, SampleFormat, Tag};
use viewer::background::{Background, BackgroundError, decode_tiff, describe_tiff, encode_png};

/// The picture: 10 x 6 pixels (rows not a whole number of bytes at 1 to 4 bits), quadrants
/// top-left, top-right, bottom-left, bottom-right.
const W: u32 = 10;
const H: u32 = 6;
const COLOURS: [[u8; 3]; 4] = [[255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]];
/// Grey levels every depth from 2 bits up holds exactly.
const GREYS: [u8; 4] = [0, 85, 170, 255];

fn quadrant(x: u32, y: u32, w: u32, h: u32) -> usize {
    usize::from(y >= h / 2) * 2 + usize::from(x >= w / 2)
}

/// One value per pixel from the quadrant's index, rows top first.
fn pixels<T>(w: u32, h: u32, f: impl Fn(usize) -> Vec<T>) -> Vec<T> {
    (0..h)
        .flat_map(|y| (0..w).map(move |x| quadrant(x, y, w, h)))
        .flat_map(f)
        .collect()
}

fn expected_colour() -> Vec<u8> {
    pixels(W, H, |q| {
        let [r, g, b] = COLOURS[q];
        vec![r, g, b, 255]
    })
}

fn expected_grey() -> Vec<u8> {
    pixels(W, H, |q| vec![GREYS[q], GREYS[q], GREYS[q], 255])
}

fn encode<C: ColorType>(
    data: &[C::Inner],
    compression: Compression,
    predictor: Predictor,
) -> Vec<u8>
where
    [C::Inner]: tiff::encoder::TiffValue,
{
    encode_with::<C>(data, compression, predictor, |_| {})
}

/// A TIFF written by the `tiff` crate's encoder, `tags` adding tags to the image's IFD.
fn encode_with<C: ColorType>(
    data: &[C::Inner],
    compression: Compression,
    predictor: Predictor,
    tags: impl FnOnce(
        &mut tiff::encoder::ImageEncoder<
            '_,
            &mut std::io::Cursor<Vec<u8>>,
            C,
            tiff::encoder::TiffKindStandard,
        >,
    ),
) -> Vec<u8>
where
    [C::Inner]: tiff::encoder::TiffValue,
{
    let mut out = std::io::Cursor::new(Vec::new());
    {
        let mut enc = TiffEncoder::new(&mut out)
            .unwrap()
            .with_compression(compression)
            .with_predictor(predictor);
        let mut img = enc.new_image::<C>(W, H).unwrap();
        tags(&mut img);
        img.write_data(data).unwrap();
    }
    out.into_inner()
}

/// A colour type the `tiff` crate's encoder does not have: 8-bit palette indices.
struct Palette8;

impl ColorType for Palette8 {
    type Inner = u8;
    const TIFF_VALUE: PhotometricInterpretation = PhotometricInterpretation::RGBPalette;
    const BITS_PER_SAMPLE: &'static [u16] = &[8];
    const SAMPLE_FORMAT: &'static [SampleFormat] = &[SampleFormat::Uint];
    fn horizontal_predict(row: &[u8], result: &mut Vec<u8>) {
        result.extend_from_slice(row);
    }
}

/// One IFD entry for [`hand_tiff`]: tag, field type (3 SHORT, 4 LONG, 7 UNDEFINED) and
/// values (each written in the type's size).
type HandTag = (u16, u16, Vec<u32>);

/// A single-strip TIFF written byte by byte, for what the encoder cannot write (sub-byte
/// samples, planar images, big-endian files, JPEG strips, unusual photometrics):
/// `strip` is the image data as stored.
fn hand_tiff(big_endian: bool, w: u32, h: u32, tags: &[HandTag], strip: &[u8]) -> Vec<u8> {
    let put = |out: &mut Vec<u8>, v: u32, n: usize| {
        let b = v.to_be_bytes();
        let b = &b[4 - n..];
        if big_endian {
            out.extend_from_slice(b);
        } else {
            out.extend(b.iter().rev());
        }
    };
    // A planar image has a strip per plane.
    let planes = if tags.iter().any(|t| t.0 == 284 && t.2 == [2]) {
        tags.iter().find(|t| t.0 == 277).map_or(1, |t| t.2[0])
    } else {
        1
    };
    let plane = strip.len() as u32 / planes;
    let mut all: Vec<HandTag> = vec![
        (256, 4, vec![w]),
        (257, 4, vec![h]),
        (273, 4, (0..planes).map(|p| 8 + p * plane).collect()),
        (278, 4, vec![h]),
        (279, 4, vec![plane; planes as usize]),
    ];
    all.extend(tags.iter().cloned());
    if !all.iter().any(|t| t.0 == 259) {
        all.push((259, 3, vec![1]));
    }
    all.sort_by_key(|t| t.0);
    let mut out = Vec::new();
    out.extend_from_slice(if big_endian { b"MM" } else { b"II" });
    put(&mut out, 42, 2);
    out.extend_from_slice(&[0; 4]);
    out.extend_from_slice(strip);
    if out.len() % 2 == 1 {
        out.push(0);
    }
    let ifd = out.len();
    let mut at = Vec::new();
    put(&mut at, ifd as u32, 4);
    out[4..8].copy_from_slice(&at);
    let mut spill = ifd + 2 + all.len() * 12 + 4;
    let mut values = Vec::new();
    let mut entries = Vec::new();
    for (tag, ty, vals) in &all {
        let size = match ty {
            3 => 2,
            4 => 4,
            _ => 1,
        };
        put(&mut entries, u32::from(*tag), 2);
        put(&mut entries, u32::from(*ty), 2);
        put(&mut entries, vals.len() as u32, 4);
        let mut bytes = Vec::new();
        for v in vals {
            put(&mut bytes, *v, size);
        }
        if bytes.len() <= 4 {
            bytes.resize(4, 0);
            entries.extend_from_slice(&bytes);
        } else {
            put(&mut entries, spill as u32, 4);
            spill += bytes.len();
            values.extend_from_slice(&bytes);
        }
    }
    put(&mut out, all.len() as u32, 2);
    out.extend_from_slice(&entries);
    put(&mut out, 0, 4);
    out.extend_from_slice(&values);
    out
}

/// Packs `bits`-bit samples, each row starting on a byte, most significant bits first.
fn pack(samples: &[u8], per_row: usize, bits: usize) -> Vec<u8> {
    let mut out = Vec::new();
    for row in samples.chunks(per_row) {
        let mut bytes = vec![0u8; (per_row * bits).div_ceil(8)];
        for (i, s) in row.iter().enumerate() {
            let bit = i * bits;
            bytes[bit / 8] |= s << (8 - bits - bit % 8);
        }
        out.extend(bytes);
    }
    out
}

/// A 16-entry colour map whose first four entries are the quadrants' colours (16 bits each).
fn colour_map(entries: usize, colours: &[[u8; 3]]) -> Vec<u32> {
    let mut map = vec![0u32; 3 * entries];
    for (i, c) in colours.iter().enumerate() {
        for ch in 0..3 {
            map[ch * entries + i] = u32::from(c[ch]) * 257;
        }
    }
    map
}

/// Every colour kind: a name and the file's bytes.
fn colour_kinds() -> Vec<(&'static str, Vec<u8>)> {
    let rgb8 = pixels(W, H, |q| COLOURS[q].to_vec());
    let rgb16: Vec<u16> = rgb8.iter().map(|v| u16::from(*v) * 257).collect();
    let rgba8 = expected_colour();
    let rgba16: Vec<u16> = rgba8.iter().map(|v| u16::from(*v) * 257).collect();
    let cmyk8 = pixels(W, H, |q| {
        let [r, g, b] = COLOURS[q];
        vec![255 - r, 255 - g, 255 - b, 0]
    });
    let index = pixels(W, H, |q| vec![q as u8]);
    let deflate = Compression::Deflate(DeflateLevel::Balanced);
    let planar: Vec<u8> = (0..3)
        .flat_map(|ch| rgb8.iter().skip(ch).step_by(3).copied().collect::<Vec<_>>())
        .collect();
    let map16 = colour_map(16, &COLOURS);
    let map256 = colour_map(256, &COLOURS);
    let be16: Vec<u8> = rgb16.iter().flat_map(|v| v.to_be_bytes()).collect();
    vec![
        (
            "RGB 8-bit",
            encode::<colortype::RGB8>(&rgb8, Compression::Uncompressed, Predictor::None),
        ),
        (
            "RGB 8-bit LZW",
            encode::<colortype::RGB8>(&rgb8, Compression::Lzw, Predictor::Horizontal),
        ),
        (
            "RGB 16-bit deflate",
            encode::<colortype::RGB16>(&rgb16, deflate, Predictor::Horizontal),
        ),
        (
            "RGB 16-bit big-endian",
            hand_tiff(
                true,
                W,
                H,
                &[(258, 3, vec![16; 3]), (262, 3, vec![2]), (277, 3, vec![3])],
                &be16,
            ),
        ),
        (
            "RGB 8-bit planar",
            hand_tiff(
                false,
                W,
                H,
                &[
                    (258, 3, vec![8; 3]),
                    (262, 3, vec![2]),
                    (277, 3, vec![3]),
                    (284, 3, vec![2]),
                ],
                &planar,
            ),
        ),
        (
            "RGBA 8-bit",
            encode::<colortype::RGBA8>(&rgba8, Compression::Packbits, Predictor::None),
        ),
        (
            "RGBA 16-bit",
            encode::<colortype::RGBA16>(&rgba16, Compression::Lzw, Predictor::None),
        ),
        (
            // As AerialMIT.tif: associated alpha, deflate, horizontal predictor.
            "RGBA 8-bit associated alpha deflate (AerialMIT)",
            encode_with::<colortype::RGBA8>(&rgba8, deflate, Predictor::Horizontal, |img| {
                let associated = [ExtraSamples::AssociatedAlpha.to_u16()];
                img.encoder()
                    .write_tag(Tag::ExtraSamples, &associated[..])
                    .unwrap()
            }),
        ),
        (
            "CMYK 8-bit",
            encode::<colortype::CMYK8>(&cmyk8, Compression::Lzw, Predictor::None),
        ),
        (
            "CMYK 16-bit",
            encode::<colortype::CMYK16>(
                &cmyk8
                    .iter()
                    .map(|v| u16::from(*v) * 257)
                    .collect::<Vec<_>>(),
                Compression::Uncompressed,
                Predictor::None,
            ),
        ),
        (
            "palette 8-bit LZW",
            encode_with::<Palette8>(&index, Compression::Lzw, Predictor::None, |img| {
                let map: Vec<u16> = map256.iter().map(|v| *v as u16).collect();
                img.encoder().write_tag(Tag::ColorMap, &map[..]).unwrap();
            }),
        ),
        (
            "palette 4-bit",
            hand_tiff(
                false,
                W,
                H,
                &[
                    (258, 3, vec![4]),
                    (262, 3, vec![3]),
                    (277, 3, vec![1]),
                    (320, 3, map16.clone()),
                ],
                &pack(&index, W as usize, 4),
            ),
        ),
        (
            "palette 4-bit big-endian",
            hand_tiff(
                true,
                W,
                H,
                &[
                    (258, 3, vec![4]),
                    (262, 3, vec![3]),
                    (277, 3, vec![1]),
                    (320, 3, map16),
                ],
                &pack(&index, W as usize, 4),
            ),
        ),
    ]
}

/// Every grey kind.
fn grey_kinds() -> Vec<(&'static str, Vec<u8>)> {
    let g8 = pixels(W, H, |q| vec![GREYS[q]]);
    let g16: Vec<u16> = g8.iter().map(|v| u16::from(*v) * 257).collect();
    let inverted: Vec<u8> = g8.iter().map(|v| 255 - v).collect();
    let ga8 = pixels(W, H, |q| vec![GREYS[q], 255]);
    let two_bit: Vec<u8> = g8.iter().map(|v| v / 85).collect();
    let four_bit: Vec<u8> = g8.iter().map(|v| v / 17).collect();
    let grey_map: Vec<u32> = colour_map(4, &GREYS.map(|g| [g, g, g]));
    vec![
        (
            "grey 8-bit",
            encode::<colortype::Gray8>(&g8, Compression::Uncompressed, Predictor::None),
        ),
        (
            "grey 16-bit LZW",
            encode::<colortype::Gray16>(&g16, Compression::Lzw, Predictor::Horizontal),
        ),
        (
            "grey 8-bit white is zero",
            hand_tiff(
                false,
                W,
                H,
                &[(258, 3, vec![8]), (262, 3, vec![0])],
                &inverted,
            ),
        ),
        (
            "grey 8-bit with alpha",
            hand_tiff(
                false,
                W,
                H,
                &[
                    (258, 3, vec![8, 8]),
                    (262, 3, vec![1]),
                    (277, 3, vec![2]),
                    (338, 3, vec![2]),
                ],
                &ga8,
            ),
        ),
        (
            "grey 2-bit",
            hand_tiff(
                false,
                W,
                H,
                &[(258, 3, vec![2]), (262, 3, vec![1])],
                &pack(&two_bit, W as usize, 2),
            ),
        ),
        (
            "grey 4-bit",
            hand_tiff(
                false,
                W,
                H,
                &[(258, 3, vec![4]), (262, 3, vec![1])],
                &pack(&four_bit, W as usize, 4),
            ),
        ),
        (
            "grey palette 2-bit",
            hand_tiff(
                false,
                W,
                H,
                &[(258, 3, vec![2]), (262, 3, vec![3]), (320, 3, grey_map)],
                &pack(&two_bit, W as usize, 2),
            ),
        ),
    ]
}

fn scratch(name: &str) -> PathBuf {
    test_support::scratch_dir(&format!("viewer-tiff-kinds-{name}"))
}

/// Writes `bytes` as `<name>.tif` with an `.info`, and loads it as the viewer does.
fn load(dir: &Path, name: &str, bytes: &[u8]) -> Result<Background, BackgroundError> {
    let file = name.replace([' ', '(', ')'], "_");
    let tif = dir.join(format!("{file}.tif"));
    std::fs::write(&tif, bytes).unwrap();
    let info = dir.join(format!("{file}.info"));
    std::fs::write(&info, "img_centx = 0.5\nimg_centy = 0.5\nimg_meters = 1\n").unwrap();
    Background::load(&tif, &info, None)
}

#[test]
fn every_colour_kind_decodes_to_the_same_served_png() {
    let dir = scratch("colour");
    let want = expected_colour();
    let png = encode_png(&viewer::background::Rgba {
        width: W,
        height: H,
        data: want.clone(),
    });
    for (name, bytes) in colour_kinds() {
        let img = decode_tiff(&bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!((img.width, img.height), (W, H), "{name}");
        assert_eq!(img.data, want, "{name} ({})", describe_tiff(&bytes));
        let bg = load(&dir, name, &bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(bg.png, png, "{name}: the served PNG");
    }
}

#[test]
fn every_grey_kind_decodes_to_the_same_served_png() {
    let dir = scratch("grey");
    let want = expected_grey();
    let png = encode_png(&viewer::background::Rgba {
        width: W,
        height: H,
        data: want.clone(),
    });
    for (name, bytes) in grey_kinds() {
        let img = decode_tiff(&bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(img.data, want, "{name} ({})", describe_tiff(&bytes));
        let bg = load(&dir, name, &bytes).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(bg.png, png, "{name}: the served PNG");
    }
}

#[test]
fn the_kinds_are_named() {
    let kinds: Vec<(String, String)> = colour_kinds()
        .into_iter()
        .chain(grey_kinds())
        .map(|(n, b)| (n.to_string(), describe_tiff(&b)))
        .collect();
    let of = |n: &str| &kinds.iter().find(|k| k.0 == n).unwrap().1;
    assert_eq!(of("palette 4-bit"), "palette 4-bit (uncompressed)");
    assert_eq!(of("palette 8-bit LZW"), "palette 8-bit (LZW)");
    assert_eq!(of("RGB 16-bit deflate"), "RGB 16-bit (deflate)");
    assert_eq!(of("RGB 16-bit big-endian"), "RGB 16-bit (uncompressed)");
    assert_eq!(of("CMYK 8-bit"), "CMYK (separated) 8-bit (LZW)");
    assert_eq!(
        of("RGBA 8-bit associated alpha deflate (AerialMIT)"),
        "RGB 8-bit, 4 samples (deflate)"
    );
    assert_eq!(
        of("grey 8-bit white is zero"),
        "grey (white is zero) 8-bit (uncompressed)"
    );
    assert_eq!(describe_tiff(b"GIF89a"), "not a TIFF");
}

#[test]
fn premultiplied_alpha_is_unmultiplied_and_straight_alpha_kept() {
    // Half-transparent red, stored premultiplied (associated) and straight (unassociated).
    let px: Vec<u8> = (0..W * H).flat_map(|_| [128u8, 0, 0, 128]).collect();
    let assoc =
        encode_with::<colortype::RGB8>(&px, Compression::Uncompressed, Predictor::None, |img| {
            img.extra_samples(&[ExtraSamples::AssociatedAlpha]).unwrap()
        });
    let straight = encode::<colortype::RGBA8>(&px, Compression::Uncompressed, Predictor::None);
    assert_eq!(&decode_tiff(&assoc).unwrap().data[..4], &[255, 0, 0, 128]);
    assert_eq!(
        &decode_tiff(&straight).unwrap().data[..4],
        &[128, 0, 0, 128]
    );
}

/// A 32 x 32 picture of 16-pixel quadrants (whole JPEG blocks), JPEG-encoded at quality
/// 100 into one strip: as RGB components (photometric RGB, as forrest19.tif) or converted
/// to YCbCr with 2 x 2 chroma subsampling (photometric YCbCr, libtiff's usual JPEG TIFF).
fn jpeg_tiff(ycbcr: bool) -> (Vec<u8>, Vec<u8>) {
    let (w, h) = (32u32, 32u32);
    let rgb = pixels(w, h, |q| COLOURS[q].to_vec());
    let mut jpeg = Vec::new();
    let mut enc = jpeg_encoder::Encoder::new(&mut jpeg, 100);
    let (colour, tags): (_, Vec<HandTag>) = if ycbcr {
        enc.set_sampling_factor(jpeg_encoder::SamplingFactor::F_2_2);
        (
            jpeg_encoder::ColorType::Rgb,
            vec![(262, 3, vec![6]), (530, 3, vec![2, 2])],
        )
    } else {
        // The components stored as they are: R, G, B.
        enc.set_sampling_factor(jpeg_encoder::SamplingFactor::F_1_1);
        (jpeg_encoder::ColorType::Ycbcr, vec![(262, 3, vec![2])])
    };
    enc.encode(&rgb, w as u16, h as u16, colour).unwrap();
    let mut all = vec![(258, 3, vec![8; 3]), (259, 3, vec![7]), (277, 3, vec![3])];
    all.extend(tags);
    let want = pixels(w, h, |q| {
        let [r, g, b] = COLOURS[q];
        vec![r, g, b, 255]
    });
    (hand_tiff(false, w, h, &all, &jpeg), want)
}

#[test]
fn jpeg_compressed_tiffs_decode_rgb_and_ycbcr() {
    for ycbcr in [false, true] {
        let (bytes, want) = jpeg_tiff(ycbcr);
        let kind = describe_tiff(&bytes);
        assert!(kind.ends_with("8-bit (JPEG)"), "{kind}");
        let img = decode_tiff(&bytes).unwrap_or_else(|e| panic!("{kind}: {e}"));
        assert_eq!((img.width, img.height), (32, 32));
        // Lossy: every channel within a few levels of the quadrant's colour; with chroma
        // subsampling, away from the quadrants' edges (the upsampled chroma blends there).
        let margin = if ycbcr { 3 } else { 0 };
        let inside = |p: usize| {
            let (x, y) = (p % 32 % 16, p / 32 % 16);
            (margin..16 - margin).contains(&x) && (margin..16 - margin).contains(&y)
        };
        let mut worst = (0, 0);
        for p in (0..32 * 32).filter(|p| inside(*p)) {
            for c in 0..4 {
                let d = img.data[p * 4 + c].abs_diff(want[p * 4 + c]);
                if d > worst.0 {
                    worst = (d, p);
                }
            }
        }
        assert!(
            worst.0 <= 6,
            "{kind}: off by {} at pixel {}: {:?}",
            worst.0,
            worst.1,
            &img.data[worst.1 * 4..worst.1 * 4 + 4]
        );
    }
}

#[test]
fn unsupported_kinds_are_refused_naming_the_file_and_the_kind() {
    let dir = scratch("refused");
    let lab = hand_tiff(
        false,
        W,
        H,
        &[(258, 3, vec![8; 3]), (262, 3, vec![8]), (277, 3, vec![3])],
        &vec![0; (W * H * 3) as usize],
    );
    let float = encode::<colortype::Gray32Float>(
        &vec![0.5f32; (W * H) as usize],
        Compression::Uncompressed,
        Predictor::None,
    );
    let jpeg2000 = hand_tiff(
        false,
        W,
        H,
        &[
            (258, 3, vec![8; 3]),
            (259, 3, vec![34712]),
            (262, 3, vec![2]),
            (277, 3, vec![3]),
        ],
        &[0xff, 0x4f, 0xff, 0x51, 1, 2, 3],
    );
    let mut truncated = colour_kinds().remove(1).1;
    truncated.truncate(truncated.len() / 3);
    let bad_map = hand_tiff(
        false,
        W,
        H,
        &[(258, 3, vec![4]), (262, 3, vec![3]), (320, 3, vec![0; 12])],
        &vec![0; (W * H) as usize],
    );
    for (name, bytes, kind) in [
        ("lab", lab, "CIE L*a*b* 8-bit (uncompressed)"),
        ("float", float, "grey floating-point 32-bit (uncompressed)"),
        ("jpeg2000", jpeg2000, "RGB 8-bit (JPEG 2000)"),
        ("palette_map", bad_map, "palette 4-bit (uncompressed)"),
        (
            "garbage",
            b"II*\0garbage".to_vec(),
            "a TIFF without a readable image directory",
        ),
        (
            "png",
            encode_png(&decode_tiff(&colour_kinds()[0].1).unwrap()),
            "not a TIFF",
        ),
        ("truncated", truncated, ""),
    ] {
        let err = load(&dir, name, &bytes).expect_err(name).to_string();
        let file = dir.join(format!("{name}.tif"));
        assert!(err.contains(&file.display().to_string()), "{name}: {err}");
        assert!(err.contains(kind), "{name}: {err}");
        assert!(err.contains(": not read ("), "{name}: {err}");
    }
}
