// progress.h: progress reporting for long loops: a redrawn bar on a TTY, plain lines otherwise
// (at most one every few seconds), always with a rate and an ETA. Thread-safe.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <string>

namespace ltm {

class Progress {
public:
    /// `unit` names what is counted ("points", "rays", "scenes"); total > 0. `show` false keeps it
    /// silent (a step inside a larger loop that has its own bar); it also stays silent below
    /// LogLevel::normal.
    Progress(std::string label, uint64_t total, std::string unit, bool show = true);
    ~Progress();
    Progress(const Progress &) = delete;
    Progress &operator=(const Progress &) = delete;
    void add(uint64_t n = 1);
    /// Prints the final line (idempotent); returns the elapsed seconds.
    double finish();
    double elapsed_seconds() const;

private:
    void draw(uint64_t done, bool final_line);
    std::string m_label, m_unit;
    uint64_t m_total;
    std::atomic<uint64_t> m_done{0};
    std::chrono::steady_clock::time_point m_start, m_last_draw;
    std::mutex m_mutex;
    bool m_tty, m_finished = false, m_enabled;
};

/// "12.3 k", "4.56 M": compact human-readable counts for rates.
std::string format_count(double v);
/// "1 h 02 min", "3.4 s".
std::string format_duration(double seconds);
/// Seconds on the steady clock since `t` (a stage's timing: t = steady_clock::now(), work, then this).
inline double seconds_since(std::chrono::steady_clock::time_point t) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace ltm
