#include "app/bench/bench_speedup.hpp"

#include "app/bench/study_metrics.hpp"
#include "app/bench/study_runner.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/json.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <unistd.h>

namespace crackle::app {

namespace {

/// One way of running a preset: which executable, which overrides.
struct Variant {
    std::string label;
    bool baseline = false;
    std::vector<std::string> overrides;
};

struct Result {
    std::vector<StatMap> runs;
    std::vector<double> wall, memory;
};

std::string f(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

double median(std::vector<double> v) {
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/// Mean and sample standard deviation of a statistic (of its logarithm when the scale says so).
std::pair<double, double> mean_spread(const std::vector<StatMap>& runs, const StatScale& s) {
    std::vector<double> x;
    for (const StatMap& r : runs)
        if (auto it = r.find(s.key); it != r.end() && std::isfinite(it->second))
            x.push_back(s.logarithmic ? std::log(it->second) : it->second);
    if (x.empty()) return {NAN, NAN};
    double m = 0, v = 0;
    for (double a : x)
        m += a;
    m /= static_cast<double>(x.size());
    for (double a : x)
        v += (a - m) * (a - m);
    return {m, x.size() > 1 ? std::sqrt(v / static_cast<double>(x.size() - 1)) : 0.0};
}

/// The largest |shift| of a statistic's mean from the starting point's, in units of the
/// starting point's seed spread: 0 where both agree exactly, infinite where the start's seeds agree
/// and the means do not.
double largest_shift(const std::vector<StatMap>& runs, const std::vector<StatMap>& start,
                     const std::vector<StatScale>& scales, std::string* which) {
    double worst = 0;
    for (const StatScale& s : scales) {
        const auto [m, sd] = mean_spread(runs, s);
        const auto [m0, sd0] = mean_spread(start, s);
        if (!std::isfinite(m) || !std::isfinite(m0)) continue;
        const double z = m == m0 ? 0.0 : sd0 > 0 ? std::abs(m - m0) / sd0 : INFINITY;
        if (z > worst) {
            worst = z;
            if (which) *which = s.key;
        }
    }
    return worst;
}

} // namespace

int speedup_command(const SpeedupArgs& args, std::ostream& out) {
    if (args.baseline.empty() || access(args.baseline.c_str(), X_OK) != 0)
        throw InputError("bench speedup", "the baseline '" + args.baseline.string() + "' is not an executable",
                         "build the starting point (scripts/bench-baseline REV prints its path) and pass it with "
                         "--baseline");
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe");
    const int seeds = args.quick ? 1 : std::max(1, args.seeds);
    const std::filesystem::path work = std::filesystem::temp_directory_path()
                                       / ("crackle-speedup-" + std::to_string(static_cast<long long>(getpid())));
    std::filesystem::create_directories(work);
    const Reference reference = embedded_reference();
    Json report = Json::object();
    report["baseline"] = args.baseline.string();
    report["seeds"] = seeds;
    out << "# crackle bench speedup (baseline " << args.baseline.string() << ", " << seeds << " seed"
        << (seeds > 1 ? "s" : "") << ")\n\n";
    for (const std::string preset : {"mud", "bark"}) {
        // The starting point is the baseline with the preset's old 8000 elements.
        const std::string start_elements = args.quick ? "1000" : "8000";
        std::vector<Variant> variants = {
            {"this build, preset as shipped", false, {}},
            {"baseline, preset as shipped", true, {}},
            {"baseline, " + start_elements + " elements (the starting point)",
             true,
             {"simulation.elements=" + start_elements}},
        };
        if (args.quick)
            for (Variant& v : variants)
                if (v.overrides.empty()) v.overrides.push_back("simulation.elements=600");
        std::vector<Result> results(variants.size());
        for (int seed = 1; seed <= seeds; ++seed)
            for (std::size_t i = 0; i < variants.size(); ++i) { // interleaved: drifts in machine speed hit all alike
                StudyRun run;
                run.scene = preset;
                run.preset = preset;
                run.seed = seed;
                run.overrides = variants[i].overrides;
                run.overrides.push_back("simulation.seed=" + std::to_string(seed));
                const RunOutcome o =
                    run_child(variants[i].baseline ? args.baseline : self, run, work, 1800, [](double) {});
                if (o.status != "ok")
                    throw NumericError(preset + " (" + variants[i].label + ", seed " + std::to_string(seed)
                                       + ") ended with " + o.status + ": " + o.message);
                results[i].runs.push_back(read_stats(o));
                results[i].wall.push_back(results[i].runs.back()["wall_seconds"]);
                results[i].memory.push_back(o.peak_memory_mb);
            }
        const std::vector<StatScale> scales = scales_of(compared_statistics(preset));
        const auto ref = reference.find(preset);
        const std::vector<StatMap>& start = results.back().runs;
        const double start_wall = median(results.back().wall);
        out << "## " << preset << "\n\n"
            << "| run | elements | wall, median (min–max) | speed-up over the start | peak MiB | crack length per area "
               "| T share | largest shift (start's spreads) | error: rms z (worst) | within tolerance |\n"
            << "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        Json rows = Json::array();
        for (std::size_t i = 0; i < variants.size(); ++i) {
            const Result& r = results[i];
            std::string which = "-";
            const double shift = largest_shift(r.runs, start, scales, &which);
            const std::vector<StatError> errors =
                ref == reference.end() ? std::vector<StatError>{} : seed_average_errors(r.runs, ref->second, preset);
            const double z = rms_z(errors);
            const int within = within_tolerance(errors);
            const auto [cl, cl_sd] = mean_spread(r.runs, {"crack_length_per_area", false});
            const auto [tj, tj_sd] = mean_spread(r.runs, {"t_junction_fraction", false});
            const double wall = median(r.wall);
            out << "| " << variants[i].label << " | " << f("%.0f", r.runs.front().at("elements_initial")) << " | "
                << f("%.2f s", wall) << " (" << f("%.2f", *std::min_element(r.wall.begin(), r.wall.end())) << "–"
                << f("%.2f", *std::max_element(r.wall.begin(), r.wall.end())) << ") | " << f("%.2f×", start_wall / wall)
                << " | " << f("%.0f", median(r.memory)) << " | " << f("%.1f", cl) << " ± " << f("%.1f", cl_sd) << " | "
                << f("%.3f", tj) << " ± " << f("%.3f", tj_sd) << " | "
                << (i + 1 == variants.size() ? std::string("—") : f("%.2f", shift) + " (" + which + ")") << " | "
                << f("%.2f", z) << " (" << stat_title(worst_statistic(errors)) << ") | "
                << (within == 1   ? "yes"
                    : within == 0 ? "no"
                                  : "–")
                << " |\n";
            Json row = Json::object();
            row["run"] = variants[i].label;
            row["wall_median_s"] = wall;
            row["walls_s"] = Json::array();
            for (double w : r.wall)
                row["walls_s"].push_back(w);
            row["speedup_over_start"] = start_wall / wall;
            row["peak_memory_mb"] = median(r.memory);
            row["crack_length_per_area"] = cl;
            row["t_junction_fraction"] = tj;
            row["largest_shift_in_start_spreads"] = shift;
            row["rms_z_to_reference"] = z;
            row["within_tolerance"] = within;
            rows.push_back(row);
        }
        out << "\n";
        report[preset] = rows;
    }
    std::filesystem::remove_all(work);
    if (!args.out_dir.empty()) write_file_atomically(args.out_dir / "speedup.json", report.dump());
    return 0;
}

} // namespace crackle::app
