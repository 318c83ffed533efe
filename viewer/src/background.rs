//! The map's background image: pMarineViewer's `tiff_file = NAME.tif` with its `NAME.info`
//! (the image's lat/lon bounds), decoded here and handed to the page as a PNG from memory,
//! placed in local metres on the mission's LatOrigin/LongOrigin grid.
//!
//! pMarineViewer reads the image with libtiff's RGBA interface, so any kind libtiff knows
//! shows. [`decode_tiff`] reads the kinds backgrounds come in (the list is in its docs):
//! MOOS-IvP's own `AerialMIT.tif` (also `Default.tif`) is 8-bit RGBA with premultiplied
//! alpha, deflate-compressed with a horizontal predictor; `forrest19.tif` (the version in
//! the history that can be read) is 8-bit RGB compressed as JPEG. Palettes are read through
//! their `ColorMap` here, the `tiff` crate doing the rest; a kind it cannot read is an error
//! naming the file and the kind ([`describe_tiff`]).
//!
//! The `.info` file, as pMarineViewer's BackImg reads it (lib_marineview/BackImg.cpp,
//! `readTiffInfo`, `processConfiguration`): one `key = value` per line, `//` comments,
//! blank lines skipped, a line with other than one `=`, an unknown key or a value that is
//! not a number makes the file unusable. Two forms:
//! - bounds: `lat_north`, `lat_south`, `lon_west`, `lon_east` (all four; north above south,
//!   east of west), optionally `datum_lat`/`datum_lon` (the first of each counts);
//! - the older form: `img_centx`, `img_centy` (where the datum lies, as fractions of the
//!   image's width and height from its left and bottom edges) and `img_meters` (per cent of
//!   the image per metre: the image is `100 / img_meters` metres a side).
//!
//! Placement: with bounds, the north-west corner projected on the mission's grid gives the
//! image's left and top edges and the south-east corner its right and bottom (the image is
//! drawn as that axis-aligned box, as pMarineViewer draws it); without a mission origin the
//! grid is the `.info`'s datum, else the image's centre (pMarineViewer's own choice). In the
//! older form the datum is taken to be the mission's origin.
//!
//! The file is looked for as pMarineViewer does, with the mission's folder first: the name
//! as given (absolute, or relative to the mission's folder), then in each folder of
//! `IVP_IMAGE_DIRS` (colon-separated), then in the current folder. `.tif` and `.tiff` both
//! map to `.info`.

use std::path::{Path, PathBuf};

/// Why a background cannot be shown.
#[derive(Debug, Clone, PartialEq)]
pub enum BackgroundError {
    /// The image or its `.info` was not found (the places looked in).
    NotFound(String),
    /// The file name ends neither in `.tif` nor `.tiff`.
    NotTiff(String),
    /// The `.info` file is unusable: the line (1-based, 0 for the whole file) and why.
    Info(usize, String),
    /// The TIFF cannot be decoded.
    Decode(String),
    /// The geodesy failed (an origin out of range).
    Geodesy(String),
}

impl std::fmt::Display for BackgroundError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BackgroundError::NotFound(s) => write!(f, "background image not found: {s}"),
            BackgroundError::NotTiff(s) => write!(f, "{s}: expected a .tif or .tiff file"),
            BackgroundError::Info(0, s) => write!(f, "background .info: {s}"),
            BackgroundError::Info(l, s) => write!(f, "background .info line {l}: {s}"),
            BackgroundError::Decode(s) => write!(f, "background image: {s}"),
            BackgroundError::Geodesy(s) => write!(f, "background placement: {s}"),
        }
    }
}

impl std::error::Error for BackgroundError {}

