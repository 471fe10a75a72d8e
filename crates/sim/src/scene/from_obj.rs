//! Wavefront OBJ scenes (triangulated), with the up axis as a load option; materials give the
//! diffuse colour (`Kd`) or texture (`map_Kd`, with the `vt` coordinates).

use super::loader::ReadReferenced;
use super::obj_check::{check_mtl, check_obj};
use std::cell::RefCell;
use super::{Mesh, Scene, SceneError, Texture, UpAxis, Wrap};
use std::collections::HashMap;
use std::path::Path;

/// Parses an .obj file's bytes; material libraries (`mtllib`) are read with `read` for their
/// diffuse colour and texture. A `map_Kd` image path is taken relative to the .obj's folder
/// (where the .mtl normally lies); the texture replaces `Kd` (factor 1), and OBJ's v axis (up)
/// is flipped to glTF's.
pub(crate) fn parse_obj(bytes: &[u8], path: &Path, up: UpAxis, read: ReadReferenced<'_>, with_textures: bool) -> Result<Scene, SceneError> {
    let malformed = |reason: String| SceneError::Malformed { path: path.to_path_buf(), reason };
    check_obj(bytes).map_err(malformed)?;
    let opts = tobj::LoadOptions { triangulate: true, single_index: true, ..Default::default() };
    // A material library that fails its check is an error of the scene; tobj's own error
    // type cannot carry the message, so it waits here.
    let bad_mtl: RefCell<Option<String>> = RefCell::new(None);
    let load_mtl = |mtl: &Path| {
        let bytes = read(mtl).map_err(|_| tobj::LoadError::OpenFileFailed)?;
        if let Err(e) = check_mtl(&bytes) {
            bad_mtl.borrow_mut().get_or_insert_with(|| format!("material library {}: {e}", mtl.display()));
            return Err(tobj::LoadError::MaterialParseError);
        }
        tobj::load_mtl_buf(&mut &bytes[..])
    };
    let loaded = tobj::load_obj_buf(&mut &bytes[..], &opts, load_mtl);
    if let Some(e) = bad_mtl.into_inner() {
        return Err(malformed(e));
    }
    let (models, materials) = loaded.map_err(|e| malformed(format!("bad OBJ: {e}")))?;
    let materials = materials.unwrap_or_else(|e| {
        tracing::warn!("{}: its material library cannot be read ({e}); meshes are drawn grey", path.display());
        Vec::new()
    });
    let mut out = Scene::default();
    // Texture file (as written) and wrap mode to its index in `out.textures`.
    let mut loaded: HashMap<(String, Wrap), u32> = HashMap::new();
    for m in models {
        let p = &m.mesh.positions;
        let positions: Vec<[f32; 3]> = p.chunks_exact(3).map(|c| up.to_world([c[0], c[1], c[2]])).collect();
        let indices = m.mesh.indices.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        let mat = m.mesh.material_id.and_then(|i| materials.get(i));
        let base_color = mat.and_then(|mat| mat.diffuse).map(|d| [d[0], d[1], d[2], 1.0]).unwrap_or([0.6, 0.6, 0.6, 1.0]);
        let mut mesh = Mesh::new(&m.name, positions, indices, base_color);
        if let Some(spec) = mat.and_then(|mat| mat.diffuse_texture.as_deref()).filter(|_| with_textures) {
            if m.mesh.texcoords.is_empty() {
                tracing::warn!("{}: mesh '{}': map_Kd {spec} without vt coordinates; drawn with Kd only", path.display(), m.name);
            } else {
                let (file, wrap) = map_kd(spec);
                let key = (file.to_string(), wrap);
                let idx = match loaded.get(&key) {
                    Some(&i) => i,
                    None => {
                        let err = |reason: String| SceneError::Texture { path: path.to_path_buf(), mesh: m.name.clone(), image: file.to_string(), reason };
                        let bytes = read(Path::new(file)).map_err(|e| err(format!("cannot read {file}: {e}")))?;
                        let t = Texture::decode(file, &bytes, wrap, wrap).map_err(err)?;
                        out.textures.push(t);
                        let i = out.textures.len() as u32 - 1;
                        loaded.insert(key, i);
                        i
                    }
                };
                mesh.uvs = m.mesh.texcoords.chunks_exact(2).map(|c| [c[0], 1.0 - c[1]]).collect();
                mesh.texture = Some(idx);
                mesh.base_color = [1.0; 4];
            }
        }
        out.meshes.push(mesh);
    }
    Ok(out)
}

/// The image file and wrap mode of a `map_Kd` statement's arguments: options (`-clamp on`,
/// `-s 1 1 1`, ...) come first, the file name last.
fn map_kd(spec: &str) -> (&str, Wrap) {
    if !spec.starts_with('-') {
        return (spec, Wrap::Repeat);
    }
    let words: Vec<&str> = spec.split_whitespace().collect();
    let clamp = words.windows(2).any(|w| w[0] == "-clamp" && w[1] == "on");
    (words.last().copied().unwrap_or(spec), if clamp { Wrap::ClampToEdge } else { Wrap::Repeat })
}

#[cfg(test)]
mod tests {
    #[test]
    fn map_kd_options_precede_the_file() {
        use super::{map_kd, Wrap};
        assert_eq!(map_kd("wood floor.png"), ("wood floor.png", Wrap::Repeat));
        assert_eq!(map_kd("-s 2 2 1 -clamp on tex/a.jpg"), ("tex/a.jpg", Wrap::ClampToEdge));
    }
}
