//! The first pass of a prediction over a batch of neighbours: each pair's gap coefficients,
//! with no branch that depends on the pair, keeping the few pairs that may fail before the
//! bound. On x86-64 processors with AVX (found at run time) the pairs go four at a time in
//! AVX lanes, each lane with the scalar pass's operations in order; elsewhere one at a time.

use super::{ListedSpheres, Motion};
#[cfg(target_arch = "x86_64")]
use kinetic_core::prefetch;
use kinetic_core::{Real, Vec3};

impl ListedSpheres {
    /// The first pass over a batch of `m`'s neighbours, one pair at a time: writes to `out`
    /// every place's coefficients and the places of the pairs that
    /// [`pair_due`](super::predict::pair_due) would not turn away at once (apart, and
    /// parting or failing after `bound`), and returns how many. Each pair's gap
    /// is taken around the later of the two plans' starts, as `pair_due` takes it;
    /// `STARTED_NOW` says that `m`'s plan starts now, so that every pair's gap is taken
    /// around now. Processors without AVX take it; the tests check the lanes against it.
    #[inline]
    pub(super) fn sift<const STARTED_NOW: bool>(
        &self,
        m: &Motion,
        here: Vec3,
        bound: Real,
        batch: &[u32],
        out: &mut FirstPassOut,
    ) -> usize {
        let now = self.now;
        let motion = &self.motion[..];
        let half = self.period.half_side;
        // The starts first, in a loop of loads alone: the neighbours' motions are fetched
        // together rather than one pair at a time.
        let mut starts = [0.0; BATCH];
        for (start, &k) in starts.iter_mut().zip(batch) {
            *start = motion[k as usize].t0;
        }
        let mut len = 0;
        out.clear = 0;
        for (j, (&k, &t0)) in batch.iter().zip(&starts).enumerate() {
            let mb = &motion[k as usize];
            let mut d = here - mb.at(now);
            let near = (d.x.abs() < half.x) & (d.y.abs() < half.y) & (d.z.abs() < half.z);
            let mut shift = Vec3::ZERO;
            if !near {
                shift = self.period.nearest(d);
                d -= shift;
            }
            let reach = m.radius + mb.radius;
            let threshold2 = reach * reach;
            let v = m.velocity - mb.velocity;
            let (base, c0, c1, gap_now);
            if STARTED_NOW {
                base = now;
                c0 = d.dot(d) - threshold2;
                c1 = 2.0 * d.dot(v);
                gap_now = c0;
            } else {
                let later = if m.t0 > t0 { m.t0 } else { t0 };
                base = if later < now { later } else { now };
                let db = if base == now {
                    d
                } else {
                    (m.at(base) - mb.at(base)) - shift
                };
                c0 = db.dot(db) - threshold2;
                c1 = 2.0 * db.dot(v);
                gap_now = if base == now {
                    c0
                } else {
                    d.dot(d) - threshold2
                };
            }
            let apart = (c0 > 0.0) & (gap_now > 0.0);
            let ahead = bound - base;
            let after_bound =
                ahead.is_finite() & (c0 > -c1 * (ahead * (1.0 + 1e-9) + bound.abs() * 1e-15));
            let parting = (c0 <= 0.0) & (c1 > 0.0) & (base == now);
            let none = parting | (apart & ((c1 >= 0.0) | after_bound));
            (out.c0[j], out.c1[j], out.base[j]) = (c0, c1, base);
            out.clear |= u32::from(apart) << j;
            out.at[len] = j as u8;
            len += usize::from(!none);
        }
        len
    }

    /// The first pass over a batch, as the scalar pass (`sift`) gives it: in AVX lanes where
    /// the processor has AVX.
    #[inline]
    pub(super) fn first_pass<const STARTED_NOW: bool>(
        &self,
        m: &Motion,
        here: Vec3,
        bound: Real,
        batch: &[u32],
        out: &mut FirstPassOut,
    ) -> usize {
        #[cfg(target_arch = "x86_64")]
        if self.wide {
            // SAFETY: `wide` is set only where the processor has AVX, which `sift_wide`
            // asks for.
            #[allow(unsafe_code)]
            return unsafe { self.sift_wide::<STARTED_NOW>(m, here, bound, batch, out) };
        }
        self.sift::<STARTED_NOW>(m, here, bound, batch, out)
    }

