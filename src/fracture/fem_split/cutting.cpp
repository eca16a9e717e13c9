/// @file fem-split's cuts: cut_towards, opening edges, new fractures, Griffith tip extension (§5.7.2–5.7.5, Alg. 11).
#include "core/timer.hpp"
#include "fracture/fem_split/splitter.hpp"

#include <algorithm>
#include <cmath>

namespace crackle::fracture::split_detail {

Splitter::CutEnd Splitter::cut_towards(std::size_t v, const Vec3& direction, std::vector<FaceId>& touched) {
    CutEnd end;
    RayHit hit;
    if (!cast_ray(m_model, v, direction, hit)) return end;
    const mesh::SurfaceMesh& m = m_model.mesh();
    const FaceId f = face_id(hit.face);
    const int kb = hit.edge, kc = (hit.edge + 1) % 3, kv = (hit.edge + 2) % 3;
    const std::size_t b = ix(m.faces[f].v[static_cast<std::size_t>(kb)]);
    const std::size_t c = ix(m.faces[f].v[static_cast<std::size_t>(kc)]);
    // A point of a face's edge where a topology change puts it: on the surface, in the face's
    // frame (on a curved surface the chord runs inside it by up to a sagitta, which next to a
    // thin triangle can fold it).
    const mesh::Surface& surface = m_model.surface();
    auto on_surface = [&](FaceId g, int ka, int kb2, double t) -> Vec3 {
        if (m.periodic) return surface.position((1 - t) * m.corner_domain(g, ka) + t * m.corner_domain(g, kb2));
        return surface.project((1 - t) * m.corner_position(g, ka) + t * m.corner_position(g, kb2));
    };
    // Would the split leave slivers? Check the four new triangles at t = 0.
    const Vec3 V = m.corner_position(f, kv), B = m.corner_position(f, kb), C = m.corner_position(f, kc);
    const Vec3 P = on_surface(f, kb, kc, hit.t);
    double worst = std::min(min_angle(V, B, P), min_angle(V, P, C));
    const mesh::FaceNeighbor nb = m.neighbor(f, hit.edge);
    if (nb.face != mesh::NO_FACE) {
        const Vec3 W = m.corner_position(nb.face, (nb.edge + 2) % 3);
        const Vec3 Bn = m.corner_position(nb.face, (nb.edge + 1) % 3), Cn = m.corner_position(nb.face, nb.edge);
        const Vec3 Pn = on_surface(nb.face, (nb.edge + 1) % 3, nb.edge, hit.t);
        worst = std::min({worst, min_angle(W, Bn, Pn), min_angle(W, Pn, Cn)});
    }
    const bool near_vertex = hit.t < m_split.snap_fraction || hit.t > 1 - m_split.snap_fraction;
    if (!near_vertex && worst >= m_split.min_angle_deg) {
        const auto [nv, faces] = m_model.split_edge(f, hit.edge, hit.t);
        touched.insert(touched.end(), faces.begin(), faces.end());
        end.vertex = ix(nv);
        end.ok = true;
        return end;
    }
    // Edge collapse seen from the survivor (§5.7.5): move the nearer vertex onto the plane if it
    // is free (not on a crack) and its elements stay well shaped; else cut through it as it is.
    const bool to_b = hit.t < 0.5;
    const std::size_t x = to_b ? b : c;
    if (!on_border(m_model, x)) {
        Vec3 top, rate;
        const mesh::NewVertex target = m_model.edge_point(f, hit.edge, hit.t, &top, &rate);
        // Where x lands, seen from each of its faces (move_vertex moves it by the same step in
        // every face's frame): each face must stay well shaped and facing out of the surface.
        Vec2 step = Vec2::Zero();
        if (m.periodic) {
            step = target.domain - m.domain[vertex_id(x)];
            for (int i = 0; i < 2; ++i)
                step[i] -= m.period[i] * std::round(step[i] / m.period[i]);
        }
        bool fine = true;
        for (std::uint32_t g : m_model.incident_faces(x)) {
            const int kx = corner_of(m, g, x);
            std::array<Vec3, 3> q;
            for (int k = 0; k < 3; ++k)
                q[static_cast<std::size_t>(k)] = m.corner_position(face_id(g), k);
            q[static_cast<std::size_t>(kx)] =
                m.periodic ? surface.position(m.corner_domain(face_id(g), kx) + step) : target.position;
            const Vec3 n_after = (q[1] - q[0]).cross(q[2] - q[0]);
            const Vec3 outward = surface.frame(Vec3((q[0] + q[1] + q[2]) / 3.0)).n;
            if (n_after.normalized().dot(outward) < 0.5 || min_angle(q[0], q[1], q[2]) < 0.5 * m_split.min_angle_deg) {
                fine = false;
                break;
            }
        }
        if (fine) {
            m_model.move_vertex(vertex_id(x), target, top, rate);
            for (std::uint32_t g : m_model.incident_faces(x))
                touched.push_back(face_id(g));
            ++m_counts.collapses;
            end.vertex = x;
            end.ok = true;
            return end;
        }
    }
    ++m_counts.snaps;
    end.vertex = x;
    end.ok = true;
    return end;
}

bool Splitter::open_edges(const std::vector<std::pair<std::size_t, std::size_t>>& edges, std::vector<FaceId>& touched) {
    const mesh::SurfaceMesh& m = m_model.mesh();
    std::vector<std::pair<FaceId, int>> sides;
    for (const auto& [a, b] : edges)
        for (std::uint32_t f : m_model.incident_faces(a)) {
            const mesh::Face& face = m.faces[face_id(f)];
            for (int k = 0; k < 3; ++k) {
                const std::size_t p = ix(face.v[static_cast<std::size_t>(k)]);
                const std::size_t q = ix(face.v[static_cast<std::size_t>((k + 1) % 3)]);
                if ((p == a && q == b) || (p == b && q == a)) {
                    sides.emplace_back(face_id(f), k);
                    touched.push_back(face_id(f));
                }
            }
        }
    const auto copies = m_model.cut(sides);
    // Faces moved onto new copies changed their nodes: refresh them too.
    for (const auto& [copy, origin] : copies)
        for (std::uint32_t f : m_model.incident_faces(ix(copy)))
            touched.push_back(face_id(f));
    return !copies.empty();
}

Splitter::Start Splitter::start_fracture(std::size_t v, double ratio, Event& ev) {
    // Fine elements around the node first (§5.7.6); its stress is then looked at again.
    if (refine_vicinity(v)) return Start::Refined;
    Timer timer;
    const NodalStress ns = node_stress(v);
    std::vector<FaceId> touched;
    const Vec3 p0 = m_model.mesh().positions[vertex_id(v)];
    // Both ways from the node (§5.7.2): two straddling elements, two new tips.
    std::vector<std::pair<std::size_t, std::size_t>> edges;
    std::vector<std::size_t> ends;
    for (double sign : {1.0, -1.0}) {
        const CutEnd e = cut_towards(v, sign * ns.crack, touched);
        if (e.ok && e.vertex != v) {
            edges.emplace_back(v, e.vertex);
            ends.push_back(e.vertex);
        }
    }
    if (edges.empty() || !open_edges(edges, touched)) {
        // Nothing opened: refresh what the cutting changed; the caller fences the node off.
        m_stats.topology_seconds += timer.seconds();
        refresh_after(touched, relax_near(touched));
        return Start::Blocked;
    }
    m_stats.topology_seconds += timer.seconds();
    const std::vector<FaceId> flipped = flip_slivers(touched);
    touched.insert(touched.end(), flipped.begin(), flipped.end());
    const std::vector<std::size_t> moved = relax_near(touched);
    refresh_after(touched, moved);
    for (std::size_t e : ends)
        if (is_tip(m_model, e)) {
            m_tips.push_back(e);
            // The nucleus (nonlocal.hpp): a crack starts as long as the stress was averaged over;
            // until each arm is half that long its tips extend without the energy test.
            if (m_nonlocal) {
                const double arm = m_model.mesh().nearest_step(p0, m_model.mesh().positions[vertex_id(e)]).norm();
                const double rest = 0.5 * nucleus_length(v) - arm;
                if (rest > 0) m_nucleus[e] = rest;
            }
            smooth_near(e);
        }
    ev.time = m_model.time();
    ev.position = p0;
    ev.kind = "split";
    ev.ratio = ratio;
    ++m_counts.splits;
    return Start::Opened;
}

bool Splitter::extend_tip(std::size_t tip, Event& ev) {
    if (tip >= m_model.mesh().num_vertices() || !is_tip(m_model, tip)) return false;
    if (refine_vicinity(tip)) {
        m_tips.push_front(tip); // look again, on the finer mesh
        return false;
    }
    const NodalStress ns = node_stress(tip);
    if (ns.threshold <= 0) return false;
    // A nucleus still shorter than its length grows on without the tests below.
    double nucleus = 0;
    if (const auto it = m_nucleus.find(tip); it != m_nucleus.end()) {
        nucleus = it->second;
        m_nucleus.erase(it);
    }
    if (!m_split.griffith && ns.ratio < 1.0 && nucleus <= 0) {
        // Without Griffith's test a tip runs on its stress alone: below threshold it waits for
        // the load to rise, and Alg. 5's time step ends when it crosses (advance_time()).
        m_dormant.push_back(tip);
        return false;
    }
    // Onwards: away from the crack behind the tip (its lips' far ends).
    const mesh::SurfaceMesh& m = m_model.mesh();
    Vec3 behind = Vec3::Zero();
    for (std::uint32_t f : m_model.incident_faces(tip)) {
        const int k = corner_of(m, f, tip);
        if (m.neighbor(face_id(f), k).face == mesh::NO_FACE)
            behind = m.corner_position(face_id(f), (k + 1) % 3) - m.corner_position(face_id(f), k);
    }
    Vec3 dir = ns.crack;
    submodel_direction(tip, dir); // keeps ns.crack when off
    if (dir.dot(behind) > 0) dir = -dir;

    Timer timer;
    // A trial, so a rejected extension rolls back exactly (digest §3.9.4 caveat 2). The stress
    // cache is refreshed only once an extension is accepted, so it needs no undo.
    const bool trial = m_split.griffith && nucleus <= 0;
    if (trial) m_model.begin_trial();
    m_in_trial = trial;
    // What a rolled-back cut counted is not kept.
    const std::size_t collapses = m_counts.collapses, snaps = m_counts.snaps;
    auto roll_back = [&] {
        m_model.rollback();
        m_counts.collapses = collapses;
        m_counts.snaps = snaps;
    };
    std::vector<FaceId> touched;
    const CutEnd end = cut_towards(tip, dir, touched);
    if (!end.ok || end.vertex == tip) {
        m_in_trial = false;
        if (trial)
            roll_back();
        else if (!touched.empty())
            refresh_after(touched, relax_near(touched));
        return false;
    }
    // The step measured the short way: across a periodic seam the two nodes' own positions lie a
    // period apart, which made the new wall ~50 steps long and arrested every tip at the seams.
    const double step = m_model.bottom_step(vertex_id(tip), vertex_id(end.vertex)).norm();
    const double area =
        step * 0.5 * (m_model.vertex_thickness(vertex_id(tip)) + m_model.vertex_thickness(vertex_id(end.vertex)));
    const bool opened = open_edges({{tip, end.vertex}}, touched);
    m_stats.topology_seconds += timer.seconds();
    if (!opened) {
        // The cut ran along an edge that was already cracked: the tip has nowhere to go.
        m_in_trial = false;
        if (trial)
            roll_back();
        else
            refresh_after(touched, relax_near(touched));
        return false;
    }
    double released = 0;
    std::vector<std::size_t> moved = relax_near(touched, &released);
    m_in_trial = false;

    if (trial) {
        // Alg. 11 with the physical ½F·u (digest caveat 1): cutting at fixed positions keeps
        // the strain energy (a duplicated node; a node split into an edge at its rest position
        // plus the interpolated displacement, which on a curved surface releases next to nothing
        // itself: < 3 % of a cut's release on coarse meshes, less on fine ones), so what the cut
        // releases is what the relaxation after it releases, ½ rᵀΔx, exact for the linear
        // solves and local to the change (tests compare it with the energy sums).
        timer.reset();
        const double G = released / std::max(area, 1e-300);
        const double nu = m_model.poisson_ratio();
        const double G_ic = (1 - nu * nu) * sqr(ns.toughness) / ns.young;
        m_stats.stress_seconds += timer.seconds();
        if (!(G > G_ic)) {
            roll_back();
            m_zones.push_back(m_model.mesh().positions[vertex_id(tip)]);
            ++m_counts.arrests;
            Event arrest;
            arrest.time = m_model.time();
            arrest.position = m_zones.back();
            arrest.kind = "arrest";
            arrest.ratio = ns.ratio;
            m_counts.arrests_at.push_back(arrest);
            return false;
        }
    }
    if (trial) {
        m_model.commit();
        if (check_drift(m_model, m_options, m_radius, m_stats)) moved = m_model.last_updated_vertices();
    }
    refresh_after(touched, moved);
    // After the energy test: flips change the discrete energy at fixed nodes.
    const std::vector<FaceId> flipped = flip_slivers(touched);
    if (!flipped.empty()) refresh_after(flipped, relax_near(flipped));
    if (is_tip(m_model, end.vertex)) {
        m_tips.push_back(end.vertex);
        if (nucleus - step > 0) m_nucleus[end.vertex] = nucleus - step;
        smooth_near(end.vertex);
    }
    ev.time = m_model.time();
    ev.position = m_model.mesh().positions[vertex_id(end.vertex)];
    ev.kind = "extend";
    ev.ratio = ns.ratio;
    ++m_counts.extensions;
    return true;
}

} // namespace crackle::fracture::split_detail
