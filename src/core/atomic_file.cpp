#include "core/atomic_file.hpp"

#include "core/error.hpp"

#include <fstream>
#include <sstream>
#include <system_error>
#include <unistd.h>

namespace crackle {

AtomicOutput::~AtomicOutput() {
    for (const auto& [tmp, final_path] : m_pending) {
        std::error_code ec;
        std::filesystem::remove(tmp, ec);
    }
}

void AtomicOutput::write(const std::filesystem::path& path, std::string_view bytes) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path parent = path.parent_path();
    if (!parent.empty()) fs::create_directories(parent, ec);
    fs::path tmp = path;
    tmp += ".tmp" + std::to_string(::getpid());
    {
        std::ofstream os(tmp, std::ios::binary | std::ios::trunc);
        if (!os)
            throw InputError(path.string(), "cannot write this file",
                             "check that the folder exists and is writable, or choose another --out");
        os.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        if (!os) {
            os.close();
            fs::remove(tmp, ec);
            throw InputError(path.string(), "writing failed (disk full?)", "free space or choose another --out");
        }
    }
    m_pending.emplace_back(tmp, path);
}

void AtomicOutput::write(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
    write(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

void AtomicOutput::commit() {
    for (const auto& [tmp, final_path] : m_pending) {
        std::error_code ec;
        std::filesystem::rename(tmp, final_path, ec);
        if (ec)
            throw InputError(final_path.string(), "cannot move the finished file into place: " + ec.message(),
                             "check permissions of the output folder");
    }
    m_pending.clear();
}

void write_file_atomically(const std::filesystem::path& path, std::string_view bytes) {
    AtomicOutput out;
    out.write(path, bytes);
    out.commit();
}

std::string read_file(const std::filesystem::path& path, const std::string& what) {
    std::ifstream is(path, std::ios::binary);
    if (!is || std::filesystem::is_directory(path))
        throw InputError(path.string(), what + " not found or not readable", "check the path and its spelling");
    std::ostringstream ss;
    ss << is.rdbuf();
    return ss.str();
}

} // namespace crackle
