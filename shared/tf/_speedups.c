/* zenros.tf._speedups: the two hot paths of the TF buffer, in C.
 *
 * - evaluate(src_pre, src, tgt_pre, tgt, t): a cached Chain at time t (chain.py's
 *   Chain.evaluate and _accumulate, the same arithmetic in the same order).
 * - Inserter: FrameStore.set_transform's in-order hot path (a newer sample for a link
 *   whose samples all share this parent), with everything else handed to the Python
 *   method it is given (refusals, new links, re-parenting, out of order, waiters...).
 *
 * The Python code is the reference: both are tested against each other, and
 * ZENROS_TF_PURE=1 turns this module off. Message fields are read at the member
 * offsets of the exact types bound by bind(); any other type takes the Python path.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <structmember.h>
#include <math.h>

typedef struct {
    double x, y, z, qx, qy, qz, qw;
} Tf7;

/* TimeCache deletes its pruned prefix once it is this long and no shorter than the rest
   (cache.COMPACT_AT; accel.py uses this module only if the two agree). */
#define COMPACT_AT 32

static PyObject *str_segment;
static PyObject *str_vals;

/* ------------------------------------------------------------------ small helpers */

static int
read7(PyObject *tup, Tf7 *o)
{
    double v[7];
    if (!PyTuple_Check(tup) || PyTuple_GET_SIZE(tup) != 7) {
        PyErr_SetString(PyExc_TypeError, "a transform is a 7-tuple");
        return -1;
    }
    for (int k = 0; k < 7; k++) {
        PyObject *it = PyTuple_GET_ITEM(tup, k);
        v[k] = PyFloat_CheckExact(it) ? PyFloat_AS_DOUBLE(it) : PyFloat_AsDouble(it);
        if (v[k] == -1.0 && PyErr_Occurred())
            return -1;
    }
    o->x = v[0]; o->y = v[1]; o->z = v[2];
    o->qx = v[3]; o->qy = v[4]; o->qz = v[5]; o->qw = v[6];
    return 0;
}

static PyObject *
tuple7(const Tf7 *a)
{
    PyObject *t = PyTuple_New(7);
    if (t == NULL)
        return NULL;
    double v[7] = {a->x, a->y, a->z, a->qx, a->qy, a->qz, a->qw};
    for (int k = 0; k < 7; k++) {
        PyObject *f = PyFloat_FromDouble(v[k]);
        if (f == NULL) {
            Py_DECREF(t);
            return NULL;
        }
        PyTuple_SET_ITEM(t, k, f);
    }
    return t;
}

/* a ∘ b (rigid.compose) */
static inline Tf7
compose(const Tf7 *a, const Tf7 *b)
{
    double qx = a->qx, qy = a->qy, qz = a->qz, qw = a->qw;
    double tx = 2.0 * (qy * b->z - qz * b->y);
    double ty = 2.0 * (qz * b->x - qx * b->z);
    double tz = 2.0 * (qx * b->y - qy * b->x);
    Tf7 r;
    r.x = a->x + b->x + qw * tx + qy * tz - qz * ty;
    r.y = a->y + b->y + qw * ty + qz * tx - qx * tz;
    r.z = a->z + b->z + qw * tz + qx * ty - qy * tx;
    r.qx = qw * b->qx + qx * b->qw + qy * b->qz - qz * b->qy;
    r.qy = qw * b->qy - qx * b->qz + qy * b->qw + qz * b->qx;
    r.qz = qw * b->qz + qx * b->qy - qy * b->qx + qz * b->qw;
    r.qw = qw * b->qw - qx * b->qx - qy * b->qy - qz * b->qz;
    return r;
}

static inline int
as_ll(PyObject *o, long long *out)
{
    long long v = PyLong_AsLongLong(o);
    if (v == -1 && PyErr_Occurred())
        return -1;
    *out = v;
    return 0;
}

