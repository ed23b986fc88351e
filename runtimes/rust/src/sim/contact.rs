//! A contact's response: where and along which normal two bodies touch,
//! and the frictionless impulse (docs/simulator.md, "Impulse").

use super::motion::{point_at, turn_rate};
use super::out::Res;
use super::predict::{circle_params, circles_gap, pe_coefficients, touching_now};
use super::scene::{Body, Vertex};
use super::support::{slide_accel, support_relative};
use super::world::Queue;
use super::{Equations, CC, MAX_COEF};

/// Contact point (cx, cy) and unit normal (nx, ny) from A to B of a
/// feature at t (both bodies advanced to t, or B's angle at t given as
/// bang: the TOI library's bodies stay at their time 0); `verts` is the
/// scene's.
#[allow(clippy::too_many_arguments)]
pub fn contact_frame(
    verts: &[Vertex],
    t: f64,
    feature: i32,
    a_: &Body,
    b_: &Body,
    i: i32,
    j: i32,
    bang: f64,
) -> (f64, f64, f64, f64) {
    let va = if i >= 0 { Some(&verts[a_.vert(i as usize)]) } else { None };
    let (nx, ny, cx, cy);
    if feature == CC {
        let (ax_, ay_) = point_at(a_, None, t);
        let vb = if j >= 0 { Some(&verts[b_.vert(j as usize)]) } else { None };
        let (bx_, by_) = point_at(b_, vb, t);
        let (dx, dy) = (bx_ - ax_, by_ - ay_);
        let dist = (dx * dx + dy * dy).sqrt();
        if dist > 0.0 {
            nx = dx / dist;
            ny = dy / dist;
        } else {
            nx = 1.0;
            ny = 0.0;
        }
        cx = ax_ + a_.r * nx;
        cy = ay_ + a_.r * ny;
    } else {
        let (px, py) = point_at(a_, va, t);
        let ed = &verts[b_.vert(j as usize)];
        let th = bang + ed.psi;
        let (c, s) = ed.normal.of(th);
        // from A to B: against the edge's outward normal
        nx = -c;
        ny = -s;
        let rad = if va.is_none() { a_.r } else { 0.0 };
        cx = px + rad * nx;
        cy = py + rad * ny;
    }
    (cx, cy, nx, ny)
}

/// The bodies' accelerations push them together along the normal (n from
/// A to B): the relative normal acceleration of the centres is negative.
/// (Centripetal terms of turning bodies are left out.)
#[inline(always)]
pub fn pressed(a_: &Body, b_: &Body, nx: f64, ny: f64) -> bool {
    (b_.ax - a_.ax) * nx + (b_.ay - a_.ay) * ny < 0.0
}

/// The gap polynomial of the contact's feature (feature, i, j as in a
/// collision record: the one that predicted it), taken again at the
/// contact (A's time: both advanced), predicts this contact now
/// (touching_now: approaching, c1 < 0, or c2 < 0 and closing again before
/// the gap exceeds its kappa).  Its second derivative has the centripetal
/// terms of a turn, which `pressed` leaves out.  `verts` is the scene's,
/// `tol` its tolerance; the polynomial is counted as a prediction's is.
#[allow(clippy::too_many_arguments)]
pub fn closing<E: Equations>(
    verts: &[Vertex],
    tol: f64,
    q: &mut Queue,
    a_: &Body,
    b_: &Body,
    feature: i32,
    i: i32,
    j: i32,
) -> Res<bool> {
    let now = a_.tb;
    let mut c = [0.0; MAX_COEF];
    let (deg, kappa);
    if feature == CC {
        let vb = if j >= 0 { Some(&verts[b_.vert(j as usize)]) } else { None };
        let rb = if vb.is_none() { b_.r } else { 0.0 };
        deg = circles_gap::<E, _>(q, &circle_params(a_, now, None), a_.r, &circle_params(b_, now, vb), rb, &mut c)?;
        kappa = tol * (2.0 * (a_.r + rb) + tol);
    } else {
        if i >= 0 {
            let v = &verts[a_.vert(i as usize)];
            deg = pe_coefficients::<E, _>(verts, q, a_, b_, v.rho, v.beta, 0.0, j as usize, now, &mut c)?;
        } else {
            deg = pe_coefficients::<E, _>(verts, q, a_, b_, a_.orbit, a_.ophase, a_.r, j as usize, now, &mut c)?;
        }
        kappa = tol;
    }
    Ok(touching_now(&c, deg, kappa))
}

