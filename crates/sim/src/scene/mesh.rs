//! The scene's geometry: named meshes of triangles in the world frame, with their materials
//! (a base colour factor and optionally a texture from the scene's table).

use super::Texture;
use serde::{Deserialize, Serialize};

/// An axis-aligned box in the world frame (m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Aabb {
    /// Minimum corner (m).
    pub min: [f32; 3],
    /// Maximum corner (m).
    pub max: [f32; 3],
}

impl Aabb {
    /// The empty box (min = +inf, max = -inf).
    pub fn empty() -> Self {
        Self { min: [f32::INFINITY; 3], max: [f32::NEG_INFINITY; 3] }
    }
    /// Grows the box to contain `p`.
    pub fn grow(&mut self, p: [f32; 3]) {
        for i in 0..3 {
            self.min[i] = self.min[i].min(p[i]);
            self.max[i] = self.max[i].max(p[i]);
        }
    }
    /// True when the box contains nothing.
    pub fn is_empty(&self) -> bool {
        (0..3).any(|i| self.min[i] > self.max[i])
    }
}

/// One mesh: triangles with a name (from the file's node/mesh), a base colour and optionally a
/// base-colour texture with per-vertex texture coordinates.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mesh {
    /// Node or mesh name as in the file ("" when unnamed).
    pub name: String,
    /// Vertex positions in the world frame (m, z up).
    pub positions: Vec<[f32; 3]>,
    /// Triangles as indices into `positions`, counter-clockwise seen from outside.
    pub indices: Vec<[u32; 3]>,
    /// Base colour, linear RGBA in [0, 1] (glTF baseColorFactor; grey when unknown); it
    /// multiplies the texture's (decoded) colour.
    pub base_color: [f32; 4],
    /// Texture coordinates of each vertex (glTF convention: (0, 0) top-left of the image, v
    /// down); empty when the mesh has none, else as long as `positions`.
    #[serde(default)]
    pub uvs: Vec<[f32; 2]>,
    /// Base-colour texture: an index into [`Scene::textures`]; used only when `uvs` is set.
    #[serde(default)]
    pub texture: Option<u32>,
}

impl Mesh {
    /// An untextured mesh.
    pub fn new(name: &str, positions: Vec<[f32; 3]>, indices: Vec<[u32; 3]>, base_color: [f32; 4]) -> Mesh {
        Mesh { name: name.to_string(), positions, indices, base_color, uvs: Vec::new(), texture: None }
    }
    /// The corners of triangle `t` (m).
    pub fn triangle(&self, t: usize) -> [[f32; 3]; 3] {
        let [a, b, c] = self.indices[t];
        [self.positions[a as usize], self.positions[b as usize], self.positions[c as usize]]
    }
}

/// A static scene: meshes in the world frame (REP-103, z up, metres) and the textures they use.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Scene {
    /// The meshes.
    pub meshes: Vec<Mesh>,
    /// Base-colour textures, each stored once and referred to by [`Mesh::texture`].
    #[serde(default)]
    pub textures: Vec<Texture>,
}

impl Scene {
    /// The texture mesh `m` is drawn with: its texture when it has one (in range, with
    /// consistent texels) and texture coordinates for every vertex; else `None` (the factor alone).
    pub fn texture_of(&self, m: &Mesh) -> Option<&Texture> {
        let t = self.textures.get(m.texture? as usize)?;
        (t.is_consistent() && !m.uvs.is_empty() && m.uvs.len() == m.positions.len()).then_some(t)
    }
    /// Number of triangles over all meshes.
    pub fn triangle_count(&self) -> usize {
        self.meshes.iter().map(|m| m.indices.len()).sum()
    }
    /// Bounding box of all vertices that triangles use (empty box for an empty scene).
    pub fn bounds(&self) -> Aabb {
        let mut b = Aabb::empty();
        for t in self.triangles() {
            for p in t {
                b.grow(p);
            }
        }
        b
    }
    /// Every triangle of the scene, as three corners (m).
    pub fn triangles(&self) -> impl Iterator<Item = [[f32; 3]; 3]> + '_ {
        self.meshes.iter().flat_map(|m| (0..m.indices.len()).map(move |t| m.triangle(t)))
    }
    /// The triangles in chunks of at most `n` (each within one mesh), in scene order: (mesh
    /// index, triangle indices), to share work between threads and join it back in order.
    pub fn triangle_chunks(&self, n: usize) -> Vec<(usize, std::ops::Range<usize>)> {
        let n = n.max(1);
        self.meshes
            .iter()
            .enumerate()
            .flat_map(|(m, mesh)| {
                let len = mesh.indices.len();
                (0..len.div_ceil(n)).map(move |k| (m, k * n..((k + 1) * n).min(len)))
            })
            .collect()
    }
    /// Adds an axis-aligned box from `min` to `max` (m) as a closed mesh of 12 triangles.
    pub fn add_box(&mut self, name: &str, min: [f32; 3], max: [f32; 3], color: [f32; 4]) {
        let [x0, y0, z0] = min;
        let [x1, y1, z1] = max;
        let positions = vec![
            [x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
            [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1],
        ];
        let indices = vec![
            [0, 2, 1], [0, 3, 2], // bottom (-z)
            [4, 5, 6], [4, 6, 7], // top (+z)
            [0, 1, 5], [0, 5, 4], // -y
            [2, 3, 7], [2, 7, 6], // +y
            [1, 2, 6], [1, 6, 5], // +x
            [3, 0, 4], [3, 4, 7], // -x
        ];
        self.meshes.push(Mesh::new(name, positions, indices, color));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_has_outward_normals() {
        let mut s = Scene::default();
        s.add_box("b", [0.0, 0.0, 0.0], [1.0, 2.0, 3.0], [1.0; 4]);
        assert_eq!(s.triangle_count(), 12);
        let c = [0.5f32, 1.0, 1.5];
        for [a, b, d] in s.triangles() {
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [d[0] - a[0], d[1] - a[1], d[2] - a[2]];
            let n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
            let out = [a[0] - c[0], a[1] - c[1], a[2] - c[2]];
            assert!(n[0] * out[0] + n[1] * out[1] + n[2] * out[2] > 0.0);
        }
        let b = s.bounds();
        assert_eq!(b.min, [0.0, 0.0, 0.0]);
        assert_eq!(b.max, [1.0, 2.0, 3.0]);
    }
}
