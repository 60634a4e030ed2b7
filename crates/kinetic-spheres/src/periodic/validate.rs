//! Checking the structure against its invariants (for tests; quadratic in the spheres).

use super::predict::pair_due;
use super::{Kind, PeriodicSpheres};
use kinetic_core::Real;

impl PeriodicSpheres {
    /// Checks the invariants: lists are symmetric; every sphere is
    /// within its shell; every unlisted pair's centres are beyond the list reach (nearest
    /// image), so it cannot touch; every listed pair is covered (see
    /// [`PeriodicSpheres::validate_cover`]); every scheduled event is not before now and is the
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
        }
        for i in 0..n {
            for k in i + 1..n {
                let d = self.centre[i].at - self.centre[k].at;
                let side = self.period.side;
                let d = d - (d / side).round() * side;
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
