/* zenros.services.nav.planning._astar: 8-connected cost-aware A* on a uint8 cost grid, in C.
 *
 * search(costs, width, height, steps, start, goal, h_straight, h_diag, budget_s, max_expansions)
 *   costs: a C-contiguous buffer of width*height bytes (row-major, index y*width + x);
 *   steps: 512 int64: the fixed-point cost of a straight step into a cell of each cost
 *          byte, then of a diagonal step (negative: the cell cannot be entered);
 *   start, goal: flat cell indices; h_straight, h_diag: the octile heuristic's integer
 *          coefficients (h = h_straight * max(dx, dy) + h_diag * min(dx, dy));
 *   budget_s: seconds allowed (<= 0: no limit); max_expansions (<= 0: no limit).
 * Returns (status, path, g_goal, expansions): status 0 found, 1 no path, 2 timeout,
 * 3 expansion limit; path: bytes of int32 flat indices from goal back to start.
 *
 * It is astar.py's search_python, step for step (integer arithmetic, the same neighbour
 * order, the same open-list order), so both return the same path; Python is the
 * reference and ZENROS_NAV_PURE=1 turns this module off. The search runs without the GIL.
 *
 * Per-cell state (g, parent, open/closed mark, open-list slot) sits in one 24-byte
 * record, so a neighbour costs one cache line or two, and it is kept between searches (a
 * generation counter replaces clearing it).
 *
 * A cell whose g improves while its entry still waits in a later bucket has that entry
 * updated (in place, or swapped out of the unsorted bucket) instead of leaving a stale
 * one behind: the live entries, hence the order, are those of the Python reference.
 *
 * The open list: cells whose f equals the f last taken from the ordered part go on a
 * stack (each expansion pushes its own in descending (h, cell) order, so the one nearest
 * the goal is on top); the ordered part is a ring of buckets of width 2^BUCKET_SHIFT in
 * f, the current bucket a binary heap by (f, h >> 10, cell), later ones plain arrays
 * heapified when they become current.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define CHECK_EVERY 1024
#define BUCKET_SHIFT 18 /* a quarter of a cell at 2^20 per cell */

enum { FOUND = 0, NO_PATH = 1, TIMEOUT = 2, LIMIT = 3, NOMEM = -2, RING = -3 };

typedef struct {
    int64_t f;
    uint64_t tie; /* (h >> 10, clamped to 32 bits) << 32 | cell */
} Entry;

static inline int
before(const Entry *a, const Entry *b)
{
    return a->f < b->f || (a->f == b->f && a->tie < b->tie);
}

static inline uint64_t
tie_key(int64_t h, int32_t idx)
{
    uint64_t hq = (uint64_t)(h >> 10);
    if (hq > 0xffffffffu)
        hq = 0xffffffffu;
    return (hq << 32) | (uint32_t)idx;
}

typedef struct {
    Entry *a;
    size_t n, cap;
} Heap;

static int
reserve(Heap *hp)
{
    if (hp->n == hp->cap) {
        size_t cap = hp->cap ? hp->cap * 2 : 64;
        Entry *na = realloc(hp->a, cap * sizeof(Entry));
        if (na == NULL)
            return -1;
        hp->a = na;
        hp->cap = cap;
    }
    return 0;
}

static void
sift_down(Entry *a, size_t n, size_t i, Entry e)
{
    for (;;) {
        size_t l = 2 * i + 1;
        if (l >= n)
            break;
        size_t c = l;
        if (l + 1 < n && before(&a[l + 1], &a[l]))
            c = l + 1;
        if (!before(&a[c], &e))
            break;
        a[i] = a[c];
        i = c;
    }
    a[i] = e;
}

static int
heap_push(Heap *hp, Entry e)
{
    if (reserve(hp) < 0)
        return -1;
    size_t i = hp->n++;
    Entry *a = hp->a;
    while (i > 0) {
        size_t p = (i - 1) >> 1;
        if (!before(&e, &a[p]))
            break;
        a[i] = a[p];
        i = p;
    }
    a[i] = e;
    return 0;
}

static Entry
heap_pop(Heap *hp)
{
    Entry top = hp->a[0];
    Entry last = hp->a[--hp->n];
    if (hp->n > 0)
        sift_down(hp->a, hp->n, 0, last);
    return top;
}

static void
heapify(Heap *hp)
{
    for (size_t i = hp->n / 2; i-- > 0;)
        sift_down(hp->a, hp->n, i, hp->a[i]);
}

/* The ordered part. Every entry of the current heap has a smaller f than every entry of
   a later bucket, so its top is the global minimum. With a consistent heuristic a new
   entry's f is at most 2 * max_step above the f being expanded; the ring covers that. */
