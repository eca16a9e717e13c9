#pragma once
/// @file Small mass–spring runs for tests.

#include "fracture/mass_spring/mass_spring.hpp"
#include "fracture/statistics.hpp"
#include "support/fem_fixture.hpp"

#include <Eigen/Eigenvalues>

#include <memory>

namespace crackle::test {

struct SpringSpec {
    LayerSpec layer;
    std::size_t masses = 400;
    fracture::MassSpringOptions options;
};

/// Surface, fields and a mass–spring model built from a spec.
struct SpringLayer {
    explicit SpringLayer(const SpringSpec& s)
        : spec(s), surface(make_surface(s.layer.kind, s.layer.size.x(), s.layer.size.y())),
          thickness(s.layer.thickness, sim::VariationOptions{}, surface, s.layer.seed, 1),
          young(s.layer.young, sim::VariationOptions{}, surface, s.layer.seed, 2),
          threshold(s.layer.threshold, sim::VariationOptions{}, surface, s.layer.seed, 3),
          toughness(s.layer.toughness, sim::VariationOptions{}, surface, s.layer.seed, 4) {
        sim::LayerFields fields{&thickness, &young, &threshold, &toughness, s.layer.poisson};
        Rng sampling(s.layer.seed, RngStream::Sampling);
        mesh::SamplingOptions so;
        const mesh::SurfaceMesh lattice =
            fracture::mass_spring_mesh(surface, s.masses, s.options.lattice, so, sampling);
        Rng rng(s.layer.seed, RngStream::Fracture);
        model = std::make_unique<fracture::MassSpringModel>(lattice, surface,
                                                            sim::GrowthField(s.layer.growth, s.layer.kind),
                                                            s.layer.shrinkage, fields, s.options, rng);
    }
    SpringSpec spec;
    mesh::Surface surface;
    sim::PropertyField thickness, young, threshold, toughness;
    std::unique_ptr<fracture::MassSpringModel> model;
};

struct SpringRun {
    fracture::CrackPattern pattern;
    fracture::PatternStatistics stats;
    fracture::RunStats run;
    fracture::MassSpringStats springs;
    std::vector<std::size_t> broken; ///< springs in the order they broke
};

inline SpringRun run_springs(const SpringSpec& spec, double duration = 1.0) {
    SpringLayer layer(spec);
    fracture::FractureOptions o;
    o.duration = duration;
    Rng rng(spec.layer.seed, RngStream::Fracture);
    SpringRun r;
    r.pattern = fracture::run_mass_spring(*layer.model, o, rng, &r.run, &r.springs);
    r.stats = fracture::pattern_statistics(r.pattern);
    return r;
}

} // namespace crackle::test

namespace crackle::test {

/// Crack direction at a scale larger than one segment: at each crack segment, the dominant
/// direction (degrees in [0, 180)) of the crack segments within `radius`, weighted by length.
/// Periodic planes only.
inline std::vector<std::pair<double, double>> coarse_crack_directions(const fracture::CrackPattern& p, double radius) {
    const auto segs = fracture::crack_segments(p);
    const Vec2 L = p.mesh.period;
    std::vector<Vec2> mid;
    for (const auto& s : segs)
        mid.push_back(0.5 * (s.a + s.b));
    std::vector<std::pair<double, double>> out;
    for (std::size_t i = 0; i < segs.size(); ++i) {
        Mat2 M = Mat2::Zero();
        for (std::size_t j = 0; j < segs.size(); ++j) {
            Vec2 d = mid[j] - mid[i];
            d.x() -= L.x() * std::round(d.x() / L.x());
            d.y() -= L.y() * std::round(d.y() / L.y());
            if (d.norm() > radius) continue;
            const Vec2 t = segs[j].b - segs[j].a;
            M += t * t.transpose() / std::max(t.norm(), 1e-300);
        }
        Eigen::SelfAdjointEigenSolver<Mat2> eig(M);
        const Vec2 d = eig.eigenvectors().col(1);
        out.emplace_back(wrap(std::atan2(d.y(), d.x()) * RAD_TO_DEG, 180.0), segs[i].length());
    }
    return out;
}

/// Share of the crack length whose coarse direction lies within `tolerance` degrees of one of
/// `directions` (degrees, mod 180).
inline double share_near(const std::vector<std::pair<double, double>>& dirs, std::initializer_list<double> directions,
                         double tolerance) {
    double near = 0, total = 0;
    for (const auto& [angle, w] : dirs) {
        total += w;
        for (double d : directions) {
            double diff = std::abs(wrap(angle - d, 180.0));
            diff = std::min(diff, 180.0 - diff);
            if (diff <= tolerance) {
                near += w;
                break;
            }
        }
    }
    return total > 0 ? near / total : 0.0;
}

} // namespace crackle::test
