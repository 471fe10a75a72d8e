//! What the gltf crate leaves to its caller: the GLB container's header and chunks (it
//! subtracts before it checks), and the accessors a mesh is read through (its reader panics on
//! an unexpected layout, overflows on a huge count, and reads nothing out of range).

use gltf::accessor::{DataType, Dimensions};

/// The little-endian `u32` at byte `at` (the caller checks that 4 bytes are there).
fn u32_at(b: &[u8], at: usize) -> u32 {
    u32::from_le_bytes([b[at], b[at + 1], b[at + 2], b[at + 3]])
}

/// Checks a GLB container (the bytes start with `glTF`): a 12-byte header (version 2, a total
/// length the file holds), a JSON chunk and an optional BIN chunk, each within the file. The
/// error names the byte offset at fault.
pub(crate) fn check_glb(b: &[u8]) -> Result<(), String> {
    if b.len() < 12 {
        return Err(format!("truncated GLB header: the file ends at byte {}, a GLB header takes 12 bytes", b.len()));
    }
    let version = u32_at(b, 4);
    if version != 2 {
        return Err(format!("GLB header, byte 4: version {version}; only glTF 2 is read"));
    }
    let length = u32_at(b, 8) as usize;
    if length < 20 {
        return Err(format!("GLB header, byte 8: total length {length} is less than a header and a JSON chunk header (20 bytes)"));
    }
    if length > b.len() {
        return Err(format!("GLB header, byte 8: total length {length}, but the file ends at byte {}", b.len()));
    }
    // The gltf crate reads the chunks up to the end of the file: a JSON chunk, then a BIN chunk
    // when bytes remain.
    let end = b.len();
    let mut at = 12;
    for (name, kind) in [("JSON", b"JSON"), ("BIN", b"BIN\0")] {
        if name == "BIN" && at == end {
            break;
        }
        if end - at < 8 {
            return Err(format!("truncated GLB: the {name} chunk header at byte {at} is cut off by the end of the file (byte {end})"));
        }
        let len = u32_at(b, at) as usize;
        let ty = &b[at + 4..at + 8];
        if ty != kind {
            return Err(format!(
                "GLB chunk at byte {at}: type \"{}\", expected \"{}\"",
                String::from_utf8_lossy(ty).escape_debug(),
                String::from_utf8_lossy(kind).escape_debug()
            ));
        }
        let data = at + 8;
        if len > end - data {
            return Err(format!("GLB {name} chunk at byte {at}: its length {len} runs past the end of the file (byte {end})"));
        }
        at = data + len;
    }
    Ok(())
}

/// Checks that accessor `a` (the `what` of a mesh primitive: `POSITION`, `indices`,
/// `TEXCOORD_n`) has a layout the reader takes (`dims`, a component type of `types`), at least
/// one element, and lies within its buffer views, which lie within their buffers.
pub(crate) fn check_accessor(a: &gltf::Accessor, what: &str, dims: Dimensions, types: &[DataType], buffers: &[Vec<u8>]) -> Result<(), String> {
    let name = format!("{what} (accessor {})", a.index());
    if a.dimensions() != dims || !types.contains(&a.data_type()) {
        return Err(format!("{name}: {:?} of {:?}, expected {dims:?} of {}", a.dimensions(), a.data_type(), types.iter().map(|t| format!("{t:?}")).collect::<Vec<_>>().join(" or ")));
    }
    let count = a.count();
    if count == 0 {
        return Err(format!("{name}: count is 0"));
    }
    if let Some(view) = a.view() {
        check_range(&name, &view, a.offset(), count, a.size(), buffers)?;
    }
    if let Some(sparse) = a.sparse() {
        let n = sparse.count();
        if n == 0 || n > count {
            return Err(format!("{name}: sparse count {n}, expected 1 to {count}"));
        }
        let idx = sparse.indices();
        let size = match idx.index_type() {
            gltf::accessor::sparse::IndexType::U8 => 1,
            gltf::accessor::sparse::IndexType::U16 => 2,
            gltf::accessor::sparse::IndexType::U32 => 4,
        };
        check_range(&format!("{name} sparse indices"), &idx.view(), idx.offset(), n, size, buffers)?;
        let values = sparse.values();
        check_range(&format!("{name} sparse values"), &values.view(), values.offset(), n, a.size(), buffers)?;
    }
    Ok(())
}

