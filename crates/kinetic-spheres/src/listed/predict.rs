//! Predicting a sphere's next event: its listed pairs (closed forms, or the world's root
//! walk), its shell crossing and its wall contact, the earliest of which is scheduled.

use super::first_pass::{BATCH, Kept};
use super::runners::Runners;
use super::{Kind, ListedSpheres, Motion, Next, TIE_SHELL, TIE_WALL};
use kinetic_core::FlightPlan;
use kinetic_core::Response;
use kinetic_core::elastic::{Due, Walk};
use kinetic_core::elastic::{WallHit, wall_hit};
use kinetic_core::kds::certificates::ball_ball_gap;
use kinetic_core::kds::pair_key;
use kinetic_core::kds::roots::quadratic_roots;
use kinetic_core::{Real, Vec3};

/// The next failure of the disjointness certificate of spheres `a` and `b` met through the
/// image `shift` (`(x_a - x_b) - shift`), after `now`: its time, and whether it is a graze.
///
/// The gap is taken around the later of the two plans' starts, as the world takes it, so a
/// pair with no shift fails at the world's time, bit for bit. `d_now` is
/// `(x_a - x_b) - shift` now, as [`Motion::at`] gives the positions. `skip` is a time up to
/// which the pair's events were consumed without a change of plans (after a graze). With
/// `bound` finite, a failure that clearly comes after `bound` may be reported as none.
#[inline]
pub(super) fn pair_due(
    ma: &Motion,
    mb: &Motion,
    shift: Vec3,
    d_now: Vec3,
    now: Real,
    skip: Option<Real>,
    bound: Real,
) -> Option<(Real, bool)> {
    // max and min of finite times, without the NaN handling of `f64::max`.
    let later = if ma.t0 > mb.t0 { ma.t0 } else { mb.t0 };
    let base = if later < now { later } else { now };
    let reach = ma.radius + mb.radius;
    let threshold2 = reach * reach;
    let db = if base == now {
        d_now
    } else {
        (ma.at(base) - mb.at(base)) - shift
    };
    let c0 = db.dot(db) - threshold2;
    let v = ma.velocity - mb.velocity;
    let c1 = 2.0 * db.dot(v);
    if c0 <= 0.0 && c1 > 0.0 && base == now {
        // In contact now (just met, within rounding) and moving apart: the gap only grows.
        return None;
    }
    if c0 > 0.0 {
        let gap_now = if base == now {
            c0
        } else {
            d_now.dot(d_now) - threshold2
        };
        if gap_now > 0.0 {
            if c1 >= 0.0 {
                return None;
            }
            // The first root is at least c0 / -c1 after base: a pair that clearly fails after
            // the bound cannot be the sphere's next event.
            let ahead = bound - base;
            if ahead.is_finite() && c0 > -c1 * (ahead * (1.0 + 1e-9) + bound.abs() * 1e-15) {
                return None;
            }
            let c2 = v.dot(v);
            let (p, q) = (4.0 * c2 * c0, c1 * c1);
            if p - q > 1e-6 * (p + q) {
                return None;
            }
            if skip.is_none()
                && let Some(t) = clear_first_contact(c0, c1, c2, base, now)
            {
                return Some((t, false));
            }
        }
    }
    walk_due(ma, mb, shift, threshold2, base, now, skip)
}

/// A clear first contact of the gap `c0 + c1 tau + c2 tau^2` around `base` (`c0 > 0 > c1`):
/// two distinct roots ahead, the first clearly after `now`, taken directly as the walk (and
/// `quadratic_roots`, whose arithmetic this is) would report it; `None` when it is not that
/// clear (a clear miss included: the caller decides by the walk).
#[inline]
fn clear_first_contact(c0: Real, c1: Real, c2: Real, base: Real, now: Real) -> Option<Real> {
    let (p, q) = (4.0 * c2 * c0, c1 * c1);
    // (NaN coefficients fail this test and go to the walk.)
    if q - p <= 1e-6 * (p + q) || (q - p).is_nan() {
        return None;
    }
    // With c0 > 0 > c1 and distinct roots, the first is c0 / q.
    let disc = q - p;
    let half = -0.5 * (c1 - disc.sqrt());
    let first = c0 / half;
    if first > 0.0 && first.is_finite() && half < c2 * Real::MAX && base + first > now {
        debug_assert_eq!(first, {
            let mut roots = [(0.0, false); 4];
            quadratic_roots(c0, c1, c2, &mut roots);
            roots[0].0
        });
        Some(base + first)
    } else {
        None
    }
}

