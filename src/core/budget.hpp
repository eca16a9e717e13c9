#pragma once
/// @file A run's budget of wall time and memory (issue 16, "bounded work"): `--max-time` and
/// `--max-memory` (or $CRACKLE_MAX_TIME, $CRACKLE_MAX_MEMORY).
///
/// A BudgetScope watches one run from a thread of its own: it reads the clock and the
/// resident memory (/proc/self/statm) twenty times a second. When the run passes a limit it
/// raises a flag that the run's loops see at their next budget_check() (every Progress update,
/// every fracture event, every Newton iteration), which throws BudgetError: the run unwinds,
/// writes nothing (outputs are placed only when all are made, AtomicOutput) and exits 2. A run
/// stuck in one long step that never checks (a sparse factorization, a GL draw) is ended hard
/// after a grace period: the message, then the named temporaries removed, then _exit(2), never
/// in the middle of a commit's renames.
///
/// The budget never changes a result: a run either finishes with the bytes it would have
/// written without a budget or stops with nothing written.

#include "core/error.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace crackle {

/// A run that passed its time or memory budget: bad input in the sense that the request does
/// not fit the budget it was given (exit 2, with the fix).
class BudgetError : public InputError {
public:
    using InputError::InputError;
};

/// The limits of every run in this process; 0 = none.
struct BudgetLimits {
    double seconds = 0;        ///< --max-time
    std::uint64_t bytes = 0;   ///< --max-memory; 0 = the machine's (machine_memory_bytes)
    std::string time_source;   ///< where the limits came from, for messages: "--max-time"
    std::string memory_source; ///< "--max-memory", or "" for the machine's memory
};

/// Sets the process-wide limits (the CLI, once).
void set_budget_limits(const BudgetLimits& limits);
const BudgetLimits& budget_limits();

/// The memory this process may use: the smallest of the machine's RAM (MemTotal) and its
/// control group's limit (memory.max, cgroup v2, as a container or a Slurm job sets it).
std::uint64_t machine_memory_bytes();

/// The memory budget in force: --max-memory, else 90 % of the machine's memory (the rest is
/// the system's; a run stopped there exits 2 instead of being killed by the kernel); no limit
/// when the machine's memory cannot be read.
std::uint64_t memory_budget_bytes();

/// Resident memory of this process now, in bytes (0 if unknown).
std::uint64_t resident_bytes();

/// Parses a size: "512M", "8G", "8GiB", "1.5g", "2000000000" (bytes); K/M/G/T are powers of
/// 1024. nullopt for anything else, or for 0.
std::optional<std::uint64_t> parse_memory_size(std::string_view text);

/// "" for a valid size, else what is wrong (the CLI's check).
std::string memory_size_check(const std::string& text);

/// "1.5 GiB", "300 MiB".
std::string format_bytes(double bytes);

/// "45 s", "12 min", "3.2 h".
std::string format_seconds(double seconds);

/// Watches one run (see the file comment). Nested scopes share the outer one's clock.
class BudgetScope {
public:
    /// @param what  what runs, for messages: "bake of mud (seed 3)"
    explicit BudgetScope(std::string what);
    ~BudgetScope();
    BudgetScope(const BudgetScope&) = delete;
    BudgetScope& operator=(const BudgetScope&) = delete;

private:
    bool m_owner = false;
};

/// Throws BudgetError when the current run has passed its budget. Cheap (one atomic load); does
/// nothing off the thread that opened the scope (never throws inside a worker or a parallel
/// loop).
void budget_check();

} // namespace crackle
