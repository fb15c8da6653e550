/* _common.h -- the helper layer shared by the exdex extension modules
 * (_coremodule.c, _toolmodule.c). Include it after Python.h and
 * numpy/arrayobject.h; every helper is static inline, so each module gets its own
 * copy and no symbol is exported.
 *
 * Calling convention of both modules:
 *   - functions take METH_VARARGS | METH_KEYWORDS (or METH_O for one
 *     argument) and return a new reference, or NULL with an exception set;
 *   - bad arguments raise TypeError (wrong kind) or ValueError (wrong value),
 *     the message naming the parameter and its allowed range;
 *   - a C status other than EXDEX_OK goes through expy_raise_status, the one
 *     mapping of status codes to exceptions:
 *         EXDEX_EINVAL     -> ValueError naming the offending parameter
 *         EXDEX_ENOMEM     -> MemoryError
 *         EXDEX_ENOCONV    -> exdex.SolverError (status 3)
 *         EXDEX_ENONFINITE -> exdex.SolverError (status 4)
 *     exdex.SolverError is created by exdex._core; exdex._tool imports it, so
 *     both modules raise the same class;
 *   - enums of the C API are exported as int constants from one table per
 *     module (expy_add_constants), so Python never hard-codes their values. */
#ifndef EXDEX_PY_COMMON_H
#define EXDEX_PY_COMMON_H

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "exdex.h"

/* ------------------------------------------------------------ exceptions */

/* ValueError with a printf-style message (PyErr_Format has no %g). */
static inline void expy_value_error(const char *fmt, ...)
{
    char buf[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    PyErr_SetString(PyExc_ValueError, buf);
}

/* Raise solver_error(message, status) with the attribute `status` set (and
 * `index` when index >= 0). */
static inline void expy_raise_solver_error(PyObject *solver_error, int status, Py_ssize_t index, const char *message)
{
    PyObject *args, *inst, *o;
    args = Py_BuildValue("(si)", message, status);
    if (!args) return;
    inst = PyObject_Call(solver_error, args, NULL);
    Py_DECREF(args);
    if (!inst) return;
    if ((o = PyLong_FromLong(status))) {
        PyObject_SetAttrString(inst, "status", o);
        Py_DECREF(o);
    }
    if (index >= 0 && (o = PyLong_FromSsize_t(index))) {
        PyObject_SetAttrString(inst, "index", o);
        Py_DECREF(o);
    }
    PyErr_Clear();
    PyErr_SetObject(solver_error, inst);
    Py_DECREF(inst);
}

/* The one status -> exception mapping (see the header comment). `what` names
 * the call ("simulate", "volumes", "batch index 3: simulate", ...), `bad` the
 * offending parameter of an EXDEX_EINVAL (or NULL), `detail` an optional
 * explanation appended to the SolverError message (or NULL). Returns NULL. */
static inline PyObject *expy_raise_status(PyObject *solver_error, int status, const char *what, const char *bad,
                                   const char *detail, Py_ssize_t index)
{
    char msg[768];
    switch (status) {
    case EXDEX_EINVAL:
        if (bad)
            PyErr_Format(PyExc_ValueError, "%s: invalid value of '%s'", what, bad);
        else
            PyErr_Format(PyExc_ValueError, "%s: invalid argument", what);
        break;
    case EXDEX_ENOMEM:
        PyErr_NoMemory();
        break;
    default:
        if (detail && detail[0])
            snprintf(msg, sizeof msg, "%s: %s (%s)", what, exdex_strerror(status), detail);
        else
            snprintf(msg, sizeof msg, "%s: %s", what, exdex_strerror(status));
        expy_raise_solver_error(solver_error, status, index, msg);
    }
    return NULL;
}

/* ------------------------------------------------------------ arguments */

/* obj as a C-contiguous float64 array of any shape; NULL with a TypeError
 * "<name> must be a real array of shape <shape>". Rejects complex input. */
static inline PyArrayObject *expy_doubles(PyObject *obj, const char *name, const char *shape)
{
    PyArrayObject *a;
    if (PyComplex_Check(obj) || PyUnicode_Check(obj) || PyBytes_Check(obj) ||
        (PyArray_Check(obj) && PyArray_ISCOMPLEX((PyArrayObject *)obj))) {
        PyErr_Format(PyExc_TypeError, "%s must be a real array of shape %s, not %.100s", name, shape,
                     Py_TYPE(obj)->tp_name);
        return NULL;
    }
    a = (PyArrayObject *)PyArray_FROMANY(obj, NPY_DOUBLE, 0, 0, NPY_ARRAY_IN_ARRAY);
    if (!a) {
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "%s must be a real array of shape %s", name, shape);
    }
    return a;
}

