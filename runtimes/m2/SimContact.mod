IMPLEMENTATION MODULE SimContact ;

(* A contact's response: a transcription of the Python reference's
   contact_frame, normal_speed, pressed, pay_floor, hop, contact_impulse,
   along, held, held_impulse and sleeper_impulse, with the same IEEE double
   operations in the same order. *)

FROM RealMath IMPORT cos, sin ;
FROM CMath IMPORT sqrt ;
FROM SimScene IMPORT Bodies, BodyRef, RestSpeed, Verts ;
FROM SimQueue IMPORT FeatCC ;
FROM SimWorld IMPORT HeldNow, Unpaid ;
FROM SimMotion IMPORT PointAt, TurnRate ;
FROM SimPredict IMPORT closing ;
FROM SimSupport IMPORT slide_accel, support_relative ;


(* Contact point (cx, cy) and unit normal (nx, ny) from A to B of a feature
   at t (both bodies advanced to t). *)
PROCEDURE contact_frame (t: REAL; feature: INTEGER; A, B: BodyRef; i, j: INTEGER; VAR cx, cy, nx, ny: REAL) ;
VAR
   vA, vB: INTEGER ;
   pax, pay, pbx, pby, dx, dy, dist, px, py, th, rad: REAL ;
BEGIN
   IF i >= 0 THEN vA := A^.v0 + i ELSE vA := -1 END ;
   IF feature = FeatCC THEN
      PointAt (A, -1, t, pax, pay) ;
      IF j >= 0 THEN vB := B^.v0 + j ELSE vB := -1 END ;
      PointAt (B, vB, t, pbx, pby) ;
      dx := pbx - pax ;
      dy := pby - pay ;
      dist := sqrt (dx * dx + dy * dy) ;
      IF dist > 0.0 THEN
         nx := dx / dist ;
         ny := dy / dist
      ELSE
         nx := 1.0 ;
         ny := 0.0
      END ;
      cx := pax + A^.r * nx ;
      cy := pay + A^.r * ny
   ELSE
      PointAt (A, vA, t, px, py) ;
      th := B^.ang + Verts^[B^.v0 + j].psi ;
      (* from A to B: against the edge's outward normal *)
      nx := -cos (th) ;
      ny := -sin (th) ;
      IF vA < 0 THEN rad := A^.r ELSE rad := 0.0 END ;
      cx := px + rad * nx ;
      cy := py + rad * ny
   END
END contact_frame ;


(* Normal relative velocity (B's against A's, along n from A to B) of the
   material points at the contact: negative when approaching. *)
PROCEDURE normal_speed (A, B: BodyRef; cx, cy, nx, ny: REAL) : REAL ;
VAR
   uax, uay, ubx, uby: REAL ;
BEGIN
   uax := A^.vx - A^.om * (cy - A^.py) ;
   uay := A^.vy + A^.om * (cx - A^.px) ;
   ubx := B^.vx - B^.om * (cy - B^.py) ;
   uby := B^.vy + B^.om * (cx - B^.px) ;
   RETURN (ubx - uax) * nx + (uby - uay) * ny
END normal_speed ;


(* The bodies' accelerations push them together along the normal (n from
   A to B): the relative normal acceleration of the centres is negative.
   (Centripetal terms of turning bodies are left out.) *)
PROCEDURE pressed (A, B: BodyRef; nx, ny: REAL) : BOOLEAN ;
BEGIN
   RETURN (B^.ax - A^.ax) * nx + (B^.ay - A^.ay) * ny < 0.0
END pressed ;


(* A hop at the floor speed adds dE = need / 2 to the pair's energy (need =
   (floor^2 - cap) / kn): it is paid from the pair's common motion, the
   velocity V of its centre of mass (mass M), which an equal change of both
   velocities scales by f = sqrt(1 - need / (M V^2)), leaving their relative
   motion, hence the hop, untouched.  Not when a body of the pair is held
   (fixed, or a sleeper held as fixed) or the common motion cannot pay it
   (M V^2 <= need): FALSE, the hop then adds dE (Unpaid). *)
PROCEDURE pay_floor (A, B: BodyRef; need: REAL) : BOOLEAN ;
VAR
   ma, mb, mass, vx, vy, e2, f, dx, dy: REAL ;
