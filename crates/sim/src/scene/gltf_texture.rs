//! glTF base-colour textures: images read from buffer views, data URIs or files beside the
//! .gltf, decoded once per (image, wrap modes) however many materials use them.

use super::loader::ReadReferenced;
use super::{SceneError, Texture, Wrap};
use base64::Engine;
use std::collections::HashMap;
use std::path::Path;

/// The textures of one glTF file: each image's bytes read on first use, all decoded at the
/// end, in parallel ([`GltfTextures::finish`]).
pub(crate) struct GltfTextures<'a> {
    /// The glTF file (for messages).
    path: &'a Path,
    /// Reads the files relative URIs name.
    read: ReadReferenced<'a>,
    buffers: &'a [Vec<u8>],
    /// (image index, wrap s, wrap t) to the index in `pending`.
    loaded: HashMap<(usize, Wrap, Wrap), u32>,
    /// The textures to decode, in order of first use: the image's name, its encoded bytes,
    /// its wrap modes and the mesh that first used it (for messages).
    pending: Vec<(String, Vec<u8>, Wrap, Wrap, String)>,
}

impl<'a> GltfTextures<'a> {
    pub(crate) fn new(path: &'a Path, buffers: &'a [Vec<u8>], read: ReadReferenced<'a>) -> Self {
        Self { path, read, buffers, loaded: HashMap::new(), pending: Vec::new() }
    }

    /// The index of `tex` in the scene's texture table, reading its image's bytes on first
    /// use; the error names the file, the mesh and the image.
    pub(crate) fn get(&mut self, tex: &gltf::Texture, mesh: &str) -> Result<u32, SceneError> {
        let sampler = tex.sampler();
        let (ws, wt) = (Wrap::from_gltf(sampler.wrap_s()), Wrap::from_gltf(sampler.wrap_t()));
        let image = tex.source();
        let key = (image.index(), ws, wt);
        if let Some(&i) = self.loaded.get(&key) {
            return Ok(i);
        }
        let name = match image.source() {
            gltf::image::Source::Uri { uri, .. } if !uri.starts_with("data:") => uri.to_string(),
            _ => format!("image {}", image.index()),
        };
        let bytes = self.bytes(&image.source()).map_err(|reason| texture_error(self.path, mesh, &name, reason))?;
        let i = self.pending.len() as u32;
        self.pending.push((name, bytes, ws, wt, mesh.to_string()));
        self.loaded.insert(key, i);
        Ok(i)
    }

    /// The decoded textures, in the order [`GltfTextures::get`] numbered them (decoded in
    /// parallel; the first that fails in that order is the error).
    pub(crate) fn finish(self) -> Result<Vec<Texture>, SceneError> {
        use rayon::prelude::*;
        let path = self.path;
        self.pending
            .into_par_iter()
            .map(|(name, bytes, ws, wt, mesh)| Texture::decode(&name, &bytes, ws, wt).map_err(|reason| texture_error(path, &mesh, &name, reason)))
            .collect::<Vec<_>>()
            .into_iter()
            .collect()
    }

    /// The encoded bytes of an image.
    fn bytes(&self, src: &gltf::image::Source) -> Result<Vec<u8>, String> {
        match src {
            gltf::image::Source::View { view, .. } => {
                let buf = self.buffers.get(view.buffer().index()).ok_or("its buffer view refers to a missing buffer")?;
                let (a, n) = (view.offset(), view.length());
                buf.get(a..a.saturating_add(n)).map(|b| b.to_vec()).ok_or_else(|| {
                    format!("its buffer view (bytes {a}..{}) lies outside its buffer ({} bytes)", a.saturating_add(n), buf.len())
                })
            }
            gltf::image::Source::Uri { uri, .. } => read_uri(uri, self.read),
        }
    }
}

fn texture_error(path: &Path, mesh: &str, image: &str, reason: String) -> SceneError {
    SceneError::Texture { path: path.to_path_buf(), mesh: mesh.to_string(), image: image.to_string(), reason }
}

/// The bytes a glTF URI names: a base64 data URI, or a file (relative to the glTF's folder,
/// percent-encoded, optionally `file://`) read with `read`; network URIs are refused.
pub(crate) fn read_uri(uri: &str, read: ReadReferenced<'_>) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, data) = rest.split_once(";base64,").ok_or("a data URI that is not base64")?;
        base64::engine::general_purpose::STANDARD.decode(data).map_err(|e| format!("bad base64 in its data URI: {e}"))
    } else if uri.contains("://") && !uri.starts_with("file://") {
        Err("only files and data URIs are read, not network URIs".into())
    } else {
        let rel = uri.strip_prefix("file://").unwrap_or(uri);
        let rel = urlencoding::decode(rel).map_err(|e| format!("bad percent-encoding in the URI: {e}"))?;
        read(Path::new(&*rel)).map_err(|e| format!("cannot read {rel}: {e}"))
    }
}
