//! ROS map_server maps (YAML + image), read and written exactly as map_server and map_saver
//! (noetic) do.

use serde::{Deserialize, Deserializer, Serialize};
use std::path::{Path, PathBuf};
use xhab_types::{OccupancyGrid, Pose2, GRID_UNKNOWN};

/// How image values become occupancy (map_server's `mode`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MapMode {
    /// Occupied, free or unknown (default).
    #[default]
    Trinary,
    /// Occupied, free, or a cost in between.
    Scale,
    /// The image value itself.
    Raw,
}

/// The map's YAML, with map_server's keys and defaults; any other key is an error (a typo
/// such as `negat: 1` must not pass silently).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MapMetadata {
    /// Image file, relative to the YAML's folder unless absolute.
    pub image: PathBuf,
    /// Cell size (m).
    pub resolution: f64,
    /// Pose of the lower-left pixel: [x (m), y (m), yaw (rad)].
    pub origin: [f64; 3],
    /// Invert black and white (0/1 or false/true).
    #[serde(default, deserialize_with = "bool_or_int")]
    pub negate: bool,
    /// Occupancy above which a cell is occupied (default 0.65).
    #[serde(default = "default_occ")]
    pub occupied_thresh: f64,
    /// Occupancy below which a cell is free (default 0.196).
    #[serde(default = "default_free")]
    pub free_thresh: f64,
    /// Interpretation of values (default trinary).
    #[serde(default)]
    pub mode: MapMode,
}

fn default_occ() -> f64 {
    0.65
}
fn default_free() -> f64 {
    0.196
}

fn bool_or_int<'de, D: Deserializer<'de>>(d: D) -> Result<bool, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum B {
        B(bool),
        I(i64),
    }
    match B::deserialize(d)? {
        B::B(b) => Ok(b),
        B::I(0) => Ok(false),
        B::I(1) => Ok(true),
        B::I(v) => Err(serde::de::Error::custom(format!("expected 0 or 1, got {v}"))),
    }
}

/// Why a map could not be read or written; names the file and the field.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MapError {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// A YAML key is missing or has a bad value.
    #[error("{path}: {field}: {reason}")]
    Yaml {
        /// The YAML file.
        path: PathBuf,
        /// The key.
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// The image is unreadable, truncated or of an unsupported kind.
    #[error("{path}: {reason}")]
    Image {
        /// The image file.
        path: PathBuf,
        /// What is wrong.
        reason: String,
    },
}

/// Smallest cell size a map may have (m).
pub const MIN_RESOLUTION: f64 = 1e-4;
/// Largest cell size a map may have (m).
pub const MAX_RESOLUTION: f64 = 100.0;
/// Most cells (pixels) a map image may have.
pub const MAX_CELLS: usize = 400_000_000;

/// Reads a map_server map: the YAML at `yaml_path` and the image it names.
pub fn load_map(yaml_path: &Path) -> Result<(OccupancyGrid, MapMetadata), MapError> {
    let bytes = std::fs::read(yaml_path).map_err(|source| MapError::Io { path: yaml_path.to_path_buf(), source })?;
    let text = String::from_utf8(bytes).map_err(|e| MapError::Yaml {
        path: yaml_path.to_path_buf(),
        field: "(file)".into(),
        reason: format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
    })?;
    let meta = parse_map_yaml(&text, yaml_path)?;
    let image = meta.image_path(yaml_path);
    let bytes = std::fs::read(&image).map_err(|source| MapError::Io { path: image.clone(), source })?;
    let grid = decode_map_image(&bytes, &image, &meta)?;
    Ok((grid, meta))
}

impl MapMetadata {
    /// Where the image is: `image` as written when absolute, else relative to the YAML's folder.
    pub fn image_path(&self, yaml_path: &Path) -> PathBuf {
        if self.image.is_absolute() {
            self.image.clone()
        } else {
            yaml_path.parent().unwrap_or(Path::new(".")).join(&self.image)
        }
    }
}

