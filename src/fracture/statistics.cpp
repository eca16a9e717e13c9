#include "fracture/statistics.hpp"

#include "fracture/hanging_splits.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <map>
#include <set>

namespace crackle::fracture {

using mesh::face_id;
using mesh::FaceId;
using mesh::ix;

namespace {

/// Local 2D coordinates of a face corner in the reference configuration.
Vec2 corner_2d(const CrackPattern& p, FaceId f, int k, const Vec3& origin, const mesh::TangentFrame& frame) {
    if (p.surface.periodic()) return p.mesh.corner_domain(f, k);
    const Vec3 d = p.mesh.corner_position(f, k) - origin;
    return Vec2(d.dot(frame.e_u), d.dot(frame.e_v));
}

Vec2 face_centroid_2d(const CrackPattern& p, FaceId f) {
    if (p.surface.periodic())
        return (p.mesh.corner_domain(f, 0) + p.mesh.corner_domain(f, 1) + p.mesh.corner_domain(f, 2)) / 3.0;
    return Vec2::Zero(); // sphere: handled with 3D positions
}

/// The crack network as a graph for junction statistics: removed faces linked to removed
/// neighbours (element removal), or crack vertices linked along crack edges (splitting).
struct SkeletonGraph {
    std::vector<std::vector<std::uint32_t>> adjacency;
    std::vector<Vec3> position; // 3D reference position (sphere) or (x, y, 0) domain position
};

SkeletonGraph removal_skeleton(const CrackPattern& p) {
    SkeletonGraph g;
    const std::size_t nf = p.mesh.num_faces();
    std::vector<std::int64_t> node_of(nf, -1);
    for (std::size_t f = 0; f < nf; ++f) {
        if (!p.removed[f]) continue;
        node_of[f] = static_cast<std::int64_t>(g.position.size());
        const auto pts = p.mesh.face_positions(face_id(f));
        if (p.surface.periodic()) {
            const Vec2 c = face_centroid_2d(p, face_id(f));
            g.position.emplace_back(c.x(), c.y(), 0.0);
        } else {
            g.position.push_back((pts[0] + pts[1] + pts[2]) / 3.0);
        }
    }
    g.adjacency.resize(g.position.size());
    for (std::size_t f = 0; f < nf; ++f) {
        if (node_of[f] < 0) continue;
        for (int k = 0; k < 3; ++k) {
            const mesh::FaceNeighbor nb = p.mesh.neighbor(face_id(f), k);
            if (nb.face == mesh::NO_FACE || node_of[ix(nb.face)] < 0) continue;
            g.adjacency[static_cast<std::size_t>(node_of[f])].push_back(
                static_cast<std::uint32_t>(node_of[ix(nb.face)]));
        }
    }
    return g;
}

/// Crack vertices (copies of one reference point merged) linked along crack edges, for
/// patterns whose cracks are edges rather than removed elements (springs, splitting); a crack
/// edge split on one side only is its finer path (fracture/hanging_splits.hpp).
SkeletonGraph crack_skeleton(const CrackPattern& p) {
    SkeletonGraph g;
    std::map<std::array<double, 3>, std::uint32_t> node_of;
    auto node = [&](mesh::VertexId v) {
        const Vec3 key3 =
            p.surface.periodic() ? Vec3(p.mesh.domain[v].x(), p.mesh.domain[v].y(), 0.0) : p.mesh.positions[v];
        const std::array<double, 3> key{key3.x(), key3.y(), key3.z()};
        const auto [it, inserted] = node_of.emplace(key, static_cast<std::uint32_t>(g.position.size()));
        if (inserted) {
            g.position.push_back(key3);
            g.adjacency.emplace_back();
        }
        return it->second;
    };
    std::map<NodePair, int> lips; // per crack link: its lips (two, one where the other side is split)
    for (const CrackEdge& c : p.cracks) {
        const auto& face = p.mesh.faces[c.face];
        const std::uint32_t a = node(face.v[static_cast<std::size_t>(c.edge)]);
        const std::uint32_t b = node(face.v[static_cast<std::size_t>((c.edge + 1) % 3)]);
        if (a != b) ++lips[std::minmax(a, b)];
    }
    // A link split at hanging nodes on its other side is the same crack as the finer path:
    // keeping both would make a triangle and two spurious junctions.
    std::vector<NodePair> single;
    for (const auto& [key, count] : lips)
        if (count == 1) single.push_back(key);
    const Vec2 period = p.surface.periodic() ? p.mesh.period : Vec2::Zero();
    std::set<NodePair> coarse;
    for (const HangingSplit& split : hanging_splits(single, g.position, period))
        coarse.insert(split.coarse);
    for (const auto& [key, count] : lips) {
        if (coarse.count(key)) continue;
        g.adjacency[key.first].push_back(key.second);
        g.adjacency[key.second].push_back(key.first);
    }
    return g;
}

/// Difference b − a in the local frame at a, with the minimum image on periodic domains.
Vec2 local_difference(const CrackPattern& p, const Vec3& a, const Vec3& b) {
    if (p.surface.periodic()) {
        Vec2 d(b.x() - a.x(), b.y() - a.y());
        const Vec2 L = p.mesh.period;
        d.x() -= L.x() * std::round(d.x() / L.x());
        d.y() -= L.y() * std::round(d.y() / L.y());
        return d;
    }
    const mesh::TangentFrame fr = p.surface.frame(a);
    const Vec3 d = b - a;
    return Vec2(d.dot(fr.e_u), d.dot(fr.e_v));
}

struct JunctionCounts {
    int total = 0, t = 0, y = 0;
};

JunctionCounts junction_counts(const CrackPattern& p, const SkeletonGraph& g) {
    constexpr int BRANCH_STEPS = 2; // ≈ two element lengths (digest §7.1)
    JunctionCounts counts;
    for (std::size_t j = 0; j < g.adjacency.size(); ++j) {
        if (g.adjacency[j].size() != 3) continue;
        std::array<double, 3> angle{};
        for (std::size_t b = 0; b < 3; ++b) {
            std::uint32_t prev = static_cast<std::uint32_t>(j), cur = g.adjacency[j][b];
            for (int s = 1; s < BRANCH_STEPS && g.adjacency[cur].size() == 2; ++s) {
                const std::uint32_t next = g.adjacency[cur][0] == prev ? g.adjacency[cur][1] : g.adjacency[cur][0];
                prev = cur;
                cur = next;
            }
            const Vec2 d = local_difference(p, g.position[j], g.position[cur]);
            angle[b] = std::atan2(d.y(), d.x());
        }
        std::sort(angle.begin(), angle.end());
        const double a1 = (angle[1] - angle[0]) * RAD_TO_DEG, a2 = (angle[2] - angle[1]) * RAD_TO_DEG;
        const double a3 = 360.0 - a1 - a2;
        ++counts.total;
        switch (classify_junction(a1, a2, a3)) {
        case JunctionKind::T:
            ++counts.t;
            break;
        case JunctionKind::Y:
            ++counts.y;
            break;
        case JunctionKind::Other:
            break;
        }
    }
    return counts;
}

} // namespace

JunctionKind classify_junction(double a, double b, double c) {
    const double largest = std::max({a, b, c}), smallest = std::min({a, b, c});
    if (largest >= 155.0) return JunctionKind::T;
    if (largest <= 145.0 && smallest >= 95.0) return JunctionKind::Y;
    return JunctionKind::Other;
}

std::vector<CrackSegment> crack_segments(const CrackPattern& p) {
    // One segment per crack lip (each crack has two: weight ½).
    std::vector<CrackSegment> segments;
    segments.reserve(p.cracks.size());
    for (const CrackEdge& c : p.cracks) {
        const FaceId f = c.face;
        const int k = c.edge;
        CrackSegment s;
        const Vec3 mid3 = 0.5 * (p.mesh.corner_position(f, k) + p.mesh.corner_position(f, (k + 1) % 3));
        const mesh::TangentFrame frame = p.surface.periodic() ? mesh::TangentFrame{} : p.surface.frame(mid3);
        s.a = corner_2d(p, f, k, mid3, frame);
        s.b = corner_2d(p, f, (k + 1) % 3, mid3, frame);
        s.weight = 0.5;
        if (p.surface.periodic()) {
            const Vec2 m = 0.5 * (s.a + s.b);
            s.uv = Vec2(wrap(m.x() / p.mesh.period.x(), 1.0), wrap(m.y() / p.mesh.period.y(), 1.0));
        } else {
            s.uv = p.surface.uv(p.surface.project(mid3));
        }
        segments.push_back(s);
    }
    return segments;
}

PatternStatistics pattern_statistics(const CrackPattern& p) {
    PatternStatistics st;
    st.fragments = p.num_fragments;
    double intact_area = 0;
    st.min_angle_deg = 180.0;
    std::vector<double> fragment_area(static_cast<std::size_t>(std::max(p.num_fragments, 0)), 0.0);
    for (std::size_t f = 0; f < p.mesh.num_faces(); ++f) {
        const double a = p.mesh.face_area(face_id(f));
        st.total_area += a;
        if (p.removed[f]) continue;
        intact_area += a;
        if (f < p.fragment.size() && p.fragment[f] >= 0 && p.fragment[f] < p.num_fragments)
            fragment_area[static_cast<std::size_t>(p.fragment[f])] += a;
        const auto ang = p.mesh.face_angles(face_id(f));
        st.min_angle_deg = std::min(st.min_angle_deg, *std::min_element(ang.begin(), ang.end()) * RAD_TO_DEG);
    }
    st.mean_fragment_area = st.fragments > 0 ? intact_area / st.fragments : 0.0;
    if (fragment_area.size() >= 2 && st.mean_fragment_area > 0) {
        double var = 0;
        for (double a : fragment_area)
            var += sqr(a - st.mean_fragment_area);
        st.fragment_area_cv = std::sqrt(var / double(fragment_area.size())) / st.mean_fragment_area;
    }

    // === Orientation tensor M = Σ ℓ t tᵀ / Σ ℓ and ψ6 (digest §7.1)
    Mat2 M = Mat2::Zero();
    std::complex<double> hexatic = 0;
    double axial = 0;
    for (const CrackSegment& s : crack_segments(p)) {
        const double len = s.weight * s.length();
        if (len <= 0) continue;
        const Vec2 t = (s.b - s.a).normalized();
        M += len * t * t.transpose();
        const double theta = std::atan2(t.y(), t.x());
        hexatic += len * std::polar(1.0, 6.0 * theta);
        if (std::abs(t.y()) > std::cos(30.0 * DEG_TO_RAD)) axial += len;
        st.crack_length += len;
    }
    if (st.crack_length > 0) {
        M /= st.crack_length;
        Eigen::SelfAdjointEigenSolver<Mat2> eig(M);
        const double l1 = eig.eigenvalues()[1], l2 = eig.eigenvalues()[0];
        st.anisotropy = (l1 + l2) > 0 ? (l1 - l2) / (l1 + l2) : 0.0;
        const Vec2 d = eig.eigenvectors().col(1);
        st.dominant_angle_deg = wrap(std::atan2(d.y(), d.x()) * RAD_TO_DEG, 180.0);
        st.psi6 = std::abs(hexatic) / st.crack_length;
        st.axial_fraction = axial / st.crack_length;
    }
    st.crack_length_per_area = st.total_area > 0 ? st.crack_length / st.total_area : 0.0;

    // === Junctions of the crack network
    const bool removal = std::any_of(p.removed.begin(), p.removed.end(), [](char r) { return r != 0; });
    const JunctionCounts jc = junction_counts(p, removal ? removal_skeleton(p) : crack_skeleton(p));
    st.junctions = jc.total;
    if (jc.total > 0) {
        st.t_junction_fraction = static_cast<double>(jc.t) / jc.total;
        st.y_junction_fraction = static_cast<double>(jc.y) / jc.total;
    }
    return st;
}

CrackPathStatistics crack_path_statistics(const CrackPattern& p, double min_chain_length) {
    CrackPathStatistics st;

    // === Orientation spread about the dominant direction of the orientation tensor
    Mat2 M = Mat2::Zero();
    double total = 0;
    const std::vector<CrackSegment> segments = crack_segments(p);
    for (const CrackSegment& s : segments) {
        const double len = s.weight * s.length();
        if (len <= 0) continue;
        const Vec2 t = (s.b - s.a).normalized();
        M += len * t * t.transpose();
        total += len;
    }
    if (total > 0) {
        Eigen::SelfAdjointEigenSolver<Mat2> eig(M);
        const Vec2 d = eig.eigenvectors().col(1);
        double sum = 0;
        for (const CrackSegment& s : segments) {
            const double len = s.weight * s.length();
            if (len <= 0) continue;
            // δ = angle between the undirected tangent and d, in [0°, 90°]
            const double delta = std::acos(std::min(1.0, std::abs((s.b - s.a).normalized().dot(d))));
            sum += len * sqr(delta * RAD_TO_DEG);
        }
        st.orientation_spread_deg = std::sqrt(sum / total);
    }

    // === Chains of the crack network between nodes of degree ≠ 2
    const bool removal = std::any_of(p.removed.begin(), p.removed.end(), [](char r) { return r != 0; });
    const SkeletonGraph g = removal ? removal_skeleton(p) : crack_skeleton(p);
    std::set<std::pair<std::uint32_t, std::uint32_t>> used;
    auto take = [&](std::uint32_t a, std::uint32_t b) {
        return used.emplace(std::min(a, b), std::max(a, b)).second; // false: walked already
    };
    double sum_length = 0, sum_distance = 0, sum_ratio = 0;
    auto add_chain = [&](double length, const Vec2& displacement) {
        const double distance = displacement.norm();
        if (length < min_chain_length || length <= 0) return;
        if (distance <= 1e-9 * length) return; // a closed loop that does not wrap
        ++st.chains;
        sum_length += length;
        sum_distance += distance;
        sum_ratio += length / distance;
    };
    // Walks from `from` through `first` along degree-2 nodes until a node of another degree,
    // or back to `from` on a closed loop; returns the path length and the unwrapped displacement.
    auto walk = [&](std::uint32_t from, std::uint32_t first, double& length, Vec2& displacement) {
        std::uint32_t prev = from, cur = first;
        length = 0;
        displacement = Vec2::Zero();
        while (true) {
            const Vec2 step = local_difference(p, g.position[prev], g.position[cur]);
            length += step.norm();
            displacement += step;
            if (cur == from || g.adjacency[cur].size() != 2) return;
            const std::uint32_t next = g.adjacency[cur][0] == prev ? g.adjacency[cur][1] : g.adjacency[cur][0];
            if (!take(cur, next)) return;
            prev = cur;
            cur = next;
        }
    };
    for (std::size_t pass = 0; pass < 2; ++pass) // ends and junctions first, then closed loops
        for (std::uint32_t u = 0; u < g.adjacency.size(); ++u) {
            if ((g.adjacency[u].size() != 2) != (pass == 0)) continue;
            for (std::uint32_t w : g.adjacency[u]) {
                if (!take(u, w)) continue;
                double length = 0;
                Vec2 displacement;
                walk(u, w, length, displacement);
                add_chain(length, displacement);
            }
        }
    if (st.chains > 0) {
        st.tortuosity = sum_length / sum_distance;
        st.mean_tortuosity = sum_ratio / st.chains;
    }
    return st;
}

} // namespace crackle::fracture