/// What an `.info` file says.
#[derive(Debug, Clone, PartialEq)]
pub enum Info {
    /// The image's lat/lon bounds (degrees), and the datum if given.
    Bounds {
        /// Northern edge.
        lat_north: f64,
        /// Southern edge.
        lat_south: f64,
        /// Western edge.
        lon_west: f64,
        /// Eastern edge.
        lon_east: f64,
        /// `datum_lat`/`datum_lon`, when both are given.
        datum: Option<(f64, f64)>,
    },
    /// The older form: the datum's place in the image (fractions) and per cent per metre.
    Centre {
        /// `img_centx`.
        centx: f64,
        /// `img_centy`.
        centy: f64,
        /// `img_meters`.
        meters: f64,
    },
}

/// Reads an `.info` file's text.
pub fn parse_info(text: &str) -> Result<Info, BackgroundError> {
    let mut v: [Option<f64>; 9] = [None; 9];
    const KEYS: [&str; 9] = [
        "img_centx",
        "img_centy",
        "img_meters",
        "lat_north",
        "lat_south",
        "lon_west",
        "lon_east",
        "datum_lat",
        "datum_lon",
    ];
    for (i, raw) in text.lines().enumerate() {
        let line = raw.split("//").next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let bad = |why: String| BackgroundError::Info(i + 1, why);
        let parts: Vec<&str> = line.split('=').collect();
        if parts.len() != 2 {
            return Err(bad(format!("{line:?}: expected key = value")));
        }
        let (key, value) = (parts[0].trim(), parts[1].trim());
        let k = KEYS
            .iter()
            .position(|k| *k == key)
            .ok_or_else(|| bad(format!("unknown key {key:?}")))?;
        let n = value
            .parse::<f64>()
            .ok()
            .filter(|n| n.is_finite() && moos_types::text::is_number(value))
            .ok_or_else(|| bad(format!("{key}: {value:?} is not a number")))?;
        // The datum: the first one given counts, as in pMarineViewer.
        if k < 7 || v[k].is_none() {
            v[k] = Some(n);
        }
    }
    if let [_, _, _, Some(n), Some(s), Some(w), Some(e), dlat, dlon] = v {
        if n <= s || e <= w {
            return Err(BackgroundError::Info(
                0,
                format!(
                    "lat_north {n} must be above lat_south {s}, lon_east {e} east of lon_west {w}"
                ),
            ));
        }
        return Ok(Info::Bounds {
            lat_north: n,
            lat_south: s,
            lon_west: w,
            lon_east: e,
            datum: dlat.zip(dlon),
        });
    }
    if let [Some(centx), Some(centy), Some(meters), ..] = v {
        if meters <= 0.0 {
            return Err(BackgroundError::Info(
                0,
                "img_meters must be positive".into(),
            ));
        }
        return Ok(Info::Centre {
            centx,
            centy,
            meters,
        });
    }
    Err(BackgroundError::Info(
        0,
        "needs lat_north, lat_south, lon_west and lon_east (or img_centx, img_centy and img_meters)"
            .into(),
    ))
}

/// Where the image lies in local metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// x of the left edge.
    pub left: f64,
    /// x of the right edge.
    pub right: f64,
    /// y of the bottom edge.
    pub bottom: f64,
    /// y of the top edge.
    pub top: f64,
}

impl Info {
    /// The image's box on the grid of `origin` (LatOrigin, LongOrigin); see the module
    /// docs for the fallbacks without one.
    pub fn place(&self, origin: Option<(f64, f64)>) -> Result<Placement, BackgroundError> {
        match *self {
            Info::Bounds {
                lat_north,
                lat_south,
                lon_west,
                lon_east,
                datum,
            } => {
                let (lat0, lon0) = origin
                    .or(datum)
                    .unwrap_or(((lat_north + lat_south) / 2.0, (lon_west + lon_east) / 2.0));
                let grid = vehicle::geodesy::LocalGrid::new(lat0, lon0)
                    .map_err(|e| BackgroundError::Geodesy(e.to_string()))?;
                let geo =
                    |e: vehicle::geodesy::GeodesyError| BackgroundError::Geodesy(e.to_string());
                let (left, top) = grid.to_local(lat_north, lon_west).map_err(geo)?;
                let (right, bottom) = grid.to_local(lat_south, lon_east).map_err(geo)?;
                Ok(Placement {
                    left,
                    right,
                    bottom,
                    top,
                })
            }
            Info::Centre {
                centx,
                centy,
                meters,
            } => {
                let size = 100.0 / meters;
                Ok(Placement {
                    left: -centx * size,
                    right: (1.0 - centx) * size,
                    bottom: -centy * size,
                    top: (1.0 - centy) * size,
                })
            }
        }
    }
}