/// The pair's next failure by the world's root walk (contact now, grazes, consumed events).
#[cold]
fn walk_due(
    ma: &Motion,
    mb: &Motion,
    shift: Vec3,
    threshold2: Real,
    base: Real,
    now: Real,
    skip: Option<Real>,
) -> Option<(Real, bool)> {
    // The relative motion as the gap of one ball against a ball at rest at the origin: the
    // same numbers as the world's gap of the two plans when the shift is zero.
    let gap = |t: Real| {
        let rel = [
            (ma.at(t) - mb.at(t)) - shift,
            ma.velocity - mb.velocity,
            Vec3::ZERO,
        ];
        ball_ball_gap(&rel, &[Vec3::ZERO; 3], threshold2)
    };
    let fb = gap(base);
    let f = if base == now { fb } else { gap(now) };
    let mut walk = Walk::elastic(&fb, base, now, &f);
    if let Some(until) = skip {
        while walk.due.is_some_and(|(t, _, _)| t <= until) {
            walk.consume(Response::Elastic);
        }
    }
    walk.due.map(|(t, _, due)| (t, due == Due::Graze))
}

/// How long until a sphere at `position` moving at `velocity` is `radius` from `centre`.
#[inline]
fn shell_exit(position: Vec3, velocity: Vec3, centre: Vec3, radius: Real) -> Real {
    let d = position - centre;
    let a = velocity.dot(velocity);
    if a == 0.0 {
        return Real::INFINITY;
    }
    let c = d.dot(d) - radius * radius;
    if c >= 0.0 {
        return 0.0;
    }
    let b = d.dot(velocity);
    let disc = b * b - a * c;
    // c < 0: one root ahead, written without cancellation.
    let root = disc.sqrt();
    if b > 0.0 {
        -c / (b + root)
    } else {
        (root - b) / a
    }
    .max(0.0)
}

impl ListedSpheres {
    /// The time up to which the pair's events were consumed, if any.
    #[inline]
    pub(super) fn skip_of(&self, a: u32, b: u32) -> Option<Real> {
        let c = self.counter[b as usize];
        self.skips
            .get(&a)?
            .iter()
            .find(|&&(o, oc, _)| o == b && oc == c)
            .map(|s| s.2)
    }

    /// Sphere `id`'s wall certificate as it is kept: its plan's first wall contact when it
    /// may reach a wall before its shell (see [`ListedSpheres::near_wall`]), else `None` until
    /// it re-centres.
    pub(super) fn wall_kept(&self, id: u32) -> Option<WallHit> {
        if self.near_wall(id) {
            self.wall_of(id)
        } else {
            None
        }
    }

    /// Whether sphere `id` may touch a wall while within its shell: its list centre is within
    /// the shell plus its radius (and a hair) of a wall. A sphere that may not reaches its
    /// shell before any wall, and its wall certificate can wait until it re-centres: the
    /// certificate is taken at the plan's start, so it is then the same, bit for bit.
    pub(super) fn near_wall(&self, id: u32) -> bool {
        let Some(walls) = self.walls.as_ref() else {
            return false;
        };
        let i = id as usize;
        let c = &self.centre[i];
        let reach = (c.shell + self.motion[i].radius) * (1.0 + 1e-9);
        !((c.at - reach).cmpgt(walls.min).all() && (c.at + reach).cmplt(walls.max).all())
    }

    /// Sphere `id`'s wall certificate inside walls: the first wall contact of its plan, as
    /// the world computes it when the plan starts (`None` in a periodic box).
    pub(super) fn wall_of(&self, id: u32) -> Option<WallHit> {
        let walls = self.walls.as_ref()?;
        let m = &self.motion[id as usize];
        let plan = FlightPlan::linear(m.position, m.velocity).starting_at(m.t0);
        wall_hit(&plan, m.radius, walls, 3, m.t0.min(self.now))
    }

