//! Checking the structure against its invariants (for tests; quadratic in the spheres).

use super::predict::pair_due;
use super::{Kind, ListedSpheres};
use kinetic_core::Real;

impl ListedSpheres {
    /// Checks the invariants: lists are symmetric; every sphere is
    /// within its shell; every unlisted pair's centres are beyond the list reach (nearest
    /// image), so it cannot touch; every listed pair is covered (see
    /// [`ListedSpheres::validate_cover`]); every scheduled event is not before now and is the
    /// one the queue holds; the queue is ordered.
    pub fn validate(&self) -> Result<(), String> {
        self.queue.validate()?;
        self.validate_cover()?;
        self.grid.validate()?;
        let n = self.len();
        for i in 0..n as u32 {
            for &k in self.lists.of(i) {
                if !self.lists.of(k).contains(&i) {
                    return Err(format!("periodic: list of {i} holds {k} but not back"));
                }
            }
            let m = &self.motion[i as usize];
            let c = self.centre[i as usize];
            let from_centre = (m.at(self.now) - c.at).length();
            if from_centre > c.shell * (1.0 + 1e-9) + 1e-12 {
                return Err(format!(
                    "periodic: sphere {i} is {from_centre} from its list centre, beyond its shell {}",
                    c.shell
                ));
            }
            if let Some((time, _, next)) = self.queue.get(i)
                && next.kind != Kind::Idle
                && time < self.now
            {
                return Err(format!("periodic: sphere {i}'s event is in the past"));
            }
            if let Some(walls) = self.walls {
                let at = m.at(self.now);
                let slack = 1e-9 * (walls.max - walls.min).max_element();
                if (at - m.radius + slack).cmplt(walls.min).any()
                    || (at + m.radius - slack).cmpgt(walls.max).any()
                {
                    return Err(format!("walls: sphere {i} at {at:?} is through a wall"));
                }
                if self.wall[i as usize] != self.wall_kept(i) {
                    return Err(format!(
                        "walls: sphere {i}'s wall certificate is not its plan's"
                    ));
                }
                // A sphere far from the walls reaches its shell first.
                if self.wall[i as usize].is_none()
                    && let Some(hit) = self.wall_of(i)
                    && hit.time.max(self.now) < self.queue.get(i).map_or(Real::INFINITY, |e| e.0)
                {
                    return Err(format!(
                        "walls: sphere {i} reaches a wall at {} before its event, unwatched",
                        hit.time
                    ));
                }
                let event = self.queue.get(i).map_or(Real::INFINITY, |e| e.0);
                if let Some(hit) = self.wall[i as usize]
                    && event > hit.time.max(self.now)
                {
                    return Err(format!(
                        "walls: sphere {i} reaches a wall at {} before its event at {event}",
                        hit.time
                    ));
                }
            }
        }
        for i in 0..n {
            for k in i + 1..n {
                let (d, _) = self.period.apart(self.centre[i].at - self.centre[k].at);
                let reach = (self.motion[i].radius + self.motion[k].radius) * self.list_factor;
                let listed = self.lists.of(i as u32).contains(&(k as u32));
                if !listed && d.length() < reach * (1.0 - 1e-12) {
                    return Err(format!(
                        "periodic: spheres {i} and {k} are {} apart at their centres, within the reach {reach}, and not listed",
                        d.length()
                    ));
                }
            }
        }
        Ok(())
    }

    /// Checks that every listed pair is covered: one of its two spheres has an event not
    /// after the pair's failure (linear in the listed pairs).
    pub fn validate_cover(&self) -> Result<(), String> {
        let at = |s: u32| self.queue.get(s).map_or(Real::INFINITY, |e| e.0);
        for i in 0..self.len() as u32 {
            let m = &self.motion[i as usize];
            for &k in self.lists.of(i) {
                let mk = &self.motion[k as usize];
                let (d, shift) = self.period.apart(m.at(self.now) - mk.at(self.now));
                let skip = self.skip_of(i, k);
                if let Some((t, _)) = pair_due(m, mk, shift, d, self.now, skip, Real::INFINITY)
                    && t < at(i).min(at(k))
                {
                    return Err(format!(
                        "periodic: spheres {i} and {k} fail at {t}, before either's event ({} and {})",
                        at(i),
                        at(k)
                    ));
                }
            }
        }
        Ok(())
    }
}
