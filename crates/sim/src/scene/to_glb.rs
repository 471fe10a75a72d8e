//! Writing a scene as GLB 2.0 (y up, as glTF wants), byte for byte deterministic.

use super::{Scene, SceneError};
use image::ImageEncoder;
use std::path::Path;

/// The scene as GLB bytes: one node, mesh and material per [`super::Mesh`], positions
/// converted back to glTF's y-up frame; textures as PNG images (texture coordinates as
/// `TEXCOORD_0`, wrap modes in one sampler per texture).
pub fn to_glb_bytes(scene: &Scene) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    let (mut views, mut accessors, mut meshes, mut nodes, mut materials) = (vec![], vec![], vec![], vec![], vec![]);
    let (mut images, mut textures, mut samplers) = (vec![], vec![], vec![]);
    // Scene texture index to glTF texture index (textures that cannot be encoded are left out).
    let mut tex_index: Vec<Option<usize>> = Vec::new();
    for t in &scene.textures {
        let mut png = Vec::new();
        let ok = t.is_consistent()
            && image::codecs::png::PngEncoder::new(&mut png).write_image(&t.rgba, t.width, t.height, image::ExtendedColorType::Rgba8).is_ok();
        if !ok {
            tex_index.push(None);
            continue;
        }
        views.push(serde_json::json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": png.len()}));
        bin.extend_from_slice(&png);
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        images.push(serde_json::json!({"bufferView": views.len() - 1, "mimeType": "image/png", "name": t.name}));
        samplers.push(serde_json::json!({"wrapS": t.wrap_s.gltf_code(), "wrapT": t.wrap_t.gltf_code()}));
        textures.push(serde_json::json!({"source": images.len() - 1, "sampler": samplers.len() - 1}));
        tex_index.push(Some(textures.len() - 1));
    }
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
        accessors.push(serde_json::json!({"bufferView": views.len() - 1, "componentType": 5126, "count": m.positions.len(), "type": "VEC3", "min": lo, "max": hi}));
        let pos_accessor = accessors.len() - 1;
        let off = bin.len();
        for t in &m.indices {
            for i in t {
                bin.extend_from_slice(&i.to_le_bytes());
            }
        }
        views.push(serde_json::json!({"buffer": 0, "byteOffset": off, "byteLength": m.indices.len() * 12, "target": 34963}));
        accessors.push(serde_json::json!({"bufferView": views.len() - 1, "componentType": 5125, "count": m.indices.len() * 3, "type": "SCALAR"}));
        let idx_accessor = accessors.len() - 1;
        let mut attributes = serde_json::json!({"POSITION": pos_accessor});
        let mut pbr = serde_json::json!({"baseColorFactor": m.base_color, "metallicFactor": 0.0, "roughnessFactor": 1.0});
        let tex = scene.texture_of(m).and(m.texture).and_then(|t| tex_index.get(t as usize).copied().flatten());
        if let Some(t) = tex {
            let off = bin.len();
            for uv in &m.uvs {
                bin.extend_from_slice(&uv[0].to_le_bytes());
                bin.extend_from_slice(&uv[1].to_le_bytes());
            }
            views.push(serde_json::json!({"buffer": 0, "byteOffset": off, "byteLength": m.uvs.len() * 8, "target": 34962}));
            accessors.push(serde_json::json!({"bufferView": views.len() - 1, "componentType": 5126, "count": m.uvs.len(), "type": "VEC2"}));
            attributes["TEXCOORD_0"] = serde_json::json!(accessors.len() - 1);
            pbr["baseColorTexture"] = serde_json::json!({"index": t});
        }
        materials.push(serde_json::json!({"pbrMetallicRoughness": pbr}));
        meshes.push(serde_json::json!({"name": m.name, "primitives": [{"attributes": attributes, "indices": idx_accessor, "material": k, "mode": 4}]}));
        nodes.push(serde_json::json!({"name": m.name, "mesh": k}));
    }
    let mut root = serde_json::json!({
        "asset": {"version": "2.0", "generator": "xhab"},
        "scene": 0,
        "scenes": [{"nodes": (0..scene.meshes.len()).collect::<Vec<_>>()}],
        "nodes": nodes, "meshes": meshes, "materials": materials,
        "accessors": accessors, "bufferViews": views,
        "buffers": [{"byteLength": bin.len()}],
    });
    if !images.is_empty() {
        root["images"] = images.into();
        root["samplers"] = samplers.into();
        root["textures"] = textures.into();
    }
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