typedef struct {
    Heap *ring;
    size_t nring, mask;
    int shift;   /* bucket width: 2^shift */
    int64_t cur; /* absolute index of the current bucket */
    size_t count;
} Open;

static int
open_init(Open *o, int64_t max_step)
{
    /* wider buckets when steps are huge (a large cost weight), so the ring stays small;
       the order is exact whatever the width */
    o->shift = BUCKET_SHIFT;
    while (((2 * max_step) >> o->shift) + 4 > (1 << 16))
        o->shift++;
    int64_t need = ((2 * max_step) >> o->shift) + 4;
    size_t n = 64;
    while ((int64_t)n < need)
        n <<= 1;
    if (n > o->nring) {
        Heap *r = realloc(o->ring, n * sizeof(Heap));
        if (r == NULL)
            return -1;
        memset(r + o->nring, 0, (n - o->nring) * sizeof(Heap));
        o->ring = r;
        o->nring = n;
    }
    o->mask = n - 1;
    for (size_t i = 0; i < o->nring; i++)
        o->ring[i].n = 0;
    o->count = 0;
    o->cur = 0;
    return 0;
}

static void
open_free(Open *o)
{
    for (size_t i = 0; i < o->nring; i++)
        free(o->ring[i].a);
    free(o->ring);
    o->ring = NULL;
    o->nring = 0;
}

/* Adds an entry; returns its slot in a later (unsorted) bucket, -1 when it went into
   the current heap, or an error (NOMEM, RING: both below -1). */
static int64_t
open_push(Open *o, int64_t f, uint64_t tie)
{
    Entry e = {f, tie};
    int64_t b = f >> o->shift;
    if (o->count == 0)
        o->cur = b;
    o->count++;
    if (b <= o->cur) {
        if (heap_push(&o->ring[o->cur & (int64_t)o->mask], e) < 0)
            return NOMEM;
        return -1;
    }
    if ((uint64_t)(b - o->cur) > o->mask)
        return RING;
    Heap *hp = &o->ring[b & (int64_t)o->mask];
    if (reserve(hp) < 0)
        return NOMEM;
    hp->a[hp->n] = e;
    return (int64_t)hp->n++;
}

static Entry
open_pop(Open *o)
{
    Heap *hp = &o->ring[o->cur & (int64_t)o->mask];
    while (hp->n == 0) {
        o->cur++;
        hp = &o->ring[o->cur & (int64_t)o->mask];
        heapify(hp);
    }
    o->count--;
    return heap_pop(hp);
}

/* Per-cell state, kept between searches so its pages stay mapped: a cell is open when
   mark == gen, closed when mark == gen + 1, unseen otherwise. */
typedef struct {
    int64_t g;
    int32_t parent;
    uint32_t mark;
    int32_t slot; /* where its entry sits in a later bucket (valid while that bucket is
                     still ahead of the current one), or -1 */
    int32_t pad;
} CellState;

typedef struct {
    size_t n;
    CellState *cell;
    uint32_t gen;
    Open open;
    int32_t *stack;
    size_t sn, scap;
} Workspace;

static Workspace *spare; /* one idle workspace, taken and given back under the GIL */

static void
ws_free(Workspace *ws)
{
    if (ws == NULL)
        return;
    free(ws->cell);
    open_free(&ws->open);
    free(ws->stack);
    free(ws);
}

static Workspace *
ws_take(size_t n)
{
    Workspace *ws = spare;
    spare = NULL;
    if (ws != NULL && ws->n >= n)
        return ws;
    ws_free(ws);
    ws = calloc(1, sizeof(Workspace));
    if (ws == NULL)
        return NULL;
    ws->n = n;
    ws->cell = calloc(n, sizeof(CellState));
    if (ws->cell == NULL) {
        ws_free(ws);
        return NULL;
    }
    return ws;
}

static void
ws_give(Workspace *ws)
{
    if (spare == NULL)
        spare = ws;
    else
        ws_free(ws);
}

static double
now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static inline int64_t
octile(int32_t x, int32_t y, int32_t gx, int32_t gy, int64_t hs, int64_t hd)
{
    int32_t dx = x > gx ? x - gx : gx - x;
    int32_t dy = y > gy ? y - gy : gy - y;
    return dx < dy ? hs * dy + hd * dx : hs * dx + hd * dy;
}

typedef struct {
    const uint8_t *costs;
    int32_t w, h;
    const int64_t *straight, *diag;
    int32_t start, goal;
    int64_t hs, hd;
    double budget;
    long long max_exp;
} Query;

static int
push_stack(Workspace *ws, const int32_t *cells, int n)
{
    if (ws->sn + (size_t)n > ws->scap) {
        size_t cap = ws->scap ? ws->scap * 2 : 4096;
        while (cap < ws->sn + (size_t)n)
            cap *= 2;
        int32_t *st = realloc(ws->stack, cap * sizeof(int32_t));
        if (st == NULL)
            return NOMEM;
        ws->stack = st;
        ws->scap = cap;
    }
    for (int j = 0; j < n; j++)
        ws->stack[ws->sn++] = cells[j];
    return 0;
}

