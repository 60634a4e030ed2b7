//! The numeric types: kinetic math is `f64` throughout (contact times to 1e-7 relative).

/// The scalar type.
pub type Real = f64;
/// A rotation.
pub use glam::DQuat as Quat;
/// A point or vector in 3-space.
pub use glam::DVec3 as Vec3;
