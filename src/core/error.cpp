#include "core/error.hpp"

namespace crackle {

InputError::InputError(const std::string& where, const std::string& what, const std::string& fix)
    : std::runtime_error(where.empty() ? what + " (" + fix + ")" : where + ": " + what + " (" + fix + ")") {}

void assertion_failed(const char* expr, const std::string& msg, const char* file, int line) {
    std::ostringstream os;
    os << file << ":" << line << ": assertion failed: " << expr;
    if (!msg.empty()) os << ": " << msg;
    throw InvariantError(os.str());
}

} // namespace crackle
