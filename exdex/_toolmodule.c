/* _toolmodule.c -- exdex._tool: CPython/NumPy wrapper of the tool-design core
 * (csrc/cone.c, paper Section 3). The only file of the tool module that
 * includes Python.h. Converts and validates arguments (messages name the
 * parameter and its allowed range), releases the GIL around the vectorised C
 * loops, and maps C status codes to exceptions. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <numpy/arrayobject.h>

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "exdex.h"
#include "_common.h"

typedef struct {
    PyObject *SolverError;   /* exdex._core.SolverError, shared */
} tool_state;

static tool_state *get_state(PyObject *module)
{
    return (tool_state *)PyModule_GetState(module);
}

/* ---------------------------------------------------------------- helpers
 * Argument conversion and the status -> exception mapping are shared with
 * exdex._core (_common.h). */

static int set_status_error(PyObject *module, int status, const char *what)
{
    expy_raise_status(get_state(module)->SolverError, status, what, NULL, NULL, -1);
    return -1;
}

#define as_double_array(obj, name, shape) expy_doubles((obj), (name), (shape))
#define value_error expy_value_error
#define all_finite expy_all_finite
#define get_double expy_double
#define get_long expy_long

/* box: lo (3,), hi (3,) with hi > lo, finite */
static int get_box(PyObject *lo_obj, PyObject *hi_obj, double lo[3], double hi[3])
{
    PyObject *objs[2] = {lo_obj, hi_obj};
    const char *names[2] = {"lo", "hi"};
    double *dst[2] = {lo, hi};
    for (int k = 0; k < 2; k++) {
        PyArrayObject *a = as_double_array(objs[k], names[k], "(3,)");
        if (!a) return -1;
        if (PyArray_NDIM(a) != 1 || PyArray_DIM(a, 0) != 3 || !all_finite(a)) {
            PyErr_Format(PyExc_ValueError, "%s must have shape (3,) with finite entries "
                         "(the twist box bounds of Vx, Vy, wz)", names[k]);
            Py_DECREF(a);
            return -1;
        }
        memcpy(dst[k], PyArray_DATA(a), 3 * sizeof(double));
        Py_DECREF(a);
    }
    for (int j = 0; j < 3; j++)
        if (!(hi[j] > lo[j])) {
            value_error("hi must exceed lo on every axis (axis %d: lo = %g, hi = %g)", j,
                        lo[j], hi[j]);
            return -1;
        }
    return 0;
}

static const char *const volume_method_names[] = {"exact", "grid", "qmc", NULL};
static const int volume_method_values[] = {EXDEX_VOLUME_EXACT, EXDEX_VOLUME_GRID, EXDEX_VOLUME_QMC};

static int get_method(PyObject *obj, int *method)
{
    return expy_choice(obj, "method", volume_method_names, volume_method_values, method);
}

/* ---------------------------------------------------------------- volumes */

PyDoc_STRVAR(volumes_doc,
"volumes(rows, lo, hi, method='exact', grid_n=64, qmc_points=65536, qmc_shifts=16, seed=1)\n"
"--\n\n"
"Volumes of {x in [lo, hi] : rows x >= 0} for a batch of cones.\n\n"
"rows: (n, m, 3) float, m <= 136 (all-zero rows are padding). lo, hi: (3,).\n"
"method: 'exact' (divergence theorem), 'grid' (grid_n cells per axis, cell\n"
"centres counted) or 'qmc' (Sobol, qmc_shifts random shifts of qmc_points\n"
"points). Returns (volume, err), two (n,) arrays; err is the QMC standard\n"
"error (NaN for the other methods). The GIL is released during the loop.");

