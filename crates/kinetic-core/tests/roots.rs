//! Certificate roots against roots planted by construction, and adversarial cases.

use kinetic_core::kds::Poly;
use kinetic_core::kds::roots::{first_sign_change, roots_after_zero};
use proptest::prelude::*;

/// The polynomial `scale * prod (tau - r_i)`.
fn planted(scale: f64, roots: &[f64]) -> Poly {
    let mut c = vec![scale];
    for &r in roots {
        let mut next = vec![0.0; c.len() + 1];
        for (i, &x) in c.iter().enumerate() {
            next[i + 1] += x;
            next[i] -= r * x;
        }
        c = next;
    }
    Poly::new(&c)
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs().max(1.0)
}

proptest! {
    #[test]
    fn planted_simple_roots_are_found(
        mut roots in prop::collection::vec(-50.0f64..50.0, 1..=4),
        scale in prop::sample::select(vec![-1e6, -3.0, -1e-3, 1e-3, 1.0, 7.5, 1e6]),
    ) {
        roots.sort_by(f64::total_cmp);
        // Keep roots apart so each is well conditioned.
        prop_assume!(roots.windows(2).all(|w| w[1] - w[0] > 0.5));
        prop_assume!(roots.iter().all(|r| r.abs() > 1e-3));
        let p = planted(scale, &roots);
        let found = roots_after_zero(&p);
        let expected: Vec<f64> = roots.iter().copied().filter(|&r| r > 0.0).collect();
        prop_assert_eq!(found.len(), expected.len(), "{:?} from {:?}", found, p);
        let mut before = p.sign_just_after_zero();
        for (r, want) in found.iter().zip(&expected) {
            prop_assert!(close(r.tau, *want, 1e-9), "root {} vs planted {}", r.tau, want);
            prop_assert!(r.is_sign_change());
            prop_assert_eq!(r.before, before);
            before = r.after;
        }
        prop_assert_eq!(first_sign_change(&p).is_some(), !expected.is_empty());
    }

    #[test]
    fn planted_double_root_is_a_touch(r in 0.1f64..100.0, other in -100.0f64..-0.1, scale in 0.01f64..100.0) {
        // scale (tau - r)^2 (tau - other): a touch at r, no sign change after zero.
        let p = planted(scale, &[r, r, other]);
        let found = roots_after_zero(&p);
        prop_assert!(first_sign_change(&p).is_none() || found.iter().all(|x| close(x.tau, r, 1e-6)),
            "double root {} gave {:?}", r, found);
    }

    #[test]
    fn sign_between_roots_matches_evaluation(roots in prop::collection::vec(0.5f64..20.0, 1..=4)) {
        let mut roots = roots;
        roots.sort_by(f64::total_cmp);
        prop_assume!(roots.windows(2).all(|w| w[1] - w[0] > 0.2));
        let p = planted(1.0, &roots);
        let found = roots_after_zero(&p);
        for r in found.iter() {
            let probe = r.tau + 0.05;
            prop_assert_eq!(kinetic_core::kds::sign(p.eval(probe)), r.after);
        }
    }
}

#[test]
fn root_exactly_at_zero_is_not_reported() {
    // tau (tau - 2): the root at 0 is the present, not the future.
    let p = planted(1.0, &[0.0, 2.0]);
    let r = roots_after_zero(&p);
    assert_eq!(r.len(), 1);
    assert_eq!(r.get(0).unwrap().tau, 2.0);
    assert_eq!(p.sign_just_after_zero(), -1);
}

#[test]
fn double_root_of_a_quadratic_is_a_touch() {
    let p = Poly::new(&[25.0, -10.0, 1.0]); // (tau - 5)^2
    let r = roots_after_zero(&p);
    assert_eq!(r.len(), 1);
    let root = r.get(0).unwrap();
    assert_eq!((root.tau, root.before, root.after), (5.0, 1, 1));
    assert_eq!(first_sign_change(&p), None);
}

#[test]
fn double_root_of_a_quartic_is_a_touch() {
    // (tau - 1)^2 (tau - 3)^2: two touches, no sign change.
    let p = planted(1.0, &[1.0, 1.0, 3.0, 3.0]);
    assert_eq!(first_sign_change(&p), None);
    let r = roots_after_zero(&p);
    assert!(r.iter().all(|x| !x.is_sign_change()));
    assert!(r.iter().any(|x| close(x.tau, 1.0, 1e-9)) && r.iter().any(|x| close(x.tau, 3.0, 1e-9)));
}

#[test]
fn clustered_roots_are_separated() {
    let roots = [1.0, 1.0 + 1e-6, 2.0, 2.0 + 1e-6];
    let p = planted(1.0, &roots);
    let found: Vec<f64> = roots_after_zero(&p).iter().map(|r| r.tau).collect();
    assert_eq!(found.len(), 4, "{found:?}");
    // Conditioning bound: coefficient rounding (~1e-16 * 10) over |p'(root)| (~1e-6) gives
    // ~2e-9; nothing in f64 can do better from these coefficients.
    for (f, r) in found.iter().zip(roots) {
        assert!((f - r).abs() < 1e-8, "{f} vs {r}");
    }
}

#[test]
fn huge_and_tiny_coefficients() {
    // Roots at 1e-9 and 1e9 in one quadratic.
    let p = planted(1.0, &[1e-9, 1e9]);
    let found: Vec<f64> = roots_after_zero(&p).iter().map(|r| r.tau).collect();
    assert!(
        close(found[0], 1e-9, 1e-12) && (found[0] - 1e-9).abs() < 1e-20,
        "{found:?}"
    );
    assert!((found[1] - 1e9).abs() < 1e-6 * 1e9, "{found:?}");
    // A quartic with a tiny leading coefficient: a huge Cauchy bound.
    let p = Poly::new(&[-1.0, 1.0, 0.0, 0.0, 1e-30]);
    let first = first_sign_change(&p).unwrap();
    assert!(close(first, 1.0, 1e-12), "{first}");
    // Coefficients near overflow.
    let p = Poly::new(&[1e300, -2e300, 1e300 / 4.0]); // roots of tau^2/4 - 2 tau + 1
    let first = first_sign_change(&p).unwrap();
    assert!(close(first, 4.0 - 12f64.sqrt(), 1e-12), "{first}");
}

#[test]
fn constant_and_zero_polynomials_never_change_sign() {
    assert_eq!(first_sign_change(&Poly::ZERO), None);
    assert_eq!(first_sign_change(&Poly::new(&[3.0])), None);
    assert_eq!(first_sign_change(&Poly::new(&[-3.0])), None);
}

#[test]
fn odd_order_critical_root_is_a_sign_change() {
    // (tau - 2)^3 changes sign at 2 even though p' vanishes there too.
    let p = planted(1.0, &[2.0, 2.0, 2.0]);
    let first = first_sign_change(&p).unwrap();
    assert!((first - 2.0).abs() < 1e-4, "{first}");
}
