//! Certificate roots: where a polynomial of degree at most 4 vanishes after `tau = 0`.
//!
//! Degrees up to 2 use closed forms (the numerically stable quadratic formula). Degrees 3 and
//! 4 are isolated through the roots of the derivative (recursively down to the quadratic):
//! between two consecutive critical points the polynomial is monotone, so it has a root there
//! exactly when the signs at the two ends differ, and that root is polished by Newton steps
//! inside a shrinking bracket. "Does the certificate fail" is decided by signs, never by an
//! epsilon: a double root (a graze) leaves the sign unchanged and is reported as a touch, not
//! as a sign change, and a root exactly at `tau = 0` is not reported at all (the sign just
//! after zero, [`Poly::sign_just_after_zero`], already accounts for it).

use crate::poly::{Poly, sign};

/// A real root of a polynomial at `tau > 0`, with the signs on either side of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Root {
    /// Where the polynomial vanishes (local time).
    pub tau: f64,
    /// The sign just before the root (-1 or 1).
    pub before: i8,
    /// The sign just after the root (-1 or 1). Equal to `before` for a touch (a double root).
    pub after: i8,
}

impl Root {
    /// Whether the polynomial changes sign here (false for a touch).
    pub fn is_sign_change(&self) -> bool {
        self.before != self.after
    }
}

/// All roots of a polynomial in `tau > 0`, in increasing order (at most 4).
#[derive(Clone, Copy, Debug, Default)]
pub struct Roots {
    roots: [Option<Root>; 4],
    len: u8,
}

impl Roots {
    fn push(&mut self, root: Root) {
        if (self.len as usize) < 4 {
            self.roots[self.len as usize] = Some(root);
            self.len += 1;
        }
    }

    /// The number of roots.
    pub fn len(&self) -> usize {
        self.len as usize
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The `i`-th root in increasing order.
    pub fn get(&self, i: usize) -> Option<Root> {
        self.roots.get(i).copied().flatten()
    }

    /// The roots in increasing order.
    pub fn iter(&self) -> impl Iterator<Item = Root> + '_ {
        self.roots[..self.len as usize].iter().flatten().copied()
    }
}

/// The roots of `p` in `tau > 0`, each with the signs around it.
///
/// The signs are exact where they can be: the sign just after zero comes from the
/// coefficients, and the sign alternates across each simple root.
///
/// ```
/// # use kinetic_core::kds::{Poly, roots::roots_after_zero};
/// // (tau - 1)(tau - 3) = tau^2 - 4 tau + 3
/// let r = roots_after_zero(&Poly::new(&[3.0, -4.0, 1.0]));
/// assert_eq!(r.len(), 2);
/// assert_eq!(r.get(0).unwrap().tau, 1.0);
/// assert_eq!((r.get(0).unwrap().before, r.get(0).unwrap().after), (1, -1));
/// ```
pub fn roots_after_zero(p: &Poly) -> Roots {
    let p = &in_range(p);
    let mut out = Roots::default();
    let s0 = p.sign_just_after_zero();
    if s0 == 0 {
        return out;
    }
    let mut found = [(0.0, false); 4];
    let n = raw_roots(p, &mut found);
    let mut before = s0;
    for &(tau, touch) in &found[..n] {
        let after = if touch { before } else { -before };
        out.push(Root { tau, before, after });
        before = after;
    }
    out
}

/// `p` scaled by a power of two (exactly: the same roots and signs) so that its largest
/// coefficient is near 1, when it is so small or so large that products of coefficients (a
/// discriminant, a Newton step) would underflow or overflow; `p` itself otherwise, so that
/// ordinary certificates are solved bit for bit as written.
fn in_range(p: &Poly) -> Poly {
    const LOW: f64 = 1.0 / (1u128 << 100) as f64 / (1u128 << 100) as f64 / (1u128 << 100) as f64;
    let m = p.c.iter().fold(0.0f64, |m, &x| m.max(x.abs()));
    if m == 0.0 || !m.is_finite() || (LOW..=1.0 / LOW).contains(&m) {
        return *p;
    }
    let scale = 2f64.powi(-m.log2().round() as i32);
    Poly {
        c: p.c.map(|x| x * scale),
    }
}

/// The first time `tau > 0` at which `p` changes sign, if any. A touch (double root) is
/// skipped: the certificate still holds after it.
///
/// ```
/// # use kinetic_core::kds::{Poly, roots::first_sign_change};
/// assert_eq!(first_sign_change(&Poly::new(&[4.0, 0.0, -1.0])), Some(2.0)); // 4 - tau^2
/// assert_eq!(first_sign_change(&Poly::new(&[1.0, -2.0, 1.0])), None); // (tau - 1)^2
/// ```
pub fn first_sign_change(p: &Poly) -> Option<f64> {
    roots_after_zero(p)
        .iter()
        .find(Root::is_sign_change)
        .map(|r| r.tau)
}

