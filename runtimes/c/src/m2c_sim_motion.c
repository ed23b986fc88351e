/* Motion between events: every body moves exactly, p + (v + a dt/2) dt,
 * v + a dt, angle + w dt, from its state at its own time tb (s).  The hot
 * helpers (m2c_sim_state_at, m2c_sim_rebase, m2c_sim_point_at,
 * m2c_sim_turn_rate, the cos, sin cache) are static inline in
 * m2c_sim_internal.h; here is what the live world's queries call. */
#include "m2c_sim_internal.h"

/* Body b's exact state at t (s), from its state at b->tb (m2c_world_state's answer). */
void m2c_sim_body_state(const m2c_sim_body *b, double t, m2c_body_state *s)
{
    m2c_sim_motion q = m2c_sim_state_at(b, t);
    s->x = q.x;
    s->y = q.y;
    s->vx = q.vx;
    s->vy = q.vy;
    s->angle = q.ang;
    s->omega = b->om;
}