/* bisect.bisect_right (side 1) or bisect_left (side 0) on a list of ints; -1 on error */
static Py_ssize_t
bisect(PyObject *lst, long long t, Py_ssize_t lo, int right)
{
    Py_ssize_t hi = PyList_GET_SIZE(lst);
    while (lo < hi) {
        Py_ssize_t mid = (lo + hi) / 2;
        long long v;
        if (as_ll(PyList_GET_ITEM(lst, mid), &v) < 0)
            return -1;
        if (right ? t < v : t <= v)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

PyDoc_STRVAR(latest_doc,
"latest(dyn) -> int\n\n"
"The smallest last stamp of the non-empty stamp lists in dyn (0 if dyn is empty).");

static PyObject *
latest(PyObject *self, PyObject *dyn)
{
    if (!PyList_CheckExact(dyn)) {
        PyErr_SetString(PyExc_TypeError, "latest takes a list of stamp lists");
        return NULL;
    }
    Py_ssize_t n = PyList_GET_SIZE(dyn);
    if (n == 0)
        return PyLong_FromLong(0);
    PyObject *best = NULL;
    long long bv = 0;
    for (Py_ssize_t k = 0; k < n; k++) {
        PyObject *s = PyList_GET_ITEM(dyn, k);
        if (!PyList_CheckExact(s) || PyList_GET_SIZE(s) == 0) {
            PyErr_SetString(PyExc_ValueError, "latest needs non-empty stamp lists");
            return NULL;
        }
        PyObject *last = PyList_GET_ITEM(s, PyList_GET_SIZE(s) - 1);
        long long v;
        if (as_ll(last, &v) < 0)
            return NULL;
        if (best == NULL || v < bv) {
            best = last;
            bv = v;
        }
    }
    Py_INCREF(best);
    return best;
}

/* ------------------------------------------------------------------ bound types */

/* A field of an exact type, read at its member offset (borrowed; NULL if unset). */
typedef struct {
    PyTypeObject *type;
    Py_ssize_t off;
} Field;

#define GET(obj, f) (Py_TYPE(obj) == (f).type ? *(PyObject **)((char *)(obj) + (f).off) : NULL)

static Field ts_header, ts_child, ts_transform;  /* TransformStamped */
static Field h_stamp, h_frame;                     /* Header */
static Field tm_sec, tm_nanosec;                   /* Time */
static Field tr_translation, tr_rotation;          /* Transform */
static Field v_x, v_y, v_z;                        /* Vector3 */
static Field q_x, q_y, q_z, q_w;                   /* Quaternion */
static Field c_stamps, c_vals, c_parents, c_segs, c_parent, c_lo;  /* TimeCache */
static int bound = 0;

static PyObject *str_lo;

/* A cache's ``lo`` (its oldest live sample's index); -1 on error. */
static Py_ssize_t
cache_lo(PyObject *cache)
{
    PyObject *v = bound ? GET(cache, c_lo) : NULL;
    long long lo;
    if (v != NULL) {
        if (as_ll(v, &lo) < 0)
            return -1;
    } else {
        v = PyObject_GetAttr(cache, str_lo);
        if (v == NULL)
            return -1;
        int rc = as_ll(v, &lo);
        Py_DECREF(v);
        if (rc < 0)
            return -1;
    }
    if (lo < 0) {
        PyErr_SetString(PyExc_ValueError, "negative cache index");
        return -1;
    }
    return (Py_ssize_t)lo;
}

/* ------------------------------------------------------------------ evaluate */

/* bisect_right(stamps, t, lo) for stamps[lo] = first <= t < last = stamps[n - 1]: starts
   where t would be if the samples were evenly spaced (a steady broadcaster), steps a few
   samples from there, and bisects only if that does not find it. -1 on error. */
static Py_ssize_t
locate(PyObject *stamps, long long t, Py_ssize_t lo, Py_ssize_t n, long long first,
       long long last)
{
    Py_ssize_t g = lo + (Py_ssize_t)((double)(t - first) / (double)(last - first) * (n - 1 - lo));
    if (g < lo)
        g = lo;
    if (g > n - 2)
        g = n - 2;
    long long v;
    if (as_ll(PyList_GET_ITEM(stamps, g), &v) < 0)
        return -1;
    if (v <= t) { /* forward: the first index after g with a stamp > t */
        for (int step = 0; step < 4; step++) {
            if (as_ll(PyList_GET_ITEM(stamps, g + 1), &v) < 0)
                return -1;
            if (v > t)
                return g + 1;
            g++; /* g + 1 <= n - 1, and stamps[n - 1] = last > t */
        }
        return bisect(stamps, t, g + 1, 1);
    }
    for (int step = 0; step < 4; step++) { /* backward: stamps[g] > t */
        if (g - 1 < lo)
            return lo; /* unreachable: stamps[lo] = first <= t */
        if (as_ll(PyList_GET_ITEM(stamps, g - 1), &v) < 0)
            return -1;
        if (v <= t)
            return g;
        g--;
    }
    return bisect(stamps, t, lo, 1);
}

/* The link of one dynamic step at t: 1 found, 0 no data at t, -1 error. */
static int
link_at(PyObject *step, long long t, Tf7 *o)
{
    if (!PyTuple_Check(step) || PyTuple_GET_SIZE(step) != 4) {
        PyErr_SetString(PyExc_TypeError, "a chain step is a 4-tuple");
        return -1;
    }
    PyObject *stamps = PyTuple_GET_ITEM(step, 0);
    PyObject *segs = PyTuple_GET_ITEM(step, 1);
    PyObject *cache = PyTuple_GET_ITEM(step, 2);
    if (!PyList_CheckExact(stamps) || !PyList_CheckExact(segs)) {
        PyErr_SetString(PyExc_TypeError, "chain step lists expected");
        return -1;
    }
    Py_ssize_t n = PyList_GET_SIZE(stamps);
    if (n == 0)
        return 0;
    Py_ssize_t lo = cache_lo(cache);
    if (lo < 0)
        return -1;
    if (lo >= n) {
        PyErr_SetString(PyExc_ValueError, "cache index out of range");
        return -1;
    }
    long long last, first;
    if (as_ll(PyList_GET_ITEM(stamps, n - 1), &last) < 0
        || as_ll(PyList_GET_ITEM(stamps, lo), &first) < 0)
        return -1;
    /* i = bisect_right(stamps, t, lo), found cheaply where it matters */
    Py_ssize_t i;
    if (t < first)
        i = lo;
    else if (t >= last)
        i = n;
    else if ((i = locate(stamps, t, lo, n, first, last)) < 0)
        return -1;
    if (i > lo && t < last) {
        PyObject *seg = i - 1 < PyList_GET_SIZE(segs) ? PyList_GET_ITEM(segs, i - 1) : Py_None;
        Py_INCREF(seg);
        if (seg == Py_None) {
            Py_DECREF(seg);
            PyObject *idx = PyLong_FromSsize_t(i - 1);
            if (idx == NULL)
                return -1;
            seg = PyObject_CallMethodOneArg(cache, str_segment, idx);
            Py_DECREF(idx);
        }
        if (seg == NULL)
            return -1;
        if (!PyTuple_Check(seg) || PyTuple_GET_SIZE(seg) != 17) {
            Py_DECREF(seg);
            PyErr_SetString(PyExc_TypeError, "a segment is a 17-tuple");
            return -1;
        }
        long long s0;
        double v[16];
        if (as_ll(PyTuple_GET_ITEM(seg, 0), &s0) < 0) {
            Py_DECREF(seg);
            return -1;
        }
        for (int k = 0; k < 16; k++) {
            PyObject *it = PyTuple_GET_ITEM(seg, k + 1);
            v[k] = PyFloat_CheckExact(it) ? PyFloat_AS_DOUBLE(it) : PyFloat_AsDouble(it);
            if (v[k] == -1.0 && PyErr_Occurred()) {
                Py_DECREF(seg);
                return -1;
            }
        }
        Py_DECREF(seg);
        /* s0, idt, x, y, z, dx, dy, dz, ax, ay, az, aw, cx, cy, cz, cw, th */
        double r = (double)(t - s0) * v[0];
        double c = cos(r * v[15]), s = sin(r * v[15]);
        o->x = v[1] + r * v[4];
        o->y = v[2] + r * v[5];
        o->z = v[3] + r * v[6];
        o->qx = c * v[7] + s * v[11];
        o->qy = c * v[8] + s * v[12];
        o->qz = c * v[9] + s * v[13];
        o->qw = c * v[10] + s * v[14];
        return 1;
    }
    if (i > lo && t == last) {
        PyObject *vals = bound ? GET(cache, c_vals) : NULL;
        if (vals != NULL)
            Py_INCREF(vals);
        else if ((vals = PyObject_GetAttr(cache, str_vals)) == NULL)
            return -1;
        int rc = -1;
        if (PyList_Check(vals) && PyList_GET_SIZE(vals) > 0)
            rc = read7(PyList_GET_ITEM(vals, PyList_GET_SIZE(vals) - 1), o) < 0 ? -1 : 1;
        else
            PyErr_SetString(PyExc_TypeError, "cache values missing");
        Py_DECREF(vals);
        return rc;
    }
    return 0;
}

/* Compose a side's links bottom up (A ← post ∘ T_i(t) ∘ A): 1, 0 (no data) or -1. */
static int
accumulate(PyObject *pre, PyObject *steps, long long t, Tf7 *A)
{
    if (!PyList_CheckExact(steps)) {
        PyErr_SetString(PyExc_TypeError, "chain steps must be a list");
        return -1;
    }
    Py_ssize_t n = PyList_GET_SIZE(steps);
    int have = 0;
    if (pre != Py_None) {
        if (read7(pre, A) < 0)
            return -1;
        have = 1;
    }
    for (Py_ssize_t k = 0; k < n; k++) {
        PyObject *step = PyList_GET_ITEM(steps, k);
        Tf7 L;
        int rc = link_at(step, t, &L);
        if (rc <= 0)
            return rc;
        if (have) {
            *A = compose(&L, A);
        } else {
            *A = L;
            have = 1;
        }
        PyObject *post = PyTuple_GET_ITEM(step, 3);
        if (post != Py_None) {
            Tf7 P;
            if (read7(post, &P) < 0)
                return -1;
            *A = compose(&P, A);
        }
    }
    if (!have) {
        A->x = A->y = A->z = A->qx = A->qy = A->qz = 0.0;
        A->qw = 1.0;
    }
    return 1;
}

PyDoc_STRVAR(evaluate_doc,
"evaluate(src_pre, src, tgt_pre, tgt, t) -> tuple | None\n\n"
"T_target_source at t (ns, not 0) for a chain's parts, or None if a link has no data.");

static PyObject *
evaluate(PyObject *self, PyObject *const *args, Py_ssize_t nargs)
{
    if (nargs != 5) {
        PyErr_SetString(PyExc_TypeError, "evaluate takes 5 arguments");
        return NULL;
    }
    long long t;
    if (as_ll(args[4], &t) < 0)
        return NULL;
    Tf7 src;
    int rc = accumulate(args[0], args[1], t, &src);
    if (rc <= 0) {
        if (rc < 0)
            return NULL;
        Py_RETURN_NONE;
    }
    if (args[2] == Py_None && PyList_CheckExact(args[3]) && PyList_GET_SIZE(args[3]) == 0)
        return tuple7(&src);
    Tf7 tgt;
    rc = accumulate(args[2], args[3], t, &tgt);
    if (rc <= 0) {
        if (rc < 0)
            return NULL;
        Py_RETURN_NONE;
    }
    /* inverse(tgt) ∘ src (Chain.evaluate) */
    double x = src.x - tgt.x, y = src.y - tgt.y, z = src.z - tgt.z;
    double qx = -tgt.qx, qy = -tgt.qy, qz = -tgt.qz, qw = tgt.qw;
    double rx = src.qx, ry = src.qy, rz = src.qz, rw = src.qw;
    double tx = 2.0 * (qy * z - qz * y);
    double ty = 2.0 * (qz * x - qx * z);
    double tz = 2.0 * (qx * y - qy * x);
    Tf7 r;
    r.x = x + qw * tx + qy * tz - qz * ty;
    r.y = y + qw * ty + qz * tx - qx * tz;
    r.z = z + qw * tz + qx * ty - qy * tx;
    r.qx = qw * rx + qx * rw + qy * rz - qz * ry;
    r.qy = qw * ry - qx * rz + qy * rw + qz * rx;
    r.qz = qw * rz + qx * ry - qy * rx + qz * rw;
    r.qw = qw * rw - qx * rx - qy * ry - qz * rz;
    return tuple7(&r);
}

/* ------------------------------------------------------------------ bound types */


static int
bind_field(Field *f, PyObject *type, const char *name)
{
    if (!PyType_Check(type)) {
        PyErr_SetString(PyExc_TypeError, "bind expects types");
        return -1;
    }
    PyObject *d = PyObject_GetAttrString(type, name); /* the class attribute: a descriptor */
    if (d == NULL)
        return -1;
    if (!Py_IS_TYPE(d, &PyMemberDescr_Type)) {
        Py_DECREF(d);
        PyErr_Format(PyExc_TypeError, "%s.%s is not a slot", ((PyTypeObject *)type)->tp_name,
                     name);
        return -1;
    }
    PyMemberDef *m = ((PyMemberDescrObject *)d)->d_member;
    Py_DECREF(d); /* the type keeps it alive */
    if (m->type != T_OBJECT_EX && m->type != T_OBJECT) {
        PyErr_Format(PyExc_TypeError, "%s.%s is not an object slot",
                     ((PyTypeObject *)type)->tp_name, name);
        return -1;
    }
    f->type = (PyTypeObject *)type;
    f->off = m->offset;
    return 0;
}

PyDoc_STRVAR(bind_doc,
"bind(TransformStamped, Header, Time, Transform, Vector3, Quaternion, TimeCache)\n\n"
"Learn the slot offsets of the message and cache types the insert path reads.");

static PyObject *
bind(PyObject *self, PyObject *const *a, Py_ssize_t nargs)
{
    if (nargs != 7) {
        PyErr_SetString(PyExc_TypeError, "bind takes 7 types");
        return NULL;
    }
    bound = 0;
    if (bind_field(&ts_header, a[0], "header") || bind_field(&ts_child, a[0], "child_frame_id")
        || bind_field(&ts_transform, a[0], "transform") || bind_field(&h_stamp, a[1], "stamp")
        || bind_field(&h_frame, a[1], "frame_id") || bind_field(&tm_sec, a[2], "sec")
        || bind_field(&tm_nanosec, a[2], "nanosec")
        || bind_field(&tr_translation, a[3], "translation")
        || bind_field(&tr_rotation, a[3], "rotation") || bind_field(&v_x, a[4], "x")
        || bind_field(&v_y, a[4], "y") || bind_field(&v_z, a[4], "z")
        || bind_field(&q_x, a[5], "x") || bind_field(&q_y, a[5], "y")
        || bind_field(&q_z, a[5], "z") || bind_field(&q_w, a[5], "w")
        || bind_field(&c_stamps, a[6], "stamps") || bind_field(&c_vals, a[6], "vals")
        || bind_field(&c_parents, a[6], "parents") || bind_field(&c_segs, a[6], "segs")
        || bind_field(&c_parent, a[6], "parent") || bind_field(&c_lo, a[6], "lo"))
        return NULL;
    /* keep the types alive for as long as the module: offsets refer to them */
    for (int k = 0; k < 7; k++)
        Py_INCREF(a[k]);
    bound = 1;
    Py_RETURN_NONE;
}

/* ------------------------------------------------------------------ Inserter */

typedef struct {
    PyObject_HEAD
    PyObject *caches;    /* dict: child -> Cache */
    PyObject *authority; /* dict: child -> str */
    PyObject *locked;    /* the store lock's bound locked() */
    PyObject *fallback;  /* fallback(transform, authority, strict=...) */
    long long cache_ns;
    int watchers;
    vectorcallfunc vectorcall;
} Inserter;

static PyObject *str_default_authority;
static PyObject *str_strict;
static PyObject *str_authority;

/* A float or int field as a double; 0 for anything else (the Python path decides). */
static inline int
get_double(PyObject *o, double *out)
{
    if (o == NULL)
        return 0;
    if (PyFloat_CheckExact(o)) {
        *out = PyFloat_AS_DOUBLE(o);
        return 1;
    }
    if (PyLong_CheckExact(o)) {
        *out = PyLong_AsDouble(o);
        if (*out == -1.0 && PyErr_Occurred()) {
            PyErr_Clear();
            return 0;
        }
        return 1;
    }
    return 0;
}

static inline int
plain_id(PyObject *s)
{
    return s != NULL && PyUnicode_CheckExact(s) && PyUnicode_GET_LENGTH(s) > 0
           && PyUnicode_READ_CHAR(s, 0) != '/';
}

/* The hot path; 1 stored, 0 not the hot case (nothing changed), -1 error. */
static int
fast_insert(Inserter *self, PyObject *msg, PyObject *auth)
{
    if (!bound || self->watchers || !PyUnicode_CheckExact(auth))
        return 0;
    PyObject *h = GET(msg, ts_header), *child = GET(msg, ts_child), *tr = GET(msg, ts_transform);
    if (h == NULL || tr == NULL || !plain_id(child))
        return 0;
    PyObject *parent = GET(h, h_frame), *st = GET(h, h_stamp);
    PyObject *v = GET(tr, tr_translation), *q = GET(tr, tr_rotation);
    if (st == NULL || v == NULL || q == NULL || !plain_id(parent))
        return 0;
    double x, y, z, qx, qy, qz, qw;
    PyObject *f[7] = {GET(v, v_x), GET(v, v_y), GET(v, v_z), GET(q, q_x),
                      GET(q, q_y), GET(q, q_z), GET(q, q_w)};
    if (!get_double(f[0], &x) || !get_double(f[1], &y) || !get_double(f[2], &z)
        || !get_double(f[3], &qx) || !get_double(f[4], &qy) || !get_double(f[5], &qz)
        || !get_double(f[6], &qw))
        return 0;
    PyObject *sec = GET(st, tm_sec), *nsec = GET(st, tm_nanosec);
    if (sec == NULL || nsec == NULL || !PyLong_CheckExact(sec) || !PyLong_CheckExact(nsec))
        return 0;
    double n = qx * qx + qy * qy + qz * qz + qw * qw;
    if (!(0.0 * (x + y + z) == 0.0) || !(-0.01 < n - 1.0 && n - 1.0 < 0.01))
        return 0; /* refused: the Python path says why */
    int overflow;
    long long s = PyLong_AsLongLongAndOverflow(sec, &overflow);
    if (overflow || (s == -1 && PyErr_Occurred()) || s < -9000000000LL || s > 9000000000LL) {
        PyErr_Clear();
        return 0;
    }
    long long ns = PyLong_AsLongLongAndOverflow(nsec, &overflow);
    if (overflow || (ns == -1 && PyErr_Occurred()) || ns < 0 || ns > 4000000000LL) {
        PyErr_Clear();
        return 0;
    }
    long long stamp = s * 1000000000LL + ns;
    PyObject *cache = PyDict_GetItemWithError(self->caches, child);
    if (cache == NULL) {
        PyErr_Clear();
        return 0;
    }
    PyObject *cparent = GET(cache, c_parent);
    if (cparent == NULL || !PyUnicode_CheckExact(cparent))
        return 0;
    if (cparent != parent) {
        int eq = PyUnicode_Compare(cparent, parent);
        if (eq != 0) {
            if (eq == -1 && PyErr_Occurred())
                PyErr_Clear();
            return 0;
        }
    }
    PyObject *stamps = GET(cache, c_stamps), *vals = GET(cache, c_vals);
    PyObject *parents = GET(cache, c_parents), *segs = GET(cache, c_segs);
    if (stamps == NULL || vals == NULL || parents == NULL || segs == NULL
        || !PyList_CheckExact(stamps) || !PyList_CheckExact(vals)
        || !PyList_CheckExact(parents) || !PyList_CheckExact(segs))
        return 0;
    Py_ssize_t len = PyList_GET_SIZE(stamps);
    if (len == 0 || PyList_GET_SIZE(vals) != len || PyList_GET_SIZE(parents) != len
        || PyList_GET_SIZE(segs) != len)
        return 0;
    long long last;
    if (as_ll(PyList_GET_ITEM(stamps, len - 1), &last) < 0) {
        PyErr_Clear();
        return 0;
    }
    if (stamp <= last)
        return 0;
    PyObject *plo = GET(cache, c_lo);
    long long lo;
    if (plo == NULL || !PyLong_CheckExact(plo) || as_ll(plo, &lo) < 0 || lo < 0 || lo >= len) {
        PyErr_Clear();
        return 0;
    }
    int normalize = !(-1e-12 < n - 1.0 && n - 1.0 < 1e-12);
    if (normalize) {
        double k = 1.0 / sqrt(n);
        qx *= k; qy *= k; qz *= k; qw *= k;
    }
    /* Exclusion without taking the lock (two Python-level calls cost more than the rest):
       if nobody holds it now, nobody can until this function returns, since from here on
       it neither releases the GIL nor runs Python code. Allocations could run the cyclic
       GC, and with it finalizers, so the GC is paused. A thread that was blocked in
       acquire() may own the OS lock already, but it cannot run before we return. A holder
       means contention: the Python path waits for the lock properly. */
    PyObject *held = PyObject_CallNoArgs(self->locked);
    if (held == NULL)
        return -1;
    int busy = held != Py_False;
    Py_DECREF(held);
    if (busy)
        return 0;
    int gc_was_on = PyGC_Disable();
    int rc = -1;
    Py_INCREF(cache);
    Tf7 val = {x, y, z, qx, qy, qz, qw};
    PyObject *pstamp = NULL, *pval = NULL;
    pstamp = PyLong_FromLongLong(stamp);
    /* the message's own objects, as the Python path keeps them; new floats where the
       quaternion was normalised */
    pval = PyTuple_New(7);
    if (pval == NULL)
        goto done;
    double qv[4] = {val.qx, val.qy, val.qz, val.qw};
    for (int k = 0; k < 7; k++) {
        PyObject *item = f[k];
        if (k >= 3 && normalize) {
            item = PyFloat_FromDouble(qv[k - 3]);
            if (item == NULL)
                goto done;
        } else {
            Py_INCREF(item);
        }
        PyTuple_SET_ITEM(pval, k, item);
    }
    if (pstamp == NULL || pval == NULL)
        goto done;
    if (PyList_Append(stamps, pstamp) < 0)
        goto done;
    if (PyList_Append(vals, pval) < 0 || PyList_Append(segs, Py_None) < 0
        || PyList_Append(parents, cparent) < 0) {
        /* keep the lists aligned whatever happened */
        Py_ssize_t m = PyList_GET_SIZE(stamps);
        PyList_SetSlice(stamps, len, m, NULL);
        PyList_SetSlice(vals, len, PyList_GET_SIZE(vals), NULL);
        PyList_SetSlice(segs, len, PyList_GET_SIZE(segs), NULL);
        PyList_SetSlice(parents, len, PyList_GET_SIZE(parents), NULL);
        goto done;
    }
    /* prune (TimeCache.prune with one parent throughout: no breaks to count) */
    long long first, cutoff = stamp - self->cache_ns;
    if (as_ll(PyList_GET_ITEM(stamps, lo), &first) < 0)
        goto done;
    if (first < cutoff) {
        long long second;
        Py_ssize_t k = lo + 1;
        if (as_ll(PyList_GET_ITEM(stamps, lo + 1), &second) < 0)
            goto done;
        if (second < cutoff) {
            k = bisect(stamps, cutoff, lo, 0);
            if (k < 0)
                goto done;
        }
        if (k >= COMPACT_AT && 2 * k >= PyList_GET_SIZE(stamps)) {
            if (PyList_SetSlice(stamps, 0, k, NULL) < 0 || PyList_SetSlice(vals, 0, k, NULL) < 0
                || PyList_SetSlice(parents, 0, k, NULL) < 0
                || PyList_SetSlice(segs, 0, k, NULL) < 0)
                goto done;
            k = 0;
        }
        PyObject *nlo = PyLong_FromSsize_t(k);
        if (nlo == NULL)
            goto done;
        PyObject **slot = (PyObject **)((char *)cache + c_lo.off);
        PyObject *old = *slot;
        *slot = nlo;
        Py_XDECREF(old);
    }
    if (PyDict_SetItem(self->authority, child, auth) < 0)
        goto done;
    rc = 1;
done:
    Py_XDECREF(pstamp);
    Py_XDECREF(pval);
    Py_DECREF(cache);
    if (gc_was_on)
        PyGC_Enable();
    return rc;
}

static PyObject *
inserter_call(PyObject *op, PyObject *const *args, size_t nargsf, PyObject *kwnames)
{
    Inserter *self = (Inserter *)op;
    Py_ssize_t nargs = PyVectorcall_NARGS(nargsf);
    PyObject *msg = NULL, *auth = NULL, *strict = Py_False;
    if (nargs < 1 || nargs > 2)
        goto bad;
    msg = args[0];
    if (nargs == 2)
        auth = args[1];
    if (kwnames != NULL) {
        for (Py_ssize_t k = 0; k < PyTuple_GET_SIZE(kwnames); k++) {
            PyObject *name = PyTuple_GET_ITEM(kwnames, k);
            PyObject *val = args[nargs + k];
            if (PyUnicode_Check(name) && PyUnicode_Compare(name, str_strict) == 0)
                strict = val;
            else if (auth == NULL && PyUnicode_Check(name)
                     && PyUnicode_Compare(name, str_authority) == 0)
                auth = val;
            else
                goto bad;
        }
    }
    if (auth == NULL)
        auth = str_default_authority;
    int rc = fast_insert(self, msg, auth);
    if (rc < 0)
        return NULL;
    if (rc > 0)
        Py_RETURN_TRUE;
    PyObject *kw = Py_BuildValue("{sO}", "strict", strict);
    if (kw == NULL)
        return NULL;
    PyObject *pargs = PyTuple_Pack(2, msg, auth);
    if (pargs == NULL) {
        Py_DECREF(kw);
        return NULL;
    }
    PyObject *r = PyObject_Call(self->fallback, pargs, kw);
    Py_DECREF(pargs);
    Py_DECREF(kw);
    return r;
bad:
    PyErr_SetString(PyExc_TypeError,
                    "set_transform(transform, authority='default_authority', *, strict=False)");
    return NULL;
}

static PyObject *
inserter_new(PyTypeObject *type, PyObject *args, PyObject *kwds)
{
    static char *kwlist[] = {"caches", "authority", "lock", "cache_ns", "fallback", NULL};
    PyObject *caches, *authority, *lock, *fallback;
    long long cache_ns;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "O!O!OLO:Inserter", kwlist, &PyDict_Type,
                                     &caches, &PyDict_Type, &authority, &lock, &cache_ns,
                                     &fallback))
        return NULL;
    Inserter *self = (Inserter *)type->tp_alloc(type, 0);
    if (self == NULL)
        return NULL;
    self->locked = PyObject_GetAttrString(lock, "locked");
    if (self->locked == NULL) {
        Py_DECREF(self);
        return NULL;
    }
    Py_INCREF(caches);
    Py_INCREF(authority);
    Py_INCREF(fallback);
    self->caches = caches;
    self->authority = authority;
    self->fallback = fallback;
    self->cache_ns = cache_ns;
    self->watchers = 0;
    self->vectorcall = inserter_call;
    return (PyObject *)self;
}

