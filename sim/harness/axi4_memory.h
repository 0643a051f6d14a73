// The C++ AXI4 memory model of dptbd's Verilator harnesses: the subordinate behind a
// design's state-store manager port m_axi_state_* (dptbd_dp --state-store axi,
// dptbd_axi --state-store axi). Header-only; included by dptbd_dp_axi_harness.cpp and
// dptbd_axi_harness.cpp (built with DPTBD_AXI_STORE).
//
// The memory answers each read burst after a random latency (drawn per burst) and each
// write burst's response after a random latency from its last beat; every ready (AR, AW, W)
// and valid (R, B) it drives is high with a given probability per cycle. It is adversarial
// about ordering: a read takes the contents when its address is accepted, a write changes
// them when its response is sent. It checks every AXI4 rule it sees (INCR, full-width
// beats, aligned addresses, at most 256 beats, no 4 KB crossing, full strobes, WLAST on
// exactly the last beat, at most `outstanding` bursts in flight per direction, the region
// [base, base + span) (span: the frame's bytes unless given), valid and payload held until
// the handshake) and counts violations (the first one's text is kept). It logs every
// address handshake (cycle, direction, address: `log`).
//
// Error responses: a read burst whose AR handshake falls in [error_from, error_to) is
// answered with the error response (SLVERR, or DECERR: `error_response`) on every beat
// (random data) with probability read_error; a write burst whose AW handshake falls there
// gets that BRESP with probability write_error and changes nothing. Their draws use a generator of their own: without errors the run is the
// one without this feature, cycle for cycle.
//
// Data widths: 32, 64 and 128 bits (a beat is kept as bytes; Verilator's 128-bit ports
// are VlWide<4>).
#pragma once

#include <array>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "harness_io.h"
#include "verilated.h"

