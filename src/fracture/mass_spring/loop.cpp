/// @file run_mass_spring: the break loop and its time search (Alg. 5); the pattern of Voronoi kites
/// it returns is made in kite_pattern.cpp (§4.4).
#include "core/progress.hpp"
#include "core/timer.hpp"
#include "fracture/mass_spring/mass_spring_internal.hpp"
#include "fracture/toolkit/pick.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::fracture {

using mesh::face_id;

namespace {

/// The break loop's model and options, and the counters every relaxation adds to.
struct BreakLoop {
    MassSpringModel& model;
    const FractureOptions& options;
    RunStats& run;
    MassSpringStats& stats;
    double dt_min; ///< the time search's resolution

    void relax() {
        Timer t;
        model.relax(&stats);
        run.solve_seconds += t.seconds();
        ++run.solves;
    }

    double max_ratio() const {
        double r = 0;
        for (std::size_t s = 0; s < model.springs().size(); ++s)
            r = std::max(r, model.ratio(s));
        return r;
    }

    /// The time of the next break (Alg. 5): predict it from the tangent-linear rates, solve
    /// there, and bisect if the prediction overshot.
    void advance_to_next_break() {
        const auto& springs = model.springs();
        Timer stress_timer;
        const std::vector<double> rates = model.ratio_rates();
        const double t0 = model.time();
        double step = options.duration - t0;
        for (std::size_t si = 0; si < springs.size(); ++si) {
            if (springs[si].broken || rates[si] <= 0) continue;
            step = std::min(step, (1.0 - model.ratio(si)) / rates[si]);
        }
        step = std::clamp(step, dt_min, std::max(dt_min, 0.25 * options.duration));
        run.stress_seconds += stress_timer.seconds();
        double t_hi = std::min(options.duration, t0 + step);
        // Anchors slide plastically (§4.1): a probe past the break must not leave its slides
        // behind, so every probe starts from the last state known to lie before the break.
        MassSpringModel::State below = model.state();
        model.set_time(t_hi);
        relax();
        ++stats.time_steps;
        ++run.time_steps;
        double r = max_ratio();
        if (r > 1.0 + 1e-6) {
            // Overshot: bisect between t0 (no break) and t_hi.
            double t_lo = t0;
            bool at_hi = true;
            while (t_hi - t_lo > dt_min && r > 1.0 + 1e-6) {
                const double mid = 0.5 * (t_lo + t_hi);
                model.restore(below);
                model.set_time(mid);
                relax();
                const double rm = max_ratio();
                if (rm > 1.0) {
                    t_hi = mid;
                    r = rm;
                    at_hi = true;
                } else {
                    t_lo = mid;
                    below = model.state();
                    at_hi = false;
                }
                ++stats.time_steps;
                ++run.time_steps;
            }
            if (!at_hi) {
                model.restore(below);
                model.set_time(t_hi);
                relax();
            }
        }
    }
};

} // namespace

CrackPattern run_mass_spring(MassSpringModel& model, const FractureOptions& options, Rng& rng, RunStats* run_out,
                             MassSpringStats* stats_out) {
    RunStats run;
    MassSpringStats stats;
    Timer total;
    EventLog events(options);
    BreakLoop loop{model, options, run, stats, options.time_tolerance * options.duration};
    loop.relax();
    FractureProgress progress(options.duration, model.mesh().num_faces());
    const auto& springs = model.springs();
    while (true) {
        progress.update(model.time(), events.size());
        double ratio = 0;
        std::size_t s = 0;
        // The spring most over its break strain, ties drawn from the seed.
        if (pick_most_over(
                springs.size(), [&](std::size_t i) { return model.ratio(i); },
                [&](std::size_t i) { return !springs[i].broken; }, rng, s, ratio)) {
            if (events.full(model.time())) break;
            const auto& sp = springs[s];
            Event ev;
            ev.time = model.time();
            const auto& mesh = model.mesh();
            const auto p = mesh.face_positions(face_id(sp.face));
            ev.position = 0.5 * (p[static_cast<std::size_t>(sp.edge)] + p[static_cast<std::size_t>((sp.edge + 1) % 3)]);
            ev.kind = "break";
            ev.ratio = ratio;
            model.break_spring(s);
            ++stats.breaks;
            loop.relax();
            events.add(ev);
            continue;
        }
        if (model.time() >= options.duration) break;
        loop.advance_to_next_break();
    }
    progress.finish();

    CrackPattern p = kite_pattern(model, stats);
    stats.factorizations = model.factorizations();
    stats.downdates = model.downdates();
    p.events_capped = events.capped();
    p.events = events.take();
    run.total_seconds = total.seconds();
    if (run_out) *run_out = run;
    if (stats_out) *stats_out = stats;
    return p;
}

} // namespace crackle::fracture