static PyObject *tool_volumes_fn(PyObject *module, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"rows", "lo", "hi", "method", "grid_n", "qmc_points",
                             "qmc_shifts", "seed", NULL};
    PyObject *rows_obj, *lo_obj, *hi_obj, *method_obj = NULL, *grid_obj = NULL,
             *pts_obj = NULL, *shifts_obj = NULL, *seed_obj = NULL;
    PyArrayObject *rows = NULL, *vol = NULL, *err = NULL;
    PyObject *result = NULL;
    double lo[3], hi[3];
    int method = EXDEX_VOLUME_EXACT;
    exdex_volume_opts opts = exdex_default_volume_opts();
    long v;

    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OOO|OOOOO:volumes", kwlist, &rows_obj,
                                     &lo_obj, &hi_obj, &method_obj, &grid_obj, &pts_obj,
                                     &shifts_obj, &seed_obj))
        return NULL;
    if (get_box(lo_obj, hi_obj, lo, hi)) goto fail;
    if (method_obj && get_method(method_obj, &method)) goto fail;
    if (grid_obj) {
        if (get_long(grid_obj, "grid_n", 1, 100000, &v)) goto fail;
        opts.grid_n = v;
    }
    if (pts_obj) {
        if (get_long(pts_obj, "qmc_points", 1, 1L << 30, &v)) goto fail;
        opts.qmc_points = v;
    }
    if (shifts_obj) {
        if (get_long(shifts_obj, "qmc_shifts", 1, 4096, &v)) goto fail;
        opts.qmc_shifts = (int)v;
    }
    if (seed_obj) {
        if (get_long(seed_obj, "seed", 0, 0x7fffffffL, &v)) goto fail;
        opts.seed = (unsigned long)v;
    }
    rows = as_double_array(rows_obj, "rows", "(n, m, 3)");
    if (!rows) goto fail;
    if (PyArray_NDIM(rows) != 3 || PyArray_DIM(rows, 2) != 3) {
        PyErr_Format(PyExc_ValueError, "rows must have shape (n, m, 3), got %d dimensions",
                     PyArray_NDIM(rows));
        goto fail;
    }
    if (PyArray_DIM(rows, 1) > EXDEX_CONE_MAX_ROWS) {
        PyErr_Format(PyExc_ValueError, "rows: m must be in [0, %d] rows per cone, got %zd",
                     EXDEX_CONE_MAX_ROWS, (Py_ssize_t)PyArray_DIM(rows, 1));
        goto fail;
    }
    if (!all_finite(rows)) {
        PyErr_SetString(PyExc_ValueError, "rows must be finite");
        goto fail;
    }
    npy_intp n = PyArray_DIM(rows, 0);
    int m = (int)PyArray_DIM(rows, 1);
    vol = (PyArrayObject *)PyArray_SimpleNew(1, &n, NPY_DOUBLE);
    err = (PyArrayObject *)PyArray_SimpleNew(1, &n, NPY_DOUBLE);
    if (!vol || !err) goto fail;
    int status;
    Py_BEGIN_ALLOW_THREADS
    status = exdex_cone_volumes(method, (size_t)n, m, (const double *)PyArray_DATA(rows), lo,
                                hi, &opts, (double *)PyArray_DATA(vol),
                                (double *)PyArray_DATA(err));
    Py_END_ALLOW_THREADS
    if (status) {
        set_status_error(module, status, "volumes");
        goto fail;
    }
    result = Py_BuildValue("(OO)", vol, err);
fail:
    Py_XDECREF(rows);
    Py_XDECREF(vol);
    Py_XDECREF(err);
    return result;
}

/* ------------------------------------------------------------------- rows */

PyDoc_STRVAR(paper_rows_doc,
"paper_rows(phi, theta)\n--\n\n"
"The paper's Eqs. 10-11 literally: rows (n, 2, 3) for the unit square at\n"
"attack angles phi (n,) against two surfaces at angles theta (n,) [rad].");

static PyObject *paper_rows_fn(PyObject *module, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"phi", "theta", NULL};
    PyObject *phi_obj, *theta_obj, *result = NULL;
    PyArrayObject *phi = NULL, *theta = NULL, *out = NULL;
    (void)module;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OO:paper_rows", kwlist, &phi_obj,
                                     &theta_obj))
        return NULL;
    phi = as_double_array(phi_obj, "phi", "(n,)");
    if (!phi) goto fail;
    theta = as_double_array(theta_obj, "theta", "(n,)");
    if (!theta) goto fail;
    if (PyArray_NDIM(phi) != 1 || PyArray_NDIM(theta) != 1 ||
        PyArray_DIM(phi, 0) != PyArray_DIM(theta, 0)) {
        PyErr_SetString(PyExc_ValueError, "phi and theta must be 1-D arrays of equal length");
        goto fail;
    }
    if (!all_finite(phi) || !all_finite(theta)) {
        PyErr_SetString(PyExc_ValueError, "phi and theta must be finite [rad]");
        goto fail;
    }
    npy_intp dims[3] = {PyArray_DIM(phi, 0), 2, 3};
    out = (PyArrayObject *)PyArray_SimpleNew(3, dims, NPY_DOUBLE);
    if (!out) goto fail;
    const double *p = PyArray_DATA(phi), *t = PyArray_DATA(theta);
    double *o = PyArray_DATA(out);
    for (npy_intp i = 0; i < dims[0]; i++) exdex_cone_rows_paper(o + 6 * i, p[i], t[i]);
    result = (PyObject *)out;
    out = NULL;
fail:
    Py_XDECREF(phi);
    Py_XDECREF(theta);
    Py_XDECREF(out);
    return result;
}

PyDoc_STRVAR(contact_rows_doc,
"contact_rows(points, normals, mu=0.0)\n--\n\n"
"Rows of k contacts: points (k, 2) in the object frame [m], normals (k, 2)\n"
"unit, pointing from the tool into the object's free side. mu = 0: one row\n"
"(n, r x n) per contact, shape (k, 3); mu > 0: the two friction-cone edges\n"
"per contact, shape (2k, 3).");