namespace dptbd_harness {

// The memory's settings (the job keys of the harnesses that use it).
struct Axi4MemoryJob {
    uint64_t lat_min = 0, lat_max = 0, wlat_min = 0, wlat_max = 0, base = 0, span = 0;
    bool write_latency_given = false;
    double axi_ready = 1.0, axi_valid = 1.0, read_error = 0.0, write_error = 0.0;
    uint64_t error_from = 0, error_to = ~0ULL;
    uint8_t error_response = 2;   // RRESP / BRESP of an error: SLVERR (2) or DECERR (3)
};

// Parse one of the memory's job keys; false if `key` is not one of them.
//   latency MIN MAX        read latency range, cycles from AR handshake to first beat
//   write_latency MIN MAX  write response latency range, cycles after the last W beat
//                          (default: the read latency range)
//   axi_ready P            probability of each of ARREADY, AWREADY, WREADY per cycle
//   axi_valid P            probability of RVALID / BVALID when a beat / response is due
//   base ADDR              the state's base address (decimal)
//   span BYTES             bytes of memory from base (default: the frame's state)
//   read_error P           probability that a read burst is answered with an error
//   write_error P          probability that a write burst is answered with an error
//   error_cycles A B       errors only for bursts whose address handshake is in [A, B)
//   error_response R       the errors' response: SLVERR (the default) or DECERR
inline bool read_memory_key(const std::string& k, const char* rest, Axi4MemoryJob& job) {
    if (k == "latency") {
        if (std::sscanf(rest, "%" SCNu64 " %" SCNu64, &job.lat_min, &job.lat_max) != 2)
            fail("latency needs MIN MAX");
        if (!job.write_latency_given) { job.wlat_min = job.lat_min; job.wlat_max = job.lat_max; }
    } else if (k == "write_latency") {
        if (std::sscanf(rest, "%" SCNu64 " %" SCNu64, &job.wlat_min, &job.wlat_max) != 2)
            fail("write_latency needs MIN MAX");
        job.write_latency_given = true;
    } else if (k == "axi_ready") job.axi_ready = std::strtod(rest, nullptr);
    else if (k == "axi_valid") job.axi_valid = std::strtod(rest, nullptr);
    else if (k == "base") job.base = std::strtoull(rest, nullptr, 10);
    else if (k == "span") job.span = std::strtoull(rest, nullptr, 10);
    else if (k == "read_error") job.read_error = std::strtod(rest, nullptr);
    else if (k == "write_error") job.write_error = std::strtod(rest, nullptr);
    else if (k == "error_cycles") {
        if (std::sscanf(rest, "%" SCNu64 " %" SCNu64, &job.error_from, &job.error_to) != 2)
            fail("error_cycles needs FROM TO");
    } else if (k == "error_response") {
        char name[16] = {};
        if (std::sscanf(rest, "%15s", name) != 1) fail("error_response needs SLVERR or DECERR");
        const std::string r(name);
        if (r == "SLVERR") job.error_response = 2;
        else if (r == "DECERR") job.error_response = 3;
        else fail("error_response " + r + ": the responses are SLVERR, DECERR");
    } else return false;
    return true;
}

template <unsigned BYTES>
using Beat = std::array<uint8_t, BYTES>;

// A port value to bytes and back: 32- and 64-bit ports are integers, wider ones VlWide.
template <unsigned BYTES, typename T,
          typename = std::enable_if_t<std::is_integral<T>::value>>
inline Beat<BYTES> beat_of(const T& value) {
    Beat<BYTES> b{};
    for (unsigned k = 0; k < BYTES; ++k) b[k] = uint8_t(uint64_t(value) >> (8 * k));
    return b;
}
template <unsigned BYTES, std::size_t N>
inline Beat<BYTES> beat_of(const VlWide<N>& value) {
    Beat<BYTES> b{};
    for (unsigned k = 0; k < BYTES; ++k) b[k] = uint8_t(value[k / 4] >> (8 * (k % 4)));
    return b;
}
template <unsigned BYTES, typename T,
          typename = std::enable_if_t<std::is_integral<T>::value>>
inline void set_port(T& port, const Beat<BYTES>& b) {
    uint64_t v = 0;
    for (unsigned k = 0; k < BYTES; ++k) v |= uint64_t(b[k]) << (8 * k);
    port = static_cast<T>(v);
}
template <unsigned BYTES, std::size_t N>
inline void set_port(VlWide<N>& port, const Beat<BYTES>& b) {
    for (std::size_t w = 0; w < N; ++w) port[w] = 0;
    for (unsigned k = 0; k < BYTES; ++k) port[k / 4] |= uint32_t(b[k]) << (8 * (k % 4));
}

// The memory behind `dut->m_axi_state_*`, DATA_BITS wide (32, 64 or 128). Per cycle:
// drive() before the falling-edge eval (what the memory offers), sample() after it and
// before the rising edge (the handshakes at this edge), outside reset only.
template <class Dut, unsigned DATA_BITS>
class Axi4Memory {
    static_assert(DATA_BITS == 32 || DATA_BITS == 64 || DATA_BITS == 128,
                  "the AXI4 memory model takes 32, 64 or 128 data bits");

  public:
    static constexpr uint64_t BEAT = DATA_BITS / 8;
    using Data = Beat<BEAT>;

    uint64_t read_bursts = 0, write_bursts = 0, violations = 0;
    uint64_t read_errors = 0, write_errors = 0;   // error beats (R), bursts (B) sent
    // of those, the ones whose RRESP / BRESP read DECERR on the port at the handshake
    uint64_t read_decerrs = 0, write_decerrs = 0;
    uint64_t first_read_error = ~0ULL, first_write_error = ~0ULL;   // their first handshake
    // Observed stalls: cycles the manager's AR / AW / W valid waited on a low ready, and
    // cycles an R beat or a B response was due but its valid was held low; bursts whose
    // last byte is the last byte of a 4 KB page (read, write).
    uint64_t ar_stalls = 0, aw_stalls = 0, w_stalls = 0, r_stalls = 0, b_stalls = 0;
    uint64_t read_boundary_bursts = 0, write_boundary_bursts = 0;
    std::string first_violation;
    std::vector<uint64_t> log;   // per address handshake: cycle << 1 | is_write, address

