#include "app/bench/bench_scale.hpp"

#include "app/bench/study_metrics.hpp"
#include "app/bench/study_runner.hpp"
#include "app/run/run_plan.hpp"
#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "core/json.hpp"
#include "io/preset.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace crackle::app {

namespace {

std::string f(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

/// One point of a series: a mud run at `elements` on a square tile of side `side` (m).
struct Point {
    std::string series; ///< "scale" or "refinement"
    long long elements = 0;
    double side = 0;
};

struct Measured {
    std::vector<StatMap> runs;
    std::vector<double> wall, memory;
};

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n == 0 ? NAN : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double stat(const std::vector<StatMap>& runs, const char* key) {
    double sum = 0;
    int n = 0;
    for (const StatMap& r : runs)
        if (auto it = r.find(key); it != r.end() && std::isfinite(it->second)) {
            sum += it->second;
            ++n;
        }
    return n ? sum / n : NAN;
}

/// Runs every point `seeds` times with each build, interleaved (machine drift hits all alike), as
/// child `crackle simulate` processes: what each measured.
std::vector<std::vector<Measured>> measure(const std::vector<std::pair<std::string, std::filesystem::path>>& builds,
                                           const std::vector<Point>& points, int seeds) {
    const std::filesystem::path work =
        std::filesystem::temp_directory_path() / ("crackle-scale-" + std::to_string(static_cast<long long>(getpid())));
    std::filesystem::create_directories(work);

    std::vector<std::vector<Measured>> measured(builds.size(), std::vector<Measured>(points.size()));
    for (std::size_t p = 0; p < points.size(); ++p)
        for (int seed = 1; seed <= seeds; ++seed)
            for (std::size_t b = 0; b < builds.size(); ++b) { // interleaved: machine drift hits all alike
                StudyRun run;
                run.scene = "mud";
                run.preset = "mud";
                run.seed = seed;
                run.overrides = {"simulation.elements=" + std::to_string(points[p].elements),
                                 "surface.size=[" + f("%.6f", points[p].side) + "," + f("%.6f", points[p].side) + "]",
                                 "simulation.seed=" + std::to_string(seed)};
                const RunOutcome o = run_child(builds[b].second, run, work, 3600, [](double) {});
                if (o.status != "ok")
                    throw NumericError("mud at " + std::to_string(points[p].elements) + " elements (" + builds[b].first
                                       + ", seed " + std::to_string(seed) + ") ended with " + o.status + ": "
                                       + o.message);
                Measured& m = measured[b][p];
                m.runs.push_back(read_stats(o));
                if (const Json* steps = o.report.find("time_steps"); steps && steps->is_number())
                    m.runs.back()["time_steps"] = steps->as_number();
                m.wall.push_back(m.runs.back()["wall_seconds"]);
                m.memory.push_back(o.peak_memory_mb);
            }
    std::filesystem::remove_all(work);
    return measured;
}

} // namespace

double mud_auto_side(long long elements) {
    io::PresetRequest request;
    request.name_or_path = "mud";
    const LayerPlan layer = make_run_plan(io::load_preset(request)).layer;
    const double h = 0.5 * (layer.thickness_min + layer.thickness_max);
    return std::sqrt(static_cast<double>(elements) * h * h / 2.0);
}

double loglog_slope(const std::vector<double>& size, const std::vector<double>& cost) {
    const std::size_t n = std::min(size.size(), cost.size());
    if (n < 2) return NAN;
    double mx = 0, my = 0;
    for (std::size_t i = 0; i < n; ++i) {
        mx += std::log(size[i]);
        my += std::log(cost[i]);
    }
    mx /= static_cast<double>(n);
    my /= static_cast<double>(n);
    double sxy = 0, sxx = 0;
    for (std::size_t i = 0; i < n; ++i) {
        sxy += (std::log(size[i]) - mx) * (std::log(cost[i]) - my);
        sxx += (std::log(size[i]) - mx) * (std::log(size[i]) - mx);
    }
    return sxx > 0 ? sxy / sxx : NAN;
}

int scale_command(const ScaleArgs& args, std::ostream& out) {
    if (!args.baseline.empty() && access(args.baseline.c_str(), X_OK) != 0)
        throw InputError("bench scale", "the baseline '" + args.baseline.string() + "' is not an executable",
                         "build it (scripts/bench-baseline REV prints its path) and pass it with --baseline");
    std::string python;
    if (args.charts) {
        python = find_python_with_matplotlib();
        if (python.empty())
            throw InputError(
                "bench scale", "the chart needs python3 with matplotlib, and none was found",
                "run scripts/setup (installs python3-matplotlib), set CRACKLE_PYTHON, or pass --no-charts");
    }
    const std::filesystem::path out_dir = args.out_dir.empty() ? std::filesystem::path("bench") : args.out_dir;
    std::filesystem::create_directories(out_dir);

    io::PresetRequest request;
    request.name_or_path = "mud";
    const double tile = make_run_plan(io::load_preset(request)).surface.size.x();
    std::vector<Point> points;
    const std::vector<long long> scale_sizes =
        args.quick ? std::vector<long long>{300, 600} : std::vector<long long>{2500, 5000, 10000, 20000};
    for (long long n : scale_sizes)
        points.push_back({"scale", n, mud_auto_side(n)});
    const std::vector<long long> refine_sizes =
        args.quick ? std::vector<long long>{300, 600} : std::vector<long long>{1250, 2500, 5000, 10000};
    for (long long n : refine_sizes)
        points.push_back({"refinement", n, tile});

    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe");
    std::vector<std::pair<std::string, std::filesystem::path>> builds{{"this build", self}};
    if (!args.baseline.empty()) builds.emplace_back("baseline", args.baseline);
    const Reference reference = embedded_reference();
    const int seeds = std::max(1, args.seeds);
    const std::vector<std::vector<Measured>> measured = measure(builds, points, seeds);

    std::string csv = "build,series,elements,tile_m,wall_s,peak_memory_mib,fracture_events,time_steps,"
                      "t_junction_fraction,crack_length_per_area,rms_z,within_tolerance\n";
    Json report = Json::object();
    out << "# crackle bench scale (mud, " << seeds << " seed" << (seeds > 1 ? "s" : "") << " per point)\n";
    const auto ref = reference.find("mud");
    for (const char* series : {"scale", "refinement"}) {
        const bool scale = std::string(series) == "scale";
        out << "\n## " << (scale ? "Scale: growing tiles at 2 elements per h²" : "Refinement: the preset's tile, finer")
            << "\n\n| build | elements | tile | wall (median) | peak MiB | events | time steps | T share | crack "
               "length per area | error: rms z (worst) | within tolerance "
               "|\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
        Json series_json = Json::object();
        for (std::size_t b = 0; b < builds.size(); ++b) {
            std::vector<double> sizes, walls, memories;
            for (std::size_t p = 0; p < points.size(); ++p) {
                if (points[p].series != series) continue;
                const Measured& m = measured[b][p];
                const double wall = median(m.wall), memory = median(m.memory);
                const std::vector<StatError> errors =
                    ref == reference.end() ? std::vector<StatError>{} : seed_average_errors(m.runs, ref->second, "mud");
                const double z = rms_z(errors);
                const int within = within_tolerance(errors);
                sizes.push_back(static_cast<double>(points[p].elements));
                walls.push_back(wall);
                memories.push_back(memory);
                out << "| " << builds[b].first << " | " << points[p].elements << " | " << f("%.3f m", points[p].side)
                    << " | " << f("%.2f s", wall) << " | " << f("%.0f", memory) << " | "
                    << f("%.0f", stat(m.runs, "events")) << " | " << f("%.0f", stat(m.runs, "time_steps")) << " | "
                    << f("%.3f", stat(m.runs, "t_junction_fraction")) << " | "
                    << f("%.1f", stat(m.runs, "crack_length_per_area")) << " | " << f("%.2f", z) << " ("
                    << stat_title(worst_statistic(errors)) << ") | "
                    << (within == 1   ? "yes"
                        : within == 0 ? "no"
                                      : "–")
                    << " |\n";
                csv += builds[b].first + "," + series + "," + std::to_string(points[p].elements) + ","
                       + f("%.6f", points[p].side) + "," + f("%.4f", wall) + "," + f("%.1f", memory) + ","
                       + f("%.0f", stat(m.runs, "events")) + "," + f("%.0f", stat(m.runs, "time_steps")) + ","
                       + f("%.4f", stat(m.runs, "t_junction_fraction")) + ","
                       + f("%.3f", stat(m.runs, "crack_length_per_area")) + "," + f("%.4f", z) + ","
                       + std::to_string(within) + "\n";
            }
            Json row = Json::object();
            row["time_slope"] = loglog_slope(sizes, walls);
            row["memory_slope"] = loglog_slope(sizes, memories);
            series_json[builds[b].first] = row;
        }
        out << "\n";
        for (std::size_t b = 0; b < builds.size(); ++b)
            out << builds[b].first << ": time grows like elements^"
                << f("%.2f", series_json[builds[b].first]["time_slope"].as_number()) << ", peak memory like elements^"
                << f("%.2f", series_json[builds[b].first]["memory_slope"].as_number()) << " (log-log fit)\n";
        report[series] = series_json;
    }
    write_file_atomically(out_dir / "scale.csv", csv);
    write_file_atomically(out_dir / "scale.json", report.dump());
    if (!python.empty()) {
        run_chart_script(python, "scale_charts", {(out_dir / "scale.csv").string(), out_dir.string()},
                         out_dir / "scale_charts.log");
        out << "\nchart: " << (out_dir / "scale.png").string() << "\n";
    }
    return 0;
}

} // namespace crackle::app
