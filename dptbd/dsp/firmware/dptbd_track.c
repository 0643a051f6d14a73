/*
 * dptbd_track.c - paper 001 section 3 (binary track association), portable C99.
 * The reference is dptbd.dsp.association.Tracker: every function below names the method
 * it mirrors, and the order of every loop, compare and rounding is the same, so the
 * records come out bit for bit equal (tests/dsp/test_c_tracker.py).
 */
#include <string.h>

#include "dptbd_track.h"

#define DPTBD_MAGIC 0x44505442u /* "DPTB" */

enum { CLASS_CONFIRMED = 0, CLASS_PREDICTED = 1, CLASS_TENTATIVE = 2, CLASS_NONE = 3 };

/* ---- integer helpers ------------------------------------------------------------- */

/* floor(a / b) for b > 0 (Python's //). */
static int64_t floor_div(int64_t a, int64_t b)
{
    int64_t q = a / b;
    if ((a % b != 0) && (a < 0)) {
        q -= 1;
    }
    return q;
}

/* a / b rounded half up, b > 0: (2a + b) // (2b)  (association.div_round). */
static int64_t div_round(int64_t a, int64_t b)
{
    return floor_div(2 * a + b, 2 * b);
}

static int64_t abs64(int64_t a) { return a < 0 ? -a : a; }
static int64_t min64(int64_t a, int64_t b) { return a < b ? a : b; }
static int64_t max64(int64_t a, int64_t b) { return a > b ? a : b; }

/* Unsigned 128-bit arithmetic on two 64-bit halves, for |v|^2 |h|^2 (up to 2^122). */
typedef struct { uint64_t hi, lo; } u128;

static u128 mul_64x64(uint64_t a, uint64_t b)
{
    uint64_t a0 = a & 0xffffffffu, a1 = a >> 32, b0 = b & 0xffffffffu, b1 = b >> 32;
    uint64_t p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
    uint64_t mid = (p00 >> 32) + (p01 & 0xffffffffu) + (p10 & 0xffffffffu);
    u128 r;
    r.lo = (mid << 32) | (p00 & 0xffffffffu);
    r.hi = p11 + (p01 >> 32) + (p10 >> 32) + (mid >> 32);
    return r;
}

static int u128_ge(u128 a, u128 b) { return a.hi > b.hi || (a.hi == b.hi && a.lo >= b.lo); }

static u128 u128_sub(u128 a, u128 b)
{
    u128 r;
    r.lo = a.lo - b.lo;
    r.hi = a.hi - b.hi - (a.lo < b.lo ? 1u : 0u);
    return r;
}

static u128 u128_add(u128 a, u128 b)
{
    u128 r;
    r.lo = a.lo + b.lo;
    r.hi = a.hi + b.hi + (r.lo < a.lo ? 1u : 0u);
    return r;
}

static u128 u128_shr(u128 a, unsigned s) /* 0 < s < 64 */
{
    u128 r;
    r.lo = (a.lo >> s) | (a.hi << (64u - s));
    r.hi = a.hi >> s;
    return r;
}

/* floor(sqrt(a)), exact (math.isqrt): the digit-by-digit method, 64 steps at most. */
static uint64_t isqrt_u128(u128 a)
{
    u128 res = {0, 0}, bit;
    int k;
    if (a.hi == 0 && a.lo == 0) {
        return 0;
    }
    /* highest power of four <= a */
    k = 126;
    for (;;) {
        uint64_t want_hi = k >= 64 ? ((uint64_t)1 << (k - 64)) : 0;
        uint64_t want_lo = k >= 64 ? 0 : ((uint64_t)1 << k);
        bit.hi = want_hi;
        bit.lo = want_lo;
        if (u128_ge(a, bit)) {
            break;
        }
        k -= 2;
    }
    for (;;) {
        u128 trial = u128_add(res, bit);
        if (u128_ge(a, trial)) {
            a = u128_sub(a, trial);
            res = u128_add(u128_shr(res, 1), bit);
        } else {
            res = u128_shr(res, 1);
        }
        if (k == 0) {
            break;
        }
        k -= 2;
        bit = u128_shr(bit, 2);
    }
    return res.lo;
}