/// An RGBA image, rows top first.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Rgba {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// 4 bytes a pixel.
    pub data: Vec<u8>,
}

/// Decodes the first image of a TIFF to RGBA, as pMarineViewer's libtiff reads any kind:
///
/// - grey (`BlackIsZero` or `WhiteIsZero`) of 1, 2, 4, 8 or 16 bits, with or without alpha;
/// - palette (colour-mapped) of 1, 2, 4, 8 or 16 bits through its `ColorMap`;
/// - RGB and RGBA of 8 or 16 bits (premultiplied alpha un-multiplied), chunky or planar;
/// - CMYK (separated, 4 inks) of 8 or 16 bits, with or without alpha;
/// - YCbCr of 8 bits (as JPEG-compressed TIFFs usually are);
///
/// uncompressed, PackBits, LZW, deflate or JPEG; 16-bit samples keep their high byte.
/// Anything else (CIE L*a*b*, floating-point or signed samples, other compressions) is a
/// [`BackgroundError::Decode`] naming the kind ([`describe_tiff`]), never a panic.
pub fn decode_tiff(bytes: &[u8]) -> Result<Rgba, BackgroundError> {
    let kind = describe_tiff(bytes);
    let refuse = |why: String| BackgroundError::Decode(format!("{kind}: not read ({why})"));
    // A third-party decoder on a user's file: a panic in it is an error here too.
    let decoded =
        std::panic::catch_unwind(|| match first_ifd(bytes).and_then(|ifd| ifd.photometric) {
            Some(entry) if entry.value == 3 => decode_palette(bytes, entry),
            _ => decode_direct(bytes),
        });
    match decoded {
        Ok(Ok(img)) => Ok(img),
        Ok(Err(why)) => Err(refuse(why)),
        Err(_) => Err(refuse("the decoder failed".into())),
    }
}

/// The kind of image a TIFF holds, for messages: photometric interpretation, bits per
/// sample, samples per pixel and compression, e.g. `palette 4-bit (uncompressed)` or
/// `CIE L*a*b* 8-bit, 3 samples (LZW)`; `not a TIFF` when the header is not one, `a TIFF
/// without a readable image directory` when its first directory lies outside the file.
pub fn describe_tiff(bytes: &[u8]) -> String {
    let Some(ifd) = first_ifd(bytes) else {
        let tiff = matches!(
            bytes.get(0..4),
            Some(b"II*\0" | b"MM\0*" | b"II+\0" | b"MM\0+")
        );
        return if tiff {
            "a TIFF without a readable image directory".into()
        } else {
            "not a TIFF".into()
        };
    };
    let photometric = match ifd.photometric.map(|e| e.value) {
        Some(0) => "grey (white is zero)".to_string(),
        Some(1) => "grey".into(),
        Some(2) => "RGB".into(),
        Some(3) => "palette".into(),
        Some(4) => "transparency mask".into(),
        Some(5) => "CMYK (separated)".into(),
        Some(6) => "YCbCr".into(),
        Some(8) => "CIE L*a*b*".into(),
        Some(9) => "ICC L*a*b*".into(),
        Some(10) => "ITU L*a*b*".into(),
        Some(32844) => "LogL".into(),
        Some(32845) => "LogLuv".into(),
        Some(p) => format!("photometric {p}"),
        None => "photometric missing".into(),
    };
    let format = match ifd.sample_format {
        2 => " signed",
        3 => " floating-point",
        _ => "",
    };
    let samples = match (ifd.photometric.map(|e| e.value), ifd.samples) {
        (Some(0 | 1 | 3 | 4), 1) | (Some(2 | 6 | 8 | 9 | 10), 3) | (Some(5), 4) => String::new(),
        (_, n) => format!(", {n} samples"),
    };
    let compression = match ifd.compression {
        1 => "uncompressed".to_string(),
        2 => "CCITT RLE".into(),
        3 => "CCITT fax 3".into(),
        4 => "CCITT fax 4".into(),
        5 => "LZW".into(),
        6 => "old-style JPEG".into(),
        7 => "JPEG".into(),
        8 | 32946 => "deflate".into(),
        32773 => "PackBits".into(),
        34712 => "JPEG 2000".into(),
        34887 => "LERC".into(),
        50000 => "zstd".into(),
        50001 => "WebP".into(),
        c => format!("compression {c}"),
    };
    format!(
        "{photometric}{format} {}-bit{samples} ({compression})",
        ifd.bits
    )
}

