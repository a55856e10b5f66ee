// progress.cpp: the bar redraws at most 10×/s on a TTY; non-TTY output gets a line per ~5 s.
#include "ltm/core/progress.h"

#include <cmath>
#include <cstdio>

#include <unistd.h>

#include "ltm/core/log.h"

namespace ltm {

std::string format_count(double v) {
    const char *suffix[] = {"", " k", " M", " G", " T"};
    int i = 0;
    while (std::abs(v) >= 1000.0 && i < 4) v /= 1000.0, ++i;
    char buf[32];
    std::snprintf(buf, sizeof buf, v < 10 ? "%.2f%s" : (v < 100 ? "%.1f%s" : "%.0f%s"), v, suffix[i]);
    return buf;
}

std::string format_duration(double s) {
    char buf[48];
    if (!std::isfinite(s)) return "?";
    if (s < 60) std::snprintf(buf, sizeof buf, "%.1f s", s);
    else if (s < 3600) std::snprintf(buf, sizeof buf, "%d min %02d s", int(s) / 60, int(s) % 60);
    else std::snprintf(buf, sizeof buf, "%d h %02d min", int(s) / 3600, (int(s) / 60) % 60);
    return buf;
}

Progress::Progress(std::string label, uint64_t total, std::string unit, bool show)
    : m_label(std::move(label)), m_unit(std::move(unit)), m_total(total ? total : 1),
      m_start(std::chrono::steady_clock::now()), m_last_draw(m_start),
      m_tty(isatty(fileno(stderr))), m_enabled(show && log_level() >= LogLevel::normal) {}

Progress::~Progress() { finish(); }

double Progress::elapsed_seconds() const {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count();
}

void Progress::add(uint64_t n) {
    const uint64_t done = m_done.fetch_add(n) + n;
    if (!m_enabled) return;
    const auto now = std::chrono::steady_clock::now();
    const double since = std::chrono::duration<double>(now - m_last_draw).count();
    if (since < (m_tty ? 0.1 : 5.0)) return;
    std::unique_lock lock(m_mutex, std::try_to_lock);
    if (!lock.owns_lock() || m_finished) return;
    m_last_draw = now;
    draw(done, false);
}

double Progress::finish() {
    std::lock_guard lock(m_mutex);
    const double t = elapsed_seconds();
    if (!m_finished && m_enabled) draw(m_done.load(), true);
    m_finished = true;
    return t;
}

void Progress::draw(uint64_t done, bool final_line) {
    const double t = elapsed_seconds();
    const double frac = std::min(1.0, double(done) / double(m_total));
    const double rate = t > 0 ? double(done) / t : 0.0;
    const double eta = rate > 0 ? double(m_total - std::min(done, m_total)) / rate : NAN;
    char tail[160];
    std::snprintf(tail, sizeof tail, " %5.1f%% %s/%s %s, %s %s/s, %s %s", 100 * frac,
                  format_count(double(done)).c_str(), format_count(double(m_total)).c_str(),
                  m_unit.c_str(), format_count(rate).c_str(), m_unit.c_str(),
                  final_line ? "took" : "ETA", format_duration(final_line ? t : eta).c_str());
    if (m_tty) {
        const int width = 30, filled = int(frac * width);
        std::string bar(size_t(filled), '#');
        bar.resize(size_t(width), '.');
        std::fprintf(stderr, "\r%s [%s]%s\033[K%s", m_label.c_str(), bar.c_str(), tail,
                     final_line ? "\n" : "");
    } else {
        std::fprintf(stderr, "%s:%s\n", m_label.c_str(), tail);
    }
    std::fflush(stderr);
}

}  // namespace ltm
