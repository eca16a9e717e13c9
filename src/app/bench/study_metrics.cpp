#include "app/bench/study_metrics.hpp"

#include "core/embedded.hpp"
#include "core/error.hpp"
#include "core/math.hpp"
#include "core/rng.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <sstream>

namespace crackle::app {

const std::vector<StatScale>& reference_scales() {
    // Crack density, fragment area and count vary over decades: their spreads are of the logs.
    static const std::vector<StatScale> scales = {
        {"crack_length_per_area", true},
        {"mean_fragment_area", true},
        {"fragment_area_cv", false},
        {"t_junction_fraction", false},
        {"anisotropy", false},
        {"tortuosity", false},
        {"fragments", true},
        {"arrest_height", false},
    };
    return scales;
}

const std::vector<StatTolerance>& stat_tolerances() {
    // What a texture user would accept: judgements, not measurements (docs/benchmarks.md,
    // "The error scale"). Crack density and plate size 5 % relative; T share and anisotropy 0.05
    // and tortuosity 0.01 (1 % more path than the straight line) absolute. The area CV (0.05, as
    // the T share) and the arrest height (0.02 tile heights, 6 mm on the 0.3 m tile) are set the
    // same way. The fragment count is listed but not compared (mean fragment area carries it).
    // Nothing divides by these: they give the "within tolerance" verdict only.
    static const std::vector<StatTolerance> tolerances = {
        {"crack_length_per_area", ToleranceKind::Relative, 0.05},
        {"mean_fragment_area", ToleranceKind::Relative, 0.05},
        {"fragment_area_cv", ToleranceKind::Absolute, 0.05},
        {"t_junction_fraction", ToleranceKind::Absolute, 0.05},
        {"anisotropy", ToleranceKind::Absolute, 0.05},
        {"tortuosity", ToleranceKind::Absolute, 0.01},
        {"fragments", ToleranceKind::Relative, 0.05},
        {"arrest_height", ToleranceKind::Absolute, 0.02},
    };
    return tolerances;
}

const StatTolerance* find_tolerance(const std::string& key) {
    for (const StatTolerance& t : stat_tolerances())
        if (t.key == key) return &t;
    return nullptr;
}

std::vector<std::string> compared_statistics(const std::string& scene) {
    if (scene == "mud" || scene == "bark")
        return {"crack_length_per_area", "mean_fragment_area", "fragment_area_cv",
                "t_junction_fraction",   "anisotropy",         "tortuosity"};
    if (scene == "arrest") return {"arrest_height"};
    return {};
}

const std::vector<std::string>& error_statistics() {
    static const std::vector<std::string> keys = {"crack_length_per_area", "mean_fragment_area", "fragment_area_cv",
                                                  "t_junction_fraction",   "anisotropy",         "tortuosity",
                                                  "arrest_height"};
    return keys;
}

std::vector<StatScale> scales_of(const std::vector<std::string>& keys) {
    std::vector<StatScale> out;
    for (const std::string& key : keys) {
        const auto it = std::find_if(reference_scales().begin(), reference_scales().end(),
                                     [&](const StatScale& s) { return s.key == key; });
        out.push_back({key, it != reference_scales().end() && it->logarithmic});
    }
    return out;
}

namespace {

double transformed(double x, const StatScale& s) {
    return s.logarithmic ? std::log(std::max(x, 1e-300)) : x;
}

bool is_logarithmic(const std::string& key) {
    return scales_of({key}).front().logarithmic;
}

/// Sample standard deviation (n − 1) of v; 0 for fewer than two values.
double sample_sigma(const std::vector<double>& v) {
    if (v.size() < 2) return 0.0;
    double mean = 0;
    for (double a : v)
        mean += a;
    mean /= double(v.size());
    double ss = 0;
    for (double a : v)
        ss += sqr(a - mean);
    return std::sqrt(ss / double(v.size() - 1));
}

/// The q-quantile of sorted values, linear between order statistics.
double quantile(const std::vector<double>& sorted, double q) {
    const double at = q * double(sorted.size() - 1);
    const auto i = static_cast<std::size_t>(at);
    const double f = at - double(i);
    return i + 1 < sorted.size() ? sorted[i] + f * (sorted[i + 1] - sorted[i]) : sorted[i];
}

/// The bootstrap's own generator: a fixed seed on a stream no pipeline stage uses, so a band
/// depends on the values only.
constexpr std::uint64_t BOOTSTRAP_SEED = 20260214;
constexpr std::uint64_t BOOTSTRAP_STREAM = 0xB007;

/// The stored values of a reference statistic as compared (logs where the scale says so).
std::vector<double> compared_values(const std::vector<double>& values, const StatScale& s) {
    std::vector<double> out;
    for (double v : values)
        out.push_back(transformed(v, s));
    return out;
}

} // namespace

SpreadEstimate bootstrap_spread(const std::vector<double>& values, int resamples) {
    SpreadEstimate e;
    const std::size_t n = values.size();
    if (n < 2 || resamples < 1) return e;
    e.sigma = sample_sigma(values);
    // A resample's sample variance averages (n − 1)/n of the sample's (it redraws the observed
    // values only): each resample's σ is scaled by √(n/(n − 1)) so that the band is centred on σ
    // rather than below it, which matters at the few seeds a reference has.
    const double unbias = std::sqrt(double(n) / double(n - 1));
    Rng rng(BOOTSTRAP_SEED, BOOTSTRAP_STREAM);
    std::vector<double> sigmas(static_cast<std::size_t>(resamples)), draw(n);
    for (double& sigma : sigmas) {
        for (double& d : draw)
            d = values[rng.uniform_int(static_cast<std::uint32_t>(n))];
        sigma = unbias * sample_sigma(draw);
    }
    std::sort(sigmas.begin(), sigmas.end());
    e.low = quantile(sigmas, 0.16);
    e.high = quantile(sigmas, 0.84);
    return e;
}

SceneReference make_scene_reference(const std::string& command, long long elements, const std::vector<long long>& seeds,
                                    const std::vector<StatMap>& runs, const std::vector<StatScale>& scales) {
    SceneReference r;
    r.command = command;
    r.elements = elements;
    r.seeds = seeds;
    for (const StatScale& s : scales) {
        ReferenceStat st;
        double sum = 0;
        for (const StatMap& run : runs) {
            const auto it = run.find(s.key);
            if (it == run.end()) continue;
            st.values.push_back(it->second);
            sum += transformed(it->second, s);
        }
        if (st.values.empty()) continue;
        const double n = double(st.values.size());
        st.mean = sum / n;
        double var = 0;
        for (double v : st.values)
            var += sqr(transformed(v, s) - st.mean);
        st.spread = st.values.size() > 1 ? std::sqrt(var / (n - 1)) : 0.0;
        const SpreadEstimate band = bootstrap_spread(compared_values(st.values, s));
        st.spread_low = band.low;
        st.spread_high = band.high;
        if (s.logarithmic) st.mean = std::exp(st.mean); // stored as the geometric mean
        r.stats[s.key] = st;
    }
    return r;
}

Json reference_to_json(const Reference& reference) {
    Json out = Json::object();
    for (const auto& [scene, r] : reference) {
        Json j = Json::object();
        j["command"] = r.command;
        j["elements"] = r.elements;
        Json seeds = Json::array();
        for (long long s : r.seeds)
            seeds.push_back(s);
        j["seeds"] = seeds;
        Json stats = Json::object();
        for (const auto& [key, st] : r.stats) {
            Json s = Json::object();
            s["mean"] = st.mean;
            s["spread"] = st.spread;
            // For readers; reference_from_json() recomputes it from the values.
            s["spread_bootstrap_16_84"] = Json::array();
            s["spread_bootstrap_16_84"].push_back(st.spread_low);
            s["spread_bootstrap_16_84"].push_back(st.spread_high);
            Json values = Json::array();
            for (double v : st.values)
                values.push_back(v);
            s["values"] = values;
            stats[key] = s;
        }
        j["statistics"] = stats;
        out[scene] = j;
    }
    return out;
}

Reference reference_from_json(const Json& json, const std::string& source) {
    auto need = [&](const Json& parent, const std::string& key, const std::string& where) -> const Json& {
        const Json* v = parent.find(key);
        if (!v)
            throw InputError(source, where + " has no '" + key + "'",
                             "regenerate it with crackle bench --make-reference");
        return *v;
    };
    Reference out;
    for (const auto& [scene, j] : json.members()) {
        SceneReference r;
        r.command = need(j, "command", scene).as_string();
        r.elements = static_cast<long long>(need(j, "elements", scene).as_number());
        for (const Json& s : need(j, "seeds", scene).elements())
            r.seeds.push_back(static_cast<long long>(s.as_number()));
        for (const auto& [key, s] : need(j, "statistics", scene).members()) {
            ReferenceStat st;
            st.mean = need(s, "mean", scene + "." + key).as_number();
            st.spread = need(s, "spread", scene + "." + key).as_number();
            for (const Json& v : need(s, "values", scene + "." + key).elements())
                st.values.push_back(v.as_number());
            const SpreadEstimate band = bootstrap_spread(compared_values(st.values, scales_of({key}).front()));
            st.spread_low = band.low;
            st.spread_high = band.high;
            r.stats[key] = st;
        }
        out[scene] = r;
    }
    return out;
}

Reference embedded_reference() {
    for (const EmbeddedFile& f : embedded::bench_files())
        if (f.name == "reference")
            return reference_from_json(Json::parse(f.text, "reference.json (embedded)"), "reference.json (embedded)");
    return {};
}

std::vector<StatError> stat_errors(const StatMap& x, const SceneReference& reference,
                                   const std::vector<std::string>& keys) {
    std::vector<StatError> out;
    const auto fragments = reference.stats.find("fragments");
    for (const std::string& key : keys) {
        StatError e;
        e.key = key;
        const auto xi = x.find(key);
        const auto ri = reference.stats.find(key);
        if (xi != x.end()) e.value = xi->second;
        if (ri != reference.stats.end()) {
            e.mean = ri->second.mean;
            e.spread = ri->second.spread;
        }
        const bool fragment_statistic = key == "mean_fragment_area" || key == "fragment_area_cv";
        if (ri == reference.stats.end()) {
            e.why_not = "not in the reference";
        } else if (xi == x.end() || !std::isfinite(e.value) || (key == "arrest_height" && e.value < 0)) {
            e.why_not = "not measured";
        } else if (ri->second.values.size() < 2) {
            e.why_not = "reference has fewer than 2 seeds";
        } else if (fragment_statistic && fragments != reference.stats.end()
                   && fragments->second.mean < MIN_REFERENCE_FRAGMENTS) {
            char buf[96];
            std::snprintf(buf, sizeof buf, "reference has %.1f fragments per run", fragments->second.mean);
            e.why_not = buf;
        } else if (!(e.spread > 0) || !std::isfinite(e.spread)) {
            e.why_not = "reference seeds agree exactly (no seed spread)";
        } else {
            e.comparable = true;
        }
        if (!e.comparable) {
            out.push_back(e);
            continue;
        }
        // z_k = (x_k − μ_k)/σ_k, of log x for the logarithmic statistics: no floor in it.
        const StatScale scale{key, is_logarithmic(key)};
        e.z = (transformed(e.value, scale) - transformed(e.mean, scale)) / e.spread;
        const StatTolerance* tolerance = find_tolerance(key);
        const bool relative = tolerance && tolerance->kind == ToleranceKind::Relative;
        e.error = relative ? e.value / e.mean - 1.0 : e.value - e.mean;
        e.within_tolerance = tolerance && std::abs(e.error) <= tolerance->value;
        out.push_back(e);
    }
    return out;
}

double rms_z(const std::vector<StatError>& errors) {
    double sum = 0;
    int n = 0;
    for (const StatError& e : errors)
        if (e.comparable) {
            sum += sqr(e.z);
            ++n;
        }
    return n > 0 ? std::sqrt(sum / n) : NAN;
}

std::string stat_title(const std::string& key) {
    static const std::map<std::string, std::string> titles = {{"crack_length_per_area", "crack length per area"},
                                                              {"mean_fragment_area", "mean fragment area"},
                                                              {"fragment_area_cv", "fragment area CV"},
                                                              {"t_junction_fraction", "T share"},
                                                              {"anisotropy", "anisotropy"},
                                                              {"tortuosity", "tortuosity"},
                                                              {"arrest_height", "arrest height"},
                                                              {"fragments", "fragments"}};
    const auto it = titles.find(key);
    return it == titles.end() ? key : it->second;
}

std::vector<StatError> seed_average_errors(const std::vector<StatMap>& runs, const SceneReference& reference,
                                           const std::string& scene) {
    const std::vector<std::string> keys = compared_statistics(scene);
    return stat_errors(average_stats(runs, scales_of(keys)), reference, keys);
}

std::string worst_statistic(const std::vector<StatError>& errors) {
    const StatError* worst = nullptr;
    for (const StatError& e : errors)
        if (e.comparable && (!worst || std::abs(e.z) > std::abs(worst->z))) worst = &e;
    return worst ? worst->key : std::string();
}

int within_tolerance(const std::vector<StatError>& errors) {
    int verdict = -1;
    for (const StatError& e : errors)
        if (e.comparable) {
            if (!e.within_tolerance) return 0;
            verdict = 1;
        }
    return verdict;
}

StatMap average_stats(const std::vector<StatMap>& runs, const std::vector<StatScale>& scales) {
    StatMap out;
    for (const StatScale& s : scales) {
        double sum = 0;
        int n = 0;
        for (const StatMap& run : runs) {
            const auto it = run.find(s.key);
            if (it == run.end() || !std::isfinite(it->second)) continue;
            sum += transformed(it->second, s);
            ++n;
        }
        if (n > 0) out[s.key] = s.logarithmic ? std::exp(sum / n) : sum / n;
    }
    return out;
}

double film_first_crack_time(double young_modulus, double poisson_ratio, double threshold, double shrinkage_rate) {
    return threshold * (1.0 - poisson_ratio) / (young_modulus * shrinkage_rate);
}

double curved_film_stress_factor(bool sphere, double R, double h, double nu, double r) {
    // Linear isotropic elasticity with an isotropic eigenstrain −1 (E = 1): the stresses are
    // affine in A once B = −A·R^k, so σ_rr(R + h) = 0 fixes A from two evaluations.
    const double c = 1.0 / ((1 + nu) * (1 - 2 * nu)), eigen = -1.0 / (1 - 2 * nu);
    const double k = sphere ? 3.0 : 2.0;
    struct Stress {
        double rr, tt, zz;
    };
    auto stress = [&](double A, double rho) {
        const double B = -A * std::pow(R, k);
        const double e_tt = A + B / std::pow(rho, k);
        const double e_rr = A - (k - 1) * B / std::pow(rho, k);
        if (sphere) // e_φφ = e_θθ
            return Stress{c * ((1 - nu) * e_rr + 2 * nu * e_tt) - eigen, c * (e_tt + nu * e_rr) - eigen, 0.0};
        return Stress{c * ((1 - nu) * e_rr + nu * e_tt) - eigen, c * ((1 - nu) * e_tt + nu * e_rr) - eigen,
                      c * nu * (e_rr + e_tt) - eigen};
    };
    const double s0 = stress(0, R + h).rr, s1 = stress(1, R + h).rr;
    const Stress s = stress(-s0 / (s1 - s0), r);
    const double flat = 1.0 / (1 - nu);
    return (sphere ? s.tt : std::max(s.tt, s.zz)) / flat;
}

double arrest_height(const std::string& events_csv) {
    std::istringstream in(events_csv);
    std::string line;
    std::getline(in, line); // header: time,x,y,z,u,v,kind,ratio
    std::vector<double> v;
    while (std::getline(in, line)) {
        std::vector<std::string> cells;
        std::stringstream row(line);
        std::string cell;
        while (std::getline(row, cell, ','))
            cells.push_back(cell);
        if (cells.size() < 7 || cells[6] == "arrest") continue;
        const double vv = std::strtod(cells[5].c_str(), nullptr);
        if (vv > 0.1) v.push_back(vv);
    }
    if (v.empty()) return -1.0;
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(0.05 * double(v.size() - 1) + 0.5)];
}

} // namespace crackle::app
