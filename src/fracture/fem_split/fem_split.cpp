/// @file Element splitting's public functions: invariants, crack tips, nodal stress, run_fem_split (Federl 2002, §5.7).
#include "fracture/fem_split/fem_split.hpp"

#include "core/timer.hpp"
#include "fracture/fem_split/splitter.hpp"
#include "fracture/toolkit/fem_pattern.hpp"

#include <algorithm>
#include <array>
#include <map>
#include <sstream>

namespace crackle::fracture {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;
using mesh::vertex_id;
using mesh::VertexId;
using split_detail::corner_of;
using split_detail::is_tip;
using split_detail::nodal_from;
using split_detail::Splitter;

std::string check_split_invariants(const sim::FemModel& model) {
    const mesh::SurfaceMesh& m = model.mesh();
    std::string problem = m.validate();
    if (!problem.empty()) return problem;
    std::ostringstream os;
    for (std::size_t f = 0; f < m.num_faces(); ++f) {
        for (VertexId w : m.faces[face_id(f)].v) {
            const auto& list = model.incident_faces(ix(w));
            if (std::find(list.begin(), list.end(), static_cast<std::uint32_t>(f)) == list.end()) {
                os << "face " << f << " is missing from the incidence list of its vertex " << ix(w);
                return os.str();
            }
        }
        if (!model.alive(face_id(f))) continue;
        const auto p = m.face_positions(face_id(f));
        const Vec3 c = (p[0] + p[1] + p[2]) / 3.0;
        if ((p[1] - p[0]).cross(p[2] - p[0]).dot(model.surface().frame(c).n) <= 0) {
            os << "face " << f << " is inverted or degenerate at t = 0";
            return os.str();
        }
        if (!(sim::wedge::volume(model.reference_nodes(face_id(f))) > 0)) {
            os << "element " << f << " has a non-positive reference volume";
            return os.str();
        }
    }
    for (std::size_t v = 0; v < m.num_vertices(); ++v)
        for (std::uint32_t f : model.incident_faces(v))
            if (corner_of(m, f, v) < 0) {
                os << "vertex " << v << " lists face " << f << " which does not contain it";
                return os.str();
            }
    return {};
}

std::vector<std::size_t> crack_tips(const sim::FemModel& model) {
    std::vector<std::size_t> tips;
    for (std::size_t v = 0; v < model.mesh().num_vertices(); ++v)
        if (!model.incident_faces(v).empty() && is_tip(model, v)) tips.push_back(v);
    return tips;
}

NodalStress nodal_stress(const sim::FemModel& model, std::size_t vertex) {
    return nodal_from(model, vertex, [&](std::size_t f) { return model.top_stress(face_id(f)); });
}

CrackPattern run_fem_split(sim::FemModel& model, const FractureOptions& options, const SplitOptions& split, Rng& rng,
                           RunStats* stats_out, SplitStats* split_out) {
    RunStats stats;
    SplitStats counts;
    Timer total;
    const std::size_t elements_initial = model.num_alive();
    Splitter splitter(model, options, split, rng, stats, counts);
    EventLog& events = splitter.run();
    CrackPattern pattern = pattern_from_model(model, "fem-split", elements_initial);
    // Crack openings: the distance between the deformed midpoints of the two lips of an edge.
    std::map<std::array<double, 6>, std::vector<std::size_t>> lips;
    for (std::size_t i = 0; i < pattern.cracks.size(); ++i) {
        const CrackEdge& c = pattern.cracks[i];
        const mesh::Face& face = pattern.mesh.faces[c.face];
        Vec3 a = pattern.mesh.positions[face.v[static_cast<std::size_t>(c.edge)]];
        Vec3 b = pattern.mesh.positions[face.v[static_cast<std::size_t>((c.edge + 1) % 3)]];
        if (std::lexicographical_compare(b.data(), b.data() + 3, a.data(), a.data() + 3)) std::swap(a, b);
        lips[{a.x(), a.y(), a.z(), b.x(), b.y(), b.z()}].push_back(i);
    }
    for (const auto& [key, ids] : lips) {
        if (ids.size() != 2) continue;
        auto mid = [&](const CrackEdge& c) -> Vec3 {
            const Vec3 p = pattern.deformed_corner(c.face, c.edge);
            const Vec3 q = pattern.deformed_corner(c.face, (c.edge + 1) % 3);
            return 0.5 * (p + q);
        };
        // The two lips may sit in faces on opposite sides of a periodic border: the nearest image.
        const Vec3 d = mid(pattern.cracks[ids[0]]) - mid(pattern.cracks[ids[1]]);
        double w = d.norm();
        if (pattern.mesh.periodic)
            for (int i = -1; i <= 1; ++i)
                for (int j = -1; j <= 1; ++j)
                    w = std::min(w, (d + i * pattern.deformed_period[0] + j * pattern.deformed_period[1]).norm());
        pattern.cracks[ids[0]].opening = pattern.cracks[ids[1]].opening = w;
    }
    pattern.events_capped = events.capped();
    pattern.events = events.take();
    stats.total_seconds = total.seconds();
    if (stats_out) *stats_out = stats;
    if (split_out) *split_out = counts;
    return pattern;
}

} // namespace crackle::fracture
