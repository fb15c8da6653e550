/* _coremodule.c -- exdex._core: the CPython + NumPy C API wrapper of the
 * simulation core (csrc/). Converts and validates arguments, releases the GIL
 * around whole-trajectory C calls, maps C status codes to exceptions, and runs
 * batches of trajectories on POSIX threads (simulate_batch).
 *
 * The Python layer (exdex/scene.py, exdex/simulate.py) validates user input
 * with friendly messages first; this module checks again, because it is
 * callable directly, and names the offending key in every error. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <pythread.h>
#define PY_ARRAY_UNIQUE_SYMBOL exdex_core_ARRAY_API
#include <numpy/arrayobject.h>

#include <pthread.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "exdex.h"
#include "_common.h"

typedef struct {
    PyObject *SolverError;
    PyObject *ModelType;
    PyObject *StepperType;
} core_state;

static core_state *get_state(PyObject *module) { return (core_state *)PyModule_GetState(module); }

/* Raise the library exception for a C status (the mapping of _common.h). */
static PyObject *raise_status(PyObject *module, int status, const char *what, const char *bad)
{
    return expy_raise_status(get_state(module)->SolverError, status, what, bad, NULL, -1);
}

/* Convert obj to a C-contiguous float64 array of exactly `n` elements. New
 * reference or NULL with TypeError/ValueError naming `name`. */
static PyArrayObject *as_doubles(PyObject *obj, npy_intp n, const char *name)
{
    PyArrayObject *arr;
    if (!PyArray_Check(obj) && !PySequence_Check(obj) && !PyNumber_Check(obj)) {
        PyErr_Format(PyExc_TypeError, "'%s' must be a number or an array of numbers, not %s", name,
                     Py_TYPE(obj)->tp_name);
        return NULL;
    }
    arr = (PyArrayObject *)PyArray_FROMANY(obj, NPY_DOUBLE, 0, 3, NPY_ARRAY_IN_ARRAY);
    if (!arr) {
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "'%s' must be convertible to a float64 array", name);
        return NULL;
    }
    if (n >= 0 && PyArray_SIZE(arr) != n) {
        PyErr_Format(PyExc_ValueError, "'%s' must have %zd elements, got %zd", name, (Py_ssize_t)n,
                     (Py_ssize_t)PyArray_SIZE(arr));
        Py_DECREF(arr);
        return NULL;
    }
    return arr;
}

static int dict_doubles(PyObject *d, const char *key, double *out, npy_intp n)
{
    PyObject *obj = PyDict_GetItemString(d, key); /* borrowed */
    PyArrayObject *arr;
    if (!obj) {
        PyErr_Format(PyExc_KeyError, "scene spec is missing '%s'", key);
        return -1;
    }
    arr = as_doubles(obj, n, key);
    if (!arr) return -1;
    memcpy(out, PyArray_DATA(arr), (size_t)n * sizeof(double));
    Py_DECREF(arr);
    return 0;
}

static int dict_double(PyObject *d, const char *key, double *out) { return dict_doubles(d, key, out, 1); }

static int dict_int(PyObject *d, const char *key, int *out)
{
    PyObject *obj = PyDict_GetItemString(d, key);
    long v;
    if (!obj) {
        PyErr_Format(PyExc_KeyError, "scene spec is missing '%s'", key);
        return -1;
    }
    if (!PyLong_Check(obj)) {
        PyErr_Format(PyExc_TypeError, "'%s' must be an int, not %s", key, Py_TYPE(obj)->tp_name);
        return -1;
    }
    v = PyLong_AsLong(obj);
    if (v == -1 && PyErr_Occurred()) return -1;
    if (v < -1000000 || v > 1000000) {
        PyErr_Format(PyExc_ValueError, "'%s' out of range", key);
        return -1;
    }
    *out = (int)v;
    return 0;
}

/* Optional (k, cols) array from the dict; returns a new ref (may be an empty
 * array) and its row count. */
static PyArrayObject *dict_rows(PyObject *d, const char *key, int cols, int max_rows, npy_intp *rows)
{
    PyObject *obj = PyDict_GetItemString(d, key);
    PyArrayObject *arr;
    if (!obj || obj == Py_None) {
        *rows = 0;
        return (PyArrayObject *)PyArray_ZEROS(1, (npy_intp[]){0}, NPY_DOUBLE, 0);
    }
    arr = (PyArrayObject *)PyArray_FROMANY(obj, NPY_DOUBLE, 1, 2, NPY_ARRAY_IN_ARRAY);
    if (!arr) {
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "'%s' must be a float64 array of shape (k, %d)", key, cols);
        return NULL;
    }
    if (PyArray_SIZE(arr) == 0) {
        *rows = 0;
        return arr;
    }
    if (PyArray_NDIM(arr) != 2 || PyArray_DIM(arr, 1) != cols ||
        (max_rows > 0 && PyArray_DIM(arr, 0) > max_rows)) {
        if (max_rows > 0)
            PyErr_Format(PyExc_ValueError, "'%s' must have shape (k, %d) with k <= %d", key, cols, max_rows);
        else
            PyErr_Format(PyExc_ValueError, "'%s' must have shape (k, %d)", key, cols);
        Py_DECREF(arr);
        return NULL;
    }
    *rows = PyArray_DIM(arr, 0);
    return arr;
}

/* Optional sampled-motion keys (absent: end slopes from the data, absolute
 * poses, no tool): motion_end_given (2 flags, 0 or 1), motion_end_velocity
 * and motion_end_omega (2 x 3: first, last sample), motion_relative and
 * motion_tool (0 or 1), motion_tool_pose (7: x y z qw qx qy qz). A flag
 * other than 0 or 1 is passed on as 2, which the core rejects by name. */
static int sampled_options(PyObject *spec, exdex_motion_def *mo)
{
    double g[2];
    if (PyDict_GetItemString(spec, "motion_end_given")) {
        if (dict_doubles(spec, "motion_end_given", g, 2)) return -1;
        for (int e = 0; e < 2; e++) mo->end_given[e] = (g[e] == 0.0 || g[e] == 1.0) ? (int)g[e] : 2;
    }
    if (PyDict_GetItemString(spec, "motion_end_velocity") &&
        dict_doubles(spec, "motion_end_velocity", &mo->end_velocity[0][0], 6))
        return -1;
    if (PyDict_GetItemString(spec, "motion_end_omega") &&
        dict_doubles(spec, "motion_end_omega", &mo->end_omega[0][0], 6))
        return -1;
    if (PyDict_GetItemString(spec, "motion_relative") && dict_int(spec, "motion_relative", &mo->relative))
        return -1;
    if (PyDict_GetItemString(spec, "motion_tool") && dict_int(spec, "motion_tool", &mo->tool)) return -1;
    if (PyDict_GetItemString(spec, "motion_tool_pose") && dict_doubles(spec, "motion_tool_pose", mo->tool_pose, 7))
        return -1;
    return 0;
}

/* One obstacle from its dict: kind (int), and face_points / face_normals
 * ((k, 3), polytope) or center, axis (3) and radius (cylinder); optional
 * mu (default 0). */
static int obstacle_from_dict(PyObject *d, exdex_obstacle_def *o)
{
    memset(o, 0, sizeof *o);
    if (!PyDict_Check(d)) {
        PyErr_SetString(PyExc_TypeError, "'obstacles' must be a list of dicts (use exdex.Obstacle)");
        return -1;
    }
    if (dict_int(d, "kind", &o->kind)) return -1;
    if (PyDict_GetItemString(d, "mu") && dict_double(d, "mu", &o->mu)) return -1;
    if (o->kind == EXDEX_OBSTACLE_POLYTOPE) {
        npy_intp nfp, nfn;
        PyArrayObject *fp = dict_rows(d, "face_points", 3, EXDEX_MAX_FACES, &nfp), *fn;
        if (!fp) return -1;
        fn = dict_rows(d, "face_normals", 3, EXDEX_MAX_FACES, &nfn);
        if (!fn) {
            Py_DECREF(fp);
            return -1;
        }
        if (nfp != nfn) {
            PyErr_SetString(PyExc_ValueError, "'face_points' and 'face_normals' must have the same length");
            Py_DECREF(fp);
            Py_DECREF(fn);
            return -1;
        }
        o->n_faces = (int)nfp;
        if (nfp) {
            memcpy(o->face_point, PyArray_DATA(fp), (size_t)nfp * 3 * sizeof(double));
            memcpy(o->face_normal, PyArray_DATA(fn), (size_t)nfn * 3 * sizeof(double));
        }
        Py_DECREF(fp);
        Py_DECREF(fn);
        return 0;
    }
    if (dict_doubles(d, "center", o->center, 3) || dict_doubles(d, "axis", o->axis, 3) ||
        dict_double(d, "radius", &o->radius))
        return -1;
    return 0;
}

/* Optional 'obstacles' key: a sequence of obstacle dicts. */
static int obstacles_from_dict(PyObject *spec, exdex_scene_def *def)
{
    PyObject *obj = PyDict_GetItemString(spec, "obstacles"), *seq;
    Py_ssize_t n;
    def->n_obstacles = 0;
    if (!obj || obj == Py_None) return 0;
    seq = PySequence_Fast(obj, "'obstacles' must be a sequence of obstacle dicts");
    if (!seq) return -1;
    n = PySequence_Fast_GET_SIZE(seq);
    if (n > EXDEX_MAX_OBSTACLES) {
        PyErr_Format(PyExc_ValueError, "'obstacles' holds at most %d obstacles", EXDEX_MAX_OBSTACLES);
        Py_DECREF(seq);
        return -1;
    }
    for (Py_ssize_t i = 0; i < n; i++)
        if (obstacle_from_dict(PySequence_Fast_GET_ITEM(seq, i), &def->obstacles[i])) {
            Py_DECREF(seq);
            return -1;
        }
    def->n_obstacles = (int)n;
    Py_DECREF(seq);
    return 0;
}

/* Store `item` (a new reference, stolen) at index i of the object array keep. */
static void keep_item(PyArrayObject *keep, npy_intp i, PyObject *item)
{
    PyObject **slot = (PyObject **)PyArray_GETPTR1(keep, i);
    Py_XSETREF(*slot, item);
}

/* Chain pieces (motion_kind EXDEX_MOTION_CHAIN): `motion_pieces`, a sequence
 * of dicts with the motion_* keys of a scene spec (motion_kind,
 * motion_rotation, motion_axis, motion_center, motion_amplitude,
 * motion_duration, motion_beta, motion_v_max, motion_frequency; sampled:
 * motion_times, motion_poses and the optional keys of sampled_options),
 * and the optional motion_allow_jump (0 or 1). The piece definitions and
 * their sample arrays live in the object array *keep (a new reference the
 * caller keeps until the model is built). */
static int chain_pieces(PyObject *spec, exdex_motion_def *mo, PyArrayObject **keep)
{
    PyObject *obj = PyDict_GetItemString(spec, "motion_pieces"), *seq = NULL, *buf = NULL;
    exdex_motion_def *pieces;
    Py_ssize_t n;
    npy_intp nk;
    if (PyDict_GetItemString(spec, "motion_allow_jump") && dict_int(spec, "motion_allow_jump", &mo->allow_jump))
        return -1;
    if (!obj) {
        PyErr_SetString(PyExc_KeyError, "scene spec is missing 'motion_pieces'");
        return -1;
    }
    seq = PySequence_Fast(obj, "'motion_pieces' must be a sequence of motion dicts");
    if (!seq) return -1;
    n = PySequence_Fast_GET_SIZE(seq);
    if (n < 1 || n > EXDEX_MOTION_MAX_PIECES) {
        PyErr_Format(PyExc_ValueError, "'motion_pieces' must hold 1 to %d pieces, got %zd", EXDEX_MOTION_MAX_PIECES, n);
        Py_DECREF(seq);
        return -1;
    }
    nk = 1 + 2 * (npy_intp)n;
    *keep = (PyArrayObject *)PyArray_ZEROS(1, &nk, NPY_OBJECT, 0);
    buf = PyBytes_FromStringAndSize(NULL, n * (Py_ssize_t)sizeof(exdex_motion_def));
    if (!*keep || !buf) goto fail;
    pieces = (exdex_motion_def *)PyBytes_AS_STRING(buf);
    keep_item(*keep, 0, buf);
    for (Py_ssize_t i = 0; i < n; i++) {
        PyObject *d = PySequence_Fast_GET_ITEM(seq, i);
        exdex_motion_def *pd = &pieces[i];
        memset(pd, 0, sizeof *pd);
        if (!PyDict_Check(d)) {
            PyErr_Format(PyExc_TypeError, "'motion_pieces[%zd]' must be a dict", i);
            goto fail;
        }
        if (dict_int(d, "motion_kind", &pd->kind) || dict_int(d, "motion_rotation", &pd->rotation) ||
            dict_doubles(d, "motion_axis", pd->axis, 3) || dict_doubles(d, "motion_center", pd->center, 3) ||
            dict_double(d, "motion_amplitude", &pd->amplitude) ||
            dict_double(d, "motion_duration", &pd->duration) || dict_double(d, "motion_beta", &pd->beta) ||
            dict_double(d, "motion_v_max", &pd->v_max))
            goto fail;
        if (PyDict_GetItemString(d, "motion_frequency") && dict_double(d, "motion_frequency", &pd->frequency))
            goto fail;
        if (pd->kind == EXDEX_MOTION_SAMPLED) {
            PyObject *tobj = PyDict_GetItemString(d, "motion_times");
            PyArrayObject *t, *p;
            npy_intp np_;
            if (!tobj) {
                PyErr_Format(PyExc_KeyError, "'motion_pieces[%zd]' is missing 'motion_times'", i);
                goto fail;
            }
            t = as_doubles(tobj, -1, "motion_times");
            if (!t) goto fail;
            keep_item(*keep, 1 + 2 * i, (PyObject *)t);
            if (PyArray_NDIM(t) != 1) {
                PyErr_SetString(PyExc_ValueError, "'motion_times' must be 1-D");
                goto fail;
            }
            p = dict_rows(d, "motion_poses", 7, -1, &np_);
            if (!p) goto fail;
            keep_item(*keep, 2 + 2 * i, (PyObject *)p);
            if (np_ != PyArray_SIZE(t)) {
                PyErr_SetString(PyExc_ValueError, "'motion_poses' must have one row per entry of 'motion_times'");
                goto fail;
            }
            pd->n_samples = (size_t)np_;
            pd->times = (const double *)PyArray_DATA(t);
            pd->poses = (const double *)PyArray_DATA(p);
            if (sampled_options(d, pd)) goto fail;
        }
    }
    Py_DECREF(seq);
    mo->n_pieces = (size_t)n;
    mo->pieces = pieces;
    return 0;
fail:
    if (!*keep) Py_XDECREF(buf);
    Py_XDECREF(seq);
    Py_CLEAR(*keep);
    return -1;
}