BEGIN
   IF (A^.invM = 0.0) OR (B^.invM = 0.0) THEN RETURN FALSE END ;
   ma := 1.0 / A^.invM ;
   mb := 1.0 / B^.invM ;
   mass := ma + mb ;
   vx := (ma * A^.vx + mb * B^.vx) / mass ;
   vy := (ma * A^.vy + mb * B^.vy) / mass ;
   e2 := mass * (vx * vx + vy * vy) ;
   IF NOT (e2 > need) THEN RETURN FALSE END ;
   f := sqrt (1.0 - need / e2) ;
   dx := vx * f - vx ;
   dy := vy * f - vy ;
   A^.vx := A^.vx + dx ;
   A^.vy := A^.vy + dy ;
   B^.vx := B^.vx + dx ;
   B^.vy := B^.vy + dy ;
   RETURN TRUE
END pay_floor ;


(* A slow pressed contact (pressed, -vn < rest_speed): the bodies separate
   at hop along n, paid from their relative motion at the contact, so the
   pair's energy stays what it was: hop = rest_speed when kn Q pays it, else
   sqrt(kn Q), but at least rest_speed / 32 (a pair nearly at rest on each
   other: the energy that adds is paid from the pair's common motion,
   pay_floor, else the hop sets Unpaid).  With
   u = (vn, vt) the relative velocity of the material points in the frame
   (n, t), t = (-ny, nx), and K the contact's 2x2 inverse mass matrix (kn,
   knt; knt, kt), the pair's energy relative to its centre is Q / 2,
   Q = u . K^-1 u; the new relative velocity is (hop, x) with the same Q (x
   on vt's side of knt hop / kn), through the impulse P = K^-1 (u' - u)
   (normal part jn, tangential jt).  Returns jn. *)
PROCEDURE hop (A, B: BodyRef; cx, cy, nx, ny, vn: REAL) : REAL ;
VAR
   tx, ty, uax, uay, ubx, uby, vt, ran, rbn, rat, rbt, m, kn, kt, knt, det, q, cap, h, d, root, mid, x,
   dn, dt, jn, jt, px, py, floor: REAL ;
BEGIN
   tx := -ny ;
   ty := nx ;
   uax := A^.vx - A^.om * (cy - A^.py) ;
   uay := A^.vy + A^.om * (cx - A^.px) ;
   ubx := B^.vx - B^.om * (cy - B^.py) ;
   uby := B^.vy + B^.om * (cx - B^.px) ;
   vt := (ubx - uax) * tx + (uby - uay) * ty ;
   ran := (cx - A^.px) * ny - (cy - A^.py) * nx ;
   rbn := (cx - B^.px) * ny - (cy - B^.py) * nx ;
   rat := (cx - A^.px) * ty - (cy - A^.py) * tx ;
   rbt := (cx - B^.px) * ty - (cy - B^.py) * tx ;
   m := A^.invM + B^.invM ;
   kn := m + A^.invI * ran * ran + B^.invI * rbn * rbn ;
   kt := m + A^.invI * rat * rat + B^.invI * rbt * rbt ;
   knt := A^.invI * ran * rat + B^.invI * rbn * rbt ;
   det := kn * kt - knt * knt ;
   q := (kt * vn * vn - 2.0 * knt * vn * vt + kn * vt * vt) / det ;
   cap := kn * q ;
   floor := 0.03125 * RestSpeed ;
   IF cap >= RestSpeed * RestSpeed THEN
      h := RestSpeed
   ELSIF cap >= floor * floor THEN
      h := sqrt (cap)
   ELSE
      h := floor
   END ;
   d := det * (cap - h * h) ;
   IF d > 0.0 THEN root := sqrt (d) ELSE root := 0.0 END ;
   mid := knt * h ;
   IF vt * kn >= mid THEN
      x := (mid + root) / kn
   ELSE
      x := (mid - root) / kn
   END ;
   dn := h - vn ;
   dt := x - vt ;
   jn := (kt * dn - knt * dt) / det ;
   jt := (kn * dt - knt * dn) / det ;
   px := jn * nx + jt * tx ;
   py := jn * ny + jt * ty ;
   A^.vx := A^.vx - px * A^.invM ;
   A^.vy := A^.vy - py * A^.invM ;
   A^.om := A^.om - (jn * ran + jt * rat) * A^.invI ;
   B^.vx := B^.vx + px * B^.invM ;
   B^.vy := B^.vy + py * B^.invM ;
   B^.om := B^.om + (jn * rbn + jt * rbt) * B^.invI ;
   IF (cap < floor * floor) AND NOT pay_floor (A, B, (floor * floor - cap) / kn) THEN
      Unpaid := TRUE
   END ;
   RETURN jn
