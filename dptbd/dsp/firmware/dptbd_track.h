/*
 * dptbd_track.h - the DSP stage of paper 001 (section 3, binary track association) as
 * portable C99 firmware.  The one public header: capacities, records, parameters, API.
 *
 * Reference: dptbd.dsp.association.Tracker (Python).  This code is checked against it
 * bit for bit after every segment (tests/dsp/test_c_tracker.py); docs/dsp_firmware.md
 * describes the API, the memory and work bounds and the behaviour on bad input.
 *
 * Rules kept by the implementation (dptbd_track.c):
 *   - no dynamic allocation, no floating point, no global mutable state: every byte of
 *     state is in one dptbd_tracker context, passed by pointer;
 *   - capacities are compile-time constants (override with -D...);
 *   - no library beyond <stdint.h> and <string.h>;
 *   - integer arithmetic only: positions and velocities in Q4 pixels (1/16 px), ratios in
 *     Q8 (1/256); parameters arrive as integer codes (dptbd_params).
 */
#ifndef DPTBD_TRACK_H
#define DPTBD_TRACK_H

#include <stdint.h>

#include "dptbd_candidate_record.h"

/* ---- compile-time capacities (AssociationConfig's capacity, max_candidates, max_points,
 *      output_capacity) ---- */
#ifndef DPTBD_CAPACITY
#define DPTBD_CAPACITY 64          /* track records */
#endif
#ifndef DPTBD_MAX_CANDIDATES
#define DPTBD_MAX_CANDIDATES 128   /* input buffer: candidates per segment */
#endif
#ifndef DPTBD_MAX_POINTS
#define DPTBD_MAX_POINTS 64        /* history ring per record */
#endif
#ifndef DPTBD_OUTPUT_CAPACITY
#define DPTBD_OUTPUT_CAPACITY 64   /* archive of finished confirmed tracks (may be 0) */
#endif

#if DPTBD_CAPACITY < 1 || DPTBD_CAPACITY > 65535
#error "DPTBD_CAPACITY must be in [1, 65535]"
#endif
#if DPTBD_MAX_CANDIDATES < 1 || DPTBD_MAX_CANDIDATES > 65535
#error "DPTBD_MAX_CANDIDATES must be in [1, 65535]"
#endif
#if DPTBD_MAX_POINTS < 1 || DPTBD_MAX_POINTS > 65535
#error "DPTBD_MAX_POINTS must be in [1, 65535]"
#endif
#if DPTBD_OUTPUT_CAPACITY < 0 || DPTBD_OUTPUT_CAPACITY > 65535
#error "DPTBD_OUTPUT_CAPACITY must be in [0, 65535]"
#endif
/* C99 has no zero-length arrays: an empty archive still reserves one (unused) slot. */
#define DPTBD_ARCHIVE_SLOTS (DPTBD_OUTPUT_CAPACITY > 0 ? DPTBD_OUTPUT_CAPACITY : 1)

/* ---- fixed point ---- */
#define DPTBD_Q_BITS 4
#define DPTBD_ONE (1 << DPTBD_Q_BITS)        /* 1 pixel in Q4 */
#define DPTBD_RATIO_BITS 8
#define DPTBD_RATIO_ONE (1 << DPTBD_RATIO_BITS)

/* ---- record states ---- */
#define DPTBD_FREE 0
#define DPTBD_TENTATIVE 1
#define DPTBD_CONFIRMED 2

/* ---- status codes: negative = refused, nothing changed; positive = warning bits, the
 *      segment was processed ---- */
typedef int dptbd_status;
#define DPTBD_OK 0
#define DPTBD_W_CLIPPED 1          /* list longer than DPTBD_MAX_CANDIDATES: tail dropped */
#define DPTBD_W_REJECTED 2         /* candidates outside the frame dropped */
#define DPTBD_E_NULL (-1)          /* NULL context, or NULL list with n > 0 */
#define DPTBD_E_PARAMS (-2)        /* a parameter outside its range (dptbd_track_init) */
#define DPTBD_E_NOT_INITIALISED (-3) /* context not set up by dptbd_track_init */
#define DPTBD_E_SEGMENTS (-4)      /* segment counter exhausted (2^31 - 1 segments) */
#define DPTBD_E_MAPS (-5)          /* dptbd_backtrack: START inside a segment, or the path
                                      leaves the frame (corrupt direction maps) */

/* One candidate as the tracker receives it: the FPGA's record (row, col, E, d; wire
 * layout in dptbd_candidate_record.h) and the start (row0, col0) of its backtracked DP
 * path in the segment; path = 1 when row0/col0 are known (Python: CANDIDATE_DTYPE). */