/// Normal relative velocity (B's against A's, along n from A to B) of the
/// material points at the contact: negative when approaching.
#[inline(always)]
pub fn normal_speed(a_: &Body, b_: &Body, cx: f64, cy: f64, nx: f64, ny: f64) -> f64 {
    let uax = a_.vx - a_.om * (cy - a_.py);
    let uay = a_.vy + a_.om * (cx - a_.px);
    let ubx = b_.vx - b_.om * (cy - b_.py);
    let uby = b_.vy + b_.om * (cx - b_.px);
    (ubx - uax) * nx + (uby - uay) * ny
}

/// What `contact_impulse` reads besides the two bodies: the scene's
/// vertices, tolerance and rest speed, the queue's counters (for
/// `closing`'s polynomial), and the contact's feature (feature, i, j as in
/// its collision record).
pub struct ImpulseCtx<'a> {
    pub verts: &'a [Vertex],
    pub tol: f64,
    pub rest_speed: f64,
    pub q: &'a mut Queue,
    pub feature: i32,
    pub i: i32,
    pub j: i32,
    /// a hop since sleeper_impulse cleared it added energy (pay_floor could not pay)
    pub unpaid: bool,
    /// the sleeper of sleeper_impulse was put to sleep by a jam at this instant: no touch wakes it
    pub held_now: bool,
}

/// The impulse of a contact of the feature (ctx: feature, i, j) at (cx, cy)
/// with normal (nx, ny) from A to B (both advanced to the contact time):
/// 0.0 when the material points do not approach and are not pressed
/// together, else the normal impulse j (velocities changed).  A fast
/// contact is frictionless and leaves at sep = max(e |vn|, min(|vn|,
/// rest_speed)); a slow pressed one hops (`hop`).  When the material
/// points do not approach, the centres' accelerations do not press them
/// and a body of the pair turns, the feature's gap polynomial decides
/// whether they are pressed (`closing`: the turn closes the gap, which
/// would otherwise predict the same contact again at once).  Never adds
/// energy (docs/simulator.md, Impulse).
#[allow(clippy::too_many_arguments)]
pub fn contact_impulse<E: Equations>(
    ctx: &mut ImpulseCtx,
    a_: &mut Body,
    b_: &mut Body,
    cx: f64,
    cy: f64,
    nx: f64,
    ny: f64,
) -> Res<f64> {
    let vn = normal_speed(a_, b_, cx, cy, nx, ny);
    let rest = ctx.rest_speed;
    let mut press = pressed(a_, b_, nx, ny);
    if !press && !(vn < 0.0) && (turn_rate(a_) > 0.0 || turn_rate(b_) > 0.0) {
        press = closing::<E>(ctx.verts, ctx.tol, ctx.q, a_, b_, ctx.feature, ctx.i, ctx.j)?;
    }
    if press && -vn < rest {
        return Ok(hop(a_, b_, cx, cy, nx, ny, vn, rest, &mut ctx.unpaid));
    }
    let mut imp = 0.0;
    if vn < 0.0 {
        let ran = (cx - a_.px) * ny - (cy - a_.py) * nx;
        let rbn = (cx - b_.px) * ny - (cy - b_.py) * nx;
        let k = a_.inv_m + b_.inv_m + a_.inv_i * ran * ran + b_.inv_i * rbn * rbn;
        let e = a_.e * b_.e;
        let first = e * -vn;
        // Python's max(e * -vn, min(-vn, rest))
        let lo = if rest < -vn { rest } else { -vn };
        let sep = if lo > first { lo } else { first };
        imp = (sep - vn) / k;
        a_.vx = a_.vx - imp * a_.inv_m * nx;
        a_.vy = a_.vy - imp * a_.inv_m * ny;
        a_.om = a_.om - imp * a_.inv_i * ran;
        b_.vx = b_.vx + imp * b_.inv_m * nx;
        b_.vy = b_.vy + imp * b_.inv_m * ny;
        b_.om = b_.om + imp * b_.inv_i * rbn;
    }
    Ok(imp)
}

