#pragma once
/// @file Background growth as a linear velocity field (Federl 2002, §3.3.1; digest §1.3–1.6).
/// Attachment points move on straight lines, P(t) = P(0) + t·v(P(0)) (Eq. 3.4), so growth is
/// linear in time: a rate r = 1 doubles a length at t = 1.

#include "core/math.hpp"
#include "mesh/surface.hpp"

namespace crackle::sim {

enum class GrowthKind { None, Isogonic, Anisotropic };

const char* to_string(GrowthKind kind);

/// Parameters of the [growth] preset section.
struct GrowthOptions {
    GrowthKind kind = GrowthKind::Anisotropic;
    double r1 = 1.0; ///< rate along the direction of maximum growth (1/time)
    double r2 = 0.0; ///< rate perpendicular to it, in the surface (1/time)
    /// Direction of r1 in texture space, degrees from the u axis. (The thesis measures α from
    /// the Y axis: α = 90° − angle_deg.) Cylinder and sphere take 0 (r1 around, r2 along the
    /// axis) or 90 (r1 along the axis).
    double angle_deg = 0.0;
    bool operator==(const GrowthOptions&) const = default; ///< every field: the options test compares whole structs
};

/// v(x) = T·x with a constant growth tensor T = ∂v/∂x (Eq. 3.3). The fixed point is the
/// origin: the plane's domain corner, the trunk axis, the sphere's centre.
class GrowthField {
public:
    GrowthField(const GrowthOptions& options, mesh::SurfaceKind surface);

    /// Velocity at an initial position, written out per field (Eq. 3.4's v, §3.3.1's closed
    /// form for the plane; Eq. 3.5 for the cylinder), not as T·x, so tests can compare the
    /// two.
    Vec3 velocity(const Vec3& x0) const;
    /// Growth tensor T_G (digest §1.4), from its eigen-decomposition.
    const Mat3& tensor() const { return m_tensor; }
    /// Position at time t of the attachment point that started at x0 (Eq. 3.4).
    Vec3 position(const Vec3& x0, double t) const { return x0 + t * velocity(x0); }
    /// The periodic shift at time t of a shift s0 at t = 0: the period grows with the
    /// background, s(t) = (I + tT)·s0.
    Vec3 period_shift(const Vec3& s0, double t) const { return s0 + t * (m_tensor * s0); }
    /// RERG in direction e (Eq. 3.2): eᵀ·T·e, the specific growth rate of a surface segment.
    double rate_along(const Vec3& e) const { return e.dot(m_tensor * e); }

    const GrowthOptions& options() const { return m_options; }

private:
    GrowthOptions m_options;
    mesh::SurfaceKind m_surface;
    double m_rate_u = 0, m_rate_v = 0; // cylinder / sphere: rates around and along the axis
    Mat3 m_tensor = Mat3::Zero();
};

} // namespace crackle::sim
