/* zenros.services.nav.planner._astar: 8-connected cost-aware A* on a uint8 cost grid, in C.
 *
 * search(costs, width, height, mult, start, goal, h_scale, budget_s, max_expansions)
 *   costs: a C-contiguous buffer of width*height bytes (row-major, index y*width + x);
 *   mult:  a buffer of 256 doubles, the traversal multiplier of each cost byte
 *          (a negative or infinite entry marks the cost as impassable);
 *   start, goal: flat cell indices; h_scale: the octile heuristic's factor;
 *   budget_s: seconds allowed (<= 0: no limit); max_expansions (<= 0: no limit).
 * Returns (status, path, g_goal, expansions): status 0 found, 1 no path, 2 timeout,
 * 3 expansion limit; path: bytes of int32 flat indices from goal back to start.
 *
 * It is astar.py's search, step for step: the same step costs (mult[c] times 1 or
 * sqrt 2, c the cost of the cell entered), the same heuristic arithmetic, the same
 * neighbour order and the same total order of the open list (f, then h, then index),
 * so both return the same path. Python is the reference; ZENROS_NAV_PURE=1 turns this
 * module off. The search runs without the GIL.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

typedef struct {
    double f;
    double h;
    int32_t idx;
} Entry;

static inline int
before(const Entry *a, const Entry *b)
{
    if (a->f != b->f)
        return a->f < b->f;
    if (a->h != b->h)
        return a->h < b->h;
    return a->idx < b->idx;
}

typedef struct {
    Entry *a;
    size_t n, cap;
} Heap;

static int
heap_push(Heap *hp, double f, double h, int32_t idx)
{
    if (hp->n == hp->cap) {
        size_t cap = hp->cap ? hp->cap * 2 : 4096;
        Entry *na = realloc(hp->a, cap * sizeof(Entry));
        if (na == NULL)
            return -1;
        hp->a = na;
        hp->cap = cap;
    }
    Entry e = {f, h, idx};
    size_t i = hp->n++;
    while (i > 0) {
        size_t p = (i - 1) >> 1;
        if (!before(&e, &hp->a[p]))
            break;
        hp->a[i] = hp->a[p];
        i = p;
    }
    hp->a[i] = e;
    return 0;
}

static Entry
heap_pop(Heap *hp)
{
    Entry top = hp->a[0];
    Entry last = hp->a[--hp->n];
    size_t n = hp->n, i = 0;
    for (;;) {
        size_t l = 2 * i + 1;
        if (l >= n)
            break;
        size_t c = l;
        if (l + 1 < n && before(&hp->a[l + 1], &hp->a[l]))
            c = l + 1;
        if (!before(&hp->a[c], &last))
            break;
        hp->a[i] = hp->a[c];
        i = c;
    }
    if (n > 0)
        hp->a[i] = last;
    return top;
}

static double
now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

#define SQRT2 1.4142135623730951
#define CHECK_EVERY 1024

enum { FOUND = 0, NO_PATH = 1, TIMEOUT = 2, LIMIT = 3, NOMEM = -1 };

/* the octile distance between two cells, scaled (astar.py's _octile) */
static inline double
octile(int32_t x, int32_t y, int32_t gx, int32_t gy, double scale)
{
    int32_t dx = x > gx ? x - gx : gx - x;
    int32_t dy = y > gy ? y - gy : gy - y;
    int32_t lo = dx < dy ? dx : dy, hi = dx < dy ? dy : dx;
    return scale * ((double)hi + (SQRT2 - 1.0) * (double)lo);
}