/// Parses and checks a map's YAML text (keys, resolution, origin, thresholds); `yaml_path`
/// names the file in errors.
pub fn parse_map_yaml(text: &str, yaml_path: &Path) -> Result<MapMetadata, MapError> {
    let de = serde_yaml::Deserializer::from_str(text);
    let meta: MapMetadata = serde_path_to_error::deserialize(de).map_err(|e| MapError::Yaml {
        path: yaml_path.to_path_buf(),
        field: if e.path().to_string() == "." { "(top)".into() } else { e.path().to_string() },
        reason: e.inner().to_string(),
    })?;
    let bad = |field: &str, reason: String| MapError::Yaml { path: yaml_path.to_path_buf(), field: field.into(), reason };
    if !(meta.resolution.is_finite() && meta.resolution > 0.0) {
        return Err(bad("resolution", format!("must be a positive number, got {}", meta.resolution)));
    }
    // Cells from 0.1 mm to 100 m: outside that no map is meant, and cell arithmetic
    // (distances over the resolution) would overflow or lose all precision.
    if !(MIN_RESOLUTION..=MAX_RESOLUTION).contains(&meta.resolution) {
        return Err(bad("resolution", format!("must be between {MIN_RESOLUTION} and {MAX_RESOLUTION} m per cell, got {}", meta.resolution)));
    }
    if meta.origin.iter().any(|v| !v.is_finite()) {
        return Err(bad("origin", "must be three finite numbers".into()));
    }
    if !(0.0..=1.0).contains(&meta.occupied_thresh) || !(0.0..=1.0).contains(&meta.free_thresh) || meta.free_thresh >= meta.occupied_thresh {
        return Err(bad("free_thresh", format!("thresholds must satisfy 0 <= free_thresh ({}) < occupied_thresh ({}) <= 1", meta.free_thresh, meta.occupied_thresh)));
    }
    Ok(meta)
}

/// Decodes a map image's bytes (PGM P5/P2, or PNG) into the occupancy grid `meta` describes,
/// as map_server does; `image_path` names the image in errors.
pub fn decode_map_image(bytes: &[u8], image_path: &Path, meta: &MapMetadata) -> Result<OccupancyGrid, MapError> {
    let img = read_image(bytes, image_path)?;
    Ok(to_grid(&img, meta))
}

/// A decoded image: rows top first, `channels` bytes per pixel (alpha last when present).
struct Pixels {
    w: usize,
    h: usize,
    channels: usize,
    has_alpha: bool,
    data: Vec<u8>,
}

fn read_image(bytes: &[u8], path: &Path) -> Result<Pixels, MapError> {
    let bad = |reason: String| MapError::Image { path: path.to_path_buf(), reason };
    if bytes.starts_with(b"P5") || bytes.starts_with(b"P2") {
        return read_pgm(bytes).map_err(bad);
    }
    let start = String::from_utf8_lossy(&bytes[..bytes.len().min(4)]).escape_debug().to_string();
    if bytes.len() >= 2 && bytes[0] == b'P' && bytes[1].is_ascii_digit() {
        return Err(bad(format!("byte 0: magic \"{start}\" is a netpbm image other than PGM; map images are PGM (P5 or P2) or PNG")));
    }
    let reader = image::ImageReader::new(std::io::Cursor::new(bytes)).with_guessed_format().map_err(|e| bad(format!("cannot read the image: {e}")))?;
    if reader.format().is_none() {
        return Err(bad(format!("byte 0: not a PGM (magic P5 or P2) or PNG image (it starts with \"{start}\")")));
    }
    let img = reader.decode().map_err(|e| bad(format!("cannot decode the image: {e}")))?;
    let has_alpha = img.color().has_alpha();
    let (w, h) = (img.width() as usize, img.height() as usize);
    if w == 0 || h == 0 || w.saturating_mul(h) > MAX_CELLS {
        return Err(bad(format!("{w} x {h} pixels is empty or larger than {MAX_CELLS}")));
    }
    // As SDL_image hands map_server the pixels: grey as one channel, colour as three, and
    // anything with alpha as four (grey + alpha turned into RGBA).
    let (channels, data) = if has_alpha {
        (4, img.to_rgba8().into_raw())
    } else if img.color().channel_count() == 1 {
        (1, img.to_luma8().into_raw())
    } else {
        (3, img.to_rgb8().into_raw())
    };
    Ok(Pixels { w, h, channels, has_alpha, data })
}