    /// Sphere `id`'s motion, its centre now, and its own event (the earlier of its shell
    /// crossing and its wall contact) as the earliest event so far: where a prediction
    /// starts.
    #[inline]
    fn start_prediction(&self, id: u32) -> (Motion, Vec3, Earliest) {
        let i = id as usize;
        let m = self.motion[i];
        let here = m.at(self.now);
        let c = self.centre[i];
        let exit = self.now + shell_exit(here, m.velocity, c.at, c.shell);
        let wall = self.wall[i].map_or(Real::INFINITY, |h| h.time.max(self.now));
        let earliest = if wall <= exit {
            Earliest::new(wall, Kind::Wall, TIE_WALL)
        } else {
            Earliest::new(exit, Kind::Shell, TIE_SHELL)
        };
        (m, here, earliest)
    }

    /// Recomputes sphere `id`'s next event from its shell and its listed pairs (each through
    /// its nearest image now) and schedules it.
    ///
    /// Pairs go in batches. A first pass over a batch computes each pair's gap coefficients
    /// with no branch that depends on the pair and keeps the few that may fail before the
    /// shell crossing; a second pass takes their roots. The neighbours' motions are read
    /// without waiting on a guess at the previous pair, and only kept pairs cost a root.
    pub(super) fn predict(&mut self, id: u32) {
        let i = id as usize;
        let now = self.now;
        let (m, here, mut best) = self.start_prediction(id);
        if self.skips.is_empty() {
            let mut sifted = self.sifted.take().unwrap_or_default();
            let list = self.lists.of(id);
            for batch in list.chunks(BATCH) {
                let bound = best.bound();
                let kept = if m.t0 == now {
                    self.first_pass::<true>(&m, here, bound, batch, &mut sifted)
                } else {
                    self.first_pass::<false>(&m, here, bound, batch, &mut sifted)
                };
                for pair in sifted.kept(batch, kept) {
                    self.offer_kept(id, &m, here, &pair, &mut best);
                }
            }
            self.sifted = Some(sifted);
        } else {
            for j in 0..self.lists.of(id).len() {
                let k = self.lists.of(id)[j];
                let mb = &self.motion[k as usize];
                let (d, shift) = self.period.apart(here - mb.at(now));
                let skip = self.skip_of(id, k);
                if let Some((t, graze)) = pair_due(&m, mb, shift, d, now, skip, best.next.time) {
                    best.offer(t, graze, k, |o| pair_key(self.ext[i], self.ext[o as usize]));
                }
            }
            best.runners.spoil();
        }
        let mut next = best.next;
        if next.kind == Kind::Pair {
            next.tie = pair_key(self.ext[i], self.ext[next.other as usize]);
            next.counter = self.counter[next.other as usize];
        }
        #[cfg(test)]
        self.check_prediction(id, &next);
        // A shell crossing never goes stale, so the spare of an earlier prediction is left
        // as it is: only a stale pair event, scheduled by this prediction or its spare, reads it.
        if next.kind == Kind::Pair {
            self.keep_spare(id, &best.runners, best.shell, best.own);
        }
        self.queue
            .schedule(id, next.time, next.tie, next.scheduled());
    }

    /// The second pass: a kept pair's failure time, in closed form where it is clear and by
    /// [`pair_due`] otherwise, offered to `best`.
    #[inline]
    fn offer_kept(&self, id: u32, m: &Motion, here: Vec3, pair: &Kept, best: &mut Earliest) {
        let &Kept {
            k,
            c0,
            c1,
            base,
            clear,
        } = pair;
        let mb = &self.motion[k as usize];
        let bound = best.bound();
        if clear {
            // As `pair_due` takes a pair clear of the other at base and now, approaching.
            let ahead = bound - base;
            if ahead.is_finite() && c0 > -c1 * (ahead * (1.0 + 1e-9) + bound.abs() * 1e-15) {
                return; // fails after the earliest found since the first pass
            }
            let v = m.velocity - mb.velocity;
            let c2 = v.dot(v);
            let (p, q) = (4.0 * c2 * c0, c1 * c1);
            if p - q > 1e-6 * (p + q) {
                return; // clearly missing
            }
            if let Some(t) = clear_first_contact(c0, c1, c2, base, self.now) {
                best.offer(t, false, k, |o| {
                    pair_key(self.ext[id as usize], self.ext[o as usize])
                });
                return;
            }
        }
        let (d, shift) = self.period.apart(here - mb.at(self.now));
        if let Some((t, graze)) = pair_due(m, mb, shift, d, self.now, None, bound) {
            best.offer_walked(t, graze, k, |o| {
                pair_key(self.ext[id as usize], self.ext[o as usize])
            });
        }
    }
}