static int
run(const Query *q, Workspace *ws, long long *expansions)
{
    static const int DX[8] = {1, -1, 0, 0, 1, 1, -1, -1};
    static const int DY[8] = {0, 0, 1, -1, 1, -1, 1, -1};
    const int32_t w = q->w, h = q->h;
    int32_t off[8];
    for (int k = 0; k < 8; k++)
        off[k] = DY[k] * w + DX[k];
    int64_t max_step = 0;
    for (int c = 0; c < 256; c++) {
        if (q->straight[c] > max_step)
            max_step = q->straight[c];
        if (q->diag[c] > max_step)
            max_step = q->diag[c];
    }
    if (ws->gen >= UINT32_MAX - 2) {
        for (size_t i = 0; i < ws->n; i++)
            ws->cell[i].mark = 0;
        ws->gen = 0;
    }
    ws->gen += 2;
    const uint32_t OPEN = ws->gen, CLOSED = ws->gen + 1;
    CellState *cell = ws->cell;
    Open *open = &ws->open;
    if (open_init(open, max_step) < 0)
        return NOMEM;
    ws->sn = 0;
    const int32_t gx = q->goal % w, gy = q->goal / w;
    const double inv_w = 1.0 / (double)w;
    const double deadline = q->budget > 0 ? now_s() + q->budget : 0.0;
    long long n_exp = 0;
    int status = NO_PATH, rc;

    cell[q->start].g = 0;
    cell[q->start].parent = -1;
    cell[q->start].mark = OPEN;
    cell[q->start].slot = -1;
    int64_t h0 = octile(q->start % w, q->start / w, gx, gy, q->hs, q->hd);
    if (open_push(open, h0, tie_key(h0, q->start)) < -1)
        return NOMEM;
    int64_t cur_f = -1;
    while (ws->sn > 0 || open->count > 0) {
        int32_t cur;
        if (ws->sn > 0) {
            cur = ws->stack[--ws->sn];
        } else {
            Entry e = open_pop(open);
            cur = (int32_t)(uint32_t)(e.tie & 0xffffffffu);
            cur_f = e.f;
        }
        if (cell[cur].mark == CLOSED)
            continue; /* a stale entry: the cell was closed with a better g */
        cell[cur].mark = CLOSED;
        if (cur == q->goal) {
            status = FOUND;
            break;
        }
        n_exp++;
        if (q->max_exp > 0 && n_exp > q->max_exp) {
            status = LIMIT;
            break;
        }
        if (deadline > 0 && (n_exp % CHECK_EVERY) == 0 && now_s() > deadline) {
            status = TIMEOUT;
            break;
        }
        int32_t y = (int32_t)((double)cur * inv_w); /* cur / w without a division ... */
        if ((int64_t)y * w > cur)
            y--;
        else if ((int64_t)(y + 1) * w <= cur)
            y++; /* ... corrected for rounding */
        const int32_t x = cur - y * w;
        const int inner = x > 0 && y > 0 && x < w - 1 && y < h - 1;
        const int64_t gc = cell[cur].g;
        int64_t same_h[8];
        int32_t same_i[8];
        int ns = 0;
        for (int k = 0; k < 8; k++) {
            const int32_t nx = x + DX[k], ny = y + DY[k];
            if (!inner && (nx < 0 || ny < 0 || nx >= w || ny >= h))
                continue;
            const int32_t nb = cur + off[k];
            CellState *cs = &cell[nb];
            const uint32_t mk = cs->mark;
            if (mk == CLOSED)
                continue;
            const int64_t step = k < 4 ? q->straight[q->costs[nb]] : q->diag[q->costs[nb]];
            if (step < 0)
                continue;
            const int64_t ng = gc + step;
            if (mk == OPEN && ng >= cs->g)
                continue;
            const int64_t hn = octile(nx, ny, gx, gy, q->hs, q->hd);
            const int64_t fn = ng + hn;
            if (mk == OPEN && cs->slot >= 0) {
                /* a better g for a cell whose entry waits in a later bucket: update
                   that entry instead of leaving it behind as a stale one */
                const int64_t b_old = (cs->g + hn) >> open->shift;
                if (b_old > open->cur) {
                    Heap *bk = &open->ring[b_old & (int64_t)open->mask];
                    if (fn != cur_f && (fn >> open->shift) == b_old) {
                        bk->a[cs->slot].f = fn; /* same bucket: in place */
                        cs->g = ng;
                        cs->parent = cur;
                        continue;
                    }
                    Entry last = bk->a[--bk->n]; /* otherwise take it out */
                    if ((size_t)cs->slot != bk->n) {
                        bk->a[cs->slot] = last;
                        cell[(int32_t)(uint32_t)(last.tie & 0xffffffffu)].slot = cs->slot;
                    }
                    open->count--;
                }
            }
            cs->g = ng;
            cs->parent = cur;
            cs->mark = OPEN;
            cs->slot = -1;
            if (fn == cur_f) {
                int j = ns++; /* keep same_* in descending (h, cell) order */
                while (j > 0 && (same_h[j - 1] < hn || (same_h[j - 1] == hn && same_i[j - 1] < nb))) {
                    same_h[j] = same_h[j - 1];
                    same_i[j] = same_i[j - 1];
                    j--;
                }
                same_h[j] = hn;
                same_i[j] = nb;
            } else {
                const int64_t slot = open_push(open, fn, tie_key(hn, nb));
                if (slot < -1)
                    return (int)slot;
                cs->slot = (int32_t)slot;
            }
        }
        if (ns > 0 && (rc = push_stack(ws, same_i, ns)) < 0)
            return rc;
    }
    *expansions = n_exp;
    return status;
}

