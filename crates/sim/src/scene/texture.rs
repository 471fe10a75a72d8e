//! Base-colour textures: RGBA8 sRGB images with glTF's wrap modes, stored once per scene.

use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// How a texture coordinate outside [0, 1] picks a texel (glTF sampler `wrapS`/`wrapT`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Wrap {
    /// The image tiles the plane (glTF `REPEAT`, 10497; the default).
    #[default]
    Repeat,
    /// Coordinates are clamped to the edge texels (glTF `CLAMP_TO_EDGE`, 33071).
    ClampToEdge,
    /// The image tiles the plane, every other copy mirrored (glTF `MIRRORED_REPEAT`, 33648).
    MirroredRepeat,
}

impl Wrap {
    /// The mode of a glTF sampler's wrap value.
    pub fn from_gltf(w: gltf::texture::WrappingMode) -> Wrap {
        match w {
            gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
            gltf::texture::WrappingMode::ClampToEdge => Wrap::ClampToEdge,
            gltf::texture::WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        }
    }

    /// The glTF enum value (10497, 33071 or 33648).
    pub fn gltf_code(self) -> u32 {
        match self {
            Wrap::Repeat => 10497,
            Wrap::ClampToEdge => 33071,
            Wrap::MirroredRepeat => 33648,
        }
    }

    /// The texel index (in `0..n`, `n > 0`) that integer texel coordinate `i` maps to.
    #[inline(always)]
    pub fn apply(self, i: i32, n: i32) -> i32 {
        match self {
            // A mask for a power of two (most textures; a tiled floor's coordinates are mostly
            // outside the image, so the sampler comes here at every texel).
            Wrap::Repeat if n & (n - 1) == 0 => i & (n - 1),
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::ClampToEdge => i.clamp(0, n - 1),
            Wrap::MirroredRepeat => {
                let k = i.rem_euclid(2 * n);
                if k >= n { 2 * n - 1 - k } else { k }
            }
        }
    }
}

/// One base-colour texture: an image in sRGB encoding and how it wraps. Texture coordinates
/// follow glTF: (0, 0) is the top-left corner of the image, u grows to the right, v downwards;
/// texel centres lie at half-integer multiples of `1 / width` and `1 / height`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Texture {
    /// Where the image came from, for messages (a file name, or "image N" of a glTF file).
    pub name: String,
    /// Width (texels, > 0).
    pub width: u32,
    /// Height (texels, > 0).
    pub height: u32,
    /// Texels as RGBA bytes in sRGB encoding (alpha linear, unused: materials are opaque),
    /// row-major, top row first; `width * height * 4` bytes. Shared: a copy of the texture
    /// (of a scene, or a renderer's finest mip level) copies no texels.
    pub rgba: Arc<Vec<u8>>,
    /// Wrap mode along u (glTF `wrapS`, default repeat).
    pub wrap_s: Wrap,
    /// Wrap mode along v (glTF `wrapT`, default repeat).
    pub wrap_t: Wrap,
}

impl Texture {
    /// Decodes an encoded image (PNG or JPEG, format guessed from its first bytes) into
    /// RGBA8; the error says why in words.
    pub fn decode(name: &str, bytes: &[u8], wrap_s: Wrap, wrap_t: Wrap) -> Result<Texture, String> {
        let img = image::load_from_memory(bytes).map_err(|e| format!("cannot decode the image: {e}"))?;
        let rgba = img.to_rgba8();
        let (width, height) = rgba.dimensions();
        if width == 0 || height == 0 {
            return Err(format!("the image is empty ({width}x{height})"));
        }
        Ok(Texture { name: name.to_string(), width, height, rgba: Arc::new(rgba.into_raw()), wrap_s, wrap_t })
    }

    /// The RGBA bytes of texel (`x`, `y`) (column, row from the top), both in range.
    #[inline(always)]
    pub fn texel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = (y as usize * self.width as usize + x as usize) * 4;
        [self.rgba[i], self.rgba[i + 1], self.rgba[i + 2], self.rgba[i + 3]]
    }

    /// True when the sizes agree with the texel data.
    pub fn is_consistent(&self) -> bool {
        self.width > 0 && self.height > 0 && self.rgba.len() == self.width as usize * self.height as usize * 4
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_modes_map_texel_indices() {
        let n = 4;
        let idx = |w: Wrap| (-5..9).map(|i| w.apply(i, n)).collect::<Vec<_>>();
        assert_eq!(idx(Wrap::Repeat), [3, 0, 1, 2, 3, 0, 1, 2, 3, 0, 1, 2, 3, 0]);
        assert_eq!(idx(Wrap::ClampToEdge), [0, 0, 0, 0, 0, 0, 1, 2, 3, 3, 3, 3, 3, 3]);
        assert_eq!(idx(Wrap::MirroredRepeat), [3, 3, 2, 1, 0, 0, 1, 2, 3, 3, 2, 1, 0, 0]);
    }

    #[test]
    fn undecodable_bytes_are_an_error_not_a_panic() {
        let e = Texture::decode("x.png", b"not an image", Wrap::Repeat, Wrap::Repeat).unwrap_err();
        assert!(e.contains("cannot decode"), "{e}");
    }
}
