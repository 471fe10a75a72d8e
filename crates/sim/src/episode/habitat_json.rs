//! Habitat's PointNav dataset files: gzipped (or plain) JSON in Habitat's y-up frame,
//! converted to and from the world frame here and nowhere else.

use super::{Dataset, Episode, Goal};
use serde::{Deserialize, Serialize};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use xhab_types::{normalize_angle, Point3};

/// Why a dataset could not be read or written; names the file and the JSON field.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DatasetError {
    /// The file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// The JSON does not match Habitat's schema.
    #[error("{path}: {field}: {reason}")]
    Schema {
        /// The file.
        path: PathBuf,
        /// Dotted path of the field (e.g. `episodes[3].start_position`).
        field: String,
        /// What is wrong.
        reason: String,
    },
    /// A dataset that cannot be written as Habitat JSON (e.g. a non-finite position).
    #[error("episodes[{index}] ({episode_id}): {field}: {reason}")]
    Unwritable {
        /// Index of the episode.
        index: usize,
        /// Its id.
        episode_id: String,
        /// The field.
        field: String,
        /// What is wrong.
        reason: String,
    },
}

#[derive(Serialize, Deserialize)]
struct FileDataset {
    #[serde(default)]
    episodes: Vec<FileEpisode>,
}

#[derive(Serialize, Deserialize)]
#[serde(untagged)]
enum Id {
    Text(String),
    Number(serde_json::Number),
}

/// A PointNav goal has a position and a radius only (Habitat's `NavigationGoal`): any other key
/// is a typo, not an extension.
#[derive(Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileGoal {
    position: [f64; 3],
    #[serde(default = "default_radius")]
    radius: Option<f64>,
}

fn default_radius() -> Option<f64> {
    Some(0.2)
}

#[derive(Serialize, Deserialize)]
struct FileEpisode {
    episode_id: Id,
    scene_id: String,
    start_position: [f64; 3],
    start_rotation: [f64; 4],
    #[serde(default)]
    info: serde_json::Value,
    goals: Vec<FileGoal>,
}

/// Reads a PointNav dataset: gzipped or plain JSON (told by its first bytes), and, when the
/// top file lists no episodes and a `content/` folder stands beside it, every
/// `content/*.json.gz` in name order.
pub fn read_dataset(path: &Path) -> Result<Dataset, DatasetError> {
    let mut ds = read_one(path)?;
    if ds.episodes.is_empty() {
        let content = path.parent().unwrap_or(Path::new(".")).join("content");
        if content.is_dir() {
            let io = |source| DatasetError::Io { path: content.clone(), source };
            let mut files: Vec<PathBuf> = std::fs::read_dir(&content)
                .map_err(io)?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.to_string_lossy().ends_with(".json.gz") || p.to_string_lossy().ends_with(".json"))
                .collect();
            files.sort();
            for f in files {
                ds.episodes.extend(read_one(&f)?.episodes);
            }
        }
    }
    Ok(ds)
}

fn read_one(path: &Path) -> Result<Dataset, DatasetError> {
    let bytes = std::fs::read(path).map_err(|source| DatasetError::Io { path: path.to_path_buf(), source })?;
    parse_dataset(&bytes, path)
}