    /// The scalar pass (`sift`) four pairs at a time in the four lanes of AVX registers, on
    /// processors that have AVX: each lane takes the scalar pass's operations in its order,
    /// so the coefficients are the same to the bit. Four motions are read whole, two
    /// registers each, and transposed to one coordinate a register.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx")]
    pub(super) fn sift_wide<const STARTED_NOW: bool>(
        &self,
        m: &Motion,
        here: Vec3,
        bound: Real,
        batch: &[u32],
        out: &mut FirstPassOut,
    ) -> usize {
        use std::arch::x86_64::*;
        let now = self.now;
        let motion = &self.motion[..];
        if !STARTED_NOW {
            // No collision asked for these motions: they are asked for together first.
            for &k in batch {
                prefetch(&motion[k as usize]);
            }
        }
        let p = &self.period;
        let splat = _mm256_set1_pd;
        let splat3 = |v: Vec3| [splat(v.x), splat(v.y), splat(v.z)];
        let sign = splat(-0.0);
        let abs = |x: __m256d| _mm256_andnot_pd(sign, x);
        let select = |mask: __m256d, a: __m256d, b: __m256d| _mm256_blendv_pd(b, a, mask);
        // The scalar pass's comparisons: ordered (false where either side is NaN).
        let lt = |a: __m256d, b: __m256d| _mm256_cmp_pd::<_CMP_LT_OS>(a, b);
        let le = |a: __m256d, b: __m256d| _mm256_cmp_pd::<_CMP_LE_OS>(a, b);
        let eq = |a: __m256d, b: __m256d| _mm256_cmp_pd::<_CMP_EQ_OQ>(a, b);
        let (zero, two, now4) = (splat(0.0), splat(2.0), splat(now));
        let (here, half, side, inv) = (
            splat3(here),
            splat3(p.half_side),
            splat3(p.side),
            splat3(p.inv_side),
        );
        let (mp, mv, mt0) = (splat3(m.position), splat3(m.velocity), splat(m.t0));
        let radius = splat(m.radius);
        let magic = splat(kinetic_core::elastic::ROUNDING);
        let (bound4, slack) = (splat(bound), splat(bound.abs() * 1e-15));
        let (infinity, widen) = (splat(Real::INFINITY), splat(1.0 + 1e-9));
        let ahead_now = _mm256_sub_pd(bound4, now4);
        let finite_now = lt(abs(ahead_now), infinity);
        let reach_bound_now = _mm256_add_pd(_mm256_mul_pd(ahead_now, widen), slack);
        let dot = |u: &[__m256d; 3], v: &[__m256d; 3]| {
            _mm256_add_pd(
                _mm256_add_pd(_mm256_mul_pd(u[0], v[0]), _mm256_mul_pd(u[1], v[1])),
                _mm256_mul_pd(u[2], v[2]),
            )
        };
        // A motion's halves: (t0, position) and (velocity, radius), one aligned load each.
        const _: () = {
            use std::mem::offset_of;
            assert!(offset_of!(Motion, t0) == 0 && offset_of!(Motion, position) == 8);
            assert!(offset_of!(Motion, velocity) == 32 && offset_of!(Motion, radius) == 56);
            assert!(std::mem::align_of::<Motion>() >= 32);
        };
        let halves = |k: u32| {
            let m: *const f64 = (&motion[k as usize] as *const Motion).cast();
            // SAFETY: a motion is 64 bytes of eight `f64`, aligned to 64 (checked above).
            #[allow(unsafe_code)]
            unsafe {
                (_mm256_load_pd(m), _mm256_load_pd(m.add(4)))
            }
        };
        let mut len = 0;
        out.clear = 0;
        for (q, quad) in batch.chunks(4).enumerate() {
            let last = quad[quad.len() - 1];
            let at = |j: usize| *quad.get(j).unwrap_or(&last);
            let (a, b, c, d4) = (halves(at(0)), halves(at(1)), halves(at(2)), halves(at(3)));
            // The 4 x 4 transposes: one field of the four motions a register.
            let (l0, l1) = (_mm256_unpacklo_pd(a.0, b.0), _mm256_unpacklo_pd(c.0, d4.0));
            let (h0, h1) = (_mm256_unpackhi_pd(a.0, b.0), _mm256_unpackhi_pd(c.0, d4.0));
            let t0 = _mm256_permute2f128_pd::<0x20>(l0, l1);
            let pos = [
                _mm256_permute2f128_pd::<0x20>(h0, h1),
                _mm256_permute2f128_pd::<0x31>(l0, l1),
                _mm256_permute2f128_pd::<0x31>(h0, h1),
            ];
            let (l0, l1) = (_mm256_unpacklo_pd(a.1, b.1), _mm256_unpacklo_pd(c.1, d4.1));
            let (h0, h1) = (_mm256_unpackhi_pd(a.1, b.1), _mm256_unpackhi_pd(c.1, d4.1));
            let vel = [
                _mm256_permute2f128_pd::<0x20>(l0, l1),
                _mm256_permute2f128_pd::<0x20>(h0, h1),
                _mm256_permute2f128_pd::<0x31>(l0, l1),
            ];
            let radii = _mm256_permute2f128_pd::<0x31>(h0, h1);
            let dt = _mm256_sub_pd(now4, t0);
            let mut d = [zero; 3];
            let mut near = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
            for x in 0..3 {
                d[x] = _mm256_sub_pd(here[x], _mm256_add_pd(pos[x], _mm256_mul_pd(vel[x], dt)));
                near = _mm256_and_pd(near, lt(abs(d[x]), half[x]));
            }
            // The image shift, zero in a lane whose pair is near.
            let mut shift = [zero; 3];
            if _mm256_movemask_pd(near) != 15 {
                for x in 0..3 {
                    let whole =
                        _mm256_sub_pd(_mm256_add_pd(_mm256_mul_pd(d[x], inv[x]), magic), magic);
                    shift[x] = _mm256_andnot_pd(near, _mm256_mul_pd(whole, side[x]));
                    d[x] = _mm256_sub_pd(d[x], shift[x]);
                }
            }
            let reach = _mm256_add_pd(radius, radii);
            let threshold2 = _mm256_mul_pd(reach, reach);
            let w = [
                _mm256_sub_pd(mv[0], vel[0]),
                _mm256_sub_pd(mv[1], vel[1]),
                _mm256_sub_pd(mv[2], vel[2]),
            ];
            let (base, at_now, c0, c1, gap_now);
            if STARTED_NOW {
                base = now4;
                at_now = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
                c0 = _mm256_sub_pd(dot(&d, &d), threshold2);
                c1 = _mm256_mul_pd(two, dot(&d, &w));
                gap_now = c0;
            } else {
                let later = select(lt(t0, mt0), mt0, t0);
                base = select(lt(later, now4), later, now4);
                at_now = eq(base, now4);
                let (ta, tb) = (_mm256_sub_pd(base, mt0), _mm256_sub_pd(base, t0));
                let mut db = [zero; 3];
                for x in 0..3 {
                    let ma = _mm256_add_pd(mp[x], _mm256_mul_pd(mv[x], ta));
                    let mb = _mm256_add_pd(pos[x], _mm256_mul_pd(vel[x], tb));
                    db[x] = select(at_now, d[x], _mm256_sub_pd(_mm256_sub_pd(ma, mb), shift[x]));
                }
                c0 = _mm256_sub_pd(dot(&db, &db), threshold2);
                c1 = _mm256_mul_pd(two, dot(&db, &w));
                gap_now = select(at_now, c0, _mm256_sub_pd(dot(&d, &d), threshold2));
            }
            let apart = _mm256_and_pd(lt(zero, c0), lt(zero, gap_now));
            let (finite, reach_bound) = if STARTED_NOW {
                (finite_now, reach_bound_now)
            } else {
                let ahead = _mm256_sub_pd(bound4, base);
                (
                    lt(abs(ahead), infinity),
                    _mm256_add_pd(_mm256_mul_pd(ahead, widen), slack),
                )
            };
            let after_bound = _mm256_and_pd(
                finite,
                lt(_mm256_mul_pd(_mm256_xor_pd(c1, sign), reach_bound), c0),
            );
            let parting = _mm256_and_pd(_mm256_and_pd(le(c0, zero), lt(zero, c1)), at_now);
            let none = _mm256_or_pd(
                parting,
                _mm256_and_pd(apart, _mm256_or_pd(le(zero, c1), after_bound)),
            );
            let keep = !_mm256_movemask_pd(none) & ((1 << quad.len()) - 1);
            let at = 4 * q;
            // SAFETY: `at + 4 <= BATCH`: a batch holds at most `BATCH` pairs, a multiple of 4.
            #[allow(unsafe_code)]
            unsafe {
                _mm256_storeu_pd(out.c0[at..at + 4].as_mut_ptr(), c0);
                _mm256_storeu_pd(out.c1[at..at + 4].as_mut_ptr(), c1);
                _mm256_storeu_pd(out.base[at..at + 4].as_mut_ptr(), base);
            }
            out.clear |= (_mm256_movemask_pd(apart) as u32) << at;
            // The kept lanes' places, packed four bytes at once (`len <= at`, so the four
            // bytes fit the room after the batch's places).
            let (places, count) = KEPT_LANES[keep as usize];
            let places = places + (at as u32) * 0x0101_0101;
            out.at[len..len + 4].copy_from_slice(&places.to_le_bytes());
            len += count as usize;
        }
        len
    }
}

