// Verilator harness of dptbd_dp built with --state-store axi (DPPipelineAxi): streams an
// input word sequence through the design, its state in a C++ AXI4 memory model below, and
// writes every output transfer. dptbd.sim.verilator.dp_axi builds and drives it.
//
// The memory answers each read burst after a random latency (drawn per burst) and each
// write burst's response after a random latency from its last beat; every ready (AR, AW, W)
// and valid (R, B) it drives is high with a given probability per cycle. It is adversarial
// about ordering: a read takes the contents when its address is accepted, a write changes
// them when its response is sent. It checks every AXI4 rule it sees (INCR, full-width
// beats, aligned addresses, at most 256 beats, no 4 KB crossing, full strobes, WLAST on
// exactly the last beat, at most DPTBD_AXI_OUTSTANDING bursts in flight per direction, the
// region [base, base + frame bytes), valid and payload held until the handshake) and counts
// violations (the first one's text goes to result.txt).
//
// Compile-time: DPTBD_AXI_DATA_BITS (32 or 64), DPTBD_AXI_OUTSTANDING, DPTBD_FRAME_BYTES.
// Usage: dptbd_sim JOB_DIR; JOB_DIR/job.txt holds the StreamJob keys (harness_io.h) and
//   latency MIN MAX        read latency range, cycles from AR handshake to first beat
//   write_latency MIN MAX  write response latency range, cycles after the last W beat
//   axi_ready P            probability of each of ARREADY, AWREADY, WREADY per cycle
//   axi_valid P            probability of RVALID / BVALID when a beat / response is due
//   base ADDR              the state's base address (state_base is driven with it)
//   segment_frames K       the run-time K driven on segment_frames
// JOB_DIR/in.bin: input payloads. Writes out.bin, out_cycles.bin, accept_cycles.bin and
// result.txt (status, cycles, accepted, outputs, seconds, read_bursts, write_bursts,
// violations, first_violation, read_errors, write_errors).
#include <chrono>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "Vdut.h"
#include "harness_io.h"
#include "verilated.h"

#define PORT(group, member) dut->group##___05F##member
#define AXI(member) dut->m_axi_state_##member

