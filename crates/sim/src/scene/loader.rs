//! `load`: any supported scene file, checked.

use super::{LoadOptions, Scene, SceneError};
use std::path::Path;

/// Loads a scene file (.glb, .gltf, .obj, .ply; case-insensitive) into the world frame, drops
/// ceilings when asked, and checks it: finite vertices, indices in range, triangles present.
pub fn load(path: &Path, opts: &LoadOptions) -> Result<Scene, SceneError> {
    let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
    if !path.exists() {
        return Err(SceneError::Io { path: path.to_path_buf(), source: std::io::Error::new(std::io::ErrorKind::NotFound, "no such file") });
    }
    let mut scene = match ext.as_str() {
        "glb" | "gltf" => super::from_gltf::load_gltf(path)?,
        "obj" => super::from_obj::load_obj(path, opts.up_axis)?,
        "ply" => super::from_ply::load_ply(path, opts.up_axis)?,
        _ => return Err(SceneError::UnknownFormat { path: path.to_path_buf() }),
    };
    if opts.drop_ceilings {
        scene.meshes.retain(|m| !m.name.to_lowercase().contains("ceiling"));
    }
    check(&mut scene, path)?;
    Ok(scene)
}

/// Rejects non-finite vertices and out-of-range indices; drops empty meshes; drops (with a
/// warning) a mesh's texture when its texture coordinates are missing, miscounted or
/// non-finite, or its texture index is out of range, so it is drawn with its colour factor.
pub(crate) fn check(scene: &mut Scene, path: &Path) -> Result<(), SceneError> {
    let textures = scene.textures.len();
    for m in &mut scene.meshes {
        let why = match m.texture {
            None => None,
            Some(t) if t as usize >= textures => Some(format!("texture {t} does not exist ({textures} textures)")),
            Some(_) if m.uvs.len() != m.positions.len() => {
                Some(format!("{} texture coordinates for {} vertices", m.uvs.len(), m.positions.len()))
            }
            Some(_) => m.uvs.iter().position(|uv| !uv.iter().all(|c| c.is_finite())).map(|v| format!("non-finite texture coordinate at vertex {v}")),
        };
        if let Some(why) = why {
            tracing::warn!("{}: mesh '{}': {why}; drawn with its base colour factor only", path.display(), m.name);
            m.texture = None;
            m.uvs.clear();
        }
    }
    for m in &scene.meshes {
        if let Some(v) = m.positions.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
            return Err(SceneError::NonFinite { path: path.to_path_buf(), mesh: m.name.clone(), vertex: v });
        }
        let n = m.positions.len() as u32;
        if let Some(t) = m.indices.iter().position(|t| t.iter().any(|&i| i >= n)) {
            return Err(SceneError::Malformed {
                path: path.to_path_buf(),
                reason: format!("mesh '{}' triangle {t} refers to a vertex out of range ({n} vertices)", m.name),
            });
        }
    }
    scene.meshes.retain(|m| !m.indices.is_empty());
    if scene.triangle_count() == 0 {
        return Err(SceneError::Empty { path: path.to_path_buf() });
    }
    Ok(())
}
