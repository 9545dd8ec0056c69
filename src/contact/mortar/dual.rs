//! Numbers that carry their first and second derivatives with respect to
//! `N` local unknowns (forward automatic differentiation to second order):
//! the mortar integrals are written once, and their gradients (the
//! constraint rows) and Hessians (the contact part of the tangent) are
//! exact to round-off, whatever the segmentation, projections and normals
//! they pass through.
//!
//! Most values depend on a few of the unknowns only (a contactor node's
//! position on 2, a nodal normal on the 6 to 10 of its sides' nodes, a
//! constant on none), so each value carries its span: the range
//! `lo..hi` of unknowns outside which its gradient and Hessian are zero.
//! Operations work over the spans of their operands only (over all `N`
//! unknowns, the common case once a projection mixes both sides, in loops
//! of compile-time bounds, which vectorize). The gradient is
//! stored whole (zero outside the span); the Hessian is symmetric, and
//! only its upper triangle is stored, packed row by row (`H = N (N + 1) /
//! 2` entries: the values are copied and moved whole, so the storage is
//! what each copy costs). Only its entries within the span (`(i, j)`, `lo
//! <= i <= j < hi`) are computed and read (`hessian`): entries outside it
//! hold stale numbers, and a span that widens zeroes the entries it takes
//! in first. Operations update their left operand in place (it is taken by
//! value), so that a result is not built in a fresh, zero-filled value.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A value with its gradient and Hessian over `N` unknowns; `H` is the
/// size of the Hessian's packed upper triangle, `N (N + 1) / 2`, or 0: a
/// value of the first order, with no Hessian (`hessian` is not to be
/// called on it).
#[derive(Clone, Copy, Debug)]
pub(super) struct Dual<const N: usize, const H: usize> {
    pub v: f64,
    /// The gradient: zero outside `lo..hi`.
    pub g: [f64; N],
    /// The Hessian's upper triangle, row `i` (columns `i..N`) from
    /// `start::<N>(i)`, meaningful within `lo..hi` only.
    h: [f64; H],
    /// The span of unknowns the value depends on (empty: `lo == hi`).
    lo: usize,
    hi: usize,
}

/// Where row `i` of an upper triangle of order `n`, packed row by row,
/// starts (at its diagonal entry).
#[inline(always)]
const fn start<const N: usize>(i: usize) -> usize {
    i * (2 * N + 1 - i) / 2
}

/// The smallest span that holds spans `a` and `b` (an empty one holds
/// nothing).
fn union(a: (usize, usize), b: (usize, usize)) -> (usize, usize) {
    if a.0 == a.1 {
        b
    } else if b.0 == b.1 {
        a
    } else {
        (a.0.min(b.0), a.1.max(b.1))
    }
}

impl<const N: usize, const H: usize> Dual<N, H> {
    /// `H` is the packed triangle's size or 0 (checked when the type is
    /// used).
    const PACKED: () = assert!(
        H == 0 || H == N * (N + 1) / 2,
        "H must be N (N + 1) / 2, or 0"
    );
    /// Whether the value carries its Hessian.
    const SECOND: bool = H > 0;
    /// A first-order value's operations are called, not inlined: their
    /// loops over the gradient, inlined into every expression, made the
    /// first-order integrals the largest function of the FMU's library
    /// (issue 15 keeps the Hertz FMU under 2 MB). Plain numbers (`N = 0`)
    /// and second-order values inline as the compiler decides.
    const OUTLINED: bool = N > 0 && H == 0;

    /// A constant.
    pub fn c(v: f64) -> Self {
        if Self::OUTLINED {
            Self::c_outlined(v)
        } else {
            Self::c_body(v)
        }
    }

    #[inline(never)]
    fn c_outlined(v: f64) -> Self {
        Self::c_body(v)
    }

    fn c_body(v: f64) -> Self {
        let () = Self::PACKED;
        Dual {
            v,
            g: [0.0; N],
            h: [0.0; H],
            lo: 0,
            hi: 0,
        }
    }

    /// Unknown `i` at the value `v`.
    pub fn var(v: f64, i: usize) -> Self {
        let mut d = Self::c(v);
        d.g[i] = 1.0;
        (d.lo, d.hi) = (i, i + 1);
        d
    }

