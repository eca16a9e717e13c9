// Thesis claims about the stress field around scripted cracks on the periodic plane:
// Figs. 5.9 (σ1 before and after cracking), 5.18 (nodal stress at a tip), 5.24 (tip sub-model)
// and 5.25 (local relaxation does not leak across a crack). The cracks are chains of mesh
// edges cut open (tests/support/scripted_crack.hpp), so each test controls where they run.

#include "fracture/fem_split/fem_split.hpp"
#include "support/accuracy.hpp"
#include "support/fracture_fixture.hpp"
#include "support/scripted_crack.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <vector>

using namespace crackle;
using test::LayerSpec;

namespace {

/// Largest in-surface principal stress at every node (Pa), nodal averaging of §5.7.1.
std::vector<double> nodal_sigma1(const sim::FemModel& m) {
    std::vector<double> s(m.mesh().num_vertices(), 0.0);
    for (std::size_t v = 0; v < s.size(); ++v) {
        if (m.incident_faces(v).empty()) continue;
        const fracture::NodalStress ns = fracture::nodal_stress(m, v);
        s[v] = ns.ratio * ns.threshold;
    }
    return s;
}

/// Minimum-image distance between two domain points.
double domain_distance(const sim::FemModel& m, const Vec2& a, const Vec2& b) {
    Vec2 d = a - b;
    const Vec2 L = m.mesh().period;
    d.x() -= L.x() * std::round(d.x() / L.x());
    d.y() -= L.y() * std::round(d.y() / L.y());
    return d.norm();
}

Vec2 domain_of(const sim::FemModel& m, std::size_t v) {
    return m.mesh().domain[mesh::vertex_id(v)];
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

/// Angle between two undirected directions (degrees, [0, 90]).
double line_angle(const Vec3& a, const Vec3& b) {
    return std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized())))) * RAD_TO_DEG;
}

/// A loaded periodic layer (square tile of side `size`), relaxed at t = 1.
struct LoadedLayer {
    LoadedLayer(std::uint64_t seed, std::size_t elements, double size, double thickness, sim::GrowthOptions growth)
        : layer([&] {
              LayerSpec s;
              s.size = Vec2(size, size);
              s.elements = elements;
              s.thickness = thickness;
              s.seed = seed;
              s.growth = growth;
              return s;
          }()) {
        layer.model->set_time(1.0);
        layer.model->relax();
        h = mesh::mesh_quality(layer.model->mesh()).edge_mean;
    }
    sim::FemModel& model() { return *layer.model; }
    double side() const { return layer.spec.size.x(); }
    test::Layer layer;
    double h = 0; ///< mean edge length (m)
};

/// Cuts a slit along y through the tile centre (0.3 … 0.7 of the side) and relaxes globally;
/// returns the chain (its ends are the tips).
std::vector<std::size_t> cut_slit(LoadedLayer& c) {
    sim::FemModel& m = c.model();
    const double L = c.side();
    const auto path = test::edge_path(m, Vec2(0.5 * L, 0.3 * L), Vec2(0.5 * L, 0.7 * L), c.h);
    test::cut_path(m, path);
    m.relax();
    return path;
}

