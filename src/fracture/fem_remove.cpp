#include "fracture/fem_remove.hpp"

#include "core/error.hpp"
#include "core/log.hpp"
#include "core/progress.hpp"
#include "fracture/stress_cache.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace crackle::fracture {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;

namespace {

struct Candidate {
    std::size_t face = 0;
    double ratio = 0;
};

/// The element with the highest ratio above 1; ties (within 1e-12) broken by the RNG.
bool pick_candidate(const sim::FemModel& model, const StressCache& cache, Rng& rng, Candidate& out) {
    double best = 1.0;
    std::vector<std::size_t> ties;
    for (std::size_t f = 0; f < cache.size(); ++f) {
        if (!model.alive(face_id(f))) continue;
        const double r = cache.ratio(f);
        if (r <= 1.0) continue;
        if (r > best * (1 + 1e-12)) {
            best = r;
            ties.assign(1, f);
        } else if (r >= best * (1 - 1e-12)) {
            ties.push_back(f);
        }
    }
    if (ties.empty()) return false;
    out.face = ties.size() == 1 ? ties[0] : ties[rng.uniform_int(static_cast<std::uint32_t>(ties.size()))];
    out.ratio = cache.ratio(out.face);
    return true;
}

Vec3 reference_centroid(const sim::FemModel& model, FaceId f) {
    const auto p = model.mesh().face_positions(f);
    return (p[0] + p[1] + p[2]) / 3.0;
}

} // namespace

CrackPattern pattern_from_model(const sim::FemModel& model, const std::string& method, std::size_t elements_initial) {
    CrackPattern p;
    p.method = method;
    p.surface = model.surface();
    p.mesh = model.mesh();
    p.final_time = model.time();
    p.elements_initial = elements_initial;
    const std::size_t nv = p.mesh.num_vertices(), nf = p.mesh.num_faces();
    p.deformed.resize(nv);
    p.thickness.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) {
        p.deformed[v] = model.top_position(mesh::vertex_id(v));
        p.thickness[v] = model.vertex_thickness(mesh::vertex_id(v));
    }
    for (int i = 0; i < 2; ++i)
        p.deformed_period[static_cast<std::size_t>(i)] =
            model.growth().period_shift(p.mesh.period_vectors[static_cast<std::size_t>(i)], model.time());
    p.removed.resize(nf);
    p.young_modulus.resize(nf);
    for (std::size_t f = 0; f < nf; ++f) {
        p.removed[f] = model.alive(face_id(f)) ? 0 : 1;
        p.young_modulus[f] = model.material(face_id(f)).young_modulus;
    }
    p.poisson_ratio = model.poisson_ratio();
    p.growth_map = Mat3::Identity() + model.time() * model.growth().tensor();
    label_fragments(p);
    // Crack lips: intact edges facing a removed element; the opening is the removed
    // element's deformed height over that edge, its depth the layer thickness.
    for (CrackEdge c : removal_crack_lips(p)) {
        const int k = c.edge;
        const mesh::FaceNeighbor nb = p.mesh.neighbor(c.face, k);
        const Vec3 a = p.deformed_corner(c.face, k), b = p.deformed_corner(c.face, (k + 1) % 3);
        if (nb.face != mesh::NO_FACE) {
            const Vec3 far = p.deformed_corner(nb.face, (nb.edge + 2) % 3);
            c.opening = (far - a).cross(b - a).norm() / std::max((b - a).norm(), 1e-300);
        }
        const auto& face = p.mesh.faces[c.face];
        c.depth = 0.5
                  * (p.thickness[ix(face.v[static_cast<std::size_t>(k)])]
                     + p.thickness[ix(face.v[static_cast<std::size_t>((k + 1) % 3)])]);
        p.cracks.push_back(c);
    }
    return p;
}

