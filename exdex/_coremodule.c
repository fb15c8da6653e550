/* _coremodule.c -- exdex._core: the CPython + NumPy C API wrapper of the
 * simulation core (csrc/). Converts and validates arguments, releases the GIL
 * around whole-trajectory C calls, maps C status codes to exceptions.
 *
 * The Python layer (exdex/scene.py, exdex/simulate.py) validates user input
 * with friendly messages first; this module checks again, because it is
 * callable directly, and names the offending key in every error. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define PY_ARRAY_UNIQUE_SYMBOL exdex_core_ARRAY_API
#include <numpy/arrayobject.h>

#include <string.h>

#include "exdex.h"

typedef struct {
    PyObject *SolverError;
} core_state;

static core_state *get_state(PyObject *module) { return (core_state *)PyModule_GetState(module); }

/* Raise the library exception for a C status (or ValueError for EINVAL). */
static PyObject *raise_status(PyObject *module, int status, const char *what, const char *bad)
{
    if (status == EXDEX_EINVAL) {
        if (bad)
            PyErr_Format(PyExc_ValueError, "%s: invalid value of '%s'", what, bad);
        else
            PyErr_Format(PyExc_ValueError, "%s: invalid argument", what);
    } else if (status == EXDEX_ENOMEM) {
        PyErr_NoMemory();
    } else {
        PyObject *exc = get_state(module)->SolverError;
        PyObject *args = Py_BuildValue("(si)", exdex_strerror(status), status);
        if (args) {
            PyObject *inst = PyObject_Call(exc, args, NULL);
            Py_DECREF(args);
            if (inst) {
                PyObject *st = PyLong_FromLong(status);
                if (st) {
                    PyObject_SetAttrString(inst, "status", st);
                    Py_DECREF(st);
                }
                PyErr_SetObject(exc, inst);
                Py_DECREF(inst);
            }
        }
    }
    return NULL;
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

/* Fill an exdex_scene_def from a spec dict. Sampled-motion arrays are
 * returned as new references in *times / *poses (kept alive by the caller
 * until the model is built). */
static int scene_from_dict(PyObject *spec, exdex_scene_def *def, PyArrayObject **times,
                           PyArrayObject **poses)
{
    PyArrayObject *verts = NULL, *sp = NULL, *sn = NULL;
    npy_intp nv, nsp, nsn, nt, np_;
    *times = *poses = NULL;
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
    def->n_vertices = (int)nv;
    if (nv) memcpy(def->vertices, PyArray_DATA(verts), (size_t)nv * 2 * sizeof(double));
    def->n_stops = (int)nsp;
    if (nsp) {
        memcpy(def->stop_point, PyArray_DATA(sp), (size_t)nsp * 3 * sizeof(double));
        memcpy(def->stop_normal, PyArray_DATA(sn), (size_t)nsn * 3 * sizeof(double));
    }
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
    }
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
    *times = *poses = NULL;
    return -1;
}

static PyObject *stats_dict(const exdex_stats *st)
{
    return Py_BuildValue("{s:n,s:n,s:n,s:n,s:n,s:d}", "steps", (Py_ssize_t)st->steps, "stick_steps",
                         (Py_ssize_t)st->stick_steps, "solver_iterations", (Py_ssize_t)st->solver_iterations,
                         "stop_iterations", (Py_ssize_t)st->stop_iterations, "warnings",
                         (Py_ssize_t)st->warnings, "min_gap", st->min_gap);
}

PyDoc_STRVAR(simulate_doc,
"simulate(spec, t_end, dt) -> dict\n\n"
"Run one trajectory in C with the GIL released. `spec` is the dict made by\n"
"exdex.Scene.to_spec(); use exdex.simulate() instead of calling this directly.\n"
"Returns a dict of arrays t, q, v, wrench, stick, stop_force and a stats dict.");