    Axi4Memory(const Axi4MemoryJob& job, uint64_t frame_bytes, uint64_t outstanding,
               uint64_t seed)
        : job_(job), frame_bytes_(job.span ? job.span : frame_bytes), outstanding_(outstanding),
          bytes_(frame_bytes_), rng_{seed * 2 + 3}, error_rng_{seed ^ 0xE77E77E77E77E77EULL},
          ready_thr_(threshold_of(1.0 - job.axi_ready)),
          valid_thr_(threshold_of(1.0 - job.axi_valid)),
          read_error_thr_(threshold_of(job.read_error)),
          write_error_thr_(threshold_of(job.write_error)) {
        Rng garbage{seed ^ 0x5A5A5A5A5A5A5A5AULL};
        for (auto& b : bytes_) b = uint8_t(garbage.next());
    }

    // The state's bytes (base first).
    const std::vector<uint8_t>& bytes() const { return bytes_; }

    // What the memory offers in this cycle. In reset (`rst`), nothing.
    void drive(Dut* dut, bool rst) {
        if (rst) clear();
        dut->m_axi_state_arready = ar_ready_;
        dut->m_axi_state_awready = aw_ready_;
        dut->m_axi_state_wready = w_ready_;
        dut->m_axi_state_rvalid = r_on_;
        set_port<BEAT>(dut->m_axi_state_rdata, r_on_ ? r_data_ : Data{});
        dut->m_axi_state_rlast = r_on_ && r_last_;
        dut->m_axi_state_rresp = r_on_ && r_error_ ? job_.error_response : 0;
        dut->m_axi_state_rid = 0;
        dut->m_axi_state_bvalid = b_on_;
        dut->m_axi_state_bresp = b_on_ && !responses_.empty() && responses_.front().error
                                     ? job_.error_response : 0;
        dut->m_axi_state_bid = 0;
    }

