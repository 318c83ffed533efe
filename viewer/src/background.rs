//! The map's background image: pMarineViewer's `tiff_file = NAME.tif` with its `NAME.info`
//! (the image's lat/lon bounds), decoded here and handed to the page as a PNG from memory,
//! placed in local metres on the mission's LatOrigin/LongOrigin grid.
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

/// Decodes a TIFF (8- or 16-bit grey, grey+alpha, RGB or RGBA; uncompressed, LZW or
/// deflate; the first image of the file) to RGBA.
pub fn decode_tiff(bytes: &[u8]) -> Result<Rgba, BackgroundError> {
    use tiff::ColorType;
    use tiff::decoder::{Decoder, DecodingResult};
    let err = |e: tiff::TiffError| BackgroundError::Decode(e.to_string());
    let mut d = Decoder::new(std::io::Cursor::new(bytes)).map_err(err)?;
    let (width, height) = d.dimensions().map_err(err)?;
    let color = d.colortype().map_err(err)?;
    let samples: Vec<u8> = match d.read_image().map_err(err)? {
        DecodingResult::U8(v) => v,
        DecodingResult::U16(v) => v.into_iter().map(|x| (x >> 8) as u8).collect(),
        _ => {
            return Err(BackgroundError::Decode(
                "only 8- and 16-bit samples are read".into(),
            ));
        }
    };
    let channels = match color {
        ColorType::Gray(8 | 16) => 1,
        ColorType::GrayA(8 | 16) => 2,
        ColorType::RGB(8 | 16) => 3,
        ColorType::RGBA(8 | 16) => 4,
        other => {
            return Err(BackgroundError::Decode(format!(
                "colour type {other:?} is not read (grey, grey+alpha, RGB or RGBA)"
            )));
        }
    };
    let pixels = width as usize * height as usize;
    if samples.len() < pixels * channels {
        return Err(BackgroundError::Decode("fewer samples than pixels".into()));
    }
    let mut data = Vec::with_capacity(pixels * 4);
    for p in samples.chunks_exact(channels).take(pixels) {
        let px = match channels {
            1 => [p[0], p[0], p[0], 255],
            2 => [p[0], p[0], p[0], p[1]],
            3 => [p[0], p[1], p[2], 255],
            _ => [p[0], p[1], p[2], p[3]],
        };
        data.extend_from_slice(&px);
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
        let img = decode_tiff(&read(tif)?)?;
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