    fn span(&self) -> (usize, usize) {
        (self.lo, self.hi)
    }

    /// Row `i` of the Hessian's upper triangle, columns `i..to`.
    #[inline(always)]
    fn row(&self, i: usize, to: usize) -> &[f64] {
        let s = start::<N>(i);
        &self.h[s..s + to - i]
    }

    #[inline(always)]
    fn row_mut(&mut self, i: usize, to: usize) -> &mut [f64] {
        let s = start::<N>(i);
        &mut self.h[s..s + to - i]
    }

    /// Widens the span to `lo..hi` (which holds it), zeroing the
    /// Hessian's entries it takes in (the gradient's are zero already).
    fn widen(&mut self, (lo, hi): (usize, usize)) {
        if (lo, hi) == self.span() {
            return;
        }
        if !Self::SECOND {
            (self.lo, self.hi) = (lo, hi);
            return;
        }
        let (a, b) = if self.lo == self.hi {
            (hi, hi)
        } else {
            self.span()
        };
        for i in lo..hi {
            let row = self.row_mut(i, hi);
            if i < a || i >= b {
                row.fill(0.0);
            } else {
                row[b - i..].fill(0.0);
            }
        }
        (self.lo, self.hi) = (lo, hi);
    }

    /// The end of the columns of row `i` that lie in the span's square
    /// (`i` itself: none).
    fn row_end(&self, i: usize) -> usize {
        if self.lo <= i && i < self.hi {
            self.hi
        } else {
            i
        }
    }

    /// `self += k b`.
    fn add_scaled(&mut self, k: f64, b: &Self) {
        if Self::OUTLINED {
            self.add_scaled_outlined(k, b)
        } else {
            self.add_scaled_body(k, b)
        }
    }

    #[inline(never)]
    fn add_scaled_outlined(&mut self, k: f64, b: &Self) {
        self.add_scaled_body(k, b)
    }

    fn add_scaled_body(&mut self, k: f64, b: &Self) {
        self.v += k * b.v;
        let (blo, bhi) = b.span();
        if blo == bhi {
            return;
        }
        let (lo, hi) = union(self.span(), (blo, bhi));
        if !Self::SECOND {
            (self.lo, self.hi) = (lo, hi);
        } else if self.span() == (0, N) && (blo, bhi) == (0, N) {
            for (h, bh) in self.h.iter_mut().zip(&b.h) {
                *h += k * bh;
            }
        } else if (lo, hi) == (blo, bhi) {
            // b's span holds self's: one pass, which sets the entries
            // outside self's.
            for i in lo..hi {
                let end = self.row_end(i);
                let (old, new) = self.row_mut(i, hi).split_at_mut(end - i);
                let (bold, bnew) = b.row(i, hi).split_at(end - i);
                for (h, bh) in old.iter_mut().zip(bold) {
                    *h += k * bh;
                }
                for (h, bh) in new.iter_mut().zip(bnew) {
                    *h = k * bh;
                }
            }
            (self.lo, self.hi) = (lo, hi);
        } else {
            self.widen((lo, hi));
            for i in blo..bhi {
                for (h, bh) in self.row_mut(i, bhi).iter_mut().zip(b.row(i, bhi)) {
                    *h += k * bh;
                }
            }
        }
        for (g, bg) in self.g[blo..bhi].iter_mut().zip(&b.g[blo..bhi]) {
            *g += k * bg;
        }
    }

    /// `self += k a b`, with no product formed apart.
    pub fn add_product(&mut self, k: f64, a: &Self, b: &Self) {
        if Self::OUTLINED {
            self.add_product_outlined(k, a, b)
        } else {
            self.add_product_body(k, a, b)
        }
    }

    #[inline(never)]
    fn add_product_outlined(&mut self, k: f64, a: &Self, b: &Self) {
        self.add_product_body(k, a, b)
    }