/// Binary (P5, 8 or 16 bit) and ASCII (P2) PGM; errors name the header field or the byte
/// offset where the file goes wrong.
fn read_pgm(b: &[u8]) -> Result<Pixels, String> {
    const FIELDS: [&str; 3] = ["width", "height", "maxval"];
    let mut pos = 2;
    let mut header = Vec::new();
    while header.len() < 3 {
        while pos < b.len() && b[pos].is_ascii_whitespace() {
            pos += 1;
        }
        if pos < b.len() && b[pos] == b'#' {
            while pos < b.len() && b[pos] != b'\n' {
                pos += 1;
            }
            continue;
        }
        let field = FIELDS[header.len()];
        let start = pos;
        while pos < b.len() && b[pos].is_ascii_digit() {
            pos += 1;
        }
        if start == pos {
            let found = if pos < b.len() { format!("{:?}", b[pos] as char) } else { "the end of the file".into() };
            return Err(format!("broken PGM header: byte {pos}: expected the {field} (a number), found {found}"));
        }
        let v: usize = std::str::from_utf8(&b[start..pos])
            .ok()
            .and_then(|s| s.parse().ok())
            .ok_or_else(|| format!("broken PGM header: byte {start}: the {field} is too large"))?;
        header.push(v);
    }
    let (w, h, maxval) = (header[0], header[1], header[2]);
    if maxval == 0 || maxval > 65535 {
        return Err(format!("PGM header: maxval {maxval} must be between 1 and 65535"));
    }
    if w == 0 || h == 0 || w.saturating_mul(h) > MAX_CELLS {
        return Err(format!("PGM header: width {w} x height {h} pixels is empty or larger than {MAX_CELLS}"));
    }
    let scale = |v: usize| ((v * 255 + maxval / 2) / maxval).min(255) as u8;
    let data = if b.starts_with(b"P5") {
        pos += 1; // the single whitespace after maxval
        let bps = if maxval > 255 { 2 } else { 1 };
        let need = w * h * bps;
        if b.len() < pos + need {
            return Err(format!(
                "truncated PGM: the pixel data from byte {pos} should hold {need} bytes for {w} x {h} pixels, the file ends at byte {}",
                b.len()
            ));
        }
        let px = &b[pos..pos + need];
        if bps == 2 {
            px.chunks_exact(2).map(|c| scale((c[0] as usize) << 8 | c[1] as usize)).collect()
        } else if maxval == 255 {
            px.to_vec()
        } else {
            px.iter().map(|&v| scale(v as usize)).collect()
        }
    } else {
        let text = std::str::from_utf8(&b[pos..]).map_err(|e| format!("ASCII PGM: byte {}: pixel data that is not text", pos + e.valid_up_to()))?;
        let mut data = Vec::with_capacity((w * h).min(text.len() / 2 + 1));
        let mut at = pos;
        for tok in text.split_ascii_whitespace() {
            if data.len() == w * h {
                break;
            }
            // The token's byte offset in the file (tokens are slices of `text`).
            at = pos + (tok.as_ptr() as usize - text.as_ptr() as usize);
            let v: usize = tok.parse().map_err(|_| format!("ASCII PGM: byte {at}: bad pixel value '{tok}'"))?;
            data.push(if maxval == 255 { v.min(255) as u8 } else { scale(v.min(maxval)) });
        }
        if data.len() < w * h {
            return Err(format!("truncated PGM: {} of {} pixel values (the last at byte {at}) for {w} x {h} pixels", data.len(), w * h));
        }
        data
    };
    Ok(Pixels { w, h, channels: 1, has_alpha: false, data })
}

