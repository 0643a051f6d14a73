// Verilator harness of dptbd_dp built with --state-store axi (DPPipelineAxi): streams an
// input word sequence through the design, its state in a C++ AXI4 memory model below, and
// writes every output transfer. dptbd.sim.verilator.dp_axi builds and drives it. At P > 1
// pixels per clock a payload wider than 64 bits (a beat of P pixels or states) travels as
// several uint64 words, the low bits first, in in.bin and out.bin.
//
// The memory is the shared model of axi4_memory.h (random latency per burst, random
// ready / valid, every AXI4 rule it sees checked, optional SLVERR or DECERR responses in a cycle window).
//
// Compile-time: DPTBD_AXI_DATA_BITS (32, 64 or 128), DPTBD_AXI_OUTSTANDING,
// DPTBD_FRAME_BYTES.
// Usage: dptbd_sim JOB_DIR; JOB_DIR/job.txt holds the StreamJob keys (harness_io.h) and
//   the memory's keys (axi4_memory.h: latency, write_latency, axi_ready, axi_valid,
//   base, read_error, write_error, error_cycles, error_response); state_base is driven
//   with base
//   segment_frames K       the run-time K driven on segment_frames
// JOB_DIR/in.bin: input payloads (words: beats). Writes out.bin, out_cycles.bin, accept_cycles.bin and
// result.txt (status, cycles, accepted, outputs, seconds, read_bursts, write_bursts,
// violations, first_violation, read_errors, write_errors: cycles read_error / write_error
// was high, read_error_beats, write_error_bursts: error beats / responses the memory sent,
// and the memory's observed counters).
#include <chrono>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "Vdut.h"
#include "axi4_memory.h"
#include "harness_io.h"
#include "verilated.h"

#define PORT(group, member) dut->group##___05F##member

namespace {

using dptbd_harness::fail;
using dptbd_harness::read_words;

using Memory = dptbd_harness::Axi4Memory<Vdut, DPTBD_AXI_DATA_BITS>;

using dptbd_harness::PortOf;

struct Job : dptbd_harness::StreamJob {
    dptbd_harness::Axi4MemoryJob memory;
    uint64_t k = 1;
};

}  // namespace

int main(int argc, char** argv) {
    const std::string dir = dptbd_harness::job_dir(argc, argv);
    const Job job = dptbd_harness::read_job_file<Job>(dir + "/job.txt", [](
            const std::string& k, const char* rest, Job& into) {
        if (dptbd_harness::read_memory_key(k, rest, into.memory)) return true;
        if (k != "segment_frames") return false;
        into.k = std::strtoull(rest, nullptr, 10);
        return true;
    });
    auto context = std::make_unique<VerilatedContext>();
    auto dut = std::make_unique<Vdut>(context.get());
    using InPort = PortOf<decltype(PORT(pixels, payload))>;
    using OutPort = PortOf<decltype(PORT(states, payload))>;
    const std::vector<uint64_t> in = read_words(dir + "/in.bin", job.words * InPort::words);
    const std::vector<uint64_t> no_input(InPort::words, 0);
    std::vector<uint64_t> out_payload(OutPort::words, 0);

    Memory mem(job.memory, DPTBD_FRAME_BYTES, DPTBD_AXI_OUTSTANDING, job.seed);
    dptbd_harness::Pauses pauses(job);

    std::vector<uint64_t> out, out_cycles, accept_cycles(job.words, ~0ULL);
    uint64_t read_errors = 0, write_errors = 0;
    uint64_t next_word = 0, reset_until = 2, idle = 0, cycle = 0;
    bool offering = false;
    std::string status = "timeout";
    dut->clk = 0;
    dut->rst = 1;
    dut->segment_frames = job.k;
    dut->lut_addr = 0;
    dut->lut_data = 0;
    dut->eval();
    const auto t0 = std::chrono::steady_clock::now();
    for (; cycle < job.max_cycles; ++cycle) {
        const bool rst = cycle < reset_until;
        dut->rst = rst;
        dut->state_base = job.memory.base;
        dut->lut_we = 0;
        if (!offering && next_word < job.words)
            offering = pauses.offer();
        PORT(pixels, valid) = offering;
        InPort::set(PORT(pixels, payload),
                    offering ? &in[next_word * InPort::words] : no_input.data());
        const bool ready = pauses.ready();
        PORT(states, ready) = ready;
        mem.drive(dut.get(), false);
        dut->clk = 0;
        dut->eval();
        const bool out_valid = PORT(states, valid);
        if (!rst) {
            if (offering && PORT(pixels, ready)) {
                accept_cycles[next_word++] = cycle;
                offering = false;
            }
            if (out_valid && ready) {
                OutPort::get(PORT(states, payload), out_payload.data());
                out.insert(out.end(), out_payload.begin(), out_payload.end());
                out_cycles.push_back(cycle);
            }
            read_errors += dut->read_error;
            write_errors += dut->write_error;
            mem.sample(dut.get(), cycle);
        }
        dut->clk = 1;
        dut->eval();
        idle = (out_valid || rst || offering) ? 0 : idle + 1;
        if (next_word == job.words && idle >= job.drain) {
            status = "done";
            ++cycle;
            break;
        }
    }
    const double seconds = dptbd_harness::seconds_since(t0);
    dptbd_harness::finish(context.get(), dut.get(), job);
    FILE* fh = dptbd_harness::write_run(dir, out, out_cycles, accept_cycles, status, cycle,
                                        next_word, out.size() / OutPort::words);
    std::fprintf(fh, "seconds %.9f\nread_bursts %" PRIu64 "\nwrite_bursts %" PRIu64 "\n"
                 "violations %" PRIu64 "\nread_errors %" PRIu64 "\nwrite_errors %" PRIu64 "\n"
                 "first_violation %s\n",
                 seconds, mem.read_bursts, mem.write_bursts, mem.violations, read_errors,
                 write_errors,
                 mem.first_violation.empty() ? "none" : mem.first_violation.c_str());
    std::fprintf(fh, "read_error_beats %" PRIu64 "\nwrite_error_bursts %" PRIu64 "\n",
                 mem.read_errors, mem.write_errors);
    mem.report(fh);
    std::fclose(fh);
    return 0;
}