    fn add_product_body(&mut self, k: f64, a: &Self, b: &Self) {
        let (av, bv) = (k * a.v, k * b.v);
        self.v += av * b.v;
        let (alo, ahi) = a.span();
        let (blo, bhi) = b.span();
        let ab = union((alo, ahi), (blo, bhi));
        if ab.0 == ab.1 {
            return;
        }
        if Self::SECOND && self.span() == (0, N) && (alo, ahi) == (0, N) && (blo, bhi) == (0, N) {
            for i in 0..N {
                let (ag, bg) = (k * a.g[i], k * b.g[i]);
                let s = start::<N>(i);
                let rows = (self.h[s..s + N - i].iter_mut())
                    .zip(&a.h[s..s + N - i])
                    .zip(&b.h[s..s + N - i]);
                let cols = a.g[i..].iter().zip(&b.g[i..]);
                for (((h, ah), bh), (agj, bgj)) in rows.zip(cols) {
                    *h += bv * ah + av * bh + ag * bgj + bg * agj;
                }
            }
            for i in 0..N {
                self.g[i] += av * b.g[i] + bv * a.g[i];
            }
            return;
        }
        self.widen(union(self.span(), ab));
        if Self::SECOND {
            self.add_product_hessian(k, a, b);
        }
        let (lo, hi) = ab;
        for ((g, ag), bg) in self.g[lo..hi]
            .iter_mut()
            .zip(&a.g[lo..hi])
            .zip(&b.g[lo..hi])
        {
            *g += av * bg + bv * ag;
        }
    }

    /// `add_product`'s Hessian terms over the operands' spans (`self`
    /// widened to hold them).
    fn add_product_hessian(&mut self, k: f64, a: &Self, b: &Self) {
        let (av, bv) = (k * a.v, k * b.v);
        let (alo, ahi) = a.span();
        let (blo, bhi) = b.span();
        let ab = union((alo, ahi), (blo, bhi));
        for i in alo..ahi {
            for (h, ah) in self.row_mut(i, ahi).iter_mut().zip(a.row(i, ahi)) {
                *h += bv * ah;
            }
        }
        for i in blo..bhi {
            for (h, bh) in self.row_mut(i, bhi).iter_mut().zip(b.row(i, bhi)) {
                *h += av * bh;
            }
        }
        if alo != ahi && blo != bhi {
            let (lo, hi) = ab;
            for i in lo..hi {
                let (ag, bg) = (k * a.g[i], k * b.g[i]);
                let cols = a.g[i..hi].iter().zip(&b.g[i..hi]);
                for (h, (agj, bgj)) in self.row_mut(i, hi).iter_mut().zip(cols) {
                    *h += ag * bgj + bg * agj;
                }
            }
        }
    }

    /// `self += k a b` in the value and gradient alone, as `add_product`
    /// forms them: the Hessian is left undefined, for a sum whose Hessian
    /// is never read (`hessian` on it is meaningless).
    pub fn add_product_first_order(&mut self, k: f64, a: &Self, b: &Self) {
        let (av, bv) = (k * a.v, k * b.v);
        self.v += av * b.v;
        let ab = union(a.span(), b.span());
        if ab.0 == ab.1 {
            return;
        }
        let (lo, hi) = ab;
        for ((g, ag), bg) in self.g[lo..hi]
            .iter_mut()
            .zip(&a.g[lo..hi])
            .zip(&b.g[lo..hi])
        {
            *g += av * bg + bv * ag;
        }
        (self.lo, self.hi) = union(self.span(), ab);
    }

    /// `self *= k` for a plain number `k`; by zero, a constant.
    fn scale_in_place(&mut self, k: f64) {
        if Self::OUTLINED {
            self.scale_in_place_outlined(k)
        } else {
            self.scale_in_place_body(k)
        }
    }

    #[inline(never)]
    fn scale_in_place_outlined(&mut self, k: f64) {
        self.scale_in_place_body(k)
    }

    fn scale_in_place_body(&mut self, k: f64) {
        self.v *= k;
        let (lo, hi) = self.span();
        if k == 0.0 {
            self.g[lo..hi].fill(0.0);
            (self.lo, self.hi) = (0, 0);
            return;
        }
        for i in lo..hi {
            self.g[i] *= k;
            if Self::SECOND {
                for h in self.row_mut(i, hi) {
                    *h *= k;
                }
            }
        }
    }

