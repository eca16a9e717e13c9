#include "fracture/fem_remove/fem_remove.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/progress.hpp"
#include "fracture/toolkit/fem_loop.hpp"
#include "fracture/toolkit/fem_pattern.hpp"
#include "fracture/toolkit/next_crossing.hpp"
#include "fracture/toolkit/pick.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace crackle::fracture {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;

namespace {

Vec3 reference_centroid(const sim::FemModel& model, FaceId f) {
    const auto p = model.mesh().face_positions(f);
    return (p[0] + p[1] + p[2]) / 3.0;
}

} // namespace

namespace {

/// The vertices of these faces, sorted, each once.
std::vector<std::size_t> vertices_of_faces(const sim::FemModel& model, const std::vector<FaceId>& faces) {
    std::vector<std::size_t> vs;
    for (FaceId f : faces)
        for (mesh::VertexId v : model.mesh().faces[f].v)
            vs.push_back(ix(v));
    std::sort(vs.begin(), vs.end());
    vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
    return vs;
}

/// Alg. 5: the time of the next fracture after t0 (at most `horizon`), to `dt_min`, on the exact
/// affine solution; `last_step` the previous search's step (its first guess).
double next_fracture_time(const StressCache& cache, double t0, double horizon, double dt_min, double& last_step) {
    // Earliest possible crossing per element, from λ_max(σ₀ + τσ̇) ≤ ‖σ₀‖ + τ‖σ̇‖: only
    // elements whose bound has passed need their eigenvalues checked.
    const std::vector<std::pair<double, std::size_t>> earliest = cache.earliest_crossings();
    std::vector<std::size_t> over;
    bool narrowed = false;
    auto any_over = [&](double t) {
        if (narrowed) {
            for (std::size_t f : over)
                if (cache.ratio_at(f, t - t0) > 1.0) return true;
            return false;
        }
        for (const auto& [bound, f] : earliest) {
            if (bound > t - t0) break;
            if (cache.ratio_at(f, t - t0) > 1.0) return true;
        }
        return false;
    };
    // The first crossing is among the elements over threshold at t_hi (each ratio is convex
    // in t, so one below threshold at both ends stays below).
    auto narrow = [&](double t_hi) {
        for (const auto& [bound, f] : earliest) {
            if (bound > t_hi - t0) break;
            if (cache.ratio_at(f, t_hi - t0) > 1.0) over.push_back(f);
        }
        narrowed = true;
    };
    return next_crossing(t0, horizon, dt_min, last_step, any_over, narrow);
}

} // namespace

CrackPattern run_fem_remove(sim::FemModel& model, const FractureOptions& options, Rng& rng, RunStats* stats_out,
                            RemovalStats* removal_out) {
    RunStats stats;
    RemovalStats removal;
    Timer total;
    EventLog events(options);
    const std::size_t elements_initial = model.num_alive();
    const double dt_min = options.time_tolerance * options.duration;

    // Local radius in hops (§5.8.3). The error of a local solve decays as exp(−r/1.6h)
    // (docs/perf-limits.md), so start from the hops that cover ln(1/tol)·1.6 thicknesses.
    sim::LocalRelaxOptions local_options;
    local_options.tolerance = options.local_tolerance;
    double radius = initial_radius(model, local_options.tolerance);
    double rate_radius = radius;
    std::vector<std::size_t> rate_seeds; // nodes whose rate is stale since the last time step
    auto relax_near = [&](const std::vector<std::size_t>& seeds) {
        return relax_after_change(model, seeds, radius, local_options, options, stats, rate_seeds);
    };
    auto vertices_of = [&](const std::vector<FaceId>& faces) { return vertices_of_faces(model, faces); };

    StressCache cache(model);
    relax_all(model, cache, stats); // the state at the start: equilibrium and its rate, globally
    FractureProgress progress(options.duration, elements_initial);
    double last_step = options.duration * 1e-3;

    while (true) {
        progress.update(model.time(), events.size());
        Timer timer;
        std::size_t picked = 0;
        double best = 0;
        // The element with the highest ratio above 1 (§5.6.2), ties drawn from the seed.
        const bool have = pick_most_over(
            cache.size(), [&](std::size_t f) { return cache.ratio(f); },
            [&](std::size_t f) { return model.alive(face_id(f)); }, rng, picked, best);
        stats.stress_seconds += timer.seconds();
        if (have) {
            if (events.full(model.time())) break;
            const FaceId f = face_id(picked);
            Event ev;
            ev.time = model.time();
            ev.position = reference_centroid(model, f);
            ev.ratio = cache.ratio(picked);
            std::vector<std::size_t> moved;
            timer.reset();
            if (options.min_element_size > 0 && model.element_size(f) > options.min_element_size) {
                // Alg. 8: too coarse to remove; refine here instead (Rivara, Alg. 9).
                const std::vector<FaceId> touched = model.subdivide(f);
                ev.kind = "subdivide";
                ++removal.subdivisions;
                cache.resize();
                stats.topology_seconds += timer.seconds();
                moved = relax_near(vertices_of(touched));
                timer.reset();
                for (FaceId t : touched)
                    cache.refresh(ix(t)); // new elements: σ and σ̇
            } else {
                model.remove_element(f);
                ev.kind = "remove";
                ++removal.removals;
                stats.topology_seconds += timer.seconds();
                moved = relax_near(vertices_of({f}));
                timer.reset();
                cache.refresh(picked);
            }
            cache.refresh_around(moved);
            stats.stress_seconds += timer.seconds();
            events.add(ev, model);
            continue;
        }
        if (model.time() >= options.duration) break;

        settle_time_step(model, cache, options, local_options, rate_radius, rate_seeds, stats);

        // === Alg. 5: find the time of the next fracture
        timer.reset();
        const double t_next = next_fracture_time(
            cache, model.time(), std::min(options.duration, model.stiffness_horizon()), dt_min, last_step);
        stats.stress_seconds += timer.seconds();

        // Move along the exact affine solution; no solve unless shrinkage rebuilt the stiffness.
        advance_model(model, cache, t_next, stats);
    }
    progress.finish();

    CrackPattern pattern = pattern_from_model(model, "fem-remove", elements_initial);
    pattern.events_capped = events.capped();
    pattern.events = events.take();
    stats.total_seconds = total.seconds();
    if (stats_out) *stats_out = stats;
    if (removal_out) *removal_out = removal;
    return pattern;
}

} // namespace crackle::fracture