/* 1 when every element of a float64 array is finite. */
static inline int expy_all_finite(PyArrayObject *a)
{
    const double *d = (const double *)PyArray_DATA(a);
    npy_intp n = PyArray_SIZE(a);
    for (npy_intp i = 0; i < n; i++)
        if (!isfinite(d[i])) return 0;
    return 1;
}

/* A real number (not complex, not a str); -1 with a TypeError naming it. */
static inline int expy_double(PyObject *obj, const char *name, double *out)
{
    double v;
    if (!PyNumber_Check(obj) || PyComplex_Check(obj)) {
        PyErr_Format(PyExc_TypeError, "%s must be a real number, not %.100s", name, Py_TYPE(obj)->tp_name);
        return -1;
    }
    v = PyFloat_AsDouble(obj);
    if (v == -1.0 && PyErr_Occurred()) {
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "%s must be a real number", name);
        return -1;
    }
    *out = v;
    return 0;
}

/* An int (not a bool) in [lo, hi]; -1 with TypeError / ValueError naming it. */
static inline int expy_long(PyObject *obj, const char *name, long lo, long hi, long *out)
{
    int overflow = 0;
    long v;
    if (!PyLong_Check(obj) || PyBool_Check(obj)) {
        PyErr_Format(PyExc_TypeError, "%s must be an int, not %.100s", name, Py_TYPE(obj)->tp_name);
        return -1;
    }
    v = PyLong_AsLongAndOverflow(obj, &overflow);
    if (v == -1 && PyErr_Occurred()) return -1;
    if (overflow || v < lo || v > hi) {
        PyErr_Format(PyExc_ValueError, "%s must be in [%ld, %ld]", name, lo, hi);
        return -1;
    }
    *out = v;
    return 0;
}

/* A str among `names` (NULL-terminated); *out gets values[i]. -1 with
 * TypeError / ValueError listing the allowed names. */
static inline int expy_choice(PyObject *obj, const char *name, const char *const *names, const int *values, int *out)
{
    char allowed[256] = "";
    const char *s;
    size_t used = 0;
    for (int i = 0; names[i]; i++)
        used += (size_t)snprintf(allowed + used, used < sizeof allowed ? sizeof allowed - used : 0, "%s'%s'",
                                 i ? ", " : "", names[i]);
    if (!PyUnicode_Check(obj)) {
        PyErr_Format(PyExc_TypeError, "%s must be a str: one of %s, not %.100s", name, allowed,
                     Py_TYPE(obj)->tp_name);
        return -1;
    }
    s = PyUnicode_AsUTF8(obj);
    if (!s) return -1;
    for (int i = 0; names[i]; i++)
        if (strcmp(s, names[i]) == 0) {
            *out = values[i];
            return 0;
        }
    PyErr_Format(PyExc_ValueError, "%s must be one of %s, not '%s'", name, allowed, s);
    return -1;
}

/* ------------------------------------------------------------ constants */

typedef struct {
    const char *name;
    long value;
} expy_constant;

/* Add every {name, value} of a table ending in {NULL, 0} as an int constant. */
static inline int expy_add_constants(PyObject *module, const expy_constant *table)
{
    for (; table->name; table++)
        if (PyModule_AddIntConstant(module, table->name, table->value) < 0) return -1;
    return 0;
}

#endif /* EXDEX_PY_COMMON_H */
