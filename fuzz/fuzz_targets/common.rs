//! Input helpers shared by the fuzz targets (`mod common;` in each).

use libfuzzer_sys::arbitrary::{Result, Unstructured};

/// Pyramid sides and level count: sides in `1 ..= small` mostly (generation
/// is O(texels)), any `u32` sometimes; any level count.
pub fn pyramid_shape(u: &mut Unstructured, small: u32) -> Result<(u32, u32, u8)> {
    let (w, h) = if u.ratio(7, 8)? {
        (u.int_in_range(1..=small)?, u.int_in_range(1..=small)?)
    } else {
        (u.arbitrary()?, u.arbitrary()?)
    };
    Ok((w, h, u.arbitrary()?))
}
