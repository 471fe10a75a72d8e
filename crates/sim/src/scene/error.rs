//! Errors of scene loading: each names the file and what is wrong with it.

use std::path::PathBuf;

/// Why a scene could not be loaded or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SceneError {
    /// The file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// The file extension names no format we read (glb, gltf, obj, ply).
    #[error("{path}: unknown scene format (expected .glb, .gltf, .obj or .ply)")]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// The file is malformed: truncated, bad header, bad index, etc.
    #[error("{path}: {reason}")]
    Malformed {
        /// The file.
        path: PathBuf,
        /// What is wrong, in words.
        reason: String,
    },
    /// A vertex has a NaN or infinite coordinate.
    #[error("{path}: mesh '{mesh}' has a non-finite vertex coordinate at vertex {vertex}")]
    NonFinite {
        /// The file.
        path: PathBuf,
        /// Name of the mesh.
        mesh: String,
        /// Index of the vertex.
        vertex: usize,
    },
    /// A mesh's base-colour texture cannot be read: its image file is missing, its bytes
    /// cannot be decoded (PNG and JPEG are read), or its glTF reference is broken. Fix or
    /// remove the material's texture reference.
    #[error("{path}: mesh '{mesh}': texture {image}: {reason}")]
    Texture {
        /// The scene file.
        path: PathBuf,
        /// Name of the mesh that uses the texture.
        mesh: String,
        /// The image, as the file names it (a path, or "image N").
        image: String,
        /// What is wrong, in words.
        reason: String,
    },
    /// The scene has no triangles left (after dropping ceilings).
    #[error("{path}: the scene has no triangles")]
    Empty {
        /// The file.
        path: PathBuf,
    },
}