/// A slow pressed contact (pressed, -vn < rest_speed): the bodies separate
/// at hop along n, paid from their relative motion at the contact, so the
/// pair's energy stays what it was: hop = rest_speed when kn Q pays it,
/// else sqrt(kn Q), but at least rest_speed / 32 (a pair nearly at rest on
/// each other: the energy that adds is paid from the pair's common motion,
/// `pay_floor`, else the hop sets `unpaid`).  With
/// u = (vn, vt) the relative velocity of the material points in the frame
/// (n, t), t = (-ny, nx), and K the contact's 2x2 inverse mass matrix (kn,
/// knt; knt, kt), the pair's energy relative to its centre is Q / 2,
/// Q = u . K^-1 u; the new relative velocity is (hop, x) with the same Q (x
/// on vt's side of knt hop / kn), through the impulse P = K^-1 (u' - u)
/// (normal part jn, tangential jt).  Returns jn.
#[allow(clippy::too_many_arguments)]
pub fn hop(
    a_: &mut Body,
    b_: &mut Body,
    cx: f64,
    cy: f64,
    nx: f64,
    ny: f64,
    vn: f64,
    rest_speed: f64,
    unpaid: &mut bool,
) -> f64 {
    let (tx, ty) = (-ny, nx);
    let uax = a_.vx - a_.om * (cy - a_.py);
    let uay = a_.vy + a_.om * (cx - a_.px);
    let ubx = b_.vx - b_.om * (cy - b_.py);
    let uby = b_.vy + b_.om * (cx - b_.px);
    let vt = (ubx - uax) * tx + (uby - uay) * ty;
    let ran = (cx - a_.px) * ny - (cy - a_.py) * nx;
    let rbn = (cx - b_.px) * ny - (cy - b_.py) * nx;
    let rat = (cx - a_.px) * ty - (cy - a_.py) * tx;
    let rbt = (cx - b_.px) * ty - (cy - b_.py) * tx;
    let m = a_.inv_m + b_.inv_m;
    let kn = m + a_.inv_i * ran * ran + b_.inv_i * rbn * rbn;
    let kt = m + a_.inv_i * rat * rat + b_.inv_i * rbt * rbt;
    let knt = a_.inv_i * ran * rat + b_.inv_i * rbn * rbt;
    let det = kn * kt - knt * knt;
    let q = (kt * vn * vn - 2.0 * knt * vn * vt + kn * vt * vt) / det;
    let cap = kn * q;
    let rest = rest_speed;
    let floor = 0.03125 * rest;
    let hop = if cap >= rest * rest {
        rest
    } else if cap >= floor * floor {
        cap.sqrt()
    } else {
        floor
    };
    let d = det * (cap - hop * hop);
    let root = if d > 0.0 { d.sqrt() } else { 0.0 };
    let mid = knt * hop;
    let x = if vt * kn >= mid { (mid + root) / kn } else { (mid - root) / kn };
    let dn = hop - vn;
    let dt = x - vt;
    let jn = (kt * dn - knt * dt) / det;
    let jt = (kn * dt - knt * dn) / det;
    let px = jn * nx + jt * tx;
    let py = jn * ny + jt * ty;
    a_.vx = a_.vx - px * a_.inv_m;
    a_.vy = a_.vy - py * a_.inv_m;
    a_.om = a_.om - (jn * ran + jt * rat) * a_.inv_i;
    b_.vx = b_.vx + px * b_.inv_m;
    b_.vy = b_.vy + py * b_.inv_m;
    b_.om = b_.om + (jn * rbn + jt * rbt) * b_.inv_i;
    if cap < floor * floor && !pay_floor(a_, b_, (floor * floor - cap) / kn) {
        *unpaid = true;
    }
    jn
}

