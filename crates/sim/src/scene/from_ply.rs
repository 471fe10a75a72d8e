//! PLY scenes (ascii and binary), with the up axis as a load option (Matterport PLY is z-up).

use super::{Mesh, Scene, SceneError, UpAxis};
use ply_rs::ply::{DefaultElement, Property};
use std::path::Path;

fn num(p: &Property) -> Option<f64> {
    Some(match p {
        Property::Char(v) => *v as f64,
        Property::UChar(v) => *v as f64,
        Property::Short(v) => *v as f64,
        Property::UShort(v) => *v as f64,
        Property::Int(v) => *v as f64,
        Property::UInt(v) => *v as f64,
        Property::Float(v) => *v as f64,
        Property::Double(v) => *v,
        _ => return None,
    })
}

fn list(p: &Property) -> Option<Vec<i64>> {
    Some(match p {
        Property::ListChar(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListUChar(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListShort(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListUShort(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListInt(v) => v.iter().map(|&x| x as i64).collect(),
        Property::ListUInt(v) => v.iter().map(|&x| x as i64).collect(),
        _ => return None,
    })
}

/// Parses a .ply file's bytes: `vertex` elements with x, y, z and `face` elements with a
/// `vertex_indices` (or `vertex_index`) list; polygons are fan-triangulated. The mesh is named
/// after `path`'s file stem.
pub(crate) fn parse_ply(bytes: &[u8], path: &Path, up: UpAxis) -> Result<Scene, SceneError> {
    let malformed = |reason: String| SceneError::Malformed { path: path.to_path_buf(), reason };
    let mut reader = bytes;
    let parser = ply_rs::parser::Parser::<DefaultElement>::new();
    let ply = parser.read_ply(&mut reader).map_err(|e| malformed(format!("bad PLY: {e}")))?;
    let verts = ply.payload.get("vertex").ok_or_else(|| malformed("no 'vertex' element".into()))?;
    let mut positions = Vec::with_capacity(verts.len());
    for (i, v) in verts.iter().enumerate() {
        let c = |k: &str| v.get(k).and_then(num).ok_or_else(|| malformed(format!("vertex {i} has no numeric '{k}'")));
        positions.push(up.to_world([c("x")? as f32, c("y")? as f32, c("z")? as f32]));
    }
    let mut indices = Vec::new();
    for (fi, f) in ply.payload.get("face").map(|v| v.as_slice()).unwrap_or(&[]).iter().enumerate() {
        let l = f
            .get("vertex_indices")
            .or_else(|| f.get("vertex_index"))
            .and_then(list)
            .ok_or_else(|| malformed(format!("face {fi} has no vertex_indices list")))?;
        for k in 2..l.len() {
            let t = [l[0], l[k - 1], l[k]];
            if t.iter().any(|&x| x < 0 || x as usize >= positions.len()) {
                return Err(malformed(format!("face {fi} refers to a vertex out of range (the file has {} vertices)", positions.len())));
            }
            indices.push(t.map(|x| x as u32));
        }
    }
    let name = path.file_stem().map(|s| s.to_string_lossy().to_string()).unwrap_or_default();
    Ok(Scene { meshes: vec![Mesh::new(&name, positions, indices, [0.6, 0.6, 0.6, 1.0])], textures: Vec::new() })
}