/* floor(a * b / c) for c > 0, exact for any 64-bit a, b with a * b / c < 2^64. */
static uint64_t mul_div_u64(uint64_t a, uint64_t b, uint64_t c)
{
    u128 num = mul_64x64(a, b);
    uint64_t rem = 0, quo = 0;
    int i;
    if (num.hi == 0) {
        return num.lo / c;
    }
    for (i = 127; i >= 0; --i) { /* restoring long division, one bit at a time */
        uint64_t bit = i >= 64 ? (num.hi >> (i - 64)) & 1u : (num.lo >> i) & 1u;
        int carry = (rem >> 63) != 0;
        rem = (rem << 1) | bit;
        quo <<= 1;
        if (carry || rem >= c) {
            rem -= c;
            quo |= 1u;
        }
    }
    return quo;
}

/* ---- parameters ------------------------------------------------------------------ */

static int in_range(int32_t v, int32_t lo, int32_t hi) { return v >= lo && v <= hi; }

static int params_valid(const dptbd_params *p)
{
    return p->segment_frames >= 1
        && in_range(p->segment_stride, 1, 1024)
        && in_range(p->height, 1, 65536) && in_range(p->width, 1, 65536)
        && in_range(p->radius, 0, 255)
        && in_range(p->merge_radius, 0, 16) && in_range(p->duplicate_radius, 0, 1000)
        && in_range(p->seed_gate, 0, 16000) && in_range(p->gate_base, 0, 16000)
        && in_range(p->gate_growth, 0, 1600) && in_range(p->gate_miss, 0, 16000)
        && in_range(p->gate_max, 0, 65535)
        && in_range(p->gate_growth_segments, 0, 1000)
        && in_range(p->manoeuvre, 0, 16000) && in_range(p->link_gate, 0, 16000)
        && in_range(p->heading_min, 0, 16000) && in_range(p->heading_weight, 0, 25600)
        && in_range(p->reject_reversed, 0, 1)
        && in_range(p->confirm_ratio, 0, 256) && in_range(p->predict_ratio, 0, 256)
        && in_range(p->delete_ratio, 0, 256)
        && p->confirm_ratio >= p->predict_ratio && p->predict_ratio >= p->delete_ratio
        && in_range(p->confirm_hits, 1, 65535) && in_range(p->predict_hits, 1, 65535)
        && p->confirm_hits >= p->predict_hits
        && in_range(p->max_misses, 0, 255)
        && p->confirm_gap >= 1
        && in_range(p->wake_radius, 0, 16) && in_range(p->wake_points, 1, 65535);
}

dptbd_status dptbd_track_init(dptbd_tracker *t, const dptbd_params *p)
{
    if (t == NULL || p == NULL) {
        return DPTBD_E_NULL;
    }
    memset(t, 0, sizeof *t);
    if (!params_valid(p)) {
        return DPTBD_E_PARAMS;   /* magic stays 0: step refuses the context */
    }
    t->p = *p;
    t->segment = -1;
    t->next_id = 1;
    t->magic = DPTBD_MAGIC;
    return DPTBD_OK;
}

/* ---- one segment ------------------------------------------------------------------ */

static int ratio_at_least(int64_t hits, int64_t length, int32_t ratio_q8)
{
    return hits * DPTBD_RATIO_ONE >= (int64_t)ratio_q8 * length;
}

static int in_prediction_space(const dptbd_tracker *t, int i)
{
    const dptbd_track *r = &t->tracks[i];
    return r->state == DPTBD_CONFIRMED
        || (r->hits >= t->p.predict_hits && ratio_at_least(r->hits, r->length, t->p.predict_ratio));
}

/* Tracker._headings */
static void headings(dptbd_tracker *t, uint32_t n)
{
    const dptbd_params *p = &t->p;
    int64_t side = 2 * (int64_t)p->radius + 1;
    uint32_t j;
    for (j = 0; j < n; ++j) {
        const dptbd_candidate *c = &t->inbuf[j];
        int64_t hr, hc;
        if (c->path && p->segment_frames > 1) {
            hr = div_round(((int64_t)c->row - c->row0) * DPTBD_ONE * p->segment_stride, p->segment_frames - 1);
            hc = div_round(((int64_t)c->col - c->col0) * DPTBD_ONE * p->segment_stride, p->segment_frames - 1);
        } else if ((int64_t)c->direction < side * side) {
            int64_t dy = (int64_t)c->direction / side - p->radius;
            int64_t dx = (int64_t)c->direction % side - p->radius;
            hr = dy * DPTBD_ONE * p->segment_stride;
            hc = dx * DPTBD_ONE * p->segment_stride;
        } else {
            hr = hc = 0;
        }
        t->head_row[j] = (int32_t)hr;
        t->head_col[j] = (int32_t)hc;
    }
}