/* Optional grip schedule: key grip_schedule, a (2, n) float64 array (row 0
 * the times, row 1 the forces; n >= 1), and grip_kind (0 linear, 1 cubic,
 * 2 step). The array is returned as a new reference in *grip (kept alive
 * by the caller until the model is built), NULL without a schedule. */
static int grip_from_dict(PyObject *spec, exdex_scene_def *def, PyArrayObject **grip)
{
    PyObject *obj = PyDict_GetItemString(spec, "grip_schedule");
    if (!obj || obj == Py_None) return 0;
    if (PyDict_GetItemString(spec, "grip_kind") && dict_int(spec, "grip_kind", &def->grip_kind)) return -1;
    *grip = (PyArrayObject *)PyArray_FROMANY(obj, NPY_DOUBLE, 2, 2, NPY_ARRAY_IN_ARRAY);
    if (!*grip || PyArray_DIM(*grip, 0) != 2 || PyArray_DIM(*grip, 1) < 1) {
        Py_CLEAR(*grip);
        PyErr_Clear();
        PyErr_SetString(PyExc_ValueError, "'grip_schedule' must be a float64 array of shape (2, n), n >= 1 "
                                          "(row 0 the times, row 1 the forces)");
        return -1;
    }
    def->grip_n = (size_t)PyArray_DIM(*grip, 1);
    def->grip_times = (const double *)PyArray_DATA(*grip);
    def->grip_forces = def->grip_times + def->grip_n;
    return 0;
}

/* Optional pads on the fingers: pad (k, 2) or pad_radius, pad_center,
 * pad_scale; face (k, 2) or face_radius, face_center (absent: the patch
 * fixed on the object). */
static int pads_from_dict(PyObject *spec, exdex_scene_def *def)
{
    static const char *keys[2] = {"pad", "face"};
    for (int k = 0; k < 2; k++) {
        npy_intp n = 0;
        PyArrayObject *a = dict_rows(spec, keys[k], 2, EXDEX_MAX_PAD_VERTICES, &n);
        if (!a) return -1;
        if (n) memcpy(k ? def->face : def->pad, PyArray_DATA(a), (size_t)n * 2 * sizeof(double));
        if (k) def->face_n = (int)n;
        else def->pad_n = (int)n;
        Py_DECREF(a);
    }
    if (PyDict_GetItemString(spec, "pad_radius") && dict_double(spec, "pad_radius", &def->pad_radius)) return -1;
    if (PyDict_GetItemString(spec, "pad_center") && dict_doubles(spec, "pad_center", def->pad_center, 2)) return -1;
    if (PyDict_GetItemString(spec, "pad_scale") && dict_double(spec, "pad_scale", &def->pad_scale)) return -1;
    if (PyDict_GetItemString(spec, "face_radius") && dict_double(spec, "face_radius", &def->face_radius)) return -1;
    if (PyDict_GetItemString(spec, "face_center") && dict_doubles(spec, "face_center", def->face_center, 2))
        return -1;
    return 0;
}

/* Optional limit surface: limit_surface (0 ellipsoid, 1 exact) and the
 * contact region region_vertices (k, 2) or region_radius (absent: none). */
static int surface_from_dict(PyObject *spec, exdex_scene_def *def)
{
    npy_intp n = 0;
    PyArrayObject *a;
    if (PyDict_GetItemString(spec, "limit_surface") && dict_int(spec, "limit_surface", &def->limit_surface))
        return -1;
    a = dict_rows(spec, "region_vertices", 2, EXDEX_REGION_MAX_VERTICES, &n);
    if (!a) return -1;
    if (n) {
        memcpy(def->region_vertices, PyArray_DATA(a), (size_t)n * 2 * sizeof(double));
        def->region_n = (int)n;
        def->region_kind = EXDEX_REGION_POLYGON;
    }
    Py_DECREF(a);
    if (PyDict_GetItemString(spec, "region_radius") && PyDict_GetItemString(spec, "region_radius") != Py_None) {
        if (dict_double(spec, "region_radius", &def->region_radius)) return -1;
        if (!n) def->region_kind = EXDEX_REGION_DISC;
    }
    return 0;
}

/* Fill an exdex_scene_def from a spec dict. Sampled-motion arrays and the
 * grip schedule are returned as new references in *times / *poses / *grip
 * (kept alive by the caller until the model is built); a chain's pieces and
 * their arrays in *times (an object array, chain_pieces). */
static int scene_from_dict(PyObject *spec, exdex_scene_def *def, PyArrayObject **times,
                           PyArrayObject **poses, PyArrayObject **grip)
{
    PyArrayObject *verts = NULL, *sp = NULL, *sn = NULL;
    npy_intp nv, nsp, nsn, nt, np_;
    *times = *poses = *grip = NULL;
    if (!PyDict_Check(spec)) {
        PyErr_SetString(PyExc_TypeError, "spec must be a dict (use exdex.Scene)");
        return -1;
    }
    *def = exdex_default_scene_def();
    if (dict_double(spec, "mass", &def->mass) || dict_doubles(spec, "inertia", def->inertia, 9) ||
        dict_double(spec, "mu", &def->mu) || dict_double(spec, "grip_force", &def->grip_force) ||
        dict_int(spec, "fingers", &def->fingers) || dict_double(spec, "e_r", &def->e_r) ||
        dict_doubles(spec, "patch_center", def->patch_center, 2) ||
        dict_doubles(spec, "gravity", def->gravity, 3) || dict_int(spec, "dof", &def->dof) ||
        dict_doubles(spec, "slide_axis", def->slide_axis, 2) || dict_doubles(spec, "q0", def->q0, 3) ||
        dict_doubles(spec, "v0", def->v0, 3) || dict_doubles(spec, "R0", def->R0, 9) ||
        dict_doubles(spec, "p0", def->p0, 3) || dict_int(spec, "motion_kind", &def->motion.kind) ||
        dict_int(spec, "motion_rotation", &def->motion.rotation) ||
        dict_doubles(spec, "motion_axis", def->motion.axis, 3) ||
        dict_doubles(spec, "motion_center", def->motion.center, 3) ||
        dict_double(spec, "motion_amplitude", &def->motion.amplitude) ||
        dict_double(spec, "motion_duration", &def->motion.duration) ||
        dict_double(spec, "motion_beta", &def->motion.beta) ||
        dict_double(spec, "motion_v_max", &def->motion.v_max) || dict_int(spec, "method", &def->method) ||
        dict_int(spec, "friction_solver", &def->friction_solver) || dict_double(spec, "eps", &def->eps) ||
        dict_double(spec, "rtol", &def->rtol) || dict_double(spec, "atol", &def->atol))
        return -1;
    /* optional: 0 (the C default) is "equal to mu" */
    if (PyDict_GetItemString(spec, "mu_static") && dict_double(spec, "mu_static", &def->mu_static)) return -1;
    /* optional: a disc outline (absent or 0: the polygon of 'vertices') */
    if (PyDict_GetItemString(spec, "disc_radius") && dict_double(spec, "disc_radius", &def->disc_radius)) return -1;
    if (PyDict_GetItemString(spec, "disc_center") && dict_doubles(spec, "disc_center", def->disc_center, 2))
        return -1;
    verts = dict_rows(spec, "vertices", 2, EXDEX_MAX_VERTICES, &nv);
    if (!verts) goto fail;
    sp = dict_rows(spec, "stop_points", 3, EXDEX_MAX_STOPS, &nsp);
    if (!sp) goto fail;
    sn = dict_rows(spec, "stop_normals", 3, EXDEX_MAX_STOPS, &nsn);
    if (!sn) goto fail;
    if (nsp != nsn) {
        PyErr_SetString(PyExc_ValueError, "'stop_points' and 'stop_normals' must have the same length");
        goto fail;
    }
    if (obstacles_from_dict(spec, def)) goto fail;
    def->n_vertices = (int)nv;
    if (nv) memcpy(def->vertices, PyArray_DATA(verts), (size_t)nv * 2 * sizeof(double));
    def->n_stops = (int)nsp;
    if (nsp) {
        memcpy(def->stop_point, PyArray_DATA(sp), (size_t)nsp * 3 * sizeof(double));
        memcpy(def->stop_normal, PyArray_DATA(sn), (size_t)nsn * 3 * sizeof(double));
    }
    /* optional: each stop's friction coefficient (absent: frictionless) */
    if (PyDict_GetItemString(spec, "stop_mus")) {
        PyArrayObject *smu = as_doubles(PyDict_GetItemString(spec, "stop_mus"), -1, "stop_mus");
        if (!smu) goto fail;
        if (PyArray_NDIM(smu) != 1 || PyArray_DIM(smu, 0) != nsp) {
            PyErr_SetString(PyExc_ValueError, "'stop_mus' must have one entry per stop");
            Py_DECREF(smu);
            goto fail;
        }
        if (nsp) memcpy(def->stop_mu, PyArray_DATA(smu), (size_t)nsp * sizeof(double));
        Py_DECREF(smu);
    }
    if (PyDict_GetItemString(spec, "motion_frequency") &&
        dict_double(spec, "motion_frequency", &def->motion.frequency))
        goto fail;
    if (pads_from_dict(spec, def)) goto fail;
    /* optional: the motion played from a later time (a continued run) */
    if (PyDict_GetItemString(spec, "motion_time_shift") &&
        dict_double(spec, "motion_time_shift", &def->motion.time_shift))
        goto fail;
    if (surface_from_dict(spec, def)) goto fail;
    if (def->motion.kind == EXDEX_MOTION_CHAIN && chain_pieces(spec, &def->motion, times)) goto fail;
    if (def->motion.kind == EXDEX_MOTION_SAMPLED) {
        PyObject *tobj = PyDict_GetItemString(spec, "motion_times");
        if (!tobj) {
            PyErr_SetString(PyExc_KeyError, "scene spec is missing 'motion_times'");
            goto fail;
        }
        *times = as_doubles(tobj, -1, "motion_times");
        if (!*times) goto fail;
        if (PyArray_NDIM(*times) != 1) {
            PyErr_SetString(PyExc_ValueError, "'motion_times' must be 1-D");
            goto fail;
        }
        nt = PyArray_SIZE(*times);
        *poses = dict_rows(spec, "motion_poses", 7, -1, &np_);
        if (!*poses) goto fail;
        if (np_ != nt) {
            PyErr_SetString(PyExc_ValueError, "'motion_poses' must have one row per entry of 'motion_times'");
            goto fail;
        }
        def->motion.n_samples = (size_t)nt;
        def->motion.times = (const double *)PyArray_DATA(*times);
        def->motion.poses = (const double *)PyArray_DATA(*poses);
        if (sampled_options(spec, &def->motion)) goto fail;
    }
    if (grip_from_dict(spec, def, grip)) goto fail;
    Py_DECREF(verts);
    Py_DECREF(sp);
    Py_DECREF(sn);
    return 0;
fail:
    Py_XDECREF(verts);
    Py_XDECREF(sp);
    Py_XDECREF(sn);
    Py_XDECREF(*times);
    Py_XDECREF(*poses);
    Py_XDECREF(*grip);
    *times = *poses = *grip = NULL;
    return -1;
}

/* A float, or None for NaN ("no such event": dicts with None compare equal). */
static PyObject *float_or_none(double x)
{
    if (isnan(x)) Py_RETURN_NONE;
    return PyFloat_FromDouble(x);
}

/* The impact and warning-time fields of exdex_stats into dict d (times
 * None when there was no impact / warning, the stop index then None too);
 * -1 on error. */
static int add_impact_stats(PyObject *d, const exdex_stats *st)
{
    PyObject *o = Py_BuildValue("{s:n,s:d,s:N,s:N,s:N}", "impacts", (Py_ssize_t)st->impacts, "max_impulse",
                                st->max_impulse, "max_impulse_t", float_or_none(st->max_impulse_t),
                                "max_impulse_stop",
                                st->max_impulse_stop >= 0 ? PyLong_FromLong(st->max_impulse_stop)
                                                          : Py_NewRef(Py_None),
                                "first_warning_t", float_or_none(st->first_warning_t));
    int rc = o ? PyDict_Update(d, o) : -1;
    Py_XDECREF(o);
    return rc;
}

static PyObject *stats_dict(const exdex_stats *st)
{
    PyObject *d = Py_BuildValue("{s:n,s:n,s:n,s:n,s:n,s:d}", "steps", (Py_ssize_t)st->steps, "stick_steps",
                                (Py_ssize_t)st->stick_steps, "solver_iterations", (Py_ssize_t)st->solver_iterations,
                                "stop_iterations", (Py_ssize_t)st->stop_iterations, "warnings",
                                (Py_ssize_t)st->warnings, "min_gap", st->min_gap);
    if (d && add_impact_stats(d, st)) Py_CLEAR(d);
    if (d) {
        PyObject *o = Py_BuildValue("{s:N}", "grasp_lost_t", float_or_none(st->lost_t));
        if (!o || PyDict_Update(d, o)) Py_CLEAR(d);
        Py_XDECREF(o);
    }
    return d;
}

/* Validate (t_end, dt) and set *n to the number of samples; -1 with a
 * ValueError naming the argument and its range. */
static int check_times(double t_end, double dt, size_t *n)
{
    if (!(isfinite(dt) && dt > 0)) {
        char b[96];
        PyOS_snprintf(b, sizeof b, "dt must be finite and > 0, got %g", dt);
        PyErr_SetString(PyExc_ValueError, b);
        return -1;
    }
    if (!(isfinite(t_end) && t_end >= dt)) {
        char b[128];
        PyOS_snprintf(b, sizeof b, "t_end must be finite and >= dt (%g), got %g", dt, t_end);
        PyErr_SetString(PyExc_ValueError, b);
        return -1;
    }
    *n = exdex_n_samples(t_end, dt);
    if (*n == 0) {
        char b[96];
        PyOS_snprintf(b, sizeof b, "t_end / dt must be between 1 and 1e9 steps, got %g", t_end / dt);
        PyErr_SetString(PyExc_ValueError, b);
        return -1;
    }
    return 0;
}

PyDoc_STRVAR(simulate_doc,
"simulate(spec, t_end, dt, certify=True, stop_at_failure=False) -> dict\n\n"
"Run one trajectory in C with the GIL released. `spec` is the dict made by\n"
"exdex.Scene.to_spec(); use exdex.simulate() instead of calling this directly.\n"
"Returns a dict of arrays t, q, v, wrench, stick, stop_force, a stats dict and\n"
"the certificate of a 1-DoF run's reduction (exdex_certify; None for planar\n"
"runs and with certify=False). stop_at_failure=True certifies as the run goes\n"
"(exdex_simulate_certified): a 1-DoF run whose reduction fails ends there, its\n"
"last sample at the certificate's valid_until.");

