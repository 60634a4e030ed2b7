//! Checking the structure against its invariants (for tests; quadratic in the spheres).

use super::{Kind, PeriodicSpheres};

impl PeriodicSpheres {
    /// Checks the invariants: lists are symmetric; every sphere is
    /// within its shell; every unlisted pair's centres are beyond the list reach (nearest
    /// image), so it cannot touch; every scheduled event is not before now and is the one the
    /// queue holds; the queue is ordered.
    pub fn validate(&self) -> Result<(), String> {
        self.queue.validate()?;
        let n = self.len();
        for i in 0..n as u32 {
            for &k in self.lists.of(i) {
                if !self.lists.of(k).contains(&i) {
                    return Err(format!("periodic: list of {i} holds {k} but not back"));
                }
            }
            let m = &self.motion[i as usize];
            let from_centre = (m.at(self.now) - self.centre[i as usize]).length();
            if from_centre > self.shell[i as usize] * (1.0 + 1e-9) + 1e-12 {
                return Err(format!(
                    "periodic: sphere {i} is {from_centre} from its list centre, beyond its shell {}",
                    self.shell[i as usize]
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
                let d = self.centre[i] - self.centre[k];
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
}
