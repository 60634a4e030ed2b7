//! The broad phase for rapier3d 0.27 (f32; feature `f32`, the default).

use rapier3d as rapier;

include!("adapter.rs");
