// Verilator harness of dptbd's generated Verilog: streams a whole input word sequence
// through the design, cycle by cycle, with seeded stimulus, and writes every output
// transfer with its cycle. No Python runs per cycle; dptbd.sim.verilator drives this
// program with binary files (see docs/gateware.md, "Compiled RTL simulation").
//
// One source for three top levels, chosen at compile time:
//   DPTBD_DESIGN_DP    dptbd_dp  (DPPipeline: on-chip state store, output `states`)
//   DPTBD_DESIGN_CORE  dptbd_dp  (DPCore: the state store is the C++ model below)
//   DPTBD_DESIGN_SEG   dptbd_seg (DPSegmenter: DP + segmenter, output `candidates`)
// DPTBD_TRACE adds an FST waveform (verilator --trace-fst).
//
// Usage: dptbd_sim JOB_DIR
//   JOB_DIR/job.txt   one "key value..." per line:
//                       words N              input words in in.bin
//                       valid_gap P          probability of an idle input cycle, [0, 1)
//                       ready_pause P        probability of output back-pressure, [0, 1)
//                       seed S               seeds both pause generators (and the store)
//                       max_cycles N         give up after N cycles (reported as timeout)
//                       drain N              stop once every word is in and the output
//                                            has been idle (valid low) for N cycles
//                       store_init zero|random   DPCore's external store at power-up
//                       reset C H            hold rst high in cycles C .. C+H-1 (sorted)
//                       lut I A D            before offering input word I, write code D
//                                            to LUT entry A (one write per cycle, sorted)
//                       settings I K N S     from offering input word I on, drive the
//                                            run-time settings K (segment_frames) and, on
//                                            dptbd_seg, n (candidate_count), s
//                                            (histogram_shift); sorted. The ports are 0
//                                            until the first line applies: give one for 0.
//                       trace PATH           FST file (DPTBD_TRACE builds only)
//                       coverage PATH        write the run's VerilatedCov data there at
//                                            the end (coverage builds only)
//   JOB_DIR/in.bin    N little-endian uint64 input payloads (pixel | first << B_in); a
//                     payload wider than 64 bits (a beat of P pixels, P > 1) is
//                     ceil(bits / 64) uint64 words, the low bits first: N times as many
// Writes into JOB_DIR:
//   out.bin           uint64 payload of every output transfer, in order (as in.bin:
//                     ceil(bits / 64) words each for a payload wider than 64 bits)
//   out_cycles.bin    uint64 cycle of each output transfer
//   accept_cycles.bin uint64 cycle in which each input word was accepted
//   result.txt        "key value" lines: status, cycles, accepted, outputs, seconds, the
//                     counts of the `events` pulses (events_frame_done, ...), ...
// Cycle 0 is the first simulated cycle; rst is high in cycles 0 and 1 (power-up reset).
// A transfer is valid & ready sampled before a rising edge at which rst is low: a word
// on offer while rst is high is not taken, and the source offers it again after reset.
#include <algorithm>
#include <chrono>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "Vdut.h"
#include "harness_io.h"
#include "verilated.h"
#ifdef DPTBD_TRACE
#include "verilated_fst_c.h"
#endif

// Amaranth names stream members `pixels__valid`; Verilator escapes "__" as "___05F".
#define PORT(group, member) dut->group##___05F##member
#if defined(DPTBD_DESIGN_SEG)
#define OUT_PORT(member) PORT(candidates, member)
#elif defined(DPTBD_DESIGN_DP) || defined(DPTBD_DESIGN_CORE)
#define OUT_PORT(member) PORT(states, member)
#else
#error "define one of DPTBD_DESIGN_DP, DPTBD_DESIGN_CORE, DPTBD_DESIGN_SEG"
#endif

namespace {

using dptbd_harness::Rng;
using dptbd_harness::fail;
using dptbd_harness::read_words;

using dptbd_harness::PortOf;

struct Reset { uint64_t cycle, hold; };
struct LutWrite { uint64_t before_word, addr, data; };
struct Settings { uint64_t before_word, k, n, s; };

struct Job : dptbd_harness::StreamJob {
    std::string store_init = "zero", trace;
    std::vector<Reset> resets;
    std::vector<LutWrite> luts;
    std::vector<Settings> settings;
};

}  // namespace

