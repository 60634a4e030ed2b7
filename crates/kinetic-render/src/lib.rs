//! # kinetic-render
//!
//! A headless wgpu 30 renderer: a [`Snapshot`] of a scene (balls, cuboids, convex hulls, a
//! plane patch, overlay lines) becomes a [`Frame`] of RGBA pixels, saved as PNG. It runs with
//! no GPU at all, on Mesa's software rasterisers (lavapipe through Vulkan, llvmpipe through
//! GL), and on real GPUs ([`AdapterChoice::Gpu`]).
//!
//! Objects are instanced meshes, lit by a key light and a sky fill, drawn with depth and
//! 4x multisampling; the [`Camera`] frames the whole snapshot by default.
//!
//! ```no_run
//! use glam::Vec3;
//! use kinetic_render::{AdapterChoice, Camera, Instance, Renderer, Snapshot};
//!
//! let mut snapshot = Snapshot::new(Vec3::Z);
//! snapshot.instances.push(Instance::ball(Vec3::ZERO, 1.0, [0.8, 0.3, 0.1, 1.0]));
//! let mut renderer = Renderer::new(640, 480, AdapterChoice::Software)?;
//! let frame = renderer.render(&snapshot, &Camera::framing(&snapshot, 640.0 / 480.0))?;
//! frame.save_png("ball.png".as_ref())?;
//! # Ok::<(), kinetic_render::RenderError>(())
//! ```
#![warn(missing_docs)]
#![forbid(unsafe_code)]

mod camera;
mod frame;
mod gpu;
mod mesh;
mod snapshot;

pub use camera::Camera;
pub use frame::{Difference, Frame};
/// The f32 vector crate of the renderer's types ([`Instance`], [`Camera`]).
pub use glam;
pub use gpu::{AdapterChoice, Renderer};
pub use snapshot::{HullMesh, Instance, Line, MeshKind, Snapshot};

/// What can go wrong while rendering.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// No adapter at all: the machine has neither a GPU driver nor Mesa's software ones.
    #[error(
        "no graphics adapter ({detail}); install Mesa's software drivers \
         (Debian/Ubuntu: apt-get install mesa-vulkan-drivers libegl1 libgl1-mesa-dri) or a GPU driver"
    )]
    NoAdapter {
        /// What wgpu said.
        detail: String,
    },
    /// The adapter would not give a device, or the device failed.
    #[error("graphics device: {0}")]
    Device(String),
    /// A picture size of zero or over the adapter's limit.
    #[error("picture size {width}x{height}: each side must be 1 to {max} pixels")]
    Size {
        /// Asked width.
        width: u32,
        /// Asked height.
        height: u32,
        /// The adapter's largest texture side.
        max: u32,
    },
    /// The snapshot refers to something it does not have.
    #[error("snapshot: {0}")]
    Snapshot(String),
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// A PNG could not be encoded or decoded.
    #[error("{path}: PNG: {detail}")]
    Png {
        /// The file.
        path: String,
        /// Why.
        detail: String,
    },
}
