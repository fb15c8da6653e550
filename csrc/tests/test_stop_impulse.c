/* test_stop_impulse.c -- the velocity-level frictional contact step
 * (stop_impulse.c) against closed forms, and on seeded random problems against
 * the conditions that define its solution, checked here independently of
 * the solver: the impulse balance, the plate's maximum dissipation, normal
 * complementarity, Coulomb's law at every row, and the energy inequality. */
#include "check.h"
#include "../stop_impulse.h"

#include <math.h>
#include <string.h>

static fc_problem problem(int n, const double Md[3], const double vs[3], double cap, int nr, const fc_row *rows)
{
    fc_problem p;
    memset(&p, 0, sizeof p);
    p.n = n;
    for (int c = 0; c < 3; c++) {
        p.Md[c] = c < n ? Md[c] : 1.0;
        p.vs[c] = c < n ? vs[c] : 0.0;
        p.A[c][c] = 1.0;
    }
    p.cap = cap;
    p.vscale = 1.0;
    p.vrest = 1e-12;
    p.nr = nr;
    p.rows = rows;
    return p;
}

/* A particle (n = 3, the third coordinate idle) thrown at a wall G = (1, 0,
 * 0) with tangent T = (0, 1, 0), no plate friction. Plastic impact: lam =
 * -M vx (the normal velocity goes to 0). Coulomb: the tangential impulse
 * that would stop the slide is -M vy; it sticks (v = 0 exactly) iff |M vy|
 * <= mu lam, else it slides on with vy - sign(vy) mu lam / M. */
EXDEX_TEST(fcontact_oblique_impact_closed_form)
{
    double Md[3] = {2.0, 2.0, 1.0};
    for (int c = 0; c < 2; c++) {
        double mu = c ? 0.8 : 0.3, vs[3] = {-1.0, 0.5, 0.0}, lam[1], beta[1];
        fc_row r = {{1, 0, 0}, {0, 1, 0}, 0.0, 0.0, mu, 1};
        fc_problem p = problem(3, Md, vs, 0.0, 1, &r);
        fc_result res;
        unsigned char hint[1] = {1};
        ENSURE(fc_solve(&p, hint, vs, NULL, lam, beta, &res) == 1);
        ENSURE_CLOSE(lam[0], 2.0, 1e-14);
        if (mu * 2.0 >= 2.0 * 0.5) {
            ENSURE(res.v[0] == 0.0 && res.v[1] == 0.0 && res.v[2] == 0.0);  /* stuck: exactly still */
            ENSURE_CLOSE(beta[0], -1.0, 1e-14);
        } else {
            ENSURE_CLOSE(res.v[0], 0.0, 1e-15);
            ENSURE_CLOSE(res.v[1], 0.5 - mu * 2.0 / 2.0, 1e-14);
            ENSURE_CLOSE(beta[0], -mu * 2.0, 1e-14);
        }
    }
}

/* A block's face landing flat on a floor, the face drawn by N = 13 points
 * x_i in [-h, h] at y = -h, every one hinted (more than FC_MAX_CAND rows):
 * n = (0, 1), t = e_z x n = (-1, 0), so G_i = (0, 1, x_i) and the tangent
 * row T = (-1, 0, -h) is the face's (r x t = -h for every point), tb = 0.
 * No plate friction. A plastic landing with the face flat (omega' = 0,
 * vy' = 0): sum lam = -M vy; the moment sum lam_i x_i = beta h puts the
 * centre of pressure at beta h / sum lam, inside the face for mu <= 1.
 * Stick (v' = 0) iff |vx| <= mu |vy|, beta = M vx; else the slide slows by
 * mu |vy|: vx' = vx - sign(vx) mu |vy|, beta = sign(vx) mu sum lam. */
EXDEX_TEST(fcontact_face_of_many_points_lands_as_its_corners)
{
    enum { N = 13 };
    double h = 0.01, Md[3] = {0.1, 0.1, 1e-5};
    for (int c = 0; c < 2; c++) {
        double mu = c ? 0.8 : 0.3, vs[3] = {0.5, -1.0, 0.0}, lam[N], beta[N], ls = 0.0, bs = 0.0, mom = 0.0;
        fc_row r[N];
        unsigned char hint[N];
        fc_problem p;
        fc_result res;
        for (int i = 0; i < N; i++) {
            double x = -h + 2.0 * h * i / (N - 1);
            r[i] = (fc_row){{0, 1, x}, {-1, 0, -h}, 0.0, 0.0, mu, 0};
            hint[i] = 1;
        }
        p = problem(3, Md, vs, 0.0, N, r);
        ENSURE(fc_solve(&p, hint, vs, NULL, lam, beta, &res) == 1);
        for (int i = 0; i < N; i++) {
            double x = -h + 2.0 * h * i / (N - 1);
            ENSURE(lam[i] >= 0.0);
            ENSURE(res.v[1] + x * res.v[2] >= -1e-14);
            ls += lam[i];
            bs += beta[i];
            mom += lam[i] * x;
        }
        ENSURE_CLOSE(ls, Md[0] * 1.0, 1e-14);
        ENSURE_CLOSE(res.v[1], 0.0, 1e-14);
        ENSURE_CLOSE(res.v[2], 0.0, 1e-12);
        ENSURE_CLOSE(mom, bs * h, 1e-15);
        if (0.5 <= mu * 1.0) {
            ENSURE_CLOSE(res.v[0], 0.0, 1e-14);
            ENSURE_CLOSE(bs, Md[0] * 0.5, 1e-14);
        } else {
            ENSURE_CLOSE(res.v[0], 0.5 - mu * 1.0, 1e-14);
            ENSURE_CLOSE(bs, mu * ls, 1e-14);
        }
    }
}

