// Verilator harness of the AXI top level dptbd_axi (hw/axi_top.py, docs/integration.md):
// streams the input beats (tdata, tuser[0], tlast; faults included) through
// s_axis_video with seeded tvalid gaps, takes m_axis_cand with seeded tready
// back-pressure, and performs AXI4-Lite writes, reads and idle waits before given input
// beats. No Python runs per cycle; dptbd.sim.verilator.axi drives this program with
// binary files. A sibling of dptbd_harness.cpp (the dptbd_dp / dptbd_seg harness), with
// the same job-file style, pause generator and cycle conventions.
//
// Usage: dptbd_sim JOB_DIR
//   JOB_DIR/job.txt   one "key value..." per line:
//                       words N              input beats in in.bin
//                       valid_gap P          probability of an idle input cycle, [0, 1)
//                       ready_pause P        probability of tready low on m_axis_cand
//                       seed S               seeds both pause generators
//                       max_cycles N         give up after N cycles (status timeout)
//                       drain N              stop once every beat and operation is done and
//                                            m_axis_cand has been idle for N cycles
//                       op I KIND A D        before offering beat I (I = N: after the last
//                                            beat), in file order: KIND w = write D to byte
//                                            address A (AW and W together, all strobes),
//                                            r = read address A (D bit 0: probing, once
//                                            AR is taken araddr is A ^ 4, AR is offered
//                                            (D bit 1: AW and W too) and rready is low for
//                                            PROBE_HOLD cycles of rvalid; a ready seen
//                                            meanwhile counts in axil_violations),
//                                            i = stay idle A cycles,
//                                            m = write as w with the strobes D >> 32
//                                            (wstrb, 4 bits) and the data D & 0xFFFFFFFF
//                                            (D bit 36: W offered only from the cycle
//                                            after the AW handshake, awaddr A ^ 4 then),
//                                            b = read address A again until bit 0 of the
//                                            data is 0 (STATUS.soft_reset_busy: wait
//                                            for a soft reset), reported as one read,
//                                            a = hold aresetn low A cycles (A >= 1),
//                                            p = load counter A (bit A of preset_load)
//                                            with D for one cycle (mutant builds of
//                                            sim/mutation/presets.py only)
//                       coverage PATH        write the run's VerilatedCov data there at
//                                            the end (coverage builds only)
//                       period P             in.bin holds P beats, repeated: beat i is
//                                            in.bin's beat i % P (long runs; then
//                                            accept_cycles.bin is left empty)
//   JOB_DIR/in.bin    N (or P) little-endian uint64 beats: tdata | tuser[0] << 32 | tlast << 33
//                     (a dptbd_axi of P pixels per clock: tdata holds the beat's P byte
//                     lanes, at most 32 bits; dptbd.sim.verilator.axi.wide_beat_words)
// Writes into JOB_DIR:
//   out.bin           uint64 tdata of every m_axis_cand transfer, in order
//   out_flags.bin     uint64 tuser[0] | tlast << 1 of each transfer
//   out_cycles.bin    uint64 cycle of each transfer
//   accept_cycles.bin uint64 cycle in which each input beat was accepted
//   irq_cycles.bin    uint64 cycle of every change of irq (sampled as the handshakes are,
//                     before the rising edge, aresetn high): its rises and falls in turn
//   ops.bin           per w/r operation: uint64 data (reads) | resp << 32 | done cycle << 34
//   result.txt        "key value" lines: status, cycles, accepted, outputs, seconds,
//                     irq_rises, stalled_input_cycles, paused_output_cycles,
//                     axil_violations (readies seen while a probing read was pending)
// Cycle 0 is the first simulated cycle; aresetn is low in cycles 0 and 1 and during the
// cycles of an a operation.
//
// Built with DPTBD_AXI_STORE (dptbd_axi --state-store axi; DPTBD_AXI_DATA_BITS,
// DPTBD_AXI_OUTSTANDING, DPTBD_FRAME_BYTES): the state store's port m_axi_state_* is
// served by the AXI4 memory model of axi4_memory.h (its job keys: latency, write_latency,
// axi_ready, axi_valid, base, span, read_error, write_error, error_cycles,
// error_response; aresetn abandons its bursts); result.txt also holds read_bursts,
// write_bursts, violations, read_error_beats, write_error_bursts, first_read_error /
// first_write_error (cycle of the first error beat's / response's handshake, 2**64-1:
// none), memory_idle (1: no burst in flight at the end) and, last, first_violation
// (text, "none" without one), and bursts.bin the memory's log: per address handshake
// uint64 cycle << 1 | is_write, address.
#include <chrono>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "Vdut.h"
#include "harness_io.h"
#ifdef DPTBD_AXI_STORE
#include "axi4_memory.h"
#endif
#include "verilated.h"