static PyObject *core_simulate(PyObject *module, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"spec", "t_end", "dt", NULL};
    PyObject *spec, *result = NULL, *stats = NULL;
    double t_end, dt;
    exdex_scene_def def;
    PyArrayObject *times = NULL, *poses = NULL;
    PyArrayObject *t = NULL, *q = NULL, *v = NULL, *wr = NULL, *stick = NULL, *sf = NULL;
    exdex_model *model = NULL;
    exdex_trajectory tr;
    exdex_stats st;
    const char *bad = NULL;
    int status, ndof, nstops;
    size_t n;

    if (!PyArg_ParseTupleAndKeywords(args, kwds, "Odd", kwlist, &spec, &t_end, &dt)) return NULL;
    if (!(isfinite(dt) && dt > 0)) {
        PyErr_Format(PyExc_ValueError, "dt must be finite and > 0, got %g", dt);
        return NULL;
    }
    if (!(isfinite(t_end) && t_end >= dt)) {
        PyErr_Format(PyExc_ValueError, "t_end must be finite and >= dt (%g), got %g", dt, t_end);
        return NULL;
    }
    n = exdex_n_samples(t_end, dt);
    if (n == 0) {
        PyErr_Format(PyExc_ValueError, "t_end / dt must be between 1 and 1e9 steps, got %g", t_end / dt);
        return NULL;
    }
    if (scene_from_dict(spec, &def, &times, &poses)) return NULL;
    model = exdex_model_alloc(&def, &status, &bad);
    Py_XDECREF(times);
    Py_XDECREF(poses);
    if (!model) return raise_status(module, status, "scene", bad);
    ndof = exdex_model_ndof(model);
    nstops = exdex_model_nstops(model);
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
    Py_BEGIN_ALLOW_THREADS
    status = exdex_simulate(model, t_end, dt, &tr, &st);
    Py_END_ALLOW_THREADS
    if (status) {
        raise_status(module, status, "simulate", NULL);
        goto done;
    }
    stats = stats_dict(&st);
    if (!stats) goto done;
    result = Py_BuildValue("{s:O,s:O,s:O,s:O,s:O,s:O,s:O}", "t", t, "q", q, "v", v, "wrench", wr, "stick",
                           stick, "stop_force", sf, "stats", stats);
done:
    exdex_model_free(model);
    Py_XDECREF(t);
    Py_XDECREF(q);
    Py_XDECREF(v);
    Py_XDECREF(wr);
    Py_XDECREF(stick);
    Py_XDECREF(sf);
    Py_XDECREF(stats);
    return result;
}

PyDoc_STRVAR(motion_eval_doc,
"motion_eval(spec, t) -> dict\n\n"
"Gripper kinematics of the scene's motion at the times t (1-D float64):\n"
"R (n, 3, 3) = R_AB, p, v, a, w, dw (n, 3), all in the world frame A.");

static PyObject *core_motion_eval(PyObject *module, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"spec", "t", NULL};
    PyObject *spec, *tobj, *result = NULL;
    PyArrayObject *times = NULL, *poses = NULL, *ta = NULL, *out[6] = {NULL};
    exdex_scene_def def;
    exdex_motion *mo = NULL;
    const char *bad = NULL;
    int status = EXDEX_OK;
    npy_intp n;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OO", kwlist, &spec, &tobj)) return NULL;
    ta = (PyArrayObject *)PyArray_FROMANY(tobj, NPY_DOUBLE, 0, 1, NPY_ARRAY_IN_ARRAY);
    if (!ta) return NULL;
    n = PyArray_SIZE(ta);
    if (scene_from_dict(spec, &def, &times, &poses)) goto done;
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
    Py_XDECREF(ta);
    for (int i = 0; i < 6; i++) Py_XDECREF(out[i]);
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

static PyObject *core_n_samples(PyObject *module, PyObject *args)
{
    double t_end, dt;
    (void)module;
    if (!PyArg_ParseTuple(args, "dd", &t_end, &dt)) return NULL;
    return PyLong_FromSize_t(exdex_n_samples(t_end, dt));
}

static PyMethodDef core_methods[] = {
    {"simulate", (PyCFunction)(void (*)(void))core_simulate, METH_VARARGS | METH_KEYWORDS, simulate_doc},
    {"motion_eval", (PyCFunction)(void (*)(void))core_motion_eval, METH_VARARGS | METH_KEYWORDS,
     motion_eval_doc},
    {"friction_solve", (PyCFunction)(void (*)(void))core_friction_solve, METH_VARARGS | METH_KEYWORDS,
     friction_solve_doc},
    {"er_disc", core_er_disc, METH_O, "e_r [m] of a uniform pressure disc of radius R: 2R/3 (NaN if R <= 0)."},
    {"er_rectangle", core_er_rectangle, METH_VARARGS,
     "e_r [m] of a uniform pressure rectangle with half-sides a, b (NaN if not positive)."},
    {"n_samples", core_n_samples, METH_VARARGS, "Number of samples simulate returns for (t_end, dt); 0 if invalid."},
    {NULL, NULL, 0, NULL}};

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
    if (PyModule_AddIntConstant(module, "MAX_STOPS", EXDEX_MAX_STOPS) < 0) return -1;
    if (PyModule_AddIntConstant(module, "MAX_VERTICES", EXDEX_MAX_VERTICES) < 0) return -1;
    return 0;
}

static int core_traverse(PyObject *module, visitproc visit, void *arg)
{
    Py_VISIT(get_state(module)->SolverError);
    return 0;
}

static int core_clear(PyObject *module)
{
    Py_CLEAR(get_state(module)->SolverError);
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
