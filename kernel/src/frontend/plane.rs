//! Vectors in a working plane, (abscissa, ordinate): the arithmetic the front end's plane
//! geometry shares (corner elements, CIP and CT circles, the smooth approach).

/// A point or a direction in the plane.
pub type V = [f64; 2];

pub fn add(a: V, b: V) -> V {
    [a[0] + b[0], a[1] + b[1]]
}

pub fn sub(a: V, b: V) -> V {
    [a[0] - b[0], a[1] - b[1]]
}

pub fn scale(a: V, k: f64) -> V {
    [a[0] * k, a[1] * k]
}

pub fn dot(a: V, b: V) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

pub fn cross(a: V, b: V) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

pub fn len(a: V) -> f64 {
    libm::hypot(a[0], a[1])
}

pub fn dist(a: V, b: V) -> f64 {
    libm::hypot(a[0] - b[0], a[1] - b[1])
}

/// `a` scaled to length 1 (a zero vector stays zero).
pub fn unit(a: V) -> V {
    let l = len(a);
    if l <= 0.0 {
        a
    } else {
        [a[0] / l, a[1] / l]
    }
}

/// `a` turned 90° counter-clockwise.
pub fn left(a: V) -> V {
    [-a[1], a[0]]
}