/// The vertices reachable from `start` along alive elements without leaving the strip
/// x0 − L/2 < x < x0 + L/2 of the unrolled domain: with a closed crack along x = x0, the
/// vertices on the start's side of it (the strip cannot wrap around the torus to the other side).
std::vector<char> side_of(const sim::FemModel& m, std::size_t start, double x0) {
    const mesh::SurfaceMesh& mesh = m.mesh();
    const double L = mesh.period.x();
    std::vector<char> seen(mesh.num_vertices(), 0);
    std::vector<std::pair<std::size_t, Vec2>> queue;
    Vec2 p0 = domain_of(m, start);
    p0.x() -= L * std::round((p0.x() - x0) / L);
    queue.emplace_back(start, p0);
    seen[start] = 1;
    for (std::size_t head = 0; head < queue.size(); ++head) {
        const auto [v, p] = queue[head];
        for (std::uint32_t f : m.incident_faces(v)) {
            const mesh::FaceId fid = mesh::face_id(f);
            if (!m.alive(fid)) continue;
            int kv = 0;
            for (int k = 0; k < 3; ++k)
                if (mesh::ix(mesh.faces[fid].v[static_cast<std::size_t>(k)]) == v) kv = k;
            for (int k = 0; k < 3; ++k) {
                const std::size_t w = mesh::ix(mesh.faces[fid].v[static_cast<std::size_t>(k)]);
                const Vec2 q = p + mesh.corner_domain(fid, k) - mesh.corner_domain(fid, kv);
                if (seen[w] || std::abs(q.x() - x0) >= 0.5 * L) continue;
                seen[w] = 1;
                queue.emplace_back(w, q);
            }
        }
    }
    return seen;
}

} // namespace

