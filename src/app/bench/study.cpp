#include "app/bench/study.hpp"

#include "app/bench/study_metrics.hpp"
#include "app/bench/study_plan.hpp"
#include "app/bench/study_runner.hpp"
#include "app/run/run_plan.hpp"
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
    StatMap stats;                 ///< statistics and timings read from the report
    double error = NAN;            ///< the scene's error (docs/benchmarks.md, "Scenes and their error metrics")
    std::vector<StatError> errors; ///< per compared statistic, against the reference
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
    const RunPlan plan = make_run_plan(io::load_preset(r));
    const LayerPlan& layer = plan.layer;
    const double nu = layer.poisson_ratio;
    const double flat =
        film_first_crack_time(layer.young_modulus, nu, layer.threshold_stress, layer.shrinkage.top_rate);
    if (scene == "film") return flat;
    const bool sphere = scene == "film-sphere";
    const double size = plan.surface.size.x();
    const double R = sphere ? size : size / (2 * PI);
    return flat / curved_film_stress_factor(sphere, R, layer.thickness_min, nu, R);
}

double stat(const StatMap& s, const char* key) {
    const auto it = s.find(key);
    return it == s.end() ? NAN : it->second;
}

/// The per-statistic errors of a scene's statistics `x` (a run, or a point's seed mean) against
/// the reference; empty for the closed-form scenes.
std::vector<StatError> scene_stat_errors(const std::string& scene, const StatMap& x, const Reference& reference) {
    const std::vector<std::string> keys = compared_statistics(scene);
    if (keys.empty()) return {};
    const auto ref = reference.find(scene);
    if (ref == reference.end()) {
        std::vector<StatError> none;
        for (const std::string& k : keys) {
            StatError e;
            e.key = k;
            e.why_not = "no reference for the scene";
            none.push_back(e);
        }
        return none;
    }
    return stat_errors(x, ref->second, keys);
}

/// The scene error of a pattern or arrest scene from its statistics: the RMS of z over the
/// comparable statistics (mud, bark), |h − h_ref| in tile heights (arrest).
double reference_error(const std::string& scene, const StatMap& x, const std::vector<StatError>& errors,
                       const Reference& reference) {
    if (scene == "arrest") {
        const auto ref = reference.find(scene);
        const double h = stat(x, "arrest_height");
        if (ref == reference.end() || !ref->second.stats.count("arrest_height") || !(h >= 0)) return NAN;
        return std::abs(h - ref->second.stats.at("arrest_height").mean);
    }
    return rms_z(errors);
}

/// Sets one run's error and per-statistic errors (docs/benchmarks.md, "Scenes and their error
/// metrics"); NaN when it has none.
void evaluate_run(Record& r, const Reference& reference) {
    r.error = NAN;
    r.errors.clear();
    if (r.outcome.status != "ok") return;
    const double first = stat(r.stats, "first_event_time");
    if (r.run.scene == "bar") {
        r.error = std::abs(first / r.outcome.report.find("closed_form_time")->as_number() - 1.0);
    } else if (is_film(r.run.scene)) {
        r.error = first > 0 ? std::abs(first / film_time(r.run.scene) - 1.0) : NAN;
    } else {
        r.errors = scene_stat_errors(r.run.scene, r.stats, reference);
        r.error = reference_error(r.run.scene, r.stats, r.errors, reference);
    }
}

/// The column prefix of a statistic's error: relative (x/μ − 1) or absolute (x − μ).
std::string error_column(const std::string& key) {
    const StatTolerance* t = find_tolerance(key);
    return (t && t->kind == ToleranceKind::Relative ? "rel_err_" : "abs_err_") + key;
}

/// Per statistic of error_statistics(): z_<key> [z_<key>_sd], rel_err_ or abs_err_<key>,
/// within_tol_<key>; then z_rms, within_tolerance, not_comparable.
std::string error_header(bool with_sd) {
    std::string h;
    for (const std::string& k : error_statistics()) {
        h += ",z_" + k;
        if (with_sd) h += ",z_" + k + "_sd";
        h += "," + error_column(k) + ",within_tol_" + k;
    }
    return h + ",z_rms,within_tolerance,not_comparable";
}

