// `crackle bake --watch`: re-bakes when the preset file changes, survives a bad preset, stops on request.
#include "app/commands/watch.hpp"
#include "support/cli_runner.hpp"
#include "support/gl_support.hpp"

#include <doctest/doctest.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <sstream>
#include <thread>

using namespace crackle;
namespace fs = std::filesystem;

namespace {

/// Counts the bakes a watch reports and lets the test wait for the next one.
struct Bakes {
    std::mutex mutex;
    std::condition_variable changed;
    std::vector<bool> results;

    void add(bool ok) {
        {
            const std::lock_guard<std::mutex> lock(mutex);
            results.push_back(ok);
        }
        changed.notify_all();
    }
    /// Waits (at most a minute) until `n` bakes have been reported.
    bool wait_for(std::size_t n) {
        std::unique_lock<std::mutex> lock(mutex);
        return changed.wait_for(lock, std::chrono::seconds(60), [&] { return results.size() >= n; });
    }
};

const char* preset_text(const char* extra) {
    static std::string text;
    text = std::string("extends = \"mud\"\n[simulation]\nelements = 300\n") + extra;
    return text.c_str();
}

} // namespace

TEST_SUITE("app") {
    TEST_CASE("watch: re-bakes when the preset is saved, reports a bad edit with its line and goes on, and stops "
              "cleanly") {
        if (!test::gl_context_or_skip()) return;
        const fs::path dir = test::scratch_dir("watch");
        const fs::path preset = test::write_text(dir / "tile.toml", preset_text(""));
        app::BakeArgs args;
        args.preset.name_or_path = preset.string();
        args.out_dir = (dir / "maps").string();
        std::atomic<bool> stop{false};
        Bakes bakes;
        app::WatchControl control;
        control.stop = &stop;
        control.poll_seconds = 0.05;
        control.on_bake = [&](int, bool ok) { bakes.add(ok); };
        std::ostringstream out, err;
        int code = -1;
        std::thread watcher([&] { code = app::watch_command(args, app::GlobalOptions{true}, out, err, control); });

        REQUIRE(bakes.wait_for(1));
        CHECK(fs::exists(dir / "maps" / "tile_Color.png"));
        const auto first = fs::last_write_time(dir / "maps" / "tile_Color.png");
        // A typo: the watch reports it with the file and line and keeps going.
        test::write_text(preset, preset_text("[material]\nyoung_modulos = 1e7\n"));
        REQUIRE(bakes.wait_for(2));
        // The fix: baked again, into the same files.
        test::write_text(preset, preset_text("[material]\nyoung_modulus = 2e7\n"));
        REQUIRE(bakes.wait_for(3));
        // Saving the same content again is not a change.
        test::write_text(preset, preset_text("[material]\nyoung_modulus = 2e7\n"));
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        stop = true;
        watcher.join();

        CHECK(code == 0);
        REQUIRE(bakes.results.size() == 3);
        CHECK(bakes.results[0]);
        CHECK_FALSE(bakes.results[1]);
        CHECK(bakes.results[2]);
        CHECK(err.str().find("tile.toml:5") != std::string::npos);
        CHECK(err.str().find("young_modulus") != std::string::npos); // the "did you mean"
        CHECK(fs::last_write_time(dir / "maps" / "tile_Color.png") > first);
        CHECK(out.str().find("baked in") != std::string::npos);
    }

    TEST_CASE("watch: a built-in preset name cannot be watched (exit 2, nothing baked)") {
        const fs::path dir = test::scratch_dir("watch-builtin");
        const auto r = test::run_cli({"bake", "mud", "--watch", "--out", (dir / "maps").string()});
        CHECK(r.code == 2);
        CHECK(r.err.find("not a preset file") != std::string::npos);
        CHECK_FALSE(fs::exists(dir / "maps"));
    }
}
