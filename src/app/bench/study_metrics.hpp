#pragma once
/// @file The error metrics of the speed-vs-accuracy study (docs/benchmarks.md, "Scenes and their
/// error metrics"): the pattern statistics against a stored reference, each in units of the
/// reference's real seed spread (with a bootstrap band) and against a named tolerance, the bonded
/// film's closed-form first-crack time, and the Griffith arrest height read from a run's events.

#include "core/json.hpp"

#include <cmath>
#include <map>
#include <string>
#include <vector>

namespace crackle::app {

/// A named statistic of a run ("crack_length_per_area" …) → value.
using StatMap = std::map<std::string, double>;

/// How a statistic is compared and stored: its key and whether its spread and its z are taken of
/// log x (crack density, fragment area and count: quantities that vary over decades). Errors are
/// in the reference's real seed spread, with no floor under it (stat_errors()).
struct StatScale {
    std::string key;
    bool logarithmic = false; ///< compare log(x): counts and areas that vary over decades
};

/// Everything a reference stores: the pattern statistics, the fragment count and the arrest height.
const std::vector<StatScale>& reference_scales();

// === Tolerances: what a texture user would accept (judgements, not measured spreads)

/// Relative: |x/μ − 1| ≤ value. Absolute: |x − μ| ≤ value, in the statistic's own unit.
enum class ToleranceKind { Relative, Absolute };

/// A named tolerance of one statistic. Nothing divides by it: it only gives the
/// "within tolerance" verdict, beside the error in seed spreads.
struct StatTolerance {
    std::string key;
    ToleranceKind kind = ToleranceKind::Absolute;
    double value = 0;
};

/// The tolerance table (docs/benchmarks.md, "Tolerances"), one row per statistic the study
/// compares with a reference.
const std::vector<StatTolerance>& stat_tolerances();
/// The row of `key`; nullptr when the statistic has no tolerance.
const StatTolerance* find_tolerance(const std::string& key);

/// The statistics the study compares for a scene, in column order: the six pattern statistics
/// for mud and bark (all of them: those the reference cannot support are reported not
/// comparable, not left out), the arrest height for arrest, none for the closed-form scenes.
std::vector<std::string> compared_statistics(const std::string& scene);
/// Every statistic with per-statistic error columns in the study's CSVs, in column order.
const std::vector<std::string>& error_statistics();

// === The reference and its seed spread

/// A seed spread with its bootstrap uncertainty.
struct SpreadEstimate {
    double sigma = 0; ///< sample standard deviation (n − 1) of the values
    double low = 0;   ///< 16th percentile of the bootstrap σ
    double high = 0;  ///< 84th percentile of the bootstrap σ
};

constexpr int BOOTSTRAP_RESAMPLES = 4000;

/// σ of `values` and its bootstrap band: BOOTSTRAP_RESAMPLES resamples of n values drawn with
/// replacement (crackle::Rng, a fixed seed and stream: the same values give the same band), the
/// sample σ of each scaled by √(n/(n − 1)) (a resample's variance averages (n − 1)/n of the
/// sample's), and the 16th and 84th percentiles of those (±1 standard deviation for a normal
/// spread). All zero for fewer than two values.
SpreadEstimate bootstrap_spread(const std::vector<double>& values, int resamples = BOOTSTRAP_RESAMPLES);

/// What a scene's reference holds for one statistic.
struct ReferenceStat {
    double mean = 0;   ///< arithmetic mean; geometric when logarithmic
    double spread = 0; ///< sample standard deviation over the reference seeds (of log x when logarithmic)
    double spread_low = 0, spread_high = 0; ///< the bootstrap band of `spread` (bootstrap_spread())
    std::vector<double> values;             ///< one per seed, as measured
};

/// A scene's converged reference: the finest affordable fem-split runs over several seeds.
struct SceneReference {
    std::string command; ///< how it was made
    long long elements = 0;
    std::vector<long long> seeds;
    std::map<std::string, ReferenceStat> stats;
};

using Reference = std::map<std::string, SceneReference>; ///< scene → reference

/// The number of seeds `crackle bench --make-reference` runs by default; a reference with fewer
/// has an uncertain spread (the study says so).
constexpr int REFERENCE_SEEDS = 8;

/// Builds a scene's reference from its runs' statistics (one StatMap per seed): means, seed
/// spreads and their bootstrap bands.
SceneReference make_scene_reference(const std::string& command, long long elements, const std::vector<long long>& seeds,
                                    const std::vector<StatMap>& runs, const std::vector<StatScale>& scales);

/// Writes means, spreads, bootstrap bands and the per-seed values.
Json reference_to_json(const Reference& reference);
/// Reads a reference; the bootstrap band is recomputed from the per-seed values (a stored one is
/// ignored, so an older reference without it reads the same).
/// @throws InputError naming `source` when a field is missing or mistyped.
Reference reference_from_json(const Json& json, const std::string& source);

/// The reference compiled into the binary (docs/benchmarks/reference.json at build time).
Reference embedded_reference();

// === Errors against the reference

/// Fragment statistics are not comparable when the reference's runs average fewer pieces than
/// this: a mean area or an area spread over one or two pieces is not a pattern statistic.
constexpr double MIN_REFERENCE_FRAGMENTS = 10;

/// One statistic of a run (or a seed average) against the reference.
struct StatError {
    std::string key;
    bool comparable = false;
    std::string why_not; ///< when not comparable: "no reference", "no seed spread", …
    double value = NAN;  ///< x
    double mean = NAN;   ///< μ
    double spread = NAN; ///< σ (of log x when logarithmic)
    /// (x − μ)/σ, of log x when logarithmic: the error in seed spreads of the reference. No
    /// floor: a statistic every reference seed agrees on is not comparable instead.
    double z = NAN;
    double error = NAN; ///< x/μ − 1 (Relative tolerance) or x − μ (Absolute)
    bool within_tolerance = false;
};

/// The errors of `x` against `reference` for each of `keys` (compared_statistics()). A statistic
/// is not comparable when x or the reference lacks it, the reference has fewer than two values
/// or no spread, or, for the fragment statistics, fewer than MIN_REFERENCE_FRAGMENTS pieces.
std::vector<StatError> stat_errors(const StatMap& x, const SceneReference& reference,
                                   const std::vector<std::string>& keys);

/// √(mean z²) over the comparable statistics: the overall error in seed spreads (0 at the
/// reference's means; a single converged run scores about √(1 + 1/N) for an N-seed reference).
/// NaN when none is comparable.
double rms_z(const std::vector<StatError>& errors);

/// The errors of the seed average of `runs` against a pattern scene's reference, for its
/// compared_statistics() (bench scale, bench speedup, the auto-resolution test).
std::vector<StatError> seed_average_errors(const std::vector<StatMap>& runs, const SceneReference& reference,
                                           const std::string& scene);

/// A statistic's display name (the column headers of docs/benchmarks.md): "T share" …
std::string stat_title(const std::string& key);

/// The key of the comparable statistic with the largest |z|; empty when none is comparable.
std::string worst_statistic(const std::vector<StatError>& errors);

/// 1 when every comparable statistic is within its tolerance, 0 when one is not, −1 when none
/// is comparable.
int within_tolerance(const std::vector<StatError>& errors);

/// The seed average of runs' statistics (logs averaged where the scale says so, then undone).
StatMap average_stats(const std::vector<StatMap>& runs, const std::vector<StatScale>& scales);

/// The scales (key and log flag) of `keys`, for average_stats().
std::vector<StatScale> scales_of(const std::vector<std::string>& keys);

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
