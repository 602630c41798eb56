//! Path state: what texture LOD carries along a ray path across bounces.
//!
//! * [`raystack`]: the fixed-capacity ray stack of path states (path length
//!   `Pl`, cone width and spread, ray mask, depth).
//! * `raydiff` (feature `raydiff`): fixed-point ray differentials carried by
//!   every path state, transferred, reflected and refracted at each hit.

#[cfg(feature = "raydiff")]
pub mod raydiff;
pub mod raystack;
