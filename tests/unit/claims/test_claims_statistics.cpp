// The crack-path statistics the claim tests use (tortuosity and orientation spread, digest
// §7.1), checked on hand-built crack patterns on a triangular lattice, where every chain's
// length and end-to-end distance follow from the lattice geometry.

#include "fracture/statistics.hpp"
#include "mesh/lattice.hpp"
#include "mesh/triangulate.hpp"
#include "support/mesh_fixtures.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <functional>
#include <vector>

using namespace crackle;

namespace {

/// A crack pattern on a periodic triangular lattice of about 400 points on the unit tile,
/// uncracked; cracks are added with add_chain().
struct LatticePattern {
    LatticePattern() {
        p.surface = test::make_surface(mesh::SurfaceKind::Plane, 1.0, 1.0);
        p.mesh = mesh::triangulate_periodic(mesh::triangular_lattice(Vec2(1.0, 1.0), 400), p.surface);
        p.removed.assign(p.mesh.num_faces(), 0);
    }

    /// The neighbour of v whose unrolled offset d satisfies `pick`, and that offset.
    std::pair<std::size_t, Vec2> step(std::size_t v, const std::function<bool(const Vec2&)>& pick) const {
        for (mesh::FaceId f : p.mesh.vertex_faces(mesh::vertex_id(v))) {
            int kv = 0;
            for (int k = 0; k < 3; ++k)
                if (mesh::ix(p.mesh.faces[f].v[static_cast<std::size_t>(k)]) == v) kv = k;
            for (int k = 0; k < 3; ++k) {
                const Vec2 d = p.mesh.corner_domain(f, k) - p.mesh.corner_domain(f, kv);
                if (k != kv && pick(d)) return {mesh::ix(p.mesh.faces[f].v[static_cast<std::size_t>(k)]), d};
            }
        }
        FAIL("no lattice neighbour in the requested direction");
        return {v, Vec2::Zero()};
    }

    std::size_t nearest(const Vec2& x) const {
        std::size_t best = 0;
        for (std::size_t v = 1; v < p.mesh.num_vertices(); ++v)
            if ((p.mesh.domain[mesh::vertex_id(v)] - x).norm() < (p.mesh.domain[mesh::vertex_id(best)] - x).norm())
                best = v;
        return best;
    }

    /// Opens the crack along the edges v₀v₁, v₁v₂, …: both lips of each edge become CrackEdges.
    void add_chain(const std::vector<std::size_t>& chain) {
        for (std::size_t i = 0; i + 1 < chain.size(); ++i)
            for (std::size_t f = 0; f < p.mesh.num_faces(); ++f)
                for (int k = 0; k < 3; ++k) {
                    const auto& face = p.mesh.faces[mesh::face_id(f)];
                    const std::size_t a = mesh::ix(face.v[static_cast<std::size_t>(k)]);
                    const std::size_t b = mesh::ix(face.v[static_cast<std::size_t>((k + 1) % 3)]);
                    if ((a == chain[i] && b == chain[i + 1]) || (a == chain[i + 1] && b == chain[i]))
                        p.cracks.push_back({mesh::face_id(f), k, 0.0, 0.0});
                }
    }

    /// Walks `count` steps from v, step i taking the neighbour chosen by pick(i, offset);
    /// returns the vertices and adds the path length and unrolled displacement.
    std::vector<std::size_t> walk(std::size_t v, int count, const std::function<bool(int, const Vec2&)>& pick,
                                  double& length, Vec2& displacement) const {
        std::vector<std::size_t> chain{v};
        for (int i = 0; i < count; ++i) {
            const auto [w, d] = step(chain.back(), [&](const Vec2& x) { return pick(i, x); });
            chain.push_back(w);
            length += d.norm();
            displacement += d;
        }
        return chain;
    }

    fracture::CrackPattern p;
};

bool along_x(const Vec2& d) {
    return std::abs(d.y()) < 1e-9 && d.x() > 0;
}
/// Zig-zag upwards: right on even steps, left on odd ones.
bool zigzag(int i, const Vec2& d) {
    return d.y() > 1e-9 && (i % 2 == 0 ? d.x() > 0 : d.x() < 0);
}

/// Number of lattice rows: steps upwards until the walk is back where it started.
int rows(const LatticePattern& lp, std::size_t start) {
    std::size_t v = start;
    for (int n = 1; n < 200; ++n) {
        v = lp.step(v, [&](const Vec2& d) { return zigzag(n - 1, d); }).first;
        if (v == start) return n;
    }
    FAIL("the lattice does not close upwards");
    return 0;
}

} // namespace

