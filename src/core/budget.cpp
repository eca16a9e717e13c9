#include "core/budget.hpp"

#include "core/atomic_file.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <fstream>
#include <limits>
#include <mutex>
#include <sstream>
#include <thread>
#include <unistd.h>

namespace crackle {

namespace {

BudgetLimits g_limits;

/// The watchdog of the open scope. One at a time (scopes nest by sharing it).
struct Watch {
    std::mutex mutex;
    std::condition_variable wake;
    bool stop = false;
    std::thread thread;
    std::thread::id owner;
    std::string what;
    std::string message; ///< the breach, whole ("<where>: <what> (<fix>)")
    int depth = 0;
};
Watch g_watch;
std::atomic<bool> g_breached{false};

constexpr auto kPeriod = std::chrono::milliseconds(50);

/// How long a run may go on after its breach before it is ended hard: long enough for the
/// loops to reach their next check, short against the budget.
double grace_seconds(double limit) {
    return std::clamp(0.1 * limit, 2.0, 30.0);
}

std::uint64_t read_number(const std::string& path) {
    std::ifstream in(path);
    std::string word;
    if (!(in >> word) || word == "max") return 0;
    try {
        return std::stoull(word);
    } catch (const std::exception&) {
        return 0;
    }
}

/// The memory limit of this process's control group, 0 if none (cgroup v2, then v1).
std::uint64_t cgroup_limit() {
    std::ifstream self("/proc/self/cgroup");
    std::string line;
    while (std::getline(self, line)) {
        if (line.rfind("0::", 0) == 0) {
            const std::string dir = "/sys/fs/cgroup" + line.substr(3);
            if (const std::uint64_t v = read_number(dir + "/memory.max")) return v;
            if (const std::uint64_t v = read_number("/sys/fs/cgroup/memory.max")) return v;
        }
    }
    const std::uint64_t v1 = read_number("/sys/fs/cgroup/memory/memory.limit_in_bytes");
    return v1 < (std::uint64_t{1} << 60) ? v1 : 0; // v1 reports "no limit" as a huge number
}

std::string breach_message(bool time, double elapsed, std::uint64_t rss, std::uint64_t budget) {
    std::ostringstream what;
    std::string where, fix;
    if (time) {
        where = g_limits.time_source.empty() ? "--max-time" : g_limits.time_source;
        what << g_watch.what << " passed its time budget of " << format_seconds(g_limits.seconds) << " (ran "
             << format_seconds(elapsed) << ")";
        fix = "raise " + where
              + ", or ask for less work: fewer simulation.elements, a shorter "
                "simulation.duration, a smaller bake.size; nothing was written";
    } else {
        where = g_limits.memory_source.empty() ? "memory" : g_limits.memory_source;
        what << g_watch.what << " passed its memory budget of " << format_bytes(static_cast<double>(budget))
             << " (resident " << format_bytes(static_cast<double>(rss)) << ")";
        fix = g_limits.memory_source.empty()
                  ? "the budget is 90 % of this machine's memory; ask for less work: fewer simulation.elements, "
                    "fewer simulation.layers, a smaller bake.size; nothing was written"
                  : "raise " + where
                        + ", or ask for less work: fewer simulation.elements, fewer "
                          "simulation.layers, a smaller bake.size; nothing was written";
    }
    return where + ": " + what.str() + " (" + fix + ")";
}

[[noreturn]] void hard_stop(const std::string& message) {
    const std::string text = "error: " + message
                             + " [ended at once: the run was in a step that does not stop "
                               "by itself]\n";
    [[maybe_unused]] const ssize_t n = ::write(2, text.data(), text.size());
    remove_pending_temporaries();
    ::_exit(2);
}

void watch_loop(std::chrono::steady_clock::time_point start) {
    const std::uint64_t budget = memory_budget_bytes();
    double breach_at = -1;
    std::unique_lock lock(g_watch.mutex);
    while (!g_watch.wake.wait_for(lock, kPeriod, [] { return g_watch.stop; })) {
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (breach_at < 0) {
            const bool late = g_limits.seconds > 0 && elapsed > g_limits.seconds;
            const std::uint64_t rss = resident_bytes();
            if (late || rss > budget) {
                g_watch.message = breach_message(late, elapsed, rss, budget);
                breach_at = elapsed;
                g_breached.store(true);
            }
        } else if (elapsed - breach_at > grace_seconds(g_limits.seconds) && !commit_in_progress()) {
            hard_stop(g_watch.message);
        }
    }
}

} // namespace

void set_budget_limits(const BudgetLimits& limits) {
    g_limits = limits;
}
const BudgetLimits& budget_limits() {
    return g_limits;
}

std::uint64_t machine_memory_bytes() {
    std::uint64_t total = 0;
    std::ifstream in("/proc/meminfo");
    std::string key;
    std::uint64_t kb = 0;
    std::string unit;
    while (in >> key >> kb >> unit)
        if (key == "MemTotal:") {
            total = kb * 1024;
            break;
        }
    if (total == 0) {
        const long pages = ::sysconf(_SC_PHYS_PAGES);
        const long page = ::sysconf(_SC_PAGESIZE);
        if (pages > 0 && page > 0) total = static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page);
    }
    const std::uint64_t group = cgroup_limit();
    return group > 0 && (total == 0 || group < total) ? group : total;
}

