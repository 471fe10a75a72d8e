//! Wavefront OBJ scenes (triangulated), with the up axis as a load option.

use super::{Mesh, Scene, SceneError, UpAxis};
use std::path::Path;

/// Loads an .obj file; materials are read for their diffuse colour when present.
pub(crate) fn load_obj(path: &Path, up: UpAxis) -> Result<Scene, SceneError> {
    let opts = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
    let (models, materials) = tobj::load_obj(path, &opts).map_err(|e| match e {
        tobj::LoadError::OpenFileFailed => {
            SceneError::Io { path: path.to_path_buf(), source: std::io::Error::new(std::io::ErrorKind::NotFound, "cannot open the file") }
        }
        e => SceneError::Malformed { path: path.to_path_buf(), reason: format!("bad OBJ: {e}") },
    })?;
    let materials = materials.unwrap_or_default();
    let mut out = Scene::default();
    for m in models {
        let p = &m.mesh.positions;
        let positions: Vec<[f32; 3]> = p.chunks_exact(3).map(|c| up.to_world([c[0], c[1], c[2]])).collect();
        let indices = m.mesh.indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let base_color = m
            .mesh
            .material_id
            .and_then(|i| materials.get(i))
            .and_then(|mat| mat.diffuse)
            .map(|d| [d[0], d[1], d[2], 1.0])
            .unwrap_or([0.6, 0.6, 0.6, 1.0]);
        out.meshes.push(Mesh { name: m.name, positions, indices, base_color });
    }
    Ok(out)
}
