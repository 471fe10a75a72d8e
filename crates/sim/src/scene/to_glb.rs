//! Writing a scene as GLB 2.0 (y up, as glTF wants), byte for byte deterministic.

use super::{Scene, SceneError};
use std::path::Path;

/// The scene as GLB bytes: one node, mesh and material per [`super::Mesh`], positions
/// converted back to glTF's y-up frame.
pub fn to_glb_bytes(scene: &Scene) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    let (mut views, mut accessors, mut meshes, mut nodes, mut materials) = (vec![], vec![], vec![], vec![], vec![]);
    for (k, m) in scene.meshes.iter().enumerate() {
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        let off = bin.len();
        for p in &m.positions {
            let g = [p[0], p[2], -p[1]];
            for i in 0..3 {
                lo[i] = lo[i].min(g[i]);
                hi[i] = hi[i].max(g[i]);
                bin.extend_from_slice(&g[i].to_le_bytes());
            }
        }
        if m.positions.is_empty() {
            lo = [0.0; 3];
            hi = [0.0; 3];
        }
        views.push(serde_json::json!({"buffer": 0, "byteOffset": off, "byteLength": m.positions.len() * 12, "target": 34962}));
        accessors.push(serde_json::json!({"bufferView": 2 * k, "componentType": 5126, "count": m.positions.len(), "type": "VEC3", "min": lo, "max": hi}));
        let off = bin.len();
        for t in &m.indices {
            for i in t {
                bin.extend_from_slice(&i.to_le_bytes());
            }
        }
        views.push(serde_json::json!({"buffer": 0, "byteOffset": off, "byteLength": m.indices.len() * 12, "target": 34963}));
        accessors.push(serde_json::json!({"bufferView": 2 * k + 1, "componentType": 5125, "count": m.indices.len() * 3, "type": "SCALAR"}));
        materials.push(serde_json::json!({"pbrMetallicRoughness": {"baseColorFactor": m.base_color, "metallicFactor": 0.0, "roughnessFactor": 1.0}}));
        meshes.push(serde_json::json!({"name": m.name, "primitives": [{"attributes": {"POSITION": 2 * k}, "indices": 2 * k + 1, "material": k, "mode": 4}]}));
        nodes.push(serde_json::json!({"name": m.name, "mesh": k}));
    }
    let root = serde_json::json!({
        "asset": {"version": "2.0", "generator": "xhab"},
        "scene": 0,
        "scenes": [{"nodes": (0..scene.meshes.len()).collect::<Vec<_>>()}],
        "nodes": nodes, "meshes": meshes, "materials": materials,
        "accessors": accessors, "bufferViews": views,
        "buffers": [{"byteLength": bin.len()}],
    });
    let mut json = serde_json::to_vec(&root).unwrap_or_default();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}

/// Writes the scene as a .glb file.
pub fn write_glb(scene: &Scene, path: &Path) -> Result<(), SceneError> {
    std::fs::write(path, to_glb_bytes(scene)).map_err(|source| SceneError::Io { path: path.to_path_buf(), source })
}