/* Tracker._suppress_clusters */
static void suppress_clusters(dptbd_tracker *t, uint32_t n, dptbd_work *w)
{
    int32_t rad = t->p.merge_radius;
    uint32_t i, j;
    for (j = 0; j < n; ++j) {
        int keep = 1;
        if (rad > 0) {
            const dptbd_candidate *cj = &t->inbuf[j];
            for (i = 0; i < n; ++i) {
                const dptbd_candidate *ci = &t->inbuf[i];
                if (i == j) {
                    continue;
                }
                w->suppression_tests++;
                if (abs64((int64_t)ci->row - cj->row) <= rad && abs64((int64_t)ci->col - cj->col) <= rad) {
                    if (ci->energy > cj->energy || (ci->energy == cj->energy && i < j)) {
                        keep = 0;
                        break;
                    }
                }
            }
        }
        t->keep[j] = (uint8_t)keep;
        t->claimed[j] = 0;
        if (!keep) {
            t->stats.suppressed++;
        }
    }
}

/* Tracker._classify */
static void classify(dptbd_tracker *t)
{
    int i;
    for (i = 0; i < DPTBD_CAPACITY; ++i) {
        t->match[i] = -1;
        if (t->tracks[i].state == DPTBD_FREE) {
            t->cls[i] = CLASS_NONE;
        } else if (t->tracks[i].state == DPTBD_CONFIRMED) {
            t->cls[i] = CLASS_CONFIRMED;
        } else if (in_prediction_space(t, i)) {
            t->cls[i] = CLASS_PREDICTED;
        } else {
            t->cls[i] = CLASS_TENTATIVE;
        }
    }
}

/* Tracker._link_cost */
static int64_t link_cost(const dptbd_tracker *t, int i, uint32_t j)
{
    const dptbd_params *p = &t->p;
    const dptbd_track *r = &t->tracks[i];
    const dptbd_candidate *c = &t->inbuf[j];
    int64_t lr, lc, l2, lg2;
    if (p->link_gate <= 0 || p->segment_stride != p->segment_frames || !c->path
            || t->cls[i] > CLASS_PREDICTED || (int64_t)r->p_seg[1] != (int64_t)t->segment - 1) {
        return -1;
    }
    lr = (int64_t)c->row0 * DPTBD_ONE - r->p_row[1];
    lc = (int64_t)c->col0 * DPTBD_ONE - r->p_col[1];
    l2 = lr * lr + lc * lc;
    lg2 = (int64_t)p->link_gate * p->link_gate;
    if (l2 > lg2) {
        return -1;
    }
    return DPTBD_RATIO_ONE + p->heading_weight + (l2 * DPTBD_RATIO_ONE) / lg2;
}

/* Tracker._cost: Q8 cost of candidate j for track i, -1 outside the gate / reversed. */
static int64_t cost_of(const dptbd_tracker *t, int i, uint32_t j)
{
    const dptbd_params *p = &t->p;
    const dptbd_track *r = &t->tracks[i];
    const dptbd_candidate *c = &t->inbuf[j];
    uint64_t dr = (uint64_t)abs64((int64_t)c->row * DPTBD_ONE - r->pred_row);
    uint64_t dc = (uint64_t)abs64((int64_t)c->col * DPTBD_ONE - r->pred_col);
    uint64_t d2 = dr * dr + dc * dc;              /* < 2^64: |dr|, |dc| < 2^31 + 2^20 */
    uint64_t g2 = (uint64_t)r->gate * r->gate;
    int64_t cost, vr, vc, hr, hc, v2, h2, hmin2;
    if (d2 > g2) {
        return link_cost(t, i, j);
    }
    cost = (int64_t)((d2 * DPTBD_RATIO_ONE) / (g2 > 0 ? g2 : 1));
    vr = r->v_row;
    vc = r->v_col;
    hr = t->head_row[j];
    hc = t->head_col[j];
    v2 = vr * vr + vc * vc;
    h2 = hr * hr + hc * hc;
    hmin2 = (int64_t)p->heading_min * p->heading_min;
    if (v2 >= hmin2 && h2 >= hmin2 && v2 > 0 && h2 > 0) {
        int64_t dot = vr * hr + vc * hc;
        uint64_t norm;
        if (p->reject_reversed && dot < 0) {
            return -1;
        }
        norm = isqrt_u128(mul_64x64((uint64_t)v2, (uint64_t)h2)); /* |v||h| */
        if (norm > 0) {
            int64_t gap = (int64_t)norm - dot;
            if (gap > 0) { /* (1 - cos theta) / 2 in [0, 1], times the heading weight (Q8) */
                cost += (int64_t)mul_div_u64((uint64_t)p->heading_weight, (uint64_t)gap, 2 * norm);
            }
        }
    }
    return cost;
}