static PyObject *contact_rows_fn(PyObject *module, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"points", "normals", "mu", NULL};
    PyObject *pts_obj, *nrm_obj, *mu_obj = NULL, *result = NULL;
    PyArrayObject *pts = NULL, *nrm = NULL, *out = NULL;
    double mu = 0.0;
    (void)module;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OO|O:contact_rows", kwlist, &pts_obj,
                                     &nrm_obj, &mu_obj))
        return NULL;
    if (mu_obj && get_double(mu_obj, "mu", &mu)) goto fail;
    if (!(mu >= 0.0) || !isfinite(mu)) {
        value_error("mu must be finite and >= 0, got %g", mu);
        goto fail;
    }
    pts = as_double_array(pts_obj, "points", "(k, 2)");
    if (!pts) goto fail;
    nrm = as_double_array(nrm_obj, "normals", "(k, 2)");
    if (!nrm) goto fail;
    if (PyArray_NDIM(pts) != 2 || PyArray_DIM(pts, 1) != 2 || PyArray_NDIM(nrm) != 2 ||
        PyArray_DIM(nrm, 1) != 2 || PyArray_DIM(pts, 0) != PyArray_DIM(nrm, 0)) {
        PyErr_SetString(PyExc_ValueError, "points and normals must both have shape (k, 2)");
        goto fail;
    }
    if (!all_finite(pts) || !all_finite(nrm)) {
        PyErr_SetString(PyExc_ValueError, "points and normals must be finite");
        goto fail;
    }
    npy_intp k = PyArray_DIM(pts, 0);
    const double *r = PyArray_DATA(pts), *nn = PyArray_DATA(nrm);
    for (npy_intp i = 0; i < k; i++) {
        double len = hypot(nn[2 * i], nn[2 * i + 1]);
        if (fabs(len - 1.0) > 1e-9) {
            value_error("normals must be unit vectors (row %ld has length %g)", (long)i, len);
            goto fail;
        }
    }
    npy_intp dims[2] = {mu > 0.0 ? 2 * k : k, 3};
    out = (PyArrayObject *)PyArray_SimpleNew(2, dims, NPY_DOUBLE);
    if (!out) goto fail;
    double *o = PyArray_DATA(out);
    for (npy_intp i = 0; i < k; i++) {
        if (mu > 0.0)
            exdex_contact_rows_friction(o + 6 * i, r + 2 * i, nn + 2 * i, mu);
        else
            exdex_contact_row(o + 3 * i, r + 2 * i, nn + 2 * i);
    }
    result = (PyObject *)out;
    out = NULL;
fail:
    Py_XDECREF(pts);
    Py_XDECREF(nrm);
    Py_XDECREF(out);
    return result;
}

/* -------------------------------------------------------- tool problems */

/* A parsed exdex_tool_problem with the arrays that own its memory. */
typedef struct problem_args {
    exdex_tool_problem p;
    PyArrayObject *phi;
    PyArrayObject *verts;  /* (sum nv, 2), owned */
    int *nv;               /* PyMem */
} problem_args;

static void problem_args_free(problem_args *a)
{
    Py_XDECREF(a->phi);
    Py_XDECREF(a->verts);
    PyMem_Free(a->nv);
    a->phi = NULL;
    a->verts = NULL;
    a->nv = NULL;
}

static const char *const tool_model_names[] = {"contact", "paper", NULL};
static const int tool_model_values[] = {EXDEX_TOOL_CONTACT, EXDEX_TOOL_PAPER};

static int parse_model(PyObject *obj, int *model)
{
    if (!obj) { *model = EXDEX_TOOL_CONTACT; return 0; }
    return expy_choice(obj, "model", tool_model_names, tool_model_values, model);
}

