#pragma once
/// @file Top-face stresses of every element of a wedge-FEM layer, cached and moved along the
/// affine-in-time solution (shared by the FEM fracture methods).

#include "core/parallel.hpp"
#include "core/timer.hpp"
#include "sim/fem_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace crackle::fracture {

/// Top-face stresses of every element, affine in time while the stiffness is fixed:
/// σ(t₀ + τ) = σ₀ + τ·σ̇. Keeps each element's ratio at the current time and the set of
/// over-threshold candidates, so an event costs work only where stresses changed.
class StressCache {
public:
    /// `ratios`: keep each element's ratio (fem-remove picks elements by it; fem-split, which
    /// works on nodes, does not need them).
    explicit StressCache(const sim::FemModel& model, bool ratios = true) : m_model(model), m_ratios(ratios) {}

    void resize() {
        const std::size_t n = m_model.mesh().num_faces();
        m_s0.resize(n);
        m_rate.resize(n);
        m_ratio.resize(n, 0.0);
    }

    void refresh(std::size_t f, bool rate = true) {
        m_changed.push_back(static_cast<std::uint32_t>(f));
        if (!m_model.alive(mesh::face_id(f))) {
            m_ratio[f] = 0.0;
            return;
        }
        m_s0[f] = m_model.top_stress(mesh::face_id(f));
        if (rate) m_rate[f] = m_model.top_stress_rate(mesh::face_id(f));
        if (m_ratios) m_ratio[f] = ratio_at(f, 0.0);
    }

    void refresh_rate(std::size_t f) {
        if (m_model.alive(mesh::face_id(f))) m_rate[f] = m_model.top_stress_rate(mesh::face_id(f));
    }

    void refresh_all() {
        m_all_changed = true;
        resize();
        // Every element's stress reads only its own nodes and writes only its own entries: on
        // all cores, with the same bits as one by one (a global clean-up's refresh was 9 % of mud).
        parallel_rows(static_cast<int>(m_s0.size()), [&](int row) {
            const auto f = static_cast<std::size_t>(row);
            if (!m_model.alive(mesh::face_id(f))) {
                m_ratio[f] = 0.0;
                return;
            }
            m_s0[f] = m_model.top_stress(mesh::face_id(f));
            m_rate[f] = m_model.top_stress_rate(mesh::face_id(f));
            if (m_ratios) m_ratio[f] = ratio_at(f, 0.0);
        });
        for (std::size_t f = 0; f < m_s0.size(); ++f)
            m_changed.push_back(static_cast<std::uint32_t>(f));
    }

    /// Re-evaluates the elements around the given vertices (§5.8.4: recompute stresses only
    /// where nodes moved), skipping those whose nodes moved too little to change their stress
    /// by 1e-7 of the threshold. `rates` re-evaluates σ̇ instead of σ.
    std::size_t refresh_around(const std::vector<std::size_t>& vertices, bool rates = false) {
        const auto& update = m_model.last_update();
        std::size_t count = 0;
        ++m_stamp;
        if (m_seen.size() < m_s0.size()) m_seen.resize(m_s0.size(), 0);
        for (std::size_t v : vertices) {
            for (std::uint32_t f : m_model.incident_faces(v)) {
                if (m_seen[f] == m_stamp || !m_model.alive(mesh::face_id(f))) continue;
                m_seen[f] = m_stamp;
                const mesh::Face& face = m_model.mesh().faces[mesh::face_id(f)];
                const double moved =
                    std::max({update[mesh::ix(face.v[0])], update[mesh::ix(face.v[1])], update[mesh::ix(face.v[2])]});
                const auto& mat = m_model.material(mesh::face_id(f));
                // A rate change is judged over the whole run (time scale 1).
                if (mat.young_modulus * moved < 1e-7 * mat.threshold_stress * m_model.element_size(mesh::face_id(f)))
                    continue;
                if (rates)
                    refresh_rate(f);
                else
                    refresh(f, false);
                ++count;
            }
        }
        return count;
    }

    /// Moves every cached stress forward by dt along its rate.
    void advance(double dt) {
        m_all_changed = true;
        for (std::size_t f = 0; f < m_s0.size(); ++f) {
            if (!m_model.alive(mesh::face_id(f))) continue;
            for (std::size_t k = 0; k < 3; ++k)
                m_s0[f][k] += dt * m_rate[f][k];
            if (m_ratios) m_ratio[f] = ratio_at(f, 0.0);
        }
    }

    /// Largest top principal stress over threshold, dt after the cache's time.
    double ratio_at(std::size_t f, double dt) const {
        double best = -std::numeric_limits<double>::infinity();
        for (std::size_t k = 0; k < 3; ++k) {
            const sim::wedge::Vec6 s = dt == 0.0 ? m_s0[f][k] : sim::wedge::Vec6(m_s0[f][k] + dt * m_rate[f][k]);
            best = std::max(best, sim::wedge::max_principal(s).value);
        }
        return best / m_model.material(mesh::face_id(f)).threshold_stress;
    }

    double ratio(std::size_t f) const { return m_ratio[f]; }
    const sim::TopStress& stress(std::size_t f) const { return m_s0[f]; }
    const sim::TopStress& rate(std::size_t f) const { return m_rate[f]; }
    /// (lower bound of the time until the element can reach its threshold, element), sorted.
    std::vector<std::pair<double, std::size_t>> earliest_crossings() const {
        auto frobenius = [](const sim::wedge::Vec6& v) {
            return std::sqrt(sqr(v[0]) + sqr(v[1]) + sqr(v[2]) + 2 * (sqr(v[3]) + sqr(v[4]) + sqr(v[5])));
        };
        std::vector<std::pair<double, std::size_t>> out;
        out.reserve(m_s0.size());
        for (std::size_t f = 0; f < m_s0.size(); ++f) {
            if (!m_model.alive(mesh::face_id(f))) continue;
            const double thr = m_model.material(mesh::face_id(f)).threshold_stress;
            double bound = std::numeric_limits<double>::infinity();
            for (std::size_t k = 0; k < 3; ++k) {
                const double s = frobenius(m_s0[f][k]), r = frobenius(m_rate[f][k]);
                if (s >= thr)
                    bound = 0.0;
                else if (r > 0)
                    bound = std::min(bound, (thr - s) / r);
            }
            if (std::isfinite(bound)) out.emplace_back(bound, f);
        }
        std::sort(out.begin(), out.end());
        return out;
    }
    std::size_t size() const { return m_s0.size(); }

    /// The faces whose stress (not rate) changed since the last call; true if all may have.
    bool take_changes(std::vector<std::uint32_t>& faces) {
        faces.swap(m_changed);
        m_changed.clear();
        const bool all = m_all_changed;
        m_all_changed = false;
        return all;
    }

private:
    const sim::FemModel& m_model;
    bool m_ratios = true;

    std::vector<sim::TopStress> m_s0, m_rate;
    std::vector<double> m_ratio;
    std::vector<std::uint32_t> m_seen;
    std::vector<std::uint32_t> m_changed;
    bool m_all_changed = true;
    std::uint32_t m_stamp = 0;
};

} // namespace crackle::fracture
