//! Runners-up: the pairs a prediction finds failing after a sphere's earliest event, kept so
//! that when that event goes stale (its partner changed plan first) the sphere takes the next
//! one still standing instead of predicting again.
//!
//! A runner-up stands while its partner keeps the plan it had when the runner-up was found:
//! its time is then the pair's failure time. A partner that changed plan has predicted
//! since and covers the pair itself. The runners-up are the earliest pairs found, in order,
//! and every pair not kept fails later than the last of them, so the first standing one is
//! the sphere's next event among the pairs it still covers; once they are spent, the shell
//! crossing is, if no pair before it was left out.

use super::{Kind, ListedSpheres, Scheduled, TIE_SHELL, TIE_WALL};
use kinetic_core::Real;
use kinetic_core::kds::pair_key;

/// Runners-up kept per sphere.
const RUNNERS: usize = 3;

/// The runners-up a prediction collects: the earliest pairs after the earliest event, before
/// the shell crossing.
#[derive(Clone, Copy, Debug)]
pub(super) struct Runners {
    times: [Real; RUNNERS],
    others: [u32; RUNNERS],
    len: usize,
    /// Whether the runners-up may be used: no two candidates at the same time (their order
    /// would need the tie keys), and every time taken in closed form.
    usable: bool,
}

impl Runners {
    pub(super) fn new() -> Runners {
        Runners {
            times: [Real::INFINITY; RUNNERS],
            others: [0; RUNNERS],
            len: 0,
            usable: true,
        }
    }

    /// Pairs failing after this time are of no use: the last runner-up's when the list is
    /// full (pairs after it are turned away, so the shell crossing no longer comes next once
    /// the runners-up are spent), the shell crossing's before.
    #[inline]
    pub(super) fn bound(&self, shell: Real) -> Real {
        if self.len == RUNNERS {
            self.times[RUNNERS - 1]
        } else {
            shell
        }
    }

    /// The runners-up can no longer be used.
    #[inline]
    pub(super) fn spoil(&mut self) {
        self.usable = false;
    }

    /// Offers the pair with `other` failing at `time`, after the earliest event: kept in
    /// order if it comes before the shell crossing and the last runner-up.
    #[inline]
    pub(super) fn push(&mut self, time: Real, other: u32, shell: Real) {
        if time >= shell {
            self.usable &= time != shell;
            return;
        }
        let mut at = self.len;
        while at > 0 && time < self.times[at - 1] {
            at -= 1;
        }
        if at > 0 && self.times[at - 1] == time {
            self.usable = false;
        }
        if at == RUNNERS {
            return;
        }
        if self.len < RUNNERS {
            self.len += 1;
        }
        let mut j = self.len - 1;
        while j > at {
            self.times[j] = self.times[j - 1];
            self.others[j] = self.others[j - 1];
            j -= 1;
        }
        self.times[at] = time;
        self.others[at] = other;
    }
}

/// A sphere's runners-up, with each partner's plan number when they were found, its shell
/// crossing, and whether that crossing comes next once they are spent.
#[derive(Clone, Copy, Debug, Default)]
#[repr(align(64))]
pub(super) struct SavedRunners {
    times: [Real; RUNNERS],
    others: [u32; RUNNERS],
    counters: [u32; RUNNERS],
    shell: Real,
    /// Runners-up not yet taken: `taken..len`.
    taken: u8,
    len: u8,
    /// The sphere's own event comes once the runners-up are spent.
    shell_next: bool,
    /// Its own event is a wall contact (else its shell crossing).
    wall_next: bool,
}

impl SavedRunners {
    /// Nothing to take: the sphere predicts again.
    pub(super) const NONE: SavedRunners = SavedRunners {
        times: [0.0; RUNNERS],
        others: [0; RUNNERS],
        counters: [0; RUNNERS],
        shell: 0.0,
        taken: 0,
        len: 0,
        shell_next: false,
        wall_next: false,
    };
}

impl ListedSpheres {
    /// Keeps what sphere `id`'s prediction found after its earliest event, a pair.
    #[inline]
    pub(super) fn keep_spare(&mut self, id: u32, runners: &Runners, shell: Real, own: Kind) {
        let mut spare = SavedRunners::NONE;
        if runners.usable {
            for j in 0..runners.len {
                spare.times[j] = runners.times[j];
                spare.others[j] = runners.others[j];
                spare.counters[j] = self.counter[runners.others[j] as usize];
            }
            spare.len = runners.len as u8;
            spare.shell = shell;
            // A full list turned away pairs after its last: some may come before the shell.
            spare.shell_next = runners.len < RUNNERS;
            spare.wall_next = own == Kind::Wall;
        }
        self.spares[id as usize] = spare;
    }

    /// Sphere `id`'s event went stale: schedules its first standing runner-up, or its own
    /// event (shell crossing or wall contact) when that comes next; returns whether it did (if not, the sphere predicts).
    pub(super) fn take_spare(&mut self, id: u32) -> bool {
        let i = id as usize;
        let now = self.now;
        let spare = &mut self.spares[i];
        while spare.taken < spare.len {
            let j = spare.taken as usize;
            spare.taken += 1;
            let (time, other, counter) = (spare.times[j], spare.others[j], spare.counters[j]);
            if self.counter[other as usize] == counter && time > now {
                let tie = pair_key(self.ext[i], self.ext[other as usize]);
                let scheduled = Scheduled {
                    kind: Kind::Pair,
                    graze: false,
                    other,
                    counter,
                };
                self.queue.schedule(id, time, tie, scheduled);
                self.spare_counts[0] += 1;
                return true;
            }
        }
        if spare.shell_next && spare.shell > now {
            let shell = spare.shell;
            let (kind, tie) = if spare.wall_next {
                (Kind::Wall, TIE_WALL)
            } else {
                (Kind::Shell, TIE_SHELL)
            };
            *spare = SavedRunners::NONE;
            let scheduled = Scheduled {
                kind,
                ..Scheduled::default()
            };
            self.queue.schedule(id, shell, tie, scheduled);
            self.spare_counts[1] += 1;
            return true;
        }
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runners_up_are_the_earliest_in_order() {
        let mut r = Runners::new();
        for (t, o) in [(3.0, 3), (1.0, 1), (2.0, 2)] {
            r.push(t, o, 10.0);
        }
        assert_eq!((r.times, r.others, r.len), ([1.0, 2.0, 3.0], [1, 2, 3], 3));
        assert_eq!(r.bound(10.0), 3.0);
        r.push(1.5, 15, 10.0);
        assert_eq!((r.times, r.others), ([1.0, 1.5, 2.0], [1, 15, 2]));
        r.push(4.0, 4, 10.0); // after the last
        assert_eq!((r.others, r.bound(10.0)), ([1, 15, 2], 2.0));
        r.push(12.0, 12, 10.0); // after the shell: of no use
        assert_eq!(r.others, [1, 15, 2]);
        assert!(r.usable);
        r.push(1.5, 16, 10.0);
        assert!(!r.usable, "a tie needs the keys");
        let mut r = Runners::new();
        r.push(10.0, 1, 10.0);
        assert!(!r.usable, "a tie with the shell needs the keys");
        assert_eq!(Runners::new().bound(7.0), 7.0);
    }
}
