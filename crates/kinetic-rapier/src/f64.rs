//! The broad phase for rapier3d-f64 0.27 (feature `f64`).

use rapier3d_f64 as rapier;

include!("adapter.rs");