/* Tracker._stronger: class priority, then more hits, then the older id. */
static int stronger(const dptbd_tracker *t, int a, int b)
{
    if (t->cls[a] != t->cls[b]) {
        return t->cls[a] < t->cls[b];
    }
    if (t->tracks[a].hits != t->tracks[b].hits) {
        return t->tracks[a].hits > t->tracks[b].hits;
    }
    return t->tracks[a].id < t->tracks[b].id;
}

/* Tracker._match_class */
static void match_class(dptbd_tracker *t, int cls, uint32_t n, dptbd_work *w)
{
    int i, m = 0, x;
    for (i = 0; i < DPTBD_CAPACITY; ++i) {        /* insertion sort by evidence */
        int k;
        if (t->cls[i] != cls) {
            continue;
        }
        k = m;
        while (k > 0 && k < DPTBD_CAPACITY) {     /* k < m <= capacity: a bound gcc can see */
            w->sort_compares++;
            if (!stronger(t, i, t->order_tracks[k - 1])) {
                break;
            }
            t->order_tracks[k] = t->order_tracks[k - 1];
            k -= 1;
        }
        t->order_tracks[k] = (uint16_t)i;
        m += 1;
    }
    for (x = 0; x < m; ++x) {
        int best = -1;
        int64_t best_cost = -1;
        uint32_t j;
        i = t->order_tracks[x];
        for (j = 0; j < n; ++j) {
            int64_t cost;
            if (!t->keep[j] || t->claimed[j]) {
                continue;
            }
            w->cost_evaluations++;
            cost = cost_of(t, i, j);
            if (cost >= 0 && (best < 0 || cost < best_cost)) {
                best = (int)j;
                best_cost = cost;
            }
        }
        if (best >= 0) {
            t->claimed[best] = 1;
            t->match[i] = best;
            t->stats.matched++;
        }
    }
}

/* Tracker._record_point */
static void record_point(dptbd_tracker *t, int i, uint32_t j, int32_t s)
{
    dptbd_track *r = &t->tracks[i];
    const dptbd_candidate *c = &t->inbuf[j];
    uint32_t slot = r->n_points % DPTBD_MAX_POINTS;
    dptbd_point *h = &t->history[i][slot];
    if (r->n_points >= DPTBD_MAX_POINTS) {
        t->stats.history_wrapped++;
    }
    h->seg = s;
    h->row = c->row;
    h->col = c->col;
    h->energy = c->energy;
    h->row0 = c->row0;
    h->col0 = c->col0;
    h->path = c->path;
    r->n_points += 1;
}

/* Tracker._extend: prediction step (2), the new velocity. */
static void extend(dptbd_tracker *t, int i, uint32_t j, int32_t s)
{
    dptbd_track *r = &t->tracks[i];
    const dptbd_candidate *c = &t->inbuf[j];
    int64_t row = (int64_t)c->row * DPTBD_ONE, col = (int64_t)c->col * DPTBD_ONE;
    int64_t seg1 = r->p_seg[1], row1 = r->p_row[1], col1 = r->p_col[1];
    int64_t gap1 = s - seg1;
    int64_t v1r = div_round(row - row1, gap1), v1c = div_round(col - col1, gap1), vr, vc;
    if (r->hits >= 2) {
        int64_t seg0 = r->p_seg[0], row0 = r->p_row[0], col0 = r->p_col[0];
        int64_t gap2 = seg1 - seg0;
        int64_t v2r = div_round(row1 - row0, gap2), v2c = div_round(col1 - col0, gap2);
        if (max64(abs64(v1r - v2r), abs64(v1c - v2c)) > t->p.manoeuvre) {
            vr = v1r;                                  /* manoeuvre: the newest step */
            vc = v1c;
        } else {
            vr = div_round(v1r + v2r, 2);
            vc = div_round(v1c + v2c, 2);
        }
    } else {
        vr = v1r;
        vc = v1c;
    }
    r->p_seg[0] = (int32_t)seg1;
    r->p_row[0] = (int32_t)row1;
    r->p_col[0] = (int32_t)col1;
    r->p_seg[1] = s;
    r->p_row[1] = (int32_t)row;
    r->p_col[1] = (int32_t)col;
    r->v_row = (int32_t)vr;
    r->v_col = (int32_t)vc;
    r->hits = (uint16_t)min64((int64_t)r->hits + 1, 65535);
    if ((int64_t)s - r->count_seg >= t->p.confirm_gap) {
        r->counted = (uint16_t)min64((int64_t)r->counted + 1, 65535);
        r->count_seg = s;
    }
    r->misses = 0;
    record_point(t, i, j, s);
}

