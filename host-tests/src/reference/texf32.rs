//! The f32 implementation of the firmware's texture filters used by the
//! fixed-vs-float bench and tests: it lives in the firmware crate
//! (`raymip::baseline_f32`, feature `f32`) so the bare-metal budgets count the same
//! code on Cortex-M4F and RV32IMAC.

pub use raymip::baseline_f32::SamplerF32;