/// map_server's conversion (image_loader.cpp, noetic): image row j is grid row h-1-j. The
/// channels are averaged, alpha included in trinary mode only (as map_server does "to preserve
/// existing behavior"); `negate` inverts the average before any mode, raw included; in scale
/// mode a pixel whose last byte is 0 is unknown. (A palette PNG is read as its colours, not as
/// SDL's palette indices.)
fn to_grid(img: &Pixels, m: &MapMetadata) -> OccupancyGrid {
    let origin = Pose2::new(m.origin[0], m.origin[1], m.origin[2]);
    let mut g = OccupancyGrid::new(img.w, img.h, m.resolution, origin, GRID_UNKNOWN);
    let avg_channels = if img.has_alpha && m.mode != MapMode::Trinary { img.channels - 1 } else { img.channels };
    for j in 0..img.h {
        for i in 0..img.w {
            let p = &img.data[(j * img.w + i) * img.channels..(j * img.w + i + 1) * img.channels];
            let sum: f64 = p[..avg_channels].iter().map(|&v| v as f64).sum();
            let mut avg = sum / avg_channels as f64;
            // map_server reads "alpha" from the last byte of any pixel of more than one channel:
            // for RGB that is blue, so a pixel with no blue is unknown in scale mode there too.
            let alpha = if img.channels > 1 { p[img.channels - 1] as f64 } else { 255.0 };
            if m.negate {
                avg = 255.0 - avg;
            }
            let value: i8 = if m.mode == MapMode::Raw {
                // map_server stores the average through an unsigned char into int8 data.
                avg as u8 as i8
            } else {
                let occ = (255.0 - avg) / 255.0;
                if occ > m.occupied_thresh {
                    100
                } else if occ < m.free_thresh {
                    0
                } else if m.mode == MapMode::Trinary || alpha < 1.0 {
                    -1
                } else {
                    let ratio = (occ - m.free_thresh) / (m.occupied_thresh - m.free_thresh);
                    (1.0 + 98.0 * ratio) as i8
                }
            };
            g.set(i, img.h - 1 - j, value);
        }
    }
    g
}

/// Writes `grid` as map_saver does: `NAME.pgm` (P5: 254 free, 0 occupied, 205 unknown; top
/// row first) beside `yaml_path`, and the YAML naming it.
pub fn save_map(grid: &OccupancyGrid, yaml_path: &Path) -> Result<(), MapError> {
    let pgm_path = yaml_path.with_extension("pgm");
    let name = pgm_path.file_name().map(|n| n.to_string_lossy().to_string()).unwrap_or_default();
    let mut out = format!("P5\n# CREATOR: xhab {:.3} m/pix\n{} {}\n255\n", grid.resolution, grid.width, grid.height).into_bytes();
    for row in (0..grid.height).rev() {
        for col in 0..grid.width {
            let v = grid.get(col, row);
            out.push(if (0..=25).contains(&v) {
                254
            } else if v >= 65 {
                0
            } else {
                205
            });
        }
    }
    std::fs::write(&pgm_path, out).map_err(|source| MapError::Io { path: pgm_path.clone(), source })?;
    let yaml = format!(
        "image: {name}\nresolution: {}\norigin: [{}, {}, {}]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\nmode: trinary\n",
        grid.resolution, grid.origin.x, grid.origin.y, grid.origin.yaw
    );
    std::fs::write(yaml_path, yaml).map_err(|source| MapError::Io { path: yaml_path.to_path_buf(), source })
}

#[cfg(test)]
#[path = "../../../tests/support/data.rs"]
mod test_data;

#[cfg(test)]
mod tests {
    use super::*;
    use super::test_data;

