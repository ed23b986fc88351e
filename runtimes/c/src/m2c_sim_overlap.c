/* Overlap: whether a body moved to a new place would overlap another by
 * more than the tolerance (a teleport's check and add_body's,
 * docs/engine-api.md "Live inputs"), by separating axes: the edge normals
 * of either polygon, and for a circle the line from the nearest vertex.
 * Lengths in m. */
#include <math.h>

#include "m2c_sim_internal.h"

/* Outward unit normal (ox, oy) of edge j of P at t and the offset (m) of
 * its line, (ox, oy) . point = off. */
void m2c_sim_edge_line(const m2c_sim_body *P, int32_t j, double t, double *ox, double *oy, double *off)
{
    const m2c_sim_vertex *ed = &P->verts[j];
    m2c_sim_motion q = m2c_sim_state_at(P, t);
    double c = cos(q.ang);
    double s = sin(q.ang);
    *ox = c * ed->nx - s * ed->ny;
    *oy = s * ed->nx + c * ed->ny;
    *off = *ox * q.x + *oy * q.y + ed->h;
}

/* Along the edge normals of P: the largest over P's edges of the smallest
 * distance of Q's vertices beyond the edge's line. */
static double edges_separation(m2c_world *m, const m2c_sim_body *P, const m2c_sim_body *Q, double t)
{
    double best = -INFINITY;
    for (int32_t j = 0; j < P->nverts; j++) {
        double ox, oy, off;
        m2c_sim_edge_line(P, j, t, &ox, &oy, &off);
        double lo = INFINITY;
        for (int32_t k = 0; k < Q->nverts; k++) {
            double qx, qy;
            m2c_sim_point_at(m, Q, &Q->verts[k], t, &qx, &qy);
            lo = m2c_sim_min(lo, ox * qx + oy * qy - off);
        }
        best = m2c_sim_max(best, lo);
    }
    return best;
}

/* A circle against a polygon: along P's edge normals, and along the line
 * from P's nearest vertex (the first of the nearest) to the circle's centre. */
static double circle_separation(m2c_world *m, const m2c_sim_body *C, const m2c_sim_body *P, double t)
{
    double cx, cy;
    m2c_sim_point_at(m, C, NULL, t, &cx, &cy);
    double best = -INFINITY;
    for (int32_t j = 0; j < P->nverts; j++) {
        double ox, oy, off;
        m2c_sim_edge_line(P, j, t, &ox, &oy, &off);
        best = m2c_sim_max(best, ox * cx + oy * cy - off - C->r);
    }
    double d2 = INFINITY, nearx = 0.0, neary = 0.0;
    for (int32_t k = 0; k < P->nverts; k++) {
        double qx, qy;
        m2c_sim_point_at(m, P, &P->verts[k], t, &qx, &qy);
        double e2 = (cx - qx) * (cx - qx) + (cy - qy) * (cy - qy);
        if (e2 < d2) {
            d2 = e2;
            nearx = qx;
            neary = qy;
        }
    }
    if (d2 > 0.0) {
        double d = sqrt(d2);
        double ux = (cx - nearx) / d, uy = (cy - neary) / d;
        double hi = -INFINITY;
        for (int32_t k = 0; k < P->nverts; k++) {
            double qx, qy;
            m2c_sim_point_at(m, P, &P->verts[k], t, &qx, &qy);
            hi = m2c_sim_max(hi, ux * qx + uy * qy);
        }
        best = m2c_sim_max(best, ux * cx + uy * cy - C->r - hi);
    }
    return best;
}

/* The largest gap between A and B at t along a separating axis: negative
 * by the depth they overlap (edge normals of either polygon, and for a
 * circle the line from the nearest vertex; circles: the distance of the
 * centres less the radii). */
double m2c_sim_separation(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, double t)
{
    if (!A->polygon && !B->polygon) {
        double ax, ay, bx, by;
        m2c_sim_point_at(m, A, NULL, t, &ax, &ay);
        m2c_sim_point_at(m, B, NULL, t, &bx, &by);
        return sqrt((bx - ax) * (bx - ax) + (by - ay) * (by - ay)) - (A->r + B->r);
    }
    if (!A->polygon)
        return circle_separation(m, A, B, t);
    if (!B->polygon)
        return circle_separation(m, B, A, t);
    return m2c_sim_max(edges_separation(m, A, B, t), edges_separation(m, B, A, t));
}

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
