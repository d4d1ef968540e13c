//! A two-component vector over any [`Real`].

use crate::numbers::real::Real;

/// A point or velocity in the plane.
#[derive(Debug, Clone, PartialEq)]
pub struct Vec2<T> {
    /// x component.
    pub x: T,
    /// y component.
    pub y: T,
}

impl<T: Real> Vec2<T> {
    /// `(x, y)`.
    #[inline(always)]
    pub fn new(x: T, y: T) -> Self {
        Vec2 { x, y }
    }
    /// From `f64` components, exactly.
    pub fn from_f64(ctx: T::Ctx, x: f64, y: f64) -> Self {
        Vec2 {
            x: T::from_f64(ctx, x),
            y: T::from_f64(ctx, y),
        }
    }
    /// Nearest `f64` components.
    pub fn to_f64(&self) -> [f64; 2] {
        [self.x.to_f64(), self.y.to_f64()]
    }
    /// `self − o`.
    #[inline(always)]
    pub fn sub(&self, o: &Self) -> Self {
        Vec2 {
            x: self.x.clone() - &o.x,
            y: self.y.clone() - &o.y,
        }
    }
    /// `self · o` (two products, one sum: each correctly rounded).
    #[inline(always)]
    pub fn dot(&self, o: &Self) -> T {
        self.x.clone() * &o.x + &(self.y.clone() * &o.y)
    }
    /// `self × o = x·o.y − y·o.x`.
    #[inline(always)]
    pub fn cross(&self, o: &Self) -> T {
        self.x.clone() * &o.y - &(self.y.clone() * &o.x)
    }
    /// `|self|²`.
    #[inline(always)]
    pub fn norm2(&self) -> T {
        self.x.square() + &self.y.square()
    }
    /// `self + t·d` (the point reached after time `t` along velocity `d`).
    #[inline(always)]
    pub fn along(&self, t: &T, d: &Self) -> Self {
        Vec2 {
            x: self.x.clone() + &(d.x.clone() * t),
            y: self.y.clone() + &(d.y.clone() * t),
        }
    }
}

impl<T: Real> std::ops::Neg for Vec2<T> {
    type Output = Self;
    /// `−self` (exact).
    #[inline(always)]
    fn neg(self) -> Self {
        Vec2 {
            x: -self.x,
            y: -self.y,
        }
    }
}