/// The first image's tags the decoder looks at, read from the file's first IFD (classic
/// or BigTIFF, either byte order) without decoding anything.
struct Ifd {
    little_endian: bool,
    photometric: Option<Entry>,
    bits: u16,
    samples: u16,
    compression: u16,
    sample_format: u16,
}

/// Where an inline SHORT or LONG tag value lies, and what it is.
#[derive(Clone, Copy)]
struct Entry {
    /// Byte offset of the value in the file.
    at: usize,
    /// The value's field type (3 SHORT, 4 LONG).
    ty: u16,
    value: u32,
}

fn first_ifd(b: &[u8]) -> Option<Ifd> {
    let little_endian = match b.get(0..2)? {
        b"II" => true,
        b"MM" => false,
        _ => return None,
    };
    let int = |at: usize, n: usize| -> Option<u64> {
        let bytes = b.get(at..at.checked_add(n)?)?;
        let fold = |acc: u64, x: &u8| (acc << 8) | u64::from(*x);
        Some(if little_endian {
            bytes.iter().rev().fold(0, fold)
        } else {
            bytes.iter().fold(0, fold)
        })
    };
    // Classic: 2-byte entry count, 12-byte entries, 4-byte values; BigTIFF: 8, 20, 8.
    let (first, count_len, entry_len, value_len) = match int(2, 2)? {
        42 => (int(4, 4)?, 2, 12, 4),
        43 => (int(8, 8)?, 8, 20, 8),
        _ => return None,
    };
    let first = usize::try_from(first).ok()?;
    let count = int(first, count_len)?;
    let mut ifd = Ifd {
        little_endian,
        photometric: None,
        bits: 1,
        samples: 1,
        compression: 1,
        sample_format: 1,
    };
    for i in 0..count.min(4096) as usize {
        let e = first + count_len + i * entry_len;
        let (tag, ty) = (int(e, 2)?, int(e + 2, 2)? as u16);
        let n = int(e + 4, value_len)?;
        let size = match ty {
            3 => 2,
            4 => 4,
            _ => continue,
        };
        // The first value: inline when they all fit, else at the offset given.
        let at = if n * size <= value_len as u64 {
            e + 4 + value_len
        } else {
            usize::try_from(int(e + 4 + value_len, value_len)?).ok()?
        };
        let Some(value) = int(at, size as usize) else {
            continue;
        };
        let value = value as u32;
        match tag {
            258 => ifd.bits = value as u16,
            259 => ifd.compression = value as u16,
            262 => ifd.photometric = Some(Entry { at, ty, value }),
            277 => ifd.samples = value as u16,
            339 => ifd.sample_format = value as u16,
            _ => {}
        }
    }
    Some(ifd)
}

