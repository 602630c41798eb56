//! Level of detail per ray hit.

use fixed::types::I8F8;

/// A MIP level of detail in levels: signed, 8 fractional bits
/// (range `[−128, 128)`, step 1/256 level).
pub type Lod = I8F8;
