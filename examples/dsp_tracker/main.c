/*
 * dsp_tracker - the DSP stage on recorded candidate lists.
 *
 *   make -C examples/dsp_tracker                       # builds ./dsp_tracker
 *   python examples/dsp_tracker/write_candidates.py --seed 0 --out seed0.dptbd
 *   examples/dsp_tracker/dsp_tracker seed0.dptbd       # prints the confirmed tracks
 *
 * The file (little-endian, written by write_candidates.py):
 *   "DPTBDCL1"                       magic, 8 bytes
 *   u32 version (2; version 1 had 24 parameters)
 *   u32 layout[9]                    payload width; offset, width of row, col, energy, direction
 *   u32 capacities[4]                capacity, max_candidates, max_points, output_capacity
 *   i32 params[27]                   dptbd_params, in the struct's field order
 *   u32 n_segments
 *   per segment: u32 n, then n x { u64 payload (record, gateware layout); u16 row0; u16 col0; u8 path }
 *
 * Everything the file says is checked before it is used: a wrong magic, version, layout or
 * capacity, a truncated file, a trailer word among the records or trailing bytes is a
 * corrupt file (exit 2, one line on stderr naming what is wrong); parameters the firmware
 * refuses exit 3.  A list longer than DPTBD_MAX_CANDIDATES is passed whole-count to the
 * firmware, which takes the first DPTBD_MAX_CANDIDATES and counts the rest as clipped.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "dptbd_track.h"

/* the file's 27 parameters are copied straight into dptbd_params */
#define N_PARAMS 27
typedef char params_are_27_int32[sizeof(dptbd_params) == N_PARAMS * sizeof(int32_t) ? 1 : -1];

static dptbd_tracker tracker;                 /* the firmware's whole state */
static dptbd_candidate list[DPTBD_MAX_CANDIDATES];

static int corrupt(const char *path, const char *what, long where)
{
    fprintf(stderr, "dsp_tracker: %s: corrupt file: %s (at byte %ld)\n", path, what, where);
    return 2;
}

/* Read n little-endian bytes into *v; 0 at end of file. */
static int read_le(FILE *f, unsigned n, uint64_t *v)
{
    unsigned char b[8];
    unsigned i;
    if (fread(b, 1, n, f) != n) {
        return 0;
    }
    *v = 0;
    for (i = 0; i < n; ++i) {
        *v |= (uint64_t)b[i] << (8u * i);
    }
    return 1;
}

static int cmp_track(const void *a, const void *b)
{
    uint32_t x = (*(const dptbd_track *const *)a)->id, y = (*(const dptbd_track *const *)b)->id;
    return (x > y) - (x < y);
}

/* Every track ever confirmed, by id: its record, whether alive, its points oldest first
 * (the host-side read-out, as Tracker.confirmed_tracks). */
static void print_tracks(const dptbd_tracker *t)
{
    static const dptbd_track *found[DPTBD_ARCHIVE_SLOTS + DPTBD_CAPACITY];
    uint32_t n = 0, i, k;
    for (i = 0; i < t->n_archived; ++i) {
        found[n++] = &t->archive[i];
    }
    for (i = 0; i < DPTBD_CAPACITY; ++i) {
        if (t->tracks[i].state == DPTBD_CONFIRMED) {
            found[n++] = &t->tracks[i];
        }
    }
    qsort(found, n, sizeof found[0], cmp_track);
    printf("segments %lu, candidates %lu, started %lu, confirmed %lu, deleted %lu, "
           "clipped %lu, rejected %lu\n",
           (unsigned long)t->stats.segments, (unsigned long)t->stats.candidates,
           (unsigned long)t->stats.started, (unsigned long)t->stats.confirmed,
           (unsigned long)t->stats.deleted, (unsigned long)t->stats.clipped_candidates,
           (unsigned long)t->stats.rejected_candidates);
    printf("confirmed tracks: %lu\n", (unsigned long)n);
    for (k = 0; k < n; ++k) {
        const dptbd_track *r = found[k];
        int alive = r >= &t->tracks[0] && r < &t->tracks[DPTBD_CAPACITY];
        const dptbd_point *h = alive ? t->history[r - &t->tracks[0]]
                                     : t->archive_history[r - &t->archive[0]];
        uint32_t n_pts = r->n_points < DPTBD_MAX_POINTS ? r->n_points : DPTBD_MAX_POINTS;
        uint32_t start = r->n_points <= DPTBD_MAX_POINTS ? 0 : r->n_points % DPTBD_MAX_POINTS;
        printf("track %lu: segments %ld-%ld, confirmed in %ld, hits %u, %s\n",
               (unsigned long)r->id, (long)r->first_seg, (long)r->p_seg[1],
               (long)r->confirm_seg, (unsigned)r->hits, alive ? "alive" : "ended");
        for (i = 0; i < n_pts; ++i) {
            const dptbd_point *p = &h[(start + i) % DPTBD_MAX_POINTS];
            printf("  segment %ld: row %u col %u E %lu\n", (long)p->seg, (unsigned)p->row,
                   (unsigned)p->col, (unsigned long)p->energy);
        }
    }
}

