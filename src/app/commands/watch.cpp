#include "app/commands/watch.hpp"

#include "core/error.hpp"
#include "core/timer.hpp"

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <thread>

namespace crackle::app {

namespace {

std::atomic<bool>* g_interrupt_stop = nullptr;

extern "C" void on_interrupt(int) {
    if (g_interrupt_stop) g_interrupt_stop->store(true);
    std::signal(SIGINT, SIG_DFL); // a second Ctrl-C ends the process at once
}

/// The file's content, or nothing while it cannot be read (an editor replacing it).
std::optional<std::string> read_all(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return std::nullopt;
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

bool stopped(const WatchControl& c) {
    return c.stop && c.stop->load();
}

} // namespace

void install_interrupt_stop(std::atomic<bool>& stop) {
    g_interrupt_stop = &stop;
    std::signal(SIGINT, on_interrupt);
}

int watch_command(const BakeArgs& args, const GlobalOptions& global, std::ostream& out, std::ostream& err,
                  const WatchControl& control) {
    const std::filesystem::path path = args.preset.name_or_path;
    if (!std::filesystem::is_regular_file(path))
        throw InputError("bake --watch", "'" + args.preset.name_or_path + "' is not a preset file",
                         "watch a .toml file you edit; start one with the line extends = \"mud\" and the keys "
                         "you want to change");
    BakeArgs preview = args;
    preview.preview = true;
    const auto poll = std::chrono::duration<double>(control.poll_seconds);
    std::optional<std::string> baked; // the content last baked
    int count = 0;
    while (!stopped(control)) {
        std::optional<std::string> now = read_all(path);
        if (!now || now == baked) {
            std::this_thread::sleep_for(poll);
            continue;
        }
        // Editors save in steps: bake once the content has held still for one poll.
        std::this_thread::sleep_for(poll);
        if (read_all(path) != now) continue;
        baked = now;
        Timer timer;
        bool ok = false;
        try {
            bake_command(preview, global, out);
            ok = true;
        } catch (const InputError& e) {
            err << "error: " << e.what() << "\n";
        } catch (const NumericError& e) {
            err << "error: numeric failure: " << e.what() << "\n";
        }
        ++count;
        std::ostringstream took;
        took.setf(std::ios::fixed);
        took.precision(1);
        took << timer.seconds();
        out << "crackle bake --watch: " << (ok ? "baked" : "failed") << " in " << took.str() << " s; watching "
            << path.string() << " (Ctrl-C stops)" << std::endl;
        if (control.on_bake) control.on_bake(count, ok);
    }
    if (!global.quiet) out << "crackle bake --watch: stopped after " << count << " bakes\n";
    return 0;
}

} // namespace crackle::app