    /// `self *= b`: `(a b)'' = a b'' + b a'' + a' b'^T + b' a'^T`.
    fn mul_in_place(&mut self, b: &Self) {
        if Self::OUTLINED {
            self.mul_in_place_outlined(b)
        } else {
            self.mul_in_place_body(b)
        }
    }

    #[inline(never)]
    fn mul_in_place_outlined(&mut self, b: &Self) {
        self.mul_in_place_body(b)
    }

    fn mul_in_place_body(&mut self, b: &Self) {
        let (av, bv) = (self.v, b.v);
        let (alo, ahi) = self.span();
        let (blo, bhi) = b.span();
        if blo == bhi {
            return self.scale_in_place(bv);
        }
        let (lo, hi) = union((alo, ahi), (blo, bhi));
        if !Self::SECOND {
            (self.lo, self.hi) = (lo, hi);
        } else if (alo, ahi) == (0, N) && (blo, bhi) == (0, N) {
            // Both over all unknowns: bounds known at compile time.
            for i in 0..N {
                let (ag, bg) = (self.g[i], b.g[i]);
                let s = start::<N>(i);
                let rows = self.h[s..s + N - i].iter_mut().zip(&b.h[s..s + N - i]);
                let cols = self.g[i..].iter().zip(&b.g[i..]);
                for ((h, bh), (agj, bgj)) in rows.zip(cols) {
                    *h = bv * *h + av * bh + ag * bgj + bg * agj;
                }
            }
        } else if (lo, hi) == (blo, bhi) {
            // b's span holds self's: one pass, which sets the entries
            // outside self's.
            for i in lo..hi {
                let (ag, bg) = (self.g[i], b.g[i]);
                let end = self.row_end(i) - i;
                let s = start::<N>(i);
                let (old, new) = self.h[s..s + hi - i].split_at_mut(end);
                let (bold, bnew) = b.row(i, hi).split_at(end);
                let (gold, gnew) = (self.g[i..hi].split_at(end), b.g[i..hi].split_at(end));
                let cols = gold.0.iter().zip(gnew.0);
                for ((h, bh), (agj, bgj)) in old.iter_mut().zip(bold).zip(cols) {
                    *h = bv * *h + av * bh + ag * bgj + bg * agj;
                }
                let cols = gold.1.iter().zip(gnew.1);
                for ((h, bh), (agj, bgj)) in new.iter_mut().zip(bnew).zip(cols) {
                    *h = av * bh + ag * bgj + bg * agj;
                }
            }
            (self.lo, self.hi) = (lo, hi);
        } else if (lo, hi) == (alo, ahi) {
            // Self's span holds b's.
            for i in lo..hi {
                let (ag, bg) = (self.g[i], b.g[i]);
                let end = b.row_end(i) - i;
                let s = start::<N>(i);
                let (inside, outside) = self.h[s..s + hi - i].split_at_mut(end);
                let (gin, gout) = (self.g[i..hi].split_at(end), b.g[i..hi].split_at(end));
                let cols = gin.0.iter().zip(gout.0);
                let bh = b.row(i, i + end);
                for ((h, bh), (agj, bgj)) in inside.iter_mut().zip(bh).zip(cols) {
                    *h = bv * *h + av * bh + ag * bgj + bg * agj;
                }
                let cols = gin.1.iter().zip(gout.1);
                for (h, (agj, bgj)) in outside.iter_mut().zip(cols) {
                    *h = bv * *h + ag * bgj + bg * agj;
                }
            }
        } else {
            for i in alo..ahi {
                for h in self.row_mut(i, ahi) {
                    *h *= bv;
                }
            }
            self.widen((lo, hi));
            for i in blo..bhi {
                for (h, bh) in self.row_mut(i, bhi).iter_mut().zip(b.row(i, bhi)) {
                    *h += av * bh;
                }
            }
            // The outer products: zero outside the spans' crossings.
            for i in lo..hi {
                let (ag, bg) = (self.g[i], b.g[i]);
                let s = start::<N>(i);
                let row = self.h[s..s + hi - i].iter_mut();
                for (h, (agj, bgj)) in row.zip(self.g[i..hi].iter().zip(&b.g[i..hi])) {
                    *h += ag * bgj + bg * agj;
                }
            }
        }
        for (ag, bg) in self.g[lo..hi].iter_mut().zip(&b.g[lo..hi]) {
            *ag = av * bg + bv * *ag;
        }
        self.v = av * bv;
    }

