/* zenros.services.chassis._march: the laser's ray march through the map, in C.
 *
 * march(kind, width, height, px, py, dx, dy, limit, res, out) -> None
 *   kind: C-contiguous bytes, width*height, the laser's padded grid (laser.py): 0 free,
 *   1 solid, 2 outside (a ring of outside cells surrounds the map). px, py: the laser in
 *   cell units of that grid. dx, dy: float64 unit directions, one per beam. out: a
 *   writable float32 buffer, one per beam, set to the range in metres (cell units times
 *   res) to the ray's entry into the first solid cell it crosses, or inf where it first
 *   meets an outside cell or crosses more than `limit` cells of distance. A laser inside a
 *   solid or outside cell gives inf on every beam, as laser.py's numpy march does.
 *
 * Each beam is an exact grid traversal (Amanatides & Woo's DDA): it visits every cell the
 * ray passes through, in order, so it never misses a corner the numpy march's half-cell
 * sampling may. laser.py's numpy march is the reference; ZENROS_CHASSIS_PURE=1 turns this
 * module off. Runs without the GIL.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdint.h>

static double
beam(const uint8_t *kind, Py_ssize_t w, Py_ssize_t h, double px, double py, double dx,
     double dy, double limit)
{
    Py_ssize_t cx = (Py_ssize_t)floor(px), cy = (Py_ssize_t)floor(py);
    const Py_ssize_t sx = dx > 0 ? 1 : -1, sy = dy > 0 ? 1 : -1;
    /* ray parameter (cells) at the next vertical / horizontal cell boundary, and per cell */
    const double ddx = dx != 0 ? fabs(1.0 / dx) : INFINITY;
    const double ddy = dy != 0 ? fabs(1.0 / dy) : INFINITY;
    double tx = dx > 0 ? (cx + 1 - px) * ddx : dx < 0 ? (px - cx) * ddx : INFINITY;
    double ty = dy > 0 ? (cy + 1 - py) * ddy : dy < 0 ? (py - cy) * ddy : INFINITY;
    for (;;) {
        double t;
        if (tx < ty) {
            t = tx;
            tx += ddx;
            cx += sx;
        } else {
            t = ty;
            ty += ddy;
            cy += sy;
        }
        if (t > limit || cx < 0 || cy < 0 || cx >= w || cy >= h)
            return INFINITY;
        uint8_t k = kind[cy * w + cx];
        if (k == 1)
            return t;
        if (k != 0)
            return INFINITY;
    }
}

static PyObject *
march(PyObject *Py_UNUSED(self), PyObject *args)
{
    Py_buffer kb, xb, yb, ob;
    Py_ssize_t w, h;
    double px, py, limit, res;
    if (!PyArg_ParseTuple(args, "y*nnddy*y*ddw*", &kb, &w, &h, &px, &py, &xb, &yb, &limit,
                          &res, &ob))
        return NULL;
    PyObject *ret = NULL;
    const Py_ssize_t n = xb.len / (Py_ssize_t)sizeof(double);
    if (w <= 0 || h <= 0 || w > PY_SSIZE_T_MAX / h || w * h != kb.len) {
        PyErr_SetString(PyExc_ValueError, "kind must hold width*height bytes");
        goto done;
    }
    if (xb.len != yb.len || xb.len % (Py_ssize_t)sizeof(double) != 0 ||
        ob.len != n * (Py_ssize_t)sizeof(float)) {
        PyErr_SetString(PyExc_ValueError,
                        "dx and dy must be float64 and out float32, one per beam each");
        goto done;
    }
    const uint8_t *kind = (const uint8_t *)kb.buf;
    const double *dx = (const double *)xb.buf, *dy = (const double *)yb.buf;
    float *out = (float *)ob.buf;
    const int inside = px >= 0 && py >= 0 && px < (double)w && py < (double)h &&
                       kind[(Py_ssize_t)py * w + (Py_ssize_t)px] == 0;
    Py_BEGIN_ALLOW_THREADS
    for (Py_ssize_t i = 0; i < n; i++) {
        double t = inside ? beam(kind, w, h, px, py, dx[i], dy[i], limit) : INFINITY;
        out[i] = isfinite(t) ? (float)(t * res) : INFINITY;
    }
    Py_END_ALLOW_THREADS
    ret = Py_None;
    Py_INCREF(ret);
done:
    PyBuffer_Release(&kb);
    PyBuffer_Release(&xb);
    PyBuffer_Release(&yb);
    PyBuffer_Release(&ob);
    return ret;
}

static PyMethodDef methods[] = {
    {"march", march, METH_VARARGS,
     "march(kind, width, height, px, py, dx, dy, limit, res, out) -> None"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_march", "the laser's ray march through the map (see laser.py)",
    -1, methods, NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC
PyInit__march(void)
{
    return PyModule_Create(&module);
}