/* shapes: a sequence of (nv, 2) arrays; phi: (P,); lo, hi; mu; push (3,) or None */
static int parse_problem(problem_args *a, PyObject *shapes, PyObject *phi_obj,
                         PyObject *lo_obj, PyObject *hi_obj, PyObject *mu_obj,
                         PyObject *push_obj, PyObject *model_obj)
{
    memset(a, 0, sizeof *a);
    exdex_tool_problem *p = &a->p;
    if (parse_model(model_obj, &p->model)) return -1;
    if (get_box(lo_obj, hi_obj, p->lo, p->hi)) return -1;
    p->mu = 0.0;
    if (mu_obj && mu_obj != Py_None) {
        if (get_double(mu_obj, "mu", &p->mu)) return -1;
        if (!(p->mu >= 0.0) || !isfinite(p->mu)) {
            value_error("mu must be finite and >= 0, got %g", p->mu);
            return -1;
        }
    }
    p->has_push = 0;
    p->push[0] = p->push[1] = p->push[2] = 0.0;
    if (push_obj && push_obj != Py_None) {
        PyArrayObject *q = as_double_array(push_obj, "push", "(3,)");
        if (!q) return -1;
        if (PyArray_NDIM(q) != 1 || PyArray_DIM(q, 0) != 3 || !all_finite(q)) {
            PyErr_SetString(PyExc_ValueError,
                            "push must have shape (3,): a finite wrench (F_x, F_y, M_z)");
            Py_DECREF(q);
            return -1;
        }
        memcpy(p->push, PyArray_DATA(q), 3 * sizeof(double));
        Py_DECREF(q);
        p->has_push = 1;
    }
    a->phi = as_double_array(phi_obj, "phi", "(P,)");
    if (!a->phi) goto fail;
    if (PyArray_NDIM(a->phi) != 1 || PyArray_DIM(a->phi, 0) < 1 ||
        PyArray_DIM(a->phi, 0) > 1000000 || !all_finite(a->phi)) {
        PyErr_SetString(PyExc_ValueError,
                        "phi must be a 1-D array of 1 to 10^6 finite attack angles [rad]");
        goto fail;
    }
    p->n_phi = (int)PyArray_DIM(a->phi, 0);
    p->phi = PyArray_DATA(a->phi);

    PyObject *seq = PySequence_Fast(shapes, "shapes must be a sequence of (nv, 2) arrays");
    if (!seq) {
        PyErr_Clear();
        PyErr_SetString(PyExc_TypeError, "shapes must be a sequence of (nv, 2) arrays");
        goto fail;
    }
    Py_ssize_t ns = PySequence_Fast_GET_SIZE(seq);
    if (ns < 1 || ns > 10000) {
        Py_DECREF(seq);
        PyErr_SetString(PyExc_ValueError, "shapes must hold 1 to 10000 polygons");
        goto fail;
    }
    a->nv = PyMem_Malloc(sizeof(int) * (size_t)ns);
    if (!a->nv) {
        Py_DECREF(seq);
        PyErr_NoMemory();
        goto fail;
    }
    npy_intp total = 0;
    for (Py_ssize_t i = 0; i < ns; i++) {
        PyArrayObject *v = as_double_array(PySequence_Fast_GET_ITEM(seq, i), "shapes[i]",
                                           "(nv, 2)");
        if (!v) { Py_DECREF(seq); goto fail; }
        int ok = PyArray_NDIM(v) == 2 && PyArray_DIM(v, 1) == 2 && PyArray_DIM(v, 0) >= 3 &&
                 PyArray_DIM(v, 0) <= EXDEX_MAX_VERTICES && all_finite(v);
        if (ok) a->nv[i] = (int)PyArray_DIM(v, 0);
        total += ok ? PyArray_DIM(v, 0) : 0;
        Py_DECREF(v);
        if (!ok) {
            Py_DECREF(seq);
            PyErr_Format(PyExc_ValueError, "shapes[%zd] must have shape (nv, 2) with "
                         "3 <= nv <= %d finite vertices", i, EXDEX_MAX_VERTICES);
            goto fail;
        }
    }
    npy_intp dims[2] = {total, 2};
    a->verts = (PyArrayObject *)PyArray_SimpleNew(2, dims, NPY_DOUBLE);
    if (!a->verts) { Py_DECREF(seq); goto fail; }
    double *dst = PyArray_DATA(a->verts);
    for (Py_ssize_t i = 0; i < ns; i++) {
        PyArrayObject *v = as_double_array(PySequence_Fast_GET_ITEM(seq, i), "shapes[i]",
                                           "(nv, 2)");
        if (!v) { Py_DECREF(seq); goto fail; }
        memcpy(dst, PyArray_DATA(v), sizeof(double) * 2 * (size_t)a->nv[i]);
        dst += 2 * a->nv[i];
        Py_DECREF(v);
    }
    Py_DECREF(seq);
    p->n_shapes = (int)ns;
    p->n_vertices = a->nv;
    p->vertices = PyArray_DATA(a->verts);
    const char *bad = NULL;
    if (exdex_tool_problem_check(p, &bad)) {
        if (bad && strcmp(bad, "shapes") == 0)
            PyErr_SetString(PyExc_ValueError,
                            "shapes: every polygon needs a non-zero area");
        else
            PyErr_Format(PyExc_ValueError, "invalid tool problem: %s", bad ? bad : "?");
        goto fail;
    }
    return 0;
fail:
    problem_args_free(a);
    return -1;
}

PyDoc_STRVAR(tool_rows_doc,
"tool_rows(shapes, phi, lo, hi, alpha1, alpha2, s=None, mu=0.0, push=None, model='contact', shape=0)\n"
"--\n\n"
"Rows (m, 3) of one object (shapes[shape]) at one attack angle phi [rad]\n"
"against the V tool (alpha1, alpha2) [rad], with a plunger at x = s when s\n"
"is not None. See exdex.h for the geometry.");