typedef struct {
    uint32_t energy;
    uint16_t row, col;
    uint16_t row0, col0;
    uint8_t direction;
    uint8_t path;
} dptbd_candidate;

/* One track record, 001 section 3's record structure (Python: TRACK_DTYPE, 72 bytes). */
typedef struct {
    uint32_t id;             /* unique track number, from 1 */
    int32_t first_seg;       /* segment of the first point */
    int32_t confirm_seg;     /* segment of confirmation, -1 */
    int32_t p_seg[2];        /* last two points [older, newest]: segments */
    int32_t p_row[2];        /*   rows, Q4 */
    int32_t p_col[2];        /*   cols, Q4 */
    int32_t v_row, v_col;    /* velocity, Q4 pixels per segment */
    int32_t pred_row, pred_col; /* predicted point for the next segment, Q4 */
    int32_t count_seg;       /* segment of the newest hit counted toward confirmation */
    uint32_t n_points;       /* points ever written to the history ring */
    uint16_t length;         /* segments since the first point, inclusive (saturates) */
    uint16_t hits;           /* matched points (saturates) */
    uint16_t gate;           /* allowed deviation, Q4 pixels (Euclidean radius) */
    uint16_t counted;        /* hits counted toward confirmation (saturates) */
    uint8_t state;           /* DPTBD_FREE, DPTBD_TENTATIVE, DPTBD_CONFIRMED */
    uint8_t misses;          /* consecutive misses (saturates at 255) */
} dptbd_track;

/* One measured point of a track's history (Python: POINT_DTYPE). */
typedef struct {
    int32_t seg;
    uint32_t energy;
    uint16_t row, col;
    uint16_t row0, col0;
    uint8_t path;
} dptbd_point;

/* Parameters as integer codes (quantised once on the host: Tracker.__init__'s codes). */
typedef struct {
    int32_t segment_frames;       /* K, >= 1 */
    int32_t segment_stride;       /* S_t, 1 .. 1024 */
    int32_t height, width;        /* frame size, 1 .. 65536 */
    int32_t radius;               /* DP search radius r, 0 .. 255 (moves of d) */
    int32_t merge_radius;         /* pixels, 0 .. 16 */
    int32_t duplicate_radius;     /* pixels, 0 .. 1000 */
    int32_t seed_gate, gate_base, gate_growth, gate_miss, gate_max; /* Q4, 0 .. 16000 (gate_max .. 65535) */
    int32_t gate_growth_segments; /* 0 .. 1000 */
    int32_t manoeuvre, link_gate, heading_min; /* Q4, 0 .. 16000 */
    int32_t heading_weight;       /* Q8, 0 .. 25600 */
    int32_t reject_reversed;      /* 0 or 1 */
    int32_t confirm_ratio, predict_ratio, delete_ratio; /* Q8, 0 .. 256 */
    int32_t confirm_hits, predict_hits; /* 1 .. 65535 */
    int32_t max_misses;           /* 0 .. 255 */
    int32_t confirm_gap;          /* >= 1: a hit counts toward confirm_hits only if it is at
                                     least this many segments after the previous counted
                                     one (1: every hit; confirm_disjoint: ceil(K / S_t)) */
    int32_t wake_radius;          /* pixels, 0 .. 16 (0: off) */
    int32_t wake_points;          /* 1 .. 65535 newest history points of a track's wake */
} dptbd_params;

/* Counters: the Python Tracker's stats, plus the two bad-input counters. */
typedef struct {
    uint64_t segments, candidates, suppressed, matched, started, confirmed, deleted;
    uint64_t left_image, dropped_candidates, dropped_outputs, history_wrapped, duplicates;
    uint64_t peak_active;
    uint64_t wake_suppressed;     /* leftover candidates on a track's recent path */
    uint64_t clipped_candidates;  /* beyond DPTBD_MAX_CANDIDATES in one list (not processed) */
    uint64_t rejected_candidates; /* row/col (or row0/col0 with path) outside the frame */
} dptbd_stats;

/* The whole state: records, histories, archive, input buffer and scratch.  Static
 * memory: sizeof(dptbd_tracker) bytes (dptbd_track_context_bytes()). */
