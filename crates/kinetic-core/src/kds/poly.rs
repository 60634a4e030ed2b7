//! Polynomials of degree at most 4 in local time `tau = t - t0`.
//!
//! Every certificate in this crate is a polynomial that is non-negative while the certified
//! fact holds. Its coefficients are always expressed around the time the certificate was made,
//! so that `c[0]` is the exact value at that time and the signs of the coefficients decide what
//! happens "just after" it without any epsilon.

/// A polynomial `c[0] + c[1] tau + c[2] tau^2 + c[3] tau^3 + c[4] tau^4`.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Poly {
    /// Coefficients, lowest degree first.
    pub c: [f64; 5],
}

impl Poly {
    /// The zero polynomial.
    pub const ZERO: Poly = Poly { c: [0.0; 5] };

    /// A polynomial from its coefficients, lowest degree first (at most 5 of them).
    ///
    /// ```
    /// # use kinetic_core::kds::Poly;
    /// let p = Poly::new(&[-1.0, 0.0, 1.0]); // tau^2 - 1
    /// assert_eq!(p.eval(2.0), 3.0);
    /// ```
    ///
    /// # Panics
    /// If more than five coefficients are given (a programming error, not user input).
    pub fn new(coefficients: &[f64]) -> Poly {
        assert!(
            coefficients.len() <= 5,
            "a certificate polynomial has degree at most 4"
        );
        let mut c = [0.0; 5];
        c[..coefficients.len()].copy_from_slice(coefficients);
        Poly { c }
    }

    /// The degree, or `None` for the zero polynomial.
    pub fn degree(&self) -> Option<usize> {
        self.c.iter().rposition(|&x| x != 0.0)
    }

    /// The value at `tau`, by Horner's rule.
    #[inline]
    pub fn eval(&self, tau: f64) -> f64 {
        let c = &self.c;
        (((c[4] * tau + c[3]) * tau + c[2]) * tau + c[1]) * tau + c[0]
    }

    /// The derivative.
    pub fn derivative(&self) -> Poly {
        let c = &self.c;
        Poly {
            c: [c[1], 2.0 * c[2], 3.0 * c[3], 4.0 * c[4], 0.0],
        }
    }

    /// `-p`: exact, so a certificate and its reversal always disagree about the sign.
    pub fn neg(&self) -> Poly {
        Poly {
            c: self.c.map(|x| -x),
        }
    }

    /// The sign of the polynomial just after `tau = 0`: the sign of its first non-zero
    /// coefficient (-1, 0 for the zero polynomial, or 1). Exact, no tolerance.
    pub fn sign_just_after_zero(&self) -> i8 {
        self.c.iter().find(|&&x| x != 0.0).map_or(0, |&x| sign(x))
    }
}

/// The sign of `x` as -1, 0 or 1 (`-0.0` counts as 0).
#[inline]
pub fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}