namespace {

using dptbd_harness::fail;
using dptbd_harness::read_words;
using dptbd_harness::write_words;

struct Op { uint64_t before_word; char kind; uint64_t addr, data; };

// cycles of rvalid a probing read holds rready low
constexpr uint64_t PROBE_HOLD = 3;

struct Job : dptbd_harness::StreamJob {
    std::vector<Op> ops;
    uint64_t period = 0;
#ifdef DPTBD_AXI_STORE
    dptbd_harness::Axi4MemoryJob memory;
#endif
};

}  // namespace

int main(int argc, char** argv) {
    const std::string dir = dptbd_harness::job_dir(argc, argv);
    const Job job = dptbd_harness::read_job_file<Job>(dir + "/job.txt", [](
            const std::string& k, const char* rest, Job& into) {
#ifdef DPTBD_AXI_STORE
        if (dptbd_harness::read_memory_key(k, rest, into.memory)) return true;
#endif
        if (k == "op") {
            Op op{};
            char kind[8];
            if (std::sscanf(rest, "%" SCNu64 " %7s %" SCNu64 " %" SCNu64, &op.before_word,
                            kind, &op.addr, &op.data) != 4 || std::strlen(kind) != 1
                    || std::strchr("wrimbap", kind[0]) == nullptr)
                fail("op needs WORD w|r|i|m|b|a|p ADDR DATA");
            op.kind = kind[0];
#ifndef DPTBD_MUTANT
            if (op.kind == 'p') fail("op p (a counter preset) needs a mutant build");
#endif
            into.ops.push_back(op);
            return true;
        }
        if (k != "period") return false;
        into.period = std::strtoull(rest, nullptr, 10);
        if (into.period == 0) fail("period must be at least 1");
        return true;
    });
    dptbd_harness::check_coverage_job(job);
    const uint64_t stored = job.period ? job.period : job.words;
    const std::vector<uint64_t> in = read_words(dir + "/in.bin", stored);

    auto context = std::make_unique<VerilatedContext>();
    auto dut = std::make_unique<Vdut>(context.get());
#ifdef DPTBD_MUTANT
    dptbd_harness::select_mutant(dut.get());
#endif
#ifdef DPTBD_AXI_STORE
    dptbd_harness::Axi4Memory<Vdut, DPTBD_AXI_DATA_BITS> mem(
        job.memory, DPTBD_FRAME_BYTES, DPTBD_AXI_OUTSTANDING, job.seed);
#endif

    dptbd_harness::Pauses pauses(job);

    std::vector<uint64_t> out, out_flags, out_cycles, ops_out, irq_cycles;
    std::vector<uint64_t> accept_cycles(job.period ? 0 : job.words, ~0ULL);
    out.reserve(job.words / 8 + 1024);

    uint64_t next_word = 0, cycle = 0, idle = 0, stalled_in = 0, paused_out = 0;
    uint64_t irq_rises = 0;
    bool offering = false, irq = false;
    size_t next_op = 0;
    // the operation in progress: kind 0 (none) or the op's kind
    char busy = 0;
    bool aw_done = false, w_done = false, ar_done = false;
    uint64_t r_held = 0, axil_violations = 0;
    uint64_t idle_left = 0;
    std::string status = "timeout";

    dut->aclk = 0;
    dut->aresetn = 0;
    dut->eval();
    const auto t0 = std::chrono::steady_clock::now();
    for (; cycle < job.max_cycles; ++cycle) {
        // ---- start the next operation when its beat is next and nothing is on offer
        if (cycle >= 2 && !busy && !offering && next_op < job.ops.size()
                && job.ops[next_op].before_word <= next_word) {
            const Op& op = job.ops[next_op];
            busy = op.kind;
            aw_done = w_done = ar_done = false;
            r_held = 0;
            idle_left = op.addr;
        }
        const bool rst = cycle < 2 || busy == 'a';
        dut->aresetn = !rst;
        const Op* op = busy ? &job.ops[next_op] : nullptr;
        const bool writing = busy == 'w' || busy == 'm';
        // an 'm' write with data bit 36: W offered from the cycle after the AW handshake,
        // awaddr changed (bit 2 flipped) once AW is taken
        const bool late = busy == 'm' && ((op->data >> 36) & 1);
        // an 'r' read with data bit 0: once AR is taken, araddr changed, AR offered (with
        // data bit 1 AW and W too; none may be taken: one transaction at a time) and rready
        // held low for PROBE_HOLD cycles of rvalid
        const bool probe = busy == 'r' && (op->data & 1);
        const bool probing = probe && ar_done;
        const bool probing_all = probing && (op->data & 2);
        dut->s_axil_awvalid = (writing && !aw_done) || probing_all;
        dut->s_axil_awaddr = writing ? ((late && aw_done) ? op->addr ^ 4 : op->addr)
                                     : (probing ? op->addr ^ 4 : 0);
        dut->s_axil_wvalid = (writing && !w_done && (!late || aw_done)) || probing_all;
        dut->s_axil_wdata = writing ? static_cast<uint32_t>(op->data) : 0;
        dut->s_axil_wstrb = busy == 'm' ? (op->data >> 32) & 0xF : 0xF;
        dut->s_axil_bready = 1;
        const bool reading = busy == 'r' || busy == 'b';
        dut->s_axil_arvalid = (reading && !ar_done) || probing;
        dut->s_axil_araddr = reading ? (probing ? op->addr ^ 4 : op->addr) : 0;
        dut->s_axil_rready = !(probe && r_held < PROBE_HOLD);
#ifdef DPTBD_MUTANT
        dut->preset_load = busy == 'p' ? 1u << op->addr : 0;
        dut->preset_value = busy == 'p' ? static_cast<uint32_t>(op->data) : 0;
#endif
        // ---- input beat
        if (!busy && !offering && next_word < job.words
                && !(next_op < job.ops.size() && job.ops[next_op].before_word <= next_word)) {
            offering = pauses.offer();
        }
        const uint64_t beat = offering ? in[job.period ? next_word % job.period : next_word] : 0;
        dut->s_axis_video_tvalid = offering;
        dut->s_axis_video_tdata = static_cast<uint32_t>(beat & 0xFFFFFFFFULL);
        dut->s_axis_video_tuser = (beat >> 32) & 1;
        dut->s_axis_video_tlast = (beat >> 33) & 1;
        const bool ready = pauses.ready();
        dut->m_axis_cand_tready = ready;
#ifdef DPTBD_AXI_STORE
        mem.drive(dut.get(), rst);
#endif
        dut->aclk = 0;
        dut->eval();
        // ---- sample the handshakes before the rising edge
        const bool out_valid = dut->m_axis_cand_tvalid;
        if (!rst) {
            if (offering && dut->s_axis_video_tready) {
                if (!job.period) accept_cycles[next_word] = cycle;
                ++next_word;
                offering = false;
            } else if (offering) {
                ++stalled_in;
            }
            if (out_valid && ready) {
                out.push_back(static_cast<uint64_t>(dut->m_axis_cand_tdata));
                out_flags.push_back((dut->m_axis_cand_tuser & 1) | (dut->m_axis_cand_tlast << 1));
                out_cycles.push_back(cycle);
            } else if (out_valid) {
                ++paused_out;
            }
            if (writing) {
                aw_done = aw_done || (dut->s_axil_awvalid && dut->s_axil_awready);
                w_done = w_done || (dut->s_axil_wvalid && dut->s_axil_wready);
                if (dut->s_axil_bvalid) {
                    ops_out.push_back((static_cast<uint64_t>(dut->s_axil_bresp) << 32)
                                      | (cycle << 34));
                    busy = 0;
                    ++next_op;
                }
            } else if (reading) {
                if (probing && (dut->s_axil_awready || dut->s_axil_wready
                                || dut->s_axil_arready)) {
                    ++axil_violations;                      // taken during a read
                }
                ar_done = ar_done || dut->s_axil_arready;
                if (dut->s_axil_rvalid && !dut->s_axil_rready) {
                    ++r_held;
                } else if (dut->s_axil_rvalid && busy == 'b' && (dut->s_axil_rdata & 1)) {
                    ar_done = false;                        // still busy: read again
                } else if (dut->s_axil_rvalid) {
                    ops_out.push_back(static_cast<uint64_t>(dut->s_axil_rdata)
                                      | (static_cast<uint64_t>(dut->s_axil_rresp) << 32)
                                      | (cycle << 34));
                    busy = 0;
                    ++next_op;
                }
            } else if (busy == 'p') {                      // one cycle
                busy = 0;
                ++next_op;
            } else if (busy == 'i') {
                if (idle_left <= 1) { busy = 0; ++next_op; }
                else --idle_left;
            }
#ifdef DPTBD_AXI_STORE
            mem.sample(dut.get(), cycle);
#endif
            const bool level = dut->irq;
            irq_rises += level && !irq;
            if (level != irq) irq_cycles.push_back(cycle);
            irq = level;
        }
        dut->aclk = 1;
        dut->eval();
        if (busy == 'a') {                                  // aresetn held low
            if (idle_left <= 1) { busy = 0; ++next_op; }
            else --idle_left;
        }
        idle = (out_valid || rst || offering || busy) ? 0 : idle + 1;
        if (next_word == job.words && next_op == job.ops.size() && idle >= job.drain) {
            status = "done";
            ++cycle;
            break;
        }
    }
    const double seconds = dptbd_harness::seconds_since(t0);
    dptbd_harness::finish(context.get(), dut.get(), job);

    write_words(dir + "/out_flags.bin", out_flags);
    write_words(dir + "/ops.bin", ops_out);
    write_words(dir + "/irq_cycles.bin", irq_cycles);
    FILE* fh = dptbd_harness::write_run(dir, out, out_cycles, accept_cycles, status, cycle,
                                        next_word, out.size());
    std::fprintf(fh, "stalled_input_cycles %" PRIu64 "\npaused_output_cycles %" PRIu64 "\n"
                 "irq_rises %" PRIu64 "\naxil_violations %" PRIu64 "\nseconds %.9f\n",
                 stalled_in, paused_out, irq_rises, axil_violations, seconds);
#ifdef DPTBD_AXI_STORE
    std::fprintf(fh, "read_bursts %" PRIu64 "\nwrite_bursts %" PRIu64 "\nviolations %" PRIu64
                 "\nread_error_beats %" PRIu64 "\nwrite_error_bursts %" PRIu64
                 "\nfirst_read_error %" PRIu64 "\nfirst_write_error %" PRIu64
                 "\nmemory_idle %d\nfirst_violation %s\n",
                 mem.read_bursts, mem.write_bursts, mem.violations, mem.read_errors,
                 mem.write_errors, mem.first_read_error, mem.first_write_error, int(mem.idle()),
                 mem.first_violation.empty() ? "none" : mem.first_violation.c_str());
    mem.report(fh);
#endif
    std::fclose(fh);
#ifdef DPTBD_AXI_STORE
    write_words(dir + "/bursts.bin", mem.log);
#endif
    return 0;
}