/* SolverError(message, status) of a failed run with attributes status, time
 * (exdex_stats.fail_time, None when unknown) and cause (a name): the message
 * says when, why, and what to use instead. index >= 0: trajectory `index` of
 * a batch (the message starts "batch index i: ", attribute `index`). */
static void raise_run_error_at(PyObject *module, int status, const exdex_stats *st, Py_ssize_t index)
{
    static const char *const names[] = {"none", "events", "step_budget", "step_floor",
                                        "stepper", "solver", "nonfinite"};
    static const char *const why[] = {
        "",
        "more than 1000 stick/slip/contact switches within one output interval (Zeno-like "
        "accumulation of events); use method='implicit' (fixed steps, exact stick), or a finer "
        "dt (the event budget is per output interval)",
        "more than 1e5 adaptive steps within one output interval (a stiff phase; for "
        "'regularised' a small eps); use method='implicit', a larger rtol/atol (or eps), or a "
        "finer dt (the step budget is per output interval)",
        "the adaptive step collapsed below 16 ulps of t; use method='implicit' or a larger rtol/atol",
        "the ODE stepper or the event location failed; use method='implicit' or a larger rtol/atol",
        "an inner solver did not converge; try another friction_solver or method",
        "the state left the finite range (check the scene's scales and motion)"};
    int c = st->fail_cause >= 0 && st->fail_cause <= EXDEX_FAIL_NONFINITE ? st->fail_cause : 0;
    PyObject *exc = get_state(module)->SolverError, *msg, *args, *inst, *o;
    char when[64] = "", where[64] = "";
    if (index >= 0) PyOS_snprintf(where, sizeof where, "batch index %zd: ", index);
    if (!c) {
        char what[64] = "simulate";
        if (index >= 0) PyOS_snprintf(what, sizeof what, "batch index %zd", index);
        expy_raise_status(exc, status, what, NULL, NULL, index);
        return;
    }
    if (isfinite(st->fail_time)) PyOS_snprintf(when, sizeof when, " at t = %.9g s", st->fail_time);
    msg = PyUnicode_FromFormat("%s%s%s: %s", where, exdex_strerror(status), when, why[c]);
    args = msg ? Py_BuildValue("(Ni)", msg, status) : NULL;
    inst = args ? PyObject_Call(exc, args, NULL) : NULL;
    Py_XDECREF(args);
    if (!inst) return;
    if ((o = PyLong_FromLong(status))) {
        PyObject_SetAttrString(inst, "status", o);
        Py_DECREF(o);
    }
    o = isfinite(st->fail_time) ? PyFloat_FromDouble(st->fail_time) : Py_NewRef(Py_None);
    if (o) {
        PyObject_SetAttrString(inst, "time", o);
        Py_DECREF(o);
    }
    if ((o = PyUnicode_FromString(names[c]))) {
        PyObject_SetAttrString(inst, "cause", o);
        Py_DECREF(o);
    }
    if (index >= 0 && (o = PyLong_FromSsize_t(index))) {
        PyObject_SetAttrString(inst, "index", o);
        Py_DECREF(o);
    }
    PyErr_Clear();
    PyErr_SetObject(exc, inst);
    Py_DECREF(inst);
}

/* exdex_simulate with the GIL released; 0, or -1 with the library exception set. */
static int simulate_released(PyObject *module, const exdex_model *model, double t_end, double dt,
                             exdex_trajectory *tr, exdex_stats *st)
{
    int status;
    Py_BEGIN_ALLOW_THREADS
    status = exdex_simulate(model, t_end, dt, tr, st);
    Py_END_ALLOW_THREADS
    if (!status) return 0;
    if (status == EXDEX_ENOCONV || status == EXDEX_ENONFINITE)
        raise_run_error_at(module, status, st, -1);
    else
        raise_status(module, status, "simulate", NULL);
    return -1;
}

/* The certificate of a reduced run as a dict (None for a planar run). */
static PyObject *cert_dict(const exdex_certificate *c)
{
    if (!c->reduced) Py_RETURN_NONE;
    if (c->holds)
        return Py_BuildValue("{s:O,s:d}", "holds", Py_True, "valid_until", c->valid_until);
    return Py_BuildValue("{s:O,s:d,s:n,s:O,s:(ddd),s:d,s:d,s:i}", "holds", Py_False, "valid_until",
                         c->valid_until, "first_bad", (Py_ssize_t)c->first_bad, "stick",
                         c->stick ? Py_True : Py_False, "load", c->load[0], c->load[1], c->load[2], "capacity",
                         c->capacity, "gauge", c->gauge, "coordinate", c->coordinate);
}

/* Run `model` over (t_end, dt), already checked (check_times gave n
 * samples), and return the result dict of simulate(); NULL with an
 * exception set. */
static PyObject *run_model(PyObject *module, const exdex_model *model, double t_end, double dt, size_t n,
                           int certify)
{
    PyObject *result = NULL, *stats = NULL, *cert = NULL;
    PyArrayObject *t = NULL, *q = NULL, *v = NULL, *wr = NULL, *stick = NULL, *sf = NULL;
    exdex_trajectory tr;
    exdex_stats st;
    size_t n_keep = n;
    int ndof = exdex_model_ndof(model), nstops = exdex_model_nstops(model);
    {
        npy_intp d1[1] = {(npy_intp)n}, d2[2] = {(npy_intp)n, ndof}, d3[2] = {(npy_intp)n, 3},
                 d4[2] = {(npy_intp)n, nstops};
        t = (PyArrayObject *)PyArray_SimpleNew(1, d1, NPY_DOUBLE);
        q = (PyArrayObject *)PyArray_SimpleNew(2, d2, NPY_DOUBLE);
        v = (PyArrayObject *)PyArray_SimpleNew(2, d2, NPY_DOUBLE);
        wr = (PyArrayObject *)PyArray_SimpleNew(2, d3, NPY_DOUBLE);
        stick = (PyArrayObject *)PyArray_SimpleNew(1, d1, NPY_BOOL);
        sf = (PyArrayObject *)PyArray_ZEROS(2, d4, NPY_DOUBLE, 0);
        if (!t || !q || !v || !wr || !stick || !sf) goto done;
    }
    tr.n = n;
    tr.t = PyArray_DATA(t);
    tr.q = PyArray_DATA(q);
    tr.v = PyArray_DATA(v);
    tr.wrench = PyArray_DATA(wr);
    tr.stick = PyArray_DATA(stick);
    tr.stop_force = nstops ? PyArray_DATA(sf) : NULL;
    if (certify == 3) {
        /* certified as it goes: a failed reduction ends the run there */
        exdex_certificate c;
        int status;
        Py_BEGIN_ALLOW_THREADS
        status = exdex_simulate_certified(model, t_end, dt, &tr, &st, &c, &n_keep);
        Py_END_ALLOW_THREADS
        if (status) {
            if (status == EXDEX_ENOCONV || status == EXDEX_ENONFINITE)
                raise_run_error_at(module, status, &st, -1);
            else
                raise_status(module, status, "simulate", NULL);
            goto done;
        }
        cert = cert_dict(&c);
        if (!cert) goto done;
    } else if (simulate_released(module, model, t_end, dt, &tr, &st)) {
        goto done;
    } else if (st.lost_sample) {
        n_keep = st.lost_sample + 1;
    }
    stats = stats_dict(&st);
    if (!stats) goto done;
    if (certify == 3) {
        /* filled above */
    } else if (certify) {
        /* pads: only the samples written, up to the one where the grasp was lost */
        exdex_trajectory tr_cert = tr;
        if (st.lost_sample) tr_cert.n = st.lost_sample + 1;
        exdex_certificate c;
        int cs;
        Py_BEGIN_ALLOW_THREADS
        cs = certify == 2 ? exdex_certify_samples(model, &tr_cert, &c) : exdex_certify(model, &tr_cert, &c);
        Py_END_ALLOW_THREADS
        if (cs) {
            raise_status(module, cs, "certify", NULL);
            goto done;
        }
        cert = cert_dict(&c);
    } else {
        cert = Py_NewRef(Py_None);
    }
    if (!cert) goto done;
    if (n_keep < n) {
        /* the run stopped early (pads: the grasp was lost; certified as it
         * goes: the reduction failed): the arrays end at the last sample
         * written (views of those samples) */
        PyArrayObject **arrs[6] = {&t, &q, &v, &wr, &stick, &sf};
        for (int k = 0; k < 6; k++) {
            PyObject *sl = PySequence_GetSlice((PyObject *)*arrs[k], 0, (Py_ssize_t)n_keep);
            if (!sl) goto done;
            Py_DECREF(*arrs[k]);
            *arrs[k] = (PyArrayObject *)sl;
        }
    }
    result = Py_BuildValue("{s:O,s:O,s:O,s:O,s:O,s:O,s:O,s:O}", "t", t, "q", q, "v", v, "wrench", wr, "stick",
                           stick, "stop_force", sf, "stats", stats, "certificate", cert);
done:
    Py_XDECREF(t);
    Py_XDECREF(q);
    Py_XDECREF(v);
    Py_XDECREF(wr);
    Py_XDECREF(stick);
    Py_XDECREF(sf);
    Py_XDECREF(stats);
    Py_XDECREF(cert);
    return result;
}

/* Build the C model of a spec dict; NULL with an exception set. */
static exdex_model *model_from_spec(PyObject *module, PyObject *spec)
{
    exdex_scene_def def;
    PyArrayObject *times = NULL, *poses = NULL, *grip = NULL;
    exdex_model *model;
    const char *bad = NULL;
    int status;
    if (scene_from_dict(spec, &def, &times, &poses, &grip)) return NULL;
    model = exdex_model_alloc(&def, &status, &bad);   /* copies the sampled arrays */
    Py_XDECREF(times);
    Py_XDECREF(poses);
    Py_XDECREF(grip);
    if (!model) raise_status(module, status, "scene", bad);
    return model;
}

static PyObject *core_simulate(PyObject *module, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"spec", "t_end", "dt", "certify", "stop_at_failure", NULL};
    PyObject *spec, *result;
    double t_end, dt;
    size_t n;
    int certify = 1, stop = 0;
    exdex_model *model;

    if (!PyArg_ParseTupleAndKeywords(args, kwds, "Odd|pp", kwlist, &spec, &t_end, &dt, &certify, &stop))
        return NULL;
    if (stop && !certify) {
        PyErr_SetString(PyExc_ValueError, "stop_at_failure=True needs certify=True (the run stops where its "
                        "certificate fails)");
        return NULL;
    }
    if (check_times(t_end, dt, &n)) return NULL;
    model = model_from_spec(module, spec);
    if (!model) return NULL;
    result = run_model(module, model, t_end, dt, n, stop ? 3 : certify);
    exdex_model_free(model);
    return result;
}

/* ------------------------------------------------------- compiled model
 * _core.Model: a scene compiled once (exdex_model_alloc) and run many times,
 * for loops that re-run one scene (optimisation, learning, benchmarks): each
 * run skips the spec conversion and the model set-up. Immutable, so calls
 * from several threads are safe (each run has its own output). */
typedef struct {
    PyObject_HEAD
    exdex_model *model;
    PyObject *module;   /* for the module's SolverError */
} ModelObject;

static int Model_traverse(PyObject *self, visitproc visit, void *arg)
{
    Py_VISIT(Py_TYPE(self));   /* instances of heap types own a reference to their type */
    Py_VISIT(((ModelObject *)self)->module);
    return 0;
}

static int Model_clear(PyObject *self)
{
    Py_CLEAR(((ModelObject *)self)->module);
    return 0;
}

static void Model_dealloc(PyObject *self)
{
    PyTypeObject *tp = Py_TYPE(self);
    PyObject_GC_UnTrack(self);
    Model_clear(self);
    exdex_model_free(((ModelObject *)self)->model);
    tp->tp_free(self);
    Py_DECREF(tp);
}

static PyObject *Model_new_disallowed(PyTypeObject *type, PyObject *args, PyObject *kwds)
{
    (void)args;
    (void)kwds;
    PyErr_Format(PyExc_TypeError, "cannot create '%s' instances directly; use exdex.Model(scene, ...)",
                 type->tp_name);
    return NULL;
}

PyDoc_STRVAR(Model_simulate_doc,
"simulate(t_end, dt, certify=True, every_sample=False, stop_at_failure=False) -> dict\n\n"
"Run the compiled scene from t = 0 to t_end (GIL released); the same dict as\n"
"_core.simulate(spec, t_end, dt). every_sample=True certifies with every\n"
"sample evaluated (exdex_certify_samples: the reference of the proofs);\n"
"stop_at_failure=True certifies as the run goes, as _core.simulate's.");

static PyObject *Model_simulate(PyObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"t_end", "dt", "certify", "every_sample", "stop_at_failure", NULL};
    double t_end, dt;
    size_t n;
    int certify = 1, every = 0, stop = 0;
    ModelObject *mo = (ModelObject *)self;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "dd|ppp", kwlist, &t_end, &dt, &certify, &every, &stop))
        return NULL;
    if (stop && (!certify || every)) {
        PyErr_SetString(PyExc_ValueError, "stop_at_failure=True needs certify=True and every_sample=False");
        return NULL;
    }
    if (check_times(t_end, dt, &n)) return NULL;
    return run_model(mo->module, mo->model, t_end, dt, n, stop ? 3 : certify ? (every ? 2 : 1) : 0);
}

PyDoc_STRVAR(Model_final_doc,
"final(t_end, dt, certify=False) -> (q, v, stick) or (q, v, stick, certificate)\n\n"
"Run the compiled scene like simulate() but keep only the last sample:\n"
"q and v as tuples of floats (ndof entries) and stick as a bool. The\n"
"trajectory goes to a scratch buffer that is freed before returning;\n"
"certify=True checks it first (simulate's certificate dict, None for a planar run).");