    // The handshakes at the coming rising edge of cycle `cycle` (call outside reset).
    void sample(Dut* dut, uint64_t cycle) {
        const uint64_t ar_now[2] = {uint64_t(dut->m_axi_state_araddr),
                                    uint64_t(dut->m_axi_state_arlen)};
        if (ar_held_ && !(dut->m_axi_state_arvalid && ar_now[0] == ar_h_[0]
                          && ar_now[1] == ar_h_[1]))
            violate("AR: valid or payload changed before the handshake");
        ar_held_ = dut->m_axi_state_arvalid && !ar_ready_;
        ar_stalls += ar_held_;
        ar_h_[0] = ar_now[0];
        ar_h_[1] = ar_now[1];
        if (dut->m_axi_state_arvalid && ar_ready_) {
            ++read_bursts;
            log.push_back(cycle << 1);
            log.push_back(uint64_t(dut->m_axi_state_araddr));
            if (reads_.size() >= outstanding_) violate("AR: too many reads in flight");
            const uint64_t addr = dut->m_axi_state_araddr, len = dut->m_axi_state_arlen;
            read_boundary_bursts += (addr + (len + 1) * BEAT) % 4096 == 0;
            ReadBurst rb{cycle + draw(job_.lat_min, job_.lat_max), {},
                         inject(read_error_thr_, job_.read_error, cycle)};
            if (check_address("AR", addr, len, dut->m_axi_state_arsize,
                              dut->m_axi_state_arburst)) {
                for (uint64_t k = 0; k <= len; ++k) rb.beats.push_back(
                    rb.error ? garbage_beat() : beat(addr + k * BEAT));
            } else {
                for (uint64_t k = 0; k <= len; ++k) rb.beats.push_back(Data{});
            }
            reads_.push_back(rb);
        }
        const uint64_t aw_now[2] = {uint64_t(dut->m_axi_state_awaddr),
                                    uint64_t(dut->m_axi_state_awlen)};
        if (aw_held_ && !(dut->m_axi_state_awvalid && aw_now[0] == aw_h_[0]
                          && aw_now[1] == aw_h_[1]))
            violate("AW: valid or payload changed before the handshake");
        aw_held_ = dut->m_axi_state_awvalid && !aw_ready_;
        aw_stalls += aw_held_;
        aw_h_[0] = aw_now[0];
        aw_h_[1] = aw_now[1];
        if (dut->m_axi_state_awvalid && aw_ready_) {
            ++write_bursts;
            log.push_back(cycle << 1 | 1);
            log.push_back(uint64_t(dut->m_axi_state_awaddr));
            if (writes_open_ >= outstanding_) violate("AW: too many writes in flight");
            ++writes_open_;
            const uint64_t addr = dut->m_axi_state_awaddr, len = dut->m_axi_state_awlen;
            write_boundary_bursts += (addr + (len + 1) * BEAT) % 4096 == 0;
            const bool inside = check_address("AW", addr, len, dut->m_axi_state_awsize,
                                              dut->m_axi_state_awburst);
            writes_.push_back({inside ? addr : job_.base, len + 1, {},
                               inject(write_error_thr_, job_.write_error, cycle) || !inside});
        }
        const Data w_now = beat_of<BEAT>(dut->m_axi_state_wdata);
        const bool w_last = dut->m_axi_state_wlast;
        if (w_held_ && !(dut->m_axi_state_wvalid && w_now == w_h_ && w_last == w_last_h_))
            violate("W: valid or payload changed before the handshake");
        w_held_ = dut->m_axi_state_wvalid && !w_ready_;
        w_stalls += w_held_;
        w_h_ = w_now;
        w_last_h_ = w_last;
        if (dut->m_axi_state_wvalid && w_ready_) {
            if (uint64_t(dut->m_axi_state_wstrb) != strobe_all()) violate("W: strobe not full");
            wbeats_.push_back({w_now, w_last});
        }
        while (!writes_.empty() && !wbeats_.empty()) {
            WriteBurst& wb = writes_.front();
            wb.data.push_back(wbeats_.front().first);
            const bool last = wbeats_.front().second;
            wbeats_.pop_front();
            if (last != (wb.data.size() == wb.beats)) violate("W: WLAST not on the last beat");
            if (wb.data.size() == wb.beats) {
                responses_.push_back({cycle + draw(job_.wlat_min, job_.wlat_max), wb.addr,
                                      wb.data, wb.error});
                writes_.pop_front();
            }
        }
        if (r_on_ && dut->m_axi_state_rready) {
            r_on_ = false;
            read_errors += r_error_;
            read_decerrs += r_error_ && dut->m_axi_state_rresp == 3;
            if (r_error_ && first_read_error == ~0ULL) first_read_error = cycle;
            if (r_last_) reads_.pop_front();
        }
        if (b_on_ && dut->m_axi_state_bready) {
            const Response& rsp = responses_.front();
            if (rsp.error && first_write_error == ~0ULL) first_write_error = cycle;
            write_decerrs += rsp.error && dut->m_axi_state_bresp == 3;
            if (rsp.error) ++write_errors;
            else
                for (size_t k = 0; k < rsp.data.size(); ++k) write(rsp.addr + k * BEAT, rsp.data[k]);
            responses_.pop_front();
            --writes_open_;
            b_on_ = false;
        }
        // ---- what the memory offers in the next cycle -------------------------------
        ar_ready_ = chance(ready_thr_);
        aw_ready_ = chance(ready_thr_);
        w_ready_ = chance(ready_thr_);
        if (!r_on_ && !reads_.empty() && reads_.front().due <= cycle) {
            if (chance(valid_thr_)) {
                r_data_ = reads_.front().beats.front();
                reads_.front().beats.pop_front();
                r_last_ = reads_.front().beats.empty();
                r_error_ = reads_.front().error;
                r_on_ = true;
            } else {
                ++r_stalls;                  // a beat due, its valid held low
            }
        }
        if (!b_on_ && !responses_.empty() && responses_.front().due <= cycle) {
            if (chance(valid_thr_)) b_on_ = true;
            else ++b_stalls;                 // a response due, its valid held low
        }
    }

    // The observed counters above, one "key value" line each (result.txt).
    void report(std::FILE* fh) const {
        std::fprintf(fh, "read_decerrs %" PRIu64 "\nwrite_decerrs %" PRIu64 "\n",
                     read_decerrs, write_decerrs);
        std::fprintf(fh, "ar_stalls %" PRIu64 "\naw_stalls %" PRIu64 "\nw_stalls %" PRIu64
                     "\nr_stalls %" PRIu64 "\nb_stalls %" PRIu64 "\nread_boundary_bursts %"
                     PRIu64 "\nwrite_boundary_bursts %" PRIu64 "\n", ar_stalls, aw_stalls,
                     w_stalls, r_stalls, b_stalls, read_boundary_bursts,
                     write_boundary_bursts);
    }

