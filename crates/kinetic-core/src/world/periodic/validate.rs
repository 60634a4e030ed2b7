//! Checking the structure against its invariants (for tests; quadratic in the spheres).

use super::{Kind, PeriodicSpheres};

impl PeriodicSpheres {
    /// Checks the invariants: lists are symmetric with opposite shifts; every sphere is
    /// within its shell; every unlisted pair's centres are beyond the list reach (nearest
    /// image), so it cannot touch; every scheduled event is not before now and is the one the
    /// queue holds; the queue is ordered.
    pub fn validate(&self) -> Result<(), String> {
        self.queue.validate()?;
        let n = self.len();
        for i in 0..n as u32 {
            for nb in self.lists.of(i) {
                let back = [-nb.shift[0], -nb.shift[1], -nb.shift[2]];
                if !self
                    .lists
                    .of(nb.id)
                    .iter()
                    .any(|m| m.id == i && m.shift == back)
                {
                    return Err(format!(
                        "periodic: list of {i} holds {} but not back",
                        nb.id
                    ));
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
            let next = &self.next[i as usize];
            if next.kind != Kind::Idle {
                if next.time < self.now {
                    return Err(format!("periodic: sphere {i}'s event is in the past"));
                }
                if self.queue.time_of(i) != Some(next.time) {
                    return Err(format!("periodic: sphere {i}'s event is not the queue's"));
                }
            }
        }
        for i in 0..n {
            for k in i + 1..n {
                let d = self.centre[i] - self.centre[k];
                let d = d - (d * self.inv_side).round() * self.side;
                let reach = (self.motion[i].radius + self.motion[k].radius) * self.list_factor;
                let listed = self.lists.of(i as u32).iter().any(|m| m.id == k as u32);
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