END hop ;


(* The impulse of a contact of the feature (feature, i, j) at (cx, cy) with
   normal (nx, ny) from A to B (both advanced to the contact time): 0.0 when
   the material points do not approach and are not pressed together, else
   the normal impulse j (velocities changed).  A fast contact is
   frictionless and leaves at sep = max(e |vn|, min(|vn|, rest_speed)); a
   slow pressed one hops (hop).  When the material points do not approach,
   the centres' accelerations do not press them and a body of the pair
   turns, the feature's gap polynomial decides whether they are pressed
   (closing: the turn closes the gap, which would otherwise predict the same
   contact again at once).  Never adds energy (docs/simulator.md, Impulse). *)
PROCEDURE contact_impulse (A, B: BodyRef; cx, cy, nx, ny: REAL; feature, i, j: INTEGER) : REAL ;
VAR
   vn, imp, ran, rbn, k, e, sep, m1, mn, me: REAL ;
   press: BOOLEAN ;
BEGIN
   vn := normal_speed (A, B, cx, cy, nx, ny) ;
   press := pressed (A, B, nx, ny) ;
   IF (NOT press) AND (NOT (vn < 0.0)) AND ((TurnRate (A) > 0.0) OR (TurnRate (B) > 0.0)) THEN
      press := closing (A, B, feature, i, j)
   END ;
   IF press AND (-vn < RestSpeed) THEN
      RETURN hop (A, B, cx, cy, nx, ny, vn)
   END ;
   imp := 0.0 ;
   IF vn < 0.0 THEN
      ran := (cx - A^.px) * ny - (cy - A^.py) * nx ;
      rbn := (cx - B^.px) * ny - (cy - B^.py) * nx ;
      k := A^.invM + B^.invM + A^.invI * ran * ran + B^.invI * rbn * rbn ;
      e := A^.e * B^.e ;
      (* sep = max(e * -vn, min(-vn, rest_speed)), as Python's min and max pick *)
      me := e * (-vn) ;
      m1 := -vn ;
      IF RestSpeed < m1 THEN mn := RestSpeed ELSE mn := m1 END ;
      IF mn > me THEN sep := mn ELSE sep := me END ;
      imp := (sep - vn) / k ;
      A^.vx := A^.vx - imp * A^.invM * nx ;
      A^.vy := A^.vy - imp * A^.invM * ny ;
      A^.om := A^.om - imp * A^.invI * ran ;
      B^.vx := B^.vx + imp * B^.invM * nx ;
      B^.vy := B^.vy + imp * B^.invM * ny ;
      B^.om := B^.om + imp * B^.invI * rbn
   END ;
   RETURN imp
END contact_impulse ;


(* n . t of a supported body's edge tangent t (0 for a body that is not
   supported: a fixed one). *)
PROCEDURE along (b: BodyRef; nx, ny: REAL) : REAL ;
BEGIN
   IF b^.sup < 0 THEN RETURN 0.0 END ;
   RETURN nx * b^.tx + ny * b^.ty
END along ;


(* A slow contact of bodies held on their supports: each supported (on a
   fixed body: a carried body is not) or fixed, approaching (vn < 0) slower than rest_speed, not pressed, and an impulse
   along their edges can change vn (kh > 0). *)
PROCEDURE held (A, B: BodyRef; nx, ny, vn: REAL) : BOOLEAN ;
VAR
   ka, kb: REAL ;
BEGIN
   IF NOT ((A^.fixed OR ((A^.sup >= 0) AND Bodies^[A^.sup].fixed))
           AND (B^.fixed OR ((B^.sup >= 0) AND Bodies^[B^.sup].fixed))) THEN
      RETURN FALSE
   END ;
   IF (NOT (vn < 0.0)) OR (NOT (-vn < RestSpeed)) OR pressed (A, B, nx, ny) THEN RETURN FALSE END ;
   ka := along (A, nx, ny) ;
   kb := along (B, nx, ny) ;
   RETURN A^.invM * ka * ka + B^.invM * kb * kb > 0.0