TEST_SUITE("claims") {
    TEST_CASE("crack path statistics: a straight crack around the tile has tortuosity 1 and no spread") {
        LatticePattern lp;
        const std::size_t start = lp.nearest(Vec2(0.3, 0.5));
        double length = 0;
        Vec2 displacement = Vec2::Zero();
        const auto chain = lp.walk(
            start, 1000, [&](int, const Vec2& d) { return along_x(d); }, length, displacement);
        // Cut the walk where it first returns to the start (one period).
        const auto back = std::find(chain.begin() + 1, chain.end(), start);
        REQUIRE(back != chain.end());
        lp.add_chain(std::vector<std::size_t>(chain.begin(), back + 1));
        const auto st = fracture::crack_path_statistics(lp.p);
        CHECK(st.chains == 1); // a closed chain that wraps once: end-to-end = the period
        CHECK(st.tortuosity == doctest::Approx(1.0).epsilon(1e-9));
        CHECK(st.orientation_spread_deg < 1e-6);
    }

    TEST_CASE("crack path statistics: a zig-zag crack has the lattice's tortuosity and ±30° spread") {
        LatticePattern lp;
        const std::size_t start = lp.nearest(Vec2(0.5, 0.2));
        const int n = rows(lp, start);
        double length = 0;
        Vec2 displacement = Vec2::Zero();
        lp.add_chain(lp.walk(start, n, zigzag, length, displacement));
        REQUIRE(displacement.norm() == doctest::Approx(1.0)); // once around the tile in y
        // Every edge of the zig-zag has the same length e and rise dy: tortuosity e/dy.
        const auto st = fracture::crack_path_statistics(lp.p);
        CHECK(st.chains == 1);
        CHECK(st.tortuosity == doctest::Approx(length / displacement.norm()).epsilon(1e-9));
        CHECK(st.tortuosity == doctest::Approx(2.0 / std::sqrt(3.0)).epsilon(0.03)); // nearly equilateral
        const double edge = length / n, dy = displacement.norm() / n;
        const double expected = std::acos(dy / edge) * RAD_TO_DEG; // each edge leans this far from the y axis
        CHECK(st.orientation_spread_deg == doctest::Approx(expected).epsilon(1e-6));
        CHECK(st.orientation_spread_deg == doctest::Approx(30.0).epsilon(0.05));
    }

    TEST_CASE("crack path statistics: chains end at junctions and tips, loops that do not wrap and short chains are "
              "skipped") {
        LatticePattern lp;
        const std::size_t start = lp.nearest(Vec2(0.3, 0.5));
        double row_length = 0;
        Vec2 row_disp = Vec2::Zero();
        auto row = lp.walk(
            start, 1000, [&](int, const Vec2& d) { return along_x(d); }, row_length, row_disp);
        row.erase(std::find(row.begin() + 1, row.end(), start) + 1, row.end());
        row_length = 1.0; // the walk went on past one period; the row is the tile's width
        lp.add_chain(row);
        // A branch of 5 zig-zag edges up from the row: a T-junction (degree 3) to a free tip.
        double branch_length = 0;
        Vec2 branch_disp = Vec2::Zero();
        lp.add_chain(lp.walk(row[row.size() / 2], 5, zigzag, branch_length, branch_disp));
        // A hexagon around a vertex away from both: closed and contractible, no end-to-end distance.
        const std::size_t centre = lp.nearest(Vec2(0.3, 0.15));
        std::vector<std::size_t> hexagon;
        for (double angle = 0; angle < 360; angle += 60) {
            const Vec2 dir(std::cos(angle * DEG_TO_RAD), std::sin(angle * DEG_TO_RAD));
            hexagon.push_back(lp.step(centre, [&](const Vec2& d) { return d.normalized().dot(dir) > 0.95; }).first);
        }
        hexagon.push_back(hexagon.front());
        lp.add_chain(hexagon);

        const auto st = fracture::crack_path_statistics(lp.p);
        // The row from the junction around the torus back to it (wraps: end-to-end = 1) and the
        // branch; the hexagon does not count.
        CHECK(st.chains == 2);
        const double branch_t = branch_length / branch_disp.norm();
        CHECK(branch_t > 1.05);
        CHECK(st.tortuosity
              == doctest::Approx((row_length + branch_length) / (1.0 + branch_disp.norm())).epsilon(1e-6));
        CHECK(st.mean_tortuosity == doctest::Approx(0.5 * (1.0 + branch_t)).epsilon(1e-6));
        // With a minimum chain length above the branch's, only the row is left.
        const auto long_only = fracture::crack_path_statistics(lp.p, 0.5);
        CHECK(long_only.chains == 1);
        CHECK(long_only.tortuosity == doctest::Approx(1.0).epsilon(1e-9));
        // An uncracked pattern: no chains, tortuosity 1, no spread.
        LatticePattern none;
        const auto empty = fracture::crack_path_statistics(none.p);
        CHECK(empty.chains == 0);
        CHECK(empty.tortuosity == 1.0);
        CHECK(empty.orientation_spread_deg == 0.0);
    }
}