CrackPattern run_fem_remove(sim::FemModel& model, const FractureOptions& options, Rng& rng, RunStats* stats_out) {
    RunStats stats;
    Timer total;
    std::vector<Event> events;
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
        Timer timer;
        const sim::SolveStats s =
            options.local_relaxation ? model.relax_local(seeds, radius, local_options) : model.relax();
        stats.solver_iterations += s.iterations;
        ++stats.solves;
        if (options.local_relaxation) {
            ++stats.local_solves;
            stats.local_nodes += s.nodes;
            stats.local_fallbacks += s.fell_back;
        }
        rate_seeds.insert(rate_seeds.end(), seeds.begin(), seeds.end());
        stats.solve_seconds += timer.seconds();
        check_drift(model, options, radius, stats); // §5.8.3
        return model.last_updated_vertices();
    };
    auto vertices_of = [&](const std::vector<FaceId>& faces) {
        std::vector<std::size_t> vs;
        for (FaceId f : faces)
            for (mesh::VertexId v : model.mesh().faces[f].v)
                vs.push_back(ix(v));
        std::sort(vs.begin(), vs.end());
        vs.erase(std::unique(vs.begin(), vs.end()), vs.end());
        return vs;
    };

    StressCache cache(model);
    // The state at the start: equilibrium and its rate, globally.
    {
        Timer timer;
        stats.solver_iterations += model.relax().iterations + model.solve_rate().iterations;
        stats.solves += 2;
        stats.solve_seconds += timer.seconds();
        timer.reset();
        cache.refresh_all();
        stats.stress_seconds += timer.seconds();
    }
    Progress progress("fracture", options.duration);
    double last_step = options.duration * 1e-3;
    bool capped = false;

    while (true) {
        progress.update(model.time());
        Candidate cand;
        Timer timer;
        const bool have = pick_candidate(model, cache, rng, cand);
        stats.stress_seconds += timer.seconds();
        if (have) {
            if (events.size() >= options.max_events) {
                capped = true;
                log::warn("fracture stopped at simulation.max_events = ", options.max_events, " (t = ", model.time(),
                          " of ", options.duration, ")");
                break;
            }
            const FaceId f = face_id(cand.face);
            Event ev;
            ev.time = model.time();
            ev.position = reference_centroid(model, f);
            ev.ratio = cand.ratio;
            std::vector<std::size_t> moved;
            timer.reset();
            if (options.min_element_size > 0 && model.element_size(f) > options.min_element_size) {
                // Alg. 8: too coarse to remove; refine here instead (Rivara, Alg. 9).
                const std::vector<FaceId> touched = model.subdivide(f);
                ev.kind = "subdivide";
                ++stats.subdivisions;
                cache.resize();
                stats.topology_seconds += timer.seconds();
                moved = relax_near(vertices_of(touched));
                timer.reset();
                for (FaceId t : touched)
                    cache.refresh(ix(t)); // new elements: σ and σ̇
            } else {
                model.remove_element(f);
                ev.kind = "remove";
                ++stats.removals;
                stats.topology_seconds += timer.seconds();
                moved = relax_near(vertices_of({f}));
                timer.reset();
                cache.refresh(cand.face);
            }
            cache.refresh_around(moved);
            stats.stress_seconds += timer.seconds();
            events.push_back(ev);
            if (options.after_event) options.after_event(model, ev);
            continue;
        }
        if (model.time() >= options.duration) break;

        settle_time_step(model, cache, options, local_options, rate_radius, rate_seeds, stats);

        // === Alg. 5: find the time of the next fracture
        timer.reset();
        const double t0 = model.time();
        const double horizon = std::min(options.duration, model.stiffness_horizon());
        // Earliest possible crossing per element, from λ_max(σ₀ + τσ̇) ≤ ‖σ₀‖ + τ‖σ̇‖: only
        // elements whose bound has passed need their eigenvalues checked.
        const std::vector<std::pair<double, std::size_t>> earliest = cache.earliest_crossings();
        auto any_over = [&](double t) {
            for (const auto& [bound, f] : earliest) {
                if (bound > t - t0) break;
                if (cache.ratio_at(f, t - t0) > 1.0) return true;
            }
            return false;
        };
        // Bracket: grow the step until some element is over threshold, or the horizon.
        double t_lo = t0, t_hi = t0, dt = std::max(last_step, dt_min);
        bool found = false;
        while (t_hi < horizon) {
            t_hi = std::min(t_lo + dt, horizon);
            if (any_over(t_hi)) {
                found = true;
                break;
            }
            t_lo = t_hi;
            dt *= 2.0;
        }
        if (found) {
            // Bisect over the elements over threshold at t_hi: the first crossing is among them
            // (each ratio is convex in t, so one below threshold at both ends stays below).
            std::vector<std::size_t> over;
            for (const auto& [bound, f] : earliest) {
                if (bound > t_hi - t0) break;
                if (cache.ratio_at(f, t_hi - t0) > 1.0) over.push_back(f);
            }
            while (t_hi - t_lo > dt_min) {
                const double mid = 0.5 * (t_lo + t_hi);
                bool any = false;
                for (std::size_t f : over)
                    any = any || cache.ratio_at(f, mid - t0) > 1.0;
                (any ? t_hi : t_lo) = mid;
            }
            last_step = std::max(t_hi - t0, dt_min);
        }
        stats.stress_seconds += timer.seconds();

        // Move along the exact affine solution; no solve unless shrinkage rebuilt the stiffness.
        advance_model(model, cache, t_hi, stats);
    }
    progress.finish();

    CrackPattern pattern = pattern_from_model(model, "fem-remove", elements_initial);
    pattern.events = std::move(events);
    pattern.events_capped = capped;
    stats.total_seconds = total.seconds();
    if (stats_out) *stats_out = stats;
    return pattern;
}

} // namespace crackle::fracture
