/// @file fem-split's refinement: bisection near nodes (§5.7.6), von Mises indicator (§5.7.7), tip sub-models (§5.7.8).
#include "core/timer.hpp"
#include "fracture/fem_split/splitter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace crackle::fracture::split_detail {

std::vector<FaceId> Splitter::subdivide_around(std::size_t v, double size, std::size_t* calls) {
    std::vector<FaceId> touched;
    m_model.defer_updates(); // K's rows once, at the end
    for (int round = 0; round < 64; ++round) {
        // The vicinity: v's faces and every face sharing a vertex with them; the longest alive
        // one over `size`, the lowest index among equals (faces met more than once compare
        // equal to themselves: no sort needed, and a sub-model runs many rounds).
        constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
        std::uint32_t coarse = none;
        double longest = size;
        for (std::uint32_t f : m_model.incident_faces(v))
            for (VertexId w : m_model.mesh().faces[face_id(f)].v)
                for (std::uint32_t g : m_model.incident_faces(ix(w))) {
                    if (!m_model.alive(face_id(g))) continue;
                    const double length = m_model.element_size(face_id(g));
                    if (length > longest || (coarse != none && length == longest && g < coarse)) {
                        longest = length;
                        coarse = g;
                    }
                }
        if (coarse == none) break;
        const std::vector<FaceId> faces = m_model.subdivide(face_id(coarse));
        touched.insert(touched.end(), faces.begin(), faces.end());
        if (calls) ++*calls;
    }
    m_model.flush_updates();
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    return touched;
}

bool Splitter::refine_vicinity(std::size_t v) {
    if (m_options.min_element_size <= 0) return false;
    Timer timer;
    const std::vector<FaceId> touched = subdivide_around(v, m_options.min_element_size, &m_counts.subdivisions);
    m_stats.topology_seconds += timer.seconds();
    if (touched.empty()) return false;
    m_cache.resize();
    for (FaceId f : touched)
        m_cache.refresh(ix(f)); // new elements need σ̇ too
    refresh_after(touched, relax_near(touched));
    return true;
}

bool Splitter::submodel_direction(std::size_t tip, Vec3& crack) {
    if (m_split.tip_submodel_levels <= 0) return false;
    Timer timer;
    double size = INFINITY;
    for (std::uint32_t f : m_model.incident_faces(tip))
        size = std::min(size, m_model.element_size(face_id(f)));
    size /= std::pow(2.0, m_split.tip_submodel_levels);
    // A trial: the finer elements, and the solution on them, are gone afterwards (§5.7.8).
    m_model.begin_trial(/*stiffness_only=*/true);
    const std::vector<FaceId> touched = subdivide_around(tip, size);
    bool found = false;
    if (!touched.empty()) {
        std::vector<std::size_t> seeds;
        for (FaceId f : touched)
            for (VertexId w : m_model.mesh().faces[f].v)
                seeds.push_back(ix(w));
        std::sort(seeds.begin(), seeds.end());
        seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
        // Nodes outside the relaxed set stay where they are: the sub-model's fixed boundary.
        double radius = m_radius;
        m_model.relax_local(seeds, radius, m_local);
        const NodalStress fine = nodal_stress(m_model, tip);
        if (fine.threshold > 0) {
            crack = fine.crack;
            found = true;
        }
    }
    m_model.rollback();
    ++m_counts.submodels;
    m_stats.stress_seconds += timer.seconds();
    return found;
}

void Splitter::refine_by_von_mises() {
    if (m_split.vm_threshold <= 0 || m_options.min_element_size <= 0) return;
    Timer timer;
    const mesh::SurfaceMesh& m = m_model.mesh();
    auto von_mises = [](const sim::wedge::Vec6& s) {
        return std::sqrt(0.5 * (sqr(s[0] - s[1]) + sqr(s[1] - s[2]) + sqr(s[2] - s[0]))
                         + 3.0 * (sqr(s[3]) + sqr(s[4]) + sqr(s[5])));
    };
    double max_eig = 0;
    for (std::size_t f = 0; f < m.num_faces(); ++f)
        for (const sim::wedge::Vec6& s : m_cache.stress(f))
            max_eig = std::max(max_eig, std::abs(sim::wedge::max_principal(s).value));
    if (max_eig <= 0) return;
    std::vector<std::uint32_t> marked;
    for (std::size_t v = 0; v < m.num_vertices(); ++v) {
        double lo = INFINITY, hi = -INFINITY;
        for (std::uint32_t f : m_model.incident_faces(v)) {
            const double vm = von_mises(m_cache.stress(f)[static_cast<std::size_t>(corner_of(m, f, v))]);
            lo = std::min(lo, vm);
            hi = std::max(hi, vm);
        }
        if (hi - lo > m_split.vm_threshold * max_eig)
            for (std::uint32_t f : m_model.incident_faces(v))
                if (m_model.element_size(face_id(f)) > m_options.min_element_size) marked.push_back(f);
    }
    std::sort(marked.begin(), marked.end());
    marked.erase(std::unique(marked.begin(), marked.end()), marked.end());
    // Longest first, and each only if an earlier bisection has not already made it small.
    std::sort(marked.begin(), marked.end(), [&](std::uint32_t a, std::uint32_t b) {
        return m_model.element_size(face_id(a)) > m_model.element_size(face_id(b));
    });
    std::vector<FaceId> touched;
    for (std::uint32_t f : marked) {
        if (m_model.element_size(face_id(f)) <= m_options.min_element_size) continue;
        const std::vector<FaceId> faces = m_model.subdivide(face_id(f));
        touched.insert(touched.end(), faces.begin(), faces.end());
        ++m_counts.subdivisions;
        ++m_counts.vm_refinements;
    }
    m_stats.topology_seconds += timer.seconds();
    if (touched.empty()) return;
    std::sort(touched.begin(), touched.end());
    touched.erase(std::unique(touched.begin(), touched.end()), touched.end());
    m_cache.resize();
    for (FaceId f : touched)
        m_cache.refresh(ix(f));
    refresh_after(touched, relax_near(touched));
}

} // namespace crackle::fracture::split_detail
