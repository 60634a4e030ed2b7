//! The range of magnitudes the tool computes exactly. Certificates are polynomials in time
//! whose coefficients are products of positions, speeds, accelerations and sizes, and whose
//! values are squared distances: while every object stays within [`MAX_REACH`] of the origin
//! over the horizon, none of them overflows, and every contact time is exact. A scene that
//! reaches further is refused, never run into a silently wrong log.

use super::{Result, Scene, SceneError, outer_radius};
use kinetic_core::Response;

/// How far from the origin an object may get over the horizon, shape included: the square
/// root of the largest finite number, less a margin for the sums and products of the
/// certificates' arithmetic.
pub const MAX_REACH: f64 = 1e150;

impl Scene {
    /// Refuses a scene whose objects reach beyond [`MAX_REACH`] within the horizon. Inside
    /// elastic walls an object reaches no further than the walls; elsewhere it reaches its
    /// position plus its travel at its speed (the fastest any elastic exchange can make it,
    /// from the scene's kinetic energy) and acceleration, plus its size.
    pub(crate) fn check_range(&self) -> Result<()> {
        let h = self.horizon;
        let elastic = self.response == Response::Elastic;
        // The fastest an elastic exchange can make a ball: all the energy in the lightest.
        let fastest = if elastic {
            let (energy, lightest) =
                self.objects
                    .iter()
                    .fold((0.0f64, f64::INFINITY), |(e, m), o| {
                        let mass = outer_radius(&o.shape).powi(3);
                        (e + mass * o.velocity.length_squared(), m.min(mass))
                    });
            (energy / lightest).sqrt()
        } else {
            0.0
        };
        let walls = self
            .walls
            .filter(|_| elastic)
            .map(|w| w.min.abs().max(w.max.abs()).max_element());
        if let Some(w) = walls.filter(|&w| w > MAX_REACH) {
            return Err(SceneError::new(
                "walls",
                format!(
                    "reach {w:e} from the origin, beyond the {MAX_REACH:e} this tool computes exactly"
                ),
            ));
        }
        for (i, o) in self.objects.iter().enumerate() {
            let size = outer_radius(&o.shape);
            let speed = o.velocity.length().max(fastest);
            let reach = match walls {
                Some(w) => w + size,
                None => {
                    o.position.length() + speed * h + o.acceleration.length() * h * h * 0.5 + size
                }
            };
            if !reach.is_finite() || reach > MAX_REACH {
                return Err(SceneError::new(
                    format!("objects[{i}]"),
                    format!(
                        "reaches {reach:e} from the origin within the horizon (position, speed \
                         times horizon, acceleration, size), beyond the {MAX_REACH:e} this tool \
                         computes exactly"
                    ),
                ));
            }
        }
        Ok(())
    }
}