END held ;


(* The normal impulse j of a held contact (held): each supported body takes
   only its part along its support's edge, dv = -+ j (n . t) t / m, and
   keeps its support (the support's reaction takes the rest and does no
   work); the normal speed leaves at sep = max(e |vn|, min(|vn|,
   rest_speed)) through kh = (n . tA)^2 / mA + (n . tB)^2 / mB.  The
   friction of each is set again for its new speed relative to its support
   (slide_accel; support_relative: the support may move). *)
PROCEDURE held_impulse (A, B: BodyRef; nx, ny, vn: REAL) : REAL ;
VAR
   ka, kb, k, e, sep, imp, d, m1, mn, me, q, u, a: REAL ;
BEGIN
   ka := along (A, nx, ny) ;
   kb := along (B, nx, ny) ;
   k := A^.invM * ka * ka + B^.invM * kb * kb ;
   e := A^.e * B^.e ;
   (* sep = max(e * -vn, min(-vn, rest_speed)), as Python's min and max pick *)
   me := e * (-vn) ;
   m1 := -vn ;
   IF RestSpeed < m1 THEN mn := RestSpeed ELSE mn := m1 END ;
   IF mn > me THEN sep := mn ELSE sep := me END ;
   imp := (sep - vn) / k ;
   IF A^.sup >= 0 THEN
      d := imp * A^.invM * ka ;
      A^.vx := A^.vx - d * A^.tx ;
      A^.vy := A^.vy - d * A^.ty ;
      support_relative (A, q, u, a) ;
      slide_accel (A, u)
   END ;
   IF B^.sup >= 0 THEN
      d := imp * B^.invM * kb ;
      B^.vx := B^.vx + d * B^.tx ;
      B^.vy := B^.vy + d * B^.ty ;
      support_relative (B, q, u, a) ;
      slide_accel (B, u)
   END ;
   RETURN imp
END held_impulse ;


(* The impulse of a contact of A and B, one of them (S) asleep: first with
   S held as if fixed (its 1/m and 1/I zero); when that impulse would change
   the normal speed of S's material point by less than rest_speed,
   j (1/mS + (rS x n)^2 / IS) < rest_speed, and no hop of it was Unpaid, it stands (S stays asleep,
   unchanged: a gentle touch); else the other body's velocity is restored
   and the full impulse is applied (S moves: jolted, it wakes with what rests on it).
   When the other body is fixed (it moves or turns: a sleeper is never
   predicted against an unmoving one) S cannot be held (the pair would have
   no mass): the full impulse at once.  Returns the impulse applied. *)
PROCEDURE sleeper_impulse (A, B: BodyRef; cx, cy, nx, ny: REAL; feature, i, j: INTEGER) : REAL ;
VAR
   S, M: BodyRef ;
   vx, vy, om, invM, invI, imp, rsn: REAL ;
BEGIN
   IF A^.asleep THEN
      S := A ;
      M := B
   ELSE
      S := B ;
      M := A
   END ;
   IF M^.fixed THEN RETURN contact_impulse (A, B, cx, cy, nx, ny, feature, i, j) END ;
   vx := M^.vx ;
   vy := M^.vy ;
   om := M^.om ;
   invM := S^.invM ;
   invI := S^.invI ;
   S^.invM := 0.0 ;
   S^.invI := 0.0 ;
   Unpaid := FALSE ;
   imp := contact_impulse (A, B, cx, cy, nx, ny, feature, i, j) ;
   S^.invM := invM ;
   S^.invI := invI ;
   rsn := (cx - S^.px) * ny - (cy - S^.py) * nx ;
   IF ((imp * (S^.invM + S^.invI * rsn * rsn) < RestSpeed) AND NOT Unpaid) OR HeldNow (S) THEN RETURN imp END ;
   M^.vx := vx ;
   M^.vy := vy ;
   M^.om := om ;
   RETURN contact_impulse (A, B, cx, cy, nx, ny, feature, i, j)
END sleeper_impulse ;


END SimContact.