/// A hop at the floor speed adds dE = need / 2 to the pair's energy (need =
/// (floor^2 - cap) / kn): it is paid from the pair's common motion, the
/// velocity V of its centre of mass (mass M), which an equal change of both
/// velocities scales by f = sqrt(1 - need / (M V^2)), leaving their
/// relative motion, hence the hop, untouched.  Not when a body of the pair
/// is held (fixed, or a sleeper held as fixed) or the common motion cannot
/// pay it (M V^2 <= need): false, the hop then adds dE (`unpaid`).
pub fn pay_floor(a_: &mut Body, b_: &mut Body, need: f64) -> bool {
    if a_.inv_m == 0.0 || b_.inv_m == 0.0 {
        return false;
    }
    let ma = 1.0 / a_.inv_m;
    let mb = 1.0 / b_.inv_m;
    let mass = ma + mb;
    let vx = (ma * a_.vx + mb * b_.vx) / mass;
    let vy = (ma * a_.vy + mb * b_.vy) / mass;
    let e2 = mass * (vx * vx + vy * vy);
    if !(e2 > need) {
        return false;
    }
    let f = (1.0 - need / e2).sqrt();
    let dx = vx * f - vx;
    let dy = vy * f - vy;
    a_.vx = a_.vx + dx;
    a_.vy = a_.vy + dy;
    b_.vx = b_.vx + dx;
    b_.vy = b_.vy + dy;
    true
}

/// n . t of a supported body's edge tangent t (0 for a fixed body).
#[inline(always)]
pub fn along(b_: &Body, nx: f64, ny: f64) -> f64 {
    if b_.sup < 0 {
        return 0.0;
    }
    nx * b_.tx + ny * b_.ty
}

/// A slow contact of bodies held on their supports: each supported (on a
/// fixed body: a carried body is not) or fixed, approaching (vn < 0) slower
/// than rest_speed, not pressed, and an impulse along their edges can
/// change vn (kh > 0); `bodies` is the scene's.
#[allow(clippy::too_many_arguments)]
pub fn held(bodies: &[Body], a_: &Body, b_: &Body, nx: f64, ny: f64, vn: f64, rest_speed: f64) -> bool {
    let on_fixed = |x: &Body| x.fixed || (x.sup >= 0 && bodies[x.sup as usize].fixed);
    if !(on_fixed(a_) && on_fixed(b_)) {
        return false;
    }
    if !(vn < 0.0) || !(-vn < rest_speed) || pressed(a_, b_, nx, ny) {
        return false;
    }
    let ka = along(a_, nx, ny);
    let kb = along(b_, nx, ny);
    a_.inv_m * ka * ka + b_.inv_m * kb * kb > 0.0
}

