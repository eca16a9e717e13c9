#include "app/run/report.hpp"

#include "fracture/statistics.hpp"
#include "io/resolution.hpp"

#include <cstdio>

#ifndef CRACKLE_VERSION
#define CRACKLE_VERSION "unknown"
#endif

namespace crackle::app {

namespace {

double mean_thickness(const fracture::CrackPattern& p) {
    double sum = 0;
    for (double h : p.thickness)
        sum += h;
    return p.thickness.empty() ? 0.0 : sum / double(p.thickness.size());
}

/// Metres the tile covers along u and v (the sphere: around the equator and pole to pole).
Json tile_size_m(const mesh::Surface& surface) {
    Json size = Json::array();
    size.push_back(surface.period().x());
    size.push_back(surface.period().y());
    return size;
}

} // namespace

const char* crackle_version() {
    return CRACKLE_VERSION;
}

std::string fmt(const char* format, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, v);
    return buf;
}

/// The report fields of design.md for a finished simulation, plus details.
Json simulation_report(const SimulationResult& r, const StepTimes& times) {
    const auto& st = r.statistics;
    Json report = Json::object();
    report["crackle_version"] = crackle_version();
    report["preset"] = r.plan.record.preset;
    report["surface"] = mesh::to_string(r.scene->surface.kind());
    report["method"] = r.pattern.method;
    report["seed"] = static_cast<long long>(r.scene->seed);
    report["elements_initial"] = r.elements_initial;
    if (r.plan.elements.automatic) report["elements_rule"] = "auto: " + r.plan.elements.reason;
    report["elements_final"] = r.elements_final;
    report["nodes"] = r.nodes;
    report["fracture_events"] = r.pattern.events.size();
    report["fragments"] = st.fragments;
    report["mean_fragment_area"] = st.mean_fragment_area;
    report["crack_length_per_area"] = st.crack_length_per_area;
    report["anisotropy"] = st.anisotropy;
    report["dominant_angle_deg"] = st.dominant_angle_deg;
    report["psi6"] = st.psi6;
    report["t_junction_fraction"] = st.t_junction_fraction;
    report["y_junction_fraction"] = st.y_junction_fraction;
    report["min_angle_deg"] = st.min_angle_deg;
    Json wall = Json::object();
    for (const auto& [name, seconds] : times)
        wall[name] = seconds;
    report["wall_seconds"] = wall;
    report["peak_memory_mb"] = peak_memory_mb();
    // Beyond the fixed fields: details for researchers.
    report["pattern_source"] = r.pattern_source;
    report["tile_size_m"] = tile_size_m(r.pattern.surface);
    report["final_time"] = r.pattern.final_time;
    report["events_capped"] = r.pattern.events_capped;
    // The method's own counters (fracture::MethodResult::details), then the common ones.
    for (const auto& [key, value] : r.details.members())
        report[key] = value;
    report["time_steps"] = r.run.time_steps;
    report["solves"] = r.run.solves;
    report["solver_iterations"] = r.run.solver_iterations;
    report["local_solves"] = r.run.local_solves;
    report["local_mean_nodes"] = r.run.local_solves ? double(r.run.local_nodes) / double(r.run.local_solves) : 0.0;
    report["local_fallbacks"] = r.run.local_fallbacks;
    report["global_cleanups"] = r.run.global_cleanups;
    report["local_cleanups"] = r.run.local_cleanups;
    report["drift_relaxations"] = r.run.drift_relaxations;
    report["stiffness_rebuilds"] = r.run.stiffness_rebuilds;
    report["crack_length"] = st.crack_length;
    report["junctions"] = st.junctions;
    report["axial_fraction"] = st.axial_fraction;
    report["total_area"] = st.total_area;
    // Shape statistics of the speed-vs-accuracy study (docs/benchmarks.md): crack chains shorter
    // than two layer thicknesses are straight by construction and left out of the tortuosity.
    report["fragment_area_cv"] = st.fragment_area_cv;
    report["tortuosity"] = fracture::crack_path_statistics(r.pattern, 2.0 * mean_thickness(r.pattern)).tortuosity;
    double first = -1;
    for (const auto& e : r.pattern.events)
        if (first < 0 || e.time < first) first = e.time;
    report["first_event_time"] = first;          // −1 when nothing broke
    report["settings"] = r.plan.record.settings; // the plan: every key as the run resolved it
    return report;
}

void print_times(std::ostream& out, const StepTimes& times) {
    out << "  wall time   ";
    for (const auto& [name, seconds] : times)
        out << " " << name << " " << fmt("%.3f", seconds) << " s;";
    out << "\n  peak memory  " << fmt("%.1f", peak_memory_mb()) << " MiB\n";
}

void print_simulation(std::ostream& out, const SimulationResult& r) {
    const auto& st = r.statistics;
    out << "  " << r.summary << "\n";
    out << "  time         " << fmt("%.4g", r.pattern.final_time) << " of " << fmt("%.4g", r.plan.fracture.duration)
        << (r.pattern.events_capped ? " (stopped at simulation.max_events)" : "") << "; " << r.run.time_steps
        << " time steps, " << r.run.solves << " solves\n";
    out << "  fragments    " << st.fragments << ", mean area " << fmt("%.4g", st.mean_fragment_area * 1e4) << " cm2\n";
    out << "  cracks       " << fmt("%.4g", st.crack_length_per_area) << " m/m2, anisotropy "
        << fmt("%.3f", st.anisotropy) << " at " << fmt("%.1f", st.dominant_angle_deg) << " deg, psi6 "
        << fmt("%.3f", st.psi6) << "\n";
    out << "  junctions    " << st.junctions << " (T " << fmt("%.2f", st.t_junction_fraction) << ", Y "
        << fmt("%.2f", st.y_junction_fraction) << ")\n";
}

} // namespace crackle::app
