/*
 * The firmware's bad-input behaviour, run under -fsanitize=address,undefined by
 * tests/dsp/firmware/test_init.py.  Prints "selftest: all passed" and exits 0, or names
 * the first failed check and exits 1.
 */
#include <stdio.h>
#include <string.h>

#include "dptbd_track.h"

static dptbd_tracker t;                     /* static: zeroed, i.e. not initialised */
static dptbd_candidate list[DPTBD_MAX_CANDIDATES + 8];
static uint8_t maps[3][5][6];

#define CHECK(cond) do { if (!(cond)) { printf("selftest: FAILED line %d: %s\n", __LINE__, #cond); return 1; } } while (0)

static dptbd_params defaults(void)
{
    dptbd_params p;
    memset(&p, 0, sizeof p);
    p.segment_frames = 6; p.segment_stride = 6; p.height = 128; p.width = 128; p.radius = 1;
    p.merge_radius = 1; p.duplicate_radius = 2; p.seed_gate = 48; p.gate_base = 40;
    p.gate_growth = 4; p.gate_miss = 16; p.gate_max = 112; p.gate_growth_segments = 8;
    p.manoeuvre = 48; p.link_gate = 0; p.heading_min = 16; p.heading_weight = 256;
    p.reject_reversed = 0; p.confirm_ratio = 154; p.predict_ratio = 128; p.delete_ratio = 102;
    p.confirm_hits = 4; p.predict_hits = 2; p.max_misses = 3; p.confirm_gap = 1;
    p.wake_radius = 0; p.wake_points = 2;
    return p;
}