/// The earliest event found so far while predicting (the sphere's own event or a pair), its
/// tie key once a tie has asked for it, and the runners-up after it.
struct Earliest {
    next: Next,
    tie: Option<u64>,
    /// The time of the sphere's own event (its shell crossing or its wall contact) and which
    /// it is.
    shell: Real,
    own: Kind,
    runners: Runners,
}

impl Earliest {
    fn new(shell: Real, own: Kind, tie: u64) -> Earliest {
        let next = Next {
            time: shell,
            tie,
            kind: own,
            ..Next::IDLE
        };
        Earliest {
            next,
            tie: None,
            shell,
            own,
            runners: Runners::new(),
        }
    }

    /// Pairs failing after this are of no use: neither the earliest nor a runner-up.
    #[inline]
    fn bound(&self) -> Real {
        self.runners.bound(self.shell)
    }

    /// Keeps the pair with `other` failing at `time` if it comes first: earlier, or at the
    /// same time with a lower key (`key_of(other)`, asked only on a tie; the sphere's own
    /// event goes last).
    /// What comes after the earliest is offered to the runners-up.
    #[inline]
    fn offer(&mut self, time: Real, graze: bool, other: u32, key_of: impl Fn(u32) -> u64) {
        if time > self.next.time {
            self.runners.push(time, other, self.shell);
            return;
        }
        if time == self.next.time {
            self.runners.spoil();
            let held = match (self.tie, self.next.kind) {
                (Some(t), _) => t,
                (None, Kind::Pair) => key_of(self.next.other),
                (None, _) => self.next.tie,
            };
            let tie = key_of(other);
            if tie >= held {
                self.tie = Some(held);
                return;
            }
            self.tie = Some(tie);
        } else {
            self.tie = None;
            if self.next.kind == Kind::Pair {
                if self.next.graze {
                    self.runners.spoil();
                }
                self.runners
                    .push(self.next.time, self.next.other, self.shell);
            }
        }
        self.next = Next {
            time,
            other,
            kind: Kind::Pair,
            graze,
            ..self.next
        };
    }

    /// As [`Earliest::offer`], for a time not taken in closed form: the runners-up are not
    /// used.
    #[inline]
    fn offer_walked(&mut self, time: Real, graze: bool, other: u32, key_of: impl Fn(u32) -> u64) {
        self.runners.spoil();
        self.offer(time, graze, other, key_of);
    }
}

#[cfg(test)]
impl ListedSpheres {
    /// Checks a prediction against every listed pair taken by [`pair_due`] with no bound.
    fn check_prediction(&self, id: u32, next: &Next) {
        let i = id as usize;
        let now = self.now;
        let (m, here, mut best) = self.start_prediction(id);
        for &k in self.lists.of(id) {
            let mb = &self.motion[k as usize];
            let (d, shift) = self.period.apart(here - mb.at(now));
            let skip = self.skip_of(id, k);
            if let Some((t, graze)) = pair_due(&m, mb, shift, d, now, skip, Real::INFINITY) {
                best.offer(t, graze, k, |o| pair_key(self.ext[i], self.ext[o as usize]));
            }
        }
        let want = best.next;
        assert_eq!(
            (want.time.to_bits(), want.kind, want.other, want.graze),
            (next.time.to_bits(), next.kind, next.other, next.graze),
            "sphere {id} at {now}: the batched prediction differs from every pair's"
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shell_exit_reaches_the_radius() {
        let t = shell_exit(Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0), Vec3::ZERO, 1.0);
        assert_eq!(t, 0.5);
        let t = shell_exit(
            Vec3::new(0.5, 0.0, 0.0),
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::ZERO,
            1.0,
        );
        assert_eq!(t, 1.5);
        assert_eq!(
            shell_exit(Vec3::ZERO, Vec3::ZERO, Vec3::ZERO, 1.0),
            Real::INFINITY
        );
    }
}
