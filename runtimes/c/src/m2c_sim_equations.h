/* The generated entries the simulator calls (docs/simulator.md).  The
 * generated circle_circle.c and point_edge.c have no header of their own;
 * the simulator build (max2code/toolchain/c.py) compiles them with
 * `-include src/m2c_sim_equations.h`, so that a generated definition that
 * does not match these declarations fails to compile instead of being
 * called wrongly.
 *
 * NAME_coefficients fills coef[0..degree] (coef[k] multiplies t^k, t in
 * seconds) from the cheapest variant exact for these parameters and returns
 * the degree, or -1 when a parameter uses an effect the code was generated
 * without; NAME_variant returns that variant's index (for counting), or -1.
 * coef must hold M2C_MAX_DEGREE + 1 doubles. */
#ifndef M2C_SIM_EQUATIONS_H
#define M2C_SIM_EQUATIONS_H

#ifdef __cplusplus
extern "C" {
#endif

/* Two circles, each centre moving as p + v t + a t^2/2 plus an orbit term
 * of radius d (m): x gets d sin(e t + f), y gets d sin(p t + q) (rad/s,
 * rad; the simulator's circular orbit of phase phi is e = p, f = phi + pi/2,
 * q = phi).  Circle 1: a b c (x: m, m/s, m/s^2) d e f, m n o (y) p q;
 * circle 2: g h i j k l, r s u v w; radii x, z (m).  The gap is the squared
 * distance minus the squared sum of the radii (m^2). */
int circle_circle_coefficients(double a, double b, double c, double d, double e, double f, double m, double n,
                               double o, double p, double q, double g, double h, double i, double j, double k,
                               double l, double r, double s, double u, double v, double w, double x, double z,
                               double *coef);
int circle_circle_variant(double a, double b, double c, double d, double e, double f, double m, double n,
                          double o, double p, double q, double g, double h, double i, double j, double k,
                          double l, double r, double s, double u, double v, double w, double x, double z);

/* A point (centre of rotation px py (m), relative velocity vx vy (m/s) and
 * acceleration ax ay (m/s^2), at rho (m) from it with relative spin wr
 * (rad/s) and phase phr (rad)) against the line of an edge whose outward
 * normal turns at wn (rad/s) from phn (rad), h (m) from its body's centre.
 * The gap is the signed distance (m). */
int point_edge_coefficients(double px, double vx, double ax, double py, double vy, double ay, double rho, double wr,
                            double phr, double wn, double phn, double h, double *coef);
int point_edge_variant(double px, double vx, double ax, double py, double vy, double ay, double rho, double wr,
                       double phr, double wn, double phn, double h);

#ifdef __cplusplus
}
#endif

#endif