int main(int argc, char **argv)
{
    static const uint32_t layout[9] = {
        DPTBD_PAYLOAD_WIDTH, DPTBD_RECORD_ROW_OFFSET, DPTBD_RECORD_ROW_WIDTH,
        DPTBD_RECORD_COL_OFFSET, DPTBD_RECORD_COL_WIDTH, DPTBD_RECORD_ENERGY_OFFSET,
        DPTBD_RECORD_ENERGY_WIDTH, DPTBD_RECORD_DIRECTION_OFFSET, DPTBD_RECORD_DIRECTION_WIDTH};
    static const uint32_t caps[4] = {DPTBD_CAPACITY, DPTBD_MAX_CANDIDATES, DPTBD_MAX_POINTS,
                                     DPTBD_OUTPUT_CAPACITY};
    int32_t params[N_PARAMS];
    dptbd_params p;
    char magic[8];
    uint64_t v, n_seg, s, n, j;
    unsigned i;
    const char *path;
    FILE *f;
    int rc = 0;
    if (argc != 2) {
        fprintf(stderr, "usage: dsp_tracker FILE   (FILE: write_candidates.py's output)\n");
        return 1;
    }
    path = argv[1];
    f = fopen(path, "rb");
    if (f == NULL) {
        fprintf(stderr, "dsp_tracker: cannot open %s\n", path);
        return 1;
    }
    if (fread(magic, 1, 8, f) != 8 || memcmp(magic, "DPTBDCL1", 8) != 0) {
        rc = corrupt(path, "not a candidate file (magic DPTBDCL1 missing)", 0);
        goto done;
    }
    if (!read_le(f, 4, &v) || v != 2) {
        rc = corrupt(path, "version is not 2", ftell(f));
        goto done;
    }
    for (i = 0; i < 9; ++i) {
        if (!read_le(f, 4, &v) || v != layout[i]) {
            rc = corrupt(path, "record layout differs from dptbd_candidate_record.h", ftell(f));
            goto done;
        }
    }
    for (i = 0; i < 4; ++i) {
        if (!read_le(f, 4, &v) || v != caps[i]) {
            rc = corrupt(path, "capacities differ from this build's DPTBD_* constants", ftell(f));
            goto done;
        }
    }
    for (i = 0; i < N_PARAMS; ++i) {
        if (!read_le(f, 4, &v)) {
            rc = corrupt(path, "truncated in the parameters", ftell(f));
            goto done;
        }
        params[i] = (int32_t)(uint32_t)v;
    }
    memcpy(&p, params, sizeof p);    /* dptbd_params is N_PARAMS int32_t, in file order */
    if (dptbd_track_init(&tracker, &p) != DPTBD_OK) {
        fprintf(stderr, "dsp_tracker: %s: the firmware refuses the parameters\n", path);
        rc = 3;
        goto done;
    }
    if (!read_le(f, 4, &n_seg)) {
        rc = corrupt(path, "truncated before the segment count", ftell(f));
        goto done;
    }
    for (s = 0; s < n_seg; ++s) {
        dptbd_status st;
        if (!read_le(f, 4, &n)) {
            rc = corrupt(path, "truncated at a list length", ftell(f));
            goto done;
        }
        for (j = 0; j < n; ++j) {
            uint64_t word, row0, col0, has_path;
            long where = ftell(f);
            if (!read_le(f, 8, &word) || !read_le(f, 2, &row0) || !read_le(f, 2, &col0)
                    || !read_le(f, 1, &has_path)) {
                rc = corrupt(path, "truncated inside a list", ftell(f));
                goto done;
            }
            if (dptbd_payload_is_trailer(word) || (word >> DPTBD_PAYLOAD_WIDTH) != 0) {
                rc = corrupt(path, "a word that is not a candidate record", where);
                goto done;
            }
            if (j < DPTBD_MAX_CANDIDATES) {   /* the rest is read past, and clipped below */
                dptbd_fpga_record rec = dptbd_unpack_record(word);
                dptbd_candidate *c = &list[j];
                c->row = rec.row;
                c->col = rec.col;
                c->energy = rec.energy;
                c->direction = rec.direction;
                c->row0 = (uint16_t)row0;
                c->col0 = (uint16_t)col0;
                c->path = (uint8_t)has_path;
            }
        }
        st = dptbd_track_step(&tracker, list, (uint32_t)n, NULL);
        if (st < 0) {
            fprintf(stderr, "dsp_tracker: the firmware refused segment %lu (status %d)\n",
                    (unsigned long)s, st);
            rc = 3;
            goto done;
        }
    }
    if (fgetc(f) != EOF) {
        rc = corrupt(path, "bytes after the last segment", ftell(f));
        goto done;
    }
    print_tracks(&tracker);
done:
    fclose(f);
    return rc;
}