/* Tracker._delete: free record i; a confirmed track goes to the archive first. */
static void delete_track(dptbd_tracker *t, int i)
{
    if (t->tracks[i].state == DPTBD_CONFIRMED) {
#if DPTBD_OUTPUT_CAPACITY > 0
        if (t->n_archived < (uint32_t)DPTBD_OUTPUT_CAPACITY) {
            t->archive[t->n_archived] = t->tracks[i];
            memcpy(t->archive_history[t->n_archived], t->history[i], sizeof t->history[i]);
            t->n_archived++;
        } else {
            t->stats.dropped_outputs++;
        }
#else
        t->stats.dropped_outputs++;   /* no archive */
#endif
    }
    memset(&t->tracks[i], 0, sizeof t->tracks[i]);
    t->stats.deleted++;
}

/* Tracker._update: thresholds (step (3)), then predicted point and gate for s + 1. */
static void update(dptbd_tracker *t, int i, int32_t s)
{
    const dptbd_params *p = &t->p;
    dptbd_track *r = &t->tracks[i];
    int64_t length = (int64_t)s - r->first_seg + 1, hits, misses, ahead, pr, pc, gate;
    r->length = (uint16_t)min64(length, 65535);
    hits = r->hits;
    misses = r->misses;
    if (!ratio_at_least(hits, length, p->delete_ratio) || misses > p->max_misses) {
        delete_track(t, i);
        return;
    }
    if (r->state == DPTBD_TENTATIVE && r->counted >= p->confirm_hits
            && ratio_at_least(hits, length, p->confirm_ratio)) {
        r->state = DPTBD_CONFIRMED;
        r->confirm_seg = s;
        t->stats.confirmed++;
    }
    ahead = (int64_t)s + 1 - r->p_seg[1];
    pr = (int64_t)r->p_row[1] + (int64_t)r->v_row * ahead;
    pc = (int64_t)r->p_col[1] + (int64_t)r->v_col * ahead;
    if (in_prediction_space(t, i)) {
        int64_t grow = div_round((int64_t)p->gate_growth * min64(length, p->gate_growth_segments) * hits, length);
        gate = p->gate_base + grow + (int64_t)p->gate_miss * misses;
    } else {
        gate = p->seed_gate + (int64_t)p->gate_miss * misses;
    }
    gate = min64(gate, p->gate_max);
    if (pr < -gate || pc < -gate || pr > ((int64_t)p->height - 1) * DPTBD_ONE + gate
            || pc > ((int64_t)p->width - 1) * DPTBD_ONE + gate) {
        t->stats.left_image++;
        delete_track(t, i);
        return;
    }
    r->pred_row = (int32_t)pr;
    r->pred_col = (int32_t)pc;
    r->gate = (uint16_t)gate;
}

/* Tracker._remove_duplicates */
static void remove_duplicates(dptbd_tracker *t, dptbd_work *w)
{
    int64_t rad = (int64_t)t->p.duplicate_radius * DPTBD_ONE;
    int i, m = 0, x, y;
    if (rad <= 0) {
        return;
    }
    for (i = 0; i < DPTBD_CAPACITY; ++i) {
        if (t->match[i] >= 0 && t->tracks[i].state != DPTBD_FREE) {
            t->order_tracks[m++] = (uint16_t)i;
        }
    }
    for (x = 0; x < m; ++x) {
        int a = t->order_tracks[x];
        if (t->tracks[a].state == DPTBD_FREE) {
            continue;
        }
        for (y = x + 1; y < m; ++y) {
            int b = t->order_tracks[y];
            const dptbd_track *ra = &t->tracks[a], *rb = &t->tracks[b];
            if (rb->state == DPTBD_FREE) {
                continue;
            }
            w->duplicate_tests++;
            if (abs64((int64_t)ra->p_row[1] - rb->p_row[1]) <= rad
                    && abs64((int64_t)ra->p_col[1] - rb->p_col[1]) <= rad
                    && abs64((int64_t)ra->v_row - rb->v_row) <= t->p.manoeuvre
                    && abs64((int64_t)ra->v_col - rb->v_col) <= t->p.manoeuvre) {
                int weaker = stronger(t, a, b) ? b : a;
                t->stats.duplicates++;
                delete_track(t, weaker);
                if (weaker == a) {
                    break;
                }
            }
        }
    }
}

