#pragma once
/// @file The three kinds of failure (style guide §6): bad input (exit 2), numeric failure
/// (exit 3) and broken invariants (CRACKLE_ASSERT, exit 1).

#include <sstream>
#include <stdexcept>
#include <string>

namespace crackle {

/// Bad input: an unknown preset key, a missing file, an out-of-range value.
/// what() reads "<where>: <what> (<how to fix>)"; main prints "error: " before it and exits 2.
class InputError : public std::runtime_error {
public:
    InputError(const std::string& where, const std::string& what, const std::string& fix);
    explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

/// Numeric failure (no convergence, not SPD, NaN): carries the numbers; main exits 3.
class NumericError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A broken internal invariant; CRACKLE_ASSERT throws it with file:line.
class InvariantError : public std::logic_error {
public:
    using std::logic_error::logic_error;
};

[[noreturn]] void assertion_failed(const char* expr, const std::string& msg, const char* file, int line);

} // namespace crackle

/// Stays on in release builds (geometry-central: GC_SAFETY_ASSERT).
#define CRACKLE_ASSERT(cond, msg)                                                                                      \
    do {                                                                                                               \
        if (!(cond)) {                                                                                                 \
            std::ostringstream crackle_assert_os_;                                                                     \
            crackle_assert_os_ << msg;                                                                                 \
            ::crackle::assertion_failed(#cond, crackle_assert_os_.str(), __FILE__, __LINE__);                          \
        }                                                                                                              \
    } while (false)

#ifndef NDEBUG
#define CRACKLE_DCHECK(cond) CRACKLE_ASSERT(cond, "")
#define CRACKLE_DCHECK_LT(a, b) CRACKLE_ASSERT((a) < (b), #a " = " << (a) << ", " #b " = " << (b))
#else
#define CRACKLE_DCHECK(cond) ((void)0)
#define CRACKLE_DCHECK_LT(a, b) ((void)0)
#endif