typedef struct {
    uint32_t magic;               /* set by dptbd_track_init */
    dptbd_params p;
    int32_t segment;              /* index of the last segment processed, -1 */
    uint32_t next_id;
    uint32_t n_archived;
    uint32_t n_in;
    dptbd_stats stats;
    dptbd_track tracks[DPTBD_CAPACITY];
    dptbd_point history[DPTBD_CAPACITY][DPTBD_MAX_POINTS];
    dptbd_track archive[DPTBD_ARCHIVE_SLOTS];
    dptbd_point archive_history[DPTBD_ARCHIVE_SLOTS][DPTBD_MAX_POINTS];
    dptbd_candidate inbuf[DPTBD_MAX_CANDIDATES];
    /* scratch, rewritten every segment */
    int32_t head_row[DPTBD_MAX_CANDIDATES], head_col[DPTBD_MAX_CANDIDATES];
    uint16_t order[DPTBD_MAX_CANDIDATES];
    uint8_t keep[DPTBD_MAX_CANDIDATES], claimed[DPTBD_MAX_CANDIDATES];
    int32_t match[DPTBD_CAPACITY];
    uint16_t order_tracks[DPTBD_CAPACITY];
    uint8_t cls[DPTBD_CAPACITY];
} dptbd_tracker;

/* Work counters of the last dptbd_track_step (for the bound measurements); a separate
 * struct so the caller decides whether to keep it. */
typedef struct {
    uint32_t suppression_tests;   /* candidate pairs compared in cluster suppression */
    uint32_t sort_compares;       /* insertion-sort compares (tracks and new tracks) */
    uint32_t cost_evaluations;    /* match cost evaluations */
    uint32_t duplicate_tests;     /* track pairs compared for duplicates */
    uint32_t wake_tests;          /* history points compared in wake suppression */
    uint32_t free_probes;         /* record slots probed for new tracks */
} dptbd_work;

/* Set up a context (fills it completely: no prior memset needed).  DPTBD_E_NULL if t or p
 * is NULL; DPTBD_E_PARAMS if a parameter is outside its range (t is then marked not
 * initialised). */
dptbd_status dptbd_track_init(dptbd_tracker *t, const dptbd_params *p);

/* Associate one segment's candidates (n may be 0; list may be NULL when n = 0).
 * Returns DPTBD_OK, or warning bits DPTBD_W_CLIPPED | DPTBD_W_REJECTED (segment processed,
 * bad candidates dropped and counted), or a negative error (nothing changed).
 * work may be NULL. */
dptbd_status dptbd_track_step(dptbd_tracker *t, const dptbd_candidate *list, uint32_t n,
                              dptbd_work *work);

/* Records in use; 0 for a NULL or uninitialised context. */
uint32_t dptbd_track_active(const dptbd_tracker *t);

/* Size of the context in bytes (for hosts that allocate it, e.g. through ctypes). */
uint32_t dptbd_track_context_bytes(void);

/* Compiled capacities: which = 0 capacity, 1 max_candidates, 2 max_points,
 * 3 output_capacity; 4 .. 7: sizeof candidate, track, point, stats; else 0. */
uint32_t dptbd_track_build_info(int which);

/* ---- backtracking (dptbd_backtrack.c; no state) ----
 * The start (row0, col0), in the segment's first frame, of the best path ending at
 * (row, col) in its last frame: K - 1 look-ups in the segment's direction maps
 * maps[k][r][c] (frames x height x width bytes, d codes of dptbd.hw's layout, radius
 * r <= 7).  DPTBD_E_NULL, DPTBD_E_PARAMS (sizes, or (row, col) outside the frame) or
 * DPTBD_E_MAPS (START inside the segment, or a path leaving the frame); *row0, *col0 are
 * written only on DPTBD_OK. */
dptbd_status dptbd_backtrack(const uint8_t *maps, int32_t frames, int32_t height, int32_t width,
                             int32_t radius, uint16_t row, uint16_t col,
                             uint16_t *row0, uint16_t *col0);

/* dptbd_backtrack for each candidate of a list: row0, col0 and path = 1 on success; on
 * failure row0 = row, col0 = col, path = 0 (the tracker then uses d alone).  Returns the
 * number of failures (n if list is NULL). */
uint32_t dptbd_backtrack_list(const uint8_t *maps, int32_t frames, int32_t height,
                              int32_t width, int32_t radius, dptbd_candidate *list, uint32_t n);

/* ---- the input trim (dptbd_trim.c; no state) ----
 * The constant-false-alarm-count rule on a received list, in place: keeps the records
 * whose E exceeds the (count + 1)-th largest E of the list (all of them when n <= count),
 * in the list's order, and returns how many (0 for a NULL list).  n^2 compares. */
uint32_t dptbd_trim_to_count(dptbd_candidate *list, uint32_t n, uint32_t count);

#endif /* DPTBD_TRACK_H */