/// The samples of the whole image (every plane of a planar one), as read.
fn read_samples(
    d: &mut tiff::decoder::Decoder<std::io::Cursor<&[u8]>>,
) -> Result<tiff::decoder::DecodingResult, String> {
    let mut buf = tiff::decoder::DecodingResult::U8(Vec::new());
    let layout = d
        .read_image_to_buffer(&mut buf)
        .map_err(|e| e.to_string())?;
    if buf.as_buffer(0).byte_len() < layout.complete_len {
        return Err("the image's planes do not fit the decoder's limits".into());
    }
    Ok(buf)
}

/// Samples as `u16` values of `bits` bits each, chunky order: sub-byte samples unpacked
/// (each row starts on a byte), planes interleaved.
fn unpack(
    raw: tiff::decoder::DecodingResult,
    bits: u8,
    width: usize,
    height: usize,
    channels: usize,
    planar: bool,
) -> Result<Vec<u16>, String> {
    use tiff::decoder::DecodingResult;
    let (per_row, rows) = if planar {
        (width, height * channels)
    } else {
        (width * channels, height)
    };
    let flat: Vec<u16> = match (raw, bits) {
        (DecodingResult::U8(v), 8) => v.into_iter().map(u16::from).collect(),
        (DecodingResult::U16(v), 16) => v,
        (DecodingResult::U8(v), 1 | 2 | 4) => {
            let row_bytes = (per_row * bits as usize).div_ceil(8);
            let mask = (1u16 << bits) - 1;
            let mut out = Vec::with_capacity(per_row * rows);
            for row in v.chunks(row_bytes.max(1)).take(rows) {
                for i in 0..per_row {
                    let bit = i * bits as usize;
                    let byte = u16::from(*row.get(bit / 8).unwrap_or(&0));
                    out.push((byte >> (8 - bits as usize - bit % 8)) & mask);
                }
            }
            out
        }
        (
            DecodingResult::U8(_)
            | DecodingResult::U16(_)
            | DecodingResult::U32(_)
            | DecodingResult::U64(_),
            b,
        ) => {
            return Err(format!("{b}-bit samples"));
        }
        _ => return Err("signed or floating-point samples".into()),
    };
    let pixels = width * height;
    if flat.len() < pixels * channels {
        return Err("fewer samples than pixels".into());
    }
    if !planar || channels == 1 {
        return Ok(flat);
    }
    let mut out = Vec::with_capacity(pixels * channels);
    for p in 0..pixels {
        out.extend((0..channels).map(|c| flat[c * pixels + p]));
    }
    Ok(out)
}

/// A sample of `bits` bits as 8 bits: the high byte of 16, scaled up from fewer.
fn to8(v: u16, bits: u8) -> u8 {
    match bits {
        16 => (v >> 8) as u8,
        8 => v as u8,
        b => (u32::from(v) * 255 / ((1u32 << b) - 1)) as u8,
    }
}