std::string error_cells(const std::vector<StatError>& errors, const StatMap* z_sd) {
    std::string row, not_comparable;
    for (const std::string& k : error_statistics()) {
        const auto e = std::find_if(errors.begin(), errors.end(), [&](const StatError& s) { return s.key == k; });
        const bool compared = e != errors.end() && e->comparable;
        row += "," + (compared ? num(e->z) : "");
        if (z_sd) row += "," + (compared ? num(stat(*z_sd, k.c_str())) : "");
        row += "," + (compared ? num(e->error) : "") + "," + (compared ? (e->within_tolerance ? "1" : "0") : "");
        if (e != errors.end() && !e->comparable) not_comparable += (not_comparable.empty() ? "" : ";") + k;
    }
    const int verdict = within_tolerance(errors);
    return row + "," + num(rms_z(errors)) + "," + (verdict < 0 ? "" : std::to_string(verdict)) + "," + not_comparable;
}

std::string csv_header() {
    std::string h = "scene,method,elements,seed,status";
    for (const auto& c : stat_columns())
        h += "," + c;
    return h + error_header(false) + ",error\n";
}

std::string csv_row(const Record& r) {
    std::string row = r.run.scene + "," + r.run.method + "," + std::to_string(r.run.elements) + ","
                      + std::to_string(r.run.seed) + "," + r.outcome.status;
    for (const auto& c : stat_columns())
        row += "," + num(stat(r.stats, c.c_str()));
    return row + error_cells(r.errors, nullptr) + "," + num(r.error) + "\n";
}

/// Sample standard deviation (n − 1) of the finite values; NaN for fewer than two.
double seed_spread(const std::vector<double>& v) {
    std::vector<double> x;
    for (double a : v)
        if (std::isfinite(a)) x.push_back(a);
    if (x.size() < 2) return NAN;
    double mean = 0, ss = 0;
    for (double a : x)
        mean += a;
    mean /= double(x.size());
    for (double a : x)
        ss += sqr(a - mean);
    return std::sqrt(ss / double(x.size() - 1));
}

