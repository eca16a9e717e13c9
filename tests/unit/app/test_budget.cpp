/// Bounded work (issue 16): --max-time and --max-memory, the up-front estimate that refuses a
/// run that cannot fit, the watchdog that stops one that outgrows its budget (at the next check,
/// or at once after a grace period when a step never checks), and that a budget never changes
/// what a finished run writes.
#include "app/run/run_budget.hpp"
#include "core/budget.hpp"
#include "io/preset.hpp"
#include "support/cli_runner.hpp"
#include "support/gl_support.hpp"

#include <doctest/doctest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

using namespace crackle;
using test::contains;
using test::run_cli;
namespace fs = std::filesystem;

namespace {

/// Sets the process-wide limits for one scope.
class Limits {
public:
    explicit Limits(const BudgetLimits& limits) : m_old(budget_limits()) { set_budget_limits(limits); }
    ~Limits() { set_budget_limits(m_old); }
    Limits(const Limits&) = delete;
    Limits& operator=(const Limits&) = delete;

private:
    BudgetLimits m_old;
};

void sleep_s(double s) {
    std::this_thread::sleep_for(std::chrono::duration<double>(s));
}

/// The BudgetError message budget_check() throws now, or "" when it does not throw.
std::string breach() {
    try {
        budget_check();
    } catch (const BudgetError& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST_SUITE("core") {
    TEST_CASE("budget: sizes read as bytes in powers of 1024, and anything else is refused in words") {
        CHECK(parse_memory_size("512M") == 512ull << 20);
        CHECK(parse_memory_size("8G") == 8ull << 30);
        CHECK(parse_memory_size("8GiB") == 8ull << 30);
        CHECK(parse_memory_size("1.5g") == 3ull << 29);
        CHECK(parse_memory_size("2000000000") == 2000000000ull);
        for (const char* bad : {"", "0", "12X", "-1G", "G", "1e30T", "nan", "8 G"}) {
            CAPTURE(bad);
            CHECK(!parse_memory_size(bad));
            CHECK(contains(memory_size_check(bad), "512M"));
        }
        CHECK(memory_size_check("4G").empty());
        CHECK(format_bytes(1.5 * (1u << 30)) == "1.5 GiB");
        CHECK(format_seconds(45) == "45 s");
        CHECK(format_seconds(720) == "12 min");
        // The machine's memory is what /proc/meminfo or the control group says, and the default
        // budget is 90 % of it.
        const std::uint64_t machine = machine_memory_bytes();
        CHECK(machine > (256ull << 20));
        const Limits none({});
        CHECK(memory_budget_bytes() == static_cast<std::uint64_t>(0.9 * static_cast<double>(machine)));
    }

    TEST_CASE("budget: a run past its time is stopped at its next check, on its own thread only, and the flag "
              "ends with the scope") {
        BudgetLimits l;
        l.seconds = 0.3;
        l.time_source = "--max-time";
        const Limits limits(l);
        {
            const BudgetScope scope("the test run");
            CHECK(breach().empty());
            sleep_s(0.6);
            const std::string message = breach();
            CHECK_MESSAGE(contains(message, "--max-time: the test run passed its time budget of 0.3 s"), message);
            CHECK(contains(message, "nothing was written"));
            // A worker thread never throws (it may be inside a parallel loop).
            std::string other = "not run";
            std::thread([&] { other = breach(); }).join();
            CHECK(other.empty());
        }
        CHECK(breach().empty());
        // A new scope starts its own clock.
        const BudgetScope again("the next run");
        CHECK(breach().empty());
    }

    TEST_CASE("budget: a run whose resident memory grows past its budget is stopped at its next check") {
        BudgetLimits l;
        l.bytes = resident_bytes() + (64ull << 20);
        l.memory_source = "--max-memory";
        const Limits limits(l);
        const BudgetScope scope("the test run");
        CHECK(breach().empty());
        std::vector<char> big(192ull << 20);
        std::memset(big.data(), 1, big.size()); // resident, not just reserved
        sleep_s(0.3);
        const std::string message = breach();
        CHECK_MESSAGE(contains(message, "--max-memory: the test run passed its memory budget"), message);
        CHECK(big[12345] == 1);
    }

    TEST_CASE("budget: a run stuck where it never checks is ended hard after the grace period, with exit 2 and "
              "its message") {
        int pipe_fds[2];
        REQUIRE(::pipe(pipe_fds) == 0);
        const auto t0 = std::chrono::steady_clock::now();
        const pid_t pid = ::fork();
        REQUIRE(pid >= 0);
        if (pid == 0) {
            ::dup2(pipe_fds[1], 2);
            BudgetLimits l;
            l.seconds = 0.2;
            l.time_source = "--max-time";
            set_budget_limits(l);
            const BudgetScope scope("the stuck run");
            volatile double x = 0;
            for (long i = 0; i < 40'000'000'000L; ++i) // about a minute; never checks its budget
                x = x + 1e-9;
            ::_exit(0);
        }
        ::close(pipe_fds[1]);
        int status = 0;
        ::waitpid(pid, &status, 0);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::string err(4096, '\0');
        const ssize_t n = ::read(pipe_fds[0], err.data(), err.size());
        err.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
        ::close(pipe_fds[0]);
        REQUIRE(WIFEXITED(status));
        CHECK(WEXITSTATUS(status) == 2);
        CHECK_MESSAGE(contains(err, "error: --max-time: the stuck run passed its time budget"), err);
        CHECK(contains(err, "ended at once"));
        CHECK(seconds < 20); // 0.2 s, then the 2 s grace; far from the minute the loop needs
    }
}

TEST_SUITE("app") {
    TEST_CASE("budget: a request too big for the memory budget is refused before any work, naming the key and "
              "the estimate") {
        const fs::path dir = test::scratch_dir("budget-refused");
        // 16384² maps are about 35 GiB: refused against a 4 GiB budget, before the simulation.
        auto r = run_cli({"--max-memory", "4G", "bake", "mud", "--size", "16384", "--out", (dir / "out").string()});
        CHECK(r.code == 2);
        CHECK_MESSAGE(contains(r.err, "--size: bake.size: the bake of mud would need about"), r.err); // the flag named
        CHECK(contains(r.err, "more than its budget of 4.0 GiB, set by --max-memory"));
        CHECK(contains(r.err, "nothing was started"));
        CHECK(!fs::exists(dir / "out"));
        // The element count dominates a simulation.
        r = run_cli({"--max-memory", "100M", "simulate", "mud", "--set", "simulation.elements=32000", "--json",
                     (dir / "r.json").string()});
        CHECK(r.code == 2);
        CHECK_MESSAGE(contains(r.err, "simulation.elements: the simulation of mud would need about"), r.err);
        CHECK(!fs::exists(dir / "r.json"));
        // The estimate grows with what costs memory: layers of a mass-spring lattice, pixels.
        io::PresetRequest req{"mud", {"simulation.method=\"mass-spring\"", "simulation.elements=32000"}};
        auto estimate = [](const io::Preset& p, bool bake) { return app::make_run_plan(p, {.bake = bake}).estimate; };
        const double one = estimate(io::load_preset(req), false).bytes;
        req.overrides.push_back("simulation.layers=4");
        CHECK(estimate(io::load_preset(req), false).bytes > 5 * one);
        const io::Preset mud = io::load_preset({"mud", {}});
        CHECK(estimate(mud, true).bytes > estimate(mud, false).bytes);
        // An unreadable size is a usage error.
        r = run_cli({"--max-memory", "lots", "simulate", "mud"});
        CHECK(r.code == 2);
        CHECK(contains(r.err, "--max-memory"));
    }

    TEST_CASE("budget: a simulation past --max-time stops with exit 2 and writes nothing, and a budget never "
              "changes what a finished run writes") {
        const fs::path dir = test::scratch_dir("budget-time");
        const std::vector<std::string> outputs{"--png", (dir / "p.png").string(), "--json", (dir / "r.json").string()};
        std::vector<std::string> args{
            "--max-time", "1", "simulate", "mud", "--no-cache", "--set", "simulation.elements=20000"};
        args.insert(args.end(), outputs.begin(), outputs.end());
        // In a process of its own: on a slow (sanitizer) build the run may be inside a step that
        // does not check, and then the hard stop ends its process.
        const auto t0 = std::chrono::steady_clock::now();
        const auto r = test::run_crackle(args);
        const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        CHECK(r.code == 2);
        CHECK_MESSAGE(contains(r.err, "--max-time: the simulation of mud passed its time budget of 1 s"), r.err);
        CHECK(contains(r.err, "may take about")); // warned up front: the estimate is far over 1 s
        CHECK(seconds < 30);                      // 1 s, the 2 s grace at most, and a slow start
        CHECK(fs::is_empty(dir));

        // The same small run with and without a budget: the same bytes.
        auto small = [&](const std::vector<std::string>& budget, const std::string& name) {
            std::vector<std::string> a = budget;
            a.insert(a.end(), {"-q", "simulate", "mud", "--no-cache", "--set", "simulation.elements=600", "--png",
                               (dir / (name + ".png")).string()});
            const auto run = run_cli(a);
            REQUIRE_MESSAGE(run.code == 0, run.err);
            return test::slurp(dir / (name + ".png"));
        };
        CHECK(small({}, "free") == small({"--max-time", "600", "--max-memory", "20G"}, "bounded"));
    }

    TEST_CASE("budget: in a batch each variant has the budget, and one over it fails alone") {
        if (!test::gl_context_or_skip()) return;
        const fs::path dir = test::scratch_dir("budget-batch");
        // A small variant, then one a hundred times its work. The budget is three times what the
        // small one takes alone on this build (a sanitizer build is about ten times slower).
        const std::string small_set = "{\"simulation.elements\": 300, \"bake.size\": 32}";
        const fs::path manifest = test::write_text(
            dir / "m.jsonl", "{\"preset\": \"mud\", \"seed\": 1, \"set\": " + small_set
                                 + "}\n"
                                   "{\"preset\": \"mud\", \"seed\": 2, \"set\": {\"simulation.elements\": 60000}}\n");
        const auto t0 = std::chrono::steady_clock::now();
        const auto alone =
            test::run_crackle({"-q", "bake", "mud", "--seed", "1", "--no-cache", "--set", "simulation.elements=300",
                               "--size", "32", "--out", (dir / "alone").string()});
        REQUIRE_MESSAGE(alone.code == 0, alone.err);
        const double budget =
            std::ceil(3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() + 5);
        char limit[32];
        std::snprintf(limit, sizeof limit, "%.0f", budget);
        const auto r = test::run_crackle(
            {"-q", "--max-time", limit, "batch", manifest.string(), "--out", (dir / "out").string(), "--no-cache"});
        CHECK(r.code == 2);
        CHECK_MESSAGE(contains(r.err, "the bake of mud_2 passed its time budget of"), r.err);
        CHECK(fs::exists(dir / "out" / "mud_1_Color.png"));
        CHECK(!fs::exists(dir / "out" / "mud_2_Color.png"));
        // Stopped at a check, the variant is listed as failed with its reason (a hard stop, on a
        // slow build, ends the shard before the summary is updated; the rerun resumes).
        if (!contains(r.err, "ended at once"))
            CHECK(contains(test::slurp(dir / "out" / "batch-summary-1-of-1.json"), "time budget"));
    }
}
