#include "core/error.hpp"

namespace crackle {

namespace {

/// A path or value quoted in a message stays readable: a 10 MB name is shown by its ends.
std::string clipped(const std::string& s, std::size_t max) {
    if (s.size() <= max) return s;
    const std::size_t head = max / 2, tail = max / 3;
    return s.substr(0, head) + "…[" + std::to_string(s.size()) + " bytes]…" + s.substr(s.size() - tail);
}

} // namespace

InputError::InputError(const std::string& where, const std::string& what, const std::string& fix)
    : std::runtime_error(where.empty()
                             ? clipped(what, 2000) + " (" + clipped(fix, 2000) + ")"
                             : clipped(where, 240) + ": " + clipped(what, 2000) + " (" + clipped(fix, 2000) + ")") {}

void assertion_failed(const char* expr, const std::string& msg, const char* file, int line) {
    std::ostringstream os;
    os << file << ":" << line << ": assertion failed: " << expr;
    if (!msg.empty()) os << ": " << msg;
    throw InvariantError(os.str());
}

} // namespace crackle
