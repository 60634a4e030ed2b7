//! Scene files (the format is in `docs/scene-format.md`): parsing with errors that name the
//! object and field at fault ([`parse`]), writing ([`write`]), and the range of magnitudes
//! the tool computes exactly ([`range`]).

mod parse;
mod range;
mod write;

pub use range::MAX_REACH;

use glam::{DQuat, DVec3};
use kinetic_core::{FlightPlan, Response, Walls, WorldKind};
use kinetic_spheres::PeriodicBox;

/// The shape of a scene object.
#[derive(Clone, Debug, PartialEq)]
pub enum ShapeSpec {
    /// A ball.
    Ball {
        /// Its radius.
        radius: f64,
    },
    /// A box.
    Cuboid {
        /// Half its size along each axis of its own frame.
        half_extents: DVec3,
    },
    /// The convex hull of points given in the object's own frame.
    ConvexHull {
        /// The points.
        points: Vec<DVec3>,
    },
}

/// One object of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneObject {
    /// Its shape.
    pub shape: ShapeSpec,
    /// Its centre (its frame's origin) at t = 0; in a plane world, the tangency point.
    pub position: DVec3,
    /// Its velocity at t = 0.
    pub velocity: DVec3,
    /// Its constant acceleration.
    pub acceleration: DVec3,
    /// Its orientation at t = 0.
    pub orientation: DQuat,
    /// Its constant spin.
    pub angular_velocity: DVec3,
}

impl SceneObject {
    /// A ball with a linear motion.
    pub fn ball(radius: f64, position: DVec3, velocity: DVec3) -> SceneObject {
        SceneObject {
            shape: ShapeSpec::Ball { radius },
            position,
            velocity,
            acceleration: DVec3::ZERO,
            orientation: DQuat::IDENTITY,
            angular_velocity: DVec3::ZERO,
        }
    }

    /// Its flight plan from t = 0.
    pub fn plan(&self) -> FlightPlan {
        FlightPlan::accelerated(self.position, self.velocity, self.acceleration)
            .with_spin(self.orientation, self.angular_velocity)
    }

    /// The plan of its centre in 3-space: its plan in a free world; in a plane world the
    /// rolling ball's centre, its radius above the tangency point, moving in x and y.
    pub fn centre_plan(&self, world: WorldKind) -> FlightPlan {
        match world {
            WorldKind::Free => self.plan(),
            WorldKind::Plane => FlightPlan::accelerated(
                self.position.with_z(outer_radius(&self.shape)),
                self.velocity.with_z(0.0),
                self.acceleration.with_z(0.0),
            ),
        }
    }
}

/// A scene: a world, a horizon, a response, optional walls or a periodic box, and the
/// objects.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Free flight or rolling on a plane.
    pub world: WorldKind,
    /// The run covers `[0, horizon]`.
    pub horizon: f64,
    /// What happens at contact.
    pub response: Response,
    /// The box that holds the scene, if any.
    pub walls: Option<Walls>,
    /// The box whose faces wrap around (elastic balls moving linearly), if any.
    pub periodic: Option<PeriodicBox>,
    /// The objects; object `i` is named by its index.
    pub objects: Vec<SceneObject>,
}

/// What is wrong with a scene: the field at fault (`objects[3].shape.ball.radius`) and why.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{path}: {message}")]
pub struct SceneError {
    /// Where: a path such as `objects[3].velocity[1]` (empty for the whole document).
    pub path: String,
    /// What is wrong.
    pub message: String,
}

impl SceneError {
    pub(crate) fn new(path: impl Into<String>, message: impl Into<String>) -> SceneError {
        SceneError {
            path: path.into(),
            message: message.into(),
        }
    }

    /// The index of the object at fault, if the error is inside `objects`.
    pub fn object(&self) -> Option<usize> {
        let rest = self.path.strip_prefix("objects[")?;
        rest[..rest.find(']')?].parse().ok()
    }
}

/// A scene, or what is wrong with it.
pub type Result<T> = std::result::Result<T, SceneError>;

impl Scene {
    /// The largest ratio between two objects' outer radii (1 for fewer than two objects).
    pub fn size_ratio(&self) -> f64 {
        radius_spread(self.objects.iter().map(|o| outer_radius(&o.shape)))
    }
}

/// The largest ratio between two of `radii` (those above 0; 1 for fewer than two): the
/// spread of sizes the structure choice weighs, for a scene or a world's objects.
pub(crate) fn radius_spread(radii: impl IntoIterator<Item = f64>) -> f64 {
    let (lo, hi) = radii
        .into_iter()
        .filter(|&r| r > 0.0)
        .fold((f64::INFINITY, 0.0_f64), |(lo, hi), r| {
            (lo.min(r), hi.max(r))
        });
    if hi > 0.0 { hi / lo } else { 1.0 }
}

/// The radius of the ball around the object's origin that holds the shape.
pub fn outer_radius(shape: &ShapeSpec) -> f64 {
    match shape {
        ShapeSpec::Ball { radius } => *radius,
        ShapeSpec::Cuboid { half_extents } => half_extents.length(),
        ShapeSpec::ConvexHull { points } => points.iter().map(|p| p.length()).fold(0.0, f64::max),
    }
}