/// Neighbours sifted in one batch: whole quads, one bit each in [`FirstPassOut`]'s `clear`.
pub(super) const BATCH: usize = 32;
const _: () = assert!(BATCH.is_multiple_of(4) && BATCH <= 32);

/// What the first pass writes for a batch: each place's first two coefficients of its gap
/// `c0 + c1 tau + c2 tau^2` around `base`, and whether the two are clear of each other at
/// `base` and now (a bit a place), kept or not; and the places of the kept pairs, in order.
#[derive(Clone, Debug)]
pub(super) struct FirstPassOut {
    c0: [Real; BATCH],
    c1: [Real; BATCH],
    base: [Real; BATCH],
    clear: u32,
    at: [u8; BATCH + 3],
}

/// For each mask of four lanes: the kept lanes in order, one a byte from the lowest, and
/// how many they are.
#[cfg(target_arch = "x86_64")]
const KEPT_LANES: [(u32, u8); 16] = {
    let mut table = [(0, 0); 16];
    let mut mask = 0;
    while mask < 16 {
        let (mut places, mut count) = (0u32, 0u8);
        let mut lane = 0;
        while lane < 4 {
            if mask >> lane & 1 != 0 {
                places |= lane << (8 * count);
                count += 1;
            }
            lane += 1;
        }
        table[mask as usize] = (places, count);
        mask += 1;
    }
    table
};

