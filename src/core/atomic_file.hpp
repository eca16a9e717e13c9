#pragma once
/// @file All-or-nothing output (design.md: "a failed run leaves no half files"). Each file is
/// written to a temporary sibling; commit() renames them all at the end of a successful run,
/// and the destructor removes whatever was not committed.

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

    /// Renames every temporary file onto its final path.
    void commit();

private:
    std::vector<std::pair<std::filesystem::path, std::filesystem::path>> m_pending; // tmp, final
};

/// Writes one file atomically.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

/// Reads a whole file; throws InputError naming the file when it cannot.
std::string read_file(const std::filesystem::path& path, const std::string& what = "file");

} // namespace crackle
