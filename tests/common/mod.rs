//! Plane geometry shared by the TRC test files. Written here, not taken from the kernel, so
//! that the tests check softnc against geometry of their own.
#![allow(dead_code)] // each test file uses a different part

pub type P = [f64; 2];

pub fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1]]
}
pub fn add(a: P, b: P) -> P {
    [a[0] + b[0], a[1] + b[1]]
}
pub fn mul(a: P, k: f64) -> P {
    [a[0] * k, a[1] * k]
}
pub fn cross(a: P, b: P) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
pub fn dot(a: P, b: P) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
pub fn len(a: P) -> f64 {
    a[0].hypot(a[1])
}
pub fn dist(a: P, b: P) -> f64 {
    len(sub(a, b))
}
pub fn unit(a: P) -> P {
    mul(a, 1.0 / len(a))
}
/// Rotated by +90°.
pub fn left(a: P) -> P {
    [-a[1], a[0]]
}
pub fn xy(p: [f64; 3]) -> P {
    [p[0], p[1]]
}

/// A programmed element as traversed.
#[derive(Clone, Copy, Debug)]
pub enum El {
    Line { a: P, b: P },
    Arc { a: P, b: P, c: P, ccw: bool },
}

impl El {
    pub fn a(&self) -> P {
        match *self {
            El::Line { a, .. } | El::Arc { a, .. } => a,
        }
    }
    pub fn b(&self) -> P {
        match *self {
            El::Line { b, .. } | El::Arc { b, .. } => b,
        }
    }
}