    /// `f(self)` from `f`, `f'` and `f''` at `self.v` (the chain rule).
    fn chain(&mut self, f: f64, df: f64, d2f: f64) {
        if Self::OUTLINED {
            self.chain_outlined(f, df, d2f)
        } else {
            self.chain_body(f, df, d2f)
        }
    }

    #[inline(never)]
    fn chain_outlined(&mut self, f: f64, df: f64, d2f: f64) {
        self.chain_body(f, df, d2f)
    }

    fn chain_body(&mut self, f: f64, df: f64, d2f: f64) {
        let (lo, hi) = self.span();
        if Self::SECOND && (lo, hi) == (0, N) {
            for i in 0..N {
                let gi = d2f * self.g[i];
                let s = start::<N>(i);
                let row = self.h[s..s + N - i].iter_mut().zip(&self.g[i..]);
                for (h, gj) in row {
                    *h = df * *h + gi * gj;
                }
                self.g[i] *= df;
            }
            self.v = f;
            return;
        }
        for i in (lo..hi).filter(|_| Self::SECOND) {
            let gi = d2f * self.g[i];
            let s = start::<N>(i);
            let row = self.h[s..s + hi - i].iter_mut().zip(&self.g[i..hi]);
            for (h, gj) in row {
                *h = df * *h + gi * gj;
            }
        }
        for g in &mut self.g[lo..hi] {
            *g *= df;
        }
        self.v = f;
    }

    fn sqrt_in_place(&mut self) {
        let s = self.v.sqrt();
        self.chain(s, 0.5 / s, -0.25 / (s * self.v));
    }

    fn recip_in_place(&mut self) {
        let r = 1.0 / self.v;
        self.chain(r, -r * r, 2.0 * r * r * r);
    }

    // Integrals take square roots through `V2::norm`; kept for the ones
    // written on values.
    #[allow(dead_code)]
    pub fn sqrt(&self) -> Self {
        let mut out = *self;
        out.sqrt_in_place();
        out
    }

    pub fn recip(&self) -> Self {
        let mut out = *self;
        out.recip_in_place();
        out
    }

    /// Entry (i, j) of the Hessian.
    pub fn hessian(&self, i: usize, j: usize) -> f64 {
        debug_assert!(Self::SECOND, "the Hessian of a first-order value");
        let (i, j) = (i.min(j), i.max(j));
        if self.lo <= i && j < self.hi {
            self.h[start::<N>(i) + j - i]
        } else {
            0.0
        }
    }
}

impl<const N: usize, const H: usize> Add for Dual<N, H> {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, b: Self) -> Self {
        self.add_scaled(1.0, &b);
        self
    }
}

impl<const N: usize, const H: usize> Sub for Dual<N, H> {
    type Output = Self;
    #[inline(always)]
    fn sub(mut self, b: Self) -> Self {
        self.add_scaled(-1.0, &b);
        self
    }
}

impl<const N: usize, const H: usize> Neg for Dual<N, H> {
    type Output = Self;
    #[inline(always)]
    fn neg(mut self) -> Self {
        self.scale_in_place(-1.0);
        self
    }
}

impl<const N: usize, const H: usize> Mul for Dual<N, H> {
    type Output = Self;
    #[inline(always)]
    fn mul(mut self, b: Self) -> Self {
        self.mul_in_place(&b);
        self
    }
}

impl<const N: usize, const H: usize> Div for Dual<N, H> {
    type Output = Self;
    #[allow(clippy::suspicious_arithmetic_impl)]
    #[inline(always)]
    fn div(mut self, mut b: Self) -> Self {
        b.recip_in_place();
        self.mul_in_place(&b);
        self
    }
}

impl<const N: usize, const H: usize> Add<f64> for Dual<N, H> {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, b: f64) -> Self {
        self.v += b;
        self
    }
}

impl<const N: usize, const H: usize> Mul<f64> for Dual<N, H> {
    type Output = Self;
    #[inline(always)]
    fn mul(mut self, k: f64) -> Self {
        self.scale_in_place(k);
        self
    }
}

