/* zenros.services.nav.costmap._edt: the inflation layer's distance transform, in C.
 *
 * squared_distance(sources, width, height, radius) -> bytes of int32 (height * width)
 *   sources: a C-contiguous buffer of width*height bytes, nonzero where a cell is a
 *   source (lethal). Each output cell holds the exact squared Euclidean distance in cells
 *   to the nearest source when that is at most radius^2, and a value above radius^2
 *   otherwise: inflation.py's squared_distance, computed with a column pass (vertical
 *   distance, capped at radius + 1) and Felzenszwalb & Huttenlocher's lower envelope of
 *   parabolas along each row, O(cells). inflation.py's numpy code is the reference;
 *   ZENROS_NAV_PURE=1 turns this module off. Runs without the GIL.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <stdint.h>
#include <stdlib.h>

static void
transform(const uint8_t *src, int32_t w, int32_t h, int32_t radius, int32_t *out,
          int32_t *v, double *z, int64_t *f)
{
    const int32_t big = radius + 1;
    /* column pass, row by row: out[y][x] = min(vertical distance to a source, big);
       v holds the row of the last source seen in each column */
    for (int32_t x = 0; x < w; x++)
        v[x] = -2 * big - 1;
    for (int32_t y = 0; y < h; y++) {
        const uint8_t *s = &src[(size_t)y * w];
        int32_t *o = &out[(size_t)y * w];
        for (int32_t x = 0; x < w; x++) {
            if (s[x])
                v[x] = y;
            int32_t d = y - v[x];
            o[x] = d < big ? d : big;
        }
    }
    for (int32_t x = 0; x < w; x++)
        v[x] = h + 2 * big + 1;
    for (int32_t y = h - 1; y >= 0; y--) {
        const uint8_t *s = &src[(size_t)y * w];
        int32_t *o = &out[(size_t)y * w];
        for (int32_t x = 0; x < w; x++) {
            if (s[x])
                v[x] = y;
            int32_t d = v[x] - y;
            if (d < o[x])
                o[x] = d;
        }
    }
    /* row pass: out[y][x] = min over q of (x - q)^2 + g(q)^2 */
    for (int32_t y = 0; y < h; y++) {
        int32_t *row = &out[(size_t)y * w];
        for (int32_t q = 0; q < w; q++)
            f[q] = (int64_t)row[q] * row[q];
        int32_t k = 0;
        v[0] = 0;
        z[0] = -1e300;
        z[1] = 1e300;
        for (int32_t q = 1; q < w; q++) {
            double s;
            for (;;) {
                int32_t p = v[k];
                s = ((double)(f[q] + (int64_t)q * q) - (double)(f[p] + (int64_t)p * p)) /
                    (2.0 * (double)(q - p));
                if (s <= z[k] && k > 0)
                    k--;
                else
                    break;
            }
            if (s <= z[k]) { /* k == 0: q replaces the first parabola */
                v[0] = q;
                z[0] = -1e300;
                z[1] = 1e300;
                continue;
            }
            k++;
            v[k] = q;
            z[k] = s;
            z[k + 1] = 1e300;
        }
        k = 0;
        for (int32_t q = 0; q < w; q++) {
            while (z[k + 1] < (double)q)
                k++;
            int64_t dq = q - v[k];
            int64_t d = dq * dq + f[v[k]];
            row[q] = d > INT32_MAX ? INT32_MAX : (int32_t)d;
        }
    }
}

static PyObject *
squared_distance(PyObject *Py_UNUSED(self), PyObject *args)
{
    Py_buffer sb;
    Py_ssize_t w, h, radius;
    if (!PyArg_ParseTuple(args, "y*nnn", &sb, &w, &h, &radius))
        return NULL;
    PyObject *out = NULL;
    if (w <= 0 || h <= 0 || w > INT32_MAX / h || w * h != sb.len) {
        PyErr_SetString(PyExc_ValueError, "sources must hold width*height bytes");
        goto done;
    }
    if (radius < 0 || radius > 1 << 20) {
        PyErr_SetString(PyExc_ValueError, "radius must be in 0 .. 2^20");
        goto done;
    }
    out = PyBytes_FromStringAndSize(NULL, w * h * (Py_ssize_t)sizeof(int32_t));
    if (out == NULL)
        goto done;
    int32_t *v = malloc((size_t)w * sizeof(int32_t));
    double *z = malloc(((size_t)w + 1) * sizeof(double));
    int64_t *f = malloc((size_t)w * sizeof(int64_t));
    if (v == NULL || z == NULL || f == NULL) {
        free(v);
        free(z);
        free(f);
        Py_CLEAR(out);
        PyErr_NoMemory();
        goto done;
    }
    int32_t *o = (int32_t *)PyBytes_AS_STRING(out);
    Py_BEGIN_ALLOW_THREADS
    transform((const uint8_t *)sb.buf, (int32_t)w, (int32_t)h, (int32_t)radius, o, v, z, f);
    Py_END_ALLOW_THREADS
    free(v);
    free(z);
    free(f);
done:
    PyBuffer_Release(&sb);
    return out;
}

static PyMethodDef methods[] = {
    {"squared_distance", squared_distance, METH_VARARGS,
     "squared_distance(sources, width, height, radius) -> bytes of int32"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_edt", "the inflation layer's distance transform (see inflation.py)",
    -1, methods, NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC
PyInit__edt(void)
{
    return PyModule_Create(&module);
}
