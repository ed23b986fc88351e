//! Overlap: whether a body moved to a new place would overlap another
//! (a teleport's check, docs/engine-api.md "Live inputs"), by separating
//! axes.  The reference's `overlapping`, `separation`, `edge_line`,
//! `edges_separation`, `circle_separation`, operation for operation.

use super::motion::{point_at, state_at};
use super::scene::{Body, Vertex};

// Python's max(a, b) and min(a, b): the first unless the second is larger
// (smaller)
#[inline(always)]
fn max(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

#[inline(always)]
fn min(a: f64, b: f64) -> f64 {
    if b < a {
        b
    } else {
        a
    }
}

/// The first body (by index) that A (body `skip` of the world, or a body
/// not yet in it: None), with its centre moved to (x, y) at time t, would
/// overlap by more than the tolerance; None when none.  Removed bodies
/// are not there.
#[allow(clippy::too_many_arguments)]
pub fn overlapping(
    bodies: &[Body],
    verts: &[Vertex],
    tol: f64,
    a: &Body,
    skip: Option<usize>,
    x: f64,
    y: f64,
    t: f64,
) -> Option<usize> {
    // A at t, moved (a copy: the world is not changed)
    let mut a_ = a.clone();
    let (_, _, vx, vy, ang) = state_at(&a_, t);
    a_.px = x;
    a_.py = y;
    a_.vx = vx;
    a_.vy = vy;
    a_.ang = ang;
    a_.tb = t;
    for (k, b_) in bodies.iter().enumerate() {
        if Some(k) == skip || b_.gone {
            continue;
        }
        let (bx, by, _, _, _) = state_at(b_, t);
        let (dx, dy) = (bx - x, by - y);
        let reach = a_.bound + b_.bound + tol;
        if dx * dx + dy * dy > reach * reach {
            continue;
        }
        if separation(verts, &a_, b_, t) < -tol {
            return Some(k);
        }
    }
    None
}

/// The largest gap between A and B at t along a separating axis: negative
/// by the depth they overlap (edge normals of either polygon, and for a
/// circle the line from the nearest vertex; circles: the distance of the
/// centres less the radii).
pub(crate) fn separation(verts: &[Vertex], a_: &Body, b_: &Body, t: f64) -> f64 {
    if !a_.polygon && !b_.polygon {
        let (ax, ay) = point_at(a_, None, t);
        let (bx, by) = point_at(b_, None, t);
        return ((bx - ax) * (bx - ax) + (by - ay) * (by - ay)).sqrt() - (a_.r + b_.r);
    }
    if !a_.polygon {
        return circle_separation(verts, a_, b_, t);
    }
    if !b_.polygon {
        return circle_separation(verts, b_, a_, t);
    }
    polygons_separation(verts, a_, b_, t, &vertices(verts, a_, t), &vertices(verts, b_, t))
}

/// Outward unit normal (ox, oy) of edge j of P at t and the offset of its
/// line, (ox, oy) . point = off.
pub(super) fn edge_line(verts: &[Vertex], p_: &Body, j: usize, t: f64) -> (f64, f64, f64) {
    let ed = &verts[p_.vert(j)];
    let (px, py, _, _, ang) = state_at(p_, t);
    let c = ang.cos();
    let s = ang.sin();
    let ox = c * ed.nx - s * ed.ny;
    let oy = s * ed.nx + c * ed.ny;
    (ox, oy, ox * px + oy * py + ed.h)
}

/// Q's vertices at t.
pub(super) fn vertices(verts: &[Vertex], q_: &Body, t: f64) -> Vec<(f64, f64)> {
    (0..q_.nverts()).map(|k| point_at(q_, Some(&verts[q_.vert(k)]), t)).collect()
}

/// Along the edge normals of P: the largest over P's edges of the smallest
/// distance of Q's vertices (pts, at t) beyond the edge's line.  P's lines
/// are [`edge_line`]'s, with the cos and sin of P's angle taken once.
pub(super) fn edges_separation(verts: &[Vertex], p_: &Body, pts: &[(f64, f64)], t: f64) -> f64 {
    let (px, py, _, _, ang) = state_at(p_, t);
    let c = ang.cos();
    let s = ang.sin();
    let mut best = f64::NEG_INFINITY;
    for j in 0..p_.nverts() {
        let ed = &verts[p_.vert(j)];
        let ox = c * ed.nx - s * ed.ny;
        let oy = s * ed.nx + c * ed.ny;
        let off = ox * px + oy * py + ed.h;
        let mut lo = f64::INFINITY;
        for &(qx, qy) in pts {
            lo = min(lo, ox * qx + oy * qy - off);
        }
        best = max(best, lo);
    }
    best
}

/// [`separation`] of two polygons whose vertices at t are pa and pb.
pub(super) fn polygons_separation(
    verts: &[Vertex],
    a_: &Body,
    b_: &Body,
    t: f64,
    pa: &[(f64, f64)],
    pb: &[(f64, f64)],
) -> f64 {
    max(edges_separation(verts, a_, pb, t), edges_separation(verts, b_, pa, t))
}

fn circle_separation(verts: &[Vertex], c_: &Body, p_: &Body, t: f64) -> f64 {
    let (cx, cy) = point_at(c_, None, t);
    let mut best = f64::NEG_INFINITY;
    for j in 0..p_.nverts() {
        let (ox, oy, off) = edge_line(verts, p_, j, t);
        best = max(best, ox * cx + oy * cy - off - c_.r);
    }
    let pts = vertices(verts, p_, t);
    let (mut near, mut d2) = (0, f64::INFINITY);
    for (k, &(qx, qy)) in pts.iter().enumerate() {
        let e2 = (cx - qx) * (cx - qx) + (cy - qy) * (cy - qy);
        if e2 < d2 {
            near = k;
            d2 = e2;
        }
    }
    if d2 > 0.0 {
        let d = d2.sqrt();
        let (ux, uy) = ((cx - pts[near].0) / d, (cy - pts[near].1) / d);
        let mut hi = f64::NEG_INFINITY;
        for &(qx, qy) in &pts {
            hi = max(hi, ux * qx + uy * qy);
        }
        best = max(best, ux * cx + uy * cy - c_.r - hi);
    }
    best
}
