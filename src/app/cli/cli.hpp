#pragma once
/// @file The command line (CLI11, kept in this one translation unit).

#include <ostream>

namespace crackle::app {

/// Parses the arguments and runs the command. Returns the exit code: 0 success, 2 bad
/// input, 3 numeric failure, 1 anything else. Messages go to `err`, results to `out`.
int run(int argc, const char* const* argv, std::ostream& out, std::ostream& err);

} // namespace crackle::app
