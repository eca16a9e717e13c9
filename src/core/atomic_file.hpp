#pragma once
/// @file All-or-nothing output (design.md: "a failed run leaves no half files"). Each file is
/// written to an unnamed file in its folder (O_TMPFILE; a named "<file>.tmp<pid>" where the file
/// system lacks it); commit() checks every destination, then names and renames them all, and
/// puts back what it replaced if a rename fails midway. A run that ends before commit(), even by
/// SIGKILL, leaves nothing; SIGINT/SIGTERM/SIGHUP (install_interrupt_cleanup) remove named
/// temporaries too.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace crackle {

class AtomicOutput {
public:
    AtomicOutput() = default;
    AtomicOutput(const AtomicOutput&) = delete;
    AtomicOutput& operator=(const AtomicOutput&) = delete;
    ~AtomicOutput();

    /// Writes `bytes` to a temporary file next to `path` (creating parent folders).
    /// Throws InputError when the folder cannot be written.
    void write(const std::filesystem::path& path, std::string_view bytes);
    void write(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes);

    /// Renames every temporary file onto its final path, all or none: a destination that is a
    /// folder is refused before any rename, and a rename that fails puts the earlier files back.
    /// Signals are held for the few renames, so an interrupt never leaves a mixed set.
    void commit();

private:
    struct Pending {
        std::filesystem::path tmp, final_path; ///< tmp: a named temporary, empty while unnamed
        int slot = -1;                         ///< in the interrupt clean-up table
        int fd = -1;                           ///< an unnamed (O_TMPFILE) file, until commit()
    };
    std::vector<Pending> m_pending;
};

/// Writes one file atomically.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

/// Refuses, before any work, an output file that cannot be written where asked: its name is a
/// folder, a parent is a file, the nearest existing folder is not writable, or a name is longer
/// than the file system allows. `option` names where the path came from ("--json", "--out").
void check_output_path(const std::filesystem::path& file, const std::string& option);

/// SIGINT, SIGTERM and SIGHUP remove every temporary file of a pending AtomicOutput and end the
/// process with the signal's usual status (130 for Ctrl-C). Installed once by the CLI.
void install_interrupt_cleanup();

/// Removes the named temporaries of every pending AtomicOutput (async-signal-safe; for a
/// process about to end at once, as the budget's hard stop does).
void remove_pending_temporaries();

/// True while a commit() is renaming files: a hard stop waits for it to end, so that it never
/// leaves a mixed set.
bool commit_in_progress();

/// Reads a whole file; throws InputError naming the file when it cannot.
std::string read_file(const std::filesystem::path& path, const std::string& what = "file");

} // namespace crackle