fn decode_direct(bytes: &[u8]) -> Result<Rgba, String> {
    use tiff::ColorType;
    use tiff::decoder::Decoder;
    use tiff::tags::Tag;
    let e = |e: tiff::TiffError| e.to_string();
    let mut d = Decoder::new(std::io::Cursor::new(bytes)).map_err(e)?;
    let (width, height) = d.dimensions().map_err(e)?;
    let color = d.colortype().map_err(e)?;
    let planar = d
        .find_tag_unsigned::<u16>(Tag::PlanarConfiguration)
        .map_err(e)?
        == Some(2);
    let extra = d
        .find_tag_unsigned_vec::<u16>(Tag::ExtraSamples)
        .map_err(e)?
        .unwrap_or_default();
    let premultiplied = extra.first() == Some(&1);
    let (bits, channels) = match color {
        ColorType::Gray(b) => (b, 1),
        ColorType::GrayA(b) => (b, 2),
        // Grey with extra samples: the first extra is alpha when marked so.
        ColorType::Multiband {
            bit_depth,
            num_samples,
        } => (bit_depth, usize::from(num_samples)),
        ColorType::RGB(b) | ColorType::YCbCr(b) => (b, 3),
        ColorType::RGBA(b) | ColorType::CMYK(b) => (b, 4),
        ColorType::CMYKA(b) => (b, 5),
        other => return Err(format!("colour type {other:?}")),
    };
    if matches!(color, ColorType::YCbCr(b) if b != 8) {
        return Err(format!("{bits}-bit YCbCr"));
    }
    let raw = read_samples(&mut d)?;
    let (w, h) = (width as usize, height as usize);
    let s = unpack(raw, bits, w, h, channels, planar)?;
    let c = |v: u16| to8(v, bits);
    let grey_alpha = matches!(color, ColorType::GrayA(_))
        || (matches!(color, ColorType::Multiband { .. }) && matches!(extra.first(), Some(1 | 2)));
    let mut data = Vec::with_capacity(w * h * 4);
    for p in s.chunks_exact(channels).take(w * h) {
        let px = match color {
            ColorType::Gray(_) => [c(p[0]), c(p[0]), c(p[0]), 255],
            ColorType::GrayA(_) | ColorType::Multiband { .. } => {
                let a = if grey_alpha && channels > 1 {
                    c(p[1])
                } else {
                    255
                };
                [c(p[0]), c(p[0]), c(p[0]), a]
            }
            ColorType::RGB(_) => [c(p[0]), c(p[1]), c(p[2]), 255],
            ColorType::RGBA(_) => [c(p[0]), c(p[1]), c(p[2]), c(p[3])],
            ColorType::CMYK(_) | ColorType::CMYKA(_) => {
                let k = 255 - u32::from(c(p[3]));
                let ink = |v: u16| ((255 - u32::from(c(v))) * k / 255) as u8;
                let a = if channels == 5 { c(p[4]) } else { 255 };
                [ink(p[0]), ink(p[1]), ink(p[2]), a]
            }
            // ColorType::YCbCr: 8 bits, full range (ITU-R BT.601, TIFF's defaults).
            _ => {
                let (y, cb, cr) = (
                    f64::from(p[0]),
                    f64::from(p[1]) - 128.0,
                    f64::from(p[2]) - 128.0,
                );
                let q = |v: f64| v.round().clamp(0.0, 255.0) as u8;
                [
                    q(y + 1.402 * cr),
                    q(y - 0.344136 * cb - 0.714136 * cr),
                    q(y + 1.772 * cb),
                    255,
                ]
            }
        };
        data.extend_from_slice(&px);
    }
    if premultiplied {
        for px in data.chunks_exact_mut(4) {
            let a = u32::from(px[3]);
            if a > 0 && a < 255 {
                for v in &mut px[..3] {
                    *v = (u32::from(*v) * 255 / a).min(255) as u8;
                }
            }
        }
    }
    Ok(Rgba {
        width,
        height,
        data,
    })
}

