#pragma once
/// @file The error metrics of the speed-vs-accuracy study (docs/benchmarks.md, "Error metrics"):
/// the pattern statistics vector and its distance to a stored reference in units of the
/// reference's seed-to-seed spread, the bonded film's closed-form first-crack time, and the
/// Griffith arrest height read from a run's events.

#include "core/json.hpp"

#include <map>
#include <string>
#include <vector>

namespace crackle::app {

/// A named statistic of a run ("crack_length_per_area" …) → value.
using StatMap = std::map<std::string, double>;

/// One statistic of the pattern distance: how a difference is measured and the smallest
/// spread it is divided by (so a statistic every reference seed agrees on still has a scale).
struct StatScale {
    std::string key;
    bool logarithmic = false; ///< compare log(x): counts and areas that vary over decades
    double floor = 0;         ///< smallest spread (of x, or of log x)
};

/// The statistics vector of a pattern scene: crack length per area, mean fragment area, fragment
/// area spread, T-junction fraction, anisotropy, tortuosity. Bark leaves the two fragment
/// statistics out: its fissures seldom close into pieces (1–2 fragments per reference run).
std::vector<StatScale> pattern_scales(const std::string& scene);

/// Everything a reference stores: the pattern statistics, the fragment count and the arrest height.
const std::vector<StatScale>& reference_scales();

/// What a scene's reference holds for one statistic.
struct ReferenceStat {
    double mean = 0;
    double spread = 0; ///< sample standard deviation over the reference seeds (of log x when logarithmic)
    std::vector<double> values;
};

/// A scene's converged reference: the finest affordable fem-split runs over several seeds.
struct SceneReference {
    std::string command; ///< how it was made
    long long elements = 0;
    std::vector<long long> seeds;
    std::map<std::string, ReferenceStat> stats;
};

using Reference = std::map<std::string, SceneReference>; ///< scene → reference

/// Builds a scene's reference from its runs' statistics (one StatMap per seed).
SceneReference make_scene_reference(const std::string& command, long long elements, const std::vector<long long>& seeds,
                                    const std::vector<StatMap>& runs, const std::vector<StatScale>& scales);

Json reference_to_json(const Reference& reference);
/// @throws InputError naming `source` when a field is missing or mistyped.
Reference reference_from_json(const Json& json, const std::string& source);

/// The reference compiled into the binary (docs/benchmarks/reference.json at build time).
Reference embedded_reference();

/// √(mean over statistics of z²), z = (x − mean) / max(spread, floor), logs where the scale says
/// so: below 1 the run (or a seed average) is as close as two reference seeds are to each other.
/// Statistics missing from `x` or the reference are skipped; −1 when none is left.
double pattern_distance(const StatMap& x, const SceneReference& reference, const std::vector<StatScale>& scales);

/// The seed average of runs' statistics (logs averaged where the scale says so, then undone).
StatMap average_stats(const std::vector<StatMap>& runs, const std::vector<StatScale>& scales);

/// Bonded film under uniform biaxial shrinkage ε = s·t: σ = E·ε/(1 − ν) reaches the threshold at
/// t* = σ_th·(1 − ν)/(E·s).
double film_first_crack_time(double young_modulus, double poisson_ratio, double threshold, double shrinkage_rate);

/// The same film bonded to a rigid cylinder or sphere of radius R (the layer from R to R + h):
/// the thick-shell (Lamé) solution, u = A·r + B/r (cylinder, no axial strain) or A·r + B/r²
/// (sphere), u(R) = 0, σ_rr(R + h) = 0. Returns the largest in-plane principal stress at
/// radius r ∈ [R, R + h] over the flat film's E·ε/(1 − ν) (1 on the plane; below 1 on curved
/// surfaces: the free top relieves the layer). `sphere` = false for the cylinder.
double curved_film_stress_factor(bool sphere, double R, double h, double poisson_ratio, double r);

/// The Griffith arrest scene's height (fraction of the tile, from the soft edge v = 0): the 5th
/// percentile of the v coordinates of the crack events above v = 0.1 (below lie the short cracks
/// that crossed the periodic seam into the softest material, where they stop at once).
/// `events_csv` is `simulate --events` output. −1 when there is no such event.
double arrest_height(const std::string& events_csv);

} // namespace crackle::app