static int within(int64_t r, int64_t c, int64_t rj, int64_t cj, int64_t rad)
{
    return abs64(r - rj) <= rad && abs64(c - cj) <= rad;
}

/* Tracker._suppress_wake: a leftover candidate within wake_radius (Chebyshev) of a live
 * track's newest wake_points history points or their path starts starts no track. */
static void suppress_wake(dptbd_tracker *t, uint32_t n, dptbd_work *w)
{
    const int64_t rad = t->p.wake_radius;
    uint32_t j;
    if (rad <= 0) {
        return;
    }
    for (j = 0; j < n; ++j) {
        int64_t rj, cj;
        int i, near = 0;
        if (!t->keep[j] || t->claimed[j]) {
            continue;
        }
        rj = t->inbuf[j].row;
        cj = t->inbuf[j].col;
        for (i = 0; i < DPTBD_CAPACITY && !near; ++i) {
            const dptbd_track *r = &t->tracks[i];
            uint32_t q, points;
            if (r->state == DPTBD_FREE) {
                continue;
            }
            points = r->n_points;
            if (points > (uint32_t)t->p.wake_points) {
                points = (uint32_t)t->p.wake_points;
            }
            if (points > (uint32_t)DPTBD_MAX_POINTS) {
                points = (uint32_t)DPTBD_MAX_POINTS;
            }
            for (q = 0; q < points; ++q) {
                const dptbd_point *h =
                    &t->history[i][(r->n_points - 1u - q) % (uint32_t)DPTBD_MAX_POINTS];
                w->wake_tests++;
                if (within(h->row, h->col, rj, cj, rad)
                        || (h->path && within(h->row0, h->col0, rj, cj, rad))) {
                    near = 1;
                    break;
                }
            }
        }
        if (near) {
            t->keep[j] = 0;
            t->stats.wake_suppressed++;
        }
    }
}

/* Tracker._start_tracks: new tentative tracks from the leftovers, strongest first. */
static void start_tracks(dptbd_tracker *t, uint32_t n, int32_t s, dptbd_work *w)
{
    const dptbd_params *p = &t->p;
    uint32_t j, m = 0, k;
    int free_slot = 0;
    for (j = 0; j < n; ++j) {                     /* insertion sort by decreasing E */
        uint32_t e;
        if (!t->keep[j] || t->claimed[j]) {
            continue;
        }
        e = t->inbuf[j].energy;
        k = m;
        while (k > 0 && k < DPTBD_MAX_CANDIDATES) { /* k <= m < n: a bound gcc can see */
            w->sort_compares++;
            if (!(t->inbuf[t->order[k - 1]].energy < e)) {
                break;
            }
            t->order[k] = t->order[k - 1];
            k -= 1;
        }
        t->order[k] = (uint16_t)j;
        m += 1;
    }
    for (k = 0; k < m; ++k) {
        dptbd_track *r;
        int32_t row, col;
        j = t->order[k];
        while (free_slot < DPTBD_CAPACITY) {
            w->free_probes++;
            if (t->tracks[free_slot].state == DPTBD_FREE) {
                break;
            }
            free_slot += 1;
        }
        if (free_slot == DPTBD_CAPACITY) {
            t->stats.dropped_candidates += m - k;
            return;
        }
        r = &t->tracks[free_slot];
        row = (int32_t)t->inbuf[j].row * DPTBD_ONE;
        col = (int32_t)t->inbuf[j].col * DPTBD_ONE;
        memset(r, 0, sizeof *r);
        r->state = DPTBD_TENTATIVE;
        r->id = t->next_id++;
        r->first_seg = s;
        r->confirm_seg = -1;
        r->p_seg[0] = r->p_seg[1] = s;
        r->p_row[0] = r->p_row[1] = row;
        r->p_col[0] = r->p_col[1] = col;
        r->v_row = t->head_row[j];
        r->v_col = t->head_col[j];
        r->length = 1;
        r->hits = 1;
        r->counted = 1;
        r->count_seg = s;
        record_point(t, free_slot, j, s);
        t->stats.started++;
        if (p->confirm_hits <= 1) {                 /* a one-point output threshold */
            r->state = DPTBD_CONFIRMED;
            r->confirm_seg = s;
            t->stats.confirmed++;
        }
        r->pred_row = row + t->head_row[j];
        r->pred_col = col + t->head_col[j];
        r->gate = (uint16_t)min64(p->seed_gate, p->gate_max);
    }
}