/// A 2-vector of dual numbers.
#[derive(Clone, Copy, Debug)]
pub(super) struct V2<const N: usize, const H: usize>(pub Dual<N, H>, pub Dual<N, H>);

impl<const N: usize, const H: usize> V2<N, H> {
    pub fn c(x: [f64; 2]) -> Self {
        V2(Dual::c(x[0]), Dual::c(x[1]))
    }

    pub fn zero() -> Self {
        Self::c([0.0; 2])
    }

    #[inline(always)]
    pub fn dot(&self, b: &Self) -> Dual<N, H> {
        let mut d = self.0;
        d.mul_in_place(&b.0);
        d.add_product(1.0, &self.1, &b.1);
        d
    }

    /// The z component of `self x b`.
    #[inline(always)]
    pub fn cross(&self, b: &Self) -> Dual<N, H> {
        let mut d = self.0;
        d.mul_in_place(&b.1);
        d.add_product(-1.0, &self.1, &b.0);
        d
    }

    pub fn norm(&self) -> Dual<N, H> {
        let mut d = self.dot(self);
        d.sqrt_in_place();
        d
    }

    #[inline(always)]
    pub fn scale(&self, k: Dual<N, H>) -> Self {
        let mut out = *self;
        out.0.mul_in_place(&k);
        out.1.mul_in_place(&k);
        out
    }

    pub fn unit(&self) -> Self {
        let mut k = self.norm();
        k.recip_in_place();
        self.scale(k)
    }

    /// Turned by -90 degrees: the outward normal of a tangent that has its
    /// body on the left.
    pub fn right(&self) -> Self {
        let mut out = V2(self.1, self.0);
        out.1.scale_in_place(-1.0);
        out
    }

    pub fn value(&self) -> [f64; 2] {
        [self.0.v, self.1.v]
    }
}

impl<const N: usize, const H: usize> Add for V2<N, H> {
    type Output = Self;
    #[inline(always)]
    fn add(mut self, b: Self) -> Self {
        self.0.add_scaled(1.0, &b.0);
        self.1.add_scaled(1.0, &b.1);
        self
    }
}