impl Default for FirstPassOut {
    fn default() -> FirstPassOut {
        FirstPassOut {
            c0: [0.0; BATCH],
            c1: [0.0; BATCH],
            base: [0.0; BATCH],
            clear: 0,
            at: [0; BATCH + 3],
        }
    }
}

impl FirstPassOut {
    /// The `len` pairs kept from `batch`, in order.
    #[inline]
    pub(super) fn kept<'a>(
        &'a self,
        batch: &'a [u32],
        len: usize,
    ) -> impl Iterator<Item = Kept> + 'a {
        self.at[..len].iter().map(move |&j| {
            let j = j as usize;
            Kept {
                k: batch[j],
                c0: self.c0[j],
                c1: self.c1[j],
                base: self.base[j],
                clear: self.clear >> j & 1 != 0,
            }
        })
    }
}

/// A pair kept by the first pass: the neighbour, the first two coefficients of its gap
/// `c0 + c1 tau + c2 tau^2` around `base`, and whether the two are clear of each other at
/// `base` and now.
#[derive(Clone, Copy, Debug)]
pub(super) struct Kept {
    pub(super) k: u32,
    pub(super) c0: Real,
    pub(super) c1: Real,
    pub(super) base: Real,
    pub(super) clear: bool,
}

#[cfg(all(test, target_arch = "x86_64"))]
mod tests {
    use super::*;
    use crate::listed::PeriodicBox;
    use kinetic_core::FlightPlan;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// The four-lane pass over every sphere's list, with and without a bound: the same
    /// pairs kept as by the scalar pass, with the same coefficients and bases to the bit.
    /// Returns the pairs compared.
    fn same_passes(gas: &ListedSpheres) -> usize {
        let bits = |k: Kept| {
            (
                k.k,
                k.c0.to_bits(),
                k.c1.to_bits(),
                k.base.to_bits(),
                k.clear,
            )
        };
        let mut checked = 0;
        let (mut a, mut b) = (FirstPassOut::default(), FirstPassOut::default());
        let (mut c, mut d) = (FirstPassOut::default(), FirstPassOut::default());
        for id in 0..gas.len() as u32 {
            let m = gas.motion[id as usize];
            let here = m.at(gas.now);
            for batch in gas.lists.of(id).chunks(BATCH) {
                for bound in [Real::INFINITY, gas.now + 0.05, gas.now + 1.0] {
                    let scalar = (
                        gas.sift::<true>(&m, here, bound, batch, &mut a),
                        gas.sift::<false>(&m, here, bound, batch, &mut b),
                    );
                    // SAFETY: the test runs the lanes only where the processor has AVX.
                    #[allow(unsafe_code)]
                    let lanes = unsafe {
                        (
                            gas.sift_wide::<true>(&m, here, bound, batch, &mut c),
                            gas.sift_wide::<false>(&m, here, bound, batch, &mut d),
                        )
                    };
                    assert_eq!(scalar, lanes, "sphere {id}: kept counts");
                    let pairs = a.kept(batch, scalar.0).zip(c.kept(batch, lanes.0));
                    for (x, y) in pairs.chain(b.kept(batch, scalar.1).zip(d.kept(batch, lanes.1))) {
                        assert_eq!(bits(x), bits(y), "sphere {id}");
                    }
                    checked += scalar.0 + scalar.1;
                }
            }
        }
        checked
    }