int main(int argc, char** argv) {
    const std::string dir = dptbd_harness::job_dir(argc, argv);
    const Job job = dptbd_harness::read_job_file<Job>(dir + "/job.txt", [](
            const std::string& k, const char* rest, Job& into) {
        if (k == "store_init") {
            char v[64];
            if (std::sscanf(rest, "%63s", v) != 1) fail("store_init needs a value");
            into.store_init = v;
        } else if (k == "trace") {
            char v[4096];
            if (std::sscanf(rest, "%4095s", v) != 1) fail("trace needs a path");
            into.trace = v;
        } else if (k == "reset") {
            Reset r{};
            if (std::sscanf(rest, "%" SCNu64 " %" SCNu64, &r.cycle, &r.hold) != 2)
                fail("reset needs CYCLE HOLD");
            into.resets.push_back(r);
        } else if (k == "lut") {
            LutWrite w{};
            if (std::sscanf(rest, "%" SCNu64 " %" SCNu64 " %" SCNu64, &w.before_word,
                            &w.addr, &w.data) != 3)
                fail("lut needs WORD ADDR DATA");
            into.luts.push_back(w);
        } else if (k == "settings") {
            Settings w{};
            if (std::sscanf(rest, "%" SCNu64 " %" SCNu64 " %" SCNu64 " %" SCNu64,
                            &w.before_word, &w.k, &w.n, &w.s) != 4)
                fail("settings needs WORD K N S");
            into.settings.push_back(w);
        } else return false;
        return true;
    });
    dptbd_harness::check_coverage_job(job);
    auto context = std::make_unique<VerilatedContext>();
    auto dut = std::make_unique<Vdut>(context.get());
    using InPort = PortOf<decltype(PORT(pixels, payload))>;
    using OutPort = PortOf<decltype(OUT_PORT(payload))>;
    const std::vector<uint64_t> in = read_words(dir + "/in.bin", job.words * InPort::words);
    const std::vector<uint64_t> no_input(InPort::words, 0);
    std::vector<uint64_t> out_payload(OutPort::words, 0);
#ifdef DPTBD_MUTANT
    dptbd_harness::select_mutant(dut.get());
#endif
#ifdef DPTBD_TRACE
    std::unique_ptr<VerilatedFstC> tfp;
    if (!job.trace.empty()) {
        context->traceEverOn(true);
        tfp = std::make_unique<VerilatedFstC>();
        dut->trace(tfp.get(), 99);
        tfp->open(job.trace.c_str());
    }
#endif

#ifdef DPTBD_DESIGN_CORE
    // The external state store: W*H words, one synchronous read port (the word read in
    // cycle t is on read_data in cycle t+1), one write port, read before write.
    // A word of DPTBD_STORE_BITS (P states at P > 1) is StorePort::words uint64s.
    using StorePort = PortOf<decltype(PORT(state_store, read_data))>;
    constexpr size_t sw = StorePort::words;
    const uint64_t store_words = DPTBD_STORE_WORDS;
    const uint64_t top_bits = DPTBD_STORE_BITS - 64 * (sw - 1);
    const uint64_t store_mask = (top_bits >= 64) ? ~0ULL : ((1ULL << top_bits) - 1);
    std::vector<uint64_t> store(store_words * sw, 0);
    if (job.store_init == "random") {
        Rng garbage{job.seed ^ 0x5A5A5A5A5A5A5A5AULL};
        for (size_t i = 0; i < store.size(); ++i)
            store[i] = garbage.next() & (i % sw == sw - 1 ? store_mask : ~0ULL);
    } else if (job.store_init != "zero") {
        fail("store_init must be zero or random");
    }
    std::vector<uint64_t> read_data(sw, 0), write_data(sw, 0);
    uint64_t store_faults = 0;
#endif

    dptbd_harness::Pauses pauses(job);

    std::vector<uint64_t> out, out_cycles, accept_cycles(job.words, ~0ULL);
    out.reserve(job.words + 1024);
    out_cycles.reserve(job.words + 1024);

    uint64_t next_word = 0;       // index of the next input word to offer
    bool offering = false;        // valid is high with in[next_word]
    size_t next_lut = 0, next_reset = 0, next_settings = 0;
    uint64_t events_frame = 0, events_segment = 0, events_list = 0, events_saturated = 0;
#if defined(DPTBD_DESIGN_DP) || defined(DPTBD_DESIGN_CORE)
    // `segment_begin` pulses, and the sum of (index + 1) of the words accepted with one
    uint64_t segment_begins = 0, segment_begin_words = 0;
#endif
    uint64_t reset_until = 2;     // power-up reset: cycles 0, 1
    uint64_t idle = 0, cycle = 0, lut_writes = 0, stalled_in = 0, paused_out = 0;
    std::string status = "timeout";

    dut->clk = 0;
    dut->rst = 1;
    dut->eval();
    const auto t0 = std::chrono::steady_clock::now();
    for (; cycle < job.max_cycles; ++cycle) {
        // ---- drive the inputs of this cycle -------------------------------------
        if (next_reset < job.resets.size() && job.resets[next_reset].cycle == cycle) {
            reset_until = cycle + job.resets[next_reset].hold;
            ++next_reset;
        }
        const bool rst = cycle < reset_until;
        dut->rst = rst;
        while (next_settings < job.settings.size()
               && job.settings[next_settings].before_word <= next_word && !offering) {
            const Settings& w = job.settings[next_settings++];
            dut->segment_frames = w.k;
#ifdef DPTBD_DESIGN_SEG
            dut->candidate_count = w.n;
            dut->histogram_shift = w.s;
#endif
        }
        dut->lut_we = 0;
        const bool lut_due = next_lut < job.luts.size()
                             && job.luts[next_lut].before_word == next_word;
        if (!offering && lut_due) {
            if (!rst) {           // the writes come first; the word waits for them
                dut->lut_addr = job.luts[next_lut].addr;
                dut->lut_data = job.luts[next_lut].data;
                dut->lut_we = 1;
                ++next_lut;
                ++lut_writes;
            }
        } else if (!offering && next_word < job.words) {
            offering = pauses.offer();
        }
        PORT(pixels, valid) = offering;
        InPort::set(PORT(pixels, payload),
                    offering ? &in[next_word * InPort::words] : no_input.data());
        const bool ready = pauses.ready();
        OUT_PORT(ready) = ready;
#ifdef DPTBD_DESIGN_CORE
        StorePort::set(PORT(state_store, read_data), read_data.data());
#endif
        dut->clk = 0;
        dut->eval();
#ifdef DPTBD_TRACE
        if (tfp) tfp->dump(2 * cycle);
#endif
        // ---- sample the handshakes before the rising edge ----------------------
        const bool out_valid = OUT_PORT(valid);
        const bool input_busy = offering || dut->lut_we;   // the input side is not done
        if (!rst) {
#if defined(DPTBD_DESIGN_DP) || defined(DPTBD_DESIGN_CORE)
            if (dut->segment_begin) {
                ++segment_begins;
                if (offering && PORT(pixels, ready)) segment_begin_words += next_word + 1;
            }
#endif
            if (offering && PORT(pixels, ready)) {
                accept_cycles[next_word] = cycle;
                ++next_word;
                offering = false;
            } else if (offering) {
                ++stalled_in;
            }
            // `events` (dptbd.hw.layouts.event_layout): frame_done, segment_done,
            // list_done, saturated from bit 0 up
            const uint64_t events = dut->events;
            events_frame += events & 1;
            events_segment += (events >> 1) & 1;
            events_list += (events >> 2) & 1;
            events_saturated += (events >> 3) & 1;
            if (out_valid && ready) {
                OutPort::get(OUT_PORT(payload), out_payload.data());
                out.insert(out.end(), out_payload.begin(), out_payload.end());
                out_cycles.push_back(cycle);
            } else if (out_valid) {
                ++paused_out;
            }
        }
#ifdef DPTBD_DESIGN_CORE
        if (PORT(state_store, read_en)) {
            const uint64_t a = PORT(state_store, read_addr);
            if (a < store_words)
                read_data.assign(store.begin() + a * sw, store.begin() + (a + 1) * sw);
            else ++store_faults;
        }
        if (PORT(state_store, write_en)) {
            const uint64_t a = PORT(state_store, write_addr);
            if (a < store_words) {
                StorePort::get(PORT(state_store, write_data), write_data.data());
                write_data[sw - 1] &= store_mask;
                std::copy(write_data.begin(), write_data.end(), store.begin() + a * sw);
            } else {
                ++store_faults;
            }
        }
#endif
        dut->clk = 1;
        dut->eval();
#ifdef DPTBD_TRACE
        if (tfp) tfp->dump(2 * cycle + 1);
#endif
        // ---- finished: every word in, then the output idle for `drain` cycles ---
        idle = (out_valid || rst || input_busy) ? 0 : idle + 1;
        if (next_word == job.words && next_lut == job.luts.size()
                && next_reset == job.resets.size() && idle >= job.drain) {
            status = "done";
            ++cycle;
            break;
        }
    }
    const double seconds = dptbd_harness::seconds_since(t0);
#ifdef DPTBD_TRACE
    if (tfp) tfp->close();
#endif
    dptbd_harness::finish(context.get(), dut.get(), job);

    FILE* fh = dptbd_harness::write_run(dir, out, out_cycles, accept_cycles, status, cycle,
                                        next_word, out.size() / OutPort::words);
    std::fprintf(fh, "lut_writes %" PRIu64 "\nstalled_input_cycles %" PRIu64 "\n"
                 "paused_output_cycles %" PRIu64 "\nseconds %.9f\n"
                 "events_frame_done %" PRIu64 "\nevents_segment_done %" PRIu64 "\n"
                 "events_list_done %" PRIu64 "\nevents_saturated %" PRIu64 "\n",
                 lut_writes, stalled_in, paused_out, seconds, events_frame, events_segment,
                 events_list, events_saturated);
#ifdef DPTBD_DESIGN_CORE
    std::fprintf(fh, "store_faults %" PRIu64 "\n", store_faults);
#endif
#if defined(DPTBD_DESIGN_DP) || defined(DPTBD_DESIGN_CORE)
    std::fprintf(fh, "segment_begins %" PRIu64 "\nsegment_begin_words %" PRIu64 "\n",
                 segment_begins, segment_begin_words);
#endif
    std::fclose(fh);
    return 0;
}