static PyObject *Model_final(PyObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"t_end", "dt", "certify", NULL};
    double t_end, dt;
    ModelObject *mo = (ModelObject *)self;
    int ndof = exdex_model_ndof(mo->model), nstops = exdex_model_nstops(mo->model), i, certify = 0;
    PyObject *cert = NULL;
    size_t n, per;
    double *buf;
    unsigned char *stick;
    exdex_trajectory tr;
    exdex_stats st;
    PyObject *q = NULL, *v = NULL, *res = NULL;

    if (!PyArg_ParseTupleAndKeywords(args, kwds, "dd|p", kwlist, &t_end, &dt, &certify)) return NULL;
    if (check_times(t_end, dt, &n)) return NULL;
    per = 1 + 2 * (size_t)ndof + 3 + (size_t)nstops;
    if (n > ((size_t)-1) / (per * sizeof(double) + 1)) return PyErr_NoMemory();
    buf = PyMem_RawMalloc(n * per * sizeof(double));
    stick = PyMem_RawMalloc(n);
    if (!buf || !stick) {
        PyMem_RawFree(buf);
        PyMem_RawFree(stick);
        return PyErr_NoMemory();
    }
    tr.n = n;
    tr.t = buf;
    tr.q = tr.t + n;
    tr.v = tr.q + n * (size_t)ndof;
    tr.wrench = tr.v + n * (size_t)ndof;
    tr.stop_force = nstops ? tr.wrench + 3 * n : NULL;
    tr.stick = stick;
    if (simulate_released(mo->module, mo->model, t_end, dt, &tr, &st)) goto done;
    if (certify) {
        /* as run_model: pads certify the samples up to the one where the grasp was lost */
        exdex_trajectory tr_cert = tr;
        exdex_certificate c;
        int cs;
        if (st.lost_sample) tr_cert.n = st.lost_sample + 1;
        Py_BEGIN_ALLOW_THREADS
        cs = exdex_certify(mo->model, &tr_cert, &c);
        Py_END_ALLOW_THREADS
        if (cs) {
            raise_status(mo->module, cs, "certify", NULL);
            goto done;
        }
        cert = cert_dict(&c);
        if (!cert) goto done;
    }
    q = PyTuple_New(ndof);
    v = PyTuple_New(ndof);
    if (!q || !v) goto done;
    for (i = 0; i < ndof; i++) {
        PyObject *a = PyFloat_FromDouble(tr.q[(n - 1) * (size_t)ndof + (size_t)i]);
        PyObject *b = PyFloat_FromDouble(tr.v[(n - 1) * (size_t)ndof + (size_t)i]);
        if (!a || !b) {
            Py_XDECREF(a);
            Py_XDECREF(b);
            goto done;
        }
        PyTuple_SET_ITEM(q, i, a);
        PyTuple_SET_ITEM(v, i, b);
    }
    res = certify ? Py_BuildValue("(OONO)", q, v, PyBool_FromLong(stick[n - 1]), cert)
                  : Py_BuildValue("(OON)", q, v, PyBool_FromLong(stick[n - 1]));
done:
    Py_XDECREF(cert);
    Py_XDECREF(q);
    Py_XDECREF(v);
    PyMem_RawFree(buf);
    PyMem_RawFree(stick);
    return res;
}

static PyObject *Model_get_ndof(PyObject *self, void *closure)
{
    (void)closure;
    return PyLong_FromLong(exdex_model_ndof(((ModelObject *)self)->model));
}

static PyObject *Model_get_nstops(PyObject *self, void *closure)
{
    (void)closure;
    return PyLong_FromLong(exdex_model_nstops(((ModelObject *)self)->model));
}

static PyObject *Model_stepper(PyObject *self, PyObject *noargs);
PyDoc_STRVAR(Model_stepper_doc,
"stepper() -> Stepper\n\n"
"A new run of this model at its initial state, to advance step by step.");

static PyMethodDef Model_methods[] = {
    {"simulate", (PyCFunction)(void (*)(void))Model_simulate, METH_VARARGS | METH_KEYWORDS, Model_simulate_doc},
    {"final", (PyCFunction)(void (*)(void))Model_final, METH_VARARGS | METH_KEYWORDS, Model_final_doc},
    {"stepper", (PyCFunction)Model_stepper, METH_NOARGS, Model_stepper_doc},
    {NULL, NULL, 0, NULL}};

static PyGetSetDef Model_getset[] = {
    {"ndof", Model_get_ndof, NULL, "number of free coordinates (1 or 3)", NULL},
    {"n_stops", Model_get_nstops, NULL, "number of stops", NULL},
    {NULL, NULL, NULL, NULL, NULL}};

static PyType_Slot Model_slots[] = {
    {Py_tp_doc, (void *)"A scene compiled by exdex._core.compile(spec): run it with simulate() or final()."},
    {Py_tp_new, (void *)Model_new_disallowed},
    {Py_tp_dealloc, (void *)Model_dealloc},
    {Py_tp_traverse, (void *)Model_traverse},
    {Py_tp_clear, (void *)Model_clear},
    {Py_tp_methods, Model_methods},
    {Py_tp_getset, Model_getset},
    {0, NULL}};

static PyType_Spec Model_spec = {
    .name = "exdex._core.Model",
    .basicsize = sizeof(ModelObject),
    .flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_GC,
    .slots = Model_slots,
};

/* ------------------------------------------------------------- stepper
 * _core.Stepper: exdex_stepper over a compiled Model (Model.stepper()),
 * which it keeps alive. A step releases the GIL; a per-stepper lock makes a
 * second thread's call on the same stepper fail instead of racing. */
typedef struct {
    PyObject_HEAD
    exdex_stepper *s;
    PyObject *model;    /* the ModelObject */
    PyObject *module;
    PyThread_type_lock lock;
} StepperObject;

static int Stepper_traverse(PyObject *self, visitproc visit, void *arg)
{
    Py_VISIT(Py_TYPE(self));
    Py_VISIT(((StepperObject *)self)->model);
    Py_VISIT(((StepperObject *)self)->module);
    return 0;
}

static int Stepper_clear(PyObject *self)
{
    /* the stepper reads the model: it goes with the object (dealloc) */
    (void)self;
    return 0;
}

static void Stepper_dealloc(PyObject *self)
{
    StepperObject *so = (StepperObject *)self;
    PyTypeObject *tp = Py_TYPE(self);
    PyObject_GC_UnTrack(self);
    exdex_stepper_free(so->s);
    if (so->lock) PyThread_free_lock(so->lock);
    Py_CLEAR(so->model);
    Py_CLEAR(so->module);
    tp->tp_free(self);
    Py_DECREF(tp);
}

static int stepper_acquire(StepperObject *so)
{
    if (!PyThread_acquire_lock(so->lock, NOWAIT_LOCK)) {
        PyErr_SetString(PyExc_RuntimeError, "this Stepper is stepping in another thread; use one Stepper per thread");
        return -1;
    }
    return 0;
}

PyDoc_STRVAR(Stepper_step_doc,
"step(dt, grip_force=None, gripper=None) -> None\n\n"
"Advance by dt [s] (> 0) with this step's grip force [N per finger] (>= 0;\n"
"None: the scene's own force or schedule), the GIL released. gripper: None\n"
"(the scene's motion) or (R, p, v, w), the gripper's pose at the step's end\n"
"(R_AB as 9 floats, row-major; p [m]) and its twist there (v [m/s], w\n"
"[rad/s], 3 floats each, or None: the step's secant), as\n"
"exdex_stepper_step_gripper.");

/* n floats of a sequence into x; 0, or -1 with a TypeError naming what. */
static int stepper_floats(PyObject *o, double *x, Py_ssize_t n, const char *what)
{
    PyObject *seq = PySequence_Fast(o, "");
    if (!seq || PySequence_Fast_GET_SIZE(seq) != n) {
        Py_XDECREF(seq);
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "gripper %s must be %zd floats", what, n);
        return -1;
    }
    for (Py_ssize_t i = 0; i < n; i++) {
        x[i] = PyFloat_AsDouble(PySequence_Fast_GET_ITEM(seq, i));
        if (x[i] == -1.0 && PyErr_Occurred()) {
            Py_DECREF(seq);
            PyErr_Clear();
            PyErr_Format(PyExc_TypeError, "gripper %s must be %zd floats", what, n);
            return -1;
        }
    }
    Py_DECREF(seq);
    return 0;
}

static PyObject *Stepper_step(PyObject *self, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"dt", "grip_force", "gripper", NULL};
    StepperObject *so = (StepperObject *)self;
    double dt, grip = NAN;
    PyObject *gobj = Py_None, *pobj = Py_None;
    exdex_stepper_sample x;
    exdex_stats st;
    exdex_gripper_pose pose;
    int status;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "d|OO", kwlist, &dt, &gobj, &pobj)) return NULL;
    memset(&pose, 0, sizeof pose);
    if (pobj != Py_None) {
        if (!PyTuple_Check(pobj) || PyTuple_GET_SIZE(pobj) != 4) {
            PyErr_SetString(PyExc_TypeError, "gripper must be None or a tuple (R, p, v, w)");
            return NULL;
        }
        if (stepper_floats(PyTuple_GET_ITEM(pobj, 0), pose.R, 9, "R") ||
            stepper_floats(PyTuple_GET_ITEM(pobj, 1), pose.p, 3, "p"))
            return NULL;
        pose.given_v = PyTuple_GET_ITEM(pobj, 2) != Py_None;
        pose.given_w = PyTuple_GET_ITEM(pobj, 3) != Py_None;
        if ((pose.given_v && stepper_floats(PyTuple_GET_ITEM(pobj, 2), pose.v, 3, "v")) ||
            (pose.given_w && stepper_floats(PyTuple_GET_ITEM(pobj, 3), pose.w, 3, "w")))
            return NULL;
    }
    if (!(isfinite(dt) && dt > 0.0)) {
        PyErr_Format(PyExc_ValueError, "dt must be finite and > 0 [s], got %R", PyTuple_GET_ITEM(args, 0));
        return NULL;
    }
    if (gobj != Py_None) {
        grip = PyFloat_AsDouble(gobj);
        if (grip == -1.0 && PyErr_Occurred()) {
            PyErr_Clear();
            PyErr_Format(PyExc_TypeError, "grip_force must be a real number or None, not %s",
                         Py_TYPE(gobj)->tp_name);
            return NULL;
        }
        if (!(isfinite(grip) && grip >= 0.0)) {
            PyErr_Format(PyExc_ValueError, "grip_force must be finite and >= 0 [N] (or None), got %R", gobj);
            return NULL;
        }
    }
    if (stepper_acquire(so)) return NULL;
    exdex_stepper_get(so->s, &x, NULL);
    Py_BEGIN_ALLOW_THREADS
    status = exdex_stepper_step_gripper(so->s, dt, grip, pobj != Py_None ? &pose : NULL);
    Py_END_ALLOW_THREADS
    exdex_stepper_get(so->s, NULL, &st);
    PyThread_release_lock(so->lock);
    if (status == EXDEX_EINVAL && st.lost_sample) {
        char b[192];
        /* PyErr_Format has no floating-point conversions */
        PyOS_snprintf(b, sizeof b,
                      "the grasp was lost at t = %.17g s (the pads' contact region vanished): the stepper takes no "
                      "more steps (restore a saved state)", st.lost_t);
        PyErr_SetString(PyExc_ValueError, b);
        return NULL;
    }
    if (status == EXDEX_EINVAL) {
        char tb[32];
        PyOS_snprintf(tb, sizeof tb, "%.17g", x.t);
        PyErr_Format(PyExc_ValueError,
                     "dt = %R s cannot advance the time from t = %s s (t + dt rounds to t, or more than 1e9 "
                     "steps of this dt), or the stepper failed earlier (restore a saved state)%s",
                     PyTuple_GET_ITEM(args, 0), tb,
                     pobj != Py_None ? ", or gripper is not a finite pose with a rotation matrix R (to 1e-9), "
                                       "or the method is 'analytic' (it follows the scene's motion)"
                                     : ", or an earlier step gave the gripper pose (then every step must)");
        return NULL;
    }
    if (status) {
        raise_run_error_at(so->module, status, &st, -1);
        return NULL;
    }
    Py_RETURN_NONE;
}

static PyObject *doubles_tuple(const double *x, int n)
{
    PyObject *t = PyTuple_New(n);
    if (!t) return NULL;
    for (int i = 0; i < n; i++) {
        PyObject *f = PyFloat_FromDouble(x[i]);
        if (!f) {
            Py_DECREF(t);
            return NULL;
        }
        PyTuple_SET_ITEM(t, i, f);
    }
    return t;
}

PyDoc_STRVAR(Stepper_state_doc,
"state() -> (t, q, v, stick, wrench, stop_force, grip_force, steps)\n\n"
"The state after the last step: time [s], q and v (ndof floats each), the\n"
"stick flag, the mean plate wrench and stop forces over the last step, its\n"
"grip force (None: the scene's) and the number of steps taken.");

static PyObject *Stepper_state(PyObject *self, PyObject *noargs)
{
    StepperObject *so = (StepperObject *)self;
    exdex_stepper_sample x;
    int nd = exdex_model_ndof(((ModelObject *)so->model)->model);
    int ns = exdex_model_nstops(((ModelObject *)so->model)->model);
    (void)noargs;
    exdex_stepper_get(so->s, &x, NULL);
    return Py_BuildValue("(dNNNNNNn)", x.t, doubles_tuple(x.q, nd), doubles_tuple(x.v, nd),
                         PyBool_FromLong(x.stick), doubles_tuple(x.wrench, 3), doubles_tuple(x.stop_force, ns),
                         float_or_none(x.grip_force), (Py_ssize_t)x.steps);
}

PyDoc_STRVAR(Stepper_stats_doc, "stats() -> dict\n\nSolver statistics over the steps taken (simulate's keys).");

static PyObject *Stepper_stats(PyObject *self, PyObject *noargs)
{
    exdex_stats st;
    (void)noargs;
    exdex_stepper_get(((StepperObject *)self)->s, NULL, &st);
    return stats_dict(&st);
}

PyDoc_STRVAR(Stepper_certificate_doc, "certificate() -> dict or None\n\n"
"The certificate of a 1-DoF stepper's steps so far (simulate's dict; None for a planar one).");

static PyObject *Stepper_certificate(PyObject *self, PyObject *noargs)
{
    exdex_certificate c;
    (void)noargs;
    exdex_stepper_certificate(((StepperObject *)self)->s, &c);
    if (!c.reduced) Py_RETURN_NONE;
    return cert_dict(&c);
}

PyDoc_STRVAR(Stepper_holds_doc, "holds() -> bool\n\nFalse once a 1-DoF stepper's certificate has failed.");

static PyObject *Stepper_holds(PyObject *self, PyObject *noargs)
{
    exdex_certificate c;
    (void)noargs;
    exdex_stepper_certificate(((StepperObject *)self)->s, &c);
    return PyBool_FromLong(!c.reduced || c.holds);
}

PyDoc_STRVAR(Stepper_save_doc, "save() -> bytes\n\nA snapshot of the whole state (restore() takes it back).");

static PyObject *Stepper_save(PyObject *self, PyObject *noargs)
{
    StepperObject *so = (StepperObject *)self;
    size_t size = exdex_stepper_state_size(so->s);
    PyObject *b = PyBytes_FromStringAndSize(NULL, (Py_ssize_t)size);
    (void)noargs;
    if (!b) return NULL;
    if (stepper_acquire(so)) {
        Py_DECREF(b);
        return NULL;
    }
    exdex_stepper_save(so->s, PyBytes_AS_STRING(b), size);
    PyThread_release_lock(so->lock);
    return b;
}

