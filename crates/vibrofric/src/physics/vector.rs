//! In-plane vectors: `f64` for a longitudinal contact (x only), [`Planar`] for the sliding plane.
//!
//! The friction laws are written once over this trait; a longitudinal contact compiles to scalar
//! arithmetic with no second component.

use std::ops::{Add, Mul, Neg, Sub};

/// A vector of the sliding plane, or its x component alone.
pub trait Vector:
    Copy
    + Default
    + std::fmt::Debug
    + PartialEq
    + Add<Output = Self>
    + Sub<Output = Self>
    + Neg<Output = Self>
    + Mul<f64, Output = Self>
    + Send
    + Sync
    + 'static
{
    /// Number of components (1 or 2).
    const DIM: usize;
    fn from_xy(x: f64, y: f64) -> Self;
    fn x(self) -> f64;
    fn y(self) -> f64;
    fn dot(self, other: Self) -> f64;
    /// Euclidean norm (the absolute value in 1-D).
    fn norm(self) -> f64;
    fn read(slice: &[f64]) -> Self;
    fn write(self, slice: &mut [f64]);
}

impl Vector for f64 {
    const DIM: usize = 1;
    #[inline(always)]
    fn from_xy(x: f64, _y: f64) -> Self {
        x
    }
    #[inline(always)]
    fn x(self) -> f64 {
        self
    }
    #[inline(always)]
    fn y(self) -> f64 {
        0.0
    }
    #[inline(always)]
    fn dot(self, other: Self) -> f64 {
        self * other
    }
    #[inline(always)]
    fn norm(self) -> f64 {
        self.abs()
    }
    #[inline(always)]
    fn read(slice: &[f64]) -> Self {
        slice[0]
    }
    #[inline(always)]
    fn write(self, slice: &mut [f64]) {
        slice[0] = self;
    }
}

/// A vector of the sliding plane.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Planar {
    pub x: f64,
    pub y: f64,
}

impl Add for Planar {
    type Output = Planar;
    #[inline(always)]
    fn add(self, o: Planar) -> Planar {
        Planar {
            x: self.x + o.x,
            y: self.y + o.y,
        }
    }
}

impl Sub for Planar {
    type Output = Planar;
    #[inline(always)]
    fn sub(self, o: Planar) -> Planar {
        Planar {
            x: self.x - o.x,
            y: self.y - o.y,
        }
    }
}

impl Neg for Planar {
    type Output = Planar;
    #[inline(always)]
    fn neg(self) -> Planar {
        Planar {
            x: -self.x,
            y: -self.y,
        }
    }
}

impl Mul<f64> for Planar {
    type Output = Planar;
    #[inline(always)]
    fn mul(self, k: f64) -> Planar {
        Planar {
            x: self.x * k,
            y: self.y * k,
        }
    }
}

impl Vector for Planar {
    const DIM: usize = 2;
    #[inline(always)]
    fn from_xy(x: f64, y: f64) -> Self {
        Planar { x, y }
    }
    #[inline(always)]
    fn x(self) -> f64 {
        self.x
    }
    #[inline(always)]
    fn y(self) -> f64 {
        self.y
    }
    #[inline(always)]
    fn dot(self, o: Self) -> f64 {
        self.x * o.x + self.y * o.y
    }
    /// `sqrt(x² + y²)` directly: `hypot`'s guard against overflow is a library call that cost
    /// 7 % of a planar run, and the squares of velocities and deformations (|v| ≥ 1e-150,
    /// ≤ 1e150) neither overflow nor underflow; below that the norm rounds to 0 harmlessly.
    #[inline(always)]
    fn norm(self) -> f64 {
        (self.x * self.x + self.y * self.y).sqrt()
    }
    #[inline(always)]
    fn read(slice: &[f64]) -> Self {
        Planar {
            x: slice[0],
            y: slice[1],
        }
    }
    #[inline(always)]
    fn write(self, slice: &mut [f64]) {
        slice[0] = self.x;
        slice[1] = self.y;
    }
}
