//! Numbers that carry their first and second derivatives with respect to
//! `N` local unknowns (forward automatic differentiation to second order):
//! the mortar integrals are written once, and their gradients (the
//! constraint rows) and Hessians (the contact part of the tangent) are
//! exact to round-off, whatever the segmentation, projections and normals
//! they pass through.
//!
//! A Hessian is symmetric: only its upper triangle (`h[i][j]`, `j >= i`)
//! is computed and read (`hessian`); the lower one stays zero.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A value with its gradient and Hessian over `N` unknowns.
#[derive(Clone, Copy, Debug)]
pub(super) struct Dual<const N: usize> {
    pub v: f64,
    pub g: [f64; N],
    pub h: [[f64; N]; N],
}

impl<const N: usize> Dual<N> {
    /// A constant.
    pub fn c(v: f64) -> Self {
        Dual {
            v,
            g: [0.0; N],
            h: [[0.0; N]; N],
        }
    }

    /// Unknown `i` at the value `v`.
    pub fn var(v: f64, i: usize) -> Self {
        let mut d = Self::c(v);
        d.g[i] = 1.0;
        d
    }

    /// `f(self)` from `f`, `f'` and `f''` at `self.v` (the chain rule).
    fn chain(&self, f: f64, df: f64, d2f: f64) -> Self {
        let mut out = Self::c(f);
        for i in 0..N {
            out.g[i] = df * self.g[i];
            for j in i..N {
                out.h[i][j] = df * self.h[i][j] + d2f * self.g[i] * self.g[j];
            }
        }
        out
    }

    pub fn sqrt(&self) -> Self {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s, -0.25 / (s * self.v))
    }

    pub fn recip(&self) -> Self {
        let r = 1.0 / self.v;
        self.chain(r, -r * r, 2.0 * r * r * r)
    }

    /// Entry (i, j) of the Hessian.
    pub fn hessian(&self, i: usize, j: usize) -> f64 {
        self.h[i.min(j)][i.max(j)]
    }

    /// `self * k` for a plain number `k`.
    pub fn scale(&self, k: f64) -> Self {
        let mut out = *self;
        out.v *= k;
        for i in 0..N {
            out.g[i] *= k;
            for j in i..N {
                out.h[i][j] *= k;
            }
        }
        out
    }
}

impl<const N: usize> Add for Dual<N> {
    type Output = Self;
    fn add(mut self, b: Self) -> Self {
        self.v += b.v;
        for i in 0..N {
            self.g[i] += b.g[i];
            for j in i..N {
                self.h[i][j] += b.h[i][j];
            }
        }
        self
    }
}

impl<const N: usize> Sub for Dual<N> {
    type Output = Self;
    fn sub(self, b: Self) -> Self {
        self + (-b)
    }
}

impl<const N: usize> Neg for Dual<N> {
    type Output = Self;
    fn neg(self) -> Self {
        self.scale(-1.0)
    }
}

impl<const N: usize> Mul for Dual<N> {
    type Output = Self;
    fn mul(self, b: Self) -> Self {
        let mut out = Self::c(self.v * b.v);
        for i in 0..N {
            out.g[i] = self.v * b.g[i] + b.v * self.g[i];
            for j in i..N {
                out.h[i][j] = self.v * b.h[i][j]
                    + b.v * self.h[i][j]
                    + self.g[i] * b.g[j]
                    + b.g[i] * self.g[j];
            }
        }
        out
    }
}

impl<const N: usize> Div for Dual<N> {
    type Output = Self;
    #[allow(clippy::suspicious_arithmetic_impl)]
    fn div(self, b: Self) -> Self {
        self * b.recip()
    }
}

impl<const N: usize> Add<f64> for Dual<N> {
    type Output = Self;
    fn add(mut self, b: f64) -> Self {
        self.v += b;
        self
    }
}

impl<const N: usize> Mul<f64> for Dual<N> {
    type Output = Self;
    fn mul(self, k: f64) -> Self {
        self.scale(k)
    }
}

/// A 2-vector of dual numbers.
#[derive(Clone, Copy, Debug)]
pub(super) struct V2<const N: usize>(pub Dual<N>, pub Dual<N>);

impl<const N: usize> V2<N> {
    pub fn c(x: [f64; 2]) -> Self {
        V2(Dual::c(x[0]), Dual::c(x[1]))
    }

    pub fn zero() -> Self {
        Self::c([0.0; 2])
    }

    pub fn dot(&self, b: &Self) -> Dual<N> {
        self.0 * b.0 + self.1 * b.1
    }

    /// The z component of `self x b`.
    pub fn cross(&self, b: &Self) -> Dual<N> {
        self.0 * b.1 - self.1 * b.0
    }

    pub fn norm(&self) -> Dual<N> {
        self.dot(self).sqrt()
    }

    pub fn scale(&self, k: Dual<N>) -> Self {
        V2(self.0 * k, self.1 * k)
    }

    pub fn unit(&self) -> Self {
        self.scale(self.norm().recip())
    }

    /// Turned by -90 degrees: the outward normal of a tangent that has its
    /// body on the left.
    pub fn right(&self) -> Self {
        V2(self.1, -self.0)
    }

    pub fn value(&self) -> [f64; 2] {
        [self.0.v, self.1.v]
    }
}

impl<const N: usize> Add for V2<N> {
    type Output = Self;
    fn add(self, b: Self) -> Self {
        V2(self.0 + b.0, self.1 + b.1)
    }
}

impl<const N: usize> Sub for V2<N> {
    type Output = Self;
    fn sub(self, b: Self) -> Self {
        V2(self.0 - b.0, self.1 - b.1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// f(x, y) = sqrt(x^2 + y^2) / (x y) + x: the gradient and Hessian
    /// against central differences of the closed forms.
    #[test]
    fn second_derivatives_match_the_closed_form() {
        let f = |x: Dual<2>, y: Dual<2>| (x * x + y * y).sqrt() / (x * y) + x;
        let (x0, y0) = (1.3, 0.7);
        let d = f(Dual::var(x0, 0), Dual::var(y0, 1));
        let r = (x0 * x0 + y0 * y0).sqrt();
        let fx = x0 / (r * x0 * y0) - r / (x0 * x0 * y0) + 1.0;
        assert!((d.g[0] - fx).abs() < 1e-12, "{} vs {fx}", d.g[0]);
        let plain = |x: f64, y: f64| (x * x + y * y).sqrt() / (x * y) + x;
        let e = 1e-4;
        let fxy = (plain(x0 + e, y0 + e) - plain(x0 + e, y0 - e) - plain(x0 - e, y0 + e)
            + plain(x0 - e, y0 - e))
            / (4.0 * e * e);
        let fxx = (plain(x0 + e, y0) - 2.0 * plain(x0, y0) + plain(x0 - e, y0)) / (e * e);
        assert!((d.hessian(0, 1) - fxy).abs() < 1e-6 * fxy.abs().max(1.0));
        assert!((d.hessian(1, 0) - fxy).abs() < 1e-6 * fxy.abs().max(1.0));
        assert!((d.hessian(0, 0) - fxx).abs() < 1e-6 * fxx.abs().max(1.0));
    }
}
