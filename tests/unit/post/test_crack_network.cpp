// The crack network as chains for the bake's curves (post/crack_network): every crack once, in
// chains that run through junctions straight on and end at tips and at the junctions they stop
// on, with their openings measured between the right lips, on the plane, cylinder and sphere.
#include "app/run/options.hpp"
#include "app/run/pipeline.hpp"
#include "io/preset.hpp"
#include "post/pieces.hpp"
#include "render/crack_curves.hpp"
#include "support/simulated.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

using namespace crackle;

namespace {

test::Simulated simulate(const std::string& preset_name, int elements) {
    return test::simulate(preset_name, {"simulation.elements=" + std::to_string(elements)});
}

/// Metres between two texture points of the pieces' surface.
double metres(const post::PieceMesh& p, const Vec2& a, const Vec2& b) {
    const Vec2 d = b - a;
    return Vec2(d.x() * render::metres_per_u(p, 0.5 * (a.y() + b.y())), d.y() * p.tile_size.y()).norm();
}

} // namespace

TEST_SUITE("post") {
    TEST_CASE("crack network: chains cover the simulated cracks once, without jumps across the tile, and close at "
              "their tips (plane, cylinder, sphere)") {
        for (const auto& [name, elements] :
             {std::pair<std::string, int>{"mud", 2000}, {"bark", 2000}, {"fruit", 3000}}) {
            CAPTURE(name);
            const test::Simulated s = simulate(name, elements);
            const post::PieceMesh& p = s.pieces;
            REQUIRE(!p.chains.empty());
            double length = 0, longest_step = 0;
            std::vector<float> openings;
            int tips = 0;
            for (const post::CrackChain& c : p.chains) {
                REQUIRE(c.uv.size() >= 2);
                REQUIRE(c.opening.size() == c.uv.size());
                REQUIRE(c.time.size() == c.uv.size());
                for (std::size_t i = 1; i < c.uv.size(); ++i) {
                    const double step = metres(p, c.uv[i - 1], c.uv[i]);
                    length += step;
                    longest_step = std::max(longest_step, step);
                }
                for (float w : c.opening) {
                    CHECK(w >= 0.0f);
                    openings.push_back(w);
                }
                if (c.tip_front) {
                    CHECK(c.opening.front() == 0.0f);
                    ++tips;
                }
                if (c.tip_back) {
                    CHECK(c.opening.back() == 0.0f);
                    ++tips;
                }
                if (c.closed) { // back where it started, or at its image a period on (round the trunk)
                    const Vec2 d = c.uv.back() - c.uv.front();
                    CHECK((d - d.array().round().matrix()).norm() < 1e-9);
                }
            }
            // The chains' length is the statistics' crack length (the same edges, at their final
            // places: the post stage's shrinkage moves them by a few per cent at most).
            CAPTURE(length);
            CAPTURE(s.run.statistics.crack_length);
            CHECK(length == doctest::Approx(s.run.statistics.crack_length).epsilon(0.06));
            // Consecutive points are neighbours on the surface (no step across the tile).
            CHECK(longest_step < 4.0 * p.element_size);
            // No opening measured to the wrong periodic image: none is far beyond the pattern's
            // widest (the widest are the post stage's shrinkage pulling the plates apart).
            std::sort(openings.begin(), openings.end());
            const float p90 = openings[openings.size() * 9 / 10];
            CHECK(openings.back() <= 4.0f * std::max(p90, 1e-6f));
            std::size_t links = 0;
            for (const post::CrackChain& c : p.chains)
                links += c.uv.size() - 1;
            MESSAGE(name << ": " << p.chains.size() << " chains, " << tips << " tips, length " << length << " m, links "
                         << links << ", lips " << s.run.pattern.cracks.size());
        }
    }

    TEST_CASE("crack network: at a junction the crack that runs straight on is one chain (a T's bar), its stem ends "
              "on it") {
        const test::Simulated s = simulate("mud", 2000);
        const post::PieceMesh& p = s.pieces;
        // Mud meets at T junctions (§5.5). With the bar one chain, a T is one chain end (its stem's)
        // and only a Y, where nothing runs straight on, three: chain ends per junction place stay
        // near 1 (3 if every chain stopped at every junction).
        std::map<std::pair<long, long>, int> ends_at; // junction place (µ of u and v, wrapped) → chain ends
        auto place = [](const Vec2& uv) {
            const Vec2 w = uv - uv.array().floor().matrix();
            return std::make_pair(std::lround(w.x() * 1e6) % 1000000, std::lround(w.y() * 1e6) % 1000000);
        };
        for (const post::CrackChain& c : p.chains) {
            if (c.closed) continue;
            if (!c.tip_front) ++ends_at[place(c.uv.front())];
            if (!c.tip_back) ++ends_at[place(c.uv.back())];
        }
        std::size_t ends = 0;
        for (const auto& [at, n] : ends_at)
            ends += static_cast<std::size_t>(n);
        const double per_junction = double(ends) / double(ends_at.size());
        CAPTURE(ends);
        CAPTURE(ends_at.size());
        CAPTURE(s.run.statistics.y_junction_fraction);
        REQUIRE(ends_at.size() > 50);
        CHECK(per_junction >= 1.0);
        CHECK(per_junction <= 1.0 + 2.0 * s.run.statistics.y_junction_fraction + 0.15);
    }

    TEST_CASE("crack network: a junction lies where the pieces meeting there are equally far, a crack's chain in the "
              "middle of its gap (plane, cylinder, sphere)") {
        // A node was the mean of its pieces' corners. fem-split refines next to a tip, so a stem
        // often ends on a bar at a hanging node, whose corners (the stem's two) lie on the bar's
        // near lip: the bar's chain kinked half an opening towards the stem there, the bake's
        // grooves with it (issue 35: the Mask's T share 0.68 against the pieces' 0.75); and even a
        // T's three corners have their mean a sixth of the bar's opening towards the stem. A node
        // now lies at the centre of the smallest circle round its pieces' corners (a hanging
        // node's far side taken on the coarse lip across the gap): where the pieces are equally
        // far, as the crack's centre lines meet.
        // Mud on the plane and wrapped round a cylinder (bark's fissures seldom meet), fruit's skin.
        for (const auto& [name, kind, elements] : {std::tuple<std::string, std::string, int>{"mud", "plane", 1000},
                                                   {"mud", "cylinder", 1000},
                                                   {"fruit", "sphere", 1500}}) {
            CAPTURE(name);
            CAPTURE(kind);
            const test::Simulated s = test::simulate(
                name, {"simulation.elements=" + std::to_string(elements), "surface.kind=\"" + kind + "\""});
            const post::PieceMesh& p = s.pieces;
            auto near_image = [&](const Vec2& from, Vec2 q) {
                q.x() -= std::round(q.x() - from.x());
                if (p.periodic) q.y() -= std::round(q.y() - from.y());
                return q;
            };
            auto to_metres = [&](const Vec2& at, const Vec2& d) {
                return Vec2(d.x() * render::metres_per_u(p, at.y()), d.y() * p.tile_size.y());
            };
            // Per piece, the distance from q to its nearest lip (m), over the pieces within `reach`.
            auto piece_distances = [&](const Vec2& q, double reach) {
                std::map<int, double> out;
                for (const auto& lip : p.lips) {
                    const Vec2 ua = near_image(q, p.vertices[lip[0]].uv);
                    const Vec2 a = to_metres(q, ua - q), b = to_metres(q, near_image(ua, p.vertices[lip[1]].uv) - q);
                    const Vec2 ab = b - a;
                    const double t = std::clamp(-a.dot(ab) / std::max(ab.squaredNorm(), 1e-30), 0.0, 1.0);
                    const double d = (a + t * ab).norm();
                    if (d > reach) continue;
                    const int piece = p.vertices[lip[0]].fragment;
                    const auto it = out.find(piece);
                    if (it == out.end() || d < it->second) out[piece] = d;
                }
                return out;
            };
            // Each junction (a chain end that is not a tip), once: its nearest and farthest of the
            // pieces around it. 1 where the pieces are equally far; 0 on a piece's corner.
            std::map<std::pair<long, long>, Vec2> junctions;
            for (const post::CrackChain& c : p.chains) {
                if (c.closed) continue;
                for (const auto& [tip, at] :
                     {std::pair{c.tip_front, c.uv.front()}, std::pair{c.tip_back, c.uv.back()}}) {
                    if (tip) continue;
                    const Vec2 w = at - at.array().floor().matrix();
                    junctions.emplace(std::make_pair(std::lround(w.x() * 1e6), std::lround(w.y() * 1e6)), at);
                }
            }
            std::vector<double> balance;
            for (const auto& [key, at] : junctions) {
                const std::map<int, double> d = piece_distances(at, 0.5 * p.element_size);
                if (d.size() < 3) continue; // a piece meets itself round a crack's end, or a sliver
                double least = 1e300, most = 0;
                for (const auto& [piece, dist] : d)
                    least = std::min(least, dist), most = std::max(most, dist);
                if (most > 0) balance.push_back(least / most);
            }
            REQUIRE(balance.size() > 10);
            std::sort(balance.begin(), balance.end());
            const double below_half = double(std::lower_bound(balance.begin(), balance.end(), 0.5) - balance.begin())
                                      / double(balance.size());
            MESSAGE(name << " (" << kind << "): " << balance.size()
                         << " junctions; nearest over farthest piece: median " << balance[balance.size() / 2]
                         << ", 10th percentile " << balance[balance.size() / 10] << "; below one half "
                         << 100 * below_half << " %");
            // Measured (seed 1): median 0.97 (plane), 0.96 (cylinder), 0.98 (sphere); the mean of the
            // corners gave 0.68, 0.72, 0.74. (Below one half, 20-22 %, 29-30 % before: junctions whose nearby pieces
            // include one beyond the junction, within the reach of half an element.)
            CHECK(balance[balance.size() / 2] > 0.9);
        }
    }

    TEST_CASE("fem-split: a crack's opening across a periodic border is measured to the other lip's nearest image") {
        // Bark's fissures cross the cylinder's seam and the tile's top and bottom; before the fix the
        // lips of a crack across a border were a tile apart (openings of about 0.25 m).
        const test::Simulated s = simulate("bark", 2000);
        double widest = 0;
        for (const auto& c : s.run.pattern.cracks)
            widest = std::max(widest, c.opening);
        CAPTURE(widest);
        CHECK(widest > 0.0);
        CHECK(widest < 0.02 * s.pieces.tile_size.minCoeff());
    }
}