    // Nothing in flight (every burst answered) and nothing offered.
    bool idle() const {
        return reads_.empty() && writes_.empty() && wbeats_.empty() && responses_.empty()
               && !r_on_ && !b_on_;
    }

  private:
    struct ReadBurst { uint64_t due; std::deque<Data> beats; bool error; };
    struct WriteBurst { uint64_t addr, beats; std::vector<Data> data; bool error; };
    struct Response { uint64_t due, addr; std::vector<Data> data; bool error; };

    Axi4MemoryJob job_;
    uint64_t frame_bytes_, outstanding_;
    std::vector<uint8_t> bytes_;
    Rng rng_, error_rng_;
    uint64_t ready_thr_, valid_thr_, read_error_thr_, write_error_thr_;
    std::deque<ReadBurst> reads_;
    std::deque<WriteBurst> writes_;
    std::deque<std::pair<Data, bool>> wbeats_;
    std::deque<Response> responses_;
    uint64_t writes_open_ = 0;
    bool ar_ready_ = false, aw_ready_ = false, w_ready_ = false;
    bool r_on_ = false, b_on_ = false, r_last_ = false, r_error_ = false;
    Data r_data_{};
    bool ar_held_ = false, aw_held_ = false, w_held_ = false, w_last_h_ = false;
    uint64_t ar_h_[2] = {}, aw_h_[2] = {};
    Data w_h_{};

    // aresetn: every burst in flight is forgotten (AXI4 lets a reset abandon them).
    void clear() {
        reads_.clear();
        writes_.clear();
        wbeats_.clear();
        responses_.clear();
        writes_open_ = 0;
        ar_ready_ = aw_ready_ = w_ready_ = r_on_ = b_on_ = false;
        ar_held_ = aw_held_ = w_held_ = false;
    }
    static uint64_t strobe_all() { return BEAT == 16 ? 0xFFFFULL : (1ULL << BEAT) - 1; }
    uint64_t draw(uint64_t lo, uint64_t hi) { return lo + rng_.next() % (hi - lo + 1); }
    bool chance(uint64_t thr) { return !(thr && rng_.next() < thr); }
    // an error response for a burst taken in `cycle`, with probability p (1: always)
    bool inject(uint64_t thr, double p, uint64_t cycle) {
        if (p <= 0.0 || cycle < job_.error_from || cycle >= job_.error_to) return false;
        return p >= 1.0 || error_rng_.next() < thr;
    }
    Data garbage_beat() {
        Data d;
        for (auto& b : d) b = uint8_t(error_rng_.next());
        return d;
    }
    void violate(const std::string& what) {
        if (!violations++) first_violation = what;
    }
    Data beat(uint64_t addr) const {
        Data d;
        for (uint64_t k = 0; k < BEAT; ++k) d[k] = bytes_[addr - job_.base + k];
        return d;
    }
    void write(uint64_t addr, const Data& d) {
        for (uint64_t k = 0; k < BEAT; ++k) bytes_[addr - job_.base + k] = d[k];
    }
    bool check_address(const char* ch, uint64_t addr, uint64_t len, uint64_t size,
                       uint64_t burst) {
        const uint64_t beats = len + 1;
        if (burst != 1) violate(std::string(ch) + ": burst type not INCR");
        if ((1ULL << size) != BEAT) violate(std::string(ch) + ": size not the full beat");
        if (addr % BEAT) violate(std::string(ch) + ": address not aligned to the beat");
        if (beats > 256) violate(std::string(ch) + ": more than 256 beats");
        if (addr / 4096 != (addr + beats * BEAT - 1) / 4096)
            violate(std::string(ch) + ": burst crosses a 4 KB boundary");
        if (addr < job_.base || addr + beats * BEAT > job_.base + frame_bytes_) {
            violate(std::string(ch) + ": burst outside the memory");
            return false;
        }
        return true;
    }
};

}  // namespace dptbd_harness