std::uint64_t memory_budget_bytes() {
    if (g_limits.bytes > 0) return g_limits.bytes;
    const std::uint64_t machine = machine_memory_bytes();
    if (machine == 0) return std::numeric_limits<std::uint64_t>::max(); // unknown: no default budget
    return static_cast<std::uint64_t>(0.9 * static_cast<double>(machine));
}

std::uint64_t resident_bytes() {
    std::ifstream in("/proc/self/statm");
    std::uint64_t size = 0, resident = 0;
    if (!(in >> size >> resident)) return 0;
    return resident * static_cast<std::uint64_t>(::sysconf(_SC_PAGESIZE));
}

std::optional<std::uint64_t> parse_memory_size(std::string_view text) {
    std::string s(text);
    std::size_t used = 0;
    double value = 0;
    try {
        value = std::stod(s, &used);
    } catch (const std::exception&) {
        return std::nullopt;
    }
    std::string unit = s.substr(used);
    for (char& c : unit)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    double scale = 1;
    if (unit.empty() || unit == "b")
        scale = 1;
    else if (unit == "k" || unit == "kb" || unit == "kib")
        scale = 1024.0;
    else if (unit == "m" || unit == "mb" || unit == "mib")
        scale = 1024.0 * 1024;
    else if (unit == "g" || unit == "gb" || unit == "gib")
        scale = 1024.0 * 1024 * 1024;
    else if (unit == "t" || unit == "tb" || unit == "tib")
        scale = 1024.0 * 1024 * 1024 * 1024;
    else
        return std::nullopt;
    const double bytes = value * scale;
    if (!std::isfinite(bytes) || bytes < 1 || bytes > 1.0e18) return std::nullopt;
    return static_cast<std::uint64_t>(bytes);
}

std::string memory_size_check(const std::string& text) {
    return parse_memory_size(text) ? ""
                                   : "a size such as 512M, 8G or 8GiB (K, M, G, T: powers of 1024), not '" + text + "'";
}

std::string format_bytes(double bytes) {
    char buf[64];
    if (bytes >= 1024.0 * 1024 * 1024)
        std::snprintf(buf, sizeof buf, "%.1f GiB", bytes / (1024.0 * 1024 * 1024));
    else
        std::snprintf(buf, sizeof buf, "%.0f MiB", std::ceil(bytes / (1024.0 * 1024)));
    return buf;
}

std::string format_seconds(double seconds) {
    char buf[64];
    if (seconds < 120)
        std::snprintf(buf, sizeof buf, "%.3g s", seconds);
    else if (seconds < 2 * 3600)
        std::snprintf(buf, sizeof buf, "%.0f min", seconds / 60);
    else
        std::snprintf(buf, sizeof buf, "%.1f h", seconds / 3600);
    return buf;
}

BudgetScope::BudgetScope(std::string what) {
    const std::lock_guard lock(g_watch.mutex);
    if (g_watch.depth++ > 0) return;
    m_owner = true;
    g_breached.store(false);
    g_watch.stop = false;
    g_watch.message.clear();
    g_watch.what = std::move(what);
    g_watch.owner = std::this_thread::get_id();
    g_watch.thread = std::thread(watch_loop, std::chrono::steady_clock::now());
}

BudgetScope::~BudgetScope() {
    {
        const std::lock_guard lock(g_watch.mutex);
        --g_watch.depth;
        if (!m_owner) return;
        g_watch.stop = true;
    }
    g_watch.wake.notify_all();
    if (g_watch.thread.joinable()) g_watch.thread.join();
    g_breached.store(false);
}

void budget_check() {
    if (!g_breached.load(std::memory_order_relaxed)) return;
    std::string message;
    {
        const std::lock_guard lock(g_watch.mutex);
        if (std::this_thread::get_id() != g_watch.owner || g_watch.message.empty()) return;
        message = g_watch.message;
    }
    throw BudgetError(message);
}

} // namespace crackle
