#pragma once
/// @file Wall-clock timing of pipeline steps, for reports (never for tests).

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace crackle {

class Timer {
public:
    Timer() : m_start(std::chrono::steady_clock::now()) {}
    double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - m_start).count(); }
    void reset() { m_start = std::chrono::steady_clock::now(); }

private:
    std::chrono::steady_clock::time_point m_start;
};

/// Named wall times in the order they were recorded ("sampling", "triangulation", ...).
using StepTimes = std::vector<std::pair<std::string, double>>;

/// Peak resident set size of this process in MiB (VmHWM from /proc/self/status; 0 if unknown).
double peak_memory_mb();

} // namespace crackle