    /// Spheres on a jittered lattice in a small box (many pairs meet through images), run
    /// on so that plans start at different times: the lanes sift as the scalar pass does,
    /// after each of the first events (the colliding spheres' plans start now) and later.
    #[test]
    fn lanes_sift_as_the_scalar_pass() {
        if !std::arch::is_x86_feature_detected!("avx") {
            // The lanes are not used here: predictions take the scalar pass, which every
            // test checks against each pair's own prediction.
            eprintln!("no AVX on this processor: the lanes are not compared");
            return;
        }
        let mut rng = ChaCha8Rng::seed_from_u64(99);
        let mut rand = || rng.random_range(-0.5..0.5);
        let cell = PeriodicBox {
            min: Vec3::ZERO,
            max: Vec3::splat(8.0),
        };
        let spacing = 8.0 / 7.0;
        let mut spheres = Vec::new();
        for i in 0..250 {
            let site = Vec3::new((i % 7) as Real, (i / 7 % 7) as Real, (i / 49) as Real);
            let jitter = Vec3::new(rand(), rand(), rand()) * 0.2;
            let p = (site + 0.5) * spacing + jitter;
            let v = Vec3::new(rand(), rand(), rand()) * 4.0;
            spheres.push((0.4, FlightPlan::linear(p, v)));
        }
        let mut gas = ListedSpheres::periodic(cell, &spheres).unwrap();
        let mut checked = same_passes(&gas);
        for _ in 0..20 {
            assert!(gas.step(Real::INFINITY).unwrap());
            checked += same_passes(&gas);
        }
        gas.advance_to(gas.now() + 1.0).unwrap();
        checked += same_passes(&gas);
        assert!(checked > 10_000, "{checked} pairs kept");
    }
}