/// A palette image: the decoder reads the indices as grey once the copy's photometric
/// interpretation says so (the `tiff` crate refuses palettes), then each index is looked up
/// in the `ColorMap` (all reds, all greens, all blues; 16 bits each).
fn decode_palette(bytes: &[u8], photometric: Entry) -> Result<Rgba, String> {
    use tiff::ColorType;
    use tiff::decoder::Decoder;
    use tiff::tags::Tag;
    let e = |e: tiff::TiffError| e.to_string();
    let little_endian = first_ifd(bytes).is_some_and(|i| i.little_endian);
    let mut copy = bytes.to_vec();
    let one: &[u8] = match (photometric.ty, little_endian) {
        (3, true) => &[1, 0],
        (3, false) => &[0, 1],
        (_, true) => &[1, 0, 0, 0],
        (_, false) => &[0, 0, 0, 1],
    };
    copy.get_mut(photometric.at..photometric.at + one.len())
        .ok_or("photometric entry out of the file")?
        .copy_from_slice(one);
    let mut d = Decoder::new(std::io::Cursor::new(copy.as_slice())).map_err(e)?;
    let (width, height) = d.dimensions().map_err(e)?;
    let bits = match d.colortype().map_err(e)? {
        ColorType::Gray(b @ (1 | 2 | 4 | 8 | 16)) => b,
        ColorType::Gray(b) => return Err(format!("{b}-bit indices")),
        _ => return Err("more than one sample per pixel".into()),
    };
    let map = d
        .find_tag_unsigned_vec::<u16>(Tag::ColorMap)
        .map_err(e)?
        .ok_or("no ColorMap")?;
    let n = 1usize << bits;
    if map.len() != 3 * n {
        return Err(format!(
            "a ColorMap of {} values ({} expected)",
            map.len(),
            3 * n
        ));
    }
    let raw = read_samples(&mut d)?;
    let (w, h) = (width as usize, height as usize);
    let idx = unpack(raw, bits, w, h, 1, false)?;
    let mut data = Vec::with_capacity(w * h * 4);
    for &i in idx.iter().take(w * h) {
        let i = usize::from(i);
        data.extend_from_slice(&[
            (map[i] >> 8) as u8,
            (map[n + i] >> 8) as u8,
            (map[2 * n + i] >> 8) as u8,
            255,
        ]);
    }
    Ok(Rgba {
        width,
        height,
        data,
    })
}

/// Encodes an RGBA image as PNG.
pub fn encode_png(img: &Rgba) -> Vec<u8> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, img.width, img.height);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        // Writing to a Vec cannot fail, and the data's size is the header's.
        let mut w = enc.write_header().expect("PNG header into memory");
        w.write_image_data(&img.data).expect("PNG data into memory");
    }
    out
}

/// A background ready to serve: the PNG and where it lies.
#[derive(Debug, Clone, PartialEq)]
pub struct Background {
    /// The image file read.
    pub file: PathBuf,
    /// The image as PNG.
    pub png: Vec<u8>,
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// Where it lies, local metres.
    pub placement: Placement,
}

/// `NAME.tif`/`NAME.tiff` -> `NAME.info`.
pub fn info_path(tif: &Path) -> Option<PathBuf> {
    let ext = tif.extension()?.to_str()?.to_ascii_lowercase();
    matches!(ext.as_str(), "tif" | "tiff").then(|| tif.with_extension("info"))
}

/// Finds `name` and its `.info` (see the module docs for where).
pub fn locate(
    name: &str,
    mission_dir: Option<&Path>,
) -> Result<(PathBuf, PathBuf), BackgroundError> {
    let given = Path::new(name.trim());
    info_path(given).ok_or_else(|| BackgroundError::NotTiff(name.to_string()))?;
    let mut candidates = Vec::new();
    match mission_dir {
        Some(d) if given.is_relative() => candidates.push(d.join(given)),
        _ => candidates.push(given.to_path_buf()),
    }
    if given.is_relative() {
        if let Ok(dirs) = std::env::var("IVP_IMAGE_DIRS") {
            for d in dirs.split(':').filter(|d| !d.is_empty()) {
                candidates.push(Path::new(d).join(given));
            }
        }
        candidates.push(given.to_path_buf());
    }
    for c in &candidates {
        if let Some(info) = info_path(c)
            && c.is_file()
            && info.is_file()
        {
            return Ok((c.clone(), info));
        }
    }
    Err(BackgroundError::NotFound(format!(
        "{name} with its .info (looked in: {})",
        candidates
            .iter()
            .map(|c| c.display().to_string())
            .collect::<Vec<_>>()
            .join(", ")
    )))
}