int main(void)
{
    dptbd_params p = defaults(), bad;
    dptbd_work w;
    uint32_t i, few;
    int32_t seg;

    /* NULL context, NULL list, context never initialised */
    CHECK(dptbd_track_step(NULL, list, 1, NULL) == DPTBD_E_NULL);
    CHECK(dptbd_track_init(NULL, &p) == DPTBD_E_NULL);
    CHECK(dptbd_track_init(&t, NULL) == DPTBD_E_NULL);
    CHECK(dptbd_track_active(NULL) == 0);
    CHECK(dptbd_track_step(&t, list, 0, NULL) == DPTBD_E_NOT_INITIALISED);
    /* parameters out of range: refused, the context stays unusable */
    bad = p; bad.segment_stride = 0;
    CHECK(dptbd_track_init(&t, &bad) == DPTBD_E_PARAMS);
    CHECK(dptbd_track_step(&t, list, 0, NULL) == DPTBD_E_NOT_INITIALISED);
    bad = p; bad.confirm_ratio = 100;          /* below predict_ratio: thresholds unordered */
    CHECK(dptbd_track_init(&t, &bad) == DPTBD_E_PARAMS);
    bad = p; bad.height = 65537;
    CHECK(dptbd_track_init(&t, &bad) == DPTBD_E_PARAMS);
    bad = p; bad.confirm_gap = 0;              /* a hit counts at least a segment later */
    CHECK(dptbd_track_init(&t, &bad) == DPTBD_E_PARAMS);
    bad = p; bad.wake_radius = 17;
    CHECK(dptbd_track_init(&t, &bad) == DPTBD_E_PARAMS);
    bad = p; bad.wake_points = 0;
    CHECK(dptbd_track_init(&t, &bad) == DPTBD_E_PARAMS);

    CHECK(dptbd_track_init(&t, &p) == DPTBD_OK);
    CHECK(dptbd_track_step(&t, NULL, 0, NULL) == DPTBD_OK);        /* empty list, NULL ok */
    CHECK(dptbd_track_step(&t, NULL, 3, NULL) == DPTBD_E_NULL);
    CHECK(t.segment == 0);                                          /* refused: unchanged */

    /* a list longer than the capacity: the first DPTBD_MAX_CANDIDATES taken, rest counted;
     * only DPTBD_MAX_CANDIDATES records are read whatever n says */
    for (i = 0; i < DPTBD_MAX_CANDIDATES; ++i) {
        list[i].row = (uint16_t)(i % 128); list[i].col = (uint16_t)((i * 7) % 128);
        list[i].energy = 1000 + i; list[i].direction = (uint8_t)(i % 9);
        list[i].row0 = list[i].row; list[i].col0 = list[i].col; list[i].path = 1;
    }
    CHECK(dptbd_track_step(&t, list, 4000000000u, &w) == DPTBD_W_CLIPPED);
    CHECK(t.stats.clipped_candidates == 4000000000u - DPTBD_MAX_CANDIDATES);
    CHECK(t.stats.candidates == DPTBD_MAX_CANDIDATES);

    /* coordinates outside the frame: dropped and counted, the rest processed */
    list[0].row = 128; list[1].col = 60000; list[2].row0 = 200; list[2].path = 1;
    list[3].row0 = 200; list[3].path = 0;      /* no path: row0 unused, kept */
    few = DPTBD_MAX_CANDIDATES < 4 ? DPTBD_MAX_CANDIDATES : 4;
    CHECK(dptbd_track_step(&t, list, few, &w) == DPTBD_W_REJECTED);
    CHECK(t.stats.rejected_candidates == (few < 3 ? few : 3));
    CHECK(t.n_in == few - (few < 3 ? few : 3));
    CHECK(dptbd_track_step(&t, list, DPTBD_MAX_CANDIDATES + 1, NULL) == (DPTBD_W_CLIPPED | DPTBD_W_REJECTED));

    /* direction codes beyond the moves, extreme coordinates and paths: no overflow (UBSan) */
    p.height = 65536; p.width = 65536; p.segment_stride = 1024; p.segment_frames = 2;
    p.radius = 255; p.gate_max = 65535; p.seed_gate = 16000; p.gate_base = 16000;
    p.gate_growth = 1600; p.gate_miss = 16000; p.gate_growth_segments = 1000;
    p.heading_weight = 25600; p.link_gate = 16000; p.max_misses = 255; p.delete_ratio = 0;
    p.predict_ratio = 0; p.confirm_ratio = 0; p.confirm_hits = 1; p.predict_hits = 1;
    p.manoeuvre = 16000; p.heading_min = 0; p.reject_reversed = 1; p.confirm_gap = 2147483647;
    p.wake_radius = 16; p.wake_points = 65535;
    CHECK(dptbd_track_init(&t, &p) == DPTBD_OK);
    for (seg = 0; seg < 40; ++seg) {
        for (i = 0; i < DPTBD_MAX_CANDIDATES; ++i) {
            uint32_t k = (uint32_t)seg * 2654435761u + i * 40503u;
            list[i].row = (uint16_t)((i & 1) ? 65535 - (k % 7) : (k % 5));
            list[i].col = (uint16_t)((i & 2) ? 65535 - (k % 3) : (k % 11));
            list[i].row0 = (uint16_t)((i & 4) ? 0 : 65535);
            list[i].col0 = (uint16_t)((i & 8) ? 65535 : 0);
            list[i].energy = (i & 16) ? 0xffffffffu : k;
            list[i].direction = (uint8_t)(k & 0xff);
            list[i].path = (uint8_t)((i & 32) ? 0 : 1 + (k % 200));
        }
        CHECK(dptbd_track_step(&t, list, DPTBD_MAX_CANDIDATES, &w) >= 0);
    }
    /* the segment counter at its limit */
    seg = t.segment;
    t.segment = INT32_MAX;
    CHECK(dptbd_track_step(&t, list, 1, NULL) == DPTBD_E_SEGMENTS);
    t.segment = seg;
    CHECK(dptbd_track_step(&t, list, 1, NULL) == DPTBD_OK);
    /* backtracking: NULL, sizes, corrupt maps (START inside, paths leaving the frame) */
    {
        uint16_t r0 = 99, c0 = 99;
        dptbd_candidate one[3];
        memset(maps, 4, sizeof maps);                       /* d = 4: no move at r = 1 */
        CHECK(dptbd_backtrack(NULL, 3, 5, 6, 1, 0, 0, &r0, &c0) == DPTBD_E_NULL);
        CHECK(dptbd_backtrack(&maps[0][0][0], 3, 5, 6, 1, 0, 0, NULL, &c0) == DPTBD_E_NULL);
        CHECK(dptbd_backtrack(&maps[0][0][0], 3, 5, 6, 1, 5, 0, &r0, &c0) == DPTBD_E_PARAMS);
        CHECK(dptbd_backtrack(&maps[0][0][0], 3, 5, 6, 8, 0, 0, &r0, &c0) == DPTBD_E_PARAMS);
        CHECK(dptbd_backtrack(&maps[0][0][0], 3, 5, 6, 1, 4, 5, &r0, &c0) == DPTBD_OK);
        CHECK(r0 == 4 && c0 == 5);
        maps[2][0][0] = 0;                                  /* move (-1, -1) from (1, 1) */
        maps[1][1][1] = 9;                                  /* START inside the segment */
        maps[2][4][5] = 8;                                  /* move (1, 1) from (3, 4) */
        maps[1][3][4] = 8;                                  /* move (1, 1) from (2, 3) */
        maps[2][0][5] = 2;                                  /* move (-1, 1): from (1, 4) */
        maps[1][1][4] = 255;                                /* a code beyond every move */
        r0 = c0 = 99;
        CHECK(dptbd_backtrack(&maps[0][0][0], 3, 5, 6, 1, 0, 0, &r0, &c0) == DPTBD_E_MAPS);
        CHECK(r0 == 99 && c0 == 99);
        CHECK(dptbd_backtrack(&maps[0][0][0], 3, 5, 6, 1, 4, 5, &r0, &c0) == DPTBD_OK);
        CHECK(r0 == 2 && c0 == 3);
        maps[2][4][0] = 6;                                  /* move (1, -1): from (3, 1) */
        maps[1][3][1] = 6;                                  /* from (2, 2) */
        CHECK(dptbd_backtrack(&maps[0][0][0], 3, 5, 6, 1, 4, 0, &r0, &c0) == DPTBD_OK);
        maps[2][4][1] = 3;                                  /* move (0, -1): from (4, 2) */
        maps[1][4][2] = 2;                                  /* move (-1, 1): from (5, 1): off */
        CHECK(dptbd_backtrack(&maps[0][0][0], 3, 5, 6, 1, 4, 1, &r0, &c0) == DPTBD_E_MAPS);
        memset(one, 0, sizeof one);
        one[0].row = 0; one[0].col = 0; one[1].row = 4; one[1].col = 5; one[2].row = 0; one[2].col = 5;
        CHECK(dptbd_backtrack_list(&maps[0][0][0], 3, 5, 6, 1, one, 3) == 2);
        CHECK(one[0].path == 0 && one[0].row0 == 0 && one[1].path == 1 && one[1].row0 == 2);
        CHECK(one[2].path == 0 && one[2].col0 == 5);
        CHECK(dptbd_backtrack_list(&maps[0][0][0], 3, 5, 6, 1, NULL, 7) == 7);
    }
    /* the input trim: NULL, ties, a count above the list */
    {
        dptbd_candidate three[3];
        memset(three, 0, sizeof three);
        three[0].energy = 5; three[1].energy = 7; three[2].energy = 5;
        CHECK(dptbd_trim_to_count(NULL, 3, 1) == 0);
        CHECK(dptbd_trim_to_count(three, 3, 5) == 3);
        CHECK(dptbd_trim_to_count(three, 3, 2) == 1 && three[0].energy == 7);
        CHECK(dptbd_trim_to_count(three, 0, 0) == 0);
    }
    printf("selftest: all passed (context %lu bytes)\n", (unsigned long)dptbd_track_context_bytes());
    return 0;
}