/// Checks that `count` elements of `elem` bytes from byte `offset` of `view` (at its stride) lie
/// within it, and that it lies within its buffer.
fn check_range(name: &str, view: &gltf::buffer::View, offset: usize, count: usize, elem: usize, buffers: &[Vec<u8>]) -> Result<(), String> {
    let v = view.index();
    let stride = view.stride().unwrap_or(elem);
    if stride < elem {
        return Err(format!("{name}: buffer view {v}'s byteStride {stride} is less than an element ({elem} bytes)"));
    }
    let len = view.length();
    let end = (count - 1).checked_mul(stride).and_then(|x| x.checked_add(elem)).and_then(|x| x.checked_add(offset));
    if end.is_none_or(|e| e > len) {
        let end = end.map_or("beyond any size".to_string(), |e| format!("{e}"));
        return Err(format!("{name}: {count} elements of {elem} bytes (stride {stride}) from byte {offset} end at byte {end}, past the end of buffer view {v} ({len} bytes)"));
    }
    let b = view.buffer().index();
    let size = buffers.get(b).map_or(0, Vec::len);
    if view.offset().checked_add(len).is_none_or(|e| e > size) {
        return Err(format!("{name}: buffer view {v} (bytes {}..{}) lies outside buffer {b} ({size} bytes)", view.offset(), view.offset().saturating_add(len)));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::check_glb;

    fn glb(version: u32, length: u32, chunks: &[(u32, &[u8; 4], &[u8])]) -> Vec<u8> {
        let mut b = b"glTF".to_vec();
        b.extend(version.to_le_bytes());
        b.extend(length.to_le_bytes());
        for (len, ty, data) in chunks {
            b.extend(len.to_le_bytes());
            b.extend(*ty);
            b.extend(*data);
        }
        b
    }

    #[test]
    fn glb_containers_are_checked_with_byte_offsets() {
        let ok = glb(2, 24, &[(4, b"JSON", b"{}  ")]);
        assert_eq!(check_glb(&ok), Ok(()));
        let with_bin = glb(2, 36, &[(4, b"JSON", b"{}  "), (4, b"BIN\0", b"abcd")]);
        assert_eq!(check_glb(&with_bin), Ok(()));
        for (bytes, want) in [
            (b"glTF\x02\0".to_vec(), "truncated GLB header: the file ends at byte 6"),
            (glb(1, 24, &[(4, b"JSON", b"{}  ")]), "byte 4: version 1"),
            (glb(2, 4, &[(4, b"JSON", b"{}  ")]), "byte 8: total length 4"),
            (glb(2, 99, &[(4, b"JSON", b"{}  ")]), "byte 8: total length 99, but the file ends at byte 24"),
            (glb(2, 24, &[(4, b"BIN\0", b"{}  ")]), "chunk at byte 12: type \"BIN\\0\", expected \"JSON\""),
            (glb(2, 24, &[(40, b"JSON", b"{}  ")]), "JSON chunk at byte 12: its length 40 runs past the end of the file (byte 24)"),
            ([glb(2, 28, &[(4, b"JSON", b"{}  ")]), vec![9, 0, 0, 0]].concat(), "BIN chunk header at byte 24 is cut off"),
            (glb(2, 36, &[(4, b"JSON", b"{}  "), (400, b"BIN\0", b"abcd")]), "BIN chunk at byte 24: its length 400"),
        ] {
            let e = check_glb(&bytes).unwrap_err();
            assert!(e.contains(want), "{e}");
        }
    }
}