static int get_tool(PyObject *a1, PyObject *a2, PyObject *s_obj, exdex_tool_def *t)
{
    if (get_double(a1, "alpha1", &t->alpha1) || get_double(a2, "alpha2", &t->alpha2))
        return -1;
    t->plunger = 0;
    t->s = 0.0;
    if (s_obj && s_obj != Py_None) {
        if (get_double(s_obj, "s", &t->s)) return -1;
        t->plunger = 1;
    }
    if (!isfinite(t->alpha1) || !isfinite(t->alpha2) || !isfinite(t->s)) {
        PyErr_SetString(PyExc_ValueError, "alpha1, alpha2 and s must be finite");
        return -1;
    }
    return 0;
}

static PyObject *tool_rows_fn(PyObject *module, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"shapes", "phi", "lo", "hi", "alpha1", "alpha2", "s", "mu",
                             "push", "model", "shape", NULL};
    PyObject *shapes, *phi_obj, *lo_obj, *hi_obj, *a1, *a2, *s_obj = NULL, *mu_obj = NULL,
             *push_obj = NULL, *model_obj = NULL, *shape_obj = NULL, *result = NULL;
    problem_args pa;
    PyArrayObject *out = NULL;
    double phi;
    long shape = 0;
    exdex_tool_def tool;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OOOOOO|OOOOO:tool_rows", kwlist, &shapes,
                                     &phi_obj, &lo_obj, &hi_obj, &a1, &a2, &s_obj, &mu_obj,
                                     &push_obj, &model_obj, &shape_obj))
        return NULL;
    if (get_double(phi_obj, "phi", &phi)) return NULL;
    if (!isfinite(phi)) {
        PyErr_SetString(PyExc_ValueError, "phi must be finite [rad]");
        return NULL;
    }
    if (get_tool(a1, a2, s_obj, &tool)) return NULL;
    PyObject *phi_arr = Py_BuildValue("[d]", phi);
    if (!phi_arr) return NULL;
    int st = parse_problem(&pa, shapes, phi_arr, lo_obj, hi_obj, mu_obj, push_obj, model_obj);
    Py_DECREF(phi_arr);
    if (st) return NULL;
    if (shape_obj && get_long(shape_obj, "shape", 0, pa.p.n_shapes - 1, &shape)) goto fail;
    double rows[3 * EXDEX_CONE_MAX_ROWS];
    int m = 0;
    st = exdex_tool_rows(&pa.p, &tool, (int)shape, phi, rows, &m);
    if (st) {
        set_status_error(module, st, "tool_rows");
        goto fail;
    }
    npy_intp dims[2] = {m, 3};
    out = (PyArrayObject *)PyArray_SimpleNew(2, dims, NPY_DOUBLE);
    if (!out) goto fail;
    memcpy(PyArray_DATA(out), rows, sizeof(double) * 3 * (size_t)m);
    result = (PyObject *)out;
fail:
    problem_args_free(&pa);
    return result;
}

PyDoc_STRVAR(tool_volumes_doc,
"tool_volumes(shapes, phi, lo, hi, tools, plunger=False, mu=0.0, push=None, model='contact')\n"
"--\n\n"
"Exact volumes (T, S, P) for T tools (rows of tools (T, 3): alpha1, alpha2, s),\n"
"S shapes (1 for model='paper') and P attack angles. GIL released.");

static PyObject *tool_volumes_fn2(PyObject *module, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"shapes", "phi", "lo", "hi", "tools", "plunger", "mu", "push",
                             "model", NULL};
    PyObject *shapes, *phi_obj, *lo_obj, *hi_obj, *tools_obj, *mu_obj = NULL,
             *push_obj = NULL, *model_obj = NULL, *result = NULL;
    int plunger = 0;
    problem_args pa;
    PyArrayObject *tools = NULL, *out = NULL;
    exdex_tool_def *defs = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OOOOO|pOOO:tool_volumes", kwlist, &shapes,
                                     &phi_obj, &lo_obj, &hi_obj, &tools_obj, &plunger, &mu_obj,
                                     &push_obj, &model_obj))
        return NULL;
    if (parse_problem(&pa, shapes, phi_obj, lo_obj, hi_obj, mu_obj, push_obj, model_obj))
        return NULL;
    tools = as_double_array(tools_obj, "tools", "(T, 3)");
    if (!tools) goto fail;
    if (PyArray_NDIM(tools) != 2 || PyArray_DIM(tools, 1) != 3 || !all_finite(tools)) {
        PyErr_SetString(PyExc_ValueError,
                        "tools must have shape (T, 3): finite (alpha1, alpha2, s) rows");
        goto fail;
    }
    npy_intp T = PyArray_DIM(tools, 0);
    defs = PyMem_Malloc(sizeof(exdex_tool_def) * (size_t)(T > 0 ? T : 1));
    if (!defs) {
        PyErr_NoMemory();
        goto fail;
    }
    const double *td = PyArray_DATA(tools);
    for (npy_intp i = 0; i < T; i++) {
        defs[i].alpha1 = td[3 * i];
        defs[i].alpha2 = td[3 * i + 1];
        defs[i].s = td[3 * i + 2];
        defs[i].plunger = plunger;
    }
    npy_intp dims[3] = {T, pa.p.model == EXDEX_TOOL_PAPER ? 1 : pa.p.n_shapes, pa.p.n_phi};
    out = (PyArrayObject *)PyArray_SimpleNew(3, dims, NPY_DOUBLE);
    if (!out) goto fail;
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = exdex_tool_volumes(&pa.p, (size_t)T, defs, (double *)PyArray_DATA(out));
    Py_END_ALLOW_THREADS
    if (st) {
        set_status_error(module, st, "tool_volumes");
        goto fail;
    }
    result = (PyObject *)out;
    out = NULL;