uint32_t dptbd_track_active(const dptbd_tracker *t)
{
    uint32_t n = 0;
    int i;
    if (t == NULL || t->magic != DPTBD_MAGIC) {
        return 0;
    }
    for (i = 0; i < DPTBD_CAPACITY; ++i) {
        n += t->tracks[i].state != DPTBD_FREE;
    }
    return n;
}

/* Tracker.step */
dptbd_status dptbd_track_step(dptbd_tracker *t, const dptbd_candidate *list, uint32_t n,
                              dptbd_work *work)
{
    dptbd_work scratch;
    dptbd_status status = DPTBD_OK;
    uint32_t j, m = 0;
    int32_t s;
    int i;
    if (t == NULL || (list == NULL && n > 0)) {
        return DPTBD_E_NULL;
    }
    if (t->magic != DPTBD_MAGIC) {
        return DPTBD_E_NOT_INITIALISED;
    }
    if (t->segment == INT32_MAX) {
        return DPTBD_E_SEGMENTS;
    }
    if (work == NULL) {
        work = &scratch;
    }
    memset(work, 0, sizeof *work);
    if (n > DPTBD_MAX_CANDIDATES) {              /* clipped with a counter */
        t->stats.clipped_candidates += n - DPTBD_MAX_CANDIDATES;
        n = DPTBD_MAX_CANDIDATES;
        status |= DPTBD_W_CLIPPED;
    }
    for (j = 0; j < n; ++j) {                    /* the input buffer; bad records dropped */
        const dptbd_candidate *c = &list[j];
        if ((int32_t)c->row >= t->p.height || (int32_t)c->col >= t->p.width
                || (c->path && ((int32_t)c->row0 >= t->p.height || (int32_t)c->col0 >= t->p.width))) {
            t->stats.rejected_candidates++;
            status |= DPTBD_W_REJECTED;
            continue;
        }
        t->inbuf[m++] = *c;
    }
    n = m;
    t->n_in = n;
    t->segment += 1;
    s = t->segment;
    t->stats.segments++;
    t->stats.candidates += n;
    headings(t, n);
    suppress_clusters(t, n, work);
    classify(t);
    match_class(t, CLASS_CONFIRMED, n, work);
    match_class(t, CLASS_PREDICTED, n, work);
    match_class(t, CLASS_TENTATIVE, n, work);
    for (i = 0; i < DPTBD_CAPACITY; ++i) {
        if (t->tracks[i].state == DPTBD_FREE) {
            continue;
        }
        if (t->match[i] >= 0) {
            extend(t, i, (uint32_t)t->match[i], s);
        } else if (t->tracks[i].misses < 255) {
            t->tracks[i].misses += 1;
        }
        update(t, i, s);
    }
    remove_duplicates(t, work);
    suppress_wake(t, n, work);
    start_tracks(t, n, s, work);
    {
        uint32_t active = dptbd_track_active(t);
        if (active > t->stats.peak_active) {
            t->stats.peak_active = active;
        }
    }
    return status;
}

uint32_t dptbd_track_context_bytes(void)
{
    return (uint32_t)sizeof(dptbd_tracker);
}

uint32_t dptbd_track_build_info(int which)
{
    switch (which) {
    case 0: return DPTBD_CAPACITY;
    case 1: return DPTBD_MAX_CANDIDATES;
    case 2: return DPTBD_MAX_POINTS;
    case 3: return DPTBD_OUTPUT_CAPACITY;
    case 4: return (uint32_t)sizeof(dptbd_candidate);
    case 5: return (uint32_t)sizeof(dptbd_track);
    case 6: return (uint32_t)sizeof(dptbd_point);
    case 7: return (uint32_t)sizeof(dptbd_stats);
    default: return 0;
    }
}