namespace {

using dptbd_harness::Rng;
using dptbd_harness::fail;
using dptbd_harness::read_stream_key;
using dptbd_harness::read_words;
using dptbd_harness::threshold_of;
using dptbd_harness::write_words;

constexpr uint64_t BEAT = DPTBD_AXI_DATA_BITS / 8;
constexpr uint64_t OUTSTANDING = DPTBD_AXI_OUTSTANDING;
constexpr uint64_t FRAME_BYTES = DPTBD_FRAME_BYTES;

struct Job : dptbd_harness::StreamJob {
    uint64_t lat_min = 0, lat_max = 0, wlat_min = 0, wlat_max = 0, base = 0, k = 1;
    bool write_latency_given = false;
    double axi_ready = 1.0, axi_valid = 1.0;
};

Job read_job(const std::string& path) {
    Job job;
    FILE* fh = std::fopen(path.c_str(), "r");
    if (!fh) fail("cannot open " + path);
    char key[64], rest[4096];
    while (std::fscanf(fh, "%63s", key) == 1) {
        if (!std::fgets(rest, sizeof rest, fh)) rest[0] = 0;
        std::string k(key);
        if (read_stream_key(k, rest, job)) continue;
        if (k == "latency") {
            if (std::sscanf(rest, "%" SCNu64 " %" SCNu64, &job.lat_min, &job.lat_max) != 2)
                fail("latency needs MIN MAX");
        } else if (k == "write_latency") {
            if (std::sscanf(rest, "%" SCNu64 " %" SCNu64, &job.wlat_min, &job.wlat_max) != 2)
                fail("write_latency needs MIN MAX");
            job.write_latency_given = true;
        } else if (k == "axi_ready") job.axi_ready = std::strtod(rest, nullptr);
        else if (k == "axi_valid") job.axi_valid = std::strtod(rest, nullptr);
        else if (k == "base") job.base = std::strtoull(rest, nullptr, 10);
        else if (k == "segment_frames") job.k = std::strtoull(rest, nullptr, 10);
        else fail("unknown job key " + k);
    }
    std::fclose(fh);
    if (job.max_cycles == 0) fail("max_cycles must be given");
    if (!job.write_latency_given) { job.wlat_min = job.lat_min; job.wlat_max = job.lat_max; }
    return job;
}

struct ReadBurst { uint64_t due; std::deque<uint64_t> beats; };
struct WriteBurst { uint64_t addr, beats; std::vector<uint64_t> data; };
struct Response { uint64_t due, addr; std::vector<uint64_t> data; };

struct Memory {
    std::vector<uint8_t> bytes;
    uint64_t base;
    uint64_t beat(uint64_t addr) const {
        uint64_t v = 0;
        for (uint64_t k = 0; k < BEAT; ++k) v |= uint64_t(bytes[addr - base + k]) << (8 * k);
        return v;
    }
    void write(uint64_t addr, uint64_t v) {
        for (uint64_t k = 0; k < BEAT; ++k) bytes[addr - base + k] = uint8_t(v >> (8 * k));
    }
};

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) fail("usage: dptbd_sim JOB_DIR");
    const std::string dir = argv[1];
    const Job job = read_job(dir + "/job.txt");
    const std::vector<uint64_t> in = read_words(dir + "/in.bin", job.words);

    auto context = std::make_unique<VerilatedContext>();
    auto dut = std::make_unique<Vdut>(context.get());

    Rng garbage{job.seed ^ 0x5A5A5A5A5A5A5A5AULL};
    Memory mem{std::vector<uint8_t>(FRAME_BYTES), job.base};
    for (auto& b : mem.bytes) b = uint8_t(garbage.next());

    Rng valid_rng{job.seed * 2 + 1}, ready_rng{job.seed * 2 + 2}, axi_rng{job.seed * 2 + 3};
    const uint64_t gap_thr = threshold_of(job.valid_gap);
    const uint64_t pause_thr = threshold_of(job.ready_pause);
    const uint64_t axi_ready_thr = threshold_of(1.0 - job.axi_ready);
    const uint64_t axi_valid_thr = threshold_of(1.0 - job.axi_valid);
    auto draw = [&](uint64_t lo, uint64_t hi) { return lo + axi_rng.next() % (hi - lo + 1); };
    auto chance = [&](uint64_t thr) { return !(thr && axi_rng.next() < thr); };

    std::vector<uint64_t> out, out_cycles, accept_cycles(job.words, ~0ULL);
    std::deque<ReadBurst> reads;
    std::deque<WriteBurst> writes;
    std::deque<std::pair<uint64_t, bool>> wbeats;
    std::deque<Response> responses;
    uint64_t writes_open = 0, read_bursts = 0, write_bursts = 0, violations = 0;
    uint64_t read_errors = 0, write_errors = 0;
    std::string first_violation;
    auto violate = [&](const std::string& what) {
        if (!violations++) first_violation = what;
    };
    auto check_address = [&](const char* ch, uint64_t addr, uint64_t len, uint64_t size,
                             uint64_t burst) {
        const uint64_t beats = len + 1;
        if (burst != 1) violate(std::string(ch) + ": burst type not INCR");
        if ((1ULL << size) != BEAT) violate(std::string(ch) + ": size not the full beat");
        if (addr % BEAT) violate(std::string(ch) + ": address not aligned to the beat");
        if (beats > 256) violate(std::string(ch) + ": more than 256 beats");
        if (addr / 4096 != (addr + beats * BEAT - 1) / 4096)
            violate(std::string(ch) + ": burst crosses a 4 KB boundary");
        if (addr < job.base || addr + beats * BEAT > job.base + FRAME_BYTES) {
            violate(std::string(ch) + ": burst outside the frame's state");
            return false;
        }
        return true;
    };

    bool ar_ready = false, aw_ready = false, w_ready = false;
    bool r_on = false, b_on = false;
    uint64_t r_data = 0;
    bool r_last = false;
    // held payloads: valid high without ready last edge
    bool ar_held = false, aw_held = false, w_held = false;
    uint64_t ar_h[3] = {}, aw_h[3] = {}, w_h[3] = {};

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
        dut->state_base = job.base;
        dut->lut_we = 0;
        if (!offering && next_word < job.words)
            offering = !(gap_thr && valid_rng.next() < gap_thr);
        PORT(pixels, valid) = offering;
        PORT(pixels, payload) = offering ? in[next_word] : 0;
        const bool ready = !(pause_thr && ready_rng.next() < pause_thr);
        PORT(states, ready) = ready;
        AXI(arready) = ar_ready;
        AXI(awready) = aw_ready;
        AXI(wready) = w_ready;
        AXI(rvalid) = r_on;
        AXI(rdata) = r_on ? r_data : 0;
        AXI(rlast) = r_on && r_last;
        AXI(rresp) = 0;
        AXI(rid) = 0;
        AXI(bvalid) = b_on;
        AXI(bresp) = 0;
        AXI(bid) = 0;
        dut->clk = 0;
        dut->eval();
        const bool out_valid = PORT(states, valid);
        if (!rst) {
            if (offering && PORT(pixels, ready)) {
                accept_cycles[next_word++] = cycle;
                offering = false;
            }
            if (out_valid && ready) {
                out.push_back(uint64_t(PORT(states, payload)));
                out_cycles.push_back(cycle);
            }
            read_errors += dut->read_error;
            write_errors += dut->write_error;
            // ---- the memory's side of the handshakes at this edge --------------------
            const uint64_t ar_now[3] = {AXI(araddr), AXI(arlen), AXI(arsize)};
            if (ar_held && !(AXI(arvalid) && ar_now[0] == ar_h[0] && ar_now[1] == ar_h[1]))
                violate("AR: valid or payload changed before the handshake");
            ar_held = AXI(arvalid) && !ar_ready;
            for (int k = 0; k < 3; ++k) ar_h[k] = ar_now[k];
            if (AXI(arvalid) && ar_ready) {
                ++read_bursts;
                if (reads.size() >= OUTSTANDING) violate("AR: too many reads in flight");
                if (check_address("AR", AXI(araddr), AXI(arlen), AXI(arsize), AXI(arburst))) {
                    ReadBurst rb{cycle + draw(job.lat_min, job.lat_max), {}};
                    for (uint64_t k = 0; k <= AXI(arlen); ++k)
                        rb.beats.push_back(mem.beat(AXI(araddr) + k * BEAT));
                    reads.push_back(rb);
                }
            }
            const uint64_t aw_now[3] = {AXI(awaddr), AXI(awlen), AXI(awsize)};
            if (aw_held && !(AXI(awvalid) && aw_now[0] == aw_h[0] && aw_now[1] == aw_h[1]))
                violate("AW: valid or payload changed before the handshake");
            aw_held = AXI(awvalid) && !aw_ready;
            for (int k = 0; k < 3; ++k) aw_h[k] = aw_now[k];
            if (AXI(awvalid) && aw_ready) {
                ++write_bursts;
                if (writes_open >= OUTSTANDING) violate("AW: too many writes in flight");
                ++writes_open;
                if (check_address("AW", AXI(awaddr), AXI(awlen), AXI(awsize), AXI(awburst)))
                    writes.push_back({uint64_t(AXI(awaddr)), uint64_t(AXI(awlen)) + 1, {}});
                else
                    writes.push_back({job.base, uint64_t(AXI(awlen)) + 1, {}});
            }
            const uint64_t w_now[3] = {uint64_t(AXI(wdata)), AXI(wstrb), AXI(wlast)};
            if (w_held && !(AXI(wvalid) && w_now[0] == w_h[0] && w_now[2] == w_h[2]))
                violate("W: valid or payload changed before the handshake");
            w_held = AXI(wvalid) && !w_ready;
            for (int k = 0; k < 3; ++k) w_h[k] = w_now[k];
            if (AXI(wvalid) && w_ready) {
                if (AXI(wstrb) != (1ULL << BEAT) - 1) violate("W: strobe not full");
                wbeats.push_back({uint64_t(AXI(wdata)), bool(AXI(wlast))});
            }
            while (!writes.empty() && !wbeats.empty()) {
                WriteBurst& wb = writes.front();
                wb.data.push_back(wbeats.front().first);
                const bool last = wbeats.front().second;
                wbeats.pop_front();
                if (last != (wb.data.size() == wb.beats)) violate("W: WLAST not on the last beat");
                if (wb.data.size() == wb.beats) {
                    responses.push_back({cycle + draw(job.wlat_min, job.wlat_max), wb.addr,
                                         wb.data});
                    writes.pop_front();
                }
            }
            if (r_on && AXI(rready)) {
                r_on = false;
                if (r_last) reads.pop_front();
            }
            if (b_on && AXI(bready)) {
                const Response& rsp = responses.front();
                for (size_t k = 0; k < rsp.data.size(); ++k)
                    mem.write(rsp.addr + k * BEAT, rsp.data[k]);
                responses.pop_front();
                --writes_open;
                b_on = false;
            }
            // ---- what the memory offers in the next cycle -------------------------------
            ar_ready = chance(axi_ready_thr);
            aw_ready = chance(axi_ready_thr);
            w_ready = chance(axi_ready_thr);
            if (!r_on && !reads.empty() && reads.front().due <= cycle && chance(axi_valid_thr)) {
                r_data = reads.front().beats.front();
                reads.front().beats.pop_front();
                r_last = reads.front().beats.empty();
                r_on = true;
            }
            if (!b_on && !responses.empty() && responses.front().due <= cycle
                    && chance(axi_valid_thr))
                b_on = true;
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
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    dut->final();
    write_words(dir + "/out.bin", out);
    write_words(dir + "/out_cycles.bin", out_cycles);
    write_words(dir + "/accept_cycles.bin", accept_cycles);
    FILE* fh = std::fopen((dir + "/result.txt").c_str(), "w");
    if (!fh) fail("cannot write result.txt");
    std::fprintf(fh, "status %s\ncycles %" PRIu64 "\naccepted %" PRIu64 "\noutputs %zu\n"
                 "seconds %.9f\nread_bursts %" PRIu64 "\nwrite_bursts %" PRIu64 "\n"
                 "violations %" PRIu64 "\nread_errors %" PRIu64 "\nwrite_errors %" PRIu64 "\n"
                 "first_violation %s\n",
                 status.c_str(), cycle, next_word, out.size(), seconds, read_bursts,
                 write_bursts, violations, read_errors, write_errors,
                 first_violation.empty() ? "none" : first_violation.c_str());
    std::fclose(fh);
    return 0;
}