TEST_SUITE("claims") {
    TEST_CASE(
        "claims 5.9: sigma1 is uniform on the intact tile and rises from the free edges of a cut-out patch to its "
        "centre") {
        // Fig. 5.9's layers are finite patches with free edges, and their σ1 peaks near the
        // patch centre. Our plane is a periodic tile without edges: intact, its σ1 is uniform
        // (asserted). Cutting the tile along two closed cracks (x = 0 and y = 0) turns it into
        // one square patch with free edges, the thesis' setup: σ1 must then grow from the edges
        // to the centre. The patch is 5 layer thicknesses wide, so the edge zones (a few
        // thicknesses deep) meet in the middle.
        const sim::GrowthOptions iso{sim::GrowthKind::Isogonic, 1e-4, 1e-4, 0};
        constexpr int BINS = 5;
        double worst_spread = 0, worst_offset = 0, worst_rim = 0;
        bool monotone = true;
        for (std::uint64_t seed : {1u, 2u, 3u}) {
            CAPTURE(seed);
            LoadedLayer c(seed, 600, 0.05, 0.01, iso);
            sim::FemModel& m = c.model();
            const std::vector<double> before = nodal_sigma1(m);
            const double mean = std::accumulate(before.begin(), before.end(), 0.0) / double(before.size());
            double var = 0;
            for (double x : before)
                var += sqr(x - mean);
            worst_spread = std::max(worst_spread, std::sqrt(var / double(before.size())) / mean);

            // Both closed cracks in one cut: after the first, no edge chain could cross it.
            const double L = c.side();
            auto sides = test::path_sides(m, test::edge_path(m, Vec2(0, 0), Vec2(0, L), c.h));
            const auto across = test::path_sides(m, test::edge_path(m, Vec2(0, 0), Vec2(L, 0), c.h));
            sides.insert(sides.end(), across.begin(), across.end());
            m.cut(sides);
            m.relax();
            const std::vector<double> after = nodal_sigma1(m);

            // Profile over the distance to the nearest free edge, in bins up to the centre.
            std::vector<double> sum(BINS, 0.0), count(BINS, 0.0);
            for (std::size_t v = 0; v < after.size(); ++v) {
                const Vec2 d = domain_of(m, v);
                const double depth = std::min({d.x(), L - d.x(), d.y(), L - d.y()}) / (0.5 * L);
                const auto b = std::min<std::size_t>(BINS - 1, static_cast<std::size_t>(depth * BINS));
                sum[b] += after[v];
                count[b] += 1;
            }
            std::vector<double> profile(BINS);
            for (int b = 0; b < BINS; ++b)
                profile[static_cast<std::size_t>(b)] =
                    sum[static_cast<std::size_t>(b)] / std::max(1.0, count[static_cast<std::size_t>(b)]);
            for (std::size_t b = 1; b < profile.size(); ++b)
                monotone = monotone && profile[b] > profile[b - 1];
            worst_rim = std::max(worst_rim, profile.front() / profile.back());
            // Where the maximum is: σ1 averaged over each node's ring, which smooths out the
            // notches of a crack that zig-zags along mesh edges (a single rim node can peak there).
            double best = -1;
            std::size_t peak = 0;
            for (std::size_t v = 0; v < after.size(); ++v) {
                const auto ring = test::ring_of(m, v);
                double smooth = after[v];
                for (std::size_t w : ring)
                    smooth += after[w];
                smooth /= double(ring.size() + 1);
                if (smooth > best) {
                    best = smooth;
                    peak = v;
                }
            }
            worst_offset = std::max(worst_offset, domain_distance(m, domain_of(m, peak), Vec2(0.5 * L, 0.5 * L)) / L);
            CAPTURE(profile[0]);
            CAPTURE(profile[BINS - 1]);
        }
        test::record_claim("5.9", "sigma1 uniform before cracking (periodic tile, no free edges)",
                           "max over seeds of std/mean of nodal sigma1", worst_spread, "< 1e-5");
        test::record_claim("5.9", "sigma1 peaks near the centre of a patch with free edges",
                           "max over seeds of |ring-smoothed argmax - centre| / side", worst_offset, "< 0.15");
        test::record_claim("5.9", "sigma1 low at the free edges of a patch",
                           "max over seeds of sigma1(edge bin) / sigma1(centre bin)", worst_rim, "< 0.4");
        CHECK(worst_spread < 1e-5);
        CHECK(monotone);
        CHECK(worst_offset < 0.15);
        CHECK(worst_rim < 0.4);
    }

    TEST_CASE("claims 5.9, 5.18: a slit concentrates sigma1 at its tips: above the far field and the ring average") {
        // A slit across the stretch in a layer resolved by several elements per thickness
        // (h ≈ thickness / 7; with h ≈ thickness the concentration is within a few per cent).
        // Fig. 5.18's claim that the tip node is above *every* node one ring away does not hold
        // with §5.7.1's averaging: the tip averages in the elements along the unloaded lips, and
        // the node straight ahead often reaches the tip's value. What holds is asserted: the tip
        // is well above the far field and above the mean of its ring, and the peak of σ1 is at
        // a tip or its ring.
        const sim::GrowthOptions along_x{sim::GrowthKind::Anisotropic, 1e-4, 0.0, 0.0};
        double min_far = INFINITY, min_mean = INFINITY, min_max = INFINITY, worst_peak = 0;
        int above_all = 0, tips = 0;
        for (std::uint64_t seed : {1u, 2u, 3u}) {
            CAPTURE(seed);
            LoadedLayer c(seed, 800, 0.05, 0.02, along_x);
            sim::FemModel& m = c.model();
            const double far = median(nodal_sigma1(m));
            const auto path = cut_slit(c);
            const std::vector<double> s = nodal_sigma1(m);
            double nearest_tip = INFINITY;
            const auto peak = static_cast<std::size_t>(std::max_element(s.begin(), s.end()) - s.begin());
            for (std::size_t tip : {path.front(), path.back()}) {
                const auto ring = test::ring_of(m, tip);
                double ring_mean = 0, ring_max = 0;
                for (std::size_t w : ring) {
                    ring_mean += s[w] / double(ring.size());
                    ring_max = std::max(ring_max, s[w]);
                }
                min_far = std::min(min_far, s[tip] / far);
                min_mean = std::min(min_mean, s[tip] / ring_mean);
                min_max = std::min(min_max, s[tip] / ring_max);
                above_all += s[tip] > ring_max;
                ++tips;
                nearest_tip = std::min(nearest_tip, domain_distance(m, domain_of(m, peak), domain_of(m, tip)));
            }
            worst_peak = std::max(worst_peak, nearest_tip / c.h);
        }
        test::record_claim("5.9", "after cracking sigma1 peaks near the crack tips",
                           "max over seeds of |argmax sigma1 - nearest tip| / mean edge", worst_peak, "<= 1.5");
        test::record_claim("5.9", "tip stress / far-field stress > 1", "min over 6 tips of sigma1(tip)/median sigma1",
                           min_far, "> 1.2");
        test::record_claim("5.18", "tip node stress above its ring", "min over 6 tips of sigma1(tip)/mean sigma1(ring)",
                           min_mean, "> 1");
        test::record_claim("5.18", "tip node stress above every node of its ring (does not hold)",
                           "min over 6 tips of sigma1(tip)/max sigma1(ring)", min_max, "> 0.85 (claim: > 1)");
        test::record_claim("5.18", "tip node stress above every node of its ring (does not hold)",
                           "share of tips above every ring node", double(above_all) / tips, "not asserted");
        CHECK(worst_peak <= 1.5);
        CHECK(min_far > 1.2);
        CHECK(min_mean > 1.0);
        CHECK(min_max > 0.85);
    }

    TEST_CASE("claims 5.24: a temporary refined sub-model gives the tip stress of a refined mesh and leaves no "
              "element behind") {
        // §5.7.8 as fem-split builds it (Splitter::submodel_direction, with the FemModel calls it
        // makes): inside a trial, the tip's elements and one ring around them are bisected down
        // to a quarter of the tip's smallest element (tip_submodel_levels = 2), relaxed with the
        // far nodes held, evaluated, rolled back. The reference bisects every element within
        // 6 cm of the tip (3–4 coarse elements beyond the sub-model) to the same size and solves
        // globally. The loading is oblique to the slit (stretch 30° from its normal), so the
        // tip's principal direction is not fixed by symmetry.
        double worst_sub = 0, best_coarse = INFINITY, worst_angle = 0, worst_held = 0, held_share = 0;
        bool restored = true;
        for (std::uint64_t seed : {1u, 2u, 3u}) {
            CAPTURE(seed);
            LoadedLayer c(seed, 1200, 0.4, 0.01, {sim::GrowthKind::Anisotropic, 1e-4, 0.0, 30.0});
            sim::FemModel& m = c.model();
            const std::size_t tip = cut_slit(c).back();
            const sim::FemModel before = m;
            const fracture::NodalStress coarse = fracture::nodal_stress(m, tip);
            double size = INFINITY;
            for (std::uint32_t f : m.incident_faces(tip))
                size = std::min(size, m.element_size(mesh::face_id(f)));
            size /= 4.0;

            // === The sub-model
            m.begin_trial();
            std::vector<std::size_t> seeds;
            for (int round = 0; round < 1000; ++round) {
                std::vector<std::uint32_t> vicinity;
                for (std::uint32_t f : m.incident_faces(tip))
                    for (mesh::VertexId w : m.mesh().faces[mesh::face_id(f)].v)
                        for (std::uint32_t g : m.incident_faces(mesh::ix(w)))
                            vicinity.push_back(g);
                double longest = size;
                std::uint32_t coarsest = 0;
                for (std::uint32_t f : vicinity)
                    if (m.element_size(mesh::face_id(f)) > longest) {
                        longest = m.element_size(mesh::face_id(f));
                        coarsest = f;
                    }
                if (longest <= size) break;
                for (mesh::FaceId f : m.subdivide(mesh::face_id(coarsest)))
                    for (mesh::VertexId w : m.mesh().faces[f].v)
                        seeds.push_back(mesh::ix(w));
            }
            REQUIRE(m.mesh().num_faces() > before.mesh().num_faces());
            sim::FemModel whole = m; // the same refinement, solved globally
            whole.relax();
            // The held boundary is the point here: never fall back to a global solve (fem-split
            // does when the sub-model passes a quarter of the nodes, as on small tiles).
            sim::LocalRelaxOptions held;
            held.max_fraction = 1.0;
            double radius = 4;
            const sim::SolveStats st = m.relax_local(seeds, radius, held);
            CHECK_FALSE(st.fell_back);
            held_share = std::max(held_share, double(st.nodes) / double(m.mesh().num_vertices()));
            const fracture::NodalStress sub = fracture::nodal_stress(m, tip);
            const fracture::NodalStress sub_global = fracture::nodal_stress(whole, tip);
            m.rollback();
            restored = restored && m.mesh().num_faces() == before.mesh().num_faces()
                       && m.num_alive() == before.num_alive()
                       && m.mesh().num_vertices() == before.mesh().num_vertices();
            for (std::size_t v = 0; v < before.mesh().num_vertices() && restored; ++v)
                restored = m.top_position(mesh::vertex_id(v)) == before.top_position(mesh::vertex_id(v));

            // === The reference
            sim::FemModel ref = before;
            const Vec2 at = domain_of(ref, tip);
            for (bool again = true; again;) {
                again = false;
                for (std::size_t f = 0; f < ref.mesh().num_faces(); ++f) {
                    const mesh::FaceId fid = mesh::face_id(f);
                    const Vec2 centroid = (ref.mesh().corner_domain(fid, 0) + ref.mesh().corner_domain(fid, 1)
                                           + ref.mesh().corner_domain(fid, 2))
                                          / 3.0;
                    if (ref.element_size(fid) > size && domain_distance(ref, centroid, at) < 0.06) {
                        ref.subdivide(fid);
                        again = true;
                    }
                }
            }
            ref.relax();
            const fracture::NodalStress fine = fracture::nodal_stress(ref, tip);
            worst_sub = std::max(worst_sub, std::abs(sub.ratio - fine.ratio) / fine.ratio);
            best_coarse = std::min(best_coarse, std::abs(coarse.ratio - fine.ratio) / fine.ratio);
            worst_held = std::max(worst_held, std::abs(sub.ratio - sub_global.ratio) / sub_global.ratio);
            worst_angle = std::max(worst_angle, line_angle(sub.crack, fine.crack));
            CAPTURE(coarse.ratio);
            CAPTURE(sub.ratio);
            CAPTURE(fine.ratio);
        }
        test::record_claim("5.24", "tip stress from the sub-model as accurate as with refinement",
                           "max over seeds of |sigma1(sub) - sigma1(refined ref)| / sigma1(ref)", worst_sub, "< 0.05");
        test::record_claim("5.24", "tip stress from the sub-model as accurate as with refinement",
                           "min over seeds of |sigma1(coarse) - sigma1(ref)| / sigma1(ref) (what the sub-model fixes)",
                           best_coarse, "> 2 x the sub-model's error");
        test::record_claim("5.24", "elements beyond the sub-model do not affect the tip stress",
                           "max over seeds of |sigma1(held far nodes) - sigma1(global solve)| / sigma1", worst_held,
                           "< 0.01");
        test::record_claim("5.24", "elements beyond the sub-model do not affect the tip stress",
                           "max over seeds of solved nodes / all nodes in the sub-model solve", held_share, "< 0.5");
        test::record_claim("5.24", "tip direction from the sub-model",
                           "max over seeds of angle(sub-model, refined ref) (deg)", worst_angle, "< 1");
        test::record_claim("5.24", "no permanent elements", "element count and positions restored after rollback",
                           restored ? 1.0 : 0.0, "== 1");
        // In a whole run with sub-models at every tip step: only the cuts add elements (at most
        // two per cut edge; one sub-model alone adds over a hundred).
        LayerSpec s;
        s.size = Vec2(0.2, 0.2);
        s.elements = 300;
        s.growth = {sim::GrowthKind::Anisotropic, 3e-4, 0.0, 30.0};
        s.toughness = 1;
        fracture::SplitOptions split;
        split.tip_submodel_levels = 2;
        const test::FractureRun run = test::run_split(s, 1.0, split);
        const double added = double(run.pattern.mesh.num_faces()) - double(run.pattern.elements_initial);
        const double cuts = double(2 * run.split.splits + run.split.extensions);
        test::record_claim("5.24", "no permanent elements (whole fem-split run, sub-models at every tip)",
                           "elements added / (2 x cut edges)", added / (2 * cuts), "<= 1");
        CHECK(run.split.submodels > 50);
        CHECK(added <= 2 * cuts);
        CHECK(worst_sub < 0.05);
        CHECK(best_coarse > 2 * worst_sub);
        CHECK(worst_held < 0.01);
        CHECK(held_share < 0.5);
        CHECK(worst_angle < 1.0);
        CHECK(restored);
    }

    TEST_CASE("claims 5.25: a local relaxation stays on its side of a crack and matches the global solve") {
        // A closed crack along x = x0 turns the tile into a band: the nodes just across it are
        // close in space but a whole tile width away along intact elements. A short slit cut
        // 2 edges from the crack is relaxed locally (default options: a force tolerance of 1e-2
        // of the change). None of the nodes across the crack may move, although many lie
        // closer to the change than nodes that did; the result must match the global solve.
        std::size_t leaked = 0, across_near = 0;
        double worst_error = 0, max_share = 0;
        int min_hop_across = 1 << 30;
        for (std::uint64_t seed : {1u, 2u, 3u}) {
            CAPTURE(seed);
            LoadedLayer c(seed, 3000, 0.2, 0.01, {sim::GrowthKind::Isogonic, 1e-4, 1e-4, 0.0});
            sim::FemModel& m = c.model();
            const double L = c.side(), x0 = 0.5 * L;
            test::cut_path(m, test::edge_path(m, Vec2(x0, 0), Vec2(x0, L), c.h));
            m.relax();
            const Vec2 at(x0 - 2 * c.h, 0.5 * L);
            const auto seeds =
                test::cut_path(m, test::edge_path(m, at - Vec2(0, 1.5 * c.h), at + Vec2(0, 1.5 * c.h), c.h));
            const sim::FemModel before = m;
            sim::FemModel global = m;
            global.relax();
            double radius = 3;
            const sim::SolveStats st = m.relax_local(seeds, radius);
            REQUIRE_FALSE(st.fell_back);
            const std::vector<char> near_side = side_of(m, seeds.front(), x0);
            const std::vector<int> hop = test::hop_distance(m, seeds);
            double reach = 0; // farthest node the local solve moved
            for (std::size_t v : m.last_updated_vertices()) {
                reach = std::max(reach, domain_distance(m, domain_of(m, v), at));
                leaked += !near_side[v];
            }
            for (std::size_t v = 0; v < m.mesh().num_vertices(); ++v)
                if (!near_side[v] && !m.incident_faces(v).empty() && domain_distance(m, domain_of(m, v), at) < reach) {
                    ++across_near;
                    min_hop_across = std::min(min_hop_across, hop[v]);
                }
            max_share = std::max(max_share, double(st.nodes) / double(m.mesh().num_vertices()));
            double worst = 0, moved = 0;
            for (std::size_t v = 0; v < m.mesh().num_vertices(); ++v) {
                const Vec3 g = global.top_position(mesh::vertex_id(v));
                worst = std::max(worst, (m.top_position(mesh::vertex_id(v)) - g).norm());
                moved = std::max(moved, (g - before.top_position(mesh::vertex_id(v))).norm());
            }
            REQUIRE(moved > 0);
            worst_error = std::max(worst_error, worst / moved);
        }
        test::record_claim("5.25", "the local set does not leak across a crack",
                           "nodes across the crack moved by the local relaxation (3 seeds)", double(leaked), "== 0");
        test::record_claim("5.25", "the local set does not leak across a crack",
                           "nodes across the crack closer to the change than a moved node (3 seeds)",
                           double(across_near), "> 0 (the test is not vacuous)");
        test::record_claim("5.25", "the local set does not leak across a crack",
                           "min hop distance (intact elements) of those nodes", double(min_hop_across), "informative");
        test::record_claim("5.25", "local relaxation equals the global solve",
                           "max over seeds of max |x_local - x_global| / max |x_global - x_before|", worst_error,
                           "< 1e-2");
        test::record_claim("5.25", "the solve stays local", "max over seeds of solved nodes / all nodes", max_share,
                           "< 0.25");
        CHECK(leaked == 0);
        CHECK(across_near > 0);
        CHECK(worst_error < 1e-2);
        CHECK(max_share < 0.25);
    }
}
