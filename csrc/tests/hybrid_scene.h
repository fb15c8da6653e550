/* hybrid_scene.h -- test set-up shared by the C test files of the hybrid
 * methods' internals and of the obstacle rows (test_hybrid_decide.c,
 * test_hybrid_events.c, test_obstacle_rows.c): a box in the plate plane, a
 * box obstacle, and an event run begun on a scene so that a test can call
 * the methods' functions directly on its state. */
#ifndef EXDEX_TEST_HYBRID_SCENE_H
#define EXDEX_TEST_HYBRID_SCENE_H

#include "../hybrid.h"

/* A planar box of sides a x b x c and mass m with B = A (the plate plane is
 * A's x-y plane): its inertia about the centre of mass, mu = 0, gravity
 * 9.81 m/s^2 along -A z (the plate normal), the outline (a/2, -b/2),
 * (a/2, b/2), (-a/2, b/2), (-a/2, -b/2); the rest as
 * exdex_default_scene_def. */
exdex_scene_def scene_plate_box(double a, double b, double c, double m);

/* Obstacle o (n_obstacles becomes at least o + 1) the box |x_i - ctr[i]|
 * <= half[i] in A: a polytope of 6 faces, face 2 i + s with the outward
 * normal +e_i (s = 0) or -e_i (s = 1). Its friction is left as it was. */
void scene_obstacle_box(exdex_scene_def *d, int o, const double ctr[3], const double half[3]);

/* An event run of a scene definition begun for t_end (its first output
 * step t_end): the model, the method's workspace (its state O->S) and the
 * run's stats. begin_run returns the first failing status (model, alloc,
 * begin); end_run frees what it made. */
typedef struct begun {
    exdex_model *m;
    ode *O;
    exdex_stats st;
} begun;

int begin_run(const exdex_scene_def *d, double t_end, begun *b);
void end_run(begun *b);

#endif
