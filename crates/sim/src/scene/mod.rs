//! Scenes: static triangle geometry in the world frame (REP-103, z up, metres).
//!
//! Loaders convert from each format's frame once, here at the boundary: glTF/GLB (y up,
//! node transforms applied), OBJ and PLY (up axis is a load option), and the seeded
//! procedural house that is the built-in default scene. Base-colour textures (glTF
//! `baseColorTexture`, OBJ `map_Kd`) are decoded once into [`Scene::textures`].

mod error;
mod mesh;
mod texture;

pub use error::SceneError;
pub use mesh::{Aabb, Mesh, Scene};
pub use texture::{Texture, Wrap};

use serde::{Deserialize, Serialize};

/// Which axis of a file points up.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum UpAxis {
    /// y up (glTF, Habitat, most OBJ exports); `(x, y, z)` becomes `(x, -z, y)`.
    #[default]
    Y,
    /// z up (ROS, Gazebo, Matterport PLY); coordinates are kept.
    Z,
}

impl UpAxis {
    /// Converts a file point to the world frame.
    pub fn to_world(self, p: [f32; 3]) -> [f32; 3] {
        match self {
            UpAxis::Y => [p[0], -p[2], p[1]],
            UpAxis::Z => p,
        }
    }
}

/// Options for loading a scene file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LoadOptions {
    /// Up axis of OBJ and PLY files (glTF is always y up). Default y.
    pub up_axis: UpAxis,
    /// Drop meshes whose node or mesh name contains "ceiling" (case-insensitive). Default true.
    pub drop_ceilings: bool,
    /// Read and decode the base-colour textures. Default true; without them (for maps,
    /// geodesics, episodes and depth, which never read a colour) every mesh keeps its base
    /// colour factor alone, and a textured scene loads in a fraction of the time.
    pub textures: bool,
}

impl Default for LoadOptions {
    fn default() -> Self {
        Self { up_axis: UpAxis::Y, drop_ceilings: true, textures: true }
    }
}

mod from_gltf;
mod gltf_check;
mod gltf_texture;
mod from_obj;
mod obj_check;
mod from_ply;
mod ply_check;
pub mod house;
pub mod stair_building;
mod loader;
mod to_glb;

pub use loader::{load, parse, ReadReferenced, SceneFormat};
pub use to_glb::{to_glb_bytes, write_glb};