/// The normal impulse j of a held contact (`held`): each supported body
/// takes only its part along its support's edge, dv = -+ j (n . t) t / m,
/// and keeps its support (the support's reaction takes the rest and does
/// no work); the normal speed leaves at sep = max(e |vn|, min(|vn|,
/// rest_speed)) = |vn| (slow), through kh = (n . tA)^2 / mA + (n . tB)^2 /
/// mB.  The friction of each is set again for its new speed relative to
/// its support (slide_accel; support_relative: the support may move), the
/// supports `sup_a` / `sup_b` (None for a fixed body).
#[allow(clippy::too_many_arguments)]
pub fn held_impulse(
    a_: &mut Body,
    b_: &mut Body,
    sup_a: Option<&Body>,
    sup_b: Option<&Body>,
    nx: f64,
    ny: f64,
    vn: f64,
    rest_speed: f64,
) -> f64 {
    let ka = along(a_, nx, ny);
    let kb = along(b_, nx, ny);
    let k = a_.inv_m * ka * ka + b_.inv_m * kb * kb;
    let e = a_.e * b_.e;
    let first = e * -vn;
    // Python's max(e * -vn, min(-vn, rest))
    let lo = if rest_speed < -vn { rest_speed } else { -vn };
    let sep = if lo > first { lo } else { first };
    let imp = (sep - vn) / k;
    if a_.sup >= 0 {
        let d = imp * a_.inv_m * ka;
        a_.vx = a_.vx - d * a_.tx;
        a_.vy = a_.vy - d * a_.ty;
        let sup = sup_a.expect("a supported body has its support");
        let (_, u, _) = support_relative(a_, sup);
        slide_accel(a_, sup, u);
    }
    if b_.sup >= 0 {
        let d = imp * b_.inv_m * kb;
        b_.vx = b_.vx + d * b_.tx;
        b_.vy = b_.vy + d * b_.ty;
        let sup = sup_b.expect("a supported body has its support");
        let (_, u, _) = support_relative(b_, sup);
        slide_accel(b_, sup, u);
    }
    imp
}

/// The impulse of a contact of A and B, one of them (S) asleep: first with
/// S held as if fixed (its 1/m and 1/I zero); when that impulse would
/// change the normal speed of S's material point by less than rest_speed,
/// j (1/mS + (rS x n)^2 / IS) < rest_speed, and no hop of it was `unpaid`, it stands (S stays asleep,
/// unchanged: a gentle touch); else the other body's velocity is restored
/// and the full impulse is applied (S moves: `jolted`, it wakes with what rests on it).
/// When the other body is fixed (it moves or turns: a sleeper is never
/// predicted against an unmoving one) S cannot be held (the pair would
/// have no mass): the full impulse at once.  Returns the impulse applied.
pub fn sleeper_impulse<E: Equations>(
    ctx: &mut ImpulseCtx,
    a_: &mut Body,
    b_: &mut Body,
    cx: f64,
    cy: f64,
    nx: f64,
    ny: f64,
) -> Res<f64> {
    let a_sleeps = a_.asleep;
    let other_fixed = if a_sleeps { b_.fixed } else { a_.fixed };
    if other_fixed {
        return contact_impulse::<E>(ctx, a_, b_, cx, cy, nx, ny);
    }
    let (vx, vy, om) = if a_sleeps { (b_.vx, b_.vy, b_.om) } else { (a_.vx, a_.vy, a_.om) };
    let (inv_m, inv_i) = {
        let s_ = if a_sleeps { &mut *a_ } else { &mut *b_ };
        let held = (s_.inv_m, s_.inv_i);
        s_.inv_m = 0.0;
        s_.inv_i = 0.0;
        held
    };
    ctx.unpaid = false;
    let imp = contact_impulse::<E>(ctx, a_, b_, cx, cy, nx, ny)?;
    {
        let s_ = if a_sleeps { &mut *a_ } else { &mut *b_ };
        s_.inv_m = inv_m;
        s_.inv_i = inv_i;
        let rsn = (cx - s_.px) * ny - (cy - s_.py) * nx;
        if (imp * (s_.inv_m + s_.inv_i * rsn * rsn) < ctx.rest_speed && !ctx.unpaid) || ctx.held_now {
            return Ok(imp);
        }
    }
    let m_ = if a_sleeps { &mut *b_ } else { &mut *a_ };
    m_.vx = vx;
    m_.vy = vy;
    m_.om = om;
    contact_impulse::<E>(ctx, a_, b_, cx, cy, nx, ny)
}

/// Two distinct bodies of the slice, mutably.
pub fn two_mut(v: &mut [Body], a: usize, b: usize) -> (&mut Body, &mut Body) {
    assert!(a != b, "a contact needs two bodies");
    if a < b {
        let (lo, hi) = v.split_at_mut(b);
        (&mut lo[a], &mut hi[0])
    } else {
        let (lo, hi) = v.split_at_mut(a);
        (&mut hi[0], &mut lo[b])
    }
}
