/* hybrid_scene.c -- the shared set-up of hybrid_scene.h. */
#include "hybrid_scene.h"

#include <string.h>

exdex_scene_def scene_plate_box(double a, double b, double c, double m)
{
    exdex_scene_def d = exdex_default_scene_def();
    d.mass = m;
    memset(d.inertia, 0, sizeof d.inertia);
    d.inertia[0] = m * (b * b + c * c) / 12.0;
    d.inertia[4] = m * (a * a + c * c) / 12.0;
    d.inertia[8] = m * (a * a + b * b) / 12.0;
    d.mu = 0.0;
    d.gravity[0] = d.gravity[1] = 0.0;
    d.gravity[2] = -9.81;
    d.dof = EXDEX_DOF_PLANAR;
    memset(d.R0, 0, sizeof d.R0);   /* B = A: the plate plane is A's x-y plane */
    d.R0[0] = d.R0[4] = d.R0[8] = 1.0;
    d.n_vertices = 4;
    d.vertices[0][0] = a / 2;  d.vertices[0][1] = -b / 2;
    d.vertices[1][0] = a / 2;  d.vertices[1][1] = b / 2;
    d.vertices[2][0] = -a / 2; d.vertices[2][1] = b / 2;
    d.vertices[3][0] = -a / 2; d.vertices[3][1] = -b / 2;
    return d;
}

void scene_obstacle_box(exdex_scene_def *d, int o, const double ctr[3], const double half[3])
{
    if (d->n_obstacles < o + 1) d->n_obstacles = o + 1;
    d->obstacles[o].kind = EXDEX_OBSTACLE_POLYTOPE;
    d->obstacles[o].n_faces = 6;
    for (int i = 0; i < 3; i++)
        for (int s = 0; s < 2; s++) {
            int f = 2 * i + s;
            memset(d->obstacles[o].face_point[f], 0, sizeof d->obstacles[o].face_point[f]);
            memset(d->obstacles[o].face_normal[f], 0, sizeof d->obstacles[o].face_normal[f]);
            d->obstacles[o].face_normal[f][i] = s ? -1.0 : 1.0;
            d->obstacles[o].face_point[f][i] = ctr[i] + (s ? -half[i] : half[i]);
        }
}

int begin_run(const exdex_scene_def *d, double t_end, begun *b)
{
    int status = 0;
    const char *bad = NULL;
    memset(b, 0, sizeof *b);
    b->m = exdex_model_alloc(d, &status, &bad);
    if (!b->m) return status ? status : -1;
    b->O = method_event.alloc(b->m, &status);
    if (!b->O) return status;
    return method_event.begin(b->m, b->O, t_end, t_end, &b->st);
}

void end_run(begun *b)
{
    method_event.free(b->O);
    exdex_model_free(b->m);
}