PyDoc_STRVAR(Stepper_restore_doc,
"restore(snapshot) -> None\n\n"
"Return to the state saved by save() on a stepper of the same Model.");

static PyObject *Stepper_restore(PyObject *self, PyObject *arg)
{
    StepperObject *so = (StepperObject *)self;
    int status;
    if (!PyBytes_Check(arg)) {
        PyErr_Format(PyExc_TypeError, "snapshot must be the bytes of Stepper.save(), not %s", Py_TYPE(arg)->tp_name);
        return NULL;
    }
    if (stepper_acquire(so)) return NULL;
    status = exdex_stepper_restore(so->s, PyBytes_AS_STRING(arg), (size_t)PyBytes_GET_SIZE(arg));
    PyThread_release_lock(so->lock);
    if (status) {
        PyErr_SetString(PyExc_ValueError, "snapshot is not a state saved by a stepper of this Model");
        return NULL;
    }
    Py_RETURN_NONE;
}

static PyMethodDef Stepper_methods[] = {
    {"step", (PyCFunction)(void (*)(void))Stepper_step, METH_VARARGS | METH_KEYWORDS, Stepper_step_doc},
    {"state", Stepper_state, METH_NOARGS, Stepper_state_doc},
    {"stats", Stepper_stats, METH_NOARGS, Stepper_stats_doc},
    {"certificate", Stepper_certificate, METH_NOARGS, Stepper_certificate_doc},
    {"holds", Stepper_holds, METH_NOARGS, Stepper_holds_doc},
    {"save", Stepper_save, METH_NOARGS, Stepper_save_doc},
    {"restore", Stepper_restore, METH_O, Stepper_restore_doc},
    {NULL, NULL, 0, NULL}};

static PyType_Slot Stepper_slots[] = {
    {Py_tp_doc, (void *)"A run of a compiled Model advanced step by step (Model.stepper()); use exdex.Stepper."},
    {Py_tp_new, (void *)Model_new_disallowed},
    {Py_tp_dealloc, (void *)Stepper_dealloc},
    {Py_tp_traverse, (void *)Stepper_traverse},
    {Py_tp_clear, (void *)Stepper_clear},
    {Py_tp_methods, Stepper_methods},
    {0, NULL}};

static PyType_Spec Stepper_spec = {
    .name = "exdex._core.Stepper",
    .basicsize = sizeof(StepperObject),
    .flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_GC,
    .slots = Stepper_slots,
};

static PyObject *Model_stepper(PyObject *self, PyObject *noargs)
{
    ModelObject *mo = (ModelObject *)self;
    PyTypeObject *tp = (PyTypeObject *)get_state(mo->module)->StepperType;
    StepperObject *so;
    int status;
    exdex_stepper *s;
    (void)noargs;
    s = exdex_stepper_alloc(mo->model, &status);
    if (!s) return raise_status(mo->module, status, "stepper", NULL);
    so = PyObject_GC_New(StepperObject, tp);
    if (!so) {
        exdex_stepper_free(s);
        return NULL;
    }
    so->s = s;
    so->model = Py_NewRef(self);
    so->module = Py_NewRef(mo->module);
    so->lock = PyThread_allocate_lock();
    if (!so->lock) {
        PyObject_GC_Track((PyObject *)so);
        Py_DECREF(so);
        return PyErr_NoMemory();
    }
    PyObject_GC_Track((PyObject *)so);
    return (PyObject *)so;
}

PyDoc_STRVAR(compile_doc,
"compile(spec) -> Model\n\n"
"Build the C model of a spec dict (exdex.Scene.to_spec()) once, to run it\n"
"many times. Use exdex.Model(scene, ...) instead of calling this directly.");

static PyObject *core_compile(PyObject *module, PyObject *spec)
{
    PyTypeObject *tp = (PyTypeObject *)get_state(module)->ModelType;
    ModelObject *mo;
    exdex_model *model = model_from_spec(module, spec);
    if (!model) return NULL;
    mo = PyObject_GC_New(ModelObject, tp);
    if (!mo) {
        exdex_model_free(model);
        return NULL;
    }
    mo->model = model;
    mo->module = Py_NewRef(module);
    PyObject_GC_Track((PyObject *)mo);
    return (PyObject *)mo;
}

PyDoc_STRVAR(analytic_unsupported_doc,
"analytic_unsupported(spec) -> str or None\n\n"
"None if the analytic method solves the scene of a spec dict, else the\n"
"reason it does not (a sentence).");

static PyObject *core_analytic_unsupported(PyObject *module, PyObject *spec)
{
    exdex_scene_def def;
    PyArrayObject *times = NULL, *poses = NULL, *grip = NULL;
    const char *why;
    (void)module;
    if (scene_from_dict(spec, &def, &times, &poses, &grip)) return NULL;
    why = exdex_analytic_unsupported(&def);
    Py_XDECREF(times);
    Py_XDECREF(poses);
    Py_XDECREF(grip);
    if (!why) Py_RETURN_NONE;
    return PyUnicode_FromString(why);
}

PyDoc_STRVAR(motion_eval_doc,
"motion_eval(spec, t) -> dict\n\n"
"Gripper kinematics of the scene's motion at the times t (1-D float64):\n"
"R (n, 3, 3) = R_AB, p, v, a, w, dw (n, 3), all in the world frame A.");

static PyObject *core_motion_eval(PyObject *module, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"spec", "t", NULL};
    PyObject *spec, *tobj, *result = NULL;
    PyArrayObject *times = NULL, *poses = NULL, *grip = NULL, *ta = NULL, *out[6] = {NULL};
    exdex_scene_def def;
    exdex_motion *mo = NULL;
    const char *bad = NULL;
    int status = EXDEX_OK;
    npy_intp n;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OO", kwlist, &spec, &tobj)) return NULL;
    ta = (PyArrayObject *)PyArray_FROMANY(tobj, NPY_DOUBLE, 0, 1, NPY_ARRAY_IN_ARRAY);
    if (!ta) return NULL;
    n = PyArray_SIZE(ta);
    if (scene_from_dict(spec, &def, &times, &poses, &grip)) goto done;
    mo = exdex_motion_alloc(&def.motion, def.R0, def.p0, &status, &bad);
    if (!mo) {
        raise_status(module, status, "motion", bad);
        goto done;
    }
    {
        npy_intp dR[3] = {n, 3, 3}, dv[2] = {n, 3};
        out[0] = (PyArrayObject *)PyArray_SimpleNew(3, dR, NPY_DOUBLE);
        for (int i = 1; i < 6; i++) out[i] = (PyArrayObject *)PyArray_SimpleNew(2, dv, NPY_DOUBLE);
        for (int i = 0; i < 6; i++)
            if (!out[i]) goto done;
    }
    {
        const double *tp = PyArray_DATA(ta);
        double *o[6];
        for (int i = 0; i < 6; i++) o[i] = PyArray_DATA(out[i]);
        Py_BEGIN_ALLOW_THREADS
        for (npy_intp i = 0; i < n && status == EXDEX_OK; i++) {
            exdex_kinematics k;
            status = exdex_motion_eval(mo, tp[i], &k);
            memcpy(o[0] + 9 * i, k.R, sizeof k.R);
            memcpy(o[1] + 3 * i, k.p, sizeof k.p);
            memcpy(o[2] + 3 * i, k.v, sizeof k.v);
            memcpy(o[3] + 3 * i, k.a, sizeof k.a);
            memcpy(o[4] + 3 * i, k.w, sizeof k.w);
            memcpy(o[5] + 3 * i, k.dw, sizeof k.dw);
        }
        Py_END_ALLOW_THREADS
    }
    if (status) {
        raise_status(module, status, "motion", NULL);
        goto done;
    }
    result = Py_BuildValue("{s:O,s:O,s:O,s:O,s:O,s:O}", "R", out[0], "p", out[1], "v", out[2], "a", out[3],
                           "w", out[4], "dw", out[5]);
done:
    exdex_motion_free(mo);
    Py_XDECREF(times);
    Py_XDECREF(poses);
    Py_XDECREF(grip);
    Py_XDECREF(ta);
    for (int i = 0; i < 6; i++) Py_XDECREF(out[i]);
    return result;
}

PyDoc_STRVAR(grip_eval_doc,
"grip_eval(spec, t) -> (force, rate)\n\n"
"Normal force of each finger F(t) [N] and its rate dF/dt [N/s] (right derivative at a\n"
"breakpoint) at the times t (float64, any shape up to 1-D), of the scene's constant grip\n"
"force or grip schedule (exdex_model_grip).");

static PyObject *core_grip_eval(PyObject *module, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"spec", "t", NULL};
    PyObject *spec, *tobj, *result = NULL;
    PyArrayObject *ta = NULL, *fo = NULL, *ra = NULL;
    exdex_model *model = NULL;
    npy_intp n;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OO", kwlist, &spec, &tobj)) return NULL;
    ta = (PyArrayObject *)PyArray_FROMANY(tobj, NPY_DOUBLE, 0, 1, NPY_ARRAY_IN_ARRAY);
    if (!ta) return NULL;
    n = PyArray_SIZE(ta);
    model = model_from_spec(module, spec);
    if (!model) goto done;
    fo = (PyArrayObject *)PyArray_SimpleNew(1, &n, NPY_DOUBLE);
    ra = (PyArrayObject *)PyArray_SimpleNew(1, &n, NPY_DOUBLE);
    if (!fo || !ra) goto done;
    {
        const double *tp = PyArray_DATA(ta);
        double *f = PyArray_DATA(fo), *r = PyArray_DATA(ra);
        for (npy_intp i = 0; i < n; i++)
            if (exdex_model_grip(model, tp[i], f + i, r + i)) {
                PyErr_SetString(PyExc_ValueError, "t must not hold NaN");
                goto done;
            }
    }
    result = Py_BuildValue("(OO)", fo, ra);
done:
    exdex_model_free(model);
    Py_XDECREF(ta);
    Py_XDECREF(fo);
    Py_XDECREF(ra);
    return result;
}

PyDoc_STRVAR(motion_jumps_doc,
"motion_jumps(spec) -> list of (t, dv, dw)\n\n"
"Velocity jumps of the gripper frame B of the scene's motion (exdex_motion_jumps):\n"
"time t [s] and the jumps of the velocity of B's origin dv [m/s] and of its angular\n"
"velocity dw [rad/s] (right limit minus left limit), tuples in the world frame A.");

static PyObject *core_motion_jumps(PyObject *module, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"spec", NULL};
    PyObject *spec, *result = NULL;
    PyArrayObject *times = NULL, *poses = NULL, *grip = NULL;
    exdex_scene_def def;
    exdex_motion *mo = NULL;
    const char *bad = NULL;
    int status = EXDEX_OK, nj;
    double tj[EXDEX_MOTION_MAX_JUMPS], dv[EXDEX_MOTION_MAX_JUMPS][3], dw[EXDEX_MOTION_MAX_JUMPS][3];
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "O", kwlist, &spec)) return NULL;
    if (scene_from_dict(spec, &def, &times, &poses, &grip)) goto done;
    mo = exdex_motion_alloc(&def.motion, def.R0, def.p0, &status, &bad);
    if (!mo) {
        raise_status(module, status, "motion", bad);
        goto done;
    }
    nj = exdex_motion_jumps(mo, tj, dv, dw);
    result = PyList_New(0);
    for (int j = 0; result && j < nj; j++) {
        PyObject *item = Py_BuildValue("(d(ddd)(ddd))", tj[j], dv[j][0], dv[j][1], dv[j][2], dw[j][0],
                                       dw[j][1], dw[j][2]);
        if (!item || PyList_Append(result, item)) Py_CLEAR(result);
        Py_XDECREF(item);
    }
done:
    exdex_motion_free(mo);
    Py_XDECREF(times);
    Py_XDECREF(poses);
    Py_XDECREF(grip);
    return result;
}

PyDoc_STRVAR(friction_solve_doc,
"friction_solve(W, b, e, cap, solver=0) -> (p, u, sigma, stick, iterations)\n\n"
"One implicit friction step at a patch (see csrc/exdex.h): u+ = b + W p with\n"
"p minimising p.u+ over p^T E^-2 p <= cap^2. solver: 0 scalar, 1 brent,\n"
"2 multiroot (paper's four quadratic equations).");

static PyObject *core_friction_solve(PyObject *module, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"W", "b", "e", "cap", "solver", NULL};
    PyObject *Wo, *bo, *eo, *result = NULL;
    PyArrayObject *W = NULL, *b = NULL, *e = NULL;
    double cap;
    int solver = EXDEX_SOLVER_SCALAR, status;
    exdex_friction_prep prep;
    exdex_friction_result res;
    exdex_friction_ws *ws = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OOOd|i", kwlist, &Wo, &bo, &eo, &cap, &solver))
        return NULL;
    if (solver < 0 || solver > 2) {
        PyErr_Format(PyExc_ValueError, "solver must be 0, 1 or 2, got %d", solver);
        return NULL;
    }
    if (!(W = as_doubles(Wo, 9, "W")) || !(b = as_doubles(bo, 3, "b")) || !(e = as_doubles(eo, 3, "e")))
        goto done;
    status = exdex_friction_prepare(&prep, PyArray_DATA(W), PyArray_DATA(e));
    if (status) {
        raise_status(module, status, "friction_solve", "W or e (W must be SPD, e > 0)");
        goto done;
    }
    if (solver != EXDEX_SOLVER_SCALAR && !(ws = exdex_friction_ws_alloc())) {
        PyErr_NoMemory();
        goto done;
    }
    status = exdex_friction_solve(&prep, PyArray_DATA(b), cap, solver, ws, NULL, &res);
    if (status) {
        raise_status(module, status, "friction_solve", "cap or b (cap >= 0, all finite)");
        goto done;
    }
    result = Py_BuildValue("((ddd)(ddd)dii)", res.p[0], res.p[1], res.p[2], res.u[0], res.u[1], res.u[2],
                           res.sigma, res.stick, res.iterations);
done:
    exdex_friction_ws_free(ws);
    Py_XDECREF(W);
    Py_XDECREF(b);
    Py_XDECREF(e);
    return result;
}

PyDoc_STRVAR(obstacle_section_doc,
"obstacle_section(obstacle, R, p)\n--\n\n"
"Section of an obstacle (dict as in a scene spec's 'obstacles') by the plate plane of\n"
"the gripper pose R (3x3 R_AB), p (3,): a polytope gives its polygon's vertices (k, 2)\n"
"in B, counter-clockwise (finite vertices only); a cylinder gives (centre (2,),\n"
"(a, b, angle)) of its ellipse, or None when the axis lies in the plane.");