fail:
    problem_args_free(&pa);
    Py_XDECREF(tools);
    Py_XDECREF(out);
    PyMem_Free(defs);
    return result;
}

PyDoc_STRVAR(optimise_theta_doc,
"optimise_theta(shapes, phi, lo, hi, theta_lo, theta_hi, n_scan=73, xtol=1e-9, alpha1=0.0,\n"
"               s=None, mu=0.0, push=None, model='contact')\n--\n\n"
"Eq. 12: theta* = argmin_theta sum over shapes and phi of the exact volume,\n"
"alpha2 = alpha1 + theta: a scan of n_scan values then GSL Brent. Returns\n"
"(theta, f, iterations, evaluations, bracketed, scan_f (n_scan,)).");

static PyObject *optimise_theta_fn(PyObject *module, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"shapes", "phi", "lo", "hi", "theta_lo", "theta_hi", "n_scan",
                             "xtol", "alpha1", "s", "mu", "push", "model", NULL};
    PyObject *shapes, *phi_obj, *lo_obj, *hi_obj, *tlo_obj, *thi_obj, *nscan_obj = NULL,
             *xtol_obj = NULL, *a1_obj = NULL, *s_obj = NULL, *mu_obj = NULL,
             *push_obj = NULL, *model_obj = NULL, *result = NULL;
    problem_args pa;
    PyArrayObject *scan = NULL;
    double tlo, thi, xtol = 1e-9;
    long n_scan = 73;
    exdex_tool_def tool = {0.0, 0.0, 0, 0.0};
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OOOOOO|OOOOOOO:optimise_theta", kwlist,
                                     &shapes, &phi_obj, &lo_obj, &hi_obj, &tlo_obj, &thi_obj,
                                     &nscan_obj, &xtol_obj, &a1_obj, &s_obj, &mu_obj,
                                     &push_obj, &model_obj))
        return NULL;
    if (get_double(tlo_obj, "theta_lo", &tlo) || get_double(thi_obj, "theta_hi", &thi))
        return NULL;
    if (!isfinite(tlo) || !isfinite(thi) || !(thi > tlo)) {
        PyErr_SetString(PyExc_ValueError, "theta_lo < theta_hi must be finite [rad]");
        return NULL;
    }
    if (nscan_obj && get_long(nscan_obj, "n_scan", 3, 1000000, &n_scan)) return NULL;
    if (xtol_obj && get_double(xtol_obj, "xtol", &xtol)) return NULL;
    if (!(xtol > 0.0) || !isfinite(xtol)) {
        PyErr_SetString(PyExc_ValueError, "xtol must be finite and > 0 [rad]");
        return NULL;
    }
    if (a1_obj && get_double(a1_obj, "alpha1", &tool.alpha1)) return NULL;
    if (s_obj && s_obj != Py_None) {
        if (get_double(s_obj, "s", &tool.s)) return NULL;
        tool.plunger = 1;
    }
    if (!isfinite(tool.alpha1) || !isfinite(tool.s)) {
        PyErr_SetString(PyExc_ValueError, "alpha1 and s must be finite");
        return NULL;
    }
    if (!(fabs(tool.alpha1) <= EXDEX_TOOL_ANGLE_MAX) || !(fabs(tlo) <= EXDEX_TOOL_ANGLE_MAX) ||
        !(fabs(thi) <= EXDEX_TOOL_ANGLE_MAX)) {
        const char *name = !(fabs(tool.alpha1) <= EXDEX_TOOL_ANGLE_MAX) ? "alpha1"
                           : !(fabs(tlo) <= EXDEX_TOOL_ANGLE_MAX)      ? "theta_lo"
                                                                      : "theta_hi";
        char msg[96];   /* PyErr_Format has no %g */
        PyOS_snprintf(msg, sizeof msg, "%s must lie in [-%g, %g] [rad]", name, EXDEX_TOOL_ANGLE_MAX,
                      EXDEX_TOOL_ANGLE_MAX);
        PyErr_SetString(PyExc_ValueError, msg);
        return NULL;
    }
    if (parse_problem(&pa, shapes, phi_obj, lo_obj, hi_obj, mu_obj, push_obj, model_obj))
        return NULL;
    npy_intp dims[1] = {n_scan};
    scan = (PyArrayObject *)PyArray_SimpleNew(1, dims, NPY_DOUBLE);
    if (!scan) goto fail;
    exdex_tool_opt_result res;
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = exdex_tool_optimise_theta(&pa.p, &tool, tlo, thi, (int)n_scan, xtol,
                                   (double *)PyArray_DATA(scan), &res);
    Py_END_ALLOW_THREADS
    if (st) {
        set_status_error(module, st, "optimise_theta");
        goto fail;
    }
    result = Py_BuildValue("(ddiiiO)", res.x[1] - res.x[0], res.f, res.iterations,
                           res.evaluations, res.bracketed, scan);