static int
inserter_traverse(Inserter *self, visitproc visit, void *arg)
{
    Py_VISIT(self->caches);
    Py_VISIT(self->authority);
    Py_VISIT(self->locked);
    Py_VISIT(self->fallback);
    return 0;
}

static int
inserter_clear(Inserter *self)
{
    Py_CLEAR(self->caches);
    Py_CLEAR(self->authority);
    Py_CLEAR(self->locked);
    Py_CLEAR(self->fallback);
    return 0;
}

static void
inserter_dealloc(Inserter *self)
{
    PyObject_GC_UnTrack(self);
    inserter_clear(self);
    Py_TYPE(self)->tp_free((PyObject *)self);
}

static PyMemberDef inserter_members[] = {
    {"watchers", T_INT, offsetof(Inserter, watchers), 0,
     "Threads or futures waiting on the buffer: while non-zero, inserts take the Python path."},
    {NULL},
};

PyDoc_STRVAR(inserter_doc,
"Inserter(caches, authority, lock, cache_ns, fallback)\n\n"
"A callable with set_transform's signature: stores an in-order sample of a single-parent\n"
"link itself, and hands every other case to fallback(transform, authority, strict=...).");

static PyTypeObject InserterType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "zenros.tf._speedups.Inserter",
    .tp_basicsize = sizeof(Inserter),
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_GC | Py_TPFLAGS_HAVE_VECTORCALL,
    .tp_doc = inserter_doc,
    .tp_new = inserter_new,
    .tp_dealloc = (destructor)inserter_dealloc,
    .tp_traverse = (traverseproc)inserter_traverse,
    .tp_clear = (inquiry)inserter_clear,
    .tp_call = PyVectorcall_Call,
    .tp_vectorcall_offset = offsetof(Inserter, vectorcall),
    .tp_members = inserter_members,
};