/// Parses one dataset file's bytes, gzipped or plain JSON (told by the first bytes), as
/// [`read_dataset`] reads each file; `path` names the file in errors (no `content/` folder is
/// looked for).
pub fn parse_dataset(bytes: &[u8], path: &Path) -> Result<Dataset, DatasetError> {
    let schema = |field: &str, reason: String| DatasetError::Schema { path: path.to_path_buf(), field: field.into(), reason };
    let text = if bytes.starts_with(&[0x1f, 0x8b]) {
        let mut json = Vec::new();
        let mut gz = flate2::bufread::GzDecoder::new(bytes);
        let read = gz.read_to_end(&mut json);
        // The decoder reads its input no further than it has decoded: where it stopped is
        // where the gzip stream went wrong.
        let at = bytes.len() - gz.into_inner().len();
        read.map_err(|e| schema("(gzip)", format!("cannot decompress: byte {at} of {}: {e}", bytes.len())))?;
        String::from_utf8(json).map_err(|e| schema("(file)", format!("the decompressed JSON is not UTF-8 text (byte {} of it)", e.utf8_error().valid_up_to())))?
    } else {
        String::from_utf8(bytes.to_vec()).map_err(|e| schema("(file)", format!("neither gzip nor UTF-8 JSON (byte {} is not UTF-8)", e.utf8_error().valid_up_to())))?
    };
    let de = &mut serde_json::Deserializer::from_str(&text);
    let file: FileDataset = serde_path_to_error::deserialize(de).map_err(|e| DatasetError::Schema {
        path: path.to_path_buf(),
        field: e.path().to_string(),
        reason: e.inner().to_string(),
    })?;
    let mut episodes = Vec::with_capacity(file.episodes.len());
    for (i, e) in file.episodes.into_iter().enumerate() {
        let bad = |field: &str, reason: &str| DatasetError::Schema {
            path: path.to_path_buf(),
            field: format!("episodes[{i}].{field}"),
            reason: reason.to_string(),
        };
        if e.start_position.iter().any(|v| !v.is_finite()) {
            return Err(bad("start_position", "not finite"));
        }
        let q = e.start_rotation;
        if q.iter().any(|v| !v.is_finite()) || q.iter().map(|v| v * v).sum::<f64>() < 1e-12 {
            return Err(bad("start_rotation", "not a finite, non-zero quaternion"));
        }
        if e.goals.is_empty() {
            return Err(bad("goals", "empty: an episode needs a goal"));
        }
        let mut goals = Vec::with_capacity(e.goals.len());
        for (k, g) in e.goals.iter().enumerate() {
            if g.position.iter().any(|v| !v.is_finite()) {
                return Err(bad(&format!("goals[{k}].position"), "not finite"));
            }
            let radius = g.radius.unwrap_or(0.2);
            if !(radius.is_finite() && radius > 0.0) {
                return Err(bad(&format!("goals[{k}].radius"), "must be a positive number"));
            }
            goals.push(Goal { position: Point3::from_habitat(g.position), radius });
        }
        let episode_id = match e.episode_id {
            Id::Text(s) => s,
            Id::Number(n) => n.to_string(),
        };
        let geodesic_distance = e.info.get("geodesic_distance").and_then(|v| v.as_f64());
        episodes.push(Episode {
            episode_id,
            scene_id: e.scene_id,
            start_position: Point3::from_habitat(e.start_position),
            start_yaw: yaw_from_quaternion(q),
            goals,
            geodesic_distance,
            info: e.info,
        });
    }
    Ok(Dataset { episodes })
}

/// World yaw (rad) of a Habitat rotation `[x, y, z, w]` about the up axis: facing Habitat's
/// -z (rotation angle 0) is world yaw pi/2. Tilt components are ignored.
pub fn yaw_from_quaternion(q: [f64; 4]) -> f64 {
    // Rotation angle about +y of the quaternion's yaw part.
    let theta = 2.0 * q[1].atan2(q[3]);
    normalize_angle(theta + std::f64::consts::FRAC_PI_2)
}

/// Habitat rotation `[x, y, z, w]` for a world yaw (rad): the inverse of [`yaw_from_quaternion`].
pub fn quaternion_from_yaw(yaw: f64) -> [f64; 4] {
    let theta = normalize_angle(yaw - std::f64::consts::FRAC_PI_2);
    [0.0, (theta / 2.0).sin(), 0.0, (theta / 2.0).cos()]
}

/// The dataset as Habitat JSON text; fails on what JSON cannot carry (a non-finite position,
/// rotation, radius or geodesic distance), naming the episode and field.
pub fn to_json_string(ds: &Dataset) -> Result<String, DatasetError> {
    for (index, e) in ds.episodes.iter().enumerate() {
        let bad = |field: String| DatasetError::Unwritable { index, episode_id: e.episode_id.clone(), field, reason: "not a finite number".into() };
        if !e.start_position.to_habitat().iter().all(|v| v.is_finite()) {
            return Err(bad("start_position".into()));
        }
        if !e.start_yaw.is_finite() {
            return Err(bad("start_rotation".into()));
        }
        if e.geodesic_distance.is_some_and(|d| !d.is_finite()) {
            return Err(bad("info.geodesic_distance".into()));
        }
        for (k, g) in e.goals.iter().enumerate() {
            if !g.position.to_habitat().iter().all(|v| v.is_finite()) {
                return Err(bad(format!("goals[{k}].position")));
            }
            if !g.radius.is_finite() {
                return Err(bad(format!("goals[{k}].radius")));
            }
        }
    }
    let file = FileDataset {
        episodes: ds
            .episodes
            .iter()
            .map(|e| {
                let mut info = if e.info.is_object() { e.info.clone() } else { serde_json::json!({}) };
                if let (Some(d), Some(m)) = (e.geodesic_distance, info.as_object_mut()) {
                    m.insert("geodesic_distance".into(), serde_json::json!(d));
                }
                FileEpisode {
                    episode_id: Id::Text(e.episode_id.clone()),
                    scene_id: e.scene_id.clone(),
                    start_position: e.start_position.to_habitat(),
                    start_rotation: quaternion_from_yaw(e.start_yaw),
                    info,
                    goals: e.goals.iter().map(|g| FileGoal { position: g.position.to_habitat(), radius: Some(g.radius) }).collect(),
                }
            })
            .collect(),
    };
    serde_json::to_string(&file).map_err(|e| DatasetError::Unwritable { index: 0, episode_id: String::new(), field: "episodes".into(), reason: e.to_string() })
}