fail:
    problem_args_free(&pa);
    Py_XDECREF(scan);
    return result;
}

PyDoc_STRVAR(optimise_tool_doc,
"optimise_tool(shapes, phi, lo, hi, x0, free, step, plunger=False, max_iter=2000,\n"
"              size_tol=1e-7, mu=0.0, push=None, model='contact')\n--\n\n"
"GSL nmsimplex2 over the parameters (alpha1, alpha2, s) with free[i] true,\n"
"from x0 (3,) with initial steps step (3,). Returns (x (3,), f, iterations,\n"
"evaluations, converged); converged is False when max_iter was reached before\n"
"the simplex size fell below size_tol (x is then the best point found).\n"
"Raises ConvergenceError if GSL fails otherwise.");

static PyObject *optimise_tool_fn(PyObject *module, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"shapes", "phi", "lo", "hi", "x0", "free", "step", "plunger",
                             "max_iter", "size_tol", "mu", "push", "model", NULL};
    PyObject *shapes, *phi_obj, *lo_obj, *hi_obj, *x0_obj, *free_obj, *step_obj,
             *maxit_obj = NULL, *tol_obj = NULL, *mu_obj = NULL, *push_obj = NULL,
             *model_obj = NULL, *result = NULL;
    int plunger = 0;
    problem_args pa;
    PyArrayObject *x0 = NULL, *fr = NULL, *step = NULL, *xo = NULL;
    long max_iter = 2000;
    double size_tol = 1e-7;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OOOOOOO|pOOOOO:optimise_tool", kwlist,
                                     &shapes, &phi_obj, &lo_obj, &hi_obj, &x0_obj, &free_obj,
                                     &step_obj, &plunger, &maxit_obj, &tol_obj, &mu_obj,
                                     &push_obj, &model_obj))
        return NULL;
    if (maxit_obj && get_long(maxit_obj, "max_iter", 1, 100000000, &max_iter)) return NULL;
    if (tol_obj && get_double(tol_obj, "size_tol", &size_tol)) return NULL;
    if (!(size_tol > 0.0) || !isfinite(size_tol)) {
        PyErr_SetString(PyExc_ValueError, "size_tol must be finite and > 0");
        return NULL;
    }
    if (parse_problem(&pa, shapes, phi_obj, lo_obj, hi_obj, mu_obj, push_obj, model_obj))
        return NULL;
    x0 = as_double_array(x0_obj, "x0", "(3,)");
    if (!x0) goto fail;
    step = as_double_array(step_obj, "step", "(3,)");
    if (!step) goto fail;
    fr = as_double_array(free_obj, "free", "(3,)");
    if (!fr) goto fail;
    if (PyArray_NDIM(x0) != 1 || PyArray_DIM(x0, 0) != 3 || !all_finite(x0)) {
        PyErr_SetString(PyExc_ValueError, "x0 must have shape (3,): finite (alpha1, alpha2, s)");
        goto fail;
    }
    if (PyArray_NDIM(fr) != 1 || PyArray_DIM(fr, 0) != 3) {
        PyErr_SetString(PyExc_ValueError, "free must have shape (3,): flags for (alpha1, alpha2, s)");
        goto fail;
    }
    if (PyArray_NDIM(step) != 1 || PyArray_DIM(step, 0) != 3 || !all_finite(step)) {
        PyErr_SetString(PyExc_ValueError, "step must have shape (3,) with finite entries");
        goto fail;
    }
    const double *xd = PyArray_DATA(x0), *fd = PyArray_DATA(fr), *sd = PyArray_DATA(step);
    int free_param[3], nfree = 0;
    for (int i = 0; i < 3; i++) {
        free_param[i] = fd[i] != 0.0;
        nfree += free_param[i];
        if (free_param[i] && !(sd[i] > 0.0)) {
            PyErr_Format(PyExc_ValueError, "step[%d] must be > 0 for a free parameter", i);
            goto fail;
        }
    }
    if (nfree == 0) {
        PyErr_SetString(PyExc_ValueError, "free must mark at least one parameter");
        goto fail;
    }
    exdex_tool_def start = {xd[0], xd[1], plunger, xd[2]};
    exdex_tool_opt_result res;
    int st;
    Py_BEGIN_ALLOW_THREADS
    st = exdex_tool_optimise(&pa.p, &start, free_param, sd, (int)max_iter, size_tol, &res);
    Py_END_ALLOW_THREADS
    /* the iteration cap (ENOCONV with a finite best point) is reported, not
     * raised: the objective is piecewise smooth and a simplex can wander on
     * its plateaus; the caller sees converged = False */
    int converged = st == EXDEX_OK;
    if (st == EXDEX_ENOCONV && res.iterations >= max_iter && isfinite(res.f)) st = EXDEX_OK;
    if (st) {
        set_status_error(module, st, "optimise_tool");
        goto fail;
    }
    npy_intp dims[1] = {3};
    xo = (PyArrayObject *)PyArray_SimpleNew(1, dims, NPY_DOUBLE);
    if (!xo) goto fail;
    memcpy(PyArray_DATA(xo), res.x, 3 * sizeof(double));
    result = Py_BuildValue("(OdiiO)", xo, res.f, res.iterations, res.evaluations,
                           converged ? Py_True : Py_False);
