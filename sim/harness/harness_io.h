// Helpers shared by dptbd's Verilator harnesses: the seeded pause generator, error exit,
// the binary word files (little-endian uint64), the job file's reading, the end of a run
// and Port (a design port as uint64 words).
// Header-only; included by dptbd_harness.cpp, dptbd_axi_harness.cpp and
// dptbd_dp_axi_harness.cpp.
#pragma once

#include <chrono>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <type_traits>
#include <vector>

#include "verilated.h"
#if VM_COVERAGE
#include "verilated_cov.h"
#endif
#ifdef DPTBD_MUTANT
#include <csignal>
#include <unistd.h>
#endif

namespace dptbd_harness {

// splitmix64: small, seedable, good enough for pause patterns and power-up garbage.
struct Rng {
    uint64_t state;
    uint64_t next() {
        uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        return z ^ (z >> 31);
    }
};

// Probability p in [0, 1) as a threshold on a uint64 draw: draw < threshold.
inline uint64_t threshold_of(double p) {
    if (p <= 0.0) return 0;
    return static_cast<uint64_t>(p * 18446744073709551616.0);  // 2^64
}

[[noreturn]] inline void fail(const std::string& msg) {
    std::fprintf(stderr, "dptbd_sim: %s\n", msg.c_str());
    std::exit(2);
}

inline std::vector<uint64_t> read_words(const std::string& path, uint64_t n) {
    std::vector<uint64_t> v(n);
    FILE* fh = std::fopen(path.c_str(), "rb");
    if (!fh) fail("cannot open " + path);
    if (n && std::fread(v.data(), sizeof(uint64_t), n, fh) != n) fail("short read " + path);
    std::fclose(fh);
    return v;
}

inline void write_words(const std::string& path, const std::vector<uint64_t>& v) {
    FILE* fh = std::fopen(path.c_str(), "wb");
    if (!fh) fail("cannot write " + path);
    if (!v.empty() && std::fwrite(v.data(), sizeof(uint64_t), v.size(), fh) != v.size())
        fail("short write " + path);
    std::fclose(fh);
}

// The job-file keys every harness reads: word count, seed, cycle limits, the pause
// probabilities of the input and output streams and, for a coverage build, the file the
// run's coverage data goes to (absent: nothing is written).
struct StreamJob {
    uint64_t words = 0, seed = 1, max_cycles = 0, drain = 64;
    double valid_gap = 0.0, ready_pause = 0.0;
    std::string coverage;
};

// Applies ``key rest`` to ``job`` if it is one of StreamJob's keys; false otherwise.
inline bool read_stream_key(const std::string& k, const char* rest, StreamJob& job) {
    if (k == "words") job.words = std::strtoull(rest, nullptr, 10);
    else if (k == "valid_gap") job.valid_gap = std::strtod(rest, nullptr);
    else if (k == "ready_pause") job.ready_pause = std::strtod(rest, nullptr);
    else if (k == "seed") job.seed = std::strtoull(rest, nullptr, 10);
    else if (k == "max_cycles") job.max_cycles = std::strtoull(rest, nullptr, 10);
    else if (k == "drain") job.drain = std::strtoull(rest, nullptr, 10);
    else if (k == "coverage") {
        char v[4096];
        if (std::sscanf(rest, "%4095s", v) != 1) fail("coverage needs a path");
        job.coverage = v;
    } else return false;
    return true;
}

// A coverage build (verilator --coverage-*, VM_COVERAGE) writes the run's points to the
// job's coverage file at the end; any other build refuses a job that asks for one.
inline void check_coverage_job(const StreamJob& job) {
#if !VM_COVERAGE
    if (!job.coverage.empty()) fail("coverage needs a coverage build (build(..., coverage=True))");
#else
    (void)job;
#endif
}

// JOB_DIR, the one argument of every harness (refused otherwise).
inline std::string job_dir(int argc, char** argv) {
    if (argc != 2) fail("usage: dptbd_sim JOB_DIR");
    return argv[1];
}

// The job file at ``path``: StreamJob's keys, then ``keys(k, rest, job)`` for the harness's
// own (false: not one of them, refused); max_cycles must be given.
template <class Job, class Keys>
Job read_job_file(const std::string& path, Keys keys) {
    Job job;
    FILE* fh = std::fopen(path.c_str(), "r");
    if (!fh) fail("cannot open " + path);
    char key[64], rest[4096];
    while (std::fscanf(fh, "%63s", key) == 1) {
        if (!std::fgets(rest, sizeof rest, fh)) rest[0] = 0;
        const std::string k(key);
        if (!read_stream_key(k, rest, job) && !keys(k, rest, job)) fail("unknown job key " + k);
    }
    std::fclose(fh);
    if (job.max_cycles == 0) fail("max_cycles must be given");
    return job;
}

// The seeded pauses of a run: an idle input cycle with probability valid_gap, output
// back-pressure with probability ready_pause, one generator each.
struct Pauses {
    Rng valid_rng, ready_rng;
    uint64_t gap_thr, pause_thr;
    explicit Pauses(const StreamJob& job)
        : valid_rng{job.seed * 2 + 1}, ready_rng{job.seed * 2 + 2},
          gap_thr(threshold_of(job.valid_gap)), pause_thr(threshold_of(job.ready_pause)) {}
    bool offer() { return !(gap_thr && valid_rng.next() < gap_thr); }
    bool ready() { return !(pause_thr && ready_rng.next() < pause_thr); }
};

inline double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The end of a run: the design's final(), then (a coverage build) the run's coverage points
// to the job's coverage file.
template <class Dut>
void finish(VerilatedContext* context, Dut* dut, const StreamJob& job) {
    dut->final();
#if VM_COVERAGE
    if (!job.coverage.empty()) context->coveragep()->write(job.coverage.c_str());
#else
    (void)context;
    (void)job;
#endif
}

// What every harness writes at the end of a run: the output words (out.bin), the cycle of
// each output (out_cycles.bin) and of each accepted input word (accept_cycles.bin), then
// JOB_DIR/result.txt with its first lines (status, cycles, words accepted, outputs), returned
// open for the harness's own lines (it closes it; refused if it cannot be written).
inline FILE* write_run(const std::string& dir, const std::vector<uint64_t>& out,
                       const std::vector<uint64_t>& out_cycles,
                       const std::vector<uint64_t>& accept_cycles, const std::string& status,
                       uint64_t cycles, uint64_t accepted, size_t outputs) {
    write_words(dir + "/out.bin", out);
    write_words(dir + "/out_cycles.bin", out_cycles);
    write_words(dir + "/accept_cycles.bin", accept_cycles);
    FILE* fh = std::fopen((dir + "/result.txt").c_str(), "w");
    if (!fh) fail("cannot write result.txt");
    std::fprintf(fh, "status %s\ncycles %" PRIu64 "\naccepted %" PRIu64 "\noutputs %zu\n",
                 status.c_str(), cycles, accepted, outputs);
    return fh;
}

#ifdef DPTBD_MUTANT
// Mutant builds (dptbd.sim.mutation): the design carries every sampled mutation behind its
// input port `mutsel` (0: the original). select_mutant drives `mutsel` from the environment
// variable DPTBD_MUTANT and, if DPTBD_MUTANT_SECONDS is set, ends the process with exit
// status 124 after that many seconds of wall-clock time (a mutant that hangs the model).
inline void mutant_alarm(int) { _exit(124); }
template <class Dut> void select_mutant(Dut* dut) {
    const char* index = std::getenv("DPTBD_MUTANT");
    dut->mutsel = index ? std::strtoul(index, nullptr, 10) : 0;
    const char* seconds = std::getenv("DPTBD_MUTANT_SECONDS");
    if (seconds && std::strtoul(seconds, nullptr, 10) > 0) {
        std::signal(SIGALRM, mutant_alarm);
        alarm(static_cast<unsigned>(std::strtoul(seconds, nullptr, 10)));
    }
}
#endif

// A port of up to 64 bits is an integer; a wider one (a beat of P pixels or states at
// P > 1, docs/gateware.md "P pixels per clock") is a VlWide<N> of N 32-bit words. Both
// travel as Port<T>::words uint64 words, the low bits first.
template <typename T>
struct Port {
    static constexpr size_t words = 1;
    static void set(T& port, const uint64_t* w) { port = static_cast<T>(w[0]); }
    static void get(const T& port, uint64_t* w) { w[0] = static_cast<uint64_t>(port); }
};
template <std::size_t N>
struct Port<VlWide<N>> {
    static constexpr size_t words = (N + 1) / 2;
    static void set(VlWide<N>& port, const uint64_t* w) {
        for (size_t i = 0; i < N; ++i) port.at(i) = static_cast<EData>(w[i / 2] >> (32 * (i % 2)));
    }
    static void get(const VlWide<N>& port, uint64_t* w) {
        for (size_t i = 0; i < words; ++i) w[i] = 0;
        for (size_t i = 0; i < N; ++i) w[i / 2] |= static_cast<uint64_t>(port.at(i)) << (32 * (i % 2));
    }
};
template <typename T>
using PortOf = Port<std::remove_cv_t<std::remove_reference_t<T>>>;

}  // namespace dptbd_harness