static PyObject *
search(PyObject *Py_UNUSED(self), PyObject *args)
{
    Py_buffer cb, sb;
    Py_ssize_t w, h, start, goal;
    long long hs, hd, max_exp;
    double budget;
    if (!PyArg_ParseTuple(args, "y*nny*nnLLdL", &cb, &w, &h, &sb, &start, &goal, &hs, &hd,
                          &budget, &max_exp))
        return NULL;
    PyObject *result = NULL;
    Workspace *ws = NULL;
    if (w <= 0 || h <= 0 || w > INT32_MAX / h || w * h != cb.len) {
        PyErr_SetString(PyExc_ValueError, "costs must hold width*height bytes");
        goto done;
    }
    if (sb.len != 512 * (Py_ssize_t)sizeof(int64_t)) {
        PyErr_SetString(PyExc_ValueError, "steps must hold 512 int64");
        goto done;
    }
    if (start < 0 || start >= w * h || goal < 0 || goal >= w * h) {
        PyErr_SetString(PyExc_ValueError, "start and goal must be cells of the grid");
        goto done;
    }
    if (hs < 0 || hd < 0) {
        PyErr_SetString(PyExc_ValueError, "heuristic coefficients must be >= 0");
        goto done;
    }
    ws = ws_take((size_t)(w * h));
    if (ws == NULL) {
        PyErr_NoMemory();
        goto done;
    }
    int64_t steps[512];
    memcpy(steps, sb.buf, sizeof(steps));
    Query q = {(const uint8_t *)cb.buf, (int32_t)w, (int32_t)h, steps, steps + 256,
               (int32_t)start, (int32_t)goal, hs, hd, budget, max_exp};
    long long expansions = 0;
    int status;
    Py_BEGIN_ALLOW_THREADS
    status = run(&q, ws, &expansions);
    Py_END_ALLOW_THREADS
    if (status == NOMEM) {
        PyErr_NoMemory();
    } else if (status == RING) {
        PyErr_SetString(PyExc_RuntimeError, "the heuristic is not consistent with the step costs");
    } else {
        PyObject *path;
        long long g_goal = 0;
        const CellState *cell = ws->cell;
        if (status == FOUND) {
            Py_ssize_t len = 0;
            for (int32_t c = (int32_t)goal; c != -1; c = cell[c].parent)
                len++;
            path = PyBytes_FromStringAndSize(NULL, len * (Py_ssize_t)sizeof(int32_t));
            if (path != NULL) {
                int32_t *out = (int32_t *)PyBytes_AS_STRING(path);
                Py_ssize_t i = 0;
                for (int32_t c = (int32_t)goal; c != -1; c = cell[c].parent)
                    out[i++] = c;
            }
            g_goal = (long long)cell[goal].g;
        } else {
            path = PyBytes_FromStringAndSize(NULL, 0);
        }
        if (path != NULL)
            result = Py_BuildValue("(iNLL)", status, path, g_goal, (long long)expansions);
    }
    ws_give(ws);
done:
    PyBuffer_Release(&cb);
    PyBuffer_Release(&sb);
    return result;
}

static PyMethodDef methods[] = {
    {"search", search, METH_VARARGS,
     "search(costs, width, height, steps, start, goal, h_straight, h_diag, budget_s,"
     " max_expansions) -> (status, path_bytes, g_goal, expansions)"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_astar", "8-connected cost-aware A* (see astar.py)", -1, methods,
    NULL, NULL, NULL, NULL,
};

PyMODINIT_FUNC
PyInit__astar(void)
{
    return PyModule_Create(&module);
}