fail:
    problem_args_free(&pa);
    Py_XDECREF(x0);
    Py_XDECREF(fr);
    Py_XDECREF(step);
    Py_XDECREF(xo);
    return result;
}

/* ---------------------------------------------------------------- module */

static PyMethodDef tool_methods[] = {
    {"volumes", (PyCFunction)(void (*)(void))tool_volumes_fn, METH_VARARGS | METH_KEYWORDS,
     volumes_doc},
    {"paper_rows", (PyCFunction)(void (*)(void))paper_rows_fn, METH_VARARGS | METH_KEYWORDS,
     paper_rows_doc},
    {"contact_rows", (PyCFunction)(void (*)(void))contact_rows_fn,
     METH_VARARGS | METH_KEYWORDS, contact_rows_doc},
    {"tool_rows", (PyCFunction)(void (*)(void))tool_rows_fn, METH_VARARGS | METH_KEYWORDS,
     tool_rows_doc},
    {"tool_volumes", (PyCFunction)(void (*)(void))tool_volumes_fn2,
     METH_VARARGS | METH_KEYWORDS, tool_volumes_doc},
    {"optimise_theta", (PyCFunction)(void (*)(void))optimise_theta_fn,
     METH_VARARGS | METH_KEYWORDS, optimise_theta_doc},
    {"optimise_tool", (PyCFunction)(void (*)(void))optimise_tool_fn,
     METH_VARARGS | METH_KEYWORDS, optimise_tool_doc},
    {NULL, NULL, 0, NULL}};

/* The C enums and limits the Python layer uses. */
static const expy_constant tool_constants[] = {
    {"MAX_ROWS", EXDEX_CONE_MAX_ROWS},
    {"MAX_VERTICES", EXDEX_MAX_VERTICES},
    {"VOLUME_EXACT", EXDEX_VOLUME_EXACT},
    {"VOLUME_GRID", EXDEX_VOLUME_GRID},
    {"VOLUME_QMC", EXDEX_VOLUME_QMC},
    {"TOOL_MODEL_CONTACT", EXDEX_TOOL_CONTACT},
    {"TOOL_MODEL_PAPER", EXDEX_TOOL_PAPER},
    {NULL, 0}};

static int tool_exec(PyObject *module)
{
    PyObject *core;
    tool_state *st = get_state(module);
    if (_import_array() < 0) return -1;
    exdex_init();
    /* one exception class for solver failures in every exdex module */
    core = PyImport_ImportModule("exdex._core");
    if (!core) return -1;
    st->SolverError = PyObject_GetAttrString(core, "SolverError");
    Py_DECREF(core);
    if (!st->SolverError) return -1;
    if (PyModule_AddObjectRef(module, "SolverError", st->SolverError) < 0) return -1;
    /* the former name of the same class */
    if (PyModule_AddObjectRef(module, "ConvergenceError", st->SolverError) < 0) return -1;
    if (expy_add_constants(module, tool_constants) < 0) return -1;
    return 0;
}

static int tool_traverse(PyObject *module, visitproc visit, void *arg)
{
    tool_state *st = get_state(module);
    if (st) Py_VISIT(st->SolverError);
    return 0;
}

static int tool_clear(PyObject *module)
{
    tool_state *st = get_state(module);
    if (st) Py_CLEAR(st->SolverError);
    return 0;
}

static void tool_free(void *module)
{
    tool_clear((PyObject *)module);
}

static PyModuleDef_Slot tool_slots[] = {
    {Py_mod_exec, (void *)tool_exec},
    {0, NULL}};

static struct PyModuleDef tool_module = {
    PyModuleDef_HEAD_INIT,
    "exdex._tool",
    "Assistive-tool design core (paper Section 3): twist-cone rows, exact / grid /\n"
    "QMC cone volumes, and the tool-angle optimisation (Eq. 12).",
    sizeof(tool_state),
    tool_methods,
    tool_slots,
    tool_traverse,
    tool_clear,
    tool_free};

PyMODINIT_FUNC PyInit__tool(void)
{
    return PyModuleDef_Init(&tool_module);
}