impl Background {
    /// Reads the image and its `.info`, placed on the grid of `origin`.
    pub fn load(
        tif: &Path,
        info: &Path,
        origin: Option<(f64, f64)>,
    ) -> Result<Background, BackgroundError> {
        let read = |p: &Path| {
            std::fs::read(p).map_err(|e| BackgroundError::NotFound(format!("{}: {e}", p.display())))
        };
        let info_text = String::from_utf8_lossy(&read(info)?).into_owned();
        let placement = parse_info(&info_text)?.place(origin)?;
        let img = decode_tiff(&read(tif)?).map_err(|e| match e {
            BackgroundError::Decode(why) => {
                BackgroundError::Decode(format!("{}: {why}", tif.display()))
            }
            other => other,
        })?;
        Ok(Background {
            file: tif.to_path_buf(),
            png: encode_png(&img),
            width: img.width,
            height: img.height,
            placement,
        })
    }

    /// The mission's pMarineViewer `tiff_file` (the first one, `tiff_file_b` is not read),
    /// found and loaded; `None` when the mission names none.
    pub fn for_mission(
        m: &mission::moos::MissionFile,
        mission_dir: Option<&Path>,
    ) -> Option<Result<Background, BackgroundError>> {
        let block = m.process("pMarineViewer")?;
        let name = block
            .entries
            .iter()
            .find(|p| p.key.trim().eq_ignore_ascii_case("tiff_file"))?
            .value
            .trim()
            .to_string();
        if name.is_empty() {
            return None;
        }
        let origin = crate::server::mission_origin(m);
        Some(
            locate(&name, mission_dir)
                .and_then(|(tif, info)| Background::load(&tif, &info, origin)),
        )
    }

    /// The page's view: `{"url","width","height","left","right","bottom","top"}`.
    pub fn to_json(&self) -> serde_json::Value {
        let p = self.placement;
        serde_json::json!({
            "url": "/background.png",
            "width": self.width,
            "height": self.height,
            "left": p.left,
            "right": p.right,
            "bottom": p.bottom,
            "top": p.top,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn info_files_are_read_as_pmarineviewer_reads_them() {
        let i = parse_info(
            "// MIT sailing pavilion\n\nlat_north = 42.360264\nlat_south=42.35415\n  lon_east = -71.080058 // east\nlon_west = -71.094214\ndatum_lat = 42.358456\ndatum_lon = -71.087589\ndatum_lat = 1\n",
        )
        .unwrap();
        assert_eq!(
            i,
            Info::Bounds {
                lat_north: 42.360264,
                lat_south: 42.35415,
                lon_west: -71.094214,
                lon_east: -71.080058,
                datum: Some((42.358456, -71.087589)),
            }
        );
        let c = parse_info("img_centx = 0.25\nimg_centy = 0.5\nimg_meters = 0.5\n").unwrap();
        assert_eq!(
            c.place(None).unwrap(),
            Placement {
                left: -50.0,
                right: 150.0,
                bottom: -100.0,
                top: 100.0
            }
        );
        for (text, line) in [
            ("lat_north = 1 = 2\n", 1),
            ("\nzoom = 2\n", 2),
            ("lat_north = north\n", 1),
            (
                "lat_north = 1\nlat_south = 2\nlon_west = 0\nlon_east = 1\n",
                0,
            ),
            ("lat_north = 1\n", 0),
        ] {
            match parse_info(text) {
                Err(BackgroundError::Info(l, _)) => assert_eq!(l, line, "{text:?}"),
                other => panic!("{text:?}: {other:?}"),
            }
        }
    }

    #[test]
    fn tiff_names_map_to_info_names() {
        assert_eq!(
            info_path(Path::new("a/b.tif")),
            Some(PathBuf::from("a/b.info"))
        );
        assert_eq!(
            info_path(Path::new("b.TIFF")),
            Some(PathBuf::from("b.info"))
        );
        assert_eq!(info_path(Path::new("b.png")), None);
    }
}