/// Writes the dataset: gzipped when the name ends in `.gz` (fixed level, no timestamp, so
/// the same dataset gives the same bytes), plain JSON otherwise.
pub fn write_dataset(ds: &Dataset, path: &Path) -> Result<(), DatasetError> {
    let io = |source| DatasetError::Io { path: path.to_path_buf(), source };
    let json = to_json_string(ds).map_err(|e| match e {
        DatasetError::Unwritable { index, episode_id, field, reason } => DatasetError::Schema { path: path.to_path_buf(), field: format!("episodes[{index}] ({episode_id}).{field}"), reason },
        e => e,
    })?;
    let bytes = if path.to_string_lossy().ends_with(".gz") {
        let mut enc = flate2::GzBuilder::new().mtime(0).write(Vec::new(), flate2::Compression::new(6));
        enc.write_all(json.as_bytes()).map_err(io)?;
        enc.finish().map_err(io)?
    } else {
        json.into_bytes()
    };
    std::fs::write(path, bytes).map_err(io)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{FRAC_PI_2, PI};

    #[test]
    fn yaw_convention() {
        assert!((yaw_from_quaternion([0.0, 0.0, 0.0, 1.0]) - FRAC_PI_2).abs() < 1e-12);
        let s = (PI / 4.0).sin();
        let c = (PI / 4.0).cos();
        assert!((yaw_from_quaternion([0.0, s, 0.0, c]).abs() - PI).abs() < 1e-12);
        for yaw in [-3.0, -1.0, 0.0, 0.5, 2.0, 3.1] {
            assert!((yaw_from_quaternion(quaternion_from_yaw(yaw)) - yaw).abs() < 1e-12);
        }
    }

    #[test]
    fn round_trip_and_errors() {
        let dir = std::env::temp_dir().join(format!("xhab-ds-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let ds = Dataset {
            episodes: vec![Episode {
                episode_id: "7".into(),
                scene_id: "s.glb".into(),
                start_position: Point3::new(1.0, -2.0, 0.1),
                start_yaw: 0.3,
                goals: vec![Goal { position: Point3::new(3.0, 4.0, 0.1), radius: 0.2 }],
                geodesic_distance: Some(5.5),
                info: serde_json::json!({"geodesic_distance": 5.5}),
            }],
        };
        let p = dir.join("a.json.gz");
        write_dataset(&ds, &p).unwrap();
        let back = read_dataset(&p).unwrap();
        let (a, b) = (&ds.episodes[0], &back.episodes[0]);
        assert_eq!(a.episode_id, b.episode_id);
        assert!((a.start_yaw - b.start_yaw).abs() < 1e-12);
        assert!((a.start_position.y - b.start_position.y).abs() < 1e-12);
        let p2 = dir.join("b.json.gz");
        write_dataset(&ds, &p2).unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), std::fs::read(&p2).unwrap());
        let bad = dir.join("bad.json");
        std::fs::write(&bad, r#"{"episodes":[{"episode_id":1,"scene_id":"x","start_position":[0,1],"start_rotation":[0,0,0,1],"goals":[]}]}"#).unwrap();
        let e = read_dataset(&bad).unwrap_err().to_string();
        assert!(e.contains("bad.json") && e.contains("episodes[0].start_position"), "{e}");
        std::fs::write(&bad, r#"{"episodes":[{"episode_id":1,"scene_id":"x","start_position":[0,1,2],"start_rotation":[0,0,0,1],"goals":[]}]}"#).unwrap();
        let e = read_dataset(&bad).unwrap_err().to_string();
        assert!(e.contains("episodes[0].goals"), "{e}");
        let gz = std::fs::read(&p).unwrap();
        std::fs::write(&bad, &gz[..gz.len() / 2]).unwrap();
        assert!(read_dataset(&bad).is_err());
        // What JSON cannot carry is an error naming the episode and field, never an empty file.
        let mut nan = ds.clone();
        nan.episodes[0].goals[0].position.x = f64::NAN;
        let e = to_json_string(&nan).unwrap_err().to_string();
        assert_eq!(e, "episodes[0] (7): goals[0].position: not a finite number");
        let out = dir.join("nan.json");
        let e = write_dataset(&nan, &out).unwrap_err().to_string();
        assert!(e.contains("nan.json") && e.contains("goals[0].position"), "{e}");
        assert!(!out.exists());
        nan.episodes[0].goals[0].position.x = 3.0;
        nan.episodes[0].geodesic_distance = Some(f64::INFINITY);
        assert!(to_json_string(&nan).unwrap_err().to_string().contains("info.geodesic_distance"));
    }
}
