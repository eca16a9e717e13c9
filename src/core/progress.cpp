#include "core/progress.hpp"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <unistd.h>

namespace crackle {
namespace {
std::atomic<bool> g_enabled{true};
}

void set_progress_enabled(bool enabled) {
    g_enabled = enabled;
}

Progress::Progress(std::string label, double total)
    : m_label(std::move(label)), m_total(total), m_active(g_enabled && ::isatty(STDERR_FILENO) == 1) {}

Progress::~Progress() {
    finish();
}

void Progress::update(double done) {
    if (!m_active) return;
    const double t = m_timer.seconds();
    if (t < 1.0 || t - m_last_draw < 0.1) return;
    m_last_draw = t;
    draw(done);
}

void Progress::draw(double done) {
    constexpr int WIDTH = 30;
    const double fraction = m_total > 0 ? std::clamp(done / m_total, 0.0, 1.0) : 0.0;
    const int filled = static_cast<int>(fraction * WIDTH);
    std::string bar(static_cast<size_t>(filled), '#');
    bar.resize(WIDTH, '-');
    std::fprintf(stderr, "\r%-14s [%s] %5.1f%%  %6.1fs", m_label.c_str(), bar.c_str(), 100.0 * fraction,
                 m_timer.seconds());
    std::fflush(stderr);
    m_drawn = true;
}

void Progress::finish() {
    if (m_drawn) {
        draw(m_total);
        std::fprintf(stderr, "\n");
        m_drawn = false;
    }
    m_active = false;
}

} // namespace crackle
