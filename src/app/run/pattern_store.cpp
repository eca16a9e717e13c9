#include "app/run/pattern_store.hpp"

#include "app/run/report.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/strings.hpp"
#include "core/timer.hpp"
#include "fracture/statistics.hpp"
#include "io/resolution.hpp"

#include <cstdio>
#include <cstdlib>
#include <fstream>

namespace crackle::app {

namespace fs = std::filesystem;

namespace {

/// Bit-exact text of a value: the key must change when any bit of a number does.
std::string exact_text(const Value& value) {
    char buf[40];
    if (const auto* d = std::get_if<double>(&value)) {
        std::snprintf(buf, sizeof buf, "%a", *d);
        return buf;
    }
    if (const auto* v = std::get_if<std::vector<double>>(&value)) {
        std::string s = "[";
        for (double x : *v) {
            std::snprintf(buf, sizeof buf, "%a,", x);
            s += buf;
        }
        return s + "]";
    }
    if (const auto* i = std::get_if<std::int64_t>(&value)) return std::to_string(*i);
    if (const auto* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
    return "\"" + std::get<std::string>(value) + "\"";
}

bool simulation_relevant(const std::string& key) {
    return key.rfind("post.", 0) != 0 && key.rfind("bake.", 0) != 0;
}

// The run counters a report prints, to and from the pattern file's header.
Json run_json(const SimulationResult& r) {
    const fracture::RunStats& s = r.run;
    Json j = Json::object();
    j["time_steps"] = s.time_steps;
    j["solves"] = s.solves;
    j["stiffness_rebuilds"] = s.stiffness_rebuilds;
    j["solver_iterations"] = s.solver_iterations;
    j["local_solves"] = s.local_solves;
    j["local_nodes"] = s.local_nodes;
    j["local_fallbacks"] = s.local_fallbacks;
    j["global_cleanups"] = s.global_cleanups;
    j["local_cleanups"] = s.local_cleanups;
    j["drift_relaxations"] = s.drift_relaxations;
    j["solve_seconds"] = s.solve_seconds;
    j["stress_seconds"] = s.stress_seconds;
    j["topology_seconds"] = s.topology_seconds;
    j["total_seconds"] = s.total_seconds;
    j["setup_seconds"] = s.setup_seconds;
    return j;
}

double number_of(const Json& j, const char* key) {
    const Json* v = j.find(key);
    return v && v->is_number() ? v->as_number() : 0.0;
}

std::size_t count_of(const Json& j, const char* key) {
    return static_cast<std::size_t>(std::max(0.0, number_of(j, key)));
}

fracture::RunStats run_from_json(const Json& j) {
    fracture::RunStats s;
    s.time_steps = count_of(j, "time_steps");
    s.solves = count_of(j, "solves");
    s.stiffness_rebuilds = count_of(j, "stiffness_rebuilds");
    s.solver_iterations = static_cast<long long>(number_of(j, "solver_iterations"));
    s.local_solves = count_of(j, "local_solves");
    s.local_nodes = count_of(j, "local_nodes");
    s.local_fallbacks = count_of(j, "local_fallbacks");
    s.global_cleanups = count_of(j, "global_cleanups");
    s.local_cleanups = count_of(j, "local_cleanups");
    s.drift_relaxations = count_of(j, "drift_relaxations");
    s.solve_seconds = number_of(j, "solve_seconds");
    s.stress_seconds = number_of(j, "stress_seconds");
    s.topology_seconds = number_of(j, "topology_seconds");
    s.total_seconds = number_of(j, "total_seconds");
    s.setup_seconds = number_of(j, "setup_seconds");
    return s;
}

/// A simulation result rebuilt from a pattern file: the scene from the plan (for the report's
/// surface and seed), the pattern and counters from the file, the statistics recomputed.
SimulationResult result_from_file(const RunPlan& plan, fracture::PatternFile file, std::string source) {
    SimulationResult r;
    r.plan = plan;
    r.scene = make_scene(plan);
    r.pattern = std::move(file.pattern);
    const Json& h = file.header;
    r.elements_initial = count_of(h, "elements_initial");
    r.elements_final = count_of(h, "elements_final");
    r.nodes = count_of(h, "nodes");
    if (const Json* d = h.find("details")) r.details = *d;
    if (const Json* s = h.find("summary")) r.summary = s->as_string();
    if (const Json* run = h.find("run")) r.run = run_from_json(*run);
    r.statistics = fracture::pattern_statistics(r.pattern);
    r.pattern_source = std::move(source);
    return r;
}

fs::path cache_file(const std::string& key) {
    const fs::path dir = cache_dir();
    if (dir.empty()) return {};
    const std::string k = key + "build = " + build_id() + "\n";
    return dir / (hex64(fracture::fnv1a64(k)) + hex64(fracture::fnv1a64(k, 0x9e3779b97f4a7c15ull)) + ".pattern");
}

/// The first simulation-relevant line in which two keys differ ("" when equal).
std::string first_difference(const std::string& a, const std::string& b) {
    std::size_t i = 0, j = 0;
    while (i < a.size() || j < b.size()) {
        const std::size_t ea = std::min(a.find('\n', i), a.size()), eb = std::min(b.find('\n', j), b.size());
        if (a.compare(i, ea - i, b, j, eb - j) != 0) return a.substr(i, ea - i);
        i = ea + 1;
        j = eb + 1;
    }
    return "";
}

} // namespace

fs::path cache_dir() {
    if (const char* env = std::getenv("CRACKLE_CACHE"); env && *env) {
        const std::string v = env;
        if (v == "off" || v == "0" || v == "false" || v == "no") return {};
        return fs::path(v);
    }
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return fs::path(xdg) / "crackle";
    if (const char* home = std::getenv("HOME"); home && *home) return fs::path(home) / ".cache" / "crackle";
    return {};
}

std::string simulation_key(const io::Preset& preset, const RunPlan& plan) {
    std::string key = "pattern_format = " + std::to_string(fracture::PATTERN_FORMAT_VERSION) + "\n";
    for (const auto& [name, entry] : preset.values()) {
        if (!simulation_relevant(name)) continue;
        if (name == "simulation.elements") {
            // "auto" follows the map size: the key holds the count the simulation will use (the plan's).
            key += name + " = " + std::to_string(plan.elements.elements) + "\n";
            continue;
        }
        key += name + " = " + exact_text(entry.value) + "\n";
        const auto* text = std::get_if<std::string>(&entry.value);
        if (text && !text->empty() && name.size() > 6 && name.substr(name.size() - 6) == ".image") {
            // An edited image must invalidate the pattern, so the key holds its bytes' hash.
            const std::string bytes = read_file(preset.path(name), "image");
            key += name + ".bytes = " + hex64(fracture::fnv1a64(bytes)) + "\n";
        }
    }
    return key;
}

const std::string& build_id() {
    static const std::string id = [] {
        std::ifstream exe("/proc/self/exe", std::ios::binary);
        std::string bytes((std::istreambuf_iterator<char>(exe)), std::istreambuf_iterator<char>());
        return std::string(crackle_version()) + "-" + hex64(fracture::fnv1a64(bytes));
    }();
    return id;
}

std::vector<std::uint8_t> pattern_file_bytes(const SimulationResult& r) {
    Json h = Json::object();
    h["crackle_version"] = crackle_version();
    h["build"] = build_id();
    h["preset"] = r.plan.record.preset;
    h["seed"] = static_cast<long long>(r.plan.seed);
    h["simulation_key"] = r.plan.simulation_key;
    h["elements_initial"] = r.elements_initial;
    h["elements_final"] = r.elements_final;
    h["nodes"] = r.nodes;
    h["summary"] = r.summary;
    h["details"] = r.details;
    h["run"] = run_json(r);
    h["preset_toml"] = r.plan.record.toml;
    return fracture::encode_pattern(r.pattern, h);
}

void cache_store(const SimulationResult& result) {
    const fs::path file = cache_file(result.plan.simulation_key);
    if (file.empty()) return;
    try {
        const std::vector<std::uint8_t> bytes = pattern_file_bytes(result);
        write_file_atomically(file, std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
        log::debug("pattern cached in ", file.string());
    } catch (const std::exception& e) {
        log::warn("could not store the pattern in the cache (", e.what(),
                  "); set CRACKLE_CACHE to a writable folder, or CRACKLE_CACHE=off");
    }
}

SimulationResult obtain_simulation(const RunPlan& plan, const PatternOptions& options, StepTimes& times) {
    Timer step;
    if (!options.load_path.empty()) {
        const std::string bytes = read_file(options.load_path, "pattern file");
        fracture::PatternFile file = fracture::decode_pattern(bytes, options.load_path);
        const Json* key = file.header.find("simulation_key");
        const std::string& mine = plan.simulation_key;
        if (key && key->as_string() != mine) {
            const Json* made = file.header.find("preset");
            log::warn("--pattern ", options.load_path, " was simulated from ",
                      made ? made->as_string() : std::string("another preset"), " with other simulation settings than ",
                      plan.record.preset, " (first difference: ", first_difference(mine, key->as_string()),
                      "); the pattern is used as it is");
        }
        SimulationResult r = result_from_file(plan, std::move(file), "file");
        times.emplace_back("pattern_load", step.seconds());
        return r;
    }
    const std::string key = options.use_cache ? plan.simulation_key : std::string();
    const fs::path cached = options.use_cache ? cache_file(key) : fs::path();
    if (!cached.empty() && fs::is_regular_file(cached)) {
        try {
            fracture::PatternFile file = fracture::decode_pattern(read_file(cached, "cached pattern"), cached.string());
            const Json* k = file.header.find("simulation_key");
            const Json* b = file.header.find("build");
            if (k && b && k->as_string() == key && b->as_string() == build_id()) {
                log::info("reusing the cached pattern ", cached.string(), " (only post/bake keys differ)");
                SimulationResult r = result_from_file(plan, std::move(file), "cache");
                times.emplace_back("pattern_load", step.seconds());
                return r;
            }
        } catch (const InputError& e) {
            log::debug("ignoring an unreadable cached pattern: ", e.what());
        }
    }
    SimulationResult r = run_simulation(plan, times);
    r.pattern_source = "simulated";
    if (options.use_cache) cache_store(r);
    return r;
}

} // namespace crackle::app