/* 1-DoF: a row G v >= rhs with a sliding contact. With the row on, v =
 * rhs / G, and the balance M (v - vs) = -c sign(v) + lam (G - mu sigma T),
 * sigma = sign(T v + tb), gives lam = (M (v - vs) + c sign(v)) / (G - mu
 * sigma T). With mu sigma T > G no lam >= 0 exists and the row cannot
 * hold (the prescribed motion jams): fc_solve reports no mode. */
EXDEX_TEST(fcontact_1dof_inclined_closed_form_and_jam)
{
    double Md[3] = {0.5, 0, 0}, vs[3] = {-0.3, 0, 0}, c = 0.05, lam[1], beta[1];
    double G = 0.8, T = 0.6, rhs = -0.1, tb = -0.4, mu = 0.5;
    fc_row r = {{G, 0, 0}, {T, 0, 0}, rhs, tb, mu, 0};
    fc_problem p = problem(1, Md, vs, c, 1, &r);
    fc_result res;
    unsigned char hint[1] = {1};
    double v = rhs / G, s = T * v + tb, sigma = s > 0 ? 1.0 : -1.0;
    double l = (Md[0] * (v - vs[0]) + c * (v > 0 ? 1.0 : -1.0)) / (G - mu * sigma * T);
    ENSURE(l > 0);
    ENSURE(fc_solve(&p, hint, vs, NULL, lam, beta, &res) == 1);
    ENSURE_CLOSE(res.v[0], v, 1e-15);
    ENSURE_CLOSE(lam[0], l, 1e-14);
    ENSURE_CLOSE(beta[0], -sigma * mu * l, 1e-14);
    /* jam: friction stronger than the normal force's own effect */
    r.mu = 2.0;
    r.tb = 0.4; /* the contact slides the other way: sigma = +1, G - mu T < 0 */
    ENSURE(fc_solve(&p, hint, vs, NULL, lam, beta, &res) == 0);
}

/* Plate rest against a static frictional contact: the particle pressed
 * into a wall, G = (1, 0, 0), T = (0, 1, 0), rhs = 0, A = I: the needed
 * impulse b = -M vs = (0.2, -0.15) must come from the wall, lam (1, 0) +
 * beta (0, 1) with |beta| <= mu lam (mu = 0.5), plus a plate impulse P
 * with |P| <= cap. The split is a creeping plate's (its creep v ~ -P): the
 * wall blocks the creep into it, so P has no normal part, lam = 0.2; the
 * creep then slips along the wall (P_y < 0, creep +y), the wall's friction
 * is kinetic against it, beta = -mu lam = -0.1, and P = b - (lam, beta) =
 * (0, -0.05), |P| = 0.05. Rest (v = 0 exactly) iff |P| <= cap. The least
 * plate friction over the wall's cone would be the distance from b to the
 * cone, 0.0447 (nearest its edge (1, -mu): the plate pressing into the
 * wall), so at cap 0.048 it would rest where the creep slides. */
EXDEX_TEST(fcontact_rest_cone_is_the_creeping_plates_split)
{
    double Md[3] = {1.0, 1.0, 1.0}, vs[3] = {-0.2, 0.15, 0.0}, lam[1], beta[1];
    fc_row r = {{1, 0, 0}, {0, 1, 0}, 0.0, 0.0, 0.5, 1};
    fc_problem p = problem(3, Md, vs, 0.06, 1, &r);
    fc_result res;
    unsigned char hint[1] = {1};
    ENSURE(fc_solve(&p, hint, vs, NULL, lam, beta, &res) == 1);
    ENSURE(res.rest == 1 && res.v[0] == 0.0 && res.v[1] == 0.0 && res.v[2] == 0.0);
    ENSURE_CLOSE(lam[0], 0.2, 1e-14);
    ENSURE_CLOSE(beta[0], -0.1, 1e-14);
    ENSURE(fabs(res.P[0]) <= 1e-15);
    ENSURE_CLOSE(res.P[1], -0.05, 1e-14);
    /* capacity below |P|: no rest; it slides along the wall (no normal
     * velocity: the wall stops it, lam = 0.2 from the normal balance), also
     * between the least-friction need and the creep's */
    for (int k = 0; k < 2; k++) {
        p.cap = k ? 0.048 : 0.04;
        ENSURE(fc_solve(&p, hint, vs, NULL, lam, beta, &res) == 1);
        ENSURE(res.rest == 0 && res.v[1] > 0.0);
        ENSURE_CLOSE(res.v[0], 0.0, 1e-15);
        ENSURE_CLOSE(lam[0], 0.2, 1e-13);
    }
}