static PyObject *core_obstacle_section(PyObject *module, PyObject *args)
{
    PyObject *od, *Ro, *po;
    exdex_obstacle_def o;
    double R[9], p[3], xy[EXDEX_MAX_FACES][2], ab[3];
    PyArrayObject *Ra, *pa;
    int n;
    (void)module;
    if (!PyArg_ParseTuple(args, "OOO", &od, &Ro, &po)) return NULL;
    if (obstacle_from_dict(od, &o)) return NULL;
    Ra = as_doubles(Ro, 9, "R");
    if (!Ra) return NULL;
    memcpy(R, PyArray_DATA(Ra), sizeof R);
    Py_DECREF(Ra);
    pa = as_doubles(po, 3, "p");
    if (!pa) return NULL;
    memcpy(p, PyArray_DATA(pa), sizeof p);
    Py_DECREF(pa);
    n = exdex_obstacle_section(&o, R, p, xy, ab);
    if (n < 0) {
        PyErr_SetString(PyExc_ValueError, "obstacle, R or p invalid (non-finite, or not a valid obstacle)");
        return NULL;
    }
    if (o.kind == EXDEX_OBSTACLE_CYLINDER) {
        if (n == 0) Py_RETURN_NONE;
        return Py_BuildValue("(dd)(ddd)", xy[0][0], xy[0][1], ab[0], ab[1], ab[2]);
    }
    {
        npy_intp dims[2] = {n, 2};
        PyObject *out = PyArray_SimpleNew(2, dims, NPY_DOUBLE);
        if (!out) return NULL;
        if (n) memcpy(PyArray_DATA((PyArrayObject *)out), xy, (size_t)n * 2 * sizeof(double));
        return out;
    }
}

static PyObject *core_er_disc(PyObject *module, PyObject *arg)
{
    double r = PyFloat_AsDouble(arg);
    (void)module;
    if (r == -1.0 && PyErr_Occurred()) return NULL;
    return PyFloat_FromDouble(exdex_er_disc(r));
}

static PyObject *core_er_rectangle(PyObject *module, PyObject *args)
{
    double a, b;
    (void)module;
    if (!PyArg_ParseTuple(args, "dd", &a, &b)) return NULL;
    return PyFloat_FromDouble(exdex_er_rectangle(a, b));
}

static PyObject *core_limit_surface(PyObject *module, PyObject *args)
{
    int surface, what, st, n = 0, kind = EXDEX_REGION_NONE;
    double e_r, radius, in[3], out[3], scalar;
    PyObject *vobj;
    PyArrayObject *va = NULL;
    (void)module;
    if (!PyArg_ParseTuple(args, "idOdi(ddd)", &surface, &e_r, &vobj, &radius, &what, &in[0], &in[1], &in[2]))
        return NULL;
    if (vobj != Py_None) {
        va = (PyArrayObject *)PyArray_FROMANY(vobj, NPY_DOUBLE, 2, 2, NPY_ARRAY_IN_ARRAY);
        if (!va || PyArray_DIM(va, 1) != 2 || PyArray_DIM(va, 0) > EXDEX_REGION_MAX_VERTICES) {
            Py_XDECREF(va);
            PyErr_Clear();
            PyErr_Format(PyExc_ValueError, "region vertices must be a float64 array of shape (k, 2), k <= %d",
                         EXDEX_REGION_MAX_VERTICES);
            return NULL;
        }
        n = (int)PyArray_DIM(va, 0);
        kind = EXDEX_REGION_POLYGON;
    } else if (radius > 0.0) {
        kind = EXDEX_REGION_DISC;
    }
    st = exdex_limit_surface_eval(surface, e_r, kind, n, va ? (const double (*)[2])PyArray_DATA(va) : NULL, radius,
                                  what, in, out, &scalar);
    Py_XDECREF(va);
    if (st) return raise_status(module, st, "limit_surface", NULL);
    return Py_BuildValue("(ddd)d", out[0], out[1], out[2], scalar);
}

static PyObject *core_pad_region(PyObject *module, PyObject *args)
{
    PyObject *spec, *qobj, *verts = NULL;
    exdex_scene_def def;
    PyArrayObject *times = NULL, *poses = NULL, *grip = NULL;
    double q[3], area, c[2], er, radius, (*v)[2] = NULL;
    int nv = 0, st;
    (void)module;
    if (!PyArg_ParseTuple(args, "OO", &spec, &qobj)) return NULL;
    {
        PyObject *d = Py_BuildValue("{s:O}", "q", qobj);
        st = d ? dict_doubles(d, "q", q, 3) : -1;
        Py_XDECREF(d);
        if (st) return NULL;
    }
    if (scene_from_dict(spec, &def, &times, &poses, &grip)) return NULL;
    Py_XDECREF(times);
    Py_XDECREF(poses);
    Py_XDECREF(grip);
    v = PyMem_Malloc(4 * (EXDEX_MAX_PAD_VERTICES + 64) * sizeof *v);
    if (!v) return PyErr_NoMemory();
    st = exdex_pad_region(&def, q, &area, c, &er, &radius, v, 4 * (EXDEX_MAX_PAD_VERTICES + 64), &nv);
    if (st) {
        PyMem_Free(v);
        PyErr_SetString(PyExc_ValueError, "pad_region: the spec must have pads on the fingers (a valid convex pad "
                                          "and face) and q three finite numbers");
        return NULL;
    }
    {
        npy_intp dims[2] = {nv, 2};
        verts = PyArray_SimpleNew(2, dims, NPY_DOUBLE);
        if (verts && nv) memcpy(PyArray_DATA((PyArrayObject *)verts), v, (size_t)nv * 2 * sizeof(double));
    }
    PyMem_Free(v);
    if (!verts) return NULL;
    return Py_BuildValue("{s:d,s:(dd),s:d,s:d,s:N}", "area", area, "centroid", c[0], c[1], "e_r", er, "radius",
                         radius, "vertices", verts);
}

static PyObject *core_n_samples(PyObject *module, PyObject *args)
{
    double t_end, dt;
    (void)module;
    if (!PyArg_ParseTuple(args, "dd", &t_end, &dt)) return NULL;
    return PyLong_FromSize_t(exdex_n_samples(t_end, dt));
}

/* ------------------------------------------------------------------ batch
 * simulate_batch: many trajectories in one call. With a sequence of spec
 * dicts every model is built (and validated) with the GIL held; with one spec
 * dict and `vary`, the dict is read once and model 0 is built with the GIL
 * held (it fixes ndof and the stops, which scalars do not change), and every
 * other model is built from a copy of that definition by the worker thread
 * that runs it, with the GIL released, and freed right after its run. The
 * trajectories run on POSIX threads that take indices from a shared, locked
 * counter. Each trajectory is one exdex_simulate call on its own model and
 * output rows, so results are bit-identical to serial exdex.simulate for any
 * thread count. The threads live here: the C core stays thread-agnostic. */

/* Scalar fields of exdex_scene_def a batch may vary from a base spec (`vary`). */
static const char *const vary_keys[] = {"mass", "mu", "grip_force", "e_r", "motion_amplitude",
                                        "motion_duration", "motion_beta", "motion_v_max", "eps",
                                        "rtol", "atol", "mu_static", "patch_center_x", "patch_center_y",
                                        "pad_center_x", "pad_center_y", "pad_radius", "pad_scale", NULL};

static double *vary_field(exdex_scene_def *d, int which)
{
    switch (which) {
    case 0: return &d->mass;
    case 1: return &d->mu;
    case 2: return &d->grip_force;
    case 3: return &d->e_r;
    case 4: return &d->motion.amplitude;
    case 5: return &d->motion.duration;
    case 6: return &d->motion.beta;
    case 7: return &d->motion.v_max;
    case 8: return &d->eps;
    case 9: return &d->rtol;
    case 11: return &d->mu_static;
    case 12: return &d->patch_center[0];
    case 13: return &d->patch_center[1];
    case 14: return &d->pad_center[0];
    case 15: return &d->pad_center[1];
    case 16: return &d->pad_radius;
    case 17: return &d->pad_scale;
    default: return &d->atol;
    }
}

/* Replace the pending exception by one of the same type whose message starts
 * with "batch index i: ". */
static void prefix_error(Py_ssize_t i)
{
    PyObject *type, *value, *tb, *msg = NULL;
    PyErr_Fetch(&type, &value, &tb);
    PyErr_NormalizeException(&type, &value, &tb);
    if (value) {
        /* the message itself (str() of a KeyError would quote it) */
        PyObject *a = PyObject_GetAttrString(value, "args");
        if (a && PyTuple_Check(a) && PyTuple_GET_SIZE(a) == 1 && PyUnicode_Check(PyTuple_GET_ITEM(a, 0))) {
            msg = PyTuple_GET_ITEM(a, 0);
            Py_INCREF(msg);
        } else {
            PyErr_Clear();
            msg = PyObject_Str(value);
        }
        Py_XDECREF(a);
    }
    if (msg && type) {
        PyErr_Format(type, "batch index %zd: %U", i, msg);
        Py_DECREF(msg);
        Py_XDECREF(type);
        Py_XDECREF(value);
        Py_XDECREF(tb);
        return;
    }
    Py_XDECREF(msg);
    PyErr_Restore(type, value, tb);
}

/* The library exception of failed trajectory i: simulate's (raise_run_error_at:
 * when, why, what to use instead; attributes status, time, cause) with
 * "batch index i: " in front and the attribute `index` (or ValueError /
 * MemoryError). */
static void raise_trajectory_error(PyObject *module, int status, const exdex_stats *st, Py_ssize_t i)
{
    if (status == EXDEX_ENOCONV || status == EXDEX_ENONFINITE) {
        raise_run_error_at(module, status, st, i);
    } else {
        char what[64];
        PyOS_snprintf(what, sizeof what, "batch index %zd", i);
        expy_raise_status(get_state(module)->SolverError, status, what, NULL, NULL, i);
    }
}

typedef struct batch_ctx {
    exdex_model **models;   /* every model (specs), or only models[0] (base + vary) */
    const exdex_scene_def *base;   /* base + vary: the definition the workers copy */
    int nvary;
    const int *which;
    const double **vals;   /* vals[k][i]: entry i of vary field which[k] */
    size_t nb, n;           /* trajectories, samples per trajectory */
    double t_end, dt;
    int ndof, ns, final;
    /* outputs (rows of trajectory i at i * row size) */
    double *t, *q, *v, *wrench, *stop_force, *disp;
    unsigned char *stick;
    npy_int64 *steps, *stick_steps, *solver_iterations, *stop_iterations, *warnings;
    double *min_gap;
    npy_int64 *impacts, *max_impulse_stop;
    double *max_impulse, *max_impulse_t, *first_warning_t, *grasp_lost_t;
    double *cert_until;     /* certificate: valid_until (NaN: planar) */
    npy_int64 *cert_bad;    /* certificate: first failing sample (n: none, -1: planar) */
    /* shared work index and the first failure */
    pthread_mutex_t lock;
    size_t next, chunk;     /* next index to hand out; indices per hand-out */
    size_t fail_index;      /* smallest failing index, nb if none (atomic stores under lock) */
    int fail_status;
    int fail_build;         /* the failure at fail_index is the model build (bad scene) */
    const char *fail_bad;   /* then: the parameter the core names */
    exdex_stats fail_stats; /* else: the statistics of that failure (fail_time, fail_cause) */
    int stop;               /* set when a signal handler raised (Ctrl-C): no new indices */
    PyThreadState *ts;      /* the calling thread's state while the GIL is released */
} batch_ctx;

typedef struct batch_worker {
    batch_ctx *ctx;
    double *buf;            /* scratch: t (all); t, q, v, wrench, stop_force (final) */
    unsigned char *stick;   /* scratch stick (final) */
    pthread_t tid;
    size_t cur, end;        /* the indices of the chunk in hand: [cur, end) */
    int started;
    int poll;               /* the calling (main) thread: run signal handlers now and then */
    double next_poll;       /* monotonic time of the next check [s] */
} batch_worker;

static double monotonic_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The calling thread, between trajectories and at most every 0.1 s: take the
 * GIL back briefly and run Python's signal handlers, so that Ctrl-C stops a
 * long batch (the exception stays set; no new indices are handed out). */
static void batch_poll_signals(batch_worker *w)
{
    batch_ctx *c = w->ctx;
    double now = monotonic_seconds();
    int raised;
    if (now < w->next_poll) return;
    w->next_poll = now + 0.1;
    PyEval_RestoreThread(c->ts);
    raised = PyErr_CheckSignals() < 0;
    c->ts = PyEval_SaveThread();
    if (raised) {
        pthread_mutex_lock(&c->lock);
        __atomic_store_n(&c->stop, 1, __ATOMIC_RELEASE);
        pthread_mutex_unlock(&c->lock);
    }
}

/* The certificate of trajectory i into the batch's arrays. */
static int batch_certify(batch_ctx *c, const exdex_model *model, const exdex_trajectory *tr, size_t i)
{
    exdex_certificate cert;
    int status = exdex_certify(model, tr, &cert);
    if (status) return status;
    c->cert_until[i] = cert.reduced ? cert.valid_until : NAN;
    c->cert_bad[i] = cert.reduced ? (npy_int64)cert.first_bad : -1;
    return EXDEX_OK;
}