/// A method × resolution of a scene, seed-averaged.
struct Point {
    std::string scene, method;
    long long elements = 0;
    int runs = 0, ok = 0;
    StatMap mean;                  ///< means of the stat columns over the finished runs
    std::vector<StatError> errors; ///< the seed mean's per-statistic errors (pattern and arrest scenes)
    double error = NAN;
    double error_sd = NAN; ///< sample σ over the point's runs of their errors (the chart's bars)
    double wall_sd = NAN;  ///< sample σ over the point's runs of their wall times
    StatMap z_sd;          ///< per statistic: sample σ over the point's runs of their z
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
        std::vector<double> run_errors, run_walls;
        std::map<std::string, std::vector<double>> run_z;
        for (const Record* r : groups[key]) {
            ++p.runs;
            if (r->outcome.status != "ok") continue;
            ok.push_back(r->stats);
            run_walls.push_back(stat(r->stats, "wall_seconds"));
            run_errors.push_back(r->error);
            if (std::isfinite(r->error)) {
                error_sum += r->error;
                ++errors;
            }
            for (const StatError& e : r->errors)
                if (e.comparable) run_z[e.key].push_back(e.z);
        }
        p.ok = int(ok.size());
        p.error_sd = seed_spread(run_errors);
        p.wall_sd = seed_spread(run_walls);
        for (const auto& [k, zs] : run_z)
            if (const double sd = seed_spread(zs); std::isfinite(sd)) p.z_sd[k] = sd;
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
        // A point compares its seed mean (geometric for the logarithmic statistics) with the
        // reference, in the reference's single-run seed spreads.
        const std::vector<std::string> compared = compared_statistics(p.scene);
        if (ok.empty()) {
            p.error = NAN;
        } else if (!compared.empty()) {
            const StatMap seed_mean = average_stats(ok, scales_of(compared));
            p.errors = scene_stat_errors(p.scene, seed_mean, reference);
            p.error = reference_error(p.scene, seed_mean, p.errors, reference);
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
    csv += ",wall_seconds_sd" + error_header(true) + ",error,error_sd,pareto\n";
    for (const Point& p : points) {
        csv += p.scene + "," + p.method + "," + std::to_string(p.elements) + "," + std::to_string(p.runs) + ","
               + std::to_string(p.ok);
        for (const auto& c : stat_columns())
            csv += "," + num(stat(p.mean, c.c_str()));
        csv += "," + num(p.wall_sd) + error_cells(p.errors, &p.z_sd) + "," + num(p.error) + "," + num(p.error_sd) + ","
               + (p.pareto ? "1" : "0") + "\n";
    }
    return csv;
}

std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

/// A tolerance as written in the tables: "5 %" or "0.05".
std::string tolerance_text(const std::string& key) {
    const StatTolerance* t = find_tolerance(key);
    if (!t) return "–";
    return t->kind == ToleranceKind::Relative ? fmt("%g %%", 100 * t->value) : fmt("%g", t->value);
}

/// One cell of the per-statistic table: "z (error verdict)", or n/c.
std::string error_cell(const StatError& e) {
    if (!e.comparable) return "n/c";
    const StatTolerance* t = find_tolerance(e.key);
    const bool relative = t && t->kind == ToleranceKind::Relative;
    const std::string z = std::abs(e.z) >= 100 ? fmt("%+.0f", e.z) : fmt(std::abs(e.z) >= 10 ? "%+.1f" : "%+.2f", e.z);
    const std::string err = relative ? fmt("%+.1f %%", 100 * e.error) : fmt("%+.3g", e.error);
    return z + " (" + err + (e.within_tolerance ? " ✓" : " ✗") + ")";
}

/// How to read the errors, and the reference each pattern scene is compared with.
std::string summary_preamble(const std::vector<Point>& points, const Reference& reference) {
    std::vector<std::string> scenes;
    for (const Point& p : points)
        if (!compared_statistics(p.scene).empty() && reference.count(p.scene)
            && std::find(scenes.begin(), scenes.end(), p.scene) == scenes.end())
            scenes.push_back(p.scene);
    std::string md =
        "### How to read the errors\n\n"
        "- **bar, film, film-cylinder, film-sphere:** |t/t* − 1|, the relative error of the first break "
        "(crack) time against its closed form.\n"
        "- **mud, bark, arrest, per statistic k:** z_k = (x_k − μ_k)/σ_k, x_k the run's value (for a point: the "
        "mean over its seeds; geometric for crack length per area and mean fragment area, whose z is taken of "
        "log x), μ_k the reference's mean and σ_k its seed spread, the sample standard deviation over the "
        "reference's seeds. **z = 1 is one seed spread of a single run:** as far from the reference's mean as "
        "one more reference seed typically lands. No floor enters z. A converged method's n-seed mean still "
        "scatters by about √(1/n + 1/N) in z (N reference seeds).\n"
        "- **Relative or absolute error and tolerance:** beside z, each statistic's error x/μ − 1 (crack "
        "length per area, mean fragment area) or x − μ (the others), and ✓ when it is within the statistic's "
        "named tolerance (what a texture user would accept; below). Tolerances are judgements: nothing is "
        "divided by them.\n"
        "- **error (mud, bark):** √(mean z_k²) over the comparable statistics, in seed spreads. **error "
        "(arrest):** |h − h_ref| in tile heights (its z is in the per-statistic table).\n"
        "- **n/c, not comparable:** the reference gives no scale for that statistic (its seeds agree exactly, "
        "or, for the fragment statistics, it has fewer than "
        + fmt("%.0f", MIN_REFERENCE_FRAGMENTS)
        + " fragments per run); it is left out of the error.\n"
          "- **Error bars in the charts:** ±1 sample standard deviation over the point's seeds of each run's "
          "error (the seed spread of a single run's error, not the standard error of the mean); a point with "
          "one seed has none.\n";
    if (scenes.empty()) return md;
    md += "\n### Reference and tolerances\n\n"
          "| scene | statistic | seeds | mean μ | seed spread σ | σ, bootstrap 16–84 % | tolerance |\n"
          "|---|---|---:|---:|---:|---:|---:|\n";
    std::string warnings;
    for (const std::string& scene : scenes) {
        const SceneReference& ref = reference.at(scene);
        std::vector<std::string> keys = compared_statistics(scene);
        for (const std::string& k : keys) {
            const auto it = ref.stats.find(k);
            if (it == ref.stats.end()) continue;
            const ReferenceStat& st = it->second;
            const bool log = scales_of({k}).front().logarithmic;
            auto spread = [&](double v) { return log ? fmt("%.3g %%", 100 * v) : fmt("%.3g", v); };
            const std::vector<StatError> check = stat_errors({{k, st.mean}}, ref, {k});
            const std::string nc = check.front().comparable ? "" : " (n/c: " + check.front().why_not + ")";
            md += "| " + scene + " | " + stat_title(k) + nc + " | " + std::to_string(st.values.size()) + " | "
                  + fmt("%.4g", st.mean) + " | " + spread(st.spread) + " | " + spread(st.spread_low) + " – "
                  + spread(st.spread_high) + " | " + tolerance_text(k) + " |\n";
        }
        if (ref.seeds.size() < std::size_t(REFERENCE_SEEDS))
            warnings += "- The " + scene + " reference has " + std::to_string(ref.seeds.size()) + " seeds (fewer than "
                        + std::to_string(REFERENCE_SEEDS)
                        + "): its σ is uncertain by the bootstrap band above; regenerate it with crackle bench "
                          "--make-reference.\n";
    }
    md += "\nσ of crack length per area and mean fragment area is of log x (shown as a relative spread). "
          "The bootstrap band: "
          + std::to_string(BOOTSTRAP_RESAMPLES)
          + " resamples of the reference's seeds with replacement, the 16th and 84th percentiles of their σ "
            "(each scaled by √(n/(n − 1)): a resample's variance averages (n − 1)/n of the sample's). With few "
            "seeds the band is wide and lumpy: it can only redraw the values it has.\n";
    if (!warnings.empty()) md += "\n" + warnings;
    return md;
}

std::string summary_markdown(const std::vector<Point>& points, const Reference& reference) {
    std::string md = summary_preamble(points, reference);
    const auto slopes = cost_slopes(points);
    char buf[256];
    std::vector<std::string> scenes;
    for (const Point& p : points)
        if (std::find(scenes.begin(), scenes.end(), p.scene) == scenes.end()) scenes.push_back(p.scene);
    for (const std::string& scene : scenes) {
        const std::vector<std::string> keys = compared_statistics(scene);
        const std::string unit = scene == "mud" || scene == "bark" ? "RMS z"
                                 : scene == "arrest"               ? "tile heights"
                                                                   : "relative";
        md += "\n#### " + scene + "\n\n| method | elements | runs ok | wall | peak memory | events | error (" + unit
              + ") | ± seed spread | Pareto |\n|---|---:|---:|---:|---:|---:|---:|---:|:-:|\n";
        for (const Point& p : points) {
            if (p.scene != scene) continue;
            std::snprintf(buf, sizeof buf, "| %s | %lld | %d/%d | %.2f s | %.0f MiB | %.0f | %s | %s | %s |\n",
                          p.method.c_str(), p.elements, p.ok, p.runs, stat(p.mean, "wall_seconds"),
                          stat(p.mean, "peak_memory_mb"), stat(p.mean, "events"),
                          std::isfinite(p.error) ? num(p.error).c_str() : "–",
                          std::isfinite(p.error_sd) ? num(p.error_sd).c_str() : "–", p.pareto ? "●" : "");
            md += buf;
        }
        if (keys.empty() || !reference.count(scene)) continue;
        // Which statistic is off: z (error, tolerance verdict) per statistic.
        md += "\n| " + scene + ": z (error, within tolerance) | elements";
        std::string rule = "\n|---|---:";
        for (const std::string& k : keys) {
            md += " | " + stat_title(k) + " (" + tolerance_text(k) + ")";
            rule += "|---:";
        }
        md += " | within tolerance |" + rule + "|:-:|\n";
        for (const Point& p : points) {
            if (p.scene != scene) continue;
            md += "| " + p.method + " | " + std::to_string(p.elements);
            int within = 0, comparable = 0;
            for (const std::string& k : keys) {
                const auto e =
                    std::find_if(p.errors.begin(), p.errors.end(), [&](const StatError& s) { return s.key == k; });
                md += " | " + (e == p.errors.end() ? std::string("–") : error_cell(*e));
                if (e != p.errors.end() && e->comparable) {
                    ++comparable;
                    within += e->within_tolerance ? 1 : 0;
                }
            }
            md += " | " + (comparable > 0 ? std::to_string(within) + "/" + std::to_string(comparable) : "–") + " |\n";
        }
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
            throw InputError("bench", std::string("unknown ") + what + " '" + s + "'" + did_you_mean(s, known),
                             std::string(what) + "s are: " + join(known, ", "));
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
        const std::optional<StudyMethod> m = find_study_method(r.method);
        return w * (m ? m->variant.cost : 1.0);
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

std::vector<std::string> study_methods() {
    std::vector<std::string> names;
    for (const StudyMethod& m : study_methods_of_registry())
        names.push_back(m.variant.name);
    return names;
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
    // The reference's seeds: its σ is the error scale, so enough of them for a bootstrap band.
    const int reference_seeds = args.seeds > 0 ? args.seeds : REFERENCE_SEEDS;
    if (args.make_reference && reference_seeds < 2)
        throw InputError("bench",
                         "--make-reference --seeds " + std::to_string(reference_seeds)
                             + " gives no seed spread, and the spread is the study's error scale",
                         "use at least 2 seeds (default " + std::to_string(REFERENCE_SEEDS) + ")");
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
        if (reference_seeds < REFERENCE_SEEDS)
            log::warn("a reference over " + std::to_string(reference_seeds) + " seeds has an uncertain seed spread ("
                      + std::to_string(REFERENCE_SEEDS) + " or more are recommended)");
        Reference made;
        for (const std::string& scene : scenes) {
            if (!scene_has_reference(scene)) continue;
            const std::vector<StudyRun> runs = reference_runs(scene, reference_seeds);
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
        else if (scene_has_reference(scene) && reference.at(scene).seeds.size() < std::size_t(REFERENCE_SEEDS))
            log::warn("the " + scene + " reference has " + std::to_string(reference.at(scene).seeds.size())
                      + " seeds: its seed spread, the error scale, is uncertain (summary.md gives the bootstrap band; "
                        "regenerate it with crackle bench --make-reference)");
    const std::vector<StudyRun> runs = study_plan(scenes, methods, seeds, args.quick);
    std::vector<Record> records = execute(runs, args, binary, work, [&](std::vector<Record>& so_far) {
        Record& last = so_far.back();
        evaluate_run(last, reference);
        std::string csv = csv_header();
        for (const Record& r : so_far)
            csv += csv_row(r);
        write_file_atomically(out_dir / "runs.csv", csv); // readable while the study runs
    });
    std::filesystem::remove_all(work, ec);
    const std::vector<Point> points = aggregate(records, reference);
    write_file_atomically(out_dir / "points.csv", points_csv(points));
    const std::string md = summary_markdown(points, reference);
    write_file_atomically(out_dir / "summary.md", md);
    out << md;
    if (!python.empty()) {
        run_chart_script(python, "bench_charts",
                         {(out_dir / "runs.csv").string(), (out_dir / "points.csv").string(), out_dir.string()},
                         out_dir / "charts.log");
        out << "\ncharts: " << (out_dir / "error_vs_time.png").string()
            << ", stat_errors.png, cost_vs_elements.png, time_shares.png\n";
    }
    return 0;
}

} // namespace crackle::app
