/* Overlap: whether a body moved to a new place would overlap another by
 * more than the tolerance (a teleport's check and add_body's,
 * docs/engine-api.md "Live inputs"), by separating axes: the edge normals
 * of either polygon, and for a circle the line from the nearest vertex.
 * Lengths in m. */
#include <math.h>

#include "m2c_sim_internal.h"

/* The first body (by index) that A, with its centre moved to (x, y) at
 * time t, would overlap by more than the tolerance; -1 when none. */
int32_t m2c_sim_overlapping(m2c_world *m, m2c_sim_body *A, double x, double y, double t)
{
    double tol = m->s->tol;
    double spx = A->px, spy = A->py, svx = A->vx, svy = A->vy, sang = A->ang, stb = A->tb;
    m2c_sim_motion q = m2c_sim_state_at(A, t);
    A->px = x;                          /* A at t, moved (restored below) */
    A->py = y;
    A->vx = q.vx;
    A->vy = q.vy;
    A->ang = q.ang;
    A->tb = t;
    int32_t found = -1;
    for (int32_t k = 0; k < m->s->nbodies; k++) {
        const m2c_sim_body *B = &m->bodies[k];
        if (B == A || B->gone)
            continue;
        m2c_sim_motion qb = m2c_sim_state_at(B, t);
        double dx = qb.x - x, dy = qb.y - y;
        double reach = A->bound + B->bound + tol;
        if (dx * dx + dy * dy > reach * reach)
            continue;
        if (m2c_sim_separation(m, A, B, t) < -tol) {
            found = B->idx;
            break;
        }
    }
    A->px = spx;
    A->py = spy;
    A->vx = svx;
    A->vy = svy;
    A->ang = sang;
    A->tb = stb;
    return found;
}