impl<const N: usize, const H: usize> Sub for V2<N, H> {
    type Output = Self;
    #[inline(always)]
    fn sub(mut self, b: Self) -> Self {
        self.0.add_scaled(-1.0, &b.0);
        self.1.add_scaled(-1.0, &b.1);
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// f(x, y) = sqrt(x^2 + y^2) / (x y) + x: the gradient and Hessian
    /// against central differences of the closed forms.
    #[test]
    fn second_derivatives_match_the_closed_form() {
        let f = |x: Dual<2, 3>, y: Dual<2, 3>| (x * x + y * y).sqrt() / (x * y) + x;
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

#[cfg(test)]
mod reference {
    //! The spans checked against plain dense arithmetic: the same
    //! expressions in `Dense`, which carries every entry of the gradient
    //! and Hessian through every operation.

    use super::*;

    #[derive(Clone, Copy)]
    struct Dense<const N: usize> {
        v: f64,
        g: [f64; N],
        h: [[f64; N]; N],
    }

    /// What the expressions below need of a number type.
    trait Number:
        Copy
        + Add<Output = Self>
        + Sub<Output = Self>
        + Mul<Output = Self>
        + Div<Output = Self>
        + Neg<Output = Self>
        + Add<f64, Output = Self>
        + Mul<f64, Output = Self>
    {
        fn c(v: f64) -> Self;
        fn var(v: f64, i: usize) -> Self;
        fn sqrt(&self) -> Self;
        fn recip(&self) -> Self;
    }

    impl<const N: usize, const H: usize> Number for Dual<N, H> {
        fn c(v: f64) -> Self {
            Dual::c(v)
        }
        fn var(v: f64, i: usize) -> Self {
            Dual::var(v, i)
        }
        fn sqrt(&self) -> Self {
            Dual::sqrt(self)
        }
        fn recip(&self) -> Self {
            Dual::recip(self)
        }
    }

    impl<const N: usize> Dense<N> {
        fn map(&self, f: f64, df: f64, d2f: f64) -> Self {
            let mut out = Self::c(f);
            for i in 0..N {
                out.g[i] = df * self.g[i];
                for j in 0..N {
                    out.h[i][j] = df * self.h[i][j] + d2f * self.g[i] * self.g[j];
                }
            }
            out
        }
    }

    impl<const N: usize> Number for Dense<N> {
        fn c(v: f64) -> Self {
            Dense {
                v,
                g: [0.0; N],
                h: [[0.0; N]; N],
            }
        }
        fn var(v: f64, i: usize) -> Self {
            let mut d = Self::c(v);
            d.g[i] = 1.0;
            d
        }
        fn sqrt(&self) -> Self {
            let s = self.v.sqrt();
            self.map(s, 0.5 / s, -0.25 / (s * self.v))
        }
        fn recip(&self) -> Self {
            let r = 1.0 / self.v;
            self.map(r, -r * r, 2.0 * r * r * r)
        }
    }

    impl<const N: usize> Add for Dense<N> {
        type Output = Self;
        fn add(mut self, b: Self) -> Self {
            self.v += b.v;
            for i in 0..N {
                self.g[i] += b.g[i];
                for j in 0..N {
                    self.h[i][j] += b.h[i][j];
                }
            }
            self
        }
    }

    impl<const N: usize> Sub for Dense<N> {
        type Output = Self;
        fn sub(self, b: Self) -> Self {
            self + b * -1.0
        }
    }

    impl<const N: usize> Neg for Dense<N> {
        type Output = Self;
        fn neg(self) -> Self {
            self * -1.0
        }
    }

    impl<const N: usize> Mul for Dense<N> {
        type Output = Self;
        fn mul(self, b: Self) -> Self {
            let mut out = Self::c(self.v * b.v);
            for i in 0..N {
                out.g[i] = self.v * b.g[i] + b.v * self.g[i];
                for j in 0..N {
                    out.h[i][j] = self.v * b.h[i][j]
                        + b.v * self.h[i][j]
                        + self.g[i] * b.g[j]
                        + b.g[i] * self.g[j];
                }
            }
            out
        }
    }

    impl<const N: usize> Div for Dense<N> {
        type Output = Self;
        #[allow(clippy::suspicious_arithmetic_impl)]
        fn div(self, b: Self) -> Self {
            self * b.recip()
        }
    }

    impl<const N: usize> Add<f64> for Dense<N> {
        type Output = Self;
        fn add(mut self, b: f64) -> Self {
            self.v += b;
            self
        }
    }

    impl<const N: usize> Mul<f64> for Dense<N> {
        type Output = Self;
        fn mul(self, k: f64) -> Self {
            self.map(self.v * k, k, 0.0)
        }
    }

    /// Compound expressions over unknowns of narrow, overlapping and
    /// disjoint spans, constants among them: products, quotients, square
    /// roots, reciprocals, a unit vector's chain, a product by zero, sums
    /// into constants.
    fn expressions<T: Number>(x: &[f64]) -> Vec<T> {
        let u = |i: usize| T::var(x[i], i);
        let (a, b, c, d) = (u(0), u(1), u(6), u(7));
        let e = u(11) * u(10) + u(10);
        let k = T::c(0.7);
        // A unit vector from a span 0..2 and one 6..8, as a nodal normal.
        let (tx, ty) = (c - a, d - b);
        let r = (tx * tx + ty * ty).sqrt();
        let (nx, ny) = (tx / r, ty * r.recip());
        let p = (k + a * 0.0) * nx + e * ny;
        let q = (p * p + 1.0).sqrt() / (e - k * b + 3.0);
        let s = T::c(0.0) + (-q) * k + (c * 0.0 + 0.5) * d;
        let w = (a * b).recip() - (c - d * 2.0) * (e + q).sqrt();
        let overlapping = (a + c) * (c + e);
        vec![
            k * 2.0 + 1.0,
            a * b,
            e,
            nx,
            ny,
            p,
            q,
            s,
            w,
            s * w / (p + 2.0),
            w * b - a,
            overlapping,
        ]
    }

    #[test]
    fn spans_match_dense_arithmetic() {
        let x = [
            1.3, 0.7, -0.4, 2.1, 0.9, -1.1, 2.6, 1.9, 0.3, -0.8, 1.7, 0.45,
        ];
        let sparse = expressions::<Dual<12, 78>>(&x);
        let dense = expressions::<Dense<12>>(&x);
        for (k, (s, d)) in sparse.iter().zip(&dense).enumerate() {
            let scale = (d.g.iter().chain(d.h.iter().flatten()))
                .fold(d.v.abs(), |m, e| m.max(e.abs()))
                .max(1e-300);
            let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * scale;
            assert!(close(s.v, d.v), "expression {k}: {} vs {}", s.v, d.v);
            for i in 0..12 {
                assert!(close(s.g[i], d.g[i]), "expression {k}, g[{i}]");
                for j in 0..12 {
                    let (a, b) = (s.hessian(i, j), d.h[i][j]);
                    assert!(close(a, b), "expression {k}, h[{i}][{j}]: {a} vs {b}");
                }
            }
        }
        // Spans are narrow where the values are: a x b over 0..2.
        assert_eq!(sparse[0].span(), (0, 0));
        assert_eq!(sparse[1].span(), (0, 2));
        assert_eq!(sparse[2].span(), (10, 12));
    }

    /// A first-order value (no Hessian) has the value and gradient its
    /// second-order twin has, bit for bit: the mortar integrals are made
    /// in the first order at every iterate and again in the second where a
    /// solve needs the tangent, and the two must agree.
    #[test]
    fn first_order_values_match_the_second_order_bit_for_bit() {
        let x = [
            1.3, 0.7, -0.4, 2.1, 0.9, -1.1, 2.6, 1.9, 0.3, -0.8, 1.7, 0.45,
        ];
        let first = expressions::<Dual<12, 0>>(&x);
        let second = expressions::<Dual<12, 78>>(&x);
        for (k, (f, s)) in first.iter().zip(&second).enumerate() {
            assert_eq!(f.v.to_bits(), s.v.to_bits(), "expression {k}");
            assert_eq!(f.span(), s.span(), "expression {k}");
            for i in 0..12 {
                assert_eq!(f.g[i].to_bits(), s.g[i].to_bits(), "expression {k}, g[{i}]");
            }
        }
    }

    /// `add_product` (dot and cross products) against the operators it
    /// stands for, over spans that hold each other, overlap, or are apart.
    #[test]
    fn products_added_in_place_match_the_operators() {
        let x = [
            0.9, -1.2, 0.4, 1.6, 2.2, -0.3, 0.8, 1.1, -0.6, 1.4, 0.25, 1.9,
        ];
        let u = |i: usize| Dual::<12, 78>::var(x[i], i);
        let wide = (u(1) * u(5) + u(2)).sqrt() * u(9) + u(0);
        let narrow = u(3) * u(4) + u(3);
        let other = (u(10) + u(11) * u(8)).recip();
        let values = [Dual::c(1.7), wide, narrow, other, wide * other];
        for acc in &values {
            for a in &values {
                for b in &values {
                    let mut fused = *acc;
                    fused.add_product(-0.8, a, b);
                    // The first-order form: the same value and gradient,
                    // bit for bit.
                    let mut first = *acc;
                    first.add_product_first_order(-0.8, a, b);
                    assert_eq!(first.v.to_bits(), fused.v.to_bits());
                    assert!((0..12).all(|i| first.g[i].to_bits() == fused.g[i].to_bits()
                        || first.g[i] == 0.0 && fused.g[i] == 0.0));
                    let plain = *acc + *a * *b * -0.8;
                    assert!((fused.v - plain.v).abs() <= 1e-12 * plain.v.abs().max(1.0));
                    let scale = (0..12)
                        .flat_map(|i| (0..12).map(move |j| (i, j)))
                        .fold(1.0f64, |m, (i, j)| m.max(plain.hessian(i, j).abs()));
                    for i in 0..12 {
                        assert!(
                            (fused.g[i] - plain.g[i]).abs() <= 1e-12 * scale.max(plain.g[i].abs())
                        );
                        for j in 0..12 {
                            let (f, p) = (fused.hessian(i, j), plain.hessian(i, j));
                            assert!((f - p).abs() <= 1e-12 * scale, "h[{i}][{j}]: {f} vs {p}");
                        }
                    }
                }
            }
        }
    }
}
