#include "app/study.hpp"

#include "app/study_metrics.hpp"
#include "app/study_plan.hpp"
#include "app/study_runner.hpp"
#include "core/atomic_file.hpp"
#include "core/embedded.hpp"
#include "core/error.hpp"
#include "core/log.hpp"
#include "core/math.hpp"
#include "core/progress.hpp"
#include "core/strings.hpp"
#include "io/preset.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <set>

namespace crackle::app {

namespace {

/// One finished run: what the CSV row holds.
struct Record {
    StudyRun run;
    RunOutcome outcome;
    StatMap stats; ///< statistics and timings read from the report
    double error = NAN;
};

/// The CSV columns after scene, method, elements, seed and status, read from the report.
const std::vector<std::string>& stat_columns() {
    static const std::vector<std::string> columns = {
        "elements_initial",    "wall_seconds",          "fracture_seconds",   "solve_seconds",
        "stress_seconds",      "topology_seconds",      "peak_memory_mb",     "events",
        "fragments",           "crack_length_per_area", "mean_fragment_area", "fragment_area_cv",
        "t_junction_fraction", "y_junction_fraction",   "anisotropy",         "tortuosity",
        "first_event_time",    "arrest_height",         "tension_error"};
    return columns;
}

std::string num(double v) {
    if (!std::isfinite(v)) return "";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

bool is_film(const std::string& scene) {
    return scene.rfind("film", 0) == 0;
}

/// A film scene's closed-form first-crack time, from its preset's numbers: the flat film's,
/// divided on curved surfaces by the thick-shell factor at the bottom of the layer (where the
/// in-plane stress is largest).
double film_time(const std::string& scene) {
    io::PresetRequest r;
    r.name_or_path = scene_preset(scene);
    r.overrides = scene_overrides(scene);
    const io::Preset p = io::load_preset(r);
    const double nu = p.number("material.poisson_ratio");
    const double flat =
        film_first_crack_time(p.number("material.young_modulus"), nu, p.number("material.threshold_stress"),
                              p.numbers("material.shrinkage").at(0));
    if (scene == "film") return flat;
    const bool sphere = scene == "film-sphere";
    const double size = p.numbers("surface.size").at(0);
    const double R = sphere ? size : size / (2 * PI);
    return flat / curved_film_stress_factor(sphere, R, p.numbers("material.thickness").at(0), nu, R);
}

double stat(const StatMap& s, const char* key) {
    const auto it = s.find(key);
    return it == s.end() ? NAN : it->second;
}

/// The error of one run (docs/benchmarks.md, "Error metrics"); NaN when it has none.
double run_error(const Record& r, const Reference& reference) {
    if (r.outcome.status != "ok") return NAN;
    const double first = stat(r.stats, "first_event_time");
    if (r.run.scene == "bar") return std::abs(first / r.outcome.report.find("closed_form_time")->as_number() - 1.0);
    if (is_film(r.run.scene)) return first > 0 ? std::abs(first / film_time(r.run.scene) - 1.0) : NAN;
    const auto ref = reference.find(r.run.scene);
    if (ref == reference.end()) return NAN;
    if (r.run.scene == "arrest") {
        const double h = stat(r.stats, "arrest_height");
        const auto it = ref->second.stats.find("arrest_height");
        return h >= 0 && it != ref->second.stats.end() ? std::abs(h - it->second.mean) : NAN;
    }
    return pattern_distance(r.stats, ref->second, pattern_scales(r.run.scene));
}

std::string csv_header() {
    std::string h = "scene,method,elements,seed,status";
    for (const auto& c : stat_columns())
        h += "," + c;
    return h + ",error\n";
}

std::string csv_row(const Record& r) {
    std::string row = r.run.scene + "," + r.run.method + "," + std::to_string(r.run.elements) + ","
                      + std::to_string(r.run.seed) + "," + r.outcome.status;
    for (const auto& c : stat_columns())
        row += "," + num(stat(r.stats, c.c_str()));
    return row + "," + num(r.error) + "\n";
}

/// A method × resolution of a scene, seed-averaged.
struct Point {
    std::string scene, method;
    long long elements = 0;
    int runs = 0, ok = 0;
    StatMap mean; ///< means of the stat columns over the finished runs
    double error = NAN;
    bool pareto = false;
};

std::vector<Point> aggregate(const std::vector<Record>& records, const Reference& reference) {
    std::map<std::tuple<std::string, std::string, long long>, std::vector<const Record*>> groups;
    std::vector<std::tuple<std::string, std::string, long long>> order;
    for (const Record& r : records) {
        const auto key = std::make_tuple(r.run.scene, r.run.method, r.run.elements);
        if (!groups.count(key)) order.push_back(key);
        groups[key].push_back(&r);
    }
    std::vector<Point> points;
    for (const auto& key : order) {
        Point p;
        std::tie(p.scene, p.method, p.elements) = key;
        std::vector<StatMap> ok;
        double error_sum = 0;
        int errors = 0;
        for (const Record* r : groups[key]) {
            ++p.runs;
            if (r->outcome.status != "ok") continue;
            ok.push_back(r->stats);
            if (std::isfinite(r->error)) {
                error_sum += r->error;
                ++errors;
            }
        }
        p.ok = int(ok.size());
        for (const auto& c : stat_columns()) {
            double sum = 0;
            int n = 0;
            for (const StatMap& s : ok)
                if (const double v = stat(s, c.c_str()); std::isfinite(v)) {
                    sum += v;
                    ++n;
                }
            if (n > 0) p.mean[c] = sum / n;
        }
        const auto ref = reference.find(p.scene);
        if (ok.empty()) {
            p.error = NAN;
        } else if ((p.scene == "mud" || p.scene == "bark") && ref != reference.end()) {
            p.error =
                pattern_distance(average_stats(ok, pattern_scales(p.scene)), ref->second, pattern_scales(p.scene));
        } else if (p.scene == "arrest" && ref != reference.end() && ref->second.stats.count("arrest_height")) {
            const double h = stat(p.mean, "arrest_height");
            p.error = std::isfinite(h) ? std::abs(h - ref->second.stats.at("arrest_height").mean) : NAN;
        } else {
            p.error = errors > 0 ? error_sum / errors : NAN;
        }
        points.push_back(p);
    }
    // The Pareto front of each scene: no other point is both faster and more accurate.
    for (Point& p : points) {
        if (!std::isfinite(p.error)) continue;
        p.pareto = std::none_of(points.begin(), points.end(), [&](const Point& q) {
            return &q != &p && q.scene == p.scene && std::isfinite(q.error)
                   && stat(q.mean, "wall_seconds") <= stat(p.mean, "wall_seconds") && q.error <= p.error
                   && (stat(q.mean, "wall_seconds") < stat(p.mean, "wall_seconds") || q.error < p.error);
        });
    }
    return points;
}

/// Least-squares slope of log(wall) against log(elements) per scene × method.
std::map<std::pair<std::string, std::string>, double> cost_slopes(const std::vector<Point>& points) {
    std::map<std::pair<std::string, std::string>, std::vector<std::pair<double, double>>> xy;
    for (const Point& p : points) {
        const double n = double(p.elements), t = stat(p.mean, "wall_seconds");
        if (n > 0 && t > 0) xy[{p.scene, p.method}].emplace_back(std::log(n), std::log(t));
    }
    std::map<std::pair<std::string, std::string>, double> slopes;
    for (const auto& [key, v] : xy) {
        if (v.size() < 2) continue;
        double mx = 0, my = 0;
        for (const auto& [x, y] : v) {
            mx += x;
            my += y;
        }
        mx /= double(v.size());
        my /= double(v.size());
        double sxy = 0, sxx = 0;
        for (const auto& [x, y] : v) {
            sxy += (x - mx) * (y - my);
            sxx += (x - mx) * (x - mx);
        }
        if (sxx > 0) slopes[key] = sxy / sxx;
    }
    return slopes;
}

std::string points_csv(const std::vector<Point>& points) {
    std::string csv = "scene,method,elements,runs,ok";
    for (const auto& c : stat_columns())
        csv += "," + c;
    csv += ",error,pareto\n";
    for (const Point& p : points) {
        csv += p.scene + "," + p.method + "," + std::to_string(p.elements) + "," + std::to_string(p.runs) + ","
               + std::to_string(p.ok);
        for (const auto& c : stat_columns())
            csv += "," + num(stat(p.mean, c.c_str()));
        csv += "," + num(p.error) + "," + (p.pareto ? "1" : "0") + "\n";
    }
    return csv;
}

std::string summary_markdown(const std::vector<Point>& points) {
    std::string md;
    const auto slopes = cost_slopes(points);
    std::string scene;
    char buf[256];
    for (const Point& p : points) {
        if (p.scene != scene) {
            scene = p.scene;
            md += "\n#### " + scene
                  + "\n\n| method | elements | runs ok | wall | peak memory | events | error | Pareto |\n"
                    "|---|---:|---:|---:|---:|---:|---:|:-:|\n";
        }
        std::snprintf(buf, sizeof buf, "| %s | %lld | %d/%d | %.2f s | %.0f MiB | %.0f | %s | %s |\n", p.method.c_str(),
                      p.elements, p.ok, p.runs, stat(p.mean, "wall_seconds"), stat(p.mean, "peak_memory_mb"),
                      stat(p.mean, "events"), std::isfinite(p.error) ? num(p.error).c_str() : "–", p.pareto ? "●" : "");
        md += buf;
    }
    md +=
        "\n#### Cost against element count: fitted slope of log(wall) on log(elements)\n\n| scene | method | slope |\n"
        "|---|---|---:|\n";
    for (const auto& [key, slope] : slopes) {
        std::snprintf(buf, sizeof buf, "| %s | %s | %.2f |\n", key.first.c_str(), key.second.c_str(), slope);
        md += buf;
    }
    return md;
}

void check_names(const std::vector<std::string>& given, const std::vector<std::string>& known, const char* what) {
    for (const auto& s : given)
        if (std::find(known.begin(), known.end(), s) == known.end()) {
            std::string list;
            for (const auto& k : known)
                list += (list.empty() ? "" : ", ") + k;
            throw InputError("bench", std::string("unknown ") + what + " '" + s + "'" + did_you_mean(s, known),
                             std::string(what) + "s are: " + list);
        }
}

/// Runs `runs` with a progress bar, calling `done` after each.
std::vector<Record> execute(const std::vector<StudyRun>& runs, const StudyArgs& args,
                            const std::filesystem::path& binary, const std::filesystem::path& work,
                            const std::function<void(std::vector<Record>&)>& done) {
    const double limit = args.time_limit > 0 ? args.time_limit : args.quick ? 60.0 : 600.0;
    // Progress in units of expected cost (elements, heavier for the slow variants).
    auto weight = [](const StudyRun& r) {
        const double w = r.scene == "bar" ? 1.0 : double(r.elements);
        return w * (r.method == "fem-split-tip" || r.method.rfind("mass-spring", 0) == 0 ? 3.0 : 1.0);
    };
    double total = 0, finished = 0, seconds_per_unit = 1e-3;
    for (const auto& r : runs)
        total += weight(r);
    Progress progress("study", total);
    std::vector<Record> records;
    double spent = 0;
    for (const StudyRun& run : runs) {
        const double w = weight(run);
        Record rec;
        rec.run = run;
        if (run.scene == "bar") {
            rec.outcome = run_bar(run);
        } else {
            rec.outcome = run_child(binary, run, work, limit, [&](double elapsed) {
                progress.update(finished + std::min(elapsed / seconds_per_unit, 0.95 * w));
            });
        }
        rec.stats = read_stats(rec.outcome);
        if (run.scene != "arrest") rec.stats.erase("arrest_height");
        finished += w;
        spent += rec.outcome.wall;
        seconds_per_unit = std::max(spent / finished, 1e-9);
        progress.update(finished);
        records.push_back(std::move(rec));
        done(records);
    }
    progress.finish();
    return records;
}

} // namespace

const std::vector<std::string>& study_methods() {
    static const std::vector<std::string> methods = {"mass-spring-regular", "mass-spring-random", "fem-remove",
                                                     "fem-split",           "fem-split-tip",      "graph-fem"};
    return methods;
}

const std::vector<std::string>& study_scenes() {
    static const std::vector<std::string> scenes = {"bar",    "film", "film-cylinder", "film-sphere",
                                                    "arrest", "mud",  "bark"};
    return scenes;
}

int study_command(const StudyArgs& args, std::ostream& out) {
    // === Everything checked before the first run.
    check_names(args.methods, study_methods(), "method");
    check_names(args.scenes, study_scenes(), "scene");
    if (args.seeds < 0 || args.seeds > 50)
        throw InputError("bench", "--seeds " + std::to_string(args.seeds) + " is out of range", "use 1 to 50");
    if (args.time_limit < 0) throw InputError("bench", "--time-limit must not be negative", "use seconds, 0 = default");
    const std::vector<std::string> methods = args.methods.empty() ? study_methods() : args.methods;
    const std::vector<std::string> scenes = args.scenes.empty() ? study_scenes() : args.scenes;
    const int seeds = args.seeds > 0 ? args.seeds : args.quick ? 1 : 3;
    const std::filesystem::path out_dir = args.out_dir.empty() ? std::filesystem::path("bench") : args.out_dir;
    const std::filesystem::path binary =
        args.binary.empty() ? std::filesystem::read_symlink("/proc/self/exe") : args.binary;
    std::string python;
    if (args.charts && !args.make_reference) {
        python = find_python_with_matplotlib();
        if (python.empty())
            throw InputError(
                "bench", "the charts need python3 with matplotlib, and none was found",
                "run scripts/setup (installs python3-matplotlib), set CRACKLE_PYTHON, or pass --no-charts");
    }
    Reference reference;
    if (!args.reference.empty())
        reference = reference_from_json(Json::parse(read_file(args.reference, "reference"), args.reference.string()),
                                        args.reference.string());
    else
        reference = embedded_reference();
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    if (ec || !std::filesystem::is_directory(out_dir))
        throw InputError(out_dir.string(), "cannot create the output folder", "pass --out with a writable folder");
    const std::filesystem::path work = out_dir / ".work";
    std::filesystem::create_directories(work, ec);
    write_file_atomically(out_dir / ".write-check", "");
    std::filesystem::remove(out_dir / ".write-check");

    if (args.make_reference) {
        Reference made;
        for (const std::string& scene : scenes) {
            if (!scene_has_reference(scene)) continue;
            const std::vector<StudyRun> runs = reference_runs(scene);
            const std::vector<Record> records = execute(runs, args, binary, work, [](std::vector<Record>&) {});
            std::vector<StatMap> stats;
            std::vector<long long> used;
            for (const Record& r : records)
                if (r.outcome.status == "ok") {
                    stats.push_back(r.stats);
                    used.push_back(r.run.seed);
                } else {
                    throw NumericError("reference run " + scene + " seed " + std::to_string(r.run.seed) + ": "
                                       + r.outcome.status + " " + r.outcome.message);
                }
            std::string command = "crackle simulate " + runs.front().preset;
            for (const auto& o : runs.front().overrides)
                if (o.rfind("simulation.seed=", 0) != 0) command += " --set " + o;
            command += " --set simulation.seed=S";
            made[scene] = make_scene_reference(command, runs.front().elements, used, stats, reference_scales());
            out << scene << ": " << stats.size() << " reference runs\n";
        }
        write_file_atomically(out_dir / "reference.json", reference_to_json(made).dump());
        out << "wrote " << (out_dir / "reference.json").string()
            << " (copy it to docs/benchmarks/reference.json and rebuild to make it the study's)\n";
        std::filesystem::remove_all(work, ec);
        return 0;
    }

    for (const std::string& scene : scenes)
        if (scene_has_reference(scene) && !reference.count(scene))
            log::warn("no reference for scene '" + scene + "': its errors stay empty (crackle bench --make-reference)");
    const std::vector<StudyRun> runs = study_plan(scenes, methods, seeds, args.quick);
    std::vector<Record> records = execute(runs, args, binary, work, [&](std::vector<Record>& so_far) {
        Record& last = so_far.back();
        last.error = run_error(last, reference);
        std::string csv = csv_header();
        for (const Record& r : so_far)
            csv += csv_row(r);
        write_file_atomically(out_dir / "runs.csv", csv); // readable while the study runs
    });
    std::filesystem::remove_all(work, ec);
    const std::vector<Point> points = aggregate(records, reference);
    write_file_atomically(out_dir / "points.csv", points_csv(points));
    const std::string md = summary_markdown(points);
    write_file_atomically(out_dir / "summary.md", md);
    out << md;
    if (!python.empty()) {
        run_chart_script(python, "bench_charts",
                         {(out_dir / "runs.csv").string(), (out_dir / "points.csv").string(), out_dir.string()},
                         out_dir / "charts.log");
        out << "\ncharts: " << (out_dir / "error_vs_time.png").string() << ", cost_vs_elements.png, time_shares.png\n";
    }
    return 0;
}

} // namespace crackle::app
