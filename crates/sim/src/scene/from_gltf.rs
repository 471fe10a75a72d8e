//! glTF 2.0 / GLB scenes: every node's transform applied, y-up converted to the world frame;
//! materials give the base colour factor and texture (with its `TEXCOORD_n` set).

use super::gltf_check::{check_accessor, check_glb};
use super::gltf_texture::{read_uri, GltfTextures};
use gltf::accessor::{DataType, Dimensions};
use super::loader::ReadReferenced;
use super::{Mesh, Scene, SceneError, UpAxis};
use std::path::Path;

type Mat4 = [[f64; 4]; 4];

const IDENTITY: Mat4 = [[1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]];

/// Column-major product `a * b` (glTF matrices are column-major: `m[col][row]`).
fn mul(a: &Mat4, b: &Mat4) -> Mat4 {
    let mut r = [[0.0; 4]; 4];
    for c in 0..4 {
        for row in 0..4 {
            r[c][row] = (0..4).map(|k| a[k][row] * b[c][k]).sum();
        }
    }
    r
}

fn det3(m: &Mat4) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[2][1] * m[1][2]) - m[1][0] * (m[0][1] * m[2][2] - m[2][1] * m[0][2])
        + m[2][0] * (m[0][1] * m[1][2] - m[1][1] * m[0][2])
}

/// Parses a .gltf (its external buffers and images read with `read`) or .glb file's bytes;
/// `path` names the file in errors. Without `with_textures`, no image is read or decoded and
/// every mesh keeps its base colour factor alone.
pub(crate) fn parse_gltf(bytes: &[u8], path: &Path, read: ReadReferenced<'_>, with_textures: bool) -> Result<Scene, SceneError> {
    let malformed = |reason: String| SceneError::Malformed { path: path.to_path_buf(), reason };
    let is_glb = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("glb"));
    if bytes.starts_with(b"glTF") {
        check_glb(bytes).map_err(malformed)?;
    } else if is_glb {
        let magic = String::from_utf8_lossy(&bytes[..bytes.len().min(4)]).escape_debug().to_string();
        return Err(malformed(format!("GLB header, byte 0: magic \"{magic}\", expected \"glTF\"")));
    }
    let invalid = |e: gltf::Error| malformed(format!("not a valid glTF/GLB file: {e}"));
    let raw = gltf::Gltf::from_slice_without_validation(bytes).map_err(invalid)?;
    // gltf-json's validation indexes the accessors with POSITION's index unchecked.
    check_position_refs(raw.document.as_json()).map_err(malformed)?;
    let blob = raw.blob;
    let doc = gltf::Document::from_json(raw.document.into_json()).map_err(invalid)?;
    check_image_sources(doc.as_json()).map_err(malformed)?;
    let buffers = load_buffers(&doc, blob, read).map_err(malformed)?;
    if doc.extensions_used().any(|e| e == "KHR_texture_transform") {
        tracing::warn!("{}: KHR_texture_transform is not applied: textures may be misplaced", path.display());
    }
    let mut textures = GltfTextures::new(path, &buffers, read);
    let scene = doc.default_scene().or_else(|| doc.scenes().next()).ok_or_else(|| malformed("the file has no scene".into()))?;
    check_node_tree(&doc).map_err(malformed)?;
    let mut out = Scene::default();
    let mut stack: Vec<(gltf::Node, Mat4, usize)> = scene.nodes().map(|n| (n, IDENTITY, 0)).collect();
    stack.reverse();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > 256 {
            return Err(malformed("the node hierarchy is deeper than 256 levels (a cycle?)".into()));
        }
        let local = node.transform().matrix().map(|c| c.map(|v| v as f64));
        let m = mul(&parent, &local);
        if let Some(mesh) = node.mesh() {
            let name = node.name().filter(|s| !s.is_empty()).or(mesh.name()).unwrap_or("").to_string();
            for (pi, prim) in mesh.primitives().enumerate() {
                if let Some(me) = primitive(path, &buffers, with_textures.then_some(&mut textures), &prim, &m, &name, pi)? {
                    out.meshes.push(me);
                }
            }
        }
        let children: Vec<_> = node.children().collect();
        for c in children.into_iter().rev() {
            stack.push((c, m, depth + 1));
        }
    }
    out.textures = textures.finish()?;
    Ok(out)
}

/// Checks that every primitive's POSITION names an accessor the file has.
fn check_position_refs(json: &gltf::json::Root) -> Result<(), String> {
    let position = gltf::json::validation::Checked::Valid(gltf::Semantic::Positions);
    for (mi, mesh) in json.meshes.iter().enumerate() {
        for (pi, prim) in mesh.primitives.iter().enumerate() {
            if let Some(a) = prim.attributes.get(&position) {
                if a.value() >= json.accessors.len() {
                    return Err(format!("mesh {mi} primitive {pi}: POSITION names accessor {}, but the file has {} accessors", a.value(), json.accessors.len()));
                }
            }
        }
    }
    Ok(())
}

/// Checks that every image has a source the gltf crate can give without panicking: a `uri`,
/// or a `bufferView` with its `mimeType` (which glTF requires).
fn check_image_sources(json: &gltf::json::Root) -> Result<(), String> {
    for (i, image) in json.images.iter().enumerate() {
        match (&image.uri, &image.buffer_view, &image.mime_type) {
            (None, None, _) => return Err(format!("image {i} has neither a uri nor a bufferView")),
            (None, Some(_), None) => return Err(format!("image {i} has a bufferView but no mimeType")),
            _ => {}
        }
    }
    Ok(())
}

