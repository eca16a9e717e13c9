#pragma once
/// @file Measurements for the thesis claims on curved surfaces (tests/unit/claims/
/// test_claims_curved.cpp): crack orientation per latitude band of the sphere, in the local
/// tangent frame, and fissures crossing horizontal lines of the cylinder.

#include "fracture/statistics.hpp"

#include <Eigen/Eigenvalues>

#include <cmath>
#include <vector>

namespace crackle::test {

/// Orientation tensor M = Σ ℓ t tᵀ of crack segments (digest §7.1), accumulated. Segments come
/// from fracture::crack_segments(): on the sphere each is in the tangent frame at its midpoint
/// (x east, y north), so nothing is stretched by the equirectangular texture map; on the
/// cylinder x runs around the trunk and y along it.
struct Orientation {
    Mat2 M = Mat2::Zero();
    double length = 0;     ///< Σ ℓ (m), each lip counting ½
    double along_x = 0;    ///< length within 30° of the x axis (east, or around the trunk)
    std::size_t count = 0; ///< segments (lips)

    void add(const fracture::CrackSegment& s) {
        const double len = s.weight * s.length();
        if (len <= 0) return;
        const Vec2 t = (s.b - s.a).normalized();
        M += len * t * t.transpose();
        length += len;
        if (std::abs(t.x()) > std::cos(30.0 * DEG_TO_RAD)) along_x += len;
        ++count;
    }
    void add(const Orientation& o) {
        M += o.M;
        length += o.length;
        along_x += o.along_x;
        count += o.count;
    }
    /// (λ1 − λ2)/(λ1 + λ2): 0 isotropic, 1 all parallel.
    double anisotropy() const {
        if (length <= 0) return 0;
        const Eigen::SelfAdjointEigenSolver<Mat2> eig(M);
        const double l1 = eig.eigenvalues()[1], l2 = eig.eigenvalues()[0];
        return (l1 + l2) > 0 ? (l1 - l2) / (l1 + l2) : 0.0;
    }
    /// Direction of the dominant crack tangent from x, degrees in [0, 180).
    double dominant_angle_deg() const {
        const Eigen::SelfAdjointEigenSolver<Mat2> eig(M);
        const Vec2 d = eig.eigenvectors().col(1);
        return wrap(std::atan2(d.y(), d.x()) * RAD_TO_DEG, 180.0);
    }
    /// Angle between the dominant direction and the x axis, degrees in [0, 90].
    double dominant_off_x_deg() const {
        const double a = dominant_angle_deg();
        return std::min(a, 180.0 - a);
    }
    double along_x_fraction() const { return length > 0 ? along_x / length : 0.0; }
};

/// Latitude of a sphere segment's midpoint (degrees, −90 south … 90 north), from its texture
/// coordinate v = 1 − colatitude/π (mesh::Surface::uv).
inline double latitude_deg(const fracture::CrackSegment& s) {
    return (s.uv.y() - 0.5) * 180.0;
}

/// Orientation per band of |latitude|: band i holds the segments with
/// edges[i] ≤ |latitude| < edges[i + 1] (degrees), both hemispheres together.
inline std::vector<Orientation> orientation_by_latitude(const fracture::CrackPattern& p,
                                                        const std::vector<double>& edges) {
    std::vector<Orientation> bands(edges.size() - 1);
    for (const fracture::CrackSegment& s : fracture::crack_segments(p)) {
        const double lat = std::abs(latitude_deg(s));
        for (std::size_t i = 0; i + 1 < edges.size(); ++i)
            if (lat >= edges[i] && lat < edges[i + 1]) bands[i].add(s);
    }
    return bands;
}

/// Share of a unit sphere's area between |latitude| a and b (degrees), both hemispheres.
inline double sphere_band_area_fraction(double a_deg, double b_deg) {
    return std::sin(b_deg * DEG_TO_RAD) - std::sin(a_deg * DEG_TO_RAD);
}

/// Number of crack crossings of the horizontal line y = y0 of a periodic surface (domain
/// coordinates: y along v, period H): each lip crossing it counts ½, so a crack through the
/// line counts 1 (a fissure). Segments are unrolled (b − a is the true segment), so the line
/// is moved by whole periods next to each one.
inline double crossings_at(const std::vector<fracture::CrackSegment>& segments, double y0, double H) {
    double n = 0;
    for (const fracture::CrackSegment& s : segments) {
        const double lo = std::min(s.a.y(), s.b.y()), hi = std::max(s.a.y(), s.b.y());
        if (hi - lo <= 0) continue;
        const double y = y0 + H * std::ceil((lo - y0) / H); // the copy of the line at or above lo
        if (y >= lo && y < hi) n += s.weight;
    }
    return n;
}

/// Mean crack crossings over `lines` horizontal lines spread evenly over the period, offset by
/// an irrational share of the spacing so no line runs through a row of vertices by design.
inline double mean_crossings(const fracture::CrackPattern& p, int lines) {
    const std::vector<fracture::CrackSegment> segments = fracture::crack_segments(p);
    const double H = p.mesh.period.y();
    double sum = 0;
    for (int i = 0; i < lines; ++i)
        sum += crossings_at(segments, (i + 0.5 * (std::sqrt(5.0) - 1.0)) * H / lines, H);
    return sum / lines;
}

/// Σ ℓ |t_y| / H: the mean number of crossings of a horizontal line over all heights (Crofton),
/// which mean_crossings() approaches with many lines.
inline double projected_crossings(const fracture::CrackPattern& p) {
    double s = 0;
    for (const fracture::CrackSegment& seg : fracture::crack_segments(p))
        s += seg.weight * std::abs(seg.b.y() - seg.a.y());
    return s / p.mesh.period.y();
}

/// Hoop stress (Pa) at radius R + depth·h in a layer R ≤ r ≤ R + h bonded at r = R to a trunk
/// whose surface moves out by hoop_strain·R, with axial strain axial_strain, and free at
/// r = R + h: Lamé's thick ring in generalized plane strain, u(r) = A·r + B/r, u(R) =
/// hoop_strain·R, σ_rr(R + h) = 0. As h/R → 0 it tends to the thin layer on a plane,
/// E/(1 − ν²)·(hoop_strain + ν·axial_strain).
inline double lame_hoop_stress(double E, double nu, double R, double h, double depth, double hoop_strain,
                               double axial_strain) {
    const double lambda = nu * E / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
    // [R, 1/R; 2(λ+μ), −2μ/(R+h)²]·(A, B) = (ε_θ R, −λ ε_z)
    const double a = R, b = 1 / R, c = 2 * (lambda + mu), d = -2 * mu / sqr(R + h);
    const double r1 = hoop_strain * R, r2 = -lambda * axial_strain;
    const double det = a * d - b * c;
    const double A = (r1 * d - b * r2) / det, B = (a * r2 - c * r1) / det;
    const double r = R + depth * h;
    const double e_r = A - B / sqr(r), e_t = A + B / sqr(r);
    return lambda * (e_r + axial_strain) + (lambda + 2 * mu) * e_t;
}

} // namespace crackle::test
