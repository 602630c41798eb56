//! Set-up: what a camera and a scene fix before the first ray, computed
//! once so that each hit reads a table entry instead of deriving it.
//!
//! * [`camera`]: the camera's pixel spread angle `γ` and its `log2`.
//! * [`table`]: one `log2 Pb` per textured triangle (the table method's
//!   per-triangle constant) and the ray-cone constant `Δ` derived from it.
//!
//! Which MIP levels a scene can select per texture (it needs the lod and
//! the filter modes, so it sits above them) is
//! [`texture::storage::analysis`](crate::texture::storage::analysis).

pub mod camera;
pub mod table;
