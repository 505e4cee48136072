//! The bounding volume hierarchy rays are traced through: obvhs builds a binary tree, which is
//! collapsed into a 4-wide one ([`wide`]) and walked four boxes at a time ([`traverse`]).
//! Meshes keep one per mesh in object space, with their triangles packed four to a leaf
//! ([`crate::geometry::triangle4`]); the world keeps one over its instances per frame. See
//! `docs/geometry.md`.

pub mod traverse;
pub mod wide;

pub use traverse::BoxRay;
pub use wide::Bvh4;
