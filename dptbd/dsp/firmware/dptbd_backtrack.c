/*
 * dptbd_backtrack.c - the start of a candidate's best path in its segment, by walking back
 * through the segment's K direction maps (paper 001 section 2, the backward method).
 * Reference: dptbd.dsp.backtrack.backtrack (its first point); checked bit for bit in
 * tests/dsp/test_c_tracker.py.  No state: the maps are the caller's buffer.
 */
#include <string.h>

#include "dptbd_track.h"

dptbd_status dptbd_backtrack(const uint8_t *maps, int32_t frames, int32_t height, int32_t width,
                             int32_t radius, uint16_t row, uint16_t col,
                             uint16_t *row0, uint16_t *col0)
{
    int64_t side, r = row, c = col, plane;
    int32_t k;
    if (maps == NULL || row0 == NULL || col0 == NULL) {
        return DPTBD_E_NULL;
    }
    if (frames < 1 || height < 1 || height > 65536 || width < 1 || width > 65536
            || radius < 0 || radius > 7 || r >= height || c >= width) {
        return DPTBD_E_PARAMS;
    }
    side = 2 * (int64_t)radius + 1;
    plane = (int64_t)height * width;
    for (k = frames - 1; k > 0; --k) {
        int64_t d = maps[(int64_t)k * plane + r * width + c];
        if (d >= side * side) {            /* START (or worse) inside a segment */
            return DPTBD_E_MAPS;
        }
        r -= d / side - radius;
        c -= d % side - radius;
        if (r < 0 || r >= height || c < 0 || c >= width) {
            return DPTBD_E_MAPS;          /* the path left the frame: corrupt maps */
        }
    }
    *row0 = (uint16_t)r;
    *col0 = (uint16_t)c;
    return DPTBD_OK;
}

uint32_t dptbd_backtrack_list(const uint8_t *maps, int32_t frames, int32_t height,
                              int32_t width, int32_t radius, dptbd_candidate *list, uint32_t n)
{
    uint32_t j, failed = 0;
    if (list == NULL) {
        return n;
    }
    for (j = 0; j < n; ++j) {
        dptbd_candidate *cand = &list[j];
        if (dptbd_backtrack(maps, frames, height, width, radius, cand->row, cand->col,
                            &cand->row0, &cand->col0) == DPTBD_OK) {
            cand->path = 1;
        } else {
            cand->row0 = cand->row;
            cand->col0 = cand->col;
            cand->path = 0;
            failed++;
        }
    }
    return failed;
}