/* ------------------------------------------------------------------ module */

static PyMethodDef methods[] = {
    {"evaluate", (PyCFunction)(void (*)(void))evaluate, METH_FASTCALL, evaluate_doc},
    {"bind", (PyCFunction)(void (*)(void))bind, METH_FASTCALL, bind_doc},
    {"latest", (PyCFunction)latest, METH_O, latest_doc},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_speedups", "Hot paths of zenros.tf in C (see chain.py, store.py).",
    -1, methods,
};

PyMODINIT_FUNC
PyInit__speedups(void)
{
    str_segment = PyUnicode_InternFromString("segment");
    str_vals = PyUnicode_InternFromString("vals");
    str_lo = PyUnicode_InternFromString("lo");
    str_default_authority = PyUnicode_InternFromString("default_authority");
    str_strict = PyUnicode_InternFromString("strict");
    str_authority = PyUnicode_InternFromString("authority");
    if (!str_segment || !str_vals || !str_lo || !str_default_authority || !str_strict || !str_authority)
        return NULL;
    if (PyType_Ready(&InserterType) < 0)
        return NULL;
    PyObject *m = PyModule_Create(&module);
    if (m == NULL)
        return NULL;
    if (PyModule_AddIntConstant(m, "COMPACT_AT", COMPACT_AT) < 0) {
        Py_DECREF(m);
        return NULL;
    }
    Py_INCREF(&InserterType);
    if (PyModule_AddObject(m, "Inserter", (PyObject *)&InserterType) < 0) {
        Py_DECREF(&InserterType);
        Py_DECREF(m);
        return NULL;
    }
    return m;
}
