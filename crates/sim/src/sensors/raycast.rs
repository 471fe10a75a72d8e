//! The scene as a parry3d triangle mesh with its BVH, for ray casting (CPU reference path).

use super::mipmap::footprint;
use super::scan_slice::ScanSlice;
use super::surface::{barycentric, SurfaceTri, Surfaces};
use crate::scene::Scene;
use parry3d::math::Vector;
use parry3d::query::{Ray, RayCast};
use parry3d::shape::{TriMesh, TriMeshFlags};
use std::sync::{Arc, Mutex};

/// Planes' slices kept for [`RayScene::slice`] (a building's storeys).
const SLICES_KEPT: usize = 8;

/// The scene's triangles for ray queries, built once and shared (it is `Sync`).
pub struct RayScene {
    mesh: TriMesh,
    /// Texture coordinates and material of each triangle (in the mesh's order).
    surf: Vec<SurfaceTri>,
    /// The scene's materials and textures.
    surfaces: Surfaces,
    /// Horizontal slices cut so far, newest last (see [`RayScene::slice`]).
    slices: Mutex<Vec<Arc<ScanSlice>>>,
}

impl std::fmt::Debug for RayScene {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "RayScene({} triangles)", self.mesh.indices().len())
    }
}

impl RayScene {
    /// Builds the mesh and its BVH; `None` for a scene without triangles.
    pub fn new(scene: &Scene) -> Option<RayScene> {
        let mut vertices = Vec::new();
        let mut indices = Vec::new();
        for m in &scene.meshes {
            let base = vertices.len() as u32;
            vertices.extend(m.positions.iter().map(|p| Vector::new(p[0], p[1], p[2])));
            indices.extend(m.indices.iter().map(|t| [t[0] + base, t[1] + base, t[2] + base]));
        }
        let (surf, surfaces) = (Surfaces::triangles(scene), Surfaces::new(scene));
        TriMesh::with_flags(vertices, indices, TriMeshFlags::empty()).ok().map(|mesh| RayScene { mesh, surf, surfaces, slices: Mutex::new(Vec::new()) })
    }

    /// The scene cut by the horizontal plane at height `z` (m), for planar lidar rays: the
    /// same hits as [`RayScene::cast`] along horizontal rays at that height (parry3d casts at
    /// `z` rounded to `f32`, and so does the cut). Cut once per height and kept.
    pub fn slice(&self, z: f64) -> Arc<ScanSlice> {
        let z = z as f32 as f64;
        let mut kept = self.slices.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(s) = kept.iter().find(|s| s.z == z) {
            return s.clone();
        }
        let vertices: Vec<[f32; 3]> = self.mesh.vertices().iter().map(|v| [v.x, v.y, v.z]).collect();
        let slice = Arc::new(ScanSlice::new(&vertices, self.mesh.indices(), z));
        if kept.len() == SLICES_KEPT {
            kept.remove(0);
        }
        kept.push(slice.clone());
        slice
    }

    /// Distance along `dir` (in units of `dir`'s length) to the first hit from `origin`,
    /// up to `max_t`; both faces count.
    pub fn cast(&self, origin: [f64; 3], dir: [f64; 3], max_t: f64) -> Option<f64> {
        let ray = Ray::new(
            Vector::new(origin[0] as f32, origin[1] as f32, origin[2] as f32),
            Vector::new(dir[0] as f32, dir[1] as f32, dir[2] as f32),
        );
        self.mesh.cast_local_ray(&ray, max_t as f32, false).map(|t| t as f64)
    }

    /// Like [`RayScene::cast`], with the base colour at the hit (sRGB bytes: the material's
    /// factor times its texture, see [`super::surface`], the texture's level of detail from a
    /// pixel of angular size `pixel_angle` (rad)) and the cosine between the ray and the
    /// surface normal (for shading).
    pub fn cast_color(&self, origin: [f64; 3], dir: [f64; 3], max_t: f64, pixel_angle: f64) -> Option<(f64, [u8; 3], f64)> {
        let ray = Ray::new(
            Vector::new(origin[0] as f32, origin[1] as f32, origin[2] as f32),
            Vector::new(dir[0] as f32, dir[1] as f32, dir[2] as f32),
        );
        let hit = self.mesh.cast_local_ray_and_get_normal(&ray, max_t as f32, false)?;
        let l = (dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]).sqrt().max(1e-12);
        let cos = ((hit.normal.x as f64 * dir[0] + hit.normal.y as f64 * dir[1] + hit.normal.z as f64 * dir[2]) / l).abs();
        // The hit's triangle is its sub-shape (its feature is only the triangle's side).
        let t = hit.subshape as usize;
        let color = match self.surf.get(t) {
            Some(st) if t < self.mesh.indices().len() => {
                let tri = self.mesh.triangle(t as u32);
                let v = [tri.a, tri.b, tri.c].map(|p| [p.x, p.y, p.z]);
                let fp = footprint((hit.time_of_impact as f64 * l) as f32, pixel_angle as f32, cos as f32);
                self.surfaces.color(st, || barycentric(&v, origin, dir), fp)
            }
            _ => [160, 160, 160],
        };
        Some((hit.time_of_impact as f64, color, cos))
    }
}
