#include "core/atomic_file.hpp"

#include "core/error.hpp"

#include <array>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <system_error>
#include <unistd.h>

namespace crackle {

namespace {

// Temporary files an interrupt must remove: C strings the handler may read at any moment
// (unlink is async-signal-safe; the table is lock-free).
constexpr std::size_t kSlots = 1024;
std::array<std::atomic<char*>, kSlots> g_temporaries{};

int register_temporary(const std::filesystem::path& tmp) {
    char* copy = ::strdup(tmp.c_str());
    if (!copy) return -1;
    for (std::size_t i = 0; i < kSlots; ++i) {
        char* expected = nullptr;
        if (g_temporaries[i].compare_exchange_strong(expected, copy)) return static_cast<int>(i);
    }
    std::free(copy);
    return -1; // more than kSlots pending files: the destructor still removes them
}

void unregister_temporary(int slot) {
    if (slot < 0) return;
    std::free(g_temporaries[static_cast<std::size_t>(slot)].exchange(nullptr));
}

std::atomic<int> g_committing{0};
/// A signal that arrived on another thread during a commit (HeldSignals blocks them only on the
/// committing thread; a pool or llvmpipe thread may take it): delivered when the commit ends.
std::atomic<int> g_deferred{0};

extern "C" void remove_temporaries_and_exit(int sig) {
    if (g_committing.load() > 0) {
        g_deferred.store(sig);
        // Checked again: if the commit ended in between, its end saw no deferred signal.
        if (g_committing.load() > 0) return;
        g_deferred.store(0);
    }
    remove_pending_temporaries();
    std::signal(sig, SIG_DFL);
    std::raise(sig);
}

/// Holds SIGINT, SIGTERM and SIGHUP for its lifetime (they are delivered when it ends).
class HeldSignals {
public:
    HeldSignals() {
        sigset_t set;
        sigemptyset(&set);
        sigaddset(&set, SIGINT);
        sigaddset(&set, SIGTERM);
        sigaddset(&set, SIGHUP);
        pthread_sigmask(SIG_BLOCK, &set, &m_old);
    }
    ~HeldSignals() { pthread_sigmask(SIG_SETMASK, &m_old, nullptr); }
    HeldSignals(const HeldSignals&) = delete;
    HeldSignals& operator=(const HeldSignals&) = delete;

private:
    sigset_t m_old;
};

constexpr std::size_t kMaxNameBytes = 255;  // NAME_MAX of ext4, xfs, btrfs, tmpfs
constexpr std::size_t kMaxPathBytes = 4096; // PATH_MAX, with its NUL

} // namespace

void remove_pending_temporaries() {
    for (std::atomic<char*>& slot : g_temporaries)
        if (char* path = slot.load()) ::unlink(path);
}

bool commit_in_progress() {
    return g_committing.load() > 0;
}

void install_interrupt_cleanup() {
    for (int sig : {SIGINT, SIGTERM, SIGHUP})
        std::signal(sig, remove_temporaries_and_exit);
}

AtomicOutput::~AtomicOutput() {
    for (const Pending& p : m_pending) {
        if (p.fd >= 0) ::close(p.fd); // an unnamed file: gone with its descriptor
        std::error_code ec;
        if (!p.tmp.empty()) std::filesystem::remove(p.tmp, ec);
        unregister_temporary(p.slot);
    }
}

namespace {

bool write_all(int fd, std::string_view bytes) {
    while (!bytes.empty()) {
        const ssize_t n = ::write(fd, bytes.data(), bytes.size());
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        bytes.remove_prefix(static_cast<std::size_t>(n));
    }
    return true;
}

} // namespace

void AtomicOutput::write(const std::filesystem::path& path, std::string_view bytes) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path parent = path.parent_path();
    if (!parent.empty()) fs::create_directories(parent, ec);
    // An unnamed file in the target's folder (O_TMPFILE) until commit(): a run killed even
    // with SIGKILL leaves nothing behind. File systems without it get a named temporary.
    const fs::path folder = parent.empty() ? fs::path(".") : parent;
    const int fd = ::open(folder.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
    if (fd >= 0) {
        if (!write_all(fd, bytes)) {
            ::close(fd);
            throw InputError(path.string(), "writing failed (disk full?)", "free space or choose another --out");
        }
        m_pending.push_back({{}, path, -1, fd});
        return;
    }
    fs::path tmp = path;
    tmp += ".tmp" + std::to_string(::getpid());
    // Registered before the file exists, so that an interrupt while it is written removes it.
    Pending pending{tmp, path, register_temporary(tmp), -1};
    {
        std::ofstream os(tmp, std::ios::binary | std::ios::trunc);
        if (!os) {
            unregister_temporary(pending.slot);
            throw InputError(path.string(), "cannot write this file",
                             "check that the folder exists and is writable, or choose another --out");
        }
        os.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        if (!os) {
            os.close();
            fs::remove(tmp, ec);
            unregister_temporary(pending.slot);
            throw InputError(path.string(), "writing failed (disk full?)", "free space or choose another --out");
        }
    }
    m_pending.push_back(std::move(pending));
}

void AtomicOutput::write(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
    write(path, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

namespace {

/// Removes "<file>.tmp<pid>" and "<file>.old<pid>" of the given files that another process left:
/// the links a run killed inside its commit (SIGKILL, power loss) leaves beside its outputs.
/// Only the names this commit is about to replace are touched, so another run's files are safe.
void remove_debris_of(const std::vector<std::filesystem::path>& finals) {
    namespace fs = std::filesystem;
    std::map<fs::path, std::set<std::string>> by_dir;
    for (const fs::path& f : finals)
        by_dir[f.parent_path()].insert(f.filename().string());
    const std::string own = std::to_string(::getpid());
    for (const auto& [dir, names] : by_dir) {
        std::error_code ec;
        for (auto it = fs::directory_iterator(dir.empty() ? fs::path(".") : dir, ec);
             !ec && it != fs::directory_iterator(); it.increment(ec)) {
            const std::string name = it->path().filename().string();
            const std::size_t dot = name.rfind('.');
            if (dot == std::string::npos || dot + 4 >= name.size()) continue;
            const std::string kind = name.substr(dot + 1, 3), pid = name.substr(dot + 4);
            if ((kind != "tmp" && kind != "old") || pid == own
                || pid.find_first_not_of("0123456789") != std::string::npos || !names.count(name.substr(0, dot)))
                continue;
            std::error_code rm;
            fs::remove(it->path(), rm);
        }
    }
}

} // namespace

void AtomicOutput::commit() {
    namespace fs = std::filesystem;
    std::vector<fs::path> finals;
    for (const Pending& p : m_pending) {
        std::error_code ec;
        if (fs::is_directory(p.final_path, ec))
            throw InputError(p.final_path.string(), "is a folder, not a file",
                             "name a file here, or remove or rename the folder");
        finals.push_back(p.final_path);
    }
    remove_debris_of(finals);
    const HeldSignals held;
    // A budget's hard stop waits while files are being renamed.
    struct Committing {
        Committing() { ++g_committing; }
        ~Committing() {
            // A signal another thread deferred is raised on this one, where it is held until
            // HeldSignals ends just after: the files are all old or all new by then.
            if (--g_committing == 0)
                if (const int sig = g_deferred.exchange(0)) std::raise(sig);
        }
        Committing(const Committing&) = delete;
        Committing& operator=(const Committing&) = delete;
    } const committing;
    // Each replaced file keeps a hard link until every rename succeeded, to be put back if one fails.
    struct Done {
        fs::path final_path, backup;
    };
    std::vector<Done> done;
    auto roll_back = [&] {
        std::error_code ec;
        for (auto it = done.rbegin(); it != done.rend(); ++it) {
            if (it->backup.empty())
                fs::remove(it->final_path, ec);
            else
                fs::rename(it->backup, it->final_path, ec);
        }
    };
    auto fail = [&](const Pending& p, const std::string& what) {
        roll_back();
        throw InputError(p.final_path.string(), what,
                         "check permissions of the output folder; no file of this run was kept");
    };
    const std::string pid = std::to_string(::getpid());
    for (Pending& p : m_pending) {
        if (p.fd >= 0) {
            // The unnamed file gets a name beside its target, for the rename.
            p.tmp = p.final_path;
            p.tmp += ".tmp" + pid;
            const std::string self = "/proc/self/fd/" + std::to_string(p.fd);
            if (::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, p.tmp.c_str(), AT_SYMLINK_FOLLOW) != 0) {
                p.tmp.clear();
                fail(p, std::string("cannot name the finished file: ") + std::strerror(errno));
            }
            ::close(p.fd);
            p.fd = -1;
        }
        fs::path backup = p.final_path;
        backup += ".old" + pid;
        if (::link(p.final_path.c_str(), backup.c_str()) != 0) backup.clear();
        std::error_code ec;
        fs::rename(p.tmp, p.final_path, ec);
        if (ec) {
            if (!backup.empty()) fs::remove(backup, ec);
            fail(p, "cannot move the finished file into place: " + ec.message());
        }
        p.tmp.clear();
        done.push_back({p.final_path, backup});
    }
    for (const Done& d : done) {
        std::error_code ec;
        if (!d.backup.empty()) fs::remove(d.backup, ec);
    }
    for (const Pending& p : m_pending)
        unregister_temporary(p.slot);
    m_pending.clear();
}

void write_file_atomically(const std::filesystem::path& path, std::string_view bytes) {
    AtomicOutput out;
    out.write(path, bytes);
    out.commit();
}

void check_output_path(const std::filesystem::path& file, const std::string& option) {
    namespace fs = std::filesystem;
    const std::string fix = "choose another path for " + option;
    for (const fs::path& part : file)
        if (part.native().size() > kMaxNameBytes)
            throw InputError(option,
                             "a name in the path is " + std::to_string(part.native().size())
                                 + " bytes long, more than the " + std::to_string(kMaxNameBytes)
                                 + " a file system allows",
                             "shorten it");
    if (fs::absolute(file).native().size() >= kMaxPathBytes)
        throw InputError(option,
                         "the path is " + std::to_string(file.native().size()) + " bytes long, more than the "
                             + std::to_string(kMaxPathBytes - 1) + " the system allows",
                         "shorten it");
    std::error_code ec;
    if (fs::is_directory(file, ec))
        throw InputError(file.string(), "is a folder, not a file", "name a file for " + option);
    fs::path folder = file.parent_path();
    while (!folder.empty() && !fs::exists(folder, ec))
        folder = folder.parent_path();
    if (folder.empty()) folder = ".";
    if (!fs::is_directory(folder, ec))
        throw InputError(folder.string(), "is a file, so " + option + " cannot make a folder here", fix);
    if (::access(folder.c_str(), W_OK | X_OK) != 0)
        throw InputError(folder.string(), "this folder is not writable", fix);
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
