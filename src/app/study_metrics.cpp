#include "app/study_metrics.hpp"

#include "core/embedded.hpp"
#include "core/error.hpp"
#include "core/math.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace crackle::app {

const std::vector<StatScale>& reference_scales() {
    // Floors: 5 % on the scale quantities (crack density, fragment area and count, as logs), and
    // absolute ones on the dimensionless shape statistics, about what two seeds of a converged
    // run differ by.
    static const std::vector<StatScale> scales = {
        {"crack_length_per_area", true, 0.05},
        {"mean_fragment_area", true, 0.05},
        {"fragment_area_cv", false, 0.05},
        {"t_junction_fraction", false, 0.03},
        {"anisotropy", false, 0.03},
        {"tortuosity", false, 0.01},
        {"fragments", true, 0.05},
        {"arrest_height", false, 0.01},
    };
    return scales;
}

std::vector<StatScale> pattern_scales(const std::string& scene) {
    std::vector<StatScale> out;
    for (const StatScale& s : reference_scales()) {
        if (s.key == "fragments" || s.key == "arrest_height") continue;
        if (scene == "bark" && (s.key == "mean_fragment_area" || s.key == "fragment_area_cv")) continue;
        out.push_back(s);
    }
    return out;
}

namespace {

double transformed(double x, const StatScale& s) {
    return s.logarithmic ? std::log(std::max(x, 1e-300)) : x;
}

} // namespace

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

double pattern_distance(const StatMap& x, const SceneReference& reference, const std::vector<StatScale>& scales) {
    double sum = 0;
    int n = 0;
    for (const StatScale& s : scales) {
        const auto xi = x.find(s.key);
        const auto ri = reference.stats.find(s.key);
        if (xi == x.end() || ri == reference.stats.end() || !std::isfinite(xi->second)) continue;
        const double z =
            (transformed(xi->second, s) - transformed(ri->second.mean, s)) / std::max(ri->second.spread, s.floor);
        sum += z * z;
        ++n;
    }
    return n > 0 ? std::sqrt(sum / n) : -1.0;
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
