//! Lead-in and lead-out elements of a compensation run.
//!
//! CAM posts switch compensation on before the part and approach the contour along a line or
//! an arc tangent to it, go round the closed contour back to where they joined it, and leave
//! along another arc (Fanuc cutter compensation C: G41 D in the lead-in line). Those lead
//! moves run through air beside the part: the tool path of the contour's last elements
//! crosses them on purpose. The programmed contour says which elements are the part: where
//! it visits a point again it has closed. The elements from the first closed loop's first to
//! the last closed loop's last are the part; those before and after are the leads. A lead's
//! tool path is checked against the part like any other, but the lead itself is no surface
//! the check protects. A run that never closes is all part. The manuals are silent here:
//! docs/trc.md "Lead-in and lead-out elements" gives the decision.

use crate::trc::geom::{Elem, V2};
use std::collections::HashMap;

/// Points closer than this (mm) are one point of the contour.
const SAME_POINT: f64 = 1e-6;

/// Where a point lies on the grid that decides "the same point".
fn key(p: V2) -> (i64, i64) {
    let q = |v: f64| (v / SAME_POINT).round() as i64;
    (q(p.x), q(p.y))
}

/// The part of a run so far: `(lo, hi)` means elements `lo + 1 ..= hi` (ordinals from 1 in
/// the run) lie in or between closed loops.
pub(super) type Span = Option<(u32, u32)>;

fn widen(span: Span, a: u32, b: u32) -> Span {
    Some(span.map_or((a, b), |(lo, hi)| (lo.min(a), hi.max(b))))
}

/// Whether element `k` lies in `span`: part of the contour for certain (a span only grows).
pub(super) fn in_span(span: Span, k: u32) -> bool {
    span.is_some_and(|(lo, hi)| lo < k && k <= hi)
}

/// Whether element `k` is part of a run whose contour is complete with `span`: in a loop, or
/// the run never closed.
pub(super) fn part_of(span: Span, k: u32) -> bool {
    span.is_none() || in_span(span, k)
}

/// The closed loops of a run as its elements come (the whole-program check).
#[derive(Default)]
pub(super) struct Closure {
    /// Each contour point met, with the first ordinal it is the end of (0: the run's start).
    seen: HashMap<(i64, i64), u32, Cells>,
    next: u32,
    span: Span,
}

impl Closure {
    /// The next element of the run: its ordinal.
    pub fn element(&mut self, e: &Elem) -> u32 {
        if self.next == 0 {
            self.visit(e.start(), 0);
            self.next = 1;
        }
        let k = self.next;
        self.next += 1;
        self.visit(e.end(), k);
        k
    }

    fn visit(&mut self, p: V2, k: u32) {
        match self.seen.get(&key(p)) {
            Some(&a) => self.span = widen(self.span, a, k),
            None => {
                self.seen.insert(key(p), k);
            }
        }
    }

    pub fn span(&self) -> Span {
        self.span
    }
}

/// The span of a stretch of consecutive elements of one run (the window's, ordinals from 1
/// in the stretch), worked out when asked: nothing kept, nothing allocated.
pub(super) fn span_of<'a>(elems: impl Iterator<Item = &'a Elem> + Clone) -> Span {
    let first = elems.clone().next()?.start();
    let vertices = std::iter::once(first).chain(elems.clone().map(Elem::end));
    let mut span = None;
    for (b, end) in vertices.clone().enumerate().skip(1) {
        let kb = key(end);
        // The earliest visit of the point: the widest loop ending here.
        if let Some(a) = vertices.clone().take(b).position(|v| key(v) == kb) {
            span = widen(span, a as u32, b as u32);
        }
    }
    span
}

/// A fast hash for the point cells (the standard SipHash guards against inputs chosen to collide,
/// which two integer coordinates of a part program are not).
#[derive(Default, Clone, Copy)]
struct Cells;

impl std::hash::BuildHasher for Cells {
    type Hasher = CellHasher;
    fn build_hasher(&self) -> CellHasher {
        CellHasher(0)
    }
}

struct CellHasher(u64);

impl std::hash::Hasher for CellHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 =
                (self.0.rotate_left(5) ^ u64::from(*b)).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
        }
    }
    fn write_i64(&mut self, v: i64) {
        self.0 = (self.0.rotate_left(5) ^ v as u64).wrapping_mul(0x51_7c_c1_b7_27_22_0a_95);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::trc::geom::v2;

    fn line(a: (f64, f64), b: (f64, f64)) -> Elem {
        Elem::Line {
            a: v2(a.0, a.1),
            b: v2(b.0, b.1),
        }
    }

    /// A square closed at (40, 0) with a lead-in before and a lead-out after.
    fn led_square() -> Vec<Elem> {
        vec![
            line((50.0, -10.0), (40.0, 0.0)),
            line((40.0, 0.0), (0.0, 0.0)),
            line((0.0, 0.0), (0.0, 40.0)),
            line((0.0, 40.0), (80.0, 40.0)),
            line((80.0, 40.0), (80.0, 0.0)),
            line((80.0, 0.0), (40.0, 0.0)),
            line((40.0, 0.0), (30.0, -10.0)),
        ]
    }

    #[test]
    fn a_closed_contour_makes_its_lead_in_and_lead_out_leads() {
        let mut c = Closure::default();
        let ks: Vec<u32> = led_square().iter().map(|e| c.element(e)).collect();
        assert_eq!(ks, vec![1, 2, 3, 4, 5, 6, 7]);
        assert_eq!(c.span(), Some((1, 6)));
        let part: Vec<bool> = ks.iter().map(|&k| part_of(c.span(), k)).collect();
        assert_eq!(part, vec![false, true, true, true, true, true, false]);
        assert_eq!(span_of(led_square().iter()), Some((1, 6)));
    }

    #[test]
    fn an_open_contour_is_all_part() {
        let mut c = Closure::default();
        for e in &led_square()[..5] {
            let k = c.element(e);
            assert!(part_of(c.span(), k) && !in_span(c.span(), k));
        }
        assert_eq!(span_of(led_square()[..5].iter()), None);
    }

    #[test]
    fn a_loop_closed_at_the_start_takes_the_whole_run() {
        // Back to the lead-in's own start: everything is inside the loop.
        let mut es = led_square();
        es.push(line((30.0, -10.0), (50.0, -10.0)));
        assert_eq!(span_of(es.iter()), Some((0, 8)));
        assert!((1..=8).all(|k| in_span(Some((0, 8)), k)));
    }

    #[test]
    fn points_a_rounding_apart_are_one() {
        let mut es = led_square();
        es[5] = line((80.0, 0.0), (40.0 + 1e-9, -1e-10));
        assert_eq!(span_of(es.iter()), Some((1, 6)));
    }
}
