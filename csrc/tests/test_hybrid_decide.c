/* test_hybrid_decide.c -- rules of the hybrid methods' decision
 * (hybrid_decide.c), called directly on the state of a begun event run,
 * against closed forms.
 *
 * hyb_hold_set_rows: at a decision the contact set's obstacle rows are put
 * back onto their features, positions and velocities, by the M-metric
 * projection onto the set rows as equalities. The scene: a box (a x b,
 * mass m) sliding freely (mu = 0, gravity along the plate normal, B = A) on
 * the top face y = -b/2 of an obstacle box, its two lower corners (x_j =
 * +-a/2, -b/2) in the contact set. Each corner's row against the face has
 * G_j = (0, 1, x_j) (d gap / d(x, y, theta) at theta = 0) and gap y (a
 * translation). Lifted by delta and moving up at w (a drift the decision
 * must remove), the projection solves G_j dq = -delta for both rows with
 * dq = M^-1 G^T lam: by the symmetry x_1 = -x_2, lam_1 = lam_2, so dq =
 * (0, -delta, 0); and G_j v = 0 with v = v0 + M^-1 G^T mu: (vx, 0, 0), vx
 * untouched (G has no x component). Rows left on their face are left
 * alone (bit for bit). */
#include "check.h"
#include "hybrid_scene.h"

#include <math.h>
#include <string.h>

#define BOX_A 0.04
#define BOX_B 0.02

static exdex_scene_def slide_def(double vx)
{
    double a = BOX_A, b = BOX_B, top = -b / 2, h = 0.05;
    exdex_scene_def d = scene_plate_box(a, b, 0.01, 0.1);
    d.grip_force = 1.0;
    d.fingers = 2;
    d.e_r = 0.0033;
    d.v0[0] = vx;
    /* the obstacle: a box 0.2 x h x 0.1 below the object, top face y = -b/2 */
    scene_obstacle_box(&d, 0, (const double[3]){0.0, top - h / 2, 0.0}, (const double[3]){0.1, h / 2, 0.05});
    d.obstacles[0].mu = 0.0;
    d.method = EXDEX_METHOD_EVENT;
    d.rtol = 1e-10;
    d.atol = 1e-10;
    return d;
}

EXDEX_TEST(hold_set_rows_puts_drifted_obstacle_rows_back_on_their_face)
{
    const double vx = 0.01, delta = 1e-5, w = 0.003;
    exdex_scene_def d = slide_def(vx);
    begun b;
    exdex_kinematics kin;
    frame f;
    int code[MAX_ROWS], n, ncs = 0;
    double gap[MAX_ROWS], y[NY_MAX], y_on[NY_MAX];
    ENSURE(begin_run(&d, 1.0, &b) == EXDEX_OK);
    const exdex_model *m = b.m;
    ode *O = b.O;
    hyb *H = &O->S.H;
    ENSURE(H->law == LAW_COULOMB && H->mode == MODE_SLIP && H->no == 1 && H->ns == 0);
    memcpy(y, O->S.y, sizeof y);
    ENSURE(hyb_frame_seg(H, 0.0, &f, &kin) == EXDEX_OK);
    /* the lower corners' rows against the top face: the contact set */
    n = orow_all(m, &kin, y, y + 3, 1, code, gap);
    for (int i = 0; i < n; i++)
        if (orow_kind(code[i]) == OROW_VERTEX && fabs(gap[i]) <= 1e-15) H->cs[ncs++] = code[i];
    ENSURE(ncs == 2);
    H->ncs = ncs;
    H->sgn = 0;
    /* on the face: left alone */
    memcpy(y_on, y, sizeof y_on);
    hyb_hold_set_rows(H, 0.0, y);
    ENSURE(memcmp(y, y_on, (size_t)H->ny * sizeof *y) == 0);
    /* lifted by delta, moving up at w */
    y[1] = delta;
    y[4] = w;
    hyb_hold_set_rows(H, 0.0, y);
    /* to rounding: 1e-12 of the drift removed (delta in position, w in rate;
     * theta's part relative to them over the half-width a / 2) */
    ENSURE(y[0] == 0.0);
    ENSURE_SMALL(y[1], 1e-12 * delta);
    ENSURE_SMALL(y[2], 1e-12 * delta / (BOX_A / 2));
    ENSURE(y[3] == vx);
    ENSURE_SMALL(y[4], 1e-12 * w);
    ENSURE_SMALL(y[5], 1e-12 * w / (BOX_A / 2));
    for (int i = 0; i < ncs; i++) {
        double G[3], gd;
        ENSURE_SMALL(orow_planar(m, &kin, H->cs[i], y, y + 3, G, &gd, NULL), 1e-12 * delta);
        ENSURE_SMALL(gd, 1e-12 * w);
    }
    end_run(&b);
}