/// Checks that the nodes form trees, as glTF requires: no node is the child of two parents (or
/// twice of one) and none is its own descendant. Traversal from the scene's roots then ends.
fn check_node_tree(doc: &gltf::Document) -> Result<(), String> {
    let n = doc.nodes().len();
    let mut parent: Vec<Option<usize>> = vec![None; n];
    for node in doc.nodes() {
        for c in node.children() {
            if let Some(p) = parent[c.index()].replace(node.index()) {
                return Err(format!("node {} is a child of node {p} and of node {} (glTF nodes form trees)", c.index(), node.index()));
            }
        }
    }
    // Walk up from each node; meeting a node of the same walk is a cycle.
    let mut walk = vec![usize::MAX; n];
    for start in 0..n {
        let mut at = start;
        while walk[at] == usize::MAX {
            walk[at] = start;
            match parent[at] {
                Some(p) => at = p,
                None => break,
            }
        }
        if walk[at] == start && parent[at].is_some() {
            return Err(format!("node {at} is its own descendant (a cycle in the node hierarchy)"));
        }
    }
    Ok(())
}

/// The data of every buffer: the GLB's BIN chunk, a data URI or a file read with `read`;
/// each at least as long as its `byteLength` says, padded to a multiple of 4 bytes.
fn load_buffers(doc: &gltf::Document, mut blob: Option<Vec<u8>>, read: ReadReferenced<'_>) -> Result<Vec<Vec<u8>>, String> {
    let mut out = Vec::new();
    for b in doc.buffers() {
        let mut data = match b.source() {
            gltf::buffer::Source::Bin => blob.take().ok_or_else(|| format!("buffer {}: refers to the GLB's BIN chunk, which the file lacks (or an earlier buffer took)", b.index()))?,
            gltf::buffer::Source::Uri(uri) => read_uri(uri, read).map_err(|e| format!("buffer {}: {e}", b.index()))?,
        };
        if data.len() < b.length() {
            return Err(format!("buffer {}: {} bytes, but its byteLength is {}", b.index(), data.len(), b.length()));
        }
        while data.len() % 4 != 0 {
            data.push(0);
        }
        out.push(data);
    }
    Ok(out)
}

fn primitive(
    path: &Path,
    buffers: &[Vec<u8>],
    textures: Option<&mut GltfTextures>,
    prim: &gltf::Primitive,
    m: &Mat4,
    name: &str,
    pi: usize,
) -> Result<Option<Mesh>, SceneError> {
    let malformed = |reason: String| SceneError::Malformed { path: path.to_path_buf(), reason };
    let mode = prim.mode();
    if !matches!(mode, gltf::mesh::Mode::Triangles | gltf::mesh::Mode::TriangleStrip | gltf::mesh::Mode::TriangleFan) {
        tracing::warn!("{}: mesh '{name}' primitive {pi}: {mode:?} skipped (not triangles)", path.display());
        return Ok(None);
    }
    let Some(pos_accessor) = prim.get(&gltf::Semantic::Positions) else {
        return Err(malformed(format!("mesh '{name}' primitive {pi} has no POSITION attribute")));
    };
    let at = |e: String| malformed(format!("mesh '{name}' primitive {pi}: {e}"));
    check_accessor(&pos_accessor, "POSITION", Dimensions::Vec3, &[DataType::F32], buffers).map_err(at)?;
    if let Some(a) = prim.indices() {
        check_accessor(&a, "indices", Dimensions::Scalar, &[DataType::U8, DataType::U16, DataType::U32], buffers).map_err(at)?;
    }
    let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d[..]));
    let Some(pos) = reader.read_positions() else {
        return Err(malformed(format!("mesh '{name}' primitive {pi} has no POSITION attribute")));
    };
    let flip = det3(m) < 0.0;
    let positions: Vec<[f32; 3]> = pos
        .map(|p| {
            let p = p.map(|v| v as f64);
            let v: [f64; 3] = std::array::from_fn(|r| m[0][r] * p[0] + m[1][r] * p[1] + m[2][r] * p[2] + m[3][r]);
            UpAxis::Y.to_world([v[0] as f32, v[1] as f32, v[2] as f32])
        })
        .collect();
    let idx: Vec<u32> = match reader.read_indices() {
        Some(i) => i.into_u32().collect(),
        None => (0..positions.len() as u32).collect(),
    };
    let tris: Vec<[u32; 3]> = match mode {
        gltf::mesh::Mode::TriangleStrip => (2..idx.len())
            .map(|i| if i % 2 == 0 { [idx[i - 2], idx[i - 1], idx[i]] } else { [idx[i - 1], idx[i - 2], idx[i]] })
            .collect(),
        gltf::mesh::Mode::TriangleFan => (2..idx.len()).map(|i| [idx[0], idx[i - 1], idx[i]]).collect(),
        _ => idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
    };
    let indices = tris.into_iter().map(|[a, b, c]| if flip { [a, c, b] } else { [a, b, c] }).collect();
    let pbr = prim.material().pbr_metallic_roughness();
    let mut mesh = Mesh::new(name, positions, indices, pbr.base_color_factor());
    if let (Some(info), Some(textures)) = (pbr.base_color_texture(), textures) {
        let set = info.tex_coord();
        if let Some(a) = prim.get(&gltf::Semantic::TexCoords(set)) {
            check_accessor(&a, &format!("TEXCOORD_{set}"), Dimensions::Vec2, &[DataType::F32, DataType::U8, DataType::U16], buffers).map_err(at)?;
        }
        match reader.read_tex_coords(set) {
            None => tracing::warn!(
                "{}: mesh '{name}' primitive {pi}: its base colour texture uses TEXCOORD_{set}, which it lacks; drawn with its base colour factor only",
                path.display()
            ),
            Some(uv) => {
                mesh.uvs = uv.into_f32().collect();
                mesh.texture = Some(textures.get(&info.texture(), name)?);
            }
        }
    }
    Ok(Some(mesh))
}