static void *batch_run(void *arg)
{
    batch_worker *w = arg;
    batch_ctx *c = w->ctx;
    const size_t n = c->n;
    const int nd = c->ndof, ns = c->ns;
    for (;;) {
        size_t i;
        int status;
        exdex_model *model;
        exdex_trajectory tr;
        exdex_stats st;
        if (w->poll) batch_poll_signals(w);
        /* indices come in chunks of c->chunk consecutive ones, handed out in
         * order; after a failure at f, indices above f are not started (every
         * index below f was handed out already, and the ones in f's own chunk
         * run before f), so the error reported is the smallest failing index
         * whatever the thread count and chunk */
        if (w->cur >= w->end) {
            pthread_mutex_lock(&c->lock);
            w->cur = c->next;
            w->end = w->cur + c->chunk < c->nb ? w->cur + c->chunk : c->nb;
            c->next = w->end;
            pthread_mutex_unlock(&c->lock);
        }
        i = w->cur++;
        if (i >= c->nb || i > __atomic_load_n(&c->fail_index, __ATOMIC_ACQUIRE) ||
            __atomic_load_n(&c->stop, __ATOMIC_ACQUIRE))
            break;
        tr.n = n;
        tr.t = i == 0 ? c->t : w->buf;
        if (c->final) {
            tr.q = w->buf + n;
            tr.v = tr.q + n * (size_t)nd;
            tr.wrench = tr.v + n * (size_t)nd;
            tr.stop_force = ns ? tr.wrench + 3 * n : NULL;
            tr.stick = w->stick;
        } else {
            tr.q = c->q + i * n * (size_t)nd;
            tr.v = c->v + i * n * (size_t)nd;
            tr.wrench = c->wrench + i * n * 3;
            tr.stop_force = ns ? c->stop_force + i * n * (size_t)ns : NULL;
            tr.stick = c->stick + i * n;
        }
        if (c->base && i > 0) {
            exdex_scene_def def = *c->base;
            const char *bad = NULL;
            for (int k = 0; k < c->nvary; k++) *vary_field(&def, c->which[k]) = c->vals[k][i];
            model = exdex_model_alloc(&def, &status, &bad);
            if (!model) {
                pthread_mutex_lock(&c->lock);
                if (i < c->fail_index) {
                    __atomic_store_n(&c->fail_index, i, __ATOMIC_RELEASE);
                    c->fail_status = status;
                    c->fail_build = 1;
                    c->fail_bad = bad;
                }
                pthread_mutex_unlock(&c->lock);
                continue;
            }
            status = exdex_simulate(model, c->t_end, c->dt, &tr, &st);
            if (!status) status = batch_certify(c, model, &tr, i);
            exdex_model_free(model);
        } else {
            status = exdex_simulate(c->models[i], c->t_end, c->dt, &tr, &st);
            if (!status) status = batch_certify(c, c->models[i], &tr, i);
        }
        if (status) {
            pthread_mutex_lock(&c->lock);
            if (i < c->fail_index) {
                __atomic_store_n(&c->fail_index, i, __ATOMIC_RELEASE);
                c->fail_status = status;
                c->fail_build = 0;
                c->fail_stats = st;
            }
            pthread_mutex_unlock(&c->lock);
            continue;
        }
        if (st.lost_sample) {
            /* pads: the grasp was lost at sample lost_sample and the run
             * stopped there: NaN after it (stick 0) */
            for (size_t j = st.lost_sample + 1; j < n; j++) {
                for (int k = 0; k < nd; k++) tr.q[j * nd + k] = tr.v[j * nd + k] = NAN;
                for (int k = 0; k < 3; k++) tr.wrench[j * 3 + k] = NAN;
                for (int k = 0; k < ns; k++) tr.stop_force[j * ns + k] = NAN;
                tr.stick[j] = 0;
            }
        }
        if (c->final) {
            const size_t last = n - 1;
            for (int k = 0; k < nd; k++) {
                c->q[i * nd + k] = tr.q[last * nd + k];
                c->v[i * nd + k] = tr.v[last * nd + k];
            }
            for (int k = 0; k < 3; k++) c->wrench[i * 3 + k] = tr.wrench[last * 3 + k];
            for (int k = 0; k < ns; k++) c->stop_force[i * ns + k] = tr.stop_force[last * ns + k];
            c->stick[i] = tr.stick[last];
        }
        /* displacement of the last sample from the first, q[n-1] - q[0] */
        for (int k = 0; k < nd; k++) c->disp[i * nd + k] = tr.q[(n - 1) * nd + k] - tr.q[k];
        c->steps[i] = (npy_int64)st.steps;
        c->stick_steps[i] = (npy_int64)st.stick_steps;
        c->solver_iterations[i] = (npy_int64)st.solver_iterations;
        c->stop_iterations[i] = (npy_int64)st.stop_iterations;
        c->warnings[i] = (npy_int64)st.warnings;
        c->min_gap[i] = st.min_gap;
        c->impacts[i] = (npy_int64)st.impacts;
        c->max_impulse[i] = st.max_impulse;
        c->max_impulse_t[i] = st.max_impulse_t;
        c->max_impulse_stop[i] = (npy_int64)st.max_impulse_stop;
        c->first_warning_t[i] = st.first_warning_t;
        c->grasp_lost_t[i] = st.lost_t;
    }
    return NULL;
}

/* Length of the 1-D arrays of `vary` (all equal), -1 with an exception if
 * inconsistent; *keys / *arrays get new references (caller frees). */
static Py_ssize_t parse_vary(PyObject *vary, int *which, PyArrayObject **arrays, int *nvary)
{
    PyObject *key, *val;
    Py_ssize_t pos = 0, len = -1;
    *nvary = 0;
    if (!vary || vary == Py_None) return -2;
    if (!PyDict_Check(vary)) {
        PyErr_SetString(PyExc_TypeError, "vary must be a dict of spec key -> 1-D float64 array");
        return -1;
    }
    while (PyDict_Next(vary, &pos, &key, &val)) {
        const char *name;
        int w = -1;
        if (!PyUnicode_Check(key) || !(name = PyUnicode_AsUTF8(key))) {
            if (!PyErr_Occurred()) PyErr_SetString(PyExc_TypeError, "vary keys must be str");
            return -1;
        }
        for (int k = 0; vary_keys[k]; k++)
            if (!strcmp(vary_keys[k], name)) w = k;
        if (w < 0) {
            PyErr_Format(PyExc_ValueError,
                         "vary: unknown key '%s' (allowed: mass, mu, grip_force, e_r, motion_amplitude, "
                         "motion_duration, motion_beta, motion_v_max, eps, rtol, atol, mu_static, patch_center_x, "
                         "patch_center_y, pad_center_x, pad_center_y, pad_radius, pad_scale)", name);
            return -1;
        }
        arrays[*nvary] = (PyArrayObject *)PyArray_FROMANY(val, NPY_DOUBLE, 1, 1, NPY_ARRAY_IN_ARRAY);
        if (!arrays[*nvary]) {
            PyErr_Clear();
            PyErr_Format(PyExc_ValueError, "vary['%s'] must be a 1-D float64 array", name);
            return -1;
        }
        which[*nvary] = w;
        (*nvary)++;
        if (len >= 0 && PyArray_SIZE(arrays[*nvary - 1]) != len) {
            PyErr_Format(PyExc_ValueError, "vary['%s'] has %zd entries, the other arrays %zd", name,
                         (Py_ssize_t)PyArray_SIZE(arrays[*nvary - 1]), len);
            return -1;
        }
        len = PyArray_SIZE(arrays[*nvary - 1]);
    }
    return len < 0 ? -2 : len;
}

static long cpu_count(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? n : 1;
}

PyDoc_STRVAR(simulate_batch_doc,
"simulate_batch(specs, t_end, dt, threads=0, record='all', vary=None) -> dict\n\n"
"Run many trajectories with the GIL released, spread over `threads` POSIX\n"
"threads (0: the number of online CPUs). Use exdex.simulate_batch instead of\n"
"calling this directly.\n\n"
"specs : a list of spec dicts (exdex.Scene.to_spec()), one per trajectory, or\n"
"    one spec dict used for every trajectory.\n"
"vary : optional dict {spec key: 1-D float64 array of the batch length}; entry\n"
"    i replaces that scalar of spec i (keys: mass, mu, grip_force, e_r,\n"
"    motion_amplitude, motion_duration, motion_beta, motion_v_max, eps, rtol,\n"
"    atol, mu_static, patch_center_x, patch_center_y). With a single spec\n"
"    dict it sets the batch length.\n"
"record : 'all' returns q, v (B, n, ndof), wrench (B, n, 3), stick (B, n),\n"
"    stop_force (B, n, n_stops); 'final' only their last sample, q, v (B, ndof),\n"
"    wrench (B, 3), stick (B,), stop_force (B, n_stops).\n"
"Both return t (n,), displacement (B, ndof) = q[n-1] - q[0], and stats, a dict\n"
"of (B,) arrays. Every scene must have the same ndof and number of stops.\n"
"Errors name the batch index; a failing trajectory raises SolverError with\n"
"attributes status and index (the smallest failing index; with vary, a scene\n"
"the core rejects counts as failing at its index and raises ValueError).\n"
"check_signals : if true (pass it from the main thread), the calling thread runs\n"
"    Python's signal handlers about every 0.1 s, so Ctrl-C stops the batch.");

static PyObject *core_simulate_batch(PyObject *module, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"specs", "t_end", "dt", "threads", "record", "vary", "check_signals", NULL};
    enum { NVARY_MAX = 16 };
    PyObject *specs, *vary = NULL, *seq = NULL, *result = NULL, *stats = NULL;
    const char *record = "all";
    double t_end, dt;
    int threads = 0, check_signals = 0, final, nvary = 0, which[NVARY_MAX], ndof = 0, ns = 0, have_mutex = 0;
    PyArrayObject *varr[NVARY_MAX] = {NULL};
    PyArrayObject *base_times = NULL, *base_poses = NULL, *base_grip = NULL;
    PyArrayObject *t = NULL, *q = NULL, *v = NULL, *wr = NULL, *stick = NULL, *sf = NULL, *disp = NULL;
    PyArrayObject *sarr[14] = {NULL};
    exdex_model **models = NULL;
    batch_worker *workers = NULL;
    exdex_scene_def base;
    const double *vals[NVARY_MAX];
    Py_ssize_t nb, nvary_len, i, nmodels = 0;
    size_t n;
    long nthreads, running = 1;
    batch_ctx ctx;

    memset(&ctx, 0, sizeof ctx);
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "Odd|isOp", kwlist, &specs, &t_end, &dt, &threads, &record,
                                     &vary, &check_signals))
        return NULL;
    if (check_times(t_end, dt, &n)) return NULL;
    if (threads < 0 || threads > 1024) {
        PyErr_Format(PyExc_ValueError, "threads must be in [0, 1024] (0: one per CPU), got %d", threads);
        return NULL;
    }
    if (!strcmp(record, "all")) {
        final = 0;
    } else if (!strcmp(record, "final")) {
        final = 1;
    } else {
        PyErr_Format(PyExc_ValueError, "record must be 'all' or 'final', got '%s'", record);
        return NULL;
    }
    if (vary && vary != Py_None && PyDict_Size(vary) > NVARY_MAX) {
        PyErr_Format(PyExc_ValueError, "vary holds at most %d keys", (int)NVARY_MAX);
        return NULL;
    }
    nvary_len = parse_vary(vary, which, varr, &nvary);
    if (nvary_len == -1) goto done;

    /* ---- the batch: one spec dict (+ vary) or a sequence of spec dicts */
    if (PyDict_Check(specs)) {
        nb = nvary_len >= 0 ? nvary_len : 1;
        if (scene_from_dict(specs, &base, &base_times, &base_poses, &base_grip)) goto done;
    } else {
        seq = PySequence_Fast(specs, "specs must be a spec dict or a sequence of spec dicts");
        if (!seq) goto done;
        nb = PySequence_Fast_GET_SIZE(seq);
        if (nvary_len >= 0 && nvary_len != nb) {
            PyErr_Format(PyExc_ValueError, "vary arrays have %zd entries but specs has %zd", nvary_len, nb);
            goto done;
        }
    }
    if (nb < 1) {
        PyErr_SetString(PyExc_ValueError, "the batch is empty (specs or vary arrays of length 0)");
        goto done;
    }

    /* ---- build the models with the GIL held: every one (specs), or model 0
     * (base + vary; the workers build the others) */
    nmodels = seq ? nb : 1;
    models = PyMem_Calloc((size_t)nmodels, sizeof *models);
    if (!models) {
        PyErr_NoMemory();
        goto done;
    }
    for (i = 0; i < nmodels; i++) {
        exdex_scene_def def;
        PyArrayObject *times = NULL, *poses = NULL, *grip = NULL;
        const char *bad = NULL;
        int status;
        if (seq) {
            if (scene_from_dict(PySequence_Fast_GET_ITEM(seq, i), &def, &times, &poses, &grip)) {
                prefix_error(i);
                goto done;
            }
        } else {
            def = base;
        }
        for (int k = 0; k < nvary; k++) *vary_field(&def, which[k]) = ((const double *)PyArray_DATA(varr[k]))[i];
        models[i] = exdex_model_alloc(&def, &status, &bad);
        Py_XDECREF(times);
        Py_XDECREF(poses);
        Py_XDECREF(grip);
        if (!models[i]) {
            raise_status(module, status, "scene", bad);
            prefix_error(i);
            goto done;
        }
        if (i == 0) {
            ndof = exdex_model_ndof(models[0]);
            ns = exdex_model_nstops(models[0]);
        } else if (exdex_model_ndof(models[i]) != ndof || exdex_model_nstops(models[i]) != ns) {
            PyErr_Format(PyExc_ValueError,
                         "batch index %zd: every scene of a batch needs the same free coordinates and "
                         "number of stops (index 0: ndof %d, %d stops; here: ndof %d, %d stops)", i, ndof, ns,
                         exdex_model_ndof(models[i]), exdex_model_nstops(models[i]));
            goto done;
        }
    }

    /* ---- outputs */
    {
        npy_intp B = nb, N = (npy_intp)n;
        npy_intp d_t[1] = {N}, d_b[1] = {B}, d_bd[2] = {B, ndof}, d_b3[2] = {B, 3}, d_bs[2] = {B, ns};
        npy_intp d_bnd[3] = {B, N, ndof}, d_bn3[3] = {B, N, 3}, d_bn[2] = {B, N}, d_bns[3] = {B, N, ns};
        t = (PyArrayObject *)PyArray_SimpleNew(1, d_t, NPY_DOUBLE);
        disp = (PyArrayObject *)PyArray_SimpleNew(2, d_bd, NPY_DOUBLE);
        if (final) {
            q = (PyArrayObject *)PyArray_SimpleNew(2, d_bd, NPY_DOUBLE);
            v = (PyArrayObject *)PyArray_SimpleNew(2, d_bd, NPY_DOUBLE);
            wr = (PyArrayObject *)PyArray_SimpleNew(2, d_b3, NPY_DOUBLE);
            stick = (PyArrayObject *)PyArray_SimpleNew(1, d_b, NPY_BOOL);
            sf = (PyArrayObject *)PyArray_ZEROS(2, d_bs, NPY_DOUBLE, 0);
        } else {
            q = (PyArrayObject *)PyArray_SimpleNew(3, d_bnd, NPY_DOUBLE);
            v = (PyArrayObject *)PyArray_SimpleNew(3, d_bnd, NPY_DOUBLE);
            wr = (PyArrayObject *)PyArray_SimpleNew(3, d_bn3, NPY_DOUBLE);
            stick = (PyArrayObject *)PyArray_SimpleNew(2, d_bn, NPY_BOOL);
            sf = (PyArrayObject *)PyArray_ZEROS(3, d_bns, NPY_DOUBLE, 0);
        }
        /* int64: steps .. warnings (0-4), impacts (6), max_impulse_stop (9);
         * float64: min_gap (5), max_impulse (7), max_impulse_t (8), first_warning_t (10) */
        /* certificate: valid_until (11, float64), first failing sample (12, int64);
         * grasp_lost_t (13, float64: NaN where the pads held) */
        for (int k = 0; k < 14; k++)
            sarr[k] = (PyArrayObject *)PyArray_ZEROS(1, d_b, (k < 5 || k == 6 || k == 9 || k == 12) ? NPY_INT64
                                                                                                 : NPY_DOUBLE, 0);
        if (!t || !disp || !q || !v || !wr || !stick || !sf) goto done;
        for (int k = 0; k < 14; k++)
            if (!sarr[k]) goto done;
    }

    /* ---- workers: the calling thread plus nthreads - 1 POSIX threads */
    nthreads = threads ? threads : cpu_count();
    if (nthreads > nb) nthreads = (long)nb;
    workers = PyMem_Calloc((size_t)nthreads, sizeof *workers);
    if (!workers) {
        PyErr_NoMemory();
        goto done;
    }
    {
        /* scratch per worker: the time grid, and in 'final' mode one whole trajectory */
        size_t per = final ? n * (1 + 2 * (size_t)ndof + 3 + (size_t)ns) : n;
        if (per > (size_t)PY_SSIZE_T_MAX / sizeof(double)) {
            PyErr_NoMemory();
            goto done;
        }
        for (long k = 0; k < nthreads; k++) {
            workers[k].ctx = &ctx;
            workers[k].buf = PyMem_RawMalloc(per * sizeof(double));
            workers[k].stick = final ? PyMem_RawMalloc(n) : NULL;
            if (!workers[k].buf || (final && !workers[k].stick)) {
                PyErr_NoMemory();
                goto done;
            }
        }
    }
    ctx.models = models;
    if (!seq) {
        for (int k = 0; k < nvary; k++) vals[k] = (const double *)PyArray_DATA(varr[k]);
        ctx.base = &base;
        ctx.nvary = nvary;
        ctx.which = which;
        ctx.vals = vals;
    }
    ctx.nb = (size_t)nb;
    ctx.n = n;
    ctx.t_end = t_end;
    ctx.dt = dt;
    ctx.ndof = ndof;
    ctx.ns = ns;
    ctx.final = final;
    ctx.t = PyArray_DATA(t);
    ctx.q = PyArray_DATA(q);
    ctx.v = PyArray_DATA(v);
    ctx.wrench = PyArray_DATA(wr);
    ctx.stick = PyArray_DATA(stick);
    ctx.stop_force = PyArray_DATA(sf);
    ctx.disp = PyArray_DATA(disp);
    ctx.steps = PyArray_DATA(sarr[0]);
    ctx.stick_steps = PyArray_DATA(sarr[1]);
    ctx.solver_iterations = PyArray_DATA(sarr[2]);
    ctx.stop_iterations = PyArray_DATA(sarr[3]);
    ctx.warnings = PyArray_DATA(sarr[4]);
    ctx.min_gap = PyArray_DATA(sarr[5]);
    ctx.impacts = PyArray_DATA(sarr[6]);
    ctx.max_impulse = PyArray_DATA(sarr[7]);
    ctx.max_impulse_t = PyArray_DATA(sarr[8]);
    ctx.max_impulse_stop = PyArray_DATA(sarr[9]);
    ctx.first_warning_t = PyArray_DATA(sarr[10]);
    ctx.cert_until = PyArray_DATA(sarr[11]);
    ctx.cert_bad = PyArray_DATA(sarr[12]);
    ctx.grasp_lost_t = PyArray_DATA(sarr[13]);
    ctx.next = 0;
    /* short trajectories (the analytic path: about a microsecond) in chunks,
     * so that the lock is not the bottleneck; otherwise one at a time */
    ctx.chunk = (size_t)nb / ((size_t)nthreads * 64);
    if (ctx.chunk < 1) ctx.chunk = 1;
    if (ctx.chunk > 64) ctx.chunk = 64;
    ctx.fail_index = (size_t)nb;
    ctx.fail_status = EXDEX_OK;
    if (pthread_mutex_init(&ctx.lock, NULL)) {
        PyErr_SetString(PyExc_OSError, "simulate_batch: pthread_mutex_init failed");
        goto done;
    }
    have_mutex = 1;
    workers[0].poll = check_signals;
    workers[0].next_poll = monotonic_seconds() + 0.1;
    ctx.stop = 0;
    ctx.ts = PyEval_SaveThread();
    /* a thread that cannot be created is no error: the others (and this one)
     * take its share of the indices */
    for (long k = 1; k < nthreads; k++)
        if (pthread_create(&workers[k].tid, NULL, batch_run, &workers[k]) == 0) {
            workers[k].started = 1;
            running++;
        }
    batch_run(&workers[0]);
    for (long k = 1; k < nthreads; k++)
        if (workers[k].started) pthread_join(workers[k].tid, NULL);
    PyEval_RestoreThread(ctx.ts);
    if (ctx.stop) goto done;  /* a signal handler raised (KeyboardInterrupt): its exception is set */
    if (ctx.fail_index < (size_t)nb) {
        if (ctx.fail_build) {
            raise_status(module, ctx.fail_status, "scene", ctx.fail_bad);
            prefix_error((Py_ssize_t)ctx.fail_index);
        } else {
            raise_trajectory_error(module, ctx.fail_status, &ctx.fail_stats, (Py_ssize_t)ctx.fail_index);
        }
        goto done;
    }
    stats = Py_BuildValue("{s:O,s:O,s:O,s:O,s:O,s:O,s:O,s:O,s:O,s:O,s:O,s:O}", "steps", sarr[0], "stick_steps",
                          sarr[1], "solver_iterations", sarr[2], "stop_iterations", sarr[3], "warnings", sarr[4],
                          "min_gap", sarr[5], "impacts", sarr[6], "max_impulse", sarr[7], "max_impulse_t",
                          sarr[8], "max_impulse_stop", sarr[9], "first_warning_t", sarr[10],
                          "grasp_lost_t", sarr[13]);
    if (!stats) goto done;
    result = Py_BuildValue("{s:O,s:O,s:O,s:O,s:O,s:O,s:O,s:O,s:n,s:O,s:O}", "t", t, "q", q, "v", v, "wrench", wr,
                           "stick", stick, "stop_force", sf, "displacement", disp, "stats", stats,
                           "threads", (Py_ssize_t)running, "reduction_valid_until", sarr[11],
                           "reduction_first_bad", sarr[12]);
