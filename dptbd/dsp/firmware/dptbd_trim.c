/*
 * dptbd_trim.c - the DSP's input stage: the constant-false-alarm-count rule applied to a
 * received list (dptbd.dsp.association.trim_to_count).  No state; in place.
 */
#include <string.h>

#include "dptbd_track.h"

uint32_t dptbd_trim_to_count(dptbd_candidate *list, uint32_t n, uint32_t count)
{
    uint32_t i, j, m = 0;
    uint32_t kth = 0;
    if (list == NULL) {
        return 0;
    }
    if (n <= count) {
        return n;
    }
    /* the (count + 1)-th largest E: the value with fewer than count + 1 records above it
     * and at least count + 1 at or above it (n^2 compares, no scratch memory) */
    for (i = 0; i < n; ++i) {
        uint32_t above = 0, at_or_above = 0;
        for (j = 0; j < n; ++j) {
            above += list[j].energy > list[i].energy;
            at_or_above += list[j].energy >= list[i].energy;
        }
        if (above <= count && at_or_above > count) {
            kth = list[i].energy;
            break;
        }
    }
    for (i = 0; i < n; ++i) {          /* keep E > kth, in the list's order */
        if (list[i].energy > kth) {
            list[m++] = list[i];
        }
    }
    return m;
}
