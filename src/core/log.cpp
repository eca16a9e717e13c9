#include "core/log.hpp"

#include "core/progress.hpp"

#include <atomic>
#include <iostream>
#include <mutex>

namespace crackle::log {
namespace {
std::atomic<Level> g_level{Level::Warn};
std::ostream* g_stream = nullptr;
std::mutex g_mutex;
} // namespace

void set_level(Level lvl) {
    g_level = lvl;
}
Level level() {
    return g_level;
}
void set_stream(std::ostream* os) {
    std::lock_guard lock(g_mutex);
    g_stream = os;
}

void write(Level lvl, const std::string& message) {
    std::lock_guard lock(g_mutex);
    progress_clear_line(); // a message never lands in the middle of a progress bar
    std::ostream& os = g_stream ? *g_stream : std::cerr;
    switch (lvl) {
    case Level::Error:
        os << "error: ";
        break;
    case Level::Warn:
        os << "warning: ";
        break;
    case Level::Info:
        break;
    case Level::Debug:
        os << "debug: ";
        break;
    }
    os << message << '\n';
}

} // namespace crackle::log