/// Writes the roots in `tau > 0` of a non-zero `p` into `out`, ascending, each flagged
/// `true` when it is a touch; returns how many.
fn raw_roots(p: &Poly, out: &mut [(f64, bool); 4]) -> usize {
    match p.degree() {
        None | Some(0) => 0,
        Some(1) => {
            let tau = -p.c[0] / p.c[1];
            if tau > 0.0 && tau.is_finite() {
                out[0] = (tau, false);
                1
            } else {
                0
            }
        }
        Some(2) => quadratic_roots(p.c[0], p.c[1], p.c[2], out),
        Some(deg) => {
            // Critical points split (0, bound) into pieces on which p is monotone.
            let mut crit = [(0.0, false); 4];
            let ncrit = raw_roots(&p.derivative(), &mut crit);
            let bound = cauchy_bound(p, deg);
            let mut n = 0;
            let mut lo = 0.0;
            let mut s_lo = p.sign_just_after_zero();
            for &(c, _) in crit[..ncrit].iter().filter(|(c, _)| *c < bound) {
                let v = p.eval(c);
                let s = sign(v);
                if s == 0 {
                    // A root exactly at a critical point: touch unless the sign differs on
                    // the two sides (an odd-order critical root, such as tau^3).
                    let s_next = sign(p.eval(next_probe(c, &crit[..ncrit], bound)));
                    if n < 4 {
                        out[n] = (c, s_next == s_lo);
                        n += 1;
                    }
                    s_lo = if s_next == 0 { s_lo } else { s_next };
                } else {
                    if s != s_lo && n < 4 {
                        out[n] = (polish(p, lo, c, s_lo), false);
                        n += 1;
                    }
                    s_lo = s;
                }
                lo = c;
            }
            let s_hi = sign(p.c[deg]);
            if s_hi != s_lo && n < 4 {
                out[n] = (polish(p, lo, bound, s_lo), false);
                n += 1;
            }
            n
        }
    }
}

/// A point just right of critical point `c`, before the next critical point or the bound.
fn next_probe(c: f64, crit: &[(f64, bool)], bound: f64) -> f64 {
    let next = crit
        .iter()
        .map(|x| x.0)
        .find(|&x| x > c)
        .unwrap_or(bound)
        .min(bound);
    c + (next - c) * 0.5
}

/// Roots in `tau > 0` of `c0 + c1 tau + c2 tau^2` with `c2 != 0`, by the stable formula,
/// written into `out` ascending, each flagged `true` when it is a double root (a touch);
/// returns how many.
pub fn quadratic_roots(c0: f64, c1: f64, c2: f64, out: &mut [(f64, bool); 4]) -> usize {
    let disc = c1 * c1 - 4.0 * c2 * c0;
    let mut n = 0;
    if disc < 0.0 || !disc.is_finite() {
        if !disc.is_finite() {
            // Overflowing coefficients: scale down and retry (exact scaling by a power of 2).
            let m = c0.abs().max(c1.abs()).max(c2.abs());
            if m.is_finite() && m > 0.0 {
                let s = 2f64.powi(-(m.log2().ceil() as i32));
                if s != 1.0 {
                    return quadratic_roots(c0 * s, c1 * s, c2 * s, out);
                }
            }
        }
        return 0;
    }
    if disc == 0.0 {
        let tau = -c1 / (2.0 * c2);
        if tau > 0.0 {
            out[0] = (tau, true);
            n = 1;
        }
        return n;
    }
    let q = -0.5 * (c1 + disc.sqrt().copysign(c1));
    let (mut r1, mut r2) = (q / c2, c0 / q);
    if r1 > r2 {
        std::mem::swap(&mut r1, &mut r2);
    }
    for r in [r1, r2] {
        if r > 0.0 && r.is_finite() {
            out[n] = (r, false);
            n += 1;
        }
    }
    n
}

/// Cauchy's bound: every root has `|tau| < 1 + max |c_i / c_deg|`.
fn cauchy_bound(p: &Poly, deg: usize) -> f64 {
    let lead = p.c[deg].abs();
    let m = p.c[..deg]
        .iter()
        .fold(0.0f64, |m, &x| m.max(x.abs() / lead));
    (1.0 + m).min(f64::MAX / 4.0)
}

/// The root of `p` in `(a, b)` where `p` is monotone, has sign `sa` just right of `a` and
/// the opposite sign at `b`. Wide brackets are first split geometrically (so a huge Cauchy
/// bound costs a few dozen steps), then the Illinois variant of regula falsi shrinks the
/// bracket from both sides until its ends are adjacent floats.
fn polish(p: &Poly, mut a: f64, mut b: f64, sa: i8) -> f64 {
    while is_wide(a, b) {
        let m = split(a, b);
        match sign(p.eval(m)) {
            0 => return m,
            s if s == sa => a = m,
            _ => b = m,
        }
    }
    let at_least = |v: f64, s: i8| {
        if sign(v) == s {
            v
        } else {
            f64::from(s) * f64::MIN_POSITIVE
        }
    };
    let mut fa = at_least(p.eval(a), sa);
    let mut fb = at_least(p.eval(b), -sa);
    let mut kept = 0i8;
    for _ in 0..256 {
        if a.next_up() >= b {
            break;
        }
        let mut x = (a * fb - b * fa) / (fb - fa);
        if !(x > a && x < b) {
            x = a + (b - a) * 0.5;
        }
        let fx = p.eval(x);
        match sign(fx) {
            0 => return x,
            s if s == sa => {
                a = x;
                fa = fx;
                if kept == 1 {
                    fb *= 0.5;
                }
                kept = 1;
            }
            _ => {
                b = x;
                fb = fx;
                if kept == -1 {
                    fa *= 0.5;
                }
                kept = -1;
            }
        }
    }
    // The end of the final bracket where the new sign already holds.
    b
}

fn is_wide(a: f64, b: f64) -> bool {
    (a > 0.0 && b > 16.0 * a) || (a == 0.0 && b > 1e3)
}

/// A point strictly inside `(a, b)`: the midpoint, or the geometric mean for wide brackets.
fn split(a: f64, b: f64) -> f64 {
    if a > 0.0 && b > 16.0 * a {
        (a * b).sqrt()
    } else if a == 0.0 && b > 1e3 {
        b.sqrt()
    } else {
        a + (b - a) * 0.5
    }
}