static int
run(const uint8_t *costs, int32_t w, int32_t h, const double *mult, int32_t start, int32_t goal,
    double h_scale, double budget, long long max_exp, int32_t *parent, double *g, uint8_t *state,
    long long *expansions)
{
    static const int DX[8] = {1, -1, 0, 0, 1, 1, -1, -1};
    static const int DY[8] = {0, 0, 1, -1, 1, -1, 1, -1};
    Heap hp = {NULL, 0, 0};
    int32_t gx = goal % w, gy = goal / w;
    double deadline = budget > 0 ? now_s() + budget : 0.0;
    long long n_exp = 0;
    int status = NO_PATH;

    g[start] = 0.0;
    parent[start] = -1;
    state[start] = 1;
    double h0 = octile(start % w, start / w, gx, gy, h_scale);
    if (heap_push(&hp, 0.0 + h0, h0, start) < 0)
        return NOMEM;
    while (hp.n > 0) {
        Entry e = heap_pop(&hp);
        int32_t cur = e.idx;
        if (state[cur] == 2)
            continue; /* a stale entry: the cell was closed with a better g */
        state[cur] = 2;
        if (cur == goal) {
            status = FOUND;
            break;
        }
        n_exp++;
        if (max_exp > 0 && n_exp > max_exp) {
            status = LIMIT;
            break;
        }
        if (deadline > 0 && (n_exp % CHECK_EVERY) == 0 && now_s() > deadline) {
            status = TIMEOUT;
            break;
        }
        int32_t x = cur % w, y = cur / w;
        double gc = g[cur];
        for (int k = 0; k < 8; k++) {
            int32_t nx = x + DX[k], ny = y + DY[k];
            if (nx < 0 || ny < 0 || nx >= w || ny >= h)
                continue;
            int32_t nb = ny * w + nx;
            if (state[nb] == 2)
                continue;
            double m = mult[costs[nb]];
            if (!(m >= 0.0) || isinf(m))
                continue;
            double step = k < 4 ? m : m * SQRT2;
            double ng = gc + step;
            if (state[nb] == 1 && !(ng < g[nb]))
                continue;
            g[nb] = ng;
            parent[nb] = cur;
            state[nb] = 1;
            double hn = octile(nx, ny, gx, gy, h_scale);
            if (heap_push(&hp, ng + hn, hn, nb) < 0) {
                free(hp.a);
                return NOMEM;
            }
        }
    }
    free(hp.a);
    *expansions = n_exp;
    return status;
}

static PyObject *
search(PyObject *self, PyObject *args)
{
    Py_buffer cb, mb;
    Py_ssize_t w, h, start, goal;
    double h_scale, budget;
    long long max_exp;
    if (!PyArg_ParseTuple(args, "y*nny*nnddL", &cb, &w, &h, &mb, &start, &goal, &h_scale,
                          &budget, &max_exp))
        return NULL;
    PyObject *result = NULL;
    if (w <= 0 || h <= 0 || w * h != cb.len || w * h > INT32_MAX) {
        PyErr_SetString(PyExc_ValueError, "costs must hold width*height bytes");
        goto done;
    }
    if (mb.len != 256 * (Py_ssize_t)sizeof(double)) {
        PyErr_SetString(PyExc_ValueError, "mult must hold 256 doubles");
        goto done;
    }
    if (start < 0 || start >= w * h || goal < 0 || goal >= w * h) {
        PyErr_SetString(PyExc_ValueError, "start and goal must be cells of the grid");
        goto done;
    }
    size_t n = (size_t)(w * h);
    int32_t *parent = malloc(n * sizeof(int32_t));
    double *g = malloc(n * sizeof(double));
    uint8_t *state = calloc(n, 1);
    if (parent == NULL || g == NULL || state == NULL) {
        free(parent);
        free(g);
        free(state);
        PyErr_NoMemory();
        goto done;
    }
    double mult[256];
    memcpy(mult, mb.buf, sizeof(mult));
    long long expansions = 0;
    int status;
    Py_BEGIN_ALLOW_THREADS
    status = run((const uint8_t *)cb.buf, (int32_t)w, (int32_t)h, mult, (int32_t)start,
                 (int32_t)goal, h_scale, budget, max_exp, parent, g, state, &expansions);
    Py_END_ALLOW_THREADS
    if (status == NOMEM) {
        PyErr_NoMemory();
    } else {
        PyObject *path;
        double g_goal = 0.0;
        if (status == FOUND) {
            Py_ssize_t len = 0;
            for (int32_t c = (int32_t)goal; c != -1; c = parent[c])
                len++;
            path = PyBytes_FromStringAndSize(NULL, len * (Py_ssize_t)sizeof(int32_t));
            if (path != NULL) {
                int32_t *out = (int32_t *)PyBytes_AS_STRING(path);
                Py_ssize_t i = 0;
                for (int32_t c = (int32_t)goal; c != -1; c = parent[c])
                    out[i++] = c;
            }
            g_goal = g[goal];
        } else {
            path = PyBytes_FromStringAndSize(NULL, 0);
        }
        if (path != NULL)
            result = Py_BuildValue("(iNdL)", status, path, g_goal, expansions);
    }
    free(parent);
    free(g);
    free(state);
done:
    PyBuffer_Release(&cb);
    PyBuffer_Release(&mb);
    return result;
}

static PyMethodDef methods[] = {
    {"search", search, METH_VARARGS,
     "search(costs, width, height, mult, start, goal, h_scale, budget_s, max_expansions)"
     " -> (status, path_bytes, g_goal, expansions)"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_astar", "8-connected cost-aware A* (see astar.py)", -1, methods,
};

PyMODINIT_FUNC
PyInit__astar(void)
{
    return PyModule_Create(&module);
}
