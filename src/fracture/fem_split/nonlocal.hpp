#pragma once
/// @file Private to fem_split/*.cpp: the stress a crack starts from, averaged over a physical length: an objective
/// initiation criterion for the FEM methods. The thesis compares each node's stress with the threshold (§5.7.1,
/// §5.7.3): the finer the mesh, the higher the peaks it resolves at crack tips, kinks and junctions (the stress there
/// is singular), so the pattern depends on the element size, not only on the physics. A crack must open through the
/// whole layer, so a peak narrower than the layer cannot start one by itself: the stress the criterion reads is the
/// mean of the top stress over a disc of radius R (m, `material.initiation_length`), weighted by the quartic bell w(r)
/// = (1 − r²/R²)² of integral-type nonlocal models (Pijaudier-Cabot & Bažant 1987; Bažant & Jirásek 2002), the critical
/// distance of Taylor's "theory of critical distances" (2007). Once the mesh resolves R the criterion converges to a
/// mesh-independent one.
///
/// Distances run along the surface and never across a crack, as the local relaxation's set does
/// (§5.8, Fig. 5.25): a Dijkstra walk over faces through intact edges, each step centroid → edge
/// midpoint → centroid measured in its own face, so periodic frames need no shifts. A face
/// counts with its area times the bell at its centroid's distance, and stands for its mean top
/// stress, turned with the surface from the face's normal to the node's (on a curved layer a
/// neighbour's hoop stress is tilted out of the node's tangent plane: averaged as it is, a
/// cylinder of radius 3 h would lose 1 % of it). Where R does not reach past a node's own faces (a mesh coarser than R)
/// the node keeps the thesis' average of its faces' nearest Gauss points.

#include "fracture/fem_split/splitter.hpp"

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace crackle::fracture::split_detail {

class NonlocalStress {
public:
    /// `radius(v)`: R at vertex v (m); ≤ 0 keeps the thesis' nodal average there. `intact(f, k)`:
    /// whether a walk may cross edge k of face f (fem-split's cracks are mesh borders already;
    /// graph-fem's broken edges are not).
    NonlocalStress(const sim::FemModel& model, std::function<double(std::size_t)> radius,
                   std::function<bool(std::size_t, int)> intact = {});

    /// Builds every vertex's neighbourhood.
    void rebuild_all();
    /// After these faces changed (topology, or their vertices moved): rebuilds the
    /// neighbourhoods that held them and those of their vertices; returns those vertices.
    std::vector<std::size_t> rebuild_around(const std::vector<mesh::FaceId>& faces);
    /// The vertices whose average reads face f (f's own vertices at least, once built).
    const std::vector<std::uint32_t>& readers(std::size_t f) const;
    /// Whether vertex v averages over R (else: the thesis' nodal average).
    bool averaged(std::size_t v) const { return v < m_hood.size() && !m_hood[v].empty(); }

    /// The averaged stress tensor at vertex v and the equally averaged threshold, toughness and
    /// Young's modulus, from a per-face top-stress source (3 points per face, as
    /// sim::TopStress). Returns false for a vertex with no alive element.
    template <class StressOf> bool tensor(std::size_t v, StressOf&& stress_of, Mat3& sigma, NodalStress& means) const {
        if (!averaged(v)) return nodal_tensor(m_model, v, stress_of, sigma, means);
        sim::wedge::Vec6 s = sim::wedge::Vec6::Zero();
        double thr = 0, kic = 0, young = 0;
        const bool curved = m_model.surface().kind() != mesh::SurfaceKind::Plane;
        for (const auto& [f, w] : m_hood[v]) {
            const auto& top = stress_of(f);
            const sim::wedge::Vec6 mean = (top[0] + top[1] + top[2]) / 3.0;
            s += w * (curved ? turned(f, v, mean) : mean);
            const sim::ElementMaterial& mat = m_model.material(mesh::face_id(f));
            thr += w * mat.threshold_stress;
            kic += w * mat.toughness;
            young += w * mat.young_modulus;
        }
        sigma = sim::wedge::tensor(s);
        means.threshold = thr;
        means.toughness = kic;
        means.young = young;
        return true;
    }

    /// The in-surface principal stress of the averaged tensor over the averaged threshold and the
    /// crack direction normal to it, as nodal_from.
    template <class StressOf> NodalStress nodal(std::size_t v, StressOf&& stress_of) const {
        NodalStress out;
        Mat3 sigma;
        if (!tensor(v, stress_of, sigma, out)) return out;
        return principal_of(m_model, v, sigma, out);
    }

private:
    /// A face's stress turned by the rotation that takes its normal to vertex v's.
    sim::wedge::Vec6 turned(std::size_t f, std::size_t v, const sim::wedge::Vec6& stress) const;
    void build(std::size_t v);
    void forget(std::size_t v);

    const sim::FemModel& m_model;
    std::function<double(std::size_t)> m_radius;
    std::function<bool(std::size_t, int)> m_intact;
    /// Per vertex: (face, weight), weights summing to 1; empty: the thesis' average.
    std::vector<std::vector<std::pair<std::uint32_t, double>>> m_hood;
    std::vector<std::vector<std::uint32_t>> m_readers; ///< per face: the vertices averaging it
    std::vector<std::uint32_t> m_stamp_of;
    std::uint32_t m_stamp = 0;
};

} // namespace crackle::fracture::split_detail
