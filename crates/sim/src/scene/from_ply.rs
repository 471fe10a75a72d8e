//! PLY scenes (ascii and binary), with the up axis as a load option (Matterport PLY is z-up).

use super::{Mesh, Scene, SceneError, UpAxis};
use ply_rs::parser::Parser;
use ply_rs::ply::{DefaultElement, Encoding, Property};
use std::collections::HashMap;
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
/// after `path`'s file stem. Errors name the header line, the body line (ascii) or the byte
/// offset (binary) of the entry at fault.
pub(crate) fn parse_ply(bytes: &[u8], path: &Path, up: UpAxis) -> Result<Scene, SceneError> {
    let malformed = |reason: String| SceneError::Malformed { path: path.to_path_buf(), reason };
    super::ply_check::check_ply_header(bytes).map_err(malformed)?;
    let parser = Parser::<DefaultElement>::new();
    let mut reader = bytes;
    let header = parser.read_header(&mut reader).map_err(|e| malformed(ply_rs_message(&e)))?;
    let body = bytes.len() - reader.len();
    // The first body line's number (ascii): the header's lines, then one per entry.
    let mut line = bytes[..body].iter().filter(|&&b| b == b'\n').count() + 1;
    let mut payload: HashMap<&str, Vec<DefaultElement>> = HashMap::new();
    for (name, def) in &header.elements {
        let keep = name == "vertex" || name == "face";
        let mut entries = Vec::new();
        for i in 0..def.count {
            let at = bytes.len() - reader.len();
            let entry = match header.encoding {
                Encoding::Ascii => {
                    let end = reader.iter().position(|&b| b == b'\n').map_or(reader.len(), |e| e + 1);
                    let (text, rest) = reader.split_at(end);
                    reader = rest;
                    let n = line;
                    line += 1;
                    let at_line = |why: String| malformed(format!("line {n}: element '{name}' entry {i}: {why}"));
                    if text.is_empty() {
                        return Err(at_line("the file ends before it".into()));
                    }
                    let text = std::str::from_utf8(text).map_err(|_| at_line("not UTF-8 text".into()))?;
                    parser.read_ascii_element(text, def).map_err(|e| at_line(format!("{} in \"{}\"", first_line(&e), text.trim_end())))?
                }
                Encoding::BinaryLittleEndian | Encoding::BinaryBigEndian => {
                    let read = if header.encoding == Encoding::BinaryLittleEndian {
                        parser.read_little_endian_element(&mut reader, def)
                    } else {
                        parser.read_big_endian_element(&mut reader, def)
                    };
                    read.map_err(|e| {
                        let why = if reader.is_empty() { format!("the file ends at byte {} inside it", bytes.len()) } else { first_line(&e) };
                        malformed(format!("byte {at}: element '{name}' entry {i}: {why}"))
                    })?
                }
            };
            if keep {
                entries.push(entry);
            }
        }
        payload.insert(name.as_str(), entries);
    }
    let verts = payload.get("vertex").ok_or_else(|| malformed("no 'vertex' element".into()))?;
    let mut positions = Vec::with_capacity(verts.len());
    for (i, v) in verts.iter().enumerate() {
        let c = |k: &str| v.get(k).and_then(num).ok_or_else(|| malformed(format!("vertex {i} has no numeric '{k}'")));
        positions.push(up.to_world([c("x")? as f32, c("y")? as f32, c("z")? as f32]));
    }
    let mut indices = Vec::new();
    for (fi, f) in payload.get("face").map(|v| v.as_slice()).unwrap_or(&[]).iter().enumerate() {
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

/// The first line of a ply-rs error, its `Line N` as `line N`, and the header line it quotes.
fn ply_rs_message(e: &std::io::Error) -> String {
    let msg = e.to_string();
    let first = first_line(e);
    let first = first.strip_prefix("Line ").map_or_else(|| first.clone(), |rest| format!("line {rest}"));
    match msg.split_once("String: '").map(|(_, s)| s.split('\'').next().unwrap_or_default().trim()) {
        Some(quoted) if !quoted.is_empty() => format!("{first} (\"{quoted}\")"),
        _ => first,
    }
}

/// The first line of an error's message, without its trailing full stop.
fn first_line(e: &std::io::Error) -> String {
    let msg = e.to_string();
    msg.lines().next().unwrap_or_default().trim_end_matches('.').to_string()
}
