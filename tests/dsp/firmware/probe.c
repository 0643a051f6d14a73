/*
 * Test harness: the firmware's internal arithmetic and match cost, exported for
 * tests/dsp/test_c_tracker.py to compare with Python's integers and Tracker._cost.
 * It includes the firmware's source so its static functions are visible.
 */
#include "dptbd_track.c"

uint64_t probe_isqrt(uint64_t hi, uint64_t lo);
uint64_t probe_mul_div(uint64_t a, uint64_t b, uint64_t c);
int64_t probe_div_round(int64_t a, int64_t b);
int64_t probe_cost(const dptbd_tracker *t, int i, uint32_t j);

uint64_t probe_isqrt(uint64_t hi, uint64_t lo)
{
    u128 a;
    a.hi = hi;
    a.lo = lo;
    return isqrt_u128(a);
}

uint64_t probe_mul_div(uint64_t a, uint64_t b, uint64_t c) { return mul_div_u64(a, b, c); }

int64_t probe_div_round(int64_t a, int64_t b) { return div_round(a, b); }

int64_t probe_cost(const dptbd_tracker *t, int i, uint32_t j) { return cost_of(t, i, j); }