done:
    if (have_mutex) pthread_mutex_destroy(&ctx.lock);
    if (workers) {
        for (long k = 0; k < nthreads; k++) {
            PyMem_RawFree(workers[k].buf);
            PyMem_RawFree(workers[k].stick);
        }
        PyMem_Free(workers);
    }
    if (models) {
        for (i = 0; i < nmodels; i++) exdex_model_free(models[i]);
        PyMem_Free(models);
    }
    for (int k = 0; k < NVARY_MAX; k++) Py_XDECREF(varr[k]);
    for (int k = 0; k < 14; k++) Py_XDECREF(sarr[k]);
    Py_XDECREF(base_times);
    Py_XDECREF(base_poses);
    Py_XDECREF(base_grip);
    Py_XDECREF(seq);
    Py_XDECREF(t);
    Py_XDECREF(q);
    Py_XDECREF(v);
    Py_XDECREF(wr);
    Py_XDECREF(stick);
    Py_XDECREF(sf);
    Py_XDECREF(disp);
    Py_XDECREF(stats);
    return result;
}

static PyMethodDef core_methods[] = {
    {"simulate", (PyCFunction)(void (*)(void))core_simulate, METH_VARARGS | METH_KEYWORDS, simulate_doc},
    {"compile", core_compile, METH_O, compile_doc},
    {"analytic_unsupported", core_analytic_unsupported, METH_O, analytic_unsupported_doc},
    {"simulate_batch", (PyCFunction)(void (*)(void))core_simulate_batch, METH_VARARGS | METH_KEYWORDS,
     simulate_batch_doc},
    {"motion_eval", (PyCFunction)(void (*)(void))core_motion_eval, METH_VARARGS | METH_KEYWORDS,
     motion_eval_doc},
    {"motion_jumps", (PyCFunction)(void (*)(void))core_motion_jumps, METH_VARARGS | METH_KEYWORDS,
     motion_jumps_doc},
    {"grip_eval", (PyCFunction)(void (*)(void))core_grip_eval, METH_VARARGS | METH_KEYWORDS, grip_eval_doc},
    {"friction_solve", (PyCFunction)(void (*)(void))core_friction_solve, METH_VARARGS | METH_KEYWORDS,
     friction_solve_doc},
    {"obstacle_section", core_obstacle_section, METH_VARARGS, obstacle_section_doc},
    {"er_disc", core_er_disc, METH_O, "e_r [m] of a uniform pressure disc of radius R: 2R/3 (NaN if R <= 0)."},
    {"pad_region", core_pad_region, METH_VARARGS,
     "pad_region(spec, q) -> dict: the pads' contact region (area, centroid in B, e_r, radius of an exact disc "
     "region else 0, polygon vertices in B) with the object at q = (x, y, theta)."},
    {"limit_surface", core_limit_surface, METH_VARARGS,
     "limit_surface(surface, e_r, vertices or None, radius, what, (x, y, z)) -> ((x, y, z), s): "
     "exdex_limit_surface_eval per unit capacity (what 0: the friction wrench and dissipation of a slip twist; "
     "1: the gauge of a wrench and its slip direction at the limit)."},
    {"er_rectangle", core_er_rectangle, METH_VARARGS,
     "e_r [m] of a uniform pressure rectangle with half-sides a, b (NaN if not positive)."},
    {"n_samples", core_n_samples, METH_VARARGS, "Number of samples simulate returns for (t_end, dt); 0 if invalid."},
    {NULL, NULL, 0, NULL}};

/* The C enums and limits the Python layer uses (exdex/scene.py builds its
 * name -> value maps from these, never from literal numbers). */
static const expy_constant core_constants[] = {
    {"MAX_STOPS", EXDEX_MAX_STOPS},
    {"MAX_VERTICES", EXDEX_MAX_VERTICES},
    {"MAX_PAD_VERTICES", EXDEX_MAX_PAD_VERTICES},
    {"MAX_OBSTACLES", EXDEX_MAX_OBSTACLES},
    {"MAX_FACES", EXDEX_MAX_FACES},
    {"OBSTACLE_POLYTOPE", EXDEX_OBSTACLE_POLYTOPE},
    {"OBSTACLE_CYLINDER", EXDEX_OBSTACLE_CYLINDER},
    {"STATUS_OK", EXDEX_OK},
    {"STATUS_EINVAL", EXDEX_EINVAL},
    {"STATUS_ENOMEM", EXDEX_ENOMEM},
    {"STATUS_ENOCONV", EXDEX_ENOCONV},
    {"STATUS_ENONFINITE", EXDEX_ENONFINITE},
    {"DOF_TRANSLATION", EXDEX_DOF_TRANSLATION},
    {"DOF_ROTATION", EXDEX_DOF_ROTATION},
    {"DOF_PLANAR", EXDEX_DOF_PLANAR},
    {"METHOD_IMPLICIT", EXDEX_METHOD_IMPLICIT},
    {"METHOD_EVENT", EXDEX_METHOD_EVENT},
    {"METHOD_REGULARISED", EXDEX_METHOD_REGULARISED},
    {"METHOD_EXPLICIT", EXDEX_METHOD_EXPLICIT},
    {"METHOD_ANALYTIC", EXDEX_METHOD_ANALYTIC},
    {"SOLVER_SCALAR", EXDEX_SOLVER_SCALAR},
    {"SOLVER_BRENT", EXDEX_SOLVER_BRENT},
    {"SOLVER_MULTIROOT", EXDEX_SOLVER_MULTIROOT},
    {"MOTION_REST", EXDEX_MOTION_REST},
    {"MOTION_ASYMMETRIC", EXDEX_MOTION_ASYMMETRIC},
    {"MOTION_TRAPEZOID", EXDEX_MOTION_TRAPEZOID},
    {"MOTION_SAMPLED", EXDEX_MOTION_SAMPLED},
    {"MOTION_SHAKE", EXDEX_MOTION_SHAKE},
    {"MOTION_CHAIN", EXDEX_MOTION_CHAIN},
    {"MOTION_MAX_PIECES", EXDEX_MOTION_MAX_PIECES},
    {"GRIP_LINEAR", EXDEX_GRIP_LINEAR},
    {"GRIP_CUBIC", EXDEX_GRIP_CUBIC},
    {"GRIP_STEP", EXDEX_GRIP_STEP},
    {"MAX_GRIP_POINTS", EXDEX_MAX_GRIP_POINTS},
    {NULL, 0}};

static int core_exec(PyObject *module)
{
    core_state *s = get_state(module);
    if (PyArray_ImportNumPyAPI() < 0) return -1;
    exdex_init();
    s->SolverError = PyErr_NewExceptionWithDoc(
        "exdex._core.SolverError",
        "A numerical solver of the exdex core failed (no convergence or a non-finite state). "
        "The C status code is in the `status` attribute.",
        PyExc_RuntimeError, NULL);
    if (!s->SolverError) return -1;
    if (PyModule_AddObjectRef(module, "SolverError", s->SolverError) < 0) return -1;
    s->ModelType = PyType_FromModuleAndSpec(module, &Model_spec, NULL);
    if (!s->ModelType) return -1;
    if (PyModule_AddObjectRef(module, "Model", s->ModelType) < 0) return -1;
    s->StepperType = PyType_FromModuleAndSpec(module, &Stepper_spec, NULL);
    if (!s->StepperType) return -1;
    if (PyModule_AddObjectRef(module, "Stepper", s->StepperType) < 0) return -1;
    if (expy_add_constants(module, core_constants) < 0) return -1;
    return 0;
}

static int core_traverse(PyObject *module, visitproc visit, void *arg)
{
    Py_VISIT(get_state(module)->SolverError);
    Py_VISIT(get_state(module)->ModelType);
    Py_VISIT(get_state(module)->StepperType);
    return 0;
}

static int core_clear(PyObject *module)
{
    Py_CLEAR(get_state(module)->SolverError);
    Py_CLEAR(get_state(module)->ModelType);
    Py_CLEAR(get_state(module)->StepperType);
    return 0;
}

static PyModuleDef_Slot core_slots[] = {{Py_mod_exec, core_exec}, {0, NULL}};

static struct PyModuleDef core_module = {
    PyModuleDef_HEAD_INIT,
    .m_name = "exdex._core",
    .m_doc = "C core of exdex: relative dynamics of an object in a moving parallel-plate gripper.",
    .m_size = sizeof(core_state),
    .m_methods = core_methods,
    .m_slots = core_slots,
    .m_traverse = core_traverse,
    .m_clear = core_clear,
};

PyMODINIT_FUNC PyInit__core(void) { return PyModuleDef_Init(&core_module); }