static unsigned long long rng, rng_seed; /* restarted at each test from its seed */
static double urand(void)
{
    if (rng_seed != check_seed()) rng = rng_seed = check_seed();
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

/* Seeded random problems (n = 3, up to 3 rows at rhs = 0, static contacts
 * tb = 0, random mu, plate capacity and slip map): every solution returned
 * satisfies the defining conditions, and the kinetic energy does not grow:
 * v.M(v - vs) = v.P + sum lam G v + sum beta T v <= 0 term by term (the
 * plate dissipates, lam G v = lam rhs = 0, beta opposes the slip T v), so
 * |v|_M^2 <= v.M vs <= |v|_M |vs|_M. */
EXDEX_TEST(fcontact_random_conditions_and_energy)
{
    int solved = 0, trials = 400;
    for (int t = 0; t < trials; t++) {
        fc_row rows[3];
        double Md[3], vs[3], lam[3], beta[3], R[3], ev = 0.0, evs = 0.0, scale = 0.0;
        int nr = 1 + t % 3;
        fc_problem p;
        fc_result res;
        unsigned char hint[3] = {0, 0, 0};
        for (int c = 0; c < 3; c++) {
            Md[c] = 0.5 + urand();
            vs[c] = 2.0 * urand() - 1.0;
        }
        for (int i = 0; i < nr; i++) {
            double a = 6.283185307179586 * urand(), rr = 0.5 * urand();
            double nx = cos(a), ny = sin(a);
            rows[i].G[0] = nx;
            rows[i].G[1] = ny;
            rows[i].G[2] = rr * (2.0 * urand() - 1.0);
            rows[i].T[0] = -ny;
            rows[i].T[1] = nx;
            rows[i].T[2] = rr * (2.0 * urand() - 1.0);
            rows[i].rhs = 0.0;
            rows[i].tb = 0.0;
            rows[i].mu = t % 5 == 0 ? 0.0 : 1.2 * urand();
            rows[i].rest = 1;
        }
        p = problem(3, Md, vs, (t % 4 == 0) ? 0.0 : 0.5 * urand(), nr, rows);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) p.A[i][j] = (i == j ? 1.0 : 0.0) + 0.3 * (urand() - 0.5);
        if (!fc_solve(&p, hint, vs, NULL, lam, beta, &res)) continue;
        solved++;
        for (int c = 0; c < 3; c++) {
            R[c] = Md[c] * (res.v[c] - vs[c]) - res.P[c];
            for (int i = 0; i < nr; i++) R[c] -= lam[i] * rows[i].G[c] + beta[i] * rows[i].T[c];
            scale += Md[c] * fabs(vs[c]) + fabs(res.P[c]);
            ev += Md[c] * res.v[c] * res.v[c];
            evs += Md[c] * vs[c] * vs[c];
        }
        for (int c = 0; c < 3; c++) ENSURE_SMALL(R[c], 1e-12 * (1.0 + scale));
        ENSURE(ev <= evs * (1.0 + 1e-12));
        for (int i = 0; i < nr; i++) {
            double gv = rows[i].G[0] * res.v[0] + rows[i].G[1] * res.v[1] + rows[i].G[2] * res.v[2];
            double s = rows[i].T[0] * res.v[0] + rows[i].T[1] * res.v[1] + rows[i].T[2] * res.v[2];
            ENSURE(lam[i] >= 0.0);
            ENSURE(gv >= -1e-12);
            ENSURE(lam[i] * gv <= 1e-12 * (1.0 + lam[i]));
            ENSURE(fabs(beta[i]) <= rows[i].mu * lam[i] * (1.0 + 1e-10) + 1e-14);
            if (fabs(s) > 1e-10) ENSURE_CLOSE(beta[i], -copysign(rows[i].mu * lam[i], s), 1e-10 * (1.0 + lam[i]));
        }
        /* the plate: at rest inside the ellipsoid, sliding on it against the slip */
        {
            double u[3];
            for (int i = 0; i < 3; i++) u[i] = p.A[i][0] * res.v[0] + p.A[i][1] * res.v[1] + p.A[i][2] * res.v[2];
            if (res.rest) {
                ENSURE(res.v[0] == 0.0 && res.v[1] == 0.0 && res.v[2] == 0.0);
            } else if (p.cap > 0.0) {
                double nu = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
                for (int c = 0; c < 3; c++) {
                    double Pc = -p.cap * (p.A[0][c] * u[0] + p.A[1][c] * u[1] + p.A[2][c] * u[2]) / nu;
                    ENSURE_CLOSE(res.P[c], Pc, 1e-12 * (1.0 + p.cap));
                }
            }
        }
    }
    /* every problem here has a solution (Stewart-Trinkle at rhs = 0, tb =
     * 0: v = 0 with the contacts inside their cones is one when the plate
     * and the cones hold, else a slide); the enumeration must find most */
    report("fcontact_random_solved_fraction", (double)solved / trials);
    ENSURE(solved >= trials * 95 / 100);
}