    fn dir() -> PathBuf {
        let d = std::env::temp_dir().join(format!("xhab-map-{}-{:?}", std::process::id(), std::thread::current().id()));
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn write(d: &Path, name: &str, yaml_extra: &str, pgm: &[u8]) -> PathBuf {
        std::fs::write(d.join(format!("{name}.pgm")), pgm).unwrap();
        let y = d.join(format!("{name}.yaml"));
        std::fs::write(&y, format!("image: {name}.pgm\nresolution: 0.1\norigin: [1.0, 2.0, 0.0]\n{yaml_extra}")).unwrap();
        y
    }

    #[test]
    fn trinary_scale_raw_negate_and_row_flip() {
        let d = dir();
        // 3 x 2: top row 0 (black), 255 (white), 205 (grey); bottom row 100, 240, 10.
        let mut pgm = b"P5\n# c\n3 2\n255\n".to_vec();
        pgm.extend_from_slice(&[0, 255, 205, 100, 240, 10]);
        let y = write(&d, "t", "", &pgm);
        let (g, _) = load_map(&y).unwrap();
        // Bottom grid row is the image's bottom row.
        assert_eq!(g.data, vec![-1, 0, 100, 100, 0, -1]);
        let y = write(&d, "n", "negate: 1\n", &pgm);
        let (g, _) = load_map(&y).unwrap();
        // negate: occ = v/255: 100 -> 0.39 unknown, 240 -> occupied, 10 -> free; 0 -> free, 255 -> occupied, 205 -> occupied.
        assert_eq!(g.data, vec![-1, 100, 0, 0, 100, 100]);
        let y = write(&d, "s", "mode: scale\n", &pgm);
        let (g, _) = load_map(&y).unwrap();
        // 100: occ = 0.6078 -> 1 + 98 * (0.6078 - 0.196) / (0.65 - 0.196) = 89.9 -> 89.
        assert_eq!(g.get(0, 0), 89);
        let y = write(&d, "r", "mode: raw\n", &pgm);
        let (g, _) = load_map(&y).unwrap();
        assert_eq!(g.get(0, 1), 0);
        assert_eq!(g.get(1, 0), 240u8 as i8);
    }

    #[test]
    fn ascii_equals_binary_and_round_trip() {
        let d = dir();
        let mut p5 = b"P5\n3 2\n255\n".to_vec();
        p5.extend_from_slice(&[0, 255, 205, 100, 240, 10]);
        let p2 = b"P2\n3 2\n255\n0 255 205\n100 240 10\n".to_vec();
        let (a, _) = load_map(&write(&d, "a", "", &p5)).unwrap();
        let (b, _) = load_map(&write(&d, "b", "", &p2)).unwrap();
        assert_eq!(a, b);
        let mut g = OccupancyGrid::new(7, 5, 0.05, Pose2::new(-1.5, 2.25, 0.0), -1);
        for (i, v) in g.data.iter_mut().enumerate() {
            *v = [0, 100, -1][(i * 7 + i / 3) % 3];
        }
        let y = d.join("rt.yaml");
        save_map(&g, &y).unwrap();
        let (back, meta) = load_map(&y).unwrap();
        assert_eq!(back, g);
        assert_eq!(meta.image, PathBuf::from("rt.pgm"));
    }

    #[test]
    fn bad_files_name_the_problem() {
        let d = dir();
        let mut pgm = b"P5\n3 2\n255\n".to_vec();
        pgm.extend_from_slice(&[0, 255]);
        let e = load_map(&write(&d, "trunc", "", &pgm)).unwrap_err().to_string();
        assert!(e.contains("trunc.pgm") && e.contains("truncated"), "{e}");
        let y = d.join("typo.yaml");
        std::fs::write(&y, "image: x.pgm\nresolution: abc\norigin: [0, 0, 0]\n").unwrap();
        let e = load_map(&y).unwrap_err().to_string();
        assert!(e.contains("typo.yaml") && e.contains("resolution"), "{e}");
        for (text, key) in [("image: x.pgm\nresolution: 1e-50\norigin: [0, 0, 0]\n", "resolution"), ("image: x.pgm\nresolution: 0.05\norigin: [0, 0, 0]\nnegat: 1\n", "negat")] {
            std::fs::write(&y, text).unwrap();
            let e = load_map(&y).unwrap_err().to_string();
            assert!(e.contains("typo.yaml") && e.contains(key), "{e}");
        }
        std::fs::write(&y, "image: missing.pgm\nresolution: 0.05\norigin: [0, 0, 0]\n").unwrap();
        assert!(load_map(&y).unwrap_err().to_string().contains("missing.pgm"));
    }

    #[test]
    fn shared_maps_load() {
        let Some(root) = test_data::data_dir("shared_maps_load") else { return };
        let dir = root.join("maps");
        let mut n = 0;
        for e in std::fs::read_dir(&dir).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "yaml") {
                let (g, _) = load_map(&p).unwrap_or_else(|e| panic!("{e}"));
                let occ = g.data.iter().filter(|&&v| v == 100).count();
                let free = g.data.iter().filter(|&&v| v == 0).count();
                eprintln!("{}: {}x{} free {free} occupied {occ}", p.display(), g.width, g.height);
                assert!(occ > 0 && free > 0);
                n += 1;
            }
        }
        assert!(n >= 9, "{n} maps");
    }
}
