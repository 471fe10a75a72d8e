//! `load` and `parse`: any supported scene file, from disk or from bytes, checked.

use super::{LoadOptions, Scene, SceneError};
use std::path::Path;

/// A scene file's format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SceneFormat {
    /// glTF 2.0: binary (.glb) or JSON (.gltf), told apart by the first bytes.
    Gltf,
    /// Wavefront OBJ (.obj), with its MTL material libraries.
    Obj,
    /// Stanford PLY (.ply), ascii or binary.
    Ply,
}

impl SceneFormat {
    /// The format a file name's extension names (.glb, .gltf, .obj, .ply; case-insensitive).
    pub fn from_path(path: &Path) -> Option<SceneFormat> {
        let ext = path.extension().map(|e| e.to_string_lossy().to_lowercase()).unwrap_or_default();
        match ext.as_str() {
            "glb" | "gltf" => Some(SceneFormat::Gltf),
            "obj" => Some(SceneFormat::Obj),
            "ply" => Some(SceneFormat::Ply),
            _ => None,
        }
    }
}

/// Reads a file that a scene refers to (a glTF buffer or image, an OBJ material library or
/// texture), given its path as the scene writes it (relative to the scene's folder, or absolute).
pub type ReadReferenced<'a> = &'a dyn Fn(&Path) -> std::io::Result<Vec<u8>>;

/// Loads a scene file (.glb, .gltf, .obj, .ply; case-insensitive) into the world frame, drops
/// ceilings when asked, and checks it: finite vertices, indices in range, triangles present.
/// Files the scene refers to are read from beside it.
pub fn load(path: &Path, opts: &LoadOptions) -> Result<Scene, SceneError> {
    if !path.exists() {
        return Err(SceneError::Io { path: path.to_path_buf(), source: std::io::Error::new(std::io::ErrorKind::NotFound, "no such file") });
    }
    let format = SceneFormat::from_path(path).ok_or_else(|| SceneError::UnknownFormat { path: path.to_path_buf() })?;
    let bytes = std::fs::read(path).map_err(|source| SceneError::Io { path: path.to_path_buf(), source })?;
    let base = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    parse(&bytes, format, path, opts, &|rel: &Path| std::fs::read(base.join(rel)))
}

/// Parses a scene file's bytes as [`load`] does: `path` names the file in errors (and in the
/// mesh name of a PLY file); `read` reads the files the scene refers to.
pub fn parse(bytes: &[u8], format: SceneFormat, path: &Path, opts: &LoadOptions, read: ReadReferenced<'_>) -> Result<Scene, SceneError> {
    let mut scene = match format {
        SceneFormat::Gltf => super::from_gltf::parse_gltf(bytes, path, read, opts.textures)?,
        SceneFormat::Obj => super::from_obj::parse_obj(bytes, path, opts.up_axis, read, opts.textures)?,
        SceneFormat::Ply => super::from_ply::parse_ply(bytes, path, opts.up_axis)?,
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
