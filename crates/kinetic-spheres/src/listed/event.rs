//! Processing events: collisions (the elastic exchange through the pair's image), stale
//! events, shell crossings, wall contacts.

use super::{Kind, ListedSpheres, Motion, Period, Scheduled};
use crate::bulk::mass;
use kinetic_core::FlightPlan;
use kinetic_core::elastic::{Exchange, bounced};
use kinetic_core::prefetch;
use kinetic_core::{ContactEvent, ContactKind, ObjectId, WorldError};
use kinetic_core::{Real, Vec3};

/// Event kinds by index in `event_counts`, as the statistics name them.
pub(super) const EVENT_NAMES: [&str; 5] = ["collision", "stale", "shell", "graze", "bounce"];

/// The elastic exchange of two spheres touching at `now` through the image `shift`: their new
/// velocities and the virial term `r_ab . dp_a` (mass `(2 r)^3`), or `None` when they are not
/// approaching. With no shift, the world's exchange, bit for bit.
#[inline]
pub(super) fn exchange(
    ma: &Motion,
    mb: &Motion,
    shift: Vec3,
    now: Real,
) -> Option<(Vec3, Vec3, Real)> {
    let d = (ma.at(now) - mb.at(now)) - shift;
    let e = Exchange::of(d, ma.velocity, mb.velocity, ma.radius, mb.radius)?;
    Some((e.va, e.vb, mass(ma.radius) * e.dv_a * e.distance))
}

/// `p` wrapped into the box, and the whole periods taken off it.
#[inline]
pub(super) fn wrapped(period: &Period, p: Vec3) -> (Vec3, Vec3) {
    let outside = period.outside(p);
    if outside == Vec3::ZERO {
        (p, outside)
    } else {
        (p - outside, outside)
    }
}

impl ListedSpheres {
    /// Processes the next event if it is due by `until`; returns whether one was.
    pub fn step(&mut self, until: Real) -> Result<bool, WorldError> {
        let Some((id, time, next)) = self.queue.peek() else {
            return Ok(false);
        };
        if time > until || time.is_nan() {
            return Ok(false);
        }
        // The spheres of the events likely to come next are fetched while this one is done.
        for (other_id, other_next) in self.queue.following() {
            self.prefetch_event(other_id, &other_next);
        }
        if time > self.now {
            self.now = time;
        }
        let i = id as usize;
        let mut partner = id;
        match next.kind {
            Kind::Idle => {
                self.queue.remove(id);
                self.event_counts[1] += 1;
            }
            Kind::Pair => {
                partner = next.other;
                if self.counter[next.other as usize] != next.counter {
                    self.event_counts[1] += 1;
                    if !self.take_spare(id) {
                        self.predict(id);
                    }
                } else {
                    self.fire(id, next.other, next.graze);
                }
            }
            Kind::Shell => {
                self.event_counts[2] += 1;
                self.relist(id);
                if self.walls.is_some() {
                    self.wall[i] = self.wall_kept(id);
                }
                self.predict(id);
            }
            Kind::Wall => {
                self.event_counts[4] += 1;
                self.bounce(id);
                self.predict(id);
            }
        }
        self.stats.samples += 1;
        let c = self.lists.total() / 2 + self.len();
        self.stats.certificates_sum += c as f64;
        self.stats.certificates_max = self.stats.certificates_max.max(c);
        let (a, b) = (self.ext[i], self.ext[partner as usize]);
        self.zeno.count(self.now, self.len(), a, b)?;
        Ok(true)
    }

    /// A pair certificate fails: report the contact and respond. Spheres whose plans do not
    /// change (a graze, or spheres that are not approaching) skip that event of the pair.
    fn fire(&mut self, a: u32, b: u32, graze: bool) {
        // Both spheres predict again below: their neighbours are fetched together first.
        self.prefetch_neighbours(a);
        self.prefetch_neighbours(b);
        let (ea, eb) = (self.ext[a as usize], self.ext[b as usize]);
        self.stats.begins += 1;
        self.events.push(ContactEvent {
            time: self.now,
            a: ObjectId(ea.min(eb)),
            b: ObjectId(ea.max(eb)),
            kind: ContactKind::Begin,
        });
        let (ma, mb) = (self.motion[a as usize], self.motion[b as usize]);
        let now = self.now;
        let shift = self.period.nearest(ma.at(now) - mb.at(now));
        if !graze && let Some((va, vb, virial)) = exchange(&ma, &mb, shift, now) {
            self.event_counts[0] += 1;
            self.sums.collisions += 1;
            self.sums.virial += virial;
            self.replan(a, va);
            self.replan(b, vb);
            self.predict(a);
            self.predict(b);
            return;
        }
        self.event_counts[3] += 1;
        let (ca, cb) = (self.counter[a as usize], self.counter[b as usize]);
        self.skips.entry(a).or_default().push((b, cb, now));
        self.skips.entry(b).or_default().push((a, ca, now));
        self.predict(a);
        self.predict(b);
    }

    /// Asks for what processing `id`'s event `next` reads first: its sphere's motion, list
    /// centre, shell, list and queue entry, and for a pair the partner's.
    #[inline]
    fn prefetch_event(&self, id: u32, next: &Scheduled) {
        let i = id as usize;
        prefetch(&self.motion[i]);
        prefetch(&self.centre[i]);
        self.lists.prefetch(id);
        self.queue.prefetch(id);
        if next.kind == Kind::Pair {
            let other = next.other as usize;
            prefetch(&self.spares[i]);
            prefetch(&self.counter[other]);
            prefetch(&self.motion[other]);
            prefetch(&self.centre[other]);
            self.lists.prefetch(next.other);
            self.queue.prefetch(next.other);
        }
    }

    /// Asks for the motions of `id`'s neighbours.
    #[inline]
    fn prefetch_neighbours(&self, id: u32) {
        for &k in self.lists.of(id) {
            prefetch(&self.motion[k as usize]);
        }
    }

    /// Sphere `id` reaches the wall of its wall certificate: its velocity across the wall is
    /// reversed as the world's bounce reverses it, and the wall's impulse is counted.
    fn bounce(&mut self, id: u32) {
        let i = id as usize;
        let Some(hit) = self.wall[i] else {
            return;
        };
        let m = self.motion[i];
        let plan = FlightPlan::linear(m.position, m.velocity).starting_at(m.t0);
        let velocity = bounced(&plan, hit, self.now).velocity;
        self.stats.bounces += 1;
        self.sums.wall_impulse +=
            mass(m.radius) * (velocity[hit.axis] - m.velocity[hit.axis]).abs();
        self.replan(id, velocity);
    }

    /// Sphere `id` moves on from now at `velocity`: its old predictions are stale. A start
    /// outside the box is wrapped into it, and the list centre with it; inside walls, its
    /// wall certificate is made afresh.
    fn replan(&mut self, id: u32, velocity: Vec3) {
        let i = id as usize;
        let m = &mut self.motion[i];
        let (position, outside) = wrapped(&self.period, m.at(self.now));
        m.position = position;
        m.t0 = self.now;
        m.velocity = velocity;
        if outside != Vec3::ZERO {
            self.centre[i].at -= outside;
        }
        self.counter[i] = self.counter[i].wrapping_add(1);
        if !self.skips.is_empty() {
            self.skips.remove(&id);
        }
        if self.walls.is_some() {
            self.wall[i] = self.wall_kept(id);
        }
    }
}
