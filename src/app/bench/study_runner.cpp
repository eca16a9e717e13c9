#include "app/bench/study_runner.hpp"

#include "core/embedded.hpp"
#include "core/error.hpp"
#include "core/timer.hpp"
#include "fracture/bar1d.hpp"

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <spawn.h>
#include <sstream>
#include <sys/resource.h>
#include <sys/wait.h>
#include <thread>

extern char** environ;

namespace crackle::app {

namespace {

std::string read_text(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Spawns argv with stdout to /dev/null (or `out`) and stderr to `err`; returns the pid.
pid_t spawn(const std::vector<std::string>& argv, const std::filesystem::path& out, const std::filesystem::path& err) {
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, 1, out.empty() ? "/dev/null" : out.c_str(), O_WRONLY | O_CREAT | O_TRUNC,
                                     0644);
    posix_spawn_file_actions_addopen(&actions, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    std::vector<char*> args;
    for (const std::string& a : argv)
        args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    pid_t pid = 0;
    const int rc = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) throw InputError(argv[0], "cannot start: " + std::string(std::strerror(rc)), "check the path");
    return pid;
}

/// Waits for pid, killing it after time_limit seconds (≤ 0: no limit). Returns the wait
/// status (−1 after a kill) and the child's peak RSS in MiB.
int wait_child(pid_t pid, double time_limit, const std::function<void(double)>& tick, double& peak_mb) {
    Timer t;
    bool killed = false;
    while (true) {
        int status = 0;
        rusage usage{};
        const pid_t r = wait4(pid, &status, WNOHANG, &usage);
        if (r == pid) {
            peak_mb = double(usage.ru_maxrss) / 1024.0;
            return killed ? -1 : status;
        }
        if (r < 0) return -2;
        if (!killed && time_limit > 0 && t.seconds() > time_limit) {
            ::kill(pid, SIGKILL);
            killed = true;
        }
        if (tick) tick(t.seconds());
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
}

std::string describe(int status) {
    if (status == -1) return "timeout";
    if (status == -2) return "lost";
    if (WIFEXITED(status)) return WEXITSTATUS(status) == 0 ? "ok" : "exit " + std::to_string(WEXITSTATUS(status));
    if (WIFSIGNALED(status)) return "signal " + std::to_string(WTERMSIG(status));
    return "unknown";
}

} // namespace

RunOutcome run_child(const std::filesystem::path& binary, const StudyRun& run, const std::filesystem::path& work_dir,
                     double time_limit, const std::function<void(double)>& tick) {
    const std::filesystem::path json = work_dir / "run.json", events = work_dir / "run.csv", err = work_dir / "run.err";
    for (const auto& p : {json, events})
        std::filesystem::remove(p);
    // The study measures simulations: never fill the user's pattern cache with hundreds of them.
    std::vector<std::string> argv = {binary.string(), "-q", "simulate", run.preset, "--no-cache"};
    for (const std::string& o : run.overrides) {
        argv.push_back("--set");
        argv.push_back(o);
    }
    for (const std::string& a : {std::string("--json"), json.string(), std::string("--events"), events.string()})
        argv.push_back(a);
    RunOutcome out;
    Timer t;
    const pid_t pid = spawn(argv, {}, err);
    out.status = describe(wait_child(pid, time_limit, tick, out.peak_memory_mb));
    out.wall = t.seconds();
    std::istringstream lines(read_text(err));
    std::getline(lines, out.message);
    if (out.status == "ok") {
        out.report = Json::parse(read_text(json), json.string());
        out.events_csv = read_text(events);
    }
    return out;
}

RunOutcome run_bar(const StudyRun& run) {
    namespace bar = fracture::bar1d;
    bar::SimulationOptions o; // K_S = 1, K_A = 50, l₀ = 1, T_b = 0.01
    o.segments = static_cast<int>(run.elements);
    o.growth_rate = 1.0;
    const double exact = bar::break_time_free(o.stiffness, o.length, o.growth_rate, o.break_tension);
    o.duration = 2.0 * exact;
    o.max_events = 1;
    RunOutcome out;
    Timer t;
    const bar::SimulationResult r = bar::simulate(o);
    // The tension field before the first break, against Eq. A.6's closed form.
    bar::SimulationOptions before = o;
    before.duration = 0.9 * exact;
    const bar::SimulationResult b = bar::simulate(before);
    out.wall = t.seconds();
    double worst = 0, peak = 0;
    for (std::size_t j = 0; j < b.bar.num_springs(); ++j) {
        const double x = b.bar.midpoint(j);
        const double exact_t = bar::tension_free(o.stiffness, o.length, o.length * o.growth_rate * before.duration, x);
        worst = std::max(worst, std::abs(b.tensions[static_cast<Eigen::Index>(j)] - exact_t));
        peak = std::max(peak, std::abs(exact_t));
    }
    out.report = Json::object();
    out.report["first_event_time"] = r.events.empty() ? -1.0 : r.events.front().time;
    out.report["closed_form_time"] = exact;
    out.report["tension_error"] = peak > 0 ? worst / peak : 0.0;
    out.report["elements_initial"] = run.elements;
    out.report["fracture_events"] = r.events.size();
    out.peak_memory_mb = peak_memory_mb();
    return out;
}

std::string find_python_with_matplotlib() {
    std::vector<std::string> candidates;
    if (const char* env = std::getenv("CRACKLE_PYTHON"); env && *env) candidates.emplace_back(env);
    candidates.emplace_back("python3");
    candidates.emplace_back("/usr/bin/python3");
    for (const std::string& py : candidates) {
        const std::string cmd = "'" + py + "' -c 'import matplotlib' >/dev/null 2>&1";
        if (py.find('\'') == std::string::npos && std::system(cmd.c_str()) == 0) return py;
    }
    return "";
}

void run_chart_script(const std::string& python, const std::string& name, const std::vector<std::string>& args,
                      const std::filesystem::path& log) {
    std::string script;
    for (const EmbeddedFile& f : embedded::scripts())
        if (f.name == name) script = std::string(f.text);
    CRACKLE_ASSERT(!script.empty(), "every chart script is embedded");
    std::vector<std::string> argv = {python, "-c", script};
    for (const auto& a : args)
        argv.push_back(a);
    double ignored = 0;
    const int status = wait_child(spawn(argv, log, log.string() + ".err"), 0, {}, ignored);
    const int rc = WIFEXITED(status) ? WEXITSTATUS(status) : 128;
    if (rc != 0)
        throw NumericError("drawing the charts failed (exit " + std::to_string(rc) + "); see " + log.string() + ".err");
}

StatMap read_stats(const RunOutcome& o) {
    StatMap s;
    auto take = [&](const char* from, const char* to) {
        if (const Json* v = o.report.find(from); v && v->is_number()) s[to] = v->as_number();
    };
    for (const char* k : {"elements_initial", "fragments", "crack_length_per_area", "mean_fragment_area",
                          "fragment_area_cv", "t_junction_fraction", "y_junction_fraction", "anisotropy", "tortuosity",
                          "first_event_time", "tension_error"})
        take(k, k);
    take("fracture_events", "events");
    s["peak_memory_mb"] = o.peak_memory_mb;
    s["wall_seconds"] = o.wall;
    if (const Json* w = o.report.find("wall_seconds")) {
        auto wall = [&](const char* key, const char* to) {
            if (const Json* v = w->find(key)) s[to] = v->as_number();
        };
        wall("total", "wall_seconds");
        wall("fracture", "fracture_seconds");
        wall("fracture.solve", "solve_seconds");
        wall("fracture.stress", "stress_seconds");
        wall("fracture.topology", "topology_seconds");
    }
    if (!o.events_csv.empty()) s["arrest_height"] = arrest_height(o.events_csv);
    return s;
}

} // namespace crackle::app
